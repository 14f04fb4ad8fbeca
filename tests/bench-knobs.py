#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""make bench: run time against error for every option that trades one for
the other, the whole command as a user runs it.

Each row: the median wall and CPU seconds of the command (os.wait4 of the
child: user + system of every thread) and the statistical error it buys,
measured against a known truth over repeated simulated records (the rms
relative error of the estimates over SEEDS records of different seeds) or,
where the command reports one, the standard error / interval half-width it
prints beside the spread over seeds.

  allan --taus, --stride, the fit: a simulated gyro (N 0.15 deg/sqrt(h),
      K 30 deg/h/sqrt(h): K dominates from 31 s on), 100 Hz, 30 min
      (180,000 samples), SEEDS (10) records; error = rms relative error
      of the fitted K (and N) against the truth, beside the half-width of
      K's interval as printed.  The fit's bootstrap has 1000 replicates,
      not an option: its cost is shown as the time --no-fit saves.
  allan --stride on 10^7 samples of white noise (raw f64), --taus all
      and --taus decade (--stride is refused on the octave and dense
      grids), --no-fit: error = median over the taus of 1/sqrt(2 EDF), the
      deviation's relative sd from the EDF the command prints.  No
      --taus all row without a stride: beyond 2^22 points every factor is
      computed by the definition (more than 300 s at 10^7).
  adc report --monte-carlo R x --mc-duration D: the textbook MEMS gyro
      through the 16-bit converter; error = the printed se of the B ratio
      (rms over SEEDS seeds), beside the sd of the ratio over them.
  navsim --runs M: the MEMS gyro sample, 2 min at 100 Hz; error = the
      printed Monte-Carlo se of the final horizontal rms, relative.
  walk --paths P (with --plot): the bundled static gyro; --paths only sets
      the runs drawn, the error (the half-width of the N the spread implies)
      does not move.
  psd --nperseg: white noise (numpy, sd 1, 10^6 samples at 1 kHz, SEEDS
      records); error = rms relative deviation of the density from the
      closed form 2 sigma^2 / fs over the bins and records.

Writes knobs.md (a Markdown table) and knobs.svg (error against seconds,
log-log, one marker series per option) into OUTDIR.

Usage: bench-knobs.py SENSORSCOPE [OUTDIR]
"""
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

S = sys.argv[1]
OUT = sys.argv[2] if len(sys.argv) > 2 else os.getcwd()
SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SAMPLES = os.path.join(SRC, "samples")
SEEDS = int(os.environ.get("SEEDS", "10"))
ALLAN_S = float(os.environ.get("ALLAN_DURATION", "1800"))
LONG_N = int(float(os.environ.get("LONG_N", "1e7")))

TRUTH = {"N": 0.15, "K": 30.0}  # deg/sqrt(h), deg/h/sqrt(h)
GYRO_INI = ("[sensor]\nrange = 250 deg/s\nnoise_density = 0.15 deg/sqrt(h)\n"
            "rate_random_walk = 30 deg/h/sqrt(h)\n")


def timed(argv):
    """(wall s, cpu s, stdout): cpu from os.wait4 of this child alone"""
    import time
    r, w = os.pipe()
    t0 = time.perf_counter()
    pid = os.fork()
    if pid == 0:
        os.close(r)
        os.dup2(w, 1)
        fd = os.open(os.devnull, os.O_WRONLY)
        os.dup2(fd, 2)
        try:
            os.execv(argv[0], argv)
        finally:
            os._exit(127)
    os.close(w)
    chunks = []
    while True:
        b = os.read(r, 1 << 16)
        if not b:
            break
        chunks.append(b)
    os.close(r)
    _, status, ru = os.wait4(pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("bench-knobs: %s: exit status %d" %
                 (" ".join(argv), os.waitstatus_to_exitcode(status)))
    return wall, ru.ru_utime + ru.ru_stime, b"".join(chunks)


def rms_rel(est, truth):
    e = np.asarray(est, dtype=float) / truth - 1.0
    e = e[np.isfinite(e)]
    return float(np.sqrt(np.mean(e * e))) if e.size else float("nan")


ROWS = []  # (knob, setting, wall, cpu, error, error_what, note)


def row(knob, setting, walls, cpus, err, what, note=""):
    ROWS.append((knob, setting, statistics.median(walls),
                 statistics.median(cpus), err, what, note))
    print("  %-28s %-22s wall %7.3f s cpu %7.3f s  %s %.4g %s" %
          (knob, setting, ROWS[-1][2], ROWS[-1][3], what, err, note),
          flush=True)


def allan_terms(js):
    no = json.loads(js)["channels"][0]["noise"]

    def est(t):
        v = (no.get(t) or {}).get("estimate")
        return float("nan") if v is None else float(v)
    k = no.get("K") or {}
    hw = float("nan")
    if k.get("value") and k.get("hi") is not None and k.get("lo") is not None:
        hw = (k["hi"] - k["lo"]) / 2 / k["value"]
    return est("N"), est("K"), hw


def bench_allan(work):
    ini = os.path.join(work, "gyro.ini")
    with open(ini, "w") as f:
        f.write(GYRO_INI)
    recs = []
    for s in range(SEEDS):
        p = os.path.join(work, "gyro%d.bin" % s)
        subprocess.run([S, "simulate", "--sensor", ini, "--rate", "100",
                        "--duration", "%gs" % ALLAN_S, "--binary", "f64",
                        "--seed", str(101 + s), "-o", p], check=True,
                       stdout=subprocess.DEVNULL)
        recs.append(p)
    cases = [("allan --taus", t, ["--taus", t])
             for t in ("octave", "decade", "dense", "all")]
    cases += [("allan --stride (--taus all)", "K=%d" % k,
               ["--taus", "all", "--stride", str(k)]) for k in (4, 16, 64)]
    # (no dense rows: --stride is refused on the octave and dense grids,
    # where it saved no time up to 10^8 samples and lowers the EDF)
    for knob, setting, opts in cases:
        walls, cpus, ns, ks, hws = [], [], [], [], []
        for p in recs:
            w, c, out = timed([S, "allan", "--format", "json"] + opts + [p])
            walls.append(w)
            cpus.append(c)
            n, k, hw = allan_terms(out)
            ns.append(n)
            ks.append(k)
            hws.append(hw)
        en, ek = rms_rel(ns, TRUTH["N"]), rms_rel(ks, TRUTH["K"])
        row(knob, setting, walls, cpus, ek, "K: rms rel. error",
            "K: printed half-width %.3f (median); N: rms rel. error %.4f"
            % (float(np.nanmedian(hws)), en))
    # the fit (1000 bootstrap replicates, a constant) against none
    walls, cpus = [], []
    for p in recs:
        w, c, _ = timed([S, "allan", "--format", "json", "--no-fit", p])
        walls.append(w)
        cpus.append(c)
    row("allan --no-fit", "no terms", walls, cpus, float("nan"),
        "no estimate")


def bench_stride_long(work):
    """--stride on a long record, --taus all, no fit: white noise, 10^7
    samples (raw f64, mapped in place), CSV (JSON of 5 million points is
    too big to parse here); error = the median over taus of the
    deviation's relative sd 1/sqrt(2 EDF) from the printed EDF.  Without a
    stride the grid beyond 2^22 points is computed by the definition, in
    time quadratic in the record (more than 300 s at 10^7): no such row."""
    p = os.path.join(work, "long.f64")
    np.random.default_rng(7).standard_normal(LONG_N).astype("<f8").tofile(p)
    e10 = round(math.log10(LONG_N))
    size = "1e%d" % e10 if 10 ** e10 == LONG_N else "%d" % LONG_N
    for k in (4, 16, 64):
        walls, cpus = [], []
        for _ in range(3):
            w, c, out = timed([S, "allan", "--raw", "f64:1:le", "-r", "1000",
                               "--taus", "all", "--no-fit", "--format",
                               "csv", "--stride", str(k), p])
            walls.append(w)
            cpus.append(c)
        # file,channel,deviation,unit,tau_s,m,terms,dev,dev_lo,dev_hi,edf,alpha
        edf = [float(ln.rsplit(b",", 2)[1])
               for ln in out.split(b"\n")[1:] if ln]
        del out
        e = statistics.median(1 / math.sqrt(2 * q) for q in edf)
        row("allan --stride (--taus all, %s, --no-fit)" % size,
            "K=%d" % k, walls, cpus, e, "deviation: median 1/sqrt(2 EDF)",
            "%d taus" % len(edf))
    # the decade grid, where the stride is kept: its taus keep the fused
    # pass at small tiles, so without a stride it is the slowest grid
    for k in (0, 4, 16):
        walls, cpus = [], []
        for _ in range(3):
            w, c, out = timed([S, "allan", "--raw", "f64:1:le", "-r", "1000",
                               "--taus", "decade", "--no-fit", "--format",
                               "json"] + (["--stride", str(k)] if k else [])
                              + [p])
            walls.append(w)
            cpus.append(c)
        pts = json.loads(out)["channels"][0]["points"]
        e = statistics.median(1 / math.sqrt(2 * q["edf"]) for q in pts)
        row("allan --stride (decade, %s, --no-fit)" % size,
            "K=%d" % k if k else "none", walls, cpus, e,
            "deviation: median 1/sqrt(2 EDF)")
    os.unlink(p)


def bench_adc(work):
    sensor = os.path.join(SAMPLES, "gyro-textbook-mems.ini")
    adc = os.path.join(SAMPLES, "adc-textbook-16bit.ini")
    for runs, dur in ((2, 600), (4, 600), (16, 600), (4, 3600)):
        walls, cpus, ses, vals = [], [], [], []
        for s in range(SEEDS):
            w, c, out = timed([S, "adc", "report", "--format", "json",
                               "--sensor", sensor, "--adc", adc,
                               "--monte-carlo", str(runs), "--mc-duration",
                               "%ds" % dur, "--seed", str(1 + 1000 * s)])
            walls.append(w)
            cpus.append(c)
            k = json.loads(out)["adcs"][0]["monte_carlo"]["B"]
            ses.append(k["se"] if k["se"] is not None else float("nan"))
            vals.append(k["value"] if k["value"] is not None
                        else float("nan"))
        row("adc report --monte-carlo x --mc-duration",
            "%d x %d s" % (runs, dur), walls, cpus,
            float(np.sqrt(np.nanmean(np.square(ses)))),
            "B ratio: printed se (rms over seeds)",
            "sd of the ratio over %d seeds %.3g" % (SEEDS, np.nanstd(vals, ddof=1)))


def bench_navsim(work):
    sensor = os.path.join(SAMPLES, "gyro-mems-250.ini")
    for runs in (10, 30, 100):
        w, c, out = timed([S, "navsim", "--sensor", sensor, "--runs",
                           str(runs), "--duration", "2min", "--format",
                           "json"])
        d = json.loads(out)
        rms, se = d["rms"]["north_m"][-1], d["rms_se"]["north_m"][-1]
        row("navsim --runs", "%d" % runs, [w], [c], se / rms,
            "north rms at 2 min: printed se / rms")


def bench_walk(work):
    rec = os.path.join(SAMPLES, "gyro-static.csv")
    for paths in (10, 100, 1000):
        fig = os.path.join(work, "fan.svg")
        w, c, out = timed([S, "walk", "--format", "json", "--plot", fig,
                           "--paths", str(paths), rec])
        im = json.loads(out)["channels"][0]["implied_N"][-1]
        row("walk --paths (--plot)", "%d" % paths, [w], [c],
            (im["hi"] - im["lo"]) / 2 / im["value"],
            "implied N at 60 s: half-width / value")


def bench_psd(work):
    fs, n = 1000.0, 10 ** 6
    recs = []
    for s in range(SEEDS):
        p = os.path.join(work, "white%d.f64" % s)
        np.random.default_rng(31 + s).standard_normal(n).astype("<f8") \
            .tofile(p)
        recs.append(p)
    for nper in (256, 4096, 65536):
        walls, cpus, dev = [], [], []
        for p in recs:
            w, c, out = timed([S, "psd", "--raw", "f64:1:le", "-r", "%g" % fs,
                               "-u", "m/s^2", "--format", "json",
                               "--nperseg", str(nper), p])
            walls.append(w)
            cpus.append(c)
            q = np.asarray(json.loads(out)["channels"][0]["psd"])[1:-1]
            dev.append(q / (2.0 / fs) - 1.0)
        e = float(np.sqrt(np.mean(np.concatenate(dev) ** 2)))
        row("psd --nperseg", "%d" % nper, walls, cpus, e,
            "density: rms rel. deviation from 2 sigma^2/fs")


def fmt(x, d=3):
    return "n/a" if not math.isfinite(x) else "%.*g" % (d, x)


def write_table(path):
    with open(path, "w") as f:
        f.write("| option | setting | wall s | CPU s | error | of what | also |\n")
        f.write("| --- | --- | ---: | ---: | ---: | --- | --- |\n")
        for k, s, w, c, e, what, note in ROWS:
            k = "`" + k.replace(" (", "` (", 1) if " (" in k else "`%s`" % k
            f.write("| %s | %s | %s | %s | %s | %s | %s |\n" %
                    (k, s, fmt(w), fmt(c), fmt(e), what, note))
    print("wrote " + path)


COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
          "#8c564b", "#17becf", "#e377c2", "#7f7f7f"]
MARKS = ["circle", "square", "diamond", "triangle"]


def write_svg(path):
    pts = [r for r in ROWS if math.isfinite(r[4]) and r[4] > 0]
    knobs = []
    for r in pts:
        if r[0] not in knobs:
            knobs.append(r[0])
    W, H, L, R, T, B = 760, 460, 70, 290, 20, 50
    x0 = math.floor(math.log10(min(r[2] for r in pts)))
    x1 = math.ceil(math.log10(max(r[2] for r in pts)))
    y0 = math.floor(math.log10(min(r[4] for r in pts)))
    y1 = math.ceil(math.log10(max(r[4] for r in pts)))

    def X(v):
        return L + (math.log10(v) - x0) / (x1 - x0) * (W - L - R)

    def Y(v):
        return H - B - (math.log10(v) - y0) / (y1 - y0) * (H - T - B)
    o = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" '
         'font-family="sans-serif" font-size="11">' % (W, H),
         '<rect width="100%" height="100%" fill="white"/>']
    for e in range(x0, x1 + 1):
        x = X(10.0 ** e)
        o.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>'
                 % (x, T, x, H - B))
        o.append('<text x="%.1f" y="%d" text-anchor="middle">1e%d</text>'
                 % (x, H - B + 14, e))
    for e in range(y0, y1 + 1):
        y = Y(10.0 ** e)
        o.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>'
                 % (L, y, W - R, y))
        o.append('<text x="%d" y="%.1f" text-anchor="end">1e%d</text>'
                 % (L - 4, y + 4, e))
    o.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" '
             'stroke="black"/>' % (L, T, W - L - R, H - T - B))
    o.append('<text x="%d" y="%d" text-anchor="middle">wall seconds of the '
             'whole command (median)</text>' % ((L + W - R) / 2, H - 12))
    o.append('<text transform="translate(16,%d) rotate(-90)" '
             'text-anchor="middle">relative error (see table)</text>'
             % ((T + H - B) / 2))
    for i, k in enumerate(knobs):
        col, m = COLORS[i % len(COLORS)], MARKS[i % len(MARKS)]
        ser = [r for r in pts if r[0] == k]
        o.append('<polyline fill="none" stroke="%s" points="%s"/>' %
                 (col, " ".join("%.1f,%.1f" % (X(r[2]), Y(r[4]))
                                for r in ser)))
        for r in ser:
            o.append(marker(m, X(r[2]), Y(r[4]), col, r[1]))
            o.append('<text x="%.1f" y="%.1f" font-size="9" fill="%s">%s'
                     '</text>' % (X(r[2]) + 6, Y(r[4]) - 5, col,
                                  r[1].split(" (")[0]))
        ly = T + 10 + 18 * i
        o.append(marker(m, W - R + 14, ly, col, k))
        o.append('<text x="%d" y="%d">%s</text>' %
                 (W - R + 24, ly + 4, k.replace("&", "&amp;")))
    o.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(o) + "\n")
    print("wrote " + path)


def marker(m, x, y, col, title):
    t = "<title>%s</title>" % title.replace("&", "&amp;")
    if m == "circle":
        return '<circle cx="%.1f" cy="%.1f" r="4" fill="%s">%s</circle>' % (
            x, y, col, t)
    if m == "square":
        return ('<rect x="%.1f" y="%.1f" width="8" height="8" fill="%s">'
                '%s</rect>' % (x - 4, y - 4, col, t))
    if m == "diamond":
        return ('<polygon points="%.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f" '
                'fill="%s">%s</polygon>' % (x, y - 5, x + 5, y, x, y + 5,
                                             x - 5, y, col, t))
    return ('<polygon points="%.1f,%.1f %.1f,%.1f %.1f,%.1f" fill="%s">%s'
            '</polygon>' % (x, y - 5, x + 5, y + 4, x - 5, y + 4, col, t))


def main():
    os.makedirs(OUT, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="bench-knobs.") as work:
        print("allan on %d simulated records of %g s at 100 Hz" %
              (SEEDS, ALLAN_S), flush=True)
        bench_allan(work)
        bench_stride_long(work)
        print("adc report, %d seeds" % SEEDS, flush=True)
        bench_adc(work)
        print("navsim, walk, psd", flush=True)
        bench_navsim(work)
        bench_walk(work)
        bench_psd(work)
    write_table(os.path.join(OUT, "knobs.md"))
    write_svg(os.path.join(OUT, "knobs.svg"))


if __name__ == "__main__":
    main()
