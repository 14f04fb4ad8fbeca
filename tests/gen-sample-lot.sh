#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Generator of samples/lot/: twelve accelerometers of one model at rest
# (sensitive axis level, no input), six hours at 0.2 Hz, the ambient
# temperature one raised-cosine period 21..26 degC (reading noise
# 0.02 degC); each unit its own bias, temperature sensitivity and drift
# (rate ramp), the same noise (N 80 ug/sqrt(Hz), B 8 ug); unit 07 has a
# bias about 0.75 mg (7 between-unit sd) above the others.  Seeds 1..12 (unit NN: seed NN).
# Usage: sh tests/gen-sample-lot.sh PATH/TO/sensorscope OUTDIR
set -e
S=${1:?sensorscope binary}
D=${2:?output folder}
mkdir -p "$D"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# unit: bias mg, tempco ug/degC, drift ug/h
i=0
for u in "1.12 47 6" "0.94 52 11" "1.05 44 3" "1.21 58 9" "0.88 49 14" "1.02 55 5" \
	 "1.80 51 8" "1.10 41 12" "0.97 53 2" "1.15 46 10" "0.91 57 7" "1.07 50 4"; do
	i=$((i + 1))
	set -- $u
	n=$(printf '%02d' $i)
	printf '[sensor]\nname = lot sample accelerometer\nnoise_density = 80 ug/sqrt(Hz)\nbias_instability = 8 ug\nbias = %s mg\nbias_tempco = %s ug/degC\nrate_ramp = %s ug/h\n' \
		"$1" "$2" "$3" >"$T/s.ini"
	"$S" simulate -q --sensor "$T/s.ini" --rate 0.2 --duration 6h --names ax -u g \
		--temp-cycle 21:26:21600 --temp-noise 0.02 --ref-temp 23.5 --digits 7 \
		--seed $i -o "$D/unit$n.csv"
done
