/* `railride summary`: the main job. Stability summary of a vehicle: hunting
 * modes at 350 km/h, robust indices, critical speeds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

int cmd_summary(int argc, char **argv)
{
  static const char help[] = "usage: railride summary [VEHICLE] [--speed KMH] [--conicity L] [--json]\n"
                             "Stability summary: modes at the operating point (default 350 km/h, 0.17), robust\n"
                             "indices, critical speeds at conicities 0.05, 0.17, 0.40; ride comfort (PEM,\n"
                             "wuhan-guangzhou spectrum) at those conicities with and without the yaw damper SDF.\n" CLI_COMMON_HELP;
  cli_common c;
  int r = cli_parse(argc, argv, &c, NULL, NULL, NULL, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (!c.have_speed) c.speed_kmh = 350;
  if (!c.have_conicity) c.conicity = 0.17;
  c.have_speed = c.have_conicity = 1;
  rr_model *m;
  if ((r = cli_model(&c, &m, 1, 1))) return r;
  rr_error e;
  rr_modal_ws *ws = NULL;
  rr_modal_result res;
  int st = rr_modal_ws_new(m, &ws, &e);
  if (!st) st = rr_modal_result_alloc(m, &res, &e);
  if (!st) st = rr_modal_solve(m, &c.mo, ws, &res, &e);
  if (st) { rr_modal_ws_free(ws); rr_model_free(m); return cli_fail(&e, st); }
  rr_robust rb;
  st = rr_robust_indices(m, &c.mo, NULL, ws, &rb, &e);
  const double lams[3] = {0.05, 0.17, 0.40};
  double vc[3];
  int found[3];
  for (int i = 0; i < 3 && !st; i++) st = rr_critical_speed(m, lams[i], &c.mo, NULL, ws, &vc[i], &found[i], &e);
  rr_modal_ws_free(ws);
  rr_model_free(m);
  if (st) { rr_modal_result_free(&res); return cli_fail(&e, st); }
  /* ride table: conicities 0.05, 0.17, 0.40 with the yaw damper's series
     stiffness constant and with its SDF curve (paper mode: k_sdf(f)) */
  ride_setup rs;
  ride_setup_default(&rs, &c.veh);
  ride_point rp[2][3][3];
  rr_vehicle vr[2] = {c.veh, c.veh};
  vr[0].sdf_mode = RR_SDF_NONE;
  vr[1].sdf_mode = c.veh.sdf_mode != RR_SDF_NONE ? c.veh.sdf_mode : RR_SDF_PAPER;
  int have_curve = c.veh.sdf.kind != RR_CURVE_UNSET;
  for (int s = 0; s < (have_curve ? 2 : 1) && !st; s++)
    for (int i = 0; i < 3 && !st; i++) st = ride_eval(&vr[s], c.speed_kmh, lams[i], &rs, rp[s][i], NULL, NULL, &e);
  if (st) { rr_modal_result_free(&res); return cli_fail(&e, st); }
  const char *sdf = c.veh.sdf_mode == RR_SDF_PAPER ? "paper" : c.veh.sdf_mode == RR_SDF_PHYSICAL ? "physical" : "none";
  if (c.json) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "vehicle", c.veh.name);
    cJSON_AddStringToObject(root, "sdf", sdf);
    cJSON_AddNumberToObject(root, "speed_kmh", c.speed_kmh);
    cJSON_AddNumberToObject(root, "conicity", c.conicity);
    cJSON_AddNumberToObject(root, "stability_index", res.stability_index);
    cJSON_AddNumberToObject(root, "zeta_low", rb.zeta_low);
    cJSON_AddNumberToObject(root, "zeta_high", rb.zeta_high);
    cJSON_AddNumberToObject(root, "std_zeta", rb.std_zeta);
    cJSON *cs = cJSON_AddArrayToObject(root, "critical_speeds");
    for (int i = 0; i < 3; i++) {
      cJSON *o = cJSON_CreateObject();
      cJSON_AddNumberToObject(o, "conicity", lams[i]);
      if (found[i]) cJSON_AddNumberToObject(o, "critical_speed_kmh", vc[i] * 3.6);
      else cJSON_AddNullToObject(o, "critical_speed_kmh");
      cJSON_AddItemToArray(cs, o);
    }
    cJSON *ride = cJSON_AddArrayToObject(root, "ride");
    for (int s = 0; s < (have_curve ? 2 : 1); s++)
      for (int i = 0; i < 3; i++) {
        cJSON *o = cJSON_CreateObject(), *pa = cJSON_AddArrayToObject(o, "points");
        cJSON_AddNumberToObject(o, "conicity", lams[i]);
        cJSON_AddStringToObject(o, "yaw_series", s ? "sdf" : "constant");
        for (int q = 0; q < 3; q++) {
          cJSON *po = cJSON_CreateObject();
          cJSON_AddNumberToObject(po, "x", rp[s][i][q].x);
          cJSON_AddNumberToObject(po, "sperling", rp[s][i][q].sperling);
          cJSON_AddNumberToObject(po, "sperling_gb", rp[s][i][q].sperling_gb);
          cJSON_AddNumberToObject(po, "wd_rms", rp[s][i][q].wd_rms);
          cJSON_AddItemToArray(pa, po);
        }
        cJSON_AddItemToArray(ride, o);
      }
    cli_json_print(root);
  } else {
    printf("railride stability summary: vehicle %s (yaw damper SDF: %s)\n\n", c.veh.name, sdf);
    printf("Hunting-related modes at %g km/h, conicity %g (f <= %g Hz, wheelset share >= %g):\n", c.speed_kmh,
           c.conicity, c.mo.fmax_hz, c.mo.w_min);
    printf("  %9s %10s %9s %9s %9s\n", "freq_hz", "zeta", "E_car", "E_frame", "E_wheel");
    for (int i = 0; i < res.n; i++) {
      const rr_mode *md = &res.modes[i];
      if (!md->in_index) continue;
      printf("  %9.4f %10.5f %9.2e %9.2e %9.2e%s\n", md->freq_hz, md->zeta, md->energy[0], md->energy[1], md->energy[2],
             i == res.index_mode ? "  <- least damped" : "");
    }
    printf("  vehicle stability index: %.6f (negative is stable)\n\n", res.stability_index);
    printf("Robust indices (paper Table 1):\n");
    printf("  zeta_low  (250 km/h, 0.05) = %10.6f\n  zeta_high (350 km/h, 0.40) = %10.6f\n  std_zeta  (350 km/h, 8 conicities) = %10.6f\n\n",
           rb.zeta_low, rb.zeta_high, rb.std_zeta);
    printf("Critical speed (10-600 km/h):\n");
    for (int i = 0; i < 3; i++) {
      if (found[i]) printf("  conicity %.2f: %10.3f km/h\n", lams[i], vc[i] * 3.6);
      else printf("  conicity %.2f: stable to 600 km/h\n", lams[i]);
    }
    printf("\nRide comfort at %g km/h, spectrum %s (PEM, 0.3-30 Hz), floor height %g m:\n", c.speed_kmh, rs.spectrum, rs.h_p);
    printf("  Sperling W, weighting-filter method, at x = +L / 0 / -L; wd_rms: ISO 2631-1 Wd, worst point\n");
    printf("  %8s  %-26s %7s %7s %7s %12s\n", "conicity", "yaw damper series spring", "W(+L)", "W(0)", "W(-L)", "wd_rms_m/s2");
    for (int i = 0; i < 3; i++)
      for (int s = 0; s < (have_curve ? 2 : 1); s++) {
        const ride_point *p = rp[s][i];
        char lab[64];
        if (s) snprintf(lab, sizeof lab, "SDF (%s mode)", vr[1].sdf_mode == RR_SDF_PAPER ? "paper" : "physical");
        else snprintf(lab, sizeof lab, "constant %g MN/m", c.veh.yaw_series_stiffness / 1e6);
        printf("  %8.2f  %-26s %7.3f %7.3f %7.3f %12.5f\n", lams[i], lab, p[0].sperling, p[1].sperling, p[2].sperling,
               fmax(p[0].wd_rms, fmax(p[1].wd_rms, p[2].wd_rms)));
      }
  }
  rr_modal_result_free(&res);
  return 0;
}
