r"""
Linear Bellman combination: two goals, no new solve
===================================================

Solutions :math:`z_1, z_2` of the same linear PDE for terminal costs :math:`g_1, g_2` superpose:
:math:`z = w_1 z_1 + w_2 z_2` is the exact solution for the terminal cost
:math:`g = -\lambda \log(w_1 e^{-g_1/\lambda} + w_2 e^{-g_2/\lambda})`, and its policy is the
state-dependent blend :math:`u = \alpha_1 u_1 + \alpha_2 u_2` with
:math:`\alpha_i = w_i z_i / \sum_j w_j z_j`. Here a point mass has two acceptable parking spots,
x = ±1 (coordination, w = 1).

On the grid the superposition is exact when the components were stepped by *one* operator. The
default scheme fits its operator to a reference desirability, so solve the components together
(:func:`gridlbc.solve_many`, which fits them all to one shared reference), pass one reference
cost as ``fitting=`` to every solve, or use the plain operator (``fitting=None``), which does
not depend on the terminal cost at all.
"""

import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.reference import lq_solution
from gridlbc.systems import PointMass

grid = Grid([Axis(-3, 3, 81), Axis(-4, 4, 81)])
problem = Problem(
    PointMass(), grid, horizon=2.0, terminal_cost=Quadratic([1, 0], [4, 1]), temperature=0.5
)
goals = [Quadratic([-1, 0], [4, 1]), Quadratic([1, 0], [4, 1])]
lam = problem.temperature


def either(x):
    """The composite terminal cost of w = (1, 1): −λ log(exp(−g₁/λ) + exp(−g₂/λ))."""
    return -lam * np.logaddexp(-goals[0](x) / lam, -goals[1](x) / lam)


x = np.random.default_rng(0).uniform([-2, -3], [2, 3], size=(500, 2))

# %%
# The exact path: one operator. Both components are fitted to the same reference (here the
# composite cost itself, given as ``fitting=``), and so is the direct solve we check against.
# The combination then *is* the direct solve, up to floating-point rounding.
left, right = gridlbc.solve_many(problem, goals, fitting=either)
both = gridlbc.combine([left, right])  # w = (1, 1)
direct = gridlbc.solve(problem.replace(terminal_cost=either), fitting=either)
exact_gap = np.abs(both.value(x, 0.0) - direct.value(x, 0.0)).max()
print(f"one operator: exact = {both.exact}, max |v_combined − v_direct| = {exact_gap:.1e}")

# %%
# Components solved separately with the default settings are each fitted to their *own* goal:
# two different operators. They still combine (through their values), but ``combine`` reports
# that the result is not exact, and it is then as accurate as the components are, not equal to
# the direct solve to rounding. For scale: this point mass is a linear-quadratic problem, so each
# component can be compared with its exact Riccati solution
# (:func:`gridlbc.reference.lq_solution`); the combination's gap to the direct solve is smaller
# than the components' own mean error.
components = [gridlbc.solve(problem.replace(terminal_cost=g)) for g in goals]
separate = gridlbc.combine(components)
default_direct = gridlbc.solve(problem.replace(terminal_cost=either))
separate_gap = np.abs(separate.value(x, 0.0) - default_direct.value(x, 0.0)).max()
print(f"separately fitted: exact = {separate.exact}")
print(f"    max |v_combined − v_direct| = {separate_gap:.4f}")
for g, component in zip(goals, components):
    exact = lq_solution(problem.replace(terminal_cost=g))
    error = np.abs(component.value(x, 0.0) - exact.value(x, 0.0)).mean()
    print(f"    component for x = {g.center[0]:+.0f}: mean |v − v_Riccati| = {error:.4f}")

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
