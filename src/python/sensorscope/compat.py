# SPDX-License-Identifier: GPL-3.0-or-later
"""allantools' functions on sensorscope's engine.

    from sensorscope import compat as allantools
    (taus, devs, errs, ns) = allantools.oadev(y, rate=100.0,
                                              data_type="freq",
                                              taus="octave")

Each function takes allantools' arguments and returns its tuple:

data : array_like
    Phase in s (data_type="phase", the default) or fractional frequency
    (data_type="freq").  For a gyro, "freq" is a rate record (rad/s) and
    "phase" its angle (rad); the deviations are then in rad/s.
rate : float, default 1.0
    Sample rate in Hz.
data_type : {"phase", "freq"}
taus : None, "octave", "decade", "all" or array_like of float
    As allantools: None or [] is "octave" (tau = 2^k / rate), "decade"
    is {1, 2, 4} x 10^k samples, "all" every whole number of samples;
    an array holds taus in s, each rounded to the nearest whole number of
    samples (allantools' rule; sensorscope.allan() refuses instead).
    Taus beyond what the record supports are left out.

theo1 takes m = tau * rate (made even, 10 <= m) and returns the
effective tau = 0.75 m / rate, as Stable32 prints it; mtie and tierms
take the window of m + 1 samples, tau = m / rate.

Returns (taus, devs, errs, ns) as numpy arrays: the taus used (s), the
deviations, allantools' simple error estimate devs / sqrt(ns) (use
sensorscope.allan() for intervals from the equivalent degrees of
freedom), and ns, the number of terms averaged at each tau.  Points with
fewer than two terms are left out, as allantools does.  The numbers are
those of sensorscope.allan(..., m=...) at the same averaging factors.
"""

import numpy as np

from . import _capi as _c
from . import ArgumentError, _DEVS, _array, _input_kind, _points, \
    _positive

__all__ = ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev",
           "mtotdev", "htotdev", "ttotdev", "theo1", "mtie", "tierms"]


def _m_list(fn, taus, rate, n_phase, mmax):
    if taus is None or (not isinstance(taus, str) and
                        np.asarray(taus).size == 0):
        taus = "octave"
    if isinstance(taus, str):
        if taus == "octave":
            m = [1 << k for k in range(64) if (1 << k) <= mmax]
        elif taus == "decade":
            m = sorted({f * 10 ** k for k in range(20) for f in (1, 2, 4)
                        if f * 10 ** k <= mmax})
        elif taus == "all":
            m = list(range(1, mmax + 1))
        else:
            raise ArgumentError("%s: taus: '%s' is not octave, decade or "
                                "all, nor an array of taus in s" %
                                (fn, taus))
        return np.array(m, dtype=np.uint64)
    try:
        t = np.asarray(taus, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ArgumentError("%s: taus: '%s' is not octave, decade or all, "
                            "nor an array of taus in s" % (fn, taus))
    if not np.all(np.isfinite(t)) or np.any(t <= 0):
        raise ArgumentError("%s: taus: every tau must be a positive number "
                            "of seconds" % fn)
    m = np.unique(np.round(t * rate).astype(np.int64))
    m = m[(m >= 1) & (m <= mmax)]
    return m.astype(np.uint64)


def _deviation(fn, dev, data, rate, data_type, taus):
    rate = _positive(fn, "rate", rate)
    kind = _input_kind(fn, "rate", data_type)
    x = _array(data, fn, "data")
    n = x.shape[0]
    ao = _c.AllanOpts()
    ao.dev = _DEVS.index(dev)
    ao.input = {"rate": 0, "angle": 1}[kind]
    ao.ci_level = -1.0  # allantools' errors, not intervals
    ao.reject_nan = True
    n_phase = _c.allan_n_phase(ao.input, n)
    mmax = _c.allan_max_m(ao.dev, n_phase) if n_phase >= 3 else 0
    m = _m_list(fn, taus, rate, n_phase, mmax)
    if dev == "theo1":  # even factors from 10
        m = np.unique(m + (m % 2))
        m = m[(m >= 10) & (m <= mmax)]
    if m.size == 0:
        return (np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0))
    p = x.ctypes.data_as(_c.c_dptr)
    pts = _points(fn, p, x.strides[0] // 8, n, rate, ao, m)
    keep = pts["terms"] >= 2
    ns = pts["terms"][keep].astype(float)
    devs = pts["dev"][keep]
    return (pts["tau_s"][keep], devs, devs / np.sqrt(ns), ns)


def _define(name, what):
    def f(data, rate=1.0, data_type="phase", taus=None):
        return _deviation(name, name, data, rate, data_type, taus)
    f.__name__ = f.__qualname__ = name
    # its frames too (tracebacks; the function named by a GSL error)
    code = f.__code__.replace(co_name=name)
    if hasattr(code, "co_qualname"):
        code = code.replace(co_qualname=name)
    f.__code__ = code
    f.__doc__ = "%s, as allantools.%s (see the module's help)." % (what,
                                                                   name)
    return f


for _name, _what in (("adev", "Allan deviation (non-overlapping)"),
                     ("oadev", "Overlapping Allan deviation"),
                     ("mdev", "Modified Allan deviation"),
                     ("tdev", "Time deviation (s for phase data)"),
                     ("hdev", "Hadamard deviation (non-overlapping)"),
                     ("ohdev", "Overlapping Hadamard deviation"),
                     ("totdev", "Total deviation"),
                     ("mtotdev", "Modified total deviation"),
                     ("htotdev", "Hadamard total deviation"),
                     ("ttotdev", "Time total deviation (s for phase data)"),
                     ("theo1", "Theo1 deviation (tau = 0.75 m / rate)"),
                     ("mtie", "Maximum time interval error"),
                     ("tierms", "Rms time interval error")):
    globals()[_name] = _define(_name, _what)
