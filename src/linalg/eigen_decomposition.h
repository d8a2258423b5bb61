/* Eigendecomposition A = V diag(lambda) V^-1 of a small dense real matrix
 * (n <= 64) without LAPACK's Schur-vector machinery: eigenvalues by elmhes +
 * hqr (hessenberg_qr.c), then each eigenvector by inverse iteration on the Hessenberg
 * matrix (O(n^2) a vector) and elmhes' eliminations undone (EISPACK's
 * elmbak). Used where a modal expansion needs the whole basis many times
 * (the ride evaluation); callers pair V with its own inverse, so near-equal
 * eigenvalues cost accuracy only through the conditioning of V, which they
 * check. */
#ifndef RR_EIGDEC_H
#define RR_EIGDEC_H

/* Shifts per inverse-iteration pass (one AVX-512 vector of doubles, two AVX2). */
#define RR_EIGDEC_LANES 8
/* Workspace sizes, in doubles and ints. */
#define RR_EIGDEC_LWORK(n)                                                                         \
  ((1 + 2 * RR_EIGDEC_LANES) * (n) * (n) + (1 + 6 * RR_EIGDEC_LANES) * (n)) /* n <= 64 */
#define RR_EIGDEC_LIWORK(n) ((2 + RR_EIGDEC_LANES) * (n))

/* a: n x n row-major, destroyed. On return wr, wi hold the eigenvalues,
 * complex pairs adjacent with the positive imaginary part first, and vr
 * (n x n, column-major, LAPACK's dgeev layout) the eigenvectors: a real
 * eigenvalue's column j is its vector, a pair's columns j, j+1 hold the real
 * and imaginary parts of the vector of wr[j] + i wi[j]. Vectors are scaled
 * to largest component 1. Returns 0, or -1 when the QR iteration did not
 * converge or n > 64. */
int rr_eigdec(int n, double *a, double *wr, double *wi, double *vr, double *work, int *iwork);
#endif
