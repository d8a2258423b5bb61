/* railride: time-domain validation of the frequency domain.
 * A random track realisation (spectral method, seeded), exact discretisation
 * of the linear state space with a cubic Hermite hold on the inputs (values
 * and exact derivatives from the realisation), the periodic steady state of
 * the periodic realisation (no transient to discard), Welch PSD (FFTW). */
#ifndef RAILRIDE_TIMESIM_H
#define RAILRIDE_TIMESIM_H

#include "railride/common.h"

#include <stdint.h>
#include "railride/model.h"
#include "railride/spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How a realisation's lines are drawn: fixed amplitudes sqrt(2 G_s(n_k) dn)
 * with uniform phases, or Gaussian (random complex coefficients: the same
 * phases, Rayleigh amplitudes of that mean square), a Gaussian process whose
 * mean-square and band powers scatter as a measured track's would. */
typedef enum rr_track_amplitudes { RR_TRACK_GAUSSIAN = 0, RR_TRACK_FIXED = 1 } rr_track_amplitudes;
/* What a realisation is drawn for. */
typedef struct rr_track_realisation {
  double speed_ms;        /* m/s */
  const double *x_inputs; /* each input's x along the vehicle, m (ninputs) */
  int ninputs;
  double fs_hz;                   /* samples per second */
  int nsamples;                   /* one period */
  double f_lo_hz, f_hi_hz;        /* the lines kept */
  rr_track_amplitudes amplitudes; /* fixed or Gaussian */
  uint64_t seed;
} rr_track_realisation;
/* Track profile seen by each input over one period of nsamples at fs_hz:
 * y_t(v t + x_i), with lines at f_k = k fs / nsamples kept in [f_lo, f_hi],
 * drawn from the seed as the amplitudes say. u and du (time derivative,
 * exact) are ninputs x nsamples, row-major. */
RR_API int rr_track_realise(const rr_spectrum *sp, const rr_track_realisation *r, double *u,
                            double *du, rr_error *err);

/* A measured alignment record: distance_m (rising), alignment_m. */
typedef struct rr_track_record {
  int n;
  double *x, *y;
} rr_track_record;
/* Reads a CSV (header line allowed; comma or space separated). */
RR_API int rr_track_record_load(const char *path, rr_track_record *r, rr_error *err);
RR_API void rr_track_record_free(rr_track_record *r);
/* The longest run (s) the record allows at speed v for contacts at x (m). */
RR_API double rr_track_record_duration(const rr_track_record *r, double v, const double *x, int ni);
/* The alignment each contact meets at t = k / fs (k < ns), y_t(v t + x_i)
 * as in rr_track_realise with the last contact starting at the record's
 * first row; linear between rows, rates by central differences. u, du:
 * ninputs x ns. */
RR_API int rr_track_record_sample(const rr_track_record *r, double v, const double *x, int ni,
                                  double fs, int ns, double *u, double *du, rr_error *err);

/* Exact discretisation of x' = A x + B w with w(t) a cubic Hermite
 * interpolant of samples w_k, w'_k (step dt):
 * x_{k+1} = Phi x_k + G[0] w_k + G[1] w'_k + G[2] w_{k+1} + G[3] w'_{k+1}. */
typedef struct rr_lti_disc {
  int N, m;
  double dt;
  double *Phi; /* N x N */
  double *G;   /* N x 4m: [G0 G1 G2 G3] */
} rr_lti_disc;
/* Phi and G for A (N x N), B (N x m) and step dt, by one matrix exponential. */
RR_API int rr_lti_discretise(int N, int m, const double *A, const double *B, double dt,
                             rr_lti_disc *d, rr_error *err);
RR_API void rr_lti_disc_free(rr_lti_disc *d);
/* Periodic steady-state response to a periodic input (w, dw: m x ns): outputs
 * y = C x + D w + E w' (ny x ns), with C ny x N, D and E ny x m (E may be NULL). */
RR_API int rr_lti_periodic(const rr_lti_disc *d, int ns, const double *w, const double *dw, int ny,
                           const double *C, const double *D, const double *E, double *y,
                           rr_error *err);

/* Welch PSD: Hann window (periodic), 50% overlap, segment nseg, mean removed
 * per segment, one-sided (m/s^2)^2/Hz. f, P: nseg/2 + 1 entries. */
RR_API int rr_welch_psd(const double *x, int n, double fs_hz, int nseg, double *f, double *P,
                        int *navg, rr_error *err);

/* Validation of the PEM against a time-domain run. */
#define RR_VALIDATE_DURATION_S 600 /* the validation runs' default record, s */
typedef struct rr_validate_opts {
  double duration_s;              /* record length = one period of the realisation
                                     (RR_VALIDATE_DURATION_S) */
  double fs_hz;                   /* sample rate (256) */
  int nseg;                       /* Welch segment (4096) */
  uint64_t seed;                  /* (1) */
  rr_track_amplitudes amplitudes; /* the realisation's lines (Gaussian) */
  double f_lo_hz, f_hi_hz;        /* band of the track content and the PEM (0.3, 30) */
  int nfreq;                      /* PEM grid (400, log-spaced) */
  int npoints;
  const double *rows, *rows0; /* floor points as in rr_frf_opts */
  rr_progress progress;       /* steps: the track, the time run, each point, the PEM lines (none);
                                 a stop returns RR_ESTOPPED and no result */
} rr_validate_opts;
/* The defaults given in the fields' comments. */
RR_API rr_validate_opts rr_validate_opts_default(void);

#define RR_NBANDS_MAX 40
typedef struct rr_validate_point {
  double rms_pem, rms_time;
  double sperling_pem, sperling_time,
      sperling_welch; /* filter method: PEM, time filtering, Welch PSD */
  double sperling_gb_pem, sperling_gb_welch;
  double wd_rms_pem, wd_rms_welch;
  int nbands;
  double band_fc[RR_NBANDS_MAX], band_pem[RR_NBANDS_MAX], band_time[RR_NBANDS_MAX],
      band_sigma[RR_NBANDS_MAX];
  double band_error_max; /* max |time - pem| / pem over the bands */
  double band_z_max;     /* max |time - pem| / (sigma pem) */
  /* the realisation's expectation on its own lines (PEM at f_l = l / T,
     power G(f_l) / T each) and the run's scatter about it: the RMS and the
     Sperling index (filter method) with their relative standard deviations
     (a Gaussian track's line powers are exponential) and z-scores */
  double rms_lines, rms_rel_std, rms_z;
  double sperling_lines, sperling_rel_std, sperling_z;
} rr_validate_point;

typedef struct rr_validate_result {
  int npoints, navg, nwelch;
  double bin_sigma; /* relative standard deviation of one Welch bin, sqrt((1 + 2 c^2) / navg) */
  double *welch_f, *welch_P; /* nwelch, npoints x nwelch */
  /* the Welch estimator's expectation under the PEM spectrum (the PEM seen
     through the Hann window), npoints x nwelch, 0 outside the band */
  double *pem_P;
  rr_validate_point *points;
  double seconds_simulated;
} rr_validate_result;
/* The run that opts describe (above): a track realisation of sp, the time
 * simulation, Welch's PSDs against the PEM at each point, into r (free it with
 * rr_validate_result_free). */
RR_API int rr_validate(const rr_model *m, const rr_spectrum *sp, const rr_validate_opts *o,
                       rr_validate_result *r, rr_error *err);
RR_API void rr_validate_result_free(rr_validate_result *r);

#ifdef __cplusplus
}
#endif
#endif
