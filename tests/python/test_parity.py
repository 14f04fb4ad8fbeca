# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python module refuses and warns exactly where the command does (TAP
on stdout), run by tests/py-parity.sh.  Each case runs one bad input
through `sensorscope` and through the module: both must refuse (with the
same reason), both warn (with the same warnings), or both accept without
a word.  Reasons are compared after taking off what differs by nature:
the "sensorscope: " prefix and the "(see ... --help)" hint, the command or
function name, the file and channel (the command) or the array argument
"x: " (Python), "--" before an option name, and a trailing ", got VALUE"
(Python names the value the caller passed).  Where the command's reader
refuses a cell and Python gets the array, the two messages differ in
wording and must both match a pattern instead.

Also: a misaligned or byte-swapped array is copied (never read in place)
and gives the aligned array's numbers."""

import os
import re
import subprocess
import tempfile
import warnings

import numpy as np

import sensorscope as ss

SSCOPE = os.environ["SSCOPE"]
SRC = os.environ["top_srcdir"]
SAMPLES = os.path.join(SRC, "samples")
n_test = 0
failed = 0


def ok(cond, desc, detail=""):
    global n_test, failed
    n_test += 1
    print("%s %d - %s" % ("ok" if cond else "not ok", n_test, desc))
    if not cond:
        failed += 1
        for line in str(detail).splitlines()[:20]:
            print("# " + line)


def write_csv(path, values, rate=100.0, unit="rad/s", time=True):
    with open(path, "w") as f:
        f.write(("time [s],gx [%s]\n" % unit) if time else
                "# rate: %g Hz\ngx [%s]\n" % (rate, unit))
        for i, v in enumerate(values):
            cell = "nan" if np.isnan(v) else "inf" if np.isinf(v) else \
                repr(float(v))
            f.write(("%.6f,%s\n" % (i / rate, cell)) if time else
                    cell + "\n")


def norm_cli(line, path):
    """(kind, reason) of one line of the command's stderr."""
    m = re.match(r"^sensorscope: ([a-z ]+?): (warning: )?(.*)$", line)
    if not m:
        return None
    kind = "warn" if m.group(2) else "refuse"
    why = re.sub(r" \(see 'sensorscope [a-z ]+ --help'\)$", "", m.group(3))
    for p in (path, os.path.basename(path)):
        if why.startswith(p + ": "):
            why = why[len(p) + 2:]
    why = re.sub(r"^(channel )?gx: ", "", why)
    why = re.sub(r"--([a-z][a-z-]*)",
                 lambda k: k.group(1).replace("-", "_"), why)
    return kind, why


def norm_py(msg, func):
    why = msg
    if why.startswith(func + ": "):
        why = why[len(func) + 2:]
    why = re.sub(r"^x: ", "", why)
    why = re.sub(r", got .*$", "", why)
    return why


def run_cli(args, path):
    r = subprocess.run([SSCOPE] + args, capture_output=True, text=True)
    lines = [norm_cli(x, path) for x in r.stderr.splitlines()]
    lines = [x for x in lines if x]
    if r.returncode:
        return "refuse", [w for k, w in lines if k == "refuse"], r.returncode
    warns = [w for k, w in lines if k == "warn"]
    return ("warn" if warns else "ok"), warns, 0


def run_py(call, func):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            call()
        except ss.Error as e:
            return "refuse", [norm_py(str(e), func)], e
        except Exception as e:  # not the module's kind of error
            return "crash", ["%s: %s" % (type(e).__name__, e)], e
    warns = [norm_py(str(x.message), func) for x in w
             if issubclass(x.category, RuntimeWarning)]
    return ("warn" if warns else "ok"), warns, None


def case(desc, cli_args, path, func, call, like=None, usage=None):
    """Run a case; like: a pattern both reasons must match instead of
    being equal; usage: the command's exit code 2 (a bad option) goes with
    Python's ArgumentError (also a ValueError), exit 1 with ss.Error."""
    ck, cw, rc = run_cli(cli_args, path)
    pk, pw, exc = run_py(call, func)
    detail = "command: %s %s\npython:  %s %s" % (ck, cw, pk, pw)
    if ck != pk:
        ok(False, "%s: command %s, python %s" % (desc, ck, pk), detail)
        return
    if like is not None:
        same = all(re.search(like, w) for w in cw + pw) and \
            len(cw) == len(pw)
    else:
        same = sorted(cw) == sorted(pw)
    if ck == "refuse":
        arg_error = getattr(ss, "ArgumentError", ())
        same &= (rc == 2) == isinstance(exc, arg_error) and \
            (rc == 2) == isinstance(exc, ValueError)
    ok(same, "%s: both %s%s" % (desc, {"refuse": "refuse", "warn": "warn",
                                       "ok": "accept"}[ck],
                                ", same reason" if ck != "ok" else ""),
       detail)


tmp = tempfile.TemporaryDirectory()
D = tmp.name
rng = np.random.default_rng(2385)
white = rng.normal(0, 0.01, 4000)
files = {}


def make(name, values, **kw):
    path = os.path.join(D, name + ".csv")
    write_csv(path, values, **kw)
    files[name] = path
    return path


make("white", white)
make("const", np.full(4000, 0.25))
nan1 = white.copy()
nan1[97] = np.nan
make("nan", nan1)
gap97 = rng.normal(0, 0.01, 9700)
gap97[::97] = np.nan
make("gap97", gap97)
alt = white[:400].copy()
alt[::2] = np.nan
make("alt", alt)
inf = white[:50].copy()
inf[7] = np.inf
make("inf", inf, time=False)
make("one", white[:1], time=False)


def data(name):
    """The channel and rate Python gets from the same file."""
    if name == "inf":
        return inf, 100.0
    cap = ss.load(files[name], allow_nan=True)
    return np.array(cap["gx"]), cap.rate_hz


# ---------------------------------------------------------------- allan
W = files["white"]
x, fs = data("white")
case("allan: accepted", ["allan", "-q", W], W, "allan",
     lambda: ss.allan(x, fs))
for cli, kw in ((["--ci", "95"], {"ci": 95}), (["--ci", "0"], {"ci": 0}),
                (["--ci", "1"], {"ci": 1}), (["--ci", "-1"], {"ci": -1}),
                (["--ci", "nan"], {"ci": float("nan")}),
                (["--dev", "xdev"], {"dev": "xdev"}),
                (["--taus", "weekly"], {"taus": "weekly"}),
                (["--input", "phase"], {"input": "phase"}),
                (["--noise-type", "pink"], {"noise_type": "pink"}),
                (["-r", "0"], {"rate": 0}), (["-r", "-5"], {"rate": -5}),
                (["-r", "inf"], {"rate": float("inf")})):
    kw = dict(kw)
    rate = kw.pop("rate", fs)
    # (Python names what only it takes: taus in s, allantools' data_type)
    like = {"taus": r"^taus: 'weekly' is not dense, octave, decade or all",
            "input": r"^input: 'phase' is not rate or angle"}.get(
                next(iter(kw), None))
    case("allan %s" % " ".join(cli), ["allan"] + cli + [W], W, "allan",
         lambda kw=kw, rate=rate: ss.allan(x, rate, **kw), like=like)
c, fs = data("const")
case("allan: constant data", ["allan", files["const"]], files["const"],
     "allan", lambda: ss.allan(c, fs))
y, fs = data("nan")
case("allan: a NaN without allow_nan", ["allan", files["nan"]], files["nan"],
     "allan", lambda: ss.allan(y, fs), like=r"NaN.*allow[-_]nan")
g, fs = data("gap97")
case("allan: a NaN every 97 samples", ["allan", "--allow-nan",
                                       files["gap97"]],
     files["gap97"], "allan", lambda: ss.allan(g, fs, allow_nan=True))
for dv in ("mdev", "ohdev", "totdev"):
    case("allan --dev %s: a NaN every 97 samples" % dv,
         ["allan", "--allow-nan", "--no-fit", "--dev", dv, files["gap97"]],
         files["gap97"], "allan",
         lambda dv=dv: ss.allan(g, fs, dev=dv, fit=False, allow_nan=True))
a, fs = data("alt")
case("allan: every other sample NaN", ["allan", "--allow-nan", files["alt"]],
     files["alt"], "allan", lambda: ss.allan(a, fs, allow_nan=True))
i, fs = data("inf")
case("allan: an infinite sample", ["allan", files["inf"]], files["inf"],
     "allan", lambda: ss.allan(i, fs), like=r"infinite")
o, fs = data("one")
case("allan: one sample", ["allan", files["one"]], files["one"], "allan",
     lambda: ss.allan(o, fs))

# ---------------------------------------------------------------- psd
x, fs = data("white")
case("psd: accepted", ["psd", W], W, "psd", lambda: ss.psd(x, fs))
for cli, kw in ((["--nperseg", "0"], {"nperseg": 0}),
                (["--nperseg", "-3"], {"nperseg": -3}),
                (["--nperseg", "2.5"], {"nperseg": 2.5}),
                (["--nperseg", "5000"], {"nperseg": 5000}),
                (["--overlap", "1"], {"overlap": 1}),
                (["--overlap", "-0.1"], {"overlap": -0.1}),
                (["--nfft", "100"], {"nfft": 100}),
                (["--nfft", "0"], {"nfft": 0}),
                (["--window", "kaiser"], {"window": "kaiser"}),
                (["--detrend", "quadratic"], {"detrend": "quadratic"}),
                (["--scaling", "power"], {"scaling": "power"}),
                (["-r", "0"], {"rate": 0})):
    kw = dict(kw)
    rate = kw.pop("rate", fs)
    case("psd %s" % " ".join(cli), ["psd"] + cli + [W], W, "psd",
         lambda kw=kw, rate=rate: ss.psd(x, rate, **kw))
c, fs = data("const")
case("psd: constant data", ["psd", files["const"]], files["const"], "psd",
     lambda: ss.psd(c, fs))
y, fs = data("nan")
case("psd: a NaN without allow_nan", ["psd", files["nan"]], files["nan"],
     "psd", lambda: ss.psd(y, fs), like=r"NaN.*allow[-_]nan")
case("psd: a NaN with allow_nan", ["psd", "--allow-nan", files["nan"]],
     files["nan"], "psd", lambda: ss.psd(y, fs, allow_nan=True))
g, fs = data("gap97")
case("psd: a NaN in every segment", ["psd", "--allow-nan", files["gap97"]],
     files["gap97"], "psd", lambda: ss.psd(g, fs, allow_nan=True))
i, fs = data("inf")
case("psd: an infinite sample", ["psd", files["inf"]], files["inf"], "psd",
     lambda: ss.psd(i, fs), like=r"infinite")

# ---------------------------------------------------------------- load
raw = os.path.join(SAMPLES, "imu-raw.bin")
for cli, kw in ((["--scale", "0"], {"scale": 0}),
                (["--scale", "nan"], {"scale": float("nan")}),
                (["--offset", "nan"], {"offset": float("nan")}),
                (["--scale", "-2"], {"scale": -2}),
                (["-r", "0"], {"rate": 0}), (["-r", "-1"], {"rate": -1})):
    case("load %s" % " ".join(cli),
         ["info", "--raw", "i16:6:le"] + cli + [raw], raw, "load",
         lambda kw=kw: ss.load(raw, raw="i16:6:le", **kw))
case("load --raw foo", ["info", "--raw", "foo", raw], raw, "load",
     lambda: ss.load(raw, raw="foo"))

# ---------------------------------------------------------------- simulate
spec = os.path.join(SAMPLES, "gyro-mems-250.ini")
out = os.path.join(D, "sim.csv")
for cli, kw in ((["--axes", "0"], {"axes": 0}),
                (["--axes", "-1"], {"axes": -1}),
                (["--axes", "65"], {"axes": 65}),
                (["--axes", "2.5"], {"axes": 2.5}),
                (["--seed", "-1"], {"seed": -1}),
                (["--duration", "0"], {"duration": 0}),
                (["--duration", "0.001"], {"duration": 0.001}),
                (["--rate", "0"], {"rate": 0})):
    kw = dict(kw)
    args = {"rate": 100, "duration": 1}
    args.update(kw)
    base = ["simulate", "--sensor", spec, "-o", out]
    if "--rate" not in cli:
        base += ["--rate", "100"]
    if "--duration" not in cli:
        base += ["--duration", "1"]
    case("simulate %s" % " ".join(cli), base + cli, spec, "simulate",
         lambda args=args: ss.simulate(spec, args.pop("rate"),
                                       args.pop("duration"), **args))

# ---------------------------------------------------------------- tempbias
th = os.path.join(SAMPLES, "accel-thermal.csv")
cap = ss.load(th)
ch = next(iter(cap))
for order in ("-1", "5", "9", "2.5", "x"):
    val = {"x": "x", "2.5": 2.5}.get(order, None)
    val = int(order) if val is None else val
    case("tempbias --order %s" % order,
         ["tempbias", "-c", ch, "--order", order, th], th, "tempbias",
         lambda val=val: ss.tempbias(cap[ch], cap.temp_degc, cap.rate_hz,
                                     order=val))

# ---------------------------------------------------------------- arrays
# a misaligned float64 array (a byte offset of 1) and a byte-swapped one
# are copied, not read in place, and give the aligned array's numbers
x, fs = data("white")
buf = np.zeros(x.size * 8 + 1, dtype=np.uint8)
mis = np.frombuffer(buf.data, dtype=np.float64, count=x.size, offset=1)
mis[:] = x
ok(not mis.flags.aligned and ss._vector(mis)[3] is not mis and
   ss._vector(x)[3] is x,
   "arrays: a misaligned array is copied, an aligned one read in place")
sw = x.astype(">f8")
r0 = ss.allan(x, fs, fit=False)
ok(all(np.array_equal(ss.allan(v, fs, fit=False).dev, r0.dev)
       for v in (mis, sw)) and
   np.array_equal(ss.psd(mis, fs).psd, ss.psd(x, fs).psd),
   "arrays: misaligned and byte-swapped arrays give the same numbers")
st = np.repeat(x, 3)[::3]
d3 = ss.allan(st, fs, fit=False).dev
# (equal up to the last bits of the threads' partial sums)
ok(ss._vector(st)[1] == 3 and ss._vector(st)[3] is st and
   np.max(np.abs(d3 / r0.dev - 1)) < 1e-12,
   "arrays: a strided view is read in place with its stride")
t2 = np.repeat(cap.temp_degc, 2)[::2]
ok(ss.tempbias(cap[ch], t2, cap.rate_hz)["coefficients"] ==
   ss.tempbias(cap[ch], cap.temp_degc, cap.rate_hz)["coefficients"],
   "arrays: a strided temperature array is copied to the contiguous one "
   "the library needs")

# ---------------------------------------------------------------- taus
# Python only (the command takes grid names): nothing rounded, nothing
# dropped without a word
x, fs = data("white")
for kw, pat in (({"m": [2.5]}, r"^allan: m: 2\.5 is not an averaging factor"),
                ({"taus": [0.015]}, r"^allan: taus: 0\.015 s is not a whole "
                 r"number of samples at 100 Hz \(1\.5\); averaging factors "
                 r"go in m="),
                ({"taus": []}, r"^allan: taus: empty"),
                ({"m": []}, r"^allan: m: empty"),
                ({"taus": [0]}, r"^allan: taus: 0 is not positive"),
                ({"taus": [1.0], "m": [1]}, r"^allan: m: give taus .* or m "
                 r".*, not both"),
                ({"m": [10 ** 6]}, r"^allan: m: every averaging factor "
                 r"exceeds the record's limit \(m <= 2000"),
                ({"taus": [10 ** 4]}, r"^allan: taus: every averaging factor "
                 r"exceeds the record's limit \(m <= 2000")):
    try:
        ss.allan(x, fs, **kw)
        ok(False, "%r refused" % (kw,))
    except ss.ArgumentError as e:
        ok(re.search(pat, str(e)) is not None,
           "%r refused: %s" % (kw, e), e)
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter("always")
    r = ss.allan(x, fs, taus=[0.02, 0.03, 10.0 ** 4], fit=False)
ok(list(r.m) == [2, 3] and len(w) == 1 and
   "averaging factor 1000000 exceeds the record's limit" in
   str(w[0].message) and "left out" in str(w[0].message),
   "taus in s: 0.02 s is m = 2, 0.03 s m = 3, a tau beyond the record is "
   "left out with a warning", [str(k.message) for k in w])
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter("always")
    r = ss.allan(x, fs, m=[2, 3, 10 ** 6], fit=False)
ok(list(r.m) == [2, 3] and len(w) == 1 and
   "m: averaging factor 1000000 exceeds" in str(w[0].message),
   "m: factors 2, 3 kept, one beyond the record left out with a warning",
   [str(k.message) for k in w])
# whole seconds are seconds, not factors (the old trap: taus=[1, 10])
r = ss.allan(x, fs, taus=[1, 10], fit=False)
ok(list(r.m) == [100, 1000] and np.allclose(r.tau_s, [1, 10]),
   "taus=[1, 10] at 100 Hz are 1 s and 10 s (m = 100, 1000)", list(r.m))

print("1..%d" % n_test)
tmp.cleanup()
