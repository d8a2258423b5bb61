"""The lateral ride evaluation by two second implementations in numpy,
independent of railride's C (bench/numpy_ride.py: a solve of the dynamic
stiffness at every frequency; bench/numpy_ride_modal.py: one eig of a state
matrix it builds itself, modal sums and a Sherman-Morrison-Woodbury correction
for the SDF): the default vehicle with the paper-mode SDF at 350 km/h, three
conicities, Sperling (filter and GB/T 5599) and the Wd RMS at the three floor
points from `railride ride --json` agree with both to 1e-9."""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
from pycheck import check, done  # noqa: E402

src = os.environ.get("RR_SOURCE_DIR", os.path.join(os.path.dirname(__file__), ".."))
cli = os.environ["RR_CLI"]
script = os.path.join(src, "bench", "numpy_ride_modal.py")
KEYS = ("sperling", "sperling_gb", "wd_rms")


def run(args, stdin=None):
    return subprocess.run(args, input=stdin, capture_output=True, text=True, check=True).stdout


for lam in ("0.05", "0.17", "0.40"):
    op = ["--sdf", "paper", "--speed", "350", "--conicity", lam, "--json"]
    ours = json.loads(run([cli, "ride"] + op))["results"][0]["points"]
    theirs = json.loads(run([sys.executable, script, "--indices"], run([cli, "matrices"] + op)))
    for route in ("direct", "modal"):
        for key in KEYS:
            for q, pt in enumerate(ours):
                a, b = pt[key], theirs[route][key][q]
                check(abs(a - b) <= 1e-9 * abs(b),
                      "conicity %s, point %d, %s: railride %.15g, numpy (%s) %.15g" % (lam, q, key, a, route, b))
done("test_ride_numpy")
