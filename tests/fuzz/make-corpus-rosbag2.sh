#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Writes the seeds of the rosbag2 folder harness, tests/fuzz/corpus/rosbag2
# (one file per folder: metadata.yaml, then each storage file after a line
# "#FILE", named f0, f1, ... in the metadata; see fuzz-rosbag2.c), and the
# .db3 seeds of the text harness, tests/fuzz/corpus/text/db3-*.db3.  Run
# from the top source folder with the build's tests/gen-ros:
#   sh tests/fuzz/make-corpus-rosbag2.sh BUILDDIR/tests/gen-ros
set -eu
gen=$1
C=tests/fuzz/corpus
t=$(mktemp -d)
trap 'rm -rf "$t"' EXIT
"$gen" "$t" 20 1 small
mkdir "$t/h"
"$gen" "$t/h" 20 1 hostile
mkdir -p "$C/rosbag2"

# seed NAME STORAGE COMPRESSION FILE...
seed() {
	name=$1 storage=$2 comp=$3
	shift 3
	{
		printf 'rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: %s\n' "$storage"
		if [ "$comp" = zstd ]; then
			printf '  compression_format: zstd\n  compression_mode: FILE\n'
		fi
		printf '  relative_file_paths:\n'
		i=0
		for f; do
			printf '    - f%d\n' $i
			i=$((i + 1))
		done
		for f; do
			printf '\n#FILE\n'
			cat "$f"
		done
	} >"$C/rosbag2/$name"
}

zstd -q -19 -c "$t/rosbag2/rosbag2_0.db3" >"$t/db3.zstd"
zstd -q -19 -c "$t/imu-none.mcap" >"$t/mcap.zstd"
seed db3 sqlite3 "" "$t/rosbag2/rosbag2_0.db3"
seed db3-zstd sqlite3 zstd "$t/db3.zstd"
seed mcap mcap "" "$t/rosbag2-mcap/rosbag2_0.mcap"
seed mcap-zstd mcap zstd "$t/mcap.zstd"
seed mcap-split mcap "" "$t/imu-lz4.mcap" "$t/imu-none.mcap"
seed db3-view sqlite3 "" "$t/h/view-messages.db3"
seed db3-dag sqlite3 "" "$t/h/dag.db3"
seed bomb-db3 sqlite3 zstd "$t/h/bomb-db3-small/rosbag2_0.db3.zstd"
seed bomb-mcap mcap zstd "$t/h/bomb-mcap-small/rosbag2_0.mcap.zstd"
cp "$t/rosbag2/rosbag2_0.db3" "$C/text/db3-imu.db3"
cp "$t/h/view-messages.db3" "$C/text/db3-view.db3"
cp "$t/h/computed.db3" "$C/text/db3-computed.db3"
cp "$t/h/dag.db3" "$C/text/db3-dag.db3"
