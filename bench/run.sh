#!/bin/sh
# Runs the benchmarks on one core and prints the figures side by side with
# numpy/scipy on the same matrices (Debian's python3-numpy, python3-scipy).
set -e
cd "$(dirname "$0")/.."
B=${BUILD:-build}
export OPENBLAS_NUM_THREADS=1
PY=/usr/bin/python3
echo "== railride (C) =="
taskset -c 0 "$B/bench/bench_modal"
echo "== numpy/scipy, same state matrix (default vehicle, 350 km/h, conicity 0.17) =="
"$B/railride" matrices --speed 350 --conicity 0.17 --json | taskset -c 0 $PY bench/numpy_modal.py
echo "== ride evaluation (C) =="
taskset -c 0 "$B/bench/bench_ride"
echo "== numpy, the same 400 batched 17x17 systems =="
"$B/railride" matrices --speed 350 --conicity 0.17 --json | taskset -c 0 $PY bench/numpy_ride.py
