"""numpy doing the work of one railride vertical ride evaluation, vectorised,
written independently from the model's description (docs/vertical.md).

The default car (Table A1 values, the vertical model's assumed inertias,
length and bending mode), 350 km/h, the TB/T 3352 vertical spectrum (read
from spectra/tbt3352-vertical.txt), 400 log-spaced frequencies 0.3-30 Hz,
floor points +L, 0, -L. Per evaluation: the symmetric (3x3) and
antisymmetric (2x2) blocks and each frame's pitch solved as batched stacks
(the fastest numpy route; the 7x7 stack is also timed), the PSDs, RMS,
Sperling (filter and GB/T 5599 line methods), Wk, EN 12299 Wb and ISO 8041
Wb RMS, and the 5 s Wb RMS percentiles (the window kernel precomputed, as
railride's plan does; scipy's gammaincinv). Reads railride's
`ride --direction vertical --json` on stdin and prints the largest relative
difference of every index, then the times.
"""
import json
import sys
import time

import numpy as np
from scipy.special import gammaincinv, gammaln

mc, Icy, Lcb, fb, zb = 38936.0, 2.0e6, 25.0, 10.0, 0.02
mf, Ify, L, b = 2328.0, 2000.0, 8.6875, 1.25
kp, cp, ks, cs = 2 * 0.75e6, 2 * 10e3, 2 * 0.2e6, 2 * 10e3      # per wheelset, per bogie
v = 350 / 3.6
T = 5.0
f = np.geomspace(0.3, 30, 400)
f[-1] = 30.0
w = 2 * np.pi * f
xs = np.array([L, 0.0, -L])
bl = 4.730040744862704


def shape(x):
    be = bl / Lcb
    return -(np.cos(be * x) / np.cos(bl / 2) + np.cosh(be * x) / np.cosh(bl / 2))


phi = shape(np.array([L]))[0] / np.sqrt(mc)
phix = shape(xs) / np.sqrt(mc)
wb = 2 * np.pi * fb
Ms, Ma = np.array([mc, 1.0, 2 * mf]), np.array([Icy, 2 * mf])
Ks = 2 * ks * np.array([[1, phi, -1], [phi, phi**2, -phi], [-1, -phi, 1]]) + np.diag([0, wb**2, 4 * kp])
Cs = 2 * cs * np.array([[1, phi, -1], [phi, phi**2, -phi], [-1, -phi, 1]]) + np.diag([0, 2 * zb * wb, 4 * cp])
Ka = 2 * ks * np.array([[L * L, L], [L, 1]]) + np.diag([0, 4 * kp])
Ca = 2 * cs * np.array([[L * L, L], [L, 1]]) + np.diag([0, 4 * cp])
d = np.array([0, 2 * b, 2 * L, 2 * L + 2 * b])


SEGS = [[float(t) for t in line.split("=")[1].split()]
        for line in open("spectra/tbt3352-vertical.txt") if line.startswith("segment")]


def spectrum(n):
    segs = SEGS
    S = np.zeros_like(n)
    done = np.zeros(n.shape, bool)
    for i, (lo, hi, A, k) in enumerate(segs):
        sel = ~done & ((n <= hi) | (i == len(segs) - 1))
        S = np.where(sel, A / n**k, S)
        done |= sel
    return S * 1e-6


def iso2(f, f1, f2, f3, f4, q4, f5=0, q5=0, f6=0, q6=0, K=1.0):
    s = 2j * np.pi * f
    w1, w2, w3, w4 = (2 * np.pi * x for x in (f1, f2, f3, f4))
    Q = 1 / np.sqrt(2)
    H = (s * s / (s * s + w1 * s / Q + w1 * w1)) * (w2 * w2 / (s * s + w2 * s / Q + w2 * w2)) \
        * K * (1 + s / w3) / (1 + s / (q4 * w4) + s * s / (w4 * w4))
    if f5:
        w5, w6 = 2 * np.pi * f5, 2 * np.pi * f6
        H = H * (w5 / w6) ** 2 * (1 + s / (q5 * w5) + s * s / w5**2) / (1 + s / (q6 * w6) + s * s / w6**2)
    return np.abs(H) ** 2


def sperling2(f):
    f2 = f * f
    return 0.588**2 * (1.911 * f2 + (0.25 * f2) ** 2) / ((1 - 0.277 * f2) ** 2 + (1.563 * f - 0.0368 * f2 * f) ** 2)


# the plan: grid weightings, trapezoid weights, GB/T 5599 bands, window kernel
def plan():
    p = {"S2": sperling2(f), "Wk2": iso2(f, 0.4, 100, 12.5, 12.5, 0.63, 2.37, 0.91, 3.35, 0.91),
         "Wb2": iso2(f, 0.4, 100, 16, 16, 0.63, 2.5, 0.8, 4, 0.8, 1.024),
         "Wbi2": iso2(f, 0.4, 100, 16, 16, 0.55, 2.5, 0.9, 4, 0.95, 1.024)}
    tw = np.zeros_like(f)
    tw[:-1] += 0.5 * np.diff(f)
    tw[1:] += 0.5 * np.diff(f)
    p["tw"] = tw
    fc = 0.6 + 0.2 * np.arange(200)
    fc = fc[fc + 0.1 <= 30 * (1 + 1e-12)]
    p["fc"] = fc
    p["lo"] = np.searchsorted(f, fc, side="right") - 1
    p["t"] = (fc - f[p["lo"]]) / (f[p["lo"] + 1] - f[p["lo"]])
    p["Fgb"] = np.where(fc <= 5.9, 0.325 * fc**2, np.where(fc <= 20, 400 / fc**2, 1.0)) / fc
    p["Kmat"] = np.sinc((f[:, None] - f[None, :]) * T) ** 2 + np.sinc((f[:, None] + f[None, :]) * T) ** 2
    p["e"] = np.exp(-1j * np.outer(w, d) / v)   # the delays: fixed while speed and layout are
    return p


def cramer_blocks(w, e):
    """The symmetric 3x3 and antisymmetric 2x2 blocks solved by their
    adjugates, vectorised over the frequencies (numpy's fastest route: faster
    than np.linalg.solve on the stacks)."""
    jw, w2 = 1j * w, w * w
    a = Ks[0, 0] + jw * Cs[0, 0] - w2 * Ms[0]
    b = Ks[0, 1] + jw * Cs[0, 1]
    c = Ks[0, 2] + jw * Cs[0, 2]
    d = Ks[1, 1] + jw * Cs[1, 1] - w2 * Ms[1]
    ee = Ks[1, 2] + jw * Cs[1, 2]
    f = Ks[2, 2] + jw * Cs[2, 2] - w2 * Ms[2]
    zp = kp + jw * cp
    F1, F2 = zp * (e[:, 0] + e[:, 1]), zp * (e[:, 2] + e[:, 3])
    r2 = F1 + F2                                   # the symmetric force (on z_s only)
    c02, c12, c22 = b * ee - c * d, b * c - a * ee, a * d - b * b
    det = a * (d * f - ee * ee) + b * (c * ee - b * f) + c * c02
    zc, qb = c02 * r2 / det, c12 * r2 / det
    A = Ka[0, 0] + jw * Ca[0, 0] - w2 * Ma[0]
    B = Ka[0, 1] + jw * Ca[0, 1]
    D = Ka[1, 1] + jw * Ca[1, 1] - w2 * Ma[1]
    thc = -B * (F1 - F2) / (A * D - B * B)          # the antisymmetric force (on z_a only)
    return zc, qb, thc


def evaluate(p, Gt=None):
    """One evaluation; Gt given: the track's PSD set once (an optimiser's
    designs at one speed, as railride's rr_vertical_ride_design)."""
    e = p["e"]
    zc, qb, thc = cramer_blocks(w, e)
    H = -(w**2)[:, None] * (zc[:, None] - xs[None] * thc[:, None] + phix[None] * qb[:, None])
    if Gt is None:
        Gt = spectrum(f / v) / v
    G = Gt[:, None] * (H.real ** 2 + H.imag ** 2)
    tw = p["tw"][:, None]
    out = {"rms": np.sqrt((tw * G).sum(0)), "sperling": 4.42 * np.sqrt((tw * p["S2"][:, None] * G).sum(0)) ** 0.3,
           "wk_rms": np.sqrt((tw * p["Wk2"][:, None] * G).sum(0)),
           "wb_iso8041_rms": np.sqrt((tw * p["Wbi2"][:, None] * G).sum(0))}
    Gc = G[p["lo"]] + p["t"][:, None] * (G[p["lo"] + 1] - G[p["lo"]])
    A = np.sqrt(2 * Gc * 0.2)
    out["sperling_gb"] = 3.57 * (A**3 * p["Fgb"][:, None]).sum(0) ** 0.1
    U = tw * p["Wb2"][:, None] * G
    s2 = U.sum(0)
    V = (U * (p["Kmat"] @ U)).sum(0)
    k, th = s2 * s2 / V, V / s2
    x = gammaincinv(np.stack([k, k]), np.array([[0.5], [0.95]]))
    out["wb_rms"] = np.sqrt(s2)
    out["p50"], out["p95"] = np.sqrt(th * x[0]), np.sqrt(th * x[1])
    out["shape_k"] = k
    out["mean"] = np.sqrt(th) * np.exp(gammaln(k + 0.5) - gammaln(k))
    return out


def evaluate_7x7(p):
    """the same FRF from the 7x7 stack (for the time only)"""
    M7 = np.diag([mc, Icy, 1, mf, Ify, mf, Ify])
    K7 = np.zeros((7, 7))
    C7 = np.zeros((7, 7))
    for i, xf in enumerate((L, -L)):
        J = np.zeros(7)
        J[[0, 1, 2, 3 + 2 * i]] = 1, -xf, phi, -1
        K7 += ks * np.outer(J, J)
        C7 += cs * np.outer(J, J)
    BK, BC = np.zeros((7, 4)), np.zeros((7, 4))
    for j in range(4):
        J = np.zeros(7)
        sj = 1 if j % 2 == 0 else -1
        J[3 + 2 * (j // 2)], J[4 + 2 * (j // 2)] = 1, -sj * b
        K7 += kp * np.outer(J, J)
        C7 += cp * np.outer(J, J)
        BK[:, j], BC[:, j] = kp * J, cp * J
    K7[2, 2] += wb**2
    C7[2, 2] += 2 * zb * wb
    D = K7[None] + 1j * w[:, None, None] * C7[None] - (w**2)[:, None, None] * M7[None]
    r = (BK[None] + 1j * w[:, None, None] * BC[None]) @ np.exp(-1j * np.outer(w, d) / v)[..., None]
    return np.linalg.solve(D, r)


def timeit(fn, reps):
    fn()
    best = []
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(reps):
            fn()
        best.append((time.perf_counter() - t0) / reps * 1e6)
    return float(np.median(best))


p = plan()
out = evaluate(p)
ref = json.load(sys.stdin)["points"]
worst = 0.0
for q, pt in enumerate(ref):
    for k, mine in (("rms", out["rms"]), ("sperling", out["sperling"]), ("sperling_gb", out["sperling_gb"]),
                    ("wk_rms", out["wk_rms"]), ("wb_rms", out["wb_rms"]), ("wb_iso8041_rms", out["wb_iso8041_rms"])):
        worst = max(worst, abs(mine[q] / pt[k] - 1))
    for k in ("p50", "p95", "shape_k", "mean"):
        worst = max(worst, abs(out[k][q] / pt["wb_5s"][k] - 1))
print("numpy_vertical_indices p95 %s sperling %s; largest relative difference from railride %.2e" % (
    np.round(out["p95"], 5), np.round(out["sperling"], 4), worst))
Gt0 = spectrum(f / v) / v
print("numpy_vertical_evaluation_us %.1f  (with the plan: %.1f us; the 7x7 stack solve alone %.1f us)" % (
    timeit(lambda: evaluate(p), 200), timeit(lambda: evaluate(plan()), 20), timeit(lambda: evaluate_7x7(p), 200)))
print("numpy_vertical_design_us %.1f  (the track's PSD set once)" % timeit(lambda: evaluate(p, Gt0), 200))
