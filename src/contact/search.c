/* The contact of a wheel on its rail: exact for polylines (docs/contact.md,
 * contact search). The vertical gap is piecewise linear with breakpoints at
 * the rail's vertices and the shifted wheel's, so first contact is at one of
 * them: every candidate is evaluated in one merge walk, ties go to the
 * gauge-most point. With rigid roll the wheel polyline is turned and the
 * roll at which both wheels touch is found by Brent's method. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "contact/contact_impl.h"
#include "util/internal.h"

#define TIE_MM 1e-9 /* candidates this close to the deepest are ties */
#define END_MM 1e-9 /* a contact this close to a profile's end is at the end of its data */
#define JUMP_MM 1.0 /* a rail contact moving further between grid points is a jump */

/* A wheel as the search sees it: points (x, z) in the rail's frame less a
   shift s (x + s is the rail coordinate), with its segment slopes. */
typedef struct wheel_view {
  const double *x, *z, *k;
  int n;
  double s;
  const rr_chords *ch; /* its blocks' chords (no roll), or NULL: every candidate evaluated */
} wheel_view;

/* A rail with its segment slopes, and scratch for the candidates' depths
   and their segments (kept from one call to the next as starting points:
   between neighbouring displacements each moves by a step at most, so the
   walks are short and predictable). */
typedef struct rail_view {
  const double *x, *z, *k;
  int n;
  double *dr, *dw; /* depth at each rail vertex, each wheel vertex (scratch) */
  int *kr,
      *kw; /* the wheel segment under each rail vertex, the rail segment under each wheel vertex */
  const rr_chords *ch;     /* its blocks' chords, with the wheel's */
  double *ub;              /* scratch: each block's bound */
  double *bmax_r, *bmax_w; /* scratch: each block's deepest (-inf: skipped) */
  int *seg_r, *seg_w;      /* per side: each block's end segments, kept as guesses */
} rail_view;

#define BLOCK 32      /* candidates bounded together */
#define BOUND_MM 1e-9 /* margin on a block's bound: the interpolation rounds */

/* The first index j in [lo, hi) with !(x[j] + shift < lim), x increasing. */
static int first_not_below(const double *x, int lo, int hi, double shift, double lim)
{
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (x[mid] + shift < lim)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/* The segment of at on polyline x (rr_poly_segment's), walked from the guess
 *k (the same block's last time: the shift moves by a grid step). */
static int segment_from(const double *x, int n, double at, int *k)
{
  int j = *k;
  while (j > 0 && x[j] > at) j--;
  while (j < n - 2 && x[j + 1] <= at) j++;
  return *k = j;
}

/* Depths of rail vertices ja .. jend-1 over the wheel into dr (the walk from
   segment k); the deepest of them. */
static double rail_block(const rail_view *r, const wheel_view *w, int ja, int jend, int k)
{
  const double *v = r->x, *zr = r->z, *u = w->x, *zw = w->z, *kw = w->k, s = w->s;
  int n = w->n;
  double dmax = -INFINITY;
  for (int j = ja; j < jend; j++) {
    double x = v[j] - s;
    while (k < n - 2 && u[k + 1] <= x) k++;
    double d = r->dr[j] = zr[j] - (kw[k] * (x - u[k]) + zw[k]);
    dmax = d > dmax ? d : dmax;
  }
  return dmax;
}

/* Depths of wheel vertices ia .. iend-1 under the rail into dw. */
static double wheel_block(const rail_view *r, const wheel_view *w, int ia, int iend, int k)
{
  const double *v = r->x, *zr = r->z, *kr = r->k, *u = w->x, *zw = w->z, s = w->s;
  int m = r->n;
  double dmax = -INFINITY;
  for (int i = ia; i < iend; i++) {
    double x = u[i] + s;
    while (k < m - 2 && v[k + 1] <= x) k++;
    double d = r->dw[i] = (kr[k] * (x - v[k]) + zr[k]) - zw[i];
    dmax = d > dmax ? d : dmax;
  }
  return dmax;
}

/* A bound on the depths of candidates a .. e of one kind (block b of its
   profile) over blocks qa .. qb of the other: at every candidate the rail
   lies below its chord + up and the wheel above its chord - down, so the
   depth lies below the lines' difference, linear along the candidates: its
   greater end value over each overlap of the two blocks. */
static double chord_bound(const rail_view *r, const wheel_view *w, int wheel, int b, int a, int e,
                          int qa, int qb)
{
  const rr_chords *cr = r->ch, *cw = w->ch, *co = wheel ? cr : cw;
  const double *x = wheel ? w->x : r->x, s = w->s, sh = wheel ? -w->s : w->s;
  double ub = -INFINITY;
  for (int q = qa; q <= qb; q++) { /* x: the candidates' own coordinate */
    int oa = q * BLOCK, oe = oa + BLOCK < co->n - 1 ? oa + BLOCK : co->n - 1;
    double lo = co->x[oa] + sh, hi = co->x[oe] + sh; /* the overlap (no NaN here: ternaries) */
    lo = x[a] > lo ? x[a] : lo;
    hi = x[e] < hi ? x[e] : hi;
    int pr = wheel ? q : b, pw = wheel ? b : q; /* the rail's block, the wheel's */
    for (int t = 0; t < 2; t++) {
      double xv = t ? hi : lo, xr = wheel ? xv + s : xv, xw = xr - s;
      double f =
          (cr->c[pr] + cr->k[pr] * xr + cr->up[pr]) - (cw->c[pw] + cw->k[pw] * xw - cw->down[pw]);
      ub = f > ub ? f : ub;
    }
  }
  return ub;
}

/* The candidates lo .. hi-1 of one kind (rail vertices, wheel: 0, 1) in
   blocks of BLOCK indices: a block whose bound (chord_bound) is below the
   deepest so far less the tie margin holds no candidate and is skipped
   (bmax -inf); the others' deepest go to bmax. The highest bound goes first.
   Returns the deepest. */
static double blocks(const rail_view *r, const wheel_view *w, int wheel, int lo, int hi,
                     double dmax, double *bmax, int *seg)
{
  if (hi <= lo) return dmax; /* none of this kind (lo may be the profile's end) */
  const double *x = wheel ? w->x : r->x, *o = wheel ? r->x : w->x;
  int no = wheel ? r->n : w->n, b0 = lo / BLOCK, b1 = (hi + BLOCK - 1) / BLOCK, top = -1;
  double sh = wheel ? w->s : -w->s; /* a candidate's coordinate on the other profile */
  for (int b = b0; b < b1; b++) {
    int a = b * BLOCK > lo ? b * BLOCK : lo, e = ((b + 1) * BLOCK < hi ? (b + 1) * BLOCK : hi) - 1;
    int ka = segment_from(o, no, x[a] + sh, &seg[2 * b]),
        kb = segment_from(o, no, x[e] + sh, &seg[2 * b + 1]);
    r->ub[b] = chord_bound(r, w, wheel, b, a, e, ka / BLOCK, kb / BLOCK);
    bmax[b] = -INFINITY;
    if (top < 0 || r->ub[b] > r->ub[top]) top = b;
  }
  for (int it = b0 - 1; it < b1; it++) {
    int b = it < b0 ? top : it;
    if (b < 0 || bmax[b] > -INFINITY || r->ub[b] + BOUND_MM < dmax - TIE_MM) continue;
    int a = b * BLOCK > lo ? b * BLOCK : lo, e = (b + 1) * BLOCK < hi ? (b + 1) * BLOCK : hi;
    bmax[b] = wheel ? wheel_block(r, w, a, e, seg[2 * b]) : rail_block(r, w, a, e, seg[2 * b]);
    dmax = bmax[b] > dmax ? bmax[b] : dmax;
  }
  return dmax;
}

/* The first candidate lo .. hi-1 (then the extra one) within the tie margin
   of dmax and below the rail coordinate lim, looking only into blocks whose
   deepest reaches the margin: its index, or -1. */
static int first_tie(const double *d, const double *bmax, int lo, int hi, int extra, double dmax,
                     const double *x, double sh, double lim)
{
  for (int b = lo / BLOCK; lo < hi && b * BLOCK < hi; b++) {
    if (!(bmax[b] >= dmax - TIE_MM)) continue;
    for (int j = b * BLOCK > lo ? b * BLOCK : lo; j < hi && j < (b + 1) * BLOCK; j++) {
      if (!(x[j] + sh < lim)) return -1;
      if (d[j] >= dmax - TIE_MM) return j;
    }
  }
  return extra >= 0 && x[extra] + sh < lim && d[extra] >= dmax - TIE_MM ? extra : -1;
}

/* deepest() with the candidates bounded a block at a time (no roll: the
   profiles' height ranges known); the same depths, deepest and tie. */
static double deepest_bounded(const rail_view *r, const wheel_view *w, int *kind, int *at)
{
  const double *v = r->x, *u = w->x, s = w->s;
  int m = r->n, n = w->n, jx = -1, ix = -1;
  double dmax = -INFINITY;
  int j0 = first_not_below(v, 0, m, -s, u[0]), j1 = first_not_below(v, j0, m, -s, u[n - 1]);
  if (j1 < m && v[j1] - s == u[n - 1]) { /* the last wheel point's own value (numpy.interp) */
    double d = r->dr[jx = j1] = r->z[j1] - w->z[n - 1];
    dmax = d > dmax ? d : dmax;
  }
  int i0 = first_not_below(u, 0, n, s, v[0]), i1 = first_not_below(u, i0, n, s, v[m - 1]);
  if (i1 < n && u[i1] + s == v[m - 1]) {
    double d = r->dw[ix = i1] = r->z[m - 1] - w->z[i1];
    dmax = d > dmax ? d : dmax;
  }
  dmax = blocks(r, w, 0, j0, j1, dmax, r->bmax_r, r->seg_r);
  dmax = blocks(r, w, 1, i0, i1, dmax, r->bmax_w, r->seg_w);
  int j = first_tie(r->dr, r->bmax_r, j0, j1, jx, dmax, v, 0, INFINITY);
  int i = first_tie(r->dw, r->bmax_w, i0, i1, ix, dmax, u, s, j >= 0 ? v[j] : INFINITY);
  *kind = i >= 0 ? 1 : j >= 0 ? 0 : -1;
  *at = i >= 0 ? i : j;
  return dmax;
}

/* The deepest overlap d = z_r - z_w over the candidates, and the tie with
   the smallest rail coordinate: *kind 0 a rail vertex (index *at), 1 a
   wheel vertex. Returns dmax (*kind -1 when the profiles do not overlap).
   One merge walk computes every depth; the ties are then read back. */
static double deepest(const rail_view *r, const wheel_view *w, int *kind, int *at)
{
  if (w->ch && r->ch) return deepest_bounded(r, w, kind, at);
  const double *restrict v = r->x, *restrict zr = r->z, *restrict kr = r->k, *restrict u = w->x,
                         *restrict zw = w->z, *restrict kw = w->k, s = w->s;
  double *restrict ddr = r->dr, *restrict ddw = r->dw;
  int *restrict ckr = r->kr, *restrict ckw = r->kw;
  int m = r->n, n = w->n, j0, j1, i0, i1;
  double dmax = -INFINITY, ulast = u[n - 1], vlast = v[m - 1];
  /* rail vertices over the wheel: u[0] <= v - s <= u[n-1] (the last, equal
     one on its own: numpy.interp gives the last value there) */
  for (j0 = 0; j0 < m && v[j0] - s < u[0]; j0++) {
  }
  int kp = 0;
  for (j1 = j0; j1 < m; j1++) {
    double x = v[j1] - s;
    if (!(x < ulast)) break;
    int k = ckr[j1] > kp ? ckr[j1] : kp; /* the segment: at least the previous vertex's */
    while (k > kp && u[k] > x) k--;
    while (k < n - 2 && u[k + 1] <= x) k++;
    ckr[j1] = kp = k;
    double d = ddr[j1] = zr[j1] - (kw[k] * (x - u[k]) + zw[k]);
    dmax = d > dmax ? d : dmax;
  }
  if (j1 < m && v[j1] - s == ulast) {
    double d = ddr[j1] = zr[j1] - zw[n - 1];
    dmax = d > dmax ? d : dmax;
    j1++;
  }
  /* wheel vertices over the rail: v[0] <= u + s <= v[m-1] */
  for (i0 = 0; i0 < n && u[i0] + s < v[0]; i0++) {
  }
  kp = 0;
  for (i1 = i0; i1 < n; i1++) {
    double x = u[i1] + s;
    if (!(x < vlast)) break;
    int k = ckw[i1] > kp ? ckw[i1] : kp;
    while (k > kp && v[k] > x) k--;
    while (k < m - 2 && v[k + 1] <= x) k++;
    ckw[i1] = kp = k;
    double d = ddw[i1] = (kr[k] * (x - v[k]) + zr[k]) - zw[i1];
    dmax = d > dmax ? d : dmax;
  }
  if (i1 < n && u[i1] + s == vlast) {
    double d = ddw[i1] = zr[m - 1] - zw[i1];
    dmax = d > dmax ? d : dmax;
    i1++;
  }
  *kind = -1;
  double vbest = INFINITY;
  for (int j = j0; j < j1; j++)
    if (r->dr[j] >= dmax - TIE_MM) {
      vbest = v[j];
      *kind = 0;
      *at = j;
      break;
    }
  for (int i = i0; i < i1 && u[i] + s < vbest; i++)
    if (r->dw[i] >= dmax - TIE_MM) {
      *kind = 1;
      *at = i;
      break;
    }
  return dmax;
}

/* One-sided slopes of a polyline at x: a vertex (x exactly one) has its two
   segments' slopes, an inner point its segment's twice. */
static void slopes(const double *x, const double *z, int n, double at, double *left, double *right)
{
  int k = rr_poly_segment(x, n, at);
  double sk = (z[k + 1] - z[k]) / (x[k + 1] - x[k]);
  *left = *right = sk;
  int vtx = at == x[k] ? k : at == x[k + 1] ? k + 1 : -1;
  if (vtx < 0) return;
  *left = vtx > 0 ? (z[vtx] - z[vtx - 1]) / (x[vtx] - x[vtx - 1]) : sk;
  *right = vtx < n - 1 ? (z[vtx + 1] - z[vtx]) / (x[vtx + 1] - x[vtx]) : sk;
}

/* The contact of one side: rail point, wheel point (in the wheel view's own
   coordinates), angle, validity; false when the profiles do not overlap. */
static int side_contact(const rail_view *r, const wheel_view *w, rr_contact_side *c, double *wx_out)
{
  int kind = -1, at = -1;
  double dmax = deepest(r, w, &kind, &at);
  if (kind < 0) return 0;
  double vc, wx; /* the contact's rail coordinate, and its wheel-view coordinate */
  if (kind == 0) {
    vc = r->x[at];
    wx = vc - w->s;
    c->rail_z_mm = r->z[at];
  } else {
    wx = w->x[at];
    vc = wx + w->s;
    c->rail_z_mm = rr_poly_interp(r->x, r->z, r->n, vc);
  }
  c->rail_v_mm = vc;
  c->lift_mm = dmax;
  double swl, swr, srl, srr;
  slopes(w->x, w->z, w->n, wx, &swl, &swr);
  slopes(r->x, r->z, r->n, vc, &srl, &srr);
  c->gamma_rad = atan((fmax(swl, srr) + fmin(swr, srl)) / 2);
  double lo = fmax(r->x[0], w->x[0] + w->s), hi = fmin(r->x[r->n - 1], w->x[w->n - 1] + w->s);
  c->valid = !(vc - lo <= END_MM || hi - vc <= END_MM);
  *wx_out = wx;
  return 1;
}

/* Scratch of one execute call: candidates' depths and a turned wheel; with
   no roll, each side's height ranges (the wheel's least, the rail's
   greatest) and the blocks' bounds. */
typedef struct search_ws {
  double *dr, *dw, *tx, *tz, *tk, *ub, *bmax_r, *bmax_w;
  int *kr[2], *kw[2];       /* per side: segment guesses (search, rail_view) */
  int *seg_r[2], *seg_w[2]; /* per side: the blocks' end segments */
  rr_chords wch[2], rch[2]; /* per side: the wheel's and the rail's chords (no roll) */
  int bounded;
} search_ws;

static rail_view rail_of(const rr_contact_plan *p, int s, const search_ws *ws)
{
  return (rail_view){.x = p->rail[s].x,
                     .z = p->rail[s].z,
                     .k = p->rail_k[s],
                     .n = p->rail[s].n,
                     .dr = ws->dr,
                     .dw = ws->dw,
                     .kr = ws->kr[s],
                     .kw = ws->kw[s],
                     .ub = ws->ub,
                     .bmax_r = ws->bmax_r,
                     .bmax_w = ws->bmax_w,
                     .seg_r = ws->seg_r[s],
                     .seg_w = ws->seg_w[s]};
}

/* No roll: each wheel lowered onto its rail, s = +-y + offset. */
static int state_no_roll(const rr_contact_plan *p, double y, const search_ws *ws,
                         rr_contact_state *st, rr_error *err)
{
  for (int s = 0; s < 2; s++) {
    const rr_polyline *w = &p->wheel[s];
    wheel_view wv = {.x = w->x,
                     .z = w->z,
                     .k = p->wheel_k[s],
                     .n = w->n,
                     .s = (s ? -y : y) + p->setup.offset_mm[s],
                     .ch = ws->bounded ? &ws->wch[s] : NULL};
    rail_view rv = rail_of(p, s, ws);
    rv.ch = ws->bounded ? &ws->rch[s] : NULL;
    rr_contact_side *c = &st->side[s];
    double u;
    if (!side_contact(&rv, &wv, c, &u))
      return rr_seterr(err, RR_EINVAL, "contact: at y = %g mm the %s wheel is off its rail", y,
                       s ? "left" : "right");
    c->wheel_u_mm = u;
    c->wheel_z_mm = rr_poly_interp(w->x, w->z, w->n, u); /* a vertex's own z exactly */
    c->r_mm = p->setup.r0_mm[s] - c->wheel_z_mm;
  }
  st->roll_rad = 0;
  st->roll_implied_rad =
      ((st->side[0].lift_mm + p->setup.r0_mm[0]) - (st->side[1].lift_mm + p->setup.r0_mm[1])) /
      (2 * p->setup.b_mm);
  return RR_OK;
}

/* Rigid roll: the wheel of side s turned by phi about the axle (H = 0) into
   the rail's frame, into ws's tx, tz, tk; false when it no longer rises
   strictly. */
static int turned_wheel(const rr_contact_plan *p, int s, double y, double phi, const search_ws *ws)
{
  const rr_polyline *w = &p->wheel[s];
  double c = cos(phi), sn = sin(phi), b = p->setup.b_mm, r0 = p->setup.r0_mm[s],
         Y = p->setup.Y_mm[s], sg = s ? -1 : 1;
  for (int i = 0; i < w->n; i++) {
    double eta = b + w->x[i], zeta = w->z[i] - r0;
    ws->tx[i] = sg * y + c * eta - sg * sn * zeta - Y;
    ws->tz[i] = sg * sn * eta + c * zeta;
    if (i && !(ws->tx[i] > ws->tx[i - 1])) return 0;
  }
  rr_poly_slopes(ws->tx, ws->tz, w->n, ws->tk);
  return 1;
}

static wheel_view turned_view(const rr_contact_plan *p, int s, const search_ws *ws)
{
  return (wheel_view){.x = ws->tx, .z = ws->tz, .k = ws->tk, .n = p->wheel[s].n, .s = 0};
}

/* The height side s needs at roll phi (-inf when it cannot touch). */
static double side_height(const rr_contact_plan *p, int s, double y, double phi,
                          const search_ws *ws)
{
  if (!turned_wheel(p, s, y, phi, ws)) return -INFINITY;
  wheel_view wv = turned_view(p, s, ws);
  rail_view rv = rail_of(p, s, ws);
  int kind = -1, at;
  double h = deepest(&rv, &wv, &kind, &at);
  return kind < 0 ? -INFINITY : h;
}

typedef struct roll_fn {
  const rr_contact_plan *p;
  double y;
  const search_ws *ws;
} roll_fn;

/* Both wheels touch where F(phi) = H_R(phi) - H_L(phi) = 0. */
static double roll_F(const roll_fn *f, double phi)
{
  return side_height(f->p, 0, f->y, phi, f->ws) - side_height(f->p, 1, f->y, phi, f->ws);
}

/* Brent's root finder on [a, b] with F(a), F(b) of opposite signs, to
   |dphi| <= 1e-17 + 1e-15 |phi|. */
static double brent(const roll_fn *f, double a, double b, double fa, double fb)
{
  double c = a, fc = fa, d = b - a, e = d;
  for (int it = 0; it < 200; it++) {
    if ((fb > 0) == (fc > 0)) {
      c = a;
      fc = fa;
      d = e = b - a;
    }
    if (fabs(fc) < fabs(fb)) {
      a = b;
      b = c;
      c = a;
      fa = fb;
      fb = fc;
      fc = fa;
    }
    double tol = 1e-17 + 1e-15 * fabs(b), m = 0.5 * (c - b);
    if (fabs(m) <= tol || fb == 0) return b;
    if (fabs(e) >= tol && fabs(fa) > fabs(fb)) { /* interpolation */
      double s = fb / fa, pp, q;
      if (a == c) {
        pp = 2 * m * s;
        q = 1 - s;
      } else {
        double qq = fa / fc, r = fb / fc;
        pp = s * (2 * m * qq * (qq - r) - (b - a) * (r - 1));
        q = (qq - 1) * (r - 1) * (s - 1);
      }
      if (pp > 0) q = -q;
      pp = fabs(pp);
      if (2 * pp < fmin(3 * m * q - fabs(tol * q), fabs(e * q))) {
        e = d;
        d = pp / q;
      } else {
        d = m;
        e = m;
      }
    } else {
      d = m;
      e = m;
    }
    a = b;
    fa = fb;
    b += fabs(d) > tol ? d : (m > 0 ? tol : -tol);
    fb = roll_F(f, b);
  }
  return b;
}

/* The roll at which both wheels touch, from the guess phi_g outward. */
static int solve_roll(const roll_fn *f, double guess, double *phi, rr_error *err)
{
  double d = 1e-5 + 0.05 * fabs(guess), a, b, fa, fb;
  for (int k = 0; k < 60; k++, d *= 2) {
    a = guess - d;
    b = guess + d;
    fa = roll_F(f, a);
    fb = roll_F(f, b);
    if (isfinite(fa) && isfinite(fb) && (fa > 0) != (fb > 0)) {
      *phi = brent(f, a, b, fa, fb);
      return RR_OK;
    }
  }
  return rr_seterr(err, RR_ENOCONV,
                   "contact: no wheelset roll brings both wheels onto their rails "
                   "at y = %g mm",
                   f->y);
}

/* Rigid roll: the roll solved, then each side's contact on its turned
   wheel, the wheel point mapped back to the wheel's own coordinates. */
static int state_rigid(const rr_contact_plan *p, double y, double *guess, int first,
                       const search_ws *ws, rr_contact_state *st, rr_error *err)
{
  roll_fn f = {.p = p, .y = y, .ws = ws};
  double phi = 0, g = *guess;
  if (first) g = roll_F(&f, 0) / (2 * p->setup.b_mm);
  if (!isfinite(g)) g = 0;
  int rc = solve_roll(&f, g, &phi, err);
  if (rc) return rc;
  *guess = phi;
  double H = side_height(p, 0, y, phi, ws);
  for (int s = 0; s < 2; s++) {
    const rr_polyline *w = &p->wheel[s];
    if (!turned_wheel(p, s, y, phi, ws))
      return rr_seterr(err, RR_EINVAL, "contact: the turned wheel folds over at y = %g mm", y);
    wheel_view wv = turned_view(p, s, ws);
    rail_view rv = rail_of(p, s, ws);
    rr_contact_side *c = &st->side[s];
    double vx;
    if (!side_contact(&rv, &wv, c, &vx))
      return rr_seterr(err, RR_EINVAL, "contact: at y = %g mm the %s wheel is off its rail", y,
                       s ? "left" : "right");
    int k = rr_poly_segment(ws->tx, w->n, vx);
    double t = (vx - ws->tx[k]) / (ws->tx[k + 1] - ws->tx[k]);
    c->wheel_u_mm = t == 0 ? w->x[k] : t == 1 ? w->x[k + 1] : w->x[k] + t * (w->x[k + 1] - w->x[k]);
    c->wheel_z_mm = t == 0 ? w->z[k] : t == 1 ? w->z[k + 1] : w->z[k] + t * (w->z[k + 1] - w->z[k]);
    c->r_mm = p->setup.r0_mm[s] - c->wheel_z_mm;
    c->lift_mm = H + sin(phi) * (s ? -p->setup.b_mm : p->setup.b_mm) - cos(phi) * p->setup.r0_mm[s];
  }
  st->roll_rad = st->roll_implied_rad = phi;
  return RR_OK;
}

/* The no-roll search's chords of both sides into ws (tables in t). */
static void ws_bounds(const rr_contact_plan *p, search_ws *ws, double *t)
{
  for (int s = 0; s < 2; s++) {
    const rr_polyline *w = &p->wheel[s], *r = &p->rail[s];
    rr_chords_build(&ws->wch[s], t, w->x, w->z, w->n, BLOCK);
    t += 4 * (size_t)rr_chords_count(w->n, BLOCK);
    rr_chords_build(&ws->rch[s], t, r->x, r->z, r->n, BLOCK);
    t += 4 * (size_t)rr_chords_count(r->n, BLOCK);
  }
  ws->bounded = 1;
}

int rr_contact_execute(const rr_contact_plan *p, const double *y_mm, int n, rr_contact_state *out,
                       rr_error *err)
{
  int m = p->rail[0].n > p->rail[1].n ? p->rail[0].n : p->rail[1].n,
      nw = p->wheel[0].n > p->wheel[1].n ? p->wheel[0].n : p->wheel[1].n, st = RR_OK;
  int nb = (m > nw ? m : nw) / BLOCK + 2, bounded = p->roll != RR_ROLL_RIGID;
  size_t nt =
      bounded ? 8 * ((size_t)rr_chords_count(nw, BLOCK) + (size_t)rr_chords_count(m, BLOCK)) : 0;
  /* one scratch block a call */
  double *blk = malloc(sizeof(double) * ((size_t)m + 4 * (size_t)nw + 3 * (size_t)nb + nt)),
         guess = 0;
  int *ik = calloc(2 * ((size_t)m + (size_t)nw) + 8 * (size_t)nb, sizeof *ik);
  if (!blk || !ik) {
    free(blk);
    free(ik);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  int *sg = ik + 2 * ((size_t)m + (size_t)nw); /* 2 segments a block, per kind and side */
  search_ws ws = {.dr = blk,
                  .dw = blk + m,
                  .tx = blk + m + nw,
                  .tz = blk + m + 2 * nw,
                  .tk = blk + m + 3 * nw,
                  .ub = blk + m + 4 * nw,
                  .bmax_r = blk + m + 4 * nw + nb,
                  .bmax_w = blk + m + 4 * nw + 2 * nb,
                  .kr = {ik, ik + m + nw},
                  .kw = {ik + m, ik + 2 * m + nw},
                  .seg_r = {sg, sg + 2 * nb},
                  .seg_w = {sg + 4 * nb, sg + 6 * nb}};
  if (bounded) ws_bounds(p, &ws, blk + m + 4 * nw + 3 * nb);
  for (int i = 0; i < n && !st; i++) {
    rr_contact_state *s = &out[i];
    memset(s, 0, sizeof *s);
    s->y_mm = y_mm[i];
    if (!isfinite(y_mm[i]))
      st = rr_seterr(err, RR_EINVAL, "contact: y must be finite");
    else if (p->roll == RR_ROLL_RIGID)
      st = state_rigid(p, y_mm[i], &guess, i == 0, &ws, s, err);
    else
      st = state_no_roll(p, y_mm[i], &ws, s, err);
    s->dr_mm = s->side[0].r_mm - s->side[1].r_mm;
    s->valid = s->side[0].valid && s->side[1].valid;
  }
  free(blk);
  free(ik);
  return st;
}

int rr_contact_jumps(const rr_contact_state *s, int n, rr_contact_jump *out, int cap)
{
  int k = 0;
  for (int i = 1; i < n; i++)
    for (int sd = 0; sd < 2; sd++) {
      const rr_contact_side *a = &s[i - 1].side[sd], *b = &s[i].side[sd];
      if (!(fabs(b->rail_v_mm - a->rail_v_mm) > JUMP_MM)) continue;
      if (k < cap)
        out[k] = (rr_contact_jump){.side = sd,
                                   .y_from_mm = s[i - 1].y_mm,
                                   .y_to_mm = s[i].y_mm,
                                   .rail_from_mm = a->rail_v_mm,
                                   .rail_to_mm = b->rail_v_mm,
                                   .wheel_from_mm = a->wheel_u_mm,
                                   .wheel_to_mm = b->wheel_u_mm};
      k++;
    }
  return k;
}

long rr_contact_range(double a, double b, double step, double *out, long cap)
{
  if (!(step > 0) || !(b >= a) || !isfinite(a) || !isfinite(b)) return -1;
  double cnt = floor((b - a) / step + 1e-9) + 1;
  if (!(cnt <= 1e8)) return -1;
  long n = (long)cnt;
  for (long k = 0; out && k < n && k < cap; k++)
    out[k] = rint((a + (double)k * step) * 1e10) / 1e10;
  return n;
}
