"""Implicit diffusion along one axis: Thomas sweeps on closed lines, Sherman–Morrison on cyclic
ones (:mod:`gridlbc.schemes.splitting.diffusion`); the state cost with the slice maxima."""

from __future__ import annotations

import numpy as np

from .options import jit, jit_parallel, prange

_INTERLEAVED = 8  # contiguous lines solved side by side: their recursions overlap in the core


@jit
def closed_line_tasks(n_nodes: int, n: int, stride: int) -> int:
    """How many tasks :func:`diffuse_closed_kernel` splits the lines of one closed axis into:
    ``_INTERLEAVED`` contiguous lines (stride 1) or 64 neighbouring strided lines per task."""
    if stride == 1:
        return -(-(n_nodes // n) // _INTERLEAVED)
    return n_nodes // (n * stride) * -(-stride // 64)


@jit_parallel
def diffuse_closed_kernel(z, factors, uniform, n, stride, block_max):
    """Solve every line of one closed axis in place with precomputed Thomas factors.

    ``factors`` is ``(3, n)`` when the coefficients are the same on every line (``uniform``),
    else ``(3, N)`` per node. Lines are taken several at a time side by side
    (:func:`closed_line_tasks`): strided lines 64 at a time, so that memory is read
    contiguously whatever the axis; contiguous lines ``_INTERLEAVED`` at a time, so that their
    serial recursions interleave instead of each waiting on its previous node. When
    ``block_max`` has columns, the maximum of each row over each block of tasks is written there
    (fusing the slice maximum into this pass).
    """
    n_rhs, n_nodes = z.shape
    chunk = min(stride, 64)
    n_chunks = (stride + chunk - 1) // chunk
    n_tasks = closed_line_tasks(n_nodes, n, stride)
    n_blocks = block_max.shape[1] if block_max.shape[1] > 0 else min(n_tasks, 256)
    track = block_max.shape[1] > 0
    n_lines = n_nodes // n
    for b in prange(n_blocks):
        for r in range(n_rhs):
            peak = 0.0
            for task in range(b * n_tasks // n_blocks, (b + 1) * n_tasks // n_blocks):
                if stride == 1:  # contiguous lines, interleaved
                    first = task * _INTERLEAVED
                    last = min(first + _INTERLEAVED, n_lines)
                    for i in range(n):
                        for line in range(first, last):
                            node = line * n + i
                            f = i if uniform else node
                            if i == 0:
                                z[r, node] = z[r, node] * factors[0, f]
                            else:
                                z[r, node] = (
                                    z[r, node] * factors[0, f] + factors[1, f] * z[r, node - 1]
                                )
                    for line in range(first, last):
                        peak = max(peak, z[r, line * n + n - 1])
                    for i in range(n - 2, -1, -1):
                        for line in range(first, last):
                            node = line * n + i
                            f = i if uniform else node
                            z[r, node] -= factors[2, f] * z[r, node + 1]
                            peak = max(peak, z[r, node])
                    continue
                start = (task // n_chunks) * n * stride
                j0 = (task % n_chunks) * chunk
                j1 = min(stride, j0 + chunk)
                for i in range(n):
                    row = start + i * stride
                    for node in range(row + j0, row + j1):
                        f = i if uniform else node
                        if i == 0:
                            z[r, node] = z[r, node] * factors[0, f]
                        else:
                            z[r, node] = (
                                z[r, node] * factors[0, f] + factors[1, f] * z[r, node - stride]
                            )
                if track:
                    row = start + (n - 1) * stride
                    for node in range(row + j0, row + j1):
                        peak = max(peak, z[r, node])
                for i in range(n - 2, -1, -1):
                    row = start + i * stride
                    for node in range(row + j0, row + j1):
                        f = i if uniform else node
                        z[r, node] -= factors[2, f] * z[r, node + stride]
                        if track:
                            peak = max(peak, z[r, node])
            if track:
                block_max[r, b] = peak


@jit_parallel
def diffuse_periodic_kernel(z, ratio, n, stride):
    """The cyclic version of :func:`diffuse_closed_kernel`, by Sherman–Morrison per line."""
    n_rhs, n_nodes = z.shape
    n_outer = n_nodes // (n * stride)
    n_tasks = n_rhs * n_outer * stride
    n_blocks = min(n_tasks, 256)
    for blk in prange(n_blocks):
        a = np.empty(n)
        bb = np.empty(n)
        y = np.empty(n)
        q = np.empty(n)
        cp = np.empty(n)
        for task in range(blk * n_tasks // n_blocks, (blk + 1) * n_tasks // n_blocks):
            r_idx = task // (n_outer * stride)
            rest = task % (n_outer * stride)
            base = (rest // stride) * n * stride + rest % stride
            for i in range(n):
                rr = ratio[base + i * stride]
                a[i] = -rr
                bb[i] = 1.0 + 2.0 * rr
                y[i] = z[r_idx, base + i * stride]
                q[i] = 0.0
            # A = T + u vᵀ with T tridiagonal: u = (γ, 0…0, c_{n−1}), v = (1, 0…0, a_0/γ).
            gamma = -bb[0]
            corner_low = a[0]  # A[0, n−1]
            corner_up = a[n - 1]  # A[n−1, 0] (symmetric stencil: c_{n−1} = a_{n−1})
            bb[0] -= gamma
            bb[n - 1] -= corner_up * corner_low / gamma
            q[0] = gamma
            q[n - 1] = corner_up
            # Thomas on T for y and q together (sub- and super-diagonal a[i] / a[i+1]).
            cp[0] = a[0] / bb[0]
            y[0] /= bb[0]
            q[0] /= bb[0]
            for i in range(1, n):
                m = bb[i] - a[i] * cp[i - 1]
                cp[i] = (a[i] if i < n - 1 else 0.0) / m
                y[i] = (y[i] - a[i] * y[i - 1]) / m
                q[i] = (q[i] - a[i] * q[i - 1]) / m
            for i in range(n - 2, -1, -1):
                y[i] -= cp[i] * y[i + 1]
                q[i] -= cp[i] * q[i + 1]
            factor = (y[0] + corner_low / gamma * y[n - 1]) / (
                1.0 + q[0] + corner_low / gamma * q[n - 1]
            )
            for i in range(n):
                z[r_idx, base + i * stride] = y[i] - factor * q[i]


@jit_parallel
def cost_max_kernel(z, cost, block_max):
    """z[r] *= cost (when ``cost`` is not empty); block_max[r, b] = max of z[r] over block b."""
    n_rhs, n_nodes = z.shape
    n_blocks = block_max.shape[1]
    use_cost = cost.size > 0
    for b in prange(n_blocks):
        for r in range(n_rhs):
            peak = 0.0
            for p in range(b * n_nodes // n_blocks, (b + 1) * n_nodes // n_blocks):
                if use_cost:
                    z[r, p] *= cost[p]
                peak = max(peak, z[r, p])
            block_max[r, b] = peak
