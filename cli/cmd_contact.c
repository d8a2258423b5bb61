/* `railride contact`: wheel-rail contact geometry and the equivalent
 * conicity from profiles (EN 15302; docs/contact.md): a text summary, the
 * conicity function as CSV, the whole result as JSON, the per-y table to a
 * file. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "outfile.h"
#include "railride/contact.h"

#define CONTACT_MAX_POINTS 200001 /* y grid */
#define CONTACT_MAX_AMPS 10001
#define FLANGE_RAD 0.5 /* a contact angle this steep is flange contact */

typedef struct contact_args {
  const char *wheel[2], *rail[2]; /* right, left (NULL: the other side's) */
  rr_contact_opts o;
  int gmp_auto;
  double y_a, y_b, y_step;
  double *amps;
  long namps;
  double e0; /* NaN: b */
  int json, csv, details;
  const char *grid_path, *plot_data;
} contact_args;

enum {
  OPT_WHEEL = 6000,
  OPT_WHEEL_L,
  OPT_WHEEL_R,
  OPT_RAIL,
  OPT_RAIL_L,
  OPT_RAIL_R,
  OPT_GAUGE,
  OPT_FB,
  OPT_WORIGIN,
  OPT_INCL,
  OPT_GMP,
  OPT_GMPDEPTH,
  OPT_LOFF,
  OPT_RADIUS,
  OPT_RADIUS_R,
  OPT_RADIUS_L,
  OPT_ROLL,
  OPT_YRANGE,
  OPT_AMPS,
  OPT_E0,
  OPT_CJSON,
  OPT_CCSV,
  OPT_NODETAILS,
  OPT_GRID,
  OPT_PLOTDATA
};

/* 1/40, 1:20 or a decimal: the tangent of the rail's inclination. */
static int inclination(const char *arg, double *out)
{
  double a, b;
  char c, tail;
  if ((sscanf(arg, " %lf %c %lf %c", &a, &c, &b, &tail) == 3) && (c == '/' || c == ':') && a > 0 &&
      b > 0) {
    *out = a / b;
    return 0;
  }
  if (cli_number("inclination", arg, "1", out)) return -1;
  return 0;
}

/* a:b:step (inclusive, as the standard's tools make it) or a list. */
static int amplitudes(const char *arg, contact_args *a)
{
  double x, y, st;
  char tail;
  free(a->amps);
  a->amps = NULL;
  if (sscanf(arg, "%lf:%lf:%lf%c", &x, &y, &st, &tail) == 3) {
    a->namps = rr_contact_range(x, y, st, NULL, 0);
    if (a->namps < 1 || a->namps > CONTACT_MAX_AMPS || !(x > 0))
      return cli_bad("--amplitudes: FROM:TO:STEP with 0 < FROM <= TO, STEP > 0, at most %d values",
                     CONTACT_MAX_AMPS);
    a->amps = malloc(sizeof(double) * (size_t)a->namps);
    if (!a->amps) return cli_bad("out of memory");
    rr_contact_range(x, y, st, a->amps, a->namps);
    return 0;
  }
  a->amps = malloc(sizeof(double) * 64);
  int n = 0;
  if (!a->amps || cli_list("amplitudes", arg, "mm", a->amps, 64, &n)) return EXIT_BADINPUT;
  a->namps = n;
  for (int i = 0; i < n; i++)
    if (!(a->amps[i] > 0)) return cli_bad("--amplitudes: amplitudes must be > 0 mm");
  return 0;
}

static int y_range(const char *arg, contact_args *a)
{
  char tail;
  if (sscanf(arg, "%lf:%lf:%lf%c", &a->y_a, &a->y_b, &a->y_step, &tail) != 3)
    return cli_bad("--y-range: FROM:TO:STEP in mm expected (write --y-range=-10:10:0.01)");
  long n = rr_contact_range(a->y_a, a->y_b, a->y_step, NULL, 0);
  if (n < 2 || n > CONTACT_MAX_POINTS || fmax(fabs(a->y_a), fabs(a->y_b)) > 100)
    return cli_bad("--y-range: 2 .. %d points within +-100 mm", CONTACT_MAX_POINTS);
  return 0;
}

static int radius_pair(const char *arg, contact_args *a)
{
  double r[2];
  int n = 0;
  if (cli_list("radius", arg, "mm", r, 2, &n)) return EXIT_BADINPUT;
  a->o.r0_right_mm = r[0];
  a->o.r0_left_mm = n == 2 ? r[1] : r[0];
  return 0;
}

static int contact_option(int opt, const char *arg, contact_args *a)
{
  switch (opt) {
  case OPT_WHEEL: a->wheel[0] = a->wheel[1] = arg; return 0;
  case OPT_WHEEL_R: a->wheel[0] = arg; return 0;
  case OPT_WHEEL_L: a->wheel[1] = arg; return 0;
  case OPT_RAIL: a->rail[0] = a->rail[1] = arg; return 0;
  case OPT_RAIL_R: a->rail[0] = arg; return 0;
  case OPT_RAIL_L: a->rail[1] = arg; return 0;
  case OPT_GAUGE: return cli_number("gauge", arg, "mm", &a->o.gauge_mm) ? EXIT_BADINPUT : 0;
  case OPT_FB:
    return cli_number("flange-back", arg, "mm", &a->o.flange_back_mm) ? EXIT_BADINPUT : 0;
  case OPT_WORIGIN:
    return cli_number("wheel-origin", arg, "mm", &a->o.wheel_origin_mm) ? EXIT_BADINPUT : 0;
  case OPT_INCL: return inclination(arg, &a->o.inclination) ? EXIT_BADINPUT : 0;
  case OPT_GMP:
    if (!strcmp(arg, "auto")) {
      a->o.gmp_right_mm = a->o.gmp_left_mm = NAN;
      return 0;
    }
    if (cli_number("rail-gmp", arg, "mm", &a->o.gmp_right_mm)) return EXIT_BADINPUT;
    a->o.gmp_left_mm = a->o.gmp_right_mm;
    return 0;
  case OPT_GMPDEPTH:
    return cli_number("gmp-depth", arg, "mm", &a->o.gmp_depth_mm) ? EXIT_BADINPUT : 0;
  case OPT_LOFF:
    return cli_number("lateral-offset", arg, "mm", &a->o.lateral_offset_mm) ? EXIT_BADINPUT : 0;
  case OPT_RADIUS: return radius_pair(arg, a);
  case OPT_RADIUS_R:
    return cli_number("radius-right", arg, "mm", &a->o.r0_right_mm) ? EXIT_BADINPUT : 0;
  case OPT_RADIUS_L:
    return cli_number("radius-left", arg, "mm", &a->o.r0_left_mm) ? EXIT_BADINPUT : 0;
  case OPT_ROLL:
    if (!strcmp(arg, "none") || !strcmp(arg, "rigid")) {
      a->o.roll = arg[0] == 'r' ? RR_ROLL_RIGID : RR_ROLL_NONE;
      return 0;
    }
    return cli_bad("--roll: none or rigid expected, got '%s'", arg);
  case OPT_YRANGE: return y_range(arg, a);
  case OPT_AMPS: return amplitudes(arg, a);
  case OPT_E0: return cli_number("e0", arg, "mm", &a->e0) ? EXIT_BADINPUT : 0;
  case OPT_CJSON: a->json = 1; return 0;
  case OPT_CCSV: a->csv = 1; return 0;
  case OPT_NODETAILS: a->details = 0; return 0;
  case OPT_GRID: a->grid_path = arg; return 0;
  case OPT_PLOTDATA: a->plot_data = arg; return 0;
  }
  return EXIT_BADINPUT;
}

static const char contact_help[] =
    "usage: railride contact --wheel W --rail R [options] [--json | --csv]\n"
    "Wheel-rail contact geometry and equivalent conicity from profiles (EN 15302): for the\n"
    "wheelset at each lateral displacement y (positive to the right) the contact point of each\n"
    "wheel on its rail (exact for the polylines: every vertex a candidate, ties to the gauge-most\n"
    "point), rolling radii, dr = r_right - r_left, contact angles; then tan gamma_e(y-hat) by the\n"
    "standard's reference method (the kinematic wavelength against Klingel's), with harmonic\n"
    "linearisation and linear regression beside it. Profiles: two columns (lateral vertical,\n"
    "mm), written for the right-hand side (the left is the mirror). Lengths in mm unless a unit\n"
    "is given. The text summary gives tan gamma_e at 3 mm, y0, contact jumps and the onset of\n"
    "flange contact (contact angle above 0.5 rad); --csv the conicity function: amplitude_mm,\n"
    "tan_gamma_e, tan_gamma_e_harmonic, tan_gamma_e_regression, turning_left_mm,\n"
    "turning_right_mm, wavelength_mm.\n" CLI_COMMON_HELP;

static int contact_parse(int argc, char **argv, contact_args *a)
{
  static const cli_opt opts[] = {
      {"wheel", OPT_WHEEL, "W", "wheel profile, both sides"},
      {"wheel-right", OPT_WHEEL_R, "W", "the right wheel's (E9 of EN 15302: A right, B left)"},
      {"wheel-left", OPT_WHEEL_L, "W", "the left wheel's"},
      {"rail", OPT_RAIL, "R", "rail profile, both sides"},
      {"rail-right", OPT_RAIL_R, "R", "the right rail's"},
      {"rail-left", OPT_RAIL_L, "R", "the left rail's"},
      {"gauge", OPT_GAUGE, "G", "track gauge (default 1435)"},
      {"flange-back", OPT_FB, "FB", "flange-back distance (default 1360)"},
      {"wheel-origin", OPT_WORIGIN, "D", "flange back to the wheel origin (default 70)"},
      {"inclination", OPT_INCL, "I",
       "rail inclination applied to the rail file: 1/40, 1:20 or a decimal (default 0: the file is "
       "in the track frame)"},
      {"rail-gmp", OPT_GMP, "V",
       "the rail file's gauge measuring point, or auto (default: 14 mm below the top of rail, "
       "--gmp-depth)"},
      {"gmp-depth", OPT_GMPDEPTH, "D", "depth of the gauge measuring point (default 14)"},
      {"lateral-offset", OPT_LOFF, "D",
       "the wheel origin less the rail origin, both sides (instead of placing)"},
      {"radius", OPT_RADIUS, "R", "nominal rolling radius, or R_RIGHT,R_LEFT (default 460)"},
      {"radius-right", OPT_RADIUS_R, "R", "the right wheel's nominal radius"},
      {"radius-left", OPT_RADIUS_L, "R", "the left wheel's"},
      {"roll", OPT_ROLL, "M",
       "none (default, the EN 15302 benchmark) or rigid (the wheelset's roll solved so that both "
       "wheels touch)"},
      {"y-range", OPT_YRANGE, "=A:B:STEP", "the lateral grid (default -10:10:0.01)"},
      {"amplitudes", OPT_AMPS, "A:B:STEP",
       "amplitudes for tan gamma_e, or a list A1,A2,.. (default 0.5:10:0.1)"},
      {"e0", OPT_E0, "E",
       "Klingel half contact spacing for the wavelength (default: the wheel origin's, flange back "
       "/ 2 + wheel origin)"},
      {"grid", OPT_GRID, "FILE.csv",
       "write the per-y table (dr, radii, angles, contact points, validity)"},
      {"plot-data", OPT_PLOTDATA, "FILE",
       "write what --plot draws (gnuplot data: the grid, the conicity function, the right wheel on "
       "its rail at y = 0 and at the flange)"},
      {"no-contact-details", OPT_NODETAILS, NULL, "leave the contact points out of the JSON"},
      {"json", OPT_CJSON, NULL, "JSON output"},
      {"csv", OPT_CCSV, NULL, "the conicity function as CSV"},
      CLI_OPT_HELP_ROW,
      CLI_OPT_END};
  optind = 1;
  cli_opt_state os = {.nseen = 0};
  int opt, got;
  while ((got = cli_next_option("contact", argc, argv, opts, &os, &opt)) != 0) {
    if (got < 0) return EXIT_BADINPUT;
    if (opt == 'h') {
      cli_help_print("contact", contact_help, opts);
      return CLI_HELP_SHOWN;
    }
    int r = contact_option(opt, optarg, a);
    if (r) return r;
  }
  if (optind < argc) return cli_bad("contact: unexpected argument '%s'", argv[optind]);
  if (!a->wheel[0] || !a->wheel[1] || !a->rail[0] || !a->rail[1])
    return cli_bad("contact: --wheel (or --wheel-right and --wheel-left) and --rail are required");
  if (a->json && a->csv) return cli_bad("contact: --json or --csv, not both");
  return 0;
}

/* The result of a run: the grid's states, the conicity per amplitude. */
typedef struct contact_run {
  rr_contact_setup su;
  double *y;
  long n;
  rr_contact_state *st;
  rr_conicity *cs;
  rr_conicity c3;
  double y0, first, last, e0, r0;
  rr_contact_jump jumps[64];
  int njumps;
} contact_run;

static int load_profiles(const contact_args *a, rr_polyline *p)
{
  const char *names[4] = {a->wheel[0], a->wheel[1], a->rail[0], a->rail[1]};
  rr_error e;
  for (int k = 0; k < 4; k++) {
    int same = -1;
    for (int j = 0; j < k; j++)
      if (!strcmp(names[j], names[k]) && (j < 2) == (k < 2)) same = j;
    if (same >= 0) {
      p[k] = p[same];
      continue;
    }
    int st = rr_polyline_load(names[k], &p[k], &e);
    if (st) return cli_fail(&e, st);
  }
  return 0;
}

static int contact_compute(const contact_args *a, const rr_polyline *p, contact_run *r)
{
  rr_error e;
  rr_contact_plan *plan = NULL;
  rr_conicity_plan *cp = NULL;
  r->n = rr_contact_range(a->y_a, a->y_b, a->y_step, NULL, 0);
  r->y = malloc(sizeof(double) * (size_t)r->n);
  r->st = malloc(sizeof *r->st * (size_t)r->n);
  r->cs = malloc(sizeof *r->cs * (size_t)a->namps);
  double *dr = malloc(sizeof(double) * (size_t)r->n);
  int *valid = malloc(sizeof(int) * (size_t)r->n);
  int st = RR_OK;
  if (!r->y || !r->st || !r->cs || !dr || !valid) {
    free(dr);
    free(valid);
    return cli_bad("out of memory");
  }
  {
    rr_contact_range(a->y_a, a->y_b, a->y_step, r->y, r->n);
    st = rr_contact_plan_new(&p[0], &p[1], &p[2], &p[3], &a->o, &plan, &e);
  }
  if (!st) st = rr_contact_execute(plan, r->y, (int)r->n, r->st, &e);
  if (!st) {
    rr_contact_plan_setup(plan, &r->su);
    for (long i = 0; i < r->n; i++) {
      dr[i] = r->st[i].dr_mm;
      valid[i] = r->st[i].valid;
    }
    st = rr_conicity_plan_new(r->y, dr, valid, (int)r->n, &cp, &e);
  }
  if (!st) {
    r->e0 = isnan(a->e0) ? r->su.b_mm : a->e0;
    r->r0 = (r->su.r0_mm[0] + r->su.r0_mm[1]) / 2;
    r->y0 = rr_conicity_y0(cp);
    rr_conicity_range(cp, &r->first, &r->last);
    for (long k = 0; k < a->namps; k++) rr_conicity_eval(cp, a->amps[k], r->e0, r->r0, &r->cs[k]);
    rr_conicity_eval(cp, 3.0, r->e0, r->r0, &r->c3);
    r->njumps = rr_contact_jumps(r->st, (int)r->n, r->jumps, 64);
  }
  rr_conicity_plan_free(cp);
  rr_contact_plan_free(plan);
  free(dr);
  free(valid);
  return st ? cli_fail(&e, st) : 0;
}

/* One field of every state, as a JSON array. */
typedef double (*state_field)(const rr_contact_state *s);
#define FIELD(name, expr)                                                                          \
  static double name(const rr_contact_state *s) { return expr; }
FIELD(f_y, s->y_mm)
FIELD(f_dr, s->dr_mm)
FIELD(f_rr, s->side[0].r_mm)
FIELD(f_rl, s->side[1].r_mm)
FIELD(f_gr, s->side[0].gamma_rad)
FIELD(f_gl, s->side[1].gamma_rad)
FIELD(f_roll, s->roll_rad)
FIELD(f_rolli, s->roll_implied_rad)
FIELD(f_lr, s->side[0].lift_mm)
FIELD(f_ll, s->side[1].lift_mm)
FIELD(f_cvr, s->side[0].rail_v_mm)
FIELD(f_czr, s->side[0].rail_z_mm)
FIELD(f_cur, s->side[0].wheel_u_mm)
FIELD(f_cwr, s->side[0].wheel_z_mm)
FIELD(f_cvl, s->side[1].rail_v_mm)
FIELD(f_czl, s->side[1].rail_z_mm)
FIELD(f_cul, s->side[1].wheel_u_mm)
FIELD(f_cwl, s->side[1].wheel_z_mm)

static const struct {
  const char *key;
  state_field f;
  int detail; /* a contact point (left out with --no-contact-details) */
} state_keys[] = {
    {"y_mm", f_y, 0},
    {"dr_mm", f_dr, 0},
    {"r_right_mm", f_rr, 0},
    {"r_left_mm", f_rl, 0},
    {"gamma_right_rad", f_gr, 0},
    {"gamma_left_rad", f_gl, 0},
    {"roll_rad", f_roll, 0},
    {"roll_implied_rad", f_rolli, 0},
    {"lift_right_mm", f_lr, 0},
    {"lift_left_mm", f_ll, 0},
    {"contact_rail_right_mm", f_cvr, 1},
    {"contact_rail_z_right_mm", f_czr, 1},
    {"contact_wheel_right_mm", f_cur, 1},
    {"contact_wheel_z_right_mm", f_cwr, 1},
    {"contact_rail_left_mm", f_cvl, 1},
    {"contact_rail_z_left_mm", f_czl, 1},
    {"contact_wheel_left_mm", f_cul, 1},
    {"contact_wheel_z_left_mm", f_cwl, 1},
};
#define NSTATE_KEYS (int)(sizeof state_keys / sizeof state_keys[0])

static cJSON *state_array(const contact_run *r, state_field f)
{
  cJSON *arr = cJSON_CreateArray();
  for (long i = 0; i < r->n; i++) cJSON_AddItemToArray(arr, cJSON_CreateNumber(f(&r->st[i])));
  return arr;
}

static cJSON *setup_json(const contact_args *a, const contact_run *r)
{
  cJSON *s = cJSON_CreateObject();
  const char *side[2] = {"right", "left"};
  char key[48];
  cJSON_AddNumberToObject(s, "radius_right_mm", r->su.r0_mm[0]);
  cJSON_AddNumberToObject(s, "radius_left_mm", r->su.r0_mm[1]);
  cJSON_AddNumberToObject(s, "inclination", a->o.inclination);
  cJSON_AddNumberToObject(s, "wheel_origin_lateral_mm", r->su.b_mm);
  for (int k = 0; k < 2; k++) {
    snprintf(key, sizeof key, "rail_origin_lateral_%s_mm", side[k]);
    cJSON_AddNumberToObject(s, key, r->su.Y_mm[k]);
    snprintf(key, sizeof key, "offset_%s_mm", side[k]);
    cJSON_AddNumberToObject(s, key, r->su.offset_mm[k]);
  }
  for (int k = 0; k < 2; k++) {
    snprintf(key, sizeof key, "gmp_%s", side[k]);
    cJSON *g = cJSON_AddObjectToObject(s, key);
    cJSON_AddNumberToObject(g, "v_mm", r->su.gmp_v_mm[k]);
    cJSON_AddNumberToObject(g, "z_mm", r->su.gmp_z_mm[k]);
    cJSON_AddBoolToObject(g, "at_data_end", r->su.gmp_at_data_end[k]);
  }
  return s;
}

static void amplitude_json(cJSON *root, const contact_args *a, const contact_run *r)
{
  cJSON *amp = cJSON_AddArrayToObject(root, "amplitude_mm"),
        *tg = cJSON_AddArrayToObject(root, "tan_gamma_e"),
        *th = cJSON_AddArrayToObject(root, "tan_gamma_e_harmonic"),
        *tr = cJSON_AddArrayToObject(root, "tan_gamma_e_regression"),
        *tp = cJSON_AddArrayToObject(root, "turning_points_mm"),
        *hc = cJSON_AddArrayToObject(root, "harmonic_centre_mm"),
        *wl = cJSON_AddArrayToObject(root, "wavelength_mm");
  for (long k = 0; k < a->namps; k++) {
    const rr_conicity *c = &r->cs[k];
    cJSON_AddItemToArray(amp, cJSON_CreateNumber(c->amplitude_mm));
    cJSON_AddItemToArray(tg, cJSON_CreateNumber(c->tan_gamma_e));
    cJSON_AddItemToArray(th, cJSON_CreateNumber(c->tan_gamma_e_harmonic));
    cJSON_AddItemToArray(tr, cJSON_CreateNumber(c->tan_gamma_e_regression));
    cJSON_AddItemToArray(tp, cJSON_CreateDoubleArray(c->turning_mm, 2));
    cJSON_AddItemToArray(hc, cJSON_CreateNumber(c->harmonic_centre_mm));
    cJSON_AddItemToArray(wl,
                         cJSON_CreateNumber(isfinite(c->wavelength_mm) ? c->wavelength_mm : NAN));
  }
}

static void contact_json(const contact_args *a, const contact_run *r)
{
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "method", "EN 15302 wavelength (a); harmonic (b); regression (c)");
  cJSON_AddStringToObject(root, "roll_mode", a->o.roll == RR_ROLL_RIGID ? "rigid" : "none");
  cJSON_AddItemToObject(root, "setup", setup_json(a, r));
  for (int k = 0; k < NSTATE_KEYS; k++)
    if (a->details || !state_keys[k].detail)
      cJSON_AddItemToObject(root, state_keys[k].key, state_array(r, state_keys[k].f));
  cJSON *v = cJSON_AddArrayToObject(root, "valid");
  for (long i = 0; i < r->n; i++) cJSON_AddItemToArray(v, cJSON_CreateBool(r->st[i].valid));
  cJSON *js = cJSON_AddArrayToObject(root, "jumps");
  for (int k = 0; k < r->njumps && k < 64; k++) {
    const rr_contact_jump *j = &r->jumps[k];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "side", j->side ? "left" : "right");
    cJSON_AddNumberToObject(o, "y_from", j->y_from_mm);
    cJSON_AddNumberToObject(o, "y_to", j->y_to_mm);
    cJSON_AddNumberToObject(o, "rail_from", j->rail_from_mm);
    cJSON_AddNumberToObject(o, "rail_to", j->rail_to_mm);
    cJSON_AddNumberToObject(o, "wheel_from", j->wheel_from_mm);
    cJSON_AddNumberToObject(o, "wheel_to", j->wheel_to_mm);
    cJSON_AddItemToArray(js, o);
  }
  cJSON_AddNumberToObject(root, "y0_mm", r->y0);
  double range[2] = {r->first, r->last};
  cJSON_AddItemToObject(root, "conicity_range_mm", cJSON_CreateDoubleArray(range, 2));
  amplitude_json(root, a, r);
  cJSON_AddNumberToObject(root, "klingel_e0_mm", r->e0);
  cJSON_AddNumberToObject(root, "klingel_r0_mm", r->r0);
  cJSON_AddNumberToObject(root, "tan_gamma_e_3mm", r->c3.tan_gamma_e);
  cJSON_AddNumberToObject(root, "tan_gamma_e_harmonic_3mm", r->c3.tan_gamma_e_harmonic);
  cJSON_AddNumberToObject(root, "tan_gamma_e_regression_3mm", r->c3.tan_gamma_e_regression);
  cli_json_print(root);
}

static void contact_csv(const contact_args *a, const contact_run *r)
{
  printf("amplitude_mm,tan_gamma_e,tan_gamma_e_harmonic,tan_gamma_e_regression,turning_left_mm,"
         "turning_right_mm,wavelength_mm\n");
  for (long k = 0; k < a->namps; k++) {
    const rr_conicity *c = &r->cs[k];
    printf("%.10g,", c->amplitude_mm);
    cli_csv_num(stdout, c->tan_gamma_e, ',');
    cli_csv_num(stdout, c->tan_gamma_e_harmonic, ',');
    cli_csv_num(stdout, c->tan_gamma_e_regression, ',');
    cli_csv_num(stdout, c->turning_mm[0], ',');
    cli_csv_num(stdout, c->turning_mm[1], ',');
    cli_csv_num(stdout, isfinite(c->wavelength_mm) ? c->wavelength_mm : NAN, '\n');
  }
}

/* The first displacement on each side at which the approaching wheel's
   contact angle passes FLANGE_RAD (NaN when none in the grid). */
static void flange_onset(const contact_run *r, double *right, double *left)
{
  *right = *left = NAN;
  for (long i = 0; i < r->n; i++) {
    const rr_contact_state *s = &r->st[i];
    if (s->y_mm > 0 && isnan(*right) && s->side[0].gamma_rad > FLANGE_RAD) *right = s->y_mm;
  }
  for (long i = r->n - 1; i >= 0; i--) {
    const rr_contact_state *s = &r->st[i];
    if (s->y_mm < 0 && isnan(*left) && s->side[1].gamma_rad > FLANGE_RAD) *left = s->y_mm;
  }
}

static void contact_text(const contact_args *a, const contact_run *r)
{
  char b1[32], b2[32], b3[32];
  printf("wheel %s / %s on rail %s / %s (right / left), roll %s\n", a->wheel[0], a->wheel[1],
         a->rail[0], a->rail[1], a->o.roll == RR_ROLL_RIGID ? "rigid" : "none");
  printf("  placement: wheel origins at +-%g mm, offsets %.4f / %.4f mm, gauge points %.4f / "
         "%.4f mm%s\n",
         r->su.b_mm, r->su.offset_mm[0], r->su.offset_mm[1], r->su.gmp_v_mm[0], r->su.gmp_v_mm[1],
         r->su.gmp_at_data_end[0] || r->su.gmp_at_data_end[1] ? " (at a data end)" : "");
  printf("  y0 = %s mm; valid data %s .. %s mm\n", cli_num_or_none(b1, sizeof b1, r->y0),
         cli_num_or_none(b2, sizeof b2, r->first), cli_num_or_none(b3, sizeof b3, r->last));
  printf("  tan gamma_e at 3 mm: %s (EN 15302 wavelength method); harmonic %s, regression %s\n",
         cli_num_or_none(b1, sizeof b1, r->c3.tan_gamma_e),
         cli_num_or_none(b2, sizeof b2, r->c3.tan_gamma_e_harmonic),
         cli_num_or_none(b3, sizeof b3, r->c3.tan_gamma_e_regression));
  double fr, fl;
  flange_onset(r, &fr, &fl);
  printf("  flange contact (contact angle > %g rad) from y = %s mm (right) and %s mm (left)\n",
         FLANGE_RAD, cli_num_or_none(b1, sizeof b1, fr), cli_num_or_none(b2, sizeof b2, fl));
  printf("  contact jumps (> 1 mm on the rail): %d\n", r->njumps);
  for (int k = 0; k < r->njumps && k < 64; k++)
    printf("    %s: y %.3f -> %.3f mm, rail %.3f -> %.3f mm\n", r->jumps[k].side ? "left" : "right",
           r->jumps[k].y_from_mm, r->jumps[k].y_to_mm, r->jumps[k].rail_from_mm,
           r->jumps[k].rail_to_mm);
}

static int contact_grid(const contact_run *r, const char *path)
{
  cli_outfile out;
  int rc = cli_out_open(&out, path, "--grid");
  if (rc) return rc;
  for (int k = 0; k < NSTATE_KEYS; k++) fprintf(out.fp, "%s,", state_keys[k].key);
  fprintf(out.fp, "valid\n");
  for (long i = 0; i < r->n; i++) {
    for (int k = 0; k < NSTATE_KEYS; k++) fprintf(out.fp, "%.12g,", state_keys[k].f(&r->st[i]));
    fprintf(out.fp, "%d\n", r->st[i].valid);
  }
  return cli_out_commit(&out);
}

/* The right wheel (at displacement y, lowered onto its rail) and its rail in
   track coordinates (mm from the track centre), one block each. */
static void wheel_on_rail(FILE *fp, const rr_polyline *p, const contact_run *r, long i)
{
  const rr_contact_state *s = &r->st[i];
  for (int k = 0; k < p[2].n; k++) fprintf(fp, "%.6g %.6g\n", r->su.Y_mm[0] + p[2].x[k], p[2].z[k]);
  fputs("\n\n", fp);
  for (int k = 0; k < p[0].n; k++)
    fprintf(fp, "%.6g %.6g\n", s->y_mm + r->su.b_mm + p[0].x[k], p[0].z[k] + s->side[0].lift_mm);
  fprintf(fp, "\n\n%.6g %.6g\n\n\n", r->su.Y_mm[0] + s->side[0].rail_v_mm, s->side[0].rail_z_mm);
}

/* What --plot draws, as gnuplot data blocks (index 0 the grid: y dr
   gamma_right gamma_left rail_right rail_left wheel_right wheel_left; 1 the
   conicity function; 2-4 and 5-7 the right wheel on its rail at y = 0 and at
   the onset of flange contact; comments give the labels). */
static int contact_plot_data(const contact_args *a, const rr_polyline *p, const contact_run *r,
                             const char *path)
{
  cli_outfile out;
  int rc = cli_out_open(&out, path, "--plot-data");
  if (rc) return rc;
  FILE *fp = out.fp;
  double fr, fl;
  flange_onset(r, &fr, &fl);
  long i0 = 0, i1 = 0;
  for (long i = 0; i < r->n; i++) {
    if (fabs(r->st[i].y_mm) < fabs(r->st[i0].y_mm)) i0 = i;
    if (!isnan(fr) && r->st[i].y_mm == fr) i1 = i;
  }
  if (isnan(fr)) i1 = r->n - 1;
  fprintf(fp, "# tan_gamma_e at 3 mm: %.4f; y0 = %.4f mm; wheel %s on rail %s\n", r->c3.tan_gamma_e,
          r->y0, a->wheel[0], a->rail[0]);
  fprintf(fp, "# shown at y = %.3f and %.3f mm\n", r->st[i0].y_mm, r->st[i1].y_mm);
  for (long i = 0; i < r->n; i++) {
    const rr_contact_state *s = &r->st[i];
    if (!s->valid) continue;
    fprintf(fp, "%.6g %.8g %.6g %.6g %.6g %.6g %.6g %.6g\n", s->y_mm, s->dr_mm,
            s->side[0].gamma_rad, s->side[1].gamma_rad, s->side[0].rail_v_mm, s->side[1].rail_v_mm,
            s->side[0].wheel_u_mm, s->side[1].wheel_u_mm);
  }
  fputs("\n\n", fp);
  for (long k = 0; k < a->namps; k++) {
    const rr_conicity *c = &r->cs[k];
    fprintf(fp, "%.6g %.8g %.8g %.8g\n", c->amplitude_mm,
            isnan(c->tan_gamma_e) ? NAN : c->tan_gamma_e, c->tan_gamma_e_harmonic,
            c->tan_gamma_e_regression);
  }
  fputs("\n\n", fp);
  wheel_on_rail(fp, p, r, i0);
  wheel_on_rail(fp, p, r, i1);
  return cli_out_commit(&out);
}

int cmd_contact(int argc, char **argv)
{
  contact_args a = {.o = rr_contact_opts_default(),
                    .y_a = -10,
                    .y_b = 10,
                    .y_step = 0.01,
                    .e0 = NAN,
                    .details = 1};
  int r = amplitudes("0.5:10:0.1", &a);
  if (!r) r = contact_parse(argc, argv, &a);
  rr_polyline p[4] = {{0}};
  contact_run run = {0};
  if (!r) r = load_profiles(&a, p);
  if (!r) r = contact_compute(&a, p, &run);
  if (!r && a.grid_path) r = contact_grid(&run, a.grid_path);
  if (!r && a.plot_data) r = contact_plot_data(&a, p, &run, a.plot_data);
  if (!r && a.json)
    contact_json(&a, &run);
  else if (!r && a.csv)
    contact_csv(&a, &run);
  else if (!r)
    contact_text(&a, &run);
  int dup[4] = {0}; /* a profile shared by two sides is freed once */
  for (int k = 0; k < 4; k++)
    for (int j = 0; j < k; j++) dup[k] |= p[k].x && p[j].x == p[k].x;
  for (int k = 0; k < 4; k++)
    if (!dup[k]) rr_polyline_free(&p[k]);
  free(run.y);
  free(run.st);
  free(run.cs);
  free(a.amps);
  return r == CLI_HELP_SHOWN ? 0 : r;
}
