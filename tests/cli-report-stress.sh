#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# report under stress: runs at once on the same capture into as many
# folders give the same results, file for file; a report interrupted at
# random points (SIGINT, SIGTERM, SIGHUP) leaves either its previous
# folder as it was or the new one complete, never a half folder and never
# a staging folder; one killed where no handler runs (SIGKILL) leaves its
# staging folder, which the next report into that folder removes.
# Each round interrupts two runs (one into a new folder, one over a
# report) per signal.  make check runs 3 at once and 1 round (6
# interrupted runs) on the capture's first 4,000 lines (under 10 s of
# CPU); make check-long (SSCOPE_TEST_TIER=long) 8 at once and 10 rounds
# (60 interrupted runs, 10 killed) on the whole capture
# (SSCOPE_STRESS_ROUNDS sets the rounds of the long tier: CI runs 5).
. "$(dirname "$0")/lib.sh"

CAP="$SAMPLES/gyro-static.csv"
if long_tier; then rounds=${SSCOPE_STRESS_ROUNDS:-10} many=8; else
	rounds=1 many=3
	head -n 4000 "$CAP" >"$T/short.csv"
	CAP="$T/short.csv"
fi

# the files of a report folder and their contents, wall times masked
digest() {
	(cd "$1" && for f in $(ls | sort); do
		printf '%s ' "$f"
		case $f in
		*.json) sed 's/"wall_time_s":{[^}]*}/"wall_time_s":{}/' "$f" | cksum ;;
		report.html | report.txt) sed 's/[0-9-]* [0-9:]* UTC//; s/Wall time:.*//; s/wall time.*//' "$f" | cksum ;;
		*) cksum <"$f" ;;
		esac
	done)
}

# ------------------------------------------------------------ many at once
pids=
for i in $(seq "$many"); do
	$SSCOPE_RUN "$SSCOPE" report -q -o "$T/c$i" "$CAP" >"$T/c$i.out" 2>"$T/c$i.err" &
	pids="$pids $!"
done
fails=0
for p in $pids; do wait "$p" || fails=$((fails + 1)); done
[ $fails -eq 0 ] && ok "$many reports at once: all exit 0" || not_ok "$many reports at once: $fails failed"
digest "$T/c1" >"$T/d1"
[ "$(wc -l <"$T/d1")" -ge 5 ] && ok "a report folder has its files ($(wc -l <"$T/d1"))" || not_ok "report folder c1: $(cat "$T/d1")"
same=0
for i in $(seq 2 "$many"); do
	digest "$T/c$i" >"$T/d$i"
	if cmp -s "$T/d1" "$T/d$i"; then same=$((same + 1)); else diff "$T/d1" "$T/d$i" | diag /dev/stdin; fi
done
[ $same -eq $((many - 1)) ] && ok "$many reports at once: the same files and results" || not_ok "$many reports at once: $((many - 1 - same)) differ"

# ------------------------------------------------------------ interrupted
# how long one run takes here (CPU-bound: interrupts spread over it)
start=$(date +%s%N)
ss report -q -o "$T/ref" "$CAP" >/dev/null 2>&1
end=$(date +%s%N)
digest "$T/ref" >"$T/dref"
span=$(((end - start) / 1000000))
[ $span -gt 20 ] || span=20
# pseudo-random delays in [0, span] ms, the same sequence every run
awk -v n="$rounds" -v span="$span" 'BEGIN { srand(20261201); for (i = 0; i < 3 * n; i++) printf "%.3f\n", rand() * span / 1000 }' >"$T/delays"

interrupt() { # SIG DELAY FOLDER: start a report into FOLDER, signal it
	# the program itself, not a subshell running it, gets the signal
	$SSCOPE_RUN "$SSCOPE" report -q -o "$3" "$CAP" >/dev/null 2>"$T/int.err" &
	p=$!
	sleep "$2"
	kill -"$1" $p 2>/dev/null
	wait $p
}

half=0 temp=0 lost=0 bad=0 k=0
cp -r "$T/ref" "$T/kept"
for sig in INT TERM HUP; do
	i=0
	while [ $i -lt "$rounds" ]; do
		i=$((i + 1)) k=$((k + 1))
		d=$(sed -n "${k}p" "$T/delays")
		# a new folder: absent or complete
		rm -rf "$T/new"
		interrupt $sig "$d" "$T/new"
		rc=$?
		case $rc in 0 | 129 | 130 | 143) ;; *) bad=$((bad + 1)) ; diag "$T/int.err" ;; esac
		if [ -e "$T/new" ] && ! digest "$T/new" | cmp -s - "$T/dref"; then
			half=$((half + 1))
			digest "$T/new" | diff - "$T/dref" | diag /dev/stdin
		fi
		# a folder that holds a report: the old one or the new one
		interrupt $sig "$d" "$T/kept"
		if ! digest "$T/kept" | cmp -s - "$T/dref"; then lost=$((lost + 1)); fi
		if ls "$T" | grep -q '\.tmp\.\|\.old\.'; then temp=$((temp + 1)); ls "$T" | diag /dev/stdin; rm -rf "$T"/*.tmp.* "$T"/*.old.*; fi
	done
done
n=$((3 * rounds))
[ $bad -eq 0 ] && ok "$n interrupted reports: exit 0 or the signal's" || not_ok "$bad of $n interrupted reports: another exit status"
[ $half -eq 0 ] && ok "$n interrupted reports: never a half folder" || not_ok "$half of $n interrupted reports left a half folder"
[ $lost -eq 0 ] && ok "$n interrupted reports over a report: the folder is always a whole report" || not_ok "$lost of $n interrupted reports changed the folder they replace"
[ $temp -eq 0 ] && ok "$((2 * n)) interrupted reports: never a staging folder left" || not_ok "$temp of $n rounds of interrupted reports left a staging folder"

# ------------------------------------------------------------ SIGKILL
# nothing can clean up after SIGKILL: the staging folder stays until the
# next report into the same folder, which removes it
stale=0 left=0 i=0
while [ $i -lt "$rounds" ]; do
	i=$((i + 1)) k=$((k + 1))
	d=$(sed -n "$(( (k - 1) % n + 1 ))p" "$T/delays")
	interrupt KILL "$d" "$T/kept"
	ls "$T" | grep -q '^kept\.tmp\.' && stale=$((stale + 1))
	digest "$T/kept" | cmp -s - "$T/dref" || left=$((left + 1))
done
[ $left -eq 0 ] && ok "$rounds killed reports over a report: the folder is always a whole report" || not_ok "$left of $rounds killed reports changed the folder"
# a staging folder of a live run is never taken for a stale one
mkdir "$T/user.tmp.abcdef"
echo mine >"$T/user.tmp.abcdef/notes.txt"
run "a report after the killed ones" 0 report -q -o "$T/kept" "$CAP"
if ls "$T" | grep -q '^kept\.tmp\.'; then
	not_ok "the next report removes the staging folders of killed runs ($stale were left)"
	ls "$T" | diag /dev/stdin
else
	ok "the next report removes the staging folders of killed runs ($stale were left)"
fi
[ -s "$T/user.tmp.abcdef/notes.txt" ] && ok "a folder of another name is left alone" || not_ok "a folder of another name was touched"
# a stale staging folder with a file of the user's keeps that file
mkdir "$T/kept.tmp.zzzzzz"
echo mine >"$T/kept.tmp.zzzzzz/notes.txt"
cp "$T/ref/report.json" "$T/kept.tmp.zzzzzz/"
run "a report beside a staging folder holding a user's file" 0 report -q -o "$T/kept" "$CAP"
[ -s "$T/kept.tmp.zzzzzz/notes.txt" ] && [ ! -e "$T/kept.tmp.zzzzzz/report.json" ] &&
	ok "the user's file is kept, the report files removed" || not_ok "stale folder with a user's file: $(ls "$T/kept.tmp.zzzzzz")"
done_testing
