/* Validation of the frequency domain (PEM) against a time-domain run of the
 * same linear state space driven by a random track realisation. */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/comfort.h"
#include "railride/pem.h"
#include "railride/timesim.h"
#include "model_impl.h"
#include "hessenberg_qr.h"
#include "internal.h"

rr_validate_opts rr_validate_opts_default(void)
{
  rr_validate_opts o;
  memset(&o, 0, sizeof o);
  o.duration_s = 600;
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
  rr_frf_opts fo = {nf, f, o->f_lo_hz, o->f_hi_hz, o->npoints, o->rows, o->rows0, RR_FRF_MODAL};
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
                  p->wd_rms_welch,   p->band_error_max,  p->band_z_max};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
      if (!isfinite(v[i]))
        return rr_seterr(err, RR_ENOCONV, "validate: a result at point %d is not finite", q + 1);
  }
  for (int i = 0; i < r->nwelch * r->npoints; i++)
    if (!isfinite(r->welch_P[i]) || !isfinite(r->pem_P[i]))
      return rr_seterr(err, RR_ENOCONV, "validate: a PSD is not finite");
  return RR_OK;
}

int rr_validate(const rr_model *m, const rr_spectrum *sp, const rr_validate_opts *o,
                rr_validate_result *r, rr_error *err)
{
  memset(r, 0, sizeof *r);
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
  int n = m->n, ni = m->ni, np = o->npoints, N = rr_model_state_size(m);
  int ns = (int)lround(o->duration_s * o->fs_hz);
  ns += ns % 2;
  if (o->nseg > ns)
    return rr_seterr(err, RR_EINVAL,
                     "validate: Welch segment (%d) longer than the record (%d samples)", o->nseg,
                     ns);
  double dt = 1.0 / o->fs_hz;
  int st = RR_OK, ny = 2 * np, nh = o->nseg / 2 + 1;
  double *A = malloc(sizeof(double) * N * N), *A2 = malloc(sizeof(double) * N * N),
         *Bs = malloc(sizeof(double) * N * ni);
  double *ABs = malloc(sizeof(double) * N * ni);
  double *u = malloc(sizeof(double) * ni * (size_t)ns),
         *du = malloc(sizeof(double) * ni * (size_t)ns);
  double *y = malloc(sizeof(double) * ny * (size_t)ns), *aw = malloc(sizeof(double) * (size_t)ns);
  double *C = calloc((size_t)ny * N, sizeof(double)), *D = calloc((size_t)ny * ni, sizeof(double)),
         *E = calloc((size_t)ny * ni, sizeof(double));
  double *Gp = malloc(sizeof(double) * o->nfreq * np), *fp = malloc(sizeof(double) * o->nfreq);
  rr_lti_disc dv = {0}, dfl = {0};
  r->npoints = np;
  r->nwelch = nh;
  r->welch_f = malloc(sizeof(double) * nh);
  r->welch_P = malloc(sizeof(double) * nh * np);
  r->pem_P = calloc((size_t)nh * np, sizeof(double));
  r->points = calloc(np, sizeof(rr_validate_point));
  if (!A || !A2 || !Bs || !ABs || !u || !du || !y || !aw || !C || !D || !E || !Gp || !fp ||
      !r->welch_f || !r->welch_P || !r->pem_P || !r->points) {
    st = rr_seterr(err, RR_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = rr_model_state_matrix(m, 0, A, err)) || (st = rr_model_state_input(m, Bs, err)))
    goto done;
  {
    /* an unstable vehicle has no steady state: neither the time run nor the
       PEM describe anything then */
    double *wr = malloc(sizeof(double) * N), *wi = malloc(sizeof(double) * N);
    if (!wr || !wi) {
      free(wr);
      free(wi);
      st = rr_seterr(err, RR_ENOMEM, "out of memory");
      goto done;
    }
    memcpy(A2, A, sizeof(double) * N * N);
    int bad = rr_eig_small(N, A2, wr, wi);
    double remax = -INFINITY, fr = 0;
    for (int i = 0; i < N && !bad; i++)
      if (wr[i] > remax) {
        remax = wr[i];
        fr = fabs(wi[i]) / (2 * RR_PI);
      }
    free(wr);
    free(wi);
    if (!bad && remax > 0) {
      st = rr_seterr(err, RR_EINVAL,
                     "validate: the vehicle is unstable at %g km/h, conicity %g (eigenvalue "
                     "%.4g%+.4gi, %.3g Hz): "
                     "no steady state to compare",
                     m->speed * RR_KMH, m->conicity, remax, 2 * RR_PI * fr, fr);
      goto done;
    }
  }
  cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, N, N, N, 1.0, A, N, A, N, 0.0, A2, N);
  cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, N, ni, N, 1.0, A, N, Bs, ni, 0.0, ABs, ni);
  /* a = rows . (A z + Bs u)[accelerations] + rows0 . q;
     a' = rows . (A^2 z + A Bs u + Bs u')[accelerations] + rows0 . q' */
  for (int q = 0; q < np; q++) {
    const double *row = o->rows + (size_t)q * n, *row0 = o->rows0 ? o->rows0 + (size_t)q * n : NULL;
    for (int k = 0; k < n; k++) {
      if (row[k] == 0) continue;
      for (int j = 0; j < N; j++) {
        C[q * N + j] += row[k] * A[(n + k) * N + j];
        C[(np + q) * N + j] += row[k] * A2[(n + k) * N + j];
      }
      for (int j = 0; j < ni; j++) {
        D[q * ni + j] += row[k] * Bs[(n + k) * ni + j];
        D[(np + q) * ni + j] += row[k] * ABs[(n + k) * ni + j];
        E[(np + q) * ni + j] += row[k] * Bs[(n + k) * ni + j];
      }
    }
    if (row0)
      for (int k = 0; k < n; k++) {
        C[q * N + k] += row0[k];
        C[(np + q) * N + n + k] += row0[k];
      }
  }
  double xin[RR_SYS_MAX_INPUTS];
  for (int i = 0; i < ni; i++) xin[i] = m->contacts[i].x;
  long step = 0, nsteps = 3 + np;
  if ((st = rr_track_realise(sp, m->speed, xin, ni, o->fs_hz, ns, o->f_lo_hz, o->f_hi_hz, o->seed,
                             u, du, err)))
    goto done;
  if ((st = rr_progress_step(&o->progress, ++step, nsteps, err))) goto done;
  if ((st = rr_lti_discretise(N, ni, A, Bs, dt, &dv, err))) goto done;
  if ((st = rr_lti_periodic(&dv, ns, u, du, ny, C, D, E, y, err))) goto done;
  if ((st = rr_progress_step(&o->progress, ++step, nsteps, err))) goto done;
  r->seconds_simulated = 2 * ns * dt; /* two passes over the period */
  /* the Sperling weighting as a filter in the time domain */
  double fA[9], fB[3], fC[3], zero = 0;
  rr_sperling_filter_ss(RR_AXIS_LATERAL, fA, fB, fC);
  if ((st = rr_lti_discretise(3, 1, fA, fB, dt, &dfl, err))) goto done;
  /* PEM on its standard grid */
  for (int k = 0; k < o->nfreq; k++)
    fp[k] = o->f_lo_hz * pow(o->f_hi_hz / o->f_lo_hz, (double)k / (o->nfreq - 1));
  if ((st = pem_on(m, sp, o, o->nfreq, fp, Gp, err))) goto done;
  /* Welch, and the PEM at the Welch bins inside the band */
  int kb0 = -1, kb1 = -1;
  for (int q = 0; q < np && !st; q++) {
    rr_validate_point *pt = &r->points[q];
    const double *a = y + (size_t)q * ns, *ad = y + (size_t)(np + q) * ns;
    double ss = 0;
    for (int k = 0; k < ns; k++) ss += a[k] * a[k];
    pt->rms_time = sqrt(ss / ns);
    if ((st = rr_lti_periodic(&dfl, ns, a, ad, 1, fC, &zero, NULL, aw, err))) break;
    ss = 0;
    for (int k = 0; k < ns; k++) ss += aw[k] * aw[k];
    pt->sperling_time = rr_sperling_from_weighted_rms(sqrt(ss / ns));
    pt->rms_pem = rr_psd_rms(fp, Gp + q, o->nfreq, np);
    rr_sperling_filter_index(fp, Gp + q, o->nfreq, np, RR_AXIS_LATERAL, &pt->sperling_pem, err);
    rr_sperling_gb_index(fp, Gp + q, o->nfreq, np, RR_AXIS_LATERAL, &pt->sperling_gb_pem, err);
    rr_weighted_rms(fp, Gp + q, o->nfreq, np, RR_ISO_WD, &pt->wd_rms_pem, err);
    double *P = r->welch_P + (size_t)q * nh;
    if ((st = rr_welch_psd(a, ns, o->fs_hz, o->nseg, r->welch_f, P, &r->navg, err))) break;
    if (kb0 < 0) {
      for (int k = 0; k < nh; k++)
        if (r->welch_f[k] >= o->f_lo_hz && r->welch_f[k] <= o->f_hi_hz) {
          if (kb0 < 0) kb0 = k;
          kb1 = k;
        }
    }
    int nb = kb1 - kb0 + 1;
    if (nb < 2) {
      st = rr_seterr(err, RR_EINVAL, "validate: Welch segment too short for the band");
      break;
    }
    rr_sperling_filter_index(r->welch_f + kb0, P + kb0, nb, 1, RR_AXIS_LATERAL, &pt->sperling_welch,
                             err);
    rr_sperling_gb_index(r->welch_f + kb0, P + kb0, nb, 1, RR_AXIS_LATERAL, &pt->sperling_gb_welch,
                         err);
    rr_weighted_rms(r->welch_f + kb0, P + kb0, nb, 1, RR_ISO_WD, &pt->wd_rms_welch, err);
    st = rr_progress_step(&o->progress, ++step, nsteps, err);
  }
  if (st) goto done;
  {
    /* The Welch estimator's expectation under the PEM spectrum: each line of
       the realisation (f_l = l / T, power G_pem(f_l) / T) seen through the Hann
       window's spectral kernel |W(f_l - f_k)|^2 / (fs sum w^2). Comparing
       with this, not with the PEM at the bin centres, leaves only statistical
       scatter (no leakage bias from strong neighbours). */
    double T = ns * dt;
    int l0 = (int)ceil(o->f_lo_hz * T - 1e-9), l1 = (int)floor(o->f_hi_hz * T + 1e-9),
        nl = l1 - l0 + 1;
    double *fl = malloc(sizeof(double) * nl), *Gl = malloc(sizeof(double) * nl * np);
    if (!fl || !Gl) {
      free(fl);
      free(Gl);
      st = rr_seterr(err, RR_ENOMEM, "out of memory");
      goto done;
    }
    for (int l = 0; l < nl; l++) fl[l] = (l0 + l) / T;
    st = pem_on(m, sp, o, nl, fl, Gl, err);
    double wss = 0;
    for (int j = 0; j < o->nseg; j++) {
      double wj = 0.5 * (1 - cos(2 * RR_PI * j / o->nseg));
      wss += wj * wj;
    }
    double dfb = o->fs_hz / o->nseg;
    int reach = (int)ceil(32 * dfb * T); /* lines within 32 bins of a bin */
    for (int k = kb0; k <= kb1 && !st; k++) {
      double fk = r->welch_f[k];
      int lc = (int)lround(fk * T) - l0;
      for (int l = (lc - reach > 0 ? lc - reach : 0); l <= lc + reach && l < nl; l++) {
        double complex W = hann_dtft(2 * RR_PI * (fl[l] - fk) / o->fs_hz, o->nseg);
        double kern = creal(W * conj(W)) / (o->fs_hz * wss);
        for (int q = 0; q < np; q++) r->pem_P[(size_t)q * nh + k] += Gl[l * np + q] / T * kern;
      }
    }
    free(fl);
    free(Gl);
    if (st || (st = rr_progress_step(&o->progress, ++step, nsteps, err))) goto done;
  }
  /* 1/3-octave bands wholly inside the band; expected spread of a band from
     K Hann segments at 50% overlap (variance factor 1 + 2 c^2, c = 0.167)
     over M bins of which 1/1.5 are independent (Hann ENBW 1.5 bins):
     sigma = sqrt((1 + 2 c^2) / K * 1.5 / M), M >= 1.5 */
  double df = o->fs_hz / o->nseg;
  r->bin_sigma = sqrt((1 + 2 * 0.167 * 0.167) / r->navg);
  for (int q = 0; q < np; q++) {
    rr_validate_point *pt = &r->points[q];
    const double *P = r->welch_P + (size_t)q * nh, *Q = r->pem_P + (size_t)q * nh;
    pt->nbands = 0;
    for (int b = -20; b <= 20 && pt->nbands < RR_NBANDS_MAX; b++) {
      double fc = pow(10, b / 10.0), lo = fc * pow(10, -0.05), hi = fc * pow(10, 0.05);
      if (lo < o->f_lo_hz || hi > o->f_hi_hz) continue;
      double pt_time = 0, pt_pem = 0;
      int M = 0;
      for (int k = kb0; k <= kb1; k++)
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
done:
  free(A);
  free(A2);
  free(Bs);
  free(ABs);
  free(u);
  free(du);
  free(y);
  free(aw);
  free(C);
  free(D);
  free(E);
  free(Gp);
  free(fp);
  rr_lti_disc_free(&dv);
  rr_lti_disc_free(&dfl);
  if (!st) st = results_finite(r, err);
  if (st) rr_validate_result_free(r);
  return st;
}
