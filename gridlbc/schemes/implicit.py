"""Implicit upwind scheme for the linear Bellman PDE : the reference discretisation.

The generator L of a continuous-time Markov chain on the nodes approximates aᵀ∇ + tr(D ∇²),
D = ½ λ B R⁻¹ Bᵀ (diagonal), with upwind jump rates (:mod:`gridlbc.schemes.generator`): from
node i along axis k it jumps

    to i + e_k at rate max(a_k, 0)/h_k + D_kk/h_k²,    to i − e_k at rate max(−a_k, 0)/h_k + D_kk/h_k²,

with periodic wrap, and jumps that would leave a closed axis suppressed (a reflecting state
constraint: no probability leaves the box). The nodes of an exit set (SPEC §9), if the problem
has one, do not jump: z keeps its exit value exp(−g_E/λ) there; a node next to the set jumps to
where the segment to its neighbour enters it, with the rates of unequal arms
(:func:`~gridlbc.schemes.generator.folded_exit_generator`), as the stationary solve does. Backward
Euler reads

    (I + Δt diag(q/λ) − Δt L) z(t) = z(t + Δt),

an M-matrix: z ≥ 0 and the discrete maximum principle hold for any Δt. The price is first-order
numerical diffusion |a_k| h_k / 2 along each axis, which swamps the physical noise where the drift
is fast. The matrix is assembled once from COO arrays; each step's system is solved as chosen by
:data:`LINEAR_SOLVERS` (sparse LU for small 2D grids, Gauss–Seidel sweeps otherwise).

As a :class:`~gridlbc.schemes.protocol.Scheme` (:data:`IMPLICIT`): a default step of Courant
number 1 against the drift's largest rate, the plain loop of :mod:`gridlbc.schemes.march`, and
the check of the diffusion's tails (:func:`gridlbc.schemes.tails.check_resolution`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..backends.numba.implicit import gauss_seidel_kernel
from ..errors import ConvergenceError
from ..problem import Problem
from .generator import folded_exit_generator, generator_matrix
from .march import march_linear
from .protocol import Marched, MarchPlan, SchemeBase, StepRule, Terminal
from .tails import check_resolution

DIRECT_LIMIT = 400_000
"""Grids with more nodes than this (or more than two dimensions) use the iterative solver."""


LINEAR_SOLVERS = ("auto", "direct", "gauss-seidel", "bicgstab")
"""How the implicit step's linear system A z(t) = z(t + Δt) is solved:

- ``"direct"``: sparse LU (scipy splu), factorised once per solve; exact to rounding. Fill-in
  makes it impractical beyond 2D or a few hundred thousand nodes.
- ``"gauss-seidel"``: numba symmetric Gauss–Seidel sweeps (alternately forward and backward)
  on the M-matrix splitting A = D − N (D diagonal, N ≥ 0), z_i ← (b_i + Σ_j N_ij z_j)/D_ii,
  warm-started from b, all sweeps of a step in one compiled call (single core: one kernel
  launch per step, no thread wake-ups). Every iterate is non-negative (z ≥ 0 and the maximum
  principle hold at any iteration count) and each sweep contracts the max-norm error by at
  most ρ = max_i Σ_j N_ij / D_ii < 1; the sweeps stop when the max-norm change is
  ≤ ``tol``·max z, leaving an error of at most ρ/(1 − ρ) times that.
- ``"bicgstab"``: scipy's BiCGSTAB with a Jacobi preconditioner (relative residual ``tol``): the
  plain-scipy baseline of ``benchmarks/scale.py``. Its iterates are not guaranteed non-negative.
- ``"auto"``: direct for 2D grids up to :data:`DIRECT_LIMIT` nodes, Gauss–Seidel otherwise.
"""


class ImplicitStep:
    """The backward-Euler step operator of a problem and time step, built once per solve.

    Call ``step(z, out, scale)``: writes ``out = A⁻¹(scale · z)`` for ``z`` ``(K, N)`` and
    returns the row maxima of ``out``; see :data:`LINEAR_SOLVERS` for how A is inverted.
    """

    name = "implicit"
    supports_fitting = False

    def __init__(
        self,
        problem: Problem,
        dt: float,
        linear_solver: str = "auto",
        tol: float = 1e-10,
        max_iterations: int = 10_000,
    ):
        if linear_solver not in LINEAR_SOLVERS:
            raise ValueError(
                f"linear_solver must be one of {', '.join(LINEAR_SOLVERS)}, got {linear_solver!r}"
            )
        grid = problem.require_grid("the implicit scheme")
        exit_nodes = problem.exit_mask()
        q = np.where(exit_nodes, 0.0, problem.state_cost_values())
        if exit_nodes.any():
            L = folded_exit_generator(problem, "upwind", exit_nodes)
        else:
            L = generator_matrix(problem, "upwind")
        self.matrix = (
            sp.identity(grid.size, format="csr") + sp.diags(dt * q / problem.temperature) - dt * L
        ).tocsr()
        if linear_solver == "auto":
            small = grid.size <= DIRECT_LIMIT and grid.ndim <= 2
            linear_solver = "direct" if small else "gauss-seidel"
        self.linear_solver, self.tol, self.max_iterations = linear_solver, tol, max_iterations
        self.iterations: list[int] = []
        diagonal = self.matrix.diagonal()
        if linear_solver == "direct":
            self._lu = spla.splu(self.matrix.tocsc())
        elif linear_solver == "bicgstab":
            self._preconditioner = spla.LinearOperator(
                self.matrix.shape, matvec=lambda v, inv=1.0 / diagonal: inv * v
            )
        else:
            off = -(self.matrix - sp.diags(diagonal)).tocsr()
            off.eliminate_zeros()
            self._off = (off.indptr.astype(np.int64), off.indices.astype(np.int32), off.data)
            self._inv_diag = 1.0 / diagonal
            self.contraction = float(np.max(np.asarray(off.sum(axis=1)).ravel() * self._inv_diag))

    @property
    def direct(self) -> bool:
        return self.linear_solver == "direct"

    @property
    def nbytes(self) -> int:
        total = self.matrix.data.nbytes + self.matrix.indices.nbytes + self.matrix.indptr.nbytes
        if self.direct:
            total += sum(
                m.data.nbytes + m.indices.nbytes + m.indptr.nbytes for m in (self._lu.L, self._lu.U)
            )
        elif self.linear_solver == "gauss-seidel":
            total += sum(a.nbytes for a in self._off) + self._inv_diag.nbytes
        return int(total)

    @staticmethod
    def estimate_bytes(grid) -> int:
        """Memory of the operator for ``grid``: the matrix twice (CSR with its off-diagonal
        copy) and its assembly; the LU fill-in of ``"direct"`` is not predictable."""
        return grid.size * (2 * grid.ndim + 1) * 12 * 4

    def _gauss_seidel(self, b: np.ndarray, out: np.ndarray) -> float:
        out[...] = b  # warm start: z(t) ≈ z(t + Δt)
        sweeps = gauss_seidel_kernel(
            *self._off, self._inv_diag, b, out, self.tol, self.max_iterations
        )
        if sweeps < 0:
            raise ConvergenceError(
                f"Gauss–Seidel did not converge in {self.max_iterations} sweeps (contraction "
                f"{self.contraction:.3f}): use a smaller dt"
            )
        self.iterations.append(sweeps)
        return float(out.max())

    def __call__(self, z: np.ndarray, out: np.ndarray, scale: np.ndarray) -> np.ndarray:
        """out = A⁻¹ (scale · z) for every row of ``z`` ``(K, N)``; returns the row maxima."""
        b = z * scale[:, None]
        if self.direct:
            out[...] = self._lu.solve(np.ascontiguousarray(b.T)).T
            return out.max(axis=1)
        if self.linear_solver == "gauss-seidel":
            return np.array([self._gauss_seidel(b[r], out[r]) for r in range(b.shape[0])])
        for r in range(b.shape[0]):
            count = [0]

            def _count(_, count=count):
                count[0] += 1

            sol, info = spla.bicgstab(
                self.matrix,
                b[r],
                x0=b[r],
                rtol=self.tol,
                atol=0.0,
                M=self._preconditioner,
                callback=_count,
                maxiter=10_000,
            )
            if info != 0:
                raise ConvergenceError(
                    f"BiCGSTAB did not converge in the implicit step (info={info})"
                )
            self.iterations.append(count[0])
            out[r] = sol
        return out.max(axis=1)


MIN_STEPS = 50
"""Fewest steps of the implicit scheme's default time grid."""


class ImplicitScheme(SchemeBase):
    """Implicit upwind with backward Euler (this module), the reference scheme. Backward Euler
    is stable and monotone at any step: no :class:`~gridlbc.schemes.protocol.StepBound`."""

    name = "implicit"
    supports_fitting = False
    supports_exit = True
    supports_linear_solver = True
    step = ImplicitStep

    def step_rule(self, settings) -> StepRule:
        """Courant number 1 against the largest rate (its first-order error grows with the
        step), at least ``min_steps`` (default :data:`MIN_STEPS`) steps."""
        return StepRule(1.0, "peak", settings.min_steps or MIN_STEPS)

    def march(self, plan: MarchPlan, terminal: Terminal) -> Marched:
        """The plain loop (:func:`~gridlbc.schemes.march.march_linear`); no fitting."""
        if terminal.reference is not None or terminal.log:
            raise ValueError("the implicit scheme has no fitted operator: solve with fitting=None")
        step = ImplicitStep(plan.problem, plan.dt, linear_solver=plan.options["linear_solver"])
        return march_linear(plan, terminal, step, self.name, plan.elapsed())

    def check(self, solutions: list, marched: Marched) -> None:
        """The tails of the backward-Euler diffusion over the whole step
        (:func:`~gridlbc.schemes.tails.check_resolution`)."""
        for solution in solutions:
            check_resolution(solution.problem, solution, solution.diagnostics.dt)


IMPLICIT = ImplicitScheme()
"""The implicit scheme (``method="implicit"``)."""
