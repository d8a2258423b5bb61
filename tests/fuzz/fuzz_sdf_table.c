/* SDF tables: parse, then run a paper-mode SDF vehicle on the curve. */
#include "fuzz_common.h"
#include <math.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  rr_sdf_curve c;
  rr_error e;
  memset(&c, 0, sizeof c);
  if (rr_sdf_table_load(fuzz_file("t.csv", data, size), &c, &e)) return 0;
  for (double f = 0.01; f < 200; f *= 3)
    if (!(rr_sdf_storage(&c, f) > 0) || !isfinite(rr_sdf_storage(&c, f))) abort();
  rr_vehicle v;
  rr_vehicle_default(&v);
  v.sdf = c;
  v.sdf_mode = RR_SDF_PAPER;
  if (!rr_vehicle_check(&v, &e)) fuzz_index(&v);
  return 0;
}
