# SPDX-License-Identifier: GPL-3.0-or-later
"""OADEV of 1e7 samples: sensorscope.allan() against the C engine called
directly and an allantools-style numpy implementation (tests/bench-python.sh).
Also sensorscope.allan() without the fit (and without intervals), which is
what allantools computes, beside the C engine without the fit.  The fit
keeps what depends only on the rate, length and taus in a plan
(sscope_noise_plan_new; the module keeps one per thread): the first call
fills it, the timed best of 3 reuses it, and the direct C call is given a
plan too; the first call's time is printed beside.  Wall and CPU times (CPU: less sensitive to other jobs on a shared machine)
are printed with the two speed criteria (Python within 10 % of the C
engine; 30 times faster than the numpy reference); it exits 1 only when the
values differ."""

import ctypes as C
import math
import sys
import time

import numpy as np

import sensorscope as ss
from sensorscope import _capi as c

n, rate = 10_000_000, 100.0
x = np.random.default_rng(1).normal(0, 2.385, n)


def timed(f):
    t0, c0 = time.perf_counter(), time.process_time()
    r = f()
    return time.perf_counter() - t0, time.process_time() - c0, r


plan = C.c_void_p()
assert c.noise_plan_new(C.byref(plan)) == 0


def raw(fit=True):
    res = C.POINTER(c.AllanResult)()
    ao, fo, d = c.AllanOpts(), c.NoiseFitOpts(), c.Diag()
    ao.ci_level = 0.683
    fo.ci_level = 0.683
    fo.skip = not fit
    fo.plan = plan if fit else None
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


# the first calls fill the plans
w_first, c_first, _r = timed(lambda: ss.allan(x, rate))
timed(raw)
# interleave the two so that the machine's load hits both alike
w_c = c_c = w_py = c_py = math.inf
for _ in range(3):
    w, c_, _r = timed(raw)
    w_c, c_c = min(w_c, w), min(c_c, c_)
    w, c_, r = timed(lambda: ss.allan(x, rate))
    w_py, c_py = min(w_py, w), min(c_py, c_)
w_np, c_np, ref = timed(lambda: numpy_oadev(x, rate, [int(m) for m in r.m]))
err = float(np.max(np.abs(r.dev - ref) / ref))
print("OADEV of 1e7 samples, %d dense taus (intervals and fit included), "
      "best of 3 (numpy: 1 run):" % len(r.m))
print("  %-28s %8s %8s" % ("", "wall s", "CPU s"))
print("  %-28s %8.3f %8.3f" % ("C engine (direct call)", w_c, c_c))
print("  %-28s %8.3f %8.3f" % ("sensorscope.allan (Python)", w_py, c_py))
print("  %-28s %8.3f %8.3f" % ("allantools-style numpy", w_np, c_np))
print("  %-28s %8.3f %8.3f   numpy / it: %.1f (wall), %.1f (CPU)" % (
    "  first call (plan filled)", w_first, c_first, w_np / w_first,
    c_np / c_first))
print("  Python / C engine: %.3f (wall), %.3f (CPU): %s" % (
    w_py / w_c, c_py / c_c,
    "within 10 %" if min(w_py / w_c, c_py / c_c) <= 1.1 else "NOT within 10 %"))
print("  numpy / Python: %.1f (wall), %.1f (CPU): %s" % (
    w_np / w_py, c_np / c_py,
    "at least 30x" if max(w_np / w_py, c_np / c_py) >= 30 else "below 30x"))
# what allantools' oadev() gives (deviations, no fit): with intervals, and
# the deviations alone; the C engine without the fit beside them
w_cn = c_cn = math.inf
for _ in range(3):
    w, c_, _r = timed(lambda: raw(fit=False))
    w_cn, c_cn = min(w_cn, w), min(c_cn, c_)
print("  %-28s %8.3f %8.3f   numpy / it: %.1f (wall), %.1f (CPU)" % (
    "C engine, no fit", w_cn, c_cn, w_np / w_cn, c_np / c_cn))
for what, kw in (("sensorscope.allan, no fit", dict(fit=False)),
                 ("  ... no intervals either", dict(fit=False, ci=None))):
    w_k = c_k = math.inf
    for _ in range(3):
        w, c_, rk = timed(lambda: ss.allan(x, rate, **kw))
        w_k, c_k = min(w_k, w), min(c_k, c_)
    err = max(err, float(np.max(np.abs(rk.dev - ref) / ref)))
    print("  %-28s %8.3f %8.3f   numpy / it: %.1f (wall), %.1f (CPU)"
          "; / C no fit: %.3f (wall)" % (
              what, w_k, c_k, w_np / w_k, c_np / c_k, w_k / w_cn))
print("  largest relative difference of the deviations: %.2e" % err)
c.noise_plan_free(plan)
sys.exit(0 if err < 1e-9 else 1)
