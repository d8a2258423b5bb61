/* Stability commands: matrices, modes, robust, critical-speed, locus, map. */
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "outfile.h"
#include "parallel.h"

#define RUN_PARSE(reads, extra, cb, user, help)                                                    \
  do {                                                                                             \
    int r_ = cli_parse(argc, argv, &c, reads, extra, cb, user, help);                              \
    if (r_ == CLI_HELP_SHOWN) return 0;                                                            \
    if (r_) return r_;                                                                             \
  } while (0)

static const char *energy_names[RR_NGROUPS] = {"carbody", "frames", "wheelsets"};

enum { OPT_SHAPES = 2050, OPT_MODES_DIRECTION };

/* --direction (read before parsing) and nothing else */
static int direction_only_cb(int opt, const char *arg, void *u)
{
  (void)arg;
  (void)u;
  return opt == OPT_MODES_DIRECTION ? 0 : 1;
}

int cmd_matrices(int argc, char **argv)
{
  static const char help[] =
      "usage: railride matrices [VEHICLE] --speed KMH --conicity L [--json]\n"
      "       railride matrices [VEHICLE] --direction vertical [--speed KMH] [--json]\n"
      "Prints M, C, K (17x17), B (17x4), the Maxwell elements and the state matrix A.\n"
      "In paper SDF mode A is taken at the curve's lowest stiffness. --direction vertical:\n"
      "the vertical model's M, C, K (7x7), BK, BC (7x4), the wheelsets' positions and\n"
      "distances, phi at the pivots, the floor rows at +L, 0, -L, A (14x14) and, with a\n"
      "speed, the wheelsets' delays.\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"direction", OPT_MODES_DIRECTION, "D", "lateral (default) or vertical"}, CLI_OPT_END};
  cli_common c;
  rr_model *m;
  int dir = cli_direction_one("matrices", argc, argv);
  if (dir < 0) return EXIT_BADINPUT;
  RUN_PARSE(dir == CLI_DIR_VERTICAL
                ? CLI_READS_SPEED | CLI_READS_JSON
                : CLI_READS_SPEED | CLI_READS_CONICITY | CLI_READS_JSON | CLI_READS_GRAVITY,
            extra, direction_only_cb, NULL, help);
  if (dir == CLI_DIR_VERTICAL) return matrices_vertical(&c);
  int r = cli_model(&c, &m, 1, 1);
  if (r) return r;
  int n = rr_model_ndof(m), ni = rr_model_ninputs(m), N = rr_model_state_size(m);
  double *A = malloc(sizeof(double) * (size_t)N * (size_t)N);
  rr_error e;
  if (!A) {
    rr_model_free(m);
    return cli_bad("out of memory");
  }
  int st = rr_model_state_matrix(m, 0, A, &e);
  if (st) {
    free(A);
    rr_model_free(m);
    return cli_fail(&e, st);
  }
  if (c.json) {
    cJSON *root = cJSON_CreateObject(), *dofs = cJSON_AddArrayToObject(root, "dofs");
    for (int i = 0; i < n; i++)
      cJSON_AddItemToArray(dofs, cJSON_CreateString(rr_model_dof_name(m, i)));
    cJSON_AddNumberToObject(root, "speed_kmh", c.speed_kmh);
    cJSON_AddNumberToObject(root, "conicity", c.conicity);
    cJSON_AddStringToObject(root, "conicity_source", c.conicity_source);
    cJSON_AddItemToObject(root, "M", cli_json_matrix(rr_model_M(m), n, n));
    cJSON_AddItemToObject(root, "C", cli_json_matrix(rr_model_C(m), n, n));
    cJSON_AddItemToObject(root, "K", cli_json_matrix(rr_model_K(m), n, n));
    cJSON_AddItemToObject(root, "B", cli_json_matrix(rr_model_B(m), n, ni));
    cJSON *mx = cJSON_AddArrayToObject(root, "maxwell");
    for (int i = 0; i < rr_model_nmaxwell(m); i++) {
      rr_maxwell_info info;
      rr_model_maxwell(m, i, &info, NULL); /* i in range */
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
      rr_model_maxwell(m, i, &info, NULL); /* i in range */
      printf("  %-24s k = %.6g N/m  c = %.6g N s/m%s\n", info.name, info.k, info.c,
             info.sdf ? "  (SDF)" : "");
    }
    printf("State matrix A: %d x %d (use --json for its entries)\n", N, N);
  }
  free(A);
  rr_model_free(m);
  return 0;
}

cJSON *cli_mode_json(const rr_mode *md, int paper)
{
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "name", md->name);
  cJSON_AddNumberToObject(o, "freq_hz", md->freq_hz);
  cJSON_AddNumberToObject(o, "real", md->re);
  cJSON_AddNumberToObject(o, "imag", md->im);
  cJSON_AddNumberToObject(o, "stability_index", md->zeta);
  cJSON *en = cJSON_AddObjectToObject(o, "energy");
  for (int g = 0; g < RR_NGROUPS; g++) cJSON_AddNumberToObject(en, energy_names[g], md->energy[g]);
  cJSON_AddNumberToObject(o, "roll_share", md->roll_share);
  cJSON_AddNumberToObject(o, "frame_roll_share", md->frame_roll_share);
  cJSON_AddBoolToObject(o, "oscillatory", md->oscillatory);
  cJSON_AddBoolToObject(o, "hunting_related", md->hunting);
  cJSON_AddBoolToObject(o, "in_index", md->in_index);
  if (paper) {
    cJSON_AddBoolToObject(o, "self_consistent", md->self_consistent);
    cJSON_AddNumberToObject(o, "sdf_k", md->sdf_k);
  }
  return o;
}

/* The verdict line (docs/model.md: any oscillatory mode with zeta >= 0). */
static void print_verdict(const rr_modal_result *res)
{
  if (res->max_mode < 0) {
    printf("verdict: stable (no oscillatory mode)\n");
    return;
  }
  const rr_mode *md = &res->modes[res->max_mode];
  printf("verdict: %s (least damped mode: %s at %.4f Hz, zeta %.6f)\n",
         rr_modal_stable(res->zeta_max) ? "stable" : "UNSTABLE", md->name, md->freq_hz, md->zeta);
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

/* A mode's shape as JSON: per DOF its amplitude and phase (the q part of the
   eigenvector, unit norm, largest component real and positive). */
static cJSON *shape_json(const rr_model *m, const rr_complex *phi)
{
  cJSON *arr = cJSON_CreateArray();
  for (int i = 0; i < rr_model_ndof(m); i++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "dof", rr_model_dof_name(m, i));
    cJSON_AddNumberToObject(o, "amplitude", cabs(phi[i]));
    cJSON_AddNumberToObject(o, "phase_deg", cabs(phi[i]) > 0 ? carg(phi[i]) * 180 / RR_PI : 0);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

static void modes_json(const cli_common *c, const rr_model *m, const rr_modal_result *res,
                       int paper)
{
  cJSON *root = cJSON_CreateObject();
  if (res->index_mode >= 0)
    cJSON_AddNumberToObject(root, "stability_index", res->stability_index);
  else
    cJSON_AddNullToObject(root, "stability_index");
  cJSON_AddStringToObject(root, "index_source", cli_index_source_key(res->index_source));
  if (res->index_mode >= 0)
    cJSON_AddStringToObject(root, "index_mode", res->modes[res->index_mode].name);
  else
    cJSON_AddNullToObject(root, "index_mode");
  cJSON_AddBoolToObject(root, "stable", rr_modal_stable(res->zeta_max));
  cJSON_AddNumberToObject(root, "zeta_max", res->zeta_max);
  cJSON_AddNumberToObject(root, "speed_kmh", c->speed_kmh);
  cJSON_AddNumberToObject(root, "conicity", c->conicity);
  cJSON_AddStringToObject(root, "conicity_source", c->conicity_source);
  cli_band_json(root, &c->mo, res->fmax_hz);
  cJSON_AddNumberToObject(root, "w_min", c->mo.w_min);
  cJSON_AddNumberToObject(root, "r_max", c->mo.r_max);
  cJSON *arr = cJSON_AddArrayToObject(root, "modes");
  for (int i = 0; i < res->n; i++) {
    if (res->modes[i].im <= 0) continue;
    cJSON *o = cli_mode_json(&res->modes[i], paper);
    cJSON_AddItemToObject(o, "shape", shape_json(m, res->shapes + (size_t)i * (size_t)res->ndof));
    cJSON_AddItemToArray(arr, o);
  }
  cli_json_print(root);
}

static void modes_table(const cli_common *c, const rr_modal_result *res, int paper)
{
  printf("%s at %.6g km/h, conicity %.6g (%s)%s\n", c->veh.name, c->speed_kmh, c->conicity,
         c->conicity_source,
         paper                                ? " (SDF paper mode: self-consistent modes)"
         : c->veh.sdf_mode == RR_SDF_PHYSICAL ? " (SDF physical mode)"
                                              : "");
  printf("%10s %12s %12s %10s %9s %9s %9s %9s %9s  %-34s %s\n", "freq_hz", "real", "imag", "zeta",
         "E_car", "E_frame", "E_wheel", "roll", "fr_roll", "mode", "flags");
  for (int i = 0; i < res->n; i++) {
    const rr_mode *md = &res->modes[i];
    if (md->im <= 0) continue;
    printf("%10.4f %12.5g %12.5g %10.5f %9.2e %9.2e %9.2e %9.2e %9.2e  %-34s %s%s%s%s\n",
           md->freq_hz, md->re, md->im, md->zeta, md->energy[0], md->energy[1], md->energy[2],
           md->roll_share, md->frame_roll_share, md->name, md->in_index ? "index " : "",
           md->hunting ? "hunting" : "", md->self_consistent ? "" : " not-self-consistent",
           i == res->index_mode ? "  <- sets the index" : "");
  }
  char buf[256];
  cli_index_text(buf, sizeof buf, res->stability_index, res->index_source,
                 res->index_mode >= 0 ? &res->modes[res->index_mode] : NULL, NAN, &c->mo,
                 res->fmax_hz);
  printf("vehicle stability index: %s\n", buf);
  print_verdict(res);
}

typedef struct modes_args {
  const char *shape_data;
} modes_args;
static int modes_cb(int opt, const char *arg, void *u)
{
  modes_args *a = u;
  if (opt == OPT_MODES_DIRECTION) return 0; /* read before parsing */
  if (opt != OPT_SHAPES) return 1;
  a->shape_data = arg;
  return 0;
}

/* The modes a plan view shows: hunting-related below fmax, and the one
   that sets the index; at most PLAN_MAX_PANELS, lowest first. */
#define PLAN_MAX_PANELS 9
static int plan_modes(const rr_modal_result *res, int *pick)
{
  int n = 0;
  for (int i = 0; i < res->n && n < PLAN_MAX_PANELS; i++)
    if (res->modes[i].oscillatory && (res->modes[i].in_index || i == res->index_mode))
      pick[n++] = i;
  return n;
}

/* One body's outline (half length a along x, half width w along y) at
   centre (x, y) turned by psi, closed, then a blank line. */
static void outline(FILE *fp, double x, double y, double psi, double a, double w)
{
  const double cx[5] = {-a, a, a, -a, -a}, cy[5] = {-w, -w, w, w, -w};
  for (int k = 0; k < 5; k++)
    fprintf(fp, "%.6g %.6g\n", x + cx[k] * cos(psi) - cy[k] * sin(psi),
            y + cx[k] * sin(psi) + cy[k] * cos(psi));
  fputc('\n', fp);
}

/* The plan view's data: per panel a comment with its title, then the
   bodies at rest, at phase 0 and a quarter period later (three blocks,
   separated by two blank lines: gnuplot's index 4p, 4p+1, 4p+2), then the
   roll labels (index 4p+3). The shape
   is scaled so the largest lateral motion is 0.6 m on the drawing; yaw
   turns by the same scale (capped at 20 degrees); roll is marked by the
   body's name in the title of the panel. */
static int write_shape_data(const char *path, const cli_common *c, const rr_model *m,
                            const rr_modal_result *res)
{
  cli_outfile out;
  int r = cli_out_open(&out, path, "--shape-data");
  if (r) return r;
  FILE *fp = out.fp;
  const rr_vehicle *v = &c->veh;
  int pick[PLAN_MAX_PANELS], np = plan_modes(res, pick), n = rr_model_ndof(m);
  const char *body[7] = {"c", "f1", "f2", "w1", "w2", "w3", "w4"};
  double L = v->bogie_half_spacing, b = v->wheelbase_half, s2 = v->contact_half_spacing;
  const double bx[7] = {0, L, -L, L + b, L - b, -L + b, -L - b};
  const double ha[7] = {L + b + 2.0, b + 0.9, b + 0.9, 0.12, 0.12, 0.12, 0.12};
  const double hw[7] = {1.6, 1.2, 1.2, s2 + 0.1, s2 + 0.1, s2 + 0.1, s2 + 0.1};
  fprintf(fp, "# railride modes: plan views of %d modes of %s at %g km/h, conicity %g\n", np,
          v->name, c->speed_kmh, c->conicity);
  for (int p = 0; p < np; p++) {
    const rr_mode *md = &res->modes[pick[p]];
    const rr_complex *phi = res->shapes + (size_t)pick[p] * (size_t)n;
    double big = 0;
    for (int i = 0; i < n; i++)
      if (rr_model_dof_name(m, i)[0] == 'y') big = fmax(big, cabs(phi[i]));
    double sc = big > 0 ? 0.6 / big : 1;
    fprintf(fp, "# panel %d: %s, %.3f Hz, zeta %.3f, roll share %.2f%s\n", p, md->name, md->freq_hz,
            md->zeta, md->roll_share, pick[p] == res->index_mode ? " (sets the index)" : "");
    for (int ph = -1; ph < 2; ph++) { /* at rest, phase 0, a quarter period later */
      for (int k = 0; k < 7; k++) {
        double y = 0, psi = 0;
        for (int i = 0; i < n && ph >= 0; i++) {
          const char *nm = rr_model_dof_name(m, i), *u = strchr(nm, '_');
          if (!u || strcmp(u + 1, body[k])) continue;
          double q = ph == 0 ? creal(phi[i]) : -cimag(phi[i]); /* Re(phi e^{i pi/2}) */
          if (nm[0] == 'y') y = sc * q;
          if (!strncmp(nm, "psi", 3)) psi = fmax(-0.35, fmin(0.35, sc * q));
        }
        outline(fp, bx[k], y, psi, ha[k], hw[k]);
      }
      fputs("\n\n", fp);
    }
    fputs("0 99 \"\"\n", fp);     /* off the drawing: the block is never empty */
    for (int k = 0; k < 3; k++) { /* roll, at the bodies that have it: amplitude on the scale */
      char dof[16];
      snprintf(dof, sizeof dof, "phi_%s", body[k]);
      for (int i = 0; i < n; i++)
        if (!strcmp(rr_model_dof_name(m, i), dof) && sc * cabs(phi[i]) > 0.5 * RR_PI / 180)
          fprintf(fp, "%.6g %.6g \"roll %.0f deg\"\n", bx[k], k ? -hw[k] - 0.9 : hw[k] + 0.9,
                  sc * cabs(phi[i]) * 180 / RR_PI);
    }
    fputs("\n\n", fp);
  }
  return cli_out_commit(&out);
}

int cmd_modes(int argc, char **argv)
{
  static const char help[] =
      "usage: railride modes [VEHICLE] --speed KMH --conicity L [--fmax HZ] [--json]\n"
      "Eigenvalues of the state matrix: frequency, stability index zeta = Re/|lambda|\n"
      "(negative is stable), kinetic-energy shares, roll share and a name by dominant\n"
      "motion. The vehicle stability index is the largest zeta over hunting-related modes\n"
      "(wheelset share >= wmin, frame-roll share < rmax) below fmax, unless some mode of any\n"
      "frequency and shape is unstable, which then sets it: its sign is the verdict. With\n"
      "no hunting-related mode and all stable it is undefined (none; JSON null). JSON gives\n"
      "each mode's shape (amplitude and phase per DOF; unit norm, largest component real).\n"
      "--plot FILE draws the hunting-related modes below fmax (and the one that sets the\n"
      "index) in plan view, one panel each: the seven bodies displaced in lateral and yaw,\n"
      "at phase 0 and a quarter period later, roll marked.\n"
      "--direction vertical: the vertical model's modes (no speed or conicity): frequency,\n"
      "natural frequency, damping ratio (positive when stable), energy shares, "
      "names.\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"shape-data", OPT_SHAPES, "FILE",
       "write those panels' body outlines (gnuplot data) to FILE"},
      {"direction", OPT_MODES_DIRECTION, "D", "lateral (default) or vertical"},
      CLI_OPT_END};
  cli_common c;
  rr_model *m;
  modes_args a = {0};
  int dir = cli_direction_one("modes", argc, argv);
  if (dir < 0) return EXIT_BADINPUT;
  RUN_PARSE(dir == CLI_DIR_VERTICAL ? CLI_READS_JSON
                                    : CLI_READS_SPEED | CLI_READS_CONICITY | CLI_READS_JSON |
                                          CLI_READS_INDEX | CLI_READS_GRAVITY,
            extra, modes_cb, &a, help);
  if (dir == CLI_DIR_VERTICAL) {
    if (a.shape_data)
      return cli_bad("--shape-data: the lateral modes' (not with --direction vertical)");
    return modes_vertical(&c);
  }
  int r = cli_model(&c, &m, 1, 1);
  if (r) return r;
  rr_modal_result res;
  if ((r = solve_modes(m, &c.mo, &res))) {
    rr_model_free(m);
    return r;
  }
  int paper = c.veh.sdf_mode == RR_SDF_PAPER;
  if (a.shape_data) r = write_shape_data(a.shape_data, &c, m, &res);
  if (r)
    ;
  else if (c.json)
    modes_json(&c, m, &res, paper);
  else
    modes_table(&c, &res, paper);
  rr_modal_result_free(&res);
  rr_model_free(m);
  return r;
}

typedef struct robust_args {
  rr_robust_opts ro;
} robust_args;
enum { OPT_NCON = 2000 };

static int robust_cb(int opt, const char *arg, void *u)
{
  robust_args *a = u;
  if (opt == OPT_NCON) {
    char *end;
    long k = strtol(arg, &end, 10);
    if (*end || k < 1 || k > 10000)
      return cli_bad("--n-conicity: whole number >= 1 expected, got '%s'", arg);
    a->ro.n_conicity = (int)k;
    return 0;
  }
  return 1;
}

int cmd_robust(int argc, char **argv)
{
  static const char help[] =
      "usage: railride robust [VEHICLE] [--n-conicity N] [--json]\n"
      "Robust stability indices (paper Table 1): zeta_low at 250 km/h, conicity 0.05;\n"
      "zeta_high at 350 km/h, 0.40; std_zeta: population standard deviation of the index\n"
      "at 350 km/h over N (default 8) conicities from 0.05 to 0.40.\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"n-conicity", OPT_NCON, "N", "number of conicities for std_zeta"}, CLI_OPT_END};
  cli_common c;
  robust_args a = {.ro = rr_robust_opts_default()};
  RUN_PARSE(CLI_READS_JSON | CLI_READS_INDEX | CLI_READS_GRAVITY, extra, robust_cb, &a, help);
  rr_model *m;
  int r = cli_model(&c, &m, 0, 0);
  if (r) return r;
  rr_error e;
  rr_modal_ws *ws;
  rr_robust rb;
  int st = rr_modal_ws_new(m, &ws, &e);
  if (!st) st = rr_robust_indices(m, &c.mo, &a.ro, ws, &rb, &e);
  double edge_low = rr_modal_band_edge_at(m, &c.mo, a.ro.v_low_ms, a.ro.conicity_low),
         edge_high = rr_modal_band_edge_at(m, &c.mo, a.ro.v_high_ms, a.ro.conicity_high);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (st) return cli_fail(&e, st);
  int stable = rb.n_unstable == 0;
  if (c.json) {
    cJSON *root = cJSON_CreateObject(); /* an undefined index is null */
    cJSON_AddNumberToObject(root, "zeta_low", rb.zeta_low);
    cJSON_AddNumberToObject(root, "zeta_high", rb.zeta_high);
    cJSON_AddNumberToObject(root, "std_zeta", rb.std_zeta);
    cJSON_AddNumberToObject(root, "n_conicity", a.ro.n_conicity);
    cJSON_AddBoolToObject(root, "stable", stable);
    cJSON_AddNumberToObject(root, "zeta_max", rb.zeta_max);
    cJSON_AddNumberToObject(root, "n_unstable_points", rb.n_unstable);
    cJSON_AddNumberToObject(root, "fmax_low_hz", edge_low);
    cJSON_AddNumberToObject(root, "fmax_high_hz", edge_high);
    cJSON_AddStringToObject(root, "fmax_rule", c.mo.fmax_hz > 0 ? "fixed" : "kinematic");
    cli_json_print(root);
  } else {
    char b1[32], b2[32], b3[32];
    printf("%s robust stability indices (negative is stable; none: undefined, no hunting-related "
           "mode)\n",
           c.veh.name);
    printf("  zeta_low  (%g km/h, conicity %g): %10s\n", a.ro.v_low_ms * RR_KMH, a.ro.conicity_low,
           cli_num_or_none(b1, sizeof b1, rb.zeta_low));
    printf("  zeta_high (%g km/h, conicity %g): %10s\n", a.ro.v_high_ms * RR_KMH,
           a.ro.conicity_high, cli_num_or_none(b2, sizeof b2, rb.zeta_high));
    printf("  std_zeta  (%g km/h, %d conicities %g-%g): %10s\n", a.ro.v_high_ms * RR_KMH,
           a.ro.n_conicity, a.ro.conicity_min, a.ro.conicity_max,
           cli_num_or_none(b3, sizeof b3, rb.std_zeta));
    printf("  index band edge: %.2f Hz at zeta_low's point, %.2f Hz at zeta_high's (%s)\n",
           edge_low, edge_high, cli_band_rule(&c.mo));
    if (stable)
      printf("verdict: stable at every point (largest zeta of any mode %.6f)\n", rb.zeta_max);
    else
      printf("verdict: UNSTABLE at %d of the points (first: %g km/h, conicity %g; largest zeta "
             "%.6f)\n",
             rb.n_unstable, rb.unstable_speed_ms * RR_KMH, rb.unstable_conicity, rb.zeta_max);
  }
  return 0;
}

typedef struct crit_args {
  double vmin, vmax, step;
  int index_modes;
} crit_args;
enum { OPT_VMIN = 2100, OPT_VMAX, OPT_STEP, OPT_INDEX_MODES };

static int crit_cb(int opt, const char *arg, void *u)
{
  crit_args *a = u;
  if (opt == OPT_INDEX_MODES) {
    a->index_modes = 1;
    return 0;
  }
  double *dst = opt == OPT_VMIN   ? &a->vmin
                : opt == OPT_VMAX ? &a->vmax
                : opt == OPT_STEP ? &a->step
                                  : NULL;
  if (!dst) return 1;
  const char *name = opt == OPT_VMIN ? "vmin" : opt == OPT_VMAX ? "vmax" : "step";
  if (cli_number(name, arg, "km/h", dst)) return 1;
  if (!(*dst > 0 && *dst <= RR_SPEED_MAX_MS * RR_KMH))
    return cli_bad("--%s: must be within (0, %g] km/h", name, RR_SPEED_MAX_MS * RR_KMH);
  return 0;
}

static cJSON *critical_json(const cli_common *c, double conicity, const crit_args *a,
                            const rr_critical *cr, int paper)
{
  cJSON *root = cJSON_CreateObject();
  if (cr->found)
    cJSON_AddNumberToObject(root, "critical_speed_kmh", cr->speed_ms * RR_KMH);
  else
    cJSON_AddNullToObject(root, "critical_speed_kmh");
  cJSON_AddBoolToObject(root, "stable_to_range_end", !cr->found);
  cJSON_AddNumberToObject(root, "conicity", conicity);
  cJSON_AddStringToObject(root, "conicity_source", c->conicity_source);
  cJSON_AddStringToObject(root, "rule", a->index_modes ? "index modes" : "any oscillatory mode");
  if (a->index_modes) /* the index's band edge, taken at each speed tried */
    cJSON_AddStringToObject(root, "fmax_rule", c->mo.fmax_hz > 0 ? "fixed" : "kinematic");
  double range[2] = {a->vmin, a->vmax};
  cJSON_AddItemToObject(root, "range_kmh", cJSON_CreateDoubleArray(range, 2));
  if (cr->found)
    cJSON_AddItemToObject(root, "mode", cli_mode_json(&cr->mode, paper));
  else
    cJSON_AddNullToObject(root, "mode");
  return root;
}

static void critical_text(const cli_common *c, double conicity, const crit_args *a,
                          const rr_critical *cr)
{
  const rr_mode *md = &cr->mode;
  char rule[96] = "";
  if (a->index_modes && c->mo.fmax_hz > 0)
    snprintf(rule, sizeof rule, " (the index's modes below a fixed %g Hz)", c->mo.fmax_hz);
  else if (a->index_modes)
    snprintf(rule, sizeof rule, " (the index's modes, band edge max(10 Hz, f_K) at each speed)");
  if (!cr->found) {
    printf("%s at conicity %g: stable to the range's end (%g km/h)%s\n", c->veh.name, conicity,
           a->vmax, rule);
    return;
  }
  printf("%s critical speed at conicity %g (%s): %.3f km/h%s\n", c->veh.name, conicity,
         c->conicity_source, cr->speed_ms * RR_KMH, rule);
  printf("  unstable mode: %s at %.4f Hz (energy carbody %.3f, frames %.3f, wheelsets %.3f; roll "
         "%.3f, frame roll %.3f; %s)\n",
         md->name, md->freq_hz, md->energy[0], md->energy[1], md->energy[2], md->roll_share,
         md->frame_roll_share, md->hunting ? "hunting-related" : "not hunting-related");
}

/* Critical speeds at conicities lo..hi-1 of the list. */
typedef struct crit_list {
  rr_model *m;
  rr_modal_ws *ws;
  const cli_common *c;
  const rr_critical_opts *co;
} crit_list;

static int crit_items(void *user, long lo, long hi, void *out)
{
  crit_list *w = user;
  rr_error e;
  for (long i = lo; i < hi; i++) {
    int st = rr_critical_speed(w->m, w->c->conicities[i], &w->c->mo, w->co, w->ws,
                               (rr_critical *)out + (i - lo), &e);
    if (st) return cli_fail(&e, st);
  }
  return 0;
}

/* rr_critical_opts_default's scan step and tolerance, for the help text */
#define CRIT_STEP_TEXT RR_STR(RR_CRITICAL_STEP_KMH) " km/h"
#define CRIT_TOL_TEXT RR_STR(RR_CRITICAL_TOL_KMH) " km/h"

int cmd_critical(int argc, char **argv)
{
  static const char help[] =
      "usage: railride critical-speed [VEHICLE] --conicity L1[,L2,...] [--vmin KMH] [--vmax KMH] "
      "[--step KMH] [--index-modes] [--json]\n"
      "Lowest speed in [vmin, vmax] (default " CLI_CRITICAL_RANGE
      ") at which some oscillatory mode, of any\n"
      "frequency and shape, has zeta >= 0: a scan at --step (default " CRIT_STEP_TEXT
      "), then bisection to\n" CRIT_TOL_TEXT
      ". Reports the mode that goes unstable. With several conicities, one result each\n"
      "(JSON: {\"results\": [...]}).\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {{"vmin", OPT_VMIN, "KMH", "lowest speed of the range"},
                                  {"vmax", OPT_VMAX, "KMH", "highest speed of the range"},
                                  {"step", OPT_STEP, "KMH", "scan step"},
                                  {"index-modes", OPT_INDEX_MODES, NULL,
                                   "only the stability index's modes count (the index reaching 0)"},
                                  CLI_OPT_END};
  cli_common c;
  rr_critical_opts co = rr_critical_opts_default();
  crit_args a = {.vmin = RR_CRITICAL_V_MIN_KMH, /* co's, in km/h */
                 .vmax = RR_CRITICAL_V_MAX_KMH,
                 .step = RR_CRITICAL_STEP_KMH,
                 .index_modes = co.index_modes};
  int r = cli_parse_list(argc, argv, &c,
                         CLI_READS_CONICITY | CLI_READS_JSON | CLI_READS_INDEX | CLI_READS_GRAVITY |
                             CLI_READS_PROGRESS,
                         extra, crit_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (!c.have_conicity) return cli_bad("--conicity is required");
  if (!(a.vmax > a.vmin)) return cli_bad("--vmax must exceed --vmin");
  rr_model *m;
  if ((r = cli_model(&c, &m, 0, 1))) return r;
  rr_error e;
  rr_modal_ws *ws;
  co.v_min_ms = a.vmin / RR_KMH;
  co.v_max_ms = a.vmax / RR_KMH;
  co.step_ms = a.step / RR_KMH;
  co.index_modes = a.index_modes;
  int st = rr_modal_ws_new(m, &ws, &e);
  if (st) {
    rr_model_free(m);
    return cli_fail(&e, st);
  }
  /* the conicities computed (over MPI ranks under mpirun), then written */
  rr_critical crs[64];
  unsigned char done[64] = {0};
  crit_list w = {.m = m, .ws = ws, .c = &c, .co = &co};
  cli_progress pr;
  cli_progress_start(&pr, "critical-speed", c.ncon, c.progress && c.ncon > 1);
  cli_catch_stops();
  r = cli_par_for(c.ncon, 1, sizeof crs[0], crit_items, &w, crs, done, &pr);
  if (c.ncon > 1) cli_progress_end(&pr);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (r) return r;
  cJSON *all = c.json && c.ncon > 1 ? cJSON_CreateObject() : NULL,
        *arr = all ? cJSON_AddArrayToObject(all, "results") : NULL;
  for (int i = 0; i < c.ncon && done[i]; i++) { /* a stopped run: the leading ones done */
    if (!c.json)
      critical_text(&c, c.conicities[i], &a, &crs[i]);
    else {
      cJSON *one = critical_json(&c, c.conicities[i], &a, &crs[i], c.veh.sdf_mode == RR_SDF_PAPER);
      if (arr)
        cJSON_AddItemToArray(arr, one);
      else
        cli_json_print(one);
    }
  }
  if (all) cli_json_print(all);
  return cli_stopped() ? CLI_EXIT_STOPPED : 0;
}

typedef struct grid_args {
  rr_locus_param param; /* locus: speed or conicity */
  double from, to;
  int n, have_range;
  double s_from, s_to, c_from, c_to;
  int s_n, c_n;
  double limit; /* work cap (--limit) */
  int shares;   /* map --shares: the hunting mode's energy shares too */
} grid_args;
enum { OPT_PARAM = 2200, OPT_RANGE, OPT_SPEEDS, OPT_CONICITIES, OPT_GLIMIT, OPT_SHARES };

static int grid_cb(int opt, const char *arg, void *u)
{
  grid_args *a = u;
  switch (opt) {
  case OPT_PARAM:
    if (!strcmp(arg, "speed"))
      a->param = RR_LOCUS_SPEED;
    else if (!strcmp(arg, "conicity"))
      a->param = RR_LOCUS_CONICITY;
    else
      return cli_bad("--over: 'speed' or 'conicity' expected, got '%s'", arg);
    return 0;
  case OPT_RANGE:
    a->have_range = 1;
    return cli_range("range", arg, a->param == RR_LOCUS_SPEED ? "km/h" : "1", &a->from, &a->to,
                     &a->n)
               ? 1
               : 0;
  case OPT_SPEEDS: return cli_range("speeds", arg, "km/h", &a->s_from, &a->s_to, &a->s_n) ? 1 : 0;
  case OPT_CONICITIES:
    return cli_range("conicities", arg, "1", &a->c_from, &a->c_to, &a->c_n) ? 1 : 0;
  case OPT_GLIMIT: return cli_limit(arg, &a->limit) ? 1 : 0;
  case OPT_SHARES: a->shares = 1; return 0;
  }
  return 1;
}

static double lin(double a, double b, int i, int n)
{
  return n == 1 ? a : a + (b - a) * i / (n - 1);
}

/* The locus over MPI ranks: windows of points whose eigen-solves (the cost)
   are spread over the ranks as records (rr_locus_solve), then followed in
   order on every rank (rr_locus_follow): rr_locus's result to the bit. */
#define LOCUS_WINDOW_PER_RANK                                                                      \
  64 /* points a rank solves per window: the records' memory stays small */

typedef struct locus_solve_job {
  rr_model *m;
  rr_modal_ws *ws;
  rr_modal_result res;
  const cli_common *c;
  rr_locus_param param;
  const double *vals; /* the window's values */
  size_t rs;          /* record size */
} locus_solve_job;

static int locus_solve_items(void *user, long lo, long hi, void *out)
{
  locus_solve_job *w = user;
  rr_error e;
  for (long p = lo; p < hi; p++) {
    int st = rr_locus_solve(w->m, w->param, w->vals[p], &w->c->mo, w->ws, &w->res,
                            (char *)out + (size_t)(p - lo) * w->rs, &e);
    if (st) return cli_fail(&e, st);
  }
  return 0;
}

/* Fills pts and *nb as rr_locus does; *ndone: the points followed (fewer
   after Ctrl-C, the rest NaN). */
static int locus_mpi(rr_model *m, const cli_common *c, rr_locus_param param, const double *vals,
                     long n, rr_locus_point *pts, int *nb, long *ndone, cli_progress *pr)
{
  double v0 = rr_model_speed(m), l0 = rr_model_conicity(m);
  locus_solve_job w = {.m = m, .c = c, .param = param, .rs = rr_locus_record_size(m)};
  size_t stride = (size_t)rr_locus_stride(m);
  long win = (long)cli_par_size() * LOCUS_WINDOW_PER_RANK;
  char *recs = malloc(w.rs * (size_t)(win < n ? win : n));
  unsigned char *done = malloc((size_t)win);
  rr_locus_tracker *t = NULL;
  rr_error e;
  int r = recs && done ? 0 : cli_bad("out of memory"), st = RR_OK;
  if (!r && ((st = rr_modal_ws_new(m, &w.ws, &e)) || (st = rr_modal_result_alloc(m, &w.res, &e)) ||
             (st = rr_locus_tracker_new(m, &t, &e))))
    r = cli_fail(&e, st);
  *nb = 0;
  *ndone = 0;
  for (long lo = 0; lo < n && !r; lo += win) {
    long len = lo + win < n ? win : n - lo, ok = 0;
    w.vals = vals + lo;
    memset(done, 0, (size_t)len);
    r = cli_par_for(len, 1, w.rs, locus_solve_items, &w, recs, done, NULL);
    while (ok < len && done[ok]) ok++; /* after Ctrl-C: the window's leading points solved */
    if (!r && ok &&
        (st = rr_locus_follow(t, vals + lo, (int)ok, recs, pts + (size_t)lo * stride, nb, &e)))
      r = cli_fail(&e, st);
    *ndone += ok;
    if (pr) cli_progress_step(pr, ok);
    if (ok < len) break;
  }
  for (long p = *ndone; p < n && !r; p++) /* a stopped run: the points not followed */
    for (size_t b = 0; b < stride; b++)
      pts[(size_t)p * stride + b] = (rr_locus_point){.param = vals[p], .re = NAN, .im = NAN};
  rr_model_set_operating(m, v0, l0, NULL);
  rr_locus_tracker_free(t);
  rr_modal_result_free(&w.res);
  rr_modal_ws_free(w.ws);
  free(recs);
  free(done);
  return r;
}

/* The range over the swept parameter: the default when none is given, then
   checked against the model's limits. */
static int locus_range(grid_args *a)
{
  if (!a->have_range) { /* 20:500:25 km/h, or conicity 0.02:0.5:25 */
    a->from = a->param == RR_LOCUS_SPEED ? 20 : 0.02;
    a->to = a->param == RR_LOCUS_SPEED ? 500 : 0.5;
    a->n = 25;
  }
  if (a->param == RR_LOCUS_SPEED &&
      !(a->from > 0 && a->to > 0 && fmax(a->from, a->to) <= RR_SPEED_MAX_MS * RR_KMH))
    return cli_bad("--range: speeds must be within (0, %g] km/h", RR_SPEED_MAX_MS * RR_KMH);
  if (a->param == RR_LOCUS_CONICITY &&
      !(a->from >= 0 && a->to >= 0 && fmax(a->from, a->to) <= RR_CONICITY_MAX))
    return cli_bad("--range: conicities must be within [0, %g]", RR_CONICITY_MAX);
  return 0;
}

/* The branches as CSV rows or JSON points; a point where a branch was not
   matched (or not reached) has no row. v0, l0: the fixed speed (km/h) and
   conicity. */
static void locus_print(const cli_common *c, const grid_args *a, const rr_locus_point *pts, int nb,
                        size_t stride, double v0, double l0)
{
  cJSON *root = c->json ? cJSON_CreateObject() : NULL,
        *arr = root ? cJSON_AddArrayToObject(root, "points") : NULL;
  if (!c->json)
    printf("branch,speed_kmh,conicity,freq_hz,real_per_s,imag_rad_per_s,stability_index,mac,"
           "e_carbody,e_frames,e_wheelsets,roll_share,hunting_related,frame_roll_share\n");
  for (int b = 0; b < nb; b++)
    for (int p = 0; p < a->n; p++) {
      const rr_locus_point *lp = &pts[(size_t)p * stride + (size_t)b];
      if (!isfinite(lp->re)) continue;
      double sp = a->param == RR_LOCUS_SPEED ? lp->param * RR_KMH : v0,
             co = a->param == RR_LOCUS_CONICITY ? lp->param : l0;
      if (!c->json) {
        printf("%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.6f,%.6g,%.6g,%.6g,%.6g,%d,%.6g\n", b, sp,
               co, lp->freq_hz, lp->re, lp->im, lp->zeta, lp->mac, lp->energy[0], lp->energy[1],
               lp->energy[2], lp->roll_share, lp->hunting, lp->frame_roll_share);
        continue;
      }
      cJSON *o = cJSON_CreateObject();
      cJSON_AddNumberToObject(o, "branch", b);
      cJSON_AddNumberToObject(o, "speed_kmh", sp);
      cJSON_AddNumberToObject(o, "conicity", co);
      cJSON_AddNumberToObject(o, "freq_hz", lp->freq_hz);
      cJSON_AddNumberToObject(o, "real", lp->re);
      cJSON_AddNumberToObject(o, "imag", lp->im);
      cJSON_AddNumberToObject(o, "stability_index", lp->zeta);
      cJSON_AddNumberToObject(o, "mac", lp->mac);
      cJSON_AddNumberToObject(o, "roll_share", lp->roll_share);
      cJSON_AddNumberToObject(o, "frame_roll_share", lp->frame_roll_share);
      cJSON_AddBoolToObject(o, "hunting_related", lp->hunting);
      cJSON_AddItemToArray(arr, o);
    }
  if (root) cli_json_print(root);
}

/* The locus: point by point with progress (one process), or spread over
   the MPI ranks. Returns 0, CLI_EXIT_STOPPED (the points done in pts) or an
   exit status. */
static int locus_compute(rr_model *m, const cli_common *c, const grid_args *a, const double *vals,
                         rr_locus_point *pts, int *nb)
{
  cli_progress pr;
  cli_catch_stops();
  cli_progress_start(&pr, "locus", a->n, c->progress);
  int r = 0;
  if (cli_par_size() > 1) {
    long ndone = a->n;
    r = locus_mpi(m, c, a->param, vals, a->n, pts, nb, &ndone, &pr);
    if (!r && ndone < a->n) r = CLI_EXIT_STOPPED;
  } else {
    rr_progress hook = cli_progress_hook(&pr);
    rr_error e;
    int st = rr_locus(m, a->param, vals, a->n, &c->mo, &hook, pts, nb, &e);
    r = st == RR_ESTOPPED ? CLI_EXIT_STOPPED : st ? cli_fail(&e, st) : 0;
  }
  cli_progress_end(&pr);
  return r;
}

int cmd_locus(int argc, char **argv)
{
  static const char help[] =
      "usage: railride locus [VEHICLE] [--over speed|conicity] [--range FROM:TO:N] [--speed KMH | "
      "--conicity L] [--json]\n"
      "Root locus: every oscillatory mode followed from point to point by eigenvector\n"
      "correlation (MAC): a branch is born where its mode becomes oscillatory and ends where\n"
      "it turns real (no rows outside its life). Over speed (default 20:500:25 km/h at --conicity, "
      "default 0.17)\n"
      "or conicity (default 0.02:0.5:25 at --speed, default 350 km/h). CSV columns:\n"
      "branch,speed_kmh,conicity,freq_hz,real_per_s,imag_rad_per_s,stability_index,mac,e_carbody,e_"
      "frames,\n"
      "e_wheelsets,roll_share,hunting_related,frame_roll_share (e_*: kinetic energy "
      "shares)\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"over", OPT_PARAM, "P", "parameter swept (--over before --range)"},
      {"range", OPT_RANGE, "FROM:TO:N", "its values"},
      {"limit", OPT_GLIMIT, "N", "most points accepted (default " RR_STR(CLI_LIMIT_LOCUS) ")"},
      CLI_OPT_END};
  cli_common c;
  grid_args a = {.limit = CLI_LIMIT_LOCUS};
  RUN_PARSE(CLI_READS_SPEED | CLI_READS_CONICITY | CLI_READS_JSON | CLI_READS_INDEX |
                CLI_READS_GRAVITY | CLI_READS_PROGRESS,
            extra, grid_cb, &a, help);
  if (a.param == RR_LOCUS_SPEED && c.have_speed)
    return cli_bad("locus: --over speed sweeps the speed (--range); --speed is not read");
  if (a.param == RR_LOCUS_CONICITY && c.have_conicity)
    return cli_bad("locus: --over conicity sweeps the conicity (--range); --conicity is not read");
  if (cli_over_limit("locus", a.n, a.limit, "points")) return EXIT_BADINPUT;
  int r = locus_range(&a);
  rr_model *m;
  if (r || (r = cli_model(&c, &m, 0, 0))) return r;
  double *vals = malloc(sizeof(double) * (size_t)a.n);
  rr_locus_point *pts = malloc(sizeof(rr_locus_point) * (size_t)a.n * (size_t)rr_locus_stride(m));
  int nb = 0;
  if (!vals || !pts) r = cli_bad("out of memory");
  for (int i = 0; i < a.n && !r; i++)
    vals[i] = lin(a.from, a.to, i, a.n) / (a.param == RR_LOCUS_SPEED ? RR_KMH : 1.0);
  if (!r) r = locus_compute(m, &c, &a, vals, pts, &nb);
  if (!r || r == CLI_EXIT_STOPPED) /* stopped: the points done */
    locus_print(&c, &a, pts, nb, (size_t)rr_locus_stride(m), rr_model_speed(m) * RR_KMH,
                rr_model_conicity(m));
  rr_model_free(m);
  free(vals);
  free(pts);
  return r;
}

/* A map point: the index, and (--shares) the hunting mode's frequency and
   kinetic-energy shares, NaN where no mode is hunting-related. */
typedef struct map_cell {
  rr_stability z;
  double hunt_freq_hz, e[RR_NGROUPS];
} map_cell;
#define MAP_COLUMNS                                                                                \
  "speed_kmh,conicity,stability_index,index_freq_hz,zeta_max,stable,index_source,fmax_hz"
#define MAP_SHARE_COLUMNS ",hunting_freq_hz,hunting_e_carbody,hunting_e_frames,hunting_e_wheelsets"

static void map_point(cJSON *arr, double v, double l, const map_cell *cell, int shares)
{
  const rr_stability *z = &cell->z;
  int stable = rr_modal_stable(z->zeta_max);
  if (!arr) { /* an undefined index: empty cells */
    printf("%.10g,%.10g,", v, l);
    cli_csv_num(stdout, z->index, ',');
    cli_csv_num(stdout, z->index_freq_hz, ',');
    printf("%.10g,%d,%s,%.10g%s", z->zeta_max, stable, cli_index_source_key(z->source), z->fmax_hz,
           shares ? "," : "\n");
    for (int g = -1; shares && g < RR_NGROUPS; g++)
      cli_csv_num(stdout, g < 0 ? cell->hunt_freq_hz : cell->e[g], g + 1 < RR_NGROUPS ? ',' : '\n');
    return;
  }
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "speed_kmh", v);
  cJSON_AddNumberToObject(o, "conicity", l);
  cJSON_AddNumberToObject(o, "stability_index", z->index);
  if (isfinite(z->index_freq_hz))
    cJSON_AddNumberToObject(o, "index_freq_hz", z->index_freq_hz);
  else
    cJSON_AddNullToObject(o, "index_freq_hz");
  cJSON_AddStringToObject(o, "index_source", cli_index_source_key(z->source));
  cJSON_AddNumberToObject(o, "zeta_max", z->zeta_max);
  cJSON_AddBoolToObject(o, "stable", stable);
  cJSON_AddNumberToObject(o, "fmax_hz", z->fmax_hz);
  if (shares && isfinite(cell->hunt_freq_hz)) {
    cJSON_AddNumberToObject(o, "hunting_freq_hz", cell->hunt_freq_hz);
    cJSON_AddItemToObject(o, "hunting_energy", cJSON_CreateDoubleArray(cell->e, RR_NGROUPS));
  } else if (shares) {
    cJSON_AddNullToObject(o, "hunting_freq_hz");
    cJSON_AddNullToObject(o, "hunting_energy");
  }
  cJSON_AddItemToArray(arr, o);
}

/* The map's speed rows lo..hi-1, each row's conicities through the batched
   index (SIMD lanes). */
typedef struct map_rows {
  rr_model *m;
  rr_modal_ws *ws;
  const cli_common *c;
  const grid_args *a;
  double *vs, *ls;     /* a row's operating points (c_n each) */
  rr_stability *zs;    /* a row's indices (c_n) */
  rr_modal_result res; /* --shares: every mode of a point */
  rr_error e;
} map_rows;

/* --shares: one full modal solve per point, the hunting mode's shares kept. */
static int map_point_shares(map_rows *w, double v_ms, double l, map_cell *cell)
{
  rr_modal_result *r = &w->res;
  int st = rr_model_set_operating(w->m, v_ms, l, &w->e);
  if (!st) st = rr_modal_solve(w->m, &w->c->mo, w->ws, r, &w->e);
  if (st) return st;
  const rr_mode *imd = r->index_mode >= 0 ? &r->modes[r->index_mode] : NULL;
  const rr_mode *hmd = r->hunting_mode >= 0 ? &r->modes[r->hunting_mode] : NULL;
  cell->z = (rr_stability){.index = r->stability_index,
                           .index_freq_hz = imd ? imd->freq_hz : NAN,
                           .source = r->index_source,
                           .hunting_index = r->hunting_index,
                           .zeta_max = r->zeta_max,
                           .max_freq_hz = r->max_mode >= 0 ? r->modes[r->max_mode].freq_hz : NAN,
                           .fmax_hz = r->fmax_hz};
  cell->hunt_freq_hz = hmd ? hmd->freq_hz : NAN;
  for (int g = 0; g < RR_NGROUPS; g++) cell->e[g] = hmd ? hmd->energy[g] : NAN;
  return 0;
}

static int map_rows_eval(void *user, long lo, long hi, void *out)
{
  map_rows *w = user;
  const grid_args *a = w->a;
  map_cell *cells = out;
  for (long i = lo; i < hi; i++) {
    map_cell *row = cells + (i - lo) * a->c_n;
    for (int j = 0; j < a->c_n; j++) {
      w->vs[j] = lin(a->s_from, a->s_to, (int)i, a->s_n) / RR_KMH;
      w->ls[j] = lin(a->c_from, a->c_to, j, a->c_n);
    }
    int st = 0;
    for (int j = 0; j < a->c_n && a->shares && !st; j++)
      st = map_point_shares(w, w->vs[j], w->ls[j], &row[j]);
    if (!a->shares) {
      st = rr_modal_stability_batch(w->m, &w->c->mo, w->ws, a->c_n, w->vs, w->ls, w->zs, &w->e);
      for (int j = 0; j < a->c_n && !st; j++)
        row[j] = (map_cell){.z = w->zs[j], .hunt_freq_hz = NAN, .e = {NAN, NAN, NAN}};
    }
    if (st) return cli_fail(&w->e, st);
  }
  return 0;
}

/* The map's workspace and results; frees what it made and returns its
   status on failure (then map_rows_free is still safe). */
static void map_rows_free(map_rows *w)
{
  free(w->vs);
  free(w->zs);
  rr_modal_result_free(&w->res);
  rr_modal_ws_free(w->ws);
  rr_model_free(w->m);
  w->vs = NULL, w->zs = NULL, w->ws = NULL, w->m = NULL;
}

static int map_alloc(map_rows *w, size_t npts, map_cell **cells, unsigned char **done)
{
  int st = rr_modal_ws_new(w->m, &w->ws, &w->e);
  if (!st && w->a->shares) st = rr_modal_result_alloc(w->m, &w->res, &w->e);
  if (st) return cli_fail(&w->e, st);
  w->vs = malloc(sizeof(double) * (size_t)w->a->c_n * 2);
  w->ls = w->vs ? w->vs + w->a->c_n : NULL;
  w->zs = malloc(sizeof *w->zs * (size_t)w->a->c_n);
  *cells = malloc(sizeof **cells * npts);
  *done = calloc((size_t)w->a->s_n, 1);
  return w->vs && w->zs && *cells && *done ? 0 : cli_bad("out of memory");
}

int cmd_map(int argc, char **argv)
{
  static const char help[] =
      "usage: railride map [VEHICLE] [--speeds FROM:TO:N] [--conicities FROM:TO:N] [--json]\n"
      "Vehicle stability index over a speed x conicity grid (paper Fig. 7); defaults\n"
      "100:500:41 km/h and 0.02:0.5:25. CSV columns:\n" MAP_COLUMNS "\n"
      "(zeta_max: the largest zeta of any oscillatory mode; stable: 1 when it is < 0;\n"
      "index_source: hunting, unstable_outside_hunting, or none with empty index cells).\n"
      "--shares adds the hunting mode's (the least damped hunting-related one below fmax)\n"
      "frequency and kinetic-energy shares (paper Fig. 14), empty where there is none:\n"
      "hunting_freq_hz,hunting_e_carbody,hunting_e_frames,hunting_e_wheelsets.\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"speeds", OPT_SPEEDS, "FROM:TO:N", "speed grid, km/h"},
      {"conicities", OPT_CONICITIES, "FROM:TO:N", "conicity grid"},
      {"limit", OPT_GLIMIT, "N", "most points accepted (default " RR_STR(CLI_LIMIT_GRID) ")"},
      {"shares", OPT_SHARES, NULL,
       "the hunting mode's energy shares too (a full modal solve a point)"},
      CLI_OPT_END};
  cli_common c;
  grid_args a = {.s_from = 100,
                 .s_to = 500,
                 .s_n = 41,
                 .c_from = 0.02,
                 .c_to = 0.5,
                 .c_n = 25,
                 .limit = CLI_LIMIT_GRID};
  RUN_PARSE(CLI_READS_JSON | CLI_READS_INDEX | CLI_READS_GRAVITY | CLI_READS_PROGRESS, extra,
            grid_cb, &a, help);
  if (!(a.s_from > 0 && a.s_to > 0 && fmax(a.s_from, a.s_to) <= RR_SPEED_MAX_MS * RR_KMH))
    return cli_bad("--speeds: must be within (0, %g] km/h", RR_SPEED_MAX_MS * RR_KMH);
  if (!(a.c_from >= 0 && a.c_to >= 0 && fmax(a.c_from, a.c_to) <= RR_CONICITY_MAX))
    return cli_bad("--conicities: must be within [0, %g]", RR_CONICITY_MAX);
  if (cli_over_limit("map", (double)a.s_n * a.c_n, a.limit, "points")) return EXIT_BADINPUT;
  rr_model *m;
  int r = cli_model(&c, &m, 0, 0);
  if (r) return r;
  map_rows w = {.m = m, .c = &c, .a = &a};
  size_t npts = (size_t)a.s_n * (size_t)a.c_n;
  map_cell *cells = NULL;
  unsigned char *done = NULL;
  r = map_alloc(&w, npts, &cells, &done);
  if (!r) { /* the rows computed (over MPI ranks when run under mpirun), then written */
    cli_progress pr;
    cli_progress_start(&pr, "map", a.s_n, c.progress);
    cli_catch_stops();
    r = cli_par_for(a.s_n, 1, sizeof *cells * (size_t)a.c_n, map_rows_eval, &w, cells, done, &pr);
    cli_progress_end(&pr);
  }
  map_rows_free(&w);
  cJSON *root = c.json && !r ? cJSON_CreateObject() : NULL,
        *arr = root ? cJSON_AddArrayToObject(root, "points") : NULL;
  if (!r && !c.json) printf("%s%s\n", MAP_COLUMNS, a.shares ? MAP_SHARE_COLUMNS : "");
  for (int i = 0; i < a.s_n && !r; i++) /* a stopped run: the rows done */
    for (int j = 0; j < a.c_n && done[i]; j++)
      map_point(arr, lin(a.s_from, a.s_to, i, a.s_n), lin(a.c_from, a.c_to, j, a.c_n),
                &cells[(size_t)i * (size_t)a.c_n + (size_t)j], a.shares);
  free(cells);
  free(done);
  if (r) return r;
  if (root) cli_json_print(root);
  return cli_stopped() ? CLI_EXIT_STOPPED : 0; /* what was done is written */
}
