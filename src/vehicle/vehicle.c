/* Vehicle parameters: the key table, built-in vehicles (docs/model.md section 9)
 * and range checks. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "railride/vehicle.h"
#include "util/internal.h"

#define OFF(f) offsetof(rr_vehicle, f)
#define NOFF ((size_t)-1)
enum {
  P = RR_KEY_POSITIVE,
  N = RR_KEY_NONNEG,
  INF = RR_KEY_INF_OK,
  OPT = RR_KEY_OPTIONAL,
  SPC = RR_KEY_SPECIAL
};

static const rr_vehicle_key keys[] = {
    {"vehicle", "name", "", NOFF, SPC | OPT, 0, 0,
     "the vehicle's name in outputs (default: the file's name)"},
    {"vehicle", "base", "", NOFF, SPC | OPT, 0, 0,
     "a built-in vehicle (type1, type2) or a file, relative to this one, whose keys this file "
     "inherits"},
    {"carbody", "mass", "kg", OFF(carbody_mass), P, 1000, 1e+06, "carbody mass m_c"},
    {"carbody", "roll_inertia", "kg.m2", OFF(carbody_roll_inertia), P, 1000, 1e+09,
     "carbody roll inertia I_cx about x through its centre of gravity"},
    {"carbody", "yaw_inertia", "kg.m2", OFF(carbody_yaw_inertia), P, 1000, 1e+09,
     "carbody yaw inertia I_cz about z"},
    {"carbody", "cg_height", "m", OFF(carbody_cg_height), N, 0, 10,
     "height h_c of the carbody's centre of gravity above rail"},
    {"carbody", "pitch_inertia", "kg.m2", OFF(carbody_pitch_inertia), P | OPT, 1000, 1e+09,
     "carbody pitch inertia I_cy about y (vertical model; default 2.0e6)"},
    {"carbody", "length", "m", OFF(carbody_length), P | OPT, 1, 100,
     "carbody length L_cb, the bending beam's (vertical model; default 25 m)"},
    {"carbody", "bending_frequency", "Hz", OFF(carbody_bending_frequency), P | OPT, 0.1, 200,
     "first free-free vertical bending frequency of the carbody alone (vertical model; 10 Hz)"},
    {"carbody", "bending_damping", "1", OFF(carbody_bending_damping), N | OPT, 0, 0.99,
     "modal damping ratio of that bending mode (vertical model; default 0.02)"},
    {"frame", "mass", "kg", OFF(frame_mass), P, 10, 100000, "bogie frame mass m_f (each)"},
    {"frame", "roll_inertia", "kg.m2", OFF(frame_roll_inertia), P, 1, 1e+07,
     "frame roll inertia I_fx"},
    {"frame", "yaw_inertia", "kg.m2", OFF(frame_yaw_inertia), P, 1, 1e+07,
     "frame yaw inertia I_fz"},
    {"frame", "cg_height", "m", OFF(frame_cg_height), N, 0, 10,
     "height h_f of the frame's centre of gravity above rail"},
    {"frame", "pitch_inertia", "kg.m2", OFF(frame_pitch_inertia), P | OPT, 1, 1e+07,
     "frame pitch inertia I_fy about y (vertical model; default 2000)"},
    {"wheelset", "mass", "kg", OFF(wheelset_mass), P, 10, 100000, "wheelset mass m_w (each)"},
    {"wheelset", "yaw_inertia", "kg.m2", OFF(wheelset_yaw_inertia), P, 1, 1e+06,
     "wheelset yaw inertia I_wz"},
    {"wheelset", "rolling_radius", "m", OFF(rolling_radius), P, 0.05, 2,
     "nominal rolling radius r0 (also the wheelset's centre height)"},
    {"wheelset", "contact_half_spacing", "m", OFF(contact_half_spacing), P, 0.1, 2,
     "half the lateral distance between the two wheel-rail contacts, l0"},
    {"layout", "bogie_half_spacing", "m", OFF(bogie_half_spacing), P, 0.3, 50,
     "L: car centre to bogie centre (bogie pivots at x = +-L)"},
    {"layout", "wheelbase_half", "m", OFF(wheelbase_half), P, 0.1, 10,
     "b: bogie centre to axle (half the bogie wheelbase)"},
    {"primary", "longitudinal_stiffness", "N/m", OFF(primary_kx), N, 0, 1e+12,
     "k_px: longitudinal stiffness of one axle box"},
    {"primary", "lateral_stiffness", "N/m", OFF(primary_ky), N, 0, 1e+12,
     "k_py: lateral stiffness of one axle box (at the rotating-arm node)"},
    {"primary", "vertical_stiffness", "N/m", OFF(primary_kz), N, 0, 1e+12,
     "k_pz: vertical stiffness of one axle box (acts on frame roll)"},
    {"primary", "vertical_damping", "N.s/m", OFF(primary_cz), N, 0, 1e+10,
     "c_pz: vertical damping of one axle box"},
    {"primary", "half_spacing", "m", OFF(primary_half_spacing), P, 0.05, 5,
     "l1: half the lateral spacing of the axle boxes"},
    {"primary", "arm_length", "m", OFF(primary_arm_length), N, 0, 5,
     "l_b: rotating-arm length, axle to lateral node, toward the bogie centre"},
    {"secondary", "longitudinal_stiffness", "N/m", OFF(secondary_kx), N, 0, 1e+12,
     "k_sx: longitudinal stiffness of one air spring"},
    {"secondary", "lateral_stiffness", "N/m", OFF(secondary_ky), N, 0, 1e+12,
     "k_sy: lateral stiffness of one air spring"},
    {"secondary", "vertical_stiffness", "N/m", OFF(secondary_kz), N, 0, 1e+12,
     "k_sz: vertical stiffness of one air spring"},
    {"secondary", "vertical_damping", "N.s/m", OFF(secondary_cz), N, 0, 1e+10,
     "c_sz: vertical damping of one air spring"},
    {"secondary", "half_spacing", "m", OFF(secondary_half_spacing), P, 0.05, 5,
     "l2: half the lateral spacing of the air springs"},
    {"secondary", "height", "m", OFF(secondary_height), N, 0, 10,
     "h_s: height of the air springs' attachment above rail"},
    {"secondary", "antiroll_stiffness", "N.m/rad", OFF(antiroll_stiffness), N, 0, 1e+12,
     "k_phi: anti-roll bar torsional stiffness, per bogie"},
    {"lateral_damper", "damping", "N.s/m", OFF(lateral_damping), N, 0, 1e+10,
     "c_sy: secondary lateral damper, one equivalent damper per bogie"},
    {"lateral_damper", "series_stiffness", "N/m", OFF(lateral_series_stiffness), P | INF, 1000,
     1e+15, "k_sys: its series (end) stiffness; inf for a plain damper"},
    {"lateral_damper", "height", "m", OFF(lateral_damper_height), N, 0, 10,
     "h_ld: its height above rail"},
    {"yaw_damper", "damping", "N.s/m", OFF(yaw_damping), N, 0, 1e+10,
     "c_sx: one yaw damper (two per bogie)"},
    {"yaw_damper", "series_stiffness", "N/m", OFF(yaw_series_stiffness), P | INF, 1000, 1e+15,
     "k_ncsx: its constant series stiffness; inf for a plain damper"},
    {"yaw_damper", "half_spacing", "m", OFF(yaw_half_spacing), P, 0.05, 5,
     "l_cx: half the lateral spacing of the yaw dampers"},
    {"yaw_damper", "height", "m", OFF(yaw_height), N, 0, 10,
     "h_yd: yaw dampers' height above rail"},
    {"yaw_damper", "sdf", "", NOFF, SPC | OPT, 0, 0,
     "frequency-dependent series stiffness: none, paper or physical"},
    {"yaw_damper", "sdf_k1", "Hz", OFF(sdf.k1_hz), P | OPT, 0.001, 1000,
     "K1: frequency scale of the SDF curve"},
    {"yaw_damper", "sdf_k2", "N/m", OFF(sdf.k2), N | OPT, 0, 1e+12,
     "K2: stiffness rise of the SDF curve"},
    {"yaw_damper", "sdf_k3", "N/m", OFF(sdf.k3), P | OPT, 1000, 1e+12,
     "K3: static stiffness of the SDF curve"},
    {"yaw_damper", "sdf_table", "", NOFF, SPC | OPT, 0, 0,
     "a CSV file f_hz, k_storage [, k_loss] (N/m) for the SDF curve, relative to this file"},
    {"contact", "longitudinal_creep", "N", OFF(f11), N, 0, 1e+11,
     "f11: Kalker longitudinal creep coefficient, per wheel"},
    {"contact", "lateral_creep", "N", OFF(f22), N, 0, 1e+11,
     "f22: Kalker lateral creep coefficient, per wheel"},
    {"contact", "gravity_stiffness", "", NOFF, SPC | OPT, 0, 0,
     "yes: add the gravitational stiffness (default no, as the paper)"},
    {"contact", "friction", "1", OFF(friction), P | OPT, 0.01, 2,
     "mu: friction coefficient of the creep saturation (nonlinear model; default 0.3)"},
    {"contact", "flange_clearance", "m", OFF(flange_clearance), N | OPT, 0, 0.05,
     "lateral play before the flange spring acts (nonlinear model; default 8 mm)"},
    {"contact", "flange_stiffness", "N/m", OFF(flange_stiffness), N | OPT, 0, 1e+11,
     "k_f: flange contact stiffness (nonlinear model; default 500 kN/mm; 0: no flange)"},
    {"contact", "conicity_poly", "", NOFF, SPC | OPT, 0, 0,
     "lambda(a) = c0 + c1 a + c2 a^2 ... with a in mm: the coefficients, space separated "
     "(nonlinear model)"},
    {"contact", "conicity_table", "", NOFF, SPC | OPT, 0, 0,
     "a CSV file a_mm, conicity for lambda(a), relative to this file (nonlinear model)"},
    {"contact", "conicity_hold", "m", OFF(conicity_hold), P | OPT, 1e-3, 0.05,
     "a polynomial lambda(a) is held at its value beyond this (default 12 mm)"},
    {"contact", "wheel", "", NOFF, SPC | OPT, 0, 0,
     "a wheel profile file (lateral vertical, mm; right side), relative to this file: the linear "
     "conicity becomes its equivalent conicity"},
    {"contact", "rail", "", NOFF, SPC | OPT, 0, 0, "the rail profile file (right side)"},
    {"contact", "wheel_left", "", NOFF, SPC | OPT, 0, 0, "the left wheel's (default: mirrored)"},
    {"contact", "rail_left", "", NOFF, SPC | OPT, 0, 0, "the left rail's (default: mirrored)"},
    {"contact", "gauge", "m", OFF(wheel_rail.gauge), P | OPT, 0.5, 3, "track gauge (1435 mm)"},
    {"contact", "flange_back", "m", OFF(wheel_rail.flange_back), P | OPT, 0.5, 3,
     "flange-back distance (1360 mm)"},
    {"contact", "wheel_origin", "m", OFF(wheel_rail.wheel_origin), N | OPT, 0, 0.5,
     "flange back to the wheel profile's origin (70 mm)"},
    {"contact", "inclination", "", NOFF, SPC | OPT, 0, 0,
     "rail inclination applied to the rail file: 1/40 (default), 1:20, a decimal, 0"},
    {"contact", "gauge_point", "", NOFF, SPC | OPT, 0, 0,
     "the rail file's gauge measuring point (a length), or auto (14 mm below the top of rail)"},
    {"contact", "roll", "", NOFF, SPC | OPT, 0, 0, "none (default) or rigid wheelset roll"},
    {"contact", "amplitude", "m", OFF(wheel_rail.amplitude), P | OPT, 1e-4, 0.02,
     "amplitude of the equivalent conicity that the linear model takes (3 mm)"},
    {"contact", "radius_left", "m", OFF(wheel_rail.radius_left), P | OPT, 0.1, 1,
     "the left wheel's nominal rolling radius (default: the vehicle's)"},
};

const rr_vehicle_key *rr_vehicle_keys(int *n)
{
  *n = (int)(sizeof keys / sizeof keys[0]);
  return keys;
}

const rr_vehicle_key *rr_vehicle_key_find(const char *sk)
{
  const char *dot = strchr(sk, '.');
  if (!dot) return NULL;
  size_t ls = (size_t)(dot - sk);
  for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
    if (keys[i].offset != NOFF && strlen(keys[i].section) == ls &&
        !strncmp(keys[i].section, sk, ls) && !strcmp(keys[i].key, dot + 1))
      return &keys[i];
  return NULL;
}

double *rr_vehicle_field(rr_vehicle *veh, const rr_vehicle_key *key)
{
  if (!key || key->offset == NOFF) return NULL;
  return (double *)((char *)veh + key->offset);
}

void rr_vehicle_default(rr_vehicle *v)
{
  memset(v, 0, sizeof *v);
  snprintf(v->name, sizeof v->name, "type1");
  /* Paper Table A1, kept as printed (roll/yaw inertia of the carbody look swapped: docs/model.md
   * section 9). */
  v->carbody_mass = 38936;
  v->carbody_roll_inertia = 1.67e6;
  v->carbody_yaw_inertia = 9.61e5;
  v->carbody_cg_height = 1.62;
  v->frame_mass = 2328;
  v->frame_roll_inertia = 2110;
  v->frame_yaw_inertia = 4080;
  v->frame_cg_height = 0.61;
  v->wheelset_mass = 1639;
  v->wheelset_yaw_inertia = 822;
  v->rolling_radius = 0.46;
  v->contact_half_spacing = 1.493 / 2;
  v->bogie_half_spacing = 17.375 / 2;
  v->wheelbase_half = 2.5 / 2;
  v->primary_kx = 50e6;
  v->primary_ky = 5e6;
  v->primary_kz = 0.75e6;
  v->primary_cz = 10e3;
  v->primary_half_spacing = 1.0;
  v->primary_arm_length = 0.48;
  v->secondary_kx = 0.133e6;
  v->secondary_ky = 0.133e6;
  v->secondary_kz = 0.2e6;
  v->secondary_cz = 10e3;
  v->secondary_half_spacing = 1.1;
  v->secondary_height = 0.77;
  v->antiroll_stiffness = 4.15e6;
  v->lateral_damping = 50e3;
  v->lateral_series_stiffness = 10e6;
  v->lateral_damper_height = 0.65;
  v->yaw_damping = 4000e3;
  v->yaw_series_stiffness = 10e6;
  v->yaw_half_spacing = 1.35;
  v->yaw_height = 0.61;
  v->sdf_mode = RR_SDF_NONE;
  v->sdf.kind = RR_CURVE_SLS; /* paper Table 2, Type 1 */
  v->sdf.k1_hz = 1.5;
  v->sdf.k2 = 8e6;
  v->sdf.k3 = 6e6;
  v->f11 = 1e7;
  v->f22 = 1e7;
  v->gravity_stiffness = 0;
  rr_vehicle_contact_defaults(v);
  rr_vehicle_vertical_defaults(v);
}

void rr_vehicle_vertical_defaults(rr_vehicle *v)
{
  v->carbody_pitch_inertia = RR_CARBODY_PITCH_INERTIA_DEFAULT;
  v->carbody_length = RR_CARBODY_LENGTH_DEFAULT;
  v->carbody_bending_frequency = RR_CARBODY_BENDING_FREQUENCY_DEFAULT;
  v->carbody_bending_damping = RR_CARBODY_BENDING_DAMPING_DEFAULT;
  v->frame_pitch_inertia = RR_FRAME_PITCH_INERTIA_DEFAULT;
}

void rr_vehicle_contact_defaults(rr_vehicle *v)
{
  v->friction = RR_FRICTION_DEFAULT;
  v->flange_clearance = RR_FLANGE_CLEARANCE_DEFAULT;
  v->flange_stiffness = RR_FLANGE_STIFFNESS_DEFAULT;
  v->conicity_hold = RR_CONICITY_HOLD_DEFAULT;
  memset(&v->profile, 0, sizeof v->profile);
  v->wheel_rail = (rr_wheel_rail){.gauge = 1.435,
                                  .flange_back = 1.360,
                                  .wheel_origin = 0.070,
                                  .inclination = 1.0 / 40,
                                  .gauge_point = NAN,
                                  .roll = 0,
                                  .amplitude = 3e-3,
                                  .radius_left = NAN};
}

int rr_vehicle_builtin(const char *name, rr_vehicle *v, rr_error *err)
{
  if (!strcmp(name, "type1") || !strcmp(name, "default")) {
    rr_vehicle_default(v);
    return RR_OK;
  }
  if (!strcmp(name, "type2")) {
    rr_vehicle_default(v);
    snprintf(v->name, sizeof v->name, "type2");
    v->lateral_damping = 15e3;
    v->yaw_damping = 660e3;
    v->sdf.k1_hz = 1.5; /* paper Table 2, Type 2 */
    v->sdf.k2 = 10e6;
    v->sdf.k3 = 2e6;
    return RR_OK;
  }
  return rr_seterr(err, RR_EINVAL, "unknown built-in vehicle '%s' (type1, type2)", name);
}

int rr_vehicle_key_check(const rr_vehicle_key *k, double x, rr_error *err)
{
  const char *u = strcmp(k->si_unit, "1") ? k->si_unit : "";
  if (isinf(x) && x > 0 && (k->flags & INF)) return RR_OK;
  if (isnan(x) || isinf(x))
    return rr_seterr(err, RR_EINVAL, "[%s] %s: value must be finite", k->section, k->key);
  if (x < k->min || x > k->max)
    return rr_seterr(err, RR_EINVAL, "[%s] %s: %g %s outside the physical range %g .. %g %s%s",
                     k->section, k->key, x, u, k->min, k->max, u,
                     (k->flags & INF) ? " (or inf)" : "");
  return RR_OK;
}

int rr_vehicle_check(const rr_vehicle *v, rr_error *err)
{
  for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
    const rr_vehicle_key *k = &keys[i];
    if (k->offset == NOFF) continue;
    if (!strncmp(k->key, "sdf_", 4) && v->sdf.kind != RR_CURVE_SLS)
      continue; /* no curve, or a table */
    if (!strcmp(k->key, "radius_left") && isnan(v->wheel_rail.radius_left)) continue; /* unset */
    int st = rr_vehicle_key_check(k, *(const double *)((const char *)v + k->offset), err);
    if (st) return st;
  }
  if (v->profile.kind != RR_PROFILE_NONE) {
    int st = rr_profile_check(&v->profile, err);
    if (st) return st;
  }
  if (v->sdf_mode < RR_SDF_NONE || v->sdf_mode > RR_SDF_PHYSICAL)
    return rr_seterr(err, RR_EINVAL, "[yaw_damper] sdf: unknown mode %d", v->sdf_mode);
  if (v->sdf_mode != RR_SDF_NONE) {
    int st = rr_sdf_curve_check(&v->sdf, "[yaw_damper]", err);
    if (st) return st;
  }
  return RR_OK;
}
