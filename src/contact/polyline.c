/* Wheel and rail profiles as polylines: checked, copied, freed (the files
 * are read in profile_file.c; docs/contact.md, profile files). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "railride/contact.h"
#include "contact/contact_impl.h"
#include "util/internal.h"

void rr_polyline_free(rr_polyline *p)
{
  if (!p) return;
  free(p->x);
  free(p->z);
  p->x = p->z = NULL;
  p->n = 0;
}

int rr_polyline_check_points(const char *what, const rr_polyline *p, rr_error *err)
{
  if (p->n < 3) return rr_seterr(err, RR_EPARSE, "%s: a profile needs at least 3 points", what);
  for (int i = 0; i < p->n; i++)
    if (!isfinite(p->x[i]) || !isfinite(p->z[i]))
      return rr_seterr(err, RR_EINVAL, "%s: point %d is not finite", what, i + 1);
  for (int i = 1; i < p->n; i++)
    if (!(p->x[i] > p->x[i - 1]))
      return rr_seterr(err, RR_EINVAL, "%s: point %d: the lateral coordinate must rise strictly",
                       what, i + 1);
  return RR_OK;
}

int rr_polyline_from(const double *x, const double *z, int n, rr_polyline *p, rr_error *err)
{
  *p = (rr_polyline){0};
  if (n < 0 || n > RR_POLY_MAX_POINTS) return rr_seterr(err, RR_EINVAL, "profile: %d points", n);
  p->x = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  p->z = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  if (!p->x || !p->z) {
    rr_polyline_free(p);
    return rr_seterr(err, RR_ENOMEM, "out of memory");
  }
  memcpy(p->x, x, sizeof(double) * (size_t)n);
  memcpy(p->z, z, sizeof(double) * (size_t)n);
  p->n = n;
  int st = rr_polyline_check_points("profile", p, err);
  if (st) rr_polyline_free(p);
  return st;
}
