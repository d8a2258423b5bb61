/* A small ODE system and its SUNDIALS CVODES set-up (BDF, dense Newton with
 * the system's own Jacobian, per-state absolute tolerances), shared by the
 * time integration and the periodic-orbit solver. */
#ifndef RR_ODE_CVODES_H
#define RR_ODE_CVODES_H

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include "railride/error.h"

/* dz/dt = f(t, z; p) and its Jacobian df/dz (n x n, row-major). */
typedef struct rr_ode {
  int n;
  void (*rhs)(void *user, double t, double p, const double *z, double *dz);
  void (*jac)(void *user, double t, double p, const double *z, double *J);
  void *user;
} rr_ode;

typedef struct ode_cv {
  const rr_ode *ode;
  double p; /* the parameter the system runs at */
  SUNContext ctx;
  void *mem;
  N_Vector y, atol;
  SUNMatrix A;
  SUNLinearSolver LS;
  double *J; /* n x n, row-major */
} ode_cv;

/* atol: n per-state absolute tolerances. */
int rr_ode_open(ode_cv *c, const rr_ode *ode, double p, const double *z0, double rtol,
                const double *atol, rr_error *err);
void rr_ode_close(ode_cv *c);
/* CVODES callbacks (user data: the ode_cv). */
int rr_ode_cv_rhs(double t, N_Vector y, N_Vector ydot, void *user);
int rr_ode_cv_jac(double t, N_Vector y, N_Vector fy, SUNMatrix Jm, void *user, N_Vector t1,
                  N_Vector t2, N_Vector t3);

#endif
