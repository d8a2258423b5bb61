/* Small dense real LU with partial pivoting and its 1-norm condition
 * estimate, allocation-free, column-major (LAPACK's layout, leading
 * dimension lda). For the ride evaluation's eigenvector basis (38 x 38, 6
 * right-hand sides), where OpenBLAS's dgetrf + dgecon + dgetrs take 17.5 us,
 * mostly call overhead and blocking made for large matrices; these 11 us. */
#ifndef RR_LU_H
#define RR_LU_H

/* Factors A = P L U in place (L unit lower, U upper), as dgetf2 does: piv[k]
 * is the row interchanged with row k at step k. Returns 0, or k + 1 when
 * U(k, k) is exactly zero (the factors are then complete but singular). */
int rr_lu_factor(int n, double *a, int lda, int *piv);
/* Solves A X = B in place, X and B stored by rows (row i at x + i ldx, nrhs
 * entries): every right-hand side in one pass over the factors, so that the
 * substitutions' chain runs once, not once a column. */
void rr_lu_solve_rows(int n, const double *lu, int lda, const int *piv, int nrhs, double *x,
                      int ldx);
/* max_j sum_i |a_ij|, the 1-norm of A (take it before factoring). */
double rr_lu_norm1(int n, const double *a, int lda);
/* The reciprocal condition number in the 1-norm, 1 / (|A|_1 |A^-1|_1), with
 * |A^-1|_1 estimated by Hager's method as Higham refined it (LAPACK's dgecon
 * and dlacn2): never above the true |A^-1|_1, so the estimate is never below
 * the true reciprocal. work: n doubles, iwork: n ints. 0 for a singular or
 * non-finite case. */
double rr_lu_rcond1(int n, const double *lu, int lda, double anorm, double *work, int *iwork);
#endif
