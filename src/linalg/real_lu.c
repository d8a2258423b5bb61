/* Small dense real LU with partial pivoting and its condition estimate. */
#include <float.h>
#include <math.h>
#include <string.h>
#include "linalg/real_lu.h"
#include "util/internal.h"

#define A_(i, j) a[(size_t)(j) * (size_t)lda + (size_t)(i)]
#define LU_(i, j) lu[(size_t)(j) * (size_t)lda + (size_t)(i)]

/* The first index of the largest |x_i| (BLAS idamax), in four independent
   chains: each keeps its own first maximum, ties between them go to the
   smaller index. */
RR_INLINE int iamax(int n, const double *x)
{
  double bv[4] = {-1, -1, -1, -1};
  int bi[4] = {0, 0, 0, 0}, i = 0;
  for (; i + 3 < n; i += 4)
    for (int e = 0; e < 4; e++)
      if (fabs(x[i + e]) > bv[e]) {
        bv[e] = fabs(x[i + e]);
        bi[e] = i + e;
      }
  double best = bv[0];
  int p = bi[0];
  for (int e = 1; e < 4; e++)
    if (bv[e] > best || (bv[e] == best && bi[e] < p)) {
      best = bv[e];
      p = bi[e];
    }
  for (; i < n; i++)
    if (fabs(x[i]) > best) {
      best = fabs(x[i]);
      p = i;
    }
  return p;
}

/* c_e -= l u_e for four columns at once: l is loaded once for the four */
RR_INLINE void update4(int m, const double *restrict l, double *restrict c0, double *restrict c1,
                       double *restrict c2, double *restrict c3, const double *u)
{
  for (int i = 0; i < m; i++) {
    double li = l[i];
    c0[i] -= li * u[0];
    c1[i] -= li * u[1];
    c2[i] -= li * u[2];
    c3[i] -= li * u[3];
  }
}

RR_CLONES int rr_lu_factor(int n, double *a, int lda, int *piv)
{
  int info = 0;
  for (int k = 0; k < n; k++) {
    int p = k + iamax(n - k, &A_(k, k));
    piv[k] = p;
    if (A_(p, k) == 0) {
      if (!info) info = k + 1;
      continue;
    }
    if (p != k)
      for (int j = 0; j < n; j++) {
        double t = A_(k, j);
        A_(k, j) = A_(p, j);
        A_(p, j) = t;
      }
    /* LAPACK's multipliers: by the reciprocal unless it would overflow */
    double d = A_(k, k), r = 1 / d;
    double *lk = &A_(0, k);
    if (fabs(d) >= DBL_MIN)
      for (int i = k + 1; i < n; i++) lk[i] *= r;
    else
      for (int i = k + 1; i < n; i++) lk[i] /= d;
    int j = k + 1, m = n - k - 1;
    for (; j + 3 < n; j += 4) {
      double u[4] = {A_(k, j), A_(k, j + 1), A_(k, j + 2), A_(k, j + 3)};
      update4(m, lk + k + 1, &A_(k + 1, j), &A_(k + 1, j + 1), &A_(k + 1, j + 2), &A_(k + 1, j + 3),
              u);
    }
    for (; j < n; j++) {
      double u = A_(k, j), *cj = &A_(0, j);
      for (int i = k + 1; i < n; i++) cj[i] -= lk[i] * u;
    }
  }
  return info;
}

/* y -= t a */
RR_INLINE void axpy(int m, double t, const double *restrict a, double *restrict y)
{
  for (int i = 0; i < m; i++) y[i] -= t * a[i];
}

/* x = L^-1 x, then x = U^-1 x (column by column, as dtrsv) */
RR_INLINE void solve_lu(int n, const double *lu, int lda, double *x)
{
  for (int j = 0; j < n; j++)
    if (x[j] != 0) axpy(n - j - 1, x[j], &LU_(j + 1, j), x + j + 1);
  for (int j = n - 1; j >= 0; j--)
    if (x[j] != 0) axpy(j, x[j] /= LU_(j, j), &LU_(0, j), x);
}

/* x = U^-T x, then x = L^-T x (dot products down the columns, DOT4's four partial sums) */
RR_INLINE void solve_lu_t(int n, const double *lu, int lda, double *x)
{
  for (int j = 0; j < n; j++) {
    double d;
    DOT4(double, &LU_(0, j), x, 0, j, d);
    x[j] = (x[j] - d) / LU_(j, j);
  }
  for (int j = n - 1; j >= 0; j--) {
    double d;
    DOT4(double, &LU_(0, j), x, j + 1, n, d);
    x[j] -= d;
  }
}

/* y -= t x over one row of right-hand sides */
RR_INLINE void row_axpy(int m, double t, const double *restrict x, double *restrict y)
{
  for (int c = 0; c < m; c++) y[c] -= t * x[c];
}

RR_CLONES void rr_lu_solve_rows(int n, const double *lu, int lda, const int *piv, int nrhs,
                                double *x, int ldx)
{
#define X_(i) (x + (size_t)(i) * (size_t)ldx)
  for (int k = 0; k < n; k++)
    if (piv[k] != k)
      for (int c = 0; c < nrhs; c++) {
        double t = X_(k)[c];
        X_(k)[c] = X_(piv[k])[c];
        X_(piv[k])[c] = t;
      }
  for (int j = 0; j < n; j++)
    for (int i = j + 1; i < n; i++)
      if (LU_(i, j) != 0) row_axpy(nrhs, LU_(i, j), X_(j), X_(i));
  for (int j = n - 1; j >= 0; j--) {
    double d = LU_(j, j);
    for (int c = 0; c < nrhs; c++) X_(j)[c] /= d;
    for (int i = 0; i < j; i++)
      if (LU_(i, j) != 0) row_axpy(nrhs, LU_(i, j), X_(j), X_(i));
  }
#undef X_
}

double rr_lu_norm1(int n, const double *a, int lda)
{
  double v = 0;
  for (int j = 0; j < n; j++) {
    double s = 0;
    for (int i = 0; i < n; i++) s += fabs(A_(i, j));
    if (s > v || isnan(s)) v = s;
  }
  return v;
}

RR_INLINE double asum(int n, const double *x)
{
  double s = 0;
  for (int i = 0; i < n; i++) s += fabs(x[i]);
  return s;
}

/* x_i = sign(x_i) (+1 for zero); returns whether that differs from sgn */
RR_INLINE int sign_vector(int n, double *x, const int *sgn)
{
  int changed = 0;
  for (int i = 0; i < n; i++) {
    int s = x[i] >= 0 ? 1 : -1;
    changed |= s != sgn[i];
    x[i] = s;
  }
  return changed;
}

/* |A^-1|_1 estimated as dlacn2 does (Higham, ACM TOMS 14, 1988): a gradient
 * search over the unit vectors from the start (1/n, ..., 1/n), at most five
 * steps, then the alternating-sign vector as a safeguard. A^-1 is (LU)^-1:
 * the row interchanges permute its columns, which leaves the 1-norm alone. */
RR_INLINE double inverse_norm1(int n, const double *lu, int lda, double *x, int *sgn)
{
  enum { ITMAX = 5 };
  for (int i = 0; i < n; i++) x[i] = 1.0 / n;
  solve_lu(n, lu, lda, x);
  if (n == 1) return fabs(x[0]);
  double est = asum(n, x);
  for (int i = 0; i < n; i++) sgn[i] = (int)(x[i] = x[i] >= 0 ? 1 : -1);
  solve_lu_t(n, lu, lda, x);
  int j = iamax(n, x);
  for (int iter = 2;; iter++) {
    memset(x, 0, sizeof(double) * (size_t)n);
    x[j] = 1;
    solve_lu(n, lu, lda, x);
    double estold = est;
    est = asum(n, x);
    /* a repeated sign vector, or no increase (cycling): converged */
    if (!sign_vector(n, x, sgn) || est <= estold) break;
    for (int i = 0; i < n; i++) sgn[i] = (int)x[i];
    solve_lu_t(n, lu, lda, x);
    int jlast = j;
    j = iamax(n, x);
    if (!(x[jlast] != fabs(x[j]) && iter < ITMAX)) break;
  }
  double alt = 1;
  for (int i = 0; i < n; i++) {
    x[i] = alt * (1 + (double)i / (n - 1));
    alt = -alt;
  }
  solve_lu(n, lu, lda, x);
  double temp = 2 * (asum(n, x) / (3.0 * n));
  return temp > est ? temp : est;
}

RR_CLONES double rr_lu_rcond1(int n, const double *lu, int lda, double anorm, double *work,
                              int *iwork)
{
  if (n == 0) return 1;
  if (!(anorm > 0) || !isfinite(anorm)) return 0;
  double ainv = inverse_norm1(n, lu, lda, work, iwork);
  if (!(ainv > 0) || !isfinite(ainv)) return 0;
  double r = (1 / ainv) / anorm;
  return isfinite(r) ? r : 0;
}
