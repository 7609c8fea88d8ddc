"""The tutorial (docs/tutorial.rst): solve a pendulum swing-up, certify it, combine two goals.

python examples/tutorial.py            # 201² grid, about half a minute
python examples/tutorial.py --quick    # 61² grid, a few seconds
"""

import argparse

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import Pendulum

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--quick", action="store_true", help="61² grid and 100 samples")
args = parser.parse_args()
n, samples = (61, 100) if args.quick else (201, 400)

# θ from the upright (periodic), ω in rad/s; λ = 1, R = 1, swing up to the upright in T = 3 s.
grid = Grid([Axis(-np.pi, np.pi, n, periodic=True), Axis(-10, 10, n)])
problem = Problem(Pendulum(), grid, horizon=3.0, terminal_cost=Quadratic([0, 0], [10, 0.5]))
solution = gridlbc.solve(problem)  # splitting, fitted to g (the default)
x0 = np.array([2.8, 0.0])  # near hanging down, at rest
print("v(x0) =", solution.value(x0, 0.0), " u*(x0) =", solution.policy(x0, 0.0))

# Is the prediction honest? Certify it: the true optimum v*(x0) by importance sampling on the
# SDE with this policy as proposal, the policy's own cost J and the gap J − v*; richardson=True
# also certifies at twice the step and extrapolates the Euler–Maruyama step's bias away.
certificate = gridlbc.certify(
    problem, solution.policy, x0, n_samples=samples, dt=0.002, seed=0, richardson=True
)
print(certificate.summary())

# Two goals, one operator (fitted to both); combine them (w = 1) without solving again.
left, right = gridlbc.solve_many(
    problem, [Quadratic([-0.6, 0], [10, 0.5]), Quadratic([0.6, 0], [10, 0.5])]
)
both = gridlbc.combine([left, right])  # optimal for g = −λ log(e^{−g₁/λ} + e^{−g₂/λ})
print("α(x0) =", both.blend_weights(x0, 0.0))  # α_i = w_i z_i / Σ w_j z_j
