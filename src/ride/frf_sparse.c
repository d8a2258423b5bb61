/* Frequency responses by sparse direct solves, a frequency a lane (see
 * frf_sparse.h). */
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "ride/frf_lanes.h"
#include "railride/sdf.h"
#define MXMAX (2 * RR_SYS_MAX_BODIES) /* rr_dsolver's element capacity */

/* Multiply-adds of an LU of order n, at most; Maxwell J' J entries kept. */
static size_t mac_cap(size_t n) { return n < 2 ? 1 : (n - 1) * n * (2 * n - 1) / 6; }
static size_t mx_cap(size_t n) { return 4 * n * n + 64; }

static void prog_layout(rr_frf_prog *g, size_t n, rr_block *b)
{
  size_t NN = n * n, M = mac_cap(n), i = sizeof(int);
  g->cidx = rr_block_take(b, NN, i);
  g->piv = rr_block_take(b, n, i);
  g->ls = rr_block_take(b, n + 1, i);
  g->lc = rr_block_take(b, NN, i);
  g->lrow = rr_block_take(b, NN, i);
  g->us = rr_block_take(b, n + 1, i);
  g->uc = rr_block_take(b, NN, i);
  g->ucol = rr_block_take(b, NN, i);
  g->mdst = rr_block_take(b, M, i);
  g->cmx = rr_block_take(b, mx_cap(n), i);
  g->act = rr_block_take(b, n, sizeof(unsigned));
  g->in0 = rr_block_take(b, n, sizeof(unsigned));
  g->formed = rr_block_take(b, NN, 1);
  g->k0 = rr_block_take(b, NN, sizeof(double));
  g->c0 = rr_block_take(b, NN, sizeof(double));
  g->m0 = rr_block_take(b, NN, sizeof(double));
  g->valid = 0;
}

void rr_frf_sparse_layout(rr_frf_sparse *s, int n, int ni, int np, rr_block *b)
{
  size_t N = (size_t)n, NN = N * N, nb = N * (size_t)ni, d = sizeof(double),
         z = sizeof(double complex), i = sizeof(int);
  s->ds = rr_block_take(b, 1, sizeof *s->ds); /* zeroed: no cached factors yet */
  s->sig = rr_block_take(b, RR_FRF_SIG_CAP(N), i);
  s->interpret = 0;
  s->dsi = rr_block_take(b, RR_DSOLVER_IWORK(N), i);
  s->dsz = rr_block_take(b, RR_DSOLVER_ZWORK(N), z);
  s->t = rr_block_take(b, N, z);
  s->b = rr_block_take(b, N, z);
  prog_layout(&s->prog, N, b);
  s->Dr = rr_block_take(b, NN * L, d);
  s->Di = rr_block_take(b, NN * L, d);
  s->br = rr_block_take(b, nb * L, d);
  s->bi = rr_block_take(b, nb * L, d);
  s->xr = rr_block_take(b, nb * L, d);
  s->xi = rr_block_take(b, nb * L, d);
  s->jj = rr_block_take(b, mx_cap(N), d);
  s->gr = rr_block_take(b, (size_t)ni * L, d);
  s->gi = rr_block_take(b, (size_t)ni * L, d);
  s->kr = rr_block_take(b, MXMAX * L, d);
  s->ki = rr_block_take(b, MXMAX * L, d);
  s->rhs = rr_block_take(b, nb, d);
  s->on = rr_block_take(b, (size_t)np, i);
  s->oj = rr_block_take(b, (size_t)np * N, i);
  s->ow = rr_block_take(b, (size_t)np * N, d);
  s->ow0 = rr_block_take(b, (size_t)np * N, d);
  s->n = n;
  s->ni = ni;
  s->np = np;
}

/* ---- compiling the factorisation ---- */

/* The structure of D: its pattern's nonzeros, the diagonal and the Maxwell
   elements' J' J entries (whatever their values). */
static void structure(const rr_dsolver *ds, int n, unsigned char *S)
{
  memset(S, 0, (size_t)n * (size_t)n);
  for (int q = 0; q < ds->nnz; q++) S[ds->pos[q]] = 1;
  for (int i = 0; i < n; i++) S[i * n + i] = 1;
  for (int e = 0; e < ds->nmx; e++)
    for (int a = 0; a < ds->mx[e].nz; a++)
      for (int b = 0; b < ds->mx[e].nz; b++) S[ds->mx[e].idx[a] * n + ds->mx[e].idx[b]] = 1;
}

/* The factors' structure in the solver's order (leaves first: wheelsets,
   frames, carbody; no row interchanges), by symbolic elimination, and the
   compact index of each entry: pivots, U's rows, L's columns. */
static void compact_entries(rr_frf_sparse *s, rr_frf_prog *g)
{
  int n = s->n, c = 0, nl = 0, nu = 0, *cidx = g->cidx;
  unsigned char S[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF], S0[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF];
  structure(s->ds, n, S);
  memcpy(S0, S, (size_t)n * (size_t)n);
  for (int i = 0; i < n * n; i++) cidx[i] = -1;
  for (int k = 0; k < n; k++) {
    g->formed[c] = 1;
    cidx[k * n + k] = g->piv[k] = c++;
    g->us[k] = nu;
    for (int j = k + 1; j < n; j++)
      if (S[k * n + j]) {
        g->ucol[nu] = j;
        g->formed[c] = S0[k * n + j];
        cidx[k * n + j] = g->uc[nu++] = c++;
      }
    g->ls[k] = nl;
    for (int r = k + 1; r < n; r++) {
      if (!S[r * n + k]) continue;
      g->lrow[nl] = r;
      g->formed[c] = S0[r * n + k];
      cidx[r * n + k] = g->lc[nl++] = c++;
      for (int q = g->us[k]; q < nu; q++) S[r * n + g->ucol[q]] = 1; /* fill */
    }
  }
  g->us[n] = nu;
  g->ls[n] = nl;
  g->ncomp = c;
}

/* Each step's multiply-adds, row by row of L: the entry each updates
   (D[dst] -= l D[u], u running along U's row). */
static void compile_macs(const rr_frf_sparse *s, rr_frf_prog *g)
{
  int n = s->n, m = 0;
  for (int k = 0; k < n; k++)
    for (int q = g->ls[k]; q < g->ls[k + 1]; q++)
      for (int c = g->us[k]; c < g->us[k + 1]; c++)
        g->mdst[m++] = g->cidx[g->lrow[q] * n + g->ucol[c]];
}

/* Where the Maxwell elements' entries are. */
static void compile_maxwell(const rr_frf_sparse *s, rr_frf_prog *g)
{
  const rr_dsolver *ds = s->ds;
  int n = s->n, t = 0;
  for (int e = 0; e < ds->nmx; e++)
    for (int a = 0; a < ds->mx[e].nz; a++)
      for (int b = 0; b < ds->mx[e].nz; b++)
        g->cmx[t++] = g->cidx[ds->mx[e].idx[a] * n + ds->mx[e].idx[b]];
}

/* The model's values on g's entries (K, C, M), and the inputs each forward
   step touches (an input's entries are structurally zero until the
   elimination reaches them). Depends on the model as it is now. */
static void prog_values(rr_frf_sparse *s, rr_frf_prog *g)
{
  const rr_dsolver *ds = s->ds;
  int n = s->n, ni = s->ni, *cidx = g->cidx;
  memset(g->k0, 0, sizeof(double) * (size_t)g->ncomp);
  memset(g->c0, 0, sizeof(double) * (size_t)g->ncomp);
  memset(g->m0, 0, sizeof(double) * (size_t)g->ncomp);
  for (int q = 0; q < ds->nnz; q++) {
    g->k0[cidx[ds->pos[q]]] = ds->nz_k[q];
    g->c0[cidx[ds->pos[q]]] = ds->nz_c[q];
  }
  for (int i = 0; i < n; i++) g->m0[cidx[i * n + i]] = ds->mass[i];
  unsigned in[RR_SYS_MAX_DOF] = {0}; /* the inputs present in each physical row */
  for (int r = 0; r < n; r++) {
    for (int i = 0; i < ni; i++) in[r] |= s->rhs[r * ni + i] != 0 ? 1u << i : 0;
    g->in0[r] = in[r];
  }
  for (int k = 0; k < n; k++) {
    g->act[k] = in[k];
    for (int q = g->ls[k]; q < g->ls[k + 1]; q++) in[g->lrow[q]] |= g->act[k];
  }
}

/* The factorisation compiled for ds's structure. */
static void compile(rr_frf_sparse *s)
{
  rr_frf_prog *g = &s->prog;
  compact_entries(s, g);
  compile_macs(s, g);
  compile_maxwell(s, g);
  prog_values(s, g);
  g->valid = 1;
}

/* ---- one pass: eight frequencies ---- */

/* D(jw) of every lane on the compiled entries: K - w^2 M + jw C from the
   program's copies, then the Maxwell elements. */
RR_INLINE void form(const rr_frf_sparse *s, const rr_frf_prog *g, const vd *w)
{
  const rr_dsolver *ds = s->ds;
  double *Dr = s->Dr, *Di = s->Di;
  const vd w2 = -(*w * *w);
  for (int c = 0; c < g->ncomp; c++) {
    VSTORE(Dr + c * L, g->k0[c] + w2 * g->m0[c]);
    VSTORE(Di + c * L, *w * g->c0[c]);
  }
  for (int e = 0, t = 0; e < ds->nmx; e++) {
    vd ker, kei;
    maxwell(s, e, w, &ker, &kei);
    for (int a = 0; a < ds->mx[e].nz * ds->mx[e].nz; a++, t++) {
      double *dr = Dr + g->cmx[t] * L, *di = Di + g->cmx[t] * L;
      VSTORE(dr, VLOAD(dr) + ker * s->jj[t]);
      VSTORE(di, VLOAD(di) + kei * s->jj[t]);
    }
  }
}

/* The LU in every lane; returns the lanes whose multipliers outgrew the
   threshold (they went on, their numbers unused). Each multiplier stays in
   registers for its row's updates. */
RR_CLONES_V4 static unsigned factor(rr_frf_sparse *s, const rr_frf_prog *g)
{
  double *Dr = s->Dr, *Di = s->Di;
  vl bad = {0};
  const int *dst = g->mdst;
  for (int k = 0; k < s->n; k++) {
    vd br = VLOAD(Dr + g->piv[k] * L), bi = VLOAD(Di + g->piv[k] * L),
       inv = 1 / (br * br + bi * bi);
    vd lim = RR_DSOLVER_PIVOT_GROWTH * (VABS(br) + VABS(bi)), ir = br * inv, ii = -bi * inv;
    const int *uc = g->uc + g->us[k];
    int nu = g->us[k + 1] - g->us[k];
    for (int q = g->ls[k]; q < g->ls[k + 1]; q++, dst += nu) {
      double *pr = Dr + g->lc[q] * L, *pi = Di + g->lc[q] * L;
      vd ar = VLOAD(pr), ai = VLOAD(pi);
      bad |= ~(VABS(ar) + VABS(ai) <= lim);
      vd lr = CMUL_RE(ar, ai, ir, ii), li = CMUL_IM(ar, ai, ir, ii);
      VSTORE(pr, lr);
      VSTORE(pi, li);
      for (int c = 0; c < nu; c++) {
        double *dr = Dr + dst[c] * L, *di = Di + dst[c] * L;
        vd ur = VLOAD(Dr + uc[c] * L), ui = VLOAD(Di + uc[c] * L);
        VSTORE(dr, CMAC_RE(VLOAD(dr), lr, li, ur, ui));
        VSTORE(di, CMAC_IM(VLOAD(di), lr, li, ur, ui));
      }
    }
  }
  return rr_frf_lane_bits(&bad);
}

/* The right-hand sides: each input's column of B, or (s->sum) one vector,
   the inputs' columns weighted by their lags in each lane. */
RR_INLINE void rhs_init(const rr_frf_sparse *s, const rr_frf_prog *g, vd *br, vd *bi)
{
  int n = s->n, ni = s->ni;
  if (!s->sum) {
    for (int j = 0; j < n * ni; j++) {
      br[j] = (vd){0} + s->rhs[j];
      bi[j] = (vd){0};
    }
    return;
  }
  for (int k = 0; k < n; k++) {
    vd yr = {0}, yi = {0};
    for (unsigned a = g->in0[k]; a; a &= a - 1) {
      int i = __builtin_ctz(a);
      yr = yr + s->rhs[k * ni + i] * VLOAD(s->gr + i * L);
      yi = yi + s->rhs[k * ni + i] * VLOAD(s->gi + i * L);
    }
    br[k] = yr;
    bi[k] = yi;
  }
}

/* Forward substitution of every right-hand side in every lane (entries
   that are structurally zero skipped: act), then back substitution of the
   unknowns k >= kmin. */
RR_INLINE void solve(rr_frf_sparse *s, const rr_frf_prog *g)
{
  int n = s->n, ne = s->sum ? 1 : s->ni;
  const double *Dr = s->Dr, *Di = s->Di;
  vd *br = (vd *)(void *)s->br, *bi = (vd *)(void *)s->bi;
  vd *xr = (vd *)(void *)s->xr, *xi = (vd *)(void *)s->xi;
  rhs_init(s, g, br, bi);
  for (int k = 0; k < n; k++) {
    unsigned act = s->sum ? g->act[k] != 0 : g->act[k];
    if (!act) continue;
    const vd *yr = br + k * ne, *yi = bi + k * ne;
    for (int q = g->ls[k]; q < g->ls[k + 1]; q++) {
      vd ar = VLOAD(Dr + g->lc[q] * L), ai = VLOAD(Di + g->lc[q] * L);
      vd *zr = br + g->lrow[q] * ne, *zi = bi + g->lrow[q] * ne;
      for (unsigned a = act; a; a &= a - 1) {
        int i = __builtin_ctz(a);
        zr[i] = CMAC_RE(zr[i], ar, ai, yr[i], yi[i]);
        zi[i] = CMAC_IM(zi[i], ar, ai, yr[i], yi[i]);
      }
    }
  }
  for (int k = n - 1; k >= s->kmin; k--) {
    vd dr = VLOAD(Dr + g->piv[k] * L), di = VLOAD(Di + g->piv[k] * L), den = dr * dr + di * di;
    vd ir = dr / den, ii = -di / den;
    for (int i = 0; i < ne; i++) {
      vd cr = br[k * ne + i], ci = bi[k * ne + i];
      for (int q = g->us[k]; q < g->us[k + 1]; q++) {
        vd ur = VLOAD(Dr + g->uc[q] * L), ui = VLOAD(Di + g->uc[q] * L);
        int j = g->ucol[q] * ne + i;
        cr = CMAC_RE(cr, ur, ui, xr[j], xi[j]);
        ci = CMAC_IM(ci, ur, ui, xr[j], xi[j]);
      }
      xr[k * ne + i] = CMUL_RE(cr, ci, ir, ii);
      xi[k * ne + i] = CMUL_IM(cr, ci, ir, ii);
    }
  }
}

/* H of the lanes in ok (H: the group's first frequency). */
RR_INLINE void outputs(const rr_frf_sparse *s, const vd *w, unsigned ok, double complex *H)
{
  int n = s->n, ni = s->sum ? 1 : s->ni, np = s->np;
  const vd *xr = (const vd *)(const void *)s->xr, *xi = (const vd *)(const void *)s->xi;
  const vd w2 = -(*w * *w);
  for (int q = 0; q < np; q++)
    for (int i = 0; i < ni; i++) {
      vd ar = {0}, ai = {0}, br = {0}, bi = {0};
      for (int c = 0; c < s->on[q]; c++) {
        int j = s->oj[q * n + c] * ni + i;
        double a = s->ow[q * n + c], a0 = s->ow0[q * n + c];
        ar += a * xr[j];
        ai += a * xi[j];
        br += a0 * xr[j];
        bi += a0 * xi[j];
      }
      vd hr = w2 * ar + br, hi = w2 * ai + bi;
      for (int l = 0; l < L; l++) {
        if (!(ok >> l & 1)) continue;
        /* a complex is its two parts in order (C11 6.2.5) */
        double *z = (double *)&H[((size_t)l * (size_t)np + (size_t)q) * (size_t)ni + (size_t)i];
        z[0] = hr[l];
        z[1] = hi[l];
      }
    }
}

/* Formed, factored with g, solved and output for the lanes of mask that g
   suits; returns those. */
RR_CLONES_V4 static unsigned pass(rr_frf_sparse *s, const rr_frf_prog *g, const double *wl,
                                  unsigned mask, double complex *H)
{
  vd w;
  memcpy(&w, wl, sizeof w);
  form(s, g, &w);
  unsigned ok = mask & ~factor(s, g);
  if (ok) {
    solve(s, g);
    outputs(s, &w, ok, H);
  }
  return ok;
}

/* Codelet c's form, factorisation and solve, then the outputs, for the
   lanes of mask it suits; returns those. */
RR_CLONES_V4 static unsigned pass_codelet(rr_frf_sparse *s, const rr_frf_codelet *c,
                                          const double *wl, unsigned mask, double complex *H)
{
  vd w;
  memcpy(&w, wl, sizeof w);
  unsigned ok = mask & ~c->run[s->sum](s, wl);
  if (ok) outputs(s, &w, ok, H);
  return ok;
}

/* ---- the driver ---- */

static int put(int *sig, int at, const int *x, int n)
{
  memcpy(sig + at, x, sizeof(int) * (size_t)n);
  return at + n;
}

int rr_frf_sparse_signature(const rr_frf_sparse *s, int *sig)
{
  const rr_frf_prog *g = &s->prog;
  const rr_dsolver *ds = s->ds;
  int n = s->n, nl = g->ls[n], nu = g->us[n], t = 0, at = 0;
  sig[at++] = n;
  sig[at++] = s->ni;
  sig[at++] = g->ncomp;
  sig[at++] = ds->nmx;
  for (int e = 0; e < ds->nmx; e++) t += sig[at++] = ds->mx[e].nz * ds->mx[e].nz;
  at = put(sig, at, g->piv, n);
  at = put(sig, at, g->ls, n + 1);
  at = put(sig, at, g->lrow, nl);
  at = put(sig, at, g->lc, nl);
  at = put(sig, at, g->us, n + 1);
  at = put(sig, at, g->ucol, nu);
  at = put(sig, at, g->uc, nu);
  for (int k = 0; k < n; k++) sig[at++] = (int)g->act[k];
  for (int k = 0; k < n; k++) sig[at++] = (int)g->in0[k];
  for (int c = 0; c < g->ncomp; c++) sig[at++] = g->formed[c];
  return put(sig, at, g->cmx, t);
}

/* The codelet generated for the structure just prepared, or NULL. */
static const rr_frf_codelet *find_codelet(rr_frf_sparse *s)
{
  if (s->interpret) return NULL;
  int ns = rr_frf_sparse_signature(s, s->sig);
  for (int i = 0; i < rr_frf_ncodelets; i++) {
    const rr_frf_codelet *c = &rr_frf_codelets[i];
    if (c->nsig == ns && s->kmin >= c->kmin && !memcmp(c->sig, s->sig, sizeof(int) * (size_t)ns))
      return c;
  }
  return NULL;
}

/* The inputs in the solver's order, the output rows' nonzeros and the lowest
   unknown they read, each Maxwell element's J_a J_b; -1 when the elements
   have more entries than the workspace holds. */
static int setup(rr_frf_sparse *s, const rr_model *m, const double *rows, const double *rows0)
{
  const rr_dsolver *ds = s->ds;
  int n = s->n, ni = s->ni, t = 0;
  s->kmin = n;
  for (int k = 0; k < n; k++)
    for (int i = 0; i < ni; i++) s->rhs[k * ni + i] = m->B[ds->perm[k] * ni + i];
  for (int q = 0; q < s->np; q++) {
    int c = 0;
    for (int j = 0; j < n; j++) {
      double a = rows[q * n + ds->perm[j]], a0 = rows0 ? rows0[q * n + ds->perm[j]] : 0;
      if (a == 0 && a0 == 0) continue;
      s->oj[q * n + c] = j;
      s->ow[q * n + c] = a;
      s->ow0[q * n + c++] = a0;
      if (j < s->kmin) s->kmin = j;
    }
    s->on[q] = c;
  }
  for (int e = 0; e < ds->nmx; e++) {
    if ((size_t)(t + ds->mx[e].nz * ds->mx[e].nz) > mx_cap((size_t)n)) return -1;
    for (int a = 0; a < ds->mx[e].nz; a++)
      for (int b = 0; b < ds->mx[e].nz; b++) s->jj[t++] = ds->mx[e].J[a] * ds->mx[e].J[b];
  }
  return 0;
}

/* Each element's series stiffness at the lanes' frequencies (SDF elements:
   the curve's, one curve for all). */
static void series(rr_frf_sparse *s, const rr_model *m, const double *w)
{
  double kr[L], ki[L];
  int have = 0;
  for (int e = 0; e < s->ds->nmx; e++) {
    double *pr = s->kr + e * L, *pi = s->ki + e * L;
    if (!s->ds->mx[e].sdf) {
      for (int l = 0; l < L; l++) pr[l] = s->ds->mx[e].k, pi[l] = 0;
      continue;
    }
    for (int l = 0; l < L && !have; l++) {
      double complex k = rr_sdf_series_k(&m->curve, m->sdf_mode, I * w[l]);
      kr[l] = creal(k);
      ki[l] = cimag(k);
    }
    have = 1;
    memcpy(pr, kr, sizeof kr);
    memcpy(pi, ki, sizeof ki);
  }
}

/* One frequency by the scalar solver with partial pivoting, always afresh
   (a cached order would make the result depend on the frequencies solved
   before); H: the frequency's outputs, lag: its inputs' lags (s->sum). */
static void scalar(rr_frf_sparse *s, const rr_model *m, double w, const double complex *lag,
                   double complex *H)
{
  rr_dsolver *ds = s->ds;
  int n = s->n, ni = s->ni, ne = s->sum ? 1 : ni;
  double k_sdf = m->sdf_mode == RR_SDF_PAPER ? rr_sdf_storage(&m->curve, w / (2 * RR_PI)) : 0;
  rr_dsolver_factor_fresh(ds, I * w, k_sdf);
  for (int i = 0; i < ne; i++) {
    for (int k = 0; k < n; k++) {
      double complex b = s->sum ? 0 : s->rhs[k * ni + i];
      for (int e = 0; e < ni && s->sum; e++) b += s->rhs[k * ni + e] * lag[e];
      s->b[k] = b;
    }
    rr_dsolver_solve(ds, s->b, s->t);
    for (int q = 0; q < s->np; q++) {
      double complex a = 0, a0 = 0;
      for (int c = 0; c < s->on[q]; c++) {
        a += s->ow[q * n + c] * s->b[s->oj[q * n + c]];
        a0 += s->ow0[q * n + c] * s->b[s->oj[q * n + c]];
      }
      H[q * ne + i] = -w * w * a + a0;
    }
  }
}

int rr_frf_sparse_prepare(rr_frf_sparse *s, const rr_model *m, const double *rows,
                          const double *rows0)
{
  s->ds->dirty = 0; /* rr_dsolver_init sets it when the pattern is not the last one */
  rr_dsolver_init(s->ds, m, s->dsi, s->dsz);
  if (s->ds->dirty) s->prog.valid = 0;
  int lanes = !setup(s, m, rows, rows0);
  if (lanes && !s->prog.valid) compile(s);
  if (lanes) prog_values(s, &s->prog);
  return lanes;
}

/* The lanes' lags from frequency k0 on (the last frequency repeated). */
static void lanes_lag(rr_frf_sparse *s, const double complex *lag, int k0, int nk)
{
  for (int i = 0; i < s->ni; i++)
    for (int l = 0; l < L; l++) {
      double complex z = lag[(size_t)(k0 + (l < nk ? l : nk - 1)) * (size_t)s->ni + (size_t)i];
      s->gr[i * L + l] = creal(z);
      s->gi[i * L + l] = cimag(z);
    }
}

void rr_frf_sparse_execute(rr_frf_sparse *s, const rr_model *m, const double *f, int nf,
                           const double *rows, const double *rows0, const double complex *lag,
                           double complex *H)
{
  int lanes = rr_frf_sparse_prepare(s, m, rows, rows0);
  const rr_frf_codelet *c = lanes ? find_codelet(s) : NULL;
  s->codelet = c ? (int)(c - rr_frf_codelets) : -1;
  s->sum = lag != NULL;
  size_t stride = (size_t)s->np * (size_t)(s->sum ? 1 : s->ni);
  for (int k0 = 0; k0 < nf; k0 += L) {
    int nk = nf - k0 < L ? nf - k0 : L;
    double w[L];
    for (int l = 0; l < L; l++) w[l] = 2 * RR_PI * f[k0 + (l < nk ? l : nk - 1)];
    unsigned todo = (1u << nk) - 1;
    if (lanes) {
      series(s, m, w);
      if (s->sum) lanes_lag(s, lag, k0, nk);
      double complex *Hk = H + (size_t)k0 * stride;
      todo &= ~(c ? pass_codelet(s, c, w, todo, Hk) : pass(s, &s->prog, w, todo, Hk));
    }
    for (; todo; todo &= todo - 1) {
      int l = __builtin_ctz(todo);
      const double complex *lk = s->sum ? lag + (size_t)(k0 + l) * (size_t)s->ni : NULL;
      scalar(s, m, w[l], lk, H + (size_t)(k0 + l) * stride);
    }
  }
}
