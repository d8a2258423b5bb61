/* Internal helpers shared by the library's sources. */
#ifndef RR_INTERNAL_H
#define RR_INTERNAL_H

#include <stddef.h>
#include "railride/error.h"
#include "railride/model.h"

#if defined(__GNUC__)
#define RR_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define RR_PRINTF(a, b)
#endif

/* Fills err (when non-NULL) and returns code. */
int rr_seterr(rr_error *err, int code, const char *fmt, ...) RR_PRINTF(3, 4);

#define RR_G 9.81

#endif
