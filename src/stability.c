/* Stability studies built on the modal solver: robust indices (paper
 * Table 1), critical speed, root loci tracked by eigenvector correlation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/modal.h"
#include "internal.h"

rr_robust_opts rr_robust_opts_default(void)
{
  rr_robust_opts r = {250 / 3.6, 0.05, 350 / 3.6, 0.40, 0.05, 0.40, 8};
  return r;
}

static int index_at(rr_model *m, double v, double lam, const rr_modal_opts *o, rr_modal_ws *ws, double *z, rr_error *err)
{
  int st = rr_model_set_operating(m, v, lam, err);
  if (st) return st;
  return rr_modal_stability_index(m, o, ws, z, err);
}

static double sweep_conicity(const rr_robust_opts *r, int i)
{
  int nc = r->n_conicity;
  return nc == 1 ? r->conicity_min : r->conicity_min + (r->conicity_max - r->conicity_min) * i / (nc - 1);
}

int rr_robust_indices(rr_model *m, const rr_modal_opts *o, const rr_robust_opts *r, rr_modal_ws *ws,
                      rr_robust *out, rr_error *err)
{
  rr_robust_opts def = rr_robust_opts_default();
  if (!r) r = &def;
  int nc = r->n_conicity;
  if (nc < 1) return rr_seterr(err, RR_EINVAL, "robust: conicity count must be >= 1");
  /* points: zeta_low's, zeta_high's, then the conicity sweep at v_high,
     whose end point equal to zeta_high's is not solved twice; evaluated in
     groups that share one instruction stream */
  int reuse = sweep_conicity(r, nc - 1) == r->conicity_high;
  int npts = 2 + nc - reuse;
  double sum = 0, sum2 = 0;
  enum { CHUNK = 16 };   /* points per call: the call groups them in lanes */
  for (int p0 = 0; p0 < npts; p0 += CHUNK) {
    double v[CHUNK], lam[CHUNK], z[CHUNK];
    int nb = npts - p0 < CHUNK ? npts - p0 : CHUNK;
    for (int c = 0; c < nb; c++) {
      int p = p0 + c, i = p - 2;
      v[c] = p == 0 ? r->v_low_ms : r->v_high_ms;
      lam[c] = p == 0 ? r->conicity_low : p == 1 ? r->conicity_high : sweep_conicity(r, i);
    }
    int st = rr_modal_stability_index_batch(m, o, ws, nb, v, lam, z, err);
    if (st) return st;
    for (int c = 0; c < nb; c++) {
      int p = p0 + c;
      if (p == 0) out->zeta_low = z[c];
      if (p == 1) out->zeta_high = z[c];
      if (p >= 2) { sum += z[c]; sum2 += z[c] * z[c]; }
    }
  }
  if (reuse) { sum += out->zeta_high; sum2 += out->zeta_high * out->zeta_high; }
  double mean = sum / nc;
  double var = sum2 / nc - mean * mean;
  out->std_zeta = sqrt(var > 0 ? var : 0);
  return RR_OK;
}

rr_critical_opts rr_critical_opts_default(void)
{
  rr_critical_opts c = {10 / 3.6, 600 / 3.6, 1 / 3.6, 1e-3 / 3.6};
  return c;
}

int rr_critical_speed(rr_model *m, double lam, const rr_modal_opts *o, const rr_critical_opts *c,
                      rr_modal_ws *ws, double *v_out, int *found, rr_error *err)
{
  rr_critical_opts def = rr_critical_opts_default();
  if (!c) c = &def;
  if (!(c->v_min_ms > 0 && c->v_max_ms > c->v_min_ms && c->step_ms > 0 && c->tol_ms > 0))
    return rr_seterr(err, RR_EINVAL, "critical speed: need 0 < v_min < v_max, step > 0, tol > 0");
  *found = 0;
  *v_out = NAN;
  double va = c->v_min_ms, za;
  int st = index_at(m, va, lam, o, ws, &za, err);
  if (st) return st;
  if (za >= 0) { *found = 1; *v_out = va; return RR_OK; }
  int nsteps = (int)ceil((c->v_max_ms - c->v_min_ms) / c->step_ms - 1e-9);
  /* the scan eight speeds at a time (SIMD lanes, see
     rr_modal_stability_index_batch); the bisection one at a time */
  enum { AHEAD = 8 };
  for (int i0 = 1; i0 <= nsteps; i0 += AHEAD) {
    double vs[AHEAD], ls[AHEAD], zs[AHEAD];
    int nb = nsteps - i0 + 1 < AHEAD ? nsteps - i0 + 1 : AHEAD;
    for (int c4 = 0; c4 < nb; c4++) {
      int i = i0 + c4;
      vs[c4] = i == nsteps ? c->v_max_ms : c->v_min_ms + i * c->step_ms;
      ls[c4] = lam;
    }
    if ((st = rr_modal_stability_index_batch(m, o, ws, nb, vs, ls, zs, err))) return st;
    for (int c4 = 0; c4 < nb; c4++) {
      double vb = vs[c4];
      if (zs[c4] >= 0) {
        while (vb - va > c->tol_ms) {
          double vm = 0.5 * (va + vb), zm;
          if ((st = index_at(m, vm, lam, o, ws, &zm, err))) return st;
          if (zm >= 0) vb = vm; else va = vm;
        }
        *found = 1;
        *v_out = vb;
        return RR_OK;
      }
      va = vb;
    }
  }
  return RR_OK;
}

int rr_locus(rr_model *m, int param, const double *values, int npts, const rr_modal_opts *o,
             rr_locus_point *out, int *nbranch, rr_error *err)
{
  double v0 = rr_model_speed(m), l0 = rr_model_conicity(m);
  rr_modal_ws *ws = NULL;
  rr_modal_result res;
  int st = rr_modal_ws_new(m, &ws, err);
  if (st) return st;
  if ((st = rr_modal_result_alloc(m, &res, err))) { rr_modal_ws_free(ws); return st; }
  int n = rr_model_ndof(m), nb = 0;
  double complex *prev = NULL;
  int *used = NULL;
  for (int p = 0; p < npts; p++) {
    st = param == 0 ? rr_model_set_operating(m, values[p], l0, err) : rr_model_set_operating(m, v0, values[p], err);
    if (st) goto out;
    if ((st = rr_modal_solve(m, o, ws, &res, err))) goto out;
    if (p == 0) {
      for (int i = 0; i < res.n; i++) nb += res.modes[i].oscillatory;
      prev = malloc((size_t)(nb ? nb : 1) * (size_t)n * sizeof *prev);
      used = malloc((size_t)res.cap * sizeof *used);
      if (!prev || !used) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto out; }
      int b = 0;
      for (int i = 0; i < res.n; i++) {
        if (!res.modes[i].oscillatory) continue;
        memcpy(prev + (size_t)b * n, res.shapes + (size_t)i * n, (size_t)n * sizeof *prev);
        rr_mode *md = &res.modes[i];
        rr_locus_point lp = {values[p], md->re, md->im, md->freq_hz, md->zeta, 1.0, {md->energy[0], md->energy[1], md->energy[2]}};
        out[b++] = lp;
      }
      continue;
    }
    /* greedy assignment, best correlations first */
    for (int i = 0; i < res.n; i++) used[i] = 0;
    int *done = calloc((size_t)(nb ? nb : 1), sizeof(int));
    if (!done) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto out; }
    for (int round = 0; round < nb; round++) {
      double bestmac = -1;
      int bb = -1, bi = -1;
      for (int b = 0; b < nb; b++) {
        if (done[b]) continue;
        for (int i = 0; i < res.n; i++) {
          if (used[i]) continue;
          double mac = rr_mac(prev + (size_t)b * n, res.shapes + (size_t)i * n, n);
          if (mac > bestmac) { bestmac = mac; bb = b; bi = i; }
        }
      }
      if (bb < 0) break;
      done[bb] = 1;
      used[bi] = 1;
      rr_mode *md = &res.modes[bi];
      rr_locus_point lp = {values[p], md->re, md->im, md->freq_hz, md->zeta, bestmac, {md->energy[0], md->energy[1], md->energy[2]}};
      out[(size_t)p * nb + bb] = lp;
      memcpy(prev + (size_t)bb * n, res.shapes + (size_t)bi * n, (size_t)n * sizeof *prev);
    }
    for (int b = 0; b < nb; b++)
      if (!done[b]) {
        rr_locus_point lp = {values[p], NAN, NAN, NAN, NAN, 0, {NAN, NAN, NAN}};
        out[(size_t)p * nb + b] = lp;
      }
    free(done);
  }
  *nbranch = nb;
out:
  rr_model_set_operating(m, v0, l0, NULL);
  free(prev);
  free(used);
  rr_modal_result_free(&res);
  rr_modal_ws_free(ws);
  return st;
}
