#!/bin/sh
# Two builds side by side on one core, in alternating pairs (this VM's speed
# drifts within a run): the index, the batched index, the robust triple,
# design batches and the ride evaluation. Usage: bench/against.sh OLD_BUILD [NEW_BUILD] [PAIRS]
# (e.g. a worktree of the previous commit built in /tmp/old/build).
set -e
OLD=${1:?usage: bench/against.sh OLD_BUILD [NEW_BUILD] [PAIRS]}
NEW=${2:-build}
N=${3:-5}
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
t=$(mktemp -d)
trap 'rm -rf "$t"' EXIT
for i in $(seq "$N"); do
  for side in old new; do
    b=$OLD; [ "$side" = new ] && b=$NEW
    taskset -c 1 "$b/bench/bench_modal" | head -4 >> "$t/$side.modal"
    taskset -c 1 "$b/bench/bench_batch" 2>/dev/null | grep "^designs_per_s_1_thread " >> "$t/$side.modal"
    taskset -c 1 "$b/bench/bench_ride" | grep "^ride_no_sdf_modal_us \|^ride_sdf_paper_modal_smw_us " >> "$t/$side.modal"
  done
done
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
for key in stability_index_us stability_index_batch_per_point_us robust_triple_us full_modal_solve_us \
  designs_per_s_1_thread ride_no_sdf_modal_us ride_sdf_paper_modal_smw_us; do
  o=$(grep "^$key " "$t/old.modal" | awk '{print $2}' | median)
  n=$(grep "^$key " "$t/new.modal" | awk '{print $2}' | median)
  echo "$key old $o new $n ratio $(echo "$n $o" | awk '{printf "%.3f", $1 / $2}') ($N pairs, medians)"
done
