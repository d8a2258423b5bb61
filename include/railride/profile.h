/* railride: tread profiles for the nonlinear model (docs/model.md,
 * "Nonlinear model"): the equivalent conicity as a function of the
 * wheelset's lateral displacement relative to the track. */
#ifndef RAILRIDE_PROFILE_H
#define RAILRIDE_PROFILE_H

#include "railride/common.h"

#include "railride/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* conicity lambda(a), a = |y_w - y_t| */
#define RR_PROFILE_MAX 64
typedef enum rr_profile_kind {
  RR_PROFILE_NONE = 0, /* not given */
  RR_PROFILE_POLY = 1, /* lambda = sum c_k a^k, a in mm, held beyond hold_mm */
  RR_PROFILE_TABLE = 2 /* (a_mm, lambda) points, linear, held beyond the last */
} rr_profile_kind;

typedef struct rr_profile {
  rr_profile_kind kind;
  char name[64];                                    /* "new", "worn", or the file's name */
  int n;                                            /* coefficients or points */
  double c[RR_PROFILE_MAX];                         /* polynomial coefficients (a in mm) */
  double a_mm[RR_PROFILE_MAX], lam[RR_PROFILE_MAX]; /* table */
  double hold_mm; /* polynomial held at its value beyond (12 mm) */
} rr_profile;

/* Built-in treads (assumptions: the paper gives only lambda(3 mm) = 0.12 new,
 * 0.30 worn, with negative slopes): "new" 0.15 - 0.010 a, "worn" 0.375 -
 * 0.025 a, a in mm, each held beyond 12 mm. */
RR_API int rr_profile_builtin(const char *name, rr_profile *p, rr_error *err);
/* A CSV table a_mm, conicity (increasing a_mm from 0). */
RR_API int rr_profile_load(const char *path, rr_profile *p, rr_error *err);
/* A built-in name or a table file. */
RR_API int rr_profile_open(const char *spec, rr_profile *p, rr_error *err);
/* A polynomial from its coefficients (a in mm). */
RR_API int rr_profile_poly(const double *c, int n, double hold_mm, rr_profile *p, rr_error *err);
/* lambda at lateral displacement a (m, either sign); > 0 across the range is
 * checked when a profile is made. */
RR_API double rr_profile_conicity(const rr_profile *p, double a_m);
RR_API int rr_profile_check(const rr_profile *p, rr_error *err);
/* One line saying what the profile is (the formula or the table); returns
 * snprintf's count. */
RR_API int rr_profile_describe(const rr_profile *p, char *buf, int n);

#ifdef __cplusplus
}
#endif
#endif
