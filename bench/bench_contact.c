#define _POSIX_C_SOURCE 200809L
/* Contact geometry and equivalent conicity: one profile pair (EN 15302's
 * wheel A, 1001 points, on rail S-UIC 519-A, 1001 points), the 2001-point y
 * grid -10:10:0.01, 66 amplitudes 1.0-7.5 mm by all three methods: the
 * profiles read, the contact searched, the conicity function, all included;
 * no roll and rigid roll. Medians of 7 runs. Run from the source tree's root
 * (bench/run.sh). */
#include <stdio.h>
#include "bench_util.h"
#include "railride/contact.h"

static double run(rr_contact_roll roll, double *tg3)
{
  double y[2001], dr[2001];
  int valid[2001];
  static rr_contact_state st[2001];
  rr_error e;
  double t0 = bench_now();
  rr_polyline w, r;
  if (rr_polyline_load("profiles/en15302/RUIC519A.dat", &w, &e) ||
      rr_polyline_load("profiles/en15302/SUIC519A.dat", &r, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    exit(1);
  }
  rr_contact_opts o = rr_contact_opts_default();
  o.gmp_right_mm = o.gmp_left_mm = -32.5;
  o.roll = roll;
  rr_contact_plan *p;
  int n = (int)rr_contact_range(-10, 10, 0.01, y, 2001);
  if (rr_contact_plan_new(&w, NULL, &r, NULL, &o, &p, &e) || rr_contact_execute(p, y, n, st, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    exit(1);
  }
  for (int i = 0; i < n; i++) {
    dr[i] = st[i].dr_mm;
    valid[i] = st[i].valid;
  }
  rr_conicity_plan *cp;
  if (rr_conicity_plan_new(y, dr, valid, n, &cp, &e)) exit(1);
  rr_conicity c;
  for (int k = 0; k < 66; k++) rr_conicity_eval(cp, 1.0 + 0.1 * k, 750, 460, &c);
  rr_conicity_eval(cp, 3.0, 750, 460, &c);
  *tg3 = c.tan_gamma_e;
  double t = bench_now() - t0;
  rr_conicity_plan_free(cp);
  rr_contact_plan_free(p);
  rr_polyline_free(&w);
  rr_polyline_free(&r);
  return t;
}

int main(void)
{
  double t[7], tg;
  for (int k = 0; k < 7; k++) t[k] = run(RR_ROLL_NONE, &tg);
  printf("contact_pair_no_roll_ms %.1f  (tan_gamma_e at 3 mm %.5f)\n", 1e3 * bench_median(t, 7),
         tg);
  for (int k = 0; k < 3; k++) t[k] = run(RR_ROLL_RIGID, &tg);
  printf("contact_pair_rigid_roll_ms %.1f  (tan_gamma_e at 3 mm %.5f)\n", 1e3 * bench_median(t, 3),
         tg);
  return 0;
}
