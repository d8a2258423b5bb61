/* railride: matrix exponential by scaling and squaring with the [13/13] Pade
 * approximant (Higham, SIAM J. Matrix Anal. Appl. 26(4), 2005). */
#ifndef RAILRIDE_EXPM_H
#define RAILRIDE_EXPM_H

#include "railride/common.h"

#include "railride/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Workspace size in doubles for an n x n exponential. */
RR_API size_t rr_expm_work_size(int n);
/* E = exp(A), both n x n row-major (may not alias). work: rr_expm_work_size(n)
 * doubles, or NULL to allocate. */
RR_API int rr_expm(int n, const double *A, double *E, double *work, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
