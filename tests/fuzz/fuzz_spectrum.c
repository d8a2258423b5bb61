/* Spectrum files: parse, then evaluate what was accepted over its band. */
#include "fuzz_common.h"
#include <math.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  rr_spectrum sp;
  rr_error e;
  if (rr_spectrum_load(fuzz_file("s.txt", data, size), &sp, &e)) return 0;
  for (int i = 0; i <= 20; i++) {
    double n = sp.valid_lo * pow(sp.valid_hi / sp.valid_lo, i / 20.0), s = rr_spectrum_eval(&sp, n);
    if (!(s >= 0) || isinf(s)) abort();
  }
  rr_spectrum_close(&sp);
  return 0;
}
