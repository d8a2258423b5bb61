/* The vehicle's wheel and rail profiles ([contact] of a vehicle file) as the
 * linear model's conicity: the equivalent conicity at the section's
 * amplitude (docs/model.md, contact geometry from profiles). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/contact.h"
#include "util/internal.h"

#define GRID_MM 10.0
#define GRID_STEP_MM 0.01

int rr_vehicle_has_profiles(const rr_vehicle *v) { return v->wheel_rail.wheel[0][0] != 0; }

/* A path that fits a profile slot. */
static int path_fits(const char *path, const char *what, rr_error *err)
{
  if (strlen(path) < RR_PROFILE_PATH_MAX) return RR_OK;
  return rr_seterr(err, RR_EINVAL, "the %s profile's path is longer than %d bytes", what,
                   RR_PROFILE_PATH_MAX - 1);
}

int rr_vehicle_set_profiles(rr_vehicle *v, const char *wheel, const char *rail, rr_error *err)
{
  rr_wheel_rail *w = &v->wheel_rail;
  int has_rail = rail && rail[0];
  if (!wheel || !wheel[0]) return rr_seterr(err, RR_EINVAL, "no wheel profile given");
  if (!has_rail && !w->rail[0][0])
    return rr_seterr(err, RR_EINVAL, "a rail profile is needed (none given, none in [contact])");
  int rc = path_fits(wheel, "wheel", err);
  if (!rc && has_rail) rc = path_fits(rail, "rail", err);
  if (rc) return rc; /* checked first: v is unchanged on error */
  memcpy(w->wheel[0], wheel, strlen(wheel) + 1);
  w->wheel[1][0] = 0;
  if (has_rail) {
    memcpy(w->rail[0], rail, strlen(rail) + 1);
    w->rail[1][0] = 0;
  }
  return RR_OK;
}

static const char *base_name(const char *path)
{
  const char *b = strrchr(path, '/');
  return b ? b + 1 : path;
}

static rr_contact_opts opts_of(const rr_vehicle *v)
{
  const rr_wheel_rail *w = &v->wheel_rail;
  rr_contact_opts o = rr_contact_opts_default();
  o.gauge_mm = 1e3 * w->gauge;
  o.flange_back_mm = 1e3 * w->flange_back;
  o.wheel_origin_mm = 1e3 * w->wheel_origin;
  o.inclination = w->inclination;
  o.gmp_right_mm = o.gmp_left_mm = 1e3 * w->gauge_point; /* NaN: found */
  o.r0_right_mm = 1e3 * v->rolling_radius;
  o.r0_left_mm = isnan(w->radius_left) ? o.r0_right_mm : 1e3 * w->radius_left;
  o.roll = w->roll ? RR_ROLL_RIGID : RR_ROLL_NONE;
  return o;
}

/* The four profiles (a left one "" is its right one). */
static int load4(const rr_wheel_rail *w, rr_polyline *p, rr_error *err)
{
  const char *names[4] = {w->wheel[0], w->wheel[1][0] ? w->wheel[1] : w->wheel[0], w->rail[0],
                          w->rail[1][0] ? w->rail[1] : w->rail[0]};
  if (!w->rail[0][0])
    return rr_seterr(err, RR_EINVAL, "[contact] wheel: a rail profile is needed too");
  for (int k = 0; k < 4; k++) {
    int st = rr_polyline_load(names[k], &p[k], err);
    if (st) return st;
  }
  return RR_OK;
}

/* The contact of the vehicle's profiles at every y of the grid (y in mm;
   the caller frees both arrays). */
static int vehicle_states(const rr_vehicle *v, double **y_out, rr_contact_state **st_out, long *n,
                          rr_error *err)
{
  *y_out = NULL;
  *st_out = NULL;
  if (!rr_vehicle_has_profiles(v)) return rr_seterr(err, RR_EINVAL, "the vehicle has no profiles");
  rr_polyline p[4] = {{0}};
  rr_contact_plan *plan = NULL;
  long ny = rr_contact_range(-GRID_MM, GRID_MM, GRID_STEP_MM, NULL, 0);
  double *y = malloc(sizeof(double) * (size_t)ny);
  rr_contact_state *st = malloc(sizeof *st * (size_t)ny);
  rr_contact_opts o = opts_of(v);
  int rc = y && st ? load4(&v->wheel_rail, p, err) : rr_seterr(err, RR_ENOMEM, "out of memory");
  if (!rc) {
    rr_contact_range(-GRID_MM, GRID_MM, GRID_STEP_MM, y, ny);
    rc = rr_contact_plan_new(&p[0], &p[1], &p[2], &p[3], &o, &plan, err);
  }
  if (!rc) rc = rr_contact_execute(plan, y, (int)ny, st, err);
  rr_contact_plan_free(plan);
  for (int k = 0; k < 4; k++) rr_polyline_free(&p[k]);
  if (rc) {
    free(y);
    free(st);
    return rc;
  }
  *y_out = y;
  *st_out = st;
  *n = ny;
  return RR_OK;
}

/* The conicity plan of the vehicle's profiles on the grid (caller frees). */
static int profile_plan(const rr_vehicle *v, rr_conicity_plan **cp, rr_error *err)
{
  *cp = NULL;
  double *y, *dr = NULL;
  int *valid = NULL;
  rr_contact_state *st;
  long ny;
  int rc = vehicle_states(v, &y, &st, &ny, err);
  if (rc) return rc;
  dr = malloc(sizeof(double) * (size_t)ny);
  valid = malloc(sizeof(int) * (size_t)ny);
  if (!dr || !valid) rc = rr_seterr(err, RR_ENOMEM, "out of memory");
  for (long i = 0; !rc && i < ny; i++) {
    dr[i] = st[i].dr_mm;
    valid[i] = st[i].valid;
  }
  if (!rc) rc = rr_conicity_plan_new(y, dr, valid, (int)ny, cp, err);
  free(y);
  free(dr);
  free(valid);
  free(st);
  return rc;
}

void rr_contact_functions_free(rr_contact_functions *cf)
{
  if (!cf) return;
  free(cf->dr_m);
  free(cf->tan_right);
  free(cf->tan_left);
  free(cf->valid);
  *cf = (rr_contact_functions){0};
}

int rr_vehicle_contact_functions(const rr_vehicle *v, rr_contact_functions *out, rr_error *err)
{
  *out = (rr_contact_functions){0};
  double *y;
  rr_contact_state *st;
  long ny;
  int rc = vehicle_states(v, &y, &st, &ny, err);
  if (rc) return rc;
  size_t n = (size_t)ny;
  out->n = (int)ny;
  out->y0_m = 1e-3 * y[0];
  out->dy_m = 1e-3 * GRID_STEP_MM;
  out->dr_m = malloc(sizeof(double) * n);
  out->tan_right = malloc(sizeof(double) * n);
  out->tan_left = malloc(sizeof(double) * n);
  out->valid = malloc(sizeof(int) * n);
  if (!out->dr_m || !out->tan_right || !out->tan_left || !out->valid)
    rc = rr_seterr(err, RR_ENOMEM, "out of memory");
  for (size_t i = 0; !rc && i < n; i++) {
    out->dr_m[i] = 1e-3 * st[i].dr_mm;
    out->tan_right[i] = tan(st[i].side[0].gamma_rad);
    out->tan_left[i] = tan(st[i].side[1].gamma_rad);
    out->valid[i] = st[i].valid;
  }
  rr_contact_jump jumps[RR_CONTACT_EDGES_MAX / 2];
  int nj = rc ? 0 : rr_contact_jumps(st, (int)ny, jumps, RR_CONTACT_EDGES_MAX / 2);
  for (int j = 0; j < nj && j < RR_CONTACT_EDGES_MAX / 2; j++) {
    out->edge_y_m[out->nedges++] = 1e-3 * jumps[j].y_from_mm;
    out->edge_y_m[out->nedges++] = 1e-3 * jumps[j].y_to_mm;
  }
  if (!rc)
    snprintf(out->source, sizeof out->source, "profiles %s/%s", base_name(v->wheel_rail.wheel[0]),
             base_name(v->wheel_rail.rail[0]));
  free(y);
  free(st);
  if (rc) rr_contact_functions_free(out);
  return rc;
}

int rr_vehicle_profile_conicity_function(const rr_vehicle *v, const double *amp_mm, int namp,
                                         double *tan_ge, rr_error *err)
{
  rr_conicity_plan *cp;
  int rc = profile_plan(v, &cp, err);
  rr_contact_opts o = opts_of(v);
  for (int k = 0; !rc && k < namp; k++) {
    rr_conicity c;
    rr_conicity_eval(cp, amp_mm[k], o.wheel_origin_mm + o.flange_back_mm / 2, o.r0_right_mm, &c);
    tan_ge[k] = c.tan_gamma_e;
  }
  rr_conicity_plan_free(cp);
  return rc;
}

int rr_vehicle_profile_conicity(const rr_vehicle *v, double *conicity, char *source, size_t n,
                                rr_error *err)
{
  const rr_wheel_rail *w = &v->wheel_rail;
  double a = 1e3 * w->amplitude;
  int rc = rr_vehicle_profile_conicity_function(v, &a, 1, conicity, err);
  if (!rc && !(*conicity >= 0 && isfinite(*conicity)))
    rc = rr_seterr(err, RR_EINVAL,
                   "[contact]: the profiles' equivalent conicity at %g mm is undefined (no "
                   "equilibrium, or the oscillation leaves the valid contact data)",
                   a);
  if (!rc && source)
    snprintf(source, n, "profiles %s/%s at %g mm", base_name(w->wheel[0]), base_name(w->rail[0]),
             a);
  return rc;
}
