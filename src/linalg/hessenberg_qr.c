/* Eigenvalues of small dense matrices: elmhes + hqr (see hessenberg_qr.h). */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "linalg/hessenberg_qr.h"
#include "util/internal.h"

#define A(i, j) a[(i)*n + (j)]
/* inline, unlike fmax/fmin (no NaN can reach them here) */
#define MAX(a, b) ((a) > (b) ? (a) : (b))
#define MIN(a, b) ((a) < (b) ? (a) : (b))

/* four doubles as one vector (GCC's and Clang's vector extension); passed
   by pointer, never as an argument or result, which would change the ABI
   between the clones */
typedef double v4d __attribute__((vector_size(32)));
typedef long long v4l __attribute__((vector_size(32)));

/* The rows r0..r3 (v4d lvalues) of a 4 x 4 block become its columns: a
   macro, so that they stay in registers. */
#define TRANSPOSE4(r0, r1, r2, r3)                                                                 \
  do {                                                                                             \
    v4d t0_ = __builtin_shufflevector(r0, r1, 0, 4, 2, 6),                                         \
        t1_ = __builtin_shufflevector(r0, r1, 1, 5, 3, 7),                                         \
        t2_ = __builtin_shufflevector(r2, r3, 0, 4, 2, 6),                                         \
        t3_ = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);                                         \
    r0 = __builtin_shufflevector(t0_, t2_, 0, 1, 4, 5);                                            \
    r1 = __builtin_shufflevector(t1_, t3_, 0, 1, 4, 5);                                            \
    r2 = __builtin_shufflevector(t0_, t2_, 2, 3, 6, 7);                                            \
    r3 = __builtin_shufflevector(t1_, t3_, 2, 3, 6, 7);                                            \
  } while (0)

/* DOT4 of rows j..j + 3 at once, each row's four partial sums one vector
 * (y's entries loaded once for the four), then transposed so that the
 * four results are summed as DOT4 sums them: bit for bit the same. The
 * results are added to column c. */
static inline __attribute__((always_inline)) void dot4_rows(double *a, int n, int j,
                                                            const double *y, int i0, int c)
{
  v4d acc[4] = {{0}};
  int i = i0;
  for (; i + 3 < n; i += 4) {
    v4d yv;
    memcpy(&yv, y + i, sizeof yv);
    for (int e = 0; e < 4; e++) {
      v4d rv;
      memcpy(&rv, &A(j + e, i), sizeof rv);
      acc[e] += rv * yv;
    }
  }
  for (; i < n; i++)
    for (int e = 0; e < 4; e++) acc[e][0] += A(j + e, i) * y[i];
  TRANSPOSE4(acc[0], acc[1], acc[2], acc[3]);
  v4d d = (acc[0] + acc[1]) + (acc[2] + acc[3]);
  for (int e = 0; e < 4; e++) A(j + e, c) += d[e];
}

/* Reduction to upper Hessenberg form by stabilised elementary similarity
 * transformations (Gaussian elimination with row interchanges). The step's
 * elementary transforms L_i = I + y_i e_i e_m' commute, so it is applied as
 * L^-1 A L in two contiguous passes: every row elimination first, then
 * column m += A y as one dot product per row (row-major friendly). */
static inline __attribute__((always_inline)) void elmhes(int n, double *a, int *perm)
{
  double y[64];
  for (int m = 1; m < n - 1; m++) {
    double x = 0;
    int piv = m;
    for (int j = m; j < n; j++)
      if (fabs(A(j, m - 1)) > fabs(x)) {
        x = A(j, m - 1);
        piv = j;
      }
    if (perm) perm[m] = piv;
    if (piv != m) {
      for (int j = m - 1; j < n; j++) {
        double t = A(piv, j);
        A(piv, j) = A(m, j);
        A(m, j) = t;
      }
      for (int i = 0; i < n; i++) {
        double t = A(i, piv);
        A(i, piv) = A(i, m);
        A(i, m) = t;
      }
    }
    if (x == 0) continue;
    const double *rm = &A(m, 0);
    int any = 0;
    for (int i = m + 1; i < n; i++) {
      double yi = A(i, m - 1) / x;
      y[i] = yi;
      A(i, m - 1) = perm ? yi : 0; /* kept for the back-transformation */
      if (yi == 0) continue;
      any = 1;
      double *ri = &A(i, 0);
      for (int j = m; j < n; j++) ri[j] -= yi * rm[j];
    }
    if (!any) continue;
    int j = 0;
    for (; j + 3 < n; j += 4) dot4_rows(a, n, j, y, m + 1, m);
    for (; j < n; j++) {
      double d;
      DOT4(double, &A(j, 0), y, m + 1, n, d);
      A(j, m) += d;
    }
  }
}

static double sgn(double a, double b) { return b >= 0 ? fabs(a) : -fabs(a); }

/* ---- Francis double-shift QR, eigenvalues only ----
 * The control (deflation, roots, shifts, where a sweep starts) runs per
 * matrix ("lane"), on a strided view: entry (i, j) at a[(i ld + j) st]. The
 * bulge-chasing sweep, where the time goes, exists twice: for one matrix,
 * and for 4 or 8 matrices at once in SIMD lanes (rr_eig_batch, hessenberg_qr_lanes.h). */
#define E(i, j) a[((size_t)(i) * (size_t)ld + (size_t)(j)) * (size_t)st]

typedef struct {
  int nn, l, m, its, status; /* status: 0 sweep pending, 1 done, -1 no convergence */
  double t, anorm, p, q, r;
} qr_lane;

/* A fresh lane for the Hessenberg matrix of order n whose entries' absolute
 * sum (row by row, from the subdiagonal on) is anorm. */
static void lane_init(int n, double anorm, qr_lane *L)
{
  L->nn = n - 1;
  L->its = 0;
  L->t = 0;
  L->anorm = anorm;
  L->status = 0;
}

/* The row l at which the active block nn splits off: the lowest l with a
 * negligible subdiagonal E(l, l-1) (set to zero), by the deflation test of
 * Ahues & Tisseur (LAPACK Working Note 122), as in LAPACK's dlahqr: small
 * relative to the 2 x 2 block it couples. cand: bit l set where row l may
 * pass; the lanes compute the test's first two steps (h <= DBL_MIN or
 * h <= eps s) for every lane at once (split_candidates), so that only those
 * rows are read here, highest first; the single matrix passes every bit. */
static inline __attribute__((always_inline)) int split_row(double *a, int ld, int st, int nn,
                                                           double anorm, unsigned long long cand)
{
  /* rows 1..nn (n <= 64, so nn <= 63) */
  unsigned long long rows = cand & (nn >= 63 ? ~0ULL : (2ULL << nn) - 1) & ~1ULL;
  while (rows) {
    int l = 63 - __builtin_clzll(rows);
    rows &= ~(1ULL << l);
    double h = fabs(E(l, l - 1)), s;
    if (h <= DBL_MIN) {
      E(l, l - 1) = 0;
      return l;
    }
    s = fabs(E(l - 1, l - 1)) + fabs(E(l, l));
    if (s == 0) s = anorm;
    if (h <= DBL_EPSILON * s) {
      double hu = fabs(E(l - 1, l)), ab = MAX(h, hu), ba = MIN(h, hu);
      double dd = fabs(E(l - 1, l - 1) - E(l, l)), aa = MAX(fabs(E(l, l)), dd),
             bb = MIN(fabs(E(l, l)), dd);
      double ss = aa + ab;
      if (ba * (ab / ss) <= MAX(DBL_MIN, DBL_EPSILON * (bb * (aa / ss)))) {
        E(l, l - 1) = 0;
        return l;
      }
    }
  }
  return 0;
}

/* The two roots of the trailing 2 x 2 block (rows nn - 1, nn) into wr, wi. */
static inline __attribute__((always_inline)) void two_roots(double x, double y, double w, double t,
                                                            int nn, double *wr, double *wi)
{
  double p = 0.5 * (y - x), q = p * p + w, z = sqrt(fabs(q));
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
}

/* Where the double-shift sweep starts (row m, l <= m <= nn - 2) and its first
 * column (p, q, r), scaled to unit 1-norm into L: two small consecutive
 * subdiagonals let it start above l. The column is formed times h(m+1, m),
 * the test being scale-free: no division per row. */
static inline __attribute__((always_inline)) void sweep_start(double *a, int ld, int st, int l,
                                                              int nn, double x, double y, double w,
                                                              int clear, qr_lane *L)
{
  int m;
  double p = 0, q = 0, r = 0, s, z;
  for (m = nn - 2; m >= l; m--) {
    z = E(m, m);
    r = x - z;
    s = y - z;
    double h21 = E(m + 1, m);
    p = (r * s - w) + E(m, m + 1) * h21;
    q = (E(m + 1, m + 1) - z - r - s) * h21;
    r = E(m + 2, m + 1) * h21;
    if (m == l) break;
    double u = fabs(E(m, m - 1)) * (fabs(q) + fabs(r));
    double v = fabs(p) * (fabs(E(m - 1, m - 1)) + fabs(z) + fabs(E(m + 1, m + 1)));
    if (u + v == v) break;
  }
  s = 1 / (fabs(p) + fabs(q) + fabs(r));
  /* the previous sweep's bulge entries below the subdiagonal, unless that
     sweep cleared them as it went (the lanes' sweep does) */
  for (int i = m + 2; clear && i <= nn; i++) {
    E(i, i - 2) = 0;
    if (i != m + 2) E(i, i - 3) = 0;
  }
  L->nn = nn;
  L->l = l;
  L->m = m;
  L->p = p * s;
  L->q = q * s;
  L->r = r * s;
}

/* Takes the roots that have converged at the bottom of the active block and
 * prepares the next double-shift sweep: rows l..nn, starting at row m with
 * first column (p, q, r). Sets status 1 when every root is found. With xyw,
 * the sweep's block and its shifts (x, y, w) only, into L and xyw[0..2]:
 * the lanes find every lane's start at once (sweep_start_lanes). */
static inline __attribute__((always_inline)) void lane_advance(double *a, int n, int ld, int st,
                                                               qr_lane *L, double *wr, double *wi,
                                                               int clear, unsigned long long cand,
                                                               double *xyw)
{
  int nn = L->nn;
  while (nn >= 0) {
    int l = split_row(a, ld, st, nn, L->anorm, cand);
    double x = E(nn, nn);
    if (l == nn) { /* one root */
      wr[nn] = x + L->t;
      wi[nn--] = 0;
      L->its = 0;
      continue;
    }
    double y = E(nn - 1, nn - 1), w = E(nn, nn - 1) * E(nn - 1, nn);
    if (l == nn - 1) { /* two roots */
      two_roots(x, y, w, L->t, nn, wr, wi);
      nn -= 2;
      L->its = 0;
      continue;
    }
    /* no root yet: a double QR step */
    if (L->its == 30 * (n > 10 ? n : 10)) { /* LAPACK's limit */
      L->status = -1;
      L->nn = nn;
      return;
    }
    if (L->its > 0 && L->its % 10 == 0) { /* exceptional shift */
      L->t += x;
      for (int i = 0; i <= nn; i++) E(i, i) -= x;
      double s = fabs(E(nn, nn - 1)) + fabs(E(nn - 1, nn - 2));
      y = x = 0.75 * s;
      w = -0.4375 * s * s;
    }
    ++L->its;
    if (!xyw) {
      sweep_start(a, ld, st, l, nn, x, y, w, clear, L);
      return;
    }
    L->nn = nn;
    L->l = l;
    xyw[0] = x;
    xyw[1] = y;
    xyw[2] = w;
    return;
  }
  L->nn = nn;
  L->status = 1;
}
#undef E

/* ---- the single sweep's rows above the bulge, four at a time ----
 * Step k's column update reaches rows l..k + 3, strided in row-major
 * storage. Rows l..k, above the bulge, are read by nothing else for the
 * rest of the sweep, so they are kept transposed in blocks of four rows
 * (t[c][b]: column c of rows l + 4b..l + 4b + 3), where a step updates a
 * block's column with one vector operation instead of four scalar ones. A
 * block enters once its last row has had the sweep's last row update
 * (step l + 4b + 3, or m if that is later); until then its rows are
 * updated one by one like the rows below. Every entry gets the same
 * operations in the same order: the eigenvalues do not change by a bit. */
typedef struct {
  v4d t[64][16];
  int nb; /* blocks entered */
} above_rows;

static inline __attribute__((always_inline)) int block_entry(int l, int m, int b)
{
  return l + 4 * b + 3 > m ? l + 4 * b + 3 : m;
}

/* Columns c..c + 3 of rows i0..i0 + 3 into t[c..c + 3][b], and back. */
static inline __attribute__((always_inline)) void block_in(const double *a, int n, int i0, int c,
                                                           int b, above_rows *u)
{
  v4d r0, r1, r2, r3;
  memcpy(&r0, &A(i0, c), sizeof r0);
  memcpy(&r1, &A(i0 + 1, c), sizeof r1);
  memcpy(&r2, &A(i0 + 2, c), sizeof r2);
  memcpy(&r3, &A(i0 + 3, c), sizeof r3);
  TRANSPOSE4(r0, r1, r2, r3);
  u->t[c][b] = r0;
  u->t[c + 1][b] = r1;
  u->t[c + 2][b] = r2;
  u->t[c + 3][b] = r3;
}

static inline __attribute__((always_inline)) void block_out(double *a, int n, int i0, int c, int b,
                                                            const above_rows *u)
{
  v4d r0 = u->t[c][b], r1 = u->t[c + 1][b], r2 = u->t[c + 2][b], r3 = u->t[c + 3][b];
  TRANSPOSE4(r0, r1, r2, r3);
  memcpy(&A(i0, c), &r0, sizeof r0);
  memcpy(&A(i0 + 1, c), &r1, sizeof r1);
  memcpy(&A(i0 + 2, c), &r2, sizeof r2);
  memcpy(&A(i0 + 3, c), &r3, sizeof r3);
}

/* At step k, after its row updates: the blocks due by then enter, columns
   k..nn (the ones later column updates reach). */
static inline __attribute__((always_inline)) void above_enter(const double *a, int n, int l, int m,
                                                              int k, int nn, above_rows *u)
{
  for (int b = u->nb; b < 16 && block_entry(l, m, b) <= k && l + 4 * b + 3 <= nn - 1; b = ++u->nb) {
    int i0 = l + 4 * b, c = k;
    for (; c + 3 <= nn; c += 4) block_in(a, n, i0, c, b, u);
    for (; c <= nn; c++) /* as one vector: read back whole, it forwards */
      u->t[c][b] = (v4d){A(i0, c), A(i0 + 1, c), A(i0 + 2, c), A(i0 + 3, c)};
  }
}

/* Step k's column update of every block (x, y, z, q, r: its reflector). */
static inline __attribute__((always_inline)) void
above_update(above_rows *u, int k, int nn, double x, double y, double z, double q, double r)
{
  int last = k == nn - 1; /* a 2-row reflector */
  v4d *t0 = u->t[k], *t1 = u->t[k + 1], *t2 = u->t[k + (last ? 1 : 2)];
  for (int b = 0; b < u->nb; b++) {
    v4d a0 = t0[b], a1 = t1[b], a2 = t2[b], pp = x * a0 + y * a1;
    if (!last) {
      pp = pp + z * a2;
      t2[b] = a2 - pp * r;
    }
    t1[b] = a1 - pp * q;
    t0[b] = a0 - pp;
  }
}

/* The sweep done: the blocks back into their rows. */
static inline __attribute__((always_inline)) void above_leave(double *a, int n, int l, int m,
                                                              int nn, const above_rows *u)
{
  for (int b = 0; b < u->nb; b++) {
    int i0 = l + 4 * b, c = block_entry(l, m, b);
    for (; c + 3 <= nn; c += 4) block_out(a, n, i0, c, b, u);
    for (; c <= nn; c++)
      for (int j = 0; j < 4; j++) A(i0 + j, c) = u->t[c][b][j];
  }
}

/* Step k's column update of row ri (entries k..k + 2); returns entry k. */
static inline __attribute__((always_inline)) double
column_row(double *ri, int k, int nn, double x, double y, double z, double q, double r)
{
  double pp = x * ri[k] + y * ri[k + 1];
  if (k != nn - 1) {
    pp += z * ri[k + 2];
    ri[k + 2] -= pp * r;
  }
  ri[k + 1] -= pp * q;
  return ri[k] -= pp;
}

/* One sweep on one matrix (row-major, order n): rows and columns of the
 * active block only. */
static inline __attribute__((always_inline)) void sweep1(double *a, int n, const qr_lane *L)
{
  int l = L->l, m = L->m, nn = L->nn;
  double p = L->p, q = L->q, r = L->r, s, x, y, z;
  above_rows u __attribute__((aligned(32)));
  u.nb = 0;
  /* column k - 1 below the diagonal as step k - 1 left it, passed in
     registers rather than reloaded (fwd: that step was not skipped) */
  double f0 = 0, f1 = 0, f2 = 0;
  int fwd = 0;
  for (int k = m; k <= nn - 1; k++) {
    x = 1;
    if (k != m) {
      p = fwd ? f0 : A(k, k - 1);
      q = fwd ? f1 : A(k + 1, k - 1);
      r = k != nn - 1 ? (fwd ? f2 : A(k + 2, k - 1)) : 0;
      x = fabs(p) + fabs(q) + fabs(r);
      /* scaled only where p^2 + q^2 + r^2 could under- or overflow */
      if (x != 0 && (x < 1e-100 || x > 1e100)) {
        double ix = 1 / x;
        p *= ix;
        q *= ix;
        r *= ix;
      } else
        x = 1;
    }
    if ((s = sgn(sqrt(p * p + q * q + r * r), p)) == 0) {
      above_enter(a, n, l, m, k, nn, &u);
      fwd = 0;
      continue;
    }
    if (k == m) {
      if (l != m) A(k, k - 1) = -A(k, k - 1);
    } else {
      A(k, k - 1) = -s * x;
    }
    /* reciprocals of s and p + s side by side: fewer divisions on the
       sweep's critical path */
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
    /* the blocks above the bulge, then the rows not in one (measured
       faster than the rows the next step reads first) */
    above_enter(a, n, l, m, k, nn, &u);
    above_update(&u, k, nn, x, y, z, q, r);
    for (int i = l + 4 * u.nb; i <= k; i++) column_row(&A(i, 0), k, nn, x, y, z, q, r);
    f0 = column_row(&A(k + 1, 0), k, nn, x, y, z, q, r);
    if (k + 2 <= nn) f1 = column_row(&A(k + 2, 0), k, nn, x, y, z, q, r);
    if (k + 3 <= nn) f2 = column_row(&A(k + 3, 0), k, nn, x, y, z, q, r);
    fwd = 1;
  }
  above_leave(a, n, l, m, nn, &u);
}

RR_CLONES int rr_hqr(int n, double *a, double *wr, double *wi)
{
  qr_lane L;
  double anorm = 0;
  for (int i = 0; i < n; i++)
    for (int j = i > 0 ? i - 1 : 0; j < n; j++) anorm += fabs(a[i * n + j]);
  lane_init(n, anorm, &L);
  for (;;) {
    lane_advance(a, n, n, 1, &L, wr, wi, 1, ~0ULL, NULL);
    if (L.status) return L.status < 0 ? -1 : 0;
    sweep1(a, n, &L);
  }
}

/* ---- several matrices at once in SIMD lanes (hessenberg_qr_lanes.h) ---- */
#define QRW 4
#include "linalg/hessenberg_qr_lanes.h"
#undef QRW
#if RR_HAVE_V4
#define QRW 8
#include "linalg/hessenberg_qr_lanes.h"
#undef QRW
#endif

RR_CLONES static int eig_batch4(int n, int nb, const double *const *mats, double *wr, double *wi,
                                double *work, int *fail)
{
  return eig_lanes4(n, nb, mats, wr, wi, work, fail);
}

#if RR_HAVE_V4
__attribute__((target("arch=x86-64-v4"))) static int eig_batch8(int n, int nb,
                                                                const double *const *mats,
                                                                double *wr, double *wi,
                                                                double *work, int *fail)
{
  return eig_lanes8(n, nb, mats, wr, wi, work, fail);
}
#endif

int rr_eig_batch_lanes(void)
{
#if RR_HAVE_V4
  __builtin_cpu_init();
  return __builtin_cpu_supports("x86-64-v4") ? 8 : 4;
#else
  return 4;
#endif
}

size_t rr_eig_batch_work(int n)
{
  return (size_t)(n + 1) * (size_t)(n + 1) * RR_QR_LANES_MAX + RR_QR_LANES_MAX;
}

int rr_eig_batch(int n, int nb, int lanes, const double *const *mats, double *wr, double *wi,
                 double *work, int *fail)
{
  if (n > 64 || n < 1 || nb < 1 || nb > RR_QR_LANES_MAX) return -1;
  if (lanes <= 0 || lanes > rr_eig_batch_lanes()) lanes = rr_eig_batch_lanes();
#if RR_HAVE_V4
  if (lanes == 8 && nb > 4) return eig_batch8(n, nb, mats, wr, wi, work, fail);
#endif
  int bad = 0;
  for (int c = 0; c < nb; c += 4) {
    int k = nb - c < 4 ? nb - c : 4;
    bad |= eig_batch4(n, k, mats + c, wr + (size_t)c * (size_t)n, wi + (size_t)c * (size_t)n, work,
                      fail + c);
  }
  return bad;
}

RR_CLONES int rr_eig_small(int n, double *a, double *wr, double *wi)
{
  if (n > 64) return -1; /* elmhes' multiplier buffer; larger goes to LAPACK */
  elmhes(n, a, NULL);
  return rr_hqr(n, a, wr, wi);
}

RR_CLONES void rr_elmhes(int n, double *a, int *perm) { elmhes(n, a, perm); }
