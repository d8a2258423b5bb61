/* First-order state space z = [q; dq/dt; u] (MODEL.md section 5). Each
 * Maxwell element adds its damper stroke u; in physical SDF mode each SDF
 * element also adds its inner dashpot stroke, after all the strokes. */
#include <math.h>
#include <string.h>
#include "model_impl.h"
#include "internal.h"

int rr_model_state_size(const rr_model *m)
{
  return 2 * m->n + m->nmx + (m->sdf_mode == RR_SDF_PHYSICAL ? m->nsdf : 0);
}

int rr_model_state_matrix(const rr_model *m, double sdf_k, double *A, rr_error *err)
{
  int n = m->n, N = rr_model_state_size(m);
  int phys = m->sdf_mode == RR_SDF_PHYSICAL;
  memset(A, 0, sizeof(double) * (size_t)N * (size_t)N);
  for (int i = 0; i < n; i++) {
    A[i * N + n + i] = 1.0;
    double im = 1.0 / m->mdiag[i];
    for (int j = 0; j < n; j++) {
      A[(n + i) * N + j] = -m->K[i * n + j] * im;
      A[(n + i) * N + n + j] = -m->C[i * n + j] * im;
    }
  }
  double k_lo = 0, k_hi = 0;
  if (m->sdf_mode == RR_SDF_PAPER) rr_sdf_range(&m->curve, &k_lo, &k_hi);
  if (phys && m->curve.kind == RR_CURVE_TABLE)
    return rr_seterr(err, RR_EUNSUP, "a tabulated SDF curve has no state-space form: use paper mode for modal analysis");
  int inner = 2 * n + m->nmx;   /* next inner-dashpot state */
  for (int e = 0; e < m->nmx; e++) {
    const rr_mx *x = &m->mx[e];
    int u = 2 * n + e;
    int sdf = x->sdf && m->sdf_mode != RR_SDF_NONE;
    if (sdf && phys) {
      /* c_sx in series with K3 || (K2 in series with c_z = K2 tau):
         f = (K3+K2)(Jq - u1) - K2 u2, u1' = f / c_sx, u2' = (Jq - u1 - u2) / tau. */
      double K3 = m->curve.k3, K2 = m->curve.k2, tau = 1.0 / (2 * RR_PI * m->curve.k1_hz);
      double ks = K3 + K2;
      int u2 = inner++;
      for (int a = 0; a < x->nz; a++) {
        int i = x->idx[a];
        double im = 1.0 / m->mdiag[i];
        for (int b = 0; b < x->nz; b++) A[(n + i) * N + x->idx[b]] -= ks * x->J[i] * x->J[x->idx[b]] * im;
        A[(n + i) * N + u] += ks * x->J[i] * im;
        A[(n + i) * N + u2] += K2 * x->J[i] * im;
        A[u * N + i] = ks * x->J[i] / x->c;
        A[u2 * N + i] = x->J[i] / tau;
      }
      A[u * N + u] = -ks / x->c;
      A[u * N + u2] = -K2 / x->c;
      A[u2 * N + u] = -1.0 / tau;
      A[u2 * N + u2] = -1.0 / tau;
      continue;
    }
    double k = x->k;
    if (sdf) k = sdf_k > 0 ? sdf_k : k_lo;   /* paper mode: constant k per solve */
    for (int a = 0; a < x->nz; a++) {
      int i = x->idx[a];
      double im = 1.0 / m->mdiag[i];
      for (int b = 0; b < x->nz; b++) A[(n + i) * N + x->idx[b]] -= k * x->J[i] * x->J[x->idx[b]] * im;
      A[(n + i) * N + u] += k * x->J[i] * im;
      A[u * N + i] = k * x->J[i] / x->c;
    }
    A[u * N + u] = -k / x->c;
  }
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
