#!/usr/bin/env bash
# The bad-input corpus (tests/bad/cases.txt): every case exits with status 2
# and one line on stderr naming file, line and key (or the option), within a
# time and memory limit.
set -u
RR=${RR_CLI:?RR_CLI must name the railride binary}
SRC=${RR_SOURCE_DIR:?}
BAD="$SRC/tests/bad"
pass=0 fail=0
err=$(mktemp)
trap 'rm -f "$err"' EXIT
cd "$SRC"
while IFS='|' read -r name pattern args; do
  case "$name" in '#'*|'') continue ;; esac
  name=$(echo "$name" | sed 's/ *$//'); pattern=$(echo "$pattern" | sed 's/^ *//; s/ *$//')
  args=${args# }
  args=${args//\$BAD/$BAD}
  # shellcheck disable=SC2086
  # 4 GB of address space at most (not under AddressSanitizer, whose shadow memory needs more)
  ( [ -z "${ASAN_OPTIONS:-}" ] && ulimit -v 4000000; timeout 60 "$RR" $args ) > /dev/null 2> "$err"
  st=$?
  if [ $st -ne 2 ]; then fail=$((fail + 1)); echo "FAIL: $name: exit $st (want 2): $(head -c 300 "$err")" >&2; continue; fi
  if [ "$(wc -l < "$err")" -ne 1 ]; then fail=$((fail + 1)); echo "FAIL: $name: not one line: $(head -c 300 "$err")" >&2; continue; fi
  if ! grep -qF -- "$pattern" "$err"; then fail=$((fail + 1)); echo "FAIL: $name: '$(cat "$err")' lacks '$pattern'" >&2; continue; fi
  pass=$((pass + 1))
done < "$BAD/cases.txt"
echo "bad input: $pass passed, $fail failed"
[ $fail -eq 0 ] && [ $pass -ge 100 ]
