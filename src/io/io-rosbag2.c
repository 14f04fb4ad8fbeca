/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * rosbag2 bag folders: metadata.yaml (written by rosbag2, key
 * rosbag2_bagfile_information) names the storage ("sqlite3" or "mcap")
 * and the files of a split recording under relative_file_paths; each file
 * is read in that order into one recording.  Only the few keys needed are
 * read, line by line (no general YAML parser).  Whole-file zstd
 * compression (compression_mode FILE) is undone in memory, bounded
 * (io-decomp.c) and checked to be SQLite or MCAP on its first MiB;
 * per-message compression is refused with the fix.
 */
#include "internal.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io-formats.h"

#define MAX_FILES 4096

bool ssc_rosbag2_is_dir(const char *path)
{
	struct stat st;
	char p[4096];

	if (stat(path, &st) || !S_ISDIR(st.st_mode))
		return false;
	snprintf(p, sizeof(p), "%s/metadata.yaml", path);
	return access(p, R_OK) == 0;
}

/* rosbag2 writes a few KiB of metadata (more with many topics) */
#define MAX_METADATA (16u << 20)

/* Open a regular file for reading (never blocking on a FIFO). */
static int open_regular(const char *path, struct stat *st,
			struct sscope_diag *diag)
{
	int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);

	if (fd < 0)
		return ssc_diag(diag, -errno, "%s: %s", path,
				sscope_strerror(-errno));
	if (fstat(fd, st)) {
		int e = -errno;

		close(fd);
		return ssc_diag(diag, e, "%s: %s", path, sscope_strerror(e));
	}
	if (!S_ISREG(st->st_mode)) {
		close(fd);
		return ssc_diag(diag, -EBADMSG,
				"%s: not a regular file (a bag folder holds files)",
				path);
	}
	return fd;
}

/* the whole of metadata.yaml, NUL-terminated */
static int slurp(const char *path, char **out, struct sscope_diag *diag)
{
	struct stat st;
	int fd = open_regular(path, &st, diag);
	char *b;
	size_t n = 0;

	*out = NULL;
	if (fd < 0)
		return fd;
	if (st.st_size > (off_t)MAX_METADATA) {
		close(fd);
		return ssc_diag(diag, -EBADMSG,
				"%s: %lld bytes, more than rosbag2 metadata can be: name the .db3 or .mcap file instead",
				path, (long long)st.st_size);
	}
	b = malloc((size_t)st.st_size + 1);
	if (!b) {
		close(fd);
		return ssc_diag(diag, -ENOMEM, "%s: out of memory", path);
	}
	while (n < (size_t)st.st_size) {
		ssize_t k = read(fd, b + n, (size_t)st.st_size - n);

		if (k < 0 && errno == EINTR)
			continue;
		if (k < 0) {
			int e = -errno;

			free(b);
			close(fd);
			return ssc_diag(diag, e, "%s: %s", path,
					sscope_strerror(e));
		}
		if (k == 0)
			break;
		n += (size_t)k;
	}
	close(fd);
	b[n] = '\0';
	*out = b;
	return 0;
}

/* value of "key: value" on a line (quotes removed), or NULL */
static char *yaml_value(const char *y, const char *key)
{
	size_t kl = strlen(key);

	for (const char *l = y; l && *l; l = strchr(l, '\n'), l = l ? l + 1 : l) {
		const char *p = l, *e;

		while (*p == ' ')
			p++;
		if (strncmp(p, key, kl) || p[kl] != ':')
			continue;
		p += kl + 1;
		while (*p == ' ')
			p++;
		e = p + strcspn(p, "\r\n");
		while (e > p && e[-1] == ' ')
			e--;
		if (e - p >= 2 && (*p == '"' || *p == '\'') && e[-1] == *p) {
			p++;
			e--;
		}
		{
			char *v = malloc((size_t)(e - p) + 1);

			if (v) {
				memcpy(v, p, (size_t)(e - p));
				v[e - p] = '\0';
			}
			return v;
		}
	}
	return NULL;
}

/* the list items under "relative_file_paths:" */
static size_t yaml_files(const char *y, char **out, size_t max)
{
	const char *l = strstr(y, "relative_file_paths:");
	size_t n = 0;

	if (!l)
		return 0;
	l = strchr(l, '\n');
	while (l && n < max) {
		const char *p = l + 1, *e;

		while (*p == ' ')
			p++;
		if (*p != '-')
			break;
		p++;
		while (*p == ' ')
			p++;
		e = p + strcspn(p, "\r\n");
		while (e > p && e[-1] == ' ')
			e--;
		if (e - p >= 2 && (*p == '"' || *p == '\'') && e[-1] == *p) {
			p++;
			e--;
		}
		out[n] = malloc((size_t)(e - p) + 1);
		if (!out[n])
			break;
		memcpy(out[n], p, (size_t)(e - p));
		out[n][e - p] = '\0';
		n++;
		l = strchr(p, '\n');
	}
	return n;
}

/* What a rosbag2 storage file must be after whole-file decompression:
 * SQLite, whose header declares its size (sqlite.org/fileformat.html,
 * 1.3: page size x in-header page count, valid when the version-valid-for
 * number equals the change counter -- always so since SQLite 3.7.0), or
 * MCAP, whose magic is followed by a Header record (mcap.dev/spec): the
 * records that start in the first MiB have known op codes. */
static int storage_check(const unsigned char *h, size_t n, size_t *limit,
			 void *ctx, const char *disp, struct sscope_diag *diag)
{
	size_t cap = *(const size_t *)ctx;

	switch (ssc_container_detect(h, n)) {
	case SSC_C_SQLITE: {
		uint32_t ps, pc;
		unsigned long long sz;

		if (n < 100 || memcmp(h + 24, h + 92, 4))
			return ssc_diag(diag, -EBADMSG,
					"%s: a SQLite file without a valid size in its header once decompressed (not written by rosbag2): decompress it with `zstd -d` and name the .db3 file",
					disp);
		ps = (uint32_t)h[16] << 8 | h[17];
		pc = (uint32_t)h[28] << 24 | (uint32_t)h[29] << 16 |
		     (uint32_t)h[30] << 8 | h[31];
		if (ps == 1)
			ps = 65536;
		sz = (unsigned long long)ps * pc;
		if (sz > cap)
			return ssc_diag(diag, -ENOMEM,
					"%s: holds a SQLite database of %.0f MiB (says its header), more than the %.0f MiB a decompressed file may take here (half the memory this process may use): convert the bag with `ros2 bag convert` to uncompressed storage",
					disp, (double)sz / 1048576.0,
					(double)cap / 1048576.0);
		if (sz > *limit)
			return ssc_diag(diag, -EBADMSG,
					"%s: corrupt zstd data (a SQLite database of %.0f MiB from a smaller file)",
					disp, (double)sz / 1048576.0);
		if (sz)
			*limit = (size_t)sz;
		return 0;
	}
	case SSC_C_MCAP:
		for (size_t p = 8; p + 9 <= n;) {
			uint64_t len = 0;

			for (int i = 8; i >= 1; i--)
				len = len << 8 | h[p + (size_t)i];
			if ((p == 8 && h[p] != 0x01) || h[p] == 0 ||
			    len > cap)
				return ssc_diag(diag, -EBADMSG,
						"%s: not an MCAP file once decompressed (record at byte %zu): check metadata.yaml, or decompress it with `zstd -d` and run `mcap doctor`",
						disp, p);
			if (len > n - p - 9)
				break;
			p += 9 + (size_t)len;
		}
		return 0;
	default:
		return ssc_diag(diag, -EBADMSG,
				"%s: not a SQLite (.db3) or MCAP file once decompressed (compression_mode FILE): check metadata.yaml",
				disp);
	}
}

static int one_file(struct ssc_ros *c, const char *path, bool zstd_file,
		    struct sscope_diag *diag)
{
	struct stat st;
	int fd = open_regular(path, &st, diag), rc;
	void *m;
	unsigned char *z = NULL;
	const unsigned char *b;
	size_t len;

	if (fd < 0)
		return fd;
	if (st.st_size <= 0) {
		close(fd);
		return ssc_diag(diag, -EBADMSG, "%s: empty file", path);
	}
	m = mmap(NULL, (size_t)st.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
	close(fd);
	if (m == MAP_FAILED)
		return ssc_diag(diag, -EIO, "%s: cannot map the file", path);
	b = m;
	len = (size_t)st.st_size;
	if (zstd_file) {
		size_t cap = ssc_expand_cap();

		rc = ssc_unzstd(m, len, cap, storage_check, &cap, &z, &len,
				path, diag);
		if (rc) {
			munmap(m, (size_t)st.st_size);
			return rc;
		}
		b = z;
	}
	switch (ssc_container_detect(b, len)) {
	case SSC_C_SQLITE:
		rc = ssc_db3_read(b, len, c, path, diag);
		break;
	case SSC_C_MCAP:
		rc = ssc_mcap_read(b, len, b == m, c, path, diag);
		break;
	default:
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: not a SQLite (.db3) or MCAP file", path);
	}
	free(z);
	munmap(m, (size_t)st.st_size);
	return rc;
}

int ssc_rosbag2_open(struct ssc_table **t, const char *dir, const char *topic,
		     struct sscope_diag *diag)
{
	char path[4096], *files[MAX_FILES];
	char *y, *storage = NULL, *cfmt = NULL, *cmode = NULL;
	size_t nf = 0;
	struct ssc_ros *c = NULL;
	bool zfile = false;
	char fmt[96];
	int rc = 0;

	*t = NULL;
	snprintf(path, sizeof(path), "%s/metadata.yaml", dir);
	rc = slurp(path, &y, diag);
	if (rc)
		return rc;
	if (!strstr(y, "rosbag2_bagfile_information")) {
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: not rosbag2 metadata (no rosbag2_bagfile_information)",
			      path);
		goto out;
	}
	storage = yaml_value(y, "storage_identifier");
	cfmt = yaml_value(y, "compression_format");
	cmode = yaml_value(y, "compression_mode");
	if (cfmt && *cfmt) {
		if (strcmp(cfmt, "zstd") || !cmode || ssc_strcasecmp(cmode, "file")) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: compression %s, mode %s is not read (only whole-file zstd is): decompress with `ros2 bag convert`",
				      path, cfmt, cmode ? cmode : "?");
			goto out;
		}
		zfile = true;
	}
	nf = yaml_files(y, files, MAX_FILES);
	if (nf == 0) {
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: no relative_file_paths: name the .db3 or .mcap file instead",
			      path);
		goto out;
	}
	rc = ssc_ros_new(&c, dir);
	for (size_t i = 0; i < nf && !rc; i++) {
		if (strstr(files[i], "..") || files[i][0] == '/') {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: file path '%s' leaves the bag folder",
				      path, files[i]);
			break;
		}
		snprintf(path, sizeof(path), "%s/%s", dir, files[i]);
		rc = one_file(c, path, zfile, diag);
	}
	snprintf(fmt, sizeof(fmt), "rosbag2 folder (%s storage%s, %zu file%s)",
		 storage ? storage : "?", zfile ? ", zstd files" : "", nf,
		 nf == 1 ? "" : "s");
	if (!rc)
		rc = ssc_ros_finish(c, fmt, topic, t, diag);
out:
	for (size_t i = 0; i < nf; i++)
		free(files[i]);
	ssc_ros_free(c);
	free(storage);
	free(cfmt);
	free(cmode);
	free(y);
	return rc;
}
