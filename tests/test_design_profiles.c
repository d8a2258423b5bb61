/* The built-in design profiles against what defines them: S1002's flange
 * height, thickness and qR (EN 13715), 60E1's head width and, as an
 * independent check of its construction from the arcs of EN 13674-1, the
 * standard's rail S-UIC 519-A (EN 15302 Annex D, a 60E1 stored at 1:20)
 * turned upright: within 0.05 mm of the built-in everywhere, and wheel A on
 * it gives Annex E1's tan gamma_e at 3 mm. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"

static const char *source_dir(void)
{
  const char *s = getenv("RR_SOURCE_DIR");
  return s ? s : "..";
}

/* The built-in S1002 (EN 13715) against its defining dimensions: flange
   height 28 mm, flange thickness 32.5 mm at 10 mm above the measuring
   circle (from the flange back at -70 mm), qR 10.8 mm (between that point
   and the flange face 2 mm below the tip). */
static double crossing(const rr_polyline *p, double z, double from)
{
  for (int i = 1; i < p->n; i++)
    if (p->x[i] > from && (p->z[i - 1] - z) * (p->z[i] - z) <= 0 && p->z[i] != p->z[i - 1])
      return p->x[i - 1] + (p->x[i] - p->x[i - 1]) * (z - p->z[i - 1]) / (p->z[i] - p->z[i - 1]);
  return NAN;
}

static void test_s1002(void)
{
  rr_polyline p;
  rr_error e;
  CHECK_OK(rr_polyline_builtin("S1002", &p, &e), e);
  double zmin = 0, umin = 0;
  for (int i = 0; i < p.n; i++)
    if (p.z[i] < zmin) zmin = p.z[i], umin = p.x[i];
  CHECK_CLOSE(-zmin, 28, 0, 1e-9, "S1002 flange height (mm)");
  CHECK_CLOSE(umin, -55, 0, 1e-9, "S1002 flange tip position (mm)");
  double u10 = crossing(&p, -10, umin), u26 = crossing(&p, -26, umin);
  CHECK_CLOSE(u10 + 70, 32.5, 0, 0.01, "S1002 flange thickness (mm)");
  CHECK_CLOSE(u10 - u26, 10.8, 0, 0.02, "S1002 qR (mm)");
  int joins = 1;
  for (int i = 1; i < p.n; i++)
    joins &= fabs(p.z[i] - p.z[i - 1]) < 2.1; /* no gap between sections */
  CHECK(joins && p.x[0] == -70 && p.n == 1301, "S1002: 1301 points from the flange back, joined");
  rr_polyline_free(&p);
  CHECK(rr_polyline_builtin("S1003", &p, &e) == RR_EINVAL, "an unknown built-in: %s", e.msg);
  CHECK(rr_polyline_load("S1002", &p, &e) == RR_OK && p.n == 1301, "S1002 by name as a file");
  rr_polyline_free(&p);
}

/* The 60E1 head: 72 mm wide where the 13 mm arc meets the 1:20 side,
   14.3 mm below the crown; symmetric; the crown at (0, 0). */
static void test_60e1_dimensions(const rr_polyline *p)
{
  CHECK_CLOSE(p->x[p->n - 1] - p->x[0], 72.0, 0, 0.005, "60E1 head width (mm)");
  CHECK_CLOSE(-p->z[0], 14.3, 0, 0.01, "60E1: the head's 72 mm 14.3 mm below the crown");
  double zmax = -INFINITY, asym = 0;
  for (int i = 0; i < p->n; i++) {
    zmax = fmax(zmax, p->z[i]);
    asym = fmax(asym, fabs(p->x[i] + p->x[p->n - 1 - i]) + fabs(p->z[i] - p->z[p->n - 1 - i]));
  }
  CHECK(zmax == 0 && asym < 1e-12, "60E1: crown at 0 (%g), symmetric (%g)", zmax, asym);
  /* the crown's curvature radius from three points: 300 mm */
  int c = p->n / 2;
  double h = p->x[c + 5] - p->x[c], sag = p->z[c] - p->z[c + 5];
  CHECK_CLOSE(h * h / (2 * sag), 300, 1e-3, 0, "60E1 crown radius (mm)");
}

/* The shortest distance from (v, z) to the polyline. */
static double distance(const rr_polyline *p, double v, double z)
{
  double best = INFINITY;
  for (int i = 1; i < p->n; i++) {
    double dx = p->x[i] - p->x[i - 1], dz = p->z[i] - p->z[i - 1];
    double t = ((v - p->x[i - 1]) * dx + (z - p->z[i - 1]) * dz) / (dx * dx + dz * dz);
    t = fmin(fmax(t, 0), 1);
    best = fmin(best, hypot(v - p->x[i - 1] - t * dx, z - p->z[i - 1] - t * dz));
  }
  return best;
}

static void test_60e1_against_annex_d(const rr_polyline *e1)
{
  char path[1024];
  snprintf(path, sizeof path, "%s/profiles/en15302/SUIC519A.dat", source_dir());
  rr_polyline a;
  rr_error e;
  CHECK_OK(rr_polyline_load(path, &a, &e), e);
  /* upright: turned back by 1:20 about the file's origin; its crown by a
     parabola through the points within 8 mm of the highest */
  double th = -atan(1.0 / 20), c = cos(th), s = sin(th);
  double *v = malloc(sizeof(double) * (size_t)a.n), *z = malloc(sizeof(double) * (size_t)a.n);
  int top = 0;
  if (!v || !z || a.n < 3) {
    CHECK(0, "S-UIC 519-A read");
    return;
  }
  for (int i = 0; i < a.n; i++) {
    v[i] = c * a.x[i] - s * a.z[i];
    z[i] = s * a.x[i] + c * a.z[i];
    if (z[i] > z[top]) top = i;
  }
  double S[5] = {0}, T[3] = {0}; /* least squares z = q0 + q1 u + q2 u^2, u = v - v_top */
  for (int i = 0; i < a.n; i++) {
    double u = v[i] - v[top];
    if (fabs(u) >= 8) continue;
    for (int k = 0; k < 5; k++) S[k] += pow(u, k);
    for (int k = 0; k < 3; k++) T[k] += z[i] * pow(u, k);
  }
  double M[3][3] = {{S[0], S[1], S[2]}, {S[1], S[2], S[3]}, {S[2], S[3], S[4]}}, q[3];
  double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
               M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
               M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  for (int k = 0; k < 3; k++) { /* Cramer */
    double N[3][3];
    memcpy(N, M, sizeof N);
    for (int r = 0; r < 3; r++) N[r][k] = T[r];
    q[k] = (N[0][0] * (N[1][1] * N[2][2] - N[1][2] * N[2][1]) -
            N[0][1] * (N[1][0] * N[2][2] - N[1][2] * N[2][0]) +
            N[0][2] * (N[1][0] * N[2][1] - N[1][1] * N[2][0])) /
           det;
  }
  double uc = -q[1] / (2 * q[2]), vc = v[top] + uc, zc = q[0] + q[1] * uc + q[2] * uc * uc,
         worst = 0;
  for (int i = 0; i < a.n; i++) worst = fmax(worst, distance(e1, v[i] - vc, z[i] - zc));
  CHECK(worst < 0.05, "S-UIC 519-A upright within %.4f mm of the built-in 60E1", worst);
  /* wheel A on the built-in turned to 1:20, placed as Annex E places rail A
     (its crown 2.608 mm outward of the file's origin at 1:20) */
  double off = -(cos(-th) * vc - sin(-th) * zc);
  char wheel[1024];
  snprintf(wheel, sizeof wheel, "%s/profiles/en15302/RUIC519A.dat", source_dir());
  rr_polyline w;
  CHECK_OK(rr_polyline_load(wheel, &w, &e), e);
  rr_contact_opts o = rr_contact_opts_default();
  o.inclination = 1.0 / 20;
  o.lateral_offset_mm = off;
  rr_contact_plan *plan;
  CHECK_OK(rr_contact_plan_new(&w, NULL, e1, NULL, &o, &plan, &e), e);
  long n = rr_contact_range(-10, 10, 0.01, NULL, 0);
  double *y = malloc(sizeof(double) * (size_t)n), *dr = malloc(sizeof(double) * (size_t)n);
  int *valid = malloc(sizeof(int) * (size_t)n);
  rr_contact_state *st = malloc(sizeof *st * (size_t)n);
  rr_contact_range(-10, 10, 0.01, y, n);
  CHECK_OK(rr_contact_execute(plan, y, (int)n, st, &e), e);
  for (long i = 0; i < n; i++) dr[i] = st[i].dr_mm, valid[i] = st[i].valid;
  rr_conicity_plan *cp;
  CHECK_OK(rr_conicity_plan_new(y, dr, valid, (int)n, &cp, &e), e);
  rr_conicity r;
  rr_conicity_eval(cp, 3, 750, 460, &r);
  CHECK_CLOSE(r.tan_gamma_e, 0.18748, 0, 1e-3,
              "wheel A on the built-in 60E1 at 1:20: Annex E1 at 3 mm");
  rr_conicity_plan_free(cp);
  rr_contact_plan_free(plan);
  free(y);
  free(dr);
  free(valid);
  free(st);
  free(v);
  free(z);
  rr_polyline_free(&w);
  rr_polyline_free(&a);
}

int main(void)
{
  test_s1002();
  rr_polyline e1;
  rr_error e;
  CHECK_OK(rr_polyline_builtin("60E1", &e1, &e), e);
  test_60e1_dimensions(&e1);
  test_60e1_against_annex_d(&e1);
  rr_polyline_free(&e1);
  return check_done("design profiles");
}
