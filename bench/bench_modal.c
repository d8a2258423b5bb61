#define _POSIX_C_SOURCE 200809L
/* Benchmark: vehicle stability index and robust triple per evaluation, one
 * core (OpenBLAS single-threaded). Prints one line per figure. */
#include <stdio.h>
#include <string.h>
#include <time.h>
#include "railride/railride.h"
#include "bench_util.h"

/* Paper-mode SDF (type1, paper Table 2 curve): the index by the fast
   tracking and by the reference, the robust triple, one critical speed. */
static void bench_sdf_paper(void)
{
  rr_vehicle v;
  rr_model *m;
  rr_modal_ws *ws;
  rr_error e;
  rr_vehicle_default(&v);
  v.sdf_mode = RR_SDF_PAPER;
  if (rr_model_from_vehicle(&v, &m, &e) || rr_modal_ws_new(m, &ws, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    return;
  }
  rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e);
  double z = 0, t0;
  rr_modal_opts ref = rr_modal_opts_default();
  ref.tracking = RR_TRACK_REFERENCE;
  int reps = 200;
  rr_modal_stability_index(m, NULL, ws, &z, &e);
  t0 = bench_now();
  for (int i = 0; i < reps; i++) rr_modal_stability_index(m, NULL, ws, &z, &e);
  printf("sdf_paper_index_ms %.3f  (index %.6f)\n", (bench_now() - t0) / reps * 1e3, z);
  t0 = bench_now();
  for (int i = 0; i < 3; i++) rr_modal_stability_index(m, &ref, ws, &z, &e);
  printf("sdf_paper_index_reference_ms %.1f  (index %.6f)\n", (bench_now() - t0) / 3 * 1e3, z);
  rr_robust rb;
  t0 = bench_now();
  for (int i = 0; i < 20; i++) rr_robust_indices(m, NULL, NULL, ws, &rb, &e);
  printf("sdf_paper_robust_triple_ms %.2f\n", (bench_now() - t0) / 20 * 1e3);
  rr_critical cr;
  t0 = bench_now();
  rr_critical_speed(m, 0.4, NULL, NULL, ws, &cr, &e);
  printf("sdf_paper_critical_speed_s %.2f  (conicity 0.4: %.3f km/h)\n", bench_now() - t0,
         cr.speed_ms * RR_KMH);
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

/* The 8-lane batch's cost from the lanes falling out of step: each of the
 * eight conicities run as eight copies of itself (lanes in step throughout,
 * the same arithmetic per lane), against the eight mixed. Returns us a point. */
static double batch_in_step_us(rr_model *m, rr_modal_ws *ws, const double *lb, int reps)
{
  double vb[8], lc[8], t = 0;
  rr_stability zb[8];
  rr_error e;
  for (int c = 0; c < 8; c++) {
    for (int i = 0; i < 8; i++) {
      vb[i] = 350 / RR_KMH;
      lc[i] = lb[c];
    }
    double t0 = bench_now();
    for (int i = 0; i < reps / 64; i++) rr_modal_stability_batch(m, NULL, ws, 8, vb, lc, zb, &e);
    t += (bench_now() - t0) / (reps / 64) / 8;
  }
  return t / 8 * 1e6;
}

/* "index": only the eigenvalue figures bench/run.sh pairs with numpy's */
int main(int argc, char **argv)
{
  int quick = argc > 1 && !strcmp(argv[1], "index");
  openblas_set_num_threads(1);
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_model *m;
  rr_error e;
  rr_modal_ws *ws;
  rr_modal_result r;
  if (rr_model_from_vehicle(&v, &m, &e) || rr_modal_ws_new(m, &ws, &e) ||
      rr_modal_result_alloc(m, &r, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    return 1;
  }
  rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e);
  double z, t0;
  int reps = 3000;
  for (int i = 0; i < 100; i++) rr_modal_stability_index(m, NULL, ws, &z, &e);
  t0 = bench_now();
  for (int i = 0; i < reps; i++) rr_modal_stability_index(m, NULL, ws, &z, &e);
  printf("stability_index_us %.1f\n", (bench_now() - t0) / reps * 1e6);
  t0 = bench_now();
  for (int i = 0; i < reps / 3 && !quick; i++) rr_modal_solve(m, NULL, ws, &r, &e);
  if (!quick) printf("full_modal_solve_us %.1f\n", (bench_now() - t0) / (reps / 3) * 1e6);
  /* eight conicities at 350 km/h through the batched index (two groups of four lanes) */
  double vb[8], lb[8];
  rr_stability zb[8];
  for (int i = 0; i < 8; i++) {
    vb[i] = 350 / RR_KMH;
    lb[i] = 0.05 * (i + 1);
  }
  t0 = bench_now();
  for (int i = 0; i < reps / 8; i++) rr_modal_stability_batch(m, NULL, ws, 8, vb, lb, zb, &e);
  double t_mixed = (bench_now() - t0) / (reps / 8) / 8 * 1e6;
  printf("stability_index_batch_per_point_us %.1f\n", t_mixed);
  if (!quick) {
    double t_step = batch_in_step_us(m, ws, lb, reps);
    printf("stability_index_batch_in_step_per_point_us %.1f  (each conicity in all 8 lanes: "
           "the mixed batch costs %.2fx)\n",
           t_step, t_mixed / t_step);
  }
  rr_robust rb;
  t0 = bench_now();
  for (int i = 0; i < reps / 9; i++) rr_robust_indices(m, NULL, NULL, ws, &rb, &e);
  printf("robust_triple_us %.1f\n", (bench_now() - t0) / (reps / 9) * 1e6);
  if (quick) {
    rr_modal_result_free(&r);
    rr_modal_ws_free(ws);
    rr_model_free(m);
    return 0;
  }
  /* one design change + index: the optimiser's unit of work */
  t0 = bench_now();
  for (int i = 0; i < reps; i++) {
    v.primary_kx = 10e6 + (i % 100) * 1e6;
    rr_model_free(m);
    rr_model_from_vehicle(&v, &m, &e);
    rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e);
    rr_modal_stability_index(m, NULL, ws, &z, &e);
  }
  printf("rebuild_plus_index_us %.1f\n", (bench_now() - t0) / reps * 1e6);
  rr_modal_result_free(&r);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  bench_sdf_paper();
  return 0;
}
