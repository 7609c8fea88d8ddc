"""Interpolation: a controller for a goal between two solved goals, by projection and linear
Bellman combination, against the naive blend of the two controllers; every cost certified.

A point in the plane (dx = u dt + noise, T = 3, λ = 0.2) starts in front of the middle of a long
wall and must end at an intermediate goal c̄ directly behind it. The two components are
trajectory components (paper §5): a locally optimal path to a goal just above c̄, round the
wall's upper end, and its mirror image to a goal just below, round the lower end, each with its
LQR tracker and quadratic value expansion (the task of ``figures/interpolation.png``). What to
expect:

- LBC, u = Σ αᵢuᵢ with αᵢ ∝ wᵢ exp(−v̂ᵢ/λ), follows whichever path the noise has made cheaper;
  behind the wall, where both expansions hold, the other component's weight rises and its
  tracker pulls towards its own goal, so LBC stops nearer c̄ than either component alone: the
  final y signed towards the end of the wall a rollout went round ("stops at") is smaller for
  LBC, by many paired SE, and about that of the exact optimum of its composite task (the grid
  components combined); the intermediate goal's own optimal controller (the direct grid solve
  of ḡ) stops nearer still;
- the naive blend u = Σ wᵢuᵢ / Σ wᵢ averages a tracker and its mirror image (y → −y), so it
  has no sideways push on the axis y = 0 and drives along it, through the wall: every rollout
  enters it, and it costs far more than LBC;
- each component alone goes round its own end and costs a little more than LBC, measured with
  common noise (the same noise for every controller, so per-sample differences give a paired
  standard error); the margin needs many samples.

    python examples/interpolation.py [--out figures] [--quick] [--n 151 --samples 32000]

(``--n 151 --samples 32000`` prints the table of docs/studies.rst, the figure's numbers.)
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Quadratic
from gridlbc.studies.figures import route_signed_final_y as stops_at
from gridlbc.studies.problems import (
    OBSTACLE,
    OBSTACLE_GOALS,
    OBSTACLE_START,
    OBSTACLE_TARGET,
    OBSTACLE_WEIGHTS,
    obstacle_problem,
    obstacle_trajectories,
)

RADIUS = 0.25  # a rollout "reaches" c̄ when it ends within this distance

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="figures", help="output folder (default: figures)")
parser.add_argument("--quick", action="store_true", help="41×61 grid, Δt = 0.02, 300 samples")
parser.add_argument("--n", type=int, default=101, help="x nodes, odd (default 101; the figure 151)")
parser.add_argument("--samples", type=int, default=4000, help="rollouts per controller")
args = parser.parse_args()
n, samples, dt = (41, 300, 0.02) if args.quick else (args.n, args.samples, 0.01)

# The task: the intermediate goal g = 20(x + 0.7)² + 10 y², behind the wall x = 0, |y| ≤ 1.8.
# The grid serves only the references: the exact combination and the direct solve of ḡ.
problem = obstacle_problem(n)
goals = [Quadratic(c, OBSTACLE_WEIGHTS) for c in OBSTACLE_GOALS]  # (−0.7, ±0.09)
upper, lower = obstacle_trajectories(problem)
weights = gridlbc.project(
    problem.terminal_cost, goals, problem.grid, temperature=problem.temperature
)
lbc = gridlbc.combine([upper, lower], weights)  # α_i ∝ w_i exp(−v̂_i/λ)
*grid_components, direct = gridlbc.solve_many(problem, [*goals, problem.terminal_cost], dt=dt)
controllers = {
    "LBC": lbc.policy,
    "naive blend": gridlbc.naive_blend([upper, lower], weights).policy,
    "upper goal alone": upper.policy,
    "lower goal alone": lower.policy,
    "exact LBC (grid)": gridlbc.combine(grid_components, weights).policy,
    "direct ḡ (grid)": direct.policy,
}
print(
    f"{problem.grid.describe()}, Δt = {dt:g}, {samples} samples; projected weights "
    f"{np.round(weights, 3)}, β = {np.round(lbc.blend_weights(OBSTACLE_START, 0.0), 3)}"
)

# Certify each controller on the composite task g_w (importance sampling, any policy as
# proposal). Then roll each out with the same seed, so every controller meets the same noise and
# the per-sample cost differences to LBC give a paired standard error.
task = lbc.problem
runs = {
    name: gridlbc.simulate(task, policy, OBSTACLE_START, samples, dt=dt, seed=1)
    for name, policy in controllers.items()
}
print(
    f"{'controller':17s} {'J ± SE':>15s} {'J − v* ± SE':>16s} {'J − J_LBC ± SE':>16s} "
    f"{'enter wall':>11s} {'within ' + str(RADIUS):>12s} {'median |x_T − c̄|':>17s} "
    f"{'stops at ± SE':>15s} {'− LBC’s ± SE':>16s}"
)


def se(a):
    return a.std(ddof=1) / np.sqrt(a.size)


certificates = {}
for name, policy in controllers.items():
    cert = certificates[name] = gridlbc.certify(
        task, policy, OBSTACLE_START, samples, dt=dt, seed=0, progress=False
    )
    run = runs[name]
    d = run.costs - runs["LBC"].costs
    # final y signed towards the end of the wall the rollout went round: how far short of c̄
    # (y = 0) it stops on the side it comes from
    stop = stops_at(run)
    shift = stop - stops_at(runs["LBC"])  # paired: the same noise
    entered = OBSTACLE(run.states.reshape(-1, 2)).reshape(run.states.shape[:2]).max(axis=1)
    distance = np.linalg.norm(run.final_states - OBSTACLE_TARGET, axis=1)
    print(
        f"{name:17s} {cert.policy_cost:7.3f} ± {cert.policy_cost_se:.3f} "
        f"{cert.gap:+8.3f} ± {cert.gap_se:.3f} "
        f"{d.mean():+8.3f} ± {se(d):.3f} "
        f"{100 * np.mean(entered > OBSTACLE.height / 2):9.1f} % "
        f"{100 * np.mean(distance < RADIUS):10.1f} % {np.median(distance):17.3f} "
        f"{stop.mean():+8.3f} ± {se(stop):.3f} {shift.mean():+8.3f} ± {se(shift):.3f}"
    )
best = certificates["exact LBC (grid)"]  # the optimum as proposal: the smallest SE of v*
print(
    f"(certified optimum v* = {best.optimal_value:.3f} ± {best.optimal_value_se:.3f} with the "
    f"exact LBC as proposal)"
)

fig, axes = plt.subplots(1, 4, figsize=(14, 5), sharey=True, constrained_layout=True)
X, Y = np.meshgrid(np.linspace(-2, 2, 161), np.linspace(-3, 3, 241))
wall = OBSTACLE(np.column_stack([X.ravel(), Y.ravel()])).reshape(X.shape)
for ax, name in zip(axes, list(runs)[:4]):
    ax.contour(X, Y, wall, [OBSTACLE.height / 2], colors="C3")
    for path in runs[name].states[:20]:
        ax.plot(path[:, 0], path[:, 1], lw=0.6)
    ax.plot(*np.transpose(OBSTACLE_GOALS), "kx")
    ax.set(title=name, xlabel="x", aspect="equal")
axes[0].set_ylabel("y")
fig.suptitle("Wall task, trajectory components: 20 noisy rollouts per controller")
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
fig.savefig(out / "interpolation_example.png", dpi=90)
print("wrote", out / "interpolation_example.png")
