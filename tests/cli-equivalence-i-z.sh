#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# A scene's stage and its command are one code path (see
# cli-equivalence.sh): the sample scenes i-z.
. "$(dirname "$0")/lib.sh"
. "$top_srcdir/tests/equivalence.sh"

scene_equivalence "$SAMPLES"/[i-z]*.scene.ini

done_testing
