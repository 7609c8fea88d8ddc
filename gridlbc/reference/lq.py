"""The Riccati solution of linear-quadratic problems, the exact check for the grid solvers.

:func:`~gridlbc.reference.lq_solution` is the closed-form optimum of a linear system with quadratic
costs: v(x, t) = ½ xᵀP(t)x + p(t)ᵀx + c₀(t) with S = B R⁻¹ Bᵀ and, backward from T,

    −Ṗ  = AᵀP + P A − P S P + 2 W_q                    P(T)  = 2 W_T
    −ṗ  = (A − S P)ᵀ p − 2 W_q c_q                     p(T)  = −2 W_T c_T
    −ċ₀ = −½ pᵀ S p + (λ/2) tr(S P) + c_qᵀ W_q c_q      c₀(T) = c_Tᵀ W_T c_T

and u*(x, t) = −R⁻¹ Bᵀ (P x + p). The ODEs are integrated to near machine precision (DOP853).

:func:`~gridlbc.reference.euler_chain_value` is the exact optimum of the Euler–Maruyama chain of the
same problem, the number :func:`gridlbc.certify` estimates at a given step (docs
page :doc:`validating`).

"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ..costs import Quadratic
from ..problem import Problem, check_time, state_evaluation


@dataclass(frozen=True, eq=False)
class LQSolution:
    """The exact value and policy of a linear-quadratic problem at any (x, t).

    Attributes
    ----------
    problem : Problem
        The problem solved.
    """

    problem: Problem
    _dense: Callable[[float], np.ndarray]

    def coefficients(self, t: float) -> tuple[np.ndarray, np.ndarray, float]:
        """(P(t), p(t), c₀(t))."""
        T = self.problem.require_horizon("lq_solution")
        y = self._dense(T - check_time(t, T))
        d = self.problem.state_dim
        return y[: d * d].reshape(d, d), y[d * d : d * d + d], float(y[-1])

    @state_evaluation
    def value(self, x, t) -> np.ndarray:
        """v(x, t), shape ``(N,)`` (a scalar for one state ``(d,)``)."""
        x = self.problem.check_states(x)
        P, p, c0 = self.coefficients(t)
        return 0.5 * np.einsum("ni,ij,nj->n", x, P, x) + x @ p + c0

    @state_evaluation
    def policy(self, x, t) -> np.ndarray:
        """u*(x, t) = −R⁻¹ Bᵀ (P x + p), shape ``(N, m)`` (``(m,)`` for one state)."""
        x = self.problem.check_states(x)
        P, p, _ = self.coefficients(t)
        matrices = self.problem.system.linear_matrices()
        assert matrices is not None, "lq_solution checked the system is linear"
        _, B = matrices
        return -(x @ P + p) @ B @ self.problem.R_inv.T


def _quadratic_terms(cost, name: str, d: int) -> tuple[np.ndarray, np.ndarray]:
    if cost is None:
        return np.zeros((d, d)), np.zeros(d)
    if not isinstance(cost, Quadratic):
        raise TypeError(f"lq_solution needs {name} to be a gridlbc.costs.Quadratic (or None)")
    return cost.weights, cost.center


def is_linear_quadratic(problem: Problem) -> bool:
    """Whether :func:`~gridlbc.reference.lq_solution` applies to ``problem``: a(x) = A x with
    constant B, Quadratic (or no) terminal and state costs, and no periodic axis."""
    return (
        problem.system.linear_matrices() is not None
        and not problem.periodic_axes
        and isinstance(problem.terminal_cost, Quadratic)
        and (problem.state_cost is None or isinstance(problem.state_cost, Quadratic))
    )


def lq_solution(problem: Problem, rtol: float = 1e-12) -> LQSolution:
    """The exact solution for a linear system with quadratic costs.

    Requires ``problem.system.linear_matrices()`` (a(x) = A x, constant B), Quadratic terminal and
    state costs, and no periodic axis (the closed form lives on all of Rᵈ); a grid-free Problem
    will do.

    Parameters
    ----------
    problem : Problem
        The linear-quadratic problem.
    rtol : float
        Relative tolerance of the Riccati integration (docs page :doc:`maths`).

    Returns
    -------
    LQSolution
    """
    matrices = problem.system.linear_matrices()
    if matrices is None:
        raise TypeError(
            f"lq_solution needs a linear system (a(x) = A x, constant B), known by its "
            f"linear_matrices(), and {type(problem.system).__name__}.linear_matrices() returns "
            "None: for a linear system of your own give it a linear_matrices() returning "
            "(A, B), or use gridlbc.systems.LinearSystem(A, B); for a nonlinear one, "
            "reference.solve_hjb"
        )
    if problem.periodic_axes:
        raise ValueError(
            "lq_solution is the solution on all of Rᵈ: the problem must have no "
            f"periodic axis, got {list(problem.periodic_axes)}"
        )
    A, B = matrices
    d = A.shape[0]
    S = B @ problem.R_inv @ B.T
    WT, cT = _quadratic_terms(problem.terminal_cost, "terminal_cost", d)
    Wq, cq = _quadratic_terms(problem.state_cost, "state_cost", d)
    lam = problem.temperature

    def rhs(_tau, y):  # d/dτ with τ = T − t
        P = y[: d * d].reshape(d, d)
        p = y[d * d : d * d + d]
        dP = A.T @ P + P @ A - P @ S @ P + 2 * Wq
        dp = (A - S @ P).T @ p - 2 * Wq @ cq
        dc = -0.5 * p @ S @ p + 0.5 * lam * np.trace(S @ P) + cq @ Wq @ cq
        return np.concatenate([dP.ravel(), dp, [dc]])

    y0 = np.concatenate([(2 * WT).ravel(), -2 * WT @ cT, [cT @ WT @ cT]])
    sol = solve_ivp(
        rhs, (0.0, problem.horizon), y0, method="DOP853", rtol=rtol, atol=1e-14, dense_output=True
    )
    if not sol.success:
        raise RuntimeError(f"Riccati integration failed: {sol.message}")
    return LQSolution(problem, sol.sol)


def euler_chain_value(problem: Problem, x0, n_steps: int = 300) -> float:
    """The optimal cost of the Euler–Maruyama chain of a linear-quadratic problem from ``x0``:
    −λ log E₀[exp(−(g(x_K) + Σ q(x_k) Δt)/λ)] for the zero-control chain
    x_{k+1} = (I + A Δt) x_k + B η_k, η_k ~ N(0, λ R⁻¹ Δt), Δt = T / ``n_steps``, exactly.

    v_k(x) = ½ xᵀP_k x + p_kᵀx + c_k; integrating η out of exp(−v_{k+1}/λ) gives, with
    F = I + A Δt and N = B (R/Δt + BᵀPB)⁻¹ Bᵀ,

        P_k = 2W_q Δt + Fᵀ(P − PNP)F,      p_k = −2W_q c_q Δt + Fᵀ(p − PNp),
        c_k = c_qᵀW_q c_q Δt + c − ½ pᵀNp + (λ/2) log det(I + Δt R⁻¹BᵀPB).

    This is what :func:`gridlbc.certify` estimates at the step Δt for any proposal (its
    distance from :func:`~gridlbc.reference.lq_solution`'s value is the chain's O(Δt) weak error).

    Parameters
    ----------
    problem : Problem
        Linear dynamics and Quadratic (or no) state cost, a Quadratic terminal cost, horizon T.
    x0 : array_like (d,)
        The start state.
    n_steps : int
        Euler–Maruyama steps over T.
    """
    matrices = problem.system.linear_matrices()
    if matrices is None:
        raise TypeError(
            f"euler_chain_value needs a linear system (a(x) = A x, constant B); "
            f"{type(problem.system).__name__} is not"
        )
    A, B = matrices
    lam, R, dt = problem.temperature, problem.R, problem.require_horizon("a chain") / n_steps
    d = A.shape[0]
    WT, cT = _quadratic_terms(problem.terminal_cost, "terminal_cost", d)
    Wq, cq = _quadratic_terms(problem.state_cost, "state_cost", d)
    P, p, c = 2 * WT, -2 * WT @ cT, cT @ WT @ cT
    F = np.eye(d) + A * dt
    for _ in range(n_steps):
        N = B @ np.linalg.solve(R / dt + B.T @ P @ B, B.T)
        logdet = np.linalg.slogdet(np.eye(B.shape[1]) + dt * np.linalg.solve(R, B.T @ P @ B))[1]
        P, p, c = (
            2 * Wq * dt + F.T @ (P - P @ N @ P) @ F,
            -2 * Wq @ cq * dt + F.T @ (p - P @ N @ p),
            cq @ Wq @ cq * dt + c - 0.5 * p @ N @ p + 0.5 * lam * logdet,
        )
    x0 = np.asarray(x0, dtype=float)
    return float(0.5 * x0 @ P @ x0 + p @ x0 + c)
