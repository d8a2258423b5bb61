/* Eigenvalues of a small dense real matrix, fast: stabilised elementary
 * reduction to Hessenberg form and the Francis double-shift QR iteration
 * (Wilkinson & Reinsch, Handbook for Automatic Computation II, 1971: the
 * algorithms of EISPACK's elmhes and hqr). No LAPACK call overhead for the
 * 40 x 40 state matrices of the stability index. */
#ifndef RR_HQR_H
#define RR_HQR_H
#include <stddef.h>

/* Destroys a (n x n, row-major). Returns 0, or -1 when the QR iteration did
 * not converge (the caller falls back to LAPACK). */
int rr_eig_small(int n, double *a, double *wr, double *wi);

/* The two halves, for callers that also want eigenvectors (eigen_decomposition.c).
 * rr_elmhes leaves the Hessenberg matrix in a's upper part and, below the
 * subdiagonal, the multipliers: a(i, m-1) for row i > m of step m, whose row
 * interchange is perm[m] (n <= 64). rr_hqr destroys its argument; pairs come
 * with the negative imaginary part first. */
void rr_elmhes(int n, double *a, int *perm);
int rr_hqr(int n, double *a, double *wr, double *wi);

/* Eigenvalues of nb <= RR_QR_LANES_MAX matrices of the same order n <= 64 at
 * once, the QR sweeps of several in SIMD lanes (one instruction stream for
 * several operating points of one design): groups of 8 where the processor
 * has AVX-512 (rr_eig_batch_lanes() == 8), else of 4. lanes: 0 for the best
 * available, 4 to force groups of 4. mats[c]: row-major n x n, read only.
 * Lane c's eigenvalues go to wr, wi + c n, in the order rr_hqr would give
 * them, to rounding. work: rr_eig_batch_work(n) doubles. Returns 0, or
 * nonzero when some lane did not converge (fail[c] = 1: the caller solves
 * that one otherwise) or the arguments are out of range. */
#define RR_QR_LANES_MAX 8
int rr_eig_batch_lanes(void);
size_t rr_eig_batch_work(int n);
int rr_eig_batch(int n, int nb, int lanes, const double *const *mats, double *wr, double *wi,
                 double *work, int *fail);
#endif
