#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# lot split over machines: --plan-jobs writes a plan and a GNU parallel
# command file or a Slurm job-array script, each task (--job) one unit's
# result, --merge the lot; the merged lot equals `lot` on one machine
# (JSON and text byte for byte), with limits, a level and a manifest; a
# result of another plan, a changed input, a missing task are refused.
. "$(dirname "$0")/lib.sh"

L="$SAMPLES/lot"
printf '[accel]\nnoise_density = 60 ug/sqrt(Hz)\nbias_instability = 30 ug\n' >"$T/lim.ini"
cp "$L"/unit0[1-6].csv "$T/"
cd "$T" || exit 1

# one machine
run "lot on one machine" 0 lot --format json --spec lim.ini --ci 0.8 unit0[1-6].csv
cp "$T/out" "$T/single.json"
run "lot on one machine, text" 0 lot --spec lim.ini --ci 0.8 unit0[1-6].csv
cp "$T/out" "$T/single.txt"

# GNU parallel (or the same lines run one after the other without it)
run "plan for GNU parallel" 0 lot --plan-jobs parallel par --spec lim.ini --ci 0.8 unit0[1-6].csv
has "the plan says how to run it" "$T/out" "6 units planned in par: run parallel < par/jobs.txt, then sensorscope lot --merge par"
[ "$(wc -l <par/jobs.txt)" -eq 6 ] && ok "one line per unit" || not_ok "one line per unit"
if command -v parallel >/dev/null 2>&1; then
	if parallel --will-cite --jobs 2 <par/jobs.txt >"$T/par.out" 2>&1; then
		ok "GNU parallel ran the tasks"
	else
		not_ok "GNU parallel ran the tasks"
		diag "$T/par.out"
	fi
else
	echo "ok $((tap_n + 1)) - # SKIP GNU parallel not installed (the tasks run by sh)"
	tap_n=$((tap_n + 1))
	sh par/jobs.txt >/dev/null
fi
[ -s par/unit-5.json ] && ok "each task wrote its result" || not_ok "each task wrote its result"
run "merge" 0 lot --merge par --format json
cmp -s "$T/out" "$T/single.json" && ok "merged JSON equals the lot on one machine" ||
	not_ok "merged JSON equals the lot on one machine"
run "merge, text" 0 lot --merge par
cmp -s "$T/out" "$T/single.txt" && ok "merged text equals the lot on one machine" ||
	not_ok "merged text equals the lot on one machine"
run "merge draws the figures" 0 lot --merge par --plot "$T/m.svg"
[ -s "$T/m.svg" ] && [ -s "$T/m-adev.svg" ] && ok "merge: both figures" || not_ok "merge: both figures"

# Slurm: the script's body run for each array index
run "plan for Slurm" 0 lot --plan-jobs slurm:slu --spec lim.ini --ci 0.8 unit0[1-6].csv
has "sbatch array of 6" slu/lot.sbatch '^#SBATCH --array=0-5$'
i=0
while [ $i -lt 6 ]; do
	SLURM_ARRAY_TASK_ID=$i sh slu/lot.sbatch >/dev/null 2>"$T/slurm.err" || not_ok "slurm task $i"
	i=$((i + 1))
done
run "merge of the Slurm tasks" 0 lot --merge slu --format json
cmp -s "$T/out" "$T/single.json" && ok "Slurm: merged JSON equals the lot on one machine" ||
	not_ok "Slurm: merged JSON equals the lot on one machine"

# a manifest's names, channels and temperature columns travel with the plan
{
	echo "unit,file,channels,temperature"
	for i in 1 2 3 4; do echo "SN-$i,unit0$i.csv,ax,temp"; done
} >"$T/lot.csv"
run "lot of a manifest" 0 lot --format json lot.csv
cp "$T/out" "$T/man.json"
run "plan of a manifest" 0 lot --plan-jobs parallel:man lot.csv
sh man/jobs.txt >/dev/null
run "merge of a manifest" 0 lot --merge man --format json
cmp -s "$T/out" "$T/man.json" && ok "manifest: merged JSON equals the lot" ||
	not_ok "manifest: merged JSON equals the lot"

# refusals
run "a plan into an existing folder" 1 lot --plan-jobs parallel:par unit0[1-3].csv
one_line_error "a plan into an existing folder"
[ "$(wc -l <par/jobs.txt)" -eq 6 ] && ok "the existing plan is untouched" || not_ok "the existing plan is untouched"
cp par/unit-0.json "$T/keep.json"
cp man/unit-0.json par/unit-0.json
run "a result of another plan" 1 lot --merge par
has "another plan: said" "$T/err" "result of another plan"
cp "$T/keep.json" par/unit-0.json
rm par/unit-3.json
run "a task not run" 1 lot --merge par
has "a task not run: said" "$T/err" 'par/unit-3.json is missing: task 3 .unit04.csv. has not run'
echo "1,2,3" >>unit04.csv
run "a unit changed since the plan: its task" 1 lot --job par:3
has "changed input: the task says so" "$T/err" "changed since the plan"
run "a unit changed since the plan: the merge" 1 lot --merge slu
has "changed input: the merge says stale" "$T/err" "stale"
run "--job with input files" 2 lot --job par:0 unit01.csv
run "--plan-jobs: an unknown engine" 2 lot --plan-jobs pbs:x unit0[1-3].csv
run "--plan-jobs: an unknown engine, folder apart" 2 lot --plan-jobs pbs x unit0[1-3].csv
run "--job: no index" 2 lot --job par
run "--job: a task the plan has not" 1 lot --job par:6
has "the plan's size is said" "$T/err" "plans 6 units: no task 6"
run "--merge with --spec" 2 lot --merge par --spec lim.ini
done_testing
