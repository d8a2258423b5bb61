/* Vectors of L doubles (GCC's and Clang's vector extension) for the lane
 * kernels that run one problem a SIMD lane: the includer defines L first.
 * A vector is never passed by value, so that the clones keep one ABI. The
 * arrays' entries are whole vectors, aligned (block.h), read and written
 * through vector lvalues: a vector aliases its element type (double) and
 * nothing else, so index arrays stay in registers across the stores (memcpy
 * would alias them too). Vector compares belong in the cloned functions
 * themselves: GCC lowers an inlined body's generic vector operations for the
 * body's own (default) target first, which splits a compare into scalar ones. */
#ifndef RR_LANE_VECTOR_H
#define RR_LANE_VECTOR_H

#include <stdint.h>

typedef double vd __attribute__((vector_size(8 * L)));
typedef long long vl __attribute__((vector_size(8 * L)));
#define VLOAD(p) (*(const vd *)(const void *)(p))
#define VSTORE(p, v) (*(vd *)(void *)(p) = (v))
#define VABS(x) ((vd)((vl)(x) & ((vl){0} + INT64_MAX)))
#define VSEL(m, a, b) ((vd)(((vl)(a) & (m)) | ((vl)(b) & ~(m))))
/* a b + c rounded once in each lane: one FMA instruction where the target
   has FMA (GCC's and Clang's vectorisers make the lane loop one), libm's
   fma where it has not, so the same bits on every target. */
#define VFMA(a, b, c) VFMA_N(a, b, c, __COUNTER__) /* locals named apart: VFMAs nest */
#define VFMA_N(a, b, c, n) VFMA_(a, b, c, n)
#define VFMA_(a, b, c, n)                                                                          \
  __extension__({                                                                                  \
    vd a_##n = (a), b_##n = (b), c_##n = (c), r_##n;                                               \
    for (int l_ = 0; l_ < L; l_++) r_##n[l_] = __builtin_fma(a_##n[l_], b_##n[l_], c_##n[l_]);     \
    r_##n;                                                                                         \
  })

#endif
