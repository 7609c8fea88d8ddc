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

from dataclasses import dataclass

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


@dataclass(frozen=True)
class Generator:
    """A generator with its jumps to the exit set's boundary (:func:`exit_generator`).

    Attributes
    ----------
    matrix : scipy.sparse.csr_matrix (N, N)
        L among the nodes; its diagonal is minus every rate out of a node, the jumps to boundary
        points included (so its rows sum to minus those).
    boundary_rates : scipy.sparse.csr_matrix (N, n_b)
        The rates of the jumps from the nodes next to the exit set to its boundary points.
    boundary_points : ndarray (n_b, d)
        Where each of those arms meets the exit set.
    """

    matrix: sp.csr_matrix
    boundary_rates: sp.csr_matrix
    boundary_points: np.ndarray


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
    return _assemble(problem, rates, absorbing, fit_exit=False).matrix


def exit_generator(problem: Problem, rates: str, exit_nodes: np.ndarray) -> Generator:
    """The generator of a first-exit problem with its exit set's boundary fitted: a node next to
    the set along axis k jumps to the point where the segment to its neighbour enters the set,
    at distance θh (θ ∈ (0, 1], found by bisection on the set's mask), instead of to the
    neighbour node. At such a node the rates along k are those of unequal arms h₊, h₋
    (Shortley–Weller),

        r± = 2 D_kk / (h± (h₊ + h₋)) + max(±a_k, 0)/h±,

    which keep the drift (r₊h₊ − r₋h₋ = a_k) and the variance (r₊h₊² + r₋h₋² = 2D_kk + O(h)) and
    stay non-negative: the matrix is still an M-matrix. The exit set's position is then resolved
    to the bisection's precision rather than to a cell, and the boundary condition
    z = exp(−g_E/λ) is imposed where the set begins.

    Parameters
    ----------
    problem : Problem
        Drift, noise, grid and exit set.
    rates : str
        ``"upwind"`` or ``"fitted"`` away from the exit set (:data:`RATES`).
    exit_nodes : ndarray of bool (N,)
        The nodes in the exit set (absorbing).
    """
    return _assemble(problem, rates, exit_nodes, fit_exit=True)


BISECTIONS = 40
"""Bisection steps that locate the exit set's boundary on an arm (to 2⁻⁴⁰ of the cell)."""


def _crossing(problem: Problem, start: np.ndarray, step: np.ndarray) -> np.ndarray:
    """θ ∈ (0, 1] per arm: where ``start + θ step`` (outside the exit set at θ = 0, inside at 1)
    first enters it, to 2⁻:data:`BISECTIONS` (the inside end of the last bracket)."""
    lo, hi = np.zeros(len(start)), np.ones(len(start))
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        inside = problem.exit_mask(problem.wrap(start + mid[:, None] * step))
        hi = np.where(inside, mid, hi)
        lo = np.where(inside, lo, mid)
    return hi


def _assemble(
    problem: Problem, rates: str, absorbing: np.ndarray | None, fit_exit: bool
) -> Generator:
    if rates not in RATES:
        raise ValueError(f"rates must be one of {', '.join(RATES)}, got {rates!r}")
    grid = problem.require_grid("the Markov-chain generator")
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
    b_rows, b_values, points = [], [], []
    total = np.zeros(n_nodes)
    for k, ax in enumerate(grid.axes):
        h, s = ax.spacing, int(grid.strides[k])
        i = multi[k]
        targets, valid, arms = {}, {}, {}
        for sign in (1, -1):
            target_i = i + sign
            if boundaries[k] is Boundary.PERIODIC:
                targets[sign] = flat + s * (np.mod(target_i, ax.n) - i)
                valid[sign] = moving.copy()
            else:  # Boundary.REFLECTING: no jump out of the box
                inside = (target_i >= 0) & (target_i < ax.n)
                targets[sign] = np.where(inside, flat + sign * s, flat)
                valid[sign] = moving & inside
            arms[sign] = np.full(n_nodes, h)
        cut = {sign: np.zeros(n_nodes, dtype=bool) for sign in (1, -1)}
        if fit_exit and absorbing is not None:
            for sign in (1, -1):
                cut[sign] = valid[sign] & absorbing[targets[sign]]
                nodes = np.flatnonzero(cut[sign])
                step = np.zeros((len(nodes), grid.ndim))
                step[:, k] = sign * h
                theta = _crossing(problem, x[nodes], step)
                arms[sign][nodes] = theta * h
                points.append(problem.wrap(x[nodes] + theta[:, None] * step))
        up, down = jump_rates(drift[:, k], diffusion[:, k], h, rates)
        fitted = cut[1] | cut[-1]  # unequal arms: Shortley–Weller with upwind drift
        if fitted.any():
            hp, hm, a, D = arms[1][fitted], arms[-1][fitted], drift[fitted, k], diffusion[fitted, k]
            up[fitted] = 2 * D / (hp * (hp + hm)) + np.maximum(a, 0.0) / hp
            down[fitted] = 2 * D / (hm * (hp + hm)) + np.maximum(-a, 0.0) / hm
        for sign, rate in ((1, up), (-1, down)):
            keep = valid[sign] & (rate > 0)
            total[keep] += rate[keep]
            to_node = keep & ~cut[sign]
            rows.append(flat[to_node])
            cols.append(targets[sign][to_node])
            values.append(rate[to_node])
            b_rows.append(flat[cut[sign]])
            b_values.append(rate[cut[sign]])
    entries = (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols)))
    off = sp.coo_matrix(entries, shape=(n_nodes, n_nodes)).tocsr()
    n_b = sum(len(r) for r in b_rows)
    b_entries = (np.concatenate(b_values), (np.concatenate(b_rows), np.arange(n_b)))
    to_boundary = sp.coo_matrix(b_entries, shape=(n_nodes, n_b)).tocsr()
    boundary_points = np.concatenate(points) if points else np.empty((0, grid.ndim))
    return Generator((off - sp.diags(total)).tocsr(), to_boundary, boundary_points)
