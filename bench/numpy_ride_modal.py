"""numpy doing one ride evaluation the way railride does it: by modes, not by
a solve per frequency. The same inputs and outputs as numpy_ride.py (its
spectrum, weightings and index code are reused), a different algorithm:

- the state matrix with the Maxwell elements as states, the yaw dampers' series
  stiffness held at a reference value k_ref (the paper-mode curve's value at 0 Hz);
- one np.linalg.eig of it (LAPACK dgeev) and one solve for the left factors;
- every frequency's modal sums as matrix products of the weights 1 / (jw - lambda);
- the SDF's frequency dependence as a rank-4 Sherman-Morrison-Woodbury correction:
  D = D_ref + U diag(dk(w)) U', one batched 4 x 4 solve for the 400 frequencies.

It gives numpy_ride.py's indices (checked below to 1e-9) in a fraction of its
time: this, not the solve per frequency, is the best numpy baseline for
railride's ride evaluation (bench/run.sh pairs railride with both).
"""
import json
import sys
import time

import numpy as np

import numpy_ride as nr

d = nr.d
M, C, K, B = nr.M, nr.C, nr.K, nr.B
n = M.shape[0]
w = nr.w
mx = d["maxwell"]
J = np.array([m["J"] for m in mx])  # (6, 17) element rows
cs = np.array([m["c"] for m in mx], dtype=float)
yaw = nr.yaw
K_REF = 6e6  # the paper-mode k_sdf at 0 Hz
kref = np.where(yaw, K_REF, np.array([m["k"] for m in mx], dtype=float))
ne = len(mx)
Minv = np.linalg.inv(M)


def state_matrix():
    """x = (q, q', u): u_e the damper's own stroke, F_e = k_e (J_e q - u_e) = c_e u_e'."""
    N = 2 * n + ne
    A = np.zeros((N, N))
    A[:n, n:2 * n] = np.eye(n)
    Kq = K + (J.T * kref) @ J
    A[n:2 * n, :n] = -Minv @ Kq
    A[n:2 * n, n:2 * n] = -Minv @ C
    A[n:2 * n, 2 * n:] = Minv @ (J.T * kref)
    A[2 * n:, :n] = (kref / cs)[:, None] * J
    A[2 * n:, 2 * n:] = -np.diag(kref / cs)
    return A


U = J[yaw].T  # (17, 4): the SDF elements' rows
XSDF = nr.f / 1.5
KSDF = 6e6 + 8e6 * XSDF**2 / (1 + XSDF**2)
jw = 1j * w


def ke(k, c):
    return k * c * jw[:, None] / (k + c * jw[:, None])


DK = ke(KSDF[:, None], cs[yaw][None, :]) - ke(K_REF, cs[yaw][None, :])  # (400, 4)
RB = B @ nr.LAG.T  # (17, 400): each frequency's lagged input sum


def floor_q():
    """The floor points' displacement rows, then U' (the SDF elements' strokes)."""
    return np.vstack([nr.rows, U.T])  # (7, 17)


R7 = floor_q()


def evaluate():
    """The floor points' displacements at every frequency (400, 3)."""
    lam, V = np.linalg.eig(state_matrix())
    # the inputs enter the velocity rows as M^-1 F
    Fin = np.zeros((V.shape[0], 8))
    Fin[n:2 * n, :4] = Minv @ B
    Fin[n:2 * n, 4:] = Minv @ U
    P = np.linalg.solve(V, Fin)  # (N, 8): the left factors times the inputs and SDF rows
    Rv = R7 @ V[:n]  # (7, N): the outputs and strokes through each mode
    Wt = 1.0 / (jw[:, None] - lam[None, :])  # (400, N)
    # the reference system's response to the lagged inputs (X0) and to the SDF rows (GU)
    X0 = (Wt * (nr.LAG @ P[:, :4].T)) @ Rv.T  # (400, 7)
    GU = (Wt @ (Rv.T[:, :, None] * P[:, None, 4:]).reshape(len(lam), -1)).reshape(-1, 7, 4)
    S = np.eye(4)[None] + DK[:, :, None] * GU[:, 3:]
    y = np.linalg.solve(S, (DK * X0[:, 3:])[..., None])  # (400, 4, 1)
    return X0[:, :3] - (GU[:, :3] @ y)[..., 0]


def indices():
    return nr.comfort(-(w**2)[:, None] * evaluate())


if __name__ == "__main__":
    direct = nr.indices(nr.build())
    modal = indices()
    for a, b in zip(direct, modal):
        if not np.allclose(a, b, rtol=1e-9, atol=0):
            sys.exit("numpy_ride_modal: indices differ from the direct solve: %s %s" % (a, b))
    if "--indices" in sys.argv:  # both routes' indices in full, no timing (tests/test_ride_numpy.py)
        keys = ("sperling", "sperling_gb", "wd_rms")
        print(json.dumps({route: {k: list(v) for k, v in zip(keys, r)}
                          for route, r in (("direct", direct), ("modal", modal))}))
        sys.exit(0)
    print("numpy_ride_modal_indices sperling %s gb %s wd %s" % tuple(np.round(v, 5) for v in modal))
    times = sorted(nr.timeit(indices, 40) for _ in range(9))  # median of 9 batches: the VM drifts
    print("numpy_ride_modal_evaluation_us %.1f  (median of 9 batches of 40, best %.1f; eig alone %.1f us)" % (
        times[4], times[0], nr.timeit(lambda: np.linalg.eig(state_matrix()), 200)))
