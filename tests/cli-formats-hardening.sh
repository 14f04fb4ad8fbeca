#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The container and stream readers on the corpus of broken files in
# tests/fuzz/corpus/{bag,mcap,npy,gzip} (written by
# tests/fuzz/make-corpus-formats.py): lengths past the end or wrapping,
# chunk sizes of gigabytes, corrupt compressed data, messages of unknown
# streams or too short for their type, shapes that overflow, streams cut
# short.  Each is exit 1 with one line naming the file and what is wrong,
# from a file and from standard input; under make check-valgrind also
# without a read outside the input.  Then the crafted containers of issue
# 29 (written by tests/gen-ros hostile): .db3 files whose tables are
# recursive views, a computed column or a b-tree of shared pages; 150 IMU
# topics in one .db3; rosbag2 folders and gzip files that expand to
# gigabytes -- each refused in a fraction of a second with one line, or
# within a memory limit, saying so.
. "$(dirname "$0")/lib.sh"

CORPUS="$top_srcdir/tests/fuzz/corpus"

check() { # FILE PATTERN
	f=$CORPUS/$1
	run "$1" 1 info "$f"
	one_line_error "$1"
	has "$1: message" "$T/err" "$2"
	run_in "$1 (stdin)" 1 "$f" info -
	one_line_error "$1 (stdin)"
}

check bag/header-len-past-end.bag 'ROS bag: record header cut short at byte 13 .*rosbag reindex'
check bag/data-len-wraps.bag 'ROS bag: record data cut short at byte 13'
check bag/field-len-past-end.bag 'ROS bag: record without an op code'
check bag/chunk-size-4g.bag 'ROS bag: chunk larger than 1 GiB'
check bag/chunk-bad-lz4.bag 'chunk at byte 13: corrupt lz4 data'
check bag/chunk-bad-bz2.bag 'chunk at byte 13: corrupt bz2 data \(0 bytes decoded, 4096 expected\)'
check bag/message-unknown-conn.bag 'message of an unknown connection'
check bag/imu-message-short.bag 'topic /imu \(sensor_msgs/Imu\), message at byte 13: 26 bytes are too few for the type'
check bag/frame-id-past-end.bag 'bytes are too few for the type'
check bag/cut-in-chunk.bag 'ROS bag: record data cut short'
check mcap/record-len-huge.mcap 'MCAP: record cut short at byte 8 .*mcap recover'
check mcap/chunk-usize-huge.mcap 'MCAP: chunk larger than 1 GiB'
check text/mcap-chunk-size-unbounded.mcap 'MCAP: chunk larger than its compressed data can hold'
check mcap/chunk-bad-zstd.mcap 'corrupt zstd data'
check mcap/chunk-records-past-end.mcap 'MCAP: chunk records cut short'
check mcap/message-unknown-channel.mcap 'message of an unknown channel'
check mcap/cdr-bad-encapsulation.mcap 'CDR encapsulation 00 07 is not plain CDR'
check mcap/cdr-string-past-end.mcap 'bytes are too few for the type'
check mcap/schema-string-past-end.mcap 'MCAP: schema record cut short'
check mcap/no-footer.mcap 'no data end or footer record'
check mcap/cut-in-chunk.mcap 'MCAP: record cut short'
check npy/header-len-past-end.npy 'npy: truncated header'
check npy/shape-overflow.npy 'npy: shape too large'
check npy/truncated.npy 'npy data are 800 bytes where the shape \(100, 3\) and dtype need 2400'
check npy/structured.npy 'save a plain numeric array'
check npy/three-dims.npy 'more than two dimensions'
check npy/negative-shape.npy 'npy: bad header \(shape\)'
check npy/version-9.npy 'npy format version 9.0 is not known'
check gzip/truncated.csv.gz 'gzip data truncated'
check gzip/corrupt.csv.gz 'corrupt gzip data'

# ---- issue 29: hostile containers
GEN="$top_builddir/tests/gen-ros"
H="$T/h"
mkdir "$H" && "$GEN" "$H" 200 1 hostile || not_ok "gen-ros hostile"

refuse() { # NAME PATTERN
	run "$1" 1 info "$H/$1"
	one_line_error "$1"
	has "$1: reason" "$T/err" "$2"
}
if [ -f "$H/view-messages.db3" ]; then
	refuse view-messages.db3 "view-messages.db3: rosbag2 SQLite file: 'messages' is a view, not a table \\(refused: .*ros2 bag convert"
	refuse view-topics.db3 "'topics' is a view, not a table"
	refuse computed.db3 "column 'timestamp' of 'messages' is computed at each read"
	refuse dag.db3 "dag.db3: rosbag2 SQLite file: reading it takes more work than a file of its size can need .*integrity_check"
	run "150 IMU topics: the last one" 0 info --format json --topic /imu149 "$H/many-topics.db3"
	json_check "/imu149: its 40 messages, gx 149 .. 149.039" "$T/out" \
	  '.channels[0].samples == 40 and .channels[0].min == 149 and .channels[0].max == 149.039'
	run "150 IMU topics: --topic needed" 1 info "$H/many-topics.db3"
	has "150 IMU topics: named" "$T/err" '150 IMU topics: choose one with --topic NAME'
else
	skip "hostile .db3 files" "built without SQLite"
fi
refuse bomb-text "bomb-text/rosbag2_0.db3.zstd: not a SQLite \\(.db3\\) or MCAP file once decompressed"
refuse bomb-mcap-zeros "not an MCAP file once decompressed \\(record at byte 8\\)"
refuse bomb-db3 "corrupt zstd data \\(they go on past the 8192 bytes the file declares\\)"
refuse bomb-db3-huge "holds a SQLite database of 134217728 MiB \\(says its header\\), more than the [0-9]+ MiB a decompressed file may take here"

# what only a cap stops: 8 GiB of zstd, 320 MiB of gzip (320 members of
# 1 MiB of zeros after a bag's first line), under a limit of 600 MB of
# address space (cap 300 MB); not under valgrind or the sanitizers, whose
# own memory the limit would cut
head -c 1048576 /dev/zero | gzip -1 >"$T/z1.gz"
printf '#ROSBAG V2.0\n' | gzip >"$T/bomb.bag.gz"
i=0
while [ $i -lt 320 ]; do cat "$T/z1.gz"; i=$((i + 1)); done >>"$T/bomb.bag.gz"
if [ -z "$SSCOPE_RUN" ] && [ "${SSCOPE_SANITIZERS:-0}" != 1 ] &&
   (ulimit -v 600000 && ss --version) >/dev/null 2>&1; then
	for f in bomb-mcap bomb.bag.gz; do
		case $f in bomb-mcap) p="$H/$f" ;; *) p="$T/$f" ;; esac
		(ulimit -v 600000 && exec "$SSCOPE" info "$p") >"$T/out" 2>"$T/err"
		if [ $? -eq 1 ]; then ok "$f under 600 MB (exit 1)"; else not_ok "$f under 600 MB"; diag "$T/err"; fi
		one_line_error "$f under 600 MB"
		has "$f: over the cap, not corrupt" "$T/err" 'expand to more than the [0-9]+ MiB a decompressed file may take here \(half the memory this process may use\)'
		lacks "$f: not called corrupt" "$T/err" 'corrupt'
	done
else
	skip "zstd and gzip bombs under a memory limit" "valgrind, sanitizers or no ulimit -v"
fi

done_testing
