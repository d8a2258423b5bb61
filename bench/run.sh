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
echo "== numpy/scipy: the paper-mode SDF index by the reference tracking (type1, Table 2 curve) =="
"$B/railride" matrices examples/type1-sdf-paper.ini --speed 350 --conicity 0.17 --json | taskset -c 1 $PY bench/numpy_sdf.py 1.5 8e6 6e6
echo "== ride evaluation (C) =="
taskset -c 1 "$B/bench/bench_ride"
echo "== numpy, the same evaluation (D built, 400 batched 17x17 solves, PEM, the three indices at 3 points) =="
"$B/railride" matrices --speed 350 --conicity 0.17 --json | taskset -c 1 $PY bench/numpy_ride.py
echo "== design batches (paper objectives: 9 eigen-solves a design) =="
"$B/bench/bench_batch"
echo "== the same from Python (ctypes), one thread =="
RAILRIDE_LIB="$B/librailride.so" THREADS=1 taskset -c 1 $PY bench/python_batch.py
echo "== validation: 600 s at 350 km/h simulated and analysed =="
"$B/railride" validate --speed 350 --conicity 0.2 | tail -1
echo "== nonlinear model: simulation, bifurcation diagram by continuation and by the scan =="
taskset -c 1 "$B/bench/bench_nonlinear"
