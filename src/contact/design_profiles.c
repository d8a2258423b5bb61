/* Built-in design profiles from their published definitions
 * (docs/references.md): the S1002 wheel of EN 13715 (UIC 510-2), sections
 * A-H, as polynomials and circular arcs in the lateral coordinate s from the
 * measuring circle (positive to the field side, mm), giving the radius
 * increase F(s); the profile's z_w = -F(s) (docs/contact.md). Sampled every
 * 0.1 mm from the flange back (s = -70) to s = 60: the chord of the
 * smallest arc (the flange tip's, 12 mm) is within 1.1e-4 mm of it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/contact.h"
#include "internal.h"

#define S1002_FROM -70.0
#define S1002_TO 60.0
#define S1002_STEP 0.1

/* A circular arc a + sign sqrt(r^2 - (s + c)^2) (0 beyond its reach). */
static double arc(double s, double a, double r, double c, double sign)
{
  double q = r * r - (s + c) * (s + c);
  return a + sign * sqrt(q > 0 ? q : 0);
}

/* sum_k c_k s^k (Horner, c[0] first). */
static double poly(const double *c, int n, double s)
{
  double v = 0;
  for (int k = n - 1; k >= 0; k--) v = v * s + c[k];
  return v;
}

/* The radius increase F(s) of S1002 (mm). */
static double s1002(double s)
{
  static const double B[9] = {0,
                              -3.358537058e-02,
                              1.565681624e-03,
                              -2.810427944e-05,
                              5.844240864e-08,
                              -1.562379023e-08,
                              5.309217349e-15,
                              -5.957839843e-12,
                              2.646656573e-13};
  static const double C[8] = {-4.320221063e+03, -1.038384026e+03, -1.065501873e+02,
                              -6.051367875,     -2.054332446e-01, -4.169739389e-03,
                              -4.687195829e-05, -2.252755540e-07};
  if (s < -62.764705882) return arc(s, 9.519259302, 20.5, 49.5, 1);         /* H: flange back */
  if (s < -49.662510381) return arc(s, 16.0, 12.0, 55.0, 1);                /* G: flange tip */
  if (s < -39.764473993) return arc(s, 8.834924130, 20.0, 58.558326413, 1); /* F */
  if (s < -38.426669071) return -93.576667419 - 2.747477419 * s; /* E: flange face, 70 deg */
  if (s < -35.0) return arc(s, 16.446, 13.0, 26.210665, -1);     /* D: flange root */
  if (s < -26.0) return poly(C, 8, s);                           /* C */
  if (s < 32.15796) return poly(B, 9, s);                        /* B: tread */
  return 1.364323640 - 0.066666667 * s;                          /* A: chamfer side */
}

int rr_polyline_builtin(const char *name, rr_polyline *p, rr_error *err)
{
  *p = (rr_polyline){0};
  if (strcmp(name, "S1002") && strcmp(name, "s1002"))
    return rr_seterr(err, RR_EINVAL, "'%s' is not a built-in profile (S1002)", name);
  int n = (int)lround((S1002_TO - S1002_FROM) / S1002_STEP) + 1;
  p->x = malloc(sizeof(double) * (size_t)n);
  p->z = malloc(sizeof(double) * (size_t)n);
  if (!p->x || !p->z) {
    rr_polyline_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int i = 0; i < n; i++) {
    p->x[i] = S1002_FROM + i * S1002_STEP;
    p->z[i] = -s1002(p->x[i]);
  }
  p->n = n;
  return RR_OK;
}

int rr_polyline_is_builtin(const char *name)
{
  return !strcmp(name, "S1002") || !strcmp(name, "s1002");
}
