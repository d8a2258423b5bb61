/* A wheel or rail profile from a two-column text file, or a built-in
 * design profile by name when no such file exists (docs/contact.md,
 * profile files). */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "railride/contact.h"
#include "contact/contact_impl.h"
#include "util/internal.h"
#include "util/textfile.h"

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
    } else if (p->n >= RR_POLY_MAX_POINTS)
      st =
          rr_seterr(err, RR_EPARSE, "%s:%d: more than %d points", path, r.line, RR_POLY_MAX_POINTS);
    else if (push(p, &cap, x, z))
      st = rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  if (!st && r.status) st = rr_seterr(err, r.status, "%s", r.err.msg);
  rr_lines_close(&r);
  if (!st) st = rr_polyline_check_points(path, p, err);
  if (st) rr_polyline_free(p);
  return st;
}
