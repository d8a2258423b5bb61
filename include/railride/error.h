/* railride: status codes and error reporting.
 * Every fallible call returns an int status (RR_OK = 0) and, when given a
 * non-NULL rr_error, fills it with a one-line message naming file, line and
 * key where they apply. The library never prints, exits or aborts. */
#ifndef RAILRIDE_ERROR_H
#define RAILRIDE_ERROR_H

#include "railride/common.h"

#ifdef __cplusplus
extern "C" {
#endif

enum rr_status {
  RR_OK = 0,
  RR_EINVAL = 1,   /* invalid argument or value (NaN, out of range, ...) */
  RR_ENOMEM = 2,   /* allocation failed */
  RR_EIO = 3,      /* file cannot be opened or read */
  RR_EPARSE = 4,   /* malformed file: syntax, unknown section or key, missing key */
  RR_EUNIT = 5,    /* unknown unit or unit of the wrong dimension */
  RR_ELAPACK = 6,  /* a LAPACK routine failed (e.g. QR iteration did not converge) */
  RR_ENOCONV = 7,  /* an iteration did not converge */
  RR_EUNSUP = 8,   /* combination of options not supported */
  RR_ESTOPPED = 9, /* stopped by the caller's progress callback (rr_progress) */
  RR_EUNDEF = 10,  /* a result is undefined (a stability index with no hunting-related mode) */
  RR_EDERAIL = 11  /* a wheelset left the contact data (a derailment indication) */
};

#define RR_ERROR_MSG_MAX 512

typedef struct rr_error {
  int code;                   /* one of enum rr_status */
  char msg[RR_ERROR_MSG_MAX]; /* one line, no trailing newline */
} rr_error;

/* Static description of a status code. */
RR_API const char *rr_strerror(int status);

#ifdef __cplusplus
}
#endif
#endif
