/* Work split over MPI ranks when railride runs under mpirun or srun (built
 * with RAILRIDE_MPI); one process otherwise, with the same code path.
 *
 * Every rank runs the same command. A loop over independent items (designs of
 * a generation, grid points, conicities) goes through cli_par_for: ranks take
 * chunks of items from a shared counter on rank 0 (dynamic: a rank with cheap
 * items takes more), compute them, and every rank receives every result, so
 * that what follows (NSGA-II's selection, the CSV) is the serial computation on
 * the same numbers. Only rank 0 writes standard output, files and progress; the
 * other ranks' standard output goes to /dev/null. */
#ifndef RR_CLI_PARALLEL_H
#define RR_CLI_PARALLEL_H

#include <stddef.h>
#include "console.h"

/* MPI_Init when the process was started by an MPI launcher; call first. */
void cli_par_init(int *argc, char ***argv);
/* On rank 0 of a job of several ranks: each rank's busy and waiting time to
   stderr; then MPI_Finalize. Returns status. */
int cli_par_finalize(int status);
int cli_par_rank(void);
int cli_par_size(void);

/* Items lo..hi-1 computed into out (their results, item_bytes each, from
   item lo). Nonzero: an error, which ends the loop on every rank. */
typedef int (*cli_par_fn)(void *user, long lo, long hi, void *out);

/* Items [0, n) in chunks of `chunk` (one process) or of a size chosen for
   balance (several); results (n x item_bytes) complete on every rank.
   done (n, may be NULL): 1 for the items computed (a Ctrl-C leaves the
   rest 0). pr (may be NULL): progress, shown by rank 0. Returns 0 or the
   first error status of fn on any rank. */
int cli_par_for(long n, long chunk, size_t item_bytes, cli_par_fn fn, void *user, void *results,
                unsigned char *done, cli_progress *pr);

/* cli_par_for as a library runner (rr_runner_opts.fn): jobs one at a time,
   results on every rank. */
int cli_par_runner(void *ctx, long n, size_t item_bytes, rr_items_fn items, void *arg, void *out);

/* The largest of every rank's status (a collective): a check that only
   rank 0 makes (its output files) ends the job on every rank. */
int cli_par_all(int status);

/* 1 on every rank when any rank was asked to stop (Ctrl-C, SIGTERM): a
   collective, for loops whose ranks must stop at the same step. */
int cli_par_any_stopped(void);

#endif
