/* Reading user files safely (see textfile.h). */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "textfile.h"
#include "internal.h"

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

int rr_lines_next(rr_lines *r, const char **text)
{
  if (r->status) return -1;
  errno = 0;
  ssize_t n = getline(&r->buf, &r->cap, r->fp);
  if (n < 0) {
    if (ferror(r->fp)) {
      r->status = rr_seterr(&r->err, RR_EIO, "%s:%d: cannot read: %s", r->path, r->line + 1,
                            strerror(errno));
      return -1;
    }
    return 0;
  }
  r->line++;
  if (memchr(r->buf, 0, (size_t)n)) return stop(r, "NUL byte in the line (not a text file?)");
  while (n > 0 && (r->buf[n - 1] == '\n' || r->buf[n - 1] == '\r')) r->buf[--n] = 0;
  const char *p = r->buf;
  while (isspace((unsigned char)*p)) p++;
  if (*p == '#' || *p == ';') {
    r->buf[0] = 0;
    *text = r->buf;
    return 1;
  }
  if (n > r->limit) {
    char msg[96];
    snprintf(msg, sizeof msg, "line of %zd characters, longer than the limit of %d", n, r->limit);
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
