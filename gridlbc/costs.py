"""State and terminal costs.

A cost is any callable ``c(x)`` taking states ``(N, d)`` and returning ``(N,)``; a state cost may
also take the time, q(x, t) (:class:`Tracking`, or a callable with a parameter ``t``:
:class:`TimeDependent`), which the trajectory methods use and the grid solvers refuse. The
library's own :class:`Quadratic`

    g(x) = (x − c)ᵀ W (x − c)

is wrap-aware: on a periodic axis the difference x − c is taken to the nearest image, in
``[−P/2, P/2)`` for period P, so an angle cost is continuous across the seam. Its exponential
h = exp(−g/λ) is the Gaussian exp(−½ (x − c)ᵀ A (x − c)) with A = 2W/λ, whose inner products
:func:`gridlbc.project` evaluates in closed form.
"""

from __future__ import annotations

import inspect
import numbers
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .backends.numba.costs import quadratic_kernel


@dataclass(frozen=True, eq=False, init=False)
class Quadratic:
    """g(x) = (x − c)ᵀ W (x − c), wrap-aware on periodic axes.

    Parameters
    ----------
    center : array_like, shape (d,)
        c, the minimiser (angles in radians from the upright).
    weights : array_like, shape (d,) or (d, d)
        W: a vector is the diagonal; a matrix must be symmetric positive semi-definite.
    periods : array_like, shape (d,), optional
        Period of each coordinate (``inf`` for none). Left ``None``, a :class:`gridlbc.Problem`
        fills it in from its grid's periodic axes.
    """

    center: np.ndarray
    weights: np.ndarray
    periods: np.ndarray | None

    def __init__(self, center: ArrayLike, weights: ArrayLike, periods: ArrayLike | None = None):
        c = np.atleast_1d(np.asarray(center, dtype=float))
        if c.ndim != 1 or not np.all(np.isfinite(c)):
            raise ValueError(f"Quadratic center must be a finite vector, got {center!r}")
        d = c.size
        W = np.asarray(weights, dtype=float)
        if W.ndim <= 1:
            W = np.diag(np.broadcast_to(W, (d,)))
        if W.shape != (d, d):
            raise ValueError(
                f"Quadratic weights must have shape ({d},) or ({d}, {d}) to match the center, "
                f"got shape {np.shape(weights)}"
            )
        if not np.all(np.isfinite(W)) or not np.allclose(W, W.T, rtol=1e-12, atol=0):
            raise ValueError("Quadratic weights must be a finite symmetric matrix")
        if np.linalg.eigvalsh(W).min() < -1e-12 * max(1.0, np.abs(W).max()):
            raise ValueError(
                "Quadratic weights must be positive semi-definite (a cost, not a reward)"
            )
        object.__setattr__(self, "center", c)
        object.__setattr__(self, "weights", W)
        P = None
        if periods is not None:
            P = np.asarray(periods, dtype=float).reshape(-1)
            if P.shape != (d,) or np.any(P <= 0):
                raise ValueError(f"Quadratic periods must be {d} positive numbers (inf for none)")
        object.__setattr__(self, "periods", P)

    @property
    def dim(self) -> int:
        return self.center.size

    def with_periods(self, periods) -> Quadratic:
        """The same cost, wrap-aware with the given periods (``inf`` where not periodic)."""
        return Quadratic(self.center, self.weights, periods)

    def difference(self, x) -> np.ndarray:
        """x − c, to the nearest periodic image on periodic coordinates, shape ``(N, d)``."""
        return wrap_difference(cost_states(x, self.dim) - self.center, self.periods)

    def __call__(self, x) -> np.ndarray:
        """(x − c)ᵀ W (x − c) at states ``(N, d)``, ``(N,)``: at least 0 (W is positive
        semi-definite; where it is singular, rounding would otherwise put the form a few ulps
        below 0 along its null directions)."""
        return quadratic_form(
            cost_states(x, self.dim), self.center[None], self.weights, self.periods
        )

    def __repr__(self):
        w = (
            np.diag(self.weights)
            if np.count_nonzero(self.weights - np.diag(np.diag(self.weights))) == 0
            else self.weights
        )
        return f"Quadratic(center={self.center.tolist()}, weights={np.asarray(w).tolist()})"


@dataclass(frozen=True)
class Constant:
    """The cost c(x) = value everywhere (an exit cost given as a number).

    Parameters
    ----------
    value : float
        The constant, finite.
    dim : int
        The state's coordinates.
    """

    value: float
    dim: int

    def __post_init__(self):
        try:
            value = float(self.value)
        except (TypeError, ValueError):
            raise TypeError(f"a constant cost must be a number, got {self.value!r}") from None
        if not np.isfinite(value):
            raise ValueError(f"a constant cost must be finite, got {value}")
        object.__setattr__(self, "value", value)

    def __call__(self, x) -> np.ndarray:
        return np.full(np.shape(x)[0], self.value)


def is_number(cost) -> bool:
    """Whether a cost was given as a number (a real, not a bool), the :class:`Constant` it
    stands for (:class:`gridlbc.Problem`, :func:`gridlbc.project`).

    Parameters
    ----------
    cost : object
        A cost as the user gave it.
    """
    return isinstance(cost, numbers.Real) and not isinstance(cost, bool)


def wrap_angle(angles) -> np.ndarray:
    """Angles (radians) to the nearest image of 0, in [−π, π).

    Parameters
    ----------
    angles : array_like
        Any shape; a new array of the same shape is returned.
    """
    return np.mod(np.asarray(angles, dtype=float) + np.pi, 2 * np.pi) - np.pi


def wrap_difference(diff: np.ndarray, periods) -> np.ndarray:
    """Differences taken to the nearest image, in ``[−P/2, P/2)``, on periodic coordinates.

    Parameters
    ----------
    diff : ndarray (N, d)
        Differences of states.
    periods : array_like (d,) or None
        The period of each coordinate (``inf`` where not periodic; ``None``: none is).

    Returns
    -------
    ndarray (N, d)
        A new array.
    """
    diff = np.array(diff, dtype=float)
    if periods is not None:
        for k in np.flatnonzero(np.isfinite(periods)):
            P = periods[k]
            diff[:, k] = np.mod(diff[:, k] + 0.5 * P, P) - 0.5 * P
    return diff


def cost_states(x, dim: int) -> np.ndarray:
    """``x`` as the float states ``(N, dim)`` a quadratic cost reads (one state ``(dim,)`` as one
    row), or a clear error.

    Parameters
    ----------
    x : array_like
        The states.
    dim : int
        The cost's coordinates.
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    if x.ndim != 2 or x.shape[1] != dim:
        raise ValueError(f"cost argument must have shape (N, {dim}), got {x.shape}")
    return x


def quadratic_form(x: np.ndarray, center: np.ndarray, weights: np.ndarray, periods) -> np.ndarray:
    """max((x − c)ᵀ W (x − c), 0) per state, the difference to its nearest image on periodic
    coordinates (:func:`wrap_difference`), in one compiled pass.

    Parameters
    ----------
    x : ndarray (N, d)
        States.
    center : ndarray (N, d) or (1, d)
        c, one per state or one for all.
    weights : ndarray (d, d)
        W, symmetric positive semi-definite.
    periods : array_like (d,) or None
        The period of each coordinate (``inf`` where not periodic; ``None``: none is).

    Returns
    -------
    ndarray (N,)
    """
    d = x.shape[1]
    periods = np.full(d, np.inf) if periods is None else np.asarray(periods, dtype=float)
    out = np.empty(x.shape[0])
    quadratic_kernel(
        np.ascontiguousarray(x), np.ascontiguousarray(center, dtype=float), weights, periods, out
    )
    return out


def evaluate_cost(cost, x: np.ndarray, name: str) -> np.ndarray:
    """Evaluate a cost callable on states and check the result is finite, shape ``(N,)``.

    Parameters
    ----------
    cost : callable
        g(x) on ``(N, d)`` states.
    x : ndarray (N, d)
        The states.
    name : str
        What to call the cost in error messages (e.g. ``"terminal_cost"``).
    """
    values = np.asarray(cost(x), dtype=float)
    if values.shape == ():
        values = np.full(x.shape[0], float(values))
    if values.shape != (x.shape[0],):
        raise ValueError(
            f"{name} must return one value per state, shape ({x.shape[0]},), got shape {values.shape}"
        )
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{name} returned a non-finite value (NaN or inf) at some states")
    return values


@dataclass(frozen=True, eq=False)
class Tracking:
    """The tracking cost q(x, t) = (x − x̃(t))ᵀ Q (x − x̃(t)) of the paper's §6.1, wrap-aware.

    x̃(t) is the reference path, linear between the given samples (held at the ends). Costs that
    depend on time are used by :mod:`gridlbc.trajectory` and :func:`gridlbc.simulate`; the grid
    solvers need q(x) and refuse them.

    Parameters
    ----------
    times : array_like, shape (S,)
        Increasing sample times of the reference path.
    states : array_like, shape (S, d)
        x̃ at those times (angles unwrapped, in radians from the upright).
    weights : array_like, shape (d,) or (d, d)
        Q, positive semi-definite.
    periods : array_like, shape (d,), optional
        As for :class:`Quadratic`; a :class:`gridlbc.Problem` fills it in.
    """

    times: np.ndarray
    states: np.ndarray
    weights: np.ndarray
    periods: np.ndarray | None = None

    time_dependent = True

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float)
        x = np.asarray(self.states, dtype=float)
        if t.ndim != 1 or t.size < 1 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise ValueError("Tracking times must be a non-empty increasing vector of finite times")
        if x.ndim != 2 or x.shape[0] != t.size or not np.all(np.isfinite(x)):
            raise ValueError(
                f"Tracking states must be finite with shape ({t.size}, d), one row "
                f"per time, got shape {np.shape(self.states)}"
            )
        shape = Quadratic(x[0], self.weights, self.periods)  # validates weights and periods
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "states", x)
        object.__setattr__(self, "weights", shape.weights)
        object.__setattr__(self, "periods", shape.periods)

    @property
    def dim(self) -> int:
        return self.states.shape[1]

    def with_periods(self, periods) -> Tracking:
        return Tracking(self.times, self.states, self.weights, periods)

    def reference(self, t) -> np.ndarray:
        """x̃(t) for times ``(N,)`` (or one time), shape ``(N, d)``."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        return np.stack(
            [np.interp(t, self.times, self.states[:, k]) for k in range(self.dim)], axis=1
        )

    def difference(self, x, t) -> np.ndarray:
        """x − x̃(t), nearest image on periodic coordinates, shape ``(N, d)``."""
        x = cost_states(x, self.dim)
        return wrap_difference(x - self.reference(np.broadcast_to(t, x.shape[:1])), self.periods)

    def __call__(self, x, t) -> np.ndarray:
        """(x − x̃(t))ᵀ Q (x − x̃(t)) at states ``(N, d)`` and time(s) ``t``, ``(N,)``, at least 0
        (as :meth:`Quadratic.__call__`)."""
        x = cost_states(x, self.dim)
        reference = self.reference(np.broadcast_to(t, x.shape[:1]))
        return quadratic_form(x, reference, self.weights, self.periods)


TIME_PARAMETERS = ("t", "time")
"""The names by which a state cost takes the time (:func:`time_parameter`)."""


def time_parameter(cost) -> inspect.Parameter | None:
    """The parameter of ``cost`` after the states through which it takes the time: one named
    ``t`` or ``time`` (:data:`TIME_PARAMETERS`); None where it has none, or where its signature
    cannot be read.

    Why: the grid solvers call a state cost as q(x). A cost written ``q(x, t=0.0)`` would be
    read at t = 0 alone, a different problem, and every estimate of the solve would judge that
    problem: its answer could be far off without a word (stranger round 31, docs page
    :doc:`limitations`). :class:`gridlbc.Problem` marks such a cost time-dependent
    (:class:`TimeDependent`), as :class:`Tracking` is.

    Parameters
    ----------
    cost : callable
        A state cost.

    Returns
    -------
    inspect.Parameter or None
    """
    try:
        parameters = list(inspect.signature(cost).parameters.values())
    except (TypeError, ValueError):
        return None
    variadic = (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD)
    for parameter in parameters[1:]:
        if parameter.name in TIME_PARAMETERS and parameter.kind not in variadic:
            return parameter
    return None


@dataclass(frozen=True, eq=False)
class TimeDependent:
    """A state cost q(x, t) that takes the time through a parameter (:func:`time_parameter`),
    marked time-dependent as :class:`Tracking` is: trajectory methods, :func:`gridlbc.simulate`
    and :func:`gridlbc.certify` pass it t, the grid solvers refuse it with a clear error.

    Parameters
    ----------
    cost : callable
        The user's q, called as ``cost(x, t=t)`` (positionally where ``t`` is positional-only).
    parameter : inspect.Parameter
        Its time parameter.
    """

    cost: Callable
    parameter: inspect.Parameter

    time_dependent = True

    def __call__(self, x, t) -> np.ndarray:
        if self.parameter.kind is inspect.Parameter.POSITIONAL_ONLY:
            return self.cost(x, t)
        return self.cost(x, **{self.parameter.name: t})

    def __repr__(self) -> str:
        return f"TimeDependent({self.cost!r})"
