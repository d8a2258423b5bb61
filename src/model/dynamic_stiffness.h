/* Solves with the dynamic stiffness D(s) = s^2 M + s C + K + sum J' k_e(s) J
 * of a model at a fixed operating point, many times and cheaply: the DOFs
 * are reordered leaves first (wheelsets, frames, carbody), D is formed from
 * the nonzero pattern of M, C, K and the Maxwell rows, and factored by a
 * sparse LU with partial pivoting whose row and column patterns are recorded
 * for the solves. For the 17-DOF car: ~110 nonzeros, ~140 after
 * factoring, against 289 dense. Vectors are in the solver's order
 * (rr_dsolver_to / _from convert). */
#ifndef RR_DYN_SOLVER_H
#define RR_DYN_SOLVER_H

#include <complex.h>
#include "model/model_impl.h"

typedef struct rr_dsolver {
  const rr_model *m;
  int n, nnz, nmx;
  int perm[RR_SYS_MAX_DOF];                 /* solver index -> model DOF */
  double mass[RR_SYS_MAX_DOF];              /* diagonal M, solver order */
  int pos[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF]; /* i n + j of each nonzero (the model's sparsity) */
  double nz_c[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF], nz_k[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF];
  struct {
    int nz, idx[RR_SYS_MAX_DOF], sdf;
    double J[RR_SYS_MAX_DOF], k, c, mult;
  } mx[2 * RR_SYS_MAX_BODIES];
  double complex *D;                                       /* n x n, factored in place */
  int *ord, *lstart, *lrow, *ustart, *ucol;                /* the last factors' patterns */
  int *rest, *dyn_ord, *dyn_ls, *dyn_lr, *dyn_us, *dyn_uc; /* pivoting LU's patterns */
  int *sta_ord, *sta_ls, *sta_lr, *sta_us, *sta_uc;        /* cached: the last pivoting LU's */
  int dirty;                 /* no cache yet: D may hold nonzeros anywhere */
  long n_static, n_pivoting; /* factorisations with the cached order, with pivoting */
} rr_dsolver;

/* Size of the int and complex workspaces rr_dsolver_init needs for n DOFs. */
#define RR_DSOLVER_IWORK(n) (4 * (n) * (n) + 8 * (n) + 4)
#define RR_DSOLVER_ZWORK(n) ((n) * (n))

#define RR_DSOLVER_PIVOT_GROWTH 10.0 /* threshold pivoting: |l| <= 10 */

/* Takes the model as it is now (operating point included). */
void rr_dsolver_init(rr_dsolver *ds, const rr_model *m, int *iwork, double complex *zwork);
/* Factors D(s) with the SDF elements' series stiffness k_sdf (paper mode). */
void rr_dsolver_factor(rr_dsolver *ds, double complex s, double k_sdf);
/* b <- D^-1 b with the last factors; t: n scratch. */
void rr_dsolver_solve(const rr_dsolver *ds, double complex *b, double complex *t);
/* y = D'(s) x (derivative in s). */
void rr_dsolver_deriv(const rr_dsolver *ds, double complex s, double k_sdf, const double complex *x,
                      double complex *y);
/* Solver order <-> model DOF order. */
void rr_dsolver_to(const rr_dsolver *ds, const double complex *model, double complex *solver);
void rr_dsolver_from(const rr_dsolver *ds, const double complex *solver, double complex *model);

#endif
