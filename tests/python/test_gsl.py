# SPDX-License-Identifier: GPL-3.0-or-later
"""A GSL error never aborts the interpreter that imported sensorscope (TAP
on stdout), run by tests/py-gsl.sh.  The errors are real ones of the GSL
the library is linked with, called through ctypes in this process: log of
a negative number (GSL_EDOM) and exp(1000) (GSL_EOVRFLW).  Oracle for the
calls: without the module's handler each one aborts a child interpreter
(SIGABRT).  With it, this interpreter lives, the module's next call raises
sensorscope.Error naming the function called and GSL's reason, and the
call after that is clean; a thread's error is its own, and an error on a
thread that never called the library (as the library's workers) reaches
the next caller instead of being lost.  The plan line comes last: an abort
leaves the run without one, which fails it."""

import ctypes as C
import errno
import math
import os
import signal
import subprocess
import sys
import threading

import numpy as np

import sensorscope as ss
from sensorscope import _capi
from sensorscope import compat

n_test = 0
failed = 0


def ok(cond, desc, detail=""):
    global n_test, failed
    n_test += 1
    print("%s %d - %s" % ("ok" if cond else "not ok", n_test, desc),
          flush=True)
    if not cond:
        failed += 1
        for line in str(detail).splitlines()[:20]:
            print("# " + line)


def loaded_gsl():
    """The libgsl this process loaded with libsensorscope."""
    with open("/proc/self/maps") as f:
        for line in f:
            path = line.split()[-1]
            if os.path.basename(path).startswith("libgsl.so"):
                return path
    return None


GSL = loaded_gsl()
if GSL is None:
    print("1..0 # SKIP libsensorscope does not load a shared libgsl")
    raise SystemExit(0)
gsl = C.CDLL(GSL)
for name in ("gsl_sf_log", "gsl_sf_exp"):
    getattr(gsl, name).restype = C.c_double
    getattr(gsl, name).argtypes = [C.c_double]
GSL_EDOM, GSL_EOVRFLW = 1, 16

x = np.random.default_rng(2385).normal(size=4096) * 2.385
RATE = 100.0


def raised(f, *args, **kw):
    try:
        f(*args, **kw)
    except ss.Error as e:
        return e
    return None


# ------------------------------------------------------- without the module
# the oracle: the same calls abort an interpreter without the handler
CHILD = r"""
import ctypes, os, sys
mode = sys.argv[1]
if mode == "module" or mode == "reset":
    import sensorscope
else:
    ctypes.CDLL(os.environ["SENSORSCOPE_LIB"])
gsl = [l.split()[-1] for l in open("/proc/self/maps")
       if os.path.basename(l.split()[-1]).startswith("libgsl.so")][0]
g = ctypes.CDLL(gsl)
if mode == "reset":
    g.gsl_set_error_handler(None)   # GSL's default again
g.gsl_sf_%s.restype = ctypes.c_double
g.gsl_sf_%s.argtypes = [ctypes.c_double]
g.gsl_sf_%s(%s)
print("survived")
"""
for fn, arg in (("log", "-2.385"), ("exp", "1000.0")):
    for mode, lives in (("library", False), ("reset", False),
                        ("module", True)):
        r = subprocess.run([sys.executable, "-c",
                            CHILD % (fn, fn, fn, arg), mode],
                           capture_output=True, text=True)
        if lives:
            ok(r.returncode == 0 and "survived" in r.stdout,
               "gsl_sf_%s(%s) after import sensorscope: the child lives"
               % (fn, arg), r.stderr)
        else:
            ok(r.returncode == -signal.SIGABRT and "survived" not in r.stdout,
               "gsl_sf_%s(%s) with GSL's default handler (%s): SIGABRT"
               % (fn, arg, "libsensorscope loaded alone" if mode == "library"
                  else "the module's handler replaced"),
               "status %d\n%s" % (r.returncode, r.stderr))

# ------------------------------------------------------------- in process
base = ss.allan(x, RATE)
ok(not _capi.gsl_error_pending(), "no GSL error recorded after a clean call")

v = gsl.gsl_sf_log(-2.385)
ok(math.isnan(v), "a GSL domain error in this process: it lives, NaN back")
ok(_capi.gsl_error_pending(), "the error is recorded")
e = raised(ss.allan, x, RATE)
msg = str(e) if e else ""
ok(e is not None and msg.startswith("allan: a numerical routine failed "
                                    "(GSL, ") and "domain error" in msg and
   "log.c:" in msg and "\n" not in msg,
   "the next call raises sensorscope.Error: function, GSL file:line, reason",
   msg)
ok(e is not None and e.code == -errno.EDOM and e.gsl_errno == GSL_EDOM,
   "Error.code -EDOM, Error.gsl_errno GSL_EDOM",
   e and (e.code, e.gsl_errno))
ok(not _capi.gsl_error_pending(), "the raise took the record")
again = ss.allan(x, RATE)
ok(np.array_equal(again.dev, base.dev), "the call after is clean and equal")

v = gsl.gsl_sf_exp(1000.0)
ok(math.isinf(v), "a GSL overflow in this process: it lives, inf back")
e = raised(ss.psd, x, RATE)
ok(e is not None and str(e).startswith("psd: ") and "overflow" in str(e)
   and e.code == -errno.ERANGE and e.gsl_errno == GSL_EOVRFLW,
   "psd raises: overflow, Error.code -ERANGE, gsl_errno GSL_EOVRFLW",
   e and (str(e), e.code, e.gsl_errno))

gsl.gsl_sf_log(-2.385)
gsl.gsl_sf_exp(1000.0)
e = raised(compat.oadev, x, rate=RATE)
ok(e is not None and str(e).startswith("oadev: ") and "domain error" in
   str(e), "two errors: the first is reported, by the function called "
   "(compat.oadev)", e)
ok(raised(compat.oadev, x, rate=RATE) is None,
   "and only once: the call after is clean")

# a call that returns nothing of its own checks too
gsl.gsl_sf_log(-2.385)
e = raised(ss.version)
ok(e is not None and str(e).startswith("version: "),
   "version() raises after an error too", e)

# --------------------------------------------------------------- threads
out = {}


def own_thread():
    ss.version()                  # this thread calls the library first
    gsl.gsl_sf_log(-2.385)
    out["own"] = raised(ss.allan, x, RATE)


t = threading.Thread(target=own_thread)
t.start()
t.join()
ok(out.get("own") is not None and "domain error" in str(out["own"]),
   "a thread's error raises in that thread", out.get("own"))
ok(not _capi.gsl_error_pending() and raised(ss.allan, x, RATE) is None,
   "and not in another one")

# a thread that never called the library: as a worker of the library
t = threading.Thread(target=lambda: gsl.gsl_sf_exp(1000.0))
t.start()
t.join()
ok(_capi.gsl_error_pending(),
   "an error on a thread that keeps no record is not lost")
e = raised(ss.allan, x, RATE)
ok(e is not None and "overflow" in str(e),
   "the next caller raises it", e)
ok(raised(ss.allan, x, RATE) is None, "once")

# threads that call at once and fail nowhere raise nothing
errors = []


def calls():
    for _ in range(4):
        e = raised(ss.allan, x, RATE)
        if e is not None:
            errors.append(e)


ts = [threading.Thread(target=calls) for _ in range(4)]
for t in ts:
    t.start()
for t in ts:
    t.join()
ok(not errors, "4 threads x 4 clean calls: no error", errors[:3])

print("1..%d" % n_test)
raise SystemExit(1 if failed else 0)
