"""
A task that ends: reach a goal and stop
=======================================

A first-exit problem has no horizon. The task ends when the state first enters the exit set E,
paying the exit cost there; until then it pays q per second. The desirability solves a linear
*stationary* equation, one sparse linear system on the grid, and exit costs on one E combine
exactly, like terminal costs do (docs page :doc:`/first_exit`).

Here a point mass (position, velocity) must come to rest in one of two bays. Each component
pays nothing in its own bay and 5 in the other; their combination with weights w is the optimal
controller for "either bay, with preference w", made without solving again. The certificate
stops each sample path when it parks; the titles compare it with the prediction and the
prediction's own error estimate (the position axis has no noise, so the grid is first order
there).
"""

import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem
from gridlbc.regions import Ball

grid = Grid([Axis(-2.0, 2.0, 161, name="position"), Axis(-3.0, 3.0, 161, name="velocity")])
bays = Ball([-1.0, 0.0], [0.25, 0.4]) | Ball([1.0, 0.0], [0.25, 0.4])
base = Problem(
    gridlbc.systems.PointMass(),
    grid,
    None,  # no horizon: first exit
    state_cost=lambda x: 0.5 + 0.05 * x[:, 1] ** 2,
    temperature=0.5,
    exit=bays,
)


def bay(side):
    """Exit cost 0 in the bay on ``side`` (−1 left, +1 right), 5 in the other."""
    return lambda x: np.where(np.sign(x[:, 0]) == side, 0.0, 5.0)


left, right = gridlbc.solve_many(base, [bay(-1), bay(1)])  # one operator, two exit costs
x0 = np.array([0.3, 0.5])
fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), constrained_layout=True)
X, V = np.meshgrid(*grid.points(), indexing="ij")
for ax, w in zip(axes, [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]):
    combined = gridlbc.combine([left, right], w)
    value = combined.value(grid.nodes()).reshape(grid.shape)
    mesh = ax.pcolormesh(X, V, np.minimum(value, 8.0), shading="auto")
    ax.contour(X, V, base.exit_mask().reshape(grid.shape), [0.5], colors="white")
    runs = gridlbc.simulate(
        combined.problem, combined.policy, x0, 6, dt=0.01, seed=0, max_time=10.0
    )
    for r in range(runs.n_samples):
        end = int(np.searchsorted(runs.times, runs.exit_times[r])) + 1
        ax.plot(runs.states[r, :end, 0], runs.states[r, :end, 1], "w", lw=0.8)
    c = gridlbc.certify(
        combined.problem, combined.policy, x0, 500, dt=0.01, seed=1, max_time=10.0, progress=False
    )
    predicted, estimate = float(combined.value(x0)), float(combined.error_estimate(x0))
    ax.set_title(
        f"w = {w}: v(x₀) {predicted:.3f} (est. error {estimate:.3f}),\n"
        f"certified {c.optimal_value:.3f} ± {c.optimal_value_se:.3f} (Δt 0.01)",
        fontsize=9,
    )
    ax.set_xlabel("position")
    fig.colorbar(mesh, ax=ax)
axes[0].set_ylabel("velocity")
print(f"α at the start (w = 1, 1): {gridlbc.combine([left, right]).blend_weights(x0)}")
plt.show()
