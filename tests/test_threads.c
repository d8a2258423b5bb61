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
  check_cleanup();
  return check_done("threads");
}
