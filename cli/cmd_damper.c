/* `railride damper`: Maxwell damper characteristics over frequency (paper eq. 5-8, Fig. 2). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

#define DAMPER_NK_MAX 16 /* series stiffnesses in one run (--k K1,K2,..) */
typedef struct damper_args {
  int element; /* 0 yaw, 1 lateral */
  double k[DAMPER_NK_MAX], c;
  int have_k, have_c; /* have_k: how many --k gave */
  double f_from, f_to;
  int n;
} damper_args;
/* The CSV header, printed by the help and the run alike. */
#define DAMPER_COLUMNS                                                                             \
  "freq_hz,k_series_n_per_m,storage_n_per_m,loss_n_per_m,eq_damping_n_s_per_m,dissipation"
enum { OPT_ELEMENT = 2300, OPT_K, OPT_C, OPT_FREQS };

static int damper_cb(int opt, const char *arg, void *u)
{
  damper_args *a = u;
  switch (opt) {
  case OPT_ELEMENT:
    if (!strcmp(arg, "yaw"))
      a->element = 0;
    else if (!strcmp(arg, "lateral"))
      a->element = 1;
    else
      return cli_bad("--element: 'yaw' or 'lateral' expected, got '%s'", arg);
    return 0;
  case OPT_K:
    if (cli_list("k", arg, "N/m", a->k, DAMPER_NK_MAX, &a->have_k)) return 1;
    for (int i = 0; i < a->have_k; i++)
      if (!(a->k[i] > 0)) return cli_bad("--k: must be > 0");
    return 0;
  case OPT_C:
    if (cli_number("c", arg, "N.s/m", &a->c)) return 1;
    if (!(a->c > 0)) return cli_bad("--c: must be > 0");
    a->have_c = 1;
    return 0;
  case OPT_FREQS:
    if (cli_range("freqs", arg, "Hz", &a->f_from, &a->f_to, &a->n)) return 1;
    if (!(a->f_from >= CLI_BAND_LO_MIN && a->f_to >= a->f_from && a->f_to <= CLI_BAND_HI_MAX &&
          a->n <= CLI_BAND_N_MAX))
      return cli_bad("--freqs: need %g <= FROM <= TO <= %g Hz and N <= %d", CLI_BAND_LO_MIN,
                     CLI_BAND_HI_MAX, CLI_BAND_N_MAX);
    return 0;
  }
  return 1;
}

/* One damper's curve over a's grid: the JSON object's keys and points[] into
   o, or the CSV rows on stdout (o NULL). ks: the series stiffness, or the
   vehicle's SDF curve (sdf). Returns 0 or EXIT_FAIL after the message. */
static int damper_curve(const rr_vehicle *veh, const damper_args *a, double k, double cd, int sdf,
                        cJSON *o)
{
  cJSON *arr = NULL;
  if (o) {
    cJSON_AddNumberToObject(o, "k", k);
    cJSON_AddNumberToObject(o, "c", cd);
    cJSON_AddNumberToObject(o, "omega_opt", rr_maxwell_omega_opt(k, cd));
    cJSON_AddNumberToObject(o, "f_opt_hz", rr_maxwell_omega_opt(k, cd) / (2 * RR_PI));
    cJSON_AddBoolToObject(o, "sdf", sdf);
    arr = cJSON_AddArrayToObject(o, "points");
  }
  for (int i = 0; i < a->n; i++) {
    double f = a->n == 1 ? a->f_from : a->f_from * pow(a->f_to / a->f_from, (double)i / (a->n - 1));
    double w = 2 * RR_PI * f;
    double complex ks = sdf ? rr_sdf_series_k(&veh->sdf, veh->sdf_mode, I * w) : k;
    double complex ke = rr_maxwell_stiffness(ks, cd, I * w);
    double st = creal(ke), lo = cimag(ke);
    if (!(isfinite(st) && isfinite(lo) && isfinite(lo / w) && isfinite(lo / st) && st > 0)) {
      fprintf(stderr, /* a non-finite result is an error, never a number */
              "railride: damper: the characteristics are not finite at %g Hz (k = %g N/m, c = %g "
              "N s/m: storage %g N/m)\n",
              f, creal(ks), cd, st);
      return EXIT_FAIL;
    }
    if (o) {
      cJSON *p = cJSON_CreateObject();
      cJSON_AddNumberToObject(p, "freq_hz", f);
      cJSON_AddNumberToObject(p, "k_series", creal(ks));
      cJSON_AddNumberToObject(p, "storage", st);
      cJSON_AddNumberToObject(p, "loss", lo);
      cJSON_AddNumberToObject(p, "eq_damping", lo / w);
      cJSON_AddNumberToObject(p, "dissipation", lo / st);
      cJSON_AddItemToArray(arr, p);
    } else {
      printf("%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", f, creal(ks), st, lo, lo / w, lo / st);
    }
  }
  return 0;
}

int cmd_damper(int argc, char **argv)
{
  static const char help[] =
      "usage: railride damper [VEHICLE] [--element yaw|lateral] [--k N/M] [--c NS/M] [--freqs "
      "FROM:TO:N] [--json]\n"
      "Dynamic stiffness k_e = k c jw / (k + c jw) of a damper c in series with a spring k\n"
      "(with the vehicle's SDF curve for the yaw damper when sdf is on): storage (equivalent\n"
      "stiffness), loss, equivalent damping loss/w, dissipation factor loss/storage, over\n"
      "log-spaced frequencies (default 0.1:30:200 Hz); omega_opt = k/c maximises the loss.\n"
      "CSV columns: " DAMPER_COLUMNS "\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"element", OPT_ELEMENT, "E", "yaw (default) or lateral damper of the vehicle"},
      {"k", OPT_K, "N/M[,N/M..]",
       "override the series stiffness, N/m; a list gives one curve each (rows in turn, CSV;"
       " JSON curves[]), at most " RR_STR(DAMPER_NK_MAX)},
      {"c", OPT_C, "NS/M", "override the damping, N s/m"},
      {"freqs", OPT_FREQS, "FROM:TO:N", "frequency grid, Hz"},
      CLI_OPT_END};
  cli_common c;
  damper_args a = {.f_from = 0.1, .f_to = 30, .n = 200};
  int r = cli_parse(argc, argv, &c, CLI_READS_JSON, extra, damper_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  double kv = a.element == 0 ? c.veh.yaw_series_stiffness : c.veh.lateral_series_stiffness;
  double cd = a.element == 0 ? c.veh.yaw_damping : c.veh.lateral_damping;
  int sdf = a.element == 0 && c.veh.sdf_mode != RR_SDF_NONE && !a.have_k;
  int nk = a.have_k ? a.have_k : 1;
  const double *ks = a.have_k ? a.k : &kv;
  if (a.have_c) cd = a.c;
  if (!(cd > 0)) return cli_bad("damping is 0: no damper characteristics");
  rr_error e; /* --k, --c within the physical range of the element's keys */
  const char *kk =
                 a.element == 0 ? "yaw_damper.series_stiffness" : "lateral_damper.series_stiffness",
             *kc = a.element == 0 ? "yaw_damper.damping" : "lateral_damper.damping";
  for (int i = 0; i < a.have_k; i++)
    if (rr_vehicle_key_check(rr_vehicle_key_find(kk), ks[i], &e)) return cli_bad("--k: %s", e.msg);
  if (a.have_c && rr_vehicle_key_check(rr_vehicle_key_find(kc), cd, &e))
    return cli_bad("--c: %s", e.msg);
  cJSON *root = c.json ? cJSON_CreateObject() : NULL;
  cJSON *curves = root && nk > 1 ? cJSON_AddArrayToObject(root, "curves") : NULL;
  if (!root) printf("%s\n", DAMPER_COLUMNS);
  for (int i = 0; i < nk && !r; i++) {
    if (!root) /* the CSV stays plain (pandas.read_csv): the summary goes to stderr */
      fprintf(stderr,
              "railride: %s %s damper: c = %g N s/m, k = %g N/m%s; omega_opt = k/c = %g rad/s "
              "(%g Hz)\n",
              c.veh.name, a.element == 0 ? "yaw" : "lateral", cd, ks[i],
              sdf ? " (SDF curve applies)" : "", ks[i] / cd, ks[i] / cd / (2 * RR_PI));
    cJSON *o = curves ? cJSON_CreateObject() : root;
    if (curves) cJSON_AddItemToArray(curves, o);
    r = damper_curve(&c.veh, &a, ks[i], cd, sdf, o);
  }
  if (root && !r) cli_json_print(root);
  if (root && r) cJSON_Delete(root);
  return r;
}
