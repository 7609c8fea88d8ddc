"""The semi-Lagrangian drift's kernels: the gather over each foot's simplex, plain or fitted to a
reference (:mod:`gridlbc.schemes.splitting.drift`), and the drift's Courant rates."""

from __future__ import annotations

import functools
import math

import numpy as np

from .. import QUANTUM, REFERENCE_FLOOR
from .options import jit, jit_parallel, prange


@functools.cache
def _advect_kernels(d: int):
    """The drift kernels of :func:`advect_compact_kernel` and :func:`advect_table_kernel` for
    grids of dimension ``d``, compiled with d a constant (numba unrolls the vertex loops) and
    with the per-node arrays read as flat rows through unsigned indices (no negative-index
    wrapping), which lets the compiler vectorise the decoding."""

    @jit_parallel
    def compact(z, base, code, frac, offsets, scale, ell, ones_row, out):
        n_rhs, n_nodes = z.shape
        fitted = ell.size > 0
        fractions = frac.reshape(-1)
        vertex = offsets.reshape(-1)
        for p in prange(n_nodes):
            node = np.int64(base[p])
            row = np.int64(code[p]) * (d + 1)
            fit = 1.0
            if fitted:
                previous = QUANTUM
                mean = 0.0
                for j in range(d + 1):
                    f = np.int64(fractions[p * d + j]) if j < d else np.int64(0)
                    mean += (previous - f) * ell[np.uint64(node + vertex[row + j])]
                    previous = f
                fit = np.exp(mean * (1.0 / QUANTUM))
            for r in range(n_rhs):
                if r == ones_row:  # the integer weights telescope to Q: the same number, exactly
                    acc = float(QUANTUM)
                else:
                    zr = z[r]
                    previous = QUANTUM
                    acc = 0.0
                    for j in range(d):
                        f = np.int64(fractions[p * d + j])
                        acc += (previous - f) * zr[np.uint64(node + vertex[row + j])]
                        previous = f
                    acc += previous * zr[np.uint64(node + vertex[row + d])]
                out[r, p] = acc * (fit * scale[r] * (1.0 / QUANTUM))

    @jit_parallel
    def table(z, idx, weights, scale, ell, ones_row, out):
        n_rhs, n_nodes = z.shape
        fitted = ell.size > 0
        vertices = idx.reshape(-1)
        weight = weights.reshape(-1)
        for p in prange(n_nodes):
            first = p * (d + 1)
            fit = 1.0
            total = 0.0
            if fitted:
                mean = 0.0
                for j in range(d + 1):
                    mean += weight[first + j] * ell[np.uint64(vertices[first + j])]
                    total += weight[first + j]
                fit = np.exp(mean)
            for r in range(n_rhs):
                if r == ones_row:
                    acc = total
                else:
                    zr = z[r]
                    acc = 0.0
                    for j in range(d + 1):
                        acc += weight[first + j] * zr[np.uint64(vertices[first + j])]
                out[r, p] = acc * (fit * scale[r])

    return compact, table


def advect_compact_kernel(z, base, code, frac, offsets, scale, ell, ones_row, out):
    """out[r, p] = scale[r] · F_p · Σ_j w_j z[r, v_j] over the foot's simplex vertices
    v_j = base[p] + offsets[code[p], j] with w_j = (f_{j−1} − f_j)/Q from the sorted quantised
    fractions (f_{−1} = Q, f_d = 0). Fitted (``ell`` = log φ given, ``z`` already divided by φ
    by :func:`fitting_kernel`): F_p = exp(Σ_j w_j ell[v_j]) = φ̄, the reference's geometric mean
    over the simplex; F_p = 1 when ``ell`` is empty. Row ``ones_row`` (−1: none) is known to be
    all ones, so its gather is skipped: Σ_j w_j · 1 = 1 exactly. All arrays C-contiguous."""
    _advect_kernels(frac.shape[1])[0](z, base, code, frac, offsets, scale, ell, ones_row, out)


def advect_table_kernel(z, idx, weights, scale, ell, ones_row, out):
    """out[r, p] = scale[r] · F_p · Σ_j weights[p, j] z[r, idx[p, j]], the fitting factor F_p and
    ``ones_row`` as in :func:`advect_compact_kernel`."""
    _advect_kernels(idx.shape[1] - 1)[1](z, idx, weights, scale, ell, ones_row, out)


@jit_parallel
def fitting_kernel(z, reference, ell):
    """With φ = max(z[reference], TINY): ell = log φ, and every row of ``z`` divided by φ in
    place, so that the drift's gather Σ_j w_j z(y_j)/φ(y_j) times φ̄ is the fitted P_φ z.
    Returns the number of nodes where φ was floored: where it is zero, the reference row is
    all ones (x/x = 1 exactly in floating point)."""
    n_rhs, n_nodes = z.shape
    floored = 0
    for p in prange(n_nodes):
        phi = z[reference, p]
        if phi < REFERENCE_FLOOR:
            phi = REFERENCE_FLOOR
            floored += 1
        ell[p] = np.log(phi)
        for r in range(n_rhs):
            z[r, p] /= phi
    return floored


@jit
def rate_sums(drift, spacing):
    """max over the rows of r = max_k |drift_k| / spacing_k, and the sum of r² (NaN if any
    drift is NaN)."""
    peak, squares = 0.0, 0.0
    for i in range(drift.shape[0]):
        rate = 0.0
        for k in range(drift.shape[1]):
            rate = max(rate, abs(drift[i, k]) / spacing[k])
            if drift[i, k] != drift[i, k]:
                squares = math.nan
        peak = max(peak, rate)
        squares += rate * rate
    return peak, squares
