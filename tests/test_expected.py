"""Committed outputs (tests/expected/): each command's output against the file of its name,
text exactly and numbers to 1e-9 relative or 1e-12 absolute; lines and JSON keys that name
seconds skipped. The absolute floor is for values that are zero up to rounding (the phase
of a real shape component, the real part of a near-rigid mode beside an imaginary part of
order 1, a vertical shape's 1e-29 pitch): their digits change with the CPU's vector width
(AVX2 against AVX-512 kernels in OpenBLAS and railride's lanes) and say nothing. A CSV
column named residual (a Newton solve's) is a convergence figure: both values below
RESIDUAL_MAX pass. A shape's phase_deg is known as well as its amplitude is: to
ATOL / amplitude radians beyond the relative 1e-9 (its amplitude is on the line before),
and to PHASE_ATOL_DEG at least: the shapes of a near-repeated pair (the two bogies'
wheelset yaw, 3e-7 apart in frequency) are known to eps |A| / gap, about 1e-7. With --update, the files are rewritten (tools/update-expected)."""
import math
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
RTOL, ATOL = 1e-9, 1e-12
RESIDUAL_MAX = 1e-8  # the orbit solver's Newton tolerance is tighter
PHASE_ATOL_DEG = 1e-6


def cases():
    for line in open(os.path.join(here, "commands.txt")):
        if line.strip() and not line.startswith("#"):
            name, args = (t.strip() for t in line.split("|", 1))
            yield name, shlex.split(args)


def kept(text):
    return [l for l in text.splitlines() if not SECONDS.search(l)]


def residual_fields(header):
    """The indices of a CSV header's residual columns (none for other text)."""
    return {i for i, f in enumerate(header.split(",")) if f == "residual"} if "," in header else set()


def same_number(x, y, residual):
    fx, fy = float(x), float(y)
    if residual and max(abs(fx), abs(fy)) < RESIDUAL_MAX:
        return True
    return abs(fx - fy) <= ATOL + RTOL * max(abs(fx), abs(fy))


AMPLITUDE = re.compile(r'"amplitude":\s*(\S+?),?$')
PHASE = re.compile(r'"phase_deg":\s*(\S+?),?$')


def same_phase(a, b, amplitude):
    pa, pb = PHASE.search(a), PHASE.search(b)
    if not (pa and pb and amplitude and a[:pa.start()] == b[:pb.start()]):
        return False
    fx, fy = float(pa.group(1)), float(pb.group(1))
    d = abs(fx - fy) % 360
    return min(d, 360 - d) <= max(RTOL * max(abs(fx), abs(fy)) + math.degrees(ATOL / amplitude),
                                  PHASE_ATOL_DEG)


def same_line(a, b, residual=frozenset(), amplitude=None):
    if amplitude and same_phase(a, b, amplitude):
        return True
    if NUM.sub("#", a) != NUM.sub("#", b):
        return False
    if residual:  # a CSV row: field by field
        fa, fb = a.split(","), b.split(",")
        return all(x == y or (NUM.fullmatch(x) and same_number(x, y, i in residual))
                   for i, (x, y) in enumerate(zip(fa, fb)))
    return all(same_number(x, y, False) for x, y in zip(NUM.findall(a), NUM.findall(b)))


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
    residual = residual_fields(want[0]) if want else set()
    amp = [None] + [float(m.group(1)) if m else None for m in map(AMPLITUDE.search, want[:-1])]
    bad = [i for i, (a, b) in enumerate(zip(got, want)) if not same_line(a, b, residual, amp[i])]
    if len(got) != len(want):
        why = "%d lines, %d committed" % (len(got), len(want))
    elif bad:
        why = "line %d: got %r, committed %r" % (bad[0] + 1, got[bad[0]][:120], want[bad[0]][:120])
    check(len(got) == len(want) and not bad, "%s: %s" % (name, why if len(got) != len(want) or bad else ""))
if not update:
    done("expected")
