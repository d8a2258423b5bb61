/* Optimisation commands: optimise (NSGA-II over a problem file) and sweep
 * (any objective over a grid of two vehicle-file keys). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <unistd.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "cli.h"
#include "outfile.h"
#include "parallel.h"

static int whole(const char *v, long lo, long hi, long *out)
{
  char *end;
  errno = 0;
  long k = strtol(v, &end, 10);
  if (end == v || *end || errno || k < lo || k > hi) return -1;
  *out = k;
  return 0;
}

typedef struct eval_ctx {
  rr_design *d;
  int threads;
  const rr_problem *p;
  const double *x; /* the batch being evaluated */
} eval_ctx;

/* Designs lo..hi-1 of the batch: objectives (maximised ones negated) and
   then the constraints' violations, value - bound for <=, bound - value for
   >= (NSGA-II counts those > 0). */
#define EVAL_SLICE 256 /* designs between two looks at a stop request: ~0.1 s a thread */
static int eval_items(void *user, long lo, long hi, void *out)
{
  eval_ctx *c = user;
  const rr_problem *p = c->p;
  int w = p->nobj + p->ncon, n = (int)(hi - lo);
  double *f = out;
  rr_error e;
  /* in slices, so that Ctrl-C or SIGTERM stops a large generation within
     about a second (the generation is then dropped, the last whole one kept) */
  for (int s0 = 0; s0 < n; s0 += EVAL_SLICE) {
    int ns = n - s0 < EVAL_SLICE ? n - s0 : EVAL_SLICE;
    if (cli_stopped()) return RR_ESTOPPED;
    int st = rr_design_evaluate_batch(c->d, ns, c->x + (lo + s0) * p->nvar, f + cli_at(s0, w, 0),
                                      c->threads, NULL, &e);
    if (st) return cli_fail(&e, st);
  }
  for (int i = 0; i < n; i++) {
    for (int k = 0; k < p->nobj; k++)
      if (p->maximize[k]) f[i * w + k] = -f[i * w + k];
    for (int k = 0; k < p->ncon; k++) {
      double *g = &f[i * w + p->nobj + k];
      *g = p->con_sense[k] * (*g - p->con_bound[k]);
    }
  }
  return 0;
}

/* A generation's batch: in one piece on one process, in chunks over the
   ranks under MPI (every rank then holds every design's values). */
static int eval_batch(void *user, int n, const double *x, double *f)
{
  eval_ctx *c = user;
  c->x = x;
  return cli_par_for(n, n, sizeof(double) * (size_t)(c->p->nobj + c->p->ncon), eval_items, c, f,
                     NULL, NULL);
}

static int same_design(const double *a, const double *b, int n)
{
  return !memcmp(a, b, sizeof(double) * (size_t)n);
}

/* The final front (rank 0, duplicates once) as CSV and JSON; best and worst
   of each objective over it. With constraints: feasible and violation
   columns. Returns the designs written. */
static int write_front(FILE *fp, FILE *fj, const rr_problem *p, const double *X, const double *F,
                       const int *rank, const double *cv, int N, double *best, double *worst)
{
  for (int j = 0; j < p->nvar; j++) cli_csv_key_field(fp, p->keys[j], ',');
  for (int k = 0; k < p->nobj; k++)
    cli_csv_field(fp, p->objs[k], k + 1 < p->nobj || p->ncon ? ',' : '\n');
  if (p->ncon) fprintf(fp, "feasible,violation\n");
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "index_band_edge",
                          "max(10 Hz, f_K) at each stability objective's operating point, unless "
                          "the objective's fmax= fixes it");
  cJSON *arr = cJSON_AddArrayToObject(root, "front");
  int nfront = 0;
  for (int k = 0; k < p->nobj; k++) {
    best[k] = INFINITY;
    worst[k] = -INFINITY;
  }
  for (int i = 0; i < N; i++) {
    if (rank[i] != 0) continue;
    int dup = 0;
    for (int q = 0; q < i && !dup; q++)
      dup = rank[q] == 0 &&
            same_design(X + (size_t)q * (size_t)p->nvar, X + (size_t)i * (size_t)p->nvar, p->nvar);
    if (dup) continue;
    nfront++;
    cJSON *o = cJSON_CreateObject(), *vars = cJSON_AddObjectToObject(o, "variables"),
          *objs = cJSON_AddObjectToObject(o, "objectives");
    for (int j = 0; j < p->nvar; j++) {
      fprintf(fp, "%.10g,", X[i * p->nvar + j]);
      cJSON_AddNumberToObject(vars, p->keys[j], X[i * p->nvar + j]);
    }
    for (int k = 0; k < p->nobj; k++) {
      double fk = F[i * p->nobj + k];
      fprintf(fp, "%.10g%s", fk, k + 1 < p->nobj || p->ncon ? "," : "\n");
      cJSON_AddItemToObject(objs, p->objs[k],
                            isfinite(fk) ? cJSON_CreateNumber(fk) : cJSON_CreateNull());
      double sk = p->maximize[k] ? -fk : fk;
      if (sk < best[k]) best[k] = sk;
      if (sk > worst[k]) worst[k] = sk;
    }
    if (p->ncon) {
      fprintf(fp, "%d,", cv[i] == 0);
      cli_csv_num(fp, cv[i], '\n');
      cJSON_AddBoolToObject(o, "feasible", cv[i] == 0);
      cJSON_AddItemToObject(o, "violation",
                            isfinite(cv[i]) ? cJSON_CreateNumber(cv[i]) : cJSON_CreateNull());
    }
    cJSON_AddItemToArray(arr, o);
  }
  char *text = cJSON_Print(root);
  if (text) {
    fputs(text, fj);
    fputc('\n', fj);
    free(text);
  }
  cJSON_Delete(root);
  return nfront;
}

typedef struct run_log {
  int total, show; /* generations; progress on stderr */
  FILE *history;   /* PREFIX-history.csv */
} run_log;

static int progress(void *user, int gen, long evals, double secs, int front, double hv)
{
  run_log *l = user;
  if (l->history) {
    fprintf(l->history, "%d,%ld,%.6g,%d,", gen, evals, secs, front);
    cli_csv_num(l->history, hv, '\n');
    fflush(l->history);
  }
  if (l->show) {
    double eta = secs / gen * (l->total - gen);
    fprintf(stderr, "\rgen %4d/%d  evals %9ld  %8.0f evals/s  front %5d", gen, l->total, evals,
            (double)evals / secs, front);
    if (!isnan(hv)) fprintf(stderr, "  hypervolume %.6g", hv);
    fprintf(stderr, "  ETA %.0f s   %s", eta, gen == l->total ? "\n" : "");
  }
  return cli_par_any_stopped(); /* Ctrl-C, SIGTERM: every rank stops after this generation */
}

/* PREFIX-pareto.csv, -pareto.json and -history.csv opened (rank 0; the
   other ranks write to /dev/null), -checkpoint.bin named and, to resume,
   checked. Returns 0 or the exit status (message printed). */
/* The previous run's history copied into the new one's scratch file (a
   resumed run goes on from it). */
static int copy_history(const char *path, FILE *to)
{
  FILE *from = fopen(path, "r");
  if (!from && errno == ENOENT) { /* a run killed before it wrote one: a new history */
    fprintf(stderr, "railride: optimise --resume: no %s; it starts again here\n", path);
    fprintf(to, "generation,evaluations,seconds,front_size,hypervolume\n");
    return 0;
  }
  if (!from) return cli_bad("optimise --resume: cannot read %s: %s", path, strerror(errno));
  char buf[65536];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, from)) > 0) fwrite(buf, 1, n, to);
  int bad = ferror(from);
  fclose(from);
  return bad ? cli_bad("optimise --resume: cannot read %s", path) : 0;
}

/* Every output goes to a scratch file that replaces the previous one only
   when the run has written it whole (outfile.h). */
static int open_outputs(const char *prefix, int resume, char *path, char *hpath, char *jpath,
                        char *cpath, cli_outfile *fp, cli_outfile *fj, cli_outfile *fh)
{
  const size_t n = PATH_MAX + 16;
  if (!*prefix) return cli_bad("optimise: the output prefix is empty");
  snprintf(cpath, n, "%s-checkpoint.bin", prefix);
  snprintf(path, n, "%s-pareto.csv", prefix);
  snprintf(hpath, n, "%s-history.csv", prefix);
  snprintf(jpath, n, "%s-pareto.json", prefix);
  if (resume && access(cpath, R_OK)) return cli_bad("optimise --resume: no checkpoint %s", cpath);
  int rank0 = cli_par_rank() == 0, r;
  if ((r = cli_out_open(fp, rank0 ? path : "/dev/null", "optimise"))) return r;
  if ((r = cli_out_open(fj, rank0 ? jpath : "/dev/null", "optimise")) ||
      (r = cli_out_open(fh, rank0 ? hpath : "/dev/null", "optimise")) ||
      (r = resume && rank0 ? copy_history(hpath, fh->fp) : 0)) {
    cli_out_abort(fp);
    cli_out_abort(fj);
    cli_out_abort(fh);
    return r;
  }
  if (!resume) fprintf(fh->fp, "generation,evaluations,seconds,front_size,hypervolume\n");
  return 0;
}

enum {
  OPT_POP = 5000,
  OPT_GEN,
  OPT_OSEED,
  OPT_THREADS,
  OPT_OUT,
  OPT_SX,
  OPT_SY,
  OPT_OBJ,
  OPT_OLIMIT,
  OPT_PROGRESS,
  OPT_RESUME
};

typedef struct optim_args {
  long pop, gen, threads;
  long long seed;
  const char *out, *problem;
  double limit;
  int progress, resume;
} optim_args;

/* The largest population whose NSGA-II arrays stay within ~2 GB. */
#define CLI_POPULATION_MAX 2000000

/* Options into a; the problem file's name in a->problem. Returns 0,
   CLI_HELP_SHOWN or an exit status. */
static int optim_parse(int argc, char **argv, optim_args *a, const char *help)
{
  static const cli_opt opts[] = {
      {"population", OPT_POP, "N", "population size, even (default: the problem file's)"},
      {"generations", OPT_GEN, "N", "generations (default: the problem file's)"},
      {"seed", OPT_OSEED, "N", "random seed (default: the problem file's)"},
      {"threads", OPT_THREADS, "N", "threads for the evaluations (0: all cores)"},
      {"output", OPT_OUT, "PREFIX", "output prefix (default: the problem file's)"},
      {"limit", OPT_OLIMIT, "N",
       "most designs evaluated, population x (generations + 1) (default " RR_STR(
           CLI_LIMIT_DESIGNS) ")"},
      {"progress", OPT_PROGRESS, NULL, "progress on stderr even when it is not a terminal"},
      {"resume", OPT_RESUME, NULL, "go on from PREFIX-checkpoint.bin"},
      CLI_OPT_HELP_ROW,
      CLI_OPT_END};
  optind = 1;
  cli_opt_state os = {.nseen = 0};
  int opt, got;
  while ((got = cli_next_option("optimise", argc, argv, opts, &os, &opt)) != 0) {
    long k;
    if (got < 0) return EXIT_BADINPUT;
    switch (opt) {
    case 'h': cli_help_print(argv[0], help, opts); return CLI_HELP_SHOWN;
    case OPT_POP:
      if (whole(optarg, 4, 10000000, &k) || k % 2)
        return cli_bad("--population: an even whole number >= 4 expected");
      a->pop = k;
      break;
    case OPT_GEN:
      if (whole(optarg, 0, 1000000, &k))
        return cli_bad("--generations: a whole number >= 0 expected");
      a->gen = k;
      break;
    case OPT_OSEED:
      if (whole(optarg, 0, LONG_MAX, &k)) return cli_bad("--seed: a whole number >= 0 expected");
      a->seed = k;
      break;
    case OPT_THREADS:
      if (whole(optarg, 0, 1024, &k)) return cli_bad("--threads: a whole number >= 0 expected");
      a->threads = k;
      break;
    case OPT_OUT: a->out = optarg; break;
    case OPT_OLIMIT:
      if (cli_limit(optarg, &a->limit)) return EXIT_BADINPUT;
      break;
    case OPT_PROGRESS: a->progress = 1; break;
    case OPT_RESUME: a->resume = 1; break;
    default: return cli_getopt_error("optimise", opt, argv[optind - 1]);
    }
  }
  if (optind >= argc) return cli_bad("optimise: a problem file is required (see --help)");
  if (argc - optind > 1) return cli_bad("unexpected argument '%s'", argv[optind + 1]);
  a->problem = argv[optind];
  return 0;
}

/* The problem file with the command line's overrides, within the limits. */
static int optim_problem(const optim_args *a, rr_problem *p)
{
  rr_error e;
  int st = rr_problem_load(a->problem, p, &e);
  if (st) return cli_fail(&e, st);
  if (a->pop > 0) p->population = (int)a->pop;
  if (a->gen >= 0) p->generations = (int)a->gen;
  if (a->seed >= 0) p->seed = (unsigned long long)a->seed;
  if (a->threads >= 0) p->threads = (int)a->threads;
  if (a->out) snprintf(p->output, sizeof p->output, "%s", a->out);
  if (p->population > CLI_POPULATION_MAX)
    return cli_bad("optimise: population %d exceeds %d (memory)", p->population,
                   CLI_POPULATION_MAX);
  double designs = (double)p->population * (p->generations + 1.0);
  return cli_over_limit("optimise", designs, a->limit, "designs") ? EXIT_BADINPUT : 0;
}

/* A run: its output files, design context and final population. */
typedef struct optim_run {
  char path[PATH_MAX + 16], hpath[PATH_MAX + 16], jpath[PATH_MAX + 16], cpath[PATH_MAX + 16];
  cli_outfile fp, fj, fh; /* the front (CSV, JSON) and the history: replaced when complete */
  run_log log;
  rr_design *d;
  rr_vehicle veh;     /* the problem's vehicle after inheritance */
  double *X, *F, *cv; /* population x variables, x objectives, violations */
  int *rank;
  int done_gens;
  long evaluated; /* designs this run passed to the evaluation */
  int resumed;
  double seconds;
} optim_run;

static void run_close(optim_run *r)
{
  cli_out_abort(&r->fp); /* after a failure: the previous files stay */
  cli_out_abort(&r->fj);
  cli_out_abort(&r->fh);
  rr_design_free(r->d);
  free(r->X);
  free(r->F);
  free(r->cv);
  free(r->rank);
}

/* The outputs (opened before the run, so that a bad folder shows now), the
   design context and the population's arrays. */
static int run_open(optim_run *r, const rr_problem *p, const optim_args *a)
{
  int st = cli_par_all(open_outputs(p->output, a->resume, r->path, r->hpath, r->jpath, r->cpath,
                                    &r->fp, &r->fj, &r->fh));
  if (st) return st; /* on any rank: every rank stops */
  r->log.history = r->fh.fp;
  rr_vehicle v;
  rr_error e;
  if ((st = rr_vehicle_open(p->vehicle[0] ? p->vehicle : NULL, &v, &e))) return cli_fail(&e, st);
  r->veh = v;
  const char *keys[RR_DESIGN_MAX_VARS], *objs[RR_DESIGN_MAX_OBJS];
  for (int i = 0; i < p->nvar; i++) keys[i] = p->keys[i];
  for (int i = 0; i < p->nobj; i++) objs[i] = p->objs[i];
  for (int i = 0; i < p->ncon; i++)
    objs[p->nobj + i] = p->cons[i]; /* constraints: evaluated after the objectives */
  if ((st = rr_design_new(&v, p->nvar, keys, p->nobj + p->ncon, objs, &r->d, &e)))
    return cli_fail(&e, st);
  size_t N = (size_t)p->population;
  r->X = malloc(sizeof(double) * N * (size_t)p->nvar);
  r->F = malloc(sizeof(double) * N * (size_t)p->nobj);
  r->cv = malloc(sizeof(double) * N);
  r->rank = malloc(sizeof(int) * N);
  return r->X && r->F && r->cv && r->rank ? 0 : cli_bad("out of memory");
}

/* The vehicle's values as the model reads them: every numeric key, the SDF
   mode and curve, the gravitational stiffness (not its name or padding). */
static uint64_t vehicle_hash(rr_vehicle *v)
{
  int nk;
  const rr_vehicle_key *keys = rr_vehicle_keys(&nk);
  uint64_t h = RR_FNV_OFFSET;
  for (int i = 0; i < nk; i++)
    if (!(keys[i].flags & RR_KEY_SPECIAL)) h = rr_hash_bytes(h, rr_vehicle_field(v, &keys[i]), 8);
  const rr_sdf_curve *c = &v->sdf;
  h = rr_hash_bytes(h, &v->sdf_mode, sizeof v->sdf_mode);
  h = rr_hash_bytes(h, &v->gravity_stiffness, sizeof v->gravity_stiffness);
  h = rr_hash_bytes(h, &c->kind, sizeof c->kind);
  h = rr_hash_bytes(h, &c->k1_hz, sizeof c->k1_hz);
  h = rr_hash_bytes(h, &c->k2, sizeof c->k2);
  h = rr_hash_bytes(h, &c->k3, sizeof c->k3);
  h = rr_hash_bytes(h, &c->n, sizeof c->n);
  h = rr_hash_bytes(h, &c->has_loss, sizeof c->has_loss);
  h = rr_hash_bytes(h, c->f_hz, sizeof c->f_hz[0] * (size_t)(c->n > 0 ? c->n : 0));
  h = rr_hash_bytes(h, c->k_storage, sizeof c->k_storage[0] * (size_t)(c->n > 0 ? c->n : 0));
  return rr_hash_bytes(h, c->k_loss, sizeof c->k_loss[0] * (size_t)(c->n > 0 ? c->n : 0));
}

/* What a checkpoint must match to be resumed: each part of the run hashed,
   by name (rr_nsga2_fingerprint). */
static rr_nsga2_fingerprint run_fingerprint(optim_run *r, const rr_problem *p)
{
  rr_nsga2_fingerprint fp = {.n = 6,
                             .name = {"the vehicle", "the variables or their bounds",
                                      "the objectives or their sense", "the constraints",
                                      "the population or seed", "the railride version"}};
  uint64_t h[6] = {vehicle_hash(&r->veh), RR_FNV_OFFSET, RR_FNV_OFFSET,
                   RR_FNV_OFFSET,         RR_FNV_OFFSET, RR_FNV_OFFSET};
  for (int i = 0; i < p->nvar; i++) {
    h[1] = rr_hash_bytes(h[1], p->keys[i], strlen(p->keys[i]) + 1);
    h[1] = rr_hash_bytes(rr_hash_bytes(h[1], &p->lo[i], 8), &p->hi[i], 8);
  }
  for (int i = 0; i < p->nobj; i++)
    h[2] = rr_hash_bytes(rr_hash_bytes(h[2], p->objs[i], strlen(p->objs[i]) + 1), &p->maximize[i],
                         sizeof p->maximize[i]);
  for (int i = 0; i < p->ncon; i++) {
    h[3] = rr_hash_bytes(h[3], p->cons[i], strlen(p->cons[i]) + 1);
    h[3] = rr_hash_bytes(rr_hash_bytes(h[3], &p->con_sense[i], sizeof p->con_sense[i]),
                         &p->con_bound[i], 8);
  }
  h[4] = rr_hash_bytes(rr_hash_bytes(h[4], &p->population, sizeof p->population), &p->seed,
                       sizeof p->seed);
  h[5] = rr_hash_bytes(h[5], rr_version(), strlen(rr_version()));
  for (int i = 0; i < 6; i++) fp.part[i] = h[i];
  return fp;
}

/* NSGA-II over the problem; every rank runs it on the same numbers and rank 0
   writes the checkpoint. */
static int run_nsga2(optim_run *r, const rr_problem *p, const optim_args *a)
{
  eval_ctx ec = {.d = r->d, .threads = p->threads, .p = p};
  rr_nsga2_opts o = rr_nsga2_opts_default();
  o.population = p->population;
  o.generations = p->generations;
  o.seed = p->seed;
  o.progress = progress;
  o.user = &r->log;
  o.generations_done = &r->done_gens;
  o.evaluated = &r->evaluated;
  r->resumed = a->resume != 0;
  o.ncon = p->ncon;
  o.cv_out = r->cv;
  o.checkpoint = cli_par_rank() == 0 ? r->cpath : NULL;
  o.resume = a->resume ? r->cpath : NULL;
  o.fingerprint = run_fingerprint(r, p);
  cli_catch_stops();
  rr_error e;
  double t0 = cli_now_s();
  int st =
      rr_nsga2_run(p->nvar, p->nobj, p->lo, p->hi, eval_batch, &ec, &o, r->X, r->F, r->rank, &e);
  r->seconds = cli_now_s() - t0;
  if (st == RR_ESTOPPED) {
    fprintf(stderr, "railride: optimise: stopped by a signal before the first generation was "
                    "complete; nothing written (the previous files are unchanged)\n");
    return CLI_EXIT_STOPPED;
  }
  if (st) return cli_fail(&e, st);
  for (int i = 0; i < p->population; i++) /* maximised objectives back to their sign */
    for (int k = 0; k < p->nobj; k++)
      if (p->maximize[k]) r->F[i * p->nobj + k] = -r->F[i * p->nobj + k];
  return 0;
}

/* The front's files (committed whole) and the summary on standard output. */
static int run_report(optim_run *r, const rr_problem *p, const char *problem)
{
  int N = p->population, nfeas = 0, st;
  double best[RR_DESIGN_MAX_OBJS], worst[RR_DESIGN_MAX_OBJS];
  int nfront = write_front(r->fp.fp, r->fj.fp, p, r->X, r->F, r->rank, r->cv, N, best, worst);
  if ((st = cli_out_commit(&r->fp)) || (st = cli_out_commit(&r->fj))) return st;
  for (int i = 0; i < N; i++) nfeas += r->rank[i] == 0 && r->cv[i] == 0;
  long evals = (long)N * (r->done_gens + 1);
  printf("railride optimise %s: NSGA-II, population %d, %d generations, seed %llu\n", problem, N,
         p->generations, p->seed);
  if (r->done_gens < p->generations)
    printf("  stopped by a signal after generation %d of %d: the front below is that "
           "generation's\n",
           r->done_gens, p->generations);
  printf("  %ld designs in %.1f s (%.0f designs/s); %ld evaluated%s\n", evals, r->seconds,
         (double)evals / r->seconds, r->evaluated,
         r->resumed ? " after the resume" : ", the others unchanged copies of a parent");
  printf("  Pareto front: %d designs, written to %s (also %s; history: %s)\n", nfront, r->path,
         r->jpath, r->hpath);
  if (p->ncon)
    printf("  constraints: %d of the front's designs feasible%s\n", nfeas,
           nfeas ? "" : " (none: the front is the least violating)");
  for (int k = 0; k < p->nobj; k++) {
    int mx = p->maximize[k];
    printf("  %-28s %s: best %.6g, range on the front %.6g .. %.6g\n", p->objs[k],
           mx ? "max" : "min", mx ? -best[k] : best[k], mx ? -worst[k] : best[k],
           mx ? -best[k] : worst[k]);
  }
  return 0;
}

int cmd_optimise(int argc, char **argv)
{
  static const char help[] =
      "usage: railride optimise PROBLEM.ini [--population N] [--generations N] [--seed N] "
      "[--threads N] [--output PREFIX]\n"
      "NSGA-II over the problem file's variables (vehicle-file keys with bounds) and objectives;\n"
      "writes PREFIX-pareto.csv and .json (the non-dominated designs, each once: variables in SI,\n"
      "objectives; with constraints, feasible and total violation),\n"
      "PREFIX-history.csv (per generation: evaluations, seconds, front size; every 10th and the\n"
      "last the hypervolume, 2 or 3 objectives, with the initial population's worst values +10% "
      "as\n"
      "reference, empty otherwise) and a summary. Progress with an ETA\n"
      "on stderr when it is a terminal (or with --progress). Ctrl-C or SIGTERM stops after the\n"
      "generation in progress and writes its front (exit status 130). PREFIX-checkpoint.bin holds\n"
      "the run's state after every generation; --resume goes on from it (the same problem,\n"
      "population and seed: the result is the uninterrupted run's; a changed problem, vehicle or\n"
      "version is refused, naming what changed). Each output replaces the previous file only\n"
      "when written whole (the history at the end of the run). An offspring that is a parent's\n"
      "unchanged copy takes that parent's values without being evaluated again (the same\n"
      "result); the summary gives the designs evaluated. See "
      "examples/paper-optimisation.ini.\n" CLI_COMMON_HELP;
  optim_args a = {.pop = -1, .gen = -1, .threads = -1, .seed = -1, .limit = CLI_LIMIT_DESIGNS};
  int st = optim_parse(argc, argv, &a, help);
  if (st) return st == CLI_HELP_SHOWN ? 0 : st;
  rr_problem p;
  if ((st = optim_problem(&a, &p))) return st;
  optim_run r = {.log = {.total = p.generations,
                         .show = (a.progress || isatty(STDERR_FILENO)) && cli_par_rank() == 0}};
  st = run_open(&r, &p, &a);
  if (!st) st = run_nsga2(&r, &p, &a);
  r.log.history = NULL;
  if (!st) st = cli_out_commit(&r.fh); /* complete before the summary */
  if (!st) st = run_report(&r, &p, a.problem);
  run_close(&r);
  if (st) return st;
  return r.done_gens < p.generations ? CLI_EXIT_STOPPED : 0; /* 128 + SIGINT, as a shell says */
}

/* An axis: a vehicle-file key, or the operating point's speed (km/h) or
   conicity, which then fill the objective's own arguments. */
enum sweep_axis { AXIS_KEY = 0, AXIS_SPEED = 1, AXIS_CONICITY = 2 };
typedef struct sweep_args {
  char key[2][64];
  double from[2], to[2];
  int n[2], have[2];
  enum sweep_axis kind[2];
  const char *objective;
  double limit;
} sweep_args;

static int parse_axis(const char *opt, const char *arg, sweep_args *a, int ax)
{
  const char *eq = strchr(arg, '=');
  if (!eq)
    return cli_bad("--%s: expected section.key=FROM:TO:N, speed=FROM:TO:N or conicity=FROM:TO:N",
                   opt);
  snprintf(a->key[ax], sizeof a->key[ax], "%.*s", (int)(eq - arg), arg);
  a->have[ax] = 1;
  if (!strcmp(a->key[ax], "speed") || !strcmp(a->key[ax], "conicity")) {
    int sp = a->key[ax][0] == 's';
    a->kind[ax] = sp ? AXIS_SPEED : AXIS_CONICITY;
    if (cli_range(opt, eq + 1, sp ? "km/h" : "1", &a->from[ax], &a->to[ax], &a->n[ax]))
      return EXIT_BADINPUT;
    double hi = sp ? RR_SPEED_MAX_MS * RR_KMH : RR_CONICITY_MAX;
    if (!(fmin(a->from[ax], a->to[ax]) > 0 && fmax(a->from[ax], a->to[ax]) <= hi))
      return cli_bad("--%s: %s must be within (0, %g]", opt, a->key[ax], hi);
    return 0;
  }
  const rr_vehicle_key *k = rr_vehicle_key_find(a->key[ax]);
  if (!k)
    return cli_bad("--%s: '%s' is not a numeric vehicle-file key (section.key), speed or conicity",
                   opt, a->key[ax]);
  if (cli_range(opt, eq + 1, k->si_unit, &a->from[ax], &a->to[ax], &a->n[ax])) return EXIT_BADINPUT;
  rr_error e;
  if (rr_vehicle_key_check(k, a->from[ax], &e) || rr_vehicle_key_check(k, a->to[ax], &e))
    return cli_bad("--%s: %s", opt, e.msg);
  return 0;
}

/* The objective at the operating point the axes give (speed, conicity; the
   rest as the objective has it). */
static int objective_at(const char *obj, const double *v, const enum sweep_axis *kind, int nax,
                        char *out, size_t n)
{
  double kmh = NAN, lam = NAN;
  for (int ax = 0; ax < nax; ax++) {
    if (kind[ax] == AXIS_SPEED) kmh = v[ax];
    if (kind[ax] == AXIS_CONICITY) lam = v[ax];
  }
  rr_error e;
  if (rr_objective_at(obj, kmh, lam, out, n, &e))
    return cli_bad("sweep: a speed or conicity axis needs an objective at an operating point: %s",
                   e.msg);
  return 0;
}

static double axis_value(const sweep_args *a, int ax, int i)
{
  return a->n[ax] == 1 ? a->from[ax] : a->from[ax] + (a->to[ax] - a->from[ax]) * i / (a->n[ax] - 1);
}

static int sweep_cb(int opt, const char *arg, void *u)
{
  sweep_args *a = u;
  if (opt == OPT_SX) return parse_axis("x", arg, a, 0);
  if (opt == OPT_SY) return parse_axis("y", arg, a, 1);
  if (opt == OPT_OBJ) {
    a->objective = arg;
    return 0;
  }
  if (opt == OPT_OLIMIT) return cli_limit(arg, &a->limit) ? 1 : 0;
  return 1;
}

/* One grid point: the design over the key axes (rebuilt when the objective
   changes with a speed or conicity axis), the value and its mode. */
typedef struct sweep_run {
  const sweep_args *a;
  const cli_common *c;
  int nax, nkeys, key_of[2], op_axes, has_freq, damp_axis;
  int has_bound;   /* a critical speed: a value at the range's end is flagged */
  int has_edge;    /* an index: the band edge of each point */
  int has_verdict; /* a lateral ride objective: the verdict at each point */
  const char *keys[2];
  rr_design *d;
  char obj[160];
} sweep_run;

/* A point's value and the frequency of the mode behind it. */
typedef struct sweep_val {
  double f, freq_hz;
  double at_bound; /* 1: f is the critical speed range's end (stable to it), not a result */
  double fmax_hz;  /* an index's band edge */
  double stable;   /* a ride objective's verdict: 1, 0, or NaN not taken */
} sweep_val;

static double verdict_value(int v) { return v < 0 ? NAN : (double)v; }

static int sweep_point(sweep_run *r, const double *v, sweep_val *out, rr_error *e)
{
  double x[2];
  for (int ax = 0, k = 0; ax < r->nax; ax++)
    if (r->a->kind[ax] == AXIS_KEY) x[k++] = v[ax];
  if (r->op_axes || !r->d) {
    char obj[160];
    const char *text = r->a->objective;
    if (r->op_axes) {
      if (objective_at(r->a->objective, v, r->a->kind, r->nax, obj, sizeof obj)) return -1;
      text = obj;
    }
    if (!r->d || strcmp(text, r->obj)) {
      rr_design_free(r->d);
      r->d = NULL;
      const char *objs[1] = {text};
      snprintf(r->obj, sizeof r->obj, "%s", text);
      int st = rr_design_new(&r->c->veh, r->nkeys, r->keys, 1, objs, &r->d, e);
      if (!st) st = rr_design_set_modal_opts(r->d, &r->c->mo, e);
      if (st) return cli_fail(e, st);
    }
  }
  int st = rr_design_evaluate(r->d, x, &out->f, e);
  if (st == RR_EUNDEF) { /* an undefined index: an empty cell, the sweep goes on */
    out->f = out->freq_hz = NAN;
    out->at_bound = 0;
    out->fmax_hz = rr_design_band_edge(r->d, 0);
    out->stable = verdict_value(rr_design_verdict(r->d, 0));
    return 0;
  }
  if (st) return cli_fail(e, st);
  out->freq_hz = rr_design_mode_freq(r->d, 0);
  out->at_bound = rr_design_at_bound(r->d, 0);
  out->fmax_hz = rr_design_band_edge(r->d, 0);
  out->stable = verdict_value(rr_design_verdict(r->d, 0));
  return 0;
}

static void sweep_row(const sweep_run *r, const double *v, const sweep_val *p)
{
  for (int ax = 0; ax < r->nax; ax++) printf("%.10g,", v[ax]);
  cli_csv_num(stdout, p->f, r->has_freq || r->has_verdict ? ',' : '\n');
  if (r->has_verdict) cli_csv_num(stdout, p->stable, '\n');
  char tail = r->has_bound || r->has_edge ? ',' : '\n';
  if (r->has_freq) cli_csv_num(stdout, p->freq_hz, r->damp_axis >= 0 ? ',' : tail);
  if (r->has_freq && r->damp_axis >= 0)
    cli_csv_num(stdout, v[r->damp_axis] * 2 * RR_PI * p->freq_hz, tail);
  if (r->has_bound) printf("%d\n", p->at_bound != 0);
  if (r->has_edge) cli_csv_num(stdout, p->fmax_hz, '\n');
}

/* Grid points lo..hi-1 (row-major over --x, --y). */
static int sweep_points(void *user, long lo, long hi, void *out)
{
  sweep_run *r = user;
  rr_error e;
  for (long k = lo; k < hi; k++) {
    double v[2] = {axis_value(r->a, 0, (int)(k / r->a->n[1])),
                   axis_value(r->a, 1, (int)(k % r->a->n[1]))};
    int st = sweep_point(r, v, (sweep_val *)out + (k - lo), &e);
    if (st) return st;
  }
  return 0;
}

/* The CSV header: the axes (with units), the objective, the mode's frequency
   and k_opt when they are added. */
static void sweep_header(const sweep_run *run)
{
  const sweep_args *a = run->a;
  for (int ax = 0; ax < run->nax; ax++) {
    if (a->kind[ax] == AXIS_KEY)
      cli_csv_key_field(stdout, a->key[ax], ',');
    else
      cli_csv_field(stdout, a->kind[ax] == AXIS_SPEED ? "speed_kmh" : a->key[ax], ',');
  }
  cli_csv_field(stdout, a->objective, run->has_freq || run->has_verdict ? ',' : '\n');
  if (run->has_verdict) printf("stable\n");
  if (run->has_freq)
    printf("mode_freq_hz%s%s\n", run->damp_axis >= 0 ? ",k_opt_n_per_m" : "",
           run->has_bound  ? ",at_range_end"
           : run->has_edge ? ",fmax_hz"
                           : "");
}

/* The grid's points (over MPI ranks under mpirun), then its rows: those done
   when the run was stopped. */
static int sweep_grid(sweep_run *run)
{
  const sweep_args *a = run->a;
  long npts = (long)a->n[0] * a->n[1];
  sweep_val *vals = malloc(sizeof *vals * (size_t)npts);
  unsigned char *done = calloc((size_t)npts, 1);
  if (!vals || !done) {
    free(vals);
    free(done);
    return cli_bad("out of memory");
  }
  cli_progress pr;
  cli_progress_start(&pr, "sweep", npts, run->c->progress);
  cli_catch_stops();
  int r = cli_par_for(npts, 1, sizeof *vals, sweep_points, run, vals, done, &pr);
  cli_progress_end(&pr);
  rr_design_free(run->d);
  for (long k = 0; k < npts && !r; k++) {
    double v[2] = {axis_value(a, 0, (int)(k / a->n[1])), axis_value(a, 1, (int)(k % a->n[1]))};
    if (done[k]) sweep_row(run, v, &vals[k]);
  }
  free(vals);
  free(done);
  return r ? r : cli_stopped() ? CLI_EXIT_STOPPED : 0;
}

int cmd_sweep(int argc, char **argv)
{
  static const char help[] =
      "usage: railride sweep [VEHICLE] --x AXIS=FROM:TO:N [--y AXIS=FROM:TO:N] --objective "
      "NAME[@ARGS]\n"
      "Any objective (as in problem files: index@KMH,L, zeta_low, sperling@KMH,L[,X], "
      "critical_speed@L, ...)\n"
      "over one or two axes, CSV: x[, y], objective. An axis is a vehicle-file key (section.key), "
      "or\n"
      "speed (km/h) or conicity, which then set the objective's operating point (index, sperling,\n"
      "sperling_gb, wd_rms, rms; e.g. --x conicity=0.05:0.4:8 --objective index@350). For index@\n"
      "objectives the frequency of the mode that sets the index is added, and when one axis is\n"
      "yaw_damper.damping the optimal-dissipation stiffness k_opt = c 2 pi f of that mode\n"
      "(paper Fig. 10). Values with units are accepted: --x \"yaw_damper.damping=100 kN.s/m:4000 "
      "kN.s/m:20\".\n" CLI_COMMON_HELP;
  static const cli_opt extra[] = {
      {"x", OPT_SX, "AXIS=FROM:TO:N",
       "the first axis: section.key, speed or conicity, and its grid"},
      {"y", OPT_SY, "AXIS=FROM:TO:N", "the second axis (optional)"},
      {"objective", OPT_OBJ, "NAME[@ARGS]", "the objective (railride objectives lists them)"},
      {"limit", OPT_OLIMIT, "N", "most grid points accepted (default " RR_STR(CLI_LIMIT_GRID) ")"},
      CLI_OPT_END};
  cli_common c;
  sweep_args a = {.limit = CLI_LIMIT_GRID};
  int r = cli_parse(argc, argv, &c, CLI_READS_INDEX | CLI_READS_GRAVITY | CLI_READS_PROGRESS, extra,
                    sweep_cb, &a, help);
  if (r == CLI_HELP_SHOWN) return 0;
  if (r) return r;
  if (!a.have[0] || !a.objective) return cli_bad("sweep: --x and --objective are required");
  if (a.have[1] && a.kind[0] == a.kind[1] && a.kind[0] != AXIS_KEY)
    return cli_bad("sweep: --x and --y are the same quantity");
  sweep_run run = {.a = &a, .c = &c, .nax = a.have[1] ? 2 : 1, .damp_axis = -1};
  if (!a.have[1]) a.n[1] = 1;
  if (cli_over_limit("sweep", (double)a.n[0] * a.n[1], a.limit, "points")) return EXIT_BADINPUT;
  for (int ax = 0; ax < run.nax; ax++) {
    if (a.kind[ax] == AXIS_KEY)
      run.keys[run.nkeys++] = a.key[ax];
    else
      run.op_axes = 1;
    if (!strcmp(a.key[ax], "yaw_damper.damping")) run.damp_axis = ax;
  }
  /* the mode behind the value: its frequency, and on a yaw-damping axis the
     optimal-dissipation stiffness k = c 2 pi f of that mode (paper Fig. 10) */
  run.has_freq = !strncmp(a.objective, "index", 5) || !strncmp(a.objective, "critical_speed@", 15);
  run.has_bound = !strncmp(a.objective, "critical_speed@", 15);
  run.has_edge = !strncmp(a.objective, "index", 5);
  static const char *const rides[] = {"sperling@", "sperling_gb@", "wd_rms@", "rms@", "n_mv@"};
  for (int i = 0; i < 5; i++) run.has_verdict |= !strncmp(a.objective, rides[i], strlen(rides[i]));
  if (run.op_axes) { /* the objective checked before any output */
    char probe[160];
    double v0[2] = {a.from[0], a.from[1]};
    if ((r = objective_at(a.objective, v0, a.kind, run.nax, probe, sizeof probe))) return r;
  }
  sweep_header(&run);
  return sweep_grid(&run);
}
