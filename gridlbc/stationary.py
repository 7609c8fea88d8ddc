"""Stationary problems: first exit without a horizon, and average cost (SPEC §9; docs page
:doc:`first_exit`; Todorov 2009).

**First exit.** The task ends at τ, the first time the state enters the exit set E, paying
g_E(x_τ). Off E, z = exp(−v/λ) solves the *linear* stationary equation

    (q/λ) z = aᵀ∇z + (λ/2) tr(B R⁻¹ Bᵀ ∇²z),        z = exp(−g_E/λ) on E.

On the grid, aᵀ∇ + (λ/2) tr(B R⁻¹ Bᵀ ∇²) becomes the generator L of a monotone Markov chain on the
nodes (:mod:`gridlbc.schemes.generator`; exponentially fitted rates by default), whose nodes next
to E jump to the points b where their arms enter E (the set's boundary fitted between the
nodes), and the equation the sparse linear system

    (diag(q/λ) − L)_II z_I = L_IE z_E + L_Ib z_b,        z_E, z_b = exp(−g_E/λ) there,

over the nodes I off E, with the nodes of E and the boundary points as known values. Its matrix is a non-singular
M-matrix exactly when every node can reach E or a node with q > 0 along the chain's jumps
(:func:`check_well_posed` refuses a problem where some cannot: their z would be undetermined).
It is solved directly (sparse LU) or by a Krylov method; no time marching. The solution is
linear in z_E: exit costs g_i on one E, solved with one operator, superpose exactly,
z = Σ_i w_i z_i (:func:`gridlbc.combine`).

**Average cost.** A task that never ends has an optimal cost per unit time c and a relative value
h(x) (v(x, T) ≈ c T + h(x) for long horizons): e = exp(−h/λ) is the principal eigenfunction of
the same operator,

    (L − diag(q/λ)) e = −(c/λ) e,

the eigenvalue of largest real part, whose eigenvector is positive (Perron–Frobenius: the
matrix's off-diagonal entries are non-negative). It is found by shift-and-invert Arnoldi
(scipy's ARPACK, one sparse LU) about σ = −min q/λ + ε, which is above the principal eigenvalue
and closer to it than to any other, where the first-exit system would be solved by LU (one and
two dimensions); otherwise by Noda's inverse iteration, whose shifts σ_k ↓ μ keep σ_k I − M a
non-singular M-matrix solved by the same Krylov methods (:func:`principal_eigenpair`). h is
normalised to min h = 0 at the nodes, and the embedded solves on the grids 2h and 4h, normalised
the same way, give the estimates of h (:meth:`StationarySolution.error_estimate`) and of c
(``average_cost_error``, :func:`gridlbc.accuracy.scalar_estimate`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import time
import warnings
from dataclasses import dataclass
from functools import partial
from typing import cast

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spla

from .accuracy import (
    UNPOSED,
    Refinement,
    assess,
    average_truncation,
    axes_to_refine,
    check_budget,
    check_scalar,
    check_tolerance,
    embedded_grid,
    finish,
    limiting_axes,
    over_budget,
    predicted_seconds,
    refined_grid,
    scalar_estimate,
    scalar_relative,
    stationary_gap,
    unestimated,
)
from .accuracy.embedding import embed
from .errors import (
    ConvergenceError,
    GridlbcWarning,
    ResolutionWarning,
    UnderflowWarning,
    warn_user,
)
from .grid import Grid
from .problem import Problem
from .schemes.generator import RATES, Generator, exit_generator, generator_matrix
from .solution import OperatorSignature, SolveDiagnostics, StationarySolution
from .storage import available_memory

LINEAR_SOLVERS = ("auto", "direct", "bicgstab", "gmres")
"""How the first-exit system is solved (its rows scaled to a unit diagonal first):

- ``"direct"``: sparse LU (SuperLU with a fill-reducing ordering), exact to rounding; its fill-in
  grows quickly beyond two dimensions;
- ``"bicgstab"``: BiCGSTAB on the scaled system (relative residual ``residual``), warm-started
  from zero: a few matrix products per iteration and no factorisation;
- ``"gmres"``: restarted GMRES preconditioned by an incomplete LU factorisation, for systems on
  which BiCGSTAB stalls;
- ``"auto"``: direct in one and two dimensions up to :data:`DIRECT_LIMIT` unknowns, and beyond
  it while the factorisation fits in half the available memory (:data:`BYTES_PER_NODE`);
  otherwise BiCGSTAB, and GMRES where BiCGSTAB does not converge
  (``benchmarks/stationary_solvers.py`` measures the choice, docs page :doc:`first_exit`).

The residual bounds the iterative solves' error in z relative to its largest value, so
v = −λ log z would be rounding where z is far below it (far from the exit set, where v exceeds
its minimum by many λ): the entries below :data:`TAIL` of the largest are solved again from the
others (:func:`accurate_tail`), without defect correction.
"""

DIRECT_LIMIT = 1_000_000
"""Unknowns of a 1-D or 2-D problem that ``"auto"`` solves by sparse LU whatever the memory
reports (beyond them, while :data:`BYTES_PER_NODE` per unknown fits in half of it)."""

BYTES_PER_NODE = 2500
"""Peak memory of a first-exit solve by sparse LU per grid node (2.2 kB measured on 401² and
801² grids, 1.9 kB on 1608×1601), for the choice of ``"auto"`` and for
:func:`solve_stationary_to_tolerance`'s check before refining."""

MAX_ITERATIONS = 5_000
"""Iterations of BiCGSTAB (restarts of GMRES: a tenth) before it counts as not converged."""

MAX_SHIFTS = 50
"""Shifts of the average cost's iterative eigen-solve (:func:`principal_eigenpair`) before it
counts as not converged."""


@dataclass(frozen=True)
class StationarySettings:
    """How a stationary problem is solved.

    Parameters
    ----------
    rates : str
        The generator's jump rates, ``"fitted"`` (default) or ``"upwind"``
        (:mod:`gridlbc.schemes.generator`).
    linear_solver : str
        One of :data:`LINEAR_SOLVERS`.
    residual : float
        The relative residual at which the Krylov solvers stop (and the eigen-solver's
        tolerance).
    error_estimate : bool
        Also solve on the embedded grid (every other node) so that the solution carries an
        a-posteriori error estimate (:meth:`gridlbc.Solution.error_estimate`,
        :mod:`gridlbc.accuracy`), and warn where it exceeds the default tolerance.
    fit_exit : bool
        Impose z = exp(−g_E/λ) where the exit set begins between two nodes, found by bisection
        on its mask (:func:`gridlbc.schemes.generator.exit_generator`); False: at the nodes
        inside it, which places the set's boundary only to within a cell (first order, and
        irregular as the grid is refined).
    defect_correction : int
        Steps of defect correction (0: none): the first-order solution z₁ corrected by the
        residual of a second-order discretisation L₂ of the same generator, solved with the
        same matrix, z_{j+1} = z_j + A₁⁻¹ (b₂ − A₂ z_j) (:func:`_defect_correction`). Still
        linear in the exit values, so exit costs solved together combine exactly; second
        order where z is resolved, and undone, with a :class:`gridlbc.ResolutionWarning`,
        where a step would make z negative somewhere (z not resolved: v varies by much more
        than λ over a cell). Needs ``fit_exit``.
    """

    rates: str = "fitted"
    linear_solver: str = "auto"
    residual: float = 1e-12
    error_estimate: bool = True
    fit_exit: bool = True
    defect_correction: int = 0

    def __post_init__(self):
        if self.rates not in RATES:
            raise ValueError(f"rates must be one of {', '.join(RATES)}, got {self.rates!r}")
        if self.linear_solver not in LINEAR_SOLVERS:
            raise ValueError(
                f"linear_solver must be one of {', '.join(LINEAR_SOLVERS)} for a stationary "
                f"problem, got {self.linear_solver!r}"
            )
        if not (0 < self.residual < 1):
            raise ValueError(f"residual must lie in (0, 1), got {self.residual}")
        steps = self.defect_correction
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0:
            raise ValueError(
                f"defect_correction must be a number of steps, 0, 1, 2, ..., got {steps!r}"
            )
        if steps and not self.fit_exit:
            raise ValueError("defect_correction needs fit_exit=True (the exit set's boundary)")


def stationary_settings(options: dict) -> StationarySettings:
    """:class:`StationarySettings` from keyword options, with a clear error for the options of a
    time march (``dt``, ``method``, ...) that do not apply."""
    known = set(StationarySettings.__dataclass_fields__)
    ignored = {"progress"}
    unknown = sorted(set(options) - known - ignored)
    if unknown:
        raise TypeError(
            f"{', '.join(unknown)} do not apply to a stationary problem (no time march): it "
            f"takes {', '.join(sorted(known))}"
        )
    return StationarySettings(**{k: v for k, v in options.items() if k in known})


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


def check_well_posed(L: sp.csr_matrix, sinks: np.ndarray, grid: Grid) -> None:
    """Refuse a problem in which some nodes can reach neither a sink (a node of E or one with
    q > 0) along the chain's jumps: their desirability is undetermined (nothing is ever paid
    and nothing ends the task; the linear system is singular there). A breadth-first search
    from a virtual node joined to every sink, along the jumps reversed."""
    n = grid.size
    off = (L - sp.diags(L.diagonal())).tocsr()
    targets = np.flatnonzero(sinks)
    source = sp.csr_matrix(
        (np.ones(len(targets)), (np.zeros(len(targets), dtype=np.int64), targets)), shape=(1, n)
    )
    graph = sp.bmat([[off.T, None], [source, sp.csr_matrix((1, 1))]], format="csr")
    reached = np.zeros(n + 1, dtype=bool)
    reached[csgraph.breadth_first_order(graph, n, directed=True, return_predecessors=False)] = True
    if not reached[:n].all():
        stuck = np.flatnonzero(~reached[:n])
        x = np.array2string(grid.node_coordinates(stuck[:1])[0], precision=3, separator=", ")
        raise ValueError(
            f"{len(stuck)} of {n} nodes (e.g. {x}) reach neither the exit set nor a state cost "
            "q > 0: the problem is ill-posed there (nothing ends the task and nothing is paid). "
            "Give a state cost q > 0, or an exit set that every state can reach"
        )


def _digest(*arrays: np.ndarray) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return "sha256:" + h.hexdigest()[:16]


def _method(s: StationarySettings, ndim: int, unknowns: int) -> str:
    """The linear solver that ``s.linear_solver`` names, ``"auto"`` resolved: sparse LU in one
    and two dimensions up to :data:`DIRECT_LIMIT` unknowns or while its factorisation fits in
    half the available memory (a 2-D factorisation of millions of unknowns takes about a minute,
    where the Krylov methods can stall on the same system: docs page :doc:`first_exit`),
    BiCGSTAB otherwise."""
    if s.linear_solver != "auto":
        return s.linear_solver
    if ndim > 2:
        return "bicgstab"
    available = available_memory()
    fits = available is not None and BYTES_PER_NODE * unknowns <= 0.5 * available
    return "direct" if unknowns <= DIRECT_LIMIT or fits else "bicgstab"


def _scaled_rows(A: sp.spmatrix) -> tuple[sp.csr_matrix, sp.dia_matrix]:
    """A with its rows divided by their diagonal, and that diagonal's inverse (for the
    right-hand sides): a node whose arm to the exit set is very short has a very large rate to
    it, and the scaled row (unit diagonal, off-diagonal sum below 1) keeps both the conditioning
    and an iterative solver's residual meaningful."""
    inverse = sp.diags(1.0 / A.diagonal())
    return (inverse @ A).tocsr(), inverse


def _solve_linear(A: sp.csr_matrix, b: np.ndarray, s: StationarySettings, ndim: int):
    """Z with A Z = b for right-hand sides ``b`` ``(n, K)``, and the iteration count (0 for the
    direct solve, which factorises once for all K), the rows scaled first (:func:`_scaled_rows`)."""
    return _linear_solver(A, s, ndim)(b)


def _linear_solver(A: sp.csr_matrix, s: StationarySettings, ndim: int):
    """A function ``b (n, K) -> (Z, iterations)`` with A Z = b: :func:`_solve_linear` with its
    factorisation (direct) or its scaled matrix (Krylov) kept for further right-hand sides."""
    A, inverse = _scaled_rows(A)
    method = _method(s, ndim, A.shape[0])
    if method == "direct":
        lu = spla.splu(A.tocsc())
        return lambda b: (lu.solve(inverse @ b), 0)

    def solve(b):
        b = inverse @ b
        Z, total = np.empty_like(b), 0
        for r in range(b.shape[1]):
            Z[:, r], iterations = _iterative(A, b[:, r], s, method)
            total += iterations
        return Z, total

    return solve


def _iterative(
    A: sp.csr_matrix,
    b: np.ndarray,
    s: StationarySettings,
    method: str,
    guess=None,
    residual: float | None = None,
):
    """(z, iterations) with A z = b by ``method`` (``"bicgstab"`` or ``"gmres"``) from ``guess``
    to the relative ``residual`` (default ``s.residual``), falling back on ILU-preconditioned
    GMRES where BiCGSTAB stalls under ``"auto"``; a clear error if neither reaches it."""
    residual = s.residual if residual is None else residual
    z, iterations = _krylov(A, b, residual, method, guess)
    if z is None and s.linear_solver == "auto":  # BiCGSTAB stalled: ILU-preconditioned GMRES
        z, more = _krylov(A, b, residual, "gmres", guess)
        iterations += more
    if z is None:
        raise ConvergenceError(
            f"the Krylov solve did not reach the relative residual {residual:g} in "
            f"{iterations} iterations: give linear_solver='direct' if its factorisation fits "
            "in memory"
        )
    return z, iterations


def _krylov(A: sp.csr_matrix, b: np.ndarray, residual: float, method: str, guess=None):
    """(z, iterations) by BiCGSTAB or ILU-preconditioned GMRES from ``guess`` (default zero); z
    None if it did not converge."""
    count = [0]

    def _count(_):
        count[0] += 1

    if method == "bicgstab":
        z, info = spla.bicgstab(
            A, b, x0=guess, rtol=residual, atol=0.0, maxiter=MAX_ITERATIONS, callback=_count
        )
    else:
        ilu = spla.spilu(A.tocsc(), drop_tol=1e-4, fill_factor=10)
        z, info = spla.gmres(
            A,
            b,
            x0=guess,
            rtol=residual,
            atol=0.0,
            M=spla.LinearOperator(A.shape, ilu.solve),
            restart=50,
            maxiter=MAX_ITERATIONS // 10,
            callback=_count,
            callback_type="pr_norm",
        )
    return (z if info == 0 else None), count[0]


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
        One per exit cost, each as :func:`solve_first_exit` gives for
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
        generator = Generator(L0, sp.csr_matrix((grid.size, 0)), np.empty((0, grid.ndim)))
    L, to_boundary = generator.matrix, generator.boundary_rates
    reaches_boundary = np.asarray(to_boundary.sum(axis=1)).ravel() > 0
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
    solver = _linear_solver(A_II, s, grid.ndim)
    Z, iterations = solver(np.stack(rhs, axis=1))
    if generator.second_order is None and _method(s, grid.ndim, len(interior)) != "direct":
        for r in range(Z.shape[1]):  # the Krylov solve resolves z relative to its largest only
            Z[:, r] = accurate_tail(A_II, rhs[r], Z[:, r], s, grid.ndim)
    digest = _digest(E, q, L.data, to_boundary.data, generator.boundary_points)
    label = f"stationary-{s.rates}"
    if generator.second_order is not None:
        Z, corrected, more = _defect_correction(
            Z, solver, generator.second_order, q / lam, E, z_exits, z_boundary, s
        )
        iterations += more
        if corrected:  # another linear map of the exit values: another operator
            L2, to_boundary2 = generator.second_order
            digest = _digest(np.frombuffer(digest.encode(), np.uint8), L2.data, to_boundary2.data)
            label += f"+dc{s.defect_correction}"
    out = []
    for r, p in enumerate(problems):
        z = np.empty(grid.size)
        z[E], z[interior] = z_exits[r], Z[:, r]
        np.clip(z, 0.0, None, out=z)  # an iterative solve's rounding may dip below zero
        counts = (iterations,) if iterations else ()
        out.append(_package(p, label, z, tops[r], start, setup, counts, digest))
    return out


def _defect_correction(Z, solver, second_order, decay, E, z_exits, z_boundary, s):
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
    large factor, the correction overshoots and z can come out negative: then every column
    keeps the first-order solution (the same map for all, so they still combine exactly) and
    a :class:`gridlbc.ResolutionWarning` says so.

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
    if np.all(corrected > 0):
        return corrected, True, total
    negative = np.count_nonzero(np.any(corrected <= 0, axis=1))
    warn_user(
        f"defect correction made z ≤ 0 at {negative} of {len(corrected)} nodes: the grid does "
        "not resolve z = exp(−v/λ) (v changes by much more than λ across a cell); the "
        "solution is the first-order one. Refine the grid, or raise the temperature",
        ResolutionWarning,
    )
    return Z, False, total


def solve_average_cost(
    problem: Problem, s: StationarySettings, distribution: bool = False
) -> StationarySolution:
    """The average-cost solution of ``problem``: c and the relative value (module docstring).

    Parameters
    ----------
    problem : Problem
        With ``horizon="average"``.
    s : StationarySettings
    distribution : bool
        Also find the stationary distribution of the solve's controlled chain
        (:func:`stationary_distribution`; the left eigenvector, see
        :func:`principal_eigenpair`).

    Returns
    -------
    StationarySolution
        With ``average_cost`` c (and ``stationary_distribution`` if asked for); its value is the
        relative value h (min 0); ``diagnostics`` ``iterations`` holds the Krylov iterations of
        each shift of the iterative eigen-solve.
    """
    start = time.perf_counter()
    grid = problem.require_grid("solve")
    problem.noise_diagonal(grid.node_coordinates([0]))
    lam = problem.temperature
    q = problem.state_cost_values()
    M = (generator_matrix(problem, s.rates) - sp.diags(q / lam)).tocsr()
    setup = time.perf_counter() - start
    mu, e, iterations, e_left = principal_eigenpair(M, s, grid.ndim, left=distribution)
    if e.min() < -1e-8 * e.max():
        warn_user(
            "the principal eigenvector has negative entries beyond rounding: the chain may not "
            "be irreducible (parts of the box it never leaves); the relative value is unreliable",
            ResolutionWarning,
        )
    shifted = (mu * sp.identity(len(e), format="csr") - M).tocsr()
    e = accurate_tail(shifted, np.zeros(len(e)), e / e.max(), s, grid.ndim)
    label = f"stationary-{s.rates}"
    solution = _package(problem, label, e, 0.0, start, setup, iterations, _digest(q, M.data))
    object.__setattr__(solution, "average_cost", -lam * mu)
    if e_left is not None:
        object.__setattr__(solution, "stationary_distribution", stationary_distribution(e, e_left))
    return solution


TAIL = 1e-6
"""Entries of an iterative first-exit solve's z, and of the principal eigenvector, below this
share of their largest are solved for again from the others (:func:`accurate_tail`): v more
than λ log(1/TAIL) ≈ 14 λ above its least value."""


def accurate_tail(
    A: sp.csr_matrix, b: np.ndarray, x: np.ndarray, s: StationarySettings, ndim: int
) -> np.ndarray:
    """A non-negative solution ``x`` of A x = b with its small entries solved for again: the
    desirability of a first-exit solve (A = (diag(q/λ) − L)_II, b ≥ 0) or the principal
    eigenvector of an average-cost one (A = μI − M, b = 0).

    An iterative solve's residual, and an eigen-solve's, are norms, so x is accurate relative
    to its largest entry only: an entry far below it is rounding, and v = −λ log x there would
    stop near λ log(1/ε) ≈ 36 λ (λ log(1/residual) for a Krylov solve, or +inf where the
    rounding dips below zero) above its least value whatever the truth, on every grid alike (the
    estimate cannot see it). Over the nodes T where x < :data:`TAIL` of its largest (H the
    others, held), the rows T of A x = b give

        A_TT x_T = b_T − A_TH x_H,

    a non-singular M-matrix (for the eigenvector: the principal eigenvalue of M's restriction
    to T is below μ, M being irreducible) with a non-negative right-hand side (A's off-diagonal
    entries are not positive), solved as the first-exit system is (:func:`_solve_linear`): by
    sparse LU each entry keeps its own relative accuracy, as z does in a direct first-exit
    solve; an iterative solve resolves entries down to its residual relative to the largest of
    T, so it is repeated on the entries below :data:`TAIL` of that, and so on, down to the
    smallest normal number. Each pass solves in units of its threshold (x_T about 1 at most),
    which keeps the Krylov iterates out of the subnormal range (BiCGSTAB falling back on
    ILU-GMRES as under ``"auto"``; where neither converges the solve warns, and those entries
    stay rounding)."""
    x = np.clip(x, 0.0, None)
    threshold = TAIL * float(x.max())
    # BiCGSTAB with ILU-GMRES to fall back on (or LU where "auto" picks it)
    robust = s if s.linear_solver != "bicgstab" else dataclasses.replace(s, linear_solver="auto")
    while threshold > np.finfo(float).tiny:
        tail = x < threshold
        if not tail.any() or tail.all():
            break
        rows = A[tail]
        rhs = (b[tail] - rows[:, ~tail] @ x[~tail]) / threshold
        try:
            solved, _ = _solve_linear(rows[:, tail].tocsr(), rhs[:, None], robust, ndim)
        except ConvergenceError as error:
            warn_user(
                f"the values more than {-np.log(threshold / x.max()):.0f} λ above their least "
                f"could not be solved again from the larger entries of z ({error}): there "
                "they are rounding, whatever the truth; give linear_solver='direct' if its "
                "factorisation fits in memory",
                ResolutionWarning,
            )
            break
        x[tail] = np.clip(solved[:, 0], 0.0, None) * threshold
        if _method(robust, ndim, int(tail.sum())) == "direct":
            break
        threshold *= TAIL
    return x


def stationary_distribution(e: np.ndarray, e_left: np.ndarray) -> np.ndarray:
    """π_i = e_i ẽ_i / Σ_j e_j ẽ_j: the long-run share of time that the solve's controlled chain
    spends at node i.

    The optimal controlled chain jumps from i to j at the rate M_ij e_j / e_i (M = L − diag(q/λ),
    e its principal right eigenvector, Todorov 2009), so its generator is
    G = diag(e)⁻¹ (M − μI) diag(e), and πG = 0 exactly when π diag(e)⁻¹ is a left eigenvector
    of M for μ: π ∝ ẽ ⊙ e. Entries below zero by rounding are set to zero."""
    pi = np.clip(e * e_left, 0.0, None)
    return pi / pi.sum()


def eigen_residual(M: sp.spmatrix, mu: float, e: np.ndarray) -> float:
    """‖(M − μ I) e‖₂ / (‖M‖_∞ ‖e‖₂): the eigen-solve's convergence measure."""
    norm = float(abs(M).sum(axis=1).max())
    return float(np.linalg.norm(M @ e - mu * e) / (norm * np.linalg.norm(e)))


def principal_eigenpair(M: sp.csr_matrix, s: StationarySettings, ndim: int, left: bool = False):
    """The eigenvalue μ of largest real part of M = L − diag(q/λ) and its eigenvector e > 0 (max
    entry 1), and the Krylov iterations per shift (empty for the direct solve).

    M's off-diagonal entries are non-negative, so (Perron–Frobenius, for an irreducible chain) μ
    is real and simple, e is positive, and for every σ > μ the matrix σI − M is a non-singular
    M-matrix with a positive inverse. For any positive vector x the Collatz–Wielandt quotients
    bracket μ,

        min_i (Mx)_i / x_i  ≤  μ  ≤  max_i (Mx)_i / x_i,

    the upper one with x = 1 being the largest row sum, −min q/λ. Two methods, after
    ``s.linear_solver`` (:func:`_method`):

    - direct: shift-and-invert Arnoldi (ARPACK, started from 1) about σ = −min q/λ + ε, one
      sparse LU of M − σI;
    - iterative (Noda's inverse iteration): from e₀ = 1, σ₀ = −min q/λ + ε,

          (σ_k I − M) y = e_k,      e_{k+1} = y / max y,
          σ_{k+1} = max( max_i (M e_{k+1})_i / e_{k+1,i},  ρ_{k+1} + δ ),

      the Collatz–Wielandt quotient read where e_{k+1,i} ≥ √``residual`` (below that an
      iterative solve does not resolve e's entries), never above σ_k, and ρ = eᵀMe / eᵀe
      the Rayleigh quotient (δ = ``residual`` ‖M‖_∞). σ_k stays above μ, so each shifted system
      is an M-matrix, solved as the first-exit system is (rows scaled, BiCGSTAB, ILU-GMRES where
      it stalls), from the guess y₀ = e_k / (σ_k − ρ_k), to the backward error
      η_k = max(``residual``, min(10⁻², r_k / 10)), r_k the eigen-residual of e_k below: it stops
      at ‖A y − b‖ ≤ η_k ‖A‖_∞ ‖y₀‖ (at most 0.1 ‖b‖, and at most a tenth of the guess's own
      residual: near the eigenvector the guess nearly solves the system, and a solve that
      accepted it would leave e and σ where they were). e_{k+1} is then an exact step of a
      matrix within η_k of the scaled σ_k I − M, so the eigen-residual falls to about η_k per
      shift, while the nearly singular last systems (‖y‖ ≈ ‖e‖ / (σ_k − μ), far above ‖b‖) are
      not solved to a residual relative to ‖b‖ that they need not and often cannot reach.
      σ_k − μ shrinks superlinearly. Should a
      solve come out negative (eᵀy < 0: σ fell below μ), the shift returns to the last one
      above μ and stays there (plain inverse iteration, linear convergence).

    Both stop when the eigen-residual ‖(M − ρI)e‖₂ ≤ ``residual`` · ‖M‖_∞ ‖e‖₂
    (:func:`eigen_residual`); the iterative one after :data:`MAX_SHIFTS` shifts at most.

    With ``left``, also the left eigenvector ẽ > 0 (Mᵀẽ = μẽ, max entry 1), for the chain's
    stationary distribution (:func:`stationary_distribution`): by the same shift-and-invert
    Arnoldi on Mᵀ with the transposed solves of the same LU factors, or by the same inverse
    iteration on Mᵀ (which doubles the iterative eigen-solve's work).

    Returns
    -------
    mu : float
    e : ndarray (N,)
    iterations : tuple of int
        Krylov iterations per shift (both iterations' with ``left``; empty for the direct solve).
    e_left : ndarray (N,) or None
        ẽ with ``left``, None otherwise.
    """
    n = M.shape[0]
    upper = float((M @ np.ones(n)).max())
    sigma = upper + 1e-3 * max(float(np.abs(M.diagonal()).max()), 1e-300)
    method = _method(s, ndim, n)
    if method == "direct":
        factors = spla.splu((M - sigma * sp.identity(n, format="csc")).tocsc())
        mu, e = _arnoldi(M, sigma, factors.solve, s.residual)
        if not left:
            return mu, e, (), None
        _, e_left = _arnoldi(M.T, sigma, partial(factors.solve, trans="T"), s.residual)
        return mu, e, (), e_left
    mu, e, counts = _noda(M, sigma, s, method)
    if not left:
        return mu, e, counts, None
    _, e_left, more = _noda(M.T.tocsr(), sigma, s, method)
    return mu, e, counts + more, e_left


def _arnoldi(M: sp.spmatrix, sigma: float, inverse, residual: float) -> tuple[float, np.ndarray]:
    """The eigenpair of M nearest ``sigma`` by ARPACK's shift-and-invert Arnoldi, ``inverse``
    applying (M − σI)⁻¹, started from 1 (ARPACK's default start is random: the same solve, the
    same digits); the eigenvector scaled to max entry 1."""
    n = M.shape[0]
    values, vectors = spla.eigs(
        M,
        k=1,
        sigma=sigma,
        which="LM",
        tol=residual,
        v0=np.ones(n),
        OPinv=spla.LinearOperator((n, n), matvec=inverse, dtype=float),
    )
    e = vectors[:, 0].real
    return float(values[0].real), e / e[np.argmax(np.abs(e))]


def _noda(M: sp.csr_matrix, sigma: float, s: StationarySettings, method: str):
    """Noda's inverse iteration for the principal eigenpair of M from the shift ``sigma`` above
    it (:func:`principal_eigenpair`): μ, e (max entry 1) and the Krylov iterations per shift."""
    n = M.shape[0]
    norm = float(abs(M).sum(axis=1).max())
    e, counts = np.ones(n), []
    rho = float(e @ (M @ e)) / n
    above, fixed = sigma, False
    identity = sp.identity(n, format="csr")
    error = eigen_residual(M, rho, e)
    for _ in range(MAX_SHIFTS):
        A, inverse = _scaled_rows(sigma * identity - M)
        b = inverse @ e
        guess = e / (sigma - rho) if sigma > rho else None
        # the backward error max(residual, min(10⁻², r_k/10)) as a residual relative to b:
        # ‖A y − b‖ ≤ η ‖A‖ ‖y‖ with ‖y‖ ≈ ‖e‖ / (σ − ρ)
        backward = max(s.residual, min(1e-2, 0.1 * error))
        target = 0.1
        if guess is not None:
            scale = float(np.linalg.norm(b))
            growth = float(abs(A).sum(axis=1).max() * np.linalg.norm(guess) / scale)
            # near the eigenvector the guess itself nearly solves the system: ask for a tenth of
            # its residual at most, or the shift does no work and σ never moves
            start = float(np.linalg.norm(A @ guess - b)) / scale
            target = min(0.1, backward * max(growth, 1.0), 0.1 * start)
        y, iterations = _iterative(A, b, s, method, guess, max(target, 1e-15))
        counts.append(iterations)
        if e @ y < 0:  # σ fell below μ: back to the last shift above it, and keep it
            sigma, fixed = above, True
        else:
            above = sigma
        e = y / y[np.argmax(np.abs(y))]
        Me = M @ e
        rho = float(e @ Me / (e @ e))
        error = float(np.linalg.norm(Me - rho * e) / (norm * np.linalg.norm(e)))
        if error <= s.residual:
            return rho, e, tuple(counts)
        if not fixed:
            resolved = e >= np.sqrt(s.residual)
            quotient = float(np.max(Me[resolved] / e[resolved]))
            sigma = min(sigma, max(quotient, rho + s.residual * norm))
    raise ConvergenceError(
        f"the average cost's eigen-solve did not reach the residual {s.residual:g} in "
        f"{MAX_SHIFTS} shifts ({sum(counts)} Krylov iterations): give linear_solver='direct' "
        "if its factorisation fits in memory, or a larger residual="
    )


def _package(problem, label, z, top, start, setup, iterations, digest) -> StationarySolution:
    """A :class:`StationarySolution` of nodal ``z`` · e^top; ``iterations`` a tuple of counts,
    ``label`` the operator's name in its :class:`~gridlbc.solution.OperatorSignature`."""
    peak = float(z.max())
    Z = z / peak if peak > 0 else z
    diagnostics = SolveDiagnostics(
        method="stationary",
        dt=0.0,
        steps=0,
        store_every=1,
        wall_time=time.perf_counter() - start,
        setup_time=setup,
        underflow_nodes=int(np.count_nonzero(Z == 0)),
        stored_bytes=int(Z.nbytes),
        operator_bytes=0,
        courant=0.0,
        iterations=tuple(iterations),
    )
    if diagnostics.underflow_nodes:
        warn_user(
            f"the desirability underflowed at {diagnostics.underflow_nodes} of {Z.size} nodes "
            "(v more than about 745 λ above its least value, beyond what a double holds of "
            "z = e^(−v/λ)): v reads +inf there and the policy is undefined. Raise the "
            "temperature relative to the costs, or shrink the box to the states you need (docs "
            "page 'limitations')",
            UnderflowWarning,
        )
    operator = OperatorSignature(label, 0.0, digest)
    return StationarySolution(
        problem,
        np.zeros(1),
        Z[None, :],
        np.array([top + np.log(peak)]) if peak > 0 else np.array([top]),
        diagnostics,
        operator,
    )


def stationary_work_exponent(method: str, ndim: int) -> float:
    """The power of the nodes ratio by which :func:`solve_stationary_to_tolerance` scales a
    round's time to predict the next one's (:func:`gridlbc.accuracy.predicted_seconds`), for the
    linear solver ``method`` (resolved, :func:`_method`) of the planned grid.

    Sparse LU with a fill-reducing ordering costs N^1.5 in two dimensions (nested dissection)
    and N^2 in three; measured (the first-exit solve of a ball's exit, one thread): 2-D from 161²
    to 321² and 641², exponents 1.26 and 1.37 (1.09 and 1.31 with the embedded solves), 3-D
    21³ → 33³, 2.03. BiCGSTAB's iterations grow as 1/h, N^(1/d): the work as N^(1 + 1/d), and
    more where the vectors leave the caches; measured in 3-D, 41³ → 81³ (83 → 166 iterations),
    1.65. Hence 1.5 for LU in one or two dimensions (N in 1-D, banded: conservative), 2 beyond,
    and 1.7 for the Krylov methods: at or above what was measured, so that a budget is not
    overrun by an underestimate. On small grids, where fixed costs dominate, the prediction is
    high (the two bays of ``tests/core/test_first_exit.py`` from 41²: the 161×81 round predicted
    at 0.53 s took 0.15 s): a budget stops early there, where rounds take a fraction of a
    second."""
    if method == "direct":
        return 1.5 if ndim <= 2 else 2.0
    return 1.7


def solve_stationary_to_tolerance(
    problem: Problem,
    tol: float,
    states=None,
    max_nodes: int | None = None,
    max_refinements: int = 6,
    max_seconds: float | None = None,
    **options,
) -> StationarySolution:
    """Solve a first-exit or an average-cost problem on finer and finer grids (h → h/2 along the
    axes that limit it) until its embedded error estimate meets ``tol``, or ``max_nodes``, the
    memory, ``max_refinements`` or the time budget ``max_seconds`` stops it (then a
    :class:`gridlbc.ResolutionWarning` says which). :func:`gridlbc.solve` calls this for
    ``solve(problem, tol=...)``.

    A round's error is the relative estimate of v at ``states`` (:func:`gridlbc.accuracy.assess`);
    for the average cost, the larger of that of the relative value h and c's own,
    ê_c / c (``average_cost_error``, :func:`gridlbc.accuracy.scalar_estimate`): c is what an
    average-cost solve is asked for first, and h's estimate does not bound it. The axes refined
    are those whose share of the larger error is at least half the largest share: h's shares by
    :func:`gridlbc.accuracy.axes_to_refine`, c's by :func:`_shares_of_c`, from the same solves
    with one axis coarsened.

    Before each refinement its round's time (the solve, its embedded solves and the solves with
    one axis coarsened that steer the next) is predicted from the last round's: its wall time
    times the ratio of the nodes to the power :func:`stationary_work_exponent` (measured for
    the linear solvers); a round that would take the total past ``max_seconds`` is not started
    (:attr:`gridlbc.accuracy.Refinement.predicted_seconds`), nor steered where the time left
    would not hold even a round on the same grid.

    Parameters
    ----------
    problem : Problem
        A problem without a horizon (first exit) or with ``horizon="average"``; its grid is the
        first one tried.
    tol : float
        The relative tolerance on v (on h and c for the average cost), in (0, 1).
    states : array_like (N, d), optional
        Where v (h) must meet it (default: the states that matter).
    max_nodes : int, optional
        Refine no further than this many nodes.
    max_refinements : int
        At most this many refinements.
    max_seconds : float, optional
        A wall-clock budget in seconds (default None: none), as for
        :func:`gridlbc.accuracy.solve_to_tolerance`.
    **options
        :class:`StationarySettings` fields.

    Returns
    -------
    StationarySolution
        The last solve, with :attr:`~gridlbc.Solution.refinement` (one
        :class:`~gridlbc.accuracy.Refinement` per grid, ``dt`` 0).
    """
    check_tolerance(tol, options)
    check_budget(max_seconds)
    clock = time.perf_counter()
    s = stationary_settings(options)
    history: list[Refinement] = []
    limit = ""
    while True:
        started = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ResolutionWarning)
            solution = _solved(problem, s)
        a = assess(solution, tol, states)
        if a is None and embedded_grid(solution.grid) is None:
            raise unestimated(solution.grid)
        error = UNPOSED if a is None else a.error  # None: refine until the coarser grid poses it
        c_error = _relative_error_of_c(solution)
        solved = time.perf_counter() - started
        history.append(Refinement(solution.grid.shape, 0.0, max(error, c_error), np.nan, solved))
        if history[-1].error <= tol or len(history) > max_refinements:
            break
        here = f"grid {'×'.join(map(str, solution.grid.shape))} or finer"
        limit = over_budget(max_seconds, time.perf_counter() - clock, here, solved, least=True)
        if limit:  # not even a round on this grid fits in the time left: no need to steer
            history[-1] = dataclasses.replace(history[-1], predicted_seconds=solved)
            break
        if a is None:  # the grid with every other node cannot pose the problem: every axis
            axes, shares = list(range(solution.grid.ndim)), np.full(solution.grid.ndim, np.nan)
        else:
            coarsened: dict[tuple[int, ...], StationarySolution | None] = {}
            axes, shares = axes_to_refine(
                solution, partial(_solve_quietly, problem, s, kept=coarsened), states
            )
            if c_error > error:
                axes, shares = _shares_of_c(solution, coarsened)
        finer = refined_grid(solution.grid, axes)
        seconds = time.perf_counter() - started
        method = _method(s, finer.ndim, finer.size)
        exponent = stationary_work_exponent(method, finer.ndim)
        predicted = predicted_seconds(seconds, solution.grid.size, finer.size, exponent)
        history[-1] = dataclasses.replace(
            history[-1],
            axis_errors=tuple(shares.tolist()),
            wall_time=seconds,
            predicted_seconds=predicted,
        )
        available = available_memory()
        if max_nodes is not None and finer.size > max_nodes:
            limit = f"the grid {finer.shape} would exceed max_nodes = {max_nodes}"
        elif available is not None and BYTES_PER_NODE * finer.size > 0.9 * available:
            limit = f"memory: the grid {finer.shape} would need about " + (
                f"{BYTES_PER_NODE * finer.size / 2**30:.1f} GiB of {available / 2**30:.1f} GiB"
            )
        if not limit:
            plan = f"grid {'×'.join(map(str, finer.shape))}"
            limit = over_budget(max_seconds, time.perf_counter() - clock, plan, predicted)
        if limit:
            break
        problem = problem.replace(grid=finer)
    where = "×".join(map(str, solution.grid.shape))
    advice = "raise max_refinements or max_nodes"
    if limit.startswith("the time budget"):
        advice = "raise max_seconds or loosen tol"
    finish(solution, tol, history, where, limit, max_refinements, advice)
    return solution


def _relative_error_of_c(solution: StationarySolution) -> float:
    """ê_c / c of an average-cost solve (0 for first exit; 0 where both are 0)."""
    if solution.average_cost_error is None:
        return 0.0
    return scalar_relative(solution.average_cost_error, _average_cost(solution))


def _shares_of_c(solution: StationarySolution, coarsened: dict) -> tuple[list[int], np.ndarray]:
    """Each axis's share of c's error, abs(c_i − c) / c with c_i from the solve with that axis
    alone coarsened (``coarsened``, by grid shape; NaN where there is none), and the axes whose
    share is at least half the largest (every axis where none is known)."""
    c = _average_cost(solution)
    shares = np.full(solution.grid.ndim, np.nan)
    for i in range(solution.grid.ndim):
        grid = embedded_grid(solution.grid, axes=(i,))
        other = None if grid is None else coarsened.get(grid.shape)
        if other is not None and c != 0:
            shares[i] = abs(_average_cost(other) - c) / abs(c)
    return limiting_axes(shares), shares


def _solve_quietly(problem: Problem, s: StationarySettings, grid: Grid, kept=None):
    """The stationary solve of ``problem`` on ``grid`` without its estimate and warnings, or None
    where the exit set or the costs are not resolved on that grid or its solve did not converge;
    also kept in ``kept`` (a dict, by the grid's shape) where given."""
    solve = solve_average_cost if problem.average_cost else solve_first_exit
    try:
        solution = _quietly(solve, problem.replace(grid=grid), s)
    except (ValueError, ConvergenceError):
        solution = None
    if kept is not None:
        kept[grid.shape] = solution
    return solution


def solve_stationary_many(problem: Problem, exit_costs, **options) -> list:
    """:func:`gridlbc.solve_many` for a first-exit problem: one operator, several exit costs
    (:func:`solve_first_exit_many`), each solution with its embedded estimate.

    Parameters
    ----------
    problem : Problem
        With ``horizon=None`` and an exit set.
    exit_costs : sequence of callable
        The exit costs g_i.
    **options
        :class:`StationarySettings` fields.

    Returns
    -------
    list of StationarySolution
    """
    s = stationary_settings(options)
    exit_costs = list(exit_costs)
    solutions = solve_first_exit_many(problem, exit_costs, s)
    if s.error_estimate:
        _embed_many(problem, exit_costs, s, solutions)
    return solutions


def solve_stationary(problem: Problem, **options) -> StationarySolution:
    """Solve a stationary problem: first exit (``horizon=None``) or average cost
    (``horizon="average"``); :func:`gridlbc.solve` calls this for them.

    Parameters
    ----------
    problem : Problem
    **options
        :class:`StationarySettings` fields.

    Returns
    -------
    StationarySolution
    """
    return _solved(problem, stationary_settings(options))


def _solved(problem: Problem, s: StationarySettings) -> StationarySolution:
    """:func:`solve_stationary` with its settings: the solve, and its estimate unless
    ``s.error_estimate`` is False."""
    if not problem.average_cost:
        solution = solve_first_exit(problem, s)
        if s.error_estimate:
            _embed(problem, s, solution)
        return solution
    solution = solve_average_cost(problem, s, distribution=s.error_estimate)
    if s.error_estimate:
        _embed_average(problem, s, solution)
    return solution


def _embed(problem: Problem, s: StationarySettings, solution: StationarySolution) -> None:
    """Attach the embedded estimate to one solution (:func:`_embed_many`)."""
    _embed_many(problem, [problem.exit_cost], s, [solution])


def _embed_many(problem: Problem, exit_costs, s: StationarySettings, solutions) -> None:
    """Attach to each solution its embedded estimate (:func:`gridlbc.accuracy.embedding.embed`):
    the same problem and exit cost on the grids with every other node (2h and 4h), the embedded
    solve's response to the exit costs' sub-cell excess and, where a feature narrower than a
    cell asks for it, the pair; and warn where an estimate exceeds the default tolerance, where
    none could be made, or where the exit set has a part that no node holds."""

    def solve(on: Problem, costs=exit_costs) -> list:
        return _quietly(solve_first_exit_many, on, costs, s)

    embed(problem, exit_costs, solutions, _on_grids(problem, solve), solve, base=True)


def _embed_average(problem: Problem, s: StationarySettings, solution: StationarySolution) -> None:
    """Attach to an average-cost solution the embedded estimates of its relative value h
    (:func:`gridlbc.accuracy.embedding.embed`: h normalised to min 0 at the nodes on every
    level, as on this one, and S, the response of the embedded solve to the state cost's excess
    between the nodes) and of its average cost c (``average_cost_error``,
    :func:`gridlbc.accuracy.scalar_estimate` from c on the grids h, 2h and 4h, γ_c and S_c);
    warn where either exceeds the default tolerance."""

    def solve(on: Problem, costs=()) -> list:
        return [_quietly(solve_average_cost, on, s)]

    levels, pairs, excess = embed(problem, [], [solution], _on_grids(problem, solve), solve, True)
    if not levels:
        return
    (moved,) = cast(list, excess)
    response = 0.0  # S_c: what the excess moves c by on the embedded grid
    if moved.raised is not None and moved.base is not None:
        response = abs(_average_cost(moved.raised) - _average_cost(moved.base))
    estimate = scalar_estimate(
        [solution.average_cost] + [level[0].average_cost for level in levels],
        None if pairs is None else [side[0].average_cost for side in pairs],
        stationary_gap(solution),
        response,
        average_truncation(solution),
    )
    object.__setattr__(solution, "average_cost_error", estimate.error)
    check_scalar(estimate, "the average cost c")


def _average_cost(solution) -> float:
    """c of an average-cost solve (:func:`solve_average_cost` sets it)."""
    c = cast(StationarySolution, solution).average_cost
    assert c is not None
    return c


def _on_grids(problem: Problem, solve):
    """``solve`` of ``problem`` moved to a grid (the step factor of a time march is not used)."""

    def solve_on(grid: Grid, factor: int):
        return solve(problem.replace(grid=grid))

    return solve_on


def _quietly(solve, *args):
    """``solve(*args)`` with its gridlbc warnings silenced: the warnings of a solve that checks
    another (an embedded or comparison solve) are not the user's."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridlbcWarning)
        return solve(*args)
