/* railride: stability studies built on the modal solver: robust indices
 * (paper Table 1), critical speed, root loci. */
#ifndef RAILRIDE_STABILITY_H
#define RAILRIDE_STABILITY_H

#include "railride/common.h"

#include "railride/modal.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Robust stability indices (paper Table 1). */
typedef struct rr_robust_opts {
  double v_low_ms, conicity_low;     /* 250 km/h, 0.05 */
  double v_high_ms, conicity_high;   /* 350 km/h, 0.40 */
  double conicity_min, conicity_max; /* 0.05 .. 0.40 */
  int n_conicity;                    /* 8 */
} rr_robust_opts;
/* The defaults given in the fields' comments. */
RR_API rr_robust_opts rr_robust_opts_default(void);

typedef struct rr_robust {
  double zeta_low, zeta_high, std_zeta;
  double zeta_max; /* largest zeta of any oscillatory mode over all the points */
  int n_unstable;  /* points at which some oscillatory mode has zeta >= 0 */
  /* the first such point (NaN when none), in the order (v_low, conicity_low),
     (v_high, conicity_high), then the sweep at v_high upward */
  double unstable_speed_ms, unstable_conicity;
} rr_robust;

/* Evaluated through rr_modal_stability_batch; the model's operating point is
 * restored. */
RR_API int rr_robust_indices(rr_model *m, const rr_modal_opts *o, const rr_robust_opts *r,
                             rr_modal_ws *ws, rr_robust *out, rr_error *err);
/* The same for nmodels models of one vehicle layout (the designs of an
 * optimiser generation, say), their points sharing the SIMD lanes through
 * rr_modal_stability_many: out[i] equals rr_robust_indices on models[i] to
 * the last bit. On an error no out[i] is valid (evaluate the models one by
 * one to find which failed). Operating points are restored. */
RR_API int rr_robust_indices_many(rr_model *const *models, int nmodels, const rr_modal_opts *o,
                                  const rr_robust_opts *r, rr_modal_ws *ws, rr_robust *out,
                                  rr_error *err);

/* Critical speed: the lowest speed in [v_min, v_max] (m/s) at which some
 * oscillatory mode, of any frequency and shape, has zeta >= 0 (index_modes:
 * only the modes of the stability index count, the index reaching 0). A scan
 * at step_ms, then bisection to tol_ms. A scan of more than
 * RR_CRITICAL_MAX_STEPS steps is refused (RR_EINVAL). */
#define RR_CRITICAL_MAX_STEPS 10000000
/* The defaults, km/h (integers, so that help texts can quote them). */
#define RR_CRITICAL_V_MIN_KMH 10
#define RR_CRITICAL_V_MAX_KMH 600
#define RR_CRITICAL_STEP_KMH 1
#define RR_CRITICAL_TOL_KMH 1e-3
typedef struct rr_critical_opts {
  double v_min_ms, v_max_ms, step_ms, tol_ms; /* the RR_CRITICAL_*_KMH above, in m/s */
  int index_modes;                            /* 0: any oscillatory mode */
} rr_critical_opts;
/* The defaults given in the fields' comments. */
RR_API rr_critical_opts rr_critical_opts_default(void);

typedef struct rr_critical {
  int found;       /* 0: stable to the range's end */
  double speed_ms; /* NaN when not found */
  rr_mode mode;    /* the mode that goes unstable there (when found) */
} rr_critical;
/* Changes the model's operating point. */
RR_API int rr_critical_speed(rr_model *m, double conicity, const rr_modal_opts *o,
                             const rr_critical_opts *c, rr_modal_ws *ws, rr_critical *out,
                             rr_error *err);

/* Root locus: modes followed along a parameter by eigenvector correlation
 * (MAC). Every oscillatory mode anywhere in the range is a branch: born at
 * the first point where it is oscillatory (a branch of its own when no branch
 * continues into it), ended where it turns real (its best match is a real
 * root) or finds no match; an ended branch's later rows are gaps (re = NaN),
 * and so are a branch's rows before its birth. out[p * stride + b] with
 * stride = rr_locus_stride(m) (out holds npts * stride entries); *nbranch:
 * the branches born. pr (may be NULL): progress per point; when it stops
 * the call (RR_ESTOPPED), the points not reached are gaps. More than stride
 * branches born over the range is an error (RR_EUNSUP). */
typedef enum rr_locus_param { RR_LOCUS_SPEED = 0, RR_LOCUS_CONICITY = 1 } rr_locus_param;
typedef struct rr_locus_point {
  double param, re, im, freq_hz, zeta, mac;
  double energy[RR_NGROUPS];
  double roll_share, frame_roll_share;
  int hunting;
} rr_locus_point;
/* The row length of a locus's output: the most branches it holds. */
RR_API int rr_locus_stride(const rr_model *m);
RR_API int rr_locus(rr_model *m, rr_locus_param param, const double *values, int npts,
                    const rr_modal_opts *o, const rr_progress *pr, rr_locus_point *out,
                    int *nbranch, rr_error *err);

/* rr_locus in two steps, so that the eigen-solves (its cost) can be spread
 * over threads or processes and the branches followed after, with the same
 * result to the bit (the same layout, out[p * stride + b]):
 * - rr_locus_solve: one point's modes and shapes into a record of
 *   rr_locus_record_size(m) bytes (plain data: records may be copied between
 *   processes running the same build). res: scratch from
 *   rr_modal_result_alloc. Leaves the model at that point.
 * - rr_locus_follow: the branches through npts records in order, into
 *   out[p * nbranch + b]; a tracker goes on from where its last call ended,
 *   so windows of points may be followed one after another (out: the
 *   window's first row). *nbranch: the branches born so far. */
typedef struct rr_locus_tracker rr_locus_tracker;
RR_API size_t rr_locus_record_size(const rr_model *m);
RR_API int rr_locus_solve(rr_model *m, rr_locus_param param, double value, const rr_modal_opts *o,
                          rr_modal_ws *ws, rr_modal_result *res, void *record, rr_error *err);
RR_API int rr_locus_tracker_new(const rr_model *m, rr_locus_tracker **out, rr_error *err);
RR_API void rr_locus_tracker_free(rr_locus_tracker *t);
RR_API int rr_locus_follow(rr_locus_tracker *t, const double *values, int npts, const void *records,
                           rr_locus_point *out, int *nbranch, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
