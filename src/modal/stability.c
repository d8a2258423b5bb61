/* Stability studies built on the modal solver: robust indices (paper
 * Table 1), critical speed, root loci tracked by eigenvector correlation. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "railride/stability.h"
#include "modal/modal_impl.h"
#include "util/internal.h"

rr_robust_opts rr_robust_opts_default(void)
{
  return (rr_robust_opts){.v_low_ms = 250 / RR_KMH,
                          .conicity_low = 0.05,
                          .v_high_ms = 350 / RR_KMH,
                          .conicity_high = 0.40,
                          .conicity_min = 0.05,
                          .conicity_max = 0.40,
                          .n_conicity = 8};
}

static double sweep_conicity(const rr_robust_opts *r, int i)
{
  int nc = r->n_conicity;
  return nc == 1 ? r->conicity_min
                 : r->conicity_min + (r->conicity_max - r->conicity_min) * i / (nc - 1);
}

/* The verdict over the robust points (any oscillatory mode, docs/model.md),
   point p's stability s added: the unstable point reported is the first in
   the points' order, *first the lowest such p so far (the points may come
   in any order). */
static void robust_verdict(rr_robust *out, const rr_stability *s, double v, double lam, int p,
                           int *first)
{
  if (s->zeta_max > out->zeta_max) out->zeta_max = s->zeta_max;
  if (rr_modal_stable(s->zeta_max)) return;
  out->n_unstable++;
  if (p < *first) {
    *first = p;
    out->unstable_speed_ms = v;
    out->unstable_conicity = lam;
  }
}

/* Robust point p of r (its speed and conicity): zeta_low's, zeta_high's,
   then the conicity sweep at v_high. */
static void robust_point(const rr_robust_opts *r, int p, double *v, double *lam)
{
  *v = p == 0 ? r->v_low_ms : r->v_high_ms;
  *lam = p == 0 ? r->conicity_low : p == 1 ? r->conicity_high : sweep_conicity(r, p - 2);
}

#define ROBUST_BLOCK 8 /* models whose sums one robust_block call keeps */

/* Where the points of nm models go in a robust_block run: each model's
   points at v_high (p >= 1) one after another, model by model, then every
   model's p = 0 (at v_low). The points of one design at one speed deflate
   alike in the QR iteration, so that lanes holding them waste less of
   their shared sweeps (3 % fewer vector steps than p = 0 .. npts - 1 model
   by model, 8 % fewer than point by point across the models). Run
   position ix holds model *i's point *p. */
static void block_point(int ix, int nm, int npts, int *i, int *p)
{
  int nh = npts - 1;
  *i = ix < nm * nh ? ix / nh : ix - nm * nh;
  *p = ix < nm * nh ? 1 + ix % nh : 0;
}

/* The robust indices of nm <= ROBUST_BLOCK models, their points in
   block_point's order, in calls of CHUNK points that group them in lanes;
   each model's sums in its points' order. */
static int robust_block(rr_model *const *models, int nm, const rr_modal_opts *o,
                        const rr_robust_opts *r, rr_modal_ws *ws, rr_robust *out, rr_error *err)
{
  int nc = r->n_conicity;
  /* the sweep's end point equal to zeta_high's is not solved twice */
  int reuse = sweep_conicity(r, nc - 1) == r->conicity_high;
  int npts = 2 + nc - reuse, total = nm * npts;
  double sum[ROBUST_BLOCK] = {0}, sum2[ROBUST_BLOCK] = {0};
  int first[ROBUST_BLOCK];
  for (int i = 0; i < nm; i++) {
    out[i] = (rr_robust){.zeta_max = -1, .unstable_speed_ms = NAN, .unstable_conicity = NAN};
    first[i] = npts;
  }
  enum { CHUNK = 16 }; /* points per call: a multiple of the lane counts */
  for (int g0 = 0; g0 < total; g0 += CHUNK) {
    double v[CHUNK], lam[CHUNK];
    rr_model *mods[CHUNK];
    rr_stability z[CHUNK];
    int nb = total - g0 < CHUNK ? total - g0 : CHUNK;
    for (int c = 0; c < nb; c++) {
      int i, p;
      block_point(g0 + c, nm, npts, &i, &p);
      mods[c] = models[i];
      robust_point(r, p, &v[c], &lam[c]);
    }
    int st = rr_modal_stability_many(mods, o, ws, nb, v, lam, z, err);
    if (st) return st;
    for (int c = 0; c < nb; c++) {
      int i, p;
      block_point(g0 + c, nm, npts, &i, &p);
      if (p == 0) out[i].zeta_low = z[c].index;
      if (p == 1) out[i].zeta_high = z[c].index;
      if (p >= 2) {
        sum[i] += z[c].index;
        sum2[i] += z[c].index * z[c].index;
      }
      robust_verdict(&out[i], &z[c], v[c], lam[c], p, &first[i]);
    }
  }
  for (int i = 0; i < nm; i++) {
    if (reuse) {
      sum[i] += out[i].zeta_high;
      sum2[i] += out[i].zeta_high * out[i].zeta_high;
    }
    double mean = sum[i] / nc;
    double var = sum2[i] / nc - mean * mean;
    /* an undefined index at any conicity leaves the spread undefined */
    out[i].std_zeta = isnan(var) ? NAN : sqrt(var > 0 ? var : 0);
  }
  return RR_OK;
}

int rr_robust_indices_many(rr_model *const *models, int nmodels, const rr_modal_opts *o,
                           const rr_robust_opts *r, rr_modal_ws *ws, rr_robust *out, rr_error *err)
{
  rr_robust_opts def = rr_robust_opts_default();
  if (!r) r = &def;
  if (r->n_conicity < 1) return rr_seterr(err, RR_EINVAL, "robust: conicity count must be >= 1");
  if (nmodels < 0 || (nmodels > 0 && (!models || !out)))
    return rr_seterr(err, RR_EINVAL, "robust: need nmodels >= 0 and the arrays");
  for (int i0 = 0; i0 < nmodels; i0 += ROBUST_BLOCK) {
    int nm = nmodels - i0 < ROBUST_BLOCK ? nmodels - i0 : ROBUST_BLOCK;
    int st = robust_block(models + i0, nm, o, r, ws, out + i0, err);
    if (st) return st;
  }
  return RR_OK;
}

int rr_robust_indices(rr_model *m, const rr_modal_opts *o, const rr_robust_opts *r, rr_modal_ws *ws,
                      rr_robust *out, rr_error *err)
{
  return rr_robust_indices_many(&m, 1, o, r, ws, out, err);
}

rr_critical_opts rr_critical_opts_default(void)
{
  return (rr_critical_opts){.v_min_ms = RR_CRITICAL_V_MIN_KMH / RR_KMH,
                            .v_max_ms = RR_CRITICAL_V_MAX_KMH / RR_KMH,
                            .step_ms = RR_CRITICAL_STEP_KMH / RR_KMH,
                            .tol_ms = RR_CRITICAL_TOL_KMH / RR_KMH,
                            .index_modes = 0};
}

static double rule_value(const rr_stability *s, const rr_critical_opts *c)
{
  /* index_modes: the hunting modes' own index (an undefined one never
     crosses), not the verdict's zeta_max */
  return c->index_modes ? (isnan(s->hunting_index) ? -1 : s->hunting_index) : s->zeta_max;
}

static int unstable_at(rr_model *m, double v, double lam, const rr_modal_opts *o,
                       const rr_critical_opts *c, rr_modal_ws *ws, int *yes, rr_error *err)
{
  rr_stability s;
  int st = rr_model_set_operating(m, v, lam, err);
  if (!st) st = rr_modal_stability(m, o, ws, &s, err);
  if (!st) *yes = rule_value(&s, c) >= 0;
  return st;
}

/* The mode that goes unstable at v: the index mode or the least damped one. */
static int unstable_mode(rr_model *m, double v, double lam, const rr_modal_opts *o,
                         const rr_critical_opts *c, rr_modal_ws *ws, rr_critical *out,
                         rr_error *err)
{
  rr_modal_result *r = &ws->trk[3];
  int st = rr_model_set_operating(m, v, lam, err);
  if (!st) st = rr_modal_solve(m, o, ws, r, err);
  if (st) return st;
  int i = c->index_modes ? r->hunting_mode : r->max_mode;
  out->found = 1;
  out->speed_ms = v;
  if (i >= 0) out->mode = r->modes[i];
  return RR_OK;
}

static int check_opts(const rr_critical_opts *c, rr_error *err)
{
  if (!(c->v_min_ms > 0 && c->v_max_ms > c->v_min_ms && c->step_ms > 0 && c->tol_ms > 0 &&
        isfinite(c->v_max_ms)))
    return rr_seterr(err, RR_EINVAL,
                     "critical speed: need 0 < v_min < v_max (finite), step > 0, tol > 0");
  double steps = (c->v_max_ms - c->v_min_ms) / c->step_ms;
  if (!(steps <= RR_CRITICAL_MAX_STEPS))
    return rr_seterr(
        err, RR_EINVAL,
        "critical speed: a scan of %.3g steps exceeds the limit of %d (raise the step)", steps,
        RR_CRITICAL_MAX_STEPS);
  return RR_OK;
}

/* Bisection of [va, vb] (stable at va, not at vb) to tol. */
static int bisect_speed(rr_model *m, double lam, const rr_modal_opts *o, const rr_critical_opts *c,
                        rr_modal_ws *ws, double va, double *vb, rr_error *err)
{
  while (*vb - va > c->tol_ms) {
    double vm = 0.5 * (va + *vb);
    int yes, st = unstable_at(m, vm, lam, o, c, ws, &yes, err);
    if (st) return st;
    if (yes)
      *vb = vm;
    else
      va = vm;
  }
  return RR_OK;
}

int rr_critical_speed(rr_model *m, double lam, const rr_modal_opts *o, const rr_critical_opts *c,
                      rr_modal_ws *ws, rr_critical *out, rr_error *err)
{
  rr_critical_opts def = rr_critical_opts_default();
  rr_modal_opts mdef = rr_modal_opts_default();
  if (!c) c = &def;
  if (!o) o = &mdef;
  *out = (rr_critical){.found = 0, .speed_ms = NAN};
  int st = check_opts(c, err), yes;
  if (st) return st;
  double va = c->v_min_ms;
  if ((st = unstable_at(m, va, lam, o, c, ws, &yes, err))) return st;
  if (yes) return unstable_mode(m, va, lam, o, c, ws, out, err);
  long nsteps = (long)ceil((c->v_max_ms - c->v_min_ms) / c->step_ms - 1e-9);
  /* the scan eight speeds at a time (SIMD lanes, rr_modal_stability_batch);
     the bisection one at a time */
  enum { AHEAD = 8 };
  for (long i0 = 1; i0 <= nsteps; i0 += AHEAD) {
    double vs[AHEAD], ls[AHEAD];
    rr_stability zs[AHEAD];
    int nb = nsteps - i0 + 1 < AHEAD ? (int)(nsteps - i0 + 1) : AHEAD;
    for (int j = 0; j < nb; j++) {
      long i = i0 + j;
      vs[j] = i == nsteps ? c->v_max_ms : c->v_min_ms + (double)i * c->step_ms;
      ls[j] = lam;
    }
    if ((st = rr_modal_stability_batch(m, o, ws, nb, vs, ls, zs, err))) return st;
    for (int j = 0; j < nb; j++) {
      if (rule_value(&zs[j], c) < 0) {
        va = vs[j];
        continue;
      }
      double vb = vs[j];
      if ((st = bisect_speed(m, lam, o, c, ws, va, &vb, err))) return st;
      return unstable_mode(m, vb, lam, o, c, ws, out, err);
    }
  }
  return RR_OK;
}

static rr_locus_point locus_point(double param, const rr_mode *md, double mac)
{
  return (rr_locus_point){.param = param,
                          .re = md->re,
                          .im = md->im,
                          .freq_hz = md->freq_hz,
                          .zeta = md->zeta,
                          .mac = mac,
                          .energy = {md->energy[0], md->energy[1], md->energy[2]},
                          .roll_share = md->roll_share,
                          .frame_roll_share = md->frame_roll_share,
                          .hunting = md->hunting};
}

/* A row where a branch has no mode: before its birth, after its end, or a
   point not reached. */
static rr_locus_point locus_gap(double param)
{
  return (rr_locus_point){.param = param,
                          .re = NAN,
                          .im = NAN,
                          .freq_hz = NAN,
                          .zeta = NAN,
                          .mac = 0,
                          .energy = {NAN, NAN, NAN},
                          .roll_share = NAN,
                          .frame_roll_share = NAN,
                          .hunting = 0};
}

int rr_locus_stride(const rr_model *m) { return rr_modal_state_cap(m); }

/* The state of the branches between points. */
struct rr_locus_tracker {
  int n, cap, nb;       /* ndof, modes at most (= the stride), branches born */
  double complex *prev; /* each branch's last shape (cap x n) */
  int *alive;           /* cap: 1 while a branch goes on */
  int *used, *done;     /* cap each: one point's matching */
};

/* The best (branch, mode) pair left: the live branches against every mode
   of res not yet taken, real ones included (a branch whose best match is a
   real root has turned real). */
static double best_pair(const rr_locus_tracker *t, const rr_modal_result *res, int *bb, int *bi)
{
  double best = -1;
  *bb = *bi = -1;
  for (int b = 0; b < t->nb; b++) {
    if (!t->alive[b] || t->done[b]) continue;
    for (int i = 0; i < res->n; i++) {
      if (t->used[i]) continue;
      double mac =
          rr_mac(t->prev + (size_t)b * (size_t)t->n, res->shapes + (size_t)i * (size_t)t->n, t->n);
      if (mac > best) {
        best = mac;
        *bb = b;
        *bi = i;
      }
    }
  }
  return best;
}

static void take_shape(rr_locus_tracker *t, int b, const rr_modal_result *res, int i)
{
  memcpy(t->prev + (size_t)b * (size_t)t->n, res->shapes + (size_t)i * (size_t)t->n,
         (size_t)t->n * sizeof *t->prev);
}

/* One point: the live branches matched greedily, best correlations first;
   a branch matched to a real root, or left without a mode, ends; every
   oscillatory mode left over is a new branch. row: the point's stride
   entries. */
static int locus_step(rr_locus_tracker *t, const rr_modal_result *res, double param,
                      rr_locus_point *row, rr_error *err)
{
  for (int i = 0; i < res->n; i++) t->used[i] = 0;
  for (int b = 0; b < t->cap; b++) {
    t->done[b] = 0;
    row[b] = locus_gap(param);
  }
  int bb, bi;
  double mac;
  while ((mac = best_pair(t, res, &bb, &bi)) >= 0) {
    t->done[bb] = t->used[bi] = 1;
    if (!res->modes[bi].oscillatory) {
      t->alive[bb] = 0; /* turned real */
      continue;
    }
    row[bb] = locus_point(param, &res->modes[bi], mac);
    take_shape(t, bb, res, bi);
  }
  for (int b = 0; b < t->nb; b++)
    if (!t->done[b]) t->alive[b] = 0; /* no mode left for it */
  for (int i = 0; i < res->n; i++) {
    if (t->used[i] || !res->modes[i].oscillatory) continue;
    if (t->nb >= t->cap)
      return rr_seterr(err, RR_EUNSUP, "locus: more than %d branches born over the range", t->cap);
    int b = t->nb++;
    t->alive[b] = 1;
    row[b] = locus_point(param, &res->modes[i], 1.0);
    take_shape(t, b, res, i);
  }
  return RR_OK;
}

/* A record: the count of modes, then cap modes, then cap x ndof shapes. */
typedef struct record_head {
  int n, cap, ndof, pad;
} record_head;

size_t rr_locus_record_size(const rr_model *m)
{
  size_t cap = (size_t)rr_modal_state_cap(m);
  return sizeof(record_head) + cap * sizeof(rr_mode) + cap * (size_t)m->n * sizeof(double complex);
}

/* The record as a modal result (a view: nothing allocated). */
static rr_modal_result record_view(const void *record)
{
  const record_head *h = record;
  rr_mode *modes = (rr_mode *)(void *)((char *)(uintptr_t)record + sizeof *h);
  return (rr_modal_result){.n = h->n,
                           .cap = h->cap,
                           .ndof = h->ndof,
                           .modes = modes,
                           .shapes = (double complex *)(void *)(modes + h->cap)};
}

int rr_locus_solve(rr_model *m, rr_locus_param param, double value, const rr_modal_opts *o,
                   rr_modal_ws *ws, rr_modal_result *res, void *record, rr_error *err)
{
  int st = param == RR_LOCUS_SPEED ? rr_model_set_operating(m, value, rr_model_conicity(m), err)
                                   : rr_model_set_operating(m, rr_model_speed(m), value, err);
  if (st || (st = rr_modal_solve(m, o, ws, res, err))) return st;
  record_head *h = record;
  int cap = rr_modal_state_cap(m);
  *h = (record_head){.n = res->n, .cap = cap, .ndof = m->n};
  rr_modal_result v = record_view(record);
  memcpy(v.modes, res->modes, (size_t)res->n * sizeof *v.modes);
  memcpy(v.shapes, res->shapes, (size_t)res->n * (size_t)m->n * sizeof *v.shapes);
  memset(v.modes + res->n, 0, (size_t)(cap - res->n) * sizeof *v.modes); /* plain bytes to copy */
  memset(v.shapes + (size_t)res->n * (size_t)m->n, 0,
         (size_t)(cap - res->n) * (size_t)m->n * sizeof *v.shapes);
  return RR_OK;
}

int rr_locus_tracker_new(const rr_model *m, rr_locus_tracker **out, rr_error *err)
{
  rr_locus_tracker *t = calloc(1, sizeof *t);
  *out = NULL;
  if (!t) return rr_seterr(err, RR_ENOMEM, "out of memory");
  *t = (rr_locus_tracker){.n = m->n, .cap = rr_modal_state_cap(m), .nb = 0};
  t->prev = malloc((size_t)t->cap * (size_t)t->n * sizeof *t->prev);
  t->alive = calloc((size_t)t->cap, sizeof *t->alive);
  t->used = malloc((size_t)t->cap * sizeof *t->used);
  t->done = malloc((size_t)t->cap * sizeof *t->done);
  if (!t->prev || !t->alive || !t->used || !t->done) {
    rr_locus_tracker_free(t);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  *out = t;
  return RR_OK;
}

void rr_locus_tracker_free(rr_locus_tracker *t)
{
  if (!t) return;
  free(t->prev);
  free(t->alive);
  free(t->used);
  free(t->done);
  free(t);
}

int rr_locus_follow(rr_locus_tracker *t, const double *values, int npts, const void *records,
                    rr_locus_point *out, int *nbranch, rr_error *err)
{
  size_t rs = sizeof(record_head) +
              (size_t)t->cap * (sizeof(rr_mode) + (size_t)t->n * sizeof(double complex));
  for (int p = 0; p < npts; p++) {
    rr_modal_result res = record_view((const char *)records + (size_t)p * rs);
    if (res.cap != t->cap || res.ndof != t->n || res.n < 0 || res.n > t->cap)
      return rr_seterr(err, RR_EINVAL, "locus: record %d is not one of this model's", p);
    int st = locus_step(t, &res, values[p], out + (size_t)p * (size_t)t->cap, err);
    if (st) return st;
  }
  *nbranch = t->nb;
  return RR_OK;
}

int rr_locus(rr_model *m, rr_locus_param param, const double *values, int npts,
             const rr_modal_opts *o, const rr_progress *pr, rr_locus_point *out, int *nbranch,
             rr_error *err)
{
  double v0 = rr_model_speed(m), l0 = rr_model_conicity(m);
  rr_modal_ws *ws = NULL;
  rr_locus_tracker *t = NULL;
  rr_modal_result res = {0};
  void *rec = malloc(rr_locus_record_size(m));
  int st = rec ? RR_OK : rr_seterr(err, RR_ENOMEM, "out of memory"), nb = 0, p = 0;
  if (!st) st = rr_modal_ws_new(m, &ws, err);
  if (!st) st = rr_modal_result_alloc(m, &res, err);
  if (!st) st = rr_locus_tracker_new(m, &t, err);
  size_t stride = (size_t)rr_locus_stride(m);
  for (; p < npts && !st; p++) {
    st = rr_locus_solve(m, param, values[p], o, ws, &res, rec, err);
    if (!st) st = rr_locus_follow(t, values + p, 1, rec, out + (size_t)p * stride, &nb, err);
    if (!st && (st = rr_progress_step(pr, p + 1, npts, err))) p++;
  }
  if (st == RR_ESTOPPED) /* the points not reached */
    for (p -= 1; p < npts; p++)
      for (size_t b = 0; b < stride; b++) out[(size_t)p * stride + b] = locus_gap(values[p]);
  if (!st || st == RR_ESTOPPED) *nbranch = nb;
  rr_model_set_operating(m, v0, l0, NULL);
  rr_locus_tracker_free(t);
  rr_modal_result_free(&res);
  rr_modal_ws_free(ws);
  free(rec);
  return st;
}
