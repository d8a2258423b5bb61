/* `--plot FILE` (plot.c): runs a command with its data captured and draws it
 * with gnuplot. */
#ifndef RR_CLI_PLOT_H
#define RR_CLI_PLOT_H

/* When argv holds --plot FILE: *handled = 1 and the command's exit status
   (the command fn run without it, then the picture drawn); else *handled = 0. */
int cli_plot_run(const char *cmd, int (*fn)(int, char **), int argc, char **argv, int *handled);
#include "cli.h"
/* The options main takes out of a command's arguments before it runs
   (plot_options.c, which depends on nothing: the help reads them too). */
enum { OPT_PLOT = 4000, OPT_PLOT_SCRIPT };
const cli_opt *cli_plot_rows(void);
/* Those rows for cmd's --help, or NULL when cmd draws nothing. */
const cli_opt *cli_plot_options(const char *cmd);

#endif
