/* Ride indices from the acceleration PSD (docs/model.md section 7). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/comfort.h"
#include "util/internal.h"

/* The Sperling weighting (docs/model.md section 7), the one home of its
   constants: B(f) = g |p (c + n2 p)| / |1 + d1 p + d2 p^2 + d3 p^3|, p = j f,
   c^2 = c2, g = gain (x lateral for the lateral axis). */
static const struct {
  double gain, lateral, c2, n2, d1, d2, d3;
} sperling_b = {.gain = 0.588,
                .lateral = 1.25,
                .c2 = 1.911,
                .n2 = 0.25,
                .d1 = 1.563,
                .d2 = 0.277,
                .d3 = 0.0368};
#define SPERLING_W_FACTOR 4.42 /* Wz = 4.42 a_w^0.3 (a_w in m/s^2) */
#define SPERLING_W_EXPONENT 0.3
#define SPERLING_GB_FACTOR 3.57 /* GB/T 5599: W = 3.57 (sum a^3 F / f)^0.1 */
#define SPERLING_GB_EXPONENT 0.1

static double sperling_gain(int axis)
{
  return sperling_b.gain * (axis == RR_AXIS_LATERAL ? sperling_b.lateral : 1.0);
}

/* B(f)^2, the lateral factor applied last (the order the published figures
   were checked with) */
static double sperling2(double f, int axis)
{
  double f2 = f * f;
  double num = sperling_b.c2 * f2 + (sperling_b.n2 * f2) * (sperling_b.n2 * f2);
  double a = 1 - sperling_b.d2 * f2, b = sperling_b.d1 * f - sperling_b.d3 * f2 * f;
  double B2 = (sperling_b.gain * sperling_b.gain) * num / (a * a + b * b);
  return axis == RR_AXIS_LATERAL ? (sperling_b.lateral * sperling_b.lateral) * B2 : B2;
}

double rr_sperling_from_weighted_rms(double aw)
{
  return SPERLING_W_FACTOR * pow(aw, SPERLING_W_EXPONENT);
}

/* The same B as a state-space filter in s = 2 pi j f (controllable form). */
void rr_sperling_filter_ss(enum rr_axis axis, double *A, double *B, double *C)
{
  double g = sperling_gain(axis), tp = 2 * RR_PI;
  double a3 = sperling_b.d3 / (tp * tp * tp);
  double d2 = sperling_b.d2 / (tp * tp) / a3, d1 = sperling_b.d1 / tp / a3, d0 = 1.0 / a3;
  double n2 = g * sperling_b.n2 / (tp * tp) / a3, n1 = g * sqrt(sperling_b.c2) / tp / a3;
  const double Av[9] = {0, 1, 0, 0, 0, 1, -d0, -d1, -d2};
  memcpy(A, Av, sizeof Av);
  B[0] = 0;
  B[1] = 0;
  B[2] = 1;
  C[0] = 0;
  C[1] = n1;
  C[2] = n2;
}

double rr_sperling_filter(double f, enum rr_axis axis) { return sqrt(sperling2(f, axis)); }

double rr_sperling_gb_factor(double f, enum rr_axis axis)
{
  if (axis == RR_AXIS_LATERAL) { /* at a breakpoint the lower range's formula applies */
    if (f <= 5.4) return 0.8 * f * f;
    if (f <= 26) return 650 / (f * f);
    return 1;
  }
  if (f <= 5.9) return 0.325 * f * f;
  if (f <= 20) return 400 / (f * f);
  return 1;
}

/* ISO 8041 parameters: f1, f2, f3, f4, Q4, f5, Q5, f6, Q6, K (f1 = 0: no
   high-pass; f5 = 0: no step). EN 12299's Wb and Wp as EN 12299:2009 gives
   them (its Wb's K 0.4 times a step normalised to 1 below f5 is 1.024 in
   this form). */
static const double iso[6][10] = {
    {0.4, 100, 16, 16, 0.55, 2.5, 0.9, 4, 0.95, 1.024},      /* Wb */
    {0.4, 100, 8, 8, 0.63, 0, 0, 0, 0, 1},                   /* Wc */
    {0.4, 100, 2, 2, 0.63, 0, 0, 0, 0, 1},                   /* Wd */
    {0.4, 100, 12.5, 12.5, 0.63, 2.37, 0.91, 3.35, 0.91, 1}, /* Wk */
    {0.4, 100, 16, 16, 0.63, 2.5, 0.8, 4, 0.8, 1.024},       /* Wb, EN 12299 */
    {0, 100, 2, 2, 0.63, 0, 0, 0, 0, 1},                     /* Wp, EN 12299 */
};

double complex rr_iso8041_weight(enum rr_iso_weighting wt, double f)
{
  if (wt < RR_ISO_WB || wt > RR_EN_WP) return NAN;
  const double *P = iso[wt];
  double complex s = I * 2 * RR_PI * f;
  double w1 = 2 * RR_PI * P[0], w2 = 2 * RR_PI * P[1], w3 = 2 * RR_PI * P[2], w4 = 2 * RR_PI * P[3];
  const double Q = 1 / sqrt(2.0);
  double complex Hh = P[0] > 0 ? s * s / (s * s + w1 * s / Q + w1 * w1) : 1;
  double complex Hl = w2 * w2 / (s * s + w2 * s / Q + w2 * w2);
  double complex Ht = P[9] * (1 + s / w3) / (1 + s / (P[4] * w4) + s * s / (w4 * w4));
  double complex Hs = 1;
  if (P[5] > 0) {
    double w5 = 2 * RR_PI * P[5], w6 = 2 * RR_PI * P[7];
    Hs = (w5 / w6) * (w5 / w6) * (1 + s / (P[6] * w5) + s * s / (w5 * w5)) /
         (1 + s / (P[8] * w6) + s * s / (w6 * w6));
  }
  return Hh * Hl * Ht * Hs;
}

static int check_grid(const double *f, int n, rr_error *err)
{
  if (n < 2) return rr_seterr(err, RR_EINVAL, "comfort: need at least two frequencies");
  for (int i = 1; i < n; i++)
    if (!(f[i] > f[i - 1])) return rr_seterr(err, RR_EINVAL, "comfort: frequencies must increase");
  return RR_OK;
}

/* The GB/T 5599 bands: 0.2 Hz wide from 0.5 Hz, those lying wholly inside
   the grid; each taken at its centre fc, G interpolated linearly in f. At
   most RR_GB_BANDS_MAX (grids up to ~20 kHz). */
#define RR_GB_BANDS_MAX 100000
#define GB_DF 0.2
typedef struct gb_band {
  double fc, t, ff;
  int lo;
} gb_band;

/* Band k: 1 inside the grid (b filled), 0 below its start, -1 past its end. */
static int gb_band_at(const double *f, int n, int axis, int k, gb_band *b)
{
  double lo = 0.5 + GB_DF * k, hi = lo + GB_DF, fc = lo + 0.5 * GB_DF;
  if (hi > f[n - 1] * (1 + 1e-12)) return -1;
  if (lo < f[0] * (1 - 1e-12)) return 0;
  int a = 0, z = n - 1;
  while (z - a > 1) {
    int mid = (a + z) / 2;
    if (f[mid] <= fc)
      a = mid;
    else
      z = mid;
  }
  *b = (gb_band){.fc = fc,
                 .t = (fc - f[a]) / (f[z] - f[a]),
                 .ff = rr_sperling_gb_factor(fc, axis) / fc,
                 .lo = a};
  return 1;
}

/* A_i^3 F(f_i) / f_i of one band, A_i = sqrt(2 G(f_i) df). */
static double gb_term(const gb_band *b, const double *G, int stride)
{
  const double *g = G + (size_t)b->lo * (size_t)stride;
  double A = sqrt(2 * (g[0] + b->t * (g[stride] - g[0])) * GB_DF);
  return A * A * A * b->ff;
}

static int gb_grid_check(const double *f, int n, rr_error *err)
{
  if (f[n - 1] > 0.5 + GB_DF * RR_GB_BANDS_MAX)
    return rr_seterr(err, RR_EINVAL,
                     "comfort: grid to %g Hz: the GB/T 5599 method takes grids up to %g Hz",
                     f[n - 1], 0.5 + GB_DF * RR_GB_BANDS_MAX);
  return RR_OK;
}

/* trapezoid of g(f) G(f) */
static double trapz_weighted(const double *f, const double *G, int n, int stride,
                             double (*g)(double, int), int arg)
{
  double s = 0, a = n > 0 ? G[0] * (g ? g(f[0], arg) : 1) : 0;
  for (int i = 0; i + 1 < n; i++) { /* each point weighted once */
    double b = G[(i + 1) * stride] * (g ? g(f[i + 1], arg) : 1);
    s += 0.5 * (a + b) * (f[i + 1] - f[i]);
    a = b;
  }
  return s;
}

double rr_psd_rms(const double *f, const double *G, int n, int stride)
{
  return sqrt(trapz_weighted(f, G, n, stride, NULL, 0));
}

int rr_sperling_filter_index(const double *f, const double *G, int n, int stride, enum rr_axis axis,
                             double *Wz, rr_error *err)
{
  int st = check_grid(f, n, err);
  if (st) return st;
  double aw = sqrt(trapz_weighted(f, G, n, stride, sperling2, axis));
  *Wz = rr_sperling_from_weighted_rms(aw);
  return RR_OK;
}

int rr_sperling_gb_index(const double *f, const double *G, int n, int stride, enum rr_axis axis,
                         double *W, rr_error *err)
{
  int st = check_grid(f, n, err);
  if (!st) st = gb_grid_check(f, n, err);
  if (st) return st;
  double sum = 0;
  int bands = 0;
  gb_band b;
  for (int k = 0, r; k < RR_GB_BANDS_MAX && (r = gb_band_at(f, n, axis, k, &b)) >= 0; k++)
    if (r) {
      sum += gb_term(&b, G, stride);
      bands++;
    }
  if (!bands)
    return rr_seterr(err, RR_EINVAL, "comfort: no whole 0.2 Hz band from 0.5 Hz inside %g-%g Hz",
                     f[0], f[n - 1]);
  *W = SPERLING_GB_FACTOR * pow(sum, SPERLING_GB_EXPONENT);
  return RR_OK;
}

static double iso2(double f, int wt)
{
  double complex h = rr_iso8041_weight(wt, f);
  return creal(h * conj(h));
}

int rr_weighted_rms(const double *f, const double *G, int n, int stride, enum rr_iso_weighting wt,
                    double *aw, rr_error *err)
{
  if (wt < RR_ISO_WB || wt > RR_EN_WP)
    return rr_seterr(err, RR_EINVAL, "comfort: unknown ISO weighting");
  int st = check_grid(f, n, err);
  if (st) return st;
  *aw = sqrt(trapz_weighted(f, G, n, stride, iso2, wt));
  return RR_OK;
}

double rr_en12299_comfort(double awd) { return 6 * awd; }

/* ---- the plan ---- */

struct rr_comfort_plan {
  int n, axis, nb;
  double *f, *gs, *gw; /* grid, |B|^2, |W|^2 at each point */
  gb_band *band;
};

void rr_comfort_plan_free(rr_comfort_plan *p)
{
  if (!p) return;
  free(p->f);
  free(p->gs);
  free(p->gw);
  free(p->band);
  free(p);
}

int rr_comfort_plan_new(const double *f, int n, enum rr_axis axis, rr_comfort_plan **out,
                        rr_error *err)
{
  *out = NULL;
  if (axis != RR_AXIS_LATERAL && axis != RR_AXIS_VERTICAL)
    return rr_seterr(err, RR_EINVAL, "comfort: unknown axis");
  int st = check_grid(f, n, err);
  if (!st) st = gb_grid_check(f, n, err);
  if (st) return st;
  gb_band b;
  int nb = 0;
  for (int k = 0, r; k < RR_GB_BANDS_MAX && (r = gb_band_at(f, n, axis, k, &b)) >= 0; k++) nb += r;
  if (!nb)
    return rr_seterr(err, RR_EINVAL, "comfort: no whole 0.2 Hz band from 0.5 Hz inside %g-%g Hz",
                     f[0], f[n - 1]);
  rr_comfort_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  p->n = n;
  p->axis = axis;
  p->nb = nb;
  p->f = malloc(sizeof(double) * (size_t)n);
  p->gs = malloc(sizeof(double) * (size_t)n);
  p->gw = malloc(sizeof(double) * (size_t)n);
  p->band = malloc(sizeof *p->band * (size_t)nb);
  if (!p->f || !p->gs || !p->gw || !p->band) {
    rr_comfort_plan_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  int wt = axis == RR_AXIS_LATERAL ? RR_ISO_WD : RR_ISO_WB;
  for (int i = 0; i < n; i++) {
    p->f[i] = f[i];
    p->gs[i] = sperling2(f[i], axis);
    p->gw[i] = iso2(f[i], wt);
  }
  for (int k = 0, j = 0, r; j < nb && (r = gb_band_at(f, n, axis, k, &b)) >= 0; k++)
    if (r) p->band[j++] = b;
  *out = p;
  return RR_OK;
}

/* trapezoid of g G with g tabulated on the plan's grid (g NULL: 1) */
static double trapz_tab(const double *f, const double *G, int n, int stride, const double *g)
{
  double s = 0, a = G[0] * (g ? g[0] : 1);
  for (int i = 0; i + 1 < n; i++) {
    double b = G[(i + 1) * stride] * (g ? g[i + 1] : 1);
    s += 0.5 * (a + b) * (f[i + 1] - f[i]);
    a = b;
  }
  return s;
}

static double gb_plan_index(const rr_comfort_plan *p, const double *G, int stride)
{
  double sum = 0;
  for (int k = 0; k < p->nb; k++) sum += gb_term(&p->band[k], G, stride);
  return SPERLING_GB_FACTOR * pow(sum, SPERLING_GB_EXPONENT);
}

int rr_comfort_gb(const rr_comfort_plan *p, const double *G, int stride, double *W, rr_error *err)
{
  *W = gb_plan_index(p, G, stride);
  return isfinite(*W) ? RR_OK : rr_seterr(err, RR_EINVAL, "comfort: the PSD is not finite");
}

int rr_comfort_execute(const rr_comfort_plan *p, const double *G, int stride, rr_comfort *out,
                       rr_error *err)
{
  *out = (rr_comfort){
      .rms = sqrt(trapz_tab(p->f, G, p->n, stride, NULL)),
      .sperling = rr_sperling_from_weighted_rms(sqrt(trapz_tab(p->f, G, p->n, stride, p->gs))),
      .sperling_gb = gb_plan_index(p, G, stride),
      .wd_rms = sqrt(trapz_tab(p->f, G, p->n, stride, p->gw))};
  if (isfinite(out->rms) && isfinite(out->sperling) && isfinite(out->sperling_gb) &&
      isfinite(out->wd_rms))
    return RR_OK;
  return rr_seterr(err, RR_EINVAL, "comfort: the PSD is not finite");
}
