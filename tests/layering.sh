#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The layers of the tree (README, "Layout") stay layers.  Each file's layer
# is its folder, from the bottom up:
#   src/core  <  analysis, adc  <  src/io  <  src (sensorscope.h)
#             <  src/acq  <  src/figure  <  src/workbench  <  src/cli
# and this test fails on
#   1. an #include of a file of a higher layer;
#   2. a call (or any use of a symbol) defined in a higher layer, read from
#      the built objects with nm;
#   3. a circle between files: A uses B and B, directly or not, uses A
#      (a file and its header are one file here; uses are includes and the
#      symbols of 2.);
#   4. a file write from src/figure/ (figures are bytes; their caller
#      writes them): no open/fopen/rename/... in its sources or objects.
set -u
: "${top_srcdir:=$(cd "$(dirname "$0")/.." && pwd)}"
: "${top_builddir:=$top_srcdir}"
PY=${PYTHON3:-python3}
if ! "$PY" -c 'import re' 2>/dev/null; then
	echo "1..0 # SKIP no python3"
	exit 0
fi
export top_srcdir top_builddir
NM=${NM:-nm}
export NM
exec "$PY" - <<'EOF'
import os, re, subprocess, sys

src, build, NM = os.environ['top_srcdir'], os.environ['top_builddir'], \
    os.environ['NM']
LAYERS = [('src/core', 0), ('analysis', 1), ('adc', 1), ('src/io', 2),
          ('src', 3), ('src/acq', 4), ('src/figure', 5),
          ('src/workbench', 6), ('src/cli', 7)]
RANK = dict(LAYERS)
# where a bare #include "x.h" is looked for after the file's own folder
# (AM_CPPFLAGS's order)
SEARCH = ['src', 'src/core', 'analysis', 'adc', 'src/io', 'src/figure',
          'src/workbench', 'src/cli']
n = 0


def tap(ok, what, detail=()):
    global n
    n += 1
    print('%s %d - %s' % ('ok' if ok else 'not ok', n, what))
    for d in list(detail)[:40]:
        print('# ' + d)


def layer(path):
    d = os.path.dirname(path)
    return d if d in RANK else None


files = []
for d, _ in LAYERS:
    for f in sorted(os.listdir(os.path.join(src, d))):
        if re.search(r'\.(c|h|cpp)$', f):
            files.append(d + '/' + f)


def unit(path):
    """a file and its header are one unit"""
    return re.sub(r'\.(c|h|cpp)$', '', path)


def resolve(inc, frm):
    for d in [os.path.dirname(frm)] + SEARCH:
        p = os.path.normpath(os.path.join(d, inc))
        if os.path.isfile(os.path.join(src, p)):
            return p
    return None


uses = {}  # unit -> {unit: [why]}


def use(a, b, why):
    ua, ub = unit(a), unit(b)
    if ua != ub:
        uses.setdefault(ua, {}).setdefault(ub, []).append(why)


# 1. includes
bad = []
for f in files:
    text = open(os.path.join(src, f), encoding='utf-8').read()
    for m in re.finditer(r'^\s*#\s*include\s+"([^"]+)"', text, re.M):
        p = resolve(m.group(1), f)
        if p is None or layer(p) is None:
            continue  # config.h and other generated files
        use(f, p, '#include "%s"' % m.group(1))
        if RANK[layer(p)] > RANK[layer(f)]:
            bad.append('%s includes %s (%s above %s)' %
                       (f, p, layer(p), layer(f)))
tap(not bad, 'every #include points down or sideways (%d files)' %
    len(files), bad)

# 2. symbols, from the objects of the build
objs = []
for d, _ in LAYERS:
    for sub in (os.path.join(build, d, '.libs'), os.path.join(build, d)):
        if os.path.isdir(sub):
            objs += [os.path.join(sub, o) for o in sorted(os.listdir(sub))
                     if o.endswith('.o')]
defs, undef, seen, which = {}, {}, set(), {}
for o in objs:
    d = os.path.relpath(os.path.dirname(o), build)
    if d.endswith('/.libs'):
        d = d[:-6]
    base = os.path.basename(o)[:-2]
    base = base.split('-', 1)[1] if '_la-' in base.split('-', 1)[0] + '-' \
        or base.startswith(('lib', 'src_')) else base
    s = next((d + '/' + base + e for e in ('.c', '.cpp')
              if os.path.isfile(os.path.join(src, d, base + e))), None)
    if s is None or s in seen:
        continue
    seen.add(s)
    which[o] = s
# one nm for all of them: each object's symbols follow a line "OBJECT:"
r = subprocess.run(NM.split() + list(which), capture_output=True, text=True)
s = None
for line in r.stdout.splitlines():
    if line.endswith(':') and line[:-1] in which:
        s = which[line[:-1]]
        continue
    p = line.split()
    if s is None:
        continue
    if len(p) == 3 and p[1] in 'TDBRVGS':
        defs.setdefault(p[2], s)
    elif len(p) == 2 and p[0] == 'U':
        undef.setdefault(s, set()).add(p[1])
bad = []
for s, us in sorted(undef.items()):
    for u in sorted(us):
        t = defs.get(u)
        if t is None or t == s:
            continue
        use(s, t, u)
        if RANK[layer(t)] > RANK[layer(s)]:
            bad.append('%s uses %s of %s (%s above %s)' %
                       (s, u, t, layer(t), layer(s)))
if not seen:
    print('1..%d' % (n + 1))
    tap(True, 'no objects to read # SKIP build first')
    sys.exit(0)
tap(not bad, 'every use of a symbol points down or sideways (%d objects)' %
    len(seen), bad)

# 3. circles (Tarjan's strongly connected components)
index, low, stack, on, comps = {}, {}, [], set(), []
sys.setrecursionlimit(10000)


def strong(v):
    index[v] = low[v] = len(index)
    stack.append(v)
    on.add(v)
    for w in uses.get(v, {}):
        if w not in index:
            strong(w)
            low[v] = min(low[v], low[w])
        elif w in on:
            low[v] = min(low[v], index[w])
    if low[v] == index[v]:
        c = []
        while True:
            w = stack.pop()
            on.discard(w)
            c.append(w)
            if w == v:
                break
        if len(c) > 1:
            comps.append(sorted(c))


for v in sorted(uses):
    if v not in index:
        strong(v)
bad = []
for c in comps:
    bad.append('circle: ' + ', '.join(c))
    for a in c:
        for b in c:
            if b in uses.get(a, {}):
                bad.append('  %s -> %s: %s' %
                           (a, b, ' '.join(sorted(set(uses[a][b]))[:6])))
tap(not comps, 'no circle between files (%d files that use another)' %
    len(uses), bad)

# 4. the figures write no file (reading one, a font, is fine)
WRITES = r'\b(freopen|creat|creat64|rename|renameat|renameat2|unlink|' \
    r'unlinkat|mkstemp|mkostemp|imwrite|ssc_file_put|ssc_file_open|' \
    r'ssc_out_open|sscope_writer_open)\b'
bad = []
for f in files:
    if layer(f) != 'src/figure':
        continue
    raw = re.sub(r'/\*.*?\*/|//[^\n]*', ' ',
                 open(os.path.join(src, f), encoding='utf-8').read(),
                 flags=re.S)
    code = re.sub(r'"(?:\\.|[^"\\])*"', '""', raw)
    for m in re.finditer(WRITES + r'\s*\(', code):
        bad.append('%s: %s()' % (f, m.group(1)))
    for m in re.finditer(r'\b(fopen|fdopen|open|open64|openat)\s*\(([^;]*)',
                         raw):
        if re.search(r'"[^"]*[wa+]|O_WRONLY|O_RDWR|O_CREAT', m.group(2)):
            bad.append('%s: %s(%s) for writing' %
                       (f, m.group(1), m.group(2)[:40]))
for s, us in sorted(undef.items()):
    if layer(s) == 'src/figure':
        for u in sorted(us):
            if re.search(WRITES, u) or 'imwrite' in u:
                bad.append('%s: uses %s' % (s, u))
tap(not bad, 'src/figure/ writes no file', bad)
print('1..%d' % n)
EOF
