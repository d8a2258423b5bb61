#!/usr/bin/env bash
# The README's and the guide's (docs/guide.md) examples run, so that none can go stale silently: every
# railride command of its shell blocks (the long ones with a short setting,
# an MPI launcher's command on one process), each figure its comment quotes
# ("# 422.1 km/h") found in the output, and its Python block.
set -u
RR=${RR_CLI:?RR_CLI must name the railride binary}
SRC=$(cd "${RR_SOURCE_DIR:-..}" && pwd)
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" && ln -s "$SRC/examples" examples && ln -s "$SRC/profiles" profiles &&
  mkdir build && ln -s "$RR" build/railride  # the README's paths, as in a built tree

# short settings for the long runs (the command and its options otherwise as written)
shorten() {
  sed -e 's/^\(mpirun\|srun\) [^b]*build\/railride/build\/railride/' \
      -e 's/ optimise \([^ ]*\)/ optimise \1 --population 8 --generations 1 --output readme-opt/' \
      -e 's/--duration 30/--duration 1/' \
      -e 's/--speeds 100:600:501 --conicities 0.02:0.6:59/--speeds 100:600:3 --conicities 0.02:0.6:3/'
}
# has_speed "422.1 km/h" FILE: some "X km/h" of FILE rounds to the quoted figure
has_speed() {
  python3 - "$1" "$2" <<'PY'
import re, sys
want = sys.argv[1].split()[0]
dec = len(want.split(".")[1]) if "." in want else 0
got = re.findall(r"([0-9]+(?:\.[0-9]+)?) km/h", open(sys.argv[2]).read())
sys.exit(0 if any("%.*f" % (dec, float(g)) == want for g in got) else 1)
PY
}
n=0
while IFS= read -r line; do
  want=$(printf '%s' "$line" | sed -n 's/.*# *\([0-9][0-9.]* km\/h\).*/\1/p')
  cmd=$(printf '%s' "$line" | sed 's/ *#.*//' | shorten)
  n=$((n + 1))
  if bash -c "$cmd" > "out$n.txt" 2> "err$n.txt"; then
    [ -z "$want" ] || has_speed "$want" "out$n.txt" && ok || bad "README: '$cmd' does not give $want"
  else
    bad "README: '$cmd' exits $? ($(head -1 "err$n.txt"))"
  fi
done < <(cat "$SRC/README.md" "$SRC/docs/guide.md" | awk '/^```sh/ {inb = 1; next} /^```/ {inb = 0} inb' |
         sed -e ':a' -e '/\\$/{N;s/\\\n *//;ba}' | grep -E '^(build/railride|mpirun|srun) ')
[ "$n" -ge 20 ] && ok || bad "README and the guide: only $n railride commands found"

# the examples: each vehicle file loads and solves, each problem file runs (briefly), and
# each command an example's comment gives ("#   railride ...") runs
for f in "$SRC"/examples/*.ini; do
  b=examples/$(basename "$f")
  if grep -q '^\[problem\]' "$f"; then
    build/railride optimise "$b" --population 8 --generations 1 --output ex-opt > /dev/null 2>&1 && ok || bad "$b: optimise fails"
  else
    build/railride modes "$b" --speed 300 --conicity 0.2 > /dev/null 2>&1 && ok || bad "$b: modes fails"
  fi
  grep '^#   railride ' "$f" | sed 's/^#   railride/build\/railride/; s/ *(.*//' | shorten | while IFS= read -r cmd; do
    bash -c "$cmd" > ex.txt 2> ex.err && echo ok || echo "bad $cmd: $(head -1 ex.err)"
  done > ex-runs.txt
  while IFS= read -r res; do [ "$res" = ok ] && ok || bad "$b: '${res#bad }'"; done < ex-runs.txt
done
# type1-rising-tread.ini's comment: subcritical, the Hopf point at 603.8 km/h and the fold at 574.45
build/railride bifurcation examples/type1-rising-tread.ini --speeds 100:620 > rising.txt 2>&1 &&
  has_speed "603.8 km/h" rising.txt && has_speed "574.45 km/h" rising.txt && grep -q subcritical rising.txt && ok ||
  bad "type1-rising-tread.ini: not the bifurcation its comment gives ($(grep -m1 -i 'hopf' rising.txt))"

# the Python block, as written (numpy and the shared library needed; a sanitizer build's
# library cannot load into a plain interpreter)
if [ -n "${RAILRIDE_LIB:-}" ] && ! ldd "$RAILRIDE_LIB" 2> /dev/null | grep -q 'libasan\|libtsan' &&
   /usr/bin/python3 -c "import numpy" 2> /dev/null; then
  cat "$SRC/README.md" "$SRC/docs/guide.md" | awk '/^```python/ {inb = 1; next} /^```/ {inb = 0} inb' > readme.py
  [ -s readme.py ] && PYTHONPATH="$SRC/python" /usr/bin/python3 readme.py > py.txt 2>&1 && ok ||
    bad "README: the Python block fails ($(tail -1 py.txt))"
fi
echo "readme: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
