/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The commands (src/cli/): each parses its options, calls the library and
 * the workbench, and presents the result.  Files here may include every
 * layer below (src/workbench/workbench.h brings the library); nothing
 * below includes them.
 */
#ifndef SSCOPE_CLI_H
#define SSCOPE_CLI_H

#include "workbench.h"

/* The stage graph of scenes (stages.c): S_COUNT_ entries of scene.h. */
struct ssc_stage_def;
const struct ssc_stage_def *ssc_scene_graph(void);

/* Commands */
int ssc_cmd_info(int argc, char **argv);
int ssc_cmd_run(int argc, char **argv);
int ssc_cmd_report(int argc, char **argv);
int ssc_cmd_psd(int argc, char **argv);
int ssc_cmd_vibration(int argc, char **argv);
int ssc_cmd_acquire(int argc, char **argv);
int ssc_cmd_calib(int argc, char **argv);
int ssc_cmd_budget(int argc, char **argv);
int ssc_cmd_tempbias(int argc, char **argv);
int ssc_cmd_inclino(int argc, char **argv);
int ssc_cmd_model(int argc, char **argv);
int ssc_cmd_allan(int argc, char **argv);
int ssc_cmd_simulate(int argc, char **argv);
int ssc_cmd_adc(int argc, char **argv);
int ssc_cmd_heading(int argc, char **argv);
int ssc_cmd_walk(int argc, char **argv);
int ssc_cmd_navsim(int argc, char **argv);
int ssc_cmd_datasheet(int argc, char **argv);
int ssc_cmd_plan(int argc, char **argv);
int ssc_cmd_audit(int argc, char **argv);
int ssc_cmd_lot(int argc, char **argv);
int ssc_cmd_nav(int argc, char **argv);

#endif
