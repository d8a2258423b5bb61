/* k-means (Lloyd 1982) with a deterministic farthest-point start
 * (Gonzalez 1985), for naming clusters of a Pareto set. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/nsga2.h"
#include "util/internal.h"

#define KMEANS_MAX_ITER 1000 /* Lloyd passes; each lowers the sum of squares, so it ends first */

static double dist2(const double *a, const double *b, int m)
{
  double s = 0;
  for (int j = 0; j < m; j++) s += (a[j] - b[j]) * (a[j] - b[j]);
  return s;
}

/* The index of the centre nearest to p (ties to the lower index). */
static int nearest(const double *p, const double *c, int k, int m)
{
  int best = 0;
  double bd = dist2(p, c, m);
  for (int i = 1; i < k; i++) {
    double d = dist2(p, c + (size_t)i * m, m);
    if (d < bd) bd = d, best = i;
  }
  return best;
}

/* The farthest-point start: y's smallest first coordinate, then each point
   farthest from the centres chosen so far. */
static void start(const double *y, int n, int m, int k, double *c)
{
  int first = 0;
  for (int i = 1; i < n; i++)
    if (y[(size_t)i * m] < y[(size_t)first * m]) first = i;
  memcpy(c, y + (size_t)first * m, sizeof(double) * (size_t)m);
  for (int q = 1; q < k; q++) {
    int far = 0;
    double fd = -1;
    for (int i = 0; i < n; i++) {
      const double *p = y + (size_t)i * m;
      double d = dist2(p, c + (size_t)nearest(p, c, q, m) * m, m);
      if (d > fd) fd = d, far = i;
    }
    memcpy(c + (size_t)q * m, y + (size_t)far * m, sizeof(double) * (size_t)m);
  }
}

/* Lloyd's passes until no label changes: the labels and the passes made. An
   empty group keeps its centre. */
static int lloyd(const double *y, int n, int m, int k, double *c, int *label, int *cnt)
{
  for (int i = 0; i < n; i++) label[i] = -1;
  for (int it = 1; it <= KMEANS_MAX_ITER; it++) {
    int changed = 0;
    for (int i = 0; i < n; i++) {
      int l = nearest(y + (size_t)i * m, c, k, m);
      changed |= l != label[i];
      label[i] = l;
    }
    if (!changed) return it;
    memset(cnt, 0, sizeof(int) * (size_t)k);
    for (int i = 0; i < n; i++) cnt[label[i]]++;
    for (int q = 0; q < k; q++)
      if (cnt[q]) memset(c + (size_t)q * m, 0, sizeof(double) * (size_t)m);
    for (int i = 0; i < n; i++)
      for (int j = 0; j < m; j++) c[(size_t)label[i] * m + j] += y[(size_t)i * m + j];
    for (int q = 0; q < k; q++)
      for (int j = 0; cnt[q] && j < m; j++) c[(size_t)q * m + j] /= cnt[q];
  }
  return KMEANS_MAX_ITER;
}

/* Renumbers the groups by ascending first coordinate of their centres
   (ties to the lower old number); order, rank: k ints, tmp: k x m doubles. */
static void renumber(int n, int m, int k, double *c, int *label, int *order, int *rank, double *tmp)
{
  for (int q = 0; q < k; q++) order[q] = q;
  for (int a = 1; a < k; a++) /* insertion sort: k is small */
    for (int b = a; b > 0 && c[(size_t)order[b] * m] < c[(size_t)order[b - 1] * m]; b--) {
      int t = order[b];
      order[b] = order[b - 1];
      order[b - 1] = t;
    }
  for (int q = 0; q < k; q++) rank[order[q]] = q;
  for (int i = 0; i < n; i++) label[i] = rank[label[i]];
  memcpy(tmp, c, sizeof(double) * (size_t)k * m);
  for (int q = 0; q < k; q++)
    memcpy(c + (size_t)q * m, tmp + (size_t)order[q] * m, sizeof(double) * (size_t)m);
}

int rr_kmeans(int n, int m, const double *x, int k, int scale, int *label, double *centre,
              int *iterations, rr_error *err)
{
  if (n < 1 || m < 1 || k < 1 || k > n || k > 1000)
    return rr_seterr(err, RR_EINVAL, "k-means: need 1 <= k <= n (and k <= 1000): n %d, k %d", n, k);
  for (size_t i = 0; i < (size_t)n * m; i++)
    if (!isfinite(x[i]))
      return rr_seterr(err, RR_EINVAL, "k-means: point %zu is not finite", i / m);
  double *y = malloc(sizeof(double) * ((size_t)n * m + 2 * (size_t)k * m + 2 * (size_t)m));
  int *cnt = malloc(sizeof(int) * 3 * (size_t)k); /* counts, then renumber's order and rank */
  if (!y || !cnt) {
    free(y);
    free(cnt);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  double *c = y + (size_t)n * m, *tmp = c + (size_t)k * m, *lo = tmp + (size_t)k * m, *w = lo + m;
  for (int j = 0; j < m; j++) { /* the scaling: [lo, lo + w] -> [0, 1] */
    lo[j] = INFINITY;
    double hi = -INFINITY;
    for (int i = 0; i < n; i++)
      lo[j] = fmin(lo[j], x[(size_t)i * m + j]), hi = fmax(hi, x[(size_t)i * m + j]);
    w[j] = scale && hi > lo[j] ? hi - lo[j] : 1;
    if (!scale) lo[j] = 0;
  }
  for (int i = 0; i < n; i++)
    for (int j = 0; j < m; j++) y[(size_t)i * m + j] = (x[(size_t)i * m + j] - lo[j]) / w[j];
  start(y, n, m, k, c);
  int it = lloyd(y, n, m, k, c, label, cnt);
  renumber(n, m, k, c, label, cnt + k, cnt + 2 * k, tmp);
  for (size_t q = 0; centre && q < (size_t)k; q++)
    for (int j = 0; j < m; j++) centre[q * m + j] = lo[j] + w[j] * c[q * m + j];
  if (iterations) *iterations = it;
  free(y);
  free(cnt);
  return RR_OK;
}
