"""The named problems of the studies: one definition each, shared by the demo, the verification
report, the convergence studies, the figures, the benchmarks and the tests.

- :func:`swingup_problem`: the pendulum swing-up (T = 3, λ = 1, g = xᵀdiag(10, ½)x, from
  :data:`SWINGUP_START`, near hanging down at rest);
- :func:`pendulum_problem`: the pendulum of the convergence study (T = 1, ω box ±8);
- :func:`mild_pendulum_problem` and :func:`steep_swingup_problem`: the accuracy study's damped
  pendulum with a state cost, and a swing-up whose steep terminal cost tests small temperatures;
- :func:`pointmass_problem`: the linear-quadratic point mass with a Riccati solution;
- :func:`coordination_problem`: a point mass with two acceptable goals;
- :func:`rotor_problem`: a pendulum without gravity (a rotor) turned half a turn to an angle
  between two solved goals (the interpolation example), from :data:`ROTOR_START`;
- :func:`obstacle_problem`: a point steered in the plane round a smooth wall
  (:class:`CapsuleObstacle`) to a goal behind it (the interpolation figure), from
  :data:`OBSTACLE_START`, and :func:`obstacle_trajectories`, its trajectory components;
- :func:`gymnast_problem`: the paper's acrobot swing-up (paper §6.2), from :data:`GYMNAST_START`;
- :func:`diver_problem`: the 4-link diver beyond the grid (paper §6.1–6.2, Figs. 6 and 8), a
  grid-free problem, taking off from :func:`diver_start`.
- :func:`pendulum_v1_problem`: gymnasium's ``Pendulum-v1`` (see :mod:`gridlbc.studies.gym_pendulum`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..costs import Quadratic
from ..grid import Axis, Grid
from ..problem import Problem
from ..regions import Ball, Union
from ..systems import Acrobot, LinearSystem, Pendulum, PlanarChain, PointMass
from ..trajectory import expand, optimize

# -- pendulum --------------------------------------------------------------------------------------

SWINGUP_START = np.array([2.8, 0.0])
"""Start of the swing-up (θ, ω): near hanging down (θ = ±π), at rest."""

SWINGUP_WEIGHTS = (10.0, 0.5)
"""diag W of the swing-up's terminal cost g = xᵀWx (upright at rest)."""


def pendulum_grid(n: int, omega_max: float = 10.0) -> Grid:
    """θ periodic on [−π, π) with ``n`` nodes, ω ∈ [−ω_max, ω_max] with n + 1 nodes."""
    return Grid(
        [
            Axis(-math.pi, math.pi, n, periodic=True, name="theta"),
            Axis(-omega_max, omega_max, n + 1, name="omega"),
        ]
    )


def swingup_problem(
    n: int = 256, terminal_cost=None, horizon: float = 3.0, temperature: float = 1.0
) -> Problem:
    """Pendulum swing-up: m = l = 1, g = 9.81, T = 3, λ = 1, R = 1, no state cost,
    g(x) = xᵀ diag(10, ½) x (or ``terminal_cost``), on :func:`pendulum_grid` (ω ±10)."""
    cost = Quadratic([0.0, 0.0], SWINGUP_WEIGHTS) if terminal_cost is None else terminal_cost
    return Problem(Pendulum(), pendulum_grid(n), horizon, cost, temperature=temperature)


PENDULUM_WEIGHTS = (10.0, 0.5)
"""Terminal weights of the pendulum convergence study: g = θ² · 10 + ω² · 0.5."""


def pendulum_problem(
    n: int, temperature: float = 1.0, horizon: float = 1.0, weights=PENDULUM_WEIGHTS
) -> Problem:
    """Pendulum of the convergence study (m = l = 1, g = 9.81) on :func:`pendulum_grid` with
    ω ∈ [−8, 8] (equal spacing 2π/n and 16/n), g = (θ, ω)ᵀdiag(weights)(θ, ω), no state cost."""
    return Problem(
        Pendulum(),
        pendulum_grid(n, 8.0),
        horizon,
        Quadratic([0.0, 0.0], list(weights)),
        temperature=temperature,
    )


MILD_STATES = np.array([(1.0, 0.0), (-1.0, 0.0), (0.5, 2.0), (-0.5, -2.0), (0.0, 1.0), (1.0, -2.0)])
"""Start states of the accuracy study on :func:`mild_pendulum_problem` (|θ| ≤ 1, |ω| ≤ 2)."""


def mild_pendulum_problem(n: int = 128) -> Problem:
    """Damped pendulum (b = 0.1), T = 1, λ = 1, q = xᵀdiag(0.5, 0.05)x, g = xᵀdiag(3, 0.3)x, on
    :func:`pendulum_grid` with ω ∈ [−8, 8]: a smooth value, mildly curved."""
    return Problem(
        Pendulum(damping=0.1),
        pendulum_grid(n, 8.0),
        1.0,
        Quadratic([0, 0], [3, 0.3]),
        state_cost=Quadratic([0, 0], [0.5, 0.05]),
        temperature=1.0,
    )


STEEP_START = np.array([3.0, 0.0])
"""Start of :func:`steep_swingup_problem` (θ, ω): near hanging down, at rest."""

STEEP_DETERMINISTIC_OPTIMUM = 27.95
"""The λ → 0 optimum of :func:`steep_swingup_problem` from :data:`STEEP_START` (trajectory
optimisation, as quoted with the accuracy study)."""


def steep_swingup_problem(n: int = 201, temperature: float = 1.0) -> Problem:
    """Swing-up with a steep terminal cost, g = xᵀdiag(50, 5)x, T = 2, on :func:`pendulum_grid`
    (ω ±10): v/λ rises by up to 10/λ per cell along ω, the test of small temperatures."""
    return Problem(
        Pendulum(), pendulum_grid(n), 2.0, Quadratic([0, 0], [50, 5]), temperature=temperature
    )


# -- point mass ------------------------------------------------------------------------------------


def pointmass_problem(h: float | None = None, grid: Grid | None = None) -> Problem:
    """PointMass (m = 1), λ = 0.5, q = xᵀdiag(0.5, 0.05)x, g = (x − (1, 0))ᵀdiag(2, 0.5)(x − (1, 0)),
    T = 2: linear-quadratic, so :func:`gridlbc.reference.lq_solution` is exact. On
    [−4, 4] × [−6, 6] with spacing ``h`` on both axes (8/h and 12/h must be integers), or on
    ``grid``."""
    if (h is None) == (grid is None):
        raise ValueError("give exactly one of h (a spacing) or grid")
    if grid is None:
        assert h is not None
        counts = [8 / h, 12 / h]
        if not all(abs(c - round(c)) < 1e-9 and c >= 2 for c in counts):
            raise ValueError(
                f"h must divide 8 and 12 into at least 2 cells (e.g. 1/4, 1/8), got {h}"
            )
        grid = Grid(
            [
                Axis(-4.0, 4.0, round(counts[0]) + 1, name="position"),
                Axis(-6.0, 6.0, round(counts[1]) + 1, name="velocity"),
            ]
        )
    return Problem(
        PointMass(),
        grid,
        2.0,
        Quadratic([1.0, 0.0], [2.0, 0.5]),
        Quadratic([0.0, 0.0], [0.5, 0.05]),
        control_cost=1.0,
        temperature=0.5,
    )


GOAL_WEIGHTS = (20.0, 2.0)
"""W of the coordination goals g = (x − c)ᵀW(x − c), c = (±1, 0)."""


def coordination_problem(n: int = 81) -> Problem:
    """Point mass, two acceptable outcomes: at rest at x = −1 or x = +1 after T = 3 s, λ = 0.3
    (the problem's own terminal cost is the goal at −1; combine it with the goal at +1)."""
    grid = Grid([Axis(-3.0, 3.0, n, name="position"), Axis(-4.0, 4.0, n, name="velocity")])
    return Problem(PointMass(), grid, 3.0, Quadratic([-1.0, 0.0], GOAL_WEIGHTS), temperature=0.3)


# -- exit bays (a task that ends) ------------------------------------------------------------------

BAY_CENTRES = (-1.3, 0.0, 1.3)
"""Positions of the three parking bays of :func:`bays_problem`."""

BAY_START = np.array([-0.6, 1.2])
"""Start (position, velocity) of the bays figure: between the left and middle bays, moving right."""

BAY_MISS = 5.0
"""Exit cost of a bay-indicator component at the bays it does not prefer (e^{−BAY_MISS/λ} ≈ 5e−5)."""


def bays_problem(n: int = 121) -> Problem:
    """A point mass parks in one of three bays and stops there (first exit, no horizon): the
    exit set is the three ellipses {|x − c_i| ≤ 0.2, |v| ≤ 0.4}, q = 0.5 + 0.05 v² per second,
    λ = 0.5, on [−2, 2] × [−3, 3]. Its exit cost is 0; the components of the bays figure pay 0 at
    one bay and :data:`BAY_MISS` at the others (:func:`bay_cost`)."""
    grid = Grid([Axis(-2.0, 2.0, n, name="position"), Axis(-3.0, 3.0, n, name="velocity")])
    bays = Union(tuple(Ball([c, 0.0], [0.2, 0.4]) for c in BAY_CENTRES))
    return Problem(
        PointMass(),
        grid,
        None,
        state_cost=BayStateCost(),
        temperature=0.5,
        exit=bays,
    )


@dataclass(frozen=True)
class BayStateCost:
    """q(x) = 0.5 + 0.05 v²: time costs, and so does speed."""

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return 0.5 + 0.05 * x[:, 1] ** 2


@dataclass(frozen=True)
class BayCost:
    """Exit cost 0 at bay ``index`` (the nearest bay to the state) and :data:`BAY_MISS` at the
    others."""

    index: int

    def __call__(self, x: np.ndarray) -> np.ndarray:
        nearest = np.argmin(np.abs(x[:, :1] - np.asarray(BAY_CENTRES)), axis=1)
        return np.where(nearest == self.index, 0.0, BAY_MISS)


def bay_cost(index: int) -> BayCost:
    """The exit cost of the component that prefers bay ``index`` (0, 1, 2 from the left)."""
    return BayCost(index)


# -- rotor -----------------------------------------------------------------------------------------

ROTOR_START = np.array([3.12, 0.0])
"""Start of the rotor (θ, ω): almost opposite the goals (θ = ±π), at rest."""

ROTOR_WEIGHTS = (0.8, 0.5)
"""diag W of the rotor's goals g = (x − c)ᵀW(x − c), c = (θ_goal, 0)."""

ROTOR_GOALS = (-0.25, 0.25)
"""The two solved goal angles (rad); the target θ̄ = 0 lies between them."""


def rotor_problem(n: int = 101, terminal_cost=None) -> Problem:
    """A pendulum without gravity (θ̈ = u, θ periodic, ω ∈ [−3, 3]), T = 5, λ = 0.2, R = 1; the
    terminal cost defaults to the target, at rest at θ̄ = 0."""
    grid = Grid(
        [
            Axis(-math.pi, math.pi, n, periodic=True, name="theta"),
            Axis(-3.0, 3.0, n + 1, name="omega"),
        ]
    )
    cost = Quadratic([0.0, 0.0], ROTOR_WEIGHTS) if terminal_cost is None else terminal_cost
    return Problem(Pendulum(gravity=0.0), grid, 5.0, cost, temperature=0.2)


# -- obstacle --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class CapsuleObstacle:
    """A smooth capsule of state cost in the plane: the points within r of the segment [a, b],

        q(x) = H / (1 + exp((d(x) − r) / ε)),      d(x) = ‖x − a − s (b − a)‖,
        s = clip((x − a)·(b − a) / ‖b − a‖², 0, 1),

    d the distance to the segment. H (``height``) well inside, H/2 on the rim (d = r), falling to
    zero over a few ε (``edge``) outside. ``start`` = ``end`` makes it a disc of radius r; a long
    segment across the straight path is a wall. It acts on the first two coordinates of the
    state."""

    start: tuple
    end: tuple
    radius: float
    height: float
    edge: float

    def __post_init__(self):
        for name in ("start", "end"):
            point = np.asarray(getattr(self, name), dtype=float)
            if point.shape != (2,) or not np.all(np.isfinite(point)):
                raise ValueError(
                    f"CapsuleObstacle {name} must be a finite point (x, y), got "
                    f"{getattr(self, name)!r}"
                )
        for name in ("radius", "edge"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"CapsuleObstacle {name} must be a positive length, got {value!r}")
        if not (np.isfinite(self.height) and self.height >= 0):
            raise ValueError(
                f"CapsuleObstacle height must be a finite cost ≥ 0, got {self.height!r}"
            )

    def distance(self, x) -> np.ndarray:
        """d(x), the distance of each state's first two coordinates to the segment: (N,)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))[:, :2]
        a, b = np.asarray(self.start, dtype=float), np.asarray(self.end, dtype=float)
        direction = b - a
        length2 = direction @ direction
        s = np.zeros(len(x)) if length2 == 0 else np.clip((x - a) @ direction / length2, 0, 1)
        return np.hypot(*(x - a - s[:, None] * direction).T)

    def __call__(self, x) -> np.ndarray:
        # H / (1 + e^u) = H exp(−log(1 + e^u)), finite for any u.
        u = (self.distance(x) - self.radius) / self.edge
        return self.height * np.exp(-np.logaddexp(0.0, u))


OBSTACLE = CapsuleObstacle((0.0, -1.8), (0.0, 1.8), radius=0.25, height=50.0, edge=0.08)
"""The obstacle of :func:`obstacle_problem`: a wall, the segment x = 0, |y| ≤ 1.8, thickened by
r = 0.25, cost 50 inside; it blocks the straight path from :data:`OBSTACLE_START` to the goals."""

OBSTACLE_START = np.array([1.0, 0.0])
"""Start of :func:`obstacle_problem` (x, y): in front of the wall's centre."""

OBSTACLE_TARGET = (-0.7, 0.0)
"""The intermediate goal, directly behind the wall's centre."""

OBSTACLE_GOALS = ((-0.7, 0.09), (-0.7, -0.09))
"""The solved goals, just above and just below the intermediate goal: the first is reached round
the wall's upper end, the second round its lower end."""

OBSTACLE_WEIGHTS = (20.0, 10.0)
"""diag W of the goals g = (x − c)ᵀW(x − c)."""


def obstacle_problem(
    n: int = 151, terminal_cost=None, temperature: float = 0.2, horizon: float = 3.0
) -> Problem:
    """A point steered in the plane round a wall to a goal behind it (the interpolation figure).

    The single integrator dx = u dt + dξ, Cov[dξ] = λ I dt (:class:`~gridlbc.systems.LinearSystem`
    with A = 0, B = I), on x ∈ [−2, 2] with ``n`` nodes and y ∈ [−3, 3] at the same spacing
    (``n`` odd), with the state cost q of the wall :data:`OBSTACLE` between
    :data:`OBSTACLE_START` and the goals, R = 1, T = ``horizon``, λ = ``temperature``; the
    terminal cost defaults to the intermediate goal, g = (x − c̄)ᵀW(x − c̄) with
    c̄ = :data:`OBSTACLE_TARGET` and W = diag :data:`OBSTACLE_WEIGHTS`.
    """
    if n < 5 or n % 2 == 0:
        raise ValueError(
            f"n must be an odd number of nodes ≥ 5 so that both axes share one "
            f"spacing, e.g. 41, 101 or 151; got {n}"
        )
    grid = Grid([Axis(-2.0, 2.0, n, name="x"), Axis(-3.0, 3.0, 3 * (n - 1) // 2 + 1, name="y")])
    cost = Quadratic(OBSTACLE_TARGET, OBSTACLE_WEIGHTS) if terminal_cost is None else terminal_cost
    plane = LinearSystem(np.zeros((2, 2)), np.eye(2), state_names=("x", "y"))
    return Problem(plane, grid, horizon, cost, state_cost=OBSTACLE, temperature=temperature)


def obstacle_trajectories(
    problem: Problem, restarts: int = 32, n_intervals: int = 300, radius: float | str | None = None
) -> list:
    """The trajectory components of the interpolation figure: one per goal of
    :data:`OBSTACLE_GOALS`, each a locally optimal path of the noise-free problem with its
    quadratic value expansion and LQR tracker (:func:`gridlbc.trajectory.expand`).

    The upper goal's path is the best of the multi-start search
    (:func:`gridlbc.trajectory.optimize`) and of a tape that flies at constant speed on each
    leg of start → (0, y_e + r + 0.3) → goal, round the wall's upper end (y_e its end, r its
    radius), so the search cannot settle on a path through the wall. The task is symmetric
    under y → −y, so the lower goal's optimum is the upper's mirror image: its path starts from
    the mirrored controls (u_y → −u_y) and is polished by DDP.

    ``radius`` is the trackers' saturation (:func:`gridlbc.trajectory.expand`); the default here,
    ``None``, leaves them unsaturated. The dynamics are linear with B = I, so the plain tracker
    ū + KΔx is, to O(Δt), the gradient control −∇v̂ of the component's own value expansion,
    also far from its tape. LBC needs that where its blend weights mix: behind the wall the
    other route's component gets a share of the weight (its v̂ there is an obstacle-free
    quadratic), and its unsaturated control points to its own goal, pulling LBC's rollouts
    toward c̄. Saturated (the library's default on a problem that is not linear-quadratic),
    that control is mostly the other tape's velocity, pointing towards its goal from the other
    side, and it slows LBC's descent instead: LBC then stops where a single component stops
    (docs/studies.rst, Interpolation, which measures both). A component alone stays near its tape, where
    the two trackers agree.
    """
    wall = problem.state_cost
    if not isinstance(wall, CapsuleObstacle):
        raise TypeError(
            "obstacle_trajectories needs a problem from obstacle_problem (a capsule wall)"
        )
    upper_goal, lower_goal = (
        problem.replace(terminal_cost=Quadratic(c, OBSTACLE_WEIGHTS)) for c in OBSTACLE_GOALS
    )
    corner = (0.0, wall.end[1] + wall.radius + 0.3)
    legs = np.diff([OBSTACLE_START, corner, OBSTACLE_GOALS[0]], axis=0)
    lengths = np.hypot(*legs.T)
    velocities = legs / lengths[:, None] * (lengths.sum() / problem.horizon)  # one speed
    first_leg = np.arange(n_intervals) < n_intervals * lengths[0] / lengths.sum()
    tape = np.where(first_leg[:, None], velocities[0], velocities[1])
    upper = optimize(
        upper_goal,
        OBSTACLE_START,
        restarts=restarts,
        seed=0,
        n_intervals=n_intervals,
        initial_controls=tape,
    )
    lower = optimize(
        lower_goal,
        OBSTACLE_START,
        n_intervals=n_intervals,
        initial_controls=upper.controls * [1.0, -1.0],
        search=False,
    )
    return [expand(upper_goal, upper, radius=radius), expand(lower_goal, lower, radius=radius)]


# -- gymnast ---------------------------------------------------------------------------------------

GYMNAST_START = np.array([np.radians(-105.0), np.radians(-15.0), 0.0, 0.0])
"""The paper's swing-up test state (θ1, θ2, p1, p2): (−105°, −15°) at rest."""

GYMNAST_WEIGHTS = (10.0, 10.0, 0.5, 0.5)
"""diag W of the gymnast's terminal cost g(x) = xᵀ W x."""


def gymnast_problem(
    n=31,
    momentum_bounds=(16.0, 9.0),
    hip_range: float | None = np.pi,
    horizon: float = 3.0,
    temperature: float = 1.0,
) -> Problem:
    """The acrobot swing-up (see :mod:`gridlbc.studies.gymnast`) on an n⁴ grid (or ``n`` =
    (n1, n2, n3, n4)), momentum box ±P1 × ±P2 and hip stops at ±``hip_range`` (``None``: a free,
    periodic hip)."""
    shape = (n,) * 4 if np.isscalar(n) else tuple(n)
    if len(shape) != 4:
        raise ValueError(f"n must be one node count or four, got {n!r}")
    p1, p2 = (float(b) for b in momentum_bounds)
    if not (p1 > 0 and p2 > 0):
        raise ValueError(f"momentum_bounds must be two positive numbers, got {momentum_bounds!r}")
    if hip_range is None:
        hip = Axis(-np.pi, np.pi, shape[1], periodic=True, name="theta2")
    elif isinstance(hip_range, (int, float)) and 0 < hip_range <= np.pi:
        hip = Axis(-hip_range, hip_range, shape[1], name="theta2")
    else:
        raise ValueError(
            f"hip_range must be None (a free hip) or a number in (0, π], got {hip_range!r}"
        )
    grid = Grid(
        [
            Axis(-np.pi, np.pi, shape[0], periodic=True, name="theta1"),
            hip,
            Axis(-p1, p1, shape[2], name="p1"),
            Axis(-p2, p2, shape[3], name="p2"),
        ]
    )
    return Problem(
        Acrobot(), grid, horizon, Quadratic(np.zeros(4), GYMNAST_WEIGHTS), temperature=temperature
    )


# -- diver -------------------------------------------------------------------------------------
#
# The diver (paper §6.1–6.2, Figs. 6 and 8), beyond the grid: a free-flying 4-link
# :class:`gridlbc.systems.PlanarChain` of uniform rods, 8-D state (θ1 … θ4, p1 … p4). Link 1 is the
# arms (from the hands to the shoulders), then the trunk with the head, the thighs and the shanks;
# the torques act at the shoulder, hip and knee. Masses are fractions of the body mass (total 1)
# and lengths in metres, roughly human proportions. No joint limits are modelled.
#
# The dive lasts T = 1 s (about a 3 m springboard). It takes off standing straight with the arms
# overhead, θ = (π, 0, 0, 0) (the hands at the top: every link points down), turning rigidly at
# ω0 = κ · 2 rad/s counterclockwise; κ scales the take-off angular momentum p1 = I ω0, which
# nothing in the air can change. A vertical head-first entry is θ = (0, 0, 0, 0) (the hands at the
# bottom, the body straight): half a somersault, π rad, more than the straight body's ω0 T = 2 rad,
# so the diver must pike to turn faster and open again to enter. The entry cost is
#
#     g(x) = W1 (θ1 − c)² + W_shape (θ2² + θ3² + θ4²),      wrap-aware in the angles,
#
# c = 0 for a vertical entry, c < 0 short of vertical (under-rotated), c > 0 past it.

DIVER_MASSES = (0.1, 0.58, 0.2, 0.12)
"""Arms, trunk and head, thighs, shanks (fractions of the body mass)."""

DIVER_LENGTHS = (0.6, 0.8, 0.45, 0.5)
"""Hands–shoulders, shoulders–hips, hips–knees, knees–feet (m)."""

DIVER_HORIZON = 1.0
"""Flight time T (s)."""

DIVER_SPIN = 2.0
"""Nominal take-off angular velocity ω0 of the straight body (rad/s, counterclockwise)."""

DIVER_ENTRY_WEIGHTS = (10.0, 2.0)
"""W1 on the arms' angle from vertical, W_shape on each joint angle (per rad²)."""

DIVER_CONTROL_COST = 50.0
"""R per joint torque: a dive's torques of a few tenths of N·m (body mass 1) cost about as much as
its entry error."""

DIVER_TEMPERATURE = 1.0
"""λ: the paper's exp(−v) (λ = 1), which makes exp(−g/λ) wide enough (±0.3 rad) to interpolate
entries 0.6 rad apart."""


def diver() -> PlanarChain:
    """The 4-link free-flying diver."""
    return PlanarChain(4, masses=DIVER_MASSES, lengths=DIVER_LENGTHS, pinned=False)


def diver_start(momentum_scale: float = 1.0) -> np.ndarray:
    """Take-off state ``(8,)``: straight, arms overhead, turning rigidly at κ ω0 (κ =
    ``momentum_scale``, so p1 is κ times nominal)."""
    return diver().from_velocities([np.pi, 0.0, 0.0, 0.0, momentum_scale * DIVER_SPIN, 0, 0, 0])[0]


def diver_entry_cost(entry_angle: float = 0.0) -> Quadratic:
    """g of the entry: the arms at ``entry_angle`` rad from vertical (negative: short of it), the
    body straight; no cost on the momenta."""
    w1, shape = DIVER_ENTRY_WEIGHTS
    return Quadratic([entry_angle, 0, 0, 0, 0, 0, 0, 0], [w1, shape, shape, shape, 0, 0, 0, 0])


def diver_problem(
    entry_angle: float = 0.0,
    temperature: float = DIVER_TEMPERATURE,
    control_cost: float = DIVER_CONTROL_COST,
) -> Problem:
    """The grid-free diving problem: T = 1 s, the entry cost :func:`diver_entry_cost`, q = 0."""
    return Problem(
        diver(),
        None,
        DIVER_HORIZON,
        diver_entry_cost(entry_angle),
        control_cost=control_cost,
        temperature=temperature,
    )


# -- gymnasium's Pendulum-v1 -----------------------------------------------------------------------

PENDULUM_V1_STEP = 0.05
"""Gym's time step (s)."""
PENDULUM_V1_STEPS = 200
"""Steps per episode (gym's TimeLimit): a 10 s horizon."""
PENDULUM_V1_MAX_SPEED = 8.0
"""Gym clips ω to ± this (rad/s)."""


def pendulum_v1_system() -> Pendulum:
    """Gym's pendulum in the library's form: θ̈ = (3g/2l) sin θ + (3/ml²) u = 15 sin θ + 3u."""
    return Pendulum(mass=0.75, length=2 / 3, gravity=10.0)


def _no_terminal_cost(x: np.ndarray) -> np.ndarray:
    return np.zeros(len(x))


def pendulum_v1_problem(
    n: int = 201, temperature: float = 1e-4, control_cost: float = 0.04
) -> Problem:
    """Gym's episode as a :class:`~gridlbc.Problem` on an ``n × n`` grid.

    θ periodic on [−π, π), ω on [−8, 8], horizon 200 × 0.05 s, q = 20θ² + 2ω² (gym's reward per
    step over its 0.05 s), R = ``control_cost`` (gym's is 0.04), no terminal cost (the episode
    just ends). Gym is deterministic: hence the small default temperature.
    """
    grid = Grid(
        [
            Axis(-math.pi, math.pi, n, periodic=True, name="theta"),
            Axis(-PENDULUM_V1_MAX_SPEED, PENDULUM_V1_MAX_SPEED, n, name="omega"),
        ]
    )
    return Problem(
        pendulum_v1_system(),
        grid,
        horizon=PENDULUM_V1_STEPS * PENDULUM_V1_STEP,
        terminal_cost=_no_terminal_cost,
        state_cost=Quadratic([0.0, 0.0], [20.0, 2.0]),
        control_cost=control_cost,
        temperature=temperature,
    )
