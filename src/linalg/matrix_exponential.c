/* Matrix exponential: scaling and squaring, [13/13] Pade (Higham 2005,
 * Algorithm 2.3 with the degree-13 approximant for every norm, which keeps
 * the backward error below unit roundoff). */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/expm.h"
#include "util/internal.h"

static const double b13[14] = {64764752532480000.0,
                               32382376266240000.0,
                               7771770303897600.0,
                               1187353796428800.0,
                               129060195264000.0,
                               10559470521600.0,
                               670442572800.0,
                               33522128640.0,
                               1323241920.0,
                               40840800.0,
                               960960.0,
                               16380.0,
                               182.0,
                               1.0};
static const double theta13 = 5.371920351148152;

size_t rr_expm_work_size(int n) { return (size_t)9 * (size_t)n * (size_t)n + (size_t)n; }

static void mm(int n, const double *A, const double *B, double *C)
{
  cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, n, n, n, 1.0, A, n, B, n, 0.0, C, n);
}

int rr_expm(int n, const double *A0, double *E, double *work, rr_error *err)
{
  if (n < 1) return rr_seterr(err, RR_EINVAL, "expm: n must be >= 1");
  double *own = NULL;
  if (!work) {
    own = work = malloc(sizeof(double) * rr_expm_work_size(n));
    if (!work) return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  size_t nn = (size_t)n * (size_t)n;
  double *A = work, *A2 = A + nn, *A4 = A2 + nn, *A6 = A4 + nn, *U = A6 + nn, *V = U + nn,
         *T = V + nn, *P = T + nn, *Q = P + nn;
  int *ipiv = (int *)(Q + nn); /* n ints fit in n doubles */
  /* 1-norm decides the scaling */
  double norm = 0;
  for (int j = 0; j < n; j++) {
    double s = 0;
    for (int i = 0; i < n; i++) s += fabs(A0[i * n + j]);
    if (s > norm) norm = s;
  }
  if (!isfinite(norm)) {
    free(own);
    return rr_seterr(err, RR_EINVAL, "expm: matrix is not finite");
  }
  int s = norm > theta13 ? (int)ceil(log2(norm / theta13)) : 0;
  double scale = ldexp(1.0, -s);
  for (size_t i = 0; i < nn; i++) A[i] = A0[i] * scale;
  mm(n, A, A, A2);
  mm(n, A2, A2, A4);
  mm(n, A4, A2, A6);
  /* U = A [A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I] */
  for (size_t i = 0; i < nn; i++) T[i] = b13[13] * A6[i] + b13[11] * A4[i] + b13[9] * A2[i];
  mm(n, A6, T, P);
  for (size_t i = 0; i < nn; i++) P[i] += b13[7] * A6[i] + b13[5] * A4[i] + b13[3] * A2[i];
  for (int i = 0; i < n; i++) P[i * n + i] += b13[1];
  mm(n, A, P, U);
  /* V = A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I */
  for (size_t i = 0; i < nn; i++) T[i] = b13[12] * A6[i] + b13[10] * A4[i] + b13[8] * A2[i];
  mm(n, A6, T, V);
  for (size_t i = 0; i < nn; i++) V[i] += b13[6] * A6[i] + b13[4] * A4[i] + b13[2] * A2[i];
  for (int i = 0; i < n; i++) V[i * n + i] += b13[0];
  /* (V - U) X = (V + U) */
  for (size_t i = 0; i < nn; i++) {
    P[i] = V[i] - U[i];
    Q[i] = V[i] + U[i];
  }
  int info = LAPACKE_dgesv_work(LAPACK_ROW_MAJOR, n, n, P, n, ipiv, Q, n);
  if (info) {
    free(own);
    return rr_seterr(err, RR_ELAPACK, "expm: Pade denominator singular (info %d)", info);
  }
  /* square s times */
  double *cur = Q, *nxt = T;
  for (int k = 0; k < s; k++) {
    mm(n, cur, cur, nxt);
    double *t = cur;
    cur = nxt;
    nxt = t;
  }
  memcpy(E, cur, sizeof(double) * nn);
  free(own);
  return RR_OK;
}
