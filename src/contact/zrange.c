/* Extremes of a polyline's heights over vertex index ranges in O(1) (a
 * sparse table), so that the contact search can bound a whole block of
 * candidates' depths and skip the block without evaluating it. */
#include <math.h>
#include <string.h>
#include "contact/contact_impl.h"

int rr_zrange_levels(int n)
{
  int l = 1;
  while ((1 << l) <= n) l++;
  return l;
}

void rr_zrange_build(rr_zrange *q, double *t, const double *z, int n, int max)
{
  q->t = t;
  q->n = n;
  q->levels = rr_zrange_levels(n);
  q->max = max;
  memcpy(t, z, sizeof(double) * (size_t)n);
  for (int l = 1; l < q->levels; l++) {
    const double *a = t + (size_t)(l - 1) * n;
    double *b = t + (size_t)l * n;
    int h = 1 << (l - 1);
    for (int i = 0; i + 2 * h <= n; i++) b[i] = max ? fmax(a[i], a[i + h]) : fmin(a[i], a[i + h]);
  }
}

double rr_zrange_query(const rr_zrange *q, int a, int b)
{
  int l = 0;
  while ((2 << l) <= b - a + 1) l++;
  const double *t = q->t + (size_t)l * q->n;
  double x = t[a], y = t[b - (1 << l) + 1];
  return q->max ? fmax(x, y) : fmin(x, y);
}
