"""What happens to the state at the bounds of the grid's box, per axis.

A periodic axis has no boundary: it wraps (period n·h, no duplicate end node). A closed axis has
two ends, and how the process behaves there is a :class:`Boundary`:

- :attr:`Boundary.REFLECTING`, today the only one: a state constraint, no probability leaves the
  box. The schemes implement it where they touch the ends of a closed axis: the characteristic
  feet are clamped to the box (:mod:`gridlbc.schemes.splitting.feet`); the tridiagonal diffusion
  drops the jump out of the box, (1 + r) z_0 − r z_1 in the first row
  (:func:`gridlbc.schemes.splitting.diffusion.tridiagonal_factors`); the fitted diffusion
  continues a line by mirroring it at its ends (:mod:`gridlbc.backends.numba.fitted_node`); the
  implicit scheme suppresses the generator's jumps out of the box
  (:func:`gridlbc.schemes.generator.generator_matrix`).

Exit sets (first-exit problems, SPEC §9) are not a kind of edge: they are regions of the state
space (:mod:`gridlbc.regions`), anywhere in the box or beyond an edge, whose nodes the generator
makes absorbing (:mod:`gridlbc.schemes.generator`), and where the rollouts stop
(:mod:`gridlbc.simulate`). An exit at an edge is a region beyond it (``Box([hi, -inf], [inf,
inf])``). A scheme that meets a boundary it does not implement raises (:func:`require`), so a
new member cannot silently reflect.
"""

from __future__ import annotations

import enum

from .grid import Grid


class Boundary(enum.Enum):
    """The behaviour of the state at the ends of an axis."""

    PERIODIC = "periodic"
    """The axis wraps around: no ends."""
    REFLECTING = "reflecting"
    """A state constraint: jumps out of the box are suppressed, feet are clamped to it."""


CLOSED_DEFAULT = Boundary.REFLECTING
"""The boundary of every closed (non-periodic) axis (the specification's state constraint)."""


def axis_boundaries(grid: Grid) -> tuple[Boundary, ...]:
    """The boundary of each axis of ``grid``: periodic, or :data:`CLOSED_DEFAULT`."""
    return tuple(Boundary.PERIODIC if ax.periodic else CLOSED_DEFAULT for ax in grid.axes)


def require(grid: Grid, supported: tuple[Boundary, ...], where: str) -> tuple[Boundary, ...]:
    """The axes' boundaries (:func:`axis_boundaries`), or a ``NotImplementedError`` naming
    ``where`` if one of them is not among ``supported``."""
    boundaries = axis_boundaries(grid)
    for k, boundary in enumerate(boundaries):
        if boundary not in supported:
            raise NotImplementedError(
                f"{where} does not implement a {boundary.value} boundary (axis {k}); it supports "
                f"{', '.join(b.value for b in supported)}"
            )
    return boundaries
