/* railride: the vertical ride model (docs/vertical.md): carbody bounce, pitch
 * and first free-free bending, two frames in bounce and pitch, four wheelsets
 * following the track's vertical profile; modes; the pseudo-excitation method
 * with the wheelsets' delays; every vertical ride index and the 5 s RMS
 * percentiles of EN 12299 at floor points.
 * Plan/execute as the lateral PEM: a plan fixes the grid, the window and the
 * floor points (by default +L, 0, -L of the model it is executed on) and
 * owns all workspace and the weightings; executing it on a model, a speed and
 * a spectrum allocates nothing. SI throughout (speeds in m/s). */
#ifndef RAILRIDE_VERTICAL_H
#define RAILRIDE_VERTICAL_H

#include "railride/common.h"
#include "railride/comfort.h"
#include "railride/error.h"
#include "railride/spectrum.h"
#include "railride/timesim.h"
#include "railride/vehicle.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Coordinates, in the order of every matrix and output. */
enum rr_vdof {
  RR_V_ZC = 0,  /* carbody bounce, m */
  RR_V_THC = 1, /* carbody pitch, rad (positive lowers the front) */
  RR_V_QB = 2,  /* carbody first bending, modal coordinate m sqrt(kg) */
  RR_V_ZF1 = 3, /* front frame bounce, m */
  RR_V_THF1 = 4,
  RR_V_ZF2 = 5, /* rear frame bounce, m */
  RR_V_THF2 = 6
};
#define RR_VDOF 7
#define RR_VINPUTS 4 /* wheelsets, front to rear */
/* beta L of the free-free beam's first elastic mode: cos(bL) cosh(bL) = 1 */
#define RR_BEAM_BETA_L 4.730040744862704

/* The assembled model: M q'' + C q' + K q = BK z_w + BC z_w', row-major. */
typedef struct rr_vertical_model {
  double M[RR_VDOF]; /* diagonal */
  double K[RR_VDOF * RR_VDOF], C[RR_VDOF * RR_VDOF];
  double BK[RR_VDOF * RR_VINPUTS], BC[RR_VDOF * RR_VINPUTS];
  double x_frames[2];             /* +L, -L */
  double x_wheelsets[RR_VINPUTS]; /* L+b, L-b, -L+b, -L-b */
  double d_wheelsets[RR_VINPUTS]; /* distance behind the leading wheelset */
  double phi_pivots[2];           /* phi(x_frames), 1/sqrt(kg) */
  double carbody_length, carbody_mass;
} rr_vertical_model;

/* Assembles the model of a vehicle (its values checked, b < L < L_cb/2). */
RR_API int rr_vertical_model_build(const rr_vehicle *veh, rr_vertical_model *m, rr_error *err);
/* The beam's first free-free shape W(x), x from the centre of a beam of
 * length len: (1/len) integral W^2 = 1, W(0) > 0, W(+-len/2) = -2. */
RR_API double rr_beam_shape(double x, double len);
/* The mass-normalised shape phi(x) = W(x)/sqrt(m_c) of the model's carbody. */
RR_API double rr_vertical_phi(const rr_vertical_model *m, double x);
/* The floor's vertical displacement row at x: w(x) = row . q. */
RR_API void rr_vertical_floor_row(const rr_vertical_model *m, double x, double row[RR_VDOF]);

/* Modes of the 14-state system, oscillatory ones (Im > 1e-6 |lambda|) by
 * frequency. energy: kinetic-energy shares per coordinate (sum 1). */
typedef struct rr_vertical_mode {
  double freq_hz, natural_hz, damping_ratio; /* damping ratio -Re/|lambda| */
  double re, im;                             /* lambda, 1/s */
  double energy[RR_VDOF];
  char name[64];
} rr_vertical_mode;
typedef struct rr_vertical_modes {
  int nmodes, nreal;
  rr_vertical_mode mode[RR_VDOF];
  double real[2 * RR_VDOF];    /* the non-oscillatory eigenvalues, 1/s */
  double undamped_hz[RR_VDOF]; /* sqrt(eig(M^-1 K)) / 2 pi, increasing */
} rr_vertical_modes;
RR_API int rr_vertical_modes_compute(const rr_vertical_model *m, rr_vertical_modes *out,
                                     rr_error *err);
/* The state matrix A = [[0, I], [-M^-1 K, -M^-1 C]] (14 x 14, row-major). */
RR_API void rr_vertical_state_matrix(const rr_vertical_model *m, double *A);

/* The ride evaluation's settings, each default named. */
#define RR_VERTICAL_WINDOW_DEFAULT 5.0 /* s: EN 12299's RMS window */
#define RR_VERTICAL_POINTS_MAX 16
#define RR_VERTICAL_SPECTRUM_DEFAULT "tbt3352-vertical"
typedef struct rr_vertical_opts {
  int nfreq;                               /* 400 */
  double f_lo_hz, f_hi_hz;                 /* 0.3, 30 */
  int npoints;                             /* 0: +L, 0, -L of the model executed on */
  double x_points[RR_VERTICAL_POINTS_MAX]; /* m, |x| <= L_cb/2 */
  double window_s;                         /* 5; 0: no 5 s statistics (wb_5s holds the RMS only) */
  const double *freqs_hz; /* an explicit grid (nfreq, increasing), or NULL: log-spaced */
} rr_vertical_opts;
RR_API rr_vertical_opts rr_vertical_opts_default(void);

/* One floor point's vertical indices (m/s^2 unless said). */
typedef struct rr_vertical_point {
  double x; /* m */
  double rms, sperling, sperling_gb, wk_rms, wb_rms, wb_iso8041_rms;
  rr_window_stats wb_5s; /* EN 12299 Wb */
  double n_mv_vertical;  /* 6 a_ZP95 */
} rr_vertical_point;

typedef struct rr_vertical_plan rr_vertical_plan;
RR_API int rr_vertical_plan_new(const rr_vertical_opts *o, rr_vertical_plan **out, rr_error *err);
RR_API void rr_vertical_plan_free(rr_vertical_plan *p);
RR_API int rr_vertical_nfreq(const rr_vertical_plan *p);
RR_API const double *rr_vertical_freqs(const rr_vertical_plan *p);
/* The floor points of the last execute (npoints, x in m). */
RR_API int rr_vertical_npoints(const rr_vertical_plan *p);
RR_API const double *rr_vertical_points(const rr_vertical_plan *p);
/* FRFs at speed v (m/s): H[f * npoints + p] floor acceleration (m/s^2) per m
 * of track at the leading wheelset (also after a ride evaluation);
 * Q[f * RR_VDOF + d] every coordinate's (after rr_vertical_frf_execute). */
RR_API int rr_vertical_frf_execute(rr_vertical_plan *p, const rr_vertical_model *m, double v_ms,
                                   rr_error *err);
RR_API const rr_complex *rr_vertical_frf_H(const rr_vertical_plan *p);
RR_API const rr_complex *rr_vertical_frf_Q(const rr_vertical_plan *p);
/* The FRFs, the floor PSDs G[f * npoints + p] ((m/s^2)^2/Hz) for the
 * vertical spectrum sp, and every index of every point into out[npoints]:
 * rr_vertical_plan_set_track, then rr_vertical_ride_design. */
RR_API int rr_vertical_ride_execute(rr_vertical_plan *p, const rr_vertical_model *m, double v_ms,
                                    const rr_spectrum *sp, rr_vertical_point *out, rr_error *err);
/* For many designs at one speed on one track (an optimiser's loop): the
 * track's temporal PSD G_t(f) = S(f/v)/v on the plan's grid, computed once
 * (the plan keeps no pointer to sp), then each design's evaluation. */
RR_API int rr_vertical_plan_set_track(rr_vertical_plan *p, const rr_spectrum *sp, double v_ms,
                                      rr_error *err);
RR_API int rr_vertical_ride_design(rr_vertical_plan *p, const rr_vertical_model *m,
                                   rr_vertical_point *out, rr_error *err);
/* After a ride evaluation: the longitudinal floor acceleration that carbody
 * pitch alone makes at floor height h_p (m; centre of gravity h_c),
 * a_x = (h_p - h_c) theta_c'' - g theta_c (the same at every x), and its
 * 5 s statistics weighted by Wd (a_XP50, a_XP95) and by Wc (the rigid seat
 * back's a_XD95). No longitudinal suspension or traction rods: a bound on
 * what pitch adds, not a longitudinal model. */
RR_API int rr_vertical_pitch_longitudinal(rr_vertical_plan *p, double h_p, double h_c,
                                          rr_window_stats *wd, rr_window_stats *wc, rr_error *err);
RR_API const double *rr_vertical_psd(const rr_vertical_plan *p);
RR_API const double *rr_vertical_track_psd(const rr_vertical_plan *p); /* G_t(f), m^2/Hz */
/* The plan's 5 s statistics of ncols PSD columns G[f * stride + c] on its
 * grid (lateral floor PSDs, say) weighted by w, into out[ncols]. */
RR_API int rr_vertical_window_stats(rr_vertical_plan *p, const double *G, int stride, int ncols,
                                    enum rr_iso_weighting w, rr_window_stats *out, rr_error *err);

/* Validation against a time-domain run (docs/vertical.md, "Validation"): a
 * seeded Gaussian track realisation (random complex line coefficients, each
 * wheelset with its exact delay), the 14-state system discretised exactly
 * for a cubic Hermite hold of the profile, its periodic steady state, and at
 * each floor point: the record's line FRF against the PEM's, the RMS, the
 * Sperling index and 1/3-octave band powers against their expectation on
 * the realisation's lines with the realisation's own spread (z-scores), and
 * the 5 s Wb RMS percentiles of the record against the gamma law's. */
typedef struct rr_vertical_validate_opts {
  double duration_s;              /* one period of the realisation (RR_VALIDATE_DURATION_S) */
  double fs_hz;                   /* (256) */
  int nseg;                       /* Welch segment (4096) */
  uint64_t seed;                  /* (1) */
  rr_track_amplitudes amplitudes; /* (Gaussian) */
  double window_s;                /* (5) */
  int npoints;                    /* 0: +L, 0, -L */
  double x_points[RR_VERTICAL_POINTS_MAX];
} rr_vertical_validate_opts;
RR_API rr_vertical_validate_opts rr_vertical_validate_opts_default(void);
#define RR_VERTICAL_BANDS 17 /* 1/3-octave centres 0.5 .. 20 Hz */
typedef struct rr_vertical_validate_point {
  double x;
  double rms_pem, rms_lines, rms_time, rms_rel_std, rms_z;
  double sperling_pem, sperling_lines, sperling_time, sperling_rel_std, sperling_z;
  double wb_p50_est, wb_p95_est, wb_p50_time, wb_p95_time, wb_p95_z;
  int windows;
  double frf_line_error_max; /* max |H_time - H_pem| / max |H_pem| over the lines */
  double band_fc[RR_VERTICAL_BANDS], band_pem[RR_VERTICAL_BANDS], band_time[RR_VERTICAL_BANDS],
      band_rel_std[RR_VERTICAL_BANDS], band_z[RR_VERTICAL_BANDS];
  double band_welch[RR_VERTICAL_BANDS]; /* the Welch PSD's power in the band */
  double band_z_max;
  double band_error_max, band_welch_error_max; /* max |time / pem - 1|, |welch / pem - 1| */
} rr_vertical_validate_point;
typedef struct rr_vertical_validate_result {
  int npoints, nwelch, navg;
  double *welch_f, *welch_P, *pem_P; /* nwelch; npoints x nwelch (PEM: 0 outside the band) */
  rr_vertical_validate_point points[RR_VERTICAL_POINTS_MAX];
  double seconds_simulated;
} rr_vertical_validate_result;
RR_API int rr_vertical_validate(const rr_vertical_model *m, double v_ms, const rr_spectrum *sp,
                                const rr_vertical_validate_opts *o, rr_vertical_validate_result *r,
                                rr_error *err);
RR_API void rr_vertical_validate_result_free(rr_vertical_validate_result *r);

#ifdef __cplusplus
}
#endif
#endif
