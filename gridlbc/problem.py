"""A linearly solvable finite-horizon control problem, on a grid or grid-free (paper §3.2).

    dx = (a(x) + B(x) u) dt + dξ,      Cov[dξ] = λ B R⁻¹ Bᵀ dt
    J  = E[ g(x_T) + ∫₀ᵀ ( q(x) + ½ uᵀ R u ) dt ]

The desirability z = exp(−v/λ) then solves the linear backward PDE

    −∂ₜz = −(q/λ) z + aᵀ∇z + (λ/2) tr(B R⁻¹ Bᵀ ∇²z),      z(x, T) = exp(−g(x)/λ),

and the optimal policy is u* = λ R⁻¹ Bᵀ∇z / z = −R⁻¹ Bᵀ∇v.

The grid solvers need a :class:`gridlbc.Grid`. Trajectory methods, rollouts and certificates do
not: ``Problem(system, None, horizon, terminal_cost, ..., periodic=(...))`` states only which
coordinates are angles (period 2π, wrapped into [−π, π)), for wrap-aware costs and differences.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._numba import jit
from .costs import (
    Constant,
    Quadratic,
    TimeDependent,
    Tracking,
    evaluate_cost,
    is_number,
    time_parameter,
    wrap_angle,
)
from .grid import Grid, check_states
from .regions import bind_periods, check_region, region_mask
from .systems.base import ControlAffineSystem


def _control_cost_matrix(control_cost, m: int) -> np.ndarray:
    R = np.asarray(control_cost, dtype=float)
    if R.ndim == 0:
        R = np.full(m, float(R))
    if R.ndim == 1:
        if R.shape != (m,):
            raise ValueError(
                f"control_cost must be a scalar, ({m},) or ({m}, {m}), got shape {R.shape}"
            )
        R = np.diag(R)
    if R.shape != (m, m):
        raise ValueError(
            f"control_cost must be a scalar, ({m},) or ({m}, {m}), got shape {R.shape}"
        )
    if not np.all(np.isfinite(R)) or not np.allclose(R, R.T, rtol=1e-12, atol=0):
        raise ValueError("control_cost R must be a finite symmetric matrix")
    if np.linalg.eigvalsh(R).min() <= 0:
        raise ValueError(
            "control_cost R must be positive definite (every control must cost effort)"
        )
    return R


def positive_float(name: str, value) -> float:
    """``value`` as a positive finite float, or a clear error naming ``name``."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, got {value!r}") from None
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be positive and finite, got {value}")
    return value


AVERAGE = "average"
"""``horizon=AVERAGE``: the average-cost problem (SPEC §9), a task that goes on forever."""


def _horizon(value) -> float | str | None:
    if value is None or (isinstance(value, str) and value == AVERAGE):
        return value
    if isinstance(value, str):
        raise TypeError(
            f"horizon must be a time T > 0, None (first exit) or {AVERAGE!r}, got {value!r}"
        )
    return positive_float("horizon", value)


@dataclass(frozen=True, eq=False)
class Problem:
    """A system, a grid, a horizon or an exit set, and the costs; the input to
    :func:`gridlbc.solve`.

    Parameters
    ----------
    system : ControlAffineSystem
        The dynamics a(x), B(x).
    grid : Grid or None
        The state-space box; one axis per state coordinate. ``None`` for a grid-free problem
        (trajectory methods, :func:`gridlbc.simulate`): no box, and :func:`gridlbc.solve`
        refuses it.
    horizon : float, None or "average"
        T > 0, in the system's time unit. ``None``: a stationary first-exit problem, which ends
        when the state enters ``exit`` (SPEC §9, docs page :doc:`first_exit`). ``"average"``: the
        average-cost problem, which never ends: the solution is the optimal cost per unit time
        and the relative value.
    terminal_cost : callable or float, optional
        g(x) on ``(N, d)`` states, e.g. :class:`gridlbc.costs.Quadratic` (a number: that
        constant), paid at T; required with a horizon T, and absent without one. Quadratic costs
        are made wrap-aware on the periodic axes.
    state_cost : callable or float, optional
        q(x) ≥ 0 on ``(N, d)`` states (a number: that constant); zero when omitted. A cost with
        ``time_dependent = True`` (:class:`gridlbc.costs.Tracking`), or one with a parameter
        ``t`` (``q(x, t)``, made a :class:`gridlbc.costs.TimeDependent`), is q(x, t): trajectory
        methods and :func:`gridlbc.simulate` accept it, the grid solvers refuse it.
    control_cost : float, (m,) or (m, m)
        R, symmetric positive definite (a scalar means R = r I).
    temperature : float
        λ > 0: the noise level and the unit of the exponential transform z = exp(−v/λ).
    periodic : sequence of int, optional
        The periodic coordinates (angles: period 2π, wrapped into [−π, π)) of a grid-free
        problem; default the system's ``angle_axes``, ``()`` for none. With a grid, the grid's
        periodic axes decide (give ``periodic`` only to restate them).
    exit : region or callable, optional
        The exit set E: the task ends when the state first enters it (at τ), paying
        ``exit_cost`` there. A :mod:`gridlbc.regions` shape (``Box``, ``Ball``, ``a | b``) or
        any callable returning a boolean mask ``(N,)`` of states ``(N, d)``. With a horizon T as
        well, the task ends at min(τ, T).
    exit_cost : callable or float, optional
        g_E(x), finite, paid on entering E (default 0).
    """

    system: ControlAffineSystem
    grid: Grid | None
    horizon: float | str | None
    terminal_cost: Callable[..., np.ndarray] | None = None
    state_cost: Callable[..., np.ndarray] | None = None
    control_cost: float | ArrayLike = 1.0
    temperature: float = 1.0
    periodic: tuple[int, ...] | None = None
    exit: Callable[..., np.ndarray] | None = None
    exit_cost: Callable[..., np.ndarray] | float | None = None

    def __post_init__(self):
        sys, grid = self.system, self.grid
        if grid is not None and not isinstance(grid, Grid):
            raise TypeError(f"grid must be a gridlbc.Grid or None, got {type(grid).__name__}")
        for attr in ("drift", "input_matrix", "state_dim", "control_dim"):
            if not hasattr(sys, attr):
                raise TypeError(
                    f"system must be a control-affine system with .{attr} "
                    "(subclass gridlbc.systems.ControlAffineSystem)"
                )
        if grid is not None and grid.ndim != sys.state_dim:
            raise ValueError(
                f"grid has {grid.ndim} axes but the {type(sys).__name__} state has "
                f"{sys.state_dim} coordinates: give one Axis per state coordinate"
            )

        def set_(k, v):
            return object.__setattr__(self, k, v)

        set_("periodic", self._check_periodic(self.periodic))
        set_("horizon", _horizon(self.horizon))
        set_("temperature", positive_float("temperature", self.temperature))
        set_("control_cost", _control_cost_matrix(self.control_cost, sys.control_dim))
        self._check_ending()
        for name in ("terminal_cost", "state_cost"):
            cost = getattr(self, name)
            if cost is not None:
                set_(name, self._bind_cost(self._constant(cost), name))
        if self.exit is not None:
            region = check_region(self.exit, sys.state_dim)
            set_("exit", bind_periods(region, self.periods))
            cost = self._constant(0.0 if self.exit_cost is None else self.exit_cost)
            set_("exit_cost", self._bind_cost(cost, "exit_cost"))

    def _constant(self, cost):
        """A cost given as a number, as the constant cost (:class:`gridlbc.costs.Constant`)."""
        if is_number(cost):
            return Constant(cost, self.system.state_dim)
        return cost

    def _check_ending(self) -> None:
        """How the task ends is stated once: a horizon with a terminal cost, an exit set, or
        forever (``"average"``)."""
        h, g, E = self.horizon, self.terminal_cost, self.exit
        if self.exit_cost is not None and E is None:
            raise ValueError("exit_cost is paid on entering the exit set: give exit= as well")
        if h == AVERAGE:
            if E is not None or g is not None:
                raise ValueError(
                    "an average-cost problem (horizon='average') never ends: drop exit= and "
                    "terminal_cost (give horizon=None for a first-exit problem)"
                )
        elif h is None:
            if E is None:
                raise ValueError(
                    "horizon=None poses a first-exit problem: give its exit set exit=E (a "
                    "gridlbc.regions shape or a mask function), or horizon='average' for a task "
                    "that goes on forever, or a horizon T"
                )
            if g is not None:
                raise ValueError(
                    "terminal_cost is paid at the horizon T, and this problem has none "
                    "(horizon=None): the first-exit cost is exit_cost"
                )
        elif g is None:
            raise ValueError(
                f"terminal_cost is required with a horizon (T = {h:g}): give g(x), e.g. "
                "gridlbc.costs.Quadratic(center, weights)"
            )

    @property
    def stationary(self) -> bool:
        """Whether the problem has no horizon (first exit with ``horizon=None``, or average
        cost): its solution does not depend on time."""
        return self.horizon is None or self.horizon == AVERAGE

    @property
    def average_cost(self) -> bool:
        """Whether this is the average-cost problem (``horizon="average"``)."""
        return self.horizon == AVERAGE

    def exit_mask(self, x=None) -> np.ndarray:
        """Which states (default: the grid nodes) lie in the exit set E, boolean ``(N,)`` (all
        False without one)."""
        x = self.require_grid("exit_mask()").nodes() if x is None else self.check_states(x)
        if self.exit is None:
            return np.zeros(x.shape[0], dtype=bool)
        return region_mask(self.exit, x)

    def exit_values(self, x=None) -> np.ndarray:
        """g_E at states (default: the grid nodes), checked finite."""
        x = self.require_grid("exit_values()").nodes() if x is None else self.check_states(x)
        if self.exit_cost is None:
            raise ValueError("this problem has no exit set (exit=None), so no exit cost")
        return evaluate_cost(self.exit_cost, x, "exit_cost")

    def require_horizon(self, what: str) -> float:
        """T as a float, or a clear error naming ``what`` needs a horizon."""
        if self.horizon is None or isinstance(self.horizon, str):
            raise ValueError(
                f"{what} needs a horizon T, and this problem has none (horizon="
                f"{self.horizon!r}: a first-exit or average-cost problem)"
            )
        return float(self.horizon)

    def require_terminal_cost(self, what: str) -> Callable[..., np.ndarray]:
        """g, or a clear error naming ``what`` needs a terminal cost."""
        if self.terminal_cost is None:
            raise ValueError(
                f"{what} needs a terminal cost g(x), and this problem has none (no horizon)"
            )
        return self.terminal_cost

    def _check_periodic(self, periodic) -> tuple[int, ...] | None:
        if periodic is None:
            return None
        d = self.system.state_dim
        try:
            axes = tuple(sorted({int(k) for k in periodic}))
        except (TypeError, ValueError):
            raise TypeError(
                f"periodic must be a sequence of coordinate indices, got {periodic!r}"
            ) from None
        if axes and not (axes[0] >= 0 and axes[-1] < d):
            raise ValueError(
                f"periodic indices must lie in 0 … {d - 1} (state coordinates), got {periodic!r}"
            )
        if self.grid is not None:
            on_grid = tuple(int(k) for k in np.flatnonzero(self.grid.periodic))
            if axes != on_grid:
                raise ValueError(
                    f"periodic={axes} disagrees with the grid's periodic axes {on_grid}: the grid "
                    "decides, leave periodic out (or set Axis(..., periodic=True) on the grid)"
                )
        return axes

    @property
    def state_dim(self) -> int:
        return self.system.state_dim

    @property
    def periodic_axes(self) -> tuple[int, ...]:
        """The periodic coordinates: the grid's, else ``periodic``, else the system's angles."""
        if self.grid is not None:
            return tuple(int(k) for k in np.flatnonzero(self.grid.periodic))
        if self.periodic is not None:
            return self.periodic
        return tuple(int(k) for k in getattr(self.system, "angle_axes", ()))

    @property
    def periods(self) -> np.ndarray:
        """Period per coordinate, ``inf`` where not periodic, shape ``(d,)``."""
        if self.grid is not None:
            return self.grid.periods
        P = np.full(self.state_dim, np.inf)
        P[list(self.periodic_axes)] = 2 * np.pi
        return P

    def wrap(self, x) -> np.ndarray:
        """Periodic coordinates into the grid's box, or into [−π, π) without a grid."""
        if self.grid is not None:
            return self.grid.wrap(x)
        x = np.array(x, dtype=float, copy=True)
        for k in self.periodic_axes:
            x[..., k] = wrap_angle(x[..., k])
        return x

    def check_states(self, x, name: str = "x") -> np.ndarray:
        """States as a finite float ``(N, d)`` array (one state may be ``(d,)``)."""
        if self.grid is not None:
            return self.grid.check_states(x, name)
        return check_states(x, self.state_dim, name, f"the {self.state_dim}-dimensional state")

    def require_grid(self, what: str) -> Grid:
        """The grid, or a clear error naming ``what`` needs it."""
        if self.grid is None:
            raise ValueError(
                f"{what} needs a grid, and this Problem has none (grid=None, made for trajectory "
                "methods and rollouts): give Problem(system, Grid([Axis(...), ...]), horizon, "
                "terminal_cost, ...) to solve on a grid, or use gridlbc.trajectory for a "
                "grid-free problem"
            )
        return self.grid

    def _bind_cost(self, cost, name):
        if not callable(cost):
            raise TypeError(
                f"{name} must be callable on (N, d) states, e.g. gridlbc.costs.Quadratic"
            )
        if name == "state_cost" and not getattr(cost, "time_dependent", False):
            parameter = time_parameter(cost)  # q(x, t=...): not to be read at one time alone
            if parameter is not None:
                cost = TimeDependent(cost, parameter)
        if getattr(cost, "time_dependent", False) and name == "terminal_cost":
            raise TypeError(
                "terminal_cost must be a function of the state alone, g(x): a "
                "time-dependent cost (costs.Tracking) can only be a state_cost"
            )
        if isinstance(cost, (Quadratic, Tracking)):
            if cost.dim != self.state_dim:
                raise ValueError(
                    f"{name} center has {cost.dim} coordinates but the state has {self.state_dim}"
                )
            if cost.periods is None:
                cost = cost.with_periods(self.periods)
        return cost

    def replace(self, **changes) -> Problem:
        """A copy with some fields changed (e.g. ``terminal_cost``)."""
        return dataclasses.replace(self, **changes)

    @property
    def R(self) -> np.ndarray:
        """The control cost matrix, (m, m)."""
        return np.asarray(self.control_cost)

    @property
    def R_inv(self) -> np.ndarray:
        return np.linalg.inv(np.asarray(self.control_cost))

    def terminal_values(self, x=None) -> np.ndarray:
        """g at states (default: the grid nodes), checked finite."""
        x = self.require_grid("terminal_values()").nodes() if x is None else self.check_states(x)
        if self.terminal_cost is None:
            raise ValueError(
                "this problem has no terminal cost (no horizon): a first-exit problem pays "
                "exit_cost on its exit set"
            )
        return evaluate_cost(self.terminal_cost, x, "terminal_cost")

    def state_cost_values(self, x=None, t=None, signed: bool = False) -> np.ndarray:
        """q at states (default: the grid nodes) and time ``t``, checked finite and non-negative.

        ``t`` is needed only by a time-dependent state cost (:class:`gridlbc.costs.Tracking`).
        ``signed``: not checked for sign: the samples between the nodes of the error estimate
        (:mod:`gridlbc.accuracy`) and of rollouts and certificates (:mod:`gridlbc.simulate`),
        where a cost the solve accepted at every node may dip below zero; the solve is posed on
        the nodes, and a path pays the cost as it is.
        """
        x = self.require_grid("state_cost_values()").nodes() if x is None else self.check_states(x)
        if self.state_cost is None:
            return np.zeros(x.shape[0])
        cost = self.state_cost
        if getattr(cost, "time_dependent", False):
            if t is None:
                raise ValueError(
                    "state_cost depends on time (q(x, t): costs.Tracking, or a function with a "
                    "parameter t): the grid solvers need q(x) alone. Use gridlbc.trajectory for "
                    "a tracking cost, or solve on a grid with the time as one more state "
                    "coordinate s (ds/dt = 1, no noise on it; q(x, s) is then a cost of the "
                    "state), or piece by piece where q is constant in time (docs page "
                    "'limitations')"
                )
            q = evaluate_cost(lambda y: cost(y, t), x, "state_cost")
        else:
            q = evaluate_cost(cost, x, "state_cost")
        if not signed and np.any(q < 0):
            raise ValueError(
                f"state_cost must be non-negative (min {q.min():.3g}): add a constant to it; "
                "a constant shifts v by constant·T and leaves the policy unchanged"
            )
        return q

    def noise_covariance(self, x) -> np.ndarray:
        """Σ(x) = λ B R⁻¹ Bᵀ, shape ``(N, d, d)``."""
        B = self._input_matrix(x)
        return self.temperature * np.einsum("nim,mk,njk->nij", B, self.R_inv, B)

    def input_matrix(self, x) -> np.ndarray:
        """B(x) at states ``x``, ``(N, d, m)`` as float, its shape checked."""
        return self._input_matrix(x)

    def _input_matrix(self, x) -> np.ndarray:
        """B(x) ``(N, d, m)`` as float, its shape checked."""
        x = self.check_states(x)
        d, m = self.system.state_dim, self.system.control_dim
        B = np.asarray(self.system.input_matrix(x), dtype=float)
        if B.shape != (x.shape[0], d, m):
            raise ValueError(
                f"{type(self.system).__name__}.input_matrix returned shape {B.shape}, "
                f"expected (N, d, m) = ({x.shape[0]}, {d}, {m})"
            )
        return B

    def noise_diagonal(self, x) -> np.ndarray:
        """The diagonal of Σ(x) = λ B R⁻¹ Bᵀ, shape ``(N, d)``; raises if Σ is not diagonal.

        The grid solvers need noise that is diagonal in the grid's coordinates (no cross
        derivatives ∂²z/∂x_i∂x_j).
        """
        B = self._input_matrix(x)
        diag, off = _covariance_diagonal(
            np.ascontiguousarray(B), np.asarray(self.R_inv, dtype=float), float(self.temperature)
        )
        scale = max(np.abs(diag).max(), np.finfo(float).tiny)
        if off.max() > 1e-12 * scale:
            i, j = np.unravel_index(off.argmax(), off.shape)
            raise ValueError(
                f"the noise covariance λ B R⁻¹ Bᵀ is not diagonal in the grid coordinates "
                f"(entry ({i}, {j}) is nonzero): the grid solvers need each control to drive its "
                "own state axis. Change coordinates so that it does, as the Acrobot does by using "
                "canonical momenta p = M(θ)θ̇ instead of joint velocities, or choose B and R so "
                "that B R⁻¹ Bᵀ is diagonal (for instance a diagonal R with each control driving "
                "its own state axis)."
            )
        return diag

    def describe(self) -> str:
        where = (
            self.grid.describe()
            if self.grid is not None
            else f"no grid (periodic {list(self.periodic_axes)})"
        )
        if self.horizon is None:
            ending = f"first exit to {self.exit!r}"
        elif self.horizon == AVERAGE:
            ending = "average cost"
        else:
            ending = f"T={self.horizon:g}" + (
                f", exit to {self.exit!r}" if self.exit is not None else ""
            )
        return f"{type(self.system).__name__} on {where}, {ending}, λ={self.temperature:g}"


@jit
def _covariance_diagonal(B, R_inv, lam):
    """The diagonal of λ B R⁻¹ Bᵀ per state, ``(N, d)``, and the largest |entry| off it, ``(d, d)``
    over all states, in one pass (no ``(N, d, d)`` array)."""
    n, d, m = B.shape
    diag = np.empty((n, d))
    off = np.zeros((d, d))
    for p in range(n):
        for i in range(d):
            for j in range(d):
                total = 0.0
                for a in range(m):
                    for b in range(m):
                        total += B[p, i, a] * R_inv[a, b] * B[p, j, b]
                if i == j:
                    diag[p, i] = lam * total
                else:
                    off[i, j] = max(off[i, j], abs(lam * total))
    return diag, off


# -- how a solution of a problem is evaluated -----------------------------------------------------


def check_time(t, horizon: float) -> float:
    """``t`` as a float in [0, T] (rounding-level excursions clipped); a clear error otherwise.

    Parameters
    ----------
    t : float
        A time.
    horizon : float
        T.
    """
    try:
        t = float(t)
    except (TypeError, ValueError):
        raise TypeError(f"t must be a single time (float), got {t!r}") from None
    tol = 1e-9 * horizon
    if not (np.isfinite(t) and -tol <= t <= horizon + tol):
        raise ValueError(f"t must lie in [0, T] = [0, {horizon:g}], got {t!r}")
    return min(max(t, 0.0), horizon)


def bracket(times: np.ndarray, t: float) -> tuple[int, float]:
    """The stored interval of ``t``: j and θ ∈ [0, 1] with t = (1 − θ) times[j] + θ times[j+1].

    Parameters
    ----------
    times : ndarray (S,)
        Increasing stored times, S ≥ 2.
    t : float
        A time in [times[0], times[-1]] (:func:`check_time`).
    """
    j = min(max(int(np.searchsorted(times, t, side="right")) - 1, 0), len(times) - 2)
    start, end = float(times[j]), float(times[j + 1])
    return j, min(max((t - start) / (end - start), 0.0), 1.0)  # in Python floats: a read per step


def state_evaluation(method):
    """Give an evaluation ``method(self, x, ...)`` of states ``(N, d)`` the library's convention
    for one state: given ``x`` of shape ``(d,)`` it returns the first row of its result, so a
    value is a scalar (a numpy float) and a policy ``(m,)``, where ``(N, d)`` gives ``(N,)`` and
    ``(N, m)``. The state is checked by ``self.problem.check_states`` first (so a wrong one is
    named as it was given), and the method itself always sees ``(N, d)``.

    Parameters
    ----------
    method : callable
        ``method(self, x, *args, **kwargs)`` returning an array whose first axis runs over the
        states; ``self`` has a ``problem`` (:class:`Problem`).
    """

    @functools.wraps(method)
    def evaluate(self, x, *args, **kwargs):
        if np.ndim(x) != 1:
            return method(self, x, *args, **kwargs)
        return method(self, self.problem.check_states(x), *args, **kwargs)[0]

    return evaluate
