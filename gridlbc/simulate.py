"""Monte-Carlo rollouts of a policy on the problem's SDE (paper §3.2).

Euler–Maruyama with step Δt = T/K on the Itô SDE

    dx = (a(x) + B(x) u) dt + √λ B(x) R^{−1/2} dW,      Cov[dξ] = λ B R⁻¹ Bᵀ dt,

i.e. x_{k+1} = x_k + (a(x_k) + B(x_k) u_k) Δt + √(λ Δt) B(x_k) C ε_k with C Cᵀ = R⁻¹ (Cholesky)
and ε_k ~ N(0, I_m), periodic coordinates wrapped after each step (into the grid's box, or into
[−π, π) for a grid-free problem). The noise B C ε needs no diagonal B R⁻¹ Bᵀ.

**Box edges.** ``boundary="free"`` (the default) lets the state cross a closed (non-periodic) edge
of the grid's box and go on: the SDE on Rᵈ. ``boundary="reflect"`` folds it back after each step,
x ← lo + L − |((x − lo) mod 2L) − L| with L = hi − lo, which lands in [lo, hi]: the
symmetrized Euler scheme of a diffusion reflected at the edge (Bossy, Gobet & Talay, J. Appl.
Probab. 41(3), 2004), the simulated counterpart of the solver's state constraint (SPEC §3: no
probability leaves the box). A state inside the box is left untouched, bit for bit. Each sample's
cost is the rectangle rule of the running cost plus the terminal cost,

    J = Σ_k ( q(x_k) + ½ u_kᵀ R u_k ) Δt + g(x_K),

whose sample mean estimates E[J]; for the optimal policy that is v(x₀, 0) = −λ log z(x₀, 0), up to
the O(Δt) bias of the scheme and the standard error σ/√n of the mean.

The policy and the drift are evaluated once per step for all samples (vectorised callables); the
per-sample update of state and cost is one numba kernel over the samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._numba import jit
from .costs import evaluate_cost
from .problem import Problem

DEFAULT_STEPS = 300
"""Euler–Maruyama steps over the horizon when ``dt`` is not given."""


@jit
def _em_kernel(x, drift, B, u, eps, noise, R, dt, x_out, cost, ito):
    """x_out = x + (a + B u) dt + B dε with dε = (noise ε); cost += ½ uᵀ R u dt and
    ito += uᵀ R dε (the Girsanov term of :func:`gridlbc.certify`), for every sample."""
    n, d = x.shape
    m = u.shape[1]
    for s in range(n):  # serial: a few flops per sample, threads would cost more
        kick = np.zeros(m)  # dε = √(λ dt) C ε
        for i in range(m):
            for j in range(m):
                kick[i] += noise[i, j] * eps[s, j]
        control = 0.0
        girsanov = 0.0
        for i in range(m):
            for j in range(m):
                control += u[s, i] * R[i, j] * u[s, j]
                girsanov += u[s, i] * R[i, j] * kick[j]
        cost[s] += 0.5 * control * dt
        ito[s] += girsanov
        for k in range(d):
            v = drift[s, k]
            w = 0.0
            for i in range(m):
                v += B[s, k, i] * u[s, i]
                w += B[s, k, i] * kick[i]
            x_out[s, k] = x[s, k] + v * dt + w


def em_step_numpy(x, drift, B, u, eps, noise, R, dt):
    """Plain-numpy version of the Euler–Maruyama kernel: (new states, ½ uᵀRu dt, uᵀR dε) per
    sample."""
    kick = eps @ noise.T
    x_new = x + (drift + np.einsum("ndm,nm->nd", B, u)) * dt + np.einsum("ndm,nm->nd", B, kick)
    return (
        x_new,
        0.5 * np.einsum("ni,ij,nj->n", u, R, u) * dt,
        np.einsum("ni,ij,nj->n", u, R, kick),
    )


@dataclass(frozen=True, eq=False)
class Rollouts:
    """Sampled trajectories of one policy and their costs.

    Attributes
    ----------
    times : ndarray (k,)
        0, Δt, …, T.
    states : ndarray (n, k, d)
        States at those times (periodic coordinates wrapped into the box).
    controls : ndarray (n, k − 1, m)
        The control applied on each step.
    costs : ndarray (n,)
        Realised cost per sample: Σ (q + ½ uᵀRu) Δt + g(x_T).
    terminal_costs : ndarray (n,)
        g(x_T) per sample (part of ``costs``).
    left_box : ndarray (n,) of bool
        Samples that crossed an edge of the grid's box on a non-periodic axis at some step (with
        ``boundary="free"`` they keep going, and a grid solution is clamped to the box there; with
        ``"reflect"`` they were folded back). All False for a grid-free problem (no box).
    seed : int or None
    boundary : str
        ``"free"`` or ``"reflect"`` (see the module docstring).
    """

    times: np.ndarray
    states: np.ndarray
    controls: np.ndarray
    costs: np.ndarray
    terminal_costs: np.ndarray
    left_box: np.ndarray
    seed: int | None
    boundary: str = "free"

    @property
    def n_samples(self) -> int:
        return self.costs.shape[0]

    @property
    def dt(self) -> float:
        return float(self.times[1] - self.times[0])

    @property
    def final_states(self) -> np.ndarray:
        """x_T per sample, shape ``(n, d)``."""
        return self.states[:, -1]

    @property
    def mean_cost(self) -> float:
        """The Monte-Carlo estimate of E[J]."""
        return float(self.costs.mean())

    @property
    def standard_error(self) -> float:
        """σ̂/√n of :attr:`mean_cost` (NaN for a single sample)."""
        n = self.n_samples
        return float(self.costs.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan

    @property
    def n_left_box(self) -> int:
        return int(self.left_box.sum())

    def summary(self) -> str:
        return (
            f"cost {self.mean_cost:.4g} ± {self.standard_error:.2g} (SE) over "
            f"{self.n_samples} samples, Δt = {self.dt:.3g}, {self.n_left_box} left the box"
        )


def check_sample_count(n_samples) -> int:
    """``n_samples`` as a positive int; a clear error otherwise.

    Parameters
    ----------
    n_samples : int
        How many sample paths.
    """
    if isinstance(n_samples, bool) or not isinstance(n_samples, (int, np.integer)):
        raise TypeError(f"n_samples must be an integer, got {n_samples!r}")
    if n_samples < 1:
        raise ValueError(f"n_samples must be at least 1, got {n_samples}")
    return int(n_samples)


def _initial_states(problem: Problem, x0, n_samples) -> np.ndarray:
    n_samples = check_sample_count(n_samples)
    x0 = problem.check_states(x0, "x0")
    if x0.shape[0] == 1:
        return np.repeat(x0, n_samples, axis=0)
    if x0.shape[0] != n_samples:
        raise ValueError(
            f"x0 has {x0.shape[0]} rows but n_samples = {n_samples}: give one start state (d,) "
            f"or one per sample (n_samples, d)"
        )
    return x0.copy()


def step_count(horizon: float, dt) -> int:
    """Euler–Maruyama steps over ``horizon`` for a step of about ``dt`` (``None``:
    :data:`DEFAULT_STEPS`).

    Parameters
    ----------
    horizon : float
        T.
    dt : float or None
        The largest step; the count is the fewest steps of at most it.
    """
    if dt is None:
        return DEFAULT_STEPS
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise TypeError(f"dt must be a number, got {dt!r}") from None
    if not (np.isfinite(dt) and 0 < dt <= horizon):
        raise ValueError(f"dt must lie in (0, T] = (0, {horizon:g}], got {dt}")
    return math.ceil(horizon / dt - 1e-9)


def _controls(policy, x: np.ndarray, t: float, m: int, step: int) -> np.ndarray:
    u = np.asarray(policy(x, t), dtype=float)
    if u.shape != (x.shape[0], m):
        raise ValueError(
            f"policy(x, t) must return controls of shape (N, m) = ({x.shape[0]}, {m}) for states "
            f"x of shape {x.shape}, got shape {u.shape}"
        )
    bad = ~np.all(np.isfinite(u), axis=1)
    if np.any(bad):
        raise ValueError(
            f"policy returned non-finite controls for {int(bad.sum())} of {x.shape[0]} samples at "
            f"t = {t:g} (step {step}), first at x = {x[np.argmax(bad)]}: a grid policy is undefined "
            "where the desirability underflowed (see UnderflowWarning)"
        )
    return u


def simulate(
    problem: Problem,
    policy,
    x0,
    n_samples: int = 1,
    dt: float | None = None,
    seed: int | None = None,
    noise: bool = True,
    boundary: str = "free",
) -> Rollouts:
    """Roll out ``policy`` on the SDE of ``problem`` and accumulate each sample's cost.

    Parameters
    ----------
    problem : Problem
        Dynamics, costs (q, R, g), temperature λ (the noise level) and horizon T.
    policy : callable
        ``policy(x, t)`` → controls ``(N, m)`` for states ``(N, d)``: a Solution's or combination's
        ``.policy``, or any controller of your own.
    x0 : array_like (d,) or (n_samples, d)
        Start state(s).
    n_samples : int
        Number of independent samples.
    dt : float, optional
        Euler–Maruyama step, rounded down to divide T. Default T / 300 (:data:`DEFAULT_STEPS`).
        The scheme's weak error is O(Δt) with a problem-dependent constant, large where the
        dynamics are fast (the README's swing-up tables are rolled out at Δt = 0.002). Pass a
        smaller ``dt`` when a cost must be checked to a few percent.
    seed : int, optional
        Seed of ``np.random.default_rng``: the same seed gives the same rollouts.
    noise : bool
        False: the deterministic closed loop (ε = 0).
    boundary : {"free", "reflect"}
        At a closed (non-periodic) edge of the grid's box: ``"free"`` lets the state leave the box
        (the SDE on Rᵈ); ``"reflect"`` folds it back in after each step (the solver's reflecting
        state constraint, SPEC §3). A problem without a grid has no box: ``"free"`` only.

    Returns
    -------
    Rollouts
    """
    check_problem_and_policy(problem, policy)
    x = _initial_states(problem, x0, n_samples)
    K = step_count(problem.require_horizon("simulate"), dt)
    n, d, m = x.shape[0], problem.system.state_dim, problem.system.control_dim
    states = np.empty((n, K + 1, d))
    controls = np.empty((n, K, m))

    def record(k, x_new, u):
        states[:, k + 1] = x_new
        controls[:, k] = u

    path = euler_maruyama(
        problem, policy, x, K, np.random.default_rng(seed), noise, record, boundary
    )
    states[:, 0] = path.start
    costs = path.running_cost + path.terminal_cost
    return Rollouts(
        path.times, states, controls, costs, path.terminal_cost, path.left_box, seed, boundary
    )


BOUNDARIES = ("free", "reflect")
"""What the rollouts do at a closed edge of the grid's box (see the module docstring)."""


def check_boundary(problem: Problem, boundary) -> str:
    """``boundary`` if it is one of :data:`BOUNDARIES` and the problem has a box for it.

    Parameters
    ----------
    problem : Problem
        Its grid (if any) is the box.
    boundary : str
        ``"free"`` or ``"reflect"``.
    """
    if boundary not in BOUNDARIES:
        raise ValueError(f"boundary must be one of {BOUNDARIES}, got {boundary!r}")
    if boundary == "reflect" and problem.grid is None:
        raise ValueError(
            'boundary="reflect" needs the problem\'s grid (its box); a problem without a grid has '
            'no edges: use boundary="free"'
        )
    return boundary


def reflect_into_box(x: np.ndarray, lo: np.ndarray, hi: np.ndarray, closed: np.ndarray):
    """Fold the coordinates ``closed`` of states ``x`` (n, d) back into [lo, hi], in place, by
    mirroring at the edges (as often as needed); states inside are untouched.

    Parameters
    ----------
    x : ndarray (n, d)
        States; changed in place.
    lo, hi : ndarray (d,)
        The box.
    closed : ndarray (d,) of bool
        The axes to fold (the non-periodic ones).
    """
    for k in np.flatnonzero(closed):
        out = (x[:, k] < lo[k]) | (x[:, k] > hi[k])
        if np.any(out):
            width = hi[k] - lo[k]
            y = np.mod(x[out, k] - lo[k], 2 * width)
            x[out, k] = lo[k] + np.where(y > width, 2 * width - y, y)
    return x


def check_problem_and_policy(problem, policy) -> None:
    """A clear error unless ``problem`` is a :class:`gridlbc.Problem` and ``policy`` callable.

    Parameters
    ----------
    problem : Problem
        What is simulated.
    policy : callable
        ``policy(x, t)``.
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a gridlbc.Problem, got {type(problem).__name__}")
    if not callable(policy):
        raise TypeError("policy must be callable as policy(x, t) -> (N, m), e.g. solution.policy")


@dataclass(frozen=True, eq=False)
class SamplePaths:
    """What one Euler–Maruyama run accumulates per sample (see :func:`euler_maruyama`)."""

    times: np.ndarray
    start: np.ndarray  # x₀ wrapped into the box, (n, d)
    running_cost: np.ndarray  # Σ (q + ½ uᵀRu) Δt
    final_states: np.ndarray  # x_K, (n, d)
    terminal_cost: np.ndarray  # g(x_K)
    ito: np.ndarray  # Σ uᵀR dε
    left_box: np.ndarray


def euler_maruyama(
    problem: Problem,
    policy,
    x: np.ndarray,
    n_steps: int,
    rng,
    noise: bool = True,
    on_step=None,
    boundary: str = "free",
) -> SamplePaths:
    """Run the Euler–Maruyama loop shared by :func:`simulate` and :func:`gridlbc.certify`.

    Parameters
    ----------
    problem : Problem
        The SDE and the costs.
    policy : callable
        ``policy(x, t)`` → ``(N, m)``.
    x : ndarray (n, d)
        The start states, one per sample.
    n_steps : int
        Steps over the horizon (:func:`step_count`).
    rng : numpy.random.Generator
        Draws the noise.
    noise : bool
        Whether to add it.
    on_step : callable, optional
        ``on_step(k, x_{k+1}, u_k)``, called after each step (recording, progress).
    boundary : {"free", "reflect"}
        At closed edges of the grid's box (see :func:`simulate`).

    Returns
    -------
    SamplePaths
    """
    reflect = check_boundary(problem, boundary) == "reflect"
    T = problem.require_horizon("simulate")
    step = T / n_steps
    grid, system = problem.grid, problem.system
    n, m = x.shape[0], system.control_dim
    R = np.ascontiguousarray(problem.R)
    root = np.linalg.cholesky(problem.R_inv) * math.sqrt(problem.temperature * step)

    running = np.zeros(n)
    ito = np.zeros(n)
    left = np.zeros(n, dtype=bool)
    x = problem.wrap(x)
    start = x
    eps = np.zeros((n, m))
    for k in range(n_steps):
        t = k * step
        u = _controls(policy, x, t, m, k)
        drift = np.ascontiguousarray(system.drift(x), dtype=float)
        B = np.ascontiguousarray(system.input_matrix(x), dtype=float)
        if problem.state_cost is not None:
            running += problem.state_cost_values(x, t) * step
        if noise:
            eps = rng.standard_normal((n, m))
        x_new = np.empty_like(x)
        _em_kernel(x, drift, B, u, eps, root, R, step, x_new, running, ito)
        x = problem.wrap(x_new)
        if grid is not None:
            left |= np.any(((x < grid.lo) | (x > grid.hi)) & ~grid.periodic, axis=1)
            if reflect:
                reflect_into_box(x, grid.lo, grid.hi, ~grid.periodic)
        if on_step is not None:
            on_step(k, x, u)
    terminal = evaluate_cost(problem.terminal_cost, x, "terminal_cost")
    times = np.arange(n_steps + 1) * step
    times[-1] = T
    return SamplePaths(times, start, running, x, terminal, ito, left)
