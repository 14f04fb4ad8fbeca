# SPDX-License-Identifier: GPL-3.0-or-later
"""Round trip of `sensorscope allan --export TARGET:FILE`, per target.

For each record: simulate a gyro and an accelerometer with known white noise
N and rate random walk K, let `allan` write every export file, then for each
target read the file back with a reader written from the CONSUMER's
documentation or source (not from sensorscope's writer), turn what it reads
into the noise the consumer would generate or assume at the file's rate
(its own discretisation), simulate a fresh record with it, measure that
record with `allan --format json`, and check that the recovered N and K of
each sensor fall inside their intervals around the values the consumer read.

usage: export-roundtrip.py SENSORSCOPE WORKDIR RECORDS CI [SEED]
  prints one line per target with the fraction of (record, sensor, term)
  inside the CI-level interval; exit 1 when a target's fraction is below
  the floor (0.9 for bench runs, RECORDS >= 20; all inside otherwise).
"""
import json
import math
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np

RATE = 50.0
SAMPLES = 50000  # 1000 s
TRUE = {"g": (1.0e-3, 2.0e-4), "a": (2.0e-3, 6.0e-4)}  # N, K (SI)
TARGETS = ["kalibr", "imu_utils", "openvins", "vins", "orbslam3", "basalt",
           "gtsam", "matlab", "gnss_ins_sim", "gazebo"]
EXT = {"basalt": "json", "matlab": "m", "gnss_ins_sim": "py",
       "gazebo": "sdf"}


def yaml_keys(path):
    """flat 'key: number' lines of a YAML file, comments dropped"""
    out = {}
    for line in open(path):
        line = line.split("#", 1)[0]
        m = re.match(r"\s*([A-Za-z_.]+):\s*([-+0-9.eE]+)\s*$", line)
        if m:
            out.setdefault(m.group(1), float(m.group(2)))
    return out


# ---- readers: each returns {"g": model, "a": model} where a model is
# ("rw", sd of one sample's white noise, sd of one step of the bias walk)
# or ("gm", white sd per sample, driving sd per step, phi per step), plus
# the continuous N and K the consumer means (for the check).

def white_rw(n_c, k_c, rate):
    """the continuous-time model sampled at rate: white sd N sqrt(rate),
    bias step sd K sqrt(dt) (Kalibr's IMU noise model page)"""
    return ("rw", n_c * math.sqrt(rate), k_c / math.sqrt(rate), n_c, k_c)


def read_kalibr(path, rate):
    k = yaml_keys(path)
    r = k["update_rate"]
    return {"g": white_rw(k["gyroscope_noise_density"], k["gyroscope_random_walk"], r),
            "a": white_rw(k["accelerometer_noise_density"], k["accelerometer_random_walk"], r)}


def read_openvins(path, rate):
    return read_kalibr(path, rate)  # the same four keys under imu0


def read_imu_utils(path, rate):
    # imu_utils' README: gyr_n, acc_n white noise (the Allan deviation at
    # 1 s), *_w the bias random walk; avg-axis is what VINS users copy
    txt = open(path).read()
    vals = {}
    for blk, p in (("Gyr", "gyr"), ("Acc", "acc")):
        m = re.search(blk + r":.*?avg-axis:\s*\n\s*" + p + r"_n:\s*([-+0-9.eE]+).*?\n\s*" +
                      p + r"_w:\s*([-+0-9.eE]+)", txt, re.S)
        vals[p] = (float(m.group(1)), float(m.group(2)))
    return {"g": white_rw(*vals["gyr"], rate), "a": white_rw(*vals["acc"], rate)}


def read_vins(path, rate):
    # VINS-Mono integration_base.h: noise = acc_n^2 per sample, the bias
    # grows by acc_w * dt * w each step (V = I dt, noise acc_w^2)
    k = yaml_keys(path)
    dt = 1 / rate
    out = {}
    for s, p in (("g", "gyr"), ("a", "acc")):
        n_d, w = k[p + "_n"], k[p + "_w"]
        step = w * dt
        out[s] = ("rw", n_d, step, n_d / math.sqrt(rate), step / math.sqrt(dt))
    return out


def read_orbslam3(path, rate):
    # Tracking.cc: Calib(Ng*sqrt(f), Na*sqrt(f), Ngw/sqrt(f), Naw/sqrt(f))
    k = yaml_keys(path)
    f = k["IMU.Frequency"]
    out = {}
    for s, n, w in (("g", "IMU.NoiseGyro", "IMU.GyroWalk"),
                    ("a", "IMU.NoiseAcc", "IMU.AccWalk")):
        n_d, w_d = k[n] * math.sqrt(f), k[w] / math.sqrt(f)
        out[s] = ("rw", n_d, w_d, n_d / math.sqrt(f), w_d * math.sqrt(f))
    return out


def read_basalt(path, rate):
    # calibration.hpp: discrete noise std = noise_std * sqrt(imu_update_rate);
    # bias random walk weight 1/(bias_std^2 dt)
    v = json.load(open(path))["value0"]
    r = v["imu_update_rate"]
    return {"g": white_rw(v["gyro_noise_std"][0], v["gyro_bias_std"][0], r),
            "a": white_rw(v["accel_noise_std"][0], v["accel_bias_std"][0], r)}


def read_gtsam(path, rate):
    # PreintegrationParams: continuous covariances; preintegration divides
    # them by dt; CombinedImuFactor multiplies the bias ones by dt
    txt = open(path).read()

    def diag0(key):
        m = re.search(r"^" + key + r":\s*\[\s*([-+0-9.eE]+)", txt, re.M)
        return float(m.group(1))
    return {"g": white_rw(math.sqrt(diag0("gyroscopeCovariance")),
                          math.sqrt(diag0("biasOmegaCovariance")), rate),
            "a": white_rw(math.sqrt(diag0("accelerometerCovariance")),
                          math.sqrt(diag0("biasAccCovariance")), rate)}


def read_matlab(path, rate):
    # gyroparams: NoiseDensity (rad/s)/sqrt(Hz); RandomWalk (rad/s)*sqrt(Hz)
    txt = open(path).read()
    r = float(re.search(r"SampleRate\s*=\s*([-+0-9.eE]+)", txt).group(1))
    out = {}
    for s, fn in (("g", "gyroparams"), ("a", "accelparams")):
        blk = txt[txt.index(fn + "("):]
        nd = float(re.search(r"'NoiseDensity',\s*([-+0-9.eE]+)", blk).group(1))
        rw = float(re.search(r"'RandomWalk',\s*([-+0-9.eE]+)", blk).group(1))
        out[s] = white_rw(nd, rw, r)
    return out


def read_gnss_ins_sim(path, rate):
    # gnss-ins-sim: arw in deg/sqrt(hr) -> rad/sqrt(s), white sd arw/sqrt(dt);
    # pathgen.py bias_drift: first-order Gauss-Markov, a = 1 - 1/(fs tau),
    # b = drift sqrt(1 - exp(-2/(fs tau))), drift in rad/s (deg/hr for gyro)
    ns = {}
    exec(open(path).read(), ns)  # the file is a Python fragment
    err = ns["imu_err"]
    fs = ns.get("imu_rate_hz", rate)
    d2r = math.pi / 180
    out = {}
    for s, arw, stab, corr, su in (("g", err["gyro_arw"][0] * d2r / 60,
                                    err["gyro_b_stability"][0], err["gyro_b_corr"][0], d2r / 3600),
                                   ("a", err["accel_vrw"][0] / 60,
                                    err["accel_b_stability"][0], err["accel_b_corr"][0], 1.0)):
        drift = stab * su
        a = 1 - 1 / fs / corr
        b = drift * math.sqrt(1 - math.exp(-2 / (fs * corr)))
        # continuous: the GM driving density sqrt(2 drift^2 / tau) is K
        out[s] = ("gm", arw * math.sqrt(fs), b, a, arw, drift * math.sqrt(2 / corr))
    return out


def read_gazebo(path, rate):
    # gz-sensors GaussianNoiseModel.cc: output = in + bias + N(mean, stddev);
    # bias = phi bias + N(0, sigma_b_d), sigma_b_d^2 = -sigma_b^2 tau/2
    # expm1(-2 dt/tau), phi = exp(-dt/tau)
    root = ET.parse(path).getroot()
    r = float(root.find("update_rate").text)
    dt = 1 / r
    out = {}
    for s, blk in (("g", "angular_velocity"), ("a", "linear_acceleration")):
        nz = root.find("imu/" + blk + "/x/noise")
        sd = float(nz.find("stddev").text)
        sb = float(nz.find("dynamic_bias_stddev").text)
        tau = float(nz.find("dynamic_bias_correlation_time").text)
        sbd = math.sqrt(-sb * sb * tau / 2 * math.expm1(-2 * dt / tau))
        out[s] = ("gm", sd, sbd, math.exp(-dt / tau), sd / math.sqrt(r), sb)
    return out


READERS = {t: globals()["read_" + t] for t in TARGETS}


def simulate(rng, model, n):
    if model[0] == "rw":
        _, wsd, step, _, _ = model
        return wsd * rng.standard_normal(n) + np.cumsum(step * rng.standard_normal(n))
    _, wsd, drive, phi, _, _ = model
    # b_j = phi b_{j-1} + drive w_j, b_0 = 0: phi^j sum_i phi^-i drive w_i
    j = np.arange(n)
    bias = phi ** j * np.cumsum(drive * rng.standard_normal(n) * phi ** (-j))
    return wsd * rng.standard_normal(n) + bias


def write_csv(path, g, a):
    with open(path, "w") as f:
        f.write("# rate: %g Hz\ngx [rad/s],ax [m/s^2]\n" % RATE)
        np.savetxt(f, np.column_stack([g, a + 9.80665]), fmt="%.10e", delimiter=",")


def interval(x):
    """a term's interval in SI from allan's JSON, or None"""
    if not (x.get("present") and x.get("value") and x.get("lo") is not None
            and x.get("hi") is not None):
        return None
    k = x["si"] / x["value"]
    return (x["lo"] * k, x["hi"] * k)


def inside(x, v):
    iv = interval(x)
    return iv is not None and iv[0] <= v <= iv[1]


def allan(exe, args):
    p = subprocess.run([exe, "allan"] + args, capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError("allan %s: exit %d: %s" % (" ".join(args), p.returncode,
                                                       p.stderr.strip()))
    return p.stdout


def main():
    exe, work, records, ci = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
    seed = int(sys.argv[5]) if len(sys.argv) > 5 else 20240933
    rng = np.random.default_rng(seed)
    os.makedirs(work, exist_ok=True)
    hits = {t: 0 for t in TARGETS}
    total = {t: 0 for t in TARGETS}
    misses = {t: [] for t in TARGETS}
    for rec in range(records):
        src = os.path.join(work, "truth.csv")
        write_csv(src, simulate(rng, white_rw(*TRUE["g"], RATE), SAMPLES),
                  simulate(rng, white_rw(*TRUE["a"], RATE), SAMPLES))
        files = {t: os.path.join(work, "%s.%s" % (t, EXT.get(t, "yaml"))) for t in TARGETS}
        # --force: the adequacy check can take a long rate random walk for a
        # warm-up transient and refuse B (MATLAB's file); the data are known
        args = ["--format", "json", "--force", "--ci", ci]
        for t in TARGETS:
            args += ["--export", "%s:%s" % (t, files[t])]
        first = json.loads(allan(exe, args + [src]))
        for t in TARGETS:
            model = READERS[t](files[t], RATE)
            csv = os.path.join(work, "sim.csv")
            write_csv(csv, simulate(rng, model["g"], SAMPLES), simulate(rng, model["a"], SAMPLES))
            res = json.loads(allan(exe, ["--format", "json", "--ci", ci, csv]))
            for c, c0 in zip(res["channels"], first["channels"]):
                s = "g" if c["name"] == "gx" else "a"
                for i, term in enumerate("NK"):
                    want = model[s][-2 + i]
                    total[t] += 1
                    # the value the consumer reads must be the one measured
                    # on the capture (inside its interval: the writer's
                    # convention), and the noise the consumer generates
                    # from it must measure as that value (the reader's)
                    ok = inside(c0["noise"][term], want) and inside(c["noise"][term], want)
                    if ok:
                        hits[t] += 1
                    elif len(misses[t]) < 3:
                        misses[t].append("record %d %s %s: consumer reads %.4g; capture %.4g, %s; re-simulated %.4g, %s" % (
                            rec, c["name"], term, want, c0["noise"][term].get("si") or math.nan,
                            interval(c0["noise"][term]), c["noise"][term].get("si") or math.nan,
                            interval(c["noise"][term])))
    floor = 0.9 if records >= 20 else 1.0
    bad = 0
    for t in TARGETS:
        frac = hits[t] / total[t]
        print("%-13s %4d/%-4d = %.3f inside the %s intervals%s" % (
            t, hits[t], total[t], frac, ci, "" if frac >= floor else "  BELOW %.2f" % floor))
        for m in misses[t] if frac < floor else []:
            print("    " + m)
        bad += frac < floor
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
