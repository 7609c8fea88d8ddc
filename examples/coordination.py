"""Coordination with a push (paper Fig. 9): a point mass with two acceptable outcomes, combined
with w = (1, 1), is pushed mid-way and switches goals on its own; the blend weight α against time,
and certified costs from the pushed state.

    python examples/coordination.py [--out figures] [--quick]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Quadratic
from gridlbc.studies.figures import remaining_task, simulate_with_push
from gridlbc.studies.problems import GOAL_WEIGHTS, coordination_problem

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="41² grid and 100 samples")
args = parser.parse_args()
n, samples, dt = (41, 100, 0.02) if args.quick else (81, 2000, 0.005)

# Goals: at rest at x = −1 or x = +1 after T = 3 s (λ = 0.3); coordination is w = 1 each.
problem = coordination_problem(n)
left, right = gridlbc.solve_many(
    problem, [problem.terminal_cost, Quadratic([1.0, 0.0], GOAL_WEIGHTS)]
)
both = gridlbc.combine([left, right])

# Start nearer +1, at rest; at t = 1 s a push changes the velocity by −1.5 m/s.
x0, push_time, kick = np.array([0.3, 0.0]), 1.0, np.array([0.0, -1.5])
times, states = simulate_with_push(both.problem, both.policy, x0, push_time, kick, noise=False)
alpha = np.array(
    [both.blend_weights(states[:, k], min(t, problem.horizon))[0, 1] for k, t in enumerate(times)]
)
print(f"α₊ just before the push {alpha[times <= push_time][-2]:.3f}, at the end {alpha[-1]:.3f}")

# What the rest of the task costs from the pushed state, certified, for each controller.
pushed = states[0, np.searchsorted(times, push_time) + 1]
for name, policy in {
    "LBC": both.policy,
    "goal −1 alone": left.policy,
    "goal +1 alone": right.policy,
}.items():
    task, shifted = remaining_task(both.problem, policy, push_time)
    cert = gridlbc.certify(task, shifted, pushed, samples, dt=dt, seed=0)
    print(
        f"{name:14s} cost {cert.policy_cost:.3f} ± {cert.policy_cost_se:.3f}, certified "
        f"optimum {cert.optimal_value:.3f} ± {cert.optimal_value_se:.3f}"
    )

fig, (ax_a, ax_x) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True, constrained_layout=True)
ax_a.plot(times, alpha)
ax_a.set(ylabel="α₊ = z₊ / (z₋ + z₊)", title="blend weight of the goal x = +1")
ax_x.plot(times, states[0, :, 0])
ax_x.set(xlabel="t (s)", ylabel="position x (m)")
for ax in (ax_a, ax_x):
    ax.axvline(push_time, color="k", ls=":")
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "coordination_example.png", dpi=110)
print("wrote", out / "coordination_example.png")
