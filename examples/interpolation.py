"""Interpolation: a controller for a goal between two solved goals, by projection and linear
Bellman combination, against the naive blend of the two policies; every cost certified.

A point in the plane (dx = u dt + noise) starts in front of a disc obstacle and must come to
rest at a target behind it; the solved components come to rest on either side of the target
(the task of ``figures/interpolation.png``, at a smaller size). Expect LBC to be the cheapest on
the composite task it solves exactly, but by little, and the naive blend to end nearer the
target: the exact combination's final law is the mixture of the components' final laws (the
README's interpolation paragraph).

    python examples/interpolation.py [--out figures] [--quick]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Quadratic
from gridlbc.studies.problems import (
    OBSTACLE_GOALS,
    OBSTACLE_START,
    OBSTACLE_TARGET,
    OBSTACLE_WEIGHTS,
    obstacle_problem,
)

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="41×33 grid and 200 samples")
args = parser.parse_args()
n, samples = (41, 200) if args.quick else (61, 1000)
dt = 0.02 if args.quick else 0.01  # the obstacle's cost is stiff (q/λ = 300 inside): small steps

# The task: T = 4, λ = 0.1, target g = 5(x − cx)² + 0.5(y − cy)² at c = (−2.2, 0).
problem = obstacle_problem(n)
target = problem.terminal_cost
goals = [Quadratic(c, OBSTACLE_WEIGHTS) for c in OBSTACLE_GOALS]

# Two components solved together (one fitted operator: they combine exactly), and the weights
# that aim them at the target.
upper, lower = gridlbc.solve_many(problem, goals, dt=dt)
weights = gridlbc.project(target, goals, problem.grid, temperature=problem.temperature)
lbc = gridlbc.combine([upper, lower], weights)  # exact for g_w = −λ log Σ w_i exp(−g_i/λ)
controllers = {
    "goal y = +0.35 alone": upper.policy,
    "goal y = −0.35 alone": lower.policy,
    "naive blend": gridlbc.naive_blend([upper, lower], weights).policy,
    "LBC": lbc.policy,
}
print("projected weights", np.round(weights, 4), "exact combination:", lbc.exact)

# Certify each controller on the composite task (importance sampling, any policy as proposal);
# one seed drives every controller with the same noise, so cost differences are paired.
fig, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
for name, policy in controllers.items():
    cert = gridlbc.certify(lbc.problem, policy, OBSTACLE_START, samples, dt=dt, seed=0,
                           progress=False)
    final = cert.final_states
    distance = np.hypot(*(final - OBSTACLE_TARGET).T)
    print(f"{name:21s} cost {cert.policy_cost:.3f} ± {cert.policy_cost_se:.3f}, gap to the "
          f"certified optimum {cert.gap:+.3f} ± {cert.gap_se:.3f}, mean final y "
          f"{final[:, 1].mean():+.2f}, mean distance to the target {distance.mean():.2f}")
    ax.hist(final[:, 1], bins=np.linspace(-1.5, 1.5, 61), histtype="step", lw=2,
            label=f"{name}: J = {cert.policy_cost:.3f}")
ax.set(xlabel="final y_T (target 0, goals ±0.35)", ylabel="samples",
       title=f"Obstacle task on {problem.grid.describe()}: where each controller ends")
ax.legend(fontsize=8)
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "interpolation_example.png", dpi=110)
print("wrote", out / "interpolation_example.png")
