/* Validation of the frequency domain (PEM) against a time-domain run of the
 * same linear state space driven by a random track realisation. */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/comfort.h"
#include "railride/pem.h"
#include "railride/timesim.h"
#include "model/model_impl.h"
#include "linalg/hessenberg_qr.h"
#include "util/internal.h"
#include "util/block.h"

rr_validate_opts rr_validate_opts_default(void)
{
  rr_validate_opts o;
  memset(&o, 0, sizeof o);
  o.duration_s = RR_VALIDATE_DURATION_S;
  o.fs_hz = 256;
  o.nseg = 4096;
  o.seed = 1;
  o.f_lo_hz = 0.3;
  o.f_hi_hz = 30;
  o.nfreq = 400;
  return o;
}

void rr_validate_result_free(rr_validate_result *r)
{
  if (!r) return;
  free(r->welch_f);
  free(r->welch_P);
  free(r->pem_P);
  free(r->points);
  memset(r, 0, sizeof *r);
}

/* PEM PSDs of the outputs on a given grid. */
static int pem_on(const rr_model *m, const rr_spectrum *sp, const rr_validate_opts *o, int nf,
                  const double *f, double *G, rr_error *err)
{
  rr_frf_opts fo = {.nfreq = nf,
                    .freqs_hz = f,
                    .f_lo_hz = o->f_lo_hz,
                    .f_hi_hz = o->f_hi_hz,
                    .npoints = o->npoints,
                    .rows = o->rows,
                    .rows0 = o->rows0,
                    .method = RR_FRF_SPARSE};
  rr_frf_plan *p;
  int st = rr_frf_plan_new(m, &fo, &p, err);
  if (st) return st;
  st = rr_frf_plan_execute(p, m, err);
  if (!st) st = rr_pem_psd(p, m, sp, G, err);
  rr_frf_plan_free(p);
  return st;
}

/* Hann window's DTFT at normalised angle th (rad/sample), N samples:
   0.5 S(th) - 0.25 S(th - 2pi/N) - 0.25 S(th + 2pi/N), S the geometric sum. */
static double complex hann_dtft(double th, int N)
{
  double complex acc = 0;
  const double sh[3] = {0, -2 * RR_PI / N, 2 * RR_PI / N}, wt[3] = {0.5, -0.25, -0.25};
  for (int i = 0; i < 3; i++) {
    double t = th + sh[i];
    double complex S;
    double sn = sin(0.5 * t);
    if (fabs(sn) < 1e-12)
      S = N;
    else
      S = (1 - cexp(-I * t * N)) / (1 - cexp(-I * t));
    acc += wt[i] * S;
  }
  return acc;
}

/* Every figure of a validation finite, or an error. */
static int results_finite(const rr_validate_result *r, rr_error *err)
{
  for (int q = 0; q < r->npoints; q++) {
    const rr_validate_point *p = &r->points[q];
    double v[] = {p->rms_pem,        p->rms_time,        p->sperling_pem,      p->sperling_time,
                  p->sperling_welch, p->sperling_gb_pem, p->sperling_gb_welch, p->wd_rms_pem,
                  p->wd_rms_welch,   p->band_error_max,  p->band_z_max,        p->rms_z,
                  p->sperling_z};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
      if (!isfinite(v[i]))
        return rr_seterr(err, RR_ENOCONV, "validate: a result at point %d is not finite", q + 1);
  }
  for (int i = 0; i < r->nwelch * r->npoints; i++)
    if (!isfinite(r->welch_P[i]) || !isfinite(r->pem_P[i]))
      return rr_seterr(err, RR_ENOCONV, "validate: a PSD is not finite");
  return RR_OK;
}

/* The validation's scratch, allocated and freed together. */
typedef struct vwork {
  int n, ni, np, N, ns, nh, ny;
  double dt;
  double *A, *A2, *Bs, *ABs; /* state matrix, its square, input matrix, A Bs */
  double *u, *du;            /* track inputs and their rates (ni x ns) */
  double *y, *aw;      /* outputs (accelerations, then their rates; ny x ns); a weighted one */
  double *C, *D, *E;   /* y = C z + D u + E u' */
  double *Gp, *fp;     /* PEM PSDs on the standard grid (nfreq x np), the grid */
  char *block;         /* the arrays above, one allocation (block.h) */
  rr_lti_disc dv, dfl; /* the vehicle and the Sperling filter, discretised */
  double fA[9], fB[3], fC[3];
  int kb0, kb1;      /* the Welch bins inside the band */
  long step, nsteps; /* progress */
} vwork;

static int check_opts(const rr_model *m, const rr_validate_opts *o, int *ns, rr_error *err)
{
  if (m->sdf_mode == RR_SDF_PAPER && m->nsdf)
    return rr_seterr(
        err, RR_EUNSUP,
        "validate: the paper-mode SDF has no time-domain form (use sdf = physical or none)");
  if (m->sdf_mode == RR_SDF_PHYSICAL && m->curve.kind == RR_CURVE_TABLE)
    return rr_seterr(err, RR_EUNSUP, "validate: a tabulated SDF curve has no time-domain form");
  if (!(o->duration_s > 0 && o->fs_hz > 2 * o->f_hi_hz && o->f_hi_hz > o->f_lo_hz &&
        o->f_lo_hz > 0 && o->npoints >= 1))
    return rr_seterr(err, RR_EINVAL,
                     "validate: need duration > 0, 0 < f_lo < f_hi < fs/2 and an output point");
  *ns = (int)lround(o->duration_s * o->fs_hz);
  *ns += *ns % 2;
  if (o->nseg > *ns)
    return rr_seterr(err, RR_EINVAL,
                     "validate: Welch segment (%d) longer than the record (%d samples)", o->nseg,
                     *ns);
  return RR_OK;
}

static void work_free(vwork *w)
{
  free(w->block);
  rr_lti_disc_free(&w->dv);
  rr_lti_disc_free(&w->dfl);
}

/* The run's arrays (block.h: called to size, then to carve). */
static void work_layout(vwork *w, size_t nfreq, rr_block *b)
{
  size_t N = (size_t)w->N, ni = (size_t)w->ni, ny = (size_t)w->ny, nsz = (size_t)w->ns;
  const size_t d = sizeof(double);
  w->A = rr_block_take(b, N * N, d);
  w->A2 = rr_block_take(b, N * N, d);
  w->Bs = rr_block_take(b, N * ni, d);
  w->ABs = rr_block_take(b, N * ni, d);
  w->u = rr_block_take(b, ni * nsz, d);
  w->du = rr_block_take(b, ni * nsz, d);
  w->y = rr_block_take(b, ny * nsz, d);
  w->aw = rr_block_take(b, nsz, d);
  w->C = rr_block_take(b, ny * N, d);
  w->D = rr_block_take(b, ny * ni, d);
  w->E = rr_block_take(b, ny * ni, d);
  w->Gp = rr_block_take(b, nfreq * (size_t)w->np, d);
  w->fp = rr_block_take(b, nfreq, d);
}

static int work_alloc(vwork *w, const rr_model *m, const rr_validate_opts *o, int ns,
                      rr_validate_result *r, rr_error *err)
{
  *w = (vwork){.n = m->n,
               .ni = m->ni,
               .np = o->npoints,
               .N = rr_model_state_size(m),
               .ns = ns,
               .nh = o->nseg / 2 + 1,
               .ny = 2 * o->npoints,
               .dt = 1.0 / o->fs_hz,
               .kb0 = -1,
               .kb1 = -1,
               .nsteps = 3 + o->npoints};
  rr_block b = {0};
  work_layout(w, (size_t)o->nfreq, &b);
  if (rr_block_alloc(&b)) return rr_seterr(err, RR_ENOMEM, "out of memory");
  w->block = b.base;
  work_layout(w, (size_t)o->nfreq, &b);
  r->npoints = w->np; /* the result's arrays are the caller's (rr_validate_result_free) */
  r->nwelch = w->nh;
  r->welch_f = malloc(sizeof(double) * (size_t)w->nh);
  r->welch_P = malloc(sizeof(double) * (size_t)w->nh * (size_t)w->np);
  r->pem_P = calloc((size_t)w->nh * (size_t)w->np, sizeof(double));
  r->points = calloc((size_t)w->np, sizeof(rr_validate_point));
  if (!r->welch_f || !r->welch_P || !r->pem_P || !r->points)
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  return RR_OK;
}

/* An unstable vehicle has no steady state: neither the time run nor the PEM
   describe anything then. A2 is scratch. */
static int check_stable(const rr_model *m, vwork *w, rr_error *err)
{
  int N = w->N;
  double *wr = malloc(sizeof(double) * (size_t)N), *wi = malloc(sizeof(double) * (size_t)N);
  if (!wr || !wi) {
    free(wr);
    free(wi);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  memcpy(w->A2, w->A, sizeof(double) * (size_t)N * (size_t)N);
  int bad = rr_eig_small(N, w->A2, wr, wi);
  double remax = -INFINITY, fr = 0;
  for (int i = 0; i < N && !bad; i++)
    if (wr[i] > remax) {
      remax = wr[i];
      fr = fabs(wi[i]) / (2 * RR_PI);
    }
  free(wr);
  free(wi);
  if (bad || remax <= 0) return RR_OK;
  return rr_seterr(err, RR_EINVAL,
                   "validate: the vehicle is unstable at %g km/h, conicity %g (eigenvalue "
                   "%.4g%+.4gi, %.3g Hz): no steady state to compare",
                   m->speed * RR_KMH, m->conicity, remax, 2 * RR_PI * fr, fr);
}

/* The outputs y = C z + D u + E u':
   a = rows . (A z + Bs u)[accelerations] + rows0 . q;
   a' = rows . (A^2 z + A Bs u + Bs u')[accelerations] + rows0 . q' */
static void output_rows(const rr_validate_opts *o, vwork *w)
{
  int n = w->n, N = w->N, ni = w->ni, np = w->np;
  cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, N, N, N, 1.0, w->A, N, w->A, N, 0.0, w->A2,
              N);
  cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, N, ni, N, 1.0, w->A, N, w->Bs, ni, 0.0,
              w->ABs, ni);
  for (int q = 0; q < np; q++) {
    const double *row = o->rows + (size_t)q * (size_t)n,
                 *row0 = o->rows0 ? o->rows0 + (size_t)q * (size_t)n : NULL;
    for (int k = 0; k < n; k++) {
      if (row[k] == 0) continue;
      for (int j = 0; j < N; j++) {
        w->C[q * N + j] += row[k] * w->A[(n + k) * N + j];
        w->C[(np + q) * N + j] += row[k] * w->A2[(n + k) * N + j];
      }
      for (int j = 0; j < ni; j++) {
        w->D[q * ni + j] += row[k] * w->Bs[(n + k) * ni + j];
        w->D[(np + q) * ni + j] += row[k] * w->ABs[(n + k) * ni + j];
        w->E[(np + q) * ni + j] += row[k] * w->Bs[(n + k) * ni + j];
      }
    }
    for (int k = 0; k < n && row0; k++) {
      w->C[q * N + k] += row0[k];
      w->C[(np + q) * N + n + k] += row0[k];
    }
  }
}

/* The track realisation, the vehicle's periodic steady state over it, the
   Sperling filter discretised, and the PEM on its standard grid. */
static int time_run(const rr_model *m, const rr_spectrum *sp, const rr_validate_opts *o, vwork *w,
                    rr_validate_result *r, rr_error *err)
{
  double xin[RR_SYS_MAX_INPUTS];
  for (int i = 0; i < w->ni; i++) xin[i] = m->contacts[i].x;
  rr_track_realisation tr = {.speed_ms = m->speed,
                             .x_inputs = xin,
                             .ninputs = w->ni,
                             .fs_hz = o->fs_hz,
                             .nsamples = w->ns,
                             .f_lo_hz = o->f_lo_hz,
                             .f_hi_hz = o->f_hi_hz,
                             .amplitudes = o->amplitudes,
                             .seed = o->seed};
  int st = rr_track_realise(sp, &tr, w->u, w->du, err);
  if (st || (st = rr_progress_step(&o->progress, ++w->step, w->nsteps, err))) return st;
  if ((st = rr_lti_discretise(w->N, w->ni, w->A, w->Bs, w->dt, &w->dv, err))) return st;
  st = rr_lti_periodic(&w->dv, w->ns, w->u, w->du, w->ny, w->C, w->D, w->E, w->y, err);
  if (st || (st = rr_progress_step(&o->progress, ++w->step, w->nsteps, err))) return st;
  r->seconds_simulated = 2 * w->ns * w->dt; /* two passes over the period */
  rr_sperling_filter_ss(RR_AXIS_LATERAL, w->fA, w->fB, w->fC);
  if ((st = rr_lti_discretise(3, 1, w->fA, w->fB, w->dt, &w->dfl, err))) return st;
  for (int k = 0; k < o->nfreq; k++)
    w->fp[k] = o->f_lo_hz * pow(o->f_hi_hz / o->f_lo_hz, (double)k / (o->nfreq - 1));
  return pem_on(m, sp, o, o->nfreq, w->fp, w->Gp, err);
}

/* Point q's indices from the time run (RMS, Sperling by filtering), from the
   PEM and from the Welch PSD of the run (within the band). */
static int point_indices(const rr_validate_opts *o, vwork *w, rr_validate_result *r, int q,
                         rr_error *err)
{
  rr_validate_point *pt = &r->points[q];
  int ns = w->ns, np = w->np, nh = w->nh;
  const double *a = w->y + (size_t)q * (size_t)ns, *ad = w->y + (size_t)(np + q) * (size_t)ns,
               zero = 0;
  double ss = 0;
  for (int k = 0; k < ns; k++) ss += a[k] * a[k];
  pt->rms_time = sqrt(ss / ns);
  int st = rr_lti_periodic(&w->dfl, ns, a, ad, 1, w->fC, &zero, NULL, w->aw, err);
  if (st) return st;
  ss = 0;
  for (int k = 0; k < ns; k++) ss += w->aw[k] * w->aw[k];
  pt->sperling_time = rr_sperling_from_weighted_rms(sqrt(ss / ns));
  const double *G = w->Gp + q;
  pt->rms_pem = rr_psd_rms(w->fp, G, o->nfreq, np);
  if ((st = rr_sperling_filter_index(w->fp, G, o->nfreq, np, RR_AXIS_LATERAL, &pt->sperling_pem,
                                     err)) ||
      (st = rr_sperling_gb_index(w->fp, G, o->nfreq, np, RR_AXIS_LATERAL, &pt->sperling_gb_pem,
                                 err)) ||
      (st = rr_weighted_rms(w->fp, G, o->nfreq, np, RR_ISO_WD, &pt->wd_rms_pem, err)))
    return st;
  double *P = r->welch_P + (size_t)q * (size_t)nh;
  if ((st = rr_welch_psd(a, ns, o->fs_hz, o->nseg, r->welch_f, P, &r->navg, err))) return st;
  for (int k = 0; k < nh && w->kb0 < 0; k++) /* the first point: the bins inside the band */
    if (r->welch_f[k] >= o->f_lo_hz && r->welch_f[k] <= o->f_hi_hz) {
      w->kb0 = k;
      for (w->kb1 = k; w->kb1 + 1 < nh && r->welch_f[w->kb1 + 1] <= o->f_hi_hz; w->kb1++) {
      }
    }
  int kb0 = w->kb0, nb = w->kb1 - w->kb0 + 1;
  if (nb < 2) return rr_seterr(err, RR_EINVAL, "validate: Welch segment too short for the band");
  const double *fw = r->welch_f + kb0;
  if ((st = rr_sperling_filter_index(fw, P + kb0, nb, 1, RR_AXIS_LATERAL, &pt->sperling_welch,
                                     err)) ||
      (st = rr_sperling_gb_index(fw, P + kb0, nb, 1, RR_AXIS_LATERAL, &pt->sperling_gb_welch,
                                 err)) ||
      (st = rr_weighted_rms(fw, P + kb0, nb, 1, RR_ISO_WD, &pt->wd_rms_welch, err)))
    return st;
  return rr_progress_step(&o->progress, ++w->step, w->nsteps, err);
}

/* The realisation's expected mean squares on its lines (each line's power
   G / T, exponentially distributed for a Gaussian track: its variance the
   square of its mean) and the run's z-scores about them. */
static void line_statistics(const double *G, int stride, const double *fl, int nl, double T,
                            rr_validate_point *pt)
{
  double ms = 0, var = 0, msw = 0, varw = 0;
  for (int l = 0; l < nl; l++) {
    double P = G[(size_t)l * (size_t)stride] / T, B = rr_sperling_filter(fl[l], RR_AXIS_LATERAL);
    ms += P;
    var += P * P;
    msw += B * B * P;
    varw += (B * B * P) * (B * B * P);
  }
  pt->rms_lines = sqrt(ms);
  pt->rms_rel_std = 0.5 * sqrt(var) / ms; /* d(rms)/rms = d(ms)/(2 ms) */
  pt->rms_z = (pt->rms_time / pt->rms_lines - 1) / pt->rms_rel_std;
  pt->sperling_lines = rr_sperling_from_weighted_rms(sqrt(msw));
  pt->sperling_rel_std = 0.15 * sqrt(varw) / msw; /* W = 4.42 ms^0.15 */
  pt->sperling_z = (pt->sperling_time / pt->sperling_lines - 1) / pt->sperling_rel_std;
}

/* The Welch estimator's expectation under the PEM spectrum: each line of the
   realisation (f_l = l / T, power G_pem(f_l) / T) seen through the Hann
   window's spectral kernel |W(f_l - f_k)|^2 / (fs sum w^2). Comparing with
   this, not with the PEM at the bin centres, leaves only statistical scatter
   (no leakage bias from strong neighbours). */
static int welch_expectation(const rr_model *m, const rr_spectrum *sp, const rr_validate_opts *o,
                             const vwork *w, rr_validate_result *r, rr_error *err)
{
  int np = w->np, nh = w->nh;
  double T = w->ns * w->dt;
  int l0 = (int)ceil(o->f_lo_hz * T - 1e-9), l1 = (int)floor(o->f_hi_hz * T + 1e-9),
      nl = l1 - l0 + 1;
  double *fl = malloc(sizeof(double) * (size_t)nl),
         *Gl = malloc(sizeof(double) * (size_t)nl * (size_t)np);
  if (!fl || !Gl) {
    free(fl);
    free(Gl);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  for (int l = 0; l < nl; l++) fl[l] = (l0 + l) / T;
  int st = pem_on(m, sp, o, nl, fl, Gl, err);
  double wss = 0;
  for (int j = 0; j < o->nseg; j++) {
    double wj = 0.5 * (1 - cos(2 * RR_PI * j / o->nseg));
    wss += wj * wj;
  }
  for (int q = 0; q < np && !st; q++) line_statistics(Gl + q, np, fl, nl, T, &r->points[q]);
  double dfb = o->fs_hz / o->nseg;
  int reach = (int)ceil(32 * dfb * T); /* lines within 32 bins of a bin */
  for (int k = w->kb0; k <= w->kb1 && !st; k++) {
    double fk = r->welch_f[k];
    int lc = (int)lround(fk * T) - l0;
    for (int l = (lc - reach > 0 ? lc - reach : 0); l <= lc + reach && l < nl; l++) {
      double complex W = hann_dtft(2 * RR_PI * (fl[l] - fk) / o->fs_hz, o->nseg);
      double kern = creal(W * conj(W)) / (o->fs_hz * wss);
      for (int q = 0; q < np; q++)
        r->pem_P[(size_t)q * (size_t)nh + (size_t)k] += Gl[l * np + q] / T * kern;
    }
  }
  free(fl);
  free(Gl);
  return st;
}

/* 1/3-octave bands wholly inside the band; expected spread of a band from K
   Hann segments at 50% overlap (variance factor 1 + 2 c^2, c = 0.167) over M
   bins of which 1/1.5 are independent (Hann ENBW 1.5 bins):
   sigma = sqrt((1 + 2 c^2) / K * 1.5 / M), M >= 1.5 */
static void band_compare(const rr_validate_opts *o, const vwork *w, rr_validate_result *r, int q)
{
  double df = o->fs_hz / o->nseg;
  rr_validate_point *pt = &r->points[q];
  const double *P = r->welch_P + (size_t)q * (size_t)w->nh,
               *Q = r->pem_P + (size_t)q * (size_t)w->nh;
  pt->nbands = 0;
  for (int b = -20; b <= 20 && pt->nbands < RR_NBANDS_MAX; b++) {
    double fc = pow(10, b / 10.0), lo = fc * pow(10, -0.05), hi = fc * pow(10, 0.05);
    if (lo < o->f_lo_hz || hi > o->f_hi_hz) continue;
    double pt_time = 0, pt_pem = 0;
    int M = 0;
    for (int k = w->kb0; k <= w->kb1; k++)
      if (r->welch_f[k] >= lo && r->welch_f[k] < hi) {
        pt_time += P[k] * df;
        pt_pem += Q[k] * df;
        M++;
      }
    if (M == 0) continue;
    int i = pt->nbands++;
    pt->band_fc[i] = fc;
    pt->band_time[i] = pt_time;
    pt->band_pem[i] = pt_pem;
    pt->band_sigma[i] = r->bin_sigma * sqrt(1.5 / fmax(M, 1.5));
    double e = fabs(pt_time - pt_pem) / pt_pem;
    if (e > pt->band_error_max) pt->band_error_max = e;
    if (e / pt->band_sigma[i] > pt->band_z_max) pt->band_z_max = e / pt->band_sigma[i];
  }
}

int rr_validate(const rr_model *m, const rr_spectrum *sp, const rr_validate_opts *o,
                rr_validate_result *r, rr_error *err)
{
  memset(r, 0, sizeof *r);
  int ns = 0;
  int st = check_opts(m, o, &ns, err);
  if (st) return st;
  vwork w;
  st = work_alloc(&w, m, o, ns, r, err);
  if (!st) st = rr_model_state_matrix(m, 0, w.A, err);
  if (!st) st = rr_model_state_input(m, w.Bs, err);
  if (!st) st = check_stable(m, &w, err);
  if (!st) {
    output_rows(o, &w);
    st = time_run(m, sp, o, &w, r, err);
  }
  for (int q = 0; q < w.np && !st; q++) st = point_indices(o, &w, r, q, err);
  if (!st) st = welch_expectation(m, sp, o, &w, r, err);
  if (!st) st = rr_progress_step(&o->progress, ++w.step, w.nsteps, err);
  if (!st) {
    r->bin_sigma = sqrt((1 + 2 * 0.167 * 0.167) / r->navg);
    for (int q = 0; q < w.np; q++) band_compare(o, &w, r, q);
  }
  work_free(&w);
  if (!st) st = results_finite(r, err);
  if (st) rr_validate_result_free(r);
  return st;
}
