/* Minimal test harness: every check counts; main returns failures != 0. */
#ifndef RR_CHECK_H
#define RR_CHECK_H
#include <math.h>
#include <stdio.h>
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static int check_pass, check_fail;

#define CHECK(cond, ...) do { \
    if (cond) check_pass++; \
    else { check_fail++; fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__); fprintf(stderr, __VA_ARGS__); fputc('\n', stderr); } \
  } while (0)

/* |a - b| <= atol + rtol |b| */
#define CHECK_CLOSE(a, b, rtol, atol, what) do { \
    double a_ = (a), b_ = (b); \
    CHECK(fabs(a_ - b_) <= (atol) + (rtol) * fabs(b_), "%s: got %.15g, expected %.15g (diff %.3g)", what, a_, b_, a_ - b_); \
  } while (0)

#define CHECK_OK(st, err) CHECK((st) == 0, "status %d: %s", (st), (err).msg)

static int check_done(const char *name)
{
  printf("%s: %d passed, %d failed\n", name, check_pass, check_fail);
  return check_fail != 0;
}
#endif
