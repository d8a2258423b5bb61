/* Conicity as a function of lateral displacement (see nonlinear.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "vehicle/profile_impl.h"
#include "railride/vehicle.h"
#include "util/internal.h"
#include "util/textfile.h"

#define HOLD_MM_DEFAULT 12.0
#define A_CHECK_MM 30.0 /* lambda must stay positive out to here */

int rr_profile_poly(const double *c, int n, double hold_mm, rr_profile *p, rr_error *err)
{
  if (n < 1 || n > RR_PROFILE_MAX)
    return rr_seterr(err, RR_EINVAL, "conicity_poly: 1 to %d coefficients", RR_PROFILE_MAX);
  *p = (rr_profile){
      .kind = RR_PROFILE_POLY, .n = n, .hold_mm = hold_mm > 0 ? hold_mm : HOLD_MM_DEFAULT};
  snprintf(p->name, sizeof p->name, "polynomial");
  memcpy(p->c, c, sizeof(double) * (size_t)n);
  return rr_profile_check(p, err);
}

int rr_profile_builtin(const char *name, rr_profile *p, rr_error *err)
{
  double c[2];
  if (!strcmp(name, "new")) {
    c[0] = 0.15;
    c[1] = -0.010;
  } else if (!strcmp(name, "worn")) {
    c[0] = 0.375;
    c[1] = -0.025;
  } else
    return rr_seterr(err, RR_EINVAL, "unknown tread profile '%s' (new, worn, or a table file)",
                     name);
  int st = rr_profile_poly(c, 2, HOLD_MM_DEFAULT, p, err);
  if (!st) snprintf(p->name, sizeof p->name, "%s", name);
  return st;
}

/* The header's names and units (optional; without one: mm and conicity). */
static const rr_csv_name tread_a[] = {{"a_mm", 1}, {"amplitude_mm", 1}, {"a_m", 1e3}, {NULL, 0}};
static const rr_csv_name tread_l[] = {
    {"conicity", 1}, {"lambda", 1}, {"tan_gamma_e", 1}, {NULL, 0}};

int rr_profile_load(const char *path, rr_profile *p, rr_error *err)
{
  const rr_csv_name *const cols[2] = {tread_a, tread_l};
  double sc[2] = {1, 1};
  int head = 0;
  rr_lines r;
  int st = rr_lines_open(&r, path, RR_CSV_LINE_MAX, err), got;
  if (st) return st;
  *p = (rr_profile){.kind = RR_PROFILE_TABLE};
  const char *base = strrchr(path, '/');
  snprintf(p->name, sizeof p->name, "%s", base ? base + 1 : path);
  const char *line;
  while (!st && (got = rr_lines_next(&r, &line)) > 0) {
    double a, l;
    int row = rr_csv_pair(line, p->n, &a, &l);
    if (row == 0 && p->n == 0 && !head && line[strspn(line, " \t")]) { /* the header */
      head = 1;
      st = rr_csv_header(path, r.line, line, cols, 2, 2, sc, NULL, err);
      continue;
    }
    if (row == 0) continue;
    a *= sc[0];
    l *= sc[1];
    if (row < 0)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: expected two numbers a_mm, conicity", path, r.line);
    else if (p->n >= RR_PROFILE_MAX)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: more than %d rows", path, r.line, RR_PROFILE_MAX);
    else if (!(isfinite(a) && isfinite(l) && a >= 0 && a <= 100 &&
               (p->n == 0 || a > p->a_mm[p->n - 1])))
      st = rr_seterr(err, RR_EPARSE, "%s:%d: a_mm must rise from 0, within 0 .. 100 mm", path,
                     r.line);
    else if (!(l > 0 && l <= RR_CONICITY_MAX))
      st = rr_seterr(err, RR_EPARSE, "%s:%d: conicity %g outside (0, %g]", path, r.line, l,
                     RR_CONICITY_MAX);
    else {
      p->a_mm[p->n] = a;
      p->lam[p->n] = l;
      p->n++;
    }
  }
  if (!st && r.status) st = rr_seterr(err, r.status, "%s", r.err.msg);
  rr_lines_close(&r);
  if (!st && p->n < 1) st = rr_seterr(err, RR_EPARSE, "%s: no rows", path);
  if (!st && p->a_mm[0] != 0)
    st = rr_seterr(err, RR_EPARSE, "%s: the table must start at a_mm = 0", path);
  return st ? st : rr_profile_check(p, err);
}

int rr_profile_open(const char *spec, rr_profile *p, rr_error *err)
{
  if (!strcmp(spec, "new") || !strcmp(spec, "worn")) return rr_profile_builtin(spec, p, err);
  return rr_profile_load(spec, p, err);
}

/* lambda and its slope in a (per mm), a >= 0 in mm. */
static double conicity_mm(const rr_profile *p, double a, double *slope)
{
  *slope = 0;
  if (p->kind == RR_PROFILE_POLY) {
    int held = a > p->hold_mm;
    if (held) a = p->hold_mm;
    double v = 0, d = 0;
    for (int k = p->n - 1; k >= 0; k--) {
      d = d * a + v;
      v = v * a + p->c[k];
    }
    if (!held) *slope = d;
    return v;
  }
  if (p->kind == RR_PROFILE_TABLE) {
    if (p->n == 1 || a >= p->a_mm[p->n - 1]) return p->lam[p->n - 1];
    int i = 0;
    while (a > p->a_mm[i + 1]) i++;
    double s = (p->lam[i + 1] - p->lam[i]) / (p->a_mm[i + 1] - p->a_mm[i]);
    *slope = s;
    return p->lam[i] + s * (a - p->a_mm[i]);
  }
  return NAN;
}

double rr_profile_conicity(const rr_profile *p, double a_m)
{
  double s;
  return conicity_mm(p, fabs(a_m) * 1e3, &s);
}

/* lambda(a) and d lambda / da (per m), for the contact law. */
double rr_profile_eval(const rr_profile *p, double a_m, double *dlam_da)
{
  double s, v = conicity_mm(p, fabs(a_m) * 1e3, &s);
  *dlam_da = s * 1e3;
  return v;
}

int rr_profile_check(const rr_profile *p, rr_error *err)
{
  if (p->kind != RR_PROFILE_POLY && p->kind != RR_PROFILE_TABLE)
    return rr_seterr(err, RR_EINVAL, "no tread profile given");
  for (int i = 0; i < p->n; i++)
    if (!isfinite(p->kind == RR_PROFILE_POLY ? p->c[i] : p->lam[i]))
      return rr_seterr(err, RR_EINVAL, "tread profile %s: coefficients must be finite", p->name);
  for (double a = 0; a <= A_CHECK_MM; a += 0.25) {
    double s, l = conicity_mm(p, a, &s);
    if (!(l > 0 && l <= RR_CONICITY_MAX))
      return rr_seterr(err, RR_EINVAL, "tread profile %s: conicity %g at %g mm outside (0, %g]",
                       p->name, l, a, RR_CONICITY_MAX);
  }
  return RR_OK;
}

int rr_profile_describe(const rr_profile *p, char *buf, int n)
{
  int k = 0;
  if (p->kind == RR_PROFILE_POLY) {
    k = snprintf(buf, (size_t)n, "lambda(a) =");
    for (int i = 0; i < p->n && k < n; i++)
      k += snprintf(buf + k, (size_t)(n - k),
                    i == 0   ? " %.6g"
                    : i == 1 ? " %+.6g a"
                             : " %+.6g a^%d",
                    p->c[i], i);
    if (k < n)
      k += snprintf(buf + k, (size_t)(n - k), " (a = |y_w - y_t| in mm), held beyond %g mm",
                    p->hold_mm);
  } else if (p->kind == RR_PROFILE_TABLE) {
    k = snprintf(buf, (size_t)n,
                 "lambda(a) from table %s: %d points, a = 0 .. %g mm, linear, held beyond", p->name,
                 p->n, p->a_mm[p->n - 1]);
  } else
    k = snprintf(buf, (size_t)n, "none");
  return k;
}
