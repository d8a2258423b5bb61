#define _POSIX_C_SOURCE 200809L
/* The command line's console: messages and exit statuses, Ctrl-C, the
 * clock and progress lines. The bottom of cli/: it calls nothing else
 * there (parallel.c tells it the MPI rank, so that one rank draws). */
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "console.h"

#define CONSOLE_REDRAW_S 0.25   /* a terminal's progress line, redrawn */
#define CONSOLE_FILE_LINE_S 1.0 /* a progress line to a file or pipe */

static int console_rank; /* this process's MPI rank (0 without MPI) */

void cli_console_rank(int rank) { console_rank = rank; }

int cli_bad(const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  fputs("railride: ", stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
  return EXIT_BADINPUT;
}

int cli_fail(const rr_error *e, int st)
{
  fprintf(stderr, "railride: %s\n", e->msg);
  return (st == RR_ELAPACK || st == RR_ENOMEM || st == RR_ENOCONV || st == RR_EDERAIL)
             ? EXIT_FAIL
             : EXIT_BADINPUT;
}

static volatile sig_atomic_t stop_flag;
static void on_stop(int sig)
{
  (void)sig;
  stop_flag = 1;
}

void cli_catch_stops(void)
{
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

int cli_stopped(void) { return stop_flag; }

double cli_now_s(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void cli_progress_start(cli_progress *p, const char *what, long total, int force)
{
  *p = (cli_progress){.what = what,
                      .total = total,
                      .t0 = cli_now_s(),
                      .tty = isatty(STDERR_FILENO),
                      .show = (force || isatty(STDERR_FILENO)) &&
                              console_rank == 0}; /* one progress line per job */
  p->last = p->t0;
}

void cli_progress_step(cli_progress *p, long n)
{
  p->done += n;
  double now = cli_now_s();
  /* a terminal's line is redrawn 4 times a second; a file gets a line a second */
  double every = p->tty ? CONSOLE_REDRAW_S : CONSOLE_FILE_LINE_S;
  if (!p->show || (now - p->last < every && p->done < p->total)) return;
  p->last = now;
  double done = (double)p->done, total = (double)p->total;
  double eta = p->done ? (now - p->t0) / done * (total - done) : 0;
  fprintf(stderr,
          p->tty ? "\r%s: %ld/%ld (%.0f%%)  ETA %.0f s   " : "%s: %ld/%ld (%.0f%%)  ETA %.0f s\n",
          p->what, p->done, p->total, 100.0 * done / total, eta);
}

static int progress_hook(void *user, long done, long total)
{
  cli_progress *p = user;
  p->total = total;
  cli_progress_step(p, done - p->done);
  return cli_stopped();
}

rr_progress cli_progress_hook(cli_progress *p)
{
  return (rr_progress){.fn = progress_hook, .user = p};
}

void cli_progress_end(cli_progress *p)
{
  if (p->show)
    fprintf(stderr, "%s%s: %ld/%ld in %.1f s%s\n", p->tty ? "\r" : "", p->what, p->done, p->total,
            cli_now_s() - p->t0,
            p->done < p->total ? " (stopped)"
            : p->tty           ? "             "
                               : "");
}
