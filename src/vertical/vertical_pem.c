/* The vertical pseudo-excitation method and ride indices (docs/vertical.md,
 * "Pseudo-excitation method", "Ride indices", "5 s RMS"). The plan owns the
 * grid, the weightings, the window kernel and every buffer; executing it
 * solves, per frequency, the symmetric (bounce, bending, frames together) and
 * antisymmetric (pitch, frames opposed) 3x3 and 2x2 systems the floor sees,
 * and each frame's decoupled pitch, instead of the 7x7 system. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/pem.h"
#include "railride/vertical.h"
#include "util/block.h"
#include "util/internal.h"
#include "vertical/vertical_impl.h"

rr_vertical_opts rr_vertical_opts_default(void)
{
  return (rr_vertical_opts){.nfreq = RR_FRF_NFREQ_DEFAULT,
                            .f_lo_hz = RR_FRF_F_LO_DEFAULT,
                            .f_hi_hz = RR_FRF_F_HI_DEFAULT,
                            .window_s = RR_VERTICAL_WINDOW_DEFAULT};
}

void rr_vertical_plan_free(rr_vertical_plan *p)
{
  if (!p) return;
  free(p->block);
  rr_comfort_plan_free(p->comfort);
  rr_window_plan_free(p->window);
  free(p);
}

/* Grids: the window kernel is n x n, so n is bounded with it. */
#define VERTICAL_NFREQ_WINDOW_MAX 20000
#define VERTICAL_NFREQ_MAX 4000000

static int check_opts(const rr_vertical_opts *o, rr_error *err)
{
  int nmax = o->window_s > 0 ? VERTICAL_NFREQ_WINDOW_MAX : VERTICAL_NFREQ_MAX;
  if (o->nfreq < 2 || o->nfreq > nmax)
    return rr_seterr(err, RR_EINVAL, "vertical: %d frequencies (need 2 .. %d%s)", o->nfreq, nmax,
                     o->window_s > 0 ? " with a 5 s window" : "");
  if (o->freqs_hz) {
    for (int i = 0; i < o->nfreq; i++)
      if (!(o->freqs_hz[i] > 0 && isfinite(o->freqs_hz[i]) &&
            (i == 0 || o->freqs_hz[i] > o->freqs_hz[i - 1])))
        return rr_seterr(err, RR_EINVAL, "vertical: the grid must be positive and increasing");
  } else if (!(o->f_lo_hz > 0 && o->f_hi_hz > o->f_lo_hz && isfinite(o->f_hi_hz)))
    return rr_seterr(err, RR_EINVAL, "vertical: band %g .. %g Hz (need 0 < lo < hi)", o->f_lo_hz,
                     o->f_hi_hz);
  if (o->npoints < 0 || o->npoints > RR_VERTICAL_POINTS_MAX)
    return rr_seterr(err, RR_EINVAL, "vertical: %d floor points (at most %d)", o->npoints,
                     RR_VERTICAL_POINTS_MAX);
  for (int i = 0; i < o->npoints; i++)
    if (!isfinite(o->x_points[i]))
      return rr_seterr(err, RR_EINVAL, "vertical: floor point %d is not finite", i + 1);
  if (!(o->window_s >= 0 && o->window_s <= 3600))
    return rr_seterr(err, RR_EINVAL, "vertical: window %g s (need 0 <= T <= 3600 s)", o->window_s);
  return RR_OK;
}

static double weight2(enum rr_iso_weighting w, double f)
{
  rr_complex h = rr_iso8041_weight(w, f);
  return creal(h * conj(h));
}

static int plan_weights(rr_vertical_plan *p, rr_error *err)
{
  int n = p->n;
  for (int i = 0; i < n; i++) {
    double f = p->f[i];
    p->wk2[i] = weight2(RR_ISO_WK, f);
    p->wb2[i] = weight2(RR_EN_WB, f);
    p->wd2[i] = weight2(RR_ISO_WD, f);
    p->wc2[i] = weight2(RR_ISO_WC, f);
    p->wbi2[i] = weight2(RR_ISO_WB, f);
    p->bs2[i] = rr_sperling_filter(f, RR_AXIS_VERTICAL) * rr_sperling_filter(f, RR_AXIS_VERTICAL);
    p->trap[i] = 0.5 * ((i + 1 < n ? p->f[i + 1] : f) - (i > 0 ? p->f[i - 1] : f));
  }
  int st = rr_comfort_plan_new(p->f, n, RR_AXIS_VERTICAL, &p->comfort, err);
  if (!st && p->o.window_s > 0)
    st = rr_window_plan_new(p->f, n, p->o.window_s, RR_VERTICAL_POINTS_MAX, &p->window, err);
  return st;
}

/* The plan's arrays (block.h: called to size, then to carve). */
static void plan_layout(rr_vertical_plan *p, rr_block *b)
{
  size_t n = (size_t)p->n, pm = RR_VERTICAL_POINTS_MAX, d = sizeof(double), z = sizeof(rr_complex);
  p->f = rr_block_take(b, n, d);
  p->wk2 = rr_block_take(b, n, d);
  p->wb2 = rr_block_take(b, n, d);
  p->wd2 = rr_block_take(b, n, d);
  p->wc2 = rr_block_take(b, n, d);
  p->wbi2 = rr_block_take(b, n, d);
  p->bs2 = rr_block_take(b, n, d);
  p->trap = rr_block_take(b, n, d);
  p->Gt = rr_block_take(b, n, d);
  p->Gx = rr_block_take(b, n, d);
  p->G = rr_block_take(b, n * pm, d);
  p->H = rr_block_take(b, n * pm, z);
  p->Q = rr_block_take(b, n * RR_VDOF, z);
  p->Er = rr_block_take(b, n * 2 * RR_VINPUTS, d);
  p->Ei = p->Er ? p->Er + n * RR_VINPUTS : NULL;
  p->Qr = rr_block_take(b, n * 2 * RR_VDOF, d);
  p->Qi = p->Qr ? p->Qr + n * RR_VDOF : NULL;
}

int rr_vertical_plan_new(const rr_vertical_opts *o, rr_vertical_plan **out, rr_error *err)
{
  *out = NULL;
  int st = check_opts(o, err);
  if (st) return st;
  rr_vertical_plan *p = calloc(1, sizeof *p);
  if (!p) return rr_seterr(err, RR_ENOMEM, "out of memory");
  p->o = *o;
  p->n = o->nfreq;
  rr_block b = {0};
  plan_layout(p, &b);
  if (rr_block_alloc(&b)) {
    rr_vertical_plan_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  plan_layout(p, &b);
  p->block = b.base;
  for (int i = 0; i < p->n; i++) /* given, or log-spaced with both ends exact */
    p->f[i] = o->freqs_hz     ? o->freqs_hz[i]
              : i == p->n - 1 ? o->f_hi_hz
                              : o->f_lo_hz * pow(o->f_hi_hz / o->f_lo_hz, (double)i / (p->n - 1));
  p->o.freqs_hz = NULL; /* the caller's array is not kept */
  if ((st = plan_weights(p, err))) {
    rr_vertical_plan_free(p);
    return st;
  }
  *out = p;
  return RR_OK;
}

int rr_vertical_nfreq(const rr_vertical_plan *p) { return p->n; }
const double *rr_vertical_freqs(const rr_vertical_plan *p) { return p->f; }
int rr_vertical_npoints(const rr_vertical_plan *p) { return p->np; }
const double *rr_vertical_points(const rr_vertical_plan *p) { return p->x; }
const rr_complex *rr_vertical_frf_H(const rr_vertical_plan *p) { return p->H; }
const rr_complex *rr_vertical_frf_Q(const rr_vertical_plan *p) { return p->Q; }
const double *rr_vertical_psd(const rr_vertical_plan *p) { return p->G; }
const double *rr_vertical_track_psd(const rr_vertical_plan *p) { return p->Gt; }

/* ---- indices ---- */

static const double *weights_of(const rr_vertical_plan *p, enum rr_iso_weighting w)
{
  switch (w) {
  case RR_ISO_WK: return p->wk2;
  case RR_EN_WB: return p->wb2;
  case RR_ISO_WD: return p->wd2;
  case RR_ISO_WC: return p->wc2;
  default: return NULL;
  }
}

int rr_vertical_window_stats(rr_vertical_plan *p, const double *G, int stride, int ncols,
                             enum rr_iso_weighting w, rr_window_stats *out, rr_error *err)
{
  const double *W2 = weights_of(p, w);
  if (!W2) return rr_seterr(err, RR_EINVAL, "vertical: weighting %d is not planned", (int)w);
  if (!p->window) return rr_seterr(err, RR_EUNSUP, "vertical: the plan has no 5 s window");
  return rr_window_execute(p->window, G, stride, ncols, W2, out, err);
}

/* Point i's PSD G = G_t |H|^2 and its weighted integrals in one pass:
   s[0..4] = integral of G times 1, |B_s|^2, |Wk|^2, |Wb EN|^2, |Wb ISO|^2. */
static void psd_and_sums(rr_vertical_plan *p, int i, double s[5])
{
  int np = p->np;
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0;
  for (int k = 0; k < p->n; k++) {
    size_t at = (size_t)k * (size_t)np + (size_t)i;
    rr_complex h = p->H[at];
    double g = p->Gt[k] * (creal(h) * creal(h) + cimag(h) * cimag(h)), t = p->trap[k] * g;
    p->G[at] = g;
    s0 += t;
    s1 += p->bs2[k] * t;
    s2 += p->wk2[k] * t;
    s3 += p->wb2[k] * t;
    s4 += p->wbi2[k] * t;
  }
  s[0] = s0, s[1] = s1, s[2] = s2, s[3] = s3, s[4] = s4;
}

static int point_indices(rr_vertical_plan *p, const double s[5], const rr_window_stats *wb, int i,
                         rr_vertical_point *o, rr_error *err)
{
  double gb;
  int st = rr_comfort_gb(p->comfort, p->G + i, p->np, &gb, err);
  if (st) return st;
  *o = (rr_vertical_point){.x = p->x[i],
                           .rms = sqrt(s[0]),
                           .sperling = rr_sperling_from_weighted_rms(sqrt(s[1])),
                           .sperling_gb = gb,
                           .wk_rms = sqrt(s[2]),
                           .wb_rms = sqrt(s[3]),
                           .wb_iso8041_rms = sqrt(s[4]),
                           .wb_5s = *wb,
                           .n_mv_vertical = 6 * wb->p95};
  double all[] = {o->rms,    o->sperling,  o->sperling_gb, o->wk_rms,
                  o->wb_rms, o->wb_5s.p95, o->wb_5s.p50,   o->wb_5s.mean};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; k++)
    if (!isfinite(all[k]))
      return rr_seterr(err, RR_EINVAL, "vertical: an index at x = %g m is not finite", o->x);
  return RR_OK;
}

int rr_vertical_plan_set_track(rr_vertical_plan *p, const rr_spectrum *sp, double v, rr_error *err)
{
  if (!(v > 0 && v < 1e3))
    return rr_seterr(err, RR_EINVAL, "vertical: speed %g m/s (need 0 < v < 1000)", v);
  for (int k = 0; k < p->n; k++) {
    double gt = rr_spectrum_eval(sp, p->f[k] / v) / v;
    if (!(gt >= 0 && isfinite(gt)))
      return rr_seterr(err, RR_EINVAL, "vertical: the track PSD at %g Hz is not finite", p->f[k]);
    p->Gt[k] = gt;
  }
  p->track_v = v;
  return RR_OK;
}

int rr_vertical_ride_design(rr_vertical_plan *p, const rr_vertical_model *m, rr_vertical_point *out,
                            rr_error *err)
{
  if (!(p->track_v > 0))
    return rr_seterr(err, RR_EINVAL, "vertical: no track set (rr_vertical_plan_set_track)");
  int st = rr_vertical_floor_response(p, m, p->track_v, 1, err);
  if (st) return st;
  double s[RR_VERTICAL_POINTS_MAX][5];
  for (int i = 0; i < p->np; i++) psd_and_sums(p, i, s[i]);
  rr_window_stats wb[RR_VERTICAL_POINTS_MAX];
  if (p->window)
    st = rr_window_execute(p->window, p->G, p->np, p->np, p->wb2, wb, err);
  else /* no window: the Wb RMS alone */
    for (int i = 0; i < p->np; i++) wb[i] = (rr_window_stats){.rms = sqrt(s[i][3])};
  for (int i = 0; i < p->np && !st; i++) st = point_indices(p, s[i], wb + i, i, out + i, err);
  return st;
}

int rr_vertical_pitch_longitudinal(rr_vertical_plan *p, double h_p, double h_c, rr_window_stats *wd,
                                   rr_window_stats *wc, rr_error *err)
{
  if (!(p->track_v > 0) || !p->window)
    return rr_seterr(err, RR_EINVAL, "vertical: pitch a_x needs a ride evaluation with a window");
  if (!(isfinite(h_p) && isfinite(h_c)))
    return rr_seterr(err, RR_EINVAL, "vertical: pitch a_x: heights must be finite");
  for (int k = 0; k < p->n; k++) {
    double w = 2 * RR_PI * p->f[k], c = -w * w * (h_p - h_c) - RR_G;
    double tr = p->Qr[RR_V_THC * p->n + k], ti = p->Qi[RR_V_THC * p->n + k];
    p->Gx[k] = p->Gt[k] * c * c * (tr * tr + ti * ti);
  }
  int st = rr_window_execute(p->window, p->Gx, 1, 1, p->wd2, wd, err);
  return st ? st : rr_window_execute(p->window, p->Gx, 1, 1, p->wc2, wc, err);
}

int rr_vertical_ride_execute(rr_vertical_plan *p, const rr_vertical_model *m, double v,
                             const rr_spectrum *sp, rr_vertical_point *out, rr_error *err)
{
  int st = rr_vertical_plan_set_track(p, sp, v, err);
  return st ? st : rr_vertical_ride_design(p, m, out, err);
}
