/* Vehicle files: parse, then build and solve what was accepted. */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  rr_vehicle v;
  rr_error e;
  if (!rr_vehicle_load(fuzz_file("v.ini", data, size), &v, &e)) fuzz_index(&v);
  else if (!memchr(e.msg, 0, sizeof e.msg) || strchr(e.msg, '\n')) abort();   /* one terminated line */
  return 0;
}
