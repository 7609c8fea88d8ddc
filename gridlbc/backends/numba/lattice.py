"""The kernel that carries nodal values to the points between the nodes along one axis
(:func:`gridlbc.accuracy.subcell.refine`, which documents the rule)."""

from __future__ import annotations

import numpy as np

from .options import jit_parallel, prange


@jit_parallel
def refine_rows(f, rows, m, periodic, cubic, left, right, kink, out):  # pragma: no cover - numba
    """``out[k, r]``: the reconstruction at lattice point ``rows[r]`` (m points per cell) of the
    axis whose nodal values are ``f[k, :]``: the node itself where ``rows[r]`` is a multiple of m,
    else at offset o = rows[r] mod m the cubic through the four nodes around it (weights
    ``cubic[o]``), or the quadratic of the smoother side (``left[o]`` through nodes i − 1, i,
    i + 1, ``right[o]`` through i, i + 1, i + 2) where one side's second difference exceeds the
    other's ``kink`` times, and the only quadratic there is in the end cells of a closed axis."""
    n = f.shape[1]
    for k in prange(f.shape[0]):
        for r in range(rows.shape[0]):
            i = rows[r] // m
            o = rows[r] - i * m
            if o == 0:
                out[k, r] = f[k, i % n]
                continue
            first = not periodic and i == 0
            last = not periodic and i == n - 2
            lo, hi = f[k, i % n], f[k, (i + 1) % n]
            before = 0.0 if first else f[k, (i - 1) % n]
            after = 0.0 if last else f[k, (i + 2) % n]
            left_q = left[o, 0] * before + left[o, 1] * lo + left[o, 2] * hi
            right_q = right[o, 0] * lo + right[o, 1] * hi + right[o, 2] * after
            if first:
                out[k, r] = right_q
            elif last:
                out[k, r] = left_q
            else:
                bent_left = np.abs(before - 2.0 * lo + hi)
                bent_right = np.abs(lo - 2.0 * hi + after)
                if bent_left > kink * bent_right:
                    out[k, r] = right_q
                elif bent_right > kink * bent_left:
                    out[k, r] = left_q
                else:
                    out[k, r] = (
                        cubic[o, 0] * before
                        + cubic[o, 1] * lo
                        + cubic[o, 2] * hi
                        + cubic[o, 3] * after
                    )
