/* Frequency-dependent series stiffness (SDF) of the yaw damper, docs/model.md section 4. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/sdf.h"
#include "util/internal.h"
#include "util/textfile.h"

/* Linear interpolation in log f, held constant outside the table. */
static double table_interp(const rr_sdf_curve *c, const double *y, double f)
{
  if (c->n == 1 || f <= c->f_hz[0]) return y[0];
  if (f >= c->f_hz[c->n - 1]) return y[c->n - 1];
  int lo = 0, hi = c->n - 1;
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (c->f_hz[mid] <= f)
      lo = mid;
    else
      hi = mid;
  }
  double t = log(f / c->f_hz[lo]) / log(c->f_hz[hi] / c->f_hz[lo]);
  return y[lo] + t * (y[hi] - y[lo]);
}

double rr_sdf_storage(const rr_sdf_curve *c, double f_hz)
{
  if (c->kind == RR_CURVE_TABLE) return table_interp(c, c->k_storage, fabs(f_hz));
  double x = f_hz / c->k1_hz;
  return c->k3 + c->k2 * x * x / (1.0 + x * x);
}

double complex rr_sdf_laplace(const rr_sdf_curve *c, double complex s)
{
  if (c->kind == RR_CURVE_TABLE) {
    double f = cabs(s) / (2 * RR_PI);
    return table_interp(c, c->k_storage, f) +
           I * (c->has_loss ? table_interp(c, c->k_loss, f) : 0.0);
  }
  double tau = 1.0 / (2 * RR_PI * c->k1_hz);
  return c->k3 + c->k2 * (s * tau) / (1.0 + s * tau);
}

double complex rr_sdf_complex(const rr_sdf_curve *c, double w) { return rr_sdf_laplace(c, I * w); }

double complex rr_sdf_series_k(const rr_sdf_curve *c, rr_sdf_mode mode, double complex s)
{
  if (mode == RR_SDF_PAPER) return rr_sdf_storage(c, fabs(cimag(s)) / (2 * RR_PI));
  return rr_sdf_laplace(c, s);
}

void rr_sdf_range(const rr_sdf_curve *c, double *k_lo, double *k_hi)
{
  if (c->kind == RR_CURVE_TABLE) {
    double lo = c->k_storage[0], hi = lo;
    for (int i = 1; i < c->n; i++) {
      if (c->k_storage[i] < lo) lo = c->k_storage[i];
      if (c->k_storage[i] > hi) hi = c->k_storage[i];
    }
    *k_lo = lo;
    *k_hi = hi;
  } else {
    *k_lo = c->k3;
    *k_hi = c->k3 + c->k2;
  }
}

int rr_sdf_curve_check(const rr_sdf_curve *c, const char *what, rr_error *err)
{
  if (c->kind == RR_CURVE_SLS) {
    if (!(c->k1_hz >= 1e-3 && c->k1_hz <= 1e3))
      return rr_seterr(err, RR_EINVAL, "%s: sdf_k1 outside 0.001 .. 1000 Hz", what);
    if (!(c->k2 >= 0 && c->k2 <= 1e12))
      return rr_seterr(err, RR_EINVAL, "%s: sdf_k2 outside 0 .. 1e12 N/m", what);
    if (!(c->k3 >= 1e3 && c->k3 <= 1e12))
      return rr_seterr(err, RR_EINVAL, "%s: sdf_k3 outside 1000 .. 1e12 N/m", what);
    return RR_OK;
  }
  if (c->kind == RR_CURVE_TABLE) {
    if (c->n < 1) return rr_seterr(err, RR_EINVAL, "%s: empty SDF table", what);
    for (int i = 0; i < c->n; i++) {
      if (!(c->f_hz[i] > 0 && c->f_hz[i] <= 1e4))
        return rr_seterr(err, RR_EINVAL, "%s: SDF table row %d: frequency outside (0, 1e4] Hz",
                         what, i + 1);
      if (i && !(c->f_hz[i] > c->f_hz[i - 1]))
        return rr_seterr(err, RR_EINVAL, "%s: SDF table row %d: frequencies must increase", what,
                         i + 1);
      if (!(c->k_storage[i] >= 1e3 && c->k_storage[i] <= 1e15))
        return rr_seterr(err, RR_EINVAL,
                         "%s: SDF table row %d: storage stiffness outside 1000 .. 1e15 N/m", what,
                         i + 1);
      if (c->has_loss && !(c->k_loss[i] >= 0 && c->k_loss[i] <= 1e15))
        return rr_seterr(err, RR_EINVAL,
                         "%s: SDF table row %d: loss stiffness outside 0 .. 1e15 N/m", what, i + 1);
    }
    return RR_OK;
  }
  return rr_seterr(err, RR_EINVAL, "%s: no SDF curve given (sdf_k1/sdf_k2/sdf_k3 or sdf_table)",
                   what);
}

/* One row of numbers separated by commas, semicolons or blanks: the count
   (up to 4), or -1 when something else is in the row. */
static int row_numbers(const char *p, double *v)
{
  int k = 0;
  while (*p) {
    while (isspace((unsigned char)*p)) p++;
    if (!*p) break;
    if (k == 4) return -1;
    char *end;
    errno = 0;
    v[k] = strtod(p, &end);
    if (end == p || errno == ERANGE || !isfinite(v[k])) return -1;
    k++;
    p = end;
    while (isspace((unsigned char)*p)) p++;
    if (*p == ',' || *p == ';') p++;
  }
  return k;
}

/* A header line: text, no digits leading. */
static int header_line(const char *p)
{
  while (isspace((unsigned char)*p)) p++;
  return isalpha((unsigned char)*p);
}

/* The header's names and units (optional; a table without one is Hz and N/m). */
#define RR_2PI_INV 0.15915494309189535
static const rr_csv_name sdf_f[] = {{"f_hz", 1},
                                    {"f", 1},
                                    {"freq_hz", 1},
                                    {"frequency_hz", 1},
                                    {"f_rad_per_s", RR_2PI_INV},
                                    {"omega_rad_per_s", RR_2PI_INV},
                                    {NULL, 0}};
static const rr_csv_name sdf_ks[] = {{"k_storage", 1},
                                     {"k_storage_n_per_m", 1},
                                     {"k_storage_n_per_mm", 1e3},
                                     {"k_storage_kn_per_m", 1e3},
                                     {"k_storage_kn_per_mm", 1e6},
                                     {"k_storage_mn_per_m", 1e6},
                                     {"k", 1},
                                     {"k_n_per_m", 1},
                                     {"k_n_per_mm", 1e3},
                                     {"k_kn_per_m", 1e3},
                                     {"k_kn_per_mm", 1e6},
                                     {"k_mn_per_m", 1e6},
                                     {NULL, 0}};
static const rr_csv_name sdf_kl[] = {{"k_loss", 1},
                                     {"k_loss_n_per_m", 1},
                                     {"k_loss_n_per_mm", 1e3},
                                     {"k_loss_kn_per_m", 1e3},
                                     {"k_loss_kn_per_mm", 1e6},
                                     {"k_loss_mn_per_m", 1e6},
                                     {NULL, 0}};

int rr_sdf_table_load(const char *path, rr_sdf_curve *c, rr_error *err)
{
  rr_lines r;
  int st = rr_lines_open(&r, path, RR_CSV_LINE_MAX, err), ncols = -1, got;
  if (st) return st;
  const char *line;
  const rr_csv_name *const cols[3] = {sdf_f, sdf_ks, sdf_kl};
  double sc[3] = {1, 1, 1};
  c->n = 0;
  while (!st && (got = rr_lines_next(&r, &line)) > 0) {
    double v[4];
    const char *p = line;
    while (isspace((unsigned char)*p)) p++;
    if (!*p) continue;
    if (c->n == 0 && ncols < 0 && header_line(p)) {
      if ((st = rr_csv_header(path, r.line, p, cols, 1, 3, sc, NULL, err))) break;
      ncols = 0;
      continue;
    }
    int k = row_numbers(p, v);
    if (k < 2 || k > 3)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: expected 2 or 3 numbers (f_hz, k_storage[, k_loss])",
                     path, r.line);
    else if (ncols > 0 && k != ncols)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: %d columns where earlier rows have %d", path, r.line,
                     k, ncols);
    else if (c->n >= RR_SDF_TABLE_MAX)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: more than %d rows", path, r.line, RR_SDF_TABLE_MAX);
    if (st) break;
    ncols = k;
    c->f_hz[c->n] = v[0] * sc[0];
    c->k_storage[c->n] = v[1] * sc[1];
    c->k_loss[c->n] = k == 3 ? v[2] * sc[2] : 0.0;
    c->n++;
  }
  if (!st && r.status) st = rr_seterr(err, r.status, "%s", r.err.msg);
  rr_lines_close(&r);
  if (st) return st;
  if (c->n == 0) return rr_seterr(err, RR_EPARSE, "%s: no rows", path);
  c->kind = RR_CURVE_TABLE;
  c->has_loss = ncols == 3;
  return rr_sdf_curve_check(c, path, err);
}
