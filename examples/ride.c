/* The lateral ride of the built-in vehicle, from C: one call for one
 * operating point, then a plan reused over speeds (an optimiser's loop:
 * the plan is made once, each execute allocates nothing).
 *
 *   cc ride.c $(pkg-config --cflags --libs railride) -o ride && ./ride
 *
 * Prints, per speed and floor point, Sperling's index (weighting-filter and
 * GB/T 5599 line methods) and the Wd-weighted RMS. */
#include <stdio.h>
#include <railride/railride.h>

static int fail(const rr_error *e)
{
  fprintf(stderr, "ride: %s\n", e->msg);
  return 1;
}

int main(void)
{
  rr_vehicle veh;
  rr_error e;
  rr_vehicle_default(&veh);
  rr_ride_point pt[RR_RIDE_POINTS_MAX];
  /* one call: the paper's settings (400 frequencies 0.3-30 Hz, floor points
     +L, 0, -L 1.2 m above the rail, the Wuhan-Guangzhou alignment PSD) */
  if (rr_ride_evaluate(&veh, 350 / RR_KMH, 0.2, NULL, NULL, pt, &e)) return fail(&e);
  printf("speed_kmh,x_m,sperling,sperling_gb,wd_rms_ms2\n");
  for (int q = 0; q < 3; q++)
    printf("350,%.4f,%.6f,%.6f,%.6g\n", pt[q].x, pt[q].sperling, pt[q].sperling_gb, pt[q].wd_rms);

  /* many evaluations: model, plan and spectrum made once */
  rr_model *m;
  rr_ride_plan *plan;
  rr_spectrum sp;
  if (rr_model_from_vehicle(&veh, &m, &e)) return fail(&e);
  if (rr_ride_plan_new(m, &veh, NULL, &plan, &e) || rr_spectrum_open(RR_RIDE_SPECTRUM_DEFAULT, &sp, &e))
    return fail(&e);
  for (double v_kmh = 200; v_kmh <= 300; v_kmh += 50) {
    if (rr_model_set_operating(m, v_kmh / RR_KMH, 0.2, &e) || rr_ride_execute(plan, m, &sp, pt, &e))
      return fail(&e);
    for (int q = 0; q < rr_ride_npoints(plan); q++)
      printf("%g,%.4f,%.6f,%.6f,%.6g\n", v_kmh, pt[q].x, pt[q].sperling, pt[q].sperling_gb,
             pt[q].wd_rms);
  }
  rr_spectrum_close(&sp);
  rr_ride_plan_free(plan);
  rr_model_free(m);
  return 0;
}
