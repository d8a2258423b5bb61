/* Welch PSD estimate with FFTW: Hann window, 50% overlap, one-sided. */
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include "railride/timesim.h"
#include "util/internal.h"

int rr_welch_psd(const double *x, int n, double fs, int nseg, double *f, double *P, int *navg,
                 rr_error *err)
{
  if (!(nseg >= 8 && nseg % 2 == 0 && n >= nseg && fs > 0))
    return rr_seterr(
        err, RR_EINVAL,
        "welch: need an even segment >= 8 samples, no longer than the record (%d > %d)", nseg, n);
  int nh = nseg / 2 + 1, step = nseg / 2, K = (n - nseg) / step + 1;
  double *buf = fftw_malloc(sizeof(double) * (size_t)nseg),
         *win = malloc(sizeof(double) * (size_t)nseg);
  fftw_complex *X = fftw_malloc(sizeof(fftw_complex) * (size_t)nh);
  if (!buf || !win || !X) {
    fftw_free(buf);
    free(win);
    fftw_free(X);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  fftw_plan plan = fftw_plan_dft_r2c_1d(nseg, buf, X, FFTW_ESTIMATE);
  double wss = 0;
  for (int j = 0; j < nseg; j++) {
    win[j] = 0.5 * (1 - cos(2 * RR_PI * j / nseg)); /* periodic Hann */
    wss += win[j] * win[j];
  }
  for (int k = 0; k < nh; k++) {
    P[k] = 0;
    f[k] = k * fs / nseg;
  }
  for (int s = 0; s < K; s++) {
    const double *seg = x + (size_t)s * (size_t)step;
    double mean = 0;
    for (int j = 0; j < nseg; j++) mean += seg[j];
    mean /= nseg;
    for (int j = 0; j < nseg; j++) buf[j] = (seg[j] - mean) * win[j];
    fftw_execute(plan);
    for (int k = 0; k < nh; k++) P[k] += X[k][0] * X[k][0] + X[k][1] * X[k][1];
  }
  for (int k = 0; k < nh; k++) P[k] *= (k == 0 || k == nh - 1 ? 1.0 : 2.0) / (fs * wss * K);
  fftw_destroy_plan(plan);
  fftw_free(buf);
  free(win);
  fftw_free(X);
  *navg = K;
  return RR_OK;
}
