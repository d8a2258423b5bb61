/* Listings: the vehicle-file keys (`railride keys`) and the objective names
 * (`railride objectives`), from the library's own tables. */
#include <string.h>
#include "cli.h"

static int want_json(int argc, char **argv, const char *help)
{
  int json = 0;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--json"))
      json = 1;
    else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      fputs(help, stdout);
      return -1;
    } else
      return -2 - i;
  }
  return json;
}

int cmd_keys(int argc, char **argv)
{
  static const char help[] =
      "usage: railride keys [--json]\n"
      "The vehicle-file keys: section, key, SI unit, physical range accepted, meaning.\n";
  int j = want_json(argc, argv, help);
  if (j == -1) return 0;
  if (j < -1) return cli_bad("keys: unknown argument '%s'", argv[-2 - j]);
  int n;
  const rr_vehicle_key *k = rr_vehicle_keys(&n);
  cJSON *arr = j ? cJSON_CreateArray() : NULL;
  for (int i = 0; i < n; i++) {
    int num = k[i].offset != (size_t)-1;
    if (arr) {
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "section", k[i].section);
      cJSON_AddStringToObject(o, "key", k[i].key);
      if (num) {
        cJSON_AddStringToObject(o, "unit", k[i].si_unit);
        cJSON_AddNumberToObject(o, "min", k[i].min);
        cJSON_AddNumberToObject(o, "max", k[i].max);
        cJSON_AddBoolToObject(o, "inf_allowed", (k[i].flags & RR_KEY_INF_OK) != 0);
      }
      cJSON_AddBoolToObject(o, "optional", (k[i].flags & RR_KEY_OPTIONAL) != 0);
      cJSON_AddStringToObject(o, "meaning", k[i].doc);
      cJSON_AddItemToArray(arr, o);
    } else if (num) {
      printf("[%s] %-24s %-8s %8g .. %-8g%s  %s\n", k[i].section, k[i].key, k[i].si_unit, k[i].min,
             k[i].max, (k[i].flags & RR_KEY_INF_OK) ? " or inf" : "", k[i].doc);
    } else {
      printf("[%s] %-24s %-8s %21s  %s\n", k[i].section, k[i].key, "-", "", k[i].doc);
    }
  }
  if (arr) cli_json_print(arr);
  return 0;
}

int cmd_objectives(int argc, char **argv)
{
  static const char help[] =
      "usage: railride objectives [--json]\n"
      "The objective names of problem files, `sweep --objective` and the Python Design,\n"
      "with their arguments, units and meaning. Modifiers follow ';': sdf=none|paper|physical,\n"
      "spectrum=NAME (ride), fmax=HZ, wmin=W, rmax=R (stability), index_modes, vmax=KMH "
      "(critical_speed; a value at vmax is a bound, flagged).\n";
  int j = want_json(argc, argv, help);
  if (j == -1) return 0;
  if (j < -1) return cli_bad("objectives: unknown argument '%s'", argv[-2 - j]);
  int n;
  const rr_objective_info *o = rr_objectives(&n);
  cJSON *arr = j ? cJSON_CreateArray() : NULL;
  for (int i = 0; i < n; i++) {
    char full[64];
    snprintf(full, sizeof full, "%s%s%s", o[i].name, o[i].args[0] ? "@" : "", o[i].args);
    if (arr) {
      cJSON *x = cJSON_CreateObject();
      cJSON_AddStringToObject(x, "name", o[i].name);
      cJSON_AddStringToObject(x, "syntax", full);
      cJSON_AddStringToObject(x, "unit", o[i].unit);
      cJSON_AddStringToObject(x, "meaning", o[i].doc);
      cJSON_AddItemToArray(arr, x);
    } else {
      printf("%-26s %-6s %s\n", full, o[i].unit, o[i].doc);
    }
  }
  if (arr) cli_json_print(arr);
  return 0;
}
