"""Barycentric interpolation's kernels (:mod:`gridlbc.interpolate`): the cell of one coordinate,
the Kuhn simplex and weights of states, central differences at nodes."""

from __future__ import annotations

import math

import numpy as np

from .options import jit, jit_inline, jit_parallel, prange

SERIAL_BELOW = 32_768
"""Below this many states (or nodes), the interpolation kernels run in the calling thread: their
work per item is a few hundred nanoseconds, and waking the threads costs more than it saves,
many times more on a loaded machine, where each parallel call waits for every thread to be
scheduled (a policy evaluated at each step of a few thousand simulated paths)."""


@jit
def cell(x, lo, spacing, n, periodic):
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


@jit_inline
def _kuhn_points(start, stop, x, lo, spacing, shape, strides, periodic, idx, weights):
    """The Kuhn simplex and weights of the states ``x[start:stop]`` into ``idx``, ``weights``
    (its scratch allocated here, once: a loop whose scratch is passed in from its caller runs
    several times slower)."""
    d = x.shape[1]
    frac = np.empty(d)
    order = np.empty(d, np.int64)
    first = np.empty(d, np.int64)  # the base corner's coordinates
    for p in range(start, stop):
        base = 0
        for k in range(d):
            i, frac[k] = cell(x[p, k], lo[k], spacing[k], shape[k], periodic[k])
            first[k] = i
            base += i * strides[k]
            j = k  # insertion into the decreasing order, ties in axis order (a stable sort)
            while j > 0 and frac[order[j - 1]] < frac[k]:
                order[j] = order[j - 1]
                j -= 1
            order[j] = k
        # Walk from the base corner, one axis at a time in decreasing fractional order (each
        # axis once: the walk is at the base corner's coordinate along an axis when it steps).
        idx[p, 0] = base
        weights[p, 0] = 1.0 - frac[order[0]]
        node = base
        for j in range(d):
            k = order[j]
            n = shape[k]
            if first[k] == n - 1:  # only reachable on a periodic axis
                node -= (n - 1) * strides[k]
            else:
                node += strides[k]
            idx[p, j + 1] = node
            nxt = frac[order[j + 1]] if j + 1 < d else 0.0
            weights[p, j + 1] = frac[k] - nxt


@jit_parallel
def kuhn_kernel(x, lo, spacing, shape, strides, periodic, idx, weights):
    """:func:`_kuhn_points` for every state, on the threads, in blocks."""
    n_points = x.shape[0]
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        start, stop = b * n_points // n_blocks, (b + 1) * n_points // n_blocks
        _kuhn_points(start, stop, x, lo, spacing, shape, strides, periodic, idx, weights)


@jit
def kuhn_kernel_serial(x, lo, spacing, shape, strides, periodic, idx, weights):
    """:func:`_kuhn_points` for every state, in this thread (few states: :data:`SERIAL_BELOW`)."""
    _kuhn_points(0, x.shape[0], x, lo, spacing, shape, strides, periodic, idx, weights)


@jit_inline
def _ratio(z, log_divisor, r, node):
    """z[r, node] / e^{log_divisor[r, node]} in float64, by way of logarithms (zero where z is)."""
    value = np.float64(z[r, node])  # (numba's float() keeps a float32 in single precision)
    return math.exp(math.log(value) - np.float64(log_divisor[r, node])) if value > 0.0 else 0.0


@jit_inline
def _central_gradients(
    start, stop, z, log_divisor, nodes, k, shape, strides, spacing, periodic, out
):
    """∂y/∂x_k at the flat nodes ``nodes[start:stop]`` into ``out[:, start:stop]``
    (:func:`central_gradient_kernel`; the loop in one function: a loop that calls a helper per
    node runs several times slower)."""
    n = shape[k]
    s = strides[k]
    h = spacing[k]
    for p in range(start, stop):
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
        for r in range(z.shape[0]):
            if log_divisor.shape[1] == 0:
                out[r, p] = (z[r, up] - z[r, down]) * scale
            else:
                out[r, p] = (
                    _ratio(z, log_divisor, r, up) - _ratio(z, log_divisor, r, down)
                ) * scale


@jit_parallel
def central_gradient_kernel(z, log_divisor, nodes, axis, shape, strides, spacing, periodic, out):
    """∂y/∂x_axis at the given flat nodes for y = z (in z's precision), or y = z / e^{log_divisor}
    when ``log_divisor`` has columns (:func:`_ratio`): central differences, one-sided at closed
    ends; on the threads, in blocks."""
    n_nodes = nodes.shape[0]
    n_blocks = min(n_nodes, 256)
    for b in prange(n_blocks):
        start, stop = b * n_nodes // n_blocks, (b + 1) * n_nodes // n_blocks
        _central_gradients(
            start, stop, z, log_divisor, nodes, axis, shape, strides, spacing, periodic, out
        )


@jit
def central_gradient_kernel_serial(
    z, log_divisor, nodes, axis, shape, strides, spacing, periodic, out
):
    """:func:`central_gradient_kernel` in this thread (few nodes: :data:`SERIAL_BELOW`)."""
    _central_gradients(
        0, nodes.shape[0], z, log_divisor, nodes, axis, shape, strides, spacing, periodic, out
    )
