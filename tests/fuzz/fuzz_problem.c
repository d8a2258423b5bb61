/* Problem files: parse, then open the design and evaluate its midpoint. */
#include "fuzz_common.h"
#include <math.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  rr_problem p;
  rr_vehicle v;
  rr_error e;
  if (rr_problem_load(fuzz_file("p.ini", data, size), &p, &e) ||
      rr_vehicle_open(p.vehicle[0] ? p.vehicle : NULL, &v, &e))
    return 0;
  const char *keys[RR_DESIGN_MAX_VARS], *objs[RR_DESIGN_MAX_OBJS];
  double x[RR_DESIGN_MAX_VARS], f[RR_DESIGN_MAX_OBJS];
  for (int i = 0; i < p.nvar; i++) {
    keys[i] = p.keys[i];
    x[i] = 0.5 * (p.lo[i] + p.hi[i]);
  }
  for (int i = 0; i < p.nobj; i++) objs[i] = p.objs[i];
  rr_design *d;
  if (rr_design_new(&v, p.nvar, keys, p.nobj, objs, &d, &e)) return 0;
  if (!rr_design_evaluate(d, x, f, &e))
    for (int i = 0; i < p.nobj; i++)
      if (!isfinite(f[i])) abort();
  rr_design_free(d);
  return 0;
}
