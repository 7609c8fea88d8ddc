"""Sets of states: the exit sets E of first-exit problems (SPEC §9; docs page :doc:`first_exit`).

A region is anything that answers which of ``N`` states ``(N, d)`` lie in it with a boolean mask
``(N,)``: one of the shapes here, their union ``a | b``, or any callable of that form, e.g.
``lambda x: x[:, 0] >= 0.45`` (the mountain car's flag). The shapes here know their geometry,
so :class:`Ball` measures distance to the nearest image on periodic axes, like
:class:`gridlbc.costs.Quadratic` does, and a :class:`Box` wraps across a periodic axis's seam, once
a :class:`gridlbc.Problem` gives them the periods.

They also know how far a state outside them is from their boundary and in which direction
(:meth:`RegionBase.boundary_distance`: exact for boxes and round balls, to first order near the
boundary of an ellipsoid). Rollouts use it to catch the paths that enter the region between two
time steps (the Brownian-bridge crossing probability, :mod:`gridlbc.simulate`); a plain callable
region is checked at the steps only. And they find a point of themselves in any box they meet
(:meth:`RegionBase.meeting_points`), so that a part of the exit set between the nodes of a grid,
however thin, is found and warned of (:func:`gridlbc.accuracy.missed_exit`); a plain callable
is sampled there, and a part thinner than the samples' spacing is missed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .costs import wrap_difference
from .grid import Grid
from .interpolate import interpolate


def _vector(name: str, value: ArrayLike, allow_inf: bool = False) -> np.ndarray:
    v = np.atleast_1d(np.asarray(value, dtype=float))
    if v.ndim != 1 or np.any(np.isnan(v)) or (not allow_inf and not np.all(np.isfinite(v))):
        raise ValueError(
            f"{name} must be a finite vector (one entry per coordinate), got {value!r}"
        )
    return v


class RegionBase:
    """What the shapes share: a union by ``|`` and a description."""

    def __call__(self, x: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def __or__(self, other) -> Union:
        return Union((self, other))

    def with_periods(self, periods) -> RegionBase:
        """The same region on a state space with these periods (``inf`` where not periodic)."""
        return self

    def boundary_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """For states ``x`` ``(N, d)`` outside the region: their distance to it ``(N,)`` and the
        unit outward normal of its boundary there ``(N, d)`` (so ``x − distance · normal`` is
        the nearest point of the region)."""
        raise NotImplementedError

    def segment_meets(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Whether the straight segment from ``a`` to ``b`` (``(N, d)`` each) meets the region,
        ``(N,)``. It is the mean path of a step's Brownian bridge, and the whole path along the
        axes without noise: a path can cross a set thinner than a step along such an axis with
        both of the step's ends outside it (:mod:`gridlbc.simulate`)."""
        raise NotImplementedError

    def meeting_points(self, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
        """For the boxes [lower_i, upper_i] (``(N, d)`` each, finite): a point of each box
        ``(N, d)`` that lies in the region wherever the region meets that box, however thinly
        (elsewhere a point of the box outside it). The check for an exit set narrower than a
        cell (:func:`gridlbc.accuracy.exits.missed_points`) finds every such part of a shape this
        way, where a plain callable can only be sampled."""
        raise NotImplementedError


@dataclass(frozen=True, eq=False, init=False)
class Box(RegionBase):
    """The axis-aligned box {x : lower ≤ x ≤ upper}; ``±inf`` leaves a side open, so
    ``Box([0.45, -inf], [inf, inf])`` is the half-space x₀ ≥ 0.45.

    On a periodic axis whose two sides are finite the box wraps: x lies in it where one of its
    images x + kP does, so ``Box([π − 0.2, -0.5], [π + 0.2, 0.5])`` on a pendulum's angle holds
    both sides of the seam at ±π. Each method reads the image nearest the box's middle
    (:meth:`image`), and a box at least a period wide holds the whole circle. A side left open on a
    periodic axis reads the coordinate as given (in the grid's range, where the solver and the
    rollouts keep it).

    Parameters
    ----------
    lower, upper : array_like (d,)
        The corners (``-inf``/``inf`` allowed).
    periods : array_like (d,), optional
        Filled in by :class:`gridlbc.Problem` from its periodic axes.
    """

    lower: np.ndarray
    upper: np.ndarray
    periods: np.ndarray | None

    def __init__(self, lower: ArrayLike, upper: ArrayLike, periods: ArrayLike | None = None):
        lo, hi = _vector("Box lower", lower, True), _vector("Box upper", upper, True)
        if lo.shape != hi.shape:
            raise ValueError(f"Box lower and upper differ in length: {lo.size} and {hi.size}")
        if np.any(lo > hi):
            raise ValueError(f"Box lower must not exceed upper, got {lo} and {hi}")
        object.__setattr__(self, "lower", lo)
        object.__setattr__(self, "upper", hi)
        p = (
            None
            if periods is None
            else np.broadcast_to(_vector("periods", periods, True), lo.shape)
        )
        object.__setattr__(self, "periods", p)

    @property
    def dim(self) -> int:
        return self.lower.size

    def with_periods(self, periods) -> Box:
        return Box(self.lower, self.upper, periods)

    def image(self, x: np.ndarray) -> np.ndarray:
        """``x`` moved by whole periods to its image nearest the box's middle, on the periodic
        axes where both sides are finite (elsewhere as given)."""
        if self.periods is None:
            return x
        wraps = np.isfinite(self.periods) & np.isfinite(self.lower) & np.isfinite(self.upper)
        if not wraps.any():
            return x
        middle = np.zeros_like(self.lower)  # (an open side's −inf + inf is no middle)
        middle[wraps] = 0.5 * (self.lower[wraps] + self.upper[wraps])
        nearest = middle + wrap_difference(x - middle, np.where(wraps, self.periods, np.inf))
        return np.where(wraps, nearest, x)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = self.image(x)
        return np.all((x >= self.lower) & (x <= self.upper), axis=1)

    def boundary_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Exact: the nearest point is x's image (:meth:`image`) clipped to the box."""
        x = self.image(x)
        return _towards(x, np.clip(x, self.lower, self.upper))

    def segment_meets(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Exact: the parameters s ∈ [0, 1] at which a + s (b − a) lies between an axis's two
        sides form an interval; the segment meets the box where the intervals of all axes
        overlap (an axis the segment does not move along gives all of [0, 1] or nothing). The
        segment is moved with ``a`` to ``a``'s image (:meth:`image`)."""
        shift = self.image(a) - a
        a, step = a + shift, b - a
        moving = step != 0
        with np.errstate(divide="ignore", invalid="ignore"):
            s_lower = np.where(moving, (self.lower - a) / np.where(moving, step, 1.0), -np.inf)
            s_upper = np.where(moving, (self.upper - a) / np.where(moving, step, 1.0), np.inf)
        first = np.max(np.minimum(s_lower, s_upper), axis=1, initial=0.0)
        last = np.min(np.maximum(s_lower, s_upper), axis=1, initial=1.0)
        between = np.all(moving | ((a >= self.lower) & (a <= self.upper)), axis=1)
        return between & (first <= last)

    def meeting_points(self, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
        """Exact: the middle of the two boxes' intersection, where they meet (per axis the
        overlap of [lower, upper], moved with its middle to that point's image, with the box's
        sides)."""
        middle = 0.5 * (lower + upper)
        shift = self.image(middle) - middle
        low, high = np.maximum(lower + shift, self.lower), np.minimum(upper + shift, self.upper)
        return np.where(low <= high, 0.5 * (low + high) - shift, lower)

    def __repr__(self) -> str:
        return f"Box({self.lower.tolist()}, {self.upper.tolist()})"


@dataclass(frozen=True, eq=False, init=False)
class Ball(RegionBase):
    """The ellipsoid {x : Σ_k ((x_k − c_k)/r_k)² ≤ 1}, to the nearest image on periodic axes.

    Parameters
    ----------
    center : array_like (d,)
        c.
    radius : float or array_like (d,)
        r, one radius or one per coordinate (``inf`` ignores a coordinate: a slab).
    periods : array_like (d,), optional
        Filled in by :class:`gridlbc.Problem` from its periodic axes.
    """

    center: np.ndarray
    radius: np.ndarray
    periods: np.ndarray | None

    def __init__(self, center: ArrayLike, radius: ArrayLike, periods: ArrayLike | None = None):
        c = _vector("Ball center", center)
        r = np.broadcast_to(_vector("Ball radius", radius, True), c.shape).copy()
        if np.any(r <= 0):
            raise ValueError(f"Ball radius must be positive, got {radius!r}")
        object.__setattr__(self, "center", c)
        object.__setattr__(self, "radius", r)
        p = None if periods is None else np.broadcast_to(_vector("periods", periods, True), c.shape)
        object.__setattr__(self, "periods", p)

    @property
    def dim(self) -> int:
        return self.center.size

    def with_periods(self, periods) -> Ball:
        return Ball(self.center, self.radius, periods)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        diff = x - self.center
        if self.periods is not None:
            diff = wrap_difference(diff, self.periods)
        return np.sum((diff / self.radius) ** 2, axis=1) <= 1.0

    def boundary_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """From the level set ρ(x) = √(Σ_k ((x_k − c_k)/r_k)²) = 1: normal ∇ρ / ‖∇ρ‖ and distance
        (ρ − 1) / ‖∇ρ‖, exact for a round ball and to first order in the distance otherwise."""
        diff = x - self.center
        if self.periods is not None:
            diff = wrap_difference(diff, self.periods)
        scaled = diff / self.radius
        rho = np.maximum(np.sqrt(np.sum(scaled**2, axis=1)), np.finfo(float).tiny)
        gradient = scaled / self.radius / rho[:, None]
        size = np.maximum(np.linalg.norm(gradient, axis=1), np.finfo(float).tiny)
        return np.maximum(rho - 1.0, 0.0) / size, gradient / size[:, None]

    def segment_meets(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Exact in the ellipsoid's own metric: the point a + s (b − a), s ∈ [0, 1], nearest the
        centre's image nearest ``a`` minimises a quadratic in s, and lies in the ellipsoid
        exactly where the segment meets it."""
        diff = a - self.center
        if self.periods is not None:
            diff = wrap_difference(diff, self.periods)
        start, step = diff / self.radius, (b - a) / self.radius
        length = np.sum(step**2, axis=1)
        s = -np.sum(start * step, axis=1) / np.maximum(length, np.finfo(float).tiny)
        nearest = start + np.clip(s, 0.0, 1.0)[:, None] * step
        return np.sum(nearest**2, axis=1) <= 1.0

    def meeting_points(self, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
        """Exact: the point of each box nearest the centre's nearest image in the ellipsoid's
        own metric Σ_k ((x_k − c_k)/r_k)², which is separable, so that point is the centre
        clipped to the box; it lies in the ellipsoid exactly where the ellipsoid meets the box."""
        middle = 0.5 * (lower + upper)
        diff = middle - self.center
        if self.periods is not None:
            diff = wrap_difference(diff, self.periods)
        return np.clip(middle - diff, lower, upper)

    def __repr__(self) -> str:
        return f"Ball({self.center.tolist()}, {self.radius.tolist()})"


@dataclass(frozen=True, eq=False)
class Union(RegionBase):
    """The union of regions (``a | b``)."""

    parts: tuple

    def with_periods(self, periods) -> Union:
        return Union(tuple(bind_periods(p, periods) for p in self.parts))

    def __call__(self, x: np.ndarray) -> np.ndarray:
        mask = np.zeros(x.shape[0], dtype=bool)
        for part in self.parts:
            mask |= region_mask(part, x)
        return mask

    def boundary_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The nearest part's."""
        parts = [p.boundary_distance(x) for p in self.parts]
        distances = np.stack([d for d, _ in parts])  # (parts, N)
        best = np.argmin(distances, axis=0)
        rows = np.arange(x.shape[0])
        return distances[best, rows], np.stack([n for _, n in parts])[best, rows]

    def meeting_points(self, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
        """A part's meeting point, of the first part that meets each box."""
        out = lower.copy()
        met = np.zeros(len(lower), dtype=bool)
        for part in self.parts:
            points = part.meeting_points(lower, upper)
            new = ~met & region_mask(part, points)
            out[new], met = points[new], met | new
        return out

    def __repr__(self) -> str:
        return " | ".join(repr(p) for p in self.parts)


class GridRegion:
    """An exit set known at the grid nodes (a saved first-exit problem's whose E was a callable,
    :func:`gridlbc.load`; the paths of :func:`gridlbc.accuracy.truncation_gap`): a state lies in
    it where the barycentric interpolation of the nodes' membership is at least ½, so every node
    keeps its own."""

    def __init__(self, grid: Grid, mask, description: str = "a saved exit set"):
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != (grid.size,):
            raise ValueError(f"GridRegion mask must have shape ({grid.size},), got {mask.shape}")
        self.grid, self.mask, self.description = grid, mask, description
        self._membership = mask.astype(float)  # what is interpolated, made once

    def __call__(self, x) -> np.ndarray:
        return interpolate(self.grid, self._membership, x) >= 0.5

    def __repr__(self) -> str:
        return self.description


def _towards(x: np.ndarray, nearest: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance and unit normal from the nearest points."""
    offset = x - nearest
    distance = np.linalg.norm(offset, axis=1)
    return distance, offset / np.maximum(distance, np.finfo(float).tiny)[:, None]


def boundary_parts(region) -> tuple:
    """The shapes whose union ``region`` is (a union's parts, nested unions flattened; a shape
    alone is its own one part)."""
    if isinstance(region, Union):
        return tuple(leaf for part in region.parts for leaf in boundary_parts(part))
    return (region,)


def part_distances(parts, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each of ``parts``' :meth:`RegionBase.boundary_distance` at states ``x`` ``(N, d)``: the
    distances ``(N, K)`` and unit outward normals ``(N, K, d)`` of the K parts (the Brownian
    bridge of :mod:`gridlbc.simulate` judges a crossing into each part, not only into the
    nearest)."""
    found = [part.boundary_distance(x) for part in parts]
    return np.stack([d for d, _ in found], axis=1), np.stack([n for _, n in found], axis=1)


def part_segments(parts, a: np.ndarray, b: np.ndarray, periods=None) -> np.ndarray:
    """Which of ``parts`` (:func:`boundary_parts`) the straight segment from each ``a`` to ``b``
    (``(N, d)`` each) meets, ``(N, K)`` (:meth:`RegionBase.segment_meets`). On periodic axes
    (``periods``, ``inf`` elsewhere) the segment goes the short way round, taken from each end
    in turn, so that the parts on both sides of the seam are seen."""
    step = b - a if periods is None else wrap_difference(b - a, periods)
    ends = [(a, a + step)] + ([(b - step, b)] if np.any(step != b - a) else [])
    met = np.zeros((len(a), len(parts)), dtype=bool)
    for k, part in enumerate(parts):
        if _knows(part, "segment_meets"):  # else a user's shape is judged at the steps only
            for start, end in ends:
                met[:, k] |= part.segment_meets(start, end)
    return met


def has_geometry(region) -> bool:
    """Whether ``region`` knows its boundary (:meth:`RegionBase.boundary_distance`): every one of
    its :func:`boundary_parts` does."""
    return all(_knows(part, "boundary_distance") for part in boundary_parts(region))


def meets_exactly(region) -> bool:
    """Whether ``region`` finds a point of itself in any box it meets
    (:meth:`RegionBase.meeting_points`): the shapes here and their unions."""
    return all(_knows(part, "meeting_points") for part in boundary_parts(region))


def _knows(part, method: str) -> bool:
    """Whether ``part`` is a shape whose class gives :class:`RegionBase`'s ``method``."""
    own = getattr(type(part), method) if isinstance(part, RegionBase) else None
    return own is not None and own is not getattr(RegionBase, method)


def bind_periods(region, periods):
    """``region`` made wrap-aware with ``periods`` where it knows how (:class:`Ball`,
    :class:`Box`)."""
    return region.with_periods(periods) if isinstance(region, RegionBase) else region


def check_region(region, dim: int, name: str = "exit") -> Callable[[np.ndarray], np.ndarray]:
    """``region`` if it is a region of ``dim``-dimensional states: a callable (checked for its
    dimension where it knows it); a clear error otherwise."""
    if not callable(region):
        raise TypeError(
            f"{name} must be a region (gridlbc.regions.Box, Ball, their union a | b) or a "
            f"callable returning a boolean mask (N,) of states (N, d), got "
            f"{type(region).__name__}"
        )
    known = getattr(region, "dim", None)
    if known is not None and known != dim:
        raise ValueError(f"{name} is a region of {known} coordinates but the state has {dim}")
    return region


def region_mask(region, x: np.ndarray, name: str = "exit") -> np.ndarray:
    """The boolean mask ``(N,)`` of the states ``x`` ``(N, d)`` in ``region``, checked."""
    mask = np.asarray(region(x))
    if mask.shape != (x.shape[0],):
        raise ValueError(
            f"{name} returned shape {mask.shape} for {x.shape[0]} states: a region must return "
            "one boolean per state, shape (N,)"
        )
    if mask.dtype != bool:
        if not np.all((mask == 0) | (mask == 1)):
            raise ValueError(f"{name} must return booleans (a mask), got values {mask[:5]}")
        mask = mask.astype(bool)
    return mask
