"""An exit set narrower than a cell, between the nodes (docs page :doc:`accuracy`, "An exit
between the nodes").

A grid solve knows its exit set E by the nodes that lie in it: a node in E holds the exit cost,
the others are solved for. A part of E in a cell none of whose corners is in E (a strip thinner
than a cell between two rows of nodes, a small ball between four nodes) is absent from the
problem the grid solves, and from the problem every coarser grid solves: the solves agree, and
the error estimate, whose other terms read the costs (S, γ) or certify a few steps (the local
certificate), reads nothing. For a first-exit task whose cheapest exit is such a strip, v is
then the value of the task without it (stranger round 22: a strip 0.3 cell wide at mid-cell, v
1–32 times the truth, silent).

:func:`missed_exit` samples E in each cell without a corner in E, at the points of the costs'
sampling lattice (:func:`~gridlbc.accuracy.subcell.samples_per_cell` per cell along each axis,
at the centres of a cell's sub-cells), and :func:`check_exit` warns where it finds one. A part
narrower than the lattice's spacing (an eighth of a cell in 2-D) can still be missed.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..errors import ResolutionWarning, warn_user
from ..grid import Grid
from .subcell import samples_per_cell

EXIT_BLOCK = 1 << 20
"""At most about this many lattice points are tested at once (:func:`missed_exit`)."""


def missed_exit(problem) -> np.ndarray | None:
    """A point of the exit set E of ``problem`` in a cell of its grid none of whose corners is in
    E (module docstring), ``(d,)``; None where there is none (or no exit set)."""
    if problem.exit is None:
        return None
    grid: Grid = problem.require_grid("the exit set's check")
    inside = grid.reshape(problem.exit_mask())
    lower = _open_cells(grid, inside)
    if len(lower) == 0:
        return None
    m = samples_per_cell(grid)
    offsets = np.array(list(itertools.product((np.arange(m) + 0.5) / m, repeat=grid.ndim)))
    h = np.asarray(grid.spacing, dtype=float)
    per_block = max(1, EXIT_BLOCK // len(offsets))
    for start in range(0, len(lower), per_block):
        corners = grid.lo + lower[start : start + per_block] * h
        points = (corners[:, None, :] + offsets[None] * h).reshape(-1, grid.ndim)
        hit = problem.exit_mask(grid.wrap(points))
        if hit.any():
            return points[int(np.argmax(hit))]
    return None


def _open_cells(grid: Grid, inside: np.ndarray) -> np.ndarray:
    """The lower corners (index coordinates, ``(M, d)``) of the cells none of whose corners is
    in ``inside`` (the exit mask on the grid's shape): on a periodic axis also the cells across
    its seam."""
    counts = [a.n if a.periodic else a.n - 1 for a in grid.axes]
    touched = np.zeros(counts, dtype=bool)
    for corner in itertools.product((0, 1), repeat=grid.ndim):
        touched |= _take(inside, corner, counts)
    return np.argwhere(~touched)


def _take(inside: np.ndarray, corner: tuple, counts: list) -> np.ndarray:
    """``inside`` at each cell's corner ``corner`` (0 or 1 per axis: the lower or the upper
    node, wrapped on a periodic axis), on the cells' shape ``counts``."""
    out = inside
    for k, c in enumerate(corner):
        out = np.roll(out, -c, axis=k) if c else out
        out = np.take(out, np.arange(counts[k]), axis=k)
    return out


def check_exit(solution) -> None:
    """Warn (:class:`gridlbc.ResolutionWarning`) where the exit set has a part that no node of
    the grid holds (:func:`missed_exit`)."""
    where = missed_exit(solution.problem)
    if where is None:
        return
    state = np.array2string(where, precision=3, separator=", ")
    warn_user(
        f"the exit set has a part between the nodes near {state} that no node of the grid holds "
        "(narrower than a cell): the grid solves the task without it, and so does every coarser "
        "grid, so the error estimate cannot see what it changes; where paths would exit there, "
        "v can be far too high. Give a grid whose nodes fall in every part of the exit set "
        "(a spacing below its width), and compare (docs page 'accuracy')",
        ResolutionWarning,
    )
