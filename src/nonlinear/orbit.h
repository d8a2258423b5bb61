/* Periodic orbits of an autonomous ODE with a parameter: shooting (Newton on
 * the return map; the monodromy matrix and the parameter derivative from the
 * variational equations, integrated with the orbit by SUNDIALS ARKODE's
 * explicit 8th-order Fehlberg pair), Floquet multipliers, and pseudo-arclength
 * continuation from a Hopf point (Seydel, Practical Bifurcation and Stability
 * Analysis, ch. 7). Generic, so that a system with a known answer (a van der
 * Pol oscillator) tests the same code the vehicle runs. */
#ifndef RR_ORBIT_H
#define RR_ORBIT_H

#include "nonlinear/ode_cvodes.h"
#include "railride/common.h"
#include "railride/nonlinear.h"

#define RR_ORBIT_MAX_KINKS 64
/* The variational equations run in this many groups of columns, each with
   its own copy of the orbit: jobs for a runner (rr_runner_opts). */
#define RR_ORBIT_GROUPS 2

typedef struct rr_orbit_sys {
  rr_ode ode; /* autonomous (t unused); p the continuation parameter */
  /* Optional, for speed: out = J X, J = df/dz at z, X and out n x m row by
     row (the m columns side by side), with df/dp added to the last column
     when dfdp. NULL: the dense ode.jac and a central difference in p. */
  void (*jvp)(void *user, double p, const double *z, const double *X, int m, int dfdp, double *out);
  /* Optional: nkinks functions of z whose sign changes mark where f is not
     smooth (a dead band's edges); the integration stops at each. */
  int nkinks;
  void (*kinks)(void *user, double p, const double *z, double *g);
  int k_amp;       /* the coordinate whose extreme is the amplitude */
  int k_phase;     /* the phase condition: z0[k_phase] = 0 (its rate: a turning point) */
  double amp_unit; /* arclength units of amplitude and parameter */
  double p_unit;
  const double *atol; /* per-state typical magnitudes on an orbit of amplitude amp_unit (n) */
  /* f(-z) = -f(z): the branch from the Hopf point is followed as symmetric
     orbits, z(t + T/2) = -z(t), shot over half a period (the return map of
     the half period composed with z -> -z). The full period's multipliers
     are the squares of that map's; a real one of them crossing -1 is a
     symmetry-breaking bifurcation. */
  int odd;
  /* Optional: the Jacobian whose critical eigenvector starts the branch at
     amplitude amp (a describing function: the linearisation that a cycle of
     that amplitude sees); NULL: ode.jac at z = 0. */
  void (*start_jac)(void *user, double p, double amp, double *J);
  /* Optional, with start_jac: the parameter at which that linearisation has
     a neutral oscillatory mode, the guess for the cycle of amplitude amp
     (the branch's second start point too); 0 or an error status. */
  int (*start_p)(void *user, double amp, double *p, rr_error *err);
  /* Newton's iterations before it gives up (0: 12) and its tolerance on
     |phi_T(z0) - z0| / |z0| (0: 5e-9). Tabulated contact functions, linear
     between grid points, with the steep cells of contact jumps, make the
     return map's derivative jump along the orbit: Newton converges
     linearly, to a floor of about 1e-5 set by the integrator's steps. */
  int newton_maxit;
  double newton_tol;
} rr_orbit_sys;

/* Multipliers outside the unit circle, by the kind of bifurcation their
   crossing makes: real above 1 (a fold, or a branch point), real below -1
   (symmetric orbits: symmetry breaking; others: period doubling), complex
   pairs (a torus), each pair counted once. */
enum { RR_CROSS_FOLD, RR_CROSS_FLIP, RR_CROSS_TORUS, RR_CROSS_KINDS };

typedef struct rr_orbit {
  double p, T, amp;
  double floquet_max; /* largest |multiplier| of the period but the one nearest 1 */
  int stable;
  int symmetric;               /* shot as z(t + T/2) = -z(t) (rr_orbit_sys.odd) */
  int outside[RR_CROSS_KINDS]; /* multipliers outside the unit circle, by kind */
  double residual;             /* |phi_T(z0) - z0| / |z0| (symmetric: |phi_T/2(z0) + z0| / |z0|) */
  int iterations;
} rr_orbit;

/* Newton on (z0, T) at fixed p (fix_p) or on (z0, T, p) with the amplitude
   fixed at amp (fix_amp): one orbit, refined in place; a whole period's
   (symmetric orbits too). */
int rr_orbit_solve(const rr_orbit_sys *s, double *z0, double *T, double *p, double rtol,
                   int fix_amp, double amp, rr_orbit *out, rr_error *err);

/* Unstable directions of an orbit: its multipliers outside the unit
   circle, a complex pair counting twice. */
int rr_orbit_unstable_dims(const rr_orbit *o);

/* Between two orbits of a branch, Xa and Xb ((z0, T, p) each, n + 2) with
   ra, rb their results, whose unstable dimensions differ: orbits on the
   branch between them (pseudo-arclength from Xa toward Xb, half the chord),
   keeping the half where the dimension changes, until the chord is below
   ds_tol (scaled units) or an orbit fails to converge. The bracket in place. */
int rr_orbit_bisect(const rr_orbit_sys *s, const rr_runner_opts *run, double *Xa, rr_orbit *ra,
                    double *Xb, rr_orbit *rb, double ds_tol, double rtol, rr_error *err);

/* A fold of the branch (a turning point in p) near its orbit (z0, T, p),
   whose z0[k_amp] is amp: the vertex of p against z0[k_amp], from orbits at
   fixed z0[k_amp] = a - d, a, a + d, a parabola through them, twice more
   around its vertex with d / 4. The branch's formulation (symmetric when
   s->odd). */
int rr_orbit_fold(const rr_orbit_sys *s, const rr_runner_opts *run, const double *z0, double T,
                  double p, double d, double rtol, double *p_fold, double *amp_fold, rr_error *err);

/* The Floquet multiplier of largest modulus but the trivial one (*mu) and
   its eigenvector (the real part for a complex pair) at the orbit (z0, T, p). */
int rr_orbit_floquet_vector(const rr_orbit_sys *s, const double *z0, double T, double p, double *mu,
                            double *v, rr_error *err);

/* The branch from the Hopf point p_hopf (the equilibrium z = 0 there has a
   pair +-i w): points appended to out (cap), states to z_out (cap x n, may be
   NULL). Stops outside [p_min, p_max], beyond amp_max or at cap points. */
typedef struct rr_branch_opts {
  double p_min, p_max, amp_max, amp_start, ds, ds_max, rtol;
  int cap;
  rr_runner_opts runner;
  rr_progress progress; /* after each point (points, cap): a stop ends the branch */
} rr_branch_opts;
/* *end: RR_BRANCH_RANGE left [p_min, p_max], _AMPLITUDE beyond amp_max, _CAP
   max points reached, _STALLED Newton failed at the smallest step, _STOPPED
   the progress callback asked (RR_OK: the points so far are the branch). */
int rr_orbit_branch(const rr_orbit_sys *s, double p_hopf, const rr_branch_opts *o, rr_orbit *out,
                    double *z_out, int *n, rr_branch_end *end, rr_error *err);

/* The nonlinear vehicle as an rr_orbit_sys, for bifurcation.c: amplitude y_w1,
   phase dy_w1/dt = 0; *atol allocated (free it). */
struct rr_nonlinear;
int rr_nonlinear_orbit_sys(struct rr_nonlinear *nl, rr_orbit_sys *s, double **atol, rr_error *err);

#endif
