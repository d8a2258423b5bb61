"""numpy solving the same batched systems as one railride ride evaluation.

Builds D(jw) = K - w^2 M + jw C + sum J' k_e(jw) J for the default vehicle at
350 km/h, conicity 0.17, with the paper-mode SDF k_sdf(f) on the yaw dampers
(K1 1.5 Hz, K2 8 MN/m, K3 6 MN/m) at 400 log-spaced frequencies from
`railride matrices --json` (stdin), then times np.linalg.solve on the
(400, 17, 17) stack with the 4 wheelset inputs, plus the PEM sum and the
floor acceleration at 3 points: the same work as the C evaluation.
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


def build():
    D = K[None] - (w**2)[:, None, None] * M[None] + 1j * w[:, None, None] * C[None]
    for mx in d["maxwell"]:
        J = np.array(mx["J"])
        c = mx["c"]
        if mx["name"].startswith("yaw"):
            x = f / 1.5
            k = 6e6 + 8e6 * x**2 / (1 + x**2)
        else:
            k = np.full_like(f, mx["k"])
        ke = k * c * 1j * w / (k + c * 1j * w)
        D += ke[:, None, None] * np.outer(J, J)[None]
    return D


D = build()
rows = np.zeros((3, 17))
for q, x in enumerate((L, 0.0, -L)):
    rows[q, 0], rows[q, 1], rows[q, 2] = 1.0, x, -(hp - hc)


def evaluate():
    X = np.linalg.solve(D, np.broadcast_to(B, (400, 17, 4)))
    H = -(w**2)[:, None, None] * np.einsum("pn,fni->fpi", rows, X)
    lag = np.exp(1j * np.outer(w, xin) / v)
    return np.abs(np.einsum("fpi,fi->fp", H, lag)) ** 2


evaluate()
reps = 100
t0 = time.perf_counter()
for _ in range(reps):
    evaluate()
t_solve = (time.perf_counter() - t0) / reps
t0 = time.perf_counter()
for _ in range(reps):
    build()
t_build = (time.perf_counter() - t0) / reps
print("numpy_batched_solve_us %.1f  (building the 400 D matrices: %.1f us more)" % (t_solve * 1e6, t_build * 1e6))
