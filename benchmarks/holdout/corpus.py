"""The hold-out corpus: problems that are not in the catalogue (``gridlbc.studies.problems``),
written as a new user would write them with the public API, each with the states at which its
default solve is checked against the certified optimum.

Each :class:`Member` has a builder returning the :class:`gridlbc.Problem` on the grid a user
would pick (about 201² in 2-D, 61³ in 3-D, 25⁴ in 4-D), the states to check, and the recipe of
its truth: the certificate's proposals come from a finer solve of the same problem
(:func:`refine`, ``fine`` times as many cells per axis, at its default step) and from the default
solve itself; ``truths.py`` keeps the one with the larger effective sample size, at two
Euler–Maruyama steps (``cert_dt`` and half of it). The numbers live in ``truths.json``.

Systems of the user's own are plain subclasses of :class:`gridlbc.systems.ControlAffineSystem`
(the README's recipe); the rest are built-ins with new costs, boxes, temperatures and control
costs. Three members are the failures reported in issue 25: a fast vortex core in a slow field,
a toll strip narrower than a cell across an axis only the drift moves, and a coarse 25⁴ acrobot
started fast. Narrow terminal goals, where the certificates degenerate (ESS near 1), carry an
``exact`` function instead (:func:`exact_goal`: a closed-form series), whose values ``truths.py``
records.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import strangers_round11 as r11
import strangers_round12 as r12
import strangers_round13 as r13
import strangers_round15 as r15
import strangers_round16 as r16
import strangers_round17 as r17
import strangers_round18 as r18
import strangers_round20 as r20
import strangers_round22 as r22
import strangers_round38 as r38
import strangers_round47 as r47
from scipy.special import gammaln

from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.regions import Ball, Box
from gridlbc.systems import Acrobot, ControlAffineSystem, LinearSystem, Pendulum, PointMass

PI = math.pi

# -- systems of the user's own -----------------------------------------------------------------


def _identity_inputs(x: np.ndarray, d: int) -> np.ndarray:
    return np.broadcast_to(np.eye(d), (x.shape[0], d, d))


def _last_input(x: np.ndarray, d: int, gain: float = 1.0) -> np.ndarray:
    B = np.zeros((x.shape[0], d, 1))
    B[:, -1, 0] = gain
    return B


class Vortex(ControlAffineSystem):
    """A point pushed in the plane (both axes driven) by a slow rotation about the origin and a
    fast vortex core: the flow turns at ``background + core_rate·exp(−r²/2σ²)`` rad/s about
    ``core`` (r the distance to it, σ = ``core_radius``)."""

    state_dim, control_dim, state_names = 2, 2, ("x", "y")

    def __init__(self, core=(0.8, 0.0), core_rate=18.0, core_radius=0.3, background=0.3):
        self.core = np.asarray(core, dtype=float)
        self.core_rate, self.core_radius, self.background = core_rate, core_radius, background

    def drift(self, x):
        x = self._states(x)
        rel = x - self.core
        spin = self.core_rate * np.exp(-(rel**2).sum(1) / (2 * self.core_radius**2))
        slow = self.background * np.stack([-x[:, 1], x[:, 0]], axis=1)
        return slow + spin[:, None] * np.stack([-rel[:, 1], rel[:, 0]], axis=1)

    def input_matrix(self, x):
        return _identity_inputs(self._states(x), 2)


class Duffing(ControlAffineSystem):
    """Double-well Duffing oscillator: ẍ = −δẋ + αx − βx³ + u (wells at x = ±√(α/β))."""

    state_dim, control_dim, state_names = 2, 1, ("x", "v")

    def __init__(self, alpha=1.0, beta=1.0, delta=0.2):
        self.alpha, self.beta, self.delta = alpha, beta, delta

    def drift(self, x):
        x = self._states(x)
        p, v = x[:, 0], x[:, 1]
        return np.stack([v, -self.delta * v + self.alpha * p - self.beta * p**3], axis=1)

    def input_matrix(self, x):
        return _last_input(self._states(x), 2)


class VanDerPol(ControlAffineSystem):
    """Van der Pol oscillator: ẍ = μ(1 − x²)ẋ − x + u (a limit cycle of amplitude about 2)."""

    state_dim, control_dim, state_names = 2, 1, ("x", "v")

    def __init__(self, mu=2.0):
        self.mu = mu

    def drift(self, x):
        x = self._states(x)
        p, v = x[:, 0], x[:, 1]
        return np.stack([v, self.mu * (1 - p**2) * v - p], axis=1)

    def input_matrix(self, x):
        return _last_input(self._states(x), 2)


class Torus(ControlAffineSystem):
    """Drift-free diffusion on the torus: both angles driven directly (first order)."""

    state_dim, control_dim, state_names, angle_axes = 2, 2, ("a", "b"), (0, 1)

    def drift(self, x):
        return np.zeros_like(self._states(x))

    def input_matrix(self, x):
        return _identity_inputs(self._states(x), 2)


class TollRoad(ControlAffineSystem):
    """A car moving along s at a fixed ``speed`` (no control, no noise on s), steering its lateral
    position y through its lateral velocity: ṡ = speed, ẏ = w, ẇ = −c w + u."""

    state_dim, control_dim, state_names = 3, 1, ("s", "y", "w")

    def __init__(self, speed=1.0, friction=0.5):
        self.speed, self.friction = speed, friction

    def drift(self, x):
        x = self._states(x)
        return np.stack(
            [np.full(x.shape[0], self.speed), x[:, 2], -self.friction * x[:, 2]], axis=1
        )

    def input_matrix(self, x):
        return _last_input(self._states(x), 3)


class TollStrip:
    """q(s, y): a toll of ``height`` in a Gaussian strip of width ``width`` across s = ``at``,
    waived in a gap of half-width ``gap_width`` about y = ``gap``."""

    def __init__(self, at=1.5, width=0.015, height=80.0, gap=1.0, gap_width=0.3):
        self.at, self.width, self.height = at, width, height
        self.gap, self.gap_width = gap, gap_width

    def __call__(self, x):
        x = np.atleast_2d(x)
        strip = np.exp(-0.5 * ((x[:, 0] - self.at) / self.width) ** 2)
        waived = np.exp(-0.5 * ((x[:, 1] - self.gap) / self.gap_width) ** 2)
        return self.height * strip * (1.0 - waived)


class Unicycle(ControlAffineSystem):
    """Kinematic unicycle at constant ``speed``, steered by its turn rate: ẋ = v cos θ,
    ẏ = v sin θ, θ̇ = u (θ periodic)."""

    state_dim, control_dim, state_names, angle_axes = 3, 1, ("x", "y", "heading"), (2,)

    def __init__(self, speed=1.0):
        self.speed = speed

    def drift(self, x):
        x = self._states(x)
        v = self.speed
        return np.stack([v * np.cos(x[:, 2]), v * np.sin(x[:, 2]), np.zeros(x.shape[0])], 1)

    def input_matrix(self, x):
        return _last_input(self._states(x), 3)


class RigidBody(ControlAffineSystem):
    """Euler's equations of a free rigid body with torques about its principal axes:
    I₁ω̇₁ = (I₂ − I₃) ω₂ω₃ + u₁ (and cyclically); the middle axis is unstable."""

    state_dim, control_dim, state_names = 3, 3, ("w1", "w2", "w3")

    def __init__(self, inertia=(1.0, 2.0, 3.0)):
        self.inertia = np.asarray(inertia, dtype=float)

    def drift(self, x):
        w = self._states(x)
        i1, i2, i3 = self.inertia
        return np.stack(
            [
                (i2 - i3) / i1 * w[:, 1] * w[:, 2],
                (i3 - i1) / i2 * w[:, 2] * w[:, 0],
                (i1 - i2) / i3 * w[:, 0] * w[:, 1],
            ],
            axis=1,
        )

    def input_matrix(self, x):
        w = self._states(x)
        return np.broadcast_to(np.diag(1.0 / self.inertia), (w.shape[0], 3, 3))


class Affine(ControlAffineSystem):
    """ẋ = a(x) + B u with a given drift function and a constant input matrix B (d × m)."""

    def __init__(self, drift, B, names=None, angle_axes=()):
        self._drift, self.B = drift, np.asarray(B, float)
        self.state_dim, self.control_dim = self.B.shape
        self.state_names = names or tuple(f"x{i}" for i in range(self.state_dim))
        self.angle_axes = tuple(angle_axes)

    def drift(self, x):
        return self._drift(self._states(x))

    def input_matrix(self, x):
        return np.broadcast_to(self.B, (self._states(x).shape[0], *self.B.shape))


def integrator(d, drift=None):
    """ẋ = a + u in d dimensions (B = I, R = 1), a a constant vector (default 0)."""
    if drift is None:
        return LinearSystem(np.zeros((d, d)), np.eye(d))
    a = np.asarray(drift, float)
    return Affine(lambda x: np.broadcast_to(a, x.shape).copy(), np.eye(d))


class RoundObstacle:
    """q(x): a Gaussian hill of ``height`` and radius ``radius`` about ``center`` in the first two
    coordinates (positions), whatever the others."""

    def __init__(self, center=(0.0, 0.0), radius=0.35, height=20.0):
        self.center, self.radius, self.height = np.asarray(center, float), radius, height

    def __call__(self, x):
        x = np.atleast_2d(x)
        r2 = ((x[:, :2] - self.center) ** 2).sum(1)
        return self.height * np.exp(-0.5 * r2 / self.radius**2)


class Bump:
    """q(x): a Gaussian ridge of ``height`` and width ``width`` across coordinate ``axis`` at
    ``at``, plus a constant ``floor``."""

    def __init__(self, axis=0, at=0.5, width=0.15, height=5.0, floor=0.0):
        self.axis, self.at, self.width, self.height, self.floor = axis, at, width, height, floor

    def __call__(self, x):
        x = np.atleast_2d(x)
        return self.floor + self.height * np.exp(
            -0.5 * ((x[:, self.axis] - self.at) / self.width) ** 2
        )


class TorusWell:
    """q(a, b) = height · (2 − cos(a − a₀) − cos(b − b₀)): a broad periodic well."""

    def __init__(self, center=(1.0, -1.0), height=0.5):
        self.center, self.height = np.asarray(center, float), height

    def __call__(self, x):
        x = np.atleast_2d(x)
        return self.height * (
            2 - np.cos(x[:, 0] - self.center[0]) - np.cos(x[:, 1] - self.center[1])
        )


# -- the members ------------------------------------------------------------------------------


def _grid(*axes) -> Grid:
    return Grid([Axis(*a[:3], periodic=len(a) > 3 and a[3]) for a in axes])


def vortex():
    grid = _grid((-5, 5, 201), (-5, 5, 201))
    return Problem(Vortex(), grid, 3.0, Quadratic([-1.5, 0.0], [2.0, 2.0]))


def duffing():
    grid = _grid((-2.5, 2.5, 201), (-4, 4, 201))
    return Problem(Duffing(), grid, 3.0, Quadratic([1.0, 0.0], [10.0, 1.0]), temperature=0.5)


def vanderpol():
    grid = _grid((-3.5, 3.5, 201), (-7, 7, 201))
    return Problem(
        VanDerPol(),
        grid,
        4.0,
        Quadratic([0.0, 0.0], [5.0, 1.0]),
        state_cost=Quadratic([0.0, 0.0], [1.0, 0.1]),
        temperature=0.3,
    )


def narrow_goal():
    grid = _grid((-3, 3, 201), (-4, 4, 201))
    return Problem(PointMass(), grid, 2.0, Quadratic([1.0, 0.0], [400.0, 40.0]), temperature=0.1)


def cheap_control():
    grid = _grid((-PI, PI, 201, True), (-12, 12, 201))
    return Problem(
        Pendulum(damping=0.1),
        grid,
        2.0,
        Quadratic([0.0, 0.0], [10.0, 0.5]),
        control_cost=0.05,
        temperature=0.1,
    )


def expensive_control():
    grid = _grid((-PI, PI, 201, True), (-10, 10, 201))
    return Problem(
        Pendulum(),
        grid,
        3.0,
        Quadratic([0.0, 0.0], [5.0, 0.5]),
        state_cost=Quadratic([0.0, 0.0], [1.0, 0.1]),
        control_cost=20.0,
        temperature=1.0,
    )


def hot_rotor():
    grid = _grid((-PI, PI, 201, True), (-10, 10, 201))
    return Problem(
        Pendulum(gravity=0.0), grid, 2.0, Quadratic([1.0, 0.0], [2.0, 0.2]), temperature=3.0
    )


def cold_ridge():
    grid = _grid((-2, 2, 201), (-3, 3, 201))
    return Problem(
        PointMass(),
        grid,
        1.5,
        Quadratic([0.0, 0.0], [5.0, 1.0]),
        state_cost=Bump(axis=0, at=0.5, width=0.15, height=5.0),
        temperature=0.01,
    )


def thin_wall():
    grid = _grid((-2, 2, 201), (-3, 3, 201))
    return Problem(
        PointMass(),
        grid,
        1.5,
        Quadratic([1.2, 0.0], [5.0, 1.0]),
        state_cost=Bump(axis=0, at=0.5, width=0.006, height=400.0),
        temperature=0.3,
    )


def cold_unicycle():
    return unicycle().replace(temperature=0.03)


def pinpoint_goal():
    grid = _grid((-3, 3, 201), (-4, 4, 201))
    return Problem(PointMass(), grid, 2.0, Quadratic([1.0, 0.0], [1e4, 10.0]), temperature=0.1)


def torus_diffusion():
    grid = _grid((-PI, PI, 200, True), (-PI, PI, 200, True))
    return Problem(
        Torus(),
        grid,
        1.5,
        Quadratic([0.0, 0.0], [3.0, 3.0]),
        state_cost=TorusWell(),
        temperature=0.5,
    )


def toll_strip():
    grid = _grid((-0.5, 3.5, 61), (-2, 2, 61), (-4, 4, 61))
    return Problem(
        TollRoad(), grid, 2.5, Quadratic([0.0, 0.0, 0.0], [0.0, 2.0, 0.5]), state_cost=TollStrip()
    )


def unicycle():
    grid = _grid((-3.5, 3.5, 61), (-3.5, 3.5, 61), (-PI, PI, 60, True))
    return Problem(
        Unicycle(), grid, 3.0, Quadratic([1.5, 0.0, 0.0], [3.0, 3.0, 0.0]), temperature=0.2
    )


def triple_integrator():
    A = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]
    grid = _grid((-3, 3, 61), (-3, 3, 61), (-4, 4, 61))
    return Problem(
        LinearSystem(A, [0.0, 0.0, 1.0]),
        grid,
        2.0,
        Quadratic([0.0, 0.0, 0.0], [5.0, 2.0, 1.0]),
        temperature=0.5,
    )


def tumbling_body():
    grid = _grid((-6, 6, 61), (-6, 6, 61), (-6, 6, 61))
    return Problem(
        RigidBody(), grid, 2.0, Quadratic([0.0, 0.0, 0.0], [2.0, 2.0, 2.0]), temperature=0.5
    )


def fast_acrobot():
    system = Acrobot()
    return Problem(
        system,
        system.default_grid(25),
        2.0,
        Quadratic([PI, 0.0, 0.0, 0.0], [5.0, 5.0, 0.5, 0.5]),
    )


def balance_acrobot():
    system = Acrobot()
    return Problem(
        system,
        system.default_grid(25),
        1.5,
        Quadratic([0.0, 0.0, 0.0, 0.0], [10.0, 10.0, 0.5, 0.5]),
        state_cost=Quadratic([0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 0.1, 0.1]),
        temperature=0.5,
    )


def planar_obstacle():
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1.0
    B = np.zeros((4, 2))
    B[2, 0] = B[3, 1] = 1.0
    grid = _grid((-3, 3, 25), (-3, 3, 25), (-4, 4, 25), (-4, 4, 25))
    return Problem(
        LinearSystem(A, B),
        grid,
        2.5,
        Quadratic([1.5, 0.0, 0.0, 0.0], [5.0, 5.0, 1.0, 1.0]),
        state_cost=RoundObstacle(),
        temperature=0.3,
    )


def _lq_without_exit(problem: Problem) -> dict:
    """The exact LQ policy of a late point-mass task without its exit set (stranger round 20):
    the grid policies steer toward an exit their grids over-rate (ESS 2–70 of 1000)."""
    return {"the LQ policy without the exit": r20.exit_lq_policy(problem)}


@dataclass(frozen=True)
class Member:
    """One hold-out problem: how to build it, where to check it, how its truth is made.

    Attributes
    ----------
    name : str
    build : callable
        () → Problem on the default grid a user would pick.
    states : ndarray (k, d)
        The states checked (k ≥ 3).
    what : str
        What it exercises.
    fine : float
        The finer proposal's grid has ``fine`` times as many cells per axis (solved at its
        default step).
    cert_dt : float
        The certificate's Euler–Maruyama step; the truth is also computed at half of it.
    fast : bool
        In the ``--fast`` subset (cheap 2-D members, run by the tests).
    trajectory : bool
        Also try trajectory components (LQR trackers) as the certificate's proposal.
    tags : tuple of str
        What kind of problem it is.
    max_time : float or None
        For a task that ends without a horizon: the certificate's paths stop here (long enough
        that all but a negligible share have exited; ``truths.json`` records the share).
    exact : callable or None
        States (k, d) → the exact v*(x, 0) (closed form or quadrature), for problems whose
        certificates degenerate; ``truths.py`` records it instead of a certificate. Its
        docstring's first paragraph says how it is computed.
    time : float
        The time at which the states are read (0: the task from its start). For t > 0 the truth
        is the remaining task's, the same problem over the horizon T − t (its costs and
        dynamics do not depend on time), and ``run.py`` reads v(x, t) and its estimate there.
    proposals : callable or None
        The problem certified → {name: policy}: proposals for the certificate beside the finer
        and the default solves' policies (``truths.py`` keeps the one with the largest ESS).
    options : dict
        Solve options the user passes (e.g. ``store_every``), given to the default solve and to
        the solve to a tolerance alike.
    """

    name: str
    build: Callable[[], Problem]
    states: np.ndarray
    what: str
    fine: float = 2.0
    cert_dt: float = 0.004
    fast: bool = False
    trajectory: bool = False
    tags: tuple[str, ...] = field(default=())
    max_time: float | None = None
    exact: Callable[[np.ndarray], np.ndarray] | None = None
    time: float = 0.0
    proposals: Callable[[Problem], dict] | None = None
    options: dict = field(default_factory=dict)

    def certified_problem(self) -> Problem:
        """The problem whose value at t = 0 is the truth at ``time``: the remaining task."""
        problem = self.build()
        if self.time:
            problem = problem.replace(horizon=problem.horizon - self.time)
        return problem


def refine(problem: Problem, factor: float) -> Problem:
    """The same problem on a grid with about ``factor`` times as many cells per axis."""
    axes = [
        Axis(
            a.lo,
            a.hi,
            round(a.n * factor) if a.periodic else round((a.n - 1) * factor) + 1,
            a.periodic,
            a.name,
        )
        for a in problem.grid.axes
    ]
    return problem.replace(grid=Grid(axes))


def hot_band():
    grid = _grid((-PI, PI, 201, True), (-10, 10, 201))
    return Problem(
        Pendulum(),
        grid,
        None,
        state_cost=lambda x: np.full(len(x), 0.5),
        control_cost=3.0,
        temperature=2.0,
        exit=Box([-0.5, -np.inf], [0.5, np.inf]),
    )


def dock():
    grid = _grid((-2, 2, 201), (-2, 2, 201))
    return Problem(
        PointMass(),
        grid,
        None,
        state_cost=lambda x: 1.0 + x[:, 0] ** 2,
        temperature=0.05,
        exit=Ball([0.0, 0.0], [0.1, 0.1]),
    )


def cold_upright():
    grid = _grid((-PI, PI, 201, True), (-8, 8, 201))

    def cost(x):
        return 2 * (1 - np.cos(x[:, 0])) + 0.05 * x[:, 1] ** 2

    return Problem(Pendulum(), grid, 2.5, cost, state_cost=cost, temperature=0.02)


def rotor_in_well(
    width: float, horizon: float, temperature: float, centre: float = 0.0, nodes: int = 201
) -> Problem:
    """A rotor (a pendulum without gravity) on ``nodes`` periodic nodes held in a well of state
    and terminal cost 3(1 − exp(−Δθ²/2w²)) + 0.05ω², w = ``width``, Δθ = θ − ``centre`` wrapped;
    θ = 0 lies midway between two nodes of an odd axis."""
    grid = _grid((-PI, PI, nodes, True), (-6, 6, 201))

    def cost(x):
        theta = (x[:, 0] - centre + PI) % (2 * PI) - PI
        return 3 * (1 - np.exp(-0.5 * (theta / width) ** 2)) + 0.05 * x[:, 1] ** 2

    return Problem(
        Pendulum(gravity=0.0), grid, horizon, cost, state_cost=cost, temperature=temperature
    )


def rotor_well():
    return rotor_in_well(0.15, 4.0, 0.02)


def rotor_pit():
    return rotor_in_well(0.07, 5.0, 0.005)


def mass_in_pit(
    centre: float,
    nodes: int = 201,
    width: float = 0.04,
    horizon: float = 5.0,
    temperature: float = 0.005,
    terminal_only: bool = False,
) -> Problem:
    """A point mass on ``nodes`` × 201 closed nodes over [−2, 2] × [−4, 4] in a pit of position
    3(1 − exp(−(x − c)²/2w²)), c = ``centre``, w = ``width`` (two cells by default), plus 0.05v²
    as state and terminal cost; ``terminal_only``: the pit plus 0.5v² as terminal cost only."""
    grid = _grid((-2, 2, nodes), (-4, 4, 201))
    speed = 0.5 if terminal_only else 0.05

    def cost(x):
        return 3 * (1 - np.exp(-0.5 * ((x[:, 0] - centre) / width) ** 2)) + speed * x[:, 1] ** 2

    if terminal_only:
        return Problem(PointMass(), grid, horizon, cost, temperature=temperature)
    return Problem(PointMass(), grid, horizon, cost, state_cost=cost, temperature=temperature)


def mass_pit():
    """The pit at x = 0.37, midway between the nodes 0.36 and 0.38 of the odd (nested) axis;
    0.36 is a node of its embedded axis too."""
    return mass_in_pit(0.37)


def terminal_pit():
    """The pit at x = 0.37 as terminal cost only, T = 0.5, λ = 0.05 (between the nodes 0.36 and
    0.38; 0.36 is a node of the embedded axis)."""
    return mass_in_pit(0.37, horizon=0.5, temperature=0.05, terminal_only=True)


def rotor_pit_off():
    """The rotor_pit rotor (λ = 0.005, T = 5, pit 0.07 rad wide) with its pit at θ = 0.7, on 202
    periodic nodes: the centre lies midway between two nodes of the even (nested) axis, and one
    of them is a node of its embedded axis."""
    return rotor_in_well(0.07, 5.0, 0.005, centre=0.7, nodes=202)


def mass_pit_centre():
    """The pit at x = 0.01: midway between the nodes 0 and 0.02 next to the centre of the odd
    closed axis, where the two grids of the pair (99 and 101 cells) miss it by about a quarter of
    their cell each (0.253 and 0.248), as the embedded grid does (0.25)."""
    return mass_in_pit(0.01)


def mass_pit_wall():
    """The pit on 200 closed nodes (199 cells) near the wall x = −2, midway between the nodes 10
    and 11 (x = −2 + 10.5 h): the pair's grids (99 and 100 cells) miss it by 0.224 and 0.276 of
    their cell."""
    return mass_in_pit(-2 + 10.5 * 4 / 199, nodes=200)


GOAL_IN_CELL = np.array([0.35, 0.25, -0.45])
"""The centre of a cell of goal_in_cell's 41³ grid (h = 0.1)."""


def goal_in_cell(centre=GOAL_IN_CELL, running: bool = False) -> Problem:
    """A 3-D single integrator ẋ = u on [−2, 2]³ (41³, h = 0.1), terminal cost only: a narrow goal
    2(1 − exp(−|x − c|²/2w²)) + 0.1|x|², w = 0.05 (half a cell), at c = ``centre``, λ = 0.1,
    T = 1; ``running``: the same cost as a state cost too (a pit)."""
    c = np.asarray(centre, dtype=float)

    def cost(x):
        r2 = np.sum((x - c) ** 2, axis=1)
        return 2 * (1 - np.exp(-0.5 * r2 / 0.05**2)) + 0.1 * np.sum(x**2, axis=1)

    return Problem(
        LinearSystem(np.zeros((3, 3)), np.eye(3)),
        _grid(*[(-2, 2, 41)] * 3),
        1.0,
        cost,
        state_cost=cost if running else None,
        temperature=0.1,
    )


def stiff_relax(rate: float = 50.0, horizon: float = 5.0) -> Problem:
    """A fast stable mode beside a slow one, ẋ = −k x + u₁ (k = ``rate``), ẏ = u₂ on [−2, 2]²
    (101²): q = x² + 0.2 y² + an obstacle 20 exp(−(|x| − 1.7)²/2w²), w = 0.08 (two cells), where
    no controlled path goes, g = x² + 0.2 y², λ = 0.1, T = ``horizon``."""

    def cost(x):
        wall = np.exp(-0.5 * ((np.abs(x[:, 0]) - 1.7) / 0.08) ** 2)
        return x[:, 0] ** 2 + 0.2 * x[:, 1] ** 2 + 20 * wall

    return Problem(
        LinearSystem(np.diag([-rate, 0.0]), np.eye(2)),
        _grid((-2, 2, 101), (-2, 2, 101)),
        horizon,
        Quadratic([0, 0], [1.0, 0.2]),
        state_cost=cost,
        temperature=0.1,
    )


# -- narrow goals with exact truths (stranger round 8) ------------------------------------------


def goal_cost(D, w, c, a, m=None):
    """g(y) = Σ aᵢ (yᵢ − mᵢ)² + D (1 − exp(−|y − c|²/2w²)) (the goal over the axes where c is
    not None); ``g.spec`` keeps the parameters for :func:`log_z_goal`."""
    a = np.asarray(a, float)
    m = np.zeros(len(a)) if m is None else np.asarray(m, float)
    idx = [i for i, ci in enumerate(c) if ci is not None]
    cc = np.array([c[i] for i in idx], float)

    def g(x):
        x = np.atleast_2d(x)
        r2 = np.sum((x[:, idx] - cc) ** 2, axis=1)
        return np.sum(a * (x - m) ** 2, axis=1) + D * (1 - np.exp(-0.5 * r2 / w**2))

    g.spec = dict(D=D, w=w, c=c, a=a, m=m)
    return g


def log_z_goal(mean, s2, spec, lam):
    """log E exp(−g(Y)/λ), Y ~ N(mean, s2 I), g = :func:`goal_cost`'s: exp(D e^{−r²/2w²}/λ) =
    Σₖ (D/λ)ᵏ/k! e^{−k r²/2w²}, each term a Gaussian integral in closed form, summed to
    k ≈ D/λ + 12 √(D/λ) + 30 in log space."""
    D, w, c, a, m = spec["D"], spec["w"], spec["c"], spec["a"], spec["m"]
    mu = D / lam
    K = int(mu + 12 * math.sqrt(mu) + 30)
    k = np.arange(K, dtype=float)
    logt = k * math.log(mu) - gammaln(k + 1)
    p0 = 1.0 / s2
    for i in range(len(mean)):
        p1 = 2 * a[i] / lam
        if c[i] is None:
            P = p0 + p1
            resid = p0 * p1 * (mean[i] - m[i]) ** 2 / P
            logt = logt - 0.5 * math.log(P / p0) - 0.5 * resid
        else:
            p2 = k / w**2
            P = p0 + p1 + p2
            resid = (
                p0 * p1 * (mean[i] - m[i]) ** 2
                + p0 * p2 * (mean[i] - c[i]) ** 2
                + p1 * p2 * (m[i] - c[i]) ** 2
            ) / P
            logt = logt - 0.5 * np.log(P / p0) - 0.5 * resid
    top = logt.max()
    return -mu + top + math.log(np.sum(np.exp(logt - top)))


def log_z_1d(g1, mu, s2, lam, step, period=None):
    """log E exp(−g1(Y)/λ), Y ~ N(mu, s2) (wrapped onto [−π, π) where ``period``), trapezoid."""
    s = math.sqrt(s2)
    if period is None:
        y = np.arange(mu - 12 * s, mu + 12 * s, step)
        logk = -0.5 * (y - mu) ** 2 / s2
    else:
        y = np.arange(-PI, PI, step)
        imgs = np.arange(-5, 6)[:, None] * period
        lk = -0.5 * (y[None, :] + imgs - mu) ** 2 / s2
        top = lk.max(0)
        logk = top + np.log(np.sum(np.exp(lk - top), 0))
    e = logk - g1(y) / lam
    top = e.max()
    return top + math.log(np.sum(np.exp(e - top)) * step) - 0.5 * math.log(2 * PI * s2)


def exact_separable(parts, lam, T, drift=None, step=None):
    """v(x, 0) for a terminal cost Σᵢ parts[i][0](yᵢ) (parts[i][1]: the axis's period or None)."""

    def f(X):
        """A product of 1-D integrals (trapezoid rule, 12 SD each side, images of a periodic
        axis wrapped): v = −λ Σᵢ log E exp(−gᵢ(Yᵢ)/λ), Yᵢ ~ N(xᵢ + aᵢT, λT)."""
        out = []
        for x in X:
            lz = 0.0
            for i, (g1, period, st) in enumerate(parts):
                mu = x[i] + (0.0 if drift is None else drift[i] * T)
                lz += log_z_1d(g1, mu, lam * T, lam, st, period)
            out.append(-lam * lz)
        return np.array(out)

    return f


def exact_goal(build, drift=None):
    """v(x, 0) for a :func:`goal_cost` terminal cost, ẋ = drift + u (a constant drift), no state
    cost: v = −λ log E exp(−g(X_T)/λ), X_T ~ N(x + aT, λT I) (:func:`log_z_goal`; the closed walls
    ignored, ≥ 3 standard deviations away against the pull of g)."""

    def f(X):
        """closed-form series (corpus.log_z_goal): v = −λ log E exp(−g(X_T)/λ), X_T ~ N(x + aT,
        λT I), exp(D e^{−r²/2w²}/λ) summed term by term as Gaussian integrals"""
        p = build()
        lam, T = p.temperature, p.horizon
        a = np.zeros(X.shape[1]) if drift is None else np.asarray(drift, float)
        spec = p.terminal_cost.spec
        return np.array([-lam * log_z_goal(x + a * T, lam * T, spec, lam) for x in X])

    return f


def goal_face_3d():
    """corpus.goal_in_cell's goal (w = h/2 = 0.05, depth 2, + 0.1|x|², 41³, λ = 0.1, T = 1) at
    the centre of a cell FACE: c = (0.35, 0.2, −0.4), midway on x, on nodes in y and z (1.12 w
    from the face's four nodes)."""
    p = goal_in_cell((0.35, 0.2, -0.4))
    return p.replace(terminal_cost=goal_cost(2.0, 0.05, (0.35, 0.2, -0.4), [0.1] * 3))


def goal_eighth():
    """2-D ẋ = u on [−2, 2]² (201², h = 0.02), a goal w = h/8 = 0.0025, depth 1.5, + 0.1|x|², at
    c = (0.305, −0.295): a quarter cell off a node on both axes, so every node, edge midpoint and
    cell centre is 0.35 h = 2.8 w from it (the goal term there 0.98 of its far value). λ = 0.1,
    T = 1."""
    c = (0.305, -0.295)
    return Problem(
        integrator(2),
        _grid((-2, 2, 201), (-2, 2, 201)),
        1.0,
        goal_cost(1.5, 0.0025, c, [0.1, 0.1]),
        temperature=0.1,
    )


def goal_quarter():
    """goal_eighth with a goal twice as wide, w = h/4 = 0.005, at the same quarter-cell offsets
    (every node, edge midpoint and cell centre 1.41 w from it: the goal term there 0.37 of
    its depth below the far value)."""
    c = (0.305, -0.295)
    return goal_eighth().replace(terminal_cost=goal_cost(1.5, 0.005, c, [0.1, 0.1]))


def goal_4d():
    """4-D ẋ = u on [−2, 2]⁴ (21⁴, h = 0.2), a goal w = 0.1 = h/2, + 0.1|x|², at the
    cell centre c = (0.1, −0.3, 0.5, −0.1) (2 w from all 16 of its nodes), depth 3, λ = 0.2, T = 1."""
    c = (0.1, -0.3, 0.5, -0.1)
    return Problem(
        integrator(4),
        _grid(*[(-2, 2, 21)] * 4),
        1.0,
        goal_cost(3.0, 0.1, c, [0.1] * 4),
        temperature=0.2,
    )


# -- narrow state-cost wells and pits (stranger round 8, certified) ------------------------------


def well_face():
    """ẋ = u on [−2, 2]² (81², h = 0.05): q = 2 − 1.5 exp(−|x − c|²/2w²), w = h/2, at the face
    centre c = (0.025, −0.4) (midway on x₁, a node on x₂; on a node of the 2×, 4×, 8× grids),
    g = 0.5|x|², λ = 0.02, T = 2. Sitting in the well (its LQ ground cost ≈ 0.98 + 0.5) beats
    the plain q = 2 by ≈ 0.5 per unit time."""
    c = np.array([0.025, -0.4])

    def q(x):
        x = np.atleast_2d(x)
        return 2 - 1.5 * np.exp(-0.5 * np.sum((x - c) ** 2, 1) / 0.025**2)

    return Problem(
        integrator(2),
        _grid((-2, 2, 81), (-2, 2, 81)),
        2.0,
        Quadratic([0, 0], [0.5, 0.5]),
        state_cost=q,
        temperature=0.02,
    )


DRIFT = (1.0, 0.0)
"""pit_drift's constant drift (and stranger round 8's goal_drift's)."""


def pit_drift():
    """A drift carries the process through a narrow state-cost pit: ẋ₁ = 1 + u₁, ẋ₂ = u₂ on
    [−2, 2]² (41², h = 0.1), q = 3(1 − exp(−|x − c|²/2w²)) + 0.5 x₂², w = h/2, at the face
    centre c = (0.55, 0) (midway on x₁, a node on x₂; a node of the 2×, 4×, 8× grids),
    g = 0.5|x|², λ = 0.05, T = 2 (holding still in it costs ½ + its LQ ground cost ≈ 0.9 < 3)."""
    c = np.array([0.55, 0.0])

    def q(x):
        x = np.atleast_2d(x)
        r2 = np.sum((x - c) ** 2, 1)
        return 3 * (1 - np.exp(-0.5 * r2 / 0.05**2)) + 0.5 * x[:, 1] ** 2

    return Problem(
        integrator(2, DRIFT),
        _grid((-2, 2, 41), (-2, 2, 41)),
        2.0,
        Quadratic([0, 0], [0.5, 0.5]),
        state_cost=q,
        temperature=0.05,
    )


def shallow_long_well():
    """A well only slightly below its surroundings, worth holding over a long horizon: ẋ = u on
    [−2, 2]² (41², h = 0.1), q = 0.5 + 0.05|x|² − 0.3 exp(−|x − c|²/2w²), w = h/2, c = (0.35,
    −0.25) (a cell centre; a node of the 2× and 4× grids), g = 0.1|x|², λ = 0.05, T = 8."""
    c = np.array([0.35, -0.25])

    def q(x):
        x = np.atleast_2d(x)
        return 0.5 + 0.05 * np.sum(x**2, 1) - 0.3 * np.exp(-0.5 * np.sum((x - c) ** 2, 1) / 0.05**2)

    return Problem(
        integrator(2),
        _grid((-2, 2, 41), (-2, 2, 41)),
        8.0,
        Quadratic([0.0, 0.0], [0.1, 0.1]),
        state_cost=q,
        temperature=0.05,
    )


def goal_off8():
    """m = 4's blind spot: a goal w = h/8 an eighth of a cell off a node on both axes, 201²
    (h = 0.02), c = (0.3025, −0.2975), depth 1.5, + 0.1|x|², λ = 0.1, T = 1."""
    return Problem(
        integrator(2),
        _grid((-2, 2, 201), (-2, 2, 201)),
        1.0,
        goal_cost(1.5, 0.0025, (0.3025, -0.2975), [0.1, 0.1]),
        temperature=0.1,
    )


def goal_off8_3d():
    """The same in 3-D, 41³ (h = 0.1): w = h/8, c = (0.3125, −0.1875, 0.0125) (an eighth of a
    cell off a node on every axis), depth 2, + 0.1|x|², λ = 0.1, T = 1."""
    return Problem(
        integrator(3),
        _grid(*[(-2, 2, 41)] * 3),
        1.0,
        goal_cost(2.0, 0.0125, (0.3125, -0.1875, 0.0125), [0.1] * 3),
        temperature=0.1,
    )


def goal_m2_3d():
    """A grid too large for m = 4 (65³: the h/4 lattice would hold 257³ > 2²⁴ points, so m = 2):
    ẋ = u on [−1.6, 1.6]³ (h = 0.05), goal w = h/5 a quarter cell off a node on every axis,
    c = (0.3125, −0.1875, 0.1125), depth 2, + 0.1|x|², λ = 0.1, T = 1."""
    return Problem(
        integrator(3),
        _grid(*[(-1.6, 1.6, 65)] * 3),
        1.0,
        goal_cost(2.0, 0.01, (0.3125, -0.1875, 0.1125), [0.1] * 3),
        temperature=0.1,
    )


def goal4d_mid():
    """4-D ẋ = u on [−2, 2]⁴ (21⁴, h = 0.2, 2 lattice points per cell), a goal w = 0.035 at the
    centre of a lattice cell, c = (0.05, −0.35, 0.25, −0.15) (2.9 w from its 16 lattice points),
    depth 1.5, + 0.1|x|², λ = 0.1, T = 1 (stranger round 10)."""
    return Problem(
        integrator(4),
        _grid(*[(-2, 2, 21)] * 4),
        1.0,
        goal_cost(1.5, 0.035, (0.05, -0.35, 0.25, -0.15), [0.1] * 4),
        temperature=0.1,
    )


COMB_SPACING = 2 * PI / 256 / 8  # comb_torus's lattice spacing (256 nodes, 8 points per cell)
COMB_CENTRES = PI - COMB_SPACING / 2 - (2 * PI / 32) * np.arange(32)
COMB_WIDTH = COMB_SPACING / 2 / 3.1


def _comb(t):
    """1 − Σₖ exp(−wrap(t − cₖ)²/2w²) over comb_torus's 32 troughs."""
    t = np.asarray(t, dtype=float)
    wrapped = np.mod(t[..., None] - COMB_CENTRES + PI, 2 * PI) - PI
    return 1.0 - np.exp(-0.5 * (wrapped / COMB_WIDTH) ** 2).sum(axis=-1)


def comb_torus():
    """θ ∈ [−π, π) periodic (256 nodes), y ∈ [−2, 2] (101), ẋ = u, a comb of 32 terminal troughs
    w = 0.0005 (a sixth of the lattice's spacing) across θ, each at the centre of the lattice
    cell next to a node, the first across the seam: g = 1 − Σₖ exp(−wrap(θ − cₖ)²/2w²) + 0.1 y²,
    λ = 0.1, T = 1 (stranger round 10)."""
    return Problem(
        Affine(lambda x: np.zeros_like(x), np.eye(2), angle_axes=(0,)),
        _grid((-PI, PI, 256, True), (-2, 2, 101)),
        1.0,
        lambda x: _comb(x[:, 0]) + 0.1 * x[:, 1] ** 2,
        temperature=0.1,
    )


def _s(*rows) -> np.ndarray:
    return np.array(rows, dtype=float)


def _notch_exit_exact(X):
    """cosine series (strangers_round11.exact_halfplane_g): z = Σ c_m cos(mπ(x₁+2)/4)
    cosh(κ_m(x₀+2))/cosh(κ_m(a+2)), κ_m² = 2Rq/λ² + (mπ/4)², z = e^{−g(x₁)/λ} on x₀ = a, the
    coefficients by the trapezoid rule on 400 001 points"""
    return r11.exact_halfplane_g(r11.notch_g)(X)


def _toll_blind_exact(X):
    """1-D first-exit solve (strangers_round11.fine_1d): v depends on x₀ alone; the library's
    solve on [−2, 0.5] with 100 001 nodes, within 0.005 % of the one with 50 001"""
    value, _ = r11.P11["toll_blind"][2](X)
    return value


def _notch_horizon_exact(X):
    """cosine modes along the exit line with their time-dependent parts in x₀
    (strangers_round12.exact_notch_horizon): z = Σ_m f_m cos(k_m(x₁+2)) Z_m(x₀) + e^{−g/λ} Y(x₀),
    each part a steady cosh profile less its decaying eigenmodes, checked against 161² and 321²
    grids with a wide notch"""
    value, _ = r12.P12["hz_notch_exit"][2](X)
    return value


def _strip_exact(X):
    """1-D finite differences (strangers_round22, "fd"): v depends on x₀ alone; central
    differences of (q/λ) z = D z″ + a z′ off E, z = e^{−g_E/λ} on E, on 10 001 and 20 001 nodes
    (the strip holds 38–75 of them)"""
    return r22.P22["exit_strip_mid"][2](X)[0]


def _wall_exact(X):
    """separable 1-D Crank–Nicolson (strangers_round22, "1-D"): v the sum of each axis's value,
    on 8001 and 16 001 nodes with τ/4000 and τ/8000 steps (the wall 12–24 fine nodes wide),
    within 0.003 of each other"""
    return r22.P22["driftwall2_even_node"][2](X)[0]


def _gain_exact(X):
    """separable 1-D Crank–Nicolson (strangers_round22, "1-D") as for driftwall_kept_node"""
    return r22.P22["gainband2_deep"][2](X)[0]


def _store_far_problem() -> Problem:
    """Stranger round 21's opt_store19 (round 20's LQ point mass): m = 2 brought to (1, 0),
    g = 4(x₀ − 1)² + x₁², q = (x₀ + 0.5)² + 0.1 x₁², λ = 0.5, T = 3, 101² on [−4, 4] × [−6, 6]."""
    return Problem(
        PointMass(mass=2.0),
        Grid([Axis(-4, 4, 101), Axis(-6, 6, 101)]),
        3.0,
        terminal_cost=Quadratic([1.0, 0.0], [4.0, 1.0]),
        state_cost=Quadratic([-0.5, 0.0], [1.0, 0.1]),
        temperature=0.5,
    )


LATE_TERMINAL_TIME = 2.0 - 1.0 / 13.0
"""T − Δt/2 of :func:`_late_terminal_problem`'s default solve (13 steps): the middle of its last
stored interval."""


def _late_terminal_problem() -> Problem:
    """Stranger round 21's pm_q0: a point mass with a terminal cost only, g = 4(x₀ − 1)² + x₁²,
    λ = 0.3, T = 2, 101² on [−4, 4] × [−6, 6] (the default step is T/13)."""
    return Problem(
        PointMass(),
        Grid([Axis(-4, 4, 101), Axis(-6, 6, 101)]),
        2.0,
        terminal_cost=Quadratic([1.0, 0.0], [4.0, 1.0]),
        temperature=0.3,
    )


def _late_terminal_exact(X):
    """Riccati (gridlbc.reference.lq_solution) of the remaining task, T − t = 1/13: exact for a
    linear system with quadratic costs; the states are far from the walls"""
    from gridlbc.reference import lq_solution

    remaining = _late_terminal_problem().replace(horizon=2.0 - LATE_TERMINAL_TIME)
    return lq_solution(remaining).value(X, 0.0)


SEAM_CENTRE = np.array([0.5, 0.0])
SEAM_WEIGHTS = np.array([[3.0, 1.2], [1.2, 1.0]])


def _seam_cost(x):
    """(x − c)ᵀW(x − c) with the angle's difference wrapped to [−π, π) and a cross term: as a
    user writes a wrap-aware quadratic, and discontinuous across the seam θ = c₀ + π, where the
    cross term's sign flips (a jump of 4πW₀₁|ω − c₁|)."""
    d = np.asarray(x, dtype=float) - SEAM_CENTRE
    d[:, 0] = (d[:, 0] + np.pi) % (2 * np.pi) - np.pi
    return np.einsum("ni,ij,nj->n", d, SEAM_WEIGHTS, d)


SMALL_EXIT_SCALE = 0.04356597042414412
"""The cost factor round 47's calibration chose for r47_PointMass_hzfe_18 (v at its middle state
about 0.17 λ)."""


def _small_exit_horizon_problem():
    """Stranger round 47's r47_PointMass_hzfe_18, as its generator drew it."""
    spec = r47.draw()["r47_PointMass_hzfe_18"]
    spec["scale"] = SMALL_EXIT_SCALE
    return r47.build(spec)


def _seam_jump_problem():
    return Problem(
        Pendulum(),
        _grid((-np.pi, np.pi, 64, True), (-8.0, 8.0, 107)),
        3.0,
        _seam_cost,
        temperature=0.07,
    )


def _mixing_inputs_problem() -> Problem:
    """Stranger round 38's mixB_d0.25_l0.5_T2: ẋ = B u with B = [[1, 1], [1, −1]] and
    R = Bᵀ diag(1, 4) B (noise diag(1, 0.25) λ), q = 0.3 abs(x)², g narrow (10) across 45° and 1
    along it about (0.4, −0.3), λ = 0.5, T = 2, 61² on [−3, 3]²."""
    spec = r38.problems()["mixB_d0.25_l0.5_T2"]
    return r38.build(spec)


def _store_far_exact(X):
    """Riccati (gridlbc.reference.lq_solution) of the remaining task, T − t = 1.5: exact for a
    linear system with quadratic costs; the walls are several standard deviations away"""
    from gridlbc.reference import lq_solution

    problem = _store_far_problem()
    return lq_solution(problem.replace(horizon=1.5)).value(X, 0.0)


def _tiny_ball_exact(X):
    """Bessel series (strangers_round11.ball_exact): z = K₀(κr)/K₀(κρ) about the ball, κ² =
    2Rq/λ², the box's walls over 50 decay lengths 1/κ away"""
    value, _ = r11.P11["tiny_ball_cold"][2](X)
    return value


def _gust_exact(X):
    """1-D Crank–Nicolson solve (strangers_round13.cn_1d): v depends on x₀ alone; 40 001 nodes
    and T/8000, within 0.001 % of 20 001 nodes and T/4000"""
    value, _ = r13.P13["hz_gust"][2](X)
    return value


def _headwind_exact(X):
    """1-D Crank–Nicolson solve (strangers_round13.cn_1d), as for ``gust_upstream``, with the
    narrow gust resolved by 800 nodes across its width"""
    value, _ = r13.P13["hz_headwind"][2](X)
    return value


def _well_torus_exact(X):
    """separable eigenvalue problems (strangers_round12.eig_truth): h(x) = Σ_i h_i(x_i), each
    the relative value of a 1-D periodic Schrödinger operator −(λ²/2) d²/dx² + q_i on 80 000
    points, within 1e-7 of 40 000"""
    value, _ = r13.P13["avg_well_3d"][2](X)
    return value[1:]


def _two_doors_exact(X):
    """closed form (strangers_round15.two_doors_exact): v depends on x₀ alone, z = A e^{kx₀} +
    B e^{−kx₀} between the doors with k = √(2Rq)/λ, checked against a Dirichlet Crank–Nicolson
    run to T = 30 (1e-7)"""
    value, _ = r15.P15["fe_two_doors"][2](X)
    return value


def _cold_flow_exact(X):
    """v depends on x₀ alone: second-order finite differences of the 1-D stationary equation in
    log-safe form (strangers_round13.bvp_1d) on 400 001 and 800 001 nodes"""
    value, _ = r16.P16["fe_frozen_flow"][2](X)
    return value


def _kink_tiny_horizon_exact(X):
    """Gaussian kernel integrals of e^{−g/λ}, a product of 1-D trapezoid sums on x ± 14σ with
    20 001 and 40 001 points (strangers_round17.tiny_truth); the walls are 50σ away"""
    value, _ = r17.P17["hz_tiny_T_c"][2](X)
    return value


def _sliding_switch_exact(X):
    """1-D monotone backward-Euler solves of the switching axis (strangers_round18.be_1d, upwind
    drift, 20 001 and 40 001 nodes, Richardson in the step; 3e-4 from a solve with twice the nodes
    and four times the steps) plus the free axis's Crank–Nicolson"""
    value, _ = r18.P18["sliding_frozen"][2](X)
    return value


def logistic_edge(rate: float = 2.0, horizon: float = 5.0) -> Problem:
    """A share x₁ that grows logistically, ẋ₁ = r x₁ (1 − x₁), neither driven nor noisy, beside
    an axis the control and the noise move (ẋ₀ = u), q = x₁, g = 0, λ = 0.1, T = ``horizon``,
    on 21 × 101 nodes of [−1, 1] × [0, 1]: stranger round 19b's early epidemic in closed form."""

    def drift(x):
        return np.stack([np.zeros(len(x)), rate * x[:, 1] * (1 - x[:, 1])], axis=1)

    return Problem(
        Affine(drift, [[1.0], [0.0]]),
        _grid((-1, 1, 21), (0, 1, 101)),
        horizon,
        lambda x: np.zeros(len(x)),
        state_cost=lambda x: x[:, 1],
        temperature=0.1,
    )


def _logistic_edge_exact(X, rate: float = 2.0, horizon: float = 5.0):
    """closed form: x₁(t) = x₁e^{rt}/(1 − x₁ + x₁e^{rt}) is deterministic and costs nothing to
    leave alone, so v = ∫₀ᵀ x₁ dt = log(1 + x₁(e^{rT} − 1))/r"""
    X = np.atleast_2d(np.asarray(X, float))
    return np.log1p(X[:, 1] * np.expm1(rate * horizon)) / rate


def _three_doors_exact(X):
    """5-point finite differences of (λ/2R)Δz = (q/λ)z between the doors
    (strangers_round15.fd_three_doors) at h = 0.01 and 0.005, which agree to 5e-5"""
    value, _ = r15.P15["fe_three_doors"][2](X)
    return value


def _relative_value_exact(table, name):
    def exact(X):
        value, _ = table[name][2](X)
        return value[1:]

    exact.__doc__ = (
        "the algebraic Riccati equation (strangers_round15.are_truth): h = ½ xᵀPx, min 0 at "
        "the origin (a node), P from scipy's solve_continuous_are, c = (λ/2) tr(S P), equal to "
        "the closed-loop Lyapunov cost to 1e-15"
    )
    return exact


MEMBERS: tuple[Member, ...] = (
    Member(
        "vortex",
        vortex,
        _s((0.8, 0.3), (1.2, 0.0), (-0.5, 1.5)),
        "2-D user system: a core spinning at 18 rad/s in a slow field (issue 25)",
        cert_dt=0.002,
        tags=("fast dynamics", "local feature", "closed"),
    ),
    Member(
        "duffing",
        duffing,
        _s((-1.0, 0.0), (0.0, 0.0), (-1.5, 1.0)),
        "2-D double-well Duffing oscillator, well to well, λ = 0.5",
        fast=True,
        tags=("nonlinear oscillator", "closed"),
    ),
    Member(
        "vanderpol",
        vanderpol,
        _s((2.0, 0.0), (0.0, 3.0), (-1.0, -2.0)),
        "2-D Van der Pol (μ = 2) brought to rest, quadratic state cost, λ = 0.3",
        tags=("nonlinear oscillator", "closed"),
    ),
    Member(
        "narrow_goal",
        narrow_goal,
        _s((-1.0, 0.0), (0.0, 1.0), (1.5, -1.0)),
        "2-D double integrator to a narrow goal (weights 400, 40), λ = 0.1",
        cert_dt=0.002,
        tags=("narrow cost", "closed"),
    ),
    Member(
        "cheap_control",
        cheap_control,
        _s((3.0, 0.0), (1.5, 2.0), (-2.0, -3.0)),
        "2-D damped pendulum, cheap control R = 0.05, λ = 0.1",
        tags=("cheap control", "periodic"),
    ),
    Member(
        "expensive_control",
        expensive_control,
        _s((2.5, 0.0), (0.5, 0.0), (-1.0, 1.0)),
        "2-D pendulum, expensive control R = 20, state cost, λ = 1",
        cert_dt=0.001,
        fast=True,
        tags=("expensive control", "periodic"),
    ),
    Member(
        "hot_rotor",
        hot_rotor,
        _s((-2.0, 0.0), (0.0, 2.0), (3.0, -1.0)),
        "2-D rotor (no gravity), broad cost, λ = 3",
        tags=("broad cost", "periodic", "slow dynamics"),
    ),
    Member(
        "cold_ridge",
        cold_ridge,
        _s((-1.0, 0.0), (1.5, 0.0), (1.0, 1.0)),
        "2-D point mass over a ridge of state cost across position, λ = 0.01",
        tags=("small temperature", "closed"),
    ),
    Member(
        "thin_wall",
        thin_wall,
        _s((-0.5, 0.0), (0.0, 1.0), (0.3, 0.5)),
        "2-D point mass through a wall of state cost a third of a cell thick across position, "
        "which only the drift moves, λ = 0.3",
        fine=4.0,
        tags=("local feature", "narrow cost", "closed"),
    ),
    Member(
        "pinpoint_goal",
        pinpoint_goal,
        _s((-1.0, 0.0), (0.0, 1.0), (1.5, -1.0)),
        "2-D double integrator to a goal narrower than a cell (weights 10⁴, 10), λ = 0.1",
        fine=4.0,
        cert_dt=0.002,
        tags=("narrow cost", "closed"),
    ),
    Member(
        "torus_diffusion",
        torus_diffusion,
        _s((3.0, 3.0), (-2.0, 1.0), (1.0, -0.5)),
        "2-D drift-free first-order diffusion on the torus, broad periodic state cost",
        fast=True,
        tags=("first order", "periodic"),
    ),
    Member(
        "toll_strip",
        toll_strip,
        _s((0.0, 0.0, 0.0), (0.0, -0.5, 0.0), (0.5, 1.0, 0.0)),
        "3-D: a toll strip narrower than a cell across s, which only the drift moves (issue 25)",
        tags=("local feature", "narrow cost", "closed"),
    ),
    Member(
        "unicycle",
        unicycle,
        _s((-1.0, 0.0, 0.0), (-1.0, 0.0, 1.5), (0.0, 1.0, -2.5)),
        "3-D unicycle steered by its turn rate to a point, λ = 0.2",
        tags=("periodic", "closed"),
    ),
    Member(
        "cold_unicycle",
        cold_unicycle,
        _s((-1.0, 0.0, 0.0), (-1.0, 0.0, 1.5), (0.0, 1.0, -2.5)),
        "3-D unicycle of the unicycle member at λ = 0.03",
        tags=("small temperature", "periodic", "closed"),
    ),
    Member(
        "triple_integrator",
        triple_integrator,
        _s((1.0, 0.0, 0.0), (-1.0, 1.0, 0.0), (0.5, -1.0, 1.0)),
        "3-D linear chain of integrators (jerk control), λ = 0.5",
        tags=("linear", "closed"),
    ),
    Member(
        "tumbling_body",
        tumbling_body,
        _s((0.2, 4.0, 0.2), (3.0, 0.0, 0.0), (0.0, 1.0, -3.0)),
        "3-D rigid body detumbled from a spin about its unstable middle axis",
        tags=("fast dynamics", "closed"),
    ),
    Member(
        "fast_acrobot",
        fast_acrobot,
        _s((3.0, 0.0, 4.0, 0.0), (2.5, 0.3, 0.0, 0.0), (-2.8, -0.5, 2.0, 1.0)),
        "4-D acrobot on 25⁴ brought to rest hanging down from a fast state (issue 25)",
        fine=1.5,
        cert_dt=0.001,
        tags=("fast dynamics", "coarse", "periodic"),
    ),
    Member(
        "balance_acrobot",
        balance_acrobot,
        _s((0.1, -0.1, 0.0, 0.0), (-0.15, 0.2, 0.5, 0.0), (0.05, 0.0, -1.0, 0.5)),
        "4-D acrobot balanced near the handstand on 25⁴, λ = 0.5",
        fine=1.5,
        trajectory=True,
        cert_dt=0.002,
        tags=("slow dynamics", "periodic"),
    ),
    Member(
        "planar_obstacle",
        planar_obstacle,
        _s((-1.5, 0.0, 0.0, 0.0), (-1.5, 0.3, 0.0, 0.0), (0.0, -1.5, 0.0, 1.0)),
        "4-D point mass in the plane round a round obstacle on 25⁴, λ = 0.3",
        fine=1.5,
        cert_dt=0.002,
        tags=("local feature", "closed"),
    ),
    Member(
        "hot_band",
        hot_band,
        _s((PI, 0.0), (2.0, 2.0), (-2.0, -3.0)),
        "first exit: a pendulum swung into the band |θ| < 0.5 at any speed, λ = 2, R = 3; its "
        "default solve was 25 % low and its warning judged only the states next to the band",
        max_time=30.0,
        tags=("first exit", "slow dynamics", "periodic", "expensive control"),
    ),
    Member(
        "dock",
        dock,
        _s((1.5, 0.0), (-1.0, 1.0), (0.5, -1.5)),
        "first exit: a point mass docked at rest in a small ball, λ = 0.05 (18 % low at 201²)",
        max_time=20.0,
        tags=("first exit", "narrow goal", "closed"),
    ),
    Member(
        "cold_upright",
        cold_upright,
        _s((0.3, 0.0), (-0.5, 1.0), (1.0, -1.0)),
        "a pendulum held upright against a 1 − cos θ cost at λ = 0.02 (its estimate was a "
        "quarter of a 0.7–1.5 % error)",
        cert_dt=0.002,
        tags=("low temperature", "periodic"),
    ),
    Member(
        "rotor_well",
        rotor_well,
        _s((0.3, 0.0), (-0.6, 1.0), (1.5, -1.5)),
        "a rotor kept in a Gaussian well of state cost 0.15 rad wide (5 cells) at λ = 0.02 "
        "(stranger round 4: its estimate was a fifth of a 0.4–1 % error, time and space errors "
        "of opposite sign)",
        cert_dt=0.002,
        fast=True,
        tags=("low temperature", "narrow cost", "periodic"),
    ),
    Member(
        "rotor_pit",
        rotor_pit,
        _s((0.3, 0.0), (-0.6, 1.0), (1.5, -1.5)),
        "the rotor_well rotor in a pit 0.07 rad wide (2.2 cells) at λ = 0.005, T = 5: the pit's "
        "centre lies between two nodes of the odd periodic axis (stranger round 4: 10 % high "
        "without a warning; 13 % with an estimate of 2 % at dt = 0.01)",
        cert_dt=0.002,
        fast=True,
        tags=("low temperature", "narrow cost", "periodic"),
    ),
    Member(
        "mass_pit",
        mass_pit,
        _s((0.1, 0.0), (0.8, 1.0), (-1.0, -1.0)),
        "a point mass in a pit 0.04 wide (2 cells) at λ = 0.005, T = 5, centred midway between "
        "two nodes of an odd closed axis, next to a node of its embedded axis (stranger round 5: "
        "12 % high with an estimate of 0.8 %, no warning)",
        cert_dt=0.002,
        fast=True,
        tags=("low temperature", "narrow cost", "closed"),
    ),
    Member(
        "terminal_pit",
        terminal_pit,
        _s((0.2, 0.0), (0.6, -0.5), (0.0, 1.0)),
        "a terminal cost only, a pit 0.04 wide (2 cells) at T = 0.5, λ = 0.05 (exp(−g/λ) a "
        "quarter of a cell wide), centred midway between two nodes of an odd closed axis, next to "
        "a node of its embedded axis (stranger round 5: 11–36 % high with estimates of "
        "1.5–4.6 %, no warning; space and time errors of opposite sign on both grids)",
        cert_dt=0.001,
        fast=True,
        tags=("narrow cost", "short horizon", "closed"),
    ),
    Member(
        "rotor_pit_off",
        rotor_pit_off,
        _s((0.3, 0.0), (1.2, 1.0), (-1.5, -1.5)),
        "the rotor_pit rotor with its pit at θ = 0.7 on 202 periodic nodes, midway between two "
        "nodes of the even axis, next to a node of its embedded axis (stranger round 5: 8 % high "
        "with an estimate of 0.8 %, no warning)",
        cert_dt=0.002,
        fast=True,
        tags=("low temperature", "narrow cost", "periodic"),
    ),
    Member(
        "mass_pit_centre",
        mass_pit_centre,
        _s((0.2, 0.0), (0.8, 1.0), (-1.0, -1.0)),
        "mass_pit with its pit at x = 0.01, midway between two nodes next to the centre of the "
        "odd closed axis, where both grids of the pair miss it by a quarter of their cell "
        "(stranger round 6: 15 % high with an estimate of 3.8 %, no warning)",
        cert_dt=0.002,
        fast=True,
        tags=("low temperature", "narrow cost", "closed"),
    ),
    Member(
        "mass_pit_wall",
        mass_pit_wall,
        _s((-1.6, 0.0), (-1.0, 1.0), (-0.5, -1.0)),
        "mass_pit on 200 × 201 nodes with its pit midway between two nodes near the wall x = −2, "
        "where the pair's grids miss it by 0.22 and 0.28 of their cell (stranger round 6: 16 % "
        "high with an estimate of 2.5 %, no warning)",
        cert_dt=0.002,
        fast=True,
        tags=("low temperature", "narrow cost", "closed"),
    ),
    Member(
        "goal_in_cell",
        goal_in_cell,
        _s((0.0, 0.0, 0.0), (1.0, -1.0, 0.5), (0.35, 0.25, -0.2)),
        "a 3-D single integrator with a terminal goal half a cell wide at the centre of a cell, "
        "λ = 0.1: the grid sees a shallow dip, its policy never goes into the goal (stranger round "
        "7: 64 % and 87 % high with estimates of 0.4 % and 1.6 %, no warning; exact values by "
        "quadrature in strangers_round7.py)",
        fine=3.0,
        cert_dt=0.002,
        tags=("3-D", "narrow cost", "closed"),
    ),
    Member(
        "stiff_relax",
        stiff_relax,
        _s((0.0, 0.0), (1.0, 0.5), (-1.5, -1.0)),
        "a mode relaxing at rate 50 beside a slow one, with a wall no controlled path reaches "
        "(stranger round 7: errors 0.1–0.3 %, warned when the estimate's paths stepped at T/100, "
        "where Euler–Maruyama multiplies x by −1.5 per step)",
        cert_dt=0.002,
        fast=True,
        tags=("fast dynamics", "closed"),
    ),
    Member(
        "goal_face_3d",
        goal_face_3d,
        _s((0.0, 0.0, 0.0), (1.0, -1.0, 0.5), (0.35, 0.2, -0.15)),
        "goal_in_cell's terminal goal half a cell wide at the centre of a cell face (midway on x "
        "only), λ = 0.1 (stranger round 8: 49 % and 56 % high with estimates of 2.8 % and 2.0 %, "
        "no warning; exact values by a closed-form series)",
        fine=1.5,
        cert_dt=0.002,
        tags=("3-D", "narrow cost", "closed"),
        exact=exact_goal(goal_face_3d),
    ),
    Member(
        "goal_quarter",
        goal_quarter,
        _s((0.0, 0.0), (0.3, -0.3), (-1.0, 0.5)),
        "a 2-D single integrator on 201² with a terminal goal a quarter of a cell wide, a quarter "
        "cell off a node on both axes, λ = 0.1 (stranger round 8: 27 % and 38 % high with "
        "estimates of 0.13 % and 0.38 %, no warning; exact values by a closed-form series)",
        cert_dt=0.002,
        tags=("narrow cost", "closed"),
        exact=exact_goal(goal_quarter),
    ),
    Member(
        "goal_4d",
        goal_4d,
        _s((0.0, 0.0, 0.0, 0.0), (0.1, -0.3, 0.3, 0.1), (-1.0, 1.0, 0.0, 0.5)),
        "a 4-D single integrator on 21⁴ with a terminal goal half a cell wide at the centre of a "
        "cell, λ = 0.2 (stranger round 8: 26 % and 33 % high with estimates of 0.36 % and 0.41 %, "
        "no warning; exact values by a closed-form series)",
        fine=1.5,
        cert_dt=0.002,
        tags=("narrow cost", "coarse", "closed"),
        exact=exact_goal(goal_4d),
    ),
    Member(
        "well_face",
        well_face,
        _s((0.0, -0.4), (0.5, 0.0), (-0.5, -1.0)),
        "a well of state cost half a cell wide at the centre of a cell face on 81², λ = 0.02 "
        "(stranger round 8: 19 %, 11 % and 9 % high with estimates of 6.7, 4.0 and 3.1 %, all of "
        "it the cost gap, no warning; certificates of ESS 167–248, the 641² solve within 0.3 %)",
        fine=4.0,
        cert_dt=0.002,
        fast=True,
        tags=("low temperature", "narrow cost", "closed"),
    ),
    Member(
        "pit_drift",
        pit_drift,
        _s((-0.5, 0.0), (0.5, 0.1), (-1.0, -0.5)),
        "a drift ẋ₁ = 1 + u₁ carries the process through a pit of state cost half a cell wide at "
        "the centre of a cell face on 41², λ = 0.05 (stranger round 8: 10 %, 17 % and 6 % high "
        "with estimates of 0.44, 2.3 and 1.2 %, no warning; the 8× grid 2–4 % below the "
        "certificates)",
        fine=4.0,
        cert_dt=0.002,
        fast=True,
        tags=("narrow cost", "local feature", "closed"),
    ),
    Member(
        "goal_off8",
        goal_off8,
        _s((0.0, 0.0), (0.3, -0.3), (-1.0, 0.5)),
        "a terminal goal an eighth of a cell wide an eighth of a cell off a node on 201², "
        "λ = 0.1: the blind spot of the excess between the nodes (stranger round 9: 15 % and "
        "23 % high with estimates of 0.1 % and 0.4 %, no warning; exact values by a closed-form "
        "series)",
        cert_dt=0.002,
        tags=("narrow cost", "closed"),
        exact=exact_goal(goal_off8),
    ),
    Member(
        "goal_off8_3d",
        goal_off8_3d,
        _s((0.0, 0.0, 0.0), (0.3, -0.2, 0.0), (1.0, -1.0, 0.5)),
        "goal_off8 in 3-D on 41³ (stranger round 9: 36 %, 43 % and 7 % high with estimates "
        "below 0.2 %, no warning; exact values by a closed-form series)",
        cert_dt=0.002,
        tags=("3-D", "narrow cost", "closed"),
        exact=exact_goal(goal_off8_3d),
    ),
    Member(
        "goal_m2_3d",
        goal_m2_3d,
        _s((0.0, 0.0, 0.0), (0.3, -0.2, 0.1), (1.0, -1.0, 0.5)),
        "a terminal goal a fifth of a cell wide a quarter cell off a node on 65³, a grid too "
        "large for 4 lattice points per cell (stranger round 9: 30 %, 37 % and 6 % high with "
        "estimates of 0.01 %, no warning; exact values by a closed-form series)",
        cert_dt=0.002,
        tags=("3-D", "narrow cost", "closed"),
        exact=exact_goal(goal_m2_3d),
    ),
    Member(
        "goal4d_mid",
        goal4d_mid,
        _s((0.05, -0.35, 0.25, -0.15), (0.3, -0.2, 0.1, 0.0), (-1.0, 0.5, 0.5, -0.5)),
        "a 4-D goal a sixth of a cell wide at the centre of a lattice cell on 21⁴ (stranger round "
        "10: 11.5 % and 7.5 % high, S 2.6 % and 2.2 %, no warning; the descent finds the goal's "
        "weight, the embedded grid's solve carries a quarter of its effect; exact values by a "
        "closed-form series)",
        cert_dt=0.002,
        tags=("4-D", "narrow cost", "closed"),
        exact=exact_goal(goal4d_mid),
    ),
    Member(
        "comb_torus",
        comb_torus,
        _s((0.0, 0.0), (3.1, -0.3), (-1.2, 0.5)),
        "32 terminal troughs narrower than the lattice's spacing across a periodic axis, one at "
        "its seam (stranger round 10: 60 % high at every state with S of 0.1–17 %: the excess "
        "at the lattice point beside each trough was below the descent's threshold, then more "
        "tied minima than the descent's budget; exact values by 1-D quadrature)",
        cert_dt=0.002,
        fast=True,
        tags=("narrow cost", "periodic"),
        exact=exact_separable(
            [(_comb, 2 * PI, 0.00005), (lambda y: 0.1 * y**2, None, 0.001)], 0.1, 1.0
        ),
    ),
    Member(
        "shallow_long_well",
        shallow_long_well,
        _s((0.0, 0.0), (0.35, -0.25), (-1.0, 0.5)),
        "a state-cost well half a cell wide and 6 λ deep at a cell centre, λ = 0.05, T = 8: "
        "holding a path in it costs more than it saves (stranger round 9: errors 0.01–0.7 % with "
        "estimates of 11–23 % from the excess between the nodes, warned)",
        fine=4.0,
        cert_dt=0.002,
        fast=True,
        tags=("narrow cost", "closed"),
    ),
    Member(
        "notch_exit",
        r11.notch_halfplane,
        _s((-0.5, 0.0), (0.0, 0.3), (0.3, 0.0)),
        "first exit through a half-plane whose exit cost has a cheap notch a twelfth of a cell "
        "wide, 0.024 from the nodes of every grid the estimate reads (stranger round 11: 13–47 % "
        "high with estimates of 2 % and silent, before S took the exit costs' excess)",
        fast=True,
        tags=("first exit", "narrow cost", "closed"),
        exact=_notch_exit_exact,
    ),
    Member(
        "toll_blind",
        r11.toll_blind,
        _s((-1.5, 0.0), (-0.5, 0.7), (-0.1, -1.0)),
        "first exit across a tall toll strip a sixth of a cell wide midway between two nodes next "
        "to the centre of an axis, where the embedded grid and both grids of the pair miss it "
        "alike (stranger round 11: 14–36 % low with estimates of 2–4 % and silent, before γ was "
        "sampled for tasks that end)",
        fast=True,
        tags=("first exit", "narrow cost", "closed"),
        exact=_toll_blind_exact,
    ),
    Member(
        "notch_exit_horizon",
        r12.hz_notch_exit,
        _s((-0.5, 0.0), (0.0, 0.3), (0.3, 0.0)),
        "notch_exit's exit-cost notch on a task with a horizon, T = 0.6, g = 1.5 (stranger round "
        "12: 13 % and 47 % high with estimates of 6.5 % and 8.7 %, before S took the exit cost of "
        "a task with a horizon)",
        fast=True,
        tags=("first exit", "narrow cost", "closed"),
        exact=_notch_horizon_exact,
    ),
    Member(
        "tiny_ball_cold",
        r11.tiny_ball_cold,
        _s((0.6, 0.1), (-0.2, -0.3), (0.1, 0.35)),
        "first exit into a ball of 0.7 cells' radius around a node, none of whose nodes the grid "
        "with every other node holds, λ = 0.05 (stranger round 11: 6–26 % low, no estimate and "
        "no warning; now no estimate and a warning that says why)",
        fast=True,
        tags=("first exit", "narrow goal", "closed"),
        exact=_tiny_ball_exact,
    ),
    Member(
        "gust_upstream",
        r13.hz_gust,
        _s((-1.0, 0.0), (-0.3, 0.5), (0.3, -1.0)),
        "a fast local headwind three cells wide against the paths to a goal, T = 1.5, λ = 0.2 "
        "(stranger round 13: 35 % and 44 % low upstream of the gust with estimates of about half "
        "that, silent: judged at the better half of the value only, which the gust's states "
        "leave)",
        fast=True,
        tags=("fast flow", "closed"),
        exact=_gust_exact,
    ),
    Member(
        "gust_between_nodes",
        r13.hz_headwind,
        _s((-1.0, 0.0), (-0.3, 0.5), (0.0, -1.0)),
        "a headwind 8 strong and 0.4 cells wide midway between two nodes, T = 1.5, λ = 0.2 "
        "(stranger round 13: 13–36 % low with estimates below 0.1 %, silent: every coarser solve "
        "steps over the gust alike; now the drift check warns)",
        fast=True,
        tags=("fast flow", "closed"),
        exact=_headwind_exact,
    ),
    Member(
        "well_torus_average",
        r13.avg_well_3d,
        _s((0.0, 0.0, 0.0), (0.5, 1.0, -1.0), (-1.5, -0.5, 1.0)),
        "the average cost on a 24³ torus with a well 0.15 cells wide between the nodes, the "
        "relative value h at three states (stranger round 13: h 13–14 % low with an estimate of "
        "2.7 %, silent, before S sampled the state cost of a task without a horizon)",
        tags=("average cost", "narrow cost", "periodic"),
        exact=_well_torus_exact,
    ),
    Member(
        "relative_value_cold",
        r15.avg_mass_cold,
        _s((0.5, 0.5), (1.0, -1.0), (-2.0, 2.5)),
        "the point mass's average cost at λ = 0.05 on a closed 121² box: h at (−2, 2.5) is 73 λ "
        "above its minimum, where the eigenvector is 1e-32 of its largest entry (stranger round "
        "15: h stopped near λ log(1/ε) ≈ 36 λ on every grid alike, 48 % low with an estimate of "
        "7 %, before its small entries were solved again from the others)",
        tags=("average cost", "cold", "closed"),
        exact=_relative_value_exact(r15.P15, "avg_mass_cold"),
    ),
    Member(
        "pair_average_4d",
        r15.avg_pair_4d,
        _s((0.5, 0.5, 0.0, 0.0), (1.0, -1.0, 0.5, 0.5), (-2.0, 2.0, 1.5, -1.0)),
        "two uncoupled point masses' average cost in 4-D (25⁴): the default solve raised from its "
        "estimate's 7⁴ level, where Noda's iteration stalled (stranger round 15)",
        tags=("average cost", "4-D", "closed"),
        exact=_relative_value_exact(r15.P15, "avg_pair_4d"),
    ),
    Member(
        "two_doors",
        r15.fe_two_doors,
        r15.P15["fe_two_doors"][1],
        "first exit through two doors of different costs, g_E written as np.where(x₀ ≤ −1, 1.2, "
        "0), which is 0 off E (stranger round 15: a false alarm of 38 % from the excess summed "
        "off E, and a free door on the 41² level from a crossing rounded to just outside E)",
        tags=("first exit", "step"),
        exact=_two_doors_exact,
    ),
    Member(
        "three_doors",
        r15.fe_three_doors,
        r15.P15["fe_three_doors"][1],
        "first exit through three doors whose costs step at a corner inside E (stranger round "
        "15: a false alarm from the corner's step, which no path pays between the nodes)",
        tags=("first exit", "step", "corner"),
        exact=_three_doors_exact,
    ),
    Member(
        "cold_flow_exit",
        r16.fe_frozen_flow,
        r16.P16["fe_frozen_flow"][1],
        "first exit through a user's flow at λ = 0.005 on 81²: z falls by e^{12} per cell where "
        "the chain's second differences carry e^{5} (stranger round 16: 43–61 % low, estimates a "
        "quarter to a third of the error, warned as rough, before the truncation error was "
        "carried along the paths)",
        tags=("first exit", "cold", "user system"),
        exact=_cold_flow_exact,
    ),
    Member(
        "cold_ou_average",
        r16.avg_ou_frozen,
        r16.P16["avg_ou_frozen"][1],
        "the average cost of a coupled Ornstein–Uhlenbeck pull at λ = 0.005 on 161², the "
        "relative value h at four states (stranger round 16: 7–42 % low, the estimate 0.37 of "
        "the error at the farthest state, before the truncation error was carried along the "
        "paths to h's minimum)",
        tags=("average cost", "cold", "closed"),
        exact=_relative_value_exact(r16.P16, "avg_ou_frozen"),
    ),
    Member(
        "kink_tiny_horizon",
        r17.hz_tiny_T_c,
        r17.P17["hz_tiny_T_c"][1],
        "a terminal cost with kinks between the nodes under a horizon of 0.002, in which the "
        "noise moves half a cell (stranger round 17: 11–13 % high at the kinks' crossing, too few "
        "states for the quantile; silent until the warning's confirmation read the cells' "
        "centres, 2026-12-06; solve(tol=) brings them within 2 %)",
        tags=("short horizon", "kink", "narrow cost"),
        exact=_kink_tiny_horizon_exact,
    ),
    Member(
        "sliding_switch",
        r18.sliding_frozen,
        r18.P18["sliding_frozen"][1],
        "a pull to a line that switches over a fifth of a cell (a sliding mode, ẋ₀ = −2 tanh((x₀ − "
        "0.37)/0.01) + u₀) at λ = 0.005 under the default step, which carries a path 6.7 cells "
        "(stranger round 18: 7–16 % low and silent: the midpoint foot lands beyond the line, "
        "every coarser solve alike; warned since the feet are checked by two half steps)",
        tags=("fast dynamics", "local feature", "cold", "closed"),
        exact=_sliding_switch_exact,
    ),
    Member(
        "logistic_edge",
        logistic_edge,
        _s((0.0, 0.001), (0.3, 0.004), (-0.5, 0.02), (0.0, 0.5)),
        "a share that grows logistically from an invariant edge, neither driven nor noisy, with "
        "an affine cost (stranger round 19b's early epidemic in closed form: v climbs like "
        "log x₁ from 0 at the edge to 2.7 at the first node, and the grid interpolates a line "
        "there: 82 % low on 1 % of the states, where γ ≡ 0, silent; warned since the local "
        "certificate confirms the warning)",
        tags=("local feature", "slow dynamics", "user system", "closed"),
        exact=_logistic_edge_exact,
    ),
    Member(
        "exit_late",
        r20.exit_warm,
        r20.X_EXL,
        "a point mass that may leave through |x₁| ≥ 1.8 at no cost or pay 2x₁² + v² at T = 2, "
        "read at t = 1.8 (stranger round 20's exit_warm_late, λ = 0.5): the exit lies across an "
        "axis without noise, and next to it the solve is 47 % low at (1.6, 0), every grid of "
        "51²–401² low alike; silent (the warning judges t = 0), and its estimate 6 % of the "
        "error until the truncation term read slices over [t, T] and the estimate certified "
        "the remaining task whole",
        cert_dt=0.002,
        tags=("first exit", "local feature", "noiseless axis", "closed"),
        time=1.8,
        proposals=_lq_without_exit,
    ),
    Member(
        "exit_late_cold",
        r20.exit_hz,
        _s((0.0, 0.0), (1.0, 0.5), (-1.5, 0.0), (1.7, -1.0)),
        "exit_late at λ = 0.2, read at t = 1.8 (stranger round 20's exit_hz_late): 53 % low at "
        "(−1.5, 0), warned (the plain scheme cannot resolve the desirability), its estimate a "
        "fifth of the error until the estimate certified the remaining task whole",
        cert_dt=0.002,
        tags=("first exit", "local feature", "noiseless axis", "cold", "closed"),
        time=1.8,
        proposals=_lq_without_exit,
    ),
    Member(
        "cart_exit_late",
        r20.cart_exit,
        r20.X_CEX,
        "a user's cart on a corrugated track, ẍ = −2 sin 2x − 0.2ẋ + u, that may leave through "
        "x ≥ 2.5 at no cost, read at t = 4.7 of T = 5 (stranger round 20): 62 % low at (2.2, 0), "
        "warned, its estimate a sixth of the error",
        cert_dt=0.002,
        tags=("first exit", "local feature", "noiseless axis", "user system", "closed"),
        time=4.7,
        proposals=lambda problem: {"a finer solve without the exit": r20.noexit_policy(problem)},
    ),
    Member(
        "exit_strip_between",
        r22.P22["exit_strip_mid"][0],
        r22.P22["exit_strip_mid"][1][1:4],  # off the strip, where v* > 0
        "first exit (q = 1, λ = 0.2, 81²) through a strip |x₀ − 0.525| ≤ 0.0075 at no cost, 0.15 "
        "cell wide at mid-cell, or x₀ ≤ −1.9 at cost 3 (stranger round 22's exit_strip_mid): no "
        "node of any grid lies in the strip, every solve is that of the task without it, v 1–32 "
        "times the truth, silent until the exit set was sampled between the nodes",
        tags=("first exit", "narrow exit", "closed"),
        exact=_strip_exact,
    ),
    Member(
        "driftwall_kept_node",
        r22.P22["driftwall2_even_node"][0],
        r22.P22["driftwall2_even_node"][1],
        "a drift wall ẋ₀ = −30 e^{−(x₀−0.4)²/2s²} + u₀, s an eighth of a cell, on a node the "
        "coarser grids keep (101², λ = 0.1, T = 1; stranger round 22's driftwall2_even_node): no "
        "step's midpoint evaluation feels the wall, v 43–50 % low, silent until the drift's "
        "interpolation order was read over the estimate's grids against 1.5",
        tags=("narrow drift", "user system", "closed"),
        exact=_wall_exact,
    ),
    Member(
        "gain_band",
        r22.P22["gainband2_deep"][0],
        r22.P22["gainband2_deep"][1],
        "a gain b(x₀) that drops to 0.05 in a band 0.3 cell wide at mid-cell (noise and control "
        "together; 101², λ = 0.1; stranger round 22's gainband2_deep): the grid reads B at its "
        "nodes, v 13–15 % low with every part of the estimate below 2.1 %, warned since the "
        "noise's interpolation is checked",
        tags=("narrow gain", "user system", "closed"),
        exact=_gain_exact,
    ),
    Member(
        "store_far_apart",
        _store_far_problem,
        np.array([[0.0, 0.0], [1.5, 1.0], [-2.0, -1.0]]),
        "a user's store_every=19 on a 19-step solve (only t = 0 and T stored), read at t = 1.5: v "
        "interpolated linearly in time between them, 16–29 % off; the coarser solves stored "
        "as sparsely and interpolated alike (stranger round 21's opt_store19), silent until they "
        "stored twice as densely and the estimate read what the interpolation changes",
        tags=("read late", "solve options", "closed"),
        exact=_store_far_exact,
        time=1.5,
        options={"store_every": 19},
    ),
    Member(
        "late_terminal_only",
        _late_terminal_problem,
        np.array([[1.0, 0.54], [0.9, 0.7], [1.5, 0.3]]),
        "a terminal cost only at the default step T/13, read in the middle of the last interval "
        "(stranger round 21's pm_q0): 6–7 % off near the goal, warned by the local certificate "
        "only while its chains resolve the short remaining span finely (a certificate of that "
        "span in one chain step per solve step lost the warning: its standard error grew 2.7×)",
        tags=("read late", "closed"),
        exact=_late_terminal_exact,
        time=LATE_TERMINAL_TIME,
    ),
    Member(
        "mixing_inputs_late",
        _mixing_inputs_problem,
        np.array([[3.0, -0.9], [2.5, -0.9], [0.45, -0.25]]),
        "two inputs that each push both axes (off-diagonal R, the noise diagonal) with a goal "
        "narrow across 45°, read one interval before T at the default step T/10 (stranger round "
        "38's mixB_d0.25_l0.5_T2): 45–47 % off on the wall x₀ = 3, where its warning points; the "
        "round's own reads (t = 0, 0.9 T) were within 1 %",
        tags=("read late", "closed"),
        time=1.9,
    ),
    Member(
        "seam_jump",
        _seam_jump_problem,
        np.array([[0.0, 0.0], [1.0, -1.0], [-1.5, 2.0]]),
        "a pendulum's wrap-aware quadratic terminal cost with a cross term, which jumps by up to "
        "90 across its seam inside a cell, λ = 0.07 (stranger round 39's r39_3d_hz_06 in 2-D): "
        "the sub-cell excess read the jump as a goal below every cost the problem has, and the "
        "estimate 64 times v where the solve is right",
        tags=("periodic", "small temperature", "discontinuous cost"),
    ),
    Member(
        "small_exit_horizon",
        _small_exit_horizon_problem,
        _s(
            (2.25, -3.0),
            (1.0255092844863456, -1.1170929582993399),
            (0.0012085717347403713, 0.6351224742755397),
        ),
        "a point mass's task with a horizon, T = 1.15, that also ends in a ball 2.5 cells across, "
        "λ = 0.51 with v* below λ (stranger round 47's r47_PointMass_hzfe_18): 11 % high and "
        "silent three cells from the exit while the march held the exit set at its nodes; it "
        "now fits the set's boundary between them, as the stationary solve does",
        fast=True,
        tags=("first exit", "narrow goal", "closed"),
    ),
)

BY_NAME = {m.name: m for m in MEMBERS}
