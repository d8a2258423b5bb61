/* Assembly of M, C, K, B from a system, and the operating point (speed,
 * conicity) which only touches the wheel-rail contact terms (docs/model.md section 2-3). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "model/model_impl.h"
#include "util/internal.h"

static void add_outer(double *A, int n, const double *J, double s)
{
  for (int i = 0; i < n; i++) {
    if (J[i] == 0) continue;
    for (int j = 0; j < n; j++) A[i * n + j] += s * J[i] * J[j];
  }
}

int rr_model_new(const rr_system *sys, rr_model **out, rr_error *err)
{
  *out = NULL;
  if (!sys || sys->ndof == 0) return rr_seterr(err, RR_EINVAL, "model: system has no DOFs");
  rr_model *m = calloc(1, sizeof *m);
  if (!m) return rr_seterr(err, RR_ENOMEM, "out of memory");
  m->sdf_mode = RR_SDF_NONE;
  int st = rr_model_assemble(m, sys, err);
  if (st) {
    free(m);
    return st;
  }
  if ((st = rr_model_set_operating(m, 1.0, 0.0, err))) {
    free(m);
    return st;
  }
  *out = m;
  return RR_OK;
}

int rr_model_assemble(rr_model *m, const rr_system *sys, rr_error *err)
{
  int n = m->n = sys->ndof;
  m->nmx = 0;
  /* n x n of the RR_SYS_MAX_DOF^2 arrays: clearing all of them was 96 KB a
     design in the optimiser's loop */
  memset(m->M, 0, sizeof(double) * (size_t)n * (size_t)n);
  memset(m->C0, 0, sizeof(double) * (size_t)n * (size_t)n);
  memset(m->K0, 0, sizeof(double) * (size_t)n * (size_t)n);
  m->ni = sys->ncontacts;
  for (int i = 0; i < n; i++) {
    m->mdiag[i] = sys->mass[i];
    m->M[i * n + i] = sys->mass[i];
    m->group[i] = sys->group[i];
    memcpy(m->dof_name[i], sys->dof_name[i], sizeof m->dof_name[i]);
  }
  for (int e = 0; e < sys->nelements; e++) {
    const rr_elem *el = &sys->elements[e];
    switch (el->law) {
    case RR_LAW_SPRING: add_outer(m->K0, n, el->J, el->k); break;
    case RR_LAW_DAMPER: add_outer(m->C0, n, el->J, el->c); break;
    case RR_LAW_KC:
      add_outer(m->K0, n, el->J, el->k);
      add_outer(m->C0, n, el->J, el->c);
      break;
    case RR_LAW_MAXWELL:
      if (el->c == 0) break; /* no damper: no force */
      if (isinf(el->k) && !el->sdf) {
        add_outer(m->C0, n, el->J, el->c);
        break;
      } /* rigid link */
      if (m->nmx >= (int)(sizeof m->mx / sizeof m->mx[0]))
        return rr_seterr(err, RR_EINVAL, "too many Maxwell elements");
      rr_mx *x = &m->mx[m->nmx++];
      memcpy(x->name, el->name, sizeof x->name);
      memcpy(x->J, el->J, sizeof x->J);
      x->k = el->k;
      x->c = el->c;
      x->sdf = el->sdf;
      x->nz = 0;
      for (int i = 0; i < n; i++)
        if (el->J[i] != 0) x->idx[x->nz++] = i;
      break;
    }
  }
  if (sys->ncontacts > 0) /* a system without wheels has no contact array at all */
    memcpy(m->contacts, sys->contacts, (size_t)sys->ncontacts * sizeof *sys->contacts);
  memcpy(m->bodies, sys->bodies, (size_t)sys->nbodies * sizeof *sys->bodies);
  m->nbodies = sys->nbodies;
  m->ni = sys->ncontacts;
  m->nsdf = 0;
  for (int i = 0; i < m->nmx; i++) m->nsdf += m->mx[i].sdf;
  rr_model_sparsity(m);
  return RR_OK;
}

void rr_model_free(rr_model *m) { free(m); }

int rr_model_clone(const rr_model *m, rr_model **out, rr_error *err)
{
  *out = malloc(sizeof **out);
  if (!*out) return rr_seterr(err, RR_ENOMEM, "out of memory");
  memcpy(*out, m, sizeof **out);
  return RR_OK;
}

int rr_model_set_operating(rr_model *m, double v, double lambda, rr_error *err)
{
  if (!(v > 0 && v <= RR_SPEED_MAX_MS))
    return rr_seterr(err, RR_EINVAL, "speed %g km/h outside (0, %g] km/h", v * RR_KMH,
                     RR_SPEED_MAX_MS * RR_KMH);
  if (!(lambda >= 0 && lambda <= RR_CONICITY_MAX))
    return rr_seterr(err, RR_EINVAL, "conicity %g outside [0, %g]", lambda, RR_CONICITY_MAX);
  int n = m->n, ni = m->ni;
  m->speed = v;
  m->conicity = lambda;
  memcpy(m->C, m->C0, sizeof(double) * (size_t)(n * n));
  memcpy(m->K, m->K0, sizeof(double) * (size_t)(n * n));
  memset(m->B, 0, sizeof(double) * (size_t)(n * ni));
  for (int i = 0; i < ni; i++) {
    /* Contact at offset dx: lateral motion a.q = y + dx psi, yaw b.q = psi.
       F_y = -2 f22 (a.q'/v - psi), M_z = -2 f11 l0 (l0 psi'/v + lambda (a.q - y_t)/r0),
       generalised forces a F_y + b M_z (docs/model.md section 3 with dx = 0). */
    const rr_contact *c = &m->contacts[i];
    int y = c->dof_y, p = c->dof_psi;
    double dx = c->spec.dx;
    rr_creep_terms t = rr_creep_terms_at(&c->spec, v, lambda, m->gravity);
    double cy = t.cy, cp = t.cp, kyp = t.kyp, kpy = t.kpy;
    /* C += cy a a' + cp b b' */
    m->C[y * n + y] += cy;
    m->C[y * n + p] += cy * dx;
    m->C[p * n + y] += cy * dx;
    m->C[p * n + p] += cy * dx * dx + cp;
    /* K += kyp a b' + kpy b a' */
    m->K[y * n + p] += kyp;
    m->K[p * n + p] += kyp * dx + kpy * dx;
    m->K[p * n + y] += kpy;
    m->B[p * ni + i] += kpy;
    if (m->gravity) { /* K += g a a' - W lambda l0 b b', B += g a */
      double g = t.gy;
      m->K[y * n + y] += g;
      m->K[y * n + p] += g * dx;
      m->K[p * n + y] += g * dx;
      m->K[p * n + p] += g * dx * dx - t.gpsi;
      m->B[y * ni + i] += g;
      m->B[p * ni + i] += g * dx;
    }
  }
  return RR_OK;
}

double rr_model_speed(const rr_model *m) { return m->speed; }
double rr_model_conicity(const rr_model *m) { return m->conicity; }

double rr_model_kinematic_hz(const rr_model *m, double speed_ms, double conicity)
{
  double f = 0;
  if (!(conicity > 0) || !(speed_ms > 0)) return 0;
  for (int i = 0; i < m->ni; i++) {
    const rr_contact_spec *s = &m->contacts[i].spec;
    double fk = speed_ms / (2 * RR_PI) * sqrt(conicity / (s->r0 * s->l0));
    if (fk > f) f = fk;
  }
  return f;
}

int rr_model_set_gravity_stiffness(rr_model *m, int on, rr_error *err)
{
  m->gravity = on != 0;
  return rr_model_set_operating(m, m->speed, m->conicity, err);
}

int rr_model_set_sdf(rr_model *m, rr_sdf_mode mode, const rr_sdf_curve *curve, rr_error *err)
{
  if (mode < RR_SDF_NONE || mode > RR_SDF_PHYSICAL)
    return rr_seterr(err, RR_EINVAL, "unknown SDF mode %d", mode);
  if (mode != RR_SDF_NONE) {
    int st = rr_sdf_curve_check(curve, "SDF curve", err);
    if (st) return st;
    m->curve = *curve;
  }
  m->sdf_mode = mode;
  m->nsdf = 0;
  for (int i = 0; i < m->nmx; i++) m->nsdf += m->mx[i].sdf;
  return RR_OK;
}

rr_sdf_mode rr_model_sdf_mode(const rr_model *m) { return m->sdf_mode; }
const rr_sdf_curve *rr_model_sdf_curve(const rr_model *m) { return &m->curve; }
int rr_model_ndof(const rr_model *m) { return m->n; }
int rr_model_ninputs(const rr_model *m) { return m->ni; }
const char *rr_model_dof_name(const rr_model *m, int i)
{
  return (i >= 0 && i < m->n) ? m->dof_name[i] : NULL;
}
int rr_model_dof_group(const rr_model *m, int i) { return i >= 0 && i < m->n ? m->group[i] : -1; }
double rr_model_input_x(const rr_model *m, int i)
{
  return i >= 0 && i < m->ni ? m->contacts[i].x : NAN;
}
const double *rr_model_M(const rr_model *m) { return m->M; }
const double *rr_model_C(const rr_model *m) { return m->C; }
const double *rr_model_K(const rr_model *m) { return m->K; }
const double *rr_model_B(const rr_model *m) { return m->B; }
int rr_model_nmaxwell(const rr_model *m) { return m->nmx; }

int rr_model_maxwell(const rr_model *m, int i, rr_maxwell_info *info, rr_error *err)
{
  if (i < 0 || i >= m->nmx)
    return rr_seterr(err, RR_EINVAL, "Maxwell element %d: the model has %d", i, m->nmx);
  info->name = m->mx[i].name;
  info->J = m->mx[i].J;
  info->k = m->mx[i].k;
  info->c = m->mx[i].c;
  info->sdf = m->mx[i].sdf && m->sdf_mode != RR_SDF_NONE;
  return RR_OK;
}

double complex rr_model_series_k(const rr_model *m, int i, double complex s, double sdf_k)
{
  const rr_mx *x = &m->mx[i];
  if (!x->sdf || m->sdf_mode == RR_SDF_NONE) return x->k;
  if (m->sdf_mode == RR_SDF_PAPER && sdf_k > 0) return sdf_k; /* a self-consistent root's k */
  return rr_sdf_series_k(&m->curve, m->sdf_mode, s);
}

void rr_model_dynamic_stiffness(const rr_model *m, double complex s, double sdf_k,
                                double complex *D)
{
  int n = m->n;
  double complex s2 = s * s;
  for (int i = 0; i < n * n; i++) D[i] = s * m->C[i] + m->K[i];
  for (int i = 0; i < n; i++) D[i * n + i] += s2 * m->mdiag[i];
  for (int e = 0; e < m->nmx; e++) {
    const rr_mx *x = &m->mx[e];
    double complex k = rr_model_series_k(m, e, s, sdf_k);
    double complex ke = isinf(creal(k)) ? x->c * s : k * x->c * s / (k + x->c * s);
    for (int a = 0; a < x->nz; a++) {
      int i = x->idx[a];
      double complex t = ke * x->J[i];
      for (int b = 0; b < x->nz; b++) D[i * n + x->idx[b]] += t * x->J[x->idx[b]];
    }
  }
}

int rr_model_point_row(const rr_model *m, const char *body, const double point[3],
                       enum rr_direction dir, double *row, rr_error *err)
{
  int b = -1;
  for (int i = 0; i < m->nbodies; i++)
    if (!strcmp(m->bodies[i].name, body)) b = i;
  if (b < 0) return rr_seterr(err, RR_EINVAL, "no body named '%s'", body);
  for (int i = 0; i < m->n; i++) row[i] = 0;
  if (rr_point_motion(&m->bodies[b], point, dir, 1.0, row))
    return rr_seterr(err, RR_EINVAL, "unknown direction %d", dir);
  return RR_OK;
}
