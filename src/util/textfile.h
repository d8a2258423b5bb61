/* Reading user files safely: regular files only (a FIFO would block, a
 * directory read as empty), lines of any length, NUL bytes refused, comment
 * lines of any length skipped, data lines over a documented limit refused
 * with file and line. One reader for the vehicle, problem, spectrum and SDF
 * table files. */
#ifndef RR_TEXTFILE_H
#define RR_TEXTFILE_H

#include <stdio.h>
#include "railride/error.h"

/* Longest data line of an INI file (inih's fixed line buffer, 200 bytes,
   less the newline and terminator). */
#define RR_INI_LINE_MAX 198
/* Longest data line of a CSV table. */
#define RR_CSV_LINE_MAX 4096

/* fopen(path, "r") for a regular file; the message names the path. */
FILE *rr_open_regular(const char *path, rr_error *err);

typedef struct rr_lines {
  FILE *fp;
  const char *path;
  char *buf; /* getline's buffer (freed by rr_lines_close) */
  size_t cap;
  int line;     /* number of the last line read */
  int limit;    /* longest data line accepted */
  int status;   /* RR_OK, or the error that stopped reading */
  rr_error err; /* its message: path:line: ... */
} rr_lines;

/* Opens path; limit is the longest data line accepted. */
int rr_lines_open(rr_lines *r, const char *path, int limit, rr_error *err);
void rr_lines_close(rr_lines *r);
/* The next line, without its newline, in *text: 1, or 0 at the end, or -1
   on an error (r->status, r->err). Comment lines (first non-blank '#' or
   ';') come back as "" whatever their length. */
int rr_lines_next(rr_lines *r, const char **text);
/* A CSV row of two numbers, comma or blank separated: 1 read into a, b;
   0 a line to skip (blank, a comment, or a header before the first row:
   rows_so_far == 0 and no leading number); -1 malformed. */
int rr_csv_pair(const char *line, int rows_so_far, double *a, double *b);
/* An inih reader (ini_parse_stream) over rr_lines: stops, with the error in
   r, at a NUL byte or a data line longer than num - 2. */
char *rr_lines_ini_reader(char *str, int num, void *stream);

/* A table's header: each column's accepted names, each with the factor that
   brings its unit to the table's (f_hz 1, f_rad_per_s 1/2 pi, ...). */
typedef struct rr_csv_name {
  const char *name; /* NULL ends a column's list */
  double scale;
} rr_csv_name;
/* Checks the header line (fields split at commas, semicolons, blanks)
   against cols (ncols lists; a header may name nmin..ncols columns): the
   scales of the columns it names into scale[], else RR_EUNIT naming
   path:line and the field. A header's units are honoured or refused, never
   ignored. */
int rr_csv_header(const char *path, int line, const char *text, const rr_csv_name *const *cols,
                  int nmin, int ncols, double *scale, int *nnamed, rr_error *err);

/* The index of word in the NULL-ended list, or -1 (the keyword values of
   the readers). */
int rr_word_index(const char *word, const char *const *list);

#endif
