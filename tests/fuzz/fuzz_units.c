/* Values with units, against every SI unit the vehicle keys use. */
#include "fuzz_common.h"
#include <math.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static const char *units[] = {"kg", "kg.m2", "m",    "N/m", "N.s/m", "N.m/rad",
                                "Hz", "N",     "km/h", "1",   "m2"};
  char text[256];
  if (size >= sizeof text) return 0;
  memcpy(text, data, size);
  text[size] = 0;
  for (size_t i = 0; i < sizeof units / sizeof units[0]; i++) {
    double x;
    rr_error e;
    if (!rr_units_parse(NULL, text, units[i], 0, &x, "v", &e) && !isfinite(x)) abort();
    if (!rr_units_parse(NULL, text, units[i], 1, &x, "v", &e) && isnan(x)) abort();
  }
  return 0;
}
