/* railride: frequency-dependent series stiffness of the yaw damper (SDF),
 * docs/model.md section 4. */
#ifndef RAILRIDE_SDF_H
#define RAILRIDE_SDF_H

#include "railride/common.h"
#include "railride/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RR_SDF_TABLE_MAX 256

typedef enum rr_sdf_mode {
  RR_SDF_NONE = 0,    /* constant series stiffness k_ncsx */
  RR_SDF_PAPER = 1,   /* real stiffness k_sdf(f), self-consistent modes */
  RR_SDF_PHYSICAL = 2 /* complex stiffness of a standard linear solid, extra states */
} rr_sdf_mode;

typedef enum rr_sdf_curve_kind {
  RR_CURVE_UNSET = 0,
  RR_CURVE_SLS = 1,  /* K3 + K2 g(f/K1) */
  RR_CURVE_TABLE = 2 /* tabulated f, k' [, k''] */
} rr_sdf_curve_kind;

typedef struct rr_sdf_curve {
  rr_sdf_curve_kind kind;
  double k1_hz; /* K1: frequency scale, Hz */
  double k2;    /* K2: stiffness rise, N/m */
  double k3;    /* K3: static stiffness, N/m */
  int n;        /* table points */
  int has_loss; /* table has a k'' column */
  double f_hz[RR_SDF_TABLE_MAX];
  double k_storage[RR_SDF_TABLE_MAX]; /* N/m */
  double k_loss[RR_SDF_TABLE_MAX];    /* N/m */
} rr_sdf_curve;

/* Paper mode: real series stiffness at frequency f_hz (N/m). */
RR_API double rr_sdf_storage(const rr_sdf_curve *c, double f_hz);
/* Physical mode: complex series stiffness at angular frequency w (rad/s).
 * For SLS: K3 + K2 jw tau / (1 + jw tau); for a table: k'(f) + j k''(f). */
RR_API rr_complex rr_sdf_complex(const rr_sdf_curve *c, double w);
/* Same for a complex Laplace variable s (SLS only; tables return k'(|s|/2pi)). */
RR_API rr_complex rr_sdf_laplace(const rr_sdf_curve *c, rr_complex s);
/* The series stiffness a damper element has under an SDF mode (enum
 * rr_sdf_mode) at the Laplace variable s: paper mode the real storage
 * stiffness at |Im s| / 2 pi, physical mode the complex one. The one rule the
 * model and the damper characteristics share. */
RR_API rr_complex rr_sdf_series_k(const rr_sdf_curve *c, rr_sdf_mode mode, rr_complex s);
/* Smallest and largest storage stiffness of the curve (K3, K3+K2 for SLS). */
RR_API void rr_sdf_range(const rr_sdf_curve *c, double *k_lo, double *k_hi);
/* Reads a CSV table f_hz,k_storage[,k_loss] (N/m); '#' comments and one
 * optional header line allowed. */
RR_API int rr_sdf_table_load(const char *path, rr_sdf_curve *c, rr_error *err);
/* Validates a curve; what names the context for the message. */
RR_API int rr_sdf_curve_check(const rr_sdf_curve *c, const char *what, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
