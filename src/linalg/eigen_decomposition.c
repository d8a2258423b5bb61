/* Eigendecomposition by hqr + Hessenberg inverse iteration (see eigen_decomposition.h). */
#include <float.h>
#include <math.h>
#include <string.h>
#include "eigen_decomposition.h"
#include "hessenberg_qr.h"
#include "internal.h"

/* LU of the Hessenberg matrix H - mu I with partial pivoting: row k+1 is the
 * only candidate at step k. U overwrites (ur, ui) (row-major, real and
 * imaginary parts apart so that the row updates vectorise); lr, li, sw hold
 * step k's multiplier and interchange, dr, di the reciprocal pivots. A zero pivot (mu an exact
 * eigenvalue) becomes eps3, as in LAPACK's dlaein. */
RR_INLINE void hess_lu(int n, const double *h, double mr, double mi, double eps3, double *ur,
                       double *ui, double *lr, double *li, int *sw, double *dr, double *di)
{
  for (int i = 0; i < n; i++) {
    int j0 = i > 0 ? i - 1 : 0;
    for (int j = j0; j < n; j++) {
      ur[i * n + j] = h[i * n + j];
      ui[i * n + j] = 0;
    }
    ur[i * n + i] -= mr;
    ui[i * n + i] = -mi;
  }
  for (int k = 0; k < n - 1; k++) {
    double *rk = ur + k * n, *ik = ui + k * n, *rk1 = rk + n, *ik1 = ik + n;
    sw[k] = fabs(rk1[k]) + fabs(ik1[k]) > fabs(rk[k]) + fabs(ik[k]);
    if (sw[k])
      for (int j = k; j < n; j++) {
        double t = rk[j];
        rk[j] = rk1[j];
        rk1[j] = t;
        t = ik[j];
        ik[j] = ik1[j];
        ik1[j] = t;
      }
    if (rk[k] == 0 && ik[k] == 0) rk[k] = eps3;
    double d = 1 / (rk[k] * rk[k] + ik[k] * ik[k]);
    double l_r = (rk1[k] * rk[k] + ik1[k] * ik[k]) * d, l_i = (ik1[k] * rk[k] - rk1[k] * ik[k]) * d;
    lr[k] = l_r;
    li[k] = l_i;
    for (int j = k + 1; j < n; j++) {
      double a = rk[j], b = ik[j];
      rk1[j] -= l_r * a - l_i * b;
      ik1[j] -= l_r * b + l_i * a;
    }
  }
  if (ur[n * n - 1] == 0 && ui[n * n - 1] == 0) ur[n * n - 1] = eps3;
  for (int i = 0; i < n; i++) {
    double a = ur[i * n + i], b = ui[i * n + i], d = 1 / (a * a + b * b);
    dr[i] = a * d;
    di[i] = -b * d;
  }
}

/* U y = y in place; (dr, di) = 1 / diag(U), so that no division sits in the
 * recurrence. */
RR_INLINE void back_subst(int n, const double *ur, const double *ui, const double *dr,
                          const double *di, double *yr, double *yi)
{
  for (int i = n - 1; i >= 0; i--) {
    const double *ri = ur + i * n, *ii = ui + i * n;
    double sr = yr[i], si = yi[i];
    /* a reduction the compiler may vectorise (reassociation allowed here) */
#pragma omp simd reduction(+ : sr, si)
    for (int j = i + 1; j < n; j++) {
      sr += ii[j] * yi[j] - ri[j] * yr[j];
      si -= ri[j] * yi[j] + ii[j] * yr[j];
    }
    yr[i] = sr * dr[i] - si * di[i];
    yi[i] = sr * di[i] + si * dr[i];
  }
}

/* Scales y to largest component 1 (1-norm of each component). */
RR_INLINE void normalise(int n, double *yr, double *yi)
{
  int big = 0;
  double b = 0;
  for (int i = 0; i < n; i++) {
    double t = fabs(yr[i]) + fabs(yi[i]);
    if (t > b) {
      b = t;
      big = i;
    }
  }
  if (b == 0) return;
  double d = 1 / (yr[big] * yr[big] + yi[big] * yi[big]), sr = yr[big] * d, si = -yi[big] * d;
  for (int i = 0; i < n; i++) {
    double r = yr[i] * sr - yi[i] * si;
    yi[i] = yr[i] * si + yi[i] * sr;
    yr[i] = r;
  }
  yr[big] = 1;
  yi[big] = 0;
}

/* Diagonal similarity D^-1 A D with powers of 2 (exact) equalising each
 * state's row and column 1-norms (EISPACK's balanc, Parlett & Reinsch 1969):
 * the state matrix mixes displacements, velocities and damper strokes whose
 * scales differ by orders of magnitude. d receives D. */
static void balance(int n, double *a, double *d)
{
  for (int i = 0; i < n; i++) d[i] = 1;
  for (int done = 0, sweeps = 0; !done && sweeps < 100; sweeps++) {
    done = 1;
    for (int i = 0; i < n; i++) {
      double c = 0, r = 0;
      for (int j = 0; j < n; j++)
        if (j != i) {
          c += fabs(a[(size_t)j * n + i]);
          r += fabs(a[(size_t)i * n + j]);
        }
      if (c == 0 || r == 0) continue;
      double g = r / 2, f = 1, s = c + r;
      while (c < g) {
        f *= 2;
        c *= 4;
      }
      g = r * 2;
      while (c > g) {
        f /= 2;
        c /= 4;
      }
      if ((c + r) / f < 0.95 * s) {
        done = 0;
        d[i] *= f;
        for (int j = 0; j < n; j++) a[(size_t)i * n + j] /= f;
        for (int j = 0; j < n; j++) a[(size_t)j * n + i] *= f;
      }
    }
  }
}

RR_CLONES int rr_eigdec(int n, double *a, double *wr, double *wi, double *vr, double *work,
                        int *iwork)
{
  if (n > 64 || n < 1) return -1;
  int *perm = iwork, *sw = iwork + n;
  double *h = work, *ur = h + n * n, *ui = ur + n * n, *yr = ui + n * n, *yi = yr + n, *lr = yi + n,
         *li = lr + n, *dsc = li + n, *dr = dsc + n, *di = dr + n;
  balance(n, a, dsc);
  rr_elmhes(n, a, perm);
  memcpy(h, a, sizeof(double) * n * n);
  if (rr_hqr(n, h, wr, wi)) return -1;
  for (int j = 0; j + 1 < n; j++)
    if (wi[j] < 0) { /* LAPACK's order: the positive imaginary part first */
      wi[j] = -wi[j];
      wi[j + 1] = -wi[j + 1];
      j++;
    }
  double hnorm = 0;
  for (int i = 0; i < n; i++) {
    double s = 0;
    for (int j = i > 0 ? i - 1 : 0; j < n; j++) s += fabs(a[i * n + j]);
    hnorm = fmax(hnorm, s);
  }
  double eps3 = hnorm > 0 ? DBL_EPSILON * hnorm : DBL_MIN;
  for (int j = 0; j < n; j++) {
    if (wi[j] < 0) continue; /* the conjugate of column j - 1 */
    double mr = wr[j], mi = wi[j];
    /* an eigenvalue equal to an earlier one gets a nearby shift, so that the
       two vectors differ (LAPACK's dhsein does the same) */
    for (int i = 0; i < j; i++)
      if (wi[i] >= 0 && fabs(wr[i] - mr) + fabs(wi[i] - mi) < eps3) {
        mr += eps3;
        i = -1;
      }
    hess_lu(n, a, mr, mi, eps3, ur, ui, lr, li, sw, dr, di);
    /* inverse iteration from the vector of ones taken as L^-1 P v (dlaein's
       start): U alone, then one full step. One step leaves residuals of
       n eps |H| and FRF errors near 1e-11; the second brings them to 1e-13. */
    for (int i = 0; i < n; i++) {
      yr[i] = 1;
      yi[i] = 0;
    }
    back_subst(n, ur, ui, dr, di, yr, yi);
    normalise(n, yr, yi);
    {
      for (int k = 0; k < n - 1; k++) {
        if (sw[k]) {
          double t = yr[k];
          yr[k] = yr[k + 1];
          yr[k + 1] = t;
          t = yi[k];
          yi[k] = yi[k + 1];
          yi[k + 1] = t;
        }
        yr[k + 1] -= lr[k] * yr[k] - li[k] * yi[k];
        yi[k + 1] -= lr[k] * yi[k] + li[k] * yr[k];
      }
      back_subst(n, ur, ui, dr, di, yr, yi);
    }
    /* x = D P_1 L_1 ... P_{n-2} L_{n-2} y: elmhes' and balance's
       transformations undone */
    for (int m = n - 2; m >= 1; m--) {
      for (int i = m + 1; i < n; i++) {
        double mult = a[i * n + m - 1];
        yr[i] += mult * yr[m];
        yi[i] += mult * yi[m];
      }
      int p = perm[m];
      if (p != m) {
        double t = yr[p];
        yr[p] = yr[m];
        yr[m] = t;
        t = yi[p];
        yi[p] = yi[m];
        yi[m] = t;
      }
    }
    for (int i = 0; i < n; i++) {
      yr[i] *= dsc[i];
      yi[i] *= dsc[i];
    }
    normalise(n, yr, yi);
    double *c0 = vr + (size_t)j * n;
    memcpy(c0, yr, sizeof(double) * n);
    if (wi[j] > 0) memcpy(c0 + n, yi, sizeof(double) * n);
  }
  return 0;
}
