/* railride: track irregularity spectra (spectra/README.md for the file format).
 * Every spectrum evaluates to one canonical form: one-sided, spatial frequency
 * n in cycles/m, PSD in m^2/(cycle/m) (rad^2/(cycle/m) for cross level). */
#ifndef RAILRIDE_SPECTRUM_H
#define RAILRIDE_SPECTRUM_H

#include "railride/common.h"

#include "railride/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RR_SPECTRUM_MAX_TERMS 64
/* The most rows a table (a measured PSD) may hold. */
#define RR_SPECTRUM_MAX_POINTS 1000000
#define RR_SPECTRUM_PATH_MAX 512

typedef enum rr_spectrum_form {
  RR_FORM_POWERLAW = 0,  /* S = A / n^k per segment */
  RR_FORM_GERMAN = 1,    /* German high-speed rational forms */
  RR_FORM_FRA = 2,       /* FRA classes: k A Oc^2 / (W^2 (W^2 + Oc^2)) */
  RR_FORM_RATIONAL7 = 3, /* A (n^2 + B n + C) / (n^4 + D n^3 + E n^2 + F n + G) */
  RR_FORM_TABLE = 4      /* (n, S) pairs, log-log interpolation */
} rr_spectrum_form;

typedef enum rr_german_shape {
  RR_GERMAN_ALIGNMENT,
  RR_GERMAN_VERTICAL,
  RR_GERMAN_CROSSLEVEL,
  RR_GERMAN_GAUGE
} rr_german_shape;

typedef struct rr_spectrum {
  char name[64];
  char title[160];
  char path[RR_SPECTRUM_PATH_MAX]; /* the file it was read from */
  char direction[16];              /* lateral, vertical, crosslevel, gauge */
  rr_spectrum_form form;
  int rad_per_m;             /* formula variable is Omega in rad/m (else n in cycles/m) */
  double scale;              /* file PSD unit -> m^2 (or rad^2), times 2 when two-sided */
  double valid_lo, valid_hi; /* validity, cycles/m */
  int clip;                  /* 1: zero outside the validity range; 0: extend the formula */
  /* parameters */
  int nseg;
  double seg_lo[RR_SPECTRUM_MAX_TERMS], seg_hi[RR_SPECTRUM_MAX_TERMS], seg_A[RR_SPECTRUM_MAX_TERMS],
      seg_k[RR_SPECTRUM_MAX_TERMS];
  rr_german_shape shape;
  double A, Oc, Or, Os, b, k;
  double p[7]; /* rational7 A..G */
  int npts, tab_cap;
  double *tab_n, *tab_S; /* a table's rows: heap, owned (rr_spectrum_close) */
} rr_spectrum;

/* Loads a spectrum file; a path ending in .csv is a measured PSD: two
 * columns, a header naming their units (n_per_m or n_cycles_per_m or
 * omega_rad_per_m; psd_m2_per_per_m, psd_mm2_per_cycle_per_m,
 * psd_mm2_per_rad_per_m, ...), one-sided, up to RR_SPECTRUM_MAX_POINTS rows
 * of increasing frequency and positive PSD, log-log interpolated and
 * extended by the end slopes; its direction is lateral alignment. A spectrum
 * holding a table owns memory: rr_spectrum_close frees it (safe on any
 * loaded or failed spectrum). */
RR_API int rr_spectrum_load(const char *path, rr_spectrum *sp, rr_error *err);
/* Loads by name from the spectra directory (env RAILRIDE_SPECTRA_DIR, then the
 * built-in directory) or, when spec contains '/' or ends in .txt or .csv, by
 * path (as given, relative to the current directory). */
RR_API int rr_spectrum_open(const char *spec, rr_spectrum *sp, rr_error *err);
RR_API void rr_spectrum_close(rr_spectrum *sp);
/* A deep copy of src into dst (dst closed after use). */
RR_API int rr_spectrum_copy(const rr_spectrum *src, rr_spectrum *dst, rr_error *err);
/* RR_OK when sp's direction is direction ("lateral": alignment), else
 * RR_EINVAL with a message naming the file, its direction and use. */
RR_API int rr_spectrum_require(const rr_spectrum *sp, const char *direction, const char *use,
                               rr_error *err);
/* Directory searched for spectrum names. */
RR_API const char *rr_spectrum_dir(void);
/* For bindings: a spectrum opened (as rr_spectrum_open) on the heap into *out
 * (free with rr_spectrum_delete). */
RR_API int rr_spectrum_new(const char *spec, rr_spectrum **out, rr_error *err);
RR_API void rr_spectrum_delete(rr_spectrum *sp);
/* One-sided PSD at n cycles/m, in m^2/(cycle/m) (0 outside the validity
 * range when clip is set). */
RR_API double rr_spectrum_eval(const rr_spectrum *sp, double n);
/* RMS (m) over [n1, n2] cycles/m by composite Simpson in log n. */
RR_API double rr_spectrum_rms(const rr_spectrum *sp, double n1, double n2);

#ifdef __cplusplus
}
#endif
#endif
