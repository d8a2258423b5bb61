"""numpy/scipy doing the modal work railride does, on the same matrices.

Reads `railride matrices --json` output (the state matrix A and the 17x17
M, C, K and Maxwell rows) from stdin and times eigenvalues-only, eigenvalues
with vectors, and the robust triple's 9 solves as numpy would do them.
"""
import json
import sys
import time

import numpy as np
import scipy.linalg as sl

d = json.load(sys.stdin)
A = np.array(d["A"])


def timeit(fn, reps):
    fn()
    t0 = time.perf_counter()
    for _ in range(reps):
        fn()
    return (time.perf_counter() - t0) / reps * 1e6


quick = "index" in sys.argv[1:]  # only the figures bench/run.sh pairs with railride's
print("numpy_eigvals_us %.1f" % timeit(lambda: np.linalg.eigvals(A), 3000))
if quick:
    stack = np.repeat(A[None, :, :], 200, axis=0) * (1 + 1e-9 * np.arange(200))[:, None, None]
    print("numpy_eigvals_batched_us_per_matrix %.1f" % (timeit(lambda: np.linalg.eigvals(stack), 10) / 200))
    print("numpy_robust_triple_batched_us %.1f" % timeit(lambda: np.linalg.eigvals(stack[:9].copy()), 300))
    sys.exit(0)
print("scipy_eigvals_nobalance_us %.1f" % timeit(lambda: sl.eigvals(A, check_finite=False, overwrite_a=False), 3000))
print("numpy_eig_vectors_us %.1f" % timeit(lambda: np.linalg.eig(A), 1000))
print("numpy_robust_triple_us %.1f" % timeit(lambda: [np.linalg.eigvals(A) for _ in range(9)], 300))
# numpy at its best: one call over a stack of state matrices (no Python loop
# per matrix; LAPACK's dgeev per slice inside numpy), the time per matrix --
# the baseline for railride's batched index (lanes across designs)
stack = np.repeat(A[None, :, :], 1000, axis=0) * (1 + 1e-9 * np.arange(1000))[:, None, None]
print("numpy_eigvals_batched_us_per_matrix %.1f" % (timeit(lambda: np.linalg.eigvals(stack), 5) / 1000))
nine = stack[:9].copy()
print("numpy_robust_triple_batched_us %.1f" % timeit(lambda: np.linalg.eigvals(nine), 300))
