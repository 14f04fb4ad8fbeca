#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# allan --export TARGET[:FILE]: every target's file from one capture, its
# leading comment (version, capture, continuous or discrete, inflation), a
# bound marked, usage errors; and the round trip of every target
# (tests/export-roundtrip.py, one record, 99.9 % intervals): the value each
# consumer reads, from its own documented convention, is the one measured,
# and noise generated the consumer's way measures as that value.
. "$(dirname "$0")/lib.sh"

G="$SAMPLES/gyro-static.csv"
cd "$T" || exit 1
run "export: every target, default names" 0 allan --format json --export kalibr \
	--export imu_utils --export vins --export matlab --export gnss_ins_sim \
	--export gazebo "$G"
for f in imu.yaml imu_param.yaml vins_imu.yaml imu_params.m gnss_ins_sim_imu.py imu_noise.sdf; do
	has "export: $f names sensorscope's version" "$f" "sensorscope [0-9]"
	has "export: $f names the capture" "$f" "gyro-static.csv"
	has "export: $f states the convention" "$f" "(CONTINUOUS|DISCRETE|continuous-time)"
	has "export: $f states the inflation" "$f" "inflation: none"
done
# the gyro sample does not establish K: written as its bound, marked
has "export: gazebo marks the bound" imu_noise.sdf "UPPER BOUND"
has "export: vins marks the bound beside gyr_w" vins_imu.yaml '^gyr_w: .*UPPER BOUND'
has "export: vins is discrete at 10 Hz" vins_imu.yaml 'DISCRETE time at 10 Hz'
has "export: matlab RandomWalk" imu_params.m "'RandomWalk', [0-9.]+e-[0-9]+\\); % \\(rad/s\\)\\*sqrt\\(Hz\\) UPPER BOUND"
run "export: names with - as with _" 0 allan --export gnss-ins-sim:g.py --export imu-utils:i.yaml "$G"
[ -s g.py ] && [ -s i.yaml ] && ok "export: gnss-ins-sim and imu-utils written" || not_ok "export: gnss-ins-sim and imu-utils written"
run "export: needs both sensors" 1 allan --export orbslam3:o.yaml "$G"
has "export: orbslam3 says what it needs" "$T/err" 'export orbslam3: the file needs both a gyro'
if [ -e o.yaml ]; then not_ok "export: no file on failure"; else ok "export: no file on failure"; fi
run "export: unknown target" 2 allan --export nav2 "$G"
one_line_error "export: unknown target"
has "export: unknown target lists the targets" "$T/err" "is not kalibr, imu_utils, openvins, vins, orbslam3, basalt, gtsam, matlab, gnss_ins_sim, gazebo"
run "export: one file twice" 2 allan --export vins:x.yaml --kalibr x.yaml "$G"
one_line_error "export: one file twice"
run "export: empty FILE" 2 allan --export vins: "$G"
one_line_error "export: empty FILE"
run "export: with --no-fit" 2 allan --no-fit --export gtsam "$G"

# the round trip, every target (needs numpy)
py=${PYTHON_NUMPY:-}
if [ -n "$py" ] && "$py" -c 'import numpy' 2>/dev/null; then
	if "$py" "$top_srcdir/tests/export-roundtrip.py" "$SSCOPE" \
		"$T/rt" 1 0.999 >"$T/rt.out" 2>&1; then
		ok "export: round trip of every target"
	else
		not_ok "export: round trip of every target"
	fi
	diag <"$T/rt.out"
else
	ok "export: round trip # SKIP no Python 3 with numpy"
fi
done_testing
