/* `railride summary`: the main job. Stability summary of a vehicle: hunting
 * modes at the operating point, robust indices, critical speeds, and the ride
 * table with and without the yaw damper's SDF. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

#define NLAMS 3
static const double lams[NLAMS] = {0.05, 0.17, 0.40};

typedef struct summary {
  rr_modal_result res;
  rr_robust rb;
  rr_critical crit[NLAMS];
  int have_curve;
  rr_vehicle vr[2]; /* constant series stiffness, SDF */
  ride_point rp[2][NLAMS][3];
  ride_setup rs;
  vertical_setup vs;
  vertical_both vb[3]; /* the vertical model and EN 12299 at the operating point */
  cli_progress pr;     /* a step per analysis: modes, robust, each critical speed and ride point */
} summary;

static int stability_part(cli_common *c, summary *s, rr_error *e)
{
  rr_model *m;
  int r = cli_model(c, &m, 1, 1);
  if (r) return -r;
  rr_modal_ws *ws = NULL;
  int st = rr_modal_ws_new(m, &ws, e);
  if (!st) st = rr_modal_result_alloc(m, &s->res, e);
  if (!st) st = rr_modal_solve(m, &c->mo, ws, &s->res, e);
  cli_progress_step(&s->pr, 1);
  if (!st) st = rr_robust_indices(m, &c->mo, NULL, ws, &s->rb, e);
  cli_progress_step(&s->pr, 1);
  for (int i = 0; i < NLAMS && !st; i++) {
    st = rr_critical_speed(m, lams[i], &c->mo, NULL, ws, &s->crit[i], e);
    cli_progress_step(&s->pr, 1);
  }
  rr_modal_ws_free(ws);
  rr_model_free(m);
  return st;
}

/* Ride at the three conicities with the yaw damper's series stiffness
   constant and with its SDF curve (paper mode: k_sdf(f)). */
static int ride_part(const cli_common *c, summary *s, rr_error *e)
{
  ride_setup_default(&s->rs, &c->veh);
  s->vr[0] = s->vr[1] = c->veh;
  s->vr[0].sdf_mode = RR_SDF_NONE;
  s->vr[1].sdf_mode = c->veh.sdf_mode != RR_SDF_NONE ? c->veh.sdf_mode : RR_SDF_PAPER;
  int st = RR_OK;
  for (int k = 0; k < (s->have_curve ? 2 : 1) && !st; k++)
    for (int i = 0; i < NLAMS && !st; i++) {
      st = ride_eval(&s->vr[k], c->speed_kmh, lams[i], &s->rs, s->rp[k][i], NULL, NULL, e);
      cli_progress_step(&s->pr, 1);
    }
  vertical_setup_default(&s->vs);
  if (!st) st = vertical_eval(&c->veh, c->speed_kmh, &s->rs, &s->vs, c->conicity, s->vb, e);
  cli_progress_step(&s->pr, 1);
  return st;
}

static cJSON *vertical_json(const cli_common *c, const summary *s)
{
  cJSON *v = cJSON_CreateObject(), *pa = cJSON_AddArrayToObject(v, "points");
  cJSON_AddStringToObject(v, "spectrum", s->vs.spectrum);
  cJSON_AddStringToObject(v, "lateral_spectrum", s->rs.spectrum);
  cJSON_AddNumberToObject(v, "conicity", c->conicity);
  for (int q = 0; q < 3; q++) {
    const vertical_both *b = &s->vb[q];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "x", b->z.x);
    cJSON_AddNumberToObject(o, "sperling", b->z.sperling);
    cJSON_AddNumberToObject(o, "sperling_gb", b->z.sperling_gb);
    cJSON_AddNumberToObject(o, "wb_rms", b->z.wb_rms);
    cJSON_AddNumberToObject(o, "wb_p95", b->z.wb_5s.p95);
    cJSON_AddNumberToObject(o, "wd_p95", b->wd.p95);
    cJSON_AddNumberToObject(o, "n_mv", b->en.n_mv);
    cJSON_AddNumberToObject(o, "n_vd", b->en.n_vd);
    cJSON_AddNumberToObject(o, "n_va_rigid_seat", b->en.n_va_rigid_seat);
    cJSON_AddStringToObject(o, "comfort", rr_en12299_scale(b->en.n_mv));
    cJSON_AddItemToArray(pa, o);
  }
  return v;
}

static void vertical_text(const cli_common *c, const summary *s)
{
  printf("\nVertical ride and EN 12299 mean comfort at %g km/h (vertical %s; lateral %s at "
         "conicity %g; longitudinal 0, rigid seat):\n",
         c->speed_kmh, s->vs.spectrum, s->rs.spectrum, c->conicity);
  printf("  %8s %7s %7s %10s %10s %7s %7s %7s  %s\n", "x_m", "Wz", "Wz_gb", "az_p95", "ay_p95",
         "N_MV", "N_VD", "N_VA", "comfort (N_MV)");
  for (int q = 0; q < 3; q++) {
    const vertical_both *b = &s->vb[q];
    printf("  %8.4g %7.3f %7.3f %10.5f %10.5f %7.3f %7.3f %7.3f  %s\n", b->z.x, b->z.sperling,
           b->z.sperling_gb, b->z.wb_5s.p95, b->wd.p95, b->en.n_mv, b->en.n_vd,
           b->en.n_va_rigid_seat, rr_en12299_scale(b->en.n_mv));
  }
}

static const char *sdf_name(int mode)
{
  return mode == RR_SDF_PAPER ? "paper" : mode == RR_SDF_PHYSICAL ? "physical" : "none";
}

static void summary_json(const cli_common *c, const summary *s)
{
  cJSON *root = cJSON_CreateObject();
  int paper = c->veh.sdf_mode == RR_SDF_PAPER;
  cJSON_AddStringToObject(root, "vehicle", c->veh.name);
  cJSON_AddStringToObject(root, "sdf", sdf_name(c->veh.sdf_mode));
  cJSON_AddNumberToObject(root, "speed_kmh", c->speed_kmh);
  cJSON_AddNumberToObject(root, "conicity", c->conicity);
  cJSON_AddStringToObject(root, "conicity_source", c->conicity_source);
  cJSON_AddNumberToObject(root, "stability_index", s->res.stability_index); /* NaN: null */
  cJSON_AddStringToObject(root, "index_source", cli_index_source_key(s->res.index_source));
  cJSON_AddBoolToObject(root, "stable", rr_modal_stable(s->res.zeta_max));
  cJSON_AddNumberToObject(root, "zeta_max", s->res.zeta_max);
  cli_band_json(root, &c->mo, s->res.fmax_hz);
  if (s->res.index_mode >= 0)
    cJSON_AddItemToObject(root, "index_mode",
                          cli_mode_json(&s->res.modes[s->res.index_mode], paper));
  cJSON_AddNumberToObject(root, "zeta_low", s->rb.zeta_low);
  cJSON_AddNumberToObject(root, "zeta_high", s->rb.zeta_high);
  cJSON_AddNumberToObject(root, "std_zeta", s->rb.std_zeta);
  cJSON_AddBoolToObject(root, "robust_points_stable", s->rb.n_unstable == 0);
  cJSON *cs = cJSON_AddArrayToObject(root, "critical_speeds");
  for (int i = 0; i < NLAMS; i++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "conicity", lams[i]);
    if (s->crit[i].found) {
      cJSON_AddNumberToObject(o, "critical_speed_kmh", s->crit[i].speed_ms * RR_KMH);
      cJSON_AddItemToObject(o, "mode", cli_mode_json(&s->crit[i].mode, paper));
    } else {
      cJSON_AddNullToObject(o, "critical_speed_kmh");
    }
    cJSON_AddItemToArray(cs, o);
  }
  cJSON *ride = cJSON_AddArrayToObject(root, "ride");
  for (int k = 0; k < (s->have_curve ? 2 : 1); k++)
    for (int i = 0; i < NLAMS; i++) {
      cJSON *o = cJSON_CreateObject(), *pa = cJSON_AddArrayToObject(o, "points");
      cJSON_AddNumberToObject(o, "conicity", lams[i]);
      cJSON_AddStringToObject(o, "yaw_series", k ? "sdf" : "constant");
      for (int q = 0; q < 3; q++) {
        cJSON *po = cJSON_CreateObject();
        cJSON_AddNumberToObject(po, "x", s->rp[k][i][q].x);
        cJSON_AddNumberToObject(po, "sperling", s->rp[k][i][q].sperling);
        cJSON_AddNumberToObject(po, "sperling_gb", s->rp[k][i][q].sperling_gb);
        cJSON_AddNumberToObject(po, "wd_rms", s->rp[k][i][q].wd_rms);
        cJSON_AddBoolToObject(po, "stable", s->rp[k][i][q].stable == 1);
        cJSON_AddItemToArray(pa, po);
      }
      cJSON_AddItemToArray(ride, o);
    }
  cJSON_AddItemToObject(root, "vertical", vertical_json(c, s));
  cli_json_print(root);
}

static void modes_text(const cli_common *c, const rr_modal_result *res)
{
  printf("Hunting-related modes at %g km/h, conicity %g (%s; f <= %.2f Hz, %s; wheelset share "
         ">= %g, frame-roll share < %g):\n",
         c->speed_kmh, c->conicity, c->conicity_source, res->fmax_hz, cli_band_rule(&c->mo),
         c->mo.w_min, c->mo.r_max);
  printf("  %9s %10s %9s %9s %9s %9s  %s\n", "freq_hz", "zeta", "E_car", "E_frame", "E_wheel",
         "fr_roll", "mode");
  for (int i = 0; i < res->n; i++) {
    const rr_mode *md = &res->modes[i];
    if (!md->in_index && i != res->index_mode) continue;
    printf("  %9.4f %10.5f %9.2e %9.2e %9.2e %9.2e  %s%s\n", md->freq_hz, md->zeta, md->energy[0],
           md->energy[1], md->energy[2], md->frame_roll_share, md->name,
           i == res->index_mode ? "  <- sets the index" : "");
  }
  char buf[256];
  cli_index_text(buf, sizeof buf, res->stability_index, res->index_source,
                 res->index_mode >= 0 ? &res->modes[res->index_mode] : NULL, NAN, &c->mo,
                 res->fmax_hz);
  printf("  vehicle stability index: %s (negative is stable)\n", buf);
  if (res->max_mode >= 0)
    printf("  verdict: %s (least damped of all modes: %s at %.4f Hz, zeta %.6f)\n\n",
           rr_modal_stable(res->zeta_max) ? "stable" : "UNSTABLE", res->modes[res->max_mode].name,
           res->modes[res->max_mode].freq_hz, res->zeta_max);
}

static void stability_text(const summary *s)
{
  const rr_robust *rb = &s->rb;
  printf("Robust indices (paper Table 1):\n");
  char b1[32], b2[32], b3[32];
  printf("  zeta_low  (250 km/h, 0.05) = %10s\n  zeta_high (350 km/h, 0.40) = %10s\n"
         "  std_zeta  (350 km/h, 8 conicities) = %10s\n",
         cli_num_or_none(b1, sizeof b1, rb->zeta_low),
         cli_num_or_none(b2, sizeof b2, rb->zeta_high),
         cli_num_or_none(b3, sizeof b3, rb->std_zeta));
  if (rb->n_unstable == 0)
    printf("  verdict: stable at every robust point\n\n");
  else
    printf("  verdict: UNSTABLE at %d robust points (first: %g km/h, conicity %g)\n\n",
           rb->n_unstable, rb->unstable_speed_ms * RR_KMH, rb->unstable_conicity);
  printf("Critical speed (" CLI_CRITICAL_RANGE "; any oscillatory mode reaching zeta = 0):\n");
  for (int i = 0; i < NLAMS; i++) {
    const rr_critical *cr = &s->crit[i];
    if (cr->found)
      printf("  conicity %.2f: %10.3f km/h  (%s at %.3f Hz%s)\n", lams[i], cr->speed_ms * RR_KMH,
             cr->mode.name, cr->mode.freq_hz, cr->mode.hunting ? ", hunting-related" : "");
    else
      printf("  conicity %.2f: stable to " CLI_CRITICAL_TOP "\n", lams[i]);
  }
}

static void ride_text(const cli_common *c, const summary *s)
{
  printf("\nRide comfort at %g km/h, spectrum %s (PEM, 0.3-30 Hz), floor height %g m:\n",
         c->speed_kmh, s->rs.spectrum, s->rs.h_p);
  printf("  Sperling W, weighting-filter method, at x = +L / 0 / -L; wd_rms: ISO 2631-1 Wd, worst "
         "point\n");
  printf("  %8s  %-26s %7s %7s %7s %12s\n", "conicity", "yaw damper series spring", "W(+L)", "W(0)",
         "W(-L)", "wd_rms_m/s2");
  for (int i = 0; i < NLAMS; i++)
    for (int k = 0; k < (s->have_curve ? 2 : 1); k++) {
      const ride_point *p = s->rp[k][i];
      char lab[64];
      if (k)
        snprintf(lab, sizeof lab, "SDF (%s mode)", sdf_name(s->vr[1].sdf_mode));
      else
        snprintf(lab, sizeof lab, "constant %g MN/m", c->veh.yaw_series_stiffness / 1e6);
      char b[4][32];
      printf("  %8.2f  %-26s %7s %7s %7s %12s\n", lams[i], lab,
             ride_num(b[0], 32, 3, p[0].sperling, p[0].stable),
             ride_num(b[1], 32, 3, p[1].sperling, p[1].stable),
             ride_num(b[2], 32, 3, p[2].sperling, p[2].stable),
             ride_num(b[3], 32, 5, fmax(p[0].wd_rms, fmax(p[1].wd_rms, p[2].wd_rms)), p[0].stable));
    }
}

int cmd_summary(int argc, char **argv)
{
  static const char help[] =
      "usage: railride summary [VEHICLE] [--speed KMH] [--conicity L] [--json]\n"
      "Stability summary: modes at the operating point (default 350 km/h, 0.17), robust\n"
      "indices, critical speeds at conicities 0.05, 0.17, 0.40; ride comfort (PEM,\n"
      "wuhan-guangzhou spectrum) at those conicities with and without the yaw damper "
      "SDF;\nthe vertical ride (tbt3352-vertical) and EN 12299's N_MV, N_VD, N_VA at the floor "
      "points.\n" CLI_COMMON_HELP;
  cli_common c;
  int r = cli_parse(argc, argv, &c,
                    CLI_READS_SPEED | CLI_READS_CONICITY | CLI_READS_JSON | CLI_READS_INDEX |
                        CLI_READS_GRAVITY | CLI_READS_PROGRESS,
                    NULL, NULL, NULL, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (!c.have_speed) c.speed_kmh = CLI_SPEED_DEFAULT_KMH;
  if (!c.have_conicity) c.conicity = CLI_CONICITY_DEFAULT;
  c.have_speed = c.have_conicity = 1;
  summary *s = calloc(1, sizeof *s);
  if (!s) return cli_bad("out of memory");
  rr_error e;
  s->have_curve = c.veh.sdf.kind != RR_CURVE_UNSET;
  cli_progress_start(&s->pr, "summary", 3 + NLAMS + NLAMS * (s->have_curve ? 2 : 1), c.progress);
  int st = stability_part(&c, s, &e);
  if (st < 0) {
    free(s);
    return -st;
  } /* message printed */
  if (!st) st = ride_part(&c, s, &e);
  cli_progress_end(&s->pr);
  if (!st && c.json) summary_json(&c, s);
  if (!st && !c.json) {
    printf("railride stability summary: vehicle %s (yaw damper SDF: %s)\n\n", c.veh.name,
           sdf_name(c.veh.sdf_mode));
    modes_text(&c, &s->res);
    stability_text(s);
    ride_text(&c, s);
    vertical_text(&c, s);
  }
  rr_modal_result_free(&s->res);
  free(s);
  return st ? cli_fail(&e, st) : 0;
}
