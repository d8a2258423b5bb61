/* Separate contexts in several threads at once: vehicle files with units,
 * design contexts opened, cloned and evaluated (stability and ride
 * objectives, a spectrum file), each thread checking its answers against
 * the single-threaded ones. Run under ThreadSanitizer in CI. Repetitions:
 * RR_THREAD_REPS (default 1000; 100 under TSan). */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <string.h>
#include "railride/railride.h"
#include "check.h"

#define NTHREADS 4
static const char *objs =
    "zeta_low\nindex@350,0.17;rmax=1\nsperling@350,0.17,8.6875;spectrum=tbt3352-alignment\n"
    "index@300,0.3;sdf=paper";
static double expect[4];
static char vehicle_path[512];
static int reps = 1000;

typedef struct job {
  int id, bad;
  char msg[RR_ERROR_MSG_MAX];
} job;

static int one_round(job *j, const double *x)
{
  rr_error e;
  rr_design *d;
  if (rr_design_open(j->id % 2 ? vehicle_path : "type1", "yaw_damper.series_stiffness", objs, &d,
                     &e)) {
    snprintf(j->msg, sizeof j->msg, "open: %s", e.msg);
    return -1;
  }
  rr_design *c;
  double f[4], g[4];
  int st = rr_design_clone(d, &c, &e);
  if (!st) st = rr_design_evaluate(c, x, f, &e);
  if (!st) st = rr_design_evaluate(d, x, g, &e);
  if (st) snprintf(j->msg, sizeof j->msg, "evaluate: %s", e.msg);
  for (int k = 0; k < 4 && !st; k++)
    if (f[k] != expect[k] || g[k] != expect[k]) {
      snprintf(j->msg, sizeof j->msg, "objective %d: %.17g / %.17g, expected %.17g", k, f[k], g[k],
               expect[k]);
      st = -1;
    }
  if (!st) rr_design_free(c);
  rr_design_free(d);
  return st ? -1 : 0;
}

static void *worker(void *arg)
{
  job *j = arg;
  double x[1] = {10e6};
  for (int r = 0; r < reps && !j->bad; r++) j->bad = one_round(j, x) != 0;
  return NULL;
}

/* The vertical model in each thread: its own plan, the vertical ride and
   an N_MV objective (lateral PEM, window kernel, gamma quantiles), against
   the single-threaded answers. */
static const char *vobjs = "n_mv@350,0.17,-8.6875\nwb_p95@300";
static double vexpect[2], vp95[3];

static void *vertical_worker(void *arg)
{
  job *j = arg;
  rr_vehicle v;
  rr_vertical_model m;
  rr_vertical_plan *p = NULL;
  rr_spectrum sp = {0}; /* closing a zeroed or failed spectrum is safe */
  rr_error e;
  rr_vertical_opts o = rr_vertical_opts_default();
  rr_vertical_point pt[3];
  rr_design *d = NULL;
  double x[1] = {10e6}, f[2];
  rr_vehicle_default(&v);
  int st = rr_vertical_model_build(&v, &m, &e);
  if (!st) st = rr_vertical_plan_new(&o, &p, &e);
  if (!st) st = rr_spectrum_open("german-low-vertical", &sp, &e);
  for (int r = 0; r < 20 && !st; r++) {
    st = rr_vertical_ride_execute(p, &m, (250 + 10 * (r % 2)) / RR_KMH, &sp, pt, &e);
    if (!st && r % 2 == 0)
      for (int q = 0; q < 3; q++)
        if (pt[q].wb_5s.p95 != vp95[q])
          st = -1, snprintf(e.msg, sizeof e.msg, "vertical P95 differs");
  }
  if (!st) st = rr_design_open("type1", "yaw_damper.series_stiffness", vobjs, &d, &e);
  if (!st) st = rr_design_evaluate(d, x, f, &e);
  if (!st && (f[0] != vexpect[0] || f[1] != vexpect[1]))
    st = -1, snprintf(e.msg, sizeof e.msg, "vertical objectives differ");
  if (st) {
    j->bad = 1;
    snprintf(j->msg, sizeof j->msg, "%s", e.msg);
  }
  rr_design_free(d);
  rr_vertical_plan_free(p);
  rr_spectrum_close(&sp);
  return NULL;
}

static void vertical_threads(void)
{
  rr_vehicle v;
  rr_vertical_model m;
  rr_vertical_plan *p;
  rr_spectrum sp;
  rr_error e;
  rr_vertical_opts o = rr_vertical_opts_default();
  rr_vertical_point pt[3];
  rr_design *d;
  double x[1] = {10e6};
  rr_vehicle_default(&v);
  CHECK_OK(rr_vertical_model_build(&v, &m, &e), e);
  CHECK_OK(rr_vertical_plan_new(&o, &p, &e), e);
  CHECK_OK(rr_spectrum_open("german-low-vertical", &sp, &e), e);
  CHECK_OK(rr_vertical_ride_execute(p, &m, 250 / RR_KMH, &sp, pt, &e), e);
  for (int q = 0; q < 3; q++) vp95[q] = pt[q].wb_5s.p95;
  rr_vertical_plan_free(p);
  rr_spectrum_close(&sp);
  CHECK_OK(rr_design_open("type1", "yaw_damper.series_stiffness", vobjs, &d, &e), e);
  CHECK_OK(rr_design_evaluate(d, x, vexpect, &e), e);
  rr_design_free(d);
  pthread_t t[NTHREADS];
  job jobs[NTHREADS];
  for (int i = 0; i < NTHREADS; i++) {
    jobs[i] = (job){.id = i};
    pthread_create(&t[i], NULL, vertical_worker, &jobs[i]);
  }
  for (int i = 0; i < NTHREADS; i++) {
    pthread_join(t[i], NULL);
    CHECK(!jobs[i].bad, "vertical thread %d: %s", i, jobs[i].msg);
  }
}

int main(void)
{
  check_spectra_env();
  const char *src = getenv("RR_SOURCE_DIR"), *rp = getenv("RR_THREAD_REPS");
  if (rp) reps = atoi(rp);
  /* a file that equals the built-in type1 through units and a base */
  if (check_tmpdir("thr")) return 1;
  snprintf(
      vehicle_path, sizeof vehicle_path, "%s",
      check_write_file("v.ini",
                       "[vehicle]\nbase = type1\n[carbody]\nmass = 38.936 t\n[primary]\n"
                       "longitudinal_stiffness = 50 kN/mm\n[yaw_damper]\ndamping = 4000 kN.s/m\n"));
  (void)src;
  rr_error e;
  rr_design *d;
  int st = rr_design_open("type1", "yaw_damper.series_stiffness", objs, &d, &e);
  CHECK(st == RR_OK, "open: %s", e.msg);
  if (st) return check_done("threads");
  double x[1] = {10e6};
  CHECK_OK(rr_design_evaluate(d, x, expect, &e), e);
  rr_design_free(d);
  pthread_t t[NTHREADS];
  job jobs[NTHREADS];
  for (int i = 0; i < NTHREADS; i++) {
    jobs[i] = (job){.id = i};
    pthread_create(&t[i], NULL, worker, &jobs[i]);
  }
  for (int i = 0; i < NTHREADS; i++) {
    pthread_join(t[i], NULL);
    CHECK(!jobs[i].bad, "thread %d: %s", i, jobs[i].msg);
  }
  printf("  %d threads x %d rounds of open, clone, evaluate\n", NTHREADS, reps);
  vertical_threads();
  printf("  %d threads: vertical plans and N_MV objectives\n", NTHREADS);
  check_cleanup();
  return check_done("threads");
}
