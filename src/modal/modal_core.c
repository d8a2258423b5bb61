/* The core of modal analysis, shared by modal.c (the modes, the index's
 * routes) and sdf_modes.c (paper-mode SDF modes): the eigen-solve, a mode's
 * frequency, damping and shares, the index rule, sorting and naming. */
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "modal/modal_impl.h"
#include "linalg/max_abs.h"
#include "linalg/hessenberg_qr.h"
#include "util/internal.h"

double rr_mac(const double complex *a, const double complex *b, int n)
{
  double complex ab = 0;
  double aa = 0, bb = 0;
  for (int i = 0; i < n; i++) {
    ab += conj(a[i]) * b[i];
    aa += creal(a[i] * conj(a[i]));
    bb += creal(b[i] * conj(b[i]));
  }
  if (aa == 0 || bb == 0) return 0;
  return creal(ab * conj(ab)) / (aa * bb);
}

int rr_modal_eig(const rr_model *m, double sdf_k, int vectors, rr_modal_ws *ws, int *Nout,
                 rr_error *err)
{
  int N = rr_model_state_size(m);
  if (N > ws->N) return rr_seterr(err, RR_EINVAL, "modal workspace too small (%d < %d)", ws->N, N);
  int st = rr_model_state_matrix(m, sdf_k, ws->A, err);
  if (st) return st;
  for (int i = 0; i < N; i++) /* row-major -> column-major */
    for (int j = 0; j < N; j++) ws->At[j * N + i] = ws->A[i * N + j];
  int info = LAPACKE_dgeev_work(LAPACK_COL_MAJOR, 'N', vectors ? 'V' : 'N', N, ws->At, N, ws->wr,
                                ws->wi, NULL, 1, ws->vr, N, ws->work, ws->lwork);
  if (info) return rr_seterr(err, RR_ELAPACK, "dgeev failed (info %d)", info);
  *Nout = N;
  return RR_OK;
}

void rr_mode_fill(rr_mode *md, double re, double im, double anorm)
{
  memset(md, 0, sizeof *md);
  md->re = re;
  md->im = im;
  md->freq_hz = im / (2 * RR_PI);
  double mag = hypot(re, im);
  md->zeta = mag > 0 ? re / mag : 0;
  md->oscillatory = rr_modal_is_osc(re, im, anorm);
  md->self_consistent = 1;
}

/* The index's band edge (docs/model.md, revision 4): a fixed fmax, or the
   free wheelset's kinematic frequency with a 10 Hz floor. */
double rr_modal_band_edge_at(const rr_model *m, const rr_modal_opts *o, double speed_ms,
                             double conicity)
{
  if (o && o->fmax_hz > 0) return o->fmax_hz;
  double fk = rr_model_kinematic_hz(m, speed_ms, conicity);
  return fk > RR_FMAX_FLOOR_HZ ? fk : RR_FMAX_FLOOR_HZ;
}

double rr_modal_band_edge(const rr_model *m, const rr_modal_opts *o)
{
  return rr_modal_band_edge_at(m, o, m->speed, m->conicity);
}

/* Hunting-related (docs/model.md): the wheelsets move, and not a roll mode
   of the frames (carbody roll is part of body hunting); r_max >= 1 lets
   every shape through. */
int rr_modal_hunting_related(const rr_mode *md, const rr_modal_opts *o)
{
  return md->energy[RR_GROUP_WHEELSET] >= o->w_min &&
         (md->frame_roll_share < o->r_max || o->r_max >= 1);
}

double rr_modal_index_rule(double hunting_index, double zeta_max, int have_max,
                           rr_index_source *source, int *which)
{
  rr_index_source s = RR_INDEX_NONE;
  int w = -1;
  double z = NAN;
  if (have_max && zeta_max >= 0 && !(hunting_index >= zeta_max)) {
    s = RR_INDEX_UNSTABLE; /* an unstable mode the hunting rule does not count */
    w = 1;
    z = zeta_max;
  } else if (!isnan(hunting_index)) {
    s = RR_INDEX_HUNTING;
    w = 0;
    z = hunting_index;
  }
  if (source) *source = s;
  if (which) *which = w;
  return z;
}

const char *rr_index_source_name(rr_index_source s)
{
  switch (s) {
  case RR_INDEX_HUNTING: return "hunting mode";
  case RR_INDEX_UNSTABLE: return "unstable mode outside the hunting band";
  case RR_INDEX_NONE: break;
  }
  return "none";
}

static void classify(rr_mode *md, const rr_modal_opts *o, double fmax)
{
  md->hunting = rr_modal_hunting_related(md, o);
  md->in_index = md->oscillatory && md->self_consistent && md->hunting && md->freq_hz <= fmax;
}

static int cmp_mode(const rr_mode *x, const rr_mode *y)
{
  if (x->oscillatory != y->oscillatory) return y->oscillatory - x->oscillatory;
  if (x->oscillatory) return (x->freq_hz > y->freq_hz) - (x->freq_hz < y->freq_hz);
  return (x->re < y->re) - (x->re > y->re);
}

/* Insertion sort of modes and shapes together (n <= ~70, nearly sorted):
   allocation-free, moving each shape once through the scratch row. */
static void sort_result(rr_modal_result *res, double complex *scratch)
{
  size_t row = (size_t)res->ndof * sizeof(double complex);
  for (int i = 1; i < res->n; i++) {
    rr_mode t = res->modes[i];
    int j = i;
    while (j > 0 && cmp_mode(&res->modes[j - 1], &t) > 0) j--;
    if (j == i) continue;
    memcpy(scratch, res->shapes + (size_t)i * (size_t)res->ndof, row);
    memmove(&res->modes[j + 1], &res->modes[j], (size_t)(i - j) * sizeof t);
    memmove(res->shapes + (size_t)(j + 1) * (size_t)res->ndof,
            res->shapes + (size_t)j * (size_t)res->ndof, (size_t)(i - j) * row);
    res->modes[j] = t;
    memcpy(res->shapes + (size_t)j * (size_t)res->ndof, scratch, row);
  }
}

void rr_modal_collect(const rr_model *m, int N, const rr_modal_ws *ws, rr_modal_result *res)
{
  int n = m->n;
  double anorm = rr_max_abs((size_t)N * (size_t)N, ws->A);
  res->n = 0;
  res->ndof = n;
  for (int j = 0; j < N; j++) {
    double re = ws->wr[j], im = ws->wi[j];
    if (im < 0) continue;
    rr_mode *md = &res->modes[res->n];
    rr_mode_fill(md, re, im, anorm);
    double complex *phi = res->shapes + (size_t)res->n * (size_t)n;
    for (int i = 0; i < n; i++)
      phi[i] = im > 0 ? ws->vr[(size_t)j * (size_t)N + (size_t)i] +
                            I * ws->vr[(size_t)(j + 1) * (size_t)N + (size_t)i]
                      : ws->vr[(size_t)j * (size_t)N + (size_t)i];
    rr_shape_normalise(phi, n);
    rr_mode_shares(m, phi, md);
    res->n++;
  }
}

/* No two modes of a result share a name (users tell them apart by name, as
   in SIMPACK or VAMPIRE): a name worn by several modes gets an ordinal in
   frequency order, "wheelsets yaw #2". */
static void unique_names(rr_modal_result *res)
{
  enum { SUFFIX = 6 };               /* " #" and up to 3 digits and the NUL */
  for (int i = 0; i < res->n; i++) { /* real roots are told from oscillatory modes first */
    rr_mode *md = &res->modes[i];
    size_t l = strlen(md->name);
    if (!md->oscillatory && l + 12 < sizeof md->name) memcpy(md->name + l, ", aperiodic", 12);
  }
  for (int i = 0; i < res->n; i++) {
    const char *nm = res->modes[i].name;
    int count = 0;
    for (int j = i + 1; j < res->n; j++) count += !strcmp(res->modes[j].name, nm);
    if (count == 0) continue; /* the earlier ones of a shared name were renamed already */
    char base[RR_MODE_NAME_MAX];
    snprintf(base, sizeof base, "%.*s", RR_MODE_NAME_MAX - SUFFIX, nm);
    for (int j = i, k = 1; j < res->n; j++)
      if (!strcmp(res->modes[j].name, nm) && j != i)
        snprintf(res->modes[j].name, RR_MODE_NAME_MAX, "%s #%d", base, ++k);
    snprintf(res->modes[i].name, RR_MODE_NAME_MAX, "%s #1", base);
  }
}

void rr_modal_finish(const rr_model *m, rr_modal_result *res, const rr_modal_opts *o,
                     double complex *scratch)
{
  double fmax = rr_modal_band_edge(m, o);
  sort_result(res, scratch);
  unique_names(res);
  res->hunting_index = NAN;
  res->hunting_mode = -1;
  res->zeta_max = -1;
  res->max_mode = -1;
  res->fmax_hz = fmax;
  for (int i = 0; i < res->n; i++) {
    rr_mode *md = &res->modes[i];
    classify(md, o, fmax);
    if (md->in_index && (res->hunting_mode < 0 || md->zeta > res->hunting_index)) {
      res->hunting_index = md->zeta;
      res->hunting_mode = i;
    }
    if (md->oscillatory && md->self_consistent && (res->max_mode < 0 || md->zeta > res->zeta_max)) {
      res->zeta_max = md->zeta;
      res->max_mode = i;
    }
  }
  int which;
  res->stability_index = rr_modal_index_rule(res->hunting_index, res->zeta_max, res->max_mode >= 0,
                                             &res->index_source, &which);
  res->index_mode = which == 0 ? res->hunting_mode : which == 1 ? res->max_mode : -1;
}
