/* The nonlinear vehicle's calls at a speed of the caller's (nonlinear.c),
 * for the continuation and the scans (bifurcation.c), which vary the speed
 * as a parameter without rebuilding the vehicle. */
#ifndef RR_NONLINEAR_IMPL_H
#define RR_NONLINEAR_IMPL_H
#include "railride/nonlinear.h"

/* dz = f(z) at speed v (m/s), the track input yt (NULL: straight track). */
void rr_nonlinear_rhs_at(const rr_nonlinear *nl, double v, const double *z, const double *yt,
                         double *dz);
/* J = df/dz there (row-major, size x size). */
void rr_nonlinear_jacobian_at(const rr_nonlinear *nl, double v, const double *z, const double *yt,
                              double *J);
/* df/dz X for the m columns of X (row-major, size x m) into out; with dfdv
   the last column gains df/dv (the contact forces' speed derivative). */
void rr_nonlinear_jvp_at(const rr_nonlinear *nl, double v, const double *z, const double *X, int m,
                         int dfdv, double *out);
/* Where the right-hand side is not smooth (the kinks), one value of g a kink,
   zero there (g may be NULL); returns their count. */
int rr_nonlinear_kinks_at(const rr_nonlinear *nl, double v, const double *z, double *g);
/* The Jacobian at rest with the tabulated contact geometry's slopes taken
   as their first harmonics at amplitude amp (m). */
void rr_nonlinear_jacobian_harmonic_at(const rr_nonlinear *nl, double v, double amp, double *J);
/* 1 when the right-hand side is odd in z (contact laws symmetric). */
int rr_nonlinear_is_odd(const rr_nonlinear *nl);
#endif
