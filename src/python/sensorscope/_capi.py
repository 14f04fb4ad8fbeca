# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes declarations of the libsensorscope structures and functions used by
the module.  Every structure mirrors its C declaration field by field (the
test suite compares sizes and offsets with the C compiler's)."""

import ctypes as C
import ctypes.util
import os
import pathlib

c_size = C.c_size_t
c_dbl = C.c_double
c_dptr = C.POINTER(C.c_double)


def _find_library():
    env = os.environ.get("SENSORSCOPE_LIB")
    if env:
        return env
    here = pathlib.Path(__file__).resolve().parent
    # the build tree: src/python/sensorscope -> src/.libs
    for cand in (here.parents[1] / ".libs" / "libsensorscope.so",):
        if cand.exists():
            return str(cand)
    try:
        from . import _config  # written by make install
        cand = pathlib.Path(_config.LIBDIR) / "libsensorscope.so.0"
        if cand.exists():
            return str(cand)
    except ImportError:
        pass
    name = ctypes.util.find_library("sensorscope")
    if name:
        return name
    raise OSError("libsensorscope not found: build sensorscope, install it, "
                  "or set SENSORSCOPE_LIB to the library's path")


lib = C.CDLL(_find_library())


class Diag(C.Structure):
    _fields_ = [("msg", C.c_char * 320)]


class Unit(C.Structure):
    _fields_ = [("scale", c_dbl), ("offset", c_dbl), ("dim2", C.c_int8 * 6)]


class Column(C.Structure):
    _fields_ = [("name", C.c_char_p), ("unit_label", C.c_char_p),
                ("unit", Unit), ("quantity", C.c_int), ("role", C.c_int),
                ("index", c_size)]


PROGRESS = C.CFUNCTYPE(None, C.c_void_p, C.c_uint64, C.c_uint64)
# sscope_allan_opts.plan_flags
ALLAN_EVICT_INPUT = 1 << 0
ALLAN_RELEASE_WORKSPACE = 1 << 1


class ReadOpts(C.Structure):
    _fields_ = [("raw", C.c_char_p), ("raw_scale", c_dbl),
                ("raw_offset", c_dbl), ("default_unit", C.c_char_p),
                ("columns", C.c_char_p), ("time_column", C.c_char_p),
                ("temp_column", C.c_char_p), ("rate_hz", c_dbl),
                ("nan_as_gap", C.c_bool), ("no_time", C.c_bool),
                ("threads", C.c_uint), ("in_place", C.c_bool),
                ("progress", PROGRESS),
                ("progress_ctx", C.c_void_p), ("topic", C.c_char_p),
                ("in_place_unchecked", C.c_bool)]


class OpenOpts(C.Structure):
    _fields_ = [("read", C.POINTER(ReadOpts)), ("calib", C.c_void_p),
                ("n_calib", c_size)]


class Notes(C.Structure):
    _fields_ = [("stage", C.c_int), ("unterminated", C.c_bool),
                ("rows_read", c_size), ("calib_gsens_skipped", C.c_uint),
                ("unit_unused", C.c_bool), ("rate_implausible", C.c_bool),
                ("rate_hint", Diag), ("rate_disagrees", C.c_bool),
                ("time_column_rate_hz", c_dbl)]


class Topic(C.Structure):
    _fields_ = [("name", C.c_char_p), ("type", C.c_char_p),
                ("messages", C.c_uint64), ("readable", C.c_bool),
                ("selected", C.c_bool)]


class Source(C.Structure):
    _fields_ = [("format", C.c_char_p), ("n_topics", c_size),
                ("topics", C.POINTER(Topic)), ("receive_s", c_dptr)]


class Channel(C.Structure):
    _fields_ = [("col", Column), ("data", c_dptr), ("n_nan", c_size)]


class TimeOrder(C.Structure):
    _fields_ = [("n", c_size), ("n_repeats", c_size),
                ("n_decreasing", c_size), ("n_swaps", c_size),
                ("first_row", c_size), ("first_t_s", c_dbl),
                ("first_prev_s", c_dbl), ("t0_s", c_dbl),
                ("last_s", c_dbl * 3), ("pending", C.c_int)]


class Timing(C.Structure):
    _fields_ = [("dt_median_s", c_dbl), ("dt_min_s", c_dbl),
                ("dt_max_s", c_dbl), ("jitter_rms_s", c_dbl),
                ("rate_hz", c_dbl), ("n_gaps", c_size), ("n_missing", c_size),
                ("n_backwards", c_size), ("order", TimeOrder)]


class Gap(C.Structure):
    _fields_ = [("index", c_size), ("t_s", c_dbl), ("length_s", c_dbl),
                ("missing", c_size)]


class Capture(C.Structure):
    _fields_ = [("source", C.c_char_p), ("n", c_size),
                ("n_channels", c_size), ("channels", C.POINTER(Channel)),
                ("time_s", c_dptr), ("temp_degc", c_dptr),
                ("time_col", Column), ("temp_col", Column),
                ("rate_hz", c_dbl), ("rate_source", C.c_int),
                ("n_nan", c_size), ("source_info", C.POINTER(Source)),
                ("mapping", C.c_void_p), ("mapping_len", c_size),
                ("unterminated", C.c_bool),
                ("timing", Timing), ("has_timing", C.c_bool),
                ("gaps", C.POINTER(Gap)), ("n_gaps", c_size),
                ("is_view", C.c_bool), ("values_unchecked", C.c_bool),
                ("rate_note", C.c_char * 160)]


class AllanOpts(C.Structure):
    _fields_ = [("dev", C.c_int), ("input", C.c_int), ("ci_level", c_dbl),
                ("alpha_fixed", C.c_bool), ("alpha", C.c_int),
                ("stride_div", c_size), ("threads", C.c_uint),
                ("reject_nan", C.c_bool), ("plan_flags", C.c_uint)]


class AllanPoint(C.Structure):
    _fields_ = [("tau_s", c_dbl), ("m", c_size), ("terms", c_size),
                ("skipped", c_size), ("stride", c_size), ("dev", c_dbl),
                ("dev_lo", c_dbl), ("dev_hi", c_dbl), ("edf", c_dbl),
                ("edf_full", c_dbl), ("edf_alpha", c_dbl), ("alpha", C.c_int),
                ("alpha_identified", C.c_bool)]


class NoiseCoef(C.Structure):
    _fields_ = [("value", c_dbl), ("lo", c_dbl), ("hi", c_dbl),
                ("var_sd", c_dbl), ("estimate", c_dbl),
                ("fitted", C.c_bool), ("present", C.c_bool),
                ("why", C.c_int), ("z", c_dbl), ("square", c_dbl)]


class NoiseReadoff(C.Structure):
    _fields_ = [("n", c_dbl), ("n_tau_s", c_dbl), ("b", c_dbl),
                ("b_tau_s", c_dbl), ("k", c_dbl), ("k_tau_s", c_dbl)]


class NoiseFitOpts(C.Structure):
    _fields_ = [("ci_level", c_dbl), ("allowed", C.c_uint),
                ("forced", C.c_uint), ("model_error", c_dbl),
                ("detect_sigma", c_dbl),
                ("tau_min_s", c_dbl), ("tau_max_s", c_dbl),
                ("skip", C.c_bool), ("plan", C.c_void_p)]


class NoiseFit(C.Structure):
    _fields_ = [("coef", NoiseCoef * 5), ("terms", C.c_uint),
                ("ci_level", c_dbl), ("n_points", c_size), ("chi2", c_dbl),
                ("dof", c_dbl), ("p_value", c_dbl), ("aic", c_dbl),
                ("n_plausible", c_size), ("readoff", NoiseReadoff),
                ("present", C.c_uint), ("select_z", c_dbl),
                ("sq_cov", c_dbl * 25)]


class AllanResult(C.Structure):
    _fields_ = [("n_points", c_size), ("points", C.POINTER(AllanPoint)),
                ("oadev", C.POINTER(AllanPoint)), ("n_oadev", c_size),
                ("n_phase", c_size), ("have_fit", C.c_bool),
                ("fit_error", C.c_int), ("fit", NoiseFit),
                ("fit_diag", Diag), ("n_gap_omitted", c_size),
                ("gap_note", Diag)]


class PsdOpts(C.Structure):
    _fields_ = [("window", C.c_int), ("nperseg", c_size),
                ("noverlap", c_size), ("nfft", c_size), ("detrend", C.c_int),
                ("scaling", C.c_int), ("skip_nonfinite", C.c_bool),
                ("shorten", C.c_bool), ("spectrogram_cols", c_size),
                ("measure", C.c_bool), ("threads", C.c_uint)]


class Spectrum(C.Structure):
    _fields_ = [("n_bins", c_size), ("freq_hz", c_dptr), ("value", c_dptr),
                ("fs_hz", c_dbl), ("scaling", C.c_int), ("window", C.c_int),
                ("detrend", C.c_int), ("nperseg", c_size),
                ("noverlap", c_size), ("nfft", c_size),
                ("n_segments", c_size), ("n_skipped", c_size),
                ("n_samples", C.c_uint64), ("enbw_hz", c_dbl),
                ("bin_hz", c_dbl), ("rms", c_dbl)]


class SensorSpec(C.Structure):
    _fields_ = [("name", C.c_char * 64), ("quantity", C.c_int),
                ("has", C.c_uint), ("range", c_dbl), ("q", c_dbl),
                ("n", c_dbl), ("b", c_dbl), ("k", c_dbl), ("r", c_dbl),
                ("bias", c_dbl), ("scale_factor_error", c_dbl),
                ("bias_tempco", c_dbl), ("temp_min_degc", c_dbl),
                ("temp_max_degc", c_dbl), ("sensitivity", c_dbl),
                ("zero_output_v", c_dbl), ("bandwidth_hz", c_dbl),
                ("filter_order", C.c_int)]


class SimTone(C.Structure):
    _fields_ = [("freq_hz", c_dbl), ("amplitude", c_dbl),
                ("phase_rad", c_dbl)]


class SimOpts(C.Structure):
    _fields_ = [("rate_hz", c_dbl), ("seed", C.c_uint64),
                ("stream", C.c_uint64), ("temp_profile", C.c_int),
                ("temp_degc", c_dbl), ("temp2_degc", c_dbl),
                ("temp_rate_degc_s", c_dbl), ("temp_period_s", c_dbl),
                ("temp_wave", C.c_int), ("temp_noise_degc", c_dbl),
                ("ref_temp_degc", c_dbl), ("bias_poly", c_dbl * 4),
                ("hysteresis", c_dbl),
                ("hysteresis_deadband_degc_s", c_dbl), ("gradient", c_dbl),
                ("tones", SimTone * 8), ("n_tones", c_size),
                ("quant_step", c_dbl), ("flicker_tau_min_s", c_dbl),
                ("flicker_tau_max_s", c_dbl), ("no_clip", C.c_bool)]


class TempbiasRun(C.Structure):
    _fields_ = [("x", c_dptr), ("stride", c_size), ("temp_degc", c_dptr),
                ("n", c_size), ("rate_hz", c_dbl)]


class TempbiasOpts(C.Structure):
    _fields_ = [("order", C.c_int), ("order_auto", C.c_bool),
                ("ref_temp_set", C.c_bool), ("ref_temp_degc", c_dbl),
                ("block_s", c_dbl), ("smooth_s", c_dbl), ("bin_degc", c_dbl),
                ("deadband_degc_s", c_dbl), ("rate_deadband", C.c_bool),
                ("no_hysteresis", C.c_bool), ("no_gradient", C.c_bool),
                ("warmup_set", C.c_bool), ("warmup_s", c_dbl),
                ("min_span_degc", c_dbl), ("alpha", c_dbl),
                ("table_step_degc", c_dbl)]


class TempbiasRunInfo(C.Structure):
    _fields_ = [("warmup_s", c_dbl), ("offset", c_dbl), ("offset_sd", c_dbl),
                ("mean_temp_degc", c_dbl), ("used", c_size)]


class TempbiasResult(C.Structure):
    _fields_ = [("order", C.c_int), ("order_requested", C.c_int),
                ("order_cap", C.c_int), ("levels", C.c_int),
                ("order_lowered", C.c_bool), ("note", C.c_char * 200),
                ("ref_temp_degc", c_dbl), ("half_span_degc", c_dbl),
                ("temp_min_degc", c_dbl), ("temp_max_degc", c_dbl),
                ("coef", c_dbl * 5), ("coef_sd", c_dbl * 5), ("dof", c_dbl),
                ("have_hysteresis", C.c_bool), ("hysteresis", c_dbl),
                ("hysteresis_sd", c_dbl), ("hysteresis_max", c_dbl),
                ("hysteresis_at_degc", c_dbl), ("have_split", C.c_bool),
                ("heat_coef", c_dbl * 5), ("cool_coef", c_dbl * 5),
                ("hyst_grad_collinear", C.c_bool), ("hyst_grad_vif", c_dbl),
                ("rate_heat_degc_s", c_dbl), ("rate_cool_degc_s", c_dbl),
                ("have_gradient", C.c_bool), ("gradient", c_dbl),
                ("gradient_sd", c_dbl), ("deadband_degc_s", c_dbl),
                ("turn_band_degc", c_dbl), ("smooth_s", c_dbl),
                ("block_s", c_dbl), ("bin_degc", c_dbl),
                ("residual_rms", c_dbl), ("sensitivity", c_dbl),
                ("sensitivity_sd", c_dbl), ("peak_to_peak", c_dbl),
                ("n_runs", c_size), ("runs", C.POINTER(TempbiasRunInfo)),
                ("repeat_sd", c_dbl), ("repeat_range", c_dbl),
                ("stability", c_dbl), ("stability_tau_s", c_dbl),
                ("n_bins", c_size), ("bins", C.c_void_p),
                ("n_table", c_size), ("table_temp_degc", c_dptr),
                ("table_bias", c_dptr), ("used", c_size),
                ("dropped", c_size)]


class CalibDetect(C.Structure):
    _fields_ = [("window_s", c_dbl), ("min_static_s", c_dbl),
                ("init_static_s", c_dbl), ("k", c_dbl), ("reference", c_dbl),
                ("threshold", c_dbl), ("n_intervals", c_size)]


class CalibInterval(C.Structure):
    _fields_ = [("start", c_size), ("end", c_size)]


M33 = (c_dbl * 3) * 3


class CalibTriad(C.Structure):
    _fields_ = [("bias", c_dbl * 3), ("scale", c_dbl * 3), ("mis", M33),
                ("gsens", M33), ("bias_sd", c_dbl * 3),
                ("scale_sd", c_dbl * 3), ("mis_sd", M33), ("gsens_sd", M33),
                ("has_gsens", C.c_bool), ("n_params", C.c_uint),
                ("poses", c_size), ("residual_rms", c_dbl),
                ("iterations", C.c_uint), ("cond", c_dbl)]


class AdcSpec(C.Structure):
    _fields_ = [("name", C.c_char * 64), ("bits", C.c_int), ("lo", c_dbl),
                ("hi", c_dbl), ("analog", C.c_bool), ("quantity", C.c_int),
                ("has", C.c_uint), ("rate_hz", c_dbl), ("noise", c_dbl),
                ("enob", c_dbl), ("inl_lsb", c_dbl), ("dnl_lsb", c_dbl),
                ("offset", c_dbl), ("gain_error", c_dbl),
                ("offset_drift", c_dbl), ("gain_drift", c_dbl),
                ("ref_temp_degc", c_dbl), ("reference", C.c_int),
                ("mode", C.c_int), ("coding", C.c_char * 24),
                ("oversample", C.c_uint), ("inl_profile", C.c_char * 256)]


class AdcTermResult(C.Structure):
    _fields_ = [("value", c_dbl), ("reference", c_dbl), ("ratio", c_dbl),
                ("pass_limit", c_dbl), ("fail_limit", c_dbl),
                ("verdict", C.c_int)]


class AdcAnalysis(C.Structure):
    _fields_ = [("lsb", c_dbl), ("rate_hz", c_dbl), ("sigma_sensor", c_dbl),
                ("sigma_adc", c_dbl), ("sigma_over_q", c_dbl),
                ("dithered", C.c_bool), ("n_quant", c_dbl),
                ("q_quant", c_dbl), ("n_adc", c_dbl), ("n_total", c_dbl),
                ("noise_degradation", c_dbl), ("adev_q_100s", c_dbl),
                ("bias_bound", c_dbl), ("temp_span_degc", c_dbl),
                ("temp_span_default", C.c_bool),
                ("offset_drift_bias", c_dbl), ("scale_drift", c_dbl),
                ("range_lo", c_dbl), ("range_hi", c_dbl),
                ("headroom", c_dbl), ("min_bits", C.c_int),
                ("term", AdcTermResult * 5), ("verdict", C.c_int),
                ("limiting", C.c_int), ("margin", c_dbl)]


# every structure mirrored, by C name, for the layout test
STRUCTS = {
    "sscope_diag": Diag, "sscope_unit": Unit, "sscope_capture_column": Column,
    "sscope_reader_opts": ReadOpts, "sscope_capture_topic": Topic,
    "sscope_capture_open_opts": OpenOpts,
    "sscope_capture_notes": Notes,
    "sscope_capture_source": Source, "sscope_capture_channel": Channel,
    "sscope_timing": Timing, "sscope_timing_order": TimeOrder,
    "sscope_timing_gap": Gap,
    "sscope_capture": Capture, "sscope_allan_opts": AllanOpts,
    "sscope_allan_point": AllanPoint, "sscope_noise_coef": NoiseCoef,
    "sscope_noise_readoff": NoiseReadoff,
    "sscope_noise_fit_opts": NoiseFitOpts, "sscope_noise_fit": NoiseFit,
    "sscope_allan_result": AllanResult, "sscope_psd_opts": PsdOpts,
    "sscope_psd_spectrum": Spectrum, "sscope_sensor_spec": SensorSpec,
    "sscope_sim_tone": SimTone, "sscope_sim_opts": SimOpts,
    "sscope_tempbias_run": TempbiasRun, "sscope_tempbias_opts": TempbiasOpts,
    "sscope_tempbias_runinfo": TempbiasRunInfo,
    "sscope_tempbias_result": TempbiasResult,
    "sscope_calib_detect": CalibDetect,
    "sscope_calib_interval": CalibInterval,
    "sscope_calib_triad": CalibTriad, "sscope_adc_spec": AdcSpec,
    "sscope_adc_term_result": AdcTermResult,
    "sscope_adc_analysis": AdcAnalysis,
}


# every library function the module calls that computes (the package
# checks GSL's error record after each one: sensorscope/__init__.py,
# _gsl_check); not the _free and _clear ones, which compute nothing and
# run in __del__ and finally blocks, where a raise is lost or masks another
functions = []


def _fn(name, res, *args):
    f = getattr(lib, name)
    f.restype = res
    f.argtypes = list(args)
    if not name.endswith(("_free", "_clear")):
        functions.append(f)
    return f


# GSL's errors recorded instead of abort() (sscope-gsl.h); not in
# `functions`: they are the check itself
def _gsl_fn(name, res, *args):
    f = getattr(lib, name)
    f.restype = res
    f.argtypes = list(args)
    return f


gsl_errors_record = _gsl_fn("sscope_gsl_errors_record", None)
gsl_error_pending = _gsl_fn("sscope_gsl_error_pending", C.c_bool)
gsl_error_take = _gsl_fn("sscope_gsl_error_take", C.c_int,
                         C.POINTER(C.c_int), C.c_char_p, c_size)


strerror = _fn("sscope_strerror", C.c_char_p, C.c_int)
version = _fn("sscope_version", C.c_char_p)
capture_load = _fn("sscope_capture_load", C.c_int,
                   C.POINTER(C.POINTER(Capture)), C.c_char_p,
                   C.POINTER(ReadOpts), C.POINTER(Diag))
capture_open = _fn("sscope_capture_open", C.c_int,
                   C.POINTER(C.POINTER(Capture)), C.c_char_p,
                   C.POINTER(OpenOpts), C.POINTER(Notes), C.POINTER(Diag))
capture_free = _fn("sscope_capture_free", None, C.POINTER(Capture))
capture_check_rate = _fn("sscope_capture_check_rate", C.c_int,
                         C.POINTER(Capture), C.POINTER(Diag))
quantity_name = _fn("sscope_quantity_name", C.c_char_p, C.c_int)
term_unit = _fn("sscope_term_unit", C.c_char_p, C.c_int, C.c_int)
term_si_unit = _fn("sscope_term_si_unit", C.c_char_p, C.c_int, C.c_int)
unit_parse = _fn("sscope_unit_parse", C.c_int, C.c_char_p, C.POINTER(Unit),
                 C.POINTER(Diag))
unit_quantity = _fn("sscope_unit_quantity", C.c_int, C.POINTER(Unit))
convert = _fn("sscope_unit_convert_text", C.c_int, c_dbl, C.c_char_p, C.c_char_p,
              c_dptr)
dev_parse = _fn("sscope_allan_dev_parse", C.c_int, C.c_char_p, C.POINTER(C.c_int))
allan_analyze = _fn("sscope_allan_analyze", C.c_int, c_dptr, c_size, c_size,
                    c_dbl, C.c_int, C.POINTER(AllanOpts),
                    C.POINTER(NoiseFitOpts),
                    C.POINTER(C.POINTER(AllanResult)), C.POINTER(Diag))
allan_new = _fn("sscope_allan_new", C.c_int, C.POINTER(C.c_void_p), c_size,
                C.POINTER(AllanOpts))
allan_compute = _fn("sscope_allan_compute", C.c_int, C.c_void_p, c_dptr,
                    c_size, c_size, c_dbl, C.POINTER(c_size), c_size,
                    C.POINTER(AllanPoint), C.POINTER(c_size),
                    C.POINTER(Diag))
allan_free = _fn("sscope_allan_free", None, C.c_void_p)
quantity_si_unit = _fn("sscope_quantity_si_unit", C.c_char_p, C.c_int)
allan_max_m = _fn("sscope_allan_max_m", c_size, C.c_int, c_size)
noise_p_is_bound = _fn("sscope_noise_p_is_bound", C.c_bool, c_dbl)
timing_order_check = _fn("sscope_timing_order_check", C.c_int,
                         C.POINTER(TimeOrder), C.POINTER(Diag))
timing_order_feed = _fn("sscope_timing_order_feed", None,
                        C.POINTER(TimeOrder), c_dptr, c_size)
noise_coef_resolved = _fn("sscope_noise_coef_resolved", C.c_bool,
                          C.POINTER(NoiseCoef))
noise_fit_rejected = _fn("sscope_noise_fit_rejected", C.c_bool,
                         C.POINTER(NoiseFit), c_dbl)
allan_n_phase = _fn("sscope_allan_n_phase", c_size, C.c_int, c_size)
allan_result_free = _fn("sscope_allan_result_free", None,
                        C.POINTER(AllanResult))
noise_fit = _fn("sscope_noise_fit", C.c_int, C.POINTER(AllanPoint), c_size,
                c_dbl, c_size, C.POINTER(NoiseFitOpts), C.POINTER(NoiseFit),
                C.POINTER(Diag))
noise_plan_new = _fn("sscope_noise_plan_new", C.c_int,
                     C.POINTER(C.c_void_p))
noise_plan_free = _fn("sscope_noise_plan_free", None, C.c_void_p)
psd_opts_init = _fn("sscope_psd_opts_init", None, C.POINTER(PsdOpts))
psd_noverlap = _fn("sscope_psd_noverlap", c_size, C.c_double, c_size)
window_from_name = _fn("sscope_psd_window_from_name", C.c_int, C.c_char_p,
                       C.POINTER(C.c_int))
psd_welch = _fn("sscope_psd_welch", C.c_int, c_dptr, c_size, c_size, c_dbl,
                C.POINTER(PsdOpts), C.POINTER(Spectrum))
spectrum_clear = _fn("sscope_psd_spectrum_clear", None, C.POINTER(Spectrum))
sensor_spec_load = _fn("sscope_sensor_spec_load", C.c_int, C.c_char_p,
                       C.POINTER(SensorSpec), C.POINTER(Diag))
sim_new = _fn("sscope_sim_new", C.c_int, C.POINTER(C.c_void_p),
              C.POINTER(SensorSpec), C.POINTER(SimOpts), C.POINTER(Diag))
sim_generate = _fn("sscope_sim_generate", C.c_int, C.c_void_p, c_dptr, c_dptr,
                   c_dptr, c_size)
sim_free = _fn("sscope_sim_free", None, C.c_void_p)
tempbias_fit = _fn("sscope_tempbias_fit", C.c_int, C.POINTER(TempbiasRun),
                   c_size, C.POINTER(TempbiasOpts),
                   C.POINTER(C.POINTER(TempbiasResult)), C.POINTER(Diag))
tempbias_result_free = _fn("sscope_tempbias_result_free", None,
                           C.POINTER(TempbiasResult))
calib_accel_multipos = _fn("sscope_calib_accel_multipos", C.c_int, c_dptr,
                           c_dptr, c_dptr, c_size, c_size, c_dbl, c_dbl,
                           C.POINTER(CalibDetect), C.POINTER(CalibInterval),
                           c_size, C.POINTER(CalibTriad), c_dptr, c_dptr,
                           C.POINTER(Diag))
adc_spec_load = _fn("sscope_adc_spec_load", C.c_int, C.c_char_p,
                    C.POINTER(AdcSpec), C.POINTER(Diag))
adc_analyze = _fn("sscope_adc_analyze", C.c_int, C.POINTER(SensorSpec),
                  C.POINTER(AdcSpec), c_dbl, C.POINTER(AdcAnalysis),
                  C.POINTER(Diag))
adc_verdict_name = _fn("sscope_adc_verdict_name", C.c_char_p, C.c_int)
adc_term_name = _fn("sscope_adc_term_name", C.c_char_p, C.c_int)


# ------------------------------------------------ the adequacy check
class AdequacyOpts(C.Structure):
    _fields_ = [("rate_hz", c_dbl), ("angle", C.c_bool), ("unit", C.c_char_p),
                ("temp_degc", c_dptr), ("temp_stride", c_size),
                ("requested", C.c_uint), ("max_contrast", c_dbl),
                ("fit_p_level", c_dbl), ("alpha", c_dbl), ("blocks", c_size),
                ("davar_window_s", c_dbl), ("davar_step_s", c_dbl),
                ("no_davar", C.c_bool), ("moving_channel", C.c_char_p),
                ("moving_contrast", c_dbl)]


class AdequacyFinding(C.Structure):
    _fields_ = [("cause", C.c_int), ("severity", C.c_int), ("terms", C.c_uint),
                ("t_start_s", c_dbl), ("t_end_s", c_dbl),
                ("tau_min_s", c_dbl), ("tau_max_s", c_dbl),
                ("statistic", c_dbl), ("p_value", c_dbl),
                ("action_s", c_dbl), ("message", C.c_char * 400)]


class AdequacyDavar(C.Structure):
    _fields_ = [("n_win", c_size), ("n_tau", c_size), ("window_s", c_dbl),
                ("step_s", c_dbl), ("t_s", c_dptr), ("tau_s", c_dptr),
                ("dev", c_dptr), ("edf", c_dptr), ("model", c_dptr)]


class Adequacy(C.Structure):
    _fields_ = [("duration_s", c_dbl), ("still_tested", C.c_bool),
                ("still", C.c_bool), ("contrast", c_dbl),
                ("max_contrast", c_dbl), ("have_fit", C.c_bool),
                ("fit_rejected", C.c_bool), ("fit_p_value", c_dbl),
                ("stationarity_tested", C.c_bool), ("stationary", C.c_bool),
                ("requested", C.c_uint), ("established", C.c_uint),
                ("doubtful", C.c_uint), ("verdict", C.c_int),
                ("n_findings", c_size),
                ("findings", C.POINTER(AdequacyFinding)),
                ("davar", AdequacyDavar)]


STRUCTS.update({
    "sscope_adequacy_opts": AdequacyOpts,
    "sscope_adequacy_finding": AdequacyFinding,
    "sscope_adequacy_davar": AdequacyDavar, "sscope_adequacy": Adequacy,
})

adequacy_check = _fn("sscope_adequacy_check", C.c_int, c_dptr, c_size, c_size,
                     C.POINTER(NoiseFit), C.POINTER(AdequacyOpts),
                     C.POINTER(C.POINTER(Adequacy)), C.POINTER(Diag))
adequacy_free = _fn("sscope_adequacy_free", None, C.POINTER(Adequacy))
adequacy_cause_name = _fn("sscope_adequacy_cause_name", C.c_char_p, C.c_int)
adequacy_severity_name = _fn("sscope_adequacy_severity_name", C.c_char_p,
                             C.c_int)


# ------------------------------------------------ datasheet lines
class DatasheetInfo(C.Structure):
    _fields_ = [("key", C.c_char_p), ("name", C.c_char_p),
                ("definition", C.c_char_p), ("si_suffix", C.c_char_p),
                ("term", C.c_int), ("tau_s", c_dbl),
                ("magnitude", C.c_bool)]


class DatasheetGjb(C.Structure):
    _fields_ = [("value", c_dbl), ("lo", c_dbl), ("hi", c_dbl),
                ("n_means", c_size), ("m", c_size)]


class DatasheetSpec(C.Structure):
    _fields_ = [("line", C.c_int), ("value", c_dbl), ("bandwidth_hz", c_dbl)]


class DatasheetCheck(C.Structure):
    _fields_ = [("line", C.c_int), ("limit", c_dbl), ("value", c_dbl),
                ("lo", c_dbl), ("hi", c_dbl), ("bound", C.c_bool),
                ("verdict", C.c_int), ("why", C.c_char_p),
                ("fit_rejected", C.c_bool)]


class DatasheetOpts(C.Structure):
    _fields_ = [("level", c_dbl)]


STRUCTS.update({
    "sscope_datasheet_info": DatasheetInfo,
    "sscope_datasheet_gjb": DatasheetGjb,
    "sscope_datasheet_spec": DatasheetSpec,
    "sscope_datasheet_check": DatasheetCheck,
    "sscope_datasheet_opts": DatasheetOpts,
})

datasheet_info = _fn("sscope_datasheet_info", C.POINTER(DatasheetInfo),
                     C.c_int)
datasheet_line_by_key = _fn("sscope_datasheet_line_by_key", C.c_int,
                            C.c_char_p)
datasheet_factor = _fn("sscope_datasheet_factor", C.c_int, C.c_int, c_dbl,
                       c_dptr)
datasheet_gjb_from_terms = _fn("sscope_datasheet_gjb_from_terms", c_dbl,
                               c_dbl, c_dbl, c_dbl, c_dbl)
datasheet_gjb = _fn("sscope_datasheet_gjb", C.c_int, c_dptr, c_size, c_size,
                    c_dbl, c_dbl, c_dbl, C.POINTER(DatasheetGjb),
                    C.POINTER(Diag))
datasheet_check = _fn("sscope_datasheet_check", C.c_int, c_dptr, c_size,
                      c_size, c_dbl, C.POINTER(DatasheetSpec), c_size,
                      C.POINTER(DatasheetOpts), C.POINTER(DatasheetCheck),
                      C.POINTER(Diag))
datasheet_verdict_name = _fn("sscope_datasheet_verdict_name", C.c_char_p,
                             C.c_int)


# ------------------------------------------------ lot statistics
class LotOpts(C.Structure):
    _fields_ = [("level", c_dbl), ("outlier_alpha", c_dbl),
                ("keep_outliers", C.c_bool)]


class LotSpread(C.Structure):
    _fields_ = [("k", c_size), ("k_used", c_size), ("level", c_dbl),
                ("mean", c_dbl), ("mean_lo", c_dbl), ("mean_hi", c_dbl),
                ("between_sd", c_dbl), ("between_lo", c_dbl),
                ("between_hi", c_dbl), ("total_sd", c_dbl), ("q", c_dbl),
                ("q_p", c_dbl), ("i2", c_dbl), ("n_outliers", c_size),
                ("outlier_z", c_dbl)]


STRUCTS.update({
    "sscope_lot_opts": LotOpts,
    "sscope_lot_spread": LotSpread,
})

lot_spread = _fn("sscope_lot_spread", C.c_int, c_dptr, c_dptr, c_size,
                 C.POINTER(LotOpts), C.POINTER(LotSpread), c_dptr,
                 C.POINTER(C.c_bool))


class LotBiasOpts(C.Structure):
    _fields_ = [("blocks", c_size), ("level", c_dbl), ("n", c_dbl),
                ("b", c_dbl), ("k", c_dbl), ("b_upper", c_dbl),
                ("k_upper", c_dbl)]


class LotBias(C.Structure):
    _fields_ = [("blocks", c_size), ("block_n", c_size), ("level", c_dbl),
                ("bias", c_dbl), ("bias_se", c_dbl), ("bias_lo", c_dbl),
                ("bias_hi", c_dbl), ("drift_u_s", c_dbl), ("drift_se", c_dbl),
                ("drift_lo", c_dbl), ("drift_hi", c_dbl),
                ("have_temp", C.c_bool), ("tempco_u_degc", c_dbl),
                ("tempco_se", c_dbl), ("tempco_lo", c_dbl),
                ("tempco_hi", c_dbl), ("temp_mean_degc", c_dbl),
                ("temp_span_degc", c_dbl), ("temp_time_corr", c_dbl),
                ("resid_lag1", c_dbl), ("resid_correlated", C.c_bool),
                ("drift_se_resid", c_dbl), ("drift_se_model", c_dbl),
                ("drift_se_from_model", C.c_bool),
                ("tempco_se_resid", c_dbl), ("tempco_se_model", c_dbl),
                ("tempco_se_from_model", C.c_bool),
                ("drift_se_upper", c_dbl), ("drift_upper_lo", c_dbl),
                ("drift_upper_hi", c_dbl), ("tempco_se_upper", c_dbl),
                ("tempco_upper_lo", c_dbl), ("tempco_upper_hi", c_dbl)]


STRUCTS.update({
    "sscope_lot_bias_opts": LotBiasOpts,
    "sscope_lot_bias": LotBias,
})

lot_bias = _fn("sscope_lot_bias", C.c_int, c_dptr, c_size, c_size, c_dbl,
               c_dptr, c_size, C.POINTER(LotBiasOpts), C.POINTER(LotBias))
lot_temp_removed = _fn("sscope_lot_temp_removed", C.c_int, c_dptr, c_size,
                       c_size, c_dptr, c_size, C.POINTER(LotBias), c_dptr)
lot_model_var = _fn("sscope_lot_model_var", C.c_int, c_dptr, c_size, c_dbl,
                    c_dbl, c_dbl, c_dbl, c_dptr)


# ------------------------------------------------ noise-parameter files
class ExportChan(C.Structure):
    _fields_ = [("name", C.c_char_p), ("quantity", C.c_int),
                ("fit", C.POINTER(NoiseFit)),
                ("adequacy", C.POINTER(Adequacy))]


class ExportOpts(C.Structure):
    _fields_ = [("rate_hz", c_dbl), ("inflate", c_dbl), ("source", C.c_char_p),
                ("topic", C.c_char_p), ("sensor_name", C.c_char_p),
                ("duration_s", c_dbl), ("force", C.c_bool)]


class ExportFile(C.Structure):
    _fields_ = [("text", C.c_void_p), ("len", c_size),
                ("warnings", C.c_void_p), ("forcible", C.c_bool)]


STRUCTS.update({
    "sscope_export_chan": ExportChan, "sscope_export_opts": ExportOpts,
    "sscope_export_file": ExportFile,
})

export_target = _fn("sscope_export_target", C.c_char_p, c_size)
export_name = _fn("sscope_export_name", C.c_char_p, C.c_char_p)
export_default_file = _fn("sscope_export_default_file", C.c_char_p,
                          C.c_char_p)
export = _fn("sscope_export", C.c_int, C.c_char_p, C.POINTER(ExportChan),
             c_size, C.POINTER(ExportOpts), C.POINTER(ExportFile),
             C.POINTER(Diag))
export_file_free = _fn("sscope_export_file_free", None, C.POINTER(ExportFile))


class PlanOpts(C.Structure):
    _fields_ = [("ci_level", c_dbl), ("probability", c_dbl),
                ("detect_sigma", c_dbl), ("max_length_s", c_dbl)]


class PlanPoint(C.Structure):
    _fields_ = [("length_s", c_dbl), ("p_present", c_dbl),
                ("p_width", c_dbl), ("probability", c_dbl),
                ("rel_half_width", c_dbl)]


STRUCTS["sscope_plan_opts"] = PlanOpts
STRUCTS["sscope_plan_point"] = PlanPoint
plan_predict = _fn("sscope_plan_predict", C.c_int, c_dptr, c_dbl, c_dbl,
                   C.c_int, c_dbl, C.POINTER(PlanOpts), C.POINTER(PlanPoint))
plan_needed = _fn("sscope_plan_needed", C.c_int, c_dptr, c_dbl, C.c_int,
                  c_dbl, C.POINTER(PlanOpts), C.POINTER(c_dbl))
