#define _POSIX_C_SOURCE 200809L
/* Every instruction-set copy of the eigenvalue kernels gives the same bits.
 * The library picks its copies at load time (AVX-512, AVX2 + FMA or the
 * baseline x86-64); this test links two more builds of the same sources with
 * one copy each (see tests/CMakeLists.txt): for the baseline x86-64 (SSE2, 4
 * lanes as two vectors), its symbols prefixed base_, and for x86-64-v3 (what
 * the library's AVX2 clones are compiled for; a processor with AVX-512 never
 * runs rr_eigdec's, which has an AVX-512 clone too), prefixed avx2_. The library's copies and the
 * AVX2 copy are held to the baseline on the state matrices of the default vehicle (the robust
 * points, three SDF treatments) and on seeded random matrices that split and
 * deflate early: eigenvalues alone (one matrix, lanes of 4 and of the widest
 * the copy has), the ride's eigendecomposition with its vectors, and the
 * LU, condition estimate and solve of its eigenvector basis. So a
 * machine with AVX-512 checks the AVX-512, AVX2 and baseline paths against
 * each other. The ride's modal-sum product (rr_gemm_nn) picks its path at
 * run time and takes a path by name: each path it can run is held to a
 * scalar FMA chain (libm's fma) bit for bit, and to OpenBLAS within rounding. The
 * shape tests' sparse solves in lanes (rr_dsl_shapes) and the ride's sparse frequency
 * responses in lanes (rr_frf_sparse_execute: its generated codelets and its
 * interpreter, every input and their lagged sum) are held to the baseline's too, and
 * every copy of rr_max_abs (a state matrix's largest entry) to a plain loop. */
#include <complex.h>
#include <float.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"
#include "linalg/eigen_decomposition.h" /* internal: the ride evaluation's eigendecomposition */
#include "linalg/gemm.h"                /* internal: the ride's modal-sum product */
#include "linalg/hessenberg_qr.h"       /* internal: eigenvalues one matrix or several at a time */
#include "linalg/max_abs.h"             /* internal: a state matrix's largest entry */
#include "linalg/real_lu.h"             /* internal: the LU of the ride's eigenvector basis */
#include "model/dynamic_stiffness.h"    /* internal: the shape tests' sparse solves in lanes */
#include "ride/frf_sparse.h"            /* internal: the ride's sparse solves in lanes */

int base_rr_eig_small(int n, double *a, double *wr, double *wi);
int base_rr_eig_batch(int n, int nb, int lanes, const double *const *mats, double *wr, double *wi,
                      double *work, int *fail);
int base_rr_eig_batch_lanes(void);
int base_rr_eigdec(int n, double *a, double *wr, double *wi, double *vr, double *work, int *iwork);
int avx2_rr_eig_small(int n, double *a, double *wr, double *wi);
int avx2_rr_eig_batch(int n, int nb, int lanes, const double *const *mats, double *wr, double *wi,
                      double *work, int *fail);
int avx2_rr_eigdec(int n, double *a, double *wr, double *wi, double *vr, double *work, int *iwork);
#define RR_LU_COPY(p)                                                                              \
  int p##rr_lu_factor(int n, double *a, int lda, int *piv);                                        \
  void p##rr_lu_solve_rows(int n, const double *lu, int lda, const int *piv, int nrhs, double *x,  \
                           int ldx);                                                               \
  double p##rr_lu_rcond1(int n, const double *lu, int lda, double anorm, double *work, int *iwork);
RR_LU_COPY(base_)
RR_LU_COPY(avx2_)
double base_rr_max_abs(size_t n, const double *x);
double avx2_rr_max_abs(size_t n, const double *x);
unsigned base_rr_dsl_shapes(rr_dsl *dl, unsigned mask, const double *sr, const double *si,
                            double complex *phi);
unsigned avx2_rr_dsl_shapes(rr_dsl *dl, unsigned mask, const double *sr, const double *si,
                            double complex *phi);
#define RR_FRF_SPARSE_COPY(p)                                                                      \
  void p##rr_frf_sparse_layout(rr_frf_sparse *s, int n, int ni, int np, rr_block *b);              \
  void p##rr_frf_sparse_execute(rr_frf_sparse *s, const rr_model *m, const double *f, int nf,      \
                                const double *rows, const double *rows0,                           \
                                const double complex *lag, double complex *H);
RR_FRF_SPARSE_COPY(base_)
RR_FRF_SPARSE_COPY(avx2_)

enum { NMAX = 48, NMATS = 40 };

static double mats[NMATS][NMAX * NMAX];
static int order[NMATS], nmats;

/* the default vehicle's state matrices at the robust points' speeds and
   conicities, with no SDF, the physical SDF and the paper mode */
static const int vehicle_sdf[3] = {RR_SDF_NONE, RR_SDF_PHYSICAL, RR_SDF_PAPER};

/* The default vehicle (into v) with SDF treatment s of vehicle_sdf; NULL on failure. */
static rr_model *default_model(int s, rr_vehicle *v)
{
  rr_vehicle_default(v);
  v->sdf_mode = vehicle_sdf[s];
  rr_model *m;
  rr_error e;
  if (rr_model_from_vehicle(v, &m, &e)) {
    CHECK(0, "model: %s", e.msg);
    return NULL;
  }
  return m;
}

static void vehicle_matrices(void)
{
  const double kmh[3] = {300, 350, 400}, lam[3] = {0.05, 0.17, 0.40};
  for (int s = 0; s < 3; s++) {
    rr_vehicle v;
    rr_error e;
    rr_model *m = default_model(s, &v);
    if (!m) continue;
    for (int p = 0; p < 9; p++) {
      CHECK_OK(rr_model_set_operating(m, kmh[p / 3] / RR_KMH, lam[p % 3], &e), e);
      int n = rr_model_state_size(m);
      if (n <= NMAX && !rr_model_state_matrix(m, 0, mats[nmats], &e)) order[nmats++] = n;
    }
    rr_model_free(m);
  }
}

/* dense, block diagonal and triangular: lanes that split and finish early */
static void random_matrices(void)
{
  unsigned long long s = 20261203;
  for (int t = 0; nmats < NMATS; t++) {
    int n = 5 + t % 30, kind = t % 4;
    for (int i = 0; i < n * n; i++) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      double x = (double)(s >> 11) / 9007199254740992.0 - 0.5;
      int r = i / n, c = i % n;
      if ((kind == 2 && (r < n / 3) != (c < n / 3)) || (kind == 3 && r > c)) x = 0;
      mats[nmats][i] = x;
    }
    order[nmats++] = n;
  }
}

/* The copies held to the baseline: the library's (the one it chose at load
   time) and the AVX2 copy, where this processor can run it. */
typedef struct eig_copy {
  const char *name;
  int (*small)(int n, double *a, double *wr, double *wi);
  int (*batch)(int n, int nb, int lanes, const double *const *mats, double *wr, double *wi,
               double *work, int *fail);
  int (*eigdec)(int n, double *a, double *wr, double *wi, double *vr, double *work, int *iwork);
  int (*lu_factor)(int n, double *a, int lda, int *piv);
  void (*lu_solve_rows)(int n, const double *lu, int lda, const int *piv, int nrhs, double *x,
                        int ldx);
  double (*lu_rcond1)(int n, const double *lu, int lda, double anorm, double *work, int *iwork);
} eig_copy;

static int ncopies(void)
{
#if defined(__x86_64__) /* x86-64-v3's features (Clang knows no level names) */
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                 __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2")
             ? 2
             : 1;
#else
  return 2; /* both built for the baseline */
#endif
}

static const eig_copy copies[2] = {
    {"the library's", rr_eig_small, rr_eig_batch, rr_eigdec, rr_lu_factor, rr_lu_solve_rows,
     rr_lu_rcond1},
    {"the AVX2 copy's", avx2_rr_eig_small, avx2_rr_eig_batch, avx2_rr_eigdec, avx2_rr_lu_factor,
     avx2_rr_lu_solve_rows, avx2_rr_lu_rcond1},
};

/* eigenvalues one matrix at a time and in lanes, each copy against the
   baseline's */
static void check_eigenvalues(const eig_copy *cp)
{
  static double a[NMAX * NMAX], b[NMAX * NMAX], wr[2][8 * NMAX], wi[2][8 * NMAX];
  double *work = malloc(sizeof(double) * rr_eig_batch_work(NMAX)),
         *bwork = malloc(sizeof(double) * rr_eig_batch_work(NMAX));
  int fail[8], differ = 0, batches = 0;
  for (int k = 0; k < nmats; k++) {
    int n = order[k];
    memcpy(a, mats[k], sizeof(double) * (size_t)(n * n));
    memcpy(b, mats[k], sizeof(double) * (size_t)(n * n));
    CHECK(cp->small(n, a, wr[0], wi[0]) == 0 && base_rr_eig_small(n, b, wr[1], wi[1]) == 0,
          "matrix %d: no convergence", k);
    differ += memcmp(wr[0], wr[1], sizeof(double) * (size_t)n) != 0 ||
              memcmp(wi[0], wi[1], sizeof(double) * (size_t)n) != 0;
  }
  CHECK(differ == 0, "%d of %d matrices: %s QR differs from the baseline copy's", differ, nmats,
        cp->name);
  /* groups of equal order, as the library batches them */
  for (int k = 0; k < nmats;) {
    int nb = 1;
    while (k + nb < nmats && nb < 8 && order[k + nb] == order[k]) nb++;
    const double *mp[8];
    for (int c = 0; c < nb; c++) mp[c] = mats[k + c];
    for (int lanes = 4; lanes >= 0; lanes -= 4) { /* 0: the widest that copy has */
      int n = order[k];
      CHECK(cp->batch(n, nb, lanes, mp, wr[0], wi[0], work, fail) == 0 &&
                base_rr_eig_batch(n, nb, 4, mp, wr[1], wi[1], bwork, fail) == 0,
            "batch at %d: no convergence", k);
      CHECK(!memcmp(wr[0], wr[1], sizeof(double) * (size_t)(nb * n)) &&
                !memcmp(wi[0], wi[1], sizeof(double) * (size_t)(nb * n)),
            "%s batch of %d at matrix %d, lanes %d (0: the widest): differs from the baseline copy",
            cp->name, nb, k, lanes);
      batches++;
    }
    k += nb;
  }
  free(work);
  free(bwork);
  printf("  eigenvalues, %s: %d matrices one at a time, %d batches, equal to the baseline\n",
         cp->name, nmats, batches);
}

/* the ride's eigendecomposition: eigenvalues and vectors */
static void check_eigdec(const eig_copy *cp)
{
  static double a[NMAX * NMAX], vr[2][NMAX * NMAX], work[RR_EIGDEC_LWORK(NMAX)];
  double wr[2][NMAX], wi[2][NMAX];
  int iwork[RR_EIGDEC_LIWORK(NMAX)], differ = 0, ok = 0;
  for (int k = 0; k < nmats; k++) {
    int n = order[k], st[2];
    memcpy(a, mats[k], sizeof(double) * (size_t)(n * n));
    st[0] = cp->eigdec(n, a, wr[0], wi[0], vr[0], work, iwork);
    memcpy(a, mats[k], sizeof(double) * (size_t)(n * n));
    st[1] = base_rr_eigdec(n, a, wr[1], wi[1], vr[1], work, iwork);
    CHECK(st[0] == st[1], "eigdec, matrix %d: %s status %d against the baseline's %d", k, cp->name,
          st[0], st[1]);
    if (st[0] || st[1]) continue;
    ok++;
    differ += memcmp(wr[0], wr[1], sizeof(double) * (size_t)n) != 0 ||
              memcmp(wi[0], wi[1], sizeof(double) * (size_t)n) != 0 ||
              memcmp(vr[0], vr[1], sizeof(double) * (size_t)(n * n)) != 0;
  }
  CHECK(ok >= 27, "eigdec: only %d matrices decomposed", ok);
  CHECK(differ == 0,
        "eigdec: %d of %d matrices, %s values or vectors differ from the baseline copy", differ, ok,
        cp->name);
  printf("  eigendecomposition, %s: %d matrices, values and vectors equal to the baseline\n",
         cp->name, ok);
}

/* the LU of each matrix's eigenvector basis (what the ride factors) and of
   the matrix itself: factors, pivots, the condition estimate and a solve with
   six right-hand sides */
static void check_lu(const eig_copy *cp)
{
  enum { NRHS = 6 };
  static double a[NMAX * NMAX], lu[2][NMAX * NMAX], x[2][NMAX * NRHS], wr[NMAX], wi[NMAX],
      work[RR_EIGDEC_LWORK(NMAX)];
  int iwork[RR_EIGDEC_LIWORK(NMAX)], piv[2][NMAX], differ = 0, cases = 0;
  for (int k = 0; k < nmats; k++)
    for (int basis = 0; basis < 2; basis++) {
      int n = order[k];
      memcpy(a, mats[k], sizeof(double) * (size_t)(n * n));
      if (basis && base_rr_eigdec(n, a, wr, wi, lu[0], work, iwork)) continue;
      if (basis) memcpy(a, lu[0], sizeof(double) * (size_t)(n * n));
      double anorm = rr_lu_norm1(n, a, n), rc[2];
      int st[2];
      for (int c = 0; c < 2; c++) {
        memcpy(lu[c], a, sizeof(double) * (size_t)(n * n));
        st[c] = (c ? base_rr_lu_factor : cp->lu_factor)(n, lu[c], n, piv[c]);
        rc[c] = (c ? base_rr_lu_rcond1 : cp->lu_rcond1)(n, lu[c], n, anorm, work, iwork);
        for (int i = 0; i < n * NRHS; i++) x[c][i] = 1 + 0.25 * (i % 7) - 0.125 * (i % 3);
        (c ? base_rr_lu_solve_rows : cp->lu_solve_rows)(n, lu[c], n, piv[c], NRHS, x[c], NRHS);
      }
      cases++;
      differ += st[0] != st[1] || memcmp(piv[0], piv[1], sizeof(int) * (size_t)n) != 0 ||
                memcmp(lu[0], lu[1], sizeof(double) * (size_t)(n * n)) != 0 ||
                memcmp(&rc[0], &rc[1], sizeof(double)) != 0 ||
                memcmp(x[0], x[1], sizeof(double) * (size_t)(n * NRHS)) != 0;
    }
  CHECK(cases >= 54 && differ == 0, "lu: %d of %d cases, %s factors, estimate or solution differ",
        differ, cases, cp->name);
  printf("  real LU, %s: %d matrices and bases, factors, estimates and solutions equal\n", cp->name,
         cases);
}

/* The product's paths on the ride's shape (30 x 38 times 38 x 400) and on
   shapes that exercise every tile and tail (rows not a multiple of 6,
   columns not of 32, 8 or 4, k = 0): each path the processor runs equals a
   scalar FMA chain over k in order, and so each other, bit for bit; the
   BLAS path agrees within the rounding bound k eps sum |a b|. */
static void check_gemm(void)
{
  enum { GM = 31, GN = 403, GK = 40, GA = GM * (GK + 1), GB = GK * (GN + 3), GC = GM * (GN + 2) };
  static double a[GA], b[GB], c[3][GC], ref[GC];
  const int shapes[][3] = {{30, 400, 38}, {30, 200, 38}, {1, 1, 1},  {7, 9, 5},     {13, 36, 40},
                           {6, 32, 38},   {5, 48, 3},    {12, 4, 7}, {31, 403, 40}, {2, 70, 0}};
  unsigned long long s = 20261205;
  for (int i = 0; i < GA; i++) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    a[i] = ldexp((double)(s >> 11) / 9007199254740992.0 - 0.5, (int)(s % 21) - 10);
  }
  for (int i = 0; i < GB; i++) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    b[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
  }
  int have = rr_gemm_isa(), chains = 0, blas = 0;
  for (size_t t = 0; t < sizeof shapes / sizeof shapes[0]; t++) {
    int m = shapes[t][0], n = shapes[t][1], k = shapes[t][2], lda = k + 1, ldb = n + 3,
        ldc = n + 2; /* leading dimensions past the shape: nothing read or written beyond it */
    for (int i = 0; i < m; i++)
      for (int j = 0; j < n; j++) {
        double x = 0;
        for (int p = 0; p < k; p++) x = fma(a[i * lda + p], b[p * ldb + j], x);
        ref[i * ldc + j] = x;
      }
    for (int isa = RR_GEMM_BLAS; isa <= RR_GEMM_AVX512; isa++) {
      int tiles = (isa < have ? isa : have) >= RR_GEMM_AVX2; /* the path that runs */
      for (int i = 0; i < GC; i++) c[isa][i] = 12345;
      rr_gemm_nn_isa(isa, m, n, k, a, lda, b, ldb, c[isa], ldc);
      int bad = 0, outside = 0;
      for (int i = 0; i < m; i++)
        for (int j = 0; j < n; j++) {
          double x = c[isa][i * ldc + j], r = ref[i * ldc + j], bound = 0;
          for (int p = 0; p < k; p++) bound += fabs(a[i * lda + p] * b[p * ldb + j]);
          bad +=
              tiles ? memcmp(&x, &r, sizeof x) != 0 : !(fabs(x - r) <= 2 * k * DBL_EPSILON * bound);
        }
      for (int i = 0; i < GC; i++) outside += (i / ldc >= m || i % ldc >= n) && c[isa][i] != 12345;
      CHECK(!bad && !outside,
            "gemm %d x %d x %d, path %d (processor has %d): %d entries off, %d written outside", m,
            n, k, isa, have, bad, outside);
      if (tiles)
        chains++;
      else
        blas++;
    }
  }
  CHECK(have < RR_GEMM_AVX2 || chains >= 20, "gemm: only %d tile-path runs", chains);
  printf("  modal-sum product: %d runs equal to the FMA chain bit for bit (paths up to %s), %d "
         "within rounding of it (BLAS)\n",
         chains,
         have == RR_GEMM_AVX512 ? "AVX-512"
         : have == RR_GEMM_AVX2 ? "AVX2"
                                : "none",
         blas);
}

/* The shape tests' solves of eight operating points in lanes: the
   library's copy and the AVX2 copy give the baseline's bits. */
static void check_shapes(void)
{
  rr_vehicle veh;
  rr_error e;
  rr_model *m;
  rr_vehicle_default(&veh);
  if (rr_model_from_vehicle(&veh, &m, &e)) {
    CHECK(0, "model: %s", e.msg);
    return;
  }
  enum { L = RR_DSL_LANES };
  int n = rr_model_ndof(m);
  static rr_dsolver ds;
  int *iw = calloc(RR_DSOLVER_IWORK(n), sizeof *iw);
  double complex *zw = calloc(RR_DSOLVER_ZWORK(n), sizeof *zw), *phi[3];
  rr_dsl dl, sizing;
  rr_block b = {0};
  rr_dsl_layout(&sizing, n, &b);
  CHECK(rr_block_alloc(&b) == 0, "shape lanes' block");
  rr_dsl_layout(&dl, n, &b);
  double sr[L], si[L];
  for (int l = 0; l < L; l++) {
    CHECK_OK(rr_model_set_operating(m, (250 + 20 * l) / RR_KMH, 0.04 + 0.05 * l, &e), e);
    rr_dsolver_init(&ds, m, iw, zw);
    if (l == 0) rr_dsolver_factor(&ds, -0.5 + 2 * RR_PI * 2 * I, 0); /* an order to keep */
    CHECK(rr_dsl_load(&dl, l, &ds) == 0, "shape lanes: lane %d not loaded", l);
    sr[l] = -0.2 - 0.1 * l;
    si[l] = 2 * RR_PI * (1.5 + 0.3 * l);
  }
  rr_dsl_keep_order(&dl, &ds);
  unsigned (*fn[3])(rr_dsl *, unsigned, const double *, const double *,
                    double complex *) = {base_rr_dsl_shapes, rr_dsl_shapes, avx2_rr_dsl_shapes};
  unsigned bad[3];
  for (int c = 0; c < 1 + ncopies(); c++) {
    phi[c] = calloc(L * n, sizeof *phi[c]);
    bad[c] = fn[c](&dl, 0xff, sr, si, phi[c]);
    if (c == 0) continue;
    CHECK(bad[c] == bad[0] && !memcmp(phi[c], phi[0], sizeof *phi[0] * L * n),
          "shape lanes: %s copy differs from the baseline's",
          c == 1 ? "the library's" : "the AVX2");
  }
  CHECK(bad[0] != 0xff, "shape lanes: no lane solved");
  for (int c = 0; c < 1 + ncopies(); c++) free(phi[c]);
  free(b.base);
  free(iw);
  free(zw);
  rr_model_free(m);
}

/* Largest |a - b| over n complex numbers, relative to the largest |b|. */
static double rel_diff(const double complex *a, const double complex *b, size_t n)
{
  double d = 0, s = 0;
  for (size_t i = 0; i < n; i++) {
    d = fmax(d, cabs(a[i] - b[i]));
    s = fmax(s, cabs(b[i]));
  }
  return d / s;
}

enum { FRF_NF = 403, FRF_NP = 3, FRF_NI = 4 };
typedef void (*frf_layout_fn)(rr_frf_sparse *, int, int, int, rr_block *);
typedef void (*frf_exec_fn)(rr_frf_sparse *, const rr_model *, const double *, int, const double *,
                            const double *, const double complex *, double complex *);

/* One copy's responses: every input (lag NULL) or their lagged sum, by the
   generated codelet or (interpret) the interpreter. */
static void frf_copy(frf_layout_fn lay, frf_exec_fn ex, const rr_model *m, const double *f,
                     const double *rows, const double *rows0, const double complex *lag,
                     int interpret, double complex *H)
{
  rr_frf_sparse sp;
  rr_block b = {0};
  lay(&sp, rr_model_ndof(m), FRF_NI, FRF_NP, &b);
  CHECK(rr_block_alloc(&b) == 0, "sparse frf block");
  lay(&sp, rr_model_ndof(m), FRF_NI, FRF_NP, &b);
  sp.interpret = interpret;
  ex(&sp, m, f, FRF_NF, rows, rows0, lag, H);
  CHECK(interpret ? sp.codelet == -1 : sp.codelet >= 0, "sparse frf: %s ran",
        interpret ? "the interpreter" : "a codelet");
  free(b.base);
}

/* The ride's sparse frequency responses, eight frequencies a lane group
   (403: a short last group): the default vehicle with no SDF, the physical
   SDF (complex series stiffness) and the paper mode, with the floor rows and
   the roll-gravity rows, every input and the inputs' lagged sum, by the
   codelet and by the interpreter: every copy the baseline's bits (its FMAs
   are libm's fma, rounded once as the FMA instructions round), and each
   copy's codelet its interpreter's. */
static void check_frf_sparse(void)
{
  frf_layout_fn lay[3] = {base_rr_frf_sparse_layout, rr_frf_sparse_layout,
                          avx2_rr_frf_sparse_layout};
  frf_exec_fn ex[3] = {base_rr_frf_sparse_execute, rr_frf_sparse_execute,
                       avx2_rr_frf_sparse_execute};
  static double f[FRF_NF];
  static double complex H[3][2][FRF_NF * FRF_NP * FRF_NI], lag[FRF_NF * FRF_NI];
  for (int k = 0; k < FRF_NF; k++) f[k] = 0.3 * pow(100, k / (FRF_NF - 1.0));
  for (int s = 0; s < 3; s++) {
    rr_vehicle v;
    rr_error e;
    rr_model *m = default_model(s, &v);
    if (!m) continue;
    CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
    double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[3 * 64], rows0[3 * 64];
    CHECK_OK(rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, 1, rows, rows0, &e), e);
    for (int k = 0; k < FRF_NF; k++)
      for (int i = 0; i < FRF_NI; i++)
        lag[k * FRF_NI + i] = cexp(I * 2 * RR_PI * f[k] * rr_model_input_x(m, i) / (350 / RR_KMH));
    for (int sum = 0; sum < 2; sum++) {
      size_t nh = (size_t)FRF_NF * FRF_NP * (sum ? 1 : FRF_NI);
      for (int c = 0; c < 1 + ncopies(); c++) {
        frf_copy(lay[c], ex[c], m, f, rows, rows0, sum ? lag : NULL, 0, H[c][0]);
        frf_copy(lay[c], ex[c], m, f, rows, rows0, sum ? lag : NULL, 1, H[c][1]);
        CHECK(!memcmp(H[c][0], H[c][1], nh * sizeof **H[c]),
              "sparse frf, sdf %d, sum %d: the %s copy's codelet differs from its interpreter",
              vehicle_sdf[s], sum,
              c == 0   ? "baseline"
              : c == 1 ? "library's"
                       : "AVX2");
        if (c == 2)
          CHECK(!memcmp(H[2][0], H[1][0], nh * sizeof **H[1]),
                "sparse frf, sdf %d, sum %d: the AVX2 copy differs from the library's",
                vehicle_sdf[s], sum);
      }
      CHECK(!memcmp(H[0][0], H[1][0], nh * sizeof **H[0]),
            "sparse frf, sdf %d, sum %d: the library's copy differs from the baseline's",
            vehicle_sdf[s], sum);
      if (sum) {
        /* the lagged sum solved directly against the inputs' responses summed */
        frf_copy(lay[1], ex[1], m, f, rows, rows0, NULL, 0, H[2][0]);
        double complex S[FRF_NF * FRF_NP];
        for (int k = 0; k < FRF_NF; k++)
          for (int q = 0; q < FRF_NP; q++) {
            S[k * FRF_NP + q] = 0;
            for (int i = 0; i < FRF_NI; i++)
              S[k * FRF_NP + q] += H[2][0][(k * FRF_NP + q) * FRF_NI + i] * lag[k * FRF_NI + i];
          }
        double ds = rel_diff(H[1][0], S, nh);
        CHECK(ds <= 1e-12,
              "sparse frf, sdf %d: the lagged sum within 1e-12 of the summed "
              "responses (%.2g)",
              vehicle_sdf[s], ds);
      }
    }
    CHECK(cabs(H[1][0][0]) > 0, "sparse frf: an answer");
    rr_model_free(m);
  }
  printf("  sparse frf: 3 vehicles, every input and their lagged sum, codelets and interpreter: "
         "every copy the baseline's bits\n");
}

/* The largest |x_i| (eight lanes in four chains): every copy against a plain
   loop, for every length to 64^2 that a state matrix can have and the tails
   between; the largest at every position, negative, among zeros of both
   signs and subnormals. */
static void check_max_abs(void)
{
  enum { NM = 64 * 64 };
  static double x[NM];
  double (*fn[3])(size_t, const double *) = {base_rr_max_abs, rr_max_abs, avx2_rr_max_abs};
  unsigned long long s = 99;
  for (int n = 0; n <= 64; n++)
    for (int t = 0; t < (n < 64 ? 40 : 1); t++) {
      size_t len = (size_t)(n * n + t);
      for (size_t i = 0; i < len; i++) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        int k = (int)(s >> 60);
        x[i] = k < 3   ? (k ? -0.0 : 0.0)
               : k < 5 ? 4.9e-324 * k
                       : ((double)(s >> 11) - 4.5e15) * 1e-12;
      }
      double ref = 0;
      for (size_t i = 0; i < len; i++) ref = fabs(x[i]) > ref ? fabs(x[i]) : ref;
      for (int c = 0; c < 1 + ncopies(); c++) {
        CHECK(fn[c](len, x) == ref, "max_abs copy %d, %zu entries: %g against %g", c, len,
              fn[c](len, x), ref);
        for (size_t p = 0; p < len; p += 1 + p / 5) {
          double keep = x[p];
          x[p] = -1e300;
          CHECK(fn[c](len, x) == 1e300, "max_abs copy %d, %zu entries: the largest at %zu", c, len,
                p);
          x[p] = keep;
        }
      }
    }
}

int main(void)
{
  __builtin_cpu_init();
  printf("  this processor: AVX-512 %s, AVX2 %s; library lanes %d, baseline copy lanes %d\n",
         __builtin_cpu_supports("avx512f") ? "yes" : "no",
         __builtin_cpu_supports("avx2") ? "yes" : "no", rr_eig_batch_lanes(),
         base_rr_eig_batch_lanes());
  vehicle_matrices();
  CHECK(nmats == 27, "27 vehicle state matrices, got %d", nmats);
  random_matrices();
  if (ncopies() < 2) printf("  no x86-64-v3 here: the AVX2 copy is not run\n");
  for (int c = 0; c < ncopies(); c++) {
    check_eigenvalues(&copies[c]);
    check_eigdec(&copies[c]);
    check_lu(&copies[c]);
  }
  check_gemm();
  check_shapes();
  check_max_abs();
  check_frf_sparse();
  return check_done("test_isa");
}
