/* railride: the nonlinear vehicle for hunting bifurcation (docs/model.md,
 * "Nonlinear model"). The linear model of sections 1-5 with conicity a
 * function of the wheelset's lateral displacement, creep forces saturated per
 * wheel (Shen, Hedrick & Elkins) and a flange dead-band spring; everything
 * else, the Maxwell dampers included, stays linear. Time integration by
 * SUNDIALS CVODE(S); limit cycles by shooting with the monodromy matrix from
 * forward sensitivities, followed in speed by pseudo-arclength continuation
 * from the Hopf point. */
#ifndef RAILRIDE_NONLINEAR_H
#define RAILRIDE_NONLINEAR_H

#include "railride/common.h"

#include <stdint.h>
#include "railride/contact.h"
#include "railride/model.h"
#include "railride/profile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the contact law ---- */

typedef struct rr_contact_law {
  double friction;         /* mu (0.3, an assumption) */
  double flange_clearance; /* m (8 mm, an assumption) */
  double flange_stiffness; /* N/m (500 kN/mm, Table A1); 0: no flange */
  int saturation;          /* 1: Shen-Hedrick-Elkins (default); 0: linear Kalker forces */
} rr_contact_law;
/* The defaults given in the fields' comments. */
RR_API rr_contact_law rr_contact_law_default(void);

/* ---- the nonlinear right-hand side ---- */

typedef struct rr_nonlinear rr_nonlinear;
/* From a model (its speed taken as is; SDF none or physical: paper mode has
 * no time form). Only wheelsets whose contact sits at their reference point. */
RR_API int rr_nonlinear_new(const rr_model *m, const rr_profile *p, const rr_contact_law *law,
                            rr_nonlinear **out, rr_error *err);
/* From a model and the contact functions of wheel and rail profiles
 * (docs/model.md, "Contact geometry from profiles"): dr(y) in the
 * longitudinal creepages and the normal forces' lateral resultant
 * -(Q/2)(tan gamma_L - tan gamma_R) in place of lambda(a), the flange spring
 * and the gravitational terms; read at y = -(y_w - y_t), linear between the
 * grid's points. law gives the friction and the saturation (its flange keys
 * are not used). The contact at y = 0 must lie within the data. */
RR_API int rr_nonlinear_new_contact(const rr_model *m, const rr_contact_functions *cf,
                                    const rr_contact_law *law, rr_nonlinear **out, rr_error *err);
/* The range of y_w - y_t (m) around 0 over which every contact lies within
 * the profiles' data (-inf, inf without contact functions). A state beyond
 * it ends a simulation with RR_EDERAIL. */
RR_API void rr_nonlinear_contact_range(const rr_nonlinear *nl, double *lo_m, double *hi_m);
RR_API void rr_nonlinear_free(rr_nonlinear *nl);
RR_API int rr_nonlinear_set_speed(rr_nonlinear *nl, double v_ms, rr_error *err);
RR_API double rr_nonlinear_speed(const rr_nonlinear *nl);
/* State size N: [q; dq/dt; Maxwell strokes (; inner strokes)], as
 * rr_model_state_matrix. */
RR_API int rr_nonlinear_size(const rr_nonlinear *nl);
RR_API int rr_nonlinear_ndof(const rr_nonlinear *nl);
/* Per-state absolute tolerances from a displacement tolerance (velocities 50x). */
RR_API void rr_nonlinear_atol(const rr_nonlinear *nl, double atol_m, double *atol);
/* Index of wheelset w's lateral displacement y_w (and, + ndof, its rate). */
RR_API int rr_nonlinear_index_y(const rr_nonlinear *nl, int wheelset);
RR_API int rr_nonlinear_ninputs(const rr_nonlinear *nl);
/* dz/dt at state z with track alignment yt[i] per wheelset (NULL: straight,
 * perfect track). Allocation-free. */
RR_API void rr_nonlinear_rhs(const rr_nonlinear *nl, const double *z, const double *yt, double *dz);
/* Its Jacobian d(dz/dt)/dz (N x N, row-major). */
RR_API void rr_nonlinear_jacobian(const rr_nonlinear *nl, const double *z, const double *yt,
                                  double *J);
/* Contact forces of wheelset i (saturated creep: lateral force N and yaw
 * moment N m; the flange's lateral force N). */
RR_API void rr_nonlinear_forces(const rr_nonlinear *nl, const double *z, const double *yt, int i,
                                double *fy, double *mz, double *flange);

/* ---- time integration (CVODE BDF, dense Newton, analytic Jacobian) ---- */

typedef struct rr_sim_opts {
  double duration_s; /* (10) */
  double fs_hz;      /* output samples per second (200) */
  double rtol;       /* relative tolerance (1e-7) */
  double atol_m; /* absolute tolerance on displacements, m (1e-10); velocities and strokes scaled
                    alike */
  const double *yt,
      *dyt; /* track: ninputs x nsamples at fs_hz (alignment m, its rate m/s), or NULL */
  int nsamples_track;
  rr_progress progress; /* after each sample: (samples done, nsamples); none by default */
} rr_sim_opts;
/* The defaults given in the fields' comments. */
RR_API rr_sim_opts rr_sim_opts_default(void);
/* Integrates from z0 (N); out: nsamples x N states at t = k / fs,
 * k = 0 .. nsamples - 1 (nsamples = floor(duration fs) + 1). Stopped by
 * the progress callback: RR_ESTOPPED, the samples it was last told were
 * done in place. */
RR_API int rr_simulate(const rr_nonlinear *nl, const double *z0, const rr_sim_opts *o, double *out,
                       int nsamples, rr_error *err);

/* ---- limit cycles and the bifurcation diagram ---- */

typedef struct rr_cycle {
  double speed_ms; /* the parameter */
  double period_s;
  double amplitude_m; /* max |y_w1| over the cycle (leading wheelset) */
  double floquet_max; /* largest |multiplier| but the trivial one */
  int stable;         /* floquet_max < 1 */
  int symmetric; /* z(t + T/2) = -z(t), the left-right symmetric hunting that leaves the Hopf point
                    (shot over half a period) */
  double residual; /* |phi_T(z0) - z0| / |z0| (symmetric: |phi_T/2(z0) + z0| / |z0|) */
} rr_cycle;

#define RR_ORBIT_V_MIN_KMH 100 /* the diagram's default range, km/h */
#define RR_ORBIT_V_MAX_KMH 600
typedef struct rr_orbit_opts {
  double v_min_ms, v_max_ms; /* the diagram's range (RR_ORBIT_V_*_KMH); a Hopf point outside it is
                                followed from there, within 5 % of its speed */
  double amp_max_m;          /* stop beyond this amplitude (30 mm) */
  double ds;                 /* first arclength step, in (mm, 10 km/h) units (0.2) */
  int max_points;            /* (400) */
  double rtol;               /* shooting's integration tolerance (1e-10) */
  rr_runner_opts runner;     /* where the monodromy matrix's column groups run (none: here) */
  rr_progress progress;      /* after each point: (points, max_points); a stop ends the branch
                                (RR_BRANCH_STOPPED) with what is found, folds left unrefined */
} rr_orbit_opts;
/* The defaults given in the fields' comments. */
RR_API rr_orbit_opts rr_orbit_opts_default(void);

typedef enum rr_bif_type {
  RR_BIF_NONE = 0,
  RR_BIF_SUPERCRITICAL = 1,
  RR_BIF_SUBCRITICAL = 2
} rr_bif_type;
typedef enum rr_branch_end {
  RR_BRANCH_RANGE = 0,     /* left the speed range */
  RR_BRANCH_AMPLITUDE = 1, /* beyond amp_max */
  RR_BRANCH_CAP = 2,       /* max_points reached */
  RR_BRANCH_STALLED =
      3, /* Newton failed even at the smallest step (a grazing corner, a period doubling) */
  RR_BRANCH_LINEAR = 4, /* the model is linear: no branch */
  RR_BRANCH_STOPPED = 5 /* the caller's progress callback asked to stop: the points so far */
} rr_branch_end;

/* Where the branch's stability changes between two of its points: the kind
   of crossing of the unit circle by the Floquet multipliers. */
typedef enum rr_bif_event_kind {
  RR_EVENT_FOLD = 0, /* a real multiplier through +1: a fold (the branch turns back in speed) */
  RR_EVENT_SYMMETRY_BREAKING = 1, /* a symmetric cycle's half-period multiplier through -1:
                                     asymmetric cycles branch off (not followed) */
  RR_EVENT_PERIOD_DOUBLING = 2,   /* a real multiplier through -1 (a cycle that is not symmetric) */
  RR_EVENT_TORUS = 3              /* a complex pair through the unit circle (Neimark-Sacker) */
} rr_bif_event_kind;
typedef struct rr_bif_event {
  rr_bif_event_kind kind;
  int index;                       /* between the branch's points index - 1 and index */
  double speed_lo_ms, speed_hi_ms; /* between cycles this close on the branch (0.1 km/h or
                                      0.01 mm of arclength, by bisection along it) */
  double speed_ms;                 /* midway */
  int gained; /* unstable directions beyond the event less those before (+-1, a pair +-2) */
} rr_bif_event;
#define RR_BIF_MAX_EVENTS 16

typedef struct rr_bifurcation {
  int hopf;             /* 1: the straight-track equilibrium loses stability below 2000 km/h */
  double hopf_speed_ms; /* the linear critical speed at lambda(0) (NaN: none) */
  double hopf_freq_hz;
  double
      hopf_speed_branch_ms; /* the branch extrapolated to zero amplitude (an independent check) */
  double nonlinear_critical_ms; /* the lowest speed of any cycle on the branch, folds refined (NaN:
                                   none) */
  rr_bif_type type;             /* how the branch leaves the Hopf point */
  int npoints;                  /* points on the branch */
  rr_branch_end end;            /* why the branch ended */
  int nevents;                  /* stability changes along the branch, in its order (the first
                                   RR_BIF_MAX_EVENTS) */
  rr_bif_event events[RR_BIF_MAX_EVENTS];
} rr_bifurcation;

/* The nonlinear vehicle at speed v_ms: profile and contact law NULL take the
 * vehicle's (its [contact] keys): with [contact] wheel and rail profiles,
 * their contact functions (rr_nonlinear_new_contact), else its lambda(a);
 * the model's conicity is lambda(0). */
RR_API int rr_nonlinear_from_vehicle(const rr_vehicle *veh, const rr_profile *p,
                                     const rr_contact_law *law, double v_ms, rr_nonlinear **out,
                                     rr_error *err);

/* The Hopf point alone (res's hopf fields; the rest NaN / none): the linear
 * critical speed at lambda(0), or on contact functions that of the nonlinear
 * vehicle's own linearisation at rest (their slopes at y = 0 and the normal
 * forces' stiffness), any oscillatory mode, 10 km/h .. RR_SPEED_MAX. */
RR_API int rr_bifurcation_hopf(const rr_vehicle *veh, const rr_profile *p,
                               const rr_contact_law *law, rr_bifurcation *res, rr_error *err);

/* The bifurcation diagram by continuation: the Hopf point (the linear
 * critical speed at lambda(0), any oscillatory mode), then the branch of
 * limit cycles born there, by shooting and pseudo-arclength continuation,
 * each point's stability from its Floquet multipliers. out: cap points;
 * z_out (cap x N initial states, each on the cycle with dy_w1/dt = 0) may be
 * NULL. */
RR_API int rr_bifurcation_continue(const rr_vehicle *veh, const rr_profile *p,
                                   const rr_contact_law *law, const rr_orbit_opts *o, rr_cycle *out,
                                   double *z_out, int cap, rr_bifurcation *res, rr_error *err);

/* The brute-force method (the paper's): direct integration at each speed of
 * vs (ascending), each run from the previous one's end state, then back down
 * from the top; settle_s of transient, then the amplitude and frequency of
 * y_w1 over measure_s. up, down: nv each (amplitude 0 where the motion dies
 * out: below 1 um, or its amplitude over the second half of the window more
 * than 2 % below the first half's). The first run starts from y0_m on every
 * wheelset; on the way up, a run after one whose motion died out starts from
 * reseed_m on every wheelset (a dead state cannot grow, however unstable the
 * speed), and the way down starts from y0_m when the top speed has no cycle. */
typedef struct rr_scan_point {
  double speed_ms, amplitude_m, frequency_hz;
} rr_scan_point;
typedef struct rr_scan_opts {
  double settle_s, measure_s, y0_m, reseed_m;
  rr_progress progress; /* after each run: (runs done, 2 nv), up then down; a stop returns
                           RR_ESTOPPED with the points not run NaN */
} rr_scan_opts;
/* The defaults given in the fields' comments. */
RR_API rr_scan_opts rr_scan_opts_default(void); /* 20 s, 2 s, 10 mm, 0.1 mm */
RR_API int rr_bifurcation_scan(const rr_vehicle *veh, const rr_profile *p,
                               const rr_contact_law *law, const double *vs, int nv,
                               const rr_scan_opts *o, rr_scan_point *up, rr_scan_point *down,
                               rr_error *err);

/* One cycle by shooting at the nonlinear vehicle's speed from a guess
 * (z0, T), refined in place. */
RR_API int rr_cycle_shoot(rr_nonlinear *nl, double *z0, double *T, double rtol, rr_cycle *out,
                          rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
