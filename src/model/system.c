/* The generic linear multibody layer: bodies, point elements, contacts. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/system.h"
#include "model/system_impl.h"
#include "util/internal.h"

int rr_system_new(rr_system **out, rr_error *err)
{
  *out = calloc(1, sizeof(rr_system));
  return *out ? RR_OK : rr_seterr(err, RR_ENOMEM, "out of memory");
}

void rr_system_free(rr_system *sys)
{
  if (!sys) return;
  free(sys->bodies);
  free(sys->elements);
  free(sys->contacts);
  free(sys);
}

static int grow(void **p, int *cap, int need, size_t size)
{
  if (need <= *cap) return 0;
  int nc = *cap ? 2 * *cap : 8;
  while (nc < need) nc *= 2;
  void *q = realloc(*p, (size_t)nc * size);
  if (!q) return -1;
  *p = q;
  *cap = nc;
  return 0;
}

/* dst = a, or a "_" b, cut to n - 1 characters: snprintf's result without
   its format parser, which the optimiser's loop paid for every name of
   every model it rebuilt */
static void copy_name(char *dst, size_t n, const char *a, const char *b)
{
  size_t k = 0;
  for (; k + 1 < n && *a; k++) dst[k] = *a++;
  if (b && k + 1 < n) dst[k++] = '_';
  for (; b && k + 1 < n && *b; k++) dst[k] = *b++;
  dst[k] = 0;
}

/* The new body's index (>= 0) or -status. */
static int add_body(rr_system *sys, const rr_body_spec *b, rr_error *err)
{
  if (!(isfinite(b->mass) && b->mass > 0))
    return -rr_seterr(err, RR_EINVAL, "body %s: mass must be > 0", b->name);
  if ((b->dofs & RR_DOF_PSI) && !(isfinite(b->yaw_inertia) && b->yaw_inertia > 0))
    return -rr_seterr(err, RR_EINVAL, "body %s: yaw inertia must be > 0", b->name);
  if ((b->dofs & RR_DOF_PHI) && !(isfinite(b->roll_inertia) && b->roll_inertia > 0))
    return -rr_seterr(err, RR_EINVAL, "body %s: roll inertia must be > 0", b->name);
  if (b->group < 0 || b->group >= RR_NGROUPS)
    return -rr_seterr(err, RR_EINVAL, "body %s: unknown group %d", b->name, b->group);
  if (!b->dofs || (b->dofs & ~7u))
    return -rr_seterr(err, RR_EINVAL, "body %s: DOF mask must be a non-empty RR_DOF_* set",
                      b->name);
  if (sys->nbodies >= RR_SYS_MAX_BODIES)
    return -rr_seterr(err, RR_EINVAL, "too many bodies (max %d)", RR_SYS_MAX_BODIES);
  if (grow((void **)&sys->bodies, &sys->cap_bodies, sys->nbodies + 1, sizeof *sys->bodies))
    return -rr_seterr(err, RR_ENOMEM, "out of memory");
  rr_body *bd = &sys->bodies[sys->nbodies];
  memset(bd, 0, sizeof *bd);
  copy_name(bd->name, sizeof bd->name, b->name ? b->name : "body", NULL);
  bd->group = b->group;
  memcpy(bd->ref, b->ref, sizeof bd->ref);
  bd->dof_y = bd->dof_psi = bd->dof_phi = -1;
  static const char *pre[3] = {"y", "psi", "phi"};
  const double inertia[3] = {b->mass, b->yaw_inertia, b->roll_inertia};
  int *slot[3] = {&bd->dof_y, &bd->dof_psi, &bd->dof_phi};
  for (int k = 0; k < 3; k++) {
    if (!(b->dofs & (1u << k))) continue;
    if (sys->ndof >= RR_SYS_MAX_DOF)
      return -rr_seterr(err, RR_EINVAL, "too many DOFs (max %d)", RR_SYS_MAX_DOF);
    *slot[k] = sys->ndof;
    sys->mass[sys->ndof] = inertia[k];
    sys->group[sys->ndof] = b->group;
    copy_name(sys->dof_name[sys->ndof], sizeof sys->dof_name[0], pre[k], bd->name);
    sys->ndof++;
  }
  return sys->nbodies++;
}

/* Adds sign * (displacement of the point along dir) to J. */
int rr_point_motion(const rr_body *b, const double *pt, int dir, double sign, double *J)
{
  double dx = pt[0] - b->ref[0], dy = pt[1] - b->ref[1], dz = pt[2] - b->ref[2];
  switch (dir) {
  case RR_DIR_X:
    if (b->dof_psi >= 0) J[b->dof_psi] += sign * -dy;
    return 0;
  case RR_DIR_Y:
    if (b->dof_y >= 0) J[b->dof_y] += sign;
    if (b->dof_psi >= 0) J[b->dof_psi] += sign * dx;
    if (b->dof_phi >= 0) J[b->dof_phi] += sign * -dz;
    return 0;
  case RR_DIR_Z:
    if (b->dof_phi >= 0) J[b->dof_phi] += sign * dy;
    return 0;
  case RR_DIR_ROLL:
    if (b->dof_phi >= 0) J[b->dof_phi] += sign;
    return 0;
  }
  return -1;
}

static void add_point_motion(const rr_system *sys, int body, const double *pt, int dir, double sign,
                             double *J)
{
  if (body != RR_GROUND) rr_point_motion(&sys->bodies[body], pt, dir, sign, J);
}

int rr_system_element_row(const rr_system *sys, const rr_element_spec *e, double *J, rr_error *err)
{
  if (e->body_a < RR_GROUND || e->body_a >= sys->nbodies || e->body_b < RR_GROUND ||
      e->body_b >= sys->nbodies)
    return rr_seterr(err, RR_EINVAL, "element %s: unknown body", e->name);
  if (e->body_a == e->body_b)
    return rr_seterr(err, RR_EINVAL, "element %s: joins a body to itself", e->name);
  if (e->direction < RR_DIR_X || e->direction > RR_DIR_ROLL)
    return rr_seterr(err, RR_EINVAL, "element %s: unknown direction", e->name);
  for (int i = 0; i < sys->ndof; i++) J[i] = 0;
  add_point_motion(sys, e->body_a, e->point, e->direction, 1.0, J);
  add_point_motion(sys, e->body_b, e->point, e->direction, -1.0, J);
  return RR_OK;
}

/* The new element's index (>= 0) or -status. */
static int add_element(rr_system *sys, const rr_element_spec *e, rr_error *err)
{
  const char *nm = e->name ? e->name : "element";
  int needk = e->law == RR_LAW_SPRING || e->law == RR_LAW_KC || e->law == RR_LAW_MAXWELL;
  int needc = e->law != RR_LAW_SPRING;
  if (e->law < RR_LAW_SPRING || e->law > RR_LAW_MAXWELL)
    return -rr_seterr(err, RR_EINVAL, "element %s: unknown law", nm);
  if (needk && (isnan(e->k) || e->k < 0 || (isinf(e->k) && e->law != RR_LAW_MAXWELL)))
    return -rr_seterr(err, RR_EINVAL, "element %s: stiffness must be finite and >= 0", nm);
  if (e->law == RR_LAW_MAXWELL && !(e->k > 0))
    return -rr_seterr(err, RR_EINVAL,
                      "element %s: series stiffness must be > 0 (inf for a rigid link)", nm);
  if (needc && !(isfinite(e->c) && e->c >= 0))
    return -rr_seterr(err, RR_EINVAL, "element %s: damping must be finite and >= 0", nm);
  if (grow((void **)&sys->elements, &sys->cap_elements, sys->nelements + 1, sizeof *sys->elements))
    return -rr_seterr(err, RR_ENOMEM, "out of memory");
  rr_elem *el = &sys->elements[sys->nelements];
  memset(el, 0, sizeof *el);
  int st = rr_system_element_row(sys, e, el->J, err);
  if (st) return -st;
  copy_name(el->name, sizeof el->name, nm, NULL);
  el->law = e->law;
  el->k = needk ? e->k : 0;
  el->c = needc ? e->c : 0;
  el->sdf = e->law == RR_LAW_MAXWELL && e->sdf;
  return sys->nelements++;
}

/* The new contact's index (>= 0) or -status. */
static int add_contact(rr_system *sys, const rr_contact_spec *c, rr_error *err)
{
  if (c->body < 0 || c->body >= sys->nbodies)
    return -rr_seterr(err, RR_EINVAL, "contact: unknown body");
  const rr_body *b = &sys->bodies[c->body];
  if (b->dof_y < 0 || b->dof_psi < 0)
    return -rr_seterr(err, RR_EINVAL, "contact: body %s needs y and psi DOFs", b->name);
  if (!(isfinite(c->f11) && c->f11 >= 0 && isfinite(c->f22) && c->f22 >= 0))
    return -rr_seterr(err, RR_EINVAL, "contact on %s: creep coefficients must be finite and >= 0",
                      b->name);
  if (!(isfinite(c->r0) && c->r0 > 0 && isfinite(c->l0) && c->l0 > 0))
    return -rr_seterr(err, RR_EINVAL, "contact on %s: r0 and l0 must be > 0", b->name);
  if (!(isfinite(c->axle_load) && c->axle_load >= 0))
    return -rr_seterr(err, RR_EINVAL, "contact on %s: axle load must be finite and >= 0", b->name);
  if (sys->ncontacts >= RR_SYS_MAX_INPUTS) return -rr_seterr(err, RR_EINVAL, "too many contacts");
  if (grow((void **)&sys->contacts, &sys->cap_contacts, sys->ncontacts + 1, sizeof *sys->contacts))
    return -rr_seterr(err, RR_ENOMEM, "out of memory");
  rr_contact *ct = &sys->contacts[sys->ncontacts];
  ct->spec = *c;
  ct->dof_y = b->dof_y;
  ct->dof_psi = b->dof_psi;
  if (!isfinite(c->dx))
    return -rr_seterr(err, RR_EINVAL, "contact on %s: offset must be finite", b->name);
  ct->x = b->ref[0] + c->dx;
  return sys->ncontacts++;
}

void rr_system_clear(rr_system *sys)
{
  sys->ndof = sys->nbodies = sys->nelements = sys->ncontacts = 0;
}

int rr_system_ndof(const rr_system *sys) { return sys->ndof; }

const char *rr_system_dof_name(const rr_system *sys, int i)
{
  return (i >= 0 && i < sys->ndof) ? sys->dof_name[i] : NULL;
}

int rr_system_add_body(rr_system *sys, const rr_body_spec *b, int *index, rr_error *err)
{
  int r = add_body(sys, b, err);
  if (r < 0) return -r;
  if (index) *index = r;
  return RR_OK;
}

int rr_system_add_element(rr_system *sys, const rr_element_spec *e, int *index, rr_error *err)
{
  int r = add_element(sys, e, err);
  if (r < 0) return -r;
  if (index) *index = r;
  return RR_OK;
}

int rr_system_add_contact(rr_system *sys, const rr_contact_spec *c, int *index, rr_error *err)
{
  int r = add_contact(sys, c, err);
  if (r < 0) return -r;
  if (index) *index = r;
  return RR_OK;
}
