"""Multi-start single shooting: the global search behind :func:`gridlbc.trajectory.optimize`.

The deterministic limit (λ → 0) of the control problem of docs/maths.rst is

    ẋ = a(x) + B(x) u,      J = g(x_T) + ∫₀ᵀ ( q(x, t) + ½ uᵀ R u ) dt.

With K intervals of length Δt = T/K and controls u_k held constant on [t_k, t_k+1), one step of
classical RK4 with f(x, u) = a(x) + B(x) u is

    k₁ = f(x_k, u_k),        k₂ = f(x_k + ½Δt k₁, u_k),
    k₃ = f(x_k + ½Δt k₂, u_k),  k₄ = f(x_k + Δt k₃, u_k),
    x_k+1 = F(x_k, u_k) = x_k + (Δt/6)(k₁ + 2k₂ + 2k₃ + k₄)

and the discretised cost (the rectangle rule of the rollouts) is

    J(u_0, …, u_K−1) = g(x_K) + Σ_k ( q(x_k, t_k) + ½ u_kᵀ R u_k ) Δt.

Its exact gradient is the discrete adjoint (reverse mode) of the RK4 map:

    μ_K = ∇g(x_K),   μ_k = (∂F/∂x_k)ᵀ μ_k+1 + ∇q(x_k) Δt,   ∂J/∂u_k = (∂F/∂u_k)ᵀ μ_k+1 + R u_k Δt,

with the products by ∂F/∂x and ∂F/∂u taken stage by stage through k₄, …, k₁. The Jacobians
∂f/∂x at the 4K stage points are central finite differences of the vectorised drift and input
matrix (one call for all perturbations); ∂f/∂u = B(x). Gradients of g and q are central
differences too.

Swing-ups have many local minima, so many initial tapes are tried (zero, sinusoidal pumping, random
sinusoids with offsets). They are first optimised together on a coarser tape by a batched L-BFGS
(one vectorised rollout serves all tapes, which is what makes many restarts affordable); the best
few distinct optima are refined on the full tape, and the best of those is converged with
scipy.optimize.minimize(method="L-BFGS-B").
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.optimize import minimize

StateFunction = Callable[[np.ndarray], np.ndarray]
TimedCost = Callable[[np.ndarray, np.ndarray], np.ndarray]  # q(x (P, d), t (P,)) -> (P,)

FD_STEP = np.finfo(float).eps ** (1.0 / 3.0)  # central differences, relative step
_N_REFINE = 4  # screened optima refined on the full tape
_SCREEN_ITER, _REFINE_ITER = 250, 3000
_PUMP_CYCLES = (1.0, 1.5, 2.0)  # pumping frequencies, in cycles per horizon
_PUMP_PHASES = (0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi)
_STEP_FACTORS = np.array([1.0, 0.3, 0.1, 0.03])  # step lengths tried together per round ...
_STEP_ROUNDS = 10.0 ** -np.arange(0, 12, 2)  # ... scaled by these, until one passes Armijo


class Shooting:
    """Batched RK4 single shooting: costs and adjoint gradients of N control tapes at once.

    ``state_cost`` is q(x, t) on states ``(P, d)`` and times ``(P,)``, or ``None`` for q = 0.
    """

    def __init__(
        self,
        system,
        x0: np.ndarray,
        horizon: float,
        n_intervals: int,
        terminal_cost: StateFunction,
        state_cost: TimedCost | None,
        R: np.ndarray,
    ):
        self.system = system
        self.x0, self.R = x0, R
        self.dt = horizon / n_intervals
        self.times = np.linspace(0.0, horizon, n_intervals + 1)
        self.terminal_cost, self.state_cost = terminal_cost, state_cost

    def values(self, z: np.ndarray) -> np.ndarray:
        """J of flat tapes ``(P, K m)``, inf where the rollout overflows."""
        U = z.reshape(len(z), -1, self.R.shape[0])
        with np.errstate(all="ignore"):
            J = self.cost(U, self.rollout(U)[0])
        return np.where(np.isfinite(J), J, np.inf)

    def values_and_gradients(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """J ``(P,)`` and ∇J ``(P, K m)`` of flat tapes; inf and 0 where the rollout overflows."""
        with np.errstate(all="ignore"):
            J, G = self.cost_and_gradient(z.reshape(len(z), -1, self.R.shape[0]))
        G = G.reshape(len(z), -1)
        bad = ~(np.isfinite(J) & np.all(np.isfinite(G), axis=1))
        J[bad], G[bad] = np.inf, 0.0
        return J, G

    def velocity(self, x: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """f(x, u) = a(x) + B(x) u and B(x) for states ``(P, d)`` and controls ``(P, m)``."""
        B = np.asarray(self.system.input_matrix(x), dtype=float)
        return (np.asarray(self.system.drift(x), dtype=float) + np.einsum("pij,pj->pi", B, u), B)

    def step(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """One RK4 step x_k+1 = F(x_k, u_k) for states ``(P, d)`` and controls ``(P, m)``."""
        dt = self.dt
        k1, _ = self.velocity(x, u)
        k2, _ = self.velocity(x + 0.5 * dt * k1, u)
        k3, _ = self.velocity(x + 0.5 * dt * k2, u)
        k4, _ = self.velocity(x + dt * k3, u)
        return x + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)

    def rollout(self, U: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """States ``(N, K+1, d)``, RK4 stage points ``(N, K, 4, d)``, B there ``(N, K, 4, d, m)``."""
        N, K, m = U.shape
        d = self.x0.size
        dt = self.dt
        states = np.empty((N, K + 1, d))
        stages = np.empty((N, K, 4, d))
        B = np.empty((N, K, 4, d, m))
        x = np.broadcast_to(self.x0, (N, d))
        states[:, 0] = x
        for k in range(K):
            u = U[:, k]
            stages[:, k, 0] = x
            k1, B[:, k, 0] = self.velocity(x, u)
            stages[:, k, 1] = x + 0.5 * dt * k1
            k2, B[:, k, 1] = self.velocity(stages[:, k, 1], u)
            stages[:, k, 2] = x + 0.5 * dt * k2
            k3, B[:, k, 2] = self.velocity(stages[:, k, 2], u)
            stages[:, k, 3] = x + dt * k3
            k4, B[:, k, 3] = self.velocity(stages[:, k, 3], u)
            x = x + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
            states[:, k + 1] = x
        return states, stages, B

    def running_cost(self, states: np.ndarray) -> np.ndarray:
        """q(x_k, t_k) for states ``(N, K, d)`` at t_0 … t_K−1, shape ``(N, K)``."""
        assert self.state_cost is not None, "running_cost of a problem without a state cost"
        N, K, d = states.shape
        t = np.tile(self.times[:K], N)
        return np.asarray(self.state_cost(states.reshape(N * K, d), t), dtype=float).reshape(N, K)

    def cost(self, U: np.ndarray, states: np.ndarray) -> np.ndarray:
        """J for tapes ``(N, K, m)`` with their states ``(N, K+1, d)``, shape ``(N,)``."""
        N = U.shape[0]
        J = np.asarray(self.terminal_cost(states[:, -1]), dtype=float).reshape(N)
        J = J + 0.5 * self.dt * np.einsum("nki,ij,nkj->n", U, self.R, U)
        if self.state_cost is not None:
            J = J + self.dt * self.running_cost(states[:, :-1]).sum(axis=1)
        return J

    def state_cost_gradient(self, states: np.ndarray) -> np.ndarray:
        """∇q(x_k, t_k) ``(N, K, d)`` for states ``(N, K, d)`` by central differences."""
        state_cost = self.state_cost
        assert state_cost is not None, "state_cost_gradient of a problem without a state cost"
        N, K, d = states.shape
        t = np.tile(self.times[:K], N)
        return gradient(
            lambda x: state_cost(x, np.tile(t, 2 * d)), states.reshape(N * K, d)
        ).reshape(N, K, d)

    def cost_and_gradient(self, U: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """J ``(N,)`` and ∂J/∂U ``(N, K, m)`` by the discrete adjoint."""
        N, K, m = U.shape
        d = self.x0.size
        dt = self.dt
        states, stages, B = self.rollout(U)
        J = self.cost(U, states)
        jac = self.velocity_jacobian(stages.reshape(-1, d), np.repeat(U, 4, axis=1).reshape(-1, m))
        jac = jac.reshape(N, K, 4, d, d)
        grad = dt * np.einsum("ij,nkj->nki", self.R, U)
        q_grad = None
        if self.state_cost is not None:
            q_grad = dt * self.state_cost_gradient(states[:, :-1])
        mu = gradient(self.terminal_cost, states[:, -1])
        # Reverse sweep of x_k+1 = x_k + Δt/6 (k1 + 2 k2 + 2 k3 + k4) through the stages.
        for k in range(K - 1, -1, -1):
            J_k, B_k = jac[:, k], B[:, k]
            bar_k = [dt / 6.0 * mu, dt / 3.0 * mu, dt / 3.0 * mu, dt / 6.0 * mu]
            bar_x = mu.copy()
            bar_u = np.zeros((N, m))
            # stage s is evaluated at x + c_s Δt k_s−1 with c = (½, ½, 1) for s = 1, 2, 3
            for s, c in ((3, 1.0), (2, 0.5), (1, 0.5), (0, None)):
                bar_stage = np.einsum("nij,ni->nj", J_k[:, s], bar_k[s])
                bar_u += np.einsum("nij,ni->nj", B_k[:, s], bar_k[s])
                bar_x += bar_stage
                if c is not None:
                    bar_k[s - 1] = bar_k[s - 1] + c * dt * bar_stage
            grad[:, k] += bar_u
            mu = bar_x if q_grad is None else bar_x + q_grad[:, k]
        return J, grad

    def velocity_jacobian(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """∂f/∂x ``(P, d, d)`` at points ``(P, d)`` by central differences, in one call."""
        P, d = x.shape
        points, h = _perturbations(x)
        f, _ = self.velocity(points, np.tile(u, (2 * d, 1)))
        f = f.reshape(2, d, P, d)
        return np.transpose((f[0] - f[1]) / (2.0 * h.T[:, :, None]), (1, 2, 0))


def gradient(cost: StateFunction, x: np.ndarray) -> np.ndarray:
    """∇c ``(P, d)`` at points ``(P, d)`` by central differences, in one vectorised call."""
    P, d = x.shape
    points, h = _perturbations(x)
    c = np.asarray(cost(points), dtype=float).reshape(2, d, P)
    return ((c[0] - c[1]) / (2.0 * h.T)).T


def _perturbations(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The points x ± h_j e_j stacked as ``(2 d P, d)`` (sign, axis, point), and h ``(P, d)``."""
    d = x.shape[1]
    h = FD_STEP * np.maximum(1.0, np.abs(x))
    shifted = np.repeat(x[None, None], 2, axis=0).repeat(d, axis=1)  # (2, d, P, d)
    axes = np.arange(d)
    shifted[0, axes, :, axes] += h.T
    shifted[1, axes, :, axes] -= h.T
    return shifted.reshape(-1, d), h


def multistart(
    fine: Shooting,
    coarse: Shooting,
    restarts: int,
    rng: np.random.Generator,
    given: np.ndarray | None,
) -> tuple[np.ndarray, bool, str]:
    """The best tape ``(K, m)`` found from ``restarts`` built-in initial tapes (and ``given``).

    Built-in tapes: zero, then a_j sin(2π c t/T + φ) for c = 1, 1.5, 2 cycles per horizon and four
    phases φ, then random a_j (A sin(2π c t/T + φ) + b) with A ~ U(0.2, 2), c ~ U(0.5, 3),
    φ ~ U(0, 2π), b ~ N(0, 1). The scale a_j = √(2 |J(0)| / (T m R_jj)) gives a tape a control cost
    comparable to the cost J(0) of doing nothing. Returns the tape, whether scipy's L-BFGS-B
    reported convergence, and its message.
    """
    m = fine.R.shape[0]
    K, K_coarse = len(fine.times) - 1, len(coarse.times) - 1
    horizon = fine.times[-1]
    zero = np.zeros((1, K_coarse, m))
    with np.errstate(all="ignore"):
        idle_cost = float(coarse.cost(zero, coarse.rollout(zero)[0])[0])
    amplitude = np.sqrt(2.0 * abs(idle_cost) / (horizon * m * np.diag(fine.R)))
    amplitude = np.where(
        np.isfinite(amplitude) & (amplitude > 0), amplitude, 1.0 / np.sqrt(np.diag(fine.R))
    )
    tapes = _initial_tapes(restarts, K_coarse, amplitude, rng)
    if given is not None:
        tapes = np.concatenate([tapes, _resample(given[None], K_coarse)])

    screened, screened_cost = _batched_lbfgs(
        coarse.values,
        coarse.values_and_gradients,
        tapes.reshape(len(tapes), -1),
        max_iter=_SCREEN_ITER,
    )
    best = _distinct_best(screened_cost, _N_REFINE)
    candidates = _resample(screened[best].reshape(-1, K_coarse, m), K)
    if given is not None:
        candidates = np.concatenate([candidates, given[None]])
    refined, refined_cost = _batched_lbfgs(
        fine.values,
        fine.values_and_gradients,
        candidates.reshape(len(candidates), -1),
        max_iter=_REFINE_ITER,
    )

    def objective(z: np.ndarray) -> tuple[float, np.ndarray]:
        J, G = fine.values_and_gradients(z[None])
        return float(J[0]), G[0]

    start = refined[np.argmin(refined_cost)]
    result = minimize(
        objective,
        start,
        jac=True,
        method="L-BFGS-B",
        options={"maxiter": 10000, "maxfun": 20000, "ftol": 1e-14, "gtol": 1e-9},
    )
    return result.x.reshape(K, m), bool(result.success), str(result.message)


def _initial_tapes(
    count: int, K: int, amplitude: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    """``count`` tapes ``(count, K, m)`` sampled at the interval midpoints (see ``multistart``)."""
    s = (np.arange(K) + 0.5) / K  # t / T
    m = amplitude.size
    tapes = [np.zeros((K, m))]
    tapes += [
        np.sin(2 * np.pi * c * s + p)[:, None] * amplitude
        for c in _PUMP_CYCLES
        for p in _PUMP_PHASES
    ]
    while len(tapes) < count:
        size = rng.uniform(0.2, 2.0, m)
        cycles = rng.uniform(0.5, 3.0, m)
        phase = rng.uniform(0.0, 2 * np.pi, m)
        offset = rng.normal(size=m)
        tapes.append(amplitude * (size * np.sin(2 * np.pi * cycles * s[:, None] + phase) + offset))
    return np.array(tapes[:count])


def _resample(U: np.ndarray, K: int) -> np.ndarray:
    """Piecewise-constant tapes ``(N, K_old, m)`` on K equal intervals (midpoint lookup)."""
    K_old = U.shape[1]
    return U[:, ((np.arange(K) + 0.5) * K_old / K).astype(int)]


def _distinct_best(costs: np.ndarray, count: int) -> np.ndarray:
    """Indices of the ``count`` lowest finite costs, skipping repeats of the same optimum."""
    chosen: list[int] = []
    for i in np.argsort(np.where(np.isfinite(costs), costs, np.inf)):
        if not np.isfinite(costs[i]) or len(chosen) == count:
            break
        if all(abs(costs[i] - costs[j]) > 1e-3 * max(1.0, abs(costs[j])) for j in chosen):
            chosen.append(int(i))
    return np.array(chosen or [0])


def _batched_lbfgs(
    value: Callable[[np.ndarray], np.ndarray],
    value_and_gradient: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    x0: np.ndarray,
    max_iter: int,
    memory: int = 10,
    ftol: float = 1e-10,
    gtol: float = 1e-8,
) -> tuple[np.ndarray, np.ndarray]:
    """Minimise N independent functions at once: L-BFGS, each with its own memory and step.

    ``value(x)`` maps points ``(P, n)`` to values ``(P,)`` (inf where undefined),
    ``value_and_gradient(x)`` adds the gradients ``(P, n)``. Calls are batched over all tapes
    still running, and the line search tries several step lengths per call (the first that
    satisfies Armijo's condition is taken), since a batched call costs little more than one.
    A pair with sᵀy ≤ 0 is not stored. Returns the final points and values.
    """
    x = x0.copy()
    N, n = x.shape
    f, g = value_and_gradient(x)
    S, Y = np.zeros((N, memory, n)), np.zeros((N, memory, n))
    rho = np.zeros((N, memory))  # 1/(sᵀy) per stored pair, 0 for an empty slot
    slot = np.zeros(N, dtype=int)
    running = np.isfinite(f)
    for _ in range(max_iter):
        live = np.flatnonzero(running)
        if live.size == 0:
            break
        direction = _two_loop(g[live], S[live], Y[live], rho[live], slot[live])
        slope = np.einsum("pn,pn->p", g[live], direction)
        uphill = slope >= 0
        direction[uphill] = -g[live][uphill]
        slope[uphill] = -np.einsum("pn,pn->p", g[live][uphill], g[live][uphill])
        step = np.full(live.size, np.nan)
        for first in _STEP_ROUNDS:
            pending = np.flatnonzero(np.isnan(step))
            if pending.size == 0:
                break
            trial_steps = first * _STEP_FACTORS  # (k,)
            trial = (
                x[live[pending], None] + trial_steps[None, :, None] * direction[pending, None]
            )  # (p, k, n)
            f_trial = value(trial.reshape(-1, n)).reshape(pending.size, -1)
            armijo = f_trial <= (
                f[live[pending], None] + 1e-4 * trial_steps[None] * slope[pending, None]
            )
            found = armijo.any(axis=1)
            step[pending[found]] = trial_steps[np.argmax(armijo[found], axis=1)]
        accepted = np.flatnonzero(~np.isnan(step))
        running[live[np.isnan(step)]] = False  # line search failed: stop where it is
        if accepted.size == 0:
            continue
        rows = live[accepted]
        x_new = x[rows] + step[accepted, None] * direction[accepted]
        f_new, g_new = value_and_gradient(x_new)
        ok = np.isfinite(f_new)
        running[rows[~ok]] = False
        rows, x_new, f_new, g_new = rows[ok], x_new[ok], f_new[ok], g_new[ok]
        s, y = x_new - x[rows], g_new - g[rows]
        sy = np.einsum("pn,pn->p", s, y)
        store = sy > 1e-12 * np.sqrt(np.einsum("pn,pn->p", s, s) * np.einsum("pn,pn->p", y, y))
        keep, cols = rows[store], slot[rows[store]] % memory
        S[keep, cols], Y[keep, cols], rho[keep, cols] = s[store], y[store], 1.0 / sy[store]
        slot[keep] += 1
        stalled = f[rows] - f_new <= ftol * np.maximum(1.0, np.abs(f_new))
        small = np.max(np.abs(g_new), axis=1) <= gtol
        x[rows], f[rows], g[rows] = x_new, f_new, g_new
        running[rows[stalled | small]] = False
    return x, f


def _two_loop(
    g: np.ndarray, S: np.ndarray, Y: np.ndarray, rho: np.ndarray, slot: np.ndarray
) -> np.ndarray:
    """−H g by the L-BFGS two-loop recursion, per row, with each row's stored pairs."""
    P, memory, _ = S.shape
    q = g.copy()
    alpha = np.zeros((P, memory))
    order = [(slot - 1 - i) % memory for i in range(memory)]  # newest first
    rows = np.arange(P)
    for i, col in enumerate(order):
        a = rho[rows, col] * np.einsum("pn,pn->p", S[rows, col], q)
        alpha[:, i] = a
        q -= a[:, None] * Y[rows, col]
    newest = order[0]
    yy = np.einsum("pn,pn->p", Y[rows, newest], Y[rows, newest])
    has_pair = rho[rows, newest] > 0
    gamma = np.where(
        has_pair,
        1.0 / np.where(has_pair, rho[rows, newest] * yy, 1.0),
        1.0 / np.maximum(np.linalg.norm(g, axis=1), 1e-300),
    )
    r = gamma[:, None] * q
    for i, col in reversed(list(enumerate(order))):
        b = rho[rows, col] * np.einsum("pn,pn->p", Y[rows, col], r)
        r += (alpha[:, i] - b)[:, None] * S[rows, col]
    return -r
