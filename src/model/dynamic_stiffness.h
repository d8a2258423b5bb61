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
#include "util/block.h"

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
/* The same with partial pivoting whatever the cached order: the factors
   then depend on s alone, not on the points factored before. */
void rr_dsolver_factor_fresh(rr_dsolver *ds, double complex s, double k_sdf);
/* b <- D^-1 b with the last factors; t: n scratch. */
void rr_dsolver_solve(const rr_dsolver *ds, double complex *b, double complex *t);
/* y = D'(s) x (derivative in s). */
void rr_dsolver_deriv(const rr_dsolver *ds, double complex s, double k_sdf, const double complex *x,
                      double complex *y);
/* Entry i of the fixed start vector of the one-step inverse iterations. */
static inline double complex rr_dsolver_start(int i) { return 1.0 + 0.1 * i + 0.01 * I * (i % 3); }

/* Solver order <-> model DOF order. */
void rr_dsolver_to(const rr_dsolver *ds, const double complex *model, double complex *solver);
void rr_dsolver_from(const rr_dsolver *ds, const double complex *solver, double complex *model);

/* ---- the shape test of several points at once (dynamic_stiffness_lanes.c) ----
 * Up to RR_DSL_LANES operating points (one a lane) whose D share one
 * pattern: each lane has its own values and its own s, and all are factored
 * with one pivot order at a time, with rr_dsolver_factor's and _solve's
 * operations lane by lane. The orders are the last few that rr_dsolver's
 * pivoting found (kept with rr_dsl_keep_order): a lane whose multipliers
 * outgrow RR_DSOLVER_PIVOT_GROWTH under one tries the next. Arrays: entry q
 * of lane l at [q L + l]. */
#define RR_DSL_LANES 8
#define RR_DSL_ORDERS 4
typedef struct rr_dsl_order {
  int valid;
  int *ord, *ls, *lr, *us, *uc; /* as rr_dsolver's sta_* */
} rr_dsl_order;
typedef struct rr_dsl {
  int n, nnz, nmx, loaded, patterned; /* the pattern (set by the first lane loaded) */
  int *pos, *perm;                    /* D's nonzeros (i n + j); solver index -> model DOF */
  int *mxnz, *mxidx;                  /* Maxwell elements: entries, their DOFs (nmx x n) */
  double *nzc, *nzk, *mass;           /* C and K at the nonzeros (nnz x L); diagonal M (n x L) */
  double *mk, *mc, *mm, *mJ;          /* Maxwell k, c, multiplicity (nmx x L); J (nmx x n x L) */
  double *Dr, *Di;                    /* D, factored in place (n x n x L) */
  double *tr, *ti;                    /* the solve's vector (n x L) */
  rr_dsl_order orders[RR_DSL_ORDERS];
  int newest;             /* the order kept last */
  int pref[RR_DSL_LANES]; /* the order that suited the lane's last test (-1: none yet) */
} rr_dsl;

/* The arrays for n DOFs from b (block.h: a sizing pass, then a carving one). */
void rr_dsl_layout(rr_dsl *dl, int n, rr_block *b);
/* Forgets the loaded lanes (the next load sets the pattern; the kept
   orders stay while it is the same). */
void rr_dsl_reset(rr_dsl *dl);
/* Lane l takes ds's values (ds just initialised at that point). Returns 0,
   or -1 (lane not loaded) when ds's pattern is not the lanes' or ds has
   SDF elements. */
int rr_dsl_load(rr_dsl *dl, int l, const rr_dsolver *ds);
/* Keeps ds's cached pivot order (on the lanes' pattern) for the lanes. */
void rr_dsl_keep_order(rr_dsl *dl, const rr_dsolver *ds);
/* The lanes have an order to try. */
int rr_dsl_has_order(const rr_dsl *dl);
/* D(s_l) formed and factored in the lanes of mask (bit l) with the kept
   orders, first the one that suited most of these lanes' last tests (or the
   newest), then the inverse-iteration solve from the fixed
   start vector; lane l's result in model DOF order into phi + l n. Returns
   the lanes that no kept order suits: their phi is not valid (the
   single-point solver pivots afresh for them). */
unsigned rr_dsl_shapes(rr_dsl *dl, unsigned mask, const double *sr, const double *si,
                       double complex *phi);

#endif
