"""The embedded grids of an error estimate and the finer grids of a solve to a tolerance (docs page
:doc:`accuracy`).

The embedded grid keeps every other node of each axis (spacing 2h). On a closed axis with an odd
node count and a periodic one with an even count its nodes are the fine grid's even-numbered
nodes (the axis is *nested*). Otherwise (an odd periodic axis, an even closed one) its nodes are
not the fine ones and can lie closer to a narrow feature than any fine node; the estimate then
also reads :func:`twin_grid`, one node more on those axes, and takes the larger of the two
differences.
"""

from __future__ import annotations

import numpy as np

from ..grid import Axis, Grid


def embedded_grid(grid: Grid, axes=None) -> Grid | None:
    """The grid with every other node of each axis (spacing 2h), or of the given ``axes`` only;
    None when an axis would keep fewer than three nodes (four on a periodic axis). A closed axis
    with an odd node count and a periodic one with an even count keep exactly their
    even-numbered nodes; otherwise the coarse spacing is slightly above 2h, the coarse nodes are
    not the fine ones, and the estimate also reads :func:`twin_grid`."""
    out = []
    for i, a in enumerate(grid.axes):
        if axes is not None and i not in axes:
            out.append(a)
            continue
        n = a.n // 2 if a.periodic else (a.n + 1) // 2
        if n < (4 if a.periodic else 3):
            return None
        out.append(Axis(a.lo, a.hi, n, periodic=a.periodic, name=a.name))
    return Grid(out)


def nested(axis: Axis) -> bool:
    """Whether every other node of ``axis`` is a node of its embedded axis: a periodic axis with
    an even node count, a closed one with an odd count (an even number of cells)."""
    return axis.n % 2 == (0 if axis.periodic else 1)


def twin_grid(grid: Grid, axes=None) -> Grid | None:
    """The embedded grid (:func:`embedded_grid`) with one node more on each axis whose embedded
    axis is not nested in it (:func:`nested`: an odd periodic axis, an even closed one), or on
    those of the given ``axes`` only; None when every such axis is nested or the grid is too
    coarse to embed.

    Why a second embedded grid: on an axis that is not nested, the coarse nodes can lie closer to
    a narrow feature of the problem (a pit in the state cost) than any node of the grid, and the
    coarse solve can then be *more* accurate than the fine one, hiding the fine grid's error.
    Measured in units of their own cells, the offset f of the fine nodes from any point is the
    sum of the offsets a and b of the two embedded axes (m and m + 1 nodes bracketing the fine
    count's half: a periodic axis of 2m + 1 nodes has f = x(2m + 1)/L = a + b, a closed one of
    2m nodes f = x(2m − 1)/L = a + b), so the fine grid's distance to the nearest node is at most
    twice the larger of the two coarse ones (distance to the nearest integer is subadditive),
    which is about what a coarse cell of 2h makes it: one of the two coarse grids misses every
    point at least as badly as the grid itself. The estimate reads the larger of the two
    differences (:meth:`EmbeddedEstimate.difference`)."""
    coarse = embedded_grid(grid, axes)
    if coarse is None:
        return None
    chosen = range(grid.ndim) if axes is None else axes
    misaligned = [i for i in chosen if not nested(grid.axes[i])]
    if not misaligned:
        return None
    return Grid(
        [
            Axis(c.lo, c.hi, c.n + 1, periodic=c.periodic, name=c.name) if i in misaligned else c
            for i, c in enumerate(coarse.axes)
        ]
    )


def refined_grid(grid: Grid, axes=None) -> Grid:
    """The grid with every cell halved (spacing h/2), or only along the given ``axes``: the grid
    whose embedded grid is ``grid``."""
    return Grid(
        [
            a
            if axes is not None and i not in axes
            else Axis(
                a.lo, a.hi, 2 * a.n if a.periodic else 2 * a.n - 1, periodic=a.periodic, name=a.name
            )
            for i, a in enumerate(grid.axes)
        ]
    )


def scaled_grid(grid: Grid, factors) -> Grid:
    """The grid with each axis's spacing divided by at least ``factors[i]`` (≥ 1; 1 leaves the
    axis as it is): the fewest cells that do so, an even number of them, so that the grid with
    every other node (:func:`embedded_grid`) keeps spacing exactly 2h. A factor of 2 gives
    :func:`refined_grid`."""
    out = []
    for a, r in zip(grid.axes, factors):
        cells = a.n if a.periodic else a.n - 1
        if r <= 1.0:
            out.append(a)
            continue
        cells = 2 * int(np.ceil(cells * r / 2.0 - 1e-9))
        n = cells if a.periodic else cells + 1
        out.append(Axis(a.lo, a.hi, n, periodic=a.periodic, name=a.name))
    return Grid(out)
