/* Wheel and rail profiles as polylines: read from two-column text files,
 * copied, freed (docs/contact.md, profile files). */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "railride/contact.h"
#include "util/internal.h"
#include "util/textfile.h"

#define POLY_MAX_POINTS 1000000

void rr_polyline_free(rr_polyline *p)
{
  if (!p) return;
  free(p->x);
  free(p->z);
  p->x = p->z = NULL;
  p->n = 0;
}

static int push(rr_polyline *p, int *cap, double x, double z)
{
  if (p->n == *cap) {
    int c = *cap ? 2 * *cap : 256;
    double *a = realloc(p->x, sizeof *a * (size_t)c);
    if (a) p->x = a;
    double *b = a ? realloc(p->z, sizeof *b * (size_t)c) : NULL;
    if (b) p->z = b;
    if (!a || !b) return -1;
    *cap = c;
  }
  p->x[p->n] = x;
  p->z[p->n] = z;
  p->n++;
  return 0;
}

/* Two numbers separated by blanks, a tab, a comma or a semicolon, nothing
   after: 1; something else: 0. */
static int two_numbers(const char *s, double *a, double *b)
{
  char *e;
  errno = 0;
  *a = strtod(s, &e);
  if (e == s || errno == ERANGE) return 0;
  s = e;
  while (isspace((unsigned char)*s)) s++;
  if (*s == ',' || *s == ';') s++;
  *b = strtod(s, &e);
  if (e == s || errno == ERANGE) return 0;
  while (isspace((unsigned char)*e)) e++;
  return !*e && isfinite(*a) && isfinite(*b);
}

static int check_points(const char *what, const rr_polyline *p, rr_error *err)
{
  if (p->n < 3) return rr_seterr(err, RR_EPARSE, "%s: a profile needs at least 3 points", what);
  for (int i = 0; i < p->n; i++)
    if (!isfinite(p->x[i]) || !isfinite(p->z[i]))
      return rr_seterr(err, RR_EINVAL, "%s: point %d is not finite", what, i + 1);
  for (int i = 1; i < p->n; i++)
    if (!(p->x[i] > p->x[i - 1]))
      return rr_seterr(err, RR_EINVAL, "%s: point %d: the lateral coordinate must rise strictly",
                       what, i + 1);
  return RR_OK;
}

int rr_polyline_load(const char *path, rr_polyline *p, rr_error *err)
{
  rr_lines r;
  *p = (rr_polyline){0};
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  if (rr_polyline_is_builtin(base) && access(path, F_OK) != 0) /* no such file: the built-in */
    return rr_polyline_builtin(base, p, err);
  int st = rr_lines_open(&r, path, RR_CSV_LINE_MAX, err), got, cap = 0;
  if (st) return st;
  const char *line;
  while (!st && (got = rr_lines_next(&r, &line)) > 0) {
    double x, z;
    if (!line[strspn(line, " \t\r")]) continue; /* blank or a comment */
    if (!two_numbers(line, &x, &z)) {
      if (p->n == 0) continue; /* a header: before the first row */
      st = rr_seterr(err, RR_EPARSE, "%s:%d: two numbers expected (lateral vertical, mm)", path,
                     r.line);
    } else if (p->n >= POLY_MAX_POINTS)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: more than %d points", path, r.line, POLY_MAX_POINTS);
    else if (push(p, &cap, x, z))
      st = rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  if (!st && r.status) st = rr_seterr(err, r.status, "%s", r.err.msg);
  rr_lines_close(&r);
  if (!st) st = check_points(path, p, err);
  if (st) rr_polyline_free(p);
  return st;
}

int rr_polyline_from(const double *x, const double *z, int n, rr_polyline *p, rr_error *err)
{
  *p = (rr_polyline){0};
  if (n < 0 || n > POLY_MAX_POINTS) return rr_seterr(err, RR_EINVAL, "profile: %d points", n);
  p->x = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  p->z = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  if (!p->x || !p->z) {
    rr_polyline_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  memcpy(p->x, x, sizeof(double) * (size_t)n);
  memcpy(p->z, z, sizeof(double) * (size_t)n);
  p->n = n;
  int st = check_points("profile", p, err);
  if (st) rr_polyline_free(p);
  return st;
}
