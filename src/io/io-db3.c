/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * rosbag2 SQLite storage (.db3, the rosbag2_storage_default_plugins schema
 * from ROS 2 Dashing to Jazzy): a table topics(id, name, type,
 * serialization_format, ...) and a table messages(id, topic_id, timestamp,
 * data) whose timestamp is the receive time in ns and data the CDR
 * message.  The database is opened from the bytes already in memory
 * (sqlite3_deserialize, read only), so a .db3 on standard input works too.
 * Messages of readable topics are read in receive-time order (rosbag2's
 * own order); the others are only counted.
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-formats.h"

#ifdef HAVE_SQLITE3
#include <sqlite3.h>

static int db_err(sqlite3 *db, const char *disp, struct sscope_diag *diag)
{
	int e = sqlite3_errcode(db);

	if (e == SQLITE_NOMEM)
		return -ENOMEM;
	return ssc_diag(diag, -EBADMSG,
			"%s: rosbag2 SQLite file: %s (not a rosbag2 .db3, or corrupt)",
			disp, sqlite3_errmsg(db));
}

int ssc_db3_read(const unsigned char *buf, size_t len, struct ssc_ros *c,
		 const char *disp, struct sscope_diag *diag)
{
	sqlite3 *db = NULL;
	sqlite3_stmt *st = NULL;
	size_t *map = NULL, nmap = 0;
	int rc = 0, s;

	if (sqlite3_open_v2(":memory:", &db, SQLITE_OPEN_READWRITE, NULL) !=
	    SQLITE_OK) {
		sqlite3_close(db);
		return -ENOMEM;
	}
	/* read only, no copy: SQLite never writes the mapped bytes */
	if (sqlite3_deserialize(db, "main", (unsigned char *)buf,
				(sqlite3_int64)len, (sqlite3_int64)len,
				SQLITE_DESERIALIZE_READONLY) != SQLITE_OK) {
		rc = db_err(db, disp, diag);
		goto out;
	}
	if (sqlite3_prepare_v2(db,
			       "SELECT id, name, type, serialization_format FROM topics",
			       -1, &st, NULL) != SQLITE_OK) {
		rc = db_err(db, disp, diag);
		goto out;
	}
	while ((s = sqlite3_step(st)) == SQLITE_ROW) {
		sqlite3_int64 id = sqlite3_column_int64(st, 0);
		const char *name = (const char *)sqlite3_column_text(st, 1);
		const char *type = (const char *)sqlite3_column_text(st, 2);
		const char *ser = (const char *)sqlite3_column_text(st, 3);
		size_t idx;

		if (id < 0 || id > (1 << 20) || !name || !type) {
			rc = ssc_diag(diag, -EBADMSG, "%s: rosbag2: bad topics table",
				      disp);
			goto out;
		}
		if ((size_t)id >= nmap) {
			size_t nn = (size_t)id + 1;
			size_t *n = realloc(map, nn * sizeof(*n));

			if (!n) {
				rc = -ENOMEM;
				goto out;
			}
			memset(n + nmap, 0, (nn - nmap) * sizeof(*n));
			map = n;
			nmap = nn;
		}
		rc = ssc_ros_topic(c, name, type,
				   ser && !strcmp(ser, "cdr") ? SSC_ENC_CDR :
								SSC_ENC_UNKNOWN,
				   &idx);
		if (rc)
			goto out;
		map[id] = idx + 1;
	}
	if (s != SQLITE_DONE) {
		rc = db_err(db, disp, diag);
		goto out;
	}
	sqlite3_finalize(st);
	st = NULL;
	/* counts of every topic, then the messages of the readable ones */
	if (sqlite3_prepare_v2(db,
			       "SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id",
			       -1, &st, NULL) != SQLITE_OK) {
		rc = db_err(db, disp, diag);
		goto out;
	}
	while ((s = sqlite3_step(st)) == SQLITE_ROW) {
		sqlite3_int64 id = sqlite3_column_int64(st, 0);

		if (id >= 0 && (size_t)id < nmap && map[id] &&
		    !ssc_ros_readable(c, map[id] - 1))
			ssc_ros_count(c, map[id] - 1,
				      (uint64_t)sqlite3_column_int64(st, 1));
	}
	if (s != SQLITE_DONE) {
		rc = db_err(db, disp, diag);
		goto out;
	}
	sqlite3_finalize(st);
	st = NULL;
	/* only the readable topics' blobs are loaded */
	{
		char q[1024];
		size_t ql = (size_t)snprintf(q, sizeof(q),
					     "SELECT topic_id, timestamp, data, id FROM messages WHERE topic_id IN (-1");

		for (size_t i = 0; i < nmap && ql + 32 < sizeof(q); i++)
			if (map[i] && ssc_ros_readable(c, map[i] - 1))
				ql += (size_t)snprintf(q + ql, sizeof(q) - ql,
						       ",%zu", i);
		snprintf(q + ql, sizeof(q) - ql, ") ORDER BY timestamp, id");
		s = sqlite3_prepare_v2(db, q, -1, &st, NULL);
	}
	if (s != SQLITE_OK) {
		rc = db_err(db, disp, diag);
		goto out;
	}
	while ((s = sqlite3_step(st)) == SQLITE_ROW) {
		sqlite3_int64 id = sqlite3_column_int64(st, 0);
		const unsigned char *d;
		int n;

		if (id < 0 || (size_t)id >= nmap || !map[id]) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: rosbag2: message %lld of an unknown topic",
				      disp, (long long)sqlite3_column_int64(st, 3));
			goto out;
		}
		if (!ssc_ros_readable(c, map[id] - 1))
			continue;
		d = sqlite3_column_blob(st, 2);
		n = sqlite3_column_bytes(st, 2);
		rc = ssc_ros_message(c, map[id] - 1, d ? d : (const unsigned char *)"",
				     (size_t)n, sqlite3_column_int64(st, 1),
				     (uint64_t)sqlite3_column_int64(st, 3) | 1ULL << 63,
				     diag);
		if (rc)
			goto out;
	}
	if (s != SQLITE_DONE)
		rc = db_err(db, disp, diag);
out:
	sqlite3_finalize(st);
	sqlite3_close(db);
	free(map);
	return rc;
}

#else

int ssc_db3_read(const unsigned char *buf, size_t len, struct ssc_ros *c,
		 const char *disp, struct sscope_diag *diag)
{
	(void)buf;
	(void)len;
	(void)c;
	(void)disp;
	return ssc_diag(diag, -ENOTSUP,
			"a rosbag2 SQLite (.db3) file, but this sensorscope was built without SQLite (install libsqlite3-dev and configure --with-sqlite3, or convert the bag to MCAP)");
}

#endif
