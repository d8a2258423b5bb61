#define _POSIX_C_SOURCE 200809L
/* Ride comfort in the frequency domain: spectra, FRF (modal + SMW against
 * direct solves), PEM (against the cross-spectral product and the lag
 * factor), and the comfort indices (hand-worked sinusoids, ISO 8041 tables). */
#define _POSIX_C_SOURCE 200809L
#include <complex.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "railride/railride.h"
#include "ride/frf_sparse.h" /* internal: the sparse route's fallback, counted */
#include "util/block.h"

#define write_file check_write_file

static void test_spectra(void)
{
  rr_spectrum s;
  rr_error e;
  /* published RMS over 2-200 m (the published track spectrum tables) */
  const char *names[4] = {"tbt3352-alignment", "tbt3352-vertical", "tbt3352-crosslevel",
                          "tbt3352-gauge"};
  const double rms_mm[4] = {0.6678, 1.2203, 0.5235, 0.3437};
  for (int i = 0; i < 4; i++) {
    CHECK_OK(rr_spectrum_open(names[i], &s, &e), e);
    CHECK_CLOSE(1e3 * rr_spectrum_rms(&s, 0.005, 0.5), rms_mm[i], 0, 0.5e-4, names[i]);
  }
  /* the alignment in closed form: sum of A/(1-k) (b^(1-k) - a^(1-k)) */
  CHECK_OK(rr_spectrum_open("wuhan-guangzhou", &s, &e), e);
  double seg[3][4] = {{0.005, 0.045, 3.9513e-3, 1.8670},
                      {0.045, 0.1234, 1.1047e-2, 1.5354},
                      {0.1234, 0.5, 7.5633e-4, 2.8171}};
  double var = 0;
  for (int i = 0; i < 3; i++)
    var += seg[i][2] / (1 - seg[i][3]) *
           (pow(seg[i][1], 1 - seg[i][3]) - pow(seg[i][0], 1 - seg[i][3]));
  CHECK_CLOSE(1e3 * rr_spectrum_rms(&s, 0.005, 0.5), sqrt(var), 1e-9, 0,
              "power-law RMS vs closed form");
  CHECK_CLOSE(rr_spectrum_eval(&s, 0.08), 1e-6 * 1.1047e-2 / pow(0.08, 1.5354), 1e-14, 0,
              "eval in m^2/(1/m)");
  CHECK_CLOSE(rr_spectrum_eval(&s, 0.002), 1e-6 * 3.9513e-3 / pow(0.002, 1.8670), 1e-14, 0,
              "end segment extends");
  /* German alignment, rad/m: S_n(n) = 2 pi S_W(2 pi n); over all W the integral is
     A Oc^2 pi / (2 Or Oc (Or + Oc)) */
  CHECK_OK(rr_spectrum_open("german-low-alignment", &s, &e), e);
  double A = 2.119e-7, Oc = 0.8246, Or = 0.0206, n = 0.05, W = 2 * RR_PI * n;
  CHECK_CLOSE(rr_spectrum_eval(&s, n),
              2 * RR_PI * A * Oc * Oc / ((W * W + Or * Or) * (W * W + Oc * Oc)), 1e-13, 0,
              "rad/m conversion");
  double total = A * Oc * Oc * RR_PI / (2 * Or * Oc * (Or + Oc));
  CHECK_CLOSE(pow(rr_spectrum_rms(&s, 1e-13, 1e5), 2), total, 1e-8, 0,
              "German alignment variance in closed form");
  /* file forms: table (log-log) and rational7 against their formulas; two-sided doubles */
  const char *p = write_file("t.txt", "name = t\ndirection = lateral\nform = table\nfreq_unit = "
                                      "1/m\npsd_unit = m^2/(1/m)\nsided = two\nvalid = 0.01 1\n"
                                      "point = 0.01 1e-4\npoint = 0.1 1e-6\npoint = 1 1e-9\n");
  CHECK_OK(rr_spectrum_load(p, &s, &e), e);
  CHECK_CLOSE(rr_spectrum_eval(&s, 0.0316227766016838), 2 * 1e-4 * pow(3.16227766016838, -2), 1e-12,
              0, "table log-log midpoint, two-sided");
  CHECK_CLOSE(rr_spectrum_eval(&s, 0.5), 2 * 1e-6 * pow(5, -3), 1e-12, 0, "table second slope");
  rr_spectrum_close(&s);
  /* a measured PSD as CSV: header units honoured (mm^2 per cycle/m, rad/m),
     tens of thousands of rows, the same log-log interpolation */
  {
    enum { NROW = 40000 };
    char *csv = malloc((size_t)NROW * 48 + 64), *q = csv;
    q += sprintf(q, "n_cycles_per_m,psd_mm2_per_cycle_per_m\n");
    for (int i = 0; i < NROW; i++) { /* S = 1e-3 n^-2 mm^2/(1/m), 1e-3 .. 1 1/m */
      double nn = 1e-3 * pow(1e3, i / (NROW - 1.0));
      q += sprintf(q, "%.17g,%.17g\n", nn, 1e-3 / (nn * nn));
    }
    p = write_file("m.csv", csv);
    CHECK_OK(rr_spectrum_open(p, &s, &e), e);
    CHECK(s.npts == NROW && !strcmp(s.direction, "lateral"), "measured PSD: %d rows", s.npts);
    CHECK_CLOSE(rr_spectrum_eval(&s, 0.0123), 1e-9 / (0.0123 * 0.0123), 1e-9, 0,
                "measured PSD in m^2/(1/m)");
    CHECK_CLOSE(rr_spectrum_rms(&s, 0.01, 0.1), sqrt(1e-9 * (1 / 0.01 - 1 / 0.1)), 1e-6, 0,
                "measured PSD RMS against the closed form");
    rr_spectrum c;
    CHECK_OK(rr_spectrum_copy(&s, &c, &e), e);
    CHECK(c.tab_n != s.tab_n && c.npts == s.npts && c.tab_S[777] == s.tab_S[777], "a deep copy");
    rr_spectrum_close(&c);
    rr_spectrum_close(&s);
    p = write_file("w.csv", "omega_rad_per_m,psd_m2_per_rad_per_m\n0.1,2e-6\n1,2e-8\n");
    CHECK_OK(rr_spectrum_open(p, &s, &e), e);
    CHECK_CLOSE(rr_spectrum_eval(&s, 0.1 / (2 * RR_PI)), 2 * RR_PI * 2e-6, 1e-12, 0,
                "rad/m columns: S_n = 2 pi S_Omega");
    rr_spectrum_close(&s);
    p = write_file("u.csv", "n_per_m,psd_m2_per_rad_per_m\n0.1,2e-6\n1,2e-8\n");
    CHECK(rr_spectrum_open(p, &s, &e) == RR_EUNIT && strstr(e.msg, "u.csv:1"),
          "header units "
          "that disagree: %s",
          e.msg);
    p = write_file("v.csv", "n_per_m,psd_m2_per_per_m\n0.1,2e-6\n0.05,2e-8\n");
    CHECK(rr_spectrum_open(p, &s, &e) == RR_EINVAL && strstr(e.msg, "v.csv:3"), "decreasing: %s",
          e.msg);
    free(csv);
  }
  /* a spectrum of another direction is refused for the lateral input */
  CHECK_OK(rr_spectrum_open("german-high-crosslevel", &s, &e), e);
  CHECK(rr_spectrum_require(&s, "lateral", "the lateral input", &e) == RR_EINVAL &&
            strstr(e.msg, "german-high-crosslevel.txt: a crosslevel spectrum"),
        "cross level as lateral: %s", e.msg);
  CHECK_OK(rr_spectrum_open("german-high-alignment", &s, &e), e);
  CHECK_OK(rr_spectrum_require(&s, "lateral", "the lateral input", &e), e);
  p = write_file("r.txt", "direction = vertical\nform = rational7\nfreq_unit = 1/m\npsd_unit = "
                          "mm^2/(1/m)\nsided = one\nvalid = 0.01 0.5\n"
                          "params = 0.1 0.2 0.3 0.4 0.5 0.6 0.7\n");
  CHECK_OK(rr_spectrum_load(p, &s, &e), e);
  double x = 0.2, want = 0.1 * (x * x + 0.2 * x + 0.3) /
                         (x * x * x * x + 0.4 * x * x * x + 0.5 * x * x + 0.6 * x + 0.7);
  CHECK_CLOSE(rr_spectrum_eval(&s, x), 1e-6 * want, 1e-13, 0, "rational7");
  CHECK(!strcmp(s.name, "r"), "name from the file name");
  /* bad files */
  p = write_file("b1.txt", "direction = lateral\nform = powerlaw\nfreq_unit = 1/m\npsd_unit = "
                           "mm^2/(rad/m)\nsided = one\nvalid = 0.01 0.5\nsegment = 0.01 0.5 1 2\n");
  CHECK(rr_spectrum_load(p, &s, &e) == RR_EUNIT && strstr(e.msg, "psd_unit"), "unit mismatch: %s",
        e.msg);
  p = write_file("b2.txt", "direction = lateral\nform = powerlaw\nfreq_unit = 1/m\npsd_unit = "
                           "mm^2/(1/m)\nsided = one\nvalid = 0.01 0.5\nsegment = 0.01 0.5 -1 2\n");
  CHECK(rr_spectrum_load(p, &s, &e) == RR_EINVAL && strstr(e.msg, "b2.txt:7: segment"),
        "negative A: %s", e.msg);
  p = write_file("b3.txt", "direction = lateral\nform = powerlaw\nfreq_unit = 1/m\nsided = "
                           "one\nvalid = 0.01 0.5\nsegment = 0.01 0.5 1 2\n");
  CHECK(rr_spectrum_load(p, &s, &e) == RR_EPARSE && strstr(e.msg, "psd_unit"), "missing key: %s",
        e.msg);
  p = write_file("b4.txt", "direction = lateral\nform = powerlaw\ncolour = blue\n");
  CHECK(rr_spectrum_load(p, &s, &e) == RR_EPARSE && strstr(e.msg, "b4.txt:3: colour"),
        "unknown key: %s", e.msg);
  CHECK(rr_spectrum_open("no-such-spectrum", &s, &e) == RR_EIO, "unknown name");
  /* a pole or a negative region anywhere the formula is used (it extends past
     `valid`) is refused at load */
  p = write_file("pole.txt", "direction = lateral\nform = rational7\nfreq_unit = 1/m\npsd_unit = "
                             "mm^2/(1/m)\nsided = one\nvalid = 0.01 0.05\n"
                             "params = 0.1 0.2 0.3 0.4 0.5 0.6 -0.7\n");
  CHECK(rr_spectrum_load(p, &s, &e) == RR_EINVAL && strstr(e.msg, "pole at"), "a pole: %s", e.msg);
  p = write_file("neg.txt", "direction = lateral\nform = rational7\nfreq_unit = 1/m\npsd_unit = "
                            "mm^2/(1/m)\nsided = one\nvalid = 0.01 0.05\n"
                            "params = 0.1 -0.2 0.001 0.4 0.5 0.6 0.7\n");
  CHECK(rr_spectrum_load(p, &s, &e) == RR_EINVAL && strstr(e.msg, "negative"),
        "a negative region: %s", e.msg);
  p = write_file("negz.txt", "direction = lateral\nform = rational7\nfreq_unit = 1/m\npsd_unit = "
                             "mm^2/(1/m)\nsided = one\nvalid = 0.25 0.5\noutside = zero\n"
                             "params = 0.1 -0.2 0.001 0.4 0.5 0.6 0.7\n");
  CHECK_OK(rr_spectrum_load(p, &s, &e), e); /* its roots lie outside what is used */
}

static rr_model *vehicle_model(const char *base, int sdf, const char *table)
{
  rr_vehicle v;
  rr_error e;
  rr_vehicle_builtin(base, &v, &e);
  v.sdf_mode = sdf;
  if (table) rr_sdf_table_load(table, &v.sdf, &e);
  rr_model *m;
  if (rr_model_from_vehicle(&v, &m, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    return NULL;
  }
  rr_model_set_operating(m, 350 / RR_KMH, 0.2, &e);
  return m;
}

static rr_frf_plan *floor_plan(rr_model *m, int method, int roll_gravity)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[3 * 17], rows0[3 * 17];
  rr_error e;
  rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, roll_gravity, rows, rows0, &e);
  rr_frf_opts o = {400, NULL, 0.3, 30, 3, rows, roll_gravity ? rows0 : NULL, method};
  rr_frf_plan *p;
  if (rr_frf_plan_new(m, &o, &p, &e)) {
    fprintf(stderr, "%s\n", e.msg);
    return NULL;
  }
  return p;
}

/* Type 2 with two more paper-mode SDF dampers (lateral, carbody to each frame,
   not mirror images of each other): four SMW elements, the general M2. */
static rr_model *four_sdf_dampers(void)
{
  rr_vehicle v;
  rr_error e;
  rr_vehicle_builtin("type2", &v, &e);
  v.sdf_mode = RR_SDF_PAPER;
  rr_system *sys;
  rr_model *m = NULL;
  CHECK_OK(rr_vehicle_system(&v, &sys, &e), e);
  for (int j = 0; j < 2; j++) {
    rr_element_spec d = {.name = j ? "extra_2" : "extra_1",
                         .body_a = 0,
                         .body_b = 1 + j,
                         .point = {j ? -v.bogie_half_spacing : v.bogie_half_spacing, 0.3 * j, 0.9},
                         .direction = RR_DIR_Y,
                         .law = RR_LAW_MAXWELL,
                         .k = 4e6,
                         .c = 3e4 * (1 + j),
                         .sdf = 1};
    CHECK_OK(rr_system_add_element(sys, &d, NULL, &e), e);
  }
  CHECK_OK(rr_model_new(sys, &m, &e), e);
  CHECK_OK(rr_model_set_sdf(m, RR_SDF_PAPER, &v.sdf, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.2, &e), e);
  rr_system_free(sys);
  return m;
}

/* The largest difference between two FRFs of nf frequencies and nt entries
   each, at every frequency relative to the reference's largest entry there. */
static double frf_diff(const double complex *H, const double complex *Href, int nf, int nt)
{
  double worst = 0;
  for (int k = 0; k < nf; k++) {
    double big = 0;
    for (int t = 0; t < nt; t++) big = fmax(big, cabs(Href[k * nt + t]));
    for (int t = 0; t < nt; t++) worst = fmax(worst, cabs(H[k * nt + t] - Href[k * nt + t]) / big);
  }
  return worst;
}

/* The modal FRF (both sources of the modal basis: Hessenberg inverse
   iteration and LAPACK's left and right vectors) and the sparse one (the
   default) against the dense direct solve, at every frequency relative to its
   largest entry. */
static void compare_modal_direct(rr_model *m, int rg, const char *label)
{
  rr_frf_plan *pd = floor_plan(m, RR_FRF_DIRECT, rg);
  rr_error e;
  CHECK_OK(rr_frf_plan_execute(pd, m, &e), e);
  const double complex *Hd = rr_frf_H(pd);
  rr_frf_plan *ps = floor_plan(m, RR_FRF_SPARSE, rg);
  CHECK_OK(rr_frf_plan_execute(ps, m, &e), e);
  double ws = frf_diff(rr_frf_H(ps), Hd, 400, 12);
  CHECK(ws < 1e-12, "%s, sparse vs dense rel diff %.3g", label, ws);
  rr_frf_plan_free(ps);
  for (int method = RR_FRF_MODAL; method <= RR_FRF_MODAL_LAPACK;
       method += RR_FRF_MODAL_LAPACK - RR_FRF_MODAL) {
    rr_frf_plan *pm = floor_plan(m, method, rg);
    CHECK_OK(rr_frf_plan_execute(pm, m, &e), e);
    double worst = frf_diff(rr_frf_H(pm), Hd, 400, 12);
    CHECK(worst < 1e-10, "%s, %s: modal vs direct rel diff %.3g", label,
          method == RR_FRF_MODAL ? "inverse iteration" : "dgeev", worst);
    rr_frf_plan_free(pm);
  }
  rr_frf_plan_free(pd);
}

static void test_modal_vs_direct(void)
{
  const char *src = getenv("RR_SOURCE_DIR");
  char table[512];
  snprintf(table, sizeof table, "%s/examples/sdf-table.csv", src ? src : "..");
  struct {
    const char *base;
    int sdf;
    const char *table;
    int rg;
  } cases[] = {
      {"type1", RR_SDF_NONE, NULL, 0},   {"type2", RR_SDF_PHYSICAL, NULL, 0},
      {"type2", RR_SDF_PAPER, NULL, 0},  {"type1", RR_SDF_PAPER, NULL, 1},
      {"type2", RR_SDF_PAPER, table, 0}, {"type2", RR_SDF_PHYSICAL, table, 1},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    rr_model *m = vehicle_model(cases[c].base, cases[c].sdf, cases[c].table);
    char label[96];
    snprintf(label, sizeof label, "case %zu (%s sdf %d%s)", c, cases[c].base, cases[c].sdf,
             cases[c].table ? " table" : "");
    compare_modal_direct(m, cases[c].rg, label);
    rr_model_free(m);
  }
  rr_model *m = four_sdf_dampers();
  compare_modal_direct(m, 1, "type2 with four paper-mode SDF dampers");
  rr_model_free(m);
}

/* Near zero conicity the rigid lateral drift is a nearly defective double
   eigenvalue: the modal plan must notice its ill-conditioned basis and solve
   directly, and stay within 1e-10 of the direct route either way. */
static void test_near_defective(void)
{
  rr_model *m = vehicle_model("type1", RR_SDF_PAPER, NULL);
  rr_frf_plan *pm = floor_plan(m, RR_FRF_MODAL, 0), *pd = floor_plan(m, RR_FRF_DIRECT, 0),
              *ps = floor_plan(m, RR_FRF_SPARSE, 0);
  const double lam[] = {1e-2, 1e-3, 1e-5, 1e-7, 1e-10, 1e-12};
  const enum rr_frf_method route[] = {RR_FRF_MODAL,  RR_FRF_MODAL,  RR_FRF_MODAL,
                                      RR_FRF_DIRECT, RR_FRF_DIRECT, RR_FRF_DIRECT};
  for (int c = 0; c < 6; c++) {
    rr_error e;
    CHECK_OK(rr_model_set_operating(m, 300 / RR_KMH, lam[c], &e), e);
    CHECK_OK(rr_frf_plan_execute(pm, m, &e), e);
    CHECK_OK(rr_frf_plan_execute(pd, m, &e), e);
    CHECK(rr_frf_route(pm) == route[c], "conicity %g: route %d, expected %d", lam[c],
          rr_frf_route(pm), route[c]);
    double worst = frf_diff(rr_frf_H(pm), rr_frf_H(pd), 400, 12);
    CHECK(worst < 1e-10, "conicity %g: modal plan vs direct rel diff %.3g", lam[c], worst);
    CHECK_OK(rr_frf_plan_execute(ps, m, &e), e); /* no basis to be ill-conditioned */
    worst = frf_diff(rr_frf_H(ps), rr_frf_H(pd), 400, 12);
    CHECK(worst < 1e-12, "conicity %g: sparse vs dense rel diff %.3g", lam[c], worst);
  }
  rr_frf_plan_free(ps);
  rr_frf_plan_free(pm);
  rr_frf_plan_free(pd);
  rr_model_free(m);
}

/* A wheelset on a lateral spring, almost no lateral creep: near the spring's
   resonance (~8.8 Hz) the lateral diagonal of D nearly vanishes beside the
   yaw moment the longitudinal creep couples in, so the sparse route's
   no-interchange factorisation fails its growth test there. */
static rr_model *weak_wheelset(void)
{
  rr_error e;
  rr_system *sys;
  int bw = -1;
  CHECK_OK(rr_system_new(&sys, &e), e);
  rr_body_spec w = {.name = "w",
                    .group = RR_GROUP_WHEELSET,
                    .mass = 1639,
                    .yaw_inertia = 822,
                    .ref = {0, 0, 0.46},
                    .dofs = RR_DOF_Y | RR_DOF_PSI};
  CHECK_OK(rr_system_add_body(sys, &w, &bw, &e), e);
  rr_element_spec ky = {.name = "ky",
                        .body_a = bw,
                        .body_b = RR_GROUND,
                        .point = {0, 0, 0.46},
                        .direction = RR_DIR_Y,
                        .law = RR_LAW_SPRING,
                        .k = 5e6};
  CHECK_OK(rr_system_add_element(sys, &ky, NULL, &e), e);
  for (int sd = -1; sd <= 1; sd += 2) {
    rr_element_spec kx = {.name = "kx",
                          .body_a = bw,
                          .body_b = RR_GROUND,
                          .point = {0, sd * 1.0, 0.46},
                          .direction = RR_DIR_X,
                          .law = RR_LAW_MAXWELL,
                          .k = 1e6,
                          .c = 2e4};
    CHECK_OK(rr_system_add_element(sys, &kx, NULL, &e), e);
  }
  rr_contact_spec c = {.body = bw, .f11 = 1e7, .f22 = 1, .r0 = 0.46, .l0 = 0.7465};
  CHECK_OK(rr_system_add_contact(sys, &c, NULL, &e), e);
  rr_model *m = NULL;
  CHECK_OK(rr_model_new(sys, &m, &e), e);
  rr_system_free(sys);
  CHECK_OK(rr_model_set_operating(m, 300 / RR_KMH, 0.2, &e), e);
  return m;
}

/* The sparse route: lanes that fail the growth test are solved with
   pivoting (counted) and agree with the dense solve; a frequency's result
   depends on nothing but the model and that frequency (the same bits in
   another lane, in reverse order, after another model). */
static void test_sparse_route(void)
{
  rr_model *m = weak_wheelset(), *other = vehicle_model("type2", RR_SDF_PAPER, NULL);
  rr_error e;
  double rows[4] = {1, 0, 0, 1}, f[400], fr[400];
  for (int k = 0; k < 400; k++) f[k] = 0.3 * pow(100, k / 399.0), fr[399 - k] = f[k];
  rr_frf_opts o = {400, f, 0, 0, 2, rows, NULL, RR_FRF_DIRECT};
  rr_frf_plan *pd;
  CHECK_OK(rr_frf_plan_new(m, &o, &pd, &e), e);
  CHECK_OK(rr_frf_plan_execute(pd, m, &e), e);
  rr_frf_sparse sp;
  rr_block b = {0};
  rr_frf_sparse_layout(&sp, 2, 1, 2, &b);
  CHECK(!rr_block_alloc(&b), "sparse workspace");
  rr_frf_sparse_layout(&sp, 2, 1, 2, &b);
  double complex H[800], Hr[800], H2[800];
  rr_frf_sparse_execute(&sp, m, f, 400, rows, NULL, NULL, H);
  CHECK(sp.codelet == -1, "a two-DOF model: the interpreter");
  long fallbacks = sp.ds->n_pivoting;
  CHECK(fallbacks >= 3 && fallbacks < 100, "lanes solved with pivoting: %ld", fallbacks);
  double worst = frf_diff(H, rr_frf_H(pd), 400, 2);
  CHECK(worst < 1e-12, "weak wheelset: sparse vs dense rel diff %.3g", worst);
  rr_frf_sparse_execute(&sp, m, fr, 400, rows, NULL, NULL, Hr);
  int same = 1;
  for (int k = 0; k < 400; k++) same &= !memcmp(H + 2 * k, Hr + 2 * (399 - k), sizeof H[0] * 2);
  CHECK(same, "sparse: a frequency's bits in another lane");
  free(b.base);
  rr_frf_plan_free(pd);
  /* through the plan: another model in between changes nothing */
  o.method = RR_FRF_SPARSE;
  rr_frf_plan *ps;
  CHECK_OK(rr_frf_plan_new(m, &o, &ps, &e), e);
  CHECK_OK(rr_frf_plan_execute(ps, m, &e), e);
  memcpy(H2, rr_frf_H(ps), sizeof H2);
  CHECK(!memcmp(H2, H, sizeof H), "sparse plan: the workspace's bits");
  rr_frf_plan *po = floor_plan(other, RR_FRF_SPARSE, 0);
  CHECK_OK(rr_frf_plan_execute(po, other, &e), e);
  CHECK_OK(rr_frf_plan_execute(ps, m, &e), e);
  CHECK(!memcmp(rr_frf_H(ps), H2, sizeof H2), "sparse plan: the same bits a second time");
  rr_frf_plan_free(po);
  rr_frf_plan_free(ps);
  rr_model_free(other);
  rr_model_free(m);
}

/* One sparse execute on a fresh workspace: every input or (lag) their
   lagged sum, by a codelet where one fits or (interpret) the interpreter;
   returns the codelet that ran (-1: the interpreter). */
static int sparse_run(rr_model *m, const double *f, const double *rows, const double *rows0,
                      const double complex *lag, int interpret, double complex *H)
{
  rr_frf_sparse sp;
  rr_block b = {0};
  int n = rr_model_ndof(m), ni = rr_model_ninputs(m);
  rr_frf_sparse_layout(&sp, n, ni, 3, &b);
  CHECK(!rr_block_alloc(&b), "sparse workspace");
  rr_frf_sparse_layout(&sp, n, ni, 3, &b);
  sp.interpret = interpret;
  rr_frf_sparse_execute(&sp, m, f, 400, rows, rows0, lag, H);
  free(b.base);
  return sp.codelet;
}

/* The generated codelets: every built-in structure (two vehicles, three SDF
   treatments, gravitational stiffness on and off, roll gravity on and off)
   runs on one and gets the interpreter's bits, for every input and for the
   lagged sum, which agrees with the inputs' responses summed; a structure
   the generator never saw (a vehicle with no secondary lateral damper) runs
   on the interpreter and agrees with the dense solve. */
static void test_codelets(void)
{
  static double complex H[2][400 * 3 * 4], S[400 * 3];
  static double complex lag[400 * 4];
  double f[400];
  for (int k = 0; k < 400; k++) f[k] = 0.3 * pow(100, k / 399.0);
  int runs = 0;
  for (int t = 0; t < 24; t++) {
    rr_vehicle v;
    rr_error e;
    rr_vehicle_builtin(t < 12 ? "type1" : "type2", &v, &e);
    v.sdf_mode = (int[]){RR_SDF_NONE, RR_SDF_PAPER, RR_SDF_PHYSICAL}[t / 4 % 3];
    v.gravity_stiffness = t / 2 % 2;
    rr_model *m;
    CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
    CHECK_OK(rr_model_set_operating(m, 330 / RR_KMH, 0.25, &e), e);
    double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[3 * 17], rows0[3 * 17];
    CHECK_OK(rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, t % 2, rows, rows0, &e), e);
    const double *r0 = t % 2 ? rows0 : NULL;
    for (int k = 0; k < 400; k++)
      for (int i = 0; i < 4; i++)
        lag[k * 4 + i] = cexp(I * 2 * RR_PI * f[k] * rr_model_input_x(m, i) / (330 / RR_KMH));
    for (int sum = 0; sum < 2; sum++) {
      size_t nh = 400 * 3 * (sum ? 1 : 4);
      int c = sparse_run(m, f, rows, r0, sum ? lag : NULL, 0, H[0]);
      CHECK(c >= 0, "case %d: a built-in structure without a codelet", t);
      CHECK(sparse_run(m, f, rows, r0, sum ? lag : NULL, 1, H[1]) == -1, "interpret");
      runs += !memcmp(H[0], H[1], nh * sizeof H[0][0]);
      CHECK(!memcmp(H[0], H[1], nh * sizeof H[0][0]),
            "case %d, sum %d: the codelet's bits are the interpreter's", t, sum);
    }
    /* H[1] holds the lagged sum, H[0] every input's response */
    sparse_run(m, f, rows, r0, NULL, 0, H[0]);
    for (int k = 0; k < 400 * 3; k++) {
      S[k] = 0;
      for (int i = 0; i < 4; i++) S[k] += H[0][k * 4 + i] * lag[k / 3 * 4 + i];
    }
    double d = frf_diff(H[1], S, 400, 3);
    CHECK(d < 1e-12, "case %d: the lagged sum solved against the responses summed: %.3g", t, d);
    rr_model_free(m);
  }
  CHECK(runs == 48, "every case on a codelet with the interpreter's bits: %d of 48", runs);
  /* another topology: the interpreter, and the dense solve's answers */
  rr_vehicle v;
  rr_error e;
  rr_vehicle_default(&v);
  v.lateral_damping = 0;
  rr_model *m;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  rr_frf_plan *pd = floor_plan(m, RR_FRF_DIRECT, 0);
  CHECK_OK(rr_frf_plan_execute(pd, m, &e), e);
  double xs[3] = {v.bogie_half_spacing, 0, -v.bogie_half_spacing}, rows[3 * 17];
  CHECK_OK(rr_vehicle_floor_rows(m, &v, xs, 3, 1.2, 0, rows, NULL, &e), e);
  double fp[400];
  memcpy(fp, rr_frf_freqs(pd), sizeof fp);
  CHECK(sparse_run(m, fp, rows, NULL, NULL, 0, H[0]) == -1,
        "no secondary lateral damper: no codelet fits");
  double d = frf_diff(H[0], rr_frf_H(pd), 400, 12);
  CHECK(d < 1e-12, "no secondary lateral damper: the interpreter against the dense solve %.3g", d);
  rr_frf_plan_free(pd);
  rr_model_free(m);
}

/* rr_pem_design, the optimiser's path: the sparse route's PSDs from the
   lagged sum solved directly, against the plan executed and its H combined;
   the plan's H untouched. The modal route executes the plan: the same bits. */
static void test_pem_design(void)
{
  rr_model *m = vehicle_model("type1", RR_SDF_PAPER, NULL);
  rr_error e;
  rr_spectrum sp;
  CHECK_OK(rr_spectrum_open("wuhan-guangzhou", &sp, &e), e);
  static double Gt[400], G[400 * 3], Gd[400 * 3];
  static double complex H[400 * 3 * 4];
  for (int method = RR_FRF_MODAL; method <= RR_FRF_SPARSE; method += RR_FRF_SPARSE - RR_FRF_MODAL) {
    rr_frf_plan *p = floor_plan(m, method, 1);
    CHECK_OK(rr_pem_track(p, &sp, 350 / RR_KMH, Gt, &e), e);
    CHECK_OK(rr_frf_plan_execute(p, m, &e), e);
    CHECK_OK(rr_pem_psd_track(p, m, Gt, G, &e), e);
    memcpy(H, rr_frf_H(p), sizeof H);
    CHECK_OK(rr_pem_design(p, m, Gt, Gd, &e), e);
    double worst = 0;
    for (int k = 0; k < 400 * 3; k++) worst = fmax(worst, fabs(Gd[k] - G[k]) / G[k]);
    if (method == RR_FRF_SPARSE) {
      CHECK(worst < 1e-11, "pem design, sparse: the lagged sum's PSDs within %.3g", worst);
      CHECK(!memcmp(H, rr_frf_H(p), sizeof H), "pem design: the plan's H untouched");
    } else
      CHECK(worst == 0, "pem design, modal: the plan executed, the same bits (%.3g)", worst);
    rr_frf_plan_free(p);
  }
  rr_spectrum_close(&sp);
  rr_model_free(m);
}

static void test_pem(void)
{
  rr_model *m = vehicle_model("type1", RR_SDF_NONE, NULL);
  rr_frf_plan *p = floor_plan(m, RR_FRF_MODAL, 0);
  rr_error e;
  rr_spectrum s;
  rr_frf_plan_execute(p, m, &e);
  rr_spectrum_open("wuhan-guangzhou", &s, &e);
  double *G = malloc(sizeof(double) * 400 * 3);
  /* a spectrum that turns negative in the band the ride uses is an error
     (status 2 at the command line), never a number */
  rr_spectrum neg = {.form = RR_FORM_RATIONAL7,
                     .scale = 1e-6,
                     .valid_lo = 0.01,
                     .valid_hi = 0.02,
                     .p = {0.1, -0.2, 0.001, 0.4, 0.5, 0.6, 0.7}};
  snprintf(neg.path, sizeof neg.path, "neg.txt");
  CHECK(rr_pem_psd(p, m, &neg, G, &e) == RR_EINVAL && strstr(e.msg, "neg.txt: the PSD is negative"),
        "a negative PSD in the band: %s", e.msg);
  CHECK_OK(rr_pem_psd(p, m, &s, G, &e), e);
  const double *f = rr_frf_freqs(p);
  const double complex *H = rr_frf_H(p);
  double v = rr_model_speed(m), x[4];
  for (int i = 0; i < 4; i++) x[i] = rr_model_input_x(m, i);
  /* the direct product H S H^* with the 4x4 cross-spectral matrix of the inputs */
  double worst = 0;
  for (int k = 0; k < 400; k++) {
    double w = 2 * RR_PI * f[k], Gt = rr_spectrum_eval(&s, f[k] / v) / v;
    for (int q = 0; q < 3; q++) {
      const double complex *h = H + (k * 3 + q) * 4;
      double complex acc = 0;
      double scale = 0; /* the incoherent sum: the lags can cancel the coherent one */
      for (int i = 0; i < 4; i++) {
        scale += 4 * Gt * creal(h[i] * conj(h[i]));
        for (int j = 0; j < 4; j++) acc += h[i] * Gt * cexp(I * w * (x[i] - x[j]) / v) * conj(h[j]);
      }
      worst = fmax(worst, fabs(creal(acc) - G[k * 3 + q]) / scale);
      CHECK(fabs(cimag(acc)) <= 1e-13 * scale, "H S H* is real");
    }
  }
  CHECK(worst < 1e-12, "PEM vs H S H*: rel diff %.3g", worst);
  /* identical inputs: the lag factor 16 cos^2(w b/v) cos^2(w L/v) */
  double complex ones[4] = {1, 1, 1, 1};
  double L = 8.6875, b = 1.25;
  for (double fr = 0.3; fr < 30; fr *= 1.7) {
    double w = 2 * RR_PI * fr, cb = cos(w * b / v), cl = cos(w * L / v);
    CHECK_CLOSE(rr_pem_combine(ones, x, 4, w, v, 1.0), 16 * cb * cb * cl * cl, 1e-12, 1e-12,
                "lag factor");
  }
  /* at low frequency the car follows the track: sum_i H_pi / (-w^2) -> 1 */
  rr_vehicle vv;
  rr_vehicle_default(&vv);
  double xs[1] = {0}, rows[17];
  rr_vehicle_floor_rows(m, &vv, xs, 1, 1.2, 0, rows, NULL, &e);
  double flow = 0.002;
  rr_frf_opts o = {1, &flow, 0, 0, 1, rows, NULL, RR_FRF_DIRECT};
  rr_frf_plan *p0;
  rr_frf_plan_new(m, &o, &p0, &e);
  rr_frf_plan_execute(p0, m, &e);
  double complex sum = 0;
  for (int i = 0; i < 4; i++) sum += rr_frf_H(p0)[i];
  double w0 = 2 * RR_PI * 0.002;
  CHECK_CLOSE(creal(sum / (-w0 * w0)), 1, 0, 1e-3, "quasi-static following");
  rr_frf_plan_free(p0);
  free(G);
  rr_frf_plan_free(p);
  rr_model_free(m);
}

static void test_comfort(void)
{
  rr_error e;
  /* a sinusoid of amplitude A at f0: a spike of area A^2/2 on a uniform grid */
  double f[301], G[301];
  for (int i = 0; i <= 300; i++) {
    f[i] = 0.2 + 0.1 * i;
    G[i] = 0;
  }
  int k0 = 18; /* f0 = 2.0 Hz */
  double A = 0.3;
  CHECK_CLOSE(f[k0], 2.0, 1e-14, 0, "spike at 2 Hz");
  G[k0] = A * A / 2 / 0.1;
  double W;
  CHECK_OK(rr_sperling_filter_index(f, G, 301, 1, RR_AXIS_LATERAL, &W, &e), e);
  /* B_s(2 Hz) by hand from docs/model.md section 7 */
  double num = 1.911 * 4 + pow(0.25 * 4, 2),
         den = pow(1 - 0.277 * 4, 2) + pow(1.563 * 2 - 0.0368 * 8, 2);
  double Bw = 1.25 * 0.588 * sqrt(num / den);
  CHECK_CLOSE(W, 4.42 * pow(Bw * A / sqrt(2), 0.3), 1e-12, 0, "Sperling filter, sinusoid");
  CHECK_CLOSE(rr_psd_rms(f, G, 301, 1), A / sqrt(2), 1e-12, 0, "RMS of a sinusoid");
  /* GB line method: a sinusoid at a band centre on a 0.2 Hz grid aligned to the centres */
  double g2[100], G2[100];
  for (int i = 0; i < 100; i++) {
    g2[i] = 0.4 + 0.2 * i;
    G2[i] = 0;
  }                          /* 0.4, 0.6, ... */
  G2[7] = A * A / (2 * 0.2); /* f = 1.8 Hz */
  CHECK_OK(rr_sperling_gb_index(g2, G2, 100, 1, RR_AXIS_LATERAL, &W, &e), e);
  CHECK_CLOSE(W, 3.57 * pow(A * A * A * 0.8 * 1.8 * 1.8 / 1.8, 0.1), 1e-12, 0,
              "GB line method, lateral 1.8 Hz");
  for (int i = 0; i < 100; i++) G2[i] = 0;
  G2[49] = A * A / (2 * 0.2); /* f = 10.2 Hz */
  CHECK_OK(rr_sperling_gb_index(g2, G2, 100, 1, RR_AXIS_VERTICAL, &W, &e), e);
  CHECK_CLOSE(W, 3.57 * pow(A * A * A * (400 / (10.2 * 10.2)) / 10.2, 0.1), 1e-12, 0,
              "GB line method, vertical 10.2 Hz");
  CHECK(rr_sperling_gb_factor(5.4, RR_AXIS_LATERAL) == 0.8 * 5.4 * 5.4 &&
            rr_sperling_gb_factor(26, RR_AXIS_LATERAL) == 650 / 676.0 &&
            rr_sperling_gb_factor(30, RR_AXIS_LATERAL) == 1,
        "breakpoints take the lower formula");
  /* a flat PSD: RMS = sqrt(G0 (f2 - f1)) */
  for (int i = 0; i <= 300; i++) G[i] = 0.01;
  CHECK_CLOSE(rr_psd_rms(f, G, 301, 1), sqrt(0.01 * 30), 1e-12, 0, "flat RMS");
  /* ISO 8041-1 Annex B design-goal factors at the third-octave centres 10^(n/10) Hz */
  struct {
    int wt, n;
    double v;
  } tab[] = {
      {RR_ISO_WD, -5, 0.533},   {RR_ISO_WD, 0, 1.011},  {RR_ISO_WD, 3, 0.8913},
      {RR_ISO_WD, 6, 0.5143},   {RR_ISO_WD, 9, 0.255},  {RR_ISO_WD, 12, 0.1266},
      {RR_ISO_WD, 20, 0.01414}, {RR_ISO_WB, 0, 0.3853}, {RR_ISO_WB, 8, 1.054},
      {RR_ISO_WB, 20, 0.1154},  {RR_ISO_WC, 0, 0.991},  {RR_ISO_WC, 10, 0.7762},
      {RR_ISO_WK, 8, 1.054},    {RR_ISO_WK, 0, 0.4825}, {RR_ISO_WK, 14, 0.5103},
  };
  for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++) {
    double fc = pow(10, tab[i].n / 10.0);
    char what[64];
    snprintf(what, sizeof what, "ISO 8041 weighting %d at %.4g Hz", tab[i].wt, fc);
    CHECK_CLOSE(cabs(rr_iso8041_weight(tab[i].wt, fc)), tab[i].v, 6e-4, 0, what);
  }
  double aw;
  for (int i = 0; i <= 300; i++) G[i] = 0;
  G[k0] = A * A / 2 / 0.1;
  CHECK_OK(rr_weighted_rms(f, G, 301, 1, RR_ISO_WD, &aw, &e), e);
  CHECK_CLOSE(aw, cabs(rr_iso8041_weight(RR_ISO_WD, 2.0)) * A / sqrt(2), 1e-12, 0,
              "Wd RMS of a sinusoid");
  CHECK(rr_sperling_gb_index(f, G, 1, 1, 0, &W, &e) == RR_EINVAL, "one point refused");
}

/* The library's ride plan (ride.h) against the stages assembled by hand:
   the same bits for the paper's defaults, the direct FRF route through the
   plan agreeing with the modal one, the PSD's integral giving the RMS, and
   its limits refused. */
/* Two ride points field by field, to the bit (memcmp would read padding). */
static int same_point(const rr_ride_point *a, const rr_ride_point *b)
{
  const double da[7] = {a->x, a->rms, a->sperling, a->sperling_gb, a->wd_rms, a->n_mv, a->zeta_max},
               db[7] = {b->x, b->rms, b->sperling, b->sperling_gb, b->wd_rms, b->n_mv, b->zeta_max};
  return !memcmp(da, db, sizeof da) && a->stable == b->stable;
}

static void test_ride_plan(void)
{
  rr_ride_opts d = rr_ride_opts_default();
  CHECK(d.nfreq == 400 && d.f_lo_hz == 0.3 && d.f_hi_hz == 30 && d.floor_height_m == 1.2 &&
            d.npoints == 0 && !d.roll_gravity && d.method == RR_FRF_SPARSE && !d.freqs_hz,
        "the ride defaults are the paper's");
  rr_vehicle v;
  rr_error e;
  rr_vehicle_builtin("type1", &v, &e);
  rr_ride_point pt[3], pd[3];
  CHECK_OK(rr_ride_evaluate(&v, 350 / RR_KMH, 0.2, NULL, NULL, pt, &e), e);
  rr_model *m = vehicle_model("type1", RR_SDF_NONE, NULL);
  rr_frf_plan *fp = floor_plan(m, RR_FRF_SPARSE, 0);
  rr_comfort_plan *cp;
  rr_spectrum s;
  double G[400 * 3], Gi[400 * 3], Gt0[400];
  CHECK_OK(rr_spectrum_open("wuhan-guangzhou", &s, &e), e);
  /* the plan solves for the inputs' lagged sum (rr_pem_design) */
  CHECK_OK(rr_pem_track(fp, &s, 350 / RR_KMH, Gt0, &e), e);
  CHECK_OK(rr_pem_design(fp, m, Gt0, G, &e), e);
  /* every input's response, then the PEM's sum: the same within rounding */
  CHECK_OK(rr_frf_plan_execute(fp, m, &e), e);
  CHECK_OK(rr_pem_psd(fp, m, &s, Gi, &e), e);
  for (int k = 0; k < 400 * 3; k++)
    CHECK_CLOSE(G[k], Gi[k], 1e-11, 0, "the lagged sum's PSD against every input's");
  CHECK_OK(rr_comfort_plan_new(rr_frf_freqs(fp), 400, RR_AXIS_LATERAL, &cp, &e), e);
  for (int q = 0; q < 3; q++) {
    rr_comfort c;
    CHECK_OK(rr_comfort_execute(cp, G + q, 3, &c, &e), e);
    CHECK(pt[q].x == (q == 1 ? 0 : (1 - q) * v.bogie_half_spacing) && pt[q].rms == c.rms &&
              pt[q].sperling == c.sperling && pt[q].sperling_gb == c.sperling_gb &&
              pt[q].wd_rms == c.wd_rms && pt[q].n_mv == rr_en12299_comfort(c.wd_rms),
          "ride plan point %d: the hand-assembled stages' bits", q);
  }
  rr_ride_opts o = rr_ride_opts_default();
  o.method = RR_FRF_DIRECT;
  rr_ride_plan *rp;
  CHECK_OK(rr_ride_plan_new(m, &v, &o, &rp, &e), e);
  CHECK_OK(rr_ride_execute(rp, m, &s, pd, &e), e);
  CHECK(rr_ride_npoints(rp) == 3 && rr_ride_nfreq(rp) == 400, "the plan's sizes");
  const double *f = rr_ride_freqs(rp), *Gp = rr_ride_psd(rp);
  for (int q = 0; q < 3; q++) {
    CHECK_CLOSE(pd[q].sperling, pt[q].sperling, 1e-9, 0, "direct route through the plan");
    double I2 = 0;
    for (int k = 1; k < 400; k++)
      I2 += 0.5 * (f[k] - f[k - 1]) * (Gp[k * 3 + q] + Gp[(k - 1) * 3 + q]);
    CHECK_CLOSE(sqrt(I2), pd[q].rms, 1e-13, 0, "the RMS is the PSD's integral");
  }
  rr_ride_plan_free(rp);
  /* the two-step path an optimiser takes (the track once, then designs) gives
     the one-call path's bits, and refuses a model at another speed */
  rr_ride_point p2[3];
  CHECK_OK(rr_ride_plan_new(m, &v, NULL, &rp, &e), e);
  CHECK(rr_ride_design(rp, m, p2, &e) == RR_EINVAL, "no track set: refused (%s)", e.msg);
  CHECK_OK(rr_ride_plan_set_track(rp, &s, 350 / RR_KMH, &e), e);
  for (int rep = 0; rep < 2; rep++) {
    CHECK_OK(rr_ride_design(rp, m, p2, &e), e);
    for (int q = 0; q < 3; q++)
      CHECK(same_point(&p2[q], &pt[q]), "two-step ride, point %d: the same bits", q);
  }
  double Gt[400];
  CHECK_OK(rr_pem_track(fp, &s, 350 / RR_KMH, Gt, &e), e);
  double G2[400 * 3];
  CHECK_OK(rr_pem_psd_track(fp, m, Gt, G2, &e), e);
  CHECK(!memcmp(Gi, G2, sizeof Gi), "rr_pem_psd_track: rr_pem_psd's bits");
  CHECK(rr_pem_track(fp, &s, 0, Gt, &e) == RR_EINVAL, "a zero speed refused: %s", e.msg);
  rr_model_set_operating(m, 300 / RR_KMH, 0.2, &e);
  CHECK(rr_ride_design(rp, m, p2, &e) == RR_EINVAL, "a model at another speed refused: %s", e.msg);
  rr_model_set_operating(m, 350 / RR_KMH, 0.2, &e);
  rr_ride_plan_free(rp);
  o.npoints = RR_RIDE_POINTS_MAX + 1;
  CHECK(rr_ride_plan_new(m, &v, &o, &rp, &e) == RR_EINVAL && !rp, "17 floor points refused");
  CHECK(rr_ride_evaluate(&v, 350 / RR_KMH, 0.2, "tbt3352-vertical", NULL, pt, &e) == RR_EINVAL,
        "a vertical spectrum refused: %s", e.msg);
  rr_comfort_plan_free(cp);
  rr_frf_plan_free(fp);
  rr_spectrum_close(&s);
  rr_model_free(m);
}

int main(void)
{
  if (check_tmpdir("ride")) return 1;
  check_spectra_env();
  test_spectra();
  test_modal_vs_direct();
  test_near_defective();
  test_sparse_route();
  test_codelets();
  test_pem_design();
  test_pem();
  test_comfort();
  test_ride_plan();
  check_cleanup();
  return check_done("ride");
}
