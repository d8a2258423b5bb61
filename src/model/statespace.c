/* First-order state space z = [q; dq/dt; u] (docs/model.md section 5). Each
 * Maxwell element adds its damper stroke u; in physical SDF mode each SDF
 * element also adds its inner dashpot stroke, after all the strokes. */
#include <math.h>
#include <string.h>
#include "model/model_impl.h"
#include "util/internal.h"

int rr_model_state_size(const rr_model *m)
{
  return 2 * m->n + m->nmx + (m->sdf_mode == RR_SDF_PHYSICAL ? m->nsdf : 0);
}

/* Fills the q rows shared by every route: [0 I; -M^-1 K, -M^-1 C]. */
static void fill_mechanical(const rr_model *m, double *A, int N)
{
  int n = m->n;
  memset(A, 0, sizeof(double) * (size_t)N * (size_t)N);
  for (int i = 0; i < n; i++) {
    A[i * N + n + i] = 1.0;
    double im = 1.0 / m->mdiag[i];
    for (int j = 0; j < n; j++) {
      A[(n + i) * N + j] = -m->K[i * n + j] * im;
      A[(n + i) * N + n + j] = -m->C[i * n + j] * im;
    }
  }
}

/* Adds Maxwell element x, scaled by mult, with stroke state u (and inner
 * dashpot state u2 in physical SDF mode, else -1). */
static void fill_maxwell(const rr_model *m, rr_sdf_mode mode, const rr_mx *x, double mult,
                         double sdf_k, int u, int u2, double *A, int N)
{
  int n = m->n;
  int sdf = x->sdf && mode != RR_SDF_NONE;
  double c = mult * x->c;
  if (sdf && u2 >= 0) {
    /* c_sx in series with K3 || (K2 in series with c_z = K2 tau):
       f = (K3+K2)(Jq - u1) - K2 u2, u1' = f / c_sx, u2' = (Jq - u1 - u2) / tau. */
    double K3 = mult * m->curve.k3, K2 = mult * m->curve.k2,
           tau = 1.0 / (2 * RR_PI * m->curve.k1_hz);
    double ks = K3 + K2;
    for (int a = 0; a < x->nz; a++) {
      int i = x->idx[a];
      double im = 1.0 / m->mdiag[i];
      for (int b = 0; b < x->nz; b++)
        A[(n + i) * N + x->idx[b]] -= ks * x->J[i] * x->J[x->idx[b]] * im;
      A[(n + i) * N + u] += ks * x->J[i] * im;
      A[(n + i) * N + u2] += K2 * x->J[i] * im;
      A[u * N + i] = ks * x->J[i] / c;
      A[u2 * N + i] = x->J[i] / tau;
    }
    A[u * N + u] = -ks / c;
    A[u * N + u2] = -K2 / c;
    A[u2 * N + u] = -1.0 / tau;
    A[u2 * N + u2] = -1.0 / tau;
    return;
  }
  double k = x->k;
  if (sdf) { /* paper mode: constant k per solve, the curve's minimum unless given */
    double k_lo, k_hi;
    rr_sdf_range(&m->curve, &k_lo, &k_hi);
    k = sdf_k > 0 ? sdf_k : k_lo;
  }
  k *= mult;
  for (int a = 0; a < x->nz; a++) {
    int i = x->idx[a];
    double im = 1.0 / m->mdiag[i];
    for (int b = 0; b < x->nz; b++)
      A[(n + i) * N + x->idx[b]] -= k * x->J[i] * x->J[x->idx[b]] * im;
    A[(n + i) * N + u] += k * x->J[i] * im;
    A[u * N + i] = k * x->J[i] / c;
  }
  A[u * N + u] = -k / c;
}

int rr_model_state_matrix(const rr_model *m, double sdf_k, double *A, rr_error *err)
{
  int n = m->n, N = rr_model_state_size(m);
  int phys = m->sdf_mode == RR_SDF_PHYSICAL;
  if (phys && m->curve.kind == RR_CURVE_TABLE)
    return rr_seterr(
        err, RR_EUNSUP,
        "a tabulated SDF curve has no state-space form: use paper mode for modal analysis");
  fill_mechanical(m, A, N);
  int inner = 2 * n + m->nmx; /* inner-dashpot states follow all the strokes */
  for (int e = 0; e < m->nmx; e++) {
    const rr_mx *x = &m->mx[e];
    int u2 = phys && x->sdf ? inner++ : -1;
    fill_maxwell(m, m->sdf_mode, x, 1.0, sdf_k, 2 * n + e, u2, A, N);
  }
  return RR_OK;
}

/* J rows equal up to sign. */
static int mirror(const rr_mx *a, const rr_mx *b, int n)
{
  if (a->k != b->k || a->c != b->c || a->sdf != b->sdf || a->nz != b->nz) return 0;
  int same = 1, opp = 1;
  for (int i = 0; i < n; i++) {
    double tol = 1e-12 * (fabs(a->J[i]) + fabs(b->J[i]));
    if (fabs(a->J[i] - b->J[i]) > tol) same = 0;
    if (fabs(a->J[i] + b->J[i]) > tol) opp = 0;
  }
  return same || opp;
}

int rr_merged_elements(const rr_model *m, int *elem, double *mult)
{
  int partner[2 * RR_SYS_MAX_BODIES], nkeep = 0;
  for (int e = 0; e < m->nmx; e++) partner[e] = -2;
  for (int e = 0; e < m->nmx; e++) {
    if (partner[e] != -2) continue;
    partner[e] = -1;
    for (int f = e + 1; f < m->nmx; f++)
      if (partner[f] == -2 && mirror(&m->mx[e], &m->mx[f], m->n)) {
        partner[e] = f;
        partner[f] = e;
        break;
      }
    elem[nkeep] = e;
    mult[nkeep] = partner[e] >= 0 ? 2.0 : 1.0;
    nkeep++;
  }
  return nkeep;
}

int rr_state_matrix_merged(const rr_model *m, double sdf_k, double *A, int *Nout, rr_error *err)
{
  return rr_state_matrix_merged_as(m, m->sdf_mode, sdf_k, A, Nout, err);
}

int rr_state_matrix_merged_as(const rr_model *m, rr_sdf_mode mode, double sdf_k, double *A,
                              int *Nout, rr_error *err)
{
  int n = m->n, phys = mode == RR_SDF_PHYSICAL;
  if (phys && m->curve.kind == RR_CURVE_TABLE)
    return rr_seterr(
        err, RR_EUNSUP,
        "a tabulated SDF curve has no state-space form: use paper mode for modal analysis");
  int elem[2 * RR_SYS_MAX_BODIES];
  double mult[2 * RR_SYS_MAX_BODIES];
  int nkeep = rr_merged_elements(m, elem, mult), ninner = 0;
  for (int i = 0; i < nkeep; i++) ninner += phys && m->mx[elem[i]].sdf;
  int N = 2 * n + nkeep + ninner;
  fill_mechanical(m, A, N);
  int inner = 2 * n + nkeep;
  for (int i = 0; i < nkeep; i++) {
    const rr_mx *x = &m->mx[elem[i]];
    fill_maxwell(m, mode, x, mult[i], sdf_k, 2 * n + i, phys && x->sdf ? inner++ : -1, A, N);
  }
  *Nout = N;
  return RR_OK;
}

int rr_model_state_input(const rr_model *m, double *Bs, rr_error *err)
{
  int n = m->n, ni = m->ni, N = rr_model_state_size(m);
  memset(Bs, 0, sizeof(double) * (size_t)N * (size_t)ni);
  for (int i = 0; i < n; i++)
    for (int j = 0; j < ni; j++) Bs[(n + i) * ni + j] = m->B[i * ni + j] / m->mdiag[i];
  return RR_OK;
}
