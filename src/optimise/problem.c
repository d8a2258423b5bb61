/* Optimisation problem files (see problem.h). */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <math.h>
#include <errno.h>
#include <ini.h>
#include <stdarg.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/problem.h"
#include "util/internal.h"
#include "util/textfile.h"

typedef struct pr_ctx {
  const char *path;
  rr_lines rl;
  rr_problem *p;
  rr_error *err;
  int status;
  int var_line[RR_DESIGN_MAX_VARS];
  char seen[8][16];
  int nseen;
  int known; /* a problem-file section was met: the file is one, its text may be quoted */
} pr_ctx;

/* The first failure, "FILE:LINE: [SECTION] KEY: message"; returns 0 (inih: stop). */
static int pr_fail(pr_ctx *c, const char *sec, const char *key, const char *fmt, ...)
    RR_PRINTF(4, 5);
static int pr_fail(pr_ctx *c, const char *sec, const char *key, const char *fmt, ...)
{
  if (c->status) return 0;
  char msg[RR_ERROR_MSG_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  c->status =
      rr_seterr(c->err, RR_EPARSE, "%s:%d: [%s] %s: %s", c->path, c->rl.line, sec, key, msg);
  return 0;
}

static void trim(char *s)
{
  char *a = s;
  while (isspace((unsigned char)*a)) a++;
  memmove(s, a, strlen(a) + 1);
  size_t n = strlen(s);
  while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
}

static int whole(const char *v, long long lo, long long hi, long long *out)
{
  char *end;
  errno = 0;
  long long k = strtoll(v, &end, 10);
  if (end == v || *end || errno || k < lo || k > hi) return -1;
  *out = k;
  return 0;
}

/* [problem] keys, each once. */
static int problem_key(pr_ctx *c, const char *name, const char *val)
{
  rr_problem *p = c->p;
  long long k;
  for (int i = 0; i < c->nseen; i++)
    if (!strcmp(c->seen[i], name)) return pr_fail(c, "problem", name, "key given twice%s", "");
  if (c->nseen < 8 && strlen(name) < sizeof c->seen[0])
    snprintf(c->seen[c->nseen++], sizeof c->seen[0], "%s", name);
  if (!strcmp(name, "vehicle"))
    snprintf(p->vehicle, sizeof p->vehicle, "%s", val);
  else if (!strcmp(name, "output")) {
    if (!*val) return pr_fail(c, "problem", name, "an output prefix expected (it is empty)%s", "");
    snprintf(p->output, sizeof p->output, "%s", val);
  } else if (!strcmp(name, "population")) {
    if (whole(val, 4, RR_PROBLEM_POPULATION_MAX, &k) || k % 2)
      return pr_fail(c, "problem", name,
                     "an even whole number from 4 to 10000000 expected, got '%s'", val);
    p->population = (int)k;
  } else if (!strcmp(name, "generations")) {
    if (whole(val, 0, RR_PROBLEM_GENERATIONS_MAX, &k))
      return pr_fail(c, "problem", name, "a whole number from 0 to 1000000 expected, got '%s'",
                     val);
    p->generations = (int)k;
  } else if (!strcmp(name, "seed")) {
    if (whole(val, 0, LLONG_MAX, &k))
      return pr_fail(c, "problem", name, "a whole number >= 0 expected, got '%s'", val);
    p->seed = (unsigned long long)k;
  } else if (!strcmp(name, "threads")) {
    if (whole(val, 0, 1024, &k))
      return pr_fail(c, "problem", name, "a whole number from 0 to 1024 expected, got '%s'", val);
    p->threads = (int)k;
  } else
    return pr_fail(c, "problem", name,
                   "unknown key (vehicle, population, generations, seed, threads, output)%s", "");
  return 1;
}

/* section.key = LO .. HI */
static int variable(pr_ctx *c, const char *name, char *val)
{
  rr_problem *p = c->p;
  const rr_vehicle_key *key = rr_vehicle_key_find(name);
  if (!key)
    return pr_fail(c, "variables", name, "not a numeric vehicle-file key (section.key)%s", "");
  for (int i = 0; i < p->nvar; i++)
    if (!strcmp(p->keys[i], name)) {
      char line[32];
      snprintf(line, sizeof line, "%d", c->var_line[i]);
      return pr_fail(c, "variables", name, "listed twice (first on line %s)", line);
    }
  if (p->nvar >= RR_DESIGN_MAX_VARS)
    return pr_fail(c, "variables", name, "more than 32 variables%s", "");
  char *sep = strstr(val, "..");
  if (!sep)
    return pr_fail(c, "variables", name,
                   "expected 'FROM .. TO' with units, e.g. 10 kN/mm .. 120 kN/mm%s", "");
  *sep = 0;
  char a[256], b[256], what[RR_ERROR_MSG_MAX];
  snprintf(a, sizeof a, "%s", val);
  snprintf(b, sizeof b, "%s", sep + 2);
  trim(a);
  trim(b);
  snprintf(what, sizeof what, "%s:%d: [variables] %s", c->path, c->rl.line, name);
  double lo, hi;
  rr_error e;
  if (rr_units_parse(NULL, a, key->si_unit, 0, &lo, what, &e) ||
      rr_units_parse(NULL, b, key->si_unit, 0, &hi, what, &e)) {
    c->status = rr_seterr(c->err, e.code, "%s", e.msg);
    return 0;
  }
  if (!(hi > lo))
    return pr_fail(c, "variables", name, "the upper bound must exceed the lower%s", "");
  if (rr_vehicle_key_check(key, lo, &e) || rr_vehicle_key_check(key, hi, &e))
    return pr_fail(c, "variables", name, "bounds: %s", e.msg);
  snprintf(p->keys[p->nvar], sizeof p->keys[0], "%s", name);
  p->lo[p->nvar] = lo;
  p->hi[p->nvar] = hi;
  c->var_line[p->nvar] = c->rl.line;
  p->nvar++;
  return 1;
}

/* constraint = NAME <= VALUE or NAME >= VALUE */
static int constraint(pr_ctx *c, const char *name, char *val)
{
  rr_problem *p = c->p;
  if (p->ncon + p->nobj >= RR_DESIGN_MAX_OBJS)
    return pr_fail(c, "objectives", name, "more than 16 objectives and constraints%s", "");
  char *op = strstr(val, "<=");
  int sense = 1;
  if (!op) {
    op = strstr(val, ">=");
    sense = -1;
  }
  if (!op)
    return pr_fail(c, "objectives", name, "'%s': expected NAME <= VALUE or NAME >= VALUE", val);
  char *rhs = op + 2, *end;
  *op = 0;
  trim(val);
  trim(rhs);
  errno = 0;
  double b = strtod(rhs, &end);
  if (end == rhs || *end || errno || !isfinite(b))
    return pr_fail(c, "objectives", name, "'%s': the bound must be a finite number", rhs);
  rr_error e;
  if (rr_objective_check(val, &e)) return pr_fail(c, "objectives", name, "%s", e.msg);
  snprintf(p->cons[p->ncon], sizeof p->cons[0], "%s", val);
  p->con_sense[p->ncon] = sense;
  p->con_bound[p->ncon] = b;
  p->ncon++;
  return 1;
}

/* objective = NAME [minimize|maximize] */
static int objective(pr_ctx *c, const char *name, char *val)
{
  rr_problem *p = c->p;
  if (!strcmp(name, "constraint")) return constraint(c, name, val);
  if (strcmp(name, "objective"))
    return pr_fail(c, "objectives", name,
                   "unknown key (objective = NAME minimize|maximize, constraint = NAME <= VALUE)%s",
                   "");
  if (p->nobj + p->ncon >= RR_DESIGN_MAX_OBJS)
    return pr_fail(c, "objectives", name, "more than 16 objectives and constraints%s", "");
  char *sp = strrchr(val, ' ');
  int maxi = 0;
  if (sp && (!strcmp(sp + 1, "minimize") || !strcmp(sp + 1, "minimise")))
    *sp = 0;
  else if (sp && (!strcmp(sp + 1, "maximize") || !strcmp(sp + 1, "maximise"))) {
    *sp = 0;
    maxi = 1;
  }
  trim(val);
  rr_error e;
  if (rr_objective_check(val, &e)) return pr_fail(c, "objectives", name, "%s", e.msg);
  for (int i = 0; i < p->nobj; i++)
    if (!strcmp(p->objs[i], val)) return pr_fail(c, "objectives", name, "'%s' listed twice", val);
  snprintf(p->objs[p->nobj], sizeof p->objs[0], "%s", val);
  p->maximize[p->nobj] = maxi;
  p->nobj++;
  return 1;
}

static int handler(void *user, const char *section, const char *name, const char *value)
{
  pr_ctx *c = user;
  if (c->status) return 1;
  char val[512];
  snprintf(val, sizeof val, "%s", value);
  trim(val);
  c->known |= !strcmp(section, "problem") || !strcmp(section, "variables") ||
              !strcmp(section, "objectives");
  if (!strcmp(section, "problem")) return problem_key(c, name, val);
  if (!strcmp(section, "variables")) return variable(c, name, val);
  if (!strcmp(section, "objectives")) return objective(c, name, val);
  if (!c->known) { /* not a problem file: quote none of it */
    c->status = rr_seterr(c->err, RR_EPARSE,
                          "%s:%d: not a problem file (no [problem], [variables] or [objectives] "
                          "before this line)",
                          c->path, c->rl.line);
    return 0;
  }
  return pr_fail(c, section, name, "unknown section (problem, variables, objectives)%s", "");
}

/* A vehicle file (not a built-in name) is relative to the problem file. */
static void resolve_vehicle(const char *path, rr_problem *p)
{
  rr_vehicle probe;
  if (!p->vehicle[0] || p->vehicle[0] == '/' || !rr_vehicle_builtin(p->vehicle, &probe, NULL))
    return;
  const char *slash = strrchr(path, '/');
  if (!slash) return;
  char tmp[2 * RR_PROBLEM_PATH_MAX];
  snprintf(tmp, sizeof tmp, "%.*s/%s", (int)(slash - path), path, p->vehicle);
  if (strlen(tmp) < sizeof p->vehicle) snprintf(p->vehicle, sizeof p->vehicle, "%s", tmp);
}

int rr_problem_load(const char *path, rr_problem *p, rr_error *err)
{
  *p = (rr_problem){.population = 100, .generations = 100, .seed = 1};
  snprintf(p->output, sizeof p->output, "pareto");
  pr_ctx c = {.path = path, .p = p, .err = err};
  int st = rr_lines_open(&c.rl, path, RR_INI_LINE_MAX, err);
  if (st) return st;
  int r = ini_parse_stream(rr_lines_ini_reader, &c.rl, handler, &c);
  rr_lines_close(&c.rl);
  if (c.status) return c.status;
  if (c.rl.status) return rr_seterr(err, c.rl.status, "%s", c.rl.err.msg);
  if (r > 0)
    return rr_seterr(err, RR_EPARSE, "%s:%d: malformed line (expected [section] or key = value)",
                     path, r);
  if (!p->nvar)
    return rr_seterr(err, RR_EPARSE, "%s: [variables]: at least one variable is needed", path);
  if (!p->nobj)
    return rr_seterr(err, RR_EPARSE, "%s: [objectives]: at least one objective is needed", path);
  resolve_vehicle(path, p);
  return RR_OK;
}
