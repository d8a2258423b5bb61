/* The 17-DOF vehicle as a configuration of the generic layer (docs/model.md section 1-3). */
#include <math.h>
#include "model/model_impl.h"
#include "util/internal.h"

int rr_vehicle_system(const rr_vehicle *v, rr_system **out, rr_error *err)
{
  *out = NULL;
  rr_system *s;
  int st = rr_system_new(&s, err);
  if (st) return st;
  st = rr_vehicle_fill(v, s, err);
  if (st) {
    rr_system_free(s);
    return st;
  }
  *out = s;
  return RR_OK;
}

/* The bodies' indices and positions along the car. */
typedef struct car_layout {
  int c, f[2], w[4];   /* carbody, frames, wheelsets */
  double xf[2], xw[4]; /* frame and wheelset x (m) */
} car_layout;

static int add_bodies(const rr_vehicle *v, rr_system *s, car_layout *car, rr_error *err)
{
  const double L = v->bogie_half_spacing, b = v->wheelbase_half;
  *car = (car_layout){.xf = {L, -L}, .xw = {L + b, L - b, -L + b, -L - b}};
  rr_body_spec cb = {.name = "c",
                     .group = RR_GROUP_CARBODY,
                     .mass = v->carbody_mass,
                     .yaw_inertia = v->carbody_yaw_inertia,
                     .roll_inertia = v->carbody_roll_inertia,
                     .ref = {0, 0, v->carbody_cg_height},
                     .dofs = RR_DOF_Y | RR_DOF_PSI | RR_DOF_PHI};
  int st = rr_system_add_body(s, &cb, &car->c, err);
  if (st) return st;
  /* the names as constants: formatting them was a per cent of a design's
     evaluation in the optimiser's loop, which rebuilds the model each time */
  static const char *const frame[2] = {"f1", "f2"}, *const wheel[4] = {"w1", "w2", "w3", "w4"};
  for (int j = 0; j < 2; j++) {
    rr_body_spec fb = {.name = frame[j],
                       .group = RR_GROUP_FRAME,
                       .mass = v->frame_mass,
                       .yaw_inertia = v->frame_yaw_inertia,
                       .roll_inertia = v->frame_roll_inertia,
                       .ref = {car->xf[j], 0, v->frame_cg_height},
                       .dofs = RR_DOF_Y | RR_DOF_PSI | RR_DOF_PHI};
    if ((st = rr_system_add_body(s, &fb, &car->f[j], err))) return st;
  }
  for (int i = 0; i < 4; i++) {
    rr_body_spec wb = {.name = wheel[i],
                       .group = RR_GROUP_WHEELSET,
                       .mass = v->wheelset_mass,
                       .yaw_inertia = v->wheelset_yaw_inertia,
                       .roll_inertia = 0,
                       .ref = {car->xw[i], 0, v->rolling_radius},
                       .dofs = RR_DOF_Y | RR_DOF_PSI};
    if ((st = rr_system_add_body(s, &wb, &car->w[i], err))) return st;
  }
  return RR_OK;
}

static int add_element(rr_system *s, const rr_element_spec *e, rr_error *err)
{
  return rr_system_add_element(s, e, NULL, err);
}

/* Maxwell elements first, in state order: yaw dampers (bogie 1 L, R, bogie 2
   L, R), then lateral dampers (bogie 1, 2). */
static int add_dampers(const rr_vehicle *v, rr_system *s, const car_layout *car, rr_error *err)
{
  static const char *const yaw[2][2] = {{"yaw_damper_b1_left", "yaw_damper_b1_right"},
                                        {"yaw_damper_b2_left", "yaw_damper_b2_right"}},
                           *const lateral[2] = {"lateral_damper_b1", "lateral_damper_b2"};
  int st = RR_OK;
  for (int j = 0; j < 2; j++)
    for (int side = 0; side < 2 && !st; side++) {
      rr_element_spec e = {
          .name = yaw[j][side],
          .body_a = car->c,
          .body_b = car->f[j],
          .point = {car->xf[j], (side == 0 ? 1.0 : -1.0) * v->yaw_half_spacing, v->yaw_height},
          .direction = RR_DIR_X,
          .law = RR_LAW_MAXWELL,
          .k = v->yaw_series_stiffness,
          .c = v->yaw_damping,
          .sdf = v->sdf_mode != RR_SDF_NONE};
      st = add_element(s, &e, err);
    }
  for (int j = 0; j < 2 && !st; j++) {
    rr_element_spec e = {.name = lateral[j],
                         .body_a = car->c,
                         .body_b = car->f[j],
                         .point = {car->xf[j], 0, v->lateral_damper_height},
                         .direction = RR_DIR_Y,
                         .law = RR_LAW_MAXWELL,
                         .k = v->lateral_series_stiffness,
                         .c = v->lateral_damping,
                         .sdf = 0};
    st = add_element(s, &e, err);
  }
  return st;
}

/* A spring or spring-damper between bodies a and b at point p. */
static rr_element_spec element(const char *name, int a, int b, const double p[3], int direction,
                               int law, double k, double c)
{
  return (rr_element_spec){.name = name,
                           .body_a = a,
                           .body_b = b,
                           .point = {p[0], p[1], p[2]},
                           .direction = direction,
                           .law = law,
                           .k = k,
                           .c = c,
                           .sdf = 0};
}

/* Three elements in order (x, y, z); the first failure's status. */
static int add_three(rr_system *s, const rr_element_spec e[3], rr_error *err)
{
  int st = RR_OK;
  for (int k = 0; k < 3 && !st; k++) st = add_element(s, &e[k], err);
  return st;
}

/* Primary suspension: rotating-arm axle boxes, the lateral spring at the arm's
   node (toward the bogie centre), longitudinal and vertical at the axle. */
static int add_primary(const rr_vehicle *v, rr_system *s, const car_layout *car, rr_error *err)
{
  int st = RR_OK;
  for (int i = 0; i < 4 && !st; i++) {
    int j = i / 2, w = car->w[i], f = car->f[j];
    double sgn_x = car->xw[i] - car->xf[j] > 0 ? 1.0 : -1.0; /* arm node toward the bogie centre */
    for (int side = 0; side < 2 && !st; side++) {
      double y = (side == 0 ? 1.0 : -1.0) * v->primary_half_spacing;
      const double axle[3] = {car->xw[i], y, v->rolling_radius},
                   node[3] = {car->xw[i] - sgn_x * v->primary_arm_length, y, v->rolling_radius};
      const rr_element_spec e[3] = {
          element("primary_longitudinal", w, f, axle, RR_DIR_X, RR_LAW_SPRING, v->primary_kx, 0),
          element("primary_lateral", w, f, node, RR_DIR_Y, RR_LAW_SPRING, v->primary_ky, 0),
          element("primary_vertical", w, f, axle, RR_DIR_Z, RR_LAW_KC, v->primary_kz,
                  v->primary_cz)};
      st = add_three(s, e, err);
    }
  }
  return st;
}

/* Secondary suspension (air springs) and the anti-roll bars. */
static int add_secondary(const rr_vehicle *v, rr_system *s, const car_layout *car, rr_error *err)
{
  int st = RR_OK;
  for (int j = 0; j < 2 && !st; j++) {
    int c = car->c, f = car->f[j];
    for (int side = 0; side < 2 && !st; side++) {
      const double p[3] = {car->xf[j], (side == 0 ? 1.0 : -1.0) * v->secondary_half_spacing,
                           v->secondary_height};
      const rr_element_spec e[3] = {
          element("secondary_longitudinal", c, f, p, RR_DIR_X, RR_LAW_SPRING, v->secondary_kx, 0),
          element("secondary_lateral", c, f, p, RR_DIR_Y, RR_LAW_SPRING, v->secondary_ky, 0),
          element("secondary_vertical", c, f, p, RR_DIR_Z, RR_LAW_KC, v->secondary_kz,
                  v->secondary_cz)};
      st = add_three(s, e, err);
    }
    const double centre[3] = {car->xf[j], 0, 0};
    rr_element_spec ar =
        element("antiroll_bar", c, f, centre, RR_DIR_ROLL, RR_LAW_SPRING, v->antiroll_stiffness, 0);
    if (!st) st = add_element(s, &ar, err);
  }
  return st;
}

/* Wheel-rail contact at each wheelset; the axle load for the optional
   gravitational stiffness. */
static int add_contacts(const rr_vehicle *v, rr_system *s, const car_layout *car, rr_error *err)
{
  double W = RR_G * (v->carbody_mass + 2 * v->frame_mass + 4 * v->wheelset_mass) / 4;
  for (int i = 0; i < 4; i++) {
    rr_contact_spec c = {.body = car->w[i],
                         .f11 = v->f11,
                         .f22 = v->f22,
                         .r0 = v->rolling_radius,
                         .l0 = v->contact_half_spacing,
                         .axle_load = W,
                         .dx = 0};
    int st = rr_system_add_contact(s, &c, NULL, err);
    if (st) return st;
  }
  return RR_OK;
}

int rr_vehicle_fill(const rr_vehicle *v, rr_system *s, rr_error *err)
{
  int st = rr_vehicle_check(v, err);
  if (st) return st;
  rr_system_clear(s);
  car_layout car;
  if (!(st = add_bodies(v, s, &car, err)) && !(st = add_dampers(v, s, &car, err)) &&
      !(st = add_primary(v, s, &car, err)) && !(st = add_secondary(v, s, &car, err)))
    st = add_contacts(v, s, &car, err);
  return st;
}

int rr_model_rebuild(rr_model *m, const rr_vehicle *v, rr_system *scratch, rr_error *err)
{
  int st = rr_vehicle_fill(v, scratch, err);
  if (st) return st;
  double speed = m->speed, lam = m->conicity;
  if ((st = rr_model_assemble(m, scratch, err))) return st;
  m->gravity = v->gravity_stiffness;
  m->sdf_mode = RR_SDF_NONE;
  if (v->sdf_mode != RR_SDF_NONE && (st = rr_model_set_sdf(m, v->sdf_mode, &v->sdf, err)))
    return st;
  return rr_model_set_operating(m, speed, lam, err);
}

int rr_model_from_vehicle(const rr_vehicle *v, rr_model **out, rr_error *err)
{
  rr_system *s;
  int st = rr_vehicle_system(v, &s, err);
  if (st) return st;
  st = rr_model_new(s, out, err);
  rr_system_free(s);
  if (st) return st;
  (*out)->gravity = v->gravity_stiffness;
  rr_model_set_operating(*out, 1.0, 0.0, NULL);
  if (v->sdf_mode != RR_SDF_NONE) {
    st = rr_model_set_sdf(*out, v->sdf_mode, &v->sdf, err);
    if (st) {
      rr_model_free(*out);
      *out = NULL;
      return st;
    }
  }
  return RR_OK;
}
