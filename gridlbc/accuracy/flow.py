"""A drift that changes between the nodes, where neither the grid nor the coarser solves follow it
(docs page :doc:`accuracy`, "A flow narrower than a cell").

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

    F = max_x max_k |a_k(x) − (I_h a)_k(x)| Δt / h_k

is how far, in cells of axis k, the drift between the nodes carries a path in one step beyond
what the grid's picture of it says. A drift the grid resolves has an interpolation error that
falls as h²: on the grid with every other node (I_2h a, :func:`~gridlbc.accuracy.embedded_grid`)
it is about four times as large, and the observed order

    p = log₂( Σ_x |a − I_2h a| / Σ_x |a − I_h a| )

is near 2. A feature narrower than a cell is missed by both alike (p near 0). Where F is at
least :data:`FLOW_CELLS` and p < 1 (not converging at first order, the test the embedded
estimate uses for its own levels), :func:`check_flow` warns and says where: there the path lands
in another cell than the grid's picture of the flow says, and refining the grid has not begun
to show the feature. A smooth drift that the grid resolves only roughly (large F, p near 2) is
the scheme's business, which the embedded estimate measures.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np

from ..errors import ResolutionWarning, warn_user
from ..interpolate import barycentric
from .estimate import observed_order, states_that_matter
from .grids import embedded_grid
from .paths import ROUNDING

FLOW_SAMPLES = 1 << 14
"""States at which :func:`flow_excess` compares the drift with its interpolants."""

FLOW_CELLS = 0.5
""":func:`check_flow` warns where the drift between the nodes carries a path this share of a cell
or more beyond its interpolant in one step (and the excess does not shrink on refinement): half
a cell puts the path in another cell than the grid's picture of the flow says."""

SEED = 20090802
"""The samples' seed: the same solve gives the same numbers."""


def flow_excess(solution, samples: int = FLOW_SAMPLES) -> tuple[float, float, np.ndarray]:
    """F, the largest excess of the drift over its interpolant in cells per step, the observed
    order p of the interpolants on the grid and the embedded grid (NaN without one), over
    states sampled around the :func:`~gridlbc.accuracy.states_that_matter` (module docstring),
    and where F is largest.

    Parameters
    ----------
    solution : Solution
        A solution with a horizon (its step Δt).
    samples : int
        States sampled.

    Returns
    -------
    cells : float
        F (0 where there is nothing to sample).
    order : float
        p.
    where : ndarray (d,)
        The state where F is largest (NaN where there is none).
    """
    problem, grid = solution.problem, solution.grid
    x = _around(solution, samples)
    if len(x) == 0 or solution.diagnostics.dt <= 0:
        return 0.0, np.nan, np.full(grid.ndim, np.nan)
    h = np.asarray(grid.spacing, dtype=float)
    drift = problem.system.drift
    exact = np.asarray(drift(x), dtype=float)
    excess = np.abs(exact - _interpolant(drift, grid, x))
    cells = (excess * solution.diagnostics.dt / h).max(axis=1)
    worst = int(np.argmax(cells))
    coarse = embedded_grid(grid)
    order = np.nan
    if coarse is not None:
        coarser = np.abs(exact - _interpolant(drift, coarse, x))
        order = observed_order(excess.sum(axis=1), coarser.sum(axis=1))
    return float(cells[worst]), order, x[worst]


def follows_coefficients(solution, samples: int = FLOW_SAMPLES) -> bool:
    """Whether the grid of ``solution`` and the coarser grids its estimate reads (spacings 2h and
    4h, :func:`~gridlbc.accuracy.embedded_grid`) follow the drift a and the noise's variances
    diag Σ between their nodes: at the states :func:`flow_excess` samples, the interpolation
    error of each converges at first order or better from 4h to 2h and from 2h to h (the
    observed order at least 1, as the estimate asks of its own levels), or is rounding at the
    finer of the two (an affine drift, constant noise).

    Where it does not, a coefficient changes within a cell of one of the grids (a gust, a jet, a
    noise that switches): the solves on those grids depend on where their nodes fall, and the
    embedded solve may be outside the range where Richardson's comparison holds even where the
    grid itself resolves the feature (a gust 0.02 wide on a grid of spacing 0.025: the
    interpolation errors shrink at order 2 from 2h to h and at 0.5 from 4h to 2h)."""
    x = _around(solution, samples)
    if len(x) == 0:
        return True
    problem, levels = solution.problem, [solution.grid]
    while len(levels) < 3 and (coarse := embedded_grid(levels[-1])) is not None:
        levels.append(coarse)
    for f in (problem.system.drift, problem.noise_diagonal):
        exact = np.asarray(f(x), dtype=float)
        rounding = ROUNDING * float(np.abs(exact).sum())
        errors = [np.abs(exact - _interpolant(f, level, x)).sum(axis=1) for level in levels]
        for fine, coarse in pairwise(errors):
            if fine.sum() > rounding and observed_order(fine, coarse) < 1.0:
                return False
    return True


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
    none where there are none."""
    grid = solution.grid
    nodes = states_that_matter(solution)
    if len(nodes) == 0:
        return nodes
    rng = np.random.default_rng(SEED)
    h = np.asarray(grid.spacing, dtype=float)
    x = nodes[rng.integers(len(nodes), size=samples)]
    return grid.clamp(x + (2.0 * rng.random(x.shape) - 1.0) * h)


def _interpolant(f, grid, x: np.ndarray) -> np.ndarray:
    """(I f)(x): ``f`` (states ``(n, d)`` → ``(n, k)``, the drift or the noise's variances) at
    the vertices of each state's simplex on ``grid``, weighted (evaluated once at each vertex
    that the simplices share)."""
    idx, weights = barycentric(grid, x)
    vertices, which = np.unique(idx, return_inverse=True)
    values = np.asarray(f(grid.node_coordinates(vertices)), dtype=float)
    return np.einsum("nv,nvk->nk", weights, values[which.reshape(idx.shape)])


FLOW_WARNING = "the drift changes between the nodes"
"""How :func:`check_flow`'s warning begins (a solve to a tolerance refines its step for it and
warns itself where it remains)."""


def check_flow(solution) -> None:
    """Warn (:class:`gridlbc.ResolutionWarning`) where the drift between the nodes carries a path
    :data:`FLOW_CELLS` of a cell or more beyond its interpolant in one step and the excess does
    not shrink from the grid with every other node to this one (:func:`flow_excess`)."""
    cells, order, where = flow_excess(solution)
    if cells < FLOW_CELLS or order >= 1.0:
        return
    state = np.array2string(where, precision=3, separator=", ")
    warn_user(
        f"{FLOW_WARNING} near {state} where the grid does not follow it: "
        f"in one step it carries a path {cells:.2g} cells beyond what its interpolant from the "
        "nodes says, and its interpolant on the grid with every other node is no worse (a gust "
        "or jet narrower than a cell). The coarser solves step over it alike, so the error "
        "estimate sees at most part of it, and v can be far off. Give a grid that resolves the flow, "
        "or a dt that moves a path less than half a cell through it, and compare (docs page "
        "'accuracy')",
        ResolutionWarning,
    )
