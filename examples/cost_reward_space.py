"""Cost space and reward space: the value v, the desirability z = exp(−v/λ) and the policy u* of
a pendulum swing-up, solved once and evaluated on a lattice of states.

    python examples/cost_reward_space.py [--out figures] [--quick]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc.studies.problems import swingup_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="61² grid, for a look in seconds")
args = parser.parse_args()

# The swing-up: θ from the upright (periodic), ω in rad/s, T = 3, λ = 1, g = 10θ² + ½ω².
problem = swingup_problem(61 if args.quick else 201)
solution = gridlbc.solve(problem)

# Any state, any time: value, desirability and policy by barycentric interpolation of the stored
# slices (of log z for this default solve, fitted to its own terminal cost).
theta, omega = np.meshgrid(np.linspace(-np.pi, np.pi, 241), np.linspace(-10, 10, 161))
states = np.column_stack([theta.ravel(), omega.ravel()])
fields = {
    "value v(x, 0)": solution.value(states, 0.0),
    "desirability z(x, 0) = exp(−v/λ)": solution.desirability(states, 0.0),
    "policy u*(x, 0)": solution.policy(states, 0.0)[:, 0],
}

fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
for ax, (title, values) in zip(axes, fields.items()):
    signed = title.startswith("policy")  # torque: white at zero
    limit = np.abs(values).max() if signed else None
    image = ax.pcolormesh(
        theta,
        omega,
        values.reshape(theta.shape),
        shading="auto",
        cmap="RdBu_r" if signed else "viridis",
        vmin=-limit if signed else None,
        vmax=limit,
    )
    fig.colorbar(image, ax=ax)
    ax.set(title=title, xlabel="θ (rad from upright)", ylabel="ω (rad/s)")
fig.suptitle(f"Pendulum swing-up on {problem.grid.describe()}: cost space vs reward space")
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "cost_reward_space_example.png", dpi=110)
print("wrote", out / "cost_reward_space_example.png")
