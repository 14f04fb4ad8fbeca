# SPDX-License-Identifier: GPL-3.0-or-later
"""sensorscope: characterisation of inertial sensors, from Python.

A thin layer over libsensorscope (ctypes): numpy arrays go in and come out
without copies where the layout allows (an aligned float64 array whose
stride is a whole number of elements is read in place; anything else is
copied first; loaded captures are returned as views of the library's own
arrays).  Every failure raises sensorscope.Error carrying the library's
message; a bad argument raises sensorscope.ArgumentError (also a
ValueError) naming the function and the argument, e.g. "allan: ci: 95 is
not a level between 0 and 1 (e.g. 0.683, 0.95) or none".  Arguments are
refused, and doubtful results warned about (RuntimeWarning), exactly where
the `sensorscope` command refuses or warns, with the same reasons.  A
failure inside GSL (a special function out of range, a root not bracketed)
never aborts the interpreter: importing the module installs the library's
recording GSL error handler (process-wide), and
after every library call a recorded GSL error raises sensorscope.Error
("allan: a numerical routine failed (GSL, FILE:LINE: REASON): no result",
.gsl_errno set) even where the call itself reported success.  Each thread
has its own record; an error on one of the library's worker threads is
raised by the next call that checks, on whichever thread.

    import sensorscope as ss
    cap = ss.load("imu.bag")                  # CSV, bags, MCAP, npy, ...
    res = ss.allan(cap["gx"], cap.rate_hz)    # OADEV, intervals, IEEE 952 fit
    res.noise["N"].value                      # rad/s/sqrt(Hz), SI
    res.noise["N"].to("deg/sqrt(h)")          # (value, lo, hi)

Users of allantools: `from sensorscope import compat as allantools` gives
its functions with its signatures and return values (sensorscope.compat).
"""

import ctypes as C
import errno
import math
import numbers
import sys
import threading
import warnings

import numpy as np

from . import _capi as _c

__all__ = ["Error", "ArgumentError", "Capture", "Channel", "load", "allan",
           "psd", "simulate",
           "tempbias", "calib", "adc_report",
           "AllanResult", "Coef", "Spectrum", "version", "__version__"]

SI_TERM_UNITS = {}


class Error(Exception):
    """A failure of the library: .code is the negative errno, str() the
    library's message (file, line, column, key...).  .gsl_errno is GSL's
    error number when a GSL routine failed, else None.  A missing file,
    a file not allowed and a folder where a file was expected are also
    FileNotFoundError, PermissionError and IsADirectoryError."""

    def __new__(cls, *args, **kwargs):
        if cls is Error and args and isinstance(args[0], int):
            cls = _OS_ERRORS.get(-args[0], Error)
        if issubclass(cls, OSError):
            return OSError.__new__(cls)
        return Exception.__new__(cls)

    def __init__(self, code, message, gsl_errno=None):
        Exception.__init__(self, message)
        self.code = code
        self.gsl_errno = gsl_errno
        if isinstance(self, OSError):
            self.errno, self.strerror = -code, message

    def __str__(self):
        return str(self.args[0]) if self.args else ""


class FileMissingError(Error, FileNotFoundError):
    """Error for a file that does not exist (also FileNotFoundError)."""


class FileAccessError(Error, PermissionError):
    """Error for a file not allowed (also PermissionError)."""


class FolderGivenError(Error, IsADirectoryError):
    """Error for a folder where a file was expected (also
    IsADirectoryError)."""


_OS_ERRORS = {errno.ENOENT: FileMissingError, errno.EACCES: FileAccessError,
              errno.EISDIR: FolderGivenError}


class ArgumentError(Error, ValueError):
    """A bad argument: str() is "function: argument: why" (the reason the
    command gives for the same option); .code is -EINVAL."""

    def __init__(self, message):
        super().__init__(-22, message)


def _bad(func, arg, why):
    raise ArgumentError("%s: %s: %s" % (func, arg, why))


def _warn(func, msg, stacklevel=3):
    """A RuntimeWarning where the command prints "warning:"."""
    warnings.warn("%s: %s" % (func, msg), RuntimeWarning,
                  stacklevel=stacklevel)


def _text(v):
    """A value as the command would have read it."""
    return "%g" % v if isinstance(v, float) else str(v)


def _number(func, arg, v):
    """A finite real number (the command's rule for numeric options)."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        try:
            v = float(v)
        except (TypeError, ValueError):
            _bad(func, arg, "'%s' is not a number" % (v,))
    f = float(v)
    if not math.isfinite(f):
        _bad(func, arg, "'%s' is not a number" % _text(f))
    return f


def _positive(func, arg, v):
    f = _number(func, arg, v)
    if not f > 0:
        _bad(func, arg, "must be positive, got %s" % _text(f))
    return f


def _count(func, arg, v):
    """A non-negative integer (the command's rule for counts)."""
    if isinstance(v, bool):
        _bad(func, arg, "'%s' is not a non-negative integer" % v)
    if isinstance(v, numbers.Integral) and v >= 0:
        return int(v)
    if isinstance(v, numbers.Real) and math.isfinite(v) and v >= 0 and \
            float(v).is_integer():
        return int(v)
    _bad(func, arg, "'%s' is not a non-negative integer" % _text(v))


def _level(func, arg, v, example="0.99"):
    """A level or probability strictly between 0 and 1 (0 is not "the
    default": it is refused, as by the command)."""
    v = _number(func, arg, v)
    if not 0 < v < 1:
        _bad(func, arg, "%s is not a level between 0 and 1 (e.g. %s)"
             % (_text(v), example))
    return v


def _choice(func, arg, v, names, listing):
    if not isinstance(v, str) or v not in names:
        _bad(func, arg, "'%s' is not %s" % (v, listing))
    return v


def version():
    """The library's version string."""
    return _c.version().decode()


__version__ = version()


def _check(rc, diag, what=""):
    if rc < 0:
        msg = diag.msg.decode(errors="replace") if diag is not None else ""
        if not msg:
            msg = _c.strerror(rc).decode()
        if what and not msg.startswith(what + ":"):
            msg = what + ": " + msg
        raise Error(rc, msg)


# GSL's codes (gsl_errno.h) as the library's: EDOM, ERANGE, EINVAL,
# ENOMEM, EUNDRFLW, EOVRFLW; any other is a computation that failed (EDOM)
_GSL_ERRNO = {1: -errno.EDOM, 2: -errno.ERANGE, 4: -errno.EINVAL,
              8: -errno.ENOMEM, 15: -errno.ERANGE, 16: -errno.ERANGE}


def _called(frame, c_name):
    """The module's function the user called: the outermost frame of this
    package (compat included) on the stack, else the C function's name."""
    name = None
    while frame is not None and \
            frame.f_globals.get("__name__", "").partition(".")[0] == __name__:
        name = getattr(frame.f_code, "co_qualname", frame.f_code.co_name)
        frame = frame.f_back
    return name or c_name


def _gsl_check(result, func, args):
    """The errcheck of every library function (_capi.functions): a GSL
    error recorded during the call, on this thread or on a worker thread
    of the library, discards its result, whatever it returned."""
    if _c.gsl_error_pending():
        code = C.c_int()
        buf = C.create_string_buffer(320)
        if _c.gsl_error_take(C.byref(code), buf, len(buf)):
            raise Error(_GSL_ERRNO.get(code.value, -errno.EDOM),
                        "%s: a numerical routine failed (GSL, %s): no result"
                        % (_called(sys._getframe(1), func.__name__),
                           buf.value.decode(errors="replace")), code.value)
    return result


for _f in _c.functions:
    _f.errcheck = _gsl_check
del _f
# GSL's default handler aborts the process: record instead (sscope-gsl.h)
_c.gsl_errors_record()


def _b(s):
    return None if s is None else str(s).encode()


def _path(func, arg, p):
    """A file's path (str, bytes or os.PathLike) as bytes for the library;
    anything else an ArgumentError naming the argument."""
    import os
    if not isinstance(p, (str, bytes, os.PathLike)):
        _bad(func, arg, "expected a file's path, got %s" % type(p).__name__)
    return os.fsencode(p)


def _array(x, func, arg, contiguous=False):
    """x as a 1-D float64 numpy array the library can read: x itself when
    it is native float64, aligned on 8 bytes, with a positive stride of
    whole elements (and contiguous when asked), else a copy."""
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as e:
        _bad(func, arg, "not an array of numbers (%s)" % e)
    if a.ndim != 1:
        _bad(func, arg, "expected a 1-D array, got shape %r" % (a.shape,))
    if a.dtype.kind not in "biuf":
        _bad(func, arg, "expected real numbers, got %s values" % a.dtype)
    if a.dtype != np.float64 or not a.flags.aligned or \
            a.ctypes.data % 8 or a.strides[0] <= 0 or a.strides[0] % 8 or \
            (contiguous and not a.flags.c_contiguous):
        a = np.array(a, dtype=np.float64, order="C", copy=True)
    return a


def _vector(x, func="", arg="x"):
    """(pointer, stride in elements, n, keep-alive) of a 1-D float64 view
    of x, without a copy when x already is aligned float64 with an
    element-multiple stride (a misaligned or byte-swapped array is
    copied)."""
    a = _array(x, func, arg)
    if a.shape[0] == 0:
        _bad(func, arg, "no samples")
    stride = a.strides[0] // 8
    return a.ctypes.data_as(_c.c_dptr), stride, a.shape[0], a


def _finite(func, arg, a, allow_nan, what):
    """The command's rule for samples: an infinite one is refused, a NaN
    one too unless allow_nan (then a gap)."""
    bad = ~np.isfinite(a)
    if not bad.any():
        return
    inf = np.isinf(a)
    if inf.any():
        raise Error(-33, "%s: %s: infinite sample at index %d" %
                    (func, arg, int(np.argmax(inf))))
    if not allow_nan and what is None:
        # a function that takes no gaps
        raise Error(-33, "%s: %s: NaN sample at index %d" %
                    (func, arg, int(np.argmax(bad))))
    if not allow_nan:
        raise Error(-33, "%s: %s: NaN sample at index %d (give "
                    "allow_nan=True to read NaN samples as gaps: %s)" %
                    (func, arg, int(np.argmax(bad)), what))


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


class Channel(np.ndarray):
    """A channel of a loaded capture: a read-only numpy array in SI units
    that also says what it holds: .name, .unit (the SI unit, e.g.
    "rad/s"), .quantity ("angular rate", ...) and .file_unit (the file's
    own label).  A slice is still a Channel; the result of arithmetic is a
    plain array (its unit may no longer be .unit).  allan() and
    adequacy() take the unit from it."""

    def __array_finalize__(self, obj):
        for k in ("name", "unit", "quantity", "file_unit"):
            setattr(self, k, getattr(obj, k, None))

    def __array_wrap__(self, arr, context=None, return_scalar=False):
        arr = np.asarray(arr)
        return arr[()] if return_scalar else arr


class Capture:
    """A loaded capture: channels as numpy arrays in SI units (Channel:
    views of the library's memory, read-only, that know their unit), time
    stamps (s from the first sample), temperature (degC), and the
    container's details."""

    def __init__(self, ptr, path):
        self._owner = _Owner(ptr, _c.capture_free)
        cap = ptr.contents
        self.path = path
        self.n = cap.n
        self.rate_hz = cap.rate_hz if cap.rate_hz > 0 else None
        self.rate_source = ("none", "given", "time column",
                            "header")[cap.rate_source]
        # why a '# rate:' comment gave no rate (None: no such comment, or
        # a rate is known)
        self.rate_note = cap.rate_note.decode() or None
        self.channels = {}
        self.units = {}
        self.quantities = {}
        for k in range(cap.n_channels):
            ch = cap.channels[k]
            name = ch.col.name.decode()
            v = _view(ch.data, cap.n, self._owner).view(Channel)
            v.name = name
            v.quantity = _quantity_name(ch.col.quantity)
            v.unit = _c.quantity_si_unit(ch.col.quantity).decode()
            v.file_unit = ch.col.unit_label.decode()
            self.channels[name] = v
            self.units[name] = v.file_unit
            self.quantities[name] = v.quantity
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
    if rate is not None:
        rate = _positive("load", "rate", rate)
    if scale is not None:
        scale = _number("load", "scale", scale)
        if scale == 0:
            _bad("load", "scale", "must not be 0")
    if offset is not None:
        offset = _number("load", "offset", offset)
    if (scale is not None or offset is not None) and raw is None:
        _bad("load", "scale" if scale is not None else "offset",
             "applies to raw input only (give raw=...)")
    path_b = _path("load", "path", path)
    if units is not None:
        if not isinstance(units, str):
            _bad("load", "units", "'%s' is not a unit such as deg/s or g"
                 % (units,))
        _quantity_of(units, "load", "units")
    o = _c.ReadOpts()
    o.columns = _b(",".join(columns) if isinstance(columns, (list, tuple))
                   else columns)
    o.rate_hz = rate if rate is not None else 0.0
    o.default_unit = _b(units)
    o.topic = _b(topic)
    o.time_column = _b(time_column)
    o.temp_column = _b(temp_column)
    o.nan_as_gap = bool(allow_nan)
    o.raw = _b(raw)
    # (0 is the library's "not given": a given scale is never 0, and an
    # offset of 0 is no offset)
    o.raw_scale = scale if scale is not None else 0.0
    o.raw_offset = offset if offset is not None else 0.0
    oo = _c.OpenOpts()
    oo.read = C.pointer(o)
    ptr = C.POINTER(_c.Capture)()
    d = _c.Diag()
    nt = _c.Notes()
    # read, select the columns and judge the rate in one call, as the
    # command does (sscope_capture_open)
    rc = _c.capture_open(C.byref(ptr), path_b, C.byref(oo), C.byref(nt),
                         C.byref(d))
    if rc < 0:
        msg = d.msg.decode(errors="replace") or "%s: %s" % (
            path, _c.strerror(rc).decode())
        if raw is not None and msg.startswith("bad raw layout"):
            _bad("load", "raw", msg)
        raise Error(rc, "load: " + msg)
    cap = Capture(ptr, str(path))
    if warn and nt.unterminated:
        _warn("load", "%s: the last line (row %d) has no newline: was the "
              "capture cut short?" % (path, nt.rows_read))
    if warn and nt.unit_unused:
        _warn("load", "%s: units=%s changes nothing: the file names the "
              "unit of every channel" % (path, units))
    if warn and nt.rate_implausible:
        _warn("load", "%s: %s" % (path, nt.rate_hint.msg.decode()))
    if warn and nt.rate_disagrees:
        _warn("load", "%s: rate %g Hz but the time column implies %.6g Hz: "
              "using rate %g Hz" % (path, rate, nt.time_column_rate_hz, rate))
    c = ptr.contents
    if warn and c.time_s:
        # a time column that is constant or runs backwards, as the
        # command warns
        d = _c.Diag()
        order = c.timing.order
        if not c.has_timing:
            order = _c.TimeOrder()
            _c.timing_order_feed(C.byref(order), c.time_s, c.n)
        if _c.timing_order_check(C.byref(order), C.byref(d)) < 0:
            _warn("load", "%s: time column '%s' %s" % (
                path, c.time_col.name.decode(), d.msg.decode()))
    return cap


# ------------------------------------------------------------------ allan

# in the order of enum sscope_allan_dev
_DEVS = ("oadev", "adev", "mdev", "tdev", "hdev", "ohdev", "totdev",
         "mtotdev", "htotdev", "ttotdev", "theo1", "theobr", "theoh", "mtie",
         "tierms")
_DEV_LIST = ", ".join(_DEVS[:-1]) + " or " + _DEVS[-1]
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
    resolved (present and its interval excludes zero: False where the
    record shows the term but does not measure it), reason (None when
    present), si_unit; .to(unit) converts."""

    def __init__(self, c, si_unit):
        self.value = c.value
        self.lo = c.lo
        self.hi = c.hi
        self.fitted = bool(c.fitted)
        self.present = bool(c.present)
        self.resolved = bool(_c.noise_coef_resolved(C.byref(c)))
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
            return "%.6g [%.4g, %.4g] %s%s" % (
                self.value, self.lo, self.hi, self.si_unit,
                "" if self.resolved else
                " (present, not measured: its interval reaches zero)")
        if math.isfinite(self.hi) and self.hi > 0:
            return "not shown present (below %.4g %s: %s)" % (
                self.hi, self.si_unit, self.reason)
        return "not shown present (%s)" % self.reason


class AllanResult:
    """Deviation points (numpy arrays tau_s, m, terms, dev, dev_lo, dev_hi,
    edf, alpha) in the data's SI unit, and the noise fit: noise = {"Q":
    Coef, "N": ..., "R": ...}, chi2, dof, p_value, rejected (p below 0.01:
    the terms indicative only, with a RuntimeWarning as the command's),
    readoff."""

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
          fit=True, unit=None, threads=0, noise_type=None, allow_nan=False,
          m=None, data_type=None):
    """Allan-family deviation with confidence intervals and the IEEE 952
    noise fit (as `sensorscope allan`).

    Parameters
    ----------
    x : array_like, 1-D
        Samples at `rate` Hz in SI units: a rate (rad/s, m/s^2, ...) or,
        with input="angle", its integral (rad, m/s, ...).  NaN samples are
        refused unless `allow_nan`; then they are gaps: terms spanning one
        are left out and taus left without a complete term are omitted
        with a RuntimeWarning (as ``sensorscope allan --allow-nan``).
        Read in place when aligned float64 with an element-multiple
        stride, else copied.
    rate : float
        Sample rate in Hz (> 0).
    dev : str, default "oadev"
        oadev, adev, mdev, tdev, hdev, ohdev, totdev, mtotdev, htotdev,
        ttotdev (s), theo1, theobr, theoh (tau = 0.75 m / rate for the
        Theo1 family), mtie or tierms (s; no intervals: dev_lo, dev_hi and
        edf are NaN), as ``sensorscope allan --dev``.
    taus : str or array_like of float, default "dense"
        A grid (dense, octave, decade, all) or taus in seconds, each a
        whole number of samples (tau * rate within 1e-9 of an integer).
    m : array_like of int, optional
        Averaging factors instead of `taus` (whole numbers >= 1; tau =
        m / rate).  Giving both `taus` (other than the default) and `m`
        is an error.  Factors beyond the record's limit are left out with
        a RuntimeWarning, or refused when none is left.
    ci : float or None, default 0.683
        Level of the intervals, in (0, 1); None or "none" for none.
    input : {"rate", "angle"}, default "rate"
        What `x` holds.  `data_type` is allantools' name for it:
        "freq" is "rate", "phase" is "angle".
    fit : bool, default True
        Fit the IEEE 952 terms Q, N, B, K, R (on the dense grid, whatever
        `taus` is).
    unit : str, optional
        The SI unit of `x` ("rad/s", "m/s^2"), which sets the units of the
        noise terms.  Taken from `x` when it is a channel of a loaded
        capture (Channel.unit); otherwise angular rate (rad/s, or rad
        with input="angle") is assumed, and the result says so
        (.unit, .unit_assumed).
    threads : int, default 0
        Threads of the computation (0: as many as cores).
    noise_type : str, optional
        None or "auto" to identify the noise at each tau, or one of wpm,
        fpm, wfm, ffm, rwfm for the intervals.

    Returns
    -------
    AllanResult
        Arrays tau_s, m, terms, dev, dev_lo, dev_hi, edf, alpha (dev in the
        unit of a rate: .unit); noise = {"Q", "N", "B", "K", "R": Coef} in
        SI (.to("deg/sqrt(h)") converts; a term not shown present has
        value NaN and hi its upper bound), chi2, dof, p_value (with
        p_value_bound: True when it is the bootstrap's floor, 1/1001, so
        the true p is below it), ci_level,
        readoff; noise is None and fit_error says why when the fit fails.

    Raises
    ------
    ArgumentError
        A bad argument, named with the allowed values.
    Error
        Data the analysis cannot take (too short, infinite samples, ...).
    """
    fn = "allan"
    dev = _choice(fn, "dev", dev.lower() if isinstance(dev, str) else dev,
                  _DEVS, _DEV_LIST)
    rate = _positive(fn, "rate", rate)
    if ci is None or (isinstance(ci, str) and ci == "none"):
        ci = None
    else:
        ci = _number(fn, "ci", ci)
        if not 0 < ci < 1:
            _bad(fn, "ci", "%s is not a level between 0 and 1 (e.g. 0.683, "
                 "0.95) or none" % _text(ci))
    input = _input_kind(fn, input, data_type)
    alpha = None
    if noise_type is not None and not (isinstance(noise_type, str) and
                                       noise_type.lower() == "auto"):
        names = {v.lower(): k for k, v in _NOISE.items()}
        if not isinstance(noise_type, str) or \
                noise_type.lower() not in names:
            _bad(fn, "noise_type", "'%s' is not auto, wpm, fpm, wfm, ffm or "
                 "rwfm" % (noise_type,))
        alpha = names[noise_type.lower()]
    threads = _count(fn, "threads", threads)
    if threads > 1024:
        _bad(fn, "threads", "%d is not 0 (all cores) to 1024" % threads)
    if m is not None and not (isinstance(taus, str) and taus == "dense"):
        _bad(fn, "m", "give taus (seconds or a grid) or m (averaging "
             "factors), not both")
    quantity, unit, assumed = _data_unit(fn, x, unit, input)
    p, stride, n, keep = _vector(x, fn, "x")
    ao = _c.AllanOpts()
    ao.dev = _DEVS.index(dev)
    ao.input = {"rate": 0, "angle": 1}[input]
    ao.ci_level = -1.0 if ci is None else ci
    ao.threads = threads
    ao.reject_nan = not allow_nan
    # the workspace is not kept between calls: its pages go back to the
    # system on every thread instead of on one when it is freed
    ao.plan_flags = _c.ALLAN_RELEASE_WORKSPACE
    if alpha is not None:
        ao.alpha_fixed = True
        ao.alpha = alpha
    fo = _c.NoiseFitOpts()
    fo.ci_level = ci if ci is not None else 0.683
    fo.skip = not fit  # no fit computed that nobody asked for
    if fit:
        fo.plan = _noise_plan()
    want = None
    if m is not None:
        want = _factors(fn, "m", m, rate, ao.dev, ao.input, n)
    elif isinstance(taus, str):
        grid = _GRIDS[_choice(fn, "taus", taus, _GRIDS,
                              "dense, octave, decade or all, or taus in s")]
    else:
        want = _factors(fn, "taus", taus, rate, ao.dev, ao.input, n)
    out = AllanResult()
    out.deviation = dev
    out.unit = unit
    out.unit_assumed = assumed
    out.noise = None
    out.fit_error = None
    # without a fit (fit=False, or one that failed) its numbers are
    # unknown: None, never missing attributes
    out.chi2 = out.dof = out.p_value = out.readoff = out.rejected = None
    out.p_value_bound = None
    out.ci_level = ci if ci is not None else None
    if want is not None:
        # the points at the factors asked for; the fit on the dense grid
        pts = _points(fn, p, stride, n, rate, ao, want)
        for f in ("tau_s", "m", "terms", "dev", "dev_lo", "dev_hi", "edf",
                  "alpha"):
            out.__dict__[f] = np.array(pts[f]) if len(pts) else np.zeros(0)
        out.n_phase = _c.allan_n_phase(ao.input, n)
        if not fit:
            del keep
            return out
        grid = _GRIDS["dense"]
    res = C.POINTER(_c.AllanResult)()
    d = _c.Diag()
    rc = _c.allan_analyze(p, stride, n, rate, grid, C.byref(ao),
                          C.byref(fo), C.byref(res), C.byref(d))
    del keep
    if rc < 0:
        _allan_error(fn, rc, d)
    try:
        r = res.contents
        if want is None:
            pts = _point_array(r.points, r.n_points)
            if r.n_gap_omitted:
                _warn(fn, "x: " + r.gap_note.msg.decode(errors="replace"))
            for f in ("tau_s", "m", "terms", "dev", "dev_lo", "dev_hi", "edf",
                      "alpha"):
                out.__dict__[f] = np.array(pts[f]) if r.n_points \
                    else np.zeros(0)
            out.n_phase = r.n_phase
        if fit and r.have_fit:
            units = _si_units(quantity)
            if units[0] is None:
                # another quantity: the terms' units from the rate's, as
                # the command's (Q rate*s, N rate/sqrt(Hz), B rate, ...)
                ru = unit + "/s" if input == "angle" else unit
                units = [ru + "*s", ru + "/sqrt(Hz)", ru, ru + "/s/sqrt(Hz)",
                         ru + "/s"]
            out.noise = {t: Coef(r.fit.coef[i], units[i])
                         for i, t in enumerate(_TERMS)}
            out.chi2 = r.fit.chi2
            out.dof = r.fit.dof
            out.p_value = r.fit.p_value
            # at the bootstrap's floor p is only known to be below it
            out.p_value_bound = bool(_c.noise_p_is_bound(r.fit.p_value))
            out.ci_level = r.fit.ci_level
            # the command's warnings: a rejected fit, a term shown but
            # not measured
            out.rejected = bool(_c.noise_fit_rejected(C.byref(r.fit), 0.01))
            if out.rejected:
                _warn(fn, "x: fit rejected: chi2 %.3g for %.3g dof, bootstrap p %s "
                      "%.2g, below 0.01: the five-term noise model does not "
                      "describe this record (a deterministic trend such as "
                      "a temperature effect, or a process outside the "
                      "model); read the terms as indicative only" % (
                          out.chi2, out.dof,
                          "<" if out.p_value_bound else "=", out.p_value))
            for t, c in out.noise.items():
                if c.fitted and not c.resolved:
                    _warn(fn, "x: %s present, but its %.3g %% interval "
                          "[0, %.3g] %s reaches zero: the record shows it, "
                          "it does not measure it" % (
                              t, 100 * out.ci_level, c.hi, c.si_unit))
            ro = r.fit.readoff
            out.readoff = {"N": ro.n, "N_tau_s": ro.n_tau_s, "B": ro.b,
                           "B_tau_s": ro.b_tau_s, "K": ro.k,
                           "K_tau_s": ro.k_tau_s}
        elif fit:
            # the command's warning: why there are no noise terms
            out.fit_error = r.fit_diag.msg.decode(errors="replace") or \
                _c.strerror(r.fit_error).decode()
            _warn(fn, "x: " + out.fit_error)
        return out
    finally:
        _c.allan_result_free(res)


def _allan_error(fn, rc, d):
    msg = d.msg.decode(errors="replace") or _c.strerror(rc).decode()
    if msg.startswith("NaN sample at index"):
        msg += " (give allow_nan=True to read NaN samples as gaps)"
    if rc == -22:
        raise Error(rc, "%s: %s" % (fn, msg))
    raise Error(rc, "%s: x: %s" % (fn, msg))


def _point_array(ptr, n):
    """A structured numpy view of n sscope_allan_point at ptr."""
    if not n:
        return np.zeros(0, dtype=[("tau_s", "<f8")])
    return np.ctypeslib.as_array(
        C.cast(ptr, C.POINTER(C.c_byte)),
        (n * C.sizeof(_c.AllanPoint),)).view(np.dtype({
            "names": [f[0] for f in _c.AllanPoint._fields_],
            "formats": ["<f8", "<u8", "<u8", "<u8", "<u8", "<f8", "<f8",
                        "<f8", "<f8", "<f8", "<f8", "<i4", "?"],
            "offsets": [getattr(_c.AllanPoint, f[0]).offset
                        for f in _c.AllanPoint._fields_],
            "itemsize": C.sizeof(_c.AllanPoint)}))


def _points(fn, p, stride, n, rate, ao, m):
    """The deviation at the averaging factors m (increasing): a copy of
    the library's points (a plan made and freed here)."""
    plan = C.c_void_p()
    if _c.allan_new(C.byref(plan), n, C.byref(ao)) != 0:
        raise MemoryError("%s: workspace for %d samples" % (fn, n))
    try:
        mm = (_c.c_size * len(m))(*[int(k) for k in m])
        pts = (_c.AllanPoint * max(len(m), 1))()
        npts = _c.c_size()
        d = _c.Diag()
        rc = _c.allan_compute(plan, p, stride, n, rate, mm, len(m), pts,
                              C.byref(npts), C.byref(d))
        if rc < 0:
            _allan_error(fn, rc, d)
        return np.array(_point_array(C.cast(pts, C.c_void_p), npts.value))
    finally:
        _c.allan_free(plan)


def _input_kind(fn, input, data_type):
    """input ("rate"/"angle") from input or allantools' data_type."""
    if data_type is not None:
        kind = {"freq": "rate", "phase": "angle"}.get(data_type) \
            if isinstance(data_type, str) else None
        if kind is None:
            _bad(fn, "data_type", "'%s' is not freq or phase (allantools' "
                 "names: freq is input='rate', phase is input='angle')" %
                 (data_type,))
        if input not in ("rate", kind):
            _bad(fn, "data_type", "'%s' contradicts input='%s'" %
                 (data_type, input))
        return kind
    if input in ("phase", "freq"):
        _bad(fn, "input", "'%s' is not rate or angle (allantools' "
             "data_type='%s' is input='%s')" % (
                 input, input, "angle" if input == "phase" else "rate"))
    return _choice(fn, "input", input, ("rate", "angle"), "rate or angle")


_RATE_OF = {"angle": "angular rate", "velocity": "acceleration"}


def _data_unit(fn, x, unit, input):
    """(rate quantity, unit of x, assumed?) from unit=, a Channel, or the
    angular-rate default."""
    assumed = False
    if unit is None:
        unit = getattr(x, "unit", None)
    if unit is None:
        unit, assumed = ("rad" if input == "angle" else "rad/s"), True
    if not isinstance(unit, str):
        _bad(fn, "unit", "'%s' is not a unit such as rad/s or m/s^2" %
             (unit,))
    q = _quantity_of(unit, fn)
    u = _c.Unit()
    if _c.unit_parse(_b(unit), C.byref(u), None) == 0 and \
            (u.scale != 1 or u.offset != 0):
        # the samples are taken as SI: a unit of another scale would label
        # them wrongly (and the noise terms with them)
        _bad(fn, "unit", "'%s' is not an SI unit: give x in SI (x * %.10g)"
             " with its SI unit" % (unit, u.scale))
    if input == "angle":
        q = _RATE_OF.get(q, q)
    return q, unit, assumed


def _factors(f, arg, v, rate, dev, input, n):
    """Averaging factors from taus in s (arg "taus": each a whole number
    of samples) or factors (arg "m": whole numbers >= 1); nothing is
    rounded.  Factors beyond the record are refused when none is left,
    else left out with a warning."""
    try:
        t = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        if arg == "m":
            _bad(f, "m", "'%s' is not an array of averaging factors" % (v,))
        _bad(f, "taus", "'%s' is not dense, octave, decade or all, nor an "
             "array of taus in s" % (v,))
    if t.ndim != 1:
        t = t.reshape(-1)
    if t.size == 0:
        _bad(f, arg, "empty: give %s" % (
            "averaging factors" if arg == "m" else "a grid name or taus in s"))
    m = []
    for x in t:
        if not math.isfinite(x) or x <= 0:
            _bad(f, arg, "%s is not positive" % _text(float(x)))
        if arg == "m":
            if not float(x).is_integer():
                _bad(f, "m", "%s is not an averaging factor (a whole number "
                     "of samples >= 1; taus in s go in taus=)" %
                     _text(float(x)))
            m.append(int(x))
        else:
            k = x * rate
            if abs(k - round(k)) > 1e-9 * k or round(k) < 1:
                _bad(f, "taus", "%s s is not a whole number of samples at "
                     "%s Hz (%s); averaging factors go in m=" % (
                         _text(float(x)), _text(rate), _text(float(k))))
            m.append(int(round(k)))
    m = sorted(set(m))
    if _DEVS[dev] in ("theo1", "theobr"):
        odd = [k for k in m if k % 2 or k < 10]
        if odd:
            _bad(f, arg, "%s takes even averaging factors of at least 10, "
                 "not %s" % (_DEVS[dev], ", ".join(str(k) for k in odd)))
    mmax = _c.allan_max_m(dev, _c.allan_n_phase(input, n))
    beyond = [k for k in m if k > mmax]
    if len(beyond) == len(m):
        _bad(f, arg, "every averaging factor exceeds the record's limit "
             "(m <= %d for %s of %d samples)" % (mmax, _DEVS[dev], n))
    if beyond:
        _warn(f, "%s: averaging factor%s %s exceed%s the record's limit "
              "(m <= %d for %s of %d samples): left out" % (
                  arg, "s" if len(beyond) > 1 else "",
                  ", ".join(str(k) for k in beyond),
                  "" if len(beyond) > 1 else "s", mmax, _DEVS[dev], n),
              stacklevel=4)
    return np.array([k for k in m if k <= mmax], dtype=np.uint64)


def _quantity_of(unit, fn="allan", arg="unit"):
    if unit is None:
        return None
    u = _c.Unit()
    d = _c.Diag()
    if _c.unit_parse(_b(unit), C.byref(u), C.byref(d)) < 0:
        _bad(fn, arg, d.msg.decode(errors="replace") or
             "'%s' is not a known unit" % unit)
    return _quantity_name(_c.unit_quantity(C.byref(u)))


# ------------------------------------------------------------------ psd

class Spectrum:
    """One-sided spectrum: frequency_hz, psd (numpy arrays), rms, and the
    parameters used (window, nperseg, noverlap, nfft, n_segments)."""

    def __repr__(self):
        return "<sensorscope.Spectrum %d bins, %s, rms %.4g>" % (
            len(self.frequency_hz), self.scaling, self.rms)


_WINDOWS = ("hann", "hamming", "blackman", "blackmanharris", "flattop",
            "boxcar")


def psd(x, rate, window="hann", nperseg=256, overlap=0.5, nfft=None,
        detrend="constant", scaling="density", allow_nan=False):
    """Welch's PSD of x as scipy.signal.welch(x, fs=rate, window,
    nperseg, noverlap=int(nperseg*overlap), nfft, detrend, scaling), as
    `sensorscope psd`: window hann, hamming, blackman, blackmanharris,
    flattop or boxcar; overlap in [0, 1); nfft >= nperseg; detrend
    constant, linear or none; scaling density or spectrum.  NaN samples
    are refused unless allow_nan (then the segments holding one are left
    out, with a RuntimeWarning); an nperseg longer than the record is
    shortened to it, with a RuntimeWarning."""
    f = "psd"
    rate = _positive(f, "rate", rate)
    window = _choice(f, "window", window, _WINDOWS,
                     "hann, hamming, blackman, blackmanharris, flattop or "
                     "boxcar")
    nperseg = _count(f, "nperseg", nperseg)
    if not 1 <= nperseg <= 1 << 30:
        _bad(f, "nperseg", "must be 1 to 2^30, got %d" % nperseg)
    if overlap is not None:
        overlap = _number(f, "overlap", overlap)
        if not 0 <= overlap < 1:
            _bad(f, "overlap", "must be in [0, 1), got %s" % _text(overlap))
    if nfft is not None:
        nfft = _count(f, "nfft", nfft)
        if not 1 <= nfft <= 1 << 30:
            _bad(f, "nfft", "must be 1 to 2^30, got %d" % nfft)
        if nfft < nperseg:
            raise ArgumentError("psd: nfft %d is shorter than nperseg %d" %
                                (nfft, nperseg))
        if nfft > 64 * nperseg:
            _bad(f, "nfft", "%d is more than 64 times nperseg %d: zero "
                 "padding beyond that only interpolates the spectrum"
                 % (nfft, nperseg))
    if detrend is None or detrend is False:
        detrend = "none"
    detrend = _choice(f, "detrend", detrend, ("constant", "linear", "none"),
                      "constant, linear or none")
    scaling = _choice(f, "scaling", scaling, ("density", "spectrum"),
                      "density or spectrum")
    p, stride, n, keep = _vector(x, f, "x")
    _finite(f, "x", keep, allow_nan, "the segments holding them are left out")
    o = _c.PsdOpts()
    _c.psd_opts_init(C.byref(o))
    w = C.c_int()
    if _c.window_from_name(_b(window), C.byref(w)) < 0:
        _bad(f, "window", "'%s' is not known" % window)
    o.window = w.value
    o.nperseg = nperseg
    if overlap is not None:
        # as the command: floor(overlap * nperseg), below nperseg (the
        # record's length when nperseg is shortened to it)
        o.noverlap = _c.psd_noverlap(float(overlap), min(nperseg, n))
    o.nfft = nfft if nfft else 0
    o.detrend = {"constant": 0, "linear": 1, "none": 2}[detrend]
    o.scaling = {"density": 0, "spectrum": 1}[scaling]
    o.skip_nonfinite = bool(allow_nan)
    o.shorten = True
    s = _c.Spectrum()
    rc = _c.psd_welch(p, stride, n, rate, C.byref(o), C.byref(s))
    del keep
    if rc == -33:  # EDOM: only NaN gaps remain (checked above)
        raise Error(rc, "psd: x: every segment holds a NaN gap")
    if rc == -34:  # ERANGE
        raise Error(rc, "psd: x: at %g Hz the spectrum leaves the double "
                    "range (values above 1.8e308 or all below 1e-292 in "
                    "SI units): check rate and the data's unit" % rate)
    _check(rc, None, "psd")
    if s.nperseg < nperseg:
        _warn(f, "x: nperseg %d is longer than the record (%d samples): "
              "one segment of %d" % (nperseg, n, s.nperseg))
    if s.n_skipped:
        _warn(f, "x: %d of %d segments skipped (NaN gaps)" %
              (s.n_skipped, s.n_skipped + s.n_segments))
    if s.rms == 0:
        if s.nperseg <= {1: 2, 0: 1}.get(s.detrend, 0):
            _warn(f, "x: segments of %d sample%s are zero once their %s is "
                  "removed: the spectrum is zero (give a longer nperseg)"
                  % (s.nperseg, "" if s.nperseg == 1 else "s",
                     "line" if s.detrend == 1 else "mean"))
        else:
            _warn(f, "x: the detrended signal is zero (constant input): "
                  "the spectrum is zero")
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
    f = "simulate"
    rate = _positive(f, "rate", rate)
    duration = _positive(f, "duration", duration)
    seed = _count(f, "seed", seed)
    if seed >= 1 << 64:
        _bad(f, "seed", "%d is beyond 2^64 - 1" % seed)
    axes = _count(f, "axes", axes)
    if not 1 <= axes <= 64:
        _bad(f, "axes", "1..64, got %d" % axes)
    if temp_degc is not None:
        temp_degc = _number(f, "temp_degc", temp_degc)
    # rounded half away from zero, as the command (llround)
    v = rate * duration
    if v >= 2.0 ** 40:
        _bad(f, "duration", "%s s at %s Hz is %.3g samples: more than "
             "memory holds" % (_text(duration), _text(rate), v))
    n = int(v) + (1 if v - int(v) >= 0.5 else 0)
    if n <= 0:
        raise ArgumentError("simulate: duration x rate is less than one "
                            "sample")
    spec = _c.SensorSpec()
    d = _c.Diag()
    _check(_c.sensor_spec_load(_path(f, "sensor", sensor), C.byref(spec),
                               C.byref(d)), d, "simulate: sensor")
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
                          C.byref(d)), d, f)
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

def tempbias(x, temp_degc, rate, order="auto", ref_temp=None,
             allow_nan=False):
    """Bias against temperature (as `sensorscope tempbias`): x and
    temp_degc are arrays of one run, or lists of arrays (one per power
    cycle); x in SI.  Returns a dict: order, ref_temp_degc, coefficients
    (b(T) = sum c_k (T - T_ref)^k, SI per degC^k), coefficient_sd,
    residual_rms, sensitivity (None at order 0: none resolved),
    hysteresis {max, at_degc, eta}, gradient, turn_on_repeatability {sd,
    range, runs}, table [(temp_degc, bias)].  NaN samples are refused
    unless `allow_nan` (then gaps, as ``sensorscope tempbias
    --allow-nan``); infinite ones always."""
    f = "tempbias"
    rate = _positive(f, "rate", rate)
    if not (isinstance(order, str) and order == "auto"):
        if isinstance(order, bool) or not isinstance(order, numbers.Real):
            try:
                float(order)
            except (TypeError, ValueError):
                _bad(f, "order", "'%s' is not a number" % (order,))
        if isinstance(order, bool) or not float(order).is_integer() or \
                not 0 <= float(order) <= 4:
            _bad(f, "order", "'%s' is not auto or 0..4" % _text(order))
        order = int(float(order))
    if ref_temp is not None:
        ref_temp = _number(f, "ref_temp", ref_temp)
    # a list of arrays is one run each; a list of numbers is one run
    def runs_of(v):
        return v if isinstance(v, (list, tuple)) and v and \
            not isinstance(v[0], numbers.Real) else [v]
    xs, ts = runs_of(x), runs_of(temp_degc)
    if len(xs) != len(ts):
        _bad(f, "temp_degc", "%d temperature arrays for %d runs" %
             (len(ts), len(xs)))
    runs = (_c.TempbiasRun * len(xs))()
    keep = []
    for j, (a, t) in enumerate(zip(xs, ts)):
        p, stride, n, k1 = _vector(a, f, "x")
        k2 = _array(t, f, "temp_degc", contiguous=True)
        _finite(f, "x", k1, allow_nan, "they are left out of the blocks")
        _finite(f, "temp_degc", k2, allow_nan,
                "they are left out of the blocks")
        if k2.shape[0] != n:
            _bad(f, "temp_degc", "run %d: %d samples, %d temperatures" %
                 (j, n, k2.shape[0]))
        pt = k2.ctypes.data_as(_c.c_dptr)
        keep += [k1, k2]
        runs[j] = _c.TempbiasRun(p, stride, pt, n, rate)
    o = _c.TempbiasOpts()
    if order == "auto":
        o.order_auto = True
        o.order = -1
    else:
        o.order = order
    if ref_temp is not None:
        o.ref_temp_set = True
        o.ref_temp_degc = ref_temp
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
            # None at order 0: no temperature term, none known
            "sensitivity": r.sensitivity if r.order >= 1 else None,
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

def calib(ax, ay, az, rate, gravity=9.80665, allow_nan=False):
    """Accelerometer multi-position calibration (Tedaldi et al. 2014, as
    `sensorscope calib accel`): static poses are detected in the record
    (x, y, z in m/s^2) and the 9-parameter model u' = T K (y - b) is
    fitted.  Returns a dict: bias (m/s^2), scale, misalignment (3x3, unit
    diagonal), their *_sd, residual_rms (m/s^2), poses.  NaN samples are refused unless `allow_nan`
    (then gaps, as ``sensorscope calib accel --allow-nan``)."""
    rate = _positive("calib", "rate", rate)
    gravity = _positive("calib", "gravity", gravity)
    arrs = [_array(a, "calib", name, contiguous=True)
            for a, name in ((ax, "ax"), (ay, "ay"), (az, "az"))]
    for a, name in zip(arrs, ("ax", "ay", "az")):
        _finite("calib", name, a, allow_nan,
                "windows holding one are not static")
    n = arrs[0].shape[0]
    for a, name in zip(arrs[1:], ("ay", "az")):
        if a.shape[0] != n:
            _bad("calib", name, "%d samples, ax has %d" % (a.shape[0], n))
    det = _c.CalibDetect()
    iv = (_c.CalibInterval * 4096)()
    t = _c.CalibTriad()
    w1 = np.empty(n)
    w2 = np.empty(n)
    d = _c.Diag()
    rc = _c.calib_accel_multipos(
        *(a.ctypes.data_as(_c.c_dptr) for a in arrs), 1, n, rate,
        gravity, C.byref(det), iv, 4096, C.byref(t),
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
    verdict}} (None where unknown: a drift the spec does not give).  An
    inl_profile file named in a spec is not read here."""
    if rate is None or (not isinstance(rate, bool) and
                        isinstance(rate, numbers.Real) and rate == 0):
        rate = 0.0  # not given: the sensor's own rate
    else:
        rate = _positive("adc_report", "rate", rate)
    if isinstance(adcs, (str, bytes)):
        adcs = [adcs]
    sp = _c.SensorSpec()
    d = _c.Diag()
    _check(_c.sensor_spec_load(_path("adc_report", "sensor", sensor),
                               C.byref(sp), C.byref(d)), d,
           "adc_report: sensor")
    out = []
    for path in adcs:
        a = _c.AdcSpec()
        _check(_c.adc_spec_load(_path("adc_report", "adcs", path),
                                C.byref(a), C.byref(d)), d,
               "adc_report: adcs")
        an = _c.AdcAnalysis()
        _check(_c.adc_analyze(C.byref(sp), C.byref(a), float(rate),
                              C.byref(an), C.byref(d)), d, "adc_report")
        terms = {}
        for i in range(5):
            tr = an.term[i]
            terms[_c.adc_term_name(i).decode()] = {
                "value": _num(tr.value), "reference": _num(tr.reference),
                "ratio": _num(tr.ratio),
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


# ---------------------------------------------------------------- adequacy
class Adequacy:
    """What a record supports (the library's adequacy check, the one that
    allan, report, run and the exporters use): verdict ("valid", "bounds",
    "doubtful", "not_valid"), still (None when not tested) and contrast,
    fit_rejected and fit_p_value, stationary (None when not tested), the
    terms requested, established and doubtful (lists of "Q".."R"),
    findings (dicts: cause, severity, terms, t_start_s, t_end_s, tau_min_s,
    tau_max_s, statistic, p_value, action_s, message -- one line each that
    names the cause, the range at fault and what to do), davar (the
    dynamic Allan deviation: t_s, tau_s, dev[window, tau], edf, model, in
    the data's SI unit; None when the record is too short), and noise (the
    fit's coefficients, as allan() gives them, or None)."""

    def __repr__(self):
        return "<sensorscope.Adequacy %s: %d findings>" % (
            self.verdict, len(self.findings))


def _term_names(mask):
    return [t for i, t in enumerate(_TERMS) if (mask >> i) & 1]


def adequacy(x, rate, temp_degc=None, input="rate", terms=None, unit=None,
             alpha=None, davar=True):
    """The adequacy check of x (samples at `rate` Hz, SI units) and of its
    IEEE 952 noise fit (OADEV, dense taus, 68.3 % intervals): is the record
    still, long enough for each term in `terms` (default "NBK"), described
    by the fit, and stationary (warm-up transient, bias step, rate ramp,
    drift that follows temp_degc when given); with the DAVAR map.
    unit: as for allan() (from a Channel, else rad/s assumed).
    Returns an Adequacy."""
    fn = "adequacy"
    rate = _positive(fn, "rate", rate)
    input = _choice(fn, "input", input, ("rate", "angle"), "rate or angle")
    if terms is not None:
        if isinstance(terms, str):
            terms = list(terms)
        for t in terms:
            if not isinstance(t, str) or len(t) != 1 or t not in _TERMS:
                _bad(fn, "terms", "%r is not Q, N, B, K or R" % (t,))
    if alpha is not None:
        alpha = _number(fn, "alpha", alpha)
        if not 0 < alpha < 1:
            _bad(fn, "alpha", "%s is not between 0 and 1 (e.g. 0.05)"
                 % _text(alpha))
    quantity, unit, _ = _data_unit(fn, x, unit, input)
    p, stride, n, keep = _vector(x, fn, "x")
    tkeep = None
    ao = _c.AllanOpts()
    ao.input = {"rate": 0, "angle": 1}[input]
    ao.ci_level = 0.683
    fo = _c.NoiseFitOpts()
    fo.ci_level = 0.683
    fo.plan = _noise_plan()
    res = C.POINTER(_c.AllanResult)()
    d = _c.Diag()
    rc = _c.allan_analyze(p, stride, n, float(rate), _GRIDS["dense"],
                          C.byref(ao), C.byref(fo), C.byref(res), C.byref(d))
    _check(rc, d, "adequacy")
    q = C.POINTER(_c.Adequacy)()
    try:
        r = res.contents
        qo = _c.AdequacyOpts()
        qo.rate_hz = float(rate)
        qo.angle = input == "angle"
        qo.unit = _b(unit)
        if terms is not None:
            qo.requested = sum(1 << _TERMS.index(t) for t in set(terms))
        if alpha is not None:
            qo.alpha = float(alpha)
        qo.no_davar = not davar
        if temp_degc is not None:
            tp, tstride, tn, tkeep = _vector(temp_degc, fn, "temp_degc")
            if tn != n:
                _bad(fn, "temp_degc", "%d samples for the %d of x" % (tn, n))
            qo.temp_degc = tp
            qo.temp_stride = tstride
        rc = _c.adequacy_check(p, stride, n,
                               C.byref(r.fit) if r.have_fit else None,
                               C.byref(qo), C.byref(q), C.byref(d))
        _check(rc, d, "adequacy")
        a = q.contents
        out = Adequacy()
        out.verdict = {0: "valid", 1: "bounds", 2: "doubtful",
                       3: "not_valid"}[a.verdict]
        out.still = bool(a.still) if a.still_tested else None
        out.contrast = a.contrast
        out.fit_rejected = bool(a.fit_rejected) if a.have_fit else None
        out.fit_p_value = a.fit_p_value
        out.fit_p_value_bound = bool(_c.noise_p_is_bound(a.fit_p_value))
        out.stationary = bool(a.stationary) if a.stationarity_tested \
            else None
        out.requested = _term_names(a.requested)
        out.established = _term_names(a.established)
        out.doubtful = _term_names(a.doubtful)
        out.findings = []
        for i in range(a.n_findings):
            f = a.findings[i]
            out.findings.append({
                "cause": _c.adequacy_cause_name(f.cause).decode(),
                "severity": _c.adequacy_severity_name(f.severity).decode(),
                "terms": _term_names(f.terms),
                "t_start_s": f.t_start_s, "t_end_s": f.t_end_s,
                "tau_min_s": f.tau_min_s, "tau_max_s": f.tau_max_s,
                "statistic": f.statistic, "p_value": f.p_value,
                "action_s": f.action_s,
                "message": f.message.decode(errors="replace")})
        dv = a.davar
        out.davar = None
        if dv.n_win:
            nw, nt = dv.n_win, dv.n_tau
            out.davar = {
                "window_s": dv.window_s, "step_s": dv.step_s,
                "t_s": np.ctypeslib.as_array(dv.t_s, (nw,)).copy(),
                "tau_s": np.ctypeslib.as_array(dv.tau_s, (nt,)).copy(),
                "dev": np.ctypeslib.as_array(dv.dev, (nw * nt,)).copy()
                .reshape(nw, nt),
                "edf": np.ctypeslib.as_array(dv.edf, (nw * nt,)).copy()
                .reshape(nw, nt),
                "model": np.ctypeslib.as_array(dv.model, (nt,)).copy()}
        out.noise = None
        if r.have_fit:
            units = _si_units(quantity)
            out.noise = {t: Coef(r.fit.coef[i], units[i])
                         for i, t in enumerate(_TERMS)}
        return out
    finally:
        del keep, tkeep
        if q:
            _c.adequacy_free(q)
        _c.allan_result_free(res)


__all__ += ["adequacy", "Adequacy"]


# ------------------------------------------------------------ datasheet

_DS_TERMS = {1: "N", 2: "B", 3: "K"}   # enum sscope_term


def _ds_lines(fn, lines, noise_bandwidth, quantity):
    """{key: value} -> [(line index, SI value, info)]: a value is a number
    in SI or a string with its unit, checked against the line's dimension
    for a gyro ("angular rate") or an accelerometer ("acceleration")."""
    if not isinstance(lines, dict) or not lines:
        _bad(fn, "lines", "a dict of datasheet lines, e.g. "
             "{'noise_density': '0.014 deg/s/sqrt(Hz)'}")
    rate_unit = {"angular rate": "rad/s", "acceleration": "m/s^2"}.get(
        quantity)
    if rate_unit is None:
        _bad(fn, "quantity", "'angular rate' or 'acceleration'")
    out = []
    for key, v in lines.items():
        li = _c.datasheet_line_by_key(_b(key))
        if li < 0:
            _bad(fn, "lines", "'%s' is not a datasheet line" % key)
        info = _c.datasheet_info(li).contents
        suffix = info.si_suffix.decode()
        si_unit = "1" if suffix == "1" else rate_unit + suffix
        if isinstance(v, str):
            parts = v.strip().split(None, 1)
            if len(parts) != 2:
                _bad(fn, "lines", "%s = %s: a unit is needed" % (key, v))
            r = C.c_double()
            try:
                num = float(parts[0])
            except ValueError:
                _bad(fn, "lines", "%s = %s: not a number" % (key, v))
            if _c.convert(num, _b(parts[1]), _b(si_unit), C.byref(r)):
                _bad(fn, "lines", "%s = %s: '%s' is not a unit of %s" %
                     (key, v, parts[1], key))
            val = r.value
        else:
            val = _number(fn, key, v)
        if not (val > 0 and math.isfinite(val)):
            _bad(fn, "lines", "%s must be positive" % key)
        if key == "rms_noise" and noise_bandwidth is None:
            _bad(fn, "noise_bandwidth", "rms_noise needs the noise bandwidth")
        out.append((li, val, info))
    return out


def datasheet_terms(lines, quantity="angular rate", noise_bandwidth=None):
    """The IEEE 952 terms of datasheet lines (the keys of `sensorscope
    datasheet`: noise_density, random_walk, rms_noise, bias_instability,
    in_run_bias_stability, rate_random_walk, ...), each value a number in
    SI or a string with its unit ("0.15 deg/sqrt(h)"); noise_bandwidth in
    Hz for rms_noise.  Returns {"N", "B", "K"} in SI (None when no line
    gives the term), from the first line of each in the library's order."""
    fn = "datasheet_terms"
    bw = float("nan") if noise_bandwidth is None else \
        _positive(fn, "noise_bandwidth", noise_bandwidth)
    got = sorted(_ds_lines(fn, lines, noise_bandwidth, quantity),
                 key=lambda t: t[0])
    out = {"N": None, "B": None, "K": None}
    for li, val, info in got:
        t = _DS_TERMS.get(info.term)
        f = C.c_double()
        if t is None or out[t] is not None or \
                _c.datasheet_factor(li, bw, C.byref(f)):
            continue
        out[t] = val / f.value
    return out


def datasheet_gjb(x, rate, tau=10.0, ci=0.99):
    """GJB 2426A bias stability of x (samples at `rate` Hz): the 1 sigma of
    consecutive non-overlapping `tau`-second means, with its chi-squared
    interval at `ci`.  Returns {"value", "lo", "hi", "n_means", "m"}."""
    fn = "datasheet_gjb"
    rate = _positive(fn, "rate", rate)
    tau = _positive(fn, "tau", tau)
    ci = _level(fn, "ci", ci)
    p, stride, n, keep = _vector(x, fn, "x")
    g = _c.DatasheetGjb()
    d = _c.Diag()
    rc = _c.datasheet_gjb(p, stride, n, rate, tau, float(ci), C.byref(g),
                          C.byref(d))
    del keep
    _check(rc, d, fn)
    return {"value": g.value, "lo": g.lo, "hi": g.hi, "n_means": g.n_means,
            "m": g.m}


def datasheet_check(x, rate, lines, quantity="angular rate",
                    noise_bandwidth=None, ci=0.99):
    """x (a stationary record at `rate` Hz, SI) against datasheet lines (as
    datasheet_terms()): per line {"key", "limit", "value", "lo", "hi",
    "bound", "verdict", "why"} in SI, the verdict "within spec", "out of
    spec" or "inconclusive", guard-banded by the interval at `ci` (as
    `sensorscope datasheet --check`).  A value the record cannot establish
    is None, with the reason in "why"; "fit_rejected" flags a term line
    whose noise fit the chi-squared test rejects (indicative only)."""
    fn = "datasheet_check"
    rate = _positive(fn, "rate", rate)
    bw = float("nan") if noise_bandwidth is None else \
        _positive(fn, "noise_bandwidth", noise_bandwidth)
    got = _ds_lines(fn, lines, noise_bandwidth, quantity)
    spec = (_c.DatasheetSpec * len(got))()
    for i, (li, val, _info) in enumerate(got):
        spec[i].line, spec[i].value, spec[i].bandwidth_hz = li, val, bw
    res = (_c.DatasheetCheck * len(got))()
    o = _c.DatasheetOpts()
    o.level = _level(fn, "ci", ci)
    p, stride, n, keep = _vector(x, fn, "x")
    d = _c.Diag()
    rc = _c.datasheet_check(p, stride, n, rate, spec, len(got), C.byref(o),
                            res, C.byref(d))
    del keep
    _check(rc, d, fn)

    def num(v):
        return None if math.isnan(v) else v

    return [{"key": info.key.decode(), "limit": r.limit,
             "value": num(r.value), "lo": num(r.lo), "hi": num(r.hi),
             "bound": bool(r.bound),
             "verdict": _c.datasheet_verdict_name(r.verdict).decode(),
             "why": r.why.decode() if r.why else None,
             "fit_rejected": bool(r.fit_rejected)}
            for r, (_li, _v, info) in zip(res, got)]


__all__ += ["datasheet_terms", "datasheet_gjb", "datasheet_check"]


# ------------------------------------------------------------ lot
def lot_spread(values, se, level=0.90, outlier_alpha=0.01,
               keep_outliers=False):
    """The spread of a quantity over a lot of units: `values` (one estimate
    per unit) with their standard errors `se` (> 0), in the random-effects
    model value = mean + unit effect (sd `between_sd`) + measurement error
    (sd se).  Returns a dict: "mean" with its Hartung-Knapp interval
    ("mean_lo", "mean_hi"), "between_sd" (REML) with its Q-profile interval
    ("between_lo", "between_hi"; "between_note" says why when that interval
    is [0, 0]), "total_sd" (the plain sd of the values),
    Cochran's "q" and "q_p", "i2", the robust "z" of each unit and the
    indices of the "outliers" flagged at `outlier_alpha` per unit; the
    estimates leave out the units beyond the family-wise level ("k_used"
    of "k") unless `keep_outliers` (as the command's lot)."""
    fn = "lot_spread"
    y = np.ascontiguousarray(values, dtype=float).ravel()
    s = np.ascontiguousarray(se, dtype=float).ravel()
    if y.size != s.size:
        _bad(fn, "se", "one standard error per value (%d values, %d errors)"
             % (y.size, s.size))
    if y.size < 3:
        _bad(fn, "values", "%d unit%s: the spread needs at least 3"
             % (y.size, "" if y.size == 1 else "s"))
    for arg, a in (("values", y), ("se", s)):
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            _bad(fn, arg, "%s at index %d is not a finite number"
                 % (_text(a[bad[0]]), bad[0]))
    bad = np.flatnonzero(s <= 0)
    if bad.size:
        _bad(fn, "se", "%s at index %d: a standard error is positive"
             % (_text(s[bad[0]]), bad[0]))
    # squares and weights of these must stay finite and non-zero
    bad = np.flatnonzero((s < 1e-150) | (s > 1e150))
    if bad.size:
        _bad(fn, "se", "%s at index %d is beyond 1e-150 .. 1e150 (give the "
             "values and errors in a unit that brings them near 1)"
             % (_text(s[bad[0]]), bad[0]))
    bad = np.flatnonzero(np.abs(y) > 1e150)
    if bad.size:
        _bad(fn, "values", "%s at index %d is beyond 1e150 in magnitude"
             % (_text(y[bad[0]]), bad[0]))
    level = _number(fn, "level", level)
    if not 0 < level < 1:
        _bad(fn, "level", "%s is not a level between 0 and 1 (e.g. 0.90)"
             % _text(level))
    outlier_alpha = _number(fn, "outlier_alpha", outlier_alpha)
    if not 0 < outlier_alpha < 1:
        _bad(fn, "outlier_alpha", "%s is not between 0 and 1 (e.g. 0.01)"
             % _text(outlier_alpha))
    o = _c.LotOpts()
    o.level = level
    o.outlier_alpha = outlier_alpha
    o.keep_outliers = bool(keep_outliers)
    r = _c.LotSpread()
    z = np.empty(y.size)
    fl = (C.c_bool * max(1, y.size))()
    dp = C.POINTER(C.c_double)
    rc = _c.lot_spread(y.ctypes.data_as(dp), s.ctypes.data_as(dp), y.size,
                       C.byref(o), C.byref(r), z.ctypes.data_as(dp), fl)
    _check(rc, None, fn)
    out = {k: getattr(r, k) for k, _t in _c.LotSpread._fields_}
    # an empty Q-profile set: the units agree better than their own
    # errors imply, and the interval [0, 0] says only that
    out["between_note"] = (
        "the units agree better than their own standard errors imply: no "
        "spread between them can be told" if r.between_hi == 0 else None)
    out["z"] = z
    out["outliers"] = [i for i in range(y.size) if fl[i]]
    return out


__all__ += ["lot_spread"]


_LOT_TERMS = ("N", "B", "K", "bias", "bias_drift", "temp_sensitivity")
_LOT_MODEL = ("random effects: each unit's value = mean + unit effect (sd "
              "between_sd) + its own measurement error (sd from its 68.3 % "
              "interval); between_sd by REML with its Q-profile interval "
              "(Viechtbauer 2007), the mean by Hartung-Knapp; units beyond "
              "the family-wise outlier level left out")
# the conservative se's flag (src/workbench/lot.h SSC_LOT_SE_UPPER_RATIO)
_LOT_SE_UPPER_RATIO = 1.5


def _lot_upper(a, key):
    """A term's upper bound as the lot command takes it: the upper end of
    its interval, the fit's bound where not shown, inf where none."""
    k = a.noise[key] if a.noise else None
    return k.hi if k is not None and k.hi > 0 else math.inf


def _lot_upper_doubt(model):
    """The command's reason for a conservative se above 1.5 times the
    reported one (src/workbench/lot.c cell_doubt())."""
    nb, nk = not model[1] > 0, not model[2] > 0
    tail = ("would make this interval more than 1.5 times wider (%sthe "
            "verdicts use that wider interval): record longer, or take %s "
            "from a longer record of the model or its datasheet")
    if nb and nk:
        return ("the record cannot rule out flicker (B) or a rate random "
                "walk (K) that " + tail % ("each at the fit's upper bound; ",
                                           "B and K"))
    if not nb and not nk:
        return ("B and K at the upper ends of their intervals "
                + tail % ("", "B and K"))
    if nk:
        return ("the record cannot rule out a rate random walk (K) that "
                + tail % ("K at the fit's upper bound; ", "K"))
    return ("the record cannot rule out flicker (B) that "
            + tail % ("B at the fit's upper bound; ", "B"))


_LOT_BIAS_METHOD = (
    "batch means: the record cut into bias_blocks equal blocks, their means "
    "fitted by least squares as bias + bias_drift (t - t_mean) + "
    "temp_sensitivity (T - T_mean), t the block centres, T the blocks' mean "
    "temperatures (without a temperature column, no T term); bias is the "
    "mean of the record; standard errors from the residuals, Student-t "
    "68.3 % intervals with bias_blocks - 3 degrees of freedom (- 2 without "
    "temperature); where the unit's noise model (N, B, K the allan fit "
    "shows in the record less its fitted temperature effect) has B or K, "
    "the drift's and temperature sensitivity's standard errors are the "
    "larger of the residuals' and the noise model's (the variance of their "
    "weights "
    "on the block means under white, flicker and random-walk rate noise; "
    "normal quantile; se_from says which); se_upper is a conservative "
    "standard error of the drift and the temperature sensitivity, the "
    "largest of se and the noise model's with B, then K, at its upper "
    "bound (the fit's bound of a term it does not show, the upper end of "
    "the interval of one it shows; \"inf\" where the record gives no "
    "finite bound): where it exceeds se more than 1.5 "
    "times, doubt says so and which term, and a verdict against a drift or "
    "temperature-sensitivity limit always uses the interval of se_upper "
    "(normal quantile); where temperature follows time "
    "(temperature.time_corr "
    "near -1 or 1) drift and temperature sensitivity cannot be told apart "
    "and both intervals are wide")


def _lot_manifest(path):
    """The units of a manifest (a CSV file whose header names the columns
    unit and file, optionally channels and temperature) as (path, name,
    channels, temperature column) tuples, or None for another file."""
    import csv
    import os
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f, skipinitialspace=True))
    except (OSError, UnicodeDecodeError):
        return None
    if not rows:
        return None
    head = [h.strip().lower() for h in rows[0]]
    if "unit" not in head or "file" not in head:
        return None
    col = {k: head.index(k) if k in head else None
           for k in ("unit", "file", "channels", "temperature")}
    here = os.path.dirname(path) or "."
    out = []
    for r in rows[1:]:
        if not r or not "".join(r).strip() or r[0].startswith("#"):
            continue

        def get(k):
            i = col[k]
            return r[i].strip() if i is not None and i < len(r) and \
                r[i].strip() else None
        if not get("unit") or not get("file"):
            raise ArgumentError("lot: %s: a unit and a file are needed"
                                % path)
        ch = get("channels")
        out.append((os.path.join(here, get("file")), get("unit"),
                    ",".join(ch.replace(";", " ").split()) if ch else None,
                    get("temperature")))
    return out


def _lot_files(files):
    """(path, name or None, channels or None, temperature column or
    None) of each unit: folders stand for their capture files, sorted,
    manifests for their units."""
    import os
    if isinstance(files, (str, bytes, os.PathLike)):
        files = [files]
    skip = (".ini", ".md", ".json", ".yaml", ".yml", ".svg", ".png",
            ".html")
    out = []
    for f in files:
        f = os.fspath(f)
        if os.path.isdir(f) and \
                not os.path.exists(os.path.join(f, "metadata.yaml")):
            out += [(os.path.join(f, e), None, None, None)
                    for e in sorted(os.listdir(f))
                    if not e.startswith(".") and
                    not e.lower().endswith(skip) and
                    os.path.isfile(os.path.join(f, e))]
        else:
            m = _lot_manifest(f) if os.path.isfile(f) else None
            out += m if m is not None else [(f, None, None, None)]
    return out


def _lot_conv(si, q, t):
    """(value, unit) of term index t (see _LOT_TERMS) of quantity code q in
    its conventional unit, as the lot command shows it."""
    st = 4 if t == 4 else 2 if t >= 3 else 1 + t   # R, B, or N..K
    si_u = _c.term_si_unit(q, st).decode()
    u = _c.term_unit(q, st).decode()
    r = C.c_double(si)
    ok = math.isfinite(si) and \
        _c.convert(si, _b(si_u), _b(u), C.byref(r)) == 0
    unit = u if ok or not math.isfinite(si) else si_u
    if not math.isfinite(si):
        # the unit of a missing value: as the command, the conventional
        # one when 1 converts
        one = C.c_double()
        unit = u if _c.convert(1.0, _b(si_u), _b(u), C.byref(one)) == 0 \
            else si_u
    if t == 5:
        unit = {3: ("deg/h/degC", "rad/s/degC"),
                4: ("ug/degC", "m/s^2/degC")}[q][unit == si_u]
    return (r.value if ok else si), unit


def _num(v):
    return float(v) if math.isfinite(v) else None


def lot(files, level=0.90):
    """Many units of one model, one capture each (as `sensorscope lot`
    FILE..., a FOLDER or a MANIFEST.csv with columns unit, file[, channels]
    [, temperature]): every gyro and accelerometer channel's N, B, K (the
    allan fit, 68.3 % intervals), bias, drift and temperature sensitivity
    (batch means) and per channel and term the lot's
    spread (lot_spread() at `level`).  Returns the command's JSON object
    as a dict (without --spec; "path" as given).  A folder stands for its
    capture files, sorted; a manifest for its units (files relative to
    it)."""
    fn = "lot"
    ops = _lot_files(files)
    paths = [p for p, _n, _c, _t in ops]
    if len(paths) < 3:
        _bad(fn, "files", "a lot needs at least 3 units (captures), got %d"
             % len(paths))
    level = _number(fn, "level", level)
    if not 0 < level < 1:
        _bad(fn, "level", "a level between 0 and 1")
    import os
    # one unit's record in memory at a time (as the command)
    first = load(ops[0][0], columns=ops[0][2], temp_column=ops[0][3])
    qcode = {"angular rate": 3, "acceleration": 4}
    chans = [(n, first.quantities[n]) for n in first
             if first.quantities[n] in qcode]
    if not chans:
        raise Error(-errno.EDOM, "%s: no angular-rate or acceleration channel"
                    % paths[0])
    temp = first.temp_degc is not None
    U, NT = len(ops), len(_LOT_TERMS)
    cells, constant = {}, {}
    for u, (path, _n, cols, tcol) in enumerate(ops):
        cap = first if u == 0 else load(path, columns=cols, temp_column=tcol)
        first = None
        if not cap.rate_hz:
            raise Error(-errno.EDOM, "%s: no sample rate: %s"
                        % (paths[u], cap.rate_note or
                           "no time column and no '# rate:' comment"))
        if (cap.temp_degc is not None) != temp:
            raise Error(-errno.EDOM, "%s: %s temperature column, but %s %s"
                        % (paths[u], "no" if temp else "a", paths[0],
                           "has one" if temp else "has none"))
        for c, (name, q) in enumerate(chans):
            if cap.quantities.get(name) != q:
                raise Error(-errno.EDOM, "%s: no channel '%s' of the same "
                            "quantity as in %s" % (paths[u], name, paths[0]))
            x = np.ascontiguousarray(cap[name], dtype=float)
            fin = x[np.isfinite(x)]
            constant[u, c] = bool(fin.size and np.all(fin == fin[0]))
            a = allan(x, cap.rate_hz, taus="dense", ci=0.682689492137086)
            v, se, pres = [math.nan] * NT, [math.nan] * NT, [False] * NT
            lo, hi = [math.nan] * NT, [math.nan] * NT
            # the terms' upper bounds: the upper end of the interval,
            # the fit's bound where not shown (none: inf), as the command
            model_hi = [_lot_upper(a, key) for key in ("N", "B", "K")]
            for t, key in enumerate(("N", "B", "K")):
                k = a.noise[key] if a.noise else None
                if k is not None and k.present and math.isfinite(k.value) \
                        and math.isfinite(k.lo) and math.isfinite(k.hi) \
                        and k.hi > k.lo:
                    pres[t] = True
                    v[t], lo[t], hi[t] = k.value, k.lo, k.hi
                    se[t] = 0.5 * (k.hi - k.lo)
            b = _c.LotBias()
            o = _c.LotBiasOpts(20, 0.0, 0.0, 0.0, 0.0)
            dp = C.POINTER(C.c_double)
            tp = None
            if temp:
                tt = np.ascontiguousarray(cap.temp_degc, dtype=float)
                tp = tt.ctypes.data_as(dp)
            rc = _c.lot_bias(x.ctypes.data_as(dp), 1, x.size, cap.rate_hz,
                             tp, 1, C.byref(o), C.byref(b))
            _check(rc, None, fn)
            # the noise model of the drift's and sensitivity's intervals:
            # the terms the fit of the record less its temperature effect
            # shows (as the command)
            model = [v[t] if pres[t] else 0.0 for t in range(3)]
            if b.have_temp:
                r = np.empty(x.size)
                _check(_c.lot_temp_removed(x.ctypes.data_as(dp), 1, x.size, tp,
                                           1, C.byref(b),
                                           r.ctypes.data_as(dp)), None, fn)
                ar = allan(r, cap.rate_hz, taus="dense",
                           ci=0.682689492137086)
                model_hi = [_lot_upper(ar, key) for key in ("N", "B", "K")]
                for t, key in enumerate(("N", "B", "K")):
                    k = ar.noise[key] if ar.noise else None
                    model[t] = k.value if (
                        k is not None and k.present and
                        math.isfinite(k.value) and math.isfinite(k.lo) and
                        math.isfinite(k.hi) and k.hi > k.lo) else 0.0
            if model[1] > 0 or model[2] > 0 or model_hi[1] > 0 or \
                    model_hi[2] > 0:
                o = _c.LotBiasOpts(20, 0.0, *model, model_hi[1], model_hi[2])
                rc = _c.lot_bias(x.ctypes.data_as(dp), 1, x.size,
                                 cap.rate_hz, tp, 1, C.byref(o), C.byref(b))
                _check(rc, None, fn)
            for t, (val, s, l, h) in enumerate((
                    (b.bias, b.bias_se, b.bias_lo, b.bias_hi),
                    (b.drift_u_s, b.drift_se, b.drift_lo, b.drift_hi),
                    (b.tempco_u_degc, b.tempco_se, b.tempco_lo,
                     b.tempco_hi)), start=3):
                v[t], se[t], lo[t], hi[t] = val, s, l, h
                pres[t] = math.isfinite(val) and s > 0
            cells[u, c] = (v, lo, hi, se, pres, b, cap.rate_hz, model)
    terms = {}
    for c, (name, q) in enumerate(chans):
        for t in range(NT):
            idx = [u for u in range(U) if cells[u, c][4][t]]
            z = [math.nan] * U
            fl = [False] * U
            sp = None
            if len(idx) >= 3:
                try:
                    sp = lot_spread([cells[u, c][0][t] for u in idx],
                                    [cells[u, c][3][t] for u in idx],
                                    level=level)
                except (Error, ArgumentError):
                    sp = None
            if sp is not None:
                for i, u in enumerate(idx):
                    z[u] = float(sp["z"][i])
                for i in sp["outliers"]:
                    fl[idx[i]] = True
            terms[c, t] = (len(idx), sp, z, fl)
    units = []
    for u in range(U):
        chs = []
        for c, (name, q) in enumerate(chans):
            v, lo, hi, se, pres, b, fs, model = cells[u, c]
            qc = qcode[q]
            jt = {}
            for t, key in enumerate(_LOT_TERMS):
                val, unit = _lot_conv(v[t], qc, t)
                e = {"present": pres[t], "value": _num(val),
                     "lo": _num(_lot_conv(lo[t], qc, t)[0]),
                     "hi": _num(_lot_conv(hi[t], qc, t)[0]), "unit": unit}
                if t >= 3:
                    e["se"] = _num(_lot_conv(se[t], qc, t)[0])
                e["z"] = _num(terms[c, t][2][u])
                e["outlier"] = terms[c, t][3][u]
                if t in (4, 5) and pres[t]:
                    e["se_from"] = "noise model" if (
                        b.drift_se_from_model if t == 4 else
                        b.tempco_se_from_model) else "residuals"
                # the command's doubt: correlated block means that the
                # unit's noise model (B, K) does not account for
                if t in (4, 5) and pres[t] and b.resid_correlated \
                        and not model[1] > 0 and not model[2] > 0:
                    e["doubt"] = (
                        "the block means' residuals are correlated (the "
                        "bias wanders) but the unit's fit shows neither B "
                        "nor K: the interval takes them as independent "
                        "and is too narrow")
                if t in (4, 5):
                    su = (b.drift_se_upper if t == 4 else b.tempco_se_upper) \
                        if pres[t] else math.nan
                    e["se_upper"] = "inf" if math.isinf(su) else \
                        _num(_lot_conv(su, qc, t)[0])
                    if "doubt" not in e and pres[t] and \
                            su > _LOT_SE_UPPER_RATIO * se[t]:
                        e["doubt"] = _lot_upper_doubt(model)
                jt[key] = e
            jc = {"name": name, "terms": jt, "bias_blocks": b.blocks,
                  "block_s": b.block_n / fs,
                  "residual_lag1": _num(b.resid_lag1),
                  "constant": constant[u, c],
                  "temperature": {"mean_degc": _num(b.temp_mean_degc),
                                  "span_degc": _num(b.temp_span_degc),
                                  "time_corr": _num(b.temp_time_corr)}
                  if b.have_temp else None}
            chs.append(jc)
        units.append({"unit": ops[u][1] or os.path.basename(paths[u]),
                      "path": paths[u], "channels": chs})
    between, outliers = [], []
    for c, (name, q) in enumerate(chans):
        qc = qcode[q]
        for t, key in enumerate(_LOT_TERMS):
            k, sp, z, fl = terms[c, t]
            e = {"channel": name, "term": key,
                 "unit": _lot_conv(1.0, qc, t)[1], "units": U,
                 "units_resolved": k}
            if sp is None:
                e["why"] = ("no temperature column: no temperature "
                            "sensitivity" if t == 5 and not temp else
                            "fewer than 3 units show the term: no spread")
                between.append(e)
                continue

            def cv(x):
                return _num(_lot_conv(x, qc, t)[0])
            # N, B, K are amplitudes: the interval of their mean cut at 0
            cut = t <= 2 and sp["mean_lo"] < 0
            e.update({"units_used": sp["k_used"], "mean": cv(sp["mean"]),
                      "mean_lo": cv(0.0 if cut else sp["mean_lo"]),
                      "mean_lo_cut": bool(cut),
                      "mean_hi": cv(sp["mean_hi"]),
                      "between_sd": cv(sp["between_sd"]),
                      "between_sd_lo": cv(sp["between_lo"]),
                      "between_sd_hi": cv(sp["between_hi"]),
                      "total_sd": cv(sp["total_sd"]),
                      "q_p_value": _num(sp["q_p"]), "i2": _num(sp["i2"]),
                      "outlier_z": _num(sp["outlier_z"]), "outliers": []})
            for u in range(U):
                if fl[u]:
                    base = ops[u][1] or os.path.basename(paths[u])
                    e["outliers"].append(base)
                    outliers.append({"unit": base, "channel": name,
                                     "term": key, "z": _num(z[u])})
            between.append(e)
    return {"command": "lot", "level": level, "model": _LOT_MODEL,
            "bias_method": _LOT_BIAS_METHOD, "units": units,
            "between": between, "outliers": outliers}


__all__ += ["lot"]


# ------------------------------------------------------------ exports

def export_targets():
    """The names export() takes: kalibr, imu_utils, openvins, vins,
    orbslam3, basalt, gtsam, matlab, gnss_ins_sim, gazebo."""
    out, i = [], 0
    while _c.export_target(i):
        out.append(_c.export_target(i).decode())
        i += 1
    return out


_QCODE = {"angular rate": 3, "acceleration": 4}


def _export_channels(fn, source, rate):
    """[(name, Channel-or-array, quantity, unit)], rate, temperature, name,
    topic from a Capture or a dict of channels."""
    if isinstance(source, Capture):
        if rate is not None:
            _bad(fn, "rate", "a Capture has its own rate (%s Hz)"
                 % _text(source.rate_hz))
        if not source.rate_hz:
            _bad(fn, "source", "%s has no sample rate (%s)"
                 % (source.path, source.rate_note or
                    "no time column and no '# rate:' comment"))
        chans = [(k, source[k], source.quantities[k], source[k].unit)
                 for k in source]
        topic = next((t["name"] for t in source.topics if t["selected"] and
                      "Temperature" not in t["type"]), None)
        return chans, source.rate_hz, source.temp_degc, source.path, topic
    if not isinstance(source, dict) or not source:
        _bad(fn, "source", "a Capture (from load()) or a dict of channels "
             "{'gx': array, ...}, not %s" % type(source).__name__)
    rate = _positive(fn, "rate", rate) if rate is not None else None
    if rate is None:
        _bad(fn, "rate", "a dict of channels needs rate= (Hz)")
    chans = []
    for k, x in source.items():
        q, unit, assumed = _data_unit(fn, x, None, "rate")
        if assumed:
            _warn(fn, "%s: no unit (not a Channel of a loaded capture): "
                  "rad/s assumed" % k)
        chans.append((str(k), x, q, unit))
    return chans, rate, None, "data", None


def export(source, target, path=None, inflate=1.0, force=False, rate=None,
           name=None):
    """Noise parameters for an estimator or simulator, as
    `sensorscope allan --export TARGET` writes them: the same text.

    Parameters
    ----------
    source : Capture or dict
        A loaded capture (every angular-rate and acceleration channel is
        analysed: OADEV on the dense grid, the IEEE 952 fit with 68.3 %
        intervals, the adequacy check with the capture's temperature), or
        a dict {name: samples} of one sensor's channels in SI units
        (Channels of a capture carry their unit; a plain array is taken
        as rad/s, with a warning) with rate=.
    target : str
        One of export_targets(): kalibr, imu_utils, openvins, vins,
        orbslam3, basalt, gtsam, matlab, gnss_ins_sim, gazebo.  Each
        file's leading comment states its convention (continuous or
        discrete, units, what its "random walk" is).
    path : str, optional
        Write the file there, atomically (nothing is written when the
        export is refused).  None: only return the text.
    inflate : float
        Multiplies every value (the file names the command's --inflate);
        default 1, the measured values.
    force : bool
        Write values the adequacy check doubts (the record moves, the fit
        is rejected, a warm-up, step or temperature drift biases them),
        each marked in a comment (the file says --force).
    rate : float
        Sample rate in Hz, for a dict source only.
    name : str, optional
        The sensor's name (imu_utils' `name`), default "imu".

    Returns
    -------
    str
        The file's text.  A term the record does not establish is written
        as its upper bound, marked in the file, with a RuntimeWarning; a
        value is never written as 0.  NaN samples (gaps) are refused.

    Raises
    ------
    ArgumentError for a bad argument; Error when the export is refused
    (the reason in one line: a doubtful value without force, a sensor
    the file needs missing, no value or bound for a term)."""
    fn = "export"
    names = export_targets()
    if not isinstance(target, str) or not _c.export_name(_b(target)):
        _bad(fn, "target", "'%s' is not %s" % (target, ", ".join(names)))
    target = _c.export_name(_b(target)).decode()
    inflate = _positive(fn, "inflate", inflate)
    if not 1 <= inflate <= 1000:
        _bad(fn, "inflate", "%s is not a factor from 1 to 1000 (a margin "
             "widens the noise values, never narrows them)" % _text(inflate))
    if name is not None and not isinstance(name, str):
        _bad(fn, "name", "'%s' is not a sensor name (a string)" % (name,))
    chans, rate, temp, src, topic = _export_channels(fn, source, rate)
    chans = [c for c in chans if c[2] in _QCODE]
    keep, res, adq = [], [], []
    try:
        tkeep = None
        if temp is not None:
            tp, tstride, tn, tkeep = _vector(temp, fn, "temperature")
        n_max = 0
        for cname, x, q, unit in chans:
            p, stride, n, k = _vector(x, fn, cname)
            keep.append(k)
            bad = ~np.isfinite(np.asarray(x))
            if bad.any():
                raise Error(-errno.EDOM, "%s: %s: %s sample at index %d (an "
                            "export needs a record without gaps)" % (
                                fn, cname, "NaN" if np.isnan(
                                    np.asarray(x)[np.argmax(bad)]) else
                                "infinite", int(np.argmax(bad))))
            n_max = max(n_max, n)
            ao = _c.AllanOpts()
            ao.ci_level = 0.683
            fo = _c.NoiseFitOpts()
            fo.ci_level = 0.683
            fo.plan = _noise_plan()
            r = C.POINTER(_c.AllanResult)()
            d = _c.Diag()
            rc = _c.allan_analyze(p, stride, n, float(rate), _GRIDS["dense"],
                                  C.byref(ao), C.byref(fo), C.byref(r),
                                  C.byref(d))
            _check(rc, d, "%s: %s" % (fn, cname))
            res.append(r)
            adq.append(C.POINTER(_c.Adequacy)())
        # the adequacy check of each channel; when one inertial channel
        # moves, the others again saying so (as the command does)
        moving = None
        for again in (False, True):
            for i, (cname, x, q, unit) in enumerate(chans):
                a = adq[i].contents if adq[i] else None
                if again and (moving is None or i == moving[0] or a is None
                              or not a.still):
                    continue
                p, stride, n, _k = _vector(x, fn, cname)
                qo = _c.AdequacyOpts()
                qo.rate_hz = float(rate)
                qo.unit = _b(_c.quantity_si_unit(_QCODE[q]).decode())
                if temp is not None:
                    qo.temp_degc = tp
                    qo.temp_stride = tstride
                if again:
                    qo.moving_channel = _b(chans[moving[0]][0])
                    qo.moving_contrast = moving[1]
                r = res[i].contents
                if adq[i]:
                    _c.adequacy_free(adq[i])
                    adq[i] = C.POINTER(_c.Adequacy)()
                d = _c.Diag()
                rc = _c.adequacy_check(p, stride, n,
                                       C.byref(r.fit) if r.have_fit else None,
                                       C.byref(qo), C.byref(adq[i]),
                                       C.byref(d))
                _check(rc, d, "%s: %s: adequacy check" % (fn, cname))
            if not again:
                for i in range(len(chans)):
                    a = adq[i].contents
                    if a.still_tested and not a.still:
                        moving = (i, a.contrast)
                        break
        arr = (_c.ExportChan * max(len(chans), 1))()
        for i, (cname, x, q, unit) in enumerate(chans):
            r = res[i].contents
            arr[i].name = _b(cname)
            arr[i].quantity = _QCODE[q]
            arr[i].fit = C.pointer(r.fit) if r.have_fit else None
            arr[i].adequacy = adq[i]
        o = _c.ExportOpts()
        o.rate_hz = float(rate)
        o.inflate = inflate
        o.source = _b(src)
        o.topic = _b(topic) if topic else None
        o.sensor_name = _b(name) if name else None
        o.duration_s = n_max / float(rate)
        o.force = bool(force)
        f = _c.ExportFile()
        d = _c.Diag()
        rc = _c.export(_b(target), arr, len(chans), C.byref(o), C.byref(f),
                       C.byref(d))
        if rc < 0:
            msg = d.msg.decode(errors="replace") or \
                _c.strerror(rc).decode()
            if f.forcible:
                msg += " (force=True writes it with each doubtful value " \
                    "marked)"
            raise Error(rc, "%s: %s: %s" % (fn, target, msg))
        try:
            text = C.string_at(f.text, f.len).decode()
            warn = C.string_at(f.warnings).decode() if f.warnings else ""
        finally:
            _c.export_file_free(C.byref(f))
    finally:
        for q in adq:
            if q:
                _c.adequacy_free(q)
        for r in res:
            _c.allan_result_free(r)
        del keep
    for line in warn.splitlines():
        _warn(fn, "%s: %s" % (target, line))
    if path is not None:
        import os
        path = os.fspath(path)
        tmp = "%s.%d.tmp" % (path, os.getpid())
        try:
            with open(tmp, "w") as fh:
                fh.write(text)
            os.replace(tmp, path)
        except OSError as e:
            try:
                os.unlink(tmp)
            except OSError:
                pass
            raise Error(-(e.errno or errno.EIO), "%s: %s: %s" % (
                fn, path, _c.strerror(e.errno).decode() if e.errno else e))
    return text


__all__ += ["export", "export_targets"]


_PLAN_TERMS = "QNBKR"


def plan(sensor_or_terms, resolve, rate, lengths=(3600.0, 10800.0, 21600.0,
                                                  43200.0, 86400.0),
         ci=None, probability=0.9, max_length=30 * 86400.0):
    """The record length for each term of `resolve` ({"B": 0.25, ...}: the
    relative half-width (hi - lo) / (2 value) wanted of its interval at
    level `ci`, default 0.6827 as the command) to be shown present by the noise fit and resolved to it
    with `probability`, and the probability at each of `lengths` (s), for
    a record at `rate` Hz, as `sensorscope plan`.  `sensor_or_terms`: a
    sensor spec INI path ([sensor] section) or a dict of IEEE 952 terms in
    SI ({"N": ..., "B": ..., "K": ...}; missing terms are 0).  Returns
    {"rate_hz", "ci_level", "probability_wanted", "terms": [{"term",
    "target", "needed_s" (inf when never), "never" (None or the reason),
    "lengths": [{"length_s", "probability", "p_present", "p_width",
    "rel_half_width"}]}]} -- the numbers of the command's JSON."""
    fn = "plan"
    rate = _positive(fn, "rate", rate)
    coef = (C.c_double * 5)()
    why = "the sensor spec has no %s (0)"
    if isinstance(sensor_or_terms, dict):
        for k, v in sensor_or_terms.items():
            if k not in _PLAN_TERMS:
                _bad(fn, "sensor_or_terms", "unknown term %r (Q N B K R)" % k)
            v = 0.0 if v is None else _number(fn, "sensor_or_terms", v)
            if not v >= 0:
                _bad(fn, "sensor_or_terms", "%s must be >= 0" % k)
            coef[_PLAN_TERMS.index(k)] = v
        why = "the terms give no %s"
    else:
        spec = _c.SensorSpec()
        d = _c.Diag()
        _check(_c.sensor_spec_load(_path(fn, "sensor_or_terms",
                                         sensor_or_terms), C.byref(spec),
                                   C.byref(d)), d, fn + ": sensor_or_terms")
        for i, k in enumerate("qnbkr"):
            coef[i] = getattr(spec, k)
    if not isinstance(resolve, dict) or not resolve:
        _bad(fn, "resolve", "a dict {term: relative half-width}, e.g. "
             "{'B': 0.25}")
    if ci is None:
        ci = 0.682689492137086
    o = _c.PlanOpts(_level(fn, "ci", ci, "0.683"),
                    _level(fn, "probability", probability, "0.9"), 3.0,
                    _positive(fn, "max_length", max_length))
    if isinstance(lengths, numbers.Real):
        lengths = [lengths]
    lens = [_positive(fn, "lengths", v) for v in lengths]
    terms = []
    for t, w in resolve.items():
        if t not in _PLAN_TERMS:
            _bad(fn, "resolve", "unknown term %r (Q N B K R)" % t)
        w = _positive(fn, "resolve", w)
        j = _PLAN_TERMS.index(t)
        need = C.c_double()
        _check(_c.plan_needed(coef, rate, j, w, C.byref(o), C.byref(need)),
               None, fn)
        pts = []
        for L in lens:
            p = _c.PlanPoint()
            _check(_c.plan_predict(coef, rate, L, j, w, C.byref(o),
                                   C.byref(p)), None, fn)
            pts.append({"length_s": p.length_s,
                        "probability": p.probability,
                        "p_present": p.p_present, "p_width": p.p_width,
                        "rel_half_width": p.rel_half_width})
        never = None
        if not need.value < float("inf"):
            never = (why % t) if coef[j] <= 0 else \
                "not reached within the longest record considered " \
                "(max_length)"
        terms.append({"term": t, "target": w, "needed_s": need.value,
                      "never": never, "lengths": pts})
    return {"rate_hz": rate, "ci_level": o.ci_level,
            "probability_wanted": o.probability, "terms": terms}


__all__ += ["plan"]
