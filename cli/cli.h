/* railride command line: shared helpers. The CLI is a thin layer over the
 * public API: it parses options, calls the library, prints tables or JSON. */
#ifndef RR_CLI_H
#define RR_CLI_H

#include <cjson/cJSON.h>
#include <getopt.h>
#include <stdio.h>
#include "railride/railride.h"
#include "console.h"

/* The operating point commands use when none is given (the paper's). */
#define CLI_SPEED_DEFAULT_KMH 350.0
#define CLI_CONICITY_DEFAULT 0.17

/* What the ride options accept: floor points within 100 m of the car
   centre, floor heights up to 10 m, frequency grids of 1 mHz .. 10 kHz. */
#define CLI_FLOOR_X_MAX 100.0
#define CLI_FLOOR_H_MAX 10.0
#define CLI_BAND_LO_MIN 1e-3
#define CLI_BAND_HI_MAX 1e4
#define CLI_BAND_N_MAX 100000

/* The critical-speed scan's default range, for help texts (stability.h). */
#define CLI_CRITICAL_RANGE RR_STR(RR_CRITICAL_V_MIN_KMH) "-" RR_STR(RR_CRITICAL_V_MAX_KMH) " km/h"
#define CLI_CRITICAL_TOP RR_STR(RR_CRITICAL_V_MAX_KMH) " km/h"

/* The validation runs' default record length, for help texts (timesim.h). */
#define CLI_VALIDATE_DURATION RR_STR(RR_VALIDATE_DURATION_S)

/* Options most commands share. */
typedef struct cli_common {
  const char *vehicle_spec; /* NULL: built-in default */
  rr_vehicle veh;
  double speed_kmh, conicity;
  int have_speed, have_conicity;
  double conicities[64]; /* --conicity L1,L2,... (list commands) */
  int ncon;
  int conicity_list; /* set by commands that take a list */
  int json;
  rr_modal_opts mo;
  int sdf_override;          /* -1: keep the vehicle's */
  int gravity;               /* -1: keep */
  unsigned given;            /* CLI_READS_* of the shared options given */
  int progress;              /* --progress: progress on stderr even when it is not a terminal */
  const char *profiles;      /* --profiles WHEEL[,RAIL] */
  char conicity_source[200]; /* where the conicity came from (outputs say it) */
} cli_common;

/* Long options shared by the stability commands (ids >= 1000). */
enum {
  OPT_SPEED = 1000,
  OPT_CONICITY,
  OPT_JSON,
  OPT_FMAX,
  OPT_WMIN,
  OPT_RMAX,
  OPT_SDF,
  OPT_GRAVITY,
  OPT_HELP,
  OPT_PROGRESS_ALL,
  OPT_PROFILES
};
/* One option of a command, for the parser and the help alike: getopt_long's
   table and the --help lines are both made from these rows, so the two
   cannot disagree. A table ends with a row whose name is NULL. */
typedef struct cli_opt {
  const char *name;  /* long name, without "--" */
  int id;            /* what the command's callback receives */
  const char *value; /* the value's name in --help ("FROM:TO:N"); NULL: a flag */
  const char *help;  /* what --help says of it (wrapped to CLI_HELP_WIDTH) */
} cli_opt;
#define CLI_OPT_END                                                                                \
  {                                                                                                \
    0, 0, 0, 0                                                                                     \
  }
/* The --help row of a command that parses its own options. */
#define CLI_OPT_HELP_ROW                                                                           \
  {                                                                                                \
    "help", 'h', NULL, "this text"                                                                 \
  }
/* The most options a command has (the shared ones included). */
#define CLI_OPTS_MAX 96
/* The help's option column: "  --name VALUE" padded to this width. */
#define CLI_HELP_COLUMN 23
/* The help's lines are wrapped to this width (terminals of 100 columns). */
#define CLI_HELP_WIDTH 99
/* A table's rows as --help prints them. */
void cli_opt_help(FILE *fp, const cli_opt *t);
/* A command's help text with the option rows of t where its CLI_COMMON_HELP
   marker is (after the shared options the command reads, for cli_parse),
   and cmd's --plot options when it draws. */
void cli_help_print(const char *cmd, const char *text, const cli_opt *t);
/* Where a command's help lists its options (the shared ones it reads, then
   its own). */
#define CLI_COMMON_HELP "@COMMON@\n"
/* Which shared options a command reads (the vehicle and --sdf: all); one
   it does not read is an error, and so is any option given twice. */
enum {
  CLI_READS_SPEED = 1,
  CLI_READS_CONICITY = 2,
  CLI_READS_JSON = 4,
  CLI_READS_INDEX = 8,
  CLI_READS_GRAVITY = 16,  /* --gravity-stiffness: the command builds a linear model */
  CLI_READS_PROGRESS = 32, /* --progress: the command reports progress */
  CLI_READS_PROFILES = 64, /* --profiles for the nonlinear model's contact functions */
  CLI_VEHICLE_PAIR = 128   /* no VEHICLE: both built-ins (the help says so) */
};

void cli_common_init(cli_common *c);
/* What every option handler returns (cli_common_option, the commands'
   callbacks and their helpers): the option taken, not one it handles, or a
   positive exit status after its message (cli_bad's EXIT_BADINPUT, say). */
enum cli_opt_result { CLI_OPT_TAKEN = 0, CLI_OPT_NOT_MINE = -1, CLI_OPT_BAD = EXIT_BADINPUT };
/* Handles a shared option (enum cli_opt_result). */
int cli_common_option(cli_common *c, int opt, const char *arg);
/* Loads the vehicle (positional argument) and applies overrides; prints and
 * returns EXIT_BADINPUT on error. */
int cli_load_vehicle(cli_common *c, int argc, char **argv);
/* After the vehicle: the conicity from --profiles or the vehicle's profiles
   when the command reads one and none is given (c->conicity_source says). */
int cli_profile_conicity(cli_common *c, unsigned reads);
/* Builds a model at the common operating point (requires speed/conicity when asked). */
int cli_model(cli_common *c, rr_model **m, int need_speed, int need_conicity);
/* Parses a number option with units into `unit`; prints the error. */
int cli_number(const char *opt, const char *arg, const char *unit, double *out);
/* The same, within [lo, hi] (the message gives the range). */
int cli_number_in(const char *opt, const char *arg, const char *unit, double lo, double hi,
                  double *out);
/* The checks every option meets after getopt_long returned opt (longindex:
   its entry in opts, or -1): its name written in full (getopt_long would take
   "--c" for "--conicity"), and not given before (seen: the ids so far,
   *nseen of them, cap 64). Returns 0, or EXIT_BADINPUT after the message. */
int cli_option_checks(const char *cmd, char **argv, const struct option *opts, int opt,
                      int longindex, int *seen, int *nseen);
/* getopt_long's table of a cli_opt table (the end row included): the count
   of options, or -1 when they pass cap - 1. */
int cli_opt_getopt(const cli_opt *t, struct option *out, int cap);
/* getopt_long with those checks: 1 with the next option's id in *opt, 0
   after the last, -1 after an error's message (a missing value, an unknown,
   abbreviated or repeated option). Start with optind = 1 and a zeroed s. */
typedef struct cli_opt_state {
  int seen[64], nseen;
} cli_opt_state;
int cli_next_option(const char *cmd, int argc, char **argv, const cli_opt *opts, cli_opt_state *s,
                    int *opt);
/* The message for getopt's ':' (missing value) or '?' (unknown option); returns EXIT_BADINPUT. */
int cli_getopt_error(const char *cmd, int opt, const char *word);
/* Work caps: a command refuses a job larger than its limit (--limit N
   raises it); each returns EXIT_BADINPUT after printing, or 0. */
#define CLI_LIMIT_GRID 1e6        /* map and sweep points */
#define CLI_LIMIT_LOCUS 1e5       /* locus points */
#define CLI_LIMIT_DESIGNS 1e8     /* optimise: population x (generations + 1) */
#define CLI_LIMIT_SAMPLES 4194304 /* validate: duration x fs */
int cli_limit(const char *arg, double *limit);
int cli_over_limit(const char *cmd, double work, double limit, const char *unit);
/* --seed: a whole number 0 .. 2^64 - 1 into *seed; EXIT_BADINPUT after the
   message, or 0. */
int cli_seed(const char *arg, unsigned long long *seed);
/* Parses FROM:TO:N. */
int cli_range(const char *opt, const char *arg, const char *unit, double *from, double *to, int *n);
/* Parses a comma list of numbers (max cap). */
int cli_list(const char *opt, const char *arg, const char *unit, double *out, int cap, int *n);
/* Prints JSON to stdout and frees it. */
void cli_json_print(cJSON *root);
cJSON *cli_json_matrix(const double *A, int rows, int cols);
/* One CSV field, quoted (RFC 4180) when it holds a comma, quote or newline,
   then the separator sep. */
void cli_csv_field(FILE *fp, const char *text, char sep);
/* Splits a CSV line in place into at most cap fields (RFC 4180 quotes,
   the line end dropped); returns the count. */
int cli_csv_split(char *line, char **fields, int cap);
/* A vehicle-file key as a CSV column name with its SI unit appended
   (yaw_damper.damping_n_s_per_m); dimensionless keys as they are. */
void cli_csv_key_field(FILE *fp, const char *section_dot_key, char sep);

/* A CSV number, or an empty field where there is none (a NaN marks "no
   such mode"): railride never writes nan or inf. */
void cli_csv_num(FILE *fp, double x, char sep);
/* How many clusters a Pareto set is named in (pareto, and the letters on
   optimise's three-objective picture): the paper's A-D. */
#define CLI_PARETO_CLUSTERS 4
/* What a column of optimise's Pareto CSV holds: a variable (a vehicle-file
   key with its unit, section.key_unit), the feasibility flags (feasible,
   violation), or an objective (anything else: zeta_low, "index@350,0.17"). */
enum cli_pareto_col { CLI_COL_VAR, CLI_COL_OBJ, CLI_COL_FLAG };
enum cli_pareto_col cli_pareto_column(const char *name);
/* A file name option's value: one that reads as an option ("--help") is
   refused with a message (EXIT_BADINPUT), else 0. */
int cli_file_arg(const char *opt, const char *arg);

/* The paper problem's cluster letters (pareto_letters.c): with objectives
   zeta_low, zeta_high, std_zeta and k = 4, relabels the k-means result
   (label[n] over the n rows x, n x m; centre k x m) so that the cluster of
   the study's design A is 0 (A), B's 1, C's 2, D's 3; otherwise, or when two
   designs share a cluster, leaves it as it is. */
void cli_paper_letters(int n, int m, const double *x, const char *const *names, int k, int *label,
                       double *centre);

/* Row-major index i * stride + j of ints, as the size_t an array takes. */
static inline size_t cli_at(int i, int stride, int j)
{
  return (size_t)i * (size_t)stride + (size_t)j;
}

/* The vehicle stability index as text: "-0.118200 (hunting mode: carbody
   lateral-yaw at 1.0500 Hz)", "+0.0064 (unstable mode outside the hunting
   band: ...)", or "none (no hunting-related mode below F Hz; all stable)".
   mode may be NULL (the frequency alone is then named). */
void cli_index_text(char *buf, size_t len, double index, rr_index_source src, const rr_mode *mode,
                    double freq_hz, const rr_modal_opts *o, double fmax_used);
/* The index's band edge rule: "fixed" (--fmax) or "max(10 Hz, f_K)". */
const char *cli_band_rule(const rr_modal_opts *o);
/* fmax_hz (the edge used) and fmax_rule ("fixed" or "kinematic") into obj. */
void cli_band_json(cJSON *obj, const rr_modal_opts *o, double fmax_used);
/* An index or other number as "%.6f", or "none" when undefined (NaN). */
const char *cli_num_or_none(char *buf, size_t len, double x);
/* The index's source for JSON: "hunting", "unstable_outside_hunting", "none". */
const char *cli_index_source_key(rr_index_source s);

/* A mode as JSON (paper: with the SDF root fields). */
cJSON *cli_mode_json(const rr_mode *md, int paper);

/* Long runs: progress with an ETA on stderr when it is a terminal (or when
   forced by --progress), and Ctrl-C/SIGTERM caught so that a loop can stop
   and write what it has. */

/* Subcommands. */
int cmd_summary(int argc, char **argv);
int cmd_matrices(int argc, char **argv);
int cmd_modes(int argc, char **argv);
int cmd_robust(int argc, char **argv);
int cmd_critical(int argc, char **argv);
int cmd_locus(int argc, char **argv);
int cmd_map(int argc, char **argv);
int cmd_damper(int argc, char **argv);

/* Runs getopt_long over argv with the shared options plus `extra` (ended by
 * CLI_OPT_END, ids < 1000 or >= 2000), calling extra_cb for those. Loads the
 * vehicle. Returns 0 to go on, or an exit status (help printed: -1 -> 0). */
typedef int (*cli_extra_cb)(int opt, const char *arg, void *user); /* enum cli_opt_result */
int cli_parse(int argc, char **argv, cli_common *c, unsigned reads, const cli_opt *extra,
              cli_extra_cb cb, void *user, const char *usage_text);
/* The same, with --conicity taking a comma list into c->conicities. */
int cli_parse_list(int argc, char **argv, cli_common *c, unsigned reads, const cli_opt *extra,
                   cli_extra_cb cb, void *user, const char *usage_text);
#define CLI_HELP_SHOWN (-1)

/* Ride evaluation shared by ride, compare and summary. */
typedef struct ride_setup {
  const char *spectrum; /* name or file (default wuhan-guangzhou) */
  double x[16];         /* floor points, m (default +L, 0, -L) */
  int npoints;
  double h_p; /* floor height (default 1.2 m) */
  int roll_gravity;
  double f_lo, f_hi;
  int nfreq;
  enum rr_frf_method method;
  rr_ride_unstable when_unstable; /* --linear-when-unstable: RR_RIDE_LINEAR */
} ride_setup;
typedef rr_ride_point ride_point;
/* The library's ride options for a command's setup. */
rr_ride_opts ride_opts(const ride_setup *r);
void ride_setup_default(ride_setup *r, const rr_vehicle *veh);
void ride_default_points(ride_setup *r, const rr_vehicle *veh);
/* The floor-point options every ride-type command takes. */
enum { OPT_SPECTRUM = 3000, OPT_POINTS, OPT_HEIGHT, OPT_ROLLG, OPT_LINEAR_UNSTABLE };
/* clang-format off */
#define RIDE_HEIGHT_DEFAULT RR_STR(RR_FLOOR_HEIGHT_DEFAULT)
#define RIDE_POINT_OPTIONS \
  {"points", OPT_POINTS, "X1,X2,..", "floor points along the car, m (default +L, 0, -L)"}, \
  {"floor-height", OPT_HEIGHT, "H", "floor height above rail, m (default " RIDE_HEIGHT_DEFAULT ")"}, \
  {"roll-gravity", OPT_ROLLG, NULL, "the accelerometer senses a_y + g phi_c"}
#define RIDE_SETUP_OPTIONS \
  {"spectrum", OPT_SPECTRUM, "S", \
   "lateral alignment spectrum: a name in spectra/, a file (.txt), or a measured " \
   "PSD (.csv, two columns with units in the header, e.g. n_per_m,psd_m2_per_per_m); " \
   "default " RR_RIDE_SPECTRUM_DEFAULT}, \
  {"linear-when-unstable", OPT_LINEAR_UNSTABLE, NULL, \
   "where some mode is unstable, give the linear response's indices (not a ride comfort) " \
   "instead of leaving them undefined"}, \
  RIDE_POINT_OPTIONS
/* clang-format on */
/* Handles one of them (enum cli_opt_result). */
int ride_setup_option(ride_setup *r, int opt, const char *arg);

/* --direction: which model a ride-type command runs. */
enum cli_direction { CLI_DIR_LATERAL = 0, CLI_DIR_VERTICAL = 1, CLI_DIR_BOTH = 2 };
/* Finds --direction in argv before parsing (it decides which shared options
   the command reads): the direction, or -1 after a message. */
int cli_direction_scan(const char *cmd, int argc, char **argv);
/* The same for commands of one model at a time: both is refused. */
int cli_direction_one(const char *cmd, int argc, char **argv);
/* The vertical side of ride, frf and modes (cmd_vertical.c). */
typedef struct vertical_setup {
  int direction;         /* enum cli_direction */
  const char *spectrum;  /* --vertical-spectrum (default tbt3352-vertical) */
  int outside;           /* -1: the file's; 0 extend; 1 zero */
  double window_s;       /* --window (5 s) */
  double ax_p95, ax_p50; /* --ax-p95, --ax-p50: longitudinal Wd 5 s RMS percentiles (0) */
  int ax_pitch;          /* --ax-pitch: those from carbody pitch at floor height hp instead */
  double hp;             /* --hp (1.2 m) */
  int lateral_given;     /* --lateral-wd-p95 (1) or --lateral-wd-rms (2): a_Y given, no PEM */
  double lateral[16];    /* the given values: one for every point, or one each */
  int nlateral;
  int dofs;         /* frf --dofs: every coordinate's FRF too */
  const char *plot; /* --plot FILE.png */
} vertical_setup;
void vertical_setup_default(vertical_setup *v);
/* ride --direction vertical|both (conicity: the lateral side's, both only) */
int ride_vertical(const cli_common *c, const ride_setup *rs, const vertical_setup *vs,
                  double conicity, const char *psd_path);
int frf_vertical(const cli_common *c, const ride_setup *rs, const vertical_setup *vs);
/* One floor point's vertical indices and, with the lateral side, its Wd 5 s
   statistics and EN 12299 indices. */
typedef struct vertical_both {
  ride_point lat; /* the lateral PEM's indices */
  rr_vertical_point z;
  rr_window_stats wd;
  rr_en12299 en;
} vertical_both;
/* The vertical ride at rs's points and, when conicity is not NaN, the
   lateral side too (summary, compare). out: rs->npoints. */
int vertical_eval(const rr_vehicle *veh, double speed_kmh, const ride_setup *rs,
                  const vertical_setup *vs, double conicity, vertical_both *out, rr_error *e);
int modes_vertical(const cli_common *c);
int matrices_vertical(const cli_common *c);
/* validate --direction vertical (cmd_validate_vertical.c) */
int validate_vertical(int argc, char **argv);
/* After parsing: the floor points default to +L, 0, -L of the vehicle loaded
   (the defaults set before parsing were the built-in vehicle's). */
void ride_setup_points(ride_setup *r, const rr_vehicle *veh, int argc, char **argv);
/* Evaluates the ride at one operating point; psd (nfreq x npoints) optional. */
int ride_eval(const rr_vehicle *veh, double speed_kmh, double conicity, const ride_setup *r,
              ride_point *out, double *psd, double *freqs, rr_error *err);
cJSON *ride_methods_json(void);
/* A ride index as text with its digits after the point, "unstable" where
   the operating point is unstable and the index undefined, "none" for
   another NaN. */
const char *ride_num(char *buf, size_t len, int digits, double x, int stable);

int cmd_ride(int argc, char **argv);
int cmd_frf(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_validate(int argc, char **argv);
int cmd_optimise(int argc, char **argv);
int cmd_sweep(int argc, char **argv);
int cmd_keys(int argc, char **argv);
/* cmd_pareto.c */
int cmd_pareto(int argc, char **argv);
int cmd_contact(int argc, char **argv);
int cmd_wear(int argc, char **argv);
int cmd_objectives(int argc, char **argv);
int cmd_simulate(int argc, char **argv);
int cmd_bifurcation(int argc, char **argv);

#endif
