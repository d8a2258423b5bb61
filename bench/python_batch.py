"""Python's batch evaluation against C's on the same designs (paper objectives)."""
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import railride  # noqa: E402

lo = np.array([10e6, 5e3, 100e3, 1e6])
hi = np.array([120e6, 60e3, 4000e3, 30e6])
d = railride.Design("type1", ["primary.longitudinal_stiffness", "lateral_damper.damping",
                              "yaw_damper.damping", "yaw_damper.series_stiffness"],
                    ["zeta_low", "zeta_high", "std_zeta"], threads=int(os.environ.get("THREADS", "1")))
rng = np.random.default_rng(1)
d.evaluate_batch(lo + (hi - lo) * rng.random((64, 4)))
for n in (1000, 4000):
    x = lo + (hi - lo) * rng.random((n, 4))
    t0 = time.perf_counter()
    d.evaluate_batch(x)
    print("python_batch_%d_designs_per_s %.0f" % (n, n / (time.perf_counter() - t0)))
