#define _POSIX_C_SOURCE 200809L
/* Option parsing, vehicle loading and output helpers shared by the commands. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>
#include "cli.h"
#include "plot.h"

void cli_common_init(cli_common *c)
{
  memset(c, 0, sizeof *c);
  c->mo = rr_modal_opts_default();
  c->sdf_override = -1;
  c->gravity = -1;
}

int cli_number(const char *opt, const char *arg, const char *unit, double *out)
{
  rr_error e;
  char what[128];
  snprintf(what, sizeof what, "--%s", opt);
  if (rr_units_parse(NULL, arg, unit, 0, out, what, &e)) {
    cli_bad("%s", e.msg);
    return -1;
  }
  return 0;
}

int cli_number_in(const char *opt, const char *arg, const char *unit, double lo, double hi,
                  double *out)
{
  if (cli_number(opt, arg, unit, out)) return -1;
  if (!(*out >= lo && *out <= hi)) {
    cli_bad("--%s: %s outside %g .. %g %s", opt, arg, lo, hi, strcmp(unit, "1") ? unit : "");
    return -1;
  }
  return 0;
}

int cli_range(const char *opt, const char *arg, const char *unit, double *from, double *to, int *n)
{
  char buf[256];
  snprintf(buf, sizeof buf, "%s", arg);
  char *a = strtok(buf, ":"), *b = strtok(NULL, ":"), *c = strtok(NULL, ":");
  if (!a || !b || !c || strtok(NULL, ":")) {
    cli_bad("--%s: expected FROM:TO:N, got '%s'", opt, arg);
    return -1;
  }
  if (cli_number(opt, a, unit, from) || cli_number(opt, b, unit, to)) return -1;
  char *end;
  long k = strtol(c, &end, 10);
  if (*end || k < 1 || k > 1000000) {
    cli_bad("--%s: N must be a whole number >= 1, got '%s'", opt, c);
    return -1;
  }
  *n = (int)k;
  if (k == 1 && *from != *to) {
    cli_bad("--%s: N = 1 is one value: FROM and TO must be equal, got '%s'", opt, arg);
    return -1;
  }
  return 0;
}

int cli_seed(const char *arg, unsigned long long *seed)
{
  char *end;
  errno = 0;
  unsigned long long s = strtoull(arg, &end, 10);
  if (*end || !*arg || !isdigit((unsigned char)arg[0]) || errno == ERANGE)
    return cli_bad("--seed: a whole number from 0 to %llu expected, got '%s'", ULLONG_MAX, arg);
  *seed = s;
  return 0;
}

int cli_list(const char *opt, const char *arg, const char *unit, double *out, int cap, int *n)
{
  char buf[1024];
  snprintf(buf, sizeof buf, "%s", arg);
  *n = 0;
  for (char *t = strtok(buf, ","); t; t = strtok(NULL, ",")) {
    if (*n >= cap) {
      cli_bad("--%s: more than %d values", opt, cap);
      return -1;
    }
    if (cli_number(opt, t, unit, &out[(*n)++])) return -1;
  }
  if (*n == 0) {
    cli_bad("--%s: empty list", opt);
    return -1;
  }
  return 0;
}

int cli_common_option(cli_common *c, int opt, const char *arg)
{
  switch (opt) {
  case OPT_SPEED:
    if (cli_number("speed", arg, "km/h", &c->speed_kmh)) return CLI_OPT_BAD;
    if (!(c->speed_kmh > 0 && c->speed_kmh <= RR_SPEED_MAX_MS * RR_KMH)) {
      cli_bad("--speed: must be within (0, %g] km/h (got '%s')", RR_SPEED_MAX_MS * RR_KMH, arg);
      return CLI_OPT_BAD;
    }
    c->have_speed = 1;
    return CLI_OPT_TAKEN;
  case OPT_CONICITY:
    if (cli_list("conicity", arg, "1", c->conicities, 64, &c->ncon)) return CLI_OPT_BAD;
    if (c->ncon > 1 && !c->conicity_list) {
      cli_bad("--conicity: one value expected, got '%s'", arg);
      return CLI_OPT_BAD;
    }
    for (int i = 0; i < c->ncon; i++)
      if (!(c->conicities[i] >= 0 && c->conicities[i] <= RR_CONICITY_MAX)) {
        cli_bad("--conicity: must be within [0, %g] (got '%s')", RR_CONICITY_MAX, arg);
        return CLI_OPT_BAD;
      }
    c->conicity = c->conicities[0];
    c->have_conicity = 1;
    return CLI_OPT_TAKEN;
  case OPT_JSON: c->json = 1; return CLI_OPT_TAKEN;
  case OPT_FMAX:
    return cli_number_in("fmax", arg, "Hz", 1e-3, 1e6, &c->mo.fmax_hz) ? CLI_OPT_BAD
                                                                       : CLI_OPT_TAKEN;
  case OPT_WMIN:
    if (cli_number("wmin", arg, "1", &c->mo.w_min)) return CLI_OPT_BAD;
    if (!(c->mo.w_min >= 0 && c->mo.w_min <= 1)) {
      cli_bad("--wmin: must be within 0..1");
      return CLI_OPT_BAD;
    }
    return CLI_OPT_TAKEN;
  case OPT_RMAX:
    if (cli_number("rmax", arg, "1", &c->mo.r_max)) return CLI_OPT_BAD;
    if (!(c->mo.r_max >= 0 && c->mo.r_max <= 1)) {
      cli_bad("--rmax: must be within 0..1");
      return CLI_OPT_BAD;
    }
    return CLI_OPT_TAKEN;
  case OPT_SDF:
    if (!strcmp(arg, "none"))
      c->sdf_override = RR_SDF_NONE;
    else if (!strcmp(arg, "paper"))
      c->sdf_override = RR_SDF_PAPER;
    else if (!strcmp(arg, "physical"))
      c->sdf_override = RR_SDF_PHYSICAL;
    else {
      cli_bad("--sdf: '%s' is not none, paper or physical", arg);
      return CLI_OPT_BAD;
    }
    return CLI_OPT_TAKEN;
  case OPT_GRAVITY: c->gravity = 1; return CLI_OPT_TAKEN;
  case OPT_PROFILES: c->profiles = arg; return CLI_OPT_TAKEN;
  case OPT_PROGRESS_ALL: c->progress = 1; return CLI_OPT_TAKEN;
  }
  return CLI_OPT_NOT_MINE;
}

/* The conicity of a command that reads one: given, or the profiles' (the
   vehicle file's [contact] or --profiles), or the default; the outputs say
   which. */
/* --profiles WHEEL[,RAIL] named in the vehicle. */
static int apply_profiles(cli_common *c)
{
  char w[RR_PROFILE_PATH_MAX];
  const char *comma = strchr(c->profiles, ',');
  snprintf(w, sizeof w, "%.*s", comma ? (int)(comma - c->profiles) : (int)strlen(c->profiles),
           c->profiles);
  if (!comma && !c->veh.wheel_rail.rail[0][0])
    return cli_bad("--profiles: a rail is needed (--profiles WHEEL,RAIL, or [contact] rail)");
  rr_error e;
  if (rr_vehicle_set_profiles(&c->veh, w, comma ? comma + 1 : NULL, &e))
    return cli_bad("--profiles: %s", e.msg);
  return 0;
}

int cli_profile_conicity(cli_common *c, unsigned reads)
{
  if (c->profiles && !(reads & CLI_READS_CONICITY)) return apply_profiles(c);
  if (!(reads & CLI_READS_CONICITY)) return 0;
  if (c->profiles && c->have_conicity)
    return cli_bad("--profiles gives the conicity: not with --conicity");
  if (c->profiles && apply_profiles(c)) return EXIT_BADINPUT;
  int profiled = rr_vehicle_has_profiles(&c->veh);
  if (c->have_conicity) {
    snprintf(c->conicity_source, sizeof c->conicity_source, "%s",
             profiled ? "option (over the vehicle file's profiles)" : "option");
    return 0;
  }
  if (!profiled) {
    snprintf(c->conicity_source, sizeof c->conicity_source, "default %g", CLI_CONICITY_DEFAULT);
    return 0;
  }
  rr_error e;
  double lam;
  int st =
      rr_vehicle_profile_conicity(&c->veh, &lam, c->conicity_source, sizeof c->conicity_source, &e);
  if (st) return cli_fail(&e, st);
  if (!(lam <= RR_CONICITY_MAX)) return cli_bad("the profiles' conicity %g is out of range", lam);
  c->conicity = c->conicities[0] = lam;
  c->ncon = 1;
  c->have_conicity = 1;
  return 0;
}

int cli_load_vehicle(cli_common *c, int argc, char **argv)
{
  if (argc - optind > 1) return cli_bad("unexpected argument '%s'", argv[optind + 1]);
  c->vehicle_spec = optind < argc ? argv[optind] : NULL;
  rr_error e;
  int st = rr_vehicle_open(c->vehicle_spec, &c->veh, &e);
  if (st) return cli_fail(&e, st);
  if (c->sdf_override >= 0) c->veh.sdf_mode = c->sdf_override;
  if (c->gravity >= 0) c->veh.gravity_stiffness = c->gravity;
  if ((st = rr_vehicle_check(&c->veh, &e))) return cli_fail(&e, st);
  return 0;
}

int cli_model(cli_common *c, rr_model **m, int need_speed, int need_conicity)
{
  if (need_speed && !c->have_speed) return cli_bad("--speed is required");
  if (need_conicity && !c->have_conicity) return cli_bad("--conicity is required");
  rr_error e;
  int st = rr_model_from_vehicle(&c->veh, m, &e);
  if (st) return cli_fail(&e, st);
  if ((st = rr_model_set_operating(*m,
                                   (c->have_speed ? c->speed_kmh : CLI_SPEED_DEFAULT_KMH) / RR_KMH,
                                   c->have_conicity ? c->conicity : CLI_CONICITY_DEFAULT, &e))) {
    rr_model_free(*m);
    return cli_fail(&e, st);
  }
  return 0;
}

void cli_json_print(cJSON *root)
{
  char *s = cJSON_Print(root);
  if (s) {
    fputs(s, stdout);
    fputc('\n', stdout);
  }
  free(s);
  cJSON_Delete(root);
}

cJSON *cli_json_matrix(const double *A, int rows, int cols)
{
  cJSON *arr = cJSON_CreateArray();
  for (int i = 0; i < rows; i++)
    cJSON_AddItemToArray(arr, cJSON_CreateDoubleArray(A + (size_t)i * (size_t)cols, cols));
  return arr;
}

static int parse_impl(int argc, char **argv, cli_common *c, unsigned reads, const cli_opt *extra,
                      cli_extra_cb cb, void *user, const char *usage_text, int list);

int cli_getopt_error(const char *cmd, int opt, const char *word)
{
  if (opt == ':') return cli_bad("%s: option '%s' needs a value (see --help)", cmd, word);
  if (optopt > 0 && optopt < 128 && isprint(optopt))
    return cli_bad("%s: unknown option '-%c' (see --help)", cmd, optopt);
  return cli_bad("%s: unknown option '%s' (see --help)", cmd, word);
}

int cli_parse(int argc, char **argv, cli_common *c, unsigned reads, const cli_opt *extra,
              cli_extra_cb cb, void *user, const char *usage_text)
{
  return parse_impl(argc, argv, c, reads, extra, cb, user, usage_text, 0);
}

int cli_parse_list(int argc, char **argv, cli_common *c, unsigned reads, const cli_opt *extra,
                   cli_extra_cb cb, void *user, const char *usage_text)
{
  return parse_impl(argc, argv, c, reads, extra, cb, user, usage_text, 1);
}

/* The shared options, each with what reading it takes: shown (and parsed)
   when the command has every flag of reads and none of unless. A row with
   id 0 is the positional VEHICLE (help only). */
typedef struct common_row {
  cli_opt o;
  unsigned reads, unless;
} common_row;
static const common_row common_rows[] = {
    {{"VEHICLE", 0, NULL, "vehicle file (INI) or built-in name (type1, type2); default type1"},
     0,
     CLI_VEHICLE_PAIR},
    {{"VEHICLE", 0, NULL,
      "vehicle file (INI) or built-in name (type1, type2); default both built-ins, each with its "
      "own curve"},
     CLI_VEHICLE_PAIR,
     0},
    {{"speed", OPT_SPEED, "KMH", "speed, km/h (a unit may be given: \"97 m/s\")"},
     CLI_READS_SPEED,
     0},
    {{"conicity", OPT_CONICITY, "L", "equivalent conicity"}, CLI_READS_CONICITY, 0},
    {{"profiles", OPT_PROFILES, "W[,R]",
      "instead: the equivalent conicity of wheel and rail profiles (EN 15302, at 3 mm; the rail "
      "defaults to the vehicle file's [contact] rail)"},
     CLI_READS_CONICITY,
     0},
    {{"profiles", OPT_PROFILES, "W[,R]",
      "wheel and rail profiles: the nonlinear model reads their contact functions (dr(y), contact "
      "angles) in place of lambda(a) and the flange spring (the rail defaults to the vehicle "
      "file's)"},
     CLI_READS_PROFILES,
     0},
    {{"fmax", OPT_FMAX, "HZ",
      "the stability index's band edge, fixed (default: max(10 Hz, f_K) at each operating "
      "point, f_K the free wheelset's kinematic frequency)"},
     CLI_READS_INDEX,
     0},
    {{"wmin", OPT_WMIN, "W", "least wheelset energy share of a hunting mode (default 1e-3)"},
     CLI_READS_INDEX,
     0},
    {{"rmax", OPT_RMAX, "R", "frame-roll energy share a hunting mode stays below (default 0.5)"},
     CLI_READS_INDEX,
     0},
    {{"sdf", OPT_SDF, "MODE", "override the yaw damper SDF: none, paper, physical"}, 0, 0},
    {{"gravity-stiffness", OPT_GRAVITY, NULL,
      "add the gravitational stiffness (docs/model.md, contact)"},
     CLI_READS_GRAVITY,
     0},
    {{"json", OPT_JSON, NULL, "JSON output"}, CLI_READS_JSON, 0},
    {{"progress", OPT_PROGRESS_ALL, NULL,
      "progress with an ETA on stderr even when it is not a terminal"},
     CLI_READS_PROGRESS,
     0},
};
#define NCOMMON (sizeof common_rows / sizeof common_rows[0])
static const cli_opt help_row = {"help", OPT_HELP, NULL, "this text"};

/* One row: "  --name VALUE" (or "  VEHICLE") padded to the column, then its
   help wrapped at word boundaries to CLI_HELP_WIDTH, each further line
   indented to the column. */
static void opt_row(FILE *fp, const cli_opt *o)
{
  const char *v = o->value ? o->value : ""; /* "=A:B" for values that may start with '-' */
  int col = fprintf(fp, "  %s%s%s%s", o->id ? "--" : "", o->name, *v && *v != '=' ? " " : "", v);
  int pad = col < CLI_HELP_COLUMN - 1 ? CLI_HELP_COLUMN - col : 2;
  fprintf(fp, "%*s", pad, "");
  int start = col += pad; /* where the line's first word goes */
  for (const char *p = o->help; *p;) {
    while (*p == ' ') p++;
    size_t w = strcspn(p, " ");
    if (!w) break;
    if (col > start && col + 1 + (int)w > CLI_HELP_WIDTH) {
      fprintf(fp, "\n%*s", CLI_HELP_COLUMN, "");
      col = start = CLI_HELP_COLUMN;
    } else if (col > start) {
      fputc(' ', fp);
      col++;
    }
    fwrite(p, 1, w, fp);
    col += (int)w;
    p += w;
  }
  fputc('\n', fp);
}

void cli_opt_help(FILE *fp, const cli_opt *t)
{
  for (int i = 0; t && t[i].name; i++) opt_row(fp, &t[i]);
}

static int shown(const common_row *r, unsigned reads)
{
  return (r->reads & reads) == r->reads && !(r->unless & reads);
}

/* The help text with, where its marker is, the shared options the command
   reads (reads_all: none when it parses its own) and then its own. */
static void print_help(const char *cmd, const char *text, unsigned reads, int with_common,
                       const cli_opt *own)
{
  const char *m = strstr(text, CLI_COMMON_HELP);
  if (!m) {
    fputs(text, stdout);
    return;
  }
  fwrite(text, 1, (size_t)(m - text), stdout);
  for (size_t i = 0; with_common && i < NCOMMON; i++)
    if (shown(&common_rows[i], reads)) opt_row(stdout, &common_rows[i].o);
  const cli_opt *help = with_common ? &help_row : NULL; /* --help last */
  for (int i = 0; own && own[i].name; i++)
    if (own[i].id == 'h')
      help = &own[i];
    else
      opt_row(stdout, &own[i]);
  cli_opt_help(stdout, cli_plot_options(cmd)); /* main takes them out before the command runs */
  if (help) opt_row(stdout, help);
  fputs(m + strlen(CLI_COMMON_HELP), stdout);
}

void cli_help_print(const char *cmd, const char *text, const cli_opt *t)
{
  print_help(cmd, text, 0, 0, t);
}

int cli_opt_getopt(const cli_opt *t, struct option *out, int cap)
{
  int n = 0;
  for (int i = 0; t[i].name; i++) {
    int dup = 0; /* one id may have two help rows (--profiles) */
    for (int j = 0; j < n; j++) dup |= out[j].val == t[i].id;
    if (dup || !t[i].id) continue;
    if (n >= cap - 1) return -1;
    out[n++] = (struct option){t[i].name, t[i].value ? required_argument : no_argument, 0, t[i].id};
  }
  out[n] = (struct option){0, 0, 0, 0};
  return n;
}

static const char *row_name(const cli_opt *t, int opt)
{
  for (int i = 0; t[i].name; i++)
    if (t[i].id == opt) return t[i].name;
  return "?";
}

static const char *opt_name(const struct option *opts, int opt)
{
  for (int i = 0; opts[i].name; i++)
    if (opts[i].val == opt) return opts[i].name;
  return "?";
}

static unsigned reads_of(int opt)
{
  switch (opt) {
  case OPT_SPEED: return CLI_READS_SPEED;
  case OPT_CONICITY: return CLI_READS_CONICITY;
  case OPT_JSON: return CLI_READS_JSON;
  case OPT_FMAX:
  case OPT_WMIN:
  case OPT_RMAX: return CLI_READS_INDEX;
  case OPT_PROFILES: return CLI_READS_CONICITY | CLI_READS_PROFILES;
  case OPT_GRAVITY: return CLI_READS_GRAVITY;
  case OPT_PROGRESS_ALL: return CLI_READS_PROGRESS;
  }
  return 0;
}

/* 1 when opt was given before (seen: the ids so far, *nseen of them). */
static int given_twice(int *seen, int *nseen, int cap, int opt)
{
  for (int i = 0; i < *nseen; i++)
    if (seen[i] == opt) return 1;
  if (*nseen < cap) seen[(*nseen)++] = opt;
  return 0;
}

int cli_option_checks(const char *cmd, char **argv, const struct option *opts, int opt,
                      int longindex, int *seen, int *nseen)
{
  if (longindex >= 0) { /* the word that named it: before its value, or with "=value" */
    const struct option *o = &opts[longindex];
    int sep = o->has_arg == required_argument && optarg && optarg == argv[optind - 1];
    const char *word = argv[optind - 1 - sep];
    size_t len = strlen(o->name);
    if (strncmp(word, "--", 2) || strncmp(word + 2, o->name, len) ||
        (word[2 + len] && word[2 + len] != '='))
      return cli_bad("%s: option '%.*s' is not written in full (did you mean '--%s'?)", cmd,
                     (int)strcspn(word, "="), word, o->name);
  }
  if (given_twice(seen, nseen, 64, opt))
    return cli_bad("%s: option '--%s' given twice", cmd, opt_name(opts, opt));
  return 0;
}

int cli_next_option(const char *cmd, int argc, char **argv, const cli_opt *t, cli_opt_state *s,
                    int *opt)
{
  struct option opts[CLI_OPTS_MAX];
  if (cli_opt_getopt(t, opts, CLI_OPTS_MAX) < 0)
    return cli_bad("%s: more than %d options (a bug)", cmd, CLI_OPTS_MAX - 1), -1;
  int li = -1;
  opterr = 0;
  *opt = getopt_long(argc, argv, ":h", opts, &li);
  if (*opt == -1) return 0;
  if (*opt == ':' || *opt == '?') {
    cli_getopt_error(cmd, *opt, argv[optind - 1]);
    return -1;
  }
  return cli_option_checks(cmd, argv, opts, *opt, li, s->seen, &s->nseen) ? -1 : 1;
}

static int parse_impl(int argc, char **argv, cli_common *c, unsigned reads, const cli_opt *extra,
                      cli_extra_cb cb, void *user, const char *usage_text, int list)
{
  cli_opt opts[CLI_OPTS_MAX]; /* every shared option (one it does not read is refused below) */
  int n = 0;
  for (size_t i = 0; i < NCOMMON; i++) opts[n++] = common_rows[i].o;
  opts[n++] = help_row;
  for (int i = 0; extra && extra[i].name && n < CLI_OPTS_MAX - 1; i++) opts[n++] = extra[i];
  opts[n] = (cli_opt)CLI_OPT_END;
  cli_common_init(c);
  c->conicity_list = list;
  optind = 1;
  cli_opt_state os = {.nseen = 0};
  int opt, got;
  while ((got = cli_next_option(argv[0], argc, argv, opts, &os, &opt)) != 0) {
    if (got < 0) return EXIT_BADINPUT;
    if (opt == 'h' || opt == OPT_HELP) {
      print_help(argv[0], usage_text, reads, 1, extra);
      return CLI_HELP_SHOWN;
    }
    if (reads_of(opt) && !(reads_of(opt) & reads))
      return cli_bad("%s: option '--%s' is not one this command reads (see --help)", argv[0],
                     row_name(opts, opt));
    int r = cli_common_option(c, opt, optarg);
    if (r == CLI_OPT_NOT_MINE && cb) r = cb(opt, optarg, user);
    if (r == CLI_OPT_TAKEN) continue;
    return EXIT_BADINPUT; /* the handler's message is out; an option no handler takes is a bug */
  }
  int r = cli_load_vehicle(c, argc, argv);
  return r ? r : cli_profile_conicity(c, reads);
}

/* Splits a CSV line in place into at most cap fields (RFC 4180 quotes);
   returns the count. */
int cli_csv_split(char *s, char **f, int cap)
{
  int n = 0;
  s[strcspn(s, "\r\n")] = 0;
  while (n < cap) {
    char *out = s;
    f[n++] = s;
    if (*s == '"') { /* quoted: "" is a quote */
      for (char *p = s + 1; *p; p++) {
        if (*p == '"' && p[1] != '"') {
          s = p + 1;
          break;
        }
        *out++ = *p;
        if (*p == '"') p++;
        s = p + 1;
      }
      *out = 0;
    } else {
      s += strcspn(s, ",");
    }
    if (*s != ',') {
      *s = 0;
      return n;
    }
    *s++ = 0;
  }
  return n;
}

void cli_csv_field(FILE *fp, const char *text, char sep)
{
  if (!strpbrk(text, ",\"\r\n")) {
    fprintf(fp, "%s%c", text, sep);
    return;
  }
  fputc('"', fp);
  for (const char *p = text; *p; p++) {
    if (*p == '"') fputc('"', fp);
    fputc(*p, fp);
  }
  fprintf(fp, "\"%c", sep);
}

/* "N.s/m" -> "n_s_per_m", "kg.m2" -> "kg_m2", "1" -> "" */
static void unit_suffix(const char *unit, char *out, size_t cap)
{
  size_t k = 0;
  for (const char *p = unit; *p && k + 6 < cap; p++) {
    if (*p == '/')
      k += (size_t)snprintf(out + k, cap - k, "_per_");
    else if (*p == '.' || *p == ' ')
      out[k++] = '_';
    else if (*p != '^')
      out[k++] = (char)tolower((unsigned char)*p);
  }
  out[k] = 0;
  if (!strcmp(out, "1")) out[0] = 0;
}

void cli_csv_key_field(FILE *fp, const char *section_dot_key, char sep)
{
  const rr_vehicle_key *key = rr_vehicle_key_find(section_dot_key);
  char unit[64] = "", name[256];
  if (key && key->si_unit) unit_suffix(key->si_unit, unit, sizeof unit);
  snprintf(name, sizeof name, "%s%s%s", section_dot_key, unit[0] ? "_" : "", unit);
  cli_csv_field(fp, name, sep);
}

enum cli_pareto_col cli_pareto_column(const char *name)
{
  if (!strcmp(name, "feasible") || !strcmp(name, "violation")) return CLI_COL_FLAG;
  return strchr(name, '.') && !strchr(name, '@') && !strchr(name, ',') ? CLI_COL_VAR : CLI_COL_OBJ;
}

int cli_file_arg(const char *opt, const char *arg)
{
  if (arg[0] == '-' && arg[1] == '-')
    return cli_bad("--%s: '%s' is an option, not a file name (the option needs a value)", opt, arg);
  return 0;
}

int cli_limit(const char *arg, double *limit)
{
  char *end;
  errno = 0;
  double v = strtod(arg, &end);
  if (end == arg || *end || errno || !(v >= 1 && v <= 1e15))
    return cli_bad("--limit: a number from 1 to 1e15 expected, got '%s'", arg);
  *limit = v;
  return 0;
}

int cli_over_limit(const char *cmd, double work, double limit, const char *unit)
{
  if (work <= limit) return 0;
  return cli_bad("%s: %.4g %s exceed the limit of %.4g (raise it with --limit N)", cmd, work, unit,
                 limit);
}

void cli_csv_num(FILE *fp, double x, char sep)
{
  if (isfinite(x))
    fprintf(fp, "%.10g%c", x, sep);
  else
    fputc(sep, fp);
}

const char *cli_num_or_none(char *buf, size_t len, double x)
{
  if (isnan(x))
    snprintf(buf, len, "none");
  else
    snprintf(buf, len, "%.6f", x);
  return buf;
}

const char *cli_index_source_key(rr_index_source s)
{
  return s == RR_INDEX_HUNTING    ? "hunting"
         : s == RR_INDEX_UNSTABLE ? "unstable_outside_hunting"
                                  : "none";
}

const char *cli_band_rule(const rr_modal_opts *o)
{
  return o->fmax_hz > 0 ? "fixed" : "max(10 Hz, f_K)";
}

void cli_band_json(cJSON *obj, const rr_modal_opts *o, double fmax_used)
{
  cJSON_AddNumberToObject(obj, "fmax_hz", fmax_used);
  cJSON_AddStringToObject(obj, "fmax_rule", o->fmax_hz > 0 ? "fixed" : "kinematic");
}

void cli_index_text(char *buf, size_t len, double index, rr_index_source src, const rr_mode *mode,
                    double freq_hz, const rr_modal_opts *o, double fmax_used)
{
  char band[64];
  snprintf(band, sizeof band, "band edge %.2f Hz, %s", fmax_used, cli_band_rule(o));
  if (src == RR_INDEX_NONE) {
    snprintf(buf, len,
             "none (undefined: no hunting-related mode below %.4g Hz; all modes stable; %s)",
             fmax_used, band);
    return;
  }
  if (mode)
    snprintf(buf, len, "%.6f (%s: %s at %.4f Hz; %s)", index, rr_index_source_name(src), mode->name,
             mode->freq_hz, band);
  else
    snprintf(buf, len, "%.6f (%s at %.4f Hz; %s)", index, rr_index_source_name(src), freq_hz, band);
}
