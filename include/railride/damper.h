/* railride: Maxwell damper characteristics (paper eq. 3-8, Fig. 2). */
#ifndef RAILRIDE_DAMPER_H
#define RAILRIDE_DAMPER_H

#include "railride/common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rr_damper_point {
  double freq_hz;
  double storage;     /* Re k_e: equivalent stiffness (N/m) */
  double loss;        /* Im k_e (N/m) */
  double eq_damping;  /* Im k_e / w: equivalent damping (N s/m) */
  double dissipation; /* loss / storage = k / (c w) */
} rr_damper_point;

/* Dynamic stiffness of damper c in series with complex spring k at jw. */
RR_API rr_complex rr_maxwell_stiffness(rr_complex k, double c, rr_complex s);
/* Characteristics at frequency f_hz for series spring k (N/m) and damper c (N s/m). */
RR_API rr_damper_point rr_maxwell_point(double k, double c, double f_hz);
/* Frequency of maximum loss (optimal dissipation): w = k / c. */
RR_API double rr_maxwell_omega_opt(double k, double c);

#ifdef __cplusplus
}
#endif
#endif
