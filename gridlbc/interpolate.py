"""Barycentric interpolation on the Kuhn (Freudenthal) triangulation of a grid (docs/maths.rst).

A state x falls in the cell with lower corner i = ⌊(x − lo)/h⌋ and fractional coordinates
f = (x − lo)/h − i ∈ [0, 1]ᵈ. Sorting f in decreasing order, f_π(1) ≥ … ≥ f_π(d), picks the simplex
with vertices

    v_0 = i,   v_j = v_{j−1} + e_π(j)   (j = 1 … d)

and barycentric weights

    w_0 = 1 − f_π(1),   w_j = f_π(j) − f_π(j+1),   w_d = f_π(d),

which are non-negative, sum to one and reproduce affine functions exactly. Periodic axes wrap
(the neighbour of node n−1 is node 0); on other axes points are clamped to the box first.

Interpolation is linear in the nodal values, so anything evaluated from interpolated z and
interpolated Bᵀ∇z stays linear in z (the superposition guarantee of docs/maths.rst).
"""

from __future__ import annotations

import numpy as np

from .backends.numba.interpolation import (
    SERIAL_BELOW,
    central_gradient_kernel,
    central_gradient_kernel_serial,
    kuhn_kernel,
    kuhn_kernel_serial,
)
from .grid import Grid


def barycentric(grid: Grid, x) -> tuple[np.ndarray, np.ndarray]:
    """Simplex vertices and barycentric weights of states ``x`` ``(N, d)`` on ``grid``.

    Returns ``(idx, weights)``, both ``(N, d+1)``: flat node indices and weights ≥ 0 summing to one,
    so that the interpolant of nodal values ``f`` is ``(f[idx] * weights).sum(-1)``.
    """
    x = grid.check_states(x)
    n = x.shape[0]
    idx = np.empty((n, grid.ndim + 1), dtype=np.int64)
    weights = np.empty((n, grid.ndim + 1))
    kernel = kuhn_kernel if n >= SERIAL_BELOW else kuhn_kernel_serial
    kernel(np.ascontiguousarray(x), *grid.kernel_arrays(), idx, weights)
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
    kernel = (
        central_gradient_kernel if nodes.size >= SERIAL_BELOW else central_gradient_kernel_serial
    )
    kernel(
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
