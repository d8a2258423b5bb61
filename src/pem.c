/* Frequency response by modal expansion (+ Sherman-Morrison-Woodbury for the
 * SDF elements that have no state-space form) or by direct solves, and the
 * pseudo-excitation method (MODEL.md section 6). */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/pem.h"
#include "model_impl.h"
#include "clu.h"
#include "internal.h"

#define MAXU 8

struct rr_frf_plan {
  int n, ni, np, nf, Nmax, method, has0;
  double *f;                 /* nf */
  double *rows, *rows0;      /* np x n */
  double complex *H;         /* nf x np x ni */
  /* modal workspace */
  double *A, *At, *vl, *vr, *wr, *wi, *work;
  int lwork;
  double complex *lam, *o, *o0, *b, *u, *c;   /* per mode: np, np, ni, nU, nU */
  double *tre, *tim;          /* per term (pair or real mode): residue entries, real and imaginary parts */
  double *are, *aim;          /* accumulators of one frequency */
  /* direct workspace */
  double complex *D, *X;
  int *piv;
};

void rr_frf_plan_free(rr_frf_plan *p)
{
  if (!p) return;
  free(p->f); free(p->rows); free(p->rows0); free(p->H);
  free(p->A); free(p->At); free(p->vl); free(p->vr); free(p->wr); free(p->wi); free(p->work);
  free(p->lam); free(p->o); free(p->o0); free(p->b); free(p->u); free(p->c);
  free(p->tre); free(p->tim); free(p->are); free(p->aim);
  free(p->D); free(p->X); free(p->piv);
  free(p);
}

int rr_frf_plan_new(const rr_model *m, const rr_frf_opts *o, rr_frf_plan **out, rr_error *err)
{
  *out = NULL;
  if (!o || o->npoints < 1 || !o->rows) return rr_seterr(err, RR_EINVAL, "frf: at least one output row is needed");
  int nf = o->nfreq > 0 ? o->nfreq : 400;
  if (!o->freqs_hz) {
    double lo = o->f_lo_hz > 0 ? o->f_lo_hz : 0.3, hi = o->f_hi_hz > 0 ? o->f_hi_hz : 30;
    if (!(hi > lo) && nf > 1) return rr_seterr(err, RR_EINVAL, "frf: need 0 < f_lo < f_hi");
  }
  if (o->method != RR_FRF_MODAL && o->method != RR_FRF_DIRECT) return rr_seterr(err, RR_EINVAL, "frf: unknown method");
  rr_frf_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  int n = p->n = m->n, np = p->np = o->npoints, ni = p->ni = m->ni;
  p->nf = nf;
  p->method = o->method;
  p->has0 = o->rows0 != NULL;
  int N = p->Nmax = 2 * n + m->nmx + m->nsdf + 2;
  for (int i = 0; i < m->nmx; i++) N += m->mx[i].sdf;   /* room for physical mode */
  p->Nmax = N;
  size_t NN = (size_t)N * N;
  p->f = malloc(sizeof(double) * nf);
  p->rows = malloc(sizeof(double) * np * n);
  p->rows0 = calloc((size_t)np * n, sizeof(double));
  p->H = malloc(sizeof(double complex) * (size_t)nf * np * ni);
  p->A = malloc(sizeof(double) * NN);
  p->At = malloc(sizeof(double) * NN);
  p->vl = malloc(sizeof(double) * NN);
  p->vr = malloc(sizeof(double) * NN);
  p->wr = malloc(sizeof(double) * N);
  p->wi = malloc(sizeof(double) * N);
  p->lam = malloc(sizeof(double complex) * N);
  p->o = malloc(sizeof(double complex) * N * np);
  p->o0 = malloc(sizeof(double complex) * N * np);
  p->b = malloc(sizeof(double complex) * N * ni);
  p->u = malloc(sizeof(double complex) * N * MAXU);
  p->c = malloc(sizeof(double complex) * N * MAXU);
  p->D = malloc(sizeof(double complex) * n * n);
  size_t E = (size_t)2 * np * ni + (size_t)MAXU * ni + (size_t)2 * np * MAXU + (size_t)MAXU * MAXU;
  p->tre = malloc(sizeof(double) * N * E);
  p->tim = malloc(sizeof(double) * N * E);
  p->are = malloc(sizeof(double) * E);
  p->aim = malloc(sizeof(double) * E);
  p->X = malloc(sizeof(double complex) * n * (ni + MAXU));
  p->piv = malloc(sizeof(int) * n);
  if (!p->f || !p->rows || !p->rows0 || !p->H || !p->A || !p->At || !p->vl || !p->vr || !p->wr || !p->wi || !p->lam ||
      !p->o || !p->o0 || !p->b || !p->u || !p->c || !p->D || !p->X || !p->piv || !p->tre || !p->tim || !p->are || !p->aim) {
    rr_frf_plan_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int i = 0; i < nf; i++) {
    if (o->freqs_hz) p->f[i] = o->freqs_hz[i];
    else {
      double lo = o->f_lo_hz > 0 ? o->f_lo_hz : 0.3, hi = o->f_hi_hz > 0 ? o->f_hi_hz : 30;
      p->f[i] = nf == 1 ? lo : lo * pow(hi / lo, (double)i / (nf - 1));
    }
    if (!(isfinite(p->f[i]) && p->f[i] > 0)) { rr_frf_plan_free(p); return rr_seterr(err, RR_EINVAL, "frf: frequencies must be > 0"); }
  }
  memcpy(p->rows, o->rows, sizeof(double) * np * n);
  if (o->rows0) memcpy(p->rows0, o->rows0, sizeof(double) * np * n);
  double q;
  int info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'V', 'V', N, p->At, N, p->wr, p->wi, p->vl, N, p->vr, N, &q, -1);
  if (info) { rr_frf_plan_free(p); return rr_seterr(err, RR_ELAPACK, "dgeev workspace query failed"); }
  p->lwork = (int)q + 1;
  p->work = malloc(sizeof(double) * p->lwork);
  if (!p->work) { rr_frf_plan_free(p); return rr_seterr(err, RR_ENOMEM, "out of memory"); }
  *out = p;
  return RR_OK;
}

int rr_frf_nfreq(const rr_frf_plan *p) { return p->nf; }
int rr_frf_npoints(const rr_frf_plan *p) { return p->np; }
int rr_frf_ninputs(const rr_frf_plan *p) { return p->ni; }
const double *rr_frf_freqs(const rr_frf_plan *p) { return p->f; }
const double complex *rr_frf_H(const rr_frf_plan *p) { return p->H; }

static int execute_direct(rr_frf_plan *p, const rr_model *m)
{
  int n = p->n, ni = p->ni, np = p->np;
  for (int k = 0; k < p->nf; k++) {
    double w = 2 * RR_PI * p->f[k];
    rr_model_dynamic_stiffness(m, I * w, 0, p->D);
    double nrm = 0;
    for (int i = 0; i < n * n; i++) nrm += cabs(p->D[i]);
    rr_clu_factor(p->D, n, p->piv, 1e-300 + 1e-17 * nrm / n);
    for (int i = 0; i < ni; i++) {
      double complex *x = p->X + (size_t)i * n;
      for (int r = 0; r < n; r++) x[r] = m->B[r * ni + i];
      rr_clu_solve(p->D, n, p->piv, x);
    }
    for (int q = 0; q < np; q++)
      for (int i = 0; i < ni; i++) {
        double complex acc = 0, acc0 = 0;
        const double complex *x = p->X + (size_t)i * n;
        for (int r = 0; r < n; r++) { acc += p->rows[q * n + r] * x[r]; acc0 += p->rows0[q * n + r] * x[r]; }
        p->H[((size_t)k * np + q) * ni + i] = -w * w * acc + acc0;
      }
  }
  return RR_OK;
}

/* The elements handled by SMW: SDF elements without a state-space form
 * (paper mode; physical mode with a table). Merged mirror pairs count once. */
static int smw_elements(const rr_model *m, int *elem, double *mult)
{
  int sdf_ss = m->sdf_mode == RR_SDF_PHYSICAL && m->curve.kind != RR_CURVE_TABLE;
  if (m->sdf_mode == RR_SDF_NONE || sdf_ss) return 0;
  int all[2 * RR_SYS_MAX_BODIES], nu = 0;
  double mm[2 * RR_SYS_MAX_BODIES];
  int nk = rr_merged_elements(m, all, mm);
  for (int i = 0; i < nk; i++)
    if (m->mx[all[i]].sdf && nu < MAXU) { elem[nu] = all[i]; mult[nu] = mm[i]; nu++; }
  return nu;
}

/* Residues from LAPACK's eigenvectors of the state matrix in p->A (left and
   right): (sI - A)^-1 = sum_j x_j u_j^H / (u_j^H x_j (s - lambda_j)). */
static int residues_dgeev(rr_frf_plan *p, const rr_model *m, int N, int nu, const int *uel, rr_error *err)
{
  int n = p->n, ni = p->ni, np = p->np;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) p->At[j * N + i] = p->A[i * N + j];
  int info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'V', 'V', N, p->At, N, p->wr, p->wi, p->vl, N, p->vr, N, p->work, p->lwork);
  if (info) return rr_seterr(err, RR_ELAPACK, "dgeev failed (info %d)", info);
  for (int j = 0; j < N; j++) {
    double complex lam = p->wr[j] + I * p->wi[j];
    int pair = p->wi[j] != 0, first = pair && p->wi[j] > 0;
    int c0 = pair ? (first ? j : j - 1) : j;
    double sg = pair && !first ? -1.0 : 1.0;
#define XR(r) (p->vr[(size_t)c0 * N + (r)] + (pair ? sg * I * p->vr[(size_t)(c0 + 1) * N + (r)] : 0))
#define UL(r) (p->vl[(size_t)c0 * N + (r)] + (pair ? sg * I * p->vl[(size_t)(c0 + 1) * N + (r)] : 0))
    double complex s = 0;
    for (int r = 0; r < N; r++) s += conj(UL(r)) * XR(r);
    if (cabs(s) == 0) return rr_seterr(err, RR_ELAPACK, "frf: defective state matrix (use the direct method)");
    double complex is = 1.0 / s;
    p->lam[j] = lam;
    for (int q = 0; q < np; q++) {
      double complex a = 0, a0 = 0;
      for (int r = 0; r < n; r++) { a += p->rows[q * n + r] * XR(r); a0 += p->rows0[q * n + r] * XR(r); }
      p->o[j * np + q] = a;
      p->o0[j * np + q] = a0;
    }
    for (int i = 0; i < ni; i++) {
      double complex a = 0;
      for (int r = 0; r < n; r++) a += conj(UL(n + r)) * (m->B[r * ni + i] / m->mdiag[r]);
      p->b[j * ni + i] = a * is;
    }
    for (int e = 0; e < nu; e++) {
      const rr_mx *x = &m->mx[uel[e]];
      double complex a = 0, cc = 0;
      for (int t = 0; t < x->nz; t++) {
        int r = x->idx[t];
        a += x->J[r] * XR(r);
        cc += conj(UL(n + r)) * (x->J[r] / m->mdiag[r]);
      }
      p->u[j * MAXU + e] = a;
      p->c[j * MAXU + e] = cc * is;
    }
#undef XR
#undef UL
  }
  return RR_OK;
}

static int execute_modal(rr_frf_plan *p, const rr_model *m, rr_error *err)
{
  int ni = p->ni, np = p->np;
  int uel[MAXU];
  double umult[MAXU];
  int nu = smw_elements(m, uel, umult);
  double k_lo = 0, k_hi = 0;
  if (nu) rr_sdf_range(&m->curve, &k_lo, &k_hi);
  /* State-space part: SMW elements held at the reference stiffness k_lo. */
  rr_model *mm = (rr_model *)m;
  int mode_saved = mm->sdf_mode;
  if (nu) mm->sdf_mode = RR_SDF_PAPER;
  int N, st = rr_state_matrix_merged(m, k_lo, p->A, &N, err);
  if (st) { mm->sdf_mode = mode_saved; return st; }
  if (N > p->Nmax) { mm->sdf_mode = mode_saved; return rr_seterr(err, RR_EINVAL, "frf plan too small for this model"); }
  mm->sdf_mode = mode_saved;
  if ((st = residues_dgeev(p, m, N, nu, uel, err))) return st;
  /* Residue entries per term: Hq (np x ni), H0 (np x ni), Hu (nu x ni),
     Gq (np x nu), G0 (np x nu), Z (nu x nu), each the product of a left and
     a right projection. A conjugate pair contributes
     R d1 + conj(R) d2 = Re(R) (d1 + d2) + Im(R) j (d1 - d2), so it is stored
     once (the eigenvalue with Im > 0) and costs two real-times-complex
     products per entry instead of two complex products. */
  int nHq = np * ni, nHu = nu * ni, nGq = np * nu, nZ = nu * nu;
  /* the roll-gravity blocks H0, G0 last, and only when asked for */
  int oHq = 0, oHu = nHq, oGq = oHu + nHu, oZ = oGq + nGq, oH0 = oZ + nZ, oG0 = oH0 + nHq;
  int E = p->has0 ? oG0 + nGq : oH0;
  int nt = 0;
  double complex tlam[2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES];
  int tpair[2 * RR_SYS_MAX_DOF + 4 * RR_SYS_MAX_BODIES];
  for (int j = 0; j < N; j++) {
    if (p->wi[j] < 0) continue;   /* the conjugate of a stored pair */
    double *tr = p->tre + (size_t)nt * E, *ti = p->tim + (size_t)nt * E;
    const double complex *o = p->o + j * np, *o0 = p->o0 + j * np, *bb = p->b + j * ni, *uu = p->u + j * MAXU, *cc = p->c + j * MAXU;
#define PUT(off, val) do { double complex v_ = (val); tr[off] = creal(v_); ti[off] = cimag(v_); } while (0)
    for (int q = 0; q < np; q++) {
      for (int i = 0; i < ni; i++) PUT(oHq + q * ni + i, o[q] * bb[i]);
      for (int e = 0; e < nu; e++) PUT(oGq + q * nu + e, o[q] * cc[e]);
      if (p->has0) {
        for (int i = 0; i < ni; i++) PUT(oH0 + q * ni + i, o0[q] * bb[i]);
        for (int e = 0; e < nu; e++) PUT(oG0 + q * nu + e, o0[q] * cc[e]);
      }
    }
    for (int e = 0; e < nu; e++) {
      for (int i = 0; i < ni; i++) PUT(oHu + e * ni + i, uu[e] * bb[i]);
      for (int g = 0; g < nu; g++) PUT(oZ + e * nu + g, uu[e] * cc[g]);
    }
#undef PUT
    tlam[nt] = p->lam[j];
    tpair[nt] = p->wi[j] > 0;
    nt++;
  }
  for (int k = 0; k < p->nf; k++) {
    double w = 2 * RR_PI * p->f[k];
    double complex s = I * w;
    double *restrict are = p->are, *restrict aim = p->aim;
    for (int e = 0; e < E; e++) are[e] = aim[e] = 0;
    for (int t = 0; t < nt; t++) {
      double complex d1 = 1.0 / (s - tlam[t]), sg, dl;
      if (tpair[t]) {
        double complex d2 = 1.0 / (s - conj(tlam[t]));
        sg = d1 + d2;           /* multiplies Re(R) */
        dl = I * (d1 - d2);     /* multiplies Im(R) */
      } else {
        sg = d1;                /* R d1 = Re(R) d1 + Im(R) j d1 */
        dl = I * d1;
      }
      double sr = creal(sg), si = cimag(sg), dr = creal(dl), di = cimag(dl);
      const double *restrict tr = p->tre + (size_t)t * E, *restrict ti = p->tim + (size_t)t * E;
      for (int e = 0; e < E; e++) {
        are[e] += tr[e] * sr + ti[e] * dr;
        aim[e] += tr[e] * si + ti[e] * di;
      }
    }
    double complex Hq[16 * 16], H0[16 * 16], Hu[MAXU * 16], Gq[16 * MAXU], G0[16 * MAXU], Z[MAXU * MAXU];
    for (int e = 0; e < nHq; e++) {
      Hq[e] = are[oHq + e] + I * aim[oHq + e];
      H0[e] = p->has0 ? are[oH0 + e] + I * aim[oH0 + e] : 0;
    }
    for (int e = 0; e < nHu; e++) Hu[e] = are[oHu + e] + I * aim[oHu + e];
    for (int e = 0; e < nGq; e++) {
      Gq[e] = are[oGq + e] + I * aim[oGq + e];
      G0[e] = p->has0 ? are[oG0 + e] + I * aim[oG0 + e] : 0;
    }
    for (int e = 0; e < nZ; e++) Z[e] = are[oZ + e] + I * aim[oZ + e];
    if (nu) {
      /* D = D0 + U dK U^T: O D^-1 B = O D0^-1 B - O D0^-1 U (I + dK Z)^-1 dK U^T D0^-1 B */
      double complex dK[MAXU], W[MAXU * MAXU], Y[MAXU * 16];
      int piv[MAXU];
      for (int e = 0; e < nu; e++) {
        const rr_mx *x = &m->mx[uel[e]];
        double complex kf = rr_model_series_k(m, uel[e], s, 0);
        double complex c = x->c;
        dK[e] = umult[e] * (kf * c * s / (kf + c * s) - k_lo * c * s / (k_lo + c * s));
      }
      for (int e = 0; e < nu; e++)
        for (int g = 0; g < nu; g++) W[e * nu + g] = (e == g) + dK[e] * Z[e * nu + g];
      rr_clu_factor(W, nu, piv, 1e-300);
      for (int i = 0; i < ni; i++) {
        double complex y[MAXU];
        for (int e = 0; e < nu; e++) y[e] = dK[e] * Hu[e * ni + i];
        rr_clu_solve(W, nu, piv, y);
        for (int e = 0; e < nu; e++) Y[e * ni + i] = y[e];
      }
      for (int q = 0; q < np; q++)
        for (int i = 0; i < ni; i++)
          for (int e = 0; e < nu; e++) {
            Hq[q * ni + i] -= Gq[q * nu + e] * Y[e * ni + i];
            H0[q * ni + i] -= G0[q * nu + e] * Y[e * ni + i];
          }
    }
    double complex *Hk = p->H + (size_t)k * np * ni;
    for (int t = 0; t < np * ni; t++) Hk[t] = -w * w * Hq[t] + H0[t];
  }
  return RR_OK;
}

int rr_frf_plan_execute(rr_frf_plan *p, const rr_model *m, rr_error *err)
{
  if (m->n != p->n || m->ni != p->ni) return rr_seterr(err, RR_EINVAL, "frf: plan was made for another model size");
  if (p->np > 16 || p->ni > 16) return rr_seterr(err, RR_EINVAL, "frf: at most 16 points and 16 inputs");
  if (p->method == RR_FRF_DIRECT) return execute_direct(p, m);
  return execute_modal(p, m, err);
}

double rr_pem_combine(const double complex *H, const double *x, int ni, double w, double v, double Gt)
{
  double complex a = 0;
  for (int i = 0; i < ni; i++) a += H[i] * cexp(I * w * x[i] / v);
  return Gt * creal(a * conj(a));
}

int rr_pem_psd(const rr_frf_plan *p, const rr_model *m, const rr_spectrum *sp, double *G, rr_error *err)
{
  double v = m->speed;
  for (int k = 0; k < p->nf; k++) {
    double f = p->f[k], w = 2 * RR_PI * f;
    double Gt = rr_spectrum_eval(sp, f / v) / v;   /* temporal one-sided PSD, m^2/Hz */
    double complex lag[RR_SYS_MAX_INPUTS];
    for (int i = 0; i < p->ni; i++) lag[i] = cexp(I * w * m->contacts[i].x / v);
    for (int q = 0; q < p->np; q++) {
      const double complex *h = p->H + ((size_t)k * p->np + q) * p->ni;
      double complex a = 0;
      for (int i = 0; i < p->ni; i++) a += h[i] * lag[i];
      G[k * p->np + q] = Gt * (creal(a) * creal(a) + cimag(a) * cimag(a));
    }
  }
  return RR_OK;
}

int rr_vehicle_floor_rows(const rr_model *m, const rr_vehicle *veh, const double *x, int np, double h_p,
                          int roll_gravity, double *rows, double *rows0, rr_error *err)
{
  for (int q = 0; q < np; q++) {
    double pt[3] = {x[q], 0, h_p};
    int st = rr_model_point_row(m, "c", pt, RR_DIR_Y, rows + (size_t)q * m->n, err);
    if (st) return st;
    if (rows0) {
      double *r0 = rows0 + (size_t)q * m->n;
      for (int i = 0; i < m->n; i++) r0[i] = 0;
      if (roll_gravity) {
        for (int b = 0; b < m->nbodies; b++)
          if (!strcmp(m->bodies[b].name, "c") && m->bodies[b].dof_phi >= 0) r0[m->bodies[b].dof_phi] = RR_G;
      }
    }
  }
  (void)veh;
  return RR_OK;
}
