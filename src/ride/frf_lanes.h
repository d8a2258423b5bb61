/* What the sparse FRF's interpreter (frf_sparse.c) and its generated
 * codelets (frf_codelets.c) share: the lane vectors, the Maxwell elements'
 * stiffness in every lane, and the codelet table. */
#ifndef RR_FRF_LANES_H
#define RR_FRF_LANES_H

#include <math.h>
#include "ride/frf_sparse.h"
/* The complex multiply-adds d - l u of the factorisation and the solves,
   each part as two FMAs (VFMA: the same bits on every target); the
   interpreter and the codelets spell them with these macros alone. */
#define CMAC_RE(dr, lr, li, ur, ui) VFMA(li, ui, VFMA(-(lr), ur, dr))
#define CMAC_IM(di, lr, li, ur, ui) VFMA(-(li), ur, VFMA(-(lr), ui, di))
/* a b for complex a, b: its real and imaginary parts */
#define CMUL_RE(ar, ai, br, bi) VFMA(ar, br, -((ai) * (bi)))
#define CMUL_IM(ar, ai, br, bi) VFMA(ar, bi, (ai) * (br))
#include "util/internal.h"

#define L RR_FRF_LANES
#include "util/lane_vector.h" /* after L */

/* Element e's k_e(jw) = k c jw / (k + c jw), times its multiplicity. */
RR_INLINE void maxwell(const rr_frf_sparse *s, int e, const vd *w, vd *ker, vd *kei)
{
  double c = s->ds->mx[e].c, mu = s->ds->mx[e].mult;
  if (isinf(s->kr[e * L])) { /* a rigid series spring: the dashpot alone */
    *ker = (vd){0};
    *kei = mu * c * *w;
    return;
  }
  vd k = VLOAD(s->kr + e * L), ki = VLOAD(s->ki + e * L);
  vd nr = -(ki * c) * *w, ni = (k * c) * *w; /* (k + j ki) c jw */
  vd dr = k, di = ki + c * *w, den = dr * dr + di * di;
  *ker = mu * (nr * dr + ni * di) / den;
  *kei = mu * (ni * dr - nr * di) / den;
}

/* The lanes set in a mask vector, as bits. */
RR_INLINE unsigned rr_frf_lane_bits(const vl *bad)
{
  unsigned bits = 0;
  for (int l = 0; l < L; l++) bits |= (*bad)[l] ? 1u << l : 0;
  return bits;
}

/* A codelet: form, factor and solve (the unknowns k >= kmin stored in xr,
   xi) for the structure whose signature (rr_frf_sparse_signature) is sig,
   run[0] for every input, run[1] for their lagged sum (s->sum); returns the
   lanes whose multipliers outgrew the threshold. */
typedef struct rr_frf_codelet {
  const int *sig;
  int nsig, kmin;
  unsigned (*run[2])(rr_frf_sparse *s, const double *w);
} rr_frf_codelet;

extern const rr_frf_codelet rr_frf_codelets[];
extern const int rr_frf_ncodelets;

#endif
