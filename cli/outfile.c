#define _POSIX_C_SOURCE 200809L
/* Output files written whole or not at all (outfile.h). */
#include "outfile.h"
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "cli.h"

/* The scratch name: ".NAME.XXXXXX" in the target's folder, so the rename
   stays on one file system. */
static int scratch_name(const char *path, char *out, size_t n)
{
  const char *slash = strrchr(path, '/');
  int dir = slash ? (int)(slash - path) + 1 : 0;
  int w = snprintf(out, n, "%.*s.%s.XXXXXX", dir, path, slash ? slash + 1 : path);
  return w > 0 && (size_t)w < n ? 0 : -1;
}

int cli_out_open(cli_outfile *o, const char *path, const char *what)
{
  struct stat st;
  memset(o, 0, sizeof *o);
  o->what = what;
  if (!path || !*path) return cli_bad("%s: an empty file name", what);
  if (snprintf(o->path, sizeof o->path, "%s", path) >= (int)sizeof o->path)
    return cli_bad("%s: file name too long", what);
  if (!stat(path, &st) && !S_ISREG(st.st_mode)) { /* a device or a pipe: in place */
    if (S_ISDIR(st.st_mode)) return cli_bad("%s: %s is a folder", what, path);
    o->fp = fopen(path, "w");
    return o->fp ? 0 : cli_bad("%s: cannot write %s: %s", what, path, strerror(errno));
  }
  if (scratch_name(path, o->tmp, sizeof o->tmp)) return cli_bad("%s: file name too long", what);
  int fd = mkstemp(o->tmp);
  if (fd < 0) {
    int e = errno;
    o->tmp[0] = 0;
    return cli_bad("%s: cannot write beside %s: %s", what, path, strerror(e));
  }
  mode_t mask = umask(0); /* the mode a plain fopen would give */
  umask(mask);
  if (fchmod(fd, 0666 & ~mask) || !(o->fp = fdopen(fd, "w"))) {
    int e = errno;
    close(fd);
    unlink(o->tmp);
    o->tmp[0] = 0;
    return cli_bad("%s: cannot write beside %s: %s", what, path, strerror(e));
  }
  return 0;
}

int cli_out_commit(cli_outfile *o)
{
  if (!o->fp) return 0;
  int bad = fflush(o->fp) != 0 || ferror(o->fp), e = errno, scratch = o->tmp[0] != 0;
  if (!bad && o->tmp[0] && fsync(fileno(o->fp))) bad = 1, e = errno;
  if (fclose(o->fp) && !bad) bad = 1, e = errno;
  o->fp = NULL;
  if (!bad && o->tmp[0] && rename(o->tmp, o->path)) bad = 1, e = errno;
  if (bad) {
    if (o->tmp[0]) unlink(o->tmp);
    o->tmp[0] = 0;
    fprintf(stderr, "railride: %s: writing %s failed: %s%s\n", o->what, o->path,
            strerror(e ? e : EIO), scratch ? " (the previous file, if any, is unchanged)" : "");
    return EXIT_FAIL;
  }
  o->tmp[0] = 0;
  return 0;
}

void cli_out_abort(cli_outfile *o)
{
  if (o->fp) fclose(o->fp);
  o->fp = NULL;
  if (o->tmp[0]) unlink(o->tmp);
  o->tmp[0] = 0;
}

int cli_out_copy(const char *src, const char *path, const char *what)
{
  FILE *in = fopen(src, "rb");
  if (!in) return cli_bad("%s: %s was not drawn", what, path);
  cli_outfile o;
  int r = cli_out_open(&o, path, what);
  char buf[65536];
  size_t n;
  while (!r && (n = fread(buf, 1, sizeof buf, in)) > 0)
    if (fwrite(buf, 1, n, o.fp) != n) break;
  int bad = ferror(in);
  fclose(in);
  if (r) return r;
  if (bad) {
    cli_out_abort(&o);
    return cli_bad("%s: reading the drawn picture failed", what);
  }
  return cli_out_commit(&o);
}

int cli_stdout_close(int status)
{
  int bad = fflush(stdout) != 0 || ferror(stdout), e = errno;
  if (fclose(stdout) && !bad) bad = 1, e = errno;
  if (!bad) return status;
  fprintf(stderr, "railride: writing standard output failed: %s\n", strerror(e ? e : EIO));
  return status ? status : EXIT_FAIL;
}
