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
/* Ints in a structure's signature (rr_frf_sparse_signature), at most. */
#define RR_FRF_SIG_CAP(n) (9 * (n) * (n) + 6 * (n) + 80 + 2 * RR_SYS_MAX_BODIES)

/* The factorisation, compiled: entry lists into the compact factor array. */
typedef struct rr_frf_prog {
  int valid, ncomp;
  int *cidx;             /* each position's compact index, or -1 (n x n) */
  int *piv;              /* compact index of pivot k (n) */
  int *ls, *lc, *lrow;   /* L: column k's entries ls[k] .. ls[k + 1], their rows */
  int *us, *uc, *ucol;   /* U: row k's entries, their columns */
  int *mdst;             /* the entry each multiply-add updates, step by step, row by row */
  int *cmx;              /* compact index of each Maxwell element's J' J entries */
  unsigned *act;         /* step k's forward substitution: the inputs it touches (bits) */
  unsigned *in0;         /* the inputs each row of B has (bits) */
  unsigned char *formed; /* each entry: 1 where D has it, 0 for fill (zero until updated) */
  double *k0, *c0, *m0;  /* each entry's K, C and M (zero where the model has none) */
} rr_frf_prog;

typedef struct rr_frf_sparse {
  int n, ni, np, kmin;
  int interpret;  /* 1: never a codelet (the tests' comparisons); 0 from the layout */
  int sum;        /* this execute: one right-hand side, the inputs' lagged sum */
  int codelet;    /* the codelet the last execute ran (its index), or -1: the interpreter */
  int *sig;       /* the structure's signature (RR_FRF_SIG_CAP(n)) */
  rr_dsolver *ds; /* the pattern, and the lanes the growth test refuses */
  int *dsi;
  double complex *dsz, *t, *b;
  rr_frf_prog prog;
  double *Dr, *Di;  /* the compact factors (ncomp x lanes) */
  double *br, *bi;  /* the solves' vectors (n x ni x lanes) */
  double *xr, *xi;  /* the unknowns k >= kmin (n x ni x lanes) */
  double *jj;       /* each Maxwell element's J_a J_b, as cmx lists them */
  double *kr, *ki;  /* each Maxwell element's series stiffness in each lane */
  double *gr, *gi;  /* each input's lag in each lane (ni x lanes) */
  double *rhs;      /* the inputs' columns of B, solver order (n x ni) */
  int *on, *oj;     /* output q's nonzeros: count, unknowns (np, np x n) */
  double *ow, *ow0; /* their rows and rows0 entries (np x n) */
} rr_frf_sparse;

/* The workspace's arrays for n DOFs, ni inputs and np output rows (block.h). */
void rr_frf_sparse_layout(rr_frf_sparse *s, int n, int ni, int np, rr_block *b);
/* The model as it is now taken, the factorisation compiled for its structure
   (when new) and its values set; returns 1, or 0 when the lanes cannot take
   it (the scalar solver then solves every frequency). */
int rr_frf_sparse_prepare(rr_frf_sparse *s, const rr_model *m, const double *rows,
                          const double *rows0);
/* The compiled structure's signature into sig (RR_FRF_SIG_CAP(n) ints):
   everything a codelet's code depends on (after rr_frf_sparse_prepare);
   returns its length. */
int rr_frf_sparse_signature(const rr_frf_sparse *s, int *sig);
/* H[(k np + q) ni + i] = (-w^2 rows_q + rows0_q) D(jw_k)^-1 B_i at the nf
   frequencies f (Hz), for the model as it is now; or, given lag (nf x ni,
   the inputs' weights at each frequency), the response to their sum,
   H[k np + q] = (-w^2 rows_q + rows0_q) D(jw_k)^-1 sum_i B_i lag[k ni + i]:
   one right-hand side a frequency. */
void rr_frf_sparse_execute(rr_frf_sparse *s, const rr_model *m, const double *f, int nf,
                           const double *rows, const double *rows0, const double complex *lag,
                           double complex *H);

#endif
