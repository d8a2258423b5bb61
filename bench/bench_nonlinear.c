#define _POSIX_C_SOURCE 200809L
/* The nonlinear model's speed: 60 s of simulated running at
 * 350 km/h, and a whole bifurcation diagram (100-600 km/h) by continuation
 * against the scan method at equal resolution: the scan's speed step is the
 * continuation's median step between neighbouring cycles, over the whole
 * range (the scan cannot know where the cycles are), up and down, 20 s to
 * settle and 2 s measured at each speed. One core. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "railride/railride.h"
#include "bench_util.h"

static void simulate(const char *veh_name, const char *prof)
{
  rr_vehicle v;
  rr_profile p;
  rr_error e;
  rr_vehicle_open(veh_name, &v, &e);
  rr_profile_open(prof, &p, &e);
  rr_nonlinear *nl;
  if (rr_nonlinear_from_vehicle(&v, &p, NULL, 350 / RR_KMH, &nl, &e)) {
    printf("%s\n", e.msg);
    return;
  }
  int N = rr_nonlinear_size(nl), ns = 60 * 200 + 1;
  double *z = calloc(N, sizeof(double)), *out = malloc(sizeof(double) * N * ns), t[5];
  for (int w = 0; w < 4; w++) z[rr_nonlinear_index_y(nl, w)] = 5e-3;
  rr_sim_opts so = rr_sim_opts_default();
  so.duration_s = 60;
  for (int r = 0; r < 5; r++) {
    double t0 = bench_now();
    rr_simulate(nl, z, &so, out, ns, &e);
    t[r] = bench_now() - t0;
  }
  printf("simulate %s %s: 60 s at 350 km/h (5 mm disturbance, 200 samples/s) in %.3f s (median of "
         "5)\n",
         veh_name, prof, bench_median(t, 5));
  free(z);
  free(out);
  rr_nonlinear_free(nl);
}

static void diagram(const char *veh_name, const char *prof, int with_scan)
{
  rr_vehicle v;
  rr_profile p;
  rr_error e;
  rr_vehicle_open(veh_name, &v, &e);
  rr_profile_open(prof, &p, &e);
  rr_cycle c[400];
  rr_bifurcation b;
  double t0 = bench_now();
  int st = rr_bifurcation_continue(&v, &p, NULL, NULL, c, NULL, 400, &b, &e);
  double tc = bench_now() - t0;
  if (st) {
    printf("%s %s: %s\n", veh_name, prof, e.msg);
    return;
  }
  double steps[400];
  int ns = 0;
  for (int i = 1; i < b.npoints; i++)
    steps[ns++] = fabs(c[i].speed_ms - c[i - 1].speed_ms) * RR_KMH;
  double step = ns ? bench_median(steps, ns) : 5;
  printf("continuation %s %s: %d cycles in %.2f s (Hopf %.2f km/h, nonlinear critical %.2f km/h, "
         "%s), median step %.2f km/h\n",
         veh_name, prof, b.npoints, tc, b.hopf_speed_ms * RR_KMH, b.nonlinear_critical_ms * RR_KMH,
         b.type == RR_BIF_SUPERCRITICAL ? "supercritical"
         : b.type == RR_BIF_SUBCRITICAL ? "subcritical"
                                        : "none",
         step);
  if (!with_scan) return;
  int nv = (int)floor(500 / step) + 1;
  double *vs = malloc(sizeof(double) * nv);
  rr_scan_point *up = malloc(sizeof *up * nv), *down = malloc(sizeof *down * nv);
  for (int i = 0; i < nv; i++) vs[i] = (100 + i * step) / RR_KMH;
  t0 = bench_now();
  st = rr_bifurcation_scan(&v, &p, NULL, vs, nv, NULL, up, down, &e);
  double ts = bench_now() - t0;
  int found = 0, settled = 0;
  double dev = 0; /* where both sweeps agree (settled), the scan against the stable branch */
  for (int i = 0; i < nv && !st; i++) {
    double au = up[i].amplitude_m, ad = down[i].amplitude_m;
    found += au > 0 || ad > 0;
    if (!(au > 0 && fabs(au - ad) <= 0.01 * au)) continue;
    for (int k = 1; k < b.npoints; k++)
      if (c[k - 1].stable && c[k].stable &&
          (c[k - 1].speed_ms - vs[i]) * (c[k].speed_ms - vs[i]) <= 0) {
        double u = (vs[i] - c[k - 1].speed_ms) / (c[k].speed_ms - c[k - 1].speed_ms),
               a = c[k - 1].amplitude_m + u * (c[k].amplitude_m - c[k - 1].amplitude_m);
        dev = fmax(dev, fabs(ad - a) / a);
        settled++;
        break;
      }
  }
  if (st)
    printf("scan: %s\n", e.msg);
  else
    printf("scan %s %s: %d speeds up and down in %.2f s: continuation %.1fx faster (the scan found "
           "cycles at %d speeds; at the %d where both sweeps agree within 1 %% on the stable "
           "branch, within %.2f %% of its amplitude)\n",
           veh_name, prof, nv, ts, ts / tc, found, settled, 100 * dev);
  free(vs);
  free(up);
  free(down);
}

int main(int argc, char **argv)
{
  openblas_set_num_threads(1);
  int scan = !(argc > 1 && !strcmp(argv[1], "--no-scan"));
  simulate("type1", "worn");
  simulate("type1", "new");
  diagram("type1", "worn", scan);
  diagram("type1", "new", 0);
  diagram("type2", "worn", scan);
  diagram("type2", "new", 0);
  return 0;
}
