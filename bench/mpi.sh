#!/bin/sh
# optimise over MPI ranks: the paper's problem (population 5000, 100
# generations; POP, GEN to change) on 1 process x 1 thread and on 2 ranks x 1
# thread, the parallel efficiency, the exchange's time per generation and its
# share, the exchange's latency and bandwidth (bench/mpi_allgather), and the
# cost model that follows for more ranks and population 5000 and 50000.
set -e
cd "$(dirname "$0")/.."
B=${BUILD:-build}
POP=${POP:-5000}
GEN=${GEN:-100}
P=examples/paper-optimisation.ini
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
now() { date +%s.%N; }
# REPS alternating runs of each (this 2-vCPU machine's speed drifts): the
# fastest of each is compared; then 1 process x 2 OpenMP threads for reference
REPS=${REPS:-2}
t1=1e9 t2=1e9
sub() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a - b }'; }
less() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a < b) }'; }
for r in $(seq 1 $REPS); do
  a=$(now)
  "$B/railride" optimise $P --population $POP --generations $GEN --threads 1 --output "$tmp/s" > "$tmp/s.out"
  b=$(now)
  mpirun -np 2 --oversubscribe "$B/railride" optimise $P --population $POP --generations $GEN --threads 1 --output "$tmp/m" > "$tmp/m.out" 2> "$tmp/m$r.err"
  c=$(now)
  s1=$(sub "$b" "$a") s2=$(sub "$c" "$b")
  echo "run $r: 1 process x 1 thread $s1 s, 2 ranks x 1 thread $s2 s"
  less "$s1" "$t1" && t1=$s1
  less "$s2" "$t2" && t2=$s2 && cp "$tmp/m$r.err" "$tmp/m.err"
done
a=$(now)
"$B/railride" optimise $P --population $POP --generations $GEN --threads 2 --output "$tmp/t" > /dev/null
echo "reference: 1 process x 2 threads $(sub "$(now)" "$a") s"
a=0 b=$t1 c=$(awk -v a="$t1" -v b="$t2" 'BEGIN { printf "%.3f", a + b }')
cmp -s "$tmp/s-pareto.csv" "$tmp/m-pareto.csv" && echo "fronts: bit-identical" || echo "fronts: DIFFER"
grep "MPI ranks" "$tmp/m.err"
mpirun -np 2 --oversubscribe "$B/bench/mpi_allgather" 8 $((POP * 3 * 8)) $((POP * 30 * 8)) > "$tmp/ag.txt"
cat "$tmp/ag.txt"
"$B/bench/bench_nsga2" > "$tmp/ns.txt"
/usr/bin/python3 - "$a" "$b" "$c" "$tmp/m.err" "$tmp/ag.txt" $POP $GEN "$tmp/ns.txt" <<'PY'
import re, sys
a, b, c = map(float, sys.argv[1:4]); pop, gen = int(sys.argv[6]), int(sys.argv[7])
t1, t2 = b - a, c - b
m = re.search(r"busy s per rank: ([\d. ]+); waiting and exchange s: ([\d. ]+)", open(sys.argv[4]).read())
busy = [float(x) for x in m.group(1).split()]; wait = [float(x) for x in m.group(2).split()]
ag = [l.split() for l in open(sys.argv[5]).read().splitlines()[1:]]
lat = float(ag[0][2]); t_small = float(ag[1][2]); t_big = float(ag[2][2])
bw = (int(ag[2][0]) - int(ag[1][0])) / (t_big - t_small)          # bytes/s, the slope
evals = pop * (gen + 1)
t_eval = sum(busy)                                                  # designs' evaluation, all ranks
t_rest = t2 - max(b_ + w_ for b_, w_ in zip(busy, wait))            # NSGA-II itself, on every rank
print(f"1 process x 1 thread: {t1:.1f} s; 2 ranks x 1 thread: {t2:.1f} s; efficiency {t1 / (2 * t2):.3f}")
print(f"per generation: exchange and waiting {sum(wait) / len(wait) / gen * 1e3:.2f} ms "
      f"({sum(wait) / len(wait) / t2 * 100:.1f} % of the run); evaluation {t_eval / gen * 1e3:.0f} ms (all ranks); "
      f"NSGA-II on each rank {t_rest / gen * 1e3:.1f} ms")
print(f"exchange: latency {lat * 1e6:.1f} us, bandwidth {bw / 1e9:.2f} GB/s (shared memory)")
nsga = {int(l.split()[0]): float(l.split()[1]) for l in open(sys.argv[8])}
other = max(t_rest / gen - nsga[5000] * pop / 5000, 0)   # per generation: the run's own serial work besides sorting
print(f"NSGA-II's own work per generation (bench_nsga2): {nsga[5000] * 1e3:.1f} ms at 5000, {nsga[50000] * 1e3:.0f} ms at 50000; "
      f"the rest of rank 0's serial work {other * 1e3:.1f} ms")
# cost model: T(P) = T_nsga + T_eval / P + gen * (a log2 P + S (P - 1) / P / bw + imbalance)
import math
per_design = t_eval / evals
for name, a_, bw_ in (("this machine (shared memory)", lat, bw), ("a cluster, InfiniBand (2 us, 10 GB/s)", 2e-6, 10e9),
                      ("a cluster, 10 Gb Ethernet TCP (50 us, 1 GB/s)", 50e-6, 1e9)):
    print(f"cost model, {name}:")
    for n in (5000, 50000):
        S = n * 3 * 8 + 16 * 64                       # objectives + chunk lists, one generation
        t_n = gen * (nsga[n] + other * n / pop)   # every rank repeats it: the serial part
        best = None
        row = []
        for P in (1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024):
            ex = 0 if P == 1 else gen * (2 * a_ * math.ceil(math.log2(P)) + S * (P - 1) / P / bw_)
            imb = 0 if P == 1 else gen * (n * per_design / (P * 32)) / 2       # half a chunk (1/32 of a share)
            T = t_n + n * (gen + 1) * per_design / P + ex + imb
            row.append((P, T))
        T1 = row[0][1]
        cells = "  ".join(f"P={P}: {T:.1f} s (eff {T1 / (P * T):.2f})" for P, T in row)
        stop = next((P for (P, T), (P2, T2) in zip(row, row[1:]) if T1 / (P2 * T2) < 0.5), None)
        print(f"  population {n}: {cells}")
        print(f"    efficiency >= 0.5 up to P = {stop} ranks, below it at {2 * stop}" if stop else "    efficiency stays above 0.5 to 1024 ranks")
PY
# bifurcation by continuation: the monodromy matrix's column groups over the
# ranks (the Newton iterations between them run on every rank alike)
for r in 1 2; do
  a=$(now)
  "$B/railride" bifurcation examples/type2.ini --profile worn --csv > "$tmp/bs.csv" 2> /dev/null
  b=$(now)
  mpirun -np 2 --oversubscribe "$B/railride" bifurcation examples/type2.ini --profile worn --csv > "$tmp/bm.csv" 2> "$tmp/bm.err"
  c=$(now)
  echo "bifurcation type2 worn, run $r: 1 process x 1 thread $(sub "$b" "$a") s, 2 ranks x 1 thread $(sub "$c" "$b") s ($(grep "MPI ranks" "$tmp/bm.err"))"
done
cmp -s "$tmp/bs.csv" "$tmp/bm.csv" && echo "bifurcation branches: bit-identical" || echo "bifurcation branches: DIFFER"
