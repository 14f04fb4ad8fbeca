# SPDX-License-Identifier: GPL-3.0-or-later
"""OADEV of 1e7 samples: sensorscope.allan() against the C engine called
directly and an allantools-style numpy implementation (tests/bench-python.sh).
Exits 1 when the Python call costs more than 10 % over the C engine or is
not 30 times faster than the numpy reference, or the values differ."""

import ctypes as C
import math
import sys
import time

import numpy as np

import sensorscope as ss
from sensorscope import _capi as c

n, rate = 10_000_000, 100.0
x = np.random.default_rng(1).normal(0, 2.385, n)


def best(f, k=3):
    t = []
    r = None
    for _ in range(k):
        t0 = time.perf_counter()
        r = f()
        t.append(time.perf_counter() - t0)
    return min(t), r


def raw():
    res = C.POINTER(c.AllanResult)()
    ao, fo, d = c.AllanOpts(), c.NoiseFitOpts(), c.Diag()
    ao.ci_level = 0.683
    fo.ci_level = 0.683
    rc = c.allan_analyze(x.ctypes.data_as(c.c_dptr), 1, n, rate, 0,
                         C.byref(ao), C.byref(fo), C.byref(res), C.byref(d))
    assert rc == 0
    c.allan_result_free(res)


def numpy_oadev(y, rate, ms):
    phase = np.concatenate(([0.0], np.cumsum(y))) / rate
    out = []
    for m in ms:
        tau = m / rate
        d = phase[2 * m:] - 2 * phase[m:-m] + phase[:-2 * m]
        out.append(math.sqrt(np.sum(d * d) / (2 * len(d) * tau * tau)))
    return np.array(out)


# interleave the two so that the machine's load hits both alike
t_c = t_py = math.inf
for _ in range(3):
    t_c = min(t_c, best(raw, 1)[0])
    t, r = best(lambda: ss.allan(x, rate), 1)
    t_py = min(t_py, t)
t0 = time.perf_counter()
ref = numpy_oadev(x, rate, [int(m) for m in r.m])
t_np = time.perf_counter() - t0
err = float(np.max(np.abs(r.dev - ref) / ref))
print("OADEV of 1e7 samples, %d dense taus (intervals and fit included):"
      % len(r.m))
print("  C engine (direct call)      %.3f s" % t_c)
print("  sensorscope.allan (Python)  %.3f s  = %.3f x the C engine's time"
      % (t_py, t_py / t_c))
print("  allantools-style numpy      %.3f s  = %.1f x the time of "
      "sensorscope.allan" % (t_np, t_np / t_py))
print("  largest relative difference of the deviations: %.2e" % err)
sys.exit(0 if t_py <= 1.1 * t_c and t_np >= 30 * t_py and err < 1e-9
         else 1)
