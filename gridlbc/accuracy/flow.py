"""A drift or a noise that changes between the nodes, where neither the grid nor the coarser solves
follow it (docs page :doc:`accuracy`, "A flow narrower than a cell").

A solve with a horizon carries each node along the drift a over one step Δt and reads the value
where it lands (the splitting's midpoint rule evaluates a once between the nodes per step; the
implicit scheme reads a at the nodes only). Where a changes across less than a cell (a gust, a
jet, a kick between two nodes), where a path lands depends on where those evaluations fall, and
the solves on coarser grids and with longer steps, which the embedded estimate compares, step
over the feature alike: they agree with one another and with this solve, the estimate reads
nothing, and v can be tens of percent off.

What a grid represents of the drift is its interpolant I_h a from the nodes. At states sampled
around the states that matter (:data:`FLOW_SAMPLES`: a node drawn from those states, then an
offset uniform within a cell along each axis, with a fixed seed),

    F = max_x max_k abs(a_k(x) − (I_h a)_k(x)) Δt / h_k

is how far, in cells of axis k, the drift between the nodes carries a path in one step beyond
what the grid's picture of it says. A drift the grid resolves has an interpolation error that
falls as h²: on the grid with every other node (I_2h
a, :func:`~gridlbc.accuracy.grids.embedded_grid`) it is about four times as large, and the observed
order

    p = log₂( Σ_x abs(a − I_2h a) / Σ_x abs(a − I_h a) )

is near 2. A feature narrower than a cell is missed by both alike (p near 0), one that jumps within
a cell gives p near 1. p is observed from 2h to h and from 4h to 2h, the grids the estimate
compares, and the least of the two is read: a wall on a node that the grid with every other node
keeps is over-represented alike by both interpolants' hats (p between 1 and 2 on both pairs),
and the midpoint rule's one evaluation lands beyond the wall, so that no step feels it and v is
far low (stranger round 22's ``driftwall2_even_node``, docs page :doc:`accuracy`, "A wall ...
an eighth of a cell wide"). Where F is at least :data:`~gridlbc.accuracy.flow.FLOW_CELLS` and p is
below :data:`~gridlbc.accuracy.flow.SMOOTH_ORDER`, nearer first than second
order, :func:`~gridlbc.accuracy.check_flow` warns and says where: there the path lands in another
cell than the grid's picture of the flow says, and the grids do not follow the feature. A smooth
drift that the grid resolves only roughly (large F, p near 2) is the scheme's business, which the
embedded estimate measures.

The noise is read the same way (:func:`~gridlbc.accuracy.noise_excess`): the grid reads the gain
B(x), and with it Σ = λ B R⁻¹ Bᵀ, at its nodes only, and a gain that drops within a cell (a band of
a third of a cell where it falls to a twentieth) leaves the solve that of a constant gain, v
low, with every part of the estimate far below the error (round 22's ``gainband2_deep``, docs
page :doc:`accuracy`, "A noise that changes within a cell"). There F compares the spread of one
step, sqrt(abs(Σ − I_h Σ) Δt) / h in cells.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np

from ..errors import ResolutionWarning, state_text, warn_user
from ..interpolate import barycentric
from .estimate import observed_order
from .grids import embedded_grid
from .matter import states_that_matter
from .paths import ROUNDING

FLOW_SAMPLES = 1 << 14
"""States at which :func:`~gridlbc.accuracy.flow_excess` compares the drift with its
interpolants."""

FLOW_CELLS = 0.5
""":func:`~gridlbc.accuracy.check_flow` warns where the drift between the nodes carries a path this
share of a cell or more beyond its interpolant in one step (and the excess does not shrink on
refinement): half a cell puts the path in another cell than the grid's picture of the flow says."""

SMOOTH_ORDER = 1.5
"""The interpolation error of a coefficient smooth at the grid's scale shrinks at order 2 from
one grid to the next finer, of one that jumps within a cell at order 1, of one narrower than a
cell at order 0 or below: an observed order below this, nearer first than second order, says
that the grids do not follow it (:func:`~gridlbc.accuracy.followed`)."""

SEED = 20090802
"""The samples' seed: the same solve gives the same numbers."""


def flow_excess(solution, samples: int = FLOW_SAMPLES) -> tuple[float, float, np.ndarray]:
    """F, the largest excess of the drift over its interpolant in cells per step, the least
    observed order p of its interpolants from 4h to 2h and from 2h to h (:func:`_excess`), over
    states sampled around the :func:`~gridlbc.accuracy.states_that_matter` (module docstring),
    and where F is largest.

    Parameters
    ----------
    solution : Solution
        A solution with a horizon (its step Δt; F is 0 without one).
    samples : int
        States sampled.

    Returns
    -------
    cells : float
        F (0 where there is nothing to sample).
    order : float
        p (NaN without a coarser grid; +inf where the interpolant reproduces the drift to
        rounding: an affine drift).
    where : ndarray (d,)
        The state where F is largest (NaN where there is none).
    """
    x = _around(solution, samples)
    excess, order = _excess(solution, "drift", x)
    cells = excess * solution.diagnostics.dt / np.asarray(solution.grid.spacing, dtype=float)
    return _largest(cells, order, x, solution.grid.ndim)


def noise_excess(solution, samples: int = FLOW_SAMPLES) -> tuple[float, float, np.ndarray]:
    """:func:`~gridlbc.accuracy.flow_excess` for the noise's variances diag Σ(x) (Σ = λ B R⁻¹ Bᵀ, so
    also the control's gain B): F = max_x max_k sqrt(abs(Σ_kk − I_h Σ_kk) Δt) / h_k, how far in
    cells the spread of one step differs from the grid's picture of it, and the least observed order
    of the interpolants (+inf for a constant noise)."""
    x = _around(solution, samples)
    excess, order = _excess(solution, "noise", x)
    cells = np.sqrt(excess * solution.diagnostics.dt) / np.asarray(solution.grid.spacing)
    return _largest(cells, order, x, solution.grid.ndim)


def _largest(cells: np.ndarray, order: float, x: np.ndarray, ndim: int):
    """(F, p, where) from the cells per step ``cells`` (n, d) at the states ``x``."""
    if len(x) == 0:
        return 0.0, np.nan, np.full(ndim, np.nan)
    cells = cells.max(axis=1)
    worst = int(np.argmax(cells))
    return float(cells[worst]), order, x[worst]


def _excess(solution, coefficient: str, x: np.ndarray) -> tuple[np.ndarray, float]:
    """abs(f − I_h f) at the states ``x`` (n, d) for the ``coefficient`` f, ``"drift"`` (a) or
    ``"noise"`` (diag Σ), and the least order observed from its interpolants on the
    grid and the coarser grids the estimate reads (4h to 2h, 2h to h; a pair of levels whose
    finer error is rounding is left out: +inf where every one is; NaN without a coarser grid).

    Why both pairs of levels: the embedded solve is compared as if in Richardson's range, and a
    feature the grid resolves may be narrower than a cell of the embedded grid (a gust narrower
    than a cell of the coarser grids: order 2 from 2h to h and below 1 from 4h to 2h), or the
    grid and the embedded grid may both keep the node it sits on (a drift wall on such a node:
    both orders between 1 and 2, where a smooth drift gives 2 and 2; docs page :doc:`accuracy`,
    "A flow narrower than a cell" and "A wall ... an eighth of a cell wide")."""
    key = (coefficient, len(x))  # the states are drawn with a fixed seed: kept with the solution
    if key in solution._cache.setdefault("coefficient_excess", {}):
        return solution._cache["coefficient_excess"][key]
    problem = solution.problem
    f = problem.system.drift if coefficient == "drift" else problem.noise_diagonal
    if len(x) == 0:
        return np.zeros((0, solution.grid.ndim)), np.nan
    levels = [solution.grid]
    while len(levels) < 3 and (coarse := embedded_grid(levels[-1])) is not None:
        levels.append(coarse)
    exact = np.asarray(f(x), dtype=float)
    rounding = ROUNDING * float(np.abs(exact).sum())
    errors = [np.abs(exact - _interpolant(f, level, x)) for level in levels]
    orders = [
        observed_order(fine.sum(axis=1), coarse.sum(axis=1))
        for fine, coarse in pairwise(errors)
        if fine.sum() > rounding
    ]
    found = errors[0], (np.nan if len(levels) == 1 else min(orders, default=np.inf))
    solution._cache["coefficient_excess"][key] = found
    return found


def followed(order: float) -> bool:
    """Whether an observed interpolation order says the grids follow a coefficient: at least
    :data:`~gridlbc.accuracy.flow.SMOOTH_ORDER` (or +inf, or NaN where no coarser grid could be
    compared)."""
    return not order < SMOOTH_ORDER


def follows_coefficients(solution, samples: int = FLOW_SAMPLES) -> bool:
    """Whether the grid of ``solution`` and the coarser grids its estimate reads follow the
    drift and the noise between their nodes: the least observed order of each one's
    interpolants (:func:`~gridlbc.accuracy.flow_excess`, :func:`~gridlbc.accuracy.noise_excess`)
    is :func:`~gridlbc.accuracy.followed`.

    Where it is not, a coefficient changes within a cell of one of the grids (a gust, a jet, a
    noise that switches): the solves on those grids depend on where their nodes fall."""
    return all(followed(measure(solution, samples)[1]) for measure in (flow_excess, noise_excess))


def reads_pair(solution, responses) -> bool:
    """Whether the error estimate of ``solution`` reads the pair of grids
    (:func:`~gridlbc.accuracy.phase_pair`, docs page :doc:`accuracy`, "Features between nodes"):
    where the problem may have a feature narrower than a cell, whose error depends on where the
    nodes fall, which the embedded grid, every other node of the grid, can miss alike. That is,
    where the costs have an excess between the nodes that a coarse solve was run to respond to
    (one of ``responses``, the :class:`~gridlbc.accuracy.subcell.Response` of each cost, has
    its raised solve), where there is an exit set (its boundary falls between the nodes), and
    where the grids do not follow the drift or the noise (:func:`follows_coefficients`).
    Elsewhere, with smooth costs and coefficients, the pair's difference is of the order of the
    embedded one, and its coarse solves are saved."""
    if solution.problem.exit is not None:
        return True
    if any(response.raised is not None for response in responses or ()):
        return True
    return not follows_coefficients(solution)


def _around(solution, samples: int) -> np.ndarray:
    """``samples`` states around the :func:`~gridlbc.accuracy.states_that_matter`: a node drawn
    from them, then an offset uniform within a cell along each axis (a fixed seed), ``(M, d)``;
    none where there are none. Kept with the solution (the drift and the noise read the same)."""
    kept = solution._cache.setdefault("coefficient_states", {})
    if samples not in kept:
        grid = solution.grid
        nodes = states_that_matter(solution)
        if len(nodes):
            rng = np.random.default_rng(SEED)
            h = np.asarray(grid.spacing, dtype=float)
            x = nodes[rng.integers(len(nodes), size=samples)]
            nodes = grid.clamp(x + (2.0 * rng.random(x.shape) - 1.0) * h)
        kept[samples] = nodes
    return kept[samples]


def _interpolant(f, grid, x: np.ndarray) -> np.ndarray:
    """(I f)(x): ``f`` (states ``(n, d)`` → ``(n, k)``, the drift or the noise's variances) at
    the vertices of each state's simplex on ``grid``, weighted (evaluated once at each vertex
    that the simplices share)."""
    idx, weights = barycentric(grid, x)
    used = np.zeros(grid.size, dtype=bool)  # the vertices in use, found without sorting
    used[idx] = True
    vertices = np.flatnonzero(used)
    position = np.cumsum(used) - 1  # a vertex's row among them
    values = np.asarray(f(grid.node_coordinates(vertices)), dtype=float)
    return np.einsum("nv,nvk->nk", weights, values[position[idx]])


FLOW_WARNING = "the drift changes between the nodes"
"""How :func:`~gridlbc.accuracy.check_flow`'s warning begins (a solve to a tolerance refines its
step for it and warns itself where it remains)."""

NOISE_WARNING = "the noise changes between the nodes"
"""How :func:`~gridlbc.accuracy.check_flow`'s warning about the noise begins."""


def check_flow(solution) -> None:
    """Warn (:class:`gridlbc.ResolutionWarning`) where the drift between the nodes carries a path
    :data:`~gridlbc.accuracy.flow.FLOW_CELLS` of a cell or more beyond its interpolant in one step,
    or the noise's spread in one step differs from its interpolant's by as much
    (:func:`~gridlbc.accuracy.noise_excess`), and the grids do not follow it
    (:func:`~gridlbc.accuracy.followed`)."""
    for measure, begins, how, why in (
        (
            flow_excess,
            FLOW_WARNING,
            "in one step it carries a path {} cells beyond what its interpolant from the nodes "
            "says",
            "a smooth drift gives 2: a gust, jet or wall narrower than a cell). The coarser "
            "solves step over it alike, so the error estimate sees at most part of it, and v can "
            "be far off. Give a grid that resolves the flow, or a dt that moves a path less than "
            "half a cell through it",
        ),
        (
            noise_excess,
            NOISE_WARNING,
            "the spread of one step differs by {} cells from what its interpolant from the nodes "
            "says",
            "a smooth gain gives 2: a gain or noise that changes within a cell). The grid reads "
            "the gain B(x) at its nodes only, so the error estimate sees at most part of it, and "
            "v can be far off. Give a grid that resolves it",
        ),
    ):
        cells, order, where = measure(solution)
        if cells >= FLOW_CELLS and not followed(order):
            state = state_text(where)
            warn_user(
                f"{begins} near {state} where the grid does not follow it: "
                f"{how.format(f'{cells:.2g}')}, and its interpolants on the coarser grids shrink "
                f"towards it at order {order:.2g} ({why}, and compare (docs page 'accuracy')",
                ResolutionWarning,
            )
