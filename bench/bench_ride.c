/* Benchmark: one ride evaluation (400 frequencies, 3 floor points, SDF on):
 * FRF plan execute (eigendecomposition + per-frequency modal sums + SMW),
 * PEM PSD and, at each point, RMS, Sperling (filter and GB/T 5599 line
 * methods) and the Wd RMS by a comfort plan; one core. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "railride/railride.h"
#include "bench_util.h"

#define RR_BATCHES 15

static void run(const char *label, int sdf, int method, int reps)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  v.sdf_mode = sdf;
  rr_model *m;
  rr_error e;
  rr_spectrum sp;
  if (rr_model_from_vehicle(&v, &m, &e) || rr_spectrum_open("wuhan-guangzhou", &sp, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    exit(1);
  }
  rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e);
  double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[3 * 17];
  rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, 0, rows, NULL, &e);
  rr_frf_opts o = rr_frf_opts_default();
  o.npoints = 3;
  o.rows = rows;
  o.method = method;
  rr_frf_plan *p;
  rr_comfort_plan *cp;
  rr_frf_plan_new(m, &o, &p, &e);
  rr_comfort_plan_new(rr_frf_freqs(p), 400, RR_AXIS_LATERAL, &cp, &e);
  double G[1200], W[3];
  rr_comfort c;
  /* median of batch means: the machine's speed drifts during a run */
  double tb[RR_BATCHES], te[RR_BATCHES];
  for (int b = 0; b < RR_BATCHES; b++) {
    double t0 = bench_now(), texec = 0;
    for (int r = 0; r < reps; r++) {
      double t1 = bench_now();
      rr_frf_plan_execute(p, m, &e);
      texec += bench_now() - t1;
      rr_pem_psd(p, m, &sp, G, &e);
      for (int q = 0; q < 3; q++) {
        rr_comfort_execute(cp, G + q, 3, &c, &e);
        W[q] = c.sperling;
      }
    }
    tb[b] = (bench_now() - t0) / reps;
    te[b] = texec / reps;
  }
  double med = bench_median(tb, RR_BATCHES), best = tb[0]; /* sorted by the median */
  printf("ride_%s_us %.1f  (median of %d batches of %d, best %.1f; frf execute %.1f us; W = %.4f "
         "%.4f %.4f)\n",
         label, med * 1e6, RR_BATCHES, reps, best * 1e6, bench_median(te, RR_BATCHES) * 1e6, W[0],
         W[1], W[2]);
  rr_frf_plan_free(p);
  rr_comfort_plan_free(cp);
  rr_model_free(m);
}

int main(void)
{
  openblas_set_num_threads(1);
  run("sdf_paper_modal_smw", RR_SDF_PAPER, RR_FRF_MODAL, 40);
  run("sdf_physical_modal", RR_SDF_PHYSICAL, RR_FRF_MODAL, 40);
  run("no_sdf_modal", RR_SDF_NONE, RR_FRF_MODAL, 40);
  run("sdf_paper_modal_lapack", RR_SDF_PAPER, RR_FRF_MODAL_LAPACK, 40);
  run("sdf_paper_direct", RR_SDF_PAPER, RR_FRF_DIRECT, 4);
  return 0;
}
