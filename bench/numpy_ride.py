"""numpy doing the work of one railride ride evaluation, vectorised as far
as numpy goes: D(jw) at every frequency as one matrix product of the
stacked frequency coefficients, one batched solve of the lagged input sum,
the floor rows, weighted integrals and GB/T bands as products.

From `railride matrices --json` (stdin: M, C, K, B and the Maxwell rows of the
default vehicle at 350 km/h, conicity 0.17): builds D(jw) = K - w^2 M + jw C +
sum J' k_e(jw) J at 400 log-spaced frequencies 0.3-30 Hz with the paper-mode
SDF k_sdf(f) on the yaw dampers (K1 1.5 Hz, K2 8 MN/m, K3 6 MN/m), solves the
(400, 17, 17) stack for the 4 wheelset inputs, forms the floor acceleration at
3 points with the PEM lags and the Wuhan-Guangzhou (TB/T 3352) alignment
spectrum, and computes Sperling (filter and GB/T 5599 line methods) and the
ISO 8041 Wd RMS at each point: the same steps as railride's evaluation (frf
plan execute, PEM PSD, comfort indices). Prints the indices (a cross-check)
and the time per evaluation, with and without building D.
"""
import json
import sys
import time

import numpy as np

d = json.load(sys.stdin)
M, C, K, B = (np.array(d[k]) for k in "MCKB")
f = np.geomspace(0.3, 30, 400)
w = 2 * np.pi * f
v = 350 / 3.6
L, b, hc, hp = 8.6875, 1.25, 1.62, 1.2
xin = np.array([L + b, L - b, -L + b, -L - b])
JJ = np.array([np.outer(mx["J"], mx["J"]).ravel() for mx in d["maxwell"]])   # (6, 289)
yaw = np.array([mx["name"].startswith("yaw") for mx in d["maxwell"]])
cs = np.array([mx["c"] for mx in d["maxwell"]])
ks = np.array([mx["k"] for mx in d["maxwell"]], dtype=float)
rows = np.zeros((3, 17))
for q, x in enumerate((L, 0.0, -L)):
    rows[q, 0], rows[q, 1], rows[q, 2] = 1.0, x, -(hp - hc)
SEG = [(0.005, 0.045, 0.0039513, 1.867), (0.045, 0.1234, 0.011047, 1.5354), (0.1234, 0.5, 0.00075633, 2.8171)]


def spectrum(n):
    """TB/T 3352 alignment, m^2/(1/m), end segments extended."""
    S = np.empty_like(n)
    for i, (lo, hi, A, k) in enumerate(SEG):
        sel = (n >= lo if i else True) & (n < hi if i < len(SEG) - 1 else True)
        S = np.where(sel, A / n**k, S) if i else A / n**k
    return S * 1e-6


BASIS = np.vstack([K.ravel(), M.ravel(), C.ravel(), JJ]).astype(complex)   # (9, 289)
XSDF = f / 1.5
KYAW = 6e6 + 8e6 * XSDF**2 / (1 + XSDF**2)   # the paper-mode k_sdf(f), once per grid


def build():
    """D(jw) for the 400 frequencies as one matrix product: the frequency
    coefficients [1, -w^2, jw, k_e(jw) of each Maxwell element] stacked
    against [K, M, C, J J' ...]."""
    jw = 1j * w[:, None]
    k = np.where(yaw[None, :], KYAW[:, None], ks[None, :])   # (400, 6)
    ke = k * cs * jw / (k + cs * jw)
    coef = np.hstack([np.ones((400, 1)), -(w**2)[:, None], jw, ke])   # (400, 9)
    return (coef @ BASIS).reshape(400, 17, 17)


def sperling2(f):
    f2 = f * f
    num = 1.911 * f2 + (0.25 * f2) ** 2
    return 1.25**2 * 0.588**2 * num / ((1 - 0.277 * f2) ** 2 + (1.563 * f - 0.0368 * f2 * f) ** 2)


def wd2(f):
    s = 2j * np.pi * f
    w1, w2, w3, w4, Q = 2 * np.pi * 0.4, 2 * np.pi * 100, 2 * np.pi * 2, 2 * np.pi * 2, 1 / np.sqrt(2)
    H = (s * s / (s * s + w1 * s / Q + w1 * w1)) * (w2 * w2 / (s * s + w2 * s / Q + w2 * w2)) \
        * (1 + s / w3) / (1 + s / (0.63 * w4) + s * s / (w4 * w4))
    return np.abs(H) ** 2


def trapz(y):
    return ((y[1:] + y[:-1]) * 0.5 * np.diff(f)[:, None]).sum(axis=0)


fc = 0.6 + 0.2 * np.arange(int((30 - 0.5) / 0.2 + 1e-9))
fc = fc[fc + 0.1 <= 30 * (1 + 1e-12)]
Fgb = np.where(fc <= 5.4, 0.8 * fc**2, np.where(fc <= 26, 650 / fc**2, 1.0))
Gt = spectrum(f / v) / v
S2, W2 = sperling2(f)[:, None], wd2(f)[:, None]   # grid weightings, once (as railride's comfort plan)


LAG = np.exp(1j * np.outer(w, xin) / v)   # the inputs' lags, fixed at one speed
RHS = (B[None] @ LAG[:, :, None])           # (400, 17, 1): the lagged sum of the inputs
LO = np.searchsorted(f, fc, side="right") - 1
TT = ((fc - f[LO]) / (f[LO + 1] - f[LO]))[:, None]
TW = np.zeros(400)
TW[:-1] += 0.5 * np.diff(f)
TW[1:] += 0.5 * np.diff(f)
WTS = np.stack([TW * S2[:, 0], TW * W2[:, 0]], axis=1)   # trapezoid x weighting, once


def indices(D):
    """One solve per frequency for the lagged sum (all the PSD needs), the
    floor rows as one product, the weighted integrals as one product and the
    GB/T bands by precomputed interpolation."""
    X = np.linalg.solve(D, RHS)[..., 0]                 # (400, 17)
    return comfort(-(w**2)[:, None] * (X @ rows.T))     # (400, 3) floor accelerations


def comfort(H):
    """Sperling (filter, GB/T 5599) and the Wd RMS from the floor accelerations H (400, 3)."""
    G = (H.real**2 + H.imag**2) * Gt[:, None]
    sw = WTS.T @ G                                      # (2, 3)
    wz = 4.42 * np.sqrt(sw[0]) ** 0.3
    A = np.sqrt(2 * (G[LO] + TT * (G[LO + 1] - G[LO])) * 0.2)
    wgb = 3.57 * ((A**3 * (Fgb / fc)[:, None]).sum(axis=0)) ** 0.1
    return wz, wgb, np.sqrt(sw[1])


def timeit(fn, reps):
    fn()
    t0 = time.perf_counter()
    for _ in range(reps):
        fn()
    return (time.perf_counter() - t0) / reps * 1e6


if __name__ == "__main__":
    wz, wgb, awd = indices(build())
    print("numpy_ride_indices sperling %s gb %s wd %s" % (np.round(wz, 4), np.round(wgb, 4), np.round(awd, 5)))
    D = build()
    print("numpy_ride_evaluation_us %.1f  (build D %.1f us, solve and indices %.1f us)" % (
        timeit(lambda: indices(build()), 50), timeit(build, 50), timeit(lambda: indices(D), 50)))
