/* Reading user files safely (see textfile.h). */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "util/textfile.h"
#include "util/internal.h"

FILE *rr_open_regular(const char *path, rr_error *err)
{
  struct stat st;
  if (stat(path, &st)) {
    rr_seterr(err, RR_EIO, "%s: cannot open: %s", path, strerror(errno));
    return NULL;
  }
  if (!S_ISREG(st.st_mode)) {
    rr_seterr(err, RR_EIO, "%s: not a regular file%s", path,
              S_ISDIR(st.st_mode) ? " (a directory)" : "");
    return NULL;
  }
  FILE *fp = fopen(path, "r");
  if (!fp) rr_seterr(err, RR_EIO, "%s: cannot open: %s", path, strerror(errno));
  return fp;
}

int rr_lines_open(rr_lines *r, const char *path, int limit, rr_error *err)
{
  *r = (rr_lines){.path = path, .limit = limit};
  r->fp = rr_open_regular(path, err);
  return r->fp ? RR_OK : (err ? err->code : RR_EIO);
}

void rr_lines_close(rr_lines *r)
{
  if (r->fp) fclose(r->fp);
  free(r->buf);
  r->fp = NULL;
  r->buf = NULL;
}

static int stop(rr_lines *r, const char *what)
{
  r->status = rr_seterr(&r->err, RR_EPARSE, "%s:%d: %s", r->path, r->line, what);
  return -1;
}

/* One line read a character at a time, kept up to the limit and never
   more: a line of any length costs no memory (a 700 MB line under a memory
   cap used to end the file silently). Comment lines of any length are
   skipped; a data line over the limit is refused. */
int rr_lines_next(rr_lines *r, const char **text)
{
  if (r->status) return -1;
  size_t keep = (size_t)r->limit + 2; /* the limit, one more to know it is passed, the NUL */
  if (r->cap < keep) {
    char *b = realloc(r->buf, keep);
    if (!b) {
      r->status = rr_seterr(&r->err, RR_ENOMEM, "%s: out of memory", r->path);
      return -1;
    }
    r->buf = b;
    r->cap = keep;
  }
  size_t n = 0, total = 0;
  int c, nul = 0, lead = 0; /* lead: the first non-blank character */
  errno = 0;
  while ((c = getc(r->fp)) != EOF && c != '\n') {
    total++;
    nul |= c == 0;
    if (!lead && !isspace(c)) lead = c;
    if (n + 1 < keep) r->buf[n++] = (char)c;
  }
  if (c == EOF && ferror(r->fp)) {
    r->status = rr_seterr(&r->err, RR_EIO, "%s:%d: cannot read: %s", r->path, r->line + 1,
                          strerror(errno ? errno : EIO));
    return -1;
  }
  if (c == EOF && total == 0) return 0;
  r->line++;
  r->buf[n] = 0;
  if (nul) return stop(r, "NUL byte in the line (not a text file?)");
  while (n > 0 && r->buf[n - 1] == '\r') r->buf[--n] = 0, total--;
  if (lead == '#' || lead == ';') {
    r->buf[0] = 0;
    *text = r->buf;
    return 1;
  }
  if (total > (size_t)r->limit) {
    char msg[96];
    snprintf(msg, sizeof msg, "line of %zu characters, longer than the limit of %d", total,
             r->limit);
    return stop(r, msg);
  }
  *text = r->buf;
  return 1;
}

char *rr_lines_ini_reader(char *str, int num, void *stream)
{
  rr_lines *r = stream;
  const char *text;
  int keep = r->limit;
  if (num - 2 < r->limit) r->limit = num - 2;
  int got = rr_lines_next(r, &text);
  r->limit = keep;
  if (got <= 0) return NULL;
  snprintf(str, (size_t)num, "%s\n", text);
  return str;
}

int rr_csv_pair(const char *line, int rows_so_far, double *a, double *b)
{
  char tail;
  if (!line[0] || (rows_so_far == 0 && sscanf(line, " %lf", a) != 1)) return 0;
  if (sscanf(line, " %lf , %lf %c", a, b, &tail) == 2 ||
      sscanf(line, " %lf %lf %c", a, b, &tail) == 2)
    return 1;
  return -1;
}

int rr_word_index(const char *word, const char *const *list)
{
  for (int i = 0; list[i]; i++)
    if (!strcmp(word, list[i])) return i;
  return -1;
}

int rr_csv_header(const char *path, int line, const char *text, const rr_csv_name *const *cols,
                  int nmin, int ncols, double *scale, int *nnamed, rr_error *err)
{
  int k = 0;
  for (const char *p = text; *p;) {
    p += strspn(p, ", ;\t\r");
    size_t n = strcspn(p, ", ;\t\r");
    if (!n) break;
    if (k >= ncols)
      return rr_seterr(err, RR_EPARSE, "%s:%d: header: more than %d columns", path, line, ncols);
    const rr_csv_name *c = cols[k];
    while (c->name && (strlen(c->name) != n || strncmp(c->name, p, n))) c++;
    if (!c->name) { /* the message lists what is accepted, not the file's text */
      char want[256] = "";
      for (const rr_csv_name *w = cols[k]; w->name; w++) {
        size_t l = strlen(want);
        snprintf(want + l, sizeof want - l, "%s%s", l ? ", " : "", w->name);
      }
      return rr_seterr(err, RR_EUNIT, "%s:%d: header: column %d is not one of %s", path, line,
                       k + 1, want);
    }
    scale[k++] = c->scale;
    p += n;
  }
  if (k < nmin)
    return rr_seterr(err, RR_EPARSE, "%s:%d: header: %d columns, %d expected", path, line, k, nmin);
  if (nnamed) *nnamed = k;
  return RR_OK;
}
