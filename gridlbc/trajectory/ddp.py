"""Gauss–Newton DDP (iLQR) on the RK4-discretised deterministic problem.

Around a tape (x̄_k, ū_k) the RK4 map F of :mod:`gridlbc.trajectory.shooting` is linearised,
δx_k+1 = A_k δx_k + B_k δu_k, with A_k = ∂F/∂x and B_k = ∂F/∂u by the chain rule through the
four stages (f_x at each stage point by central differences):

    D₁ = f_x¹,  D₂ = f_x² (I + ½Δt D₁),  D₃ = f_x³ (I + ½Δt D₂),  D₄ = f_x⁴ (I + Δt D₃),
    E₁ = B¹,    E₂ = f_x² ½Δt E₁ + B²,    E₃ = f_x³ ½Δt E₂ + B³,    E₄ = f_x⁴ Δt E₃ + B⁴,
    A_k = I + (Δt/6)(D₁ + 2D₂ + 2D₃ + D₄),    B_k = (Δt/6)(E₁ + 2E₂ + 2E₃ + E₄).

The costs ℓ_k = (q(x_k, t_k) + ½ uᵀRu) Δt and g(x_K) enter by their gradients and Hessians
(exact for :class:`gridlbc.costs.Quadratic` and :class:`gridlbc.costs.Tracking`, central
differences otherwise, projected onto the positive semi-definite cone). The backward pass, from
p_K = ∇g, P_K = ∇²g,

    Q_x = ℓ_x + Aᵀp',  Q_u = ℓ_u + Bᵀp',  Q_xx = ℓ_xx + AᵀP'A,  Q_uu = RΔt + BᵀP'B,  Q_ux = BᵀP'A,
    k = −Q_uu⁻¹ Q_u,   K = −Q_uu⁻¹ Q_ux,
    p = Q_x + Kᵀ Q_uu k + Kᵀ Q_u + Q_uxᵀ k,    P = Q_xx + Kᵀ Q_uu K + Kᵀ Q_ux + Q_uxᵀ K,

drops the second derivatives of the dynamics (Gauss–Newton), so P = Q_xx − Q_uxᵀQ_uu⁻¹Q_ux is a
Schur complement of a positive semi-definite matrix: P ⪰ 0 at every step. The forward pass
u_k = ū_k + α k_k + K_k (x_k − x̄_k) is tried for several α at once (one batched rollout) and the
cheapest is accepted if it lowers J; otherwise Q_uu is regularised (Levenberg–Marquardt) and the
step retried. At convergence k → 0 and ∂J/∂u_k = Q_u → 0; p_k and P_k are then the gradient and
Gauss–Newton Hessian of the cost-to-go at x̄_k, and K_k the time-varying LQR gain.

The full (Newton) DDP pass keeps the second derivatives of the dynamics: with z = (x, u) and
F_zz the second derivatives of the RK4 map (central differences of A and B),

    [[Q_xx, Q_xu], [Q_ux, Q_uu]] += Σ_i p'_i ∂²F_i/∂z²,

and then P_k is the exact Hessian of the discrete cost-to-go of the neighbouring optima (no longer
⪰ 0 by construction). The projected pass carries P_k⁺, the positive semi-definite part of each
P_k, to the step before it: every step keeps the dynamics' curvature, but no step's model
rewards a deviation. :func:`gridlbc.trajectory.expand` takes its value from the full pass and
its tracker's gain from the projected one by default (:func:`sweeps` runs several passes on one
linearisation); the iLQR iterations here keep the Gauss–Newton model, which is the robust one
far from a minimum.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..costs import Quadratic, Tracking
from .shooting import Shooting, gradient

_ALPHAS = 0.5 ** np.arange(12)  # forward-pass step lengths tried together
_HESSIAN_STEP = np.finfo(float).eps ** 0.25  # outer step of finite-difference Hessians


@dataclass(frozen=True)
class BackwardPass:
    """One Riccati sweep: p ``(K+1, d)``, P ``(K+1, d, d)``, feed-forward k ``(K, m)``, gains K
    ``(K, m, d)`` and the predicted first-order decrease Σ k·Q_u (negative or zero)."""

    p: np.ndarray
    P: np.ndarray
    feedforward: np.ndarray
    gains: np.ndarray
    decrease: float
    control_gradient: np.ndarray  # Q_u (K, m): ∂J/∂u_k


def linearize(shooting: Shooting, U: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """States ``(K+1, d)`` of tape ``U`` ``(K, m)`` and the RK4 Jacobians A ``(K, d, d)``,
    B ``(K, d, m)``."""
    states = shooting.rollout(U[None])[0][0]
    A, Bd = step_jacobians(shooting, states[:-1], U)
    return states, A, Bd


def step_jacobians(
    shooting: Shooting, x: np.ndarray, u: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """A = ∂F/∂x ``(P, d, d)`` and B = ∂F/∂u ``(P, d, m)`` of one RK4 step from states
    ``(P, d)`` with controls ``(P, m)`` (the stage chain rule of the module docstring)."""
    P, d = x.shape
    h = shooting.dt
    k1, B1 = shooting.velocity(x, u)
    x2 = x + 0.5 * h * k1
    k2, B2 = shooting.velocity(x2, u)
    x3 = x + 0.5 * h * k2
    k3, B3 = shooting.velocity(x3, u)
    x4 = x + h * k3
    _, B4 = shooting.velocity(x4, u)
    stages = np.stack([x, x2, x3, x4], axis=1)  # (P, 4, d)
    fx = shooting.velocity_jacobian(stages.reshape(-1, d), np.repeat(u, 4, axis=0))
    fx = fx.reshape(P, 4, d, d)
    eye = np.eye(d)
    D1 = fx[:, 0]
    D2 = fx[:, 1] @ (eye + 0.5 * h * D1)
    D3 = fx[:, 2] @ (eye + 0.5 * h * D2)
    D4 = fx[:, 3] @ (eye + h * D3)
    E2 = fx[:, 1] @ (0.5 * h * B1) + B2
    E3 = fx[:, 2] @ (0.5 * h * E2) + B3
    E4 = fx[:, 3] @ (h * E3) + B4
    A = eye + (h / 6.0) * (D1 + 2.0 * D2 + 2.0 * D3 + D4)
    Bd = (h / 6.0) * (B1 + 2.0 * E2 + 2.0 * E3 + E4)
    return A, Bd


def step_hessians(shooting: Shooting, x: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The second derivatives ∂²F_i/∂z_a∂z_b of one RK4 step in z = (x, u), shape
    ``(P, d, d+m, d+m)``: central differences of :func:`step_jacobians`, symmetrised."""
    P, d = x.shape
    m = u.shape[1]
    z = np.concatenate([x, u], axis=1)
    n = d + m
    h = _HESSIAN_STEP * np.maximum(1.0, np.abs(z))  # (P, n)
    shifted = np.repeat(z[None, None], 2, axis=0).repeat(n, axis=1)  # (2, n, P, n)
    for a in range(n):
        shifted[0, a, :, a] += h[:, a]
        shifted[1, a, :, a] -= h[:, a]
    flat = shifted.reshape(-1, n)
    A, B = step_jacobians(shooting, flat[:, :d], flat[:, d:])
    J = np.concatenate([A, B], axis=2).reshape(2, n, P, d, n)  # ∂F_i/∂z_b at z ± h e_a
    H = (J[0] - J[1]) / (2.0 * h.T[:, :, None, None])  # (a, P, i, b)
    H = np.transpose(H, (1, 2, 0, 3))  # (P, i, a, b)
    return 0.5 * (H + np.swapaxes(H, 2, 3))


def cost_derivatives(
    cost, x: np.ndarray, t: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Gradient ``(P, d)`` and positive semi-definite Hessian ``(P, d, d)`` of a cost at ``x``.

    ``t`` (``(P,)``) is passed to time-dependent costs (``cost.time_dependent``). Exact for
    Quadratic and Tracking costs; central differences otherwise, the Hessian symmetrised and its
    negative eigenvalues set to zero (the Gauss–Newton model must not reward deviations).
    """
    timed = getattr(cost, "time_dependent", False)
    if isinstance(cost, (Quadratic, Tracking)):  # a Tracking cost is the time-dependent one
        diff = cost.difference(x, t) if isinstance(cost, Tracking) else cost.difference(x)
        W = cost.weights
        return 2.0 * diff @ W, np.broadcast_to(2.0 * W, (len(x), *W.shape)).copy()
    P, d = x.shape
    if timed:

        def f(y):
            return np.asarray(cost(y, np.tile(t, len(y) // P)), dtype=float)
    else:

        def f(y):
            return np.asarray(cost(y), dtype=float)

    grad = gradient(f, x)
    h = _HESSIAN_STEP * np.maximum(1.0, np.abs(x))  # (P, d)
    H = np.empty((P, d, d))
    for j in range(d):
        step = np.zeros_like(x)
        step[:, j] = h[:, j]
        both = gradient(f, np.concatenate([x + step, x - step]))
        H[:, :, j] = (both[:P] - both[P:]) / (2.0 * h[:, j, None])
    return grad, positive_part(0.5 * (H + np.swapaxes(H, 1, 2)))


def positive_part(P: np.ndarray) -> np.ndarray:
    """The projection of symmetric matrices ``(..., d, d)`` onto the positive semi-definite cone
    (negative eigenvalues set to zero)."""
    w, V = np.linalg.eigh(P)
    if np.all(w >= 0.0):
        return P
    return np.einsum("...ij,...j,...kj->...ik", V, np.maximum(w, 0.0), V)


def running_derivatives(
    shooting: Shooting, state_cost, states: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """ℓ_x ``(K, d)`` and ℓ_xx ``(K, d, d)`` of the state part q Δt at x_0 … x_K−1."""
    K = len(states) - 1
    d = states.shape[1]
    if state_cost is None:
        return np.zeros((K, d)), np.zeros((K, d, d))
    g, H = cost_derivatives(state_cost, states[:-1], shooting.times[:K])
    return shooting.dt * g, shooting.dt * H


def backward_pass(
    A: np.ndarray,
    B: np.ndarray,
    U: np.ndarray,
    R: np.ndarray,
    dt: float,
    lx: np.ndarray,
    lxx: np.ndarray,
    gx: np.ndarray,
    gxx: np.ndarray,
    regularization: float = 0.0,
    F2: np.ndarray | None = None,
    projected: bool = False,
) -> BackwardPass:
    """The Gauss–Newton Riccati sweep of the module docstring (``regularization`` μ adds
    μ·RΔt to Q_uu when solving for k and K).

    With ``F2`` (``(K, d, d+m, d+m)``, :func:`step_hessians`) it is the full (Newton) DDP sweep
    instead: Σ_i p'_i ∂²F_i/∂z² is added to [[Q_xx, Q_xu], [Q_ux, Q_uu]], so P is the exact
    Hessian of the discrete cost-to-go along the tape (no longer ⪰ 0 by construction).
    ``projected``: each P_k is replaced by its positive semi-definite part P_k⁺
    (:func:`positive_part`) before the step to k − 1 uses it, so that every step's model keeps
    the dynamics' curvature but rewards no deviation."""
    K, d, m = B.shape
    p = np.empty((K + 1, d))
    P = np.empty((K + 1, d, d))
    kff = np.empty((K, m))
    gains = np.empty((K, m, d))
    Qu_all = np.empty((K, m))
    p[K], P[K] = gx, gxx
    Ruu = R * dt
    decrease = 0.0
    for k in range(K - 1, -1, -1):
        Ak, Bk, Vx, Vxx = A[k], B[k], p[k + 1], P[k + 1]
        Qx = lx[k] + Ak.T @ Vx
        Qu = Ruu @ U[k] + Bk.T @ Vx
        VB = Vxx @ Bk
        Qxx = lxx[k] + Ak.T @ Vxx @ Ak
        Quu = Ruu + Bk.T @ VB
        Qux = VB.T @ Ak
        if F2 is not None:
            curvature = np.einsum("i,iab->ab", Vx, F2[k])
            Qxx = Qxx + curvature[:d, :d]
            Qux = Qux + curvature[d:, :d]
            Quu = Quu + curvature[d:, d:]
        solve = np.linalg.solve(Quu + regularization * Ruu, np.column_stack([Qu, Qux]))
        kk, KK = -solve[:, 0], -solve[:, 1:]
        p[k] = Qx + KK.T @ (Quu @ kk) + KK.T @ Qu + Qux.T @ kk
        Pk = Qxx + KK.T @ Quu @ KK + KK.T @ Qux + Qux.T @ KK
        P[k] = positive_part(0.5 * (Pk + Pk.T)) if projected else 0.5 * (Pk + Pk.T)
        kff[k], gains[k], Qu_all[k] = kk, KK, Qu
        decrease += float(kk @ Qu)
    return BackwardPass(p, P, kff, gains, decrease, Qu_all)


PASSES = ("gauss-newton", "newton", "projected-newton")
"""The backward passes of :func:`backward_pass`: Gauss–Newton, full DDP, and full DDP carrying
the positive semi-definite part of each P_k."""


def sweep(
    shooting: Shooting,
    U: np.ndarray,
    terminal_cost,
    state_cost,
    regularization: float = 0.0,
    newton: bool = False,
) -> tuple[np.ndarray, BackwardPass]:
    """Linearise along tape ``U`` and run the backward pass: ``(states, BackwardPass)``;
    ``newton``: with the dynamics' second derivatives (full DDP)."""
    passes = ("newton" if newton else "gauss-newton",)
    states, (back,) = sweeps(shooting, U, terminal_cost, state_cost, passes, regularization)
    return states, back


def sweeps(
    shooting: Shooting,
    U: np.ndarray,
    terminal_cost,
    state_cost,
    passes=("gauss-newton", "newton"),
    regularization: float = 0.0,
) -> tuple[np.ndarray, list[BackwardPass]]:
    """One linearisation along tape ``U``, then one backward pass per entry of ``passes``
    (each one of :data:`PASSES`): ``(states, [BackwardPass, ...])``."""
    states, A, Bd = linearize(shooting, U)
    lx, lxx = running_derivatives(shooting, state_cost, states)
    gx, gxx = cost_derivatives(terminal_cost, states[-1:])
    newton = [name != "gauss-newton" for name in passes]
    F2 = step_hessians(shooting, states[:-1], U) if any(newton) else None
    return states, [
        backward_pass(
            A,
            Bd,
            U,
            shooting.R,
            shooting.dt,
            lx,
            lxx,
            gx[0],
            gxx[0],
            regularization,
            F2 if full else None,
            projected=name == "projected-newton",
        )
        for name, full in zip(passes, newton)
    ]


def closed_loop(
    shooting: Shooting, states: np.ndarray, U: np.ndarray, back: BackwardPass, alphas: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Forward passes u_k = ū_k + α k_k + K_k (x_k − x̄_k) for each α: states ``(n, K+1, d)``,
    controls ``(n, K, m)``."""
    n = len(alphas)
    K, m = U.shape
    X = np.empty((n, K + 1, states.shape[1]))
    V = np.empty((n, K, m))
    x = np.repeat(states[:1], n, axis=0)
    X[:, 0] = x
    for k in range(K):
        u = U[k] + alphas[:, None] * back.feedforward[k] + (x - states[k]) @ back.gains[k].T
        x = shooting.step(x, u)
        X[:, k + 1], V[:, k] = x, u
    return X, V


def ilqr(
    shooting: Shooting,
    U: np.ndarray,
    terminal_cost,
    state_cost,
    max_iter: int = 200,
    tol: float = 1e-13,
) -> tuple[np.ndarray, int, bool]:
    """Polish tape ``U`` by iLQR until the relative decrease of J falls below ``tol``.

    Returns the tape, the iterations taken and whether it converged (the last accepted step
    decreased J by less than ``tol`` relative, or no step could decrease it at the largest
    regularisation, i.e. the tape is a local minimum to rounding).
    """
    with np.errstate(all="ignore"):
        J = float(shooting.cost(U[None], shooting.rollout(U[None])[0])[0])
    mu = 0.0
    for iteration in range(1, max_iter + 1):
        states, back = sweep(shooting, U, terminal_cost, state_cost, mu)
        with np.errstate(all="ignore"):
            X, V = closed_loop(shooting, states, U, back, _ALPHAS)
            costs = shooting.cost(V, X)
        costs = np.where(np.isfinite(costs), costs, np.inf)
        best = int(np.argmin(costs))
        if costs[best] < J:
            decrease = J - costs[best]
            U, J = V[best], float(costs[best])
            mu = 0.0 if mu <= 1e-6 else mu / 10.0
            if decrease <= tol * max(1.0, abs(J)):
                return U, iteration, True
        else:
            if abs(back.decrease) <= tol * max(1.0, abs(J)):
                return U, iteration, True  # nothing left to gain to first order
            mu = max(10.0 * mu, 1e-6)
            if mu > 1e8:
                return U, iteration, False
    return U, max_iter, False
