/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Sizes and field offsets of the structures the Python module mirrors
 * with ctypes (src/python/sensorscope/_capi.py), as the C compiler lays
 * them out: tests/python/test_module.py compares them with ctypes'.
 */
#include "config.h"

#include <stddef.h>
#include <stdio.h>

#include "sensorscope.h"
#include "sscope-allan.h"
#include "sscope-psd.h"
#include "sscope-sim.h"

#define S(t) printf("%s %zu\n", #t, sizeof(struct t))
#define F(t, f) printf("%s.%s %zu\n", #t, #f, offsetof(struct t, f))

int main(void)
{
	S(sscope_diag);
	F(sscope_diag, msg);
	S(sscope_unit);
	F(sscope_unit, scale);
	F(sscope_unit, offset);
	F(sscope_unit, dim2);
	S(sscope_column);
	F(sscope_column, name);
	F(sscope_column, unit_label);
	F(sscope_column, unit);
	F(sscope_column, quantity);
	F(sscope_column, role);
	F(sscope_column, index);
	S(sscope_read_opts);
	F(sscope_read_opts, raw);
	F(sscope_read_opts, raw_scale);
	F(sscope_read_opts, raw_offset);
	F(sscope_read_opts, default_unit);
	F(sscope_read_opts, columns);
	F(sscope_read_opts, time_column);
	F(sscope_read_opts, temp_column);
	F(sscope_read_opts, rate_hz);
	F(sscope_read_opts, nan_as_gap);
	F(sscope_read_opts, no_time);
	F(sscope_read_opts, threads);
	F(sscope_read_opts, progress);
	F(sscope_read_opts, progress_ctx);
	F(sscope_read_opts, topic);
	S(sscope_topic);
	F(sscope_topic, name);
	F(sscope_topic, type);
	F(sscope_topic, messages);
	F(sscope_topic, readable);
	F(sscope_topic, selected);
	S(sscope_source);
	F(sscope_source, format);
	F(sscope_source, n_topics);
	F(sscope_source, topics);
	F(sscope_source, receive_s);
	S(sscope_channel);
	F(sscope_channel, col);
	F(sscope_channel, data);
	S(sscope_capture);
	F(sscope_capture, source);
	F(sscope_capture, n);
	F(sscope_capture, n_channels);
	F(sscope_capture, channels);
	F(sscope_capture, time_s);
	F(sscope_capture, temp_degc);
	F(sscope_capture, time_col);
	F(sscope_capture, temp_col);
	F(sscope_capture, rate_hz);
	F(sscope_capture, rate_source);
	F(sscope_capture, n_nan);
	F(sscope_capture, source_info);
	S(sscope_allan_opts);
	F(sscope_allan_opts, dev);
	F(sscope_allan_opts, input);
	F(sscope_allan_opts, ci_level);
	F(sscope_allan_opts, alpha_fixed);
	F(sscope_allan_opts, alpha);
	F(sscope_allan_opts, stride_div);
	F(sscope_allan_opts, threads);
	S(sscope_allan_point);
	F(sscope_allan_point, tau_s);
	F(sscope_allan_point, m);
	F(sscope_allan_point, terms);
	F(sscope_allan_point, skipped);
	F(sscope_allan_point, stride);
	F(sscope_allan_point, dev);
	F(sscope_allan_point, dev_lo);
	F(sscope_allan_point, dev_hi);
	F(sscope_allan_point, edf);
	F(sscope_allan_point, edf_full);
	F(sscope_allan_point, alpha);
	F(sscope_allan_point, alpha_identified);
	S(sscope_noise_coef);
	F(sscope_noise_coef, value);
	F(sscope_noise_coef, lo);
	F(sscope_noise_coef, hi);
	F(sscope_noise_coef, var_sd);
	F(sscope_noise_coef, fitted);
	S(sscope_noise_readoff);
	F(sscope_noise_readoff, n);
	F(sscope_noise_readoff, b);
	F(sscope_noise_readoff, b_tau_s);
	F(sscope_noise_readoff, k);
	S(sscope_noise_fit_opts);
	F(sscope_noise_fit_opts, ci_level);
	F(sscope_noise_fit_opts, allowed);
	F(sscope_noise_fit_opts, forced);
	F(sscope_noise_fit_opts, model_error);
	F(sscope_noise_fit_opts, tau_min_s);
	F(sscope_noise_fit_opts, tau_max_s);
	S(sscope_noise_fit);
	F(sscope_noise_fit, coef);
	F(sscope_noise_fit, terms);
	F(sscope_noise_fit, ci_level);
	F(sscope_noise_fit, n_points);
	F(sscope_noise_fit, chi2);
	F(sscope_noise_fit, dof);
	F(sscope_noise_fit, p_value);
	F(sscope_noise_fit, aic);
	F(sscope_noise_fit, n_plausible);
	F(sscope_noise_fit, readoff);
	S(sscope_allan_result);
	F(sscope_allan_result, n_points);
	F(sscope_allan_result, points);
	F(sscope_allan_result, oadev);
	F(sscope_allan_result, n_oadev);
	F(sscope_allan_result, n_phase);
	F(sscope_allan_result, have_fit);
	F(sscope_allan_result, fit_error);
	F(sscope_allan_result, fit);
	S(sscope_psd_opts);
	F(sscope_psd_opts, window);
	F(sscope_psd_opts, nperseg);
	F(sscope_psd_opts, noverlap);
	F(sscope_psd_opts, nfft);
	F(sscope_psd_opts, detrend);
	F(sscope_psd_opts, scaling);
	F(sscope_psd_opts, skip_nonfinite);
	F(sscope_psd_opts, shorten);
	F(sscope_psd_opts, spectrogram_cols);
	F(sscope_psd_opts, measure);
	F(sscope_psd_opts, threads);
	S(sscope_spectrum);
	F(sscope_spectrum, n_bins);
	F(sscope_spectrum, freq_hz);
	F(sscope_spectrum, value);
	F(sscope_spectrum, fs_hz);
	F(sscope_spectrum, scaling);
	F(sscope_spectrum, window);
	F(sscope_spectrum, detrend);
	F(sscope_spectrum, nperseg);
	F(sscope_spectrum, noverlap);
	F(sscope_spectrum, nfft);
	F(sscope_spectrum, n_segments);
	F(sscope_spectrum, n_skipped);
	F(sscope_spectrum, n_samples);
	F(sscope_spectrum, enbw_hz);
	F(sscope_spectrum, bin_hz);
	F(sscope_spectrum, rms);
	S(sscope_sensor_spec);
	F(sscope_sensor_spec, name);
	F(sscope_sensor_spec, quantity);
	F(sscope_sensor_spec, has);
	F(sscope_sensor_spec, range);
	F(sscope_sensor_spec, q);
	F(sscope_sensor_spec, n);
	F(sscope_sensor_spec, b);
	F(sscope_sensor_spec, k);
	F(sscope_sensor_spec, r);
	F(sscope_sensor_spec, bias);
	F(sscope_sensor_spec, scale_factor_error);
	F(sscope_sensor_spec, bias_tempco);
	F(sscope_sensor_spec, temp_min_degc);
	F(sscope_sensor_spec, temp_max_degc);
	F(sscope_sensor_spec, sensitivity);
	F(sscope_sensor_spec, zero_output_v);
	F(sscope_sensor_spec, bandwidth_hz);
	F(sscope_sensor_spec, filter_order);
	S(sscope_sim_tone);
	F(sscope_sim_tone, freq_hz);
	F(sscope_sim_tone, amplitude);
	F(sscope_sim_tone, phase_rad);
	S(sscope_sim_opts);
	F(sscope_sim_opts, rate_hz);
	F(sscope_sim_opts, seed);
	F(sscope_sim_opts, stream);
	F(sscope_sim_opts, temp_profile);
	F(sscope_sim_opts, temp_degc);
	F(sscope_sim_opts, temp2_degc);
	F(sscope_sim_opts, temp_rate_degc_s);
	F(sscope_sim_opts, temp_period_s);
	F(sscope_sim_opts, temp_wave);
	F(sscope_sim_opts, temp_noise_degc);
	F(sscope_sim_opts, ref_temp_degc);
	F(sscope_sim_opts, bias_poly);
	F(sscope_sim_opts, hysteresis);
	F(sscope_sim_opts, hysteresis_deadband_degc_s);
	F(sscope_sim_opts, gradient);
	F(sscope_sim_opts, tones);
	F(sscope_sim_opts, n_tones);
	F(sscope_sim_opts, quant_step);
	F(sscope_sim_opts, flicker_tau_min_s);
	F(sscope_sim_opts, flicker_tau_max_s);
	F(sscope_sim_opts, no_clip);
	return 0;
}
