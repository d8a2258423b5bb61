/* railride: what every public header shares: the complex type of the API
 * (C99 double complex in C, std::complex<double> in C++; the two have the
 * same layout) and the export marker of the shared library's symbols. */
#ifndef RAILRIDE_COMMON_H
#define RAILRIDE_COMMON_H

#ifdef __cplusplus
#include <complex>
typedef std::complex<double> rr_complex;
#else
#include <complex.h>
typedef double complex rr_complex;
#endif

/* Only what the public headers declare is exported from librailride. */
#if defined(RAILRIDE_BUILD) && defined(__GNUC__)
#define RR_API __attribute__((visibility("default")))
#else
#define RR_API
#endif

/* Progress of a long call: fn(user, done, total) after each step; a nonzero
 * return stops the call, which then returns RR_ESTOPPED with the steps it
 * finished in place (each function says what that leaves). fn NULL: none. */
typedef int (*rr_progress_fn)(void *user, long done, long total);
typedef struct rr_progress {
  rr_progress_fn fn;
  void *user;
} rr_progress;

#endif
