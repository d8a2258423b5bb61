/* Internal layout of the modal workspace and the helpers the modal sources
 * share (modal.c: modes and index; sdf_modes.c: paper-mode SDF tracking). */
#ifndef RR_MODAL_IMPL_H
#define RR_MODAL_IMPL_H

#include <float.h>
#include <math.h>
#include "railride/modal.h"
#include "model/model_impl.h"

#define RR_OSC_TOL 1e-6

struct rr_modal_ws {
  int N, n;
  double *A, *At, *wr, *wi, *vr, *work; /* dgeev and the single-point QR */
  int lwork;
  double complex *D, *Dp, *x; /* 17 x 17 dynamic stiffness (and reordered), vectors */
  int *piv;
  int *cand; /* index candidates by decreasing zeta */
  double *candz;
  double *Ab, *wrb, *wib, *qrw; /* batched index: state matrices, eigenvalues, QR lanes */
  int *candb;                   /* batched index: each point's candidates (N a point) */
  double *candzb;
  double complex *phib;   /* batched index: the shapes in lanes (n a lane) */
  struct rr_dsl *dsl;     /* batched index: the shape tests in lanes */
  rr_modal_result trk[4]; /* paper mode: start, current, result; critical-speed modes */
  double complex *branch; /* paper mode: shapes being followed; sort scratch */
  double complex *tv;     /* fast tracking: vectors (12 n) */
  struct rr_dsolver *ds;  /* fast tracking: sparse D(s) solves */
  int *dsi;
  double complex *dsz;
  char *block; /* every array above, one allocation (block.h) */
};

/* Room for the largest state of any SDF mode the model may switch to: the
   modes a result holds at most. */
int rr_modal_state_cap(const rr_model *m);

/* Eigenvalues this small are zero to working precision: a rigid-body mode
   (free lateral drift at zero conicity) is a double, defective zero, which
   rounding of size eps |A| splits into a pair +-sqrt(eps |A|) that may look
   oscillatory. Exactly they are zero, hence real. */
static inline int rr_modal_is_osc(double re, double im, double anorm)
{
  double mag = hypot(re, im);
  return im > RR_OSC_TOL * mag && mag > 100 * sqrt(DBL_EPSILON * anorm);
}

/* Eigen-solve of the full state matrix into ws (wr, wi, and vr with vectors). */
int rr_modal_eig(const rr_model *m, double sdf_k, int vectors, rr_modal_ws *ws, int *N,
                 rr_error *err);
/* Modes of the last rr_modal_eig with vectors, unsorted, shapes normalised. */
void rr_modal_collect(const rr_model *m, int N, const rr_modal_ws *ws, rr_modal_result *res);
/* Eigenvalue, frequency, zeta, oscillation flag of a mode. */
void rr_mode_fill(rr_mode *md, double re, double im, double anorm);
/* The mode is hunting-related by the options' frequency and shape rules. */
int rr_modal_hunting_related(const rr_mode *md, const rr_modal_opts *o);
/* Energy and roll shares and the name of a mode from its q shape. */
void rr_mode_shares(const rr_model *m, const double complex *phi, rr_mode *md);
/* The shares alone (md's name untouched): what the hunting rule reads. */
void rr_mode_energy(const rr_model *m, const double complex *phi, rr_mode *md);
/* Unit norm, largest component real and positive. */
void rr_shape_normalise(double complex *phi, int n);
/* Sorts, classifies against o with the band edge at m's operating point,
   and sets the index and zeta_max. */
void rr_modal_finish(const rr_model *m, rr_modal_result *res, const rr_modal_opts *o,
                     double complex *scratch);

/* Paper-mode SDF: the self-consistent modes of m into res (o->tracking). */
int rr_sdf_modes(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws, rr_modal_result *res,
                 rr_error *err);
/* The same from eigenvalues only (no dgeev vectors): oscillatory modes only,
   for the stability index. */
int rr_sdf_modes_fast_osc(const rr_model *m, const rr_modal_opts *o, rr_modal_ws *ws,
                          rr_modal_result *res, rr_error *err);

#endif
