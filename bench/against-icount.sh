#!/bin/sh
# Two builds compared by instructions executed (valgrind's callgrind), which
# a busy or throttled VM cannot disturb: per evaluation of the index, an
# 8-lane batch, the robust triple and the ride, (count at 2R - count at R) / R.
# Usage: bench/against-icount.sh OLD_SRC OLD_BUILD [NEW_SRC NEW_BUILD]
set -e
OS=${1:?usage: bench/against-icount.sh OLD_SRC OLD_BUILD [NEW_SRC NEW_BUILD]}
OB=${2:?}
NS=${3:-.}
NB=${4:-build}
export OPENBLAS_NUM_THREADS=1 RAILRIDE_SPECTRA_DIR="$(cd "$NS" && pwd)/spectra"
t=$(mktemp -d)
trap 'rm -rf "$t"' EXIT
for side in old new; do
  s=$OS b=$OB
  [ "$side" = new ] && s=$NS b=$NB
  b=$(cd "$b" && pwd)
  cc -O2 -std=c11 -I"$s/include" -I"$b/include" "$(dirname "$0")/icount.c" -L"$b" -lrailride \
    -Wl,-rpath,"$b" -lm -o "$t/ic_$side"
done
ir() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 | awk '/Collected/ {print $4}'; }
for w in "index 100" "batch 20" "robust 10" "ride 20"; do
  set -- $w
  for side in old new; do
    a=$(ir "$t/ic_$side" "$1" "$2")
    c=$(ir "$t/ic_$side" "$1" $(($2 * 2)))
    eval "$side=$(( (c - a) / $2 ))"
  done
  echo "$1_instructions old $old new $new ratio $(echo "$new $old" | awk '{printf "%.4f", $1 / $2}')"
done
