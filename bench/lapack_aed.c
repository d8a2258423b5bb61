#define _GNU_SOURCE
/* Would aggressive early deflation (AED) pay on railride's state matrices?
 *
 * LAPACK switches from dlahqr (the double-shift QR railride's rr_hqr follows)
 * to dlaqr0 (multishift sweeps + AED) from order 75 up. This program forces
 * LAPACK's own dlaqr0 below that crossover, on the 9 robust points of the
 * default vehicle (40 x 40), by answering its tuning query (iparmq) itself,
 * and counts and times the parts by wrapping dlaqr5 (the sweeps) and dlahqr
 * (the windows' Schur factorisations). Measurement only: glibc's RTLD_NEXT
 * interposition, LAPACK's Fortran symbols from the OpenBLAS it links.
 *   build/bench/lapack_aed [REPS]
 */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "railride/railride.h"
#include "bench_util.h"

enum { NPTS = 9, NMAX = 64, LWORK = 8192 };

/* The tuning answers in force: NMIN (12), NW (13), NS (15); <= 0 asks LAPACK. */
static int g_nmin = 75, g_nw, g_ns;
/* Per-configuration counters, reset by run_config. */
static long g_sweeps, g_steps, g_windows, g_window_rows;
static double g_sweep_s, g_window_s;
/* dlahqr's eigenvalues at each point, once the first configuration has run. */
static double g_ref_wr[NPTS][NMAX], g_ref_wi[NPTS][NMAX];
static int g_have_ref;

typedef int iparmq_fn(int *, char *, char *, int *, int *, int *, int *, size_t, size_t);
typedef void dlaqr5_fn(int *, int *, int *, int *, int *, int *, int *, double *, double *,
                       double *, int *, int *, int *, double *, int *, double *, int *, double *,
                       int *, int *, double *, int *, int *, double *, int *);
typedef void dlahqr_fn(int *, int *, int *, int *, int *, double *, int *, double *, double *,
                       int *, int *, double *, int *, int *);
void dgehrd_(int *, int *, int *, double *, int *, double *, double *, int *, int *);
void dhseqr_(char *, char *, int *, int *, int *, double *, int *, double *, double *, double *,
             int *, double *, int *, int *, size_t, size_t);

/* The next definition of name (LAPACK's), as a function pointer. */
static void *next_symbol(const char *name)
{
  void *p = dlsym(RTLD_NEXT, name);
  if (!p) {
    fprintf(stderr, "lapack_aed: %s not found\n", name);
    exit(1);
  }
  return p;
}

int iparmq_(int *ispec, char *name, char *opts, int *n, int *ilo, int *ihi, int *lwork,
            size_t lname, size_t lopts)
{
  static iparmq_fn *real;
  if (!real) memcpy(&real, &(void *){next_symbol("iparmq_")}, sizeof real);
  if (*ispec == 12) return g_nmin;
  if (*ispec == 13 && g_nw > 0) return g_nw;
  if (*ispec == 15 && g_ns > 0) return g_ns;
  return real(ispec, name, opts, n, ilo, ihi, lwork, lname, lopts);
}

void dlaqr5_(int *wantt, int *wantz, int *kacc22, int *n, int *ktop, int *kbot, int *nshfts,
             double *sr, double *si, double *h, int *ldh, int *iloz, int *ihiz, double *z, int *ldz,
             double *v, int *ldv, double *u, int *ldu, int *nv, double *wv, int *ldwv, int *nh,
             double *wh, int *ldwh)
{
  static dlaqr5_fn *real;
  if (!real) memcpy(&real, &(void *){next_symbol("dlaqr5_")}, sizeof real);
  g_sweeps++;
  g_steps += (long)(*nshfts / 2) * (*kbot - *ktop + 1); /* bulges x rows chased */
  double t0 = bench_now();
  real(wantt, wantz, kacc22, n, ktop, kbot, nshfts, sr, si, h, ldh, iloz, ihiz, z, ldz, v, ldv, u,
       ldu, nv, wv, ldwv, nh, wh, ldwh);
  g_sweep_s += bench_now() - t0;
}

void dlahqr_(int *wantt, int *wantz, int *n, int *ilo, int *ihi, double *h, int *ldh, double *wr,
             double *wi, int *iloz, int *ihiz, double *z, int *ldz, int *info)
{
  static dlahqr_fn *real;
  if (!real) memcpy(&real, &(void *){next_symbol("dlahqr_")}, sizeof real);
  g_windows++;
  g_window_rows += *ihi - *ilo + 1;
  double t0 = bench_now();
  real(wantt, wantz, n, ilo, ihi, h, ldh, wr, wi, iloz, ihiz, z, ldz, info);
  g_window_s += bench_now() - t0;
}

/* The robust points' Hessenberg forms (column-major, n x n each). */
static int hessenberg_points(double *H, int *n_out)
{
  rr_vehicle v;
  rr_model *m;
  rr_error e;
  rr_vehicle_default(&v);
  if (rr_model_from_vehicle(&v, &m, &e)) return fprintf(stderr, "%s\n", e.msg), 1;
  int n = rr_model_state_size(m), one = 1, info, lw = LWORK;
  double tau[NMAX], work[LWORK], A[NMAX * NMAX];
  for (int p = 0; p < NPTS && n <= NMAX; p++) {
    double kmh = p == 0 ? 250 : 350, lambda = p == 0 ? 0.05 : 0.05 * p;
    if (rr_model_set_operating(m, kmh / RR_KMH, lambda, &e) || rr_model_state_matrix(m, 0, A, &e))
      return fprintf(stderr, "%s\n", e.msg), rr_model_free(m), 1;
    double *h = H + (size_t)p * n * n;
    for (int i = 0; i < n; i++) /* row-major -> column-major */
      for (int j = 0; j < n; j++) h[i + j * n] = A[i * n + j];
    dgehrd_(&n, &one, &n, h, &n, tau, work, &lw, &info);
    for (int j = 0; j < n; j++)
      for (int i = j + 2; i < n; i++) h[i + j * n] = 0;
  }
  rr_model_free(m);
  *n_out = n;
  return n > NMAX;
}

/* The eigenvalues of H (n x n Hessenberg) into wr, wi; H is overwritten. */
static void eigenvalues(int n, double *H, double *wr, double *wi)
{
  int one = 1, info, lw = LWORK;
  double work[LWORK], z[1];
  dhseqr_("E", "N", &n, &one, &n, H, &n, wr, wi, z, &one, work, &lw, &info, 1, 1);
  if (info) fprintf(stderr, "lapack_aed: dhseqr info %d\n", info);
}

/* The largest distance from an eigenvalue in (wr, wi) to the nearest in
   (rr, ri), relative to the largest modulus. */
static double set_distance(int n, const double *wr, const double *wi, const double *rr,
                           const double *ri)
{
  double worst = 0, scale = 0;
  for (int i = 0; i < n; i++) {
    double d = INFINITY;
    for (int j = 0; j < n; j++) d = fmin(d, hypot(wr[i] - rr[j], wi[i] - ri[j]));
    worst = fmax(worst, d);
    scale = fmax(scale, hypot(rr[i], ri[i]));
  }
  return worst / scale;
}

/* One configuration: best of 5 x reps over the 9 points, per solve. */
static void run_config(const char *label, int nmin, int nw, int ns, int n, const double *H,
                       int reps)
{
  static double W[NMAX * NMAX], wr[NPTS][NMAX], wi[NPTS][NMAX];
  g_nmin = nmin, g_nw = nw, g_ns = ns;
  double best = INFINITY, dist = 0;
  for (int r = 0; r < 5; r++) {
    g_sweeps = g_steps = g_windows = g_window_rows = 0;
    g_sweep_s = g_window_s = 0;
    double t0 = bench_now();
    for (int k = 0; k < reps; k++)
      for (int p = 0; p < NPTS; p++) {
        memcpy(W, H + (size_t)p * n * n, sizeof(double) * n * n);
        eigenvalues(n, W, wr[p], wi[p]);
      }
    best = fmin(best, (bench_now() - t0) / reps / NPTS);
  }
  for (int p = 0; g_have_ref && p < NPTS; p++)
    dist = fmax(dist, set_distance(n, wr[p], wi[p], g_ref_wr[p], g_ref_wi[p]));
  double solves = (double)reps * NPTS;
  printf("%-28s %7.1f us a solve", label, 1e6 * best);
  if (g_sweeps) /* dlaqr0 ran: its sweeps, its windows, its answers */
    printf(" | sweeps %5.1f, bulge steps %6.1f, %6.1f us | windows %5.1f of order %4.1f, "
           "%6.1f us | eigenvalues within %.1e of dlahqr's",
           g_sweeps / solves, g_steps / solves, 1e6 * g_sweep_s / solves, g_windows / solves,
           (double)g_window_rows / g_windows, 1e6 * g_window_s / solves, dist);
  printf("\n");
  if (!g_have_ref) { /* the first configuration is the reference */
    memcpy(g_ref_wr, wr, sizeof wr);
    memcpy(g_ref_wi, wi, sizeof wi);
    g_have_ref = 1;
  }
}

int main(int argc, char **argv)
{
  static double H[NPTS * NMAX * NMAX];
  int n, reps = argc > 1 ? atoi(argv[1]) : 400;
  openblas_set_num_threads(1);
  if (reps < 1 || hessenberg_points(H, &n)) return 1;
  printf("LAPACK's eigenvalues-only QR on the default vehicle's %d x %d state matrices "
         "(9 robust points), one core, %d x 9 solves, best of 5:\n",
         n, n, reps);
  run_config("dlahqr (LAPACK below 75)", 75, 0, 0, n, H, reps);
  run_config("dlaqr0 + AED, LAPACK's NW", 15, 0, 0, n, H, reps);
  run_config("dlaqr0 + AED, NW 8, NS 2", 15, 8, 2, n, H, reps);
  run_config("dlaqr0 + AED, NW 12, NS 4", 15, 12, 4, n, H, reps);
  return 0;
}
