/* railride: a linear model at an operating point: M, C, K, B and the Maxwell
 * elements, assembled once from a system; speed and conicity only touch the
 * contact terms, so an optimiser re-targets a model without re-assembling.
 * Matrices are row-major, DOFs in the system's order (docs/model.md section 1 for
 * the vehicle). */
#ifndef RAILRIDE_MODEL_H
#define RAILRIDE_MODEL_H

#include "railride/common.h"
#include "railride/error.h"
#include "railride/system.h"
#include "railride/vehicle.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rr_model rr_model;

/* Assembles a model from a generic system (SDF off). */
RR_API int rr_model_new(const rr_system *sys, rr_model **out, rr_error *err);
/* Builds the 17-DOF vehicle system of docs/model.md section 2-3 (caller frees). */
RR_API int rr_vehicle_system(const rr_vehicle *veh, rr_system **out, rr_error *err);
/* Vehicle -> system -> model, with the vehicle's SDF mode and curve. */
RR_API int rr_model_from_vehicle(const rr_vehicle *veh, rr_model **out, rr_error *err);
RR_API void rr_model_free(rr_model *m);
/* An independent copy into *out (free with rr_model_free). */
RR_API int rr_model_clone(const rr_model *m, rr_model **out, rr_error *err);

/* Operating point: speed (m/s) and equivalent conicity, within the range above. */
RR_API int rr_model_set_operating(rr_model *m, double speed_ms, double conicity, rr_error *err);
RR_API double rr_model_speed(const rr_model *m);
RR_API double rr_model_conicity(const rr_model *m);
/* The free wheelset's kinematic (Klingel) frequency f_K = (v / 2 pi)
 * sqrt(lambda / (r0 l0)) in Hz at speed_ms and conicity, the largest over
 * the model's contacts (0 without contacts or at conicity <= 0). */
RR_API double rr_model_kinematic_hz(const rr_model *m, double speed_ms, double conicity);
/* Gravitational stiffness option (docs/model.md section 3); the operating
 * point's contact terms are rebuilt with it. */
RR_API int rr_model_set_gravity_stiffness(rr_model *m, int on, rr_error *err);
/* SDF mode and curve for the elements flagged sdf. */
RR_API int rr_model_set_sdf(rr_model *m, rr_sdf_mode mode, const rr_sdf_curve *curve,
                            rr_error *err);
RR_API rr_sdf_mode rr_model_sdf_mode(const rr_model *m);
RR_API const rr_sdf_curve *rr_model_sdf_curve(const rr_model *m);

RR_API int rr_model_ndof(const rr_model *m);
RR_API int rr_model_ninputs(const rr_model *m);
RR_API const char *rr_model_dof_name(const rr_model *m, int i);
RR_API int rr_model_dof_group(const rr_model *m, int i);      /* enum rr_group */
RR_API double rr_model_input_x(const rr_model *m, int input); /* x of the contact (m) */
RR_API const double *rr_model_M(const rr_model *m);           /* n x n */
RR_API const double *rr_model_C(const rr_model *m);           /* n x n, contact included */
RR_API const double *rr_model_K(const rr_model *m);           /* n x n, contact included */
RR_API const double *rr_model_B(const rr_model *m);           /* n x ninputs */

/* Displacement row (length ndof) of a point (absolute x, y, z) fixed to the
 * named body, along dir (enum rr_direction): u = row . q. The vehicle's
 * bodies are "c", "f1", "f2", "w1".."w4". */
RR_API int rr_model_point_row(const rr_model *m, const char *body, const double point[3],
                              enum rr_direction dir, double *row, rr_error *err);

/* Maxwell elements (c in series with finite k), in state order. */
RR_API int rr_model_nmaxwell(const rr_model *m);
typedef struct rr_maxwell_info {
  const char *name;
  const double *J; /* elongation row, length ndof */
  double k, c;     /* series stiffness N/m, damping N s/m */
  int sdf;         /* follows the SDF curve */
} rr_maxwell_info;
/* Maxwell element i (0 .. rr_model_nmaxwell - 1) into *info. */
RR_API int rr_model_maxwell(const rr_model *m, int i, rr_maxwell_info *info, rr_error *err);

/* State space z = [q; dq/dt; u] (docs/model.md section 5). Size 2n + nmaxwell,
 * plus one inner state per SDF element in physical mode. */
RR_API int rr_model_state_size(const rr_model *m);
/* Fills A (N x N row-major). sdf_k > 0 overrides the series stiffness of the
 * SDF elements (paper mode); otherwise paper mode uses the curve's minimum. */
RR_API int rr_model_state_matrix(const rr_model *m, double sdf_k, double *A, rr_error *err);
/* Input matrix of the state space (N x ninputs). */
RR_API int rr_model_state_input(const rr_model *m, double *Bs, rr_error *err);

/* Series stiffness of element i at Laplace variable s under the model's SDF
 * mode (paper mode: k_sdf(|Im s|/2pi), sdf_k > 0 overrides). */
RR_API rr_complex rr_model_series_k(const rr_model *m, int i, rr_complex s, double sdf_k);
/* Dynamic stiffness D(s) = s^2 M + s C + K + sum J' k_e(s) J (n x n). */
RR_API void rr_model_dynamic_stiffness(const rr_model *m, rr_complex s, double sdf_k,
                                       rr_complex *D);

#ifdef __cplusplus
}
#endif
#endif
