/* Minimal test harness: every check counts; main returns failures != 0. */
#ifndef RR_CHECK_H
#define RR_CHECK_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static int check_pass, check_fail;

#define CHECK(cond, ...)                                                                           \
  do {                                                                                             \
    if (cond)                                                                                      \
      check_pass++;                                                                                \
    else {                                                                                         \
      check_fail++;                                                                                \
      fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);                                         \
      fprintf(stderr, __VA_ARGS__);                                                                \
      fputc('\n', stderr);                                                                         \
    }                                                                                              \
  } while (0)

/* |a - b| <= atol + rtol |b| */
#define CHECK_CLOSE(a, b, rtol, atol, what)                                                        \
  do {                                                                                             \
    double a_ = (a), b_ = (b);                                                                     \
    CHECK(fabs(a_ - b_) <= (atol) + (rtol)*fabs(b_), "%s: got %.15g, expected %.15g (diff %.3g)",  \
          what, a_, b_, a_ - b_);                                                                  \
  } while (0)

#define CHECK_OK(st, err) CHECK((st) == 0, "status %d: %s", (st), (err).msg)

/* A scratch directory, files written into it, and the spectra of the tree. */
static char check_dir[256];

static inline int check_tmpdir(const char *tag)
{
  snprintf(check_dir, sizeof check_dir, "/tmp/rr_test_%s_XXXXXX", tag);
  return mkdtemp(check_dir) ? 0 : -1;
}

static inline const char *check_write_file(const char *name, const char *text)
{
  static char path[512];
  snprintf(path, sizeof path, "%s/%s", check_dir, name);
  FILE *fp = fopen(path, "w");
  if (fp) {
    fputs(text, fp);
    fclose(fp);
  }
  return path;
}

static inline void check_cleanup(void)
{
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf %s", check_dir);
  if (check_dir[0] && system(cmd)) {
  }
}

static inline void check_spectra_env(void)
{
  const char *src = getenv("RR_SOURCE_DIR");
  char sd[512];
  snprintf(sd, sizeof sd, "%s/spectra", src ? src : "..");
  setenv("RAILRIDE_SPECTRA_DIR", sd, 1);
}

static int check_done(const char *name)
{
  printf("%s: %d passed, %d failed\n", name, check_pass, check_fail);
  return check_fail != 0;
}
#endif
