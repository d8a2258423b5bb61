#define _POSIX_C_SOURCE 200809L
/* Vehicle files: INI (libinih) with `base =` inheritance, values with units
 * (docs/model.md section 9). Every message names file, line and key. */
#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <stdarg.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/vehicle.h"
#include "util/internal.h"
#include "util/textfile.h"
#include "vehicle/vehicle_json.h"

#define MAX_BASE_DEPTH 8
#define NKEYS_MAX 128 /* room for the key table (checked at each load) */

typedef struct parse_ctx {
  const char *path;
  char dir[PATH_MAX];
  rr_lines rs;
  rr_vehicle *veh;
  rr_units *units;
  rr_error *err;
  int status;
  int pass; /* 1: [vehicle] only; 2: everything */
  char base[PATH_MAX];
  int base_line;
  char name[64];
  int seen[NKEYS_MAX];            /* line where each key was set, 0 if not */
  int curve_keys;                 /* sdf_k1/k2/k3 given: bit mask */
  int profile_keys, profile_line; /* conicity_poly 1, conicity_table 2; where */
  int table_line;
  int known; /* a vehicle-file section was met: the file is one, its text may be quoted */
} parse_ctx;

/* The first failure, "FILE:LINE: message"; returns 0 (inih: stop). */
static int fail(parse_ctx *c, int code, const char *fmt, ...) RR_PRINTF(3, 4);
static int fail(parse_ctx *c, int code, const char *fmt, ...)
{
  if (c->status == RR_OK) {
    char buf[RR_ERROR_MSG_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    c->status = rr_seterr(c->err, code, "%s:%d: %s", c->path, c->rs.line, buf);
  }
  return 0;
}

static void trim_copy(char *dst, size_t n, const char *src)
{
  while (isspace((unsigned char)*src)) src++;
  size_t len = strlen(src);
  while (len && isspace((unsigned char)src[len - 1])) len--;
  if (len >= n) len = n - 1;
  memcpy(dst, src, len);
  dst[len] = 0;
}

/* conicity_poly = c0 c1 ...: plain numbers (a in mm), spaces or commas. */
static int poly_value(parse_ctx *c, const char *section, const char *name, const char *val)
{
  rr_profile *p = &c->veh->profile;
  *p = (rr_profile){.kind = RR_PROFILE_POLY};
  snprintf(p->name, sizeof p->name, "polynomial");
  const char *s = val;
  while (*s) {
    while (isspace((unsigned char)*s) || *s == ',') s++;
    if (!*s) break;
    char *end;
    errno = 0;
    double x = strtod(s, &end);
    if (end == s || errno == ERANGE || !isfinite(x) ||
        (*end && !isspace((unsigned char)*end) && *end != ','))
      return fail(c, RR_EPARSE, "[%s] %s: coefficients are plain numbers (a in mm), got '%s'",
                  section, name, val);
    if (p->n >= RR_PROFILE_MAX)
      return fail(c, RR_EPARSE, "[%s] %s: more than 64 coefficients%s", section, name, "");
    p->c[p->n++] = x;
    s = end;
  }
  if (!p->n) return fail(c, RR_EPARSE, "[%s] %s: no coefficients%s", section, name, "");
  c->profile_line = c->rs.line;
  c->profile_keys |= 1;
  return 1;
}

static void resolve_path(const parse_ctx *c, const char *rel, char *out, size_t n)
{
  if (rel[0] == '/' || !c->dir[0])
    snprintf(out, n, "%s", rel);
  else
    snprintf(out, n, "%s/%s", c->dir, rel);
}

/* Pass 1: the [vehicle] keys that decide how the rest is read. */
static int pass1_key(parse_ctx *c, const char *section, const char *name, const char *value)
{
  if (!strcmp(section, "vehicle") && !strcmp(name, "base")) {
    trim_copy(c->base, sizeof c->base, value);
    c->base_line = c->rs.line;
  }
  if (!strcmp(section, "vehicle") && !strcmp(name, "name"))
    trim_copy(c->name, sizeof c->name, value);
  return 1;
}

/* The key table's entry of [section] name, refused when unknown or given
   twice; NULL then (status set). */
static const rr_vehicle_key *known_key(parse_ctx *c, const char *section, const char *name)
{
  int nk, idx = -1, section_known = 0;
  const rr_vehicle_key *keys = rr_vehicle_keys(&nk);
  for (int i = 0; i < nk && idx < 0; i++) {
    if (strcmp(keys[i].section, section)) continue;
    section_known = 1;
    if (!strcmp(keys[i].key, name)) idx = i;
  }
  char msg[64] = "";
  if (!section_known && !c->known) { /* not a vehicle file: quote none of it */
    if (!c->status)
      c->status = rr_seterr(c->err, RR_EPARSE,
                            "%s:%d: not a vehicle file (no vehicle-file section before this line; "
                            "railride keys lists them)",
                            c->path, c->rs.line);
    return NULL;
  }
  c->known |= section_known;
  if (!section_known || idx < 0) {
    fail(c, RR_EPARSE, section_known ? "[%s] %s: unknown key%s" : "[%s] %s: unknown section%s",
         section, name, msg);
    return NULL;
  }
  if (c->seen[idx]) {
    snprintf(msg, sizeof msg, " (first set on line %d)", c->seen[idx]);
    fail(c, RR_EPARSE, "[%s] %s: key given twice%s", section, name, msg);
    return NULL;
  }
  c->seen[idx] = c->rs.line;
  return &keys[idx];
}

/* A file a key names (a tread table, an SDF table), read relative to the
   vehicle file. */
static int table_key(parse_ctx *c, const rr_vehicle_key *k, const char *val)
{
  char full[PATH_MAX + 8];
  resolve_path(c, val, full, sizeof full);
  rr_error e2;
  if (!strcmp(k->key, "conicity_table")) {
    if (rr_profile_load(full, &c->veh->profile, &e2))
      return fail(c, e2.code, "[%s] %s: %s", k->section, k->key, e2.msg);
    c->profile_line = c->rs.line;
    c->profile_keys |= 2;
    return 1;
  }
  rr_sdf_curve cur;
  memset(&cur, 0, sizeof cur);
  if (rr_sdf_table_load(full, &cur, &e2))
    return fail(c, e2.code, "[%s] %s: %s", k->section, k->key, e2.msg);
  c->veh->sdf = cur;
  c->table_line = c->rs.line;
  return 1;
}

/* [contact]'s wheel and rail profiles: files (relative to this file),
   the inclination (1/40, 1:20 or a decimal), the gauge point (auto or a
   length), the roll (none, rigid). */
static int wheel_rail_key(parse_ctx *c, const rr_vehicle_key *k, const char *val)
{
  rr_wheel_rail *w = &c->veh->wheel_rail;
  static const char *const file_keys[] = {"wheel", "wheel_left", "rail", "rail_left", NULL};
  static const char *const rolls[] = {"none", "rigid", NULL};
  int i = rr_word_index(k->key, file_keys);
  if (i >= 0) {
    char *dst = i < 2 ? w->wheel[i] : w->rail[i - 2];
    char full[PATH_MAX + 8];
    resolve_path(c, val, full, sizeof full);
    if (strlen(full) >= RR_PROFILE_PATH_MAX)
      return fail(c, RR_EINVAL, "[%s] %s: file name too long%s", k->section, k->key, "");
    snprintf(dst, RR_PROFILE_PATH_MAX, "%s", full);
    return 1;
  }
  if (!strcmp(k->key, "roll")) {
    if ((i = rr_word_index(val, rolls)) < 0)
      return fail(c, RR_EINVAL, "[%s] %s: '%s' is not none or rigid", k->section, k->key, val);
    w->roll = i;
    return 1;
  }
  if (!strcmp(k->key, "gauge_point") && !strcmp(val, "auto")) {
    w->gauge_point = NAN;
    return 1;
  }
  double a, b, x;
  char sep, tail;
  rr_error e2;
  if (!strcmp(k->key, "gauge_point")) {
    char what[128];
    snprintf(what, sizeof what, "%s:%d: [contact] gauge_point", c->path, c->rs.line);
    if (rr_units_parse(c->units, val, "m", 0, &x, what, &e2) || !(fabs(x) < 0.2))
      return fail(c, RR_EINVAL, "[%s] %s: a length within 200 mm or auto, got '%s'", k->section,
                  k->key, val);
    w->gauge_point = x;
    return 1;
  }
  if (sscanf(val, " %lf %c %lf %c", &a, &sep, &b, &tail) == 3 && (sep == '/' || sep == ':') &&
      a >= 0 && b > 0)
    x = a / b;
  else if (rr_units_parse(c->units, val, "1", 0, &x, "inclination", &e2))
    return fail(c, RR_EINVAL, "[%s] %s: 1/40, 1:20 or a decimal expected, got '%s'", k->section,
                k->key, val);
  if (!(fabs(x) <= 0.5))
    return fail(c, RR_EINVAL, "[%s] %s: an inclination within 0.5, got '%s'", k->section, k->key,
                val);
  w->inclination = x;
  return 1;
}

/* The keys that are not numbers: sdf, gravity_stiffness, the tread and the
   tables ([vehicle] ones were read in pass 1). */
static int special_key(parse_ctx *c, const rr_vehicle_key *k, const char *val)
{
  static const char *const modes[] = {"none", "paper", "physical", NULL};
  static const int mode_of[] = {RR_SDF_NONE, RR_SDF_PAPER, RR_SDF_PHYSICAL};
  static const char *const yes_no[] = {"yes", "true", "on", "1", "no", "false", "off", "0", NULL};
  int i;
  if (!strcmp(k->section, "vehicle")) return 1;
  if (!strcmp(k->key, "sdf")) {
    if ((i = rr_word_index(val, modes)) < 0)
      return fail(c, RR_EINVAL, "[%s] %s: '%s' is not none, paper or physical", k->section, k->key,
                  val);
    c->veh->sdf_mode = mode_of[i];
    return 1;
  }
  if (!strcmp(k->key, "gravity_stiffness")) {
    if ((i = rr_word_index(val, yes_no)) < 0)
      return fail(c, RR_EINVAL, "[%s] %s: '%s' is not yes or no", k->section, k->key, val);
    c->veh->gravity_stiffness = i < 4;
    return 1;
  }
  if (!strcmp(k->key, "conicity_poly")) return poly_value(c, k->section, k->key, val);
  if (!strcmp(k->key, "conicity_table") || !strcmp(k->key, "sdf_table"))
    return table_key(c, k, val);
  if (!strcmp(k->section, "contact")) return wheel_rail_key(c, k, val); /* the profiles' keys */
  return 1;
}

/* A number with a unit of the key's dimension, within the key's range. */
static int number_key(parse_ctx *c, const rr_vehicle_key *k, const char *val)
{
  char what[RR_ERROR_MSG_MAX];
  snprintf(what, sizeof what, "%s:%d: [%s] %s", c->path, c->rs.line, k->section, k->key);
  double x;
  int st =
      rr_units_parse(c->units, val, k->si_unit, (k->flags & RR_KEY_INF_OK) != 0, &x, what, c->err);
  if (st) {
    c->status = st;
    return 0;
  }
  rr_error e2;
  if ((st = rr_vehicle_key_check(k, x, &e2))) {
    c->status = rr_seterr(c->err, st, "%s:%d: %s (got '%s')", c->path, c->rs.line, e2.msg, val);
    return 0;
  }
  *rr_vehicle_field(c->veh, k) = x;
  if (!strcmp(k->key, "sdf_k1")) c->curve_keys |= 1;
  if (!strcmp(k->key, "sdf_k2")) c->curve_keys |= 2;
  if (!strcmp(k->key, "sdf_k3")) c->curve_keys |= 4;
  return 1;
}

static int handler(void *user, const char *section, const char *name, const char *value)
{
  parse_ctx *c = user;
  if (c->status) return 1; /* first error only */
  if (c->pass == 1) return pass1_key(c, section, name, value);
  const rr_vehicle_key *k = known_key(c, section, name);
  if (!k) return 0;
  char val[PATH_MAX];
  trim_copy(val, sizeof val, value);
  return k->flags & RR_KEY_SPECIAL ? special_key(c, k, val) : number_key(c, k, val);
}

static int is_json(const char *path)
{
  size_t n = strlen(path);
  return n > 5 && !strcmp(path + n - 5, ".json");
}

/* A JSON file's keys through the same handler, each at its line. */
static int run_pass_json(parse_ctx *c, int pass)
{
  c->pass = pass;
  int st = rr_vehicle_json_walk(c->path, handler, c, &c->rs.line, c->err);
  if (c->status) return c->status;
  return st;
}

static int run_pass(parse_ctx *c, int pass)
{
  if (is_json(c->path)) return run_pass_json(c, pass);
  int st = rr_lines_open(&c->rs, c->path, RR_INI_LINE_MAX, c->err);
  if (st) return st;
  c->pass = pass;
  int r = ini_parse_stream(rr_lines_ini_reader, &c->rs, handler, c);
  int line = c->rs.line;
  rr_lines_close(&c->rs);
  c->rs.line = line;
  if (c->status) return c->status;
  if (c->rs.status) return rr_seterr(c->err, c->rs.status, "%s", c->rs.err.msg);
  if (r > 0)
    return rr_seterr(c->err, RR_EPARSE, "%s:%d: malformed line (expected [section] or key = value)",
                     c->path, r);
  if (r < 0) return rr_seterr(c->err, RR_EIO, "%s: cannot read", c->path);
  return RR_OK;
}

static int load_depth(const char *path, rr_vehicle *veh, rr_error *err, int depth);

/* The base file named at the base line: reported there when it cannot be
   read at all. */
static int load_base(parse_ctx *c, rr_vehicle *veh, rr_error *err, int depth)
{
  char bpath[PATH_MAX + 8];
  rr_error e2;
  if (rr_vehicle_builtin(c->base, veh, &e2) == RR_OK) return RR_OK;
  resolve_path(c, c->base, bpath, sizeof bpath);
  FILE *fp = rr_open_regular(bpath, &e2);
  if (!fp)
    return rr_seterr(err, RR_EIO, "%s:%d: [vehicle] base: %s", c->path, c->base_line, e2.msg);
  fclose(fp);
  return load_depth(bpath, veh, err, depth + 1);
}

/* Without a base, every required key must be in the file. */
static int check_required(parse_ctx *c)
{
  int nk;
  const rr_vehicle_key *keys = rr_vehicle_keys(&nk);
  for (int i = 0; i < nk; i++)
    if (!(keys[i].flags & RR_KEY_OPTIONAL) && !c->seen[i])
      return rr_seterr(c->err, RR_EPARSE, "%s:%d: [%s] %s: missing required key (no base given)",
                       c->path, c->rs.line, keys[i].section, keys[i].key);
  return RR_OK;
}

/* The tread: one of the two keys, then checked. */
static int check_tread(parse_ctx *c, rr_vehicle *veh)
{
  if (c->profile_keys == 3)
    return rr_seterr(c->err, RR_EPARSE,
                     "%s:%d: [contact] conicity_table: give either conicity_poly or conicity_table",
                     c->path, c->profile_line);
  if (veh->profile.kind == RR_PROFILE_POLY) veh->profile.hold_mm = veh->conicity_hold * 1e3;
  rr_error e2;
  int st = c->profile_keys ? rr_profile_check(&veh->profile, &e2) : RR_OK;
  if (st)
    rr_seterr(c->err, st, "%s:%d: [contact] %s: %s", c->path, c->profile_line,
              c->profile_keys == 1 ? "conicity_poly" : "conicity_table", e2.msg);
  return st;
}

/* The SDF curve: a table or the three sdf_k keys, and one whenever the SDF
   is on. */
static int check_curve(parse_ctx *c, rr_vehicle *veh)
{
  if (c->table_line && c->curve_keys)
    return rr_seterr(c->err, RR_EPARSE,
                     "%s:%d: [yaw_damper] sdf_table: give either sdf_table or sdf_k1/sdf_k2/sdf_k3",
                     c->path, c->table_line);
  if (c->curve_keys && c->curve_keys != 7) {
    const char *miss = !(c->curve_keys & 1) ? "sdf_k1" : !(c->curve_keys & 2) ? "sdf_k2" : "sdf_k3";
    return rr_seterr(c->err, RR_EPARSE,
                     "%s:%d: [yaw_damper] %s: sdf_k1, sdf_k2 and sdf_k3 go together", c->path,
                     c->rs.line, miss);
  }
  if (c->curve_keys) { /* the file's curve replaces the inherited one as a whole */
    veh->sdf.kind = RR_CURVE_SLS;
    veh->sdf.n = 0;
  }
  if (veh->sdf_mode != RR_SDF_NONE && veh->sdf.kind == RR_CURVE_UNSET)
    return rr_seterr(
        c->err, RR_EPARSE,
        "%s:%d: [yaw_damper] sdf: a curve is required (sdf_k1/sdf_k2/sdf_k3 or sdf_table)", c->path,
        c->rs.line);
  return RR_OK;
}

/* Pass 2 over a file whose pass 1 is done: its base (or empty defaults),
   then its keys, then the checks of the whole. */
static int read_keys(parse_ctx *c, rr_vehicle *veh, int depth)
{
  int has_base = c->base[0] != 0, st = RR_OK;
  if (has_base) {
    if ((st = load_base(c, veh, c->err, depth))) return st;
  } else {
    memset(veh, 0, sizeof *veh);
    rr_vehicle_contact_defaults(veh);  /* the optional nonlinear-model keys */
    rr_vehicle_vertical_defaults(veh); /* and the vertical model's */
  }
  const char *slash = strrchr(c->path, '/');
  snprintf(veh->name, sizeof veh->name, "%s", c->name[0] ? c->name : slash ? slash + 1 : c->path);
  c->veh = veh;
  if ((st = rr_units_new(&c->units, c->err)) || (st = run_pass(c, 2))) return st;
  if ((!has_base && (st = check_required(c))) || (st = check_tread(c, veh)) ||
      (st = check_curve(c, veh)))
    return st;
  rr_error e2;
  if ((st = rr_vehicle_check(veh, &e2))) rr_seterr(c->err, st, "%s: %s", c->path, e2.msg);
  return st;
}

static int load_depth(const char *path, rr_vehicle *veh, rr_error *err, int depth)
{
  if (depth > MAX_BASE_DEPTH)
    return rr_seterr(err, RR_EPARSE, "%s: base chain deeper than %d (a cycle?)", path,
                     MAX_BASE_DEPTH);
  int nk;
  rr_vehicle_keys(&nk);
  if (nk > NKEYS_MAX) /* a key table grown past the parser's room: a build error, told */
    return rr_seterr(err, RR_EUNSUP, "vehicle files: %d keys, the parser has room for %d", nk,
                     NKEYS_MAX);
  parse_ctx *c = calloc(1, sizeof *c);
  if (!c) return rr_seterr(err, RR_ENOMEM, "out of memory");
  c->path = path;
  c->err = err;
  const char *slash = strrchr(path, '/');
  if (slash) snprintf(c->dir, sizeof c->dir, "%.*s", (int)(slash - path), path);
  if (slash == path) snprintf(c->dir, sizeof c->dir, "/");
  int st = run_pass(c, 1);
  if (!st) st = read_keys(c, veh, depth);
  rr_units_free(c->units);
  free(c);
  return st;
}

int rr_vehicle_load(const char *path, rr_vehicle *veh, rr_error *err)
{
  if (!path || !veh) return rr_seterr(err, RR_EINVAL, "rr_vehicle_load: NULL argument");
  rr_vehicle tmp;
  int st = load_depth(path, &tmp, err, 0);
  if (st == RR_OK) *veh = tmp;
  return st;
}

int rr_vehicle_open(const char *spec, rr_vehicle *veh, rr_error *err)
{
  if (!spec) {
    rr_vehicle_default(veh);
    return RR_OK;
  }
  if (rr_vehicle_builtin(spec, veh, NULL) == RR_OK) return RR_OK;
  return rr_vehicle_load(spec, veh, err);
}

int rr_vehicle_new(const char *spec, rr_vehicle **out, rr_error *err)
{
  rr_vehicle *v = malloc(sizeof *v);
  *out = NULL;
  if (!v) return rr_seterr(err, RR_ENOMEM, "out of memory");
  int st = rr_vehicle_open(spec, v, err);
  if (st) {
    free(v);
    return st;
  }
  *out = v;
  return RR_OK;
}

void rr_vehicle_delete(rr_vehicle *veh) { free(veh); }
