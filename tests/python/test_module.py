# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of the Python module (TAP on stdout), run by tests/py-module.sh:
the ctypes layouts against the C compiler's, every function against the
CLI's JSON on the bundled samples, OADEV against an allantools-style numpy
reference, zero-copy inputs, containers, and errors as exceptions."""

import json
import shutil
import math
import os
import subprocess
import sys
import tempfile
import warnings

import numpy as np

import sensorscope as ss
from sensorscope import _capi

SSCOPE = os.environ["SSCOPE"]
SRC = os.environ["top_srcdir"]
BUILD = os.environ["top_builddir"]
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


def cli(*args):
    r = subprocess.run([SSCOPE] + list(args), capture_output=True, text=True)
    if r.returncode:
        raise RuntimeError(r.stderr)
    return json.loads(r.stdout)


def conv(v, frm, to):
    r = _capi.C.c_double()
    assert _capi.convert(v, frm.encode(), to.encode(), _capi.C.byref(r)) == 0
    return r.value


def rel(a, b):
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300)))


# ---------------------------------------------------------------- layouts
lay = subprocess.run([os.path.join(BUILD, "tests", "py-layout")],
                     capture_output=True, text=True, check=True).stdout
c_lay = dict(line.rsplit(" ", 1) for line in lay.splitlines())
bad = []
for cname, cls in _capi.STRUCTS.items():
    if int(c_lay[cname]) != _capi.C.sizeof(cls):
        bad.append("%s: size C %s, ctypes %d" % (cname, c_lay[cname],
                                                 _capi.C.sizeof(cls)))
    for f in cls._fields_:
        off = getattr(cls, f[0]).offset
        if int(c_lay["%s.%s" % (cname, f[0])]) != off:
            bad.append("%s.%s: C %s, ctypes %d" % (
                cname, f[0], c_lay["%s.%s" % (cname, f[0])], off))
ok(not bad, "ctypes layouts equal the C compiler's (%d structures)" %
   len(_capi.STRUCTS), "\n".join(bad))

# ---------------------------------------------------------------- load
gyro = os.path.join(SAMPLES, "gyro-static.csv")
cap = ss.load(gyro)
info = cli("info", "--format", "json", gyro)
ok(cap.n == info["rows"] and cap.rate_hz == info["rate_hz"] and
   list(cap) == [c["name"] for c in info["channels"]],
   "load: rows, rate and channels as info's JSON")
ok(cap.rate_source == "header" and cap.rate_note is None,
   "load: the rate from the header comment, no note")
with tempfile.TemporaryDirectory() as d:
    bad_rate = os.path.join(d, "rate.csv")
    with open(bad_rate, "w") as f:
        f.write("# rate: 0 Hz\ngx\n1\n2\n3\n")
    c0 = ss.load(bad_rate)
    j0 = cli("info", "--format", "json", bad_rate)
    ok(c0.rate_hz is None and c0.rate_note == j0["rate_note"] and
       c0.rate_note.startswith("line 1: '# rate: 0 Hz' is not a sample rate"),
       "load: a rate comment that gives no rate, its note as info's JSON")
means = [conv(float(np.mean(cap[c["name"]])), "rad/s", c["unit"])
         for c in info["channels"]]
ok(rel(means, [c["mean"] for c in info["channels"]]) < 1e-9,
   "load: means (SI) equal info's means in the channel unit",
   (means, [c["mean"] for c in info["channels"]]))
ok(cap.units["gx"] == "deg/s" and cap.quantities["gx"] == "angular rate",
   "load: unit labels and quantities")
gx = cap["gx"]
ok(not gx.flags.owndata and not gx.flags.writeable,
   "load: channels are read-only views of the library's arrays")
del cap
ok(abs(float(np.sum(gx)) - float(np.sum(np.array(gx)))) == 0,
   "load: a view outlives its Capture object")

# ---------------------------------------------------------------- allan
j = cli("allan", "--format", "json", "-c", "gx", gyro)["channels"][0]
cap = ss.load(gyro, columns="gx")
r = ss.allan(cap["gx"], cap.rate_hz, unit="rad/s")
dev_cli = [conv(p["dev"], j["dev_unit"], "rad/s") for p in j["points"]]
ok(len(r.dev) == len(j["points"]) and rel(r.tau_s, [p["tau_s"] for p in
                                                    j["points"]]) == 0,
   "allan: the taus of the CLI")
ok(rel(r.dev, dev_cli) < 1e-12, "allan: deviations equal the CLI's JSON",
   rel(r.dev, dev_cli))
ok(rel(r.dev_lo, [conv(p["dev_lo"], j["dev_unit"], "rad/s")
                  for p in j["points"]]) < 1e-12 and
   rel(r.edf, [p["edf"] for p in j["points"]]) < 1e-12,
   "allan: intervals and EDF equal the CLI's")
terms_ok = True
detail = []
for t in "NBK":
    c = j["noise"][t]
    if c["fitted"] != r.noise[t].fitted or (
            c["fitted"] and rel(r.noise[t].value, c["si"]) > 1e-12):
        terms_ok = False
        detail.append((t, c, r.noise[t]))
ok(terms_ok, "allan: the noise fit (N, B, K in SI) equals the CLI's", detail)
ok(r.noise["N"].si_unit == "rad/s/sqrt(Hz)", "allan: SI units of the terms")
v, lo, hi = r.noise["N"].to("deg/sqrt(h)")
ok(abs(v - j["noise"]["N"]["value"]) <= 1e-9 * abs(v),
   "allan: N converted to deg/sqrt(h) equals the CLI's value")

# allantools-style reference: phase = cumsum / rate, second differences
rng = np.random.default_rng(7)
x = rng.normal(0, 2.385, 100000)
rate = 50.0


def oadev_ref(y, rate, m):
    phase = np.concatenate(([0.0], np.cumsum(y))) / rate
    tau = m / rate
    d = phase[2 * m:] - 2 * phase[m:-m] + phase[:-2 * m]
    return math.sqrt(np.sum(d * d) / (2 * len(d) * tau * tau))


r = ss.allan(x, rate, taus="octave", fit=False)
ref = [oadev_ref(x, rate, int(m)) for m in r.m]
ok(rel(r.dev, ref) < 1e-9, "allan: OADEV equals an allantools-style numpy "
   "reference on %d taus" % len(ref), rel(r.dev, ref))
rf = ss.allan(x, rate, taus="octave")
ok(r.noise is None and r.fit_error is None and rf.noise is not None and
   np.array_equal(r.dev, rf.dev) and np.array_equal(r.edf, rf.edf),
   "allan: fit=False (no fit computed) gives the same deviations, no terms")
# zero copy and strides
big = rng.normal(size=200001)
a1 = ss.allan(big[::2], 10.0, taus="octave", fit=False)
a2 = ss.allan(np.ascontiguousarray(big[::2]), 10.0, taus="octave", fit=False)
# equal up to the last bits of the threads' partial sums
ok(rel(a1.dev, a2.dev) < 1e-12, "allan: a strided view reads in place "
   "and equals the contiguous copy", rel(a1.dev, a2.dev))
p, stride, n, keep = ss._vector(big[::3])
ok(keep.base is big or keep is big or (stride == 3 and n == 66667),
   "allan: float64 strided input is not copied (stride %d)" % stride)
r = ss.allan(np.arange(1000, dtype=np.int16).astype(float) * 0 + 1, 10.0,
             taus="octave")
ok(r.dev[0] == 0, "allan: a constant gives zero deviation")

# ---------------------------------------------------------------- psd
vib = os.path.join(SAMPLES, "vibration.csv")
j = cli("psd", "--format", "json", "--nperseg", "1024", vib)["channels"][0]
cap = ss.load(vib)
name = j["name"]
s = ss.psd(cap[name], cap.rate_hz, nperseg=1024)
unit = j["unit"]
scale = conv(1.0, cap.units[name], "m/s^2") if cap.quantities[name] == \
    "acceleration" else 1.0
ok(rel(s.frequency_hz[1:], j["frequency_hz"][1:]) < 1e-12 and
   rel(s.psd[1:] / scale ** 2, j["psd"][1:]) < 1e-9,
   "psd: equals the CLI's JSON (%s, %d bins)" % (name, len(s.psd)),
   rel(s.psd[1:] / scale ** 2, j["psd"][1:]))
# a record shorter than nperseg: one segment of the record, the overlap
# recomputed for it, as the command (which says nperseg 100, noverlap 50)
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter("always")
    s100 = ss.psd(np.asarray(cap[name])[:100], cap.rate_hz)
ok(s100.nperseg == 100 and s100.noverlap == 50 and s100.n_segments == 1 and
   any("longer than the record" in str(x.message) for x in w),
   "psd: nperseg 256 on 100 samples is one segment of 100, with a warning",
   (s100.nperseg, s100.noverlap, [str(x.message) for x in w]))
try:
    from scipy.signal import welch
    f, pxx = welch(np.asarray(cap[name]), fs=cap.rate_hz, nperseg=1024)
    ok(rel(s.psd[1:], pxx[1:]) < 1e-10, "psd: equals scipy.signal.welch")
except ImportError:
    ok(True, "psd: scipy not installed # SKIP")

# ---------------------------------------------------------------- simulate
spec = os.path.join(SAMPLES, "gyro-mems-250.ini")
if not os.path.exists(spec):
    specs = [os.path.join(SAMPLES, "specs", f)
             for f in sorted(os.listdir(os.path.join(SAMPLES, "specs")))
             if f.endswith(".ini")] if os.path.isdir(
        os.path.join(SAMPLES, "specs")) else []
    spec = specs[0] if specs else None
if spec:
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "sim.csv")
        subprocess.run([SSCOPE, "simulate", "--sensor", spec, "--rate", "100",
                        "--duration", "20", "--seed", "5", "--axes", "2",
                        "--digits", "17", "-o", out], check=True)
        sim = ss.simulate(spec, 100, 20, seed=5, axes=2)
        ref = ss.load(out)
        names = [k for k in sim if k != "t"]
        ok(names == list(ref) and all(
            rel(sim[k], ref[k]) < 1e-12 for k in names),
           "simulate: the same samples as `sensorscope simulate` (%s)" %
           os.path.basename(spec),
           [(k, rel(sim[k], ref[k])) for k in names if k in ref])
else:
    ok(True, "simulate: no sensor spec among the samples # SKIP")
for arg, why in ((SAMPLES, "is a directory"),
                 (os.path.join(SAMPLES, "no-such.ini"),
                  "no such file or directory")):
    try:
        ss.simulate(arg, 100, 1)
        ok(False, "simulate refuses a sensor that " + why)
    except ss.Error as e:
        ok(str(e) == "simulate: sensor: %s: %s" % (arg, why),
           "simulate names the argument: %s" % why, str(e))

# ---------------------------------------------------------------- tempbias
th = os.path.join(SAMPLES, "accel-thermal.csv")
j = cli("tempbias", "--format", "json", th)["channels"][0]
cap = ss.load(th)
tb = ss.tempbias(cap[j["channel"]], cap.temp_degc, cap.rate_hz)
u = conv(1.0, j["unit"], "m/s^2")
ok(tb["order"] == j["fit"]["order"] and
   abs(tb["ref_temp_degc"] - j["fit"]["ref_temp_degc"]) < 1e-12 and
   rel(np.array(tb["coefficients"]) / u, j["fit"]["coefficients"]) < 1e-12
   and rel(tb["residual_rms"] / u, j["fit"]["residual_rms"]) < 1e-12,
   "tempbias: order, T_ref, coefficients and residual equal the CLI's JSON "
   "(%s)" % j["channel"], (tb["coefficients"], j["fit"]))
ok(len(tb["table"]) == len(j["table"]) and
   rel([b / u for _, b in tb["table"]], [r["bias"] for r in j["table"]])
   < 1e-12, "tempbias: the compensation table equals the CLI's")

# ---------------------------------------------------------------- calib
mp = os.path.join(SAMPLES, "imu-multipose.csv")
j = cli("calib", "accel", "--format", "json", mp)["triads"][0]
cap = ss.load(mp)
cb = ss.calib(*(cap[c] for c in j["channels"]), cap.rate_hz)
g = conv(1.0, j["input_unit"], "m/s^2")
ok(cb["poses"] == j.get("poses", cb["poses"]) and
   rel(np.array(cb["bias"]) / g, j["bias"]) < 1e-6 and
   rel(np.array(cb["scale"]) * g, j["scale"]) < 1e-6 and
   np.max(np.abs(np.array(cb["misalignment"]) -
                 np.array(j["misalignment"]))) < 1e-7,
   "calib: bias, scale and misalignment equal the CLI's JSON (input in %s, "
   "here SI)" % j["input_unit"], (cb, j))

# ---------------------------------------------------------------- adc
sensor = os.path.join(SAMPLES, "gyro-textbook-quiet.ini")
adcs = [os.path.join(SAMPLES, f) for f in
        ("adc-textbook-16bit.ini", "adc-textbook-18bit.ini")]
j = cli("adc", "report", "--format", "json", "--sensor", sensor,
        "--adc", adcs[0], "--adc", adcs[1])["adcs"]
rep = ss.adc_report(sensor, adcs)
ok(len(rep) == 2 and all(
    r["name"] == c["name"] and r["bits"] == c["bits"] and
    rel(r["lsb"], c["lsb"]["si"]) < 1e-12 and r["dithered"] == c["dithered"]
    and r["min_bits"] == c["min_bits"] for r, c in zip(rep, j)),
   "adc_report: LSB, dithering and minimum word length equal the CLI's",
   (rep, j))
ok(all(r["verdict"] == c["verdict"] for r, c in zip(rep, j)),
   "adc_report: verdicts equal the CLI's (%s)" %
   ", ".join(r["verdict"] for r in rep))

with tempfile.TemporaryDirectory() as d:
    nd = os.path.join(d, "nodrift.ini")
    with open(nd, "w") as f:
        f.write("[adc]\nbits = 16\nrange = -300:300 deg/s\nrate = 1kHz\n")
    t = ss.adc_report(sensor, nd)[0]["terms"]
    ok(t["offset_drift"]["value"] is None and
       t["offset_drift"]["verdict"] == "info" and
       t["scale_drift"]["value"] is None,
       "adc_report: a drift the spec does not give is None ('info'), not 0",
       t)

# ---------------------------------------------------------------- containers
with tempfile.TemporaryDirectory() as d:
    subprocess.run([os.path.join(BUILD, "tests", "gen-ros"), d, "200", "10"],
                   check=True)
    csv = ss.load(os.path.join(d, "imu.csv"))
    same = True
    for f in ("imu-none.bag", "imu-bz2.bag", "imu-lz4.bag", "imu-zstd.mcap",
              "imu-lz4.mcap", "rosbag2-mcap"):
        c = ss.load(os.path.join(d, f))
        same &= all(np.array_equal(c[k], csv[k]) for k in csv) and \
            np.array_equal(c.time_s, csv.time_s)
    ok(same, "load: bags and MCAP give the CSV's channels and stamps bit "
       "for bit")
    c = ss.load(os.path.join(d, "imu-lz4.bag"))
    ok(c.format == "ROS 1 bag v2.0 (lz4 chunks)" and
       [t["name"] for t in c.topics if t["selected"]] ==
       ["/imu/temperature", "/imu/data"] and
       abs(float(c.receive_s[10] - c.time_s[10]) - 0.0015) < 1e-9 and
       c.temp_degc is not None,
       "load: format, topics, receive times and temperature of a bag")
    try:
        ss.load(os.path.join(d, "two-imu.mcap"))
        ok(False, "load: two IMU topics raise")
    except ss.Error as e:
        ok(e.code == -22 and "--topic" in str(e) and "/imu1/data" in str(e),
           "load: two IMU topics raise ss.Error naming them", e)
    c = ss.load(os.path.join(d, "two-imu.mcap"), topic="/imu1/data")
    ok(c.n == 2000, "load: topic= selects one")
    np.save(os.path.join(d, "x.npy"), np.asfortranarray(
        np.arange(30.0).reshape(10, 3)))
    c = ss.load(os.path.join(d, "x.npy"), rate=10, units="deg/s")
    ok(list(c) == ["col1", "col2", "col3"] and c["col2"][3] ==
       conv(10.0, "deg/s", "rad/s"), "load: a Fortran-order npy")
    with open(os.path.join(d, "ns.csv"), "w") as f:
        f.write("t,gx\n")
        for i in range(50):
            f.write("%d,%d\n" % (1700000000000000000 + 5000000 * i, i % 3))
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        ss.load(os.path.join(d, "ns.csv"))
    ok(any("stamps are in ns the rate is 200 Hz" in str(x.message)
           for x in w), "load: ns read as s gives a RuntimeWarning",
       [str(x.message) for x in w])

# ---------------------------------------------------------------- adequacy
g = ss.load(os.path.join(SAMPLES, "gyro-static.csv"))
j = cli("allan", "--format", "json", "-c", "gx",
        os.path.join(SAMPLES, "gyro-static.csv"))["channels"][0]["adequacy"]
a = ss.adequacy(g["gx"], g.rate_hz, unit="rad/s")
ok(a.verdict == j["verdict"] and a.still == j["still"]
   and a.contrast == j["contrast"] and a.established == j["established"]
   and [f["message"] for f in a.findings] ==
   [f["message"] for f in j["findings"]],
   "adequacy: the CLI's verdict, contrast and findings (gyro-static gx)",
   "%s %s" % (a.findings, j["findings"]))
dv = a.davar
ok(dv is not None and dv["dev"].shape == (len(j["davar"]["t_s"]),
                                          len(j["davar"]["tau_s"]))
   and rel(dv["dev"][3] * 180 / math.pi, j["davar"]["dev"][3]) < 1e-12,
   "adequacy: the DAVAR map equals the CLI's (window 4, deg/s)")
rt = ss.load(os.path.join(SAMPLES, "gyro-ratetable.csv"), columns="gx")
a = ss.adequacy(rt["gx"], rt.rate_hz)
ok(a.verdict == "not_valid" and a.still is False
   and a.findings[0]["cause"] == "moves"
   and a.doubtful == ["Q", "N", "B", "K", "R"],
   "adequacy: the rate-table record moves: no term valid",
   a.findings[:1])
try:
    ss.adequacy(g["gx"], g.rate_hz, temp_degc=np.zeros(5))
    ok(False, "adequacy: a temperature of another length raises")
except ValueError:
    ok(True, "adequacy: a temperature of another length raises ValueError")


# ---------------------------------------------------------------- errors
try:
    ss.load("/nonexistent/capture.csv")
    ok(False, "errors: a missing file raises")
except ss.Error as e:
    ok(e.code == -2 and "/nonexistent/capture.csv" in str(e),
       "errors: a missing file raises ss.Error with the library's message",
       e)
try:
    ss.allan(np.ones(1), 10.0)
    ok(False, "errors: a too-short record raises")
except ss.Error as e:
    ok(e.code < 0 and str(e), "errors: a too-short record raises ss.Error "
       "(%s)" % e)
bad = np.sin(np.arange(5000) * 2.385)
bad[1234] = np.inf
try:
    ss.allan(bad, 10.0, taus="octave", fit=False)
    ok(False, "errors: an infinite sample raises")
except ss.Error as e:
    ok("index 1234" in str(e), "errors: an infinite sample raises ss.Error "
       "at its index (%s)" % e)
try:
    ss.allan(np.ones(100), 10.0, dev="xdev")
    ok(False, "errors: an unknown deviation raises")
except ValueError as e:
    ok("xdev" in str(e), "errors: an unknown deviation raises ValueError")
# a bad argument is refused before any work, naming the argument
gyro = os.path.join(SAMPLES, "gyro-static.csv")
for call, says in (
        (lambda: ss.adequacy(np.ones(100), 10.0, terms=["Z"]),
         "adequacy: terms: 'Z' is not Q, N, B, K or R"),
        (lambda: ss.adequacy(np.ones(100), 10.0, alpha=2),
         "adequacy: alpha: 2 is not between 0 and 1"),
        (lambda: ss.datasheet_gjb(np.ones(100), 10.0, ci=2),
         "datasheet_gjb: ci: 2 is not a level between 0 and 1"),
        (lambda: ss.load(gyro, units="furlong"),
         "load: units: unknown unit 'furlong'")):
    try:
        call()
        ok(False, "errors: refused: " + says)
    except ss.ArgumentError as e:
        ok(str(e).startswith(says), "errors: refused: " + says, str(e))

# ---------------------------------------------------------------- units
# the unit comes from a loaded capture's channel; without one, rad/s is
# assumed and said; .to() works on every term
cap = ss.load(gyro)
gx = cap["gx"]
ok(isinstance(gx, ss.Channel) and gx.unit == "rad/s" and
   gx.quantity == "angular rate" and gx[10:].unit == "rad/s" and
   not isinstance(gx * 2, ss.Channel),
   "Channel: unit and quantity, kept by a slice, not by arithmetic",
   (type(gx), gx.unit, gx.quantity))
r = ss.allan(gx, cap.rate_hz, taus="octave")
ok(r.unit == "rad/s" and not r.unit_assumed and
   all(isinstance(r.noise[t].to("deg/h" if t == "B" else
                                "deg/h/sqrt(h)" if t == "K" else
                                "deg/sqrt(h)" if t == "N" else
                                "deg/h^2" if t == "R" else "deg"), tuple)
       for t in "QNBKR"),
   "allan on a capture's channel: its unit; .to() on every term",
   (r.unit, r.unit_assumed))
r2 = ss.allan(np.array(gx), cap.rate_hz, taus="octave")
ok(r2.unit == "rad/s" and r2.unit_assumed and
   abs(r2.noise["N"].to("deg/sqrt(h)")[0] -
       r.noise["N"].to("deg/sqrt(h)")[0]) < 1e-12,
   "allan on a plain array: rad/s assumed and said (unit_assumed)")
try:
    ss.allan(gx, cap.rate_hz, unit="degs")
    ok(False, "unit='degs' refused")
except ss.ArgumentError as e:
    ok(str(e).startswith("allan: unit: "), "unit='degs': ArgumentError "
       "naming the argument (%s)" % e)
try:
    ss.allan(np.array([]), 10.0)
    ok(False, "allan on no samples refused")
except ss.ArgumentError as e:
    ok(str(e) == "allan: x: no samples", "allan on no samples: ArgumentError "
       "that says so (%s)" % e)

# ---------------------------------------------------------------- module
ok(ss.__version__ == ss.version() and "Channel" in ss.__all__ and
   "np" not in ss.__all__ and all(hasattr(ss, k) for k in ss.__all__),
   "__version__, __all__ names what exists and no imported module")
doc = ss.allan.__doc__
ok(all(k in doc for k in ("Parameters", "Returns", "Raises", "NaN",
                          "m : ", "taus : ", "unit : ")),
   "allan's docstring: parameters (NaN gaps, taus, m, unit), returns, "
   "raises")

# ---------------------------------------------------------------- compat
# allantools' signature and return tuple; the NBS 1000-point set of NIST
# SP 1065 (the values allantools' own tests check) through it
from sensorscope import compat as at  # noqa: E402

nbs = np.empty(1000)
v = 1234567890
for i in range(1000):
    nbs[i] = v / 2147483647.0
    v = (16807 * v) % 2147483647
ref = {"adev": (2.922319e-01, 9.965736e-02, 3.897804e-02),
       "oadev": (2.922319e-01, 9.159953e-02, 3.241343e-02),
       "mdev": (2.922319e-01, 6.172376e-02, 2.170921e-02),
       "tdev": (1.687202e-01, 3.563623e-01, 1.253382e+00),
       "hdev": (2.943883e-01, 1.052754e-01, 3.910860e-02),
       "ohdev": (2.943883e-01, 9.581083e-02, 3.237638e-02),
       "totdev": (2.922319e-01, 9.134743e-02, 3.406530e-02)}
for name, want in ref.items():
    t, d, e, nn = getattr(at, name)(nbs, rate=1.0, data_type="freq",
                                    taus=[1, 10, 100])
    ok(list(t) == [1, 10, 100] and rel(d, want) < 5e-7 and
       np.allclose(e, d / np.sqrt(nn)),
       "compat.%s: NBS 1000-point set at tau 1, 10, 100 to the 7 printed "
       "digits (SP 1065)" % name, (list(t), list(d), want))
t, d, e, nn = at.oadev(nbs, rate=1.0, data_type="freq", taus=[1, 10, 100])
ok(list(nn) == [999, 981, 801], "compat.oadev: term counts of SP 1065",
   list(nn))
# the same numbers as the native call; phase = the integral of freq
for name in ref:
    t, d, e, nn = getattr(at, name)(nbs, 4.0, "freq", "octave")
    r = ss.allan(nbs, 4.0, dev=name, m=np.round(t * 4.0), fit=False,
                 ci=None)
    ph = np.concatenate(([0.0], np.cumsum(nbs) / 4.0))
    tp, dp, ep, np_ = getattr(at, name)(ph, 4.0, "phase", "octave")
    ok(np.array_equal(d, r.dev) and np.array_equal(t, r.tau_s) and
       list(tp) == list(t) and rel(dp, d) < 1e-12,
       "compat.%s: the native call's numbers; phase data give the same"
       % name, (rel(dp, d),))
# allantools' Stable32 checks on PHASE.DAT (the phase form of the NBS
# set) for the total, Theo1 and time-error deviations: every value to the
# digits Stable32 printed (tables in tests/data/stable32, copied from
# allantools' test suite)
ph = np.concatenate(([0.0], np.cumsum(nbs)))


def s32(name):
    with open(os.path.join(SRC, "tests", "data", "stable32",
                           "phase_dat_%s.txt" % name)) as f:
        return np.array([ln.split() for ln in f if not ln.startswith("#")],
                        dtype=float)


def printed(got, want):
    """got equals want to the 5 significant digits Stable32 printed"""
    half = 0.5 * 10.0 ** (np.floor(np.log10(np.abs(want))) - 4)
    return bool(np.all(np.abs(np.asarray(got) - want) <= half * 1.0001))


for name, table, col in (("mtotdev", "mtotdev_octave", 5),
                         ("ttotdev", "ttotdev_octave", 5),
                         ("htotdev", "htotdev_octave", 5),
                         ("theo1", "theo1_alpha0", 3),
                         ("mtie", "mtie", 3)):
    tb = s32(table)
    if name == "htotdev":  # Stable32 identifies flicker PM at m 128, 256
        tb = tb[tb[:, 3] == 0]
    t, d, e, nn = getattr(at, name)(ph, 1.0, "phase", tb[:, 0])
    ok(len(t) == len(tb) and np.allclose(t, tb[:, 1]) and
       printed(d, tb[:, col]),
       "compat.%s: Stable32's PHASE.DAT table, %d taus to its printed "
       "digits" % (name, len(tb)),
       (len(t), len(tb), list(np.abs(d - tb[:len(d), col]))[:5]))
tb = s32("htotdev_octave")
r = ss.allan(ph, 1.0, dev="htotdev", input="angle", m=[128, 256],
             noise_type="fpm", fit=False)
ok(printed(r.dev, tb[7:, 5]),
   "htotdev at m = 128, 256 with Stable32's flicker PM: its printed digits",
   list(r.dev))
try:
    ss.allan(ph, 1.0, dev="theo1", m=[12, 13])
    ok(False, "theo1: an odd factor refused")
except ss.ArgumentError as e:
    ok("even averaging factors of at least 10, not 13" in str(e),
       "theo1: an odd factor is refused, named (%s)" % e)

# allantools' tau generator (its test_tau_generator, N = 128)
d128 = np.random.default_rng(5).random(128)
ok(list(at.adev(d128)[0]) == [1, 2, 4, 8, 16, 32] and
   list(at.adev(d128, taus=[])[0]) == [1, 2, 4, 8, 16, 32] and
   list(at.adev(d128, taus="decade")[0]) == [1, 2, 4, 10, 20, 40] and
   list(at.adev(d128, taus="all")[0]) == list(range(1, 43)),
   "compat: taus None, [], decade and all as allantools (N = 128)",
   [list(at.adev(d128, taus=k)[0]) for k in (None, "decade", "all")])
try:
    at.oadev(d128, data_type="fractional")
    ok(False, "compat: a bad data_type refused")
except ss.ArgumentError as e:
    ok("data_type" in str(e) and "freq or phase" in str(e),
       "compat: a bad data_type names the argument and the allowed values")

# ---------------------------------------------------------------- datasheet
# by hand: 0.15 deg/sqrt(h) = 0.15 * pi/180 / 60 rad/sqrt(s); an Allan
# minimum of 0.5 deg/h is B = 0.5 / sqrt(2 ln2 / pi) = 0.5 / 0.6642825 deg/h
t = ss.datasheet_terms({"random_walk": "0.15 deg/sqrt(h)",
                        "in_run_bias_stability": "0.5 deg/h"})
ok(rel(t["N"], 0.15 * math.pi / 180 / 60) < 1e-14 and
   rel(t["B"], 0.5 / 0.6642824702679601 * math.pi / 180 / 3600) < 1e-14 and
   t["K"] is None, "datasheet_terms: ARW and Allan minimum by hand", t)
# 0.05 deg/s rms over 100 Hz = 0.05 / sqrt(100) = 0.005 deg/s/sqrt(Hz)
t = ss.datasheet_terms({"rms_noise": "0.05 deg/s"}, noise_bandwidth=100)
ok(rel(t["N"], 0.005 * math.pi / 180) < 1e-14,
   "datasheet_terms: rms over a noise bandwidth", t)
# 0.23 mg/sqrt(Hz) = 0.23e-3 * 9.80665 m/s^2/sqrt(Hz)
t = ss.datasheet_terms({"noise_density": "0.23 mg/sqrt(Hz)"},
                       quantity="acceleration")
ok(rel(t["N"], 2.2555295e-3) < 1e-12, "datasheet_terms: mg/sqrt(Hz)", t)
for bad_lines, why in (({"noise": "1 deg/h"}, "unknown key"),
                       ({"noise_density": "1 deg/h"}, "wrong dimension"),
                       ({"noise_density": "0.01"}, "no unit"),
                       ({"rms_noise": "0.05 deg/s"}, "no bandwidth")):
    try:
        ss.datasheet_terms(bad_lines)
        ok(False, "datasheet_terms refuses: " + why)
    except ss.ArgumentError:
        ok(True, "datasheet_terms refuses: " + why)
# the GJB figure against plain numpy averaging, to 1e-12
rng = np.random.default_rng(41)
xg = 2e-3 + rng.normal(scale=1e-2, size=123457) + \
    np.cumsum(rng.normal(scale=1e-5, size=123457))
g = ss.datasheet_gjb(xg, 100.0, 10.0)
means = xg[:123000].reshape(123, 1000).mean(axis=1)
ok(g["n_means"] == 123 and rel(g["value"], np.std(means, ddof=1)) < 1e-12 and
   g["lo"] < g["value"] < g["hi"], "datasheet_gjb: plain numpy sd of means",
   g)
# the check against the CLI on the same capture
with tempfile.TemporaryDirectory() as td:
    sini = os.path.join(td, "s.ini")
    with open(sini, "w") as f:
        f.write("[sensor]\nnoise_density = 0.0175 deg/s/sqrt(Hz)\n")
    csv = os.path.join(td, "c.csv")
    subprocess.run([SSCOPE, "simulate", "--sensor", sini, "--rate", "100",
                    "--duration", "300", "--seed", "5", "-o", csv],
                   check=True)
    ds = os.path.join(SAMPLES, "datasheets", "bmi088.ini")
    j = cli("datasheet", "--check", csv, "--format", "json", ds)
    c = ss.datasheet_check(ss.load(csv)["gx"], 100.0,
                           {"noise_density": "0.014 deg/s/sqrt(Hz)"})
    jc = j["channels"][0]["checks"][0]
    ok(c[0]["verdict"] == jc["verdict"] == "out of spec" and
       rel(c[0]["value"], jc["si"]) < 1e-12 and
       rel(c[0]["hi"], jc["si_hi"]) < 1e-12,
       "datasheet_check: the CLI's verdict and interval", (c, jc))
    c = ss.datasheet_check(ss.load(csv)["gx"], 100.0,
                           {"run_to_run_bias": "10 deg/h"})
    ok(c[0]["value"] is None and c[0]["verdict"] == "inconclusive" and
       c[0]["why"], "datasheet_check: not measurable is None, not 0", c)

# ---------------------------------------------------------------- lot
# five units with se 0.5, values 1 2 4 3 5: tau^2 = 10/4 - 0.25 = 2.25 by
# hand (REML of a balanced lot), mean 3, Q-profile 90 % upper end
# sqrt(10 / 0.710723 - 0.25) = 3.717557 (chi-squared(4) table)
r = ss.lot_spread([1, 2, 4, 3, 5], [0.5] * 5)
ok(rel(r["between_sd"], 1.5) < 1e-9 and rel(r["mean"], 3) < 1e-12 and
   rel(r["between_hi"], 3.717557) < 1e-5 and r["outliers"] == [] and
   r["k_used"] == 5, "lot_spread: a balanced lot by hand", r)
# a unit 10 sd out is flagged and left out of the spread
rng = np.random.default_rng(34)
vals = rng.normal(size=60) + rng.normal(scale=0.5, size=60)
vals[7] += 10 * math.sqrt(1.25)
r = ss.lot_spread(vals, np.full(60, 0.5))
ok(7 in r["outliers"] and r["k_used"] == 59 and abs(r["z"][7]) > 5,
   "lot_spread: a planted outlier flagged and left out", r["outliers"])
for args, why, says in (
        (([1, 2], [1, 1]), "two units", "values: 2 units"),
        (([1, 2, 3], [1, 0, 1]), "a zero standard error",
         "se: 0 at index 1"),
        (([1, 2, float("nan")], [1, 1, 1]), "a NaN value",
         "values: nan at index 2 is not a finite number"),
        (([1, 2, 3], [1, 1]), "mismatched lengths", "se: one standard"),
        (([1, 2, 3], [1, 1, 1], 1.5), "a level of 1.5", "level: 1.5")):
    try:
        ss.lot_spread(*args)
        ok(False, "lot_spread refuses " + why)
    except ss.ArgumentError as e:
        ok(str(e).startswith("lot_spread: " + says),
           "lot_spread refuses %s and says which argument" % why, str(e))

# sensorscope.lot() is the command's JSON: the bundled lot (a folder) and
# four of its units, every number to 1e-9 relative, every key and string
def same_json(a, b, where="", bad=None):
    bad = [] if bad is None else bad
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            bad.append("%s: keys %s vs %s" % (where, sorted(set(a) ^ set(b)),
                                               ""))
        for k in set(a) & set(b):
            same_json(a[k], b[k], where + "." + k, bad)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            bad.append("%s: %d vs %d items" % (where, len(a), len(b)))
        for i, (x, y) in enumerate(zip(a, b)):
            same_json(x, y, "%s[%d]" % (where, i), bad)
    elif isinstance(a, bool) or isinstance(b, bool) or a is None or \
            b is None or isinstance(a, str):
        if a != b:
            bad.append("%s: %r vs %r" % (where, a, b))
    elif not (a == b or abs(a - b) <= 1e-9 * max(abs(a), abs(b))):
        bad.append("%s: %r vs %r" % (where, a, b))
    return bad


lotdir = os.path.join(SAMPLES, "lot")
py = ss.lot(lotdir)
cmd = cli("lot", "--format", "json", *sorted(
    os.path.join(lotdir, f) for f in os.listdir(lotdir)))
bad = same_json(py, cmd)
ok(not bad, "lot(folder): the command's JSON (%d units)" % len(py["units"]),
   "\n".join(bad))
four = [os.path.join(lotdir, "unit%02d.csv" % i) for i in (2, 5, 7, 11)]
bad = same_json(ss.lot(four, level=0.8),
                cli("lot", "--format", "json", "--ci", "0.8", *four))
ok(not bad, "lot(files, level): the command's JSON", "\n".join(bad))
mdir = tempfile.mkdtemp()
with open(os.path.join(mdir, "lot.csv"), "w") as f:
    f.write("unit,file,channels,temperature\n")
    for i in (1, 4, 7, 9):
        f.write("SN-%d,%s,ax,temp\n" % (i, os.path.abspath(
            os.path.join(lotdir, "unit%02d.csv" % i))))
bad = same_json(ss.lot(os.path.join(mdir, "lot.csv")),
                cli("lot", "--format", "json", os.path.join(mdir, "lot.csv")))
ok(not bad, "lot(manifest): the command's JSON", "\n".join(bad))
# four units and a stuck one: the stuck unit flagged, K's interval cut at 0
sdir = tempfile.mkdtemp()
for i in (1, 2, 3, 4):
    shutil.copy(os.path.join(lotdir, "unit%02d.csv" % i), sdir)
with open(os.path.join(lotdir, "unit01.csv")) as f, \
        open(os.path.join(sdir, "unit05.csv"), "w") as g:
    g.write(f.readline())
    for line in f:
        g.write(line.split(",")[0] + ",0.001,20\n")
pys = ss.lot(sdir)
bad = same_json(pys, cli("lot", "--format", "json", *sorted(
    os.path.join(sdir, f) for f in os.listdir(sdir))))
ok(not bad and [u["channels"][0]["constant"] for u in pys["units"]] ==
   [False] * 4 + [True] and any(
       b["mean_lo_cut"] and b["mean_lo"] == 0 for b in pys["between"]
       if b["term"] == "K"),
   "lot: a stuck unit flagged constant, K's interval cut at 0, as the command",
   "\n".join(bad))
ok([(o["unit"], o["term"]) for o in py["outliers"]] ==
   [("unit07.csv", "bias")], "lot: unit07 the bias outlier", py["outliers"])
try:
    ss.lot(four[:2])
    ok(False, "lot refuses two units")
except ss.ArgumentError:
    ok(True, "lot refuses two units")

# ---------------------------------------------------------------- export
# export() is `allan --export`: the same bytes for every target on a
# gyro-and-accelerometer record, and on a moving record with force (the
# command's files written beside it by one run)
euroc = os.path.join(SAMPLES, "euroc-imu.csv")
walk = os.path.join(SAMPLES, "walk-stops.csv")
targets = ss.export_targets()
ok(len(targets) == 10 and "vins" in targets and "gazebo" in targets,
   "export_targets: the ten targets", targets)
with tempfile.TemporaryDirectory() as td:
    for src, extra, force in ((euroc, [], False),
                              (walk, ["--force", "--inflate", "3"], True)):
        args = [SSCOPE, "allan", "--format", "json"] + extra
        for t in targets:
            args += ["--export", "%s:%s" % (t, os.path.join(td, t))]
        r = subprocess.run(args + [src], capture_output=True, text=True)
        cap = ss.load(src)
        bad = []
        nwarn = 0
        for t in targets:
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                txt = ss.export(cap, t, force=force,
                                inflate=3.0 if force else 1.0)
            nwarn += len(w)
            with open(os.path.join(td, t)) as fh:
                if fh.read() != txt:
                    bad.append(t)
        ok(r.returncode == 0 and not bad,
           "export(%s%s): every target's file is the command's, byte for "
           "byte" % (os.path.basename(src), ", force" if force else ""),
           r.stderr + " ".join(bad))
        ok(nwarn > 0, "export(%s): bounds and forced values are warned "
           "about (%d warnings)" % (os.path.basename(src), nwarn))
    # refused without force: the command's reason, no file left behind
    cap = ss.load(walk)
    out = os.path.join(td, "refused.yaml")
    try:
        ss.export(cap, "kalibr", path=out)
        ok(False, "export refuses a moving record")
    except ss.Error as e:
        ok("the record moves" in str(e) and "force=True" in str(e) and
           not os.path.exists(out),
           "export refuses a moving record: the reason, force named, no "
           "file", str(e))
    # a file needing both sensors from a gyro alone
    try:
        ss.export(ss.load(gyro), "gtsam")
        ok(False, "export: gtsam needs both sensors")
    except ss.Error as e:
        ok("needs both a gyro" in str(e), "export: gtsam needs both sensors",
           str(e))
    # a dict of channels with rate= is the capture's export
    cap = ss.load(euroc)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = ss.export(cap, "vins", path=os.path.join(td, "v.yaml"))
        b = ss.export({k: cap[k] for k in cap}, "vins", rate=cap.rate_hz)
    with open(os.path.join(td, "v.yaml")) as fh:
        ok(fh.read() == a, "export(path=): the file holds the text returned")
    ok(a.replace(euroc, "data") == b,
       "export(dict, rate=): the capture's file (data named 'data')")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        g1 = ss.export(cap, "gnss-ins-sim")
        g2 = ss.export(cap, "gnss_ins_sim")
    ok(g1 == g2, "export: 'gnss-ins-sim' is gnss_ins_sim")
for bad_call, arg in ((lambda: ss.export(ss.load(gyro), "nav2"), "target"),
                      (lambda: ss.export(ss.load(gyro), "vins", inflate=0),
                       "inflate"),
                      (lambda: ss.export({"gx": np.zeros(10)}, "vins"),
                       "rate"),
                      (lambda: ss.export(ss.load(gyro), "vins", rate=5),
                       "rate")):
    try:
        bad_call()
        ok(False, "export: a bad %s is refused" % arg)
    except ss.ArgumentError as e:
        ok(arg in str(e), "export: a bad %s is refused, naming it" % arg,
           str(e))
try:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ss.export({"gx": np.array([0.0, np.nan] * 500)}, "vins", rate=10)
    ok(False, "export: NaN samples refused")
except ss.Error as e:
    ok("NaN sample at index 1" in str(e), "export: NaN samples refused, "
       "with the index", str(e))

# ------------------------------------------- bad arguments, named (no crash)
def refused(call, starts, desc):
    try:
        call()
        ok(False, desc)
    except ss.ArgumentError as e:
        ok(str(e).startswith(starts), desc, str(e))


ADC16 = os.path.join(SAMPLES, "adc-16bit.ini")
MEMS = os.path.join(SAMPLES, "gyro-mems-250.ini")
refused(lambda: ss.simulate(None, 100, 1), "simulate: sensor: expected a "
        "file's path", "simulate(None): the argument named")
refused(lambda: ss.plan(None, {"B": 0.25}, 100), "plan: sensor_or_terms: ",
        "plan(None): the argument named")
refused(lambda: ss.adc_report(None, [ADC16]), "adc_report: sensor: ",
        "adc_report(None): the argument named")
refused(lambda: ss.adc_report(MEMS, [None]), "adc_report: adcs: ",
        "adc_report(adcs=[None]): the argument named")
refused(lambda: ss.psd(np.zeros(5000), 100.0, nfft=2 ** 30),
        "psd: nfft: ", "psd: nfft beyond 64 times nperseg refused at once")
refused(lambda: ss.psd(np.random.default_rng(2).normal(size=5000), 100.0,
                       nperseg=4, nfft=257),
        "psd: nfft: 257 is more than 64 times nperseg 4",
        "psd: nfft one beyond 64 times nperseg refused")
ok(ss.psd(np.random.default_rng(2).normal(size=5000), 100.0, nperseg=4,
          nfft=256).nfft == 256, "psd: nfft of 64 times nperseg taken")
refused(lambda: ss.load(os.path.join(SAMPLES, "gyro-static.csv"), scale=2.0),
        "load: scale: applies to raw input only", "load: scale without raw")
refused(lambda: ss.allan(np.zeros(100) + 1.0, 10.0, unit="deg/s"),
        "allan: unit: 'deg/s' is not an SI unit: give x in SI (x * 0.01745",
        "allan: a unit other than SI refused, with the factor (the samples "
        "are read as SI)")
# the command's flags, in Python too: a term shown but not measured, a
# rejected fit (the same samples as the command's warnings in cli-allan.sh)
capg = ss.load(os.path.join(SAMPLES, "gyro-static.csv"))
with warnings.catch_warnings(record=True) as wl:
    warnings.simplefilter("always")
    rg = ss.allan(capg["gz"], capg.rate_hz)
ok(rg.noise["K"].fitted and not rg.noise["K"].resolved and
   rg.noise["N"].resolved and "not measured" in repr(rg.noise["K"]) and
   any("K present, but its 68.3 % interval [0, " in str(w.message)
       for w in wl),
   "allan: a present term whose interval reaches zero flagged (resolved, "
   "repr, warning)", [str(w.message) for w in wl])
capu = ss.load(os.path.join(SAMPLES, "lot", "unit01.csv"))
with warnings.catch_warnings(record=True) as wl:
    warnings.simplefilter("always")
    ru = ss.allan(capu["ax"], capu.rate_hz)
cj = cli("allan", "-c", "ax", "--format", "json",
          os.path.join(SAMPLES, "lot", "unit01.csv"))
ok(ru.rejected == cj["channels"][0]["fit"]["rejected"] is True and
   any("fit rejected" in str(w.message) for w in wl),
   "allan: a rejected fit flagged as the command's", ru.p_value)
refused(lambda: ss.plan(MEMS, {"B": 0.25}, 100, ci=0), "plan: ci: 0 is not",
        "plan: ci=0 refused (it was taken as the default)")
refused(lambda: ss.simulate(MEMS, 10, 1, seed=2 ** 64), "simulate: seed: ",
        "simulate: a seed beyond 2^64 - 1 refused (it wrapped to 0)")
refused(lambda: ss.adc_report(MEMS, [ADC16], rate=-5), "adc_report: rate: ",
        "adc_report: a negative rate refused")
refused(lambda: ss.allan(np.ones(100), 10.0, threads=2 ** 40),
        "allan: threads: ", "allan: threads beyond 1024 refused")
ok(len(ss.simulate(MEMS, 10, 0.25)["t"]) == 3,
   "simulate: 2.5 samples round up to 3, as the command")
tb_t = np.linspace(20, 40, 2000)
tb_x = 1e-3 * (tb_t - 30) + np.random.default_rng(7).normal(0, 1e-4, 2000)
tb_x[8] = np.inf
try:
    ss.tempbias(tb_x, tb_t, 1.0)
    ok(False, "tempbias: an infinite sample refused")
except ss.Error as e:
    ok(str(e) == "tempbias: x: infinite sample at index 8",
       "tempbias: an infinite sample refused, with its index", str(e))
try:
    ss.load(os.path.join(SAMPLES, "no-such-file.csv"))
    ok(False, "load: a missing file raises FileNotFoundError")
except FileNotFoundError as e:
    ok(isinstance(e, ss.Error) and e.code == -2 and
       str(e).endswith("no-such-file.csv: no such file or directory"),
       "load: a missing file raises FileNotFoundError (also ss.Error)", str(e))
ls0 = ss.lot_spread([1, 1.1, 0.9, 1.05, 0.95], [1.0] * 5)
ok(ls0["between_hi"] == 0 and "agree better than their own" in
   ls0["between_note"], "lot_spread: an interval [0, 0] says why")
refused(lambda: ss.lot_spread([1, 1.1, 0.9], [1e300] * 3), "lot_spread: se: ",
        "lot_spread: a standard error too large to square refused (was NaN)")
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    rnf = ss.allan(np.random.default_rng(3).normal(0, 1e-3, 4000), 100.0,
                   fit=False)
    rm = ss.allan(np.random.default_rng(3).normal(0, 1e-3, 4000), 100.0,
                  unit="m")
ok(rnf.chi2 is None and rnf.p_value is None and rnf.rejected is None,
   "allan without a fit: its numbers None, not missing")
ok(rm.noise["N"].si_unit == "m/sqrt(Hz)" and rm.noise["B"].si_unit == "m",
   "allan on another quantity: the terms' units from the data's, as the "
   "command's")
zt = os.path.join(tempfile.mkdtemp(), "zt.csv")
with open(zt, "w") as fh:
    fh.write("t,gx\n1,0.1\n1,0.2\n1,0.3\n1,0.4\n")
with warnings.catch_warnings(record=True) as wl:
    warnings.simplefilter("always")
    czt = ss.load(zt)
ok(czt.rate_hz is None and any("time column 't' is constant" in
                               str(w.message) for w in wl),
   "load: a constant time column warned about, as the command does")
tb_x[8] = np.nan
ok(ss.tempbias(tb_x, tb_t, 1.0, allow_nan=True)["order"] >= 0,
   "tempbias: allow_nan reads a NaN as a gap, as the command's --allow-nan")
xa = np.random.default_rng(5).normal(0, 1e-3, 5000)
Ta = np.linspace(20, 40, 5000)
Ta[10] = np.nan
qa = ss.adequacy(xa, 100.0, temp_degc=Ta)
ok(any("temperature sample 11 is not a number" in f["message"]
       for f in qa.findings),
   "adequacy: a gap in the temperature said, not a crash")
ok(ss.adequacy(xa, 100.0, terms="NN").requested == ["N"],
   "adequacy: a term named twice is that term")

# ---------------------------------------------------------------- install
# `make install` puts the module where the interpreter looks for the
# prefix /usr/local (Debian 12: /usr/local/lib/python3.11/dist-packages)
pyd = os.environ.get("SSCOPE_PYTHONDIR", "")
pre = os.environ.get("SSCOPE_PREFIX", "")
found = subprocess.run(
    [sys.executable, "-c", "import sys; print('\\n'.join(sys.path))"],
    capture_output=True, text=True).stdout.split()
if pyd.startswith(pre + "/") and \
        any(p.startswith("/usr/local/lib/python3") for p in found):
    rel_dir = pyd[len(pre):]
    ok("/usr/local" + rel_dir in found,
       "install: %s under the prefix /usr/local is on the interpreter's "
       "path" % rel_dir, found)
else:
    print("ok %d - # SKIP install path: not Debian's interpreter layout "
          "(%s)" % (n_test + 1, pyd))
    n_test += 1

print("1..%d" % n_test)
