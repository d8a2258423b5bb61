/* Time integration of the nonlinear vehicle by SUNDIALS CVODES: BDF (orders
 * 1-5) with Newton iterations on the exact dense Jacobian. Error control: the
 * local error of every state within rtol |z| + atol, atol = atol_m for
 * displacements and strokes, 50 atol_m for velocities (a 8 Hz motion's
 * ratio). The track between its samples: cubic Hermite from the samples and
 * their rates, as the validation uses. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/nonlinear.h"
#include "nonlinear/ode_cvodes.h"
#include "util/internal.h"

#define RR_NL_MAX_INPUTS 16

rr_sim_opts rr_sim_opts_default(void)
{
  return (rr_sim_opts){.duration_s = 10, .fs_hz = 200, .rtol = 1e-7, .atol_m = 1e-10};
}

typedef struct sim_ctx {
  const rr_nonlinear *nl;
  const rr_sim_opts *o;
} sim_ctx;

/* y_t of every input at time t (Hermite between samples; held at the ends);
   NULL without a track. */
static const double *track_at(const sim_ctx *s, double t, double *yt)
{
  const rr_sim_opts *o = s->o;
  if (!o->yt || o->nsamples_track < 2) return NULL;
  int ns = o->nsamples_track, ni = rr_nonlinear_ninputs(s->nl);
  double x = t * o->fs_hz, h = 1 / o->fs_hz;
  int k = (int)floor(x);
  if (k < 0) k = 0;
  if (k > ns - 2) k = ns - 2;
  double u = fmin(fmax(x - k, 0), 1);
  double h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u),
         h01 = u * u * (3 - 2 * u), h11 = u * u * (u - 1);
  for (int i = 0; i < ni; i++) {
    const double *a = o->yt + (size_t)i * (size_t)ns, *da = o->dyt + (size_t)i * (size_t)ns;
    yt[i] = h00 * a[k] + h10 * h * da[k] + h01 * a[k + 1] + h11 * h * da[k + 1];
  }
  return yt;
}

static void sim_rhs(void *user, double t, double p, const double *z, double *dz)
{
  (void)p;
  sim_ctx *s = user;
  double yt[RR_NL_MAX_INPUTS];
  rr_nonlinear_rhs(s->nl, z, track_at(s, t, yt), dz);
}

static void sim_jac(void *user, double t, double p, const double *z, double *J)
{
  (void)p;
  sim_ctx *s = user;
  double yt[RR_NL_MAX_INPUTS];
  rr_nonlinear_jacobian(s->nl, z, track_at(s, t, yt), J);
}

/* RR_EDERAIL when a wheelset at time t stands beyond the contact data. */
static int check_contact(const sim_ctx *s, double t, const double *z, rr_error *err)
{
  double lo, hi, yt[RR_NL_MAX_INPUTS];
  rr_nonlinear_contact_range(s->nl, &lo, &hi);
  if (!isfinite(lo) && !isfinite(hi)) return RR_OK;
  const double *track = track_at(s, t, yt);
  for (int w = 0; w < rr_nonlinear_ninputs(s->nl); w++) {
    double d = z[rr_nonlinear_index_y(s->nl, w)] - (track ? track[w] : 0);
    if (!(d >= lo && d <= hi))
      return rr_seterr(err, RR_EDERAIL,
                       "simulate: wheelset %d at %.3f mm from the track centre line at t = %g s, "
                       "beyond the contact data (%.3f .. %.3f mm): a derailment indication",
                       w + 1, 1e3 * d, t, 1e3 * lo, 1e3 * hi);
  }
  return RR_OK;
}

void rr_nonlinear_atol(const rr_nonlinear *nl, double atol_m, double *atol)
{
  int N = rr_nonlinear_size(nl), n = rr_nonlinear_ndof(nl);
  for (int i = 0; i < N; i++) atol[i] = i >= n && i < 2 * n ? 50 * atol_m : atol_m;
}

int rr_simulate(const rr_nonlinear *nl, const double *z0, const rr_sim_opts *o, double *out,
                int nsamples, rr_error *err)
{
  rr_sim_opts def = rr_sim_opts_default();
  if (!o) o = &def;
  if (!(o->duration_s > 0 && o->fs_hz > 0 && o->rtol > 0 && o->atol_m > 0 && nsamples >= 1))
    return rr_seterr(err, RR_EINVAL, "simulate: need duration, fs, tolerances > 0");
  if (rr_nonlinear_ninputs(nl) > RR_NL_MAX_INPUTS)
    return rr_seterr(err, RR_EINVAL, "simulate: too many inputs");
  int N = rr_nonlinear_size(nl), st;
  sim_ctx s = {.nl = nl, .o = o};
  rr_ode ode = {.n = N, .rhs = sim_rhs, .jac = sim_jac, .user = &s};
  double *atol = malloc(sizeof(double) * (size_t)N);
  if (!atol) return rr_seterr(err, RR_ENOMEM, "out of memory");
  rr_nonlinear_atol(nl, o->atol_m, atol);
  ode_cv c;
  st = rr_ode_open(&c, &ode, rr_nonlinear_speed(nl), z0, o->rtol, atol, err);
  free(atol);
  if (st) return st;
  memcpy(out, z0, sizeof(double) * (size_t)N);
  st = check_contact(&s, 0, z0, err);
  for (int k = 1; k < nsamples && !st; k++) {
    double t = 0;
    int r = CVode(c.mem, k / o->fs_hz, c.y, &t, CV_NORMAL);
    const double *y = N_VGetArrayPointer(c.y);
    if (r < 0)
      st = rr_seterr(err, RR_ENOCONV, "simulate: CVODES failed at t = %g s (flag %d)", t, r);
    for (int i = 0; i < N && !st; i++)
      if (!isfinite(y[i]))
        st = rr_seterr(err, RR_ENOCONV, "simulate: the state is not finite at t = %g s", t);
    if (!st) st = check_contact(&s, t, y, err);
    if (!st) memcpy(out + (size_t)k * (size_t)N, y, sizeof(double) * (size_t)N);
    if (!st) st = rr_progress_step(&o->progress, k + 1, nsamples, err);
  }
  rr_ode_close(&c);
  return st;
}
