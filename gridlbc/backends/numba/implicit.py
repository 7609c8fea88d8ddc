"""Symmetric Gauss–Seidel sweeps of the implicit scheme (:mod:`gridlbc.schemes.implicit`)."""

from __future__ import annotations

from .options import jit


@jit
def gauss_seidel_kernel(indptr, indices, off, inv_diag, b, x, tol, max_sweeps):
    """Symmetric Gauss–Seidel sweeps x_i ← (b_i + Σ_j N_ij x_j)/D_ii, alternately forward and
    backward, in place, until the max-norm change of a sweep is ≤ tol · max x.
    Returns the number of sweeps (negative if it did not converge)."""
    n = b.shape[0]
    for sweep in range(1, max_sweeps + 1):
        change = 0.0
        peak = 0.0
        for step in range(n):
            i = step if sweep % 2 == 1 else n - 1 - step
            acc = b[i]
            for k in range(indptr[i], indptr[i + 1]):
                acc += off[k] * x[indices[k]]
            value = acc * inv_diag[i]
            change = max(change, abs(value - x[i]))
            peak = max(peak, value)
            x[i] = value
        if change <= tol * peak:
            return sweep
    return -max_sweeps
