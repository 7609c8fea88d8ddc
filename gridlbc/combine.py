"""Linear Bellman combination of solved controllers (paper §3–4).

Desirabilities z_i of one linear PDE (same dynamics a, B, state cost q, control cost R,
temperature λ and horizon T) for terminal rewards h_i = exp(−g_i/λ) superpose: for fixed weights
w_i,

    z = Σ w_i z_i   solves the same PDE with   h = Σ w_i h_i,  i.e.  g = −λ log Σ w_i exp(−g_i/λ),

and its optimal policy is the state- and time-dependent blend of the component policies

    u(x, t) = Σ α_i(x, t) u_i(x, t),      α_i = w_i z_i / Σ_j w_j z_j          (paper eq. 1, 11).

With w_i = 1 the combination *coordinates* (several acceptable outcomes); with w from
:func:`gridlbc.project` it *interpolates* goals. Since the grid solver is linear in the terminal
data, :func:`combine` equals the direct solve of the composite cost to rounding.

Each component stores z_i = Z_i e^{ℓ_i} with its own log-scale per slice. The combination works
with the common scale L = max_i L_i(t),

    z e^{−L} = Σ w_i z̃_i e^{L_i − L},

so components whose scales differ by e^{±700} (1e±300) combine without overflow: the smaller ones
contribute what they contribute in float64, and no more.

:func:`naive_blend` is the baseline the paper beats: u = Σ w_i u_i / Σ w_i with the weights fixed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .problem import Problem
from .solution import Solution, warn_underflow


def check_weights(weights, n: int) -> np.ndarray:
    """Validate fixed blend weights: ``None`` → all ones (coordination), else ``n`` finite numbers
    with a positive sum (single weights may be negative, as projection can give)."""
    if weights is None:
        return np.ones(n)
    w = np.asarray(weights, dtype=float)
    if w.ndim != 1 or w.size != n:
        raise ValueError(
            f"weights must be {n} numbers, one per component, got shape {np.shape(weights)}"
        )
    if not np.all(np.isfinite(w)):
        raise ValueError(f"weights must be finite, got {w.tolist()}")
    if not np.any(w != 0):
        raise ValueError("weights are all zero: the combined desirability would vanish everywhere")
    if not w.sum() > 0:
        raise ValueError(
            f"weights sum to {w.sum():g} ≤ 0: the combined desirability Σ w_i z_i must be "
            "positive; flip the signs or use weights=None (coordination, all ones)"
        )
    return w


def _same_cost(a, b, grid) -> bool:
    """Whether two costs agree at every grid node (the discrete problem only sees node values)."""
    if a is b:
        return True
    if a is None or b is None:
        return False
    nodes = grid.nodes()
    return bool(np.array_equal(np.asarray(a(nodes), float), np.asarray(b(nodes), float)))


def _check_components(solutions) -> tuple[Solution, ...]:
    solutions = tuple(solutions)
    if not solutions:
        raise ValueError("solutions is empty: give at least one gridlbc.Solution to combine")
    for i, s in enumerate(solutions):
        if not isinstance(s, Solution):
            raise TypeError(f"solutions[{i}] must be a gridlbc.Solution, got {type(s).__name__}")
    ref = solutions[0]
    p0 = ref.problem
    for i, s in enumerate(solutions[1:], start=1):
        p = s.problem
        differs = []
        if p.system != p0.system:
            differs.append(f"system ({p0.system!r} vs {p.system!r})")
        if p.grid != p0.grid:
            differs.append(f"grid ({p0.grid.describe()} vs {p.grid.describe()})")
        if p.horizon != p0.horizon:
            differs.append(f"horizon ({p0.horizon:g} vs {p.horizon:g})")
        if p.temperature != p0.temperature:
            differs.append(f"temperature λ ({p0.temperature:g} vs {p.temperature:g})")
        if not np.array_equal(p.R, p0.R):
            differs.append(f"control cost R ({p0.R.tolist()} vs {p.R.tolist()})")
        if p.grid == p0.grid and not _same_cost(p.state_cost, p0.state_cost, p.grid):
            differs.append("state cost q (values differ at the grid nodes)")
        if not np.array_equal(s.times, ref.times):
            differs.append(f"time grid ({len(ref.times)} vs {len(s.times)} stored slices, or "
                           "different times: solve all with the same dt and store_every)")
        if s.diagnostics.method != ref.diagnostics.method:
            differs.append(f"solver method ({ref.diagnostics.method} vs {s.diagnostics.method})")
        if s.diagnostics.fitting != ref.diagnostics.fitting:
            differs.append(f"fitting reference ({ref.diagnostics.fitting} vs "
                           f"{s.diagnostics.fitting}: solve them together with "
                           "solve_many(..., fitting='terminal'), or pass one shared reference "
                           "cost as fitting=)")
        if differs:
            raise ValueError(
                f"solutions[{i}] and solutions[0] must solve the same PDE to combine, but differ "
                f"in: {'; '.join(differs)}. Only the terminal cost may differ (gridlbc.solve_many "
                "solves several terminal costs consistently)."
            )
    return solutions


@dataclass(frozen=True, eq=False)
class CompositeCost:
    """The terminal cost of a combination, g(x) = −λ log Σ w_i exp(−g_i(x)/λ).

    Evaluated stably (log-sum-exp); +inf where Σ w_i exp(−g_i/λ) ≤ 0, which only negative weights
    can cause.
    """

    costs: tuple
    weights: np.ndarray
    temperature: float

    def __call__(self, x) -> np.ndarray:
        lam = self.temperature
        e = np.stack([-np.asarray(c(x), dtype=float) / lam for c in self.costs])  # (n, N)
        top = e.max(axis=0)
        s = np.einsum("i,in->n", self.weights, np.exp(e - top))
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(s > 0, -lam * (np.log(np.where(s > 0, s, 1.0)) + top), np.inf)


@dataclass(frozen=True, eq=False)
class CombinedSolution:
    """z = Σ w_i z_i of solutions sharing one PDE; evaluates like a :class:`gridlbc.Solution`.

    Attributes
    ----------
    components : tuple of Solution
    weights : ndarray (n,)
        The fixed weights w (all ones for coordination).
    problem : Problem
        The components' problem with the composite terminal cost
        g = −λ log Σ w_i exp(−g_i/λ) (a :class:`CompositeCost`), e.g. for :func:`gridlbc.simulate`.
    """

    components: tuple[Solution, ...]
    weights: np.ndarray
    problem: Problem

    @property
    def times(self) -> np.ndarray:
        return self.components[0].times

    @property
    def grid(self):
        return self.problem.grid

    @property
    def temperature(self) -> float:
        return self.problem.temperature

    def _component_fields(self, x, t, gradient: bool):
        """Per component (w_i e^{L_i − L} z̃_i, w_i e^{L_i − L} g̃_i) on the common scale L."""
        fields = [s.scaled_fields(x, t, gradient) for s in self.components]
        L = max(f[0] for f in fields)
        factors = [w * math.exp(f[0] - L) for w, f in zip(self.weights, fields)]  # may underflow
        z = np.stack([c * f[1] for c, f in zip(factors, fields)])  # (n, N)
        g = np.stack([c * f[2] for c, f in zip(factors, fields)]) if gradient else None
        return L, z, g

    def scaled_fields(self, x, t, gradient: bool = True):
        """Combined ``(L, z, g)``: z(x, t) = z e^L and Bᵀ∇z(x, t) = g e^L, as
        :meth:`gridlbc.Solution.scaled_fields`, with L the largest component scale."""
        L, z, g = self._component_fields(x, t, gradient)
        return L, z.sum(axis=0), (g.sum(axis=0) if gradient else None)

    def blend_weights(self, x, t) -> np.ndarray:
        """α_i(x, t) = w_i z_i / Σ_j w_j z_j, shape ``(N, n)``: non-negative and summing to one
        when the weights are; NaN (with an UnderflowWarning) where Σ w_j z_j underflowed."""
        _, z, _ = self._component_fields(x, t, gradient=False)
        total = z.sum(axis=0)
        bad = ~(total > 0)
        warn_underflow(bad)
        with np.errstate(divide="ignore", invalid="ignore"):
            alpha = (z / np.where(bad, 1.0, total)).T
        alpha[bad] = np.nan
        return alpha

    # The evaluation from scaled fields is exactly Solution's: share it rather than repeat it.
    log_desirability = Solution.log_desirability
    desirability = Solution.desirability
    value = Solution.value
    policy = Solution.policy


def combine(solutions, weights=None) -> CombinedSolution:
    """Linear Bellman combination z = Σ w_i z_i of solutions of one PDE (paper §3–4).

    Parameters
    ----------
    solutions : sequence of Solution
        Solved for different terminal costs g_i, everything else equal (system, grid, horizon,
        stored times, state cost q, control cost R, temperature λ, solver method); otherwise a
        ``ValueError`` names what differs.
    weights : array_like (n,), optional
        Fixed weights w_i. ``None`` (coordination): all ones. Otherwise finite with a positive
        sum; from :func:`gridlbc.project` to interpolate a target cost.

    Returns
    -------
    CombinedSolution
        ``value``, ``log_desirability``, ``desirability``, ``policy`` exactly as the solution of
        the composite terminal cost g = −λ log Σ w_i exp(−g_i/λ), plus ``blend_weights``
        α_i = w_i z_i / Σ_j w_j z_j, and u = Σ α_i u_i.
    """
    solutions = _check_components(solutions)
    w = check_weights(weights, len(solutions))
    base = solutions[0].problem
    cost = CompositeCost(tuple(s.problem.terminal_cost for s in solutions), w, base.temperature)
    return CombinedSolution(solutions, w, base.replace(terminal_cost=cost))


@dataclass(frozen=True, eq=False)
class NaiveBlend:
    """The fixed-weight average u = Σ w_i u_i / Σ w_i of component policies (the paper's
    baseline): same weights at every state and time, blind to which component is relevant."""

    components: tuple
    weights: np.ndarray

    def policy(self, x, t) -> np.ndarray:
        """u(x, t) = Σ w_i u_i(x, t) / Σ w_i, shape ``(N, m)``."""
        u = [np.asarray(c.policy(x, t), dtype=float) for c in self.components]
        shapes = {a.shape for a in u}
        if len(shapes) != 1:
            raise ValueError(f"component policies return different shapes {sorted(shapes)}")
        return np.einsum("i,i...->...", self.weights, np.stack(u)) / self.weights.sum()


def naive_blend(solutions, weights) -> NaiveBlend:
    """The naive blend u = Σ w_i u_i / Σ w_i with fixed ``weights`` (paper Fig. 6).

    ``solutions`` are any objects with ``.policy(x, t)`` (Solutions or your own controllers);
    ``weights`` as for :func:`combine` (``None``: the plain average).
    """
    components = tuple(solutions)
    if not components:
        raise ValueError("solutions is empty: give at least one controller to blend")
    for i, c in enumerate(components):
        if not callable(getattr(c, "policy", None)):
            raise TypeError(f"solutions[{i}] has no .policy(x, t) method ({type(c).__name__})")
    return NaiveBlend(components, check_weights(weights, len(components)))
