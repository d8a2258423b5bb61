#!/usr/bin/env bash
# railride under mpirun (2 ranks on this machine, loopback): the distributed
# commands give the serial output bit for bit; a killed rank ends the job
# with the checkpoint of the last finished generation intact, and the run
# resumed from it is the uninterrupted run.
set -u
RR=${RR_CLI:?}
SRC=${RR_SOURCE_DIR:?}
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# CI and containers run as root; loopback only; no oversubscription warning
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_tcp_if_include=lo OMPI_MCA_oob_tcp_if_include=lo
export OMPI_MCA_rmaps_base_oversubscribe=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
mpi() { mpirun -np 2 --oversubscribe "$RR" "$@"; }
same() {  # same NAME FILE1 FILE2
  if cmp -s "$2" "$3"; then ok; else bad "$1: the MPI output differs from the serial one"; diff "$2" "$3" | head -5 >&2; fi
}

# NSGA-II: the paper's problem shortened
P="$SRC/examples/paper-optimisation.ini"
"$RR" optimise "$P" --population 200 --generations 10 --threads 1 --output "$tmp/s" > /dev/null 2>&1 || bad "serial optimise"
mpi optimise "$P" --population 200 --generations 10 --threads 1 --output "$tmp/m" > "$tmp/m.out" 2> "$tmp/m.err" || bad "mpirun optimise: $(tail -3 "$tmp/m.err")"
same "optimise front (CSV)" "$tmp/s-pareto.csv" "$tmp/m-pareto.csv"
same "optimise front (JSON)" "$tmp/s-pareto.json" "$tmp/m-pareto.json"
# the checkpoint less its clock (8 bytes at offset 40: the elapsed seconds)
noclock() { head -c 40 "$1" > "$2"; tail -c +49 "$1" >> "$2"; }
noclock "$tmp/s-checkpoint.bin" "$tmp/sc" && noclock "$tmp/m-checkpoint.bin" "$tmp/mc"
same "optimise checkpoint (less the elapsed seconds)" "$tmp/sc" "$tmp/mc"
cut -d, -f1,2,4,5 "$tmp/s-history.csv" > "$tmp/sh" && cut -d, -f1,2,4,5 "$tmp/m-history.csv" > "$tmp/mh"
same "optimise history (less the seconds)" "$tmp/sh" "$tmp/mh"
grep -q "written to $tmp/m-pareto.csv" "$tmp/m.out" && [ "$(grep -c "NSGA-II" "$tmp/m.out")" -eq 1 ] && ok || bad "one summary, from rank 0"
grep -q "2 MPI ranks; busy s per rank: [0-9.]* [0-9.]*;" "$tmp/m.err" && ok || bad "per-rank busy time reported"
# with constraints (the violations travel with the objectives)
C="$SRC/examples/paper-optimisation-constrained.ini"
"$RR" optimise "$C" --population 40 --generations 4 --threads 1 --output "$tmp/sc" > /dev/null 2>&1
mpi optimise "$C" --population 40 --generations 4 --threads 1 --output "$tmp/mc" > /dev/null 2>&1 || bad "mpirun constrained optimise"
same "constrained front" "$tmp/sc-pareto.csv" "$tmp/mc-pareto.csv"

# grids and lists
args=(--x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:7" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:6" --objective "index@350,0.17")
"$RR" sweep "${args[@]}" > "$tmp/s.csv" && mpi sweep "${args[@]}" > "$tmp/m.csv" 2> /dev/null || bad "sweep runs"
same "sweep" "$tmp/s.csv" "$tmp/m.csv"
"$RR" sweep --x speed=150:550:9 --objective "sperling@0,0.2" > "$tmp/s2.csv" && mpi sweep --x speed=150:550:9 --objective "sperling@0,0.2" > "$tmp/m2.csv" 2> /dev/null || bad "sweep speed runs"
same "sweep over speed" "$tmp/s2.csv" "$tmp/m2.csv"
"$RR" map --speeds 100:500:17 --conicities 0.02:0.5:9 > "$tmp/s3.csv" && mpi map --speeds 100:500:17 --conicities 0.02:0.5:9 > "$tmp/m3.csv" 2> /dev/null || bad "map runs"
same "map" "$tmp/s3.csv" "$tmp/m3.csv"
"$RR" map type2 --json > "$tmp/s4.json" && mpi map type2 --json > "$tmp/m4.json" 2> /dev/null || bad "map json runs"
same "map (JSON, type2)" "$tmp/s4.json" "$tmp/m4.json"
"$RR" critical-speed type2 --conicity 0.05,0.2,0.4,0.6 --json > "$tmp/s5.json" && mpi critical-speed type2 --conicity 0.05,0.2,0.4,0.6 --json > "$tmp/m5.json" 2> /dev/null || bad "critical-speed runs"
same "critical-speed list" "$tmp/s5.json" "$tmp/m5.json"
"$RR" locus type2 --range 50:600:300 > "$tmp/s7.csv" && mpi locus type2 --range 50:600:300 > "$tmp/m7.csv" 2> /dev/null || bad "locus runs"
same "locus over speed (records solved over the ranks, followed in order)" "$tmp/s7.csv" "$tmp/m7.csv"
"$RR" locus --over conicity --range 0.02:0.6:40 --speed 300 --json > "$tmp/s8.json" && mpi locus --over conicity --range 0.02:0.6:40 --speed 300 --json > "$tmp/m8.json" 2> /dev/null || bad "locus conicity runs"
same "locus over conicity (JSON)" "$tmp/s8.json" "$tmp/m8.json"
"$RR" bifurcation --profile new --csv > "$tmp/s9.csv" 2> /dev/null && mpi bifurcation --profile new --csv > "$tmp/m9.csv" 2> "$tmp/m9.err" || bad "bifurcation runs"
same "bifurcation by continuation (the monodromy matrix's column groups over the ranks)" "$tmp/s9.csv" "$tmp/m9.csv"
[ "$(grep -c "nonlinear model" "$tmp/m9.err")" -eq 1 ] && ok || bad "bifurcation's assumptions once per job"
mpi bifurcation --profile worn --method scan --speeds 500:560 --step 20 --settle 2 --csv > "$tmp/m10.txt" 2> "$tmp/m10.err" && "$RR" bifurcation --profile worn --method scan --speeds 500:560 --step 20 --settle 2 --csv > "$tmp/s10.txt" 2> /dev/null || bad "bifurcation scan runs"
same "bifurcation scan (rank 0 alone)" "$tmp/s10.txt" "$tmp/m10.txt"
grep -q "rank 0 runs it alone" "$tmp/m10.err" && ok || bad "the note for the scan"
# a command that is not distributed: rank 0 alone, one output
mpi modes --speed 300 --conicity 0.2 > "$tmp/m6.txt" 2> "$tmp/m6.err" && "$RR" modes --speed 300 --conicity 0.2 > "$tmp/s6.txt" || bad "modes runs"
same "modes (rank 0 alone)" "$tmp/s6.txt" "$tmp/m6.txt"
grep -q "rank 0 runs it alone" "$tmp/m6.err" && ok || bad "the note for a command not distributed"
# a bad input: every rank stops, one message, exit status 2 through mpirun
mpi optimise "$P" --output /nonexistent/dir/x > /dev/null 2> "$tmp/bad.err"; st=$?
[ $st -ne 0 ] && [ "$(grep -c "cannot write" "$tmp/bad.err")" -eq 1 ] && ok || bad "unwritable output under mpirun: exit $st, $(grep -c "cannot write" "$tmp/bad.err") messages"

# a rank killed: the job ends, the checkpoint holds the last finished generation,
# and resuming gives the uninterrupted run's front
"$RR" optimise "$P" --population 100 --generations 80 --threads 1 --output "$tmp/full" > /dev/null 2>&1
mpi optimise "$P" --population 100 --generations 80 --threads 1 --output "$tmp/k" > /dev/null 2> "$tmp/k.err" &
job=$!
killed=""
for _ in $(seq 1 100); do   # rank 1, once a checkpoint exists
  sleep 0.1
  [ -f "$tmp/k-checkpoint.bin" ] || continue
  for p in $(pgrep -f "railride optimise $P --population 100 --generations 80"); do
    if tr '\0' '\n' < "/proc/$p/environ" 2> /dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1"; then kill -9 "$p" && killed=$p; fi
  done
  [ -n "$killed" ] && break
done
wait $job; st=$?
[ -n "$killed" ] && [ $st -ne 0 ] && ok || bad "killed rank: the job did not end with an error (killed '$killed', exit $st)"
grep -qi "signal 9\|killed" "$tmp/k.err" && ok || bad "killed rank: no message naming the kill ($(tail -2 "$tmp/k.err"))"
"$RR" optimise "$P" --population 100 --generations 80 --threads 1 --output "$tmp/k" --resume > /dev/null 2>&1 || bad "resume after the kill"
same "resumed after a killed rank = uninterrupted run" "$tmp/full-pareto.csv" "$tmp/k-pareto.csv"

echo "mpi: $pass passed, $fail failed"
[ $fail -eq 0 ]
