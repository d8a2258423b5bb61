/* Writes src/ride/frf_codelets.c: the sparse FRF's form, factorisation and
 * solves as straight-line code (codelets, as FFTW's genfft writes them) for
 * the factorisation structures of the built-in vehicles (type1, type2; every
 * SDF treatment, with and without gravitational stiffness and roll gravity).
 * A codelet does the interpreter's operations (frf_sparse.c: form, factor,
 * solve) in the same order on the same values, so its results are the
 * interpreter's bits; what it drops is the index lists' loads, the loops,
 * the fill's formation and the values no output needs. A structure with no
 * codelet (a vehicle file with another topology or a zero element) runs on
 * the interpreter.
 *
 *   build/tests/frf_codelets_gen > src/ride/frf_codelets.c
 *
 * test_frf_codelets fails while the committed file is not this program's
 * output. It links the library, and so the committed file: should that not
 * compile, an empty table bootstraps it,
 *   const rr_frf_codelet rr_frf_codelets[] = {{0}}; const int rr_frf_ncodelets = 0; */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "railride/railride.h"
#include "model/model_impl.h"
#include "ride/frf_sparse.h"
#include "util/block.h"

#define SIG_CAP RR_FRF_SIG_CAP(RR_SYS_MAX_DOF)

typedef struct codelet {
  int sig[SIG_CAP], nsig, kmin;
  char what[160];
} codelet;

static void die(const char *what)
{
  fprintf(stderr, "frf_codelets_gen: %s\n", what);
  exit(1);
}

/* ---- emission ---- */

/* The code is written in the order the values are needed, so that few are
   live at once (GCC keeps source order on x86): an entry of D is formed
   where the elimination first touches it, a right-hand side where the
   forward substitution first reads it, and the forward substitution's step
   k follows the factorisation's step k (it needs L's column k alone). */
typedef struct emitter {
  const rr_frf_sparse *s;
  const rr_frf_prog *g;
  int kmin, sum, ne;
  unsigned char entry[RR_SYS_MAX_DOF * RR_SYS_MAX_DOF]; /* formed yet */
  unsigned char y[RR_SYS_MAX_DOF][RR_SYS_MAX_INPUTS];   /* right-hand side set yet */
} emitter;

/* Entry c formed as the interpreter's form() has it: K - w^2 M + jw C (zero
   for fill), then each Maxwell element's term in the elements' order. */
static void entry(emitter *em, int c)
{
  const rr_frf_prog *g = em->g;
  if (em->entry[c]) return;
  em->entry[c] = 1;
  if (g->formed[c])
    printf("  vd r%d = k0[%d] + w2 * m0[%d], i%d = w * c0[%d];\n", c, c, c, c, c);
  else
    printf("  vd r%d = z, i%d = z;\n", c, c);
  for (int e = 0, t = 0; e < em->s->ds->nmx; e++)
    for (int a = 0; a < em->s->ds->mx[e].nz * em->s->ds->mx[e].nz; a++, t++)
      if (g->cmx[t] == c)
        printf("  r%d = r%d + ker%d * jj[%d];\n  i%d = i%d + kei%d * jj[%d];\n", c, c, e, t, c, c,
               e, t);
}

/* The inputs step k's forward substitution carries (bits): every input
   reaching row k, or bit 0 for the lagged sum. */
static unsigned active(const emitter *em, int k)
{
  return em->sum ? em->g->act[k] != 0 : em->g->act[k];
}

/* Right-hand side i's row k as the interpreter's rhs_init sets it. */
static void rhs(emitter *em, int k, int i)
{
  int ni = em->s->ni;
  if (em->y[k][i]) return;
  em->y[k][i] = 1;
  if (!em->sum) {
    printf("  vd y%d_%dr = z + rhs[%d], y%d_%di = z;\n", k, i, k * ni + i, k, i);
    return;
  }
  printf("  vd y%d_0r = z, y%d_0i = z;\n", k, k);
  for (unsigned a = em->g->in0[k]; a; a &= a - 1) {
    int e = __builtin_ctz(a);
    printf("  y%d_0r = y%d_0r + rhs[%d] * VLOAD(s->gr + %d);\n", k, k, k * ni + e,
           e * RR_FRF_LANES);
    printf("  y%d_0i = y%d_0i + rhs[%d] * VLOAD(s->gi + %d);\n", k, k, k * ni + e,
           e * RR_FRF_LANES);
  }
}

/* Whether right-hand side i's row k is read: by the forward substitution
   (it reaches row k, which has entries below its pivot) or the back
   substitution (k >= kmin). */
static int read_y(const emitter *em, int k, int i)
{
  const rr_frf_prog *g = em->g;
  return k >= em->kmin || ((active(em, k) >> i & 1) && g->ls[k] < g->ls[k + 1]);
}

/* Factorisation step k: the multipliers of L's column k, the updates. */
static void factor_step(emitter *em, int k)
{
  const rr_frf_prog *g = em->g;
  int p = g->piv[k], n = em->s->n;
  entry(em, p);
  printf("  /* step %d */\n", k);
  printf("  inv = 1 / (r%d * r%d + i%d * i%d), lim = G * (VABS(r%d) + VABS(i%d));\n", p, p, p, p, p,
         p);
  printf("  ir = r%d * inv, ii = -i%d * inv;\n", p, p);
  for (int c = g->us[k]; c < g->us[k + 1]; c++) entry(em, g->uc[c]);
  for (int q = g->ls[k]; q < g->ls[k + 1]; q++) {
    int a = g->lc[q];
    entry(em, a);
    /* a sum, not |=: GCC 12 lowers an OR of AVX-512 compares to scalars */
    printf("  bad += ~(VABS(r%d) + VABS(i%d) <= lim);\n", a, a);
    printf("  lr = CMUL_RE(r%d, i%d, ir, ii), li = CMUL_IM(r%d, i%d, ir, ii);\n", a, a, a, a);
    printf("  r%d = lr, i%d = li;\n", a, a);
    for (int c = g->us[k]; c < g->us[k + 1]; c++) {
      int u = g->uc[c], d = g->cidx[g->lrow[q] * n + g->ucol[c]];
      entry(em, d);
      printf("  r%d = CMAC_RE(r%d, lr, li, r%d, i%d);\n", d, d, u, u);
      printf("  i%d = CMAC_IM(i%d, lr, li, r%d, i%d);\n", d, d, u, u);
    }
  }
}

/* Forward substitution step k: L's column k applied to the rows below. */
static void forward_step(emitter *em, int k)
{
  const rr_frf_prog *g = em->g;
  for (int q = g->ls[k]; q < g->ls[k + 1]; q++)
    for (int i = 0; i < em->ne; i++) {
      int a = g->lc[q], r = g->lrow[q];
      if (!(active(em, k) >> i & 1) || !read_y(em, r, i)) continue;
      rhs(em, k, i);
      rhs(em, r, i);
      printf("  y%d_%dr = CMAC_RE(y%d_%dr, r%d, i%d, y%d_%dr, y%d_%di);\n", r, i, r, i, a, a, k, i,
             k, i);
      printf("  y%d_%di = CMAC_IM(y%d_%di, r%d, i%d, y%d_%dr, y%d_%di);\n", r, i, r, i, a, a, k, i,
             k, i);
    }
}

/* Back substitution of the unknowns k >= kmin, stored for the outputs. */
static void back(emitter *em)
{
  const rr_frf_prog *g = em->g;
  int n = em->s->n, ne = em->ne;
  for (int k = n - 1; k >= em->kmin; k--) {
    int p = g->piv[k];
    entry(em, p);
    printf("  /* unknown %d */\n", k);
    printf("  den = r%d * r%d + i%d * i%d, ir = r%d / den, ii = -i%d / den;\n", p, p, p, p, p, p);
    for (int i = 0; i < ne; i++) {
      rhs(em, k, i);
      printf("  vd x%d_%dr, x%d_%di;\n  cr = y%d_%dr, ci = y%d_%di;\n", k, i, k, i, k, i, k, i);
      for (int q = g->us[k]; q < g->us[k + 1]; q++) {
        int u = g->uc[q], j = g->ucol[q];
        entry(em, u);
        printf("  cr = CMAC_RE(cr, r%d, i%d, x%d_%dr, x%d_%di);\n", u, u, j, i, j, i);
        printf("  ci = CMAC_IM(ci, r%d, i%d, x%d_%dr, x%d_%di);\n", u, u, j, i, j, i);
      }
      printf("  x%d_%dr = CMUL_RE(cr, ci, ir, ii), x%d_%di = CMUL_IM(cr, ci, ir, ii);\n", k, i, k,
             i);
      printf("  VSTORE(xr + %d, x%d_%dr);\n  VSTORE(xi + %d, x%d_%di);\n",
             (k * ne + i) * RR_FRF_LANES, k, i, (k * ne + i) * RR_FRF_LANES, k, i);
    }
  }
}

static void emit_run(const rr_frf_sparse *s, const codelet *c, int id, int sum)
{
  static emitter em;
  em = (emitter){.s = s, .g = &s->prog, .kmin = c->kmin, .sum = sum, .ne = sum ? 1 : s->ni};
  printf("\nRR_CLONES_V4 static unsigned run%d_%d(rr_frf_sparse *s, const double *wl)\n{\n", id,
         sum);
  printf("  const rr_frf_prog *g = &s->prog;\n");
  printf("  const double *k0 = g->k0, *c0 = g->c0, *m0 = g->m0, *jj = s->jj, *rhs = s->rhs;\n");
  printf("  double *xr = s->xr, *xi = s->xi;\n");
  printf("  vd w;\n  memcpy(&w, wl, sizeof w);\n");
  printf("  const vd z = {0}, w2 = -(w * w);\n  vl bad = {0};\n");
  printf("  vd inv, lim, ir, ii, lr, li, den, cr, ci;\n");
  for (int e = 0; e < s->ds->nmx; e++)
    printf("  vd ker%d, kei%d;\n  maxwell(s, %d, &w, &ker%d, &kei%d);\n", e, e, e, e, e);
  for (int k = 0; k < s->n; k++) {
    if (s->prog.ls[k] == s->prog.ls[k + 1]) continue; /* nothing below the pivot */
    factor_step(&em, k);
    forward_step(&em, k);
  }
  back(&em);
  printf("  (void)lr, (void)li, (void)inv, (void)lim, (void)den, (void)cr, (void)ci;\n");
  printf("  return rr_frf_lane_bits(&bad);\n}\n");
}

static void emit_codelet(const rr_frf_sparse *s, const codelet *c, int id)
{
  printf("\n/* %s */\nstatic const int sig%d[] = {", c->what, id);
  for (int i = 0; i < c->nsig; i++)
    printf("%s%d", !i ? "\n  " : i % 16 ? ", " : ",\n  ", c->sig[i]);
  printf("};\n");
  emit_run(s, c, id, 0);
  emit_run(s, c, id, 1);
}

/* ---- the structures of the built-in vehicles ---- */

typedef struct config {
  const char *vehicle;
  int sdf, gravity_stiffness, roll_gravity;
} config;

/* The workspace prepared for config c (free *blk after). */
static void prepare(const config *c, rr_frf_sparse *s, rr_block *blk)
{
  rr_vehicle v;
  rr_error e;
  rr_model *m;
  rr_ride_plan *p;
  if (rr_vehicle_builtin(c->vehicle, &v, &e)) die(e.msg);
  v.sdf_mode = c->sdf;
  v.gravity_stiffness = c->gravity_stiffness;
  if (rr_model_from_vehicle(&v, &m, &e)) die(e.msg);
  if (rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e)) die(e.msg);
  rr_ride_opts o = rr_ride_opts_default();
  o.roll_gravity = c->roll_gravity;
  if (rr_ride_plan_new(m, &v, &o, &p, &e)) die(e.msg);
  const double *rows0, *rows = rr_ride_rows(p, &rows0);
  *blk = (rr_block){0};
  int np = rr_ride_npoints(p);
  rr_frf_sparse_layout(s, m->n, m->ni, np, blk);
  if (rr_block_alloc(blk)) die("out of memory");
  rr_frf_sparse_layout(s, m->n, m->ni, np, blk);
  if (!rr_frf_sparse_prepare(s, m, rows, rows0)) die("a built-in vehicle the lanes cannot take");
  rr_ride_plan_free(p);
  rr_model_free(m);
}

/* Configuration c's structure into the table cl (ncl entries so far, at
   most CL_MAX): a new entry, or the lower kmin of the one that has it;
   returns the entries now. */
#define CL_MAX 16
static int add_structure(codelet *cl, config *first, int ncl, const config *c)
{
  rr_frf_sparse s;
  rr_block blk;
  prepare(c, &s, &blk);
  codelet *d = &cl[ncl];
  d->nsig = rr_frf_sparse_signature(&s, d->sig);
  d->kmin = s.kmin;
  int i = 0;
  while (i < ncl &&
         !(cl[i].nsig == d->nsig && !memcmp(cl[i].sig, d->sig, sizeof(int) * (size_t)d->nsig)))
    i++;
  if (i < ncl) {
    if (d->kmin < cl[i].kmin) cl[i].kmin = d->kmin;
  } else {
    if (ncl == CL_MAX) die("more structures than the table holds");
    snprintf(d->what, sizeof d->what, "%d DOFs, %d entries; first %s, sdf mode %d%s%s", s.n,
             s.prog.ncomp, c->vehicle, c->sdf, c->gravity_stiffness ? ", gravity stiffness" : "",
             c->roll_gravity ? ", roll gravity" : "");
    first[ncl++] = *c;
  }
  free(blk.base);
  return ncl;
}

int main(void)
{
  static const char *vehicles[] = {"type1", "type2"};
  static const int sdf[] = {RR_SDF_NONE, RR_SDF_PAPER, RR_SDF_PHYSICAL};
  static codelet cl[CL_MAX];
  config first[CL_MAX];
  int ncl = 0;
  for (int t = 0; t < 2 * 3 * 2 * 2; t++) {
    config c = {vehicles[t / 12], sdf[t / 4 % 3], t / 2 % 2, t % 2};
    ncl = add_structure(cl, first, ncl, &c);
  }
  printf("/* clang-format off */\n"
         "/* Generated by tools/frf_codelets_gen.c (frf_codelets_gen > this file): do not\n"
         " * edit. The sparse FRF's form, factorisation and solves as straight-line code\n"
         " * for the built-in vehicles' structures; the same operations in the same order\n"
         " * as the interpreter in frf_sparse.c, so the same bits. */\n");
  printf(
      "#include <string.h>\n#include \"ride/frf_lanes.h\"\n\n#define G RR_DSOLVER_PIVOT_GROWTH\n");
  for (int i = 0; i < ncl; i++) {
    rr_frf_sparse s;
    rr_block blk;
    prepare(&first[i], &s, &blk);
    emit_codelet(&s, &cl[i], i);
    free(blk.base);
  }
  printf("\nconst rr_frf_codelet rr_frf_codelets[] = {\n");
  for (int i = 0; i < ncl; i++)
    printf("  {sig%d, sizeof sig%d / sizeof *sig%d, %d, {run%d_0, run%d_1}},\n", i, i, i,
           cl[i].kmin, i, i);
  printf("};\nconst int rr_frf_ncodelets = %d;\n", ncl);
  return ferror(stdout) || fflush(stdout) ? 1 : 0;
}
