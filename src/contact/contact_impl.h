/* Internal layout of a contact plan (placement.c makes it, search.c uses it). */
#ifndef RR_CONTACT_IMPL_H
#define RR_CONTACT_IMPL_H

#include "railride/contact.h"

#define RR_POLY_MAX_POINTS 1000000 /* a profile's points, at most */
/* A profile's points finite and strictly rising in the lateral coordinate
   (what: the file or the caller, for the message). */
int rr_polyline_check_points(const char *what, const rr_polyline *p, rr_error *err);

struct rr_contact_plan {
  rr_polyline wheel[2], rail[2];  /* right, left; rails after inclination, local frames */
  double *wheel_k[2], *rail_k[2]; /* segment slopes (n - 1 each) */
  rr_contact_setup setup;
  rr_contact_roll roll;
};

/* numpy.interp on a polyline (x == last gives the last value). */
double rr_poly_interp(const double *x, const double *z, int n, double at);
/* The segment slopes of a polyline (n - 1), as numpy.interp computes them. */
void rr_poly_slopes(const double *x, const double *z, int n, double *k);
/* The segment k of x with x[k] <= at < x[k+1], clipped to 0 .. n-2. */
int rr_poly_segment(const double *x, int n, double at);

/* The greatest (max) or least height of a polyline over any vertex range,
   in O(1): a sparse table t of rr_zrange_levels(n) x n doubles. */
typedef struct rr_zrange {
  const double *t;
  int n, levels, max;
} rr_zrange;
int rr_zrange_levels(int n);
void rr_zrange_build(rr_zrange *q, double *t, const double *z, int n, int max);
/* The extreme over vertices a .. b (a <= b, both inside). */
double rr_zrange_query(const rr_zrange *q, int a, int b);

#endif
