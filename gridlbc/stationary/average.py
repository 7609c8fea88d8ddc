"""Average cost (SPEC §9; docs page :doc:`first_exit`): the principal eigenpair
(L − diag(q/λ)) e = −(c/λ) e by Noda's inverse iteration, and the
stationary distribution from the left eigenvector (:mod:`gridlbc.stationary`)."""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import (
    ConvergenceError,
    ResolutionWarning,
    warn_user,
)
from ..problem import Problem
from ..schemes.generator import generator_matrix
from ..solution import StationarySolution
from .linear import (
    MAX_SHIFTS,
    StationarySettings,
    accurate_tail,
    iterative,
    linear_method,
    operator_digest,
    packaged,
    scaled_rows,
)


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
        (:func:`~gridlbc.stationary.average.stationary_distribution`; the left eigenvector, see
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
    solution = packaged(
        problem, label, e, 0.0, start, setup, iterations, operator_digest(q, M.data)
    )
    object.__setattr__(solution, "average_cost", -lam * mu)
    if e_left is not None:
        object.__setattr__(solution, "stationary_distribution", stationary_distribution(e, e_left))
    return solution


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

    the upper one with x = 1 being the largest row sum, −min q/λ. Noda's inverse iteration,
    from e₀ = 1, σ₀ = −min q/λ + ε,

          (σ_k I − M) y = e_k,      e_{k+1} = y / max y,
          σ_{k+1} = max( max_i (M e_{k+1})_i / e_{k+1,i},  ρ_{k+1} + δ ),

      the Collatz–Wielandt quotient read where e_{k+1,i} ≥ √``residual`` (below that an
      iterative solve does not resolve e's entries), never above σ_k, and ρ = eᵀMe / eᵀe
      the Rayleigh quotient (δ = ``residual`` ‖M‖_∞). σ_k stays above μ, so each shifted system
      is an M-matrix, solved after ``s.linear_solver``
      (:func:`~gridlbc.stationary.linear.linear_method`):

    - direct: by a sparse LU of σ_k I − M, exactly. A factorisation costs many solves, so where
      a solve has brought the eigen-residual down to at most
      :data:`~gridlbc.stationary.average.KEEP` of what it was, the shift is kept, and its LU
      (plain inverse iteration, whose residual falls by about (σ − μ)/(σ − μ₂) a solve, μ₂
      the next eigenvalue: that rate, measured, is what the kept shift is judged by); a new
      shift is taken where a solve cut it less;
    - iterative: as the first-exit system is (rows scaled, BiCGSTAB, ILU-GMRES where
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

    It stops when the eigen-residual ‖(M − ρI)e‖₂ ≤ ``residual`` · ‖M‖_∞ ‖e‖₂
    (:func:`~gridlbc.stationary.average.eigen_residual`),
    after :data:`~gridlbc.stationary.linear.MAX_SHIFTS` shifts at most. Why not shift-and-invert
    Arnoldi about σ₀ (ARPACK, one LU), used until 2026-12-06: on a strongly non-normal M (an axis
    without noise at a small λ) it converged to Ritz values of tiny residual that are not
    eigenvalues, complex where the Collatz–Wielandt bound puts the real μ below them, so that c
    came out low, and it took orders of magnitude more solves and time than Noda's iteration
    (stranger round 27's cold average cost: docs page :doc:`first_exit`, "How it is solved" and
    "Linear solvers"); the two agree elsewhere to the residual.

    With ``left``, also the left eigenvector ẽ > 0 (Mᵀẽ = μẽ, max entry 1), for the chain's
    stationary distribution (:func:`~gridlbc.stationary.average.stationary_distribution`), by the
    same iteration on Mᵀ (which doubles the eigen-solve's work).

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
    method = linear_method(s, ndim, n)
    mu, e, counts = _noda(M, sigma, s, method)
    if not left:
        return mu, e, counts, None
    _, e_left, more = _noda(M.T.tocsr(), sigma, s, method)
    return mu, e, counts + more, e_left


KEEP = 0.1
"""The direct eigen-solve keeps its shift, and the shift's LU, while each solve brings the
eigen-residual down to at most this fraction of what it was
(:func:`~gridlbc.stationary.principal_eigenpair`)."""


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
    factors: dict[float, spla.SuperLU] = {}  # the LU of σI − M (direct), by σ
    for _ in range(MAX_SHIFTS):
        if method == "direct":  # exact solves: one LU per shift, kept while σ stays
            if sigma not in factors:
                factors = {sigma: spla.splu((sigma * identity - M).tocsc())}
            y = factors[sigma].solve(e)
        else:
            y, iterations = _shifted_solve(sigma * identity - M, sigma, e, rho, error, s, method)
            counts.append(iterations)
        if e @ y < 0:  # σ fell below μ: back to the last shift above it, and keep it
            sigma, fixed = above, True
        else:
            above = sigma
        e = y / y[np.argmax(np.abs(y))]
        Me = M @ e
        rho = float(e @ Me / (e @ e))
        error, before = float(np.linalg.norm(Me - rho * e) / (norm * np.linalg.norm(e))), error
        if error <= s.residual:
            return rho, e, tuple(counts)
        if method == "direct" and error <= KEEP * before:
            continue  # σ converges fast enough as it is: its LU is kept (principal_eigenpair)
        if not fixed:
            resolved = e >= np.sqrt(s.residual)
            quotient = float(np.max(Me[resolved] / e[resolved]))
            sigma = min(sigma, max(quotient, rho + s.residual * norm))
    advice = (
        "give a larger residual="
        if method == "direct"
        else f"({sum(counts)} Krylov iterations): give linear_solver='direct' if its "
        "factorisation fits in memory, or a larger residual="
    )
    raise ConvergenceError(
        f"the average cost's eigen-solve did not reach the residual {s.residual:g} in "
        f"{MAX_SHIFTS} shifts {advice}"
    )


def _shifted_solve(
    shifted, sigma: float, e, rho: float, error: float, s: StationarySettings, method
):
    """y with ``shifted`` y = e, ``shifted`` = σI − M, by a Krylov ``method`` (rows scaled) from the
    guess e / (σ − ρ), to the backward error max(residual, min(10⁻², error / 10))
    (:func:`principal_eigenpair`), and its iteration count."""
    A, inverse = scaled_rows(shifted)
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
    return iterative(A, b, s, method, guess, max(target, 1e-15))
