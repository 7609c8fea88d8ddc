"""Gymnasium's ``Pendulum-v1`` as a gridlbc problem: the same dynamics, cost and episodes.

Gym's pendulum (gymnasium ``classic_control/pendulum.py``) has g = 10, m = l = 1 and θ measured
from the upright, positive in the same sense as its torque, so its

    θ̈ = (3g / 2l) sin θ + (3 / m l²) u = 15 sin θ + 3u

is the library's :class:`~gridlbc.systems.Pendulum` with (g/l) = 15 and 1/(m l²) = 3, i.e.
``Pendulum(mass=0.75, length=2/3, gravity=10)`` (both angles from the upright: no sign change).
Gym steps it by semi-implicit Euler with Δt = 0.05, clipping the torque to ±2 and the velocity
to ±8,

    ω' = clip(ω + (15 sin θ + 3 clip(u, ±2)) Δt, ±8),    θ' = θ + ω' Δt,

for 200 steps (10 s) from θ ~ U(−π, π), ω ~ U(−1, 1), observing (cos θ, sin θ, ω) and rewarding
each step −(θ² + 0.1 ω² + 0.001 u²) with θ wrapped to [−π, π). A reward per step of length Δt is
a cost rate of 1/Δt = 20 times it, so the episode's return is −∫₀¹⁰ (q + ½ R u²) dt up to the
time discretisation with

    q(θ, ω) = 20 θ² + 2 ω²,    R = 0.04   (½ R = 20 · 0.001).

:func:`gridlbc.studies.problems.pendulum_v1_problem` is that problem on a grid: the ω axis is the
closed box [−8, 8] (a reflecting state constraint, as gym's velocity clip is), θ is periodic.
Gym is deterministic; the library's problems have noise λ B R⁻¹ Bᵀ, so a small temperature is
the closest match.

Gym bounds the torque to ±2, which the linearly solvable formulation cannot express (its
control cost is quadratic and unbounded, and R also sets the noise): its policy, clipped, plans
for torques it will not get. :func:`gridlbc.reference.solve_hjb` with ``control_bounds=(-2, 2)``
minimises over the bounded torques directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .problems import PENDULUM_V1_STEP, PENDULUM_V1_STEPS

DT = PENDULUM_V1_STEP
"""Gym's time step (s)."""
STEPS = PENDULUM_V1_STEPS
"""Steps per episode (gym's TimeLimit): a 10 s horizon."""


def state_from_observation(observation) -> np.ndarray:
    """Gym's observations ``(N, 3)`` = (cos θ, sin θ, ω) as states ``(N, 2)`` = (θ, ω)."""
    obs = np.atleast_2d(np.asarray(observation, dtype=float))
    if obs.shape[-1] != 3:
        raise ValueError(
            f"observation must have 3 entries (cos θ, sin θ, ω), got shape {obs.shape}"
        )
    return np.column_stack([np.arctan2(obs[:, 1], obs[:, 0]), obs[:, 2]])


@dataclass(frozen=True)
class Episodes:
    """Returns of gym episodes: ``scores`` (n,) the summed rewards, ``starts`` (n, 2) the initial
    states (θ, ω), ``seeds`` (n,) the reset seeds."""

    scores: np.ndarray
    starts: np.ndarray
    seeds: np.ndarray

    @property
    def mean(self) -> float:
        return float(self.scores.mean())

    @property
    def standard_error(self) -> float:
        return float(self.scores.std(ddof=1) / math.sqrt(self.scores.size))

    def summary(self) -> str:
        return f"{self.mean:.1f} ± {self.standard_error:.1f} ({self.scores.size} episodes)"


def run_episodes(policy, episodes: int = 500, seed: int = 0) -> Episodes:
    """Run ``policy(x, t) -> (N, 1)`` on gym's ``Pendulum-v1``, one env per episode.

    Episode i is reset with seed ``seed + i`` (gym's own start distribution); all episodes are
    stepped together so that the policy is evaluated on a batch of states per step, at
    t = k Δt. Gym clips the torque itself. Needs gymnasium (``pip install "gridlbc[gymnasium]"``).
    """
    try:
        import gymnasium
    except ImportError:
        raise ImportError(
            'run_episodes needs gymnasium: pip install "gridlbc[gymnasium]"'
        ) from None
    if isinstance(episodes, bool) or not isinstance(episodes, (int, np.integer)) or episodes < 2:
        raise ValueError(
            f"episodes must be an integer ≥ 2 (for a standard error), got {episodes!r}"
        )
    envs = [gymnasium.make("Pendulum-v1") for _ in range(episodes)]
    seeds = seed + np.arange(episodes)
    obs = np.array([env.reset(seed=int(s))[0] for env, s in zip(envs, seeds)])
    starts = state_from_observation(obs)
    scores = np.zeros(episodes)
    for k in range(STEPS):
        u = np.asarray(policy(state_from_observation(obs), k * DT), dtype=float)
        if u.shape != (episodes, 1) or not np.all(np.isfinite(u)):
            raise ValueError(
                f"policy must return finite torques of shape ({episodes}, 1) at t = {k * DT:g}, "
                f"got shape {u.shape}" + ("" if u.shape != (episodes, 1) else " with NaN or inf")
            )
        for i, env in enumerate(envs):
            obs[i], reward, _, truncated, _ = env.step(u[i].astype(np.float32))
            scores[i] += reward
    if not truncated:
        raise RuntimeError(f"gym did not end the episode after {STEPS} steps: check its TimeLimit")
    for env in envs:
        env.close()
    return Episodes(scores, starts, seeds)


def zero_policy(x, t) -> np.ndarray:
    """No torque: the baseline."""
    return np.zeros((np.atleast_2d(x).shape[0], 1))
