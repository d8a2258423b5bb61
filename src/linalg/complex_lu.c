/* Small dense complex LU with partial pivoting. */
#include <math.h>
#include "linalg/complex_lu.h"

static double abs1(double complex z) { return fabs(creal(z)) + fabs(cimag(z)); }

int rr_clu_factor(double complex *A, int n, int *piv, double tiny)
{
  int replaced = 0;
  for (int k = 0; k < n; k++) {
    int p = k;
    double best = abs1(A[k * n + k]);
    for (int i = k + 1; i < n; i++) {
      double v = abs1(A[i * n + k]);
      if (v > best) {
        best = v;
        p = i;
      }
    }
    piv[k] = p;
    if (p != k)
      for (int j = 0; j < n; j++) {
        double complex t = A[k * n + j];
        A[k * n + j] = A[p * n + j];
        A[p * n + j] = t;
      }
    if (best <= tiny) {
      A[k * n + k] = tiny;
      replaced++;
    }
    double complex inv = 1.0 / A[k * n + k];
    for (int i = k + 1; i < n; i++) {
      double complex l = A[i * n + k] * inv;
      A[i * n + k] = l;
      if (l == 0) continue;
      for (int j = k + 1; j < n; j++) A[i * n + j] -= l * A[k * n + j];
    }
  }
  return replaced;
}

void rr_clu_solve(const double complex *LU, int n, const int *piv, double complex *b)
{
  /* Whole-row swaps during factoring leave L in the final row order, so the
     swaps go to b first, then the forward substitution. */
  for (int k = 0; k < n; k++)
    if (piv[k] != k) {
      double complex t = b[k];
      b[k] = b[piv[k]];
      b[piv[k]] = t;
    }
  for (int k = 0; k < n; k++)
    for (int i = k + 1; i < n; i++) b[i] -= LU[i * n + k] * b[k];
  for (int k = n - 1; k >= 0; k--) {
    for (int j = k + 1; j < n; j++) b[k] -= LU[k * n + j] * b[j];
    b[k] /= LU[k * n + k];
  }
}
