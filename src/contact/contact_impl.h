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

/* A polyline in blocks of `block` segments (block q: vertices q block ..
   (q + 1) block, the last shared with the next block): each block's chord
   z = c + k x through its end vertices, and how far its vertices rise above
   it (up) and fall below it (down). buf: 4 rr_chords_count(n, block). */
typedef struct rr_chords {
  const double *x;
  int n, block, nb;
  double *k, *c, *up, *down;
} rr_chords;
int rr_chords_count(int n, int block);
void rr_chords_build(rr_chords *c, double *buf, const double *x, const double *z, int n, int block);

#endif
