/* The lateral ride's setup shared by the ride-type commands (ride, frf,
 * compare, summary, wear, validate, the vertical side's N_MV): the floor
 * point options, the library's ride options made from them, and one
 * evaluation through the library's ride plan. */
#include <math.h>
#include <string.h>
#include "cli.h"

/* The paper's floor points: above the bogie centres and the car's centre,
   x = +L, 0, -L (the library's default). */
void ride_default_points(ride_setup *r, const rr_vehicle *veh)
{
  r->npoints = rr_ride_points_default(veh, r->x);
}

void ride_setup_default(ride_setup *r, const rr_vehicle *veh)
{
  rr_ride_opts o = rr_ride_opts_default();
  *r = (ride_setup){.spectrum = RR_RIDE_SPECTRUM_DEFAULT,
                    .h_p = o.floor_height_m,
                    .roll_gravity = o.roll_gravity,
                    .f_lo = o.f_lo_hz,
                    .f_hi = o.f_hi_hz,
                    .nfreq = o.nfreq,
                    .method = o.method,
                    .when_unstable = o.when_unstable};
  ride_default_points(r, veh);
}

rr_ride_opts ride_opts(const ride_setup *r)
{
  rr_ride_opts o = rr_ride_opts_default();
  o.nfreq = r->nfreq;
  o.f_lo_hz = r->f_lo;
  o.f_hi_hz = r->f_hi;
  o.npoints = r->npoints;
  memcpy(o.x_points, r->x, sizeof(double) * (size_t)r->npoints);
  o.floor_height_m = r->h_p;
  o.roll_gravity = r->roll_gravity;
  o.method = r->method;
  o.when_unstable = r->when_unstable;
  return o;
}

void ride_setup_points(ride_setup *r, const rr_vehicle *veh, int argc, char **argv)
{
  for (int i = 1; i < argc; i++)
    if (!strncmp(argv[i], "--points", 8)) return;
  ride_default_points(r, veh);
}

cJSON *ride_methods_json(void)
{
  cJSON *m = cJSON_CreateObject();
  cJSON_AddStringToObject(m, "rms", "unweighted RMS, trapezoid over the band");
  cJSON_AddStringToObject(m, "sperling",
                          "Sperling Wz, weighting-filter method: 4.42 a_w^0.3, lateral B_w = 1.25 "
                          "B_s (docs/model.md section 7)");
  cJSON_AddStringToObject(
      m, "sperling_gb",
      "Sperling W, GB/T 5599 line method: 0.2 Hz bands from 0.5 Hz, lateral F(f)");
  cJSON_AddStringToObject(m, "wd_rms", "ISO 2631-1 / EN 12299 Wd-weighted RMS (ISO 8041 Wd)");
  cJSON_AddStringToObject(
      m, "en12299_nmv",
      "6 a_wd from the RMS, lateral axis only (stationary model: no 5 s percentile scatter)");
  return m;
}

const char *ride_num(char *buf, size_t len, int digits, double x, int stable)
{
  if (isnan(x)) return stable == 0 ? "unstable" : "none";
  snprintf(buf, len, "%.*f", digits, x);
  return buf;
}

/* PEM is a steady-state method: an unstable operating point's indices are
   undefined (the library's rule), or with --linear-when-unstable the linear
   response's; either way the reader is told once. */
static void warn_if_unstable(const ride_setup *r, const ride_point *p, double speed_kmh,
                             double conicity)
{
  if (p->stable != 0) return;
  fprintf(stderr, "railride: warning: unstable at %g km/h, conicity %g (zeta_max %.4g): %s\n",
          speed_kmh, conicity, p->zeta_max,
          r->when_unstable == RR_RIDE_LINEAR
              ? "the indices are the linear response's, not a steady-state ride comfort"
              : "the ride indices are undefined (--linear-when-unstable gives the linear "
                "response's)");
}

int ride_eval(const rr_vehicle *veh, double speed_kmh, double conicity, const ride_setup *r,
              ride_point *out, double *psd, double *freqs, rr_error *err)
{
  rr_model *m = NULL;
  rr_ride_plan *plan = NULL;
  rr_spectrum sp;
  rr_ride_opts o = ride_opts(r);
  int st = rr_spectrum_open(r->spectrum, &sp, err), opened = !st;
  if (!st) st = rr_spectrum_require(&sp, "lateral", "--spectrum: the lateral track input", err);
  if (!st) st = rr_model_from_vehicle(veh, &m, err);
  if (!st) st = rr_model_set_operating(m, speed_kmh / RR_KMH, conicity, err);
  if (!st) st = rr_ride_plan_new(m, veh, &o, &plan, err);
  if (!st) st = rr_ride_execute(plan, m, &sp, out, err);
  if (!st) warn_if_unstable(r, out, speed_kmh, conicity);
  size_t nf = st ? 0 : (size_t)rr_ride_nfreq(plan);
  if (!st && psd) memcpy(psd, rr_ride_psd(plan), sizeof(double) * nf * (size_t)r->npoints);
  if (!st && freqs) memcpy(freqs, rr_ride_freqs(plan), sizeof(double) * nf);
  rr_ride_plan_free(plan);
  rr_model_free(m);
  if (opened) rr_spectrum_close(&sp);
  return st;
}

int ride_setup_option(ride_setup *r, int opt, const char *arg)
{
  switch (opt) {
  case OPT_SPECTRUM: r->spectrum = arg; return 0;
  case OPT_POINTS:
    if (cli_list("points", arg, "m", r->x, 16, &r->npoints)) return 1;
    for (int i = 0; i < r->npoints; i++)
      if (!(fabs(r->x[i]) <= CLI_FLOOR_X_MAX))
        return cli_bad("--points: %g m outside -%g .. %g m", r->x[i], CLI_FLOOR_X_MAX,
                       CLI_FLOOR_X_MAX);
    return 0;
  case OPT_HEIGHT:
    return cli_number_in("floor-height", arg, "m", 0, CLI_FLOOR_H_MAX, &r->h_p) ? 1 : 0;
  case OPT_ROLLG: r->roll_gravity = 1; return 0;
  case OPT_LINEAR_UNSTABLE: r->when_unstable = RR_RIDE_LINEAR; return 0;
  }
  return -1;
}
