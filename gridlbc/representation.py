"""How a :class:`gridlbc.Solution` holds its desirability, and how it is interpolated from there.

A solution keeps time slices of nodal data with one log-scale per slice. What the data *are*
depends on the solve (docs page ``schemes``: exponential fitting), and so does how they are
interpolated to a state x and a time t between two slices (barycentric in space, linear in
time). Three representations, each a type:

- :class:`LinearZ` (the plain operator): the slices hold z itself, interpolated linearly;
- :class:`RelativeZ` (fitted to a shared reference φ: :func:`gridlbc.solve_many`, an explicit
  ``fitting=``): the slices hold z, interpolated relative to log φ, which the representation
  keeps at the same times,

      z(x, t) = exp(I[log φ](x, t)) · I[y](x, t),     y = z/φ at the nodes;

- :class:`LogZ` (a solve fitted to its own terminal cost): the slices hold log z, interpolated
  linearly, z(x, t) = exp(I[log z](x, t)).

Every representation answers with the same :class:`Fields`, the one form that
:class:`gridlbc.Solution` evaluates value, desirability and policy from:

    z(x, t)  = exp(b + c) · y,
    Bᵀ∇z     = exp(b + c) · (y Bᵀ∇b + Bᵀ∇y),
    u*(x, t) = λ R⁻¹ Bᵀ∇z / z = λ R⁻¹ (Bᵀ∇b + Bᵀ∇y / y)        (docs page ``maths``),

with b(x, t) an interpolated log-factor (0 for :class:`LinearZ`, I[log φ] for
:class:`RelativeZ`, I[log z] for :class:`LogZ`), c a common log-scale and y an interpolant linear
in the nodal z (1 for :class:`LogZ`). For a fixed representation y and Bᵀ∇y are linear in the
stored z, so solutions that share one (the plain operator, or one φ) combine exactly
(paper §3, :func:`gridlbc.combine`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Protocol

import numpy as np

from .errors import GridlbcWarning, UnderflowWarning, warn_user
from .grid import Grid
from .interpolate import input_gradient, interpolate_slices


@dataclass(frozen=True, eq=False)
class Stencil:
    """Where and when a solution is evaluated: the Kuhn simplices of the states and the stored
    interval of the time.

    Parameters
    ----------
    grid : Grid
        The solution's grid.
    nodes, weights : ndarray (N, d+1)
        Flat node indices of each state's simplex and its barycentric weights
        (:func:`gridlbc.interpolate.barycentric`).
    slot : int
        The stored interval [t_j, t_{j+1}] of the time (j).
    theta : float
        The time's position in it, θ ∈ [0, 1].
    input_matrix : ndarray (N, d+1, d, m) or None
        B at the simplices' vertices; ``None`` when no gradient is wanted.
    steady : bool
        A stationary solution's stencil: one stored slice, no time (``slot`` 0, ``theta`` 0).
    """

    grid: Grid
    nodes: np.ndarray
    weights: np.ndarray
    slot: int
    theta: float
    input_matrix: np.ndarray | None = None
    steady: bool = False

    @property
    def time_weights(self) -> np.ndarray:
        """(1 − θ, θ), the weights of the two slices around the time ((1,) when steady)."""
        if self.steady:
            return np.ones(1)
        return np.array([1.0 - self.theta, self.theta])

    @property
    def gradient(self) -> bool:
        """Whether gradients are wanted (B at the vertices is known)."""
        return self.input_matrix is not None

    def pair(self, slices: np.ndarray) -> np.ndarray:
        """The two stored slices ``(2, size)`` around the time (a view, not a copy); the one
        slice ``(1, size)`` when steady."""
        return slices[self.slot : self.slot + (1 if self.steady else 2)]

    def interpolate(
        self,
        pair: np.ndarray,
        time_weights: np.ndarray,
        log_divisor: np.ndarray | None = None,
    ) -> np.ndarray:
        """Σ_s τ_s Σ_v w_v f_s(vertex v), ``(N,)``, of the nodal slices ``pair`` (of f /
        e^{log_divisor} when given; :func:`gridlbc.interpolate.interpolate_slices`)."""
        return interpolate_slices(pair, time_weights, self.nodes, self.weights, log_divisor)

    def input_gradient(
        self,
        pair: np.ndarray,
        time_weights: np.ndarray,
        log_divisor: np.ndarray | None = None,
    ) -> np.ndarray:
        """Bᵀ I[∇f], ``(N, m)``: ∇f by finite differences at the vertices (of f / e^{log_divisor}
        when given) along the axes that B drives, interpolated in space and with
        ``time_weights`` in time (:func:`gridlbc.interpolate.input_gradient`)."""
        B = self.input_matrix
        assert B is not None, "build the stencil with gradient=True"
        return input_gradient(
            self.grid, pair, time_weights, self.nodes, self.weights, B, log_divisor
        )


@dataclass(frozen=True, eq=False)
class Fields:
    """Interpolated fields at N states: z = exp(b + c) · y and Bᵀ∇z = exp(b + c) ·
    (y Bᵀ∇b + Bᵀ∇y) (the module docstring).

    Parameters
    ----------
    log_base : ndarray (N,) or None
        b, an interpolated log-factor (``None``: 0).
    log_offset : float
        c, a log-scale common to the states.
    linear : ndarray (N,) or None
        y ≥ 0, linear in the nodal z (``None``: 1).
    base_gradient, linear_gradient : ndarray (N, m) or None
        Bᵀ∇b and Bᵀ∇y (``None``: zero, or not asked for).
    """

    log_base: np.ndarray | None
    log_offset: float
    linear: np.ndarray | None
    base_gradient: np.ndarray | None = None
    linear_gradient: np.ndarray | None = None

    def log_desirability(self) -> np.ndarray:
        """log z, ``(N,)``: −inf, with an :class:`~gridlbc.UnderflowWarning`, where y underflowed."""
        if self.linear is None:
            assert self.log_base is not None
            return self.log_base + self.log_offset
        log_y = log_checked(self.linear)
        if self.log_base is None:
            return log_y + self.log_offset
        return self.log_base + self.log_offset + log_y

    def scaled(self) -> tuple[float, np.ndarray, np.ndarray | None]:
        """``(L, z, g)`` with z(x, t) = z · e^L ``(N,)`` and Bᵀ∇z = g · e^L ``(N, m)`` (``None``
        without gradients): the form in which solutions add up (:func:`gridlbc.combine`)."""
        if self.log_base is None:
            assert self.linear is not None
            return self.log_offset, self.linear, self.linear_gradient
        top = float(self.log_base.max())
        with np.errstate(under="ignore"):
            base = np.exp(self.log_base - top)
        gb = self.base_gradient
        if self.linear is None:
            return top + self.log_offset, base, None if gb is None else gb * base[:, None]
        z = base * self.linear
        g = None if gb is None else base[:, None] * self.numerator()
        return top + self.log_offset, z, g

    def numerator(self) -> np.ndarray:
        """y Bᵀ∇b + Bᵀ∇y, ``(N, m)``: Bᵀ∇z / exp(b + c)."""
        if self.base_gradient is None:
            assert self.linear_gradient is not None, "evaluate the fields with gradient=True"
            return self.linear_gradient
        if self.linear is None:
            return self.base_gradient
        assert self.linear_gradient is not None
        return self.base_gradient * self.linear[:, None] + self.linear_gradient

    def ended(self, inside: np.ndarray, log_z: np.ndarray) -> Fields:
        """These fields with log z = ``log_z`` ``(n,)`` and no gradient at the states ``inside``
        (a boolean mask with n True entries): where the task has ended on entering its exit set
        E, z = exp(−g_E/λ) exactly and u = 0 (:meth:`gridlbc.Solution.fields`)."""
        log_base = None if self.log_base is None else self.log_base.copy()
        linear = None if self.linear is None else self.linear.copy()
        if log_base is None:
            assert linear is not None
            with np.errstate(under="ignore", over="ignore"):
                linear[inside] = np.exp(log_z - self.log_offset)
        else:
            log_base[inside] = log_z - self.log_offset
            if linear is not None:
                linear[inside] = 1.0
        gradients = [
            None if g is None else g.copy() for g in (self.base_gradient, self.linear_gradient)
        ]
        for g in gradients:
            if g is not None:
                g[inside] = 0.0
        return Fields(log_base, self.log_offset, linear, *gradients)

    def policy(self, temperature: float, R_inv: np.ndarray) -> np.ndarray:
        """u* = λ R⁻¹ (y Bᵀ∇b + Bᵀ∇y) / y, ``(N, m)``: NaN, with an
        :class:`~gridlbc.UnderflowWarning`, where y underflowed."""
        if self.linear is None:
            assert self.base_gradient is not None, "evaluate the fields with gradient=True"
            return temperature * (self.base_gradient @ R_inv.T)
        return policy_from_fields(temperature, R_inv, self.linear, self.numerator())


class Representation(Protocol):
    """What a solution's stored slices are and how they are interpolated (module docstring)."""

    name: ClassVar[str]

    def fields(self, stencil: Stencil, slices: np.ndarray, log_scales: np.ndarray) -> Fields:
        """The :class:`Fields` of stored ``slices`` ``(S, size)`` with ``log_scales`` ``(S,)``
        at the stencil's states and time."""
        ...

    def log_nodes(self, stored: np.ndarray, log_scale: float) -> np.ndarray:
        """log z at every node of one stored slice with its log-scale (−inf where z is 0)."""
        ...


@dataclass(frozen=True)
class LinearZ:
    """The slices hold z/e^ℓ (max 1 per slice), interpolated linearly in space and time: the plain
    operator's solutions, linear in their terminal data on and off the grid."""

    name: ClassVar[str] = "linear"

    def fields(self, stencil: Stencil, slices: np.ndarray, log_scales: np.ndarray) -> Fields:
        """y = I[z] e^{−L}, Bᵀ∇y = Bᵀ I[∇z] e^{−L}, L the larger of the two slices' scales."""
        scales = stencil.pair(log_scales)
        top = float(scales.max())
        weights = stencil.time_weights * np.exp(scales - top)
        pair = stencil.pair(slices)
        z = stencil.interpolate(pair, weights)
        g = stencil.input_gradient(pair, weights) if stencil.gradient else None
        return Fields(None, top, z, None, g)

    def log_nodes(self, stored: np.ndarray, log_scale: float) -> np.ndarray:
        """log z = log Z + ℓ (−inf where Z is 0, or below it by the rounding of a linear solve:
        the implicit march's z far below its largest value, stranger round 44, where a NaN
        value and numpy's invalid-value warning came out)."""
        with np.errstate(divide="ignore"):
            return np.log(np.maximum(stored.astype(float), 0.0)) + log_scale


@dataclass(frozen=True, eq=False)
class RelativeZ:
    """The slices hold z/e^ℓ, interpolated relative to the fitting reference φ of the operator:
    z = exp(I[log φ]) · I[z/φ] (module docstring). Exact wherever z ∝ φ with log-affine φ, and
    y = z/φ varies far more slowly than z. Solutions solved together share one instance.

    Parameters
    ----------
    log_slices : ndarray (S, size)
        log φ at the nodes and stored times, relative to its maximum per slice (floored where φ
        underflowed).
    log_scales : ndarray (S,)
        Their log-scales: log φ(x_node, t_j) = ``log_slices[j, node] + log_scales[j]``.
    """

    log_slices: np.ndarray
    log_scales: np.ndarray
    name: ClassVar[str] = "relative"

    def fields(self, stencil: Stencil, slices: np.ndarray, log_scales: np.ndarray) -> Fields:
        """b = I[log φ], c the larger of the two slices' log(scale of z / scale of φ), y =
        I[z/φ] e^{−c}, and their gradients (y's from differences of z/φ at the nodes)."""
        weights = stencil.time_weights
        offsets = stencil.pair(log_scales) - stencil.pair(self.log_scales)
        top = float(offsets.max())
        relative = weights * np.exp(offsets - top)  # the time weights of y, relative to e^top
        Z, R = stencil.pair(slices), stencil.pair(self.log_slices)
        ell = stencil.interpolate(R, weights) + weights @ stencil.pair(self.log_scales)
        y = stencil.interpolate(Z, relative, log_divisor=R)
        if not stencil.gradient:
            return Fields(ell, top, y)
        g_ell = stencil.input_gradient(R, weights)
        g_y = stencil.input_gradient(Z, relative, log_divisor=R)
        return Fields(ell, top, y, g_ell, g_y)

    def log_nodes(self, stored: np.ndarray, log_scale: float) -> np.ndarray:
        """log z = log Z + ℓ (−inf where Z is 0): the slices hold z, as :class:`LinearZ`'s."""
        return LinearZ().log_nodes(stored, log_scale)


@dataclass(frozen=True)
class LogZ:
    """The slices hold log z − ℓ (max 0 per slice), interpolated linearly: v = −λ log z is then
    piecewise linear, and nothing underflows however large v/λ grows. A solve fitted to its own
    terminal cost (its operator depends on that cost, so it is not linear in it anyway)."""

    name: ClassVar[str] = "log"

    def fields(self, stencil: Stencil, slices: np.ndarray, log_scales: np.ndarray) -> Fields:
        """b = I[log z] (with the scales), y = 1, and Bᵀ∇b = Bᵀ I[∇ log z]."""
        weights = stencil.time_weights
        pair = stencil.pair(slices)
        ell = stencil.interpolate(pair, weights) + weights @ stencil.pair(log_scales)
        g = stencil.input_gradient(pair, weights) if stencil.gradient else None
        return Fields(ell, 0.0, None, g)

    def log_nodes(self, stored: np.ndarray, log_scale: float) -> np.ndarray:
        """log z = the stored value + ℓ."""
        return stored.astype(float) + log_scale


REPRESENTATIONS: dict[str, type] = {"linear": LinearZ, "relative": RelativeZ, "log": LogZ}
"""The representations by :attr:`name` (how :func:`gridlbc.save` records them)."""


def warn_underflow(bad: np.ndarray) -> None:
    """Raise an :class:`~gridlbc.UnderflowWarning` if any query state's desirability underflowed.

    Parameters
    ----------
    bad : ndarray of bool
        Where it underflowed.
    """
    if np.any(bad):
        warn_user(
            f"desirability underflowed at {int(bad.sum())} of {bad.size} query states: value is "
            "+inf there and the policy undefined (NaN). Shrink the box, or raise the temperature "
            "relative to the costs (docs page 'limitations'); for a first exit, the solve's "
            "warning says where the exit set cannot be reached at all (there no setting helps).",
            UnderflowWarning,
        )


def not_positive(z: np.ndarray) -> np.ndarray:
    """Where the desirability ``z`` (up to a positive factor) is not positive, with a warning
    that says why: zero, where it underflowed (:func:`warn_underflow`), or negative, which only
    a combination with negative weights can be (a :class:`~gridlbc.GridlbcWarning`: no grid or
    temperature makes it a desirability there).

    Parameters
    ----------
    z : ndarray
        Desirabilities.
    """
    negative = z < 0
    bad = ~(z > 0)
    warn_underflow(bad & ~negative)
    if np.any(negative):
        warn_user(
            f"Σ w_i z_i < 0 at {int(negative.sum())} of {negative.size} query states: the "
            "negative weights outweigh the positive ones there, so the combination is no "
            "desirability (value +inf, policy and blend weights undefined, NaN). A combination "
            "with negative weights holds only where Σ w_i z_i stays positive: read it there, or "
            "use weights that keep it so (gridlbc.project warns when its weights do not)",
            GridlbcWarning,
        )
    return bad


def log_checked(z: np.ndarray) -> np.ndarray:
    """log z, −inf (with a warning, :func:`not_positive`) where z is not positive.

    Parameters
    ----------
    z : ndarray
        Desirabilities.
    """
    bad = not_positive(z)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(bad, -np.inf, np.log(np.where(bad, 1.0, z)))


def policy_from_fields(
    temperature: float, R_inv: np.ndarray, z: np.ndarray, g: np.ndarray
) -> np.ndarray:
    """u = λ R⁻¹ g / z for interpolated z ``(N,)`` and Bᵀ∇z ``(N, m)`` sharing one scale.

    Parameters
    ----------
    temperature : float
        λ.
    R_inv : ndarray (m, m)
        R⁻¹.
    z : ndarray (N,)
        The desirability, up to a common factor.
    g : ndarray (N, m)
        Bᵀ∇z, up to the same factor.
    """
    bad = not_positive(z)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = temperature * (g @ R_inv.T) / z[:, None]
    u[bad] = np.nan
    return u
