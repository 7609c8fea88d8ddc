"""An exit set narrower than a cell, between the nodes (docs page :doc:`accuracy`, "An exit
between the nodes").

A grid solve knows its exit set E by the nodes that lie in it: a node in E holds the exit cost,
the others are solved for. A part of E in a cell none of whose corners is in E (a strip thinner
than a cell between two rows of nodes, a small ball between four nodes) is absent from the
problem the grid solves, and from the problem every coarser grid solves: the solves agree, and
the error estimate, whose other terms read the costs (S, γ) or certify a few steps (the local
certificate), reads nothing. For a first-exit task whose cheapest exit is such a strip, v is
then the value of the task without it, many times the truth and silent (stranger round 22's
strip at mid-cell: docs page :doc:`accuracy`, "An exit between the nodes").

:func:`~gridlbc.accuracy.exits.missed_points` samples E in each cell without a corner in E or next
to a node in E (a part of E there is the edge of a part the grid holds), at the
points of the costs' sampling lattice (:func:`~gridlbc.accuracy.grids.samples_per_cell` per cell
along each axis, at the centres of a cell's sub-cells), and :func:`~gridlbc.accuracy.check_exit`
warns where it finds one. The estimate's response S (:func:`gridlbc.accuracy.responses`) also reads
what they change: the embedded grid solved again with each part moved onto its nearest node
(:class:`MovedExit`). For an exit set given as a shape (:class:`gridlbc.regions.Box`,
:class:`~gridlbc.regions.Ball`, their unions) the check is exact: each cell is tested for a point of
the shape (:meth:`~gridlbc.regions.RegionBase.meeting_points`), so a part is found however thin. A
plain callable is only sampled, and a part of it narrower than the lattice's spacing (an eighth of
a cell in 2-D) can still be missed.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..costs import evaluate_cost
from ..errors import ResolutionWarning, state_text, warn_user
from ..grid import Grid
from ..regions import GridRegion, meets_exactly
from .grids import samples_per_cell

EXIT_BLOCK = 1 << 20
"""At most about this many lattice points are tested at once (:func:`missed_exit`)."""


def missed_exit(problem) -> np.ndarray | None:
    """A point of the exit set E of ``problem`` in a cell of its grid none of whose corners is in
    E (module docstring), ``(d,)``; None where there is none (or no exit set)."""
    points = missed_points(problem, first=True)
    return points[0] if len(points) else None


def missed_points(problem, first: bool = False) -> np.ndarray:
    """The points of the exit set E of ``problem`` in the cells of its grid none of whose
    corners is in E or next to a node in E (module docstring), ``(M, d)`` (the first block's
    only where ``first``):
    for a shape, one in each cell it meets (:meth:`gridlbc.regions.RegionBase.meeting_points`),
    for a plain callable, the lattice points it holds; none without an exit set."""
    grid: Grid = problem.require_grid("the exit set's check")
    if problem.exit is None:
        return np.empty((0, grid.ndim))
    lower = _open_cells(grid, grid.reshape(problem.exit_mask()))
    h = np.asarray(grid.spacing, dtype=float)
    exact = meets_exactly(problem.exit)
    offsets = None  # the lattice's points in a cell, for a callable only
    if not exact:
        m = samples_per_cell(grid)
        offsets = np.array(list(itertools.product((np.arange(m) + 0.5) / m, repeat=grid.ndim)))
    per_block = EXIT_BLOCK if offsets is None else max(1, EXIT_BLOCK // len(offsets))
    found = []
    for start in range(0, len(lower), per_block):
        corners = grid.lo + lower[start : start + per_block] * h
        if offsets is None:
            points = grid.wrap(problem.exit.meeting_points(corners, corners + h))
        else:
            points = grid.wrap((corners[:, None, :] + offsets[None] * h).reshape(-1, grid.ndim))
        hit = problem.exit_mask(points)
        if hit.any():
            found.append(points[hit])
            if first:
                break
    return np.concatenate(found) if found else np.empty((0, grid.ndim))


class MovedExit:
    """The exit set of a problem on a coarser ``grid`` with its parts between the fine grid's
    nodes (``points``, :func:`~gridlbc.accuracy.exits.missed_points`) moved onto the nearest coarse
    node: the task a coarse solve answers when it does hold them. The estimate's response S compares
    it with the task without them (:func:`gridlbc.accuracy.responses`): what the parts no node holds
    change, to within the coarse grid's cell of where they lie.

    Attributes
    ----------
    region : GridRegion
        The coarse grid's exit nodes and the nodes the parts moved onto.
    """

    def __init__(self, problem, grid: Grid, points: np.ndarray):
        self.grid, self.points = grid, points
        self.nodes = grid.nearest_node(points) @ grid.strides
        added = np.zeros(grid.size, dtype=bool)
        added[self.nodes] = True
        inside = problem.exit_mask(grid.nodes()) | added
        self.region = GridRegion(grid, inside, f"{problem.exit!r} with its parts between the nodes")

    def cost(self, exit_cost) -> MovedCost:
        """``exit_cost`` with, at each node a part moved onto, its least value over the part's
        points there (the cheapest way out that the part offers)."""
        values = evaluate_cost(exit_cost, self.points, "exit_cost")
        at = np.full(self.grid.size, np.inf)
        np.minimum.at(at, self.nodes, values)
        return MovedCost(exit_cost, self.grid, at)


class MovedCost:
    """An exit cost that a :class:`MovedExit` reads: ``cost`` at states ``x``, but at a node of
    ``grid`` where ``at`` is finite, ``at`` there."""

    def __init__(self, cost, grid: Grid, at: np.ndarray):
        self.cost, self.grid, self.at = cost, grid, at

    def __call__(self, x) -> np.ndarray:
        x = np.atleast_2d(np.asarray(x, dtype=float))
        out = evaluate_cost(self.cost, x, "exit_cost")
        h = np.asarray(self.grid.spacing, dtype=float)
        on_node = np.all(np.abs(np.remainder(x - self.grid.lo + h / 2, h) - h / 2) <= 1e-9 * h, 1)
        moved = self.at[self.grid.nearest_node(x) @ self.grid.strides]
        return np.where(on_node & np.isfinite(moved), moved, out)


def _open_cells(grid: Grid, inside: np.ndarray) -> np.ndarray:
    """The lower corners (index coordinates, ``(M, d)``) of the cells none of whose corners is
    in ``inside`` (the exit mask on the grid's shape) or next to a node in it: on a periodic
    axis also the cells across its seam.

    Why not next to one either: a part of E in such a cell is an edge of a part the grid holds
    (the cap of a ball that bulges between two rows of nodes), which the grid places to within a
    cell like any other edge, not a part that no node holds: warned of, it would be a false
    alarm on many a ball."""
    counts = [a.n if a.periodic else a.n - 1 for a in grid.axes]
    near = inside
    for k, axis in enumerate(grid.axes):  # grown by a node each way along every axis in turn
        grown = near.copy()
        for shift in (1, -1):
            moved = np.roll(near, shift, axis=k)
            if not axis.periodic:  # what rolled across the ends is not a neighbour
                np.moveaxis(moved, k, 0)[0 if shift == 1 else -1] = False
            grown |= moved
        near = grown
    touched = np.zeros(counts, dtype=bool)
    for corner in itertools.product((0, 1), repeat=grid.ndim):
        touched |= _take(near, corner, counts)
    return np.argwhere(~touched)


def _take(inside: np.ndarray, corner: tuple, counts: list) -> np.ndarray:
    """``inside`` at each cell's corner ``corner`` (0 or 1 per axis: the lower or the upper
    node, wrapped on a periodic axis), on the cells' shape ``counts``."""
    out = inside
    for k, c in enumerate(corner):
        out = np.roll(out, -c, axis=k) if c else out
        out = np.take(out, np.arange(counts[k]), axis=k)
    return out


def check_exit(solution, points: np.ndarray | None = None) -> None:
    """Warn (:class:`gridlbc.ResolutionWarning`) where the exit set has a part that no node of
    the grid holds: one of ``points`` (:func:`~gridlbc.accuracy.exits.missed_points`, where the
    caller has them) or
    :func:`missed_exit`."""
    where = missed_exit(solution.problem) if points is None else next(iter(points), None)
    if where is None:
        return
    state = state_text(where)
    warn_user(
        f"the exit set has a part between the nodes near {state} that no node of the grid holds "
        "(narrower than a cell): the grid solves the task without it, and so does every coarser "
        "grid; where paths would exit there, v can be far too high. The error estimate reads "
        "what it changes with the part moved onto a node of the grid with every other node. "
        "Give a grid whose nodes fall in every part of the exit set (a spacing below its "
        "width), or solve with tol=, and compare (docs page 'accuracy')",
        ResolutionWarning,
    )
