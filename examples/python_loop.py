"""Drive railride from a plain Python loop: a random search over two yaw
damper parameters for the most robust design (smallest zeta_high).

    PYTHONPATH=python python3 examples/python_loop.py
"""
import numpy as np

import railride

rng = np.random.default_rng(1)
lo = np.array([100e3, 1e6])      # yaw_damper.damping (N s/m), series_stiffness (N/m)
hi = np.array([4000e3, 30e6])
with railride.Design("type1", variables=["yaw_damper.damping", "yaw_damper.series_stiffness"],
                     objectives=["zeta_high", "index@300,0.2"]) as d:
    best = None
    for it in range(5):
        x = lo + (hi - lo) * rng.random((200, 2))
        f = d.evaluate_batch(x)
        i = np.nanargmin(f[:, 0])
        if best is None or f[i, 0] < best[1][0]:
            best = (x[i], f[i])
        print("round %d: best zeta_high %.5f at c = %.0f kN.s/m, k = %.2f MN/m"
              % (it, best[1][0], best[0][0] / 1e3, best[0][1] / 1e6))
