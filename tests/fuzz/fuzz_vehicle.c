/* Vehicle files: parse, then build and solve what was accepted; with a tread
 * profile, the nonlinear right-hand side at a state in flange contact too. */
#include "fuzz_common.h"
#include <math.h>

static void fuzz_nonlinear(const rr_vehicle *v)
{
  rr_nonlinear *nl;
  rr_error e;
  if (v->profile.kind == RR_PROFILE_NONE ||
      rr_nonlinear_from_vehicle(v, NULL, NULL, 300 / RR_KMH, &nl, &e))
    return;
  int N = rr_nonlinear_size(nl);
  double *z = calloc((size_t)N, sizeof(double)), *dz = malloc(sizeof(double) * (size_t)N);
  for (int w = 0; w < rr_nonlinear_ninputs(nl); w++)
    z[rr_nonlinear_index_y(nl, w)] = 0.01 * (w + 1);
  rr_nonlinear_rhs(nl, z, NULL, dz);
  for (int i = 0; i < N; i++)
    if (!isfinite(dz[i])) abort();
  free(z);
  free(dz);
  rr_nonlinear_free(nl);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  rr_vehicle v;
  rr_error e;
  if (!rr_vehicle_load(fuzz_file("v.ini", data, size), &v, &e)) {
    fuzz_index(&v);
    fuzz_nonlinear(&v);
  } else if (!memchr(e.msg, 0, sizeof e.msg) || strchr(e.msg, '\n'))
    abort(); /* one terminated line */
  return 0;
}
