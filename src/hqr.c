/* Eigenvalues of small dense matrices: elmhes + hqr (see hqr.h). */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include "hqr.h"

#define A(i, j) a[(i) * n + (j)]
/* inline, unlike fmax/fmin (no NaN can reach them here) */
#define MAX(a, b) ((a) > (b) ? (a) : (b))
#define MIN(a, b) ((a) < (b) ? (a) : (b))

/* Reduction to upper Hessenberg form by stabilised elementary similarity
 * transformations (Gaussian elimination with row interchanges). The step's
 * elementary transforms L_i = I + y_i e_i e_m' commute, so it is applied as
 * L^-1 A L in two contiguous passes: every row elimination first, then
 * column m += A y as one dot product per row (row-major friendly). */
static void elmhes(int n, double *a, int *perm)
{
  double y[64];
  for (int m = 1; m < n - 1; m++) {
    double x = 0;
    int piv = m;
    for (int j = m; j < n; j++)
      if (fabs(A(j, m - 1)) > fabs(x)) { x = A(j, m - 1); piv = j; }
    if (perm) perm[m] = piv;
    if (piv != m) {
      for (int j = m - 1; j < n; j++) { double t = A(piv, j); A(piv, j) = A(m, j); A(m, j) = t; }
      for (int i = 0; i < n; i++) { double t = A(i, piv); A(i, piv) = A(i, m); A(i, m) = t; }
    }
    if (x == 0) continue;
    const double *rm = &A(m, 0);
    int any = 0;
    for (int i = m + 1; i < n; i++) {
      double yi = A(i, m - 1) / x;
      y[i] = yi;
      A(i, m - 1) = perm ? yi : 0;   /* kept for the back-transformation */
      if (yi == 0) continue;
      any = 1;
      double *ri = &A(i, 0);
      for (int j = m; j < n; j++) ri[j] -= yi * rm[j];
    }
    if (!any) continue;
    for (int j = 0; j < n; j++) {
      const double *rj = &A(j, 0);
      /* four partial sums: a single chain would wait on every add */
      double a0 = 0, a1 = 0, a2 = 0, a3 = 0;
      int i = m + 1;
      for (; i + 3 < n; i += 4) {
        a0 += rj[i] * y[i];
        a1 += rj[i + 1] * y[i + 1];
        a2 += rj[i + 2] * y[i + 2];
        a3 += rj[i + 3] * y[i + 3];
      }
      for (; i < n; i++) a0 += rj[i] * y[i];
      A(j, m) += (a0 + a1) + (a2 + a3);
    }
  }
}

static double sgn(double a, double b) { return b >= 0 ? fabs(a) : -fabs(a); }

/* Francis double-shift QR on the active block only (eigenvalues, no Schur
 * form). Reads only the Hessenberg part and the bulge it makes itself. */
int rr_hqr(int n, double *a, double *wr, double *wi)
{
  double anorm = 0, p = 0, q = 0, r = 0, s, t = 0, w, x, y, z;
  for (int i = 0; i < n; i++)
    for (int j = i > 0 ? i - 1 : 0; j < n; j++) anorm += fabs(A(i, j));
  int nn = n - 1;
  while (nn >= 0) {
    int its = 0, l;
    do {
      for (l = nn; l >= 1; l--) {
        /* deflation test of Ahues & Tisseur (LAPACK Working Note 122), as in
           LAPACK's dlahqr: a small subdiagonal is negligible relative to the
           2 x 2 block it couples */
        double h = fabs(A(l, l - 1));
        if (h <= DBL_MIN) { A(l, l - 1) = 0; break; }
        s = fabs(A(l - 1, l - 1)) + fabs(A(l, l));
        if (s == 0) s = anorm;
        if (h <= DBL_EPSILON * s) {
          double hu = fabs(A(l - 1, l)), ab = MAX(h, hu), ba = MIN(h, hu);
          double dd = fabs(A(l - 1, l - 1) - A(l, l)), aa = MAX(fabs(A(l, l)), dd), bb = MIN(fabs(A(l, l)), dd);
          double ss = aa + ab;
          if (ba * (ab / ss) <= MAX(DBL_MIN, DBL_EPSILON * (bb * (aa / ss)))) { A(l, l - 1) = 0; break; }
        }
      }
      x = A(nn, nn);
      if (l == nn) {                      /* one root */
        wr[nn] = x + t;
        wi[nn--] = 0;
      } else {
        y = A(nn - 1, nn - 1);
        w = A(nn, nn - 1) * A(nn - 1, nn);
        if (l == nn - 1) {                /* two roots */
          p = 0.5 * (y - x);
          q = p * p + w;
          z = sqrt(fabs(q));
          x += t;
          if (q >= 0) {
            z = p + sgn(z, p);
            wr[nn - 1] = wr[nn] = x + z;
            if (z != 0) wr[nn] = x - w / z;
            wi[nn - 1] = wi[nn] = 0;
          } else {
            wr[nn - 1] = wr[nn] = x + p;
            wi[nn - 1] = -(wi[nn] = z);
          }
          nn -= 2;
        } else {                          /* no root yet: a double QR step */
          if (its == 30 * (n > 10 ? n : 10)) return -1;   /* LAPACK's limit */
          if (its > 0 && its % 10 == 0) {                  /* exceptional shift */
            t += x;
            for (int i = 0; i <= nn; i++) A(i, i) -= x;
            s = fabs(A(nn, nn - 1)) + fabs(A(nn - 1, nn - 2));
            y = x = 0.75 * s;
            w = -0.4375 * s * s;
          }
          ++its;
          int m;
          /* Where to start the sweep: two small consecutive subdiagonals?
             The first column of the shifted product is formed times
             h(m+1, m), the test being scale-free: no division per row. */
          for (m = nn - 2; m >= l; m--) {
            z = A(m, m);
            r = x - z;
            s = y - z;
            double h21 = A(m + 1, m);
            p = (r * s - w) + A(m, m + 1) * h21;
            q = (A(m + 1, m + 1) - z - r - s) * h21;
            r = A(m + 2, m + 1) * h21;
            if (m == l) break;
            double u = fabs(A(m, m - 1)) * (fabs(q) + fabs(r));
            double v = fabs(p) * (fabs(A(m - 1, m - 1)) + fabs(z) + fabs(A(m + 1, m + 1)));
            if (u + v == v) break;
          }
          s = 1 / (fabs(p) + fabs(q) + fabs(r));
          p *= s;
          q *= s;
          r *= s;
          for (int i = m + 2; i <= nn; i++) {
            A(i, i - 2) = 0;
            if (i != m + 2) A(i, i - 3) = 0;
          }
          for (int k = m; k <= nn - 1; k++) {
            if (k != m) {
              p = A(k, k - 1);
              q = A(k + 1, k - 1);
              r = k != nn - 1 ? A(k + 2, k - 1) : 0;
              x = fabs(p) + fabs(q) + fabs(r);
              /* scaled only where p^2 + q^2 + r^2 could under- or overflow */
              if (x != 0 && (x < 1e-100 || x > 1e100)) {
                double ix = 1 / x;
                p *= ix;
                q *= ix;
                r *= ix;
              } else x = 1;
            }
            if ((s = sgn(sqrt(p * p + q * q + r * r), p)) != 0) {
              if (k == m) {
                if (l != m) A(k, k - 1) = -A(k, k - 1);
              } else {
                A(k, k - 1) = -s * x;
              }
              /* reciprocals of s and p + s side by side: fewer divisions on
                 the sweep's critical path */
              double is = 1 / s;
              p += s;
              double ip = 1 / p;
              x = p * is;
              y = q * is;
              z = r * is;
              q *= ip;
              r *= ip;
              double *rk = &A(k, 0), *rk1 = &A(k + 1, 0);
              if (k != nn - 1) {
                double *rk2 = &A(k + 2, 0);
                for (int j = k; j <= nn; j++) {
                  double pp = rk[j] + q * rk1[j] + r * rk2[j];
                  rk2[j] -= pp * z;
                  rk1[j] -= pp * y;
                  rk[j] -= pp * x;
                }
              } else {
                for (int j = k; j <= nn; j++) {
                  double pp = rk[j] + q * rk1[j];
                  rk1[j] -= pp * y;
                  rk[j] -= pp * x;
                }
              }
              int mmin = nn < k + 3 ? nn : k + 3;
              for (int i = l; i <= mmin; i++) {
                double *ri = &A(i, 0);
                double pp = x * ri[k] + y * ri[k + 1];
                if (k != nn - 1) {
                  pp += z * ri[k + 2];
                  ri[k + 2] -= pp * r;
                }
                ri[k + 1] -= pp * q;
                ri[k] -= pp;
              }
            }
          }
        }
      }
    } while (l < nn - 1);
  }
  return 0;
}

int rr_eig_small(int n, double *a, double *wr, double *wi)
{
  if (n > 64) return -1;   /* elmhes' multiplier buffer; larger goes to LAPACK */
  elmhes(n, a, NULL);
  return rr_hqr(n, a, wr, wi);
}

void rr_elmhes(int n, double *a, int *perm)
{
  elmhes(n, a, perm);
}
