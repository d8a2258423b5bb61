/* The stability index of the built-in vehicle, from C: the model built once
 * per design, a workspace once, then the operating point changed cheaply
 * and the index evaluated without allocating (an optimiser's inner loop);
 * several operating points in one batch share the SIMD lanes.
 *
 *   cc stability.c $(pkg-config --cflags --libs railride) -o stability && ./stability
 *
 * Prints, per speed and conicity, the index (its sign is the verdict:
 * negative stable), what set it, and the least damped mode's zeta. */
#include <stdio.h>
#include <railride/railride.h>

static int fail(const rr_error *e)
{
  fprintf(stderr, "stability: %s\n", e->msg);
  return 1;
}

static void row(double kmh, double conicity, const rr_stability *s)
{
  printf("%g,%g,%.17g,%s,%.17g\n", kmh, conicity, s->index, rr_index_source_name(s->source),
         s->zeta_max);
}

int main(void)
{
  rr_vehicle veh;
  rr_error e;
  rr_model *m;
  rr_modal_ws *ws;
  rr_stability s, out[4];
  rr_vehicle_default(&veh);
  if (rr_model_from_vehicle(&veh, &m, &e)) return fail(&e); /* M, C, K, B: once per design */
  if (rr_modal_ws_new(m, &ws, &e)) return fail(&e);        /* workspace: once */
  printf("speed_kmh,conicity,stability_index,set_by,zeta_max\n");
  /* one operating point: only the contact terms change */
  if (rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e) || rr_modal_stability(m, NULL, ws, &s, &e))
    return fail(&e);
  row(350, 0.17, &s);
  /* four at once (the paper's robust points and one more) */
  double v[4] = {250 / RR_KMH, 350 / RR_KMH, 350 / RR_KMH, 350 / RR_KMH};
  double lam[4] = {0.05, 0.05, 0.2, 0.4};
  if (rr_modal_stability_batch(m, NULL, ws, 4, v, lam, out, &e)) return fail(&e);
  for (int p = 0; p < 4; p++) row(v[p] * RR_KMH, lam[p], &out[p]);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  return 0;
}
