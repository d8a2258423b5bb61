/* Benchmark: design evaluations per second for the paper's three objectives
 * (zeta_low, zeta_high, std_zeta: 9 eigen-solves a design), 1 and 2 threads. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "railride/railride.h"
#include "bench_util.h"

int main(int argc, char **argv)
{
  openblas_set_num_threads(1);
  int n = argc > 1 ? atoi(argv[1]) : 4000;
  rr_vehicle v;
  rr_vehicle_default(&v);
  const char *keys[4] = {"primary.longitudinal_stiffness", "lateral_damper.damping",
                         "yaw_damper.damping", "yaw_damper.series_stiffness"};
  const char *objs[3] = {"zeta_low", "zeta_high", "std_zeta"};
  const double lo[4] = {10e6, 5e3, 100e3, 1e6}, hi[4] = {120e6, 60e3, 4000e3, 30e6};
  rr_design *d;
  rr_error e;
  if (rr_design_new(&v, 4, keys, 3, objs, &d, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    return 1;
  }
  double *x = malloc(sizeof(double) * n * 4), *f = malloc(sizeof(double) * n * 3);
  unsigned s = 1;
  for (int i = 0; i < n * 4; i++) {
    s = s * 1664525u + 1013904223u;
    x[i] = lo[i % 4] + (hi[i % 4] - lo[i % 4]) * ((s >> 8) / 16777216.0);
  }
  double rate[3] = {0, 0, 0};
  for (int t = 1; t <= 2; t++) {
    rr_design_evaluate_batch(d, 64, x, f, t, NULL, NULL); /* warm: thread contexts */
    double t0 = bench_now();
    rr_design_evaluate_batch(d, n, x, f, t, NULL, NULL);
    rate[t] = n / (bench_now() - t0);
    printf("designs_per_s_%d_thread%s %.0f\n", t, t > 1 ? "s" : "", rate[t]);
  }
  printf("speedup_1_to_2_threads %.2f\n", rate[2] / rate[1]);
  printf("paper_run_500k_designs_projected_s %.0f\n", 505000 / rate[2]);
  rr_design_free(d);
  free(x);
  free(f);
  return 0;
}
