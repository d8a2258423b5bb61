/* railride: physical quantities with units (udunits2), for every file and
 * option that takes a number. SI inside. */
#ifndef RAILRIDE_UNITS_H
#define RAILRIDE_UNITS_H
#include "railride/common.h"
#include "railride/error.h"
#ifdef __cplusplus
extern "C" {
#endif
/* Unit parsing (udunits2). A context holds the unit database; create one per
 * thread (udunits itself is not thread-safe) or pass NULL to rr_units_parse,
 * which then loads the database only when the text carries a unit. */
typedef struct rr_units rr_units;
RR_API int rr_units_new(rr_units **out, rr_error *err);
RR_API void rr_units_free(rr_units *u);
/* Parses "50 kN/mm" into SI for a quantity whose SI unit is si_unit.
 * Bare numbers are SI. Non-finite values are rejected unless allow_inf
 * (then "inf" is accepted). what names the context for messages. */
RR_API int rr_units_parse(rr_units *u, const char *text, const char *si_unit, int allow_inf,
                          double *out, const char *what, rr_error *err);

#ifdef __cplusplus
}
#endif
#endif
