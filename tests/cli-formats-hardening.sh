#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The container and stream readers on the corpus of broken files in
# tests/fuzz/corpus/{bag,mcap,npy,gzip} (written by
# tests/fuzz/make-corpus-formats.py): lengths past the end or wrapping,
# chunk sizes of gigabytes, corrupt compressed data, messages of unknown
# streams or too short for their type, shapes that overflow, streams cut
# short.  Each is exit 1 with one line naming the file and what is wrong,
# from a file and from standard input; under make check-valgrind also
# without a read outside the input.
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

done_testing
