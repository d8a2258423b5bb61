/* Eigenvalues of a small dense real matrix, fast: stabilised elementary
 * reduction to Hessenberg form and the Francis double-shift QR iteration
 * (Wilkinson & Reinsch, Handbook for Automatic Computation II, 1971: the
 * algorithms of EISPACK's elmhes and hqr). No LAPACK call overhead for the
 * 40 x 40 state matrices of the stability index. */
#ifndef RR_HQR_H
#define RR_HQR_H

/* Destroys a (n x n, row-major). Returns 0, or -1 when the QR iteration did
 * not converge (the caller falls back to LAPACK). */
int rr_eig_small(int n, double *a, double *wr, double *wi);
#endif
