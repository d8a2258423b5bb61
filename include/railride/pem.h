/* railride: frequency response and the pseudo-excitation method (docs/model.md section 6).
 * Plan/execute: a plan fixes the frequency grid and the output points and owns
 * all workspace; executing it on a model (after any change of design, speed or
 * conicity) fills the complex FRFs without allocating; a spectrum then turns
 * them into PSDs at the cost of one multiply per frequency. */
#ifndef RAILRIDE_PEM_H
#define RAILRIDE_PEM_H

#include "railride/common.h"
#include "railride/model.h"
#include "railride/spectrum.h"
#include "railride/vehicle.h"

#ifdef __cplusplus
extern "C" {
#endif

enum rr_frf_method {
  RR_FRF_MODAL = 0,        /* modal expansion of the state-space part + SMW for the
                              SDF elements without a state-space form;
                              eigenvectors by Hessenberg inverse iteration; when their
                              basis is ill-conditioned (near zero conicity: a
                              defective rigid drift) the plan solves directly */
  RR_FRF_DIRECT = 1,       /* one dense n x n complex solve of D(jw) per frequency */
  RR_FRF_MODAL_LAPACK = 2, /* the modal expansion with dgeev's left and right vectors,
                              always (a cross-check; poor near defective points) */
  RR_FRF_SPARSE = 3        /* a sparse LU of D(jw) per frequency, eight frequencies at
                              a time in SIMD lanes, kept pivot orders; no modes, so
                              no conditioning to watch (default) */
};

/* The paper's ride evaluation: 400 log-spaced frequencies 0.3-30 Hz, floor
   points 1.2 m above the rail (an assumption: the paper does not say). */
#define RR_FRF_NFREQ_DEFAULT 400
#define RR_FRF_F_LO_DEFAULT 0.3
#define RR_FRF_F_HI_DEFAULT 30 /* Hz (the help texts quote these) */
#define RR_FLOOR_HEIGHT_DEFAULT 1.2

typedef struct rr_frf_opts {
  int nfreq;               /* number of frequencies (default 400) */
  const double *freqs_hz;  /* explicit grid, or NULL for log-spaced f_lo..f_hi */
  double f_lo_hz, f_hi_hz; /* default 0.3, 30 */
  int npoints;             /* output points */
  const double *rows;      /* npoints x ndof: displacement rows; output = -w^2 rows.q + rows0.q */
  const double *rows0;     /* npoints x ndof or NULL: rows taken without -w^2 (roll gravity) */
  enum rr_frf_method method;
} rr_frf_opts;

/* The defaults above, sparse method, no output rows yet. */
RR_API rr_frf_opts rr_frf_opts_default(void);

typedef struct rr_frf_plan rr_frf_plan;

/* Sizes a plan for the model's DOF, input and state counts. */
RR_API int rr_frf_plan_new(const rr_model *m, const rr_frf_opts *o, rr_frf_plan **out,
                           rr_error *err);
RR_API void rr_frf_plan_free(rr_frf_plan *p);
/* Computes the FRFs for the model as it is now. Allocation-free with a
 * single-threaded BLAS (OpenBLAS's threaded GEMM allocates its jobs; at these
 * sizes threads only cost: OPENBLAS_NUM_THREADS=1, as railride's CLI sets). */
RR_API int rr_frf_plan_execute(rr_frf_plan *p, const rr_model *m, rr_error *err);
RR_API int rr_frf_nfreq(const rr_frf_plan *p);
/* The method the last execute took (RR_FRF_DIRECT when a modal plan fell back). */
RR_API enum rr_frf_method rr_frf_route(const rr_frf_plan *p);
RR_API int rr_frf_npoints(const rr_frf_plan *p);
RR_API int rr_frf_ninputs(const rr_frf_plan *p);
RR_API const double *rr_frf_freqs(const rr_frf_plan *p);
/* H[(f * npoints + p) * ninputs + i]: output p (m/s^2 for acceleration rows) per
 * unit track alignment (m) at input i, harmonic at frequency f, no time lag. */
RR_API const rr_complex *rr_frf_H(const rr_frf_plan *p);

/* PEM: one-sided output PSDs G[f * npoints + p] ((m/s^2)^2/Hz) for a track
 * spectrum at the model's speed: pseudo-excitation sqrt(G_t(f)) exp(jw x_i/v)
 * at each input, G_t(f) = G_s(f/v)/v. */
RR_API int rr_pem_psd(const rr_frf_plan *p, const rr_model *m, const rr_spectrum *sp, double *G,
                      rr_error *err);
/* The same in two steps, for many designs at one speed on one track (an
 * optimiser's loop): the track's G_t(f) on the plan's grid into Gt[nfreq]
 * (m^2/Hz) once, at v_ms (m/s), then each design's PSDs from it, the
 * model at that speed. Evaluating the spectrum was a few per cent of a
 * ride evaluation. */
RR_API int rr_pem_track(const rr_frf_plan *p, const rr_spectrum *sp, double v_ms, double *Gt,
                        rr_error *err);
RR_API int rr_pem_psd_track(const rr_frf_plan *p, const rr_model *m, const double *Gt, double *G,
                            rr_error *err);
/* A design's PSDs in one call, the FRFs included (rr_pem_psd_track's G
 * for a plan executed on m): the sparse route solves for the inputs' lagged
 * sum directly, one right-hand side a frequency instead of one an input,
 * and leaves the plan's per-input H as it was; the other routes execute the
 * plan. The optimiser's path (rr_ride_design). */
RR_API int rr_pem_design(rr_frf_plan *p, const rr_model *m, const double *Gt, double *G,
                         rr_error *err);
/* The response to one alignment seen by every input with its lag:
 * sum_i H_i exp(j w x_i / v) (x: the inputs' positions, m; w rad/s; v m/s). */
RR_API rr_complex rr_pem_lagged_sum(const rr_complex *H, const double *x, int ninputs, double w,
                                    double v);
/* One PEM term: Gt |rr_pem_lagged_sum|^2. */
RR_API double rr_pem_combine(const rr_complex *H, const double *x, int ninputs, double w, double v,
                             double Gt);

/* Vehicle floor points: lateral displacement rows of (x_p, 0, h_p) on the
 * carbody; with roll_gravity, rows0 = g at phi_c (the accelerometer senses
 * a_y + g phi_c). rows, rows0: npoints x ndof. */
RR_API int rr_vehicle_floor_rows(const rr_model *m, const rr_vehicle *veh, const double *x,
                                 int npoints, double h_p, int roll_gravity, double *rows,
                                 double *rows0, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
