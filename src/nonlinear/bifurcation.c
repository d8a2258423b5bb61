/* Limit cycles of the nonlinear vehicle on straight, perfect track: the
 * diagram by continuation from the Hopf point (orbit.c), one cycle by
 * shooting, and the brute-force scan by direct integration, up and down in
 * speed (the paper's method). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <lapacke.h>
#include "railride/nonlinear.h"
#include "railride/stability.h"
#include "nonlinear/nonlinear_impl.h"
#include "nonlinear/orbit.h"
#include "util/internal.h"

#define AMP_UNIT 1e-3            /* arclength: 1 mm of amplitude ... */
#define SPEED_UNIT (10 / RR_KMH) /* ... weighs as 10 km/h */
#define AMP_START 0.02e-3        /* the first cycle's amplitude, m */
#define NEWTON_MAXIT_TABLE 40    /* shooting's Newton on contact functions (orbit.h) */
#define NEWTON_TOL_TABLE 5e-5    /* ... and its tolerance: 0.05 um on a 1 mm cycle */
#define RTOL_TABLE 1e-8          /* ... and the integration's, at least (the floor is Newton's) */
#define AMP_START_TABLE                                                                            \
  0.3e-3                         /* ... on contact functions: 30 of their grid steps, so that the  \
                                    first cycle sees their mean slope, not one segment's */
#define HOPF_V_MIN (10 / RR_KMH) /* the Hopf point is sought from here to RR_SPEED_MAX_MS */
#define HOPF_STEP (5 / RR_KMH)   /* in steps of 5 km/h, then bisected */
#define WINDOW_BEYOND 1.05       /* a Hopf point outside the range is followed this far past it */
#define SCAN_FS 1000.0           /* samples a second in the scan's runs */
#define SCAN_DEAD 1e-6           /* m: a motion below this has died out */
#define SCAN_DECAY 0.02          /* a motion decaying faster over the measured window dies out */

rr_orbit_opts rr_orbit_opts_default(void)
{
  return (rr_orbit_opts){.v_min_ms = RR_ORBIT_V_MIN_KMH / RR_KMH,
                         .v_max_ms = RR_ORBIT_V_MAX_KMH / RR_KMH,
                         .amp_max_m = 30e-3,
                         .ds = 0.2,
                         .max_points = 400,
                         .rtol = 1e-10};
}

rr_scan_opts rr_scan_opts_default(void)
{
  return (rr_scan_opts){.settle_s = 20, .measure_s = 2, .y0_m = 10e-3, .reseed_m = 0.1e-3};
}

static void sys_rhs(void *u, double t, double p, const double *z, double *dz)
{
  (void)t;
  rr_nonlinear_rhs_at(u, p, z, NULL, dz);
}

static void sys_jac(void *u, double t, double p, const double *z, double *J)
{
  (void)t;
  rr_nonlinear_jacobian_at(u, p, z, NULL, J);
}

static void sys_jvp(void *u, double p, const double *z, const double *X, int m, int dfdp,
                    double *out)
{
  rr_nonlinear_jvp_at(u, p, z, X, m, dfdp, out);
}

static void sys_kinks(void *u, double p, const double *z, double *g)
{
  rr_nonlinear_kinks_at(u, p, z, g);
}

static void sys_start_jac(void *u, double p, double amp, double *J)
{
  rr_nonlinear_jacobian_harmonic_at(u, p, amp, J);
}

static int neutral_speed(const rr_nonlinear *nl, double amp, double *v_out, double *f_out,
                         rr_error *err);

static int sys_start_p(void *u, double amp, double *p, rr_error *err)
{
  double f;
  return neutral_speed(u, amp, p, &f, err);
}

/* The vehicle as an orbit system: amplitude y_w1, phase dy_w1/dt = 0. */
int rr_nonlinear_orbit_sys(rr_nonlinear *nl, rr_orbit_sys *s, double **atol, rr_error *err)
{
  int N = rr_nonlinear_size(nl), k = rr_nonlinear_index_y(nl, 0);
  if (k < 0) return rr_seterr(err, RR_EINVAL, "orbit: the model has no wheelset");
  int nk = rr_nonlinear_kinks_at(nl, 1, NULL, NULL);
  if (nk > RR_ORBIT_MAX_KINKS)
    return rr_seterr(err, RR_EUNSUP, "orbit: more than %d wheelset kinks", RR_ORBIT_MAX_KINKS);
  *atol = malloc(sizeof(double) * (size_t)N);
  if (!*atol) return rr_seterr(err, RR_ENOMEM, "out of memory");
  rr_nonlinear_atol(nl, AMP_UNIT, *atol); /* magnitudes on a 1 mm orbit */
  *s = (rr_orbit_sys){.ode = {.n = N, .rhs = sys_rhs, .jac = sys_jac, .user = nl},
                      .jvp = sys_jvp,
                      .nkinks = nk,
                      .kinks = sys_kinks,
                      .k_amp = k,
                      .k_phase = rr_nonlinear_ndof(nl) + k,
                      .amp_unit = AMP_UNIT,
                      .p_unit = SPEED_UNIT,
                      .atol = *atol,
                      /* straight, perfect track: the vehicle is left-right symmetric (and so
                         are its contact functions when the profiles are mirrored) */
                      .odd = rr_nonlinear_is_odd(nl)};
  double lo, hi;
  rr_nonlinear_contact_range(nl, &lo, &hi);
  if (isfinite(lo) || isfinite(hi)) {
    s->start_jac = sys_start_jac;
    s->start_p = sys_start_p;
    s->newton_maxit = NEWTON_MAXIT_TABLE;
    s->newton_tol = NEWTON_TOL_TABLE;
  }
  return RR_OK;
}

static rr_cycle cycle_of(const rr_orbit *o)
{
  return (rr_cycle){.speed_ms = o->p,
                    .period_s = o->T,
                    .amplitude_m = o->amp,
                    .floquet_max = o->floquet_max,
                    .stable = o->stable,
                    .symmetric = o->symmetric,
                    .residual = o->residual};
}

/* The kind of crossing between two points whose unstable dimension differs:
   the kind whose count moved most the same way (two real multipliers
   outside that meet and leave the real axis change no dimension). */
static rr_bif_event_kind crossing_kind(const rr_orbit *a, const rr_orbit *b, int gained)
{
  static const int weight[RR_CROSS_KINDS] = {1, 1, 2};
  int best = 0, kind = RR_CROSS_FOLD;
  for (int k = 0; k < RR_CROSS_KINDS; k++) {
    int moved = (b->outside[k] - a->outside[k]) * weight[k] * (gained > 0 ? 1 : -1);
    if (moved > best) {
      best = moved;
      kind = k;
    }
  }
  if (kind == RR_CROSS_FOLD) return RR_EVENT_FOLD;
  if (kind == RR_CROSS_TORUS) return RR_EVENT_TORUS;
  return b->symmetric ? RR_EVENT_SYMMETRY_BREAKING : RR_EVENT_PERIOD_DOUBLING;
}

#define EVENT_DS 0.01 /* events are located to this arclength (0.1 km/h or 0.01 mm) */

/* The stability changes along the branch, each located between cycles on
   the branch closer than EVENT_DS (rr_orbit_bisect from the two cycles
   around it; where that fails, those two stand). Z: the cycles' states. */
static void find_events(const rr_orbit_sys *s, const rr_orbit_opts *opt, const rr_orbit *o,
                        const double *Z, int n, rr_bifurcation *res)
{
  int N = s->ode.n;
  double *X = malloc(sizeof(double) * 2 * ((size_t)N + 2)), *Y = X + N + 2;
  res->nevents = 0;
  for (int i = 1; i < n && res->nevents < RR_BIF_MAX_EVENTS; i++) {
    int gained = rr_orbit_unstable_dims(&o[i]) - rr_orbit_unstable_dims(&o[i - 1]);
    if (!gained) continue;
    double lo = o[i - 1].p, hi = o[i].p;
    if (X) {
      rr_orbit ra = o[i - 1], rb = o[i];
      rr_error e;
      memcpy(X, Z + (size_t)(i - 1) * (size_t)N, sizeof(double) * (size_t)N);
      memcpy(Y, Z + (size_t)i * (size_t)N, sizeof(double) * (size_t)N);
      X[N] = ra.T, X[N + 1] = ra.p, Y[N] = rb.T, Y[N + 1] = rb.p;
      if (!rr_orbit_bisect(s, &opt->runner, X, &ra, Y, &rb, EVENT_DS, opt->rtol, &e)) {
        lo = X[N + 1];
        hi = Y[N + 1];
      }
    }
    res->events[res->nevents++] = (rr_bif_event){.kind = crossing_kind(&o[i - 1], &o[i], gained),
                                                 .index = i,
                                                 .speed_ms = 0.5 * (lo + hi),
                                                 .speed_lo_ms = fmin(lo, hi),
                                                 .speed_hi_ms = fmax(lo, hi),
                                                 .gained = gained};
  }
  free(X);
}

static rr_contact_law law_of(const rr_vehicle *veh)
{
  rr_contact_law l = rr_contact_law_default();
  l.friction = veh->friction;
  l.flange_clearance = veh->flange_clearance;
  l.flange_stiffness = veh->flange_stiffness;
  return l;
}

/* The tread profile: the one given, else NULL when the vehicle has wheel
   and rail profiles (their contact functions), else the vehicle's lambda(a). */
static int profile_of(const rr_vehicle *veh, const rr_profile **p, rr_error *err)
{
  if (*p || rr_vehicle_has_profiles(veh)) return RR_OK;
  if (veh->profile.kind == RR_PROFILE_NONE)
    return rr_seterr(err, RR_EINVAL,
                     "no tread profile: give one (new, worn or a table), [contact] wheel and rail "
                     "profiles, or conicity_poly / conicity_table");
  *p = &veh->profile;
  return RR_OK;
}

/* The slope of dr / 2 at y = 0 (the contact functions' conicity there),
   within the model's range: the model's operating conicity, which the
   nonlinear vehicle does not read (its contact terms are the tables'). */
static double table_conicity(const rr_contact_functions *cf)
{
  int k = (int)lround(-cf->y0_m / cf->dy_m);
  double lam = k > 0 && k < cf->n - 1 ? (cf->dr_m[k + 1] - cf->dr_m[k - 1]) / (4 * cf->dy_m) : 0;
  return isfinite(lam) ? fmin(fmax(lam, 0), RR_CONICITY_MAX) : 0;
}

/* The model at (v, lambda(0)) and the nonlinear vehicle on it; p NULL: on
   the vehicle's profiles' contact functions. */
static int build(const rr_vehicle *veh, const rr_profile *p, const rr_contact_law *law, double v,
                 rr_model **m, rr_nonlinear **nl, rr_error *err)
{
  *m = NULL;
  *nl = NULL;
  rr_contact_law def;
  if (!law) {
    def = law_of(veh);
    law = &def;
  }
  rr_contact_functions cf = {0};
  int st = p ? RR_OK : rr_vehicle_contact_functions(veh, &cf, err);
  if (!st) st = rr_model_from_vehicle(veh, m, err);
  if (!st)
    st = rr_model_set_operating(*m, v, p ? rr_profile_conicity(p, 0) : table_conicity(&cf), err);
  if (!st)
    st =
        p ? rr_nonlinear_new(*m, p, law, nl, err) : rr_nonlinear_new_contact(*m, &cf, law, nl, err);
  rr_contact_functions_free(&cf);
  if (st) {
    rr_model_free(*m);
    *m = NULL;
  }
  return st;
}

int rr_nonlinear_from_vehicle(const rr_vehicle *veh, const rr_profile *p, const rr_contact_law *law,
                              double v, rr_nonlinear **out, rr_error *err)
{
  *out = NULL;
  int st0 = profile_of(veh, &p, err);
  if (st0) return st0;
  rr_model *m;
  int st = build(veh, p, law, v, &m, out, err);
  rr_model_free(m);
  return st;
}

/* Nothing nonlinear left: constant conicity, no saturation, no flange
   (contact functions, p NULL, count as nonlinear). */
static int is_linear(const rr_profile *p, const rr_contact_law *law)
{
  if (!p || law->saturation || law->flange_stiffness > 0) return 0;
  for (int i = 1; i < p->n; i++)
    if (p->kind == RR_PROFILE_POLY ? p->c[i] != 0 : p->lam[i] != p->lam[0]) return 0;
  return 1;
}

/* The Hopf point: the linear critical speed at lambda(0), any oscillatory mode. */
static int hopf_point(rr_model *m, double lam0, rr_bifurcation *res, rr_error *err)
{
  rr_modal_ws *ws;
  int st = rr_modal_ws_new(m, &ws, err);
  if (st) return st;
  rr_critical_opts co = rr_critical_opts_default();
  co.v_min_ms = HOPF_V_MIN;
  co.step_ms = HOPF_STEP;
  co.v_max_ms = RR_SPEED_MAX_MS;
  co.index_modes = 0;
  rr_critical cr;
  st = rr_critical_speed(m, lam0, NULL, &co, ws, &cr, err);
  rr_modal_ws_free(ws);
  if (!st && cr.found) {
    res->hopf = 1;
    res->hopf_speed_ms = cr.speed_ms;
    res->hopf_freq_hz = cr.mode.freq_hz;
  }
  return st;
}

/* The largest real part of the oscillatory eigenvalues of df/dz at the
   straight-track equilibrium at speed v (amp > 0: with the contact
   functions' harmonic slopes at that amplitude), and that eigenvalue's
   frequency. w: N x N + 2 N scratch. */
static int equilibrium_rate(const rr_nonlinear *nl, double v, double amp, double *w, double *rate,
                            double *freq_hz, rr_error *err)
{
  int N = rr_nonlinear_size(nl);
  double *J = w, *wr = J + (size_t)N * (size_t)N, *wi = wr + N;
  rr_nonlinear_jacobian_harmonic_at(nl, v, amp, J);
  if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', N, J, N, wr, wi, NULL, 1, NULL, 1))
    return rr_seterr(err, RR_ELAPACK, "bifurcation: dgeev failed at the equilibrium");
  *rate = -INFINITY;
  *freq_hz = NAN;
  for (int i = 0; i < N; i++)
    if (wi[i] > 1e-6 * hypot(wr[i], wi[i]) && wr[i] > *rate) {
      *rate = wr[i];
      *freq_hz = wi[i] / (2 * RR_PI);
    }
  return RR_OK;
}

/* The lowest speed from HOPF_V_MIN at which an oscillatory eigenvalue of
   the linearisation at amplitude amp (0: the equilibrium's own, the contact
   functions' slopes at y = 0 and the normal forces' stiffness included)
   crosses into the right half-plane, in HOPF_STEP steps, then bisected to
   HOPF_TOL; NaN when none up to RR_SPEED_MAX_MS. */
#define HOPF_TOL (1e-6 / RR_KMH)
static int neutral_speed(const rr_nonlinear *nl, double amp, double *v_out, double *f_out,
                         rr_error *err)
{
  int N = rr_nonlinear_size(nl);
  double *w = malloc(sizeof(double) * ((size_t)N * (size_t)N + 2 * (size_t)N)), r, f = NAN;
  if (!w) return rr_seterr(err, RR_ENOMEM, "out of memory");
  double lo = HOPF_V_MIN, hi = NAN;
  int st = equilibrium_rate(nl, lo, amp, w, &r, &f, err);
  if (!st && r >= 0) hi = lo;
  for (double v = lo + HOPF_STEP; !st && isnan(hi) && v < RR_SPEED_MAX_MS + HOPF_STEP;
       v += HOPF_STEP) {
    double vc = fmin(v, RR_SPEED_MAX_MS);
    if ((st = equilibrium_rate(nl, vc, amp, w, &r, &f, err))) break;
    if (r >= 0)
      hi = vc;
    else
      lo = vc;
  }
  while (!st && isfinite(hi) && hi - lo > HOPF_TOL) {
    double mid = 0.5 * (lo + hi);
    if ((st = equilibrium_rate(nl, mid, amp, w, &r, &f, err))) break;
    if (r >= 0)
      hi = mid;
    else
      lo = mid;
  }
  if (!st && isfinite(hi)) st = equilibrium_rate(nl, hi, amp, w, &r, &f, err);
  *v_out = hi;
  *f_out = f;
  free(w);
  return st;
}

/* Where the branch on contact functions starts: the speed at which the
   linearisation a cycle of AMP_START_TABLE sees (the harmonic slopes) has
   a neutral oscillatory mode. The tables' slopes near y = 0 may differ
   from their mean over the first cycle (a contact jump within it), so the
   Hopf point's speed can be far from that cycle's. */
static int branch_start(const rr_nonlinear *nl, double v_hopf, double *v0, rr_error *err)
{
  double f;
  int st = neutral_speed(nl, AMP_START_TABLE, v0, &f, err);
  if (!st && !isfinite(*v0)) *v0 = v_hopf;
  return st;
}

/* The Hopf point of the vehicle on contact functions. */
static int jacobian_hopf(const rr_nonlinear *nl, rr_bifurcation *res, rr_error *err)
{
  double v, f;
  int st = neutral_speed(nl, 0, &v, &f, err);
  if (!st && isfinite(v)) {
    res->hopf = 1;
    res->hopf_speed_ms = v;
    res->hopf_freq_hz = f;
  }
  return st;
}

/* p at zero amplitude from the first points (a parabola in the amplitude). */
static double extrapolate_hopf(const rr_cycle *c, int n)
{
  if (n < 2) return NAN;
  if (n == 2)
    return c[0].speed_ms - c[0].amplitude_m * (c[1].speed_ms - c[0].speed_ms) /
                               (c[1].amplitude_m - c[0].amplitude_m);
  double a0 = c[0].amplitude_m, a1 = c[1].amplitude_m, a2 = c[2].amplitude_m;
  return c[0].speed_ms * a1 * a2 / ((a0 - a1) * (a0 - a2)) +
         c[1].speed_ms * a0 * a2 / ((a1 - a0) * (a1 - a2)) +
         c[2].speed_ms * a0 * a1 / ((a2 - a0) * (a2 - a1));
}

/* The lowest speed on the branch (the Hopf point included). A fold there
   (the lowest cycle has neighbours on both sides) is refined by cycles at
   fixed amplitudes around it (rr_orbit_fold), started a quarter of the
   smaller neighbour spacing apart; if those fail, the lowest cycle's speed
   stands (an upper bound). */
static double lowest_speed(const rr_orbit_sys *s, const rr_orbit_opts *o, const rr_orbit *c,
                           const double *Z, int n, double v_hopf)
{
  int b = -1;
  double best = v_hopf;
  for (int i = 0; i < n; i++)
    if (c[i].p < best) {
      best = c[i].p;
      b = i;
    }
  if (b <= 0 || b >= n - 1) return best;
  double d = 0.25 * fmin(fabs(c[b].amp - c[b - 1].amp), fabs(c[b + 1].amp - c[b].amp)), vf, af;
  rr_error e;
  int st = rr_orbit_fold(s, &o->runner, Z + (size_t)b * (size_t)s->ode.n, c[b].T, c[b].p, d,
                         o->rtol, &vf, &af, &e);
  return !st && vf < best ? vf : best;
}

/* How far a wheelset may move either way within the contact data (inf
   without contact functions): the branch ends beyond it. */
static double contact_reach(const rr_nonlinear *nl)
{
  double lo, hi;
  rr_nonlinear_contact_range(nl, &lo, &hi);
  return fmin(-lo, hi);
}

static void summarise(const rr_cycle *c, int n, rr_bifurcation *res)
{
  res->npoints = n;
  if (n < 1) return;
  res->type = c[0].speed_ms >= res->hopf_speed_ms ? RR_BIF_SUPERCRITICAL : RR_BIF_SUBCRITICAL;
  res->hopf_speed_branch_ms = extrapolate_hopf(c, n < 3 ? n : 3);
}

/* Nothing found yet. */
static rr_bifurcation bifurcation_none(void)
{
  return (rr_bifurcation){.hopf_speed_ms = NAN,
                          .hopf_freq_hz = NAN,
                          .hopf_speed_branch_ms = NAN,
                          .nonlinear_critical_ms = NAN,
                          .type = RR_BIF_NONE,
                          .end = RR_BRANCH_RANGE};
}

int rr_bifurcation_hopf(const rr_vehicle *veh, const rr_profile *p, const rr_contact_law *law,
                        rr_bifurcation *res, rr_error *err)
{
  *res = bifurcation_none();
  int st = profile_of(veh, &p, err);
  if (st) return st;
  rr_contact_law lv = law ? *law : law_of(veh);
  rr_model *m;
  rr_nonlinear *nl;
  st = build(veh, p, &lv, HOPF_V_MIN, &m, &nl, err);
  if (!st)
    st = p ? hopf_point(m, rr_profile_conicity(p, 0), res, err) : jacobian_hopf(nl, res, err);
  rr_nonlinear_free(nl);
  rr_model_free(m);
  return st;
}

int rr_bifurcation_continue(const rr_vehicle *veh, const rr_profile *p, const rr_contact_law *law,
                            const rr_orbit_opts *o, rr_cycle *out, double *z_out, int cap,
                            rr_bifurcation *res, rr_error *err)
{
  rr_orbit_opts def = rr_orbit_opts_default();
  if (!o) o = &def;
  *res = bifurcation_none();
  if (!(o->v_min_ms > 0 && o->v_max_ms > o->v_min_ms && o->v_max_ms <= RR_SPEED_MAX_MS &&
        o->amp_max_m > 0 && o->ds > 0 && o->rtol > 0 && o->max_points >= 2 && cap >= 2))
    return rr_seterr(
        err, RR_EINVAL,
        "bifurcation: speeds 0 < min < max <= %g km/h, positive steps, room for 2 points",
        RR_SPEED_MAX_MS * RR_KMH);
  int st0 = profile_of(veh, &p, err);
  if (st0) return st0;
  rr_contact_law lv = law ? *law : law_of(veh);
  rr_model *m;
  rr_nonlinear *nl;
  int st = build(veh, p, &lv, o->v_min_ms, &m, &nl, err);
  if (!st)
    st = p ? hopf_point(m, rr_profile_conicity(p, 0), res, err) : jacobian_hopf(nl, res, err);
  if (!st && res->hopf && is_linear(p, &lv)) res->end = RR_BRANCH_LINEAR;
  if (!st && res->hopf && res->end != RR_BRANCH_LINEAR) {
    rr_orbit_sys s;
    double *atol = NULL;
    rr_orbit *pts = malloc(sizeof *pts * (size_t)cap);
    if (!pts) st = rr_seterr(err, RR_ENOMEM, "out of memory");
    if (!st) st = rr_nonlinear_orbit_sys(nl, &s, &atol, err);
    double vh = res->hopf_speed_ms, v0 = vh;
    if (!st && !p) st = branch_start(nl, vh, &v0, err);
    rr_branch_opts bo = {.p_min = fmin(o->v_min_ms, fmin(vh, v0) / WINDOW_BEYOND),
                         .p_max = vh <= o->v_max_ms ? o->v_max_ms
                                                    : fmin(vh * WINDOW_BEYOND, RR_SPEED_MAX_MS),
                         /* above the range, only a branch that turns back down can enter it */
                         .amp_max = fmin(o->amp_max_m, contact_reach(nl)),
                         .amp_start = p ? AMP_START : AMP_START_TABLE,
                         .ds = o->ds,
                         .ds_max = 15 * o->ds,
                         .rtol = p ? o->rtol : fmax(o->rtol, RTOL_TABLE),
                         .cap = cap < o->max_points ? cap : o->max_points,
                         .runner = o->runner,
                         .progress = o->progress};
    int n = 0;
    double *Z =
        z_out ? z_out : malloc(sizeof(double) * (size_t)cap * (size_t)rr_nonlinear_size(nl));
    if (!st && !Z) st = rr_seterr(err, RR_ENOMEM, "out of memory");
    if (!st) st = rr_orbit_branch(&s, v0, &bo, pts, Z, &n, &res->end, err);
    for (int i = 0; i < n; i++) out[i] = cycle_of(&pts[i]);
    summarise(out, n, res);
    int refine = !st && res->end != RR_BRANCH_STOPPED; /* a stop wants out soon */
    if (refine && n) res->nonlinear_critical_ms = lowest_speed(&s, o, pts, Z, n, vh);
    if (refine) find_events(&s, o, pts, Z, n, res);
    if (Z != z_out) free(Z);
    free(pts);
    free(atol);
  }
  rr_nonlinear_free(nl);
  rr_model_free(m);
  return st;
}

int rr_cycle_shoot(rr_nonlinear *nl, double *z0, double *T, double rtol, rr_cycle *out,
                   rr_error *err)
{
  rr_orbit_sys s;
  double *atol, p = rr_nonlinear_speed(nl);
  rr_orbit r;
  int st = rr_nonlinear_orbit_sys(nl, &s, &atol, err);
  if (st) return st;
  st = rr_orbit_solve(&s, z0, T, &p, rtol > 0 ? rtol : 1e-10, 0, 0, &r, err);
  if (!st) *out = cycle_of(&r);
  free(atol);
  return st;
}

/* The largest |u| of samples u[0..ns) (stride apart), peaks refined by
   parabolas. */
static double peak(const double *u, int stride, int ns)
{
  double a = 0;
  for (int i = 1; i < ns - 1; i++) {
    double y0 = fabs(u[(size_t)(i - 1) * (size_t)stride]), y1 = fabs(u[(size_t)i * (size_t)stride]),
           y2 = fabs(u[(size_t)(i + 1) * (size_t)stride]);
    double den = y0 - 2 * y1 + y2;
    a = fmax(a, y1 >= y0 && y1 >= y2 && den < 0 ? y1 - 0.125 * (y0 - y2) * (y0 - y2) / den : y1);
  }
  return a;
}

/* Amplitude and frequency (up-crossings) of samples u[0..ns) at fs. A
   motion still decaying (its second half's amplitude below the first's by
   more than SCAN_DECAY) or below SCAN_DEAD is no cycle: amplitude 0. */
static void measure(const double *u, int stride, int ns, double fs, double *amp, double *freq)
{
  double a1 = peak(u, stride, ns / 2),
         a2 = peak(u + (size_t)(ns / 2) * (size_t)stride, stride, ns - ns / 2), t_first = NAN,
         t_last = NAN;
  int ncross = 0;
  for (int i = 1; i < ns; i++) {
    double p = u[(size_t)(i - 1) * (size_t)stride], q = u[(size_t)i * (size_t)stride];
    if (p < 0 && q >= 0) {
      double t = (i - 1 + p / (p - q)) / fs;
      if (!ncross) t_first = t;
      t_last = t;
      ncross++;
    }
  }
  int cycle = a2 > SCAN_DEAD && a2 >= (1 - SCAN_DECAY) * a1;
  *amp = cycle ? fmax(a1, a2) : 0;
  *freq = cycle && ncross >= 2 ? (ncross - 1) / (t_last - t_first) : NAN;
}

/* A fresh start: every wheelset displaced by y_m (within half the contact
   data's reach, so that the first swing stays on the data), the rest at
   rest. */
static void scan_seed(const rr_nonlinear *nl, double *z, double y_m)
{
  double half = 0.5 * contact_reach(nl);
  if (fabs(y_m) > half) y_m = copysign(half, y_m);
  memset(z, 0, sizeof(double) * (size_t)rr_nonlinear_size(nl));
  for (int w = 0; w < rr_nonlinear_ninputs(nl); w++) z[rr_nonlinear_index_y(nl, w)] = y_m;
}

/* One run at nl's speed from z (left at the run's end). */
static int scan_run(rr_nonlinear *nl, double *z, const rr_scan_opts *o, double *buf, int ns,
                    rr_scan_point *pt, rr_error *err)
{
  rr_sim_opts so = rr_sim_opts_default();
  int N = rr_nonlinear_size(nl), k = rr_nonlinear_index_y(nl, 0);
  so.duration_s = (ns - 1) / SCAN_FS;
  so.fs_hz = SCAN_FS;
  int st = rr_simulate(nl, z, &so, buf, ns, err);
  if (st) return st;
  int first = (int)ceil(o->settle_s * SCAN_FS);
  pt->speed_ms = rr_nonlinear_speed(nl);
  measure(buf + (size_t)first * (size_t)N + k, N, ns - first, SCAN_FS, &pt->amplitude_m,
          &pt->frequency_hz);
  memcpy(z, buf + (size_t)(ns - 1) * (size_t)N, sizeof(double) * (size_t)N);
  return RR_OK;
}

int rr_bifurcation_scan(const rr_vehicle *veh, const rr_profile *p, const rr_contact_law *law,
                        const double *vs, int nv, const rr_scan_opts *o, rr_scan_point *up,
                        rr_scan_point *down, rr_error *err)
{
  rr_scan_opts def = rr_scan_opts_default();
  if (!o) o = &def;
  if (!(nv >= 1 && o->settle_s >= 0 && o->measure_s > 0 && o->settle_s + o->measure_s <= 1e4 &&
        isfinite(o->y0_m) && isfinite(o->reseed_m)))
    return rr_seterr(err, RR_EINVAL,
                     "scan: at least one speed, settle >= 0, measure > 0 s (together <= 1e4 s), "
                     "finite disturbances");
  for (int i = 0; i < nv; i++)
    if (!(vs[i] > 0 && vs[i] <= RR_SPEED_MAX_MS) || (i && !(vs[i] > vs[i - 1])))
      return rr_seterr(err, RR_EINVAL, "scan: speeds must rise within (0, %g] km/h",
                       RR_SPEED_MAX_MS * RR_KMH);
  int st0 = profile_of(veh, &p, err);
  if (st0) return st0;
  rr_model *m;
  rr_nonlinear *nl;
  int st = build(veh, p, law, vs[0], &m, &nl, err);
  if (st) return st;
  int N = rr_nonlinear_size(nl), ns = (int)ceil((o->settle_s + o->measure_s) * SCAN_FS) + 1;
  double *z = calloc((size_t)N, sizeof(double)),
         *buf = malloc(sizeof(double) * (size_t)ns * (size_t)N);
  if (!z || !buf) st = rr_seterr(err, RR_ENOMEM, "out of memory");
  if (!st) scan_seed(nl, z, o->y0_m);
  for (int i = 0; i < nv; i++) /* a stop leaves what was not run undefined */
    up[i] = down[i] = (rr_scan_point){.speed_ms = vs[i], .amplitude_m = NAN, .frequency_hz = NAN};
  long done = 0;
  for (int i = 0; i < nv && !st; i++) { /* up: each speed from the last end state */
    if (i > 0 && up[i - 1].amplitude_m == 0) scan_seed(nl, z, o->reseed_m); /* it died out */
    if (!(st = rr_nonlinear_set_speed(nl, vs[i], err)))
      st = scan_run(nl, z, o, buf, ns, &up[i], err);
    if (!st) st = rr_progress_step(&o->progress, ++done, 2L * nv, err);
  }
  if (!st && up[nv - 1].amplitude_m == 0) scan_seed(nl, z, o->y0_m); /* no cycle on top */
  for (int i = nv - 1; i >= 0 && !st; i--) { /* down, from the top speed's motion */
    if (!(st = rr_nonlinear_set_speed(nl, vs[i], err)))
      st = scan_run(nl, z, o, buf, ns, &down[i], err);
    if (!st) st = rr_progress_step(&o->progress, ++done, 2L * nv, err);
  }
  free(z);
  free(buf);
  rr_nonlinear_free(nl);
  rr_model_free(m);
  return st;
}
