#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# A scene's stage and its command are one code path: for every sample
# scene, each stage's JSON equals the JSON of the standalone command on
# the same inputs and options (cli-equivalence-report.sh: the same for
# `report` on every sample capture).  The command lines are the ones
# `run --dry-run` prints for each stage (the stage's options as its
# section gives them, the scene's [input] options, --sensor/--adc for its
# specifications and --result for the results of earlier stages); they
# are run here one by one and their JSON compared with the stage's
# STAGE.json: numbers bit-equal, except where noted.
. "$(dirname "$0")/lib.sh"
. "$top_srcdir/tests/equivalence.sh"

for sc in "$SAMPLES"/*.scene.ini; do
	b=$(basename "$sc" .scene.ini)
	out="$T/scene-$b"
	run "scene $b: plan" 0 run --dry-run -o "$out" "$sc"
	cp "$T/out" "$T/plan-$b"
	run "scene $b: run" 0 run -q -o "$out" "$sc"
	cp "$T/err" "$out.err"
	compare "$out" "$T/plan-$b" "scene $b"
done

done_testing
