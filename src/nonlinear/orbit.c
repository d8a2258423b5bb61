/* Periodic orbits: shooting with the variational equations, Floquet multipliers,
 * pseudo-arclength continuation from a Hopf point (see orbit.h). */
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <arkode/arkode_erkstep.h>
#include "nonlinear/orbit.h"
#include "nonlinear/nvector_fast.h"
#include "util/internal.h"
#include "util/block.h"

#define NEWTON_MAXIT 12
#define NEWTON_TOL 5e-9 /* |phi_T(z0) - z0| relative to |z0| */
#define PERIOD_GROWTH_MAX                                                                          \
  4.0                   /* a branch whose period grows past 4 x the Hopf period has left hunting */
#define KINK_TTOL 1e-12 /* a kink this close (in periods) to a step's start counts as at it */
#define RTOL_VAR                                                                                   \
  1e-6 /* the variational equations' tolerance: Phi feeds Newton and Floquet only                  \
        */

/* One period from z0: z(T), the monodromy matrix Phi (n x n, row-major) and
   d z(T) / dp, and the amplitude max |z_k_amp| over the period. */
typedef struct flow {
  double *zT, *Phi, *phip, amp;
} flow;

/* The orbit with a group of its variational equations: Y = [z; columns
   c0 .. c0 + nc - 1 of [Phi, phi_p], n rows of nc side by side], n (1 + nc). The system is not
   stiff at the speeds of hunting (spectral radius ~ 600 1/s against a period of ~0.1 s), so an
   explicit 8th-order pair beats BDF with sensitivities by an order of magnitude. */
typedef struct var_ctx {
  const rr_orbit_sys *s;
  double p;
  int sens;          /* variational columns integrated with the orbit (0: the orbit alone) */
  int c0;            /* the first one's index: 0 .. n - 1 Phi's columns, n the parameter's */
  double *J, *a, *b; /* dense fallback: n x n, n, n */
  char msg[160];     /* ARKODE's last complaint (the library never prints) */
} var_ctx;

static void var_errors(int code, const char *module, const char *function, char *msg, void *user)
{
  (void)code;
  (void)module;
  (void)function;
  var_ctx *c = user;
  snprintf(c->msg, sizeof c->msg, "%s", msg);
}

static void var_dense(const var_ctx *c, const double *z, const double *X, double *out)
{
  const rr_orbit_sys *s = c->s;
  int n = s->ode.n;
  s->ode.jac(s->ode.user, 0, c->p, z, c->J);
  size_t m = (size_t)c->sens;
  for (size_t k = 0; k < m; k++)
    for (int i = 0; i < n; i++) {
      double acc = 0;
      for (int j = 0; j < n; j++)
        acc += c->J[(size_t)i * (size_t)n + (size_t)j] * X[(size_t)j * m + k];
      out[(size_t)i * m + k] = acc;
    }
  if (c->c0 + c->sens <= n) return; /* no parameter column */
  double h = 1e-6 * fmax(fabs(c->p), 1e-3);
  s->ode.rhs(s->ode.user, 0, c->p + h, z, c->a);
  s->ode.rhs(s->ode.user, 0, c->p - h, z, c->b);
  for (int i = 0; i < n; i++) out[(size_t)i * m + m - 1] += (c->a[i] - c->b[i]) / (2 * h);
}

static int var_rhs(double t, N_Vector y, N_Vector ydot, void *user)
{
  (void)t;
  const var_ctx *c = user;
  const rr_orbit_sys *s = c->s;
  int n = s->ode.n;
  const double *Y = N_VGetArrayPointer(y);
  double *D = N_VGetArrayPointer(ydot);
  s->ode.rhs(s->ode.user, 0, c->p, Y, D);
  if (!c->sens) return 0;
  if (s->jvp)
    s->jvp(s->ode.user, c->p, Y, Y + n, c->sens, c->c0 + c->sens > n, D + n);
  else
    var_dense(c, Y, Y + n, D + n);
  return 0;
}

/* Per-component absolute tolerances, rtol times a typical magnitude: the
   states' own (s->atol, per amplitude unit) times the orbit's amplitude in
   those units; Phi's column j: atol_i / atol_j; phi_p: atol_i / p_unit. */
static void var_tolerances(const rr_orbit_sys *s, double rtol, double scale, int c0, int nc,
                           double *tol)
{
  int n = s->ode.n;
  for (int i = 0; i < n; i++) tol[i] = rtol * s->atol[i] * scale;
  for (int i = 0; i < n; i++)
    for (int c = 0; c < nc; c++) {
      int k = c0 + c;
      tol[(size_t)n + (size_t)i * (size_t)nc + (size_t)c] =
          rtol * s->atol[i] / (k < n ? s->atol[k] : s->p_unit);
    }
}

/* Integration of one period that never steps across a kink of f (the
   system's kink functions change sign there): a step that crosses one is
   taken back and the integration stopped at the kink, then restarted beyond
   it, so every step sees a smooth right-hand side and the flow keeps the
   accuracy its tolerance promises. The amplitude: |z_k_amp| at the zeros of
   its rate, z_k_phase, located on the dense output. */
typedef struct period {
  const rr_orbit_sys *s;
  double p;
  int sens;
  void *mem;
  N_Vector y, yprev, ytmp;
  double ga[RR_ORBIT_MAX_KINKS + 1], gb[RR_ORBIT_MAX_KINKS + 1], amp;
} period;

static void indicators(const period *P, const double *z, double *g)
{
  const rr_orbit_sys *s = P->s;
  int nk = P->sens ? 0 : s->nkinks;
  if (nk) s->kinks(s->ode.user, P->p, z, g);
  g[nk] = z[s->k_phase];
}

static int crossed(double a, double b) { return (a < 0 && b >= 0) || (a > 0 && b <= 0); }

/* The zero of indicator j in (ta, tb) on the last step's dense output
   (Illinois false position); y there left in P->ytmp. */
static double locate(period *P, int j, double ta, double tb)
{
  double ga = P->ga[j], gb = P->gb[j], g[RR_ORBIT_MAX_KINKS + 1], t = tb;
  int side = 0;
  for (int it = 0; it < 60 && tb - ta > 1e-15 * fmax(1, fabs(tb)); it++) {
    t = (ta * gb - tb * ga) / (gb - ga);
    ERKStepGetDky(P->mem, t, 0, P->ytmp);
    indicators(P, N_VGetArrayPointer(P->ytmp), g);
    if (g[j] == 0) break;
    if (crossed(ga, g[j])) {
      tb = t;
      gb = g[j];
      if (side == -1) ga *= 0.5;
      side = -1;
    } else {
      ta = t;
      ga = g[j];
      if (side == 1) gb *= 0.5;
      side = 1;
    }
  }
  ERKStepGetDky(P->mem, t, 0, P->ytmp);
  return t;
}

static int period_run(period *P, double T)
{
  const rr_orbit_sys *s = P->s;
  int nk = P->sens ? 0 : s->nkinks,
      at_kink = 0; /* Phi, at its loose tolerance, steps across kinks */
  double t = 0, tprev = 0, tstop = T, h = 0, h_nat = 0, *Y = N_VGetArrayPointer(P->y);
  indicators(P, Y, P->ga);
  P->amp = fabs(Y[s->k_amp]);
  N_VScale(1, P->y, P->yprev);
  while (t < T) {
    int r = ERKStepEvolve(P->mem, tstop, P->y, &t, ARK_ONE_STEP);
    if (r < 0) return r;
    ERKStepGetLastStep(P->mem, &h);
    indicators(P, Y, P->gb);
    double tk = t;
    for (int i = 0; i < nk; i++)
      if (crossed(P->ga[i], P->gb[i])) tk = fmin(tk, locate(P, i, tprev, t));
    /* a kink inside the step (not at its very start): back to the start and
       stop at the kink; a located kink a hair early is caught again by the
       next, short, step and the stop refined */
    if (tk < t && tk - tprev > KINK_TTOL * T) {
      ERKStepReset(P->mem, tprev, P->yprev);
      N_VScale(1, P->yprev, P->y);
      ERKStepSetStopTime(P->mem, tk);
      ERKStepSetInitStep(P->mem, tk - tprev);
      h_nat = fmax(h_nat, h); /* the step the smooth side allows, for the restart */
      tstop = tk;
      at_kink = 1;
      t = tprev;
      continue;
    }
    if (crossed(P->ga[nk], P->gb[nk])) {
      locate(P, nk, tprev, t);
      P->amp = fmax(P->amp, fabs(N_VGetArrayPointer(P->ytmp)[s->k_amp]));
    }
    P->amp = fmax(P->amp, fabs(Y[s->k_amp]));
    if (at_kink && t >= tstop) { /* at the kink: a fresh start beyond it */
      ERKStepReset(P->mem, t, P->y);
      ERKStepSetStopTime(P->mem, T);
      ERKStepSetInitStep(P->mem, fmin(fmax(0.5 * h_nat, 1e-6 * T), T - t));
      tstop = T;
      at_kink = 0;
      h_nat = 0;
    }
    tprev = t;
    N_VScale(1, P->y, P->yprev);
    memcpy(P->ga, P->gb, sizeof(double) * (size_t)(nk + 1));
  }
  return 0;
}

/* One period from z0 with columns c0 .. c0 + nc - 1 of the variational
   equations (nc = 0: the orbit alone): z(T) to zT, the amplitude to *amp,
   and the columns at T to cols (n rows of nc; may be NULL when nc = 0). */
static int flow_period(const rr_orbit_sys *s, double p, const double *z0, double T, double rtol,
                       int c0, int nc, double *zT, double *amp, double *cols, rr_error *err)
{
  int n = s->ode.n, st = RR_OK;
  sunindextype ny = (sunindextype)n * (1 + nc);
  var_ctx c = {.s = s, .p = p, .sens = nc, .c0 = c0};
  period P = {.s = s, .p = p, .sens = nc > 0};
  SUNContext ctx = NULL;
  N_Vector tol = NULL;
  if (SUNContext_Create(NULL, &ctx)) return rr_seterr(err, RR_ENOMEM, "SUNDIALS context");
  P.y = N_VNew_Serial(ny, ctx);
  P.yprev = N_VNew_Serial(ny, ctx);
  P.ytmp = N_VNew_Serial(ny, ctx);
  tol = N_VNew_Serial(ny, ctx);
  if (P.y) rr_nvector_fast(P.y); /* one pass per stage combination, not one per term */
  c.J = malloc(sizeof(double) * ((size_t)n * (size_t)n + 2 * (size_t)n));
  if (!P.y || !P.yprev || !P.ytmp || !tol || !c.J) {
    st = rr_seterr(err, RR_ENOMEM, "out of memory");
    goto done;
  }
  c.a = c.J + (size_t)n * (size_t)n;
  c.b = c.a + n;
  double *Y = N_VGetArrayPointer(P.y), scale = fmax(fabs(z0[s->k_amp]) / s->amp_unit, 1e-3);
  memset(Y, 0, sizeof(double) * (size_t)ny);
  memcpy(Y, z0, sizeof(double) * (size_t)n);
  for (int k = 0; k < nc; k++) /* Phi(0) = I, phi_p(0) = 0 */
    if (c0 + k < n) Y[(size_t)n + (size_t)(c0 + k) * (size_t)nc + (size_t)k] = 1;
  var_tolerances(s, rtol, scale, c0, nc, N_VGetArrayPointer(tol));
  P.mem = ERKStepCreate(var_rhs, 0, P.y, ctx);
  if (!P.mem ||
      ERKStepSetTableNum(P.mem, nc ? ARKODE_DORMAND_PRINCE_7_4_5 : ARKODE_FEHLBERG_13_7_8) ||
      ERKStepSVtolerances(P.mem, rtol, tol) || ERKStepSetUserData(P.mem, &c) ||
      ERKStepSetErrHandlerFn(P.mem, var_errors, &c) || ERKStepSetStopTime(P.mem, T) ||
      ERKStepSetMaxNumSteps(P.mem, 200000) || ERKStepSetMaxStep(P.mem, T / 32) ||
      ERKStepSetMaxErrTestFails(P.mem,
                                50)) { /* a step beyond the stability bound fails many times over */
    st = rr_seterr(err, RR_ENOMEM, "orbit: ARKODE set-up failed");
    goto done;
  }
  if (period_run(&P, T)) {
    st = rr_seterr(err, RR_ENOCONV, "orbit: ARKODE: %s", c.msg);
    goto done;
  }
  for (int i = 0; i < (int)ny && !st; i++)
    if (!isfinite(Y[i])) st = rr_seterr(err, RR_ENOCONV, "orbit: the flow is not finite");
  *amp = P.amp;
  memcpy(zT, Y, sizeof(double) * (size_t)n);
  if (nc) memcpy(cols, Y + n, sizeof(double) * (size_t)n * (size_t)nc);
done:
  if (P.mem) ERKStepFree(&P.mem);
  N_Vector v[4] = {P.y, P.yprev, P.ytmp, tol};
  for (int i = 0; i < 4; i++)
    if (v[i]) N_VDestroy(v[i]);
  free(c.J);
  SUNContext_Free(&ctx);
  return st;
}

/* The variational equations in RR_ORBIT_GROUPS groups of columns, each
   integrated with its own copy of the orbit: the groups are independent
   jobs that a runner may spread over processes, and one process computes the
   same groups, so that the numbers do not depend on how many there are. A
   job's result: z(T) (n), the amplitude (1), its columns (n rows of its
   column count). */
typedef struct sens_job {
  const rr_orbit_sys *s;
  double p, T, rtol;
  const double *z0;
  int ncols;                     /* columns a group: the last group may have fewer */
  rr_error err[RR_ORBIT_GROUPS]; /* each group's failure, where it ran here */
} sens_job;

static size_t sens_item(int n, int ncols) { return (size_t)n * (size_t)(1 + ncols) + 1; }

static int sens_ncols(int n) { return (n + 1 + RR_ORBIT_GROUPS - 1) / RR_ORBIT_GROUPS; }

/* flow_sens' buffer, doubles. */
static size_t sens_buf_size(int n) { return RR_ORBIT_GROUPS * sens_item(n, sens_ncols(n)); }

static int sens_run(void *arg, long lo, long hi, void *out)
{
  sens_job *j = arg;
  int n = j->s->ode.n, total = n + 1;
  double *o = out;
  for (long g = lo; g < hi; g++, o += sens_item(n, j->ncols)) {
    int c0 = (int)g * j->ncols, nc = total - c0 < j->ncols ? total - c0 : j->ncols;
    int st = nc > 0 ? flow_period(j->s, j->p, j->z0, j->T, j->rtol, c0, nc, o, o + n, o + n + 1,
                                  &j->err[g])
                    : RR_OK;
    if (st) return st;
  }
  return RR_OK;
}

/* The groups here, over OpenMP threads where there are several. */
static int local_runner(sens_job *j, double *out)
{
  int st = RR_OK;
  size_t item = sens_item(j->s->ode.n, j->ncols);
#ifdef _OPENMP
#pragma omp parallel for schedule(static, 1) reduction(max : st)
#endif
  for (int g = 0; g < RR_ORBIT_GROUPS; g++) {
    int sg = sens_run(j, g, g + 1, out + (size_t)g * item);
    st = sg > st ? sg : st;
  }
  return st;
}

/* The monodromy matrix Phi and phi_p = dz(T)/dp at (z0, T, p), with z(T)
   from the first group; buf: sens_buf_size doubles. */
static int flow_sens(const rr_orbit_sys *s, const rr_runner_opts *run, double p, const double *z0,
                     double T, flow *f, double *buf, rr_error *err)
{
  int n = s->ode.n, ncols = sens_ncols(n);
  sens_job j = {.s = s, .p = p, .T = T, .rtol = RTOL_VAR, .z0 = z0, .ncols = ncols};
  for (int g = 0; g < RR_ORBIT_GROUPS; g++) j.err[g].msg[0] = 0;
  size_t item = sens_item(n, ncols);
  int st = run && run->fn
               ? run->fn(run->ctx, RR_ORBIT_GROUPS, item * sizeof(double), sens_run, &j, buf)
               : local_runner(&j, buf);
  if (st) {
    for (int g = 0; g < RR_ORBIT_GROUPS; g++)
      if (j.err[g].msg[0]) return rr_seterr(err, st, "%s", j.err[g].msg);
    return rr_seterr(err, st, "orbit: the variational equations failed in another process (%s)",
                     rr_strerror(st));
  }
  memcpy(f->zT, buf, sizeof(double) * (size_t)n);
  f->amp = buf[n];
  for (int k = 0; k <= n; k++) {
    int g = k / ncols, c = k % ncols, nc = n + 1 - g * ncols < ncols ? n + 1 - g * ncols : ncols;
    const double *rows = buf + (size_t)g * item + n + 1 + c;
    for (int i = 0; i < n; i++) {
      double x = rows[(size_t)i * (size_t)nc];
      if (k == n)
        f->phip[i] = x;
      else
        f->Phi[(size_t)i * (size_t)n + (size_t)k] = x;
    }
  }
  return RR_OK;
}

/* The constraint closing the Newton system: p fixed, amplitude fixed, or
   pseudo-arclength tA dA + tp dp = ds (scaled units). */
typedef struct closure {
  int kind;      /* 0 p, 1 amplitude, 2 arclength */
  double amp, p; /* targets (kinds 0, 1); the previous point (kind 2) */
  double tA, tp, ds;
} closure;

/* Newton's workspace. The flow rows of the bordered system [Phi - I, f(z_T),
   phi_p] (n x (n + 2)) come from a period with the variational equations
   and are then kept up to date by Broyden's rank-one updates, so that most
   iterations cost one plain period; the phase and closure rows are exact. */
typedef struct work {
  int n, valid;       /* valid: B holds the flow rows of a nearby orbit */
  int half;           /* symmetric orbits: the half period's map composed with z -> -z */
  double T_max;       /* periods beyond are out of the domain */
  double *B, *Jn, *R; /* n (n + 2), (n + 2)^2, n + 2 */
  double *F, *Fn, *dX,
      *zt; /* z_T - z0 now and after the step (n), the step (n + 2), a trial z0 (n) */
  int *piv;
  flow f;
  const rr_runner_opts *run; /* where the variational groups run (NULL: here) */
  double *sbuf;              /* their results */
  double *ea, *wr, *wi;      /* the Floquet eigenproblem's scratch */
  char *block;               /* the arrays, one allocation (block.h) */
} work;

/* Newton's arrays (block.h: called to size, then to carve). */
static void work_layout(work *w, rr_block *b)
{
  size_t m = (size_t)w->n + 2, n = (size_t)w->n;
  const size_t d = sizeof(double);
  w->B = rr_block_take(b, n * m, d);
  w->Jn = rr_block_take(b, m * m, d);
  w->R = rr_block_take(b, m, d);
  w->F = rr_block_take(b, n, d);
  w->Fn = rr_block_take(b, n, d);
  w->dX = rr_block_take(b, m, d);
  w->zt = rr_block_take(b, n, d);
  w->piv = rr_block_take(b, m, sizeof(int));
  w->f.zT = rr_block_take(b, n, d);
  w->f.Phi = rr_block_take(b, n * n, d);
  w->f.phip = rr_block_take(b, n, d);
  w->sbuf = rr_block_take(b, sens_buf_size(w->n), d);
  w->ea = rr_block_take(b, n * n, d);
  w->wr = rr_block_take(b, n, d);
  w->wi = rr_block_take(b, n, d);
}

static int work_new(work *w, int n)
{
  *w = (work){.n = n, .T_max = INFINITY};
  rr_block b = {0};
  work_layout(w, &b);
  if (rr_block_alloc(&b)) return -1;
  w->block = b.base;
  work_layout(w, &b);
  return 0;
}

static void work_free(work *w) { free(w->block); }

static double norm2(const double *x, int n)
{
  double s = 0;
  for (int i = 0; i < n; i++) s += x[i] * x[i];
  return sqrt(s);
}

/* The integration span of a period T: half of it for a symmetric orbit. */
static double span(const work *w, double T) { return w->half ? 0.5 * T : T; }

/* The flow rows from a period with the variational equations (in w->f):
   d/d(z0, T, p) of F = z(span) -+ z0 (+ for a symmetric orbit). */
static void flow_rows(const rr_orbit_sys *s, work *w, double p)
{
  int n = w->n, m = n + 2;
  double *fz = w->R, sign = w->half ? 1 : -1, dspan = w->half ? 0.5 : 1; /* R: scratch */
  s->ode.rhs(s->ode.user, 0, p, w->f.zT, fz);
  for (int i = 0; i < n; i++) {
    double *row = w->B + (size_t)i * (size_t)m;
    for (int j = 0; j < n; j++)
      row[j] = w->f.Phi[(size_t)i * (size_t)n + (size_t)j] + sign * (i == j);
    row[n] = fz[i] * dspan;
    row[n + 1] = w->f.phip[i];
  }
  w->valid = 1;
}

/* The bordered Newton system in X = (z0, T, p), row-major (n + 2)^2, and its
   right-hand side: F, the phase condition, the closure. */
static void newton_system(const rr_orbit_sys *s, work *w, const double *z0, double p,
                          const closure *c)
{
  int n = w->n, m = n + 2;
  double *J = w->Jn, *R = w->R;
  memcpy(J, w->B, sizeof(double) * (size_t)n * (size_t)m);
  memset(J + (size_t)n * (size_t)m, 0, sizeof(double) * 2 * (size_t)m);
  memcpy(R, w->F, sizeof(double) * (size_t)n);
  J[n * m + s->k_phase] = 1;
  R[n] = z0[s->k_phase];
  double *last = J + (size_t)(n + 1) * (size_t)m;
  if (c->kind == 0) {
    last[n + 1] = 1;
    R[n + 1] = p - c->p;
  } else if (c->kind == 1) {
    last[s->k_amp] = 1;
    R[n + 1] = z0[s->k_amp] - c->amp;
  } else {
    last[s->k_amp] = c->tA / s->amp_unit;
    last[n + 1] = c->tp / s->p_unit;
    R[n + 1] =
        c->tA * (z0[s->k_amp] - c->amp) / s->amp_unit + c->tp * (p - c->p) / s->p_unit - c->ds;
  }
}

/* Broyden's good update of the flow rows after the step dX took F to Fn. */
static void broyden(work *w)
{
  int n = w->n, m = n + 2;
  double dd = 0;
  for (int j = 0; j < m; j++) dd += w->dX[j] * w->dX[j];
  if (!(dd > 0)) return;
  for (int i = 0; i < n; i++) {
    double *row = w->B + (size_t)i * (size_t)m, bx = 0;
    for (int j = 0; j < m; j++) bx += row[j] * w->dX[j];
    double g = (w->Fn[i] - w->F[i] - bx) / dd;
    for (int j = 0; j < m; j++) row[j] += g * w->dX[j];
  }
}

/* Floquet multipliers from the flow's Jacobian Phi over the span: the
   return map's is Phi, or -Phi for a symmetric orbit's half period (whose
   multipliers' squares are the period's). Sets the largest modulus but the
   trivial multiplier's (the one nearest 1: the orbit's own direction), the
   count outside the unit circle by kind, and stability. a, wr, wi: n x n,
   n, n of scratch. */
static int floquet(const double *Phi, int n, int half, double *a, double *wr, double *wi,
                   rr_orbit *o, rr_error *err)
{
  for (size_t i = 0; i < (size_t)n * (size_t)n; i++) a[i] = half ? -Phi[i] : Phi[i];
  if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', n, a, n, wr, wi, NULL, 1, NULL, 1))
    return rr_seterr(err, RR_ELAPACK, "orbit: Floquet multipliers: dgeev failed");
  int trivial = 0;
  for (int i = 1; i < n; i++)
    if (hypot(wr[i] - 1, wi[i]) < hypot(wr[trivial] - 1, wi[trivial])) trivial = i;
  o->floquet_max = -1;
  memset(o->outside, 0, sizeof o->outside);
  for (int i = 0; i < n; i++) {
    if (i == trivial) continue;
    double r = hypot(wr[i], wi[i]), mod = half ? r * r : r;
    o->floquet_max = fmax(o->floquet_max, mod);
    if (mod <= 1 || wi[i] < 0) continue; /* a complex pair once */
    o->outside[wi[i] > 0 ? RR_CROSS_TORUS : wr[i] > 0 ? RR_CROSS_FOLD : RR_CROSS_FLIP]++;
  }
  o->stable = o->floquet_max < 1;
  o->symmetric = half;
  return RR_OK;
}

/* One period (half, symmetric) at the tight tolerance: F = z(span) -+ z0
   and the amplitude (a symmetric orbit's half has the whole one's). */
static int residual(const rr_orbit_sys *s, work *w, const double *z0, double T, double p,
                    double rtol, double *F, double *amp, rr_error *err)
{
  int st = flow_period(s, p, z0, span(w, T), rtol, 0, 0, w->f.zT, &w->f.amp, NULL, err);
  double sign = w->half ? 1 : -1;
  for (int i = 0; i < w->n && !st; i++) F[i] = w->f.zT[i] + sign * z0[i];
  *amp = w->f.amp;
  return st;
}

/* The flow rows afresh at (z0, T, p), from the variational equations. */
static int refresh(const rr_orbit_sys *s, work *w, const double *z0, double T, double p,
                   rr_error *err)
{
  int st = flow_sens(s, w->run, p, z0, span(w, T), &w->f, w->sbuf, err);
  if (!st) flow_rows(s, w, p);
  return st;
}

/* Newton-Broyden from (z0, T, p) under closure c; converged values in place.
   The variational equations are integrated when the rows are stale (no
   nearby orbit, or a step that failed to halve the residual) and once at
   the solution, for its Floquet multipliers and the next orbit's start. */
/* The closure row's residual in merit units (its own scaled units). */
static double closure_scale(const rr_orbit_sys *s, const closure *c)
{
  return c->kind == 0 ? 1 / s->p_unit : c->kind == 1 ? 1 / s->amp_unit : 1;
}

/* One trial point X + lam dX: its residual (infinite outside the domain). */
static int trial(const rr_orbit_sys *s, work *w, const double *z0, double T, double p, double lam,
                 double rtol, double *rn, double *amp, rr_error *err)
{
  int n = w->n;
  for (int i = 0; i < n; i++) w->zt[i] = z0[i] + lam * w->dX[i];
  double Tt = T + lam * w->dX[n], pt = p + lam * w->dX[n + 1];
  *rn = INFINITY;
  if (!(Tt > 0 && Tt <= w->T_max && pt > 0)) return RR_OK;
  int st = residual(s, w, w->zt, Tt, pt, rtol, w->Fn, amp, err);
  if (st == RR_ENOCONV) return RR_OK; /* a wild trial: no flow; shorter steps may do */
  if (!st) *rn = norm2(w->Fn, n) / fmax(norm2(w->zt, n), 1e-300);
  return st;
}

static int newton_run(const rr_orbit_sys *s, work *w, double *z0, double *T, double *p, double rtol,
                      const closure *c, rr_orbit *out, rr_error *err)
{
  int n = w->n, m = n + 2, st = RR_OK, fresh = 0;
  double amp, res;
  if (!w->valid) {
    if ((st = refresh(s, w, z0, *T, *p, err))) return st;
    fresh = 1;
  }
  if ((st = residual(s, w, z0, *T, *p, rtol, w->F, &amp, err))) return st;
  res = norm2(w->F, n) / fmax(norm2(z0, n), 1e-300);
  int maxit = s->newton_maxit > 0 ? s->newton_maxit : NEWTON_MAXIT;
  double tol = s->newton_tol > 0 ? s->newton_tol : NEWTON_TOL;
  for (int it = 1; it <= maxit; it++) {
    newton_system(s, w, z0, *p, c);
    if (res <= tol && fabs(w->R[n + 1]) <= 1e-9 * (c->kind == 0 ? s->p_unit : 1)) {
      if ((st = refresh(s, w, z0, *T, *p, err))) return st;
      *out = (rr_orbit){.p = *p, .T = *T, .amp = amp, .residual = res, .iterations = it};
      return floquet(w->f.Phi, n, w->half, w->ea, w->wr, w->wi, out, err);
    }
    if (LAPACKE_dgesv(LAPACK_ROW_MAJOR, m, 1, w->Jn, m, w->piv, w->R, 1))
      return rr_seterr(err, RR_ENOCONV, "orbit: singular Newton system");
    /* the merit: the return map's residual plus the linear rows' (which a
       full step satisfies); accept a step that lowers it or reaches the
       noise floor, else the variational equations afresh here, then halving */
    double merit =
        res + fabs(w->R[n]) / fmax(norm2(z0, n), 1e-300) + fabs(w->R[n + 1]) * closure_scale(s, c);
    for (int i = 0; i < m; i++) w->dX[i] = -w->R[i];
    double lam = 1, rn;
    for (int k = 0;; k++) {
      if ((st = trial(s, w, z0, *T, *p, lam, rtol, &rn, &amp, err))) return st;
      if (rn < merit || rn <= 10 * tol) break;
      if (!fresh || k >= 4) break;
      lam *= 0.5;
    }
    if (!(rn < merit || rn <= 10 * tol)) {
      if (fresh) return rr_seterr(err, RR_ENOCONV, "orbit: Newton stalls at residual %.1e", res);
      if ((st = refresh(s, w, z0, *T, *p, err))) return st;
      fresh = 1;
      continue;
    }
    for (int i = 0; i < m; i++) w->dX[i] *= lam;
    memcpy(z0, w->zt, sizeof(double) * (size_t)n);
    *T += w->dX[n];
    *p += w->dX[n + 1];
    if (rn > 0.5 * res && !fresh && rn > 10 * tol) { /* slow: Newton's own rows from here */
      if ((st = refresh(s, w, z0, *T, *p, err))) return st;
      fresh = 1;
    } else {
      broyden(w);
      fresh = 0;
    }
    memcpy(w->F, w->Fn, sizeof(double) * (size_t)n);
    res = rn;
  }
  return rr_seterr(err, RR_ENOCONV,
                   "orbit: Newton did not converge in %d iterations (residual %.1e)", maxit, res);
}

static int newton(const rr_orbit_sys *s, work *w, double *z0, double *T, double *p, double rtol,
                  const closure *c, rr_orbit *out, rr_error *err)
{
  int st = newton_run(s, w, z0, T, p, rtol, c, out, err);
  if (st) w->valid = 0; /* the rows may have been updated from a wild step */
  return st;
}

int rr_orbit_solve(const rr_orbit_sys *s, double *z0, double *T, double *p, double rtol,
                   int fix_amp, double amp, rr_orbit *out, rr_error *err)
{
  work w;
  int st = work_new(&w, s->ode.n) ? rr_seterr(err, RR_ENOMEM, "out of memory") : RR_OK;
  closure c = {.kind = fix_amp ? 1 : 0, .amp = amp, .p = *p};
  if (!st) st = newton(s, &w, z0, T, p, rtol, &c, out, err);
  work_free(&w);
  return st;
}

#define FOLD_ROUNDS 3

/* The vertex of the parabola through (a - d, p[0]), (a, p[1]), (a + d, p[2]):
   its abscissa to *av; its ordinate returned (NaN: not a minimum). */
static double vertex(double a, double d, const double p[3], double *av)
{
  double curv = p[0] - 2 * p[1] + p[2], slope = p[2] - p[0];
  if (!(curv > 0)) return NAN;
  *av = a - 0.5 * d * slope / curv;
  return p[1] - slope * slope / (8 * curv);
}

int rr_orbit_fold(const rr_orbit_sys *s, const rr_runner_opts *run, const double *z0, double T,
                  double p, double d, double rtol, double *p_fold, double *amp_fold, rr_error *err)
{
  int n = s->ode.n, st = RR_OK;
  work w;
  double *X = malloc(sizeof(double) * 2 * ((size_t)n + 2)), *X0 = X + n + 2;
  if (!X || work_new(&w, n)) {
    free(X);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  w.run = run;
  w.half = s->odd;
  memcpy(X0, z0, sizeof(double) * (size_t)n);
  X0[n] = T;
  X0[n + 1] = p;
  double a = z0[s->k_amp];
  for (int round = 0; round < FOLD_ROUNDS && !st; round++, d *= 0.25) {
    double pk[3];
    for (int k = 0; k < 3 && !st; k++) { /* from the nearest orbit known: the centre's */
      memcpy(X, X0, sizeof(double) * ((size_t)n + 2));
      closure c = {.kind = 1, .amp = a + (k - 1) * d};
      rr_orbit r;
      st = newton(s, &w, X, &X[n], &X[n + 1], rtol, &c, &r, err);
      pk[k] = X[n + 1];
      if (k == 1) memcpy(X0, X, sizeof(double) * ((size_t)n + 2));
    }
    double av = a, pv = st ? NAN : vertex(a, d, pk, &av);
    if (!st && !isfinite(pv))
      st = rr_seterr(err, RR_ENOCONV, "orbit: no fold near %g (p against amplitude is not convex)",
                     p);
    *p_fold = pv;
    *amp_fold = av;
    a = av;
  }
  work_free(&w);
  free(X);
  return st;
}

int rr_orbit_unstable_dims(const rr_orbit *o)
{
  return o->outside[RR_CROSS_FOLD] + o->outside[RR_CROSS_FLIP] + 2 * o->outside[RR_CROSS_TORUS];
}

#define BISECT_MAXIT 8

static double chord(const rr_orbit_sys *s, const double *a, const double *b);

int rr_orbit_bisect(const rr_orbit_sys *s, const rr_runner_opts *run, double *Xa, rr_orbit *ra,
                    double *Xb, rr_orbit *rb, double ds_tol, double rtol, rr_error *err)
{
  int n = s->ode.n, st = RR_OK, m = n + 2;
  work w;
  double *X = malloc(sizeof(double) * (size_t)m);
  if (!X || work_new(&w, n)) {
    free(X);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  w.run = run;
  w.half = s->odd;
  int da = rr_orbit_unstable_dims(ra);
  for (int it = 0; it < BISECT_MAXIT && chord(s, Xa, Xb) > ds_tol; it++) {
    double len = chord(s, Xa, Xb);
    rr_orbit r;
    int fail = 1;
    for (int k = 0; k < 2 && fail; k++) { /* halfway, else a third of the way */
      double u = k ? 1.0 / 3 : 0.5;
      closure c = {.kind = 2,
                   .amp = Xa[s->k_amp],
                   .p = Xa[n + 1],
                   .tA = (Xb[s->k_amp] - Xa[s->k_amp]) / s->amp_unit / len,
                   .tp = (Xb[n + 1] - Xa[n + 1]) / s->p_unit / len,
                   .ds = u * len};
      for (int i = 0; i < m; i++) X[i] = Xa[i] + u * (Xb[i] - Xa[i]);
      rr_error e;
      fail = newton(s, &w, X, &X[n], &X[n + 1], rtol, &c, &r, &e);
    }
    if (fail) break; /* the bracket stands */
    int left = rr_orbit_unstable_dims(&r) == da;
    memcpy(left ? Xa : Xb, X, sizeof(double) * (size_t)m);
    *(left ? ra : rb) = r;
  }
  work_free(&w);
  free(X);
  return st;
}

int rr_orbit_floquet_vector(const rr_orbit_sys *s, const double *z0, double T, double p, double *mu,
                            double *v, rr_error *err)
{
  int n = s->ode.n, st;
  flow f;
  double *buf =
      malloc(sizeof(double) * ((size_t)n * (size_t)n * 2 + 4 * (size_t)n + sens_buf_size(n)));
  if (!buf) return rr_seterr(err, RR_ENOMEM, "out of memory");
  f.Phi = buf;
  double *V = buf + (size_t)n * (size_t)n, *wr = V + (size_t)n * (size_t)n, *wi = wr + n;
  f.zT = wi + n;
  f.phip = f.zT + n;
  st = flow_sens(s, NULL, p, z0, T, &f, f.phip + n, err);
  if (!st && LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'V', n, f.Phi, n, wr, wi, NULL, 1, V, n))
    st = rr_seterr(err, RR_ELAPACK, "orbit: Floquet vectors: dgeev failed");
  int trivial = 0, best = -1;
  for (int i = 1; i < n && !st; i++)
    if (hypot(wr[i] - 1, wi[i]) < hypot(wr[trivial] - 1, wi[trivial])) trivial = i;
  for (int i = 0; i < n && !st; i++)
    if (i != trivial && (best < 0 || hypot(wr[i], wi[i]) > hypot(wr[best], wi[best]))) best = i;
  if (!st) {
    *mu = hypot(wr[best], wi[best]);
    int col = wi[best] < 0 ? best - 1 : best; /* a complex pair: the real part of its vector */
    for (int i = 0; i < n; i++) v[i] = V[(size_t)i * (size_t)n + (size_t)col];
  }
  free(buf);
  return st;
}

/* The start at the Hopf point: the critical eigenvector of df/dz(0) (or of
   the start Jacobian at amp),
   phased so that z[k_phase] = 0 and scaled to z[k_amp] = amp; T = 2 pi / w. */
static int hopf_start(const rr_orbit_sys *s, double p, double amp, double *z0, double *T,
                      rr_error *err)
{
  int n = s->ode.n, st = RR_OK, best = -1;
  double *J = calloc((size_t)n * (size_t)n, sizeof(double)),
         *wr = malloc(sizeof(double) * (size_t)n), *wi = malloc(sizeof(double) * (size_t)n),
         *V = malloc(sizeof(double) * (size_t)n * (size_t)n);
  if (!J || !wr || !wi || !V) st = rr_seterr(err, RR_ENOMEM, "out of memory");
  if (!st) {
    memset(z0, 0, sizeof(double) * (size_t)n);
    if (s->start_jac)
      s->start_jac(s->ode.user, p, amp, J);
    else
      s->ode.jac(s->ode.user, 0, p, z0, J);
    if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'V', n, J, n, wr, wi, NULL, 1, V, n))
      st = rr_seterr(err, RR_ELAPACK, "orbit: dgeev failed at the Hopf point");
  }
  for (int i = 0; i < n && !st; i++)
    if (wi[i] > 0 && (best < 0 || wr[i] > wr[best])) best = i;
  if (!st && best < 0)
    st = rr_seterr(err, RR_ENOCONV, "orbit: no oscillatory eigenvalue at the Hopf point");
  if (!st) { /* v = a + i b (columns best, best + 1); Re(v e^{i th}) = a cos th - b sin th */
    double ap = V[s->k_phase * n + best], bp = V[s->k_phase * n + best + 1], th = atan2(ap, bp);
    for (int i = 0; i < n; i++) z0[i] = V[i * n + best] * cos(th) - V[i * n + best + 1] * sin(th);
    double scale = amp / z0[s->k_amp];
    for (int i = 0; i < n; i++) z0[i] *= scale;
    z0[s->k_phase] = 0;
    *T = 2 * RR_PI / wi[best];
  }
  free(J);
  free(wr);
  free(wi);
  free(V);
  return st;
}

static void store(const rr_orbit *o, const double *z0, int n, rr_orbit *out, double *z_out, int *k)
{
  out[*k] = *o;
  if (z_out) memcpy(z_out + (size_t)*k * (size_t)n, z0, sizeof(double) * (size_t)n);
  (*k)++;
}

/* The last three points of the branch, X = (z0, T, p), and their arclength
   (chord lengths in the scaled amplitude-parameter plane). */
typedef struct history {
  int n, k;
  double *X[3], s[3];
} history;

static double chord(const rr_orbit_sys *s, const double *a, const double *b)
{
  int n = s->ode.n;
  return hypot((a[s->k_amp] - b[s->k_amp]) / s->amp_unit, (a[n + 1] - b[n + 1]) / s->p_unit);
}

static void history_push(const rr_orbit_sys *s, history *h, const double *X)
{
  double *slot = h->X[0];
  double s0 = h->k ? h->s[2] + chord(s, X, h->X[2]) : 0;
  h->X[0] = h->X[1];
  h->X[1] = h->X[2];
  h->X[2] = slot;
  h->s[0] = h->s[1];
  h->s[1] = h->s[2];
  h->s[2] = s0;
  memcpy(slot, X, sizeof(double) * (size_t)(h->n + 2));
  h->k++;
}

/* The predictor at arclength s2 + ds: the parabola through the last three
   points (the line through two when there are only two). */
static void history_predict(const history *h, double ds, double *X)
{
  const double *s = h->s, t = s[2] + ds;
  double l0 = 0, l1 = -ds / (s[2] - s[1]), l2 = 1 + ds / (s[2] - s[1]);
  if (h->k >= 3) {
    l0 = (t - s[1]) * (t - s[2]) / ((s[0] - s[1]) * (s[0] - s[2]));
    l1 = (t - s[0]) * (t - s[2]) / ((s[1] - s[0]) * (s[1] - s[2]));
    l2 = (t - s[0]) * (t - s[1]) / ((s[2] - s[0]) * (s[2] - s[1]));
  }
  for (int i = 0; i < h->n + 2; i++)
    X[i] = l0 * (h->k >= 3 ? h->X[0][i] : 0) + l1 * h->X[1][i] + l2 * h->X[2][i];
}

/* Whether a cycle (ua, up) from the last one (scaled amplitude and speed
   changes), solved at a fixed amplitude (kind 1) or speed (kind 0), lies
   back on the branch that came in along (dA, dp): the branch's line
   backward reaches its fixed coordinate with the other within half of the
   line's change. Ahead of the last cycle in that coordinate the branch
   behind cannot be. */
static int behind(int kind, double ua, double up, double dA, double dp)
{
  double fixed = kind ? ua : up, along = kind ? dA : dp, other = kind ? up : ua,
         slope = kind ? dp / dA : dA / dp; /* the other coordinate per unit of the fixed one */
  if (fixed * along >= 0) return 0;
  return fabs(other - fixed * slope) <= 0.5 * fabs(fixed * slope);
}

/* Past a corner of the branch, where a wheelset starts or stops touching a
   flange and the branch turns abruptly (a grazing point), the arclength's
   hyperplane ahead misses it. From the last cycle Xl, whose branch came in
   along (dA, dp) (scaled): cycles at fixed amplitudes a few um either side
   (a flange's stiffness lets the amplitude move ~0.01 mm in 1 km/h beyond
   the contact), then at fixed speeds up to 1 km/h either side (in
   amp_unit, p_unit); the first near Xl that is not back on the branch
   behind is the branch beyond. 0: X and r hold it. */
static int corner_step(const rr_orbit_sys *s, work *w, const double *Xl, double dA, double dp,
                       double rtol, double *X, rr_orbit *r)
{
  static const double damp[] = {2e-3, 1e-3, 4e-3, 0.5e-3, 8e-3}, dspeed[] = {0.1, 0.05, 0.025};
  int n = s->ode.n, na = (int)(sizeof damp / sizeof damp[0]),
      nv = (int)(sizeof dspeed / sizeof dspeed[0]);
  for (int i = 0; i < 2 * (na + nv); i++) {
    int kind = i < 2 * na ? 1 : 0, j = (kind ? i : i - 2 * na) / 2;
    double sign = (i % 2 ? -1 : 1) * ((kind ? dA : dp) >= 0 ? 1 : -1);
    memcpy(X, Xl, sizeof(double) * ((size_t)n + 2));
    closure c = {.kind = kind,
                 .amp = Xl[s->k_amp] + sign * damp[kind ? j : 0] * s->amp_unit,
                 .p = Xl[n + 1] + sign * dspeed[kind ? 0 : j] * s->p_unit};
    rr_error e;
    if (newton(s, w, X, &X[n], &X[n + 1], rtol, &c, r, &e)) continue;
    double ua = (X[s->k_amp] - Xl[s->k_amp]) / s->amp_unit, up = (X[n + 1] - Xl[n + 1]) / s->p_unit;
    if (fabs(ua) <= 0.1 && fabs(up) <= 1 && !behind(kind, ua, up, dA, dp)) return 0;
  }
  return -1;
}

#define TURN_COS_MIN 0.5 /* a step may turn the branch by at most 60 degrees */

/* The cosine of the turn from the last secant (tA, tp) (scaled, unit) to the
   step from the last cycle a to X. */
static double turn_cos(const rr_orbit_sys *s, const double *X, const double *a, double tA,
                       double tp)
{
  int n = s->ode.n;
  double uA = (X[s->k_amp] - a[s->k_amp]) / s->amp_unit, up = (X[n + 1] - a[n + 1]) / s->p_unit;
  double len = hypot(uA, up);
  return len > 0 ? (uA * tA + up * tp) / len : 1;
}

int rr_orbit_branch(const rr_orbit_sys *s, double p_hopf, const rr_branch_opts *o, rr_orbit *out,
                    double *z_out, int *np, rr_branch_end *end, rr_error *err)
{
  int n = s->ode.n, st = RR_OK, k = 0;
  *end = RR_BRANCH_CAP;
  size_t m = (size_t)n + 2;
  *np = 0;
  work w;
  double *buf = malloc(sizeof(double) * 4 * m), *X = buf + 3 * m;
  history h = {.n = n, .X = {buf, buf + m, buf + 2 * m}};
  if (work_new(&w, n) || !buf) {
    st = rr_seterr(err, RR_ENOMEM, "out of memory");
    goto done;
  }
  w.run = &o->runner;
  w.half = s->odd; /* the Hopf point's cycle is symmetric when f is odd, and so is its branch */
  double ds = o->ds;
  rr_orbit r;
  /* two points at fixed amplitudes leave the Hopf point; then arclength */
  X[n + 1] = p_hopf;
  if ((st = hopf_start(s, p_hopf, o->amp_start, X, &X[n], err))) goto done;
  w.T_max = PERIOD_GROWTH_MAX * X[n];
  for (int i = 0; i < 2; i++) { /* at amp_start and 3 amp_start: close enough to extrapolate back */
    closure c = {.kind = 1, .amp = o->amp_start * (1 + 2 * i)};
    if (i == 1 && s->start_p) { /* the second from its own describing function too */
      double p1;
      if ((st = s->start_p(s->ode.user, c.amp, &p1, err))) goto done;
      if (isfinite(p1)) {
        X[n + 1] = p1;
        if ((st = hopf_start(s, p1, c.amp, X, &X[n], err))) goto done;
      }
    }
    if ((st = newton(s, &w, X, &X[n], &X[n + 1], o->rtol, &c, &r, err))) goto done;
    store(&r, X, n, out, z_out, &k);
    history_push(s, &h, X);
  }
  for (;;) {
    if (k >= o->cap) {
      *end = RR_BRANCH_CAP;
      break;
    }
    const double *a = h.X[2], *b = h.X[1]; /* the last two points */
    if (a[n + 1] < o->p_min || a[n + 1] > o->p_max) {
      *end = RR_BRANCH_RANGE;
      break;
    }
    if (fabs(a[s->k_amp]) > o->amp_max) {
      *end = RR_BRANCH_AMPLITUDE;
      break;
    }
    double dA = (a[s->k_amp] - b[s->k_amp]) / s->amp_unit, dp = (a[n + 1] - b[n + 1]) / s->p_unit,
           len = hypot(dA, dp);
    closure c = {
        .kind = 2, .amp = a[s->k_amp], .p = a[n + 1], .tA = dA / len, .tp = dp / len, .ds = ds};
    history_predict(&h, ds, X);
    rr_error e2;
    int fail = newton(s, &w, X, &X[n], &X[n + 1], o->rtol, &c, &r, &e2);
    if (fail || turn_cos(s, X, a, dA / len, dp / len) < TURN_COS_MIN) {
      ds *= 0.5; /* a failure, or a step that turned too far: it may have jumped branches */
      if (ds >= 1e-2 * o->ds) continue;
      if (corner_step(s, &w, h.X[2], dA / len, dp / len, o->rtol, X, &r)) {
        *end = RR_BRANCH_STALLED; /* cannot go on: the branch ends here */
        break;
      }
      h.k = 1; /* the line through the corner and the cycle beyond predicts from here */
      ds = chord(s, X, h.X[2]);
    }
    store(&r, X, n, out, z_out, &k);
    history_push(s, &h, X);
    if (o->progress.fn && o->progress.fn(o->progress.user, k, o->cap)) {
      *end = RR_BRANCH_STOPPED;
      break;
    }
    if (r.iterations <= 6)
      ds = fmin(ds * 1.5, o->ds_max); /* Broyden: 5-6 iterations is easy going */
    else if (r.iterations >= 10)
      ds *= 0.6;
  }
done:
  *np = k;
  work_free(&w);
  free(buf);
  return st;
}
