/* The vertical side of ride, frf and modes (--direction vertical|both): the
 * vertical model's PEM and indices at the floor points, EN 12299's mean
 * comfort with the lateral model's Wd percentiles, its FRFs and its modes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "outfile.h"

void vertical_setup_default(vertical_setup *v)
{
  *v = (vertical_setup){.direction = CLI_DIR_LATERAL,
                        .spectrum = RR_VERTICAL_SPECTRUM_DEFAULT,
                        .outside = -1,
                        .window_s = RR_VERTICAL_WINDOW_DEFAULT,
                        .hp = RR_FLOOR_HEIGHT_DEFAULT};
}

int cli_direction_scan(const char *cmd, int argc, char **argv)
{
  static const char *const names[] = {"lateral", "vertical", "both"};
  int dir = CLI_DIR_LATERAL;
  for (int i = 1; i < argc; i++) {
    const char *v = NULL;
    if (!strcmp(argv[i], "--direction"))
      v = i + 1 < argc ? argv[++i] : "";
    else if (!strncmp(argv[i], "--direction=", 12))
      v = argv[i] + 12;
    else
      continue;
    int k = 0;
    while (k < 3 && strcmp(v, names[k])) k++;
    if (k == 3)
      return cli_bad("%s: --direction: lateral, vertical or both expected, got '%s'", cmd, v), -1;
    dir = k;
  }
  return dir;
}

int cli_direction_one(const char *cmd, int argc, char **argv)
{
  int dir = cli_direction_scan(cmd, argc, argv);
  if (dir == CLI_DIR_BOTH) return cli_bad("%s: --direction lateral or vertical", cmd), -1;
  return dir;
}

/* ---- the evaluation ---- */

typedef struct vertical_run {
  rr_vertical_model m;
  rr_vertical_plan *plan;
  rr_spectrum sp;
  int opened, np, nf;
  rr_vertical_point pt[RR_VERTICAL_POINTS_MAX];
  /* both: the lateral side */
  ride_point lat[RR_VERTICAL_POINTS_MAX];
  rr_window_stats wd[RR_VERTICAL_POINTS_MAX];
  rr_en12299 en[RR_VERTICAL_POINTS_MAX];
  int have_en;             /* a lateral side (PEM or given): EN 12299's indices */
  rr_window_stats ax, axc; /* --ax-pitch: pitch's longitudinal a_x, Wd and Wc */
  double *lat_psd, *lat_f;
} vertical_run;

static void run_free(vertical_run *r)
{
  rr_vertical_plan_free(r->plan);
  if (r->opened) rr_spectrum_close(&r->sp);
  free(r->lat_psd);
  free(r->lat_f);
}

static int open_spectrum(vertical_run *r, const vertical_setup *vs, rr_error *e)
{
  int st = rr_spectrum_open(vs->spectrum, &r->sp, e);
  r->opened = !st;
  if (!st)
    st =
        rr_spectrum_require(&r->sp, "vertical", "--vertical-spectrum: the vertical track input", e);
  if (!st && vs->outside >= 0) r->sp.clip = vs->outside;
  return st;
}

static int plan_run(vertical_run *r, const rr_vehicle *veh, const ride_setup *rs,
                    const vertical_setup *vs, rr_error *e)
{
  rr_vertical_opts o = rr_vertical_opts_default();
  o.nfreq = rs->nfreq;
  o.f_lo_hz = rs->f_lo;
  o.f_hi_hz = rs->f_hi;
  o.window_s = vs->window_s;
  o.npoints = rs->npoints;
  memcpy(o.x_points, rs->x, sizeof(double) * (size_t)rs->npoints);
  r->np = rs->npoints;
  r->nf = rs->nfreq;
  int st = rr_vertical_model_build(veh, &r->m, e);
  if (!st) st = rr_vertical_plan_new(&o, &r->plan, e);
  return st;
}

/* The lateral PEM on the same grid and points, its Wd 5 s percentiles, and
   EN 12299's indices per point. */
static int lateral_side(vertical_run *r, const rr_vehicle *veh, double speed_kmh,
                        const ride_setup *rs, const vertical_setup *vs, double conicity,
                        rr_error *e)
{
  r->lat_psd = malloc(sizeof(double) * (size_t)r->nf * (size_t)r->np);
  r->lat_f = malloc(sizeof(double) * (size_t)r->nf);
  if (!r->lat_psd || !r->lat_f) {
    snprintf(e->msg, sizeof e->msg, "out of memory");
    return RR_ENOMEM;
  }
  int st = ride_eval(veh, speed_kmh, conicity, rs, r->lat, r->lat_psd, r->lat_f, e);
  if (st) return st;
  if (r->lat[0].stable == 0 && rs->when_unstable != RR_RIDE_LINEAR) {
    /* unstable: the lateral side is undefined, and EN 12299 with it (NaN carries through) */
    for (int q = 0; q < r->np; q++) r->wd[q] = (rr_window_stats){NAN, NAN, NAN, NAN, NAN, NAN};
    return RR_OK;
  }
  const double *f = rr_vertical_freqs(r->plan);
  for (int k = 0; k < r->nf; k++)
    if (fabs(r->lat_f[k] - f[k]) > 1e-12 * f[k]) {
      snprintf(e->msg, sizeof e->msg, "the lateral and vertical grids differ at %g Hz", f[k]);
      return RR_EINVAL;
    }
  return rr_vertical_window_stats(r->plan, r->lat_psd, r->np, r->np, RR_ISO_WD, r->wd, e);
}

/* --lateral-wd-p95 / --lateral-wd-rms: the given value(s) as both percentiles */
static int lateral_given(vertical_run *r, const vertical_setup *vs, rr_error *e)
{
  if (vs->nlateral != 1 && vs->nlateral != r->np) {
    snprintf(e->msg, sizeof e->msg, "--lateral-wd-%s: one value or one per floor point (%d)",
             vs->lateral_given == 1 ? "p95" : "rms", r->np);
    return RR_EINVAL;
  }
  for (int q = 0; q < r->np; q++) {
    double a = vs->lateral[vs->nlateral == 1 ? 0 : q];
    r->wd[q] = (rr_window_stats){.rms = vs->lateral_given == 2 ? a : NAN, .p50 = a, .p95 = a};
  }
  return RR_OK;
}

/* EN 12299's indices per point from the Z, Y and X percentiles */
static void combine(vertical_run *r, const vertical_setup *vs)
{
  double ax50 = vs->ax_pitch ? r->ax.p50 : vs->ax_p50, ax95 = vs->ax_pitch ? r->ax.p95 : vs->ax_p95;
  double axd95 = vs->ax_pitch ? r->axc.p95 : ax95; /* a rigid seat's back: the floor's */
  for (int q = 0; q < r->np; q++) {
    rr_en12299_inputs in = {.ax50 = ax50,
                            .ax95 = ax95,
                            .axd95 = axd95,
                            .ay50 = r->wd[q].p50,
                            .ay95 = r->wd[q].p95,
                            .az50 = r->pt[q].wb_5s.p50,
                            .az95 = r->pt[q].wb_5s.p95};
    r->en[q] = rr_en12299_indices(&in);
  }
  r->have_en = 1;
}

/* The vertical run and, with a conicity (not NaN), the lateral side. */
static int run_eval(vertical_run *r, const rr_vehicle *veh, double speed_kmh, const ride_setup *rs,
                    const vertical_setup *vs, double conicity, rr_error *e)
{
  int st = open_spectrum(r, vs, e);
  if (!st) st = plan_run(r, veh, rs, vs, e);
  if (!st) st = rr_vertical_ride_execute(r->plan, &r->m, speed_kmh / RR_KMH, &r->sp, r->pt, e);
  if (!st && vs->ax_pitch)
    st =
        rr_vertical_pitch_longitudinal(r->plan, vs->hp, veh->carbody_cg_height, &r->ax, &r->axc, e);
  if (!st && !isnan(conicity))
    st = lateral_side(r, veh, speed_kmh, rs, vs, conicity, e);
  else if (!st && vs->lateral_given)
    st = lateral_given(r, vs, e);
  if (!st && (!isnan(conicity) || vs->lateral_given)) combine(r, vs);
  return st;
}

int vertical_eval(const rr_vehicle *veh, double speed_kmh, const ride_setup *rs,
                  const vertical_setup *vs, double conicity, vertical_both *out, rr_error *e)
{
  vertical_run r = {0};
  int st = run_eval(&r, veh, speed_kmh, rs, vs, conicity, e);
  for (int q = 0; q < rs->npoints && !st; q++)
    out[q] = (vertical_both){.lat = r.lat[q], .z = r.pt[q], .wd = r.wd[q], .en = r.en[q]};
  run_free(&r);
  return st;
}

/* ---- outputs ---- */

static void write_psd(FILE *fp, const vertical_run *r, int both)
{
  const double *f = rr_vertical_freqs(r->plan), *G = rr_vertical_psd(r->plan),
               *Gt = rr_vertical_track_psd(r->plan);
  fprintf(fp, "f_hz,track_psd_m2_per_hz");
  for (int q = 0; q < r->np; q++) fprintf(fp, ",psd_x%gm_m2s-4_per_hz", r->pt[q].x);
  if (both)
    for (int q = 0; q < r->np; q++) fprintf(fp, ",lateral_psd_x%gm_m2s-4_per_hz", r->pt[q].x);
  fprintf(fp, ",sperling_weight2,wb_en12299_weight2,wk_weight2%s\n", both ? ",wd_weight2" : "");
  for (int k = 0; k < r->nf; k++) {
    fprintf(fp, "%.10g,%.10g", f[k], Gt[k]);
    for (int q = 0; q < r->np; q++) fprintf(fp, ",%.10g", G[(size_t)k * (size_t)r->np + (size_t)q]);
    if (both)
      for (int q = 0; q < r->np; q++)
        fprintf(fp, ",%.10g", r->lat_psd[(size_t)k * (size_t)r->np + (size_t)q]);
    double b = rr_sperling_filter(f[k], RR_AXIS_VERTICAL);
    double complex wk = rr_iso8041_weight(RR_ISO_WK, f[k]), wb = rr_iso8041_weight(RR_EN_WB, f[k]);
    fprintf(fp, ",%.10g,%.10g,%.10g", b * b, creal(wb * conj(wb)), creal(wk * conj(wk)));
    if (both) {
      double complex wd = rr_iso8041_weight(RR_ISO_WD, f[k]);
      fprintf(fp, ",%.10g", creal(wd * conj(wd)));
    }
    fputc('\n', fp);
  }
}

static cJSON *stats_json(const rr_window_stats *s)
{
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "shape_k", s->shape_k);
  cJSON_AddNumberToObject(o, "dof", s->dof);
  cJSON_AddNumberToObject(o, "p50", s->p50);
  cJSON_AddNumberToObject(o, "p95", s->p95);
  cJSON_AddNumberToObject(o, "mean", s->mean);
  return o;
}

static cJSON *methods_json(void)
{
  cJSON *m = cJSON_CreateObject();
  cJSON_AddStringToObject(m, "rms", "unweighted RMS, trapezoid over the band");
  cJSON_AddStringToObject(m, "sperling", "Sperling Wz, weighting-filter method, vertical B_s");
  cJSON_AddStringToObject(m, "sperling_gb", "GB/T 5599 line method, vertical F(f)");
  cJSON_AddStringToObject(m, "wk_rms", "ISO 2631-1 Wk-weighted RMS (ISO 8041 Wk)");
  cJSON_AddStringToObject(m, "wb_rms", "EN 12299 Wb-weighted RMS");
  cJSON_AddStringToObject(m, "wb_iso8041_rms", "ISO 8041 / ISO 2631-4 Wb-weighted RMS");
  cJSON_AddStringToObject(m, "wb_5s",
                          "5 s RMS of the EN 12299 Wb-weighted acceleration: gamma law with the "
                          "window mean square's exact mean and variance");
  cJSON_AddStringToObject(m, "n_mv", "EN 12299 6 sqrt(aX95^2 + aY95^2 + aZ95^2), floor");
  cJSON_AddStringToObject(m, "n_vd", "EN 12299 3 sqrt(16 aX50^2 + 4 aY50^2 + aZ50^2) + 5 aY95");
  cJSON_AddStringToObject(m, "n_va_rigid_seat",
                          "EN 12299 4 aZ95 + 2 sqrt(aY95^2 + aZ95^2) + 4 aXD95, seat = floor");
  return m;
}

/* the longitudinal term: given numbers (0 by default) or pitch's a_x */
static cJSON *longitudinal_json(const vertical_run *r, const vertical_setup *vs)
{
  cJSON *x = cJSON_CreateObject();
  if (vs->ax_pitch) {
    cJSON_AddStringToObject(x, "source", "carbody pitch at the floor height (--ax-pitch)");
    cJSON_AddNumberToObject(x, "wd_rms", r->ax.rms);
    cJSON_AddNumberToObject(x, "wd_p50", r->ax.p50);
    cJSON_AddNumberToObject(x, "wd_p95", r->ax.p95);
    cJSON_AddNumberToObject(x, "wc_p95", r->axc.p95);
    return x;
  }
  cJSON_AddStringToObject(x, "source", "given (--ax-p95, --ax-p50; default 0: not modelled)");
  cJSON_AddNullToObject(x, "wd_rms");
  cJSON_AddNumberToObject(x, "wd_p50", vs->ax_p50);
  cJSON_AddNumberToObject(x, "wd_p95", vs->ax_p95);
  cJSON_AddNumberToObject(x, "wc_p95", vs->ax_p95); /* a rigid seat: the floor's */
  return x;
}

static cJSON *lateral_json(const vertical_run *r, int q, const vertical_setup *vs)
{
  cJSON *l = cJSON_CreateObject();
  cJSON_AddStringToObject(l, "source",
                          vs->lateral_given == 1   ? "given (--lateral-wd-p95)"
                          : vs->lateral_given == 2 ? "given (--lateral-wd-rms)"
                                                   : "lateral PEM (Wd, 5 s gamma law)");
  cJSON_AddNumberToObject(l, "wd_rms", r->wd[q].rms); /* NaN (not known): null */
  cJSON_AddNumberToObject(l, "wd_p50", r->wd[q].p50);
  cJSON_AddNumberToObject(l, "wd_p95", r->wd[q].p95);
  if (!vs->lateral_given) {
    cJSON_AddNumberToObject(l, "sperling", r->lat[q].sperling);
    cJSON_AddBoolToObject(l, "stable", r->lat[q].stable == 1);
    cJSON_AddNumberToObject(l, "zeta_max", r->lat[q].zeta_max);
  }
  return l;
}

static cJSON *point_json(const vertical_run *r, int q, const vertical_setup *vs)
{
  const rr_vertical_point *p = &r->pt[q];
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "x", p->x);
  cJSON_AddNumberToObject(o, "rms", p->rms);
  cJSON_AddNumberToObject(o, "sperling", p->sperling);
  cJSON_AddNumberToObject(o, "sperling_gb", p->sperling_gb);
  cJSON_AddNumberToObject(o, "wk_rms", p->wk_rms);
  cJSON_AddNumberToObject(o, "wb_rms", p->wb_rms);
  cJSON_AddNumberToObject(o, "wb_iso8041_rms", p->wb_iso8041_rms);
  cJSON_AddItemToObject(o, "wb_5s", stats_json(&p->wb_5s));
  cJSON_AddNumberToObject(o, "n_mv_vertical", p->n_mv_vertical);
  cJSON_AddItemToObject(o, "longitudinal", longitudinal_json(r, vs));
  if (!r->have_en) {
    cJSON_AddNullToObject(o, "lateral");
    cJSON_AddNullToObject(o, "n_mv");
    cJSON_AddNullToObject(o, "n_vd");
    cJSON_AddNullToObject(o, "n_va_rigid_seat");
    return o;
  }
  cJSON_AddItemToObject(o, "lateral", lateral_json(r, q, vs));
  cJSON_AddNumberToObject(o, "n_mv", r->en[q].n_mv);
  cJSON_AddNumberToObject(o, "n_vd", r->en[q].n_vd);
  cJSON_AddNumberToObject(o, "n_va_rigid_seat", r->en[q].n_va_rigid_seat);
  if (isnan(r->en[q].n_mv))
    cJSON_AddNullToObject(o, "comfort");
  else
    cJSON_AddStringToObject(o, "comfort", rr_en12299_scale(r->en[q].n_mv));
  return o;
}

static void ride_json_out(const cli_common *c, const ride_setup *rs, const vertical_setup *vs,
                          const vertical_run *r, double conicity)
{
  int both = vs->direction == CLI_DIR_BOTH;
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "vehicle", c->veh.name);
  cJSON_AddNumberToObject(root, "speed_kmh", c->speed_kmh);
  cJSON_AddStringToObject(root, "direction", both ? "both" : "vertical");
  cJSON_AddStringToObject(root, "spectrum", vs->spectrum);
  cJSON_AddStringToObject(root, "spectrum_direction", r->sp.direction);
  cJSON_AddStringToObject(root, "spectrum_outside", r->sp.clip ? "zero" : "extend");
  if (both) {
    cJSON_AddStringToObject(root, "lateral_spectrum", rs->spectrum);
    cJSON_AddNumberToObject(root, "conicity", conicity);
    cJSON_AddStringToObject(root, "conicity_source", c->conicity_source);
    cJSON_AddNumberToObject(root, "floor_height", rs->h_p);
  }
  cJSON_AddNumberToObject(root, "nfreq", r->nf);
  cJSON_AddNumberToObject(root, "fmin_hz", rs->f_lo);
  cJSON_AddNumberToObject(root, "fmax_hz", rs->f_hi);
  cJSON_AddNumberToObject(root, "window_s", vs->window_s);
  cJSON_AddNumberToObject(root, "ax_p95", vs->ax_p95);
  cJSON_AddNumberToObject(root, "ax_p50", vs->ax_p50);
  cJSON_AddBoolToObject(root, "ax_pitch", vs->ax_pitch);
  cJSON_AddNumberToObject(root, "hp", vs->hp);
  cJSON_AddItemToObject(root, "ignored_keys", cJSON_CreateArray()); /* unknown keys are errors */
  cJSON_AddStringToObject(root, "p95_method", "gamma");
  cJSON_AddItemToObject(root, "methods", methods_json());
  cJSON *pa = cJSON_AddArrayToObject(root, "points");
  for (int q = 0; q < r->np; q++) cJSON_AddItemToArray(pa, point_json(r, q, vs));
  cli_json_print(root);
}

static void ride_text_out(const cli_common *c, const ride_setup *rs, const vertical_setup *vs,
                          const vertical_run *r, double conicity)
{
  printf("%s at %g km/h, vertical spectrum %s (%s outside its range), band %g-%g Hz (%d points), "
         "%g s windows\n",
         c->veh.name, c->speed_kmh, vs->spectrum, r->sp.clip ? "zero" : "extended", rs->f_lo,
         rs->f_hi, r->nf, vs->window_s);
  printf("Sperling (vertical): filter (W) and GB/T 5599 line (W_gb); Wk: ISO 2631-1; Wb: EN 12299; "
         "P50/P95: of the 5 s Wb RMS\n");
  printf("%9s %11s %7s %7s %11s %11s %11s %11s %7s %8s\n", "x_m", "rms_m/s2", "W", "W_gb",
         "wk_m/s2", "wb_m/s2", "wb_p50", "wb_p95", "k", "6aZ95");
  for (int q = 0; q < r->np; q++) {
    const rr_vertical_point *p = &r->pt[q];
    printf("%9.4g %11.5g %7.4f %7.4f %11.5g %11.5g %11.5g %11.5g %7.3f %8.4f\n", p->x, p->rms,
           p->sperling, p->sperling_gb, p->wk_rms, p->wb_rms, p->wb_5s.p50, p->wb_5s.p95,
           p->wb_5s.shape_k, p->n_mv_vertical);
  }
  if (!r->have_en) return;
  char lat[160], lon[160];
  if (vs->lateral_given)
    snprintf(lat, sizeof lat, "lateral given (--lateral-wd-%s)",
             vs->lateral_given == 1 ? "p95" : "rms");
  else
    snprintf(lat, sizeof lat, "lateral from the lateral PEM (conicity %g, spectrum %s, Wd)",
             conicity, rs->spectrum);
  if (vs->ax_pitch)
    snprintf(lon, sizeof lon, "longitudinal from carbody pitch at %g m (P95 %.4g, P50 %.4g m/s2)",
             vs->hp, r->ax.p95, r->ax.p50);
  else
    snprintf(lon, sizeof lon, "longitudinal given (P95 %g, P50 %g m/s2)", vs->ax_p95, vs->ax_p50);
  printf("\nEN 12299 mean comfort: %s, %s, rigid seat\n", lat, lon);
  printf("%9s %11s %11s %11s %11s %7s %7s %7s  %s\n", "x_m", "ay_p50", "ay_p95", "az_p50", "az_p95",
         "N_MV", "N_VD", "N_VA", "comfort (N_MV)");
  for (int q = 0; q < r->np; q++) {
    int stable = vs->lateral_given ? 1 : r->lat[q].stable;
    char b[5][32];
    printf("%9.4g %11s %11s %11.5g %11.5g %7s %7s %7s  %s\n", r->pt[q].x,
           ride_num(b[0], 32, 5, r->wd[q].p50, stable), ride_num(b[1], 32, 5, r->wd[q].p95, stable),
           r->pt[q].wb_5s.p50, r->pt[q].wb_5s.p95, ride_num(b[2], 32, 3, r->en[q].n_mv, stable),
           ride_num(b[3], 32, 3, r->en[q].n_vd, stable),
           ride_num(b[4], 32, 3, r->en[q].n_va_rigid_seat, stable),
           rr_en12299_scale(r->en[q].n_mv));
  }
  printf("scale: < 1 very comfortable, 1-2 comfortable, 2-4 medium, 4-5 uncomfortable, >= 5 very "
         "uncomfortable\n");
}

int ride_vertical(const cli_common *c, const ride_setup *rs, const vertical_setup *vs,
                  double conicity, const char *psd_path)
{
  vertical_run r = {0};
  rr_error e = {0};
  cli_outfile psd = {0};
  int st, both = vs->direction == CLI_DIR_BOTH, ret;
  if (psd_path && (ret = cli_out_open(&psd, psd_path, "--psd"))) return ret;
  st = run_eval(&r, &c->veh, c->speed_kmh, rs, vs, both ? conicity : NAN, &e);
  if (st) {
    cli_out_abort(&psd);
    run_free(&r);
    return cli_fail(&e, st);
  }
  if (psd.fp) write_psd(psd.fp, &r, both);
  ret = cli_out_commit(&psd);
  if (!ret && c->json)
    ride_json_out(c, rs, vs, &r, conicity);
  else if (!ret)
    ride_text_out(c, rs, vs, &r, conicity);
  run_free(&r);
  return ret;
}

/* ---- frf --direction vertical ---- */

static const char *const vdof_names[RR_VDOF] = {"z_c",      "theta_c", "q_b",     "z_f1",
                                                "theta_f1", "z_f2",    "theta_f2"};

static cJSON *complex_arrays(cJSON *o, const rr_complex *H, int n, int stride, int with_abs)
{
  cJSON *re = cJSON_AddArrayToObject(o, "re"), *im = cJSON_AddArrayToObject(o, "im"),
        *ab = with_abs ? cJSON_AddArrayToObject(o, "abs") : NULL;
  for (int k = 0; k < n; k++) {
    rr_complex h = H[(size_t)k * (size_t)stride];
    cJSON_AddItemToArray(re, cJSON_CreateNumber(creal(h)));
    cJSON_AddItemToArray(im, cJSON_CreateNumber(cimag(h)));
    if (ab) cJSON_AddItemToArray(ab, cJSON_CreateNumber(cabs(h)));
  }
  return o;
}

static void frf_json_out(const vertical_run *r, const vertical_setup *vs)
{
  const double *f = rr_vertical_freqs(r->plan), *x = rr_vertical_points(r->plan);
  const rr_complex *H = rr_vertical_frf_H(r->plan), *Q = rr_vertical_frf_Q(r->plan);
  cJSON *root = cJSON_CreateObject();
  cJSON_AddItemToObject(root, "f_hz", cJSON_CreateDoubleArray(f, r->nf));
  cJSON *pa = cJSON_AddArrayToObject(root, "points");
  for (int q = 0; q < r->np; q++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "x", x[q]);
    cJSON_AddItemToArray(pa, complex_arrays(o, H + q, r->nf, r->np, 1));
  }
  if (vs->dofs) {
    cJSON *d = cJSON_AddObjectToObject(root, "dofs");
    for (int k = 0; k < RR_VDOF; k++)
      complex_arrays(cJSON_AddObjectToObject(d, vdof_names[k]), Q + k, r->nf, RR_VDOF, 0);
  }
  cli_json_print(root);
}

static void frf_csv_out(const vertical_run *r, const vertical_setup *vs)
{
  const double *f = rr_vertical_freqs(r->plan), *x = rr_vertical_points(r->plan);
  const rr_complex *H = rr_vertical_frf_H(r->plan), *Q = rr_vertical_frf_Q(r->plan);
  printf("f_hz,x_m,output,re,im,magnitude,phase_deg\n");
  for (int k = 0; k < r->nf; k++) {
    for (int q = 0; q < r->np; q++) {
      rr_complex h = H[(size_t)k * (size_t)r->np + (size_t)q];
      printf("%.10g,%.6g,floor_acceleration,%.10g,%.10g,%.10g,%.6f\n", f[k], x[q], creal(h),
             cimag(h), cabs(h), carg(h) * 180 / RR_PI);
    }
    for (int d = 0; vs->dofs && d < RR_VDOF; d++) {
      rr_complex h = Q[(size_t)k * RR_VDOF + (size_t)d];
      printf("%.10g,,%s,%.10g,%.10g,%.10g,%.6f\n", f[k], vdof_names[d], creal(h), cimag(h), cabs(h),
             carg(h) * 180 / RR_PI);
    }
  }
}

int frf_vertical(const cli_common *c, const ride_setup *rs, const vertical_setup *vs)
{
  vertical_run r = {0};
  rr_error e = {0};
  int st = plan_run(&r, &c->veh, rs, vs, &e);
  if (!st) st = rr_vertical_frf_execute(r.plan, &r.m, c->speed_kmh / RR_KMH, &e);
  if (st) {
    run_free(&r);
    return cli_fail(&e, st);
  }
  if (c->json)
    frf_json_out(&r, vs);
  else
    frf_csv_out(&r, vs);
  run_free(&r);
  return 0;
}

/* ---- modes --direction vertical ---- */

static void modes_json_out(const cli_common *c, const rr_vertical_model *m,
                           const rr_vertical_modes *md)
{
  cJSON *root = cJSON_CreateObject(), *arr = cJSON_AddArrayToObject(root, "modes");
  cJSON_AddStringToObject(root, "vehicle", c->veh.name);
  cJSON_AddStringToObject(root, "direction", "vertical");
  for (int i = 0; i < md->nmodes; i++) {
    const rr_vertical_mode *o = &md->mode[i];
    cJSON *j = cJSON_CreateObject(), *en;
    cJSON_AddNumberToObject(j, "freq_hz", o->freq_hz);
    cJSON_AddNumberToObject(j, "natural_hz", o->natural_hz);
    cJSON_AddNumberToObject(j, "damping_ratio", o->damping_ratio);
    cJSON_AddNumberToObject(j, "real", o->re);
    cJSON_AddNumberToObject(j, "imag", o->im);
    cJSON_AddStringToObject(j, "name", o->name);
    en = cJSON_AddObjectToObject(j, "energy");
    for (int d = 0; d < RR_VDOF; d++) cJSON_AddNumberToObject(en, vdof_names[d], o->energy[d]);
    cJSON_AddItemToArray(arr, j);
  }
  cJSON_AddItemToObject(root, "overdamped_real", cJSON_CreateDoubleArray(md->real, md->nreal));
  cJSON_AddItemToObject(root, "undamped_hz", cJSON_CreateDoubleArray(md->undamped_hz, RR_VDOF));
  cJSON_AddItemToObject(root, "phi_pivots", cJSON_CreateDoubleArray(m->phi_pivots, 2));
  double w[2] = {rr_beam_shape(m->x_frames[0], m->carbody_length),
                 rr_beam_shape(m->x_frames[1], m->carbody_length)};
  cJSON_AddItemToObject(root, "phi_unit_pivots", cJSON_CreateDoubleArray(w, 2));
  cJSON_AddNumberToObject(root, "phi_unit_centre", rr_beam_shape(0, m->carbody_length));
  cli_json_print(root);
}

static void modes_text_out(const cli_common *c, const rr_vertical_modes *md)
{
  printf("%s: vertical modes (carbody bounce, pitch, first bending; frames bounce, pitch)\n",
         c->veh.name);
  printf("%11s %11s %9s  %-36s %s\n", "freq_Hz", "natural_Hz", "damping", "name",
         "energy z_c th_c q_b z_f1 th_f1 z_f2 th_f2");
  for (int i = 0; i < md->nmodes; i++) {
    const rr_vertical_mode *o = &md->mode[i];
    printf("%11.6f %11.6f %9.5f  %-36s", o->freq_hz, o->natural_hz, o->damping_ratio, o->name);
    for (int d = 0; d < RR_VDOF; d++) printf(" %.3f", o->energy[d]);
    putchar('\n');
  }
  for (int i = 0; i < md->nreal; i++) printf("aperiodic: %.6g 1/s\n", md->real[i]);
  printf("undamped (Hz):");
  for (int i = 0; i < RR_VDOF; i++) printf(" %.6f", md->undamped_hz[i]);
  printf("\n(damping: the ratio -Re/|lambda|, positive when stable)\n");
}

int modes_vertical(const cli_common *c)
{
  rr_vertical_model m;
  rr_vertical_modes md;
  rr_error e = {0};
  int st = rr_vertical_model_build(&c->veh, &m, &e);
  if (!st) st = rr_vertical_modes_compute(&m, &md, &e);
  if (st) return cli_fail(&e, st);
  if (c->json)
    modes_json_out(c, &m, &md);
  else
    modes_text_out(c, &md);
  return 0;
}

/* ---- matrices --direction vertical ---- */

static void matrix_text(const char *name, const double *A, int rows, int cols)
{
  printf("%s (%d x %d)\n", name, rows, cols);
  for (int i = 0; i < rows; i++) {
    for (int j = 0; j < cols; j++) printf(" %14.7g", A[i * cols + j]);
    putchar('\n');
  }
  putchar('\n');
}

int matrices_vertical(const cli_common *c)
{
  rr_vertical_model m;
  rr_error e = {0};
  int st = rr_vertical_model_build(&c->veh, &m, &e);
  if (st) return cli_fail(&e, st);
  double M[RR_VDOF * RR_VDOF] = {0}, A[4 * RR_VDOF * RR_VDOF], rows[3 * RR_VDOF];
  for (int i = 0; i < RR_VDOF; i++) M[i * RR_VDOF + i] = m.M[i];
  rr_vertical_state_matrix(&m, A);
  double x[3] = {m.x_frames[0], 0, m.x_frames[1]};
  for (int q = 0; q < 3; q++) rr_vertical_floor_row(&m, x[q], rows + q * RR_VDOF);
  if (!c->json) {
    printf("%s: the vertical model, rows/columns z_c theta_c q_b z_f1 theta_f1 z_f2 theta_f2; "
           "inputs the wheelsets front to rear\n\n",
           c->veh.name);
    matrix_text("M", M, RR_VDOF, RR_VDOF);
    matrix_text("C", m.C, RR_VDOF, RR_VDOF);
    matrix_text("K", m.K, RR_VDOF, RR_VDOF);
    matrix_text("BK", m.BK, RR_VDOF, RR_VINPUTS);
    matrix_text("BC", m.BC, RR_VDOF, RR_VINPUTS);
    printf("phi(+-L) = %.10g, %.10g 1/sqrt(kg); state matrix A: 14 x 14 (--json)\n",
           m.phi_pivots[0], m.phi_pivots[1]);
    return 0;
  }
  cJSON *root = cJSON_CreateObject(), *d = cJSON_AddArrayToObject(root, "dofs");
  for (int i = 0; i < RR_VDOF; i++) cJSON_AddItemToArray(d, cJSON_CreateString(vdof_names[i]));
  cJSON_AddItemToObject(root, "M", cli_json_matrix(M, RR_VDOF, RR_VDOF));
  cJSON_AddItemToObject(root, "C", cli_json_matrix(m.C, RR_VDOF, RR_VDOF));
  cJSON_AddItemToObject(root, "K", cli_json_matrix(m.K, RR_VDOF, RR_VDOF));
  cJSON_AddItemToObject(root, "BK", cli_json_matrix(m.BK, RR_VDOF, RR_VINPUTS));
  cJSON_AddItemToObject(root, "BC", cli_json_matrix(m.BC, RR_VDOF, RR_VINPUTS));
  cJSON_AddItemToObject(root, "x_frames", cJSON_CreateDoubleArray(m.x_frames, 2));
  cJSON_AddItemToObject(root, "x_wheelsets", cJSON_CreateDoubleArray(m.x_wheelsets, RR_VINPUTS));
  cJSON_AddItemToObject(root, "d_wheelsets", cJSON_CreateDoubleArray(m.d_wheelsets, RR_VINPUTS));
  cJSON_AddNumberToObject(root, "beta_l", RR_BEAM_BETA_L);
  cJSON_AddItemToObject(root, "phi_pivots", cJSON_CreateDoubleArray(m.phi_pivots, 2));
  cJSON_AddItemToObject(root, "floor_rows", cli_json_matrix(rows, 3, RR_VDOF));
  cJSON_AddItemToObject(root, "A", cli_json_matrix(A, 2 * RR_VDOF, 2 * RR_VDOF));
  if (c->have_speed) {
    double tau[RR_VINPUTS];
    for (int j = 0; j < RR_VINPUTS; j++) tau[j] = m.d_wheelsets[j] / (c->speed_kmh / RR_KMH);
    cJSON_AddItemToObject(root, "delays_s", cJSON_CreateDoubleArray(tau, RR_VINPUTS));
  }
  cli_json_print(root);
  return 0;
}
