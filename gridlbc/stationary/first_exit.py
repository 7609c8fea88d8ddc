"""First exit without a horizon (SPEC §9; docs page :doc:`first_exit`): the linear system
(diag(q/λ) − L)_II z_I = L_IE z_E + L_Ib z_b over the nodes off the exit set, solved once for
several exit costs (:mod:`gridlbc.stationary`)."""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from ..errors import ResolutionWarning, state_text, warn_user
from ..grid import Grid
from ..problem import Problem
from ..schemes.generator import Generator, exit_generator, generator_matrix
from ..solution import StationarySolution
from .linear import (
    StationarySettings,
    accurate_tail,
    linear_method,
    linear_solver,
    operator_digest,
    packaged,
)


def exit_nodes(problem: Problem) -> np.ndarray:
    """The grid nodes in the exit set, boolean ``(N,)``, or a clear error when the grid cannot
    resolve the set (no node in it) or when every node is in it."""
    grid = problem.require_grid("a first-exit solve")
    mask = problem.exit_mask()
    if not mask.any():
        raise ValueError(
            f"the exit set {problem.exit!r} contains no node of the grid ({grid.describe()}): it "
            "lies outside the box or is narrower than a cell. Move it into the box, widen it, or "
            "refine the grid"
        )
    if mask.all():
        raise ValueError(
            f"every node of the grid lies in the exit set {problem.exit!r}: the task ends before "
            "it starts; shrink the exit set or widen the box"
        )
    return mask


def reaching(L: sp.csr_matrix, sinks: np.ndarray) -> np.ndarray:
    """The nodes from which the chain of generator ``L`` can reach one of ``sinks`` (boolean
    ``(N,)`` each) along its jumps: a breadth-first search from a virtual node joined to every
    sink, along the jumps reversed."""
    n = L.shape[0]
    off = (L - sp.diags(L.diagonal())).tocsr()
    targets = np.flatnonzero(sinks)
    source = sp.csr_matrix(
        (np.ones(len(targets)), (np.zeros(len(targets), dtype=np.int64), targets)), shape=(1, n)
    )
    graph = sp.bmat([[off.T, None], [source, sp.csr_matrix((1, 1))]], format="csr")
    reached = np.zeros(n + 1, dtype=bool)
    reached[csgraph.breadth_first_order(graph, n, directed=True, return_predecessors=False)] = True
    return reached[:n]


def check_well_posed(L: sp.csr_matrix, sinks: np.ndarray, grid: Grid) -> None:
    """Refuse a problem in which some nodes can reach neither a sink (a node of E or one with
    q > 0) along the chain's jumps (:func:`reaching`): their desirability is undetermined
    (nothing is ever paid and nothing ends the task; the linear system is singular there)."""
    stuck = np.flatnonzero(~reaching(L, sinks))
    if len(stuck):
        x = state_text(grid.node_coordinates(stuck[:1])[0])
        raise ValueError(
            f"{len(stuck)} of {grid.size} nodes (e.g. {x}) reach neither the exit set nor a state "
            "cost q > 0: the problem is ill-posed there (nothing ends the task and nothing is "
            "paid). Give a state cost q > 0, or an exit set that every state can reach"
        )


def solve_first_exit(problem: Problem, s: StationarySettings) -> StationarySolution:
    """The stationary first-exit solution of ``problem`` (module docstring).

    Parameters
    ----------
    problem : Problem
        With ``horizon=None`` and an exit set.
    s : StationarySettings

    Returns
    -------
    StationarySolution
    """
    return solve_first_exit_many(problem, [problem.exit_cost], s)[0]


def solve_first_exit_many(problem: Problem, exit_costs, s: StationarySettings) -> list:
    """First-exit solutions of ``problem`` for several exit costs on its exit set: one generator,
    one factorisation (or one Krylov solve per cost), so that they are solutions of one linear
    operator and combine exactly (:func:`gridlbc.combine`).

    Parameters
    ----------
    problem : Problem
        With ``horizon=None`` and an exit set; its own ``exit_cost`` is not used.
    exit_costs : sequence of callable
        The exit costs g_i.
    s : StationarySettings

    Returns
    -------
    list of StationarySolution
        One per exit cost, each as :func:`~gridlbc.stationary.first_exit.solve_first_exit` gives for
        ``problem.replace(exit_cost=g_i)``.
    """
    start = time.perf_counter()
    grid = problem.require_grid("solve")
    problem.noise_diagonal(grid.node_coordinates([0]))  # refuse cross-diffusion first
    E = exit_nodes(problem)
    lam = problem.temperature
    q = np.where(E, 0.0, problem.state_cost_values())
    if s.fit_exit:
        generator = exit_generator(problem, s.rates, E, second_order=s.defect_correction > 0)
    else:
        L0 = generator_matrix(problem, s.rates, absorbing=E)
        generator = Generator(
            L0, sp.csr_matrix((grid.size, 0)), np.empty((0, grid.ndim)), np.empty(0, int)
        )
    L, to_boundary = generator.matrix, generator.boundary_rates
    reaches_boundary = np.asarray(to_boundary.sum(axis=1)).ravel() > 0
    # where the chain never reaches E, the task never ends and z = 0 exactly (v = +inf); there
    # it must pay q > 0 somewhere on its way
    never = ~reaching(L, E | reaches_boundary)
    if never.any():
        check_well_posed(L, E | (q > 0) | reaches_boundary, grid)
    interior = np.flatnonzero(~E)
    A = (sp.diags(q / lam) - L).tocsr()[interior]
    problems = [problem.replace(exit_cost=cost) for cost in exit_costs]
    tops, z_exits, rhs, z_boundary = [], [], [], []
    for p in problems:
        g_nodes = p.exit_values()[E]
        g_points = np.empty(0)
        if len(generator.boundary_points):
            g_points = p.exit_values(generator.boundary_points)
        g_min = min(g_nodes.min(), np.min(g_points, initial=np.inf))
        tops.append(-g_min / lam)  # z_E = exp(−g_E/λ) = e^top · exp(−(g_E − min g_E)/λ)
        with np.errstate(under="ignore"):
            z_exit = np.exp(-(g_nodes - g_min) / lam)
            z_points = np.exp(-(g_points - g_min) / lam)
        z_exits.append(z_exit)
        z_boundary.append(z_points)
        rhs.append(-A[:, np.flatnonzero(E)] @ z_exit + to_boundary[interior] @ z_points)
    setup = time.perf_counter() - start
    A_II = A[:, interior].tocsr()
    solver = linear_solver(A_II, s, grid.ndim)
    Z, iterations = solver(np.stack(rhs, axis=1))
    if generator.second_order is None and linear_method(s, grid.ndim, len(interior)) != "direct":
        for r in range(Z.shape[1]):  # the Krylov solve resolves z relative to its largest only
            Z[:, r] = accurate_tail(A_II, rhs[r], Z[:, r], s, grid.ndim)
    digest = operator_digest(E, q, L.data, to_boundary.data, generator.boundary_points)
    label = f"stationary-{s.rates}"
    if generator.second_order is not None:
        Z, corrected, more = _defect_correction(
            Z, solver, generator.second_order, q / lam, E, z_exits, z_boundary, s, never
        )
        iterations += more
        if corrected:  # another linear map of the exit values: another operator
            L2, to_boundary2 = generator.second_order
            digest = operator_digest(
                np.frombuffer(digest.encode(), np.uint8), L2.data, to_boundary2.data
            )
            label += f"+dc{s.defect_correction}"
    out = []
    for r, p in enumerate(problems):
        z = np.empty(grid.size)
        z[E], z[interior] = z_exits[r], Z[:, r]
        np.clip(z, 0.0, None, out=z)  # an iterative solve's rounding may dip below zero
        z[never] = 0.0
        counts = (iterations,) if iterations else ()
        out.append(packaged(p, label, z, tops[r], start, setup, counts, digest, never))
    return out


def _defect_correction(Z, solver, second_order, decay, E, z_exits, z_boundary, s, never):
    """``s.defect_correction`` steps of defect correction (Hemker; Trottenberg, Oosterlee and
    Schüller, *Multigrid*, §5.4) of the first-order solutions ``Z`` ``(n_I, K)`` of
    A₁ z_I = b₁, A₁ = (diag(q/λ) − L₁)_II: with the second-order L₂ of the same generator
    (:func:`gridlbc.schemes.generator.exit_generator`) and its system A₂ z_I = b₂,

        z_{j+1} = z_j + A₁⁻¹ (b₂ − A₂ z_j),        b₂ = L₂_IE z_E + L₂_Ib z_b,

    solved by ``solver`` (A₁'s factorisation or Krylov solve, reused). The fixed point is
    L₂'s solution; one step from z₁ leaves the error A₁⁻¹ (A₁ − A₂)(z₁ − z) = O(h²) where z
    and the first-order error are smooth, so one or two steps raise the order from one to
    two on the axes without noise. Each step is linear in (z_E, z_b), so the columns of ``Z``
    (exit costs on one exit set) stay solutions of one linear map.

    Where z is not resolved (v changes by many λ across a cell) the first-order z is off by a
    large factor, the correction overshoots and z can come out negative (read off the nodes
    ``never``, from which the chain never reaches E and z is 0): then every column keeps the
    first-order solution (the same map for all, so they still combine exactly) and a
    :class:`gridlbc.ResolutionWarning` says so.

    Returns
    -------
    (Z, corrected, iterations) : the corrected (or the first-order) solutions, whether the
    correction was kept, the Krylov iterations of the correction solves (0 for LU).
    """
    L2, to_boundary2 = second_order
    interior = np.flatnonzero(~E)
    A2 = (sp.diags(decay) - L2).tocsr()[interior]
    known = np.stack(
        [
            A2[:, np.flatnonzero(E)] @ z_exit - to_boundary2[interior] @ z_points
            for z_exit, z_points in zip(z_exits, z_boundary)
        ],
        axis=1,
    )  # −b₂ per column
    A2 = A2[:, interior]
    corrected, total = Z, 0
    for _ in range(s.defect_correction):
        delta, iterations = solver(-known - A2 @ corrected)
        corrected, total = corrected + delta, total + iterations
    reach = ~never[interior]  # elsewhere z is 0 in both: the chain never reaches E
    if np.all(corrected[reach] > 0):
        return corrected, True, total
    negative = np.count_nonzero(np.any(corrected[reach] <= 0, axis=1))
    warn_user(
        f"defect correction made z ≤ 0 at {negative} of {len(corrected)} nodes: the grid does "
        "not resolve z = exp(−v/λ) (v changes by much more than λ across a cell); the "
        "solution is the first-order one. Refine the grid, or raise the temperature",
        ResolutionWarning,
    )
    return Z, False, total
