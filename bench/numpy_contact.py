"""numpy doing the contact search of one railride contact run, vectorised.

EN 15302's wheel A on rail S-UIC 519-A (1001 points each, rail as stored,
gauge point -32.5 mm so the wheel origin sits above the rail origin), the
2001-point grid y = -10:10:0.01 mm, no roll: for every y and side the exact
polyline search (every rail vertex and every shifted wheel vertex a
candidate, the gauge-most of the ties), then dr = r_R - r_L. All y at once
(2001 x 1001 arrays). Only the search: the conicity function is not
included, so the ratio against railride's all-included figure flatters
numpy. With a file argument (`railride contact --grid` of the same case) it
also prints the largest dr difference (a cross-check). Prints the median of
5 runs in ms.
"""
import sys
import time

import numpy as np

W = np.loadtxt("profiles/en15302/RUIC519A.dat", comments="#")
R = np.loadtxt("profiles/en15302/SUIC519A.dat", comments="#")
u, zw, v, zr = W[:, 0], W[:, 1], R[:, 0], R[:, 1]
r0 = 460.0


def side(s):
    """Contact on one side for the shifts s (ny,): the wheel's z at contact and validity."""
    S = s[:, None]
    # rail vertices over the wheel: d = z_r - z_w(v_j - s)
    uj = v[None, :] - S
    inr = (uj >= u[0]) & (uj <= u[-1])
    dr_ = np.where(inr, zr[None, :] - np.interp(uj, u, zw), -np.inf)
    # shifted wheel vertices over the rail: d = z_r(u_i + s) - z_w
    vi = u[None, :] + S
    inw = (vi >= v[0]) & (vi <= v[-1])
    dw = np.where(inw, np.interp(vi, v, zr) - zw[None, :], -np.inf)
    dmax = np.maximum(dr_.max(axis=1), dw.max(axis=1))[:, None]
    # gauge-most tie: the smallest rail coordinate among d >= dmax - 1e-9
    vr = np.where(dr_ >= dmax - 1e-9, v[None, :], np.inf).min(axis=1)
    vw = np.where(dw >= dmax - 1e-9, vi, np.inf).min(axis=1)
    vc = np.minimum(vr, vw)
    zc = np.where(vw < vr, zw[np.argmin(np.where(dw >= dmax - 1e-9, vi, np.inf), axis=1)],
                  np.interp(vc - s, u, zw))
    lo, hi = np.maximum(v[0], u[0] + s), np.minimum(v[-1], u[-1] + s)
    return zc, (vc - lo > 1e-9) & (hi - vc > 1e-9)


def run():
    y = np.round(np.linspace(-10, 10, 2001), 10)
    zR, okR = side(y)
    zL, okL = side(-y)
    return y, (r0 - zR) - (r0 - zL), okR & okL


t = []
for _ in range(5):
    t0 = time.perf_counter()
    y, dr, ok = run()
    t.append(time.perf_counter() - t0)
print("numpy_contact_search_ms %.1f  (valid %d of %d)" % (1e3 * sorted(t)[2], ok.sum(), y.size))
if len(sys.argv) > 1:
    g = np.genfromtxt(sys.argv[1], delimiter=",", names=True)
    m = ok & (g["valid"] > 0)
    print("numpy_contact_dr_max_diff_mm %.2e" % np.abs(dr[m] - g["dr_mm"][m]).max())
