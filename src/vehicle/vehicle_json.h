/* JSON vehicle files, walked key by key into the INI parser's handler. */
#ifndef RR_VEHICLE_JSON_H
#define RR_VEHICLE_JSON_H
#include "railride/error.h"

/* fn(user, section, key, value text): nonzero to go on (the INI handler's
   convention). *line is set to each key's line before fn sees it. Returns
   RR_OK, -1 when fn stopped (its error is its own), or a status. */
typedef int (*rr_json_key_fn)(void *user, const char *section, const char *key, const char *value);
int rr_vehicle_json_walk(const char *path, rr_json_key_fn fn, void *user, int *line, rr_error *err);
#endif
