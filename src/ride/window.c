/* The 5 s RMS of a stationary Gaussian response and EN 12299's mean comfort
 * (docs/vertical.md, "5 s RMS" and "EN 12299"). The window mean square m of
 * a process with one-sided PSD S has E m = integral S and, on the grid's
 * lines u_i = w_i S(f_i), Var m = sum_ij u_i u_j K_ij with
 * K_ij = sinc^2((f_i - f_j) T) + sinc^2((f_i + f_j) T) (Isserlis); m is
 * taken as gamma-distributed with that mean and variance (Satterthwaite,
 * Welch), and the RMS's percentiles are the square roots of m's. */
#define _DEFAULT_SOURCE /* lgamma_r */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/comfort.h"
#include "internal.h"

#define WINDOW_COLS_MAX 64

#define WINDOW_ALIGN 8 /* doubles: rows start on 64-byte lines */

/* The kernel above its diagonal, by pairs of rows (i, i + 1), i even: each
   pair's block holds both rows from the aligned column j0 = i rounded down
   to WINDOW_ALIGN (zeros at and below the diagonal), row i then row i + 1,
   each ld - j0 long; the blocks follow each other, so that a pass over the
   kernel is one sequential stream (what the prefetchers follow best). */
struct rr_window_plan {
  int n, ld, maxcols; /* ld: n rounded up to WINDOW_ALIGN */
  double *w;          /* trapezoid weights */
  double *pairs;      /* the blocks, aligned */
  size_t *at;         /* each pair's block's start in pairs */
  double *diag;       /* the kernel's diagonal */
  double *u;          /* maxcols x ld workspace, aligned */
  double *zero;       /* ld zeros: the unused columns of a pass */
};

static int pair_j0(int i) { return i / WINDOW_ALIGN * WINDOW_ALIGN; }

/* An aligned, zeroed block of n doubles (n a multiple of WINDOW_ALIGN). */
static double *aligned_zeros(size_t n)
{
  double *a = aligned_alloc(WINDOW_ALIGN * sizeof(double), n * sizeof(double));
  if (a) memset(a, 0, n * sizeof(double));
  return a;
}

static double sinc2(double x)
{
  if (x == 0) return 1;
  double s = sin(RR_PI * x) / (RR_PI * x);
  return s * s;
}

void rr_window_plan_free(rr_window_plan *p)
{
  if (!p) return;
  free(p->w);
  free(p->pairs);
  free(p->at);
  free(p->diag);
  free(p->u);
  free(p->zero);
  free(p);
}

int rr_window_plan_new(const double *f, int n, double T, int maxcols, rr_window_plan **out,
                       rr_error *err)
{
  *out = NULL;
  if (n < 2 || n > 20000 || maxcols < 1 || maxcols > WINDOW_COLS_MAX || !(T > 0 && T < 1e6))
    return rr_seterr(err, RR_EINVAL,
                     "window: need 2 .. 20000 frequencies, a window > 0 s and 1 .. %d columns",
                     WINDOW_COLS_MAX);
  for (int i = 1; i < n; i++)
    if (!(f[i] > f[i - 1] && f[i - 1] >= 0))
      return rr_seterr(err, RR_EINVAL, "window: frequencies must be >= 0 and increase");
  rr_window_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  size_t nn = (size_t)n, ld = (nn + WINDOW_ALIGN - 1) / WINDOW_ALIGN * WINDOW_ALIGN;
  p->n = n;
  p->ld = (int)ld;
  p->maxcols = maxcols;
  size_t npairs = (nn + 1) / 2, total = 0;
  p->at = malloc(sizeof(size_t) * npairs);
  for (size_t q = 0; p->at && q < npairs; q++) {
    p->at[q] = total;
    total += 2 * (ld - (size_t)pair_j0((int)(2 * q)));
  }
  p->w = malloc(sizeof(double) * nn);
  p->diag = malloc(sizeof(double) * nn);
  p->pairs = p->at ? aligned_zeros(total) : NULL;
  p->u = aligned_zeros(ld * (size_t)maxcols);
  p->zero = aligned_zeros(ld);
  if (!p->w || !p->diag || !p->pairs || !p->at || !p->u || !p->zero) {
    rr_window_plan_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int i = 0; i < n; i++)
    p->w[i] = 0.5 * ((i + 1 < n ? f[i + 1] : f[i]) - (i > 0 ? f[i - 1] : f[i]));
  for (int i = 0; i < n; i++) {
    int j0 = pair_j0(i - i % 2);
    double *row = p->pairs + p->at[i / 2] + (size_t)(i % 2) * (ld - (size_t)j0) - (size_t)j0;
    p->diag[i] = 1 + sinc2(2 * f[i] * T);
    for (int j = i + 1; j < n; j++) row[j] = sinc2((f[i] - f[j]) * T) + sinc2((f[i] + f[j]) * T);
  }
  *out = p;
  return RR_OK;
}

#define QF_COLS 3 /* columns per pass: the usual three floor points */

/* sum_ij u_i u_j K_ij of 3 columns u[0..2] (unused ones: the zero row):
   sum_i u_i (K_ii u_i + 2 sum_{j>i} K_ij u_j), two kernel rows at a time so
   that each pair is read once for all three columns, from the aligned line
   at or below the diagonal (the zeros below it count nothing). Fused
   multiply-adds in every copy (the default one's from libm), so that every
   processor gets the same bits. */
RR_CLONES_V4 static void quadratic_forms3(const rr_window_plan *p, const double *const u[QF_COLS],
                                          double V[QF_COLS])
{
  int n = p->n, ld = p->ld, i = 0;
  const double *u0 = u[0], *u1 = u[1], *u2 = u[2];
  double v[QF_COLS] = {0, 0, 0};
  for (; i < n; i += 2) {
    int j0 = pair_j0(i), two = i + 1 < n;
    const double *k0 = p->pairs + p->at[i / 2] - j0, *k1 = k0 + (ld - j0);
    double a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;
    if (!two) k1 = p->zero;
#pragma omp simd reduction(+ : a0, a1, a2, b0, b1, b2)
    for (int j = j0; j < n; j++) {
      a0 = __builtin_fma(k0[j], u0[j], a0);
      a1 = __builtin_fma(k0[j], u1[j], a1);
      a2 = __builtin_fma(k0[j], u2[j], a2);
      b0 = __builtin_fma(k1[j], u0[j], b0);
      b1 = __builtin_fma(k1[j], u1[j], b1);
      b2 = __builtin_fma(k1[j], u2[j], b2);
    }
    double a[QF_COLS] = {a0, a1, a2}, b[QF_COLS] = {b0, b1, b2};
    for (int c = 0; c < QF_COLS; c++) {
      const double *uc = u[c];
      v[c] += uc[i] * (p->diag[i] * uc[i] + 2 * a[c]);
      if (two) v[c] += uc[i + 1] * (p->diag[i + 1] * uc[i + 1] + 2 * b[c]);
    }
  }
  for (int c = 0; c < QF_COLS; c++) V[c] = v[c];
}

static void quadratic_forms(const rr_window_plan *p, int ncols, double *V)
{
  for (int c = 0; c < ncols; c += QF_COLS) {
    const double *u[QF_COLS];
    double v[QF_COLS];
    for (int k = 0; k < QF_COLS; k++)
      u[k] = c + k < ncols ? p->u + (size_t)(c + k) * (size_t)p->ld : p->zero;
    quadratic_forms3(p, u, v);
    for (int k = 0; k < QF_COLS && c + k < ncols; k++) V[c + k] = v[k];
  }
}

static int gamma_stats(double s2, double V, rr_window_stats *o, rr_error *err)
{
  *o = (rr_window_stats){.rms = sqrt(s2)};
  if (s2 == 0) return RR_OK; /* a zero process: every percentile 0 */
  double k = s2 * s2 / V, theta = V / s2, x50, x95;
  int st = rr_gamma_p_inv(k, 0.50, &x50, err);
  if (!st) st = rr_gamma_p_inv(k, 0.95, &x95, err);
  if (st) return st;
  int sg;
  o->shape_k = k;
  o->dof = 2 * k;
  o->p50 = sqrt(theta * x50);
  o->p95 = sqrt(theta * x95);
  o->mean = sqrt(theta) * exp(lgamma_r(k + 0.5, &sg) - lgamma_r(k, &sg));
  return RR_OK;
}

int rr_window_execute(rr_window_plan *p, const double *G, int stride, int ncols, const double *W2,
                      rr_window_stats *out, rr_error *err)
{
  if (ncols < 1 || ncols > p->maxcols)
    return rr_seterr(err, RR_EINVAL, "window: %d columns, the plan has room for 1 .. %d", ncols,
                     p->maxcols);
  int n = p->n;
  double s2[WINDOW_COLS_MAX], V[WINDOW_COLS_MAX];
  for (int c = 0; c < ncols; c++) {
    double *u = p->u + (size_t)c * (size_t)p->ld, s = 0;
    for (int i = 0; i < n; i++) {
      double g = G[(size_t)i * (size_t)stride + (size_t)c];
      u[i] = p->w[i] * (W2 ? W2[i] : 1) * g;
      s += u[i];
    }
    if (!(s >= 0 && isfinite(s)))
      return rr_seterr(err, RR_EINVAL, "window: a PSD that is negative or not finite");
    s2[c] = s;
  }
  quadratic_forms(p, ncols, V);
  for (int c = 0; c < ncols; c++) {
    int st = gamma_stats(s2[c], V[c], out + c, err);
    if (st) return st;
  }
  return RR_OK;
}

/* ---- EN 12299 mean comfort (rigid seat: seat pan and back = floor) ---- */

rr_en12299 rr_en12299_indices(const rr_en12299_inputs *a)
{
  double ax95 = a->ax95, ay95 = a->ay95, az95 = a->az95;
  return (rr_en12299){
      .n_mv = 6 * sqrt(ax95 * ax95 + ay95 * ay95 + az95 * az95),
      .n_vd =
          3 * sqrt(16 * a->ax50 * a->ax50 + 4 * a->ay50 * a->ay50 + a->az50 * a->az50) + 5 * ay95,
      .n_va_rigid_seat = 4 * az95 + 2 * sqrt(ay95 * ay95 + az95 * az95) + 4 * a->axd95};
}

const char *rr_en12299_scale(double n)
{
  if (n < 1) return "very comfortable";
  if (n < 2) return "comfortable";
  if (n < 4) return "medium";
  if (n < 5) return "uncomfortable";
  return "very uncomfortable";
}
