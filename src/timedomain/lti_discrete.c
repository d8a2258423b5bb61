/* Exact discretisation with a cubic Hermite input hold, and the periodic
 * steady-state simulation of a discretised linear system. */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/expm.h"
#include "railride/timesim.h"
#include "util/internal.h"

void rr_lti_disc_free(rr_lti_disc *d)
{
  if (!d) return;
  free(d->Phi);
  free(d->G);
  d->Phi = d->G = NULL;
}

int rr_lti_discretise(int N, int m, const double *A, const double *B, double dt, rr_lti_disc *d,
                      rr_error *err)
{
  memset(d, 0, sizeof *d);
  if (!(N >= 1 && m >= 1 && dt > 0))
    return rr_seterr(err, RR_EINVAL, "lti: need N, m >= 1 and dt > 0");
  /* Van Loan: exp(dt [[A, B, 0, 0, 0], [0, 0, I/dt, 0, 0], [0, 0, 0, 2I/dt, 0],
     [0, 0, 0, 0, 3I/dt], [0...]]): the block row of x holds
     Gamma_p = int_0^dt e^{A(dt - tau)} B (tau/dt)^p dtau in the column block of
     the chain state that produces (tau/dt)^p. */
  int S = N + 4 * m;
  double *Mx = calloc((size_t)S * (size_t)S, sizeof(double)),
         *E = malloc(sizeof(double) * (size_t)S * (size_t)S);
  d->Phi = malloc(sizeof(double) * (size_t)N * (size_t)N);
  d->G = malloc(sizeof(double) * (size_t)N * 4 * (size_t)m);
  if (!Mx || !E || !d->Phi || !d->G) {
    free(Mx);
    free(E);
    rr_lti_disc_free(d);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int i = 0; i < N; i++) {
    for (int j = 0; j < N; j++) Mx[i * S + j] = A[i * N + j] * dt;
    for (int j = 0; j < m; j++) Mx[i * S + N + j] = B[i * m + j] * dt;
  }
  for (int p = 1; p <= 3; p++) /* y_{p-1}' = p y_p / dt */
    for (int j = 0; j < m; j++) Mx[(N + (p - 1) * m + j) * S + N + p * m + j] = p;
  int st = rr_expm(S, Mx, E, NULL, err);
  if (st) {
    free(Mx);
    free(E);
    rr_lti_disc_free(d);
    return st;
  }
  double *Gam[4];
  double *gbuf = malloc(sizeof(double) * 4 * (size_t)N * (size_t)m);
  if (!gbuf) {
    free(Mx);
    free(E);
    rr_lti_disc_free(d);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int p = 0; p < 4; p++) {
    Gam[p] = gbuf + (size_t)p * (size_t)N * (size_t)m;
    for (int i = 0; i < N; i++)
      for (int j = 0; j < m; j++) Gam[p][i * m + j] = E[i * S + N + p * m + j];
  }
  for (int i = 0; i < N; i++)
    memcpy(d->Phi + i * N, E + (size_t)i * (size_t)S, sizeof(double) * (size_t)N);
  /* Hermite: w(t) = h00 w_k + h10 dt w'_k + h01 w_{k+1} + h11 dt w'_{k+1}, t = tau/dt;
     in powers of t: 1: w_k; t: dt w'_k; t^2: -3 w_k - 2 dt w'_k + 3 w_{k+1} - dt w'_{k+1};
     t^3: 2 w_k + dt w'_k - 2 w_{k+1} + dt w'_{k+1}. */
  for (int i = 0; i < N; i++)
    for (int j = 0; j < m; j++) {
      int ij = i * m + j;
      double g0 = Gam[0][ij], g1 = Gam[1][ij], g2 = Gam[2][ij], g3 = Gam[3][ij];
      d->G[i * 4 * m + j] = g0 - 3 * g2 + 2 * g3;
      d->G[i * 4 * m + m + j] = dt * (g1 - 2 * g2 + g3);
      d->G[i * 4 * m + 2 * m + j] = 3 * g2 - 2 * g3;
      d->G[i * 4 * m + 3 * m + j] = dt * (-g2 + g3);
    }
  d->N = N;
  d->m = m;
  d->dt = dt;
  free(gbuf);
  free(Mx);
  free(E);
  return RR_OK;
}

/* One pass over the period from x (updated in place); outputs when y != NULL. */
static void pass(const rr_lti_disc *d, int ns, const double *w, const double *dw, int ny,
                 const double *C, const double *D, const double *E, double *y, double *x,
                 double *xn, double *in)
{
  int N = d->N, m = d->m;
  for (int k = 0; k < ns; k++) {
    int k1 = (k + 1) % ns;
    if (y)
      for (int r = 0; r < ny; r++) {
        double acc = 0;
        for (int i = 0; i < N; i++) acc += C[r * N + i] * x[i];
        for (int j = 0; j < m; j++) {
          acc += D[r * m + j] * w[(size_t)j * (size_t)ns + (size_t)k];
          if (E) acc += E[r * m + j] * dw[(size_t)j * (size_t)ns + (size_t)k];
        }
        y[(size_t)r * (size_t)ns + (size_t)k] = acc;
      }
    for (int j = 0; j < m; j++) {
      in[j] = w[(size_t)j * (size_t)ns + (size_t)k];
      in[m + j] = dw[(size_t)j * (size_t)ns + (size_t)k];
      in[2 * m + j] = w[(size_t)j * (size_t)ns + (size_t)k1];
      in[3 * m + j] = dw[(size_t)j * (size_t)ns + (size_t)k1];
    }
    cblas_dgemv(CblasRowMajor, CblasNoTrans, N, N, 1.0, d->Phi, N, x, 1, 0.0, xn, 1);
    cblas_dgemv(CblasRowMajor, CblasNoTrans, N, 4 * m, 1.0, d->G, 4 * m, in, 1, 1.0, xn, 1);
    memcpy(x, xn, sizeof(double) * (size_t)N);
  }
}

int rr_lti_periodic(const rr_lti_disc *d, int ns, const double *w, const double *dw, int ny,
                    const double *C, const double *D, const double *E, double *y, rr_error *err)
{
  int N = d->N;
  double *x = calloc((size_t)N, sizeof(double)), *xn = malloc(sizeof(double) * (size_t)N),
         *in = malloc(sizeof(double) * 4 * (size_t)d->m);
  double *P = malloc(sizeof(double) * (size_t)N * (size_t)N),
         *T = malloc(sizeof(double) * (size_t)N * (size_t)N),
         *R = malloc(sizeof(double) * (size_t)N * (size_t)N);
  int *piv = malloc(sizeof(int) * (size_t)N);
  int st = RR_OK;
  if (!x || !xn || !in || !P || !T || !R || !piv) {
    st = rr_seterr(err, RR_ENOMEM, "out of memory");
    goto done;
  }
  /* r: the state after one period from rest */
  pass(d, ns, w, dw, 0, NULL, NULL, NULL, NULL, x, xn, in);
  /* Phi^ns by binary powering */
  memset(R, 0, sizeof(double) * (size_t)N * (size_t)N);
  for (int i = 0; i < N; i++) R[i * N + i] = 1;
  memcpy(P, d->Phi, sizeof(double) * (size_t)N * (size_t)N);
  for (unsigned e = (unsigned)ns; e; e >>= 1) {
    if (e & 1) {
      cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, N, N, N, 1.0, R, N, P, N, 0.0, T, N);
      memcpy(R, T, sizeof(double) * (size_t)N * (size_t)N);
    }
    if (e > 1) {
      cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, N, N, N, 1.0, P, N, P, N, 0.0, T, N);
      memcpy(P, T, sizeof(double) * (size_t)N * (size_t)N);
    }
  }
  /* x0 = (I - Phi^ns)^-1 r: the periodic steady state */
  for (int i = 0; i < N * N; i++) R[i] = -R[i];
  for (int i = 0; i < N; i++) R[i * N + i] += 1;
  int info = LAPACKE_dgesv(LAPACK_ROW_MAJOR, N, 1, R, N, piv, x, 1);
  if (info) {
    st = rr_seterr(err, RR_ELAPACK,
                   "lti: no periodic steady state (a mode with period dividing the record?)");
    goto done;
  }
  pass(d, ns, w, dw, ny, C, D, E, y, x, xn, in);
done:
  free(x);
  free(xn);
  free(in);
  free(P);
  free(T);
  free(R);
  free(piv);
  return st;
}
