#!/bin/sh
# Runs the benchmarks on one core and prints the figures side by side with
# numpy/scipy on the same matrices (Debian's python3-numpy, python3-scipy).
set -e
cd "$(dirname "$0")/.."
B=${BUILD:-build}
export OPENBLAS_NUM_THREADS=1
PY=/usr/bin/python3
echo "== railride (C) =="
taskset -c 1 "$B/bench/bench_modal"
echo "== numpy/scipy, same state matrix (default vehicle, 350 km/h, conicity 0.17) =="
"$B/railride" matrices --speed 350 --conicity 0.17 --json | taskset -c 1 $PY bench/numpy_modal.py
echo "== stability index against numpy in alternating pairs (numpy's best: eigvals, one call over a stack for the batch and the triple) =="
pairs=$(mktemp)
"$B/railride" matrices --speed 350 --conicity 0.17 --json > "$pairs.json"
for i in 1 2 3 4 5 6; do
  a=$(taskset -c 1 $PY bench/numpy_modal.py index < "$pairs.json" | awk '{print $2}' | tr '\n' ' ')
  b=$(taskset -c 1 "$B/bench/bench_modal" index | awk '{print $2}' | tr '\n' ' ')
  # a design's 9 eigen-solves and the rest (one thread), as us a design
  d=$(OMP_NUM_THREADS=1 taskset -c 1 "$B/bench/bench_batch" 2000 | awk '/^designs_per_s_1_thread/ {print 1e6 / $2}')
  echo "$a $b $d"
done > "$pairs"
for c in "1 4 single index" "2 5 8-lane batch, per point" "3 6 robust triple" \
  "3 7 a design of the paper objectives; numpy its 9 eigvals over a stack alone"; do
  set -- $c
  r=$(awk -v x="$1" -v y="$2" '{print $x / $y}' "$pairs" | sort -g | awk '{r[NR] = $1} END {printf "%.1f", (r[3] + r[4]) / 2}')
  shift 2
  echo "index_vs_numpy_median_ratio $r ($*)"
done
echo "  pairs (us: numpy single, batched per matrix, triple; C single, batch per point, triple, a design): $(tr '\n' ';' < "$pairs")"
rm -f "$pairs" "$pairs.json"
echo "== numpy/scipy: the paper-mode SDF index by the reference tracking (type1, Table 2 curve) =="
"$B/railride" matrices examples/type1-sdf-paper.ini --speed 350 --conicity 0.17 --json | taskset -c 1 $PY bench/numpy_sdf.py 1.5 8e6 6e6
echo "== ride evaluation (C) =="
taskset -c 1 "$B/bench/bench_ride"
echo "== numpy, the same evaluation (D as one product of stacked coefficients, one batched solve of the lagged input sum, the indices as products) =="
"$B/railride" matrices --speed 350 --conicity 0.17 --json | taskset -c 1 $PY bench/numpy_ride.py
echo "== numpy by modes, the same evaluation the way railride does it (one eig, modal sums as products, the SDF as a rank-4 SMW correction): the best numpy baseline =="
"$B/railride" matrices --speed 350 --conicity 0.17 --json | taskset -c 1 $PY bench/numpy_ride_modal.py
echo "== ride evaluation against both numpy routes in alternating triples (this VM's speed changes within a run) =="
pairs=$(mktemp)
"$B/railride" matrices --speed 350 --conicity 0.17 --json > "$pairs.json"
for i in 1 2 3 4 5 6; do
  a=$(taskset -c 1 $PY bench/numpy_ride.py < "$pairs.json" | tail -1 | awk '{print $2}')
  m=$(taskset -c 1 $PY bench/numpy_ride_modal.py < "$pairs.json" | tail -1 | awk '{print $2}')
  c=$(taskset -c 1 "$B/bench/bench_ride" | head -1)
  b=$(echo "$c" | awk '{print $2}')
  d=$(echo "$c" | sed 's/.*set once \([0-9.]*\) us.*/\1/')
  echo "$a $b $m $d"
done > "$pairs"
med=$(awk '{print $1 / $2}' "$pairs" | sort -g | awk '{r[NR] = $1} END {printf "%.1f", (r[3] + r[4]) / 2}')
medm=$(awk '{print $3 / $2}' "$pairs" | sort -g | awk '{r[NR] = $1} END {printf "%.1f", (r[3] + r[4]) / 2}')
best=$(awk '{if (!n || $1 < n) n = $1; if (!c || $2 < c) c = $2} END {printf "%.1f", n / c}' "$pairs")
medd=$(awk '{print $3 / $4}' "$pairs" | sort -g | awk '{r[NR] = $1} END {printf "%.1f", (r[3] + r[4]) / 2}')
echo "ride_vs_numpy_modal_median_ratio $medd (against the best numpy baseline, like for like: both take the track's PSD computed once); $medm with railride's full execute (the track's PSD each time)"
echo "ride_vs_numpy_direct_median_ratio $med (a solve per frequency); best against best $best"
echo "  runs (us: numpy direct, C full execute, numpy modal, C track set once): $(tr '\n' ';' < "$pairs")"
echo "== vertical ride evaluation (C): 400 frequencies, 3 points, every index and the 5 s Wb percentiles; ride --direction both =="
taskset -c 1 "$B/bench/bench_vertical"
echo "== numpy, the same vertical evaluation written from docs/vertical.md (checked against railride's numbers) =="
"$B/railride" ride --speed 350 --direction vertical --json > "$pairs.json"
taskset -c 1 $PY bench/numpy_vertical.py < "$pairs.json"
echo "== vertical ride against numpy in alternating pairs =="
for i in 1 2 3 4 5 6; do
  out=$(taskset -c 1 $PY bench/numpy_vertical.py < "$pairs.json")
  a=$(echo "$out" | awk '/^numpy_vertical_evaluation_us/ {print $2}')
  ad=$(echo "$out" | awk '/^numpy_vertical_design_us/ {print $2}')
  c=$(taskset -c 1 "$B/bench/bench_vertical")
  b=$(echo "$c" | awk '/^vertical_ride_us/ {print $2}')
  bd=$(echo "$c" | awk '/^vertical_ride_design_us/ {print $2}')
  echo "$a $b $ad $bd"
done > "$pairs"
r1=$(awk '{print $1 / $2}' "$pairs" | sort -g | awk '{r[NR] = $1} END {printf "%.1f", (r[3] + r[4]) / 2}')
r2=$(awk '{print $3 / $4}' "$pairs" | sort -g | awk '{r[NR] = $1} END {printf "%.1f", (r[3] + r[4]) / 2}')
echo "vertical_vs_numpy_median_ratio $r1 (one evaluation), design path $r2"
echo "  pairs (us: numpy, C, numpy design, C design): $(tr '\n' ';' < "$pairs")"
rm -f "$pairs" "$pairs.json"
echo "== design batches (paper objectives: 9 eigen-solves a design) =="
"$B/bench/bench_batch"
echo "== the same from Python (ctypes), one thread =="
RAILRIDE_LIB="$B/librailride.so" THREADS=1 taskset -c 1 $PY bench/python_batch.py
echo "== validation: 600 s at 350 km/h simulated and analysed =="
"$B/railride" validate --speed 350 --conicity 0.2 | tail -1
echo "== contact geometry and equivalent conicity (EN 15302 wheel A on rail A, 2001 y, 66 amplitudes) =="
taskset -c 1 "$B/bench/bench_contact"
echo "== numpy, the same run (search vectorised over y, the conicity function over the amplitudes; checked against railride's) =="
cj=$(mktemp)
"$B/railride" contact --wheel profiles/en15302/RUIC519A.dat --rail profiles/en15302/SUIC519A.dat --rail-gmp -32.5 --amplitudes 1:7.5:0.1 --json > "$cj"
taskset -c 1 $PY bench/numpy_contact.py "$cj"
echo "== contact against numpy in alternating pairs (all included) =="
for i in 1 2 3 4 5 6; do
  a=$(taskset -c 1 $PY bench/numpy_contact.py | awk '/^numpy_contact_all_ms/ {print $2}')
  b=$(taskset -c 1 "$B/bench/bench_contact" | awk '/^contact_pair_no_roll_ms/ {print $2}')
  echo "$a $b"
done > "$pairs"
r=$(awk '{print $1 / $2}' "$pairs" | sort -g | awk '{r[NR] = $1} END {printf "%.1f", (r[3] + r[4]) / 2}')
echo "contact_vs_numpy_median_ratio $r (ms: numpy, C: $(tr '\n' ';' < "$pairs"))"
rm -f "$cj" "$pairs"
echo "== nonlinear model: simulation, bifurcation diagram by continuation and by the scan =="
OMP_NUM_THREADS=1 taskset -c 1 "$B/bench/bench_nonlinear"
