/* Values with units ("50 kN/mm") converted to SI through udunits2.
 *
 * A value is one number, optionally followed by a unit of exactly the
 * quantity's dimension, related to its SI unit by a plain scale factor.
 * udunits reads far more than that (expressions: "1.6.2 m" is 0.32 m,
 * "38936 kg 2" is 77872 kg; offsets "kg since 2000", logarithms "lg(re 1
 * kg)", reciprocals: "2e-8 m/N" converts to a stiffness), so the unit text is
 * checked against a small grammar first (unit names with integer powers,
 * joined by '.', '*', '/', spaces and parentheses; the number 1 only as a
 * numerator, as in "1/m"), and the conversion must map x to a x with a > 0.
 *
 * The unit database is loaded once per process and, udunits' parser not
 * being reentrant, every use holds one lock: contexts in several threads
 * may parse at once. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <udunits2.h>
#include "railride/units.h"
#include "util/internal.h"

#define UNIT_TEXT_MAX 128

static pthread_once_t db_once = PTHREAD_ONCE_INIT;
static pthread_mutex_t db_lock = PTHREAD_MUTEX_INITIALIZER;
static ut_system *db; /* read-only once loaded */

static void db_load(void)
{
  ut_set_error_message_handler(ut_ignore); /* a library must not print */
  db = ut_read_xml(NULL);
}

static int db_get(rr_error *err)
{
  pthread_once(&db_once, db_load);
  if (db) return RR_OK;
  return rr_seterr(err, RR_EIO,
                   "cannot load the udunits2 unit database (package libudunits2-data)");
}

struct rr_units {
  int unused;
};

int rr_units_new(rr_units **out, rr_error *err)
{
  *out = NULL;
  int st = db_get(err);
  if (st) return st;
  *out = calloc(1, sizeof **out);
  return *out ? RR_OK : rr_seterr(err, RR_ENOMEM, "out of memory");
}

void rr_units_free(rr_units *u) { free(u); }

/* udunits words that make a unit an offset, a logarithm or a time origin,
   and its division by a word ("m per s"; '/' is the grammar's): udunits'
   scanner takes them in any case, and its parser leaks a token on some
   spellings of "per" ("m per0s"), found by fuzz_units. */
static int keyword(const char *id, size_t n)
{
  static const char *const words[] = {"since", "after", "from", "ref", "lg", "log", "ln", "per"};
  for (size_t i = 0; i < sizeof words / sizeof words[0]; i++)
    if (strlen(words[i]) == n && !strncasecmp(words[i], id, n)) return 1;
  return 0;
}

/* The unit grammar; 0 when text is a plain unit expression, else -1 and the
   offending position in *bad. */
static int plain_unit(const char *s, const char **bad)
{
  int depth = 0;
  for (const char *p = s; *p;) {
    unsigned char c = (unsigned char)*p;
    if (c == ' ' || c == '.' || c == '*' || c == '/') {
      p++;
      continue;
    }
    if (c == '(') {
      depth++;
      p++;
      continue;
    }
    if (c == ')') {
      if (--depth < 0) break;
      p++;
      continue;
    }
    if (isalpha(c) || c == '_' || c == '%') {
      const char *id = p;
      if (c == '%') /* percent, a name of its own, as udunits reads it ("%per" is "%" "per") */
        p++;
      else
        while (isalpha((unsigned char)*p) || *p == '_') p++;
      if (keyword(id, (size_t)(p - id))) {
        *bad = id;
        return -1;
      }
      if (*p == '^') p++; /* a power: m^2, m2, s-1, s^-2 */
      if (*p == '-' && isdigit((unsigned char)p[1])) p++;
      while (isdigit((unsigned char)*p)) p++;
      continue;
    }
    if (c == '1') { /* a numerator only: 1/m */
      const char *q = p + 1;
      while (*q == ' ') q++;
      if (*q == '/' && !isdigit((unsigned char)q[1])) {
        p = q;
        continue;
      }
    }
    *bad = p;
    return -1;
  }
  if (depth != 0) {
    *bad = s + strlen(s);
    return -1;
  }
  return 0;
}

/* The scale a of the converter, when it is x -> a x with a > 0. */
static int plain_scale(const cv_converter *cv, double *a)
{
  double c0 = cv_convert_double(cv, 0.0), c1 = cv_convert_double(cv, 1.0),
         c2 = cv_convert_double(cv, 2.0);
  if (!(c0 == 0 && c1 > 0 && isfinite(c1) && fabs(c2 - 2 * c1) <= 1e-12 * c1)) return -1;
  *a = c1;
  return 0;
}

/* text is what udunits reads, unit what the user wrote (for messages). */
static int convert_locked(const char *text, const char *unit, const char *si_unit, double *scale,
                          const char *what, rr_error *err)
{
  ut_unit *from = ut_parse(db, text, UT_ASCII), *to = ut_parse(db, si_unit, UT_ASCII);
  int st = RR_OK;
  const char *q = strcmp(si_unit, "1") ? si_unit : "a dimensionless quantity";
  if (!from)
    st = rr_seterr(err, RR_EUNIT, "%s: unknown unit '%s'", what, unit);
  else if (!to)
    st = rr_seterr(err, RR_EUNIT, "%s: internal unit '%s' not understood", what, si_unit);
  else if (!ut_are_convertible(from, to))
    st = rr_seterr(err, RR_EUNIT, "%s: '%s' is not a unit of %s", what, unit, q);
  else {
    cv_converter *cv = ut_get_converter(from, to);
    if (!cv || plain_scale(cv, scale))
      st = rr_seterr(err, RR_EUNIT,
                     "%s: '%s' is not a plain multiple of %s (no offset, logarithm or reciprocal)",
                     what, unit, q);
    cv_free(cv);
  }
  ut_free(from);
  ut_free(to);
  return st;
}

/* Engineers' run-together spellings, read as their dotted forms: Ns/m,
   kNs/m, kgm^2, MNm/rad; and speeds udunits does not name (mph, kph). */
static const char *const joined[][2] = {
    {"Ns", "N.s"},      {"kNs", "kN.s"},     {"MNs", "MN.s"},   {"Nm", "N.m"},
    {"kNm", "kN.m"},    {"MNm", "MN.m"},     {"kgm", "kg.m"},   {"Nms", "N.m.s"},
    {"kNms", "kN.m.s"}, {"mph", "(mile/h)"}, {"kph", "(km/h)"},
};

/* Angles. udunits takes the radian for the number 1, so "9.4 rad/s" would
   pass for 9.4 Hz (a 2 pi error) and "rpm" for 2 pi / 60 Hz. Where the
   user's unit names an angle, every angle (and Hz, one cycle a second) is
   written as a multiple of a base unit no quantity here uses (the candela),
   and the angle's power must then match the quantity's: rad/s for a
   frequency is divided by 2 pi, deg for a conicity is refused. */
#define RR_CD_2PI "(6.283185307179586 cd)"
static const char *const angles[][2] = {
    {"rad", "cd"},
    {"radian", "cd"},
    {"radians", "cd"},
    {"mrad", "(0.001 cd)"},
    {"urad", "(1e-6 cd)"},
    {"deg", "(0.017453292519943295 cd)"},
    {"degree", "(0.017453292519943295 cd)"},
    {"degrees", "(0.017453292519943295 cd)"},
    {"arcdeg", "(0.017453292519943295 cd)"},
    {"rev", RR_CD_2PI},
    {"revolution", RR_CD_2PI},
    {"revolutions", RR_CD_2PI},
    {"cycle", RR_CD_2PI},
    {"cycles", RR_CD_2PI},
    {"turn", RR_CD_2PI},
    {"turns", RR_CD_2PI},
    {"rpm", "(" RR_CD_2PI "/min)"},
    {"rps", "(" RR_CD_2PI "/s)"},
};
/* The SI units whose angle is implied: Hz is a cycle a second. */
static const char *const implied[][2] = {{"Hz", "(" RR_CD_2PI "/s)"}};

/* Factor units: a dimensional value in "%" would be scaled silently. */
static const char *const factors[] = {"%", "percent", "ppm", "ppb", "ppt", "permil"};

typedef const char *const word_table[2];

/* unit with every identifier found in tab (n rows) replaced by its text,
   into out (len bytes); *hits counts the replacements. */
static void replace_words(const char *unit, word_table *tab, size_t n, char *out, size_t len,
                          int *hits, int *powered)
{
  size_t k = 0;
  if (hits) *hits = 0;
  if (powered) *powered = 0;
  for (const char *p = unit; *p && k + 1 < len;) {
    if (!isalpha((unsigned char)*p) && *p != '%') {
      out[k++] = *p++;
      continue;
    }
    const char *id = p;
    while (isalpha((unsigned char)*p) || *p == '%') p++;
    size_t l = (size_t)(p - id);
    const char *rep = NULL;
    for (size_t i = 0; i < n && !rep; i++)
      if (strlen(tab[i][0]) == l && !strncmp(tab[i][0], id, l)) rep = tab[i][1];
    int pw = *p == '^' || isdigit((unsigned char)*p) || (*p == '-' && isdigit((unsigned char)p[1]));
    if (rep && rep[0] == '(' && pw) { /* "(km/h)2" is no unit udunits reads well: refused */
      if (powered) *powered = 1;
      rep = NULL;
    }
    if (rep && hits) (*hits)++;
    int w = rep ? snprintf(out + k, len - k, "%s", rep)
                : snprintf(out + k, len - k, "%.*s", (int)l, id);
    k += w > 0 ? (size_t)w : 0;
    if (k >= len) k = len - 1;
  }
  out[k] = 0;
}

static int has_factor_unit(const char *unit)
{
  for (const char *p = unit; *p;) {
    if (!isalpha((unsigned char)*p) && *p != '%') {
      p++;
      continue;
    }
    const char *id = p;
    while (isalpha((unsigned char)*p) || *p == '%') p++;
    for (size_t i = 0; i < sizeof factors / sizeof factors[0]; i++)
      if (strlen(factors[i]) == (size_t)(p - id) && !strncmp(factors[i], id, (size_t)(p - id)))
        return 1;
  }
  return 0;
}

/* The SI scale of unit text (trimmed). */
static int unit_scale(const char *unit, const char *si_unit, double *scale, const char *what,
                      rr_error *err)
{
  const char *bad;
  if (plain_unit(unit, &bad))
    return rr_seterr(
        err, RR_EUNIT,
        "%s: unit '%s' not understood at '%.12s' (one number, then a unit such as kN/mm)", what,
        unit, bad);
  if (strcmp(si_unit, "1") && has_factor_unit(unit))
    return rr_seterr(err, RR_EUNIT,
                     "%s: unit '%s' holds a factor unit (%%, ppm) that would scale a %s value "
                     "silently",
                     what, unit, si_unit);
  int st = db_get(err);
  if (st) return st;
  char spelled[2 * UNIT_TEXT_MAX], angular[8 * UNIT_TEXT_MAX], target[8 * UNIT_TEXT_MAX];
  int nang = 0;
  int pw1 = 0, pw2 = 0;
  replace_words(unit, joined, sizeof joined / sizeof joined[0], spelled, sizeof spelled, NULL,
                &pw1);
  replace_words(spelled, angles, sizeof angles / sizeof angles[0], angular, sizeof angular, &nang,
                &pw2);
  if (pw1 || pw2)
    return rr_seterr(err, RR_EUNIT,
                     "%s: unit '%s': a power of an angle or of mph / kph is not "
                     "accepted",
                     what, unit);
  if (nang) { /* an angle named: both sides with angles as candelas */
    char t1[8 * UNIT_TEXT_MAX];
    replace_words(si_unit, implied, sizeof implied / sizeof implied[0], t1, sizeof t1, NULL, NULL);
    replace_words(t1, angles, sizeof angles / sizeof angles[0], target, sizeof target, NULL, NULL);
  }
  pthread_mutex_lock(&db_lock);
  st = nang ? convert_locked(angular, unit, target, scale, what, err)
            : convert_locked(spelled, unit, si_unit, scale, what, err);
  pthread_mutex_unlock(&db_lock);
  if (st == RR_EUNIT && nang)
    rr_seterr(err, RR_EUNIT,
              "%s: '%s' is not a unit of %s (angles count here: 1 Hz is 2 pi rad/s, and a "
              "quantity without an angle takes none)",
              what, unit, strcmp(si_unit, "1") ? si_unit : "a dimensionless quantity");
  return st;
}

static const char *skip_space(const char *s)
{
  while (*s && isspace((unsigned char)*s)) s++;
  return s;
}

/* The number at the start of text: finite (or +inf where allowed), not out
   of double's range. */
static int leading_number(const char *text, int allow_inf, double *v, const char **end,
                          const char *what, rr_error *err)
{
  char *e;
  errno = 0;
  *v = strtod(text, &e);
  *end = e;
  if (e == text) return rr_seterr(err, RR_EINVAL, "%s: '%s' is not a number", what, text);
  if (isnan(*v)) return rr_seterr(err, RR_EINVAL, "%s: NaN is not allowed", what);
  int literal_inf = isinf(*v) && errno != ERANGE;
  if (isinf(*v) && !(allow_inf && literal_inf && *v > 0))
    return rr_seterr(err, RR_EINVAL, "%s: '%s' must be finite", what, text);
  if (errno == ERANGE) return rr_seterr(err, RR_EINVAL, "%s: '%s' is out of range", what, text);
  return RR_OK;
}

int rr_units_parse(rr_units *u, const char *text, const char *si_unit, int allow_inf, double *out,
                   const char *what, rr_error *err)
{
  (void)u;
  const char *end;
  double v, scale = 0;
  if (!text || !*skip_space(text)) return rr_seterr(err, RR_EINVAL, "%s: empty value", what);
  int st = leading_number(skip_space(text), allow_inf, &v, &end, what, err);
  if (st) return st;
  if (end > text && !isspace((unsigned char)*end) && *end && !isalpha((unsigned char)*end) &&
      *end != '%')
    return rr_seterr(err, RR_EINVAL, "%s: '%s' is not a number followed by a unit", what, text);
  end = skip_space(end);
  if (!*end) {
    *out = v;
    return RR_OK;
  } /* a bare number: SI */
  char unit[UNIT_TEXT_MAX];
  size_t len = strlen(end);
  while (len && isspace((unsigned char)end[len - 1])) len--;
  if (len >= sizeof unit)
    return rr_seterr(err, RR_EUNIT, "%s: unit '%.40s...' too long", what, end);
  memcpy(unit, end, len);
  unit[len] = 0;
  if ((st = unit_scale(unit, si_unit, &scale, what, err))) return st;
  double r = v * scale;
  if (isinf(v)) {
    *out = v;
    return RR_OK;
  }
  if (!isfinite(r) || (r == 0 && v != 0))
    return rr_seterr(err, RR_EINVAL, "%s: '%s' is out of range in SI", what, text);
  *out = r;
  return RR_OK;
}
