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

import numpy as np

from ..errors import ResolutionWarning, warn_user
from ..interpolate import barycentric
from .estimate import observed_order, states_that_matter
from .grids import embedded_grid

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
    nodes = states_that_matter(solution)
    if len(nodes) == 0 or solution.diagnostics.dt <= 0:
        return 0.0, np.nan, np.full(grid.ndim, np.nan)
    rng = np.random.default_rng(SEED)
    h = np.asarray(grid.spacing, dtype=float)
    x = nodes[rng.integers(len(nodes), size=samples)]
    x = grid.clamp(x + (2.0 * rng.random(x.shape) - 1.0) * h)
    drift = np.asarray(problem.system.drift(x), dtype=float)
    excess = np.abs(drift - _interpolant(problem, grid, x))
    cells = (excess * solution.diagnostics.dt / h).max(axis=1)
    worst = int(np.argmax(cells))
    coarse = embedded_grid(grid)
    order = np.nan
    if coarse is not None:
        coarser = np.abs(drift - _interpolant(problem, coarse, x))
        order = observed_order(excess.sum(axis=1), coarser.sum(axis=1))
    return float(cells[worst]), order, x[worst]


def _interpolant(problem, grid, x: np.ndarray) -> np.ndarray:
    """(I a)(x): the drift at the vertices of each state's simplex on ``grid``, weighted (the
    drift evaluated once at each vertex that the simplices share)."""
    idx, weights = barycentric(grid, x)
    vertices, which = np.unique(idx, return_inverse=True)
    drift = np.asarray(problem.system.drift(grid.node_coordinates(vertices)), dtype=float)
    return np.einsum("nv,nvk->nk", weights, drift[which.reshape(idx.shape)])


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
