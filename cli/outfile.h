/* Output files that are complete or absent: written to a fresh scratch file
 * beside the target (mkstemp: never a planted name or symlink), checked,
 * fsync'd and renamed over the target only when every write succeeded, so
 * a failed or stopped command leaves the previous file byte-identical. A
 * target that exists and is not a regular file (/dev/null, /dev/stdout, a
 * FIFO) is written in place, every write checked. */
#ifndef RR_CLI_OUTFILE_H
#define RR_CLI_OUTFILE_H

#include <stdio.h>

#define CLI_OUT_PATH_MAX 4096

typedef struct cli_outfile {
  FILE *fp;
  char path[CLI_OUT_PATH_MAX]; /* the target */
  char tmp[CLI_OUT_PATH_MAX];  /* the scratch file ("" when written in place) */
  const char *what;            /* for messages: "--psd", "the Pareto front" */
} cli_outfile;

/* Opens the scratch file; prints the error and returns EXIT_BADINPUT (a
   folder that cannot be written) or 0. */
int cli_out_open(cli_outfile *o, const char *path, const char *what);
/* Flushes, checks, fsyncs, closes and renames; 0, or EXIT_FAIL after the
   message (the scratch file removed, the target untouched). */
int cli_out_commit(cli_outfile *o);
/* Drops the scratch file (the target untouched); safe on a closed one. */
void cli_out_abort(cli_outfile *o);
/* Copies the file src to the target path through a scratch file (the
   picture gnuplot drew in a private folder). 0 or EXIT_FAIL. */
int cli_out_copy(const char *src, const char *path, const char *what);
/* Standard output's final check: a write that failed (a full disk, a closed
   pipe) is an error with a message and exit status 1. */
int cli_stdout_close(int status);

#endif
