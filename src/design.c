/* Design contexts: allocation-free evaluation of objectives for optimisers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include "railride/comfort.h"
#include "railride/design.h"
#include "railride/modal.h"
#include "railride/pem.h"
#include "railride/spectrum.h"
#include "model_impl.h"
#include "internal.h"

enum obj_kind { OBJ_ZETA_LOW, OBJ_ZETA_HIGH, OBJ_STD_ZETA, OBJ_INDEX, OBJ_CRITICAL, OBJ_SPERLING, OBJ_SPERLING_GB,
                OBJ_WD_RMS, OBJ_RMS };

typedef struct objective {
  char text[128];
  int kind, sdf;             /* sdf: -1 keeps the vehicle's */
  double speed_ms, conicity, x;
  char spectrum[64];
  int model;                 /* index into the design's models */
  /* ride resources */
  rr_frf_plan *plan;
  rr_spectrum sp;
  double *G;
} objective;

struct rr_design {
  rr_vehicle base, cur;
  int nvar, nobj;
  char keys[RR_DESIGN_MAX_VARS][64];
  const rr_vehicle_key *key[RR_DESIGN_MAX_VARS];
  char objtext[RR_DESIGN_MAX_OBJS][128];
  objective obj[RR_DESIGN_MAX_OBJS];
  int nmodels;
  int model_sdf[3];          /* sdf mode of each model (-1: the vehicle's) */
  rr_model *model[3];
  rr_modal_ws *ws[3];
  rr_system *scratch;
  int nclones;
  rr_design **clones;
};

static int parse_objective(const char *text, objective *o, rr_error *err)
{
  memset(o, 0, sizeof *o);
  snprintf(o->text, sizeof o->text, "%s", text);
  o->sdf = -1;
  snprintf(o->spectrum, sizeof o->spectrum, "wuhan-guangzhou");
  char buf[128];
  snprintf(buf, sizeof buf, "%s", text);
  char *opts = strchr(buf, ';');
  if (opts) *opts++ = 0;
  char *at = strchr(buf, '@');
  if (at) *at++ = 0;
  static const struct { const char *name; int kind, nargs_min, nargs_max; } names[] = {
    {"zeta_low", OBJ_ZETA_LOW, 0, 0}, {"zeta_high", OBJ_ZETA_HIGH, 0, 0}, {"std_zeta", OBJ_STD_ZETA, 0, 0},
    {"index", OBJ_INDEX, 2, 2}, {"critical_speed", OBJ_CRITICAL, 1, 1}, {"sperling", OBJ_SPERLING, 2, 3},
    {"sperling_gb", OBJ_SPERLING_GB, 2, 3}, {"wd_rms", OBJ_WD_RMS, 2, 3}, {"rms", OBJ_RMS, 2, 3},
  };
  int k = -1;
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
    if (!strcmp(buf, names[i].name)) k = (int)i;
  if (k < 0) return rr_seterr(err, RR_EINVAL, "objective '%s': unknown name (zeta_low, zeta_high, std_zeta, index@, critical_speed@, sperling@, sperling_gb@, wd_rms@, rms@)", text);
  o->kind = names[k].kind;
  double a[3] = {0, 0, 0};
  int na = 0;
  if (at) {
    for (char *t = strtok(at, ","); t; t = strtok(NULL, ",")) {
      if (na >= 3) return rr_seterr(err, RR_EINVAL, "objective '%s': too many arguments", text);
      char *end;
      a[na] = strtod(t, &end);
      if (end == t || *end || !isfinite(a[na])) return rr_seterr(err, RR_EINVAL, "objective '%s': '%s' is not a number", text, t);
      na++;
    }
  }
  if (na < names[k].nargs_min || na > names[k].nargs_max)
    return rr_seterr(err, RR_EINVAL, "objective '%s': %d to %d arguments expected after '@'", text, names[k].nargs_min, names[k].nargs_max);
  if (o->kind == OBJ_CRITICAL) o->conicity = a[0];
  else if (na >= 2) { o->speed_ms = a[0] / 3.6; o->conicity = a[1]; o->x = na == 3 ? a[2] : 0; }
  if (na >= 2 && !(o->speed_ms > 0)) return rr_seterr(err, RR_EINVAL, "objective '%s': speed must be > 0 km/h", text);
  if (o->conicity < 0) return rr_seterr(err, RR_EINVAL, "objective '%s': conicity must be >= 0", text);
  for (char *t = opts ? strtok(opts, ";") : NULL; t; t = strtok(NULL, ";")) {
    if (!strncmp(t, "sdf=", 4)) {
      if (!strcmp(t + 4, "none")) o->sdf = RR_SDF_NONE;
      else if (!strcmp(t + 4, "paper")) o->sdf = RR_SDF_PAPER;
      else if (!strcmp(t + 4, "physical")) o->sdf = RR_SDF_PHYSICAL;
      else return rr_seterr(err, RR_EINVAL, "objective '%s': sdf must be none, paper or physical", text);
    } else if (!strncmp(t, "spectrum=", 9)) {
      snprintf(o->spectrum, sizeof o->spectrum, "%s", t + 9);
    } else return rr_seterr(err, RR_EINVAL, "objective '%s': unknown option '%s'", text, t);
  }
  return RR_OK;
}

void rr_design_free(rr_design *d)
{
  if (!d) return;
  for (int i = 0; i < d->nobj; i++) { rr_frf_plan_free(d->obj[i].plan); free(d->obj[i].G); }
  for (int i = 0; i < d->nmodels; i++) { rr_model_free(d->model[i]); rr_modal_ws_free(d->ws[i]); }
  rr_system_free(d->scratch);
  for (int i = 0; i < d->nclones; i++) rr_design_free(d->clones[i]);
  free(d->clones);
  free(d);
}

static int is_ride(int kind) { return kind >= OBJ_SPERLING; }

/* The vehicle as a model variant sees it. */
static void variant(const rr_design *d, int sdf, rr_vehicle *v)
{
  *v = d->cur;
  if (sdf >= 0) v->sdf_mode = sdf;
}

int rr_design_new(const rr_vehicle *base, int nvar, const char *const *var_keys, int nobj, const char *const *objectives,
                  rr_design **out, rr_error *err)
{
  *out = NULL;
  if (nvar < 0 || nvar > RR_DESIGN_MAX_VARS) return rr_seterr(err, RR_EINVAL, "design: 0 to %d variables", RR_DESIGN_MAX_VARS);
  if (nobj < 1 || nobj > RR_DESIGN_MAX_OBJS) return rr_seterr(err, RR_EINVAL, "design: 1 to %d objectives", RR_DESIGN_MAX_OBJS);
  int st = rr_vehicle_check(base, err);
  if (st) return st;
  rr_design *d = calloc(1, sizeof *d);
  if (!d) return rr_seterr(err, RR_ENOMEM, "out of memory");
  d->base = d->cur = *base;
  d->nvar = nvar;
  d->nobj = nobj;
  for (int i = 0; i < nvar; i++) {
    snprintf(d->keys[i], sizeof d->keys[i], "%s", var_keys[i]);
    d->key[i] = rr_vehicle_key_find(var_keys[i]);
    if (!d->key[i]) { st = rr_seterr(err, RR_EINVAL, "design variable '%s': not a numeric vehicle-file key (section.key)", var_keys[i]); goto fail; }
  }
  for (int i = 0; i < nobj; i++) {
    snprintf(d->objtext[i], sizeof d->objtext[i], "%s", objectives[i]);
    if ((st = parse_objective(objectives[i], &d->obj[i], err))) goto fail;
  }
  d->scratch = rr_system_new();
  if (!d->scratch) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto fail; }
  for (int i = 0; i < nobj; i++) {
    objective *o = &d->obj[i];
    int m = -1;
    for (int j = 0; j < d->nmodels; j++)
      if (d->model_sdf[j] == o->sdf) m = j;
    if (m < 0) {
      m = d->nmodels++;
      d->model_sdf[m] = o->sdf;
      rr_vehicle v;
      variant(d, o->sdf, &v);
      if (v.sdf_mode != RR_SDF_NONE && v.sdf.kind == RR_CURVE_UNSET) {
        st = rr_seterr(err, RR_EINVAL, "objective '%s': the vehicle has no SDF curve", o->text);
        goto fail;
      }
      /* room for every SDF state whatever the variables do */
      rr_vehicle vm = v;
      if ((st = rr_model_from_vehicle(&vm, &d->model[m], err))) goto fail;
      if ((st = rr_modal_ws_new(d->model[m], &d->ws[m], err))) goto fail;
    }
    o->model = m;
    if (is_ride(o->kind)) {
      if ((st = rr_spectrum_open(o->spectrum, &o->sp, err))) goto fail;
      double row[RR_SYS_MAX_DOF], pt[1] = {o->x};
      rr_model *mm = d->model[m];
      if ((st = rr_vehicle_floor_rows(mm, &d->cur, pt, 1, 1.2, 0, row, NULL, err))) goto fail;
      rr_frf_opts fo = {400, NULL, 0.3, 30, 1, row, NULL, RR_FRF_MODAL};
      if ((st = rr_frf_plan_new(mm, &fo, &o->plan, err))) goto fail;
      o->G = malloc(sizeof(double) * 400);
      if (!o->G) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto fail; }
    }
  }
  *out = d;
  return RR_OK;
fail:
  rr_design_free(d);
  return st;
}

int rr_design_clone(const rr_design *d, rr_design **out, rr_error *err)
{
  const char *keys[RR_DESIGN_MAX_VARS], *objs[RR_DESIGN_MAX_OBJS];
  for (int i = 0; i < d->nvar; i++) keys[i] = d->keys[i];
  for (int i = 0; i < d->nobj; i++) objs[i] = d->objtext[i];
  return rr_design_new(&d->base, d->nvar, keys, d->nobj, objs, out, err);
}

int rr_design_nvar(const rr_design *d) { return d->nvar; }
int rr_design_nobj(const rr_design *d) { return d->nobj; }

int rr_design_evaluate(rr_design *d, const double *x, double *f, rr_error *err)
{
  int st = RR_OK;
  for (int i = 0; i < d->nobj; i++) f[i] = NAN;
  d->cur = d->base;
  for (int i = 0; i < d->nvar; i++) {
    if (!isfinite(x[i])) return rr_seterr(err, RR_EINVAL, "design variable %s: not finite", d->keys[i]);
    *rr_vehicle_field(&d->cur, d->key[i]) = x[i];
  }
  if ((st = rr_vehicle_check(&d->cur, err))) return st;
  for (int m = 0; m < d->nmodels; m++) {
    rr_vehicle v;
    variant(d, d->model_sdf[m], &v);
    if ((st = rr_model_rebuild(d->model[m], &v, d->scratch, err))) return st;
  }
  int robust_done[3] = {0, 0, 0};
  rr_robust rb[3];
  rr_modal_opts mo = rr_modal_opts_default();
  for (int i = 0; i < d->nobj && !st; i++) {
    objective *o = &d->obj[i];
    rr_model *m = d->model[o->model];
    rr_modal_ws *ws = d->ws[o->model];
    switch (o->kind) {
    case OBJ_ZETA_LOW:
    case OBJ_ZETA_HIGH:
    case OBJ_STD_ZETA:
      if (!robust_done[o->model]) {
        if ((st = rr_robust_indices(m, &mo, NULL, ws, &rb[o->model], err))) break;
        robust_done[o->model] = 1;
      }
      f[i] = o->kind == OBJ_ZETA_LOW ? rb[o->model].zeta_low : o->kind == OBJ_ZETA_HIGH ? rb[o->model].zeta_high : rb[o->model].std_zeta;
      break;
    case OBJ_INDEX:
      if (!(st = rr_model_set_operating(m, o->speed_ms, o->conicity, err))) st = rr_modal_stability_index(m, &mo, ws, &f[i], err);
      break;
    case OBJ_CRITICAL: {
      double v;
      int found;
      if (!(st = rr_critical_speed(m, o->conicity, &mo, NULL, ws, &v, &found, err))) f[i] = found ? v * 3.6 : 600;
      break;
    }
    default: {
      if ((st = rr_model_set_operating(m, o->speed_ms, o->conicity, err))) break;
      if ((st = rr_frf_plan_execute(o->plan, m, err))) break;
      if ((st = rr_pem_psd(o->plan, m, &o->sp, o->G, err))) break;
      const double *fr = rr_frf_freqs(o->plan);
      if (o->kind == OBJ_SPERLING) st = rr_sperling_filter_index(fr, o->G, 400, 1, RR_AXIS_LATERAL, &f[i], err);
      else if (o->kind == OBJ_SPERLING_GB) st = rr_sperling_gb_index(fr, o->G, 400, 1, RR_AXIS_LATERAL, &f[i], err);
      else if (o->kind == OBJ_WD_RMS) st = rr_weighted_rms(fr, o->G, 400, 1, RR_ISO_WD, &f[i], err);
      else f[i] = rr_psd_rms(fr, o->G, 400, 1);
    }
    }
  }
  if (st)
    for (int i = 0; i < d->nobj; i++) f[i] = NAN;
  return st;
}

int rr_design_evaluate_batch(rr_design *d, int n, const double *x, double *f, int nthreads)
{
  int nt = 1;
#ifdef _OPENMP
  nt = nthreads > 0 ? nthreads : omp_get_max_threads();
  if (nt > n) nt = n > 0 ? n : 1;
#else
  (void)nthreads;
#endif
  /* thread-private contexts, made once and kept */
  if (nt > 1 && d->nclones < nt - 1) {
    rr_design **c = realloc(d->clones, sizeof(rr_design *) * (nt - 1));
    if (!c) nt = 1;
    else {
      d->clones = c;
      while (d->nclones < nt - 1) {
        if (rr_design_clone(d, &d->clones[d->nclones], NULL)) { nt = d->nclones + 1; break; }
        d->nclones++;
      }
    }
  }
  int failed = 0;
#ifdef _OPENMP
#pragma omp parallel for num_threads(nt) schedule(dynamic, 4) reduction(+ : failed)
#endif
  for (int i = 0; i < n; i++) {
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    rr_design *ctx = t == 0 ? d : d->clones[t - 1];
    if (rr_design_evaluate(ctx, x + (size_t)i * d->nvar, f + (size_t)i * d->nobj, NULL)) failed++;
  }
  return failed;
}

rr_design *rr_design_open(const char *vehicle, const char *keys_nl, const char *objectives_nl, char *errbuf, int errlen)
{
  rr_error e = {0, ""};
  rr_vehicle v;
  rr_design *d = NULL;
  char kb[4096], ob[4096];
  const char *keys[RR_DESIGN_MAX_VARS], *objs[RR_DESIGN_MAX_OBJS];
  int nk = 0, no = 0;
  snprintf(kb, sizeof kb, "%s", keys_nl ? keys_nl : "");
  snprintf(ob, sizeof ob, "%s", objectives_nl ? objectives_nl : "");
  for (char *t = strtok(kb, "\n"); t && nk < RR_DESIGN_MAX_VARS; t = strtok(NULL, "\n")) keys[nk++] = t;
  for (char *t = strtok(ob, "\n"); t && no < RR_DESIGN_MAX_OBJS; t = strtok(NULL, "\n")) objs[no++] = t;
  int st = rr_vehicle_open(vehicle && *vehicle ? vehicle : NULL, &v, &e);
  if (!st) st = rr_design_new(&v, nk, keys, no, objs, &d, &e);
  if (st && errbuf && errlen > 0) snprintf(errbuf, (size_t)errlen, "%s", e.msg);
  return st ? NULL : d;
}
