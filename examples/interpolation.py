"""Interpolation: a controller for a goal between two solved goals, by projection and linear
Bellman combination, against the naive blend of the two policies; every cost certified.

A point in the plane (dx = u dt + noise, T = 3, λ = 0.2) starts in front of the middle of a long
wall and must end at an intermediate goal directly behind it. The two solved components end
either side of that goal: one goes round the wall's upper end, the other round its lower end
(the task of ``figures/interpolation.png``, here at a smaller size). What to expect:

- LBC, solved exactly for the composite goal, sends half its rollouts round each end and ends
  centred on the intermediate goal (mean final y ≈ 0);
- the naive blend averages "go up" and "go down" in front of the wall's middle: many of its
  rollouts stall there and some cross the wall; it costs clearly more than LBC;
- each component alone costs more than LBC too, but by at most λ log 2 = 0.139 (a theorem: the
  README's interpolation section), so the difference is measured with common noise.

    python examples/interpolation.py [--out figures] [--quick] [--n 101 --samples 4000]

(``--n 101 --samples 4000`` prints the README's table, the figure's numbers.)
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
    OBSTACLE,
    OBSTACLE_GOALS,
    OBSTACLE_START,
    OBSTACLE_WEIGHTS,
    obstacle_problem,
)

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="41×61 grid, Δt = 0.02, 300 samples")
parser.add_argument("--n", type=int, default=61, help="x nodes, odd (default 61; the figure 101)")
parser.add_argument("--samples", type=int, default=1000, help="rollouts per controller")
args = parser.parse_args()
n, samples, dt = (41, 300, 0.02) if args.quick else (args.n, args.samples, 0.01)

# The task: the intermediate goal g = 5(x + 0.7)² + 0.75 y², behind the wall x = 0, |y| ≤ 1.8.
problem = obstacle_problem(n)
goals = [Quadratic(c, OBSTACLE_WEIGHTS) for c in OBSTACLE_GOALS]  # (−0.7, ±0.35)

# The two components solved together (one operator: they combine exactly), and the weights
# that aim them at the intermediate goal.
upper, lower = gridlbc.solve_many(problem, goals, dt=dt)
weights = gridlbc.project(problem.terminal_cost, goals, problem.grid,
                          temperature=problem.temperature)
lbc = gridlbc.combine([upper, lower], weights)  # exact for g_w = −λ log Σ w_i exp(−g_i/λ)
controllers = {
    "LBC": lbc.policy,
    "naive blend": gridlbc.naive_blend([upper, lower], weights).policy,
    "upper goal alone": upper.policy,
    "lower goal alone": lower.policy,
}
print(f"{problem.grid.describe()}, Δt = {dt:g}, {samples} samples; projected weights "
      f"{np.round(weights, 3)}, exact combination: {lbc.exact}, "
      f"β = {np.round(lbc.blend_weights(OBSTACLE_START, 0.0)[0], 3)}")

# Certify each controller on the composite task g_w (importance sampling, any policy as
# proposal). Then roll each out with the same seed, so every controller meets the same noise and
# the per-sample cost differences to LBC give a paired standard error.
task = lbc.problem
runs = {name: gridlbc.simulate(task, policy, OBSTACLE_START, samples, dt=dt, seed=1)
        for name, policy in controllers.items()}
print(f"{'controller':17s} {'J ± SE':>15s} {'J − v* ± SE':>16s} {'J − J_LBC ± SE':>16s} "
      f"{'enter wall':>11s}  mean final (x, y)")
certificates = {}
for name, policy in controllers.items():
    cert = certificates[name] = gridlbc.certify(task, policy, OBSTACLE_START, samples, dt=dt,
                                                seed=0, progress=False)
    run = runs[name]
    d = run.costs - runs["LBC"].costs
    entered = OBSTACLE(run.states.reshape(-1, 2)).reshape(run.states.shape[:2]).max(axis=1)
    final = run.final_states.mean(axis=0)
    print(f"{name:17s} {cert.policy_cost:7.3f} ± {cert.policy_cost_se:.3f} "
          f"{cert.gap:+8.3f} ± {cert.gap_se:.3f} "
          f"{d.mean():+8.3f} ± {d.std(ddof=1) / np.sqrt(samples):.3f} "
          f"{100 * np.mean(entered > OBSTACLE.height / 2):9.1f} %  ({final[0]:+.2f}, {final[1]:+.2f})")
best = certificates["LBC"]  # the optimal proposal: the smallest SE of v*
print(f"(certified optimum v* = {best.optimal_value:.3f} ± {best.optimal_value_se:.3f} with LBC "
      f"as proposal; LBC can beat the best component by at most λ log 2 = "
      f"{task.temperature * np.log(2):.3f})")

fig, axes = plt.subplots(1, 4, figsize=(14, 5), sharey=True, constrained_layout=True)
X, Y = np.meshgrid(np.linspace(-2, 2, 161), np.linspace(-3, 3, 241))
wall = OBSTACLE(np.column_stack([X.ravel(), Y.ravel()])).reshape(X.shape)
for ax, (name, run) in zip(axes, runs.items()):
    ax.contour(X, Y, wall, [OBSTACLE.height / 2], colors="C3")
    for path in run.states[:20]:
        ax.plot(path[:, 0], path[:, 1], lw=0.6)
    ax.plot(*np.transpose(OBSTACLE_GOALS), "kx")
    ax.set(title=name, xlabel="x", aspect="equal")
axes[0].set_ylabel("y")
fig.suptitle(f"Wall task on {problem.grid.describe()}: 20 noisy rollouts per controller")
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "interpolation_example.png", dpi=90)
print("wrote", out / "interpolation_example.png")
