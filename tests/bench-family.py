# SPDX-License-Identifier: GPL-3.0-or-later
"""Whole-process benchmark of the total, Theo and time-error deviations
(sensorscope allan --dev mtie|tierms|mtotdev|htotdev|theo1) against numpy
transcriptions of their definitions (NIST SP 1065 5.2.12-5.2.19) written
here: allantools is not packaged by Debian and not installable here, so
the peer is the definition, vectorised the obvious way (MTIE: the max and
min of every window by numpy's sliding_window_view, O(N m) per tau; MTOT
and HTOT: a Python loop over the 3m-point subsequences, each reflected and
cumulated by numpy; Theo1: a loop over the m/2 offsets, each a vector over
the record).  Each row: our whole process (best of BENCH_REPEAT, default
2), the peer in memory, the ratio, and the largest relative difference of
the results over the taus both computed.  Then our scaling from 1e4 to
1e7 samples.

Usage: bench-family.py SENSORSCOPE_BINARY
Environment: BENCH_REPEAT (2), BENCH_MTIE_PEER_MMAX (65536: the peer's MTIE
costs N m per tau, so it stops there, about 18 s; ours computes the whole
grid, and the ratio is then a lower bound), BENCH_SCALING_MAX (10000000), TMPDIR.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

EXE = sys.argv[1]
REPEAT = int(os.environ.get("BENCH_REPEAT", "2"))
MTIE_MMAX = int(os.environ.get("BENCH_MTIE_PEER_MMAX", "65536"))
SCALE_MAX = int(os.environ.get("BENCH_SCALING_MAX", "10000000"))


def ours(path, dev, rate=1.0):
    argv = [EXE, "allan", "--raw", "f64:1:le", "--rate", repr(rate), "--taus",
            "octave", "--no-fit", "--ci", "none", "--format", "json",
            "--dev", dev, path]
    if dev == "htotdev":  # the bias factor of white FM at every tau
        argv[-1:-1] = ["--noise-type", "wfm"]
    best, out = math.inf, b""
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        t = time.perf_counter() - t0
        if p.returncode:
            raise SystemExit("%s: %s" % (" ".join(argv), p.stderr.decode()))
        best, out = min(best, t), p.stdout
    pts = json.loads(out)["channels"][0]["points"]
    return best, {pt["m"]: pt["dev"] for pt in pts}


def timed(fn):
    t0 = time.perf_counter()
    r = fn()
    return time.perf_counter() - t0, r


def phase_of(y):
    """the engine's phase of a rate record: mean removed, zero prepended"""
    return np.concatenate(([0.0], np.cumsum(y - y.mean())))


def octave(mmax):
    m, v = [], 1
    while v <= mmax:
        m.append(v)
        v *= 2
    return m


def mtie_def(x, m):
    w = np.lib.stride_tricks.sliding_window_view(x, m + 1)
    return float(np.max(w.max(axis=1) - w.min(axis=1)))


def tierms_def(x, m):
    d = x[m:] - x[:-m]
    return float(np.sqrt(np.mean(d * d)))


def tot_def(v, m):
    """mean over the 3m-point subsequences of (1/6m) sum z_j^2 of the
    half-average-detrended, reflected extension"""
    L, h = 3 * m, (3 * m) // 2
    k = np.arange(L)
    acc = 0.0
    nsub = len(v) - L + 1
    for n in range(nsub):
        s = v[n:n + L]
        slope = (s[L - h:].mean() - s[:h].mean()) / (L - h)
        d = s - slope * k
        e = np.concatenate((d[::-1], d, d[::-1]))
        c = np.concatenate(([0.0], np.cumsum(e)))
        w = c[m:] - c[:-m]
        z = w[2 * m:8 * m] - 2 * w[m:7 * m] + w[:6 * m]
        acc += float(np.dot(z, z)) / (6 * m)
    return acc / nsub


def mtot_def(x, m):
    return math.sqrt(tot_def(x, m) / (2.0 * m ** 4))


def htot_def(x, m):
    y = np.diff(x)
    if m == 1:
        d = y[2:] - 2 * y[1:-1] + y[:-2]
        return math.sqrt(float(np.mean(d * d)) / 6)
    return math.sqrt(tot_def(y, m) / (6.0 * m * m))


def theo1_def(x, m):
    n, h = len(x), m // 2
    s = 0.0
    a = x[:n - m]
    c = x[m:]
    for d in range(h):
        t = (a - x[h - d:h - d + n - m]) + (c - x[h + d:h + d + n - m])
        s += float(np.dot(t, t)) / (h - d)
    return math.sqrt(s / (0.75 * (n - m) * m * m))


def compare(name, n, path, x, dev, fn, mmax, taus_note=""):
    t_ours, got = ours(path, dev)
    ms = [m for m in sorted(got) if m <= mmax]
    t_peer, ref = timed(lambda: {m: fn(x, m) for m in ms})
    err = max(abs(got[m] - ref[m]) / abs(ref[m]) for m in ms if ref[m] != 0)
    print("%-34s ours %8.2f s | peer %8.2f s  x%6.1f  max rel diff %.1e%s" %
          ("%s %.0e octave" % (name, n), t_ours, t_peer, t_peer / t_ours, err,
           taus_note), flush=True)
    return t_peer / t_ours


def main():
    tmp = tempfile.mkdtemp(prefix="sscope-bench-family.")
    rng = np.random.default_rng(20240601)
    try:
        data = {}
        for n in (10 ** 4, 10 ** 5, 10 ** 6, 10 ** 7):
            if n > SCALE_MAX and n > 10 ** 6:
                continue
            # white rate plus a rate random walk (a gyro's N and K)
            y = rng.normal(size=n) * 0.01 + np.cumsum(rng.normal(size=n)) * 1e-5
            p = os.path.join(tmp, "r%d.f64" % n)
            y.astype("<f8").tofile(p)
            data[n] = (p, phase_of(y))
        p, x = data[10 ** 6]
        compare("MTIE", 1e6, p, x, "mtie", mtie_def, MTIE_MMAX,
                "  (peer to m = %d, ours to m = 2^19)" % MTIE_MMAX)
        compare("TIE rms", 1e6, p, x, "tierms", tierms_def, 1 << 30)
        p, x = data[10 ** 4]
        compare("MTOTDEV", 1e4, p, x, "mtotdev", mtot_def, 1 << 30)
        compare("HTOTDEV (white FM bias factor)", 1e4, p, x, "htotdev",
                lambda xx, m: htot_def(xx, m) / (math.sqrt(0.995) if m > 1 else 1),
                1 << 30, "  (--noise-type wfm)")
        p, x = data[10 ** 5]
        compare("Theo1", 1e5, p, x, "theo1", theo1_def, 1 << 30)
        print("\nscaling (ours, whole process, octave grid):")
        for dev, nmax in (("mtie", 10 ** 7), ("tierms", 10 ** 7),
                          ("theo1", 10 ** 5), ("mtotdev", 10 ** 5),
                          ("htotdev", 10 ** 5)):
            line = "  %-8s" % dev
            for n in sorted(data):
                if n > nmax or n > SCALE_MAX:
                    continue
                t, _ = ours(data[n][0], dev)
                line += "  %.0e: %7.2f s" % (n, t)
            print(line, flush=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


main()
