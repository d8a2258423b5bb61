/* `--plot FILE` for every command whose output is a curve, a map or a table
 * over a parameter: the command runs as usual with its CSV captured (or
 * written to a scratch file through its own option), then gnuplot draws it
 * into FILE, the terminal chosen by the extension (.svg, .png, .pdf). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
extern char **environ;
#include "cli.h"
#include "outfile.h"
#include "parallel.h"
#include "plot.h"

/* A picture's main title goes on with what it is of on a second line: the
   command line's vehicle, speed, conicity and tread (RR_CTX, set by
   write_script; not read as enhanced text, so file names show as written). */
#define GP_CTX ".\"\\n\".RR_CTX noenhanced"

/* The second contour of index maps: the paper's Fig. 5 marks where the
   index reaches -0.3 (well damped). */
#define PLOT_INDEX_CONTOUR -0.3

#define PLOT_W 900
#define PLOT_H 600

/* How a command's data reaches the plot: its standard output (with extra
   arguments that make it CSV), or a file named by one of its options. */
typedef struct plot_kind {
  const char *cmd;
  const char *extra;       /* argument appended to get CSV on stdout, or NULL */
  const char *file_option; /* the option that writes the data file, or NULL */
  int grid; /* rows on a grid over the first two columns (a map); 2: when --y is given */
  void (*script)(FILE *gp, const char *data, int argc, char **argv);
} plot_kind;

/* A user's text (an objective, a key) as a gnuplot string literal: single
   quoted (no escapes, no substitution), every character outside a plain set
   shown as '?', so that no text reaches gnuplot as code (its backquotes run
   commands, its quotes end strings). */
static const char *gp_str(char *out, size_t n, const char *text)
{
  static const char plain[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                              " _.,;:=@+-()/%<>*^#[]";
  size_t k = 0;
  if (n < 3) return "''";
  out[k++] = '\'';
  for (const char *p = text; *p && k + 2 < n; p++) out[k++] = strchr(plain, *p) ? *p : '?';
  out[k++] = '\'';
  out[k] = 0;
  return out;
}

static const char *arg_after(int argc, char **argv, const char *opt)
{
  for (int i = 0; i + 1 < argc; i++)
    if (!strcmp(argv[i], opt)) return argv[i + 1];
  return NULL;
}

static int has_arg(int argc, char **argv, const char *opt)
{
  for (int i = 0; i < argc; i++)
    if (!strcmp(argv[i], opt)) return 1;
  return 0;
}

/* The series stiffnesses of damper CSV d when it holds several curves (the
   first frequency on more than one row: --k K1,K2,..): how many, into k. */
static int damper_curves(const char *d, double *k, int cap)
{
  FILE *f = fopen(d, "r");
  if (!f) return 0;
  char line[512];
  int n = 0;
  double f0 = NAN, fr, kk;
  while (fgets(line, sizeof line, f))
    if (sscanf(line, "%lf,%lf", &fr, &kk) == 2) {
      if (isnan(f0)) f0 = fr;
      if (fr == f0 && n < cap) k[n++] = kk;
    }
  fclose(f);
  return n;
}

/* Several series stiffnesses (paper Fig. 2): storage stiffness and
   equivalent damping over frequency, a curve each. */
static void damper_family(FILE *gp, const char *d, const char *el, const double *k, int n)
{
  fprintf(gp,
          "set multiplot layout 1,2 title '%s damper as a Maxwell element for several series "
          "stiffnesses'" GP_CTX "\n"
          "set logscale x; set autoscale xfix; set key top left; set xlabel 'frequency (Hz)'\n",
          el);
  static const char *const what[2][3] = {
      {"storage_n_per_m", "1e6", "equivalent stiffness (MN/m)"},
      {"eq_damping_n_s_per_m", "1e3", "equivalent damping (kN s/m)"}};
  for (int p = 0; p < 2; p++) {
    fprintf(gp, "set ylabel '%s'\nplot ", what[p][2]);
    for (int i = 0; i < n; i++)
      fprintf(gp,
              "%s'%s' u 'freq_hz':(column('k_series_n_per_m') == %.17g ? column('%s')/%s : 1/0) "
              "w l lw 2 t 'k_s = %.4g MN/m'",
              i ? ", " : "", d, k[i], what[p][0], what[p][1], k[i] / 1e6);
    fprintf(gp, "\n");
    if (!p) fprintf(gp, "set key top right\n");
  }
  fprintf(gp, "unset multiplot\n");
}

static void script_damper(FILE *gp, const char *d, int argc, char **argv)
{
  const char *el = arg_after(argc, argv, "--element");
  double k[16];
  int n = damper_curves(d, k, 16);
  if (n > 1) {
    damper_family(gp, d, el && !strcmp(el, "lateral") ? "Lateral" : "Yaw", k, n);
    return;
  }
  fprintf(gp,
          "set title '%s damper as a Maxwell element: dynamic stiffness over frequency'" GP_CTX "\n"
          "set logscale x; set autoscale xfix; set key outside bottom center horizontal\n"
          "set xlabel 'frequency (Hz)'; set ylabel 'stiffness (MN/m)'\n"
          "set y2label 'dissipation factor loss/storage'; set y2tics; set ytics nomirror\n"
          "plot '%s' u 'freq_hz':(column('k_series_n_per_m')/1e6) w l lw 2 dt 3 "
          "t 'series stiffness k_s(f)', "
          "'' u 'freq_hz':(column('storage_n_per_m')/1e6) w l lw 2 t 'storage stiffness', "
          "'' u 'freq_hz':(column('loss_n_per_m')/1e6) w l lw 2 t 'loss stiffness', "
          "'' u 'freq_hz':'dissipation' axes x1y2 w l lw 2 dt 2 t 'dissipation factor (right)'\n",
          el && !strcmp(el, "lateral") ? "Lateral" : "Yaw", d);
}

/* A root locus's branch at its least damped point (largest stability index). */
typedef struct locus_peak {
  int branch, hunting;
  double re, freq, zeta, e[3]; /* e: carbody, frames, wheelsets kinetic-energy shares */
} locus_peak;
#define LOCUS_LABELS 6 /* branches named on a locus: more clutter it */

/* The branches of locus CSV d (rows: branch,speed,conicity,freq,re,im,zeta,
   mac,e_c,e_f,e_w,roll,hunting,...) at their least damped points into all
   (cap of them), and the data's extent: re_lo, re_hi, f_lo, f_hi in span.
   Returns how many. */
static int locus_branches(const char *d, locus_peak *all, int cap, double span[4])
{
  FILE *f = fopen(d, "r");
  if (!f) return 0;
  int n = 0;
  char line[1024];
  span[0] = span[2] = INFINITY;
  span[1] = span[3] = -INFINITY;
  while (fgets(line, sizeof line, f)) {
    locus_peak r;
    double sp, con, im, mac, roll;
    if (sscanf(line, "%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%d", &r.branch, &sp, &con,
               &r.freq, &r.re, &im, &r.zeta, &mac, &r.e[0], &r.e[1], &r.e[2], &roll,
               &r.hunting) != 13)
      continue; /* the header */
    span[0] = fmin(span[0], r.re), span[1] = fmax(span[1], r.re);
    span[2] = fmin(span[2], r.freq), span[3] = fmax(span[3], r.freq);
    int k = 0;
    while (k < n && all[k].branch != r.branch) k++;
    if (k == n && n < cap)
      all[n++] = r; /* a new branch */
    else if (k < n && r.zeta > all[k].zeta)
      all[k] = r;
  }
  fclose(f);
  return n;
}

/* The LOCUS_LABELS least damped branches, each labelled at its least damped
   point with the body that holds most of its kinetic energy (fixed words: no
   data reaches gnuplot as code); a branch whose point lies on one already
   labelled (within 3% of the plot) is left out. */
static void locus_labels(FILE *gp, const char *d)
{
  static const char *const body[] = {"carbody", "bogie frames", "wheelsets"};
  locus_peak all[256], pk[LOCUS_LABELS];
  double span[4];
  int n = locus_branches(d, all, 256, span), m = 0;
  double wr = fmax(span[1] - span[0], 1e-12), wf = fmax(span[3] - span[2], 1e-12);
  for (int it = 0; it < n && m < LOCUS_LABELS; it++) {
    int best = it; /* selection: the it-th least damped */
    for (int k = it + 1; k < n; k++)
      if (all[k].zeta > all[best].zeta) best = k;
    locus_peak t = all[it];
    all[it] = all[best];
    all[best] = t;
    int near = 0;
    for (int j = 0; j < m; j++)
      near |=
          fabs(pk[j].re - all[it].re) < 0.03 * wr && fabs(pk[j].freq - all[it].freq) < 0.03 * wf;
    if (near) continue;
    locus_peak *p = &pk[m++];
    *p = all[it];
    int b = p->e[1] > p->e[0] ? 1 : 0;
    if (p->e[2] > p->e[b]) b = 2;
    fprintf(gp,
            "set label %d '%s%s, zeta %.3f' at %.17g, %.17g right point pt 6 ps 1.5 "
            "offset -1,0.7 font ',9' front\n",
            100 + m, body[b], p->hunting ? " (hunting)" : "", p->zeta, p->re, p->freq);
  }
}

static void script_locus(FILE *gp, const char *d, int argc, char **argv)
{
  const char *over = arg_after(argc, argv, "--over");
  int by_conicity = over && !strcmp(over, "conicity");
  locus_labels(gp, d);
  fprintf(gp,
          "set title 'Root locus over %s'" GP_CTX "\n"
          "set xlabel 'real part (1/s)'; set ylabel 'frequency (Hz)'; set cblabel '%s'\n"
          "set xzeroaxis; set yzeroaxis; set palette rgb 33,13,10\n"
          "set arrow from 0, graph 0 to 0, graph 1 nohead dt 2 lw 1.5\n"
          "plot '%s' u 'real_per_s':'freq_hz':'%s' w p pt 7 ps 0.6 palette notitle\n",
          by_conicity ? "conicity" : "speed", by_conicity ? "conicity" : "speed (km/h)", d,
          by_conicity ? "conicity" : "speed_kmh");
}

/* A filled map over the first two columns (gridded: a blank line between
   rows, see gridded()), interpolated, with the zero contour drawn when the
   values cross zero (a stability index: blue stable, red unstable, white 0).
   overlay: a further splot clause drawn as a zero contour, or "". panel: one
   of a multiplot's (its title without the context, which the whole has). */
static void map_script(FILE *gp, const char *d, int zcol, const char *xl, const char *yl,
                       const char *zl, const char *title, int centred, const char *overlay,
                       double sx, double sy, int panel)
{
  char t[300], x[200], y[200], z[200];
  gp_str(t, sizeof t, title);
  fprintf(gp,
          "set title %s%s\nset xlabel %s; set ylabel %s; set cblabel %s\n"
          "stats '%s' u %d nooutput\n",
          t, panel ? "" : GP_CTX, gp_str(x, sizeof x, xl), gp_str(y, sizeof y, yl),
          gp_str(z, sizeof z, zl), d, zcol);
  if (centred)
    fprintf(gp, "m = (abs(STATS_min) > abs(STATS_max)) ? abs(STATS_min) : abs(STATS_max)\nset "
                "cbrange [-m:m]\n"
                "set palette defined (0 '#2166ac', 0.5 '#f7f7f7', 1 '#b2182b')\n"
                "set contour base; set cntrparam levels discrete 0\n");
  else
    fprintf(gp, "set palette rgb 33,13,10\nset contour base; set cntrparam levels auto 8\n");
  fprintf(gp,
          "set pm3d map interpolate 4,4; set cntrlabel onecolor; set key opaque\n"
          "set autoscale xfix; set autoscale yfix\n" /* the axes end where the data end */
          "sx = %.17g; sy = %.17g  # axis units: SI / (sx, sy)\n"
          "splot '%s' u ($1/sx):($2/sy):%d w pm3d notitle, '' u ($1/sx):($2/sy):%d w l nosurface "
          "lw %s lc 'black' %s",
          sx, sy, d, zcol, zcol, centred ? "3" : "1",
          centred ? "t (STATS_min < 0 && STATS_max > 0 ? 'index = 0' : '')" : "notitle");
  if (centred) /* the paper's Fig. 5 contour too, as z + 0.3 at the one level 0 (the header
                  skipped: an expression would make it a point and break the grid) */
    fprintf(
        gp,
        ", '' skip 1 u ($1/sx):($2/sy):($%d - (" RR_STR(
            PLOT_INDEX_CONTOUR) ")) w l nosurface lw 2 "
                                "dt 2 lc 'black' t (STATS_min < (" RR_STR(
                                    PLOT_INDEX_CONTOUR) ") && STATS_max > "
                                                        "(" RR_STR(
                                                            PLOT_INDEX_CONTOUR) ") ? 'index "
                                                                                "= " RR_STR(
                                                                                    PLOT_INDEX_CONTOUR) "' : '')",
        zcol);
  fprintf(gp, "%s\n", overlay);
}

static void script_map(FILE *gp, const char *d, int argc, char **argv)
{
  if (!has_arg(argc, argv, "--shares")) {
    map_script(gp, d, 3, "speed (km/h)", "conicity", "stability index",
               "Vehicle stability index (negative is stable)", 1, "", 1, 1, 0);
    return;
  }
  /* paper Fig. 14: where the hunting mode's energy sits, carbody or bogies */
  fprintf(gp, "set multiplot layout 1,2 title 'Hunting mode: kinetic-energy shares'" GP_CTX "\n"
              "set cbrange [0:1]\n");
  map_script(gp, d, 10, "speed (km/h)", "conicity", "", "carbody", 0, "", 1, 1, 1);
  map_script(gp, d, 11, "speed (km/h)", "conicity", "share", "bogie frames", 0, "", 1, 1, 1);
  fprintf(gp, "unset multiplot\n");
}

/* An axis label in engineering units, and the factor SI values are divided
   by: "yaw damper series stiffness (MN/m)", 1e6; "speed (km/h)"; a key
   without a unit by its name. */
static double axis_label(const char *key, char *out, size_t n)
{
  static const struct {
    const char *si, *eng;
    double scale;
  } eng[] = {{"N/m", "MN/m", 1e6},
             {"N.s/m", "kN s/m", 1e3},
             {"N.m/rad", "kN m/rad", 1e3},
             {"N.m.s/rad", "kN m s/rad", 1e3},
             {"kg.m2", "kg m^2", 1}};
  const rr_vehicle_key *k = rr_vehicle_key_find(key);
  char name[128];
  size_t i = 0;
  for (; key[i] && i + 1 < sizeof name; i++)
    name[i] = key[i] == '.' || key[i] == '_' ? ' ' : key[i];
  name[i] = 0;
  if (!strcmp(key, "speed")) {
    snprintf(out, n, "speed (km/h)");
    return 1;
  }
  if (!k || !k->si_unit || !strcmp(k->si_unit, "1")) {
    snprintf(out, n, "%s", name);
    return 1;
  }
  for (size_t j = 0; j < sizeof eng / sizeof eng[0]; j++)
    if (!strcmp(k->si_unit, eng[j].si)) {
      snprintf(out, n, "%s (%s)", name, eng[j].eng);
      return eng[j].scale;
    }
  snprintf(out, n, "%s (%s)", name, k->si_unit);
  return 1;
}

static void script_sweep(FILE *gp, const char *d, int argc, char **argv)
{
  const char *x = arg_after(argc, argv, "--x"), *y = arg_after(argc, argv, "--y"),
             *o = arg_after(argc, argv, "--objective");
  char xk[128] = "x", yk[128] = "y", xl[160], yl[160], title[256];
  if (x) snprintf(xk, sizeof xk, "%.*s", (int)strcspn(x, "="), x);
  double sx = axis_label(xk, xl, sizeof xl), sy = 1;
  int bound = o && !strncmp(o, "critical_speed@", 15); /* values at the range's end flagged */
  if (!y) { /* one axis: the objective (and its mode's frequency) along it */
    char t[300], a[200], b[200];
    snprintf(title, sizeof title, "%s along %s", o ? o : "objective", xk);
    fprintf(gp,
            "set title %s" GP_CTX "\nset xlabel %s; set ylabel %s\n"
            "plot '%s' u ($1/%.17g):2 w lp pt 7 ps 0.6 lw 2 notitle",
            gp_str(t, sizeof t, title), gp_str(a, sizeof a, xl),
            gp_str(b, sizeof b, o ? o : "objective"), d, sx);
    if (bound) /* the sweep's last column, at_range_end: a value that is the range's end */
      fprintf(gp,
              ", '' u ($1/%.17g):($%d > 0 ? $2 : NaN) w p pt 6 ps 1.6 lw 2 lc 'red' "
              "t 'stable to the range end (a bound, not a critical speed)'",
              sx, 4 + !strcmp(xk, "yaw_damper.damping"));
    fputc('\n', gp);
    return;
  }
  snprintf(yk, sizeof yk, "%.*s", (int)strcspn(y, "="), y);
  sy = axis_label(yk, yl, sizeof yl);
  snprintf(title, sizeof title, "%s over %s and %s", o ? o : "objective", xk, yk);
  int centred = o && (!strncmp(o, "index", 5) || !strncmp(o, "zeta", 4));
  /* yaw damping against series stiffness with an index objective: the sweep
     writes k_opt = c 2 pi f (column 5) of the mode that sets the index; the
     line k = c w is where the stiffness axis equals it (paper Fig. 10) */
  char overlay[400] = "";
  int kx = !strcmp(xk, "yaw_damper.series_stiffness"),
      ky = !strcmp(yk, "yaw_damper.series_stiffness");
  int cx = !strcmp(xk, "yaw_damper.damping"), cy = !strcmp(yk, "yaw_damper.damping");
  if (o && !strncmp(o, "index", 5) && ((kx && cy) || (ky && cx)))
    snprintf(overlay, sizeof overlay,
             ", '' skip 1 u ($1/sx):($2/sy):($%d - $5) w l nosurface lw 2 dt 2 lc 'dark-green' "
             "t 'k = c w'", /* skip: the header's quoted comma would break the grid */
             kx ? 1 : 2);
  if (bound) /* a plateau at the range's end is a bound, not a value: its points marked */
    snprintf(overlay + strlen(overlay), sizeof overlay - strlen(overlay),
             ", '' skip 1 u ($1/sx):($2/sy):($%d > 0 ? $3 : NaN) w p pt 7 ps 1 lc 'black' "
             "t 'stable to the range end (a bound, not a critical speed)'",
             5 + (cx || cy));
  map_script(gp, d, 3, xl, yl, o ? o : "objective", title, centred, overlay, sx, sy, 0);
}

/* The PSDs (columns 2 .. n-1) and, on the right axis, the Sperling
   weighting |B(f)|^2 (the last column) that the index applies to them. */
/* ride --direction vertical|both: the PSD file's last three (four) columns
   are weightings, its second the track's; the EN 12299 Wb on the right */
/* Legends from the PSD column names: psd_c0.1_x8.6875m_m2s-4_per_hz reads
   "conicity 0.1, floor x = 8.6875 m", a lateral_ prefix "lateral, " (and
   the others "vertical, " when both are drawn); other names as they are. */
static const char psd_labels[] =
    "xpos(s) = s[strstrt(s, '_x') + 2:strstrt(s, 'm_m2') - 1]\n"
    "con(s) = strstrt(s, 'psd_c') ? sprintf('conicity %s, ', s[strstrt(s, 'psd_c') + "
    "5:strstrt(s, '_x') - 1]) : ''\n"
    "other = ''  # what a name without the lateral_ prefix is, when both are drawn\n"
    "lat(s) = strstrt(s, 'lateral_') == 1 ? 'lateral, ' : other\n"
    "label(s) = strstrt(s, '_x') && strstrt(s, 'm_m2') ? lat(s) . con(s) . 'floor x = ' . "
    "xpos(s) . ' m' : s\n"
    "set autoscale xfix\n";

static void script_psd_vertical(FILE *gp, const char *d, int nweights)
{
  fputs(psd_labels, gp);
  if (nweights == 4) fputs("other = 'vertical, '\n", gp); /* --direction both */
  fprintf(gp,
          "set title 'Carbody floor acceleration PSDs (PEM) and the EN 12299 Wb weighting'" GP_CTX
          "\n"
          "set datafile separator ','\n"
          "set logscale xy; set xlabel 'frequency (Hz)'; set ylabel 'PSD ((m/s^2)^2/Hz)'; set "
          "format y '%%.0e'\n"
          "set logscale y2; set y2label 'weighting |Wb(f)|^2'; set y2tics; set ytics nomirror; "
          "set key below\n"
          "stats '%s' skip 1 nooutput; n = STATS_columns; w = n - %d\n"
          "top = 0; do for [i=3:w] { stats '%s' u i nooutput; top = STATS_max > top ? STATS_max : "
          "top }\n"
          "set yrange [top * 1e-6:top * 3]  # the filters' exact zeros would take the axis down 10 "
          "decades\n"
          "plot for [i=3:w] '%s' u 1:i w l lw 2 t label(columnhead(i)), "
          "'' u 1:(column(w + 2)) axes x1y2 w l lw 1.5 dt 2 lc 'black' t 'EN 12299 Wb (right)'\n",
          d, nweights, d, d);
}

static void script_psd(FILE *gp, const char *d, int argc, char **argv)
{
  const char *dir = arg_after(argc, argv, "--direction");
  if (dir && strcmp(dir, "lateral")) {
    script_psd_vertical(gp, d, strcmp(dir, "both") ? 3 : 4);
    return;
  }
  fputs(psd_labels, gp);
  fprintf(
      gp,
      "set title 'Carbody floor lateral acceleration PSD (PEM) and the Sperling weighting'" GP_CTX
      "\n"
      "set logscale xy; set xlabel 'frequency (Hz)'; set ylabel 'PSD ((m/s^2)^2/Hz)'; set "
      "format y '%%.0e'\n"
      "set logscale y2; set y2label 'Sperling weighting |B(f)|^2'; set y2tics; set ytics "
      "nomirror; set key below\n"
      "stats '%s' skip 1 nooutput; n = STATS_columns\n"
      "plot for [i=2:n-1] '%s' u 1:i w l lw 2 t label(columnhead(i)), "
      "'' u 1:n axes x1y2 w l lw 1.5 dt 2 lc 'black' t 'Sperling weighting (right)'\n",
      d, d);
}

/* Welch PSDs of the time run, the PEM expectation, and around the PEM the
   +-2 sigma band a Welch bin spreads over (the last column, relative). */
static void script_validate(FILE *gp, const char *d, int argc, char **argv)
{
  (void)argc;
  (void)argv;
  fprintf(
      gp,
      "set title 'Time-domain run (Welch) against the PEM (band: 2 sigma of a Welch bin)'" GP_CTX
      "\n"
      "set logscale xy; set xlabel 'frequency (Hz)'; set ylabel 'PSD ((m/s^2)^2/Hz)'; set "
      "format y '%%.0e'\n"
      "stats '%s' skip 1 nooutput; n = (STATS_columns - 2) / 2; s = STATS_columns\n"
      "set style fill transparent solid 0.25 noborder; set xrange [0.25:35]; set key below\n"
      "pos(v) = v > 0 ? v : 1/0\n"
      "stats '%s' u (pos(column(2 + n))) nooutput; set yrange [STATS_min / 10:*]\n"
      "plot for [i=2+n:1+2*n] '%s' u 1:(pos(column(i) * (1 - 2 * column(s)))):(pos(column(i) * "
      "(1 + 2 * column(s)))) "
      "w filledcurves lc i-n-1 notitle, "
      "for [i=2:1+n] '' u 1:(pos(column(i))) w l lw 1 lc i-1 t columnhead(i), "
      "for [i=2+n:1+2*n] '' u 1:(pos(column(i))) w l lw 2.5 dt 2 lc i-n-1 t columnhead(i)\n",
      d, d, d);
}

/* The vehicles of compare's CSV d in order, each its data rows first .. last
   (0-based after the header): how many. */
#define CMP_VEHICLES_MAX 8
static int compare_vehicles(const char *d, char names[][64], int *first, int *last)
{
  FILE *f = fopen(d, "r");
  char line[1024];
  int n = 0, row = -1;
  while (f && fgets(line, sizeof line, f)) {
    if (row++ < 0) continue; /* the header */
    char *nm;
    cli_csv_split(line, &nm, 1); /* the first field: the vehicle's name */
    if (n && !strcmp(names[n - 1], nm)) {
      last[n - 1] = row - 1;
    } else if (n < CMP_VEHICLES_MAX) {
      snprintf(names[n], 64, "%s", nm);
      first[n] = last[n] = row - 1;
      n++;
    }
  }
  if (f) fclose(f);
  return n;
}

/* One panel of compare's picture: columns c (constant) and c + 1 (SDF)
   against conicity, a curve each per vehicle (its rows; names as data). */
static void compare_panel(FILE *gp, const char *d, const char *ylabel, int c, char names[][64],
                          const int *first, const int *last, int n)
{
  fprintf(gp, "set ylabel '%s'\nplot ", ylabel);
  for (int v = 0; v < n; v++) {
    char t[100], nm[80];
    snprintf(nm, sizeof nm, "%s constant", names[v]);
    fprintf(gp, "%s'%s' skip 1 every ::%d::%d u 2:%d w lp lw 2 lc %d t %s, ", v ? ", " : "", d,
            first[v], last[v], c, v + 1, gp_str(t, sizeof t, nm));
    snprintf(nm, sizeof nm, "%s SDF", names[v]);
    fprintf(gp, "'%s' skip 1 every ::%d::%d u 2:%d w lp lw 2 dt 2 lc %d t %s", d, first[v], last[v],
            c + 1, v + 1, gp_str(t, sizeof t, nm));
  }
  fprintf(gp, "\nunset key\n"); /* one key, above the panels */
}

static void script_compare(FILE *gp, const char *d, int argc, char **argv)
{
  (void)argc;
  (void)argv;
  char names[CMP_VEHICLES_MAX][64];
  int first[CMP_VEHICLES_MAX], last[CMP_VEHICLES_MAX], n = compare_vehicles(d, names, first, last);
  fprintf(
      gp,
      "set datafile separator ','\nset multiplot layout 1,3 title 'Yaw damper: SDF against "
      "constant series stiffness'" GP_CTX "\n"
      "set key at screen 0.5, screen 0.875 center horizontal maxrows 1 font ',9'; set tmargin 5\n"
      "set xlabel 'conicity'; set format x '%%.2g'; set xtics rotate by -45\n");
  compare_panel(gp, d, "stability index", 3, names, first, last, n);
  compare_panel(gp, d, "Sperling index W", 5, names, first, last, n);
  compare_panel(gp, d, "EN 12299 N_MV (with the vertical model)", 7, names, first, last, n);
  fprintf(gp, "unset multiplot\n");
}

static void script_bifurcation(FILE *gp, const char *d, int argc, char **argv)
{
  if (arg_after(argc, argv, "--method") && !strcmp(arg_after(argc, argv, "--method"), "scan")) {
    fprintf(gp,
            "set title 'Limit cycles by direct integration (scan)'" GP_CTX "\n"
            "set xlabel 'speed (km/h)'; set ylabel 'leading wheelset amplitude (mm)'\n"
            "plot '%s' u ((strcol(1) eq 'up') ? $2 : 1/0):($3*1e3) w lp pt 7 t 'speed rising', "
            "'' u ((strcol(1) eq 'down') ? $2 : 1/0):($3*1e3) w lp pt 6 dt 2 t 'speed falling'\n",
            d);
    return;
  }
  /* the straight-running branch: stable up to the Hopf point (where the
     branch of cycles is born, its first row), unstable beyond; folds (the
     speed turns back) and changes of stability marked along the branch */
  double lo = 100, hi = 600;
  const char *sp = arg_after(argc, argv, "--speeds");
  if (sp && sscanf(sp, "%lf:%lf", &lo, &hi) != 2) lo = 100, hi = 600;
  fprintf(
      gp,
      "set title 'Hunting limit cycles (continuation): stable solid, unstable hollow'" GP_CTX "\n"
      "set xlabel 'speed (km/h)'; set ylabel 'leading wheelset amplitude (mm)'; set key top left\n"
      "stats '%s' skip 1 u 1 every ::0::0 nooutput; hopf = STATS_min\n"
      "lo = %.17g; hi = %.17g; set xrange [lo < hopf ? lo : hopf:hi > hopf ? hi : hopf]\n"
      "set offsets 0, 0, graph 0.05, graph 0.02\n"
      "set arrow 1 from lo, 0 to hopf, 0 nohead lw 3 lc rgb '#1b7837' front\n"
      "set arrow 2 from hopf, 0 to hi, 0 nohead lw 2 dt 2 lc rgb '#b2182b' front\n"
      "set label 1 sprintf('Hopf %%.1f km/h', hopf) at hopf, 0 point pt 7 ps 1.5 lc rgb 'black' "
      "right offset -1, 1 front\n"
      "pv = NaN; pdv = NaN; ps = NaN\n"
      "fold(v) = (dv = v - pv, f = (pdv * dv < 0), pdv = (dv != 0 ? dv : pdv), pv = v, f)\n"
      "turn(st) = (t = (ps == ps && st != ps), ps = st, t)\n"
      "plot '%s' u 1:($4 == 1 ? $2*1e3 : 1/0) w p pt 7 ps 0.8 lc rgb '#1b7837' t 'stable cycle', "
      "'' u 1:($4 == 0 ? $2*1e3 : 1/0) w p pt 6 ps 0.8 lc rgb '#b2182b' t 'unstable cycle', "
      "'' u 1:($2*1e3) w l lc rgb '#999999' notitle, "
      "'' u 1:(fold($1) ? $2*1e3 : 1/0) w p pt 4 ps 2 lw 2 lc rgb 'black' t 'fold', "
      "'' u 1:(turn($4) ? $2*1e3 : 1/0) w p pt 8 ps 2 lw 2 lc rgb '#762a83' t 'stability changes', "
      "NaN w l lw 3 lc rgb '#1b7837' t 'straight running, stable', "
      "NaN w l lw 2 dt 2 lc rgb '#b2182b' t 'straight running, unstable'\n",
      d, lo, hi, d);
}

/* The Pareto front: the objectives (the columns that are not section.key
   variables) two by two. The front's file is named in the run's summary. */
/* What the Pareto plots need of a front's CSV (optimise's, or `pareto
   --csv`'s): the columns (0-based) of the objectives and variables, the
   feasibility flag and the cluster letters when present, and each column's
   range over the set. */
#define PP_MAX 32
typedef struct pareto_plot {
  int nobj, obj[PP_MAX], nvar, var[PP_MAX], ncl, col_cluster, col_feasible, ncol;
  char name[PP_MAX * 2][128], letters[27];
  double lo[PP_MAX * 2], hi[PP_MAX * 2];
} pareto_plot;

static int pareto_plot_read(const char *d, pareto_plot *pp)
{
  FILE *f = fopen(d, "r");
  char line[8192];
  memset(pp, 0, sizeof *pp);
  pp->col_cluster = pp->col_feasible = -1;
  if (!f || !fgets(line, sizeof line, f)) {
    if (f) fclose(f);
    return -1;
  }
  char *fld[PP_MAX * 2];
  int col = cli_csv_split(line, fld, PP_MAX * 2);
  for (int j = 0; j < col; j++) { /* the header's fields */
    snprintf(pp->name[j], sizeof pp->name[j], "%s", fld[j]);
    const char *nm = pp->name[j];
    pp->lo[j] = INFINITY, pp->hi[j] = -INFINITY;
    if (!strcmp(nm, "feasible")) pp->col_feasible = j;
    if (!strcmp(nm, "cluster"))
      pp->col_cluster = j;
    else if (cli_pareto_column(nm) == CLI_COL_VAR && pp->nvar < PP_MAX)
      pp->var[pp->nvar++] = j;
    else if (cli_pareto_column(nm) == CLI_COL_OBJ && pp->nobj < PP_MAX)
      pp->obj[pp->nobj++] = j;
  }
  while (fgets(line, sizeof line, f)) { /* data rows: numbers, then the letter */
    char *p = line;
    for (int j = 0; j < col && *p; j++) {
      if (j == pp->col_cluster && *p >= 'A' && *p <= 'Z' && !strchr(pp->letters, *p))
        pp->letters[pp->ncl++] = *p;
      double v = strtod(p, NULL);
      pp->lo[j] = fmin(pp->lo[j], v), pp->hi[j] = fmax(pp->hi[j], v);
      p += strcspn(p, ",");
      p += *p == ',';
    }
  }
  fclose(f);
  pp->ncol = col;
  for (int a = 1; a < pp->ncl; a++) /* A, B, ... in order */
    for (int b = a; b > 0 && pp->letters[b] < pp->letters[b - 1]; b--) {
      char t = pp->letters[b];
      pp->letters[b] = pp->letters[b - 1], pp->letters[b - 1] = t;
    }
  return pp->nobj >= 1 ? 0 : -1;
}

/* The k-means clusters of front d's feasible designs over their objectives,
   as `railride pareto` makes them (the same call on the same rows): the
   centres' first two objectives into c (k x 2). Returns 0, or -1 when the
   front has fewer than k designs. */
static int front_clusters(const char *d, const pareto_plot *pp, int k, double *c)
{
  FILE *f = fopen(d, "r");
  int n = 0, cap = 0, m = pp->nobj, r = -1;
  double *x = NULL, row[PP_MAX * 2], *ctr = malloc(sizeof(double) * cli_at(k, m, 0));
  int *lab = NULL;
  char line[8192];
  if (!f || !ctr || !fgets(line, sizeof line, f)) goto done;
  while (fgets(line, sizeof line, f)) {
    char *p = line;
    for (int j = 0; j < pp->ncol; j++, p += *p == ',') row[j] = strtod(p, &p);
    if (pp->col_feasible >= 0 && row[pp->col_feasible] == 0) continue;
    if (n == cap) {
      double *nx = realloc(x, sizeof(double) * cli_at(cap = cap ? 2 * cap : 256, m, 0));
      if (!nx) goto done;
      x = nx;
    }
    for (int j = 0; j < m; j++) x[cli_at(n, m, j)] = row[pp->obj[j]];
    n++;
  }
  rr_error e;
  if (n >= k && (lab = malloc(sizeof(int) * (size_t)n)) &&
      !rr_kmeans(n, m, x, k, 1, lab, ctr, NULL, &e)) {
    const char *names[PP_MAX];
    for (int j = 0; j < m; j++) names[j] = pp->name[pp->obj[j]];
    cli_paper_letters(n, m, x, names, k, lab, ctr);
    for (int q = 0; q < k; q++)
      c[2 * q] = ctr[cli_at(q, m, 0)], c[2 * q + 1] = ctr[cli_at(q, m, 1)];
    r = 0;
  }
done:
  if (f) fclose(f);
  free(x);
  free(ctr);
  free(lab);
  return r;
}

static void script_optimise(FILE *gp, const char *d, int argc, char **argv)
{
  (void)argc;
  (void)argv;
  pareto_plot pp;
  if (pareto_plot_read(d, &pp)) {
    fprintf(gp, "set title 'no objectives to draw'\nplot 0 notitle\n");
    return;
  }
  int obj[8], nobj = pp.nobj < 8 ? pp.nobj : 8;
  char names[8][128];
  for (int j = 0; j < nobj; j++) {
    obj[j] = pp.obj[j] + 1; /* gnuplot's columns from 1 */
    snprintf(names[j], sizeof names[j], "%s", pp.name[pp.obj[j]]);
  }
  int npairs = nobj * (nobj - 1) / 2;
  char a[200], b[200];
  if (npairs < 1) { /* one objective: its values over the front */
    fprintf(gp,
            "set title 'Pareto front'" GP_CTX
            "\nset ylabel %s\nplot '%s' u 0:%d w p pt 7 notitle\n",
            gp_str(a, sizeof a, names[0]), d, obj[0]);
    return;
  }
  if (nobj == 3) { /* the paper's Fig. 3: the first two, coloured by the third */
    char c[200];
    double cc[2 * CLI_PARETO_CLUSTERS];
    if (!front_clusters(d, &pp, CLI_PARETO_CLUSTERS, cc)) { /* railride pareto's A-D */
      fprintf(gp, "set style textbox opaque noborder\n");
      for (int q = 0; q < CLI_PARETO_CLUSTERS; q++)
        fprintf(gp, "set label %d '%c' at %.17g, %.17g center boxed font ',13' front\n", 200 + q,
                'A' + q, cc[2 * q], cc[2 * q + 1]);
    }
    fprintf(gp,
            "set title 'Pareto front (NSGA-II)'" GP_CTX
            "; set format x '%%.3g'; set format y '%%.3g'\n"
            "set xlabel %s; set ylabel %s; set cblabel %s; set palette rgb 33,13,10\n"
            "plot '%s' u %d:%d:%d w p pt 7 ps 0.6 palette notitle\n",
            gp_str(a, sizeof a, names[0]), gp_str(b, sizeof b, names[1]),
            gp_str(c, sizeof c, names[2]), d, obj[0], obj[1], obj[2]);
    return;
  }
  fprintf(
      gp,
      "set xtics rotate by -45; set format x '%%.2g'; set format y '%%.2g'\n"
      "set multiplot layout 1,%d title 'Pareto front (NSGA-II): the objectives two by two'" GP_CTX
      "\n",
      npairs < 3 ? npairs : 3);
  for (int i = 0, shown = 0; i < nobj && shown < 3; i++)
    for (int j = i + 1; j < nobj && shown < 3; j++, shown++)
      fprintf(gp,
              "set xlabel %s; set ylabel %s\nplot '%s' u %d:%d w p pt 7 ps 0.5 lc rgb "
              "'#2166ac' notitle\n",
              gp_str(a, sizeof a, names[i]), gp_str(b, sizeof b, names[j]), d, obj[i], obj[j]);
  fprintf(gp, "unset multiplot\n");
}

/* modes: one plan-view panel per mode of the data (its '# panel' lines
   give the titles). */
static void script_modes(FILE *gp, const char *d, int argc, char **argv)
{
  (void)argc;
  (void)argv;
  char titles[9][200], line[512];
  int np = 0;
  FILE *f = fopen(d, "r");
  while (f && np < 9 && fgets(line, sizeof line, f)) {
    if (strncmp(line, "# panel ", 8)) continue;
    const char *t = strchr(line, ':');
    line[strcspn(line, "\n")] = 0;
    gp_str(titles[np++], sizeof titles[0], t ? t + 2 : line);
  }
  if (f) fclose(f);
  int cols = np <= 3 ? 1 : np <= 8 ? 2 : 3, rows = (np + cols - 1) / cols;
  fprintf(gp,
          "set datafile separator whitespace\n"
          "set xrange [-16:16]; set yrange [-3.5:3.5]; set ytics 2; set xtics 5\n"
          "set tmargin 2; set bmargin 2.5; set lmargin 7; set rmargin 2\n"
          "set multiplot layout %d,%d title 'Mode shapes in plan view: lateral and yaw "
          "(exaggerated; grey at rest, red phase 0, blue dashed a quarter period later)'" GP_CTX
          " font ',11'\n",
          rows > 0 ? rows : 1, cols);
  for (int p = 0; p < np; p++)
    fprintf(
        gp,
        "set title %s font ',9' offset 0,-0.5\n"
        "set xlabel '%s' offset 0,0.5 font ',9'; set ylabel 'lateral (m)' offset 1,0 font ',9'\n"
        "plot '%s' index %d u 1:2 w l lc rgb '#bbbbbb' notitle, "
        "'' index %d u 1:2 w l lw 2 lc rgb '#b2182b' notitle, "
        "'' index %d u 1:2 w l lw 1.5 dt 2 lc rgb '#2166ac' notitle, "
        "'' index %d u 1:2:3 w labels font ',8' notitle\n",
        titles[p], p >= np - cols ? "x along the car (m)" : "", d, 4 * p, 4 * p + 1, 4 * p + 2,
        4 * p + 3);
  fprintf(gp, "unset multiplot\n");
}

/* contact: the right wheel on its rail (at y = 0 and at the flange), dr,
   the contact angles, tan gamma_e by the three methods, and the contact
   points on rail and wheel against y (the data's comments give the title). */
static void script_contact(FILE *gp, const char *d, int argc, char **argv)
{
  (void)argc;
  (void)argv;
  char line[512], title[300] = "'Contact geometry'";
  FILE *f = fopen(d, "r");
  if (f && fgets(line, sizeof line, f)) {
    line[strcspn(line, "\n")] = 0;
    gp_str(title, sizeof title, line + (line[0] == '#' ? 2 : 0));
  }
  if (f) fclose(f);
  fprintf(
      gp,
      "set datafile separator whitespace; set key top left font ',8'\n"
      "set multiplot layout 3,2 title %s" GP_CTX " font ',10'\n"
      "set title 'right wheel on its rail (grey y = 0, red at the flange)' font ',9'\n"
      "set xlabel 'lateral from the track centre (mm)'; set ylabel 'vertical (mm)'\n"
      "set size ratio -1\n"
      "plot '%s' index 2 u 1:2 w l lc rgb '#444444' notitle, '' index 3 u 1:2 w l lc rgb '#999999' "
      "notitle, '' index 4 u 1:2 w p pt 7 lc rgb '#999999' notitle, '' index 6 u 1:2 w l lc rgb "
      "'#b2182b' notitle, '' index 7 u 1:2 w p pt 7 lc rgb '#b2182b' notitle\n"
      "set size noratio\n"
      "set title 'rolling radius difference' font ',9'; set xlabel 'y (mm)'; set ylabel 'dr (mm)'\n"
      "plot '%s' index 0 u 1:2 w l lw 2 lc rgb '#2166ac' notitle\n"
      "set title 'contact angles' font ',9'; set ylabel 'gamma (rad)'\n"
      "plot '%s' index 0 u 1:3 w l lw 2 t 'right', '' index 0 u 1:4 w l lw 2 dt 2 t 'left'\n"
      "set title 'equivalent conicity' font ',9'; set xlabel 'amplitude (mm)'; "
      "set ylabel 'tan gamma_e'\n"
      "plot '%s' index 1 u 1:2 w l lw 2 t 'EN 15302', '' index 1 u 1:3 w l dt 2 t 'harmonic', "
      "'' index 1 u 1:4 w l dt 3 t 'regression'\n"
      "set title 'contact point on the rail' font ',9'; set xlabel 'y (mm)'; "
      "set ylabel 'v (mm)'\n"
      "plot '%s' index 0 u 1:5 w p pt 7 ps 0.2 t 'right', '' index 0 u 1:6 w p pt 7 ps 0.2 t "
      "'left'\n"
      "set title 'contact point on the wheel' font ',9'; set ylabel 'u (mm)'\n"
      "plot '%s' index 0 u 1:7 w p pt 7 ps 0.2 t 'right', '' index 0 u 1:8 w p pt 7 ps 0.2 t "
      "'left'\n"
      "unset multiplot\n",
      title, d, d, d, d, d, d);
}

/* wear: per wheel profile (numbered along x, names in the key of the
   first panel) the conicity function, tan gamma_e at 3 mm, the stability
   index, the linear critical speed and Sperling at the floor points. */
static void script_wear(FILE *gp, const char *d, int argc, char **argv)
{
  (void)argc;
  (void)argv;
  char names[32][200], line[512], title[300] = "'Wear study'";
  int np = 0;
  FILE *f = fopen(d, "r");
  for (int row = 0; f && fgets(line, sizeof line, f) && line[0] == '#'; row++) {
    line[strcspn(line, "\n")] = 0;
    const char *t = strchr(line, ':');
    if (!row)
      gp_str(title, sizeof title, line + 2);
    else if (np < 32 && t)
      gp_str(names[np++], sizeof names[0], t + 2);
  }
  if (f) fclose(f);
  fprintf(gp,
          "set datafile separator whitespace; set key top left font ',8'\n"
          "set multiplot layout 2,2 title %s" GP_CTX " font ',10'\n"
          "set title 'equivalent conicity (EN 15302)' font ',9'\n"
          "set xlabel 'amplitude (mm)'; set ylabel 'tan gamma_e'\nplot ",
          title);
  for (int i = 0; i < np; i++)
    fprintf(gp, "%s'%s' index 0 u 1:%d w lp pt 7 ps 0.5 lw 2 t %s", i ? ", " : "", d, i + 2,
            names[i]);
  fprintf(gp, "%s\n", np ? "" : "NaN notitle");
  fprintf(gp,
          "set xlabel 'profile (wear stage)'; set xtics 1; set xrange [0.5:%d.5]; set key off\n"
          "set title 'stability index at the speed (below 0 stable)' font ',9'\n"
          "set ylabel 'index'; set xzeroaxis lw 1.5\n"
          "plot '%s' index 1 u 1:3 w lp pt 7 lw 2 lc rgb '#b2182b'\n"
          "set title 'linear critical speed (triangles: none up to " CLI_CRITICAL_TOP
          ")' font ',9'\n"
          "set ylabel 'speed (km/h)'; set yrange [0:660]\n"
          "plot '%s' index 1 u 1:4 w p pt 7 ps 1.2 lc rgb '#2166ac', '' index 1 u 1:8 w p pt 9 "
          "ps 1.5 lc rgb '#2166ac'\n"
          "set yrange [*:*]\n"
          "set title 'Sperling W at the floor points' font ',9'; set ylabel 'W'; set key on\n"
          "plot '%s' index 1 u 1:5 w lp pt 7 lw 2 t '+L', '' index 1 u 1:6 w lp pt 5 lw 2 t "
          "'0', '' index 1 u 1:7 w lp pt 9 lw 2 t '-L'\n"
          "unset multiplot\n",
          np > 0 ? np : 1, d, d, d);
}

/* A CSV column's vehicle-file key: the name less its unit suffix
   ("yaw_damper.damping_n_s_per_m" -> "yaw_damper.damping"), or the name. */
static void column_key(const char *col, char *key, size_t n)
{
  snprintf(key, n, "%s", col);
  for (char *u = strrchr(key, '_'); u && !rr_vehicle_key_find(key); u = strrchr(key, '_')) *u = 0;
  if (!rr_vehicle_key_find(key)) snprintf(key, n, "%s", col);
}

/* A scatter of columns x, y (0-based; scaled by sx, sy) with a colour and a
   letter per cluster. */
static void pareto_scatter(FILE *gp, const char *d, const pareto_plot *pp, int x, int y, double sx,
                           double sy)
{
  fprintf(gp, "plot ");
  for (int q = 0; q < pp->ncl; q++)
    fprintf(gp,
            "%s'%s' u (strcol(%d) eq '%c' ? $%d/%.17g : 1/0):($%d/%.17g) w p pt 7 ps 0.6 lc %d t "
            "'cluster %c'",
            q ? ", " : "", d, pp->col_cluster + 1, pp->letters[q], x + 1, sx, y + 1, sy, q + 1,
            pp->letters[q]);
  fprintf(gp, "\n");
}

/* The paper's Figs. 3, 4 and 6 from `pareto --csv`: the front coloured by
   cluster (the first two objectives, and the second against the third),
   each cluster's variables over their range on the set, and the yaw
   damper's damping against its series stiffness (else the first two
   variables). */
static void script_pareto(FILE *gp, const char *d, int argc, char **argv)
{
  (void)argc, (void)argv;
  pareto_plot pp;
  char a[200], b[200], ka[128], kb[128], la[200], lb[200];
  if (pareto_plot_read(d, &pp)) {
    fprintf(gp, "set title 'no clusters to draw'\nplot 0 notitle\n");
    return;
  }
  fprintf(
      gp,
      "set multiplot layout 2,2 title 'Pareto set in clusters (k-means over the objectives)'" GP_CTX
      "\n"
      "set key at screen 0.5, screen 0.905 center horizontal font ',9'; set tmargin 4\n"
      "set format x '%%.3g'; set format y '%%.3g'; set xtics rotate by -30 font ',9'\n");
  int o0 = pp.obj[0], o1 = pp.obj[1], o2 = pp.nobj > 2 ? pp.obj[2] : pp.obj[0];
  fprintf(gp, "set title 'the front' font ',10'; set xlabel %s; set ylabel %s\n",
          gp_str(a, sizeof a, pp.name[o0]), gp_str(b, sizeof b, pp.name[o1]));
  pareto_scatter(gp, d, &pp, o0, o1, 1, 1);
  fprintf(gp,
          "set title 'the front, second and third objectives' font ',10'; set xlabel %s; set "
          "ylabel %s\n",
          gp_str(a, sizeof a, pp.name[o1]), gp_str(b, sizeof b, pp.name[o2]));
  pareto_scatter(gp, d, &pp, o1, o2, 1, 1);
  /* the variables: each over [least, greatest] on the set, the clusters side by side */
  fprintf(gp,
          "set title 'variables over their range on the set' font ',10'; set xlabel ''; "
          "set ylabel 'fraction of range'; set yrange [-0.05:1.05]; set format x '%%g'\n"
          "set xrange [0.5:%d.5]; set xtics (",
          pp.nvar);
  for (int j = 0; j < pp.nvar; j++) {
    column_key(pp.name[pp.var[j]], ka, sizeof ka);
    for (char *p = ka; *p; p++)
      if (*p == '.' || *p == '_') *p = ' ';
    fprintf(gp, "%s%s %d", j ? ", " : "", gp_str(a, sizeof a, ka), j + 1);
  }
  fprintf(gp, ") rotate by -15 font ',7'\nplot ");
  for (int j = 0; j < pp.nvar; j++)
    for (int q = 0; q < pp.ncl; q++) {
      int c = pp.var[j];
      double w = pp.hi[c] > pp.lo[c] ? pp.hi[c] - pp.lo[c] : 1;
      fprintf(gp,
              "%s'%s' u (strcol(%d) eq '%c' ? %.17g : 1/0):(($%d - %.17g)/%.17g) w p pt 7 ps 0.4 "
              "lc %d %s%c%s",
              j || q ? ", " : "", d, pp.col_cluster + 1, pp.letters[q],
              j + 1 + 0.6 * ((q + 0.5) / pp.ncl - 0.5), c + 1, pp.lo[c], w, q + 1,
              j ? "notitle" : "t 'cluster ", j ? ' ' : pp.letters[q], j ? "" : "'");
    }
  fprintf(
      gp,
      "\nset xrange [*:*]; set yrange [*:*]; set xtics auto norotate font ''; set format x '%%g'; "
      "set format y '%%g'\n");
  if (pp.nvar >= 2) { /* the paper's Fig. 6: yaw damping against series stiffness */
    int x = pp.var[0], y = pp.var[1];
    for (int j = 0; j < pp.nvar; j++) {
      column_key(pp.name[pp.var[j]], ka, sizeof ka);
      if (!strcmp(ka, "yaw_damper.series_stiffness")) x = pp.var[j];
      if (!strcmp(ka, "yaw_damper.damping")) y = pp.var[j];
    }
    column_key(pp.name[x], ka, sizeof ka);
    column_key(pp.name[y], kb, sizeof kb);
    double sx = axis_label(ka, la, sizeof la), sy = axis_label(kb, lb, sizeof lb);
    fprintf(gp, "set title 'the designs, two variables' font ',10'; set xlabel %s; set ylabel %s\n",
            gp_str(a, sizeof a, la), gp_str(b, sizeof b, lb));
    pareto_scatter(gp, d, &pp, x, y, sx, sy);
  }
  fprintf(gp, "unset multiplot\n");
}

static const plot_kind kinds[] = {
    {"wear", NULL, "--plot-data", 0, script_wear},
    {"contact", NULL, "--plot-data", 0, script_contact},
    {"modes", NULL, "--shape-data", 0, script_modes},
    {"damper", NULL, NULL, 0, script_damper},
    {"locus", NULL, NULL, 0, script_locus},
    {"map", NULL, NULL, 1, script_map},
    {"sweep", NULL, NULL, 2, script_sweep},
    {"ride", NULL, "--psd", 0, script_psd},
    {"validate", NULL, "--psd", 0, script_validate},
    {"compare", NULL, "--plot-data", 0, script_compare},
    {"bifurcation", NULL, "--plot-data", 0, script_bifurcation},
    {"optimise", NULL, NULL, 0, script_optimise},
    {"pareto", NULL, "--plot-data", 0, script_pareto},
    {"optimize", NULL, NULL, 0, script_optimise},
};
#define NKINDS (int)(sizeof kinds / sizeof kinds[0])

static const char *terminal_for(const char *path)
{
  const char *dot = strrchr(path, '.');
  if (!dot) return NULL;
  if (!strcmp(dot, ".svg"))
    return "svg size " RR_STR(PLOT_W) "," RR_STR(PLOT_H) " dynamic noenhanced font 'sans,12'";
  if (!strcmp(dot, ".png"))
    return "pngcairo size " RR_STR(PLOT_W) "," RR_STR(PLOT_H) " noenhanced font 'sans,11'";
  if (!strcmp(dot, ".pdf")) return "pdfcairo size 9in,6in noenhanced font 'sans,11'";
  return NULL;
}

/* gnuplot on PATH, as Debian's gnuplot-nox installs it. */
static int have_gnuplot(void)
{
  const char *path = getenv("PATH");
  char buf[PATH_MAX];
  for (const char *p = path ? path : "/usr/bin"; p && *p;) {
    size_t n = strcspn(p, ":");
    snprintf(buf, sizeof buf, "%.*s/gnuplot", (int)n, p);
    if (!access(buf, X_OK)) return 1;
    p += n + (p[n] == ':');
  }
  return 0;
}

/* gnuplot run on the script, without a shell (an argument vector), its
   messages into err; 0 when it exited 0. */
static int run_gnuplot(const char *script, const char *err)
{
  posix_spawn_file_actions_t fa;
  char path[PATH_MAX]; /* argv's strings are writable in the spawn's interface */
  snprintf(path, sizeof path, "%s", script);
  char *const av[] = {"gnuplot", path, NULL};
  pid_t pid;
  int st = -1;
  if (posix_spawn_file_actions_init(&fa)) return -1;
  if (!posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, err, O_WRONLY | O_CREAT | O_TRUNC,
                                        0600) &&
      !posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0) &&
      !posix_spawnp(&pid, "gnuplot", &fa, NULL, av, environ))
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
  posix_spawn_file_actions_destroy(&fa);
  return WIFEXITED(st) && WEXITSTATUS(st) == 0 ? 0 : -1;
}

/* The script and the picture in the private folder dir (fixed names: no
   user text in the script), then the picture copied to out whole. */
/* What the picture is of, from the command line: the vehicle (the first
   argument after the command when it is not an option, or a later *.ini or
   built-in name; else the built-in default), the speed, the conicity and the
   tread when given. */
static void context(int argc, char **argv, char *out, size_t n)
{
  const char *veh = argc > 1 && argv[1][0] != '-' ? argv[1] : NULL;
  for (int i = 2; i < argc && !veh; i++) { /* later: a file.ini, or a built-in's name */
    size_t l = strlen(argv[i]);
    if ((l > 4 && !strcmp(argv[i] + l - 4, ".ini")) || !strcmp(argv[i], "type1") ||
        !strcmp(argv[i], "type2"))
      veh = argv[i];
  }
  const char *slash = veh ? strrchr(veh, '/') : NULL;
  size_t k = (size_t)snprintf(out, n, "%s",
                              veh                           ? (slash ? slash + 1 : veh)
                              : !strcmp(argv[0], "compare") ? "type1 and type2"
                                                            : "type1");
  static const char *const opts[][2] = {
      {"--speed", " km/h"}, {"--conicity", ""}, {"--profile", ""}};
  static const char *const what[] = {"", "conicity ", "tread "};
  for (int i = 0; i < 3 && k < n; i++) {
    const char *v = arg_after(argc, argv, opts[i][0]);
    int plain = v && strspn(v, "0123456789.") == strlen(v); /* a unit given: as written */
    if (v) k += (size_t)snprintf(out + k, n - k, ", %s%s%s", what[i], v, plain ? opts[i][1] : "");
  }
}

/* The gnuplot script drawing data into pic (both names safe in a gnuplot
   string: scratch paths, or plain_name()'s) at script. */
static int write_script(const plot_kind *k, const char *script, const char *out, const char *pic,
                        const char *data, const char *ctx, int argc, char **argv)
{
  FILE *gp = fopen(script, "w");
  if (!gp) return cli_bad("--plot: cannot write a scratch file: %s", strerror(errno));
  fprintf(gp,
          "set terminal %s\nset output '%s'\nset datafile separator ','\nset grid\nset key "
          "noautotitle\n",
          terminal_for(out), pic);
  char lit[320];
  fprintf(gp, "RR_CTX = %s\n", gp_str(lit, sizeof lit, ctx));
  k->script(gp, data, argc, argv);
  if (ferror(gp) | fclose(gp))
    return cli_bad("--plot: cannot write a scratch file: %s", strerror(errno));
  return 0;
}

static int render(const plot_kind *k, const char *dir, const char *out, const char *data,
                  const char *ctx, int argc, char **argv)
{
  char script[PATH_MAX], pic[PATH_MAX], err[PATH_MAX];
  const char *ext = strrchr(out, '.');
  snprintf(script, sizeof script, "%s/plot.gp", dir);
  snprintf(pic, sizeof pic, "%s/picture%s", dir, ext);
  snprintf(err, sizeof err, "%s/gnuplot.err", dir);
  int w = write_script(k, script, out, pic, data, ctx, argc, argv);
  if (w) return w;
  int failed = run_gnuplot(script, err);
  char msg[512] = "", line[512];
  FILE *fe = fopen(err, "r");
  while (fe && fgets(line, sizeof line, fe)) /* the last line that says something */
    if (line[strspn(line, " \t\r\n")]) snprintf(msg, sizeof msg, "%s", line);
  if (fe) fclose(fe);
  msg[strcspn(msg, "\n")] = 0;
  if (failed) {
    fprintf(stderr, "railride: --plot %s: gnuplot failed: %s\n", out, msg[0] ? msg : "no message");
    return EXIT_FAIL;
  }
  if (msg[0]) /* drawn, but something in it may be missing (a curve, a contour) */
    fprintf(stderr, "railride: --plot %s: gnuplot: %s\n", out, msg);
  return cli_out_copy(pic, out, "--plot");
}

/* Copies a data file the command wrote where the user asked into the
   private folder, so that the script names only files of ours. */
static const char *private_copy(const char *src, const char *dir, char *out, size_t n)
{
  snprintf(out, n, "%s/input.csv", dir);
  FILE *f = fopen(src, "rb"), *g = fopen(out, "wb");
  char buf[65536];
  size_t k;
  while (f && g && (k = fread(buf, 1, sizeof buf, f)) > 0) fwrite(buf, 1, k, g);
  if (f) fclose(f);
  if (g) fclose(g);
  return out;
}

/* The private folder and what it holds (files only: made by us). */
static void remove_private(const char *dir)
{
  DIR *d = opendir(dir);
  struct dirent *e;
  char p[PATH_MAX];
  while (d && (e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
    unlink(p);
  }
  if (d) closedir(d);
  rmdir(dir);
}

/* The grid's rows with a blank line wherever the first column changes (how
   gnuplot reads a surface); returns the file written. */
static const char *gridded(const char *in, char *out, size_t n)
{
  snprintf(out, n, "%s.grid", in);
  FILE *f = fopen(in, "r"), *g = fopen(out, "w");
  char line[4096], prev[256] = "";
  for (int row = 0; f && g && fgets(line, sizeof line, f); row++) {
    char key[256];
    snprintf(key, sizeof key, "%.*s", (int)strcspn(line, ","), line);
    if (row > 1 && strcmp(key, prev)) fputc('\n', g);
    snprintf(prev, sizeof prev, "%s", key);
    fputs(line, g);
  }
  if (f) fclose(f);
  if (g) fclose(g);
  return out;
}

/* The Pareto file an optimise run's summary names ("written to F"). */
static const char *front_file(const char *summary, char *out, size_t n)
{
  FILE *f = fopen(summary, "r");
  char line[PATH_MAX + 128];
  out[0] = 0;
  while (f && fgets(line, sizeof line, f)) {
    char *w = strstr(line, "written to ");
    if (w) {
      snprintf(out, n, "%s", w + 11);
      out[strcspn(out, "\r\n")] = 0;
      char *h = strstr(out, " (");
      if (h) *h = 0;
    }
  }
  if (f) fclose(f);
  return out;
}

/* Copies file path to stdout. */
static void replay(const char *path)
{
  FILE *f = fopen(path, "r");
  char buf[65536];
  size_t n;
  while (f && (n = fread(buf, 1, sizeof buf, f)) > 0) fwrite(buf, 1, n, stdout);
  if (f) fclose(f);
  fflush(stdout);
}

/* A name that can stand in a gnuplot string as it is: letters, digits and
   "._-", not starting with '.' or '-'. */
static int plain_name(const char *name)
{
  static const char ok[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-";
  return name[0] && name[0] != '.' && name[0] != '-' && strspn(name, ok) == strlen(name);
}

static const char *base_name(const char *path)
{
  const char *b = strrchr(path, '/');
  return b ? b + 1 : path;
}

/* Script file path with every quoted 'from' replaced by 'to' (data paths:
   plain names, no quote inside). */
static int rename_data(const char *path, const char *from, const char *to)
{
  FILE *f = fopen(path, "r");
  char *text = NULL;
  size_t n = 0, cap = 0, k;
  char buf[4096];
  while (f && (k = fread(buf, 1, sizeof buf, f)) > 0) {
    if (n + k + 1 > cap) {
      char *t = realloc(text, cap = 2 * (n + k + 1));
      if (!t) break;
      text = t;
    }
    memcpy(text + n, buf, k);
    n += k;
  }
  int bad = !f || ferror(f) || !text;
  if (f) fclose(f);
  if (bad) {
    free(text);
    return cli_bad("--plot-script: cannot read a scratch file");
  }
  text[n] = 0;
  char q[PATH_MAX + 2];
  snprintf(q, sizeof q, "'%s'", from);
  FILE *o = fopen(path, "w");
  for (char *p = text, *hit; o && *p; p = hit + strlen(q)) {
    if (!(hit = strstr(p, q))) {
      fputs(p, o);
      break;
    }
    fprintf(o, "%.*s'%s'", (int)(hit - p), p, to);
  }
  free(text);
  if (!o || ferror(o) | fclose(o)) return cli_bad("--plot-script: cannot write a scratch file");
  return 0;
}

/* --plot-script S.gp: the script that drew the picture, for the user to
   restyle, beside its data S.csv; both name their files without a folder,
   so that `gnuplot S.gp` run in S's folder redraws the --plot file there. */
static int user_script(const plot_kind *k, const char *dir, const char *gp, const char *out,
                       const char *data, const char *ctx, int argc, char **argv)
{
  char script[PATH_MAX], csv[PATH_MAX], csv_name[PATH_MAX];
  size_t len = strlen(gp) - 3; /* without ".gp" */
  snprintf(csv, sizeof csv, "%.*s.csv", (int)len, gp);
  snprintf(csv_name, sizeof csv_name, "%s", base_name(csv));
  snprintf(script, sizeof script, "%s/user.gp", dir);
  /* made from the data itself (some scripts read it: labels, clusters), then
     pointed at the copy beside it */
  int r = write_script(k, script, out, base_name(out), data, ctx, argc, argv);
  if (!r) r = rename_data(script, data, csv_name);
  if (!r) r = cli_out_copy(data, csv, "--plot-script");
  return r ? r : cli_out_copy(script, gp, "--plot-script");
}

/* --plot-script's value checked: S.gp, plain names for S and the picture. */
static int script_arg(const char *gp, const char *out)
{
  size_t n = strlen(gp);
  if (n < 4 || strcmp(gp + n - 3, ".gp")) return cli_bad("--plot-script: '%s' must end in .gp", gp);
  if (!plain_name(base_name(gp)) || !plain_name(base_name(out)))
    return cli_bad("--plot-script: the script's and the picture's file names may hold only "
                   "letters, digits, '.', '_' and '-' (they are written into the script)");
  return 0;
}

/* 1 when word is "--NAME" of the plot options' row id. */
static int is_plot_opt(const char *word, int id)
{
  const cli_opt *t = cli_plot_rows();
  for (int i = 0; t[i].name; i++)
    if (t[i].id == id) return !strncmp(word, "--", 2) && !strcmp(word + 2, t[i].name);
  return 0;
}

int cli_plot_run(const char *cmd, int (*fn)(int, char **), int argc, char **argv, int *handled)
{
  *handled = 0;
  int at = -1, sat = -1;
  for (int i = 1; i < argc; i++) {
    if (is_plot_opt(argv[i], OPT_PLOT)) at = i;
    if (is_plot_opt(argv[i], OPT_PLOT_SCRIPT)) sat = i;
  }
  if (at < 0 && sat < 0) return 0;
  *handled = 1;
  if (at < 0) return cli_bad("%s: --plot-script goes with --plot FILE", cmd);
  const plot_kind *k = NULL;
  for (int i = 0; i < NKINDS; i++)
    if (!strcmp(kinds[i].cmd, cmd)) k = &kinds[i];
  if (!k || !cli_plot_options(cmd)) /* both lists, or neither: the help says what runs */
    return cli_bad("%s: --plot is not an option of this command (it has no curve or map to draw)",
                   cmd);
  if (at + 1 >= argc) return cli_bad("--plot: a file name ending in .svg, .png or .pdf expected");
  const char *out = argv[at + 1];
  if (!terminal_for(out)) return cli_bad("--plot: '%s' must end in .svg, .png or .pdf", out);
  if (sat >= 0 && sat + 1 >= argc)
    return cli_bad("--plot-script: a file name ending in .gp expected");
  const char *gp = sat >= 0 ? argv[sat + 1] : NULL;
  if (gp && script_arg(gp, out)) return EXIT_BADINPUT;
  if (!have_gnuplot())
    return cli_bad("--plot: gnuplot not found on PATH (Debian package gnuplot-nox)");
  cli_outfile probe; /* the folder writable, the target untouched */
  int pr = cli_out_open(&probe, out, "--plot");
  if (pr) return pr;
  cli_out_abort(&probe);
  char dir[] = "/tmp/railride_plot_XXXXXX", data[PATH_MAX];
  if (!mkdtemp(dir)) return cli_bad("--plot: no scratch folder: %s", strerror(errno));
  snprintf(data, sizeof data, "%s/data.csv", dir);
  /* the command's own argv without --plot FILE, with what makes its data */
  char **av = calloc((size_t)argc + 4, sizeof *av);
  int n = 0;
  for (int i = 0; i < argc; i++)
    if (i != at && i != at + 1 && (sat < 0 || (i != sat && i != sat + 1))) av[n++] = argv[i];
  const char *file_data = k->file_option ? arg_after(n, av, k->file_option) : NULL;
  char opt_file[64], opt_extra[64]; /* the kind's option names, writable as argv's are */
  snprintf(opt_file, sizeof opt_file, "%s", k->file_option ? k->file_option : "");
  snprintf(opt_extra, sizeof opt_extra, "%s", k->extra ? k->extra : "");
  if (k->file_option && !file_data) {
    av[n++] = opt_file;
    av[n++] = data;
    file_data = data;
  }
  if (k->extra && !has_arg(n, av, k->extra)) av[n++] = opt_extra;
  char ctx[300]; /* before the command runs: getopt_long reorders av */
  context(n, av, ctx, sizeof ctx);
  int r;
  if (k->file_option)
    r = fn(n, av);
  else { /* capture standard output in the data file, then show it */
    fflush(stdout);
    int saved = dup(STDOUT_FILENO);
    FILE *f = freopen(data, "w", stdout);
    r = f ? fn(n, av) : cli_bad("--plot: cannot write a scratch file");
    fflush(stdout);
    dup2(saved, STDOUT_FILENO);
    close(saved);
    replay(data); /* the command's CSV still reaches standard output */
  }
  char grid[PATH_MAX + 8], front[PATH_MAX], copy[PATH_MAX];
  const char *src = file_data ? file_data : data;
  if (!r && k->script == script_optimise) src = front_file(data, front, sizeof front);
  if (!r && strcmp(src, data)) src = private_copy(src, dir, copy, sizeof copy);
  if (!r && (k->grid == 1 || (k->grid == 2 && has_arg(n, av, "--y"))))
    src = gridded(src, grid, sizeof grid);
  if (!r && cli_par_rank() == 0)
    r = render(k, dir, out, src, ctx, n, av); /* one picture from MPI */
  if (!r && gp && cli_par_rank() == 0) r = user_script(k, dir, gp, out, src, ctx, n, av);
  free(av);
  remove_private(dir);
  return r;
}
