/* A small dense product C = A B (row-major, no transposes) for the shapes of
 * the ride's modal sums (30 x 38 times 38 x 400): register tiles of 6 rows by
 * up to 32 columns with the processor's widest FMA vectors. OpenBLAS, as
 * Debian ships it and as it runs under OPENBLAS_CORETYPE=Haswell, takes its
 * AVX2 kernel on an AVX-512 processor: 44 of a Zen 5 core's 131 GF/s.
 * Every entry is one FMA chain over k in order (c = a_0 b_0, then
 * c = fma(a_k, b_k, c)), so the AVX-512 and AVX2 paths give the same bits;
 * where neither is present, cblas_dgemm does the product. */
#ifndef RR_GEMM_H
#define RR_GEMM_H

enum { RR_GEMM_BLAS = 0, RR_GEMM_AVX2 = 1, RR_GEMM_AVX512 = 2 };

/* The widest path this processor runs (RR_GEMM_*). */
int rr_gemm_isa(void);
/* C (m x n, ldc) = A (m x k, lda) B (k x n, ldb), on the widest path. */
void rr_gemm_nn(int m, int n, int k, const double *a, int lda, const double *b, int ldb, double *c,
                int ldc);
/* The same on a given path (tests hold the paths to each other); a path the
 * processor lacks falls back to the widest it has. */
void rr_gemm_nn_isa(int isa, int m, int n, int k, const double *a, int lda, const double *b,
                    int ldb, double *c, int ldc);
#endif
