/* `railride pareto`: an optimise run's Pareto set in clusters (the paper's
 * A-D and its Figs. 3, 4 and 6): k-means over the objectives (rr_kmeans),
 * then each cluster's objectives and the parameters of its designs. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "outfile.h"

#define PARETO_COLS_MAX 64
#define PARETO_ROWS_MAX 1000000
#define PARETO_LINE_MAX 8192
#define PARETO_K_MAX 26 /* named by letters */

typedef struct pareto_set {
  const char *path;
  int ncol, nrow;
  char name[PARETO_COLS_MAX][128];
  enum cli_pareto_col kind[PARETO_COLS_MAX];
  int feasible_col; /* -1: none (every design counts) */
  double *v;        /* nrow x ncol */
  char **line;      /* each row as written (for --csv) */
  int nobj, obj[PARETO_COLS_MAX], nvar, var[PARETO_COLS_MAX];
} pareto_set;

typedef struct pareto_args {
  const char *path, *plot_data;
  int k, csv;
} pareto_args;

static int read_header(pareto_set *ps, char *line)
{
  char *f[PARETO_COLS_MAX + 1];
  ps->ncol = cli_csv_split(line, f, PARETO_COLS_MAX + 1);
  if (ps->ncol > PARETO_COLS_MAX)
    return cli_bad("%s:1: more than %d columns", ps->path, PARETO_COLS_MAX);
  ps->feasible_col = -1;
  for (int j = 0; j < ps->ncol; j++) {
    snprintf(ps->name[j], sizeof ps->name[j], "%s", f[j]);
    ps->kind[j] = cli_pareto_column(f[j]);
    if (!strcmp(f[j], "feasible")) ps->feasible_col = j;
    if (ps->kind[j] == CLI_COL_OBJ) ps->obj[ps->nobj++] = j;
    if (ps->kind[j] == CLI_COL_VAR) ps->var[ps->nvar++] = j;
  }
  if (!ps->nobj)
    return cli_bad("%s:1: no objective columns (is it optimise's -pareto.csv?)", ps->path);
  return 0;
}

/* One data row (line number ln) into ps->v's row ps->nrow. */
static int read_row(pareto_set *ps, char *line, int ln)
{
  char copy[PARETO_LINE_MAX], *f[PARETO_COLS_MAX + 1];
  snprintf(copy, sizeof copy, "%s", line);
  copy[strcspn(copy, "\r\n")] = 0;
  int n = cli_csv_split(line, f, PARETO_COLS_MAX + 1);
  if (n != ps->ncol)
    return cli_bad("%s:%d: %d fields, the header has %d", ps->path, ln, n, ps->ncol);
  double *row = ps->v + cli_at(ps->nrow, ps->ncol, 0);
  for (int j = 0; j < n; j++) {
    char *end;
    errno = 0;
    row[j] = strtod(f[j], &end);
    if (end == f[j] || *end || errno || !isfinite(row[j]))
      return cli_bad("%s:%d: column '%s': a finite number expected, got '%s'", ps->path, ln,
                     ps->name[j], f[j]);
  }
  if (!(ps->line[ps->nrow] = strdup(copy))) return cli_bad("out of memory");
  ps->nrow++;
  return 0;
}

static void pareto_free(pareto_set *ps)
{
  for (int i = 0; ps->line && i < ps->nrow; i++) free(ps->line[i]);
  free(ps->line);
  free(ps->v);
}

static int pareto_read(pareto_set *ps)
{
  FILE *fp = fopen(ps->path, "r");
  if (!fp) return cli_bad("pareto: cannot read '%s': %s", ps->path, strerror(errno));
  char line[PARETO_LINE_MAX];
  int r = 0, ln = 1, cap = 0;
  if (!fgets(line, sizeof line, fp))
    r = cli_bad("%s:1: empty (optimise's -pareto.csv expected)", ps->path);
  else
    r = read_header(ps, line);
  while (!r && fgets(line, sizeof line, fp)) {
    ln++;
    if (!strchr(line, '\n') && !feof(fp))
      r = cli_bad("%s:%d: a line longer than %d characters", ps->path, ln, PARETO_LINE_MAX - 1);
    else if (line[strspn(line, " \r\n")] == 0)
      continue;
    else if (ps->nrow == PARETO_ROWS_MAX)
      r = cli_bad("%s:%d: more than %d designs", ps->path, ln, PARETO_ROWS_MAX);
    if (!r && ps->nrow == cap) {
      cap = cap ? 2 * cap : 256;
      double *v = realloc(ps->v, sizeof(double) * cli_at(cap, ps->ncol, 0));
      char **l = realloc(ps->line, sizeof(char *) * (size_t)cap);
      if (v) ps->v = v;
      if (l) ps->line = l;
      if (!v || !l) r = cli_bad("out of memory");
    }
    if (!r) r = read_row(ps, line, ln);
  }
  if (!r && ferror(fp)) r = cli_bad("pareto: cannot read '%s': %s", ps->path, strerror(errno));
  fclose(fp);
  if (!r && !ps->nrow) r = cli_bad("%s: no designs", ps->path);
  return r;
}

/* Which rows are clustered (the feasible ones), their objectives packed
   into x (nuse x nobj), and each row's cluster label (-1: not clustered). */
typedef struct pareto_clusters {
  int k, nuse, passes;
  int *label;     /* nrow */
  double *centre; /* k x nobj */
  int count[PARETO_K_MAX];
} pareto_clusters;

/* 1 when row i counts: feasible, or no feasibility column. */
static int counts(const pareto_set *ps, int i)
{
  return ps->feasible_col < 0 || ps->v[cli_at(i, ps->ncol, ps->feasible_col)] != 0;
}

static int pareto_cluster(const pareto_set *ps, int k, pareto_clusters *pc)
{
  int n = ps->nrow, m = ps->nobj, r = 0;
  double *x = malloc(sizeof(double) * cli_at(n, m, 0));
  int *lab = malloc(sizeof(int) * (size_t)n);
  pc->label = malloc(sizeof(int) * (size_t)n);
  pc->centre = malloc(sizeof(double) * cli_at(k, m, 0));
  pc->k = k;
  if (!x || !lab || !pc->label || !pc->centre) r = cli_bad("out of memory");
  for (int i = 0; !r && i < n; i++) {
    if (!counts(ps, i)) continue;
    for (int j = 0; j < m; j++) x[cli_at(pc->nuse, m, j)] = ps->v[cli_at(i, ps->ncol, ps->obj[j])];
    pc->nuse++;
  }
  if (!r && pc->nuse < k)
    r = cli_bad("pareto: %d clusters asked of %d feasible designs", k, pc->nuse);
  rr_error e;
  int st = r ? 0 : rr_kmeans(pc->nuse, m, x, k, 1, lab, pc->centre, &pc->passes, &e);
  if (st) r = cli_fail(&e, st);
  const char *names[PARETO_K_MAX];
  for (int j = 0; j < m && j < PARETO_K_MAX; j++) names[j] = ps->name[ps->obj[j]];
  if (!r && m <= PARETO_K_MAX) cli_paper_letters(pc->nuse, m, x, names, k, lab, pc->centre);
  for (int i = 0, u = 0; !r && i < n; i++) {
    pc->label[i] = counts(ps, i) ? lab[u++] : -1;
    if (pc->label[i] >= 0) pc->count[pc->label[i]]++;
  }
  free(x);
  free(lab);
  return r;
}

/* A variable's mean, least and greatest over cluster q's designs. */
static void var_stats(const pareto_set *ps, const pareto_clusters *pc, int q, int col,
                      double out[3])
{
  out[0] = 0, out[1] = INFINITY, out[2] = -INFINITY;
  for (int i = 0; i < ps->nrow; i++)
    if (pc->label[i] == q) {
      double v = ps->v[cli_at(i, ps->ncol, col)];
      out[0] += v / pc->count[q];
      out[1] = fmin(out[1], v);
      out[2] = fmax(out[2], v);
    }
}

static void pareto_text(const pareto_set *ps, const pareto_clusters *pc)
{
  printf("%s: %d designs, %d clustered (feasible), %d objectives and %d variables; %d clusters by "
         "k-means over the objectives, each scaled to [0, 1] (%d passes)\n",
         ps->path, ps->nrow, pc->nuse, ps->nobj, ps->nvar, pc->k, pc->passes);
  for (int q = 0; q < pc->k; q++) {
    printf("\ncluster %c: %d designs\n", 'A' + q, pc->count[q]);
    for (int j = 0; j < ps->nobj; j++)
      printf("  %-44s centre %.6g\n", ps->name[ps->obj[j]], pc->centre[cli_at(q, ps->nobj, j)]);
    for (int j = 0; j < ps->nvar; j++) {
      double s[3];
      var_stats(ps, pc, q, ps->var[j], s);
      printf("  %-44s mean %.6g, range %.6g .. %.6g\n", ps->name[ps->var[j]], s[0], s[1], s[2]);
    }
  }
}

static void pareto_csv(FILE *fp, const pareto_set *ps, const pareto_clusters *pc)
{
  for (int j = 0; j < ps->ncol; j++) cli_csv_field(fp, ps->name[j], ',');
  fprintf(fp, "cluster\n");
  for (int i = 0; i < ps->nrow; i++) {
    fprintf(fp, "%s,", ps->line[i]);
    if (pc->label[i] >= 0) fputc('A' + pc->label[i], fp);
    fputc('\n', fp);
  }
}

static void pareto_json(const pareto_set *ps, const pareto_clusters *pc)
{
  cJSON *root = cJSON_CreateObject(), *cl = cJSON_AddArrayToObject(root, "clusters");
  cJSON_AddStringToObject(root, "file", ps->path);
  cJSON_AddNumberToObject(root, "designs", ps->nrow);
  cJSON_AddNumberToObject(root, "clustered", pc->nuse);
  cJSON_AddNumberToObject(root, "passes", pc->passes);
  for (int q = 0; q < pc->k; q++) {
    cJSON *c = cJSON_CreateObject(), *o = cJSON_AddObjectToObject(c, "centre"),
          *v = cJSON_AddObjectToObject(c, "variables");
    char nm[2] = {(char)('A' + q), 0};
    cJSON_AddStringToObject(c, "name", nm);
    cJSON_AddNumberToObject(c, "designs", pc->count[q]);
    for (int j = 0; j < ps->nobj; j++)
      cJSON_AddNumberToObject(o, ps->name[ps->obj[j]], pc->centre[cli_at(q, ps->nobj, j)]);
    for (int j = 0; j < ps->nvar; j++) {
      double s[3];
      var_stats(ps, pc, q, ps->var[j], s);
      cJSON *sv = cJSON_AddObjectToObject(v, ps->name[ps->var[j]]);
      cJSON_AddNumberToObject(sv, "mean", s[0]);
      cJSON_AddNumberToObject(sv, "min", s[1]);
      cJSON_AddNumberToObject(sv, "max", s[2]);
    }
    cJSON_AddItemToArray(cl, c);
  }
  cJSON *lab = cJSON_AddArrayToObject(root, "labels");
  for (int i = 0; i < ps->nrow; i++) {
    char nm[2] = {(char)('A' + pc->label[i]), 0};
    cJSON_AddItemToArray(lab, pc->label[i] >= 0 ? cJSON_CreateString(nm) : cJSON_CreateNull());
  }
  cli_json_print(root);
}

enum { OPT_PK = 5100, OPT_PCSV, OPT_PJSON, OPT_PPLOTDATA };

static int pareto_parse(int argc, char **argv, pareto_args *a, const char *help, int *json)
{
  static const cli_opt opts[] = {
      {"clusters", OPT_PK, "K",
       "how many clusters, 1 to " RR_STR(PARETO_K_MAX) " (default " RR_STR(
           CLI_PARETO_CLUSTERS) ")"},
      {"csv", OPT_PCSV, NULL, "the file's rows with a cluster column added (empty: infeasible)"},
      {"json", OPT_PJSON, NULL,
       "JSON output: each cluster's centre and variables, each row's label"},
      {"plot-data", OPT_PPLOTDATA, "FILE", "the --csv table to FILE too (what --plot draws)"},
      CLI_OPT_HELP_ROW,
      CLI_OPT_END};
  optind = 1;
  cli_opt_state os = {.nseen = 0};
  int opt, got;
  double k;
  while ((got = cli_next_option("pareto", argc, argv, opts, &os, &opt)) != 0) {
    if (got < 0) return EXIT_BADINPUT;
    if (opt == 'h') return cli_help_print("pareto", help, opts), CLI_HELP_SHOWN;
    if (opt == OPT_PCSV) a->csv = 1;
    if (opt == OPT_PJSON) *json = 1;
    if (opt == OPT_PPLOTDATA && cli_file_arg("plot-data", optarg)) return EXIT_BADINPUT;
    if (opt == OPT_PPLOTDATA) a->plot_data = optarg;
    if (opt == OPT_PK) {
      if (cli_number_in("clusters", optarg, "1", 1, PARETO_K_MAX, &k)) return EXIT_BADINPUT;
      if (k != floor(k)) return cli_bad("--clusters: a whole number expected, got '%s'", optarg);
      a->k = (int)k;
    }
  }
  if (optind >= argc)
    return cli_bad("pareto: the Pareto CSV (optimise's PREFIX-pareto.csv) is required");
  if (argc - optind > 1) return cli_bad("pareto: unexpected argument '%s'", argv[optind + 1]);
  if (a->csv && *json) return cli_bad("pareto: --json or --csv, not both");
  a->path = argv[optind];
  return 0;
}

int cmd_pareto(int argc, char **argv)
{
  static const char help[] =
      "usage: railride pareto PREFIX-pareto.csv [--clusters K] [--json|--csv]\n"
      "An optimise run's Pareto set in clusters (the paper's A-D, Figs. 3, 4 and 6): k-means over\n"
      "the objectives, each scaled to [0, 1] over the set, from a farthest-point start (no\n"
      "randomness: the same file gives the same clusters), the clusters named A, B, ... by\n"
      "ascending first objective; for the paper's problem (zeta_low, zeta_high, std_zeta; 4\n"
      "clusters) by the designs they hold: A best zeta_high, B best zeta_low, C best std_zeta\n"
      "stable at both robust points, D nearest the ideal point (when in four clusters).\n"
      "With constraints only the feasible designs are clustered.\n"
      "Prints each cluster's size, objective centre and its variables' mean and "
      "range.\n" CLI_COMMON_HELP;
  pareto_args a = {.k = CLI_PARETO_CLUSTERS};
  int json = 0;
  int r = pareto_parse(argc, argv, &a, help, &json);
  if (r) return r == CLI_HELP_SHOWN ? 0 : r;
  pareto_set ps = {.path = a.path};
  pareto_clusters pc = {0};
  cli_outfile pd = {0}; /* opened first: a folder that cannot be written fails before the work */
  if (a.plot_data && (r = cli_out_open(&pd, a.plot_data, "--plot-data"))) return r;
  r = pareto_read(&ps);
  if (!r) r = pareto_cluster(&ps, a.k, &pc);
  if (!r && pd.fp) pareto_csv(pd.fp, &ps, &pc);
  if (pd.fp) r = r ? (cli_out_abort(&pd), r) : cli_out_commit(&pd);
  if (!r && a.csv)
    pareto_csv(stdout, &ps, &pc);
  else if (!r && json)
    pareto_json(&ps, &pc);
  else if (!r)
    pareto_text(&ps, &pc);
  free(pc.label);
  free(pc.centre);
  pareto_free(&ps);
  return r;
}
