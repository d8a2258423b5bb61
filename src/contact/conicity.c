#define _GNU_SOURCE /* sincos */
/* The equivalent conicity of a piecewise-linear dr(y) (docs/contact.md,
 * equivalent conicity): (a) EN 15302's reference method, the wavelength of
 * the kinematic oscillation compared with Klingel's, by an exact energy
 * integral; (b) harmonic linearisation and (c) linear regression, in closed
 * form per segment. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "contact/contact_impl.h"
#include "util/internal.h"

struct rr_conicity_plan {
  int n;           /* points of the valid run used */
  double *y, *d;   /* the run's y and dr */
  double *m;       /* segment slopes of dr (n - 1) */
  double *S;       /* the potential S(y) = int_{y0}^{y} dr at the grid points */
  double *rmR;     /* running maximum of S to the right of y0, from i0 + 1 */
  double *rmL;     /* and to the left, from i0 down (rmL[k] for k = i0 .. 0) */
  double *PL, *PR; /* scratch for one amplitude's inward sums (n each) */
  double y0;
  int i0; /* the segment holding y0 */
  double smax_right, smax_left;
};

void rr_conicity_plan_free(rr_conicity_plan *p)
{
  if (!p) return;
  free(p->y);
  free(p);
}

double rr_conicity_y0(const rr_conicity_plan *p) { return p->y0; }

void rr_conicity_range(const rr_conicity_plan *p, double *first, double *last)
{
  *first = p->n ? p->y[0] : NAN;
  *last = p->n ? p->y[p->n - 1] : NAN;
}

static int seg(const rr_conicity_plan *p, double at) { return rr_poly_segment(p->y, p->n, at); }
static double dr_at(const rr_conicity_plan *p, int j, double at)
{
  return p->d[j] + p->m[j] * (at - p->y[j]);
}

/* The equilibrium: the zero crossing (or the middle of a run of exact zeros
   between a negative and a positive value) nearest y = 0. */
static double find_y0(const double *y, const double *d, int n)
{
  double best = NAN;
  for (int i = 0; i + 1 < n; i++) {
    double c = NAN;
    if (d[i] < 0 && d[i + 1] > 0) {
      c = y[i] - d[i] * (y[i + 1] - y[i]) / (d[i + 1] - d[i]);
    } else if (d[i] < 0 && d[i + 1] == 0) {
      int j = i + 1;
      while (j + 1 < n && d[j + 1] == 0) j++;
      if (j + 1 < n && d[j + 1] > 0) c = j == i + 1 ? y[i + 1] : (y[i + 1] + y[j]) / 2;
      i = j - 1; /* go on after the run */
    }
    if (!isnan(c) && (isnan(best) || fabs(c) < fabs(best) || (fabs(c) == fabs(best) && c < best)))
      best = c;
  }
  return best;
}

/* S at the grid points, accumulated outward from y0 by trapezoids. */
static void potential(rr_conicity_plan *p)
{
  int n = p->n, i0 = p->i0;
  const double *y = p->y, *d = p->d;
  double *S = p->S;
  S[i0 + 1] = (y[i0 + 1] - p->y0) * d[i0 + 1] / 2;
  for (int k = i0 + 2; k < n; k++) S[k] = S[k - 1] + (y[k] - y[k - 1]) * (d[k - 1] + d[k]) / 2;
  S[i0] = -(p->y0 - y[i0]) * d[i0] / 2;
  for (int k = i0 - 1; k >= 0; k--) S[k] = S[k + 1] - (y[k + 1] - y[k]) * (d[k] + d[k + 1]) / 2;
  double r = -INFINITY;
  for (int k = i0 + 1; k < n; k++) p->rmR[k] = r = fmax(r, S[k]);
  p->smax_right = r;
  r = -INFINITY;
  for (int k = i0; k >= 0; k--) p->rmL[k] = r = fmax(r, S[k]);
  p->smax_left = r;
}

int rr_conicity_plan_new(const double *y, const double *dr, const int *valid, int n,
                         rr_conicity_plan **out, rr_error *err)
{
  *out = NULL;
  for (int i = 1; i < n; i++)
    if (!(y[i] > y[i - 1])) return rr_seterr(err, RR_EINVAL, "conicity: y must rise strictly");
  rr_conicity_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  p->y0 = NAN;
  int near = -1; /* the grid point nearest y = 0, and the valid run around it */
  for (int i = 0; i < n; i++)
    if (near < 0 || fabs(y[i]) < fabs(y[near])) near = i;
  int a = near, b = near;
  if (near >= 0 && (!valid || valid[near])) {
    while (a > 0 && (!valid || valid[a - 1]) && isfinite(dr[a - 1])) a--;
    while (b + 1 < n && (!valid || valid[b + 1]) && isfinite(dr[b + 1])) b++;
    p->n = b - a + 1;
  }
  if (p->n < 2 || !isfinite(dr[near])) {
    p->n = 0;
    *out = p; /* every conicity undefined */
    return RR_OK;
  }
  size_t N = (size_t)p->n;
  p->y = malloc(sizeof(double) * N * 8);
  if (!p->y) {
    free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  p->d = p->y + N;
  p->m = p->d + N;
  p->S = p->m + N;
  p->rmR = p->S + N;
  p->rmL = p->rmR + N;
  p->PL = p->rmL + N;
  p->PR = p->PL + N;
  memcpy(p->y, y + a, sizeof(double) * N);
  memcpy(p->d, dr + a, sizeof(double) * N);
  for (size_t j = 0; j + 1 < N; j++) p->m[j] = (p->d[j + 1] - p->d[j]) / (p->y[j + 1] - p->y[j]);
  p->y0 = find_y0(p->y, p->d, p->n);
  if (!isnan(p->y0)) {
    p->i0 = seg(p, p->y0);
    potential(p);
  }
  *out = p;
  return RR_OK;
}

/* The turning point right of y0 for the energy C (S reaching C, or leaving
   0 when C = 0). */
static double turn_right(const rr_conicity_plan *p, double C)
{
  int lo = p->i0 + 1, hi = p->n; /* first k with rmR[k] >= C (> 0 when C = 0) */
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (C > 0 ? p->rmR[mid] >= C : p->rmR[mid] > C)
      hi = mid;
    else
      lo = mid + 1;
  }
  if (lo >= p->n) return p->y[p->n - 1];
  int k = lo;
  double ya = k == p->i0 + 1 ? p->y0 : p->y[k - 1], Sa = k == p->i0 + 1 ? 0 : p->S[k - 1],
         da = k == p->i0 + 1 ? 0 : p->d[k - 1], mk = p->m[k - 1];
  double q = C - Sa, den = da + sqrt(fmax(da * da + 2 * mk * q, 0));
  double t = den > 0 ? 2 * q / den : 0;
  return fmin(ya + t, p->y[k]);
}

/* And left of it. */
static double turn_left(const rr_conicity_plan *p, double C)
{
  int k = -1; /* the first grid point going left where S reaches C: rmL is monotone downwards */
  int lo = 0, hi = p->i0 + 1;
  while (lo < hi) { /* the largest k <= i0 with rmL[k] >= C (> 0 when C = 0) */
    int mid = (lo + hi) / 2;
    if (C > 0 ? p->rmL[mid] >= C : p->rmL[mid] > C)
      lo = mid + 1;
    else
      hi = mid;
  }
  k = lo - 1;
  if (k < 0) return p->y[0];
  double ya = k == p->i0 ? p->y0 : p->y[k + 1], Sa = k == p->i0 ? 0 : p->S[k + 1],
         da = k == p->i0 ? 0 : p->d[k + 1], mk = p->m[k];
  double q = C - Sa, den = -da + sqrt(fmax(da * da + 2 * mk * q, 0));
  double t = den > 0 ? 2 * q / den : 0;
  return fmax(ya - t, p->y[k]);
}

static double half_range(const rr_conicity_plan *p, double C, double *yl, double *yr)
{
  *yl = turn_left(p, C);
  *yr = turn_right(p, C);
  return (*yr - *yl) / 2;
}

/* 8-point Gauss-Legendre on [-1, 1]. */
static const double GL_X[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                               -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                               0.7966664774136267,  0.9602898564975363};
static const double GL_W[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                               0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                               0.2223810344533745, 0.1012285362903763};

/* The inward sums of dr from each turning point to the grid points inside
   (PL_j = -int_{yL}^{y_j} dr, PR_j = int_{y_j}^{yR} dr), into p's scratch. */
static void inward_sums(rr_conicity_plan *p, double yl, double yr, int kl, int kr)
{
  const double *y = p->y, *d = p->d;
  double dl = dr_at(p, kl, yl), drr = dr_at(p, kr, yr);
  p->PL[kl + 1] = -(y[kl + 1] - yl) * (dl + d[kl + 1]) / 2;
  for (int j = kl + 2; j <= kr; j++)
    p->PL[j] = p->PL[j - 1] - (y[j] - y[j - 1]) * (d[j - 1] + d[j]) / 2;
  p->PR[kr] = (yr - y[kr]) * (d[kr] + drr) / 2;
  for (int j = kr - 1; j > kl; j--)
    p->PR[j] = p->PR[j + 1] + (y[j + 1] - y[j]) * (d[j] + d[j + 1]) / 2;
}

/* The integrand (L/2) sin(theta) / sqrt(C - S(y)) at theta (given by sh, ch:
   sin and cos of theta / 2), for a piece in segment j on the side of y0
   given by left, without cancellation. */
static double integrand(const rr_conicity_plan *p, double sh, double ch, double yl, double yr,
                        int j, int left, int kl, int kr)
{
  double L = yr - yl;
  double y = yl + L * sh * sh, drv = dr_at(p, j, y);
  if (left) {
    if (j == kl) return sqrt(L) * ch / sqrt(-(dr_at(p, kl, yl) + drv) / 2);
    double Q = p->PL[j] - (y - p->y[j]) * (p->d[j] + drv) / 2;
    return L * sh * ch / sqrt(Q); /* (L / 2) sin(theta) */
  }
  if (j == kr) return sqrt(L) * sh / sqrt((drv + dr_at(p, kr, yr)) / 2);
  double Q = p->PR[j + 1] + (p->y[j + 1] - y) * (drv + p->d[j + 1]) / 2;
  return L * sh * ch / sqrt(Q);
}

static double theta_of(double y, double yl, double yr)
{
  double a = y - yl, b = yr - y; /* finite: ternaries, not libm's fmax calls */
  return 2 * atan2(sqrt(a > 0 ? a : 0), sqrt(b > 0 ? b : 0));
}

/* C - S(y) at y in segment j, strictly inside the turning segments kl .. kr
   (from the inward sums: no cancellation). */
static double gap_inner(const rr_conicity_plan *p, double y, int j, int left)
{
  double drv = dr_at(p, j, y);
  return left ? p->PL[j] - (y - p->y[j]) * (p->d[j] + drv) / 2
              : p->PR[j + 1] + (p->y[j + 1] - y) * (drv + p->d[j + 1]) / 2;
}

/* A piece [ya, yb] at least FAR_WIDTHS of its widths from both turning
   points: 1 / sqrt(C - S) is analytic well beyond it, so Gauss-Legendre in y
   itself is exact to rounding (error ~ rho^-16, rho > 8 for the nearest
   singularity), with no trigonometry. */
#define FAR_WIDTHS 2.0
static double piece_far(const rr_conicity_plan *p, double ya, double yb, int j, int left)
{
  double h = (yb - ya) / 2, c = (yb + ya) / 2, sum = 0;
  for (int q = 0; q < 8; q++) sum += GL_W[q] / sqrt(gap_inner(p, c + h * GL_X[q], j, left));
  return h * sum;
}

/* A piece next to a turning point, in theta (y = yL + L sin^2(theta / 2),
   which takes the inverse square root out): theta t0 .. t1. */
static double piece_near(rr_conicity_plan *p, double t0, double t1, double yl, double yr, int j,
                         int left, int kl, int kr)
{
  double h = (t1 - t0) / 2, c = (t1 + t0) / 2, sum = 0, sc, cc;
  sincos(c / 2, &sc, &cc);                 /* the nodes' half angles by the addition theorem: */
  for (int q = 0; q < 4 && t1 > t0; q++) { /* 5 sincos a piece, not 8 */
    double sx, cx;
    sincos(h * GL_X[7 - q] / 2, &sx, &cx); /* the nodes +-x_q share them */
    sum += GL_W[q] * integrand(p, sc * cx - cc * sx, cc * cx + sc * sx, yl, yr, j, left, kl, kr);
    sum +=
        GL_W[7 - q] * integrand(p, sc * cx + cc * sx, cc * cx - sc * sx, yl, yr, j, left, kl, kr);
  }
  return h * sum;
}

/* The integral int_{yL}^{yR} dy / sqrt(C - S(y)) in pieces between the grid
   points (and y0), 8 Gauss-Legendre nodes each: in theta next to the turning
   points, in y away from them. */
static double wave_integral(rr_conicity_plan *p, double yl, double yr)
{
  int kl = seg(p, yl), kr = seg(p, yr);
  inward_sums(p, yl, yr, kl, kr);
  double t0 = 0, integral = 0, y_a = yl; /* t0: theta at y_a (NaN: not yet known) */
  int g = kl + 1, y0_done = 0, j = kl;
  while (y_a < yr) {
    double yb = yr; /* the piece's end: the next grid point inside, y0, or yR */
    if (g < p->n && p->y[g] < yr) yb = p->y[g];
    if (!y0_done && p->y0 <= yb) {
      yb = p->y0;
      y0_done = 1;
    }
    if (g < p->n && p->y[g] <= yb) g++;
    int left = yb <= p->y0;
    while (j < p->n - 2 && y_a >= p->y[j + 1]) j++; /* the segment from the piece's left end */
    double far = FAR_WIDTHS * (yb - y_a);
    if (j > kl && j < kr && yb > y_a && y_a - yl >= far && yr - yb >= far) {
      integral += piece_far(p, y_a, yb, j, left);
      t0 = NAN; /* theta at the next piece's start, if it needs it, from y */
    } else {
      if (isnan(t0)) t0 = theta_of(y_a, yl, yr);
      double t1 = yb >= yr ? RR_PI : theta_of(yb, yl, yr);
      integral += piece_near(p, t0, t1, yl, yr, j, left, kl, kr);
      t0 = t1;
    }
    y_a = yb;
  }
  return integral;
}

/* (a) The EN 15302 reference: the energy whose oscillation has the
   amplitude, then tan_gamma_e = (pi / I)^2. */
static void wavelength_method(rr_conicity_plan *p, double A, rr_conicity *out)
{
  double yl, yr, Cmax = fmin(p->smax_right, p->smax_left);
  if (half_range(p, 0, &yl, &yr) >= A) { /* inside a dead zone */
    out->tan_gamma_e = 0;
    out->turning_mm[0] = yl;
    out->turning_mm[1] = yr;
    out->energy = 0;
    return;
  }
  if (!(Cmax > 0) || half_range(p, Cmax, &yl, &yr) < A) return; /* turning points off the data */
  double lo = 0, hi = Cmax;
  for (int it = 0; it < 400; it++) {
    double mid = (lo + hi) / 2;
    if (!(mid > lo && mid < hi)) break;
    if (half_range(p, mid, &yl, &yr) < A)
      lo = mid;
    else
      hi = mid;
  }
  if (fabs(half_range(p, hi, &yl, &yr) - A) > 1e-9) return; /* A jumps over the amplitude */
  double in = wave_integral(p, yl, yr);
  out->tan_gamma_e = (RR_PI / in) * (RR_PI / in);
  out->turning_mm[0] = yl;
  out->turning_mm[1] = yr;
  out->energy = hi;
}

/* (b) Harmonic linearisation: the mean M(y_c) and the first harmonic of dr
   along y_c + A sin(theta), in closed form per segment piece (cos theta =
   sqrt(1 - x^2), sin 2 theta = 2 x cos theta at x = s / A); with dM/dy_c,
   the mean of dr's slope (sum of m_j dtheta / pi), for Newton's step. */
static void harmonic_sums(const rr_conicity_plan *p, double yc, double A, double *M, double *dM,
                          double *tg)
{
  double lo = yc - A, hi = yc + A, y_a = lo, m = 0, t = 0, dm = 0, th_a = -RR_PI / 2, c_a = 0,
         s2_a = 0;
  int j = seg(p, lo), g = j + 1;
  while (y_a < hi) {
    double yb = hi, th_b = RR_PI / 2, c_b = 0, s2_b = 0;
    if (g < p->n && p->y[g] < hi) {
      yb = p->y[g++];
      double x = (yb - yc) / A, cx; /* finite: ternaries, not libm calls */
      x = x < -1 ? -1 : x > 1 ? 1 : x;
      th_b = asin(x);
      c_b = sqrt((cx = 1 - x * x) > 0 ? cx : 0);
      s2_b = 2 * x * c_b;
    }
    double al = p->d[j] + p->m[j] * (yc - p->y[j]), be = p->m[j];
    double dth = th_b - th_a, dcos = c_b - c_a;
    m += al * dth - be * A * dcos;
    dm += be * dth;
    t += -(al / A) * dcos + be * (dth / 2 - (s2_b - s2_a) / 4);
    th_a = th_b;
    c_a = c_b;
    s2_a = s2_b;
    y_a = yb;
    if (j < p->n - 2 && y_a >= p->y[j + 1]) j++; /* the next piece's segment, from its left end */
  }
  *M = m / RR_PI;
  *dM = dm / RR_PI;
  *tg = t / RR_PI;
}

#define HARMONIC_TOL_MM 1e-12 /* y_c's bracket width, or Newton's last step */

/* y_c where M = 0 inside the bracket [lo, hi] (M(lo) < 0 < M(hi)): Newton's
   step while it stays inside the bracket, else regula falsi (Illinois),
   until the bracket or the step is HARMONIC_TOL_MM or M vanishes. The first
   harmonic at the last centre evaluated, into tg. */
static double harmonic_root(const rr_conicity_plan *p, double A, double lo, double hi, double Ml,
                            double Mh, double *tg)
{
  double x = NAN, M, dM, newton = NAN;
  for (int it = 0, side = 0; it < 200 && hi - lo > HARMONIC_TOL_MM; it++) {
    int nt = newton > lo && newton < hi;
    x = nt ? newton : lo - Ml * (hi - lo) / (Mh - Ml);
    if (!(x > lo && x < hi)) x = (lo + hi) / 2;
    harmonic_sums(p, x, A, &M, &dM, tg);
    if (M == 0) break;
    int s = M < 0 ? -1 : 1;
    if (!nt && side == s) { /* Illinois: the stale end's weight halved */
      if (s < 0)
        Mh /= 2;
      else
        Ml /= 2;
    }
    side = s;
    if (s < 0) {
      lo = x;
      Ml = M;
    } else {
      hi = x;
      Mh = M;
    }
    newton = dM > 0 ? x - M / dM : NAN;
    if (fabs(newton - x) <= HARMONIC_TOL_MM) break;
  }
  if (isnan(x)) { /* the bracket already HARMONIC_TOL_MM wide */
    x = (lo + hi) / 2;
    harmonic_sums(p, x, A, &M, &dM, tg);
  }
  return x;
}

/* y_c where M = 0: the bracket's ends checked (M rises with y_c there), the
   root found between them. */
static void harmonic_method(const rr_conicity_plan *p, double A, rr_conicity *out)
{
  double lo = fmax(p->y0 - A, p->y[0] + A), hi = fmin(p->y0 + A, p->y[p->n - 1] - A), Ml, Mh, dM,
         tg;
  if (lo > hi) return;
  harmonic_sums(p, lo, A, &Ml, &dM, &tg);
  if (Ml > 0) return;
  double yc = lo;
  if (Ml < 0) {
    harmonic_sums(p, hi, A, &Mh, &dM, &tg);
    if (Mh < 0) return;
    yc = Mh == 0 ? hi : harmonic_root(p, A, lo, hi, Ml, Mh, &tg);
  }
  out->harmonic_centre_mm = yc;
  out->tan_gamma_e_harmonic = tg;
}

/* (c) The least-squares line through dr over y0 +- A: half its slope. */
static void regression_method(const rr_conicity_plan *p, double A, rr_conicity *out)
{
  double lo = p->y0 - A, hi = p->y0 + A, y_a = lo, sum = 0;
  if (lo < p->y[0] || hi > p->y[p->n - 1]) return;
  int j = seg(p, lo), g = j + 1;
  while (y_a < hi) {
    double yb = g < p->n && p->y[g] < hi ? p->y[g++] : hi;
    double al = p->d[j] + p->m[j] * (p->y0 - p->y[j]), be = p->m[j];
    double sa = y_a - p->y0, sb = yb - p->y0;
    sum += al * (sb * sb - sa * sa) / 2 + be * (sb * sb * sb - sa * sa * sa) / 3;
    y_a = yb;
    if (j < p->n - 2 && y_a >= p->y[j + 1]) j++;
  }
  out->tan_gamma_e_regression = 3 / (4 * A * A * A) * sum;
}

void rr_conicity_eval(rr_conicity_plan *p, double A, double e0, double r0, rr_conicity *out)
{
  *out = (rr_conicity){.amplitude_mm = A,
                       .tan_gamma_e = NAN,
                       .turning_mm = {NAN, NAN},
                       .energy = NAN,
                       .wavelength_mm = NAN,
                       .tan_gamma_e_harmonic = NAN,
                       .harmonic_centre_mm = NAN,
                       .tan_gamma_e_regression = NAN};
  if (p->n < 2 || isnan(p->y0) || !(A > 0) || !isfinite(A)) return;
  wavelength_method(p, A, out);
  if (out->tan_gamma_e >= 0)
    out->wavelength_mm =
        out->tan_gamma_e > 0 ? 2 * RR_PI * sqrt(e0 * r0 / out->tan_gamma_e) : INFINITY;
  harmonic_method(p, A, out);
  regression_method(p, A, out);
}
