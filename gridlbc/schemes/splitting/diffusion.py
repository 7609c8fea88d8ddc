"""The diffusion half step D½ of the splitting: implicit, one noise axis k at a time,

    (I − ½Δt D_k(x) δ²_k) z' = z,      D_k = ½ (λ B R⁻¹ Bᵀ)_kk,

δ²_k the three-point second difference. Each line is a tridiagonal M-matrix: cyclic on a periodic
axis (solved by Sherman–Morrison), and on a closed axis with the jumps out of the box dropped, the
reflecting state constraint (:mod:`gridlbc.boundary`), solved with Thomas factors computed once
per solve (:func:`tridiagonal_factors`). Backward Euler makes it unconditionally stable and
monotone; its error is O(Δt).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ... import boundary
from ...backends.numba.diffusion import (
    closed_line_tasks,
    diffuse_closed_kernel,
    diffuse_periodic_kernel,
)
from ...backends.numba.options import work_blocks
from ...boundary import Boundary
from ...grid import Grid


class NoiseAxis(NamedTuple):
    """One axis the noise acts on, as the diffusion passes need it: its index ``axis``; whether
    it is ``periodic``; ``data``, the implicit half step's ratios r = ½Δt D_k/h_k² per node
    (periodic) or its Thomas factors (closed: ``(3, n)`` when the same on every line, flagged
    ``uniform``, else ``(3, N)``); and ``variance``, σ² = 2 D_k ½Δt of the half step, one value
    when the same at every node, else one per node (the fitted diffusion's Gaussian)."""

    axis: int
    periodic: bool
    data: np.ndarray
    uniform: bool
    variance: np.ndarray


def tridiagonal_factors(ratio: np.ndarray, n: int) -> np.ndarray:
    """LU factors of (1 + 2r_i) z_i − r_i (z_{i−1} + z_{i+1}) on closed lines of length n.

    ``ratio`` holds r = Δt D / h² along the lines (shape ``(..., n)``, the line index last); the
    out-of-box neighbour is dropped at both ends (row 0: (1 + r_0) z_0 − r_0 z_1). Returns
    ``(3, ..., n)``: 1/m_i, r_i/m_i and c_i = −r_i/m_i (c_{n−1} = 0) of the Thomas recursion
    y_i = (b_i + r_i y_{i−1})/m_i, z_i = y_i − c_i z_{i+1}.
    """
    ratio = np.asarray(ratio, dtype=float)
    lower = ratio.copy()
    lower[..., 0] = 0.0
    upper = ratio.copy()
    upper[..., n - 1] = 0.0
    diag = 1.0 + lower + upper
    out = np.empty((3, *ratio.shape))
    c_prev = np.zeros(ratio.shape[:-1])
    for i in range(n):
        m = diag[..., i] + lower[..., i] * c_prev
        out[0, ..., i] = 1.0 / m
        out[1, ..., i] = lower[..., i] / m
        c_prev = -upper[..., i] / m
        out[2, ..., i] = c_prev
    return out


def noise_axes(grid: Grid, diffusion: list, dt: float) -> list[NoiseAxis]:
    """The :class:`NoiseAxis` of every axis with D_k > 0 somewhere, for a diffusion over ``dt``
    (the half step) with the D_k of ``diffusion`` (a float, or one per node)."""
    boundaries = boundary.require(
        grid, (Boundary.PERIODIC, Boundary.REFLECTING), "the splitting's diffusion"
    )
    axes = []
    for k, (ax, coefficient) in enumerate(zip(grid.axes, diffusion, strict=True)):
        if not np.any(coefficient > 0):
            continue
        ratio = dt * coefficient / ax.spacing**2
        variance = 2.0 * dt * coefficient
        constant = np.ndim(coefficient) == 0
        if constant or np.all(variance == variance[0]):
            variance = np.full(1, variance) if constant else variance[:1]
        if boundaries[k] is Boundary.PERIODIC:
            data = np.full(grid.size, ratio) if constant else ratio
            axes.append(NoiseAxis(k, True, data, False, variance))
            continue
        # Boundary.REFLECTING: tridiagonal_factors drops the jump out of the box
        if constant:
            factors = tridiagonal_factors(np.full(ax.n, ratio), ax.n)
            axes.append(NoiseAxis(k, False, factors, True, variance))
            continue
        lines = np.moveaxis(grid.reshape(ratio), k, -1)
        uniform = bool(np.all(lines == lines.reshape(-1, ax.n)[0]))
        if uniform:
            factors = tridiagonal_factors(lines.reshape(-1, ax.n)[0], ax.n)
        else:
            factors = np.moveaxis(tridiagonal_factors(lines, ax.n), -1, k + 1)
            factors = factors.reshape(3, grid.size)
        axes.append(NoiseAxis(k, False, np.ascontiguousarray(factors), uniform, variance))
    return axes


def max_blocks(grid: Grid, noise: list[NoiseAxis]) -> int:
    """Columns of the block maxima that :func:`half_diffusion` can fuse into its last pass (a
    closed axis), or 0 where it cannot (no noise, or a periodic last axis)."""
    if not noise or noise[-1].periodic:
        return 0
    k = noise[-1].axis
    return work_blocks(closed_line_tasks(grid.size, grid.axes[k].n, int(grid.strides[k])))


def half_diffusion(
    grid: Grid, noise: list[NoiseAxis], z: np.ndarray, block_max: np.ndarray | None = None
):
    """D½ in place on every noise axis of ``z`` ``(K, N)``; the last pass (a closed axis) also
    records the row maxima per block of lines in ``block_max`` when it is given
    (:func:`max_blocks` columns)."""
    off = np.zeros((z.shape[0], 0))  # a zero-width block_max turns the maxima off
    for position, (k, periodic, data, uniform, _) in enumerate(noise):
        ax, stride = grid.axes[k], int(grid.strides[k])
        if periodic:
            diffuse_periodic_kernel(z, data, ax.n, stride)
            continue
        last = position == len(noise) - 1 and block_max is not None
        diffuse_closed_kernel(z, data, uniform, ax.n, stride, block_max if last else off)
