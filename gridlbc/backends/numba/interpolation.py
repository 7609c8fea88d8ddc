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
def _interpolated(start, stop, z, time_weights, log_divisor, nodes, weights, out):
    """Σ_v w_v Σ_r τ_r y_r(x_v) for the states ``start:stop`` into ``out`` (N,), y_r = z[r] (or
    z[r] / e^{log_divisor[r]}, :func:`_ratio`, where ``log_divisor`` has columns)."""
    for p in range(start, stop):
        total = 0.0
        for v in range(nodes.shape[1]):
            node = nodes[p, v]
            at_vertex = 0.0
            for r in range(z.shape[0]):
                if log_divisor.shape[1] == 0:
                    at_vertex += time_weights[r] * z[r, node]
                else:
                    at_vertex += time_weights[r] * _ratio(z, log_divisor, r, node)
            total += weights[p, v] * at_vertex
        out[p] = total


@jit_parallel
def interpolate_kernel(z, time_weights, log_divisor, nodes, weights, out):
    """:func:`_interpolated` for every state, on the threads, in blocks."""
    n_points = nodes.shape[0]
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        start, stop = b * n_points // n_blocks, (b + 1) * n_points // n_blocks
        _interpolated(start, stop, z, time_weights, log_divisor, nodes, weights, out)


@jit
def interpolate_kernel_serial(z, time_weights, log_divisor, nodes, weights, out):
    """:func:`interpolate_kernel` in this thread (few states: :data:`SERIAL_BELOW`)."""
    _interpolated(0, nodes.shape[0], z, time_weights, log_divisor, nodes, weights, out)


@jit_inline
def _neighbours(node, n, s, h, periodic):
    """The nodes (up, down) of a central difference along an axis of n nodes, stride s and
    spacing h at a flat node, and its factor 1/(up − down): the node itself on the side of a
    closed end (one-sided there), the node across the seam on a periodic axis."""
    i = (node // s) % n
    if periodic:
        up = node + s if i < n - 1 else node - (n - 1) * s
        down = node - s if i > 0 else node + (n - 1) * s
        return up, down, 0.5 / h
    if i == 0:
        return node + s, node, 1.0 / h
    if i == n - 1:
        return node, node - s, 1.0 / h
    return node + s, node - s, 0.5 / h


@jit_inline
def _input_gradients(
    start,
    stop,
    z,
    time_weights,
    log_divisor,
    nodes,
    weights,
    B,
    axes,
    shape,
    strides,
    spacing,
    periodic,
    out,
):
    """Σ_v w_v B(x_v)ᵀ Σ_r τ_r ∇y_r(x_v) for the states ``start:stop`` into ``out`` (N, m), the
    derivative along each of ``axes`` a central difference at the vertex (:func:`_neighbours`);
    B (N, d+1, d, m), an axis of length 1 read for every state or vertex ((1, 1, d, m) where B is
    the same everywhere)."""
    m = out.shape[1]
    one_state, one_vertex = B.shape[0] == 1, B.shape[1] == 1  # B broadcast along the axis
    for p in range(start, stop):
        for j in range(m):
            out[p, j] = 0.0
        for v in range(nodes.shape[1]):
            node = nodes[p, v]
            w = weights[p, v]
            b = 0 if one_state else p
            c = 0 if one_vertex else v
            for a in range(axes.shape[0]):
                k = axes[a]
                up, down, scale = _neighbours(node, shape[k], strides[k], spacing[k], periodic[k])
                g = 0.0
                for r in range(z.shape[0]):
                    if log_divisor.shape[1] == 0:
                        difference = z[r, up] - z[r, down]  # in z's precision
                    else:
                        difference = _ratio(z, log_divisor, r, up) - _ratio(z, log_divisor, r, down)
                    g += time_weights[r] * difference
                g *= w * scale
                for j in range(m):
                    out[p, j] += B[b, c, k, j] * g


@jit_parallel
def input_gradient_kernel(
    z, time_weights, log_divisor, nodes, weights, B, axes, shape, strides, spacing, periodic, out
):
    """:func:`_input_gradients` for every state, on the threads, in blocks."""
    n_points = nodes.shape[0]
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        start, stop = b * n_points // n_blocks, (b + 1) * n_points // n_blocks
        _input_gradients(
            start,
            stop,
            z,
            time_weights,
            log_divisor,
            nodes,
            weights,
            B,
            axes,
            shape,
            strides,
            spacing,
            periodic,
            out,
        )


@jit
def input_gradient_kernel_serial(
    z, time_weights, log_divisor, nodes, weights, B, axes, shape, strides, spacing, periodic, out
):
    """:func:`input_gradient_kernel` in this thread (few states: :data:`SERIAL_BELOW`)."""
    _input_gradients(
        0,
        nodes.shape[0],
        z,
        time_weights,
        log_divisor,
        nodes,
        weights,
        B,
        axes,
        shape,
        strides,
        spacing,
        periodic,
        out,
    )
