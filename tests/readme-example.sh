#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The C example of the README ("The library") compiles as written against
# the built shared library, with the warnings of the build, and runs on a
# bundled sample: one line per channel, each naming its noise term N with a
# value in deg/sqrt(h) (the static gyro resolves N on every axis).
. "$(dirname "$0")/lib.sh"
: "${top_builddir:=$top_srcdir}"
CC=${CC:-cc}
# a sanitized library needs its runtime at link time: the flags of the build
san=
[ "${SSCOPE_SANITIZERS:-0}" = 1 ] && san="-fsanitize=address,undefined"
lib="$top_builddir/src/.libs"
awk '/^## / { lib = ($0 ~ /^## The library/) }
	lib && /^```c$/ { inblk = 1; next }
	inblk && /^```/ { inblk = 0; exit }
	inblk { print }' "$top_srcdir/README.md" >"$T/example.c"
if [ -s "$T/example.c" ]; then ok "README has a C example"; else not_ok "README has a C example"; fi
if [ ! -f "$lib/libsensorscope.so" ]; then
	skip "example compiles" "no shared library in $lib"
	echo "1..$tap_n"; exit 0
fi
if $CC $san -std=c11 -Wall -Wextra -Werror -I"$top_builddir" -I"$top_srcdir/src" \
	-I"$top_srcdir/src/core" -I"$top_srcdir/analysis" -I"$top_srcdir/adc" \
	-I"$top_srcdir/src/io" "$T/example.c" -o "$T/example" \
	-L"$lib" -Wl,-rpath,"$lib" -lsensorscope -lm 2>"$T/err"; then
	ok "example compiles with -Wall -Wextra -Werror"
else
	not_ok "example compiles with -Wall -Wextra -Werror"; diag "$T/err"
fi
if (cd "$T" && ./example "$SAMPLES/gyro-static.csv") >"$T/out" 2>"$T/err"; then
	ok "example runs (exit 0)"
else
	not_ok "example runs (exit 0)"; diag "$T/err"
fi
n=$(grep -c '^g[xyz]: N = [0-9.e+-]* deg/sqrt(h)$' "$T/out")
if [ "$n" = 3 ]; then ok "example prints N of gx, gy, gz in deg/sqrt(h)"
else not_ok "example prints N of gx, gy, gz in deg/sqrt(h)"; diag "$T/out"; fi
echo "1..$tap_n"
