# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by cli-equivalence.sh and cli-equivalence-report*.sh (after
# lib.sh): compare a scene's stage JSON with its command's.
: "${top_builddir:=$top_srcdir}"
SAME="$top_builddir/tests/json-same"
if [ ! -x "$SAME" ]; then
	skip "equivalence of scenes and commands" "tests/json-same not built"
	done_testing
	exit 0
fi

# compare DIR PLAN LABEL: run each command of PLAN and compare its JSON
# with DIR/STAGE.json (STAGE.json#/files/K for a stage run per capture)
compare() {
	dir=$1 plan=$2 label=$3
	stage= k=0 n_cmds=0
	# how many commands each stage has: one per capture means "files"
	while IFS= read -r line; do
		case $line in
		"  "[0-9]*". "*)
			stage=$(printf '%s\n' "$line" | sed 's/^ *[0-9]*\. *\([a-z]*\).*/\1/')
			k=0
			n=$(awk -v s="$stage" '
				/^  [0-9]+\. / { cur = $2 }
				/^     command: / && cur == s { c++ }
				END { print c + 0 }' "$plan")
			;;
		"     command: sensorscope "*)
			cmdline=${line#"     command: sensorscope "}
			eval "set -- $cmdline"
			n_cmds=$((n_cmds + 1))
			ss "$@" --format json </dev/null >"$T/cmd.json" 2>"$T/cmd.err"
			got=$?
			want="$dir/$stage.json"
			if [ ! -e "$want" ] && [ "$got" -ne 0 ]; then
				# an inferred stage the data refused: the command
				# refuses them with the same words
				# (the scene names its keys where the command names
				# its options: --run-length is run_length, --rate
				# "rate in [input]"; compared without those marks)
				norm() { sed -e 's/ in \[input\]//g' -e 's/ = / /g' -e 's/ --\([a-z]\)/ \1/g' -e 's/(--\([a-z]\)/(\1/g' "$@"; }
				msg=$(sed -n "s/^sensorscope: $stage: //p" "$T/cmd.err" | norm)
				if [ "$got" -eq 1 ] && [ -n "$msg" ] &&
				   norm "$dir.err" | grep -qF "sensorscope: report: $stage: $msg"; then
					ok "$label: $stage: refused by the data, as the command refuses them"
				else
					not_ok "$label: $stage: the command refuses what the scene refused (exit $got)"
					diag "$T/cmd.err"
					diag "$dir.err"
				fi
				k=$((k + 1))
				continue
			fi
			if [ "$got" -ne 0 ]; then
				not_ok "$label: $stage: the command ran (exit $got)"
				diag "$T/cmd.err"
				k=$((k + 1))
				continue
			fi
			[ "$n" -gt 1 ] && want="$want#/files/$k"
			# budget, navsim, heading and walk read allan/calib from
			# their JSON files (15 significant digits) where the
			# scene hands them the numbers themselves
			tol=0
			case $cmdline in *--result=* | *--from-allan=* | *--from-calib=*) tol=1e-12 ;; esac
			if "$SAME" "$want" "$T/cmd.json" $tol 2>"$T/same.err"; then
				what=$stage
				[ "$n" -gt 1 ] && what="$stage (capture $((k + 1)))"
				[ "$tol" = 0 ] && how="bit-equal" || how="within $tol"
				ok "$label: $what: JSON equals the command's ($how)"
			else
				not_ok "$label: $stage: JSON equals the command's"
				diag "$T/same.err"
				printf 'command: %s\n' "$cmdline" | diag
			fi
			k=$((k + 1))
			;;
		esac
	done <"$plan"
	if [ "$n_cmds" -gt 0 ]; then
		ok "$label: $n_cmds command(s) compared"
	else
		not_ok "$label: the plan lists no command"
		diag "$plan"
	fi
}

# report_equivalence CAPTURE...: report on each capture (imu-raw.bin with
# its documented layout, *.raw as float64), and each stage's JSON against
# the command report --dry-run names for it
report_equivalence() {
	for cap in "$@"; do
		b=$(basename "$cap")
		set --
		case $b in
		*.bin) set -- --raw i16:6:le --scale 0.01 -u deg/s -r 100 ;;
		*.raw) set -- --raw f64:1:le -u rad/s -r 100 ;;
		esac
		out="$T/report-$b"
		run "report $b: plan" 0 report --dry-run -o "$out" "$@" "$cap"
		cp "$T/out" "$T/plan-$b"
		run "report $b: run" 0 report -q -o "$out" "$@" "$cap"
		cp "$T/err" "$out.err"
		compare "$out" "$T/plan-$b" "report $b"
	done
}

# scene_equivalence SCENE...: run each scene, and each stage's JSON
# against the command run --dry-run names for it
scene_equivalence() {
	for sc in "$@"; do
		b=$(basename "$sc" .scene.ini)
		out="$T/scene-$b"
		run "scene $b: plan" 0 run --dry-run -o "$out" "$sc"
		cp "$T/out" "$T/plan-$b"
		run "scene $b: run" 0 run -q -o "$out" "$sc"
		cp "$T/err" "$out.err"
		compare "$out" "$T/plan-$b" "scene $b"
	done
}
