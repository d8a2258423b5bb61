/* railride: what every public header shares: the complex type of the API
 * (C99 double complex in C, std::complex<double> in C++; the two have the
 * same layout) and the export marker of the shared library's symbols. */
#ifndef RAILRIDE_COMMON_H
#define RAILRIDE_COMMON_H
/* Getters that take an index (rr_model_dof_name(m, i), ...) answer an
   index out of range with the type's "none": NULL for a pointer, -1 for an
   index or an enum, NaN for a quantity. They never read outside the data. */
/* A macro's value as a string literal (help texts quoting the named defaults). */
#define RR_STR_(x) #x
#define RR_STR(x) RR_STR_(x)
/* Speeds: v_kmh = v_ms * RR_KMH. */
#define RR_KMH 3.6
#define RR_PI 3.14159265358979323846

#include <stddef.h>

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

/* Independent jobs a call may hand to the caller, who runs them where it
 * likes (over MPI ranks, say: railride's CLI does). items(arg, lo, hi, out)
 * computes jobs lo .. hi - 1 into out (their results, item_bytes each, from
 * job lo) and returns 0 or a status. fn(ctx, n, item_bytes, items, arg, out)
 * must leave all n results in out (n x item_bytes) and return 0, or a nonzero
 * status of items. The call's numbers do not depend on the runner: the jobs
 * are the same with or without one. fn NULL: the call runs them itself. */
typedef int (*rr_items_fn)(void *arg, long lo, long hi, void *out);
typedef struct rr_runner_opts {
  int (*fn)(void *ctx, long n, size_t item_bytes, rr_items_fn items, void *arg, void *out);
  void *ctx;
} rr_runner_opts;

#endif
