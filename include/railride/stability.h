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
RR_API rr_robust_opts rr_robust_opts_default(void);

typedef struct rr_robust {
  double zeta_low, zeta_high, std_zeta;
  double zeta_max;   /* largest zeta of any oscillatory mode over all the points */
  int n_unstable;    /* points at which some oscillatory mode has zeta >= 0 */
  double unstable_speed_ms, unstable_conicity; /* the first such point (NaN when none) */
} rr_robust;

/* Evaluated through rr_modal_stability_batch; the model's operating point is
 * restored. */
RR_API int rr_robust_indices(rr_model *m, const rr_modal_opts *o, const rr_robust_opts *r,
                      rr_modal_ws *ws, rr_robust *out, rr_error *err);

/* Critical speed: the lowest speed in [v_min, v_max] (m/s) at which some
 * oscillatory mode, of any frequency and shape, has zeta >= 0 (index_modes:
 * only the modes of the stability index count, the index reaching 0). A scan
 * at step_ms, then bisection to tol_ms. A scan of more than
 * RR_CRITICAL_MAX_STEPS steps is refused (RR_EINVAL). */
#define RR_CRITICAL_MAX_STEPS 10000000
typedef struct rr_critical_opts {
  double v_min_ms, v_max_ms, step_ms, tol_ms;  /* 10, 600, 1, 1e-3 km/h */
  int index_modes;                             /* 0: any oscillatory mode */
} rr_critical_opts;
RR_API rr_critical_opts rr_critical_opts_default(void);

typedef struct rr_critical {
  int found;         /* 0: stable to the range's end */
  double speed_ms;   /* NaN when not found */
  rr_mode mode;      /* the mode that goes unstable there (when found) */
} rr_critical;
/* Changes the model's operating point. */
RR_API int rr_critical_speed(rr_model *m, double conicity, const rr_modal_opts *o,
                      const rr_critical_opts *c, rr_modal_ws *ws, rr_critical *out,
                      rr_error *err);

/* Root locus: modes followed along a parameter by eigenvector correlation.
 * For each point p and branch b fills out[p * nbranch + b]; *nbranch is the
 * number of oscillatory modes at the first point. out must hold
 * npts * (state size) entries. pr (may be NULL): progress per point; when it
 * stops the call (RR_ESTOPPED), the points not reached have re = NaN. */
typedef enum rr_locus_param { RR_LOCUS_SPEED = 0, RR_LOCUS_CONICITY = 1 } rr_locus_param;
typedef struct rr_locus_point {
  double param, re, im, freq_hz, zeta, mac;
  double energy[RR_NGROUPS];
  double roll_share;
  int hunting;
} rr_locus_point;
RR_API int rr_locus(rr_model *m, rr_locus_param param, const double *values, int npts,
             const rr_modal_opts *o, const rr_progress *pr, rr_locus_point *out, int *nbranch, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
