/* Modal analysis: eigenvalues of the state matrix (LAPACK dgeev), modes with
 * frequency, stability index and kinetic-energy shares; the vehicle
 * stability index (MODEL.md section 5); paper-mode SDF self-consistent modes
 * by branch tracking (MODEL.md section 4). */
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/modal.h"
#include "model_impl.h"
#include "clu.h"
#include "hqr.h"
#include "internal.h"

#define OSC_TOL 1e-6

struct rr_modal_ws {
  int N, n;
  double *A, *At, *wr, *wi, *vr, *work;
  int lwork;
  double complex *D, *x;
  int *piv;
  int *cand;
  double *candz;
  double *Ab, *wrb, *wib, *qrw;   /* batched index: RR_QR_LANES_MAX state matrices, eigenvalues, QR lanes */
  rr_modal_result trk[3];   /* paper-mode tracking scratch */
  double complex *branch;   /* paper-mode: shapes of the branches being followed */
};

rr_modal_opts rr_modal_opts_default(void)
{
  rr_modal_opts o = {10.0, 1e-3};
  return o;
}

int rr_modal_result_alloc(const rr_model *m, rr_modal_result *res, rr_error *err)
{
  int N = rr_model_state_size(m);
  if (m->sdf_mode != RR_SDF_PHYSICAL) N += m->nsdf;   /* room to switch to physical mode */
  memset(res, 0, sizeof *res);
  res->cap = N;
  res->ndof = m->n;
  res->modes = calloc((size_t)N, sizeof *res->modes);
  res->shapes = calloc((size_t)N * (size_t)m->n, sizeof *res->shapes);
  if (!res->modes || !res->shapes) {
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
  free(ws->A); free(ws->At); free(ws->wr); free(ws->wi); free(ws->vr); free(ws->work);
  free(ws->D); free(ws->x); free(ws->piv); free(ws->cand); free(ws->candz); free(ws->branch);
  free(ws->Ab); free(ws->wrb); free(ws->wib); free(ws->qrw);
  for (int i = 0; i < 3; i++) rr_modal_result_free(&ws->trk[i]);
  free(ws);
}

int rr_modal_ws_new(const rr_model *m, rr_modal_ws **out, rr_error *err)
{
  *out = NULL;
  rr_modal_ws *ws = calloc(1, sizeof *ws);
  if (!ws) return rr_seterr(err, RR_ENOMEM, "out of memory");
  int N = 2 * m->n + m->nmx + m->nsdf, n = m->n;   /* largest state of any SDF mode */
  if (m->nsdf == 0) for (int i = 0; i < m->nmx; i++) N += m->mx[i].sdf;
  ws->N = N;
  ws->n = n;
  size_t NN = (size_t)N * (size_t)N;
  ws->A = malloc(NN * sizeof(double));
  ws->At = malloc(NN * sizeof(double));
  ws->vr = malloc(NN * sizeof(double));
  ws->wr = malloc((size_t)N * sizeof(double));
  ws->wi = malloc((size_t)N * sizeof(double));
  ws->D = malloc((size_t)n * (size_t)n * sizeof(double complex));
  ws->x = malloc(2 * (size_t)n * sizeof(double complex));
  ws->piv = malloc((size_t)n * sizeof(int));
  ws->cand = malloc((size_t)N * sizeof(int));
  ws->candz = malloc((size_t)N * sizeof(double));
  ws->branch = malloc((size_t)N * (size_t)n * sizeof(double complex));
  ws->Ab = malloc(RR_QR_LANES_MAX * NN * sizeof(double));
  ws->wrb = malloc(RR_QR_LANES_MAX * (size_t)N * sizeof(double));
  ws->wib = malloc(RR_QR_LANES_MAX * (size_t)N * sizeof(double));
  ws->qrw = malloc(rr_eig_batch_work(N) * sizeof(double));
  int st = RR_OK;
  if (!ws->A || !ws->At || !ws->vr || !ws->wr || !ws->wi || !ws->D || !ws->x || !ws->piv ||
      !ws->cand || !ws->candz || !ws->branch || !ws->Ab || !ws->wrb || !ws->wib || !ws->qrw) {
    st = rr_seterr(err, RR_ENOMEM, "out of memory");
    goto fail;
  }
  double q;
  int info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'N', 'V', N, ws->At, N, ws->wr, ws->wi, NULL, 1,
                                ws->vr, N, &q, -1);
  if (info) { st = rr_seterr(err, RR_ELAPACK, "dgeev workspace query failed (%d)", info); goto fail; }
  ws->lwork = (int)q + 1;
  ws->work = malloc((size_t)ws->lwork * sizeof(double));
  if (!ws->work) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto fail; }
  for (int i = 0; i < 3; i++) {
    memset(&ws->trk[i], 0, sizeof ws->trk[i]);
    ws->trk[i].cap = N;
    ws->trk[i].ndof = n;
    ws->trk[i].modes = calloc((size_t)N, sizeof(rr_mode));
    ws->trk[i].shapes = calloc((size_t)N * (size_t)n, sizeof(double complex));
    if (!ws->trk[i].modes || !ws->trk[i].shapes) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto fail; }
  }
  *out = ws;
  return RR_OK;
fail:
  rr_modal_ws_free(ws);
  return st;
}

double rr_mac(const double complex *a, const double complex *b, int n)
{
  double complex ab = 0;
  double aa = 0, bb = 0;
  for (int i = 0; i < n; i++) {
    ab += conj(a[i]) * b[i];
    aa += creal(a[i] * conj(a[i]));
    bb += creal(b[i] * conj(b[i]));
  }
  if (aa == 0 || bb == 0) return 0;
  return creal(ab * conj(ab)) / (aa * bb);
}

/* Eigen-solve of the state matrix into ws (wr, wi and, with vectors, vr). */
static int eig(const rr_model *m, double sdf_k, int vectors, rr_modal_ws *ws, int *Nout, rr_error *err)
{
  int N = rr_model_state_size(m);
  if (N > ws->N) return rr_seterr(err, RR_EINVAL, "modal workspace too small (%d < %d)", ws->N, N);
  int st = rr_model_state_matrix(m, sdf_k, ws->A, err);
  if (st) return st;
  for (int i = 0; i < N; i++)      /* row-major -> column-major */
    for (int j = 0; j < N; j++) ws->At[j * N + i] = ws->A[i * N + j];
  int info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'N', vectors ? 'V' : 'N', N, ws->At, N, ws->wr, ws->wi,
                                NULL, 1, ws->vr, N, ws->work, ws->lwork);
  if (info) return rr_seterr(err, RR_ELAPACK, "dgeev failed (info %d)", info);
  *Nout = N;
  return RR_OK;
}

/* Eigenvalues this small are zero to working precision: a rigid-body mode
   (free lateral drift at zero conicity) is a double, defective zero, which
   rounding of size eps |A| splits into a pair +-sqrt(eps |A|) that may look
   oscillatory. Exactly they are zero, hence real. */
static int is_osc_scaled(double re, double im, double anorm)
{
  double mag = hypot(re, im);
  return im > OSC_TOL * mag && mag > 100 * sqrt(DBL_EPSILON * anorm);
}

static double max_abs(const double *A, int N)
{
  double m = 0;
  for (int i = 0; i < N * N; i++) {
    double a = fabs(A[i]);
    m = a > m ? a : m;   /* inline, unlike fmax (no NaN reaches here) */
  }
  return m;
}

static void energy_shares(const rr_model *m, const double complex *phi, double *e)
{
  double tot = 0;
  for (int g = 0; g < RR_NGROUPS; g++) e[g] = 0;
  for (int i = 0; i < m->n; i++) {
    double t = m->mdiag[i] * creal(phi[i] * conj(phi[i]));
    e[m->group[i]] += t;
    tot += t;
  }
  for (int g = 0; g < RR_NGROUPS; g++) e[g] = tot > 0 ? e[g] / tot : 0;
}

static void fill_mode(rr_mode *md, double re, double im, double anorm)
{
  memset(md, 0, sizeof *md);
  md->re = re;
  md->im = im;
  md->freq_hz = im / (2 * RR_PI);
  double mag = hypot(re, im);
  md->zeta = mag > 0 ? re / mag : 0;
  md->oscillatory = is_osc_scaled(re, im, anorm);
  md->self_consistent = 1;
}

static void classify(rr_mode *md, const rr_modal_opts *o)
{
  md->hunting = md->energy[RR_GROUP_WHEELSET] >= o->w_min;
  md->in_index = md->oscillatory && md->self_consistent && md->hunting && md->freq_hz <= o->fmax_hz;
}

static int cmp_mode(const void *a, const void *b)
{
  const rr_mode *x = a, *y = b;
  if (x->oscillatory != y->oscillatory) return y->oscillatory - x->oscillatory;
  if (x->oscillatory) return (x->freq_hz > y->freq_hz) - (x->freq_hz < y->freq_hz);
  return (x->re < y->re) - (x->re > y->re);
}

/* Sorts modes and their shapes together. */
static void sort_result(rr_modal_result *res, double complex *scratch)
{
  int n = res->ndof;
  int *order = malloc((size_t)res->n * sizeof(int));
  rr_mode *copy = malloc((size_t)res->n * sizeof(rr_mode));
  if (!order || !copy) { free(order); free(copy); qsort(res->modes, (size_t)res->n, sizeof(rr_mode), cmp_mode); return; }
  for (int i = 0; i < res->n; i++) order[i] = i;
  /* insertion sort on indices: n <= ~50 */
  for (int i = 1; i < res->n; i++) {
    int t = order[i], j = i;
    while (j > 0 && cmp_mode(&res->modes[order[j - 1]], &res->modes[t]) > 0) { order[j] = order[j - 1]; j--; }
    order[j] = t;
  }
  memcpy(copy, res->modes, (size_t)res->n * sizeof(rr_mode));
  memcpy(scratch, res->shapes, (size_t)res->n * (size_t)n * sizeof(double complex));
  for (int i = 0; i < res->n; i++) {
    res->modes[i] = copy[order[i]];
    memcpy(res->shapes + (size_t)i * n, scratch + (size_t)order[i] * n, (size_t)n * sizeof(double complex));
  }
  free(order);
  free(copy);
}

/* Modes from the last eigen-solve (vectors present). */
static void collect(const rr_model *m, int N, const rr_modal_ws *ws, rr_modal_result *res)
{
  int n = m->n;
  double anorm = max_abs(ws->A, N);
  res->n = 0;
  res->ndof = n;
  for (int j = 0; j < N; j++) {
    double re = ws->wr[j], im = ws->wi[j];
    if (im < 0) continue;
    rr_mode *md = &res->modes[res->n];
    fill_mode(md, re, im, anorm);
    double complex *phi = res->shapes + (size_t)res->n * n;
    double nrm = 0, big = 0;
    int ib = 0;
    for (int i = 0; i < n; i++) {
      phi[i] = im > 0 ? ws->vr[(size_t)j * N + i] + I * ws->vr[(size_t)(j + 1) * N + i] : ws->vr[(size_t)j * N + i];
      double a = cabs(phi[i]);
      nrm += a * a;
      if (a > big) { big = a; ib = i; }
    }
    /* unit norm, largest component real and positive */
    if (nrm > 0) {
      double complex sc = conj(phi[ib]) / (cabs(phi[ib]) * sqrt(nrm));
      for (int i = 0; i < n; i++) phi[i] *= sc;
    }
    energy_shares(m, phi, md->energy);
    res->n++;
  }
}

static void finish(rr_modal_result *res, const rr_modal_opts *o, double complex *scratch)
{
  sort_result(res, scratch);
  res->stability_index = -1;
  res->index_mode = -1;
  for (int i = 0; i < res->n; i++) {
    classify(&res->modes[i], o);
    if (res->modes[i].in_index && (res->index_mode < 0 || res->modes[i].zeta > res->stability_index)) {
      res->stability_index = res->modes[i].zeta;
      res->index_mode = i;
    }
  }
}

static int solve_paper(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, rr_modal_result *res, rr_error *err);

int rr_modal_solve(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, rr_modal_result *res, rr_error *err)
{
  rr_modal_opts def = rr_modal_opts_default();
  if (!o) o = &def;
  if (res->cap < rr_model_state_size(m)) return rr_seterr(err, RR_EINVAL, "modal result too small");
  if (m->sdf_mode == RR_SDF_PAPER && m->nsdf > 0) return solve_paper(m, o, ws, res, err);
  int N, st = eig(m, 0, 1, ws, &N, err);
  if (st) return st;
  collect(m, N, ws, res);
  finish(res, o, ws->branch);
  return RR_OK;
}

/* Eigenvector (q part) of D(s) phi = 0 by inverse iteration: with s accurate
   to ~1e-14 one step leaves the null vector accurate to ~1e-8, far finer
   than the energy-share threshold needs. */
static void null_vector(const rr_model *m, double complex s, rr_modal_ws *ws, double complex *phi)
{
  int n = m->n;
  rr_model_dynamic_stiffness(m, s, 0, ws->D);
  double nrm = 0;
  for (int i = 0; i < n * n; i++) nrm += fabs(creal(ws->D[i])) + fabs(cimag(ws->D[i]));
  rr_clu_factor(ws->D, n, ws->piv, 1e-15 * nrm / n);
  for (int i = 0; i < n; i++) phi[i] = 1.0 + 0.1 * i + 0.01 * I * (i % 3);
  rr_clu_solve(ws->D, n, ws->piv, phi);
}

/* The index from the eigenvalues (wr, wi) of the model's state matrix at
   its current operating point: candidates by decreasing zeta, the first
   hunting-related one (null vector of D(lambda)) is the index. */
static void index_from_eigs(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, int N, const double *wr,
                            const double *wi, double anorm, double *zeta)
{
  int nc = 0;
  for (int j = 0; j < N; j++) {
    double re = wr[j], im = wi[j];
    if (im <= 0 || !is_osc_scaled(re, im, anorm) || im / (2 * RR_PI) > o->fmax_hz) continue;
    ws->cand[nc] = j;
    ws->candz[nc] = re / hypot(re, im);
    nc++;
  }
  for (int i = 1; i < nc; i++) {
    int t = ws->cand[i];
    double z = ws->candz[i];
    int k = i;
    while (k > 0 && ws->candz[k - 1] < z) { ws->cand[k] = ws->cand[k - 1]; ws->candz[k] = ws->candz[k - 1]; k--; }
    ws->cand[k] = t;
    ws->candz[k] = z;
  }
  *zeta = -1;
  for (int i = 0; i < nc; i++) {
    int j = ws->cand[i];
    double e[RR_NGROUPS];
    if (o->w_min > 0) {
      null_vector(m, wr[j] + I * wi[j], ws, ws->x);
      energy_shares(m, ws->x, e);
      if (e[RR_GROUP_WHEELSET] < o->w_min) continue;
    }
    *zeta = ws->candz[i];
    break;
  }
}

static int paper_sdf(const rr_model *m) { return m->sdf_mode == RR_SDF_PAPER && m->nsdf > 0; }

int rr_modal_stability_index(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, double *zeta, rr_error *err)
{
  rr_modal_opts def = rr_modal_opts_default();
  if (!o) o = &def;
  if (paper_sdf(m)) {
    rr_modal_result *r = &ws->trk[2];
    int st = solve_paper(m, o, ws, r, err);
    if (st) return st;
    *zeta = r->stability_index;
    return RR_OK;
  }
  /* Eigenvalues only, of the merged state matrix, without balancing: the
     fast path (tests hold it to the full dgeev solve to 1e-10). */
  int N, st = rr_state_matrix_merged(m, 0, ws->A, &N, err);
  if (st) return st;
  memcpy(ws->At, ws->A, sizeof(double) * (size_t)N * N);
  if (rr_eig_small(N, ws->At, ws->wr, ws->wi)) {
    /* not converged (rare): LAPACK's Householder reduction and QR */
    for (int i = 0; i < N; i++)
      for (int j = 0; j < N; j++) ws->At[j * N + i] = ws->A[i * N + j];
    int info = LAPACKE_dgehrd_work(LAPACK_COL_MAJOR, N, 1, N, ws->At, N, ws->wr, ws->work, ws->lwork);
    if (!info) info = LAPACKE_dhseqr_work(LAPACK_COL_MAJOR, 'E', 'N', N, 1, N, ws->At, N, ws->wr, ws->wi, NULL, 1, ws->work, ws->lwork);
    if (info) return rr_seterr(err, RR_ELAPACK, "dgehrd/dhseqr failed (info %d)", info);
  }
  index_from_eigs(m, o, ws, N, ws->wr, ws->wi, max_abs(ws->A, N), zeta);
  return RR_OK;
}

int rr_modal_stability_index_batch(rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, int npts,
                                   const double *speed_ms, const double *conicity, double *zeta, rr_error *err)
{
  rr_modal_opts def = rr_modal_opts_default();
  if (!o) o = &def;
  double v0 = rr_model_speed(m), l0 = rr_model_conicity(m);
  int st = RR_OK;
  int W = rr_eig_batch_lanes();   /* 8 with AVX-512, else 4 */
  for (int p0 = 0; p0 < npts && !st; p0 += W) {
    int nb = npts - p0 < W ? npts - p0 : W, N = 0, fail[RR_QR_LANES_MAX] = {0};
    const double *mats[RR_QR_LANES_MAX];
    double anorm[RR_QR_LANES_MAX];
    size_t NN = (size_t)ws->N * (size_t)ws->N;
    int lanes = nb > 1 && !paper_sdf(m);
    for (int c = 0; c < nb && lanes && !st; c++) {
      double *A = ws->Ab + (size_t)c * NN;
      if (!(st = rr_model_set_operating(m, speed_ms[p0 + c], conicity[p0 + c], err)))
        st = rr_state_matrix_merged(m, 0, A, &N, err);
      mats[c] = A;
      anorm[c] = st ? 0 : max_abs(A, N);
    }
    if (st) break;
    /* one instruction stream for the group; a lane that fails, or a group
       of one, takes the single-point route */
    if (N > 64) lanes = 0;
    if (lanes) rr_eig_batch(N, nb, W, mats, ws->wrb, ws->wib, ws->qrw, fail);
    for (int c = 0; c < nb && !st; c++) {
      if ((st = rr_model_set_operating(m, speed_ms[p0 + c], conicity[p0 + c], err))) break;
      if (lanes && !fail[c])
        index_from_eigs(m, o, ws, N, ws->wrb + (size_t)c * N, ws->wib + (size_t)c * N, anorm[c], &zeta[p0 + c]);
      else
        st = rr_modal_stability_index(m, o, ws, &zeta[p0 + c], err);
    }
  }
  rr_model_set_operating(m, v0, l0, NULL);
  return st;
}

/* ---- paper-mode SDF: self-consistent modes by branch tracking ---- */

static double h_of(const rr_model *m, double k, const rr_mode *md)
{
  return k - rr_sdf_storage(&m->curve, md->freq_hz);
}

/* Best MAC match of shape phi among the modes of r (im >= 0). */
static int best_match(const rr_modal_result *r, const double complex *phi, int n, double *mac)
{
  int best = -1;
  double bm = -1;
  for (int i = 0; i < r->n; i++) {
    double v = rr_mac(phi, r->shapes + (size_t)i * n, n);
    if (v > bm) { bm = v; best = i; }
  }
  *mac = bm;
  return best;
}

static int solve_at(const rr_model *m, double k, rr_modal_ws *ws, rr_modal_result *r, rr_error *err)
{
  int N, st = eig(m, k, 1, ws, &N, err);
  if (st) return st;
  collect(m, N, ws, r);
  return RR_OK;
}

static int solve_paper(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, rr_modal_result *res, rr_error *err)
{
  int n = m->n;
  double k_lo, k_hi;
  rr_sdf_range(&m->curve, &k_lo, &k_hi);
  rr_modal_result *r0 = &ws->trk[0], *rb = res == &ws->trk[2] ? &ws->trk[1] : &ws->trk[2];
  rr_modal_result *rm = res;
  int st = solve_at(m, k_lo, ws, r0, err);
  if (st) return st;
  /* results accumulate in res; the tracking uses r0 (start) and rb (current) */
  rr_mode *outm = malloc((size_t)r0->n * sizeof(rr_mode));
  double complex *outs = malloc((size_t)r0->n * (size_t)n * sizeof(double complex));
  if (!outm || !outs) { free(outm); free(outs); return rr_seterr(err, RR_ENOMEM, "out of memory"); }
  int nout = 0;
  const double tol = 1e-9 * k_hi;
  for (int b = 0; b < r0->n; b++) {
    rr_mode cur = r0->modes[b];
    if (!cur.oscillatory) {   /* not followed: reported as at k_lo */
      outm[nout] = cur;
      outm[nout].sdf_k = k_lo;
      memcpy(outs + (size_t)nout * n, r0->shapes + (size_t)b * n, (size_t)n * sizeof(double complex));
      nout++;
      continue;
    }
    double complex *phi = ws->branch;
    memcpy(phi, r0->shapes + (size_t)b * n, (size_t)n * sizeof(double complex));
    double k = k_lo, h = h_of(m, k, &cur);
    double step = (k_hi - k_lo) / 32;
    int found = h >= 0, lost = 0;
    double ka = k, kb = k;
    rr_mode mb = cur;
    double complex *phia = ws->x;   /* n entries */
    memcpy(phia, phi, (size_t)n * sizeof(double complex));
    while (!found && !lost) {
      double kn = fmin(k + step, k_hi);
      if ((st = solve_at(m, kn, ws, rb, err))) goto out;
      double mac;
      int j = best_match(rb, phi, n, &mac);
      if (j < 0 || mac < 0.9) {
        step *= 0.5;
        if (step < 1e-12 * k_hi) lost = 1;
        continue;
      }
      rr_mode nx = rb->modes[j];
      if (!nx.oscillatory) { lost = 1; break; }
      double hn = h_of(m, kn, &nx);
      if (hn >= 0) {
        ka = k; memcpy(phia, phi, (size_t)n * sizeof(double complex));
        kb = kn; mb = nx;
        memcpy(phi, rb->shapes + (size_t)j * n, (size_t)n * sizeof(double complex));
        found = 1;
        break;
      }
      k = kn; cur = nx; h = hn;
      memcpy(phi, rb->shapes + (size_t)j * n, (size_t)n * sizeof(double complex));
      if (k >= k_hi) lost = 1;
    }
    if (found && h >= 0 && ka == kb) {   /* root at k_lo itself */
      mb = cur;
    } else if (found) {
      /* bisect the sign change, following the branch from the lower end */
      while (kb - ka > tol) {
        double km = 0.5 * (ka + kb);
        if ((st = solve_at(m, km, ws, rb, err))) goto out;
        double mac;
        int j = best_match(rb, phia, n, &mac);
        if (j < 0 || !rb->modes[j].oscillatory) { lost = 1; break; }
        rr_mode mm = rb->modes[j];
        if (h_of(m, km, &mm) >= 0) { kb = km; mb = mm; memcpy(phi, rb->shapes + (size_t)j * n, (size_t)n * sizeof(double complex)); }
        else { ka = km; memcpy(phia, rb->shapes + (size_t)j * n, (size_t)n * sizeof(double complex)); }
      }
    }
    rr_mode rep = found && !lost ? mb : cur;
    rep.self_consistent = found && !lost;
    rep.sdf_k = found && !lost ? kb : k;
    outm[nout] = rep;
    memcpy(outs + (size_t)nout * n, phi, (size_t)n * sizeof(double complex));
    nout++;
  }
  rm->n = nout;
  rm->ndof = n;
  memcpy(rm->modes, outm, (size_t)nout * sizeof(rr_mode));
  memcpy(rm->shapes, outs, (size_t)nout * (size_t)n * sizeof(double complex));
  finish(rm, o, ws->branch);
out:
  free(outm);
  free(outs);
  return st;
}
