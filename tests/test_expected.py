"""Committed outputs (tests/expected/): each command's output against the file of its name,
text exactly and numbers to 1e-9 relative; lines and JSON keys that name seconds skipped.
With --update, the files are rewritten (tools/update-expected)."""
import os
import re
import shlex
import subprocess
import sys

from pycheck import check, done

src = os.environ.get("RR_SOURCE_DIR", "..")
cli = os.environ["RR_CLI"]
here = os.path.join(src, "tests", "expected")
NUM = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
SECONDS = re.compile(r"cpu_seconds|\bseconds?\b|elapsed|\bin [0-9.]+ s\b", re.IGNORECASE)
RTOL, ATOL = 1e-9, 1e-300


def cases():
    for line in open(os.path.join(here, "commands.txt")):
        if line.strip() and not line.startswith("#"):
            name, args = (t.strip() for t in line.split("|", 1))
            yield name, shlex.split(args)


def kept(text):
    return [l for l in text.splitlines() if not SECONDS.search(l)]


def same_line(a, b):
    if NUM.sub("#", a) != NUM.sub("#", b):
        return False
    for x, y in zip(NUM.findall(a), NUM.findall(b)):
        fx, fy = float(x), float(y)
        if abs(fx - fy) > ATOL + RTOL * max(abs(fx), abs(fy)):
            return False
    return True


def run(args):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    r = subprocess.run([cli, *args], capture_output=True, text=True, cwd=src, env=env)
    return r.returncode, r.stdout


update = "--update" in sys.argv
for name, args in cases():
    code, out = run(args)
    path = os.path.join(here, name + ".out")
    if update:  # without the lines that name seconds: the files change only with results
        with open(path, "w") as f:
            f.write("".join(l + "\n" for l in kept(out)))
        continue
    check(code in (0, 1), "%s: exit %d" % (name, code))
    want = kept(open(path).read()) if os.path.exists(path) else None
    check(want is not None, "%s: no committed output (tools/update-expected)" % name)
    if want is None:
        continue
    got = kept(out)
    bad = [i for i, (a, b) in enumerate(zip(got, want)) if not same_line(a, b)]
    if len(got) != len(want):
        why = "%d lines, %d committed" % (len(got), len(want))
    elif bad:
        why = "line %d: got %r, committed %r" % (bad[0] + 1, got[bad[0]][:120], want[bad[0]][:120])
    check(len(got) == len(want) and not bad, "%s: %s" % (name, why if len(got) != len(want) or bad else ""))
if not update:
    done("expected")
