/* Built-in design profiles from their published definitions
 * (docs/references.md). The S1002 wheel of EN 13715 (UIC 510-2): sections
 * A-H, polynomials and circular arcs in the lateral coordinate s from the
 * measuring circle (positive to the field side, mm), giving the radius
 * increase F(s); the profile's z_w = -F(s) (docs/contact.md); sampled every
 * 0.1 mm from the flange back (s = -70) to s = 60: the chord of the
 * smallest arc (the flange tip's, 12 mm) is within 1.1e-4 mm of it. The 60E1
 * rail head of EN 13674-1, upright: tangent arcs of 300 mm (the crown, over
 * a chord of 20.456 mm), 80 mm (to a chord of 52.053 mm) and 13 mm (until
 * the side turns to 1:20, 14.3 mm below the crown, where the head is 72 mm
 * wide), sampled every 0.1 mm of their length. The 1:20 side below is left
 * out: on a rail inclined 1:20 it would stand vertical, which a profile
 * (strictly rising laterally) cannot hold; a flange that reaches it is
 * beyond the data. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "railride/contact.h"
#include "util/internal.h"

#define S1002_FROM -70.0
#define S1002_TO 60.0
#define S1002_STEP 0.1
#define RAIL_ARC_STEP 0.1 /* mm of arc between points */
#define E1_CROWN_CHORD 20.456
#define E1_R80_CHORD 52.053

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

/* Points along the arc of radius r about (cv, cz) from angle a to b
   (radians, b < a: clockwise, the crown side first), every RAIL_ARC_STEP
   of its length; the end point excluded. Returns the count written. */
static int arc_points(double cv, double cz, double r, double a, double b, double *v, double *z)
{
  int n = (int)ceil(r * (a - b) / RAIL_ARC_STEP);
  for (int k = 0; k < n; k++) {
    double t = a + (b - a) * k / n;
    v[k] = cv + r * cos(t);
    z[k] = cz + r * sin(t);
  }
  return n;
}

/* One side (v >= 0) of a head of tangent arcs r[0] (centred on the axis,
   crown at 0), r[1], r[2], ending where the surface turns to 1 in side
   from the vertical, the chords at which the arcs change given; into v, z,
   the count returned. */
static int head_half(const double r[3], const double chord[2], double side, double *v, double *z)
{
  double cv = 0, cz = -r[0], a = RR_PI / 2; /* the current arc's centre and start angle */
  int n = 0;
  for (int i = 0; i < 3; i++) {
    double b = i < 2 ? acos((0.5 * chord[i] - cv) / r[i]) : atan(1 / side);
    n += arc_points(cv, cz, r[i], a, b, v + n, z + n);
    if (i < 2) { /* the next arc's centre: on this normal, r[i + 1] in from the joint */
      double pv = cv + r[i] * cos(b), pz = cz + r[i] * sin(b);
      cv = pv - r[i + 1] * cos(b);
      cz = pz - r[i + 1] * sin(b);
    }
    a = b;
  }
  v[n] = cv + r[2] * cos(a);
  z[n++] = cz + r[2] * sin(a);
  return n;
}

static int rail_60e1(rr_polyline *p, rr_error *err)
{
  enum { CAP = 2048 };
  static const double r[3] = {300, 80, 13}, chord[2] = {E1_CROWN_CHORD, E1_R80_CHORD};
  double hv[CAP / 2], hz[CAP / 2];
  int h = head_half(r, chord, 20, hv, hz), n = 2 * h - 1;
  p->x = malloc(sizeof(double) * (size_t)n);
  p->z = malloc(sizeof(double) * (size_t)n);
  if (!p->x || !p->z) {
    rr_polyline_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int k = 0; k < h; k++) { /* the gauge side (v < 0) mirrored, then the field side */
    p->x[k] = -hv[h - 1 - k];
    p->z[k] = hz[h - 1 - k];
    p->x[h - 1 + k] = hv[k];
    p->z[h - 1 + k] = hz[k];
  }
  p->x[h - 1] = 0; /* the crown, once */
  p->n = n;
  return RR_OK;
}

static int wheel_s1002(rr_polyline *p, rr_error *err)
{
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

static const struct {
  const char *name;
  int (*make)(rr_polyline *, rr_error *);
} builtins[] = {{"S1002", wheel_s1002}, {"60E1", rail_60e1}};

int rr_polyline_builtin(const char *name, rr_polyline *p, rr_error *err)
{
  *p = (rr_polyline){0};
  for (size_t i = 0; i < sizeof builtins / sizeof builtins[0]; i++)
    if (!strcasecmp(name, builtins[i].name)) return builtins[i].make(p, err);
  return rr_seterr(err, RR_EINVAL, "'%s' is not a built-in profile (S1002, 60E1)", name);
}

int rr_polyline_is_builtin(const char *name)
{
  for (size_t i = 0; i < sizeof builtins / sizeof builtins[0]; i++)
    if (!strcasecmp(name, builtins[i].name)) return 1;
  return 0;
}
