/* The nonlinear right-hand side (docs/model.md, "Nonlinear model"): the
 * suspension as the linear state matrix without the contact terms, plus per
 * wheelset the contact forces with conicity lambda(|y - y_t|), creep forces
 * saturated per wheel and the flange dead-band spring, or, from wheel and
 * rail profiles, the tabulated rolling-radius difference and contact angles;
 * with their derivatives for the Jacobian. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/nonlinear.h"
#include "model/model_impl.h"
#include "nonlinear/nonlinear_impl.h"
#include "util/internal.h"
#include "vehicle/profile_impl.h"

#define RR_NL_MAX_STATES (2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES)

typedef struct wheelset {
  int y, p;                /* DOF indices */
  double f11, f22, r0, l0; /* per wheel */
  double W, muN;           /* axle load (gravitational stiffness), friction limit per wheel */
  double im_y, im_p;       /* 1 / m_w, 1 / I_wz */
} wheelset;

/* Contact functions on s = y_w - y_t (ascending, s_k = s0 + k ds):
   g = (r_L - r_R) / 2 = -dr(-s) / 2 (lambda s for a cone) and
   t = tan gamma_L(-s) - tan gamma_R(-s); within [lo, hi] every contact
   lies within the profiles' data. */
#define TABLE_EDGES_MAX                                                                            \
  12 /* per wheelset: with the saturation's, 4 wheelsets in the orbits' 64                         \
      */
typedef struct contact_table {
  int n, nedges;
  double s0, ds, lo, hi;
  double *g, *t;
  double edge[TABLE_EDGES_MAX]; /* the contact jumps' cells' edges in s: kinks */
} contact_table;

struct rr_nonlinear {
  int N, n, nw, gravity;
  double v;
  rr_profile prof;
  contact_table *table; /* NULL: lambda(a) and the flange spring */
  rr_contact_law law;
  wheelset w[RR_SYS_MAX_INPUTS];
  int nnz; /* the suspension's state matrix, sparse by rows */
  int *row_start, *col;
  double *val;
};

rr_contact_law rr_contact_law_default(void)
{
  return (rr_contact_law){
      .friction = 0.3, .flange_clearance = 8e-3, .flange_stiffness = 500e6, .saturation = 1};
}

void rr_nonlinear_free(rr_nonlinear *nl)
{
  if (!nl) return;
  if (nl->table) {
    free(nl->table->g);
    free(nl->table->t);
    free(nl->table);
  }
  free(nl->row_start);
  free(nl->col);
  free(nl->val);
  free(nl);
}

static int check_inputs(const rr_model *m, const rr_contact_law *law, rr_error *err)
{
  if (m->sdf_mode == RR_SDF_PAPER && m->nsdf)
    return rr_seterr(
        err, RR_EUNSUP,
        "nonlinear model: the paper-mode SDF has no time form (use sdf = physical or none)");
  if (m->sdf_mode == RR_SDF_PHYSICAL && m->curve.kind == RR_CURVE_TABLE)
    return rr_seterr(err, RR_EUNSUP, "nonlinear model: a tabulated SDF curve has no time form");
  if (!(law->friction > 0 && law->friction <= 2 && law->flange_clearance >= 0 &&
        law->flange_clearance <= 0.05 && law->flange_stiffness >= 0 &&
        law->flange_stiffness <= 1e11))
    return rr_seterr(
        err, RR_EINVAL,
        "contact law: friction in (0, 2], flange clearance 0 .. 50 mm, stiffness 0 .. 1e11 N/m");
  for (int i = 0; i < m->ni; i++)
    if (m->contacts[i].spec.dx != 0)
      return rr_seterr(err, RR_EUNSUP,
                       "nonlinear model: contacts must sit at their wheelset's reference point");
  return RR_OK;
}

/* The state matrix with the contact terms taken out (C0, K0), as rows of
   nonzeros. */
static int suspension(rr_nonlinear *nl, const rr_model *m, rr_error *err)
{
  rr_model *s = NULL;
  double *A = malloc(sizeof(double) * (size_t)nl->N * (size_t)nl->N);
  if (rr_model_clone(m, &s, err) || !A) {
    free(s);
    free(A);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  size_t nn = sizeof(double) * (size_t)m->n * (size_t)m->n;
  memcpy(s->C, s->C0, nn);
  memcpy(s->K, s->K0, nn);
  int st = rr_model_state_matrix(s, 0, A, err), N = nl->N;
  free(s);
  for (int i = 0; i < N * N && !st; i++) nl->nnz += A[i] != 0;
  nl->row_start = malloc(sizeof(int) * (size_t)(N + 1));
  nl->col = malloc(sizeof(int) * (size_t)(nl->nnz + 1));
  nl->val = malloc(sizeof(double) * (size_t)(nl->nnz + 1));
  if (!st && (!nl->row_start || !nl->col || !nl->val))
    st = rr_seterr(err, RR_ENOMEM, "out of memory");
  for (int i = 0, k = 0; i < N && !st; i++) {
    nl->row_start[i] = k;
    for (int j = 0; j < N; j++)
      if (A[i * N + j] != 0) {
        nl->col[k] = j;
        nl->val[k++] = A[i * N + j];
      }
    nl->row_start[i + 1] = k;
  }
  free(A);
  return st;
}

/* The vehicle without its contact geometry (nl->prof, nl->table unset). */
static int nonlinear_alloc(const rr_model *m, const rr_contact_law *law, rr_nonlinear **out,
                           rr_error *err)
{
  *out = NULL;
  int st = check_inputs(m, law, err);
  if (st) return st;
  rr_nonlinear *nl = calloc(1, sizeof *nl);
  if (!nl) return rr_seterr(err, RR_ENOMEM, "out of memory");
  nl->N = rr_model_state_size(m);
  nl->n = m->n;
  nl->nw = m->ni;
  nl->v = m->speed;
  nl->gravity = m->gravity;
  nl->law = *law;
  for (int i = 0; i < m->ni; i++) {
    const rr_contact *c = &m->contacts[i];
    nl->w[i] = (wheelset){.y = c->dof_y,
                          .p = c->dof_psi,
                          .f11 = c->spec.f11,
                          .f22 = c->spec.f22,
                          .r0 = c->spec.r0,
                          .l0 = c->spec.l0,
                          .W = c->spec.axle_load,
                          .muN = law->friction * c->spec.axle_load / 2,
                          .im_y = 1 / m->mdiag[c->dof_y],
                          .im_p = 1 / m->mdiag[c->dof_psi]};
  }
  if ((st = suspension(nl, m, err))) {
    rr_nonlinear_free(nl);
    return st;
  }
  *out = nl;
  return RR_OK;
}

int rr_nonlinear_new(const rr_model *m, const rr_profile *p, const rr_contact_law *law,
                     rr_nonlinear **out, rr_error *err)
{
  *out = NULL;
  rr_contact_law def = rr_contact_law_default();
  int st = rr_profile_check(p, err);
  if (!st) st = nonlinear_alloc(m, law ? law : &def, out, err);
  if (!st) (*out)->prof = *p;
  return st;
}

/* The run of valid points around y = 0 of cf, as a range of s = -y. */
static int valid_run(const rr_contact_functions *cf, contact_table *t, rr_error *err)
{
  int k0 = (int)lround(-cf->y0_m / cf->dy_m), lo = k0, hi = k0;
  if (k0 < 0 || k0 >= cf->n || (cf->valid && !cf->valid[k0]))
    return rr_seterr(err, RR_EINVAL,
                     "contact functions: y = 0 must lie on the grid, within the profiles' data");
  while (cf->valid && lo > 0 && cf->valid[lo - 1]) lo--;
  while (cf->valid && hi < cf->n - 1 && cf->valid[hi + 1]) hi++;
  if (!cf->valid) lo = 0, hi = cf->n - 1;
  t->lo = -(cf->y0_m + hi * cf->dy_m);
  t->hi = -(cf->y0_m + lo * cf->dy_m);
  return RR_OK;
}

static int table_from(const rr_contact_functions *cf, contact_table **out, rr_error *err)
{
  *out = NULL;
  if (!(cf && cf->n >= 3 && cf->dy_m > 0 && isfinite(cf->y0_m) && cf->dr_m && cf->tan_right &&
        cf->tan_left))
    return rr_seterr(err, RR_EINVAL, "contact functions: need 3 or more points, dy > 0");
  contact_table *t = calloc(1, sizeof *t);
  if (!t) return rr_seterr(err, RR_ENOMEM, "out of memory");
  int n = cf->n, st = valid_run(cf, t, err);
  t->n = n;
  t->ds = cf->dy_m;
  t->s0 = -(cf->y0_m + (n - 1) * cf->dy_m);
  t->g = malloc(sizeof(double) * (size_t)n);
  t->t = malloc(sizeof(double) * (size_t)n);
  if (!st && (!t->g || !t->t)) st = rr_seterr(err, RR_ENOMEM, "out of memory");
  for (int j = 0; j < cf->nedges && t->nedges < TABLE_EDGES_MAX; j++) {
    double e = -cf->edge_y_m[j];
    int dup = 0;
    for (int i = 0; i < t->nedges; i++) dup |= fabs(t->edge[i] - e) < 1e-3 * t->ds;
    if (!dup && e >= t->lo && e <= t->hi) t->edge[t->nedges++] = e;
  }
  for (int k = 0; k < n && !st; k++) { /* s_k = -y_(n-1-k) */
    int j = n - 1 - k;
    t->g[k] = -0.5 * cf->dr_m[j];
    t->t[k] = cf->tan_left[j] - cf->tan_right[j];
    if (!isfinite(t->g[k]) || !isfinite(t->t[k]))
      st = rr_seterr(err, RR_EINVAL, "contact functions: a value that is not finite");
  }
  if (st) {
    free(t->g);
    free(t->t);
    free(t);
    return st;
  }
  *out = t;
  return RR_OK;
}

int rr_nonlinear_new_contact(const rr_model *m, const rr_contact_functions *cf,
                             const rr_contact_law *law, rr_nonlinear **out, rr_error *err)
{
  *out = NULL;
  rr_contact_law def = rr_contact_law_default();
  int st = nonlinear_alloc(m, law ? law : &def, out, err);
  if (!st) st = table_from(cf, &(*out)->table, err);
  if (st) {
    rr_nonlinear_free(*out);
    *out = NULL;
    return st;
  }
  (*out)->prof = (rr_profile){.kind = RR_PROFILE_NONE};
  snprintf((*out)->prof.name, sizeof(*out)->prof.name, "%s",
           cf->source[0] ? cf->source : "profiles");
  return RR_OK;
}

static double table_at(const contact_table *T, const double *c, double s, double *slope);

#define HARMONIC_POINTS 256 /* around the circle: the table's segments average out */

/* The harmonic linearisation (1/(pi a)) int_0^2pi c(a sin th) sin th dth of
   column c at amplitude a (m): the slope a cycle of that amplitude sees. */
static double harmonic_slope(const contact_table *T, const double *c, double a)
{
  double sum = 0, d;
  for (int k = 0; k < HARMONIC_POINTS; k++) {
    double sn = sin(2 * RR_PI * (k + 0.5) / HARMONIC_POINTS);
    sum += table_at(T, c, a * sn, &d) * sn;
  }
  return 2 * sum / (HARMONIC_POINTS * a);
}

void rr_nonlinear_jacobian_harmonic_at(const rr_nonlinear *nl, double v, double amp, double *J)
{
  int N = nl->N;
  double z[RR_NL_MAX_STATES] = {0};
  rr_nonlinear_jacobian_at(nl, v, z, NULL, J);
  if (!nl->table || !(amp > 0)) return;
  const contact_table *T = nl->table;
  double dg0, dt0;
  table_at(T, T->g, 0, &dg0);
  table_at(T, T->t, 0, &dt0);
  double dg = harmonic_slope(T, T->g, amp) - dg0, dt = harmonic_slope(T, T->t, amp) - dt0;
  for (int i = 0; i < nl->nw; i++) { /* at rest: eps = 1, so only the geometry's slopes change */
    const wheelset *w = &nl->w[i];
    J[(nl->n + w->y) * N + w->y] += -0.5 * w->W * dt * w->im_y;
    J[(nl->n + w->p) * N + w->y] += -2 * w->l0 * w->f11 * dg / w->r0 * w->im_p;
  }
}

int rr_nonlinear_is_odd(const rr_nonlinear *nl)
{
  const contact_table *T = nl->table;
  if (!T) return 1; /* lambda(|d|) d and the flange spring are odd in d */
  for (int k = 0; k < T->n; k++)
    if (T->g[k] != -T->g[T->n - 1 - k] || T->t[k] != -T->t[T->n - 1 - k]) return 0;
  return fabs(T->s0 + 0.5 * (T->n - 1) * T->ds) <= 1e-12 * T->ds * T->n;
}

void rr_nonlinear_contact_range(const rr_nonlinear *nl, double *lo_m, double *hi_m)
{
  *lo_m = nl->table ? nl->table->lo : -INFINITY;
  *hi_m = nl->table ? nl->table->hi : INFINITY;
}

int rr_nonlinear_set_speed(rr_nonlinear *nl, double v, rr_error *err)
{
  if (!(v > 0 && v <= RR_SPEED_MAX_MS))
    return rr_seterr(err, RR_EINVAL, "speed %g km/h outside (0, %g] km/h", v * RR_KMH,
                     RR_SPEED_MAX_MS * RR_KMH);
  nl->v = v;
  return RR_OK;
}

double rr_nonlinear_speed(const rr_nonlinear *nl) { return nl->v; }
int rr_nonlinear_size(const rr_nonlinear *nl) { return nl->N; }
int rr_nonlinear_ndof(const rr_nonlinear *nl) { return nl->n; }
int rr_nonlinear_ninputs(const rr_nonlinear *nl) { return nl->nw; }
int rr_nonlinear_index_y(const rr_nonlinear *nl, int i)
{
  return i >= 0 && i < nl->nw ? nl->w[i].y : -1;
}

/* The Shen-Hedrick-Elkins factor eps(beta) and d eps / d beta. */
static double saturation(double beta, double *deps)
{
  if (beta < 3) {
    *deps = -1.0 / 3 + 2 * beta / 27;
    return 1 - beta / 3 + beta * beta / 27;
  }
  *deps = -1 / (beta * beta);
  return 1 / beta;
}

/* The unsaturated creep forces f11 s and f22 xy of one wheel (N), gd the
   rolling-radius term (r_L - r_R) / 2 (lambda d for a cone): s the left
   wheel's longitudinal creepage (the right's is -s), xy both wheels'
   lateral one. */
static void creep_forces(const wheelset *w, double v, const double *x, double gd, double *fx,
                         double *fy)
{
  *fx = w->f11 * (w->l0 * x[3] / v + gd / w->r0);
  *fy = w->f22 * (x[2] / v - x[1]);
}

/* Linear interpolation of a table's column c at s, and its slope (at a
   grid point the mean of the two sides'; held beyond the ends, slope 0). */
static double table_at(const contact_table *T, const double *c, double s, double *slope)
{
  double x = (s - T->s0) / T->ds;
  if (!(x > 0)) {
    *slope = 0;
    return c[0];
  }
  if (x >= T->n - 1) {
    *slope = 0;
    return c[T->n - 1];
  }
  int k = (int)x;
  double u = x - k, d = c[k + 1] - c[k];
  *slope = (u == 0 && k > 0 ? 0.5 * (c[k + 1] - c[k - 1]) : d) / T->ds;
  return c[k] + u * d;
}

/* The geometry's share of one wheelset's contact at d = y_w - y_t: the
   rolling-radius term gd and d gd / dd, and the lateral force that is not
   creep (flange spring and gravitational stiffness, or the normal forces'
   resultant from the profiles) with d/dd; the yaw moment's gravitational
   term W lambda l0 (per rad of psi) with d/dd. */
typedef struct contact_geometry {
  double gd, dgd, fy, dfy, mz_psi, dmz_psi;
  double flange; /* the flange spring's share of fy, or the normal forces' */
} contact_geometry;

static contact_geometry geometry(const rr_nonlinear *nl, const wheelset *w, double d)
{
  contact_geometry g = {0};
  if (nl->table) {
    double dt, t = table_at(nl->table, nl->table->t, d, &dt);
    g.gd = table_at(nl->table, nl->table->g, d, &g.dgd);
    g.fy = g.flange = -0.5 * w->W * t;
    g.dfy = -0.5 * w->W * dt;
    return g;
  }
  const rr_contact_law *law = &nl->law;
  double a = fabs(d), dl, lam = rr_profile_eval(&nl->prof, a, &dl), sg = d > 0 ? 1 : d < 0 ? -1 : 0;
  g.gd = lam * d;
  g.dgd = lam + dl * a; /* d(lambda(|d|) d) / dd */
  if (law->flange_stiffness > 0 && a > law->flange_clearance) {
    g.fy = g.flange = -law->flange_stiffness * (a - law->flange_clearance) * sg;
    g.dfy = -law->flange_stiffness;
  }
  if (nl->gravity) { /* K += W lambda / l0 on y, -W lambda l0 on psi, with lambda(|d|) */
    g.fy -= w->W * g.gd / w->l0;
    g.dfy -= w->W * g.dgd / w->l0;
    g.mz_psi = w->W * lam * w->l0;
    g.dmz_psi = w->W * w->l0 * dl * sg;
  }
  return g;
}

/* Forces of one wheelset: F[0] lateral (creep + geometry), F[1] yaw
   moment; with dF (may be NULL: the right-hand side needs none), their
   derivatives dF[k][0..4] in y, psi, dy/dt, dpsi/dt and the speed v;
   flange the geometry's share of F[0] (the flange spring's and gravity's,
   or the normal forces'). x = (y, psi, dy/dt, dpsi/dt). */
static void contact(const rr_nonlinear *nl, double v, const wheelset *w, const double *x, double yt,
                    double F[2], double dF[2][5], double *flange)
{
  const rr_contact_law *law = &nl->law;
  contact_geometry g = geometry(nl, w, x[0] - yt);
  double fx, fy, eps = 1, deps = 0, fn = 0;
  creep_forces(w, v, x, g.gd, &fx, &fy);
  int sat = law->saturation && w->muN > 0;
  if (sat) { /* |F| < 1e9 N: no overflow to guard against */
    fn = sqrt(fx * fx + fy * fy);
    eps = saturation(fn / w->muN, &deps);
  }
  /* both wheels share |F|, hence eps: F_y = 2 eps (-f22 xy), M_z = 2 eps (-f11 s) l0 */
  F[0] = -2 * eps * fy + g.fy;
  F[1] = -2 * eps * fx * w->l0 + g.mz_psi * x[1];
  *flange = g.flange;
  if (!dF) return;
  double ds[5] = {g.dgd / w->r0, 0, 0, w->l0 / v, -w->l0 * x[3] / (v * v)};
  double dxy[5] = {0, -1, 1 / v, 0, -x[2] / (v * v)}, db[5] = {0, 0, 0, 0, 0};
  for (int k = 0; k < 5 && sat && fn > 0; k++)
    db[k] = (fx * w->f11 * ds[k] + fy * w->f22 * dxy[k]) / (fn * w->muN);
  for (int k = 0; k < 5; k++) {
    dF[0][k] = -2 * (eps * w->f22 * dxy[k] + fy * deps * db[k]);
    dF[1][k] = -2 * w->l0 * (eps * w->f11 * ds[k] + fx * deps * db[k]);
  }
  dF[0][0] += g.dfy;
  dF[1][1] += g.mz_psi;
  dF[1][0] += g.dmz_psi * x[1];
}

static void wheel_state(const rr_nonlinear *nl, const wheelset *w, const double *z, double x[4])
{
  x[0] = z[w->y];
  x[1] = z[w->p];
  x[2] = z[nl->n + w->y];
  x[3] = z[nl->n + w->p];
}

void rr_nonlinear_rhs_at(const rr_nonlinear *nl, double v, const double *z, const double *yt,
                         double *dz)
{
  for (int i = 0; i < nl->N; i++) {
    double acc = 0;
    for (int k = nl->row_start[i]; k < nl->row_start[i + 1]; k++) acc += nl->val[k] * z[nl->col[k]];
    dz[i] = acc;
  }
  for (int i = 0; i < nl->nw; i++) {
    const wheelset *w = &nl->w[i];
    double x[4], F[2], fl;
    wheel_state(nl, w, z, x);
    contact(nl, v, w, x, yt ? yt[i] : 0, F, NULL, &fl);
    dz[nl->n + w->y] += F[0] * w->im_y;
    dz[nl->n + w->p] += F[1] * w->im_p;
  }
}

void rr_nonlinear_jacobian_at(const rr_nonlinear *nl, double v, const double *z, const double *yt,
                              double *J)
{
  int N = nl->N;
  memset(J, 0, sizeof(double) * (size_t)N * (size_t)N);
  for (int i = 0; i < N; i++)
    for (int k = nl->row_start[i]; k < nl->row_start[i + 1]; k++)
      J[i * N + nl->col[k]] = nl->val[k];
  for (int i = 0; i < nl->nw; i++) {
    const wheelset *w = &nl->w[i];
    double x[4], F[2], dF[2][5], fl;
    wheel_state(nl, w, z, x);
    contact(nl, v, w, x, yt ? yt[i] : 0, F, dF, &fl);
    int cols[4] = {w->y, w->p, nl->n + w->y, nl->n + w->p};
    for (int k = 0; k < 4; k++) {
      J[(nl->n + w->y) * N + cols[k]] += dF[0][k] * w->im_y;
      J[(nl->n + w->p) * N + cols[k]] += dF[1][k] * w->im_p;
    }
  }
}

/* out = J X, J = d(dz/dt)/dz at z, X and out N x m row by row (the m
   columns side by side); with dfdv, the speed derivative d(dz/dt)/dv is
   added to the last column (the variational equation of the speed's
   sensitivity). Straight, perfect track. Every column's sums run in the
   same order as a single column's would. */

/* Row i of the suspension's sparse matrix applied to columns c0 .. c0 + B - 1
   of X (rows w apart) into o; B a constant where it is inlined, so that the
   columns become whole vector operations. */
static inline void suspension_row_block(const rr_nonlinear *nl, int i, const double *X, size_t w,
                                        size_t c0, int B, double *o)
{
  double acc[8] = {0};
  for (int k = nl->row_start[i]; k < nl->row_start[i + 1]; k++) {
    const double v = nl->val[k], *x = X + (size_t)nl->col[k] * w + c0;
    for (int c = 0; c < B; c++) acc[c] += v * x[c];
  }
  for (int c = 0; c < B; c++) o[c0 + (size_t)c] = acc[c];
}

/* The suspension's sparse rows applied to the m columns at once: blocks of
   8 columns, then of 4, then single ones. */
RR_CLONES static void suspension_product(const rr_nonlinear *nl, const double *X, int m,
                                         double *out)
{
  size_t w = (size_t)m;
  for (int i = 0; i < nl->N; i++) {
    double *o = out + (size_t)i * w;
    size_t c0 = 0;
    for (; c0 + 8 <= w; c0 += 8) suspension_row_block(nl, i, X, w, c0, 8, o);
    for (; c0 + 4 <= w; c0 += 4) suspension_row_block(nl, i, X, w, c0, 4, o);
    for (; c0 < w; c0++) suspension_row_block(nl, i, X, w, c0, 1, o);
  }
}

/* The contact forces' rows: per wheelset, the two acceleration rows gain
   dF/d(y, psi, dy/dt, dpsi/dt) times those rows of X. */
RR_CLONES static void contact_product(const rr_nonlinear *nl, const double dF[][2][5],
                                      const double *X, int m, int dfdv, double *out)
{
  size_t w = (size_t)m;
  for (int i = 0; i < nl->nw; i++) {
    const wheelset *ws = &nl->w[i];
    int n = nl->n, r[4] = {ws->y, ws->p, n + ws->y, n + ws->p};
    const double *x0 = X + (size_t)r[0] * w, *x1 = X + (size_t)r[1] * w, *x2 = X + (size_t)r[2] * w,
                 *x3 = X + (size_t)r[3] * w;
    double *oy = out + (size_t)(n + ws->y) * w, *op = out + (size_t)(n + ws->p) * w;
    const double *fy = dF[i][0], *fp = dF[i][1];
#pragma omp simd
    for (size_t c = 0; c < w; c++) {
      double gy = 0, gp = 0;
      gy += fy[0] * x0[c];
      gp += fp[0] * x0[c];
      gy += fy[1] * x1[c];
      gp += fp[1] * x1[c];
      gy += fy[2] * x2[c];
      gp += fp[2] * x2[c];
      gy += fy[3] * x3[c];
      gp += fp[3] * x3[c];
      if (dfdv && c == w - 1) {
        gy += fy[4];
        gp += fp[4];
      }
      oy[c] += gy * ws->im_y;
      op[c] += gp * ws->im_p;
    }
  }
}

void rr_nonlinear_jvp_at(const rr_nonlinear *nl, double v, const double *z, const double *X, int m,
                         int dfdv, double *out)
{
  double dF[RR_SYS_MAX_INPUTS][2][5];
  for (int i = 0; i < nl->nw; i++) {
    double x[4], F[2], fl;
    wheel_state(nl, &nl->w[i], z, x);
    contact(nl, v, &nl->w[i], x, 0, F, dF[i], &fl);
  }
  suspension_product(nl, X, m, out);
  contact_product(nl, (const double(*)[2][5])dF, X, m, dfdv, out);
}

/* The saturation's argument beta = |F| / (mu N) of wheelset w at speed v. */
static double beta_of(const rr_nonlinear *nl, double v, const wheelset *w, const double *z)
{
  double x[4], fx, fy;
  wheel_state(nl, w, z, x);
  creep_forces(w, v, x, geometry(nl, w, x[0]).gd, &fx, &fy);
  return sqrt(fx * fx + fy * fy) / w->muN;
}

/* Where the right-hand side is not smooth, per wheelset on straight track:
   y = 0 (lambda(|y|) has a corner there unless lambda'(0) = 0), the
   flange's edges y = +-clearance, for a polynomial tread its hold's edges
   y = +-hold, and the switch of the saturation law at beta = 3. g (may be
   NULL) gets one value per kink, zero there; the count is returned. */
int rr_nonlinear_kinks_at(const rr_nonlinear *nl, double v, const double *z, double *g)
{
  int k = 0, spring = !nl->table && nl->law.flange_stiffness > 0;
  double dl,
      edge[3] = {0, spring ? nl->law.flange_clearance : 0,
                 nl->prof.kind == RR_PROFILE_POLY && nl->prof.hold_mm > 0 ? nl->prof.hold_mm * 1e-3
                                                                          : 0};
  dl = 0; /* the profiles' tables have a corner at every grid point: none is an event */
  if (!nl->table) rr_profile_eval(&nl->prof, 0, &dl);
  int corner = dl != 0, sat = nl->law.saturation;
  for (int i = 0; i < nl->nw; i++) {
    const wheelset *w = &nl->w[i];
    double y = z ? z[w->y] : 0;
    if (corner) {
      if (g) g[k] = y;
      k++;
    }
    for (int e = 0; nl->table && e < nl->table->nedges; e++) {
      if (g) g[k] = y - nl->table->edge[e];
      k++;
    }
    for (int e = 1; e < 3; e++) {
      if (!(edge[e] > 0)) continue;
      if (g) {
        g[k] = y - edge[e];
        g[k + 1] = y + edge[e];
      }
      k += 2;
    }
    if (sat && w->muN > 0) {
      if (g) g[k] = beta_of(nl, v, w, z) - 3;
      k++;
    }
  }
  return k;
}

void rr_nonlinear_forces(const rr_nonlinear *nl, const double *z, const double *yt, int i,
                         double *fy, double *mz, double *flange)
{
  double x[4], F[2];
  wheel_state(nl, &nl->w[i], z, x);
  contact(nl, nl->v, &nl->w[i], x, yt ? yt[i] : 0, F, NULL, flange);
  *fy = F[0];
  *mz = F[1];
}

void rr_nonlinear_rhs(const rr_nonlinear *nl, const double *z, const double *yt, double *dz)
{
  rr_nonlinear_rhs_at(nl, nl->v, z, yt, dz);
}

void rr_nonlinear_jacobian(const rr_nonlinear *nl, const double *z, const double *yt, double *J)
{
  rr_nonlinear_jacobian_at(nl, nl->v, z, yt, J);
}
