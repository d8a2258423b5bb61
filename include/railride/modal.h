/* railride: modal analysis and stability indices (MODEL.md sections 4-5). */
#ifndef RAILRIDE_MODAL_H
#define RAILRIDE_MODAL_H

#include <complex.h>
#include "railride/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rr_modal_opts {
  double fmax_hz;   /* modes above are left out of the index (default 10 Hz) */
  double w_min;     /* minimum wheelset kinetic-energy share (default 1e-3) */
} rr_modal_opts;
rr_modal_opts rr_modal_opts_default(void);

typedef struct rr_mode {
  double re, im;              /* eigenvalue (1/s), im >= 0 */
  double freq_hz;             /* im / 2 pi */
  double zeta;                /* re / |lambda|: negative is stable */
  double energy[RR_NGROUPS];  /* kinetic-energy shares carbody, frames, wheelsets */
  int oscillatory;            /* im > 1e-6 |lambda| */
  int hunting;                /* wheelset share >= w_min */
  int in_index;               /* counted in the vehicle stability index */
  int self_consistent;        /* paper SDF mode: a self-consistent root was found */
  double sdf_k;               /* paper SDF mode: series stiffness at the root (N/m) */
} rr_mode;

typedef struct rr_modal_result {
  int n;                      /* modes stored (one per conjugate pair, plus real ones) */
  int cap;
  rr_mode *modes;             /* sorted: oscillatory by frequency, then real ones */
  int ndof;
  double complex *shapes;     /* q part of each mode's eigenvector, n x ndof (may be NULL) */
  double stability_index;     /* max zeta over modes in the index; -1 when none */
  int index_mode;             /* which mode gave it, -1 when none */
} rr_modal_result;

typedef struct rr_modal_ws rr_modal_ws;
/* Workspace for a model's state size (and its ndof); reuse across calls. */
int rr_modal_ws_new(const rr_model *m, rr_modal_ws **out, rr_error *err);
void rr_modal_ws_free(rr_modal_ws *ws);
int rr_modal_result_alloc(const rr_model *m, rr_modal_result *res, rr_error *err);
void rr_modal_result_free(rr_modal_result *res);

/* All modes with energy shares and shapes. Paper SDF mode: self-consistent
 * modes by branch tracking. */
int rr_modal_solve(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                   rr_modal_result *res, rr_error *err);
/* The vehicle stability index alone, by the cheapest exact route:
 * eigenvalues only, then eigenvectors (17x17 inverse iteration on D(lambda))
 * only for the candidate modes. Allocation-free. */
int rr_modal_stability_index(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                             double *zeta, rr_error *err);

/* The index at npts operating points (speeds in m/s, conicities): zeta[p]
 * equals what rr_modal_stability_index gives there, to rounding. Groups of
 * up to four points share one instruction stream, their QR sweeps running
 * in SIMD lanes: about twice the throughput of one point at a time
 * (paper-mode SDF models go one point at a time). The model's operating
 * point is restored on return. Allocation-free. */
int rr_modal_stability_index_batch(rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, int npts,
                                   const double *speed_ms, const double *conicity, double *zeta,
                                   rr_error *err);

/* Robust stability indices (paper Table 1). */
typedef struct rr_robust_opts {
  double v_low_ms, conicity_low;    /* 250 km/h, 0.05 */
  double v_high_ms, conicity_high;  /* 350 km/h, 0.40 */
  double conicity_min, conicity_max;/* 0.05 .. 0.40 */
  int n_conicity;                   /* 8 */
} rr_robust_opts;
rr_robust_opts rr_robust_opts_default(void);
typedef struct rr_robust { double zeta_low, zeta_high, std_zeta; } rr_robust;
/* Evaluated through rr_modal_stability_index_batch (the 9 default points as
 * 4 + 4 + 1); the model's operating point is restored. */
int rr_robust_indices(rr_model *m, const rr_modal_opts *o, const rr_robust_opts *r,
                      rr_modal_ws *ws, rr_robust *out, rr_error *err);

/* Critical speed: lowest speed in [v_min, v_max] (m/s) where the index
 * reaches 0, scan step dv (m/s) then bisection to tol (m/s). *found = 0 when
 * stable to the range's end. Changes the model's operating point. */
typedef struct rr_critical_opts { double v_min_ms, v_max_ms, step_ms, tol_ms; } rr_critical_opts;
rr_critical_opts rr_critical_opts_default(void);
int rr_critical_speed(rr_model *m, double conicity, const rr_modal_opts *o,
                      const rr_critical_opts *c, rr_modal_ws *ws, double *v_ms, int *found,
                      rr_error *err);

/* Root locus: modes followed along a parameter by eigenvector correlation.
 * param: 0 = speed (values in m/s), 1 = conicity. For each point p and
 * branch b fills out[p * nbranch + b]; *nbranch is the number of oscillatory
 * modes at the first point. out must hold npts * (state size) entries. */
typedef struct rr_locus_point { double param, re, im, freq_hz, zeta, mac; double energy[RR_NGROUPS]; } rr_locus_point;
int rr_locus(rr_model *m, int param, const double *values, int npts, const rr_modal_opts *o,
             rr_locus_point *out, int *nbranch, rr_error *err);

/* Modal assurance criterion of two complex vectors. */
double rr_mac(const double complex *a, const double complex *b, int n);

#ifdef __cplusplus
}
#endif
#endif
