/* The nonlinear model on contact functions from profiles (docs/model.md,
 * "Contact geometry from profiles"), against closed forms: a cone on a
 * knife-edge rail is the constant conicity exactly (right-hand side,
 * Jacobian, Hopf point); a linear contact-angle difference gives the
 * normal forces' resultant -(Q/2) kappa s; a wheelset beyond the data ends
 * a simulation with RR_EDERAIL. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"

#define KMH (1 / RR_KMH) /* m/s per km/h */
#define G_ACC 9.81

/* Contact functions on y = -h .. h (m), n points, from closed forms. */
static rr_contact_functions tabulate(int n, double h, double (*dr)(double), double (*tr)(double),
                                     double (*tl)(double))
{
  rr_contact_functions cf = {.n = n, .y0_m = -h, .dy_m = 2 * h / (n - 1)};
  cf.dr_m = malloc(sizeof(double) * (size_t)n);
  cf.tan_right = malloc(sizeof(double) * (size_t)n);
  cf.tan_left = malloc(sizeof(double) * (size_t)n);
  for (int k = 0; k < n; k++) {
    double y = cf.y0_m + k * cf.dy_m;
    cf.dr_m[k] = dr(y);
    cf.tan_right[k] = tr(y);
    cf.tan_left[k] = tl(y);
  }
  snprintf(cf.source, sizeof cf.source, "closed form");
  return cf;
}

#define LAMBDA 0.1
static double cone_dr(double y) { return 2 * LAMBDA * y; }
static double cone_tan(double y)
{
  (void)y;
  return LAMBDA;
}

/* The same vehicle on lambda(a) = LAMBDA without a flange, and on the cone's
   contact functions: the same right-hand side and Jacobian at any state
   within the data (the table interpolates a straight line exactly). */
static void test_cone_equals_constant(void)
{
  rr_vehicle veh;
  rr_error e;
  rr_model *m;
  rr_profile p;
  double c[1] = {LAMBDA};
  CHECK_OK(rr_vehicle_open("type1", &veh, &e), e);
  CHECK_OK(rr_model_from_vehicle(&veh, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 300 * KMH, LAMBDA, &e), e);
  CHECK_OK(rr_profile_poly(c, 1, 12, &p, &e), e);
  rr_contact_law law = rr_contact_law_default();
  law.flange_stiffness = 0;
  rr_contact_functions cf = tabulate(2001, 10e-3, cone_dr, cone_tan, cone_tan);
  rr_nonlinear *a, *b;
  CHECK_OK(rr_nonlinear_new(m, &p, &law, &a, &e), e);
  CHECK_OK(rr_nonlinear_new_contact(m, &cf, &law, &b, &e), e);
  int N = rr_nonlinear_size(a);
  double *z = calloc((size_t)N, sizeof(double)), *fa = malloc(sizeof(double) * (size_t)N),
         *fb = malloc(sizeof(double) * (size_t)N),
         *Ja = malloc(sizeof(double) * (size_t)N * (size_t)N),
         *Jb = malloc(sizeof(double) * (size_t)N * (size_t)N);
  double worst_f = 0, worst_j = 0;
  unsigned s = 12345;
  for (int trial = 0; trial < 50; trial++) {
    for (int i = 0; i < N; i++) { /* displacements within +-6 mm, rates within +-0.3 m/s */
      s = s * 1103515245u + 12345u;
      double u = (double)(s >> 8) / (1u << 24) - 0.5;
      z[i] = i < rr_nonlinear_ndof(a) ? 12e-3 * u : 0.6 * u;
    }
    rr_nonlinear_rhs(a, z, NULL, fa);
    rr_nonlinear_rhs(b, z, NULL, fb);
    rr_nonlinear_jacobian(a, z, NULL, Ja);
    rr_nonlinear_jacobian(b, z, NULL, Jb);
    double na = 0, nj = 0;
    for (int i = 0; i < N; i++) na = fmax(na, fabs(fa[i]));
    for (int i = 0; i < N * N; i++) nj = fmax(nj, fabs(Ja[i]));
    for (int i = 0; i < N; i++) worst_f = fmax(worst_f, fabs(fa[i] - fb[i]) / na);
    for (int i = 0; i < N * N; i++) worst_j = fmax(worst_j, fabs(Ja[i] - Jb[i]) / nj);
  }
  CHECK(worst_f < 1e-12, "cone tables against lambda = %g: right-hand side within %.2e", LAMBDA,
        worst_f);
  CHECK(worst_j < 1e-12, "cone tables against lambda = %g: Jacobian within %.2e", LAMBDA, worst_j);
  double lo, hi;
  rr_nonlinear_contact_range(b, &lo, &hi);
  CHECK(lo == -10e-3 && hi == 10e-3, "the contact range: %g .. %g m", lo, hi);
  rr_nonlinear_contact_range(a, &lo, &hi);
  CHECK(isinf(lo) && isinf(hi), "lambda(a): no contact range");
  free(z);
  free(fa);
  free(fb);
  free(Ja);
  free(Jb);
  rr_nonlinear_free(a);
  rr_nonlinear_free(b);
  rr_contact_functions_free(&cf);
  rr_model_free(m);
}

#define KAPPA 30.0 /* 1/m: tan gamma_L - tan gamma_R = -KAPPA y */
static double zero(double y)
{
  (void)y;
  return 0;
}
static double kappa_right(double y) { return 0.05 + 0.5 * KAPPA * y; }
static double kappa_left(double y) { return 0.05 - 0.5 * KAPPA * y; }

/* A linear contact-angle difference: the wheelset's non-creep lateral force
   is -(Q/2) KAPPA s at s = y_w - y_t (the tables read at y = -s), Q the
   static axle load g (m_c + 2 m_f + 4 m_w) / 4, with dr = 0. */
static void test_normal_forces(void)
{
  rr_vehicle veh;
  rr_error e;
  rr_model *m;
  CHECK_OK(rr_vehicle_open("type1", &veh, &e), e);
  CHECK_OK(rr_model_from_vehicle(&veh, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 200 * KMH, 0.1, &e), e);
  rr_contact_functions cf = tabulate(401, 8e-3, zero, kappa_right, kappa_left);
  rr_nonlinear *nl;
  CHECK_OK(rr_nonlinear_new_contact(m, &cf, NULL, &nl, &e), e);
  double Q = G_ACC * (veh.carbody_mass + 2 * veh.frame_mass + 4 * veh.wheelset_mass) / 4;
  int N = rr_nonlinear_size(nl);
  double *z = calloc((size_t)N, sizeof(double)), yt[4] = {0, 1e-3, -2e-3, 0}, worst = 0;
  for (int w = 0; w < rr_nonlinear_ninputs(nl); w++)
    z[rr_nonlinear_index_y(nl, w)] = 3e-3 * (w - 1.3);
  for (int w = 0; w < rr_nonlinear_ninputs(nl); w++) {
    double fy, mz, fl, s = z[rr_nonlinear_index_y(nl, w)] - yt[w];
    rr_nonlinear_forces(nl, z, yt, w, &fy, &mz, &fl);
    worst = fmax(worst, fabs(fl - (-0.5 * Q * KAPPA * s)) / (0.5 * Q * KAPPA * 8e-3));
  }
  CHECK(worst < 1e-12, "normal forces: -(Q/2) kappa s within %.2e", worst);
  free(z);
  rr_nonlinear_free(nl);
  rr_contact_functions_free(&cf);
  rr_model_free(m);
}

/* A state beyond the data ends a simulation with RR_EDERAIL, naming it. */
static void test_derailment(void)
{
  rr_vehicle veh;
  rr_error e;
  rr_model *m;
  CHECK_OK(rr_vehicle_open("type1", &veh, &e), e);
  CHECK_OK(rr_model_from_vehicle(&veh, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 200 * KMH, LAMBDA, &e), e);
  rr_contact_functions cf = tabulate(201, 2e-3, cone_dr, cone_tan, cone_tan);
  rr_nonlinear *nl;
  CHECK_OK(rr_nonlinear_new_contact(m, &cf, NULL, &nl, &e), e);
  int N = rr_nonlinear_size(nl);
  double *z0 = calloc((size_t)N, sizeof(double)), *out = malloc(sizeof(double) * (size_t)N * 11);
  rr_sim_opts o = rr_sim_opts_default();
  o.duration_s = 0.1;
  o.fs_hz = 100;
  z0[rr_nonlinear_index_y(nl, 2)] = 1e-3; /* inside: runs */
  int st = rr_simulate(nl, z0, &o, out, 11, &e);
  CHECK(st == RR_OK, "inside the data: %s", st ? e.msg : "ok");
  z0[rr_nonlinear_index_y(nl, 2)] = 2.5e-3; /* beyond: stops */
  st = rr_simulate(nl, z0, &o, out, 11, &e);
  CHECK(st == RR_EDERAIL && strstr(e.msg, "wheelset 3") && strstr(e.msg, "derailment"),
        "beyond the data: status %d, %s", st, e.msg);
  free(z0);
  free(out);
  rr_nonlinear_free(nl);
  rr_contact_functions_free(&cf);
  rr_model_free(m);
}

/* A cone on a knife-edge rail through a vehicle file's [contact] gives the
   Hopf point of the constant conicity (the linear critical speed), and the
   branch leaves it as the constant conicity's does. */
static void test_cone_hopf(void)
{
  check_write_file("cone.dat", "-70 -7\n0 0\n65 6.5\n");
  check_write_file("knife.dat", "-30 -30\n0 0\n30 -30\n");
  const char *vf = check_write_file("cone.ini", "[vehicle]\nbase = type1\n[contact]\nwheel = "
                                                "cone.dat\nrail = knife.dat\ninclination = 0\n");
  rr_vehicle veh;
  rr_error e;
  CHECK_OK(rr_vehicle_open(vf, &veh, &e), e);
  rr_orbit_opts o = rr_orbit_opts_default();
  o.max_points = 4;
  rr_cycle pts[4];
  rr_bifurcation b, c;
  CHECK_OK(rr_bifurcation_continue(&veh, NULL, NULL, &o, pts, NULL, 4, &b, &e), e);
  rr_profile p;
  double lam[1] = {LAMBDA};
  CHECK_OK(rr_profile_poly(lam, 1, 12, &p, &e), e);
  rr_cycle q[4];
  CHECK_OK(rr_bifurcation_continue(&veh, &p, NULL, &o, q, NULL, 4, &c, &e), e);
  CHECK(b.hopf && c.hopf, "both have a Hopf point");
  CHECK_CLOSE(b.hopf_speed_ms * RR_KMH, c.hopf_speed_ms * RR_KMH, 0, 2e-3,
              "cone profiles: the Hopf point at the constant conicity's (km/h)");
  CHECK_CLOSE(b.hopf_freq_hz, c.hopf_freq_hz, 1e-6, 0, "cone profiles: the Hopf frequency");
  CHECK(b.type == c.type && b.npoints >= 2, "cone profiles: the same kind of bifurcation (%d, %d)",
        b.type, c.type);
}

int main(void)
{
  if (check_tmpdir("nlcontact")) return 1;
  test_cone_equals_constant();
  test_normal_forces();
  test_derailment();
  test_cone_hopf();
  check_cleanup();
  return check_done("nonlinear contact");
}
