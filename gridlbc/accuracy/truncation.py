"""The generator's truncation error on the solved value: what a stationary solve leaves out where
its desirability falls faster than a cell resolves (docs page :doc:`accuracy`, "Where z falls
faster than a cell").

A stationary solve (first exit, average cost: :mod:`gridlbc.stationary`) solves L_h z = (q − c)/λ z
with the chain's generator L_h (:mod:`gridlbc.schemes.generator`; c = 0 for first exit), and
the implicit time march steps with the same chain (:mod:`gridlbc.schemes.implicit`, upwind
rates). Its z solves the continuous equation L z = (q − c)/λ z exactly only for the state cost
q − λτ,

    τ = (L_h z − L z) / z,

the generator's truncation error on the solution, L = aᵀ∇ + tr(D ∇²) the continuous generator. In
terms of v = −λ log z, along each axis k at a node with neighbours v₊ and v₋ (Δ± = v± − v, the
chain's rates r± ≥ 0 to them, drift a_k and diffusion D_k = ½ λ (BR⁻¹Bᵀ)_kk)::

    (L_h z / z)_k = r₊ (e^{−Δ₊/λ} − 1) + r₋ (e^{−Δ₋/λ} − 1),
    (L z / z)_k   = −a_k v′/λ + D_k ((v′/λ)² − v″/λ),

with v′ = (v₊ − v₋)/2h and v″ = (v₊ − 2v + v₋)/h² of the solved v. Where v changes little over a
cell (by much less than λ) the two agree to O(h²); where z falls by a factor e^s per cell with
s ≫ 1 (a temperature small against the cell: the discrete z of a pure diffusion then falls by
arccosh(1 + (κh)²/2) per cell where the true one falls by κh), the first is the chain's and the
second the PDE's, and τ is the cost the grid leaves out. In one dimension, for z = e^{−κx}
solved on nodes with s = Δ/λ per cell, τ = (D/h²)(4 sinh²(s/2) − s²).

The solved v is the optimal value for the cost q − λτ, whose optimal policy is
u = −R⁻¹Bᵀ∇v_h, and the optimal value is a minimum over policies of expectations linear in the
cost, so along that policy

    v − v_h ≤ E[ ∫₀^τ λ τ(X_s) ds ],

which :func:`~gridlbc.accuracy.truncation_gap` samples for a first-exit solve with the paths of
:func:`gridlbc.accuracy.path_gap`, with ∇v_h from the nodes' central differences of v (exact
for a z that falls geometrically from node to node; the solve's own policy, λR⁻¹Bᵀ∇z/z from
interpolated z, is not: it moves too fast where z falls by much more than e per cell). For an
average-cost solve c − c_h ≈ E_π[λτ] under its stationary law π
(:func:`~gridlbc.accuracy.average_truncation`), and the relative value's error is the same integral
of λτ − E_π[λτ] until the paths reach h's minimum (the nodes within λ of it). The term sees the
error of a problem whose temperature is small against the cell, which the embedded solves, all far
from their asymptotic range, underestimate. It is first order in τ: where λτ is of the size of the
costs it overstates the error (the policy optimal for q − λτ is slower than the true one), on the
safe side.

Only the nodes whose neighbours along every axis are free (not in the exit set, inside the box)
and finite are read: the chain's arms to an exit set's boundary are shorter than a cell, and a
closed edge reflects; τ is zero there.
"""

from __future__ import annotations

import numpy as np

from ..interpolate import interpolate
from ..regions import GridRegion
from ..schemes.generator import jump_rates
from .paths import nodal, path_gap

SLICES = 8
"""At most this many stored slices of a time-marched solve give its λτ (evenly spaced in time;
between them the nearest is read): a full pass over the nodes each."""


def generator_rates(solution) -> str | None:
    """The jump rates of the generator a solution's operator steps with
    (:data:`gridlbc.schemes.generator.RATES`): a stationary solve's own, ``"upwind"`` for the
    implicit time march; None for an operator that is no chain's generator (the splitting
    scheme)."""
    method = solution.operator.method
    if method.startswith("stationary-"):
        return method.removeprefix("stationary-")
    return "upwind" if method == "implicit" else None


def truncation_rate(solution, j: int = 0) -> np.ndarray:
    """λτ at every node (module docstring): the cost per unit time that the generator's
    truncation error leaves out of a solve, from its solved v at stored slice ``j``; zero at
    nodes next to the exit set, a closed edge or an underflowed value. Kept with the solution.

    Parameters
    ----------
    solution : Solution
        A stationary solution of :mod:`gridlbc.stationary` or a time-marched one of the
        implicit scheme (:func:`~gridlbc.accuracy.truncation.generator_rates` not None).
    j : int
        The stored slice (time ``solution.times[j]``).

    Returns
    -------
    ndarray (N,)
    """
    kept = solution._cache.setdefault("truncation_rate", {})
    if j in kept:
        return kept[j]
    problem = solution.problem
    grid, lam = problem.require_grid("the truncation error"), problem.temperature
    rates = generator_rates(solution)
    if rates is None:
        raise ValueError(
            f"the truncation error is the generator's; the {solution.operator.method} operator "
            "is not a chain's generator"
        )
    v = solution.value_nodes(j)
    free = np.isfinite(v)
    if problem.exit is not None:
        free &= ~problem.exit_mask()
    x = grid.nodes()
    drift = np.asarray(problem.system.drift(x), dtype=float)
    diffusion = 0.5 * problem.noise_diagonal(x)
    V, free = grid.reshape(v), grid.reshape(free)
    read, total = free.copy(), np.zeros(grid.shape)
    for k, ax in enumerate(grid.axes):
        after, before = np.roll(V, -1, axis=k), np.roll(V, 1, axis=k)
        read &= np.roll(free, -1, axis=k) & np.roll(free, 1, axis=k)
        if not ax.periodic:  # a closed edge reflects: no neighbour beyond it
            read[(slice(None),) * k + (0,)] = False
            read[(slice(None),) * k + (-1,)] = False
        up, down = (
            grid.reshape(r) for r in jump_rates(drift[:, k], diffusion[:, k], ax.spacing, rates)
        )
        slope = grid.reshape(value_gradient(solution, j)[k]) / lam
        a, D = grid.reshape(drift[:, k]), grid.reshape(diffusion[:, k])
        with np.errstate(over="ignore", invalid="ignore"):
            chain = up * np.expm1(-(after - V) / lam) + down * np.expm1(-(before - V) / lam)
            curvature = (after - 2 * V + before) / (ax.spacing**2 * lam)
            total += chain - (-a * slope + D * (slope**2 - curvature))
    out = np.where(read & np.isfinite(total), lam * total, 0.0).ravel()
    kept[j] = out
    return out


def truncation_gap(solution, x, samples: int, t: float = 0.0, below=None, v=None) -> np.ndarray:
    """E[∫ λτ(X_s, s) ds] from states ``x`` (N, d) at time ``t`` along paths driven by
    u = −R⁻¹Bᵀ∇v_h (module docstring), ``samples`` per state, until they exit or reach the
    horizon; for an average-cost solve's relative value h (min 0 at a node x_m),
    E[∫₀^τ (λτ − E_π[λτ])(X_s) ds] until the paths reach the nodes where h ≤ λ (where e^{−h/λ}
    is within a factor e of its largest: around x_m, where the stationary law sits), the
    first-order change of h(x) − h(x_m) with the cost to within its change over that set. A
    time-marched solve of the implicit scheme reads λτ and ∇v_h at the nearest of up to
    :data:`~gridlbc.accuracy.truncation.SLICES` of its stored slices. Zero for an operator that is
    not a chain's generator (:func:`~gridlbc.accuracy.truncation.generator_rates`) or where λτ
    vanishes at every node.

    The paths are run only from the states where the term could exceed ``below`` (N,) (the rest
    of an estimate, or 0): for a first-exit solve where abs(λτ) ≤ ε q at every free node, the
    paths' costs give E ∫ q ds ≤ v_h − min g_E + E ∫ λτ ds, so the term is at most
    ε/(1 − ε) (v_h − min g_E), and a state where that is at most ``below`` reads 0. ``v``: v_h
    at ``x`` where the caller has read it.

    Returns
    -------
    ndarray (N,)
        At least v − v_h to first order in τ (positive where the solve underestimates v).
    """
    problem = solution.problem
    x = np.atleast_2d(np.asarray(x, dtype=float))
    out = np.zeros(len(x))
    if generator_rates(solution) is None:
        return out
    slices = _slices(solution, t)
    rates = [truncation_rate(solution, j) for j in slices]
    if not any(np.any(rate) for rate in rates):
        return out
    ends = problem.exit_mask() if problem.exit is not None else None
    if problem.average_cost:  # h(x) − h(x_m): until the paths reach h ≤ λ, less c's share
        ends = solution.value_nodes(0) <= problem.temperature
        rates = [rates[0] - average_truncation(solution)]
    reached = np.ones(len(x), dtype=bool)
    if below is not None and problem.stationary and not problem.average_cost:
        reached = ~(_bound(solution, rates[0], x, v) <= below)
        if not reached.any():
            return out
    grid = problem.require_grid("the truncation error")
    times = solution.times[slices]
    fields = [  # ∂v/∂x_k and λτ at each slice read: one stencil a step
        np.vstack([*value_gradient(solution, j), rate]) for j, rate in zip(slices, rates)
    ]
    R_inverse = np.linalg.inv(problem.R)
    read: dict = {}

    def at(y: np.ndarray, s: float) -> np.ndarray:
        """The fields at the paths' states at time s from the nearest slice read (the policy
        and the rate read the same y a step)."""
        i = int(np.argmin(np.abs(times - s)))
        if read.get("y") is not y or read.get("i") != i:
            read["y"], read["i"], read["fields"] = y, i, interpolate(grid, fields[i], y)
        return read["fields"]

    def policy(y: np.ndarray, s: float) -> np.ndarray:
        gradient = at(y, s)[:-1].T
        return -np.einsum("mk,ndk,nd->nm", R_inverse, problem.input_matrix(y), gradient)

    # the paths' end as the nodes hold it, as a saved solution's exit set (GridRegion): the same
    # paths before and after gridlbc.save
    paths = problem
    if ends is not None:
        horizon = None if problem.stationary else problem.horizon  # the average cost: none
        paths = problem.replace(horizon=horizon, exit=GridRegion(grid, ends, repr(problem.exit)))
    along = (paths, policy, lambda y, s: at(y, s)[-1])
    out[reached] = path_gap(solution, x[reached], t, samples, along=along)[0]
    return out


def _slices(solution, t: float = 0.0) -> np.ndarray:
    """The stored slices whose λτ a time-marched solve's paths from time ``t`` read: up to
    :data:`~gridlbc.accuracy.truncation.SLICES`, evenly spaced in time over [t, T], the last before
    t and the last among them (the one slice of a stationary solve). The paths see λτ only from t
    on, and near the horizon it changes fastest (an exit set's desirability against the terminal
    cost's)."""
    times = np.asarray(solution.times, dtype=float)
    first = max(int(np.searchsorted(times, t, side="right")) - 1, 0)
    count = len(times) - first
    return first + np.unique(np.linspace(0, count - 1, min(SLICES, count)).round().astype(int))


def _bound(solution, rate: np.ndarray, x: np.ndarray, v) -> np.ndarray:
    """ε/(1 − ε) (v_h − min g_E) at ``x`` with ε = max abs(λτ)/q over the nodes where λτ ≠ 0
    (:func:`~gridlbc.accuracy.truncation_gap`); inf where ε ≥ 1 or q ≤ 0 at such a node."""
    problem = solution.problem
    felt = rate != 0
    if problem.state_cost is None:
        return np.full(len(x), np.inf)
    q = nodal(solution, "state_cost")[felt]
    epsilon = float(np.max(np.abs(rate[felt]) / q)) if np.all(q > 0) else np.inf
    if not epsilon < 1:
        return np.full(len(x), np.inf)
    v = solution.value(x) if v is None else v
    lowest = min(float(np.min(nodal(solution, "exit_cost")[problem.exit_mask()])), 0.0)
    return epsilon / (1 - epsilon) * (v - lowest)


def value_gradient(solution, j: int = 0) -> list[np.ndarray]:
    """∂v/∂x_k at every node of stored slice ``j``, per axis: central differences of the solved
    v (one-sided at a closed edge, wrapped on a periodic axis), 0 where v is not finite. Kept
    with the solution."""
    kept = solution._cache.setdefault("value_gradient", {})
    if j in kept:
        return kept[j]
    grid = solution.problem.grid
    v = solution.value_nodes(j).reshape(grid.shape)
    out = []
    for k, ax in enumerate(grid.axes):
        with np.errstate(invalid="ignore"):
            if ax.periodic:
                d = (np.roll(v, -1, axis=k) - np.roll(v, 1, axis=k)) / (2 * ax.spacing)
            else:
                d = np.gradient(v, ax.spacing, axis=k)
        out.append(np.where(np.isfinite(d), d, 0.0).ravel())
    kept[j] = out
    return out


def average_truncation(solution) -> float:
    """E_π[λτ], what the truncation error leaves out of an average-cost solve's c under its
    stationary law π (first order in τ: c − c_h ≈ E_π[λτ], the derivative of c in the state cost
    being π); 0 without a ``stationary_distribution``."""
    share = getattr(solution, "stationary_distribution", None)
    return 0.0 if share is None else float(share @ truncation_rate(solution))
