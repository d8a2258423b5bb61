"""numpy/scipy doing railride's paper-mode SDF stability index the way the
model contract describes it (the reference tracking): every oscillatory mode
of the k_lo model followed as the yaw dampers' series stiffness rises to k_hi,
a full eigen-solve with vectors at each step (first step (k_hi-k_lo)/32,
halved while consecutive shapes correlate less than MAC 0.9), the sign change
of h(k) = k - k_sdf(f(k)) bisected to 1e-9 k_hi; then the index over the
self-consistent hunting-related modes below 10 Hz.

Reads `railride matrices VEHICLE --json` (M, C, K, the Maxwell rows) from
stdin; K1 (Hz), K2, K3 (N/m) of the SDF curve as arguments. Prints the index
it finds (a cross-check of railride's) and the time of one evaluation.
"""
import json
import sys
import time

import numpy as np

d = json.load(sys.stdin)
K1, K2, K3 = (float(a) for a in sys.argv[1:4])
M = np.array(d["M"])
C = np.array(d["C"])
Kq = np.array(d["K"])
dofs = d["dofs"]
mx = d["maxwell"]
n = M.shape[0]
N = 2 * n + len(mx)
Minv = np.linalg.inv(M)
mdiag = np.diag(M)
wheel = np.array([name.endswith(("w1", "w2", "w3", "w4")) for name in dofs])
roll = np.array([name.startswith("phi_") for name in dofs])


def k_sdf(f):
    x = f / K1
    return K3 + K2 * x * x / (1 + x * x)


def state_matrix(k):
    A = np.zeros((N, N))
    A[:n, n:2 * n] = np.eye(n)
    Kt = Kq.copy()
    for m, e in enumerate(mx):
        J = np.array(e["J"])
        km = k if e["sdf"] else e["k"]
        Kt += km * np.outer(J, J)
        A[n:2 * n, 2 * n + m] = Minv @ (km * J)
        A[2 * n + m, :n] = km / e["c"] * J
        A[2 * n + m, 2 * n + m] = -km / e["c"]
    A[n:2 * n, :n] = -Minv @ Kt
    A[n:2 * n, n:2 * n] = -Minv @ C
    return A


def modes(k):
    lam, V = np.linalg.eig(state_matrix(k))
    keep = lam.imag >= 0
    lam, Q = lam[keep], V[:n, keep]
    return lam, Q / np.linalg.norm(Q, axis=0)


def mac(a, b):
    return abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)


def oscillatory(l):
    return l.imag > 1e-6 * abs(l)


def h(k, l):
    return k - k_sdf(l.imag / (2 * np.pi))


def best(k, phi):
    lam, Q = modes(k)
    macs = [mac(phi, Q[:, j]) for j in range(Q.shape[1])]
    j = int(np.argmax(macs))
    return macs[j], lam[j], Q[:, j]


def track(l, phi, k_lo, k_hi):
    k, step = k_lo, (k_hi - k_lo) / 32
    if h(k, l) >= 0:
        return l, phi
    while True:
        kn = min(k + step, k_hi)
        m, ln, qn = best(kn, phi)
        if m < 0.9:
            step *= 0.5
            if step < 1e-12 * k_hi:
                return None
            continue
        if not oscillatory(ln):
            return None
        if h(kn, ln) >= 0:
            break
        k, l, phi = kn, ln, qn
        if k >= k_hi:
            return None
    ka, kb, phia, res = k, kn, phi, (ln, qn)
    while kb - ka > 1e-9 * k_hi:
        km = 0.5 * (ka + kb)
        m, lm, qm = best(km, phia)
        if not oscillatory(lm):
            return None
        if h(km, lm) >= 0:
            kb, res = km, (lm, qm)
        else:
            ka, phia = km, qm
    return res


def index(fmax=10.0, w_min=1e-3, r_max=0.5):
    k_lo, k_hi = K3, K3 + K2
    lam, Q = modes(k_lo)
    z = -1.0
    for j in range(len(lam)):
        if not oscillatory(lam[j]):
            continue
        r = track(lam[j], Q[:, j], k_lo, k_hi)
        if r is None:
            continue
        l, phi = r
        e = mdiag * abs(phi) ** 2
        e /= e.sum()
        if l.imag / (2 * np.pi) <= fmax and e[wheel].sum() >= w_min and e[roll].sum() < r_max:
            z = max(z, l.real / abs(l))
    return z


t0 = time.perf_counter()
z = index()
t = time.perf_counter() - t0
print("numpy_sdf_index %.6f" % z)
print("numpy_sdf_index_ms %.1f" % (t * 1e3))
