"""Gymnasium's first-exit tasks as gridlbc problems: ``MountainCarContinuous-v0`` here, and the
episode runner its sibling :mod:`gridlbc.studies.gym_acrobot` (``Acrobot-v1``) shares.

**Gym's map** (gymnasium ``classic_control/continuous_mountain_car.py``), one step per time unit,
state (position x, velocity v), force u clipped to [−1, 1]:

    v' = clip(v + 0.0015 u − 0.0025 cos 3x, ±0.07),   x' = clip(x + v', [−1.2, 0.6]),
    v' = 0 if x' = −1.2 and v' < 0,

reward −0.1 u² per step (u as given, *before* the clip) and +100 on the step that reaches
x ≥ 0.45 with v ≥ 0, which ends the episode; at most 999 steps; starts x₀ ~ U[−0.6, −0.4],
v₀ = 0. Gym charges force and nothing else: time is free until the 999th step.

**The continuous-time model** (:class:`MountainCar`, time unit = one gym step): the map is
semi-implicit Euler with Δt = 1 of

    ẋ = v,   v̇ = 0.0015 u − 0.0025 cos 3x,

so a = (v, −0.0025 cos 3x), B = (0, 0.0015). The per-step reward −0.1u² is the cost rate ½Ru²
with R = 0.2. The exit set is E = {x ≥ 0.45, v ≥ 0} with exit cost 0 (the +100 is paid by every
episode that finishes, so only the force matters). The velocity clip and the left wall are the
grid's box (reflecting state constraints: the chain cannot jump out, as gym's clip and its
inelastic wall keep the car in). Gym is deterministic; the linearly solvable problem has noise
λ B R⁻¹ Bᵀ in the velocity, so a small temperature λ is the nearest match.

**Why a time cost.** Without one the optimum is not attained: pumping energy ½v² + (0.0025/3)
sin 3x into the car at a rate 0.0015 u v, the force spent Σu² for a given gain falls as the
episode lengthens (u ∝ v over more swings), so the infimum is 0 at infinite length, and with
noise the car drifts out for free. The 999-step limit is what bounds it. A constant state cost q
per step (:func:`mountain_car_problem`'s ``time_cost``) prices time instead: it is the Lagrange
multiplier of the episode length, and q sets how long the optimal episode is. Too small a q
plans episodes longer than 999 steps (and scores about 0 when truncated); too large a q spends
force to finish early. The benchmark searches q (with λ and R) on the played score.

:func:`run_mountain_car` plays a policy in gym itself (one env per episode, stepped together)
and scores it by gym's summed reward; :func:`mountain_car_dp` is dynamic programming on gym's own
discrete map (no model), the best achievable score for comparison.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._numba import jit
from ..costs import Constant
from ..grid import Axis, Grid
from ..problem import Problem
from ..regions import Box
from ..systems.base import ControlAffineSystem
from .gym_pendulum import Episodes as PendulumEpisodes

MOUNTAIN_CAR_ID = "MountainCarContinuous-v0"
MC_POWER = 0.0015
"""Gym's force gain: Δv = 0.0015 u per step."""
MC_GRAVITY = 0.0025
"""Gym's slope term: Δv = −0.0025 cos 3x per step."""
MC_MAX_SPEED = 0.07
MC_MIN_POSITION, MC_MAX_POSITION = -1.2, 0.6
MC_GOAL = 0.45
MC_STEPS = 999
"""Steps per episode (gym's TimeLimit)."""
MC_CONTROL_COST = 0.2
"""R: gym's −0.1u² per step is the cost rate ½Ru² with R = 0.2."""
MC_GOAL_REWARD = 100.0


class MountainCar(ControlAffineSystem):
    """Gym's mountain car in continuous time (module docstring), time unit one gym step.

        ẋ = v,   v̇ = power · u − gravity · cos 3x

    Parameters
    ----------
    power, gravity : float
        Gym's 0.0015 and 0.0025 by default.
    """

    state_dim = 2
    control_dim = 1
    state_names = ("position", "velocity")
    angle_axes = ()
    default_box = ((MC_MIN_POSITION, MC_MAX_POSITION), (-MC_MAX_SPEED, MC_MAX_SPEED))

    def __init__(self, power: float = MC_POWER, gravity: float = MC_GRAVITY):
        self.power = float(power)
        self.gravity = float(gravity)
        if not (self.power > 0 and np.isfinite(self.power)):
            raise ValueError(f"power must be a positive finite number, got {power}")
        if not (self.gravity >= 0 and np.isfinite(self.gravity)):
            raise ValueError(f"gravity must be a non-negative finite number, got {gravity}")

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], -self.gravity * np.cos(3.0 * x[:, 0])], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 2, 1))
        B[:, 1, 0] = self.power
        return B

    def parameters(self):
        return {"power": self.power, "gravity": self.gravity}


MOUNTAIN_CAR_EXIT = Box([MC_GOAL, 0.0], [np.inf, np.inf])
"""Gym's flag: x ≥ 0.45 with v ≥ 0."""


def mountain_car_grid(n=(241, 201)) -> Grid:
    """Gym's state box, x ∈ [−1.2, 0.6], v ∈ [−0.07, 0.07], ``n`` nodes per axis (one count or
    one per axis). With n_x − 1 a multiple of 12 the flag x = 0.45 is a node, and with n_v odd
    v = 0 is."""
    counts = np.broadcast_to(np.atleast_1d(n), (2,)).tolist()
    return Grid(
        [
            Axis(MC_MIN_POSITION, MC_MAX_POSITION, int(counts[0]), name="position"),
            Axis(-MC_MAX_SPEED, MC_MAX_SPEED, int(counts[1]), name="velocity"),
        ]
    )


def mountain_car_problem(
    n=(241, 201),
    temperature: float = 0.01,
    control_cost: float = MC_CONTROL_COST,
    time_cost: float = 1e-3,
) -> Problem:
    """Gym's task as a first-exit :class:`~gridlbc.Problem` (module docstring).

    Parameters
    ----------
    n : int or (int, int)
        Grid nodes (position, velocity).
    temperature : float
        λ: the noise λ B R⁻¹ Bᵀ and the unit of z = exp(−v/λ).
    control_cost : float
        R (gym's is 0.2).
    time_cost : float
        q, the cost per step that prices the episode's length (gym has none; see the module
        docstring).
    """
    return Problem(
        MountainCar(),
        mountain_car_grid(n),
        None,
        state_cost=Constant(float(time_cost), 2),
        control_cost=control_cost,
        temperature=temperature,
        exit=MOUNTAIN_CAR_EXIT,
    )


def mountain_car_step(x: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gym's map for a batch: states ``(N, 2)`` and forces ``(N,)`` → (next states, rewards,
    terminated), in float64 (gym stores its state in float32 between steps)."""
    x = np.asarray(x, dtype=float)
    u = np.asarray(u, dtype=float).reshape(len(x))
    force = np.clip(u, -1.0, 1.0)
    v = np.clip(
        x[:, 1] + force * MC_POWER - MC_GRAVITY * np.cos(3 * x[:, 0]), -MC_MAX_SPEED, MC_MAX_SPEED
    )
    p = np.clip(x[:, 0] + v, MC_MIN_POSITION, MC_MAX_POSITION)
    v = np.where((p == MC_MIN_POSITION) & (v < 0), 0.0, v)
    done = (p >= MC_GOAL) & (v >= 0)
    reward = np.where(done, MC_GOAL_REWARD, 0.0) - 0.1 * u**2
    return np.column_stack([p, v]), reward, done


@dataclass(frozen=True)
class Episodes(PendulumEpisodes):
    """Gym episodes: ``scores`` (n,) the summed rewards, ``starts`` (n, d), ``seeds`` (n,) (as
    :class:`gridlbc.studies.gym_pendulum.Episodes`, whose mean and standard error they share),
    ``steps`` (n,) their lengths, ``reached`` (n,) whether the goal was reached, and
    ``peak_force`` (n,) the largest ``|u|`` the policy asked for."""

    steps: np.ndarray
    reached: np.ndarray
    peak_force: np.ndarray

    def summary(self) -> str:
        return (
            f"{self.mean:.3f} ± {self.standard_error:.3f} ({self.scores.size} episodes, "
            f"{self.reached.mean():.1%} reached, mean {self.steps.mean():.0f} steps)"
        )


def _check_episodes(episodes) -> int:
    if isinstance(episodes, bool) or not isinstance(episodes, (int, np.integer)) or episodes < 2:
        raise ValueError(
            f"episodes must be an integer ≥ 2 (for a standard error), got {episodes!r}"
        )
    return int(episodes)


def _gymnasium():
    try:
        import gymnasium
    except ImportError:
        raise ImportError(
            'the gym clients need gymnasium: pip install "gridlbc[gymnasium]"'
        ) from None
    return gymnasium


def run_mountain_car(policy, episodes: int = 1000, seed: int = 0) -> Episodes:
    """Play ``policy(x) -> (N, 1)`` (states ``(N, 2)`` = (position, velocity)) in gym's
    ``MountainCarContinuous-v0``, one env per episode, reset with seeds ``seed + i``.

    The episodes still running are stepped together, so the policy sees a batch per step. The
    force is passed to gym as given (gym clips it, and charges 0.1u² on the unclipped u: clip
    your policy). Score = gym's summed reward. Needs gymnasium.
    """

    def forces(x):
        u = np.asarray(policy(x), dtype=float)
        if u.shape != (x.shape[0], 1) or not np.all(np.isfinite(u)):
            raise ValueError(
                f"policy must return finite forces of shape ({x.shape[0]}, 1), got shape "
                f"{u.shape}" + ("" if u.shape != (x.shape[0], 1) else " with NaN or inf")
            )
        return [ui.astype(np.float32) for ui in u], np.abs(u[:, 0])

    return play_episodes(MOUNTAIN_CAR_ID, episodes, seed, forces, lambda env, obs: obs)


def play_episodes(env_id: str, episodes: int, seed: int, act, observe) -> Episodes:
    """One gym env per episode, reset with seeds ``seed + i``, the running ones stepped together:
    ``act(states)`` → (gym's actions, the size of each) for the running episodes' states
    ``(n, d)``, ``observe(env, obs)`` → the state the policy sees after a reset or a step."""
    gymnasium = _gymnasium()
    episodes = _check_episodes(episodes)
    envs = [gymnasium.make(env_id) for _ in range(episodes)]
    seeds = seed + np.arange(episodes)
    states = np.array(
        [observe(env, env.reset(seed=int(s))[0]) for env, s in zip(envs, seeds)], dtype=float
    )
    starts = np.array([env.unwrapped.state for env in envs], dtype=float)
    scores = np.zeros(episodes)
    steps = np.zeros(episodes, dtype=np.int64)
    reached = np.zeros(episodes, dtype=bool)
    running = np.ones(episodes, dtype=bool)
    peak = np.zeros(episodes)
    while running.any():
        active = np.flatnonzero(running)
        actions, size = act(states[active])
        peak[active] = np.maximum(peak[active], size)
        for i, a in zip(active, actions):
            obs, reward, terminated, truncated, _ = envs[i].step(a)
            states[i] = observe(envs[i], obs)
            scores[i] += reward
            steps[i] += 1
            if terminated or truncated:
                running[i] = False
                reached[i] = terminated
    for env in envs:
        env.close()
    return Episodes(scores, starts, seeds, steps, reached, peak)


def clipped(policy, bound: float = 1.0):
    """``policy`` with its forces clipped to ±``bound`` and the time argument dropped: a policy
    of the library ``(x, t)`` as a gym client ``(x)``."""

    def client(x):
        return np.clip(policy(x, 0.0), -bound, bound)

    return client


def zero_policy(x) -> np.ndarray:
    """No force: the car never reaches the flag (score 0)."""
    return np.zeros((np.atleast_2d(x).shape[0], 1))


# ---------------------------------------------------------------------------------------------
# Dynamic programming on gym's own map: the best achievable score, for comparison.


@jit
def _bilinear(V, p, v, lo_p, lo_v, hp, hv):
    """Bilinear interpolation of ``V`` (n_p, n_v) at (p, v), clamped to the box."""
    n_p, n_v = V.shape
    s = min(max((p - lo_p) / hp, 0.0), n_p - 1.0)
    t = min(max((v - lo_v) / hv, 0.0), n_v - 1.0)
    i = min(int(s), n_p - 2)
    j = min(int(t), n_v - 2)
    a = s - i
    b = t - j
    return (1 - a) * ((1 - b) * V[i, j] + b * V[i, j + 1]) + a * (
        (1 - b) * V[i + 1, j] + b * V[i + 1, j + 1]
    )


@jit
def _gym_step(p, v, u):
    """Gym's map for one state and one force (clipped to ±1): (p', v', terminated)."""
    force = min(max(u, -1.0), 1.0)
    v = v + force * MC_POWER - MC_GRAVITY * math.cos(3.0 * p)
    v = min(max(v, -MC_MAX_SPEED), MC_MAX_SPEED)
    p = min(max(p + v, MC_MIN_POSITION), MC_MAX_POSITION)
    if p == MC_MIN_POSITION and v < 0.0:
        v = 0.0
    return p, v, (p >= MC_GOAL and v >= 0.0)


@jit
def _bellman_sweep(V, out, best_u, positions, velocities, forces, price, goal_reward):
    """One Bellman update on gym's map: out(x) = max_u [−0.1u² − price + (goal_reward if the
    step reaches the flag else V(x'))]; returns the largest change."""
    n_p, n_v = V.shape
    lo_p, lo_v = positions[0], velocities[0]
    hp, hv = positions[1] - positions[0], velocities[1] - velocities[0]
    change = 0.0
    for i in range(n_p):
        for j in range(n_v):
            best = -np.inf
            arg = 0.0
            for u in forces:
                p, v, done = _gym_step(positions[i], velocities[j], u)
                value = -0.1 * u * u - price
                if done:
                    value += goal_reward
                else:
                    value += _bilinear(V, p, v, lo_p, lo_v, hp, hv)
                if value > best:
                    best, arg = value, u
            change = max(change, abs(best - V[i, j]))
            out[i, j] = best
            best_u[i, j] = arg
    return change


@dataclass(frozen=True, eq=False)
class DPSolution:
    """Dynamic programming on gym's map (:func:`mountain_car_dp`): the value ``values``
    (n_p, n_v) on the nodes ``positions`` × ``velocities`` (expected score to go), the force
    set, the price per step (0 for the exact time-limited DP), the steps (or sweeps) taken and
    the wall time."""

    positions: np.ndarray
    velocities: np.ndarray
    values: np.ndarray
    forces: np.ndarray
    price: float
    sweeps: int
    wall_time: float

    def value(self, x) -> np.ndarray:
        """Interpolated value (score to go) at states ``(N, 2)``."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        p, v = self.positions, self.velocities
        return np.array(
            [_bilinear(self.values, s[0], s[1], p[0], v[0], p[1] - p[0], v[1] - v[0]) for s in x]
        )

    def policy(self, x, forces: int = 201) -> np.ndarray:
        """The greedy force of the stationary DP at states ``(N, 2)``, ``(N, 1)``: one-step
        look-ahead over ``forces`` evenly spaced forces in [−1, 1] on gym's map."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        grid_u = np.linspace(-1.0, 1.0, forces)
        V, out, arg = self.values, np.empty((len(x), 1)), np.empty((len(x), 1))
        _greedy(V, x, self.positions, self.velocities, grid_u, self.price, MC_GOAL_REWARD, out, arg)
        return arg


@jit
def _greedy(V, x, positions, velocities, forces, price, goal_reward, out, arg):
    lo_p, lo_v = positions[0], velocities[0]
    hp, hv = positions[1] - positions[0], velocities[1] - velocities[0]
    for n in range(x.shape[0]):
        best = -np.inf
        for u in forces:
            p, v, done = _gym_step(x[n, 0], x[n, 1], u)
            value = -0.1 * u * u - price
            value += goal_reward if done else _bilinear(V, p, v, lo_p, lo_v, hp, hv)
            if value > best:
                best, arg[n, 0] = value, u
        out[n, 0] = best


def mountain_car_dp(
    n=(451, 301), forces: int = 41, price: float = 0.0, steps: int = MC_STEPS, tol: float = 1e-9
) -> DPSolution:
    """Dynamic programming on gym's deterministic map with bilinear interpolation of the value
    on an ``n`` = (n_p, n_v) grid of gym's box and ``forces`` forces evenly spaced in [−1, 1].

    ``price = 0``: the exact episode, ``steps`` Bellman updates backward from V = 0 (a
    truncated episode earns nothing more); the value is the best expected score with that many
    steps left. ``price > 0``: a stationary problem that charges ``price`` per step instead of
    limiting the steps (the discrete analogue of the time cost q), iterated until the largest
    change is below ``tol`` (at most ``steps`` × 20 sweeps); its greedy policy
    (:meth:`DPSolution.policy`) can be played in gym.
    """
    import time

    started = time.perf_counter()
    counts = np.broadcast_to(np.atleast_1d(n), (2,)).tolist()
    positions = np.linspace(MC_MIN_POSITION, MC_MAX_POSITION, int(counts[0]))
    velocities = np.linspace(-MC_MAX_SPEED, MC_MAX_SPEED, int(counts[1]))
    grid_u = np.linspace(-1.0, 1.0, forces)
    V = np.zeros((positions.size, velocities.size))
    out, best_u = np.empty_like(V), np.empty_like(V)
    sweeps = 0
    limit = steps if price == 0 else 20 * steps
    while sweeps < limit:
        change = _bellman_sweep(
            V, out, best_u, positions, velocities, grid_u, price, MC_GOAL_REWARD
        )
        V, out = out, V
        sweeps += 1
        if price > 0 and change < tol:
            break
    return DPSolution(
        positions, velocities, V.copy(), grid_u, float(price), sweeps, time.perf_counter() - started
    )


def start_states(samples: int = 1001) -> np.ndarray:
    """Gym's start distribution on an even grid of ``samples`` points: x₀ ∈ [−0.6, −0.4] (the
    midpoints of equal cells), v₀ = 0; the mean of a value over them is its expectation over
    x₀ ~ U[−0.6, −0.4] to O(samples⁻²)."""
    edges = np.linspace(-0.6, -0.4, samples + 1)
    return np.column_stack([0.5 * (edges[1:] + edges[:-1]), np.zeros(samples)])
