/* Eigendecomposition by hqr + Hessenberg inverse iteration (see eigen_decomposition.h). */
#include <float.h>
#include <math.h>
#include <string.h>
#include "linalg/eigen_decomposition.h"
#include "linalg/hessenberg_qr.h"
#include "util/internal.h"

/* Inverse iteration runs RR_EIGDEC_LANES shifts at once, lane l of every
 * array holding shift l's numbers (index [i * L + l]), so that each scalar
 * step of the one-shift algorithm becomes one vector operation; a row
 * interchange that some lanes take and others not is a select. About 3x
 * faster than one shift at a time with the same operations. */
#define L RR_EIGDEC_LANES
_Static_assert(L == 8, "back_subst takes the lanes as two vectors of four");

/* Four lanes' numbers (GCC's and Clang's vector extension), moved by memcpy
   and never passed by value, so that the clones keep one ABI. */
typedef double v4d __attribute__((vector_size(4 * sizeof(double))));
/* A compiler barrier after a step's loads: the values are used from the
   registers they were loaded into, not read from memory again for each use
   (which GCC otherwise does, folding a load into every product). No
   instruction is emitted. */
#if defined(__GNUC__)
#define LOADS_DONE() __asm__ volatile("" ::: "memory")
#else
#define LOADS_DONE() ((void)0)
#endif

typedef struct lanes {
  double *ur, *ui;           /* U of each lane's LU, n x n x L, real and imaginary parts apart */
  double *yr, *yi;           /* the iterates, n x L */
  double *lr, *li, *dr, *di; /* step k's multiplier; reciprocal pivots (n x L) */
  int *sw;                   /* step k interchanged rows k, k+1 (n x L) */
} lanes;

/* LU of the Hessenberg matrix H - mu_l I with partial pivoting: row k+1 is
 * the only candidate at step k. A zero pivot (mu an exact eigenvalue)
 * becomes eps3, as in LAPACK's dlaein. Step k touches rows k and k+1 only,
 * so row k+1 is still H's when it comes in: it is read from h, and each
 * step's interchange and elimination are one pass that writes U's row k
 * and the next working row. */
RR_INLINE void hess_lu(int n, const double *h, const double *mr, const double *mi, double eps3,
                       const lanes *w)
{
  double *ur = w->ur, *ui = w->ui;
  const double zero = 0; /* the imaginary part of H's entries off the diagonal */
  for (int j = 0; j < n; j++)
    for (int l = 0; l < L; l++) {
      ur[j * L + l] = j == 0 ? h[0] - mr[l] : h[j];
      ui[j * L + l] = j == 0 ? -mi[l] : zero;
    }
  for (int k = 0; k < n - 1; k++) {
    double *rk = ur + k * n * L, *ik = ui + k * n * L, *rk1 = rk + n * L, *ik1 = ik + n * L;
    const double *hk1 = h + (k + 1) * n; /* row k + 1 of H - mu I, as it came */
    int *sw = w->sw + k * L;
    double l_r[L], l_i[L];
    for (int l = 0; l < L; l++) {
      double ar = rk[k * L + l], ai = ik[k * L + l], br = hk1[k], bi = zero;
      sw[l] = fabs(br) + fabs(bi) > fabs(ar) + fabs(ai);
      double pr = sw[l] ? br : ar, pi = sw[l] ? bi : ai, qr = sw[l] ? ar : br, qi = sw[l] ? ai : bi;
      if (pr == 0 && pi == 0) pr = eps3;
      rk[k * L + l] = pr;
      ik[k * L + l] = pi;
      double d = 1 / (pr * pr + pi * pi);
      l_r[l] = w->lr[k * L + l] = (qr * pr + qi * pi) * d;
      l_i[l] = w->li[k * L + l] = (qi * pr - qr * pi) * d;
    }
    for (int j = k + 1; j < n; j++) {
      double hj = hk1[j];
#pragma omp simd
      for (int l = 0; l < L; l++) {
        double ar = rk[j * L + l], ai = ik[j * L + l];
        double br = j == k + 1 ? hj - mr[l] : hj, bi = j == k + 1 ? -mi[l] : zero;
        double tr = sw[l] ? br : ar, ti = sw[l] ? bi : ai, qr = sw[l] ? ar : br,
               qi = sw[l] ? ai : bi;
        rk[j * L + l] = tr;
        ik[j * L + l] = ti;
        rk1[j * L + l] = qr - (l_r[l] * tr - l_i[l] * ti);
        ik1[j * L + l] = qi - (l_r[l] * ti + l_i[l] * tr);
      }
    }
  }
  for (int l = 0; l < L; l++)
    if (ur[(n * n - 1) * L + l] == 0 && ui[(n * n - 1) * L + l] == 0)
      ur[(n * n - 1) * L + l] = eps3;
  for (int i = 0; i < n; i++)
#pragma omp simd
    for (int l = 0; l < L; l++) {
      double a = ur[(i * n + i) * L + l], b = ui[(i * n + i) * L + l], d = 1 / (a * a + b * b);
      w->dr[i * L + l] = a * d;
      w->di[i * L + l] = -b * d;
    }
}

/* U y = y in place; (dr, di) = 1 / diag(U), so that no division sits in the
 * recurrence. The 8 lanes go as two vectors of four, each loaded once: left
 * to itself, GCC folds every load into both of its products, twice the load
 * traffic, which bounds the loop. BACK_LOAD(h) declares step j's a, b (U's
 * row i) and c, d (y) of lanes 4h..4h + 3. */
#define BACK_LOAD(h)                                                                               \
  v4d a##h, b##h, c##h, d##h;                                                                      \
  memcpy(&a##h, ri + j * L + 4 * (h), sizeof a##h);                                                \
  memcpy(&b##h, ii + j * L + 4 * (h), sizeof b##h);                                                \
  memcpy(&c##h, yr + j * L + 4 * (h), sizeof c##h);                                                \
  memcpy(&d##h, yi + j * L + 4 * (h), sizeof d##h)
#define BACK_ROW(h)                                                                                \
  do {                                                                                             \
    v4d dr_, di_, o_;                                                                              \
    memcpy(&dr_, w->dr + i * L + 4 * (h), sizeof dr_);                                             \
    memcpy(&di_, w->di + i * L + 4 * (h), sizeof di_);                                             \
    o_ = sr##h * dr_ - si##h * di_;                                                                \
    memcpy(yr + i * L + 4 * (h), &o_, sizeof o_);                                                  \
    o_ = sr##h * di_ + si##h * dr_;                                                                \
    memcpy(yi + i * L + 4 * (h), &o_, sizeof o_);                                                  \
  } while (0)
RR_INLINE void back_subst(int n, const lanes *w)
{
  double *yr = w->yr, *yi = w->yi;
  for (int i = n - 1; i >= 0; i--) {
    const double *ri = w->ur + i * n * L, *ii = w->ui + i * n * L;
    v4d sr0, sr1, si0, si1;
    memcpy(&sr0, yr + i * L, sizeof sr0);
    memcpy(&sr1, yr + i * L + 4, sizeof sr1);
    memcpy(&si0, yi + i * L, sizeof si0);
    memcpy(&si1, yi + i * L + 4, sizeof si1);
    for (int j = i + 1; j < n; j++) {
      BACK_LOAD(0);
      BACK_LOAD(1);
      LOADS_DONE();
      sr0 += b0 * d0 - a0 * c0;
      sr1 += b1 * d1 - a1 * c1;
      si0 -= a0 * d0 + b0 * c0;
      si1 -= a1 * d1 + b1 * c1;
    }
    BACK_ROW(0);
    BACK_ROW(1);
  }
}
#undef BACK_LOAD
#undef BACK_ROW

/* L^-1 P y in place: the LU's interchanges and multipliers. */
RR_INLINE void forward_subst(int n, const lanes *w)
{
  double *yr = w->yr, *yi = w->yi;
  for (int k = 0; k < n - 1; k++)
#pragma omp simd
    for (int l = 0; l < L; l++) {
      int s = w->sw[k * L + l];
      double a = yr[k * L + l], b = yr[(k + 1) * L + l], c = yi[k * L + l], d = yi[(k + 1) * L + l];
      double r0 = s ? b : a, r1 = s ? a : b, i0 = s ? d : c, i1 = s ? c : d;
      double lr = w->lr[k * L + l], li = w->li[k * L + l];
      yr[k * L + l] = r0;
      yi[k * L + l] = i0;
      yr[(k + 1) * L + l] = r1 - (lr * r0 - li * i0);
      yi[(k + 1) * L + l] = i1 - (lr * i0 + li * r0);
    }
}

/* Scales each lane of y to largest component 1 (1-norm of each component,
 * the first such component where several are largest); a lane of zeros is
 * left as it is. */
RR_INLINE void normalise(int n, double *yr, double *yi)
{
  double b[L], sr[L], si[L];
  int big[L];
  for (int l = 0; l < L; l++) {
    b[l] = 0;
    big[l] = 0;
  }
  for (int i = 0; i < n; i++)
#pragma omp simd
    for (int l = 0; l < L; l++) {
      double t = fabs(yr[i * L + l]) + fabs(yi[i * L + l]);
      big[l] = t > b[l] ? i : big[l];
      b[l] = t > b[l] ? t : b[l];
    }
  for (int l = 0; l < L; l++) {
    double br = yr[big[l] * L + l], bi = yi[big[l] * L + l], d = 1 / (br * br + bi * bi);
    sr[l] = br * d;
    si[l] = -bi * d;
  }
  for (int i = 0; i < n; i++)
#pragma omp simd
    for (int l = 0; l < L; l++) {
      double r = yr[i * L + l] * sr[l] - yi[i * L + l] * si[l],
             m = yr[i * L + l] * si[l] + yi[i * L + l] * sr[l];
      yr[i * L + l] = b[l] != 0 ? r : yr[i * L + l];
      yi[i * L + l] = b[l] != 0 ? m : yi[i * L + l];
    }
  for (int l = 0; l < L; l++)
    if (b[l] != 0) {
      yr[big[l] * L + l] = 1;
      yi[big[l] * L + l] = 0;
    }
}

/* x = D P_1 L_1 ... P_{n-2} L_{n-2} y for every lane: elmhes' and balance's
   transformations undone (EISPACK's elmbak), then scaled to largest
   component 1. */
RR_INLINE void back_transform(int n, const double *a, const int *perm, const double *dsc,
                              const lanes *w)
{
  double *yr = w->yr, *yi = w->yi;
  for (int m = n - 2; m >= 1; m--) {
    for (int i = m + 1; i < n; i++) {
      double mult = a[i * n + m - 1];
#pragma omp simd
      for (int l = 0; l < L; l++) {
        yr[i * L + l] += mult * yr[m * L + l];
        yi[i * L + l] += mult * yi[m * L + l];
      }
    }
    int p = perm[m];
    if (p != m)
      for (int l = 0; l < L; l++) {
        double t = yr[p * L + l];
        yr[p * L + l] = yr[m * L + l];
        yr[m * L + l] = t;
        t = yi[p * L + l];
        yi[p * L + l] = yi[m * L + l];
        yi[m * L + l] = t;
      }
  }
  for (int i = 0; i < n; i++)
    for (int l = 0; l < L; l++) {
      yr[i * L + l] *= dsc[i];
      yi[i * L + l] *= dsc[i];
    }
  normalise(n, yr, yi);
}

/* The eigenvectors of up to L shifts (mr, mi) of the Hessenberg matrix a by
   inverse iteration from the vector of ones taken as L^-1 P v (dlaein's
   start): U alone, then one full step. One step leaves residuals of
   n eps |H| and FRF errors near 1e-11; the second brings them to 1e-13. */
RR_INLINE void inverse_iteration(int n, const double *a, const int *perm, const double *dsc,
                                 const double *mr, const double *mi, double eps3, const lanes *w)
{
  hess_lu(n, a, mr, mi, eps3, w);
  for (int i = 0; i < n * L; i++) {
    w->yr[i] = 1;
    w->yi[i] = 0;
  }
  back_subst(n, w);
  normalise(n, w->yr, w->yi);
  forward_subst(n, w);
  back_subst(n, w);
  back_transform(n, a, perm, dsc, w);
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
          c += fabs(a[(size_t)j * (size_t)n + (size_t)i]);
          r += fabs(a[(size_t)i * (size_t)n + (size_t)j]);
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
        for (int j = 0; j < n; j++) a[(size_t)i * (size_t)n + (size_t)j] /= f;
        for (int j = 0; j < n; j++) a[(size_t)j * (size_t)n + (size_t)i] *= f;
      }
    }
  }
}

#if RR_HAVE_V4
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
RR_CLONES
#endif
int rr_eigdec(int n, double *a, double *wr, double *wi, double *vr, double *work,
                        int *iwork)
{
  if (n > 64 || n < 1) return -1;
  int *perm = iwork, *col = iwork + n;
  double *h = work, *dsc = h + n * n;
  lanes w = {.ur = dsc + n, .sw = col + n};
  w.ui = w.ur + n * n * L;
  w.yr = w.ui + n * n * L;
  w.yi = w.yr + n * L;
  w.lr = w.yi + n * L;
  w.li = w.lr + n * L;
  w.dr = w.li + n * L;
  w.di = w.dr + n * L;
  balance(n, a, dsc);
  rr_elmhes(n, a, perm);
  memcpy(h, a, sizeof(double) * (size_t)n * (size_t)n);
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
  /* the shifts: one per real eigenvalue and pair; an eigenvalue equal to an
     earlier one gets a nearby shift, so that the two vectors differ (LAPACK's
     dhsein does the same) */
  int ns = 0;
  double *mr = h, *mi = h + n; /* h is free again */
  for (int j = 0; j < n; j++) {
    if (wi[j] < 0) continue; /* the conjugate of column j - 1 */
    double r = wr[j], im = wi[j];
    for (int i = 0; i < j; i++)
      if (wi[i] >= 0 && fabs(wr[i] - r) + fabs(wi[i] - im) < eps3) {
        r += eps3;
        i = -1;
      }
    col[ns] = j;
    mr[ns] = r;
    mi[ns++] = im;
  }
  for (int g = 0; g < ns; g += L) {
    double gr[L], gi[L]; /* a short last group repeats its last shift */
    for (int l = 0; l < L; l++) {
      gr[l] = mr[g + l < ns ? g + l : ns - 1];
      gi[l] = mi[g + l < ns ? g + l : ns - 1];
    }
    inverse_iteration(n, a, perm, dsc, gr, gi, eps3, &w);
    for (int l = 0; l < L && g + l < ns; l++) {
      int j = col[g + l];
      double *c0 = vr + (size_t)j * (size_t)n;
      for (int i = 0; i < n; i++) c0[i] = w.yr[i * L + l];
      if (wi[j] > 0)
        for (int i = 0; i < n; i++) c0[n + i] = w.yi[i * L + l];
    }
  }
  return 0;
}
