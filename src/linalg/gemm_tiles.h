/* The register tiles of rr_gemm_nn for one vector width: a template,
 * included by gemm.c once per path with GT_SUFFIX (the name's end), GT_TARGET
 * (the function attribute), GT_VEC and GT_W (the vector type, its doubles),
 * GT_NV (vectors in the widest tile), and GT_ZERO, GT_SET1, GT_LOAD,
 * GT_STORE, GT_FMA (a * b + c, one rounding). Every entry of C is one FMA
 * chain over k from 0 up, on either path and in the scalar column tail. */
#define GT_CAT_(a, b) a##b
#define GT_CAT(a, b) GT_CAT_(a, b)
#define gt_tile GT_CAT(gt_tile_, GT_SUFFIX)
#define gt_rows GT_CAT(gt_rows_, GT_SUFFIX)
#define gt_gemm GT_CAT(gt_gemm_, GT_SUFFIX)

/* C rows 0..MR-1, columns 0..NV GT_W - 1: MR x NV accumulators, each k one
   row of B in NV vectors and one broadcast of A's entry per row. */
GT_TARGET static inline __attribute__((always_inline)) void gt_tile(int mr, int nv, int k,
                                                                    const double *a, int lda,
                                                                    const double *b, int ldb,
                                                                    double *c, int ldc)
{
  GT_VEC acc[6][GT_NV], bv[GT_NV];
#pragma GCC unroll 6
  for (int i = 0; i < mr; i++)
#pragma GCC unroll 4
    for (int v = 0; v < nv; v++) acc[i][v] = GT_ZERO();
  for (int p = 0; p < k; p++) {
    const double *bp = b + (size_t)p * (size_t)ldb;
#pragma GCC unroll 4
    for (int v = 0; v < nv; v++) bv[v] = GT_LOAD(bp + GT_W * v);
#pragma GCC unroll 6
    for (int i = 0; i < mr; i++) {
      GT_VEC ai = GT_SET1(a[(size_t)i * (size_t)lda + (size_t)p]);
#pragma GCC unroll 4
      for (int v = 0; v < nv; v++) acc[i][v] = GT_FMA(ai, bv[v], acc[i][v]);
    }
  }
#pragma GCC unroll 6
  for (int i = 0; i < mr; i++)
#pragma GCC unroll 4
    for (int v = 0; v < nv; v++) GT_STORE(c + (size_t)i * (size_t)ldc + GT_W * v, acc[i][v]);
}

/* MR rows of C (a constant after inlining): whole tiles, then narrower
   ones, then the columns past the last whole vector one by one. */
GT_TARGET static inline __attribute__((always_inline)) void gt_rows(int mr, int n, int k,
                                                                    const double *a, int lda,
                                                                    const double *b, int ldb,
                                                                    double *c, int ldc)
{
  int j = 0;
  for (; j + GT_NV * GT_W <= n; j += GT_NV * GT_W)
    gt_tile(mr, GT_NV, k, a, lda, b + j, ldb, c + j, ldc);
  if (GT_NV > 2)
    for (; j + 2 * GT_W <= n; j += 2 * GT_W) gt_tile(mr, 2, k, a, lda, b + j, ldb, c + j, ldc);
  for (; j + GT_W <= n; j += GT_W) gt_tile(mr, 1, k, a, lda, b + j, ldb, c + j, ldc);
  for (; j < n; j++)
    for (int i = 0; i < mr; i++) {
      double s = 0;
      for (int p = 0; p < k; p++)
        s = __builtin_fma(a[(size_t)i * (size_t)lda + (size_t)p],
                          b[(size_t)p * (size_t)ldb + (size_t)j], s);
      c[(size_t)i * (size_t)ldc + (size_t)j] = s;
    }
}

GT_TARGET static void gt_gemm(int m, int n, int k, const double *a, int lda, const double *b,
                              int ldb, double *c, int ldc)
{
  for (int i = 0; i < m; i += 6) {
    const double *ai = a + (size_t)i * (size_t)lda;
    double *ci = c + (size_t)i * (size_t)ldc;
    switch (m - i < 6 ? m - i : 6) {
    case 6: gt_rows(6, n, k, ai, lda, b, ldb, ci, ldc); break;
    case 5: gt_rows(5, n, k, ai, lda, b, ldb, ci, ldc); break;
    case 4: gt_rows(4, n, k, ai, lda, b, ldb, ci, ldc); break;
    case 3: gt_rows(3, n, k, ai, lda, b, ldb, ci, ldc); break;
    case 2: gt_rows(2, n, k, ai, lda, b, ldb, ci, ldc); break;
    default: gt_rows(1, n, k, ai, lda, b, ldb, ci, ldc);
    }
  }
}

#undef gt_tile
#undef gt_rows
#undef gt_gemm
