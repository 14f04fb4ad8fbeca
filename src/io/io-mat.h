/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * MATLAB Level 5 MAT-file decoder used by the capture reader (internal).
 * The decoder reads the caller's buffer in place: it must outlive the
 * decoder object.
 */
#ifndef SSCOPE_IO_MAT_H
#define SSCOPE_IO_MAT_H

#include <stdbool.h>
#include <stddef.h>

struct sscope_diag;
struct ssc_mat;

/* Does the buffer start with a MATLAB 5 MAT-file header? */
bool ssc_mat_detect(const char *buf, size_t len);

/* Decode the variables: real numeric 2-D arrays become channels (see
 * io-mat.c).  Returns 0, -EBADMSG (malformed, truncated or compressed;
 * diag says which), -EDOM (no numeric array), -ENOMEM. */
int ssc_mat_open(struct ssc_mat **m, const unsigned char *buf, size_t len,
		 const char *disp, struct sscope_diag *diag);
size_t ssc_mat_n_channels(const struct ssc_mat *m);
const char *ssc_mat_channel_name(const struct ssc_mat *m, size_t k);
size_t ssc_mat_rows(const struct ssc_mat *m);
/* Value of channel k at row (converted from its storage type). */
double ssc_mat_value(const struct ssc_mat *m, size_t k, size_t row);
void ssc_mat_free(struct ssc_mat *m);

#endif
