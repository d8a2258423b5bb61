/* The lateral ride evaluation, planned once: floor rows, FRF plan, PEM
 * PSDs and comfort plan (include/railride/ride.h). The one place that
 * assembles these stages; the CLI, the design objectives and validation
 * all take it from here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/ride.h"
#include "util/internal.h"

struct rr_ride_plan {
  int np, nfreq;
  double x[RR_RIDE_POINTS_MAX];
  double *rows, *rows0; /* np x ndof */
  int roll_gravity;
  double *G;      /* nfreq x np */
  double *Gt;     /* the track's temporal PSD on the grid (rr_ride_plan_set_track), m^2/Hz */
  double track_v; /* the speed it is for, m/s (0: none yet) */
  rr_frf_plan *frf;
  rr_comfort_plan *comfort;
  rr_ride_unstable when_unstable;
  rr_modal_ws *mws; /* the verdict's eigenvalues */
};

rr_ride_opts rr_ride_opts_default(void)
{
  rr_frf_opts fo = rr_frf_opts_default();
  return (rr_ride_opts){.nfreq = fo.nfreq,
                        .f_lo_hz = fo.f_lo_hz,
                        .f_hi_hz = fo.f_hi_hz,
                        .floor_height_m = RR_FLOOR_HEIGHT_DEFAULT,
                        .method = fo.method,
                        .when_unstable = RR_RIDE_UNDEFINED};
}

int rr_ride_points_default(const rr_vehicle *veh, double *x)
{
  x[0] = veh->bogie_half_spacing;
  x[1] = 0;
  x[2] = -veh->bogie_half_spacing;
  return 3;
}

void rr_ride_plan_free(rr_ride_plan *p)
{
  if (!p) return;
  rr_comfort_plan_free(p->comfort);
  rr_frf_plan_free(p->frf);
  rr_modal_ws_free(p->mws);
  free(p->rows);
  free(p->rows0);
  free(p->G);
  free(p->Gt);
  free(p);
}

/* The floor points and their rows (the model's layout: taken once). */
static int plan_points(rr_ride_plan *p, const rr_model *m, const rr_vehicle *veh,
                       const rr_ride_opts *o, rr_error *err)
{
  if (o->npoints < 0 || o->npoints > RR_RIDE_POINTS_MAX)
    return rr_seterr(err, RR_EINVAL, "ride: 0 to %d floor points", RR_RIDE_POINTS_MAX);
  if (o->npoints) memcpy(p->x, o->x_points, sizeof(double) * (size_t)o->npoints);
  p->np = o->npoints ? o->npoints : rr_ride_points_default(veh, p->x);
  size_t nr = (size_t)p->np * (size_t)rr_model_ndof(m);
  p->rows = malloc(sizeof(double) * nr);
  p->rows0 = malloc(sizeof(double) * nr);
  if (!p->rows || !p->rows0) return rr_seterr(err, RR_ENOMEM, "out of memory");
  p->roll_gravity = o->roll_gravity;
  return rr_vehicle_floor_rows(m, veh, p->x, p->np, o->floor_height_m, o->roll_gravity, p->rows,
                               p->rows0, err);
}

int rr_ride_plan_new(const rr_model *m, const rr_vehicle *veh, const rr_ride_opts *o,
                     rr_ride_plan **out, rr_error *err)
{
  rr_ride_opts def = rr_ride_opts_default();
  if (!o) o = &def;
  *out = NULL;
  rr_ride_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  int st = plan_points(p, m, veh, o, err);
  p->when_unstable = o->when_unstable;
  if (!st && (unsigned)o->when_unstable > RR_RIDE_UNCHECKED)
    st = rr_seterr(err, RR_EINVAL, "ride: when_unstable %d is none of rr_ride_unstable",
                   (int)o->when_unstable);
  if (!st && o->when_unstable != RR_RIDE_UNCHECKED) st = rr_modal_ws_new(m, &p->mws, err);
  rr_frf_opts fo = {.nfreq = o->nfreq,
                    .freqs_hz = o->freqs_hz,
                    .f_lo_hz = o->f_lo_hz,
                    .f_hi_hz = o->f_hi_hz,
                    .npoints = p->np,
                    .rows = p->rows,
                    .rows0 = o->roll_gravity ? p->rows0 : NULL,
                    .method = o->method};
  if (!st) st = rr_frf_plan_new(m, &fo, &p->frf, err);
  if (!st) {
    p->nfreq = rr_frf_nfreq(p->frf);
    p->G = malloc(sizeof(double) * (size_t)p->nfreq * (size_t)p->np);
    p->Gt = malloc(sizeof(double) * (size_t)p->nfreq);
    if (!p->G || !p->Gt) st = rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  if (!st)
    st = rr_comfort_plan_new(rr_frf_freqs(p->frf), p->nfreq, RR_AXIS_LATERAL, &p->comfort, err);
  if (st) {
    rr_ride_plan_free(p);
    return st;
  }
  *out = p;
  return RR_OK;
}

int rr_ride_plan_set_track(rr_ride_plan *p, const rr_spectrum *sp, double v_ms, rr_error *err)
{
  p->track_v = 0;
  int st = rr_pem_track(p->frf, sp, v_ms, p->Gt, err);
  if (!st) p->track_v = v_ms;
  return st;
}

/* The verdict at m's operating point: zeta_max over every oscillatory mode
   (no shapes: the hunting rule does not enter it). */
static int ride_verdict(rr_ride_plan *p, const rr_model *m, int *stable, double *zeta_max,
                        rr_error *err)
{
  *stable = -1;
  *zeta_max = NAN;
  if (p->when_unstable == RR_RIDE_UNCHECKED) return RR_OK;
  rr_modal_opts mo = rr_modal_opts_default();
  mo.w_min = 0;
  mo.r_max = 1;
  rr_stability s;
  int st = rr_modal_stability(m, &mo, p->mws, &s, err);
  if (st) return st;
  *zeta_max = s.zeta_max;
  *stable = rr_modal_stable(s.zeta_max);
  return RR_OK;
}

int rr_ride_design(rr_ride_plan *p, const rr_model *m, rr_ride_point *out, rr_error *err)
{
  if (!(p->track_v > 0))
    return rr_seterr(err, RR_EINVAL, "ride: no track set (rr_ride_plan_set_track)");
  if (rr_model_speed(m) != p->track_v)
    return rr_seterr(err, RR_EINVAL,
                     "ride: the model runs at %g km/h, the track was set for %g km/h",
                     rr_model_speed(m) * RR_KMH, p->track_v * RR_KMH);
  int stable;
  double zmax;
  int st = ride_verdict(p, m, &stable, &zmax, err);
  if (!st) st = rr_pem_design(p->frf, m, p->Gt, p->G, err);
  int undefined = stable == 0 && p->when_unstable == RR_RIDE_UNDEFINED;
  for (int q = 0; q < p->np && out && !st; q++) {
    rr_comfort c;
    if ((st = rr_comfort_execute(p->comfort, p->G + q, p->np, &c, err))) break;
    out[q] = (rr_ride_point){.x = p->x[q],
                             .rms = c.rms,
                             .sperling = c.sperling,
                             .sperling_gb = c.sperling_gb,
                             .wd_rms = c.wd_rms,
                             .n_mv = rr_en12299_comfort(c.wd_rms),
                             .stable = stable,
                             .zeta_max = zmax};
    if (undefined)
      out[q].rms = out[q].sperling = out[q].sperling_gb = out[q].wd_rms = out[q].n_mv = NAN;
  }
  return st;
}

int rr_ride_execute(rr_ride_plan *p, const rr_model *m, const rr_spectrum *sp, rr_ride_point *out,
                    rr_error *err)
{
  int st = rr_ride_plan_set_track(p, sp, rr_model_speed(m), err);
  return st ? st : rr_ride_design(p, m, out, err);
}

int rr_ride_frf_execute(rr_ride_plan *p, const rr_model *m, rr_error *err)
{
  return rr_frf_plan_execute(p->frf, m, err);
}

int rr_ride_nfreq(const rr_ride_plan *p) { return p->nfreq; }
const double *rr_ride_freqs(const rr_ride_plan *p) { return rr_frf_freqs(p->frf); }
int rr_ride_npoints(const rr_ride_plan *p) { return p->np; }
const double *rr_ride_points(const rr_ride_plan *p) { return p->x; }
const double *rr_ride_psd(const rr_ride_plan *p) { return p->G; }
const rr_frf_plan *rr_ride_frf(const rr_ride_plan *p) { return p->frf; }

const double *rr_ride_rows(const rr_ride_plan *p, const double **rows0)
{
  if (rows0) *rows0 = p->roll_gravity ? p->rows0 : NULL;
  return p->rows;
}

int rr_ride_evaluate(const rr_vehicle *veh, double v_ms, double conicity, const char *spectrum,
                     const rr_ride_opts *o, rr_ride_point *out, rr_error *err)
{
  rr_model *m = NULL;
  rr_ride_plan *p = NULL;
  rr_spectrum sp;
  int st = rr_spectrum_open(spectrum ? spectrum : RR_RIDE_SPECTRUM_DEFAULT, &sp, err);
  int opened = !st;
  if (!st) st = rr_spectrum_require(&sp, "lateral", "the lateral track input", err);
  if (!st) st = rr_model_from_vehicle(veh, &m, err);
  if (!st) st = rr_model_set_operating(m, v_ms, conicity, err);
  if (!st) st = rr_ride_plan_new(m, veh, o, &p, err);
  if (!st) st = rr_ride_execute(p, m, &sp, out, err);
  rr_ride_plan_free(p);
  rr_model_free(m);
  if (opened) rr_spectrum_close(&sp);
  return st;
}
