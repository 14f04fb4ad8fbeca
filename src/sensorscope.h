/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sensorscope.h
 * @brief libsensorscope: characterisation of inertial sensors and converters.
 *
 * Conventions, stated once for the whole library:
 * - Every fallible function returns 0 on success or a negative errno:
 *   -EINVAL  a bad parameter (the caller's mistake, e.g. a negative rate);
 *   -EDOM    the data do not fit the request (too short, constant, NaN);
 *   -ERANGE  clipping or overflow (a count that does not fit, a value out of
 *            a converter's range);
 *   -ENOMEM  out of memory;
 *   -ENOTSUP a feature that was compiled out;
 *   -EIO, -ETIMEDOUT, -ENODEV  acquisition failures;
 *   -EBADMSG a malformed file or frame.
 *   sscope_strerror() gives a short text for each.
 * - Values are SI inside the library: rad, rad/s, m/s^2, m/s, m, s, Hz, V
 *   and degrees Celsius for temperature.  Conventional units (deg/h, g, ...)
 *   appear only through the unit functions (sscope-unit.h).  Physical
 *   parameters carry their unit as a suffix (_s, _hz, _rad_s, _m_s2,
 *   _degc, _v).
 * - 1-D data are passed as (const double *x, size_t stride, size_t n): the
 *   k-th sample is x[k * stride], so one column of an interleaved buffer is
 *   analysed without a copy.
 * - One-sided PSDs are in unit^2/Hz normalised by fs * sum(w^2) (scipy's
 *   "density"); FFTs are unnormalised.  Allan deviations follow IEEE 952/1554
 *   with tau = m / fs.  An ideal quantizer is mid-tread with LSB = span / 2^N.
 * - Names: every public header sscope-AREA.h declares only names with its
 *   area as sub-prefix: functions and types sscope_AREA_* (or the type
 *   struct sscope_AREA itself), macros and enum constants SSCOPE_AREA_*
 *   (sscope-psd.h: sscope_psd_welch, struct sscope_psd_spectrum,
 *   SSCOPE_PSD_WINDOW_HANN).  Only sscope-core.h holds library-wide names
 *   (sscope_version, sscope_strerror, struct sscope_diag).  Internal
 *   helpers (ssc_*) are neither declared here nor exported.
 * - Lifetimes, one vocabulary: an object the library allocates comes from
 *   sscope_X_new (or a function that says so, e.g. sscope_capture_load,
 *   sscope_allan_analyze) and goes back with sscope_X_free; a struct the
 *   caller owns (results included) is filled by sscope_X_init or by the
 *   computing function and its owned arrays are released by sscope_X_clear
 *   (the struct itself stays the caller's); files and devices are
 *   sscope_X_open / sscope_X_close (a writer is closed by _commit, which
 *   keeps the file, or _abort, which removes it).  The caller owns every
 *   array it passes.
 * - After a failure an out-pointer holds nothing to free: every function
 *   that hands back an object (sscope_X_new, sscope_X_open,
 *   sscope_capture_load, sscope_allan_analyze, ...) sets it to NULL first,
 *   and a caller-owned result struct a failing function was filling may
 *   be given to its sscope_X_clear.
 * - Options: a NULL options pointer means every default, and so does a
 *   zero-initialised struct (struct sscope_X_opts o = { 0 }), every
 *   one; a field whose zero would be a valid request has a named value
 *   for it (SSCOPE_PSD_NO_OVERLAP, SSCOPE_VIB_NO_PEAKS, a negative
 *   level or tolerance).  sscope_psd_opts_init() and
 *   sscope_vib_opts_init() only zero the struct.
 * - ABI: the shared library's libtool version (-version-info C:R:A in
 *   Makefile.am) follows libtool's rules, written there.
 * - Nothing in the library prints, exits or keeps mutable static state,
 *   save the record of sscope-gsl.h.  It installs no GSL error handler
 *   (GSL's default aborts): the host installs its own, or the recorder of
 *   sscope_gsl_errors_record() and checks sscope_gsl_error_pending() after
 *   each call.
 */
#ifndef SENSORSCOPE_H
#define SENSORSCOPE_H

/*
 * The public headers, one per area (the sub-prefix of its names), installed
 * in $(includedir)/sensorscope.  Include this one to get them all.
 */
#include "sscope-core.h"
#include "sscope-gsl.h"
#include "sscope-quantity.h"
#include "sscope-unit.h"
#include "sscope-term.h"
#include "sscope-stats.h"
#include "sscope-timing.h"
#include "sscope-capture.h"
#include "sscope-reader.h"
#include "sscope-writer.h"
#include "sscope-sensor.h"
#include "sscope-psd.h"
#include "sscope-vib.h"
#include "sscope-adis.h"
#include "sscope-spiadc.h"
#include "sscope-calib.h"
#include "sscope-budget.h"
#include "sscope-model.h"
#include "sscope-noise.h"
#include "sscope-allan.h"
#include "sscope-sim.h"
#include "sscope-tempbias.h"
#include "sscope-inclino.h"
#include "sscope-adc.h"
#include "sscope-nav.h"
#include "sscope-strapdown.h"
#include "sscope-navsim.h"
#include "sscope-zupt.h"
#include "sscope-heading.h"
#include "sscope-walk.h"
#include "sscope-clip.h"
#include "sscope-adequacy.h"
#include "sscope-datasheet.h"
#include "sscope-lot.h"
#include "sscope-export.h"
#include "sscope-plan.h"

#endif /* SENSORSCOPE_H */
