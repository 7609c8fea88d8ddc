"""Implicit upwind scheme for the linear Bellman PDE (SPEC §3): the reference discretisation.

The generator of a continuous-time Markov chain on the nodes approximates aᵀ∇ + tr(D ∇²),
D = ½ λ B R⁻¹ Bᵀ (diagonal): from node i along axis k it jumps

    to i + e_k at rate max(a_k, 0)/h_k + D_kk/h_k²,    to i − e_k at rate max(−a_k, 0)/h_k + D_kk/h_k²,

with periodic wrap, and jumps that would leave a closed axis suppressed (a reflecting state
constraint: no probability leaves the box). With L that generator (rows sum to zero) backward
Euler reads

    (I + Δt diag(q/λ) − Δt L) z(t) = z(t + Δt),

an M-matrix: z ≥ 0 and the discrete maximum principle hold for any Δt. The price is first-order
numerical diffusion |a_k| h_k / 2 along each axis, which swamps the physical noise where the drift
is fast. The matrix is assembled once from COO arrays and factorised once per solve (sparse LU);
grids too large to factorise are solved by BiCGSTAB with a Jacobi preconditioner, warm-started
from the previous slice.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .problem import Problem

DIRECT_LIMIT = 400_000
"""Grids with more nodes than this (or more than two dimensions) use the iterative solver."""


def generator_matrix(problem: Problem) -> sp.csr_matrix:
    """The upwind generator L (N×N, CSR): off-diagonal rates ≥ 0, rows summing to zero."""
    grid = problem.grid
    x = grid.nodes()
    drift = np.asarray(problem.system.drift(x), dtype=float)
    diffusion = 0.5 * problem.noise_diagonal(x)
    n_nodes = grid.size
    flat = np.arange(n_nodes)
    multi = np.unravel_index(flat, grid.shape)
    rows, cols, rates = [], [], []
    for k, ax in enumerate(grid.axes):
        h, s = ax.spacing, int(grid.strides[k])
        i = multi[k]
        for sign in (1, -1):
            rate = np.maximum(sign * drift[:, k], 0.0) / h + diffusion[:, k] / h**2
            target_i = i + sign
            if ax.periodic:
                target = flat + s * (np.mod(target_i, ax.n) - i)
                keep = rate > 0
            else:
                target = flat + sign * s
                keep = (rate > 0) & (target_i >= 0) & (target_i < ax.n)
            rows.append(flat[keep])
            cols.append(target[keep])
            rates.append(rate[keep])
    rows, cols, rates = map(np.concatenate, (rows, cols, rates))
    off = sp.coo_matrix((rates, (rows, cols)), shape=(n_nodes, n_nodes)).tocsr()
    return (off - sp.diags(np.asarray(off.sum(axis=1)).ravel())).tocsr()


class ImplicitStep:
    """The backward-Euler step operator of a problem and time step, factorised once per solve."""

    name = "implicit"

    def __init__(self, problem: Problem, dt: float, direct: bool | None = None,
                 rtol: float = 1e-12):
        grid = problem.grid
        q = problem.state_cost_values()
        L = generator_matrix(problem)
        self.matrix = (sp.identity(grid.size, format="csr") + sp.diags(dt * q / problem.temperature)
                       - dt * L).tocsc()
        if direct is None:
            direct = grid.size <= DIRECT_LIMIT and grid.ndim <= 2
        self.direct = direct
        self.rtol = rtol
        self.iterations: list[int] = []
        if direct:
            self._lu = spla.splu(self.matrix)
        else:
            self._jacobi = spla.LinearOperator(
                self.matrix.shape, matvec=lambda v, inv=1.0 / self.matrix.diagonal(): inv * v
            )

    @property
    def nbytes(self) -> int:
        total = self.matrix.data.nbytes + self.matrix.indices.nbytes + self.matrix.indptr.nbytes
        if self.direct:
            total += sum(m.data.nbytes + m.indices.nbytes + m.indptr.nbytes
                         for m in (self._lu.L, self._lu.U))
        return int(total)

    @staticmethod
    def estimate_bytes(grid) -> int:
        """Memory of the operator for ``grid`` (matrix; the LU fill-in is not predictable)."""
        return grid.size * (2 * grid.ndim + 1) * 12 * 3

    def __call__(self, z: np.ndarray, out: np.ndarray, scale: np.ndarray) -> np.ndarray:
        """out = A⁻¹ (scale · z) for every row of ``z`` ``(K, N)``; returns the row maxima."""
        z = z * scale[:, None]
        if self.direct:
            out[...] = self._lu.solve(np.ascontiguousarray(z.T)).T
            return out.max(axis=1)
        for r in range(z.shape[0]):
            count = [0]

            def _count(_):
                count[0] += 1

            sol, info = spla.bicgstab(self.matrix, z[r], x0=z[r], rtol=self.rtol, atol=0.0,
                                      M=self._jacobi, callback=_count, maxiter=10_000)
            if info != 0:
                raise RuntimeError(f"BiCGSTAB did not converge in the implicit step (info={info})")
            self.iterations.append(count[0])
            out[r] = sol
        return out.max(axis=1)
