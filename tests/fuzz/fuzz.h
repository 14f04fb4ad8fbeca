/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Shared helpers of the fuzz harnesses.  Each harness defines the
 * libFuzzer entry point LLVMFuzzerTestOneInput(); built with clang
 * (-fsanitize=fuzzer) it is a libFuzzer binary, otherwise replay.c gives
 * it a main() that runs every file of a corpus through it (make check).
 *
 * The readers take paths, so an input is handed over as a file: an
 * anonymous memory file (memfd) named /proc/self/fd/N, or a pipe on
 * standard input for the streaming path.
 */
#ifndef SSCOPE_FUZZ_H
#define SSCOPE_FUZZ_H

#include "config.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

/* Set by the replay driver: every input takes every path of a harness. */
extern int fuzz_replay;

/* An input as a file: *path receives "/proc/self/fd/N"; returns the fd
 * (close it with fuzz_file_close), or -1. */
int fuzz_file(const void *data, size_t size, char *path, size_t len);
void fuzz_file_close(int fd);

/* Put the input on standard input through a pipe (inputs up to the pipe
 * buffer, 64 KiB; larger ones return -1).  fuzz_stdin_restore() puts the
 * original standard input back. */
int fuzz_stdin(const void *data, size_t size);
void fuzz_stdin_restore(void);

/* Standard output of the code under test goes to /dev/null (its messages
 * on stderr stay: make fuzz runs libFuzzer with -close_fd_mask=3). */
void fuzz_quiet(void);

#endif
