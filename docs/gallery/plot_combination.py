"""
Linear Bellman combination: two goals, no new solve
===================================================

Solutions z₁, z₂ of the same linear PDE for terminal costs g₁, g₂ superpose: z = w₁z₁ + w₂z₂ is
the exact solution for the terminal cost g = −λ log(w₁e^{−g₁/λ} + w₂e^{−g₂/λ}), and its policy is
the state-dependent blend u = α₁u₁ + α₂u₂ with α_i = w_i z_i / Σ_j w_j z_j. Here a point mass
has two acceptable parking spots, x = ±1 (coordination, w = 1).
"""

import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import PointMass

grid = Grid([Axis(-3, 3, 81), Axis(-4, 4, 81)])
problem = Problem(
    PointMass(), grid, horizon=2.0, terminal_cost=Quadratic([1, 0], [4, 1]), temperature=0.5
)
goals = [Quadratic([-1, 0], [4, 1]), Quadratic([1, 0], [4, 1])]
left, right = (gridlbc.solve(problem.replace(terminal_cost=g)) for g in goals)
both = gridlbc.combine([left, right])  # w = (1, 1)

# %%
# Superposition is exact on the grid: the combination equals a direct solve of the composite
# terminal cost to rounding (the plain operator does not depend on the terminal cost).
lam = problem.temperature


def either(x):
    return -lam * np.logaddexp(-goals[0](x) / lam, -goals[1](x) / lam)


direct = gridlbc.solve(problem.replace(terminal_cost=either))
x = np.random.default_rng(0).uniform([-2, -3], [2, 3], size=(500, 2))
print("max |v_combined − v_direct| =", np.abs(both.value(x, 0.0) - direct.value(x, 0.0)).max())

# %%
# The blend weight of the right-hand goal over the state space at t = 0: each state is handed
# to the goal it can reach more cheaply, with a smooth hand-over in between.
P, V = np.meshgrid(np.linspace(-2.5, 2.5, 151), np.linspace(-3, 3, 121), indexing="ij")
alpha = both.blend_weights(np.column_stack([P.ravel(), V.ravel()]), 0.0)[:, 1]
fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
mesh = ax.pcolormesh(P, V, alpha.reshape(P.shape), cmap="coolwarm", vmin=0, vmax=1, shading="auto")
fig.colorbar(mesh, label="α of the goal x = +1")
ax.set(xlabel="position", ylabel="velocity", title="Coordination of two solved controllers")

# %%
# Rollouts of the combined policy from rest at the middle go to either goal.
rollouts = gridlbc.simulate(problem, both.policy, [0.0, 0.0], n_samples=200, seed=1)
final = rollouts.states[:, -1, 0]
print(f"ended near +1: {np.mean(final > 0):.0%}, near −1: {np.mean(final < 0):.0%}")
