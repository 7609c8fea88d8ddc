"""Plain-numpy twins of the compiled kernels, for the tests that compare the two on small inputs.

Each twin computes what its kernel computes, written for clarity rather than speed (and, where the
kernel prunes or quantises, without that): :func:`barycentric_numpy`
(:func:`gridlbc.interpolate.barycentric`), :func:`curvature_correction_numpy`
(:meth:`gridlbc.schemes.splitting.SplittingStep.curvature_correction`) and
:func:`diffuse_fitted_numpy`
(:func:`gridlbc.backends.numba.fitted_diffusion.diffuse_fitted_kernel`).
"""

from __future__ import annotations

import numpy as np

from .grid import Grid
from .interpolate import barycentric


def curvature_correction_numpy(grid: Grid, ell: np.ndarray, feet: np.ndarray) -> np.ndarray:
    """Plain-numpy twin of the fitted drift's curvature term
    (:class:`gridlbc.schemes.splitting.curvature.CurvatureCorrection`) from the feet ``(N, d)``
    (unquantised): −½ Σ_ab (min(f_a, f_b) − f_a f_b) H_ab, f the foot's fractional coordinates in
    its cell and H the index-unit Hessian of ``ell`` (by :func:`numpy.roll`; closed ends: the
    neighbour's) at the simplex vertex of largest weight, limited to the vertices' range."""
    shape = np.array(grid.shape)
    s = (grid.clamp(feet) - grid.lo) / grid.spacing
    s = np.where(grid.periodic, np.mod(s, shape), s)
    cell = np.where(grid.periodic, np.floor(s) % shape, np.minimum(np.floor(s), shape - 2))
    f = s - cell
    idx, weights = barycentric(grid, feet)
    nearest = idx[np.arange(len(feet)), np.argmax(weights, axis=1)]
    field = grid.reshape(ell)
    centre = [
        np.arange(n) if p or n < 3 else np.clip(np.arange(n), 1, n - 2)
        for n, p in zip(grid.shape, grid.periodic)
    ]
    total = np.zeros(len(feet))
    for a in range(grid.ndim):
        for b in range(a, grid.ndim):
            if (not grid.periodic[a] and shape[a] < 3) or (not grid.periodic[b] and shape[b] < 3):
                continue
            if a == b:
                h = np.roll(field, -1, a) - 2 * field + np.roll(field, 1, a)
            else:
                h = 0.25 * sum(
                    sign_a * sign_b * np.roll(field, (-sign_a, -sign_b), (a, b))
                    for sign_a in (1, -1)
                    for sign_b in (1, -1)
                )
            moment = np.minimum(f[:, a], f[:, b]) - f[:, a] * f[:, b]
            total += (1 if a == b else 2) * moment * h[np.ix_(*centre)].reshape(-1)[nearest]
    lin = (ell[idx] * weights).sum(axis=1)
    carried = weights > 0  # the range of the vertices that carry weight
    low = np.where(carried, ell[idx], np.inf).min(axis=1)
    high = np.where(carried, ell[idx], -np.inf).max(axis=1)
    limited = np.clip(lin - 0.5 * total, low, high)
    return limited - lin


def diffuse_fitted_numpy(
    y: np.ndarray,
    ell: np.ndarray,
    variance: float,
    h: float,
    periodic: bool,
    points: int = 64,
    images: int = 3,
) -> np.ndarray:
    """Plain-numpy twin of :func:`~gridlbc.backends.numba.fitted_diffusion.diffuse_fitted_kernel` on
    one line (``y`` ``(K, n)``, ``ell`` ``(n,)``): the same integral by the midpoint rule with
    ``points`` per cell over ``images`` line lengths to each side, every cell taken (no window), and
    the kernel's cap at the line's largest φ."""
    n = ell.size
    period = n if periodic else 2 * (n - 1)
    if periodic:
        left, centre, right = np.roll(ell, 1), ell, np.roll(ell, -1)
        kappa = left - 2 * centre + right
    else:
        inner = np.clip(np.arange(n), 1, n - 2)
        kappa = ell[inner - 1] - 2 * ell[inner] + ell[inner + 1]
    A = h * h / (2 * variance)
    m = np.arange(-images * n, images * n)
    k = np.mod(m, period)
    k0 = np.where(k > n - 1, period - k, k)
    k = np.mod(m + 1, period)
    k1 = np.where(k > n - 1, period - k, k)
    s = (np.arange(points) + 0.5) / points
    cell_kappa = np.minimum(0.5 * (kappa[k0] + kappa[k1]), A)[:, None]
    log_phi = (1 - s) * ell[k0, None] + s * ell[k1, None] - 0.5 * cell_kappa * s * (1 - s)
    y_bar = (1 - s) * y[:, k0, None] + s * y[:, k1, None]
    out = np.empty_like(y, dtype=float)
    for i in range(n):
        x = (m[:, None] - i + s) * h
        weight = np.exp(-x * x / (2 * variance) + log_phi) * h / points
        reference = weight.sum() / np.sqrt(2 * np.pi * variance)  # ∫ G_σ φ̄, capped at e^{max ℓ}
        cap = min(1.0, np.exp(ell.max()) / reference)
        out[:, i] = cap * (y_bar * weight).sum(axis=(1, 2)) / np.sqrt(2 * np.pi * variance)
    return out


def barycentric_numpy(grid: Grid, x) -> tuple[np.ndarray, np.ndarray]:
    """Plain-numpy twin of :func:`gridlbc.interpolate.barycentric`, for testing its kernel."""
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
