/* `railride validate`: the PEM against FFTs of a time-domain run. */
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

typedef struct val_args {
  rr_validate_opts vo;
  ride_setup rs;
  const char *psd_path;
  double limit; /* most samples (--limit) */
} val_args;
enum { OPT_DURATION = 4000, OPT_SEED, OPT_FS, OPT_NSEG, OPT_VPSD, OPT_VLIMIT, OPT_AMPS, OPT_VDIR };
#define CLI_FS_MIN 64.0 /* above twice the band's 30 Hz */
#define CLI_FS_MAX 1e5
#define CLI_NSEG_MAX 1048576
#define VAL_Z_TOL 4.0 /* an error in units of its sampling spread: bands, RMS, Sperling */
/* GB/T 5599 from the Welch PSD: W ~ (sum A^3)^0.1 with A ~ P^0.5, so W's
   spread is at most 0.15 of one bin's; VAL_Z_TOL of that */
#define VAL_GB_SPREAD 0.15

static int val_cb(int opt, const char *arg, void *u)
{
  val_args *a = u;
  char *end;
  switch (opt) {
  case OPT_DURATION: return cli_number_in("duration", arg, "s", 1, 1e6, &a->vo.duration_s) ? 1 : 0;
  case OPT_SEED: {
    unsigned long long s;
    if (cli_seed(arg, &s)) return 1;
    a->vo.seed = s;
    return 0;
  }
  case OPT_FS: return cli_number_in("fs", arg, "Hz", CLI_FS_MIN, CLI_FS_MAX, &a->vo.fs_hz) ? 1 : 0;
  case OPT_NSEG: {
    errno = 0;
    long k = strtol(arg, &end, 10);
    if (*end || errno || k < 8 || k > CLI_NSEG_MAX || k % 2)
      return cli_bad("--nseg: an even whole number from 8 to %d expected, got '%s'", CLI_NSEG_MAX,
                     arg);
    a->vo.nseg = (int)k;
    return 0;
  }
  case OPT_VLIMIT: return cli_limit(arg, &a->limit) ? 1 : 0;
  case OPT_VDIR: return 0; /* read before parsing */
  case OPT_AMPS:
    if (strcmp(arg, "gaussian") && strcmp(arg, "fixed"))
      return cli_bad("--track-amplitudes: gaussian or fixed expected, got '%s'", arg);
    a->vo.amplitudes = strcmp(arg, "fixed") ? RR_TRACK_GAUSSIAN : RR_TRACK_FIXED;
    return 0;
  case OPT_VPSD: a->psd_path = arg; return 0;
  }
  int r = ride_setup_option(&a->rs, opt, arg);
  return r < 0 ? 1 : r;
}

/* The figures a verdict and a report need, beside the result. */
typedef struct val_summary {
  double emax, zmax, seconds; /* largest band error and |error|/sigma; run time */
  int pass;
} val_summary;

/* The time run and its analysis (rr_validate) for the command's vehicle and
   points; progress and Ctrl-C on the way. */
static int val_run(cli_common *c, val_args *a, rr_validate_result *res, double *secs)
{
  rr_model *m;
  int r = cli_model(c, &m, 1, 1);
  if (r) return r;
  rr_error e;
  rr_spectrum sp;
  rr_ride_plan *rp = NULL; /* the ride's floor rows, the time run's outputs */
  rr_ride_opts ro = ride_opts(&a->rs);
  int st = rr_spectrum_open(a->rs.spectrum, &sp, &e), np = a->rs.npoints;
  if (!st) st = rr_spectrum_require(&sp, "lateral", "--spectrum: the lateral track input", &e);
  if (!st) st = rr_ride_plan_new(m, &c->veh, &ro, &rp, &e);
  a->vo.npoints = np;
  a->vo.rows = st ? NULL : rr_ride_rows(rp, &a->vo.rows0);
  cli_progress pr;
  cli_progress_start(&pr, "validate", 3 + np, c->progress);
  a->vo.progress = cli_progress_hook(&pr);
  cli_catch_stops();
  double t0 = cli_now_s();
  if (!st) st = rr_validate(m, &sp, &a->vo, res, &e);
  cli_progress_end(&pr);
  *secs = cli_now_s() - t0;
  rr_ride_plan_free(rp);
  rr_model_free(m);
  rr_spectrum_close(&sp);  /* safe after a failed open too */
  if (st == RR_ESTOPPED) { /* one result: nothing partial to write */
    fprintf(stderr, "railride: validate: stopped by a signal (%s); nothing written\n", e.msg);
    return CLI_EXIT_STOPPED;
  }
  return st ? cli_fail(&e, st) : 0;
}

static void write_psd(FILE *fp, const val_args *a, const rr_validate_result *res)
{
  int np = res->npoints;
  fprintf(fp, "f_hz");
  for (int q = 0; q < np; q++) fprintf(fp, ",welch_x%gm_m2s-4_per_hz", a->rs.x[q]);
  for (int q = 0; q < np; q++) fprintf(fp, ",pem_x%gm_m2s-4_per_hz", a->rs.x[q]);
  fprintf(fp, ",welch_sigma_rel\n");
  for (int k = 0; k < res->nwelch; k++) {
    fprintf(fp, "%.10g", res->welch_f[k]);
    for (int q = 0; q < np; q++)
      fprintf(fp, ",%.10g", res->welch_P[(size_t)q * (size_t)res->nwelch + (size_t)k]);
    for (int q = 0; q < np; q++)
      fprintf(fp, ",%.10g", res->pem_P[(size_t)q * (size_t)res->nwelch + (size_t)k]);
    fprintf(fp, ",%.6g\n", res->bin_sigma);
  }
}

/* The verdict: the run's RMS and Sperling index (by time filtering) within
   VAL_Z_TOL of their spread about the realisation's expectation, every
   1/3-octave band likewise, and GB/T 5599's index from the Welch PSD within
   VAL_Z_TOL of its spread of the PEM's. */
static double gb_tolerance(const rr_validate_result *res)
{
  return VAL_Z_TOL * VAL_GB_SPREAD * res->bin_sigma;
}

static void val_verdict(const rr_validate_result *res, val_summary *v)
{
  v->emax = v->zmax = 0;
  for (int q = 0; q < res->npoints; q++) {
    v->emax = fmax(v->emax, res->points[q].band_error_max);
    v->zmax = fmax(v->zmax, res->points[q].band_z_max);
  }
  v->pass = v->zmax <= VAL_Z_TOL;
  for (int q = 0; q < res->npoints; q++) {
    const rr_validate_point *p = &res->points[q];
    v->pass = v->pass && fabs(p->rms_z) <= VAL_Z_TOL && fabs(p->sperling_z) <= VAL_Z_TOL &&
              fabs(p->sperling_gb_welch / p->sperling_gb_pem - 1) <= gb_tolerance(res);
  }
}

static void val_json(const val_args *a, const rr_validate_result *res, const val_summary *v)
{
  int np = res->npoints, pass = v->pass;
  double emax = v->emax, zmax = v->zmax, secs = v->seconds;
  const rr_validate_point *p0 = &res->points[0];
  cJSON *root = cJSON_CreateObject();
  cJSON_AddNumberToObject(root, "point_x", a->rs.x[0]);
  cJSON_AddNumberToObject(root, "sperling_pem", p0->sperling_pem);
  cJSON_AddNumberToObject(root, "sperling_time", p0->sperling_time);
  cJSON_AddNumberToObject(root, "rms_pem", p0->rms_pem);
  cJSON_AddNumberToObject(root, "rms_time", p0->rms_time);
  cJSON_AddNumberToObject(root, "psd_band_error_max", emax);
  cJSON_AddNumberToObject(root, "psd_band_z_max", zmax);
  cJSON_AddNumberToObject(root, "navg", res->navg);
  cJSON_AddNumberToObject(root, "duration_s", a->vo.duration_s);
  cJSON_AddNumberToObject(root, "fs_hz", a->vo.fs_hz);
  cJSON_AddNumberToObject(root, "nseg", a->vo.nseg);
  cJSON_AddNumberToObject(root, "seed", (double)a->vo.seed);
  cJSON_AddStringToObject(root, "spectrum", a->rs.spectrum);
  cJSON_AddNumberToObject(root, "cpu_seconds", secs);
  cJSON_AddStringToObject(root, "band_sigma_rule",
                          "sqrt((1 + 2 c^2) / K * 1.5 / M): K Hann segments at 50% overlap (c = "
                          "0.167), M bins in the band, 1.5 = Hann ENBW in bins");
  cJSON_AddStringToObject(root, "verdict", pass ? "PASS" : "FAIL");
  cJSON_AddStringToObject(root, "track_amplitudes",
                          a->vo.amplitudes == RR_TRACK_FIXED ? "fixed" : "gaussian");
  cJSON *tol = cJSON_AddObjectToObject(root, "tolerances");
  cJSON_AddNumberToObject(tol, "z", VAL_Z_TOL);
  cJSON_AddNumberToObject(tol, "sperling_gb_relative", gb_tolerance(res));
  cJSON *pa = cJSON_AddArrayToObject(root, "points");
  for (int q = 0; q < np; q++) {
    const rr_validate_point *p = &res->points[q];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "x", a->rs.x[q]);
    cJSON_AddNumberToObject(o, "rms_pem", p->rms_pem);
    cJSON_AddNumberToObject(o, "rms_time", p->rms_time);
    cJSON_AddNumberToObject(o, "sperling_pem", p->sperling_pem);
    cJSON_AddNumberToObject(o, "sperling_time", p->sperling_time);
    cJSON_AddNumberToObject(o, "sperling_welch", p->sperling_welch);
    cJSON_AddNumberToObject(o, "sperling_gb_pem", p->sperling_gb_pem);
    cJSON_AddNumberToObject(o, "sperling_gb_welch", p->sperling_gb_welch);
    cJSON_AddNumberToObject(o, "wd_rms_pem", p->wd_rms_pem);
    cJSON_AddNumberToObject(o, "wd_rms_welch", p->wd_rms_welch);
    cJSON_AddNumberToObject(o, "rms_lines", p->rms_lines);
    cJSON_AddNumberToObject(o, "rms_rel_std", p->rms_rel_std);
    cJSON_AddNumberToObject(o, "rms_z", p->rms_z);
    cJSON_AddNumberToObject(o, "sperling_lines", p->sperling_lines);
    cJSON_AddNumberToObject(o, "sperling_rel_std", p->sperling_rel_std);
    cJSON_AddNumberToObject(o, "sperling_z", p->sperling_z);
    cJSON_AddNumberToObject(o, "band_error_max", p->band_error_max);
    cJSON_AddNumberToObject(o, "band_z_max", p->band_z_max);
    cJSON *ba = cJSON_AddArrayToObject(o, "bands");
    for (int b = 0; b < p->nbands; b++) {
      cJSON *bo = cJSON_CreateObject();
      cJSON_AddNumberToObject(bo, "fc_hz", p->band_fc[b]);
      cJSON_AddNumberToObject(bo, "pem", p->band_pem[b]);
      cJSON_AddNumberToObject(bo, "time", p->band_time[b]);
      cJSON_AddNumberToObject(bo, "sigma_rel", p->band_sigma[b]);
      cJSON_AddItemToArray(ba, bo);
    }
    cJSON_AddItemToArray(pa, o);
  }
  cli_json_print(root);
}

static void val_text(const cli_common *c, const val_args *a, const rr_validate_result *res,
                     const val_summary *v)
{
  int np = res->npoints, pass = v->pass;
  double emax = v->emax, zmax = v->zmax, secs = v->seconds;
  printf("%s at %g km/h, conicity %g: %g s of track (%s, %s amplitudes, seed %llu), fs %g Hz, "
         "Welch %d-point segments, K = %d averages\n",
         c->veh.name, c->speed_kmh, c->conicity, a->vo.duration_s, a->rs.spectrum,
         a->vo.amplitudes == RR_TRACK_FIXED ? "fixed" : "Gaussian", (unsigned long long)a->vo.seed,
         a->vo.fs_hz, a->vo.nseg, res->navg);
  printf("%8s %10s %10s %7s %9s %9s %7s %9s %9s %8s\n", "x_m", "rms_pem", "rms_time", "rms_z",
         "W_pem", "W_time", "W_z", "Wgb_pem", "Wgb_welch", "band_z");
  for (int q = 0; q < np; q++) {
    const rr_validate_point *p = &res->points[q];
    printf("%8.3f %10.6f %10.6f %7.2f %9.5f %9.5f %7.2f %9.4f %9.4f %8.2f\n", a->rs.x[q],
           p->rms_pem, p->rms_time, p->rms_z, p->sperling_pem, p->sperling_time, p->sperling_z,
           p->sperling_gb_pem, p->sperling_gb_welch, p->band_z_max);
  }
  printf("z: (run - expectation) / spread, the expectation and spread those of the realisation's "
         "lines\n");
  printf("1/3-octave bands: largest error %.1f%%, largest |error|/sigma %.2f (sigma from K "
         "averages)\n",
         100 * emax, zmax);
  printf("simulated and analysed in %.3f s\n", secs);
  printf("verdict: %s (RMS, Sperling and every band within %g sigma at every point, GB/T 5599 "
         "from Welch within %.1f %% of the PEM's)\n",
         pass ? "PASS" : "FAIL", VAL_Z_TOL, 100 * gb_tolerance(res));
}

int cmd_validate(int argc, char **argv)
{
  static const char help[] =
      "usage: railride validate [VEHICLE] --speed KMH --conicity L [--duration S] [--seed N] "
      "[--json] [--psd FILE.csv]\n"
      "Validates the frequency-domain ride results (PEM) against a time-domain run: a seeded\n"
      "random track realisation of the spectrum (0.3-30 Hz content, each wheelset at its own\n"
      "position), exact discretisation of the same state space (cubic Hermite input hold), the\n"
      "periodic steady state of the periodic realisation, then the RMS and the Sperling index by\n"
      "time-domain filtering, and a Welch PSD (Hann, 50% overlap) with the indices from it and\n"
      "1/3-octave band powers compared with the PEM within the spread expected from the number\n"
      "of averages. The yaw damper SDF must be none or physical (paper mode has no time "
      "form).\n" CLI_COMMON_HELP
      "Verdict: PASS when the RMS, the Sperling index and every band lie within 4 sigma of the\n"
      "realisation's expectation and GB/T 5599 from the Welch PSD within 4 of its sigma of the\n"
      "PEM's; FAIL exits with status 1.\n";
  static const cli_opt extra[] = {
      {"duration", OPT_DURATION, "S", "record length, s (default " CLI_VALIDATE_DURATION ")"},
      {"seed", OPT_SEED, "N", "realisation seed (default 1)"},
      {"fs", OPT_FS, "HZ", "sample rate (default 256)"},
      {"nseg", OPT_NSEG, "N", "Welch segment length (default 4096)"},
      {"psd", OPT_VPSD, "FILE.csv",
       "write f_hz, the Welch and PEM PSDs of each point ((m/s^2)^2/Hz) and welch_sigma_rel, the "
       "relative spread of one Welch bin"},
      {"limit", OPT_VLIMIT, "N",
       "most samples (duration x fs) accepted (default " RR_STR(CLI_LIMIT_SAMPLES) ")"},
      {"track-amplitudes", OPT_AMPS, "A",
       "gaussian (default: random complex line coefficients, a Gaussian track whose powers "
       "scatter) or fixed (random phases only)"},
      {"direction", OPT_VDIR, "D",
       "lateral (default) or vertical: the vertical model against its own run (railride validate "
       "--direction vertical --help)"},
      RIDE_SETUP_OPTIONS,
      CLI_OPT_END};
  int dir = cli_direction_one("validate", argc, argv);
  if (dir < 0) return EXIT_BADINPUT;
  if (dir == CLI_DIR_VERTICAL) return validate_vertical(argc, argv);
  cli_common c;
  val_args a = {.vo = rr_validate_opts_default(), .limit = CLI_LIMIT_SAMPLES};
  rr_vehicle tmp;
  rr_vehicle_default(&tmp);
  ride_setup_default(&a.rs, &tmp);
  int r = cli_parse(argc, argv, &c,
                    CLI_READS_SPEED | CLI_READS_CONICITY | CLI_READS_JSON | CLI_READS_GRAVITY |
                        CLI_READS_PROGRESS,
                    extra, val_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  double samples = a.vo.duration_s * a.vo.fs_hz;
  if (cli_over_limit("validate", samples, a.limit, "samples")) return EXIT_BADINPUT;
  if (a.vo.nseg > samples)
    return cli_bad("--nseg: %d exceeds the record's %.0f samples", a.vo.nseg, samples);
  ride_setup_points(&a.rs, &c.veh, argc, argv);
  cli_outfile psd = {0}; /* opened before the run: a folder that cannot be written fails first */
  if (a.psd_path && (r = cli_out_open(&psd, a.psd_path, "--psd"))) return r;
  rr_validate_result res;
  val_summary v;
  if ((r = val_run(&c, &a, &res, &v.seconds))) {
    cli_out_abort(&psd);
    return r;
  }
  if (psd.fp) write_psd(psd.fp, &a, &res);
  if ((r = cli_out_commit(&psd))) {
    rr_validate_result_free(&res);
    return r;
  }
  val_verdict(&res, &v);
  if (c.json)
    val_json(&a, &res, &v);
  else
    val_text(&c, &a, &res, &v);
  rr_validate_result_free(&res);
  return v.pass ? 0 : EXIT_FAIL;
}
