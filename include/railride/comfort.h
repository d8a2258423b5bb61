/* railride: ride indices from a one-sided acceleration PSD (docs/model.md section 7).
 * G in (m/s^2)^2/Hz on the grid f (Hz, increasing); integrals by the
 * trapezoid rule over the grid. Each index names its method. */
#ifndef RAILRIDE_COMFORT_H
#define RAILRIDE_COMFORT_H

#include "railride/common.h"
#include "railride/error.h"

#ifdef __cplusplus
extern "C" {
#endif

enum rr_axis { RR_AXIS_LATERAL = 0, RR_AXIS_VERTICAL = 1 };
/* ISO 8041 weightings; RR_EN_WB is EN 12299's Wb (its own Q4, Q5, Q6), RR_ISO_WB
   ISO 8041's / ISO 2631-4's. */
enum rr_iso_weighting {
  RR_ISO_WB = 0,
  RR_ISO_WC = 1,
  RR_ISO_WD = 2,
  RR_ISO_WK = 3,
  RR_EN_WB = 4,
  RR_EN_WP = 5
};

/* Sperling weighting filter |B(f)|: B_s vertical, 1.25 B_s lateral. */
RR_API double rr_sperling_filter(double f_hz, enum rr_axis axis);
/* The Sperling weighting B(f) as a continuous state-space filter (3 states):
 * |C (j w I - A)^-1 B| = rr_sperling_filter(f, axis). A 3x3, B 3, C 3. */
RR_API void rr_sperling_filter_ss(enum rr_axis axis, double *A, double *B, double *C);
/* Sperling's index from the weighted RMS acceleration a_w (m/s^2): 4.42 a_w^0.3. */
RR_API double rr_sperling_from_weighted_rms(double aw_ms2);
/* GB/T 5599 frequency correction factor F(f). */
RR_API double rr_sperling_gb_factor(double f_hz, enum rr_axis axis);
/* ISO 8041 frequency weighting H(j 2 pi f), band limits included. */
RR_API rr_complex rr_iso8041_weight(enum rr_iso_weighting weighting, double f_hz);

/* RMS sqrt(integral G df) (m/s^2). */
RR_API double rr_psd_rms(const double *f, const double *G, int n, int stride);
/* Sperling by the weighting filter: Wz = 4.42 a_w^0.3, a_w^2 = integral |B|^2 G df. */
RR_API int rr_sperling_filter_index(const double *f, const double *G, int n, int stride,
                                    enum rr_axis axis, double *Wz, rr_error *err);
/* Sperling by the GB/T 5599 line method: 0.2 Hz bands from 0.5 Hz lying
 * wholly inside the grid, A_i = sqrt(2 G(f_i) df), W = 3.57 (sum A^3 F/f)^0.1. */
RR_API int rr_sperling_gb_index(const double *f, const double *G, int n, int stride,
                                enum rr_axis axis, double *W, rr_error *err);
/* ISO 2631-1 / EN 12299 frequency-weighted RMS (m/s^2). */
RR_API int rr_weighted_rms(const double *f, const double *G, int n, int stride,
                           enum rr_iso_weighting weighting, double *aw, rr_error *err);
/* Every index of one axis on a fixed grid, planned once (FFTW's split): the
 * weightings |B|^2, |Wd|^2 and the GB/T 5599 bands' interpolation are
 * computed at plan time; executing it on a PSD column is a few dot products,
 * allocation-free, and gives the functions' values above to the last bit. */
typedef struct rr_comfort_plan rr_comfort_plan;
typedef struct rr_comfort {
  double rms;         /* m/s^2 */
  double sperling;    /* weighting-filter method */
  double sperling_gb; /* GB/T 5599 line method */
  double wd_rms;      /* ISO 2631-1 Wd (lateral) or Wb (vertical) weighted RMS, m/s^2 */
} rr_comfort;
/* A plan for the n frequencies f (Hz, increasing) of one axis. */
RR_API int rr_comfort_plan_new(const double *f, int n, enum rr_axis axis, rr_comfort_plan **out,
                               rr_error *err);
RR_API void rr_comfort_plan_free(rr_comfort_plan *p);
/* Every index of one PSD column G (G[k * stride], (m/s^2)^2/Hz at f[k]). */
RR_API int rr_comfort_execute(const rr_comfort_plan *p, const double *G, int stride,
                              rr_comfort *out, rr_error *err);

/* The GB/T 5599 index alone (the plan's bands), for callers that form the
 * weighted integrals themselves. */
RR_API int rr_comfort_gb(const rr_comfort_plan *p, const double *G, int stride, double *W,
                         rr_error *err);

/* EN 12299 mean-comfort figure from one axis' Wd RMS: N = 6 a_wd (the 95th
 * percentile of 5 s RMS values of a stationary Gaussian process is taken as
 * its RMS: this model has no 5 s scatter). */
RR_API double rr_en12299_comfort(double awd);

/* The 5 s RMS of a stationary Gaussian process (docs/vertical.md, "5 s RMS"):
 * the gamma law with the window mean square's exact mean and variance. */
typedef struct rr_window_stats {
  double rms;            /* sqrt of the (weighted) PSD's integral */
  double shape_k;        /* gamma shape sigma^4 / Var m */
  double dof;            /* 2 k */
  double p50, p95, mean; /* of the 5 s RMS */
} rr_window_stats;

typedef struct rr_window_plan rr_window_plan;
/* A plan for the n frequencies f (Hz, increasing, spacing below 1/window
 * for the line-process variance to be the continuous one) and a window of
 * window_s seconds: the kernel sinc^2((f_i - f_j) T) + sinc^2((f_i + f_j) T)
 * (n x n) and the trapezoid weights, for up to maxcols columns at once. */
RR_API int rr_window_plan_new(const double *f, int n, double window_s, int maxcols,
                              rr_window_plan **out, rr_error *err);
RR_API void rr_window_plan_free(rr_window_plan *p);
/* The statistics of ncols PSD columns G[k * stride + c] ((m/s^2)^2/Hz),
 * each weighted by W2[k] (|W|^2; NULL: unweighted), into out[ncols]. One
 * pass over the kernel for all columns; allocation-free. */
RR_API int rr_window_execute(rr_window_plan *p, const double *G, int stride, int ncols,
                             const double *W2, rr_window_stats *out, rr_error *err);
/* The regularised lower incomplete gamma P(a, x) and its inverse in x
 * (Halley's method from the Wilson-Hilferty start, 1e-13 relative). */
RR_API double rr_gamma_p(double a, double x);
RR_API int rr_gamma_p_inv(double a, double p, double *x, rr_error *err);

/* EN 12299 mean comfort from 5 s RMS percentiles (m/s^2): X, Y Wd-weighted,
 * Z Wb; seat pan and back taken as the floor (a rigid seat). */
typedef struct rr_en12299_inputs {
  double ax50, ax95, ay50, ay95, az50, az95;
  double axd95; /* the seat back's X (Wc); a rigid seat's: the floor's ax95 */
} rr_en12299_inputs;
typedef struct rr_en12299 {
  double n_mv, n_vd, n_va_rigid_seat;
} rr_en12299;
RR_API rr_en12299 rr_en12299_indices(const rr_en12299_inputs *a);
/* The comfort scale's words for N: "very comfortable" (< 1) .. "very uncomfortable" (>= 5);
 * "undefined" for NaN (an unstable vehicle's ride). */
RR_API const char *rr_en12299_scale(double n);

#ifdef __cplusplus
}
#endif
#endif
