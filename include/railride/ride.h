/* railride: the lateral ride evaluation as one plan (docs/model.md section 6-7).
 * The pipeline every lateral ride takes, owned here once: floor points
 * (x, 0, h_p) on the carbody, their acceleration rows, the FRF plan, the
 * pseudo-excitation PSDs for a track spectrum, and every comfort index of
 * each point. Plan once per model layout and options; execute after each
 * change of design, speed or conicity (allocation-free). */
#ifndef RAILRIDE_RIDE_H
#define RAILRIDE_RIDE_H
#include "railride/comfort.h"
#include "railride/common.h"
#include "railride/modal.h"
#include "railride/model.h"
#include "railride/pem.h"
#include "railride/spectrum.h"
#include "railride/vehicle.h"
#ifdef __cplusplus
extern "C" {
#endif
#define RR_RIDE_POINTS_MAX 16
#define RR_RIDE_SPECTRUM_DEFAULT "wuhan-guangzhou" /* the paper's lateral alignment PSD */
/* What a ride evaluation gives at an operating point where some mode is
 * unstable (zeta >= 0, any frequency and shape): a linear response of an
 * unstable vehicle is not a ride comfort. */
typedef enum rr_ride_unstable {
  RR_RIDE_UNDEFINED = 0, /* every index NaN, the verdict given (the default) */
  RR_RIDE_LINEAR = 1,    /* the linear response's indices all the same, the verdict given */
  RR_RIDE_UNCHECKED = 2  /* no verdict taken (stable = -1): for callers that judge it apart */
} rr_ride_unstable;

/* The lateral ride's settings; rr_ride_opts_default() gives the paper's. */
typedef struct rr_ride_opts {
  int nfreq;               /* RR_FRF_NFREQ_DEFAULT (400) */
  double f_lo_hz, f_hi_hz; /* 0.3, 30 */
  const double *freqs_hz;  /* an explicit grid (nfreq, increasing), or NULL: log-spaced */
  int npoints;             /* 0: the paper's points x = +L, 0, -L (L: bogie half-spacing) */
  double x_points[RR_RIDE_POINTS_MAX]; /* m, along the carbody from its centre */
  double floor_height_m;               /* RR_FLOOR_HEIGHT_DEFAULT (1.2 m above the rail) */
  int roll_gravity;                    /* 1: the accelerometer senses a_y + g phi_c (default 0) */
  enum rr_frf_method method;           /* RR_FRF_SPARSE */
  rr_ride_unstable when_unstable;      /* RR_RIDE_UNDEFINED */
} rr_ride_opts;
RR_API rr_ride_opts rr_ride_opts_default(void);
/* The paper's floor points for a vehicle: x = +L, 0, -L into x[3]; returns 3. */
RR_API int rr_ride_points_default(const rr_vehicle *veh, double *x);

/* One floor point's lateral indices (accelerations in m/s^2). */
typedef struct rr_ride_point {
  double x;           /* m */
  double rms;         /* unweighted, over the band */
  double sperling;    /* weighting-filter method */
  double sperling_gb; /* GB/T 5599 line method */
  double wd_rms;      /* ISO 2631-1 / EN 12299 Wd */
  double n_mv;        /* EN 12299 6 a_wd from the lateral axis alone (rr_en12299_comfort) */
  int stable;         /* verdict at the operating point: 1 stable, 0 unstable, -1 not taken */
  double zeta_max;    /* largest zeta of any oscillatory mode there (NaN: not taken) */
} rr_ride_point;

typedef struct rr_ride_plan rr_ride_plan;
/* A plan for the model's layout (its floor rows are taken now) and o
 * (NULL: the defaults); veh gives the default floor points. */
RR_API int rr_ride_plan_new(const rr_model *m, const rr_vehicle *veh, const rr_ride_opts *o,
                            rr_ride_plan **out, rr_error *err);
RR_API void rr_ride_plan_free(rr_ride_plan *p);
/* FRFs, PEM PSDs for the lateral spectrum sp at the model's speed, and
 * every index of every point into out[npoints] (out may be NULL). */
RR_API int rr_ride_execute(rr_ride_plan *p, const rr_model *m, const rr_spectrum *sp,
                           rr_ride_point *out, rr_error *err);
/* For many designs at one speed on one track (an optimiser's loop): the
 * track's temporal PSD on the plan's grid computed once (the plan keeps no
 * pointer to sp), then each design's evaluation, the model at v_ms (m/s);
 * rr_ride_execute is the two in one call (and sets the plan's track). */
RR_API int rr_ride_plan_set_track(rr_ride_plan *p, const rr_spectrum *sp, double v_ms,
                                  rr_error *err);
RR_API int rr_ride_design(rr_ride_plan *p, const rr_model *m, rr_ride_point *out, rr_error *err);
/* The FRFs alone, every input's (rr_ride_frf's H), for callers that need
 * no spectrum. */
RR_API int rr_ride_frf_execute(rr_ride_plan *p, const rr_model *m, rr_error *err);
RR_API int rr_ride_nfreq(const rr_ride_plan *p);
RR_API const double *rr_ride_freqs(const rr_ride_plan *p); /* Hz */
RR_API int rr_ride_npoints(const rr_ride_plan *p);
RR_API const double *rr_ride_points(const rr_ride_plan *p); /* x, m */
/* After an execute: G[f * npoints + p], (m/s^2)^2/Hz. */
RR_API const double *rr_ride_psd(const rr_ride_plan *p);
/* The plan's FRF plan: its grid and route, and its every-input H after
 * rr_ride_frf_execute (rr_ride_execute and rr_ride_design take
 * rr_pem_design's path: the sparse route solves for the inputs' lagged sum
 * and leaves H as it was). */
RR_API const rr_frf_plan *rr_ride_frf(const rr_ride_plan *p);
/* The floor rows (npoints x ndof, m per coordinate) and, with roll gravity,
 * the rows taken without -w^2 (else NULL), for callers that drive the
 * model another way (a time-domain run). */
RR_API const double *rr_ride_rows(const rr_ride_plan *p, const double **rows0);

/* One evaluation in one call: the model of veh at v_ms (m/s) and conicity,
 * the spectrum by name or file (NULL: RR_RIDE_SPECTRUM_DEFAULT), o (NULL:
 * the defaults); out[npoints]. */
RR_API int rr_ride_evaluate(const rr_vehicle *veh, double v_ms, double conicity,
                            const char *spectrum, const rr_ride_opts *o, rr_ride_point *out,
                            rr_error *err);
#ifdef __cplusplus
}
#endif
#endif
