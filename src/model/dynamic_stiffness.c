/* The dynamic stiffness of a model, formed and factored sparsely (see
 * dynamic_stiffness.h). */
#include <math.h>
#include <string.h>
#include "model/dynamic_stiffness.h"

void rr_model_sparsity(rr_model *m)
{
  rr_sparsity *sp = &m->sp;
  int n = m->n, p = 0;
  unsigned char S[RR_SYS_MAX_DOF][RR_SYS_MAX_DOF];
  memset(S, 0, sizeof S);
  for (int a = 0; a < n; a++) {
    S[a][a] = 1;
    for (int b = 0; b < n; b++) S[a][b] |= m->C0[a * n + b] != 0 || m->K0[a * n + b] != 0;
  }
  for (int c = 0; c < m->ni; c++) { /* contact terms, whatever the speed and conicity */
    int y = m->contacts[c].dof_y, q = m->contacts[c].dof_psi;
    S[y][y] = S[y][q] = S[q][y] = S[q][q] = 1;
  }
  for (int g = RR_NGROUPS - 1; g >= 0; g--)
    for (int i = 0; i < n; i++)
      if (m->group[i] == g) sp->perm[p++] = i;
  for (int i = 0; i < n; i++) sp->inv[sp->perm[i]] = i;
  sp->nnz = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      if (S[sp->perm[i]][sp->perm[j]]) {
        sp->pos[sp->nnz] = i * n + j;
        sp->pi[sp->nnz] = (unsigned char)i;
        sp->pj[sp->nnz] = (unsigned char)j;
        sp->src[sp->nnz++] = sp->perm[i] * n + sp->perm[j];
      }
  sp->nkeep = rr_merged_elements(m, sp->elem, sp->mult);
}

void rr_dsolver_init(rr_dsolver *ds, const rr_model *m, int *iwork, double complex *zwork)
{
  const rr_sparsity *sp = &m->sp;
  int n = m->n;
  /* the cached pivot order stays valid while the pattern does */
  int same = ds->n == n && ds->D == zwork && ds->nnz == sp->nnz && ds->nmx == sp->nkeep &&
             !memcmp(ds->pos, sp->pos, sizeof(int) * (size_t)sp->nnz);
  ds->m = m;
  ds->n = n;
  memcpy(ds->perm, sp->perm, sizeof(int) * (size_t)n);
  for (int i = 0; i < n; i++) ds->mass[i] = m->mdiag[sp->perm[i]];
  ds->nnz = sp->nnz;
  memcpy(ds->pos, sp->pos, sizeof(int) * (size_t)sp->nnz);
  for (int q = 0; q < sp->nnz; q++) {
    ds->nz_c[q] = m->C[sp->src[q]];
    ds->nz_k[q] = m->K[sp->src[q]];
  }
  ds->nmx = sp->nkeep;
  for (int e = 0; e < sp->nkeep; e++) {
    const rr_mx *x = &m->mx[sp->elem[e]];
    same = same && ds->mx[e].nz == x->nz;
    ds->mx[e].nz = x->nz;
    ds->mx[e].sdf = x->sdf && m->sdf_mode != RR_SDF_NONE;
    ds->mx[e].mult = sp->mult[e];
    ds->mx[e].k = x->k;
    ds->mx[e].c = x->c;
    for (int a = 0; a < x->nz; a++) {
      same = same && ds->mx[e].idx[a] == sp->inv[x->idx[a]];
      ds->mx[e].idx[a] = sp->inv[x->idx[a]];
      ds->mx[e].J[a] = x->J[x->idx[a]];
    }
  }
  ds->D = zwork;
  int *w = iwork, nn = n * n;
  ds->rest = w, w += n;
  ds->dyn_ord = w, w += n;
  ds->dyn_ls = w, w += n + 1;
  ds->dyn_us = w, w += n + 1;
  ds->dyn_lr = w, w += nn;
  ds->dyn_uc = w, w += nn;
  ds->sta_ord = w, w += n;
  ds->sta_ls = w, w += n + 1;
  ds->sta_us = w, w += n + 1;
  ds->sta_lr = w, w += nn;
  ds->sta_uc = w;
  if (!same) ds->dirty = 1;
}

/* Series stiffness k of element e at s: paper-mode SDF elements take k_sdf. */
static double complex series_k(const rr_dsolver *ds, int e, double complex s, double k_sdf)
{
  if (!ds->mx[e].sdf) return ds->mx[e].k;
  if (ds->m->sdf_mode == RR_SDF_PAPER) return k_sdf;
  return rr_sdf_laplace(&ds->m->curve, s);
}

static void form(rr_dsolver *ds, double complex s, double k_sdf)
{
  int n = ds->n;
  double complex *D = ds->D, s2 = s * s;
  if (ds->dirty)
    memset(D, 0, sizeof *D * (size_t)n * (size_t)n);
  else /* only the cached factors' positions can be nonzero */
    for (int k = 0; k < n; k++) {
      double complex *prow = D + (size_t)ds->sta_ord[k] * (size_t)n;
      prow[k] = 0;
      for (int q = ds->sta_us[k]; q < ds->sta_us[k + 1]; q++) prow[ds->sta_uc[q]] = 0;
      for (int q = ds->sta_ls[k]; q < ds->sta_ls[k + 1]; q++) D[ds->sta_lr[q] * n + k] = 0;
    }
  for (int q = 0; q < ds->nnz; q++) D[ds->pos[q]] = s * ds->nz_c[q] + ds->nz_k[q];
  for (int i = 0; i < n; i++) D[i * n + i] += s2 * ds->mass[i];
  for (int e = 0; e < ds->nmx; e++) {
    double complex k = series_k(ds, e, s, k_sdf), c = ds->mx[e].c;
    double complex ke = ds->mx[e].mult * (isinf(creal(k)) ? c * s : k * c * s / (k + c * s));
    for (int a = 0; a < ds->mx[e].nz; a++) {
      double complex t = ke * ds->mx[e].J[a];
      for (int b = 0; b < ds->mx[e].nz; b++)
        D[ds->mx[e].idx[a] * n + ds->mx[e].idx[b]] += t * ds->mx[e].J[b];
    }
  }
}

static double abs1(double complex z) { return fabs(creal(z)) + fabs(cimag(z)); }

/* The cached pivot order and patterns (of the last pivoting LU): 0 when a
   multiplier grew beyond the threshold (D is then part-factored, on the
   cached positions only). */
static int factor_cached(rr_dsolver *ds)
{
  int n = ds->n;
  double complex *A = ds->D;
  for (int k = 0; k < n; k++) {
    double complex *prow = A + (size_t)ds->sta_ord[k] * (size_t)n;
    double pk = abs1(prow[k]);
    for (int q = ds->sta_ls[k]; q < ds->sta_ls[k + 1]; q++)
      if (!(abs1(A[ds->sta_lr[q] * n + k]) <= RR_DSOLVER_PIVOT_GROWTH * pk)) return 0;
    double complex inv = 1.0 / prow[k];
    for (int q = ds->sta_ls[k]; q < ds->sta_ls[k + 1]; q++) {
      double complex *row = A + (size_t)ds->sta_lr[q] * (size_t)n;
      double complex l = row[k] * inv;
      row[k] = l;
      for (int c = ds->sta_us[k]; c < ds->sta_us[k + 1]; c++)
        row[ds->sta_uc[c]] -= l * prow[ds->sta_uc[c]];
    }
  }
  ds->ord = ds->sta_ord;
  ds->lstart = ds->sta_ls;
  ds->lrow = ds->sta_lr;
  ds->ustart = ds->sta_us;
  ds->ucol = ds->sta_uc;
  return 1;
}

static void cache_patterns(rr_dsolver *ds)
{
  int n = ds->n;
  memcpy(ds->sta_ord, ds->dyn_ord, sizeof(int) * (size_t)n);
  memcpy(ds->sta_ls, ds->dyn_ls, sizeof(int) * (size_t)(n + 1));
  memcpy(ds->sta_us, ds->dyn_us, sizeof(int) * (size_t)(n + 1));
  memcpy(ds->sta_lr, ds->dyn_lr, sizeof(int) * (size_t)ds->dyn_ls[n]);
  memcpy(ds->sta_uc, ds->dyn_uc, sizeof(int) * (size_t)ds->dyn_us[n]);
}

/* Partial pivoting. Rows stay where they are; ord[k] is the physical row of
   pivot k. L's column k lists the rows it touches (lrow), U's row k its
   columns (ucol). */
static void factor_pivoting(rr_dsolver *ds)
{
  int n = ds->n, nl = 0, nu = 0, nrest = n;
  ds->ord = ds->dyn_ord;
  ds->lstart = ds->dyn_ls;
  ds->lrow = ds->dyn_lr;
  ds->ustart = ds->dyn_us;
  ds->ucol = ds->dyn_uc;
  double complex *A = ds->D;
  double scale = 0;
  for (int i = 0; i < n; i++) {
    ds->rest[i] = i;
    scale = fmax(scale, abs1(A[i * n + i]));
  }
  double tiny = 1e-15 * scale;
  for (int k = 0; k < n; k++) {
    int best_r = 0;
    double best = -1;
    for (int r = 0; r < nrest; r++) {
      double v = abs1(A[ds->rest[r] * n + k]);
      if (v > best) {
        best = v;
        best_r = r;
      }
    }
    int p = ds->rest[best_r];
    ds->rest[best_r] = ds->rest[--nrest];
    ds->ord[k] = p;
    double complex *prow = A + (size_t)p * (size_t)n;
    if (best <= tiny) prow[k] = tiny > 0 ? tiny : 1e-300;
    ds->ustart[k] = nu;
    for (int j = k + 1; j < n; j++)
      if (prow[j] != 0) ds->ucol[nu++] = j;
    ds->lstart[k] = nl;
    double complex inv = 1.0 / prow[k];
    for (int r = 0; r < nrest; r++) {
      double complex *row = A + (size_t)ds->rest[r] * (size_t)n;
      if (row[k] == 0) continue;
      double complex l = row[k] * inv;
      row[k] = l;
      ds->lrow[nl++] = ds->rest[r];
      for (int q = ds->ustart[k]; q < nu; q++) row[ds->ucol[q]] -= l * prow[ds->ucol[q]];
    }
  }
  ds->lstart[n] = nl;
  ds->ustart[n] = nu;
}

void rr_dsolver_factor(rr_dsolver *ds, double complex s, double k_sdf)
{
  form(ds, s, k_sdf);
  if (!ds->dirty && factor_cached(ds)) {
    ds->n_static++;
    return;
  }
  if (!ds->dirty) form(ds, s, k_sdf); /* the attempt touched the cached positions only */
  factor_pivoting(ds);
  cache_patterns(ds);
  ds->dirty = 0;
  ds->n_pivoting++;
}

void rr_dsolver_factor_fresh(rr_dsolver *ds, double complex s, double k_sdf)
{
  ds->dirty = 1;
  rr_dsolver_factor(ds, s, k_sdf);
}

void rr_dsolver_solve(const rr_dsolver *ds, double complex *b, double complex *t)
{
  int n = ds->n;
  const double complex *A = ds->D;
  for (int k = 0; k < n; k++) {
    double complex bk = b[ds->ord[k]];
    if (bk == 0) continue;
    for (int q = ds->lstart[k]; q < ds->lstart[k + 1]; q++)
      b[ds->lrow[q]] -= A[ds->lrow[q] * n + k] * bk;
  }
  for (int k = n - 1; k >= 0; k--) {
    const double complex *row = A + (size_t)ds->ord[k] * (size_t)n;
    double complex acc = b[ds->ord[k]];
    for (int q = ds->ustart[k]; q < ds->ustart[k + 1]; q++)
      acc -= row[ds->ucol[q]] * t[ds->ucol[q]];
    t[k] = acc / row[k];
  }
  memcpy(b, t, sizeof *b * (size_t)n);
}

void rr_dsolver_deriv(const rr_dsolver *ds, double complex s, double k_sdf, const double complex *x,
                      double complex *y)
{
  int n = ds->n;
  for (int i = 0; i < n; i++) y[i] = 2.0 * s * ds->mass[i] * x[i];
  const rr_sparsity *sp = &ds->m->sp;
  for (int q = 0; q < ds->nnz; q++) y[sp->pi[q]] += ds->nz_c[q] * x[sp->pj[q]];
  for (int e = 0; e < ds->nmx; e++) {
    double complex k = series_k(ds, e, s, k_sdf), c = ds->mx[e].c, d;
    if (isinf(creal(k)))
      d = c;
    else {
      double complex q = k + c * s;
      d = k * k * c / (q * q);
    }
    d *= ds->mx[e].mult;
    double complex jx = 0;
    for (int a = 0; a < ds->mx[e].nz; a++) jx += ds->mx[e].J[a] * x[ds->mx[e].idx[a]];
    for (int a = 0; a < ds->mx[e].nz; a++) y[ds->mx[e].idx[a]] += d * ds->mx[e].J[a] * jx;
  }
}

void rr_dsolver_to(const rr_dsolver *ds, const double complex *model, double complex *solver)
{
  for (int i = 0; i < ds->n; i++) solver[i] = model[ds->perm[i]];
}

void rr_dsolver_from(const rr_dsolver *ds, const double complex *solver, double complex *model)
{
  for (int i = 0; i < ds->n; i++) model[ds->perm[i]] = solver[i];
}
