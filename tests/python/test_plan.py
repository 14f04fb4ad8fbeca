# SPDX-License-Identifier: GPL-3.0-or-later
"""sensorscope.plan() against `sensorscope plan --format json` (TAP on
stdout), run by tests/py-plan.sh: the same sensor spec, rate, wishes and
lengths give the same numbers (one library: equal to 1e-12 relative), a
term the spec does not have is "never" in both, terms given as a dict
equal the spec's, and bad arguments raise."""

import json
import math
import os
import subprocess

import sensorscope as ss

SSCOPE = os.environ["SSCOPE"]
SAMPLES = os.path.join(os.environ["top_srcdir"], "samples")
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


def close(a, b):
    if a is None or b is None:
        return a is None and b is None
    if math.isinf(a) or math.isinf(b):
        return a == b
    return abs(a - b) <= 1e-12 * max(abs(a), abs(b), 1e-300)


spec = os.path.join(SAMPLES, "gyro-mems-250.ini")
cli = json.loads(subprocess.run(
    [SSCOPE, "plan", "--sensor", spec, "--rate", "10", "--resolve",
     "B:20%,K:40%,R:50%", "--lengths", "1800,7200", "--format", "json"],
    capture_output=True, text=True, check=True).stdout)
py = ss.plan(spec, {"B": 0.20, "K": 0.40, "R": 0.50}, rate=10,
             lengths=[1800, 7200])
bad = []
for tc, tp in zip(cli["terms"], py["terms"]):
    nc = tc["needed_s"]
    npy = None if math.isinf(tp["needed_s"]) else tp["needed_s"]
    if tc["term"] != tp["term"] or not close(nc, npy) or \
            tc["never"] != tp["never"]:
        bad.append((tc["term"], nc, npy, tc["never"], tp["never"]))
    for lc, lp in zip(tc["lengths"], tp["lengths"]):
        for k in ("length_s", "probability", "p_present", "p_width"):
            if not close(lc[k], lp[k]):
                bad.append((tc["term"], k, lc[k], lp[k]))
ok(len(cli["terms"]) == 3 and not bad,
   "plan: needed_s, never and each length's probabilities equal the "
   "command's JSON", bad)
r = [t for t in py["terms"] if t["term"] == "R"][0]
ok(math.isinf(r["needed_s"]) and "no R" in r["never"] and
   all(p["probability"] == 0 for p in r["lengths"]),
   "plan: a term the spec does not have is never, with the reason")
deg = math.pi / 180
terms = {"N": 0.2 * deg / 60, "B": 4 * deg / 3600, "K": 20 * deg / 3600 / 60}
pd = ss.plan(terms, {"B": 0.20}, rate=10, lengths=[1800, 7200])
ok(abs(pd["terms"][0]["needed_s"] / py["terms"][0]["needed_s"] - 1) < 1e-9,
   "plan: the terms as a dict (SI) plan as the spec file")
p1 = py["terms"][0]["lengths"]
ok(0 <= p1[0]["probability"] <= p1[1]["probability"] <= 1,
   "plan: probabilities in [0, 1], not falling with the length")
for args, what in (
        (({"B": 1e-5}, {"X": 0.2}, 10), "an unknown term"),
        (({"B": 1e-5}, {"B": -0.2}, 10), "a negative width"),
        (({"B": -1e-5}, {"B": 0.2}, 10), "a negative coefficient"),
        (({"B": 1e-5}, {"B": 0.2}, 0), "a rate of 0")):
    try:
        ss.plan(*args)
        raised = False
    except (ss.ArgumentError, ss.Error):
        raised = True
    ok(raised, "plan: refuses %s" % what)
print("1..%d" % n_test)
raise SystemExit(1 if failed else 0)
