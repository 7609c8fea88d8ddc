"""Gymnasium's ``Acrobot-v1`` as a minimum-time first-exit problem (:class:`GymAcrobot`,
:func:`acrobot_problem`), played in gym (:func:`run_acrobot`).

Gym's task: torques {−1, 0, +1} on the second joint, held for Δt = 0.2 s integrated by one RK4
step, the angles wrapped to [−π, π] and the velocities clipped to ±4π and ±9π after each step;
−1 per step until the tip is above the bar (−cos θ₁ − cos(θ₁ + θ₂) > 1), at most 500 steps,
starts uniform in ±0.1 on all four coordinates.
"""

from __future__ import annotations

import math

import numpy as np

from ..grid import Axis, Grid
from ..problem import Problem
from ..systems.base import ControlAffineSystem
from .gym_clients import Episodes, _play, _TimeCost

ACROBOT_ID = "Acrobot-v1"
ACROBOT_STEP = 0.2
"""Gym's time step (s), integrated by RK4 with the torque held."""
ACROBOT_STEPS = 500
ACROBOT_TORQUES = (-1.0, 0.0, 1.0)


class GymAcrobot(ControlAffineSystem):
    """Gym's ``Acrobot-v1`` ("book" dynamics: rods of mass 1 and length 1, centres of mass at
    half length, moments of inertia 1, g = 9.8, torque on the second joint) in canonical
    momenta, so that the torque drives one axis and the noise λ B R⁻¹ Bᵀ is diagonal.

    State (θ₁, θ₂, p₁, p₂), angles as gym measures them (θ₁ = 0 hanging down, θ₂ relative to
    the first link), p = M(θ₂) θ̇ with

        M = [[3.5 + cos θ₂, 1.25 + ½ cos θ₂], [1.25 + ½ cos θ₂, 1.25]],
        V = −14.7 cos θ₁ − 4.9 cos(θ₁ + θ₂).

    Hamilton's equations: θ̇ = M⁻¹p, ṗ₁ = −∂V/∂θ₁, ṗ₂ = ½ θ̇ᵀ (∂M/∂θ₂) θ̇ − ∂V/∂θ₂ + τ, i.e.
    a = (M⁻¹p, −∂V/∂θ₁, ½ θ̇ᵀ M' θ̇ − ∂V/∂θ₂) and B = (0, 0, 0, 1). The tip is above the bar
    when −cos θ₁ − cos(θ₁ + θ₂) > 1 (gym's end of the episode).
    """

    state_dim = 4
    control_dim = 1
    state_names = ("theta1", "theta2", "p1", "p2")
    angle_axes = (0, 1)

    @staticmethod
    def mass_matrix(theta2) -> np.ndarray:
        """M(θ₂), shape ``(N, 2, 2)``."""
        c = np.cos(np.asarray(theta2, dtype=float))
        M = np.empty(c.shape + (2, 2))
        M[..., 0, 0] = 3.5 + c
        M[..., 0, 1] = M[..., 1, 0] = 1.25 + 0.5 * c
        M[..., 1, 1] = 1.25
        return M

    def velocities(self, x) -> np.ndarray:
        """θ̇ = M⁻¹ p, shape ``(N, 2)``."""
        x = self._states(x)
        return np.linalg.solve(self.mass_matrix(x[:, 1]), x[:, 2:, None])[..., 0]

    def from_velocities(self, x) -> np.ndarray:
        """Gym's state (θ₁, θ₂, θ̇₁, θ̇₂) ``(N, 4)`` as (θ₁, θ₂, p₁, p₂)."""
        x = self._states(x)
        p = np.einsum("nij,nj->ni", self.mass_matrix(x[:, 1]), x[:, 2:])
        return np.column_stack([x[:, :2], p])

    def drift(self, x):
        x = self._states(x)
        t1, t2 = x[:, 0], x[:, 1]
        w = self.velocities(x)
        s2 = np.sin(t2)
        dp1 = -14.7 * np.sin(t1) - 4.9 * np.sin(t1 + t2)
        dp2 = -0.5 * s2 * w[:, 0] ** 2 - 0.5 * s2 * w[:, 0] * w[:, 1] - 4.9 * np.sin(t1 + t2)
        return np.column_stack([w, dp1, dp2])

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 4, 1))
        B[:, 3, 0] = 1.0
        return B


def acrobot_above_bar(x) -> np.ndarray:
    """Gym's end of the episode, −cos θ₁ − cos(θ₁ + θ₂) > 1, for states ``(N, ≥ 2)``."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    return -np.cos(x[:, 0]) - np.cos(x[:, 0] + x[:, 1]) > 1.0


def acrobot_problem(
    n=(21, 21, 21, 21),
    momenta=(15.0, 8.0),
    temperature: float = 1.0,
    control_cost: float = 0.1,
) -> Problem:
    """Gym's Acrobot-v1 as a minimum-time first-exit problem: q = 1 per second (gym's −1 per
    0.2 s step, up to a factor), exit when the tip is above the bar, θ₁ and θ₂ periodic and the
    momenta on [−p₁, p₁] × [−p₂, p₂] (``momenta``), ``n`` nodes per axis. The control cost R and
    the temperature λ set the noise λ/R on p₂; gym's torque has no cost, so R only shapes the
    linear policy, whose sign picks gym's torque (:func:`acrobot_torques`)."""
    counts = np.broadcast_to(np.atleast_1d(n), (4,)).tolist()
    grid = Grid(
        [
            Axis(-math.pi, math.pi, int(counts[0]), periodic=True, name="theta1"),
            Axis(-math.pi, math.pi, int(counts[1]), periodic=True, name="theta2"),
            Axis(-momenta[0], momenta[0], int(counts[2]), name="p1"),
            Axis(-momenta[1], momenta[1], int(counts[3]), name="p2"),
        ]
    )
    return Problem(
        GymAcrobot(),
        grid,
        None,
        state_cost=_TimeCost(1.0),
        control_cost=control_cost,
        temperature=temperature,
        exit=acrobot_above_bar,
    )


def acrobot_torques(solution):
    """Gym's action (0, 1, 2 for torque −1, 0, +1) from a solution's policy at gym's states
    ``(N, 4)`` = (θ₁, θ₂, θ̇₁, θ̇₂): the sign of the continuous torque u = −R⁻¹Bᵀ∇v. For a
    minimum-time task with ``|τ| ≤ 1`` and no torque cost the bounded optimum is bang-bang,
    τ = −sign(Bᵀ∇v), and u has that sign; 0 would be optimal only where Bᵀ∇v = 0. (Rounding u
    to the nearest of the three instead mostly gives 0 and never swings up: −500.)"""
    system = solution.problem.system

    def actions(x):
        u = solution.policy(system.from_velocities(x))[:, 0]
        return np.where(u < 0, 0, 2)

    return actions


def run_acrobot(policy, episodes: int = 1000, seed: int = 0) -> Episodes:
    """Play ``policy(x) -> (N,)`` actions in {0, 1, 2} (x: gym's internal states ``(N, 4)`` =
    (θ₁, θ₂, θ̇₁, θ̇₂)) in gym's ``Acrobot-v1``, one env per episode reset with seeds
    ``seed + i``, the running ones stepped together. ``reached``: the tip got above the bar;
    ``peak_force`` is 1 if any nonzero torque was used."""

    def torques(x):
        actions = np.asarray(policy(x))
        if actions.shape != (x.shape[0],) or not np.all(np.isin(actions, (0, 1, 2))):
            raise ValueError(f"policy must return ({x.shape[0]},) actions in {{0, 1, 2}}")
        return [int(a) for a in actions], np.abs(actions - 1)

    return _play(ACROBOT_ID, episodes, seed, torques, lambda env, obs: env.unwrapped.state)
