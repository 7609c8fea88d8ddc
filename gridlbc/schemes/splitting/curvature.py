"""The curvature term of the fitted drift.

Averaging log φ linearly over the simplex misses its curvature: for quadratic ℓ = log φ with
index-unit Hessian H, Σ_j w_j ℓ(y_j) = ℓ(X) + ½ Σ_ab M_ab H_ab with the simplex's second moments
M_ab = Σ_j w_j (y_j − X)_a (y_j − X)_b, which on the Kuhn simplex are min(f_a, f_b) − f_a f_b for
the foot's fractional coordinates f in its cell. Where v is convex that bias overestimates v by
about h² v''/8 per step, accumulating over the steps (pessimism of order h²/Δt). The fitted drift
therefore uses

    log φ̄(X) = Σ_j w_j ℓ(y_j) − ½ Σ_ab M_ab H_ab,

H the central second differences of ℓ at the simplex's vertex of largest weight, and the result
limited to [min_j ℓ(y_j), max_j ℓ(y_j)] over the vertices of positive weight (a face's range when
the foot lies on it, so that mirror images stay mirror images) so that it creates no new extrema
(stable where ℓ is kinked; at a smooth maximum inside a cell it costs the bias back there). φ̄ is
still a positive function of φ alone, so for a fixed reference the step stays linear and
non-negative in z, and exact where z ∝ φ; φ̄ is now also exact for quadratic log φ.
"""

from __future__ import annotations

import numpy as np

from ...backends.numba.curvature import curvature_compact_kernel, curvature_table_kernel
from ...grid import Grid
from .feet import Feet, walk_axes


def hessian_pairs(ndim: int) -> np.ndarray:
    """``pairs[a, b]``: the column of the index-unit Hessian component ∂_a∂_b in the curvature
    kernels' scratch (:mod:`gridlbc.backends.numba.curvature`; symmetric, d(d+1)/2 columns)."""
    pairs = np.empty((ndim, ndim), dtype=np.int64)
    m = 0
    for a in range(ndim):
        for b in range(a, ndim):
            pairs[a, b] = pairs[b, a] = m
            m += 1
    return pairs


def stencils(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Where the curvature kernels (:mod:`gridlbc.backends.numba.curvature`) centre the Hessian's
    stencil at each node, as (``place``, ``stencils``):
    ``place`` (N,) numbers the node's position along each axis (0 inside, 1 at the first node,
    2 at the last) as the base-3 digits Σ_a 3^a position_a, and row ``place`` of ``stencils``
    ``(3^d, 1 + 2d)`` holds the stencil's centre offset from the node, then the offsets of its
    +e_a and −e_a neighbours from the centre: ±s_a, wrapped on a periodic axis; on a closed axis
    the centre is moved in from an end to its neighbour, and an axis of fewer than 3 nodes has
    no neighbours (offsets 0). One byte per node up to d = 5 (two up to 10), against d(d+1)/2
    numbers per node for a stored Hessian."""
    d = grid.ndim
    place = np.zeros(grid.shape, dtype=np.min_scalar_type(3**d - 1))
    for a, n in enumerate(grid.shape):
        position = np.zeros(n, dtype=place.dtype)
        position[0], position[-1] = 1, 2
        place += (
            (3**a * position).astype(place.dtype).reshape([-1 if b == a else 1 for b in range(d)])
        )
    stencils = np.zeros((3**d, 1 + 2 * d), dtype=np.int64)
    for row in range(3**d):
        for a, (n, s, periodic) in enumerate(
            zip(grid.shape, grid.strides, grid.periodic, strict=True)
        ):
            position = row // 3**a % 3
            if periodic:
                up, down = (
                    s if position != 2 else -(n - 1) * s,
                    -s if position != 1 else (n - 1) * s,
                )
            elif n < 3:
                up = down = 0
            else:
                up, down = s, -s
                stencils[row, 0] += {0: 0, 1: s, 2: -s}[position]
            stencils[row, 1 + a], stencils[row, 1 + d + a] = up, down
    return place.reshape(-1), stencils


def hessian_columns(walk_axes: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """``columns[c, k, l]`` = the Hessian column (:func:`hessian_pairs`) of ∂_{π_k}∂_{π_l}
    for the walk axes π = ``walk_axes[c]`` of each simplex shape c (:func:`walk_axes`)."""
    return np.ascontiguousarray(pairs[walk_axes[:, :, None], walk_axes[:, None, :]])


class CurvatureCorrection:
    """The curvature term c(X) = −½ Σ_ab M_ab(X) H_ab at every node's foot X of ``feet``
    (the module docstring): call ``correction(ell, out, add_mean)``. The stencils' places are
    gathered by the first call and reused by the later ones (the feet are fixed)."""

    def __init__(self, feet: Feet):
        self.feet = feet
        # where the Hessian's stencils sit (stencils(); first call)
        self._stencils: tuple[np.ndarray, np.ndarray] | None = None
        self._scratch: np.ndarray | None = None  # the default output (first call without one)

    def __call__(
        self, ell: np.ndarray, out: np.ndarray | None = None, add_mean: bool = False
    ) -> np.ndarray:
        """c at every foot for ℓ = ``ell`` ``(N,)``; with ``add_mean``, log φ̄ = Σ_j w_j ℓ(y_j) + c
        itself (the fitted log drift in one pass). Written into ``out`` ``(N,)``, by default a
        scratch array (overwritten by the next call), which is returned."""
        feet, grid = self.feet, self.feet.grid
        record = self._stencils is None
        if self._stencils is None:
            self._stencils = stencils(grid)
            self._places = np.empty(
                grid.size if feet.layout == "compact" else 0, self._stencils[0].dtype
            )
            self._pairs = hessian_pairs(grid.ndim)
            if feet.layout == "compact":
                self._columns = hessian_columns(walk_axes(grid, feet.offsets), self._pairs)
        if out is None:
            if self._scratch is None:
                self._scratch = np.empty(grid.size)
            out = self._scratch
        place, stencil_rows = self._stencils
        if feet.layout == "compact":
            curvature_compact_kernel(
                ell,
                feet.base,
                feet.code,
                feet.frac,
                feet.offsets,
                self._columns,
                place,
                stencil_rows,
                record,
                self._places,
                add_mean,
                out,
            )
        else:
            curvature_table_kernel(
                ell,
                feet.idx,
                feet.weights,
                place,
                stencil_rows,
                np.array(grid.shape, dtype=np.int64),
                grid.strides,
                self._pairs,
                add_mean,
                out,
            )
        return out
