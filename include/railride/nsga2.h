/* railride: NSGA-II (Deb, Pratap, Agarwal, Meyarivan, IEEE TEC 6(2), 2002):
 * fast non-dominated sorting, crowding distance, binary tournament, SBX
 * crossover, polynomial mutation. All objectives are minimised. Seeded and
 * reproducible; the evaluation callback gets whole batches (parallelise there). */
#ifndef RAILRIDE_NSGA2_H
#define RAILRIDE_NSGA2_H

#include "railride/common.h"

#include <stdint.h>
#include "railride/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills f (n x (m + ncon)) for x (n x d): the m objectives, then ncon
   constraint violations (>= 0, 0 when the constraint holds). NaN objectives
   count as worst, a NaN violation as infinite. Returns 0; anything else
   ends the run with RR_EINVAL (the callback's own message is its to give),
   except RR_ESTOPPED: a stop asked for during a generation, which is then
   dropped, the last complete generation being the result (generations_done
   says which; during the initial population the run returns RR_ESTOPPED). */
typedef int (*rr_nsga2_eval_fn)(void *user, int n, const double *x, double *f);
/* Called after every generation; a nonzero return stops the run there, the
   population of that generation being the result (generations_done says
   how far it got). */
typedef int (*rr_nsga2_progress_fn)(void *user, int generation, long evaluations, double seconds,
                                    int front_size, double hypervolume);

/* What determines a run beyond the numbers rr_nsga2_run sees (the vehicle,
 * the objectives and their sense, the constraints, the library version...):
 * a hash per part, with the part's name for messages. A checkpoint carries
 * them; a resume whose parts differ is refused, naming what changed. */
#define RR_NSGA2_FP_MAX 8
typedef struct rr_nsga2_fingerprint {
  int n;
  uint64_t part[RR_NSGA2_FP_MAX];
  const char *name[RR_NSGA2_FP_MAX];
} rr_nsga2_fingerprint;
/* FNV-1a over n bytes, continuing from h (start with RR_FNV_OFFSET). */
#define RR_FNV_OFFSET 14695981039346656037ULL
RR_API uint64_t rr_hash_bytes(uint64_t h, const void *p, size_t n);

typedef struct rr_nsga2_opts {
  int population;     /* even (100) */
  int generations;    /* (250) */
  uint64_t seed;      /* (1) */
  double p_crossover; /* (0.9) */
  double eta_c;       /* SBX distribution index (15) */
  double p_mutation;  /* per variable; <= 0: 1/d */
  double eta_m;       /* polynomial mutation index (20) */
  int hv_every;       /* hypervolume in progress reports every k generations (10; 0: never) */
  rr_nsga2_progress_fn progress;
  void *user;            /* for progress */
  int *generations_done; /* if not NULL: the generations completed (a stop can end the run early) */
  int ncon;              /* constraint violations after the objectives (0); Deb's constrained
                            domination: feasible designs beat infeasible ones, infeasible ones
                            rank by their total violation */
  double *cv_out;        /* if not NULL: the final population's total violations (pop) */
  const char *checkpoint; /* if not NULL: the run's state written here after every generation */
  const char *resume;     /* if not NULL: a checkpoint to go on from (same problem, population and
                             seed); the result is the one an uninterrupted run gives. Every
                             field read is checked (counts, ranges, finite values, designs
                             within their bounds): a damaged or crafted file is an error */
  rr_nsga2_fingerprint fingerprint; /* the caller's parts of the run (n = 0: none) */
  int evaluate_copies; /* 0 (default): an offspring equal bit for bit to one of its two parents
                          (no crossover or mutation changed it) takes that parent's objectives
                          and violations without an eval call, its evaluation being a repeat;
                          1: every offspring goes to eval (a noisy or stateful eval) */
  long *evaluated;     /* if not NULL: the designs this call passed to eval */
} rr_nsga2_opts;
/* The defaults given in the fields' comments. */
RR_API rr_nsga2_opts rr_nsga2_opts_default(void);

/* Runs the optimiser; x_out (pop x d), f_out (pop x m), rank_out (pop; 0 =
 * non-dominated) receive the final population. */
RR_API int rr_nsga2_run(int d, int m, const double *lo, const double *hi, rr_nsga2_eval_fn eval,
                        void *eval_user, const rr_nsga2_opts *o, double *x_out, double *f_out,
                        int *rank_out, rr_error *err);

/* Non-dominated ranks of n points (m objectives, minimised); 0 = first front.
 * *nfronts (may be NULL): the number of fronts. */
RR_API int rr_nondominated_ranks(int n, int m, const double *f, int *rank, int *nfronts,
                                 rr_error *err);
/* Exact hypervolume dominated by the points (m = 2 or 3, else RR_EUNSUP) up
 * to ref into *hv; points not strictly better than ref in every objective do
 * not count. */
RR_API int rr_hypervolume(int n, int m, const double *f, const double *ref, double *hv,
                          rr_error *err);

/* k-means clustering of a Pareto set (the paper's clusters A-D): n points
 * of m coordinates (x, n x m, row-major) into k groups, Lloyd's iterations
 * to a fixed point from a deterministic farthest-point start (the first
 * centre the point with the smallest first coordinate, each next the point
 * farthest from the centres so far; ties to the lower index). With scale,
 * each coordinate is mapped to [0, 1] over the points first, so that
 * objectives of different size weigh alike. label (n) receives 0 .. k-1,
 * numbered by ascending first coordinate of the centre; centre (k x m, may
 * be NULL) the centres in the points' own units; *iterations (may be NULL)
 * the Lloyd passes. Needs 1 <= k <= n and finite coordinates. */
RR_API int rr_kmeans(int n, int m, const double *x, int k, int scale, int *label, double *centre,
                     int *iterations, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
