"""Weights that interpolate a target terminal cost from component costs (paper §4.1).

The combination of :func:`gridlbc.combine` solves the terminal reward h = Σ w_i h_i with
h_i = exp(−g_i/λ). To aim it at a target cost ḡ, project h̄ = exp(−ḡ/λ) onto span{h_i} in
L²(state space): the weights solve the Gram system

    A w = b,      A_ij = ⟨h_i, h_j⟩,      b_i = ⟨h_i, h̄⟩,

and the relative residual ‖h̄ − Σ w_i h_i‖ / ‖h̄‖ says how well the components represent the
target. For a quadratic cost g(x) = (x − c)ᵀW(x − c), h is the Gaussian exp(−½(x − c)ᵀA(x − c))
with A = 2W/λ, and on Rᵈ

    ⟨h_i, h_j⟩ = (2π)^{d/2} det(A_i + A_j)^{−1/2} exp(−½ (c_i − c_j)ᵀ A_i (A_i + A_j)⁻¹ A_j (c_i − c_j)).

Otherwise (periodic axes, arbitrary callables, or semi-definite W) the inner products are sampled
on a grid by the trapezoid rule (spectrally accurate on periodic axes for smooth h). The
temperature λ enters through h: pass the problem's ``temperature``.

Negative weights, or weights far from summing to one, mean the components are a poor basis for
the target (paper Fig. 4): the blended cost −λ log Σ w_i h_i may then have several minima or none
near the target. :func:`project` warns about both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .costs import Constant, Quadratic, evaluate_cost, is_number
from .errors import ProjectionWarning, warn_user
from .grid import Grid
from .regions import check_region, region_mask

PROJECTION_METHODS = ("auto", "analytic", "quadrature")

NEGATIVE_TOLERANCE = 1e-6
"""Weights below −NEGATIVE_TOLERANCE · max|w| count as negative."""

SUM_TOLERANCE = 0.25
"""|Σ w − 1| above this counts as far from one."""

RESIDUAL_TOLERANCE = 0.5
"""A relative residual above this (more than half of ‖h̄‖ unexplained) counts as a poor
representation of the target. Two Gaussians one width either side of a third leave ≈ 0.35."""

CONDITION_LIMIT = 1e10
"""A normalised Gram condition number above this makes the weights unreliable."""


@dataclass(frozen=True)
class Projection:
    """The result of projecting a target reward onto the component rewards.

    Attributes
    ----------
    weights : ndarray (n,)
        w, for :func:`gridlbc.combine`.
    gram : ndarray (n, n)
        A_ij = ⟨h_i, h_j⟩.
    rhs : ndarray (n,)
        b_i = ⟨h_i, h̄⟩.
    residual : float
        ‖h̄ − Σ w_i h_i‖ / ‖h̄‖ in [0, 1] (0: the target is in the span). Computed from the Gram
        entries as (‖h̄‖² − bᵀA⁻¹b)^{1/2}, so it bottoms out near √ε ≈ 1e-8.
    condition : float
        Condition number of the Gram matrix scaled to unit diagonal (≫ 1: nearly dependent
        components, sensitive weights).
    method : str
        ``"analytic"`` or ``"quadrature"``.
    temperature : float
        λ used in h = exp(−g/λ).
    messages : tuple of str
        Why the projection is poor, if it is (also issued as :class:`ProjectionWarning`).
    """

    weights: np.ndarray
    gram: np.ndarray
    rhs: np.ndarray
    residual: float
    condition: float
    method: str
    temperature: float
    messages: tuple[str, ...] = ()

    @property
    def weight_sum(self) -> float:
        return float(self.weights.sum())


def _gaussian_inner(c_i, A_i, c_j, A_j) -> float:
    S = A_i + A_j
    sign, logdet = np.linalg.slogdet(S)
    if sign <= 0 or not np.isfinite(logdet):
        raise np.linalg.LinAlgError("A_i + A_j is singular")
    dc = c_i - c_j
    quad = dc @ A_i @ np.linalg.solve(S, A_j @ dc)
    return math.exp(0.5 * c_i.size * math.log(2 * math.pi) - 0.5 * logdet - 0.5 * quad)


def analytic_gram(costs, lam) -> np.ndarray:
    """Gram matrix ⟨h_i, h_j⟩ = ∫ e^{−(g_i + g_j)/λ} dx of all ``costs`` (quadratics on Rᵈ,
    λ = ``lam``) in closed form, shape (n, n): the ``"analytic"`` method of :func:`projection`."""
    A = [2.0 * c.weights / lam for c in costs]
    n = len(costs)
    G = np.empty((n, n))
    for i in range(n):
        for j in range(i, n):
            G[i, j] = G[j, i] = _gaussian_inner(costs[i].center, A[i], costs[j].center, A[j])
    return G


def _trapezoid_weights(grid: Grid) -> np.ndarray:
    per_axis = []
    for ax in grid.axes:
        q = np.full(ax.n, ax.spacing)
        if not ax.periodic:
            q[[0, -1]] *= 0.5
        per_axis.append(q)
    out = per_axis[0]
    for q in per_axis[1:]:
        out = np.multiply.outer(out, q)
    return out.ravel()


def _quadrature(costs, lam, grid: Grid, where=None) -> tuple[np.ndarray, np.ndarray]:
    """Gram matrix of all ``costs`` sampled on ``grid`` (on its nodes in the region ``where``
    only, if given), and the log-scales s_i with h_i = e^{s_i} h̃_i, max h̃_i = 1 at the nodes
    (the Gram is of the h̃_i)."""
    nodes = grid.nodes()
    weights = _trapezoid_weights(grid)
    if where is not None:
        inside = region_mask(check_region(where, grid.ndim, "where"), nodes, "where")
        if not inside.any():
            raise ValueError("where contains no node of the grid: nothing to project on")
        nodes, weights = nodes[inside], weights[inside]
    H = np.empty((len(costs), nodes.shape[0]))
    scales = np.empty(len(costs))
    for r, c in enumerate(costs):
        if isinstance(c, Quadratic) and c.periods is None:
            c = c.with_periods(grid.periods)
        g = evaluate_cost(c, nodes, "cost")
        scales[r] = -g.min() / lam
        with np.errstate(under="ignore"):
            H[r] = np.exp(-(g - g.min()) / lam)
    return (H * weights) @ H.T, scales


def _constant(cost, name: str, grid: Grid | None):
    """A cost given as a number as the constant cost on the grid's states
    (:class:`gridlbc.costs.Constant`, as :class:`gridlbc.Problem` reads one); otherwise the
    callable itself."""
    if is_number(cost):
        if grid is None:
            raise ValueError(
                f"{name} is a number: a constant cost is sampled on a grid (its integral over "
                "the whole space diverges), pass grid=problem.grid"
            )
        return Constant(float(cost), grid.ndim)
    if not callable(cost):
        raise TypeError(
            f"{name} must be a cost callable on (N, d) states, e.g. Quadratic, or a number"
        )
    return cost


def _choose_method(method, costs, grid) -> str:
    if method not in PROJECTION_METHODS:
        raise ValueError(f"method must be one of {', '.join(PROJECTION_METHODS)}, got {method!r}")
    quadratic = all(isinstance(c, Quadratic) for c in costs)
    periodic = (grid is not None and bool(grid.periodic.any())) or any(
        isinstance(c, Quadratic) and c.periods is not None and np.isfinite(c.periods).any()
        for c in costs
    )
    if method == "auto":
        method = "analytic" if quadratic and not periodic else "quadrature"
        if method == "analytic" and any(np.linalg.eigvalsh(c.weights).min() <= 0 for c in costs):
            method = "quadrature"  # a flat direction: the integral over Rᵈ diverges
    if method == "analytic" and not (quadratic and not periodic):
        raise ValueError(
            "method='analytic' needs Quadratic costs on a non-periodic space; use "
            "method='quadrature' with a grid"
        )
    if method == "quadrature" and grid is None:
        raise ValueError(
            "these costs need the inner products sampled on a grid (periodic axes, callables, or "
            "a quadratic with a flat direction): pass grid=problem.grid"
        )
    return method


def projection(
    target_cost,
    component_costs,
    grid: Grid | None = None,
    *,
    temperature: float = 1.0,
    method: str = "auto",
    where=None,
) -> Projection:
    """Project h̄ = exp(−ḡ/λ) onto span{exp(−g_i/λ)}; the full report.

    Parameters
    ----------
    target_cost, component_costs, grid, temperature, method, where
        As for :func:`project`.

    Returns
    -------
    Projection
        The weights with the Gram matrix, residual, condition number and any warning messages
        (not issued: :func:`project` issues them).
    """
    costs = list(component_costs)
    if not costs:
        raise ValueError("component_costs is empty: give at least one component cost")
    if grid is not None and not isinstance(grid, Grid):
        raise TypeError(f"grid must be a gridlbc.Grid or None, got {type(grid).__name__}")
    target_cost, *costs = (
        _constant(c, "target_cost" if i == 0 else f"component_costs[{i - 1}]", grid)
        for i, c in enumerate([target_cost, *costs])
    )
    lam = float(temperature)
    if not (np.isfinite(lam) and lam > 0):
        raise ValueError(f"temperature must be positive and finite, got {temperature}")
    if where is not None and method == "analytic":
        raise ValueError("where= samples the inner products on the grid: use method='quadrature'")
    method = _choose_method(
        "quadrature" if where is not None else method, [*costs, target_cost], grid
    )
    everything = [*costs, target_cost]
    if method == "analytic":
        dims = {c.dim for c in everything}
        if len(dims) != 1:
            raise ValueError(f"costs have different state dimensions {sorted(dims)}")
        G, scales = analytic_gram(everything, lam), np.zeros(len(everything))
    else:
        assert grid is not None, "_choose_method picks quadrature only with a grid"
        G, scales = _quadrature(everything, lam, grid, where)
    n = len(costs)
    A, b, target_norm2 = G[:n, :n], G[:n, n], G[n, n]
    # Solve the unit-diagonal system: Â = D A D, D = diag(A)^{-1/2}.
    D = 1.0 / np.sqrt(np.diag(A))
    A_hat = A * np.outer(D, D)
    condition = float(np.linalg.cond(A_hat))
    if not np.isfinite(condition) or condition > 1 / np.finfo(float).eps:
        raise ValueError(
            f"the component rewards are linearly dependent (Gram condition {condition:.3g}): "
            "remove duplicate or nearly identical component costs"
        )
    w_hat = np.linalg.solve(A_hat, D * b)
    fit = w_hat @ (D * b)  # ⟨Σ w h̃, h̄⟩ = ‖Σ w h̃‖² at the projection
    residual = math.sqrt(max(target_norm2 - fit, 0.0) / target_norm2)
    # Undo the node scaling h_i = e^{s_i} h̃_i: w_i = w̃_i e^{s_target − s_i}.
    weights = D * w_hat * np.exp(scales[n] - scales[:n])
    messages = _diagnose(weights, residual, condition)
    return Projection(
        weights,
        G[:n, :n] * np.exp(np.add.outer(scales[:n], scales[:n])),
        G[:n, n] * np.exp(scales[:n] + scales[n]),
        residual,
        condition,
        method,
        lam,
        messages,
    )


def _diagnose(w: np.ndarray, residual: float, condition: float) -> tuple[str, ...]:
    out = []
    if w.min() < -NEGATIVE_TOLERANCE * np.abs(w).max():
        out.append(
            f"negative weights {np.round(w, 4).tolist()}: the blended cost has minima away "
            "from the target; place components around the target (paper Fig. 4)"
        )
    if abs(w.sum() - 1) > SUM_TOLERANCE:
        out.append(
            f"weights sum to {w.sum():.3g}, far from 1: the components are too far apart or "
            "too narrow to interpolate the target (paper Fig. 4)"
        )
    if residual > RESIDUAL_TOLERANCE:
        out.append(
            f"relative residual {residual:.2g}: the target reward lies far from the span "
            "of the component rewards"
        )
    if condition > CONDITION_LIMIT:
        out.append(
            f"Gram condition number {condition:.3g}: components nearly dependent, the "
            "weights are sensitive to rounding"
        )
    return tuple(out)


def project(
    target_cost,
    component_costs,
    grid: Grid | None = None,
    *,
    temperature: float = 1.0,
    method: str = "auto",
    where=None,
) -> np.ndarray:
    """Weights w (n,) with Σ w_i exp(−g_i/λ) the L² projection of exp(−ḡ/λ) (paper §3–4).

    Parameters
    ----------
    target_cost : callable or float
        ḡ, e.g. a :class:`gridlbc.costs.Quadratic`; a number is the constant cost (sampled on
        ``grid``).
    component_costs : sequence of callables or floats
        g_i, the terminal costs of the solutions to combine (numbers as ``target_cost``).
    grid : Grid, optional
        Where to sample the inner products; needed unless all costs are quadratics with positive
        definite W on a non-periodic space (then they are exact Gaussian integrals over Rᵈ).
        Give it on a space with a periodic axis: a :class:`gridlbc.costs.Quadratic` made by you
        knows no periods until a grid or a :class:`gridlbc.Problem` gives them, and without
        either it is read on Rᵈ (an angle 3 from the target's centre is 3 away, not 2π − 3).
    temperature : float
        λ of h = exp(−g/λ); use the problem's temperature (keyword only).
    method : str
        ``"auto"`` (analytic when possible), ``"analytic"`` or ``"quadrature"``.
    where : region or callable, optional
        Project on the grid's nodes in this region only (keyword only): for exit costs, the
        exit set ``problem.exit``, the only place where they are paid (docs page
        :doc:`first_exit`). Implies quadrature.

    Warns :class:`ProjectionWarning` when the weights are negative, far from summing to one, the
    residual is large or the Gram matrix ill-conditioned; :func:`projection` returns all of it.
    """
    result = projection(
        target_cost, component_costs, grid, temperature=temperature, method=method, where=where
    )
    for message in result.messages:
        warn_user(message, ProjectionWarning)
    return result.weights
