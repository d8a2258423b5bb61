/* Faster SUNDIALS serial-vector kernels for long vectors (nvector_fast.c). */
#ifndef RR_NVECTOR_FAST_H
#define RR_NVECTOR_FAST_H
#include <sundials/sundials_nvector.h>

/* Replaces v's linear combination and weighted norms; vectors cloned from v
   (the integrator's stages) inherit them. */
void rr_nvector_fast(N_Vector v);
#endif
