/* Stability commands: matrices, modes, robust, critical-speed, locus, map. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

#define RUN_PARSE(extra, cb, user, help) do { \
    int r_ = cli_parse(argc, argv, &c, extra, cb, user, help); \
    if (r_ == CLI_HELP_SHOWN) return 0; \
    if (r_) return r_; } while (0)

static const char *energy_names[RR_NGROUPS] = {"carbody", "frames", "wheelsets"};

int cmd_matrices(int argc, char **argv)
{
  static const char help[] = "usage: railride matrices [VEHICLE] --speed KMH --conicity L [--json]\n"
                             "Prints M, C, K (17x17), B (17x4), the Maxwell elements and the state matrix A.\n"
                             "In paper SDF mode A is taken at the curve's lowest stiffness.\n" CLI_COMMON_HELP;
  cli_common c;
  rr_model *m;
  RUN_PARSE(NULL, NULL, NULL, help);
  int r = cli_model(&c, &m, 1, 1);
  if (r) return r;
  int n = rr_model_ndof(m), ni = rr_model_ninputs(m), N = rr_model_state_size(m);
  double *A = malloc(sizeof(double) * (size_t)N * N);
  rr_error e;
  if (!A) { rr_model_free(m); return cli_bad("out of memory"); }
  int st = rr_model_state_matrix(m, 0, A, &e);
  if (st) { free(A); rr_model_free(m); return cli_fail(&e, st); }
  if (c.json) {
    cJSON *root = cJSON_CreateObject(), *dofs = cJSON_AddArrayToObject(root, "dofs");
    for (int i = 0; i < n; i++) cJSON_AddItemToArray(dofs, cJSON_CreateString(rr_model_dof_name(m, i)));
    cJSON_AddNumberToObject(root, "speed_kmh", c.speed_kmh);
    cJSON_AddNumberToObject(root, "conicity", c.conicity);
    cJSON_AddItemToObject(root, "M", cli_json_matrix(rr_model_M(m), n, n));
    cJSON_AddItemToObject(root, "C", cli_json_matrix(rr_model_C(m), n, n));
    cJSON_AddItemToObject(root, "K", cli_json_matrix(rr_model_K(m), n, n));
    cJSON_AddItemToObject(root, "B", cli_json_matrix(rr_model_B(m), n, ni));
    cJSON *mx = cJSON_AddArrayToObject(root, "maxwell");
    for (int i = 0; i < rr_model_nmaxwell(m); i++) {
      rr_maxwell_info info;
      rr_model_maxwell(m, i, &info);
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "name", info.name);
      cJSON_AddItemToObject(o, "J", cJSON_CreateDoubleArray(info.J, n));
      cJSON_AddNumberToObject(o, "k", info.k);
      cJSON_AddNumberToObject(o, "c", info.c);
      cJSON_AddBoolToObject(o, "sdf", info.sdf);
      cJSON_AddItemToArray(mx, o);
    }
    cJSON_AddItemToObject(root, "A", cli_json_matrix(A, N, N));
    cli_json_print(root);
  } else {
    const char *names[4] = {"M", "C", "K", "B"};
    const double *mats[4] = {rr_model_M(m), rr_model_C(m), rr_model_K(m), rr_model_B(m)};
    for (int k = 0; k < 4; k++) {
      int cols = k == 3 ? ni : n;
      printf("%s (%d x %d), rows/columns: ", names[k], n, cols);
      for (int i = 0; i < n; i++) printf("%s%s", rr_model_dof_name(m, i), i + 1 < n ? " " : "\n");
      for (int i = 0; i < n; i++) {
        for (int j = 0; j < cols; j++) printf(" %12.5g", mats[k][i * cols + j]);
        printf("\n");
      }
      printf("\n");
    }
    printf("Maxwell elements (state order):\n");
    for (int i = 0; i < rr_model_nmaxwell(m); i++) {
      rr_maxwell_info info;
      rr_model_maxwell(m, i, &info);
      printf("  %-24s k = %.6g N/m  c = %.6g N s/m%s\n", info.name, info.k, info.c, info.sdf ? "  (SDF)" : "");
    }
    printf("State matrix A: %d x %d (use --json for its entries)\n", N, N);
  }
  free(A);
  rr_model_free(m);
  return 0;
}

static cJSON *mode_json(const rr_mode *md, int paper)
{
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "freq_hz", md->freq_hz);
  cJSON_AddNumberToObject(o, "real", md->re);
  cJSON_AddNumberToObject(o, "imag", md->im);
  cJSON_AddNumberToObject(o, "stability_index", md->zeta);
  cJSON *en = cJSON_AddObjectToObject(o, "energy");
  for (int g = 0; g < RR_NGROUPS; g++) cJSON_AddNumberToObject(en, energy_names[g], md->energy[g]);
  cJSON_AddBoolToObject(o, "oscillatory", md->oscillatory);
  cJSON_AddBoolToObject(o, "hunting", md->hunting);
  cJSON_AddBoolToObject(o, "in_index", md->in_index);
  if (paper) {
    cJSON_AddBoolToObject(o, "self_consistent", md->self_consistent);
    cJSON_AddNumberToObject(o, "sdf_k", md->sdf_k);
  }
  return o;
}

/* Solves the modes of a model; caller frees res. */
static int solve_modes(rr_model *m, const rr_modal_opts *mo, rr_modal_result *res)
{
  rr_error e;
  rr_modal_ws *ws;
  int st = rr_modal_ws_new(m, &ws, &e);
  if (!st) st = rr_modal_result_alloc(m, res, &e);
  if (!st) st = rr_modal_solve(m, mo, ws, res, &e);
  rr_modal_ws_free(ws);
  return st ? cli_fail(&e, st) : 0;
}

int cmd_modes(int argc, char **argv)
{
  static const char help[] = "usage: railride modes [VEHICLE] --speed KMH --conicity L [--fmax HZ] [--json]\n"
                             "Eigenvalues of the state matrix: frequency, stability index zeta = Re/|lambda|\n"
                             "(negative is stable), kinetic-energy shares; the vehicle stability index is the\n"
                             "largest zeta over hunting-related modes (wheelset share >= wmin) below fmax.\n" CLI_COMMON_HELP;
  cli_common c;
  rr_model *m;
  RUN_PARSE(NULL, NULL, NULL, help);
  int r = cli_model(&c, &m, 1, 1);
  if (r) return r;
  rr_modal_result res;
  if ((r = solve_modes(m, &c.mo, &res))) { rr_model_free(m); return r; }
  int paper = c.veh.sdf_mode == RR_SDF_PAPER;
  if (c.json) {
    cJSON *root = cJSON_CreateObject();
    if (res.index_mode >= 0) cJSON_AddNumberToObject(root, "stability_index", res.stability_index);
    else cJSON_AddNullToObject(root, "stability_index");
    cJSON_AddNumberToObject(root, "speed_kmh", c.speed_kmh);
    cJSON_AddNumberToObject(root, "conicity", c.conicity);
    cJSON_AddNumberToObject(root, "fmax_hz", c.mo.fmax_hz);
    cJSON_AddNumberToObject(root, "w_min", c.mo.w_min);
    cJSON *arr = cJSON_AddArrayToObject(root, "modes");
    for (int i = 0; i < res.n; i++)
      if (res.modes[i].im > 0) cJSON_AddItemToArray(arr, mode_json(&res.modes[i], paper));
    cli_json_print(root);
  } else {
    printf("%s at %.6g km/h, conicity %.6g%s\n", c.veh.name, c.speed_kmh, c.conicity,
           paper ? " (SDF paper mode: self-consistent modes)" : c.veh.sdf_mode == RR_SDF_PHYSICAL ? " (SDF physical mode)" : "");
    printf("%10s %12s %12s %10s %9s %9s %9s  %s\n", "freq_hz", "real", "imag", "zeta", "E_car", "E_frame", "E_wheel", "flags");
    for (int i = 0; i < res.n; i++) {
      const rr_mode *md = &res.modes[i];
      if (md->im <= 0) continue;
      printf("%10.4f %12.5g %12.5g %10.5f %9.2e %9.2e %9.2e  %s%s%s\n", md->freq_hz, md->re, md->im, md->zeta,
             md->energy[0], md->energy[1], md->energy[2], md->in_index ? "index " : "",
             md->hunting ? "hunting" : "", md->self_consistent ? "" : " not-self-consistent");
    }
    if (res.index_mode >= 0)
      printf("vehicle stability index: %.6f (mode at %.4f Hz)\n", res.stability_index, res.modes[res.index_mode].freq_hz);
    else
      printf("vehicle stability index: none (no hunting-related oscillatory mode below %g Hz)\n", c.mo.fmax_hz);
  }
  rr_modal_result_free(&res);
  rr_model_free(m);
  return 0;
}

typedef struct robust_args { rr_robust_opts ro; } robust_args;
enum { OPT_NCON = 2000 };

static int robust_cb(int opt, const char *arg, void *u)
{
  robust_args *a = u;
  if (opt == OPT_NCON) {
    char *end;
    long k = strtol(arg, &end, 10);
    if (*end || k < 1 || k > 10000) return cli_bad("--n-conicity: whole number >= 1 expected, got '%s'", arg);
    a->ro.n_conicity = (int)k;
    return 0;
  }
  return 1;
}

int cmd_robust(int argc, char **argv)
{
  static const char help[] = "usage: railride robust [VEHICLE] [--n-conicity N] [--json]\n"
                             "Robust stability indices (paper Table 1): zeta_low at 250 km/h, conicity 0.05;\n"
                             "zeta_high at 350 km/h, 0.40; std_zeta: population standard deviation of the index\n"
                             "at 350 km/h over N (default 8) conicities from 0.05 to 0.40.\n" CLI_COMMON_HELP
                             "  --n-conicity N       number of conicities for std_zeta\n";
  static const struct option extra[] = {{"n-conicity", required_argument, 0, OPT_NCON}, {0, 0, 0, 0}};
  cli_common c;
  robust_args a = {rr_robust_opts_default()};
  RUN_PARSE(extra, robust_cb, &a, help);
  rr_model *m;
  int r = cli_model(&c, &m, 0, 0);
  if (r) return r;
  rr_error e;
  rr_modal_ws *ws;
  rr_robust rb;
  int st = rr_modal_ws_new(m, &ws, &e);
  if (!st) st = rr_robust_indices(m, &c.mo, &a.ro, ws, &rb, &e);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (st) return cli_fail(&e, st);
  if (c.json) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "zeta_low", rb.zeta_low);
    cJSON_AddNumberToObject(root, "zeta_high", rb.zeta_high);
    cJSON_AddNumberToObject(root, "std_zeta", rb.std_zeta);
    cJSON_AddNumberToObject(root, "n_conicity", a.ro.n_conicity);
    cli_json_print(root);
  } else {
    printf("%s robust stability indices (negative is stable)\n", c.veh.name);
    printf("  zeta_low  (250 km/h, conicity 0.05): %10.6f\n", rb.zeta_low);
    printf("  zeta_high (350 km/h, conicity 0.40): %10.6f\n", rb.zeta_high);
    printf("  std_zeta  (350 km/h, %d conicities 0.05-0.40): %10.6f\n", a.ro.n_conicity, rb.std_zeta);
  }
  return 0;
}

typedef struct crit_args { double vmin, vmax, step; } crit_args;
enum { OPT_VMIN = 2100, OPT_VMAX, OPT_STEP };

static int crit_cb(int opt, const char *arg, void *u)
{
  crit_args *a = u;
  double *dst = opt == OPT_VMIN ? &a->vmin : opt == OPT_VMAX ? &a->vmax : opt == OPT_STEP ? &a->step : NULL;
  if (!dst) return 1;
  const char *name = opt == OPT_VMIN ? "vmin" : opt == OPT_VMAX ? "vmax" : "step";
  if (cli_number(name, arg, "km/h", dst)) return 1;
  if (!(*dst > 0)) return cli_bad("--%s: must be > 0 km/h", name);
  return 0;
}

int cmd_critical(int argc, char **argv)
{
  static const char help[] = "usage: railride critical-speed [VEHICLE] --conicity L [--vmin KMH] [--vmax KMH] [--step KMH] [--json]\n"
                             "Lowest speed in [vmin, vmax] (default 10-600 km/h) at which the vehicle stability\n"
                             "index reaches 0: a scan at --step (default 1 km/h), then bisection to 1e-3 km/h.\n" CLI_COMMON_HELP
                             "  --vmin, --vmax KMH   speed range\n  --step KMH           scan step\n";
  static const struct option extra[] = {{"vmin", required_argument, 0, OPT_VMIN}, {"vmax", required_argument, 0, OPT_VMAX},
                                        {"step", required_argument, 0, OPT_STEP}, {0, 0, 0, 0}};
  cli_common c;
  crit_args a = {10, 600, 1};
  RUN_PARSE(extra, crit_cb, &a, help);
  if (!c.have_conicity) return cli_bad("--conicity is required");
  if (!(a.vmax > a.vmin)) return cli_bad("--vmax must exceed --vmin");
  rr_model *m;
  int r = cli_model(&c, &m, 0, 1);
  if (r) return r;
  rr_error e;
  rr_modal_ws *ws;
  rr_critical_opts co = {a.vmin / 3.6, a.vmax / 3.6, a.step / 3.6, 1e-3 / 3.6};
  double v;
  int found = 0;
  int st = rr_modal_ws_new(m, &ws, &e);
  if (!st) st = rr_critical_speed(m, c.conicity, &c.mo, &co, ws, &v, &found, &e);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (st) return cli_fail(&e, st);
  if (c.json) {
    cJSON *root = cJSON_CreateObject();
    if (found) cJSON_AddNumberToObject(root, "critical_speed_kmh", v * 3.6);
    else cJSON_AddNullToObject(root, "critical_speed_kmh");
    cJSON_AddBoolToObject(root, "stable_to_range_end", !found);
    cJSON_AddNumberToObject(root, "conicity", c.conicity);
    double range[2] = {a.vmin, a.vmax};
    cJSON_AddItemToObject(root, "range_kmh", cJSON_CreateDoubleArray(range, 2));
    cli_json_print(root);
  } else if (found) {
    printf("%s critical speed at conicity %g: %.3f km/h\n", c.veh.name, c.conicity, v * 3.6);
  } else {
    printf("%s at conicity %g: stable to the range's end (%g km/h)\n", c.veh.name, c.conicity, a.vmax);
  }
  return 0;
}

typedef struct grid_args {
  int param;               /* locus: 0 speed, 1 conicity */
  double from, to;
  int n, have_range;
  double s_from, s_to, c_from, c_to;
  int s_n, c_n;
} grid_args;
enum { OPT_PARAM = 2200, OPT_RANGE, OPT_SPEEDS, OPT_CONICITIES };

static int grid_cb(int opt, const char *arg, void *u)
{
  grid_args *a = u;
  switch (opt) {
  case OPT_PARAM:
    if (!strcmp(arg, "speed")) a->param = 0;
    else if (!strcmp(arg, "conicity")) a->param = 1;
    else return cli_bad("--over: 'speed' or 'conicity' expected, got '%s'", arg);
    return 0;
  case OPT_RANGE:
    a->have_range = 1;
    return cli_range("range", arg, a->param == 0 ? "km/h" : "1", &a->from, &a->to, &a->n) ? 1 : 0;
  case OPT_SPEEDS: return cli_range("speeds", arg, "km/h", &a->s_from, &a->s_to, &a->s_n) ? 1 : 0;
  case OPT_CONICITIES: return cli_range("conicities", arg, "1", &a->c_from, &a->c_to, &a->c_n) ? 1 : 0;
  }
  return 1;
}

static double lin(double a, double b, int i, int n) { return n == 1 ? a : a + (b - a) * i / (n - 1); }

int cmd_locus(int argc, char **argv)
{
  static const char help[] = "usage: railride locus [VEHICLE] [--over speed|conicity] [--range FROM:TO:N] [--speed KMH | --conicity L] [--json]\n"
                             "Root locus: each oscillatory mode followed from point to point by eigenvector\n"
                             "correlation (MAC). Over speed (default 20:500:25 km/h at --conicity, default 0.17)\n"
                             "or conicity (default 0.02:0.5:25 at --speed, default 350 km/h). CSV columns:\n"
                             "branch,speed_kmh,conicity,freq_hz,real,imag,stability_index,mac,e_carbody,e_frames,e_wheelsets\n" CLI_COMMON_HELP
                             "  --over P             parameter swept (--over before --range)\n  --range FROM:TO:N    its values\n";
  static const struct option extra[] = {{"over", required_argument, 0, OPT_PARAM}, {"range", required_argument, 0, OPT_RANGE}, {0, 0, 0, 0}};
  cli_common c;
  grid_args a;
  memset(&a, 0, sizeof a);
  RUN_PARSE(extra, grid_cb, &a, help);
  if (!a.have_range) {
    if (a.param == 0) { a.from = 20; a.to = 500; a.n = 25; }
    else { a.from = 0.02; a.to = 0.5; a.n = 25; }
  }
  if (a.param == 0 && !(a.from > 0 && a.to > 0)) return cli_bad("--range: speeds must be > 0");
  if (a.param == 1 && !(a.from >= 0 && a.to >= 0)) return cli_bad("--range: conicities must be >= 0");
  rr_model *m;
  int r = cli_model(&c, &m, 0, 0);
  if (r) return r;
  double *vals = malloc(sizeof(double) * (size_t)a.n);
  rr_locus_point *pts = malloc(sizeof(rr_locus_point) * (size_t)a.n * (size_t)rr_model_state_size(m));
  if (!vals || !pts) { free(vals); free(pts); rr_model_free(m); return cli_bad("out of memory"); }
  for (int i = 0; i < a.n; i++) vals[i] = lin(a.from, a.to, i, a.n) / (a.param == 0 ? 3.6 : 1.0);
  rr_error e;
  int nb = 0;
  int st = rr_locus(m, a.param, vals, a.n, &c.mo, pts, &nb, &e);
  double v0 = rr_model_speed(m) * 3.6, l0 = rr_model_conicity(m);
  rr_model_free(m);
  if (st) { free(vals); free(pts); return cli_fail(&e, st); }
  cJSON *root = c.json ? cJSON_CreateObject() : NULL, *arr = root ? cJSON_AddArrayToObject(root, "points") : NULL;
  if (!c.json) printf("branch,speed_kmh,conicity,freq_hz,real,imag,stability_index,mac,e_carbody,e_frames,e_wheelsets\n");
  for (int b = 0; b < nb; b++)
    for (int p = 0; p < a.n; p++) {
      const rr_locus_point *lp = &pts[(size_t)p * nb + b];
      double sp = a.param == 0 ? lp->param * 3.6 : v0, co = a.param == 1 ? lp->param : l0;
      if (c.json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "branch", b);
        cJSON_AddNumberToObject(o, "speed_kmh", sp);
        cJSON_AddNumberToObject(o, "conicity", co);
        cJSON_AddNumberToObject(o, "freq_hz", lp->freq_hz);
        cJSON_AddNumberToObject(o, "real", lp->re);
        cJSON_AddNumberToObject(o, "imag", lp->im);
        cJSON_AddNumberToObject(o, "stability_index", lp->zeta);
        cJSON_AddNumberToObject(o, "mac", lp->mac);
        cJSON_AddItemToArray(arr, o);
      } else {
        printf("%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.6f,%.6g,%.6g,%.6g\n", b, sp, co, lp->freq_hz, lp->re, lp->im,
               lp->zeta, lp->mac, lp->energy[0], lp->energy[1], lp->energy[2]);
      }
    }
  if (root) cli_json_print(root);
  free(vals);
  free(pts);
  return 0;
}

int cmd_map(int argc, char **argv)
{
  static const char help[] = "usage: railride map [VEHICLE] [--speeds FROM:TO:N] [--conicities FROM:TO:N] [--json]\n"
                             "Vehicle stability index over a speed x conicity grid (paper Fig. 7); defaults\n"
                             "100:500:41 km/h and 0.02:0.5:25. CSV columns: speed_kmh,conicity,stability_index\n" CLI_COMMON_HELP
                             "  --speeds FROM:TO:N   speed grid, km/h\n  --conicities FROM:TO:N  conicity grid\n";
  static const struct option extra[] = {{"speeds", required_argument, 0, OPT_SPEEDS}, {"conicities", required_argument, 0, OPT_CONICITIES}, {0, 0, 0, 0}};
  cli_common c;
  grid_args a;
  memset(&a, 0, sizeof a);
  a.s_from = 100; a.s_to = 500; a.s_n = 41;
  a.c_from = 0.02; a.c_to = 0.5; a.c_n = 25;
  RUN_PARSE(extra, grid_cb, &a, help);
  if (!(a.s_from > 0 && a.s_to > 0)) return cli_bad("--speeds: must be > 0");
  if (!(a.c_from >= 0 && a.c_to >= 0)) return cli_bad("--conicities: must be >= 0");
  rr_model *m;
  int r = cli_model(&c, &m, 0, 0);
  if (r) return r;
  rr_error e;
  rr_modal_ws *ws;
  int st = rr_modal_ws_new(m, &ws, &e);
  if (st) { rr_model_free(m); return cli_fail(&e, st); }
  cJSON *root = c.json ? cJSON_CreateObject() : NULL, *arr = root ? cJSON_AddArrayToObject(root, "points") : NULL;
  if (!c.json) printf("speed_kmh,conicity,stability_index\n");
  /* one speed's conicities at a time, through the batched index */
  double *vs = malloc(sizeof(double) * (size_t)a.c_n * 3), *ls = vs ? vs + a.c_n : NULL, *zs = ls ? ls + a.c_n : NULL;
  if (!vs) { rr_modal_ws_free(ws); rr_model_free(m); cJSON_Delete(root); return cli_bad("out of memory"); }
  for (int i = 0; i < a.s_n && !st; i++) {
    for (int j = 0; j < a.c_n; j++) {
      vs[j] = lin(a.s_from, a.s_to, i, a.s_n) / 3.6;
      ls[j] = lin(a.c_from, a.c_to, j, a.c_n);
    }
    if ((st = rr_modal_stability_index_batch(m, &c.mo, ws, a.c_n, vs, ls, zs, &e))) break;
    for (int j = 0; j < a.c_n; j++) {
      double v = lin(a.s_from, a.s_to, i, a.s_n), l = ls[j], z = zs[j];
      if (c.json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "speed_kmh", v);
        cJSON_AddNumberToObject(o, "conicity", l);
        cJSON_AddNumberToObject(o, "stability_index", z);
        cJSON_AddItemToArray(arr, o);
      } else {
        printf("%.10g,%.10g,%.10g\n", v, l, z);
      }
    }
  }
  free(vs);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (st) { cJSON_Delete(root); return cli_fail(&e, st); }
  if (root) cli_json_print(root);
  return 0;
}
