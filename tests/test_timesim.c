#define _POSIX_C_SOURCE 200809L
/* Time-domain validation pieces against closed forms, and a short
 * validation run against the PEM. */
#define _POSIX_C_SOURCE 200809L
#include <fftw3.h> /* before complex.h: fftw_complex as double[2] */
#include <complex.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"

static double maxdiff(const double *a, const double *b, int n)
{
  double d = 0;
  for (int i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i]));
  return d;
}

static void test_expm(void)
{
  rr_error e;
  double E[16];
  /* rotation generator: exp([[0, w], [-w, 0]] t) */
  double w = 7.3, R[4] = {0, w, -w, 0}, Rw[4] = {cos(w), sin(w), -sin(w), cos(w)};
  CHECK_OK(rr_expm(2, R, E, NULL, &e), e);
  CHECK(maxdiff(E, Rw, 4) < 1e-13, "rotation: %g", maxdiff(E, Rw, 4));
  /* nilpotent */
  double Nl[9] = {0, 1, 0, 0, 0, 1, 0, 0, 0}, Nw[9] = {1, 1, 0.5, 0, 1, 1, 0, 0, 1};
  rr_expm(3, Nl, E, NULL, &e);
  CHECK(maxdiff(E, Nw, 9) < 1e-15, "nilpotent");
  /* upper triangular with distinct eigenvalues, large norm (scaling and squaring):
     exp([[a, c], [0, b]]) = [[e^a, c (e^a - e^b)/(a - b)], [0, e^b]] */
  double a = -100, b = -3, c = 250, T[4] = {a, c, 0, b};
  double Tw[4] = {exp(a), c * (exp(a) - exp(b)) / (a - b), 0, exp(b)};
  rr_expm(2, T, E, NULL, &e);
  CHECK(maxdiff(E, Tw, 4) < 1e-14, "triangular, norm 350: %g", maxdiff(E, Tw, 4));
  /* damped oscillator x'' + 2 z w x' + w^2 x = 0 over t = 0.37 */
  double wn = 12, z = 0.1, t = 0.37, wd = wn * sqrt(1 - z * z),
         D[4] = {0, t, -wn * wn * t, -2 * z * wn * t};
  rr_expm(2, D, E, NULL, &e);
  double ex = exp(-z * wn * t);
  double Dw[4] = {ex * (cos(wd * t) + z * wn / wd * sin(wd * t)), ex * sin(wd * t) / wd,
                  -ex * wn * wn / wd * sin(wd * t), ex * (cos(wd * t) - z * wn / wd * sin(wd * t))};
  CHECK(maxdiff(E, Dw, 4) < 1e-13, "damped oscillator: %g", maxdiff(E, Dw, 4));
  /* exp(A) exp(-A) = I for a dense 4x4 */
  double A[16], Am[16], F[16], P[16];
  for (int i = 0; i < 16; i++) {
    A[i] = sin(1.3 * i + 0.2) * 3;
    Am[i] = -A[i];
  }
  rr_expm(4, A, E, NULL, &e);
  rr_expm(4, Am, F, NULL, &e);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      P[i * 4 + j] = 0;
      for (int k = 0; k < 4; k++) P[i * 4 + j] += E[i * 4 + k] * F[k * 4 + j];
    }
  double I4[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  CHECK(maxdiff(P, I4, 16) < 1e-11, "exp(A) exp(-A) = I: %g", maxdiff(P, I4, 16));
}

static void test_hermite(void)
{
  /* x' = -a x + b u, u = sin(w t): periodic response |H| sin(w t + arg H), H = b / (j w + a) */
  rr_error e;
  double a = 3, b = 2, w = 2 * RR_PI * 2, fs = 64;
  int ns = 64 * 4; /* 8 periods of the input */
  double A = -a, B = b, C = 1, D = 0;
  rr_lti_disc d;
  CHECK_OK(rr_lti_discretise(1, 1, &A, &B, 1 / fs, &d, &e), e);
  double *u = malloc(sizeof(double) * ns), *du = malloc(sizeof(double) * ns),
         *y = malloc(sizeof(double) * ns);
  for (int k = 0; k < ns; k++) {
    u[k] = sin(w * k / fs);
    du[k] = w * cos(w * k / fs);
  }
  CHECK_OK(rr_lti_periodic(&d, ns, u, du, 1, &C, &D, NULL, y, &e), e);
  double complex H = b / (I * w + a);
  double err = 0;
  for (int k = 0; k < ns; k++) err = fmax(err, fabs(y[k] - cabs(H) * sin(w * k / fs + carg(H))));
  /* cubic Hermite interpolation error (w dt)^4 / 384 of the input amplitude, at most */
  double bound = pow(w / fs, 4) / 384 * cabs(H) * 2;
  CHECK(err < bound, "Hermite hold: error %.3g (bound %.3g)", err, bound);
  CHECK(err < 2e-5, "Hermite hold absolute error %.3g", err);
  rr_lti_disc_free(&d);
  free(u);
  free(du);
  free(y);
}

/* rr_track_realise with the realisation's fields as arguments (the tests
   vary one or two of them at a time). */
static int realise(const rr_spectrum *sp, double v, const double *x, int ni, double fs, int ns,
                   double f_lo, double f_hi, rr_track_amplitudes amp, uint64_t seed, double *u,
                   double *du, rr_error *e)
{
  rr_track_realisation r = {.speed_ms = v,
                            .x_inputs = x,
                            .ninputs = ni,
                            .fs_hz = fs,
                            .nsamples = ns,
                            .f_lo_hz = f_lo,
                            .f_hi_hz = f_hi,
                            .amplitudes = amp,
                            .seed = seed};
  return rr_track_realise(sp, &r, u, du, e);
}

static void test_track_and_welch(void)
{
  rr_error e;
  rr_spectrum sp;
  CHECK_OK(rr_spectrum_open("wuhan-guangzhou", &sp, &e), e);
  double v = 80, fs = 64, x[2] = {0, -2.5}; /* second input 2.5 m behind: lag 2 samples */
  int ns = 8192;
  double *u = malloc(sizeof(double) * 2 * ns), *du = malloc(sizeof(double) * 2 * ns);
  CHECK_OK(realise(&sp, v, x, 2, fs, ns, 0.5, 20, RR_TRACK_FIXED, 7, u, du, &e), e);
  /* mean square over the period = the sum of line powers = integral of G_t over the band */
  double ms = 0, T = ns / fs, want = 0;
  for (int k = 0; k < ns; k++) ms += u[k] * u[k] / ns;
  for (int k = 1; k < ns / 2; k++) {
    double f = k / T;
    if (f >= 0.5 && f <= 20) want += rr_spectrum_eval(&sp, f / v) / v / T;
  }
  CHECK_CLOSE(ms, want, 1e-10, 0, "realisation mean square");
  /* the rear input sees the same track 2.5 m = 2 samples later */
  double lagerr = 0;
  for (int k = 0; k < ns; k++) lagerr = fmax(lagerr, fabs(u[ns + (k + 2) % ns] - u[k]));
  CHECK(lagerr < 1e-12 * sqrt(ms) * 100, "lag: %g", lagerr);
  /* the derivative against a 4th-order central difference, on a band where
     the difference itself is accurate (w h <= 0.4) */
  realise(&sp, v, x, 2, fs, ns, 0.5, 4, RR_TRACK_FIXED, 7, u, du, &e);
  double derr = 0, dmax = 0;
  for (int k = 2; k < ns - 2; k++) {
    double fd = (-u[k + 2] + 8 * u[k + 1] - 8 * u[k - 1] + u[k - 2]) * fs / 12;
    derr = fmax(derr, fabs(fd - du[k]));
    dmax = fmax(dmax, fabs(du[k]));
  }
  CHECK(derr < 2e-3 * dmax, "derivative vs finite difference: %g of %g", derr, dmax);
  realise(&sp, v, x, 2, fs, ns, 0.5, 20, RR_TRACK_FIXED, 7, u, du, &e);
  /* same seed, same track; another seed, another */
  double *u2 = malloc(sizeof(double) * ns);
  realise(&sp, v, x, 1, fs, ns, 0.5, 20, RR_TRACK_FIXED, 7, u2, NULL, &e);
  CHECK(maxdiff(u, u2, ns) == 0, "reproducible");
  realise(&sp, v, x, 1, fs, ns, 0.5, 20, RR_TRACK_FIXED, 8, u2, NULL, &e);
  CHECK(maxdiff(u, u2, ns) > 1e-4, "seed matters");
  /* Gaussian lines: the fixed draw's phases, Rayleigh amplitudes of mean
     square 1 (each line's power exponential: P(ratio^2 > 1) = 1/e) */
  realise(&sp, v, x, 1, fs, ns, 0.5, 20, RR_TRACK_GAUSSIAN, 7, u2, NULL, &e);
  fftw_complex *Uf = fftw_malloc(sizeof(fftw_complex) * (ns / 2 + 1)),
               *Ug = fftw_malloc(sizeof(fftw_complex) * (ns / 2 + 1));
  fftw_plan pf = fftw_plan_dft_r2c_1d(ns, u, Uf, FFTW_ESTIMATE),
            pg = fftw_plan_dft_r2c_1d(ns, u2, Ug, FFTW_ESTIMATE);
  fftw_execute(pf);
  fftw_execute(pg);
  double sum = 0, phase_err = 0;
  int nl = 0, above = 0;
  for (int k = 1; k < ns / 2; k++) {
    double af = hypot(Uf[k][0], Uf[k][1]);
    if (af < 1e-300 || k / T < 0.5 || k / T > 20) continue;
    double r2 = (Ug[k][0] * Ug[k][0] + Ug[k][1] * Ug[k][1]) / (af * af);
    double cross =
        atan2(Ug[k][1] * Uf[k][0] - Ug[k][0] * Uf[k][1], Ug[k][0] * Uf[k][0] + Ug[k][1] * Uf[k][1]);
    phase_err = fmax(phase_err, fabs(cross));
    sum += r2;
    above += r2 > 1;
    nl++;
  }
  CHECK(nl > 2000 && fabs(sum / nl - 1) < 5 / sqrt(nl),
        "Gaussian lines' mean square ratio %g over %d lines", sum / nl, nl);
  CHECK(fabs((double)above / nl - exp(-1)) < 5 * sqrt(exp(-1) * (1 - exp(-1)) / nl),
        "exponential line powers: %g above 1", (double)above / nl);
  CHECK(phase_err < 1e-9, "the Gaussian draw keeps the phases (%g rad)", phase_err);
  fftw_destroy_plan(pf);
  fftw_destroy_plan(pg);
  fftw_free(Uf);
  fftw_free(Ug);
  /* Welch: a sinusoid of amplitude A on a bin integrates to A^2/2 */
  int n = 16384, nseg = 1024, navg;
  double *s = malloc(sizeof(double) * n), f[513], P[513], Amp = 0.7, f0 = 10 * fs / nseg;
  for (int k = 0; k < n; k++) s[k] = Amp * sin(2 * RR_PI * f0 * k / fs + 0.3);
  CHECK_OK(rr_welch_psd(s, n, fs, nseg, f, P, &navg, &e), e);
  double tot = 0;
  for (int k = 0; k < 513; k++) tot += P[k] * fs / nseg;
  CHECK_CLOSE(tot, Amp * Amp / 2, 1e-10, 0, "Welch power of a sinusoid");
  CHECK(navg == 31, "averages %d", navg);
  CHECK(rr_welch_psd(s, 100, fs, nseg, f, P, &navg, &e) == RR_EINVAL,
        "record shorter than a segment");
  free(u);
  free(du);
  free(u2);
  free(s);
}

static void test_sperling_filter(void)
{
  double A[9], B[3], C[3];
  for (int axis = 0; axis < 2; axis++) {
    rr_sperling_filter_ss(axis, A, B, C);
    for (double f = 0.2; f < 40; f *= 1.9) {
      /* C (j w I - A)^-1 B for the companion form: N(s) / D(s) */
      double complex s = I * 2 * RR_PI * f;
      double complex H =
          (C[2] * s * s + C[1] * s + C[0]) / (s * s * s - A[8] * s * s - A[7] * s - A[6]);
      CHECK_CLOSE(cabs(H), rr_sperling_filter(f, axis), 1e-12, 0, "Sperling filter modulus");
    }
  }
}

static void test_validation_run(void)
{
  rr_vehicle v;
  rr_vehicle_builtin("type2", &v, NULL);
  v.sdf_mode = RR_SDF_PHYSICAL;
  rr_model *m;
  rr_error e;
  rr_spectrum sp;
  rr_model_from_vehicle(&v, &m, &e);
  rr_model_set_operating(m, 350 / RR_KMH, 0.2, &e);
  rr_spectrum_open("wuhan-guangzhou", &sp, &e);
  double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[51];
  rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, 0, rows, NULL, &e);
  rr_validate_opts o = rr_validate_opts_default();
  o.duration_s = 64;
  o.fs_hz = 128;
  o.nseg = 1024;
  o.npoints = 3;
  o.rows = rows;
  o.amplitudes = RR_TRACK_FIXED;
  rr_validate_result r;
  CHECK_OK(rr_validate(m, &sp, &o, &r, &e), e);
  CHECK(r.navg == 15, "averages %d", r.navg);
  for (int q = 0; q < 3; q++) {
    const rr_validate_point *p = &r.points[q];
    /* fixed amplitudes: over a whole period the mean square is the line sum of
       the PEM integrand, deterministic: the tolerance is the integration
       rule's (log grid) or the hold's (the lines), not statistics' */
    CHECK_CLOSE(p->rms_time, p->rms_pem, 1e-3, 0, "RMS time vs PEM");
    CHECK_CLOSE(p->rms_time, p->rms_lines, 5e-5, 0,
                "RMS time vs the lines' sum (the hold at fs 128 Hz)");
    CHECK_CLOSE(p->sperling_time, p->sperling_pem, 3e-4, 0, "Sperling by time filtering vs PEM");
    CHECK_CLOSE(p->sperling_time, p->sperling_lines, 2e-5, 0, "Sperling time vs the lines'");
    /* band powers: within 4 sigma of the spread expected from K averages */
    CHECK(p->band_z_max < 4, "point %d: band z %.2f", q, p->band_z_max);
    CHECK(p->nbands == 19, "bands %d", p->nbands);
  }
  rr_validate_result_free(&r);
  /* Gaussian amplitudes (the default): the RMS and Sperling scatter about the
     lines' expectation by their predicted spread */
  o.amplitudes = RR_TRACK_GAUSSIAN;
  CHECK_OK(rr_validate(m, &sp, &o, &r, &e), e);
  for (int q = 0; q < 3; q++) {
    const rr_validate_point *p = &r.points[q];
    CHECK(fabs(p->rms_z) < 4 && fabs(p->sperling_z) < 4 && p->band_z_max < 4.5,
          "Gaussian track, point %d: z rms %.2f, Sperling %.2f, bands %.2f", q, p->rms_z,
          p->sperling_z, p->band_z_max);
    CHECK(p->rms_rel_std > 0.01 && p->rms_rel_std < 0.5, "RMS spread %g", p->rms_rel_std);
    CHECK(fabs(p->rms_time / p->rms_lines - 1) > 1e-4,
          "the Gaussian run's RMS is not the expectation's");
  }
  rr_validate_result_free(&r);
  /* paper mode has no time form */
  v.sdf_mode = RR_SDF_PAPER;
  rr_model *mp;
  rr_model_from_vehicle(&v, &mp, &e);
  rr_model_set_operating(mp, 350 / RR_KMH, 0.2, &e);
  CHECK(rr_validate(mp, &sp, &o, &r, &e) == RR_EUNSUP, "paper mode refused");
  rr_model_free(mp);
  rr_model_free(m);
}

int main(void)
{
  check_spectra_env();
  test_expm();
  test_hermite();
  test_track_and_welch();
  test_sperling_filter();
  test_validation_run();
  return check_done("timesim");
}
