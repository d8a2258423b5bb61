/* Work split over MPI ranks (see parallel.h). Without MPI, or when the
 * process was not started by an MPI launcher, one rank does every chunk. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "parallel.h"
#ifdef RR_HAVE_MPI
#include <mpi.h>
#endif

/* Chunks per rank and loop under MPI: small enough that the last chunk
   costs little waiting (~1/32 of a rank's share), large enough that a fetch
   (~5 us) is nothing against it. */
#define PAR_CHUNKS_PER_RANK 32

typedef struct par_state {
  int rank, size, mpi;
  double busy_s, wait_s; /* inside fn; fetching, waiting for the others and exchanging */
  long items;
#ifdef RR_HAVE_MPI
  MPI_Win win; /* the shared counter: one long on rank 0 */
  long *counter;
#endif
} par_state;

/* One process's state: the CLI is one job per process. */
static par_state par = {.rank = 0, .size = 1};

int cli_par_rank(void) { return par.rank; }
int cli_par_size(void) { return par.size; }

/* Started by mpirun/mpiexec (Open MPI, MPICH) or srun (PMI/PMIx)? */
static int under_launcher(void)
{
  static const char *vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"};
  for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
    if (getenv(vars[i])) return 1;
  return 0;
}

void cli_par_init(int *argc, char ***argv)
{
#ifdef RR_HAVE_MPI
  if (!under_launcher()) return;
  MPI_Init(argc, argv);
  par.mpi = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &par.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &par.size);
  cli_console_rank(par.rank);
  MPI_Win_allocate(par.rank == 0 ? (MPI_Aint)sizeof(long) : 0, sizeof(long), MPI_INFO_NULL,
                   MPI_COMM_WORLD, &par.counter, &par.win);
  if (par.rank == 0) *par.counter = 0;
  MPI_Win_lock_all(0, par.win);
  MPI_Barrier(MPI_COMM_WORLD);
  if (par.rank != 0 && !freopen("/dev/null", "w", stdout)) fclose(stdout); /* rank 0 alone writes */
#else
  (void)argc;
  (void)argv;
  if (under_launcher() && getenv("OMPI_COMM_WORLD_RANK") &&
      atoi(getenv("OMPI_COMM_WORLD_RANK")) == 0)
    fprintf(stderr, "railride: built without MPI (RAILRIDE_MPI): every rank runs the whole job\n");
#endif
}

int cli_par_finalize(int status)
{
#ifdef RR_HAVE_MPI
  if (!par.mpi) return status;
  double mine[2] = {par.busy_s, par.wait_s},
         *all = par.rank == 0 ? malloc(sizeof(double) * 2 * (size_t)par.size) : NULL;
  MPI_Gather(mine, 2, MPI_DOUBLE, all, 2, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (par.rank == 0 && all && par.items > 0) {
    fprintf(stderr, "railride: %d MPI ranks; busy s per rank:", par.size);
    for (int r = 0; r < par.size; r++) fprintf(stderr, " %.2f", all[2 * r]);
    fprintf(stderr, "; waiting and exchange s:");
    for (int r = 0; r < par.size; r++) fprintf(stderr, " %.2f", all[2 * r + 1]);
    fprintf(stderr, "\n");
  }
  free(all);
  MPI_Win_unlock_all(par.win);
  MPI_Win_free(&par.win);
  MPI_Finalize();
#endif
  return status;
}

int cli_par_runner(void *ctx, long n, size_t item_bytes, rr_items_fn items, void *arg, void *out)
{
  (void)ctx;
  return cli_par_for(n, 1, item_bytes, items, arg, out, NULL, NULL);
}

int cli_par_all(int status)
{
  int any = status;
#ifdef RR_HAVE_MPI
  if (par.mpi) MPI_Allreduce(&status, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
#endif
  return any;
}

int cli_par_any_stopped(void)
{
  int mine = cli_stopped(), any = mine;
#ifdef RR_HAVE_MPI
  if (par.mpi) MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
#endif
  return any;
}

/* One process: the chunks in order. */
static int for_serial(long n, long chunk, size_t item_bytes, cli_par_fn fn, void *user,
                      char *results, unsigned char *done, cli_progress *pr)
{
  for (long lo = 0; lo < n; lo += chunk) {
    if (done && cli_stopped()) break;
    long hi = lo + chunk < n ? lo + chunk : n;
    double t0 = cli_now_s();
    int st = fn(user, lo, hi, results + (size_t)lo * item_bytes);
    par.busy_s += cli_now_s() - t0;
    par.items += hi - lo;
    if (st) return st;
    if (done) memset(done + lo, 1, (size_t)(hi - lo));
    if (pr) cli_progress_step(pr, hi - lo);
  }
  return 0;
}

#ifdef RR_HAVE_MPI
/* Every rank's chunks (lo, hi pairs) and their results to every rank. */
static int exchange(long nmine, const long *mine, size_t item_bytes, char *results,
                    unsigned char *done)
{
  int size = par.size, *cnt = malloc(sizeof(int) * 2 * (size_t)size),
      *disp = cnt ? cnt + size : NULL;
  int nm = (int)nmine;
  if (!cnt) return cli_bad("out of memory");
  MPI_Allgather(&nm, 1, MPI_INT, cnt, 1, MPI_INT, MPI_COMM_WORLD);
  long total = 0;
  for (int r = 0; r < size; r++) {
    disp[r] = (int)(2 * total);
    total += cnt[r];
  }
  long *all = malloc(sizeof(long) * 2 * (size_t)(total ? total : 1));
  int *c2 = malloc(sizeof(int) * (size_t)size);
  size_t mybytes = 0;
  for (long k = 0; k < nmine; k++) mybytes += (size_t)(mine[2 * k + 1] - mine[2 * k]) * item_bytes;
  char *pack = malloc(mybytes ? mybytes : 1);
  if (!all || !c2 || !pack || mybytes > (size_t)2147483647) {
    free(cnt);
    free(all);
    free(c2);
    free(pack);
    return cli_bad("MPI: the results exchange needs %zu bytes from one rank (at most 2 GB)",
                   mybytes);
  }
  for (int r = 0; r < size; r++) c2[r] = 2 * cnt[r];
  MPI_Allgatherv(mine, 2 * nm, MPI_LONG, all, c2, disp, MPI_LONG, MPI_COMM_WORLD);
  size_t off = 0;
  for (long k = 0; k < nmine; k++) {
    size_t b = (size_t)(mine[2 * k + 1] - mine[2 * k]) * item_bytes;
    memcpy(pack + off, results + (size_t)mine[2 * k] * item_bytes, b);
    off += b;
  }
  /* byte counts and displacements of each rank's packed results */
  int *bc = malloc(sizeof(int) * 2 * (size_t)size), *bd = bc ? bc + size : NULL;
  char *recv = NULL;
  size_t tb = 0;
  for (int r = 0, k = 0; r < size && bc; r++) {
    size_t rb = 0;
    for (int j = 0; j < cnt[r]; j++, k++) rb += (size_t)(all[2 * k + 1] - all[2 * k]) * item_bytes;
    bc[r] = (int)rb;
    bd[r] = (int)tb;
    tb += rb;
  }
  if (bc && tb <= (size_t)2147483647) recv = malloc(tb ? tb : 1);
  int st = 0;
  if (!recv)
    st = cli_bad("MPI: the results exchange needs %zu bytes (at most 2 GB)", tb);
  else {
    MPI_Allgatherv(pack, (int)mybytes, MPI_BYTE, recv, bc, bd, MPI_BYTE, MPI_COMM_WORLD);
    off = 0;
    for (long k = 0; k < total; k++) { /* the chunks in rank order, as packed */
      size_t b = (size_t)(all[2 * k + 1] - all[2 * k]) * item_bytes;
      memcpy(results + (size_t)all[2 * k] * item_bytes, recv + off, b);
      if (done) memset(done + all[2 * k], 1, (size_t)(all[2 * k + 1] - all[2 * k]));
      off += b;
    }
  }
  free(cnt);
  free(all);
  free(c2);
  free(pack);
  free(bc);
  free(recv);
  return st;
}

static int for_mpi(long n, size_t item_bytes, cli_par_fn fn, void *user, char *results,
                   unsigned char *done, cli_progress *pr)
{
  long chunk = n / ((long)par.size * PAR_CHUNKS_PER_RANK);
  if (chunk < 1) chunk = 1;
  long cap = 64, nmine = 0, *mine = malloc(sizeof(long) * 2 * (size_t)cap);
  int st = mine ? 0 : cli_bad("out of memory");
  double t0 = cli_now_s(), busy = 0;
  while (!st && !(done && cli_stopped())) {
    long lo;
    MPI_Fetch_and_op(&chunk, &lo, MPI_LONG, 0, 0, MPI_SUM, par.win);
    MPI_Win_flush(0, par.win);
    if (lo >= n) break;
    long hi = lo + chunk < n ? lo + chunk : n;
    double t1 = cli_now_s();
    st = fn(user, lo, hi, results + (size_t)lo * item_bytes);
    busy += cli_now_s() - t1;
    if (nmine == cap) {
      long *m2 = realloc(mine, sizeof(long) * 4 * (size_t)cap);
      if (!m2) {
        st = cli_bad("out of memory");
        break;
      }
      mine = m2;
      cap *= 2;
    }
    mine[2 * nmine] = lo;
    mine[2 * nmine + 1] = hi;
    nmine++;
    if (pr && hi > pr->done)
      cli_progress_step(pr, hi - pr->done); /* the counter's position: all ranks' work */
  }
  /* every rank is past its last fetch: rank 0 resets the counter for the
     next loop before the exchange lets anyone start one */
  int any = st;
  MPI_Allreduce(&st, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (par.rank == 0) {
    long zero = 0;
    MPI_Accumulate(&zero, 1, MPI_LONG, 0, 0, 1, MPI_LONG, MPI_REPLACE, par.win);
    MPI_Win_flush(0, par.win);
  }
  if (!any) any = exchange(nmine, mine, item_bytes, results, done);
  free(mine);
  par.busy_s += busy;
  par.wait_s += cli_now_s() - t0 - busy;
  par.items += n;
  return any;
}
#endif

int cli_par_for(long n, long chunk, size_t item_bytes, cli_par_fn fn, void *user, void *results,
                unsigned char *done, cli_progress *pr)
{
  if (pr && par.rank != 0) pr = NULL;
#ifdef RR_HAVE_MPI
  if (par.size > 1) return for_mpi(n, item_bytes, fn, user, results, done, pr);
#endif
  return for_serial(n, chunk < 1 ? 1 : chunk, item_bytes, fn, user, results, done, pr);
}
