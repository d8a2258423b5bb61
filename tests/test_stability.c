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

static double critical(const char *name, double lam, int index_modes, rr_mode *md)
{
  rr_model *m = model_of(name, -1);
  rr_modal_ws *ws;
  rr_critical cr;
  rr_error e;
  rr_critical_opts co = rr_critical_opts_default();
  co.index_modes = index_modes;
  CHECK_OK(rr_modal_ws_new(m, &ws, &e), e);
  CHECK_OK(rr_critical_speed(m, lam, NULL, &co, ws, &cr, &e), e);
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
  CHECK(isinf(critical("type1", 0.6, 1, NULL)),
        "type1 at 0.6 with the index's modes: stable to 600 km/h");
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

/* Objective modifiers reach the value. */
static void test_objective_modifiers(void)
{
  rr_vehicle v;
  rr_vehicle_default(&v);
  const char *objs[4] = {"index@350,0.17;fmax=20;wmin=0;rmax=1", "index@350,0.17",
                         "critical_speed@0.6", "critical_speed@0.6;index_modes"};
  rr_design *d;
  rr_error e;
  double f[4];
  CHECK_OK(rr_design_new(&v, 0, NULL, 4, objs, &d, &e), e);
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
  CHECK_CLOSE(f[3], 600, 0, 0, "critical_speed@0.6;index_modes");
  CHECK(fabs(rr_design_mode_freq(d, 2) - 10.09) < 0.05, "critical mode frequency %g",
        rr_design_mode_freq(d, 2));
  const char *bad[3] = {"index@350,0.17;rmax=2", "zeta_low;index_modes",
                        "sperling@350,0.17;fmax=20"};
  for (int i = 0; i < 3; i++) {
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

int main(void)
{
  test_roll_out_hunting_in();
  test_headline();
  test_verdict_any_mode();
  test_objective_modifiers();
  test_sdf_fast_vs_reference();
  return check_done("stability");
}
