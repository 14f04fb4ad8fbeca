# SPDX-License-Identifier: GPL-3.0-or-later
"""How the cost of each command grows with the record (make bench, via
tests/bench-growth.sh): a gyro-like raw f64 record (white noise plus a
random walk, one channel at 100 Hz) of 1e4 .. 1e8 samples (1e9 with
BENCH_GROWTH_MAX=1e9: 8 GB, streamed from the raw file, deleted after);
for info, allan (octave, dense, all: without the fit), the noise fit
(allan on its dense grid with the fit), psd and report: wall and CPU
seconds and peak RSS of the whole process (/usr/bin/time), and the
exponent of the time between sizes and over the sizes from 1e6 on, to be
read against each algorithm's order (N; the all-tau grid N log^2 N: its
OADEV sums by transforms)."""

import math
import os
import subprocess
import sys
import tempfile

import numpy as np

S = os.path.join(os.environ.get("top_builddir", "."), "src", "sensorscope")
NMAX = int(float(os.environ.get("BENCH_GROWTH_MAX", "1e8")))
SIZES = [n for n in (10**4, 10**5, 10**6, 10**7, 10**8, 10**9) if n <= NMAX]
RAW = ["--raw", "f64:1:le", "--rate", "100", "-u", "deg/s", "-q"]
# (name, arguments, largest size, order of its algorithm)
CMDS = [
    ("info", ["info"], 10**9, "N"),
    ("allan octave", ["allan", "--taus", "octave", "--no-fit",
                      "--format", "json"], 10**9, "N"),
    ("allan dense", ["allan", "--taus", "dense", "--no-fit",
                     "--format", "json"], 10**9, "N"),
    # (N / 2 taus: 10^6 samples write 87 MB of JSON)
    ("allan all", ["allan", "--taus", "all", "--no-fit",
                   "--format", "json"], 10**6, "N log^2 N"),
    ("noise fit", ["allan", "--format", "json"], 10**9, "N"),
    ("psd", ["psd", "--format", "json"], 10**9, "N"),
    ("report", ["report", "-o", "@DIR@"], 10**8, "N"),
]


def write_record(path, n):
    """white noise 0.01 deg/s plus a random walk, in chunks of 1e7"""
    rng = np.random.default_rng(7)
    walk = 0.0
    with open(path, "wb") as f:
        left = n
        while left:
            k = min(left, 10**7)
            w = np.cumsum(rng.normal(0.0, 1e-5, k)) + walk
            walk = float(w[-1])
            (0.5 + w + rng.normal(0.0, 0.01, k)).astype("<f8").tofile(f)
            left -= k


def measure(args, out):
    t = subprocess.run(["/usr/bin/time", "-f", "%e %U %S %M", "-o", out]
                       + args, stdout=subprocess.DEVNULL,
                       stderr=subprocess.PIPE, text=True)
    if t.returncode:
        return None
    with open(out) as fh:
        w, u, s, kb = fh.read().split()[-4:]
    return float(w), float(u) + float(s), int(kb) / 1024.0


def slope(a, b):
    """log10 ratio of times over a decade"""
    return math.log10(b / a) if a > 0 and b > 0 else float("nan")


def main():
    if not os.path.exists("/usr/bin/time"):
        print("bench-growth: /usr/bin/time (Debian package time) is needed: "
              "skipped")
        return 0
    with open("/proc/loadavg") as fh:
        load = " ".join(fh.read().split()[:3])
    print("load average: %s (wall times grow with it; CPU times do not)"
          % load)
    res = {}
    with tempfile.TemporaryDirectory(dir=os.environ.get("TMPDIR")) as td:
        tfile = os.path.join(td, "time")
        for n in SIZES:
            path = os.path.join(td, "rec.f64")
            write_record(path, n)
            for name, args, nmax, _order in CMDS:
                if n > nmax:
                    continue
                args = [a.replace("@DIR@", os.path.join(td, "rep"))
                        for a in args]
                r = measure([S] + args + RAW + [path], tfile)
                res[name, n] = r
                if r:
                    print("%-13s %8.0e samples: %8.3f s wall %8.3f s CPU "
                          "%8.1f MB" % (name, n, r[0], r[1], r[2]),
                          flush=True)
                else:
                    print("%-13s %8.0e samples: failed" % (name, n))
            os.unlink(path)
    print()
    print("| command | order | " + " | ".join("%.0e" % n for n in SIZES)
          + " | exponent (CPU, per decade from 1e6) | peak RSS at the "
          "largest |")
    print("|---|---|" + "---|" * len(SIZES) + "---|---|")
    for name, _args, nmax, order in CMDS:
        cells, cpu, last = [], [], None
        for n in SIZES:
            r = res.get((name, n))
            cells.append("%.3g s" % r[1] if r else "-")
            if r and n >= 10**6:
                cpu.append((math.log10(n), math.log10(max(r[1], 1e-3))))
            if r:
                last = r
        if len(cpu) >= 2:
            xs, ys = zip(*cpu)
            mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
            b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / \
                sum((x - mx) ** 2 for x in xs)
            ex = "%.2f" % b
        elif name == "allan all":
            r4, r5 = res.get((name, 10**5)), res.get((name, 10**6))
            ex = "%.2f (1e5 to 1e6)" % slope(r4[1], r5[1]) if r4 and r5 \
                else "-"
        else:
            ex = "-"
        print("| %s | %s | %s | %s | %s |" % (
            name, order, " | ".join(cells), ex,
            "%.0f MB" % last[2] if last else "-"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
