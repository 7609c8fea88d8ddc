"""What the stationary solves share (docs page :doc:`first_exit`): their settings, the sparse
linear solvers (LU, BiCGSTAB, GMRES) with rows scaled to a unit diagonal, the re-solve of a
solution's small entries (:func:`~gridlbc.stationary.accurate_tail`), and the packaging of a solved
z as a
:class:`~gridlbc.solution.StationarySolution`."""

from __future__ import annotations

import dataclasses
import hashlib
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import (
    ConvergenceError,
    ResolutionWarning,
    UnderflowWarning,
    state_text,
    warn_user,
)
from ..schemes.generator import RATES
from ..solution import OperatorSignature, SolveDiagnostics, StationarySolution
from ..storage import available_memory

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
its minimum by many λ): the entries below :data:`~gridlbc.stationary.linear.TAIL` of the largest are
solved again from the others (:func:`~gridlbc.stationary.accurate_tail`), without defect correction.
"""


DIRECT_LIMIT = 1_000_000
"""Unknowns of a 1-D or 2-D problem that ``"auto"`` solves by sparse LU whatever the memory
reports (beyond them, while :data:`BYTES_PER_NODE` per unknown fits in half of it)."""


BYTES_PER_NODE = 2500
"""Peak memory of a first-exit solve by sparse LU per grid node, set at or above what was
measured (docs page :doc:`first_exit`, "Linear solvers"), for the choice of ``"auto"`` and for
:func:`~gridlbc.stationary.solve_stationary_to_tolerance`'s check before refining."""


MAX_ITERATIONS = 5_000
"""Iterations of BiCGSTAB (restarts of GMRES: a tenth) before it counts as not converged."""


MAX_SHIFTS = 100
"""Shifts of the average cost's eigen-solve
(:func:`~gridlbc.stationary.principal_eigenpair`) before it counts as not converged
(a margin above what stranger round 27's cold average cost of a linear system with one
control takes: docs page :doc:`first_exit`, "Linear solvers")."""


@dataclass(frozen=True)
class StationarySettings:
    """How a stationary problem is solved.

    Parameters
    ----------
    rates : str
        The generator's jump rates, ``"fitted"`` (default) or ``"upwind"``
        (:mod:`gridlbc.schemes.generator`).
    linear_solver : str
        One of :data:`~gridlbc.stationary.linear.LINEAR_SOLVERS`.
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
        same matrix, z_{j+1} = z_j + A₁⁻¹ (b₂ − A₂ z_j)
        (:func:`~gridlbc.stationary.first_exit._defect_correction`). Still linear in the exit
        values, so exit costs solved together combine exactly; second order where z is resolved, and
        undone, with a :class:`gridlbc.ResolutionWarning`, where a step would make z negative
        somewhere (z not resolved: v varies by much more than λ over a cell). Needs ``fit_exit``.
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
        verb = "does" if len(unknown) == 1 else "do"
        raise TypeError(
            f"{', '.join(unknown)} {verb} not apply to a stationary problem (no time march): it "
            f"takes {', '.join(sorted(known))} (and tol=, states=, max_nodes=, max_seconds= "
            "for a solve to a tolerance)"
        )
    return StationarySettings(**{k: v for k, v in options.items() if k in known})


def operator_digest(*arrays: np.ndarray) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return "sha256:" + h.hexdigest()[:16]


def linear_method(s: StationarySettings, ndim: int, unknowns: int) -> str:
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


def scaled_rows(A: sp.spmatrix) -> tuple[sp.csr_matrix, sp.dia_matrix]:
    """A with its rows divided by their diagonal, and that diagonal's inverse (for the
    right-hand sides): a node whose arm to the exit set is very short has a very large rate to
    it, and the scaled row (unit diagonal, off-diagonal sum below 1) keeps both the conditioning
    and an iterative solver's residual meaningful."""
    inverse = sp.diags(1.0 / A.diagonal())
    return (inverse @ A).tocsr(), inverse


def solve_linear(A: sp.csr_matrix, b: np.ndarray, s: StationarySettings, ndim: int):
    """Z with A Z = b for right-hand sides ``b`` ``(n, K)``, and the iteration count (0 for the
    direct solve, which factorises once for all K), the rows scaled first (:func:`scaled_rows`)."""
    return linear_solver(A, s, ndim)(b)


def linear_solver(A: sp.csr_matrix, s: StationarySettings, ndim: int):
    """A function ``b (n, K) -> (Z, iterations)`` with A Z =
    b: :func:`~gridlbc.stationary.linear.solve_linear` with its factorisation (direct) or its scaled
    matrix (Krylov) kept for further right-hand sides."""
    A, inverse = scaled_rows(A)
    method = linear_method(s, ndim, A.shape[0])
    if method == "direct":
        lu = spla.splu(A.tocsc())
        return lambda b: (lu.solve(inverse @ b), 0)

    def solve(b):
        b = inverse @ b
        Z, total = np.empty_like(b), 0
        for r in range(b.shape[1]):
            Z[:, r], iterations = iterative(A, b[:, r], s, method)
            total += iterations
        return Z, total

    return solve


def iterative(
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


TAIL = 1e-6
"""Entries of an iterative first-exit solve's z, and of the principal eigenvector, below this
share of their largest are solved for again from the others
(:func:`~gridlbc.stationary.accurate_tail`): v more than λ log(1/TAIL) ≈ 14 λ above its least
value."""


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
    estimate cannot see it). Over the nodes T where x < :data:`~gridlbc.stationary.linear.TAIL` of
    its largest (H the others, held), the rows T of A x = b give

        A_TT x_T = b_T − A_TH x_H,

    a non-singular M-matrix (for the eigenvector: the principal eigenvalue of M's restriction
    to T is below μ, M being irreducible) with a non-negative right-hand side (A's off-diagonal
    entries are not positive), solved as the first-exit system is
    (:func:`~gridlbc.stationary.linear.solve_linear`): by sparse LU each entry keeps its own
    relative accuracy, as z does in a direct first-exit solve; an iterative solve resolves entries
    down to its residual relative to the largest of T, so it is repeated on the entries
    below :data:`~gridlbc.stationary.linear.TAIL` of that, and so on, down to the smallest normal
    number. Each pass solves in units of its threshold (x_T about 1 at most), which keeps the Krylov
    iterates out of the subnormal range (BiCGSTAB falling back on ILU-GMRES as under ``"auto"``;
    where neither converges the solve warns, and those entries stay rounding)."""
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
            solved, _ = solve_linear(rows[:, tail].tocsr(), rhs[:, None], robust, ndim)
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
        if linear_method(robust, ndim, int(tail.sum())) == "direct":
            break
        threshold *= TAIL
    return x


def packaged(
    problem, label, z, top, start, setup, iterations, digest, never=None
) -> StationarySolution:
    """A :class:`StationarySolution` of nodal ``z`` · e^top; ``iterations`` a tuple of counts,
    ``label`` the operator's name in its :class:`~gridlbc.solution.OperatorSignature`; ``never``
    (boolean ``(N,)``, optional) the nodes from which a first exit's chain never reaches the exit
    set, where z is 0 whatever the temperature (:class:`~gridlbc.UnderflowWarning` says so apart
    from an underflow)."""
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
    never = np.zeros(Z.size, dtype=bool) if never is None else never
    if never.any():
        x = state_text(problem.grid.node_coordinates(np.flatnonzero(never)[:1])[0])
        warn_user(
            f"the exit set cannot be reached from {int(never.sum())} of {Z.size} nodes (e.g. {x}): "
            "neither the drift nor the noise leads from them to it, so the task never ends "
            "there, v is +inf and the policy undefined. This is the problem, not an underflow: "
            "a higher temperature or a smaller box does not change it. Let the exit set reach "
            "those states, or give the dynamics a way to it (noise or a drift along the axes "
            "that lead there)",
            UnderflowWarning,
        )
    underflowed = int(np.count_nonzero((Z == 0) & ~never))
    if underflowed:
        warn_user(
            f"the desirability underflowed at {underflowed} of {Z.size} nodes "
            "(where the solved v is more than about 745 λ above its least value, beyond what a "
            "double holds of z = e^(−v/λ), or where the solve errs by that much): v reads +inf "
            "there and the policy is undefined. Raise the "
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
    """The power of the nodes ratio by which
    :func:`~gridlbc.stationary.solve_stationary_to_tolerance` scales a round's time to predict
    the next one's (:func:`gridlbc.accuracy.predicted_seconds`), for the linear solver ``method``
    (resolved, :func:`~gridlbc.stationary.linear.linear_method`) of the planned grid.

    Sparse LU with a fill-reducing ordering costs N^1.5 in two dimensions (nested dissection)
    and N^2 in three. BiCGSTAB's iterations grow as 1/h, N^(1/d): the work as N^(1 + 1/d), and
    more where the vectors leave the caches. Hence 1.5 for LU in one or two dimensions (N in
    1-D, banded: conservative), 2 beyond, and 1.7 for the Krylov methods: at or above the
    exponents measured on the first-exit solve of a ball's exit (docs page :doc:`first_exit`,
    "Linear solvers"), so that a budget is not overrun by an underestimate. On small grids,
    where fixed costs dominate, the prediction is high (the two bays of
    ``tests/core/test_first_exit.py``, same page): a budget stops early there, where rounds
    take a fraction of a second."""
    if method == "direct":
        return 1.5 if ndim <= 2 else 2.0
    return 1.7
