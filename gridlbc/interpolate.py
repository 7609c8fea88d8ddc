"""Barycentric interpolation on the Kuhn (Freudenthal) triangulation of a grid (README, "The maths in brief").

A state x falls in the cell with lower corner i = ⌊(x − lo)/h⌋ and fractional coordinates
f = (x − lo)/h − i ∈ [0, 1]ᵈ. Sorting f in decreasing order, f_π(1) ≥ … ≥ f_π(d), picks the simplex
with vertices

    v_0 = i,   v_j = v_{j−1} + e_π(j)   (j = 1 … d)

and barycentric weights

    w_0 = 1 − f_π(1),   w_j = f_π(j) − f_π(j+1),   w_d = f_π(d),

which are non-negative, sum to one and reproduce affine functions exactly. Periodic axes wrap
(the neighbour of node n−1 is node 0); on other axes points are clamped to the box first.

Interpolation is linear in the nodal values, so anything evaluated from interpolated z and
interpolated Bᵀ∇z stays linear in z (the superposition guarantee of the README's "The maths in brief").
"""

from __future__ import annotations

import math

import numpy as np

from ._numba import jit, jit_inline, jit_parallel, prange
from .grid import Grid


@jit
def _cell(x, lo, spacing, n, periodic):
    """The cell ⌊(x − lo)/h⌋ of one coordinate and the fraction in it, (i, f): wrapped on a
    periodic axis, clamped to the box (and to the last cell) on the others."""
    s = (x - lo) / spacing
    if periodic:
        s = s - n * np.floor(s / n)
        i = int(np.floor(s))
        if i >= n:  # rounding can give s == n exactly
            i -= n
            s -= n
        return i, s - i
    if s < 0.0:
        s = 0.0
    elif s > n - 1:
        s = n - 1.0
    i = min(int(np.floor(s)), n - 2)
    return i, s - i


@jit_parallel
def _kuhn_kernel(x, lo, spacing, shape, strides, periodic, idx, weights):
    n_points, d = x.shape
    for p in prange(n_points):
        frac = np.empty(d)
        base = 0
        for k in range(d):
            i, frac[k] = _cell(x[p, k], lo[k], spacing[k], shape[k], periodic[k])
            base += i * strides[k]
        order = np.argsort(-frac, kind="mergesort")
        # Walk from the base corner, one axis at a time in decreasing fractional order.
        idx[p, 0] = base
        weights[p, 0] = 1.0 - frac[order[0]]
        node = base
        for j in range(d):
            k = order[j]
            n = shape[k]
            coord = (node // strides[k]) % n
            if coord == n - 1:  # only reachable on a periodic axis
                node -= (n - 1) * strides[k]
            else:
                node += strides[k]
            idx[p, j + 1] = node
            nxt = frac[order[j + 1]] if j + 1 < d else 0.0
            weights[p, j + 1] = frac[k] - nxt


def barycentric(grid: Grid, x) -> tuple[np.ndarray, np.ndarray]:
    """Simplex vertices and barycentric weights of states ``x`` ``(N, d)`` on ``grid``.

    Returns ``(idx, weights)``, both ``(N, d+1)``: flat node indices and weights ≥ 0 summing to one,
    so that the interpolant of nodal values ``f`` is ``(f[idx] * weights).sum(-1)``.
    """
    x = grid.check_states(x)
    n = x.shape[0]
    idx = np.empty((n, grid.ndim + 1), dtype=np.int64)
    weights = np.empty((n, grid.ndim + 1))
    _kuhn_kernel(np.ascontiguousarray(x), *grid.kernel_arrays(), idx, weights)
    return idx, weights


def interpolate(grid: Grid, values, x) -> np.ndarray:
    """Interpolate nodal values ``(..., size)`` at states ``(N, d)``; returns ``(..., N)``."""
    values = np.asarray(values)
    if values.shape[-1] != grid.size:
        raise ValueError(
            f"values must have {grid.size} nodal entries in the last axis for grid "
            f"{grid.describe()}, got shape {values.shape}"
        )
    idx, weights = barycentric(grid, x)
    return (values[..., idx] * weights).sum(axis=-1)


def barycentric_numpy(grid: Grid, x) -> tuple[np.ndarray, np.ndarray]:
    """Plain-numpy version of :func:`barycentric`, for testing the compiled kernel."""
    x = grid.clamp(grid.check_states(x))
    shape = np.array(grid.shape)
    s = (x - grid.lo) / grid.spacing
    periodic = grid.periodic
    s = np.where(periodic, np.mod(s, shape), s)
    cell = np.floor(s).astype(np.int64)
    cell = np.where(periodic, cell % shape, np.minimum(cell, shape - 2))
    frac = s - cell
    order = np.argsort(-frac, axis=1, kind="stable")
    n, d = x.shape
    corners = np.repeat(cell[:, None, :], d + 1, axis=1)
    sorted_frac = np.take_along_axis(frac, order, axis=1)
    weights = np.empty((n, d + 1))
    weights[:, 0] = 1.0 - sorted_frac[:, 0]
    weights[:, 1:d] = sorted_frac[:, :-1] - sorted_frac[:, 1:]
    weights[:, d] = sorted_frac[:, -1]
    for j in range(d):
        step = np.zeros((n, d), dtype=np.int64)
        np.put_along_axis(step, order[:, j : j + 1], 1, axis=1)
        corners[:, j + 1 :] += step[:, None, :]
    corners = np.where(periodic, corners % shape, corners)
    idx = corners @ grid.strides
    return idx, weights


@jit_inline
def _ratio(z, log_divisor, r, node):
    """z[r, node] / e^{log_divisor[r, node]} in float64, by way of logarithms (zero where z is)."""
    value = np.float64(z[r, node])  # (numba's float() keeps a float32 in single precision)
    return math.exp(math.log(value) - np.float64(log_divisor[r, node])) if value > 0.0 else 0.0


@jit_parallel
def _central_gradient_kernel(z, log_divisor, nodes, axis, shape, strides, spacing, periodic, out):
    """∂y/∂x_axis at the given flat nodes for y = z (in z's precision), or y = z / e^{log_divisor}
    when ``log_divisor`` has columns (:func:`_ratio`): central differences, one-sided at closed
    ends."""
    k = axis
    n = shape[k]
    s = strides[k]
    h = spacing[k]
    n_rows = z.shape[0]
    for p in prange(nodes.shape[0]):
        node = nodes[p]
        i = (node // s) % n
        if periodic:
            up = node + s if i < n - 1 else node - (n - 1) * s
            down = node - s if i > 0 else node + (n - 1) * s
            scale = 0.5 / h
        elif i == 0:
            up, down, scale = node + s, node, 1.0 / h
        elif i == n - 1:
            up, down, scale = node, node - s, 1.0 / h
        else:
            up, down, scale = node + s, node - s, 0.5 / h
        for r in range(n_rows):
            if log_divisor.shape[1] == 0:
                out[r, p] = (z[r, up] - z[r, down]) * scale
            else:
                out[r, p] = (
                    _ratio(z, log_divisor, r, up) - _ratio(z, log_divisor, r, down)
                ) * scale


def node_gradient(
    grid: Grid,
    values: np.ndarray,
    nodes: np.ndarray,
    axis: int,
    log_divisor: np.ndarray | None = None,
) -> np.ndarray:
    """Finite-difference derivative along ``axis`` of nodal ``values`` ``(K, size)`` at flat
    ``nodes`` (of values / e^{log_divisor} when ``log_divisor`` ``(K, size)`` is given).

    Second-order central differences in the interior and on periodic axes, first-order one-sided
    differences at the ends of a non-periodic axis. Returns ``(K, len(nodes))``; linear in values.
    """
    values = np.ascontiguousarray(values)
    nodes = np.ascontiguousarray(nodes, dtype=np.int64).reshape(-1)
    divisor = (
        np.empty((values.shape[0], 0)) if log_divisor is None else np.ascontiguousarray(log_divisor)
    )
    out = np.empty((values.shape[0], nodes.size), dtype=np.result_type(values.dtype, np.float64))
    _central_gradient_kernel(
        values,
        divisor,
        nodes,
        int(axis),
        np.array(grid.shape, dtype=np.int64),
        grid.strides,
        grid.spacing,
        bool(grid.axes[axis].periodic),
        out,
    )
    return out
