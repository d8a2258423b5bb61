/* A polyline's blocks as chords with the heights' spread about them, so
 * that the contact search can bound the depths of a whole block of
 * candidates by two lines and skip the block without evaluating it: the
 * profiles are smooth, so the spread (curvature over a block) is far
 * smaller than the range of heights. */
#include <math.h>
#include "contact/contact_impl.h"

int rr_chords_count(int n, int block) { return (n - 2) / block + 1; }

void rr_chords_build(rr_chords *c, double *buf, const double *x, const double *z, int n, int block)
{
  c->x = x;
  c->n = n;
  c->block = block;
  c->nb = rr_chords_count(n, block);
  c->k = buf;
  c->c = buf + c->nb;
  c->up = buf + 2 * c->nb;
  c->down = buf + 3 * c->nb;
  for (int q = 0; q < c->nb; q++) {
    int a = q * block, e = a + block < n - 1 ? a + block : n - 1;
    double k = (z[e] - z[a]) / (x[e] - x[a]), c0 = z[a] - k * x[a], up = 0, dn = 0;
    for (int i = a; i <= e; i++) {
      double r = z[i] - (c0 + k * x[i]);
      up = r > up ? r : up;
      dn = -r > dn ? -r : dn;
    }
    c->k[q] = k;
    c->c[q] = c0;
    c->up[q] = up;
    c->down[q] = dn;
  }
}
