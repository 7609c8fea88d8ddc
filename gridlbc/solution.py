"""Solved desirability on a grid, evaluated anywhere in state and time.

A :class:`Solution` stores time slices of the desirability in log-scaled form,

    z(x_node, t_j) = Z[j, node] · exp(ℓ_j),      max_node Z[j] = 1,

so that z may span far more than float64's range without underflowing as a whole. At any state x
and time t ∈ [t_j, t_{j+1}] (θ = (t − t_j)/(t_{j+1} − t_j)):

    z(x, t)      = (1 − θ) I[z_j](x) + θ I[z_{j+1}](x)          (I: barycentric interpolation)
    v(x, t)      = −λ log z(x, t)
    u*(x, t)     = λ R⁻¹ I[Bᵀ∇z](x, t) / z(x, t)

with ∇z by finite differences at the simplex vertices. All three interpolants are linear in the
nodal z, so combinations of solutions evaluate exactly as the solution of the combined problem.

Linear interpolation of z is poor where v/λ changes by more than about one per cell: there z
varies by a large factor across a cell, and the central difference of z overstates ∇z/z by
sinh(Δ)/Δ for a rise Δ of v/λ per cell (a factor of 3 at Δ = 3, and far more beyond). The
fitted solvers therefore interpolate as their fitted step does:

- A solve fitted to its own terminal cost is not linear in its terminal data anyway (its
  operator is built from it); it stores log z (``diagnostics.interpolation == "log"``) and
  interpolates that, v(x, t) = −λ Σ w I[log z], u* = λ R⁻¹ Bᵀ I[∇ log z].
- Solutions fitted to a shared reference φ (:func:`gridlbc.solve_many`, an explicit
  ``fitting=``) keep log φ at the stored times (:class:`FittingReference`,
  ``interpolation == "fitted"``) and interpolate relative to it:

      z(x, t) = exp(I[log φ](x, t)) · I[y](x, t),     y = z/φ at the nodes,
      Bᵀ∇z    = z · Bᵀ I[∇ log φ] + exp(I[log φ]) · Bᵀ I[∇y],

  both linear in time between slices. For the fixed φ these are linear in the nodal z, so
  solutions sharing φ still combine exactly as the solution of the combined problem; they are
  exact wherever z ∝ φ with log-affine φ, and y = z/φ varies far more slowly than z.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from .errors import UnderflowWarning
from .interpolate import barycentric, node_gradient
from .problem import Problem


@dataclass(frozen=True)
class SolveDiagnostics:
    """What a solve did and cost.

    Attributes
    ----------
    method : str
        The scheme (:data:`gridlbc.METHODS`).
    dt : float
        The time step.
    steps : int
        How many steps.
    store_every : int
        Every k-th step's slice is kept.
    wall_time, setup_time : float
        Seconds in total and building the step operator.
    underflow_nodes : int
        Nodes whose desirability is zero at t = 0 (value +inf there).
    stored_bytes, operator_bytes : int
        Bytes of the kept slices and of the step operator.
    courant : float
        max_k max|a_k| Δt / h_k.
    iterations : tuple of int
        Per-step iteration counts of an iterative solve (empty for direct and splitting steps).
    flushed_values : int
        Stored values that were positive in the float64 time stepping but rounded to zero by
        float32 storage (far below their slice's maximum; value +inf there).
    memory_estimate : int
        The bytes the solve was estimated to need (checked before allocating).
    fitting : str
        ``"none"``, or a fingerprint of the reference the drift was fitted to (solutions
        combine exactly only when it matches).
    interpolation : str
        ``"linear"`` (the slices hold scaled z, interpolated linearly), ``"fitted"`` (scaled z
        too, interpolated relative to the operator's reference φ, :attr:`Solution.reference`)
        or ``"log"`` (a solve fitted to its own terminal cost: the slices hold log z relative to
        its maximum, and v = −λ log z is interpolated linearly).
    """

    method: str
    dt: float
    steps: int
    store_every: int
    wall_time: float
    setup_time: float
    underflow_nodes: int
    stored_bytes: int
    operator_bytes: int
    courant: float
    iterations: tuple[int, ...] = ()
    flushed_values: int = 0
    memory_estimate: int = 0
    fitting: str = "none"
    interpolation: str = "linear"


def check_time(t, horizon: float) -> float:
    """``t`` as a float in [0, T] (rounding-level excursions clipped); a clear error otherwise."""
    try:
        t = float(t)
    except (TypeError, ValueError):
        raise TypeError(f"t must be a single time (float), got {t!r}") from None
    tol = 1e-9 * horizon
    if not (np.isfinite(t) and -tol <= t <= horizon + tol):
        raise ValueError(f"t must lie in [0, T] = [0, {horizon:g}], got {t!r}")
    return min(max(t, 0.0), horizon)


def bracket(times: np.ndarray, t: float) -> tuple[int, float]:
    """The stored interval of ``t``: j and θ ∈ [0, 1] with t = (1 − θ) times[j] + θ times[j+1]."""
    j = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    theta = (t - times[j]) / (times[j + 1] - times[j])
    return j, float(np.clip(theta, 0.0, 1.0))


class FieldEvaluation:
    """Value, desirability and policy anywhere from the interpolated fields (L, z, Bᵀ∇z) of
    :meth:`scaled_fields`, with z(x, t) = z · e^L: the evaluation that :class:`Solution` and
    :class:`gridlbc.CombinedSolution` share. Subclasses provide ``problem`` and
    ``scaled_fields(x, t, gradient)``; both are linear in z, so the combination's evaluation is
    exactly the composite solution's."""

    @property
    def temperature(self) -> float:
        return self.problem.temperature

    def log_desirability(self, x, t) -> np.ndarray:
        """log z(x, t), shape ``(N,)`` (−inf where z underflowed, with an UnderflowWarning)."""
        L, z, _ = self.scaled_fields(x, t, gradient=False)
        return _log_checked(z) + L

    def desirability(self, x, t) -> np.ndarray:
        """z(x, t) = exp(−v/λ), shape ``(N,)``. May underflow to 0 far from the goal: use
        :meth:`log_desirability` or :meth:`value` for the full range."""
        L, z, _ = self.scaled_fields(x, t, gradient=False)
        with np.errstate(under="ignore", over="ignore"):
            return z * np.exp(L)

    def value(self, x, t) -> np.ndarray:
        """Optimal cost-to-go v(x, t) = −λ log z(x, t), shape ``(N,)``."""
        return -self.temperature * self.log_desirability(x, t)

    def policy(self, x, t) -> np.ndarray:
        """Optimal control u*(x, t) = λ R⁻¹ Bᵀ∇z / z = −R⁻¹ Bᵀ∇v, shape ``(N, m)``."""
        _L, z, g = self.scaled_fields(x, t)
        return policy_from_fields(self.problem, z, g)


@dataclass(frozen=True, eq=False)
class FittingReference:
    """log φ of a fitted operator's reference at a solution's stored times: log φ(x_node, t_j) =
    ``log_slices[j, node]`` + ``log_scales[j]`` (max 0 per slice). Solutions solved together
    share one instance; their evaluation is relative to it (the module docstring)."""

    log_slices: np.ndarray
    log_scales: np.ndarray


@dataclass(frozen=True, eq=False)
class Solution(FieldEvaluation):
    """The solved desirability of a :class:`gridlbc.Problem` (one terminal cost).

    Attributes
    ----------
    problem : Problem
    times : ndarray (S,)
        Times of the stored slices, increasing from 0 to T.
    slices : ndarray (S, N)
        Scaled nodal desirability Z (max 1 per slice), float64 or float32.
    log_scales : ndarray (S,)
        ℓ_j, so that z = Z · exp(ℓ_j).
    diagnostics : SolveDiagnostics
    reference : FittingReference or None
        log φ of the fitted operator's reference at the same times, for ``interpolation ==
        "fitted"`` (None otherwise).
    embedded : Solution or None
        The same problem solved on the embedded grid (every other node) with step 2Δt, from
        which :meth:`error_estimate` reads (None if not solved: ``error_estimate=False``, or a
        grid too coarse to embed).
    estimate_order : float
        The order p in the Richardson estimate ``abs(v_2h − v_h) / (2^p − 1)`` (observed from a third
        solve at 4h, in [1, 2]: :func:`gridlbc.accuracy.observed_order`).
    estimate_floor : float
        The least error the estimate reports (:func:`gridlbc.accuracy.estimate_floor`).
    refinement : tuple of gridlbc.accuracy.Refinement
        With ``solve(tol=...)``: the solves that led to this one (empty otherwise).
    """

    problem: Problem
    times: np.ndarray
    slices: np.ndarray
    log_scales: np.ndarray
    diagnostics: SolveDiagnostics
    reference: FittingReference | None = None
    _B_cache: dict = field(default_factory=dict, repr=False, compare=False)
    embedded: Solution | None = field(default=None, repr=False, compare=False)
    estimate_order: float = field(default=1.0, repr=False, compare=False)
    estimate_floor: float = field(default=0.0, repr=False, compare=False)
    refinement: tuple = field(default=(), repr=False, compare=False)

    @property
    def grid(self):
        return self.problem.grid

    @property
    def nbytes(self) -> int:
        """Bytes held by the stored slices and their scales."""
        return int(self.slices.nbytes + self.log_scales.nbytes + self.times.nbytes)

    def error_estimate(self, x, t=0.0, local: bool = False) -> np.ndarray:
        """An a-posteriori estimate of ``abs(v(x, t) − v_exact(x, t))`` (SPEC §10, docs page
        :doc:`accuracy`): ``abs(v_2h(x, t) − v(x, t)) / (2^p − 1)``, the Richardson estimate from the embedded solve with the observed order p, and at least
        :attr:`estimate_floor` (:mod:`gridlbc.accuracy`).

        Parameters
        ----------
        x : array_like (N, d) or (d,)
            States.
        t : float
            Time in [0, T].
        local : bool
            Leave out the floor (the local Richardson difference only).

        Returns
        -------
        ndarray (N,)
            The estimated absolute error of :meth:`value` at each state.
        """
        if self.embedded is None:
            raise ValueError(
                "this solution carries no error estimate: it was solved with "
                "error_estimate=False or on a grid too coarse to embed (fewer than 5 nodes on "
                "an axis); solve again with the default settings"
            )
        difference = np.abs(self.embedded.value(x, t) - self.value(x, t))
        estimate = difference / (2.0**self.estimate_order - 1.0)
        return estimate if local else np.maximum(estimate, self.estimate_floor)

    # -- nodal access ---------------------------------------------------------------------------

    def log_desirability_nodes(self, j: int = 0) -> np.ndarray:
        """log z at every node of stored slice ``j`` (−inf where it underflowed), shape ``(N,)``."""
        if self.diagnostics.interpolation == "log":
            return self.slices[j].astype(float) + self.log_scales[j]
        with np.errstate(divide="ignore"):
            return np.log(self.slices[j].astype(float)) + self.log_scales[j]

    def value_nodes(self, j: int = 0) -> np.ndarray:
        """v = −λ log z at every node of stored slice ``j`` (+inf where z underflowed)."""
        return -self.temperature * self.log_desirability_nodes(j)

    # -- evaluation anywhere --------------------------------------------------------------------

    def _check_time(self, t) -> float:
        return check_time(t, self.problem.horizon)

    def _bracket(self, t: float) -> tuple[int, float]:
        return bracket(self.times, t)

    def _time_weights(self, t) -> tuple[list[int], np.ndarray, float]:
        """Slices, their weights (1−θ)·e^{ℓ−L}, θ·e^{ℓ−L}, and the common log-scale L."""
        j, theta = self._bracket(self._check_time(t))
        js = [j, j + 1]
        scales = self.log_scales[js]
        L = float(scales.max())
        w = np.array([1.0 - theta, theta]) * np.exp(scales - L)
        return js, w, L

    def _input_matrix_at(self, nodes: np.ndarray) -> np.ndarray:
        system = self.problem.system
        if system.linear_matrices() is not None:  # constant B: evaluate once
            B = self._B_cache.get("constant")
            if B is None:
                B = np.asarray(system.input_matrix(self.grid.nodes()[:1]), dtype=float)[0]
                self._B_cache["constant"] = B
            return np.broadcast_to(B, nodes.shape + B.shape)
        coords = self.grid.node_coordinates(nodes.ravel())
        B = np.asarray(system.input_matrix(coords), dtype=float)
        return B.reshape(nodes.shape + B.shape[1:])

    def scaled_fields(self, x, t, gradient: bool = True):
        """Interpolated z and Bᵀ∇z at states ``x``, time ``t``, up to a common factor e^L.

        Returns ``(L, z, g)`` with z(x, t) = z · e^L of shape ``(N,)`` and Bᵀ∇z(x, t) = g · e^L of
        shape ``(N, m)`` (``g`` is ``None`` when ``gradient`` is false). The building block of
        every evaluation here and of :func:`gridlbc.combine`.
        """
        if self.diagnostics.interpolation == "log":
            ell, g = self._log_fields(x, t, gradient)
            L = float(ell.max())
            with np.errstate(under="ignore"):
                z = np.exp(ell - L)
            return L, z, None if g is None else g * z[:, None]
        if self.reference is not None:
            ell, y, C, g_ell, g_y = self._fitted_fields(x, t, gradient)
            top = float(ell.max())
            with np.errstate(under="ignore"):
                phi = np.exp(ell - top)
            z = phi * y
            g = None if g_ell is None else phi[:, None] * (g_ell * y[:, None] + g_y)
            return top + C, z, g
        grid = self.grid
        x = grid.check_states(x)
        js, tw, L = self._time_weights(t)
        idx, bw = barycentric(grid, x)
        Z = self.slices[js[0] : js[0] + 2]  # (2, N), a view: no copy of the stored slices
        z = np.einsum("s,snv,nv->n", tw, Z[:, idx], bw)
        if not gradient:
            return L, z, None
        B = self._input_matrix_at(idx)  # (N, d+1, d, m)
        g = np.zeros((x.shape[0], self.problem.system.control_dim))
        for k in np.flatnonzero(np.any(B != 0, axis=(0, 1, 3))):
            dz = node_gradient(grid, Z, idx.ravel(), k).reshape((2, *idx.shape))
            dz = np.einsum("s,snv->nv", tw, dz)  # ∂_k z at the vertices, time-interpolated
            g += np.einsum("nv,nvm,nv->nm", bw, B[:, :, k, :], dz)
        return L, z, g

    def _log_fields(self, x, t, gradient: bool):
        """For ``interpolation="log"``: the interpolated ℓ = log z ``(N,)`` and Bᵀ∇ℓ ``(N, m)``
        (``None`` without ``gradient``), linear in the nodal log z in space and in time."""
        grid = self.grid
        x = grid.check_states(x)
        j, theta = self._bracket(self._check_time(t))
        tw = np.array([1.0 - theta, theta])
        idx, bw = barycentric(grid, x)
        S = self.slices[j : j + 2]
        ell = np.einsum("s,snv,nv->n", tw, S[:, idx], bw) + tw @ self.log_scales[j : j + 2]
        if not gradient:
            return ell, None
        B = self._input_matrix_at(idx)
        g = np.zeros((x.shape[0], self.problem.system.control_dim))
        for k in np.flatnonzero(np.any(B != 0, axis=(0, 1, 3))):
            dl = node_gradient(grid, S, idx.ravel(), k).reshape((2, *idx.shape))
            g += np.einsum("nv,nvm,nv->nm", bw, B[:, :, k, :], np.einsum("s,snv->nv", tw, dl))
        return ell, g

    def _fitted_fields(self, x, t, gradient: bool):
        """For a reference (``interpolation="fitted"``): I[log φ] ``(N,)``, I[y] ``(N,)`` up to
        the factor e^C, C, and Bᵀ I[∇ log φ], Bᵀ I[∇y] ``(N, m)`` (``None`` without
        ``gradient``), all linear in time between the two slices around t, y = z/φ linear in
        the nodal z (the module docstring)."""
        grid = self.grid
        x = grid.check_states(x)
        j, theta = self._bracket(self._check_time(t))
        ref = self.reference
        tw = np.array([1.0 - theta, theta])
        offsets = self.log_scales[j : j + 2] - ref.log_scales[j : j + 2]  # log of z's scale / φ's
        C = float(offsets.max())
        ty = tw * np.exp(offsets - C)  # the time weights of y, relative to e^C
        idx, bw = barycentric(grid, x)
        Z, R = self.slices[j : j + 2], ref.log_slices[j : j + 2]
        ell = np.einsum("s,snv,nv->n", tw, R[:, idx], bw) + tw @ ref.log_scales[j : j + 2]
        Zv, Rv = Z[:, idx].astype(float), R[:, idx].astype(float)
        with np.errstate(divide="ignore", under="ignore"):
            yv = np.where(Zv > 0, np.exp(np.log(np.where(Zv > 0, Zv, 1.0)) - Rv), 0.0)
        y = np.einsum("s,snv,nv->n", ty, yv, bw)
        if not gradient:
            return ell, y, C, None, None
        B = self._input_matrix_at(idx)
        shape = (x.shape[0], self.problem.system.control_dim)
        g_ell, g_y = np.zeros(shape), np.zeros(shape)
        for k in np.flatnonzero(np.any(B != 0, axis=(0, 1, 3))):
            d_ell = node_gradient(grid, R, idx.ravel(), k).reshape((2, *idx.shape))
            d_y = node_gradient(grid, Z, idx.ravel(), k, log_divisor=R).reshape((2, *idx.shape))
            Bk = B[:, :, k, :]
            g_ell += np.einsum("nv,nvm,nv->nm", bw, Bk, np.einsum("s,snv->nv", tw, d_ell))
            g_y += np.einsum("nv,nvm,nv->nm", bw, Bk, np.einsum("s,snv->nv", ty, d_y))
        return ell, y, C, g_ell, g_y

    def log_desirability(self, x, t) -> np.ndarray:
        """log z(x, t), shape ``(N,)`` (−inf where z underflowed, with an UnderflowWarning)."""
        if self.diagnostics.interpolation == "log":
            return self._log_fields(x, t, gradient=False)[0]
        if self.reference is not None:
            ell, y, C, _, _ = self._fitted_fields(x, t, gradient=False)
            return ell + C + _log_checked(y)
        return super().log_desirability(x, t)

    def policy(self, x, t) -> np.ndarray:
        """Optimal control u*(x, t) = λ R⁻¹ Bᵀ∇z / z = −R⁻¹ Bᵀ∇v, shape ``(N, m)``."""
        if self.diagnostics.interpolation == "log":
            _, g = self._log_fields(x, t, gradient=True)
            return self.temperature * (g @ self.problem.R_inv.T)
        if self.reference is not None:  # u = λ R⁻¹ Bᵀ (∇ log φ + ∇y / y)
            _, y, _, g_ell, g_y = self._fitted_fields(x, t, gradient=True)
            return policy_from_fields(self.problem, y, g_ell * y[:, None] + g_y)
        return super().policy(x, t)


def warn_underflow(bad: np.ndarray) -> None:
    """Raise an :class:`UnderflowWarning` if any query state's desirability underflowed."""
    if np.any(bad):
        warnings.warn(
            f"desirability underflowed at {int(bad.sum())} of {bad.size} query states: value is "
            "+inf there and the policy undefined (NaN). Shrink the box, or raise the temperature "
            "relative to the costs (docs page 'limitations').",
            UnderflowWarning,
            stacklevel=4,
        )


def _log_checked(z: np.ndarray) -> np.ndarray:
    """log z, −inf (with a warning) where z underflowed to zero."""
    bad = ~(z > 0)
    warn_underflow(bad)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(bad, -np.inf, np.log(np.where(bad, 1.0, z)))


def policy_from_fields(problem: Problem, z: np.ndarray, g: np.ndarray) -> np.ndarray:
    """u = λ R⁻¹ g / z for interpolated z ``(N,)`` and Bᵀ∇z ``(N, m)`` sharing one scale."""
    bad = ~(z > 0)
    warn_underflow(bad)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = problem.temperature * (g @ problem.R_inv.T) / z[:, None]
    u[bad] = np.nan
    return u
