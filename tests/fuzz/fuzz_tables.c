/* The nonlinear model's two-column readers: tread profile tables (then the
 * conicity over 0-30 mm) and measured alignment records (then sampled for
 * the Type 1 vehicle's contacts at 300 km/h), wheel and rail profiles
 * (then in contact with themselves), and dr(y) tables (then their equivalent
 * conicity by the three methods). The first input byte picks the reader. */
#include "fuzz_common.h"
#include "railride/contact.h"
#include <math.h>

static void profile(const uint8_t *data, size_t size)
{
  rr_profile p;
  rr_error e;
  if (rr_profile_load(fuzz_file("p.csv", data, size), &p, &e)) return;
  for (int i = 0; i <= 60; i++) {
    double l = rr_profile_conicity(&p, i * 0.5e-3);
    if (!(l > 0 && l <= 5)) abort();
  }
}

static void record(const uint8_t *data, size_t size)
{
  rr_track_record r;
  rr_error e;
  if (rr_track_record_load(fuzz_file("t.csv", data, size), &r, &e)) return;
  double x[4] = {9.9375, 7.4375, -7.4375, -9.9375}, v = 300 / RR_KMH, fs = 100;
  double dur = rr_track_record_duration(&r, v, x, 4);
  int ns = dur > 0 ? (int)fmin(floor(dur * fs) + 1, 2000) : 0;
  if (ns >= 2) {
    double *u = malloc(sizeof(double) * 4 * ns), *du = malloc(sizeof(double) * 4 * ns);
    if (!rr_track_record_sample(&r, v, x, 4, fs, ns, u, du, &e))
      for (int i = 0; i < 4 * ns; i++)
        if (!isfinite(u[i]) || fabs(u[i]) > 1) abort();
    free(u);
    free(du);
  }
  rr_track_record_free(&r);
}

/* A wheel or rail profile (contact geometry): accepted ones put in contact
   with themselves at a few displacements, every number finite or an error. */
static void polyline(const uint8_t *data, size_t size)
{
  rr_polyline p;
  rr_error e;
  if (rr_polyline_load(fuzz_file("w.dat", data, size), &p, &e)) return;
  rr_contact_plan *plan;
  rr_contact_opts o = rr_contact_opts_default();
  o.lateral_offset_mm = 0;
  if (!rr_contact_plan_new(&p, NULL, &p, NULL, &o, &plan, &e)) {
    double y[5] = {-2, -1, 0, 1, 2};
    rr_contact_state st[5];
    if (!rr_contact_execute(plan, y, 5, st, &e))
      for (int i = 0; i < 5; i++)
        if (!isfinite(st[i].dr_mm) || !isfinite(st[i].side[0].gamma_rad)) abort();
    rr_contact_plan_free(plan);
  }
  rr_polyline_free(&p);
}

/* A dr(y) table from the bytes (y rising in steps of 0.01-2.56 mm, dr from
   16-bit integers in um): each method's conicity is finite or undefined
   (NaN), never infinite. */
static void conicity(const uint8_t *data, size_t size)
{
  enum { NMAX = 400 };
  double y[NMAX], dr[NMAX];
  int n = 0;
  for (size_t i = 0; i + 2 < size && n < NMAX; i += 3, n++) {
    y[n] = (n ? y[n - 1] : -0.005 * (double)(size / 3)) + 0.01 * (1 + data[i]);
    dr[n] = (int16_t)(data[i + 1] | data[i + 2] << 8) * 1e-3;
  }
  rr_conicity_plan *cp;
  rr_error e;
  if (rr_conicity_plan_new(y, dr, NULL, n, &cp, &e)) return;
  const double A[4] = {0.5, 1, 3, 7.5};
  for (int k = 0; k < 4; k++) {
    rr_conicity c;
    rr_conicity_eval(cp, A[k], 750, 460, &c);
    if (isinf(c.tan_gamma_e) || isinf(c.tan_gamma_e_harmonic) || isinf(c.tan_gamma_e_regression))
      abort();
    if (!isnan(c.tan_gamma_e) && !(isfinite(c.turning_mm[0]) && isfinite(c.turning_mm[1]))) abort();
  }
  rr_conicity_plan_free(cp);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  if (size < 1) return 0;
  if (data[0] == 255) /* apart from the three readers: the seeds keep their reader */
    conicity(data + 1, size - 1);
  else if (data[0] % 3 == 1)
    record(data + 1, size - 1);
  else if (data[0] % 3 == 2)
    polyline(data + 1, size - 1);
  else
    profile(data + 1, size - 1);
  return 0;
}
