"""The embedded grids of an error estimate and the finer grids of a solve to a tolerance (docs page
:doc:`accuracy`).

The embedded grid keeps every other node of each axis (spacing 2h). On a closed axis with an odd
node count and a periodic one with an even count its nodes are the fine grid's even-numbered
nodes (the axis is *nested*); otherwise its spacing is slightly above 2h. Beside it the estimate
reads a pair of grids whose cell counts add up to the grid's (:func:`~gridlbc.accuracy.phase_pair`):
how much their solves differ says how much a solve at this resolution depends on where the nodes
fall relative to the problem's narrow features, which the embedded grid alone cannot see."""

from __future__ import annotations

import numpy as np

from ..errors import ConvergenceError
from ..grid import Axis, Grid


def embedded_grid(grid: Grid, axes=None) -> Grid | None:
    """The grid with every other node of each axis (spacing 2h), or of the given ``axes`` only;
    None when an axis would keep fewer than three nodes (four on a periodic axis). A closed axis
    with an odd node count and a periodic one with an even count keep exactly their
    even-numbered nodes; otherwise the coarse spacing is slightly above 2h and the coarse nodes
    are not the fine ones."""
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


def cells(axis: Axis) -> int:
    """The number of cells of ``axis``: its node count on a periodic axis, one less on a closed one."""
    return axis.n if axis.periodic else axis.n - 1


def phase_pair(grid: Grid) -> tuple[Grid, Grid] | None:
    """Two grids of about twice the spacing whose cell counts add up to the grid's along each axis
    without being equal: c₁ + c₂ = C with c₁ = (C − 1)/2 for
    an odd count C and c₁ = C/2 − 1 for an even one; None where a grid would be too coarse (three
    nodes, four on a periodic axis).

    Why: how well a grid resolves a feature narrower than a few cells (a pit in the state cost, a
    sharp goal) depends on how far the feature lies from the nearest node, and the embedded grid
    (:func:`~gridlbc.accuracy.grids.embedded_grid`), whose nodes are every other node of the grid,
    misses a feature midway between two nodes by exactly as much as the grid does, so the difference
    between the two solves cannot see that error. At a point x of an axis of length L, the offsets
    from the nearest node measured in cells of each grid, f = xC/L, a = xc₁/L and b = xc₂/L, satisfy
    f = a + b: where the grid's nodes are aligned with the feature (f an integer) the two
    coarse grids miss it by the same distance and agree, and where the grid misses it (f near ½)
    their offsets a and ½ − a differ and so do their solves, unless both are a quarter cell off:
    a ≡ b where x(c₂ − c₁)/L is an integer, next to the ends of the axis and, for an even C
    (c₂ − c₁ = 2), next to its centre, where the pair is blind to such a feature.
    The estimate reads abs(v_c₁ − v_c₂) beside the embedded difference
    (:meth:`EmbeddedEstimate.difference`). Where C is odd (an odd periodic axis, an even closed
    one) the embedded axis is itself the one of c₁ cells."""
    pair: list[list[Axis]] = [[], []]
    for a in grid.axes:
        C = cells(a)
        counts = ((C - 1) // 2, (C + 1) // 2) if C % 2 else (C // 2 - 1, C // 2 + 1)
        for side, c in zip(pair, counts, strict=True):
            n = c if a.periodic else c + 1
            if n < (4 if a.periodic else 3):
                return None
            side.append(Axis(a.lo, a.hi, n, periodic=a.periodic, name=a.name))
    return Grid(pair[0]), Grid(pair[1])


def embedded_store_every(store_every: int, factor: int) -> int:
    """How often a coarser solve of the estimate (step ``factor`` Δt) stores its slices where the
    solve it checks stores every ``store_every``-th: every max(1, ⌊store_every / 2 factor⌋)-th
    of its steps, so its stored slices are at most half the solve's interval Δs = store_every Δt
    apart (every one of its steps where the solve stores every step or every few).

    Why: a value read between two stored slices is interpolated linearly in time, off by about
    Δs² ∂²v/∂t² / 8 at the middle. Coarser solves that stored as sparsely would interpolate
    alike, and their difference from the solve would not see it (stranger round 21: a point
    mass with only t = 0 and T stored, read at T/2, docs page :doc:`accuracy`); stored twice as
    densely they measure it (:meth:`~gridlbc.accuracy.EmbeddedEstimate.between_slices`)."""
    return max(1, store_every // (2 * factor))


def embedded_solves(fine: Grid, solve) -> tuple[list, str]:
    """The solves an estimate reads: ``solve(grid, factor)`` on the embedded grid (spacing 2h,
    ``factor`` 2: the step is doubled with the spacing) and on the one below it (4h, ``factor``
    4).

    A solve that raises ValueError (the problem cannot be posed that coarsely: an exit set that
    holds no node of the coarser grid) or :class:`gridlbc.ConvergenceError` (its iterative
    solve did not converge that coarsely) ends the levels there: an estimate's coarse solve
    never fails the solve it checks.

    Returns
    -------
    levels : list
        The solves at 2h and 4h, as far as the grids and the problem allow (empty: no estimate).
    reason : str
        Why there is no level: the grid is too coarse to embed, or the problem cannot be posed
        (or solved) on the embedded grid ("" where there is one).
    """
    levels: list = []
    reason = ""
    grid = embedded_grid(fine)
    if grid is None:
        reason = (
            f"the grid {fine.shape} is too coarse to embed a grid with every other node (a "
            "closed axis needs at least 5 nodes, a periodic one 8), so nothing checks its "
            "values, which may be far off on so few nodes; give a finer grid"
        )
    for factor in (2, 4):
        if grid is None:
            break
        try:
            levels.append(solve(grid, factor))
        except ValueError as error:
            if not levels:
                reason = (
                    f"the problem cannot be posed on the grid with every other node: {error}. A "
                    "problem the grid with every other node cannot hold is resolved by a few "
                    "nodes of this one, and its values may be far off; refine the grid until "
                    "that coarser grid holds it"
                )
            break
        except ConvergenceError as error:
            if not levels:
                reason = (
                    f"the solve on the grid with every other node did not converge ({error}); "
                    "certify the values you need (gridlbc.certify)"
                )
            break
        grid = embedded_grid(grid)
    return levels, reason


def pair_solves(fine: Grid, embedded, solve) -> list | None:
    """``solve(grid, 2)`` on each grid of :func:`~gridlbc.accuracy.phase_pair` (step 2Δt), the
    ``embedded`` solve itself where the pair's first grid is the embedded one; None where the grid
    is too coarse for the pair or a solve raises ValueError or :class:`gridlbc.ConvergenceError` (as
    in
    :func:`embedded_solves`, the estimate's solves never fail the solve they check).

    The estimate reads the pair only where the problem has a feature whose error depends on
    where the nodes fall (:func:`gridlbc.accuracy.reads_pair`)."""
    pair = phase_pair(fine)
    if pair is None:
        return None
    try:
        return [embedded if c == embedded_grid(fine) else solve(c, 2) for c in pair]
    except (ValueError, ConvergenceError):
        return None


LATTICE_POINTS = 1 << 24
"""The sampling lattice has as many points per cell along each axis, of 8, 4 and 2, as keep it
within this many points (:func:`samples_per_cell`)."""


def samples_per_cell(grid: Grid) -> int:
    """m, the lattice points per cell along each axis: the most of 8, 4 and 2 for which the
    lattice holds at most :data:`LATTICE_POINTS` points (m = 8 on a 2-D grid up to 512², 4 up to
    about 1000² and on a 3-D one up to 64³), and 2 beyond, so that sampling the costs stays a few
    seconds' work."""
    for m in (8, 4):
        if refined_grid(grid, factor=m).size <= LATTICE_POINTS:
            return m
    return 2


def refined_grid(grid: Grid, axes=None, factor: int = 2) -> Grid:
    """The grid with every cell divided into ``factor`` (spacing h/factor; every factor-th node a
    node of ``grid``), or only along the given ``axes``. With the default factor 2: the grid whose
    embedded grid is ``grid``."""
    return Grid(
        [
            a
            if axes is not None and i not in axes
            else Axis(
                a.lo,
                a.hi,
                factor * a.n if a.periodic else factor * (a.n - 1) + 1,
                periodic=a.periodic,
                name=a.name,
            )
            for i, a in enumerate(grid.axes)
        ]
    )


def scaled_grid(grid: Grid, factors) -> Grid:
    """The grid with each axis's spacing divided by at least ``factors[i]`` (≥ 1; 1 leaves the
    axis as it is): the fewest cells that do so, an even number of them, so that the grid with
    every other node (:func:`~gridlbc.accuracy.grids.embedded_grid`) keeps spacing exactly 2h. A
    factor of 2 gives
    :func:`~gridlbc.accuracy.grids.refined_grid`."""
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
