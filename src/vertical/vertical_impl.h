/* The vertical stage's shared internals: the plan (vertical_pem.c) and the
 * per-frequency solve (vertical_frf.c). */
#ifndef RR_VERTICAL_IMPL_H
#define RR_VERTICAL_IMPL_H

#include "railride/vertical.h"

struct rr_vertical_plan {
  rr_vertical_opts o;
  int n, np;
  double x[RR_VERTICAL_POINTS_MAX];
  double rows[RR_VERTICAL_POINTS_MAX * RR_VDOF];
  double *f, *wk2, *wb2, *wd2, *wc2, *trap;
  double *wbi2, *bs2; /* ISO 8041 Wb, Sperling's vertical B_s: |.|^2 on the grid */
  rr_complex *H, *Q;
  double *G, *Gt;
  double *Gx;                          /* pitch's longitudinal floor PSD */
  double *Qr, *Qi;                     /* q by coordinate: [d * n + k] */
  double *Er, *Ei;                     /* delay factors e^{-jw tau_j}: [j * n + k] */
  double delay_v, delay_d[RR_VINPUTS]; /* what they were made for (v 0: nothing yet) */
  double track_v;                      /* the speed Gt is for (0: no track set) */
  rr_comfort_plan *comfort;
  rr_window_plan *window;
  void *block; /* every array above, one allocation (plan_layout) */
};

/* Sets the floor points of the plan for model m (the default +L, 0, -L). */
int rr_vertical_set_points(rr_vertical_plan *p, const rr_vertical_model *m, rr_error *err);
/* The floor's coordinates in Qr, Qi (the ride's need; rr_vertical_frf_execute
   adds the frames' and Q), and with outputs the floor FRFs H. */
int rr_vertical_floor_response(rr_vertical_plan *p, const rr_vertical_model *m, double v,
                               int outputs, rr_error *err);

#endif
