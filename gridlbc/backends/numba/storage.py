"""Storing a renormalised slice of z in the slices' dtype (:mod:`gridlbc.storage`)."""

from __future__ import annotations

import numpy as np

from .options import jit_parallel, prange


@jit_parallel
def store_kernel(Z, scale, out, flushed):
    """out[r, :] = Z[r, :] · scale[r] in out's dtype; returns how many nonzero values it flushed
    to zero (float32 storage of values below ~1e-45 of the slice maximum), counted per work
    block in ``flushed``. The rows are read as flat arrays over unsigned ranges, which the
    compiler vectorises."""
    n_rhs, n_nodes = Z.shape
    n_blocks = flushed.shape[0]
    for b in prange(n_blocks):
        count = 0
        first = np.uint64(b * n_nodes // n_blocks)
        last = np.uint64((b + 1) * n_nodes // n_blocks)
        for r in range(n_rhs):
            source = Z[r]
            target = out[r]
            factor = scale[r]
            for p in range(first, last):
                value = source[p] * factor
                target[p] = value
                count += (value > 0.0) & (target[p] == 0.0)
        flushed[b] = count
    return flushed.sum()
