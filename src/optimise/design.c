/* Design contexts: allocation-free evaluation of objectives for optimisers. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include "railride/comfort.h"
#include "railride/design.h"
#include "railride/problem.h"
#include "railride/modal.h"
#include "railride/stability.h"
#include "railride/pem.h"
#include "railride/ride.h"
#include "railride/spectrum.h"
#include "railride/vertical.h"
#include "model/model_impl.h"
#include "util/internal.h"

/* One model per SDF variant an objective asks for: the vehicle's own, none,
   paper, physical. */
#define MAX_MODELS 4
/* Designs evaluated together when every objective is a robust index: their
   points share the SIMD lanes (8 designs of 9 points fill 9 groups of 8). */
#define DESIGN_GROUP 8
enum { MO_FMAX = 1, MO_WMIN = 2, MO_RMAX = 4 };

enum obj_kind {
  OBJ_ZETA_LOW,
  OBJ_ZETA_HIGH,
  OBJ_STD_ZETA,
  OBJ_INDEX,
  OBJ_CRITICAL,
  OBJ_SPERLING,
  OBJ_SPERLING_GB,
  OBJ_WD_RMS,
  OBJ_RMS,
  OBJ_N_MV, /* EN 12299 N_MV: the lateral and the vertical model */
  /* the vertical model alone */
  OBJ_SPERLING_Z,
  OBJ_SPERLING_GB_Z,
  OBJ_WB_RMS,
  OBJ_WB_P95,
  OBJ_RMS_Z,
  OBJ_N_MV_Z
};

typedef struct objective {
  char text[128];
  int kind, sdf; /* sdf: -1 keeps the vehicle's */
  double speed_ms, conicity, x;
  char spectrum[64];
  rr_modal_opts mo; /* the index's rule; fields set by modifiers flagged in mo_set */
  unsigned mo_set;
  int index_modes; /* critical_speed: only the index's modes count */
  double vmax_ms;  /* critical_speed: the range's end (vmax=KMH; default the library's) */
  int at_bound;    /* critical_speed: stable to vmax_ms, the value is that bound */
  double fmax_hz;  /* index: the band edge of the last value (NaN for the others) */
  int verdict;     /* index, lateral ride: 1 stable, 0 unstable at its point; -1 not taken */
  double freq_hz;  /* frequency of the mode behind the last value (NaN if none) */
  int model;       /* index into the design's models */
  /* ride resources */
  rr_ride_plan *plan; /* one floor point at x */
  rr_spectrum sp;
  /* the vertical model's */
  char vspectrum[64];
  rr_spectrum vsp;
  rr_vertical_plan *vplan;
} objective;

struct rr_design {
  rr_vehicle base, cur;
  int nvar, nobj;
  char keys[RR_DESIGN_MAX_VARS][64];
  const rr_vehicle_key *key[RR_DESIGN_MAX_VARS];
  char objtext[RR_DESIGN_MAX_OBJS][128];
  objective obj[RR_DESIGN_MAX_OBJS];
  rr_modal_opts mo; /* the rule of objectives without modifiers */
  int nmodels;
  int model_sdf[MAX_MODELS]; /* sdf mode of each model (-1: the vehicle's) */
  rr_model *model[MAX_MODELS];
  rr_modal_ws *ws[MAX_MODELS];
  rr_system *scratch;
  int nclones;
  rr_design **clones;
  rr_model *member[DESIGN_GROUP - 1][MAX_MODELS]; /* models of a group's other designs */
};

/* rr_critical_opts_default's range, for the objective's description */
#define CRITICAL_RANGE RR_STR(RR_CRITICAL_V_MIN_KMH) "-" RR_STR(RR_CRITICAL_V_MAX_KMH) " km/h"
#define CRITICAL_TOP RR_STR(RR_CRITICAL_V_MAX_KMH)
static const rr_objective_info objective_docs[] = {
    {"zeta_low", "", "1",
     "vehicle stability index at 250 km/h, conicity 0.05 (paper Table 1; negative is "
     "stable)"},
    {"zeta_high", "", "1", "vehicle stability index at 350 km/h, conicity 0.40"},
    {"std_zeta", "", "1",
     "population standard deviation of the index at 350 km/h over 8 conicities 0.05-0.40"},
    {"index", "KMH,L", "1", "vehicle stability index at speed KMH, conicity L"},
    {"critical_speed", "L", "km/h",
     "lowest speed (" CRITICAL_RANGE ") at which an oscillatory mode has zeta >= 0; " CRITICAL_TOP
     " when none"},
    {"sperling", "KMH,L[,X]", "1",
     "Sperling index, weighting-filter method, floor point x = X m (default 0)"},
    {"sperling_gb", "KMH,L[,X]", "1", "Sperling index, GB/T 5599 line method"},
    {"wd_rms", "KMH,L[,X]", "m/s^2", "ISO 2631-1 / EN 12299 Wd-weighted lateral acceleration RMS"},
    {"rms", "KMH,L[,X]", "m/s^2", "unweighted lateral acceleration RMS, 0.3-30 Hz"},
    {"n_mv", "KMH,L[,X]", "1",
     "EN 12299 mean comfort N_MV at floor point X: the lateral Wd and vertical Wb 5 s RMS P95 "
     "(longitudinal 0)"},
    {"sperling_z", "KMH[,X]", "1", "vertical Sperling index (weighting filter), vertical model"},
    {"sperling_gb_z", "KMH[,X]", "1", "vertical Sperling index, GB/T 5599 line method"},
    {"wb_rms", "KMH[,X]", "m/s^2", "EN 12299 Wb-weighted vertical acceleration RMS"},
    {"wb_p95", "KMH[,X]", "m/s^2", "95th percentile of the 5 s Wb-weighted vertical RMS"},
    {"rms_z", "KMH[,X]", "m/s^2", "unweighted vertical acceleration RMS, 0.3-30 Hz"},
    {"n_mv_z", "KMH[,X]", "1", "N_MV's vertical term 6 a_ZP95"},
};

const rr_objective_info *rr_objectives(int *n)
{
  *n = (int)(sizeof objective_docs / sizeof objective_docs[0]);
  return objective_docs;
}

static const struct objective_name {
  const char *name;
  int kind, nargs_min, nargs_max;
} objective_names[] = {
    {"zeta_low", OBJ_ZETA_LOW, 0, 0},
    {"zeta_high", OBJ_ZETA_HIGH, 0, 0},
    {"std_zeta", OBJ_STD_ZETA, 0, 0},
    {"index", OBJ_INDEX, 2, 2},
    {"critical_speed", OBJ_CRITICAL, 1, 1},
    {"sperling", OBJ_SPERLING, 2, 3},
    {"sperling_gb", OBJ_SPERLING_GB, 2, 3},
    {"wd_rms", OBJ_WD_RMS, 2, 3},
    {"rms", OBJ_RMS, 2, 3},
    {"n_mv", OBJ_N_MV, 2, 3},
    {"sperling_z", OBJ_SPERLING_Z, 1, 2},
    {"sperling_gb_z", OBJ_SPERLING_GB_Z, 1, 2},
    {"wb_rms", OBJ_WB_RMS, 1, 2},
    {"wb_p95", OBJ_WB_P95, 1, 2},
    {"rms_z", OBJ_RMS_Z, 1, 2},
    {"n_mv_z", OBJ_N_MV_Z, 1, 2},
};
#define NOBJ_NAMES (int)(sizeof objective_names / sizeof objective_names[0])

static int is_ride(int kind) { return kind >= OBJ_SPERLING; }
/* the objectives that run the lateral PEM, and those that run the vertical */
static int is_lateral_ride(int kind) { return kind >= OBJ_SPERLING && kind <= OBJ_N_MV; }
static int is_vertical(int kind) { return kind >= OBJ_N_MV; }
static int is_vertical_only(int kind) { return kind > OBJ_N_MV; }
/* What objectives' arguments accept: a floor point within 100 m of the car
   centre (as the command line's --points), the index band 1 mHz .. 1 MHz. */
#define OBJ_X_MAX_M 100.0
#define OBJ_FMAX_MIN_HZ 1e-3
#define OBJ_FMAX_MAX_HZ 1e6
/* The objectives made of the stability index (which may be undefined). */
static int is_index(int kind) { return kind <= OBJ_INDEX; }
static int is_robust(int kind) { return kind <= OBJ_STD_ZETA; }
static int is_stability(int kind) { return !is_ride(kind); }

/* A finite number, the whole token. */
static int number(const char *t, double *v)
{
  char *end;
  *v = strtod(t, &end);
  return end != t && !*end && isfinite(*v) ? 0 : -1;
}

/* The numbers after '@' (a comma list, at most 3) into a, their count to *na. */
static int read_args(char *at, const char *text, double *a, int *na, rr_error *err)
{
  char *sv;
  *na = 0;
  for (char *t = at ? strtok_r(at, ",", &sv) : NULL; t; t = strtok_r(NULL, ",", &sv)) {
    if (*na >= 3) return rr_seterr(err, RR_EINVAL, "objective '%s': too many arguments", text);
    if (number(t, &a[(*na)++]))
      return rr_seterr(err, RR_EINVAL, "objective '%s': '%s' is not a number", text, t);
  }
  return RR_OK;
}

static int parse_args(char *at, const struct objective_name *nm, objective *o, rr_error *err)
{
  double a[3] = {0, 0, 0};
  int na, st = read_args(at, o->text, a, &na, err);
  if (st) return st;
  if (na < nm->nargs_min || na > nm->nargs_max)
    return rr_seterr(err, RR_EINVAL, "objective '%s': %d to %d arguments expected after '@'",
                     o->text, nm->nargs_min, nm->nargs_max);
  if (o->kind == OBJ_CRITICAL)
    o->conicity = a[0];
  else if (is_vertical_only(o->kind)) {
    o->speed_ms = a[0] / RR_KMH;
    o->x = na == 2 ? a[1] : 0;
  } else if (na >= 2) {
    o->speed_ms = a[0] / RR_KMH;
    o->conicity = a[1];
    o->x = na == 3 ? a[2] : 0;
  }
  if ((na >= 2 || is_vertical_only(o->kind)) &&
      !(o->speed_ms > 0 && o->speed_ms <= RR_SPEED_MAX_MS))
    return rr_seterr(err, RR_EINVAL, "objective '%s': speed must be within (0, %g] km/h", o->text,
                     RR_SPEED_MAX_MS * RR_KMH);
  if (!(o->conicity >= 0 && o->conicity <= RR_CONICITY_MAX))
    return rr_seterr(err, RR_EINVAL, "objective '%s': conicity must be within [0, %g]", o->text,
                     RR_CONICITY_MAX);
  if (!(fabs(o->x) <= OBJ_X_MAX_M))
    return rr_seterr(err, RR_EINVAL,
                     "objective '%s': the floor point must be within %g m of the "
                     "car centre",
                     o->text, OBJ_X_MAX_M);
  return RR_OK;
}

static int parse_rule(const char *t, objective *o, rr_error *err)
{
  double v;
  const char *eq = strchr(t, '=');
  if (!eq || number(eq + 1, &v))
    return rr_seterr(err, RR_EINVAL, "objective '%s': '%s' needs a number", o->text, t);
  size_t k = (size_t)(eq - t);
  if (k == 4 && !strncmp(t, "fmax", 4) && v >= OBJ_FMAX_MIN_HZ && v <= OBJ_FMAX_MAX_HZ) {
    o->mo.fmax_hz = v;
    o->mo_set |= MO_FMAX;
  } else if (k == 4 && !strncmp(t, "wmin", 4) && v >= 0 && v <= 1) {
    o->mo.w_min = v;
    o->mo_set |= MO_WMIN;
  } else if (k == 4 && !strncmp(t, "rmax", 4) && v >= 0 && v <= 1) {
    o->mo.r_max = v;
    o->mo_set |= MO_RMAX;
  } else
    return rr_seterr(err, RR_EINVAL,
                     "objective '%s': '%s' out of range (fmax %g .. %g Hz, wmin and rmax in 0..1)",
                     o->text, t, OBJ_FMAX_MIN_HZ, OBJ_FMAX_MAX_HZ);
  return RR_OK;
}

static int parse_option(const char *t, objective *o, rr_error *err)
{
  if (!strncmp(t, "sdf=", 4)) {
    if (!strcmp(t + 4, "none"))
      o->sdf = RR_SDF_NONE;
    else if (!strcmp(t + 4, "paper"))
      o->sdf = RR_SDF_PAPER;
    else if (!strcmp(t + 4, "physical"))
      o->sdf = RR_SDF_PHYSICAL;
    else
      return rr_seterr(err, RR_EINVAL, "objective '%s': sdf must be none, paper or physical",
                       o->text);
    return RR_OK;
  }
  if (!strncmp(t, "spectrum=", 9) && is_lateral_ride(o->kind)) {
    snprintf(o->spectrum, sizeof o->spectrum, "%s", t + 9);
    return RR_OK;
  }
  if (!strncmp(t, "vspectrum=", 10) && is_vertical(o->kind)) {
    snprintf(o->vspectrum, sizeof o->vspectrum, "%s", t + 10);
    return RR_OK;
  }
  if (!strcmp(t, "index_modes") && o->kind == OBJ_CRITICAL) {
    o->index_modes = 1;
    return RR_OK;
  }
  if (!strncmp(t, "vmax=", 5) && o->kind == OBJ_CRITICAL) {
    double v;
    rr_critical_opts co = rr_critical_opts_default();
    if (number(t + 5, &v) || !(v / RR_KMH > co.v_min_ms && v / RR_KMH <= RR_SPEED_MAX_MS))
      return rr_seterr(err, RR_EINVAL,
                       "objective '%s': vmax must be a speed in km/h within (%g, %g]", o->text,
                       co.v_min_ms * RR_KMH, RR_SPEED_MAX_MS * RR_KMH);
    o->vmax_ms = v / RR_KMH;
    return RR_OK;
  }
  if (is_stability(o->kind) &&
      (!strncmp(t, "fmax=", 5) || !strncmp(t, "wmin=", 5) || !strncmp(t, "rmax=", 5)))
    return parse_rule(t, o, err);
  return rr_seterr(err, RR_EINVAL, "objective '%s': unknown option '%s' for this objective",
                   o->text, t);
}

/* text split in place: buf gets the name, *at the arguments after '@' and
 *opts the modifiers after ';' (NULL when absent); the name's entry. */
static const struct objective_name *split_objective(const char *text, char *buf, size_t n,
                                                    char **at, char **opts)
{
  snprintf(buf, n, "%s", text);
  *opts = strchr(buf, ';');
  if (*opts) *(*opts)++ = 0;
  *at = strchr(buf, '@');
  if (*at) *(*at)++ = 0;
  for (int i = 0; i < NOBJ_NAMES; i++)
    if (!strcmp(buf, objective_names[i].name)) return &objective_names[i];
  return NULL;
}

static int parse_objective(const char *text, objective *o, rr_error *err)
{
  *o = (objective){.sdf = -1,
                   .mo = rr_modal_opts_default(),
                   .freq_hz = NAN,
                   .vmax_ms = rr_critical_opts_default().v_max_ms};
  snprintf(o->text, sizeof o->text, "%s", text);
  snprintf(o->spectrum, sizeof o->spectrum, "wuhan-guangzhou");
  snprintf(o->vspectrum, sizeof o->vspectrum, "%s", RR_VERTICAL_SPECTRUM_DEFAULT);
  if (strlen(text) >= sizeof o->text)
    return rr_seterr(err, RR_EINVAL, "objective '%.40s...': too long", text);
  char buf[128], *at, *opts;
  const struct objective_name *nm = split_objective(text, buf, sizeof buf, &at, &opts);
  if (!nm)
    return rr_seterr(err, RR_EINVAL,
                     "objective '%s': unknown name (railride objectives lists them)", text);
  o->kind = nm->kind;
  int st = parse_args(at, nm, o, err);
  char *sv, *seen[8];
  int nseen = 0;
  for (char *t = opts && !st ? strtok_r(opts, ";", &sv) : NULL; t && !st;
       t = strtok_r(NULL, ";", &sv)) {
    size_t k = strcspn(t, "=");
    for (int i = 0; i < nseen && !st; i++) /* a modifier given twice */
      if (strcspn(seen[i], "=") == k && !strncmp(seen[i], t, k))
        st = rr_seterr(err, RR_EINVAL, "objective '%s': '%.*s' given twice", o->text, (int)k, t);
    if (nseen < 8) seen[nseen++] = t;
    if (!st) st = parse_option(t, o, err);
  }
  return st;
}

/* rr_objective_at for a vertical objective NAME@KMH[,X] */
static int objective_at_vertical(const char *name, const double *a, int na, const char *opts,
                                 double speed_kmh, char *out, size_t n, rr_error *err)
{
  double v = isfinite(speed_kmh) ? speed_kmh : a[0];
  if (isnan(v)) return rr_seterr(err, RR_EINVAL, "objective '%s': no speed given (NAME@KMH)", name);
  int len = na == 2 ? snprintf(out, n, "%s@%.10g,%.17g%s%s", name, v, a[1], opts ? ";" : "",
                               opts ? opts : "")
                    : snprintf(out, n, "%s@%.10g%s%s", name, v, opts ? ";" : "", opts ? opts : "");
  if (len < 0 || (size_t)len >= n)
    return rr_seterr(err, RR_EINVAL, "objective '%s': too long at this point", name);
  objective o;
  return parse_objective(out, &o, err);
}

int rr_objective_at(const char *text, double speed_kmh, double conicity, char *out, size_t n,
                    rr_error *err)
{
  char buf[128], *at, *opts;
  if (strlen(text) >= sizeof buf)
    return rr_seterr(err, RR_EINVAL, "objective '%.40s...': too long", text);
  const struct objective_name *nm = split_objective(text, buf, sizeof buf, &at, &opts);
  int vonly = nm && is_vertical_only(nm->kind);
  if (!nm || (nm->nargs_min != 2 && !vonly))
    return rr_seterr(err, RR_EINVAL,
                     "objective '%s': not one at an operating point (index, sperling, "
                     "sperling_gb, wd_rms, rms, n_mv, and the vertical ones)",
                     text);
  double a[3] = {NAN, NAN, 0};
  int na, st = read_args(at, text, a, &na, err);
  if (st) return st;
  if (vonly) /* KMH[,X]: as NAME@KMH,L[,X] with the conicity not used */
    return objective_at_vertical(buf, a, na, opts, speed_kmh, out, n, err);
  if (isfinite(speed_kmh)) a[0] = speed_kmh;
  if (isfinite(conicity)) a[1] = conicity;
  if (isnan(a[0]) || isnan(a[1]))
    return rr_seterr(err, RR_EINVAL, "objective '%s': no %s given (NAME@KMH,L)", text,
                     isnan(a[0]) ? "speed" : "conicity");
  int len = na == 3 ? snprintf(out, n, "%s@%.10g,%.10g,%.17g%s%s", buf, a[0], a[1], a[2],
                               opts ? ";" : "", opts ? opts : "")
                    : snprintf(out, n, "%s@%.10g,%.10g%s%s", buf, a[0], a[1], opts ? ";" : "",
                               opts ? opts : "");
  if (len < 0 || (size_t)len >= n)
    return rr_seterr(err, RR_EINVAL, "objective '%s': too long at this point", text);
  objective o;
  return parse_objective(out, &o, err);
}

int rr_objective_check(const char *text, rr_error *err)
{
  objective o;
  return parse_objective(text, &o, err);
}

void rr_design_free(rr_design *d)
{
  if (!d) return;
  for (int i = 0; i < d->nobj; i++) {
    rr_ride_plan_free(d->obj[i].plan);
    rr_spectrum_close(&d->obj[i].sp);
    rr_spectrum_close(&d->obj[i].vsp);
    rr_vertical_plan_free(d->obj[i].vplan);
  }
  for (int i = 0; i < d->nmodels; i++) {
    rr_model_free(d->model[i]);
    rr_modal_ws_free(d->ws[i]);
    for (int j = 0; j < DESIGN_GROUP - 1; j++) rr_model_free(d->member[j][i]);
  }
  rr_system_free(d->scratch);
  for (int i = 0; i < d->nclones; i++) rr_design_free(d->clones[i]);
  free(d->clones);
  free(d);
}

/* The vehicle as a model variant sees it. */
static void variant(const rr_vehicle *cur, int sdf, rr_vehicle *v)
{
  *v = *cur;
  if (sdf >= 0) v->sdf_mode = sdf;
}

/* The model slot of an SDF variant, made on first use. */
static int model_slot(rr_design *d, int sdf, const char *text, int *slot, rr_error *err)
{
  for (int j = 0; j < d->nmodels; j++)
    if (d->model_sdf[j] == sdf) {
      *slot = j;
      return RR_OK;
    }
  if (d->nmodels >= MAX_MODELS)
    return rr_seterr(err, RR_EINVAL, "objective '%s': too many SDF variants", text);
  rr_vehicle v;
  variant(&d->cur, sdf, &v);
  if (v.sdf_mode != RR_SDF_NONE && v.sdf.kind == RR_CURVE_UNSET)
    return rr_seterr(err, RR_EINVAL, "objective '%s': the vehicle has no SDF curve", text);
  int m = d->nmodels++, st;
  d->model_sdf[m] = sdf;
  if ((st = rr_model_from_vehicle(&v, &d->model[m], err))) return st;
  if ((st = rr_modal_ws_new(d->model[m], &d->ws[m], err))) return st;
  *slot = m;
  return RR_OK;
}

/* The vertical model's plan: one floor point, the default grid (the lateral
   PEM's, so that N_MV combines the two on one grid) and window. */
static int vertical_plan(objective *o, rr_error *err)
{
  rr_vertical_opts vo = rr_vertical_opts_default();
  vo.npoints = 1;
  vo.x_points[0] = o->x;
  int st = rr_vertical_plan_new(&vo, &o->vplan, err);
  return st ? st : rr_vertical_plan_set_track(o->vplan, &o->vsp, o->speed_ms, err);
}

/* Models, workspaces and frequency-response plans for the parsed objectives
   (the spectra are already in them). */
static int build(rr_design *d, rr_error *err)
{
  int st;
  if ((st = rr_system_new(&d->scratch, err))) return st;
  for (int i = 0; i < d->nobj; i++) {
    objective *o = &d->obj[i];
    if ((st = model_slot(d, o->sdf, o->text, &o->model, err))) return st;
    if (is_vertical(o->kind) && (st = vertical_plan(o, err))) return st;
    if (!is_lateral_ride(o->kind)) continue;
    rr_ride_opts ro = rr_ride_opts_default();
    ro.npoints = 1;
    ro.x_points[0] = o->x;
    if ((st = rr_ride_plan_new(d->model[o->model], &d->cur, &ro, &o->plan, err))) return st;
    /* the objective's speed and track are fixed: the track's PSD once */
    if ((st = rr_ride_plan_set_track(o->plan, &o->sp, o->speed_ms, err))) return st;
  }
  return RR_OK;
}

/* A context with the base vehicle and keys set and nothing built. */
static int context(const rr_vehicle *base, int nvar, const char *const *var_keys, int nobj,
                   rr_design **out, rr_error *err)
{
  *out = NULL;
  if (nvar < 0 || nvar > RR_DESIGN_MAX_VARS)
    return rr_seterr(err, RR_EINVAL, "design: 0 to %d variables", RR_DESIGN_MAX_VARS);
  if (nobj < 1 || nobj > RR_DESIGN_MAX_OBJS)
    return rr_seterr(err, RR_EINVAL, "design: 1 to %d objectives", RR_DESIGN_MAX_OBJS);
  int st = rr_vehicle_check(base, err);
  if (st) return st;
  rr_design *d = calloc(1, sizeof *d);
  if (!d) return rr_seterr(err, RR_ENOMEM, "out of memory");
  d->base = d->cur = *base;
  d->nvar = nvar;
  d->nobj = nobj;
  d->mo = rr_modal_opts_default();
  *out = d;
  for (int i = 0; i < nvar; i++) {
    d->key[i] = rr_vehicle_key_find(var_keys[i]);
    if (!d->key[i])
      return rr_seterr(err, RR_EINVAL,
                       "design variable '%s': not a numeric vehicle-file key (section.key)",
                       var_keys[i]);
    for (int j = 0; j < i; j++)
      if (d->key[j] == d->key[i])
        return rr_seterr(err, RR_EINVAL, "design variable '%s': listed twice", var_keys[i]);
    snprintf(d->keys[i], sizeof d->keys[i], "%s", var_keys[i]);
  }
  return RR_OK;
}

int rr_design_new(const rr_vehicle *base, int nvar, const char *const *var_keys, int nobj,
                  const char *const *objectives, rr_design **out, rr_error *err)
{
  rr_design *d;
  int st = context(base, nvar, var_keys, nobj, &d, err);
  for (int i = 0; i < nobj && !st; i++) {
    snprintf(d->objtext[i], sizeof d->objtext[i], "%s", objectives[i]);
    if ((st = parse_objective(objectives[i], &d->obj[i], err))) break;
    if (is_lateral_ride(d->obj[i].kind) &&
        !(st = rr_spectrum_open(d->obj[i].spectrum, &d->obj[i].sp, err)))
      st = rr_spectrum_require(&d->obj[i].sp, "lateral", "the lateral track input", err);
    if (!st && is_vertical(d->obj[i].kind) &&
        !(st = rr_spectrum_open(d->obj[i].vspectrum, &d->obj[i].vsp, err)))
      st = rr_spectrum_require(&d->obj[i].vsp, "vertical", "the vertical track input", err);
  }
  if (!st) st = build(d, err);
  if (st) {
    rr_design_free(d);
    return st;
  }
  *out = d;
  return RR_OK;
}

/* A copy of what the parent parsed (objectives, spectra, rule): no file is
   read again. */
int rr_design_clone(const rr_design *d, rr_design **out, rr_error *err)
{
  const char *keys[RR_DESIGN_MAX_VARS];
  for (int i = 0; i < d->nvar; i++) keys[i] = d->keys[i];
  rr_design *c;
  int st = context(&d->base, d->nvar, keys, d->nobj, &c, err);
  if (!st) {
    c->mo = d->mo;
    for (int i = 0; i < d->nobj && !st; i++) { /* no table shared: each context owns its own */
      memcpy(c->objtext[i], d->objtext[i], sizeof c->objtext[i]);
      c->obj[i] = d->obj[i];
      c->obj[i].plan = NULL;
      c->obj[i].vplan = NULL;
      st = rr_spectrum_copy(&d->obj[i].sp, &c->obj[i].sp, err);
      if (st) /* d's tables, not this context's to close */
        c->obj[i].vsp = (rr_spectrum){.npts = 0};
      else
        st = rr_spectrum_copy(&d->obj[i].vsp, &c->obj[i].vsp, err);
    }
    if (!st) st = build(c, err); /* a failed copy is not overwritten by a good build */
  }
  if (st) {
    rr_design_free(c);
    return st;
  }
  *out = c;
  return RR_OK;
}

int rr_design_set_modal_opts(rr_design *d, const rr_modal_opts *o, rr_error *err)
{
  if (!(o->fmax_hz >= 0 && o->w_min >= 0 && o->w_min <= 1 && o->r_max >= 0 && o->r_max <= 1))
    return rr_seterr(err, RR_EINVAL,
                     "design: fmax must be > 0 (or RR_FMAX_AUTO), w_min and r_max within 0..1");
  d->mo = *o;
  for (int i = 0; i < d->nclones; i++) d->clones[i]->mo = *o;
  return RR_OK;
}

int rr_design_nvar(const rr_design *d) { return d->nvar; }
int rr_design_nobj(const rr_design *d) { return d->nobj; }

double rr_design_mode_freq(const rr_design *d, int i)
{
  return i >= 0 && i < d->nobj ? d->obj[i].freq_hz : NAN;
}

int rr_design_at_bound(const rr_design *d, int i)
{
  return i >= 0 && i < d->nobj ? d->obj[i].at_bound : 0;
}

double rr_design_band_edge(const rr_design *d, int i)
{
  return i >= 0 && i < d->nobj ? d->obj[i].fmax_hz : NAN;
}

int rr_design_verdict(const rr_design *d, int i)
{
  return i >= 0 && i < d->nobj ? d->obj[i].verdict : -1;
}

/* The rule an objective uses: the context's, with its own modifiers. */
static rr_modal_opts rule_of(const rr_design *d, const objective *o)
{
  rr_modal_opts mo = d->mo;
  if (o->mo_set & MO_FMAX) mo.fmax_hz = o->mo.fmax_hz;
  if (o->mo_set & MO_WMIN) mo.w_min = o->mo.w_min;
  if (o->mo_set & MO_RMAX) mo.r_max = o->mo.r_max;
  return mo;
}

static int same_rule(const rr_modal_opts *a, const rr_modal_opts *b)
{
  return a->fmax_hz == b->fmax_hz && a->w_min == b->w_min && a->r_max == b->r_max &&
         a->tracking == b->tracking;
}

/* Robust indices, shared by the objectives of one model and rule. */
typedef struct robust_cache {
  int n, model[RR_DESIGN_MAX_OBJS];
  rr_modal_opts mo[RR_DESIGN_MAX_OBJS];
  rr_robust rb[RR_DESIGN_MAX_OBJS];
} robust_cache;

static int robust_find(const robust_cache *rc, int model, const rr_modal_opts *mo)
{
  int k = 0;
  while (k < rc->n && !(rc->model[k] == model && same_rule(&rc->mo[k], mo))) k++;
  return k;
}

static int robust_value(rr_design *d, rr_model *const *models, const objective *o,
                        const rr_modal_opts *mo, robust_cache *rc, double *f, rr_error *err)
{
  int k = robust_find(rc, o->model, mo);
  if (k == rc->n) {
    int st = rr_robust_indices(models[o->model], mo, NULL, d->ws[o->model], &rc->rb[k], err);
    if (st) return st;
    rc->model[k] = o->model;
    rc->mo[k] = *mo;
    rc->n++;
  }
  const rr_robust *rb = &rc->rb[k];
  *f = o->kind == OBJ_ZETA_LOW    ? rb->zeta_low
       : o->kind == OBJ_ZETA_HIGH ? rb->zeta_high
                                  : rb->std_zeta;
  return RR_OK;
}

static int ride_value(objective *o, rr_model *m, double *f, rr_error *err)
{
  int st;
  rr_ride_point c;
  if ((st = rr_model_set_operating(m, o->speed_ms, o->conicity, err))) return st;
  if ((st = rr_ride_design(o->plan, m, &c, err))) return st;
  o->verdict = c.stable;
  *f = o->kind == OBJ_SPERLING      ? c.sperling
       : o->kind == OBJ_SPERLING_GB ? c.sperling_gb
       : o->kind == OBJ_WD_RMS      ? c.wd_rms
                                    : c.rms;
  return RR_OK;
}

/* The vertical objectives; N_MV adds the lateral PEM's Wd 5 s percentile
   on the same grid (the longitudinal term 0). */
static int vertical_value(rr_design *d, objective *o, rr_model *m, double *f, rr_error *err)
{
  rr_vertical_model vm;
  rr_vertical_point p;
  int st = rr_vertical_model_build(&d->cur, &vm, err);
  if (!st) st = rr_vertical_ride_design(o->vplan, &vm, &p, err);
  if (st) return st;
  switch (o->kind) {
  case OBJ_SPERLING_Z: *f = p.sperling; return RR_OK;
  case OBJ_SPERLING_GB_Z: *f = p.sperling_gb; return RR_OK;
  case OBJ_WB_RMS: *f = p.wb_rms; return RR_OK;
  case OBJ_WB_P95: *f = p.wb_5s.p95; return RR_OK;
  case OBJ_RMS_Z: *f = p.rms; return RR_OK;
  case OBJ_N_MV_Z: *f = p.n_mv_vertical; return RR_OK;
  default: break;
  }
  rr_window_stats wd;
  rr_ride_point lat[RR_RIDE_POINTS_MAX];
  if ((st = rr_model_set_operating(m, o->speed_ms, o->conicity, err))) return st;
  if ((st = rr_ride_design(o->plan, m, lat, err))) return st;
  o->verdict = lat[0].stable;
  if (lat[0].stable == 0) { /* the lateral side undefined, and N_MV with it */
    *f = NAN;
    return RR_OK;
  }
  const double *G = rr_ride_psd(o->plan);
  if ((st = rr_vertical_window_stats(o->vplan, G, 1, 1, RR_ISO_WD, &wd, err))) return st;
  rr_en12299_inputs in = {.ay50 = wd.p50, .ay95 = wd.p95, .az50 = p.wb_5s.p50, .az95 = p.wb_5s.p95};
  *f = rr_en12299_indices(&in).n_mv;
  return RR_OK;
}

static int objective_value(rr_design *d, rr_model *const *models, objective *o, robust_cache *rc,
                           double *f, rr_error *err)
{
  rr_model *m = models[o->model];
  rr_modal_ws *ws = d->ws[o->model];
  rr_modal_opts mo = rule_of(d, o);
  int st;
  o->freq_hz = NAN;
  o->at_bound = 0;
  o->fmax_hz = NAN;
  o->verdict = -1;
  switch (o->kind) {
  case OBJ_ZETA_LOW:
  case OBJ_ZETA_HIGH:
  case OBJ_STD_ZETA: return robust_value(d, models, o, &mo, rc, f, err);
  case OBJ_INDEX: {
    rr_stability s;
    if ((st = rr_model_set_operating(m, o->speed_ms, o->conicity, err))) return st;
    if ((st = rr_modal_stability(m, &mo, ws, &s, err))) return st;
    *f = s.index; /* NaN when undefined: the design fails (never counts as good) */
    o->freq_hz = s.index_freq_hz;
    o->fmax_hz = s.fmax_hz;
    o->verdict = rr_modal_stable(s.zeta_max);
    return RR_OK;
  }
  case OBJ_CRITICAL: {
    rr_critical_opts co = rr_critical_opts_default();
    rr_critical cr;
    co.index_modes = o->index_modes;
    co.v_max_ms = o->vmax_ms;
    if ((st = rr_critical_speed(m, o->conicity, &mo, &co, ws, &cr, err))) return st;
    *f = cr.found ? cr.speed_ms * RR_KMH : co.v_max_ms * RR_KMH; /* a bound: at_bound says so */
    o->at_bound = !cr.found;
    o->freq_hz = cr.found ? cr.mode.freq_hz : NAN;
    return RR_OK;
  }
  default: return is_vertical(o->kind) ? vertical_value(d, o, m, f, err) : ride_value(o, m, f, err);
  }
}

/* Design x into d->cur and the models (rebuilt). */
static int design_set(rr_design *d, const double *x, rr_model *const *models, rr_error *err)
{
  int st = RR_OK;
  d->cur = d->base;
  for (int i = 0; i < d->nvar; i++) {
    if (!isfinite(x[i]))
      return rr_seterr(err, RR_EINVAL, "design variable %s: not finite", d->keys[i]);
    *rr_vehicle_field(&d->cur, d->key[i]) = x[i];
  }
  if ((st = rr_vehicle_check(&d->cur, err))) return st;
  for (int m = 0; m < d->nmodels && !st; m++) {
    rr_vehicle v;
    variant(&d->cur, d->model_sdf[m], &v);
    st = rr_model_rebuild(models[m], &v, d->scratch, err);
  }
  return st;
}

/* The objectives of the design the models hold, rc holding robust indices
   already known; every f NaN on an error. */
static int design_objectives(rr_design *d, rr_model *const *models, robust_cache *rc, double *f,
                             rr_error *err)
{
  int st = RR_OK;
  for (int i = 0; i < d->nobj && !st; i++)
    st = objective_value(d, models, &d->obj[i], rc, &f[i], err);
  for (int i = 0; i < d->nobj && !st; i++)
    if (isnan(f[i]) && is_index(d->obj[i].kind))
      st = rr_seterr(err, RR_EUNDEF,
                     "objective '%s' is undefined: no hunting-related mode below fmax, and every "
                     "mode stable",
                     d->obj[i].text);
    else if (isnan(f[i]) && is_lateral_ride(d->obj[i].kind))
      st = rr_seterr(err, RR_EUNDEF,
                     "objective '%s' is undefined: some mode is unstable at its operating point "
                     "(a linear response of an unstable vehicle is not a ride comfort)",
                     d->obj[i].text);
    else if (!isfinite(f[i]))
      st = rr_seterr(err, RR_ENOCONV, "objective '%s' is not finite", d->obj[i].text);
  if (st)
    for (int i = 0; i < d->nobj; i++) f[i] = NAN;
  return st;
}

int rr_design_evaluate(rr_design *d, const double *x, double *f, rr_error *err)
{
  for (int i = 0; i < d->nobj; i++) f[i] = NAN;
  int st = design_set(d, x, d->model, err);
  robust_cache rc = {.n = 0};
  return st ? st : design_objectives(d, d->model, &rc, f, err);
}

/* The models of a group's design j (0: the context's own), made on first use. */
static rr_model *const *member_models(rr_design *d, int j)
{
  if (j == 0) return d->model;
  rr_model **mm = d->member[j - 1];
  for (int m = 0; m < d->nmodels; m++)
    if (!mm[m] && rr_model_clone(d->model[m], &mm[m], NULL)) return NULL;
  return mm;
}

/* Each (model, rule) pair's robust indices for the group's designs that
   were set (ok[j]) in one call, the points of all in SIMD lanes, into their
   caches. When the call fails each design computes its own: the same
   numbers, and its own error. */
static void group_robust(rr_design *d, int G, rr_model *const *const *models, const int *ok,
                         robust_cache *rc)
{
  for (int i = 0; i < d->nobj; i++) {
    const objective *o = &d->obj[i];
    rr_modal_opts mo = rule_of(d, o);
    rr_model *mm[DESIGN_GROUP];
    int who[DESIGN_GROUP], n = 0;
    for (int j = 0; j < G; j++)
      if (ok[j] && robust_find(&rc[j], o->model, &mo) == rc[j].n) {
        who[n] = j;
        mm[n++] = models[j][o->model];
      }
    rr_robust rb[DESIGN_GROUP];
    if (n == 0 || rr_robust_indices_many(mm, n, &mo, NULL, d->ws[o->model], rb, NULL)) continue;
    for (int k = 0; k < n; k++) {
      robust_cache *c = &rc[who[k]];
      c->model[c->n] = o->model;
      c->mo[c->n] = mo;
      c->rb[c->n++] = rb[k];
    }
  }
}

/* G <= DESIGN_GROUP designs; returns how many failed. Grouped only when
   every objective is a robust index (their results are bit for bit those of
   rr_design_evaluate); otherwise one by one. */
static int evaluate_group(rr_design *d, int G, const double *x, double *f)
{
  rr_model *const *models[DESIGN_GROUP];
  int grouped = G > 1, ok[DESIGN_GROUP], failed = 0;
  for (int i = 0; i < d->nobj; i++) grouped &= is_robust(d->obj[i].kind);
  for (int j = 0; j < G && grouped; j++) grouped = (models[j] = member_models(d, j)) != NULL;
  if (!grouped) {
    for (int j = 0; j < G; j++)
      failed += rr_design_evaluate(d, x + (size_t)j * (size_t)d->nvar,
                                   f + (size_t)j * (size_t)d->nobj, NULL) != RR_OK;
    return failed;
  }
  robust_cache rc[DESIGN_GROUP];
  for (int j = 0; j < G; j++) {
    double *fj = f + (size_t)j * (size_t)d->nobj;
    for (int i = 0; i < d->nobj; i++) fj[i] = NAN;
    ok[j] = design_set(d, x + (size_t)j * (size_t)d->nvar, models[j], NULL) == RR_OK;
    rc[j].n = 0;
  }
  group_robust(d, G, models, ok, rc);
  for (int j = 0; j < G; j++)
    failed += !ok[j] || design_objectives(d, models[j], &rc[j], f + (size_t)j * (size_t)d->nobj,
                                          NULL) != RR_OK;
  return failed;
}

int rr_design_evaluate_batch(rr_design *d, int n, const double *x, double *f, int nthreads,
                             int *nfailed, rr_error *err)
{
  if (n < 0 || (n > 0 && (!x || !f)))
    return rr_seterr(err, RR_EINVAL, "design: a batch needs n >= 0 and its arrays");
  int ng = (n + DESIGN_GROUP - 1) / DESIGN_GROUP, nt = 1;
#ifdef _OPENMP
  nt = nthreads > 0 ? nthreads : omp_get_max_threads();
  if (nt > ng) nt = ng > 0 ? ng : 1;
#else
  (void)nthreads;
#endif
  /* thread-private contexts, made once and kept */
  if (nt > 1 && d->nclones < nt - 1) {
    rr_design **c = realloc(d->clones, sizeof(rr_design *) * (size_t)(nt - 1));
    if (!c)
      nt = 1;
    else {
      d->clones = c;
      while (d->nclones < nt - 1) {
        if (rr_design_clone(d, &d->clones[d->nclones], NULL)) {
          nt = d->nclones + 1;
          break;
        }
        d->nclones++;
      }
    }
  }
  int failed = 0;
#ifdef _OPENMP
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1) reduction(+ : failed)
#endif
  for (int g = 0; g < ng; g++) {
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    rr_design *ctx = t == 0 ? d : d->clones[t - 1];
    int i0 = g * DESIGN_GROUP, G = n - i0 < DESIGN_GROUP ? n - i0 : DESIGN_GROUP;
    failed +=
        evaluate_group(ctx, G, x + (size_t)i0 * (size_t)d->nvar, f + (size_t)i0 * (size_t)d->nobj);
  }
  if (nfailed) *nfailed = failed;
  return RR_OK;
}

int rr_design_open(const char *vehicle, const char *keys_nl, const char *objectives_nl,
                   rr_design **out, rr_error *err)
{
  rr_vehicle v;
  *out = NULL;
  char kb[4096], ob[4096];
  const char *keys[RR_DESIGN_MAX_VARS], *objs[RR_DESIGN_MAX_OBJS];
  int nk = 0, no = 0;
  snprintf(kb, sizeof kb, "%s", keys_nl ? keys_nl : "");
  snprintf(ob, sizeof ob, "%s", objectives_nl ? objectives_nl : "");
  char *sv;
  for (char *t = strtok_r(kb, "\n", &sv); t && nk < RR_DESIGN_MAX_VARS;
       t = strtok_r(NULL, "\n", &sv))
    keys[nk++] = t;
  for (char *t = strtok_r(ob, "\n", &sv); t && no < RR_DESIGN_MAX_OBJS;
       t = strtok_r(NULL, "\n", &sv))
    objs[no++] = t;
  int st = rr_vehicle_open(vehicle && *vehicle ? vehicle : NULL, &v, err);
  if (!st) st = rr_design_new(&v, nk, keys, no, objs, out, err);
  return st;
}
