/* The vertical model's modes (docs/vertical.md, "State space and modes"):
 * the eigenvalues of A = [[0, I], [-M^-1 K, -M^-1 C]] (LAPACK dgeev), the
 * oscillatory ones named by the coordinates holding most of their kinetic
 * energy; and the undamped frequencies from M^-1/2 K M^-1/2 (dsyev). */
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "railride/vertical.h"
#include "util/internal.h"

#define NS (2 * RR_VDOF)
#define OSC_TOL 1e-6 /* oscillatory: Im > 1e-6 |lambda| (as the lateral modes) */

void rr_vertical_state_matrix(const rr_vertical_model *m, double *A)
{
  memset(A, 0, sizeof(double) * NS * NS);
  for (int i = 0; i < RR_VDOF; i++) {
    A[i * NS + RR_VDOF + i] = 1;
    for (int j = 0; j < RR_VDOF; j++) {
      A[(RR_VDOF + i) * NS + j] = -m->K[i * RR_VDOF + j] / m->M[i];
      A[(RR_VDOF + i) * NS + RR_VDOF + j] = -m->C[i * RR_VDOF + j] / m->M[i];
    }
  }
}

/* The name from the energy shares: the carbody's coordinates by name, the
   frames' bounce in or out of phase, a frame's pitch by bogie. */
static void mode_name(const rr_vertical_mode *md, const rr_complex *v, char *name, size_t sz)
{
  const double *e = md->energy;
  double bounce = e[RR_V_ZF1] + e[RR_V_ZF2], pitch = e[RR_V_THF1] + e[RR_V_THF2];
  int big = RR_V_ZC;
  for (int d = 1; d < 3; d++)
    if (e[d] > e[big]) big = d;
  if (e[big] >= bounce && e[big] >= pitch) {
    static const char *const carbody[] = {"carbody bounce", "carbody pitch",
                                          "carbody first bending"};
    snprintf(name, sz, "%s", carbody[big]);
  } else if (bounce >= pitch) {
    double in = creal(v[RR_V_ZF1] * conj(v[RR_V_ZF2]));
    double sh = e[RR_V_ZF1] / bounce;
    if (sh > 0.9 || sh < 0.1)
      snprintf(name, sz, "bogie %d bounce", sh > 0.9 ? 1 : 2);
    else
      snprintf(name, sz, "frames bounce, %s", in >= 0 ? "in phase" : "anti-phase");
  } else {
    double sh = e[RR_V_THF1] / pitch;
    if (sh > 0.9 || sh < 0.1)
      snprintf(name, sz, "bogie %d pitch", sh > 0.9 ? 1 : 2);
    else
      snprintf(name, sz, "frames pitch");
  }
}

/* kinetic-energy shares 1/2 |lambda|^2 m_k |v_k|^2 */
static void energy_shares(const rr_vertical_model *m, const rr_complex *v, double *e)
{
  double s = 0;
  for (int d = 0; d < RR_VDOF; d++) {
    e[d] = m->M[d] * creal(v[d] * conj(v[d]));
    s += e[d];
  }
  for (int d = 0; d < RR_VDOF; d++) e[d] = s > 0 ? e[d] / s : 0;
}

/* "#2", "#3" on repeated names (every mode's name is its own) */
static void unique_names(rr_vertical_modes *o)
{
  for (int i = 1; i < o->nmodes; i++) {
    int same = 1;
    for (int j = 0; j < i; j++)
      if (!strcmp(o->mode[i].name, o->mode[j].name) ||
          (!strncmp(o->mode[j].name, o->mode[i].name, strlen(o->mode[i].name)) &&
           !strncmp(o->mode[j].name + strlen(o->mode[i].name), " #", 2)))
        same++;
    if (same > 1) {
      size_t l = strlen(o->mode[i].name);
      snprintf(o->mode[i].name + l, sizeof o->mode[i].name - l, " #%d", same);
    }
  }
}

static int undamped(const rr_vertical_model *m, double *hz, rr_error *err)
{
  double S[RR_VDOF * RR_VDOF], w[RR_VDOF];
  for (int i = 0; i < RR_VDOF; i++)
    for (int j = 0; j < RR_VDOF; j++)
      S[i * RR_VDOF + j] = m->K[i * RR_VDOF + j] / sqrt(m->M[i] * m->M[j]);
  if (LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'N', 'U', RR_VDOF, S, RR_VDOF, w))
    return rr_seterr(err, RR_ELAPACK, "vertical modes: dsyev failed");
  for (int i = 0; i < RR_VDOF; i++) hz[i] = sqrt(fmax(w[i], 0)) / (2 * RR_PI);
  return RR_OK;
}

static void sort_modes(rr_vertical_modes *o)
{
  for (int i = 1; i < o->nmodes; i++)
    for (int j = i; j > 0 && o->mode[j].freq_hz < o->mode[j - 1].freq_hz; j--) {
      rr_vertical_mode t = o->mode[j];
      o->mode[j] = o->mode[j - 1];
      o->mode[j - 1] = t;
    }
}

/* A repeated eigenvalue (the two frames' pitch when nothing couples them)
   has a plane of eigenvectors, and dgeev's pair in it depends on rounding,
   so on the CPU. Each is replaced by the one concentrated on one of the two
   coordinates that hold most of the pair's energy: w_a without the second's
   component, w_b without the first's; the pair shares its eigenvalue. */
#define REPEAT_TOL 1e-9 /* |lambda_a - lambda_b| <= 1e-9 |lambda|: one eigenvalue */
static void split_repeated(const rr_vertical_model *m, rr_complex (*v)[RR_VDOF],
                           rr_vertical_mode *a, rr_vertical_mode *b, int ia, int ib)
{
  double e[RR_VDOF];
  int d1 = -1, d2 = -1;
  for (int d = 0; d < RR_VDOF; d++) {
    e[d] = m->M[d] * (creal(v[ia][d] * conj(v[ia][d])) + creal(v[ib][d] * conj(v[ib][d])));
    if (d1 < 0 || e[d] > e[d1])
      d2 = d1, d1 = d;
    else if (d2 < 0 || e[d] > e[d2])
      d2 = d;
  }
  if (d1 > d2) { /* by coordinate, not by energy: the order is the model's */
    int t = d1;
    d1 = d2, d2 = t;
  }
  rr_complex wa[RR_VDOF], wb[RR_VDOF];
  for (int d = 0; d < RR_VDOF; d++) {
    wa[d] = v[ia][d] * v[ib][d2] - v[ib][d] * v[ia][d2];
    wb[d] = v[ia][d] * v[ib][d1] - v[ib][d] * v[ia][d1];
  }
  memcpy(v[ia], wa, sizeof wa);
  memcpy(v[ib], wb, sizeof wb);
  double re = 0.5 * (a->re + b->re), im = 0.5 * (a->im + b->im);
  a->re = b->re = re, a->im = b->im = im;
  a->freq_hz = b->freq_hz = im / (2 * RR_PI);
  a->natural_hz = b->natural_hz = hypot(re, im) / (2 * RR_PI);
  a->damping_ratio = b->damping_ratio = -re / hypot(re, im);
}

int rr_vertical_modes_compute(const rr_vertical_model *m, rr_vertical_modes *o, rr_error *err)
{
  double A[NS * NS], wr[NS], wi[NS], vr[NS * NS];
  rr_complex v[RR_VDOF][RR_VDOF]; /* the modes' shapes, as o->mode */
  rr_vertical_state_matrix(m, A);
  if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'V', NS, A, NS, wr, wi, NULL, NS, vr, NS))
    return rr_seterr(err, RR_ELAPACK, "vertical modes: dgeev failed");
  memset(o, 0, sizeof *o);
  for (int k = 0; k < NS; k++) {
    double mag = hypot(wr[k], wi[k]);
    if (!(wi[k] > OSC_TOL * mag)) {
      if (fabs(wi[k]) <= OSC_TOL * mag) o->real[o->nreal++] = wr[k];
      continue;
    }
    int n = o->nmodes++; /* row-major vr: a pair's columns k (real), k + 1 (imaginary) */
    for (int d = 0; d < RR_VDOF; d++) v[n][d] = vr[d * NS + k] + I * vr[d * NS + k + 1];
    o->mode[n] = (rr_vertical_mode){.re = wr[k],
                                    .im = wi[k],
                                    .freq_hz = wi[k] / (2 * RR_PI),
                                    .natural_hz = mag / (2 * RR_PI),
                                    .damping_ratio = -wr[k] / mag};
  }
  for (int i = 0; i < o->nmodes; i++)
    for (int j = i + 1; j < o->nmodes; j++) {
      rr_vertical_mode *a = &o->mode[i], *b = &o->mode[j];
      if (hypot(a->re - b->re, a->im - b->im) <= REPEAT_TOL * hypot(a->re, a->im))
        split_repeated(m, v, a, b, i, j);
    }
  for (int i = 0; i < o->nmodes; i++) {
    energy_shares(m, v[i], o->mode[i].energy);
    mode_name(&o->mode[i], v[i], o->mode[i].name, sizeof o->mode[i].name);
  }
  sort_modes(o);
  unique_names(o);
  return undamped(m, o->undamped_hz, err);
}
