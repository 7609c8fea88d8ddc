"""The kernels that carry nodal values to points between the nodes: along one axis onto the
sampling lattice, and at any points (:func:`gridlbc.accuracy.subcell.refine` documents the
rule)."""

from __future__ import annotations

import numpy as np

from .options import jit, jit_inline, jit_parallel, prange


@jit_inline
def _c_strides(shape):  # pragma: no cover - numba
    """The flat index's step for each axis of an array of ``shape`` in C order."""
    d = shape.shape[0]
    strides = np.ones(d, np.int64)
    for a in range(d - 2, -1, -1):
        strides[a] = strides[a + 1] * shape[a + 1]
    return strides


@jit_inline
def _weights(t, w):  # pragma: no cover - numba
    """The coefficients of :func:`_between` at offset t, into ``w`` (10,): the left quadratic's
    on ``before``, ``lo``, ``hi`` (0–2), the right one's on ``lo``, ``hi``, ``after`` (3–5; the
    one on ``hi`` subtracted) and the cubic's on all four (6–9; the one on ``hi`` subtracted),
    each product formed as the rule writes it."""
    w[0] = 0.5 * t * (t - 1.0)
    w[1] = 1.0 - t * t
    w[2] = 0.5 * (t + 1.0) * t
    w[3] = 0.5 * (t - 1.0) * (t - 2.0)
    w[4] = t * (t - 2.0)
    w[5] = 0.5 * t * (t - 1.0)
    w[6] = -t * (t - 1.0) * (t - 2.0) / 6.0
    w[7] = 0.5 * (t + 1.0) * (t - 1.0) * (t - 2.0)
    w[8] = 0.5 * (t + 1.0) * t * (t - 2.0)
    w[9] = (t + 1.0) * t * (t - 1.0) / 6.0


@jit_inline
def _between(before, lo, hi, after, node, w, first, last, kink):  # pragma: no cover - numba
    """The value at offset t (0 ≤ t ≤ 1, in cells) from node ``lo`` towards ``hi``, from the
    coefficients ``w`` of :func:`_weights` at t: ``lo`` at t = 0 (``node``), else the cubic
    through ``before``, ``lo``, ``hi``, ``after`` (at −1, 0, 1, 2),

        −t (t − 1)(t − 2)/6 f₋₁ + (t + 1)(t − 1)(t − 2)/2 f₀ − (t + 1) t (t − 2)/2 f₁
        + (t + 1) t (t − 1)/6 f₂,

    or the quadratic of the smoother side (t (t − 1)/2 f₋₁ + (1 − t²) f₀ + (t + 1) t/2 f₁ on
    the left, (t − 1)(t − 2)/2 f₀ − t (t − 2) f₁ + t (t − 1)/2 f₂ on the right) where one side's
    second difference exceeds the other's ``kink`` times, and the only quadratic there is in the
    first (``first``) or last (``last``) cell of a closed axis."""
    if node:
        return lo
    left = w[0] * before + w[1] * lo + w[2] * hi
    right = w[3] * lo - w[4] * hi + w[5] * after
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
    return w[6] * before + w[7] * lo - w[8] * hi + w[9] * after


@jit_parallel
def refine_rows(f, rows, m, periodic, kink, out):  # pragma: no cover - numba
    """``out[k, r]``: the reconstruction (:func:`_between`) at lattice point ``rows[r]`` (m
    points per cell: offset o = rows[r] mod m, t = o/m) of the axis whose nodal values are
    ``f[k, :]``. The nodes and coefficients of each point are found once for every k."""
    n = f.shape[1]
    count = rows.shape[0]
    around = np.empty((count, 4), np.int64)  # the nodes i − 1 … i + 2 (wrapped)
    ends = np.empty((count, 3), np.bool_)  # t = 0, first cell, last cell
    w = np.empty((count, 10))
    for r in range(count):
        i = rows[r] // m
        o = rows[r] - i * m
        for j in range(4):
            around[r, j] = (i - 1 + j) % n
        ends[r, 0] = o / m == 0.0
        ends[r, 1] = not periodic and i == 0
        ends[r, 2] = not periodic and i >= n - 2
        _weights(o / m, w[r])
    for k in prange(f.shape[0]):
        for r in range(count):
            first, last = ends[r, 1], ends[r, 2]
            out[k, r] = _between(
                f[k, around[r, 0]] if not first else 0.0,
                f[k, around[r, 1]],
                f[k, around[r, 2]],
                f[k, around[r, 3]] if not last else 0.0,
                ends[r, 0],
                w[r],
                first,
                last,
                kink,
            )


@jit
def lattice_points(first, shape, values, starts, out):  # pragma: no cover - numba
    """``out[p, a]``: the coordinate along axis a of the lattice point whose flat index (C
    order, a lattice of ``shape``) is ``first + p``, ``values[starts[a] + j_a]`` for its index
    j_a along a (``values`` holds each axis's coordinates in turn), counting on along the axes
    from point to point."""
    d = shape.shape[0]
    index = np.empty(d, np.int64)
    rest = first
    for a in range(d - 1, -1, -1):
        index[a] = rest % shape[a]
        rest //= shape[a]
    for p in range(out.shape[0]):
        if p > 0:
            a = d - 1
            index[a] += 1
            while a > 0 and index[a] == shape[a]:
                index[a] = 0
                a -= 1
                index[a] += 1
        for a in range(d):
            out[p, a] = values[starts[a] + index[a]]


@jit_parallel
def local_minima(true, rebuilt, shape, wrap, rounding, out):  # pragma: no cover - numba
    """``out[p]``: whether the excess e = ``true`` − ``rebuilt`` (flat, C order, of a lattice of
    ``shape``) is below −``rounding`` at point p and at most e at each of its 3^d neighbours
    (indices clipped to the lattice along an axis, wrapped where ``wrap``): a minimum filter's
    local minima, with their neighbours read only where the excess is that low."""
    d = shape.shape[0]
    size = true.shape[0]
    strides = _c_strides(shape)
    n_blocks = min(size, 256)
    for b in prange(n_blocks):
        offset = np.empty((d, 3), np.int64)  # the flat offsets of the indices j − 1, j, j + 1
        for p in range(b * size // n_blocks, (b + 1) * size // n_blocks):
            gap = true[p] - rebuilt[p]
            lowest = gap < -rounding
            if lowest:
                rest = p
                for a in range(d - 1, -1, -1):
                    n = shape[a]
                    index = rest % n
                    rest //= n
                    for step in range(3):
                        j = index + step - 1
                        j = j % n if wrap[a] else min(max(j, 0), n - 1)
                        offset[a, step] = j * strides[a]
                for s in range(3**d):
                    q = 0
                    code = s
                    for a in range(d - 1, -1, -1):
                        q += offset[a, code % 3]
                        code //= 3
                    if true[q] - rebuilt[q] < gap:
                        lowest = False
                        break
            out[p] = lowest


@jit_parallel
def rebuild_points(nodes, shape, periodic, positions, kink, out):  # pragma: no cover - numba
    """``out[p]``: the reconstruction of the nodal values ``nodes`` (flat, C order, of a grid of
    ``shape``) at the point whose position in cells along each axis (from the first node) is
    ``positions[p]``: the rule of :func:`_between` along the first axis for each of the 4^(d−1)
    rows of the 4^d nodes around the point, then along the second on those values, and so on,
    as the lattice is reconstructed axis by axis."""
    d = shape.shape[0]
    size = 4**d
    strides = _c_strides(shape)
    n_points = positions.shape[0]
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        cell = np.empty(d, np.int64)
        t = np.empty(d)
        values = np.empty(size)
        w = np.empty(10)
        offset = np.empty((d, 4), np.int64)  # the flat offsets of the nodes i − 1 … i + 2
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
                for digit in range(4):
                    j = i - 1 + digit
                    j = j % n if periodic[a] else min(max(j, 0), n - 1)
                    offset[a, digit] = j * strides[a]
            for s in range(size):
                flat = 0
                rest = s
                for a in range(d - 1, -1, -1):
                    flat += offset[a, rest % 4]
                    rest //= 4
                values[s] = nodes[flat]
            count = size
            for a in range(d):
                count //= 4
                n = shape[a]
                first = not periodic[a] and cell[a] == 0
                last = not periodic[a] and cell[a] >= n - 2
                _weights(t[a], w)
                for s in range(count):
                    values[s] = _between(
                        values[s],
                        values[count + s],
                        values[2 * count + s],
                        values[3 * count + s],
                        t[a] == 0.0,
                        w,
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
    strides = _c_strides(shape)
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


@jit_parallel
def least_in_supports(values, indptr, indices, out):  # pragma: no cover - numba
    """``out[a, j, c]``: the least of ``values[a, i, c]`` over the rows i = ``indices[p]``,
    ``indptr[j]`` ≤ p < ``indptr[j + 1]`` (a CSR matrix's pattern: the lattice points in the
    support of coarse node j's hat along the middle axis), +inf where there are none."""
    outer, rows, inner = out.shape
    for task in prange(outer * rows):
        a, j = task // rows, task % rows
        for c in range(inner):
            out[a, j, c] = np.inf
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            for c in range(inner):
                if values[a, i, c] < out[a, j, c]:
                    out[a, j, c] = values[a, i, c]
