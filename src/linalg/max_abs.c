/* The largest |x_i|, eight lanes in four chains: GCC does not vectorise a
 * scalar max reduction (it must keep the order NaNs would be met in), and one
 * chain of compares waits on itself. max is exact in any grouping. */
#include "linalg/max_abs.h"
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "util/internal.h"

typedef double v8 __attribute__((vector_size(64)));
typedef long long l8 __attribute__((vector_size(64)));

/* m = max(m, |x[0..7]|) lane by lane */
#define MAX8(m, x)                                                                                 \
  do {                                                                                             \
    v8 a_;                                                                                         \
    memcpy(&a_, (x), sizeof a_);                                                                   \
    a_ = (v8)((l8)a_ & ((l8){0} + INT64_MAX));                                                     \
    l8 g_ = a_ > (m);                                                                              \
    (m) = (v8)(((l8)a_ & g_) | ((l8)(m) & ~g_));                                                   \
  } while (0)

RR_CLONES_V4 double rr_max_abs(size_t n, const double *x)
{
  v8 m0 = {0}, m1 = {0}, m2 = {0}, m3 = {0};
  size_t i = 0;
  for (; i + 32 <= n; i += 32) {
    MAX8(m0, x + i);
    MAX8(m1, x + i + 8);
    MAX8(m2, x + i + 16);
    MAX8(m3, x + i + 24);
  }
  for (; i + 8 <= n; i += 8) MAX8(m0, x + i);
  double m = 0;
  for (int k = 0; k < 8; k++) {
    double a = m0[k] > m1[k] ? m0[k] : m1[k], b = m2[k] > m3[k] ? m2[k] : m3[k];
    a = a > b ? a : b;
    m = a > m ? a : m;
  }
  for (; i < n; i++) m = fabs(x[i]) > m ? fabs(x[i]) : m;
  return m;
}
