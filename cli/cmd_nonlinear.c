/* `railride simulate` and `railride bifurcation`: the nonlinear vehicle
 * (docs/model.md, "Nonlinear model") in the time domain, and its hunting
 * limit cycles against speed. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "cli.h"
#include "outfile.h"
#include "parallel.h"

#define SIM_DISTURBANCE_DEFAULT 5e-3 /* m, on every wheelset, when no track is given */
#define SIM_FS_DEFAULT 256.0         /* Hz: the validation's sample rate, hence its realisations */
#define SIM_DURATION_MAX 1e4         /* s */
#define SCAN_STEP_DEFAULT_KMH 5.0

typedef struct nl_args {
  const char *profile, *spectrum, *track, *method, *plot_data, *columns;
  double duration, fs, disturbance, step_kmh, settle, v_lo, v_hi, limit;
  unsigned long long seed;
  int have_seed, have_disturbance, csv, every, accelerations;
} nl_args;
enum {
  OPT_PROFILE = 5000,
  OPT_NDUR,
  OPT_NFS,
  OPT_DIST,
  OPT_NSPEC,
  OPT_NSEED,
  OPT_TRACK,
  OPT_SPEEDS,
  OPT_METHOD,
  OPT_CSV,
  OPT_STEP,
  OPT_SETTLE,
  OPT_NLIMIT,
  OPT_NPLOTDATA,
  OPT_EVERY,
  OPT_COLUMNS,
  OPT_ACCEL
};

static int speeds_option(nl_args *a, const char *arg)
{
  char buf[256];
  snprintf(buf, sizeof buf, "%s", arg);
  char *colon = strchr(buf, ':');
  if (!colon || strchr(colon + 1, ':'))
    return cli_bad("--speeds: expected FROM:TO (km/h), got '%s'", arg);
  *colon = 0;
  if (cli_number_in("speeds", buf, "km/h", 1, RR_SPEED_MAX_MS * RR_KMH, &a->v_lo) ||
      cli_number_in("speeds", colon + 1, "km/h", 1, RR_SPEED_MAX_MS * RR_KMH, &a->v_hi))
    return 1;
  return a->v_hi > a->v_lo ? 0 : cli_bad("--speeds: FROM must be below TO, got '%s'", arg);
}

static int nl_cb(int opt, const char *arg, void *u)
{
  nl_args *a = u;
  switch (opt) {
  case OPT_PROFILE: a->profile = arg; return 0;
  case OPT_NDUR:
    return cli_number_in("duration", arg, "s", 1e-3, SIM_DURATION_MAX, &a->duration) ? 1 : 0;
  case OPT_NFS: return cli_number_in("fs", arg, "Hz", 1, 1e5, &a->fs) ? 1 : 0;
  case OPT_DIST:
    a->have_disturbance = 1;
    return cli_number_in("disturbance", arg, "m", -0.05, 0.05, &a->disturbance) ? 1 : 0;
  case OPT_NSPEC: a->spectrum = arg; return 0;
  case OPT_NSEED: {
    unsigned long long s;
    if (cli_seed(arg, &s)) return 1;
    a->seed = s;
    a->have_seed = 1;
    return 0;
  }
  case OPT_TRACK: a->track = arg; return 0;
  case OPT_SPEEDS: return speeds_option(a, arg);
  case OPT_METHOD:
    if (strcmp(arg, "continuation") && strcmp(arg, "scan"))
      return cli_bad("--method: 'continuation' or 'scan' expected, got '%s'", arg);
    a->method = arg;
    return 0;
  case OPT_CSV: a->csv = 1; return 0;
  case OPT_STEP: return cli_number_in("step", arg, "km/h", 0.01, 1000, &a->step_kmh) ? 1 : 0;
  case OPT_SETTLE: return cli_number_in("settle", arg, "s", 0.1, 1000, &a->settle) ? 1 : 0;
  case OPT_NLIMIT: return cli_limit(arg, &a->limit) ? 1 : 0;
  case OPT_NPLOTDATA: a->plot_data = arg; return cli_file_arg("plot-data", arg) ? 1 : 0;
  case OPT_EVERY: {
    double n;
    if (cli_number_in("every", arg, "1", 1, INT_MAX, &n)) return 1;
    if (n != floor(n)) return cli_bad("--every: a whole number of samples, got '%s'", arg);
    a->every = (int)n;
    return 0;
  }
  case OPT_COLUMNS: a->columns = arg; return 0;
  case OPT_ACCEL: a->accelerations = 1; return 0;
  }
  return 1;
}

/* The contact geometry: --profile (a tread law lambda(a)), else the
   vehicle's wheel and rail profiles (--profiles or [contact] wheel and
   rail: p->kind RR_PROFILE_NONE, its name "profiles W/R"), else the
   vehicle's lambda(a). */
static int nl_profile(const nl_args *a, const rr_vehicle *veh, rr_profile *p)
{
  rr_error e;
  if (a->profile) {
    int st = rr_profile_open(a->profile, p, &e);
    return st ? cli_bad("--profile: %s", e.msg) : 0;
  }
  if (rr_vehicle_has_profiles(veh)) {
    const char *w = strrchr(veh->wheel_rail.wheel[0], '/'),
               *r = strrchr(veh->wheel_rail.rail[0], '/');
    *p = (rr_profile){.kind = RR_PROFILE_NONE};
    snprintf(p->name, sizeof p->name, "profiles %.25s/%.25s", w ? w + 1 : veh->wheel_rail.wheel[0],
             r ? r + 1 : veh->wheel_rail.rail[0]);
    return 0;
  }
  if (veh->profile.kind == RR_PROFILE_NONE)
    return cli_bad("no tread profile: give --profile new|worn|FILE.csv, --profiles WHEEL[,RAIL], "
                   "or [contact] wheel and rail, or conicity_poly / conicity_table");
  *p = veh->profile;
  return 0;
}

/* What the library takes: the tread law, or NULL for the profiles. */
static const rr_profile *nl_lib(const rr_profile *p)
{
  return p->kind == RR_PROFILE_NONE ? NULL : p;
}

/* One line on the contact geometry in use. */
static void nl_describe(const rr_profile *p, char *d, size_t n)
{
  if (nl_lib(p))
    rr_profile_describe(p, d, (int)n);
  else
    snprintf(d, n,
             "%s: contact functions dr(y) and contact angles (normal forces, flange from the "
             "geometry)",
             p->name);
}

/* The model's assumptions, echoed in every output. */
static cJSON *assumptions_json(const rr_vehicle *veh, const rr_profile *p)
{
  char d[512];
  nl_describe(p, d, sizeof d);
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "conicity", d);
  cJSON_AddNumberToObject(o, "friction", veh->friction);
  if (nl_lib(p)) {
    cJSON_AddNumberToObject(o, "flange_clearance_m", veh->flange_clearance);
    cJSON_AddNumberToObject(o, "flange_stiffness_n_per_m", veh->flange_stiffness);
  }
  cJSON_AddStringToObject(o, "creep_saturation",
                          "Shen-Hedrick-Elkins, per wheel, static wheel load");
  cJSON_AddStringToObject(o, "suspension",
                          "linear, as the linear model (Maxwell dampers included)");
  return o;
}

/* The assumptions beside a CSV: on stderr, so that the CSV itself reads
   with a plain CSV reader. */
static void assumptions_note(const char *cmd, const rr_vehicle *veh, const rr_profile *p)
{
  if (cli_par_rank() != 0) return; /* once per job */
  char d[512], fl[96] = "";
  nl_describe(p, d, sizeof d);
  if (nl_lib(p))
    snprintf(fl, sizeof fl, "; flange clearance %g mm, stiffness %g kN/mm",
             veh->flange_clearance * 1e3, veh->flange_stiffness * 1e-6);
  fprintf(stderr,
          "railride %s: nonlinear model: %s; friction %g%s; Shen-Hedrick-Elkins creep saturation; "
          "linear suspension\n",
          cmd, d, veh->friction, fl);
}

/* ---- simulate ---- */

/* The track inputs: a realisation, a record, or none (NULL). */
static int sim_track(const nl_args *a, const rr_vehicle *veh, double v, int ns, double **u,
                     double **du)
{
  *u = *du = NULL;
  if (!a->spectrum && !a->track) return 0;
  rr_error e;
  rr_model *m;
  int st = rr_model_from_vehicle(veh, &m, &e);
  if (st) return cli_fail(&e, st);
  int ni = rr_model_ninputs(m);
  double x[64];
  for (int i = 0; i < ni; i++) x[i] = rr_model_input_x(m, i);
  rr_model_free(m);
  *u = malloc(sizeof(double) * (size_t)ni * (size_t)ns);
  *du = malloc(sizeof(double) * (size_t)ni * (size_t)ns);
  if (!*u || !*du) return cli_bad("out of memory");
  if (a->track) {
    rr_track_record r;
    if ((st = rr_track_record_load(a->track, &r, &e))) return cli_bad("--track: %s", e.msg);
    st = rr_track_record_sample(&r, v, x, ni, a->fs, ns, *u, *du, &e);
    rr_track_record_free(&r);
    return st ? cli_bad("--track: %s", e.msg) : 0;
  }
  rr_spectrum sp;
  if ((st = rr_spectrum_open(a->spectrum, &sp, &e))) return cli_fail(&e, st);
  rr_validate_opts vo = rr_validate_opts_default();
  rr_track_realisation tr = {.speed_ms = v,
                             .x_inputs = x,
                             .ninputs = ni,
                             .fs_hz = a->fs,
                             .nsamples = ns,
                             .f_lo_hz = vo.f_lo_hz,
                             .f_hi_hz = vo.f_hi_hz,
                             .amplitudes = RR_TRACK_FIXED,
                             .seed = a->have_seed ? a->seed : vo.seed};
  if (!(st = rr_spectrum_require(&sp, "lateral", "--spectrum: the lateral track input", &e)))
    st = rr_track_realise(&sp, &tr, *u, *du, &e);
  rr_spectrum_close(&sp);
  return st ? cli_fail(&e, st) : 0;
}

/* The output's columns: time, every DOF, with --accelerations each DOF's
   second derivative, and per wheelset the track alignment, saturated creep
   force and yaw moment and the flange force; --columns picks some of them. */
enum sim_col_kind { COL_T, COL_Q, COL_ACC, COL_YT, COL_FY, COL_MZ, COL_FL };
typedef struct sim_col {
  enum sim_col_kind kind;
  int i; /* the DOF or the wheelset */
  char name[48];
} sim_col;
#define SIM_MAX_DOF 64 /* the model's limits (system.h's): a bigger one is refused */
#define SIM_MAX_INPUTS 16
#define SIM_COLS_MAX (1 + 2 * SIM_MAX_DOF + 4 * SIM_MAX_INPUTS)

static int sim_columns_all(const rr_model *m, int nw, int accel, sim_col *c)
{
  int k = 0, n = rr_model_ndof(m);
  c[k++] = (sim_col){.kind = COL_T, .name = "t_s"};
  for (int i = 0; i < n; i++) {
    const char *nm = rr_model_dof_name(m, i);
    c[k] = (sim_col){.kind = COL_Q, .i = i};
    snprintf(c[k++].name, sizeof c->name, "%s_%s", nm, nm[0] == 'y' ? "m" : "rad");
  }
  for (int i = 0; i < n && accel; i++) {
    const char *nm = rr_model_dof_name(m, i);
    c[k] = (sim_col){.kind = COL_ACC, .i = i};
    snprintf(c[k++].name, sizeof c->name, "%s_acc_%s", nm, nm[0] == 'y' ? "m_s2" : "rad_s2");
  }
  static const char *const quantity[4] = {"yt", "Fy", "Mz", "flange"}, *const unit[4] = {"m", "N",
                                                                                         "Nm", "N"};
  for (int w = 0; w < nw; w++)
    for (int f = 0; f < 4; f++) {
      c[k] = (sim_col){.kind = COL_YT + f, .i = w};
      snprintf(c[k++].name, sizeof c->name, "%s_w%d_%s", quantity[f], w + 1, unit[f]);
    }
  return k;
}

/* --columns A,B,..: t_s first, then the named ones in the order given. */
static int sim_columns_pick(const char *list, const sim_col *all, int nall, sim_col *out)
{
  char buf[4096];
  if (snprintf(buf, sizeof buf, "%s", list) >= (int)sizeof buf)
    return -cli_bad("--columns: the list is too long");
  int k = 0;
  out[k++] = all[0];
  for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    int j = 0;
    while (j < nall && strcmp(all[j].name, tok)) j++;
    if (j == nall)
      return -cli_bad("--columns: no column '%s' (the header's names: %s, %s, ..., %s)", tok,
                      all[0].name, all[1].name, all[nall - 1].name);
    if (j > 0 && k < SIM_COLS_MAX) out[k++] = all[j];
  }
  return k;
}

typedef struct sim_out {
  const sim_col *cols;
  int ncols, every;
  double fs;
  const double *u; /* ninputs x ns, or NULL */
  int ns;
} sim_out;

static void sim_write(FILE *fp, const rr_nonlinear *nl, const double *Z, int ndone,
                      const sim_out *o, double *dz)
{
  int N = rr_nonlinear_size(nl), n = rr_nonlinear_ndof(nl), nw = rr_nonlinear_ninputs(nl);
  for (int j = 0; j < o->ncols; j++) fprintf(fp, j ? ",%s" : "%s", o->cols[j].name);
  fputc('\n', fp);
  for (int k = 0; k < ndone; k += o->every) {
    const double *z = Z + (size_t)k * (size_t)N;
    double yt[SIM_MAX_INPUTS], frc[SIM_MAX_INPUTS][3];
    for (int w = 0; w < nw; w++) {
      yt[w] = o->u ? o->u[(size_t)w * (size_t)o->ns + (size_t)k] : 0;
      rr_nonlinear_forces(nl, z, yt, w, &frc[w][0], &frc[w][1], &frc[w][2]);
    }
    rr_nonlinear_rhs(nl, z, yt, dz);
    for (int j = 0; j < o->ncols; j++) {
      const sim_col *c = &o->cols[j];
      double x = c->kind == COL_T     ? k / o->fs
                 : c->kind == COL_Q   ? z[c->i]
                 : c->kind == COL_ACC ? dz[n + c->i]
                 : c->kind == COL_YT  ? yt[c->i]
                                      : frc[c->i][c->kind - COL_FY];
      fprintf(fp, j ? ",%.10g" : "%.10g", x);
    }
    fputc('\n', fp);
  }
}

/* The run, with progress and Ctrl-C: a stopped run writes the samples it
   finished (exit 130). */
static int sim_integrate(const nl_args *a, const cli_common *c, rr_nonlinear *nl, const double *u,
                         const double *du, int ns, double *Z, int *ndone)
{
  int N = rr_nonlinear_size(nl);
  double *z0 = calloc((size_t)N, sizeof(double));
  if (!z0) return cli_bad("out of memory");
  double y0 = a->have_disturbance ? a->disturbance : u ? 0 : SIM_DISTURBANCE_DEFAULT;
  for (int w = 0; w < rr_nonlinear_ninputs(nl); w++) z0[rr_nonlinear_index_y(nl, w)] = y0;
  rr_sim_opts so = rr_sim_opts_default();
  so.duration_s = a->duration;
  so.fs_hz = a->fs;
  so.yt = u;
  so.dyt = du;
  so.nsamples_track = u ? ns : 0;
  cli_progress pr;
  cli_progress_start(&pr, "simulate", ns, c->progress);
  so.progress = cli_progress_hook(&pr);
  cli_catch_stops();
  rr_error e;
  int st = rr_simulate(nl, z0, &so, Z, ns, &e);
  cli_progress_end(&pr);
  free(z0);
  *ndone = st == RR_ESTOPPED ? (int)pr.done : ns;
  if (st == RR_ESTOPPED) {
    fprintf(stderr,
            "railride simulate: stopped by a signal: %d of %d samples (%g of %g s) written\n",
            *ndone, ns, (*ndone - 1) / a->fs, a->duration);
    return CLI_EXIT_STOPPED;
  }
  return st ? cli_fail(&e, st) : 0;
}

static int sim_run(const nl_args *a, const cli_common *c, const rr_profile *p)
{
  double v = c->speed_kmh / RR_KMH;
  int ns = (int)floor(a->duration * a->fs + 1e-9) + 1, ndone = 0;
  double *u, *du, *Z = NULL, *dz = NULL;
  sim_col *all = malloc(sizeof *all * SIM_COLS_MAX), *cols = malloc(sizeof *cols * SIM_COLS_MAX);
  int r = sim_track(a, &c->veh, v, ns, &u, &du), ncols = 0;
  rr_nonlinear *nl = NULL;
  rr_model *m = NULL;
  rr_error e;
  int st = 0;
  if (!r && (!all || !cols)) r = cli_bad("out of memory");
  if (!r && (st = rr_nonlinear_from_vehicle(&c->veh, nl_lib(p), NULL, v, &nl, &e)))
    r = cli_fail(&e, st);
  if (!r && (st = rr_model_from_vehicle(&c->veh, &m, &e))) r = cli_fail(&e, st);
  if (!r && (rr_model_ndof(m) > SIM_MAX_DOF || rr_nonlinear_ninputs(nl) > SIM_MAX_INPUTS))
    r = cli_bad("simulate: at most %d DOF and %d wheelsets", SIM_MAX_DOF, SIM_MAX_INPUTS);
  if (!r) {
    int nall = sim_columns_all(m, rr_nonlinear_ninputs(nl), a->accelerations || a->columns, all);
    ncols = a->columns ? sim_columns_pick(a->columns, all, nall, cols) : nall;
    if (ncols < 0)
      r = -ncols;
    else if (!a->columns)
      memcpy(cols, all, sizeof *cols * (size_t)nall);
  }
  if (!r) {
    Z = malloc(sizeof(double) * (size_t)rr_nonlinear_size(nl) * (size_t)ns);
    dz = malloc(sizeof(double) * (size_t)rr_nonlinear_size(nl));
    if (!Z || !dz) r = cli_bad("out of memory");
  }
  if (!r) r = sim_integrate(a, c, nl, u, du, ns, Z, &ndone);
  if (!r || r == CLI_EXIT_STOPPED) {
    assumptions_note("simulate", &c->veh, p);
    fprintf(stderr,
            "railride simulate: speed %g km/h; SUNDIALS CVODE BDF, relative tolerance %g, absolute "
            "%g m\n",
            c->speed_kmh, rr_sim_opts_default().rtol, rr_sim_opts_default().atol_m);
    sim_out o = {.cols = cols, .ncols = ncols, .every = a->every, .fs = a->fs, .u = u, .ns = ns};
    sim_write(stdout, nl, Z, ndone, &o, dz);
  }
  free(u);
  free(du);
  free(Z);
  free(dz);
  free(all);
  free(cols);
  rr_nonlinear_free(nl);
  rr_model_free(m);
  return r;
}

/* The tread option of simulate and bifurcation. */
#define NL_PROFILE_OPT                                                                             \
  {                                                                                                \
    "profile", OPT_PROFILE, "P",                                                                   \
        "tread: new, worn, or a CSV a_mm,conicity (default: the vehicle's)"                        \
  }

int cmd_simulate(int argc, char **argv)
{
  static const char help[] =
      "usage: railride simulate [VEHICLE] --speed KMH [--profile new|worn|FILE.csv] [--duration "
      "S]\n"
      "                         [--disturbance Y0] [--spectrum S [--seed N] | --track FILE.csv] "
      "[--fs HZ]\n"
      "Time histories of the nonlinear vehicle (conicity lambda(a), creep saturation, flange\n"
      "spring; docs/model.md, \"Nonlinear model\") by SUNDIALS CVODE: from a lateral disturbance\n"
      "of every wheelset, a random track realisation of a spectrum (the same realisations as\n"
      "`validate` for the same --duration, --fs and --seed), or a measured alignment record\n"
      "(CSV distance_m, alignment_m, resampled at the speed). CSV on standard output (the model's\n"
      "assumptions on stderr): t_s, every DOF (m or rad), per wheelset the track\n"
      "alignment, saturated creep force Fy and yaw moment Mz, and the flange "
      "force.\n" CLI_COMMON_HELP
      "Ctrl-C (or SIGTERM) stops the run and writes the samples done (exit 130).\n";
  static const cli_opt extra[] = {
      NL_PROFILE_OPT,
      {"duration", OPT_NDUR, "S", "simulated time, s (default 10)"},
      {"disturbance", OPT_DIST, "Y0",
       "initial lateral displacement of every wheelset (default 5 mm without a track)"},
      {"spectrum", OPT_NSPEC, "S", "track irregularity spectrum (name or file)"},
      {"seed", OPT_NSEED, "N", "realisation seed (default 1)"},
      {"track", OPT_TRACK, "FILE.csv", "measured alignment record: distance_m, alignment_m"},
      {"fs", OPT_NFS, "HZ", "output (and track) samples per second (default 256)"},
      {"limit", OPT_NLIMIT, "N",
       "most output samples (duration x fs) accepted (default " RR_STR(CLI_LIMIT_SAMPLES) ")"},
      {"every", OPT_EVERY, "N", "write every N-th sample (default 1: all)"},
      {"accelerations", OPT_ACCEL, NULL, "also each DOF's acceleration (NAME_acc_m_s2 or _rad_s2)"},
      {"columns", OPT_COLUMNS, "A,B,..",
       "only these columns of the header (t_s always first), e.g. y_w1_m,y_c_acc_m_s2,Fy_w1_N"},
      CLI_OPT_END};
  cli_common c;
  nl_args a = {.duration = 10, .fs = SIM_FS_DEFAULT, .limit = CLI_LIMIT_SAMPLES, .every = 1};
  int r = cli_parse(argc, argv, &c, CLI_READS_SPEED | CLI_READS_PROFILES | CLI_READS_PROGRESS,
                    extra, nl_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (!c.have_speed) return cli_bad("simulate: --speed is required");
  if (a.spectrum && a.track) return cli_bad("simulate: give --spectrum or --track, not both");
  if (a.have_seed && !a.spectrum) return cli_bad("--seed: only with --spectrum");
  if (cli_over_limit("simulate", a.duration * a.fs, a.limit, "samples")) return EXIT_BADINPUT;
  rr_profile p;
  if ((r = nl_profile(&a, &c.veh, &p))) return r;
  return sim_run(&a, &c, &p);
}

/* ---- bifurcation ---- */

static const char *type_name(int t)
{
  return t == RR_BIF_SUPERCRITICAL ? "supercritical"
         : t == RR_BIF_SUBCRITICAL ? "subcritical"
                                   : "none";
}

static const char *end_name(int e)
{
  static const char *names[] = {
      "left the speed range",
      "beyond the amplitude limit",
      "point limit reached",
      "continuation stalled (a grazing corner or a secondary bifurcation)",
      "linear model: no limit cycles",
      "stopped by a signal"};
  return e >= 0 && e <= RR_BRANCH_STOPPED ? names[e] : "?";
}

static const char *event_name(rr_bif_event_kind k)
{
  static const char *names[] = {"fold", "symmetry-breaking", "period-doubling", "torus"};
  return k >= RR_EVENT_FOLD && k <= RR_EVENT_TORUS ? names[k] : "?";
}

static cJSON *num_or_null(double x)
{
  return isfinite(x) ? cJSON_CreateNumber(x) : cJSON_CreateNull();
}

static cJSON *bif_head(const cli_common *c, const rr_profile *p, const nl_args *a)
{
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "vehicle", c->veh.name);
  cJSON_AddStringToObject(o, "profile", p->name);
  cJSON_AddItemToObject(o, "assumptions", assumptions_json(&c->veh, p));
  cJSON_AddStringToObject(o, "method", a->method);
  cJSON *r = cJSON_AddArrayToObject(o, "speeds_kmh");
  cJSON_AddItemToArray(r, cJSON_CreateNumber(a->v_lo));
  cJSON_AddItemToArray(r, cJSON_CreateNumber(a->v_hi));
  return o;
}

/* The stability changes along the branch, a line each after lead. */
static void bif_events_print(FILE *f, const char *lead, const rr_bifurcation *b,
                             const rr_cycle *pts)
{
  for (int i = 0; i < b->nevents; i++) {
    const rr_bif_event *e = &b->events[i];
    int g = e->gained;
    (void)pts;
    fprintf(f, "%s%s between %.3f and %.3f km/h (%+d unstable direction%s)%s\n", lead,
            event_name(e->kind), e->speed_lo_ms * RR_KMH, e->speed_hi_ms * RR_KMH, g,
            abs(g) == 1 ? "" : "s",
            e->kind == RR_EVENT_SYMMETRY_BREAKING ? ": asymmetric cycles branch off (not followed)"
                                                  : "");
  }
}

/* The branch as CSV (--csv, --plot-data). */
static void bif_csv_cont(FILE *fp, const rr_bifurcation *b, const rr_cycle *pts)
{
  fprintf(fp, "speed_kmh,amplitude_m,frequency_hz,stable,max_floquet_modulus,symmetric,residual\n");
  for (int i = 0; i < b->npoints; i++)
    fprintf(fp, "%.10g,%.10g,%.10g,%d,%.10g,%d,%.3g\n", pts[i].speed_ms * RR_KMH,
            pts[i].amplitude_m, 1 / pts[i].period_s, pts[i].stable, pts[i].floquet_max,
            pts[i].symmetric, pts[i].residual);
}

static void bif_print_cont(const cli_common *c, const rr_profile *p, const nl_args *a,
                           const rr_bifurcation *b, const rr_cycle *pts, double secs)
{
  if (a->csv) {
    assumptions_note("bifurcation", &c->veh, p);
    bif_events_print(stderr, "railride bifurcation: ", b, pts);
    bif_csv_cont(stdout, b, pts);
    return;
  }
  if (c->json) {
    cJSON *o = bif_head(c, p, a);
    cJSON_AddItemToObject(o, "linear_critical_speed_kmh", num_or_null(b->hopf_speed_ms * RR_KMH));
    cJSON_AddItemToObject(o, "hopf_frequency_hz", num_or_null(b->hopf_freq_hz));
    cJSON_AddItemToObject(o, "hopf_speed_from_branch_kmh",
                          num_or_null(b->hopf_speed_branch_ms * RR_KMH));
    cJSON_AddItemToObject(o, "nonlinear_critical_speed_kmh",
                          num_or_null(b->nonlinear_critical_ms * RR_KMH));
    cJSON_AddStringToObject(o, "type", type_name(b->type));
    cJSON_AddStringToObject(o, "branch_end", end_name(b->end));
    cJSON *arr = cJSON_AddArrayToObject(o, "branch");
    for (int i = 0; i < b->npoints; i++) {
      cJSON *q = cJSON_CreateObject();
      cJSON_AddNumberToObject(q, "speed_kmh", pts[i].speed_ms * RR_KMH);
      cJSON_AddNumberToObject(q, "amplitude_m", pts[i].amplitude_m);
      cJSON_AddNumberToObject(q, "frequency_hz", 1 / pts[i].period_s);
      cJSON_AddBoolToObject(q, "stable", pts[i].stable);
      cJSON_AddNumberToObject(q, "max_floquet_modulus", pts[i].floquet_max);
      cJSON_AddBoolToObject(q, "symmetric", pts[i].symmetric);
      cJSON_AddNumberToObject(q, "residual", pts[i].residual);
      cJSON_AddItemToArray(arr, q);
    }
    cJSON *ev = cJSON_AddArrayToObject(o, "events");
    for (int i = 0; i < b->nevents; i++) {
      const rr_bif_event *e = &b->events[i];
      cJSON *q = cJSON_CreateObject();
      cJSON_AddStringToObject(q, "kind", event_name(e->kind));
      cJSON_AddNumberToObject(q, "speed_kmh", e->speed_ms * RR_KMH);
      cJSON *br = cJSON_AddArrayToObject(q, "bracket_kmh");
      cJSON_AddItemToArray(br, cJSON_CreateNumber(e->speed_lo_ms * RR_KMH));
      cJSON_AddItemToArray(br, cJSON_CreateNumber(e->speed_hi_ms * RR_KMH));
      cJSON *bt = cJSON_AddArrayToObject(q, "between_points");
      cJSON_AddItemToArray(bt, cJSON_CreateNumber(e->index - 1));
      cJSON_AddItemToArray(bt, cJSON_CreateNumber(e->index));
      cJSON_AddNumberToObject(q, "unstable_directions_gained", e->gained);
      cJSON_AddItemToArray(ev, q);
    }
    cJSON_AddNumberToObject(o, "seconds", secs);
    cli_json_print(o);
    return;
  }
  char d[512];
  nl_describe(p, d, sizeof d);
  printf("%s, tread %s: %s\n", c->veh.name, p->name, d);
  printf("friction %g, flange clearance %g mm, flange stiffness %g kN/mm\n", c->veh.friction,
         c->veh.flange_clearance * 1e3, c->veh.flange_stiffness * 1e-6);
  if (!b->hopf) {
    printf("the straight-track equilibrium is stable to %g km/h: no Hopf point\n",
           RR_SPEED_MAX_MS * RR_KMH);
    return;
  }
  printf("linear critical speed (Hopf)  %9.3f km/h  (%.3f Hz; from the branch %.3f)\n",
         b->hopf_speed_ms * RR_KMH, b->hopf_freq_hz, b->hopf_speed_branch_ms * RR_KMH);
  printf("nonlinear critical speed      %9.3f km/h\n", b->nonlinear_critical_ms * RR_KMH);
  printf("bifurcation                   %s; %d %scycles, branch end: %s (%.2f s)\n",
         type_name(b->type), b->npoints, b->npoints && pts[0].symmetric ? "symmetric " : "",
         end_name(b->end), secs);
  if (b->nevents) printf("stability changes:\n");
  bif_events_print(stdout, "  ", b, pts);
  printf("%12s %12s %10s %8s %10s\n", "speed_kmh", "amplitude_mm", "freq_hz", "stable", "max|mu|");
  for (int i = 0; i < b->npoints; i++)
    printf("%12.3f %12.4f %10.4f %8s %10.5f\n", pts[i].speed_ms * RR_KMH, pts[i].amplitude_m * 1e3,
           1 / pts[i].period_s, pts[i].stable ? "yes" : "no", pts[i].floquet_max);
}

/* The scan as CSV (--csv, --plot-data). */
static void bif_csv_scan(FILE *fp, const rr_scan_point *up, const rr_scan_point *down, int nv)
{
  fprintf(fp, "sweep,speed_kmh,amplitude_m,frequency_hz\n");
  for (int s = 0; s < 2; s++)
    for (int i = 0; i < nv; i++) {
      const rr_scan_point *q = s ? &down[nv - 1 - i] : &up[i];
      fprintf(fp, "%s,%.10g,", s ? "down" : "up", q->speed_ms * RR_KMH);
      cli_csv_num(fp, q->amplitude_m, ','); /* empty: not run (a stopped scan) */
      cli_csv_num(fp, q->frequency_hz, '\n');
    }
}

/* --plot-data: the CSV of the continuation (up NULL) or of the scan to its file. */
static int bif_plot_data(const nl_args *a, const rr_bifurcation *b, const rr_cycle *pts,
                         const rr_scan_point *up, const rr_scan_point *down, int nv)
{
  if (!a->plot_data) return 0;
  cli_outfile o;
  int r = cli_out_open(&o, a->plot_data, "--plot-data");
  if (r) return r;
  if (up)
    bif_csv_scan(o.fp, up, down, nv);
  else
    bif_csv_cont(o.fp, b, pts);
  return cli_out_commit(&o);
}

static int bif_continue(const cli_common *c, const rr_profile *p, const nl_args *a)
{
  rr_orbit_opts o = rr_orbit_opts_default();
  o.v_min_ms = a->v_lo / RR_KMH;
  o.v_max_ms = a->v_hi / RR_KMH;
  if (cli_par_size() > 1) /* the monodromy matrix's column groups over the ranks */
    o.runner = (rr_runner_opts){.fn = cli_par_runner};
  rr_cycle *pts = malloc(sizeof *pts * (size_t)o.max_points);
  if (!pts) return cli_bad("out of memory");
  rr_bifurcation b;
  rr_error e;
  double t0 = cli_now_s();
  cli_progress pr;
  cli_progress_start(&pr, "bifurcation", o.max_points, c->progress);
  o.progress = cli_progress_hook(&pr);
  cli_catch_stops();
  int st = rr_bifurcation_continue(&c->veh, nl_lib(p), NULL, &o, pts, NULL, o.max_points, &b, &e);
  cli_progress_end(&pr);
  if (st) {
    free(pts);
    return cli_par_rank() == 0 ? cli_fail(&e, st) : st; /* every rank failed alike: one message */
  }
  int r = bif_plot_data(a, &b, pts, NULL, NULL, 0);
  if (!r) bif_print_cont(c, p, a, &b, pts, cli_now_s() - t0);
  free(pts);
  if (!r && b.end == RR_BRANCH_STOPPED) {
    fprintf(stderr,
            "railride bifurcation: stopped by a signal: the %d branch points found written "
            "(folds not refined)\n",
            b.npoints);
    return CLI_EXIT_STOPPED;
  }
  return r;
}

/* The scan's reading, as the paper reads its figure: the linear critical
   speed where the up-sweep's amplitude leaves zero, the nonlinear one the
   lowest speed with a cycle on either sweep. */
static void scan_read(const rr_scan_point *up, const rr_scan_point *down, int nv, double *v_lin,
                      double *v_nl)
{
  *v_lin = *v_nl = NAN;
  for (int i = 0; i < nv && !isfinite(*v_lin); i++)
    if (up[i].amplitude_m > 0) *v_lin = up[i].speed_ms;
  for (int i = 0; i < nv && !isfinite(*v_nl); i++)
    if (up[i].amplitude_m > 0 || down[i].amplitude_m > 0) *v_nl = up[i].speed_ms;
}

static void scan_points_json(cJSON *arr, const rr_scan_point *s, int nv, const char *sweep)
{
  for (int i = 0; i < nv; i++) {
    cJSON *q = cJSON_CreateObject();
    cJSON_AddStringToObject(q, "sweep", sweep);
    cJSON_AddNumberToObject(q, "speed_kmh", s[i].speed_ms * RR_KMH);
    int run = !isnan(s[i].amplitude_m); /* a stopped scan leaves the rest not run: null */
    cJSON_AddItemToObject(q, "amplitude_m", num_or_null(s[i].amplitude_m));
    cJSON_AddItemToObject(q, "frequency_hz", num_or_null(s[i].frequency_hz));
    cJSON_AddItemToObject(q, "stable",
                          run ? cJSON_CreateBool(s[i].amplitude_m > 0) : cJSON_CreateNull());
    cJSON_AddNullToObject(q, "max_floquet_modulus");
    cJSON_AddItemToArray(arr, q);
  }
}

static void bif_print_scan(const cli_common *c, const rr_profile *p, const nl_args *a,
                           const rr_scan_point *up, const rr_scan_point *down, int nv, double secs)
{
  double v_lin, v_nl;
  scan_read(up, down, nv, &v_lin, &v_nl);
  const char *type = !isfinite(v_lin) ? "none" : v_nl < v_lin ? "subcritical" : "supercritical";
  if (a->csv) {
    assumptions_note("bifurcation", &c->veh, p);
    bif_csv_scan(stdout, up, down, nv);
    return;
  }
  if (c->json) {
    cJSON *o = bif_head(c, p, a);
    cJSON_AddItemToObject(o, "linear_critical_speed_kmh", num_or_null(v_lin * RR_KMH));
    cJSON_AddItemToObject(o, "nonlinear_critical_speed_kmh", num_or_null(v_nl * RR_KMH));
    cJSON_AddStringToObject(o, "type", type);
    cJSON_AddNumberToObject(o, "step_kmh", a->step_kmh);
    cJSON_AddNumberToObject(o, "settle_s", a->settle);
    cJSON *arr = cJSON_AddArrayToObject(o, "branch");
    scan_points_json(arr, up, nv, "up");
    scan_points_json(arr, down, nv, "down");
    cJSON_AddNumberToObject(o, "seconds", secs);
    cli_json_print(o);
    return;
  }
  printf("%s, tread %s (scan, %g km/h steps, %g s to settle, %.2f s)\n", c->veh.name, p->name,
         a->step_kmh, a->settle, secs);
  printf("linear critical speed     %9.1f km/h (amplitude leaves zero on the way up)\n",
         v_lin * RR_KMH);
  printf("nonlinear critical speed  %9.1f km/h (lowest speed with a cycle)\n", v_nl * RR_KMH);
  printf("bifurcation               %s\n%12s %14s %14s\n", type, "speed_kmh", "up_amp_mm",
         "down_amp_mm");
  for (int i = 0; i < nv; i++)
    printf("%12.2f %14.4f %14.4f\n", up[i].speed_ms * RR_KMH, up[i].amplitude_m * 1e3,
           down[i].amplitude_m * 1e3);
}

static int bif_scan(const cli_common *c, const rr_profile *p, const nl_args *a)
{
  int nv = (int)floor((a->v_hi - a->v_lo) / a->step_kmh + 1e-9) + 1;
  double work = 2.0 * nv * (a->settle + 2);
  if (cli_over_limit("bifurcation --method scan", work, a->limit, "simulated seconds"))
    return EXIT_BADINPUT;
  double *vs = malloc(sizeof(double) * (size_t)nv);
  rr_scan_point *up = malloc(sizeof *up * (size_t)nv), *down = malloc(sizeof *down * (size_t)nv);
  if (!vs || !up || !down) {
    free(vs);
    free(up);
    free(down);
    return cli_bad("out of memory");
  }
  for (int i = 0; i < nv; i++) vs[i] = (a->v_lo + i * a->step_kmh) / RR_KMH;
  rr_scan_opts so = rr_scan_opts_default();
  so.settle_s = a->settle;
  rr_error e;
  double t0 = cli_now_s();
  cli_progress pr;
  cli_progress_start(&pr, "bifurcation --method scan", 2L * nv, c->progress);
  so.progress = cli_progress_hook(&pr);
  cli_catch_stops();
  int st = rr_bifurcation_scan(&c->veh, nl_lib(p), NULL, vs, nv, &so, up, down, &e);
  cli_progress_end(&pr);
  int stopped = st == RR_ESTOPPED; /* the runs done are written; the rest are empty */
  int r = st && !stopped ? cli_fail(&e, st) : bif_plot_data(a, NULL, NULL, up, down, nv);
  if (!r) bif_print_scan(c, p, a, up, down, nv, cli_now_s() - t0);
  if (!r && stopped) {
    fprintf(stderr, "railride bifurcation: stopped by a signal: %ld of %ld runs written\n", pr.done,
            2L * nv);
    r = CLI_EXIT_STOPPED;
  }
  free(vs);
  free(up);
  free(down);
  return r;
}

/* rr_orbit_opts_default's speed range, as --speeds writes it */
#define NL_SCAN_LIMIT_S 1e5 /* scan: most simulated seconds, by default */
#define NL_SPEEDS_DEFAULT RR_STR(RR_ORBIT_V_MIN_KMH) ":" RR_STR(RR_ORBIT_V_MAX_KMH)

int cmd_bifurcation(int argc, char **argv)
{
  static const char help[] =
      "usage: railride bifurcation [VEHICLE] [--profile new|worn|FILE.csv] [--speeds A:B]\n"
      "                            [--method continuation|scan] [--json|--csv]\n"
      "Hunting limit cycles of the nonlinear vehicle on straight, perfect track against speed.\n"
      "continuation (default): the Hopf point (the linear critical speed at lambda(0)), then the\n"
      "branch of cycles born there, left-right symmetric (each wheelset's motion half a period\n"
      "on is its mirror image), by shooting over half a period (Newton on the return map, the\n"
      "monodromy matrix from the variational equations) and pseudo-arclength continuation,\n"
      "through the corners where a wheelset reaches a flange; each cycle's stability from its\n"
      "Floquet multipliers, and where it changes, how (fold, symmetry breaking, period doubling,\n"
      "torus); the nonlinear critical speed is the branch's lowest speed (a fold refined by\n"
      "cycles at fixed amplitudes). A Hopf point above B is followed from there. scan: the\n"
      "paper's method, direct integration at each speed from the previous run's end state, up\n"
      "then down (10 mm on every wheelset to start; on the way up, 0.1 mm again after a speed\n"
      "whose motion died out; the way down from 10 mm when the top speed has no cycle).\n"
      "Amplitude: the leading wheelset's lateral displacement.\n" CLI_COMMON_HELP
      "Ctrl-C (or SIGTERM) stops the run and writes what is found: the branch so far, or the\n"
      "scan's runs done (exit 130).\n";
  static const cli_opt extra[] = {
      NL_PROFILE_OPT,
      {"speeds", OPT_SPEEDS, "A:B", "speed range, km/h (default " NL_SPEEDS_DEFAULT ")"},
      {"method", OPT_METHOD, "M", "continuation (default) or scan"},
      {"csv", OPT_CSV, NULL, "the branch as CSV (the assumptions on stderr)"},
      {"plot-data", OPT_NPLOTDATA, "FILE", "the same CSV to FILE too (what --plot draws)"},
      {"step", OPT_STEP, "KMH", "scan: speed step (default 5 km/h)"},
      {"settle", OPT_SETTLE, "S",
       "scan: transient discarded at each speed (default 20 s; 2 s measured)"},
      {"limit", OPT_NLIMIT, "N",
       "scan: most simulated seconds accepted (default " RR_STR(NL_SCAN_LIMIT_S) ")"},
      CLI_OPT_END};
  cli_common c;
  nl_args a = {.method = "continuation",
               .v_lo = RR_ORBIT_V_MIN_KMH, /* rr_orbit_opts_default's, in km/h */
               .v_hi = RR_ORBIT_V_MAX_KMH,
               .step_kmh = SCAN_STEP_DEFAULT_KMH,
               .settle = rr_scan_opts_default().settle_s,
               .limit = NL_SCAN_LIMIT_S};
  int r = cli_parse(argc, argv, &c, CLI_READS_JSON | CLI_READS_PROFILES | CLI_READS_PROGRESS, extra,
                    nl_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (a.csv && c.json) return cli_bad("bifurcation: --json or --csv, not both");
  rr_profile p;
  if ((r = nl_profile(&a, &c.veh, &p))) return r;
  if (!strcmp(a.method, "scan") && cli_par_size() > 1) { /* a chain: one rank runs it */
    if (cli_par_rank() != 0) return 0;
    fprintf(stderr, "railride bifurcation: the scan is a chain of runs (each from the last one's "
                    "end state), not distributed; rank 0 runs it alone\n");
  }
  return strcmp(a.method, "scan") ? bif_continue(&c, &p, &a) : bif_scan(&c, &p, &a);
}
