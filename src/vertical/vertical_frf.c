/* The vertical model's frequency response (docs/vertical.md, "Pseudo-
 * excitation method"). The floor sees only the symmetric coordinates
 * (z_c, q_b, z_s with z_f1 = z_f2 = z_s) and the antisymmetric ones
 * (theta_c, z_a with z_f1 = -z_f2 = z_a); each frame's pitch is decoupled.
 * Per frequency: a 3x3 and a 2x2 complex symmetric system, solved by their
 * adjugates (no pivoting, no branches), and two scalar divisions, written
 * on real and imaginary parts so that the loop runs over several
 * frequencies at once; the dense 7x7 solve is the tests' check. */
#include <math.h>
#include <string.h>
#include "util/internal.h"
#include "vertical/vertical_impl.h"

#define NS 3
#define NA 2
/* the input combinations the blocks need: r_zc, r_qb, r_zf1 + r_zf2 (sym),
   r_thc, r_zf1 - r_zf2 (anti), r_thf1, r_thf2 */
#define NR 7

/* The model in the block coordinates (projections of M, K, C, BK, BC). */
typedef struct vblocks {
  double Ks[NS * NS], Cs[NS * NS], Ms[NS], Ka[NA * NA], Ca[NA * NA], Ma[NA];
  double kth[2], cth[2], mth[2];
  double bk[NR][RR_VINPUTS], bc[NR][RR_VINPUTS];
} vblocks;

/* The block coordinates as combinations of the 7: each row of T has one or
   two entries (index, value). */
typedef struct basis_row {
  int n, d[2];
  double c[2];
} basis_row;
static const basis_row basis[NR] = {
    {1, {RR_V_ZC, 0}, {1, 0}},          {1, {RR_V_QB, 0}, {1, 0}},
    {2, {RR_V_ZF1, RR_V_ZF2}, {1, 1}},  {1, {RR_V_THC, 0}, {1, 0}},
    {2, {RR_V_ZF1, RR_V_ZF2}, {1, -1}}, {1, {RR_V_THF1, 0}, {1, 0}},
    {1, {RR_V_THF2, 0}, {1, 0}},
};

/* t_a' A t_b */
static double project(const double *A, const basis_row *a, const basis_row *b)
{
  double s = 0;
  for (int i = 0; i < a->n; i++)
    for (int j = 0; j < b->n; j++) s += a->c[i] * A[a->d[i] * RR_VDOF + b->d[j]] * b->c[j];
  return s;
}

/* T A T' into the blocks; the largest coupling between blocks into *cpl */
static void project_matrix(const double *A, double *s, double *a, double *th, double *cpl)
{
  static const int block[NR] = {0, 0, 0, 1, 1, 2, 3}, pos[NR] = {0, 1, 2, 0, 1, 0, 0};
  for (int i = 0; i < NR; i++)
    for (int j = 0; j < NR; j++) {
      double x = project(A, &basis[i], &basis[j]);
      if (block[i] != block[j])
        *cpl = fmax(*cpl, fabs(x));
      else if (block[i] == 0)
        s[pos[i] * NS + pos[j]] = x;
      else if (block[i] == 1)
        a[pos[i] * NA + pos[j]] = x;
      else
        th[block[i] - 2] = x;
    }
}

/* The blocks; RR_EUNSUP when they are coupled (a model that is not the
   symmetric car of docs/vertical.md, assembled by hand). */
static int make_blocks(const rr_vertical_model *m, vblocks *b, rr_error *err)
{
  double Md[RR_VDOF * RR_VDOF] = {0}, Ms[NS * NS], Ma[NA * NA], scale = 0, cpl = 0;
  for (int i = 0; i < RR_VDOF; i++) {
    Md[i * RR_VDOF + i] = m->M[i];
    for (int j = 0; j < RR_VDOF; j++) scale = fmax(scale, fabs(m->K[i * RR_VDOF + j]));
  }
  project_matrix(m->K, b->Ks, b->Ka, b->kth, &cpl);
  project_matrix(m->C, b->Cs, b->Ca, b->cth, &cpl);
  project_matrix(Md, Ms, Ma, b->mth, &cpl);
  for (int i = 0; i < NS; i++) b->Ms[i] = Ms[i * NS + i];
  for (int i = 0; i < NA; i++) b->Ma[i] = Ma[i * NA + i];
  for (int c = 0; c < NR; c++)
    for (int j = 0; j < RR_VINPUTS; j++) {
      b->bk[c][j] = b->bc[c][j] = 0;
      for (int t = 0; t < basis[c].n; t++) {
        b->bk[c][j] += basis[c].c[t] * m->BK[basis[c].d[t] * RR_VINPUTS + j];
        b->bc[c][j] += basis[c].c[t] * m->BC[basis[c].d[t] * RR_VINPUTS + j];
      }
    }
  if (cpl > 1e-12 * scale)
    return rr_seterr(err, RR_EUNSUP,
                     "vertical: the model's symmetric and antisymmetric parts are coupled");
  return RR_OK;
}

/* The delay factors at every frequency, kept while the speed and the
   wheelsets' distances stay (an optimiser's designs at one speed). */
static void delays(rr_vertical_plan *p, const rr_vertical_model *m, double v)
{
  int same = v == p->delay_v;
  for (int j = 0; j < RR_VINPUTS; j++) same = same && m->d_wheelsets[j] == p->delay_d[j];
  if (same) return;
  for (int j = 0; j < RR_VINPUTS; j++)
    for (int k = 0; k < p->n; k++) {
      double ph = -2 * RR_PI * p->f[k] * m->d_wheelsets[j] / v;
      p->Er[(size_t)j * (size_t)p->n + (size_t)k] = cos(ph);
      p->Ei[(size_t)j * (size_t)p->n + (size_t)k] = sin(ph);
    }
  p->delay_v = v;
  memcpy(p->delay_d, m->d_wheelsets, sizeof p->delay_d);
}

int rr_vertical_set_points(rr_vertical_plan *p, const rr_vertical_model *m, rr_error *err)
{
  double L = m->x_frames[0], half = 0.5 * m->carbody_length;
  p->np = p->o.npoints ? p->o.npoints : 3;
  for (int i = 0; i < p->np; i++) {
    p->x[i] = p->o.npoints ? p->o.x_points[i] : (i == 0 ? L : i == 1 ? 0 : -L);
    if (!(fabs(p->x[i]) <= half * (1 + 1e-12)))
      return rr_seterr(err, RR_EINVAL, "vertical: floor point %g m is off the carbody (+-%g m)",
                       p->x[i], half);
    rr_vertical_floor_row(m, p->x[i], p->rows + i * RR_VDOF);
  }
  return RR_OK;
}

/* ---- complex arithmetic on (re, im) pairs, inlined into the loop ---- */
typedef struct cx {
  double r, i;
} cx;
RR_INLINE cx cmul(cx a, cx b) { return (cx){a.r * b.r - a.i * b.i, a.r * b.i + a.i * b.r}; }
RR_INLINE cx cadd(cx a, cx b) { return (cx){a.r + b.r, a.i + b.i}; }
RR_INLINE cx csub(cx a, cx b) { return (cx){a.r - b.r, a.i - b.i}; }
RR_INLINE cx cinv(cx a)
{
  double d = 1 / (a.r * a.r + a.i * a.i);
  return (cx){a.r * d, -a.i * d};
}
/* k - w^2 m + j w c */
RR_INLINE cx dyn(double k, double c, double m, double w) { return (cx){k - w * w * m, w * c}; }

/* r_c = sum_j (bk + j w bc) e_j */
RR_INLINE cx input(const vblocks *b, int c, double w, const double *er, const double *ei, int n,
                   int k)
{
  const double *bk = b->bk[c], *bc = b->bc[c];
  cx r = cmul((cx){bk[0], w * bc[0]}, (cx){er[k], ei[k]});
  r = cadd(r, cmul((cx){bk[1], w * bc[1]}, (cx){er[n + k], ei[n + k]}));
  r = cadd(r, cmul((cx){bk[2], w * bc[2]}, (cx){er[2 * n + k], ei[2 * n + k]}));
  return cadd(r, cmul((cx){bk[3], w * bc[3]}, (cx){er[3 * n + k], ei[3 * n + k]}));
}

typedef struct cx3 {
  cx a, b, c;
} cx3;

/* The symmetric block [[a, b, c], [b, d, e], [c, e, f]] at w: its entries,
   its adjugate's first row and the inverse of its determinant. */
typedef struct sym3 {
  cx a, b, c, d, e, f, c00, c01, c02, inv;
} sym3;
RR_INLINE sym3 sym_block(const vblocks *B, double w)
{
  const double *K = B->Ks, *C = B->Cs;
  sym3 s = {.a = dyn(K[0], C[0], B->Ms[0], w),
            .b = dyn(K[1], C[1], 0, w),
            .c = dyn(K[2], C[2], 0, w),
            .d = dyn(K[4], C[4], B->Ms[1], w),
            .e = dyn(K[5], C[5], 0, w),
            .f = dyn(K[8], C[8], B->Ms[2], w)};
  s.c00 = csub(cmul(s.d, s.f), cmul(s.e, s.e));
  s.c01 = csub(cmul(s.c, s.e), cmul(s.b, s.f));
  s.c02 = csub(cmul(s.b, s.e), cmul(s.c, s.d));
  s.inv = cinv(cadd(cadd(cmul(s.a, s.c00), cmul(s.b, s.c01)), cmul(s.c, s.c02)));
  return s;
}

/* the symmetric block solved by its adjugate */
RR_INLINE cx3 solve3(const vblocks *B, double w, cx r0, cx r1, cx r2)
{
  sym3 s = sym_block(B, w);
  cx c11 = csub(cmul(s.a, s.f), cmul(s.c, s.c)), c12 = csub(cmul(s.b, s.c), cmul(s.a, s.e));
  cx c22 = csub(cmul(s.a, s.d), cmul(s.b, s.b));
  return (cx3){cmul(s.inv, cadd(cadd(cmul(s.c00, r0), cmul(s.c01, r1)), cmul(s.c02, r2))),
               cmul(s.inv, cadd(cadd(cmul(s.c01, r0), cmul(c11, r1)), cmul(c12, r2))),
               cmul(s.inv, cadd(cadd(cmul(s.c02, r0), cmul(c12, r1)), cmul(c22, r2)))};
}

/* the antisymmetric block [[a, b], [b, d]]: its entries and inverse determinant */
typedef struct anti2 {
  cx a, b, d, inv;
} anti2;
RR_INLINE anti2 anti_block(const vblocks *B, double w)
{
  const double *K = B->Ka, *C = B->Ca;
  anti2 m = {.a = dyn(K[0], C[0], B->Ma[0], w),
             .b = dyn(K[1], C[1], 0, w),
             .d = dyn(K[3], C[3], B->Ma[1], w)};
  m.inv = cinv(csub(cmul(m.a, m.d), cmul(m.b, m.b)));
  return m;
}

RR_INLINE cx3 solve2(const vblocks *B, double w, cx r0, cx r1)
{
  anti2 m = anti_block(B, w);
  return (cx3){cmul(m.inv, csub(cmul(m.d, r0), cmul(m.b, r1))),
               cmul(m.inv, csub(cmul(m.a, r1), cmul(m.b, r0))),
               {0, 0}};
}

/* coordinate d's q at frequency k into the real and imaginary planes */
RR_INLINE void store(double *qr, double *qi, int n, int k, int d, cx q)
{
  qr[d * n + k] = q.r;
  qi[d * n + k] = q.i;
}

/* Every frequency's q: qr[d * n + k], qi[d * n + k] (one simd loop, no
   branch: the blocks' adjugates). */
RR_CLONES_V4 static void frf_kernel(const vblocks *B, int n, const double *f, const double *er,
                                    const double *ei, double *restrict qr, double *restrict qi)
{
#pragma omp simd
  for (int k = 0; k < n; k++) {
    double w = 2 * RR_PI * f[k];
    cx3 s = solve3(B, w, input(B, 0, w, er, ei, n, k), input(B, 1, w, er, ei, n, k),
                   input(B, 2, w, er, ei, n, k));
    cx3 a = solve2(B, w, input(B, 3, w, er, ei, n, k), input(B, 4, w, er, ei, n, k));
    cx zc = s.a, qb = s.b, zs = s.c, thc = a.a, za = a.b;
    cx z1 = cadd(zs, za), z2 = csub(zs, za);
    cx t1 = cmul(input(B, 5, w, er, ei, n, k), cinv(dyn(B->kth[0], B->cth[0], B->mth[0], w)));
    cx t2 = cmul(input(B, 6, w, er, ei, n, k), cinv(dyn(B->kth[1], B->cth[1], B->mth[1], w)));
    store(qr, qi, n, k, RR_V_ZC, zc);
    store(qr, qi, n, k, RR_V_QB, qb);
    store(qr, qi, n, k, RR_V_THC, thc);
    store(qr, qi, n, k, RR_V_ZF1, z1);
    store(qr, qi, n, k, RR_V_ZF2, z2);
    store(qr, qi, n, k, RR_V_THF1, t1);
    store(qr, qi, n, k, RR_V_THF2, t2);
  }
}

/* The floor's coordinates alone (z_c, q_b, theta_c) when the carbody takes
   no input directly (the model's primary acts on the frames: always so for
   the car docs/vertical.md describes): then only the frames' rows of the
   blocks' right-hand sides are nonzero, one adjugate column each. */
RR_CLONES_V4 static void floor_kernel(const vblocks *B, int n, const double *f, const double *er,
                                      const double *ei, double *restrict qr, double *restrict qi)
{
#pragma omp simd
  for (int k = 0; k < n; k++) {
    double w = 2 * RR_PI * f[k];
    cx r2 = input(B, 2, w, er, ei, n, k), r4 = input(B, 4, w, er, ei, n, k);
    sym3 s = sym_block(B, w);
    anti2 m = anti_block(B, w);
    cx f2 = cmul(r2, s.inv), c12 = csub(cmul(s.b, s.c), cmul(s.a, s.e));
    cx zc = cmul(s.c02, f2), qb = cmul(c12, f2), thc = cmul(cmul(m.b, r4), m.inv);
    thc = (cx){-thc.r, -thc.i}; /* -b r / (a d - b^2) */
    store(qr, qi, n, k, RR_V_ZC, zc);
    store(qr, qi, n, k, RR_V_QB, qb);
    store(qr, qi, n, k, RR_V_THC, thc);
  }
}

/* the carbody's input rows are all zero */
static int carbody_unforced(const vblocks *b)
{
  static const int rows[] = {0, 1, 3}; /* r_zc, r_qb, r_thc */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < RR_VINPUTS; j++)
      if (b->bk[rows[i]][j] != 0 || b->bc[rows[i]][j] != 0) return 0;
  return 1;
}

/* the floor accelerations H[k * np + p] = -w^2 row . q */
static void floor_outputs(rr_vertical_plan *p)
{
  int n = p->n, np = p->np;
  const double *qr = p->Qr, *qi = p->Qi;
  for (int i = 0; i < np; i++) {
    const double *row = p->rows + i * RR_VDOF;
    double a = row[RR_V_ZC], b = row[RR_V_THC], c = row[RR_V_QB];
    for (int k = 0; k < n; k++) {
      double w2 = -(2 * RR_PI * p->f[k]) * (2 * RR_PI * p->f[k]);
      double re = a * qr[RR_V_ZC * n + k] + b * qr[RR_V_THC * n + k] + c * qr[RR_V_QB * n + k];
      double im = a * qi[RR_V_ZC * n + k] + b * qi[RR_V_THC * n + k] + c * qi[RR_V_QB * n + k];
      p->H[(size_t)k * (size_t)np + (size_t)i] = w2 * re + I * (w2 * im);
    }
  }
}

/* q of every coordinate (all = 1) or of the floor's (all = 0); H too
   unless the caller forms it (outputs = 0) */
static int response(rr_vertical_plan *p, const rr_vertical_model *m, double v, int all, int outputs,
                    rr_error *err)
{
  if (!(v > 0 && v < 1e3))
    return rr_seterr(err, RR_EINVAL, "vertical: speed %g m/s (need 0 < v < 1000)", v);
  vblocks b;
  int st = make_blocks(m, &b, err);
  if (!st) st = rr_vertical_set_points(p, m, err);
  if (st) return st;
  delays(p, m, v);
  if (all || !carbody_unforced(&b))
    frf_kernel(&b, p->n, p->f, p->Er, p->Ei, p->Qr, p->Qi);
  else
    floor_kernel(&b, p->n, p->f, p->Er, p->Ei, p->Qr, p->Qi);
  if (outputs) floor_outputs(p);
  return RR_OK;
}

int rr_vertical_floor_response(rr_vertical_plan *p, const rr_vertical_model *m, double v,
                               int outputs, rr_error *err)
{
  return response(p, m, v, 0, outputs, err);
}

int rr_vertical_frf_execute(rr_vertical_plan *p, const rr_vertical_model *m, double v,
                            rr_error *err)
{
  int st = response(p, m, v, 1, 1, err);
  for (int k = 0; k < p->n && !st; k++)
    for (int d = 0; d < RR_VDOF; d++)
      p->Q[(size_t)k * RR_VDOF + (size_t)d] = p->Qr[d * p->n + k] + I * p->Qi[d * p->n + k];
  return st;
}
