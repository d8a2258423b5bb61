/* Paper-mode SDF: self-consistent modes (docs/model.md, "SDF in modal
 * analysis"). A mode is self-consistent where the yaw dampers' series
 * stiffness k equals k_sdf at the mode's own frequency. Each oscillatory mode
 * of the k_lo model is followed along its branch as k rises to k_hi, on a grid
 * of steps (k_hi - k_lo)/32 halved wherever consecutive shapes correlate less
 * than MAC 0.9; h(k) = k - k_sdf(f(k)) changes sign between two grid points,
 * and the root is bisected to 1e-9 k_hi; the mode reported is the one at the
 * bisection's upper end.
 *
 * Two methods, the same grid and the same bisection:
 * - reference: a full eigen-solve with vectors (dgeev) at every grid and
 *   bisection point, the branch matched by MAC among all modes (~1000 solves
 *   for the default car);
 * - fast: each branch continued by Newton's method on the 17-DOF dynamic
 *   stiffness D(s, k) (nonlinear inverse iteration, one 17 x 17 complex LU an
 *   iteration, quadratic predictor in k), the root of h found by the Illinois
 *   method, and the bisection's midpoints decided from the root, so that only
 *   the upper end needs a solve. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "modal/modal_impl.h"
#include "linalg/max_abs.h"
#include "model/dynamic_stiffness.h"
#include "linalg/hessenberg_qr.h"
#include "util/internal.h"

#define MAC_MIN 0.9    /* consecutive shapes on a branch correlate at least this */
#define MAC_SURE 0.995 /* above, no other mode can be the better match in practice */
#define FIRST_STEPS 32 /* first step (k_hi - k_lo) / 32 */
#define ROOT_TOL 1e-9  /* bisection to |dk| <= 1e-9 k_hi */
#define STEP_MIN 1e-12 /* a branch is lost below steps of 1e-12 k_hi */
#define WALK_TRIES 256 /* or after this many steps tried: a sane curve needs ~32 */
#define NEWTON_MAXIT 30
#define NEWTON_TOL_GRID                                                                            \
  1e-4              /* relative eigenvalue update at which a grid solve stops: the                 \
                       update taken, the error is ~1e-8 relative, ample for MAC                    \
                       and for the sign of h away from its root */
#define H_SURE 1e-5 /* |h| / k_hi above which a grid solve's sign of h is certain */
#define NEWTON_TOL_ROOT 1e-10

static double h_of(const rr_model *m, double k, double im)
{
  return k - rr_sdf_storage(&m->curve, im / (2 * RR_PI));
}

/* ---- reference: full eigen-solves ---- */

static int best_match(const rr_modal_result *r, const double complex *phi, int n, double *mac)
{
  int best = -1;
  double bm = -1;
  for (int i = 0; i < r->n; i++) {
    double v = rr_mac(phi, r->shapes + (size_t)i * (size_t)n, n);
    if (v > bm) {
      bm = v;
      best = i;
    }
  }
  *mac = bm;
  return best;
}

static int solve_at(const rr_model *m, double k, rr_modal_ws *ws, rr_modal_result *r, rr_error *err)
{
  int N, st = rr_modal_eig(m, k, 1, ws, &N, err);
  if (st) return st;
  rr_modal_collect(m, N, ws, r);
  return RR_OK;
}

static void copy_shape(double complex *dst, const double complex *src, int n)
{
  memcpy(dst, src, (size_t)n * sizeof *dst);
}

/* One branch from r0's mode b; the reported mode and its shape go to rep, phi. */
static int ref_branch(const rr_model *m, rr_modal_ws *ws, const rr_modal_result *r0, int b,
                      rr_modal_result *rb, rr_mode *rep, double complex *phi, rr_error *err)
{
  int n = m->n, st;
  double k_lo, k_hi;
  rr_sdf_range(&m->curve, &k_lo, &k_hi);
  rr_mode cur = r0->modes[b], mb = cur;
  copy_shape(phi, r0->shapes + (size_t)b * (size_t)n, n);
  double complex *phia = ws->x;
  copy_shape(phia, phi, n);
  double k = k_lo, h = h_of(m, k, cur.im), step = (k_hi - k_lo) / FIRST_STEPS, ka = k, kb = k;
  int found = h >= 0, lost = 0;
  for (int tries = 0; !found && !lost; tries++) {
    if (tries == WALK_TRIES) { /* steps halved without end: a curve over many decades */
      lost = 1;
      break;
    }
    double kn = fmin(k + step, k_hi), mac;
    if ((st = solve_at(m, kn, ws, rb, err))) return st;
    int j = best_match(rb, phi, n, &mac);
    if (j < 0 || mac < MAC_MIN) {
      step *= 0.5;
      if (step < STEP_MIN * k_hi) lost = 1;
      continue;
    }
    rr_mode nx = rb->modes[j];
    if (!nx.oscillatory) {
      lost = 1;
      break;
    }
    double hn = h_of(m, kn, nx.im);
    if (hn >= 0) {
      ka = k;
      copy_shape(phia, phi, n);
      kb = kn;
      mb = nx;
      copy_shape(phi, rb->shapes + (size_t)j * (size_t)n, n);
      found = 1;
      break;
    }
    k = kn;
    cur = nx;
    h = hn;
    copy_shape(phi, rb->shapes + (size_t)j * (size_t)n, n);
    if (k >= k_hi) lost = 1;
  }
  if (found && h >= 0 && ka == kb)
    mb = cur; /* root at k_lo itself */
  else if (found) {
    while (kb - ka > ROOT_TOL * k_hi) {
      double km = 0.5 * (ka + kb), mac;
      if ((st = solve_at(m, km, ws, rb, err))) return st;
      int j = best_match(rb, phia, n, &mac);
      if (j < 0 || !rb->modes[j].oscillatory) {
        lost = 1;
        break;
      }
      rr_mode mm = rb->modes[j];
      if (h_of(m, km, mm.im) >= 0) {
        kb = km;
        mb = mm;
        copy_shape(phi, rb->shapes + (size_t)j * (size_t)n, n);
      } else {
        ka = km;
        copy_shape(phia, rb->shapes + (size_t)j * (size_t)n, n);
      }
    }
  }
  *rep = found && !lost ? mb : cur;
  rep->self_consistent = found && !lost;
  rep->sdf_k = found && !lost ? kb : k;
  return RR_OK;
}

static int ref_modes(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                     rr_modal_result *res, rr_error *err)
{
  int n = m->n;
  double k_lo, k_hi;
  rr_sdf_range(&m->curve, &k_lo, &k_hi);
  rr_modal_result *r0 = &ws->trk[0], *rb = res == &ws->trk[1] ? &ws->trk[2] : &ws->trk[1];
  int st = solve_at(m, k_lo, ws, r0, err);
  if (st) return st;
  /* branches are reported in r0's order into res, which must not alias r0 */
  for (int b = 0; b < r0->n; b++) {
    rr_mode *rep = &res->modes[b];
    double complex *phi = res->shapes + (size_t)b * (size_t)n;
    if (!r0->modes[b].oscillatory) { /* not followed: reported as at k_lo */
      *rep = r0->modes[b];
      rep->sdf_k = k_lo;
      copy_shape(phi, r0->shapes + (size_t)b * (size_t)n, n);
      continue;
    }
    if ((st = ref_branch(m, ws, r0, b, rb, rep, ws->branch, err))) return st;
    copy_shape(phi, ws->branch, n);
  }
  res->n = r0->n;
  res->ndof = n;
  rr_modal_finish(m, res, o, ws->branch);
  return RR_OK;
}

/* ---- fast: Newton continuation on D(s, k) ---- */

typedef struct point {
  double k;
  double complex s;
} point;

typedef struct tracker {
  const rr_model *m;
  rr_modal_ws *ws;
  rr_dsolver *ds; /* vectors below are in its DOF order */
  double k_lo, k_hi, anorm;
  double complex *phi, *xn, *t, *phia, *phib, *xc, *v, *tmp;
} tracker;

/* Eigenpair of D(s, k) x = 0 near (*s, x) by nonlinear inverse iteration
   (Ruhe 1973): y = D(s)^-1 D'(s) x, s <- s - (v'x)/(v'y), x <- y / (v'y), with
   v the normalised start vector. Quadratic: once the update is below tol |s|
   the next would be at rounding, so the last update is kept without another
   LU. Returns 0 when converged. */
static int newton(const tracker *tr, double k, double complex *s, double complex *x, double tol)
{
  int n = tr->m->n;
  double nx = 0;
  for (int i = 0; i < n; i++) nx += creal(x[i] * conj(x[i]));
  if (!(nx > 0) || !isfinite(nx)) return -1;
  for (int i = 0; i < n; i++) {
    x[i] /= nx;
    tr->v[i] = x[i] * nx;
  } /* v'x = 1 */
  for (int it = 0; it < NEWTON_MAXIT; it++) {
    rr_dsolver_factor(tr->ds, *s, k);
    rr_dsolver_deriv(tr->ds, *s, k, x, tr->t);
    rr_dsolver_solve(tr->ds, tr->t, tr->tmp);
    double complex mu = 0;
    for (int i = 0; i < n; i++) mu += conj(tr->v[i]) * tr->t[i];
    if (!(cabs(mu) > 0) || !isfinite(cabs(mu))) return -1;
    double complex ds = 1.0 / mu;
    *s -= ds;
    for (int i = 0; i < n; i++) x[i] = tr->t[i] * ds;
    if (cabs(ds) <= tol * cabs(*s)) return 0;
  }
  return -1;
}

/* Quadratic (or lower) extrapolation of s to k from the last points. */
static double complex predict(const point *h, int nh, double k)
{
  if (nh == 1) return h[0].s;
  const point *a = &h[nh - 1], *b = &h[nh - 2];
  double complex lin = a->s + (a->s - b->s) * ((k - a->k) / (a->k - b->k));
  if (nh == 2) return lin;
  const point *c = &h[nh - 3];
  double complex d1 = (a->s - b->s) / (a->k - b->k), d2 = (b->s - c->s) / (b->k - c->k);
  return lin + (d1 - d2) / (a->k - c->k) * (k - a->k) * (k - b->k);
}

/* The reference's choice at k: among all modes (eigenvalues by our QR, shapes
   by one inverse-iteration step each), the one whose shape best matches ref.
   Taken where the continued mode's match is not beyond doubt (a veering or a
   nearly degenerate pair). Returns its MAC (0 when the QR fails). */
static double best_of_all(const tracker *tr, double k, const double complex *ref, double complex *s,
                          double complex *x)
{
  const rr_model *m = tr->m;
  rr_modal_ws *ws = tr->ws;
  int n = m->n, N;
  if (rr_state_matrix_merged(m, k, ws->A, &N, NULL)) return 0;
  memcpy(ws->At, ws->A, sizeof(double) * (size_t)N * (size_t)N);
  if (rr_eig_small(N, ws->At, ws->wr, ws->wi)) return 0;
  double best = -1;
  for (int j = 0; j < N; j++) {
    if (ws->wi[j] < 0) continue;
    double complex sj = ws->wr[j] + I * ws->wi[j];
    rr_dsolver_factor(tr->ds, sj, k);
    for (int i = 0; i < n; i++) tr->t[i] = rr_dsolver_start(i);
    rr_dsolver_solve(tr->ds, tr->t, tr->tmp);
    double mac = rr_mac(ref, tr->t, n);
    if (mac > best) {
      best = mac;
      *s = sj;
      copy_shape(x, tr->t, n);
    }
  }
  return best;
}

/* The mode at k that continues the shape ref, from the guess (*s, x):
   Newton, then the reference's best match where that is in doubt. Returns
   the MAC to ref (0 when nothing converged). */
static double continue_to(const tracker *tr, double k, const double complex *ref, double complex *s,
                          double complex *x, double tol)
{
  double mac = newton(tr, k, s, x, tol) ? 0 : rr_mac(ref, x, tr->m->n);
  if (mac >= MAC_SURE) return mac;
  mac = best_of_all(tr, k, ref, s, x);
  if (mac >= MAC_MIN && rr_modal_is_osc(creal(*s), cimag(*s), tr->anorm) &&
      newton(tr, k, s, x, tol))
    return 0;
  return mac;
}

static void push(point *h, int *nh, double k, double complex s)
{
  if (*nh == 3) {
    h[0] = h[1];
    h[1] = h[2];
    *nh = 2;
  }
  h[(*nh)++] = (point){.k = k, .s = s};
}

typedef struct bracket {
  double ka, kb;         /* grid points: h(ka) < 0 <= h(kb) */
  double complex sa, sb; /* eigenvalues there; shapes in tr->phia, tr->phib */
} bracket;

/* Walks the grid from k_lo; 1: bracket found, 0: branch lost (the last good
   point in *last, its shape in tr->phi). */
static int walk(const tracker *tr, double complex s0, bracket *br, point *last)
{
  int n = tr->m->n;
  point hist[3];
  int nh = 0;
  push(hist, &nh, tr->k_lo, s0);
  double k = tr->k_lo, step = (tr->k_hi - tr->k_lo) / FIRST_STEPS;
  double complex s = s0;
  for (int tries = 0; k < tr->k_hi && tries < WALK_TRIES; tries++) {
    double kn = fmin(k + step, tr->k_hi);
    double complex sn = predict(hist, nh, kn);
    copy_shape(tr->xn, tr->phi, n);
    if (continue_to(tr, kn, tr->phi, &sn, tr->xn, NEWTON_TOL_GRID) < MAC_MIN) {
      step *= 0.5;
      if (step < STEP_MIN * tr->k_hi) break;
      continue;
    }
    if (!rr_modal_is_osc(creal(sn), cimag(sn), tr->anorm)) break;
    double hn = h_of(tr->m, kn, cimag(sn));
    if (fabs(hn) < H_SURE * tr->k_hi && newton(tr, kn, &sn, tr->xn, NEWTON_TOL_ROOT) == 0)
      hn = h_of(tr->m, kn, cimag(sn));
    if (hn >= 0) {
      *br = (bracket){.ka = k, .kb = kn, .sa = s, .sb = sn};
      copy_shape(tr->phia, tr->phi, n);
      copy_shape(tr->phib, tr->xn, n);
      return 1;
    }
    k = kn;
    s = sn;
    copy_shape(tr->phi, tr->xn, n);
    push(hist, &nh, k, s);
  }
  *last = (point){.k = k, .s = s};
  return 0;
}

/* Solve at k from the nearer end of [a, b] (s linear between them); the
   shape goes to tr->xc. */
static int solve_between(const tracker *tr, double k, const point *a, const point *b, double tol,
                         double complex *s)
{
  double w = (k - a->k) / (b->k - a->k);
  const double complex *ref = w < 0.5 ? tr->phia : tr->phib;
  *s = a->s + (b->s - a->s) * w;
  copy_shape(tr->xc, ref, tr->m->n);
  if (continue_to(tr, k, ref, s, tr->xc, tol) < MAC_MIN) return -1;
  return rr_modal_is_osc(creal(*s), cimag(*s), tr->anorm) ? 0 : -1;
}

/* Narrows [a, b] (h(a) < 0 <= h(b)) around the root by the Illinois method
   until it is far below the bisection's tolerance. */
static int narrow(const tracker *tr, point *a, point *b, double tol_k)
{
  int n = tr->m->n, side = 0;
  double fa = h_of(tr->m, a->k, cimag(a->s)), fb = h_of(tr->m, b->k, cimag(b->s));
  for (int it = 0; it < 100 && b->k - a->k > tol_k; it++) {
    double c = (a->k * fb - b->k * fa) / (fb - fa);
    if (!(c > a->k && c < b->k)) c = 0.5 * (a->k + b->k);
    double complex sc;
    if (solve_between(tr, c, a, b, NEWTON_TOL_ROOT, &sc)) return -1;
    double fc = h_of(tr->m, c, cimag(sc));
    if (fc >= 0) {
      *b = (point){.k = c, .s = sc};
      fb = fc;
      copy_shape(tr->phib, tr->xc, n);
      if (side == 1) fa *= 0.5;
      side = 1;
    } else {
      *a = (point){.k = c, .s = sc};
      fa = fc;
      copy_shape(tr->phia, tr->xc, n);
      if (side == -1) fb *= 0.5;
      side = -1;
    }
  }
  return 0;
}

/* The reference bisection of [ka, kb], its midpoints decided by the narrowed
   bracket [a, b] (a solve only for a midpoint inside it); returns its upper
   end, whose mode is solved into (*s, tr->xc). */
static int bisect(const tracker *tr, const bracket *br, point *a, point *b, double *k_out,
                  double complex *s)
{
  double lo = br->ka, hi = br->kb, tol = ROOT_TOL * tr->k_hi;
  while (hi - lo > tol) {
    double km = 0.5 * (lo + hi);
    if (km >= b->k) {
      hi = km;
      continue;
    }
    if (km <= a->k) {
      lo = km;
      continue;
    }
    double complex sm;
    if (solve_between(tr, km, a, b, NEWTON_TOL_ROOT, &sm)) return -1;
    if (h_of(tr->m, km, cimag(sm)) >= 0) {
      hi = km;
      *b = (point){.k = km, .s = sm};
      copy_shape(tr->phib, tr->xc, tr->m->n);
    } else {
      lo = km;
      *a = (point){.k = km, .s = sm};
      copy_shape(tr->phia, tr->xc, tr->m->n);
    }
  }
  *k_out = hi;
  *s = b->s;
  copy_shape(tr->xc, tr->phib, tr->m->n);
  if (b->k == hi) return 0;
  return newton(tr, hi, s, tr->xc, NEWTON_TOL_ROOT);
}

static void report(const tracker *tr, double k, double complex s, const double complex *x, int ok,
                   rr_mode *rep, double complex *shape)
{
  int n = tr->m->n;
  rr_mode_fill(rep, creal(s), cimag(s), tr->anorm);
  rr_dsolver_from(tr->ds, x, shape);
  rr_shape_normalise(shape, n);
  rr_mode_shares(tr->m, shape, rep);
  rep->self_consistent = ok;
  rep->sdf_k = k;
}

/* One branch from the k_lo eigenpair (s0, tr->phi). */
static void fast_branch(const tracker *tr, double complex s0, rr_mode *rep, double complex *shape)
{
  if (h_of(tr->m, tr->k_lo, cimag(s0)) >= 0) {
    report(tr, tr->k_lo, s0, tr->phi, 1, rep, shape);
    return;
  }
  bracket br;
  point last;
  if (!walk(tr, s0, &br, &last)) { /* lost: the last point on the branch, to full accuracy */
    newton(tr, last.k, &last.s, tr->phi, NEWTON_TOL_ROOT);
    report(tr, last.k, last.s, tr->phi, 0, rep, shape);
    return;
  }
  point a = {.k = br.ka, .s = br.sa}, b = {.k = br.kb, .s = br.sb};
  double k;
  double complex s;
  if (narrow(tr, &a, &b, 1e-3 * ROOT_TOL * tr->k_hi) || bisect(tr, &br, &a, &b, &k, &s)) {
    report(tr, br.ka, br.sa, tr->phia, 0, rep, shape); /* lost inside the bracket */
    return;
  }
  report(tr, k, s, tr->xc, 1, rep, shape);
}

static void tracker_init(tracker *tr, const rr_model *m, rr_modal_ws *ws, double anorm)
{
  int n = m->n;
  *tr = (tracker){.m = m, .ws = ws, .ds = ws->ds, .anorm = anorm};
  rr_sdf_range(&m->curve, &tr->k_lo, &tr->k_hi);
  rr_dsolver_init(tr->ds, m, ws->dsi, ws->dsz);
  double complex *t = ws->tv;
  tr->phi = t;
  tr->xn = t + n;
  tr->t = t + 2 * n;
  tr->phia = t + 3 * n;
  tr->phib = t + 4 * n;
  tr->xc = t + 5 * n;
  tr->v = t + 6 * n;
  tr->tmp = t + 7 * n;
}

/* Two branches that end on the same mode: one of them jumped to a nearly
   degenerate partner (a pair of frame-roll modes 0.001 Hz apart, say), which
   the reference's best match among all modes would not have done. */
static int same_root(const rr_mode *a, const rr_mode *b, double k_hi)
{
  return a->oscillatory && b->oscillatory && a->self_consistent && b->self_consistent &&
         fabs(a->sdf_k - b->sdf_k) <= 1e-6 * k_hi &&
         cabs((a->re - b->re) + I * (a->im - b->im)) <= 1e-9 * hypot(a->re, a->im);
}

static rr_modal_result *scratch_result(rr_modal_ws *ws, const rr_modal_result *r0,
                                       const rr_modal_result *res)
{
  for (int i = 0;; i++)
    if (&ws->trk[i] != r0 && &ws->trk[i] != res) return &ws->trk[i];
}

/* Tracks r0's oscillatory modes into res (res must not alias r0); branches
   that collide are tracked again by the reference method. */
static int fast_track(const tracker *tr, const rr_modal_result *r0, rr_modal_result *res,
                      rr_error *err)
{
  int n = tr->m->n;
  for (int b = 0; b < r0->n; b++) {
    rr_mode *rep = &res->modes[b];
    double complex *shape = res->shapes + (size_t)b * (size_t)n;
    if (!r0->modes[b].oscillatory) {
      *rep = r0->modes[b];
      rep->sdf_k = tr->k_lo;
      copy_shape(shape, r0->shapes + (size_t)b * (size_t)n, n);
      continue;
    }
    rr_dsolver_to(tr->ds, r0->shapes + (size_t)b * (size_t)n, tr->phi);
    fast_branch(tr, r0->modes[b].re + I * r0->modes[b].im, rep, shape);
  }
  res->n = r0->n;
  res->ndof = n;
  rr_modal_result *rb = scratch_result(tr->ws, r0, res);
  for (int a = 0; a < r0->n; a++)
    for (int b = a + 1; b < r0->n; b++) {
      if (!same_root(&res->modes[a], &res->modes[b], tr->k_hi)) continue;
      int pair[2] = {a, b};
      for (int q = 0; q < 2; q++) {
        int st =
            ref_branch(tr->m, tr->ws, r0, pair[q], rb, &res->modes[pair[q]], tr->ws->branch, err);
        if (st) return st;
        copy_shape(res->shapes + (size_t)pair[q] * (size_t)n, tr->ws->branch, n);
      }
    }
  return RR_OK;
}

static int fast_modes(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                      rr_modal_result *res, rr_error *err)
{
  tracker tr;
  tracker_init(&tr, m, ws, 0);
  rr_modal_result *r0 = res == &ws->trk[0] ? &ws->trk[1] : &ws->trk[0];
  int N, st = rr_modal_eig(m, tr.k_lo, 1, ws, &N, err);
  if (st) return st;
  rr_modal_collect(m, N, ws, r0);
  tr.anorm = rr_max_abs((size_t)N * (size_t)N, ws->A);
  if ((st = fast_track(&tr, r0, res, err))) return st;
  rr_modal_finish(m, res, o, ws->branch);
  return RR_OK;
}

int rr_sdf_modes(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, rr_modal_result *res,
                 rr_error *err)
{
  if (o->tracking == RR_TRACK_REFERENCE) return ref_modes(m, o, ws, res, err);
  return fast_modes(m, o, ws, res, err);
}

/* The k_lo start from eigenvalues only: each oscillatory eigenvalue's shape by
   Newton at k_lo from a fixed vector (the first step is inverse iteration). */
static int osc_start(const tracker *tr, int N, rr_modal_result *r0)
{
  int n = tr->m->n;
  r0->n = 0;
  r0->ndof = n;
  for (int j = 0; j < N; j++) {
    double re = tr->ws->wr[j], im = tr->ws->wi[j];
    if (im <= 0 || !rr_modal_is_osc(re, im, tr->anorm)) continue;
    double complex s = re + I * im, *x = tr->xn;
    for (int i = 0; i < n; i++) x[i] = rr_dsolver_start(i);
    if (newton(tr, tr->k_lo, &s, x, NEWTON_TOL_ROOT)) s = re + I * im;
    rr_dsolver_from(tr->ds, x, r0->shapes + (size_t)r0->n * (size_t)n);
    rr_mode_fill(&r0->modes[r0->n], creal(s), cimag(s), tr->anorm);
    r0->n++;
  }
  return RR_OK;
}

int rr_sdf_modes_fast_osc(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                          rr_modal_result *res, rr_error *err)
{
  if (o->tracking == RR_TRACK_REFERENCE) return ref_modes(m, o, ws, res, err);
  tracker tr;
  tracker_init(&tr, m, ws, 0);
  int N, st = rr_state_matrix_merged(m, tr.k_lo, ws->A, &N, err);
  if (st) return st;
  memcpy(ws->At, ws->A, sizeof(double) * (size_t)N * (size_t)N);
  if (rr_eig_small(N, ws->At, ws->wr, ws->wi)) return fast_modes(m, o, ws, res, err);
  tr.anorm = rr_max_abs((size_t)N * (size_t)N, ws->A);
  rr_modal_result *r0 = res == &ws->trk[0] ? &ws->trk[1] : &ws->trk[0];
  osc_start(&tr, N, r0);
  if ((st = fast_track(&tr, r0, res, err))) return st;
  rr_modal_finish(m, res, o, ws->branch);
  return RR_OK;
}
