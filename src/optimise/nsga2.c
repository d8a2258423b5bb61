/* NSGA-II, written from Deb et al. 2002 and the published SBX (Deb & Agrawal
 * 1995) and polynomial mutation formulas. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "railride/nsga2.h"
#include "util/rng.h"
#include "util/internal.h"
#include "util/block.h"

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

/* "b goes before a" for a sort over indices. */
typedef int (*idx_before)(const void *ctx, int b, int a);

/* The one sort here: stable bottom-up merge sort of n indices; tmp: n ints. */
static void merge_sort(int *idx, int n, int *tmp, idx_before before, const void *ctx)
{
  for (int w = 1; w < n; w *= 2) {
    for (int lo = 0; lo < n; lo += 2 * w) {
      int mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n, a = lo, b = mid,
          k = lo;
      while (a < mid && b < hi) tmp[k++] = before(ctx, idx[b], idx[a]) ? idx[b++] : idx[a++];
      while (a < mid) tmp[k++] = idx[a++];
      while (b < hi) tmp[k++] = idx[b++];
    }
    memcpy(idx, tmp, sizeof(int) * (size_t)n);
  }
}

typedef struct lex_order {
  const double *f;
  int m;
} lex_order;
static int lex_before(const void *ctx, int b, int a)
{
  const lex_order *o = ctx;
  return lex_cmp(o->f + (size_t)b * (size_t)o->m, o->f + (size_t)a * (size_t)o->m, o->m) < 0;
}

typedef struct key_order {
  const double *key;
  int descending;
} key_order;
static int key_before(const void *ctx, int b, int a)
{
  const key_order *o = ctx;
  return o->descending ? o->key[b] > o->key[a] : o->key[b] < o->key[a];
}

/* Indices by key[idx] (ascending, or descending), stable. */
static void sort_by_key(int *idx, int cnt, const double *key, int *tmp, int descending)
{
  key_order o = {.key = key, .descending = descending};
  merge_sort(idx, cnt, tmp, key_before, &o);
}

/* Per-front staircase of (f2, f3) minima, f2 ascending and f3 descending,
   for the O(log n) dominance query of three objectives. */
typedef struct stair {
  int *id;
  int n, cap;
} stair;

static int stair_dominated(const stair *st, const double *f, const double *p)
{
  /* the member with the largest f2 <= p2 has the smallest f3 of all such */
  int lo = 0, hi = st->n - 1, best = -1;
  while (lo <= hi) {
    int mid = (lo + hi) / 2;
    if (f[(size_t)st->id[mid] * 3 + 1] <= p[1]) {
      best = mid;
      lo = mid + 1;
    } else
      hi = mid - 1;
  }
  if (best < 0) return 0;
  const double *q = f + (size_t)st->id[best] * 3;
  if (q[2] > p[2]) return 0;
  /* q precedes p lexicographically: it dominates unless the two are equal */
  return q[0] < p[0] || q[1] < p[1] || q[2] < p[2];
}

static int stair_insert(stair *st, const double *f, int id)
{
  const double *p = f + (size_t)id * 3;
  int w = 0;
  for (int i = 0; i < st->n; i++) { /* drop members p weakly dominates in (f2, f3) */
    const double *q = f + (size_t)st->id[i] * 3;
    if (!(q[1] >= p[1] && q[2] >= p[2])) st->id[w++] = st->id[i];
  }
  st->n = w;
  if (st->n == st->cap) {
    int nc = st->cap ? 2 * st->cap : 16;
    int *q = realloc(st->id, sizeof(int) * (size_t)nc);
    if (!q) return -1;
    st->id = q;
    st->cap = nc;
  }
  int pos = 0, lo = 0, hi = st->n;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (f[(size_t)st->id[mid] * 3 + 1] < p[1])
      lo = mid + 1;
    else
      hi = mid;
  }
  pos = lo;
  memmove(st->id + pos + 1, st->id + pos, sizeof(int) * (size_t)(st->n - pos));
  st->id[pos] = id;
  st->n++;
  return 0;
}

/* The fronts' count, or -1 when out of memory. */
static int nondominated_ranks(int n, int m, const double *f, int *rank)
{
  /* ENS-SS (Zhang et al., IEEE TEC 2015): in lexicographic order no point is
     dominated by a later one, so each point joins the first front none of whose
     members dominates it. For two and three objectives the test is a search
     (an earlier q dominates p iff q2 <= p2 and q3 <= p3, q != p); otherwise
     fronts are linked lists through next[] scanned newest first. */
  int *idx = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1)),
      *head = malloc(sizeof(int) * (size_t)(n + 1)),
      *next = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  double *minf2 = malloc(sizeof(double) * (size_t)(n + 1));
  stair *st = m == 3 ? calloc((size_t)n + 1, sizeof(stair)) : NULL;
  if (!idx || !head || !next || !minf2 || (m == 3 && !st)) {
    free(idx);
    free(head);
    free(next);
    free(minf2);
    free(st);
    return -1;
  }
  for (int i = 0; i < n; i++) idx[i] = i;
  lex_order lex = {.f = f, .m = m};
  merge_sort(idx, n, next, lex_before, &lex); /* next: scratch until the fronts use it */
  int nf = 0, fail = 0;
  for (int t = 0; t < n && !fail; t++) {
    int p = idx[t];
    const double *fp = f + (size_t)p * (size_t)m;
    int k = 0;
    for (; k < nf; k++) {
      int dom = 0;
      if (m == 3)
        dom = stair_dominated(&st[k], f, fp);
      else if (m == 2) {
        /* the front member with the least f2 decides; equal points do not dominate */
        const double *q = f + (size_t)head[k] * 2;
        dom = minf2[k] <= fp[1] && (q[0] < fp[0] || minf2[k] < fp[1]);
      } else
        for (int q = head[k]; q >= 0 && !dom; q = next[q])
          dom = dominates(f + (size_t)q * (size_t)m, fp, m);
      if (!dom) break;
    }
    if (k == nf) {
      head[nf] = -1;
      minf2[nf] = INFINITY;
      nf++;
    }
    rank[p] = k;
    if (m == 2) {
      if (fp[1] < minf2[k] || head[k] < 0) {
        minf2[k] = fp[1];
        head[k] = p;
      }
    } else {
      next[p] = head[k];
      head[k] = p;
    }
    if (m == 3 && stair_insert(&st[k], f, p)) fail = 1;
  }
  if (st)
    for (int k = 0; k < nf; k++) free(st[k].id);
  free(st);
  free(idx);
  free(head);
  free(next);
  free(minf2);
  return fail ? -1 : nf;
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

/* Adds p to the 2-D staircase (s1 ascending, s2 descending) unless it is
   dominated; drops the points it dominates. Returns 1 when added. */
static int stair2_add(double *s1, double *s2, int *ns, const double *p)
{
  for (int i = 0; i < *ns; i++)
    if (s1[i] <= p[0] && s2[i] <= p[1]) return 0;
  int w = 0;
  for (int i = 0; i < *ns; i++)
    if (!(p[0] <= s1[i] && p[1] <= s2[i])) {
      s1[w] = s1[i];
      s2[w] = s2[i];
      w++;
    }
  int pos = 0;
  while (pos < w && s1[pos] < p[0]) pos++;
  memmove(s1 + pos + 1, s1 + pos, sizeof(double) * (size_t)(w - pos));
  memmove(s2 + pos + 1, s2 + pos, sizeof(double) * (size_t)(w - pos));
  s1[pos] = p[0];
  s2[pos] = p[1];
  *ns = w + 1;
  return 1;
}

/* m = 2 or 3; -1 when out of memory. */
static double hypervolume(int n, int m, const double *f, const double *ref)
{
  int *idx = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1)),
      *tmp = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  double *s1 = malloc(sizeof(double) * (size_t)(n + 1)),
         *s2 = malloc(sizeof(double) * (size_t)(n + 1)),
         *key = calloc((size_t)(n > 0 ? n : 1), sizeof(double));
  if (!idx || !tmp || !s1 || !s2 || !key) {
    free(idx);
    free(tmp);
    free(s1);
    free(s2);
    free(key);
    return -1;
  }
  int k = 0, ns = 0;
  for (int i = 0; i < n; i++) {
    const double *p = f + (size_t)i * (size_t)m;
    int in = 1;
    for (int j = 0; j < m; j++)
      if (!(p[j] < ref[j])) in = 0;
    if (in) idx[k++] = i;
  }
  double hv = 0;
  if (m == 2) {
    for (int t = 0; t < k; t++) stair2_add(s1, s2, &ns, f + (size_t)idx[t] * 2);
    hv = area2(s1, s2, ns, ref[0], ref[1]);
  } else {
    /* sweep f3 upward: the 2-D staircase of the points seen so far times the slab */
    for (int t = 0; t < k; t++) key[idx[t]] = f[(size_t)idx[t] * 3 + 2];
    sort_by_key(idx, k, key, tmp, 0);
    double area = 0;
    for (int t = 0; t < k; t++) {
      const double *p = f + (size_t)idx[t] * 3;
      if (stair2_add(s1, s2, &ns, p)) area = area2(s1, s2, ns, ref[0], ref[1]);
      double next = t + 1 < k ? f[(size_t)idx[t + 1] * 3 + 2] : ref[2];
      hv += area * (next - p[2]);
    }
  }
  free(idx);
  free(tmp);
  free(s1);
  free(s2);
  free(key);
  return hv;
}

int rr_nondominated_ranks(int n, int m, const double *f, int *rank, int *nfronts, rr_error *err)
{
  if (n < 0 || m < 1)
    return rr_seterr(err, RR_EINVAL, "nondominated ranks: n >= 0, m >= 1 expected");
  int nf = nondominated_ranks(n, m, f, rank);
  if (nf < 0) return rr_seterr(err, RR_ENOMEM, "out of memory");
  if (nfronts) *nfronts = nf;
  return RR_OK;
}

int rr_hypervolume(int n, int m, const double *f, const double *ref, double *hv, rr_error *err)
{
  if (m != 2 && m != 3)
    return rr_seterr(err, RR_EUNSUP, "hypervolume: 2 or 3 objectives, not %d", m);
  double v = hypervolume(n, m, f, ref);
  if (v < 0) return rr_seterr(err, RR_ENOMEM, "out of memory");
  *hv = v;
  return RR_OK;
}

/* crowding distance of the members of one front; col: n doubles of scratch */
static void crowding(const int *mem, int cnt, int m, const double *f, double *cd, int *tmp,
                     int *tmp2, double *col, int n)
{
  for (int i = 0; i < cnt; i++) cd[mem[i]] = 0;
  if (cnt <= 2) {
    for (int i = 0; i < cnt; i++) cd[mem[i]] = INFINITY;
    return;
  }
  (void)n;
  for (int k = 0; k < m; k++) {
    for (int i = 0; i < cnt; i++) {
      tmp[i] = mem[i];
      col[mem[i]] = f[(size_t)mem[i] * (size_t)m + (size_t)k];
    }
    sort_by_key(tmp, cnt, col, tmp2, 0);
    double lo = col[tmp[0]], hi = col[tmp[cnt - 1]];
    cd[tmp[0]] = cd[tmp[cnt - 1]] = INFINITY;
    if (!(hi > lo)) continue;
    for (int i = 1; i < cnt - 1; i++) cd[tmp[i]] += (col[tmp[i + 1]] - col[tmp[i - 1]]) / (hi - lo);
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
  if (rr_rng_uniform(r) < 0.5) {
    *a = c2;
    *b = c1;
  } else {
    *a = c1;
    *b = c2;
  }
}

static double poly_mutation(rr_rng *r, double eta, double lo, double hi, double y)
{
  if (hi <= lo) return y;
  double d1 = (y - lo) / (hi - lo), d2 = (hi - y) / (hi - lo), u = rr_rng_uniform(r),
         mp = 1.0 / (eta + 1), dq;
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
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void sanitize(double *f, int n)
{
  for (int i = 0; i < n; i++)
    if (isnan(f[i])) f[i] = INFINITY;
}

/* Constrained ranks (Deb 2000): the feasible designs (cv = 0) by
   non-domination among themselves, then the infeasible ones one front each
   in order of total violation (equal violations share a front). fc (n x m),
   idx and r2 (n) are scratch. */
static int constrained_ranks(int n, int m, const double *f, const double *cv, int *rank, double *fc,
                             int *idx, int *r2, int *tmp)
{
  int nfeas = 0, nf = 0;
  for (int i = 0; i < n; i++)
    if (cv[i] == 0) {
      memcpy(fc + (size_t)nfeas * (size_t)m, f + (size_t)i * (size_t)m, sizeof(double) * (size_t)m);
      idx[nfeas++] = i;
    }
  if (nfeas && (nf = nondominated_ranks(nfeas, m, fc, r2)) < 0) return -1;
  for (int k = 0; k < nfeas; k++) rank[idx[k]] = r2[k];
  int ninf = 0;
  for (int i = 0; i < n; i++)
    if (cv[i] != 0) idx[ninf++] = i;
  sort_by_key(idx, ninf, cv, tmp, 0);
  for (int k = 0; k < ninf; k++) {
    if (k == 0 || cv[idx[k]] != cv[idx[k - 1]]) nf++;
    rank[idx[k]] = nf - 1;
  }
  return nf;
}

static int better(int a, int b, const int *rank, const double *cd)
{
  if (rank[a] != rank[b]) return rank[a] < rank[b];
  return cd[a] > cd[b];
}

/* Objectives and total violations from an evaluation's rows (m + nc each). */
static void split_eval(const double *E, int n, int m, int nc, const int *who, double *F, double *CV)
{
  for (int r = 0; r < n; r++) {
    size_t i = (size_t)(who ? who[r] : r);
    memcpy(F + i * (size_t)m, E + (size_t)r * (size_t)(m + nc), sizeof(double) * (size_t)m);
    sanitize(F + i * (size_t)m, m);
    if (!nc) continue;
    double v = 0;
    for (int k = 0; k < nc; k++) {
      double g = E[(size_t)r * (size_t)(m + nc) + (size_t)m + (size_t)k];
      v += isnan(g) ? INFINITY : fmax(g, 0);
    }
    CV[i] = v;
  }
}

/* The run's state between generations, as a checkpoint file: a header, the
   generator's state, the caller's fingerprint of the run, the hypervolume
   reference, the bounds (a resume must be of the same problem) and the
   population with its ranks and crowding. */
#define CKPT_MAGIC "RRNSGA2"
#define CKPT_VERSION 3 /* 3: the run's elapsed seconds after the evaluations */
typedef struct nsga_state {
  int d, m, nc, N, g;
  int generations; /* the run's last generation: a resume's g may not pass it */
  long evals;
  double elapsed_s; /* the run's wall time so far, resumed runs included */
  uint64_t seed;
  rr_rng *rng;
  double *ref, *X, *F, *CV, *cd;
  const double *lo, *hi;
  int *rank;
  const rr_nsga2_fingerprint *fp;
} nsga_state;

uint64_t rr_hash_bytes(uint64_t h, const void *p, size_t n)
{
  const unsigned char *c = p;
  for (size_t i = 0; i < n; i++) h = (h ^ c[i]) * 1099511628211ULL;
  return h;
}

static int ckpt_io(FILE *f, void *p, size_t size, size_t n, int writing)
{
  return n == 0 || (writing ? fwrite(p, size, n, f) : fread(p, size, n, f)) == n ? 0 : -1;
}

/* Every field in file order (one list for writing and reading). */
static int ckpt_fields(FILE *f, nsga_state *s, int32_t *head, int64_t *ev, int32_t *nfp,
                       uint64_t *fp, double *lo, double *hi, int w)
{
  size_t N = (size_t)s->N, d = (size_t)s->d, m = (size_t)s->m;
  return ckpt_io(f, head, sizeof head[0], 6, w) || ckpt_io(f, ev, sizeof *ev, 1, w) ||
         ckpt_io(f, &s->elapsed_s, sizeof s->elapsed_s, 1, w) ||
         ckpt_io(f, &s->seed, sizeof s->seed, 1, w) ||
         ckpt_io(f, s->rng->s, sizeof(uint64_t), 4, w) || ckpt_io(f, nfp, sizeof *nfp, 1, w) ||
         *nfp < 0 || *nfp > RR_NSGA2_FP_MAX || ckpt_io(f, fp, sizeof *fp, (size_t)*nfp, w) ||
         ckpt_io(f, s->ref, sizeof(double), m, w) || ckpt_io(f, lo, sizeof(double), d, w) ||
         ckpt_io(f, hi, sizeof(double), d, w) || ckpt_io(f, s->X, sizeof(double), N * d, w) ||
         ckpt_io(f, s->F, sizeof(double), N * m, w) ||
         (s->nc && ckpt_io(f, s->CV, sizeof(double), N, w)) ||
         ckpt_io(f, s->cd, sizeof(double), N, w) || ckpt_io(f, s->rank, sizeof(int), N, w);
}

/* Written to a fresh scratch file beside the target (mkstemp: a planted
   name or symlink is never followed), fsync'd, then renamed over it. */
static int state_save(const char *path, nsga_state *s, rr_error *err)
{
  char tmp[4096 + 8];
  if (snprintf(tmp, sizeof tmp, "%s.XXXXXX", path) >= (int)sizeof tmp)
    return rr_seterr(err, RR_EINVAL, "nsga2: checkpoint name too long");
  int fd = mkstemp(tmp);
  FILE *f = fd >= 0 ? fdopen(fd, "wb") : NULL;
  if (!f) {
    if (fd >= 0) {
      close(fd);
      unlink(tmp);
    }
    return rr_seterr(err, RR_EIO, "nsga2: cannot write the checkpoint beside %s", path);
  }
  int32_t head[6] = {CKPT_VERSION, s->d, s->m, s->nc, s->N, s->g}, nfp = s->fp ? s->fp->n : 0;
  int64_t ev = s->evals;
  uint64_t fp[RR_NSGA2_FP_MAX] = {0};
  for (int i = 0; i < nfp; i++) fp[i] = s->fp->part[i];
  errno = 0;
  int bad = ckpt_io(f, CKPT_MAGIC, 1, 8, 1) ||
            ckpt_fields(f, s, head, &ev, &nfp, fp, (double *)s->lo, (double *)s->hi, 1) ||
            fflush(f) || fsync(fileno(f));
  int e = errno;
  if (fclose(f) || bad) {
    e = e ? e : errno;
    unlink(tmp);
    return rr_seterr(err, RR_EIO, "nsga2: writing the checkpoint %s failed: %s", path,
                     strerror(e ? e : EIO));
  }
  if (rename(tmp, path)) {
    unlink(tmp);
    return rr_seterr(err, RR_EIO, "nsga2: cannot rename the checkpoint to %s", path);
  }
  return RR_OK;
}

/* What a loaded state must hold: a generation within the run, a live
   generator, finite reference, designs finite and within their bounds,
   objectives and violations not NaN, ranks within the population. */
static int state_valid(const nsga_state *s, const int32_t *head, int64_t ev)
{
  size_t N = (size_t)s->N;
  if (!(head[5] >= 0 && head[5] <= s->generations)) return 0;
  if (ev != (int64_t)(head[5] + 1) * (int64_t)N) return 0; /* N a generation, and the first */
  if (!(s->elapsed_s >= 0 && s->elapsed_s < 1e12)) return 0;
  if (!(s->rng->s[0] | s->rng->s[1] | s->rng->s[2] | s->rng->s[3])) return 0;
  for (int k = 0; k < s->m; k++)
    if (!isfinite(s->ref[k])) return 0;
  for (size_t i = 0; i < N; i++) {
    for (int j = 0; j < s->d; j++) {
      double x = s->X[i * (size_t)s->d + (size_t)j];
      if (!(x >= s->lo[j] && x <= s->hi[j])) return 0;
    }
    for (int k = 0; k < s->m; k++) {
      double fv = s->F[i * (size_t)s->m + (size_t)k];
      if (isnan(fv) || fv == -INFINITY) return 0;
    }
    if ((s->nc && !(s->CV[i] >= 0)) || !(s->cd[i] >= 0) || s->rank[i] < 0 || s->rank[i] >= s->N)
      return 0;
  }
  return 1;
}

/* The parts of the run that differ, by name, into buf. */
static void fp_diff(const rr_nsga2_fingerprint *fp, int n, const uint64_t *got, char *buf,
                    size_t len)
{
  buf[0] = 0;
  if (!fp || n != fp->n) {
    snprintf(buf, len, "the run's description");
    return;
  }
  for (int i = 0; i < n; i++)
    if (got[i] != fp->part[i]) {
      size_t l = strlen(buf);
      snprintf(buf + l, len - l, "%s%s", l ? ", " : "", fp->name[i] ? fp->name[i] : "?");
    }
}

static int state_load(const char *path, nsga_state *s, rr_error *err)
{
  FILE *f = fopen(path, "rb");
  if (!f) return rr_seterr(err, RR_EIO, "%s: cannot read the checkpoint", path);
  char magic[8];
  int32_t head[6], nfp = 0;
  int64_t ev;
  uint64_t seed = s->seed, fp[RR_NSGA2_FP_MAX];
  double lo[64], hi[64];
  int st = RR_OK;
  if (ckpt_io(f, magic, 1, 8, 0) || memcmp(magic, CKPT_MAGIC, 8) ||
      ckpt_io(f, head, sizeof head[0], 1, 0) || head[0] != CKPT_VERSION)
    st = rr_seterr(err, RR_EPARSE, "%s: not a railride NSGA-II checkpoint (version %d)", path,
                   CKPT_VERSION);
  else if (ckpt_io(f, head + 1, sizeof head[0], 5, 0) || head[1] != s->d || head[2] != s->m ||
           head[3] != s->nc || head[4] != s->N || s->d > 64)
    st = rr_seterr(err, RR_EINVAL,
                   "%s: a checkpoint of another problem (variables, objectives, constraints or "
                   "population differ)",
                   path);
  else if (fseek(f, 8, SEEK_SET) || ckpt_fields(f, s, head, &ev, &nfp, fp, lo, hi, 0) ||
           fgetc(f) != EOF)
    st = rr_seterr(err, RR_EPARSE, "%s: the checkpoint is cut short or damaged", path);
  else if (s->seed != seed || memcmp(lo, s->lo, sizeof(double) * (size_t)s->d) ||
           memcmp(hi, s->hi, sizeof(double) * (size_t)s->d))
    st = rr_seterr(err, RR_EINVAL,
                   "%s: a checkpoint of another run (seed or variable bounds differ)", path);
  else if (nfp != (s->fp ? s->fp->n : 0) ||
           (nfp && memcmp(fp, s->fp->part, sizeof(uint64_t) * (size_t)nfp))) {
    char what[256];
    fp_diff(s->fp, nfp, fp, what, sizeof what);
    st = rr_seterr(err, RR_EINVAL, "%s: a checkpoint of another run: %s changed", path, what);
  } else if (!state_valid(s, head, ev))
    st = rr_seterr(err, RR_EPARSE, "%s: the checkpoint is damaged (a value out of range)", path);
  fclose(f);
  s->seed = seed;
  if (!st) {
    s->g = head[5];
    s->evals = (long)ev;
  }
  return st;
}

/* The run's arrays: parents and offspring together (R = 2N rows) and the
   sorting's scratch. */
typedef struct nsga_work {
  int d, m, nc, N, R;
  double *X, *F, *cd, *X2, *F2, *ref, *col, *E, *CV, *fc, *Xe;
  int *rank, *mem, *tmp, *sel, *tmp2, *start, *idx, *r2, *who;
  long evaluated; /* designs passed to eval */
  char *block;    /* every array above, one allocation (block.h) */
} nsga_work;

static void work_free(nsga_work *w) { free(w->block); }

/* The arrays (block.h: called to size, then to carve); the constrained
   domination's (CV, fc, idx, r2) only with constraints. */
static void work_layout(nsga_work *w, rr_block *b)
{
  size_t R = (size_t)w->R, n = (size_t)w->N, d = (size_t)w->d, m = (size_t)w->m;
  const size_t db = sizeof(double), ib = sizeof(int);
  w->X = rr_block_take(b, R * d, db);
  w->F = rr_block_take(b, R * m, db);
  w->cd = rr_block_take(b, R, db);
  w->X2 = rr_block_take(b, n * d, db);
  w->F2 = rr_block_take(b, n * m, db);
  w->ref = rr_block_take(b, m, db);
  w->col = rr_block_take(b, R, db);
  w->E = rr_block_take(b, n * (m + (size_t)w->nc), db);
  w->rank = rr_block_take(b, R, ib);
  w->mem = rr_block_take(b, R, ib);
  w->tmp = rr_block_take(b, R + 1, ib);
  w->sel = rr_block_take(b, n, ib);
  w->tmp2 = rr_block_take(b, R, ib);
  w->start = rr_block_take(b, R + 1, ib);
  w->Xe = rr_block_take(b, n * d, db);
  w->who = rr_block_take(b, n, ib);
  if (w->nc) { /* Deb's constrained domination */
    w->CV = rr_block_take(b, R, db);
    w->fc = rr_block_take(b, R * m, db);
    w->idx = rr_block_take(b, R, ib);
    w->r2 = rr_block_take(b, R, ib);
  }
}

static int work_alloc(nsga_work *w, int d, int m, int nc, int N, rr_error *err)
{
  *w = (nsga_work){.d = d, .m = m, .nc = nc, .N = N, .R = 2 * N};
  rr_block b = {0};
  work_layout(w, &b);
  if (rr_block_alloc(&b)) return rr_seterr(err, RR_ENOMEM, "out of memory");
  w->block = b.base;
  work_layout(w, &b);
  return RR_OK;
}

/* Ranks and crowding of the first n of the population; fronts gathered in
   one pass (mem: the indices ordered by front, start: nf + 1 offsets). With
   constraints, constrained ranks (fc, idx, r2 scratch). The number of
   fronts, or -status. */
static int rank_all(nsga_work *w, int n, rr_error *err)
{
  int m = w->m;
  int nf = w->CV ? constrained_ranks(n, m, w->F, w->CV, w->rank, w->fc, w->idx, w->r2, w->tmp)
                 : nondominated_ranks(n, m, w->F, w->rank);
  if (nf < 0) return -rr_seterr(err, RR_ENOMEM, "out of memory");
  int *start = w->start, *rank = w->rank;
  for (int k = 0; k <= nf; k++) start[k] = 0;
  for (int i = 0; i < n; i++) start[rank[i] + 1]++;
  for (int k = 0; k < nf; k++) start[k + 1] += start[k];
  for (int k = 0; k < nf; k++) w->tmp[k] = start[k];
  for (int i = 0; i < n; i++) w->mem[w->tmp[rank[i]]++] = i;
  for (int k = 0; k < nf; k++)
    crowding(w->mem + start[k], start[k + 1] - start[k], m, w->F, w->cd, w->tmp, w->tmp2, w->col,
             n);
  return nf;
}

/* n designs X evaluated into the rows who[] (NULL: 0..n-1) of F and of the
   violations CV; the callback's failure ends the run. */
static int evaluate(nsga_work *w, rr_nsga2_eval_fn eval, void *user, int n, const double *X,
                    const int *who, double *F, double *CV, rr_error *err)
{
  int r = n > 0 ? eval(user, n, X, w->E) : 0;
  if (r == RR_ESTOPPED) return rr_seterr(err, RR_ESTOPPED, "nsga2: stopped during a generation");
  if (r) return rr_seterr(err, RR_EINVAL, "nsga2: the evaluation failed (callback status %d)", r);
  split_eval(w->E, n, w->m, w->nc, who, F, CV);
  w->evaluated += n;
  return RR_OK;
}

/* The parent (row of X) whose copy bit for bit offspring i is, or -1: its
   two parents are the tournament's picks for its pair. */
static int copy_of(const nsga_work *w, int i)
{
  size_t d = (size_t)w->d, row = sizeof(double) * d;
  const double *c = w->X2 + (size_t)i * d;
  int a = w->sel[i & ~1], b = w->sel[i | 1];
  if (!memcmp(c, w->X + (size_t)a * d, row)) return a;
  return memcmp(c, w->X + (size_t)b * d, row) ? -1 : b;
}

/* The offspring X2 into F2 and CV's second half: a parent's copy takes the
   parent's values (an evaluation would repeat them), the others go to eval
   in one call. */
static int evaluate_offspring(nsga_work *w, rr_nsga2_eval_fn eval, void *user, int copies,
                              rr_error *err)
{
  size_t N = (size_t)w->N, d = (size_t)w->d, m = (size_t)w->m;
  double *CV2 = w->CV ? w->CV + N : NULL;
  int n = 0;
  for (size_t i = 0; i < N; i++) {
    int p = copies ? -1 : copy_of(w, (int)i);
    if (p < 0) {
      memcpy(w->Xe + (size_t)n * d, w->X2 + i * d, sizeof(double) * d);
      w->who[n++] = (int)i;
      continue;
    }
    memcpy(w->F2 + i * m, w->F + (size_t)p * m, sizeof(double) * m);
    if (CV2) CV2[i] = w->CV[p];
  }
  return evaluate(w, eval, user, n, w->Xe, w->who, w->F2, CV2, err);
}

/* The initial population, uniform within the bounds, evaluated and ranked;
   the hypervolume reference: the worst finite value of each objective in it,
   plus 10% of its range. */
static int initial_population(nsga_work *w, const double *lo, const double *hi, rr_rng *rng,
                              rr_nsga2_eval_fn eval, void *user, rr_error *err)
{
  int N = w->N, d = w->d, m = w->m;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < d; j++) w->X[i * d + j] = lo[j] + (hi[j] - lo[j]) * rr_rng_uniform(rng);
  int st = evaluate(w, eval, user, N, w->X, NULL, w->F, w->CV, err);
  if (st) return st;
  for (int k = 0; k < m; k++) {
    double a = INFINITY, b = -INFINITY;
    for (int i = 0; i < N; i++)
      if (isfinite(w->F[i * m + k])) {
        a = fmin(a, w->F[i * m + k]);
        b = fmax(b, w->F[i * m + k]);
      }
    w->ref[k] = isfinite(b) ? b + 0.1 * (b - a + 1e-12) : 1;
  }
  st = rank_all(w, N, err);
  return st < 0 ? -st : RR_OK;
}

/* Offspring into X2: binary tournament, SBX and polynomial mutation. */
static void make_offspring(nsga_work *w, const double *lo, const double *hi, rr_rng *rng,
                           const rr_nsga2_opts *o)
{
  int N = w->N, d = w->d;
  double pm = o->p_mutation > 0 ? o->p_mutation : 1.0 / d;
  for (int i = 0; i < N; i++) {
    int a = (int)(rr_rng_next(rng) % (uint64_t)N), b = (int)(rr_rng_next(rng) % (uint64_t)N);
    w->sel[i] = better(a, b, w->rank, w->cd) ? a : b;
  }
  for (int i = 0; i < N; i += 2) {
    double *c1 = w->X2 + i * d, *c2 = w->X2 + (i + 1) * d;
    memcpy(c1, w->X + w->sel[i] * d, sizeof(double) * (size_t)d);
    memcpy(c2, w->X + w->sel[i + 1] * d, sizeof(double) * (size_t)d);
    if (rr_rng_uniform(rng) < o->p_crossover)
      for (int j = 0; j < d; j++)
        if (rr_rng_uniform(rng) < 0.5) sbx(rng, o->eta_c, lo[j], hi[j], &c1[j], &c2[j]);
    for (int j = 0; j < d; j++) {
      if (rr_rng_uniform(rng) < pm) c1[j] = poly_mutation(rng, o->eta_m, lo[j], hi[j], c1[j]);
      if (rr_rng_uniform(rng) < pm) c2[j] = poly_mutation(rng, o->eta_m, lo[j], hi[j], c2[j]);
    }
  }
}

/* Environmental selection from parents and offspring (rows 0..2N-1, ranked):
   whole fronts while they fit, the last by decreasing crowding distance.
   Survivors keep the ranks and crowding distances of the combined sort:
   whole earlier fronts are kept, so no survivor's rank changes (Deb et al.). */
static void select_survivors(nsga_work *w, int nf)
{
  int N = w->N, d = w->d, m = w->m, taken = 0;
  int *keep = w->sel; /* reuse: N entries */
  for (int k = 0; k < nf && taken < N; k++) {
    int *fm = w->mem + w->start[k], c = w->start[k + 1] - w->start[k];
    if (taken + c <= N) {
      for (int i = 0; i < c; i++) keep[taken++] = fm[i];
    } else {
      sort_by_key(fm, c, w->cd, w->tmp2, 1);
      for (int i = 0; taken < N; i++) keep[taken++] = fm[i];
    }
  }
  for (int i = 0; i < N; i++) {
    memcpy(w->X2 + i * d, w->X + keep[i] * d, sizeof(double) * (size_t)d);
    memcpy(w->F2 + i * m, w->F + keep[i] * m, sizeof(double) * (size_t)m);
    w->tmp[i] = w->rank[keep[i]];
    w->col[i] = w->cd[keep[i]];
    if (w->CV) w->fc[i] = w->CV[keep[i]]; /* fc: scratch for the survivors' violations */
  }
  if (w->CV) memcpy(w->CV, w->fc, sizeof(double) * (size_t)N);
  memcpy(w->X, w->X2, sizeof(double) * (size_t)N * (size_t)d);
  memcpy(w->F, w->F2, sizeof(double) * (size_t)N * (size_t)m);
  memcpy(w->rank, w->tmp, sizeof(int) * (size_t)N);
  memcpy(w->cd, w->col, sizeof(double) * (size_t)N);
}

/* Generation g's report to the progress callback: the front's size and, every
   hv_every generations (and the last), its feasible members' hypervolume.
   Nonzero: the callback asks to stop. */
static int report(nsga_work *w, const rr_nsga2_opts *o, int g, long evals, double seconds)
{
  int N = w->N, m = w->m, fs = 0;
  for (int i = 0; i < N; i++) fs += w->rank[i] == 0;
  double hv = NAN;
  if (o->hv_every > 0 && (g % o->hv_every == 0 || g == o->generations) && m <= 3) {
    int c = 0;
    for (int i = 0; i < N; i++)
      if (w->rank[i] == 0 && (!w->CV || w->CV[i] == 0)) {
        memcpy(w->F2 + c * m, w->F + i * m, sizeof(double) * (size_t)m);
        c++;
      }
    hv = m == 1 ? NAN : hypervolume(c, m, w->F2, w->ref);
  }
  return o->progress(o->user, g, evals, seconds, fs, hv);
}

static int check_args(int d, int m, const double *lo, const double *hi, int N, rr_error *err)
{
  if (N < 4 || N % 2) return rr_seterr(err, RR_EINVAL, "nsga2: population must be even and >= 4");
  if (d < 1 || m < 1) return rr_seterr(err, RR_EINVAL, "nsga2: need >= 1 variable and objective");
  for (int j = 0; j < d; j++)
    if (!(isfinite(lo[j]) && isfinite(hi[j]) && hi[j] >= lo[j]))
      return rr_seterr(err, RR_EINVAL, "nsga2: bounds of variable %d", j);
  return RR_OK;
}

int rr_nsga2_run(int d, int m, const double *lo, const double *hi, rr_nsga2_eval_fn eval,
                 void *user, const rr_nsga2_opts *o, double *x_out, double *f_out, int *rank_out,
                 rr_error *err)
{
  rr_nsga2_opts def = rr_nsga2_opts_default();
  if (!o) o = &def;
  int N = o->population, st = check_args(d, m, lo, hi, N, err);
  if (st) return st;
  nsga_work w;
  if ((st = work_alloc(&w, d, m, o->ncon > 0 ? o->ncon : 0, N, err))) {
    work_free(&w);
    return st;
  }
  rr_rng rng;
  rr_rng_seed(&rng, o->seed);
  double t0 = now_s();
  nsga_state ck = {.d = d,
                   .m = m,
                   .nc = w.nc,
                   .N = N,
                   .seed = o->seed,
                   .rng = &rng,
                   .ref = w.ref,
                   .X = w.X,
                   .F = w.F,
                   .CV = w.CV,
                   .cd = w.cd,
                   .lo = lo,
                   .hi = hi,
                   .rank = w.rank,
                   .generations = o->generations,
                   .fp = &o->fingerprint};
  if (o->resume)
    st = state_load(o->resume, &ck, err);
  else {
    st = initial_population(&w, lo, hi, &rng, eval, user, err);
    ck.evals = N;
  }
  double before_s = ck.elapsed_s; /* a resumed run's clock goes on from its checkpoint */
  if (o->generations_done) *o->generations_done = ck.g;
  for (int g = ck.g + 1; g <= o->generations && !st; g++) {
    make_offspring(&w, lo, hi, &rng, o);
    if ((st = evaluate_offspring(&w, eval, user, o->evaluate_copies, err))) {
      if (st == RR_ESTOPPED) st = RR_OK; /* the partial generation dropped: the last whole one */
      break;
    }
    ck.evals += N;
    memcpy(w.X + N * d, w.X2, sizeof(double) * (size_t)N * (size_t)d);
    memcpy(w.F + N * m, w.F2, sizeof(double) * (size_t)N * (size_t)m);
    int nf = rank_all(&w, w.R, err);
    if (nf < 0) {
      st = -nf;
      break;
    }
    select_survivors(&w, nf);
    if (o->generations_done) *o->generations_done = g;
    ck.g = g;
    ck.elapsed_s = before_s + (now_s() - t0);
    /* the checkpoint before the report: a stop then leaves this generation's state */
    if (o->checkpoint && (st = state_save(o->checkpoint, &ck, err))) break;
    if (o->progress && report(&w, o, g, ck.evals, ck.elapsed_s)) break;
  }
  if (!st) {
    memcpy(x_out, w.X, sizeof(double) * (size_t)N * (size_t)d);
    memcpy(f_out, w.F, sizeof(double) * (size_t)N * (size_t)m);
    if (rank_out) memcpy(rank_out, w.rank, sizeof(int) * (size_t)N);
    if (o->cv_out && w.CV)
      memcpy(o->cv_out, w.CV, sizeof(double) * (size_t)N);
    else if (o->cv_out)
      memset(o->cv_out, 0, sizeof(double) * (size_t)N);
  }
  if (o->evaluated) *o->evaluated = w.evaluated;
  work_free(&w);
  return st;
}
