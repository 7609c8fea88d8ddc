"""Gymnasium's ``Acrobot-v1`` as a minimum-time first-exit problem (:class:`GymAcrobot`,
:func:`acrobot_problem`), played in gym (:func:`run_acrobot`).

**Gym's task**: torques {−1, 0, +1} on the second joint, held for Δt = 0.2 s integrated by one
RK4 step, the angles wrapped to [−π, π] and the velocities clipped to ±4π and ±9π after each
step (:func:`acrobot_step`, gym's map); −1 per step until the tip is above the bar
(−cos θ₁ − cos(θ₁ + θ₂) > 1), at most 500 steps, starts uniform in ±0.1 on all four
coordinates.

**The library's problem**: the continuous-time dynamics in canonical momenta (diagonal noise on
p₂ alone), q = 1 per second, exit when the tip is above the bar, solved by ``gridlbc.solve``
(linearly solvable) or ``solve_hjb(..., control_bounds=(-1, 1))`` (bounded torque).

**Gym's three torques from a solve**, three ways:

- :func:`acrobot_torques`: the sign of the continuous policy (the bounded minimum-time optimum
  is bang-bang);
- :meth:`StepsToGo.lookahead`: the best torque sequence of a few steps through gym's map, its
  leaves scored by the solve's value (v / Δt steps to go);
- :func:`rollout`: every torque for the next step (or sequence of a few), stepped by gym's map
  and then continued by the sign policy on gym's map to the bar; the quickest wins. It is the
  rollout of the sign policy (Bertsekas): never slower than it from any state, and it scores
  each candidate by what actually happens in gym, not by the grid's value.

:func:`acrobot_dp` is dynamic programming on gym's own map (no model, the value interpolated on a
4-D grid of gym's angles and velocities): the optimum every agent is compared with.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .._numba import jit
from ..costs import Constant
from ..grid import Axis, Grid
from ..problem import Problem
from ..systems.base import ControlAffineSystem
from .gym_clients import Episodes, play_episodes

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
        state_cost=Constant(1.0, 4),
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

    return play_episodes(ACROBOT_ID, episodes, seed, torques, lambda env, obs: env.unwrapped.state)


# ---------------------------------------------------------------------------------------------
# Gym's own map, and the greedy choice of the three torques through it.

MAX_SPEED = (4 * math.pi, 9 * math.pi)
"""Gym's clip of θ̇₁ and θ̇₂ after each step."""


@jit
def _rates(t1, t2, w1, w2, torque):
    """Gym's ``_dsdt`` (book dynamics), its arithmetic kept: (θ̈₁, θ̈₂)."""
    d1 = 0.25 + (1.0 + 0.25 + 2 * 0.5 * math.cos(t2)) + 1.0 + 1.0
    d2 = (0.25 + 0.5 * math.cos(t2)) + 1.0
    phi2 = 0.5 * 9.8 * math.cos(t1 + t2 - math.pi / 2.0)
    phi1 = (
        -0.5 * w2**2 * math.sin(t2)
        - 2 * 0.5 * w2 * w1 * math.sin(t2)
        + (0.5 + 1.0) * 9.8 * math.cos(t1 - math.pi / 2)
        + phi2
    )
    a2 = (torque + d2 / d1 * phi1 - 0.5 * w1**2 * math.sin(t2) - phi2) / (0.25 + 1.0 - d2**2 / d1)
    return -(d2 * a2 + phi1) / d1, a2


@jit
def _wrap(x):
    while x > math.pi:
        x -= 2 * math.pi
    while x < -math.pi:
        x += 2 * math.pi
    return x


@jit
def _gym_step(t1, t2, w1, w2, torque):
    """One gym step: RK4 over Δt with the torque held, angles wrapped, velocities clipped;
    (θ₁, θ₂, θ̇₁, θ̇₂, terminated)."""
    h, h2 = ACROBOT_STEP, ACROBOT_STEP / 2.0
    a1, b1 = _rates(t1, t2, w1, w2, torque)
    a2, b2 = _rates(t1 + h2 * w1, t2 + h2 * w2, w1 + h2 * a1, w2 + h2 * b1, torque)
    k2 = (w1 + h2 * a1, w2 + h2 * b1)
    a3, b3 = _rates(t1 + h2 * k2[0], t2 + h2 * k2[1], w1 + h2 * a2, w2 + h2 * b2, torque)
    k3 = (w1 + h2 * a2, w2 + h2 * b2)
    a4, b4 = _rates(t1 + h * k3[0], t2 + h * k3[1], w1 + h * a3, w2 + h * b3, torque)
    k4 = (w1 + h * a3, w2 + h * b3)
    n1 = _wrap(t1 + h / 6.0 * (w1 + 2 * k2[0] + 2 * k3[0] + k4[0]))
    n2 = _wrap(t2 + h / 6.0 * (w2 + 2 * k2[1] + 2 * k3[1] + k4[1]))
    v1 = min(max(w1 + h / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4), -MAX_SPEED[0]), MAX_SPEED[0])
    v2 = min(max(w2 + h / 6.0 * (b1 + 2 * b2 + 2 * b3 + b4), -MAX_SPEED[1]), MAX_SPEED[1])
    return n1, n2, v1, v2, -math.cos(n1) - math.cos(n2 + n1) > 1.0


@jit
def _step_kernel(states, torques, out, done):
    for n in range(states.shape[0]):
        s = _gym_step(states[n, 0], states[n, 1], states[n, 2], states[n, 3], torques[n])
        out[n, 0], out[n, 1], out[n, 2], out[n, 3] = s[0], s[1], s[2], s[3]
        done[n] = s[4]


def acrobot_step(x, actions) -> tuple[np.ndarray, np.ndarray]:
    """Gym's map for a batch: states ``(N, 4)`` = (θ₁, θ₂, θ̇₁, θ̇₂) and actions ``(N,)`` in
    {0, 1, 2} (torque −1, 0, +1) → (next states ``(N, 4)``, terminated ``(N,)``)."""
    x = np.ascontiguousarray(np.atleast_2d(x), dtype=float)
    torques = np.asarray(ACROBOT_TORQUES)[np.asarray(actions, dtype=np.int64).reshape(len(x))]
    out, done = np.empty_like(x), np.empty(len(x), dtype=bool)
    _step_kernel(x, torques, out, done)
    return out, done


@jit
def _corner(x, lo, h, n, periodic):
    """One axis of multilinear interpolation: (low node, high node, fraction), wrapped on a
    periodic axis and clamped to the box on a closed one."""
    s = (x - lo) / h
    if periodic:
        s -= n * math.floor(s / n)
        i = min(int(s), n - 1)
        return i, (i + 1) % n, s - i
    s = min(max(s, 0.0), n - 1.0)
    i = min(int(s), n - 2)
    return i, i + 1, s - i


@jit
def _interpolate(values, x0, x1, x2, x3, lo, spacing, shape, strides, periodic):
    """Multilinear interpolation of flat nodal ``values`` on a 4-D grid at one state."""
    i0, j0, f0 = _corner(x0, lo[0], spacing[0], shape[0], periodic[0])
    i1, j1, f1 = _corner(x1, lo[1], spacing[1], shape[1], periodic[1])
    i2, j2, f2 = _corner(x2, lo[2], spacing[2], shape[2], periodic[2])
    i3, j3, f3 = _corner(x3, lo[3], spacing[3], shape[3], periodic[3])
    total = 0.0
    for a in range(2):
        na, wa = (j0, f0) if a else (i0, 1.0 - f0)
        for b in range(2):
            nb, wb = (j1, f1) if b else (i1, 1.0 - f1)
            for c in range(2):
                nc, wc = (j2, f2) if c else (i2, 1.0 - f2)
                for e in range(2):
                    ne, we = (j3, f3) if e else (i3, 1.0 - f3)
                    w = wa * wb * wc * we
                    if w != 0.0:
                        node = na * strides[0] + nb * strides[1] + nc * strides[2]
                        total += w * values[node + ne * strides[3]]
    return total


@jit
def _to_go(values, s, momenta, lo, spacing, shape, strides, periodic):
    """The interpolated steps to go at gym's state ``s`` (on a grid of canonical momenta
    p = M(θ₂)θ̇ when ``momenta``, else of gym's velocities)."""
    x2, x3 = s[2], s[3]
    if momenta:
        c = math.cos(s[1])
        x2 = (3.5 + c) * s[2] + (1.25 + 0.5 * c) * s[3]
        x3 = (1.25 + 0.5 * c) * s[2] + 1.25 * s[3]
    return _interpolate(values, s[0], s[1], x2, x3, lo, spacing, shape, strides, periodic)


@jit
def _lookahead_kernel(
    states, depth, values, momenta, lo, spacing, shape, strides, periodic, actions, costs
):
    """For each state, the cost of each first action: the least over the 3^depth torque
    sequences of (steps to the first state above the bar) or (depth + steps to go at the
    leaf). Each prefix is stepped once (an odometer over the sequences)."""
    path = np.empty((depth + 1, 4))
    ended = np.zeros(depth + 1, dtype=np.bool_)
    when = np.zeros(depth + 1, dtype=np.int64)
    digit = np.zeros(depth, dtype=np.int64)
    for n in range(states.shape[0]):
        path[0] = states[n]
        ended[0] = False
        if depth == 0:
            here = _to_go(values, path[0], momenta, lo, spacing, shape, strides, periodic)
            for a in range(3):
                costs[n, a] = here
            actions[n] = 1
            continue
        for a in range(3):
            costs[n, a] = np.inf
        digit[:] = 0
        changed = 0
        while True:
            for level in range(changed, depth):
                if ended[level]:
                    path[level + 1] = path[level]
                    ended[level + 1], when[level + 1] = True, when[level]
                    continue
                s = path[level]
                t1, t2, w1, w2, done = _gym_step(s[0], s[1], s[2], s[3], digit[level] - 1.0)
                path[level + 1, 0], path[level + 1, 1] = t1, t2
                path[level + 1, 2], path[level + 1, 3] = w1, w2
                ended[level + 1], when[level + 1] = done, level + 1
            if ended[depth]:
                cost = float(when[depth])
            else:
                cost = depth + _to_go(
                    values, path[depth], momenta, lo, spacing, shape, strides, periodic
                )
            costs[n, digit[0]] = min(costs[n, digit[0]], cost)
            level = depth - 1
            while level >= 0 and digit[level] == 2:
                digit[level] = 0
                level -= 1
            if level < 0:
                break
            digit[level] += 1
            changed = level
        best = 0
        for a in range(1, 3):
            if costs[n, a] < costs[n, best]:
                best = a
        actions[n] = best


@dataclass(frozen=True, eq=False)
class StepsToGo:
    """A value in gym steps to go on a 4-D grid, and the greedy choice of gym's three torques
    through gym's own map (:meth:`lookahead`).

    Attributes
    ----------
    grid : Grid
        (θ₁, θ₂) periodic, then canonical momenta (p₁, p₂) (``momenta``: the library's
        problems, :func:`acrobot_problem`) or gym's velocities (θ̇₁, θ̇₂) (the DP on gym's map).
    values : ndarray (size,)
        Steps to go at the nodes (finite: where a solve's z underflowed, a large number).
    momenta : bool
    """

    grid: Grid
    values: np.ndarray
    momenta: bool

    @classmethod
    def from_solution(cls, solution) -> StepsToGo:
        """The value v (seconds to go, q = 1 per second) of a first-exit solve of
        :func:`acrobot_problem` (``gridlbc.solve``'s or ``solve_hjb``'s) in gym steps, v / Δt."""
        grid = solution.grid
        nodal = solution.value_nodes() if hasattr(solution, "value_nodes") else solution.values[0]
        steps = np.asarray(nodal, dtype=float) / ACROBOT_STEP
        finite = np.isfinite(steps)
        big = 10.0 * (steps[finite].max() if finite.any() else 1.0) + ACROBOT_STEPS
        return cls(grid, np.where(finite, steps, big), True)

    def __call__(self, x) -> np.ndarray:
        """Interpolated steps to go at gym's states ``(N, 4)`` = (θ₁, θ₂, θ̇₁, θ̇₂)."""
        x = np.ascontiguousarray(np.atleast_2d(x), dtype=float)
        return self.costs(x, 0)[:, 0]

    def costs(self, x, depth: int = 1) -> np.ndarray:
        """``(N, 3)``: for each first action (torque −1, 0, +1) at gym's states ``(N, 4)``, the
        least over the 3^(depth−1) continuations of the steps to the bar: k if the k-th step
        (k ≤ depth) is the first above it, else depth + the steps to go at the leaf. With
        ``depth`` 0, every column is the steps to go at x itself."""
        x = np.ascontiguousarray(np.atleast_2d(x), dtype=float)
        if isinstance(depth, bool) or not isinstance(depth, (int, np.integer)) or depth < 0:
            raise ValueError(f"depth must be a non-negative integer, got {depth!r}")
        lo, spacing, shape, strides, periodic = self.grid.kernel_arrays()
        costs = np.empty((len(x), 3))
        actions = np.empty(len(x), dtype=np.int64)
        values = np.ascontiguousarray(self.values, dtype=float)
        _lookahead_kernel(
            x,
            int(depth),
            values,
            self.momenta,
            lo,
            spacing,
            shape,
            strides,
            periodic,
            actions,
            costs,
        )
        return costs

    def lookahead(self, depth: int = 1):
        """Gym's action at states ``(N, 4)``: the first torque of the best of the 3^depth torque
        sequences through gym's map (:meth:`costs`); ties go to the lower torque."""

        def actions(x):
            return np.argmin(self.costs(x, depth), axis=1)

        return actions


def _sequences(depth: int) -> np.ndarray:
    """The 3^depth action sequences ``(3^depth, depth)``, the first action slowest."""
    if isinstance(depth, bool) or not isinstance(depth, (int, np.integer)) or depth < 1:
        raise ValueError(f"depth must be a positive integer, got {depth!r}")
    return np.array(np.unravel_index(np.arange(3**depth), (3,) * depth)).T


def rollout_steps(base, x, depth: int = 1, horizon: int = ACROBOT_STEPS) -> np.ndarray:
    """``(N, 3^depth)``: from gym's states ``(N, 4)``, the steps to the bar on gym's map of each
    torque sequence of length ``depth`` (sequences in :func:`numpy.unravel_index` order, the
    first action slowest) followed by the policy ``base`` (actions in {0, 1, 2}); ``inf``
    where the bar is not reached within ``horizon`` steps."""
    x = np.ascontiguousarray(np.atleast_2d(x), dtype=float)
    sequences = _sequences(depth)
    k = len(sequences)
    states = np.repeat(x, k, axis=0)
    steps = np.full(len(states), np.inf)
    running = np.ones(len(states), dtype=bool)
    for t in range(1, horizon + 1):
        active = np.flatnonzero(running)
        if active.size == 0:
            break
        head = t <= depth
        actions = sequences[active % k, t - 1] if head else np.asarray(base(states[active]))
        states[active], done = acrobot_step(states[active], actions)
        steps[active[done]] = t
        running[active[done]] = False
    return steps.reshape(len(x), k)


def rollout(base, depth: int = 1, horizon: int = ACROBOT_STEPS):
    """The rollout of the policy ``base`` (gym states ``(N, 4)`` → actions ``(N,)``) through
    gym's own map: at each state, every torque sequence of length ``depth`` is stepped by gym's
    map and then ``base`` is played on it to the bar (:func:`rollout_steps`); the action is the
    first torque of the quickest (ties to the lower torque). It reaches the bar no later than
    ``base`` from every state (the base's own first action is among those scored, and gym is
    deterministic), and it corrects what ``base`` got wrong about gym's map: the held torque,
    the 0.2 s step and the grid's errors."""
    first = _sequences(depth)[:, 0]

    def actions(x):
        return first[np.argmin(rollout_steps(base, x, depth, horizon), axis=1)]

    return actions


# ---------------------------------------------------------------------------------------------
# Dynamic programming on gym's own map: the optimum every agent is measured against.


@jit
def _successor_kernel(nodes, out, done):
    """Gym's step from every node under each of the three torques (float32 to halve the
    memory: the nodes' successors are only interpolated)."""
    for n in range(nodes.shape[0]):
        for a in range(3):
            s = _gym_step(nodes[n, 0], nodes[n, 1], nodes[n, 2], nodes[n, 3], a - 1.0)
            out[n, a, 0], out[n, a, 1], out[n, a, 2], out[n, a, 3] = s[0], s[1], s[2], s[3]
            done[n, a] = s[4]


@jit
def _bellman_kernel(values, out, successors, done, lo, spacing, shape, strides, periodic):
    """One Jacobi sweep of C(x) = min over the torques of 0 (the step ends above the bar) or
    1 + C(x'); returns the largest change."""
    change = 0.0
    for n in range(successors.shape[0]):
        best = np.inf
        for a in range(3):
            if done[n, a]:
                best = 0.0
                break
            s = successors[n, a]
            cost = 1.0 + _interpolate(
                values, s[0], s[1], s[2], s[3], lo, spacing, shape, strides, periodic
            )
            best = min(best, cost)
        change = max(change, abs(best - values[n]))
        out[n] = best
    return change


def acrobot_dp_grid(n=(31, 31, 31, 31), speeds=MAX_SPEED) -> Grid:
    """θ₁, θ₂ periodic on [−π, π), θ̇₁ ∈ ±``speeds[0]``, θ̇₂ ∈ ±``speeds[1]`` (by default gym's
    clips, ±4π and ±9π), ``n`` nodes per axis (one count or one per axis)."""
    counts = np.broadcast_to(np.atleast_1d(n), (4,)).tolist()
    return Grid(
        [
            Axis(-math.pi, math.pi, int(counts[0]), periodic=True, name="theta1"),
            Axis(-math.pi, math.pi, int(counts[1]), periodic=True, name="theta2"),
            Axis(-speeds[0], speeds[0], int(counts[2]), name="dtheta1"),
            Axis(-speeds[1], speeds[1], int(counts[3]), name="dtheta2"),
        ]
    )


@dataclass(frozen=True, eq=False)
class AcrobotDP:
    """Dynamic programming on gym's map (:func:`acrobot_dp`): ``steps_to_go`` (on gym's
    velocities), the Jacobi sweeps taken, the last sweep's largest change and the wall time."""

    steps_to_go: StepsToGo
    sweeps: int
    change: float
    wall_time: float


def acrobot_dp(
    n=(31, 31, 31, 31), speeds=MAX_SPEED, max_sweeps: int = ACROBOT_STEPS, tol: float = 1e-6
) -> AcrobotDP:
    """Value iteration on gym's deterministic map over its three torques, the value (gym steps
    to the bar, −1 reward each, the last free) interpolated multilinearly on
    :func:`acrobot_dp_grid` ``(n, speeds)`` (beyond its velocities, the value at the box's
    edge); no model, only gym's step (RK4, wrapping, clips) and its
    end test on the exact successor. Jacobi sweeps from C = 0: after k sweeps C is the optimum
    with k steps left (gym's limit is 500, the default ``max_sweeps``); stops earlier when the
    largest change is below ``tol``. The successors are computed once (16 bytes per node and
    torque, float32)."""
    started = time.perf_counter()
    grid = acrobot_dp_grid(n, speeds)
    successors = np.empty((grid.size, 3, 4), dtype=np.float32)
    done = np.empty((grid.size, 3), dtype=bool)
    _successor_kernel(grid.nodes(), successors, done)
    lo, spacing, shape, strides, periodic = grid.kernel_arrays()
    values, out = np.zeros(grid.size), np.empty(grid.size)
    sweeps, change = 0, np.inf
    while sweeps < max_sweeps and change >= tol:
        change = _bellman_kernel(
            values, out, successors, done, lo, spacing, shape, strides, periodic
        )
        values, out = out, values
        sweeps += 1
    steps = StepsToGo(grid, values, momenta=False)
    return AcrobotDP(steps, sweeps, float(change), time.perf_counter() - started)
