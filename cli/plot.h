/* `--plot FILE` (plot.c): runs a command with its data captured and draws it
 * with gnuplot. */
#ifndef RR_CLI_PLOT_H
#define RR_CLI_PLOT_H

/* When argv holds --plot FILE: *handled = 1 and the command's exit status
   (the command fn run without it, then the picture drawn); else *handled = 0. */
int cli_plot_run(const char *cmd, int (*fn)(int, char **), int argc, char **argv, int *handled);
#include "cli.h"
/* The options main takes for cmd before it runs (--plot, --plot-script),
   for its --help; NULL when cmd draws nothing. */
const cli_opt *cli_plot_options(const char *cmd);

#endif
