/* Internal layout of rr_system, shared with the model assembler. */
#ifndef RR_SYSTEM_IMPL_H
#define RR_SYSTEM_IMPL_H

#include "railride/system.h"

#define RR_SYS_MAX_DOF 64
#define RR_SYS_MAX_BODIES 32
#define RR_SYS_MAX_INPUTS 16

typedef struct rr_body {
  char name[24];
  int group;
  double ref[3];
  int dof_y, dof_psi, dof_phi;
} rr_body;

/* The one home of point kinematics: adds sign x the motion of body b's point
   pt along dir (enum rr_direction) to the row J (length ndof); -1 for an
   unknown direction. u_x = -dy psi; u_y = y + dx psi - dz phi; u_z = dy phi. */
int rr_point_motion(const rr_body *b, const double *pt, int dir, double sign, double *J);

typedef struct rr_elem {
  char name[48];
  int law;
  double k, c;
  int sdf;
  double J[RR_SYS_MAX_DOF];
} rr_elem;

typedef struct rr_contact {
  rr_contact_spec spec;
  int dof_y, dof_psi;
  double x;
} rr_contact;

struct rr_system {
  int ndof;
  double mass[RR_SYS_MAX_DOF];
  int group[RR_SYS_MAX_DOF];
  char dof_name[RR_SYS_MAX_DOF][32];
  rr_body *bodies;
  int nbodies, cap_bodies;
  rr_elem *elements;
  int nelements, cap_elements;
  rr_contact *contacts;
  int ncontacts, cap_contacts;
};

/* Empties a system, keeping its storage (allocation-free refills). */
void rr_system_clear(rr_system *sys);

#endif
