"""Convergence under grid refinement: the grid solver's value against the exact Riccati value on
a linear-quadratic point mass, as the spacing h halves (default fitted splitting, Courant 2).

On this problem log z is quadratic, which the fitted scheme reproduces, so its error is the time
splitting's, and the step halves with h: expect the error to fall about fourfold per halving.
The plain operator (``fitting=None``) converges at first order.

    python examples/convergence.py [--out figures] [--quick]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc.reference import lq_solution
from gridlbc.studies.problems import pointmass_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="two coarse grids, a few seconds")
args = parser.parse_args()
spacings = (1 / 2, 1 / 4) if args.quick else (1 / 4, 1 / 8, 1 / 16, 1 / 32)

# Evaluation states away from the box edges, where the reflecting walls do not bend the value,
# and where the value is within 5 of its minimum (the states an optimal controller visits).
position, velocity = np.meshgrid(np.linspace(-2, 2, 41), np.linspace(-3, 3, 61))
states = np.column_stack([position.ravel(), velocity.ravel()])
exact = lq_solution(pointmass_problem(spacings[0])).value(states, 0.0)
states, exact = states[exact < exact.min() + 5], exact[exact < exact.min() + 5]

errors = []
for h in spacings:
    solution = gridlbc.solve(pointmass_problem(h), courant=2.0, min_steps=1)
    error = np.abs(solution.value(states, 0.0) - exact)
    errors.append(error.max())
    print(f"h = {h:<7g} max |v − v_Riccati| = {errors[-1]:.4f}")
orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
print("observed orders:", np.round(orders, 2).tolist())

fig, ax = plt.subplots(figsize=(5, 4), constrained_layout=True)
ax.loglog(spacings, errors, "o-", label="fitted splitting (the default)")
ax.loglog(spacings, errors[0] * (np.array(spacings) / spacings[0]), "k:", label="order 1")
ax.loglog(spacings, errors[0] * (np.array(spacings) / spacings[0]) ** 2, "k--", label="order 2")
ax.set(
    xlabel="grid spacing h",
    ylabel="max |v − v_Riccati| at t = 0",
    title="PointMass LQ: value error under refinement",
)
ax.legend()
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "convergence_example.png", dpi=110)
print("wrote", out / "convergence_example.png")
