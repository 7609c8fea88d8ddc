"""The generator of a monotone Markov chain on the nodes that approximates aᵀ∇ + tr(D ∇²),
D = ½ λ B R⁻¹ Bᵀ (diagonal): the operator of the implicit scheme and of the stationary solves.

From node i the chain jumps along each axis k to its neighbours i ± e_k at rates r± ≥ 0 with

    r₊ − r₋ = a_k / h_k,                                          (the drift, exactly)

so L z = Σ_k r₊ (z_{i+e_k} − z_i) + r₋ (z_{i−e_k} − z_i) has rows summing to zero and
non-negative off-diagonal entries: (diag(q/λ) − L) is an M-matrix, and z ≥ 0 with the discrete
maximum principle. Two choices of the rates:

- ``"upwind"``: r± = max(±a_k, 0)/h_k + D_kk/h_k², first order, with numerical diffusion
  |a_k| h_k / 2 along each axis;
- ``"fitted"`` (exponential fitting; Scharfetter–Gummel, Il'in–Allen–Southwell): with the cell
  Péclet number P = a_k h_k / D_kk and the Bernoulli function B(s) = s/(eˢ − 1),

      r₊ = (D_kk/h_k²) B(−P),      r₋ = (D_kk/h_k²) B(P),

  central (second order) where the noise dominates a cell, upwind where the drift does, exact
  for a constant drift and diffusion along the axis in one dimension, and monotone for every P.
  Where D_kk = 0 it is the upwind rate.

Periodic axes wrap; on a closed axis a jump out of the box is dropped
(:attr:`gridlbc.boundary.Boundary.REFLECTING`). Nodes given as ``absorbing`` (those of an exit
set, SPEC §9) have no jumps at all: the chain stops there.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .. import boundary
from ..boundary import Boundary
from ..problem import Problem

RATES = ("upwind", "fitted")
"""How the jump rates are chosen (module docstring)."""


def bernoulli(s: np.ndarray) -> np.ndarray:
    """B(s) = s / (eˢ − 1), with B(0) = 1; 0 where eˢ overflows."""
    s = np.asarray(s, dtype=float)
    out = np.ones_like(s)
    nonzero = s != 0
    with np.errstate(over="ignore"):
        out[nonzero] = s[nonzero] / np.expm1(s[nonzero])
    return out


def jump_rates(drift: np.ndarray, diffusion: np.ndarray, h: float, rates: str):
    """The rates (r₊, r₋) along one axis at each node from a_k ``(N,)`` and D_kk ``(N,)``."""
    if rates == "upwind":
        return (
            np.maximum(drift, 0.0) / h + diffusion / h**2,
            np.maximum(-drift, 0.0) / h + diffusion / h**2,
        )
    noisy = diffusion > 0
    up, down = np.maximum(drift, 0.0) / h, np.maximum(-drift, 0.0) / h
    peclet = drift[noisy] * h / diffusion[noisy]
    scale = diffusion[noisy] / h**2
    up[noisy] = scale * bernoulli(-peclet)
    down[noisy] = scale * bernoulli(peclet)
    return up, down


def generator_matrix(
    problem: Problem, rates: str = "upwind", absorbing: np.ndarray | None = None
) -> sp.csr_matrix:
    """The generator L (N×N, CSR) on ``problem``'s grid: off-diagonal rates ≥ 0, rows summing to
    zero (module docstring).

    Parameters
    ----------
    problem : Problem
        Drift, noise and grid.
    rates : str
        ``"upwind"`` or ``"fitted"`` (:data:`RATES`).
    absorbing : ndarray of bool (N,), optional
        Nodes with no jumps (an exit set's).
    """
    if rates not in RATES:
        raise ValueError(f"rates must be one of {', '.join(RATES)}, got {rates!r}")
    grid = problem.grid
    assert grid is not None
    boundaries = boundary.require(
        grid, (Boundary.PERIODIC, Boundary.REFLECTING), "the Markov-chain generator"
    )
    x = grid.nodes()
    drift = np.asarray(problem.system.drift(x), dtype=float)
    diffusion = 0.5 * problem.noise_diagonal(x)
    n_nodes = grid.size
    flat = np.arange(n_nodes)
    multi = np.unravel_index(flat, grid.shape)
    moving = np.ones(n_nodes, dtype=bool) if absorbing is None else ~absorbing
    rows, cols, values = [], [], []
    for k, ax in enumerate(grid.axes):
        h, s = ax.spacing, int(grid.strides[k])
        i = multi[k]
        for sign, rate in zip((1, -1), jump_rates(drift[:, k], diffusion[:, k], h, rates)):
            target_i = i + sign
            if boundaries[k] is Boundary.PERIODIC:
                target = flat + s * (np.mod(target_i, ax.n) - i)
                keep = (rate > 0) & moving
            else:  # Boundary.REFLECTING: no jump out of the box
                target = flat + sign * s
                keep = (rate > 0) & moving & (target_i >= 0) & (target_i < ax.n)
            rows.append(flat[keep])
            cols.append(target[keep])
            values.append(rate[keep])
    entries = (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols)))
    off = sp.coo_matrix(entries, shape=(n_nodes, n_nodes)).tocsr()
    return (off - sp.diags(np.asarray(off.sum(axis=1)).ravel())).tocsr()
