/* Faster kernels for SUNDIALS' serial vectors where the vectors are long: the
 * periodic-orbit solver integrates the state with its n x (n + 1)
 * variational columns (1,680 numbers for the 40-state car), and there the
 * stage combinations of the explicit Runge-Kutta pair were half the run time
 * in the library's kernels (one pass over the result per term, scalar code).
 * These make one pass, a block at a time, with the same operations in the
 * same order per element; the weighted norm keeps four partial sums. */
#include <math.h>
#include <nvector/nvector_serial.h>
#include "nonlinear/nvector_fast.h"
#include "util/internal.h"

#define BLOCK 256    /* elements per block: the partial results stay in L1 */
#define MAX_TERMS 32 /* more terms go to the library's kernel */

/* z = sum_j c_j X_j; z may be one of the X_j (each block is read whole
   before it is written). */
RR_CLONES static int lincomb(int nvec, realtype *c, N_Vector *X, N_Vector z)
{
  if (nvec > MAX_TERMS) return N_VLinearCombination_Serial(nvec, c, X, z);
  sunindextype n = NV_LENGTH_S(z);
  double *zd = NV_DATA_S(z), acc[BLOCK];
  const double *x[MAX_TERMS];
  for (int j = 0; j < nvec; j++) x[j] = NV_DATA_S(X[j]);
  for (sunindextype i0 = 0; i0 < n; i0 += BLOCK) {
    int len = n - i0 < BLOCK ? (int)(n - i0) : BLOCK;
    const double *x0 = x[0] + i0;
#pragma omp simd
    for (int i = 0; i < len; i++) acc[i] = c[0] * x0[i];
    for (int j = 1; j < nvec; j++) {
      const double *xj = x[j] + i0;
      double cj = c[j];
#pragma omp simd
      for (int i = 0; i < len; i++) acc[i] += cj * xj[i];
    }
    for (int i = 0; i < len; i++) zd[i0 + i] = acc[i];
  }
  return 0;
}

RR_CLONES static realtype wsqrsum(N_Vector xv, N_Vector wv)
{
  sunindextype n = NV_LENGTH_S(xv);
  const double *x = NV_DATA_S(xv), *w = NV_DATA_S(wv);
  double s[4] = {0, 0, 0, 0};
  sunindextype i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; k++) {
      double p = x[i + k] * w[i + k];
      s[k] += p * p;
    }
  for (; i < n; i++) s[0] += (x[i] * w[i]) * (x[i] * w[i]);
  return (s[0] + s[1]) + (s[2] + s[3]);
}

static realtype wrmsnorm(N_Vector x, N_Vector w)
{
  return sqrt(wsqrsum(x, w) / (double)NV_LENGTH_S(x));
}

void rr_nvector_fast(N_Vector v)
{
  v->ops->nvlinearcombination = lincomb;
  v->ops->nvwsqrsumlocal = wsqrsum;
  v->ops->nvwrmsnorm = wrmsnorm;
}
