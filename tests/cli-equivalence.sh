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
# STAGE.json: numbers bit-equal, except where noted.  This file: the
# scenes a-h; cli-equivalence-i-z.sh the others.
. "$(dirname "$0")/lib.sh"
. "$top_srcdir/tests/equivalence.sh"

scene_equivalence "$SAMPLES"/[a-h]*.scene.ini

done_testing
