/* Random track realisations by the spectral method (FFTW inverse real FFT). */
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/timesim.h"
#include "util/rng.h"
#include "util/internal.h"

int rr_track_realise(const rr_spectrum *sp, const rr_track_realisation *r, double *u, double *du,
                     rr_error *err)
{
  double v = r->speed_ms, fs = r->fs_hz, f_lo = r->f_lo_hz, f_hi = r->f_hi_hz;
  const double *x = r->x_inputs;
  int ni = r->ninputs, ns = r->nsamples;
  rr_track_amplitudes how = r->amplitudes;
  uint64_t seed = r->seed;
  if (!(v > 0 && fs > 0 && ns >= 4 && ni >= 1 && f_hi > f_lo && f_lo >= 0))
    return rr_seterr(err, RR_EINVAL,
                     "track: need speed > 0, fs > 0, >= 4 samples, 0 <= f_lo < f_hi");
  int nh = ns / 2 + 1;
  double T = ns / fs, dn = 1.0 / (v * T);
  double *amp = malloc(sizeof(double) * (size_t)nh), *phase = malloc(sizeof(double) * (size_t)nh),
         *out = fftw_malloc(sizeof(double) * (size_t)ns);
  fftw_complex *Y = fftw_malloc(sizeof(fftw_complex) * (size_t)nh);
  int st = RR_OK;
  if (!amp || !phase || !Y || !out) {
    st = rr_seterr(err, RR_ENOMEM, "out of memory");
    goto done;
  }
  /* phases first, one per line whatever the band, so a band change keeps
     them; the Gaussian draw's Rayleigh factors from a second stream, so that
     both draws share their phases */
  rr_rng rng, rng_amp;
  rr_rng_seed(&rng, seed);
  rr_rng_seed(&rng_amp, seed ^ 0x5deece66dULL);
  for (int k = 0; k < nh; k++) {
    phase[k] = 2 * RR_PI * rr_rng_uniform(&rng);
    double f = k / T, n = f / v, ray = sqrt(-log(1 - rr_rng_uniform(&rng_amp))); /* E ray^2 = 1 */
    int in = k > 0 && 2 * k < ns && f >= f_lo * (1 - 1e-12) && f <= f_hi * (1 + 1e-12);
    amp[k] = in ? sqrt(2 * rr_spectrum_eval(sp, n) * dn) * (how == RR_TRACK_FIXED ? 1 : ray) : 0;
  }
  fftw_plan plan = fftw_plan_dft_c2r_1d(ns, Y, out, FFTW_ESTIMATE);
  if (!plan) {
    st = rr_seterr(err, RR_ENOMEM, "fftw plan failed");
    goto done;
  }
  for (int i = 0; i < ni; i++)
    for (int d = 0; d < 2; d++) {
      double *dst = (d ? du : u) + (size_t)i * (size_t)ns;
      if (!dst) continue;
      for (int k = 0; k < nh; k++) {
        double f = k / T, arg = phase[k] + 2 * RR_PI * (f / v) * x[i];
        double complex y = 0.5 * amp[k] * cexp(I * arg);
        if (d) y *= I * 2 * RR_PI * f; /* d/dt */
        Y[k][0] = creal(y);
        Y[k][1] = cimag(y);
      }
      fftw_execute(plan); /* out[m] = sum_k A_k cos(2 pi f_k t_m + arg_k) */
      memcpy(dst, out, sizeof(double) * (size_t)ns);
    }
  fftw_destroy_plan(plan);
done:
  free(amp);
  free(phase);
  fftw_free(Y);
  fftw_free(out);
  return st;
}
