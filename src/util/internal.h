/* Internal helpers shared by the library's sources. */
#ifndef RR_INTERNAL_H
#define RR_INTERNAL_H

#include <stddef.h>
#include "railride/common.h"
#include "railride/error.h"

#if defined(__GNUC__)
#define RR_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define RR_PRINTF(a, b)
#endif

/* AVX2 + FMA copies of a hot function, chosen at load time where the
   processor has them; the kernels it calls must be always_inline (RR_INLINE)
   so that they are compiled into each copy. */
/* RR_NO_CLONES: one copy for the compiler's target only (tests/test_isa.c
   builds the kernels so, for the baseline x86-64, to hold the clones to it). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) &&       \
    !defined(RR_NO_CLONES)
#define RR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#define RR_HAVE_V4 1 /* an AVX-512 copy of the 8-lane batch, used where present */
#else
#define RR_CLONES
#define RR_HAVE_V4 0
#endif
/* The same with an AVX-512 copy too, for loops that run 8 lanes wide. */
#if RR_HAVE_V4
#define RR_CLONES_V4 __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define RR_CLONES_V4 RR_CLONES
#endif
#if defined(__GNUC__)
#define RR_INLINE static inline __attribute__((always_inline))
#else
#define RR_INLINE static inline
#endif

/* Fills err (when non-NULL) and returns code. */
int rr_seterr(rr_error *err, int code, const char *fmt, ...) RR_PRINTF(3, 4);

#define RR_G 9.81

/* out = sum over i0 <= i < n of r[i] y[i], for T double or a vector of
 * lanes, in four partial sums: a single chain would wait on every add. */
#define DOT4(T, r, y, i0, n, out)                                                                  \
  do {                                                                                             \
    T a0_ = {0}, a1_ = {0}, a2_ = {0}, a3_ = {0};                                                  \
    int i_ = (i0);                                                                                 \
    for (; i_ + 3 < (n); i_ += 4) {                                                                \
      a0_ += (r)[i_] * (y)[i_];                                                                    \
      a1_ += (r)[i_ + 1] * (y)[i_ + 1];                                                            \
      a2_ += (r)[i_ + 2] * (y)[i_ + 2];                                                            \
      a3_ += (r)[i_ + 3] * (y)[i_ + 3];                                                            \
    }                                                                                              \
    for (; i_ < (n); i_++) a0_ += (r)[i_] * (y)[i_];                                               \
    (out) = (a0_ + a1_) + (a2_ + a3_);                                                             \
  } while (0)

/* Whether x[0 .. n) are all finite, in one pass that vectorises: x * 0 is 0
   for every finite x and NaN for an infinity or a NaN. The caller finds the
   culprit only when this says no. */
RR_INLINE int rr_all_finite(size_t n, const double *x)
{
  double z[8] = {0}; /* eight sums, one vector: no chain through one register */
  size_t i = 0;
  for (; i + 7 < n; i += 8)
    for (size_t e = 0; e < 8; e++) z[e] += x[i + e] * 0;
  for (; i < n; i++) z[0] += x[i] * 0;
  return ((z[0] + z[1]) + (z[2] + z[3])) + ((z[4] + z[5]) + (z[6] + z[7])) == 0;
}

/* Reports a step to the caller's progress callback (if any); RR_ESTOPPED,
   with err filled, when the callback asks to stop. */
int rr_progress_step(const rr_progress *pr, long done, long total, rr_error *err);

#endif
