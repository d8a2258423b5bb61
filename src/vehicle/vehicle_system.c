/* The 17-DOF vehicle as a configuration of the generic layer (docs/model.md section 1-3). */
#include <math.h>
#include <stdio.h>
#include "model_impl.h"
#include "internal.h"

#define TRY(expr)                                                                                  \
  do {                                                                                             \
    int r_ = (expr);                                                                               \
    if (r_ < 0) {                                                                                  \
      st = -r_;                                                                                    \
      goto fail;                                                                                   \
    }                                                                                              \
  } while (0)

int rr_vehicle_system(const rr_vehicle *v, rr_system **out, rr_error *err)
{
  *out = NULL;
  rr_system *s = rr_system_new();
  if (!s) return rr_seterr(err, RR_ENOMEM, "out of memory");
  int st = rr_vehicle_fill(v, s, err);
  if (st) {
    rr_system_free(s);
    return st;
  }
  *out = s;
  return RR_OK;
}

int rr_vehicle_fill(const rr_vehicle *v, rr_system *s, rr_error *err)
{
  int st = rr_vehicle_check(v, err);
  if (st) return st;
  rr_system_clear(s);
  const double L = v->bogie_half_spacing, b = v->wheelbase_half, r0 = v->rolling_radius;
  int body_c, body_f[2], body_w[4];
  rr_body_spec cb = {"c",
                     RR_GROUP_CARBODY,
                     v->carbody_mass,
                     v->carbody_yaw_inertia,
                     v->carbody_roll_inertia,
                     {0, 0, v->carbody_cg_height},
                     RR_DOF_Y | RR_DOF_PSI | RR_DOF_PHI};
  TRY(body_c = rr_system_add_body(s, &cb, err));
  const double xf[2] = {L, -L};
  const double xw[4] = {L + b, L - b, -L + b, -L - b};
  for (int j = 0; j < 2; j++) {
    char nm[8];
    snprintf(nm, sizeof nm, "f%d", j + 1);
    rr_body_spec fb = {nm,
                       RR_GROUP_FRAME,
                       v->frame_mass,
                       v->frame_yaw_inertia,
                       v->frame_roll_inertia,
                       {xf[j], 0, v->frame_cg_height},
                       RR_DOF_Y | RR_DOF_PSI | RR_DOF_PHI};
    TRY(body_f[j] = rr_system_add_body(s, &fb, err));
  }
  for (int i = 0; i < 4; i++) {
    char nm[8];
    snprintf(nm, sizeof nm, "w%d", i + 1);
    rr_body_spec wb = {nm, RR_GROUP_WHEELSET, v->wheelset_mass,     v->wheelset_yaw_inertia,
                       0,  {xw[i], 0, r0},    RR_DOF_Y | RR_DOF_PSI};
    TRY(body_w[i] = rr_system_add_body(s, &wb, err));
  }
  /* Maxwell elements first, in state order: yaw dampers (bogie 1 L, R,
     bogie 2 L, R), then lateral dampers (bogie 1, 2). */
  for (int j = 0; j < 2; j++)
    for (int side = 0; side < 2; side++) {
      double sg = side == 0 ? 1.0 : -1.0;
      char nm[48];
      snprintf(nm, sizeof nm, "yaw_damper_b%d_%s", j + 1, side == 0 ? "left" : "right");
      rr_element_spec e = {nm,
                           body_c,
                           body_f[j],
                           {xf[j], sg * v->yaw_half_spacing, v->yaw_height},
                           RR_DIR_X,
                           RR_LAW_MAXWELL,
                           v->yaw_series_stiffness,
                           v->yaw_damping,
                           v->sdf_mode != RR_SDF_NONE};
      TRY(rr_system_add_element(s, &e, err));
    }
  for (int j = 0; j < 2; j++) {
    char nm[48];
    snprintf(nm, sizeof nm, "lateral_damper_b%d", j + 1);
    rr_element_spec e = {nm,
                         body_c,
                         body_f[j],
                         {xf[j], 0, v->lateral_damper_height},
                         RR_DIR_Y,
                         RR_LAW_MAXWELL,
                         v->lateral_series_stiffness,
                         v->lateral_damping,
                         0};
    TRY(rr_system_add_element(s, &e, err));
  }
  for (int i = 0; i < 4; i++) {
    int j = i / 2;
    double sgn_x = xw[i] - xf[j] > 0 ? 1.0 : -1.0; /* arm node toward the bogie centre */
    for (int side = 0; side < 2; side++) {
      double sg = side == 0 ? 1.0 : -1.0;
      rr_element_spec ex = {"primary_longitudinal",
                            body_w[i],
                            body_f[j],
                            {xw[i], sg * v->primary_half_spacing, r0},
                            RR_DIR_X,
                            RR_LAW_SPRING,
                            v->primary_kx,
                            0,
                            0};
      rr_element_spec ey = {
          "primary_lateral",
          body_w[i],
          body_f[j],
          {xw[i] - sgn_x * v->primary_arm_length, sg * v->primary_half_spacing, r0},
          RR_DIR_Y,
          RR_LAW_SPRING,
          v->primary_ky,
          0,
          0};
      rr_element_spec ez = {"primary_vertical",
                            body_w[i],
                            body_f[j],
                            {xw[i], sg * v->primary_half_spacing, r0},
                            RR_DIR_Z,
                            RR_LAW_KC,
                            v->primary_kz,
                            v->primary_cz,
                            0};
      TRY(rr_system_add_element(s, &ex, err));
      TRY(rr_system_add_element(s, &ey, err));
      TRY(rr_system_add_element(s, &ez, err));
    }
  }
  for (int j = 0; j < 2; j++) {
    for (int side = 0; side < 2; side++) {
      double sg = side == 0 ? 1.0 : -1.0;
      double pt[3] = {xf[j], sg * v->secondary_half_spacing, v->secondary_height};
      rr_element_spec ex = {"secondary_longitudinal", body_c,   body_f[j],
                            {pt[0], pt[1], pt[2]},    RR_DIR_X, RR_LAW_SPRING,
                            v->secondary_kx,          0,        0};
      rr_element_spec ey = {"secondary_lateral",   body_c,   body_f[j],
                            {pt[0], pt[1], pt[2]}, RR_DIR_Y, RR_LAW_SPRING,
                            v->secondary_ky,       0,        0};
      rr_element_spec ez = {"secondary_vertical",  body_c,          body_f[j],
                            {pt[0], pt[1], pt[2]}, RR_DIR_Z,        RR_LAW_KC,
                            v->secondary_kz,       v->secondary_cz, 0};
      TRY(rr_system_add_element(s, &ex, err));
      TRY(rr_system_add_element(s, &ey, err));
      TRY(rr_system_add_element(s, &ez, err));
    }
    rr_element_spec ar = {"antiroll_bar",        body_c,      body_f[j],
                          {xf[j], 0, 0},         RR_DIR_ROLL, RR_LAW_SPRING,
                          v->antiroll_stiffness, 0,           0};
    TRY(rr_system_add_element(s, &ar, err));
  }
  double W = RR_G * (v->carbody_mass + 2 * v->frame_mass + 4 * v->wheelset_mass) / 4;
  for (int i = 0; i < 4; i++) {
    rr_contact_spec c = {body_w[i], v->f11, v->f22, r0, v->contact_half_spacing, W, 0};
    TRY(rr_system_add_contact(s, &c, err));
  }
  return RR_OK;
fail:
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
