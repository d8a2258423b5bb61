/* Placement of the wheel and rail profiles (docs/contact.md, placement):
 * the rail file turned by its inclination, the gauge measuring point, and
 * the lateral positions of the wheel and rail origins. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "contact/contact_impl.h"
#include "util/internal.h"

rr_contact_opts rr_contact_opts_default(void)
{
  return (rr_contact_opts){.gauge_mm = 1435,
                           .flange_back_mm = 1360,
                           .wheel_origin_mm = 70,
                           .inclination = 0,
                           .gmp_depth_mm = 14,
                           .gmp_right_mm = NAN,
                           .gmp_left_mm = NAN,
                           .lateral_offset_mm = NAN,
                           .r0_right_mm = 460,
                           .r0_left_mm = 460,
                           .roll = RR_ROLL_NONE};
}

int rr_poly_segment(const double *x, int n, double at)
{
  int lo = 0, hi = n; /* searchsorted right: the first index with x > at */
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (x[mid] <= at)
      lo = mid + 1;
    else
      hi = mid;
  }
  int k = lo - 1;
  return k < 0 ? 0 : k > n - 2 ? n - 2 : k;
}

double rr_poly_interp(const double *x, const double *z, int n, double at)
{
  if (at == x[n - 1]) return z[n - 1];
  int k = rr_poly_segment(x, n, at);
  return (z[k + 1] - z[k]) / (x[k + 1] - x[k]) * (at - x[k]) + z[k];
}

/* The rail file turned by theta = atan(tan_i) about its origin (the head towards
   the track centre); it must still rise strictly in v. */
static int incline(rr_polyline *r, double tan_i, rr_error *err)
{
  if (tan_i == 0) return RR_OK;
  double th = atan(tan_i), c = cos(th), s = sin(th);
  for (int i = 0; i < r->n; i++) {
    double v = r->x[i], z = r->z[i];
    r->x[i] = c * v - s * z;
    r->z[i] = s * v + c * z;
  }
  for (int i = 1; i < r->n; i++)
    if (!(r->x[i] > r->x[i - 1]))
      return rr_seterr(err, RR_EINVAL,
                       "contact: the inclined rail profile no longer rises strictly (point %d)",
                       i + 1);
  return RR_OK;
}

/* The innermost point of the rail surface between the top of rail and
   depth below it (the crossing of the surface with that level, walking from
   the top towards the gauge side). */
static void gauge_point(const rr_polyline *r, double depth, double *v, double *z, int *at_end)
{
  int top = 0;
  for (int i = 1; i < r->n; i++)
    if (r->z[i] > r->z[top]) top = i;
  double lev = r->z[top] - depth;
  int k = top;
  while (k > 0 && r->z[k - 1] >= lev) k--;
  *at_end = k == 0;
  if (k == 0) {
    *v = r->x[0];
    *z = r->z[0];
    return;
  }
  double t = (lev - r->z[k - 1]) / (r->z[k] - r->z[k - 1]);
  *v = r->x[k - 1] + t * (r->x[k] - r->x[k - 1]);
  *z = lev;
}

void rr_poly_slopes(const double *x, const double *z, int n, double *k)
{
  for (int i = 0; i + 1 < n; i++) k[i] = (z[i + 1] - z[i]) / (x[i + 1] - x[i]);
}

static int check_opts(const rr_contact_opts *o, rr_error *err)
{
  if (!(o->gauge_mm > 0 && o->gauge_mm < 3000 && o->flange_back_mm > 0 &&
        o->flange_back_mm < 3000 && isfinite(o->wheel_origin_mm) && fabs(o->wheel_origin_mm) < 500))
    return rr_seterr(err, RR_EINVAL, "contact: gauge, flange back, wheel origin out of range");
  if (!(isfinite(o->inclination) && fabs(o->inclination) <= 0.5 && o->gmp_depth_mm >= 0 &&
        o->gmp_depth_mm < 100))
    return rr_seterr(err, RR_EINVAL, "contact: inclination or gauge point depth out of range");
  if (!(o->r0_right_mm > 50 && o->r0_right_mm < 2000 && o->r0_left_mm > 50 && o->r0_left_mm < 2000))
    return rr_seterr(err, RR_EINVAL, "contact: nominal radii must be within 50 .. 2000 mm");
  if (o->roll != RR_ROLL_NONE && o->roll != RR_ROLL_RIGID)
    return rr_seterr(err, RR_EINVAL, "contact: roll must be none or rigid");
  return RR_OK;
}

void rr_contact_plan_free(rr_contact_plan *p)
{
  if (!p) return;
  for (int s = 0; s < 2; s++) {
    rr_polyline_free(&p->wheel[s]);
    rr_polyline_free(&p->rail[s]);
    free(p->wheel_k[s]);
    free(p->rail_k[s]);
  }
  free(p);
}

void rr_contact_plan_setup(const rr_contact_plan *p, rr_contact_setup *out) { *out = p->setup; }

int rr_contact_plan_new(const rr_polyline *wheel_right, const rr_polyline *wheel_left,
                        const rr_polyline *rail_right, const rr_polyline *rail_left,
                        const rr_contact_opts *o, rr_contact_plan **out, rr_error *err)
{
  rr_contact_opts def = rr_contact_opts_default();
  if (!o) o = &def;
  *out = NULL;
  int st = check_opts(o, err);
  if (st) return st;
  rr_contact_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  const rr_polyline *w[2] = {wheel_right, wheel_left ? wheel_left : wheel_right},
                    *r[2] = {rail_right, rail_left ? rail_left : rail_right};
  const double gmp[2] = {o->gmp_right_mm, o->gmp_left_mm}, r0[2] = {o->r0_right_mm, o->r0_left_mm};
  rr_contact_setup *su = &p->setup;
  su->b_mm = o->flange_back_mm / 2 + o->wheel_origin_mm;
  p->roll = o->roll;
  for (int s = 0; s < 2 && !st; s++) {
    st = rr_polyline_from(w[s]->x, w[s]->z, w[s]->n, &p->wheel[s], err);
    if (!st) st = rr_polyline_from(r[s]->x, r[s]->z, r[s]->n, &p->rail[s], err);
    if (!st) st = incline(&p->rail[s], o->inclination, err);
    if (st) break;
    p->wheel_k[s] = malloc(sizeof(double) * (size_t)p->wheel[s].n);
    p->rail_k[s] = malloc(sizeof(double) * (size_t)p->rail[s].n);
    if (!p->wheel_k[s] || !p->rail_k[s]) {
      st = rr_seterr(err, RR_ENOMEM, "out of memory");
      break;
    }
    rr_poly_slopes(p->wheel[s].x, p->wheel[s].z, p->wheel[s].n, p->wheel_k[s]);
    rr_poly_slopes(p->rail[s].x, p->rail[s].z, p->rail[s].n, p->rail_k[s]);
    if (isnan(gmp[s])) {
      gauge_point(&p->rail[s], o->gmp_depth_mm, &su->gmp_v_mm[s], &su->gmp_z_mm[s],
                  &su->gmp_at_data_end[s]);
    } else {
      su->gmp_v_mm[s] = gmp[s];
      su->gmp_z_mm[s] = rr_poly_interp(p->rail[s].x, p->rail[s].z, p->rail[s].n, gmp[s]);
    }
    su->Y_mm[s] = o->gauge_mm / 2 - su->gmp_v_mm[s];
    if (!isnan(o->lateral_offset_mm)) su->Y_mm[s] = su->b_mm - o->lateral_offset_mm; /* given */
    su->offset_mm[s] = su->b_mm - su->Y_mm[s];
    su->r0_mm[s] = r0[s];
  }
  if (st) {
    rr_contact_plan_free(p);
    return st;
  }
  *out = p;
  return RR_OK;
}
