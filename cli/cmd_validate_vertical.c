/* `railride validate --direction vertical`: the vertical PEM against a
 * time-domain run of the vertical model on a Gaussian random track. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "outfile.h"

#define VV_FRF_TOL 1e-3 /* the record's line FRF against the PEM's, of max |H| */
#define VV_Z_TOL 4.0    /* RMS, Sperling, P95 and bands: |z| */

typedef struct vval_args {
  rr_vertical_validate_opts vo;
  ride_setup rs;
  vertical_setup vs;
  const char *psd_path;
  double limit;
} vval_args;
enum {
  OPT_VV_DURATION = 4100,
  OPT_VV_SEED,
  OPT_VV_FS,
  OPT_VV_NSEG,
  OPT_VV_PSD,
  OPT_VV_LIMIT,
  OPT_VV_AMPS,
  OPT_VV_DIR,
  OPT_VV_SPECTRUM,
  OPT_VV_WINDOW,
  OPT_VV_OUTSIDE
};

static int whole(const char *opt, const char *arg, long lo, long hi, long *out)
{
  char *end;
  errno = 0;
  long k = strtol(arg, &end, 10);
  if (*end || !*arg || errno || k < lo || k > hi)
    return cli_bad("--%s: a whole number from %ld to %ld expected, got '%s'", opt, lo, hi, arg);
  *out = k;
  return 0;
}

static int vval_cb(int opt, const char *arg, void *u)
{
  vval_args *a = u;
  long k = 0;
  switch (opt) {
  case OPT_VV_DURATION: return cli_number_in("duration", arg, "s", 10, 1e5, &a->vo.duration_s);
  case OPT_VV_SEED: {
    unsigned long long s;
    if (cli_seed(arg, &s)) return 1;
    a->vo.seed = s;
    return 0;
  }
  case OPT_VV_FS: return cli_number_in("fs", arg, "Hz", 64, 1e5, &a->vo.fs_hz);
  case OPT_VV_NSEG:
    if (whole("nseg", arg, 8, 1048576, &k)) return 1;
    if (k % 2) return cli_bad("--nseg: an even number expected, got '%s'", arg);
    a->vo.nseg = (int)k;
    return 0;
  case OPT_VV_PSD: a->psd_path = arg; return 0;
  case OPT_VV_LIMIT: return cli_limit(arg, &a->limit) ? 1 : 0;
  case OPT_VV_DIR: return 0; /* read before parsing */
  case OPT_VV_AMPS:
    if (strcmp(arg, "gaussian") && strcmp(arg, "fixed"))
      return cli_bad("--track-amplitudes: gaussian or fixed expected, got '%s'", arg);
    a->vo.amplitudes = strcmp(arg, "fixed") ? RR_TRACK_GAUSSIAN : RR_TRACK_FIXED;
    return 0;
  case OPT_VV_SPECTRUM: a->vs.spectrum = arg; return 0;
  case OPT_VV_WINDOW: return cli_number_in("window", arg, "s", 0.01, 3600, &a->vo.window_s);
  case OPT_VV_OUTSIDE:
    if (strcmp(arg, "extend") && strcmp(arg, "zero"))
      return cli_bad("--outside: extend or zero expected, got '%s'", arg);
    a->vs.outside = !strcmp(arg, "zero");
    return 0;
  case OPT_POINTS: return ride_setup_option(&a->rs, opt, arg);
  }
  return 1;
}

static int vval_pass(const rr_vertical_validate_result *r)
{
  int pass = 1;
  for (int q = 0; q < r->npoints; q++) {
    const rr_vertical_validate_point *p = &r->points[q];
    pass = pass && p->frf_line_error_max <= VV_FRF_TOL && fabs(p->rms_z) <= VV_Z_TOL &&
           fabs(p->sperling_z) <= VV_Z_TOL && fabs(p->wb_p95_z) <= VV_Z_TOL &&
           p->band_z_max <= VV_Z_TOL;
  }
  return pass;
}

static void vval_text(const cli_common *c, const vval_args *a, const rr_vertical_validate_result *r,
                      int pass)
{
  printf("%s at %g km/h: %g s of vertical track (%s, %s amplitudes, seed %llu), fs %g Hz, %d "
         "windows of %g s\n",
         c->veh.name, c->speed_kmh, a->vo.duration_s, a->vs.spectrum,
         a->vo.amplitudes == RR_TRACK_FIXED ? "fixed" : "Gaussian", (unsigned long long)a->vo.seed,
         a->vo.fs_hz, r->npoints ? r->points[0].windows : 0, a->vo.window_s);
  printf("%8s %9s %10s %10s %6s %8s %8s %6s %10s %10s %6s %7s\n", "x_m", "frf_err", "rms_pem",
         "rms_time", "rms_z", "W_pem", "W_time", "W_z", "wb_p95_est", "wb_p95_run", "p95_z",
         "band_z");
  for (int q = 0; q < r->npoints; q++) {
    const rr_vertical_validate_point *p = &r->points[q];
    printf("%8.4g %9.2e %10.6f %10.6f %6.2f %8.5f %8.5f %6.2f %10.6f %10.6f %6.2f %7.2f\n", p->x,
           p->frf_line_error_max, p->rms_pem, p->rms_time, p->rms_z, p->sperling_pem,
           p->sperling_time, p->sperling_z, p->wb_p95_est, p->wb_p95_time, p->wb_p95_z,
           p->band_z_max);
  }
  printf("z: (run - expectation) / spread on the realisation's lines (P95: the sample quantile's "
         "spread under the gamma law)\n");
  printf("verdict: %s (the line FRF within %g of max |H|; RMS, Sperling, P95 and every "
         "1/3-octave band within %g sigma)\n",
         pass ? "PASS" : "FAIL", VV_FRF_TOL, VV_Z_TOL);
}

static cJSON *vval_point_json(const rr_vertical_validate_point *p)
{
  cJSON *o = cJSON_CreateObject(), *ba;
  const struct {
    const char *k;
    double v;
  } f[] = {{"x", p->x},
           {"rms_pem", p->rms_pem},
           {"rms_lines", p->rms_lines},
           {"rms_time", p->rms_time},
           {"rms_rel_std", p->rms_rel_std},
           {"rms_z", p->rms_z},
           {"sperling_pem", p->sperling_pem},
           {"sperling_lines", p->sperling_lines},
           {"sperling_time", p->sperling_time},
           {"sperling_rel_std", p->sperling_rel_std},
           {"sperling_z", p->sperling_z},
           {"wb_p50_est", p->wb_p50_est},
           {"wb_p95_est", p->wb_p95_est},
           {"wb_p50_time", p->wb_p50_time},
           {"wb_p95_time", p->wb_p95_time},
           {"wb_p95_z", p->wb_p95_z},
           {"windows", p->windows},
           {"frf_line_error_max", p->frf_line_error_max},
           {"psd_band_error_max", p->band_error_max},
           {"psd_band_welch_error_max", p->band_welch_error_max},
           {"psd_band_z_max", p->band_z_max}};
  for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) cJSON_AddNumberToObject(o, f[i].k, f[i].v);
  ba = cJSON_AddArrayToObject(o, "bands");
  for (int b = 0; b < RR_VERTICAL_BANDS; b++) {
    cJSON *bo = cJSON_CreateObject();
    cJSON_AddNumberToObject(bo, "fc", p->band_fc[b]);
    cJSON_AddNumberToObject(bo, "pem", p->band_pem[b]);
    cJSON_AddNumberToObject(bo, "time_lines", p->band_time[b]);
    cJSON_AddNumberToObject(bo, "welch", p->band_welch[b]);
    cJSON_AddNumberToObject(bo, "rel_std", p->band_rel_std[b]);
    cJSON_AddNumberToObject(bo, "z", p->band_z[b]);
    cJSON_AddItemToArray(ba, bo);
  }
  return o;
}

static void vval_json(const cli_common *c, const vval_args *a, const rr_vertical_validate_result *r,
                      int pass)
{
  cJSON *root = cJSON_CreateObject(), *pa;
  cJSON_AddStringToObject(root, "vehicle", c->veh.name);
  cJSON_AddStringToObject(root, "direction", "vertical");
  cJSON_AddNumberToObject(root, "speed_kmh", c->speed_kmh);
  cJSON_AddStringToObject(root, "spectrum", a->vs.spectrum);
  cJSON_AddNumberToObject(root, "duration_s", a->vo.duration_s);
  cJSON_AddNumberToObject(root, "fs_hz", a->vo.fs_hz);
  cJSON_AddNumberToObject(root, "seed", (double)a->vo.seed);
  cJSON_AddStringToObject(root, "track_amplitudes",
                          a->vo.amplitudes == RR_TRACK_FIXED ? "fixed" : "gaussian");
  cJSON_AddNumberToObject(root, "window_s", a->vo.window_s);
  cJSON_AddNumberToObject(root, "navg", r->navg);
  cJSON_AddStringToObject(root, "verdict", pass ? "PASS" : "FAIL");
  cJSON *tol = cJSON_AddObjectToObject(root, "tolerances");
  cJSON_AddNumberToObject(tol, "frf_line_error", VV_FRF_TOL);
  cJSON_AddNumberToObject(tol, "z", VV_Z_TOL);
  pa = cJSON_AddArrayToObject(root, "points");
  for (int q = 0; q < r->npoints; q++) cJSON_AddItemToArray(pa, vval_point_json(&r->points[q]));
  cli_json_print(root);
}

static void vval_psd(FILE *fp, const rr_vertical_validate_result *r)
{
  int np = r->npoints, nh = r->nwelch;
  fprintf(fp, "f_hz");
  for (int q = 0; q < np; q++) fprintf(fp, ",welch_x%gm_m2s-4_per_hz", r->points[q].x);
  for (int q = 0; q < np; q++) fprintf(fp, ",pem_x%gm_m2s-4_per_hz", r->points[q].x);
  fputc('\n', fp);
  for (int k = 0; k < nh; k++) {
    fprintf(fp, "%.10g", r->welch_f[k]);
    for (int q = 0; q < np; q++)
      fprintf(fp, ",%.10g", r->welch_P[(size_t)q * (size_t)nh + (size_t)k]);
    for (int q = 0; q < np; q++)
      fprintf(fp, ",%.10g", r->pem_P[(size_t)q * (size_t)nh + (size_t)k]);
    fputc('\n', fp);
  }
}

/* The model, the spectrum and the run. */
static int vval_run(const cli_common *c, vval_args *a, rr_vertical_validate_result *r)
{
  rr_vertical_model m;
  rr_spectrum sp;
  rr_error e = {0};
  int st = rr_spectrum_open(a->vs.spectrum, &sp, &e), opened = !st;
  if (!st)
    st = rr_spectrum_require(&sp, "vertical", "--vertical-spectrum: the vertical track input", &e);
  if (!st && a->vs.outside >= 0) sp.clip = a->vs.outside;
  if (!st) st = rr_vertical_model_build(&c->veh, &m, &e);
  a->vo.npoints = a->rs.npoints;
  memcpy(a->vo.x_points, a->rs.x, sizeof(double) * (size_t)a->rs.npoints);
  if (!st) st = rr_vertical_validate(&m, c->speed_kmh / RR_KMH, &sp, &a->vo, r, &e);
  if (opened) rr_spectrum_close(&sp);
  return st ? cli_fail(&e, st) : 0;
}

int validate_vertical(int argc, char **argv)
{
  static const char help[] =
      "usage: railride validate [VEHICLE] --speed KMH --direction vertical [--vertical-spectrum S] "
      "[--duration S] [--seed N] [--json] [--psd FILE.csv]\n"
      "The vertical model's PEM against a time-domain run of the same model: a seeded Gaussian\n"
      "realisation of the vertical profile (random complex line coefficients, 0.3-30 Hz, each\n"
      "wheelset with its exact delay), the 14-state system discretised exactly for a cubic\n"
      "Hermite hold, its periodic steady state; at each floor point the record's line FRF against\n"
      "the PEM's, the RMS, the Sperling index (weighting applied to the record's lines) and the\n"
      "1/3-octave band powers (centres 0.5-20 Hz) against their expectation with the\n"
      "realisation's own spread, and the 5 s Wb RMS P95 of the record against the gamma "
      "law's.\n" CLI_COMMON_HELP
      "Verdict: PASS when the line FRF is within 1e-3 of max |H| and the RMS, Sperling, P95 and\n"
      "every band within 4 sigma; FAIL exits with status 1.\n";
  static const cli_opt extra[] = {
      {"direction", OPT_VV_DIR, "vertical", "this command"},
      {"vertical-spectrum", OPT_VV_SPECTRUM, "S",
       "vertical track spectrum (default tbt3352-vertical)"},
      {"outside", OPT_VV_OUTSIDE, "extend|zero",
       "the spectrum beyond its valid range (default: the file's)"},
      {"duration", OPT_VV_DURATION, "S", "record length, s (default " CLI_VALIDATE_DURATION ")"},
      {"seed", OPT_VV_SEED, "N", "realisation seed (default 1)"},
      {"fs", OPT_VV_FS, "HZ", "sample rate (default 256)"},
      {"nseg", OPT_VV_NSEG, "N", "Welch segment length (default 4096)"},
      {"window", OPT_VV_WINDOW, "T", "EN 12299 RMS window, s (default 5)"},
      {"track-amplitudes", OPT_VV_AMPS, "A", "gaussian (default) or fixed (random phases only)"},
      {"points", OPT_POINTS, "X1,..", "floor points (default +L, 0, -L)"},
      {"psd", OPT_VV_PSD, "FILE.csv",
       "write f_hz, each point's Welch PSD and the PEM's ((m/s^2)^2/Hz)"},
      {"limit", OPT_VV_LIMIT, "N",
       "most samples (duration x fs) accepted (default " RR_STR(CLI_LIMIT_SAMPLES) ")"},
      CLI_OPT_END};
  cli_common c;
  vval_args a = {.vo = rr_vertical_validate_opts_default(), .limit = CLI_LIMIT_SAMPLES};
  rr_vehicle tmp;
  rr_vehicle_default(&tmp);
  ride_setup_default(&a.rs, &tmp);
  vertical_setup_default(&a.vs);
  int r = cli_parse(argc, argv, &c, CLI_READS_SPEED | CLI_READS_JSON, extra, vval_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (!c.have_speed) return cli_bad("--speed is required");
  double samples = a.vo.duration_s * a.vo.fs_hz;
  if (cli_over_limit("validate", samples, a.limit, "samples")) return EXIT_BADINPUT;
  if (a.vo.nseg > samples)
    return cli_bad("--nseg: %d exceeds the record's %.0f samples", a.vo.nseg, samples);
  ride_setup_points(&a.rs, &c.veh, argc, argv);
  cli_outfile psd = {0};
  if (a.psd_path && (r = cli_out_open(&psd, a.psd_path, "--psd"))) return r;
  rr_vertical_validate_result res;
  if ((r = vval_run(&c, &a, &res))) {
    cli_out_abort(&psd);
    return r;
  }
  if (psd.fp) vval_psd(psd.fp, &res);
  r = cli_out_commit(&psd);
  int pass = vval_pass(&res);
  if (!r && c.json)
    vval_json(&c, &a, &res, pass);
  else if (!r)
    vval_text(&c, &a, &res, pass);
  rr_vertical_validate_result_free(&res);
  return r ? r : pass ? 0 : EXIT_FAIL;
}
