/* The regularised lower incomplete gamma function and its inverse, for the
 * gamma law of the 5 s RMS (docs/vertical.md, "5 s RMS"). P by its series
 * below x = a + 1 and by the Lentz continued fraction of Q above (both to
 * double precision); the inverse by Halley's method from the Wilson-Hilferty
 * start, kept inside a bracket. */
#define _DEFAULT_SOURCE /* lgamma_r: lgamma writes the global signgam */
#include <float.h>
#include <math.h>
#include "railride/comfort.h"
#include "util/internal.h"

#define GAMMA_ITMAX 1000
#define GAMMA_EPS 1e-16
#define GAMMA_INV_CUBIC 1e-6 /* a Halley step this small leaves an error ~1e-18 */

static double log_gamma(double a)
{
  int sign;
  return lgamma_r(a, &sign);
}

/* x^a e^-x / Gamma(a), the common prefactor (lg = ln Gamma(a)) */
static double gamma_prefactor(double a, double x, double lg) { return exp(a * log(x) - x - lg); }

static double p_series(double a, double x, double lg)
{
  double term = 1 / a, sum = term;
  for (int n = 1; n < GAMMA_ITMAX; n++) {
    term *= x / (a + n);
    sum += term;
    if (fabs(term) < fabs(sum) * GAMMA_EPS) break;
  }
  return sum * gamma_prefactor(a, x, lg);
}

/* Q(a, x) by the modified Lentz continued fraction */
static double q_fraction(double a, double x, double lg)
{
  const double tiny = DBL_MIN / DBL_EPSILON;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < GAMMA_ITMAX; i++) {
    double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (fabs(c) < tiny) c = tiny;
    d = 1 / d;
    double del = d * c;
    h *= del;
    if (fabs(del - 1) < GAMMA_EPS) break;
  }
  return h * gamma_prefactor(a, x, lg);
}

/* P(a, x) for x > 0 finite */
static double gamma_p_lg(double a, double x, double lg)
{
  return x < a + 1 ? p_series(a, x, lg) : 1 - q_fraction(a, x, lg);
}

double rr_gamma_p(double a, double x)
{
  if (!(a > 0) || isnan(x)) return NAN;
  if (x <= 0) return 0;
  if (isinf(x)) return 1;
  return gamma_p_lg(a, x, log_gamma(a));
}

/* Wilson-Hilferty's start; the normal quantile by Acklam's central formula
   (enough for a start: Halley refines). */
static double wh_start(double a, double p)
{
  double q = p - 0.5, r = q * q;
  double z = q *
             (((((-39.69683028665376 * r + 220.9460984245205) * r - 275.9285104469687) * r +
                138.3577518672690) *
                   r -
               30.66479806614716) *
                  r +
              2.506628277459239) /
             (((((-54.47609879822406 * r + 161.5858368580409) * r - 155.6989798598866) * r +
                66.80131188771972) *
                   r -
               13.28068155288572) *
                  r +
              1);
  double t = 1 / (9 * a), x = a * pow(1 - t + z * sqrt(t), 3);
  return x > 0 ? x : pow(p * a * exp(log_gamma(a)), 1 / a); /* the small-x series inverted */
}

int rr_gamma_p_inv(double a, double p, double *x, rr_error *err)
{
  if (!(a > 0) || !(p > 0 && p < 1) || isinf(a))
    return rr_seterr(err, RR_EINVAL, "gamma quantile: need a > 0 and 0 < p < 1 (a %g, p %g)", a, p);
  double lo = 0, hi = INFINITY, xk = wh_start(a, p), lg = log_gamma(a);
  for (int it = 0; it < 100; it++) {
    double f = gamma_p_lg(a, xk, lg) - p;
    if (f < 0)
      lo = xk;
    else
      hi = xk;
    double dens = exp((a - 1) * log(xk) - xk - lg);
    double t = f / dens, step = t / (1 - 0.5 * t * ((a - 1) / xk - 1));
    double xn = xk - step;
    if (!(xn > lo && xn < hi)) xn = isinf(hi) ? 2 * xk + 1 : 0.5 * (lo + hi); /* bisect */
    /* Halley's error is cubic in the step's: below 1e-6 of x, xn is exact
       to double precision */
    if (fabs(xn - xk) <= GAMMA_INV_CUBIC * xn) {
      *x = xn;
      return RR_OK;
    }
    xk = xn;
  }
  return rr_seterr(err, RR_ENOCONV, "gamma quantile: no convergence (a %g, p %g)", a, p);
}
