/* Vehicle files and units: the shipped examples equal the built-ins, base
 * inheritance, and every kind of bad input names file, line and key. */
#define _POSIX_C_SOURCE 200809L
#include <sys/stat.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "railride/railride.h"

#define write_file check_write_file

static void test_units(void)
{
  rr_units *u;
  rr_error e;
  CHECK_OK(rr_units_new(&u, &e), e);
  double x;
  struct {
    const char *text, *unit;
    double want;
  } ok[] = {
      {"50 kN/mm", "N/m", 50e6},
      {"4000 kN.s/m", "N.s/m", 4e6},
      {"1.67e6 kg.m2", "kg.m2", 1.67e6},
      {"350 km/h", "m/s", 350 / 3.6},
      {"4.15 MN.m/rad", "N.m/rad", 4.15e6},
      {"1.5 Hz", "Hz", 1.5},
      {"  12.5  ", "m", 12.5},
      {"2.2 m", "m", 2.2},
      {"97 m/s", "km/h", 97 * 3.6},
      {"10 MN/m", "N/m", 1e7},
      /* engineers' run-together spellings */
      {"50 kNs/m", "N.s/m", 5e4},
      {"10 Ns/m", "N.s/m", 10},
      {"1.67e6 kgm^2", "kg.m2", 1.67e6},
      {"4.15 MNm/rad", "N.m/rad", 4.15e6},
      {"3 kNm/rad", "N.m/rad", 3e3},
      {"20 kgm2", "kg.m2", 20},
  };
  for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
    int st = rr_units_parse(u, ok[i].text, ok[i].unit, 0, &x, "v", &e);
    CHECK_OK(st, e);
    CHECK_CLOSE(x, ok[i].want, 1e-12, 0, ok[i].text);
  }
  CHECK(rr_units_parse(u, "5 kg", "N/m", 0, &x, "k", &e) == RR_EUNIT, "wrong dimension accepted");
  CHECK(strstr(e.msg, "kg") != NULL, "message names the unit: %s", e.msg);
  CHECK(rr_units_parse(u, "5 kNm/m", "N.s/m", 0, &x, "k", &e) == RR_EUNIT &&
            strstr(e.msg, "'kNm/m'"),
        "a run-together spelling of the wrong dimension, named as written: %s", e.msg);
  CHECK(rr_units_parse(u, "5 furlongz", "m", 0, &x, "k", &e) == RR_EUNIT, "unknown unit accepted");
  CHECK(rr_units_parse(u, "nan", "m", 0, &x, "k", &e) == RR_EINVAL, "NaN accepted");
  CHECK(rr_units_parse(u, "inf", "m", 0, &x, "k", &e) == RR_EINVAL, "inf accepted");
  CHECK(rr_units_parse(u, "inf", "N/m", 1, &x, "k", &e) == RR_OK && isinf(x),
        "inf refused where allowed");
  CHECK(rr_units_parse(u, "abc", "m", 0, &x, "k", &e) == RR_EINVAL, "text accepted");
  CHECK(rr_units_parse(u, "", "m", 0, &x, "k", &e) == RR_EINVAL, "empty accepted");
  rr_units_free(u);
  /* without a context, bare numbers need no database */
  CHECK(rr_units_parse(NULL, "3", "m", 0, &x, "k", &e) == RR_OK && x == 3,
        "bare number without context");
  CHECK(rr_units_parse(NULL, "3 mm", "m", 0, &x, "k", &e) == RR_OK && fabs(x - 3e-3) < 1e-15,
        "unit without context");
}

static int same_vehicle(const rr_vehicle *a, const rr_vehicle *b)
{
  int n;
  const rr_vehicle_key *k = rr_vehicle_keys(&n);
  rr_vehicle x = *a, y = *b;
  for (int i = 0; i < n; i++) {
    double *p = rr_vehicle_field(&x, &k[i]), *q = rr_vehicle_field(&y, &k[i]);
    if (p && fabs(*p - *q) > 1e-12 * fabs(*q)) {
      fprintf(stderr, "  differs: [%s] %s %.17g vs %.17g\n", k[i].section, k[i].key, *p, *q);
      return 0;
    }
  }
  return a->sdf_mode == b->sdf_mode && a->gravity_stiffness == b->gravity_stiffness &&
         a->sdf.kind == b->sdf.kind;
}

static void test_examples(void)
{
  rr_vehicle f, bi;
  rr_error e;
  const char *src = getenv("RR_SOURCE_DIR");
  char path[512];
  const char *names[2] = {"type1", "type2"};
  for (int i = 0; i < 2; i++) {
    snprintf(path, sizeof path, "%s/examples/%s.ini", src ? src : "..", names[i]);
    int st = rr_vehicle_load(path, &f, &e);
    CHECK_OK(st, e);
    rr_vehicle_builtin(names[i], &bi, &e);
    CHECK(!st && same_vehicle(&f, &bi), "%s.ini differs from the built-in", names[i]);
  }
  rr_vehicle_builtin("type2", &bi, &e);
  CHECK(bi.lateral_damping == 15e3 && bi.yaw_damping == 660e3 && bi.sdf.k3 == 2e6 &&
            bi.sdf.k2 == 10e6,
        "type2 values");
  snprintf(path, sizeof path, "%s/examples/type2-sdf-physical.ini", src ? src : "..");
  memset(&f, 0,
         sizeof f); /* a failed load leaves f as it was: checks below then fail, not read garbage */
  CHECK_OK(rr_vehicle_load(path, &f, &e), e);
  CHECK(f.sdf_mode == RR_SDF_PHYSICAL && f.sdf.kind == RR_CURVE_SLS && f.sdf.k3 == 2e6,
        "inherited curve");
  snprintf(path, sizeof path, "%s/examples/type2-sdf-table.ini", src ? src : "..");
  memset(&f, 0, sizeof f);
  CHECK_OK(rr_vehicle_load(path, &f, &e), e);
  CHECK(f.sdf.kind == RR_CURVE_TABLE && f.sdf.n == 6 && f.sdf.has_loss, "table curve");
  CHECK_CLOSE(rr_sdf_storage(&f.sdf, sqrt(1.0 * 1.5)), 0.5 * (4.8e6 + 7.0e6), 1e-12, 0,
              "log-f interpolation midpoint");
  CHECK(rr_sdf_storage(&f.sdf, 0.01) == 2.0e6 && rr_sdf_storage(&f.sdf, 100) == 11.8e6,
        "held constant outside");
}

/* Expects status st and a message containing every needle. */
static void expect_error(const char *text, int st, const char *n1, const char *n2, const char *n3)
{
  const char *p = write_file("bad.ini", text);
  rr_vehicle v;
  rr_error e = {0, ""};
  int got = rr_vehicle_load(p, &v, &e);
  CHECK(got == st, "status %d (want %d) for: %s -> %s", got, st, text, e.msg);
  const char *needles[3] = {n1, n2, n3};
  for (int i = 0; i < 3; i++)
    if (needles[i])
      CHECK(strstr(e.msg, needles[i]) != NULL, "message '%s' lacks '%s'", e.msg, needles[i]);
  CHECK(strchr(e.msg, '\n') == NULL, "message is one line: %s", e.msg);
}

static void BAD_FILE(const char *text, int st, const char *a, const char *b)
{
  expect_error(text, st, a, b, NULL);
}

static const char *check_dir_path(const char *name)
{
  static char path[512];
  snprintf(path, sizeof path, "%s/%s", check_dir, name);
  return path;
}

static void test_errors(void)
{
  const char *B = "[vehicle]\nbase = type1\n";
  char buf[1024];
#define BAD(extra, st, a, b, c)                                                                    \
  do {                                                                                             \
    snprintf(buf, sizeof buf, "%s%s", B, extra);                                                   \
    expect_error(buf, st, a, b, c);                                                                \
  } while (0)
  BAD("[primary]\nlateral_stifness = 5 kN/mm\n", RR_EPARSE, "bad.ini:4:", "lateral_stifness",
      "unknown key");
  BAD("[bogie]\nmass = 5\n", RR_EPARSE, "bad.ini:4:", "[bogie]", "unknown section");
  BAD("[primary]\nlateral_stiffness = 5 kg\n", RR_EUNIT, "bad.ini:4:", "lateral_stiffness", "kg");
  BAD("[carbody]\nmass = nan\n", RR_EINVAL, "bad.ini:4:", "mass", "NaN");
  BAD("[carbody]\n\nmass = -5 kg\n", RR_EINVAL, "bad.ini:5:", "mass",
      "physical range 1000 .. 1e+06 kg");
  BAD("[primary]\nvertical_damping = -1\n", RR_EINVAL, "bad.ini:4:", "vertical_damping",
      "physical range 0 ..");
  BAD("[yaw_damper]\nseries_stiffness = 0\n", RR_EINVAL, "bad.ini:4:", "series_stiffness",
      "(or inf)");
  BAD("[wheelset]\nrolling_radius = 0.46 x\n", RR_EUNIT, "bad.ini:4:", "rolling_radius", NULL);
  BAD("[wheelset]\nrolling_radius = abc\n", RR_EINVAL, "bad.ini:4:", "rolling_radius",
      "not a number");
  BAD("[carbody]\nmass = 40 t\nmass = 41 t\n", RR_EPARSE, "bad.ini:5:", "mass", "twice");
  BAD("[yaw_damper]\nsdf = maybe\n", RR_EINVAL, "bad.ini:4:", "sdf", NULL);
  BAD("[yaw_damper]\nsdf_k1 = 2 Hz\n", RR_EPARSE, "bad.ini", "sdf_k2", "together");
  BAD("[yaw_damper]\nsdf_table = nowhere.csv\n", RR_EIO, "bad.ini:4:", "sdf_table", "nowhere.csv");
  BAD("[contact]\ngravity_stiffness = perhaps\n", RR_EINVAL, "bad.ini:4:", "gravity_stiffness",
      NULL);
  BAD("[carbody\nmass = 1\n", RR_EPARSE, "bad.ini:3:", "malformed", NULL);
  BAD("just words\n", RR_EPARSE, "bad.ini:3:", "malformed", NULL);
  expect_error("[carbody]\nmass = 40 t\n", RR_EPARSE, "bad.ini", "missing required key",
               "roll_inertia");
  expect_error("[vehicle]\nbase = bad.ini\n", RR_EPARSE, "bad.ini", "base chain", NULL);
  expect_error("[vehicle]\nbase = nosuchbase.ini\n", RR_EIO, "bad.ini:2: [vehicle] base",
               "nosuchbase.ini", NULL);
  /* unit expressions udunits would evaluate, reciprocals, offsets, logarithms */
  BAD("[carbody]\ncg_height = 1.6.2 m\n", RR_EINVAL, "bad.ini:4:", "cg_height", NULL);
  BAD("[carbody]\nmass = 2 3 kg\n", RR_EUNIT, "bad.ini:4:", "mass", NULL);
  BAD("[carbody]\nmass = 38936 kg 2\n", RR_EUNIT, "bad.ini:4:", "mass", NULL);
  BAD("[carbody]\ncg_height = 1.62 m @ 100\n", RR_EUNIT, "bad.ini:4:", "cg_height", NULL);
  BAD("[carbody]\nmass = 1 kg since 2000\n", RR_EUNIT, "bad.ini:4:", "mass", NULL);
  BAD("[carbody]\nmass = 1 kg SINCE 2000\n", RR_EUNIT, "bad.ini:4:", "mass", NULL);
  /* division by the word (not the grammar's '/'), and the spelling whose
     parse leaks inside udunits */
  BAD("[primary]\nlateral_stiffness = 5 kN per mm\n", RR_EUNIT, "bad.ini:4:", "lateral_stiffness",
      NULL);
  BAD("[carbody]\ncg_height = 1 m Per0s\n", RR_EUNIT, "bad.ini:4:", "cg_height", NULL);
  BAD("[carbody]\nmass = 4.59 lg(re 1 kg)\n", RR_EUNIT, "bad.ini:4:", "mass", NULL);
  BAD("[primary]\nlateral_stiffness = 2e-8 m/N\n", RR_EUNIT, "bad.ini:4:", "lateral_stiffness",
      "reciprocal");
  BAD("[carbody]\nmass = 2.5e-5 1/kg\n", RR_EUNIT, "bad.ini:4:", "mass", "reciprocal");
  BAD("[yaw_damper]\nsdf_k1 = 0.5 s\nsdf_k2 = 1 MN/m\nsdf_k3 = 1 MN/m\n", RR_EUNIT,
      "bad.ini:4:", "sdf_k1", NULL);
  BAD("[carbody]\nmass = 1e-400\n", RR_EINVAL, "bad.ini:4:", "mass", "out of range");
  BAD("[carbody]\nmass = 1e300\n", RR_EINVAL, "bad.ini:4:", "mass", "physical range");
  BAD("[carbody]\nmass = 4.9e-324\n", RR_EINVAL, "bad.ini:4:", "mass", NULL);
  BAD("[carbody]\nmass = 1,5\n", RR_EINVAL, "bad.ini:4:", "mass", NULL);
  rr_vehicle v;
  rr_error e;
  CHECK(rr_vehicle_load("/nonexistent/x.ini", &v, &e) == RR_EIO &&
            strstr(e.msg, "/nonexistent/x.ini"),
        "missing file: %s", e.msg);
  /* comments of any length are legal; a data line over the limit is refused at its line */
  const char *p;
  static char big[300000];
  int n = snprintf(big, sizeof big, "[vehicle]\nbase = type1\n# ");
  memset(big + n, 'x', 250000);
  snprintf(big + n + 250000, sizeof big - (size_t)n - 250000, "\n[carbody]\nmass = 40 t\n");
  p = write_file("longcomment.ini", big);
  CHECK_OK(rr_vehicle_load(p, &v, &e), e);
  CHECK(v.carbody_mass == 40000, "value after a long comment");
  n = snprintf(big, sizeof big, "[vehicle]\nbase = type1\n[carbody]\nmass = 40 t ");
  memset(big + n, ' ', 300);
  snprintf(big + n + 300, 8, "\n");
  BAD_FILE(big, RR_EPARSE, "bad.ini:4:", "limit of 198");
  /* a NUL byte, a FIFO, a directory */
  p = check_dir_path("nul.ini");
  FILE *fp = fopen(p, "w");
  if (fp) {
    fwrite("[vehicle]\nbase = type1\n[carbody]\nmass = 4\0000 t\n", 1, 46, fp);
    fclose(fp);
  }
  CHECK(rr_vehicle_load(p, &v, &e) == RR_EPARSE && strstr(e.msg, "nul.ini:4:") &&
            strstr(e.msg, "NUL"),
        "NUL byte: %s", e.msg);
  p = check_dir_path("fifo.ini");
  CHECK(mkfifo(p, 0600) == 0, "mkfifo");
  CHECK(rr_vehicle_load(p, &v, &e) == RR_EIO && strstr(e.msg, "not a regular file"), "FIFO: %s",
        e.msg);
  CHECK(rr_vehicle_load(check_dir, &v, &e) == RR_EIO && strstr(e.msg, "directory"), "directory: %s",
        e.msg);
  /* a curve given in a file replaces the inherited one as a whole */
  p = write_file("curve.ini", "[vehicle]\nbase = type1\n[yaw_damper]\nsdf = physical\nsdf_k1 = 2 "
                              "Hz\nsdf_k2 = 1 MN/m\nsdf_k3 = 3 MN/m\n");
  CHECK_OK(rr_vehicle_load(p, &v, &e), e);
  CHECK(v.sdf.k1_hz == 2 && v.sdf.k2 == 1e6 && v.sdf.k3 == 3e6 && v.sdf_mode == RR_SDF_PHYSICAL,
        "curve override");
  /* a chain of bases: file -> file -> built-in */
  write_file("mid.ini", "[vehicle]\nbase = type2\n[carbody]\nmass = 40 t\n");
  p = write_file(
      "top.ini",
      "[vehicle]\nname = top\nbase = mid.ini\n[primary]\nlongitudinal_stiffness = 20 kN/mm\n");
  CHECK_OK(rr_vehicle_load(p, &v, &e), e);
  CHECK(v.carbody_mass == 40000 && v.primary_kx == 20e6 && v.yaw_damping == 660e3 &&
            !strcmp(v.name, "top"),
        "base chain values");
}

/* Angles are not the number 1 here: every key of the table tried with an
   angular frequency, a degree and a revolution rate. A frequency key takes
   rad/s divided by 2 pi and rpm divided by 60; an angular stiffness takes
   kN.m/deg; every other key refuses them all. Speeds take any speed unit. */
static void test_angle_units(void)
{
  int nk;
  const rr_vehicle_key *keys = rr_vehicle_keys(&nk);
  const double pi = 3.14159265358979323846;
  int tried = 0, hz = 0, ang = 0;
  for (int i = 0; i < nk; i++) {
    const rr_vehicle_key *k = &keys[i];
    if (k->flags & RR_KEY_SPECIAL) continue;
    int is_hz = !strcmp(k->si_unit, "Hz"), is_ang = !strcmp(k->si_unit, "N.m/rad");
    const struct {
      const char *text;
      double hz, ang; /* the value for a frequency key, an angular stiffness (NaN: refused) */
    } cases[] = {
        {"9.4 rad/s", 9.4 / (2 * pi), NAN},
        {"600 rpm", 10, NAN},
        {"3 deg", NAN, NAN},
        {"1 kN.m/deg", NAN, 1000 * 180 / pi},
        {"2 rev/s", 2, NAN},
        {"1 mrad", NAN, NAN},
        {"5 kN.m/rad", NAN, 5000},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
      double x = 0, want = is_hz ? cases[c].hz : is_ang ? cases[c].ang : NAN;
      rr_error e;
      int st = rr_units_parse(NULL, cases[c].text, k->si_unit, 0, &x, k->key, &e);
      tried++;
      if (isnan(want))
        CHECK(st == RR_EUNIT, "%s.%s = %s: accepted as %g %s", k->section, k->key, cases[c].text, x,
              k->si_unit);
      else
        CHECK(st == RR_OK && fabs(x - want) <= 1e-12 * want, "%s.%s = %s: %g, expected %g (%s)",
              k->section, k->key, cases[c].text, x, want, st ? e.msg : "ok");
    }
    hz += is_hz;
    ang += is_ang;
  }
  CHECK(hz >= 1 && ang >= 1 && tried > 100, "the key table: %d frequency, %d angular keys", hz,
        ang);
  const struct {
    const char *text;
    double kmh;
  } speeds[] = {{"350 km/h", 350},
                {"350 mph", 350 * 1.609344},
                {"97.2 m/s", 349.92},
                {"100 kph", 100},
                {"200 knot", 200 * 1.852}};
  for (size_t c = 0; c < sizeof speeds / sizeof speeds[0]; c++) {
    double x = 0;
    rr_error e;
    int st = rr_units_parse(NULL, speeds[c].text, "km/h", 0, &x, "speed", &e);
    CHECK(st == RR_OK && fabs(x - speeds[c].kmh) <= 1e-9 * speeds[c].kmh, "speed %s: %g km/h (%s)",
          speeds[c].text, x, st ? e.msg : "ok");
  }
  /* table headers: units honoured, unknown ones refused (never ignored) */
  {
    rr_sdf_curve c;
    rr_profile pr;
    rr_error e2;
    const char *t1 = check_write_file("k1.csv", "f_hz,k_storage_kn_per_mm\n0.1,2\n1,4\n10,8\n");
    CHECK_OK(rr_sdf_table_load(t1, &c, &e2), e2);
    CHECK(c.n == 3 && c.k_storage[1] == 4e6, "an SDF table in kN/mm: %g N/m", c.k_storage[1]);
    const char *t2 = check_write_file(
        "k2.csv", "f_rad_per_s,k_storage\n6.283185307179586,2e6\n62.83185307179586,4e6\n");
    CHECK_OK(rr_sdf_table_load(t2, &c, &e2), e2);
    CHECK(fabs(c.f_hz[0] - 1) < 1e-12 && fabs(c.f_hz[1] - 10) < 1e-12,
          "an SDF table in rad/s: %g Hz", c.f_hz[0]);
    const char *t3 = check_write_file("k3.csv", "f_hz,n_per_mm\n0.1,2000\n1,4000\n");
    CHECK(rr_sdf_table_load(t3, &c, &e2) == RR_EUNIT &&
              strstr(e2.msg, "k3.csv:1: header: column 2"),
          "an SDF header unit not understood: %s", e2.msg);
    const char *t4 = check_write_file("a1.csv", "a_m,conicity\n0,0.3\n0.004,0.2\n");
    CHECK_OK(rr_profile_load(t4, &pr, &e2), e2);
    CHECK(pr.n == 2 && pr.a_mm[1] == 4, "a tread table in m: %g mm", pr.a_mm[1]);
    const char *t5 = check_write_file("a2.csv", "a_inch,conicity\n0,0.3\n1,0.2\n");
    CHECK(rr_profile_load(t5, &pr, &e2) == RR_EUNIT && strstr(e2.msg, "a2.csv:1: header"),
          "a tread header unit not understood: %s", e2.msg);
  }
  /* a factor unit does not scale a dimensional value */
  double x;
  rr_error e;
  CHECK(rr_units_parse(NULL, "50 kN/mm %", "N/m", 0, &x, "k", &e) == RR_EUNIT, "50 kN/mm %%: %g",
        x);
  CHECK(rr_units_parse(NULL, "5 ppm kg", "kg", 0, &x, "m", &e) == RR_EUNIT, "5 ppm kg: %g", x);
}

/* Every key of the table set in one file (the parser keeps a line per key:
   the last keys of the table must not run past its room), and each value
   read back; the vertical model's keys among them. */
static void test_every_key(void)
{
  int nk;
  const rr_vehicle_key *keys = rr_vehicle_keys(&nk);
  rr_vehicle v;
  rr_vehicle_default(&v);
  char text[16384] = "[vehicle]\nbase = type1\n", last[32] = "";
  size_t at = strlen(text);
  for (int i = 0; i < nk; i++) {
    if (keys[i].offset == (size_t)-1) continue;
    const double *x = (const double *)((const char *)&v + keys[i].offset);
    if (strcmp(last, keys[i].section))
      at += (size_t)snprintf(text + at, sizeof text - at, "[%s]\n", keys[i].section);
    snprintf(last, sizeof last, "%s", keys[i].section);
    double val = isnan(*x) ? 0.46 : *x * 1.01 + (*x == 0 ? keys[i].min + 1e-3 : 0);
    if (val > keys[i].max) val = keys[i].max;
    at += (size_t)snprintf(text + at, sizeof text - at, "%s = %.17g\n", keys[i].key, val);
  }
  const char *path = write_file("every.ini", text);
  rr_vehicle got;
  rr_error e;
  int st = rr_vehicle_load(path, &got, &e);
  CHECK(st == RR_OK, "every numeric key in one file: %s", e.msg);
  if (st) return;
  CHECK(got.carbody_bending_frequency == v.carbody_bending_frequency * 1.01 &&
            got.frame_pitch_inertia == v.frame_pitch_inertia * 1.01 &&
            got.wheel_rail.amplitude == v.wheel_rail.amplitude * 1.01,
        "the vertical and the last keys read back");
}

/* A JSON vehicle file: the same keys as INI, each error at its line. */
static void test_json(void)
{
  const char *ini =
      write_file("j.ini", "[vehicle]\nbase = type1\nname = j\n[carbody]\nmass = 40000\n"
                          "pitch_inertia = 2.2e6 kg.m2\n[yaw_damper]\nsdf = paper\n"
                          "[contact]\nconicity_poly = 0.1 0.02\ngravity_stiffness = yes\n");
  rr_vehicle a, b;
  rr_error e;
  CHECK_OK(rr_vehicle_load(ini, &a, &e), e);
  const char *js = write_file(
      "j.json", "{\"base\": \"type1\", \"name\": \"j\",\n"
                " \"carbody\": {\"mass\": 40000, \"pitch_inertia\": \"2.2e6 kg.m2\"},\n"
                " \"yaw_damper\": {\"sdf\": \"paper\"},\n"
                " \"contact\": {\"conicity_poly\": [0.1, 0.02], \"gravity_stiffness\": true}}\n");
  CHECK_OK(rr_vehicle_load(js, &b, &e), e);
  CHECK(a.carbody_mass == b.carbody_mass && a.carbody_pitch_inertia == b.carbody_pitch_inertia &&
            a.sdf_mode == b.sdf_mode && a.gravity_stiffness == b.gravity_stiffness &&
            !strcmp(a.name, b.name) && a.profile.kind == b.profile.kind,
        "a JSON file reads as its INI twin");
  const char *bad = write_file("bad.json", "{\n \"carbody\": {\n  \"mass\": 4}\n}\n");
  CHECK(rr_vehicle_load(bad, &b, &e) == RR_EINVAL && strstr(e.msg, "bad.json:3: [carbody] mass"),
        "a JSON value out of range named at its line: %s", e.msg);
  const char *bad2 = write_file("bad2.json", "{\"carbody\": {\"mass\": [1, \"x\"]}}");
  CHECK(rr_vehicle_load(bad2, &b, &e) == RR_EPARSE, "a list of text refused: %s", e.msg);
  const char *bad3 = write_file("bad3.json", "{\n\"carbody\": {\n");
  CHECK(rr_vehicle_load(bad3, &b, &e) == RR_EPARSE && strstr(e.msg, "malformed JSON"),
        "malformed JSON: %s", e.msg);
  /* a key with a newline (found by the fuzzer): refused, the message one line */
  const char *bad4 = write_file("bad4.json", "{\"car\\nbody\": {\"mass\": 1}}");
  CHECK(rr_vehicle_load(bad4, &b, &e) == RR_EPARSE && !strchr(e.msg, '\n'),
        "a key with a control character: %s", e.msg);
}

int main(void)
{
  if (check_tmpdir("vf")) return 1;
  test_json();
  test_every_key();
  test_angle_units();
  test_units();
  test_examples();
  test_errors();
  check_cleanup();
  return check_done("vehicle_file");
}
