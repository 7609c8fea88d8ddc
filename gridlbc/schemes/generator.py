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
    boundary_nodes : ndarray of int (n_b,)
        The node of the exit set at the far end of each of those arms.
    second_order : tuple of two scipy.sparse.csr_matrix, or None
        A second-order, not monotone, discretisation L₂ of the same generator on the same nodes
        and boundary points (among the nodes, to the boundary points), for defect correction
        (:func:`exit_generator`); None unless asked for.
    """

    matrix: sp.csr_matrix
    boundary_rates: sp.csr_matrix
    boundary_points: np.ndarray
    boundary_nodes: np.ndarray
    second_order: tuple[sp.csr_matrix, sp.csr_matrix] | None = None


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


def exit_generator(
    problem: Problem, rates: str, exit_nodes: np.ndarray, second_order: bool = False
) -> Generator:
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

    With ``second_order`` it also assembles L₂, a second-order discretisation of
    aᵀ∇ + tr(D∇²) on the same nodes and boundary points, for defect correction
    (:mod:`gridlbc.stationary`): along each axis central diffusion (the Shortley–Weller
    weights 2D_kk / (h± (h₊ + h₋)) on unequal arms) and the drift differenced second-order
    upwind, along the direction of motion m = sign(a_k),

        a_k ∂_k z ≈ abs(a_k) (4 z_{i+m} − z_{i+2m} − 3 z_i) / (2 h_k),

    so that it never differences across the exit set's boundary behind a node, where z need not
    be smooth (on an axis without noise the paths that start there move away from the set).
    Where the exit set lies on the arm ahead, at distance h_d (the arm behind h_u), the three
    points i − m, i and the boundary point b give

        a_k ∂_k z ≈ abs(a_k) [h_u² (z_b − z_i) − h_d² (z_{i−m} − z_i)] / (h_d h_u (h_d + h_u)),

    where it lies two nodes ahead, central differences; where the node behind is not free
    either, and at the box's closed edges, L₂ keeps L₁'s rates along that axis. Its
    off-diagonal entries may be negative (it is not an M-matrix) and its rows sum to zero.

    Parameters
    ----------
    problem : Problem
        Drift, noise, grid and exit set.
    rates : str
        ``"upwind"`` or ``"fitted"`` away from the exit set (:data:`RATES`).
    exit_nodes : ndarray of bool (N,)
        The nodes in the exit set (absorbing).
    second_order : bool
        Also assemble L₂ (:attr:`Generator.second_order`).
    """
    return _assemble(problem, rates, exit_nodes, fit_exit=True, second_order=second_order)


def folded_exit_generator(problem: Problem, rates: str, exit_nodes: np.ndarray) -> sp.csr_matrix:
    """The generator of :func:`exit_generator` (the exit set's boundary fitted) as an N×N
    matrix for a march that carries z at the exit nodes: the jump to boundary point b, at rate
    r_b, becomes a jump to the exit node e at the far end of its arm with the weight

        c_b = exp(−(g_E(b) − g_E(x_e)) / λ),

    so that r_b c_b z_e = r_b exp(−g_E(b)/λ) wherever z_e = exp(−g_E(x_e)/λ), which the exit
    nodes keep from the terminal data on (times a slice's common scale). The map stays linear in
    z with off-diagonal entries ≥ 0. Among the nodes off the set it is :func:`exit_generator`'s
    matrix; the folded entries lie in the exit nodes' columns, whose rows hold no jumps, so a
    backward-Euler matrix I + Δt diag(q/λ) − Δt L is block triangular with that M-matrix block and
    its inverse is ≥ 0. Its rows next to the set no longer sum to zero where g_E varies along an
    arm. The weights depend on g_E, yet the march's equations off the set do not: each folded term
    is r_b exp(−g_E(b)/λ), linear in the exit values, so solutions for several exit costs on one
    set still combine exactly into the solution of the composite cost.

    Parameters
    ----------
    problem : Problem
        Drift, noise, grid, exit set and exit cost.
    rates : str
        ``"upwind"`` or ``"fitted"`` away from the exit set (:data:`RATES`).
    exit_nodes : ndarray of bool (N,)
        The nodes in the exit set (absorbing).
    """
    generator = exit_generator(problem, rates, exit_nodes)
    to_boundary = generator.boundary_rates.tocoo()
    if to_boundary.nnz == 0:
        return generator.matrix
    ends = generator.boundary_nodes[to_boundary.col]
    g_points = problem.exit_values(generator.boundary_points)[to_boundary.col]
    g_ends = problem.exit_values(problem.require_grid("the exit generator").nodes()[ends])
    weights = np.exp(np.minimum(-(g_points - g_ends) / problem.temperature, 700.0))
    folded = sp.coo_matrix(
        (to_boundary.data * weights, (to_boundary.row, ends)), shape=generator.matrix.shape
    )
    return (generator.matrix + folded).tocsr()


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
    problem: Problem,
    rates: str,
    absorbing: np.ndarray | None,
    fit_exit: bool,
    second_order: bool = False,
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
    b_rows, b_values, points, ends = [], [], [], []
    total = np.zeros(n_nodes)
    second: list = []  # the entries of L₂ (_second_order_axis)
    b_offset = 0
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
                # θ = 1: the set starts at the neighbour itself, whose exact coordinates are
                # where its exit cost is read (start + step can round to just outside E)
                crossed = problem.wrap(x[nodes] + theta[:, None] * step)
                at_node = theta == 1.0
                crossed[at_node] = x[targets[sign][nodes[at_node]]]
                points.append(crossed)
                ends.append(targets[sign][nodes])
        up, down = jump_rates(drift[:, k], diffusion[:, k], h, rates)
        fitted = cut[1] | cut[-1]  # unequal arms: Shortley–Weller with upwind drift
        if fitted.any():
            hp, hm, a, D = arms[1][fitted], arms[-1][fitted], drift[fitted, k], diffusion[fitted, k]
            up[fitted] = 2 * D / (hp * (hp + hm)) + np.maximum(a, 0.0) / hp
            down[fitted] = 2 * D / (hm * (hp + hm)) + np.maximum(-a, 0.0) / hm
        if second_order:  # the boundary points' columns, in the order they are appended
            b_cols = {}
            for sign in (1, -1):
                b_cols[sign] = np.full(n_nodes, -1)
                b_cols[sign][cut[sign]] = b_offset + np.arange(np.count_nonzero(cut[sign]))
                b_offset += int(np.count_nonzero(cut[sign]))
            second += _second_order_axis(
                flat, targets, valid, cut, arms, b_cols, drift[:, k], diffusion[:, k], h, up, down
            )
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
    boundary_nodes = np.concatenate(ends) if ends else np.empty(0, dtype=int)
    pair = None
    if second_order:
        pair = _second_order_matrices(second, n_nodes, n_b)
    L = (off - sp.diags(total)).tocsr()
    return Generator(L, to_boundary, boundary_points, boundary_nodes, pair)


def _second_order_matrices(entries: list, n_nodes: int, n_b: int):
    """(L₂ among the nodes, L₂ to the boundary points) from the entries of
    :func:`_second_order_axis`, the diagonal making every row sum to zero."""
    parts = {flag: [e for e in entries if e[3] is flag] for flag in (False, True)}
    stacked = {}
    for flag, group in parts.items():
        rows = np.concatenate([e[0] for e in group] + [np.empty(0, dtype=np.int64)])
        cols = np.concatenate([e[1] for e in group] + [np.empty(0, dtype=np.int64)])
        values = np.concatenate([e[2] for e in group] + [np.empty(0)])
        stacked[flag] = (rows, cols, values)
    rows, cols, values = stacked[False]
    off = sp.coo_matrix((values, (rows, cols)), shape=(n_nodes, n_nodes)).tocsr()
    b_rows, b_cols, b_values = stacked[True]
    to_boundary = sp.coo_matrix((b_values, (b_rows, b_cols)), shape=(n_nodes, n_b)).tocsr()
    total = np.bincount(rows, values, n_nodes) + np.bincount(b_rows, b_values, n_nodes)
    return (off - sp.diags(total)).tocsr(), to_boundary


def _second_order_axis(flat, targets, valid, cut, arms, b_cols, a, D, h, up, down) -> list:
    """The entries (rows, columns, coefficients, whether the columns are boundary points) of
    the second-order L₂ along one axis (:func:`exit_generator`, ``second_order``), with L₁'s
    rates ``up``, ``down`` for the box's closed edges."""
    free1 = {m: valid[m] & ~cut[m] for m in (1, -1)}
    free2 = {m: free1[m] & free1[m][targets[m]] for m in (1, -1)}
    target2 = {m: targets[m][targets[m]] for m in (1, -1)}
    moving = valid[1] | valid[-1] | cut[1] | cut[-1]
    edge = moving & ~(valid[1] & valid[-1])
    out = []

    def add(where, m, coefficient, ahead=1):
        """Coefficients on the node (or boundary point) ``ahead`` steps along m."""
        if ahead == 2:
            out.append((flat[where], target2[m][where], coefficient[where], False))
            return
        node, point = where & ~cut[m], where & cut[m]
        out.append((flat[node], targets[m][node], coefficient[node], False))
        out.append((flat[point], b_cols[m][point], coefficient[point], True))

    for m, rate in ((1, up), (-1, down)):  # the box's edges: L₁'s rates
        add(edge & valid[m] & (rate > 0), m, rate)
    inner = moving & ~edge
    hp, hm = arms[1], arms[-1]
    for m, arm in ((1, hp), (-1, hm)):  # diffusion
        add(inner & (D > 0), m, 2 * D / (arm * (hp + hm)))
    speed = np.abs(a)
    for m in (1, -1):  # drift, along the direction of motion m
        go = inner & (np.sign(a) == m)
        ahead, behind = arms[m], arms[-m]
        at_exit = go & cut[m] & free1[-m]
        add(at_exit, m, speed * behind / (ahead * (ahead + behind)))
        add(at_exit, -m, -speed * ahead / (behind * (ahead + behind)))
        add(go & cut[m] & ~free1[-m], m, speed / ahead)
        upwind2 = go & free2[m]
        add(upwind2, m, 2 * speed / h)
        add(upwind2, m, -0.5 * speed / h, ahead=2)
        central = go & free1[m] & ~free2[m] & free1[-m]
        add(central, m, 0.5 * speed / h)
        add(central, -m, -0.5 * speed / h)
        add(go & free1[m] & ~free2[m] & ~free1[-m], m, speed / h)
    return out
