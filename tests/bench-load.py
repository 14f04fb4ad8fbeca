#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""make bench: the whole process as a user runs it, idle and beside other
work (issue 35, items 1 and 2).

Start-up: `--help`, `--version` and `info` on the bundled gyro beside
/bin/true, interleaved, median of START_RUNS (default 40) runs each.

Threads: each command with its default team, with one thread and with two
(OMP_NUM_THREADS=1 / 2, which also turns off the default's choice), on an
idle machine, beside a competitor (one CPU-bound process at normal
priority, a Python busy loop: it takes one core) and beside two;
interleaved (each round starting with the next team), median of RUNS
(default 15) wall times, or of as many runs as take SPAN (default 3)
seconds a team when that is more (up to 300).  The default should be
within 10 % of the faster of one and two threads in every condition.

Usage: bench-load.py SENSORSCOPE [WORKDIR]
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

S = sys.argv[1]
SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SAMPLE = os.path.join(SRC, "samples", "gyro-static.csv")
START_RUNS = int(os.environ.get("START_RUNS", "40"))
RUNS = int(os.environ.get("RUNS", "15"))
SPAN = float(os.environ.get("SPAN", "3"))


def wall(argv, env=None):
    t0 = time.perf_counter()
    subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   env=env, check=True)
    return time.perf_counter() - t0


def medians(cases, runs):
    """cases: {label: (argv, env)}; interleaved runs, each round starting
    with the next case (no case always first), median seconds"""
    t = {k: [] for k in cases}
    order = list(cases)
    for r in range(runs):
        for k in order[r % len(order):] + order[:r % len(order)]:
            argv, env = cases[k]
            t[k].append(wall(argv, env))
    return {k: statistics.median(v) for k, v in t.items()}


def env_with(**kw):
    e = dict(os.environ)
    e.pop("OMP_NUM_THREADS", None)
    e.update(kw)
    return e


def startup():
    cases = {
        "/bin/true": (["/bin/true"], None),
        "--help": ([S, "--help"], None),
        "--version": ([S, "--version"], None),
        "info samples/gyro-static.csv": ([S, "info", SAMPLE], None),
    }
    m = medians(cases, START_RUNS)
    base = m["/bin/true"]
    print("# start-up, median of %d interleaved runs (whole process)" % START_RUNS)
    print("%-34s %9s %9s" % ("command", "ms", "x true"))
    for k, v in m.items():
        print("%-34s %9.2f %9.2f" % (k, 1e3 * v, v / base))


def thread_rows(tmp):
    rng = np.random.default_rng(35)
    big = os.path.join(tmp, "white.f64")
    rng.standard_normal(10_000_000).tofile(big)
    small = os.path.join(tmp, "all.f64")
    rng.standard_normal(30_000).tofile(small)
    csv = os.path.join(tmp, "imu.csv")
    with open(csv, "w") as f:
        f.write("# rate: 100 Hz\ngx [rad/s],gy [rad/s],gz [rad/s]\n")
        np.savetxt(f, rng.standard_normal((1_000_000, 3)), fmt="%.6e",
                   delimiter=",")
    raw = ["--raw", "f64:1:le"]
    return {
        "allan octave 1e7": [S, "allan"] + raw + ["--rate", "100", "--taus", "octave",
                                                  "--ci", "none", "--no-fit",
                                                  "--format", "json", big],
        "allan all-tau 3e4": [S, "allan"] + raw + ["--rate", "1", "--taus", "all",
                                                   "--ci", "none", "--no-fit",
                                                   "--format", "json", small],
        "psd 1e7": [S, "psd"] + raw + ["--rate", "1000", "--nperseg", "4096",
                                       "--format", "json", big],
        "info CSV 1e6 x 3": [S, "info", "--format", "json", csv],
        "report gyro-static": [S, "report", "-o",
                               os.path.join(tmp, "rep"), SAMPLE],
    }


def threads(tmp):
    rows = thread_rows(tmp)
    bad = 0
    print("# threads: median wall of at least %d interleaved runs (runs: how many); default within 10 %% of the faster of 1 and 2" % RUNS)
    print("%-22s %-13s %9s %9s %9s %7s %5s" % ("command", "machine", "default", "1 thread",
                                               "2 threads", "ok", "runs"))
    for cond, nc in (("idle", 0), ("competitor", 1), ("2 competitors", 2)):
        comp = [subprocess.Popen([sys.executable, "-c", "while True: pass"])
                for _ in range(nc)]
        if comp:
            time.sleep(0.5)
        print("# %s: load average %s" % (cond, open("/proc/loadavg").read().split()[0]))
        try:
            for name, argv in rows.items():
                # short commands: as many runs as take SPAN seconds a team
                # (their times are bimodal on a shared machine: 24 or
                # 31-38 ms for the all-tau row, whatever the team)
                runs = max(RUNS, min(300, int(SPAN / wall(argv, env_with()))))
                m = medians({"d": (argv, env_with()),
                             "1": (argv, env_with(OMP_NUM_THREADS="1")),
                             "2": (argv, env_with(OMP_NUM_THREADS="2"))}, runs)
                ok = m["d"] <= 1.10 * min(m["1"], m["2"])
                bad += not ok
                print("%-22s %-13s %9.3f %9.3f %9.3f %7s %5d" % (
                    name, cond, m["d"], m["1"], m["2"], "yes" if ok else "NO", runs))
                sys.stdout.flush()
        finally:
            for c in comp:
                c.kill()
                c.wait()
    print("# %d row%s off target" % (bad, "" if bad == 1 else "s"))


def main():
    with tempfile.TemporaryDirectory(dir=sys.argv[2] if len(sys.argv) > 2 else None) as tmp:
        print("# machine: %s, %d processors, load average at start %s" % (
            os.uname().machine, os.cpu_count(), open("/proc/loadavg").read().split()[0]))
        startup()
        threads(tmp)


if __name__ == "__main__":
    main()
