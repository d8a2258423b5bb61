/* Shared by the fuzz harnesses: the input written to a private temporary
 * file (the readers take paths), and one stability index of whatever
 * vehicle an input produced, so that accepted-but-absurd values are run
 * through the model, not only the parser. */
#ifndef RR_FUZZ_COMMON_H
#define RR_FUZZ_COMMON_H
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "railride/railride.h"

static char fuzz_dir[64];

static inline const char *fuzz_file(const char *name, const uint8_t *data, size_t size)
{
  static char path[128];
  if (!fuzz_dir[0]) {
    snprintf(fuzz_dir, sizeof fuzz_dir, "/tmp/rr_fuzz_XXXXXX");
    if (!mkdtemp(fuzz_dir)) abort();
    setenv("OPENBLAS_NUM_THREADS", "1", 1);
  }
  snprintf(path, sizeof path, "%s/%s", fuzz_dir, name);
  FILE *fp = fopen(path, "wb");
  if (!fp) abort();
  fwrite(data, 1, size, fp);
  fclose(fp);
  return path;
}

/* The bug the harnesses hunt: status 0 with an index that is not a damping
   ratio, or NaN other than the documented "undefined" (source none: no
   hunting-related mode and all stable), or a sign that is not the verdict. */
static inline void fuzz_index(const rr_vehicle *v)
{
  rr_model *m;
  rr_modal_ws *ws;
  rr_error e;
  rr_stability s;
  if (rr_model_from_vehicle(v, &m, &e)) return;
  if (!rr_modal_ws_new(m, &ws, &e)) {
    if (!rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e) &&
        !rr_modal_stability(m, NULL, ws, &s, &e)) {
      int undefined = s.source == RR_INDEX_NONE;
      if (undefined
              ? s.index == s.index || !rr_modal_stable(s.zeta_max)
              : !(s.index >= -1 && s.index <= 1) || rr_modal_stable(s.zeta_max) != (s.index < 0))
        abort();
    }
    rr_modal_ws_free(ws);
  }
  rr_model_free(m);
}
#endif
