/* The nonlinear model and its limit cycles, against independent answers:
 * the linear model's state matrix and eigenvalues, finite differences, a
 * van der Pol oscillator's amplitude by averaging, direct integration by a
 * second integrator (CVODE BDF against the shooting's explicit RK). */
#define _POSIX_C_SOURCE 200809L
#include <lapacke.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"
#include "nonlinear/orbit.h"

#define KMH (1 / RR_KMH) /* m/s per km/h */

static rr_nonlinear *vehicle_nl(const char *veh_name, const char *prof, double kmh, rr_vehicle *veh,
                                rr_profile *p)
{
  rr_error e;
  rr_nonlinear *nl = NULL;
  rr_vehicle_open(veh_name, veh, &e);
  rr_profile_open(prof, p, &e);
  int st = rr_nonlinear_from_vehicle(veh, p, NULL, kmh * KMH, &nl, &e);
  CHECK_OK(st, e);
  return nl;
}

static double norm2sq(const double *x, int n)
{
  double s = 0;
  for (int i = 0; i < n; i++) s += x[i] * x[i];
  return s;
}

/* The linear model's state matrix at (v, lambda(0)). */
static double *linear_A(const rr_vehicle *veh, double lam0, double v, int *N)
{
  rr_model *m;
  rr_error e;
  rr_model_from_vehicle(veh, &m, &e);
  rr_model_set_operating(m, v, lam0, &e);
  *N = rr_model_state_size(m);
  double *A = malloc(sizeof(double) * (size_t)*N * *N);
  int st = rr_model_state_matrix(m, 0, A, &e);
  CHECK_OK(st, e);
  rr_model_free(m);
  return A;
}

static void test_jacobian_at_zero(void)
{
  rr_vehicle veh;
  rr_profile p;
  rr_nonlinear *nl = vehicle_nl("type1", "worn", 300, &veh, &p);
  int N;
  double *A = linear_A(&veh, rr_profile_conicity(&p, 0), 300 * KMH, &N);
  CHECK(N == rr_nonlinear_size(nl), "state sizes %d vs %d", N, rr_nonlinear_size(nl));
  double *J = malloc(sizeof(double) * N * N), *z = calloc(N, sizeof(double)), dmax = 0, amax = 0;
  rr_nonlinear_jacobian(nl, z, NULL, J);
  for (int i = 0; i < N * N; i++) {
    dmax = fmax(dmax, fabs(J[i] - A[i]));
    amax = fmax(amax, fabs(A[i]));
  }
  CHECK(dmax <= 1e-9 * amax, "Jacobian at 0 vs linear A: %g (|A| %g)", dmax, amax);
  free(A);
  free(J);
  free(z);
  rr_nonlinear_free(nl);
}

/* Every column of the Jacobian against central differences, at a state with
   a wheelset in flange contact and saturated creep. */
static void test_jacobian_fd(void)
{
  rr_vehicle veh;
  rr_profile p;
  rr_nonlinear *nl = vehicle_nl("type2", "worn", 400, &veh, &p);
  int N = rr_nonlinear_size(nl), n = rr_nonlinear_ndof(nl);
  double *z = calloc(N, sizeof(double)), *J = malloc(sizeof(double) * N * N),
         *a = malloc(sizeof(double) * N), *b = malloc(sizeof(double) * N), worst = 0;
  for (int i = 0; i < N; i++) z[i] = 1e-3 * sin(1.7 * i + 0.3) * (i >= n && i < 2 * n ? 30 : 1);
  z[rr_nonlinear_index_y(nl, 1)] = 9e-3;    /* beyond the 8 mm flange clearance */
  z[n + rr_nonlinear_index_y(nl, 2)] = 0.3; /* fast lateral slip: saturated */
  rr_nonlinear_jacobian(nl, z, NULL, J);
  for (int j = 0; j < N; j++) {
    double h = 1e-7 * (j >= n && j < 2 * n ? 30 : 1), zj = z[j], col = 0, err = 0;
    z[j] = zj + h;
    rr_nonlinear_rhs(nl, z, NULL, a);
    z[j] = zj - h;
    rr_nonlinear_rhs(nl, z, NULL, b);
    z[j] = zj;
    for (int i = 0; i < N; i++) {
      col = fmax(col, fabs(J[i * N + j]));
      err = fmax(err, fabs((a[i] - b[i]) / (2 * h) - J[i * N + j]));
    }
    worst = fmax(worst, err / fmax(col, 1e-300));
  }
  CHECK(worst < 1e-5, "Jacobian against central differences: worst column %g", worst);
  free(z);
  free(J);
  free(a);
  free(b);
  rr_nonlinear_free(nl);
}

/* A tiny disturbance along the least-damped mode grows at its real part. */
static void test_growth_rate(void)
{
  rr_vehicle veh;
  rr_profile p;
  double kmh = 560; /* above the Hopf point (541.6 km/h) */
  rr_nonlinear *nl = vehicle_nl("type1", "worn", kmh, &veh, &p);
  int N;
  double *A = linear_A(&veh, rr_profile_conicity(&p, 0), kmh * KMH, &N);
  double *wr = malloc(sizeof(double) * N), *wi = malloc(sizeof(double) * N),
         *V = malloc(sizeof(double) * N * N);
  LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'V', N, A, N, wr, wi, NULL, 1, V, N);
  int b = -1;
  for (int i = 0; i < N; i++)
    if (wi[i] > 0 && (b < 0 || wr[i] > wr[b])) b = i;
  int k = rr_nonlinear_index_y(nl, 0);
  /* z0 = Re(c v) with c making y_w1 real and 1 nm: a peak of the motion */
  double vr = V[k * N + b], vi = V[k * N + b + 1], den = vr * vr + vi * vi, cr = vr / den * 1e-9,
         ci = -vi / den * 1e-9;
  double *z0 = malloc(sizeof(double) * N);
  for (int i = 0; i < N; i++) z0[i] = cr * V[i * N + b] - ci * V[i * N + b + 1];
  double T = 2 * RR_PI / wi[b];
  int periods = 20, ns = periods * 8 + 1;
  rr_sim_opts so = rr_sim_opts_default();
  so.duration_s = periods * T;
  so.fs_hz = (ns - 1) / so.duration_s;
  so.rtol = 1e-10;
  so.atol_m = 1e-22;
  double *out = malloc(sizeof(double) * N * ns);
  rr_error e;
  int st = rr_simulate(nl, z0, &so, out, ns, &e);
  CHECK_OK(st, e);
  double sigma = log(out[(size_t)(ns - 1) * N + k] / z0[k]) /
                 so.duration_s; /* y(t + 20 T) = e^(20 sigma T) y(t) */
  CHECK_CLOSE(sigma, wr[b], 1e-3, 0,
              "growth rate of a tiny disturbance vs Re(least-damped eigenvalue), 1/s");
  free(A);
  free(wr);
  free(wi);
  free(V);
  free(z0);
  free(out);
  rr_nonlinear_free(nl);
}

/* x'' - (mu - x^2) x' + x = 0: averaging gives the cycle's amplitude
   2 sqrt(mu) (the energy balance mu pi A^2 = pi A^4 / 4) and period 2 pi. */
static void vdp_rhs(void *u, double t, double mu, const double *z, double *dz)
{
  (void)u;
  (void)t;
  dz[0] = z[1];
  dz[1] = (mu - z[0] * z[0]) * z[1] - z[0];
}

static void vdp_jac(void *u, double t, double mu, const double *z, double *J)
{
  (void)u;
  (void)t;
  J[0] = 0;
  J[1] = 1;
  J[2] = -2 * z[0] * z[1] - 1;
  J[3] = mu - z[0] * z[0];
}

/* The branch from the Hopf point at mu = 0, shot over the whole period and,
   the oscillator being odd, over half of it as a symmetric orbit: both meet
   averaging's amplitude, period and nontrivial multiplier exp(-2 pi mu) (the
   amplitude's own rate -mu over a period). */
static void test_van_der_pol(void)
{
  for (int odd = 0; odd < 2; odd++) {
    double atol[2] = {1, 1};
    rr_orbit_sys s = {.ode = {.n = 2, .rhs = vdp_rhs, .jac = vdp_jac},
                      .k_amp = 0,
                      .k_phase = 1,
                      .amp_unit = 1,
                      .p_unit = 0.1,
                      .atol = atol,
                      .odd = odd};
    rr_branch_opts bo = {.p_min = -1,
                         .p_max = 0.05,
                         .amp_max = 10,
                         .amp_start = 0.05,
                         .ds = 0.2,
                         .ds_max = 1,
                         .rtol = 1e-11,
                         .cap = 100};
    rr_orbit pts[100];
    int n = 0;
    rr_branch_end end;
    rr_error e;
    int st = rr_orbit_branch(&s, 0, &bo, pts, NULL, &n, &end, &e);
    CHECK_OK(st, e);
    CHECK(n >= 5 && end == 0, "van der Pol: %d points, end %d", n, end);
    for (int i = 0; i < n; i++) {
      if (pts[i].p > 0.05) continue;
      double mu = pts[i].p;
      CHECK_CLOSE(pts[i].amp, 2 * sqrt(mu), 0.01, 0, "van der Pol amplitude vs 2 sqrt(mu)");
      CHECK_CLOSE(pts[i].T, 2 * RR_PI, 0.01, 0, "van der Pol period vs 2 pi");
      CHECK_CLOSE(pts[i].floquet_max, exp(-2 * RR_PI * mu), 1e-3, 0,
                  "van der Pol multiplier vs exp(-2 pi mu)");
      CHECK(pts[i].stable && pts[i].residual <= 1e-8 && pts[i].symmetric == odd,
            "van der Pol cycle stable, residual %g", pts[i].residual);
    }
  }
}

/* The van der Pol oscillator with a dead-band spring beyond |x| = 0.3
   (k = 100): from mu = 0.0225 its cycles touch the band at both extremes,
   the one at x = -A inside the period (shot over the whole period), where
   the integration stops at the band's edges. Every such cycle's return map,
   integrated again by CVODE (BDF, through the kinks, tolerance 1e-12),
   closes to 1e-8. */
#define VDP_BAND 0.3
#define VDP_BAND_K 100

static void band_rhs(void *u, double t, double mu, const double *z, double *dz)
{
  vdp_rhs(u, t, mu, z, dz);
  double a = fabs(z[0]) - VDP_BAND;
  if (a > 0) dz[1] -= VDP_BAND_K * a * (z[0] > 0 ? 1 : -1);
}

static void band_jac(void *u, double t, double mu, const double *z, double *J)
{
  vdp_jac(u, t, mu, z, J);
  if (fabs(z[0]) > VDP_BAND) J[2] -= VDP_BAND_K;
}

static void band_kinks(void *u, double p, const double *z, double *g)
{
  (void)u;
  (void)p;
  g[0] = z[0] - VDP_BAND;
  g[1] = z[0] + VDP_BAND;
}

static void test_dead_band(void)
{
  double atol[2] = {1, 1};
  rr_orbit_sys s = {.ode = {.n = 2, .rhs = band_rhs, .jac = band_jac},
                    .nkinks = 2,
                    .kinks = band_kinks,
                    .k_amp = 0,
                    .k_phase = 1,
                    .amp_unit = 0.1,
                    .p_unit = 0.01,
                    .atol = atol};
  rr_branch_opts bo = {.p_min = -1,
                       .p_max = 0.05,
                       .amp_max = 10,
                       .amp_start = 0.05,
                       .ds = 0.2,
                       .ds_max = 0.5,
                       .rtol = 1e-11,
                       .cap = 100};
  rr_orbit pts[100];
  double Z[200];
  int n = 0, touching = 0;
  rr_branch_end end;
  rr_error e;
  int st = rr_orbit_branch(&s, 0, &bo, pts, Z, &n, &end, &e);
  CHECK_OK(st, e);
  for (int i = 0; i < n && !st; i++) {
    if (pts[i].amp <= VDP_BAND) continue;
    touching++;
    double atol_cv[2] = {1e-14, 1e-14}, t = 0;
    ode_cv c;
    st = rr_ode_open(&c, &s.ode, pts[i].p, Z + 2 * i, 1e-12, atol_cv, &e);
    CHECK_OK(st, e);
    CVodeSetStopTime(c.mem, pts[i].T);
    CVode(c.mem, pts[i].T, c.y, &t, CV_NORMAL);
    const double *y = N_VGetArrayPointer(c.y), *z0 = Z + 2 * i;
    double res = hypot(y[0] - z0[0], y[1] - z0[1]) / hypot(z0[0], z0[1]);
    CHECK(res <= 1e-8, "touching cycle (mu %.4f, amplitude %.6f): CVODE's return %.1e", pts[i].p,
          pts[i].amp, res);
    rr_ode_close(&c);
  }
  CHECK(touching >= 3 && end == 0, "cycles touching the band: %d of %d (end %d)", touching, n, end);
}

/* Constant conicity, no saturation, no flange: a linear model, no branch;
   direct integration grows or decays at a constant rate, never settles. */
static void test_linear_no_branch(void)
{
  rr_vehicle veh;
  rr_vehicle_open("type1", &veh, NULL);
  rr_profile p;
  rr_error e;
  double c0 = 0.3;
  rr_profile_poly(&c0, 1, 12, &p, &e);
  rr_contact_law law = rr_contact_law_default();
  law.saturation = 0;
  law.flange_stiffness = 0;
  rr_cycle pts[8];
  rr_bifurcation b;
  int st = rr_bifurcation_continue(&veh, &p, &law, NULL, pts, NULL, 8, &b, &e);
  CHECK_OK(st, e);
  CHECK(b.hopf && b.npoints == 0 && b.end == RR_BRANCH_LINEAR && b.type == RR_BIF_NONE,
        "linear model: hopf %d, %d points, end %d, type %d", b.hopf, b.npoints, b.end, b.type);
  for (int side = -1; side <= 1; side += 2) {
    rr_nonlinear *nl;
    st = rr_nonlinear_from_vehicle(&veh, &p, &law, b.hopf_speed_ms * (1 + 0.01 * side), &nl, &e);
    CHECK_OK(st, e);
    int N = rr_nonlinear_size(nl), k = rr_nonlinear_index_y(nl, 0), ns = 4001;
    double *z = calloc(N, sizeof(double)), *out = malloc(sizeof(double) * N * ns),
           amp[4] = {0, 0, 0, 0};
    for (int w = 0; w < 4; w++) z[rr_nonlinear_index_y(nl, w)] = 1e-3;
    rr_sim_opts so = rr_sim_opts_default();
    so.duration_s = 40;
    so.fs_hz = 100;
    st = rr_simulate(nl, z, &so, out, ns, &e);
    CHECK_OK(st, e);
    for (int i = 1; i < ns; i++)
      amp[i * 4 / ns] = fmax(amp[i * 4 / ns], fabs(out[(size_t)i * N + k]));
    double r1 = amp[2] / amp[1], r2 = amp[3] / amp[2]; /* after 10 s: the hunting mode alone */
    CHECK(side < 0 ? r1 < 1 && r2 < 1 : r1 > 1 && r2 > 1,
          "linear model %s the Hopf point: ratios %g %g", side < 0 ? "below" : "above", r1, r2);
    CHECK_CLOSE(r2, r1, 0.05, 0, "linear model: a constant rate, no cycle to settle on");
    free(z);
    free(out);
    rr_nonlinear_free(nl);
  }
}

/* Amplitude and frequency of y_w1 over the last `last` seconds of a run of
   `dur` seconds from z0 at the nonlinear vehicle's speed. */
static void run_measure(rr_nonlinear *nl, const double *z0, double dur, double last, double *amp,
                        double *freq)
{
  int N = rr_nonlinear_size(nl), k = rr_nonlinear_index_y(nl, 0), ns = (int)(dur * 2000) + 1;
  double *out = malloc(sizeof(double) * N * ns), t_first = 0, t_last = 0;
  rr_sim_opts so = rr_sim_opts_default();
  so.duration_s = dur;
  so.fs_hz = 2000;
  so.rtol = 1e-9;
  so.atol_m = 1e-12;
  rr_error e;
  int st = rr_simulate(nl, z0, &so, out, ns, &e), nc = 0;
  CHECK_OK(st, e);
  *amp = 0;
  for (int i = (int)((dur - last) * 2000); i < ns; i++) {
    double y = out[(size_t)i * N + k], yp = out[(size_t)(i - 1) * N + k];
    *amp = fmax(*amp, fabs(y));
    if (yp < 0 && y >= 0) {
      double t = (i - 1 + yp / (yp - y)) / 2000.0;
      if (!nc) t_first = t;
      t_last = t;
      nc++;
    }
  }
  *freq = (nc - 1) / (t_last - t_first);
  free(out);
}

/* The branch's amplitude at speed v (linear between its points; NaN outside). */
static double branch_amplitude(const rr_cycle *c, int n, double v)
{
  for (int i = 1; i < n; i++)
    if ((c[i - 1].speed_ms - v) * (c[i].speed_ms - v) <= 0) {
      double u = (v - c[i - 1].speed_ms) / (c[i].speed_ms - c[i - 1].speed_ms);
      return c[i - 1].amplitude_m + u * (c[i].amplitude_m - c[i - 1].amplitude_m);
    }
  return NAN;
}

/* The scan (direct integration, the paper's method) from far below the Hopf
   point: the motion dies out there, and the way up must still find the cycles
   beyond it, at the amplitudes of the continuation's stable branch. */
static void check_scan(const rr_vehicle *veh, const rr_profile *p, const rr_cycle *c, int n,
                       double v_hopf)
{
  double kmh[4] = {300, 440, 575, 580}, vs[4];
  rr_scan_point up[4], down[4];
  rr_error e;
  for (int i = 0; i < 4; i++) vs[i] = kmh[i] * KMH;
  int st = rr_bifurcation_scan(veh, p, NULL, vs, 4, NULL, up, down, &e);
  CHECK_OK(st, e);
  for (int i = 0; i < 4 && !st; i++) {
    double want = vs[i] < v_hopf ? 0 : branch_amplitude(c, n, vs[i]);
    CHECK(isfinite(want), "scan at %g km/h: the branch covers it", kmh[i]);
    CHECK_CLOSE(up[i].amplitude_m, want, 0.01, 0, "scan up: amplitude against the branch");
    CHECK_CLOSE(down[i].amplitude_m, want, 0.01, 0, "scan down: amplitude against the branch");
  }
}

/* The fold's speed (the nonlinear critical speed) against a second method:
   cycles shot over the whole period at fixed amplitudes on a grid 0.02 mm
   apart around the branch's lowest cycle, the parabola through the lowest
   grid point and its neighbours. */
static void check_fold(const rr_vehicle *veh, const rr_profile *p, const rr_cycle *c,
                       const double *Z, int n, double v_fold)
{
  int b = 0;
  for (int i = 1; i < n; i++)
    if (c[i].speed_ms < c[b].speed_ms) b = i;
  rr_nonlinear *nl;
  rr_error e;
  int st = rr_nonlinear_from_vehicle(veh, p, NULL, c[b].speed_ms, &nl, &e);
  CHECK_OK(st, e);
  rr_orbit_sys s;
  double *atol, grid[13], h = 0.02e-3, a0 = c[b].amplitude_m - 6 * h;
  rr_nonlinear_orbit_sys(nl, &s, &atol, &e);
  int N = s.ode.n, lo = 0;
  double *z = malloc(sizeof(double) * N);
  for (int k = 0; k < 13 && !st; k++) {
    double T = c[b].period_s, v = c[b].speed_ms;
    rr_orbit r;
    memcpy(z, Z + (size_t)b * N, sizeof(double) * N);
    st = rr_orbit_solve(&s, z, &T, &v, 1e-10, 1, a0 + k * h, &r, &e);
    CHECK_OK(st, e);
    grid[k] = v;
    if (grid[k] < grid[lo]) lo = k;
  }
  CHECK(lo > 0 && lo < 12, "the grid brackets the fold (lowest at %d)", lo);
  if (!st && lo > 0 && lo < 12) {
    double curv = grid[lo - 1] - 2 * grid[lo] + grid[lo + 1], slope = grid[lo + 1] - grid[lo - 1];
    double v_grid = grid[lo] - slope * slope / (8 * curv);
    CHECK_CLOSE(v_fold * RR_KMH, v_grid * RR_KMH, 0, 5e-4,
                "the fold's speed, km/h, against fixed-amplitude cycles on a grid");
  }
  free(z);
  free(atol);
  rr_nonlinear_free(nl);
}

/* The continuation's branches, checked: Hopf speed, residuals, stable cycles
   reproduced by direct integration, unstable ones left along their unstable
   Floquet vector. A subcritical case: conicity rising with amplitude. */
static void test_branch(const char *veh_file_text, const char *prof, double v_hi_kmh,
                        rr_bif_type want_type)
{
  rr_vehicle veh;
  rr_error e;
  int st;
  if (veh_file_text)
    st = rr_vehicle_load(check_write_file("veh.ini", veh_file_text), &veh, &e);
  else
    st = rr_vehicle_open("type1", &veh, &e);
  CHECK_OK(st, e);
  rr_profile p;
  if (prof)
    rr_profile_open(prof, &p, &e);
  else
    p = veh.profile;
  rr_orbit_opts o = rr_orbit_opts_default();
  o.v_max_ms = v_hi_kmh * KMH;
  int cap = 200;
  rr_cycle *pts = malloc(sizeof *pts * cap);
  double *Z = malloc(sizeof(double) * 64 * cap);
  rr_bifurcation b;
  st = rr_bifurcation_continue(&veh, &p, NULL, &o, pts, Z, cap, &b, &e);
  CHECK_OK(st, e);
  CHECK(b.type == want_type && b.npoints >= 5, "branch type %d (want %d), %d points", b.type,
        want_type, b.npoints);
  /* the Hopf point: an independent critical-speed call, and the branch's own extrapolation */
  rr_model *m;
  rr_model_from_vehicle(&veh, &m, &e);
  rr_modal_ws *ws;
  rr_modal_ws_new(m, &ws, &e);
  rr_critical_opts co = rr_critical_opts_default();
  co.v_max_ms = 1000 * KMH;
  rr_critical cr;
  st = rr_critical_speed(m, rr_profile_conicity(&p, 0), NULL, &co, ws, &cr, &e);
  CHECK_OK(st, e);
  CHECK(fabs(b.hopf_speed_branch_ms - cr.speed_ms) * RR_KMH <= 0.1,
        "branch's Hopf %.4f vs critical-speed %.4f km/h", b.hopf_speed_branch_ms * RR_KMH,
        cr.speed_ms * RR_KMH);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (want_type == RR_BIF_SUPERCRITICAL) check_scan(&veh, &p, pts, b.npoints, b.hopf_speed_ms);
  int N = 0, checked_stable = 0, checked_unstable = 0, first_stable = -1, worst = -1;
  for (int i = 0; i < b.npoints; i++) {
    CHECK(pts[i].residual <= 1e-8, "cycle %d: residual %g", i, pts[i].residual);
    if (pts[i].stable && first_stable < 0)
      first_stable = i;
    else if (first_stable < 0 && (worst < 0 || pts[i].floquet_max > pts[worst].floquet_max))
      worst = i; /* before the fold */
  }
  int run_end = first_stable; /* the first run of stable cycles; two well inside it */
  while (run_end >= 0 && run_end + 1 < b.npoints && pts[run_end + 1].stable) run_end++;
  int mid = first_stable < 0 ? -1 : (first_stable + run_end) / 2;
  int picks[3] = {mid,
                  first_stable < 0                  ? -1
                  : (first_stable + mid) / 2 == mid ? run_end
                                                    : (first_stable + mid) / 2,
                  want_type == RR_BIF_SUBCRITICAL ? worst : -1};
  for (int q = 0; q < 3; q++) {
    int i = picks[q];
    if (i < 0) continue;
    rr_nonlinear *nl;
    st = rr_nonlinear_from_vehicle(&veh, &p, NULL, pts[i].speed_ms, &nl, &e);
    CHECK_OK(st, e);
    N = rr_nonlinear_size(nl);
    double *z = malloc(sizeof(double) * N), amp, freq;
    if (q == 0) { /* shot again over the whole period: the same cycle */
      double *zf = malloc(sizeof(double) * N), T = pts[i].period_s;
      memcpy(zf, Z + (size_t)i * N, sizeof(double) * N);
      rr_cycle full;
      st = rr_cycle_shoot(nl, zf, &T, 0, &full, &e);
      CHECK_OK(st, e);
      CHECK(pts[i].symmetric && !full.symmetric && full.residual <= 1e-8,
            "symmetric branch point, shot as a whole period (residual %g)", full.residual);
      CHECK_CLOSE(full.period_s, pts[i].period_s, 1e-8, 0, "period: whole against half");
      CHECK_CLOSE(full.amplitude_m, pts[i].amplitude_m, 1e-7, 0, "amplitude: whole against half");
      CHECK_CLOSE(full.floquet_max, pts[i].floquet_max, 1e-4, 0, "max |mu|: whole against half");
      free(zf);
    }
    if (pts[i].stable) { /* from 0.5 % off the cycle, direct integration stays on it */
      for (int j = 0; j < N; j++) z[j] = Z[(size_t)i * N + j] * 1.005;
      run_measure(nl, z, 12, 1, &amp, &freq);
      CHECK_CLOSE(amp, pts[i].amplitude_m, 0.01, 0,
                  "stable cycle: amplitude by direct integration");
      CHECK_CLOSE(freq, 1 / pts[i].period_s, 0.005, 0,
                  "stable cycle: frequency by direct integration");
      checked_stable++;
    } else { /* along the unstable Floquet vector, both ways: away from the cycle */
      rr_orbit_sys s;
      double *atol, mu, *v = malloc(sizeof(double) * N), dev[2];
      rr_nonlinear_orbit_sys(nl, &s, &atol, &e);
      st = rr_orbit_floquet_vector(&s, Z + (size_t)i * N, pts[i].period_s, pts[i].speed_ms, &mu, v,
                                   &e);
      CHECK_OK(st, e);
      double scale = 0.01 * pts[i].amplitude_m / fabs(v[rr_nonlinear_index_y(nl, 0)] + 1e-300);
      int periods = (int)ceil(log(20.0) / log(mu)); /* the perturbation grows 20-fold, linearly */
      for (int sgn = 0; sgn < 2; sgn++) {
        for (int j = 0; j < N; j++) z[j] = Z[(size_t)i * N + j] + (sgn ? -scale : scale) * v[j];
        run_measure(nl, z, periods * pts[i].period_s, 2 * pts[i].period_s, &amp, &freq);
        dev[sgn] = amp - pts[i].amplitude_m;
      }
      CHECK(mu > 1 && fabs(dev[0]) > 0.05 * pts[i].amplitude_m &&
                fabs(dev[1]) > 0.05 * pts[i].amplitude_m && dev[0] * dev[1] < 0,
            "unstable cycle (|mu| %g): perturbed both ways it leaves (amplitude changes %g, %g of "
            "%g m)",
            mu, dev[0], dev[1], pts[i].amplitude_m);
      checked_unstable++;
      free(v);
      free(atol);
    }
    free(z);
    rr_nonlinear_free(nl);
  }
  CHECK(checked_stable == 2 && checked_unstable == (want_type == RR_BIF_SUBCRITICAL),
        "checked %d stable, %d unstable", checked_stable, checked_unstable);
  if (want_type == RR_BIF_SUBCRITICAL) {
    CHECK(b.nonlinear_critical_ms < b.hopf_speed_ms - 5 * KMH,
          "subcritical: nonlinear critical %.2f below Hopf %.2f km/h",
          b.nonlinear_critical_ms * RR_KMH, b.hopf_speed_ms * RR_KMH);
    check_fold(&veh, &p, pts, Z, b.npoints, b.nonlinear_critical_ms);
  } else
    CHECK_CLOSE(b.nonlinear_critical_ms, b.hopf_speed_ms, 1e-12, 0,
                "supercritical: nonlinear = linear critical speed");
  free(pts);
  free(Z);
}

/* Half a period of direct integration (CVODE, tight) from z0 + h v and
   z0 - h v: the central difference d = Phi_half v, the half period's flow
   Jacobian along v. */
static void half_period_jvp(rr_nonlinear *nl, const double *z0, const double *v, double h, double T,
                            double *d)
{
  int N = rr_nonlinear_size(nl);
  double *z = malloc(sizeof(double) * N), *out = malloc(sizeof(double) * 2 * N);
  rr_sim_opts so = rr_sim_opts_default();
  so.duration_s = T / 2;
  so.fs_hz = 2 / T; /* the second sample at T / 2 */
  so.rtol = 1e-11;
  so.atol_m = 1e-14;
  rr_error e;
  for (int sgn = 1; sgn >= -1; sgn -= 2) {
    for (int j = 0; j < N; j++) z[j] = z0[j] + sgn * h * v[j];
    int st = rr_simulate(nl, z, &so, out, 2, &e);
    CHECK_OK(st, e);
    for (int j = 0; j < N; j++) d[j] = sgn > 0 ? out[N + j] : (d[j] - out[N + j]) / (2 * h);
  }
  free(z);
  free(out);
}

/* Type 2 on the worn tread: the symmetric branch loses stability where a
   real multiplier of its half-period map passes -1 (a wheelset reaching the
   flange). Checked beyond that point by the full period's monodromy matrix
   (its largest multiplier mu, the half map's squared) and by direct
   integration: half a period from the cycle pushed along mu's vector v
   takes the push to +sqrt(mu) v while the cycle itself turns to -z0 (the
   half map, z -> -z(T/2), has -sqrt(mu): the growing motion breaks the
   symmetry; a symmetric instability would give -sqrt(mu) v). */
static void test_symmetry_breaking(void)
{
  rr_vehicle veh;
  rr_profile p;
  rr_error e;
  rr_vehicle_open("type2", &veh, &e);
  rr_profile_open("worn", &p, &e);
  rr_orbit_opts o = rr_orbit_opts_default();
  o.v_max_ms = 548 * KMH;
  int cap = 100;
  rr_cycle *pts = malloc(sizeof *pts * cap);
  double *Z = malloc(sizeof(double) * 64 * cap);
  rr_bifurcation b;
  int st = rr_bifurcation_continue(&veh, &p, NULL, &o, pts, Z, cap, &b, &e);
  CHECK_OK(st, e);
  int ev = -1;
  for (int i = 0; i < b.nevents && ev < 0; i++)
    if (b.events[i].kind == RR_EVENT_SYMMETRY_BREAKING) ev = i;
  CHECK(ev >= 0 && b.events[ev].gained == 1 && b.events[ev].speed_ms > 530 * KMH &&
            b.events[ev].speed_ms < 548 * KMH,
        "Type 2 worn: symmetry breaking found (%d events)", b.nevents);
  if (ev >= 0) {
    int i = b.events[ev].index;
    const rr_bif_event *be = &b.events[ev];
    CHECK(pts[i - 1].stable && !pts[i].stable && pts[i - 1].symmetric && pts[i].symmetric,
          "stable symmetric cycles, then unstable ones");
    CHECK(be->speed_lo_ms >= pts[i - 1].speed_ms && be->speed_hi_ms <= pts[i].speed_ms &&
              be->speed_hi_ms - be->speed_lo_ms <= 0.2 * KMH,
          "the event located between cycles %.3f and %.3f km/h apart (%.3f - %.3f)",
          pts[i - 1].speed_ms * RR_KMH, pts[i].speed_ms * RR_KMH, be->speed_lo_ms * RR_KMH,
          be->speed_hi_ms * RR_KMH);
    rr_nonlinear *nl;
    st = rr_nonlinear_from_vehicle(&veh, &p, NULL, pts[i].speed_ms, &nl, &e);
    CHECK_OK(st, e);
    int N = rr_nonlinear_size(nl);
    rr_orbit_sys s;
    double *atol, mu, *v = malloc(sizeof(double) * N), *d = malloc(sizeof(double) * N);
    rr_nonlinear_orbit_sys(nl, &s, &atol, &e);
    const double *z0 = Z + (size_t)i * N;
    st = rr_orbit_floquet_vector(&s, z0, pts[i].period_s, pts[i].speed_ms, &mu, v, &e);
    CHECK_OK(st, e);
    /* an unstable cycle's multiplier (~20) is sensitive to rounding: the
       same build gives 20.04 or 19.96 on AVX2 and AVX-512 BLAS kernels */
    CHECK_CLOSE(mu, pts[i].floquet_max, 1e-2, 0,
                "the full period's largest multiplier vs the half period's squared");
    double vv = 0, dv = 0, rr = 0;
    for (int j = 0; j < N; j++) vv += v[j] * v[j];
    half_period_jvp(nl, z0, v, 1e-6 * sqrt(norm2sq(z0, N) / vv), pts[i].period_s, d);
    for (int j = 0; j < N; j++) dv += d[j] * v[j];
    for (int j = 0; j < N; j++) rr += pow(d[j] - dv / vv * v[j], 2);
    CHECK_CLOSE(dv / vv, sqrt(mu), 0.02, 0, "Phi_half v / v against +sqrt(mu)");
    CHECK(sqrt(rr) <= 0.02 * fabs(dv) / sqrt(vv), "Phi_half v along v (off by %g)",
          sqrt(rr) / (fabs(dv) / sqrt(vv)));
    free(v);
    free(d);
    free(atol);
    rr_nonlinear_free(nl);
  }
  free(pts);
  free(Z);
}

/* A grazing corner: design C of the study (stiff primary, weak yaw dampers)
   on the worn tread, subcritical, whose unstable branch falls until the
   leading wheelset reaches the flange (8 mm) at ~158.9 km/h. There the branch
   turns sharply back up in speed, with stable cycles in flange contact; the
   continuation steps past the corner (the branch goes on to the range's end),
   the corner is the lowest speed (the nonlinear critical speed, a fold), and
   direct integration from a stable cycle beyond it stays on it. */
static void test_grazing_corner(void)
{
  rr_vehicle veh;
  rr_profile p;
  rr_error e;
  int st = rr_vehicle_load(check_write_file("C.ini", "[vehicle]\nbase = type1\n[primary]\n"
                                                     "longitudinal_stiffness = 119.721 kN/mm\n"
                                                     "[lateral_damper]\ndamping = 59.9985 kN.s/m\n"
                                                     "[yaw_damper]\ndamping = 235.793 kN.s/m\n"
                                                     "series_stiffness = 29.9975 MN/m\n"),
                           &veh, &e);
  CHECK_OK(st, e);
  rr_profile_open("worn", &p, &e);
  rr_orbit_opts o = rr_orbit_opts_default();
  o.v_max_ms = 200 * KMH;
  int cap = 200, beyond = -1, corner = -1;
  rr_cycle *pts = malloc(sizeof *pts * cap);
  double *Z = malloc(sizeof(double) * 64 * cap);
  rr_bifurcation b;
  st = rr_bifurcation_continue(&veh, &p, NULL, &o, pts, Z, cap, &b, &e);
  CHECK_OK(st, e);
  CHECK(b.type == RR_BIF_SUBCRITICAL && b.end == RR_BRANCH_RANGE,
        "design C worn: subcritical, the branch to the range's end (end %d)", b.end);
  for (int i = 0; i < b.npoints; i++) {
    if (corner < 0 || pts[i].speed_ms < pts[corner].speed_ms) corner = i;
    if (beyond < 0 && corner >= 0 && i > corner && pts[i].amplitude_m > veh.flange_clearance &&
        pts[i].stable && pts[i].speed_ms > pts[corner].speed_ms + 10 * KMH)
      beyond = i;
  }
  CHECK(corner > 0 && corner < b.npoints - 1 &&
            fabs(pts[corner].amplitude_m - veh.flange_clearance) < 0.02e-3,
        "the lowest cycle is the corner at the flange (%g mm)", pts[corner].amplitude_m * 1e3);
  CHECK_CLOSE(b.nonlinear_critical_ms, pts[corner].speed_ms, 1e-9, 0,
              "nonlinear critical speed: the corner's");
  int fold = 0;
  for (int i = 0; i < b.nevents; i++)
    fold |= b.events[i].kind == RR_EVENT_FOLD && b.events[i].gained < 0 &&
            b.events[i].index == corner + 1;
  CHECK(fold, "a fold at the corner, stable beyond it");
  CHECK(beyond > 0, "stable cycles in flange contact beyond the corner");
  for (int i = corner - 1; i <= corner + 2 && i > 0 && i < b.npoints; i++) { /* touches of um */
    rr_nonlinear *nl;
    st = rr_nonlinear_from_vehicle(&veh, &p, NULL, pts[i].speed_ms, &nl, &e);
    CHECK_OK(st, e);
    int N = rr_nonlinear_size(nl);
    double *out = malloc(sizeof(double) * 2 * N), d = 0;
    rr_sim_opts so = rr_sim_opts_default();
    so.duration_s = pts[i].period_s;
    so.fs_hz = 1 / pts[i].period_s;
    so.rtol = 1e-11;
    so.atol_m = 1e-14;
    st = rr_simulate(nl, Z + (size_t)i * N, &so, out, 2, &e);
    CHECK_OK(st, e);
    for (int j = 0; j < N; j++) d += pow(out[N + j] - out[j], 2);
    CHECK(sqrt(d / norm2sq(out, N)) <= 1e-7,
          "cycle %d by %.4f mm: periodic by direct integration too (%.1e)", i,
          pts[i].amplitude_m * 1e3, sqrt(d / norm2sq(out, N)));
    free(out);
    rr_nonlinear_free(nl);
  }
  if (beyond > 0) {
    rr_nonlinear *nl;
    st = rr_nonlinear_from_vehicle(&veh, &p, NULL, pts[beyond].speed_ms, &nl, &e);
    CHECK_OK(st, e);
    int N = rr_nonlinear_size(nl);
    double *z = malloc(sizeof(double) * N), amp, freq;
    for (int j = 0; j < N; j++) z[j] = Z[(size_t)beyond * N + j] * 1.005;
    run_measure(nl, z, 12, 1, &amp, &freq);
    CHECK_CLOSE(amp, pts[beyond].amplitude_m, 0.01, 0, "flange-contact cycle: amplitude");
    CHECK_CLOSE(freq, 1 / pts[beyond].period_s, 0.005, 0, "flange-contact cycle: frequency");
    free(z);
    rr_nonlinear_free(nl);
  }
  free(pts);
  free(Z);
}

/* Vehicle-file keys of the nonlinear model. */
static void test_vehicle_keys(void)
{
  rr_vehicle veh;
  rr_error e;
  int st = rr_vehicle_load(
      check_write_file("nl.ini", "[vehicle]\nbase = type1\n[contact]\nfriction = 0.25\n"
                                 "flange_clearance = 7 mm\nflange_stiffness = 400 kN/mm\n"
                                 "conicity_poly = 0.2, -0.01 0.0002\nconicity_hold = 10 mm\n"),
      &veh, &e);
  CHECK_OK(st, e);
  CHECK(veh.friction == 0.25 && fabs(veh.flange_clearance - 7e-3) < 1e-15 &&
            fabs(veh.flange_stiffness - 4e8) < 1e-3,
        "contact keys read");
  CHECK_CLOSE(rr_profile_conicity(&veh.profile, 5e-3), 0.2 - 0.05 + 0.005, 1e-14, 0,
              "conicity_poly at 5 mm");
  CHECK_CLOSE(rr_profile_conicity(&veh.profile, 20e-3), 0.2 - 0.1 + 0.02, 1e-14, 0,
              "conicity_poly held beyond 10 mm");
  st = rr_vehicle_load(
      check_write_file("nl2.ini",
                       "[vehicle]\nbase = type1\n[contact]\nconicity_poly = 0.2 -0.05\n"),
      &veh, &e);
  CHECK(st != 0 && strstr(e.msg, "nl2.ini:4") && strstr(e.msg, "conicity_poly"),
        "a profile going to zero: %s", e.msg);
}

int main(void)
{
  check_tmpdir("nonlinear");
  test_jacobian_at_zero();
  test_jacobian_fd();
  test_growth_rate();
  test_van_der_pol();
  test_dead_band();
  test_linear_no_branch();
  test_vehicle_keys();
  test_branch(NULL, "worn", 580, RR_BIF_SUPERCRITICAL);
  test_symmetry_breaking();
  test_grazing_corner();
  test_branch("[vehicle]\nbase = type1\n[contact]\nconicity_poly = 0.3 0.02\n", NULL, 600,
              RR_BIF_SUBCRITICAL);
  check_cleanup();
  return check_done("nonlinear");
}
