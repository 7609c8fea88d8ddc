"""
When the linear formulation does not fit: gym's Pendulum-v1
===========================================================

Gymnasium's Pendulum-v1 clips the torque to ±2. A linearly solvable problem cannot express that:
its control cost is ½uᵀRu, unbounded, and the same R sets the noise λBR⁻¹Bᵀ. Its policy, clipped
after the fact, plans for torques it will never get. The value-space HJB solver minimises over
the bounded torques instead: ``solve_hjb(problem, control_bounds=(-2, 2))``.

Gym's pendulum is ``Pendulum(mass=0.75, length=2/3, gravity=10)`` (θ̈ = 15 sin θ + 3u) and its
reward per 0.05 s step, −(θ² + 0.1ω² + 0.001u²), is the cost rate q = 20θ² + 2ω², R = 0.04
(:mod:`gridlbc.studies.gym_pendulum`). Small grids and few episodes here; ``benchmarks/gym_pendulum.py``
runs thousands.
"""

import matplotlib.pyplot as plt
import numpy as np

import gridlbc
from gridlbc.reference import solve_hjb
from gridlbc.studies.gym_pendulum import run_episodes
from gridlbc.studies.problems import pendulum_v1_problem

n, episodes = 51, 20
bounded = solve_hjb(pendulum_v1_problem(n, temperature=1e-4), control_bounds=(-2, 2))
# The linear formulation as a new user would try it: a temperature of 1 and a larger R, so
# that the unbounded policy asks for less torque.
linear = gridlbc.solve(pendulum_v1_problem(n, temperature=1.0, control_cost=4.0))


def linear_clipped(x, t):
    return np.clip(linear.policy(x, t), -2, 2)


scores = {
    "bounded HJB": run_episodes(bounded.policy, episodes),
    "linearly solvable, clipped": run_episodes(linear_clipped, episodes),
}
for name, result in scores.items():
    print(f"{name}: {result.summary()}")

# %%
# The two policies at t = 0. The bounded one is bang-bang almost everywhere: it pumps energy
# with full torque and switches on curves that bring the pendulum up within the torque it has.
# The linear one saturates in a different pattern and never learns to pump.
theta = np.linspace(-np.pi, np.pi, 121)
omega = np.linspace(-8, 8, 101)
T, W = np.meshgrid(theta, omega, indexing="ij")
states = np.column_stack([T.ravel(), W.ravel()])
fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True, sharey=True)
for ax, (name, policy) in zip(
    axes, [("bounded HJB", bounded.policy), ("linearly solvable, clipped", linear_clipped)]
):
    mesh = ax.pcolormesh(
        T, W, policy(states, 0.0).reshape(T.shape), cmap="RdBu_r", vmin=-2, vmax=2, shading="auto"
    )
    ax.set(title=f"{name}: {scores[name].mean:.0f} per episode", xlabel="θ (rad)")
axes[0].set_ylabel("ω (rad/s)")
fig.colorbar(mesh, ax=axes, label="torque at t = 0")
