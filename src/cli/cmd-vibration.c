/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "cli.h"
int ssc_cmd_vibration(int argc, char **argv)
{
	(void)argc;
	(void)argv;
	return 2;
}
