/* Benchmark: one vertical ride evaluation (400 frequencies, 3 floor points:
 * the FRFs by the symmetric/antisymmetric blocks, the PSDs, RMS, Sperling by
 * both methods, Wk, EN and ISO Wb, the 5 s Wb RMS percentiles), and the
 * evaluation of `ride --direction both` (that, the lateral PEM at conicity
 * 0.17, its Wd 5 s percentiles and EN 12299's indices); one core. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include "railride/railride.h"
#include "bench_util.h"

#define RR_BATCHES 15
#define REPS 200

typedef struct lateral {
  rr_model *m;
  rr_frf_plan *p;
  rr_comfort_plan *cp;
  rr_spectrum sp;
  double G[1200];
} lateral;

static void die(const rr_error *e)
{
  fprintf(stderr, "%s\n", e->msg);
  exit(1);
}

static void lateral_new(const rr_vehicle *v, lateral *l)
{
  rr_error e;
  double xs[3] = {v->bogie_half_spacing, 0, -v->bogie_half_spacing}, rows[3 * 17];
  if (rr_model_from_vehicle(v, &l->m, &e) || rr_spectrum_open("wuhan-guangzhou", &l->sp, &e) ||
      rr_model_set_operating(l->m, 350 / RR_KMH, 0.17, &e) ||
      rr_vehicle_floor_rows(l->m, v, xs, 3, 1.2, 0, rows, NULL, &e))
    die(&e);
  rr_frf_opts o = rr_frf_opts_default();
  o.npoints = 3;
  o.rows = rows;
  if (rr_frf_plan_new(l->m, &o, &l->p, &e) ||
      rr_comfort_plan_new(rr_frf_freqs(l->p), 400, RR_AXIS_LATERAL, &l->cp, &e))
    die(&e);
}

/* the lateral side of `both`: PEM, its indices, the Wd percentiles, N */
static double lateral_eval(lateral *l, rr_vertical_plan *vp, const rr_vertical_point *pt)
{
  rr_error e;
  rr_comfort c;
  rr_window_stats wd[3];
  double n = 0;
  if (rr_frf_plan_execute(l->p, l->m, &e) || rr_pem_psd(l->p, l->m, &l->sp, l->G, &e) ||
      rr_vertical_window_stats(vp, l->G, 3, 3, RR_ISO_WD, wd, &e))
    die(&e);
  for (int q = 0; q < 3; q++) {
    if (rr_comfort_execute(l->cp, l->G + q, 3, &c, &e)) die(&e);
    rr_en12299_inputs in = {
        .ay50 = wd[q].p50, .ay95 = wd[q].p95, .az50 = pt[q].wb_5s.p50, .az95 = pt[q].wb_5s.p95};
    n += rr_en12299_indices(&in).n_mv;
  }
  return n;
}

int main(void)
{
  openblas_set_num_threads(1);
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_vertical_model m;
  rr_vertical_plan *p;
  rr_spectrum sp;
  rr_error e;
  rr_vertical_opts o = rr_vertical_opts_default();
  double t0 = bench_now();
  if (rr_vertical_model_build(&v, &m, &e) || rr_vertical_plan_new(&o, &p, &e) ||
      rr_spectrum_open("tbt3352-vertical", &sp, &e))
    die(&e);
  double tplan = bench_now() - t0;
  lateral l;
  lateral_new(&v, &l);
  rr_vertical_point pt[3];
  double tv[RR_BATCHES], td[RR_BATCHES], tb[RR_BATCHES], n = 0;
  for (int b = 0; b < RR_BATCHES; b++) {
    double t0b = bench_now();
    for (int r = 0; r < REPS; r++)
      if (rr_vertical_ride_execute(p, &m, 350 / RR_KMH, &sp, pt, &e)) die(&e);
    double t1 = bench_now();
    for (int r = 0; r < REPS; r++) /* the optimiser's loop: the track set once */
      if (rr_vertical_ride_design(p, &m, pt, &e)) die(&e);
    double t2 = bench_now();
    for (int r = 0; r < REPS; r++) {
      if (rr_vertical_ride_execute(p, &m, 350 / RR_KMH, &sp, pt, &e)) die(&e);
      n = lateral_eval(&l, p, pt);
    }
    tv[b] = (t1 - t0b) / REPS;
    td[b] = (t2 - t1) / REPS;
    tb[b] = (bench_now() - t2) / REPS;
  }
  printf("vertical_ride_us %.1f  (median of %d batches of %d; the plan %.0f us once; P95 = %.5f "
         "%.5f %.5f)\n",
         bench_median(tv, RR_BATCHES) * 1e6, RR_BATCHES, REPS, tplan * 1e6, pt[0].wb_5s.p95,
         pt[1].wb_5s.p95, pt[2].wb_5s.p95);
  printf("vertical_ride_design_us %.1f  (the same with the track's PSD set once: an optimiser's "
         "designs at one speed)\n",
         bench_median(td, RR_BATCHES) * 1e6);
  printf("ride_both_us %.1f  (vertical + lateral PEM + Wd percentiles + EN 12299; sum N_MV %.4f)\n",
         bench_median(tb, RR_BATCHES) * 1e6, n);
  rr_vertical_plan_free(p);
  rr_spectrum_close(&sp);
  rr_frf_plan_free(l.p);
  rr_comfort_plan_free(l.cp);
  rr_model_free(l.m);
  rr_spectrum_close(&l.sp);
  return 0;
}
