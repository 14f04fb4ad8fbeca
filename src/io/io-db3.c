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
 *
 * The file brings its own schema, so it is opened as SQLite advises for
 * untrusted databases ("Defense Against The Dark Arts", sqlite.org/
 * security.html): defensive mode, an untrusted schema, views and triggers
 * off, small limits, `topics` and `messages` required to be ordinary
 * tables without computed columns (a view can recurse without end), and a
 * budget of virtual-machine steps proportional to the file size (pages
 * of a crafted b-tree can point to the same children, so that a file of
 * a few KiB holds billions of rows).
 */
#include "internal.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-formats.h"

#ifdef HAVE_SQLITE3
#include <sqlite3.h>

/* SQLite, opened on the first .db3 file (io-lazy.c) */
#define SQLITE_FUNCS(X)                                                        \
	X(sqlite3_bind_int64) X(sqlite3_bind_text) X(sqlite3_close)            \
	X(sqlite3_column_blob) X(sqlite3_column_bytes) X(sqlite3_column_int64) \
	X(sqlite3_column_text) X(sqlite3_db_config) X(sqlite3_deserialize)     \
	X(sqlite3_errcode) X(sqlite3_errmsg) X(sqlite3_exec)                   \
	X(sqlite3_finalize) X(sqlite3_limit) X(sqlite3_open_v2)                \
	X(sqlite3_prepare_v2) X(sqlite3_progress_handler) X(sqlite3_reset)     \
	X(sqlite3_step)
SSC_LAZY_TABLE(sq, SQLITE_FUNCS);
SSC_LAZY_LIB(sqlite_lib, "libsqlite3.so.0", "libsqlite3-0", sq, SQLITE_FUNCS);

/* The work budget in virtual-machine steps: the reads below cost 0.06
 * steps per byte of a 200 Hz IMU recording and 0.34 on 100,000 messages of
 * 5 and 36 bytes (std_msgs/Empty, sensor_msgs/Temperature); a row takes at
 * least 15 bytes of the file and about 20 steps, so no real file needs
 * more than 2 a byte.  16 a byte, plus a million steps (0.1 s) for the
 * schema and small files. */
#define STEPS_PER_BYTE 16
#define STEPS_BASE 1000000ULL
#define STEPS_PER_CALL 1000

struct budget {
	unsigned long long calls, max_calls;
};

static int over_budget(void *ctx)
{
	struct budget *b = ctx;

	return ++b->calls > b->max_calls;
}

static int db_err(sqlite3 *db, const struct budget *b, const char *disp,
		  struct sscope_diag *diag)
{
	int e = sq.sqlite3_errcode(db);

	if (e == SQLITE_NOMEM)
		return ssc_diag(diag, -ENOMEM,
				"%s: rosbag2 SQLite file: out of memory", disp);
	if (e == SQLITE_INTERRUPT && b->calls > b->max_calls)
		return ssc_diag(diag, -EBADMSG,
				"%s: rosbag2 SQLite file: reading it takes more work than a file of its size can need (a corrupt or crafted b-tree): check it with `sqlite3 FILE 'PRAGMA integrity_check'`",
				disp);
	return ssc_diag(diag, -EBADMSG,
			"%s: rosbag2 SQLite file: %s (not a rosbag2 .db3, or corrupt)",
			disp, sq.sqlite3_errmsg(db));
}

/* SQLite's settings for a database from an untrusted source */
static int harden(sqlite3 *db, size_t len)
{
#if SQLITE_VERSION_NUMBER < 3031000
	(void)db;
	(void)len;
	return -1; /* no untrusted-schema mode before SQLite 3.31 */
#else
	static const int off[] = {
		SQLITE_DBCONFIG_ENABLE_TRIGGER, SQLITE_DBCONFIG_ENABLE_VIEW,
		SQLITE_DBCONFIG_TRUSTED_SCHEMA, SQLITE_DBCONFIG_ENABLE_LOAD_EXTENSION,
	};
	int v = 0;

	if (sq.sqlite3_db_config(db, SQLITE_DBCONFIG_DEFENSIVE, 1, &v) != SQLITE_OK ||
	    !v)
		return -1;
	for (size_t i = 0; i < sizeof(off) / sizeof(off[0]); i++)
		if (sq.sqlite3_db_config(db, off[i], 0, &v) != SQLITE_OK || v)
			return -1;
	/* no value longer than the file itself (a blob stored in it cannot
	 * be); short statements, shallow expressions, nothing attached */
	sq.sqlite3_limit(db, SQLITE_LIMIT_LENGTH,
		      len < (1u << 20) ? 1 << 20 : len > INT_MAX ? INT_MAX : (int)len);
	sq.sqlite3_limit(db, SQLITE_LIMIT_SQL_LENGTH, 65536);
	sq.sqlite3_limit(db, SQLITE_LIMIT_EXPR_DEPTH, 100);
	sq.sqlite3_limit(db, SQLITE_LIMIT_COMPOUND_SELECT, 3);
	sq.sqlite3_limit(db, SQLITE_LIMIT_VDBE_OP, 25000);
	sq.sqlite3_limit(db, SQLITE_LIMIT_FUNCTION_ARG, 8);
	sq.sqlite3_limit(db, SQLITE_LIMIT_ATTACHED, 0);
	sq.sqlite3_limit(db, SQLITE_LIMIT_LIKE_PATTERN_LENGTH, 50);
	sq.sqlite3_limit(db, SQLITE_LIMIT_VARIABLE_NUMBER, 10);
	sq.sqlite3_limit(db, SQLITE_LIMIT_TRIGGER_DEPTH, 1);
	sq.sqlite3_limit(db, SQLITE_LIMIT_WORKER_THREADS, 0);
	return 0;
#endif
}

/* `name` is an ordinary table of main (not a view or virtual table) with
 * no computed column */
static int real_table(sqlite3 *db, const struct budget *b, const char *name,
		      const char *disp, struct sscope_diag *diag)
{
	sqlite3_stmt *st = NULL;
	int rc = 0, s;

	if (sq.sqlite3_prepare_v2(db,
			       "SELECT type, rootpage FROM main.sqlite_master WHERE name = ?1 COLLATE NOCASE AND type <> 'trigger'",
			       -1, &st, NULL) != SQLITE_OK)
		return db_err(db, b, disp, diag);
	sq.sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
	s = sq.sqlite3_step(st);
	if (s == SQLITE_DONE) {
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: SQLite file without a '%s' table: not a rosbag2 .db3 (name the bag folder or its .db3 file)",
			      disp, name);
	} else if (s != SQLITE_ROW) {
		rc = db_err(db, b, disp, diag);
	} else {
		const char *type = (const char *)sq.sqlite3_column_text(st, 0);
		bool table = type && !strcmp(type, "table");

		/* views and virtual tables have no b-tree of their own */
		if (!table || sq.sqlite3_column_int64(st, 1) <= 0)
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: rosbag2 SQLite file: '%s' is a %.20s, not a table (refused: rosbag2 never writes one; convert the bag with `ros2 bag convert`)",
				      disp, name,
				      table ? "virtual table" : type ? type : "?");
	}
	sq.sqlite3_finalize(st);
	if (rc)
		return rc;
	/* hidden 2: a generated column computed at each read */
	if (sq.sqlite3_prepare_v2(db,
			       "SELECT name FROM pragma_table_xinfo(?1, 'main') WHERE hidden NOT IN (0, 3)",
			       -1, &st, NULL) != SQLITE_OK)
		return db_err(db, b, disp, diag);
	sq.sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
	s = sq.sqlite3_step(st);
	if (s == SQLITE_ROW)
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: rosbag2 SQLite file: column '%.40s' of '%s' is computed at each read (refused: rosbag2 never writes one; convert the bag with `ros2 bag convert`)",
			      disp, sq.sqlite3_column_text(st, 0) ?
				      (const char *)sq.sqlite3_column_text(st, 0) : "?",
			      name);
	else if (s != SQLITE_DONE)
		rc = db_err(db, b, disp, diag);
	sq.sqlite3_finalize(st);
	return rc;
}

int ssc_db3_read(const unsigned char *buf, size_t len, struct ssc_ros *c,
		 const char *disp, struct sscope_diag *diag)
{
	sqlite3 *db = NULL;
	sqlite3_stmt *st = NULL;
	size_t *map = NULL, nmap = 0;
	struct budget bud = { 0, 0 };
	int rc = 0, s;

	bud.max_calls = (STEPS_BASE + (unsigned long long)len * STEPS_PER_BYTE) /
			STEPS_PER_CALL;
	rc = ssc_lazylib_load(&sqlite_lib, diag, disp);
	if (rc)
		return rc;
	if (sq.sqlite3_open_v2(":memory:", &db, SQLITE_OPEN_READWRITE, NULL) !=
	    SQLITE_OK) {
		sq.sqlite3_close(db);
		return ssc_diag(diag, -ENOMEM,
				"%s: rosbag2 SQLite file: out of memory", disp);
	}
	if (harden(db, len)) {
		rc = ssc_diag(diag, -ENOTSUP,
			      "%s: this SQLite library cannot open a file safely (defensive mode): update libsqlite3 to 3.31 or later",
			      disp);
		goto out;
	}
	sq.sqlite3_progress_handler(db, STEPS_PER_CALL, over_budget, &bud);
	/* read only, no copy: SQLite never writes the mapped bytes */
	if (sq.sqlite3_deserialize(db, "main", (unsigned char *)buf,
				(sqlite3_int64)len, (sqlite3_int64)len,
				SQLITE_DESERIALIZE_READONLY) != SQLITE_OK) {
		rc = db_err(db, &bud, disp, diag);
		goto out;
	}
	rc = real_table(db, &bud, "topics", disp, diag);
	if (!rc)
		rc = real_table(db, &bud, "messages", disp, diag);
	if (rc)
		goto out;
	if (sq.sqlite3_prepare_v2(db,
			       "SELECT id, name, type, serialization_format FROM main.topics",
			       -1, &st, NULL) != SQLITE_OK) {
		rc = db_err(db, &bud, disp, diag);
		goto out;
	}
	while ((s = sq.sqlite3_step(st)) == SQLITE_ROW) {
		sqlite3_int64 id = sq.sqlite3_column_int64(st, 0);
		const char *name = (const char *)sq.sqlite3_column_text(st, 1);
		const char *type = (const char *)sq.sqlite3_column_text(st, 2);
		const char *ser = (const char *)sq.sqlite3_column_text(st, 3);
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
		rc = db_err(db, &bud, disp, diag);
		goto out;
	}
	sq.sqlite3_finalize(st);
	st = NULL;
	/* counts of every topic, then the messages of the readable ones */
	if (sq.sqlite3_prepare_v2(db,
			       "SELECT topic_id, COUNT(*) FROM main.messages GROUP BY topic_id",
			       -1, &st, NULL) != SQLITE_OK) {
		rc = db_err(db, &bud, disp, diag);
		goto out;
	}
	while ((s = sq.sqlite3_step(st)) == SQLITE_ROW) {
		sqlite3_int64 id = sq.sqlite3_column_int64(st, 0);

		if (id >= 0 && (size_t)id < nmap && map[id] &&
		    !ssc_ros_readable(c, map[id] - 1))
			ssc_ros_count(c, map[id] - 1,
				      (uint64_t)sq.sqlite3_column_int64(st, 1));
	}
	if (s != SQLITE_DONE) {
		rc = db_err(db, &bud, disp, diag);
		goto out;
	}
	sq.sqlite3_finalize(st);
	st = NULL;
	/* only the readable topics' blobs are loaded: their ids go into a
	 * table of the (in-memory) temporary schema, however many they are */
	if (sq.sqlite3_exec(db,
			 "PRAGMA temp_store = MEMORY;"
			 "CREATE TEMP TABLE wanted(id INTEGER PRIMARY KEY)",
			 NULL, NULL, NULL) != SQLITE_OK ||
	    sq.sqlite3_prepare_v2(db, "INSERT INTO temp.wanted VALUES (?1)", -1,
			       &st, NULL) != SQLITE_OK) {
		rc = db_err(db, &bud, disp, diag);
		goto out;
	}
	for (size_t i = 0; i < nmap; i++) {
		if (!map[i] || !ssc_ros_readable(c, map[i] - 1))
			continue;
		sq.sqlite3_bind_int64(st, 1, (sqlite3_int64)i);
		if (sq.sqlite3_step(st) != SQLITE_DONE) {
			rc = db_err(db, &bud, disp, diag);
			goto out;
		}
		sq.sqlite3_reset(st);
	}
	sq.sqlite3_finalize(st);
	st = NULL;
	if (sq.sqlite3_prepare_v2(db,
			       "SELECT topic_id, timestamp, data, id FROM main.messages"
			       " WHERE topic_id IN temp.wanted ORDER BY timestamp, id",
			       -1, &st, NULL) != SQLITE_OK) {
		rc = db_err(db, &bud, disp, diag);
		goto out;
	}
	while ((s = sq.sqlite3_step(st)) == SQLITE_ROW) {
		sqlite3_int64 id = sq.sqlite3_column_int64(st, 0);
		const unsigned char *d;
		int n;

		if (id < 0 || (size_t)id >= nmap || !map[id]) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: rosbag2: message %lld of an unknown topic",
				      disp, (long long)sq.sqlite3_column_int64(st, 3));
			goto out;
		}
		if (!ssc_ros_readable(c, map[id] - 1))
			continue;
		d = sq.sqlite3_column_blob(st, 2);
		n = sq.sqlite3_column_bytes(st, 2);
		rc = ssc_ros_message(c, map[id] - 1, d ? d : (const unsigned char *)"",
				     (size_t)n, sq.sqlite3_column_int64(st, 1),
				     (uint64_t)sq.sqlite3_column_int64(st, 3) | 1ULL << 63,
				     diag);
		if (rc)
			goto out;
	}
	if (s != SQLITE_DONE)
		rc = db_err(db, &bud, disp, diag);
out:
	sq.sqlite3_finalize(st);
	sq.sqlite3_close(db);
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
