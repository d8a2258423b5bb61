/* Values with units ("50 kN/mm") converted to SI through udunits2. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <udunits2.h>
#include "railride/vehicle.h"
#include "internal.h"

struct rr_units {
  ut_system *sys;
};

int rr_units_new(rr_units **out, rr_error *err)
{
  *out = NULL;
  /* udunits prints parse errors to stderr by default; a library must not. */
  ut_set_error_message_handler(ut_ignore);
  rr_units *u = calloc(1, sizeof *u);
  if (!u) return rr_seterr(err, RR_ENOMEM, "out of memory");
  u->sys = ut_read_xml(NULL);
  if (!u->sys) {
    free(u);
    return rr_seterr(err, RR_EIO, "cannot load the udunits2 unit database (package libudunits2-data)");
  }
  *out = u;
  return RR_OK;
}

void rr_units_free(rr_units *u)
{
  if (!u) return;
  ut_free_system(u->sys);
  free(u);
}

static int is_blank(const char *s)
{
  while (*s && isspace((unsigned char)*s)) s++;
  return *s == 0;
}

int rr_units_parse(rr_units *u, const char *text, const char *si_unit, int allow_inf,
                   double *out, const char *what, rr_error *err)
{
  char *end;
  if (!text || is_blank(text)) return rr_seterr(err, RR_EINVAL, "%s: empty value", what);
  double v = strtod(text, &end);
  if (end == text) return rr_seterr(err, RR_EINVAL, "%s: '%s' is not a number", what, text);
  if (isnan(v)) return rr_seterr(err, RR_EINVAL, "%s: NaN is not allowed", what);
  if (isinf(v) && !(allow_inf && v > 0))
    return rr_seterr(err, RR_EINVAL, "%s: '%s' must be finite", what, text);
  while (*end && isspace((unsigned char)*end)) end++;
  if (*end == 0) { *out = v; return RR_OK; }   /* bare number: SI */
  char ubuf[128];
  size_t len = strlen(end);
  while (len && isspace((unsigned char)end[len - 1])) len--;
  if (len >= sizeof ubuf) return rr_seterr(err, RR_EUNIT, "%s: unit '%s' too long", what, end);
  memcpy(ubuf, end, len);
  ubuf[len] = 0;
  rr_units *own = NULL;
  if (!u) {
    int st = rr_units_new(&own, err);
    if (st) return st;
    u = own;
  }
  int st = RR_OK;
  ut_unit *from = ut_parse(u->sys, ubuf, UT_ASCII);
  ut_unit *to = ut_parse(u->sys, si_unit, UT_ASCII);
  if (!from) {
    st = rr_seterr(err, RR_EUNIT, "%s: unknown unit '%s'", what, ubuf);
  } else if (!to) {
    st = rr_seterr(err, RR_EUNIT, "%s: internal unit '%s' not understood", what, si_unit);
  } else if (!ut_are_convertible(from, to)) {
    st = rr_seterr(err, RR_EUNIT, "%s: unit '%s' is not a unit of %s", what, ubuf,
                   strcmp(si_unit, "1") ? si_unit : "a dimensionless quantity");
  } else {
    cv_converter *cv = ut_get_converter(from, to);
    if (!cv) st = rr_seterr(err, RR_EUNIT, "%s: cannot convert '%s' to %s", what, ubuf, si_unit);
    else {
      double r = cv_convert_double(cv, v);
      cv_free(cv);
      if (!isfinite(r) && !(allow_inf && isinf(v)))
        st = rr_seterr(err, RR_EINVAL, "%s: value not finite after conversion", what);
      else *out = r;
    }
  }
  ut_free(from);
  ut_free(to);
  rr_units_free(own);
  return st;
}
