/* Frequency response by modal expansion (+ Sherman-Morrison-Woodbury for the
 * SDF elements that have no state-space form) or by direct solves, and the
 * pseudo-excitation method (docs/model.md section 6). */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/pem.h"
#include "model/model_impl.h"
#include "linalg/complex_lu.h"
#include "linalg/eigen_decomposition.h"
#include "linalg/gemm.h"
#include "linalg/real_lu.h"
#include "ride/frf_sparse.h"
#include "util/internal.h"
#include "util/block.h"

#define MAXU 8
#define FCHUNK 200 /* frequencies per GEMM, whole FV steps: weights and sums stay in cache */

struct rr_frf_plan {
  int n, ni, np, nf, Nmax, method, use_dgeev;
  enum rr_frf_method route; /* the method the last execute took */
  double *f;                /* nf */
  double *rows, *rows0;     /* np x n */
  double complex *H;        /* nf x np x ni */
  double complex *Hs;       /* nf x np: the response to the inputs' lagged sum (rr_pem_design) */
  /* modal workspace */
  double *A, *At, *vl, *vr, *wr, *wi, *work;
  int lwork;
  double complex *lam, *o, *o0, *b, *u, *c; /* per mode: np, np, ni, nU, nU */
  double *T;        /* E x K: per residue entry, its real part in each term (pair or real mode),
                       then the pairs' imaginary parts */
  double *Wt, *acc; /* per frequency chunk: K x 2 FCHUNK weights, E x 2 FCHUNK sums */
  double *ework, *V, *rhs; /* eigdec workspace, LU of the eigenvector basis, its right-hand sides */
  int *iwork, *vpiv;
  double complex *lag; /* nf x ni: exp(j w x_i / v) at lag_speed */
  double lag_speed, lag_x[RR_SYS_MAX_INPUTS];
  /* direct workspace */
  double complex *D, *X;
  int *piv;
  rr_frf_sparse sparse; /* sparse workspace */
  char *block;          /* every array above, one allocation (block.h) */
};

void rr_frf_plan_free(rr_frf_plan *p)
{
  if (!p) return;
  free(p->block);
  free(p);
}

rr_frf_opts rr_frf_opts_default(void)
{
  return (rr_frf_opts){.nfreq = RR_FRF_NFREQ_DEFAULT,
                       .freqs_hz = NULL,
                       .f_lo_hz = RR_FRF_F_LO_DEFAULT,
                       .f_hi_hz = RR_FRF_F_HI_DEFAULT,
                       .npoints = 0,
                       .rows = NULL,
                       .rows0 = NULL,
                       .method = RR_FRF_SPARSE};
}

/* The plan's arrays for nf frequencies, np points, n DOFs and N states at
   most (block.h: called to size, then to carve). */
static void plan_layout(rr_frf_plan *p, int N, int lwork, rr_block *b)
{
  size_t n = (size_t)p->n, np = (size_t)p->np, ni = (size_t)p->ni, nf = (size_t)p->nf,
         NN = (size_t)N * (size_t)N, Nz = (size_t)N;
  size_t E = np * ni + MAXU * ni + np * MAXU + MAXU * MAXU; /* residue entries a term, at most */
  const size_t d = sizeof(double), z = sizeof(double complex), i = sizeof(int);
  p->f = rr_block_take(b, nf, d);
  p->rows = rr_block_take(b, np * n, d);
  p->rows0 = rr_block_take(b, np * n, d);
  p->H = rr_block_take(b, nf * np * ni, z);
  p->Hs = rr_block_take(b, nf * np, z);
  p->A = rr_block_take(b, NN, d);
  p->At = rr_block_take(b, NN, d);
  p->vl = rr_block_take(b, NN, d);
  p->vr = rr_block_take(b, NN, d);
  p->wr = rr_block_take(b, Nz, d);
  p->wi = rr_block_take(b, Nz, d);
  p->work = rr_block_take(b, (size_t)lwork, d);
  p->lam = rr_block_take(b, Nz, z);
  p->o = rr_block_take(b, Nz * np, z);
  p->o0 = rr_block_take(b, Nz * np, z);
  p->b = rr_block_take(b, Nz * ni, z);
  p->u = rr_block_take(b, Nz * MAXU, z);
  p->c = rr_block_take(b, Nz * MAXU, z);
  p->T = rr_block_take(b, 2 * Nz * E, d);
  p->Wt = rr_block_take(b, 2 * FCHUNK * 2 * Nz, d);
  p->acc = rr_block_take(b, 2 * FCHUNK * E, d);
  p->ework = rr_block_take(b, RR_EIGDEC_LWORK(Nz), d);
  p->V = rr_block_take(b, NN, d);
  p->rhs = rr_block_take(b, Nz * (ni + MAXU + 2), d); /* N x nr by rows, then the estimate's N */
  p->iwork = rr_block_take(b, RR_EIGDEC_LIWORK(Nz) + Nz, i);
  p->vpiv = rr_block_take(b, Nz, i);
  p->lag = rr_block_take(b, nf * ni, z);
  p->D = rr_block_take(b, n * n, z);
  p->X = rr_block_take(b, n * (ni + MAXU), z);
  p->piv = rr_block_take(b, n, i);
  rr_frf_sparse_layout(&p->sparse, p->n, p->ni, p->np, b);
}

/* The frequency grid: the one given, else log-spaced from f_lo to f_hi. */
static int plan_freqs(rr_frf_plan *p, const rr_frf_opts *o, rr_error *err)
{
  int nf = p->nf;
  double lo = o->f_lo_hz > 0 ? o->f_lo_hz : RR_FRF_F_LO_DEFAULT,
         hi = o->f_hi_hz > 0 ? o->f_hi_hz : RR_FRF_F_HI_DEFAULT;
  for (int i = 0; i < nf; i++) {
    p->f[i] = o->freqs_hz ? o->freqs_hz[i] : nf == 1 ? lo : lo * pow(hi / lo, (double)i / (nf - 1));
    if (!(isfinite(p->f[i]) && p->f[i] > 0))
      return rr_seterr(err, RR_EINVAL, "frf: frequencies must be > 0");
  }
  return RR_OK;
}

int rr_frf_plan_new(const rr_model *m, const rr_frf_opts *o, rr_frf_plan **out, rr_error *err)
{
  *out = NULL;
  if (!o || o->npoints < 1 || !o->rows)
    return rr_seterr(err, RR_EINVAL, "frf: at least one output row is needed");
  int nf = o->nfreq > 0 ? o->nfreq : RR_FRF_NFREQ_DEFAULT;
  if (!o->freqs_hz) {
    double lo = o->f_lo_hz > 0 ? o->f_lo_hz : RR_FRF_F_LO_DEFAULT,
           hi = o->f_hi_hz > 0 ? o->f_hi_hz : RR_FRF_F_HI_DEFAULT;
    if (!(hi > lo) && nf > 1) return rr_seterr(err, RR_EINVAL, "frf: need 0 < f_lo < f_hi");
  }
  if (o->method != RR_FRF_MODAL && o->method != RR_FRF_DIRECT && o->method != RR_FRF_MODAL_LAPACK &&
      o->method != RR_FRF_SPARSE)
    return rr_seterr(err, RR_EINVAL, "frf: unknown method");
  rr_frf_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  p->n = m->n;
  p->np = o->npoints;
  p->ni = m->ni;
  p->nf = nf;
  p->method = o->method == RR_FRF_MODAL_LAPACK ? (int)RR_FRF_MODAL : (int)o->method;
  p->use_dgeev = o->method == RR_FRF_MODAL_LAPACK;
  int N = 2 * m->n + m->nmx + m->nsdf + 2;
  for (int i = 0; i < m->nmx; i++) N += m->mx[i].sdf; /* room for physical mode */
  p->Nmax = N;
  double q;
  if (LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'V', 'V', N, NULL, N, NULL, NULL, NULL, N, NULL, N, &q,
                         -1)) {
    rr_frf_plan_free(p);
    return rr_seterr(err, RR_ELAPACK, "dgeev workspace query failed");
  }
  p->lwork = (int)q + 1;
  rr_block b = {0};
  plan_layout(p, N, p->lwork, &b);
  if (rr_block_alloc(&b)) {
    rr_frf_plan_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  p->block = b.base;
  plan_layout(p, N, p->lwork, &b);
  p->lag_speed = -1;
  memcpy(p->rows, o->rows, sizeof(double) * (size_t)p->np * (size_t)p->n);
  if (o->rows0) memcpy(p->rows0, o->rows0, sizeof(double) * (size_t)p->np * (size_t)p->n);
  int st = plan_freqs(p, o, err);
  if (st) {
    rr_frf_plan_free(p);
    return st;
  }
  *out = p;
  return RR_OK;
}

int rr_frf_nfreq(const rr_frf_plan *p) { return p->nf; }
enum rr_frf_method rr_frf_route(const rr_frf_plan *p) { return p->route; }
int rr_frf_npoints(const rr_frf_plan *p) { return p->np; }
int rr_frf_ninputs(const rr_frf_plan *p) { return p->ni; }
const double *rr_frf_freqs(const rr_frf_plan *p) { return p->f; }
const double complex *rr_frf_H(const rr_frf_plan *p) { return p->H; }

static int execute_direct(rr_frf_plan *p, const rr_model *m)
{
  int n = p->n, ni = p->ni, np = p->np;
  for (int k = 0; k < p->nf; k++) {
    double w = 2 * RR_PI * p->f[k];
    rr_model_dynamic_stiffness(m, I * w, 0, p->D);
    double nrm = 0;
    for (int i = 0; i < n * n; i++) nrm += cabs(p->D[i]);
    rr_clu_factor(p->D, n, p->piv, 1e-300 + 1e-17 * nrm / n);
    for (int i = 0; i < ni; i++) {
      double complex *x = p->X + (size_t)i * (size_t)n;
      for (int r = 0; r < n; r++) x[r] = m->B[r * ni + i];
      rr_clu_solve(p->D, n, p->piv, x);
    }
    for (int q = 0; q < np; q++)
      for (int i = 0; i < ni; i++) {
        double complex acc = 0, acc0 = 0;
        const double complex *x = p->X + (size_t)i * (size_t)n;
        for (int r = 0; r < n; r++) {
          acc += p->rows[q * n + r] * x[r];
          acc0 += p->rows0[q * n + r] * x[r];
        }
        p->H[((size_t)k * (size_t)np + (size_t)q) * (size_t)ni + (size_t)i] = -w * w * acc + acc0;
      }
  }
  return RR_OK;
}

/* The elements handled by SMW: SDF elements without a state-space form
 * (paper mode; physical mode with a table). Merged mirror pairs count once. */
static int smw_elements(const rr_model *m, int *elem, double *mult)
{
  int sdf_ss = m->sdf_mode == RR_SDF_PHYSICAL && m->curve.kind != RR_CURVE_TABLE;
  if (m->sdf_mode == RR_SDF_NONE || sdf_ss) return 0;
  int all[2 * RR_SYS_MAX_BODIES], nu = 0;
  double mm[2 * RR_SYS_MAX_BODIES];
  int nk = rr_merged_elements(m, all, mm);
  for (int i = 0; i < nk; i++)
    if (m->mx[all[i]].sdf) {
      if (nu == MAXU) return -1;
      elem[nu] = all[i];
      mult[nu] = mm[i];
      nu++;
    }
  return nu;
}

/* Right projections of eigenvector x (state space) for term j: output rows,
   roll-gravity rows and the SMW elements' strokes. */
static void right_proj(rr_frf_plan *p, const rr_model *m, int j, int nu, const int *uel,
                       const double complex *x)
{
  int n = p->n, np = p->np;
  for (int q = 0; q < np; q++) {
    double complex a = 0, a0 = 0;
    for (int r = 0; r < n; r++) {
      a += p->rows[q * n + r] * x[r];
      a0 += p->rows0[q * n + r] * x[r];
    }
    p->o[j * np + q] = a;
    p->o0[j * np + q] = a0;
  }
  for (int e = 0; e < nu; e++) {
    const rr_mx *mx = &m->mx[uel[e]];
    double complex a = 0;
    for (int t = 0; t < mx->nz; t++) a += mx->J[mx->idx[t]] * x[mx->idx[t]];
    p->u[j * MAXU + e] = a;
  }
}

/* Column j of a LAPACK-layout eigenvector matrix as a complex vector. */
static void eigvec(const double *v, const double *wi, int N, int j, double complex *x)
{
  int pair = wi[j] != 0, c0 = pair && wi[j] < 0 ? j - 1 : j;
  double sg = pair && wi[j] < 0 ? -1.0 : 1.0;
  for (int r = 0; r < N; r++)
    x[r] = v[(size_t)c0 * (size_t)N + (size_t)r] +
           (pair ? sg * I * v[(size_t)(c0 + 1) * (size_t)N + (size_t)r] : 0);
}

/* Residues from LAPACK's eigenvectors of the state matrix in p->A (left and
   right): (sI - A)^-1 = sum_j x_j u_j^H / (u_j^H x_j (s - lambda_j)). */
static int residues_dgeev(rr_frf_plan *p, const rr_model *m, int N, int nu, const int *uel,
                          rr_error *err)
{
  int n = p->n, ni = p->ni;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) p->At[j * N + i] = p->A[i * N + j];
  int info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'V', 'V', N, p->At, N, p->wr, p->wi, p->vl, N,
                                p->vr, N, p->work, p->lwork);
  if (info) return rr_seterr(err, RR_ELAPACK, "dgeev failed (info %d)", info);
  double complex x[2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES],
      ul[2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES];
  for (int j = 0; j < N; j++) {
    eigvec(p->vr, p->wi, N, j, x);
    eigvec(p->vl, p->wi, N, j, ul);
    double complex s = 0;
    for (int r = 0; r < N; r++) s += conj(ul[r]) * x[r];
    if (cabs(s) == 0)
      return rr_seterr(err, RR_ELAPACK, "frf: defective state matrix (use the direct method)");
    double complex is = 1.0 / s;
    p->lam[j] = p->wr[j] + I * p->wi[j];
    right_proj(p, m, j, nu, uel, x);
    for (int i = 0; i < ni; i++) {
      double complex a = 0;
      for (int r = 0; r < n; r++) a += conj(ul[n + r]) * (m->B[r * ni + i] / m->mdiag[r]);
      p->b[j * ni + i] = a * is;
    }
    for (int e = 0; e < nu; e++) {
      const rr_mx *mx = &m->mx[uel[e]];
      double complex cc = 0;
      for (int t = 0; t < mx->nz; t++)
        cc += conj(ul[n + mx->idx[t]]) * (mx->J[mx->idx[t]] / m->mdiag[mx->idx[t]]);
      p->c[j * MAXU + e] = cc * is;
    }
  }
  return RR_OK;
}

/* Below this reciprocal condition number of the eigenvector basis the plan
   solves directly. Near zero conicity the rigid lateral drift becomes a
   defective double zero: with the default car the error of the expansion was
   6e-11 at rcond 1.2e-6 (conicity 1e-5), 3e-10 at 5e-7, 1e-8 at 1.5e-8, and
   dgeev's vectors did worse (1e-7 .. 2e-3), so the fallback is the direct
   route, not LAPACK's vectors. Ordinary operating points have 3e-5 .. 2e-4. */
#define RCOND_MIN 1e-6

/* Residues from rr_eigdec's right eigenvectors V and the inverse of that same
   basis: beta = V^-1 [B~ U~], B~ and U~ the inputs and the SMW elements in
   state space. Consistent by construction (sum_j x_j beta_j reproduces the
   inputs to rounding), so near-equal eigenvalues cost accuracy only through
   cond(V), which is checked. Returns 1 when the caller should solve directly. */
static int residues_fast(rr_frf_plan *p, const rr_model *m, int N, int nu, const int *uel)
{
  int n = p->n, ni = p->ni, nr = ni + nu;
  memcpy(p->At, p->A, sizeof(double) * (size_t)N * (size_t)N);
  if (rr_eigdec(N, p->At, p->wr, p->wi, p->vr, p->ework, p->iwork)) return 1;
  double *rhs = p->rhs;
  memset(rhs, 0, sizeof(double) * (size_t)N * (size_t)nr);
  for (int i = 0; i < ni; i++)
    for (int r = 0; r < n; r++)
      rhs[(size_t)(n + r) * (size_t)nr + (size_t)i] = m->B[r * ni + i] / m->mdiag[r];
  for (int e = 0; e < nu; e++) {
    const rr_mx *mx = &m->mx[uel[e]];
    for (int t = 0; t < mx->nz; t++)
      rhs[(size_t)(n + mx->idx[t]) * (size_t)nr + (size_t)(ni + e)] =
          mx->J[mx->idx[t]] / m->mdiag[mx->idx[t]];
  }
  memcpy(p->V, p->vr, sizeof(double) * (size_t)N * (size_t)N);
  double vnorm = rr_lu_norm1(N, p->V, N);
  if (rr_lu_factor(N, p->V, N, p->vpiv) ||
      !(rr_lu_rcond1(N, p->V, N, vnorm, rhs + (size_t)N * (size_t)nr, p->iwork) >= RCOND_MIN))
    return 1;
  rr_lu_solve_rows(N, p->V, N, p->vpiv, nr, rhs, nr);
  double complex x[2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES];
  for (int j = 0; j < N; j++) {
    if (p->wi[j] < 0) continue; /* a pair is stored once, by its Im > 0 member */
    int pair = p->wi[j] > 0;
    eigvec(p->vr, p->wi, N, j, x);
    p->lam[j] = p->wr[j] + I * p->wi[j];
    right_proj(p, m, j, nu, uel, x);
    /* real-basis coefficients (g_re, g_im) of the pair's columns are
       (2 Re beta, -2 Im beta) */
#define BETA(col)                                                                                  \
  (pair ? 0.5 * (rhs[(size_t)j * (size_t)nr + (size_t)(col)] -                                     \
                 I * rhs[(size_t)(j + 1) * (size_t)nr + (size_t)(col)])                            \
        : rhs[(size_t)j * (size_t)nr + (size_t)(col)])
    for (int i = 0; i < ni; i++) p->b[j * ni + i] = BETA(i);
    for (int e = 0; e < nu; e++) p->c[j * MAXU + e] = BETA(ni + e);
#undef BETA
  }
  return 0;
}

/* The SDF elements handled by SMW and where their blocks sit among the
   residue entries (execute_modal's layout). */
typedef struct smw_set {
  int nu, uel[MAXU];
  double umult[MAXU], k_lo;
  int oHq, oHu, oGq, oZ;
  /* the outputs' feedthrough rows M^-1 B and rows M^-1 U (np x ni, np x nu) */
  double dB[16 * 16], dU[16 * MAXU];
} smw_set;

/* M2 = (I + dK Z)^-1 diag(dK), nu x nu: the SMW correction is then
   O D^-1 B = O D0^-1 B - (O D0^-1 U) M2 (U^T D0^-1 B). One frequency, by LU
   (more than two dampers; smw_lanes has the closed forms for one and two). */
static void smw_matrix(const double complex *dK, const double complex *Z, int nu,
                       double complex *M2)
{
  double complex W[MAXU * MAXU];
  int piv[MAXU];
  for (int e = 0; e < nu; e++)
    for (int g = 0; g < nu; g++) W[e * nu + g] = (e == g) + dK[e] * Z[e * nu + g];
  rr_clu_factor(W, nu, piv, 1e-300);
  for (int g = 0; g < nu; g++) { /* column g of W^-1 diag(dK) */
    double complex col[MAXU];
    for (int e = 0; e < nu; e++) col[e] = e == g ? dK[g] : 0;
    rr_clu_solve(W, nu, piv, col);
    for (int e = 0; e < nu; e++) M2[e * nu + g] = col[e];
  }
}

/* The FRFs of FV frequencies at once (kk0 .. of the chunk starting at k0, its
   modal sums in acc, E a row; already the outputs' acceleration plus
   roll-gravity): the feedthrough, then the SMW correction for the nu SDF
   elements, in lanes across the frequencies (real and imaginary parts apart;
   the per-frequency complex algebra had been a tenth of the evaluation). */
#define FV 8 /* frequencies a step: one AVX-512 vector, two AVX2 */
_Static_assert(FCHUNK % FV == 0, "a chunk is whole steps of FV frequencies");

RR_INLINE void smw_lanes(const rr_model *m, const smw_set *u, const double *w, const double *kfr,
                         const double *kfi, const double *acc, int kk0, int nkp, int nu,
                         double (*m2r)[FV], double (*m2i)[FV])
{
  double dkr[MAXU][FV], dki[MAXU][FV], zr[MAXU * MAXU][FV], zi[MAXU * MAXU][FV];
  for (int e = 0; e < nu; e++) {
    /* dK = mult cs^2 (kf - k_lo) / ((kf + cs)(k_lo + cs)), cs = j c w */
    double c = m->mx[u->uel[e]].c, um = u->umult[e], klo = u->k_lo;
#pragma omp simd
    for (int l = 0; l < FV; l++) {
      double a = c * w[l], nr = -um * a * a * (kfr[l] - klo), nim = -um * a * a * kfi[l];
      double dr = kfr[l] * klo - (kfi[l] + a) * a, di = kfr[l] * a + (kfi[l] + a) * klo;
      double inv = 1 / (dr * dr + di * di);
      dkr[e][l] = (nr * dr + nim * di) * inv;
      dki[e][l] = (nim * dr - nr * di) * inv;
    }
  }
  for (int e = 0; e < nu * nu; e++) {
    const double *z = acc + (size_t)(u->oZ + e) * (size_t)(2 * nkp) + (size_t)kk0;
    for (int l = 0; l < FV; l++) {
      zr[e][l] = z[l];
      zi[e][l] = z[nkp + l];
    }
  }
  if (nu > 2) { /* the general M2, one frequency at a time */
    for (int l = 0; l < FV; l++) {
      double complex dK[MAXU], Z[MAXU * MAXU], M2[MAXU * MAXU];
      for (int e = 0; e < nu; e++) dK[e] = dkr[e][l] + I * dki[e][l];
      for (int e = 0; e < nu * nu; e++) Z[e] = zr[e][l] + I * zi[e][l];
      smw_matrix(dK, Z, nu, M2);
      for (int e = 0; e < nu * nu; e++) {
        m2r[e][l] = creal(M2[e]);
        m2i[e][l] = cimag(M2[e]);
      }
    }
    return;
  }
#pragma omp simd
  for (int l = 0; l < FV; l++) {
    if (nu == 1) { /* M2 = dK / (1 + dK Z) */
      double br = 1 + dkr[0][l] * zr[0][l] - dki[0][l] * zi[0][l],
             bi = dkr[0][l] * zi[0][l] + dki[0][l] * zr[0][l], inv = 1 / (br * br + bi * bi);
      m2r[0][l] = (dkr[0][l] * br + dki[0][l] * bi) * inv;
      m2i[0][l] = (dki[0][l] * br - dkr[0][l] * bi) * inv;
    } else { /* W = I + diag(dK) Z; M2 = W^-1 diag(dK) by the 2 x 2 inverse */
      double w0r = 1 + dkr[0][l] * zr[0][l] - dki[0][l] * zi[0][l],
             w0i = dkr[0][l] * zi[0][l] + dki[0][l] * zr[0][l];
      double w1r = dkr[0][l] * zr[1][l] - dki[0][l] * zi[1][l],
             w1i = dkr[0][l] * zi[1][l] + dki[0][l] * zr[1][l];
      double w2r = dkr[1][l] * zr[2][l] - dki[1][l] * zi[2][l],
             w2i = dkr[1][l] * zi[2][l] + dki[1][l] * zr[2][l];
      double w3r = 1 + dkr[1][l] * zr[3][l] - dki[1][l] * zi[3][l],
             w3i = dkr[1][l] * zi[3][l] + dki[1][l] * zr[3][l];
      double detr = w0r * w3r - w0i * w3i - (w1r * w2r - w1i * w2i),
             deti = w0r * w3i + w0i * w3r - (w1r * w2i + w1i * w2r);
      double inv = 1 / (detr * detr + deti * deti), idr = detr * inv, idi = -deti * inv;
      /* M2 = [w3 dK0, -w1 dK1; -w2 dK0, w0 dK1] / det */
      double ar[4] = {w3r, -w1r, -w2r, w0r}, ai[4] = {w3i, -w1i, -w2i, w0i};
      for (int e = 0; e < 4; e++) {
        double kr = dkr[e & 1][l], ki = dki[e & 1][l];
        double tr = ar[e] * idr - ai[e] * idi, ti = ar[e] * idi + ai[e] * idr;
        m2r[e][l] = tr * kr - ti * ki;
        m2i[e][l] = tr * ki + ti * kr;
      }
    }
  }
}

RR_INLINE void finish_lanes(rr_frf_plan *p, const rr_model *m, const smw_set *u, int k0, int nk,
                            int kk0, const double *acc, int nkp, int nu)
{
  int ni = p->ni, np = p->np, nH = np * ni, nv = nk - kk0 < FV ? nk - kk0 : FV;
  /* entry e's real parts at RE(e)[0 .. FV), its imaginary parts at IM(e) */
#define RE(e) (acc + (size_t)(e) * (size_t)(2 * nkp) + (size_t)kk0)
#define IM(e) (RE(e) + nkp)
  double w[FV], kfr[FV], kfi[FV], m2r[MAXU * MAXU][FV], m2i[MAXU * MAXU][FV];
  for (int l = 0; l < FV; l++) { /* a short last step repeats its last frequency */
    int kk = kk0 + (l < nv ? l : nv - 1);
    w[l] = 2 * RR_PI * p->f[k0 + kk];
    double complex kf = nu ? rr_model_series_k(m, u->uel[0], I * w[l], 0) : 0;
    kfr[l] = creal(kf);
    kfi[l] = cimag(kf);
  }
  if (nu) smw_lanes(m, u, w, kfr, kfi, acc, kk0, nkp, nu, m2r, m2i);
  for (int q = 0; q < np; q++) {
    double gr[MAXU][FV], gi[MAXU][FV]; /* g_e = sum_h (G(q, h) + dU(q, h)) M2(h, e) */
    for (int e = 0; e < nu; e++)
      for (int l = 0; l < FV; l++) {
        double sr = 0, si = 0;
        for (int h = 0; h < nu; h++) {
          double xr = RE(u->oGq + q * nu + h)[l] + u->dU[q * nu + h],
                 xi = IM(u->oGq + q * nu + h)[l];
          sr += xr * m2r[h * nu + e][l] - xi * m2i[h * nu + e][l];
          si += xr * m2i[h * nu + e][l] + xi * m2r[h * nu + e][l];
        }
        gr[e][l] = sr;
        gi[e][l] = si;
      }
    for (int i = 0; i < ni; i++) {
      double hr[FV], hi[FV];
      for (int l = 0; l < FV; l++) {
        hr[l] = RE(u->oHq + q * ni + i)[l] + u->dB[q * ni + i];
        hi[l] = IM(u->oHq + q * ni + i)[l];
        for (int e = 0; e < nu; e++) {
          double ur = RE(u->oHu + e * ni + i)[l], ui = IM(u->oHu + e * ni + i)[l];
          hr[l] -= gr[e][l] * ur - gi[e][l] * ui;
          hi[l] -= gr[e][l] * ui + gi[e][l] * ur;
        }
      }
      double complex *out = p->H + (size_t)(k0 + kk0) * (size_t)nH + q * ni + i;
      for (int l = 0; l < nv; l++) out[(size_t)l * (size_t)nH] = hr[l] + I * hi[l];
    }
  }
#undef RE
#undef IM
}

/* A chunk's FRFs from its modal sums (acc: E rows of 2 nkp, an entry's real
   parts over the chunk's frequencies, then its imaginary parts), the usual
   0, 1 and 2 dampers with nu a constant, so that the small loops unroll. */
RR_CLONES_V4 static void finish_chunk(rr_frf_plan *p, const rr_model *m, const smw_set *u, int k0,
                                      int nk, int nkp, const double *acc)
{
  for (int kk = 0; kk < nk; kk += FV) {
    switch (u->nu) {
    case 0: finish_lanes(p, m, u, k0, nk, kk, acc, nkp, 0); break;
    case 1: finish_lanes(p, m, u, k0, nk, kk, acc, nkp, 1); break;
    case 2: finish_lanes(p, m, u, k0, nk, kk, acc, nkp, 2); break;
    default: finish_lanes(p, m, u, k0, nk, kk, acc, nkp, u->nu);
    }
  }
}

/* The feedthrough of the acceleration outputs: rows M^-1 B (inputs) and
   rows M^-1 U (SMW elements), the forces' direct effect on the points. */
static void feedthrough(const rr_frf_plan *p, const rr_model *m, smw_set *u)
{
  int n = p->n, ni = p->ni, np = p->np;
  for (int q = 0; q < np; q++) {
    for (int i = 0; i < ni; i++) {
      double a = 0;
      for (int r = 0; r < n; r++) a += p->rows[q * n + r] * m->B[r * ni + i] / m->mdiag[r];
      u->dB[q * ni + i] = a;
    }
    for (int e = 0; e < u->nu; e++) {
      const rr_mx *mx = &m->mx[u->uel[e]];
      double a = 0;
      for (int t = 0; t < mx->nz; t++)
        a += p->rows[q * n + mx->idx[t]] * mx->J[mx->idx[t]] / m->mdiag[mx->idx[t]];
      u->dU[q * u->nu + e] = a;
    }
  }
}

/* A chunk's weights (nk frequencies, w angular, padded with zeros to nkp)
   of the terms with eigenvalues la + j lb, the pairs first, then the real
   modes: term t's row of W (2 nkp long) holds its real parts over the
   frequencies, then its imaginary parts; a pair's second row (nt + t) the
   weights of its imaginary residue. Across the frequencies, one vector of
   them at a time. */
RR_CLONES_V4 static void modal_weights(const double *la, const double *lb, int npair, int nt,
                                       const double *w, int nk, int nkp, double *W)
{
  size_t ld = (size_t)(2 * nkp);
  for (int t = 0; t < npair; t++) {
    /* (s - l)(s - conj l) at s = jw: (b - w)(b + w) + a^2 - 2 j a w;
       d1 + d2 = 2 (jw - a) / den, j (d1 - d2) = -2 b / den */
    double a = la[t], b = lb[t], *r1 = W + (size_t)t * ld, *r2 = W + (size_t)(nt + t) * ld;
#pragma omp simd
    for (int k = 0; k < nk; k++) {
      double dr = (b - w[k]) * (b + w[k]) + a * a, di = -2 * a * w[k],
             inv = 2 / (dr * dr + di * di);
      double rr = dr * inv, ri = -di * inv;
      r1[k] = -a * rr - w[k] * ri;
      r1[nkp + k] = w[k] * rr - a * ri;
      r2[k] = -b * rr;
      r2[nkp + k] = -b * ri;
    }
  }
  for (int t = npair; t < nt; t++) { /* d1 = 1 / (jw - a), R real */
    double a = la[t], *r1 = W + (size_t)t * ld;
#pragma omp simd
    for (int k = 0; k < nk; k++) {
      double inv = 1 / (a * a + w[k] * w[k]);
      r1[k] = -a * inv;
      r1[nkp + k] = -w[k] * inv;
    }
  }
  for (int t = 0; t < nt + npair; t++)
    for (int k = nk; k < nkp; k++)
      W[(size_t)t * ld + (size_t)k] = W[(size_t)t * ld + (size_t)(nkp + k)] = 0;
}

/* The state matrix with the SMW elements held at the reference stiffness
   k_lo (the state-space part of the expansion), into p->A. */
static int modal_state_matrix(rr_frf_plan *p, const rr_model *m, int nu, double k_lo, int *N,
                              rr_error *err)
{
  /* with SMW elements, their state-space part is the paper mode's at k_lo */
  rr_sdf_mode mode = nu ? RR_SDF_PAPER : (rr_sdf_mode)m->sdf_mode;
  int st = rr_state_matrix_merged_as(m, mode, k_lo, p->A, N, err);
  if (!st && *N > p->Nmax) st = rr_seterr(err, RR_EINVAL, "frf plan too small for this model");
  return st;
}

/* Residue entries per term: Hq (np x ni), Hu (nu x ni), Gq (np x nu), Z (nu
   x nu), each the product of a left and a right projection. The outputs are
   accelerations (plus roll-gravity): s^2 O (sI - A)^-1 B~ = O A^2 (sI -
   A)^-1 B~ + O A B~ (O B~ = 0: the inputs act on velocities), so the output
   projection of term j is lambda_j^2 o_j + o0_j and the feedthrough O A B~ =
   rows M^-1 B is added once (feedthrough()). A conjugate pair contributes R
   d1 + conj(R) d2 = Re(R) (d1 + d2) + Im(R) j (d1 - d2), so it is stored once
   (the eigenvalue with Im > 0) and costs real-times-complex products. A
   chunk's sums are then one real matrix product: entries (E x K: columns Re R
   of each term, then the pairs' Im R) times weights (K x 2 nkp: rows d1 + d2
   of each term, then j (d1 - d2) of each pair; the real parts over the
   frequencies, then the imaginary parts). Pairs come first, then real modes
   (branch-free weight loops); a real mode's residues are real, so its Im
   column is left out of the product. The terms' eigenvalues go to (la, lb);
   returns E and sets *nt, *npair. */
static int residue_table(rr_frf_plan *p, smw_set *u, int N, int *nt, int *npair, double *la,
                         double *lb)
{
  int ni = p->ni, np = p->np, nu = u->nu;
  u->oHq = 0;
  u->oHu = np * ni;
  u->oGq = u->oHu + nu * ni;
  u->oZ = u->oGq + np * nu;
  int E = u->oZ + nu * nu;
  *nt = *npair = 0;
  for (int j = 0; j < N; j++) {
    *nt += p->wi[j] >= 0;
    *npair += p->wi[j] > 0;
  }
  int K = *nt + *npair;
  for (int j = 0, tp = 0, tq = *npair; j < N; j++) {
    if (p->wi[j] < 0) continue; /* the conjugate of a stored pair */
    int t = p->wi[j] > 0 ? tp++ : tq++;
    /* column t of T (E x K), and a pair's imaginary residues in column nt + t */
    double *tr = p->T + t, *ti = p->wi[j] > 0 ? p->T + *nt + t : NULL;
    const double complex *o = p->o + j * np, *o0 = p->o0 + j * np, *bb = p->b + j * ni,
                         *uu = p->u + j * MAXU, *cc = p->c + j * MAXU, l2 = p->lam[j] * p->lam[j];
#define PUT(off, val)                                                                              \
  do {                                                                                             \
    double complex v_ = (val);                                                                     \
    tr[(size_t)(off) * (size_t)K] = creal(v_);                                                     \
    if (ti) ti[(size_t)(off) * (size_t)K] = cimag(v_);                                             \
  } while (0)
    for (int q = 0; q < np; q++) {
      double complex oa = l2 * o[q] + o0[q];
      for (int i = 0; i < ni; i++) PUT(u->oHq + q * ni + i, oa * bb[i]);
      for (int e = 0; e < nu; e++) PUT(u->oGq + q * nu + e, oa * cc[e]);
    }
    for (int e = 0; e < nu; e++) {
      for (int i = 0; i < ni; i++) PUT(u->oHu + e * ni + i, uu[e] * bb[i]);
      for (int g = 0; g < nu; g++) PUT(u->oZ + e * nu + g, uu[e] * cc[g]);
    }
#undef PUT
    la[t] = creal(p->lam[j]);
    lb[t] = cimag(p->lam[j]);
  }
  return E;
}

static int execute_modal(rr_frf_plan *p, const rr_model *m, rr_error *err)
{
  smw_set su = {.nu = 0};
  int nu = su.nu = smw_elements(m, su.uel, su.umult);
  if (nu < 0)
    return rr_seterr(err, RR_EINVAL, "frf: more than %d SDF dampers (use the direct method)", MAXU);
  double k_hi = 0;
  if (nu) rr_sdf_range(&m->curve, &su.k_lo, &k_hi);
  int N, st = modal_state_matrix(p, m, nu, su.k_lo, &N, err);
  if (st) return st;
  if (p->use_dgeev) {
    if ((st = residues_dgeev(p, m, N, nu, su.uel, err))) return st;
  } else if (residues_fast(p, m, N, nu, su.uel)) {
    p->route = RR_FRF_DIRECT;
    return execute_direct(p, m);
  }
  feedthrough(p, m, &su);
  int nt, npair;
  double la[2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES],
      lb[2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES];
  int E = residue_table(p, &su, N, &nt, &npair, la, lb), K = nt + npair;
  double w[FCHUNK];
  for (int k0 = 0; k0 < p->nf; k0 += FCHUNK) {
    int nk = p->nf - k0 < FCHUNK ? p->nf - k0 : FCHUNK, nkp = (nk + FV - 1) / FV * FV;
    for (int kk = 0; kk < nk; kk++) w[kk] = 2 * RR_PI * p->f[k0 + kk];
    modal_weights(la, lb, npair, nt, w, nk, nkp, p->Wt);
    /* sums (E x 2 nkp) = T (E x K) W (K x 2 nkp) */
    rr_gemm_nn(E, 2 * nkp, K, p->T, K, p->Wt, 2 * nkp, p->acc, 2 * nkp);
    finish_chunk(p, m, &su, k0, nk, nkp, p->acc);
  }
  return RR_OK;
}

static int lags_current(const rr_frf_plan *p, const rr_model *m)
{
  int same = p->lag_speed == m->speed;
  for (int i = 0; i < p->ni; i++) same &= p->lag_x[i] == m->contacts[i].x;
  return same;
}

/* The PEM's exp(j w x_i / v), kept while the speed and the wheelset positions
   stay (the sines and cosines were a tenth of a ride evaluation). */
static void update_lags(rr_frf_plan *p, const rr_model *m)
{
  if (lags_current(p, m)) return;
  for (int k = 0; k < p->nf; k++) {
    double w = 2 * RR_PI * p->f[k];
    for (int i = 0; i < p->ni; i++)
      p->lag[(size_t)k * (size_t)p->ni + (size_t)i] = cexp(I * w * m->contacts[i].x / m->speed);
  }
  p->lag_speed = m->speed;
  for (int i = 0; i < p->ni; i++) p->lag_x[i] = m->contacts[i].x;
}

/* The model fits the plan; the lags current. */
static int execute_begin(rr_frf_plan *p, const rr_model *m, rr_error *err)
{
  if (m->n != p->n || m->ni != p->ni)
    return rr_seterr(err, RR_EINVAL, "frf: plan was made for another model size");
  if (p->np > 16 || p->ni > 16)
    return rr_seterr(err, RR_EINVAL, "frf: at most 16 points and 16 inputs");
  if (m->ni > RR_SYS_MAX_INPUTS) return rr_seterr(err, RR_EINVAL, "frf: too many inputs");
  update_lags(p, m);
  p->route = p->use_dgeev ? RR_FRF_MODAL_LAPACK : p->method;
  return RR_OK;
}

/* RR_OK when every response in H (nf x per complex) is finite. */
static int responses_finite(const rr_frf_plan *p, const double complex *H, size_t per,
                            rr_error *err)
{
  size_t nH = (size_t)p->nf * per;
  if (rr_all_finite(2 * nH, (const double *)H)) return RR_OK;
  size_t t = 0;
  while (isfinite(creal(H[t])) && isfinite(cimag(H[t]))) t++;
  return rr_seterr(err, RR_ENOCONV,
                   "frf: response not finite at %g Hz (singular dynamic stiffness)", p->f[t / per]);
}

int rr_frf_plan_execute(rr_frf_plan *p, const rr_model *m, rr_error *err)
{
  int st = execute_begin(p, m, err);
  if (st) return st;
  if (p->method == RR_FRF_DIRECT)
    st = execute_direct(p, m);
  else if (p->method == RR_FRF_SPARSE)
    rr_frf_sparse_execute(&p->sparse, m, p->f, p->nf, p->rows, p->rows0, NULL, p->H);
  else
    st = execute_modal(p, m, err);
  return st ? st : responses_finite(p, p->H, (size_t)p->np * (size_t)p->ni, err);
}

double complex rr_pem_lagged_sum(const double complex *H, const double *x, int ni, double w,
                                 double v)
{
  double complex a = 0;
  for (int i = 0; i < ni; i++) a += H[i] * cexp(I * w * x[i] / v);
  return a;
}

double rr_pem_combine(const double complex *H, const double *x, int ni, double w, double v,
                      double Gt)
{
  double complex a = rr_pem_lagged_sum(H, x, ni, w, v);
  return Gt * creal(a * conj(a));
}

/* G_t(f) = G_s(f/v)/v, refused unless finite and >= 0 over the whole band
   the ride uses (not only the spectrum's valid range) */
static int track_at(const rr_spectrum *sp, double f, double v, double *gt, rr_error *err)
{
  double Gt = rr_spectrum_eval(sp, f / v) / v; /* temporal one-sided PSD, m^2/Hz */
  if (!(Gt >= 0 && isfinite(Gt)))
    return rr_seterr(err, RR_EINVAL,
                     "%s: the PSD is %s at n = %g 1/m (%g Hz at %g km/h; its valid range is "
                     "%g .. %g 1/m)",
                     sp->path[0] ? sp->path : sp->name, isfinite(Gt) ? "negative" : "not finite",
                     f / v, f, v * RR_KMH, sp->valid_lo, sp->valid_hi);
  *gt = Gt;
  return RR_OK;
}

/* The PEM's G = G_t |a|^2 at frequency k, point q (a: the response to the
   lagged inputs), refused unless finite. */
static int psd_put(const rr_frf_plan *p, int k, int q, double Gt, double complex a, double *G,
                   rr_error *err)
{
  G[k * p->np + q] = Gt * (creal(a) * creal(a) + cimag(a) * cimag(a));
  if (!isfinite(G[k * p->np + q]))
    return rr_seterr(err, RR_ENOCONV, "pem: PSD not finite at %g Hz", p->f[k]);
  return RR_OK;
}

/* Frequency k's row of G from the FRFs and the track's G_t there. */
static int psd_row(const rr_frf_plan *p, const rr_model *m, int k, int cached, double Gt, double *G,
                   rr_error *err)
{
  double v = m->speed, f = p->f[k], w = 2 * RR_PI * f;
  double complex lagk[RR_SYS_MAX_INPUTS];
  const double complex *lag = lagk;
  if (cached)
    lag = p->lag + (size_t)k * (size_t)p->ni;
  else
    for (int i = 0; i < p->ni; i++) lagk[i] = cexp(I * w * m->contacts[i].x / v);
  for (int q = 0; q < p->np; q++) {
    const double complex *h = p->H + ((size_t)k * (size_t)p->np + (size_t)q) * (size_t)p->ni;
    double complex a = 0;
    for (int i = 0; i < p->ni; i++) a += h[i] * lag[i];
    int st = psd_put(p, k, q, Gt, a, G, err);
    if (st) return st;
  }
  return RR_OK;
}

int rr_pem_psd(const rr_frf_plan *p, const rr_model *m, const rr_spectrum *sp, double *G,
               rr_error *err)
{
  int cached = lags_current(p, m), st = RR_OK;
  for (int k = 0; k < p->nf && !st; k++) {
    double Gt = 0;
    st = track_at(sp, p->f[k], m->speed, &Gt, err);
    if (!st) st = psd_row(p, m, k, cached, Gt, G, err);
  }
  return st;
}

int rr_pem_track(const rr_frf_plan *p, const rr_spectrum *sp, double v_ms, double *Gt,
                 rr_error *err)
{
  if (!(v_ms > 0 && v_ms <= RR_SPEED_MAX_MS))
    return rr_seterr(err, RR_EINVAL, "pem: speed %g km/h outside (0, %g] km/h", v_ms * RR_KMH,
                     RR_SPEED_MAX_MS * RR_KMH);
  int st = RR_OK;
  for (int k = 0; k < p->nf && !st; k++) st = track_at(sp, p->f[k], v_ms, Gt + k, err);
  return st;
}

int rr_pem_psd_track(const rr_frf_plan *p, const rr_model *m, const double *Gt, double *G,
                     rr_error *err)
{
  int cached = lags_current(p, m), st = RR_OK;
  for (int k = 0; k < p->nf && !st; k++) st = psd_row(p, m, k, cached, Gt[k], G, err);
  return st;
}

int rr_pem_design(rr_frf_plan *p, const rr_model *m, const double *Gt, double *G, rr_error *err)
{
  if (p->method != RR_FRF_SPARSE) { /* the routes that give every input's response */
    int st = rr_frf_plan_execute(p, m, err);
    return st ? st : rr_pem_psd_track(p, m, Gt, G, err);
  }
  int st = execute_begin(p, m, err);
  if (st) return st;
  rr_frf_sparse_execute(&p->sparse, m, p->f, p->nf, p->rows, p->rows0, p->lag, p->Hs);
  if ((st = responses_finite(p, p->Hs, (size_t)p->np, err))) return st;
  for (int k = 0; k < p->nf && !st; k++)
    for (int q = 0; q < p->np && !st; q++)
      st = psd_put(p, k, q, Gt[k], p->Hs[k * p->np + q], G, err);
  return st;
}

int rr_vehicle_floor_rows(const rr_model *m, const rr_vehicle *veh, const double *x, int np,
                          double h_p, int roll_gravity, double *rows, double *rows0, rr_error *err)
{
  for (int q = 0; q < np; q++) {
    double pt[3] = {x[q], 0, h_p};
    int st = rr_model_point_row(m, "c", pt, RR_DIR_Y, rows + (size_t)q * (size_t)m->n, err);
    if (st) return st;
    if (rows0) {
      double *r0 = rows0 + (size_t)q * (size_t)m->n;
      for (int i = 0; i < m->n; i++) r0[i] = 0;
      if (roll_gravity) {
        for (int b = 0; b < m->nbodies; b++)
          if (!strcmp(m->bodies[b].name, "c") && m->bodies[b].dof_phi >= 0)
            r0[m->bodies[b].dof_phi] = RR_G;
      }
    }
  }
  (void)veh;
  return RR_OK;
}
