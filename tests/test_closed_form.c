#define _POSIX_C_SOURCE 200809L
/* The generic layer against closed-form results: free wheelset (Klingel),
 * elastically restrained wheelset (critical speed), rigid bogie (kinematic
 * wavelength), Maxwell limits and damper characteristics. */
#include <complex.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"

static const double r0 = 0.46, l0 = 0.7465, lam = 0.2;

/* A wheelset on the ground, optionally restrained by a lateral spring ky and
 * a yaw stiffness kpsi (two longitudinal springs at +-l1). */
static rr_model *wheelset(double m, double Iz, double f11, double f22, double ky, double kpsi)
{
  rr_error e;
  rr_system *s;
  if (rr_system_new(&s, &e)) return NULL;
  rr_body_spec w = {.name = "w",
                    .group = RR_GROUP_WHEELSET,
                    .mass = m,
                    .yaw_inertia = Iz,
                    .ref = {0, 0, r0},
                    .dofs = RR_DOF_Y | RR_DOF_PSI};
  int bw = -1;
  rr_system_add_body(s, &w, &bw, &e);
  if (ky > 0) {
    rr_element_spec ey = {.name = "ky",
                          .body_a = bw,
                          .body_b = RR_GROUND,
                          .point = {0, 0, r0},
                          .direction = RR_DIR_Y,
                          .law = RR_LAW_SPRING,
                          .k = ky};
    rr_system_add_element(s, &ey, NULL, &e);
  }
  if (kpsi > 0) {
    const double l1 = 1.0;
    for (int sd = -1; sd <= 1; sd += 2) {
      rr_element_spec ex = {.name = "kx",
                            .body_a = bw,
                            .body_b = RR_GROUND,
                            .point = {0, sd * l1, r0},
                            .direction = RR_DIR_X,
                            .law = RR_LAW_SPRING,
                            .k = kpsi / (2 * l1 * l1)};
      rr_system_add_element(s, &ex, NULL, &e);
    }
  }
  rr_contact_spec c = {.body = bw, .f11 = f11, .f22 = f22, .r0 = r0, .l0 = l0};
  rr_system_add_contact(s, &c, NULL, &e);
  rr_model *mod;
  int st = rr_model_new(s, &mod, &e);
  rr_system_free(s);
  return st ? NULL : mod;
}

/* Largest real part and the frequency of the least-damped oscillatory mode. */
static void least_damped(rr_model *m, double *re, double *f)
{
  rr_error e;
  rr_modal_ws *ws;
  rr_modal_result r;
  rr_modal_ws_new(m, &ws, &e);
  rr_modal_result_alloc(m, &r, &e);
  rr_modal_opts o = {.fmax_hz = 1e9, .w_min = 0, .r_max = 1};
  rr_modal_solve(m, &o, ws, &r, &e);
  *re = -INFINITY;
  *f = NAN;
  for (int i = 0; i < r.n; i++)
    if (r.modes[i].oscillatory && r.modes[i].re > *re) {
      *re = r.modes[i].re;
      *f = r.modes[i].freq_hz;
    }
  rr_modal_result_free(&r);
  rr_modal_ws_free(ws);
}

static void test_klingel(void)
{
  /* Large creep coefficients: the free wheelset rolls kinematically. */
  rr_model *m = wheelset(1639, 822, 1e11, 1e11, 0, 0);
  rr_error e;
  for (double v = 20; v <= 100; v += 40) {
    rr_model_set_operating(m, v, lam, &e);
    double re, f;
    least_damped(m, &re, &f);
    double fk = v / (2 * RR_PI) * sqrt(lam / (r0 * l0));
    CHECK_CLOSE(f, fk, 1e-4, 0, "Klingel frequency");
  }
  rr_model_free(m);
}

static void test_restrained_critical_speed(void)
{
  const double m = 1639, Iz = 822, f11 = 1e7, f22 = 1e7, ky = 5e6, kpsi = 2e6;
  rr_model *mod = wheelset(m, Iz, f11, f22, ky, kpsi);
  /* Closed form from the 4x4 characteristic polynomial. */
  double C = 2 * f22, Cx = 2 * f11;
  double A = m * Cx * l0 * l0 + Iz * C, Bq = m * kpsi + Iz * ky, D = C * Cx * l0 * l0;
  double E = C * kpsi + ky * Cx * l0 * l0, F = ky * kpsi + C * Cx * lam * l0 / r0;
  double vc = sqrt(E * A * D / (A * A * F + E * E * m * Iz - E * A * Bq));
  rr_error e;
  rr_modal_ws *ws;
  rr_modal_ws_new(mod, &ws, &e);
  rr_modal_opts o = {.fmax_hz = 1e9, .w_min = 0, .r_max = 1};
  rr_critical_opts co = {.v_min_ms = 1, .v_max_ms = 400, .step_ms = 0.5, .tol_ms = 1e-9};
  rr_critical cr;
  int st = rr_critical_speed(mod, lam, &o, &co, ws, &cr, &e);
  double v = cr.speed_ms;
  CHECK_OK(st, e);
  CHECK(cr.found, "restrained wheelset: no critical speed found");
  CHECK_CLOSE(v, vc, 1e-7, 0, "restrained wheelset critical speed (m/s)");
  /* the least-damped mode's real part changes sign across vc */
  double re, f;
  rr_model_set_operating(mod, vc * 0.99, lam, &e);
  least_damped(mod, &re, &f);
  CHECK(re < 0, "stable below vc (re %g)", re);
  rr_model_set_operating(mod, vc * 1.01, lam, &e);
  least_damped(mod, &re, &f);
  CHECK(re > 0, "unstable above vc (re %g)", re);
  rr_modal_ws_free(ws);
  rr_model_free(mod);
}

static void test_rigid_bogie(void)
{
  /* One body, two contacts at +-b: kinematic wavelength in the large-creep limit. */
  const double b = 1.25, f11 = 1e11, f22 = 0.5e11;
  rr_error e;
  rr_system *s;
  CHECK_OK(rr_system_new(&s, &e), e);
  rr_body_spec bg = {.name = "bogie",
                     .group = RR_GROUP_WHEELSET,
                     .mass = 2 * 1639 + 2328,
                     .yaw_inertia = 2 * 822 + 4080 + 2 * 1639 * b * b,
                     .ref = {0, 0, r0},
                     .dofs = RR_DOF_Y | RR_DOF_PSI};
  int bb = -1;
  CHECK_OK(rr_system_add_body(s, &bg, &bb, &e), e);
  for (int k = -1; k <= 1; k += 2) {
    rr_contact_spec c = {.body = bb, .f11 = f11, .f22 = f22, .r0 = r0, .l0 = l0, .dx = k * b};
    CHECK_OK(rr_system_add_contact(s, &c, NULL, &e), e);
  }
  rr_model *m;
  CHECK_OK(rr_model_new(s, &m, &e), e);
  rr_system_free(s);
  double Lw = 2 * RR_PI * sqrt((r0 * l0 / lam) * (1 + (f22 / f11) * b * b / (l0 * l0)));
  for (double v = 10; v <= 50; v += 20) {
    rr_model_set_operating(m, v, lam, &e);
    double re, f;
    least_damped(m, &re, &f);
    CHECK_CLOSE(f, v / Lw, 1e-4, 0, "rigid bogie kinematic frequency");
  }
  rr_model_free(m);
}

/* Maxwell element with series stiffness -> inf equals the plain damper. */
static void test_maxwell_limit(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_error e;
  double idx[2];
  for (int k = 0; k < 2; k++) {
    v.yaw_series_stiffness = k == 0 ? INFINITY : 1e13;
    v.lateral_series_stiffness = k == 0 ? INFINITY : 1e13;
    rr_model *m;
    int st = rr_model_from_vehicle(&v, &m, &e);
    CHECK_OK(st, e);
    if (st) return;
    CHECK(rr_model_nmaxwell(m) == (k == 0 ? 0 : 6), "Maxwell count %d", rr_model_nmaxwell(m));
    rr_model_set_operating(m, 300 / RR_KMH, 0.3, &e);
    rr_modal_ws *ws;
    rr_modal_ws_new(m, &ws, &e);
    CHECK_OK(rr_modal_stability_index(m, NULL, ws, &idx[k], &e), e);
    rr_modal_ws_free(ws);
    rr_model_free(m);
  }
  CHECK_CLOSE(idx[1], idx[0], 1e-5, 0, "stiff Maxwell vs plain damper index");
  /* Damper characteristics: at w = k/c, storage = loss = k/2; limits. */
  double k = 10e6, c = 4e6, f = k / c / (2 * RR_PI);
  rr_damper_point p = rr_maxwell_point(k, c, f);
  CHECK_CLOSE(p.storage, k / 2, 1e-12, 0, "storage at omega_opt");
  CHECK_CLOSE(p.loss, k / 2, 1e-12, 0, "loss at omega_opt");
  CHECK_CLOSE(p.dissipation, 1.0, 1e-12, 0, "dissipation at omega_opt");
  p = rr_maxwell_point(k, c, 1e-4);
  CHECK_CLOSE(p.eq_damping, c, 1e-6, 0, "low-frequency equivalent damping");
  p = rr_maxwell_point(k, c, 1e4);
  CHECK_CLOSE(p.storage, k, 1e-6, 0, "high-frequency storage");
  double w = 2 * RR_PI * 3.0;
  p = rr_maxwell_point(k, c, 3.0);
  CHECK_CLOSE(p.storage, k * c * c * w * w / (k * k + c * c * w * w), 1e-12, 0, "storage formula");
  CHECK_CLOSE(p.eq_damping, k * k * c / (k * k + c * c * w * w), 1e-12, 0,
              "equivalent damping formula");
  CHECK_CLOSE(p.dissipation, k / (c * w), 1e-12, 0, "dissipation factor k/(c w)");
}

int main(void)
{
  test_klingel();
  test_restrained_critical_speed();
  test_rigid_bogie();
  test_maxwell_limit();
  return check_done("closed_form");
}
