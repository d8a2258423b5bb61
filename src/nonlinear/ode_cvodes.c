/* SUNDIALS CVODES for small dense ODE systems (see ode_cvodes.h). */
#include <stdlib.h>
#include <string.h>
#include "nonlinear/ode_cvodes.h"
#include "util/internal.h"

int rr_ode_cv_rhs(double t, N_Vector y, N_Vector ydot, void *user)
{
  ode_cv *c = user;
  c->ode->rhs(c->ode->user, t, c->p, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  return 0;
}

int rr_ode_cv_jac(double t, N_Vector y, N_Vector fy, SUNMatrix Jm, void *user, N_Vector t1,
                  N_Vector t2, N_Vector t3)
{
  (void)fy;
  (void)t1;
  (void)t2;
  (void)t3;
  ode_cv *c = user;
  int n = c->ode->n;
  c->ode->jac(c->ode->user, t, c->p, N_VGetArrayPointer(y), c->J);
  for (int j = 0; j < n; j++) { /* SUNDIALS' dense matrices are by columns */
    double *col = SUNDenseMatrix_Column(Jm, j);
    for (int i = 0; i < n; i++) col[i] = c->J[i * n + j];
  }
  return 0;
}

void rr_ode_close(ode_cv *c)
{
  if (c->mem) CVodeFree(&c->mem);
  if (c->LS) SUNLinSolFree(c->LS);
  if (c->A) SUNMatDestroy(c->A);
  if (c->y) N_VDestroy(c->y);
  if (c->atol) N_VDestroy(c->atol);
  free(c->J);
  if (c->ctx) SUNContext_Free(&c->ctx);
  memset(c, 0, sizeof *c);
}

int rr_ode_open(ode_cv *c, const rr_ode *ode, double p, const double *z0, double rtol,
                const double *atol, rr_error *err)
{
  memset(c, 0, sizeof *c);
  c->ode = ode;
  c->p = p;
  int n = ode->n;
  if (SUNContext_Create(NULL, &c->ctx)) return rr_seterr(err, RR_ENOMEM, "SUNDIALS context");
  c->y = N_VNew_Serial(n, c->ctx);
  c->atol = N_VNew_Serial(n, c->ctx);
  c->A = SUNDenseMatrix(n, n, c->ctx);
  c->J = malloc(sizeof(double) * (size_t)n * (size_t)n);
  c->mem = CVodeCreate(CV_BDF, c->ctx);
  if (!c->y || !c->atol || !c->A || !c->J || !c->mem) {
    rr_ode_close(c);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  memcpy(N_VGetArrayPointer(c->y), z0, sizeof(double) * (size_t)n);
  memcpy(N_VGetArrayPointer(c->atol), atol, sizeof(double) * (size_t)n);
  c->LS = SUNLinSol_Dense(c->y, c->A, c->ctx);
  int f = !c->LS || CVodeInit(c->mem, rr_ode_cv_rhs, 0.0, c->y) ||
          CVodeSVtolerances(c->mem, rtol, c->atol) || CVodeSetUserData(c->mem, c) ||
          CVodeSetLinearSolver(c->mem, c->LS, c->A) || CVodeSetJacFn(c->mem, rr_ode_cv_jac) ||
          CVodeSetMaxNumSteps(c->mem, 1000000);
  if (f) {
    rr_ode_close(c);
    return rr_seterr(err, RR_EINVAL, "CVODES set-up failed");
  }
  return RR_OK;
}
