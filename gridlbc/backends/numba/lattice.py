"""The kernels that carry nodal values to points between the nodes: along one axis onto the
sampling lattice, and at any points (:func:`gridlbc.accuracy.subcell.refine` documents the
rule)."""

from __future__ import annotations

import numpy as np

from .options import jit_inline, jit_parallel, prange


@jit_inline
def _between(before, lo, hi, after, t, first, last, kink):  # pragma: no cover - numba
    """The value at offset t (0 ≤ t ≤ 1, in cells) from node ``lo`` towards ``hi``: ``lo`` at
    t = 0, else the cubic through ``before``, ``lo``, ``hi``, ``after`` (at −1, 0, 1, 2), or the
    quadratic of the smoother side where one side's second difference exceeds the other's
    ``kink`` times, and the only quadratic there is in the first (``first``) or last (``last``)
    cell of a closed axis."""
    if t == 0.0:
        return lo
    left = 0.5 * t * (t - 1.0) * before + (1.0 - t * t) * lo + 0.5 * (t + 1.0) * t * hi
    right = 0.5 * (t - 1.0) * (t - 2.0) * lo - t * (t - 2.0) * hi + 0.5 * t * (t - 1.0) * after
    if first:
        return right
    if last:
        return left
    bent_left = np.abs(before - 2.0 * lo + hi)
    bent_right = np.abs(lo - 2.0 * hi + after)
    if bent_left > kink * bent_right:
        return right
    if bent_right > kink * bent_left:
        return left
    return (
        -t * (t - 1.0) * (t - 2.0) / 6.0 * before
        + 0.5 * (t + 1.0) * (t - 1.0) * (t - 2.0) * lo
        - 0.5 * (t + 1.0) * t * (t - 2.0) * hi
        + (t + 1.0) * t * (t - 1.0) / 6.0 * after
    )


@jit_parallel
def refine_rows(f, rows, m, periodic, kink, out):  # pragma: no cover - numba
    """``out[k, r]``: the reconstruction (:func:`_between`) at lattice point ``rows[r]`` (m
    points per cell: offset o = rows[r] mod m, t = o/m) of the axis whose nodal values are
    ``f[k, :]``."""
    n = f.shape[1]
    for k in prange(f.shape[0]):
        for r in range(rows.shape[0]):
            i = rows[r] // m
            o = rows[r] - i * m
            first = not periodic and i == 0
            last = not periodic and i >= n - 2
            before = f[k, (i - 1) % n] if not first else 0.0
            after = f[k, (i + 2) % n] if not last else 0.0
            out[k, r] = _between(
                before, f[k, i % n], f[k, (i + 1) % n], after, o / m, first, last, kink
            )


@jit_parallel
def rebuild_points(nodes, shape, periodic, positions, kink, out):  # pragma: no cover - numba
    """``out[p]``: the reconstruction of the nodal values ``nodes`` (flat, C order, of a grid of
    ``shape``) at the point whose position in cells along each axis (from the first node) is
    ``positions[p]``: the rule of :func:`_between` along the first axis for each of the 4^(d−1)
    rows of the 4^d nodes around the point, then along the second on those values, and so on,
    as the lattice is reconstructed axis by axis."""
    d = shape.shape[0]
    size = 4**d
    strides = np.ones(d, np.int64)
    for a in range(d - 2, -1, -1):
        strides[a] = strides[a + 1] * shape[a + 1]
    n_points = positions.shape[0]
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        cell = np.empty(d, np.int64)
        t = np.empty(d)
        values = np.empty(size)
        for p in range(b * n_points // n_blocks, (b + 1) * n_points // n_blocks):
            for a in range(d):
                n = shape[a]
                i = int(np.floor(positions[p, a]))
                if periodic[a]:
                    t[a] = positions[p, a] - i
                    i = i % n
                else:
                    i = min(max(i, 0), n - 2)
                    t[a] = min(max(positions[p, a] - i, 0.0), 1.0)
                cell[a] = i
            for s in range(size):
                flat = 0
                rest = s
                for a in range(d - 1, -1, -1):
                    digit = rest % 4
                    rest //= 4
                    j = cell[a] - 1 + digit
                    n = shape[a]
                    j = j % n if periodic[a] else min(max(j, 0), n - 1)
                    flat += j * strides[a]
                values[s] = nodes[flat]
            count = size
            for a in range(d):
                count //= 4
                n = shape[a]
                first = not periodic[a] and cell[a] == 0
                last = not periodic[a] and cell[a] >= n - 2
                for s in range(count):
                    values[s] = _between(
                        values[s],
                        values[count + s],
                        values[2 * count + s],
                        values[3 * count + s],
                        t[a],
                        first,
                        last,
                        kink,
                    )
            out[p] = values[0]


@jit_parallel
def multilinear_points(values, shape, periodic, positions, out):  # pragma: no cover - numba
    """``out[p]``: Σ_j φ_j c_j, the multilinear interpolant of the nodal ``values`` c (flat, C
    order, of a grid of ``shape``) at the point whose position in cells along each axis (from
    the first node) is ``positions[p]``: the cell's first node i = ⌊position⌋ (within 0 … n − 2
    on a closed axis, the nodes i and i + 1 taken modulo n on a periodic one), t = position − i,
    and the 2^d corners added in the order of ``itertools.product((0, 1), repeat=d)``, each
    weighted by the product of t or 1 − t over the axes in turn."""
    d = shape.shape[0]
    strides = np.ones(d, np.int64)
    for a in range(d - 2, -1, -1):
        strides[a] = strides[a + 1] * shape[a + 1]
    n_points = positions.shape[0]
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        cell = np.empty(d, np.int64)
        t = np.empty(d)
        for p in range(b * n_points // n_blocks, (b + 1) * n_points // n_blocks):
            for a in range(d):
                i = int(np.floor(positions[p, a]))
                if not periodic[a]:
                    i = min(max(i, 0), shape[a] - 2)
                cell[a] = i
                t[a] = positions[p, a] - i
            total = 0.0
            for corner in range(1 << d):
                weight = 1.0
                flat = 0
                for a in range(d):
                    up = (corner >> (d - 1 - a)) & 1
                    w = t[a] if up else 1.0 - t[a]
                    weight = w if a == 0 else weight * w
                    flat += ((cell[a] + up) % shape[a]) * strides[a]
                total += weight * values[flat]
            out[p] = total
