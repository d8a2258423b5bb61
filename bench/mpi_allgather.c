/* The exchange railride's MPI loops end with (two MPI_Allgatherv: the chunk
 * list, then the results), timed for result sizes of a generation: the
 * latency and bandwidth terms of the cost model in bench/mpi.sh.
 * Usage: mpirun -np P mpi_allgather [bytes ...] */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REPS_MIN 20
#define SECONDS_PER_SIZE 0.5

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  int rank, size;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  static const long defaults[] = {8, 1024, 120000, 1200000, 12000000};
  int nsizes = argc > 1 ? argc - 1 : (int)(sizeof defaults / sizeof defaults[0]);
  if (rank == 0) printf("%12s %10s %14s\n", "bytes_total", "reps", "seconds_each");
  for (int s = 0; s < nsizes; s++) {
    long total = argc > 1 ? atol(argv[s + 1]) : defaults[s];
    int mine = (int)(total / size), *cnt = malloc(sizeof(int) * (size_t)size),
        *disp = malloc(sizeof(int) * (size_t)size);
    char *send = calloc((size_t)mine + 1, 1), *recv = calloc((size_t)total + 1, 1);
    long chunks[64] = {0}, *all = calloc(64 * (size_t)size, sizeof(long));
    int c64[1024], d64[1024];
    for (int r = 0; r < size && r < 1024; r++) {
      cnt[r] = mine;
      disp[r] = r * mine;
      c64[r] = 64;
      d64[r] = 64 * r;
    }
    int reps = 0;
    double t0 = MPI_Wtime(), t = 0;
    do { /* as in cli/parallel.c: the chunk list, then the packed results */
      MPI_Barrier(MPI_COMM_WORLD);
      double a = MPI_Wtime();
      MPI_Allgatherv(chunks, 64, MPI_LONG, all, c64, d64, MPI_LONG, MPI_COMM_WORLD);
      MPI_Allgatherv(send, mine, MPI_BYTE, recv, cnt, disp, MPI_BYTE, MPI_COMM_WORLD);
      t += MPI_Wtime() - a;
      reps++;
      double el = MPI_Wtime() - t0;
      MPI_Bcast(&el, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
      if (reps >= REPS_MIN && el > SECONDS_PER_SIZE) break;
    } while (1);
    double tmax;
    MPI_Reduce(&t, &tmax, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    if (rank == 0) printf("%12ld %10d %14.3e\n", (long)mine * size, reps, tmax / reps);
    free(cnt);
    free(disp);
    free(send);
    free(recv);
    free(all);
  }
  MPI_Finalize();
  return 0;
}
