/* The paper problem's cluster letters, one rule for `railride pareto` and
 * the Pareto plot: the cluster holding design A (the best zeta_high) is A,
 * design B's (the best zeta_low) B, design C's (the best std_zeta among the
 * designs stable at both robust points, zeta_low and zeta_high < 0) C, design
 * D's (the least distance to the ideal point, each objective scaled to 0..1)
 * D, as examples/paper_bifurcation_study.py picks its designs. */
#include <math.h>
#include <string.h>
#include "cli.h"

/* Columns of zeta_low, zeta_high, std_zeta among the m names, or -1. */
static int paper_columns(int m, const char *const *names, int col[3])
{
  static const char *const want[3] = {"zeta_low", "zeta_high", "std_zeta"};
  col[0] = col[1] = col[2] = -1;
  for (int w = 0; w < 3; w++)
    for (int j = 0; j < m; j++)
      if (!strcmp(names[j], want[w])) col[w] = j;
  return m == 3 && col[0] >= 0 && col[1] >= 0 && col[2] >= 0;
}

/* The four designs' rows into d[4]; 0 when one has none. */
static int paper_designs(int n, const double *x, const int col[3], int d[4])
{
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < n; i++)
    for (int w = 0; w < 3; w++) {
      lo[w] = fmin(lo[w], x[3 * i + col[w]]);
      hi[w] = fmax(hi[w], x[3 * i + col[w]]);
    }
  double best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
  d[0] = d[1] = d[2] = d[3] = -1;
  for (int i = 0; i < n; i++) {
    const double *r = x + 3 * i;
    double dist = 0;
    for (int w = 0; w < 3; w++) {
      double t = hi[w] > lo[w] ? (r[col[w]] - lo[w]) / (hi[w] - lo[w]) : 0;
      dist += t * t;
    }
    double zl = r[col[0]], zh = r[col[1]];
    double score[4] = {zh, zl, zl < 0 && zh < 0 ? r[col[2]] : INFINITY, dist};
    for (int q = 0; q < 4; q++)
      if (score[q] < best[q]) best[q] = score[q], d[q] = i;
  }
  return d[0] >= 0 && d[1] >= 0 && d[2] >= 0 && d[3] >= 0;
}

void cli_paper_letters(int n, int m, const double *x, const char *const *names, int k, int *label,
                       double *centre)
{
  int col[3], d[4], perm[4] = {-1, -1, -1, -1}; /* old label -> new */
  if (k != 4 || !paper_columns(m, names, col) || !paper_designs(n, x, col, d)) return;
  for (int q = 0; q < 4; q++) {
    if (perm[label[d[q]]] >= 0) return; /* two designs in one cluster: the order stays */
    perm[label[d[q]]] = q;
  }
  double c[4 * 3];
  for (int q = 0; q < 4; q++) memcpy(c + 3 * perm[q], centre + 3 * q, sizeof(double) * 3);
  memcpy(centre, c, sizeof c);
  for (int i = 0; i < n; i++) label[i] = perm[label[i]];
}
