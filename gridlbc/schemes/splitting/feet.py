"""Characteristic feet: where the drift carries each node over one step, and how that is stored.

The second-order (midpoint) foot of node x over a step Δt is

    X(x) = x + Δt a(x + ½Δt a(x)),

wrapped on periodic axes and clamped to the box on closed ones (the reflecting constraint,
:mod:`gridlbc.boundary`), and located on the Kuhn simplex of its cell
(:func:`gridlbc.interpolate.barycentric`): d+1 vertices and non-negative weights summing to one.

The feet are computed once per solve, in chunks, and stored compactly (:data:`FEET_LAYOUTS`):
``"compact"`` keeps per node the base corner (int32), the index (uint16) of its simplex's shape
(axis order and periodic seams; a small table holds the d+1 vertex offsets of each shape) and the
sorted fractional coordinates quantised to 1/65535 of a cell (uint16): 6 + 2d bytes per node,
decoded inside the kernels. The quantisation moves each foot by at most 1/131070 of a cell (far
below the O(h²) interpolation error) and keeps the weights exactly non-negative and summing to
one, so linearity and monotonicity are exact. ``"table"`` stores the d+1 vertex indices (int32)
and weights (float32) explicitly: 8(d+1) bytes.
"""

from __future__ import annotations

import numpy as np

from ... import boundary
from ...backends import QUANTUM
from ...backends.numba.feet import encode_compact_kernel
from ...backends.numba.interpolation import kuhn_kernel
from ...boundary import Boundary
from ...grid import Grid, flat_chunks
from ...problem import Problem

FEET_LAYOUTS = ("compact", "table")
"""How the characteristic feet are stored (see the module docstring)."""

MAX_COMPACT_DIM = 8
"""The largest dimension of the compact layout (its packed simplex shape holds 4 bits per walk
step); beyond it the feet are stored as a table."""

FEET_BATCH = 1 << 20
"""Nodes per call of the compiled foot encoding (bounds the setup memory)."""


def foot(problem: Problem, x: np.ndarray, dt) -> np.ndarray:
    """The second-order (midpoint) foot X(x) = x + Δt a(x + ½Δt a(x)) of the states x after a
    time dt (a float, or one per state as an array ``(N, 1)``), wrapped and clamped."""
    grid, system = problem.require_grid("the characteristic feet"), problem.system
    midpoint = grid.clamp(x + 0.5 * dt * np.asarray(system.drift(x), dtype=float))
    return grid.clamp(x + dt * np.asarray(system.drift(midpoint), dtype=float))


def foot_chunks(problem: Problem, dt: float, start: int = 0, stop: int | None = None):
    """Feet X(x) (:func:`foot`) of the nodes start … stop − 1 (default: all), in chunks."""
    grid = problem.require_grid("the characteristic feet")
    for flat in flat_chunks(grid.size if stop is None else stop, start):
        yield flat, foot(problem, grid.node_coordinates(flat), dt)


def compact_feet(grid: Grid, idx: np.ndarray, weights: np.ndarray):
    """Compact form of barycentric vertices and weights ``(M, d+1)`` (see the module docstring).

    Returns the base corners (int32), the packed simplex shapes (uint32: for each walk step j the
    position in :func:`walk_steps` of its flat offset, 4 bits each) and the sorted fractional
    coordinates f_j = Σ_{i>j} w_i quantised to 1/65535 (uint16, non-increasing in j).
    """
    steps = np.searchsorted(walk_steps(grid), np.diff(idx, axis=1))
    shape = np.zeros(idx.shape[0], dtype=np.uint32)
    for j in range(grid.ndim):
        shape |= steps[:, j].astype(np.uint32) << np.uint32(4 * j)
    tail = np.cumsum(weights[:, :0:-1], axis=1)[:, ::-1]  # f_j = w_{j+1} + … + w_d
    frac = np.rint(np.clip(tail[:, : grid.ndim], 0.0, 1.0) * QUANTUM).astype(np.uint16)
    return idx[:, 0].astype(np.int32), shape, frac


def shape_codes(grid: Grid, shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(shapes, return_inverse=True)`` for the packed simplex shapes: by a table of
    all 16^d packed values when that is small (one pass instead of a sort), else by sorting."""
    if 16**grid.ndim > 1 << 20:
        return np.unique(shapes, return_inverse=True)
    present = np.bincount(shapes, minlength=16**grid.ndim) > 0
    rank = np.cumsum(present) - 1
    return np.flatnonzero(present).astype(np.uint32), rank[shapes]


def walk_steps(grid: Grid) -> np.ndarray:
    """The flat offsets of one step of the Kuhn walk, sorted: +s_k, or −(n_k − 1) s_k across the
    seam of a periodic axis."""
    strides = grid.strides
    wraps = [-(ax.n - 1) * strides[k] for k, ax in enumerate(grid.axes) if ax.periodic]
    return np.sort(np.concatenate([strides, np.array(wraps, dtype=np.int64)]))


def vertex_offsets(grid: Grid, shapes: np.ndarray) -> np.ndarray:
    """Offsets of the d+1 simplex vertices from the base corner per packed shape, ``(S, d+1)``."""
    walk = walk_steps(grid)
    offsets = np.zeros((shapes.size, grid.ndim + 1), dtype=np.int64)
    for j in range(grid.ndim):
        offsets[:, j + 1] = offsets[:, j] + walk[(shapes.astype(np.int64) >> (4 * j)) & 15]
    return offsets


def walk_axes(grid: Grid, offsets: np.ndarray) -> np.ndarray:
    """The axis of each walk step per packed shape, ``(S, d)``, from the vertex offsets
    (a step is +s_a, or −(n_a − 1) s_a across a periodic seam)."""
    steps = np.diff(offsets, axis=1)
    axes = np.zeros(steps.shape, dtype=np.int64)
    for a, ax in enumerate(grid.axes):
        stride = grid.strides[a]
        axes[(steps == stride) | (ax.periodic & (steps == -(ax.n - 1) * stride))] = a
    return axes


def characteristic_feet(problem: Problem, dt: float) -> np.ndarray:
    """Feet of all nodes, ``(N, d)`` (plain numpy, for tests and plots)."""
    return np.concatenate([feet for _, feet in foot_chunks(problem, dt)])


def feet_bytes_per_node(ndim: int, layout: str) -> int:
    """Memory of the stored feet per node for a layout (see :data:`FEET_LAYOUTS`)."""
    return 6 + 2 * ndim if layout == "compact" else 8 * (ndim + 1)


class Feet:
    """The characteristic feet of every node of ``problem``'s grid over a step ``dt``, stored in
    ``layout`` (:data:`FEET_LAYOUTS`; the compact one falls back to the table beyond
    :data:`MAX_COMPACT_DIM` dimensions). ``arrays`` lists what is stored: base corners, shape
    codes, quantised fractions and the shapes' vertex offsets (compact), or vertex indices and
    weights (table)."""

    def __init__(self, problem: Problem, dt: float, layout: str = "compact"):
        if layout not in FEET_LAYOUTS:
            raise ValueError(f"feet must be one of {FEET_LAYOUTS}, got {layout!r}")
        grid = problem.require_grid("the characteristic feet")
        boundary.require(grid, (Boundary.PERIODIC, Boundary.REFLECTING), "the splitting's feet")
        if layout == "compact" and grid.ndim > MAX_COMPACT_DIM:
            layout = "table"
        self.grid, self.layout = grid, layout
        N, d = grid.size, grid.ndim
        if self.layout == "compact":
            self.base = np.empty(N, dtype=np.int32)
            shapes = np.empty(N, dtype=np.uint32)
            self.frac = np.empty((N, d), dtype=np.uint16)
        else:
            self.idx = np.empty((N, d + 1), dtype=np.int32)
            self.weights = np.empty((N, d + 1), dtype=np.float32)
        batch = min(N, FEET_BATCH)
        feet = np.empty((batch, d))
        if self.layout == "table":
            idx = np.empty((batch, d + 1), dtype=np.int64)
            weights = np.empty((batch, d + 1))
        walk = walk_steps(grid)
        for start in range(0, N, batch):
            stop = min(start + batch, N)
            m = stop - start
            for flat, chunk in foot_chunks(problem, dt, start, stop):
                feet[flat[0] - start : flat[-1] + 1 - start] = chunk
            finite = np.isfinite(feet[:m]).all(axis=1)
            if not finite.all():
                node = start + int(np.argmin(finite))
                raise ValueError(
                    f"the characteristic foot of node {node} (x = {grid.node_coordinates(node)}) is "
                    f"not finite: {type(problem.system).__name__}.drift returned a non-finite value"
                )
            rows = slice(start, stop)
            if self.layout == "compact":
                encode_compact_kernel(
                    feet[:m],
                    *grid.kernel_arrays(),
                    walk,
                    self.base[rows],
                    shapes[rows],
                    self.frac[rows],
                )
            else:
                kuhn_kernel(feet[:m], *grid.kernel_arrays(), idx[:m], weights[:m])
                self.idx[rows], self.weights[rows] = idx[:m], weights[:m]
        if self.layout == "compact":
            distinct, ids = shape_codes(grid, shapes)
            self.code = ids.astype(np.uint16 if distinct.size <= 2**16 else np.uint32)
            self.offsets = vertex_offsets(grid, distinct)
            self.arrays = [self.base, self.code, self.frac, self.offsets]
        else:
            self.arrays = [self.idx, self.weights]

    @staticmethod
    def estimate_bytes(grid: Grid, layout: str = "compact") -> int:
        """Memory of the stored feet and of their encoding's working arrays on ``grid``."""
        batch = min(grid.size, FEET_BATCH) * (24 * grid.ndim + 16)  # feet, vertices, weights
        return grid.size * feet_bytes_per_node(grid.ndim, layout) + batch
