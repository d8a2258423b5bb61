/* The largest |x_i| of an array: the scale a state matrix's eigenvalues are
 * classified against (docs/model.md 5). */
#ifndef RR_MAX_ABS_H
#define RR_MAX_ABS_H

#include <stddef.h>

/* max_i |x_i| over n entries (0 when n is 0); x holds no NaN. Exact, so every
   instruction-set copy gives the same value. */
double rr_max_abs(size_t n, const double *x);

#endif
