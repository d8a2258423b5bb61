/* A fixed workload for instruction counts (bench/against-icount.sh): the index,
 * an 8-lane batch, the robust triple or the lateral ride, REPS times, on the
 * default vehicle at 350 km/h, conicity 0.17. Usage: icount WHAT REPS. Built
 * against either tree (the ride through the ride plan where ride.h exists). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <railride/railride.h>
int main(int argc, char **argv)
{
  const char *what = argv[1];
  int reps = atoi(argv[2]);
  rr_vehicle v;
  rr_error e;
  rr_model *m;
  rr_modal_ws *ws;
  double z = 0;
  rr_vehicle_default(&v);
  rr_model_from_vehicle(&v, &m, &e);
  rr_modal_ws_new(m, &ws, &e);
  rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e);
  if (!strcmp(what, "index"))
    for (int i = 0; i < reps; i++) rr_modal_stability_index(m, NULL, ws, &z, &e);
  if (!strcmp(what, "batch")) {
    double vb[8], lb[8];
    rr_stability zb[8];
    for (int k = 0; k < 8; k++) {
      vb[k] = (250 + 10 * k) / RR_KMH;
      lb[k] = 0.05 + 0.05 * k;
    }
    for (int i = 0; i < reps; i++) rr_modal_stability_batch(m, NULL, ws, 8, vb, lb, zb, &e);
    z = zb[3].index;
  }
  if (!strcmp(what, "robust")) {
    rr_robust rb;
    for (int i = 0; i < reps; i++) rr_robust_indices(m, NULL, NULL, ws, &rb, &e);
    z = rb.zeta_low;
  }
  if (!strcmp(what, "ride")) {
    rr_spectrum sp;
    rr_spectrum_open("wuhan-guangzhou", &sp, &e);
#ifdef RR_RIDE_POINTS_MAX
    rr_ride_plan *p;
    rr_ride_point pt[3];
    rr_ride_plan_new(m, &v, NULL, &p, &e);
    for (int i = 0; i < reps; i++) rr_ride_execute(p, m, &sp, pt, &e);
    z = pt[0].sperling;
#else
    double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[3 * 17], G[1200];
    rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, 0, rows, NULL, &e);
    rr_frf_opts o = rr_frf_opts_default();
    o.npoints = 3;
    o.rows = rows;
    rr_frf_plan *p;
    rr_comfort_plan *cp;
    rr_comfort c;
    rr_frf_plan_new(m, &o, &p, &e);
    rr_comfort_plan_new(rr_frf_freqs(p), 400, RR_AXIS_LATERAL, &cp, &e);
    for (int i = 0; i < reps; i++) {
      rr_frf_plan_execute(p, m, &e);
      rr_pem_psd(p, m, &sp, G, &e);
      for (int q = 0; q < 3; q++) rr_comfort_execute(cp, G + q, 3, &c, &e);
      z = c.sperling;
    }
#endif
  }
  printf("%s %.12g\n", what, z);
  return 0;
}
