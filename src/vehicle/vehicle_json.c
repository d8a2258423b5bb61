/* Vehicle files in JSON (docs/model.md section 9): the same sections and keys
 * as the INI form, {"name": ..., "base": ..., "carbody": {"mass": 38936,
 * "pitch_inertia": "2e6 kg.m2"}, ...}; a value is a number (SI), a string
 * (with a unit, or a word), true/false, or a list of numbers (a
 * polynomial's coefficients). Each key reaches the INI parser's handler
 * with the line of the file it stands on. */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "util/internal.h"
#include "vehicle/vehicle_json.h"

#define JSON_FILE_MAX (4 << 20) /* bytes: a vehicle file is small */

static char *read_all(const char *path, rr_error *err)
{
  FILE *fp = fopen(path, "rb");
  if (!fp) return rr_seterr(err, RR_EIO, "%s: cannot open", path), NULL;
  char *buf = malloc(JSON_FILE_MAX + 1);
  size_t n = buf ? fread(buf, 1, JSON_FILE_MAX + 1, fp) : 0;
  int bad = ferror(fp);
  fclose(fp);
  if (!buf) return rr_seterr(err, RR_ENOMEM, "out of memory"), NULL;
  if (bad || n > JSON_FILE_MAX) {
    free(buf);
    return rr_seterr(err, RR_EIO, "%s: %s", path, bad ? "cannot read" : "larger than 4 MB"), NULL;
  }
  buf[n] = 0;
  if (strlen(buf) != n) {
    free(buf);
    return rr_seterr(err, RR_EPARSE, "%s: a NUL byte in the file", path), NULL;
  }
  return buf;
}

/* The line of the first "key" at or after from (1 if not found). */
static int line_of(const char *text, const char *key, const char **from)
{
  char pat[160];
  snprintf(pat, sizeof pat, "\"%s\"", key);
  const char *at = strstr(*from, pat);
  if (!at) return 1;
  *from = at + 1;
  int line = 1;
  for (const char *p = text; p < at; p++) line += *p == '\n';
  return line;
}

/* A value as the INI form would carry it; 0 when it has no such form. */
static int value_text(const cJSON *v, char *out, size_t n)
{
  if (cJSON_IsNumber(v)) return snprintf(out, n, "%.17g", v->valuedouble), 1;
  if (cJSON_IsString(v)) return snprintf(out, n, "%s", v->valuestring), 1;
  if (cJSON_IsBool(v)) return snprintf(out, n, "%s", cJSON_IsTrue(v) ? "yes" : "no"), 1;
  if (!cJSON_IsArray(v)) return 0;
  size_t at = 0;
  out[0] = 0;
  for (const cJSON *e = v->child; e; e = e->next) {
    if (!cJSON_IsNumber(e)) return 0;
    at += (size_t)snprintf(out + at, at < n ? n - at : 0, "%s%.17g", at ? " " : "", e->valuedouble);
  }
  return at < n;
}

/* No control characters (a JSON string may hold newlines; an INI line
   cannot, and messages quote keys and values on one line). */
static int plain(const char *s)
{
  for (; *s; s++)
    if ((unsigned char)*s < 0x20 || *s == 0x7f) return 0;
  return 1;
}

static int walk(const char *path, const char *text, const cJSON *root, rr_json_key_fn fn,
                void *user, int *line, rr_error *err)
{
  const char *from = text;
  char val[4096];
  for (const cJSON *s = root->child; s; s = s->next) {
    int sline = line_of(text, s->string, &from);
    if (!plain(s->string))
      return rr_seterr(err, RR_EPARSE, "%s:%d: a name with control characters", path, sline);
    if (!cJSON_IsObject(s)) { /* name, base: the [vehicle] section's */
      *line = sline;
      if (cJSON_IsString(s) && !plain(s->valuestring))
        return rr_seterr(err, RR_EPARSE, "%s:%d: \"%s\": a value with control characters", path,
                         sline, s->string);
      if (!value_text(s, val, sizeof val))
        return rr_seterr(err, RR_EPARSE, "%s:%d: \"%s\": a number, text or list expected", path,
                         sline, s->string);
      if (!fn(user, "vehicle", s->string, val)) return -1;
      continue;
    }
    for (const cJSON *k = s->child; k; k = k->next) {
      *line = line_of(text, k->string, &from);
      if (!plain(k->string) || (cJSON_IsString(k) && !plain(k->valuestring)))
        return rr_seterr(err, RR_EPARSE, "%s:%d: [%s]: a key or value with control characters",
                         path, *line, s->string);
      if (!value_text(k, val, sizeof val))
        return rr_seterr(err, RR_EPARSE, "%s:%d: [%s] %s: a number, text or list expected", path,
                         *line, s->string, k->string);
      if (!fn(user, s->string, k->string, val)) return -1;
    }
  }
  return RR_OK;
}

int rr_vehicle_json_walk(const char *path, rr_json_key_fn fn, void *user, int *line, rr_error *err)
{
  char *text = read_all(path, err);
  if (!text) return err ? err->code : RR_EIO;
  cJSON *root = cJSON_Parse(text);
  int st;
  if (!root) { /* cJSON's error pointer is global: the line is counted from it at once */
    const char *where = cJSON_GetErrorPtr();
    int l = 1;
    for (const char *p = text; where && p < where && *p; p++) l += *p == '\n';
    st = rr_seterr(err, RR_EPARSE, "%s:%d: malformed JSON", path, l);
  } else if (!cJSON_IsObject(root))
    st = rr_seterr(err, RR_EPARSE, "%s:1: not a JSON object of sections", path);
  else
    st = walk(path, text, root, fn, user, line, err);
  cJSON_Delete(root);
  free(text);
  return st;
}
