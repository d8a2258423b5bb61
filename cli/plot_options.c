/* The --plot options' rows and which commands draw: data that the help
 * (common.c) and the plotting (plot.c) both read, so that neither calls
 * the other. */
#include <string.h>
#include "plot.h"

static const cli_opt plot_rows[] = {
    {"plot", OPT_PLOT, "FILE",
     "draw the result with gnuplot into FILE.png, .svg or .pdf (standard output as without it)"},
    {"plot-script", OPT_PLOT_SCRIPT, "S.gp",
     "with --plot: also the gnuplot script and its data (S.csv), to restyle; `gnuplot S.gp` in "
     "S's folder redraws FILE there"},
    CLI_OPT_END};

/* The commands plot.c has a picture for (its kinds table; test_plots draws each). */
static const char *const drawing[] = {"wear",        "contact",  "modes",    "damper",   "locus",
                                      "map",         "sweep",    "ride",     "validate", "compare",
                                      "bifurcation", "optimise", "optimize", "pareto"};

const cli_opt *cli_plot_rows(void) { return plot_rows; }

const cli_opt *cli_plot_options(const char *cmd)
{
  for (size_t i = 0; i < sizeof drawing / sizeof drawing[0]; i++)
    if (!strcmp(drawing[i], cmd)) return plot_rows;
  return NULL;
}
