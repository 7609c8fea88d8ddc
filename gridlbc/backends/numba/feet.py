"""Encoding the characteristic feet in the compact layout, compiled
(:mod:`gridlbc.schemes.splitting.feet` describes the layout)."""

from __future__ import annotations

import numpy as np

from .. import QUANTUM
from .interpolation import cell
from .options import jit_parallel, prange


@jit_parallel
def encode_compact_kernel(x, lo, spacing, shape, strides, periodic, walk, base, packed, frac):
    """The compact form of the feet ``x`` ``(M, d)`` (wrapped and clamped) in one pass: the cell and
    sorted fractional coordinates of :func:`gridlbc.interpolate.barycentric` (the same arithmetic),
    written as base corners, packed shapes and quantised fractions into ``base``, ``packed`` and
    ``frac`` exactly as :func:`gridlbc.schemes.splitting.feet.compact_feet` encodes barycentric's
    output (``walk``: :func:`gridlbc.schemes.splitting.feet.walk_steps`)."""
    n_points, d = x.shape
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        f = np.empty(d)
        order = np.empty(d, dtype=np.int64)
        for p in range(b * n_points // n_blocks, (b + 1) * n_points // n_blocks):
            corner = 0
            for k in range(d):
                i, f[k] = cell(x[p, k], lo[k], spacing[k], shape[k], periodic[k])
                corner += i * strides[k]
                j = k  # insertion into the decreasing order, ties in axis order (stable)
                while j > 0 and f[order[j - 1]] < f[k]:
                    order[j] = order[j - 1]
                    j -= 1
                order[j] = k
            base[p] = corner
            node = corner
            code = np.uint32(0)
            for j in range(d):  # the Kuhn walk; each step's position in walk, 4 bits each
                k = order[j]
                n = shape[k]
                step = -(n - 1) * strides[k] if (node // strides[k]) % n == n - 1 else strides[k]
                node += step
                position = 0
                while position < walk.size - 1 and walk[position] < step:
                    position += 1
                code |= np.uint32(position) << np.uint32(4 * j)
            packed[p] = code
            tail = 0.0  # f_j = w_{j+1} + … + w_d, summed as the twin's cumsum does
            for j in range(d - 1, -1, -1):
                tail += f[order[j]] - (f[order[j + 1]] if j + 1 < d else 0.0)
                frac[p, j] = np.uint16(np.rint(min(max(tail, 0.0), 1.0) * QUANTUM))
