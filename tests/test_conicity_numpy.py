"""The equivalent conicity by a second implementation: bench/numpy_conicity.py,
written from the contract (docs/contact.md) in numpy independently of
railride's C, on railride's own dr tables of the nine EN 15302 Annex E cases:
y0 and tan gamma_e at 1.0-7.5 mm by all three methods (the wavelength method,
harmonic linearisation, regression) agree to 1e-10, and each method calls the
same amplitudes undefined."""
import json
import os
import subprocess
import sys

import numpy as np

src = os.environ.get("RR_SOURCE_DIR", os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(src, "bench"))
sys.path.insert(0, os.path.dirname(__file__))
import numpy_conicity as nc  # noqa: E402
import numpy_contact  # noqa: E402  (the exhaustive search of the contract)
from pycheck import check, done  # noqa: E402

cli = os.environ["RR_CLI"]
prof = os.path.join(src, "profiles", "en15302")
cases = [l.strip().split(",") for l in open(os.path.join(prof, "cases.csv")) if l.strip()][1:]
for c in cases:
    name, wr, wl, rail, dr_, dl = c[0], c[1], c[2], c[3], float(c[4]), float(c[5])
    args = [cli, "contact", "--wheel-right", os.path.join(prof, wr), "--wheel-left", os.path.join(prof, wl),
            "--rail", os.path.join(prof, rail), "--radius", "%g,%g" % (dr_ / 2, dl / 2),
            "--gauge", c[6], "--flange-back", c[7], "--wheel-origin", c[8], "--inclination", c[9],
            "--rail-gmp=" + c[10], "--lateral-offset=" + c[11], "--amplitudes", "1:7.5:0.1", "--json"]
    d = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    y, dr, valid = np.array(d["y_mm"]), np.array(d["dr_mm"]), np.array(d["valid"], bool)
    amps = np.array(d["amplitude_mm"])
    y0, a, b, r = nc.conicity(y, dr, valid, amps)
    check(abs(y0 - d["y0_mm"]) < 1e-10, "%s: y0 %.12g against railride's %.12g" % (name, y0, d["y0_mm"]))
    for key, mine in (("tan_gamma_e", a), ("tan_gamma_e_harmonic", b), ("tan_gamma_e_regression", r)):
        theirs = np.array([np.nan if x is None else x for x in d[key]], float)
        same_def = (np.isfinite(mine) == np.isfinite(theirs)).all()
        both = np.isfinite(mine) & np.isfinite(theirs)
        worst = np.abs(mine[both] - theirs[both]).max() if both.any() else 0.0
        check(same_def and worst < 1e-10 and both.sum() >= 1,
              "%s %s: %d amplitudes, largest difference %.2e" % (name, key, both.sum(), worst))


# The contact search (railride skips blocks it can bound; the exhaustive search must agree):
# each Annex D wheel on the rail as stored, wheel origin over rail origin, 2001 y, no roll
R = np.loadtxt(os.path.join(prof, "SUIC519A.dat"), comments="#")
y = np.round(np.linspace(-10, 10, 2001), 10)
for wheel in ("RUIC519A", "RUIC519B", "RUIC519H", "RUIC519I"):
    W = np.loadtxt(os.path.join(prof, wheel + ".dat"), comments="#")
    args = [cli, "contact", "--wheel", os.path.join(prof, wheel + ".dat"), "--rail",
            os.path.join(prof, "SUIC519A.dat"), "--rail-gmp=-32.5", "--json"]
    d = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    zR, vR, _ = numpy_contact.search_side(W[:, 0], W[:, 1], R[:, 0], R[:, 1], y)
    zL, vL, _ = numpy_contact.search_side(W[:, 0], W[:, 1], R[:, 0], R[:, 1], -y)
    dr = zL - zR  # (r0 - zR) - (r0 - zL)
    worst = np.abs(dr - np.array(d["dr_mm"])).max()
    at = max(np.abs(np.array(d["contact_rail_right_mm"]) - vR).max(),
             np.abs(np.array(d["contact_rail_left_mm"]) - vL).max())
    check(np.allclose(np.array(d["y_mm"]), y, atol=1e-12, rtol=0) and worst < 1e-12 and at < 1e-12,
          "%s: contact search against the exhaustive one: dr differs by %.2e, the rail points by %.2e"
          % (wheel, worst, at))
done("conicity against numpy")
