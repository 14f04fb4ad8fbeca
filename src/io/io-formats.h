/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Input formats beyond delimited text (internal): a decoded "table" that
 * the capture reader serves like any other source, and the decoders that
 * fill it -- ROS 1 bags (io-bag.c), MCAP (io-mcap.c), rosbag2 SQLite files
 * and bag folders (io-db3.c, io-rosbag2.c), NumPy .npy (io-npy.c) -- plus
 * the stream filters gzip (io-gzip.c) and MATLAB v7 compression
 * (io-matz.c), the chunk decompressors (io-decomp.c) and the header of
 * `rostopic echo -p` CSV files (io-rostopic.c).
 *
 * Every decoder reads a caller's buffer with bounds checked before each
 * access: a truncated or corrupt file is -EBADMSG with a message naming
 * the format, the byte offset and the fix, never a read past the end.
 */
#ifndef SSCOPE_IO_FORMATS_H
#define SSCOPE_IO_FORMATS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

struct sscope_diag;
struct sscope_capture_source;

/* ------------------------------------------------------------ table */

/* storage type of a table column */
enum ssc_vtype {
	SSC_V_F64 = 0, SSC_V_F32, SSC_V_I8, SSC_V_U8, SSC_V_I16, SSC_V_U16,
	SSC_V_I32, SSC_V_U32, SSC_V_I64, SSC_V_U64
};

struct ssc_tcol {
	char *label;               /* "gx [rad/s]" (owned) */
	int role;                  /* enum sscope_capture_role */
	const unsigned char *data; /* value of row 0 */
	size_t stride;             /* bytes between rows */
	enum ssc_vtype type;
	bool swap;                 /* stored in the other byte order */
};

/* A decoded capture: columns that are strided views into buffers the
 * table owns (or the caller's buffer, which must outlive the table). */
struct ssc_table {
	size_t ncols, nrows;
	struct ssc_tcol *cols;
	void **owned;
	size_t n_owned;
	/* receive times of the rows, ns (owned), or NULL */
	int64_t *rx_ns;
	/* format, topics (owned; receive_s stays NULL here) */
	struct sscope_capture_source *src;
};

struct ssc_table *ssc_table_new(const char *format);
/* take ownership of p (freed with the table; freed now on failure) */
int ssc_table_own(struct ssc_table *t, void *p);
int ssc_table_add(struct ssc_table *t, const char *label, int role,
		  const void *data, size_t stride, enum ssc_vtype type,
		  bool swap);
double ssc_table_value(const struct ssc_tcol *c, size_t row);
/* exact integer value of an I64 column (time stamps in ns) */
int64_t ssc_table_i64(const struct ssc_tcol *c, size_t row);
void ssc_table_free(struct ssc_table *t);
/* a deep copy of the source description with receive_s filled from the
 * table's receive times of rows [0, n) relative to stamp t0_ns */
struct sscope_capture_source *ssc_source_copy(const struct sscope_capture_source *s,
					      const int64_t *rx_ns, size_t n,
					      int64_t t0_ns);
void ssc_source_free(struct sscope_capture_source *s);
/* a source description holding only a format name */
struct sscope_capture_source *ssc_source_new(const char *format);

/* ------------------------------------------------------------ detection */

enum ssc_container {
	SSC_C_NONE = 0, SSC_C_BAG, SSC_C_MCAP, SSC_C_SQLITE, SSC_C_NPY,
	SSC_C_GZIP, SSC_C_MAT
};

/* Recognise a format by its leading bytes. */
enum ssc_container ssc_container_detect(const void *buf, size_t len);

/* Decode a whole container held in buf (bag, MCAP, SQLite, npy) into a
 * table; topic as sscope_reader_opts.topic. */
int ssc_container_open(struct ssc_table **t, enum ssc_container kind,
		       const unsigned char *buf, size_t len, bool mapped,
		       const char *disp, const char *topic,
		       struct sscope_diag *diag);

/* A rosbag2 folder (metadata.yaml and its .db3 or .mcap files). */
bool ssc_rosbag2_is_dir(const char *path);
int ssc_rosbag2_open(struct ssc_table **t, const char *dir, const char *topic,
		     struct sscope_diag *diag);

/* ------------------------------------------------------------ ROS messages */

enum ssc_ros_enc { SSC_ENC_UNKNOWN = 0, SSC_ENC_ROS1, SSC_ENC_CDR };

/* Collects the messages of every topic of one recording (several files
 * for a split rosbag2), decoding those of readable types. */
struct ssc_ros;

int ssc_ros_new(struct ssc_ros **c, const char *disp);
/* Register a topic (idempotent by name); *idx receives its number. */
int ssc_ros_topic(struct ssc_ros *c, const char *name, const char *type,
		  enum ssc_ros_enc enc, size_t *idx);
/* One message of topic idx received at rx_ns.  `where` (a byte offset,
 * or a row number with bit 63 set) goes into messages about a malformed
 * message. */
int ssc_ros_message(struct ssc_ros *c, size_t idx, const unsigned char *data,
		    size_t len, int64_t rx_ns, uint64_t where,
		    struct sscope_diag *diag);
/* Add n messages to a topic without decoding (counts of other types). */
void ssc_ros_count(struct ssc_ros *c, size_t idx, uint64_t n);
/* Is topic idx of a type that is decoded? */
bool ssc_ros_readable(const struct ssc_ros *c, size_t idx);
/* Note a format detail ("lz4 chunks") for the format name. */
void ssc_ros_note(struct ssc_ros *c, const char *detail);
/* Select the topics and build the table. */
int ssc_ros_finish(struct ssc_ros *c, const char *format, const char *topic,
		   struct ssc_table **t, struct sscope_diag *diag);
void ssc_ros_free(struct ssc_ros *c);

/* Container walkers: feed every topic and message to the collector.
 * mapped: buf is a read-only file mapping whose pages the walker gives
 * back behind it (memory bounded by the chunks in flight, whatever the
 * file's size); false for memory the caller owns. */
int ssc_bag_read(const unsigned char *buf, size_t len, bool mapped,
		 struct ssc_ros *c, const char *disp, struct sscope_diag *diag);
int ssc_mcap_read(const unsigned char *buf, size_t len, bool mapped,
		  struct ssc_ros *c, const char *disp, struct sscope_diag *diag);
/* -ENOTSUP when built without SQLite */
int ssc_db3_read(const unsigned char *buf, size_t len, struct ssc_ros *c,
		 const char *disp, struct sscope_diag *diag);

/* ------------------------------------------------------------ npy */

int ssc_npy_open(struct ssc_table **t, const unsigned char *buf, size_t len,
		 const char *disp, struct sscope_diag *diag);

/* ------------------------------------------------------------ lazy libraries */

/* A library opened on first use (io-lazy.c): its run-time name, the
 * functions wanted (NULL-terminated) and the slots that receive them. */
struct ssc_lazylib {
	const char *soname;
	const char *package; /* Debian's package that installs it */
	const char *const *names;
	void (**fn)(void);
	int state; /* 0 not tried, 1 loaded, < 0 failed */
	char why[200];
};
/* 0 once every function is found; else -ENOSYS with diag "WHAT: cannot
 * load SONAME (why): install PACKAGE".  Thread-safe; tries once per process. */
int ssc_lazylib_load(struct ssc_lazylib *l, struct sscope_diag *diag,
		     const char *what);
/* A table of the functions FUNCS(X) lists, typed as their declarations:
 * SSC_LAZY_TABLE(z, ZSTD_FUNCS); then z.ZSTD_decompress(...) */
#define SSC_LAZY_SLOT(f) __typeof__(f) *f;
#define SSC_LAZY_NAME(f) #f,
#define SSC_LAZY_ONE(f) +1
#define SSC_LAZY_TABLE(var, FUNCS)                                             \
	static union {                                                         \
		struct {                                                       \
			FUNCS(SSC_LAZY_SLOT)                                   \
		};                                                             \
		void (*slot[0 FUNCS(SSC_LAZY_ONE)])(void);                     \
	} var
#define SSC_LAZY_LIB(var, soname, package, table, FUNCS)                       \
	static const char *const var##_names[] = { FUNCS(SSC_LAZY_NAME) NULL }; \
	static struct ssc_lazylib var = { soname, package, var##_names,          \
					  table.slot, 0, "" }

/* ------------------------------------------------------------ codecs */

enum ssc_codec { SSC_CODEC_BZ2, SSC_CODEC_LZ4, SSC_CODEC_ZSTD };

/* Decompress src into exactly dst_len bytes of dst. */
int ssc_decompress(enum ssc_codec codec, const unsigned char *src,
		   size_t src_len, unsigned char *dst, size_t dst_len,
		   const char *disp, const char *what,
		   struct sscope_diag *diag);
/* The most bytes src_len compressed bytes of codec can decode to (LZ4:
 * 255 per byte; Zstandard: a 128 KiB block from 4 bytes; bzip2: no
 * bound), so that a corrupt size field is refused before it is allocated. */
size_t ssc_decompress_bound(enum ssc_codec codec, size_t src_len);

/* Chunks decompressed together on the OpenMP threads, each into its own
 * buffer (kept for the next batch), then walked in file order by the
 * caller: a container's chunks decode on every core while its records
 * keep their order.  Add chunks until full (n == SSC_CHUNK_BATCH) or a
 * record that must follow them, then run. */
#define SSC_CHUNK_BATCH 8
struct ssc_chunk_batch {
	size_t n;
	struct ssc_chunk_job {
		enum ssc_codec codec;
		const unsigned char *src;
		size_t src_len, size;
		uint64_t at;          /* the chunk's byte offset */
	} job[SSC_CHUNK_BATCH];
	unsigned char *buf[SSC_CHUNK_BATCH];
	size_t cap[SSC_CHUNK_BATCH];
};
/* Decompress the batch's chunks into buf[i] (size bytes each); on error
 * the first failing chunk's in file order, its message naming disp and
 * the chunk's offset, and n lowered to the chunks before it (which the
 * caller walks first: an error in them comes first, as in a walk one
 * chunk at a time). */
int ssc_chunk_batch_run(struct ssc_chunk_batch *b, const char *kind,
			const char *disp, struct sscope_diag *diag);
void ssc_chunk_batch_free(struct ssc_chunk_batch *b);
/* Give back the pages of a read-only file mapping base[0, upto) that a
 * walker has passed (*dropped: how far it has, page-aligned); a no-op
 * for less than 4 MiB more. */
void ssc_map_drop_behind(const unsigned char *base, size_t upto,
			 size_t *dropped);
/* The most bytes one compressed input may expand to in memory: half the
 * physical memory, or half the address-space or data-size limit
 * (ulimit -v, -d) when lower. */
size_t ssc_expand_cap(void);
/* Called once on the first MiB of an expansion (all of it when shorter):
 * 0 when it is what the format needs, possibly lowering *limit to the
 * size it declares; else a negative errno with diag set. */
typedef int (*ssc_expand_check_fn)(const unsigned char *head, size_t n,
				   size_t *limit, void *ctx, const char *disp,
				   struct sscope_diag *diag);
/* Expand Zstandard frames (a whole file) into *out (malloc'd, *out_len
 * bytes), at most cap bytes and what the codec can make of n bytes;
 * check (may be NULL) judges the first MiB.  -ENOMEM (out of memory, or
 * more than cap), -EBADMSG corrupt, truncated or more than declared; diag
 * names disp and the fix. */
int ssc_unzstd(const unsigned char *src, size_t n, size_t cap,
	       ssc_expand_check_fn check, void *ctx, unsigned char **out,
	       size_t *out_len, const char *disp, struct sscope_diag *diag);
/* CRC-32 (zlib's) of a buffer of any size. */
uint32_t ssc_crc32(const unsigned char *p, size_t n);

/* Streaming gzip (several members allowed): the compressed bytes come
 * first from `pre` (npre bytes: a mapped file or what was already read
 * from a pipe), then from fd (-1: none).  `map`/`map_len`, when not NULL,
 * is unmapped by ssc_gz_close(); without it `pre` is copied. */
struct ssc_gz;
int ssc_gz_open(struct ssc_gz **g, const unsigned char *pre, size_t npre,
		int fd, void *map, size_t map_len);
/* Up to n decompressed bytes; 0 at the end; -EBADMSG corrupt/truncated
 * (diag says which), -EIO. */
ssize_t ssc_gz_read(struct ssc_gz *g, void *buf, size_t n, const char *disp,
		    struct sscope_diag *diag);
void ssc_gz_close(struct ssc_gz *g);

/* MATLAB v7: a copy of the MAT-file with every compressed element
 * (miCOMPRESSED, zlib) replaced by the element it holds; *out is NULL
 * (and 0 returned) when nothing is compressed. */
int ssc_matz_expand(const unsigned char *buf, size_t len, unsigned char **out,
		    size_t *out_len, const char *disp,
		    struct sscope_diag *diag);

/* The reader's container details for a capture of `rows` rows (a copy
 * with the receive times), or NULL for plain files (reader.c). */
struct sscope_reader;
struct sscope_capture_source *ssc_reader_take_source(struct sscope_reader *r,
						     size_t rows);

/* ------------------------------------------------------------ rostopic */

/* Is this header cell the first of a `rostopic echo -p` CSV ("%time")? */
bool ssc_rostopic_detect(const char *first_name);
/* For a column of such a file: its name and unit in sensorscope terms
 * (static strings, or NULL to keep the original), and whether it stays
 * out of the default selection (seq, frame_id, covariances, ...). */
void ssc_rostopic_column(const char *name, bool has_stamp,
			 const char **new_name, const char **unit,
			 bool *hidden);

#endif
