#define _POSIX_C_SOURCE 200809L
/* The stability index that measures hunting (roll modes out), the critical
 * speed over every oscillatory mode, verdicts, mode names, objective
 * modifiers, and paper-mode SDF: fast tracking against the reference. The
 * headline numbers come from an independent computation of the revised rule. */
#include <string.h>
#include "railride/railride.h"
#include "check.h"

static rr_model *model_of(const char *name, int sdf)
{
  rr_vehicle v;
  rr_error e;
  rr_model *m = NULL;
  CHECK_OK(rr_vehicle_builtin(name, &v, &e), e);
  if (sdf >= 0) v.sdf_mode = sdf;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  return m;
}

/* Frame roll (~9.2 Hz, roll share > 0.8) is out of the index; carbody hunting
   (the mode below 3 Hz with the largest carbody share among those that move
   the wheelsets) is in it. */
static void test_roll_out_hunting_in(void)
{
  const char *veh[2] = {"type1", "type2"};
  const double pts[4][2] = {{350, 0.17}, {250, 0.05}, {350, 0.4}, {350, 0.6}};
  for (int k = 0; k < 2; k++) {
    rr_model *m = model_of(veh[k], -1);
    rr_modal_ws *ws;
    rr_modal_result r;
    rr_error e;
    CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
    CHECK_OK(rr_modal_result_alloc(m, &r, &e), e);
    for (int p = 0; p < 4; p++) {
      CHECK_OK(rr_model_set_operating(m, pts[p][0] / RR_KMH, pts[p][1], &e), e);
      CHECK_OK(rr_modal_solve(m, NULL, ws, &r, &e), e);
      int nroll = 0, car = -1;
      for (int i = 0; i < r.n; i++) {
        const rr_mode *md = &r.modes[i];
        if (!md->oscillatory) continue;
        if (md->freq_hz > 8 && md->freq_hz < 11 && md->energy[RR_GROUP_FRAME] > 0.8 &&
            md->roll_share > 0.8) {
          nroll++;
          CHECK(!md->in_index && !md->hunting, "%s %g/%g: frame roll at %g Hz counted", veh[k],
                pts[p][0], pts[p][1], md->freq_hz);
          CHECK(strstr(md->name, "roll") != NULL, "frame roll named '%s'", md->name);
        }
        if (md->freq_hz < 3 && md->energy[RR_GROUP_WHEELSET] >= 1e-3 &&
            (car < 0 || md->energy[RR_GROUP_CARBODY] > r.modes[car].energy[RR_GROUP_CARBODY]))
          car = i;
      }
      CHECK(nroll == 2, "%s %g/%g: %d frame roll modes", veh[k], pts[p][0], pts[p][1], nroll);
      CHECK(car >= 0 && r.modes[car].in_index, "%s %g/%g: carbody hunting not in the index", veh[k],
            pts[p][0], pts[p][1]);
      CHECK(car >= 0 && r.modes[car].roll_share < 0.1, "carbody hunting roll share %g",
            r.modes[car].roll_share);
    }
    rr_modal_result_free(&r);
    rr_modal_ws_free(ws);
    rr_model_free(m);
  }
}

static void check_robust(const char *name, int sdf, double lo, double hi, double sd)
{
  rr_model *m = model_of(name, sdf);
  rr_modal_ws *ws;
  rr_robust rb;
  rr_error e;
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_robust_indices(m, NULL, NULL, ws, &rb, &e), e);
  CHECK_CLOSE(rb.zeta_low, lo, 0, 5e-5, name);
  CHECK_CLOSE(rb.zeta_high, hi, 0, 5e-5, name);
  CHECK_CLOSE(rb.std_zeta, sd, 0, 5e-5, name);
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

/* index_modes: 0 any mode; 1 the index's modes with the default band edge;
   2 the same with the paper's fixed 10 Hz */
static double critical(const char *name, double lam, int index_modes, rr_mode *md)
{
  rr_model *m = model_of(name, -1);
  rr_modal_ws *ws;
  rr_critical cr;
  rr_error e;
  rr_critical_opts co = rr_critical_opts_default();
  rr_modal_opts mo = rr_modal_opts_default();
  co.index_modes = index_modes != 0;
  if (index_modes == 2) mo.fmax_hz = 10;
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_critical_speed(m, lam, &mo, &co, ws, &cr, &e), e);
  if (md) *md = cr.mode;
  rr_modal_ws_free(ws);
  rr_model_free(m);
  return cr.found ? cr.speed_ms * RR_KMH : INFINITY;
}

static void test_headline(void)
{
  check_robust("type1", -1, -0.1182, -0.1884, 0.0687);
  check_robust("type2", -1, 0.0090, -0.0970, 0.1061);
  check_robust("type1", RR_SDF_PAPER, -0.1298, -0.2909, 0.0780);
  const struct {
    const char *v;
    double lam, vc;
  } cs[] = {
      {"type1", 0.4, 524.7}, {"type1", 0.6, 422.1}, {"type2", 0.05, 201.1},
      {"type2", 0.2, 580.8}, {"type2", 0.4, 426.0}, {"type2", 0.6, 347.3},
  };
  for (size_t i = 0; i < sizeof cs / sizeof cs[0]; i++)
    CHECK_CLOSE(critical(cs[i].v, cs[i].lam, 0, NULL), cs[i].vc, 0, 0.05, cs[i].v);
  rr_mode md;
  critical("type1", 0.6, 0, &md);
  CHECK(md.freq_hz > 10 && md.freq_hz < 10.2 && md.hunting,
        "type1 at 0.6: unstable mode %g Hz (hunting %d)", md.freq_hz, md.hunting);
  CHECK(isinf(critical("type1", 0.6, 2, NULL)),
        "type1 at 0.6 with the index's modes below a fixed 10 Hz: stable to 600 km/h");
  /* revision 4: the band reaches f_K (25 Hz there), so the 10.1 Hz bogie mode counts */
  CHECK_CLOSE(critical("type1", 0.6, 1, NULL), 422.1, 0, 0.05,
              "type1 at 0.6 with the index's modes, band edge max(10 Hz, f_K)");
}

/* At conicity 2 the hunting modes of the bogies are above 10 Hz and unstable:
   out of the index, yet the verdict is unstable. */
static void test_verdict_any_mode(void)
{
  rr_model *m = model_of("type1", -1);
  rr_modal_ws *ws;
  rr_modal_result r;
  rr_stability s;
  rr_error e;
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_modal_result_alloc(m, &r, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 2.0, &e), e);
  CHECK_OK(rr_modal_stability(m, NULL, ws, &s, &e), e);
  CHECK_OK(rr_modal_solve(m, NULL, ws, &r, &e), e);
  CHECK(!rr_modal_stable(s.zeta_max) && !rr_modal_stable(r.zeta_max),
        "conicity 2: verdict stable (zeta_max %g)", s.zeta_max);
  int near147 = 0, near188 = 0;
  for (int i = 0; i < r.n; i++)
    if (r.modes[i].oscillatory && r.modes[i].zeta >= 0) {
      near147 |= fabs(r.modes[i].freq_hz - 14.7) < 0.1;
      near188 |= fabs(r.modes[i].freq_hz - 18.8) < 0.1;
    }
  CHECK(near147 && near188, "conicity 2: unstable modes at 14.7 and 18.8 Hz");
  CHECK_CLOSE(s.zeta_max, r.zeta_max, 0, 1e-10, "zeta_max: fast and full");
  /* w_min = 0, r_max = 1: the index over every mode in the band */
  rr_modal_opts all = {.fmax_hz = 10, .w_min = 0, .r_max = 1};
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  CHECK_OK(rr_modal_stability(m, &all, ws, &s, &e), e);
  CHECK_OK(rr_modal_solve(m, &all, ws, &r, &e), e);
  double zb = -1;
  for (int i = 0; i < r.n; i++)
    if (r.modes[i].oscillatory && r.modes[i].freq_hz <= 10) zb = fmax(zb, r.modes[i].zeta);
  CHECK_CLOSE(s.index, zb, 0, 1e-12, "w_min 0, r_max 1: every mode in the band");
  CHECK(!strcmp(r.modes[0].name, "carbody roll"), "0.23 Hz mode named '%s'", r.modes[0].name);
  rr_modal_result_free(&r);
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

/* The robust verdict against rr_modal_stability point by point, in the
   documented order: (v_low, conicity_low), (v_high, conicity_high), then the
   sweep upward (its end point, equal to conicity_high, once). v_low is set
   above v_high so that the first point is unstable and the first unstable
   one reported must be it, however the points are grouped in lanes. */
static void test_robust_first_unstable(void)
{
  const double damping[3] = {4e6, 30e3, 10e3}; /* N s/m a yaw damper: stable, two unstable */
  rr_robust_opts ro = rr_robust_opts_default();
  ro.v_low_ms = 420 / RR_KMH;
  ro.conicity_low = 0.30;
  rr_model *m[3];
  rr_modal_ws *ws;
  rr_error e;
  for (int i = 0; i < 3; i++) {
    rr_vehicle v;
    CHECK_OK(rr_vehicle_builtin("type1", &v, &e), e);
    v.yaw_damping = damping[i];
    CHECK_OK(rr_model_from_vehicle(&v, &m[i], &e), e);
  }
  CHECK_OK(rr_modal_ws_new(m[0], &ws, &e), e);
  rr_robust many[3], one;
  CHECK_OK(rr_robust_indices_many(m, 3, NULL, &ro, ws, many, &e), e);
  for (int i = 0; i < 3; i++) {
    int nc = ro.n_conicity, n = 0;
    double zmax = -1, fv = NAN, fl = NAN, zeta0 = NAN;
    for (int p = 0; p < 2 + nc - 1; p++) {
      double v = p == 0 ? ro.v_low_ms : ro.v_high_ms;
      double lam = p == 0 ? ro.conicity_low
                   : p == 1
                       ? ro.conicity_high
                       : ro.conicity_min + (ro.conicity_max - ro.conicity_min) * (p - 2) / (nc - 1);
      rr_stability s;
      CHECK_OK(rr_model_set_operating(m[i], v, lam, &e), e);
      CHECK_OK(rr_modal_stability(m[i], NULL, ws, &s, &e), e);
      if (p == 0) zeta0 = s.zeta_max;
      zmax = fmax(zmax, s.zeta_max);
      if (!rr_modal_stable(s.zeta_max) && n++ == 0) {
        fv = v;
        fl = lam;
      }
    }
    CHECK(i == 0 ? n == 0 : (n >= 2 && !rr_modal_stable(zeta0)),
          "model %d: %d unstable points (the first unstable too: %g)", i, n, zeta0);
    CHECK(many[i].n_unstable == n && many[i].zeta_max == zmax,
          "model %d: %d unstable points, zeta_max %g (point by point %d, %g)", i,
          many[i].n_unstable, many[i].zeta_max, n, zmax);
    CHECK((isnan(fv) && isnan(many[i].unstable_speed_ms) && isnan(many[i].unstable_conicity)) ||
              (many[i].unstable_speed_ms == fv && many[i].unstable_conicity == fl),
          "model %d: first unstable point %g km/h, conicity %g (point by point %g, %g)", i,
          many[i].unstable_speed_ms * RR_KMH, many[i].unstable_conicity, fv * RR_KMH, fl);
    CHECK_OK(rr_robust_indices(m[i], NULL, &ro, ws, &one, &e), e);
    CHECK(!memcmp(&one, &many[i], sizeof one), "model %d: one by one equals many", i);
  }
  rr_modal_ws_free(ws);
  for (int i = 0; i < 3; i++) rr_model_free(m[i]);
}

/* Objective modifiers reach the value. */
static void test_objective_modifiers(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  const char *objs[7] = {"index@350,0.17;fmax=20;wmin=0;rmax=1",
                         "index@350,0.17",
                         "critical_speed@0.6",
                         "critical_speed@0.6;index_modes;fmax=10",
                         "critical_speed@0.6;index_modes",
                         "critical_speed@0.6;index_modes;fmax=10;vmax=900",
                         "critical_speed@0.4;vmax=900"};
  rr_design *d;
  rr_error e;
  double f[7];
  CHECK_OK(rr_design_new(&v, 0, NULL, 7, objs, &d, &e), e);
  CHECK_OK(rr_design_evaluate(d, NULL, f, &e), e);
  rr_model *m = model_of("type1", -1);
  rr_modal_ws *ws;
  rr_stability s;
  rr_modal_opts o = {.fmax_hz = 20, .w_min = 0, .r_max = 1};
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  CHECK_OK(rr_modal_stability(m, &o, ws, &s, &e), e);
  CHECK_CLOSE(f[0], s.index, 0, 1e-14, "index with modifiers");
  CHECK(fabs(f[0] - f[1]) > 1e-3, "modifiers change the index (%g vs %g)", f[0], f[1]);
  CHECK_CLOSE(f[2], 422.1, 0, 0.05, "critical_speed@0.6");
  CHECK_CLOSE(f[3], 600, 0, 0, "critical_speed@0.6;index_modes;fmax=10");
  CHECK(rr_design_at_bound(d, 3) && !rr_design_at_bound(d, 2), "a value at vmax is flagged");
  CHECK_CLOSE(f[4], f[2], 0, 0, "critical_speed@0.6;index_modes: the any-mode speed (revision 4)");
  CHECK(f[5] == 900 && rr_design_at_bound(d, 5), "vmax=900 raises the range's end (%g)", f[5]);
  CHECK_CLOSE(f[6], 524.7, 0, 0.05, "critical_speed@0.4;vmax=900");
  CHECK(!rr_design_at_bound(d, 6), "a critical speed found is not a bound");
  CHECK(fabs(rr_design_band_edge(d, 1) - rr_modal_band_edge_at(m, NULL, 350 / RR_KMH, 0.17)) <
                1e-12 &&
            rr_design_band_edge(d, 0) == 20 && isnan(rr_design_band_edge(d, 2)),
        "the band edge behind index objectives: %g, %g", rr_design_band_edge(d, 1),
        rr_design_band_edge(d, 0));
  CHECK(rr_design_verdict(d, 1) == 1 && rr_design_verdict(d, 2) == -1, "index objective verdicts");
  {
    /* a ride objective at an unstable point: undefined, the verdict says why */
    const char *ro[1] = {"sperling@450,0.6"};
    rr_design *dr;
    double fr;
    CHECK_OK(rr_design_new(&v, 0, NULL, 1, ro, &dr, &e), e);
    CHECK(rr_design_evaluate(dr, NULL, &fr, &e) == RR_EUNDEF && isnan(fr) &&
              rr_design_verdict(dr, 0) == 0,
          "sperling@450,0.6: undefined (%g), verdict %d", fr, rr_design_verdict(dr, 0));
    rr_design_free(dr);
  }
  CHECK(fabs(rr_design_mode_freq(d, 2) - 10.09) < 0.05, "critical mode frequency %g",
        rr_design_mode_freq(d, 2));
  const char *bad[5] = {"index@350,0.17;rmax=2", "zeta_low;index_modes",
                        "sperling@350,0.17;fmax=20", "critical_speed@0.4;vmax=5",
                        "index@350,0.17;vmax=900"};
  for (int i = 0; i < 5; i++) {
    rr_design *db = NULL;
    CHECK(rr_design_new(&v, 0, NULL, 1, &bad[i], &db, &e) == RR_EINVAL, "objective '%s' accepted",
          bad[i]);
    rr_design_free(db);
  }
  rr_modal_ws_free(ws);
  rr_model_free(m);
  rr_design_free(d);
  /* one model per SDF variant: the vehicle's own and all three named (four) */
  const char *variants[5] = {"index@350,0.17", "index@350,0.17;sdf=none",
                             "index@350,0.17;sdf=paper", "index@350,0.17;sdf=physical",
                             "sperling@350,0.17;sdf=paper"};
  CHECK_OK(rr_design_new(&v, 0, NULL, 5, variants, &d, &e), e);
  double fv[5];
  CHECK_OK(rr_design_evaluate(d, NULL, fv, &e), e);
  CHECK(fv[0] == fv[1] && fv[2] != fv[1] && isfinite(fv[3]) && isfinite(fv[4]),
        "SDF variants %g %g %g %g", fv[0], fv[1], fv[2], fv[3]);
  rr_design_free(d);
}

/* Fast and reference tracking on random SDF designs: the same self-consistent
   modes, |dk| <= 1e-9 k_hi, zeta within 1e-10. */
static void test_sdf_fast_vs_reference(void)
{
  unsigned seed = 11;
  double worst_k = 0, worst_z = 0;
  int mismatch = 0;
  for (int d = 0; d < 20; d++) {
    double r[6];
    for (int k = 0; k < 6; k++) {
      seed = seed * 1664525u + 1013904223u;
      r[k] = (seed >> 8) / 16777216.0;
    }
    rr_vehicle v;
    rr_vehicle_builtin(d % 2 ? "type2" : "type1", &v, NULL);
    v.sdf_mode = RR_SDF_PAPER;
    v.sdf.k1_hz = 0.5 + 4 * r[0];
    v.sdf.k2 = 1e6 + 20e6 * r[1];
    v.sdf.k3 = 1e6 + 15e6 * r[2];
    v.yaw_damping = 100e3 + 3900e3 * r[3];
    rr_model *m;
    rr_modal_ws *ws;
    rr_modal_result a, b;
    rr_error e;
    CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
    CHECK_OK(rr_model_set_operating(m, (150 + 350 * r[4]) / RR_KMH, 0.02 + 0.5 * r[5], &e), e);
    CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
    CHECK_OK(rr_modal_result_alloc(m, &a, &e), e);
    CHECK_OK(rr_modal_result_alloc(m, &b, &e), e);
    rr_modal_opts fast = rr_modal_opts_default(), ref = fast;
    ref.tracking = RR_TRACK_REFERENCE;
    CHECK_OK(rr_modal_solve(m, &fast, ws, &a, &e), e);
    CHECK_OK(rr_modal_solve(m, &ref, ws, &b, &e), e);
    double k_hi = v.sdf.k2 + v.sdf.k3;
    mismatch += a.n != b.n;
    for (int i = 0; i < a.n && i < b.n; i++) {
      if (!b.modes[i].oscillatory) continue;
      mismatch += a.modes[i].self_consistent != b.modes[i].self_consistent;
      worst_k = fmax(worst_k, fabs(a.modes[i].sdf_k - b.modes[i].sdf_k) / k_hi);
      worst_z = fmax(worst_z, fabs(a.modes[i].zeta - b.modes[i].zeta));
    }
    /* the index from eigenvalues only equals the full solve's */
    rr_stability s;
    CHECK_OK(rr_modal_stability(m, NULL, ws, &s, &e), e);
    CHECK_CLOSE(s.index, a.stability_index, 0, 1e-12, "SDF index: fast route and full solve");
    CHECK_CLOSE(s.zeta_max, a.zeta_max, 0, 1e-12, "SDF zeta_max: fast route and full solve");
    rr_modal_result_free(&a);
    rr_modal_result_free(&b);
    rr_modal_ws_free(ws);
    rr_model_free(m);
  }
  printf("  SDF tracking, 20 random designs: worst |dk|/k_hi %.2g, worst |dzeta| %.2g\n", worst_k,
         worst_z);
  CHECK(mismatch == 0, "fast and reference tracking disagree on %d modes", mismatch);
  CHECK(worst_k <= 1e-9, "SDF roots differ by %g k_hi", worst_k);
  CHECK(worst_z <= 1e-10, "SDF zeta differs by %g", worst_z);
}

/* MODEL.md's rule computed here from the full solve's modes (dgeev shapes,
   the mass diagonal and the DOF names), not from the library's flags: the
   frame-roll share from phi_f1 and phi_f2, the hunting modes' largest zeta
   below fmax, zeta_max over every oscillatory mode, the index zeta_max when
   that is >= 0, else the hunting one, else undefined. */
static double independent_index(const rr_model *m, const rr_modal_result *r, const rr_modal_opts *o,
                                double fmax_hz, double *zmax)
{
  const double *M = rr_model_M(m);
  int n = rr_model_ndof(m);
  double hunt = NAN;
  *zmax = -1;
  for (int i = 0; i < r->n; i++) {
    const rr_mode *md = &r->modes[i];
    double l = hypot(md->re, md->im);
    if (!(md->im > 1e-6 * l) || !md->oscillatory) continue;
    const rr_complex *phi = r->shapes + (size_t)i * (size_t)n;
    double tot = 0, wheel = 0, froll = 0;
    for (int k = 0; k < n; k++) {
      const char *nm = rr_model_dof_name(m, k);
      double t = M[k * n + k] * creal(phi[k] * conj(phi[k]));
      tot += t;
      if (!strncmp(nm, "y_w", 3) || !strncmp(nm, "psi_w", 5)) wheel += t;
      if (!strcmp(nm, "phi_f1") || !strcmp(nm, "phi_f2")) froll += t;
    }
    double z = md->re / l;
    *zmax = fmax(*zmax, z);
    if (md->im / (2 * RR_PI) <= fmax_hz && wheel / tot >= o->w_min && froll / tot < o->r_max &&
        !(z <= hunt))
      hunt = z;
  }
  return *zmax >= 0 ? *zmax : hunt;
}

/* Revision 3: the index's sign is the verdict everywhere; an undefined
   index is NaN (never -1); the fast route, the full solve and the rule
   computed independently agree on a map of each vehicle. */
static void test_sign_is_verdict(void)
{
  const char *veh[6] = {"type1",
                        "type2",
                        "../examples/paper-design-A.ini",
                        "../examples/paper-design-B.ini",
                        "../examples/paper-design-C.ini",
                        "../examples/paper-design-D.ini"};
  enum { NS = 11, NC = 13 };
  int outside = 0;
  for (int k = 0; k < 6; k++) {
    rr_vehicle v;
    rr_model *m;
    rr_modal_ws *ws;
    rr_modal_result r;
    rr_error e;
    CHECK_OK(rr_vehicle_open(veh[k], &v, &e), e);
    CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
    CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
    CHECK_OK(rr_modal_result_alloc(m, &r, &e), e);
    double sp[NS * NC], lam[NS * NC];
    rr_stability z[NS * NC];
    for (int i = 0; i < NS; i++)
      for (int j = 0; j < NC; j++) {
        sp[i * NC + j] = (100 + 50.0 * i) / RR_KMH;
        lam[i * NC + j] = 0.02 + (0.6 - 0.02) * j / (NC - 1);
      }
    for (int rule = 0; rule < 2; rule++) { /* revision 4's band edge, and a fixed 10 Hz */
      rr_modal_opts o = rr_modal_opts_default();
      if (rule) o.fmax_hz = 10;
      CHECK_OK(rr_modal_stability_batch(m, &o, ws, NS * NC, sp, lam, z, &e), e);
      int bad_sign = 0, minus1 = 0, bad_full = 0, bad_indep = 0, bad_edge = 0;
      for (int p = 0; p < NS * NC; p++) {
        int stable = rr_modal_stable(z[p].zeta_max);
        if (isnan(z[p].index))
          bad_sign += !(stable && z[p].source == RR_INDEX_NONE);
        else
          bad_sign += (z[p].index < 0) != stable;
        minus1 += z[p].index == -1;
        outside += rule && z[p].source == RR_INDEX_UNSTABLE;
        /* MODEL.md section 5: f_K = (v / 2 pi) sqrt(lambda / (r0 l0)), 10 Hz at the least */
        double fk =
            sp[p] / (2 * RR_PI) * sqrt(lam[p] / (v.rolling_radius * v.contact_half_spacing));
        double edge = rule ? 10 : fmax(10, fk);
        bad_edge += fabs(z[p].fmax_hz - edge) > 1e-12 * edge;
        CHECK_OK(rr_model_set_operating(m, sp[p], lam[p], &e), e);
        CHECK_OK(rr_modal_solve(m, &o, ws, &r, &e), e);
        double zmax, ind = independent_index(m, &r, &o, edge, &zmax);
        bad_full += !(fabs(r.stability_index - z[p].index) <= 1e-9 ||
                      (isnan(r.stability_index) && isnan(z[p].index)));
        bad_indep += !(fabs(ind - z[p].index) <= 1e-6 || (isnan(ind) && isnan(z[p].index)));
      }
      CHECK(bad_sign == 0, "%s: %d points where the index's sign is not the verdict", veh[k],
            bad_sign);
      CHECK(minus1 == 0, "%s: %d points with index -1", veh[k], minus1);
      CHECK(bad_full == 0, "%s: fast route and full solve disagree at %d points", veh[k], bad_full);
      CHECK(bad_indep == 0, "%s (rule %d): %d points differ from the independent rule", veh[k],
            rule, bad_indep);
      CHECK(bad_edge == 0, "%s (rule %d): %d points with another band edge", veh[k], rule,
            bad_edge);
    }
    rr_modal_result_free(&r);
    rr_modal_ws_free(ws);
    rr_model_free(m);
  }
  CHECK(outside > 50, "the maps should hold unstable modes outside the hunting band (%d)", outside);
  /* Type 1 at 430 km/h, conicity 0.6: the bogie mode at 10.11 Hz is
     unstable above the band; the index says so */
  rr_model *m = model_of("type1", -1);
  rr_modal_ws *ws;
  rr_stability s;
  rr_error e;
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  rr_modal_opts ten = rr_modal_opts_default();
  ten.fmax_hz = 10;
  CHECK_OK(rr_model_set_operating(m, 430 / RR_KMH, 0.6, &e), e);
  CHECK_OK(rr_modal_stability(m, &ten, ws, &s, &e), e);
  CHECK(s.source == RR_INDEX_UNSTABLE && s.index > 0 && fabs(s.index_freq_hz - 10.11) < 0.01 &&
            s.hunting_index < 0,
        "430 km/h, 0.6, fmax 10: index %g (source %d) at %g Hz, hunting modes %g", s.index,
        s.source, s.index_freq_hz, s.hunting_index);
  /* revision 4: the band edge there is f_K = 25.13 Hz, the mode is a hunting one */
  CHECK_OK(rr_modal_stability(m, NULL, ws, &s, &e), e);
  CHECK(s.source == RR_INDEX_HUNTING && s.index > 0 && fabs(s.index_freq_hz - 10.11) < 0.01 &&
            fabs(s.fmax_hz - 25.13) < 0.01,
        "430 km/h, 0.6: index %g (source %d) at %g Hz, band edge %g Hz", s.index, s.source,
        s.index_freq_hz, s.fmax_hz);
  /* no mode below fmax = 0.1 Hz and all stable: undefined */
  rr_modal_opts lo = rr_modal_opts_default();
  lo.fmax_hz = 0.1;
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  CHECK_OK(rr_modal_stability(m, &lo, ws, &s, &e), e);
  CHECK(isnan(s.index) && s.source == RR_INDEX_NONE && s.zeta_max < 0,
        "fmax 0.1 Hz: index %g, source %d", s.index, s.source);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  /* as a design objective: the design fails, never scores */
  rr_vehicle v;
  rr_vehicle_default(&v);
  const char *keys[1] = {"yaw_damper.damping"};
  const char *objs[2] = {"index@350,0.17;fmax=0.1", "index@430,0.6"};
  rr_design *d;
  double x[1] = {v.yaw_damping}, f[2];
  CHECK_OK(rr_design_new(&v, 1, keys, 1, objs, &d, &e), e);
  CHECK(rr_design_evaluate(d, x, f, &e) != 0 && isnan(f[0]), "an undefined objective: %g", f[0]);
  rr_design_free(d);
  CHECK_OK(rr_design_new(&v, 1, keys, 1, objs + 1, &d, &e), e);
  CHECK_OK(rr_design_evaluate(d, x, f, &e), e);
  CHECK(f[0] > 0, "index@430,0.6 as an objective: %g (unstable: positive)", f[0]);
  rr_design_free(d);
}

/* Revision 4: a design whose bogie hunting modes sit just above 10 Hz
   (10.0004 and 10.0478 Hz at 350 km/h, 0.4) keeps them in the index; the
   paper's fixed 10 Hz dropped them and the index jumped to a well-damped
   1.72 Hz carbody mode (-0.5466 instead of -0.1252). */
static void test_band_edge_keeps_hunting(void)
{
  rr_vehicle v;
  rr_error e;
  rr_model *m;
  rr_modal_ws *ws;
  rr_stability s, s10;
  rr_vehicle_default(&v);
  v.primary_kx = 10.0026e6;
  v.lateral_damping = 59.9409e3;
  v.yaw_damping = 1361.72e3;
  v.yaw_series_stiffness = 27.6832e6;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.4, &e), e);
  rr_modal_opts ten = rr_modal_opts_default();
  ten.fmax_hz = 10;
  CHECK_OK(rr_modal_stability(m, NULL, ws, &s, &e), e);
  CHECK_OK(rr_modal_stability(m, &ten, ws, &s10, &e), e);
  double fk = 350 / RR_KMH / (2 * RR_PI) * sqrt(0.4 / (v.rolling_radius * v.contact_half_spacing));
  CHECK_CLOSE(s.fmax_hz, fk, 1e-13, 0, "the band edge is f_K");
  CHECK_CLOSE(rr_modal_band_edge(m, NULL), fk, 1e-13, 0, "rr_modal_band_edge");
  CHECK(s.source == RR_INDEX_HUNTING && s.index_freq_hz > 10 && s.index_freq_hz < fk,
        "the bogie mode above 10 Hz sets the index: %g Hz", s.index_freq_hz);
  CHECK_CLOSE(s.index, -0.12519, 0, 5e-5, "index with the band edge at f_K");
  CHECK_CLOSE(s10.index, -0.54661, 0, 5e-5, "index with the paper's fixed 10 Hz");
  CHECK(s10.index_freq_hz < 2, "the fixed edge's index from the carbody mode (%g Hz)",
        s10.index_freq_hz);
  /* at 250 km/h, 0.05 f_K is 4.2 Hz: the floor of 10 Hz holds */
  CHECK_OK(rr_model_set_operating(m, 250 / RR_KMH, 0.05, &e), e);
  CHECK_CLOSE(rr_modal_band_edge(m, NULL), 10, 0, 0, "the 10 Hz floor");
  CHECK_CLOSE(rr_model_kinematic_hz(m, 250 / RR_KMH, 0.05), 4.2, 0, 0.05, "f_K at 250, 0.05");
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

/* Revision 3's frame-roll rule: with a typical carbody roll inertia,
   carbody hunting (roll share ~0.74) stays in the index (MODEL.md: Type 1
   zeta_low -0.0370 from the 1.05 Hz mode, wheelset share 0.057). */
static void test_typical_inertias(void)
{
  rr_vehicle v;
  rr_error e;
  rr_model *m;
  rr_modal_ws *ws;
  rr_robust rb;
  CHECK_OK(rr_vehicle_builtin("type1", &v, &e), e);
  v.carbody_roll_inertia = 9.61e4;
  v.carbody_yaw_inertia = 1.67e6;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_robust_indices(m, NULL, NULL, ws, &rb, &e), e);
  CHECK_CLOSE(rb.zeta_low, -0.0370, 0, 5e-5, "type1, typical inertias: zeta_low");
  rr_modal_result r;
  CHECK_OK(rr_modal_result_alloc(m, &r, &e), e);
  CHECK_OK(rr_model_set_operating(m, 250 / RR_KMH, 0.05, &e), e);
  CHECK_OK(rr_modal_solve(m, NULL, ws, &r, &e), e);
  const rr_mode *md = r.index_mode >= 0 ? &r.modes[r.index_mode] : NULL;
  CHECK(md && fabs(md->freq_hz - 1.05) < 0.01 &&
            fabs(md->energy[RR_GROUP_WHEELSET] - 0.057) < 1e-3 && md->roll_share > 0.7 &&
            md->frame_roll_share < 0.05,
        "the index's mode: %g Hz, wheelset share %g, roll %g", md ? md->freq_hz : NAN,
        md ? md->energy[RR_GROUP_WHEELSET] : NAN, md ? md->roll_share : NAN);
  rr_modal_result_free(&r);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  /* Type 2 with those inertias goes unstable at ~148 km/h (conicity 0.05)
     through carbody hunting: a hunting-related mode now */
  CHECK_OK(rr_vehicle_builtin("type2", &v, &e), e);
  v.carbody_roll_inertia = 9.61e4;
  v.carbody_yaw_inertia = 1.67e6;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  rr_critical cr;
  CHECK_OK(rr_critical_speed(m, 0.05, NULL, NULL, ws, &cr, &e), e);
  CHECK(cr.found && fabs(cr.speed_ms * RR_KMH - 147.8) < 0.5 && cr.mode.hunting &&
            cr.mode.energy[RR_GROUP_WHEELSET] > 0.05 && cr.mode.frame_roll_share < 0.05,
        "type2, typical inertias: critical %g km/h through '%s' (hunting %d)", cr.speed_ms * RR_KMH,
        cr.mode.name, cr.mode.hunting);
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

/* Every oscillatory mode of every point lies on exactly one branch of the
   locus (Fig. 8a: conicity 0.1, 20-500 km/h x 25; Fig. 8b: 350 km/h,
   conicity 0.02-0.5), so the index's mode is always on the locus; a mode
   that becomes oscillatory mid-range starts a branch of its own there, and
   no row has f = 0. */
static void locus_complete(const char *veh, rr_locus_param par, double fixed, double a, double b,
                           int *born_late)
{
  enum { NP = 25 };
  rr_model *m = model_of(veh, -1);
  rr_error e;
  double vals[NP];
  for (int i = 0; i < NP; i++) vals[i] = a + (b - a) * i / (NP - 1);
  if (par == RR_LOCUS_SPEED)
    rr_model_set_operating(m, 300 / RR_KMH, fixed, &e);
  else
    rr_model_set_operating(m, fixed, 0.1, &e);
  int S = rr_locus_stride(m), nb = 0;
  rr_locus_point *pts = malloc(sizeof *pts * NP * (size_t)S);
  CHECK_OK(rr_locus(m, par, vals, NP, NULL, NULL, pts, &nb, &e), e);
  rr_modal_ws *ws;
  rr_modal_result r;
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_modal_result_alloc(m, &r, &e), e);
  int missing = 0, zero_f = 0, index_off = 0, count_off = 0;
  for (int p = 0; p < NP; p++) {
    double v = par == RR_LOCUS_SPEED ? vals[p] : fixed, l = par == RR_LOCUS_SPEED ? fixed : vals[p];
    CHECK_OK(rr_model_set_operating(m, v, l, &e), e);
    CHECK_OK(rr_modal_solve(m, NULL, ws, &r, &e), e);
    int nosc = 0, alive = 0;
    for (int i = 0; i < r.n; i++) {
      if (!r.modes[i].oscillatory) continue;
      nosc++;
      int on = 0;
      for (int bb = 0; bb < nb; bb++)
        on += pts[p * S + bb].re == r.modes[i].re && pts[p * S + bb].im == r.modes[i].im;
      missing += on != 1;
    }
    for (int bb = 0; bb < nb; bb++) {
      const rr_locus_point *q = &pts[p * S + bb];
      if (isnan(q->re)) continue;
      alive++;
      zero_f += !(q->freq_hz > 0);
      if (p > 0 && isnan(pts[(p - 1) * S + bb].re) && bb > 0 && p > 0) {
        int before = 0; /* born here: no row of it before */
        for (int p2 = 0; p2 < p; p2++) before += !isnan(pts[p2 * S + bb].re);
        *born_late += before == 0;
      }
    }
    count_off += alive != nosc;
    int on_index = 0;
    for (int bb = 0; bb < nb; bb++) on_index |= pts[p * S + bb].zeta == r.stability_index;
    index_off += !on_index;
  }
  CHECK(missing == 0 && count_off == 0,
        "%s locus: %d modes not on exactly one branch, %d points "
        "whose live branches are not their oscillatory modes",
        veh, missing, count_off);
  CHECK(zero_f == 0, "%s locus: %d rows with f = 0", veh, zero_f);
  CHECK(index_off == 0, "%s locus: the index's mode missing at %d points", veh, index_off);
  rr_modal_result_free(&r);
  rr_modal_ws_free(ws);
  free(pts);
  rr_model_free(m);
}

static void test_locus_every_mode(void)
{
  int late8a = 0, late8b = 0, late_low = 0;
  locus_complete("type1", RR_LOCUS_SPEED, 0.1, 20 / RR_KMH, 500 / RR_KMH, &late8a);
  locus_complete("type1", RR_LOCUS_CONICITY, 350 / RR_KMH, 0.02, 0.5, &late8b);
  locus_complete("type2", RR_LOCUS_SPEED, 0.02, 20 / RR_KMH, 500 / RR_KMH, &late_low);
  CHECK(late8a > 0 && late_low > 0,
        "modes that become oscillatory mid-range start branches "
        "(Fig. 8a %d, low conicity %d)",
        late8a, late_low);
  printf("  locus: branches born mid-range: Fig. 8a %d, Fig. 8b %d, Type 2 at conicity 0.02 %d\n",
         late8a, late8b, late_low);
}

/* A table whose stiffness spans seven decades (found by fuzz_sdf_table):
   branches whose steps halve without end are lost after a bounded number of
   steps, by both trackings, instead of walking the range in ever smaller
   steps; the index still gives the verdict. */
static void test_sdf_steep_table(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  v.sdf_mode = RR_SDF_PAPER;
  v.sdf = (rr_sdf_curve){.kind = RR_CURVE_TABLE,
                         .n = 2,
                         .has_loss = 1,
                         .f_hz = {1.0, 10.0},
                         .k_storage = {10e6, 12.6e13},
                         .k_loss = {2.9e6, 0}};
  rr_model *m;
  rr_modal_ws *ws;
  rr_error e;
  CHECK_OK(rr_model_from_vehicle(&v, &m, &e), e);
  CHECK_OK(rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e), e);
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  rr_modal_opts fast = rr_modal_opts_default(), ref = fast;
  ref.tracking = RR_TRACK_REFERENCE;
  const rr_modal_opts *opts[2] = {&fast, &ref};
  for (int t = 0; t < 2; t++) {
    rr_stability s;
    CHECK_OK(rr_modal_stability(m, opts[t], ws, &s, &e), e);
    CHECK(s.source == RR_INDEX_NONE ||
              (s.index >= -1 && s.index <= 1 && rr_modal_stable(s.zeta_max) == (s.index < 0)),
          "steep SDF table (%s tracking): index %g is not the verdict (zeta_max %g)",
          t ? "reference" : "fast", s.index, s.zeta_max);
  }
  rr_modal_ws_free(ws);
  rr_model_free(m);
}

int main(void)
{
  test_roll_out_hunting_in();
  test_headline();
  test_verdict_any_mode();
  test_robust_first_unstable();
  test_objective_modifiers();
  test_sdf_fast_vs_reference();
  test_sdf_steep_table();
  test_sign_is_verdict();
  test_band_edge_keeps_hunting();
  test_typical_inertias();
  test_locus_every_mode();
  return check_done("stability");
}
