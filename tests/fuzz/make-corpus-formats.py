# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes tests/fuzz/corpus/{bag,mcap,npy,gzip} (run from the top source
folder with /usr/bin/python3 and the build's tests/gen-ros): small files
that each break one rule of their format -- lengths that point past the
end or wrap, sizes of gigabytes, messages of unknown streams or too short
for their type, shapes that overflow, streams cut short.  The files are
committed; tests/cli-formats-hardening.sh replays them."""
import gzip
import os
import struct
import subprocess
import tempfile

C = "tests/fuzz/corpus"
for d in ("bag", "mcap", "npy", "gzip"):
    os.makedirs(os.path.join(C, d), exist_ok=True)


def w(path, data):
    with open(os.path.join(C, path), "wb") as f:
        f.write(data)


def field(name, value):
    b = name.encode() + b"=" + value
    return struct.pack("<I", len(b)) + b


def record(header, data):
    return struct.pack("<I", len(header)) + header + \
        struct.pack("<I", len(data)) + data


MAGIC = b"#ROSBAG V2.0\n"
conn = record(field("op", b"\x07") + field("conn", struct.pack("<I", 0)) +
              field("topic", b"/imu"),
              field("topic", b"/imu") + field("type", b"sensor_msgs/Imu"))
msg_hdr = field("op", b"\x02") + field("conn", struct.pack("<I", 0)) + \
    field("time", struct.pack("<II", 1, 2))
w("bag/header-len-past-end.bag", MAGIC + struct.pack("<I", 0xfffffff0) +
  b"\0" * 16)
w("bag/data-len-wraps.bag", MAGIC + struct.pack("<I", 4) + b"abcd" +
  struct.pack("<I", 0xffffffff) + b"\0" * 8)
w("bag/field-len-past-end.bag", MAGIC + record(
    struct.pack("<I", 0x7fffffff) + b"op=\x05", b""))
w("bag/chunk-size-4g.bag", MAGIC + record(
    field("op", b"\x05") + field("compression", b"lz4") +
    field("size", struct.pack("<I", 0xffffffff)), b"\x04\x22\x4d\x18" +
    b"\0" * 12))
w("bag/chunk-bad-lz4.bag", MAGIC + record(
    field("op", b"\x05") + field("compression", b"lz4") +
    field("size", struct.pack("<I", 4096)), b"\x04\x22\x4d\x18garbage!"))
w("bag/chunk-bad-bz2.bag", MAGIC + record(
    field("op", b"\x05") + field("compression", b"bz2") +
    field("size", struct.pack("<I", 4096)), b"BZh9garbage"))
w("bag/message-unknown-conn.bag", MAGIC + record(
    field("op", b"\x05") + field("compression", b"none") +
    field("size", struct.pack("<I", len(record(msg_hdr, b"x" * 300)))),
    record(msg_hdr, b"x" * 300)))
inner = conn + record(msg_hdr, struct.pack("<IIII", 0, 1, 2, 3) + b"\0" * 10)
w("bag/imu-message-short.bag", MAGIC + record(
    field("op", b"\x05") + field("compression", b"none") +
    field("size", struct.pack("<I", len(inner))), inner))
inner = conn + record(msg_hdr, struct.pack("<IIII", 0, 1, 2, 0xffffff00) +
                      b"\0" * 300)
w("bag/frame-id-past-end.bag", MAGIC + record(
    field("op", b"\x05") + field("compression", b"none") +
    field("size", struct.pack("<I", len(inner))), inner))

MM = b"\x89MCAP0\r\n"


def mrec(op, content):
    return bytes([op]) + struct.pack("<Q", len(content)) + content


def mstr(s):
    return struct.pack("<I", len(s)) + s


footer = mrec(0x0f, struct.pack("<I", 0)) + mrec(0x02, b"\0" * 20) + MM
w("mcap/record-len-huge.mcap", MM + bytes([0x06]) +
  struct.pack("<Q", 1 << 63) + b"\0" * 32)
w("mcap/chunk-usize-huge.mcap", MM + mrec(0x06, struct.pack(
    "<QQQI", 0, 0, 1 << 40, 0) + mstr(b"zstd") + struct.pack("<Q", 4) +
    b"\x28\xb5\x2f\xfd") + footer)
w("mcap/chunk-bad-zstd.mcap", MM + mrec(0x06, struct.pack(
    "<QQQI", 0, 0, 4096, 0) + mstr(b"zstd") + struct.pack("<Q", 12) +
    b"\x28\xb5\x2f\xfdgarbage!") + footer)
w("mcap/chunk-records-past-end.mcap", MM + mrec(0x06, struct.pack(
    "<QQQI", 0, 0, 16, 0) + mstr(b"") + struct.pack("<Q", 1 << 40)) +
  footer)
chan = mrec(0x03, struct.pack("<H", 1) + mstr(b"sensor_msgs/msg/Imu") +
            mstr(b"ros2msg") + mstr(b"")) + \
    mrec(0x04, struct.pack("<HH", 1, 1) + mstr(b"/imu") + mstr(b"cdr") +
         struct.pack("<I", 0))
w("mcap/message-unknown-channel.mcap", MM + mrec(0x05, struct.pack(
    "<HIQQ", 7, 0, 1, 1) + b"\0" * 300) + footer)
w("mcap/cdr-bad-encapsulation.mcap", MM + chan + mrec(0x05, struct.pack(
    "<HIQQ", 1, 0, 1, 1) + b"\x00\x07\x00\x00" + b"\0" * 320) + footer)
w("mcap/cdr-string-past-end.mcap", MM + chan + mrec(0x05, struct.pack(
    "<HIQQ", 1, 0, 1, 1) + b"\x00\x01\x00\x00" + struct.pack(
    "<iII", 1, 2, 0xfffffff0) + b"\0" * 300) + footer)
w("mcap/schema-string-past-end.mcap", MM + mrec(
    0x03, struct.pack("<H", 1) + struct.pack("<I", 0x7fffffff) + b"ab") +
  footer)
w("mcap/no-footer.mcap", MM + chan)


def npy(header, data, ver=1):
    h = header.encode()
    pad = 64 - (10 + len(h) + 1) % 64
    h = h + b" " * pad + b"\n"
    return b"\x93NUMPY" + bytes([ver, 0]) + struct.pack("<H", len(h)) + h + \
        data


w("npy/shape-overflow.npy", npy(
    "{'descr': '<f8', 'fortran_order': False, 'shape': (4611686018427387904, 4), }",
    b"\0" * 64))
w("npy/truncated.npy", npy(
    "{'descr': '<f8', 'fortran_order': False, 'shape': (100, 3), }",
    b"\0" * 800))
w("npy/header-len-past-end.npy", b"\x93NUMPY\x01\x00\xff\xff{'descr'")
w("npy/structured.npy", npy(
    "{'descr': [('a', '<f8'), ('b', '<i4')], 'fortran_order': False, 'shape': (2,), }",
    b"\0" * 24))
w("npy/three-dims.npy", npy(
    "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2, 2), }",
    b"\0" * 32))
w("npy/negative-shape.npy", npy(
    "{'descr': '<f4', 'fortran_order': False, 'shape': (-2, 2), }",
    b"\0" * 16))
w("npy/version-9.npy", b"\x93NUMPY\x09\x00" + b"\0" * 20)

text = b"time [s],gx [rad/s]\n" + b"".join(
    b"%.2f,%.5f\n" % (i / 100, (i % 7) * 0.01) for i in range(5000))
z = gzip.compress(text)
w("gzip/truncated.csv.gz", z[:len(z) // 2])
w("gzip/corrupt.csv.gz", z[:40] + bytes(b ^ 0x5a for b in z[40:80]) + z[80:])

# a real bag and MCAP from the test writer, cut inside a chunk
with tempfile.TemporaryDirectory() as d:
    subprocess.run(["tests/gen-ros", d, "200", "2"], check=True)
    for src, dst in (("imu-lz4.bag", "bag/cut-in-chunk.bag"),
                     ("imu-zstd.mcap", "mcap/cut-in-chunk.mcap")):
        b = open(os.path.join(d, src), "rb").read()
        w(dst, b[:len(b) * 2 // 3])
