/* Shared by the benchmarks: a monotonic clock and one-core BLAS. */
#ifndef RR_BENCH_UTIL_H
#define RR_BENCH_UTIL_H
#include <stdlib.h>
#include <time.h>

void openblas_set_num_threads(int);

static inline double bench_now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int bench_cmp(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Median of n timings (sorts them). */
static inline double bench_median(double *t, int n)
{
  qsort(t, n, sizeof *t, bench_cmp);
  return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}
#endif
