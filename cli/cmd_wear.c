#define _POSIX_C_SOURCE 200809L
/* `railride wear`: the paper's robust-design question asked of real
 * profiles: for each wheel profile (design and measured wear stages, in
 * order) on the vehicle's rail, the equivalent conicity at 3 mm and its
 * function, the stability index and verdict at the operating point, the
 * linear critical speed and the Sperling index at the floor points; with
 * --nonlinear, the nonlinear vehicle on the profiles' contact functions: its
 * Hopf point, the scan's hunting speeds and the bifurcation's kind. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "outfile.h"
#include "plot.h"

#define WEAR_MAX 32
#define WEAR_VMAX_KMH RR_CRITICAL_V_MAX_KMH /* rr_critical_speed's default upper end */
#define WEAR_NAMP 14                        /* the conicity function at 1.0, 1.5 .. 7.5 mm */
#define WEAR_NL_V0_KMH 100 /* --nonlinear: the scan's speeds, from here to WEAR_VMAX_KMH */
#define WEAR_NL_STEP_KMH 25
#define WEAR_NL_RANGE                                                                              \
  RR_STR(WEAR_NL_V0_KMH) "-" RR_STR(WEAR_VMAX_KMH) " km/h (" RR_STR(WEAR_NL_STEP_KMH) " km/h"
#define WEAR_NL_NV 21
#define WEAR_NL_SETTLE_S                                                                           \
  10 /* s of transient at each speed (each starts on the last one's motion) */

static void wear_amplitudes(double amp_mm[WEAR_NAMP])
{
  for (int k = 0; k < WEAR_NAMP; k++) amp_mm[k] = 1.0 + 0.5 * k;
}

typedef struct wear_args {
  const char *wheels, *rail, *plot_data;
  int csv, nonlinear;
} wear_args;
enum { OPT_WHEELS = 6100, OPT_WRAIL, OPT_WCSV, OPT_WPLOTDATA, OPT_WNONLINEAR };

static int wear_cb(int opt, const char *arg, void *u)
{
  wear_args *a = u;
  if (opt == OPT_WHEELS) a->wheels = arg;
  if (opt == OPT_WRAIL) a->rail = arg;
  if (opt == OPT_WCSV) a->csv = 1;
  if (opt == OPT_WPLOTDATA) a->plot_data = arg;
  if (opt == OPT_WNONLINEAR) a->nonlinear = 1;
  return opt >= OPT_WHEELS && opt <= OPT_WNONLINEAR ? 0 : 1;
}

typedef struct wear_row {
  char wheel[RR_PROFILE_PATH_MAX];
  double tg3, tg[WEAR_NAMP];
  rr_stability s;
  rr_critical cr;
  ride_point rp[3];
  /* --nonlinear: the Hopf point of the vehicle on the contact functions, the
     scan's first speed with a cycle on the way up and its lowest on the way
     down (NaN: none up to 600 km/h), and the kind they show */
  double hopf_kmh, hopf_hz, onset_kmh, lowest_kmh;
  const char *kind;
} wear_row;

/* How the cycles meet the equilibrium: below the speed where it loses
   stability (the Hopf point, or the scan's onset) by more than a step:
   subcritical (hysteresis); else supercritical; none without a cycle. */
static const char *wear_kind(const wear_row *w)
{
  if (isnan(w->lowest_kmh)) return "none up to " RR_STR(WEAR_VMAX_KMH) " km/h";
  double onset = fmin(isnan(w->onset_kmh) ? INFINITY : w->onset_kmh, w->hopf_kmh);
  return w->lowest_kmh < onset - 0.5 * WEAR_NL_STEP_KMH ? "subcritical" : "supercritical";
}

/* The nonlinear vehicle on v's profiles: the Hopf point and the scan. */
static int wear_nonlinear(const rr_vehicle *v, wear_row *w)
{
  rr_error e;
  rr_bifurcation b;
  double vs[WEAR_NL_NV];
  rr_scan_point up[WEAR_NL_NV], down[WEAR_NL_NV];
  for (int k = 0; k < WEAR_NL_NV; k++) vs[k] = (WEAR_NL_V0_KMH + WEAR_NL_STEP_KMH * k) / RR_KMH;
  int st = rr_bifurcation_hopf(v, NULL, NULL, &b, &e);
  rr_scan_opts so = rr_scan_opts_default();
  so.settle_s = WEAR_NL_SETTLE_S;
  if (!st) st = rr_bifurcation_scan(v, NULL, NULL, vs, WEAR_NL_NV, &so, up, down, &e);
  if (st) return cli_fail(&e, st);
  w->hopf_kmh = b.hopf ? b.hopf_speed_ms * RR_KMH : NAN;
  w->hopf_hz = b.hopf ? b.hopf_freq_hz : NAN;
  w->onset_kmh = w->lowest_kmh = NAN;
  for (int k = 0; k < WEAR_NL_NV; k++) {
    if (isnan(w->onset_kmh) && up[k].amplitude_m > 0) w->onset_kmh = vs[k] * RR_KMH;
    if (isnan(w->lowest_kmh) && down[k].amplitude_m > 0) w->lowest_kmh = vs[k] * RR_KMH;
  }
  if (!(w->lowest_kmh <=
        w->onset_kmh)) /* a small cycle near onset can read as dying on the way down */
    w->lowest_kmh = isnan(w->onset_kmh) ? w->lowest_kmh : w->onset_kmh;
  w->kind = wear_kind(w);
  return 0;
}

/* One profile: its conicity, then the linear vehicle at it. */
static int wear_one(const cli_common *c, const wear_args *a, const char *wheel, wear_row *w)
{
  rr_vehicle v = c->veh;
  snprintf(w->wheel, sizeof w->wheel, "%s", wheel);
  if (!a->rail && !v.wheel_rail.rail[0][0])
    return cli_bad("wear: a rail is needed (--rail, or [contact] rail)");
  rr_error e;
  if (rr_vehicle_set_profiles(&v, wheel, a->rail, &e)) return cli_bad("--wheels: %s", e.msg);
  double amps[WEAR_NAMP];
  wear_amplitudes(amps);
  rr_model *m = NULL;
  rr_modal_ws *ws = NULL;
  int st = rr_vehicle_profile_conicity(&v, &w->tg3, NULL, 0, &e);
  if (!st) st = rr_vehicle_profile_conicity_function(&v, amps, WEAR_NAMP, w->tg, &e);
  if (!st) st = rr_model_from_vehicle(&v, &m, &e);
  if (!st) st = rr_modal_ws_new(m, &ws, &e);
  if (!st) st = rr_model_set_operating(m, c->speed_kmh / RR_KMH, w->tg3, &e);
  if (!st) st = rr_modal_stability(m, &c->mo, ws, &w->s, &e);
  if (!st) st = rr_critical_speed(m, w->tg3, &c->mo, NULL, ws, &w->cr, &e);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (st) return cli_fail(&e, st);
  ride_setup rs;
  ride_setup_default(&rs, &v);
  if ((st = ride_eval(&v, c->speed_kmh, w->tg3, &rs, w->rp, NULL, NULL, &e)))
    return cli_fail(&e, st);
  return a->nonlinear ? wear_nonlinear(&v, w) : 0;
}

/* A profile's file name without its folder, as a plot label. */
static const char *base_name(const char *path)
{
  const char *b = strrchr(path, '/');
  return b ? b + 1 : path;
}

static void wear_text(const cli_common *c, const wear_row *w, int n, int nonlinear)
{
  char b1[32], b2[32];
  printf("%s at %g km/h: wheel profiles on their rail (tan gamma_e by EN 15302 at 3 mm; the "
         "index's band edge %s at each profile's conicity)\n",
         c->veh.name, c->speed_kmh, cli_band_rule(&c->mo));
  printf("  %-28s %9s %10s %-9s %13s %8s %8s %8s\n", "wheel", "tan_ge_3", "index", "verdict",
         "critical_kmh", "W(+L)", "W(0)", "W(-L)");
  for (int i = 0; i < n; i++) {
    char bw[3][32];
    printf("  %-28s %9.5f %10s %-9s %13s %8s %8s %8s\n", base_name(w[i].wheel), w[i].tg3,
           cli_num_or_none(b1, sizeof b1, w[i].s.index),
           rr_modal_stable(w[i].s.zeta_max) ? "stable" : "UNSTABLE",
           w[i].cr.found ? (snprintf(b2, sizeof b2, "%.3f", w[i].cr.speed_ms * RR_KMH), b2)
                         : "> " RR_STR(WEAR_VMAX_KMH),
           ride_num(bw[0], 32, 3, w[i].rp[0].sperling, w[i].rp[0].stable),
           ride_num(bw[1], 32, 3, w[i].rp[1].sperling, w[i].rp[1].stable),
           ride_num(bw[2], 32, 3, w[i].rp[2].sperling, w[i].rp[2].stable));
  }
  if (!nonlinear) return;
  printf(
      "nonlinear vehicle on the profiles' contact functions (scan %d..%d km/h, %d km/h steps):\n",
      WEAR_NL_V0_KMH, WEAR_VMAX_KMH, WEAR_NL_STEP_KMH);
  printf("  %-28s %10s %8s %10s %11s  %s\n", "wheel", "hopf_kmh", "hopf_hz", "onset_kmh",
         "lowest_kmh", "bifurcation");
  for (int i = 0; i < n; i++) {
    char b[4][32];
    double x[4] = {w[i].hopf_kmh, w[i].hopf_hz, w[i].onset_kmh, w[i].lowest_kmh};
    for (int k = 0; k < 4; k++)
      snprintf(b[k], sizeof b[k], isfinite(x[k]) ? (k == 1 ? "%.3f" : "%.1f") : "none", x[k]);
    printf("  %-28s %10s %8s %10s %11s  %s\n", base_name(w[i].wheel), b[0], b[1], b[2], b[3],
           w[i].kind);
  }
}

static void wear_csv(const wear_row *w, int n, int nonlinear)
{
  printf("wheel,tan_gamma_e_3mm,stability_index,zeta_max,stable,critical_speed_kmh,"
         "sperling_front,sperling_centre,sperling_rear,fmax_hz%s\n",
         nonlinear ? ",hopf_speed_kmh,hopf_freq_hz,onset_kmh,nonlinear_critical_kmh,bifurcation"
                   : "");
  for (int i = 0; i < n; i++) {
    cli_csv_field(stdout, w[i].wheel, ',');
    printf("%.10g,", w[i].tg3);
    cli_csv_num(stdout, w[i].s.index, ',');
    printf("%.10g,%d,", w[i].s.zeta_max, rr_modal_stable(w[i].s.zeta_max));
    cli_csv_num(stdout, w[i].cr.found ? w[i].cr.speed_ms * RR_KMH : NAN, ',');
    cli_csv_num(stdout, w[i].rp[0].sperling, ',');
    cli_csv_num(stdout, w[i].rp[1].sperling, ',');
    cli_csv_num(stdout, w[i].rp[2].sperling, ',');
    printf("%.10g", w[i].s.fmax_hz);
    if (nonlinear) {
      double x[4] = {w[i].hopf_kmh, w[i].hopf_hz, w[i].onset_kmh, w[i].lowest_kmh};
      for (int k = 0; k < 4; k++) isfinite(x[k]) ? printf(",%.10g", x[k]) : printf(",");
      printf(",%s", w[i].kind);
    }
    putchar('\n');
  }
}

/* The nonlinear results of a row, as JSON. */
static cJSON *wear_nonlinear_json(const wear_row *w)
{
  cJSON *o = cJSON_CreateObject();
  const char *keys[4] = {"hopf_speed_kmh", "hopf_freq_hz", "onset_kmh", "nonlinear_critical_kmh"};
  double x[4] = {w->hopf_kmh, w->hopf_hz, w->onset_kmh, w->lowest_kmh};
  for (int k = 0; k < 4; k++)
    cJSON_AddItemToObject(o, keys[k],
                          isfinite(x[k]) ? cJSON_CreateNumber(x[k]) : cJSON_CreateNull());
  cJSON_AddStringToObject(o, "bifurcation", w->kind);
  cJSON_AddStringToObject(o, "method",
                          "contact functions (dr, contact angles); Hopf from the linearisation "
                          "at rest; scan up and down in speed by direct integration");
  return o;
}

static void wear_json(const cli_common *c, const wear_row *w, int n, int nonlinear)
{
  cJSON *root = cJSON_CreateObject(), *arr = cJSON_AddArrayToObject(root, "profiles");
  cJSON_AddStringToObject(root, "vehicle", c->veh.name);
  cJSON_AddNumberToObject(root, "speed_kmh", c->speed_kmh);
  double amps[WEAR_NAMP];
  wear_amplitudes(amps);
  cJSON_AddItemToObject(root, "amplitude_mm", cJSON_CreateDoubleArray(amps, WEAR_NAMP));
  for (int i = 0; i < n; i++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "wheel", w[i].wheel);
    cJSON_AddNumberToObject(o, "tan_gamma_e_3mm", w[i].tg3);
    cJSON_AddItemToObject(o, "tan_gamma_e", cJSON_CreateDoubleArray(w[i].tg, WEAR_NAMP));
    cJSON_AddNumberToObject(o, "stability_index", w[i].s.index);
    cJSON_AddStringToObject(o, "index_source", cli_index_source_key(w[i].s.source));
    cJSON_AddNumberToObject(o, "zeta_max", w[i].s.zeta_max);
    cJSON_AddBoolToObject(o, "stable", rr_modal_stable(w[i].s.zeta_max));
    cli_band_json(o, &c->mo, w[i].s.fmax_hz);
    if (w[i].cr.found)
      cJSON_AddNumberToObject(o, "critical_speed_kmh", w[i].cr.speed_ms * RR_KMH);
    else
      cJSON_AddNullToObject(o, "critical_speed_kmh");
    double sp[3] = {w[i].rp[0].sperling, w[i].rp[1].sperling, w[i].rp[2].sperling};
    cJSON_AddItemToObject(o, "sperling", cJSON_CreateDoubleArray(sp, 3));
    if (nonlinear) cJSON_AddItemToObject(o, "nonlinear", wear_nonlinear_json(&w[i]));
    cJSON_AddItemToArray(arr, o);
  }
  cli_json_print(root);
}

/* What --plot draws, as gnuplot data blocks: index 0 the conicity
   functions (amplitude, then one column per profile), index 1 one row per
   profile (number, tan gamma_e at 3 mm, index, critical speed, Sperling
   +L 0 -L, the search's upper end where none was found); '# profile k:'
   comments give the labels. */
static int wear_plot_data(const cli_common *c, const wear_row *w, int n, const char *path)
{
  cli_outfile out;
  int rc = cli_out_open(&out, path, "--plot-data");
  if (rc) return rc;
  FILE *fp = out.fp;
  double amps[WEAR_NAMP];
  wear_amplitudes(amps);
  fprintf(fp, "# %s at %g km/h: wheel profiles on their rail\n", c->veh.name, c->speed_kmh);
  for (int i = 0; i < n; i++) { /* a control character would end the comment */
    fprintf(fp, "# profile %d: ", i + 1);
    for (const char *q = base_name(w[i].wheel); *q; q++)
      fputc((unsigned char)*q < 32 ? '?' : *q, fp);
    fputc('\n', fp);
  }
  for (int k = 0; k < WEAR_NAMP; k++) {
    fprintf(fp, "%.6g", amps[k]);
    for (int i = 0; i < n; i++) fprintf(fp, " %.8g", w[i].tg[k]);
    fputc('\n', fp);
  }
  fputs("\n\n", fp);
  for (int i = 0; i < n; i++)
    fprintf(fp, "%d %.8g %.8g %.8g %.6g %.6g %.6g %g\n", i + 1, w[i].tg3, w[i].s.index,
            w[i].cr.found ? w[i].cr.speed_ms * RR_KMH : NAN, w[i].rp[0].sperling,
            w[i].rp[1].sperling, w[i].rp[2].sperling, w[i].cr.found ? NAN : (double)WEAR_VMAX_KMH);
  return cli_out_commit(&out);
}

int cmd_wear(int argc, char **argv)
{
  static const char help[] =
      "usage: railride wear [VEHICLE] --wheels P1,P2,... [--rail R] [--speed KMH] [--nonlinear]\n"
      "                     [--json|--csv]\n"
      "The paper's robust-design question asked of real profiles: for each wheel profile\n"
      "(design and measured wear stages, in order) on the rail (--rail, or the vehicle file's\n"
      "[contact] rail, with its placement keys), the equivalent conicity at 3 mm and its\n"
      "function (1.0-7.5 mm, JSON), the stability index and verdict at the speed (default\n"
      "350 km/h), the linear critical speed (" CLI_CRITICAL_RANGE
      ", any mode) and the Sperling index at\n"
      "the floor points +L, 0, -L (PEM, the Wuhan-Guangzhou alignment).\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"wheels", OPT_WHEELS, "P1,P2,..", "wheel profile files (lateral vertical, mm), at most 32"},
      {"rail", OPT_WRAIL, "R", "the rail profile file"},
      {"csv", OPT_WCSV, NULL, "CSV output"},
      {"nonlinear", OPT_WNONLINEAR, NULL,
       "also the nonlinear vehicle on each profile's contact functions (dr(y), contact angles): "
       "its Hopf point, the speeds with hunting cycles scanning up and down " WEAR_NL_RANGE
       " steps, 10 s to settle each) and the bifurcation's kind (subcritical: cycles below the "
       "speed where rest loses stability); slow: seconds a profile"},
      {"plot-data", OPT_WPLOTDATA, "FILE",
       "write what --plot draws (gnuplot data: the conicity functions, then a row per profile)"},
      CLI_OPT_END};
  cli_common c;
  wear_args a = {0};
  int r = cli_parse(argc, argv, &c, CLI_READS_SPEED | CLI_READS_JSON | CLI_READS_INDEX, extra,
                    wear_cb, &a, help);
  if (r) return r == CLI_HELP_SHOWN ? 0 : r;
  if (!a.wheels) return cli_bad("wear: --wheels is required");
  if (a.csv && c.json) return cli_bad("wear: --json or --csv, not both");
  if (!c.have_speed) c.speed_kmh = CLI_SPEED_DEFAULT_KMH;
  wear_row *rows = calloc(WEAR_MAX, sizeof *rows);
  char list[WEAR_MAX * 256];
  if (!rows) return cli_bad("out of memory");
  if (snprintf(list, sizeof list, "%s", a.wheels) >= (int)sizeof list)
    r = cli_bad("--wheels: too long");
  int n = 0;
  char *sv = NULL;
  for (char *t = r ? NULL : strtok_r(list, ",", &sv); t && !r; t = strtok_r(NULL, ",", &sv)) {
    if (n == WEAR_MAX) r = cli_bad("--wheels: at most %d profiles", WEAR_MAX);
    if (!r) r = wear_one(&c, &a, t, &rows[n++]);
  }
  if (!r && a.plot_data) r = wear_plot_data(&c, rows, n, a.plot_data);
  if (!r && c.json)
    wear_json(&c, rows, n, a.nonlinear);
  else if (!r && a.csv)
    wear_csv(rows, n, a.nonlinear);
  else if (!r)
    wear_text(&c, rows, n, a.nonlinear);
  free(rows);
  return r;
}
