/* Shared by the benchmarks: a monotonic clock and one-core BLAS. */
#ifndef RR_BENCH_UTIL_H
#define RR_BENCH_UTIL_H
#include <time.h>

void openblas_set_num_threads(int);

static inline double bench_now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}
#endif
