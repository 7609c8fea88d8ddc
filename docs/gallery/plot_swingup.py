"""
Solve a pendulum swing-up, then check the prediction
====================================================

The linear Bellman equation for the desirability z = exp(−v/λ) of a torque-driven pendulum is
solved on a grid; the value v = −λ log z and the policy u* = −R⁻¹Bᵀ∇v are then available at any
state and time. The solver's prediction v(x₀, 0) is a claim about the optimal cost: roll the
policy out on the stochastic dynamics to see what it really costs.
"""

import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import Pendulum

# %%
# The problem: θ from the upright (periodic), ω in rad/s; swing up to the upright in T = 3 s
# with temperature λ = 1 and control cost R = 1. The grid is small so that this page builds in
# seconds; the drift is fitted to the terminal cost, which keeps coarse grids honest.
grid = Grid([Axis(-np.pi, np.pi, 64, periodic=True), Axis(-10, 10, 65)])
problem = Problem(Pendulum(), grid, horizon=3.0, terminal_cost=Quadratic([0, 0], [10, 0.5]))
solution = gridlbc.solve(problem)  # the splitting scheme fitted to g (the default)
x0 = np.array([2.8, 0.0])  # near hanging down, at rest
print(f"predicted optimal cost v(x0, 0) = {solution.value(x0, 0.0):.2f}")
print(f"optimal torque u*(x0, 0) = {solution.policy(x0, 0.0)[0]:.2f}")

# %%
# Value and policy at t = 0, evaluated off the grid by barycentric interpolation.
theta = np.linspace(-np.pi, np.pi, 181)
omega = np.linspace(-10, 10, 161)
T, W = np.meshgrid(theta, omega, indexing="ij")
states = np.column_stack([T.ravel(), W.ravel()])
fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
u = solution.policy(states, 0.0)[:, 0]
for ax, field, label, style in [
    (axes[0], solution.value(states, 0.0), "value v(θ, ω, 0)", {"cmap": "viridis"}),
    (
        axes[1],
        u,
        "policy u*(θ, ω, 0)",
        {"cmap": "RdBu_r", "vmin": -np.abs(u).max(), "vmax": np.abs(u).max()},
    ),
]:
    mesh = ax.pcolormesh(T, W, field.reshape(T.shape), shading="auto", **style)
    fig.colorbar(mesh, ax=ax, label=label)
    ax.set(xlabel="θ (rad from the upright)", ylabel="ω (rad/s)")

# %%
# Is the prediction honest? Roll the policy out on the SDE (Euler–Maruyama) and compare the
# mean cost with v(x₀, 0). Their difference mixes the grid's error in the value, the policy's
# suboptimality, the sampling error (the ± SE printed) and the rollout's time-step bias; here
# they agree within about two standard errors. :doc:`../validating` separates these with the
# certified optimum.
rollouts = gridlbc.simulate(problem, solution.policy, x0, n_samples=200, dt=0.005, seed=0)
print(rollouts.summary())
fig, ax = plt.subplots(figsize=(6, 3.2), constrained_layout=True)
for path in rollouts.states[:20]:
    ax.plot(rollouts.times, np.angle(np.exp(1j * path[:, 0])), lw=0.7, color="C0", alpha=0.6)
ax.set(xlabel="t (s)", ylabel="θ (rad)", title="20 of the noisy swing-ups")
