/* railride: design contexts for optimisation loops. A context fixes the base
 * vehicle, which vehicle-file keys vary and which objectives to compute, and
 * owns every model, workspace, plan and spectrum they need: evaluate() then
 * sets the variables and fills the objectives with no allocation and no file
 * I/O. Contexts are independent: give each thread its own (rr_design_clone),
 * or let rr_design_evaluate_batch spread a batch over OpenMP threads. */
#ifndef RAILRIDE_DESIGN_H
#define RAILRIDE_DESIGN_H

#include "railride/common.h"

#include "railride/modal.h"
#include "railride/vehicle.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RR_DESIGN_MAX_VARS 32
#define RR_DESIGN_MAX_OBJS 16

/* The list below is a table: the formatter must not reflow it. */
/* clang-format off */
/* Objectives, written as strings:
 *   zeta_low, zeta_high, std_zeta   robust indices (paper Table 1)
 *   index@KMH,L                     vehicle stability index
 *   critical_speed@L                km/h (10-600 range; 600 when stable to the end)
 *   sperling@KMH,L[,X]              Sperling W (filter method) at floor point x = X m (default 0)
 *   sperling_gb@..., wd_rms@..., rms@...   other ride indices, same arguments
 * each optionally followed by modifiers, ';'-separated:
 *   sdf=none|paper|physical         the yaw damper's SDF for this objective
 *   spectrum=NAME                   ride indices: track spectrum (default wuhan-guangzhou)
 *   fmax=HZ, wmin=W, rmax=R         stability objectives: the index's rule
 *   index_modes                     critical_speed: only the index's modes count
 *   vmax=KMH                        critical_speed: the range's end (default 600)
 * e.g. "index@350,0.17;fmax=20;wmin=0;rmax=1". The full list: docs/cli.md
 * (railride objectives), installed under share/doc/railride. */
/* clang-format on */
typedef struct rr_design rr_design;

/* The objective names, for listings: name, its arguments after '@', its
 * unit and what it measures. */
typedef struct rr_objective_info {
  const char *name, *args, *unit, *doc;
} rr_objective_info;
RR_API const rr_objective_info *rr_objectives(int *n);

/* var_keys: "section.key" numeric vehicle-file keys; values are SI. */
RR_API int rr_design_new(const rr_vehicle *base, int nvar, const char *const *var_keys, int nobj,
                         const char *const *objectives, rr_design **out, rr_error *err);
RR_API void rr_design_free(rr_design *d);
/* An independent copy (for another thread). */
RR_API int rr_design_clone(const rr_design *d, rr_design **out, rr_error *err);
/* The index rule for objectives without their own fmax/wmin/rmax (default
 * rr_modal_opts_default()). */
RR_API int rr_design_set_modal_opts(rr_design *d, const rr_modal_opts *o, rr_error *err);
/* After an evaluation: the frequency (Hz) of the mode behind objective i's
 * value (index: the index mode; critical_speed: the mode that goes unstable),
 * NaN for other objectives or when there is none. */
RR_API double rr_design_mode_freq(const rr_design *d, int i);
/* 1 when objective i's last value is its range's end rather than a result
 * (critical_speed stable to its vmax), else 0. */
RR_API int rr_design_at_bound(const rr_design *d, int i);
/* The band edge (Hz) behind objective i's last value when it is an index@
 * objective, else NaN. */
RR_API double rr_design_band_edge(const rr_design *d, int i);
/* The verdict at objective i's operating point behind its last value (an
 * index@ or lateral ride objective): 1 stable, 0 unstable (a ride objective
 * is then undefined), -1 for the others. */
RR_API int rr_design_verdict(const rr_design *d, int i);
RR_API int rr_design_nvar(const rr_design *d);
RR_API int rr_design_nobj(const rr_design *d);
/* Fills f[nobj] for variables x[nvar]. On an invalid design (e.g. a negative
 * mass) returns the status and sets f to NaN. Allocation-free. */
RR_API int rr_design_evaluate(rr_design *d, const double *x, double *f, rr_error *err);
/* x: n x nvar, f: n x nobj, row-major. nthreads <= 0: OpenMP's default.
 * A design that fails gets NaN objectives (its status is rr_design_evaluate's);
 * *nfailed (may be NULL) counts them. Returns RR_OK: a failed design is a
 * result, not an error of the batch. */
RR_API int rr_design_evaluate_batch(rr_design *d, int n, const double *x, double *f, int nthreads,
                                    int *nfailed, rr_error *err);

/* Plain-C entry for bindings (ctypes): vehicle is a built-in name or a file;
 * keys and objectives are newline-separated. *out: the context (free with
 * rr_design_free). */
RR_API int rr_design_open(const char *vehicle, const char *keys_nl, const char *objectives_nl,
                          rr_design **out, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
