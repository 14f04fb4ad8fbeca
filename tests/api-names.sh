#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The public C API reads like one library (README, "Using the library"):
# - every symbol the shared library exports is sscope_AREA_* and declared in
#   the installed header sscope-AREA.h (sscope-core.h: sscope_version,
#   sscope_strerror), and every function a public header declares is
#   exported; internal helpers (ssc_*) are not;
# - types, macros and enum constants of sscope-AREA.h carry the same area
#   (struct sscope_AREA_*, SSCOPE_AREA_*);
# - lifetimes use one vocabulary: _new/_free, _init/_clear, _open/_close,
#   and every _new has its _free;
# - sensorscope.h only includes the public headers (all of them), no
#   public header includes it back, and each compiles on its own as C11
#   (and as C++ when a compiler is found).
set -u
: "${top_srcdir:=$(cd "$(dirname "$0")/.." && pwd)}"
: "${top_builddir:=$top_srcdir}"
PY=${PYTHON3:-python3}
if ! "$PY" -c 'import re' 2>/dev/null; then
	echo "1..0 # SKIP no python3"
	exit 0
fi
LIB="$top_builddir/src/.libs/libsensorscope.so"
T=$(mktemp -d "${TMPDIR:-/tmp}/sscope-api.XXXXXX")
trap 'rm -rf "$T"' EXIT
if [ -f "$LIB" ]; then
	nm -D --defined-only "$LIB" >"$T/nm" || { echo "1..1"; echo "not ok 1 - nm $LIB"; exit 0; }
else
	: >"$T/nm"
fi
export T LIB top_srcdir top_builddir
"$PY" - <<'EOF'
import os, re, shutil, subprocess, sys

src, T = os.environ['top_srcdir'], os.environ['T']
n = 0


def tap(ok, what, detail=()):
    global n
    n += 1
    print('%s %d - %s' % ('ok' if ok else 'not ok', n, what))
    for d in list(detail)[:40]:
        print('# ' + ' '.join(d.split()))


def strip_comments(t):
    return re.sub(r'/\*.*?\*/|//[^\n]*', ' ', t, flags=re.S)


mk = open(os.path.join(src, 'Makefile.am')).read()
headers = []
for m in re.finditer(r'sensorscopeinclude_HEADERS\s*\+?=((?:[^\n]*\\\n)*'
                     r'[^\n]*)', mk):
    headers += re.findall(r'\S+\.h', m.group(1))
umbrella = 'src/sensorscope.h'
public = [h for h in headers if h != umbrella]
area = {h: os.path.basename(h)[len('sscope-'):-2] for h in public}
areas = set(area.values())
CORE = {'sscope_version', 'sscope_strerror', 'sscope_diag'}


def body(h):
    return strip_comments(open(os.path.join(src, h)).read())


def declared(code):
    """(kind, name) declared at top level of a header (comments removed)."""
    out = []
    code = re.sub(r'^#ifdef __cplusplus\n.*?^#endif', '', code,
                  flags=re.M | re.S)
    for m in re.finditer(r'^#\s*define\s+(\w+)', code, re.M):
        out.append(('macro', m.group(1)))
    code = re.sub(r'^#.*$', '', code, flags=re.M)
    for m in re.finditer(r'\b(?:struct|enum|union)\s+(\w+)\s*([{;])', code):
        out.append(('type' if m.group(2) == '{' else 'fwd', m.group(1)))
    for m in re.finditer(r'\benum\b[^{;()]*\{([^}]*)\}', code):
        for e in re.findall(r'(?:^|,)\s*(\w+)', m.group(1)):
            out.append(('const', e))
    flat, depth = [], 0
    for ch in code:
        if ch == '{':
            depth += 1
        elif ch == '}':
            depth -= 1
        elif depth == 0:
            flat.append(ch)
    top, par = ''.join(flat), 0
    for k, ch in enumerate(top):
        if ch == '(':
            if par == 0:
                m = re.search(r'(\w+)\s*$', top[:k])
                if m and m.group(1) not in ('__attribute__',):
                    out.append(('func', m.group(1)))
            par += 1
        elif ch == ')':
            par -= 1
    return out


def area_of(name):
    low, best = name.lower(), None
    for a in areas:
        if low == 'sscope_' + a or low.startswith('sscope_' + a + '_'):
            if best is None or len(a) > len(best):
                best = a
    return best


# 1. names in the headers
funcs, bad = {}, []
for h in public:
    a = area[h]
    for kind, name in declared(body(h)):
        if kind == 'macro' and name == 'SSCOPE_%s_H' % a.upper():
            continue
        if a == 'core' and name in CORE:
            ok = True
        elif kind in ('func', 'type'):
            ok = name == 'sscope_' + a or name.startswith('sscope_' + a + '_')
        elif kind == 'fwd':
            ok = area_of(name) is not None
        else:
            ok = name.startswith('SSCOPE_' + a.upper() + '_')
        if not ok:
            bad.append('%s: %s %s is not %s' % (h, kind, name,
                       'SSCOPE_%s_*' % a.upper() if kind in ('macro', 'const')
                       else 'sscope_%s_*' % a))
        if kind == 'func':
            funcs.setdefault(name, []).append(h)
tap(public and not bad, 'every name in sscope-AREA.h carries its area (%d '
    'headers, %d functions)' % (len(public), len(funcs)), bad)
dup = ['%s declared in %s' % (f, ', '.join(hs))
       for f, hs in sorted(funcs.items()) if len(hs) > 1]
tap(not dup, 'each function is declared in one header', dup)

# 2. the exported symbols
syms = {}
for line in open(os.path.join(T, 'nm')):
    p = line.split()
    if len(p) >= 3:
        syms[p[2].split('@')[0]] = p[1]
if not os.path.exists(os.environ['LIB']):
    print('ok %d - exported symbols # SKIP no shared library' % (n + 1))
    n += 1
else:
    exp = {s for s, t in syms.items() if t in 'TtWiDdBbVvRr' and
           not s.startswith('_')}
    wrong = sorted(s for s in exp if not s.startswith('sscope_'))
    tap(exp and not wrong, '%d symbols exported, all sscope_*' % len(exp),
        wrong)
    undecl = sorted(s for s in exp if s.startswith('sscope_')
                    and s not in funcs)
    tap(not undecl, 'every exported symbol is declared in a public header',
        undecl)
    unexp = sorted(f for f in funcs if f not in exp)
    tap(not unexp, 'every declared function is exported', unexp)

# 3. lifetimes
words = ('destroy', 'release', 'delete', 'dispose', 'create', 'alloc',
         'fini', 'cleanup', 'unref', 'deinit', 'finish')
odd = sorted(f for f in funcs if f.rsplit('_', 1)[-1] in words)
tap(not odd, 'one lifetime vocabulary (_new/_free, _init/_clear, '
    '_open/_close)', odd)
nofree = sorted(f for f in funcs if f.endswith('_new')
                and f[:-4] + '_free' not in funcs)
tap(not nofree, 'every _new has its _free', nofree)

# 4. the umbrella
code = re.sub(r'^#.*$', '', body(umbrella), flags=re.M)
inc = re.findall(r'^#include "([^"]+)"', open(os.path.join(src, umbrella))
                 .read(), re.M)
missing = sorted(os.path.basename(h) for h in public
                 if os.path.basename(h) not in inc)
tap(not code.strip() and not missing,
    'sensorscope.h declares nothing and includes all %d headers'
    % len(public), missing + ([code.strip()[:70]] if code.strip() else []))
back = [h for h in public if '"sensorscope.h"' in body(h)]
tap(not back, 'no public header includes sensorscope.h', back)

# 5. each header alone, as an installed user would include it
incdir = os.path.join(T, 'include', 'sensorscope')
os.makedirs(incdir)
for h in headers:
    shutil.copy(os.path.join(src, h), incdir)
for lang, cc, flags in (('C11', os.environ.get('CC') or 'cc',
                         ['-std=c11', '-x', 'c']),
                        ('C++', os.environ.get('CXX') or 'c++',
                         ['-std=c++17', '-x', 'c++'])):
    if not shutil.which(cc.split()[0]):
        print('ok %d - headers compile alone as %s # SKIP no %s'
              % (n + 1, lang, cc))
        n += 1
        continue
    fails = []
    for h in headers:
        b = os.path.basename(h)
        r = subprocess.run(cc.split() + flags + [
            '-fsyntax-only', '-Wall', '-Wextra', '-Werror', '-pedantic',
            '-I', incdir, '-'], input='#include <%s>\n#include <%s>\n'
            % (b, b), capture_output=True, text=True)
        if r.returncode:
            fails.append('%s: %s' % (b, r.stderr.strip().splitlines()[0]
                                     if r.stderr.strip() else 'failed'))
    tap(not fails, 'each public header compiles alone (twice) as %s' % lang,
        fails)
print('1..%d' % n)
EOF
