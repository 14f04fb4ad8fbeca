# SPDX-License-Identifier: GPL-3.0-or-later
"""sensorscope: characterisation of inertial sensors, from Python.

A thin layer over libsensorscope (ctypes): numpy arrays go in and come out
without copies where the layout allows (any float64 array whose stride is a
whole number of elements is read in place; loaded captures are returned as
views of the library's own arrays), and every failure raises
sensorscope.Error carrying the library's message.

    import sensorscope as ss
    cap = ss.load("imu.bag")                  # CSV, bags, MCAP, npy, ...
    res = ss.allan(cap["gx"], cap.rate_hz)    # OADEV, intervals, IEEE 952 fit
    res.noise["N"].value                      # rad/s/sqrt(Hz), SI
"""

import ctypes as C
import math
import threading

import numpy as np

from . import _capi as _c

__all__ = ["Error", "Capture", "load", "allan", "psd", "simulate",
           "tempbias", "calib", "adc_report",
           "AllanResult", "Spectrum", "version"]

SI_TERM_UNITS = {}


class Error(Exception):
    """A failure of the library: .code is the negative errno, str() the
    library's message (file, line, column, key...)."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def version():
    """The library's version string."""
    return _c.version().decode()


def _check(rc, diag, what=""):
    if rc < 0:
        msg = diag.msg.decode(errors="replace") if diag is not None else ""
        if not msg:
            msg = (what + ": " if what else "") + _c.strerror(rc).decode()
        raise Error(rc, msg)


def _b(s):
    return None if s is None else str(s).encode()


def _vector(x):
    """(pointer, stride in elements, n, keep-alive) of a 1-D float64 view
    of x, without a copy when x already is float64 with an element-aligned
    stride."""
    a = np.asarray(x)
    if a.ndim != 1:
        raise ValueError("expected a 1-D array, got shape %r" % (a.shape,))
    if a.dtype != np.float64 or a.strides[0] <= 0 or a.strides[0] % 8:
        a = np.ascontiguousarray(a, dtype=np.float64)
    stride = a.strides[0] // 8
    return a.ctypes.data_as(_c.c_dptr), stride, a.shape[0], a


class _Owner:
    """Keeps a library object alive while numpy views of it exist."""

    def __init__(self, ptr, free):
        self.ptr = ptr
        self._free = free

    def __del__(self):
        if self.ptr:
            self._free(self.ptr)
            self.ptr = None


def _view(ptr, n, owner):
    """A read-only numpy array over n doubles at ptr, owned by owner."""
    if not ptr or n == 0:
        return np.empty(0)

    class _Holder:
        __array_interface__ = {
            "data": (C.cast(ptr, C.c_void_p).value, True),
            "shape": (n,), "typestr": "<f8", "version": 3}

    h = _Holder()
    h.owner = owner
    return np.asarray(h)


def _quantity_name(q):
    return _c.quantity_name(q).decode()


class Capture:
    """A loaded capture: channels as numpy arrays in SI units (views of the
    library's memory, read-only), time stamps (s from the first sample),
    temperature (degC), and the container's details."""

    def __init__(self, ptr, path):
        self._owner = _Owner(ptr, _c.capture_free)
        cap = ptr.contents
        self.path = path
        self.n = cap.n
        self.rate_hz = cap.rate_hz if cap.rate_hz > 0 else None
        self.rate_source = ("none", "given", "time column",
                            "header")[cap.rate_source]
        self.channels = {}
        self.units = {}
        self.quantities = {}
        for k in range(cap.n_channels):
            ch = cap.channels[k]
            name = ch.col.name.decode()
            self.channels[name] = _view(ch.data, cap.n, self._owner)
            self.units[name] = ch.col.unit_label.decode()
            self.quantities[name] = _quantity_name(ch.col.quantity)
        self.time_s = _view(cap.time_s, cap.n, self._owner) \
            if cap.time_s else None
        self.temp_degc = _view(cap.temp_degc, cap.n, self._owner) \
            if cap.temp_degc else None
        self.format = None
        self.topics = []
        self.receive_s = None
        if cap.source_info:
            si = cap.source_info.contents
            self.format = si.format.decode()
            for i in range(si.n_topics):
                t = si.topics[i]
                self.topics.append({
                    "name": t.name.decode(), "type": t.type.decode(),
                    "messages": t.messages, "readable": t.readable,
                    "selected": t.selected})
            if si.receive_s:
                self.receive_s = _view(si.receive_s, cap.n, self._owner)

    def __getitem__(self, name):
        return self.channels[name]

    def __iter__(self):
        return iter(self.channels)

    def __len__(self):
        return self.n

    def __repr__(self):
        return "<sensorscope.Capture %s: %d x %s at %s Hz>" % (
            self.path, self.n, list(self.channels), self.rate_hz)


def load(path, columns=None, rate=None, units=None, topic=None,
         time_column=None, temp_column=None, allow_nan=False, raw=None,
         scale=None, offset=None, warn=True):
    """Read a capture: delimited text, sensorscope binary, raw binary
    (raw="i16:6:le", scale, offset), MATLAB v5/v7, .npy, gzip, ROS 1 bags,
    rosbag2 (.db3 or folder) and MCAP (topic="NAME[,TEMPERATURE]").
    Channels are converted to SI.  Returns a Capture.  An implausible rate
    from a time column gives a RuntimeWarning naming the likely unit."""
    o = _c.ReadOpts()
    o.columns = _b(",".join(columns) if isinstance(columns, (list, tuple))
                   else columns)
    o.rate_hz = float(rate) if rate else 0.0
    o.default_unit = _b(units)
    o.topic = _b(topic)
    o.time_column = _b(time_column)
    o.temp_column = _b(temp_column)
    o.nan_as_gap = bool(allow_nan)
    o.raw = _b(raw)
    o.raw_scale = float(scale) if scale else 0.0
    o.raw_offset = float(offset) if offset else 0.0
    ptr = C.POINTER(_c.Capture)()
    d = _c.Diag()
    rc = _c.capture_load(C.byref(ptr), _b(path), C.byref(o), C.byref(d))
    _check(rc, d, str(path))
    cap = Capture(ptr, str(path))
    h = _c.Diag()
    if warn and _c.capture_check_rate(ptr, C.byref(h)) < 0:
        import warnings
        warnings.warn("%s: %s" % (path, h.msg.decode()), RuntimeWarning,
                      stacklevel=2)
    return cap


# ------------------------------------------------------------------ allan

_DEVS = ("oadev", "adev", "mdev", "tdev", "hdev", "ohdev", "totdev")
_GRIDS = {"dense": 0, "octave": 1, "decade": 2, "all": 3}
_TERMS = "QNBKR"
_NOISE = {2: "WPM", 1: "FPM", 0: "WFM", -1: "FFM", -2: "RWFM", -3: "FWHM",
          -4: "RWHM"}


_WHY = {0: None, 1: "not among the terms allowed",
        2: "the fit without it describes the curve (presence test not passed)",
        3: "not separable from the other terms on this record"}


class Coef:
    """One IEEE 952 coefficient in SI: value (NaN when not present), lo, hi
    (hi is an upper limit when not present), present (the same as fitted),
    reason (None when present), si_unit; .to(unit) converts."""

    def __init__(self, c, si_unit):
        self.value = c.value
        self.lo = c.lo
        self.hi = c.hi
        self.fitted = bool(c.fitted)
        self.present = bool(c.present)
        self.reason = _WHY.get(c.why, "not present")
        self.si_unit = si_unit

    def to(self, unit):
        """(value, lo, hi) in another unit, e.g. 'deg/sqrt(h)'."""
        out = []
        for v in (self.value, self.lo, self.hi):
            r = C.c_double()
            if not math.isfinite(v):
                out.append(v)
                continue
            rc = _c.convert(v, _b(self.si_unit), _b(unit), C.byref(r))
            if rc < 0:
                raise Error(rc, "cannot convert %s to %s" %
                            (self.si_unit, unit))
            out.append(r.value)
        return tuple(out)

    def __repr__(self):
        if self.fitted:
            return "%.6g [%.4g, %.4g] %s" % (self.value, self.lo, self.hi,
                                             self.si_unit)
        if math.isfinite(self.hi) and self.hi > 0:
            return "not shown present (below %.4g %s: %s)" % (
                self.hi, self.si_unit, self.reason)
        return "not shown present (%s)" % self.reason


class AllanResult:
    """Deviation points (numpy arrays tau_s, m, terms, dev, dev_lo, dev_hi,
    edf, alpha) in the data's SI unit, and the noise fit: noise = {"Q":
    Coef, "N": ..., "R": ...}, chi2, dof, p_value, readoff."""

    def __repr__(self):
        return "<sensorscope.AllanResult %s: %d taus, fit %s>" % (
            self.deviation, len(self.tau_s),
            "ok" if self.noise else "failed")


def _si_units(quantity):
    q = {"angular rate": 3, "acceleration": 4}.get(quantity)
    if q is None:
        return [None] * 5
    return [_c.term_si_unit(q, t).decode() for t in range(5)]


class _NoisePlan:
    """A noise-fit plan (sscope_noise_plan_new): what the fit computes that
    depends only on the rate, the length and the taus, kept between calls
    (the results are the same numbers).  One per thread: a plan serves one
    fit at a time."""

    def __init__(self):
        self.ptr = C.c_void_p()
        if _c.noise_plan_new(C.byref(self.ptr)) != 0:
            raise MemoryError("noise plan")

    def __del__(self):
        free = getattr(_c, "noise_plan_free", None)
        if free is not None and self.ptr:
            free(self.ptr)
            self.ptr = C.c_void_p()


_plans = threading.local()


def _noise_plan():
    plan = getattr(_plans, "plan", None)
    if plan is None:
        plan = _plans.plan = _NoisePlan()
    return plan.ptr


def allan(x, rate, dev="oadev", taus="dense", ci=0.683, input="rate",
          fit=True, unit=None, threads=0, noise_type=None):
    """Allan-family deviation of x (samples at `rate` Hz, SI units) with
    confidence intervals (Greenhall-Riley EDF) and the IEEE 952 noise fit.
    dev: oadev adev mdev tdev hdev ohdev totdev; taus: dense, octave,
    decade, all, or an array of averaging factors m or taus in s (values
    below 1 are taus); ci: level or None; input: "rate" or "angle";
    unit: the data's unit for the coefficient units ("rad/s", "m/s^2").
    x is read in place when it is float64 with an element-aligned stride."""
    p, stride, n, keep = _vector(x)
    ao = _c.AllanOpts()
    if dev not in _DEVS:
        raise ValueError("dev: %r is not one of %s" % (dev, ", ".join(_DEVS)))
    ao.dev = _DEVS.index(dev)
    ao.input = {"rate": 0, "angle": 1}[input]
    ao.ci_level = -1.0 if ci is None else float(ci)
    ao.threads = int(threads)
    # the workspace is not kept between calls: its pages go back to the
    # system on every thread instead of on one when it is freed
    ao.release_workspace = True
    if noise_type is not None:
        ao.alpha_fixed = True
        ao.alpha = {v: k for k, v in _NOISE.items()}[noise_type.upper()]
    fo = _c.NoiseFitOpts()
    fo.ci_level = float(ci) if ci else 0.683
    fo.skip = not fit  # no fit computed that nobody asked for
    if fit:
        fo.plan = _noise_plan()
    if isinstance(taus, str):
        if taus not in _GRIDS:
            raise ValueError("taus: %r is not dense, octave, decade or all"
                             % taus)
        grid = _GRIDS[taus]
        want = None
    else:
        grid = _GRIDS["all"] if n <= 20000 else _GRIDS["dense"]
        want = np.asarray(taus, dtype=float)
        want = np.where(want < 1, np.round(want * rate), want).astype(int)
    res = C.POINTER(_c.AllanResult)()
    d = _c.Diag()
    if want is not None:
        grid = _GRIDS["all"]
    rc = _c.allan_analyze(p, stride, n, float(rate), grid, C.byref(ao),
                          C.byref(fo), C.byref(res), C.byref(d))
    del keep
    _check(rc, d, "allan")
    try:
        r = res.contents
        pts = np.ctypeslib.as_array(
            C.cast(r.points, C.POINTER(C.c_byte)),
            (r.n_points * C.sizeof(_c.AllanPoint),)).view(np.dtype({
                "names": [f[0] for f in _c.AllanPoint._fields_],
                "formats": ["<f8", "<u8", "<u8", "<u8", "<u8", "<f8", "<f8",
                            "<f8", "<f8", "<f8", "<i4", "?"],
                "offsets": [getattr(_c.AllanPoint, f[0]).offset
                            for f in _c.AllanPoint._fields_],
                "itemsize": C.sizeof(_c.AllanPoint)})) \
            if r.n_points else np.zeros(0, dtype=[("tau_s", "<f8")])
        out = AllanResult()
        out.deviation = dev
        sel = slice(None)
        if want is not None and r.n_points:
            sel = np.isin(pts["m"], want)
        for f in ("tau_s", "m", "terms", "dev", "dev_lo", "dev_hi", "edf",
                  "alpha"):
            out.__dict__[f] = np.array(pts[f][sel]) if r.n_points \
                else np.zeros(0)
        out.n_phase = r.n_phase
        out.noise = None
        out.fit_error = None
        if fit and r.have_fit:
            units = _si_units(_quantity_of(unit))
            out.noise = {t: Coef(r.fit.coef[i], units[i])
                         for i, t in enumerate(_TERMS)}
            out.chi2 = r.fit.chi2
            out.dof = r.fit.dof
            out.p_value = r.fit.p_value
            out.ci_level = r.fit.ci_level
            ro = r.fit.readoff
            out.readoff = {"N": ro.n, "N_tau_s": ro.n_tau_s, "B": ro.b,
                           "B_tau_s": ro.b_tau_s, "K": ro.k,
                           "K_tau_s": ro.k_tau_s}
        elif fit:
            out.fit_error = _c.strerror(r.fit_error).decode()
        return out
    finally:
        _c.allan_result_free(res)


def _quantity_of(unit):
    if unit is None:
        return None
    u = _c.Unit()
    d = _c.Diag()
    _check(_c.unit_parse(_b(unit), C.byref(u), C.byref(d)), d)
    return _quantity_name(_c.unit_quantity(C.byref(u)))


# ------------------------------------------------------------------ psd

class Spectrum:
    """One-sided spectrum: frequency_hz, psd (numpy arrays), rms, and the
    parameters used (window, nperseg, noverlap, nfft, n_segments)."""

    def __repr__(self):
        return "<sensorscope.Spectrum %d bins, %s, rms %.4g>" % (
            len(self.frequency_hz), self.scaling, self.rms)


def psd(x, rate, window="hann", nperseg=256, overlap=0.5, nfft=None,
        detrend="constant", scaling="density"):
    """Welch's PSD of x as scipy.signal.welch(x, fs=rate, window,
    nperseg, noverlap=int(nperseg*overlap), nfft, detrend, scaling)."""
    p, stride, n, keep = _vector(x)
    o = _c.PsdOpts()
    _c.psd_opts_init(C.byref(o))
    w = C.c_int()
    if _c.window_from_name(_b(window), C.byref(w)) < 0:
        raise ValueError("window: %r is not known" % window)
    o.window = w.value
    o.nperseg = int(nperseg)
    o.noverlap = int(int(nperseg) * overlap) if overlap is not None \
        else o.noverlap
    o.nfft = int(nfft) if nfft else 0
    o.detrend = {"constant": 0, "linear": 1, "none": 2, None: 2,
                 False: 2}[detrend]
    o.scaling = {"density": 0, "spectrum": 1}[scaling]
    s = _c.Spectrum()
    rc = _c.psd_welch(p, stride, n, float(rate), C.byref(o), C.byref(s))
    del keep
    _check(rc, None, "psd")
    try:
        out = Spectrum()
        out.frequency_hz = np.ctypeslib.as_array(s.freq_hz, (s.n_bins,)).copy()
        out.psd = np.ctypeslib.as_array(s.value, (s.n_bins,)).copy()
        out.rms = s.rms
        out.scaling = scaling
        out.window = window
        out.nperseg = s.nperseg
        out.noverlap = s.noverlap
        out.nfft = s.nfft
        out.n_segments = s.n_segments
        out.enbw_hz = s.enbw_hz
        return out
    finally:
        _c.spectrum_clear(C.byref(s))


# ------------------------------------------------------------------ simulate

def simulate(sensor, rate, duration, seed=1, axes=1, temp_degc=None):
    """Samples whose noise obeys a sensor specification (an INI file with a
    [sensor] section, as for `sensorscope simulate`): returns a dict of
    numpy arrays in SI, axis names gx gy gz (ax ay az for accelerometers),
    and "t" in s.  The same seed gives the same samples as the command."""
    spec = _c.SensorSpec()
    d = _c.Diag()
    _check(_c.sensor_spec_load(_b(sensor), C.byref(spec), C.byref(d)), d)
    n = int(round(rate * duration))
    if n <= 0:
        raise ValueError("rate * duration must give at least one sample")
    so = _c.SimOpts()
    temps = spec.has & (1 << 9)
    so.ref_temp_degc = (spec.temp_min_degc + spec.temp_max_degc) / 2 \
        if temps else 25.0
    so.temp_degc = so.ref_temp_degc if temp_degc is None else temp_degc
    so.rate_hz = float(rate)
    so.seed = int(seed)
    so.flicker_tau_max_s = max(1e6, 10 * duration)
    base = "g" if spec.quantity == 3 else "a"
    out = {"t": np.arange(n) / float(rate)}
    for k in range(axes):
        o = _c.SimOpts.from_buffer_copy(so)
        o.stream = k
        sim = C.c_void_p()
        _check(_c.sim_new(C.byref(sim), C.byref(spec), C.byref(o),
                          C.byref(d)), d)
        try:
            y = np.empty(n)
            _check(_c.sim_generate(sim, None, y.ctypes.data_as(_c.c_dptr),
                                   None, n), None, "simulate")
        finally:
            _c.sim_free(sim)
        name = base + "xyz"[k] if axes <= 3 else "%s%d" % (base, k + 1)
        out[name] = y
    return out


# ------------------------------------------------------------------ tempbias

def tempbias(x, temp_degc, rate, order="auto", ref_temp=None):
    """Bias against temperature (analysis/tempbias.c, as `sensorscope
    tempbias`): x and temp_degc are arrays of one run, or lists of arrays
    (one per power cycle); x in SI.  Returns a dict: order,
    ref_temp_degc, coefficients (b(T) = sum c_k (T - T_ref)^k, SI per
    degC^k), coefficient_sd, residual_rms, sensitivity, hysteresis
    {max, at_degc, eta}, gradient, turn_on_repeatability {sd, range,
    runs}, table [(temp_degc, bias)]."""
    xs = x if isinstance(x, (list, tuple)) else [x]
    ts = temp_degc if isinstance(temp_degc, (list, tuple)) else [temp_degc]
    if len(xs) != len(ts):
        raise ValueError("as many temperature arrays as runs")
    runs = (_c.TempbiasRun * len(xs))()
    keep = []
    for j, (a, t) in enumerate(zip(xs, ts)):
        p, stride, n, k1 = _vector(a)
        pt, st, nt, k2 = _vector(t)
        if nt != n:
            raise ValueError("run %d: %d samples, %d temperatures" %
                             (j, n, nt))
        if st != 1:
            k2 = np.ascontiguousarray(k2)
            pt = k2.ctypes.data_as(_c.c_dptr)
        keep += [k1, k2]
        runs[j] = _c.TempbiasRun(p, stride, pt, n, float(rate))
    o = _c.TempbiasOpts()
    if order == "auto":
        o.order_auto = True
        o.order = -1
    else:
        o.order = int(order)
    if ref_temp is not None:
        o.ref_temp_set = True
        o.ref_temp_degc = float(ref_temp)
    res = C.POINTER(_c.TempbiasResult)()
    d = _c.Diag()
    rc = _c.tempbias_fit(runs, len(xs), C.byref(o), C.byref(res), C.byref(d))
    del keep
    _check(rc, d, "tempbias")
    try:
        r = res.contents
        return {
            "order": r.order, "ref_temp_degc": r.ref_temp_degc,
            "coefficients": [r.coef[i] for i in range(r.order + 1)],
            "coefficient_sd": [r.coef_sd[i] for i in range(r.order + 1)],
            "residual_rms": r.residual_rms,
            "sensitivity": r.sensitivity,
            "hysteresis": {"max": r.hysteresis_max,
                           "at_degc": r.hysteresis_at_degc,
                           "eta": r.hysteresis if r.have_hysteresis
                           else None,
                           "collinear_with_gradient": r.hyst_grad_collinear,
                           "gradient_vif": r.hyst_grad_vif},
            "gradient": r.gradient if r.have_gradient else None,
            "turn_on_repeatability": {"sd": r.repeat_sd,
                                      "range": r.repeat_range,
                                      "runs": r.n_runs},
            "table": [(r.table_temp_degc[i], r.table_bias[i])
                      for i in range(r.n_table)],
            "note": r.note.decode(errors="replace"),
        }
    finally:
        _c.tempbias_result_free(res)


# ------------------------------------------------------------------ calib

def calib(ax, ay, az, rate, gravity=9.80665):
    """Accelerometer multi-position calibration (Tedaldi et al. 2014, as
    `sensorscope calib accel`): static poses are detected in the record
    (x, y, z in m/s^2) and the 9-parameter model u' = T K (y - b) is
    fitted.  Returns a dict: bias (m/s^2), scale, misalignment (3x3, unit
    diagonal), their *_sd, residual_rms (m/s^2), poses."""
    arrs = [np.ascontiguousarray(a, dtype=np.float64) for a in (ax, ay, az)]
    n = arrs[0].shape[0]
    if any(a.ndim != 1 or a.shape[0] != n for a in arrs):
        raise ValueError("three 1-D arrays of one length")
    det = _c.CalibDetect()
    iv = (_c.CalibInterval * 4096)()
    t = _c.CalibTriad()
    w1 = np.empty(n)
    w2 = np.empty(n)
    d = _c.Diag()
    rc = _c.calib_accel_multipos(
        *(a.ctypes.data_as(_c.c_dptr) for a in arrs), 1, n, float(rate),
        float(gravity), C.byref(det), iv, 4096, C.byref(t),
        w1.ctypes.data_as(_c.c_dptr), w2.ctypes.data_as(_c.c_dptr),
        C.byref(d))
    _check(rc, d, "calib")
    m = [[t.mis[i][j] for j in range(3)] for i in range(3)]
    msd = [[t.mis_sd[i][j] for j in range(3)] for i in range(3)]
    return {"bias": list(t.bias), "scale": list(t.scale),
            "misalignment": m, "bias_sd": list(t.bias_sd),
            "scale_sd": list(t.scale_sd), "misalignment_sd": msd,
            "residual_rms": t.residual_rms, "poses": t.poses,
            "threshold_k": det.k}


# ------------------------------------------------------------------ adc

def adc_report(sensor, adcs, rate=0.0):
    """Does each converter degrade this sensor? (`sensorscope adc report`'s
    analysis): sensor is a spec file with a [sensor] section, adcs a list
    of spec files with an [adc] section.  Returns one dict per converter:
    name, bits, lsb (SI), dithered, min_bits (None when none passes),
    verdict, margin, limiting, terms {name: {value, reference, ratio,
    verdict}}.  An inl_profile file named in a spec is not read here."""
    if isinstance(adcs, (str, bytes)):
        adcs = [adcs]
    sp = _c.SensorSpec()
    d = _c.Diag()
    _check(_c.sensor_spec_load(_b(sensor), C.byref(sp), C.byref(d)), d)
    out = []
    for path in adcs:
        a = _c.AdcSpec()
        _check(_c.adc_spec_load(_b(path), C.byref(a), C.byref(d)), d)
        an = _c.AdcAnalysis()
        _check(_c.adc_analyze(C.byref(sp), C.byref(a), float(rate),
                              C.byref(an), C.byref(d)), d)
        terms = {}
        for i in range(5):
            tr = an.term[i]
            terms[_c.adc_term_name(i).decode()] = {
                "value": tr.value, "reference": tr.reference,
                "ratio": tr.ratio,
                "verdict": _c.adc_verdict_name(tr.verdict).decode()}
        out.append({
            "name": a.name.decode(), "bits": a.bits, "lsb": an.lsb,
            "dithered": bool(an.dithered),
            "min_bits": an.min_bits if an.min_bits >= 0 else None,
            "verdict": _c.adc_verdict_name(an.verdict).decode(),
            "margin": an.margin,
            "limiting": _c.adc_term_name(an.limiting).decode(),
            "n_total": an.n_total, "bias_bound": an.bias_bound,
            "terms": terms})
    return out
