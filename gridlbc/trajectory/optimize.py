"""Locally optimal trajectories of a problem's deterministic limit.

:func:`optimize` minimises the RK4-discretised cost of :mod:`gridlbc.trajectory.shooting` over
piecewise-constant control tapes: a multi-start single-shooting search (batched L-BFGS on a
coarse tape, the best few refined on the full tape, the best converged by scipy's L-BFGS-B),
then polished by Gauss–Newton DDP (:mod:`gridlbc.trajectory.ddp`). The result is the best local
optimum found, not a certificate of the global one: more ``restarts`` search wider.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..problem import Problem
from .ddp import ilqr
from .shooting import Shooting, multistart


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A locally optimal open-loop solution of a problem's deterministic limit.

    Attributes
    ----------
    times : ndarray, shape (K+1,)
        t_k = k Δt, Δt = T/K.
    states : ndarray, shape (K+1, d)
        x_k from the RK4 recursion (angles are not wrapped).
    controls : ndarray, shape (K, m)
        u_k, held constant on [t_k, t_k+1).
    cost : float
        g(x_K) + Σ_k (q(x_k, t_k) + ½ u_kᵀ R u_k) Δt.
    problem : Problem
        The problem it was optimised for (its temperature plays no part).
    converged : bool
        Whether the DDP polish converged (or, without it, L-BFGS-B reported convergence).
    message : str
        What the optimiser reported.
    """

    times: np.ndarray
    states: np.ndarray
    controls: np.ndarray
    cost: float
    problem: Problem
    converged: bool = True
    message: str = ""


def timed_state_cost(problem: Problem):
    """The problem's state cost as q(x, t) on states ``(P, d)`` and times ``(P,)`` (or None)."""
    q = problem.state_cost
    if q is None:
        return None
    if getattr(q, "time_dependent", False):
        return q
    return lambda x, t: q(x)


def shooting_for(problem: Problem, x0: np.ndarray, n_intervals: int) -> Shooting:
    """The RK4 single-shooting model of ``problem`` from ``x0`` on ``n_intervals`` intervals."""
    return Shooting(
        problem.system,
        x0,
        problem.require_horizon("trajectory optimisation"),
        n_intervals,
        problem.require_terminal_cost("trajectory optimisation"),
        timed_state_cost(problem),
        problem.R,
    )


def optimize(
    problem: Problem,
    x0,
    restarts: int = 128,
    seed: int | None = 0,
    n_intervals: int = 300,
    initial_controls=None,
    screen_intervals: int = 60,
    polish: bool = True,
    search: bool = True,
) -> Trajectory:
    """Minimise g(x_K) + Σ_k (q(x_k, t_k) + ½ u_kᵀ R u_k) Δt over piecewise-constant tapes.

    Parameters
    ----------
    problem : Problem
        Dynamics ``problem.system`` (drift a, input matrix B), horizon T, terminal cost g, state
        cost q (may depend on time, :class:`gridlbc.costs.Tracking`) and control cost R. The
        temperature plays no part: this is the noise-free problem.
    x0 : array_like, shape (d,)
        Initial state.
    restarts : int
        How many built-in initial tapes to try (zero, sinusoidal pumping, random sinusoids with
        offsets; see :func:`gridlbc.trajectory.shooting.multistart`).
    seed : int or None
        Seed of the random tapes.
    n_intervals : int
        K; Δt = T/K, one RK4 step per interval.
    initial_controls : array_like, shape (K, m) or (K,) when m = 1, optional
        A tape to start from, in addition to the built-in ones.
    screen_intervals : int
        The tapes are first optimised together on this coarser tape (at most ``n_intervals``).
    polish : bool
        Finish with Gauss–Newton DDP (iLQR) from the best tape (kept only if it is cheaper).
    search : bool
        False: skip the multi-start search and only polish ``initial_controls`` by DDP (a local
        refinement, e.g. from a neighbouring start's optimum; much faster, and only as global as
        the tape it starts from).

    Returns
    -------
    Trajectory
        The best local optimum found.
    """
    x0, m = _check_problem(problem, x0)
    n_intervals = _positive_int("n_intervals", n_intervals)
    restarts = _positive_int("restarts", restarts)
    screen_intervals = min(_positive_int("screen_intervals", screen_intervals), n_intervals)
    given = None
    if initial_controls is not None:
        given = check_tape("initial_controls", initial_controls, m, n_intervals)
    fine = shooting_for(problem, x0, n_intervals)
    if search:
        coarse = shooting_for(problem, x0, screen_intervals)
        controls, converged, message = multistart(
            fine, coarse, restarts, np.random.default_rng(seed), given
        )
    elif given is None or not polish:
        raise ValueError(
            "search=False polishes initial_controls by DDP: give initial_controls "
            "and keep polish=True"
        )
    else:
        controls, converged, message = given, False, ""
    if polish:
        polished, iterations, ok = ilqr(fine, controls, problem.terminal_cost, problem.state_cost)
        if not search or _tape_cost(fine, polished) <= _tape_cost(fine, controls):
            controls, converged = polished, ok
            message = (
                f"DDP polish {'converged' if ok else 'stopped'} after {iterations} "
                "iterations "
                + (f"(from L-BFGS-B: {message})" if search else "from initial_controls (no search)")
            )
    with np.errstate(all="ignore"):
        states = fine.rollout(controls[None])[0][0]
    cost = _tape_cost(fine, controls)
    return Trajectory(
        times=fine.times.copy(),
        states=states,
        controls=controls,
        cost=cost,
        problem=problem,
        converged=converged and np.isfinite(cost),
        message=message,
    )


def tape_cost(problem: Problem, x0, controls) -> tuple[float, np.ndarray]:
    """J of one control tape from ``x0`` and its gradient ∂J/∂u_k by the discrete adjoint.

    Parameters
    ----------
    problem : Problem
        The (deterministic) problem.
    x0 : array_like (d,)
        The start state.
    controls : array_like (K, m) or (K,)
        The tape (``(K,)`` when m = 1), on K = ``len(controls)`` intervals of T/K.

    Returns
    -------
    J : float
        The cost; inf (and the gradient zero) if the rollout overflows.
    gradient : ndarray
        ∂J/∂u_k, shaped like ``controls``.
    """
    x0, m = _check_problem(problem, x0)
    U = check_tape("controls", controls, m)
    shooting = shooting_for(problem, x0, len(U))
    J, G = shooting.values_and_gradients(U.reshape(1, -1))
    return float(J[0]), G[0].reshape(np.shape(controls))


def _tape_cost(shooting: Shooting, U: np.ndarray) -> float:
    J = shooting.values(U.reshape(1, -1))[0]
    return float(J)


def _check_problem(problem: Problem, x0) -> tuple[np.ndarray, int]:
    """Validate the problem's callables on x0; return x0 ``(d,)`` and m."""
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a gridlbc.Problem, got {type(problem).__name__}")
    system = problem.system
    x0 = np.asarray(x0, dtype=float)
    d, m = system.state_dim, system.control_dim
    if x0.shape != (d,):
        raise ValueError(f"x0 must be one state, a vector of shape ({d},), got shape {x0.shape}")
    if not np.all(np.isfinite(x0)):
        raise ValueError(f"x0 must be finite, got {x0}")
    a = np.asarray(system.drift(x0[None]), dtype=float)
    B = np.asarray(system.input_matrix(x0[None]), dtype=float)
    if a.shape != (1, d) or B.shape != (1, d, m):
        raise ValueError(
            f"{type(system).__name__}.drift / .input_matrix must return shapes "
            f"(N, {d}) / (N, {d}, {m}), got {a.shape} / {B.shape}"
        )
    if np.shape(problem.require_terminal_cost("optimize")(x0[None])) != (1,):
        raise ValueError(f"terminal_cost must return shape (N,) for states (N, {d})")
    q = timed_state_cost(problem)
    if q is not None and np.shape(q(x0[None], np.zeros(1))) != (1,):
        raise ValueError(f"state_cost must return shape (N,) for states (N, {d})")
    return x0, m


def check_tape(name: str, controls, m: int, K: int | None = None) -> np.ndarray:
    """A finite control tape as a ``(K, m)`` array (a vector is accepted when m = 1)."""
    U = np.asarray(controls, dtype=float)
    if U.ndim == 1 and m == 1:
        U = U[:, None]
    rows = "K" if K is None else K
    if U.ndim != 2 or U.shape[1] != m or U.shape[0] < 1 or (K is not None and U.shape[0] != K):
        raise ValueError(
            f"{name} must have shape ({rows}, {m}) (intervals, controls), "
            f"got shape {np.shape(controls)}"
        )
    if not np.all(np.isfinite(U)):
        raise ValueError(f"{name} must be finite")
    return U


def _positive_int(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)
