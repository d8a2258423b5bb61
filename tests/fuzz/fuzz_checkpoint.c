/* NSGA-II checkpoints: a damaged or crafted file resumed must be refused
 * (never UB, a hang, or a design outside its bounds in the result). The
 * problem is small and fixed: 2 variables in [0, 1], 2 objectives,
 * population 4, 3 generations, seed 1, a fingerprint of two parts; the seed
 * corpus holds a valid checkpoint of it, written by rr_nsga2_run on this
 * problem stopped after its first generation. */
#include "fuzz_common.h"
#include <math.h>

static int eval(void *user, int n, const double *x, double *f)
{
  (void)user;
  for (int i = 0; i < n; i++) {
    f[2 * i] = x[2 * i];
    f[2 * i + 1] = 1 - sqrt(x[2 * i]) + x[2 * i + 1];
  }
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const double lo[2] = {0, 0}, hi[2] = {1, 1};
  double X[8], F[8];
  int rank[4];
  rr_nsga2_opts o = rr_nsga2_opts_default();
  o.population = 4;
  o.generations = 3;
  o.seed = 1;
  o.fingerprint = (rr_nsga2_fingerprint){.n = 2, .part = {11, 22}, .name = {"a", "b"}};
  o.resume = fuzz_file("c.bin", data, size);
  rr_error e;
  if (rr_nsga2_run(2, 2, lo, hi, eval, NULL, &o, X, F, rank, &e)) return 0;
  for (int i = 0; i < 8; i++)
    if (!(X[i] >= 0 && X[i] <= 1) || isnan(F[i])) abort(); /* accepted: within its bounds */
  for (int i = 0; i < 4; i++)
    if (rank[i] < 0 || rank[i] >= 4) abort();
  return 0;
}
