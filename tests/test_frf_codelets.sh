#!/bin/sh
# src/ride/frf_codelets.c is what tools/frf_codelets_gen.c writes today: a
# change to the sparse FRF's compilation (frf_sparse.c) or to the built-in
# vehicles' structure without regenerating the codelets fails here.
set -e
out=$(mktemp)
trap 'rm -f "$out"' EXIT
"$RR_CODELETS_GEN" > "$out"
if ! cmp -s "$out" "$RR_SOURCE_DIR/src/ride/frf_codelets.c"; then
  diff "$out" "$RR_SOURCE_DIR/src/ride/frf_codelets.c" | head -20
  echo "src/ride/frf_codelets.c is stale: build/tests/frf_codelets_gen > src/ride/frf_codelets.c" >&2
  exit 1
fi
echo "frf codelets: $(grep -c '^static const int sig' "$out") structure(s), the committed file is the generator's output"
