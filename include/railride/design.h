/* railride: design contexts for optimisation loops. A context fixes the base
 * vehicle, which vehicle-file keys vary and which objectives to compute, and
 * owns every model, workspace, plan and spectrum they need: evaluate() then
 * sets the variables and fills the objectives with no allocation and no file
 * I/O. Contexts are independent: give each thread its own (rr_design_clone),
 * or let rr_design_evaluate_batch spread a batch over OpenMP threads. */
#ifndef RAILRIDE_DESIGN_H
#define RAILRIDE_DESIGN_H

#include "railride/vehicle.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RR_DESIGN_MAX_VARS 32
#define RR_DESIGN_MAX_OBJS 16

/* Objectives, written as strings:
 *   zeta_low, zeta_high, std_zeta       robust indices (paper Table 1)
 *   index@KMH,L                         vehicle stability index
 *   critical_speed@L                    km/h (10-600 range; 600 when stable to the end)
 *   sperling@KMH,L[,X]                  Sperling W (filter method) at floor point x = X m (default 0)
 *   sperling_gb@..., wd_rms@..., rms@...  other ride indices, same arguments
 * each optionally followed by ";sdf=none|paper|physical" and, for ride
 * indices, ";spectrum=NAME" (default wuhan-guangzhou). */
typedef struct rr_design rr_design;

/* var_keys: "section.key" numeric vehicle-file keys; values are SI. */
int rr_design_new(const rr_vehicle *base, int nvar, const char *const *var_keys, int nobj,
                  const char *const *objectives, rr_design **out, rr_error *err);
void rr_design_free(rr_design *d);
/* An independent copy (for another thread). */
int rr_design_clone(const rr_design *d, rr_design **out, rr_error *err);
int rr_design_nvar(const rr_design *d);
int rr_design_nobj(const rr_design *d);
/* Fills f[nobj] for variables x[nvar]. On an invalid design (e.g. a negative
 * mass) returns the status and sets f to NaN. Allocation-free. */
int rr_design_evaluate(rr_design *d, const double *x, double *f, rr_error *err);
/* x: n x nvar, f: n x nobj, row-major. nthreads <= 0: OpenMP's default.
 * Failed designs get NaN objectives; returns the number that failed. */
int rr_design_evaluate_batch(rr_design *d, int n, const double *x, double *f, int nthreads);

/* Plain-C entry for bindings (ctypes): vehicle is a built-in name or a file;
 * keys and objectives are newline-separated; errbuf receives the message. */
rr_design *rr_design_open(const char *vehicle, const char *keys_nl, const char *objectives_nl, char *errbuf, int errlen);

#ifdef __cplusplus
}
#endif
#endif
