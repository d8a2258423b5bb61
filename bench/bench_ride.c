/* Benchmark: one ride evaluation (400 frequencies, 3 floor points, SDF on):
 * the library's ride plan (rr_ride_execute): FRF plan execute (the default
 * sparse route: an LU of D(jw) a frequency, eight in SIMD lanes; or the
 * modal route: eigendecomposition + per-frequency modal sums + SMW), PEM PSD and, at
 * each point, RMS, Sperling (filter and GB/T 5599 line methods) and the Wd
 * RMS by a comfort plan; one core. */
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
  /* the library's ride plan (ride.h): the paper's floor points +L, 0, -L at 1.2 m */
  rr_ride_opts o = rr_ride_opts_default();
  o.method = method;
  /* the ride alone, as the numpy baselines compute it; the verdict that a
     default plan adds (rr_modal_stability at the point) is timed below */
  o.when_unstable = RR_RIDE_UNCHECKED;
  rr_ride_plan *p;
  if (rr_ride_plan_new(m, &v, &o, &p, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    exit(1);
  }
  rr_ride_point pt[3];
  /* median of batch means: the machine's speed drifts during a run; the
     FRF part alone timed in its own batches */
  double tb[RR_BATCHES], te[RR_BATCHES], td[RR_BATCHES];
  for (int b = 0; b < RR_BATCHES; b++) {
    double t0 = bench_now();
    for (int r = 0; r < reps; r++) rr_ride_execute(p, m, &sp, pt, &e);
    double t1 = bench_now();
    for (int r = 0; r < reps; r++) rr_ride_frf_execute(p, m, &e);
    double t2 = bench_now();
    /* an optimiser's designs at one speed: the track's PSD set once */
    rr_ride_plan_set_track(p, &sp, 350 / RR_KMH, &e);
    for (int r = 0; r < reps; r++) rr_ride_design(p, m, pt, &e);
    tb[b] = (t1 - t0) / reps;
    te[b] = (t2 - t1) / reps;
    td[b] = (bench_now() - t2) / reps;
  }
  double med = bench_median(tb, RR_BATCHES), best = tb[0]; /* sorted by the median */
  printf("ride_%s_us %.1f  (median of %d batches of %d, best %.1f; frf execute %.1f us; the track "
         "set once %.1f us; W = %.4f %.4f %.4f)\n",
         label, med * 1e6, RR_BATCHES, reps, best * 1e6, bench_median(te, RR_BATCHES) * 1e6,
         bench_median(td, RR_BATCHES) * 1e6, pt[0].sperling, pt[1].sperling, pt[2].sperling);
  rr_ride_plan_free(p);
  o.when_unstable = RR_RIDE_UNDEFINED;
  if (!rr_ride_plan_new(m, &v, &o, &p, &e) && !rr_ride_plan_set_track(p, &sp, 350 / RR_KMH, &e)) {
    for (int b = 0; b < RR_BATCHES; b++) {
      double t0 = bench_now();
      for (int r = 0; r < reps; r++) rr_ride_design(p, m, pt, &e);
      td[b] = (bench_now() - t0) / reps;
    }
    printf("ride_%s_with_verdict_us %.1f  (the track set once; the default plan, which takes the "
           "verdict at the point: stable %d)\n",
           label, bench_median(td, RR_BATCHES) * 1e6, pt[0].stable);
    rr_ride_plan_free(p);
  }
  rr_spectrum_close(&sp);
  rr_model_free(m);
}

int main(void)
{
  openblas_set_num_threads(1);
  run("sdf_paper_sparse", RR_SDF_PAPER, RR_FRF_SPARSE, 40); /* the default route */
  run("sdf_physical_sparse", RR_SDF_PHYSICAL, RR_FRF_SPARSE, 40);
  run("no_sdf_sparse", RR_SDF_NONE, RR_FRF_SPARSE, 40);
  run("sdf_paper_modal_smw", RR_SDF_PAPER, RR_FRF_MODAL, 40);
  run("sdf_physical_modal", RR_SDF_PHYSICAL, RR_FRF_MODAL, 40);
  run("no_sdf_modal", RR_SDF_NONE, RR_FRF_MODAL, 40);
  run("sdf_paper_modal_lapack", RR_SDF_PAPER, RR_FRF_MODAL_LAPACK, 40);
  run("sdf_paper_direct", RR_SDF_PAPER, RR_FRF_DIRECT, 4);
  return 0;
}
