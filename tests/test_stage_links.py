#!/usr/bin/env python3
"""The pipeline's order at link level: every rr_* symbol a stage's objects
use is defined in that stage or one before it (CMakeLists.txt's RR_STAGES).
The include check cannot see a call declared by hand or through a public
header of a later stage's implementation; nm can. Usage:
test_stage_links.py STAGE_OBJECTS.txt (lines "stage obj obj ...", in order)."""
import subprocess
import sys


def symbols(objs, defined):
    args = ["nm", "--defined-only" if defined else "--undefined-only", "-P"] + objs
    out = subprocess.run(args, capture_output=True, text=True, check=True).stdout
    names = set()
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 2 and not line.endswith(":") and parts[0].startswith("rr_"):
            if defined and parts[1] not in "TDBRVWtdbr":
                continue
            names.add(parts[0].split(".")[0])  # target_clones: rr_x.default, rr_x.resolver
    return names


stages = []
for line in open(sys.argv[1]):
    words = line.split()
    if words:
        stages.append((words[0], words[1:]))
defined_at = {}
for i, (stage, objs) in enumerate(stages):
    for s in symbols(objs, True):
        defined_at.setdefault(s, i)
bad = []
for i, (stage, objs) in enumerate(stages):
    for s in sorted(symbols(objs, False)):
        j = defined_at.get(s)
        if j is not None and j > i:
            bad.append("%s uses %s, defined in the later stage %s" % (stage, s, stages[j][0]))
for b in bad:
    print("FAIL: " + b, file=sys.stderr)
n = sum(len(symbols(objs, False)) for _, objs in stages)
print("stage links: %d passed, %d failed" % (n - len(bad), len(bad)))
sys.exit(1 if bad else 0)
