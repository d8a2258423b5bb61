/* railride: optimisation problem files (INI), read and checked.
 *
 *   [problem]     vehicle (built-in name, or a file relative to this one),
 *                 population (even, >= 4), generations, seed, threads, output
 *   [variables]   section.key = LO .. HI      (vehicle-file keys, with units)
 *   [objectives]  objective = NAME [minimize|maximize]   (design.h's names)
 *                 constraint = NAME <= VALUE | NAME >= VALUE  (a design violating
 *                 it loses to every feasible one: Deb's constrained domination)
 *
 * Every message names file, line and key. */
#ifndef RAILRIDE_PROBLEM_H
#define RAILRIDE_PROBLEM_H

#include "railride/common.h"

#include "railride/design.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RR_PROBLEM_PATH_MAX 4096
#define RR_PROBLEM_POPULATION_MAX 10000000
#define RR_PROBLEM_GENERATIONS_MAX 1000000

typedef struct rr_problem {
  char vehicle[RR_PROBLEM_PATH_MAX];    /* "" for the default vehicle */
  int population, generations, threads; /* 100, 100, 0 (all cores) */
  unsigned long long seed;              /* 1 */
  char output[RR_PROBLEM_PATH_MAX];     /* output prefix ("pareto") */
  int nvar, nobj;
  char keys[RR_DESIGN_MAX_VARS][64];
  double lo[RR_DESIGN_MAX_VARS], hi[RR_DESIGN_MAX_VARS]; /* SI, inside the keys' physical ranges */
  char objs[RR_DESIGN_MAX_OBJS][128];
  int maximize[RR_DESIGN_MAX_OBJS];
  int ncon; /* constraints: cons[k] <= bound (sense +1) or >= (-1) */
  char cons[RR_DESIGN_MAX_OBJS][128];
  int con_sense[RR_DESIGN_MAX_OBJS];
  double con_bound[RR_DESIGN_MAX_OBJS];
} rr_problem;

/* Reads and checks a problem file (docs/cli.md, optimise): keys once, each
 * variable once and inside its key's range, objectives and constraints
 * checked; messages name file, line and key. */
RR_API int rr_problem_load(const char *path, rr_problem *p, rr_error *err);

/* Checks an objective's text (names, arguments, modifiers) without a vehicle. */
RR_API int rr_objective_check(const char *text, rr_error *err);
/* The objective `text` at another operating point: speed_kmh and conicity
 * replace its own where finite (NaN keeps the objective's, which it may then
 * not leave out); its point x and modifiers stay. Only the objectives at an
 * operating point (index, sperling, sperling_gb, wd_rms, rms). The checked,
 * canonical text goes to out (n bytes), e.g. "index;fmax=20" at (300, 0.2):
 * "index@300,0.2;fmax=20". */
RR_API int rr_objective_at(const char *text, double speed_kmh, double conicity, char *out, size_t n,
                           rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
