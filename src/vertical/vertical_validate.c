/* The vertical PEM against a time-domain run (docs/vertical.md,
 * "Validation"), independent of the PEM's code path: the state
 * x = [q; q' - M^-1 BC z] (so that the profile's rate enters only the output),
 * its exact discretisation for a cubic Hermite hold of the profile, the
 * periodic steady state over a periodic Gaussian realisation, and the
 * record's lines, 5 s windows and Welch PSD against the PEM. */
#define _DEFAULT_SOURCE /* lgamma_r */
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/pem.h"
#include "util/internal.h"
#include "vertical/vertical_impl.h"

#define NST (2 * RR_VDOF)
#define P95 0.95

rr_vertical_validate_opts rr_vertical_validate_opts_default(void)
{
  return (rr_vertical_validate_opts){.duration_s = RR_VALIDATE_DURATION_S,
                                     .fs_hz = 256,
                                     .nseg = 4096,
                                     .seed = 1,
                                     .amplitudes = RR_TRACK_GAUSSIAN,
                                     .window_s = RR_VERTICAL_WINDOW_DEFAULT};
}

void rr_vertical_validate_result_free(rr_vertical_validate_result *r)
{
  if (!r) return;
  free(r->welch_f);
  free(r->welch_P);
  free(r->pem_P);
  r->welch_f = r->welch_P = r->pem_P = NULL;
}

/* x' = A x + B z; MBC = M^-1 BC */
static void state_space(const rr_vertical_model *m, double *A, double *B, double *MBC)
{
  rr_vertical_state_matrix(m, A);
  for (int i = 0; i < RR_VDOF; i++)
    for (int j = 0; j < RR_VINPUTS; j++)
      MBC[i * RR_VINPUTS + j] = m->BC[i * RR_VINPUTS + j] / m->M[i];
  for (int i = 0; i < RR_VDOF; i++)
    for (int j = 0; j < RR_VINPUTS; j++) {
      double cmb = 0;
      for (int l = 0; l < RR_VDOF; l++) cmb += m->C[i * RR_VDOF + l] * MBC[l * RR_VINPUTS + j];
      B[i * RR_VINPUTS + j] = MBC[i * RR_VINPUTS + j];
      B[(RR_VDOF + i) * RR_VINPUTS + j] = (m->BK[i * RR_VINPUTS + j] - cmb) / m->M[i];
    }
}

/* floor acceleration a = rows q'' = C x + D z + E z' */
static void output_rows(const double *rows, int np, const double *A, const double *B,
                        const double *MBC, double *C, double *D, double *E)
{
  memset(C, 0, sizeof(double) * (size_t)np * NST);
  memset(D, 0, sizeof(double) * (size_t)np * RR_VINPUTS);
  memset(E, 0, sizeof(double) * (size_t)np * RR_VINPUTS);
  for (int p = 0; p < np; p++)
    for (int i = 0; i < RR_VDOF; i++) {
      double r = rows[p * RR_VDOF + i];
      for (int j = 0; j < NST; j++) C[p * NST + j] += r * A[(RR_VDOF + i) * NST + j];
      for (int j = 0; j < RR_VINPUTS; j++) {
        D[p * RR_VINPUTS + j] += r * B[(RR_VDOF + i) * RR_VINPUTS + j];
        E[p * RR_VINPUTS + j] += r * MBC[i * RR_VINPUTS + j];
      }
    }
}

/* The run's buffers, freed together. */
typedef struct vrun {
  int ns, np, nl;
  double T;
  double *u, *du, *y, *yw; /* inputs (4 x ns), outputs (np x ns), a weighted record */
  double *win;             /* the 5 s windows' RMS */
  fftw_complex *U, *Y;     /* the leading input's and one output's spectra */
  double *fl;              /* the realisation's lines in the band */
  int *kl;                 /* their FFT bins */
  fftw_plan fwd_u, fwd_y, inv;
  rr_lti_disc d;
} vrun;

static void run_free(vrun *w)
{
  free(w->u);
  free(w->du);
  free(w->y);
  free(w->win);
  fftw_free(w->yw);
  fftw_free(w->U);
  fftw_free(w->Y);
  free(w->fl);
  free(w->kl);
  if (w->fwd_u) fftw_destroy_plan(w->fwd_u);
  if (w->fwd_y) fftw_destroy_plan(w->fwd_y);
  if (w->inv) fftw_destroy_plan(w->inv);
  rr_lti_disc_free(&w->d);
}

static int run_alloc(vrun *w, int ns, int np, double fs, rr_error *err)
{
  size_t n = (size_t)ns, nh = n / 2 + 1;
  *w = (vrun){.ns = ns, .np = np, .T = ns / fs};
  w->u = malloc(sizeof(double) * n * RR_VINPUTS);
  w->du = malloc(sizeof(double) * n * RR_VINPUTS);
  w->y = malloc(sizeof(double) * n * (size_t)np);
  w->win = malloc(sizeof(double) * n);
  w->yw = fftw_malloc(sizeof(double) * n);
  w->U = fftw_malloc(sizeof(fftw_complex) * nh);
  w->Y = fftw_malloc(sizeof(fftw_complex) * nh);
  w->fl = malloc(sizeof(double) * nh);
  w->kl = malloc(sizeof(int) * nh);
  if (!w->u || !w->du || !w->y || !w->win || !w->yw || !w->U || !w->Y || !w->fl || !w->kl)
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  w->fwd_u = fftw_plan_dft_r2c_1d(ns, w->u, w->U, FFTW_ESTIMATE);
  w->fwd_y = fftw_plan_dft_r2c_1d(ns, w->yw, w->Y, FFTW_ESTIMATE);
  w->inv = fftw_plan_dft_c2r_1d(ns, w->Y, w->yw, FFTW_ESTIMATE);
  if (!w->fwd_u || !w->fwd_y || !w->inv) return rr_seterr(err, RR_ENOMEM, "fftw plan failed");
  return RR_OK;
}

/* The realisation, the 14-state run, the leading input's spectrum and the
   lines with content. */
static int time_run(const rr_vertical_model *m, double v, const rr_spectrum *sp,
                    const rr_vertical_validate_opts *o, const double *rows, vrun *w, rr_error *err)
{
  double A[NST * NST], B[NST * RR_VINPUTS], MBC[RR_VDOF * RR_VINPUTS];
  double C[RR_VERTICAL_POINTS_MAX * NST], D[RR_VERTICAL_POINTS_MAX * RR_VINPUTS],
      E[RR_VERTICAL_POINTS_MAX * RR_VINPUTS];
  state_space(m, A, B, MBC);
  output_rows(rows, w->np, A, B, MBC, C, D, E);
  rr_track_realisation tr = {.speed_ms = v,
                             .x_inputs = m->x_wheelsets,
                             .ninputs = RR_VINPUTS,
                             .fs_hz = o->fs_hz,
                             .nsamples = w->ns,
                             .f_lo_hz = RR_FRF_F_LO_DEFAULT,
                             .f_hi_hz = RR_FRF_F_HI_DEFAULT,
                             .amplitudes = o->amplitudes,
                             .seed = o->seed};
  int st = rr_track_realise(sp, &tr, w->u, w->du, err);
  if (!st) st = rr_lti_discretise(NST, RR_VINPUTS, A, B, 1 / o->fs_hz, &w->d, err);
  if (!st) st = rr_lti_periodic(&w->d, w->ns, w->u, w->du, w->np, C, D, E, w->y, err);
  if (st) return st;
  fftw_execute(w->fwd_u); /* the leading wheelset's profile: row 0 of u */
  w->nl = 0;
  for (int k = 1; 2 * k < w->ns; k++) {
    double f = k / w->T;
    if (f >= RR_FRF_F_LO_DEFAULT * (1 - 1e-12) && f <= RR_FRF_F_HI_DEFAULT * (1 + 1e-12) &&
        hypot(w->U[k][0], w->U[k][1]) > 0) {
      w->fl[w->nl] = f;
      w->kl[w->nl++] = k;
    }
  }
  return w->nl >= 2 ? RR_OK : rr_seterr(err, RR_EINVAL, "validate: too short for the band");
}

/* A plan on the given grid (no window), executed: its G and H. */
static int pem_lines(const rr_vertical_model *m, double v, const rr_spectrum *sp, const double *x,
                     int np, const double *f, int n, rr_vertical_plan **pl, rr_error *err)
{
  rr_vertical_opts vo = rr_vertical_opts_default();
  vo.nfreq = n;
  vo.freqs_hz = f;
  vo.window_s = 0;
  vo.npoints = np;
  memcpy(vo.x_points, x, sizeof(double) * (size_t)np);
  rr_vertical_point pts[RR_VERTICAL_POINTS_MAX];
  int st = rr_vertical_plan_new(&vo, pl, err);
  if (!st) st = rr_vertical_ride_execute(*pl, m, v, sp, pts, err);
  return st;
}

/* the sample quantile with linear interpolation (numpy's default) of sorted a */
static double quantile(const double *a, int n, double p)
{
  double pos = p * (n - 1);
  int i = (int)floor(pos);
  return i + 1 < n ? a[i] + (pos - i) * (a[i + 1] - a[i]) : a[n - 1];
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The record's 5 s Wb RMS percentiles (the weighting applied to its lines),
   and the z-score of its P95 against the gamma law's (the sample quantile's
   spread sqrt(p (1 - p) / n) / pdf). */
static void windows_of(vrun *w, const rr_vertical_point *est, double fs, double Tw,
                       rr_vertical_validate_point *pt)
{
  int ns = w->ns, nw = (int)(ns / (Tw * fs)), len = (int)lround(Tw * fs);
  int k0 = w->kl[0], k1 = w->kl[w->nl - 1];
  for (int k = 0; k <= ns / 2; k++) {
    rr_complex h = k >= k0 && k <= k1 ? rr_iso8041_weight(RR_EN_WB, k / w->T) : 0;
    double re = w->Y[k][0], im = w->Y[k][1];
    w->Y[k][0] = (creal(h) * re - cimag(h) * im) / ns;
    w->Y[k][1] = (creal(h) * im + cimag(h) * re) / ns;
  }
  fftw_execute(w->inv);
  double *r = w->win;
  for (int i = 0; i < nw; i++) {
    double s = 0;
    for (int j = 0; j < len; j++) s += w->yw[i * len + j] * w->yw[i * len + j];
    r[i] = sqrt(s / len);
  }
  qsort(r, (size_t)nw, sizeof(double), cmp_double);
  pt->windows = nw;
  pt->wb_p50_time = quantile(r, nw, 0.5);
  pt->wb_p95_time = quantile(r, nw, P95);
  pt->wb_p50_est = est->wb_5s.p50;
  pt->wb_p95_est = est->wb_5s.p95;
  double k = est->wb_5s.shape_k, th = est->wb_5s.rms * est->wb_5s.rms / k, q = est->wb_5s.p95;
  int sg;
  double pdf_m = exp((k - 1) * log(q * q) - q * q / th - lgamma_r(k, &sg) - k * log(th));
  pt->wb_p95_z = (pt->wb_p95_time - q) / (sqrt(P95 * (1 - P95) / nw) / (2 * q * pdf_m));
}

/* Lines: FRF error, RMS, Sperling, bands. G, H: the PEM at the lines. */
static void line_checks(vrun *w, int q, const double *G, const rr_complex *H, int np,
                        rr_vertical_validate_point *pt)
{
  double hmax = 0, err = 0, ms = 0, var = 0, msw = 0, varw = 0, mst = 0, mswt = 0;
  double N2 = (double)w->ns * w->ns;
  for (int l = 0; l < w->nl; l++) hmax = fmax(hmax, cabs(H[(size_t)l * (size_t)np + (size_t)q]));
  for (int b = 0; b < RR_VERTICAL_BANDS; b++)
    pt->band_pem[b] = pt->band_time[b] = pt->band_rel_std[b] = 0;
  for (int l = 0; l < w->nl; l++) {
    int k = w->kl[l];
    rr_complex Yk = w->Y[k][0] + I * w->Y[k][1], Uk = w->U[k][0] + I * w->U[k][1];
    err = fmax(err, cabs(Yk / Uk - H[(size_t)l * (size_t)np + (size_t)q]) / hmax);
    double P = G[(size_t)l * (size_t)np + (size_t)q] / w->T, p = 2 * creal(Yk * conj(Yk)) / N2;
    double B = rr_sperling_filter(w->fl[l], RR_AXIS_VERTICAL), B2 = B * B;
    ms += P, var += P * P, mst += p;
    msw += B2 * P, varw += B2 * P * B2 * P, mswt += B2 * p;
    for (int b = 0; b < RR_VERTICAL_BANDS; b++) {
      double fc = pow(10, (b - 3) / 10.0);
      if (w->fl[l] >= fc * pow(10, -0.05) && w->fl[l] < fc * pow(10, 0.05)) {
        pt->band_pem[b] += P;
        pt->band_time[b] += p;
        pt->band_rel_std[b] += P * P;
      }
    }
  }
  pt->frf_line_error_max = err;
  pt->rms_lines = sqrt(ms);
  pt->rms_rel_std = 0.5 * sqrt(var) / ms;
  pt->rms_z = (pt->rms_time / pt->rms_lines - 1) / pt->rms_rel_std;
  pt->sperling_lines = rr_sperling_from_weighted_rms(sqrt(msw));
  pt->sperling_time = rr_sperling_from_weighted_rms(sqrt(mswt));
  pt->sperling_rel_std = 0.15 * sqrt(varw) / msw; /* W = 4.42 ms^0.15 */
  pt->sperling_z = (pt->sperling_time / pt->sperling_lines - 1) / pt->sperling_rel_std;
  pt->band_z_max = pt->band_error_max = 0;
  for (int b = 0; b < RR_VERTICAL_BANDS; b++) {
    pt->band_fc[b] = pow(10, (b - 3) / 10.0);
    pt->band_rel_std[b] = sqrt(pt->band_rel_std[b]) / pt->band_pem[b];
    pt->band_z[b] = (pt->band_time[b] / pt->band_pem[b] - 1) / pt->band_rel_std[b];
    pt->band_z_max = fmax(pt->band_z_max, fabs(pt->band_z[b]));
    pt->band_error_max = fmax(pt->band_error_max, fabs(pt->band_time[b] / pt->band_pem[b] - 1));
  }
}

/* The Welch PSD of each point and the PEM at its bins inside the band. */
static int welch_of(const rr_vertical_model *m, double v, const rr_spectrum *sp,
                    const rr_vertical_validate_opts *o, const double *x, vrun *w,
                    rr_vertical_validate_result *r, rr_error *err)
{
  int nh = o->nseg / 2 + 1, np = w->np, st = RR_OK;
  r->nwelch = nh;
  r->welch_f = malloc(sizeof(double) * (size_t)nh);
  r->welch_P = malloc(sizeof(double) * (size_t)nh * (size_t)np);
  r->pem_P = calloc((size_t)nh * (size_t)np, sizeof(double));
  if (!r->welch_f || !r->welch_P || !r->pem_P) return rr_seterr(err, RR_ENOMEM, "out of memory");
  for (int q = 0; q < np && !st; q++)
    st = rr_welch_psd(w->y + (size_t)q * (size_t)w->ns, w->ns, o->fs_hz, o->nseg, r->welch_f,
                      r->welch_P + (size_t)q * (size_t)nh, &r->navg, err);
  int k0 = 0, k1 = nh - 1;
  while (k0 < nh && r->welch_f[k0] < RR_FRF_F_LO_DEFAULT) k0++;
  while (k1 >= 0 && r->welch_f[k1] > RR_FRF_F_HI_DEFAULT) k1--;
  if (st || k1 - k0 < 1)
    return st ? st : rr_seterr(err, RR_EINVAL, "validate: Welch segment too short");
  rr_vertical_plan *pl = NULL;
  st = pem_lines(m, v, sp, x, np, r->welch_f + k0, k1 - k0 + 1, &pl, err);
  for (int k = k0; k <= k1 && !st; k++)
    for (int q = 0; q < np; q++)
      r->pem_P[(size_t)q * (size_t)nh + (size_t)k] =
          rr_vertical_psd(pl)[(size_t)(k - k0) * (size_t)np + (size_t)q];
  rr_vertical_plan_free(pl);
  double df = o->fs_hz / o->nseg; /* each point's Welch power in the bands */
  for (int q = 0; q < np && !st; q++) {
    rr_vertical_validate_point *pt = &r->points[q];
    pt->band_welch_error_max = 0;
    for (int b = 0; b < RR_VERTICAL_BANDS; b++) {
      double fc = pt->band_fc[b], lo = fc * pow(10, -0.05), hi = fc * pow(10, 0.05), s = 0;
      for (int k = 0; k < nh; k++)
        if (r->welch_f[k] >= lo && r->welch_f[k] < hi)
          s += r->welch_P[(size_t)q * (size_t)nh + (size_t)k] * df;
      pt->band_welch[b] = s;
      pt->band_welch_error_max = fmax(pt->band_welch_error_max, fabs(s / pt->band_pem[b] - 1));
    }
  }
  return st;
}

static int check_validate_opts(const rr_vertical_validate_opts *o, int *ns, rr_error *err)
{
  if (!(o->duration_s >= 10 && o->duration_s <= 1e5 && o->fs_hz > 2 * RR_FRF_F_HI_DEFAULT &&
        o->fs_hz <= 1e5 && o->window_s > 0 && o->window_s <= o->duration_s && o->npoints >= 0 &&
        o->npoints <= RR_VERTICAL_POINTS_MAX))
    return rr_seterr(err, RR_EINVAL,
                     "validate: need a duration of 10 s or more, fs above twice 30 Hz, a window "
                     "within the record and at most %d points",
                     RR_VERTICAL_POINTS_MAX);
  *ns = (int)lround(o->duration_s * o->fs_hz);
  *ns += *ns % 2;
  if (o->nseg < 8 || o->nseg % 2 || o->nseg > *ns)
    return rr_seterr(err, RR_EINVAL, "validate: Welch segment %d (need even, 8 .. %d samples)",
                     o->nseg, *ns);
  return RR_OK;
}

int rr_vertical_validate(const rr_vertical_model *m, double v, const rr_spectrum *sp,
                         const rr_vertical_validate_opts *o, rr_vertical_validate_result *r,
                         rr_error *err)
{
  memset(r, 0, sizeof *r);
  int ns = 0, st = check_validate_opts(o, &ns, err);
  if (st) return st;
  /* the PEM on its standard grid (with the window): the estimates */
  rr_vertical_opts vo = rr_vertical_opts_default();
  vo.window_s = o->window_s;
  vo.npoints = o->npoints;
  memcpy(vo.x_points, o->x_points, sizeof vo.x_points);
  rr_vertical_plan *std = NULL, *lines = NULL;
  rr_vertical_point est[RR_VERTICAL_POINTS_MAX];
  vrun w = {0};
  if (!(st = rr_vertical_plan_new(&vo, &std, err)))
    st = rr_vertical_ride_execute(std, m, v, sp, est, err);
  int np = st ? 0 : rr_vertical_npoints(std);
  if (!st) st = run_alloc(&w, ns, np, o->fs_hz, err);
  if (!st) st = time_run(m, v, sp, o, std->rows, &w, err);
  if (!st) st = pem_lines(m, v, sp, rr_vertical_points(std), np, w.fl, w.nl, &lines, err);
  for (int q = 0; q < np && !st; q++) {
    rr_vertical_validate_point *pt = &r->points[q];
    const double *y = w.y + (size_t)q * (size_t)ns;
    double ss = 0;
    for (int k = 0; k < ns; k++) ss += y[k] * y[k];
    *pt = (rr_vertical_validate_point){.x = est[q].x,
                                       .rms_pem = est[q].rms,
                                       .rms_time = sqrt(ss / ns),
                                       .sperling_pem = est[q].sperling};
    memcpy(w.yw, y, sizeof(double) * (size_t)ns);
    fftw_execute(w.fwd_y);
    line_checks(&w, q, rr_vertical_psd(lines), rr_vertical_frf_H(lines), np, pt);
    windows_of(&w, &est[q], o->fs_hz, o->window_s, pt);
  }
  r->npoints = np;
  r->seconds_simulated = 2 * ns / o->fs_hz;
  if (!st) st = welch_of(m, v, sp, o, rr_vertical_points(std), &w, r, err);
  run_free(&w);
  rr_vertical_plan_free(std);
  rr_vertical_plan_free(lines);
  if (st) rr_vertical_validate_result_free(r);
  return st;
}
