/* C = A B for small row-major matrices: AVX-512 or AVX2 register tiles,
 * chosen at run time, else cblas_dgemm (see gemm.h). */
#include "linalg/gemm.h"
#include <cblas.h>
#include <stddef.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define RR_GEMM_TILES 1

/* AVX-512: 6 x 32 tiles, 24 accumulators of the 32 registers */
#define GT_SUFFIX avx512
#define GT_TARGET __attribute__((target("avx512f,avx2,fma")))
#define GT_VEC __m512d
#define GT_W 8
#define GT_NV 4
#define GT_ZERO() _mm512_setzero_pd()
#define GT_SET1(x) _mm512_set1_pd(x)
#define GT_LOAD(p) _mm512_loadu_pd(p)
#define GT_STORE(p, v) _mm512_storeu_pd(p, v)
#define GT_FMA(a, b, c) _mm512_fmadd_pd(a, b, c)
#include "linalg/gemm_tiles.h"
#undef GT_SUFFIX
#undef GT_TARGET
#undef GT_VEC
#undef GT_W
#undef GT_NV
#undef GT_ZERO
#undef GT_SET1
#undef GT_LOAD
#undef GT_STORE
#undef GT_FMA

/* AVX2: 6 x 8 tiles, 12 accumulators of the 16 registers */
#define GT_SUFFIX avx2
#define GT_TARGET __attribute__((target("avx2,fma")))
#define GT_VEC __m256d
#define GT_W 4
#define GT_NV 2
#define GT_ZERO() _mm256_setzero_pd()
#define GT_SET1(x) _mm256_set1_pd(x)
#define GT_LOAD(p) _mm256_loadu_pd(p)
#define GT_STORE(p, v) _mm256_storeu_pd(p, v)
#define GT_FMA(a, b, c) _mm256_fmadd_pd(a, b, c)
#include "linalg/gemm_tiles.h"
#endif

int rr_gemm_isa(void)
{
#if RR_GEMM_TILES
  /* libgcc and compiler-rt report AVX-512 and AVX only where the OS saves
     their registers; the init is for a caller that runs before their
     constructors (another library's) */
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return RR_GEMM_AVX512;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return RR_GEMM_AVX2;
#endif
  return RR_GEMM_BLAS;
}

void rr_gemm_nn_isa(int isa, int m, int n, int k, const double *a, int lda, const double *b,
                    int ldb, double *c, int ldc)
{
  int have = rr_gemm_isa();
  if (isa > have) isa = have;
#if RR_GEMM_TILES
  if (isa == RR_GEMM_AVX512) {
    gt_gemm_avx512(m, n, k, a, lda, b, ldb, c, ldc);
    return;
  }
  if (isa == RR_GEMM_AVX2) {
    gt_gemm_avx2(m, n, k, a, lda, b, ldb, c, ldc);
    return;
  }
#endif
  cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, m, n, k, 1.0, a, lda, b, ldb, 0.0, c, ldc);
}

void rr_gemm_nn(int m, int n, int k, const double *a, int lda, const double *b, int ldb, double *c,
                int ldc)
{
  rr_gemm_nn_isa(RR_GEMM_AVX512, m, n, k, a, lda, b, ldb, c, ldc);
}
