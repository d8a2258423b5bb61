/* Status codes and the error message helper. */
#include <stdarg.h>
#include <stdio.h>
#include "util/internal.h"

const char *rr_strerror(int status)
{
  switch (status) {
  case RR_OK: return "success";
  case RR_EINVAL: return "invalid argument or value";
  case RR_ENOMEM: return "out of memory";
  case RR_EIO: return "cannot read file";
  case RR_EPARSE: return "malformed input";
  case RR_EUNIT: return "unknown unit or wrong dimension";
  case RR_ELAPACK: return "LAPACK routine failed";
  case RR_ENOCONV: return "iteration did not converge";
  case RR_EUNSUP: return "unsupported combination of options";
  case RR_ESTOPPED: return "stopped by the caller";
  case RR_EUNDEF: return "result undefined";
  case RR_EDERAIL: return "a wheelset left the contact data (derailment indication)";
  default: return "unknown status";
  }
}

int rr_progress_step(const rr_progress *pr, long done, long total, rr_error *err)
{
  if (!pr || !pr->fn || !pr->fn(pr->user, done, total)) return RR_OK;
  return rr_seterr(err, RR_ESTOPPED, "stopped after %ld of %ld steps", done, total);
}

int rr_seterr(rr_error *err, int code, const char *fmt, ...)
{
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    err->code = code;
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
  }
  return code;
}
