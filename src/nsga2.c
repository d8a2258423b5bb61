/* NSGA-II, written from Deb et al. 2002 and the published SBX (Deb & Agrawal
 * 1995) and polynomial mutation formulas. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "railride/nsga2.h"
#include "rng.h"
#include "internal.h"

rr_nsga2_opts rr_nsga2_opts_default(void)
{
  rr_nsga2_opts o;
  memset(&o, 0, sizeof o);
  o.population = 100;
  o.generations = 250;
  o.seed = 1;
  o.p_crossover = 0.9;
  o.eta_c = 15;
  o.p_mutation = -1;
  o.eta_m = 20;
  o.hv_every = 10;
  return o;
}

static int dominates(const double *a, const double *b, int m)
{
  int better = 0;
  for (int k = 0; k < m; k++) {
    if (a[k] > b[k]) return 0;
    if (a[k] < b[k]) better = 1;
  }
  return better;
}

static int lex_cmp(const double *a, const double *b, int m)
{
  for (int k = 0; k < m; k++) {
    if (a[k] < b[k]) return -1;
    if (a[k] > b[k]) return 1;
  }
  return 0;
}

static void sort_idx(int *idx, int n, const double *f, int m)
{
  /* merge sort on indices (stable, no global context) */
  if (n < 2) return;
  int *tmp = malloc(sizeof(int) * n);
  if (!tmp) {   /* fall back to insertion sort */
    for (int i = 1; i < n; i++) {
      int t = idx[i], j = i;
      while (j > 0 && lex_cmp(f + (size_t)idx[j - 1] * m, f + (size_t)t * m, m) > 0) { idx[j] = idx[j - 1]; j--; }
      idx[j] = t;
    }
    return;
  }
  for (int w = 1; w < n; w *= 2) {
    for (int lo = 0; lo < n; lo += 2 * w) {
      int mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n, a = lo, b = mid, k = lo;
      while (a < mid && b < hi) tmp[k++] = lex_cmp(f + (size_t)idx[b] * m, f + (size_t)idx[a] * m, m) < 0 ? idx[b++] : idx[a++];
      while (a < mid) tmp[k++] = idx[a++];
      while (b < hi) tmp[k++] = idx[b++];
    }
    memcpy(idx, tmp, sizeof(int) * n);
  }
  free(tmp);
}

int rr_nondominated_ranks(int n, int m, const double *f, int *rank)
{
  /* ENS-SS (Zhang et al., IEEE TEC 2015): in lexicographic order no point is
     dominated by a later one, so each point joins the first front none of whose
     members dominates it. Fronts are linked lists through next[] (newest
     first, where a dominator is likeliest): O(n) memory. */
  int *idx = malloc(sizeof(int) * (n > 0 ? n : 1)), *head = malloc(sizeof(int) * (n + 1)), *next = malloc(sizeof(int) * (n > 0 ? n : 1));
  if (!idx || !head || !next) { free(idx); free(head); free(next); return -1; }
  for (int i = 0; i < n; i++) idx[i] = i;
  sort_idx(idx, n, f, m);
  int nf = 0;
  for (int t = 0; t < n; t++) {
    int p = idx[t];
    const double *fp = f + (size_t)p * m;
    int k = 0;
    for (; k < nf; k++) {
      int dom = 0;
      for (int q = head[k]; q >= 0 && !dom; q = next[q]) dom = dominates(f + (size_t)q * m, fp, m);
      if (!dom) break;
    }
    if (k == nf) head[nf++] = -1;
    rank[p] = k;
    next[p] = head[k];
    head[k] = p;
  }
  free(idx); free(head); free(next);
  return nf;
}

/* 2-D staircase area of points sorted by f1 ascending (f2 descending), up to ref. */
static double area2(const double *s1, const double *s2, int k, double r1, double r2)
{
  double a = 0;
  for (int i = 0; i < k; i++) {
    double next = i + 1 < k ? s1[i + 1] : r1;
    a += (next - s1[i]) * (r2 - s2[i]);
  }
  return a;
}

double rr_hypervolume(int n, int m, const double *f, const double *ref)
{
  if (m != 2 && m != 3) return -1;
  int *idx = malloc(sizeof(int) * (n > 0 ? n : 1));
  double *s1 = malloc(sizeof(double) * (n + 1)), *s2 = malloc(sizeof(double) * (n + 1));
  if (!idx || !s1 || !s2) { free(idx); free(s1); free(s2); return -1; }
  int k = 0;
  for (int i = 0; i < n; i++) {
    const double *p = f + (size_t)i * m;
    int in = 1;
    for (int j = 0; j < m; j++) if (!(p[j] < ref[j])) in = 0;
    if (in) idx[k++] = i;
  }
  double hv = 0;
  if (m == 2) {
    /* insert all into one staircase */
    int ns = 0;
    for (int t = 0; t < k; t++) {
      const double *p = f + (size_t)idx[t] * 2;
      int dom = 0;
      for (int i = 0; i < ns && !dom; i++) if (s1[i] <= p[0] && s2[i] <= p[1]) dom = 1;
      if (dom) continue;
      int w = 0;
      for (int i = 0; i < ns; i++) if (!(p[0] <= s1[i] && p[1] <= s2[i])) { s1[w] = s1[i]; s2[w] = s2[i]; w++; }
      ns = w;
      int pos = 0;
      while (pos < ns && s1[pos] < p[0]) pos++;
      memmove(s1 + pos + 1, s1 + pos, sizeof(double) * (ns - pos));
      memmove(s2 + pos + 1, s2 + pos, sizeof(double) * (ns - pos));
      s1[pos] = p[0]; s2[pos] = p[1]; ns++;
    }
    hv = area2(s1, s2, ns, ref[0], ref[1]);
  } else {
    /* sweep f3 upward; the 2-D staircase of the points seen so far times the slab */
    for (int i = 1; i < k; i++) {   /* sort idx by f3 */
      int t = idx[i], j = i;
      while (j > 0 && f[(size_t)idx[j - 1] * 3 + 2] > f[(size_t)t * 3 + 2]) { idx[j] = idx[j - 1]; j--; }
      idx[j] = t;
    }
    int ns = 0;
    double area = 0;
    for (int t = 0; t < k; t++) {
      const double *p = f + (size_t)idx[t] * 3;
      int dom = 0;
      for (int i = 0; i < ns && !dom; i++) if (s1[i] <= p[0] && s2[i] <= p[1]) dom = 1;
      if (!dom) {
        int w = 0;
        for (int i = 0; i < ns; i++) if (!(p[0] <= s1[i] && p[1] <= s2[i])) { s1[w] = s1[i]; s2[w] = s2[i]; w++; }
        ns = w;
        int pos = 0;
        while (pos < ns && s1[pos] < p[0]) pos++;
        memmove(s1 + pos + 1, s1 + pos, sizeof(double) * (ns - pos));
        memmove(s2 + pos + 1, s2 + pos, sizeof(double) * (ns - pos));
        s1[pos] = p[0]; s2[pos] = p[1]; ns++;
        area = area2(s1, s2, ns, ref[0], ref[1]);
      }
      double next = t + 1 < k ? f[(size_t)idx[t + 1] * 3 + 2] : ref[2];
      hv += area * (next - p[2]);
    }
  }
  free(idx); free(s1); free(s2);
  return hv;
}

/* crowding distance of the members of one front */
static void crowding(const int *mem, int cnt, int m, const double *f, double *cd, int *tmp)
{
  for (int i = 0; i < cnt; i++) cd[mem[i]] = 0;
  if (cnt <= 2) { for (int i = 0; i < cnt; i++) cd[mem[i]] = INFINITY; return; }
  for (int k = 0; k < m; k++) {
    for (int i = 0; i < cnt; i++) tmp[i] = mem[i];
    for (int i = 1; i < cnt; i++) {   /* insertion sort is fine: fronts are sorted often nearly */
      int t = tmp[i], j = i;
      while (j > 0 && f[(size_t)tmp[j - 1] * m + k] > f[(size_t)t * m + k]) { tmp[j] = tmp[j - 1]; j--; }
      tmp[j] = t;
    }
    double lo = f[(size_t)tmp[0] * m + k], hi = f[(size_t)tmp[cnt - 1] * m + k];
    cd[tmp[0]] = cd[tmp[cnt - 1]] = INFINITY;
    if (!(hi > lo)) continue;
    for (int i = 1; i < cnt - 1; i++)
      cd[tmp[i]] += (f[(size_t)tmp[i + 1] * m + k] - f[(size_t)tmp[i - 1] * m + k]) / (hi - lo);
  }
}

static void sbx(rr_rng *r, double eta, double lo, double hi, double *a, double *b)
{
  double y1 = fmin(*a, *b), y2 = fmax(*a, *b);
  if (y2 - y1 < 1e-14 || hi <= lo) return;
  double u = rr_rng_uniform(r), e1 = 1.0 / (eta + 1);
  double beta = 1 + 2 * (y1 - lo) / (y2 - y1), alpha = 2 - pow(beta, -(eta + 1));
  double bq = u <= 1 / alpha ? pow(u * alpha, e1) : pow(1 / (2 - u * alpha), e1);
  double c1 = 0.5 * ((y1 + y2) - bq * (y2 - y1));
  beta = 1 + 2 * (hi - y2) / (y2 - y1);
  alpha = 2 - pow(beta, -(eta + 1));
  bq = u <= 1 / alpha ? pow(u * alpha, e1) : pow(1 / (2 - u * alpha), e1);
  double c2 = 0.5 * ((y1 + y2) + bq * (y2 - y1));
  c1 = fmin(fmax(c1, lo), hi);
  c2 = fmin(fmax(c2, lo), hi);
  if (rr_rng_uniform(r) < 0.5) { *a = c2; *b = c1; } else { *a = c1; *b = c2; }
}

static double poly_mutation(rr_rng *r, double eta, double lo, double hi, double y)
{
  if (hi <= lo) return y;
  double d1 = (y - lo) / (hi - lo), d2 = (hi - y) / (hi - lo), u = rr_rng_uniform(r), mp = 1.0 / (eta + 1), dq;
  if (u < 0.5) {
    double val = 2 * u + (1 - 2 * u) * pow(1 - d1, eta + 1);
    dq = pow(val, mp) - 1;
  } else {
    double val = 2 * (1 - u) + 2 * (u - 0.5) * pow(1 - d2, eta + 1);
    dq = 1 - pow(val, mp);
  }
  y += dq * (hi - lo);
  return fmin(fmax(y, lo), hi);
}

static double now_s(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void sanitize(double *f, int n)
{
  for (int i = 0; i < n; i++) if (isnan(f[i])) f[i] = INFINITY;
}

/* Ranks and crowding of a population of n. */
static int rank_crowd(int n, int m, const double *f, int *rank, double *cd, int *mem, int *tmp)
{
  int nf = rr_nondominated_ranks(n, m, f, rank);
  if (nf < 0) return -1;
  for (int k = 0; k < nf; k++) {
    int c = 0;
    for (int i = 0; i < n; i++) if (rank[i] == k) mem[c++] = i;
    crowding(mem, c, m, f, cd, tmp);
  }
  return nf;
}

static int better(int a, int b, const int *rank, const double *cd)
{
  if (rank[a] != rank[b]) return rank[a] < rank[b];
  return cd[a] > cd[b];
}

int rr_nsga2_run(int d, int m, const double *lo, const double *hi, rr_nsga2_eval_fn eval, void *user,
                 const rr_nsga2_opts *o, double *x_out, double *f_out, int *rank_out, rr_error *err)
{
  rr_nsga2_opts def = rr_nsga2_opts_default();
  if (!o) o = &def;
  int N = o->population;
  if (N < 4 || N % 2) return rr_seterr(err, RR_EINVAL, "nsga2: population must be even and >= 4");
  if (d < 1 || m < 1) return rr_seterr(err, RR_EINVAL, "nsga2: need >= 1 variable and objective");
  for (int j = 0; j < d; j++)
    if (!(isfinite(lo[j]) && isfinite(hi[j]) && hi[j] >= lo[j])) return rr_seterr(err, RR_EINVAL, "nsga2: bounds of variable %d", j);
  double pm = o->p_mutation > 0 ? o->p_mutation : 1.0 / d;
  int R = 2 * N;
  double *X = malloc(sizeof(double) * R * d), *F = malloc(sizeof(double) * R * m), *cd = malloc(sizeof(double) * R);
  double *X2 = malloc(sizeof(double) * N * d), *F2 = malloc(sizeof(double) * N * m), *ref = malloc(sizeof(double) * m);
  int *rank = malloc(sizeof(int) * R), *mem = malloc(sizeof(int) * R), *tmp = malloc(sizeof(int) * R), *sel = malloc(sizeof(int) * N);
  int st = RR_OK;
  if (!X || !F || !cd || !X2 || !F2 || !ref || !rank || !mem || !tmp || !sel) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto done; }
  rr_rng rng;
  rr_rng_seed(&rng, o->seed);
  double t0 = now_s();
  long evals = 0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < d; j++) X[i * d + j] = lo[j] + (hi[j] - lo[j]) * rr_rng_uniform(&rng);
  eval(user, N, X, F);
  evals += N;
  sanitize(F, N * m);
  /* hypervolume reference: the worst finite value of each objective in the
     initial population, plus 10% of its range */
  for (int k = 0; k < m; k++) {
    double a = INFINITY, b = -INFINITY;
    for (int i = 0; i < N; i++) if (isfinite(F[i * m + k])) { a = fmin(a, F[i * m + k]); b = fmax(b, F[i * m + k]); }
    ref[k] = isfinite(b) ? b + 0.1 * (b - a + 1e-12) : 1;
  }
  if (rank_crowd(N, m, F, rank, cd, mem, tmp) < 0) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto done; }
  for (int g = 1; g <= o->generations; g++) {
    /* offspring by binary tournament, SBX and polynomial mutation */
    for (int i = 0; i < N; i++) {
      int a = (int)(rr_rng_next(&rng) % N), b = (int)(rr_rng_next(&rng) % N);
      sel[i] = better(a, b, rank, cd) ? a : b;
    }
    for (int i = 0; i < N; i += 2) {
      double *c1 = X2 + i * d, *c2 = X2 + (i + 1) * d;
      memcpy(c1, X + sel[i] * d, sizeof(double) * d);
      memcpy(c2, X + sel[i + 1] * d, sizeof(double) * d);
      if (rr_rng_uniform(&rng) < o->p_crossover)
        for (int j = 0; j < d; j++)
          if (rr_rng_uniform(&rng) < 0.5) sbx(&rng, o->eta_c, lo[j], hi[j], &c1[j], &c2[j]);
      for (int j = 0; j < d; j++) {
        if (rr_rng_uniform(&rng) < pm) c1[j] = poly_mutation(&rng, o->eta_m, lo[j], hi[j], c1[j]);
        if (rr_rng_uniform(&rng) < pm) c2[j] = poly_mutation(&rng, o->eta_m, lo[j], hi[j], c2[j]);
      }
    }
    eval(user, N, X2, F2);
    evals += N;
    sanitize(F2, N * m);
    memcpy(X + N * d, X2, sizeof(double) * N * d);
    memcpy(F + N * m, F2, sizeof(double) * N * m);
    /* environmental selection from parents and offspring */
    int nf = rank_crowd(R, m, F, rank, cd, mem, tmp);
    if (nf < 0) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto done; }
    int taken = 0;
    int *keep = sel;   /* reuse: N entries */
    for (int k = 0; k < nf && taken < N; k++) {
      int c = 0;
      for (int i = 0; i < R; i++) if (rank[i] == k) mem[c++] = i;
      if (taken + c <= N) {
        for (int i = 0; i < c; i++) keep[taken++] = mem[i];
      } else {
        /* the last front by decreasing crowding distance */
        for (int i = 1; i < c; i++) {
          int t = mem[i], j = i;
          while (j > 0 && cd[mem[j - 1]] < cd[t]) { mem[j] = mem[j - 1]; j--; }
          mem[j] = t;
        }
        for (int i = 0; taken < N; i++) keep[taken++] = mem[i];
      }
    }
    for (int i = 0; i < N; i++) {
      memcpy(X2 + i * d, X + keep[i] * d, sizeof(double) * d);
      memcpy(F2 + i * m, F + keep[i] * m, sizeof(double) * m);
    }
    memcpy(X, X2, sizeof(double) * N * d);
    memcpy(F, F2, sizeof(double) * N * m);
    int nf2 = rank_crowd(N, m, F, rank, cd, mem, tmp);
    if (nf2 < 0) { st = rr_seterr(err, RR_ENOMEM, "out of memory"); goto done; }
    if (o->progress) {
      int fs = 0;
      for (int i = 0; i < N; i++) fs += rank[i] == 0;
      double hv = NAN;
      if (o->hv_every > 0 && (g % o->hv_every == 0 || g == o->generations) && m <= 3) {
        int c = 0;
        for (int i = 0; i < N; i++) if (rank[i] == 0) { memcpy(F2 + c * m, F + i * m, sizeof(double) * m); c++; }
        hv = m == 1 ? NAN : rr_hypervolume(c, m, F2, ref);
      }
      o->progress(o->user, g, evals, now_s() - t0, fs, hv);
    }
  }
  memcpy(x_out, X, sizeof(double) * N * d);
  memcpy(f_out, F, sizeof(double) * N * m);
  if (rank_out) memcpy(rank_out, rank, sizeof(int) * N);
done:
  free(X); free(F); free(cd); free(X2); free(F2); free(ref); free(rank); free(mem); free(tmp); free(sel);
  return st;
}
