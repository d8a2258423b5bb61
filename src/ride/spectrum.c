/* Track irregularity spectra: file format, evaluation, RMS. */
#define _GNU_SOURCE /* dladdr */
#include <ctype.h>
#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <sys/stat.h>
#include <errno.h>
#include <ini.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/spectrum.h"
#include "railride/vehicle.h"
#include "util/internal.h"
#include "util/textfile.h"

#ifndef RR_SPECTRA_DIR
#define RR_SPECTRA_DIR "/usr/local/share/railride/spectra"
#endif
#ifndef RR_INSTALL_DATA_REL
#define RR_INSTALL_DATA_REL "../share" /* the data directory relative to the library's */
#endif

#define SP_SEEN_MAX 32

typedef struct sp_ctx {
  const char *path;
  rr_lines rl;
  rr_spectrum *sp;
  rr_error *err;
  int status;
  int have_form, have_freq, have_psd, have_sided;
  double valid[2];
  int have_valid;
  double psd_scale;
  int two_sided;
  int psd_rad;                /* PSD unit per (rad/m) */
  int psd_angle;              /* PSD numerator an angle squared (rad^2) */
  char seen[SP_SEEN_MAX][16]; /* single-valued keys given so far */
  int nseen;
  int known; /* a spectrum key was read: the file is one, its text may be quoted */
  int seg_line[RR_SPECTRUM_MAX_TERMS]; /* each segment's line */
} sp_ctx;

/* A real root in (0, inf) of the polynomial c[0] x^deg + ... + c[deg]
   (deg 2 or 4, leading 1), by the eigenvalues of its companion matrix. */
static int positive_root(const double *c, int deg, double lo, double hi, double *root)
{
  double C[16] = {0}, wr[4], wi[4];
  for (int j = 0; j < deg; j++) C[j * deg] = -c[j + 1] / c[0]; /* first row, column-major */
  for (int i = 1; i < deg; i++) C[(i - 1) * deg + i] = 1;
  if (LAPACKE_dgeev(LAPACK_COL_MAJOR, 'N', 'N', deg, C, deg, wr, wi, NULL, 1, NULL, 1)) return 0;
  for (int i = 0; i < deg; i++)
    if (fabs(wi[i]) <= 1e-9 * fabs(wr[i]) && wr[i] > lo && wr[i] < hi) {
      *root = wr[i];
      return 1;
    }
  return 0;
}

/* The Chinese form's numerator and denominator have no positive root where
   the formula is used (everywhere when it extends, else within `valid`): a
   pole or a negative region is no PSD. */
static int rational_roots_ok(const char *path, const rr_spectrum *sp, rr_error *err)
{
  double x0 = sp->rad_per_m ? 2 * RR_PI : 1, lo = sp->clip ? sp->valid_lo * x0 : 0,
         hi = sp->clip ? sp->valid_hi * x0 : INFINITY, r;
  const double *p = sp->p;
  const double num[3] = {1, p[1], p[2]}, den[5] = {1, p[3], p[4], p[5], p[6]};
  if (positive_root(num, 2, lo, hi, &r))
    return rr_seterr(err, RR_EINVAL,
                     "%s: params: the PSD turns negative at %g (the numerator's "
                     "root) where it is used",
                     path, r);
  if (positive_root(den, 4, lo, hi, &r))
    return rr_seterr(err, RR_EINVAL, "%s: params: the PSD has a pole at %g where it is used", path,
                     r);
  return RR_OK;
}

/* What every loaded spectrum must satisfy: its form complete, and finite
   and positive across its validity range. */
static int sp_finish(const char *path, rr_spectrum *sp, rr_error *err);
static int sp_load_text(const char *path, rr_spectrum *sp, rr_error *err);

static int sp_fail(sp_ctx *c, int code, const char *key, const char *msg)
{
  if (!c->status)
    c->status = rr_seterr(c->err, code, "%s:%d: %s: %s", c->path, c->rl.line, key, msg);
  return 0;
}

/* Every key but segment, point, source and note may appear once. */
static int sp_once(sp_ctx *c, const char *name)
{
  if (!strcmp(name, "segment") || !strcmp(name, "point") || !strcmp(name, "source") ||
      !strcmp(name, "note"))
    return 1;
  for (int i = 0; i < c->nseen; i++)
    if (!strcmp(c->seen[i], name)) return sp_fail(c, RR_EPARSE, name, "key given twice");
  if (c->nseen < SP_SEEN_MAX && strlen(name) < sizeof c->seen[0])
    snprintf(c->seen[c->nseen++], sizeof c->seen[0], "%s", name);
  return 1;
}

/* Parses exactly n numbers from text. */
static int numbers(const char *text, double *v, int n)
{
  const char *p = text;
  for (int i = 0; i < n; i++) {
    char *end;
    v[i] = strtod(p, &end);
    if (end == p || !isfinite(v[i])) return -1;
    p = end;
  }
  while (isspace((unsigned char)*p)) p++;
  return *p ? -1 : 0;
}

/* "mm^2/(1/m)", "m^2/(rad/m)", "cm^2/(rad/m)", "rad^2/(1/m)" ... */
static int parse_psd_unit(sp_ctx *c, const char *val)
{
  char num[64], den[64];
  const char *slash = strstr(val, "/(");
  if (!slash)
    return sp_fail(c, RR_EUNIT, "psd_unit", "expected LENGTH^2/(1/m) or LENGTH^2/(rad/m)");
  snprintf(num, sizeof num, "%.*s", (int)(slash - val), val);
  snprintf(den, sizeof den, "%s", slash + 2);
  size_t ld = strlen(den);
  if (!ld || den[ld - 1] != ')') return sp_fail(c, RR_EUNIT, "psd_unit", "missing ')'");
  den[ld - 1] = 0;
  if (!strcmp(den, "1/m") || !strcmp(den, "cycle/m"))
    c->psd_rad = 0;
  else if (!strcmp(den, "rad/m"))
    c->psd_rad = 1;
  else
    return sp_fail(c, RR_EUNIT, "psd_unit", "denominator must be (1/m) or (rad/m)");
  if (!strcmp(num, "rad^2") || !strcmp(num, "rad2")) {
    c->psd_scale = 1;
    c->psd_angle = 1;
    return 1;
  }
  double x;
  rr_error e;
  char buf[80];
  snprintf(buf, sizeof buf, "1 %s", num);
  if (rr_units_parse(NULL, buf, "m2", 0, &x, "psd_unit", &e))
    return sp_fail(c, RR_EUNIT, "psd_unit", e.msg);
  c->psd_scale = x;
  return 1;
}

/* A key whose value is one word of a list: direction, form, freq_unit, sided,
   outside, shape. Returns 1 (read), 0 (refused: status set) or -1 (another
   key). */
static int sp_word_key(sp_ctx *c, const char *name, const char *val)
{
  static const char *const dirs[] = {"lateral", "vertical", "crosslevel", "gauge", NULL};
  static const char *const forms[] = {"powerlaw", "german", "fra", "rational7", "table", NULL};
  static const char *const units[] = {"1/m", "cycle/m", "rad/m", NULL};
  static const char *const sides[] = {"one", "two", NULL}, *const outs[] = {"extend", "zero", NULL};
  static const char *const shapes[] = {"alignment", "vertical", "crosslevel", "gauge", NULL};
  static const int form_of[] = {RR_FORM_POWERLAW, RR_FORM_GERMAN, RR_FORM_FRA, RR_FORM_RATIONAL7,
                                RR_FORM_TABLE},
                   shape_of[] = {RR_GERMAN_ALIGNMENT, RR_GERMAN_VERTICAL, RR_GERMAN_CROSSLEVEL,
                                 RR_GERMAN_GAUGE};
  rr_spectrum *s = c->sp;
  int i;
  if (!strcmp(name, "direction")) {
    if ((i = rr_word_index(val, dirs)) < 0)
      return sp_fail(c, RR_EINVAL, name, "lateral, vertical, crosslevel or gauge expected");
    snprintf(s->direction, sizeof s->direction, "%s", val);
  } else if (!strcmp(name, "form")) {
    if ((i = rr_word_index(val, forms)) < 0)
      return sp_fail(c, RR_EINVAL, name, "powerlaw, german, fra, rational7 or table expected");
    c->have_form = 1;
    s->form = form_of[i];
  } else if (!strcmp(name, "freq_unit")) {
    if ((i = rr_word_index(val, units)) < 0)
      return sp_fail(c, RR_EUNIT, name, "1/m or rad/m expected");
    c->have_freq = 1;
    s->rad_per_m = i == 2;
  } else if (!strcmp(name, "sided")) {
    if ((i = rr_word_index(val, sides)) < 0)
      return sp_fail(c, RR_EINVAL, name, "one or two expected");
    c->have_sided = 1;
    c->two_sided = i;
  } else if (!strcmp(name, "outside")) {
    if ((i = rr_word_index(val, outs)) < 0)
      return sp_fail(c, RR_EINVAL, name, "extend or zero expected");
    s->clip = i;
  } else if (!strcmp(name, "shape")) {
    if ((i = rr_word_index(val, shapes)) < 0)
      return sp_fail(c, RR_EINVAL, name, "alignment, vertical, crosslevel or gauge expected");
    s->shape = shape_of[i];
  } else
    return -1;
  return 1;
}

/* segment = n_lo n_hi A k: one piece of a piecewise power law. */
static int sp_segment(sp_ctx *c, const char *name, const char *val)
{
  rr_spectrum *s = c->sp;
  double v[4];
  if (numbers(val, v, 4) || !(v[0] > 0 && v[1] > v[0] && v[2] > 0))
    return sp_fail(c, RR_EINVAL, name, "n_lo n_hi A k expected, 0 < n_lo < n_hi, A > 0");
  if (s->nseg >= RR_SPECTRUM_MAX_TERMS) return sp_fail(c, RR_EINVAL, name, "too many segments");
  if (s->nseg && fabs(v[0] - s->seg_hi[s->nseg - 1]) > 1e-12 * v[0])
    return sp_fail(c, RR_EINVAL, name, "segments must be contiguous and increasing");
  c->seg_line[s->nseg] = c->rl.line;
  s->seg_lo[s->nseg] = v[0];
  s->seg_hi[s->nseg] = v[1];
  s->seg_A[s->nseg] = v[2];
  s->seg_k[s->nseg] = v[3];
  s->nseg++;
  return 1;
}

/* One row more of a table, the arrays grown by doubling. */
static int table_push(rr_spectrum *s, double n, double S, rr_error *err)
{
  if (s->npts >= RR_SPECTRUM_MAX_POINTS)
    return rr_seterr(err, RR_EINVAL, "%s: more than %d table rows", s->path,
                     RR_SPECTRUM_MAX_POINTS);
  if (s->npts == s->tab_cap) {
    int cap = s->tab_cap ? 2 * s->tab_cap : 64;
    double *a = realloc(s->tab_n, sizeof *a * (size_t)cap);
    if (a) s->tab_n = a;
    double *b = a ? realloc(s->tab_S, sizeof *b * (size_t)cap) : NULL;
    if (b) s->tab_S = b;
    if (!a || !b) return rr_seterr(err, RR_ENOMEM, "out of memory");
    s->tab_cap = cap;
  }
  s->tab_n[s->npts] = n;
  s->tab_S[s->npts] = S;
  s->npts++;
  return RR_OK;
}

/* point = n S: one row of a table. */
static int sp_point(sp_ctx *c, const char *name, const char *val)
{
  rr_spectrum *s = c->sp;
  double v[2];
  if (numbers(val, v, 2) || !(v[0] > 0 && v[1] > 0))
    return sp_fail(c, RR_EINVAL, name, "n S expected, both > 0");
  if (s->npts && !(v[0] > s->tab_n[s->npts - 1]))
    return sp_fail(c, RR_EINVAL, name, "frequencies must increase");
  int st = table_push(s, v[0], v[1], c->err);
  if (st) {
    c->status = st;
    return 0;
  }
  return 1;
}

/* The numeric keys: valid, params and the forms' single coefficients. */
static int sp_number_key(sp_ctx *c, const char *name, const char *val)
{
  rr_spectrum *s = c->sp;
  if (!strcmp(name, "valid")) {
    if (numbers(val, c->valid, 2) || !(c->valid[0] > 0 && c->valid[1] > c->valid[0]))
      return sp_fail(c, RR_EINVAL, name, "two numbers 0 < lo < hi expected");
    c->have_valid = 1;
    return 1;
  }
  if (!strcmp(name, "params"))
    return numbers(val, s->p, 7)
               ? sp_fail(c, RR_EINVAL, name, "seven numbers A B C D E F G expected")
               : 1;
  double *dst = !strcmp(name, "A")    ? &s->A
                : !strcmp(name, "Oc") ? &s->Oc
                : !strcmp(name, "Or") ? &s->Or
                : !strcmp(name, "Os") ? &s->Os
                : !strcmp(name, "b")  ? &s->b
                : !strcmp(name, "k")  ? &s->k
                                      : NULL;
  if (!dst && !c->known) {
    if (!c->status)
      c->status = rr_seterr(c->err, RR_EPARSE,
                            "%s:%d: not a spectrum file (no spectrum key before this line)",
                            c->path, c->rl.line);
    return 0;
  }
  if (!dst) return sp_fail(c, RR_EPARSE, name, "unknown key");
  if (numbers(val, dst, 1) || !(*dst > 0))
    return sp_fail(c, RR_EINVAL, name, "a number > 0 expected");
  return 1;
}

/* The keys a spectrum file may hold. */
static int sp_known_key(const char *name)
{
  static const char *const keys[] = {
      "name", "title",     "source", "note",  "psd_unit", "segment", "point",  "direction",
      "form", "freq_unit", "sided",  "valid", "outside",  "shape",   "params", "A",
      "Oc",   "Or",        "Os",     "b",     "k",        NULL};
  return rr_word_index(name, keys) >= 0;
}

static int sp_handler(void *user, const char *section, const char *name, const char *value)
{
  sp_ctx *c = user;
  rr_spectrum *s = c->sp;
  if (c->status) return 1;
  if (section[0] && !c->known) {
    c->status = rr_seterr(c->err, RR_EPARSE, "%s:%d: not a spectrum file (it has sections)",
                          c->path, c->rl.line);
    return 0;
  }
  if (section[0]) return sp_fail(c, RR_EPARSE, section, "spectrum files have no sections");
  if (!sp_once(c, name)) return 0;
  c->known |= sp_known_key(name);
  char val[256];
  snprintf(val, sizeof val, "%s", value);
  if (!strcmp(name, "name"))
    snprintf(s->name, sizeof s->name, "%s", val);
  else if (!strcmp(name, "title"))
    snprintf(s->title, sizeof s->title, "%s", val);
  else if (!strcmp(name, "source") || !strcmp(name, "note"))
    ; /* for the reader */
  else if (!strcmp(name, "psd_unit")) {
    c->have_psd = 1;
    return parse_psd_unit(c, val);
  } else if (!strcmp(name, "segment"))
    return sp_segment(c, name, val);
  else if (!strcmp(name, "point"))
    return sp_point(c, name, val);
  else {
    int r = sp_word_key(c, name, val);
    return r >= 0 ? r : sp_number_key(c, name, val);
  }
  return 1;
}

/* A measured PSD's header: the frequency column's unit (cycles/m or rad/m)
   and the PSD's (a length squared per the same). */
static int csv_header(const char *path, const char *line, rr_spectrum *sp, double *lscale,
                      rr_error *err)
{
  char a[128] = "", b[128] = "";
  if (sscanf(line, " %127[^, \t] %*[, \t] %127[^, \t\r]", a, b) != 2)
    return rr_seterr(err, RR_EPARSE, "%s:1: header: two column names expected", path);
  int rad;
  if (!strcmp(a, "n_per_m") || !strcmp(a, "n_cycles_per_m") || !strcmp(a, "n_1_per_m"))
    rad = 0;
  else if (!strcmp(a, "omega_rad_per_m"))
    rad = 1;
  else
    return rr_seterr(err, RR_EUNIT,
                     "%s:1: header: '%s' is not n_per_m, n_cycles_per_m or omega_rad_per_m", path,
                     a);
  static const char *const lengths[][2] = {
      {"m2", "1"}, {"mm2", "1e-6"}, {"cm2", "1e-4"}, {"um2", "1e-12"}};
  static const char *const dens[2][3] = {{"_per_per_m", "_per_cycle_per_m", "_per_cycles_per_m"},
                                         {"_per_rad_per_m", "", ""}};
  for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++)
    for (int d = 0; d < 3; d++) {
      char want[64];
      if (!dens[rad][d][0]) continue;
      snprintf(want, sizeof want, "psd_%s%s", lengths[i][0], dens[rad][d]);
      if (strcmp(b, want)) continue;
      *lscale = strtod(lengths[i][1], NULL);
      sp->rad_per_m = rad;
      return RR_OK;
    }
  return rr_seterr(err, RR_EUNIT,
                   "%s:1: header: '%s' is not a PSD unit matching '%s' (e.g. psd_m2_per_per_m, "
                   "psd_mm2_per_cycle_per_m, psd_mm2_per_rad_per_m)",
                   path, b, a);
}

static int sp_load_csv(const char *path, rr_spectrum *sp, rr_error *err)
{
  rr_lines rl;
  const char *line;
  double lscale = 1;
  int st = rr_lines_open(&rl, path, RR_CSV_LINE_MAX, err), r, head = 0;
  while (!st && (r = rr_lines_next(&rl, &line)) > 0) {
    double n, S;
    if (!head) {
      if (!*line) continue; /* a comment before the header */
      st = csv_header(path, line, sp, &lscale, err);
      head = 1;
      continue;
    }
    int k = rr_csv_pair(line, sp->npts + 1, &n, &S);
    if (k == 0) continue;
    if (k < 0 || !isfinite(n) || !isfinite(S) || !(n > 0) || !(S > 0))
      st = rr_seterr(err, RR_EINVAL, "%s:%d: two numbers n > 0, PSD > 0 expected", path, rl.line);
    else if (sp->npts && !(n > sp->tab_n[sp->npts - 1]))
      st = rr_seterr(err, RR_EINVAL, "%s:%d: frequencies must increase", path, rl.line);
    else
      st = table_push(sp, n, S, err);
  }
  if (!st && rl.status) st = rr_seterr(err, rl.status, "%s", rl.err.msg);
  rr_lines_close(&rl);
  if (st) return st;
  if (!head) return rr_seterr(err, RR_EPARSE, "%s: no header (n_per_m,psd_m2_per_per_m)", path);
  if (sp->npts < 2) return rr_seterr(err, RR_EPARSE, "%s: a PSD needs at least two rows", path);
  snprintf(sp->direction, sizeof sp->direction, "lateral");
  sp->form = RR_FORM_TABLE;
  double f = sp->rad_per_m ? 1.0 / (2 * RR_PI) : 1.0;
  sp->valid_lo = sp->tab_n[0] * f;
  sp->valid_hi = sp->tab_n[sp->npts - 1] * f;
  sp->scale = lscale * (sp->rad_per_m ? 2 * RR_PI : 1.0);
  return sp_finish(path, sp, err);
}

int rr_spectrum_load(const char *path, rr_spectrum *sp, rr_error *err)
{
  memset(sp, 0, sizeof *sp);
  snprintf(sp->path, sizeof sp->path, "%s", path);
  size_t len = strlen(path);
  int st = len > 4 && !strcmp(path + len - 4, ".csv") ? sp_load_csv(path, sp, err)
                                                      : sp_load_text(path, sp, err);
  if (st) rr_spectrum_close(sp);
  return st;
}

void rr_spectrum_close(rr_spectrum *sp)
{
  if (!sp) return;
  free(sp->tab_n);
  free(sp->tab_S);
  sp->tab_n = sp->tab_S = NULL;
  sp->npts = sp->tab_cap = 0;
}

int rr_spectrum_copy(const rr_spectrum *src, rr_spectrum *dst, rr_error *err)
{
  *dst = *src;
  dst->tab_n = dst->tab_S = NULL;
  dst->npts = dst->tab_cap = 0;
  for (int i = 0; i < src->npts; i++) {
    int st = table_push(dst, src->tab_n[i], src->tab_S[i], err);
    if (st) {
      rr_spectrum_close(dst);
      return st;
    }
  }
  return RR_OK;
}

int rr_spectrum_require(const rr_spectrum *sp, const char *direction, const char *use,
                        rr_error *err)
{
  if (!strcmp(sp->direction, direction)) return RR_OK;
  return rr_seterr(err, RR_EINVAL, "%s: a %s spectrum, not %s%s (%s)", sp->path, sp->direction,
                   direction, strcmp(direction, "lateral") ? "" : " alignment", use);
}

/* Each power-law segment finite and positive over its part of the validity
   range (the end segments extended to it): A / x^k is monotonic, so its
   ends bound it, where sp_finish's grid could step over a narrow overflow. */
static int segments_bounded(sp_ctx *c)
{
  const rr_spectrum *sp = c->sp;
  if (sp->form != RR_FORM_POWERLAW) return RR_OK;
  double x0 = sp->rad_per_m ? 2 * RR_PI : 1, vlo = sp->valid_lo * x0, vhi = sp->valid_hi * x0;
  for (int i = 0; i < sp->nseg; i++) {
    double ends[2] = {i == 0 ? vlo : fmax(sp->seg_lo[i], vlo),
                      i == sp->nseg - 1 ? vhi : fmin(sp->seg_hi[i], vhi)};
    for (int e = 0; e < 2 && ends[0] <= ends[1]; e++) {
      double S = sp->scale * (sp->seg_A[i] / pow(ends[e], sp->seg_k[i]));
      if (!(isfinite(S) && S > 0))
        return rr_seterr(c->err, RR_EINVAL,
                         "%s:%d: segment: PSD not finite and positive at n = %g 1/m", c->path,
                         c->seg_line[i], ends[e] / x0);
    }
  }
  return RR_OK;
}

static int sp_load_text(const char *path, rr_spectrum *sp, rr_error *err)
{
  sp_ctx c;
  memset(&c, 0, sizeof c);
  c.path = path;
  c.sp = sp;
  c.err = err;
  int st = rr_lines_open(&c.rl, path, RR_INI_LINE_MAX, err);
  if (st) return st;
  int r = ini_parse_stream(rr_lines_ini_reader, &c.rl, sp_handler, &c);
  rr_lines_close(&c.rl);
  if (c.status) return c.status;
  if (c.rl.status) return rr_seterr(err, c.rl.status, "%s", c.rl.err.msg);
  if (r > 0)
    return rr_seterr(err, RR_EPARSE, "%s:%d: malformed line (expected key = value)", path, r);
  const char *miss = !c.have_form        ? "form"
                     : !c.have_freq      ? "freq_unit"
                     : !c.have_psd       ? "psd_unit"
                     : !c.have_sided     ? "sided"
                     : !c.have_valid     ? "valid"
                     : !sp->direction[0] ? "direction"
                                         : NULL;
  if (miss) return rr_seterr(err, RR_EPARSE, "%s: %s: missing required key", path, miss);
  if (c.psd_rad != sp->rad_per_m)
    return rr_seterr(err, RR_EUNIT, "%s: psd_unit: its denominator must match freq_unit", path);
  if (c.psd_angle &&
      strcmp(sp->direction, "crosslevel")) /* cross level: an angle or a height difference */
    return rr_seterr(err, RR_EUNIT,
                     "%s: psd_unit: a %s spectrum is in a length squared (m^2, mm^2), not rad^2",
                     path, sp->direction);
  double f = sp->rad_per_m ? 1.0 / (2 * RR_PI) : 1.0; /* validity to cycles/m */
  sp->valid_lo = c.valid[0] * f;
  sp->valid_hi = c.valid[1] * f;
  sp->scale = c.psd_scale * (c.two_sided ? 2.0 : 1.0) * (sp->rad_per_m ? 2 * RR_PI : 1.0);
  if ((st = segments_bounded(&c))) return st;
  return sp_finish(path, sp, err);
}

static int sp_finish(const char *path, rr_spectrum *sp, rr_error *err)
{
  if (!sp->name[0]) {
    const char *b = strrchr(path, '/');
    snprintf(sp->name, sizeof sp->name, "%s", b ? b + 1 : path);
    char *dot = strrchr(sp->name, '.');
    if (dot) *dot = 0;
  }
  switch (sp->form) {
  case RR_FORM_POWERLAW:
    if (!sp->nseg)
      return rr_seterr(err, RR_EPARSE, "%s: segment: powerlaw needs at least one segment", path);
    break;
  case RR_FORM_GERMAN:
    if (!(sp->A > 0 && sp->Oc > 0 && sp->Or > 0))
      return rr_seterr(err, RR_EPARSE, "%s: german form needs A, Oc, Or", path);
    if (sp->shape >= RR_GERMAN_CROSSLEVEL && !(sp->Os > 0))
      return rr_seterr(err, RR_EPARSE, "%s: Os: needed for this shape", path);
    if (sp->shape == RR_GERMAN_CROSSLEVEL && !(sp->b > 0))
      return rr_seterr(err, RR_EPARSE, "%s: b: needed for cross level", path);
    break;
  case RR_FORM_FRA:
    if (!(sp->A > 0 && sp->Oc > 0 && sp->k > 0))
      return rr_seterr(err, RR_EPARSE, "%s: fra form needs k, A, Oc", path);
    break;
  case RR_FORM_TABLE:
    if (sp->npts < 2)
      return rr_seterr(err, RR_EPARSE, "%s: point: a table needs at least two points", path);
    break;
  case RR_FORM_RATIONAL7:
    if (!(sp->p[0] > 0))
      return rr_seterr(err, RR_EPARSE, "%s: params: seven numbers with A > 0 needed", path);
    return rational_roots_ok(path, sp, err);
  }
  /* the formula must be finite and positive across the validity range */
  for (int i = 0; i <= 50; i++) {
    double n = sp->valid_lo * pow(sp->valid_hi / sp->valid_lo, i / 50.0);
    double s = rr_spectrum_eval(sp, n);
    if (!(isfinite(s) && s > 0))
      return rr_seterr(err, RR_EINVAL, "%s: PSD not finite and positive at n = %g 1/m", path, n);
  }
  return RR_OK;
}

/* The installed tree's spectra, found from where this library was loaded:
   LIBDIR/../share/railride/spectra (a relocatable install), else the source
   tree's the library was built from. Found once per process. */
static char spectra_dir[PATH_MAX];
static pthread_once_t spectra_once = PTHREAD_ONCE_INIT;

static void find_spectra(void)
{
  Dl_info info;
  struct stat st;
  snprintf(spectra_dir, sizeof spectra_dir, "%s", RR_SPECTRA_DIR);
  if (!dladdr((void *)rr_spectrum_dir, &info) || !info.dli_fname) return;
  const char *slash = strrchr(info.dli_fname, '/');
  if (!slash) return;
  char cand[PATH_MAX];
  snprintf(cand, sizeof cand, "%.*s/" RR_INSTALL_DATA_REL "/railride/spectra",
           (int)(slash - info.dli_fname), info.dli_fname);
  if (!stat(cand, &st) && S_ISDIR(st.st_mode))
    snprintf(spectra_dir, sizeof spectra_dir, "%s", cand);
}

const char *rr_spectrum_dir(void)
{
  const char *d = getenv("RAILRIDE_SPECTRA_DIR");
  if (d && *d) return d;
  pthread_once(&spectra_once, find_spectra);
  return spectra_dir;
}

int rr_spectrum_open(const char *spec, rr_spectrum *sp, rr_error *err)
{
  memset(sp, 0, sizeof *sp); /* closable whatever happens */
  size_t len = strlen(spec);
  if (strchr(spec, '/') ||
      (len > 4 && (!strcmp(spec + len - 4, ".txt") || !strcmp(spec + len - 4, ".csv"))))
    return rr_spectrum_load(spec, sp, err);
  for (const char *p = spec; *p; p++)
    if (!(isalnum((unsigned char)*p) || *p == '-' || *p == '_' || *p == '.'))
      return rr_seterr(err, RR_EINVAL, "spectrum name '%s': letters, digits, '-', '_' only", spec);
  char path[1024];
  snprintf(path, sizeof path, "%s/%s.txt", rr_spectrum_dir(), spec);
  FILE *fp = rr_open_regular(path, NULL);
  if (!fp) return rr_seterr(err, RR_EIO, "unknown spectrum '%s' (no file %s)", spec, path);
  fclose(fp);
  return rr_spectrum_load(path, sp, err);
}

/* The formula in its own variable x (n or Omega) and units. */
static double raw(const rr_spectrum *s, double x)
{
  switch (s->form) {
  case RR_FORM_POWERLAW: {
    int i = 0;
    while (i < s->nseg - 1 && x > s->seg_hi[i]) i++; /* end segments extend outward */
    return s->seg_A[i] / pow(x, s->seg_k[i]);
  }
  case RR_FORM_GERMAN: {
    double w2 = x * x, c2 = s->Oc * s->Oc, r2 = s->Or * s->Or, s2 = s->Os * s->Os;
    switch (s->shape) {
    case RR_GERMAN_ALIGNMENT:
    case RR_GERMAN_VERTICAL: return s->A * c2 / ((w2 + r2) * (w2 + c2));
    case RR_GERMAN_CROSSLEVEL:
      return (s->A / (s->b * s->b)) * c2 * w2 / ((w2 + r2) * (w2 + c2) * (w2 + s2));
    default: return s->A * c2 * w2 / ((w2 + r2) * (w2 + c2) * (w2 + s2));
    }
  }
  case RR_FORM_FRA: return s->k * s->A * s->Oc * s->Oc / (x * x * (x * x + s->Oc * s->Oc));
  case RR_FORM_RATIONAL7: {
    const double *p = s->p;
    return p[0] * (x * x + p[1] * x + p[2]) /
           (x * x * x * x + p[3] * x * x * x + p[4] * x * x + p[5] * x + p[6]);
  }
  case RR_FORM_TABLE: {
    if (x <= s->tab_n[0])
      return s->tab_S[0] *
             pow(x / s->tab_n[0], log(s->tab_S[1] / s->tab_S[0]) / log(s->tab_n[1] / s->tab_n[0]));
    int lo = 0, hi = s->npts - 1;
    if (x >= s->tab_n[hi])
      lo = hi - 1;
    else
      while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (s->tab_n[mid] <= x)
          lo = mid;
        else
          hi = mid;
      }
    hi = lo + 1;
    double slope = log(s->tab_S[hi] / s->tab_S[lo]) / log(s->tab_n[hi] / s->tab_n[lo]);
    return s->tab_S[lo] * pow(x / s->tab_n[lo], slope);
  }
  }
  return 0;
}

double rr_spectrum_eval(const rr_spectrum *s, double n)
{
  if (!(n > 0)) return 0;
  if (s->clip && (n < s->valid_lo * (1 - 1e-12) || n > s->valid_hi * (1 + 1e-12))) return 0;
  return s->scale * raw(s, s->rad_per_m ? 2 * RR_PI * n : n);
}

double rr_spectrum_rms(const rr_spectrum *s, double n1, double n2)
{
  /* integral of S(n) dn = integral of S(n) n d(ln n); Simpson on a fine log grid,
     split at segment bounds so power-law kinks do not cost accuracy */
  double cuts[RR_SPECTRUM_MAX_TERMS + 2];
  int nc = 0;
  cuts[nc++] = n1;
  if (s->form == RR_FORM_POWERLAW)
    for (int i = 0; i < s->nseg - 1; i++) {
      double b = s->seg_hi[i] / (s->rad_per_m ? 2 * RR_PI : 1);
      if (b > n1 && b < n2) cuts[nc++] = b;
    }
  cuts[nc++] = n2;
  double total = 0;
  for (int c = 0; c + 1 < nc; c++) {
    double a = log(cuts[c]), b = log(cuts[c + 1]);
    int m = 2000;
    double h = (b - a) / m, sum = 0;
    for (int i = 0; i <= m; i++) {
      /* end samples just inside the piece: segments need not meet continuously */
      double x = i == 0   ? cuts[c] * (1 + 1e-13)
                 : i == m ? cuts[c + 1] * (1 - 1e-13)
                          : exp(a + i * h);
      double w = (i == 0 || i == m) ? 1 : (i % 2 ? 4 : 2);
      sum += w * rr_spectrum_eval(s, x) * x;
    }
    total += sum * h / 3;
  }
  return sqrt(total);
}

int rr_spectrum_new(const char *spec, rr_spectrum **out, rr_error *err)
{
  rr_spectrum *sp = malloc(sizeof *sp);
  *out = NULL;
  if (!sp) return rr_seterr(err, RR_ENOMEM, "out of memory");
  int st = rr_spectrum_open(spec, sp, err);
  if (st) {
    free(sp);
    return st;
  }
  *out = sp;
  return RR_OK;
}

void rr_spectrum_delete(rr_spectrum *sp)
{
  rr_spectrum_close(sp);
  free(sp);
}
