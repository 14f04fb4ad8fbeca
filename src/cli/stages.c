/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The stage graph of scenes: each section of a scene is one command's
 * stage (cmd-*.c), with the stages whose results it consumes and the
 * definitions its part of the report states.  The scene runner
 * (src/workbench/scene.c) is given this table: it knows the stages only
 * through it.
 */
#include "cli.h"
#include "scene.h"

static const struct ssc_stage_def stages[S_COUNT_] = {
	[S_INFO] = { "info", &ssc_info_stage, 0, NULL,
		     "Sample rate: from --rate, else the time column (mean of the "
		     "regular intervals; gaps are intervals longer than 1.5 times "
		     "the median), else a '# rate:' header comment." },
	[S_PSD] = { "psd", &ssc_psd_stage, 0, NULL,
		    "One-sided power spectral density by Welch's method with "
		    "scipy.signal.welch's conventions: DFT-even window, per-segment "
		    "detrending, density = |X|^2 / (fs sum w^2) in unit^2/Hz; RMS is "
		    "the square root of its integral (Parseval). Peak frequency and "
		    "amplitude are interpolated by a least-squares fit of the "
		    "window's exact response to five bins." },
	[S_VIBRATION] = { "vibration", &ssc_vibration_stage, 0, NULL,
			  "Velocity RMS: frequency-domain integration of the "
			  "acceleration PSD over 10-1000 Hz; severity zones of ISO "
			  "10816-1:1995 Annex B. Shaft orders n x rpm/60; bearing "
			  "defect frequencies BPFO = (n/2) fr (1 - d/D cos phi), "
			  "BPFI = (n/2) fr (1 + d/D cos phi), BSF, FTF; envelope "
			  "spectrum = |Hilbert| of the band-passed signal; kurtosis "
			  "3 for Gaussian noise." },
	[S_ALLAN] = { "allan", &ssc_allan_stage, 0, NULL,
		      "Overlapping Allan deviation (NIST SP 1065) with "
		      "Greenhall-Riley equivalent degrees of freedom and "
		      "chi-squared intervals; IEEE 952-1997 terms from "
		      "sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (2 ln2/pi) B^2 + "
		      "K^2 tau/3 + R^2 tau^2/2, all fitted together by weighted "
		      "least squares; a term is resolved above 3 sd, its "
		      "interval or bound from the fit covariance." },
	[S_TEMPBIAS] = { "tempbias", &ssc_tempbias_stage, 0, NULL,
			 "Bias b(T) by weighted least squares (QR, GSL) in the "
			 "centred and scaled temperature, one offset per power "
			 "cycle, heating/cooling and dT/dt terms; order by an F "
			 "test at 1 %, at most one order per 5 degC of span; "
			 "turn-on repeatability = sd of the per-cycle offsets; "
			 "in-run stability = minimum Allan deviation of the "
			 "compensated residuals." },
	[S_INCLINO] = { "inclino", &ssc_inclino_stage, 0, "inclino calibrate",
			"Roll = atan2(ay, az), pitch = atan2(-ax, sqrt(ay^2 + "
			"az^2)); per temperature node a least-squares fit of "
			"offset, scale and cross-coupling to the reference "
			"tilts; look-up table interpolated linearly (or by "
			"cubic spline) in temperature, clamped outside the "
			"calibrated range." },
	[S_ADC] = { "adc", &ssc_adc_stage, 0, "adc report",
		    "LSB q = range / 2^bits; white quantization noise q^2/12 "
		    "(rate rounding: AVAR q^2 / (12 fs tau); integrating: "
		    "3 Q^2 / tau^2 with Q = q / sqrt(12)) added to the "
		    "sensor's noise density; dither criterion sigma/q >= 0.5 "
		    "with the first-harmonic bound of the bias a quiet input "
		    "loses; offset and reference drift over the spec's "
		    "temperature range; Monte Carlo: simulate, digitize, "
		    "refit N, B, K and compare." },
	[S_CALIB] = { "calib", &ssc_calib_stage, 0, NULL,
		      "Error model corrected = T K (reading - bias) (Tedaldi, "
		      "Pretto & Menegatti, ICRA 2014): static intervals found by "
		      "a variance threshold, accelerometer parameters by "
		      "Levenberg-Marquardt on |g| - |a'|, gyro parameters by "
		      "matching the rotation of gravity between poses; "
		      "uncertainties s^2 (J^T J)^-1." },
	[S_BUDGET] = { "budget", &ssc_budget_stage, (1u << S_ALLAN) | (1u << S_CALIB),
		       NULL,
		       "Open loop: accelerometer bias b t^2 / 2, gyro bias "
		       "g b t^3 / 6; Schuler-bounded forms with omega_s = "
		       "sqrt(g/R) past the switch time; random walks: 1-sigma "
		       "K sqrt(t) growth, 95 % inside +-2 sigma; total = root sum "
		       "of squares." },
	[S_HEADING] = { "heading", &ssc_heading_stage, 1u << S_ALLAN, NULL,
			"Heading = integral of the vertical rate minus the bias; "
			"stops by the static detector of calib (variance magnitude "
			"below k times a noise reference), the bias re-estimated "
			"and the heading held at each; predicted error variance "
			"after a stop for the IEEE 952 terms: -2 sum c_i c_j "
			"D(|t_i - t_j|) with D = Q^2 + N^2 t/2 - (B^2/2 pi) t^2 "
			"ln t - K^2 t^3/12." },
	[S_WALK] = { "walk", &ssc_walk_stage, 1u << S_ALLAN, NULL,
		     "Runs integrated after bias removal; envelope +-2 sigma of "
		     "the predicted variance (angle random walk N^2 t plus the "
		     "bias-instability, rate-random-walk and bias-estimate "
		     "parts); implied N from the mean square of the runs, "
		     "chi-squared interval with as many degrees of freedom as "
		     "runs." },
	[S_NAVSIM] = { "navsim", &ssc_navsim_stage, (1u << S_ALLAN) | (1u << S_CALIB),
		       NULL,
		       "WGS 84 Earth, normal gravity (Somigliana); local-level "
		       "strapdown mechanisation with two-sample coning and "
		       "sculling corrections, Earth rate, transport rate and "
		       "Coriolis; sensor noise from the simulator; Monte-Carlo "
		       "percentiles beside the budget's Schuler-bounded curves." },
	[S_DATASHEET] = { "datasheet", &ssc_datasheet_stage, 0, NULL,
			  "Each datasheet line against the capture's measured value "
			  "and its interval at the stated level (IEEE 952 terms from "
			  "the noise fit, the Allan minimum, GJB 10 s / 100 s as the "
			  "sd of non-overlapping means with a chi-squared interval): "
			  "within spec only when the whole interval is below the "
			  "line, out of spec when it is above, else inconclusive." },
	[S_LOT] = { "lot", &ssc_lot_stage, 0, NULL,
		    "Random effects over the units: each unit's term = mean + unit "
		    "effect + its own error (sd from its 68.3 % interval); the "
		    "between-unit sd by REML with its Q-profile interval "
		    "(Viechtbauer 2007), the mean by Hartung-Knapp; outliers by a "
		    "robust z against the units within the family-wise level, "
		    "flagged at 1 % per unit and left out of the estimates." },
	[S_NAV] = { "nav", &ssc_nav_stage, 1u << S_ALLAN, NULL,
		    "15-state error-state Kalman filter around the strapdown mechanisation "
		    "(Groves 2013, ch. 14-15; Foxlin 2005): levelling and gyrocompassing on the "
		    "first still interval, stops by a sliding-window test (Skog et al. 2010) with "
		    "chi-squared thresholds, zero-velocity and zero-angular-rate updates at "
		    "every stop; process noise from the N, B, K terms." },
	[S_PLAN] = { "plan", &ssc_plan_stage, 0, NULL,
		     "Record length for a term to be shown present (the fit's "
		     "nested test at detect_sigma) and its interval to reach the "
		     "wanted relative half-width: the covariance of the record's "
		     "Allan variances under the model and the fit's information, "
		     "no simulation; the pilot's terms from its dense-tau fit." },
};

const struct ssc_stage_def *ssc_scene_graph(void)
{
	return stages;
}
