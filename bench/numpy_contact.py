"""numpy doing one railride contact run, vectorised: the contact search and
the equivalent conicity function (bench/numpy_conicity.py), all included.

EN 15302's wheel A on rail S-UIC 519-A (1001 points each, rail as stored,
gauge point -32.5 mm so the wheel origin sits above the rail origin), the
2001-point grid y = -10:10:0.01 mm, no roll: for every y and side the exact
polyline search (every rail vertex and every shifted wheel vertex a
candidate, the gauge-most of the ties), then dr = r_R - r_L, all y at once
(2001 x 1001 arrays); then y0 and the three methods at the 66 amplitudes
1.0-7.5 mm, all amplitudes at once. With a file argument (`railride contact
--json --amplitudes 1:7.5:0.1` of the same case) it also prints the largest
differences from railride's dr and tan gamma_e (a cross-check). Prints the
medians of 5 runs in ms.
"""
import sys
import time

import numpy as np

import numpy_conicity as nc

def search_side(u, zw, v, zr, s):
    """The exact polyline search for the shifts s (ny,), all at once: every rail vertex and
    every shifted wheel vertex a candidate, the gauge-most of the ties within 1e-9 mm. The
    wheel's z at contact, the rail coordinate of the contact, and validity."""
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
    return zc, vc, (vc - lo > 1e-9) & (hi - vc > 1e-9)


r0 = 460.0


def side(s):
    """Contact on one side for the shifts s (ny,): the wheel's z at contact and validity."""
    zc, _, ok = search_side(W[:, 0], W[:, 1], R[:, 0], R[:, 1], s)
    return zc, ok


def run():
    y = np.round(np.linspace(-10, 10, 2001), 10)
    zR, okR = side(y)
    zL, okL = side(-y)
    return y, (r0 - zR) - (r0 - zL), okR & okL


if __name__ == "__main__":  # the benchmark (the test suite imports search_side only)
    W = np.loadtxt("profiles/en15302/RUIC519A.dat", comments="#")
    R = np.loadtxt("profiles/en15302/SUIC519A.dat", comments="#")
    AMPS = np.round(np.arange(66) * 0.1 + 1.0, 10)
    t, tc = [], []
    for _ in range(5):
        t0 = time.perf_counter()
        y, dr, ok = run()
        t1 = time.perf_counter()
        y0, tg_a, tg_b, tg_c = nc.conicity(y, dr, ok, AMPS)
        t2 = time.perf_counter()
        t.append(t1 - t0)
        tc.append(t2 - t0)
    print("numpy_contact_search_ms %.1f  (valid %d of %d)" % (1e3 * sorted(t)[2], ok.sum(), y.size))
    print("numpy_contact_all_ms %.1f  (search + the conicity function, 66 amplitudes, three methods;"
          " tan_gamma_e at 3 mm %.5f)" % (1e3 * sorted(tc)[2], tg_a[20]))
    if len(sys.argv) > 1:
        import json
        g = json.load(open(sys.argv[1]))
        m = ok & np.array(g["valid"], bool)
        print("numpy_contact_dr_max_diff_mm %.2e" % np.abs(dr[m] - np.array(g["dr_mm"])[m]).max())
        for name, mine in (("tan_gamma_e", tg_a), ("tan_gamma_e_harmonic", tg_b),
                           ("tan_gamma_e_regression", tg_c)):
            theirs = np.array([np.nan if x is None else x for x in g[name]], float)
            both = np.isfinite(mine) & np.isfinite(theirs)
            print("numpy_%s_max_diff %.2e  (%d of %d defined in both, %d disagree on defined)"
                  % (name, np.abs(mine[both] - theirs[both]).max(), both.sum(), mine.size,
                     (np.isfinite(mine) != np.isfinite(theirs)).sum()))
