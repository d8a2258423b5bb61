/* The shape test's form, factor and solve of D(s) for several operating
 * points at once (see dynamic_stiffness.h). Lane l of every array holds
 * point l's numbers ([q L + l]), and each scalar step of dynamic_stiffness.c
 * (form, factor_cached, rr_dsolver_solve) becomes a loop over the lanes,
 * which the compiler turns into vector operations. The complex arithmetic
 * is written out as GCC's limited-range expansion of the scalar code writes
 * it (products (ac - bd, ad + bc), quotients over c^2 + d^2, a real
 * operand's zero imaginary part kept as a multiplied zero), so that a lane
 * gives what the single-point solver gives with the same pivot order. */
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "model/dynamic_stiffness.h"
#include "util/internal.h"

#define L RR_DSL_LANES
#include "util/lane_vector.h"         /* after L */
#define MXMAX (2 * RR_SYS_MAX_BODIES) /* rr_dsolver's element capacity */

void rr_dsl_layout(rr_dsl *dl, int n, rr_block *b)
{
  size_t N = (size_t)n, NN = N * N, d = sizeof(double), i = sizeof(int);
  dl->pos = rr_block_take(b, NN, i);
  dl->perm = rr_block_take(b, N, i);
  dl->mxnz = rr_block_take(b, MXMAX, i);
  dl->mxidx = rr_block_take(b, MXMAX * N, i);
  dl->nzc = rr_block_take(b, NN * L, d);
  dl->nzk = rr_block_take(b, NN * L, d);
  dl->mass = rr_block_take(b, N * L, d);
  dl->mk = rr_block_take(b, MXMAX * L, d);
  dl->mc = rr_block_take(b, MXMAX * L, d);
  dl->mm = rr_block_take(b, MXMAX * L, d);
  dl->mJ = rr_block_take(b, MXMAX * N * L, d);
  dl->Dr = rr_block_take(b, NN * L, d);
  dl->Di = rr_block_take(b, NN * L, d);
  dl->tr = rr_block_take(b, N * L, d);
  dl->ti = rr_block_take(b, N * L, d);
  for (int o = 0; o < RR_DSL_ORDERS; o++) {
    rr_dsl_order *po = &dl->orders[o];
    po->ord = rr_block_take(b, N, i);
    po->ls = rr_block_take(b, N + 1, i);
    po->us = rr_block_take(b, N + 1, i);
    po->lr = rr_block_take(b, NN, i);
    po->uc = rr_block_take(b, NN, i);
    po->valid = 0;
  }
  dl->n = n;
  dl->loaded = dl->patterned = dl->newest = 0;
}

void rr_dsl_reset(rr_dsl *dl) { dl->loaded = 0; }

int rr_dsl_has_order(const rr_dsl *dl) { return dl->orders[dl->newest].valid; }

static int same_order(const rr_dsl_order *po, const rr_dsolver *ds, int n)
{
  return po->valid && !memcmp(po->ord, ds->sta_ord, sizeof(int) * (size_t)n) &&
         !memcmp(po->ls, ds->sta_ls, sizeof(int) * (size_t)(n + 1)) &&
         !memcmp(po->us, ds->sta_us, sizeof(int) * (size_t)(n + 1)) &&
         !memcmp(po->lr, ds->sta_lr, sizeof(int) * (size_t)ds->sta_ls[n]) &&
         !memcmp(po->uc, ds->sta_uc, sizeof(int) * (size_t)ds->sta_us[n]);
}

void rr_dsl_keep_order(rr_dsl *dl, const rr_dsolver *ds)
{
  int n = dl->n;
  if (ds->dirty || ds->n != n) return;
  for (int o = 0; o < RR_DSL_ORDERS; o++)
    if (same_order(&dl->orders[o], ds, n)) {
      dl->newest = o;
      return;
    }
  int o = (dl->newest + 1) % RR_DSL_ORDERS;
  rr_dsl_order *po = &dl->orders[o];
  memcpy(po->ord, ds->sta_ord, sizeof(int) * (size_t)n);
  memcpy(po->ls, ds->sta_ls, sizeof(int) * (size_t)(n + 1));
  memcpy(po->us, ds->sta_us, sizeof(int) * (size_t)(n + 1));
  memcpy(po->lr, ds->sta_lr, sizeof(int) * (size_t)ds->sta_ls[n]);
  memcpy(po->uc, ds->sta_uc, sizeof(int) * (size_t)ds->sta_us[n]);
  po->valid = 1;
  dl->newest = o;
}

/* ds has the lanes' pattern (the first lane loaded set it). */
static int same_pattern(const rr_dsl *dl, const rr_dsolver *ds)
{
  if (ds->n != dl->n || ds->nnz != dl->nnz || ds->nmx != dl->nmx) return 0;
  if (memcmp(ds->pos, dl->pos, sizeof(int) * (size_t)ds->nnz)) return 0;
  if (memcmp(ds->perm, dl->perm, sizeof(int) * (size_t)ds->n)) return 0;
  for (int e = 0; e < ds->nmx; e++) {
    if (ds->mx[e].nz != dl->mxnz[e]) return 0;
    for (int a = 0; a < ds->mx[e].nz; a++)
      if (ds->mx[e].idx[a] != dl->mxidx[e * dl->n + a]) return 0;
  }
  return 1;
}

static void set_pattern(rr_dsl *dl, const rr_dsolver *ds)
{
  dl->nnz = ds->nnz;
  dl->nmx = ds->nmx;
  memcpy(dl->pos, ds->pos, sizeof(int) * (size_t)ds->nnz);
  memcpy(dl->perm, ds->perm, sizeof(int) * (size_t)ds->n);
  for (int e = 0; e < ds->nmx; e++) {
    dl->mxnz[e] = ds->mx[e].nz;
    for (int a = 0; a < ds->mx[e].nz; a++) dl->mxidx[e * dl->n + a] = ds->mx[e].idx[a];
  }
}

int rr_dsl_load(rr_dsl *dl, int l, const rr_dsolver *ds)
{
  if (l < 0 || l >= L || ds->n != dl->n) return -1;
  for (int e = 0; e < ds->nmx; e++)
    if (ds->mx[e].sdf) return -1; /* a paper-mode or tabulated series stiffness */
  if (!dl->loaded && !(dl->patterned && same_pattern(dl, ds))) {
    set_pattern(dl, ds); /* a new pattern: the kept orders were another's */
    for (int o = 0; o < RR_DSL_ORDERS; o++) dl->orders[o].valid = 0;
    dl->patterned = 1;
  } else if (!same_pattern(dl, ds)) {
    return -1;
  }
  dl->loaded = 1;
  dl->pref[l] = -1;
  int n = dl->n;
  for (int q = 0; q < ds->nnz; q++) {
    dl->nzc[q * L + l] = ds->nz_c[q];
    dl->nzk[q * L + l] = ds->nz_k[q];
  }
  for (int i = 0; i < n; i++) dl->mass[i * L + l] = ds->mass[i];
  for (int e = 0; e < ds->nmx; e++) {
    dl->mk[e * L + l] = ds->mx[e].k;
    dl->mc[e * L + l] = ds->mx[e].c;
    dl->mm[e * L + l] = ds->mx[e].mult;
    for (int a = 0; a < ds->mx[e].nz; a++) dl->mJ[(e * n + a) * L + l] = ds->mx[e].J[a];
  }
  return 0;
}

/* Zero at every position the cached factors touch (form's non-dirty path). */
RR_INLINE void clear_factor_positions(rr_dsl *dl, const rr_dsl_order *po)
{
  int n = dl->n;
  double *Dr = dl->Dr, *Di = dl->Di;
  const vd z = {0};
  for (int k = 0; k < n; k++) {
    int p = po->ord[k];
    VSTORE(Dr + (p * n + k) * L, z);
    VSTORE(Di + (p * n + k) * L, z);
    for (int q = po->us[k]; q < po->us[k + 1]; q++) {
      VSTORE(Dr + (p * n + po->uc[q]) * L, z);
      VSTORE(Di + (p * n + po->uc[q]) * L, z);
    }
    for (int q = po->ls[k]; q < po->ls[k + 1]; q++) {
      VSTORE(Dr + (po->lr[q] * n + k) * L, z);
      VSTORE(Di + (po->lr[q] * n + k) * L, z);
    }
  }
}

/* Element e's k_e(s) times its multiplicity, as form computes it for a
   series stiffness k (real: imaginary part zero) and damping c. */
RR_INLINE void maxwell_lanes(const rr_dsl *dl, int e, const vd *sr, const vd *si, vd *ker, vd *kei)
{
  const vd zero = {0}, inf = zero + INFINITY;
  vd k = VLOAD(dl->mk + e * L), c = VLOAD(dl->mc + e * L), m = VLOAD(dl->mm + e * L);
  /* (k c) s / (k + c s), and c s where k is infinite */
  vd kcr = k * c, kci = zero * c;
  vd nr = kcr * *sr - kci * *si, ni = kcr * *si + kci * *sr;
  vd dr = k + c * *sr, di = zero + c * *si, den = dr * dr + di * di;
  vd re = (nr * dr + ni * di) / den, im = (ni * dr - nr * di) / den;
  vl rigid = VABS(k) == inf;
  *ker = m * VSEL(rigid, c * *sr, re);
  *kei = m * VSEL(rigid, c * *si, im);
}

/* D(s) of every lane (rr_dsolver's form). */
RR_INLINE void form_lanes(rr_dsl *dl, const rr_dsl_order *po, const vd *sr, const vd *si)
{
  int n = dl->n;
  double *Dr = dl->Dr, *Di = dl->Di;
  clear_factor_positions(dl, po);
  for (int q = 0; q < dl->nnz; q++) {
    vd c = VLOAD(dl->nzc + q * L), k = VLOAD(dl->nzk + q * L);
    VSTORE(Dr + dl->pos[q] * L, *sr * c + k);
    VSTORE(Di + dl->pos[q] * L, *si * c);
  }
  vd s2r = *sr * *sr - *si * *si, s2i = *sr * *si + *si * *sr;
  for (int i = 0; i < n; i++) {
    double *dr = Dr + (i * n + i) * L, *di = Di + (i * n + i) * L;
    vd m = VLOAD(dl->mass + i * L);
    VSTORE(dr, VLOAD(dr) + s2r * m);
    VSTORE(di, VLOAD(di) + s2i * m);
  }
  for (int e = 0; e < dl->nmx; e++) {
    vd ker, kei;
    maxwell_lanes(dl, e, sr, si, &ker, &kei);
    const int *idx = dl->mxidx + e * n;
    const double *J = dl->mJ + (size_t)e * (size_t)n * L;
    for (int a = 0; a < dl->mxnz[e]; a++) {
      vd ja = VLOAD(J + a * L), tr = ker * ja, ti = kei * ja;
      for (int b = 0; b < dl->mxnz[e]; b++) {
        double *dr = Dr + (idx[a] * n + idx[b]) * L, *di = Di + (idx[a] * n + idx[b]) * L;
        vd jb = VLOAD(J + b * L);
        VSTORE(dr, VLOAD(dr) + tr * jb);
        VSTORE(di, VLOAD(di) + ti * jb);
      }
    }
  }
}

/* The lanes whose entry of m is set, as bits. */
RR_INLINE unsigned lanes_of(const vl *m)
{
  unsigned bits = 0;
  for (int l = 0; l < L; l++) bits |= (*m)[l] ? 1u << l : 0;
  return bits;
}

/* factor_cached in every lane; the lanes whose multipliers outgrew the
   threshold (they go on, their numbers unused), or all of mask's as soon as
   every one of those has. */
RR_INLINE unsigned factor_lanes(rr_dsl *dl, const rr_dsl_order *po, unsigned mask)
{
  int n = dl->n;
  double *Dr = dl->Dr, *Di = dl->Di;
  const vd zero = {0};
  vl bad = {0};
  for (int k = 0; k < n; k++) {
    double *pr = Dr + po->ord[k] * n * L, *pi = Di + po->ord[k] * n * L;
    vd br = VLOAD(pr + k * L), bi = VLOAD(pi + k * L), den = br * br + bi * bi;
    vd lim = RR_DSOLVER_PIVOT_GROWTH * (VABS(br) + VABS(bi));
    vd ir = (br + zero * bi) / den, ii = (zero * br - bi) / den; /* 1 / pivot, as 1.0 / z expands */
    for (int q = po->ls[k]; q < po->ls[k + 1]; q++) {
      double *rr = Dr + po->lr[q] * n * L, *ri = Di + po->lr[q] * n * L;
      vd ar = VLOAD(rr + k * L), ai = VLOAD(ri + k * L);
      bad |= ~(VABS(ar) + VABS(ai) <= lim);
      vd lr = ar * ir - ai * ii, li = ar * ii + ai * ir;
      VSTORE(rr + k * L, lr);
      VSTORE(ri + k * L, li);
      for (int c = po->us[k]; c < po->us[k + 1]; c++) {
        int j = po->uc[c] * L;
        vd ur = VLOAD(pr + j), ui = VLOAD(pi + j);
        VSTORE(rr + j, VLOAD(rr + j) - (lr * ur - li * ui));
        VSTORE(ri + j, VLOAD(ri + j) - (lr * ui + li * ur));
      }
    }
    if ((lanes_of(&bad) & mask) == mask) break; /* nothing left to factor for */
  }
  return lanes_of(&bad);
}

/* rr_dsolver_solve of the start vector in every lane, into t. */
RR_INLINE void solve_lanes(rr_dsl *dl, const rr_dsl_order *po)
{
  int n = dl->n;
  const double *Dr = dl->Dr, *Di = dl->Di;
  double *tr = dl->tr, *ti = dl->ti;
  vd br[RR_SYS_MAX_DOF], bi[RR_SYS_MAX_DOF];
  for (int i = 0; i < n; i++) {
    double complex v = rr_dsolver_start(i);
    br[i] = (vd){0} + creal(v);
    bi[i] = (vd){0} + cimag(v);
  }
  for (int k = 0; k < n; k++) {
    vd xr = br[po->ord[k]], xi = bi[po->ord[k]];
    vl skip = (xr == 0) & (xi == 0); /* the single solver's "bk == 0" */
    for (int q = po->ls[k]; q < po->ls[k + 1]; q++) {
      int r = po->lr[q];
      vd ar = VLOAD(Dr + (r * n + k) * L), ai = VLOAD(Di + (r * n + k) * L);
      br[r] = VSEL(skip, br[r], br[r] - (ar * xr - ai * xi));
      bi[r] = VSEL(skip, bi[r], bi[r] - (ar * xi + ai * xr));
    }
  }
  for (int k = n - 1; k >= 0; k--) {
    const double *rr = Dr + po->ord[k] * n * L, *ri = Di + po->ord[k] * n * L;
    vd cr = br[po->ord[k]], ci = bi[po->ord[k]];
    for (int q = po->us[k]; q < po->us[k + 1]; q++) {
      int j = po->uc[q] * L;
      vd ur = VLOAD(rr + j), ui = VLOAD(ri + j), vr = VLOAD(tr + j), vi = VLOAD(ti + j);
      cr -= ur * vr - ui * vi;
      ci -= ur * vi + ui * vr;
    }
    vd dr = VLOAD(rr + k * L), di = VLOAD(ri + k * L), den = dr * dr + di * di;
    VSTORE(tr + k * L, (cr * dr + ci * di) / den);
    VSTORE(ti + k * L, (ci * dr - cr * di) / den);
  }
}

/* The order to try next for the lanes of mask: the one most of them took
   last, else the newest; never one in tried. -1 when none is left. */
static int next_order(const rr_dsl *dl, unsigned mask, unsigned tried)
{
  int votes[RR_DSL_ORDERS] = {0}, best = -1;
  for (int l = 0; l < L; l++)
    if ((mask >> l & 1) && dl->pref[l] >= 0) votes[dl->pref[l]]++;
  for (int t = 0; t < RR_DSL_ORDERS; t++) {
    int o = (dl->newest + RR_DSL_ORDERS - t) % RR_DSL_ORDERS;
    if (!dl->orders[o].valid || (tried >> o & 1)) continue;
    if (best < 0 || votes[o] > votes[best]) best = o;
  }
  return best;
}

RR_CLONES_V4 unsigned rr_dsl_shapes(rr_dsl *dl, unsigned mask, const double *sr, const double *si,
                                    double complex *phi)
{
  int n = dl->n, o;
  unsigned tried = 0;
  vd vsr, vsi; /* the caller's arrays need not be aligned */
  memcpy(&vsr, sr, sizeof vsr);
  memcpy(&vsi, si, sizeof vsi);
  while (mask && (o = next_order(dl, mask, tried)) >= 0) {
    const rr_dsl_order *po = &dl->orders[o];
    tried |= 1u << o;
    form_lanes(dl, po, &vsr, &vsi);
    unsigned ok = mask & ~factor_lanes(dl, po, mask);
    if (!ok) continue;
    solve_lanes(dl, po);
    for (int l = 0; l < L; l++) {
      if (!(ok >> l & 1)) continue;
      dl->pref[l] = o;
      for (int i = 0; i < n; i++) { /* a complex is its two parts in order (C11 6.2.5) */
        double *z = (double *)&phi[l * n + dl->perm[i]];
        z[0] = dl->tr[i * L + l];
        z[1] = dl->ti[i * L + l];
      }
    }
    mask &= ~ok;
  }
  return mask;
}
