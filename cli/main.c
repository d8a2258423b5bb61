/* railride: command-line entry point and subcommand dispatch. */
#include <string.h>
#include "cli.h"
#include "parallel.h"
#include "outfile.h"
#include "plot.h"
#include "railride/version.h"

void openblas_set_num_threads(int);

/* Every command: its name, function, one line for the usage, and whether
   its loops split over MPI ranks (cli_par_for). The one table of commands;
   what each draws with --plot is plot.c's. */
enum { ONE_RANK = 0, DISTRIBUTED = 1 };
static const struct {
  const char *name;
  int (*fn)(int, char **);
  const char *what;
  int distributed;
} cmds[] = {
    {"summary", cmd_summary, "stability summary of a vehicle (the main job)", ONE_RANK},
    {"matrices", cmd_matrices, "M, C, K, B, Maxwell rows and the state matrix A", ONE_RANK},
    {"modes", cmd_modes, "eigenvalues, stability indices, energy shares", ONE_RANK},
    {"robust", cmd_robust, "robust stability indices zeta_low, zeta_high, std(zeta)", ONE_RANK},
    {"critical-speed", cmd_critical, "lowest speed where any oscillatory mode reaches zeta = 0",
     DISTRIBUTED},
    {"locus", cmd_locus, "root locus over speed or conicity (CSV)", DISTRIBUTED},
    {"map", cmd_map, "stability index over a (speed, conicity) grid (CSV)", DISTRIBUTED},
    {"damper", cmd_damper, "Maxwell damper characteristics over frequency (CSV)", ONE_RANK},
    {"ride", cmd_ride, "ride comfort by PEM: acceleration PSD, Sperling, Wd RMS", ONE_RANK},
    {"frf", cmd_frf, "complex FRFs of carbody acceleration per wheelset input (CSV)", ONE_RANK},
    {"validate", cmd_validate, "PEM against FFTs of a time-domain run (RMS, Sperling, band PSDs)",
     ONE_RANK},
    {"optimise", cmd_optimise, "NSGA-II over a problem file (Pareto set and front as CSV)",
     DISTRIBUTED},
    {"optimize", cmd_optimise, "(same as optimise)", DISTRIBUTED},
    {"sweep", cmd_sweep, "any objective over a grid of two vehicle-file keys (CSV)", DISTRIBUTED},
    {"simulate", cmd_simulate, "time histories of the nonlinear vehicle (CSV)", ONE_RANK},
    {"bifurcation", cmd_bifurcation, "hunting limit cycles against speed: Hopf, folds, stability",
     DISTRIBUTED},
    {"compare", cmd_compare,
     "SDF vs constant series stiffness: stability and Sperling over conicity", ONE_RANK},
    {"contact", cmd_contact, "wheel-rail contact geometry and equivalent conicity from profiles",
     ONE_RANK},
    {"wear", cmd_wear, "wheel profiles (wear stages) on their rail: conicity, stability, ride",
     ONE_RANK},
    {"pareto", cmd_pareto, "clusters of an optimise run's Pareto set and their parameters",
     ONE_RANK},
    {"keys", cmd_keys, "the vehicle-file keys: units, physical ranges, meanings", ONE_RANK},
    {"objectives", cmd_objectives, "the objective names of problem files and sweeps", ONE_RANK},
};
#define NCMDS (int)(sizeof cmds / sizeof cmds[0])

static void usage(FILE *fp)
{
  fprintf(fp, "usage: railride COMMAND [VEHICLE] [options]   (railride COMMAND --help; railride "
              "--version)\n\ncommands:\n");
  for (int i = 0; i < NCMDS; i++) fprintf(fp, "  %-15s %s\n", cmds[i].name, cmds[i].what);
}

static int run(int argc, char **argv)
{
  /* Problems here are small (40x40): BLAS threads only cost. */
  openblas_set_num_threads(1);
  if (argc < 2) {
    usage(stderr);
    return EXIT_BADINPUT;
  }
  if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
    usage(stdout);
    return 0;
  }
  if (!strcmp(argv[1], "--version")) {
    printf("railride %s (library %s)\n", RR_VERSION_STRING, rr_version());
    return 0;
  }
  for (int i = 0; i < NCMDS; i++)
    if (!strcmp(argv[1], cmds[i].name)) {
      if (cli_par_size() > 1 && !cmds[i].distributed) { /* one rank is enough */
        if (cli_par_rank() != 0) return 0;
        fprintf(stderr, "railride %s: not distributed over MPI ranks; rank 0 runs it alone\n",
                cmds[i].name);
      }
      int handled, r = cli_plot_run(cmds[i].name, cmds[i].fn, argc - 1, argv + 1, &handled);
      if (handled) return r;
      return cmds[i].fn(argc - 1, argv + 1); /* its --help lists main's --plot too */
    }
  fprintf(stderr, "railride: unknown command '%s' (railride --help lists them)\n", argv[1]);
  return EXIT_BADINPUT;
}

int main(int argc, char **argv)
{
  cli_par_init(&argc, &argv);
  return cli_par_finalize(cli_stdout_close(run(argc, argv)));
}
