/* Frequency responses by sparse direct solves of the dynamic stiffness,
 * eight frequencies at a time (one a SIMD lane): D(jw) = K - w^2 M + jw C +
 * sum J' k_e(jw) J formed on the structure of its LU factors, factored in the
 * sparse solver's DOF order (leaves first: wheelsets, frames, carbody, so
 * little fill) without row interchanges, solved for every input, and only
 * the unknowns the output rows read back-substituted. The factorisation is
 * compiled once per structure into flat lists (entries in a compact array,
 * each step's multiply-adds), so that it is a pass down a list. A lane whose
 * multipliers outgrow RR_DSOLVER_PIVOT_GROWTH (none on the built-in
 * vehicles) is solved by rr_dsolver with partial pivoting afresh. So a
 * frequency's result depends on the model and that frequency alone, never on
 * what was solved before. No modes: exact to rounding at every frequency,
 * whatever the state matrix's conditioning. */
#ifndef RR_FRF_SPARSE_H
#define RR_FRF_SPARSE_H

#include <complex.h>
#include "model/dynamic_stiffness.h"
#include "util/block.h"

#define RR_FRF_LANES 8 /* frequencies a pass: one AVX-512 vector, two AVX2 */

/* The factorisation, compiled: entry lists into the compact factor array. */
typedef struct rr_frf_prog {
  int valid, ncomp;
  int *cidx;            /* each position's compact index, or -1 (n x n) */
  int *piv;             /* compact index of pivot k (n) */
  int *ls, *lc, *lrow;  /* L: column k's entries ls[k] .. ls[k + 1], their rows */
  int *us, *uc, *ucol;  /* U: row k's entries, their columns */
  int *mdst;            /* the entry each multiply-add updates, step by step, row by row */
  int *cmx;             /* compact index of each Maxwell element's J' J entries */
  unsigned *act;        /* step k's forward substitution: the inputs it touches (bits) */
  double *k0, *c0, *m0; /* each entry's K, C and M (zero where the model has none) */
} rr_frf_prog;

typedef struct rr_frf_sparse {
  int n, ni, np, kmin;
  rr_dsolver *ds; /* the pattern, and the lanes the growth test refuses */
  int *dsi;
  double complex *dsz, *t, *b;
  rr_frf_prog prog;
  double *Dr, *Di;  /* the compact factors (ncomp x lanes) */
  double *br, *bi;  /* the solves' vectors (n x ni x lanes) */
  double *xr, *xi;  /* the unknowns k >= kmin (n x ni x lanes) */
  double *jj;       /* each Maxwell element's J_a J_b, as cmx lists them */
  double *kr, *ki;  /* each Maxwell element's series stiffness in each lane */
  double *rhs;      /* the inputs' columns of B, solver order (n x ni) */
  int *on, *oj;     /* output q's nonzeros: count, unknowns (np, np x n) */
  double *ow, *ow0; /* their rows and rows0 entries (np x n) */
} rr_frf_sparse;

/* The workspace's arrays for n DOFs, ni inputs and np output rows (block.h). */
void rr_frf_sparse_layout(rr_frf_sparse *s, int n, int ni, int np, rr_block *b);
/* H[(k np + q) ni + i] = (-w^2 rows_q + rows0_q) D(jw_k)^-1 B_i at the nf
   frequencies f (Hz), for the model as it is now. */
void rr_frf_sparse_execute(rr_frf_sparse *s, const rr_model *m, const double *f, int nf,
                           const double *rows, const double *rows0, double complex *H);

#endif
