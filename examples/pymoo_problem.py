"""The paper's optimisation shaped as a pymoo problem.

With pymoo installed, this runs pymoo's NSGA-II on railride's batch
evaluation. pymoo is not installable here, so without it the script runs the
evaluation part on a random population, exactly as pymoo would call it.

    PYTHONPATH=python python3 examples/pymoo_problem.py
"""
import numpy as np

import railride

VARIABLES = ["primary.longitudinal_stiffness", "lateral_damper.damping",
             "yaw_damper.damping", "yaw_damper.series_stiffness"]
LOWER = np.array([10e6, 5e3, 100e3, 1e6])      # SI: N/m, N s/m, N s/m, N/m
UPPER = np.array([120e6, 60e3, 4000e3, 30e6])


class PaperProblem:
    """pymoo's ElementwiseProblem-free interface: _evaluate(x, out) on a batch."""

    n_var, n_obj, xl, xu = 4, 3, LOWER, UPPER

    def __init__(self):
        self.design = railride.Design("type1", VARIABLES, ["zeta_low", "zeta_high", "std_zeta"])

    def _evaluate(self, x, out, *args, **kwargs):
        out["F"] = self.design.evaluate_batch(x)


try:
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    class PymooPaperProblem(Problem):
        def __init__(self):
            super().__init__(n_var=4, n_obj=3, xl=LOWER, xu=UPPER)
            self.inner = PaperProblem()

        def _evaluate(self, x, out, *args, **kwargs):
            self.inner._evaluate(x, out)

    res = minimize(PymooPaperProblem(), NSGA2(pop_size=100), ("n_gen", 20), seed=1, verbose=False)
    print("pymoo NSGA-II: %d non-dominated designs" % len(res.F))
except ImportError:
    problem = PaperProblem()
    x = LOWER + (UPPER - LOWER) * np.random.default_rng(1).random((100, 4))
    out = {}
    problem._evaluate(x, out)
    F = out["F"]
    print("pymoo not installed: evaluated a population of %d as pymoo would; "
          "zeta_low %.4f..%.4f, zeta_high %.4f..%.4f, std %.4f..%.4f"
          % (len(F), F[:, 0].min(), F[:, 0].max(), F[:, 1].min(), F[:, 1].max(), F[:, 2].min(), F[:, 2].max()))
