/* railride: wheel-rail contact geometry from profiles and the equivalent
 * conicity (EN 15302), independent of the vehicle model (docs/contact.md).
 * Lengths in mm, angles in rad, as the profile files and the standard give
 * them. Plan/execute: a contact plan places the four profiles once (rail
 * inclination, gauge measuring point, lateral offsets); the contact at any
 * lateral displacement y is then an exact search over the polylines'
 * vertices; a conicity plan prepares a dr(y) table once, and the equivalent
 * conicity at any amplitude is then a few hundred operations. */
#ifndef RAILRIDE_CONTACT_H
#define RAILRIDE_CONTACT_H

#include "railride/common.h"
#include "railride/error.h"
#include "railride/vehicle.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A profile: n points (x strictly increasing, mm), piecewise linear between
 * them; owned arrays. Right-hand convention (the left side is the mirror). */
typedef struct rr_polyline {
  int n;
  double *x, *z;
} rr_polyline;
/* Two numeric columns (blanks, tab, comma or semicolon); '#' comments; text
 * before the first row is a header; at least 3 points, x strictly rising.
 * A built-in profile's name (rr_polyline_builtin), or a path ending in one,
 * gives that profile when no such file exists. */
RR_API int rr_polyline_load(const char *path, rr_polyline *p, rr_error *err);
/* A built-in design profile from its published definition: "S1002" (the
 * EN 13715 wheel, 0.1 mm apart from the flange back, u = -70 .. 60 mm) or
 * "60E1" (the EN 13674-1 rail head, upright, crown at the origin, to the end
 * of its 13 mm gauge-corner arc). */
RR_API int rr_polyline_builtin(const char *name, rr_polyline *p, rr_error *err);
/* 1 when name is a built-in profile's (rr_polyline_load takes it too). */
RR_API int rr_polyline_is_builtin(const char *name);
/* A copy of n points. */
RR_API int rr_polyline_from(const double *x, const double *z, int n, rr_polyline *p, rr_error *err);
RR_API void rr_polyline_free(rr_polyline *p);

typedef struct rr_contact_opts {
  double gauge_mm;          /* 1435 */
  double flange_back_mm;    /* 1360 */
  double wheel_origin_mm;   /* flange back to the wheel origin (measuring circle), 70 */
  double inclination;       /* tan of the angle turning the rail file, 0 (as stored) */
  double gmp_depth_mm;      /* gauge measuring point below the top of rail, 14 */
  double gmp_right_mm;      /* the rail files' gauge measuring points (after inclination); */
  double gmp_left_mm;       /*   NaN: found 14 mm below the top of rail */
  double lateral_offset_mm; /* the wheel origin less the rail origin, both sides; NaN: placed */
  double r0_right_mm, r0_left_mm; /* nominal rolling radii at the measuring circles, 460 */
  rr_contact_roll roll;           /* RR_ROLL_NONE */
} rr_contact_opts;
/* The defaults given in the fields' comments. */
RR_API rr_contact_opts rr_contact_opts_default(void);

/* Where the placement put things (docs/contact.md, placement). */
typedef struct rr_contact_setup {
  double b_mm;         /* wheel origin from the wheelset centre: FB/2 + d_fb */
  double Y_mm[2];      /* rail origin from the track centre, right, left */
  double offset_mm[2]; /* b - Y, right, left */
  double gmp_v_mm[2], gmp_z_mm[2];
  int gmp_at_data_end[2];
  double r0_mm[2];
} rr_contact_setup;

typedef struct rr_contact_plan rr_contact_plan;
/* Places the profiles (copied: the caller keeps its own). wheel_left or
 * rail_left NULL: the right one mirrored. */
RR_API int rr_contact_plan_new(const rr_polyline *wheel_right, const rr_polyline *wheel_left,
                               const rr_polyline *rail_right, const rr_polyline *rail_left,
                               const rr_contact_opts *o, rr_contact_plan **out, rr_error *err);
RR_API void rr_contact_plan_free(rr_contact_plan *p);
RR_API void rr_contact_plan_setup(const rr_contact_plan *p, rr_contact_setup *out);

/* One side's contact at a displacement, in its local (outward) frames. */
typedef struct rr_contact_side {
  double rail_v_mm, rail_z_mm;   /* the contact point on the rail */
  double wheel_u_mm, wheel_z_mm; /* and on the wheel */
  double r_mm;                   /* rolling radius r0 - z_w(u) */
  double gamma_rad;              /* contact angle, positive rising to the field side */
  double lift_mm;                /* height of the wheel origin above the rail origin level */
  int valid;                     /* 0: the contact is at the end of a profile's data */
} rr_contact_side;
typedef struct rr_contact_state {
  double y_mm;  /* lateral displacement of the wheelset, positive to the right */
  double dr_mm; /* r_right - r_left */
  double roll_rad, roll_implied_rad;
  rr_contact_side side[2]; /* right, left */
  int valid;
} rr_contact_state;
/* The contact at each of n displacements y (mm, in order: with rigid roll
 * each point starts from the previous one's roll). Allocation-free. */
RR_API int rr_contact_execute(const rr_contact_plan *p, const double *y_mm, int n,
                              rr_contact_state *out, rr_error *err);
/* A contact jump: the rail contact of a side moving by more than 1 mm
 * between neighbouring grid points. Returns how many were found (at most
 * cap stored). */
typedef struct rr_contact_jump {
  int side; /* 0 right, 1 left */
  double y_from_mm, y_to_mm, rail_from_mm, rail_to_mm, wheel_from_mm, wheel_to_mm;
} rr_contact_jump;
RR_API int rr_contact_jumps(const rr_contact_state *s, int n, rr_contact_jump *out, int cap);

/* Inclusive range a:b:step as the standard's tools make it: x_k = rint((a +
 * k step) 1e10) / 1e10, k = 0 .. floor((b - a) / step + 1e-9); the count
 * (out may be NULL to ask it), -1 when step <= 0 or b < a. */
RR_API long rr_contact_range(double a, double b, double step, double *out, long cap);

/* The equivalent conicity of a dr(y) table (piecewise linear): the run of
 * valid points around y = 0, the equilibrium y0, and per amplitude the
 * EN 15302 wavelength method (a), harmonic linearisation (b) and linear
 * regression (c). */
typedef struct rr_conicity_plan rr_conicity_plan;
/* y strictly increasing (mm), dr (mm), valid (may be NULL: all valid). */
RR_API int rr_conicity_plan_new(const double *y_mm, const double *dr_mm, const int *valid, int n,
                                rr_conicity_plan **out, rr_error *err);
RR_API void rr_conicity_plan_free(rr_conicity_plan *p);
/* The equilibrium dr(y0) = 0 (NaN when none), and the valid range used. */
RR_API double rr_conicity_y0(const rr_conicity_plan *p);
RR_API void rr_conicity_range(const rr_conicity_plan *p, double *first_mm, double *last_mm);

typedef struct rr_conicity {
  double amplitude_mm;
  double tan_gamma_e;            /* (a) EN 15302 reference: NaN when undefined, 0 in a dead zone */
  double turning_mm[2];          /* (a) yL, yR */
  double energy;                 /* (a) C */
  double wavelength_mm;          /* (a) 2 pi sqrt(e0 r0 / tan_gamma_e); inf when it is 0 */
  double tan_gamma_e_harmonic;   /* (b) */
  double harmonic_centre_mm;     /* (b) y_c */
  double tan_gamma_e_regression; /* (c) */
} rr_conicity;
/* All three at one amplitude (mm); e0, r0 (mm) only for the wavelength.
 * Allocation-free (the plan holds the scratch: one thread at a time per
 * plan); undefined values are NaN, never an error. */
RR_API void rr_conicity_eval(rr_conicity_plan *p, double amplitude_mm, double e0_mm, double r0_mm,
                             rr_conicity *out);

/* The vehicle's [contact] profiles (rr_wheel_rail): 1 when it names a wheel. */
RR_API int rr_vehicle_has_profiles(const rr_vehicle *v);
/* Names the vehicle's profiles: wheel on both sides, and rail on both sides
 * when given (else the vehicle's own rail stays); the placement keys stay.
 * RR_EINVAL for a path that does not fit or no rail at all (v unchanged). */
RR_API int rr_vehicle_set_profiles(rr_vehicle *v, const char *wheel, const char *rail,
                                   rr_error *err);
/* The linear model's conicity from them: tan_gamma_e by EN 15302's method at
 * the section's amplitude, on the grid -10:10:0.01 mm, with the vehicle's
 * rolling radius; source (n bytes) says where it came from, e.g. "profiles
 * RUIC519A.dat/SUIC519A.dat at 3 mm". An undefined value is an error. */
RR_API int rr_vehicle_profile_conicity(const rr_vehicle *v, double *conicity, char *source,
                                       size_t n, rr_error *err);
/* The same profiles' equivalent conicity function: tan_gamma_e (method a) at
 * namp amplitudes (mm) into tan_ge (NaN where undefined: no error). */
RR_API int rr_vehicle_profile_conicity_function(const rr_vehicle *v, const double *amp_mm, int namp,
                                                double *tan_ge, rr_error *err);

/* ---- the contact functions the nonlinear model reads (docs/model.md) ---- */
/* A wheelset's contact on its track on a uniform grid of the lateral
 * displacement y_k = y0_m + k dy_m, k = 0 .. n - 1 (m, positive to the right
 * as above): dr = r_right - r_left (m), the tangents of the right and left
 * contact angles, and whether both contacts lie within the profiles' data.
 * Owned arrays (rr_contact_functions_free). */
#define RR_CONTACT_EDGES_MAX 24
typedef struct rr_contact_functions {
  int n;
  double y0_m, dy_m;
  double *dr_m, *tan_right, *tan_left;
  int *valid;
  int nedges; /* the grid cells of contact jumps (rr_contact_jumps), by their edges' y (m): */
  double edge_y_m[RR_CONTACT_EDGES_MAX]; /*  where the functions are steepest */
  char source[160];                      /* where they came from: "profiles WHEEL/RAIL" */
} rr_contact_functions;
RR_API void rr_contact_functions_free(rr_contact_functions *cf);
/* The vehicle's [contact] profiles on the grid -10:10:0.01 mm, with the
 * vehicle's rolling radius and the section's placement and roll. */
RR_API int rr_vehicle_contact_functions(const rr_vehicle *v, rr_contact_functions *out,
                                        rr_error *err);
#ifdef __cplusplus
}
#endif
#endif
