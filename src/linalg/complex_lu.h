/* Small dense complex LU with partial pivoting, allocation-free: the n x n
 * solves of inverse iteration and frequency response are too small for
 * LAPACK's call overhead to pay. Row-major. */
#ifndef RR_CLU_H
#define RR_CLU_H
#include <complex.h>

/* Factors A in place (L unit lower, U upper); piv receives row swaps.
 * Pivots smaller than tiny are replaced by tiny (inverse iteration wants a
 * nearly singular matrix to stay solvable). Returns the number replaced. */
int rr_clu_factor(double complex *A, int n, int *piv, double tiny);
/* Solves A x = b in place with the factors. */
void rr_clu_solve(const double complex *LU, int n, const int *piv, double complex *b);
#endif
