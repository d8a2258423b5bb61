/* NSGA-II's own work per generation (sorting, crowding, selection,
 * variation), without the designs' evaluation: DTLZ2 with 3 objectives and
 * 4 variables (the paper problem's shape), populations 5000 and 50000. Under
 * MPI every rank repeats this work, so it is the serial part of the cost
 * model in bench/mpi.sh. Prints "population seconds_per_generation". */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include "bench_util.h"
#include "railride/nsga2.h"
#include "railride/railride.h"

#define NVAR 4
#define NOBJ 3

static int dtlz2(void *user, int n, const double *x, double *f)
{
  (void)user;
  for (int i = 0; i < n; i++) {
    const double *xi = x + (size_t)i * NVAR;
    double g = 0;
    for (int j = NOBJ - 1; j < NVAR; j++) g += (xi[j] - 0.5) * (xi[j] - 0.5);
    double a = xi[0] * RR_PI / 2, b = xi[1] * RR_PI / 2;
    f[i * NOBJ + 0] = (1 + g) * cos(a) * cos(b);
    f[i * NOBJ + 1] = (1 + g) * cos(a) * sin(b);
    f[i * NOBJ + 2] = (1 + g) * sin(a);
  }
  return 0;
}

int main(void)
{
  static const int pops[] = {5000, 50000};
  double lo[NVAR] = {0, 0, 0, 0}, hi[NVAR] = {1, 1, 1, 1};
  for (int k = 0; k < 2; k++) {
    int N = pops[k], G = 10;
    rr_nsga2_opts o = rr_nsga2_opts_default();
    o.population = N;
    o.generations = G;
    o.hv_every = 0;
    double *X = malloc(sizeof(double) * N * NVAR), *F = malloc(sizeof(double) * N * NOBJ);
    int *rank = malloc(sizeof(int) * N);
    rr_error e;
    double t0 = bench_now();
    if (rr_nsga2_run(NVAR, NOBJ, lo, hi, dtlz2, NULL, &o, X, F, rank, &e)) {
      fprintf(stderr, "%s\n", e.msg);
      return 1;
    }
    printf("%d %.6f\n", N, (bench_now() - t0) / G);
    free(X);
    free(F);
    free(rank);
  }
  return 0;
}
