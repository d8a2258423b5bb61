/* railride: modal analysis and the vehicle stability index (docs/model.md,
 * "Modes and stability"). */
#ifndef RAILRIDE_MODAL_H
#define RAILRIDE_MODAL_H

#include "railride/common.h"
#include "railride/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How paper-mode SDF self-consistent modes are found. Both follow each
 * oscillatory branch on the same stiffness grid and give the same modes (to
 * 1e-13 in zeta); the reference runs a full eigen-solve with vectors at every
 * grid and bisection point (~1000 solves), the fast method continues each
 * branch by Newton's method on the 17-DOF dynamic stiffness and finds the
 * root of h(k) by a safeguarded secant. */
typedef enum rr_sdf_tracking { RR_TRACK_FAST = 0, RR_TRACK_REFERENCE = 1 } rr_sdf_tracking;

/* The index's band edge (docs/model.md, "Modes and stability"): by default
 * (fmax_hz = RR_FMAX_AUTO) max(RR_FMAX_FLOOR_HZ, f_K) at each operating point,
 * f_K the free wheelset's kinematic frequency (rr_model_kinematic_hz); a
 * positive fmax_hz fixes it (the paper's band: 10). */
#define RR_FMAX_AUTO 0.0
#define RR_FMAX_FLOOR_HZ 10.0

typedef struct rr_modal_opts {
  double fmax_hz;           /* band edge of the index (Hz); RR_FMAX_AUTO (default) or fixed */
  double w_min;             /* least wheelset kinetic-energy share of a hunting mode (1e-3) */
  double r_max;             /* frame-roll kinetic-energy share a hunting mode stays below (0.5) */
  rr_sdf_tracking tracking; /* paper-mode SDF method (RR_TRACK_FAST) */
} rr_modal_opts;
/* The defaults given in the fields' comments. */
RR_API rr_modal_opts rr_modal_opts_default(void);

#define RR_MODE_NAME_MAX 48

typedef struct rr_mode {
  double re, im;             /* eigenvalue (1/s), im >= 0 */
  double freq_hz;            /* im / 2 pi */
  double zeta;               /* re / |lambda|: negative is stable */
  double energy[RR_NGROUPS]; /* kinetic-energy shares carbody, frames, wheelsets */
  double roll_share;         /* kinetic-energy share of all roll DOFs */
  double frame_roll_share;   /* kinetic-energy share of the frames' roll DOFs */
  int oscillatory;           /* im > 1e-6 |lambda| */
  int hunting;         /* hunting-related: wheelset share >= w_min, frame-roll share < r_max */
  int in_index;        /* counted in the vehicle stability index */
  int self_consistent; /* paper SDF mode: a self-consistent root was found */
  double sdf_k;        /* paper SDF mode: series stiffness at the root (N/m) */
  char name[RR_MODE_NAME_MAX]; /* dominant motion, e.g. "carbody lateral-yaw", "frames roll" */
} rr_mode;

/* What set the vehicle stability index (docs/model.md, "Modes and
 * stability"): its sign is always the verdict. */
typedef enum rr_index_source {
  RR_INDEX_NONE = 0,     /* undefined (NaN): no hunting-related mode and all stable */
  RR_INDEX_HUNTING = 1,  /* the least damped hunting-related mode below fmax */
  RR_INDEX_UNSTABLE = 2, /* an unstable mode outside the hunting rule or band (zeta_max) */
} rr_index_source;

typedef struct rr_modal_result {
  int n; /* modes stored (one per conjugate pair, plus real ones) */
  int cap;
  rr_mode *modes; /* sorted: oscillatory by frequency, then real ones */
  int ndof;
  rr_complex *shapes;     /* q part of each mode's eigenvector, n x ndof */
  double stability_index; /* the index: hunting_index, or zeta_max when that is >= 0;
                             NaN when undefined */
  int index_mode;         /* which mode gave it, -1 when undefined */
  rr_index_source index_source;
  double hunting_index; /* max zeta over the hunting-related modes below fmax; NaN when none */
  int hunting_mode;     /* which mode gave it, -1 when none */
  double zeta_max;      /* max zeta over every oscillatory mode (any frequency, shape); -1
                           when there is none */
  int max_mode;         /* which mode gave it, -1 when none */
  double fmax_hz;       /* the band edge used (Hz) */
} rr_modal_result;

/* The index's band edge at m's operating point under o (NULL: defaults):
 * o->fmax_hz when positive, else max(RR_FMAX_FLOOR_HZ, f_K). */
RR_API double rr_modal_band_edge(const rr_model *m, const rr_modal_opts *o);
/* The same at speed_ms, conicity (the model's own operating point unused). */
RR_API double rr_modal_band_edge_at(const rr_model *m, const rr_modal_opts *o, double speed_ms,
                                    double conicity);

/* The verdict rule: a vehicle is stable at an operating point when every
 * oscillatory mode, of any frequency and shape, has zeta < 0. */
static inline int rr_modal_stable(double zeta_max) { return zeta_max < 0; }

typedef struct rr_modal_ws rr_modal_ws;
/* Workspace for a model's state size (and its ndof); reuse across calls. */
RR_API int rr_modal_ws_new(const rr_model *m, rr_modal_ws **out, rr_error *err);
RR_API void rr_modal_ws_free(rr_modal_ws *ws);
RR_API int rr_modal_result_alloc(const rr_model *m, rr_modal_result *res, rr_error *err);
RR_API void rr_modal_result_free(rr_modal_result *res);

/* All modes with energy shares, names and shapes. Paper SDF mode:
 * self-consistent modes. */
RR_API int rr_modal_solve(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                          rr_modal_result *res, rr_error *err);

/* Stability at one operating point, without mode shapes where none are
 * needed. */
typedef struct rr_stability {
  double index;           /* vehicle stability index (rr_modal_result); NaN when undefined */
  double index_freq_hz;   /* frequency of the mode that sets it; NaN when undefined */
  rr_index_source source; /* what set it */
  double hunting_index;   /* the hunting-related modes' own largest zeta; NaN when none */
  double zeta_max;        /* largest zeta over every oscillatory mode; -1 when none */
  double max_freq_hz;     /* frequency of that mode; NaN when none */
  double fmax_hz;         /* the index's band edge used (Hz) */
} rr_stability;

/* The index from its two parts, the one home of the rule: the hunting
 * modes' largest zeta, unless some oscillatory mode is unstable (zeta_max >=
 * 0), which then sets it; undefined (NaN, RR_INDEX_NONE) when no mode
 * qualifies and all are stable. *which: 0 hunting, 1 zeta_max's mode, -1 none. */
RR_API double rr_modal_index_rule(double hunting_index, double zeta_max, int have_max,
                                  rr_index_source *source, int *which);
/* "hunting mode", "unstable mode outside the hunting band", "none". */
RR_API const char *rr_index_source_name(rr_index_source s);

/* By the cheapest exact route: eigenvalues of the state matrix, then (17 x 17
 * inverse iteration) the shapes of candidate modes only; paper-mode SDF by
 * branch tracking. Allocation-free. */
RR_API int rr_modal_stability(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                              rr_stability *out, rr_error *err);
/* The index alone (out.index of rr_modal_stability). */
RR_API int rr_modal_stability_index(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                                    double *zeta, rr_error *err);

/* rr_modal_stability at npts operating points (speeds in m/s, conicities):
 * out[p] equals the single-point result to rounding. Groups of up to
 * as many points as the CPU's vector width holds (8 with AVX-512, else 4) share one instruction
 * stream, their QR sweeps in SIMD lanes; paper-mode SDF models go one point at
 * a time. The model's operating point is restored. Allocation-free. */
RR_API int rr_modal_stability_batch(rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, int npts,
                                    const double *speed_ms, const double *conicity,
                                    rr_stability *out, rr_error *err);
/* The same with point p on models[p]: models of one vehicle layout (the one
 * ws was made for; another is RR_EINVAL), such as the designs of one
 * optimiser generation, whose points then share the SIMD lanes. out[p]
 * equals rr_modal_stability on models[p] to the last bit; every model's
 * operating point is restored. Allocation-free. */
RR_API int rr_modal_stability_many(rr_model *const *models, const rr_modal_opts *o, rr_modal_ws *ws,
                                   int npts, const double *speed_ms, const double *conicity,
                                   rr_stability *out, rr_error *err);

/* Modal assurance criterion of two complex vectors. */
RR_API double rr_mac(const rr_complex *a, const rr_complex *b, int n);

#ifdef __cplusplus
}
#endif
#endif
