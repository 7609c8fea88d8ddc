"""Interpolation: a controller for a goal between two solved goals, by projection and linear
Bellman combination, against the naive blend of the two policies; every cost certified.

A rotor (a pendulum without gravity) starts almost opposite its goals and must come to rest at
θ̄ = 0; the solved components come to rest at θ = ±0.25.

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
from gridlbc.costs import wrap_angle
from gridlbc.studies.problems import ROTOR_GOALS, ROTOR_START, ROTOR_WEIGHTS, rotor_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="41² grid and 100 samples")
args = parser.parse_args()
n, samples, dt = (41, 100, 0.05) if args.quick else (101, 1000, 0.01)

# The task: T = 5, λ = 0.2, target g = 0.8θ² + 0.5ω² (at rest at θ̄ = 0).
problem = rotor_problem(n)
target = problem.terminal_cost
goals = [Quadratic([c, 0.0], ROTOR_WEIGHTS) for c in ROTOR_GOALS]

# Two components with one (fitted) operator, and the weights that aim them at the target.
left, right = gridlbc.solve_many(problem, goals, fitting="terminal")
weights = gridlbc.project(target, goals, problem.grid, temperature=problem.temperature)
lbc = gridlbc.combine([left, right], weights)  # exact for g_w = −λ log Σ w_i exp(−g_i/λ)
controllers = {
    "goal −0.25 alone": left.policy,
    "goal +0.25 alone": right.policy,
    "naive blend": gridlbc.naive_blend([left, right], weights).policy,
    "LBC": lbc.policy,
}
print("projected weights", np.round(weights, 4))

# Certify each controller on the composite task (importance sampling, any policy as proposal).
fig, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
for name, policy in controllers.items():
    cert = gridlbc.certify(lbc.problem, policy, ROTOR_START, samples, dt=dt, seed=0)
    final = wrap_angle(cert.final_states[:, 0])
    print(f"{name:17s} cost {cert.policy_cost:.3f} ± {cert.policy_cost_se:.3f}, certified "
          f"optimum {cert.optimal_value:.3f} ± {cert.optimal_value_se:.3f}, median |θ_T| "
          f"{np.median(np.abs(final)):.2f}")
    ax.hist(final, bins=np.linspace(-np.pi, np.pi, 73), histtype="step", lw=2,
            label=f"{name}: J = {cert.policy_cost:.3f}")
ax.set(xlabel="final angle θ_T (rad); target 0", ylabel="samples",
       title=f"Rotor on {problem.grid.describe()}: where each controller ends")
ax.legend(fontsize=8)
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "interpolation_example.png", dpi=110)
print("wrote", out / "interpolation_example.png")
