/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The recognition of input formats by their leading bytes (magic numbers
 * of the format specifications: "#ROSBAG V2.0\n", "\x89MCAP0\r\n",
 * "SQLite format 3\0", "\x93NUMPY", gzip 1f 8b 08, the MATLAB 5 text
 * header) and the dispatch to each decoder, which fills a table
 * (io-table.c).
 */
#include "internal.h"

#include <string.h>

#include "io-formats.h"
#include "io-mat.h"

/* ------------------------------------------------------------ detection */

enum ssc_container ssc_container_detect(const void *buf, size_t len)
{
	const unsigned char *b = buf;

	if (len >= 13 && !memcmp(b, "#ROSBAG V", 9))
		return SSC_C_BAG;
	if (len >= 8 && !memcmp(b, "\x89MCAP", 5))
		return SSC_C_MCAP;
	if (len >= 16 && !memcmp(b, "SQLite format 3", 16))
		return SSC_C_SQLITE;
	if (len >= 6 && !memcmp(b, "\x93NUMPY", 6))
		return SSC_C_NPY;
	if (len >= 3 && b[0] == 0x1f && b[1] == 0x8b && b[2] == 8)
		return SSC_C_GZIP;
	if (ssc_mat_detect(buf, len))
		return SSC_C_MAT;
	return SSC_C_NONE;
}

int ssc_container_open(struct ssc_table **t, enum ssc_container kind,
		       const unsigned char *buf, size_t len, bool mapped,
		       const char *disp, const char *topic,
		       struct sscope_diag *diag)
{
	struct ssc_ros *c;
	const char *fmt = "";
	int rc;

	*t = NULL;
	if (kind == SSC_C_NPY)
		return ssc_npy_open(t, buf, len, disp, diag);
	rc = ssc_ros_new(&c, disp);
	if (rc)
		return rc;
	switch (kind) {
	case SSC_C_BAG:
		fmt = "ROS 1 bag v2.0";
		rc = ssc_bag_read(buf, len, mapped, c, disp, diag);
		break;
	case SSC_C_MCAP:
		fmt = "MCAP";
		rc = ssc_mcap_read(buf, len, mapped, c, disp, diag);
		break;
	case SSC_C_SQLITE:
		fmt = "rosbag2 SQLite (.db3)";
		rc = ssc_db3_read(buf, len, c, disp, diag);
		break;
	default:
		rc = ssc_diag(diag, -EBADMSG, "%s: not a container", disp);
		break;
	}
	if (!rc)
		rc = ssc_ros_finish(c, fmt, topic, t, diag);
	ssc_ros_free(c);
	return rc;
}
