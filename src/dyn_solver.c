/* The dynamic stiffness of a model, formed and factored sparsely (see
 * dyn_solver.h). */
#include <math.h>
#include <string.h>
#include "dyn_solver.h"

void rr_dsolver_init(rr_dsolver *ds, const rr_model *m, int *iwork, double complex *zwork)
{
  int n = m->n, p = 0, inv[RR_SYS_MAX_DOF];
  ds->m = m;
  ds->n = n;
  for (int g = RR_NGROUPS - 1; g >= 0; g--)
    for (int i = 0; i < n; i++)
      if (m->group[i] == g) ds->perm[p++] = i;
  for (int i = 0; i < n; i++) {
    inv[ds->perm[i]] = i;
    ds->mass[i] = m->mdiag[ds->perm[i]];
  }
  ds->nnz = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      int a = ds->perm[i], b = ds->perm[j];
      double c = m->C[a * n + b], k = m->K[a * n + b];
      if (c == 0 && k == 0 && !(i == j && ds->mass[i] != 0)) continue;
      ds->nz_i[ds->nnz] = i;
      ds->nz_j[ds->nnz] = j;
      ds->nz_c[ds->nnz] = c;
      ds->nz_k[ds->nnz++] = k;
    }
  ds->nmx = m->nmx;
  for (int e = 0; e < m->nmx; e++) {
    const rr_mx *x = &m->mx[e];
    ds->mx[e].nz = x->nz;
    ds->mx[e].sdf = x->sdf && m->sdf_mode != RR_SDF_NONE;
    ds->mx[e].k = x->k;
    ds->mx[e].c = x->c;
    for (int a = 0; a < x->nz; a++) {
      ds->mx[e].idx[a] = inv[x->idx[a]];
      ds->mx[e].J[a] = x->J[x->idx[a]];
    }
  }
  ds->D = zwork;
  ds->ord = iwork;
  ds->rest = iwork + n;
  ds->lstart = iwork + 2 * n;
  ds->ustart = iwork + 3 * n + 1;
  ds->lrow = iwork + 4 * n + 2;
  ds->ucol = iwork + 4 * n + 2 + n * n;
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
  memset(D, 0, sizeof *D * (size_t)n * (size_t)n);
  for (int q = 0; q < ds->nnz; q++) {
    int i = ds->nz_i[q], j = ds->nz_j[q];
    D[i * n + j] = s * ds->nz_c[q] + ds->nz_k[q] + (i == j ? s2 * ds->mass[i] : 0);
  }
  for (int e = 0; e < ds->nmx; e++) {
    double complex k = series_k(ds, e, s, k_sdf), c = ds->mx[e].c;
    double complex ke = isinf(creal(k)) ? c * s : k * c * s / (k + c * s);
    for (int a = 0; a < ds->mx[e].nz; a++) {
      double complex t = ke * ds->mx[e].J[a];
      for (int b = 0; b < ds->mx[e].nz; b++) D[ds->mx[e].idx[a] * n + ds->mx[e].idx[b]] += t * ds->mx[e].J[b];
    }
  }
}

static double abs1(double complex z) { return fabs(creal(z)) + fabs(cimag(z)); }

/* Rows stay where they are; ord[k] is the physical row of pivot k. L's
   column k lists the rows it touches (lrow), U's row k its columns (ucol). */
void rr_dsolver_factor(rr_dsolver *ds, double complex s, double k_sdf)
{
  form(ds, s, k_sdf);
  int n = ds->n, nl = 0, nu = 0, nrest = n;
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
      if (v > best) { best = v; best_r = r; }
    }
    int p = ds->rest[best_r];
    ds->rest[best_r] = ds->rest[--nrest];
    ds->ord[k] = p;
    double complex *prow = A + (size_t)p * n;
    if (best <= tiny) prow[k] = tiny > 0 ? tiny : 1e-300;
    ds->ustart[k] = nu;
    for (int j = k + 1; j < n; j++)
      if (prow[j] != 0) ds->ucol[nu++] = j;
    ds->lstart[k] = nl;
    double complex inv = 1.0 / prow[k];
    for (int r = 0; r < nrest; r++) {
      double complex *row = A + (size_t)ds->rest[r] * n;
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

void rr_dsolver_solve(const rr_dsolver *ds, double complex *b, double complex *t)
{
  int n = ds->n;
  const double complex *A = ds->D;
  for (int k = 0; k < n; k++) {
    double complex bk = b[ds->ord[k]];
    if (bk == 0) continue;
    for (int q = ds->lstart[k]; q < ds->lstart[k + 1]; q++) b[ds->lrow[q]] -= A[ds->lrow[q] * n + k] * bk;
  }
  for (int k = n - 1; k >= 0; k--) {
    const double complex *row = A + (size_t)ds->ord[k] * n;
    double complex acc = b[ds->ord[k]];
    for (int q = ds->ustart[k]; q < ds->ustart[k + 1]; q++) acc -= row[ds->ucol[q]] * t[ds->ucol[q]];
    t[k] = acc / row[k];
  }
  memcpy(b, t, sizeof *b * (size_t)n);
}

void rr_dsolver_deriv(const rr_dsolver *ds, double complex s, double k_sdf, const double complex *x,
                      double complex *y)
{
  int n = ds->n;
  for (int i = 0; i < n; i++) y[i] = 2.0 * s * ds->mass[i] * x[i];
  for (int q = 0; q < ds->nnz; q++) y[ds->nz_i[q]] += ds->nz_c[q] * x[ds->nz_j[q]];
  for (int e = 0; e < ds->nmx; e++) {
    double complex k = series_k(ds, e, s, k_sdf), c = ds->mx[e].c, d;
    if (isinf(creal(k))) d = c;
    else { double complex q = k + c * s; d = k * k * c / (q * q); }
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
