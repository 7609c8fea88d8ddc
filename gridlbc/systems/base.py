"""Control-affine stochastic systems, the base class for built-in and user systems.

A system is the pair (a, B) of

    dx = (a(x) + B(x) u) dt + dξ,     Cov[dξ] = λ B(x) R⁻¹ B(x)ᵀ dt

(paper §3.2): the noise enters through the control channels, which is what makes the Bellman equation
linear in the desirability z = exp(−v/λ). The grid solvers further need B R⁻¹ Bᵀ to be diagonal in
the state coordinates (each control drives its own axis).

To add your own system, subclass :class:`ControlAffineSystem`, set ``state_dim``, ``control_dim``,
``state_names`` and ``angle_axes`` (which coordinates are angles, wrapped with period 2π on a
periodic grid axis) and implement :meth:`drift` and :meth:`input_matrix`, both vectorised over
``(N, d)`` arrays of states.
"""

from __future__ import annotations

import math

import numpy as np

from ..grid import Axis, Grid


def physical_parameter(name: str, value, zero_allowed: bool = False) -> float:
    """A system's constructor argument as a finite float > 0 (≥ 0 with ``zero_allowed``); a
    ``ValueError`` naming it otherwise.

    Parameters
    ----------
    name : str
        The parameter's name, for the message.
    value : float
        Its value.
    zero_allowed : bool
        Accept 0 (a gravity or a damping may vanish; a mass or a length may not).
    """
    value = float(value)
    if not (np.isfinite(value) and (value >= 0 if zero_allowed else value > 0)):
        kind = "non-negative" if zero_allowed else "positive"
        raise ValueError(f"{name} must be a {kind} finite number, got {value}")
    return value


class ControlAffineSystem:
    """Base class: ``a(x)`` by :meth:`drift`, ``B(x)`` by :meth:`input_matrix`.

    Attributes
    ----------
    state_dim : int
        d, the number of state coordinates.
    control_dim : int
        m, the number of controls.
    state_names : tuple of str
        A label per coordinate (plots and messages).
    angle_axes : tuple of int
        The coordinates that are angles (radians, measured from the upright).
    default_box : tuple
        The box a grid spans by default (:meth:`default_grid`), one entry per coordinate:
        ``None`` for an angle (periodic on [−π, π)) or a pair ``(lo, hi)``. Empty: no default.
    """

    state_dim: int = 0
    control_dim: int = 0
    state_names: tuple[str, ...] = ()
    angle_axes: tuple[int, ...] = ()
    default_box: tuple = ()

    def default_grid(self, n) -> Grid:
        """A grid over :attr:`default_box` with ``n`` nodes per axis (one count, or one per axis)."""
        name = type(self).__name__
        if not self.default_box:
            raise ValueError(
                f"{name} has no default box: give the grid's axes (lo, hi, n per coordinate)"
            )
        counts = np.atleast_1d(n).tolist()
        if len(counts) == 1:
            counts = counts * len(self.default_box)
        if len(counts) != len(self.default_box):
            raise ValueError(
                f"n must be one node count or {len(self.default_box)} (one per state "
                f"coordinate of {name}), got {len(counts)}"
            )
        names = self.state_names or (None,) * len(counts)
        return Grid(
            [
                Axis(-math.pi, math.pi, k, periodic=True, name=label)
                if box is None
                else Axis(box[0], box[1], k, name=label)
                for box, k, label in zip(self.default_box, counts, names)
            ]
        )

    def drift(self, x) -> np.ndarray:
        """Passive dynamics a(x), shape ``(N, d)`` for states ``(N, d)``."""
        raise NotImplementedError

    def input_matrix(self, x) -> np.ndarray:
        """Control matrix B(x), shape ``(N, d, m)`` for states ``(N, d)``."""
        raise NotImplementedError

    def dynamics(self, x, u) -> np.ndarray:
        """Deterministic velocity a(x) + B(x) u for states ``(N, d)`` and controls ``(N, m)``."""
        x = self._states(x)
        u = np.asarray(u, dtype=float).reshape(x.shape[0], self.control_dim)
        return self.drift(x) + np.einsum("ndm,nm->nd", self.input_matrix(x), u)

    def linear_matrices(self) -> tuple[np.ndarray, np.ndarray] | None:
        """``(A, B)`` when a(x) = A x and B is constant, else ``None`` (the default)."""
        return None

    def parameters(self) -> dict:
        """Constructor arguments, for saving and describing a system."""
        return {}

    def _states(self, x) -> np.ndarray:
        """Validate and return states as a float ``(N, d)`` array."""
        arr = np.asarray(x, dtype=float)
        if arr.ndim == 1:
            arr = arr[None, :]
        if arr.ndim != 2 or arr.shape[1] != self.state_dim:
            raise ValueError(
                f"{type(self).__name__} states must have shape (N, {self.state_dim}), "
                f"got shape {np.shape(x)}"
            )
        return arr

    def __repr__(self):
        args = ", ".join(f"{k}={v!r}" for k, v in self.parameters().items())
        return f"{type(self).__name__}({args})"

    def __eq__(self, other):
        return type(self) is type(other) and self.parameters() == other.parameters()

    def __hash__(self):
        return hash((type(self).__name__, tuple(sorted(self.parameters().items()))))


class LinearSystem(ControlAffineSystem):
    """dx = (A x + B u) dt + noise, with constant A (d×d) and B (d×m).

    Parameters
    ----------
    A : array_like (d, d)
        The drift matrix.
    B : array_like (d, m) or (d,)
        The input matrix (a vector for one control).
    state_names : sequence of str, optional
        Names of the d coordinates (default ``x0, x1, ...``).
    """

    def __init__(self, A, B, state_names=None):
        A = np.atleast_2d(np.asarray(A, dtype=float))
        B = np.asarray(B, dtype=float)
        if B.ndim == 1:
            B = B[:, None]
        d = A.shape[0]
        if A.shape != (d, d):
            raise ValueError(f"A must be square, got shape {A.shape}")
        if B.ndim != 2 or B.shape[0] != d:
            raise ValueError(f"B must have shape ({d}, m) to match A, got shape {B.shape}")
        if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B))):
            raise ValueError("A and B must be finite")
        self.A, self.B = A, B
        self.state_dim, self.control_dim = d, B.shape[1]
        self.state_names = tuple(state_names) if state_names else tuple(f"x{k}" for k in range(d))

    def drift(self, x):
        return self._states(x) @ self.A.T

    def input_matrix(self, x):
        x = self._states(x)
        return np.broadcast_to(self.B, (x.shape[0], *self.B.shape))

    def linear_matrices(self):
        return self.A.copy(), self.B.copy()

    def parameters(self):
        return {"A": self.A.tolist(), "B": self.B.tolist()}
