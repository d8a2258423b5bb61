#define _POSIX_C_SOURCE 200809L
/* The 17-DOF model against hand-derived entries of docs/model.md, the state
 * space against the dynamic stiffness (two routes to the same transfer
 * function), the fast stability index against the full solve, the paper-mode
 * SDF roots against their definition, and the Hessenberg inverse-iteration
 * eigendecomposition against its definition and dgeev, and the small real LU
 * and its condition estimate against LAPACK's dgesv and dgecon and the exact
 * 1-norm of the inverse. */
#include <complex.h>
#include <float.h>
#include <lapacke.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"
#include "linalg/eigen_decomposition.h" /* internal: the ride evaluation's eigendecomposition */
#include "linalg/hessenberg_qr.h"    /* internal: eigenvalues of several matrices in SIMD lanes */
#include "linalg/real_lu.h"          /* internal: the LU of the ride's eigenvector basis */
#include "model/dynamic_stiffness.h" /* internal: the shape tests' sparse solves in lanes */
#include "util/internal.h"           /* internal: rr_all_finite, the FRF plan's scan */

enum { YC, PC, RC, YF1, PF1, RF1, YF2, PF2, RF2, YW1, PW1, YW2, PW2, YW3, PW3, YW4, PW4 };

static void test_entries(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_model *m;
  rr_error e;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  const double V = 350 / RR_KMH, lam = 0.17;
  rr_model_set_operating(m, V, lam, &e);
  CHECK(rr_model_ndof(m) == 17 && rr_model_ninputs(m) == 4 && rr_model_state_size(m) == 40,
        "sizes");
  const char *names[17] = {"y_c",    "psi_c",  "phi_c",  "y_f1", "psi_f1", "phi_f1",
                           "y_f2",   "psi_f2", "phi_f2", "y_w1", "psi_w1", "y_w2",
                           "psi_w2", "y_w3",   "psi_w3", "y_w4", "psi_w4"};
  for (int i = 0; i < 17; i++)
    CHECK(!strcmp(rr_model_dof_name(m, i), names[i]), "dof %d is %s", i, rr_model_dof_name(m, i));
  const double *K = rr_model_K(m), *C = rr_model_C(m), *M = rr_model_M(m), *B = rr_model_B(m);
#define K_(i, j) K[(i)*17 + (j)]
#define C_(i, j) C[(i)*17 + (j)]
  double L = v.bogie_half_spacing, b = v.wheelbase_half, l1 = v.primary_half_spacing,
         lb = v.primary_arm_length;
  double l2 = v.secondary_half_spacing, l0 = v.contact_half_spacing, r0 = v.rolling_radius;
  double kpx = v.primary_kx, kpy = v.primary_ky, kpz = v.primary_kz, ksx = v.secondary_kx,
         ksy = v.secondary_ky;
  double ksz = v.secondary_kz, hs = v.secondary_height, hc = v.carbody_cg_height,
         hf = v.frame_cg_height;
  CHECK(M[YC * 17 + YC] == 38936 && M[PC * 17 + PC] == 9.61e5 && M[RC * 17 + RC] == 1.67e6 &&
            M[PW3 * 17 + PW3] == 822,
        "mass diagonal");
  /* secondary lateral: 4 air springs; yaw: 4 k_sx l2^2 + 4 k_sy L^2 */
  CHECK_CLOSE(K_(YC, YC), 4 * ksy, 1e-12, 0, "K y_c y_c");
  CHECK_CLOSE(K_(PC, PC), 4 * ksx * l2 * l2 + 4 * ksy * L * L, 1e-12, 0, "K psi_c psi_c");
  /* carbody roll: air springs lateral (h_s - h_c)^2, vertical l2^2, anti-roll bars */
  CHECK_CLOSE(K_(RC, RC),
              4 * ksy * (hs - hc) * (hs - hc) + 4 * ksz * l2 * l2 + 2 * v.antiroll_stiffness, 1e-12,
              0, "K phi_c phi_c");
  CHECK_CLOSE(K_(YC, PF1), 0, 0, 1e-9, "K y_c psi_f1");
  CHECK_CLOSE(K_(YC, YF1), -2 * ksy, 1e-12, 0, "K y_c y_f1");
  CHECK_CLOSE(K_(PC, YF1), -2 * ksy * L, 1e-12, 0, "K psi_c y_f1");
  /* frame: two wheelsets' primary lateral (4 boxes) + 2 air springs */
  CHECK_CLOSE(K_(YF1, YF1), 4 * kpy + 2 * ksy, 1e-12, 0, "K y_f1 y_f1");
  /* frame yaw: 4 boxes k_px l1^2 + lateral arm nodes at +-(b - l_b) + air springs k_sx l2^2 */
  CHECK_CLOSE(K_(PF1, PF1), 4 * kpx * l1 * l1 + 4 * kpy * (b - lb) * (b - lb) + 2 * ksx * l2 * l2,
              1e-12, 0, "K psi_f1 psi_f1");
  /* frame roll: primary vertical l1^2, primary lateral (r0 - h_f)^2, air springs */
  CHECK_CLOSE(K_(RF1, RF1),
              4 * kpz * l1 * l1 + 4 * kpy * (r0 - hf) * (r0 - hf) +
                  2 * ksy * (hs - hf) * (hs - hf) + 2 * ksz * l2 * l2 + v.antiroll_stiffness,
              1e-12, 0, "K phi_f1 phi_f1");
  /* wheelset: primary + contact */
  CHECK_CLOSE(K_(YW1, YW1), 2 * kpy, 1e-12, 0, "K y_w1 y_w1");
  CHECK_CLOSE(K_(PW1, PW1), 2 * kpx * l1 * l1 + 2 * kpy * lb * lb, 1e-12, 0, "K psi_w1 psi_w1");
  CHECK_CLOSE(K_(YW1, PW1), -2 * v.f22 - 2 * kpy * lb, 1e-12, 0,
              "K y_w1 psi_w1 (front: node behind)");
  CHECK_CLOSE(K_(YW2, PW2), -2 * v.f22 + 2 * kpy * lb, 1e-12, 0,
              "K y_w2 psi_w2 (rear: node ahead)");
  CHECK_CLOSE(K_(PW1, YW1), 2 * v.f11 * l0 * lam / r0 - 2 * kpy * lb, 1e-12, 0, "K psi_w1 y_w1");
  CHECK_CLOSE(K_(YW1, RF1), 2 * kpy * (r0 - hf), 1e-12, 0,
              "K y_w1 phi_f1 (frame point below the frame cg)");
  CHECK_CLOSE(K_(YW1, PF1), -2 * kpy * (b - lb), 1e-12, 0, "K y_w1 psi_f1");
  CHECK_CLOSE(C_(YW3, YW3), 2 * v.f22 / V, 1e-12, 0, "C y_w3");
  CHECK_CLOSE(C_(PW3, PW3), 2 * v.f11 * l0 * l0 / V, 1e-12, 0, "C psi_w3");
  CHECK_CLOSE(C_(RF2, RF2), 4 * v.primary_cz * l1 * l1 + 2 * v.secondary_cz * l2 * l2, 1e-12, 0,
              "C phi_f2");
  CHECK_CLOSE(C_(YC, YC), 0, 0, 1e-9, "C y_c (dampers are Maxwell)");
  for (int i = 0; i < 4; i++)
    for (int r = 0; r < 17; r++) {
      double want = r == PW1 + 2 * i ? 2 * v.f11 * l0 * lam / r0 : 0;
      CHECK_CLOSE(B[r * 4 + i], want, 1e-12, 0, "B");
    }
  for (int i = 0; i < 17; i++)
    for (int j = 0; j < i; j++) {
      if (i >= YW1 && j == i - 1 && (i - YW1) % 2 == 1) continue; /* creep terms: not symmetric */
      CHECK_CLOSE(K_(i, j) - K_(j, i), 0, 0, 1e-6, "suspension K symmetric");
    }
  /* Maxwell rows */
  CHECK(rr_model_nmaxwell(m) == 6, "6 Maxwell elements");
  rr_maxwell_info info;
  CHECK_OK(rr_model_maxwell(m, 0, &info, &e), e); /* yaw damper bogie 1 left */
  CHECK_CLOSE(info.J[PC], -v.yaw_half_spacing, 1e-12, 0, "yaw damper J psi_c");
  CHECK_CLOSE(info.J[PF1], v.yaw_half_spacing, 1e-12, 0, "yaw damper J psi_f1");
  CHECK(info.k == 10e6 && info.c == 4000e3, "yaw damper k, c");
  CHECK_OK(rr_model_maxwell(m, 1, &info, &e), e);
  CHECK_CLOSE(info.J[PC], v.yaw_half_spacing, 1e-12, 0, "right yaw damper J psi_c");
  CHECK_OK(rr_model_maxwell(m, 5, &info, &e), e); /* lateral damper bogie 2 */
  CHECK(rr_model_maxwell(m, 6, &info, &e) == RR_EINVAL && e.code == RR_EINVAL,
        "element 6: a status and a message");
  CHECK_CLOSE(info.J[YC], 1, 1e-12, 0, "lateral damper J y_c");
  CHECK_CLOSE(info.J[PC], -L, 1e-12, 0, "lateral damper J psi_c");
  CHECK_CLOSE(info.J[RC], -(v.lateral_damper_height - hc), 1e-12, 0, "lateral damper J phi_c");
  CHECK_CLOSE(info.J[YF2], -1, 1e-12, 0, "lateral damper J y_f2");
  CHECK_CLOSE(info.J[RF2], v.lateral_damper_height - hf, 1e-12, 0, "lateral damper J phi_f2");
  /* gravitational stiffness option */
  CHECK_OK(rr_model_set_gravity_stiffness(m, 1, &e), e);
  double W = 9.81 * (v.carbody_mass + 2 * v.frame_mass + 4 * v.wheelset_mass) / 4;
  CHECK_CLOSE(K_(YW2, YW2), 2 * kpy + W * lam / l0, 1e-12, 0, "gravity K y_w");
  CHECK_CLOSE(K_(PW2, PW2), 2 * kpx * l1 * l1 + 2 * kpy * lb * lb - W * lam * l0, 1e-12, 0,
              "gravity K psi_w");
  CHECK_CLOSE(B[YW2 * 4 + 1], W * lam / l0, 1e-12, 0, "gravity B y_w");
  rr_model_free(m);
}

/* q(s) for a unit input on wheelset `in`, by the state space (sI - A)^-1 Bs
 * and by the dynamic stiffness D(s)^-1 B: the Maxwell and SDF states must
 * reproduce the frequency-domain element laws exactly. */
static void test_two_routes(int sdf_mode)
{
  rr_vehicle v;
  rr_vehicle_builtin("type2", &v, NULL);
  v.sdf_mode = sdf_mode;
  rr_model *m;
  rr_error e;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  rr_model_set_operating(m, 300 / RR_KMH, 0.25, &e);
  int n = 17, N = rr_model_state_size(m);
  CHECK(N == (sdf_mode == RR_SDF_PHYSICAL ? 44 : 40), "state size %d", N);
  double *A = malloc(sizeof(double) * N * N), *Bs = malloc(sizeof(double) * N * 4);
  double complex *G = malloc(sizeof(double complex) * N * N),
                 *x = malloc(sizeof(double complex) * N);
  double complex *D = malloc(sizeof(double complex) * n * n),
                 *y = malloc(sizeof(double complex) * n);
  lapack_int *ipiv = malloc(sizeof(lapack_int) * N);
  rr_model_state_matrix(m, 0, A, &e);
  rr_model_state_input(m, Bs, &e);
  const double *B = rr_model_B(m);
  double freqs[3] = {0.7, 2.9, 11.0};
  for (int fi = 0; fi < 3; fi++) {
    double complex s = I * 2 * RR_PI * freqs[fi];
    for (int i = 0; i < N; i++)
      for (int j = 0; j < N; j++) G[i * N + j] = (i == j ? s : 0) - A[i * N + j];
    for (int i = 0; i < N; i++) x[i] = Bs[i * 4 + 2];
    LAPACKE_zgesv(LAPACK_ROW_MAJOR, N, 1, G, N, ipiv, x, 1);
    rr_model_dynamic_stiffness(m, s, 0, D);
    for (int i = 0; i < n; i++) y[i] = B[i * 4 + 2];
    LAPACKE_zgesv(LAPACK_ROW_MAJOR, n, 1, D, n, ipiv, y, 1);
    double big = 0, diff = 0;
    for (int i = 0; i < n; i++) {
      big = fmax(big, cabs(y[i]));
      diff = fmax(diff, cabs(x[i] - y[i]));
    }
    CHECK(diff <= 1e-9 * big, "state space vs dynamic stiffness at %g Hz (sdf %d): rel diff %.3g",
          freqs[fi], sdf_mode, diff / big);
  }
  free(A);
  free(Bs);
  free(G);
  free(x);
  free(D);
  free(y);
  free(ipiv);
  rr_model_free(m);
}

static void test_fast_vs_full(void)
{
  const char *veh[3] = {"type1", "type2", "type2"};
  int modes[3] = {RR_SDF_NONE, RR_SDF_NONE, RR_SDF_PHYSICAL};
  int count = 0, bad = 0;
  for (int k = 0; k < 3; k++) {
    rr_vehicle v;
    rr_vehicle_builtin(veh[k], &v, NULL);
    v.sdf_mode = modes[k];
    rr_model *m;
    rr_error e;
    rr_model_from_vehicle(&v, &m, &e);
    rr_modal_ws *ws;
    rr_modal_result r;
    rr_modal_ws_new(m, &ws, &e);
    rr_modal_result_alloc(m, &r, &e);
    rr_modal_opts o = rr_modal_opts_default();
    for (double sp = 100; sp <= 500; sp += 50)
      for (double lam = 0.02; lam <= 0.6; lam += 0.07) {
        rr_model_set_operating(m, sp / RR_KMH, lam, &e);
        double z;
        rr_modal_stability_index(m, &o, ws, &z, &e);
        rr_modal_solve(m, &o, ws, &r, &e);
        count++;
        if (fabs(z - r.stability_index) > 1e-10) {
          bad++;
          fprintf(stderr, "  %s sdf %d v %g lam %g: fast %.12g full %.12g\n", veh[k], modes[k], sp,
                  lam, z, r.stability_index);
        }
        double sum = r.modes[0].energy[0] + r.modes[0].energy[1] + r.modes[0].energy[2];
        CHECK_CLOSE(sum, 1, 1e-12, 0, "energy shares sum to 1");
      }
    rr_modal_result_free(&r);
    rr_modal_ws_free(ws);
    rr_model_free(m);
  }
  CHECK(bad == 0, "fast index differs from the full solve at %d of %d points", bad, count);
  /* designs spread over the optimiser's bounds (paper problem), both robust speeds */
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_modal_opts o = rr_modal_opts_default();
  unsigned seed = 7;
  bad = 0;
  for (int i = 0; i < 400; i++) {
    double r[5];
    for (int k = 0; k < 5; k++) {
      seed = seed * 1664525u + 1013904223u;
      r[k] = (seed >> 8) / 16777216.0;
    }
    v.primary_kx = 10e6 + 110e6 * r[0];
    v.lateral_damping = 5e3 + 55e3 * r[1];
    v.yaw_damping = 100e3 + 3900e3 * r[2];
    v.yaw_series_stiffness = 1e6 + 29e6 * r[3];
    rr_model *m;
    rr_error e;
    rr_modal_ws *ws;
    rr_modal_result res;
    rr_model_from_vehicle(&v, &m, &e);
    rr_model_set_operating(m, (i % 2 ? 350 : 250) / RR_KMH, 0.05 + 0.35 * r[4], &e);
    rr_modal_ws_new(m, &ws, &e);
    rr_modal_result_alloc(m, &res, &e);
    double z;
    rr_modal_stability_index(m, &o, ws, &z, &e);
    rr_modal_solve(m, &o, ws, &res, &e);
    if (fabs(z - res.stability_index) > 1e-9) {
      bad++;
      fprintf(stderr, "  design %d: fast %.12g full %.12g\n", i, z, res.stability_index);
    }
    rr_modal_result_free(&res);
    rr_modal_ws_free(ws);
    rr_model_free(m);
  }
  CHECK(bad == 0, "fast index differs from the full solve for %d of 400 random designs", bad);
}

/* The carbody roll mode of docs/model.md section 5: lightly damped, wheelsets still. */
static void test_roll_mode_excluded(void)
{
  rr_model *m;
  rr_error e;
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_model_from_vehicle(&v, &m, &e);
  rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e);
  rr_modal_ws *ws;
  rr_modal_result r;
  rr_modal_ws_new(m, &ws, &e);
  rr_modal_result_alloc(m, &r, &e);
  rr_modal_solve(m, NULL, ws, &r, &e);
  const rr_mode *md = &r.modes[0];
  CHECK(fabs(md->freq_hz - 0.23) < 0.01 && fabs(md->zeta + 0.008) < 0.001,
        "roll mode %g Hz zeta %g", md->freq_hz, md->zeta);
  CHECK(md->energy[RR_GROUP_WHEELSET] < 1e-6 && !md->in_index, "roll mode is not hunting-related");
  rr_modal_opts all = {.fmax_hz = 10, .w_min = 0, .r_max = 1};
  double z_roll = md->zeta;
  rr_modal_solve(m, &all, ws, &r, &e);
  CHECK_CLOSE(r.stability_index, z_roll, 1e-12, 0, "w_min = 0, r_max = 1 count every mode");
  /* zero conicity: free lateral drift is a double zero eigenvalue, which rounding
     splits into a tiny complex pair; it is real, not a hunting mode */
  rr_model_set_operating(m, 350 / RR_KMH, 0.0, &e);
  rr_modal_solve(m, NULL, ws, &r, &e);
  CHECK(r.index_mode >= 0 && r.modes[r.index_mode].freq_hz > 0.1,
        "zero conicity: index from a real mode (%g Hz)",
        r.index_mode >= 0 ? r.modes[r.index_mode].freq_hz : -1);
  double zf;
  rr_modal_stability_index(m, NULL, ws, &zf, &e);
  CHECK_CLOSE(zf, r.stability_index, 1e-10, 0, "zero conicity: fast index");
  rr_critical cr;
  rr_critical_speed(m, 0.0, NULL, NULL, ws, &cr, &e);
  CHECK(!cr.found, "zero conicity: no critical speed (got %g km/h)", cr.speed_ms * RR_KMH);
  rr_modal_result_free(&r);
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

/* Paper mode: each self-consistent mode has k = k_sdf(f) and is an
 * eigenvalue of the constant-k model at that k. */
static void test_paper_roots(void)
{
  rr_vehicle v;
  rr_vehicle_builtin("type2", &v, NULL);
  v.sdf_mode = RR_SDF_PAPER;
  rr_model *m;
  rr_error e;
  rr_model_from_vehicle(&v, &m, &e);
  rr_model_set_operating(m, 350 / RR_KMH, 0.3, &e);
  rr_modal_ws *ws;
  rr_modal_result r;
  rr_modal_ws_new(m, &ws, &e);
  rr_modal_result_alloc(m, &r, &e);
  CHECK_OK(rr_modal_solve(m, NULL, ws, &r, &e), e);
  int nsc = 0;
  double complex *D = malloc(sizeof(double complex) * 17 * 17);
  for (int i = 0; i < r.n; i++) {
    const rr_mode *md = &r.modes[i];
    if (!md->oscillatory || !md->self_consistent) continue;
    nsc++;
    double ks = rr_sdf_storage(&v.sdf, md->freq_hz);
    CHECK(fabs(md->sdf_k - ks) <= 2e-9 * (v.sdf.k2 + v.sdf.k3) + 1e-6 * fabs(ks) * 0,
          "root: k %.10g vs k_sdf(f) %.10g", md->sdf_k, ks);
    /* D(lambda) with series stiffness k is singular: smallest pivot relative to the largest */
    rr_model_dynamic_stiffness(m, md->re + I * md->im, md->sdf_k, D);
    lapack_int ipiv[17];
    LAPACKE_zgetrf(LAPACK_ROW_MAJOR, 17, 17, D, 17, ipiv);
    double mn = INFINITY, mx = 0;
    for (int k = 0; k < 17; k++) {
      mn = fmin(mn, cabs(D[k * 17 + k]));
      mx = fmax(mx, cabs(D[k * 17 + k]));
    }
    CHECK(mn < 1e-8 * mx, "mode %.4f Hz: D(lambda) not singular (%.3g)", md->freq_hz, mn / mx);
  }
  CHECK(nsc >= 8, "self-consistent modes found: %d", nsc);
  CHECK(r.stability_index < 0 && r.index_mode >= 0, "paper-mode index %g", r.stability_index);
  free(D);
  rr_modal_result_free(&r);
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

/* Field by field (a struct's padding is not part of its value). */
static int same_locus_point(const rr_locus_point *a, const rr_locus_point *b)
{
  int same = a->hunting == b->hunting;
  const double x[] = {
      a->param,     a->re,        a->im,         a->freq_hz,         a->zeta, a->mac, a->energy[0],
      a->energy[1], a->energy[2], a->roll_share, a->frame_roll_share};
  const double y[] = {
      b->param,     b->re,        b->im,         b->freq_hz,         b->zeta, b->mac, b->energy[0],
      b->energy[1], b->energy[2], b->roll_share, b->frame_roll_share};
  return same && !memcmp(x, y, sizeof x);
}

static int stop_at_30(void *user, long done, long total)
{
  (void)total;
  *(long *)user = done;
  return done >= 30;
}

/* Root loci follow mode shapes (MAC), not sort order: along a fine conicity
   sweep every branch stays correlated step to step and continuous in
   frequency, even where branches cross in frequency. */
static void test_locus_tracking(void)
{
  rr_vehicle v;
  rr_vehicle_builtin("type2", &v, NULL);
  rr_model *m;
  rr_error e;
  rr_model_from_vehicle(&v, &m, &e);
  rr_model_set_operating(m, 350 / RR_KMH, 0.1, &e);
  enum { NP = 80 };
  double vals[NP];
  for (int i = 0; i < NP; i++) vals[i] = 0.02 + 0.48 * i / (NP - 1);
  int S = rr_locus_stride(m);
  rr_locus_point *pts = malloc(sizeof(rr_locus_point) * NP * S);
  int nb = 0;
  CHECK_OK(rr_locus(m, 1, vals, NP, NULL, NULL, pts, &nb, &e), e);
  CHECK(nb >= 10 && nb <= S, "branches %d", nb);
  int lowmac = 0, jumps = 0, crossings = 0;
  for (int b = 0; b < nb; b++)
    for (int p = 1; p < NP; p++) {
      const rr_locus_point *a = &pts[(p - 1) * S + b], *c = &pts[p * S + b];
      if (isnan(a->re) || isnan(c->re) || c->freq_hz > 10) continue; /* alive, hunting range */
      if (c->mac < 0.9) lowmac++;
      /* a pair just born from two real roots (zeta near -1) moves fast in
         frequency, as sqrt of the distance from its birth: not a jump */
      if (a->zeta > -0.99 && c->zeta > -0.99 && fabs(c->freq_hz - a->freq_hz) > 0.3) jumps++;
      for (int b2 = 0; b2 < nb; b2++) { /* branches that swap frequency order */
        const rr_locus_point *a2 = &pts[(p - 1) * S + b2], *c2 = &pts[p * S + b2];
        if (b2 != b && (a->freq_hz - a2->freq_hz) * (c->freq_hz - c2->freq_hz) < 0) crossings++;
      }
    }
  CHECK(lowmac == 0, "%d steps with MAC < 0.9", lowmac);
  CHECK(jumps == 0, "%d frequency jumps > 0.3 Hz along a branch", jumps);
  CHECK(crossings > 0, "the sweep should contain branch crossings to be a test (%d)", crossings);
  /* a progress callback that stops after 30 points: RR_ESTOPPED, the points
     done as in the full run, the rest NaN */
  rr_locus_point *part = malloc(sizeof(rr_locus_point) * NP * S);
  long calls = 0;
  rr_progress pr = {.fn = stop_at_30, .user = &calls};
  int nb2 = 0, st = rr_locus(m, 1, vals, NP, NULL, &pr, part, &nb2, &e);
  CHECK(st == RR_ESTOPPED && e.code == RR_ESTOPPED && calls == 30 && nb2 <= nb,
        "stopped locus: status %d, %ld calls", st, calls);
  int same = 1, gaps = 1;
  for (int p = 0; p < NP; p++)
    for (int b = 0; b < nb; b++) {
      int i = p * S + b;
      if (p < 30)
        same &= same_locus_point(&part[i], &pts[i]);
      else
        gaps &= isnan(part[i].re) && part[i].param == vals[p];
    }
  CHECK(same && gaps, "stopped locus: points done bit-identical (%d), the rest NaN (%d)", same,
        gaps);
  /* the two steps: records solved out of order (as other processes would),
     followed in two windows, give rr_locus's result */
  size_t rs = rr_locus_record_size(m);
  char *recs = malloc(rs * NP);
  rr_modal_ws *ws;
  rr_modal_result res;
  rr_locus_tracker *t;
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_modal_result_alloc(m, &res, &e), e);
  CHECK_OK(rr_locus_tracker_new(m, &t, &e), e);
  for (int p = NP - 1; p >= 0; p--)
    CHECK_OK(rr_locus_solve(m, 1, vals[p], NULL, ws, &res, recs + rs * p, &e), e);
  int nb3 = 0;
  CHECK_OK(rr_locus_follow(t, vals, 33, recs, part, &nb3, &e), e);
  CHECK_OK(rr_locus_follow(t, vals + 33, NP - 33, recs + rs * 33, part + 33 * S, &nb3, &e), e);
  same = nb3 == nb;
  for (int p = 0; p < NP && same; p++)
    for (int b = 0; b < nb && same; b++) same = same_locus_point(&part[p * S + b], &pts[p * S + b]);
  CHECK(same, "solve + follow in two windows = rr_locus (branches %d, %d)", nb3, nb);
  rr_locus_tracker_free(t);
  rr_modal_result_free(&res);
  rr_modal_ws_free(ws);
  free(recs);
  free(part);
  free(pts);
  rr_model_free(m);
}

/* Residual |A V - V diag(lambda)| / (|A| |V|) of rr_eigdec's output (row-major
   A, LAPACK-layout V), and the largest distance of its eigenvalues from
   dgeev's, relative to |A|. */
static void eigdec_check(int n, const double *A, double *res, double *dist)
{
  double *a = malloc(sizeof(double) * n * n), *vr = malloc(sizeof(double) * n * n),
         *wr = malloc(sizeof(double) * 4 * n), *wi = wr + n, *lr = wi + n, *li = lr + n,
         *work = malloc(sizeof(double) * RR_EIGDEC_LWORK(n));
  int *iwork = malloc(sizeof(int) * RR_EIGDEC_LIWORK(n));
  memcpy(a, A, sizeof(double) * n * n);
  *res = *dist = INFINITY;
  if (rr_eigdec(n, a, wr, wi, vr, work, iwork) == 0) {
    double anorm = 0, vnorm = 0, r = 0;
    for (int i = 0; i < n * n; i++) {
      anorm = fmax(anorm, fabs(A[i]));
      vnorm = fmax(vnorm, fabs(vr[i]));
    }
    for (int j = 0; j < n; j++) {
      int pair = wi[j] != 0, c0 = pair && wi[j] < 0 ? j - 1 : j;
      double sg = wi[j] < 0 ? -1 : 1;
      double complex lam = wr[j] + I * wi[j];
      for (int i = 0; i < n; i++) {
        double complex av = 0;
        for (int k = 0; k < n; k++)
          av += A[i * n + k] * (vr[c0 * n + k] + (pair ? sg * I * vr[(c0 + 1) * n + k] : 0));
        double complex v = vr[c0 * n + i] + (pair ? sg * I * vr[(c0 + 1) * n + i] : 0);
        r = fmax(r, cabs(av - lam * v));
      }
    }
    *res = r / (anorm * vnorm * n);
    memcpy(a, A, sizeof(double) * n * n);
    LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', n, a, n, lr, li, NULL, n, NULL, n);
    double d = 0;
    for (int j = 0; j < n; j++) {
      double best = INFINITY;
      for (int k = 0; k < n; k++) best = fmin(best, cabs(wr[j] + I * wi[j] - (lr[k] + I * li[k])));
      d = fmax(d, best);
    }
    *dist = d / anorm;
  }
  free(a);
  free(vr);
  free(wr);
  free(work);
  free(iwork);
}

static void test_eigdec(void)
{
  /* the state matrices of the ride evaluation: speeds x conicities x SDF */
  rr_vehicle v;
  rr_vehicle_default(&v);
  double worst_res = 0, worst_dist = 0;
  for (int sdf = 0; sdf < 2; sdf++) {
    v.sdf_mode = sdf ? RR_SDF_PHYSICAL : RR_SDF_NONE;
    rr_model *m;
    rr_error e;
    CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
    int N = rr_model_state_size(m);
    double *A = malloc(sizeof(double) * N * N);
    for (double kmh = 100; kmh <= 500; kmh += 200)
      for (double lam = 0.02; lam < 0.6; lam += 0.19) {
        CHECK_OK(rr_model_set_operating(m, kmh / RR_KMH, lam, &e), e);
        CHECK_OK(rr_model_state_matrix(m, 0, A, &e), e);
        double res, dist;
        eigdec_check(N, A, &res, &dist);
        worst_res = fmax(worst_res, res);
        worst_dist = fmax(worst_dist, dist);
      }
    free(A);
    rr_model_free(m);
  }
  CHECK(worst_res < 1e-14, "eigdec on state matrices: residual %.3g", worst_res);
  CHECK(worst_dist < 1e-13, "eigdec on state matrices: eigenvalues differ from dgeev by %.3g |A|",
        worst_dist);
  /* seeded random matrices, and one with a repeated eigenvalue pair (two
     equal 2 x 2 rotation blocks under a random similarity): the vectors of
     the repeated pair must still be independent */
  unsigned long long s = 12345;
  enum { NR = 24 };
  double A[NR * NR], T[NR * NR], Ti[NR * NR], B[NR * NR];
  for (int trial = 0; trial < 20; trial++) {
    for (int i = 0; i < NR * NR; i++) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      A[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
    }
    double res, dist;
    eigdec_check(NR, A, &res, &dist);
    CHECK(res < 1e-13 && dist < 1e-12, "eigdec random %d: residual %.3g, eigenvalue distance %.3g",
          trial, res, dist);
  }
  memset(B, 0, sizeof B);
  for (int b = 0; b < NR / 2; b++) { /* 2 x 2 blocks [a w; -w a], the first two equal */
    double a = b < 2 ? -0.5 : -0.1 * b, w = b < 2 ? 3 : b;
    B[(2 * b) * NR + 2 * b] = B[(2 * b + 1) * NR + 2 * b + 1] = a;
    B[(2 * b) * NR + 2 * b + 1] = w;
    B[(2 * b + 1) * NR + 2 * b] = -w;
  }
  for (int i = 0; i < NR * NR; i++) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    T[i] = (i / NR == i % NR) + 0.3 * ((double)(s >> 11) / 9007199254740992.0 - 0.5);
  }
  memcpy(Ti, T, sizeof T);
  int piv[NR];
  LAPACKE_dgetrf(LAPACK_ROW_MAJOR, NR, NR, Ti, NR, piv);
  LAPACKE_dgetri(LAPACK_ROW_MAJOR, NR, Ti, NR, piv);
  for (int i = 0; i < NR; i++) /* A = T B T^-1 */
    for (int j = 0; j < NR; j++) {
      double acc = 0;
      for (int k = 0; k < NR; k++)
        for (int l = 0; l < NR; l++) acc += T[i * NR + k] * B[k * NR + l] * Ti[l * NR + j];
      A[i * NR + j] = acc;
    }
  double a[NR * NR], vr[NR * NR], wr[NR], wi[NR], work[RR_EIGDEC_LWORK(NR)];
  int iwork[RR_EIGDEC_LIWORK(NR)];
  memcpy(a, A, sizeof A);
  CHECK(rr_eigdec(NR, a, wr, wi, vr, work, iwork) == 0, "eigdec: repeated pair");
  double rcond = 0, vnorm = LAPACKE_dlange(LAPACK_COL_MAJOR, '1', NR, NR, vr, NR);
  LAPACKE_dgetrf(LAPACK_COL_MAJOR, NR, NR, vr, NR, piv);
  LAPACKE_dgecon(LAPACK_COL_MAJOR, '1', NR, vr, NR, vnorm, &rcond);
  CHECK(rcond > 1e-8, "eigdec: repeated pair gives a near-singular basis (rcond %.3g)", rcond);
  double res, dist;
  eigdec_check(NR, A, &res, &dist);
  CHECK(res < 1e-13 && dist < 1e-7, "eigdec repeated pair: residual %.3g, eigenvalue distance %.3g",
        res, dist);
}

/* rr_all_finite: every position (the eight-wide body and the tail) and every
 * kind of non-finite value, beside the largest and the smallest finite ones */
static void test_all_finite(void)
{
  enum { N = 37 };
  double x[N];
  for (int i = 0; i < N; i++) x[i] = i % 3 == 0 ? DBL_MAX * (i % 2 ? 1 : -1) : 4.9e-324 * i;
  CHECK(rr_all_finite(N, x) && rr_all_finite(0, x), "all finite");
  const double bad[3] = {NAN, INFINITY, -INFINITY};
  for (int p = 0; p < N; p++)
    for (int b = 0; b < 3; b++) {
      double keep = x[p];
      x[p] = bad[b];
      CHECK(!rr_all_finite(N, x), "a %g at %d of %d", bad[b], p, N);
      CHECK(rr_all_finite((size_t)p, x), "the %d before it are finite", p);
      x[p] = keep;
    }
}

/* rr_lu_* against LAPACK (dgesv's solution, dgecon's estimate: the same
 * algorithm, so the same value to rounding) and against the exact |A^-1|_1
 * from dgetri, which the estimate may not exceed: random matrices of several
 * orders, a graded ill-conditioned one, the ride's eigenvector basis, and an
 * exactly singular one. */
static void lu_check(int n, const double *A, const char *what)
{
  enum { NRHS = 6, NMAX = 40 };
  double lu[NMAX * NMAX], ref[NMAX * NMAX], x[NMAX * NRHS], b[NMAX * NRHS], work[2 * NMAX];
  int piv[NMAX], rpiv[NMAX], iwork[NMAX];
  unsigned long long s = 777 + (unsigned long long)n;
  for (int i = 0; i < n * NRHS; i++) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    b[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5; /* column-major, LAPACK's */
  }
  memcpy(lu, A, sizeof(double) * n * n);
  double anorm = rr_lu_norm1(n, A, n);
  CHECK(anorm == LAPACKE_dlange(LAPACK_COL_MAJOR, '1', n, n, A, n), "%s: 1-norm", what);
  CHECK(rr_lu_factor(n, lu, n, piv) == 0, "%s: factor", what);
  for (int i = 0; i < n; i++)
    for (int c = 0; c < NRHS; c++) x[i * NRHS + c] = b[c * n + i];
  rr_lu_solve_rows(n, lu, n, piv, NRHS, x, NRHS);
  double rc = rr_lu_rcond1(n, lu, n, anorm, work, iwork), rcref = 0;
  memcpy(ref, A, sizeof(double) * n * n);
  LAPACKE_dgetrf(LAPACK_COL_MAJOR, n, n, ref, n, rpiv);
  LAPACKE_dgecon(LAPACK_COL_MAJOR, '1', n, ref, n, anorm, &rcref);
  CHECK_CLOSE(rc, rcref, 1e-10, 0, what);
  LAPACKE_dgetri(LAPACK_COL_MAJOR, n, ref, n, rpiv);
  double inv1 = rr_lu_norm1(n, ref, n), exact = 1 / (anorm * inv1);
  CHECK(rc >= exact * (1 - 1e-10) && rc <= 10 * exact, "%s: rcond %.6g, exact %.6g", what, rc,
        exact);
  /* the solution against the explicit inverse's, to the conditioning */
  double worst = 0, xmax = 0;
  for (int c = 0; c < NRHS; c++)
    for (int i = 0; i < n; i++) {
      double acc = 0;
      for (int k = 0; k < n; k++) acc += ref[k * n + i] * b[c * n + k];
      worst = fmax(worst, fabs(acc - x[i * NRHS + c]));
      xmax = fmax(xmax, fabs(acc));
    }
  CHECK(worst <= 1e-13 * xmax / exact, "%s: solution off by %.3g of %.3g (rcond %.3g)", what, worst,
        xmax, exact);
}

static void test_lu(void)
{
  enum { NMAX = 40 };
  double A[NMAX * NMAX];
  unsigned long long s = 99;
  const int orders[] = {1, 2, 3, 5, 8, 17, 38, 40};
  for (int t = 0; t < 8; t++) {
    int n = orders[t];
    for (int i = 0; i < n * n; i++) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      A[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
    }
    char what[32];
    snprintf(what, sizeof what, "lu random %d", n);
    lu_check(n, A, what);
  }
  /* sparse (a third of the entries) plus the identity: on these the
     alternating-sign safeguard often gives the larger estimate */
  for (int n = 2; n < 14; n++) {
    for (int i = 0; i < n * n; i++) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      double r = (double)(s >> 11) / 9007199254740992.0 - 0.5;
      A[i] = (r > 0.3 ? r : 0) + (i % (n + 1) == 0);
    }
    char what[32];
    snprintf(what, sizeof what, "lu sparse %d", n);
    lu_check(n, A, what);
  }
  /* one where the search stops by its cycling test (the sign vector changes,
     the estimate does not grow) */
  lu_check(2, (const double[]){-1, -1, 2, 0}, "lu cycling");
  /* graded: a random core's columns scaled by 1 .. 2^-33 (exact scalings), so
     that the reciprocal condition number is ~1e-10 and the solves stay exact
     to rounding */
  for (int j = 0; j < 12; j++)
    for (int i = 0; i < 12; i++) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      A[j * 12 + i] = ldexp((double)(s >> 11) / 9007199254740992.0 - 0.5 + 2 * (i == j), -3 * j);
    }
  lu_check(12, A, "lu graded");
  /* the basis the ride factors: the default car's eigenvectors at 350 km/h */
  rr_vehicle v;
  rr_vehicle_default(&v);
  rr_model *m;
  rr_error e;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  int N = rr_model_state_size(m);
  double a[NMAX * NMAX], vr[NMAX * NMAX], wr[NMAX], wi[NMAX], work[RR_EIGDEC_LWORK(NMAX)];
  int iwork[RR_EIGDEC_LIWORK(NMAX)], piv[NMAX];
  CHECK(N <= NMAX, "state size %d", N);
  CHECK_OK(rr_model_state_matrix(m, 0, a, &e), e);
  CHECK(rr_eigdec(N, a, wr, wi, vr, work, iwork) == 0, "lu: eigdec");
  lu_check(N, vr, "lu eigenvector basis");
  rr_model_free(m);
  /* exactly singular: column 3 is zero, so the fourth pivot is zero */
  for (int i = 0; i < 36; i++) A[i] = (i % 7) + 1.0 / (i + 1);
  for (int i = 0; i < 6; i++) A[3 * 6 + i] = 0;
  CHECK(rr_lu_factor(6, A, 6, piv) == 4, "lu: a zero column is reported");
}

/* rr_eig_batch against rr_hqr lane by lane and against dgeev: groups of 1..8
 * seeded random matrices, mixed with matrices that split or deflate at once
 * (block diagonal, triangular), so that the lanes fall out of step; in groups
 * of 4 and in the widest the processor has (8 with AVX-512). */
static void test_eig_batch(void)
{
  enum { NR = 24, W = RR_QR_LANES_MAX };
  unsigned long long s = 987654321;
  double mats[W][NR * NR], h[NR * NR], wr[W * NR], wi[W * NR], hr[NR], hi[NR], lr[NR], li[NR],
      a[NR * NR];
  double *work = malloc(sizeof(double) * rr_eig_batch_work(NR));
  const double *mp[W];
  int fail[W];
  double worst_lane = 0, worst_geev = 0;
  for (int trial = 0; trial < 32; trial++) {
    int nb = 1 + trial % W;
    for (int c = 0; c < nb; c++) {
      int kind = (trial + c) % 5; /* 0..2 dense, 3 block diagonal, 4 upper triangular */
      for (int i = 0; i < NR * NR; i++) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        double x = (double)(s >> 11) / 9007199254740992.0 - 0.5;
        int r = i / NR, col = i % NR;
        if (kind == 3 && (r < NR / 3) != (col < NR / 3)) x = 0;
        if (kind == 4 && r > col) x = 0;
        mats[c][i] = x * (kind == 2 ? 1e4 : 1);
      }
      mp[c] = mats[c];
    }
    for (int lanes = 4; lanes >= 0; lanes -= 4) {
      CHECK(rr_eig_batch(NR, nb, lanes, mp, wr, wi, work, fail) == 0,
            "eig batch: trial %d did not converge", trial);
      for (int c = 0; c < nb; c++) {
        double anorm = 0;
        for (int i = 0; i < NR * NR; i++) anorm = fmax(anorm, fabs(mats[c][i]));
        memcpy(h, mats[c], sizeof h);
        CHECK(rr_eig_small(NR, h, hr, hi) == 0, "eig small: trial %d lane %d", trial, c);
        memcpy(a, mats[c], sizeof a);
        LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', NR, a, NR, lr, li, NULL, NR, NULL, NR);
        for (int j = 0; j < NR; j++) {
          double complex z = wr[c * NR + j] + I * wi[c * NR + j];
          /* same algorithm per lane: same order, same values */
          worst_lane = fmax(worst_lane, cabs(z - (hr[j] + I * hi[j])) / anorm);
          double best = INFINITY;
          for (int k = 0; k < NR; k++) best = fmin(best, cabs(z - (lr[k] + I * li[k])));
          worst_geev = fmax(worst_geev, best / anorm);
        }
      }
    }
  }
  /* a lane that cannot converge (a NaN entry) is reported alone; its
     neighbours' eigenvalues are untouched */
  mats[5][5 * NR + 7] = NAN;
  for (int lanes = 4; lanes >= 0; lanes -= 4) {
    CHECK(rr_eig_batch(NR, 7, lanes, mp, wr, wi, work, fail) != 0,
          "eig batch: a NaN lane went unreported");
    for (int c = 0; c < 7; c++) {
      CHECK(fail[c] == (c == 5), "eig batch: lane %d reported %d with the NaN in lane 5", c,
            fail[c]);
      if (c == 5) continue;
      double anorm = 0;
      for (int i = 0; i < NR * NR; i++) anorm = fmax(anorm, fabs(mats[c][i]));
      memcpy(h, mats[c], sizeof h);
      rr_eig_small(NR, h, hr, hi);
      for (int j = 0; j < NR; j++)
        worst_lane = fmax(worst_lane,
                          cabs(wr[c * NR + j] + I * wi[c * NR + j] - (hr[j] + I * hi[j])) / anorm);
    }
  }
  free(work);
  printf("  eig batch: groups of up to %d lanes here\n", rr_eig_batch_lanes());
  /* the lanes run the single-matrix arithmetic lane by lane: equal to the last bit */
  CHECK(worst_lane == 0, "eig batch differs from the single-matrix QR by %.3g |A|", worst_lane);
  CHECK(worst_geev < 1e-12, "eig batch differs from dgeev by %.3g |A|", worst_geev);
}

/* rr_modal_stability_batch against the single-point index: three SDF
 * treatments (paper mode takes the single-point route), 11 points (groups of
 * 4, 4, 3), the operating point restored, bad input refused. */
static void test_index_batch(void)
{
  int modes[3] = {RR_SDF_NONE, RR_SDF_PHYSICAL, RR_SDF_PAPER};
  double v[11], lam[11];
  rr_stability zb[11];
  for (int p = 0; p < 11; p++) {
    v[p] = (150 + 40 * p) / RR_KMH;
    lam[p] = 0.03 + 0.045 * ((p * 7) % 11);
  }
  double worst = 0;
  for (int k = 0; k < 3; k++) {
    rr_vehicle veh;
    rr_vehicle_builtin("type1", &veh, NULL);
    veh.sdf_mode = modes[k];
    rr_model *m;
    rr_modal_ws *ws;
    rr_error e;
    CHECK_OK(rr_model_from_vehicle(&veh, &m, &e), e);
    CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
    CHECK_OK(rr_model_set_operating(m, 300 / RR_KMH, 0.2, &e), e);
    CHECK_OK(rr_modal_stability_batch(m, NULL, ws, 11, v, lam, zb, &e), e);
    CHECK(rr_model_speed(m) == 300 / RR_KMH && rr_model_conicity(m) == 0.2,
          "index batch: operating point not restored");
    for (int p = 0; p < 11; p++) {
      rr_stability z;
      CHECK_OK(rr_model_set_operating(m, v[p], lam[p], &e), e);
      CHECK_OK(rr_modal_stability(m, NULL, ws, &z, &e), e);
      worst = fmax(worst, fmax(fabs(z.index - zb[p].index), fabs(z.zeta_max - zb[p].zeta_max)));
    }
    double vbad[2] = {300 / RR_KMH, 0};
    CHECK(rr_modal_stability_batch(m, NULL, ws, 2, vbad, lam, zb, &e) == RR_EINVAL,
          "index batch: zero speed accepted");
    rr_modal_ws_free(ws);
    rr_model_free(m);
  }
  CHECK(worst < 1e-13, "index batch differs from the single-point index by %.3g", worst);
}

/* A lane's shape phi against the single solver's from ds's factors (ref:
   2 n scratch): the relative difference; with GCC, every bit the same. */
static double shape_vs_single(const rr_dsolver *ds, const double complex *phi, double complex *ref,
                              int lane)
{
  int n = ds->n;
  for (int i = 0; i < n; i++) ref[i] = rr_dsolver_start(i);
  rr_dsolver_solve(ds, ref, ref + n);
  rr_dsolver_from(ds, ref, ref + n);
  double nrm = 0, d = 0;
  for (int i = 0; i < n; i++) {
    nrm = fmax(nrm, cabs(ref[n + i]));
    d = fmax(d, cabs(ref[n + i] - phi[i]));
#if defined(__GNUC__) && !defined(__clang__)
    CHECK(creal(ref[n + i]) == creal(phi[i]) && cimag(ref[n + i]) == cimag(phi[i]),
          "shape lanes: lane %d entry %d differs from the single solver's bits", lane, i);
#endif
  }
  return d / nrm;
}

/* The shape solves of eight operating points in lanes against the
 * single-point solver with the same cached pivot order: GCC's limited-range
 * complex arithmetic, which the lanes write out, gives the same bits; other
 * compilers' library calls round differently (within 1e-12). Lanes outside
 * the mask are left alone; a lane the kept order does not suit is reported
 * and solved once the order the single solver pivots for is kept; SDF
 * elements keep a point out of the lanes. */
static void test_shape_lanes(void)
{
  rr_vehicle veh;
  rr_error e;
  rr_model *m;
  rr_vehicle_builtin("type1", &veh, NULL);
  CHECK_OK(rr_model_from_vehicle(&veh, &m, &e), e);
  int n = rr_model_ndof(m), L = RR_DSL_LANES;
  static rr_dsolver ds;
  int *iw = calloc(RR_DSOLVER_IWORK(n), sizeof *iw);
  double complex *zw = calloc(RR_DSOLVER_ZWORK(n), sizeof *zw), *phi = calloc(L * n, sizeof *phi);
  double complex *ref = calloc(2 * n, sizeof *ref);
  rr_dsl dl, sizing;
  rr_block b = {0};
  rr_dsl_layout(&sizing, n, &b);
  CHECK(rr_block_alloc(&b) == 0, "dsl block");
  rr_dsl_layout(&dl, n, &b);
  double v[8], lam[8], sr[8], si[8];
  for (int l = 0; l < L; l++) {
    v[l] = (200 + 25 * l) / RR_KMH;
    lam[l] = 0.05 + 0.05 * l;
    sr[l] = -0.3 - 0.2 * l; /* damped modes of 1 to 8 Hz */
    si[l] = 2 * RR_PI * (1 + l);
  }
  /* the cached pivot order: a pivoting factorisation at the first point */
  CHECK_OK(rr_model_set_operating(m, v[0], lam[0], &e), e);
  rr_dsolver_init(&ds, m, iw, zw);
  rr_dsolver_factor(&ds, sr[0] + I * si[0], 0);
  CHECK(!ds.dirty, "shape lanes: the scalar solver cached no order");
  for (int l = 0; l < L; l++) {
    CHECK_OK(rr_model_set_operating(m, v[l], lam[l], &e), e);
    rr_dsolver_init(&ds, m, iw, zw);
    CHECK(rr_dsl_load(&dl, l, &ds) == 0, "shape lanes: lane %d not loaded", l);
  }
  CHECK(!rr_dsl_has_order(&dl), "shape lanes: an order before one was kept");
  rr_dsl_keep_order(&dl, &ds);
  for (int i = 0; i < L * n; i++) phi[i] = NAN;
  unsigned bad = rr_dsl_shapes(&dl, 0x7f, sr, si, phi);
  int compared = 0;
  double worst = 0;
  for (int l = 0; l < L - 1; l++) {
    if (bad >> l & 1) continue; /* the single solver would pivot afresh */
    CHECK_OK(rr_model_set_operating(m, v[l], lam[l], &e), e);
    rr_dsolver_init(&ds, m, iw, zw);
    long piv = ds.n_pivoting;
    rr_dsolver_factor(&ds, sr[l] + I * si[l], 0);
    CHECK(ds.n_pivoting == piv, "shape lanes: lane %d passed where the single solver pivots", l);
    worst = fmax(worst, shape_vs_single(&ds, phi + l * n, ref, l));
    compared++;
  }
  CHECK(compared >= 6, "shape lanes: only %d lanes compared", compared);
  CHECK(worst < 1e-12, "shape lanes: %.3g from the single solver", worst);
  for (int i = 0; i < n; i++)
    CHECK(isnan(creal(phi[(L - 1) * n + i])), "shape lanes: lane outside the mask written");
  /* a test the kept order does not suit: the lane reports it, and takes
     the order the single solver pivots for once that is kept */
  double fs = -1;
  for (double f = 0.5; f <= 12 && fs < 0; f += 0.25) {
    CHECK_OK(rr_model_set_operating(m, v[0], lam[0], &e), e);
    rr_dsolver_init(&ds, m, iw, zw);
    rr_dsl_keep_order(&dl, &ds); /* the kept order is the cache's */
    long piv = ds.n_pivoting;
    rr_dsolver_factor(&ds, -0.1 + 2 * RR_PI * f * I, 0);
    if (ds.n_pivoting > piv) fs = f; /* ds's cache is now the order pivoting found */
  }
  CHECK(fs > 0, "shape lanes: no frequency where the cached order fails");
  if (fs > 0) {
    double s1r[8], s1i[8];
    for (int l = 0; l < L; l++) s1r[l] = -0.1, s1i[l] = 2 * RR_PI * fs;
    rr_dsl fresh = dl;
    for (int o = 0; o < RR_DSL_ORDERS; o++) fresh.orders[o].valid = 0;
    fresh.orders[0] = dl.orders[dl.newest]; /* the order before fs alone */
    fresh.newest = 0;
    unsigned b1 = rr_dsl_shapes(&fresh, 1, s1r, s1i, phi);
    CHECK(b1 == 1, "shape lanes: the unsuited order was not reported (%#x)", b1);
    rr_dsl_keep_order(&fresh, &ds); /* the order pivoting found at fs */
    CHECK(rr_dsl_shapes(&fresh, 1, s1r, s1i, phi) == 0, "shape lanes: the kept order not tried");
    double d = shape_vs_single(&ds, phi, ref, 0);
    CHECK(d <= 1e-12, "shape lanes: the second order's shape %.3g from the single solver's", d);
  }
  /* SDF elements stay out */
  rr_model *ms;
  veh.sdf_mode = RR_SDF_PHYSICAL;
  CHECK_OK(rr_model_from_vehicle(&veh, &ms, &e), e);
  rr_dsolver_init(&ds, ms, iw, zw);
  CHECK(rr_dsl_load(&dl, 0, &ds) == -1, "shape lanes: SDF elements loaded");
  rr_model_free(ms);
  free(b.base);
  free(iw);
  free(zw);
  free(phi);
  free(ref);
  rr_model_free(m);
}

/* Every indexed getter answers an index out of range with its type's
   "none" (common.h): NULL, -1 or NaN, never a read outside the data. */
static void test_getters_out_of_range(void)
{
  rr_vehicle v;
  rr_error e;
  rr_model *m;
  rr_system *sys;
  rr_vehicle_default(&v);
  if (rr_model_from_vehicle(&v, &m, &e) || rr_vehicle_system(&v, &sys, &e)) {
    CHECK(0, "%s", e.msg);
    return;
  }
  int n = rr_model_ndof(m), ni = rr_model_ninputs(m);
  CHECK(rr_model_dof_name(m, n - 1) && rr_model_dof_group(m, n - 1) >= 0 &&
            isfinite(rr_model_input_x(m, ni - 1)) && rr_system_dof_name(sys, n - 1),
        "the last index is in range");
  for (int k = 0; k < 2; k++) {
    int dof = k ? -1 : n, in = k ? -1 : ni;
    CHECK(!rr_model_dof_name(m, dof) && rr_model_dof_group(m, dof) == -1 &&
              isnan(rr_model_input_x(m, in)) && !rr_system_dof_name(sys, dof),
          "index %d out of range: NULL, -1, NaN", dof);
  }
  rr_system_free(sys);
  rr_model_free(m);
}

int main(void)
{
  test_eigdec();
  test_lu();
  test_all_finite();
  test_eig_batch();
  test_index_batch();
  test_shape_lanes();
  test_entries();
  test_locus_tracking();
  test_two_routes(RR_SDF_NONE);
  test_two_routes(RR_SDF_PHYSICAL);
  test_fast_vs_full();
  test_roll_mode_excluded();
  test_paper_roots();
  test_getters_out_of_range();
  return check_done("model");
}
