/* Vehicle files, INI or (an input starting with '{') JSON: parse, then
 * build and solve what was accepted (the lateral index, the vertical model's
 * modes and one vertical ride); with a tread profile, the nonlinear
 * right-hand side at a state in flange contact too. */
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

/* what the vertical model makes of an accepted vehicle: an error (the
   layout's b < L < L_cb/2) or finite modes and indices */
static void fuzz_vertical(const rr_vehicle *v)
{
  static rr_vertical_plan *plan;
  static rr_spectrum sp;
  static int ready;
  rr_error e;
  if (!ready) {
    rr_vertical_opts o = rr_vertical_opts_default();
    o.nfreq = 40;
    if (rr_vertical_plan_new(&o, &plan, &e) || rr_spectrum_open("tbt3352-vertical", &sp, &e))
      abort();
    ready = 1;
  }
  rr_vertical_model m;
  rr_vertical_modes md;
  rr_vertical_point pt[3];
  if (rr_vertical_model_build(v, &m, &e)) return;
  if (!rr_vertical_modes_compute(&m, &md, &e))
    for (int i = 0; i < md.nmodes; i++)
      if (!isfinite(md.mode[i].freq_hz)) abort();
  if (!rr_vertical_ride_execute(plan, &m, 300 / RR_KMH, &sp, pt, &e))
    for (int i = 0; i < 3; i++)
      if (!isfinite(pt[i].wb_5s.p95) || !isfinite(pt[i].sperling)) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  rr_vehicle v;
  rr_error e;
  const char *name = size && data[0] == '{' ? "v.json" : "v.ini";
  if (!rr_vehicle_load(fuzz_file(name, data, size), &v, &e)) {
    fuzz_index(&v);
    fuzz_vertical(&v);
    fuzz_nonlinear(&v);
  } else if (!memchr(e.msg, 0, sizeof e.msg) || strchr(e.msg, '\n'))
    abort(); /* one terminated line */
  return 0;
}
