/* Ride commands: ride (PEM + comfort indices), frf (complex FRFs), compare
 * (SDF against constant series stiffness). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "outfile.h"

typedef struct ride_args {
  ride_setup rs;
  vertical_setup vs;
  double conicities[64];
  int ncon;
  const char *psd_path;
  unsigned lateral_only, vertical_only; /* options given that belong to one side (bits) */
  const char *lateral_default;          /* the default --spectrum (to see one given) */
} ride_args;
enum { OPT_BAND = 3100, OPT_PSD, OPT_METHOD, OPT_CMP_CON, OPT_CMP_CSV, OPT_CMP_PLOTDATA };

#define CMP_CSV_COLUMNS                                                                            \
  "vehicle,conicity,stability_index_const,stability_index_sdf,sperling_const,sperling_sdf,"        \
  "n_mv_const,n_mv_sdf,fmax_hz"
#define CMP_CSV_HEADER CMP_CSV_COLUMNS "\n"
/* The vertical side's options (ride, frf). */
enum {
  OPT_DIRECTION = 3200,
  OPT_VSPECTRUM,
  OPT_WINDOW,
  OPT_OUTSIDE,
  OPT_AXP95,
  OPT_AXP50,
  OPT_DOFS,
  OPT_AXPITCH,
  OPT_HP,
  OPT_LATP95,
  OPT_LATRMS
};
/* clang-format off */
#define VERTICAL_OPTIONS \
  {"direction", OPT_DIRECTION, "D", \
   "lateral (default), vertical (the vertical model: bounce, pitch, first " \
   "bending; floor vertical PSD, RMS, Sperling, Wk, Wb and the 5 s Wb RMS " \
   "percentiles), or both (adds EN 12299 N_MV, N_VD, N_VA per point from " \
   "the lateral Wd and vertical Wb percentiles; one conicity)"}, \
  {"vertical-spectrum", OPT_VSPECTRUM, "S", "vertical track spectrum (default tbt3352-vertical)"}, \
  {"outside", OPT_OUTSIDE, "extend|zero", \
   "the vertical spectrum beyond its valid range (default: the file's)"}, \
  {"window", OPT_WINDOW, "T", "EN 12299 RMS window, s (default 5)"}, \
  {"ax-p95", OPT_AXP95, "A", \
   "longitudinal Wd 5 s RMS P95, m/s^2, for N_MV/N_VD/N_VA " \
   "(default 0: longitudinal motion is not modelled)"}, \
  {"ax-p50", OPT_AXP50, "A", "the same for the P50 (default 0)"}, \
  {"ax-pitch", OPT_AXPITCH, NULL, \
   "instead, the longitudinal floor acceleration of carbody pitch alone " \
   "at floor height --hp H: (H - h_c) theta'' - g theta"}, \
  {"hp", OPT_HP, "H", "that floor height, m (default 1.2)"}, \
  {"lateral-wd-p95", OPT_LATP95, "A[,A..]", \
   "vertical: EN 12299 with the lateral Wd P95 given (P50 = P95), " \
   "one value or one per point, m/s^2"}, \
  {"lateral-wd-rms", OPT_LATRMS, "A[,A..]", \
   "the same with the stationary Wd RMS for both percentiles"}
/* clang-format on */

/* The vertical options (enum cli_opt_result). */
static int vertical_option(ride_args *a, int opt, const char *arg)
{
  vertical_setup *v = &a->vs;
  switch (opt) {
  case OPT_DIRECTION: return 0; /* read before parsing (cli_direction_scan) */
  case OPT_VSPECTRUM: v->spectrum = arg; break;
  case OPT_WINDOW:
    if (cli_number_in("window", arg, "s", 0.01, 3600, &v->window_s)) return 1;
    break;
  case OPT_OUTSIDE:
    if (strcmp(arg, "extend") && strcmp(arg, "zero"))
      return cli_bad("--outside: extend or zero expected, got '%s'", arg);
    v->outside = !strcmp(arg, "zero");
    break;
  case OPT_AXP95:
  case OPT_AXP50:
    if (cli_number_in(opt == OPT_AXP95 ? "ax-p95" : "ax-p50", arg, "m/s2", 0, 100,
                      opt == OPT_AXP95 ? &v->ax_p95 : &v->ax_p50))
      return 1;
    break;
  case OPT_DOFS: v->dofs = 1; break;
  case OPT_AXPITCH: v->ax_pitch = 1; break;
  case OPT_HP:
    if (cli_number_in("hp", arg, "m", 0, CLI_FLOOR_H_MAX, &v->hp)) return 1;
    break;
  case OPT_LATP95:
  case OPT_LATRMS: {
    const char *nm = opt == OPT_LATP95 ? "lateral-wd-p95" : "lateral-wd-rms";
    if (v->lateral_given) return cli_bad("--lateral-wd-p95 and --lateral-wd-rms: one of them");
    if (cli_list(nm, arg, "m/s2", v->lateral, 16, &v->nlateral)) return 1;
    for (int i = 0; i < v->nlateral; i++)
      if (!(v->lateral[i] >= 0 && v->lateral[i] <= 100))
        return cli_bad("--%s: %g m/s^2 outside 0 .. 100", nm, v->lateral[i]);
    v->lateral_given = opt == OPT_LATP95 ? 1 : 2;
    break;
  }
  default: return -1;
  }
  a->vertical_only |= 1u << (opt - OPT_DIRECTION);
  return 0;
}

static int ride_cb(int opt, const char *arg, void *u)
{
  ride_args *a = u;
  int r = ride_setup_option(&a->rs, opt, arg);
  if (r >= 0) {
    if (opt == OPT_HEIGHT || opt == OPT_ROLLG || opt == OPT_LINEAR_UNSTABLE)
      a->lateral_only |= 1u << (opt - OPT_SPECTRUM);
    return r;
  }
  if ((r = vertical_option(a, opt, arg)) >= 0) return r;
  switch (opt) {
  case OPT_BAND:
    if (cli_range("band", arg, "Hz", &a->rs.f_lo, &a->rs.f_hi, &a->rs.nfreq)) return 1;
    if (!(a->rs.f_lo >= CLI_BAND_LO_MIN && a->rs.f_hi > a->rs.f_lo &&
          a->rs.f_hi <= CLI_BAND_HI_MAX && a->rs.nfreq >= 2 && a->rs.nfreq <= CLI_BAND_N_MAX))
      return cli_bad("--band: need %g <= LO < HI <= %g Hz and 2 <= N <= %d", CLI_BAND_LO_MIN,
                     CLI_BAND_HI_MAX, CLI_BAND_N_MAX);
    return 0;
  case OPT_PSD: a->psd_path = arg; return 0;
  case OPT_METHOD:
    a->lateral_only |= 1u << 8;
    if (!strcmp(arg, "sparse"))
      a->rs.method = RR_FRF_SPARSE;
    else if (!strcmp(arg, "modal"))
      a->rs.method = RR_FRF_MODAL;
    else if (!strcmp(arg, "direct"))
      a->rs.method = RR_FRF_DIRECT;
    else
      return cli_bad("--method: sparse, modal or direct expected, got '%s'", arg);
    return 0;
  }
  return 1;
}

/* Parsing shared by ride and frf: defaults, options, floor points of the
   vehicle loaded. Returns 0 to go on, or an exit status (-1 after --help). */
static int ride_parse(int argc, char **argv, cli_common *c, ride_args *a, const cli_opt *extra,
                      const char *help, int conicity_list);

/* the library's default grid (pem.h), as --band writes it */
#define RIDE_BAND_DEFAULT                                                                          \
  RR_STR(RR_FRF_F_LO_DEFAULT) ":" RR_STR(RR_FRF_F_HI_DEFAULT) ":" RR_STR(RR_FRF_NFREQ_DEFAULT)
/* clang-format off */
#define RIDE_BAND_OPTIONS \
  {"band", OPT_BAND, "LO:HI:N", "log-spaced frequency grid, Hz (default " RIDE_BAND_DEFAULT ")"}, \
  {"method", OPT_METHOD, "M", \
   "sparse (default: a sparse LU per frequency), modal (modal expansion + SMW) or direct " \
   "(a dense LU per frequency)"}
#define RIDE_OPTIONS RIDE_SETUP_OPTIONS, RIDE_BAND_OPTIONS
/* frf: the same without a track input */
#define FRF_OPTIONS RIDE_POINT_OPTIONS, RIDE_BAND_OPTIONS
/* clang-format on */

/* An option that belongs to the other direction: its message, or 0. */
static int direction_mismatch(const ride_args *a)
{
  static const char *const vnames[] = {"--direction",
                                       "--vertical-spectrum",
                                       "--window",
                                       "--outside",
                                       "--ax-p95",
                                       "--ax-p50",
                                       "--dofs",
                                       "--ax-pitch",
                                       "--hp",
                                       "--lateral-wd-p95",
                                       "--lateral-wd-rms"};
  int dir = a->vs.direction;
  if (dir == CLI_DIR_BOTH && a->vs.lateral_given)
    return cli_bad("--lateral-wd-%s: with --direction vertical (both computes the lateral side)",
                   a->vs.lateral_given == 1 ? "p95" : "rms");
  if (a->vs.ax_pitch && (a->vertical_only & (3u << (OPT_AXP95 - OPT_DIRECTION))))
    return cli_bad("--ax-pitch: not with --ax-p95 or --ax-p50");
  for (int b = 0; dir == CLI_DIR_LATERAL && b < 11; b++)
    if (a->vertical_only & (1u << b))
      return cli_bad("%s: only with --direction vertical or both", vnames[b]);
  if (dir != CLI_DIR_VERTICAL) return 0;
  if (a->lateral_only & (1u << (OPT_HEIGHT - OPT_SPECTRUM)))
    return cli_bad("--floor-height: the lateral model's (not with --direction vertical)");
  if (a->lateral_only & (1u << (OPT_ROLLG - OPT_SPECTRUM)))
    return cli_bad("--roll-gravity: the lateral model's (not with --direction vertical)");
  if (a->lateral_only & (1u << 8))
    return cli_bad("--method: the lateral model's (not with --direction vertical)");
  if (a->lateral_only & (1u << (OPT_LINEAR_UNSTABLE - OPT_SPECTRUM)))
    return cli_bad("--linear-when-unstable: the lateral model's (the vertical model has no "
                   "creep and cannot go unstable)");
  if (a->rs.spectrum != a->lateral_default)
    return cli_bad("--spectrum is the lateral track input: with --direction vertical give "
                   "--vertical-spectrum");
  return 0;
}

static int ride_parse(int argc, char **argv, cli_common *c, ride_args *a, const cli_opt *extra,
                      const char *help, int conicity_list)
{
  int dir = cli_direction_scan(argc > 0 ? argv[0] : "ride", argc, argv);
  if (dir < 0) return EXIT_BADINPUT;
  memset(a, 0, sizeof *a);
  rr_vehicle tmp;
  rr_vehicle_default(&tmp);
  ride_setup_default(&a->rs, &tmp);
  vertical_setup_default(&a->vs);
  a->vs.direction = dir;
  a->lateral_default = a->rs.spectrum;
  unsigned reads = CLI_READS_SPEED | CLI_READS_JSON;
  if (dir != CLI_DIR_VERTICAL) reads |= CLI_READS_CONICITY | CLI_READS_GRAVITY;
  int r = conicity_list ? cli_parse_list(argc, argv, c, reads, extra, ride_cb, a, help)
                        : cli_parse(argc, argv, c, reads, extra, ride_cb, a, help);
  if (r) return r;
  if ((r = direction_mismatch(a))) return r;
  ride_setup_points(&a->rs, &c->veh, argc, argv);
  return 0;
}

/* The results of ride: per conicity k and point q, pts[k * np + q] and the PSD
   psd[(k * nf + i) * np + q] on freqs[i]. */
typedef struct ride_results {
  ride_point *pts;
  double *psd, *freqs;
} ride_results;

static void ride_write_psd(FILE *fp, const ride_args *a, const ride_results *rr)
{
  int np = a->rs.npoints, nf = a->rs.nfreq;
  fprintf(fp, "f_hz");
  for (int k = 0; k < a->ncon; k++)
    for (int q = 0; q < np; q++)
      fprintf(fp, ",psd_c%g_x%gm_m2s-4_per_hz", a->conicities[k], a->rs.x[q]);
  fprintf(fp, ",sperling_weight\n");
  for (int i = 0; i < nf; i++) {
    fprintf(fp, "%.10g", rr->freqs[i]);
    for (int k = 0; k < a->ncon; k++)
      for (int q = 0; q < np; q++)
        fprintf(fp, ",%.10g",
                rr->psd[((size_t)k * (size_t)nf + (size_t)i) * (size_t)np + (size_t)q]);
    double b = rr_sperling_filter(rr->freqs[i], RR_AXIS_LATERAL);
    fprintf(fp, ",%.10g\n", b * b);
  }
}

static void ride_json(const cli_common *c, const ride_args *a, const ride_results *rr)
{
  int np = a->rs.npoints;
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "spectrum", a->rs.spectrum);
  cJSON_AddStringToObject(root, "vehicle", c->veh.name);
  cJSON_AddNumberToObject(root, "speed_kmh", c->speed_kmh);
  cJSON_AddStringToObject(root, "conicity_source", c->conicity_source);
  double band[2] = {a->rs.f_lo, a->rs.f_hi};
  cJSON_AddItemToObject(root, "band_hz", cJSON_CreateDoubleArray(band, 2));
  cJSON_AddNumberToObject(root, "nfreq", a->rs.nfreq);
  cJSON_AddNumberToObject(root, "floor_height", a->rs.h_p);
  cJSON_AddItemToObject(root, "methods", ride_methods_json());
  cJSON_AddStringToObject(root, "when_unstable",
                          a->rs.when_unstable == RR_RIDE_LINEAR ? "linear" : "undefined");
  cJSON *res = cJSON_AddArrayToObject(root, "results");
  for (int k = 0; k < a->ncon; k++) {
    cJSON *o = cJSON_CreateObject(), *pa = cJSON_AddArrayToObject(o, "points");
    cJSON_AddNumberToObject(o, "conicity", a->conicities[k]);
    cJSON_AddBoolToObject(o, "stable", rr->pts[k * np].stable == 1);
    cJSON_AddNumberToObject(o, "zeta_max", rr->pts[k * np].zeta_max);
    for (int q = 0; q < np; q++) {
      const ride_point *p = &rr->pts[k * np + q];
      cJSON *po = cJSON_CreateObject();
      cJSON_AddNumberToObject(po, "x", p->x);
      cJSON_AddNumberToObject(po, "rms", p->rms);
      cJSON_AddNumberToObject(po, "sperling", p->sperling);
      cJSON_AddNumberToObject(po, "sperling_gb", p->sperling_gb);
      cJSON_AddNumberToObject(po, "wd_rms", p->wd_rms);
      cJSON_AddNumberToObject(po, "en12299_nmv", p->n_mv);
      cJSON_AddItemToArray(pa, po);
    }
    cJSON_AddItemToArray(res, o);
  }
  cli_json_print(root);
}

static void ride_text(const cli_common *c, const ride_args *a, const ride_results *rr)
{
  int np = a->rs.npoints;
  printf("%s at %g km/h, spectrum %s, band %g-%g Hz (%d points), floor height %g m\n", c->veh.name,
         c->speed_kmh, a->rs.spectrum, a->rs.f_lo, a->rs.f_hi, a->rs.nfreq, a->rs.h_p);
  printf("Sperling: weighting-filter method (W) and GB/T 5599 line method (W_gb); wd_rms: ISO "
         "2631-1 Wd\n");
  printf("%9s %9s %12s %9s %9s %12s  %s\n", "conicity", "x_m", "rms_m/s2", "W", "W_gb",
         "wd_rms_m/s2", "verdict");
  for (int k = 0; k < a->ncon; k++)
    for (int q = 0; q < np; q++) {
      const ride_point *p = &rr->pts[k * np + q];
      char b[4][32];
      printf("%9.4g %9.4g %12s %9s %9s %12s  %s\n", a->conicities[k], p->x,
             ride_num(b[0], 32, 5, p->rms, p->stable),
             ride_num(b[1], 32, 4, p->sperling, p->stable),
             ride_num(b[2], 32, 4, p->sperling_gb, p->stable),
             ride_num(b[3], 32, 5, p->wd_rms, p->stable), p->stable == 0 ? "UNSTABLE" : "stable");
    }
}

/* Every conicity's ride evaluation into rr. */
static int ride_all(const cli_common *c, const ride_args *a, ride_results *rr)
{
  int np = a->rs.npoints, nf = a->rs.nfreq;
  rr->pts = malloc(sizeof(ride_point) * (size_t)(np * a->ncon));
  rr->psd = malloc(sizeof(double) * (size_t)nf * (size_t)np * (size_t)a->ncon);
  rr->freqs = malloc(sizeof(double) * (size_t)nf);
  if (!rr->pts || !rr->psd || !rr->freqs) return cli_bad("out of memory");
  rr_error e;
  for (int k = 0; k < a->ncon; k++) {
    int st = ride_eval(&c->veh, c->speed_kmh, a->conicities[k], &a->rs, rr->pts + k * np,
                       rr->psd + (size_t)k * (size_t)nf * (size_t)np, rr->freqs, &e);
    if (st) return cli_fail(&e, st);
  }
  return 0;
}

int cmd_ride(int argc, char **argv)
{
  static const char help[] =
      "usage: railride ride [VEHICLE] --speed KMH --conicity L[,L2,...] [--spectrum NAME|FILE] "
      "[--json] [--psd FILE.csv]\n"
      "       railride ride [VEHICLE] --speed KMH --direction vertical [--vertical-spectrum S]\n"
      "       railride ride [VEHICLE] --speed KMH --conicity L --direction both\n"
      "Carbody floor lateral acceleration by the pseudo-excitation method (PEM): the track\n"
      "alignment PSD drives each wheelset with its time lag; complex responses over the band,\n"
      "then the one-sided acceleration PSD, RMS, Sperling (filter and GB/T 5599 line methods)\n"
      "and the Wd-weighted RMS at each floor point. The yaw damper SDF, when on, is taken at\n"
      "each frequency (paper mode: real k_sdf(f); physical: complex). --direction vertical\n"
      "runs the vertical model instead (its vertical profile under each wheelset with its\n"
      "delay); both adds EN 12299's mean comfort per point.\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      RIDE_OPTIONS,
      VERTICAL_OPTIONS,
      {"psd", OPT_PSD, "FILE.csv",
       "write f_hz, each (conicity, point) PSD ((m/s^2)^2/Hz) and sperling_weight, the lateral "
       "Sperling weighting |B(f)|^2 applied to the PSDs; vertical: f_hz, the track PSD, each "
       "point's PSD and the weightings |W(f)|^2"},
      CLI_OPT_END};
  cli_common c;
  ride_args a;
  int r = ride_parse(argc, argv, &c, &a, extra, help, 1);
  if (r) return r == CLI_HELP_SHOWN ? 0 : r;
  if (!c.have_speed) return cli_bad("--speed is required");
  if (a.vs.direction == CLI_DIR_VERTICAL) return ride_vertical(&c, &a.rs, &a.vs, 0, a.psd_path);
  if (!c.ncon) return cli_bad("--conicity is required (one value or a comma list)");
  if (a.vs.direction == CLI_DIR_BOTH) {
    if (c.ncon != 1) return cli_bad("--conicity: one value with --direction both");
    return ride_vertical(&c, &a.rs, &a.vs, c.conicities[0], a.psd_path);
  }
  a.ncon = c.ncon;
  memcpy(a.conicities, c.conicities, sizeof(double) * (size_t)c.ncon);
  cli_outfile psd = {0}; /* opened before the run: a folder that cannot be written fails first */
  if (a.psd_path && (r = cli_out_open(&psd, a.psd_path, "--psd"))) return r;
  ride_results rr = {0};
  r = ride_all(&c, &a, &rr);
  if (!r && psd.fp) ride_write_psd(psd.fp, &a, &rr);
  if (!r)
    r = cli_out_commit(&psd);
  else
    cli_out_abort(&psd);
  if (!r && c.json)
    ride_json(&c, &a, &rr);
  else if (!r)
    ride_text(&c, &a, &rr);
  free(rr.pts);
  free(rr.psd);
  free(rr.freqs);
  return r;
}

int cmd_frf(int argc, char **argv)
{
  static const char help[] =
      "usage: railride frf [VEHICLE] --speed KMH --conicity L [--points X,..] [--band LO:HI:N] "
      "[--json]\n"
      "Complex FRF of carbody floor lateral acceleration per unit track alignment at each\n"
      "wheelset (input 1..4, no time lag) and the lagged sum over the four (input 'sum').\n"
      "CSV columns: f_hz,x_m,input,re_per_s2,im_per_s2,magnitude_per_s2,phase_deg ((m/s^2)/m = "
      "1/s^2).\n"
      "--direction vertical: the vertical model's floor vertical acceleration per m of track\n"
      "profile at the leading wheelset, the others delayed (CSV f_hz,x_m,output,re,im,magnitude,\n"
      "phase_deg; JSON f_hz[], points[]{x, re[], im[], abs[]}).\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      FRF_OPTIONS,
      {"direction", OPT_DIRECTION, "D", "lateral (default) or vertical"},
      {"dofs", OPT_DOFS, NULL, "vertical: every coordinate's FRF too (m, rad or m sqrt(kg) per m)"},
      CLI_OPT_END};
  cli_common c;
  ride_args a;
  int r = ride_parse(argc, argv, &c, &a, extra, help, 0);
  if (r) return r == CLI_HELP_SHOWN ? 0 : r;
  if (a.vs.direction == CLI_DIR_BOTH) return cli_bad("frf: --direction lateral or vertical");
  if (a.vs.direction == CLI_DIR_VERTICAL) {
    if (!c.have_speed) return cli_bad("--speed is required");
    return frf_vertical(&c, &a.rs, &a.vs);
  }
  rr_model *m;
  if ((r = cli_model(&c, &m, 1, 1))) return r;
  int np = a.rs.npoints, ni = rr_model_ninputs(m);
  rr_error e;
  rr_ride_plan *rp = NULL;
  rr_ride_opts o = ride_opts(&a.rs);
  int st = rr_ride_plan_new(m, &c.veh, &o, &rp, &e);
  if (!st) st = rr_ride_frf_execute(rp, m, &e);
  if (st) {
    rr_ride_plan_free(rp);
    rr_model_free(m);
    return cli_fail(&e, st);
  }
  const rr_frf_plan *plan = rr_ride_frf(rp);
  const double *f = rr_frf_freqs(plan);
  const double complex *H = rr_frf_H(plan);
  double v = rr_model_speed(m), xin[16];
  for (int i = 0; i < ni; i++) xin[i] = rr_model_input_x(m, i);
  cJSON *root = c.json ? cJSON_CreateObject() : NULL,
        *arr = root ? cJSON_AddArrayToObject(root, "frf") : NULL;
  if (!c.json) printf("f_hz,x_m,input,re_per_s2,im_per_s2,magnitude_per_s2,phase_deg\n");
  for (int k = 0; k < a.rs.nfreq; k++)
    for (int q = 0; q < np; q++)
      for (int i = 0; i <= ni; i++) {
        const double complex *Hq = H + ((size_t)k * (size_t)np + (size_t)q) * (size_t)ni;
        double complex h = i < ni ? Hq[i] : rr_pem_lagged_sum(Hq, xin, ni, 2 * RR_PI * f[k], v);
        char inp[8];
        snprintf(inp, sizeof inp, i < ni ? "%d" : "sum", i + 1);
        if (c.json) {
          cJSON *ob = cJSON_CreateObject();
          cJSON_AddNumberToObject(ob, "f_hz", f[k]);
          cJSON_AddNumberToObject(ob, "x", a.rs.x[q]);
          cJSON_AddStringToObject(ob, "input", inp);
          cJSON_AddNumberToObject(ob, "re", creal(h));
          cJSON_AddNumberToObject(ob, "im", cimag(h));
          cJSON_AddItemToArray(arr, ob);
        } else {
          printf("%.10g,%.6g,%s,%.10g,%.10g,%.10g,%.6f\n", f[k], a.rs.x[q], inp, creal(h), cimag(h),
                 cabs(h), carg(h) * 180 / RR_PI);
        }
      }
  if (root) cli_json_print(root);
  rr_ride_plan_free(rp);
  rr_model_free(m);
  return 0;
}

typedef struct cmp_args {
  ride_args ra;
  double c_from, c_to;
  int c_n, csv;
  const char *plot_data; /* --plot-data FILE: the CSV there too */
  FILE *pd;
} cmp_args;

static int cmp_cb(int opt, const char *arg, void *u)
{
  cmp_args *a = u;
  if (opt == OPT_CMP_PLOTDATA) {
    a->plot_data = arg;
    return cli_file_arg("plot-data", arg) ? 1 : 0;
  }
  if (opt == OPT_CMP_CSV) {
    a->csv = 1;
    return 0;
  }
  if (opt == OPT_CMP_CON) {
    if (cli_range("conicities", arg, "1", &a->c_from, &a->c_to, &a->c_n)) return 1;
    if (!(a->c_from >= 0 && a->c_to >= 0)) return cli_bad("--conicities: must be >= 0");
    return 0;
  }
  return ride_cb(opt, arg, &a->ra);
}

/* One CSV row (an undefined index: an empty cell). */
static void cmp_csv_row(FILE *fp, const char *vehicle, double lam, double zc, double zs, double wc,
                        double ws, double nc, double ns, double fmax)
{
  cli_csv_field(fp, vehicle, ',');
  fprintf(fp, "%.10g,", lam);
  cli_csv_num(fp, zc, ',');
  cli_csv_num(fp, zs, ',');
  cli_csv_num(fp, wc, ','); /* undefined (unstable): an empty cell */
  cli_csv_num(fp, ws, ',');
  cli_csv_num(fp, nc, ',');
  cli_csv_num(fp, ns, ',');
  fprintf(fp, "%.10g\n", fmax);
}

static int compare_one(const rr_vehicle *base, const cli_common *c, const cmp_args *a, int sdf_mode,
                       cJSON *jarr)
{
  rr_vehicle vc = *base, vs = *base;
  vc.sdf_mode = RR_SDF_NONE;
  vs.sdf_mode = sdf_mode;
  rr_error e;
  int st;
  if ((st = rr_vehicle_check(&vs, &e))) return cli_fail(&e, st);
  rr_model *mc = NULL, *ms = NULL;
  rr_modal_ws *wc = NULL, *wsd = NULL;
  st = rr_model_from_vehicle(&vc, &mc, &e);
  if (!st) st = rr_model_from_vehicle(&vs, &ms, &e);
  if (!st) st = rr_modal_ws_new(mc, &wc, &e);
  if (!st) st = rr_modal_ws_new(ms, &wsd, &e);
  if (st) {
    rr_model_free(mc);
    rr_model_free(ms);
    rr_modal_ws_free(wc);
    return cli_fail(&e, st);
  }
  ride_setup rs = a->ra.rs;
  ride_default_points(&rs, base);
  if (!jarr && !a->csv) {
    printf("\n%s: yaw damper series stiffness constant (k = %g MN/m) vs SDF (%s mode, K1 %g Hz, K2 "
           "%g MN/m, K3 %g MN/m)\n",
           base->name, base->yaw_series_stiffness / 1e6,
           sdf_mode == RR_SDF_PAPER ? "paper" : "physical", base->sdf.k1_hz, base->sdf.k2 / 1e6,
           base->sdf.k3 / 1e6);
    printf("at %g km/h, spectrum %s; Sperling W (filter method), max over floor points +L, 0, -L\n",
           c->speed_kmh, rs.spectrum);
    printf("N_MV: EN 12299 mean comfort with the vertical model (tbt3352-vertical), max over the "
           "points\n");
    printf("index band edge: %s\n", cli_band_rule(&c->mo));
    printf("%9s %12s %12s %10s %10s %9s %9s %9s\n", "conicity", "zeta_const", "zeta_sdf", "W_const",
           "W_sdf", "NMV_const", "NMV_sdf", "fmax_hz");
  }
  for (int i = 0; i < a->c_n && !st; i++) {
    double lam = a->c_n == 1 ? a->c_from : a->c_from + (a->c_to - a->c_from) * i / (a->c_n - 1);
    double zc, zs;
    rr_stability sc, ss;
    vertical_both pc[3], ps[3]; /* the lateral ride and EN 12299 with the vertical model */
    vertical_setup vdef;
    vertical_setup_default(&vdef);
    st = rr_model_set_operating(mc, c->speed_kmh / RR_KMH, lam, &e);
    if (!st) st = rr_model_set_operating(ms, c->speed_kmh / RR_KMH, lam, &e);
    if (!st) st = rr_modal_stability(mc, &c->mo, wc, &sc, &e);
    if (!st) st = rr_modal_stability(ms, &c->mo, wsd, &ss, &e);
    if (!st) st = vertical_eval(&vc, c->speed_kmh, &rs, &vdef, lam, pc, &e);
    if (!st) st = vertical_eval(&vs, c->speed_kmh, &rs, &vdef, lam, ps, &e);
    if (st) break;
    zc = sc.index;
    zs = ss.index;
    double wcmax = fmax(pc[0].lat.sperling, fmax(pc[1].lat.sperling, pc[2].lat.sperling));
    double wsmax = fmax(ps[0].lat.sperling, fmax(ps[1].lat.sperling, ps[2].lat.sperling));
    double nc = fmax(pc[0].en.n_mv, fmax(pc[1].en.n_mv, pc[2].en.n_mv));
    double ns = fmax(ps[0].en.n_mv, fmax(ps[1].en.n_mv, ps[2].en.n_mv));
    if (jarr) {
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "vehicle", base->name);
      cJSON_AddNumberToObject(o, "conicity", lam);
      cJSON_AddNumberToObject(o, "stability_index_const", zc);
      cJSON_AddNumberToObject(o, "stability_index_sdf", zs);
      cJSON_AddNumberToObject(o, "sperling_const", wcmax);
      cJSON_AddNumberToObject(o, "sperling_sdf", wsmax);
      cJSON_AddNumberToObject(o, "n_mv_const", nc);
      cJSON_AddNumberToObject(o, "n_mv_sdf", ns);
      cli_band_json(o, &c->mo, sc.fmax_hz);
      cJSON_AddItemToArray(jarr, o);
    } else if (a->csv) {
      cmp_csv_row(stdout, base->name, lam, zc, zs, wcmax, wsmax, nc, ns, sc.fmax_hz);
    } else {
      char b1[32], b2[32], b3[32], b4[32], b5[32], b6[32];
      int uc = pc[0].lat.stable, us = ps[0].lat.stable;
      printf("%9.4f %12s %12s %10s %10s %9s %9s %9.2f\n", lam, cli_num_or_none(b1, sizeof b1, zc),
             cli_num_or_none(b2, sizeof b2, zs), ride_num(b3, 32, 4, wcmax, uc),
             ride_num(b4, 32, 4, wsmax, us), ride_num(b5, 32, 4, nc, uc),
             ride_num(b6, 32, 4, ns, us), sc.fmax_hz);
    }
    if (a->pd) cmp_csv_row(a->pd, base->name, lam, zc, zs, wcmax, wsmax, nc, ns, sc.fmax_hz);
  }
  rr_modal_ws_free(wc);
  rr_modal_ws_free(wsd);
  rr_model_free(mc);
  rr_model_free(ms);
  return st ? cli_fail(&e, st) : 0;
}

int cmd_compare(int argc, char **argv)
{
  static const char help[] =
      "usage: railride compare [VEHICLE] [--speed KMH] [--conicities FROM:TO:N] [--sdf "
      "paper|physical] [--json|--csv]\n"
      "SDF against constant series stiffness of the yaw damper (paper Fig. 12-13): the vehicle\n"
      "stability index and the Sperling index side by side over conicity (default 0.02:0.6:12\n"
      "at 350 km/h). Without VEHICLE: the built-in Type 1 and Type 2, each with its Table 2 "
      "curve.\n"
      "The SDF mode defaults to paper (self-consistent modes; k_sdf(f) in the frequency "
      "domain).\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      RIDE_OPTIONS,
      {"conicities", OPT_CMP_CON, "FROM:TO:N", "conicity grid"},
      {"csv", OPT_CMP_CSV, NULL, "CSV output: " CMP_CSV_COLUMNS},
      {"plot-data", OPT_CMP_PLOTDATA, "FILE", "the same CSV to FILE too (what --plot draws)"},
      CLI_OPT_END};
  cli_common c;
  cmp_args a;
  memset(&a, 0, sizeof a);
  rr_vehicle tmp;
  rr_vehicle_default(&tmp);
  ride_setup_default(&a.ra.rs, &tmp);
  a.c_from = 0.02;
  a.c_to = 0.6;
  a.c_n = 12;
  int r = cli_parse(argc, argv, &c,
                    CLI_READS_SPEED | CLI_READS_JSON | CLI_READS_INDEX | CLI_READS_GRAVITY |
                        CLI_VEHICLE_PAIR,
                    extra, cmp_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (!c.have_speed) c.speed_kmh = 350;
  if (a.csv && c.json) return cli_bad("compare: --json or --csv, not both");
  if (a.csv) printf(CMP_CSV_HEADER);
  cli_outfile pd;
  if (a.plot_data) {
    if ((r = cli_out_open(&pd, a.plot_data, "--plot-data"))) return r;
    a.pd = pd.fp;
    fprintf(a.pd, CMP_CSV_HEADER);
  }
  int mode = c.sdf_override > 0 ? c.sdf_override : RR_SDF_PAPER;
  cJSON *root = c.json ? cJSON_CreateObject() : NULL,
        *arr = root ? cJSON_AddArrayToObject(root, "rows") : NULL;
  if (root) {
    cJSON_AddNumberToObject(root, "speed_kmh", c.speed_kmh);
    cJSON_AddStringToObject(root, "sdf", mode == RR_SDF_PAPER ? "paper" : "physical");
    cJSON_AddStringToObject(root, "sperling_method",
                            "weighting filter, max over floor points +L, 0, -L");
  }
  if (c.vehicle_spec)
    r = compare_one(&c.veh, &c, &a, mode, arr);
  else {
    const char *names[2] = {"type1", "type2"};
    for (int i = 0; i < 2 && !r; i++) {
      rr_vehicle v;
      rr_vehicle_builtin(names[i], &v, NULL);
      if (c.gravity >= 0) v.gravity_stiffness = c.gravity;
      r = compare_one(&v, &c, &a, mode, arr);
    }
  }
  if (a.pd) {
    if (r)
      cli_out_abort(&pd);
    else
      r = cli_out_commit(&pd);
  }
  if (r) {
    cJSON_Delete(root);
    return r;
  }
  if (root) cli_json_print(root);
  return 0;
}
