/* railride: the layout of the public structs, for bindings that mirror them
 * (the Python package checks its copies at import). */
#ifndef RAILRIDE_LAYOUT_H
#define RAILRIDE_LAYOUT_H

#include "railride/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The offset and size of type's field ("rr_mode", "zeta"), or with field
 * NULL the type's size (offset 0). RR_OK, or RR_EINVAL for a type or field
 * not in the table (the structs Python mirrors). */
RR_API int rr_layout(const char *type, const char *field, size_t *offset, size_t *size);

#ifdef __cplusplus
}
#endif
#endif
