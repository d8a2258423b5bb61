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
#include "util/internal.h"

#define WINDOW_COLS_MAX 64

#define WINDOW_ALIGN 8 /* doubles: rows start on 64-byte lines */
#define WINDOW_ROWS 8  /* kernel rows per block: each is read once for 3 columns */
#define QF_COLS 3      /* columns per pass: the usual three floor points */

/* The kernel above its diagonal, by blocks of WINDOW_ROWS rows from
   i0, a multiple of WINDOW_ROWS: a block covers the columns from
   j0 = i0 rounded down to WINDOW_ALIGN to ld (zeros at and below the diagonal
   and past n), in chunks of WINDOW_ALIGN columns, each chunk holding its
   columns of row i0, then of row i0 + 1, ...; the blocks follow each other,
   so that a pass over the kernel is one sequential stream. */
struct rr_window_plan {
  int n, ld, maxcols; /* ld: n rounded up to WINDOW_ALIGN */
  double *w;          /* trapezoid weights */
  double *rows;       /* the blocks, aligned */
  size_t *at;         /* each block's start in rows */
  double *diag;       /* the kernel's diagonal, ld long (zeros past n) */
  double *u;          /* maxcols x ld workspace, aligned */
  double *y;          /* QF_COLS x ld: the upper triangle times u */
  double *zero;       /* ld zeros: the rows and columns past the data */
};

static int block_j0(int i) { return i / WINDOW_ALIGN * WINDOW_ALIGN; }

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
  free(p->rows);
  free(p->at);
  free(p->diag);
  free(p->u);
  free(p->y);
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
  size_t nblocks = (nn + WINDOW_ROWS - 1) / WINDOW_ROWS, total = 0;
  p->at = malloc(sizeof(size_t) * nblocks);
  for (size_t b = 0; p->at && b < nblocks; b++) {
    p->at[b] = total;
    total += WINDOW_ROWS * (ld - (size_t)block_j0((int)(b * WINDOW_ROWS)));
  }
  p->w = malloc(sizeof(double) * nn);
  p->diag = aligned_zeros(ld);
  p->rows = p->at ? aligned_zeros(total) : NULL;
  p->u = aligned_zeros(ld * (size_t)maxcols);
  p->y = aligned_zeros(ld * QF_COLS);
  p->zero = aligned_zeros(ld);
  if (!p->w || !p->diag || !p->rows || !p->at || !p->u || !p->y || !p->zero) {
    rr_window_plan_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int i = 0; i < n; i++)
    p->w[i] = 0.5 * ((i + 1 < n ? f[i + 1] : f[i]) - (i > 0 ? f[i - 1] : f[i]));
  for (int i = 0; i < n; i++) {
    int j0 = block_j0(i - i % WINDOW_ROWS);
    double *blk = p->rows + p->at[i / WINDOW_ROWS];
    size_t r = (size_t)(i % WINDOW_ROWS);
    p->diag[i] = 1 + sinc2(2 * f[i] * T);
    for (int j = i + 1; j < n; j++) {
      size_t at = (size_t)(j - j0) / WINDOW_ALIGN * WINDOW_ROWS * WINDOW_ALIGN + r * WINDOW_ALIGN +
                  (size_t)(j - j0) % WINDOW_ALIGN;
      blk[at] = sinc2((f[i] - f[j]) * T) + sinc2((f[i] + f[j]) * T);
    }
  }
  *out = p;
  return RR_OK;
}

/* y_c = U u_c with U the kernel above its diagonal, for 3 columns u_c:
   each row block is read once, and each y_c[j] gathers its rows' terms in
   row order by fused multiply-adds (no reductions across lanes), so that
   every processor and vector width gets the same bits. The rows past n and
   the columns past n hold zeros and count nothing. */
RR_CLONES_V4 static void upper_times3(const rr_window_plan *p, const double *const u[QF_COLS],
                                      double *restrict y0, double *restrict y1, double *restrict y2)
{
  int n = p->n, ld = p->ld;
  for (int i = 0; i < n; i += WINDOW_ROWS) {
    int j0 = block_j0(i);
    const double *blk = p->rows + p->at[i / WINDOW_ROWS];
    double s0[WINDOW_ROWS], s1[WINDOW_ROWS], s2[WINDOW_ROWS];
    for (int r = 0; r < WINDOW_ROWS; r++) {
      int live = i + r < n;
      s0[r] = live ? u[0][i + r] : 0;
      s1[r] = live ? u[1][i + r] : 0;
      s2[r] = live ? u[2][i + r] : 0;
    }
    for (int jb = j0; jb < ld; jb += WINDOW_ALIGN) {
      const double *restrict kb = blk + (size_t)(jb - j0) * WINDOW_ROWS;
#pragma omp simd aligned(kb : 64)
      for (int l = 0; l < WINDOW_ALIGN; l++) {
        double t0 = y0[jb + l], t1 = y1[jb + l], t2 = y2[jb + l];
        for (int r = 0; r < WINDOW_ROWS; r++) {
          double kr = kb[r * WINDOW_ALIGN + l];
          t0 = __builtin_fma(kr, s0[r], t0);
          t1 = __builtin_fma(kr, s1[r], t1);
          t2 = __builtin_fma(kr, s2[r], t2);
        }
        y0[jb + l] = t0;
        y1[jb + l] = t1;
        y2[jb + l] = t2;
      }
    }
  }
}

/* sum_j u_j (K_jj u_j + 2 y_j) in WINDOW_ALIGN fixed lanes, summed in order. */
RR_CLONES_V4 static double form_sum(const double *restrict u, const double *restrict d,
                                    const double *restrict y, int ld)
{
  double lane[WINDOW_ALIGN] = {0};
  for (int j = 0; j < ld; j += WINDOW_ALIGN)
    for (int l = 0; l < WINDOW_ALIGN; l++)
      lane[l] = __builtin_fma(u[j + l], __builtin_fma(d[j + l], u[j + l], 2 * y[j + l]), lane[l]);
  double v = 0;
  for (int l = 0; l < WINDOW_ALIGN; l++) v += lane[l];
  return v;
}

/* sum_ij u_i u_j K_ij of 3 columns u[0..2] (unused ones: the zero row). */
static void quadratic_forms3(rr_window_plan *p, const double *const u[QF_COLS], double V[QF_COLS])
{
  size_t ld = (size_t)p->ld;
  double *y[QF_COLS] = {p->y, p->y + ld, p->y + 2 * ld};
  memset(p->y, 0, sizeof(double) * ld * QF_COLS);
  upper_times3(p, u, y[0], y[1], y[2]);
  for (int c = 0; c < QF_COLS; c++) V[c] = form_sum(u[c], p->diag, y[c], p->ld);
}

static void quadratic_forms(rr_window_plan *p, int ncols, double *V)
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
  if (isnan(n)) return "undefined";
  if (n < 1) return "very comfortable";
  if (n < 2) return "comfortable";
  if (n < 4) return "medium";
  if (n < 5) return "uncomfortable";
  return "very uncomfortable";
}
