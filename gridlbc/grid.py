"""Tensor-product grids over a box in state space.

An :class:`Axis` with ``n`` nodes on ``[lo, hi]`` has spacing ``h = (hi - lo) / (n - 1)`` and nodes
``lo + i h`` for ``i = 0 … n-1``. A *periodic* axis (an angle) has no duplicate end node: its
period is ``hi - lo = n h``, so ``h = (hi - lo) / n`` and ``hi`` itself is the same point as ``lo``.

Nodes are numbered in C order (the last axis varies fastest): node ``(i_0, …, i_{d-1})`` has flat
index ``Σ_k i_k s_k`` with strides ``s_{d-1} = 1``, ``s_k = s_{k+1} n_{k+1}``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Axis:
    """One coordinate axis of a grid.

    Parameters
    ----------
    lo, hi : float
        Bounds of the axis, ``lo < hi``. On a periodic axis ``hi - lo`` is the period (for an angle
        measured from the upright, ``(-π, π)``).
    n : int
        Number of nodes, at least 3.
    periodic : bool
        Whether the axis wraps around (period ``hi - lo``, no duplicate end node).
    name : str, optional
        Label used in plots and messages.
    """

    lo: float
    hi: float
    n: int
    periodic: bool = False
    name: str | None = None

    def __post_init__(self):
        lo, hi = float(self.lo), float(self.hi)
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ValueError(f"Axis bounds must be finite, got lo={self.lo!r}, hi={self.hi!r}")
        if not lo < hi:
            raise ValueError(f"Axis needs lo < hi, got lo={lo}, hi={hi}: swap or widen the bounds")
        if isinstance(self.n, bool) or not isinstance(self.n, (int, np.integer)):
            raise TypeError(f"Axis n must be an integer number of nodes, got {self.n!r}")
        if self.n < 3:
            raise ValueError(f"Axis n must be at least 3 nodes, got n={self.n}")
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)
        object.__setattr__(self, "n", int(self.n))
        object.__setattr__(self, "periodic", bool(self.periodic))

    @property
    def spacing(self) -> float:
        """Node spacing h: ``(hi-lo)/n`` on a periodic axis, ``(hi-lo)/(n-1)`` otherwise."""
        return (self.hi - self.lo) / (self.n if self.periodic else self.n - 1)

    @property
    def period(self) -> float:
        """``hi - lo`` on a periodic axis, ``inf`` otherwise."""
        return self.hi - self.lo if self.periodic else math.inf

    def points(self) -> np.ndarray:
        """The node coordinates, shape ``(n,)``."""
        return self.lo + self.spacing * np.arange(self.n)


@dataclass(frozen=True)
class Grid:
    """A tensor-product grid: the product of its axes, nodes in C order.

    Parameters
    ----------
    axes : Axis or sequence of Axis
        One :class:`Axis` per state coordinate, in the state's order.
    """

    axes: tuple[Axis, ...]
    _lo: np.ndarray = field(init=False, repr=False, compare=False)
    _kernel: tuple = field(init=False, repr=False, compare=False)

    def __init__(self, axes):
        axes = tuple(axes) if not isinstance(axes, Axis) else (axes,)
        if not axes:
            raise ValueError("Grid needs at least one Axis")
        for k, ax in enumerate(axes):
            if not isinstance(ax, Axis):
                raise TypeError(f"Grid axes[{k}] must be an Axis, got {type(ax).__name__}")
        object.__setattr__(self, "axes", axes)
        object.__setattr__(self, "_lo", np.array([a.lo for a in axes]))
        kernel = (
            self._lo,
            np.array([a.spacing for a in axes]),
            np.array([a.n for a in axes], dtype=np.int64),
            np.array([math.prod(a.n for a in axes[k + 1 :]) for k in range(len(axes))]),
            np.array([a.periodic for a in axes]),
        )
        object.__setattr__(self, "_kernel", kernel)

    def __eq__(self, other):
        return isinstance(other, Grid) and self.axes == other.axes

    def __hash__(self):
        return hash(self.axes)

    @property
    def ndim(self) -> int:
        return len(self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(a.n for a in self.axes)

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    @property
    def spacing(self) -> np.ndarray:
        """Node spacings, shape ``(d,)``."""
        return np.array([a.spacing for a in self.axes])

    @property
    def lo(self) -> np.ndarray:
        return self._lo.copy()

    @property
    def hi(self) -> np.ndarray:
        return np.array([a.hi for a in self.axes])

    @property
    def periodic(self) -> np.ndarray:
        """Boolean mask of the periodic axes, shape ``(d,)``."""
        return np.array([a.periodic for a in self.axes])

    @property
    def periods(self) -> np.ndarray:
        """``hi - lo`` on periodic axes, ``inf`` on the others, shape ``(d,)``."""
        return np.array([a.period for a in self.axes])

    @property
    def strides(self) -> np.ndarray:
        """Flat-index strides of the C-ordered node numbering, shape ``(d,)``."""
        shape = self.shape
        return np.array([math.prod(shape[k + 1 :]) for k in range(self.ndim)], dtype=np.int64)

    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(lo, spacing, shape, strides, periodic)``: the grid as the arrays compiled kernels
        take (float64, float64, int64, int64, bool; each of shape ``(d,)``), made once with the
        grid and shared by every caller, which must not change them."""
        return self._kernel

    def points(self) -> list[np.ndarray]:
        """Node coordinates per axis."""
        return [a.points() for a in self.axes]

    def nodes(self) -> np.ndarray:
        """All node coordinates in C order, shape ``(size, d)``."""
        mesh = np.meshgrid(*self.points(), indexing="ij")
        return np.stack([m.ravel() for m in mesh], axis=1)

    def node_coordinates(self, flat) -> np.ndarray:
        """Coordinates of nodes given by flat index, shape ``(..., d)``."""
        flat = np.asarray(flat, dtype=np.int64)
        multi = np.unravel_index(flat, self.shape)
        return np.stack(
            [self._lo[k] + self.axes[k].spacing * multi[k] for k in range(self.ndim)], axis=-1
        )

    def nearest_node(self, x) -> np.ndarray:
        """The multi-index of the node nearest each state ``(N, d)``, ``(N, d)`` int64: across the
        seam on a periodic axis, the end node beyond either end of a closed one."""
        n = np.array(self.shape)
        index = np.rint((np.asarray(x, dtype=float) - self._lo) / self.spacing).astype(np.int64)
        return np.where(self.periodic, index % n, np.clip(index, 0, n - 1))

    def wrap(self, x) -> np.ndarray:
        """Map states into the box: periodic coordinates modulo their period into ``[lo, hi)``.

        Non-periodic coordinates are left as they are (see :meth:`clamp`).
        """
        x = np.array(x, dtype=float, copy=True)
        for k, ax in enumerate(self.axes):
            if ax.periodic:
                x[..., k] = ax.lo + np.mod(x[..., k] - ax.lo, ax.period)
        return x

    def clamp(self, x) -> np.ndarray:
        """Wrap periodic coordinates and clip the others to ``[lo, hi]``."""
        x = self.wrap(x)
        for k, ax in enumerate(self.axes):
            if not ax.periodic:
                np.clip(x[..., k], ax.lo, ax.hi, out=x[..., k])
        return x

    def check_states(self, x, name: str = "x") -> np.ndarray:
        """Validate states for this grid and return them as a float ``(N, d)`` array.

        A single state may be given as shape ``(d,)``. Raises a ``ValueError`` naming ``name`` on a
        wrong trailing dimension or a non-finite coordinate.
        """
        return check_states(x, self.ndim, name, f"this {self.ndim}-dimensional grid")

    def reshape(self, values: np.ndarray) -> np.ndarray:
        """View flat nodal values ``(..., size)`` as ``(..., *shape)``."""
        return values.reshape(values.shape[:-1] + self.shape)

    def node_values(self, function) -> np.ndarray:
        """``function(x)`` at every node, ``(size,)``, evaluated
        on :func:`~gridlbc.grid.flat_chunks` of nodes (the full ``(size, d)`` node array is never
        built)."""
        out = np.empty(self.size)
        for flat in flat_chunks(self.size):
            out[flat[0] : flat[-1] + 1] = function(self.node_coordinates(flat))
        return out

    def describe(self) -> str:
        """Short text such as ``'256×257 (periodic, -)'``."""
        dims = "×".join(str(n) for n in self.shape)
        kinds = ", ".join("periodic" if a.periodic else "-" for a in self.axes)
        return f"{dims} ({kinds})"


NODE_CHUNK = 1 << 14
"""Nodes per call of a system's or cost's function in chunked evaluations: small enough that the
allocator reuses the chunk's temporaries (first writes to fresh memory are slow)."""


def flat_chunks(stop: int, start: int = 0):
    """Consecutive ranges of the flat node indices start … stop − 1, :data:`NODE_CHUNK` at a
    time."""
    for first in range(start, stop, NODE_CHUNK):
        yield np.arange(first, min(first + NODE_CHUNK, stop))


def check_states(x, ndim: int, name: str = "x", where: str = "this state space") -> np.ndarray:
    """States ``x`` as a finite float ``(N, ndim)`` array (one state may be ``(ndim,)``).

    Raises a ``ValueError`` naming ``name`` and ``where`` on a wrong trailing dimension or a
    non-finite coordinate.
    """
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != ndim:
        raise ValueError(
            f"{name} must have shape (N, {ndim}) or ({ndim},) for {where}, got shape {np.shape(x)}"
        )
    if not np.all(np.isfinite(arr)):
        bad = int(np.argmax(~np.all(np.isfinite(arr), axis=1)))
        raise ValueError(f"{name} has a non-finite coordinate (first at row {bad}: {arr[bad]})")
    return arr
