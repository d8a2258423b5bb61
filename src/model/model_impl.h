/* Internal layout of rr_model, shared by the solvers. */
#ifndef RR_MODEL_IMPL_H
#define RR_MODEL_IMPL_H

#include "railride/model.h"
#include "model/system_impl.h"

typedef struct rr_mx {
  char name[48];
  double J[RR_SYS_MAX_DOF];
  int nz; /* nonzeros of J, for cheap rank-one updates */
  int idx[RR_SYS_MAX_DOF];
  double k, c;
  int sdf;
} rr_mx;

/* The structural nonzeros of the dynamic stiffness D(s) = s^2 M + s C + K +
   sum J' k_e J, fixed by the assembly (every operating point's contact terms
   included), in the sparse solver's DOF order: leaves first (wheelsets,
   frames, carbody), so that elimination creates little fill. */
typedef struct rr_sparsity {
  int perm[RR_SYS_MAX_DOF], inv[RR_SYS_MAX_DOF]; /* solver index <-> model DOF */
  int nnz;
  int pos[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF]; /* i n + j, solver order */
  int src[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF]; /* a n + b, model order */
  unsigned char pi[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF], pj[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF]; /* i, j */
  int nkeep, elem[2 * RR_SYS_MAX_BODIES]; /* Maxwell elements, mirror pairs merged */
  double mult[2 * RR_SYS_MAX_BODIES];
} rr_sparsity;

struct rr_model {
  int n, ni, nmx, nsdf;
  double M[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF];
  double C[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF], K[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF];
  double C0[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF], K0[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF];
  double B[RR_SYS_MAX_DOF * RR_SYS_MAX_INPUTS];
  double mdiag[RR_SYS_MAX_DOF];
  int group[RR_SYS_MAX_DOF];
  char dof_name[RR_SYS_MAX_DOF][32];
  rr_mx mx[2 * RR_SYS_MAX_BODIES];
  rr_contact contacts[RR_SYS_MAX_INPUTS];
  rr_body bodies[RR_SYS_MAX_BODIES];
  int nbodies;
  double speed, conicity;
  int gravity;
  rr_sdf_mode sdf_mode;
  rr_sdf_curve curve;
  rr_sparsity sp; /* the pattern of D(s), for the sparse solver */
};

/* Fills m->sp from the assembled model (dynamic_stiffness.c). */
void rr_model_sparsity(rr_model *m);
/* Assembles sys into the existing model m (no allocation). */
int rr_model_assemble(rr_model *m, const rr_system *sys, rr_error *err);
/* Fills sys (cleared first) with the vehicle; allocation-free once sys has
 * held a vehicle before. */
int rr_vehicle_fill(const rr_vehicle *veh, rr_system *sys, rr_error *err);
/* Rebuilds m in place for a changed vehicle, keeping its operating point;
 * scratch is a system reused across calls. */
int rr_model_rebuild(rr_model *m, const rr_vehicle *veh, rr_system *scratch, rr_error *err);

/* State matrix with mirror-image Maxwell pairs merged (same k, c, SDF flag,
 * J equal up to sign): one element with 2k, 2c (2 K2, 2 K3 in physical SDF
 * mode) carries the pair's force exactly; the dropped combination of strokes is
 * decoupled with real eigenvalues. Same oscillatory eigenvalues, fewer states.
 * A must hold the full state size squared; *N receives the reduced size. */
/* One wheelset contact's linear terms at speed v and conicity lambda
   (creep.c): damping cy (lateral), cp (yaw); stiffness kyp (lateral force
   per yaw), kpy (yaw moment per lateral displacement, also the track
   input's); with gravity, gy (lateral, N/m) and gpsi (yaw, N m/rad). */
typedef struct rr_creep_terms {
  double cy, cp, kyp, kpy, gy, gpsi;
} rr_creep_terms;
rr_creep_terms rr_creep_terms_at(const rr_contact_spec *s, double v, double lambda, int gravity);

int rr_state_matrix_merged(const rr_model *m, double sdf_k, double *A, int *N, rr_error *err);
/* The same with the SDF elements taken in mode (the model's own unchanged). */
int rr_state_matrix_merged_as(const rr_model *m, rr_sdf_mode mode, double sdf_k, double *A, int *N,
                              rr_error *err);

/* The merged Maxwell elements: for each state slot, the element index and its
 * multiplier (2 for a merged mirror pair). Returns the count. */
int rr_merged_elements(const rr_model *m, int *elem, double *mult);

#endif
