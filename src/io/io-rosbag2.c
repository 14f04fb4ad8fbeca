/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * rosbag2 bag folders: metadata.yaml (written by rosbag2, key
 * rosbag2_bagfile_information) names the storage ("sqlite3" or "mcap")
 * and the files of a split recording under relative_file_paths; each file
 * is read in that order into one recording.  Only the few keys needed are
 * read, line by line (no general YAML parser).  Whole-file zstd
 * compression (compression_mode FILE) is undone in memory; per-message
 * compression is refused with the fix.
 */
#include "internal.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

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

static char *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	char *b = NULL;
	size_t cap = 0, n = 0;

	if (!f)
		return NULL;
	for (;;) {
		if (n + 4096 + 1 > cap) {
			char *nb = realloc(b, cap = cap ? 2 * cap : 65536);

			if (!nb) {
				free(b);
				fclose(f);
				return NULL;
			}
			b = nb;
		}
		size_t k = fread(b + n, 1, cap - n - 1, f);

		n += k;
		if (k == 0)
			break;
	}
	fclose(f);
	b[n] = '\0';
	*len = n;
	return b;
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

/* whole-file zstd: decompress into a new buffer */
static int unzstd(const unsigned char *src, size_t n, unsigned char **out,
		  size_t *out_len)
{
	ZSTD_DStream *z = ZSTD_createDStream();
	ZSTD_inBuffer in = { src, n, 0 };
	unsigned char *b = NULL;
	size_t cap = 0, len = 0, r = 1;

	if (!z)
		return -ENOMEM;
	ZSTD_initDStream(z);
	while (in.pos < in.size || r != 0) {
		ZSTD_outBuffer o;

		if (cap - len < (1u << 20)) {
			unsigned char *nb = realloc(b, cap = cap ? 2 * cap : n * 4 + (1u << 20));

			if (!nb) {
				free(b);
				ZSTD_freeDStream(z);
				return -ENOMEM;
			}
			b = nb;
		}
		o = (ZSTD_outBuffer){ b + len, cap - len, 0 };
		r = ZSTD_decompressStream(z, &o, &in);
		len += o.pos;
		if (ZSTD_isError(r) || (in.pos == in.size && r != 0 && o.pos == 0)) {
			free(b);
			ZSTD_freeDStream(z);
			return -EBADMSG;
		}
	}
	ZSTD_freeDStream(z);
	*out = b;
	*out_len = len;
	return 0;
}

static int one_file(struct ssc_ros *c, const char *path, bool zstd_file,
		    struct sscope_diag *diag)
{
	int fd = open(path, O_RDONLY | O_CLOEXEC), rc;
	struct stat st;
	void *m;
	unsigned char *z = NULL;
	const unsigned char *b;
	size_t len;

	if (fd < 0)
		return ssc_diag(diag, -errno, "%s: %s", path,
				sscope_strerror(-errno));
	if (fstat(fd, &st) || st.st_size <= 0) {
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
		rc = unzstd(m, len, &z, &len);
		if (rc) {
			munmap(m, (size_t)st.st_size);
			return ssc_diag(diag, rc, "%s: corrupt zstd data", path);
		}
		b = z;
	}
	switch (ssc_container_detect(b, len)) {
	case SSC_C_SQLITE:
		rc = ssc_db3_read(b, len, c, path, diag);
		break;
	case SSC_C_MCAP:
		rc = ssc_mcap_read(b, len, c, path, diag);
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
	size_t yl, nf = 0;
	struct ssc_ros *c = NULL;
	bool zfile = false;
	char fmt[96];
	int rc = 0;

	*t = NULL;
	snprintf(path, sizeof(path), "%s/metadata.yaml", dir);
	y = slurp(path, &yl);
	if (!y)
		return ssc_diag(diag, -errno ? -errno : -ENOMEM, "%s: %s", path,
				sscope_strerror(-errno));
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
