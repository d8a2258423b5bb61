/* Modal analysis: modes of the state matrix with frequency, stability index,
 * energy shares and names (rr_modal_solve, LAPACK dgeev), and the vehicle
 * stability index by the cheapest exact route (rr_modal_stability: our QR on
 * the merged state matrix, shapes of candidate modes only). Paper-mode SDF
 * modes are in sdf_modes.c. */
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "modal/modal_impl.h"
#include "linalg/max_abs.h"
#include "model/dynamic_stiffness.h"
#include "linalg/hessenberg_qr.h"
#include "util/internal.h"
#include "util/block.h"

rr_modal_opts rr_modal_opts_default(void)
{
  return (rr_modal_opts){
      .fmax_hz = RR_FMAX_AUTO, .w_min = 1e-3, .r_max = 0.5, .tracking = RR_TRACK_FAST};
}

static int result_init(rr_modal_result *res, int cap, int n)
{
  memset(res, 0, sizeof *res);
  res->cap = cap;
  res->ndof = n;
  res->modes = calloc((size_t)cap, sizeof *res->modes);
  res->shapes = calloc((size_t)cap * (size_t)n, sizeof *res->shapes);
  return res->modes && res->shapes ? RR_OK : RR_ENOMEM;
}

/* Room for the largest state of any SDF mode the model may switch to. */
int rr_modal_state_cap(const rr_model *m)
{
  int N = 2 * m->n + m->nmx + m->nsdf;
  if (m->nsdf == 0)
    for (int i = 0; i < m->nmx; i++) N += m->mx[i].sdf;
  return N;
}

int rr_modal_result_alloc(const rr_model *m, rr_modal_result *res, rr_error *err)
{
  if (result_init(res, rr_modal_state_cap(m), m->n)) {
    rr_modal_result_free(res);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  return RR_OK;
}

void rr_modal_result_free(rr_modal_result *res)
{
  if (!res) return;
  free(res->modes);
  free(res->shapes);
  res->modes = NULL;
  res->shapes = NULL;
  res->n = res->cap = 0;
}

void rr_modal_ws_free(rr_modal_ws *ws)
{
  if (!ws) return;
  free(ws->block);
  free(ws);
}

/* The workspace's arrays (block.h: called to size, then to carve). */
static void ws_layout(rr_modal_ws *ws, rr_block *b)
{
  size_t N = (size_t)ws->N, n = (size_t)ws->n, NN = N * N, L = RR_QR_LANES_MAX;
  const size_t d = sizeof(double), z = sizeof(double complex), i = sizeof(int);
  ws->A = rr_block_take(b, NN, d);
  ws->At = rr_block_take(b, NN, d);
  ws->vr = rr_block_take(b, NN, d);
  ws->wr = rr_block_take(b, N, d);
  ws->wi = rr_block_take(b, N, d);
  ws->work = rr_block_take(b, (size_t)ws->lwork, d);
  ws->D = rr_block_take(b, n * n, z);
  ws->Dp = rr_block_take(b, n * n, z);
  ws->x = rr_block_take(b, 2 * n, z);
  ws->tv = rr_block_take(b, 12 * n, z);
  ws->ds = rr_block_take(b, 1, sizeof *ws->ds); /* zeroed: no cached factors yet */
  ws->dsi = rr_block_take(b, RR_DSOLVER_IWORK(n), i);
  ws->dsz = rr_block_take(b, RR_DSOLVER_ZWORK(n), z);
  ws->piv = rr_block_take(b, n, i);
  ws->cand = rr_block_take(b, N, i);
  ws->candz = rr_block_take(b, N, d);
  ws->branch = rr_block_take(b, N * n, z);
  ws->Ab = rr_block_take(b, L * NN, d);
  ws->wrb = rr_block_take(b, L * N, d);
  ws->wib = rr_block_take(b, L * N, d);
  ws->qrw = rr_block_take(b, rr_eig_batch_work(ws->N), d);
  ws->candb = rr_block_take(b, L * N, i);
  ws->candzb = rr_block_take(b, L * N, d);
  ws->phib = rr_block_take(b, RR_DSL_LANES * n, z);
  ws->dsl = rr_block_take(b, 1, sizeof *ws->dsl);
  rr_dsl sizing, *dl = ws->dsl ? ws->dsl : &sizing;
  rr_dsl_layout(dl, ws->n, b);
  for (int k = 0; k < 4; k++) { /* the tracking results: owned by the block, not freed apart */
    rr_modal_result *r = &ws->trk[k];
    *r = (rr_modal_result){.cap = ws->N, .ndof = ws->n};
    r->modes = rr_block_take(b, N, sizeof *r->modes);
    r->shapes = rr_block_take(b, N * n, sizeof *r->shapes);
  }
}

int rr_modal_ws_new(const rr_model *m, rr_modal_ws **out, rr_error *err)
{
  *out = NULL;
  rr_modal_ws *ws = calloc(1, sizeof *ws);
  if (!ws) return rr_seterr(err, RR_ENOMEM, "out of memory");
  ws->N = rr_modal_state_cap(m);
  ws->n = m->n;
  double q;
  int N = ws->N, info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'N', 'V', N, NULL, N, NULL, NULL, NULL,
                                           1, NULL, N, &q, -1);
  if (info) {
    free(ws);
    return rr_seterr(err, RR_ELAPACK, "dgeev workspace query failed (%d)", info);
  }
  ws->lwork = (int)q + 1;
  rr_block b = {0};
  ws_layout(ws, &b);
  if (rr_block_alloc(&b)) {
    free(ws);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  ws->block = b.base;
  ws_layout(ws, &b);
  *out = ws;
  return RR_OK;
}

_Static_assert(RR_DSL_LANES >= RR_QR_LANES_MAX, "a group's points each need a shape lane");

static int paper_sdf(const rr_model *m) { return m->sdf_mode == RR_SDF_PAPER && m->nsdf > 0; }

int rr_modal_solve(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, rr_modal_result *res,
                   rr_error *err)
{
  rr_modal_opts def = rr_modal_opts_default();
  if (!o) o = &def;
  if (res->cap < rr_model_state_size(m)) return rr_seterr(err, RR_EINVAL, "modal result too small");
  if (paper_sdf(m)) return rr_sdf_modes(m, o, ws, res, err);
  int N, st = rr_modal_eig(m, 0, 1, ws, &N, err);
  if (st) return st;
  rr_modal_collect(m, N, ws, res);
  rr_modal_finish(m, res, o, ws->branch);
  return RR_OK;
}

/* The q shape of eigenvalue s by one inverse-iteration step on D(s) (the
   sparse solver of ws->ds, initialised for the model): with s accurate to
   ~1e-14 the vector is accurate to ~1e-8, far finer than the share
   thresholds need. */
static void shape_of(rr_modal_ws *ws, double complex s, double complex *phi)
{
  int n = ws->ds->n;
  double complex *t = ws->x + n;
  rr_dsolver_factor(ws->ds, s, 0);
  for (int i = 0; i < n; i++) t[i] = rr_dsolver_start(i);
  rr_dsolver_solve(ws->ds, t, ws->tv);
  rr_dsolver_from(ws->ds, t, phi);
}

/* The index from hunting_index and zeta_max (index_freq_hz holds the
   hunting mode's frequency on entry). */
static void stability_resolve(rr_stability *s)
{
  int which;
  s->index = rr_modal_index_rule(s->hunting_index, s->zeta_max, !isnan(s->max_freq_hz), &s->source,
                                 &which);
  s->index_freq_hz = which == 1 ? s->max_freq_hz : which == 0 ? s->index_freq_hz : NAN;
}

static int needs_shape(const rr_modal_opts *o) { return o->w_min > 0 || o->r_max < 1; }

/* zeta_max over every oscillatory mode of the eigenvalues (wr, wi) into out
   (whose other fields it starts), and the index candidates, the modes below
   the band edge fmax (Hz), by decreasing zeta into cand and candz; returns
   their count. */
static int index_candidates(double fmax, int N, const double *wr, const double *wi, double anorm,
                            int *cand, double *candz, rr_stability *out)
{
  int nc = 0;
  *out = (rr_stability){.index = NAN,
                        .index_freq_hz = NAN,
                        .hunting_index = NAN,
                        .zeta_max = -1,
                        .max_freq_hz = NAN,
                        .fmax_hz = fmax};
  for (int j = 0; j < N; j++) {
    double re = wr[j], im = wi[j];
    if (im <= 0 || !rr_modal_is_osc(re, im, anorm)) continue;
    double z = re / hypot(re, im);
    if (isnan(out->max_freq_hz) || z > out->zeta_max) {
      out->zeta_max = z;
      out->max_freq_hz = im / (2 * RR_PI);
    }
    if (im / (2 * RR_PI) > fmax) continue;
    int k = nc++;
    while (k > 0 && candz[k - 1] < z) {
      cand[k] = cand[k - 1];
      candz[k] = candz[k - 1];
      k--;
    }
    cand[k] = j;
    candz[k] = z;
  }
  return nc;
}

/* Candidate i (an index into the eigenvalues' wi) is the hunting mode. */
static void take_candidate(const double *wi, const int *cand, const double *candz, int i,
                           rr_stability *out)
{
  out->hunting_index = candz[i];
  out->index_freq_hz = wi[cand[i]] / (2 * RR_PI);
}

/* The shapes of m's candidates (ws->ds initialised at m's operating point)
   one by one until one is hunting-related. */
static void test_candidates(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                            const double *wr, const double *wi, const int *cand,
                            const double *candz, int nc, rr_stability *out)
{
  for (int i = 0; i < nc; i++) {
    int j = cand[i];
    rr_mode md;
    shape_of(ws, wr[j] + I * wi[j], ws->x);
    rr_mode_energy(m, ws->x, &md);
    if (!rr_modal_hunting_related(&md, o)) continue;
    take_candidate(wi, cand, candz, i, out);
    return;
  }
}

/* Stability from the eigenvalues (wr, wi) of the model's state matrix at its
   operating point: zeta_max over every oscillatory mode, and the index as the
   first hunting-related candidate by decreasing zeta (a null vector of
   D(lambda) gives its shares). */
static void stability_from_eigs(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, int N,
                                const double *wr, const double *wi, double anorm, rr_stability *out)
{
  int nc = index_candidates(rr_modal_band_edge(m, o), N, wr, wi, anorm, ws->cand, ws->candz, out);
  if (nc > 0 && !needs_shape(o))
    take_candidate(wi, ws->cand, ws->candz, 0, out);
  else if (nc > 0) {
    rr_dsolver_init(ws->ds, m, ws->dsi, ws->dsz);
    test_candidates(m, o, ws, wr, wi, ws->cand, ws->candz, nc, out);
  }
  stability_resolve(out);
}

static void stability_from_result(const rr_modal_result *r, rr_stability *out)
{
  out->index = r->stability_index;
  out->index_freq_hz = r->index_mode >= 0 ? r->modes[r->index_mode].freq_hz : NAN;
  out->source = r->index_source;
  out->hunting_index = r->hunting_index;
  out->zeta_max = r->zeta_max;
  out->max_freq_hz = r->max_mode >= 0 ? r->modes[r->max_mode].freq_hz : NAN;
  out->fmax_hz = r->fmax_hz;
}

/* Eigenvalues of the merged state matrix by our QR (in place: *anorm keeps
   what the classification needs of it), LAPACK's when it fails. */
static int eigenvalues_merged(const rr_model *m, rr_modal_ws *ws, int *Nout, double *anorm,
                              rr_error *err)
{
  int N, st = rr_state_matrix_merged(m, 0, ws->A, &N, err);
  if (st) return st;
  *Nout = N;
  *anorm = rr_max_abs((size_t)N * (size_t)N, ws->A);
  if (!rr_eig_small(N, ws->A, ws->wr, ws->wi)) return RR_OK;
  if ((st = rr_state_matrix_merged(m, 0, ws->A, &N, err))) return st;
  for (int i = 0; i < N; i++) /* not converged (rare): Householder reduction and LAPACK's QR */
    for (int j = 0; j < N; j++) ws->At[j * N + i] = ws->A[i * N + j];
  int info = LAPACKE_dgehrd_work(LAPACK_COL_MAJOR, N, 1, N, ws->At, N, ws->wr, ws->work, ws->lwork);
  if (!info)
    info = LAPACKE_dhseqr_work(LAPACK_COL_MAJOR, 'E', 'N', N, 1, N, ws->At, N, ws->wr, ws->wi, NULL,
                               1, ws->work, ws->lwork);
  if (info) return rr_seterr(err, RR_ELAPACK, "dgehrd/dhseqr failed (info %d)", info);
  return RR_OK;
}

static int check_finite(const rr_stability *s, rr_error *err)
{
  /* an undefined index is NaN by rule (RR_INDEX_NONE), not by overflow */
  if ((isfinite(s->index) || s->source == RR_INDEX_NONE) && isfinite(s->zeta_max) &&
      !(s->source == RR_INDEX_NONE && s->zeta_max >= 0))
    return RR_OK;
  return rr_seterr(err, RR_ENOCONV,
                   "stability index is not finite (the model's matrices overflow)");
}

int rr_modal_stability(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                       rr_stability *out, rr_error *err)
{
  rr_modal_opts def = rr_modal_opts_default();
  if (!o) o = &def;
  if (paper_sdf(m)) {
    rr_modal_result *r = &ws->trk[2];
    int st = rr_sdf_modes_fast_osc(m, o, ws, r, err);
    if (st) return st;
    stability_from_result(r, out);
    return check_finite(out, err);
  }
  int N;
  double anorm;
  int st = eigenvalues_merged(m, ws, &N, &anorm, err);
  if (st) return st;
  stability_from_eigs(m, o, ws, N, ws->wr, ws->wi, anorm, out);
  return check_finite(out, err);
}

int rr_modal_stability_index(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                             double *zeta, rr_error *err)
{
  rr_stability s;
  int st = rr_modal_stability(m, o, ws, &s, err);
  if (!st) *zeta = s.index;
  return st;
}

/* A QR group's points whose shapes are tested in the lanes of ws->dsl (see
 * lane_stability): point c on mods[c] at (v[c], lam[c]), its candidates at
 * ws->candb + c N (nc[c] of them, next[c] the one to test). */
typedef struct lane_group {
  rr_model *const *mods;
  const double *v, *lam;
  int N, nc[RR_DSL_LANES], next[RR_DSL_LANES];
  unsigned todo, single; /* points in the lanes; points the single solver takes */
} lane_group;

/* Point c's model at its operating point and ws->ds initialised there. */
static int point_solver(const lane_group *g, int c, rr_modal_ws *ws, rr_error *err)
{
  int st = rr_model_set_operating(g->mods[c], g->v[c], g->lam[c], err);
  if (!st) rr_dsolver_init(ws->ds, g->mods[c], ws->dsi, ws->dsz);
  return st;
}

/* The shape of point c's candidate next[c] by the single solver (ws->ds at
   its point) into phi. */
static void single_shape(const lane_group *g, int c, rr_modal_ws *ws, double complex *phi)
{
  size_t off = (size_t)c * (size_t)g->N, j = (size_t)ws->candb[off + (size_t)g->next[c]];
  shape_of(ws, ws->wrb[off + j] + I * ws->wib[off + j], phi);
}

/* Point c's candidate next[c], its shape phi: the hunting mode, or on to
   the next candidate; the point leaves the lanes when settled. */
static void settle(lane_group *g, int c, const rr_modal_opts *o, const rr_modal_ws *ws,
                   const double complex *phi, rr_stability *out)
{
  size_t off = (size_t)c * (size_t)g->N;
  rr_mode md;
  rr_mode_energy(g->mods[c], phi, &md);
  if (rr_modal_hunting_related(&md, o))
    take_candidate(ws->wib + off, ws->candb + off, ws->candzb + off, g->next[c], out);
  else if (++g->next[c] < g->nc[c])
    return;
  g->todo &= ~(1u << c);
}

/* Every point's candidates; the points that need shapes loaded into the
   lanes (or left to the single solver), and the lanes given a pivot order:
   ws->ds's if it has one on their pattern, else the one the first point's
   first test finds. */
static int lanes_start(lane_group *g, int nb, const rr_modal_opts *o, rr_modal_ws *ws,
                       const double *anorm, const int *fail, rr_stability *out, rr_error *err)
{
  int st, last = -1;
  rr_dsl_reset(ws->dsl);
  for (int c = 0; c < nb; c++) {
    size_t off = (size_t)c * (size_t)g->N;
    if (fail[c]) continue;
    double fmax = rr_modal_band_edge_at(g->mods[c], o, g->v[c], g->lam[c]);
    g->nc[c] = index_candidates(fmax, g->N, ws->wrb + off, ws->wib + off, anorm[c], ws->candb + off,
                                ws->candzb + off, &out[c]);
    if (g->nc[c] > 0 && !needs_shape(o))
      take_candidate(ws->wib + off, ws->candb + off, ws->candzb + off, 0, &out[c]);
    if (g->nc[c] == 0 || !needs_shape(o)) continue;
    if ((st = point_solver(g, c, ws, err))) return st;
    last = c;
    if (rr_dsl_load(ws->dsl, c, ws->ds))
      g->single |= 1u << c;
    else
      g->todo |= 1u << c;
  }
  if (!g->todo || rr_dsl_has_order(ws->dsl)) return RR_OK;
  if ((g->single >> last & 1) || ws->ds->dirty) {
    int c = __builtin_ctz(g->todo);
    if ((st = point_solver(g, c, ws, err))) return st;
    if (ws->ds->dirty) {
      single_shape(g, c, ws, ws->phib + (size_t)c * (size_t)ws->n);
      settle(g, c, o, ws, ws->phib + (size_t)c * (size_t)ws->n, &out[c]);
    }
  }
  rr_dsl_keep_order(ws->dsl, ws->ds);
  return RR_OK;
}

/* Rounds until every point in the lanes has its hunting mode or has run
   out of candidates: each tests every such point's next candidate at once;
   a test no kept order suits goes to the single solver, whose order is kept. */
static int lanes_rounds(lane_group *g, int nb, const rr_modal_opts *o, rr_modal_ws *ws,
                        rr_stability *out, rr_error *err)
{
  while (g->todo) {
    double sr[RR_DSL_LANES] = {0}, si[RR_DSL_LANES] = {0};
    for (int c = 0; c < nb; c++) {
      if (!(g->todo >> c & 1)) continue;
      size_t off = (size_t)c * (size_t)g->N, j = (size_t)ws->candb[off + (size_t)g->next[c]];
      sr[c] = ws->wrb[off + j];
      si[c] = ws->wib[off + j];
    }
    unsigned bad = rr_dsl_shapes(ws->dsl, g->todo, sr, si, ws->phib);
    for (int c = 0; c < nb; c++) {
      if (!(g->todo >> c & 1)) continue;
      double complex *phi = ws->phib + (size_t)c * (size_t)ws->n;
      if (bad >> c & 1) {
        int st = point_solver(g, c, ws, err);
        if (st) return st;
        single_shape(g, c, ws, phi);
        rr_dsl_keep_order(ws->dsl, ws->ds);
      }
      settle(g, c, o, ws, phi, &out[c]);
    }
  }
  return RR_OK;
}

/* The index of each point of a QR group whose QR did not fail, from its
   eigenvalues in ws->wrb, ws->wib: its shape tests in SIMD lanes, those of
   points whose pattern is not the lanes' by the single solver. Leaves the
   models at any of their points. */
static int lane_stability(rr_model *const *mods, const rr_modal_opts *o, rr_modal_ws *ws, int nb,
                          const double *v, const double *lam, int N, const double *anorm,
                          const int *fail, rr_stability *out, rr_error *err)
{
  lane_group g = {.mods = mods, .v = v, .lam = lam, .N = N};
  int st = lanes_start(&g, nb, o, ws, anorm, fail, out, err);
  if (!st) st = lanes_rounds(&g, nb, o, ws, out, err);
  for (int c = 0; c < nb && !st; c++) {
    size_t off = (size_t)c * (size_t)N;
    if ((g.single >> c & 1) && !(st = point_solver(&g, c, ws, err)))
      test_candidates(mods[c], o, ws, ws->wrb + off, ws->wib + off, ws->candb + off,
                      ws->candzb + off, g.nc[c], &out[c]);
    if (!fail[c]) stability_resolve(&out[c]);
  }
  return st;
}

/* One group of up to RR_QR_LANES_MAX points, point c on model mods[c]: their
   state matrices in SIMD lanes; a lane that fails, a group of one, or
   state matrices of unequal order take the single-point route. */
static int batch_group(rr_model *const *mods, const rr_modal_opts *o, rr_modal_ws *ws, int nb,
                       const double *v, const double *lam, rr_stability *out, rr_error *err)
{
  int N = 0, fail[RR_QR_LANES_MAX] = {0}, st = RR_OK;
  const double *mats[RR_QR_LANES_MAX];
  double anorm[RR_QR_LANES_MAX];
  size_t NN = (size_t)ws->N * (size_t)ws->N;
  int lanes = nb > 1;
  for (int c = 0; c < nb && lanes; c++) {
    double *A = ws->Ab + (size_t)c * NN;
    int Nc;
    if (paper_sdf(mods[c])) {
      lanes = 0;
      break;
    }
    if ((st = rr_model_set_operating(mods[c], v[c], lam[c], err))) return st;
    if ((st = rr_state_matrix_merged(mods[c], 0, A, &Nc, err))) return st;
    if (c > 0 && Nc != N) lanes = 0;
    N = Nc;
    mats[c] = A;
    anorm[c] = rr_max_abs((size_t)N * (size_t)N, A);
  }
  if (N > 64) lanes = 0;
  if (lanes) {
    rr_eig_batch(N, nb, rr_eig_batch_lanes(), mats, ws->wrb, ws->wib, ws->qrw, fail);
    if ((st = lane_stability(mods, o, ws, nb, v, lam, N, anorm, fail, out, err))) return st;
  }
  for (int c = 0; c < nb; c++) {
    if (lanes && !fail[c]) {
      st = check_finite(&out[c], err);
    } else {
      if ((st = rr_model_set_operating(mods[c], v[c], lam[c], err))) return st;
      st = rr_modal_stability(mods[c], o, ws, &out[c], err);
    }
    if (st) return st;
  }
  return RR_OK;
}

/* A model the workspace was not made for would overrun it. */
static int check_fits(const rr_model *m, const rr_modal_ws *ws, rr_error *err)
{
  if (m->n == ws->n && rr_modal_state_cap(m) <= ws->N) return RR_OK;
  return rr_seterr(err, RR_EINVAL, "modal workspace made for another vehicle layout (%d dof)",
                   ws->n);
}

/* The groups of npts points, point p on mods[p * mstride] (mstride 0: one
   model); every model's operating point is restored, in reverse order so
   that a model met twice gets its first one. */
static int stability_points(rr_model *const *mods, int mstride, const rr_modal_opts *o,
                            rr_modal_ws *ws, int npts, const double *v, const double *lam,
                            rr_stability *out, rr_error *err)
{
  rr_modal_opts def = rr_modal_opts_default();
  if (!o) o = &def;
  int st = RR_OK, W = rr_eig_batch_lanes();
  for (int p0 = 0; p0 < npts && !st; p0 += W) {
    int nb = npts - p0 < W ? npts - p0 : W;
    rr_model *g[RR_QR_LANES_MAX];
    double v0[RR_QR_LANES_MAX], l0[RR_QR_LANES_MAX];
    for (int c = 0; c < nb; c++) {
      g[c] = mods[(size_t)(p0 + c) * (size_t)mstride];
      if ((st = check_fits(g[c], ws, err))) return st;
      v0[c] = rr_model_speed(g[c]);
      l0[c] = rr_model_conicity(g[c]);
    }
    st = batch_group(g, o, ws, nb, v + p0, lam + p0, out + p0, err);
    for (int c = nb - 1; c >= 0; c--) rr_model_set_operating(g[c], v0[c], l0[c], NULL);
  }
  return st;
}

int rr_modal_stability_batch(rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, int npts,
                             const double *speed_ms, const double *conicity, rr_stability *out,
                             rr_error *err)
{
  return stability_points(&m, 0, o, ws, npts, speed_ms, conicity, out, err);
}

int rr_modal_stability_many(rr_model *const *models, const rr_modal_opts *o, rr_modal_ws *ws,
                            int npts, const double *speed_ms, const double *conicity,
                            rr_stability *out, rr_error *err)
{
  return stability_points(models, 1, o, ws, npts, speed_ms, conicity, out, err);
}
