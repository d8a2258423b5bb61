"""Two eigenvalue routes other than the Francis QR, measured on railride's state matrices.

Measurement only (2026-12-06, docs/design-notes.md, "Tried and not kept"): would either
give the speed issue 26 asks of the eigen-solve? Neither does; this keeps the figures
reproducible.

  1. Reduce the Hessenberg matrix further, to tridiagonal form, by Gaussian
     elimination. Row interchanges would break the Hessenberg form, so there is no
     pivoting. Then find the tridiagonal's eigenvalues by the Ehrlich-Aberth
     iteration on its characteristic polynomial (the three-term recurrence, after
     Bini, Gemignani and Tisseur, SIAM J. Matrix Anal. Appl. 26(1), 2005).
     Printed: the multipliers' growth, the stability indices' error against
     numpy's eigenvalues, and the recurrence evaluations a root takes.
  2. Replace the QR's 3 x 3 Householder reflectors by Gaussian transforms with
     partial pivoting (a GR algorithm: the implicit double-shift LR with
     interchanges). Same shifts and deflation as rr_hqr. Printed: bulge steps and
     the share of steps that need an interchange.

Matrices: the 9 robust points (250 km/h at conicity 0.05; 350 km/h at 0.05..0.40)
of the built-in type1 and of seeded random designs of the paper's four variables
(each scaled by 0.3..3), from `railride matrices --json`.

  python3 bench/eig_routes.py [BUILD_DIR] [DESIGNS]     (defaults: build, 10)
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

EPS = np.finfo(float).eps
POINTS = [(250, 0.05)] + [(350, 0.05 * i) for i in range(1, 9)]
DESIGN = """[vehicle]
base = type1
[primary]
longitudinal_stiffness = {0:.6g} kN/mm
[lateral_damper]
damping = {1:.6g} kN.s/m
[yaw_damper]
damping = {2:.6g} kN.s/m
series_stiffness = {3:.6g} MN/m
"""
PAPER = (10.0, 60.0, 1360.0, 27.7)  # the variables' scale (examples/paper-design-A.ini)


def matrices(build, ndesigns):
    """State matrices of the 9 robust points, design by design."""
    rng = np.random.default_rng(7)
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for d in range(ndesigns):
            veh = "type1"
            if d:
                veh = os.path.join(tmp, "design.ini")
                with open(veh, "w") as f:
                    f.write(DESIGN.format(*(np.array(PAPER) * rng.uniform(0.3, 3.0, 4))))
            for kmh, lam in POINTS:
                cmd = [os.path.join(build, "railride"), "matrices", veh, "--speed", str(kmh),
                       "--conicity", str(lam), "--json"]
                out.append(np.array(json.loads(subprocess.run(cmd, check=True, capture_output=True).stdout)["A"]))
    return out


def elmhes(a):
    """Hessenberg form by stabilised elementary transformations (as rr_elmhes)."""
    a = a.copy()
    n = len(a)
    for m in range(1, n - 1):
        piv = m + int(np.argmax(abs(a[m:, m - 1])))
        if a[piv, m - 1] == 0:
            continue
        a[[m, piv], :] = a[[piv, m], :]
        a[:, [m, piv]] = a[:, [piv, m]]
        y = a[m + 1:, m - 1] / a[m, m - 1]
        a[m + 1:, :] -= np.outer(y, a[m, :])
        a[:, m] += a[:, m + 1:] @ y
        a[m + 1:, m - 1] = 0
    return a


def tridiagonal(h):
    """Hessenberg to tridiagonal without pivoting: (T, largest multiplier), or (None, inf)."""
    h = h.copy()
    growth = 0.0
    for k in range(len(h) - 2):
        if h[k, k + 1] == 0:
            return None, np.inf
        mult = h[k, k + 2:] / h[k, k + 1]
        growth = max(growth, np.max(abs(mult)))
        h[:, k + 2:] -= np.outer(h[:, k + 1], mult)
        h[k + 1, :] += mult @ h[k + 2:, :]
        h[k, k + 2:] = 0
    return h, growth


def newton_ratio(a, e, z):
    """p(z) / p'(z) for det(T - z I), T's diagonal a and off-diagonal products e."""
    r, q, q2 = a[0] - z, -1 / (a[0] - z), 0.0
    for k in range(1, len(a)):
        rk = (a[k] - z) - e[k - 1] / r
        q, q2, r = (-1 + (a[k] - z) * q - e[k - 1] * q2 / r) / rk, q, rk
    return 1 / q


def aberth(t, z, maxit=100):
    """Ehrlich-Aberth on T from z: (roots, each root's recurrence evaluations until its
    correction fell below 1e-15 relative; maxit for a root that did not get there)."""
    a, e = np.diag(t).copy(), np.diag(t, 1) * np.diag(t, -1)
    z = np.array(z, dtype=complex)
    done = np.zeros(len(z), bool)
    evals = np.zeros(len(z), int)
    with np.errstate(all="ignore"):
        for _ in range(maxit):
            for i in np.flatnonzero(~done):
                evals[i] += 1
                nr = newton_ratio(a, e, z[i])
                w = nr / (1 - nr * np.sum(1 / (z[i] - np.delete(z, i))))
                if np.isfinite(w):
                    z[i] -= w
                done[i] = abs(w) <= 1e-15 * abs(z[i])
            if done.all():
                break
    return z, evals


def zeta_error(ev, ref):
    """Largest error of Re/|lambda| over ref's oscillatory eigenvalues, matched nearest."""
    osc = abs(ref.imag) > 1e-6 * abs(ref)
    z = np.array([ev[np.argmin(abs(ev - r))] for r in ref[osc]])
    return float(np.max(abs(z.real / abs(z) - ref[osc].real / abs(ref[osc]))))


def split_row(h, nn, anorm):
    """dlahqr's deflation test, as rr_hqr's split_row: the row l the block splits at."""
    for l in range(nn, 0, -1):
        s = abs(h[l - 1, l - 1]) + abs(h[l, l]) or anorm
        sub = abs(h[l, l - 1])
        if sub <= EPS * s:
            ab, ba = max(sub, abs(h[l - 1, l])), min(sub, abs(h[l - 1, l]))
            dd = abs(h[l - 1, l - 1] - h[l, l])
            aa, bb = max(abs(h[l, l]), dd), min(abs(h[l, l]), dd)
            if ba * (ab / (aa + ab)) <= max(np.finfo(float).tiny, EPS * (bb * (aa / (aa + ab)))):
                h[l, l - 1] = 0
                return l
    return 0


def transform(v, gauss):
    """G with G v = (alpha, 0, 0) and its inverse; whether rows were interchanged."""
    if not gauss:
        u = v.copy()
        u[0] += np.copysign(np.linalg.norm(v), v[0])
        g = np.eye(len(v)) - 2 * np.outer(u, u) / (u @ u)
        return g, g, False
    j = int(np.argmax(abs(v)))
    p = np.eye(len(v))
    p[[0, j]] = p[[j, 0]]
    li = np.eye(len(v))
    li[1:, 0] = -(p @ v)[1:] / (p @ v)[0]
    g = li @ p
    return g, np.linalg.inv(g), j != 0


def double_shift_sweep(h, l, nn, x, y, w, gauss, count):
    """One implicit double-shift sweep of rows l..nn; count: [steps, interchanges]."""
    for m in range(nn - 2, l - 1, -1):
        z, r, s = h[m, m], x - h[m, m], y - h[m, m]
        v = np.array([(r * s - w) / h[m + 1, m] + h[m, m + 1], h[m + 1, m + 1] - z - r - s, h[m + 2, m + 1]])
        if m == l or abs(h[m, m - 1]) * (abs(v[1]) + abs(v[2])) <= EPS * abs(v[0]) * (
                abs(h[m - 1, m - 1]) + abs(z) + abs(h[m + 1, m + 1])):
            break
    for i in range(m + 2, nn + 1):
        h[i, i - 2] = 0
        if i != m + 2:
            h[i, i - 3] = 0
    for k in range(m, nn):
        rows = list(range(k, min(k + 3, nn + 1)))
        if k != m:
            v = h[rows, k - 1].copy()
        if not v[:len(rows)].any():
            continue
        g, gi, swapped = transform(v[:len(rows)], gauss)
        count[0] += 1
        count[1] += swapped
        c0 = k - 1 if k > l else k
        h[rows, c0:nn + 1] = g @ h[rows, c0:nn + 1]
        h[l:min(k + 4, nn + 1), rows] = h[l:min(k + 4, nn + 1), rows] @ gi
        if k != m:
            h[rows[1:], k - 1] = 0


def double_shift_qr(h, gauss):
    """Eigenvalues by rr_hqr's iteration (its shifts, exceptional shifts, deflation)."""
    h = h.copy()
    n, nn, its, t = len(h), len(h) - 1, 0, 0.0
    ev, count = [], [0, 0]
    anorm = np.sum(abs(np.triu(h, -1)))
    while nn >= 0:
        l = split_row(h, nn, anorm)
        if l >= nn - 1:
            ev += list(np.linalg.eigvals(h[l:nn + 1, l:nn + 1]) + t)
            nn, its = l - 1, 0
            continue
        if its == 30 * max(n, 10):
            return None, count
        x, y, w = h[nn, nn], h[nn - 1, nn - 1], h[nn, nn - 1] * h[nn - 1, nn]
        if its and its % 10 == 0:
            t += x
            h[np.arange(nn + 1), np.arange(nn + 1)] -= x
            s = abs(h[nn, nn - 1]) + abs(h[nn - 1, nn - 2])
            x = y = 0.75 * s
            w = -0.4375 * s * s
        its += 1
        double_shift_sweep(h, l, nn, x, y, w, gauss, count)
    return np.array(ev), count


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    mats = matrices(build, int(sys.argv[2]) if len(sys.argv) > 2 else 10)
    refs = [np.linalg.eigvals(a) for a in mats]
    growth, zerr, evals_cold, evals_warm = [], [], [], []
    for i, (a, ref) in enumerate(zip(mats, refs)):
        t, g = tridiagonal(elmhes(a))
        growth.append(g)
        if t is None:
            continue
        zerr.append((g, zeta_error(np.linalg.eigvals(t), ref)))
        n, big = len(ref), np.max(abs(ref))
        cold = np.exp(2j * np.pi * (np.arange(n) + 0.25) / n) * np.geomspace(1, big, n)
        evals_cold += list(aberth(t, cold)[1])
        if i % 9 >= 2:  # warm: the previous conicity's eigenvalues, made distinct
            evals_warm += list(aberth(t, refs[i - 1] * (1 + 1e-9j * np.arange(1, n + 1)))[1])
    print("matrices %d (order %d)" % (len(mats), len(mats[0])))
    print("1. tridiagonal: multiplier growth median %.2g, breakdowns %d"
          % (np.median(growth), int(np.sum(np.isinf(growth)))))
    zerr = np.array(zerr)
    for cap in (1e2, 1e3, 1e4, 1e5):
        ok = zerr[:, 0] <= cap
        worst = "%.2g" % zerr[ok, 1].max() if ok.any() else "-"
        print("   growth <= %.0e: %.1f %% of matrices, their worst zeta error %s" % (cap, 100 * ok.mean(), worst))
    print("   Ehrlich-Aberth evaluations a root, median and mean: cold %.0f, %.1f; warm %.0f, %.1f"
          " (each ~%d flops)" % (np.median(evals_cold), np.mean(evals_cold), np.median(evals_warm),
                                 np.mean(evals_warm), 30 * len(mats[0])))
    for name, gauss in (("Householder (rr_hqr)", False), ("Gaussian with interchanges", True)):
        steps = swaps = 0
        worst = 0.0
        for a, ref in zip(mats, refs):
            ev, (st, sw) = double_shift_qr(elmhes(a), gauss)
            steps, swaps = steps + st, swaps + sw
            worst = max(worst, zeta_error(ev, ref) if ev is not None else np.inf)
        print("2. %s: %.0f bulge steps a matrix, %.1f %% with an interchange, worst zeta error %.2g"
              % (name, steps / len(mats), 100 * swaps / steps, worst))


if __name__ == "__main__":
    main()
