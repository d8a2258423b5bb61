#!/usr/bin/env bash
# The installed tree, as another program sees it: `cmake --install` into a
# temporary prefix, then a downstream C program built by pkg-config and by
# find_package(railride), a C++ program on the same headers, the installed
# CLI run from elsewhere (RPATH, spectra found relative to the library),
# the whole tree moved (relocatable), and internal symbols hidden.
set -u
BUILD=${RR_BUILD_DIR:?RR_BUILD_DIR must name the build tree}
FLAGS=${RR_DOWNSTREAM_FLAGS:-}   # e.g. the sanitizers' runtime when the library was built with them
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
unset RAILRIDE_SPECTRA_DIR

cmake --install "$BUILD" --prefix "$tmp/prefix" > "$tmp/install.log" 2>&1 || { cat "$tmp/install.log"; bad "cmake --install"; }
lib=$(dirname "$(find "$tmp/prefix" -name 'librailride.so' | head -1)")
# every document an installed header cites is installed beside it
missing=""
for d in $(grep -rhoE 'docs/[a-z-]+\.md' "$tmp/prefix/include/railride" | sort -u); do
  [ -s "$tmp/prefix/share/doc/railride/${d#docs/}" ] || missing="$missing $d"
done
[ -z "$missing" ] && ok || bad "the headers cite documents not installed:$missing"
[ -n "$lib" ] && ok || bad "no librailride.so installed"

cat > "$tmp/main.c" <<'C'
#include <stdio.h>
#include <string.h>
#include <railride/railride.h>
#include <railride/version.h>
int main(void)
{
  rr_vehicle v; rr_error e; rr_model *m; rr_modal_ws *ws; rr_spectrum sp; double z;
  if (strcmp(rr_version(), RR_VERSION_STRING)) { printf("version mismatch\n"); return 1; }
  rr_vehicle_default(&v);
  if (rr_model_from_vehicle(&v, &m, &e) || rr_modal_ws_new(m, &ws, &e) ||
      rr_model_set_operating(m, 350 / RR_KMH, 0.17, &e) || rr_modal_stability_index(m, NULL, ws, &z, &e) ||
      rr_spectrum_open("wuhan-guangzhou", &sp, &e)) { printf("%s\n", e.msg); return 1; }
  printf("%.4f %s\n", z, rr_version());
  rr_modal_ws_free(ws); rr_model_free(m);
  return 0;
}
C
# pkg-config
PKG_CONFIG_PATH="$lib/pkgconfig" pkg-config --exists railride && ok || bad "pkg-config finds railride"
cc -std=c11 $FLAGS "$tmp/main.c" $(PKG_CONFIG_PATH="$lib/pkgconfig" pkg-config --cflags --libs railride) -o "$tmp/main_pc" \
  && "$tmp/main_pc" | grep -q '^-0\.[0-9]* ' && ok || bad "downstream C by pkg-config"
# find_package
mkdir -p "$tmp/down"
cp "$tmp/main.c" "$tmp/down/"
cat > "$tmp/down/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.18)
project(down C)
find_package(railride 0.1 REQUIRED)
add_executable(main main.c)
target_link_libraries(main PRIVATE railride::railride)
file(WRITE ${CMAKE_BINARY_DIR}/spectra.txt "${railride_SPECTRA_DIR}")
CM
cmake -S "$tmp/down" -B "$tmp/down/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_C_FLAGS="$FLAGS" > "$tmp/down.log" 2>&1 \
  && cmake --build "$tmp/down/build" >> "$tmp/down.log" 2>&1 && "$tmp/down/build/main" | grep -q '^-0\.[0-9]* ' \
  && ok || { cat "$tmp/down.log"; bad "downstream C by find_package(railride)"; }
[ -f "$(cat "$tmp/down/build/spectra.txt" 2>/dev/null)/wuhan-guangzhou.txt" ] && ok || bad "railride_SPECTRA_DIR"
# C++ on the same headers (the complex API as std::complex<double>)
if command -v c++ > /dev/null; then
  cat > "$tmp/main.cc" <<'CC'
#include <complex>
#include <cstdio>
#include <railride/railride.h>
#include <railride/version.h>
int main()
{
  rr_complex k = rr_maxwell_stiffness(rr_complex(1e7, 0), 1e5, rr_complex(0, 100));
  std::printf("%g %g %s\n", k.real(), k.imag(), rr_version());
  return std::abs(k - rr_complex(1e7, 0) * rr_complex(0, 1e7) / rr_complex(1e7, 1e7)) < 1e-6 ? 0 : 1;
}
CC
  c++ $FLAGS "$tmp/main.cc" $(PKG_CONFIG_PATH="$lib/pkgconfig" pkg-config --cflags --libs railride) -o "$tmp/main_cc" \
    && "$tmp/main_cc" > /dev/null && ok || bad "C++ program on the installed headers"
else
  bad "no C++ compiler (Debian package g++)"
fi
# the installed CLI, from another folder, and after moving the whole tree
(cd "$tmp" && "$tmp/prefix/bin/railride" --version | grep -q "^railride [0-9]") && ok || bad "installed railride --version"
(cd "$tmp" && "$tmp/prefix/bin/railride" ride --speed 300 --conicity 0.2 --json > "$tmp/ride.json") && ok || bad "installed railride ride (spectra)"
# examples/ride.c, the library's ride workflow as a user writes it, against the
# installed tree: its numbers are the installed CLI's (both print the same doubles)
src=$(cd "$(dirname "$0")/.." && pwd)
cc -std=c11 -Wall -Werror $FLAGS "$src/examples/ride.c" $(PKG_CONFIG_PATH="$lib/pkgconfig" pkg-config --cflags --libs railride) \
  -o "$tmp/ride_example" && (cd "$tmp" && ./ride_example > "$tmp/ride_example.csv") && ok || bad "examples/ride.c builds and runs"
if command -v python3 > /dev/null; then
  python3 - "$tmp/ride_example.csv" "$tmp/ride.json" <<'PY' && ok || bad "examples/ride.c agrees with railride ride"
import csv, json, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["speed_kmh"] == "300"]
pts = json.load(open(sys.argv[2]))["results"][0]["points"]
assert len(rows) == len(pts) == 3, (rows, pts)
for r, p in zip(rows, pts):
    for k in ("sperling", "sperling_gb"):
        assert abs(float(r[k]) - p[k]) <= 5e-7, (k, r[k], p[k])
PY
fi
# examples/stability.c, the index as an optimiser's loop computes it: each row's index is
# the installed CLI's (modes --json) to 1e-10 (the batch runs another QR path: ~1e-12 apart)
cc -std=c11 -Wall -Werror $FLAGS "$src/examples/stability.c" $(PKG_CONFIG_PATH="$lib/pkgconfig" pkg-config --cflags --libs railride) \
  -o "$tmp/stability_example" && (cd "$tmp" && ./stability_example > "$tmp/stability_example.csv") && ok || bad "examples/stability.c builds and runs"
if command -v python3 > /dev/null; then
  python3 - "$tmp/stability_example.csv" "$tmp/prefix/bin/railride" <<'PY' && ok || bad "examples/stability.c agrees with railride modes"
import csv, json, subprocess, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 5, rows
for r in rows:
    out = subprocess.run([sys.argv[2], "modes", "--speed", r["speed_kmh"], "--conicity", r["conicity"], "--json"],
                         capture_output=True, text=True, check=True).stdout
    d = json.loads(out)
    assert abs(float(r["stability_index"]) - d["stability_index"]) <= 1e-10, (r, d["stability_index"])
    assert abs(float(r["zeta_max"]) - d["zeta_max"]) <= 1e-10, (r, d["zeta_max"])
PY
fi
mv "$tmp/prefix" "$tmp/moved"
(cd / && "$tmp/moved/bin/railride" ride --speed 300 --conicity 0.2 --json > "$tmp/ride2.json") && cmp -s "$tmp/ride.json" "$tmp/ride2.json" \
  && ok || bad "relocated tree: the CLI finds its library and spectra"
# only the public API is exported
mlib=$(find "$tmp/moved" -name 'librailride.so' | head -1)
if nm -D --defined-only "$mlib" | awk '{print $3}' | grep -qE '^(rr_seterr|rr_orbit_branch|rr_lines_open|rr_hqr)$'; then
  bad "internal symbols exported"
else ok; fi
nm -D --defined-only "$mlib" | awk '{print $3}' | grep -q '^rr_bifurcation_continue$' && ok || bad "public symbol missing"

echo "install: $pass passed, $fail failed"
[ $fail -eq 0 ]
