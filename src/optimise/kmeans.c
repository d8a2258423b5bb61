/* k-means (Lloyd 1982) with a deterministic farthest-point start
 * (Gonzalez 1985), for naming clusters of a Pareto set. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/nsga2.h"
#include "util/internal.h"

#define KMEANS_MAX_ITER 1000 /* Lloyd passes; each lowers the sum of squares, so it ends first */

/* Sizes are size_t inside: n points of m coordinates, k groups. */
static double dist2(const double *a, const double *b, size_t m)
{
  double s = 0;
  for (size_t j = 0; j < m; j++) s += (a[j] - b[j]) * (a[j] - b[j]);
  return s;
}

/* The index of the centre nearest to p (ties to the lower index). */
static size_t nearest(const double *p, const double *c, size_t k, size_t m)
{
  size_t best = 0;
  double bd = dist2(p, c, m);
  for (size_t i = 1; i < k; i++) {
    double d = dist2(p, c + i * m, m);
    if (d < bd) bd = d, best = i;
  }
  return best;
}

/* The farthest-point start: y's smallest first coordinate, then each point
   farthest from the centres chosen so far. */
static void start(const double *y, size_t n, size_t m, size_t k, double *c)
{
  size_t first = 0;
  for (size_t i = 1; i < n; i++)
    if (y[i * m] < y[first * m]) first = i;
  memcpy(c, y + first * m, sizeof(double) * m);
  for (size_t q = 1; q < k; q++) {
    size_t far = 0;
    double fd = -1;
    for (size_t i = 0; i < n; i++) {
      const double *p = y + i * m;
      double d = dist2(p, c + nearest(p, c, q, m) * m, m);
      if (d > fd) fd = d, far = i;
    }
    memcpy(c + q * m, y + far * m, sizeof(double) * m);
  }
}

/* Lloyd's passes until no label changes: the labels and the passes made. An
   empty group keeps its centre. */
static int lloyd(const double *y, size_t n, size_t m, size_t k, double *c, size_t *label,
                 size_t *cnt)
{
  for (size_t i = 0; i < n; i++) label[i] = k; /* none yet */
  for (int it = 1; it <= KMEANS_MAX_ITER; it++) {
    int changed = 0;
    for (size_t i = 0; i < n; i++) {
      size_t l = nearest(y + i * m, c, k, m);
      changed |= l != label[i];
      label[i] = l;
    }
    if (!changed) return it;
    memset(cnt, 0, sizeof(size_t) * k);
    for (size_t i = 0; i < n; i++) cnt[label[i]]++;
    for (size_t q = 0; q < k; q++)
      if (cnt[q]) memset(c + q * m, 0, sizeof(double) * m);
    for (size_t i = 0; i < n; i++)
      for (size_t j = 0; j < m; j++) c[label[i] * m + j] += y[i * m + j];
    for (size_t q = 0; q < k; q++)
      for (size_t j = 0; cnt[q] && j < m; j++) c[q * m + j] /= (double)cnt[q];
  }
  return KMEANS_MAX_ITER;
}

/* Renumbers the groups by ascending first coordinate of their centres
   (ties to the lower old number); order, rank: k entries, tmp: k x m doubles. */
static void renumber(size_t n, size_t m, size_t k, double *c, size_t *label, size_t *order,
                     size_t *rank, double *tmp)
{
  for (size_t q = 0; q < k; q++) order[q] = q;
  for (size_t a = 1; a < k; a++) /* insertion sort: k is small */
    for (size_t b = a; b > 0 && c[order[b] * m] < c[order[b - 1] * m]; b--) {
      size_t t = order[b];
      order[b] = order[b - 1];
      order[b - 1] = t;
    }
  for (size_t q = 0; q < k; q++) rank[order[q]] = q;
  for (size_t i = 0; i < n; i++) label[i] = rank[label[i]];
  memcpy(tmp, c, sizeof(double) * k * m);
  for (size_t q = 0; q < k; q++) memcpy(c + q * m, tmp + order[q] * m, sizeof(double) * m);
}

/* The scaling of each coordinate over the points, [lo, lo + w] -> [0, 1]
   (scale 0: lo 0, w 1), and the scaled points into y. */
static void scale_points(const double *x, size_t n, size_t m, int scale, double *lo, double *w,
                         double *y)
{
  for (size_t j = 0; j < m; j++) {
    lo[j] = INFINITY;
    double hi = -INFINITY;
    for (size_t i = 0; i < n; i++) lo[j] = fmin(lo[j], x[i * m + j]), hi = fmax(hi, x[i * m + j]);
    w[j] = scale && hi > lo[j] ? hi - lo[j] : 1;
    if (!scale) lo[j] = 0;
  }
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < m; j++) y[i * m + j] = (x[i * m + j] - lo[j]) / w[j];
}

int rr_kmeans(int n, int m, const double *x, int k, int scale, int *label, double *centre,
              int *iterations, rr_error *err)
{
  if (n < 1 || m < 1 || k < 1 || k > n || k > 1000)
    return rr_seterr(err, RR_EINVAL, "k-means: need 1 <= k <= n (and k <= 1000): n %d, k %d", n, k);
  size_t N = (size_t)n, M = (size_t)m, K = (size_t)k;
  for (size_t i = 0; i < N * M; i++)
    if (!isfinite(x[i]))
      return rr_seterr(err, RR_EINVAL, "k-means: point %zu is not finite", i / M);
  double *y = malloc(sizeof(double) * (N * M + 2 * K * M + 2 * M));
  size_t *lab = malloc(sizeof(size_t) * (N + 3 * K)); /* labels, counts, renumber's order, rank */
  if (!y || !lab) {
    free(y);
    free(lab);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  double *c = y + N * M, *tmp = c + K * M, *lo = tmp + K * M, *w = lo + M;
  size_t *cnt = lab + N;
  scale_points(x, N, M, scale, lo, w, y);
  start(y, N, M, K, c);
  int it = lloyd(y, N, M, K, c, lab, cnt);
  renumber(N, M, K, c, lab, cnt + K, cnt + 2 * K, tmp);
  for (size_t i = 0; i < N; i++) label[i] = (int)lab[i];
  for (size_t q = 0; centre && q < K; q++)
    for (size_t j = 0; j < M; j++) centre[q * M + j] = lo[j] + w[j] * c[q * M + j];
  if (iterations) *iterations = it;
  free(y);
  free(lab);
  return RR_OK;
}
