"""The curvature term of the fitted drift, compiled (:mod:`gridlbc.schemes.splitting.curvature`)."""

from __future__ import annotations

import functools

import numpy as np

from .. import QUANTUM
from .options import jit_inline, jit_parallel, prange


@jit_inline
def _hessian_at(ell, node, stencil, d, hessian):
    """``hessian[pairs[a, b]]`` (:func:`gridlbc.schemes.splitting.curvature.hessian_pairs`) = the
    second difference of ``ell`` in index units at ``node``, on ``stencil``, the row of
    :func:`gridlbc.schemes.splitting.curvature.stencils` for the node's place: ℓ(+a) − 2ℓ + ℓ(−a) on
    the diagonal, ((ℓ(+a+b) − ℓ(−a+b)) − (ℓ(+a−b) − ℓ(−a−b)))/4 off it, exactly 0 along an axis of
    fewer than 3 nodes (its offsets are 0) without a branch. ``d`` is the grid's dimension, a
    compile-time constant where the caller's is (the loops unroll)."""
    centre = np.int64(node) + stencil[0]
    middle = ell[centre]
    column = 0
    for a in range(d):
        up_a, down_a = stencil[1 + a], stencil[1 + d + a]
        hessian[column] = ell[centre + up_a] - 2.0 * middle + ell[centre + down_a]
        column += 1
        for b in range(a + 1, d):
            up_b, down_b = stencil[1 + b], stencil[1 + d + b]
            hessian[column] = 0.25 * (
                (ell[centre + up_a + up_b] - ell[centre + down_a + up_b])
                - (ell[centre + up_a + down_b] - ell[centre + down_a + down_b])
            )
            column += 1


@jit_inline
def _limited(ell_lin, term, low, high):
    """The curvature term, cut so that ℓ_lin + term stays within [low, high] (the vertex values'
    range): no new extrema, which keeps the corrected drift stable where ℓ is kinked."""
    return min(max(ell_lin + term, low), high) - ell_lin


@functools.cache
def _curvature_compact_kernels(d: int):
    """:func:`curvature_compact_kernel` compiled for grids of dimension ``d`` (a constant: the
    loops over the vertices and walk steps unroll), reading flat rows through unsigned indices
    as :func:`gridlbc.backends.numba.drift._advect_kernels` does."""

    @jit_parallel
    def kernel(
        ell, base, code, frac, offsets, columns, place, stencils, record, places, add_mean, out
    ):
        n_nodes = base.size
        n_blocks = min(n_nodes, 256)
        fractions = frac.reshape(-1)
        vertex = offsets.reshape(-1)
        column = columns.reshape(-1)
        for block in prange(n_blocks):
            hessian = np.empty(d * (d + 1) // 2)  # scratch
            for p in range(block * n_nodes // n_blocks, (block + 1) * n_nodes // n_blocks):
                node = np.int64(base[p])
                c = np.int64(code[p])
                previous = QUANTUM
                lin = 0.0
                low, high = np.inf, -np.inf
                nearest, largest = node, -1
                for j in range(d + 1):
                    fj = np.int64(fractions[p * d + j]) if j < d else np.int64(0)
                    v = node + vertex[c * (d + 1) + j]
                    value = ell[np.uint64(v)]
                    lin += (previous - fj) * value
                    if previous > fj:
                        low, high = min(low, value), max(high, value)
                    if previous - fj > largest:
                        nearest, largest = v, previous - fj
                    previous = fj
                if record:
                    places[p] = place[nearest]
                _hessian_at(ell, nearest, stencils[np.int64(places[p])], d, hessian)
                acc = 0.0
                for k in range(d):
                    cross = 0.0
                    for m in range(k + 1, d):
                        cross += (
                            np.float64(fractions[p * d + m]) * hessian[column[(c * d + k) * d + m]]
                        )
                    f = np.float64(fractions[p * d + k]) * (1.0 / QUANTUM)
                    acc += (1.0 - f) * (
                        f * hessian[column[(c * d + k) * d + k]] + 2.0 * cross * (1.0 / QUANTUM)
                    )
                mean = lin * (1.0 / QUANTUM)
                term = _limited(mean, -0.5 * acc, low, high)
                out[p] = mean + term if add_mean else term

    return kernel


def curvature_compact_kernel(
    ell, base, code, frac, offsets, columns, place, stencils, record, places, add_mean, out
):
    """out[p] = the limited curvature term of the compact feet (see
    :class:`gridlbc.schemes.splitting.curvature.CurvatureCorrection`), plus the linear mean Σ_j w_j
    ell[v_j] when ``add_mean`` (the fitted log drift in one pass): with the sorted fractions f_k of
    walk steps k along axes π_k, M_{π_k π_k} = f_k (1 − f_k) and, for k < l, M_{π_k π_l} = f_l (1 −
    f_k); H at the vertex of largest weight (the first on a tie), computed there from ``ell``
    (:func:`_hessian_at`; a stored table of it would be gathered at the feet, five times the bytes
    of ``ell``), its component ∂_{π_k}∂_{π_l} at
    :func:`gridlbc.schemes.splitting.curvature.hessian_pairs` index ``columns[code[p], k, l]``
    (:func:`gridlbc.schemes.splitting.curvature.hessian_columns`). The stencil's row is
    ``places[p]``, the ``place`` (:func:`gridlbc.schemes.splitting.curvature.stencils`) of that
    vertex; the feet being fixed, it is gathered once, by a call with ``record``, and read in order
    by the later ones."""
    _curvature_compact_kernels(frac.shape[1])(
        ell, base, code, frac, offsets, columns, place, stencils, record, places, add_mean, out
    )


@jit_parallel
def curvature_table_kernel(
    ell, idx, weights, place, stencils, shape, strides, pairs, add_mean, out
):
    """:func:`curvature_compact_kernel` for the table feet: the walk step j → j + 1 runs along
    the axis whose stride (or wrap −(n − 1) × stride) is idx[p, j+1] − idx[p, j], and its
    fraction is f_j = Σ_{i>j} weights[p, i]; ``add_mean`` as there. Nodes are taken in blocks, so
    that the scratch of the walk's axes and fractions and of the Hessian is allocated once per
    block."""
    n_nodes, n_vertices = idx.shape
    d = n_vertices - 1
    n_blocks = min(n_nodes, 256)
    for block in prange(n_blocks):
        axis = np.empty(d, dtype=np.int64)
        f = np.empty(d)
        hessian = np.empty(d * (d + 1) // 2)
        for p in range(block * n_nodes // n_blocks, (block + 1) * n_nodes // n_blocks):
            tail = 0.0
            lin = 0.0
            low, high = np.inf, -np.inf
            for j in range(d - 1, -1, -1):
                tail += np.float64(weights[p, j + 1])
                f[j] = tail
                step = np.int64(idx[p, j + 1]) - np.int64(idx[p, j])
                axis[j] = 0
                for a in range(d):
                    if step == strides[a] or step == -(shape[a] - 1) * strides[a]:
                        axis[j] = a
            node, largest = np.int64(idx[p, 0]), -1.0
            for j in range(n_vertices):
                value = ell[idx[p, j]]
                lin += weights[p, j] * value
                if weights[p, j] > 0:
                    low, high = min(low, value), max(high, value)
                if weights[p, j] > largest:
                    node, largest = np.int64(idx[p, j]), weights[p, j]
            _hessian_at(ell, node, stencils[np.int64(place[node])], d, hessian)
            acc = 0.0
            for k in range(d):
                cross = 0.0
                for m in range(k + 1, d):
                    cross += f[m] * hessian[pairs[axis[k], axis[m]]]
                acc += (1.0 - f[k]) * (f[k] * hessian[pairs[axis[k], axis[k]]] + 2.0 * cross)
            term = _limited(lin, -0.5 * acc, low, high)
            out[p] = lin + term if add_mean else term
