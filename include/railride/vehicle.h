/* railride: vehicle parameters and vehicle files (docs/model.md section 9 and 9).
 * All fields are SI: kg, kg m^2, m, N/m, N s/m, N m/rad, Hz. The struct is
 * plain data: copy it, change a field, build a new model. */
#ifndef RAILRIDE_VEHICLE_H
#define RAILRIDE_VEHICLE_H

#include "railride/common.h"

#include <stddef.h>
#include "railride/error.h"
#include "railride/profile.h"
#include "railride/units.h"
#include "railride/sdf.h"

#ifdef __cplusplus
extern "C" {
#endif
/* The operating range a model accepts: speed in (0, RR_SPEED_MAX_MS] m/s
   (2000 km/h), equivalent conicity in [0, RR_CONICITY_MAX] (a wheel's
   conicity stays below ~1; the margin leaves room for studies). */
#define RR_SPEED_MAX_MS (2000 / RR_KMH)
#define RR_CONICITY_MAX 5.0

/* The [contact] section's wheel and rail profiles, from which the linear
 * model's conicity is the equivalent conicity (docs/contact.md): files
 * (right; left "" = mirrored), placement, roll and the amplitude; SI. */
#define RR_PROFILE_PATH_MAX 1024
/* The wheelset's roll in the contact search. */
typedef enum rr_contact_roll {
  RR_ROLL_NONE = 0, /* each wheel lowered onto its rail independently (EN 15302) */
  RR_ROLL_RIGID = 1 /* a rigid wheelset: both wheels touch, roll solved */
} rr_contact_roll;
typedef struct rr_wheel_rail {
  char wheel[2][RR_PROFILE_PATH_MAX], rail[2][RR_PROFILE_PATH_MAX]; /* right, left */
  double gauge, flange_back, wheel_origin;                          /* m: 1.435, 1.360, 0.070 */
  double inclination; /* tan of the rail inclination applied (1/40) */
  double gauge_point; /* m, the rail file's; NaN: 14 mm below the top */
  rr_contact_roll roll;
  double amplitude;   /* m: the amplitude of the linear conicity, 3 mm */
  double radius_left; /* m; NaN: the vehicle's rolling radius */
} rr_wheel_rail;

typedef struct rr_vehicle {
  char name[64];
  /* [carbody] */
  double carbody_mass, carbody_roll_inertia, carbody_yaw_inertia, carbody_cg_height;
  /* [carbody], the vertical model: pitch inertia (kg m^2), length (m), the
     first free-free vertical bending mode's frequency (Hz) and damping ratio */
  double carbody_pitch_inertia, carbody_length, carbody_bending_frequency, carbody_bending_damping;
  /* [frame] */
  double frame_mass, frame_roll_inertia, frame_yaw_inertia, frame_cg_height;
  double frame_pitch_inertia; /* the vertical model */
  /* [wheelset] */
  double wheelset_mass, wheelset_yaw_inertia, rolling_radius, contact_half_spacing;
  /* [layout]: L (bogie centre to car centre), b (half wheelbase) */
  double bogie_half_spacing, wheelbase_half;
  /* [primary], per axle box */
  double primary_kx, primary_ky, primary_kz, primary_cz, primary_half_spacing, primary_arm_length;
  /* [secondary], per air spring; anti-roll per bogie */
  double secondary_kx, secondary_ky, secondary_kz, secondary_cz, secondary_half_spacing,
      secondary_height, antiroll_stiffness;
  /* [lateral_damper], one equivalent damper per bogie */
  double lateral_damping, lateral_series_stiffness, lateral_damper_height;
  /* [yaw_damper], per damper (2 per bogie) */
  double yaw_damping, yaw_series_stiffness, yaw_half_spacing, yaw_height;
  rr_sdf_mode sdf_mode;
  rr_sdf_curve sdf; /* curve; kind RR_CURVE_UNSET when none */
  /* [contact], per wheel */
  double f11, f22;
  int gravity_stiffness; /* 0 or 1 */
  /* [contact], the nonlinear model only: friction coefficient, flange
     clearance (m) and stiffness (N/m), the tread's conicity lambda(a)
     (kind RR_PROFILE_NONE when the file gives none) */
  double friction, flange_clearance, flange_stiffness;
  double conicity_hold; /* m: a polynomial lambda(a) is held beyond (12 mm) */
  rr_profile profile;
  rr_wheel_rail wheel_rail; /* [contact] wheel and rail profiles (wheel[0] "": none) */
} rr_vehicle;

/* Built-in vehicles: "type1" (the default), "type2". Each carries its Table 2
 * SDF curve with sdf = none. Returns RR_EINVAL for an unknown name. */
RR_API int rr_vehicle_builtin(const char *name, rr_vehicle *veh, rr_error *err);
/* The default vehicle (Type 1). */
RR_API void rr_vehicle_default(rr_vehicle *veh);
/* The nonlinear model's contact assumptions (docs/model.md, "Nonlinear
 * model"): friction 0.3, flange clearance 8 mm, flange stiffness 500 kN/mm,
 * polynomial hold 12 mm; no tread profile. */
#define RR_FRICTION_DEFAULT 0.3
#define RR_FLANGE_CLEARANCE_DEFAULT 8e-3
#define RR_FLANGE_STIFFNESS_DEFAULT 500e6
#define RR_CONICITY_HOLD_DEFAULT 12e-3
/* Sets those defaults in veh (the other fields untouched). */
RR_API void rr_vehicle_contact_defaults(rr_vehicle *veh);
/* The vertical model's assumptions (docs/vertical.md, "Vehicle"): carbody
 * pitch inertia 2.0e6 kg m^2 (a uniform 25 m beam's m L^2/12, rounded),
 * length 25 m, first bending 10 Hz with damping ratio 0.02; frame pitch
 * inertia 2000 kg m^2. */
#define RR_CARBODY_PITCH_INERTIA_DEFAULT 2.0e6
#define RR_CARBODY_LENGTH_DEFAULT 25.0
#define RR_CARBODY_BENDING_FREQUENCY_DEFAULT 10.0
#define RR_CARBODY_BENDING_DAMPING_DEFAULT 0.02
#define RR_FRAME_PITCH_INERTIA_DEFAULT 2000.0
/* Sets those defaults in veh (the other fields untouched). */
RR_API void rr_vehicle_vertical_defaults(rr_vehicle *veh);
/* Loads an INI vehicle file (with `base =` inheritance). */
RR_API int rr_vehicle_load(const char *path, rr_vehicle *veh, rr_error *err);
/* Loads a built-in name if `spec` is one, otherwise a file. NULL -> default. */
RR_API int rr_vehicle_open(const char *spec, rr_vehicle *veh, rr_error *err);
/* For bindings that cannot size an rr_vehicle (ctypes, FFI): one opened from
 * a spec (as rr_vehicle_open) on the heap into *out (free with
 * rr_vehicle_delete). */
RR_API int rr_vehicle_new(const char *spec, rr_vehicle **out, rr_error *err);
RR_API void rr_vehicle_delete(rr_vehicle *veh);
/* Checks every value's range and finiteness. */
RR_API int rr_vehicle_check(const rr_vehicle *veh, rr_error *err);

/* Vehicle-file keys as data, so optimisers can address "section.key". */
typedef struct rr_vehicle_key {
  const char *section, *key;
  const char *si_unit; /* udunits spelling of the SI unit, "1" for dimensionless */
  size_t offset;       /* offset of the double in rr_vehicle, or (size_t)-1 */
  int flags;           /* RR_KEY_* */
  double min, max;     /* physical range, SI, inclusive (inf allowed with RR_KEY_INF_OK) */
  const char *doc;     /* what the key means, one line */
} rr_vehicle_key;
enum {
  RR_KEY_POSITIVE = 1, /* > 0 */
  RR_KEY_NONNEG = 2,   /* >= 0 */
  RR_KEY_INF_OK = 4,   /* may be inf (rigid series link) */
  RR_KEY_OPTIONAL = 8, /* not required without a base */
  RR_KEY_SPECIAL = 16, /* not a plain double (enum, bool, path) */
  RR_KEY_ANY_SIGN = 32 /* finite, any sign */
};
/* The key table; *n receives its length. */
RR_API const rr_vehicle_key *rr_vehicle_keys(int *n);
/* Finds "section.key" among the numeric keys; NULL when unknown. */
RR_API const rr_vehicle_key *rr_vehicle_key_find(const char *section_dot_key);
/* Checks x against the key's physical range; the message names the key and
 * the range. */
RR_API int rr_vehicle_key_check(const rr_vehicle_key *key, double x, rr_error *err);
/* Pointer to the double a numeric key addresses. */
RR_API double *rr_vehicle_field(rr_vehicle *veh, const rr_vehicle_key *key);

#ifdef __cplusplus
}
#endif
#endif
