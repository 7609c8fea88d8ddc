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
    input_gradient_kernel,
    input_gradient_kernel_serial,
    interpolate_kernel,
    interpolate_kernel_serial,
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
    if values.dtype not in (np.float32, np.float64):
        values = values.astype(float)
    idx, weights = barycentric(grid, x)
    one = np.ones(1)
    rows = [
        interpolate_slices(row[None], one, idx, weights) for row in values.reshape(-1, grid.size)
    ]
    return np.reshape(rows, values.shape[:-1] + (len(idx),))


def interpolate_slices(
    values: np.ndarray,
    time_weights: np.ndarray,
    nodes: np.ndarray,
    weights: np.ndarray,
    log_divisor: np.ndarray | None = None,
) -> np.ndarray:
    """Nodal slices interpolated at N states from their simplices, ``(N,)``:

        Σ_v w_v Σ_r τ_r y_r(x_v),      y_r = values[r] (/ e^{log_divisor[r]} if given),

    linear in ``values`` when ``log_divisor`` is None.

    Parameters
    ----------
    values : ndarray (K, size)
        Nodal values of K slices (float64 or float32).
    time_weights : ndarray (K,)
        τ_r, the slices' weights.
    nodes, weights : ndarray (N, V)
        Flat node indices and weights of each state's vertices (:func:`barycentric`).
    log_divisor : ndarray (K, size), optional
        Divide the values by e^{log_divisor} node by node first (zero where a value is).
    """
    z, tau, divisor, nodes, weights = _slices_on_simplices(
        values, time_weights, nodes, weights, log_divisor
    )
    out = np.empty(len(nodes))
    kernel = interpolate_kernel if len(nodes) >= SERIAL_BELOW else interpolate_kernel_serial
    kernel(z, tau, divisor, nodes, weights, out)
    return out


def _slices_on_simplices(values, time_weights, nodes, weights, log_divisor):
    """``(values, time_weights, log_divisor, nodes, weights)`` as the kernels take them:
    contiguous, float64 weights, int64 nodes, and a divisor without columns where none is
    given."""
    values = np.ascontiguousarray(values)
    divisor = (
        np.empty((values.shape[0], 0)) if log_divisor is None else np.ascontiguousarray(log_divisor)
    )
    return (
        values,
        np.ascontiguousarray(time_weights, dtype=float),
        divisor,
        np.ascontiguousarray(nodes, dtype=np.int64),
        np.ascontiguousarray(weights, dtype=float),
    )


def input_gradient(
    grid: Grid,
    values: np.ndarray,
    time_weights: np.ndarray,
    nodes: np.ndarray,
    weights: np.ndarray,
    input_matrix: np.ndarray,
    log_divisor: np.ndarray | None = None,
) -> np.ndarray:
    """Bᵀ∇y interpolated at N states from their simplices, ``(N, m)``:

        Σ_v w_v B(x_v)ᵀ Σ_r τ_r ∇y_r(x_v),      y_r = values[r] (/ e^{log_divisor[r]} if given),

    with ∇y_r by finite differences at the vertices along the axes that B drives: second-order
    central differences in the interior and on periodic axes, first-order one-sided ones at the
    ends of a closed axis. Linear in ``values`` when ``log_divisor`` is None.

    Parameters
    ----------
    grid : Grid
    values : ndarray (K, size)
        Nodal values of K slices (float64 or float32).
    time_weights : ndarray (K,)
        τ_r, the slices' weights.
    nodes, weights : ndarray (N, V)
        Flat node indices and weights of each state's vertices (:func:`barycentric`; V = 1 with
        weight 1 reads the derivative at nodes).
    input_matrix : ndarray (N, V, d, m)
        B at the vertices; broadcast from one (d, m) matrix where B is constant.
    log_divisor : ndarray (K, size), optional
        Divide the values by e^{log_divisor} node by node first.
    """
    B = np.asarray(input_matrix, dtype=float)
    if B.strides[0] == 0 and B.strides[1] == 0:  # constant B, broadcast
        B = B[:1, :1]
    B = np.ascontiguousarray(B)
    axes = np.flatnonzero(B.any(axis=(0, 1, 3))).astype(np.int64)  # the axes B drives
    z, tau, divisor, nodes, weights = _slices_on_simplices(
        values, time_weights, nodes, weights, log_divisor
    )
    out = np.empty((len(nodes), B.shape[-1]))
    kernel = input_gradient_kernel if len(nodes) >= SERIAL_BELOW else input_gradient_kernel_serial
    _, spacing, shape, strides, periodic = grid.kernel_arrays()
    kernel(z, tau, divisor, nodes, weights, B, axes, shape, strides, spacing, periodic, out)
    return out
