/* Spectrum files and measured PSDs (CSV): parse, then evaluate what was
 * accepted over its band and a little beyond. The first input byte picks
 * the reader: even, the key = value file; odd, the CSV. */
#include "fuzz_common.h"
#include <math.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  rr_spectrum sp;
  rr_error e;
  if (size < 1) return 0;
  const char *path = fuzz_file(data[0] % 2 ? "s.csv" : "s.txt", data + 1, size - 1);
  if (rr_spectrum_load(path, &sp, &e)) return 0;
  for (int i = 0; i <= 20; i++) {
    double n = sp.valid_lo * pow(sp.valid_hi / sp.valid_lo, i / 20.0), s = rr_spectrum_eval(&sp, n);
    if (!(s >= 0) || isinf(s)) abort();
  }
  rr_spectrum_close(&sp);
  return 0;
}
