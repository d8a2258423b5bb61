/* The calls the headers call allocation-free make no heap allocation once
 * warmed up: malloc and its kin are replaced in this program (glibc lets a
 * program define them; every library's calls then come here), counting while
 * a call runs. And the open and plan calls fail cleanly: each of their
 * allocations made to fail in turn, the call returns RR_ENOMEM and frees
 * what it had taken. Under a sanitizer, which replaces them itself, it is
 * skipped. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RR_NO_COUNT 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define RR_NO_COUNT 1
#endif
#endif

#ifndef RR_NO_COUNT
extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void *__libc_memalign(size_t, size_t);
extern void __libc_free(void *);

static volatile int counting; /* volatile: the compiler takes malloc for the builtin */
static volatile long nalloc, nfree, fail_at; /* fail_at > 0: that allocation returns NULL */

/* A breakpoint for finding an allocation: gdb -ex 'break alloc_seen'. */
__attribute__((noinline)) static void alloc_seen(void) { __asm__ volatile(""); }

/* OpenBLAS 0.3.21's small-matrix dgemm kernels for AVX-512 (SkylakeX) malloc
   a packing buffer on every call, whatever the caller does; those are
   OpenBLAS's, not railride's, and are not counted. */
static int from_openblas(void *caller)
{
  Dl_info info;
  return dladdr(caller, &info) && info.dli_fname && strstr(info.dli_fname, "openblas");
}
#define COUNT()                                                                                    \
  do {                                                                                             \
    if (counting && !from_openblas(__builtin_return_address(0))) {                                 \
      nalloc++;                                                                                    \
      alloc_seen();                                                                                \
      if (nalloc == fail_at) {                                                                     \
        errno = ENOMEM;                                                                            \
        return NULL;                                                                               \
      }                                                                                            \
    }                                                                                              \
  } while (0)

void free(void *p)
{
  if (counting && p) nfree++;
  __libc_free(p);
}

void *malloc(size_t n)
{
  COUNT();
  return __libc_malloc(n);
}

void *calloc(size_t a, size_t b)
{
  COUNT();
  return __libc_calloc(a, b);
}

void *realloc(void *p, size_t n)
{
  COUNT();
  void *q = __libc_realloc(p, n);
  if (counting && p && q) nfree++; /* the old block is released: one taken, one given back */
  return q;
}

void *aligned_alloc(size_t al, size_t n)
{
  COUNT();
  return __libc_memalign(al, n);
}

void *memalign(size_t al, size_t n)
{
  COUNT();
  return __libc_memalign(al, n);
}

int posix_memalign(void **p, size_t al, size_t n)
{
  if (counting && !from_openblas(__builtin_return_address(0))) {
    nalloc++;
    if (nalloc == fail_at) return ENOMEM;
  }
  *p = __libc_memalign(al, n);
  return *p ? 0 : ENOMEM;
}

/* Allocations made by the statement, after one warm-up run of it. */
#define ALLOCS(stmt, out)                                                                          \
  do {                                                                                             \
    stmt;                                                                                          \
    nalloc = 0;                                                                                    \
    counting = 1;                                                                                  \
    stmt;                                                                                          \
    counting = 0;                                                                                  \
    (out) = nalloc;                                                                                \
  } while (0)

static void frf_and_comfort(rr_sdf_mode sdf)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  v.sdf_mode = sdf;
  rr_model *m;
  rr_error e;
  rr_spectrum sp;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_spectrum_open("wuhan-guangzhou", &sp, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[3 * 17], rows0[3 * 17];
  CHECK_OK(rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, 1, rows, rows0, &e), e);
  rr_frf_opts o = rr_frf_opts_default();
  o.npoints = 3;
  o.rows = rows;
  o.rows0 = rows0;
  rr_frf_plan *p;
  rr_comfort_plan *cp;
  CHECK_OK(rr_frf_plan_new(m, &o, &p, &e), e);
  CHECK_OK(rr_comfort_plan_new(rr_frf_freqs(p), rr_frf_nfreq(p), RR_AXIS_LATERAL, &cp, &e), e);
  double G[3 * RR_FRF_NFREQ_DEFAULT];
  rr_comfort c;
  long n;
  int st = 0;
  ALLOCS(st |= rr_model_set_operating(m, 300 / RR_KMH, 0.2, &e), n);
  CHECK(n == 0 && !st, "set_operating: %ld allocations", n);
  ALLOCS(st |= rr_frf_plan_execute(p, m, &e), n);
  CHECK(n == 0 && !st, "frf_plan_execute (sdf %d): %ld allocations", sdf, n);
  ALLOCS(st |= rr_pem_psd(p, m, &sp, G, &e), n);
  CHECK(n == 0 && !st, "pem_psd: %ld allocations", n);
  ALLOCS(st |= rr_comfort_execute(cp, G, 3, &c, &e), n);
  CHECK(n == 0 && !st && isfinite(c.sperling), "comfort_execute: %ld allocations", n);
  rr_ride_opts ro = rr_ride_opts_default(); /* the library's ride plan: the same stages */
  ro.roll_gravity = 1;
  rr_ride_plan *rp;
  rr_ride_point pt[3];
  CHECK_OK(rr_ride_plan_new(m, &v, &ro, &rp, &e), e);
  ALLOCS(st |= rr_ride_execute(rp, m, &sp, pt, &e), n);
  CHECK(n == 0 && !st && isfinite(pt[2].sperling), "ride_execute (sdf %d): %ld allocations", sdf,
        n);
  ALLOCS(st |= rr_ride_design(rp, m, pt, &e), n); /* the track the execute set */
  CHECK(n == 0 && !st && isfinite(pt[2].sperling), "ride_design (sdf %d): %ld allocations", sdf, n);
  rr_ride_plan_free(rp);
  rr_frf_plan_free(p);
  rr_comfort_plan_free(cp);
  rr_spectrum_close(&sp);
  rr_model_free(m);
}

static void stability(const char *vehicle)
{
  rr_vehicle v;
  rr_error e;
  CHECK_OK(rr_vehicle_open(vehicle, &v, &e), e);
  rr_model *m;
  rr_modal_ws *ws;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  rr_stability s[4];
  double sp[4] = {250 / RR_KMH, 300 / RR_KMH, 350 / RR_KMH, 400 / RR_KMH},
         lam[4] = {0.05, 0.1, 0.2, 0.4};
  long n;
  int st = 0;
  ALLOCS(st |= rr_modal_stability(m, NULL, ws, &s[0], &e), n);
  CHECK(n == 0 && !st, "modal_stability (%s): %ld allocations", vehicle, n);
  ALLOCS(st |= rr_modal_stability_batch(m, NULL, ws, 4, sp, lam, s, &e), n);
  CHECK(n == 0 && !st, "modal_stability_batch (%s): %ld allocations", vehicle, n);
  /* two designs' points in the same lanes */
  rr_model *two[4] = {m, NULL, m, NULL};
  CHECK_OK(rr_model_clone(m, &two[1], &e), e);
  two[3] = two[1];
  rr_robust rb[2];
  ALLOCS(st |= rr_modal_stability_many(two, NULL, ws, 4, sp, lam, s, &e), n);
  CHECK(n == 0 && !st, "modal_stability_many (%s): %ld allocations", vehicle, n);
  ALLOCS(st |= rr_robust_indices_many(two, 2, NULL, NULL, ws, rb, &e), n);
  CHECK(n == 0 && !st, "robust_indices_many (%s): %ld allocations", vehicle, n);
  rr_model_free(two[1]);
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

static void design(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_error e;
  const char *keys[2] = {"yaw_damper.damping", "primary.longitudinal_stiffness"};
  const char *objs[5] = {"zeta_low", "zeta_high", "std_zeta", "index@350,0.17;fmax=20",
                         "sperling@350,0.17"};
  rr_design *d;
  CHECK_OK(rr_design_new(&v, 2, keys, 5, objs, &d, &e), e);
  double x[2] = {4e5, 2e7}, f[5];
  long n;
  int st = 0;
  ALLOCS(st |= rr_design_evaluate(d, x, f, &e), n);
  CHECK(n == 0 && !st, "design_evaluate: %ld allocations", n);
  x[0] = 6e5;
  ALLOCS(st |= rr_design_evaluate(d, x, f, &e), n);
  CHECK(n == 0 && !st, "design_evaluate at another design: %ld allocations", n);
  rr_design_free(d);
}

static void nonlinear(void)
{
  rr_vehicle v;
  rr_profile p;
  rr_error e;
  CHECK_OK(rr_vehicle_open("type1", &v, &e), e);
  CHECK_OK(rr_profile_open("worn", &p, &e), e);
  rr_nonlinear *nl;
  CHECK_OK(rr_nonlinear_from_vehicle(&v, &p, NULL, 350 / RR_KMH, &nl, &e), e);
  int N = rr_nonlinear_size(nl);
  double z[128] = {0}, dz[128], yt[8] = {1e-3, 0, 0, 0};
  z[rr_nonlinear_index_y(nl, 0)] = 5e-3;
  long n;
  CHECK(N <= 128, "state size %d", N);
  ALLOCS(rr_nonlinear_rhs(nl, z, yt, dz), n);
  CHECK(n == 0, "nonlinear_rhs: %ld allocations", n);
  rr_nonlinear_free(nl);
}

static void vertical(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_vertical_model m;
  rr_vertical_plan *p;
  rr_spectrum sp;
  rr_error e;
  rr_vertical_opts o = rr_vertical_opts_default();
  CHECK_OK(rr_vertical_model_build(&v, &m, &e), e);
  CHECK_OK(rr_vertical_plan_new(&o, &p, &e), e);
  CHECK_OK(rr_spectrum_open("tbt3352-vertical", &sp, &e), e);
  rr_vertical_point pt[3];
  rr_window_stats ax, axc;
  long n;
  int st = 0;
  ALLOCS(st |= rr_vertical_ride_execute(p, &m, 350 / RR_KMH, &sp, pt, &e), n);
  CHECK(n == 0 && !st, "vertical_ride_execute: %ld allocations", n);
  ALLOCS(st |= rr_vertical_ride_design(p, &m, pt, &e), n);
  CHECK(n == 0 && !st, "vertical_ride_design: %ld allocations", n);
  ALLOCS(st |= rr_vertical_frf_execute(p, &m, 300 / RR_KMH, &e), n);
  CHECK(n == 0 && !st, "vertical_frf_execute: %ld allocations", n);
  ALLOCS(st |= rr_vertical_pitch_longitudinal(p, 1.2, 1.62, &ax, &axc, &e), n);
  CHECK(n == 0 && !st, "vertical_pitch_longitudinal: %ld allocations", n);
  rr_vertical_plan_free(p);
  rr_spectrum_close(&sp);
}

/* Each allocation of call failing in turn: RR_ENOMEM, no leak (the frees
   while counting match the allocations that succeeded), until the call has
   all it needs; cleanup(obj) frees a success. */
#define FAILS(name, call, cleanup)                                                                 \
  do {                                                                                             \
    long k = 1, leaks = 0, wrong = 0;                                                              \
    for (;; k++) {                                                                                 \
      nalloc = nfree = 0;                                                                          \
      fail_at = k;                                                                                 \
      counting = 1;                                                                                \
      int st_ = (call);                                                                            \
      counting = 0;                                                                                \
      long ok_allocs = nalloc >= k ? nalloc - 1 : nalloc, freed = nfree;                           \
      fail_at = 0;                                                                                 \
      if (nalloc < k) { /* every allocation succeeded: done */                                     \
        CHECK(st_ == RR_OK, "%s: status %d with every allocation granted", name, st_);             \
        cleanup;                                                                                   \
        break;                                                                                     \
      }                                                                                            \
      wrong += st_ != RR_ENOMEM;                                                                   \
      leaks += ok_allocs != freed;                                                                 \
      if (st_ == RR_OK) cleanup;                                                                   \
    }                                                                                              \
    CHECK(k > 1 && !wrong && !leaks, "%s: %ld allocations tried; %ld not RR_ENOMEM, %ld leaked",   \
          name, k - 1, wrong, leaks);                                                              \
  } while (0)

static void failures(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_error e;
  rr_vertical_plan *vp = NULL;
  rr_vertical_opts vo = rr_vertical_opts_default();
  vo.nfreq = 60;
  FAILS("vertical_plan_new", rr_vertical_plan_new(&vo, &vp, &e), rr_vertical_plan_free(vp));
  double f[50];
  for (int i = 0; i < 50; i++) f[i] = 0.5 + 0.1 * i;
  rr_window_plan *wp = NULL;
  FAILS("window_plan_new", rr_window_plan_new(f, 50, 5, 3, &wp, &e), rr_window_plan_free(wp));
  rr_comfort_plan *cp = NULL;
  FAILS("comfort_plan_new", rr_comfort_plan_new(f, 50, RR_AXIS_VERTICAL, &cp, &e),
        rr_comfort_plan_free(cp));
  rr_model *m = NULL;
  FAILS("model_from_vehicle", rr_model_from_vehicle(&v, &m, &e), rr_model_free(m));
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  double xs[1] = {0}, rows[17];
  CHECK_OK(rr_vehicle_floor_rows(m, &v, xs, 1, 1.2, 0, rows, NULL, &e), e);
  rr_frf_opts fo = rr_frf_opts_default();
  fo.npoints = 1;
  fo.rows = rows;
  fo.nfreq = 40;
  rr_frf_plan *fp = NULL;
  FAILS("frf_plan_new", rr_frf_plan_new(m, &fo, &fp, &e), rr_frf_plan_free(fp));
  rr_ride_opts ro = rr_ride_opts_default();
  ro.nfreq = 40;
  ro.roll_gravity = 1;
  rr_ride_plan *rp = NULL;
  FAILS("ride_plan_new", rr_ride_plan_new(m, &v, &ro, &rp, &e), rr_ride_plan_free(rp));
  rr_modal_ws *ws = NULL;
  FAILS("modal_ws_new", rr_modal_ws_new(m, &ws, &e), rr_modal_ws_free(ws));
  rr_model_free(m);
  /* not rr_spectrum_open: udunits2's unit scanner exits the process when an
     allocation fails (ut_scan_bytes), a dependency's behaviour */
  /* a design context cloned (each thread's), its ride objective on a measured
     PSD, so that the clone copies the spectrum's table too */
  if (check_tmpdir("alloc") == 0) {
    const char *csv = check_write_file("track.csv", "n_per_m,psd_m2_per_cycle_per_m\n"
                                                    "0.001,1e-3\n0.01,1e-5\n0.1,1e-7\n1,1e-9\n");
    char obj[700];
    snprintf(obj, sizeof obj, "sperling@350,0.17;spectrum=%s", csv);
    const char *keys[1] = {"yaw_damper.damping"}, *objs[1] = {obj};
    rr_design *d = NULL, *c = NULL;
    CHECK_OK(rr_design_new(&v, 1, keys, 1, objs, &d, &e), e);
    if (d) FAILS("design_clone", rr_design_clone(d, &c, &e), rr_design_free(c));
    rr_design_free(d);
    check_cleanup();
  }
}
#endif

int main(void)
{
  check_spectra_env();
#ifdef RR_NO_COUNT
  printf("alloc: skipped under a sanitizer (it replaces malloc itself)\n");
  return check_done("alloc");
#else
  long n; /* the counter counts: a call that allocates is seen */
  void *volatile q = NULL;
  ALLOCS(free(q); q = malloc(16), n);
  free(q);
  CHECK(n == 1, "the counter: %ld allocations for one malloc", n);
  frf_and_comfort(RR_SDF_NONE);
  frf_and_comfort(RR_SDF_PAPER);
  stability("type1");
  stability("type2");
  stability("../examples/type1-sdf-paper.ini");
  design();
  nonlinear();
  vertical();
  failures();
  return check_done("alloc");
#endif
}
