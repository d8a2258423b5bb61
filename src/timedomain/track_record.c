/* A measured alignment record (distance_m, alignment_m) as the track inputs
 * of a time-domain run: each wheelset reads the record at its own position,
 * linearly interpolated; rates by central differences of the samples. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/timesim.h"
#include "util/internal.h"
#include "util/textfile.h"

#define RECORD_MAX_ROWS 10000000

void rr_track_record_free(rr_track_record *r)
{
  if (!r) return;
  free(r->x);
  free(r->y);
  memset(r, 0, sizeof *r);
}

static int grow(rr_track_record *r, int *cap)
{
  int nc = *cap ? 2 * *cap : 1024;
  double *x = realloc(r->x, sizeof(double) * (size_t)nc);
  if (!x) return -1;
  r->x = x;
  double *y = realloc(r->y, sizeof(double) * (size_t)nc);
  if (!y) return -1;
  r->y = y;
  *cap = nc;
  return 0;
}

int rr_track_record_load(const char *path, rr_track_record *r, rr_error *err)
{
  memset(r, 0, sizeof *r);
  rr_lines L;
  int st = rr_lines_open(&L, path, RR_CSV_LINE_MAX, err), got, cap = 0;
  if (st) return st;
  const char *line;
  while (!st && (got = rr_lines_next(&L, &line)) > 0) {
    double x, y;
    int row = rr_csv_pair(line, r->n, &x, &y);
    if (row == 0) continue;
    if (row < 0)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: expected two numbers distance_m, alignment_m", path,
                     L.line);
    else if (!(isfinite(x) && isfinite(y) && fabs(y) <= 1 && (r->n == 0 || x > r->x[r->n - 1])))
      st = rr_seterr(err, RR_EPARSE, "%s:%d: distance must rise, alignment within 1 m", path,
                     L.line);
    else if (r->n >= RECORD_MAX_ROWS)
      st = rr_seterr(err, RR_EPARSE, "%s:%d: more than %d rows", path, L.line, RECORD_MAX_ROWS);
    else if (r->n == cap && grow(r, &cap))
      st = rr_seterr(err, RR_ENOMEM, "out of memory");
    else {
      r->x[r->n] = x;
      r->y[r->n] = y;
      r->n++;
    }
  }
  if (!st && L.status) st = rr_seterr(err, L.status, "%s", L.err.msg);
  rr_lines_close(&L);
  if (!st && r->n < 2) st = rr_seterr(err, RR_EPARSE, "%s: fewer than two rows", path);
  if (st) rr_track_record_free(r);
  return st;
}

static double record_at(const rr_track_record *r, double x, int *hint)
{
  int i = *hint;
  while (i + 2 < r->n && x > r->x[i + 1]) i++;
  while (i > 0 && x < r->x[i]) i--;
  *hint = i;
  double u = (x - r->x[i]) / (r->x[i + 1] - r->x[i]);
  return r->y[i] + u * (r->y[i + 1] - r->y[i]);
}

double rr_track_record_duration(const rr_track_record *r, double v, const double *x, int ni)
{
  double lo = x[0], hi = x[0];
  for (int i = 1; i < ni; i++) {
    lo = fmin(lo, x[i]);
    hi = fmax(hi, x[i]);
  }
  return (r->x[r->n - 1] - r->x[0] - (hi - lo)) / v;
}

int rr_track_record_sample(const rr_track_record *r, double v, const double *x, int ni, double fs,
                           int ns, double *u, double *du, rr_error *err)
{
  if (!(v > 0 && fs > 0 && ns >= 2 && ni >= 1))
    return rr_seterr(err, RR_EINVAL, "track record: need speed > 0, fs > 0, >= 2 samples");
  if ((ns - 1) / fs > rr_track_record_duration(r, v, x, ni) * (1 + 1e-12))
    return rr_seterr(err, RR_EINVAL, "track record: %.6g m long, too short for %.6g s at %.6g km/h",
                     r->x[r->n - 1] - r->x[0], (ns - 1) / fs, v * RR_KMH);
  double lo = x[0];
  for (int i = 1; i < ni; i++) lo = fmin(lo, x[i]);
  for (int i = 0; i < ni;
       i++) { /* y_t(v t + x_i), the last contact starting at the record's start */
    int hint = 0;
    double *ui = u + (size_t)i * (size_t)ns;
    for (int k = 0; k < ns; k++) ui[k] = record_at(r, r->x[0] + v * k / fs + (x[i] - lo), &hint);
    for (int k = 0; k < ns; k++) {
      int a = k > 0 ? k - 1 : k, b = k < ns - 1 ? k + 1 : k;
      du[(size_t)i * (size_t)ns + (size_t)k] = (ui[b] - ui[a]) * fs / (b - a);
    }
  }
  return RR_OK;
}
