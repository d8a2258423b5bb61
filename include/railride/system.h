/* railride: the generic linear multibody layer.
 * Bodies carry up to three lateral-plane DOFs (y, yaw psi, roll phi) about a
 * reference point; point elements join a point of body A to a point of body B
 * (or the ground) along x, y, z, or in roll. A point at offset (dx,dy,dz) from a
 * body's reference moves by u_x = -dy psi, u_y = y + dx psi - dz phi,
 * u_z = dy phi (docs/model.md section 1). Elongation e = u_A - u_B along the
 * direction, e = J q. The 17-DOF vehicle is one configuration of this layer;
 * tests build single wheelsets and rigid bogies with it. */
#ifndef RAILRIDE_SYSTEM_H
#define RAILRIDE_SYSTEM_H

#include "railride/common.h"

#include "railride/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RR_GROUND (-1)
enum rr_dof_flags { RR_DOF_Y = 1, RR_DOF_PSI = 2, RR_DOF_PHI = 4 };
enum rr_direction { RR_DIR_X = 0, RR_DIR_Y = 1, RR_DIR_Z = 2, RR_DIR_ROLL = 3 };
/* Kinetic-energy groups of docs/model.md section 5. */
enum rr_group { RR_GROUP_CARBODY = 0, RR_GROUP_FRAME = 1, RR_GROUP_WHEELSET = 2, RR_NGROUPS = 3 };
enum rr_law {
  RR_LAW_SPRING = 0, /* k */
  RR_LAW_DAMPER = 1, /* c */
  RR_LAW_KC = 2,     /* k and c in parallel */
  RR_LAW_MAXWELL = 3 /* c in series with k (k = inf: plain damper) */
};

typedef struct rr_system rr_system;

typedef struct rr_body_spec {
  const char *name; /* DOFs are named y_<name>, psi_<name>, phi_<name> */
  enum rr_group group;
  double mass;         /* kg */
  double yaw_inertia;  /* kg m^2 (about z) */
  double roll_inertia; /* kg m^2 (about x) */
  double ref[3];       /* reference point x, y, z (m) */
  unsigned dofs;       /* RR_DOF_* mask; order in the DOF vector: y, psi, phi */
} rr_body_spec;

typedef struct rr_element_spec {
  const char *name;
  int body_a, body_b; /* body indices or RR_GROUND */
  double point[3];    /* absolute point x, y, z (m); unused for roll */
  enum rr_direction direction;
  enum rr_law law;
  double k; /* N/m (N m/rad in roll): parallel spring, or series spring of a Maxwell */
  double c; /* N s/m */
  int sdf;  /* Maxwell whose series spring follows the SDF curve */
} rr_element_spec;

typedef struct rr_contact_spec {
  int body;         /* wheelset body (needs y and psi DOFs) */
  double f11, f22;  /* Kalker coefficients per wheel (N) */
  double r0, l0;    /* rolling radius, half contact spacing (m) */
  double axle_load; /* N, for the optional gravitational stiffness */
  double dx;        /* contact x offset from the body reference (m): a rigid
                       bogie carries two contacts at +-b; 0 for a wheelset */
} rr_contact_spec;

/* An empty system into *out (free with rr_system_free). */
RR_API int rr_system_new(rr_system **out, rr_error *err);
RR_API void rr_system_free(rr_system *sys);
/* Adds a body; *index (may be NULL) receives its index. */
RR_API int rr_system_add_body(rr_system *sys, const rr_body_spec *b, int *index, rr_error *err);
/* Adds an element; *index (may be NULL) receives its index. */
RR_API int rr_system_add_element(rr_system *sys, const rr_element_spec *e, int *index,
                                 rr_error *err);
/* Adds a wheel-rail contact; its track input is the next input column, whose
 * number *index (may be NULL) receives. */
RR_API int rr_system_add_contact(rr_system *sys, const rr_contact_spec *c, int *index,
                                 rr_error *err);
RR_API int rr_system_ndof(const rr_system *sys);
RR_API const char *rr_system_dof_name(const rr_system *sys, int i);
/* The elongation row J (length ndof) of an element spec, without adding it. */
RR_API int rr_system_element_row(const rr_system *sys, const rr_element_spec *e, double *J,
                                 rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
