/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * ROS messages of IMU recordings, whatever the container: the topics of a
 * recording, the decoding of sensor_msgs/Imu, sensor_msgs/Temperature and
 * geometry_msgs/Vector3Stamped in both serialisations, the choice of
 * topics and the table the capture reader serves.
 *
 * Serialisations (from the ROS wiki "ROS/Technical Overview:
 * serialization" and the OMG CDR rules used by ROS 2):
 * - ROS 1: little-endian, packed.  Header = uint32 seq, time stamp
 *   (uint32 sec, uint32 nsec), string frame_id (uint32 length + bytes).
 * - ROS 2 (CDR): a 4-byte encapsulation header (00 01: little endian,
 *   00 00: big endian), then each primitive aligned to its size from the
 *   end of that header.  Header = int32 sec, uint32 nanosec, string
 *   frame_id (uint32 length counting the NUL + bytes).
 * After the header: Imu = orientation (4 float64), its covariance (9),
 * angular_velocity (3), covariance (9), linear_acceleration (3),
 * covariance (9); Temperature = temperature, variance (float64);
 * Vector3Stamped = vector (3 float64).  Covariances are ignored.
 *
 * Channels: gx gy gz [rad/s], ax ay az [m/s^2] for Imu; x y z (no unit)
 * for Vector3Stamped; temperature [degC] for a Temperature topic read
 * alone.  The header stamps are the time column (exact nanoseconds); the
 * container's receive times are kept for `info`.  A Temperature topic
 * beside the data topic becomes the temperature column, interpolated
 * linearly at the data stamps (held at the ends).
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-formats.h"
#include "sscope-capture.h"

enum kind { T_OTHER = 0, T_IMU, T_TEMP, T_VEC3 };

static const size_t kind_ncomp[] = { 0, 6, 1, 3 };

struct topic {
	char *name, *type;
	enum kind kind;
	enum ssc_ros_enc enc;
	uint64_t count;
	size_t n, cap;    /* decoded messages */
	int64_t *stamp, *rx;
	double *v[6];
	bool selected;
};

struct ssc_ros {
	const char *disp;
	struct topic *t;
	size_t n, cap;
	char notes[128];
};

int ssc_ros_new(struct ssc_ros **c, const char *disp)
{
	*c = calloc(1, sizeof(**c));
	if (!*c)
		return -ENOMEM;
	(*c)->disp = disp;
	return 0;
}

static void topic_free(struct topic *t)
{
	free(t->name);
	free(t->type);
	free(t->stamp);
	free(t->rx);
	for (int k = 0; k < 6; k++)
		free(t->v[k]);
}

void ssc_ros_free(struct ssc_ros *c)
{
	if (!c)
		return;
	for (size_t i = 0; i < c->n; i++)
		topic_free(&c->t[i]);
	free(c->t);
	free(c);
}

void ssc_ros_note(struct ssc_ros *c, const char *detail)
{
	size_t l = strlen(c->notes);

	if (strstr(c->notes, detail))
		return;
	snprintf(c->notes + l, sizeof(c->notes) - l, "%s%s", l ? ", " : "",
		 detail);
}

static enum kind type_kind(const char *type)
{
	static const struct {
		const char *pkg, *msg;
		enum kind k;
	} known[] = { { "sensor_msgs", "Imu", T_IMU },
		      { "sensor_msgs", "Temperature", T_TEMP },
		      { "geometry_msgs", "Vector3Stamped", T_VEC3 } };

	for (size_t i = 0; i < sizeof(known) / sizeof(known[0]); i++) {
		size_t pl = strlen(known[i].pkg);
		const char *m = type + pl + 1;

		if (strncmp(type, known[i].pkg, pl) || type[pl] != '/')
			continue;
		if (!strncmp(m, "msg/", 4)) /* ROS 2 */
			m += 4;
		if (!strcmp(m, known[i].msg))
			return known[i].k;
	}
	return T_OTHER;
}

int ssc_ros_topic(struct ssc_ros *c, const char *name, const char *type,
		  enum ssc_ros_enc enc, size_t *idx)
{
	struct topic *t;

	for (size_t i = 0; i < c->n; i++)
		if (!strcmp(c->t[i].name, name)) {
			*idx = i;
			return 0;
		}
	if (c->n == c->cap) {
		size_t nc = c->cap ? 2 * c->cap : 8;
		struct topic *n = realloc(c->t, nc * sizeof(*n));

		if (!n)
			return -ENOMEM;
		c->t = n;
		c->cap = nc;
	}
	t = &c->t[c->n];
	memset(t, 0, sizeof(*t));
	t->name = ssc_strdup(name);
	t->type = ssc_strdup(type ? type : "");
	if (!t->name || !t->type) {
		topic_free(t);
		return -ENOMEM;
	}
	t->enc = enc;
	t->kind = enc == SSC_ENC_UNKNOWN ? T_OTHER : type_kind(t->type);
	*idx = c->n++;
	return 0;
}

bool ssc_ros_readable(const struct ssc_ros *c, size_t idx)
{
	return idx < c->n && c->t[idx].kind != T_OTHER;
}

void ssc_ros_count(struct ssc_ros *c, size_t idx, uint64_t n)
{
	if (idx < c->n)
		c->t[idx].count += n;
}

static int grow(struct topic *t)
{
	size_t nc = t->cap ? 2 * t->cap : 4096;
	void *p;

	if (nc > SIZE_MAX / sizeof(double))
		return -ENOMEM;
	p = realloc(t->stamp, nc * sizeof(int64_t));
	if (!p)
		return -ENOMEM;
	t->stamp = p;
	p = realloc(t->rx, nc * sizeof(int64_t));
	if (!p)
		return -ENOMEM;
	t->rx = p;
	for (size_t k = 0; k < kind_ncomp[t->kind]; k++) {
		p = realloc(t->v[k], nc * sizeof(double));
		if (!p)
			return -ENOMEM;
		t->v[k] = p;
	}
	t->cap = nc;
	return 0;
}

static uint32_t get32(const unsigned char *p, bool be)
{
	return be ? (uint32_t)p[3] | (uint32_t)p[2] << 8 |
			    (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24 :
		    (uint32_t)p[0] | (uint32_t)p[1] << 8 |
			    (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static double getf64(const unsigned char *p, bool be)
{
	unsigned char b[8];
	double v;

	for (int i = 0; i < 8; i++)
		b[i] = p[be ? 7 - i : i];
	memcpy(&v, b, 8);
	return v;
}

int ssc_ros_message(struct ssc_ros *c, size_t idx, const unsigned char *d,
		    size_t len, int64_t rx_ns, uint64_t where,
		    struct sscope_diag *diag)
{
	struct topic *t;
	size_t p, need, ncomp, first;
	bool be = false;
	int64_t stamp;
	int rc;

	if (idx >= c->n)
		return 0;
	t = &c->t[idx];
	t->count++;
	if (t->kind == T_OTHER)
		return 0;
	ncomp = kind_ncomp[t->kind];
	if (t->enc == SSC_ENC_ROS1) {
		uint32_t fl;

		if (len < 16)
			goto short_msg;
		stamp = (int64_t)get32(d + 4, false) * 1000000000 +
			get32(d + 8, false);
		fl = get32(d + 12, false);
		if (fl > len - 16)
			goto short_msg;
		p = 16 + fl;
	} else {
		uint32_t fl;
		const unsigned char *o = d + 4;

		if (len < 4 || d[0] != 0 || d[1] > 1)
			return ssc_diag(diag, -EBADMSG,
					"%s: topic %s, message %s %llu: CDR encapsulation %02x %02x is not plain CDR",
					c->disp, t->name,
					where >> 63 ? "row" : "at byte",
					(unsigned long long)(where & ~(1ULL << 63)),
					len ? d[0] : 0,
					len > 1 ? d[1] : 0);
		be = d[1] == 0;
		len -= 4;
		d = o;
		if (len < 12)
			goto short_msg;
		stamp = (int64_t)(int32_t)get32(d, be) * 1000000000 +
			get32(d + 4, be);
		fl = get32(d + 8, be);
		if (fl > len - 12)
			goto short_msg;
		p = (12 + (size_t)fl + 7) & ~(size_t)7;
	}
	/* offset of the first wanted float64 and bytes needed after p */
	first = t->kind == T_IMU ? 104 : 0;
	need = t->kind == T_IMU ? 296 : t->kind == T_TEMP ? 16 : 24;
	if (p > len || len - p < need)
		goto short_msg;
	if (t->n == t->cap) {
		rc = grow(t);
		if (rc)
			return rc;
	}
	t->stamp[t->n] = stamp;
	t->rx[t->n] = rx_ns;
	for (size_t k = 0; k < ncomp; k++) {
		/* Imu: angular velocity at 104, acceleration at 200 */
		size_t off = first + 8 * k + (t->kind == T_IMU && k >= 3 ? 72 : 0);

		t->v[k][t->n] = getf64(d + p + off, be);
	}
	t->n++;
	return 0;
short_msg:
	return ssc_diag(diag, -EBADMSG,
			"%s: topic %s (%s), message %s %llu: %zu bytes are too few for the type (truncated or corrupt)",
			c->disp, t->name, t->type,
			where >> 63 ? "row" : "at byte",
			(unsigned long long)(where & ~(1ULL << 63)), len);
}

/* ------------------------------------------------------------ selection */

static void list_topics(const struct ssc_ros *c, bool readable_only,
			char *buf, size_t len)
{
	size_t used = 0;

	buf[0] = '\0';
	for (size_t i = 0; i < c->n && used + 8 < len; i++) {
		int w;

		if (readable_only && c->t[i].kind == T_OTHER)
			continue;
		w = snprintf(buf + used, len - used, "%s%s (%s, %llu)",
			     used ? ", " : "", c->t[i].name, c->t[i].type,
			     (unsigned long long)c->t[i].count);
		if (w < 0 || (size_t)w >= len - used)
			break;
		used += (size_t)w;
	}
	if (!buf[0])
		snprintf(buf, len, "none");
}

static long find_topic(const struct ssc_ros *c, const char *name, size_t n)
{
	for (size_t i = 0; i < c->n; i++)
		if (strlen(c->t[i].name) == n && !strncmp(c->t[i].name, name, n))
			return (long)i;
	/* "imu/data" for "/imu/data" */
	for (size_t i = 0; i < c->n; i++)
		if (c->t[i].name[0] == '/' && strlen(c->t[i].name) == n + 1 &&
		    !strncmp(c->t[i].name + 1, name, n))
			return (long)i;
	return -1;
}

static int choose(struct ssc_ros *c, const char *sel, long *data, long *temp,
		  struct sscope_diag *diag)
{
	char names[240];
	size_t n_imu = 0, n_vec = 0, n_temp = 0;
	long imu = -1, vec = -1, tmp = -1;

	*data = *temp = -1;
	if (sel && *sel) {
		const char *p = sel;

		while (*p) {
			size_t l = strcspn(p, ",");
			long i = find_topic(c, p, l);

			if (i < 0 || c->t[i].kind == T_OTHER) {
				list_topics(c, true, names, sizeof(names));
				return ssc_diag(diag, -EINVAL,
						i < 0 ? "%s: no topic '%.*s' (readable topics: %s)" :
							"%s: topic '%.*s' is not of a type sensorscope reads (sensor_msgs/Imu, sensor_msgs/Temperature, geometry_msgs/Vector3Stamped; readable topics: %s)",
						c->disp, (int)l, p, names);
			}
			if (c->t[i].kind == T_TEMP && *temp < 0 &&
			    (*data >= 0 || p[l] == ','))
				*temp = i;
			else if (*data < 0)
				*data = i;
			else
				return ssc_diag(diag, -EINVAL,
						"%s: --topic names two data topics (%s, %.*s): one at a time, plus a temperature topic",
						c->disp, c->t[*data].name, (int)l, p);
			p += l;
			if (*p == ',')
				p++;
		}
		if (*data < 0) {
			*data = *temp;
			*temp = -1;
		}
	} else {
		for (size_t i = 0; i < c->n; i++) {
			if (c->t[i].kind == T_IMU && !n_imu++)
				imu = (long)i;
			if (c->t[i].kind == T_VEC3 && !n_vec++)
				vec = (long)i;
			if (c->t[i].kind == T_TEMP && !n_temp++)
				tmp = (long)i;
		}
		if (n_imu > 1 || (n_imu == 0 && n_vec > 1)) {
			list_topics(c, true, names, sizeof(names));
			return ssc_diag(diag, -EINVAL,
					"%s: %zu %s topics: choose one with --topic NAME (readable topics: %s)",
					c->disp, n_imu ? n_imu : n_vec,
					n_imu ? "IMU" : "Vector3Stamped", names);
		}
		*data = imu >= 0 ? imu : vec >= 0 ? vec : n_temp == 1 ? tmp : -1;
		if (*data < 0) {
			list_topics(c, false, names, sizeof(names));
			return ssc_diag(diag, -EDOM,
					"%s: no IMU topic (sensor_msgs/Imu, Temperature or geometry_msgs/Vector3Stamped; topics: %s)",
					c->disp, names);
		}
	}
	/* the only temperature topic goes with an IMU topic */
	if (*temp < 0 && c->t[*data].kind == T_IMU && !(sel && *sel)) {
		n_temp = 0;
		for (size_t i = 0; i < c->n; i++)
			if (c->t[i].kind == T_TEMP && !n_temp++)
				tmp = (long)i;
		if (n_temp == 1)
			*temp = tmp;
	}
	if (c->t[*data].n == 0)
		return ssc_diag(diag, -EDOM, "%s: topic %s holds no message",
				c->disp, c->t[*data].name);
	return 0;
}

static int cmp_i64(const void *a, const void *b)
{
	int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;

	return (x > y) - (x < y);
}

/* temperature of topic tt at the stamps of td (linear, held at the ends) */
static double *interp_temp(const struct topic *td, const struct topic *tt)
{
	double *out = ssc_alloc_array(td->n, sizeof(double));
	int64_t *pairs = ssc_alloc_array(tt->n, 2 * sizeof(int64_t));
	size_t j = 0;

	if (!out || !pairs || tt->n == 0) {
		free(out);
		free(pairs);
		return NULL;
	}
	/* sort (stamp, value bits) pairs by stamp */
	for (size_t i = 0; i < tt->n; i++) {
		pairs[2 * i] = tt->stamp[i];
		memcpy(&pairs[2 * i + 1], &tt->v[0][i], 8);
	}
	qsort(pairs, tt->n, 2 * sizeof(int64_t), cmp_i64);
	for (size_t i = 0; i < td->n; i++) {
		int64_t s = td->stamp[i];
		double v0, v1;

		while (j + 1 < tt->n && pairs[2 * (j + 1)] <= s)
			j++;
		memcpy(&v0, &pairs[2 * j + 1], 8);
		if (s <= pairs[0] || j + 1 >= tt->n) {
			out[i] = s <= pairs[0] ? (memcpy(&v1, &pairs[1], 8), v1) : v0;
			continue;
		}
		memcpy(&v1, &pairs[2 * j + 3], 8);
		out[i] = v0 + (v1 - v0) * (double)(s - pairs[2 * j]) /
				      (double)(pairs[2 * j + 2] - pairs[2 * j]);
	}
	free(pairs);
	return out;
}

int ssc_ros_finish(struct ssc_ros *c, const char *format, const char *topic,
		   struct ssc_table **out, struct sscope_diag *diag)
{
	static const char *const imu_lab[] = { "gx [rad/s]", "gy [rad/s]",
					       "gz [rad/s]", "ax [m/s^2]",
					       "ay [m/s^2]", "az [m/s^2]" };
	static const char *const vec_lab[] = { "x", "y", "z" };
	struct ssc_table *t;
	struct topic *td;
	struct sscope_capture_topic *tp;
	char fmt[200];
	double *tv = NULL;
	long di, ti;
	int rc;

	*out = NULL;
	rc = choose(c, topic, &di, &ti, diag);
	if (rc)
		return rc;
	td = &c->t[di];
	td->selected = true;
	if (ti >= 0)
		c->t[ti].selected = true;
	snprintf(fmt, sizeof(fmt), "%s%s%s%s", format, c->notes[0] ? " (" : "",
		 c->notes, c->notes[0] ? ")" : "");
	t = ssc_table_new(fmt);
	if (!t)
		return -ENOMEM;
	tp = calloc(c->n, sizeof(*tp));
	if (!tp) {
		ssc_table_free(t);
		return -ENOMEM;
	}
	t->src->topics = tp;
	for (size_t i = 0; i < c->n; i++) {
		/* names move to the table's description */
		tp[i].name = c->t[i].name;
		tp[i].type = c->t[i].type;
		c->t[i].name = NULL;
		c->t[i].type = NULL;
		tp[i].messages = c->t[i].count;
		tp[i].readable = c->t[i].kind != T_OTHER;
		tp[i].selected = c->t[i].selected;
		t->src->n_topics = i + 1;
	}
	t->nrows = td->n;
	if (ti >= 0) {
		tv = interp_temp(td, &c->t[ti]);
		if (!tv) {
			ssc_table_free(t);
			return -ENOMEM;
		}
	}
	rc = ssc_table_own(t, td->stamp);
	if (!rc)
		rc = ssc_table_add(t, "time [ns]", SSCOPE_CAPTURE_ROLE_TIME, td->stamp,
				   sizeof(int64_t), SSC_V_I64, false);
	td->stamp = NULL;
	t->rx_ns = td->rx;
	td->rx = NULL;
	for (size_t k = 0; k < kind_ncomp[td->kind] && !rc; k++) {
		const char *lab = td->kind == T_IMU ? imu_lab[k] :
				  td->kind == T_VEC3 ? vec_lab[k] :
						       "temperature [degC]";

		rc = ssc_table_own(t, td->v[k]);
		if (!rc)
			rc = ssc_table_add(t, lab, SSCOPE_CAPTURE_ROLE_DATA, td->v[k],
					   sizeof(double), SSC_V_F64, false);
		td->v[k] = NULL;
	}
	if (tv) {
		if (!rc)
			rc = ssc_table_own(t, tv);
		else
			free(tv);
		if (!rc)
			rc = ssc_table_add(t, "temp [degC]", SSCOPE_CAPTURE_ROLE_TEMP, tv,
					   sizeof(double), SSC_V_F64, false);
	}
	if (rc) {
		ssc_table_free(t);
		return rc;
	}
	*out = t;
	return 0;
}
