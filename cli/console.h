/* The command line's console (console.c): messages and exit statuses,
 * Ctrl-C, the clock, progress. Below everything else in cli/. */
#ifndef RR_CLI_CONSOLE_H
#define RR_CLI_CONSOLE_H
#include "railride/railride.h"

#define EXIT_BADINPUT 2
#define EXIT_FAIL 1

/* "railride: MESSAGE" to stderr; EXIT_BADINPUT. */
int cli_bad(const char *fmt, ...);
/* The library's message; EXIT_FAIL for a failed computation, else EXIT_BADINPUT. */
int cli_fail(const rr_error *e, int st);
/* Which MPI rank this is (parallel.c, at start): only rank 0 draws progress. */
void cli_console_rank(int rank);

typedef struct cli_progress {
  const char *what;
  long total, done;
  double t0, last;
  int show, tty; /* drawn at all; redrawn in place (a terminal) or a line each */
} cli_progress;
void cli_progress_start(cli_progress *p, const char *what, long total, int force);
void cli_progress_step(cli_progress *p, long n);
void cli_progress_end(cli_progress *p);
/* An rr_progress for a library call: it drives p and stops the call on
   Ctrl-C (after cli_catch_stops). */
rr_progress cli_progress_hook(cli_progress *p);
void cli_catch_stops(void);
double cli_now_s(void); /* a monotonic clock, s */
int cli_stopped(void);  /* a stop was asked for */
#define CLI_EXIT_STOPPED 130

#endif
