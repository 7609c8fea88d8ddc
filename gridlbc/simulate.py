"""Monte-Carlo rollouts of a policy on the problem's SDE (paper §3.2).

Euler–Maruyama with step Δt = T/K on the Itô SDE

    dx = (a(x) + B(x) u) dt + √λ B(x) R^{−1/2} dW,      Cov[dξ] = λ B R⁻¹ Bᵀ dt,

i.e. x_{k+1} = x_k + (a(x_k) + B(x_k) u_k) Δt + √(λ Δt) B(x_k) C ε_k with C Cᵀ = R⁻¹ (Cholesky)
and ε_k ~ N(0, I_m), periodic coordinates wrapped after each step (into the grid's box, or into
[−π, π) for a grid-free problem). The noise B C ε needs no diagonal B R⁻¹ Bᵀ.

**Box edges.** By default (``boundary=None``) the rollouts treat the box as the solver does:
``"reflect"`` when the problem's grid has a closed (non-periodic) axis, ``"free"`` for a problem
without a grid (no box). ``boundary="free"`` lets the state cross a closed edge of the grid's box
and go on: the SDE on Rᵈ. ``boundary="reflect"`` folds it back after each step,
x ← lo + L − |((x − lo) mod 2L) − L| with L = hi − lo, which lands in [lo, hi]: the
symmetrized Euler scheme of a diffusion reflected at the edge (Bossy, Gobet & Talay, J. Appl.
Probab. 41(3), 2004), the simulated counterpart of the solver's state constraint (SPEC §3: no
probability leaves the box). A state inside the box is left untouched, bit for bit. Each sample's
cost is the rectangle rule of the running cost plus the terminal cost,

    J = Σ_k ( q(x_k) + ½ u_kᵀ R u_k ) Δt + g(x_K),

whose sample mean estimates E[J]; for the optimal policy that is v(x₀, 0) = −λ log z(x₀, 0), up to
the O(Δt) bias of the scheme and the standard error σ/√n of the mean.

**Tasks that end** (SPEC §9). With an exit set E a sample stops at τ, the first step that lands
in E, and pays g_E(x_τ) there in place of g(x_T); a sample that starts in E pays g_E(x₀) and
never moves. The paths run to min(τ, T), or to ``max_time`` for a first-exit problem without a
horizon, where a sample that has not exited pays what it has accrued so far (truncated:
:attr:`Rollouts.n_unexited` counts them). Checked at the steps only, a path that enters E
between two steps and leaves again would be missed, an O(√Δt) bias. Where the region knows its
geometry (the shapes of :mod:`gridlbc.regions`) the step also ends the sample with the
probability that the Brownian bridge between its two states crossed into E,

    p = exp(−2 d₀ d₁ / (σₙ² Δt)),

d₀, d₁ the distances of the two states from E and σₙ² = nᵀ λ B R⁻¹ Bᵀ n the noise's variance
along the outward normal n at the first (exact for a flat boundary and constant coefficients; the
bias is then O(Δt)); it pays g_E at the point of E nearest to the second state. The tangent plane
of a curved boundary is not E: where that probability exceeds :data:`BRIDGE_REFINE`, the
bridge's midpoint is drawn (a stop if it lies in E) and each half judged the same way, until the
crossing is implausible or the boundary one plane (at most :data:`BRIDGE_LEVELS` times), so that
the plane is taken over a fraction of the step only. Each part of a union is judged so, and a
step within reach of two parts is halved too, as is a step whose straight segment meets E (the
bridge's mean path, and the whole path along axes without noise, where a set thinner than a
step is crossed with both ends outside it and no noise across its boundary). The bridge between
two states does not depend on the drift, so this randomised stopping rule is the same under the
controlled and the passive process and :func:`gridlbc.certify`'s weight stays exact.

The policy and the drift are evaluated once per step for all samples (vectorised callables); the
per-sample update of state and cost is one numba kernel over the samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._numba import jit
from .costs import evaluate_cost, wrap_difference
from .problem import Problem, positive_float
from .regions import boundary_parts, has_geometry, part_distances, part_segments

DEFAULT_STEPS = 300
"""Euler–Maruyama steps over the horizon when ``dt`` is not given."""


@jit
def em_kernel(x, drift, B, u, eps, noise, R, dt, x_out, cost, ito):
    """x_out = x + (a + B u) dt + B dε with dε = (noise ε); cost += ½ uᵀ R u dt and
    ito += uᵀ R dε (the Girsanov term of :func:`gridlbc.certify`), for every sample."""
    n, d = x.shape
    m = u.shape[1]
    kick = np.empty(m)  # dε = √(λ dt) C ε, of each sample in turn
    for s in range(n):  # serial: a few flops per sample, threads would cost more
        kick[:] = 0.0
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
        Realised cost per sample: Σ (q + ½ uᵀRu) Δt + g(x_T), or up to τ + g_E(x_τ) for a sample
        that reached the exit set.
    terminal_costs : ndarray (n,)
        g(x_T) or g_E(x_τ) per sample (part of ``costs``); 0 for a sample of a problem without a
        horizon that had not exited.
    left_box : ndarray (n,) of bool
        Samples that crossed an edge of the grid's box on a non-periodic axis at some step (with
        ``boundary="free"`` they keep going, and a grid solution is clamped to the box there; with
        ``"reflect"`` they were folded back). All False for a grid-free problem (no box).
    seed : int or None
    boundary : str
        ``"free"`` or ``"reflect"``, as resolved (see the module docstring).
    exit_times : ndarray (n,) or None
        With an exit set: τ per sample (0 for a start in E), NaN where it had not exited by the
        end; None without one. After τ a sample's state stays where it entered E.
    """

    times: np.ndarray
    states: np.ndarray
    controls: np.ndarray
    costs: np.ndarray
    terminal_costs: np.ndarray
    left_box: np.ndarray
    seed: int | None
    boundary: str = "free"
    exit_times: np.ndarray | None = None

    @property
    def n_unexited(self) -> int:
        """Samples of a first-exit problem that had not reached the exit set by the end (0
        without an exit set)."""
        return 0 if self.exit_times is None else int(np.isnan(self.exit_times).sum())

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
        ending = "" if self.exit_times is None else f", {self.n_unexited} had not exited"
        return (
            f"cost {self.mean_cost:.4g} ± {self.standard_error:.2g} (SE) over "
            f"{self.n_samples} samples, Δt = {self.dt:.3g}, {self.n_left_box} left the box"
            f"{ending}"
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
    :data:`~gridlbc.simulate.DEFAULT_STEPS`).

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


def rollout_horizon(problem: Problem, max_time, dt=None) -> float:
    """How long the rollouts of ``problem`` run: its horizon T, or ``max_time`` for a problem
    without one (first exit: the cap on τ; average cost: the averaging time).

    Parameters
    ----------
    problem : Problem
        The problem.
    max_time : float or None
        Given for (and only for) a problem without a horizon.
    dt : float or None
        The step asked for. A problem without a horizon needs one: ``max_time`` is only a cap,
        so the default T / :data:`~gridlbc.simulate.DEFAULT_STEPS` would tie the step to it (30 s
        gives 0.1 s steps, coarse enough to swing a pendulum up by integration error alone).
    """
    if problem.stationary:
        if max_time is None:
            raise ValueError(
                "this problem has no horizon: give max_time, the time at which rollouts stop "
                "(for first exit, well beyond the typical time to reach the exit set: samples "
                "still running then are reported as not exited)"
            )
        if dt is None:
            raise ValueError(
                "this problem has no horizon: give dt, the Euler–Maruyama step, explicitly "
                "(max_time is only a cap, so a default of max_time / "
                f"{DEFAULT_STEPS} would tie the step to it); pick it for the dynamics' fastest "
                "time scale and check it by halving it (certify: richardson=True)"
            )
        return positive_float("max_time", max_time)
    if max_time is not None:
        raise TypeError(
            f"max_time caps a problem without a horizon; this one ends at T = {problem.horizon:g}"
        )
    return problem.require_horizon("simulate")


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
            "where the desirability underflowed (see UnderflowWarning), and a combination's "
            "where negative weights make Σ w_i z_i negative (see its warning)"
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
    boundary: str | None = None,
    max_time: float | None = None,
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
        Euler–Maruyama step, rounded down to divide T. Default T / 300
        (:data:`~gridlbc.simulate.DEFAULT_STEPS`); required for a problem without a horizon
        (``max_time`` is only a cap). The scheme's weak error is O(Δt) with a problem-dependent
        constant, large where the dynamics are fast (the README's swing-up tables are rolled out at
        Δt = 0.002). Pass a smaller ``dt`` when a cost must be checked to a few percent.
    seed : int, optional
        Seed of ``np.random.default_rng``: the same seed gives the same rollouts.
    noise : bool
        False: the deterministic closed loop (ε = 0).
    boundary : {"free", "reflect"}, optional
        At a closed (non-periodic) edge of the grid's box: ``"free"`` lets the state leave the box
        (the SDE on Rᵈ); ``"reflect"`` folds it back in after each step (the solver's reflecting
        state constraint, SPEC §3). None (default): as the solver, ``"reflect"`` when the grid has
        a closed axis, ``"free"`` otherwise (:func:`~gridlbc.simulate.resolve_boundary`). A problem
        without a grid has no box: ``"free"`` only.
    max_time : float, optional
        For a problem without a horizon (required there): the rollouts stop at this time
        (first exit: the samples that had not exited are counted in ``n_unexited``).

    Returns
    -------
    Rollouts
    """
    check_problem_and_policy(problem, policy)
    boundary = resolve_boundary(problem, boundary)
    x = _initial_states(problem, x0, n_samples)
    T = rollout_horizon(problem, max_time, dt)
    K = step_count(T, dt)
    n, d, m = x.shape[0], problem.system.state_dim, problem.system.control_dim
    states = np.empty((n, K + 1, d))
    controls = np.empty((n, K, m))

    def record(k, x_new, u):
        states[:, k + 1] = x_new
        controls[:, k] = u

    path = euler_maruyama(
        problem, policy, x, K, np.random.default_rng(seed), noise, record, boundary, T
    )
    states[:, 0] = path.start
    costs = path.running_cost + path.terminal_cost
    return Rollouts(
        path.times,
        states,
        controls,
        costs,
        path.terminal_cost,
        path.left_box,
        seed,
        boundary,
        path.exit_times,
    )


BOUNDARIES = ("free", "reflect")
"""What the rollouts do at a closed edge of the grid's box (see the module docstring)."""


def resolve_boundary(problem: Problem, boundary=None) -> str:
    """``boundary`` checked (:func:`check_boundary`), or for None the problem's own: ``"reflect"``
    when its grid has a closed (non-periodic) axis, as the solver treats it (SPEC §3), ``"free"``
    when it has no grid (no box) or only periodic axes (no edges).

    Parameters
    ----------
    problem : Problem
        Its grid (if any) is the box.
    boundary : str, optional
        ``"free"``, ``"reflect"`` or None.
    """
    if boundary is None:
        grid = problem.grid
        return "reflect" if grid is not None and not np.all(grid.periodic) else "free"
    return check_boundary(problem, boundary)


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
    fold_kernel(x, lo, hi, np.asarray(closed, dtype=bool), np.ones(x.shape[0], dtype=bool))
    return x


@jit
def fold_kernel(x, lo, hi, closed, rows):
    """x_k ← lo + L − abs(((x_k − lo) mod 2L) − L), L = hi − lo, for the coordinates outside
    [lo, hi] on the ``closed`` axes of the samples where ``rows`` is True, in place
    (:func:`reflect_into_box`)."""
    n, d = x.shape
    for s in range(n):
        if not rows[s]:
            continue
        for k in range(d):
            if closed[k] and (x[s, k] < lo[k] or x[s, k] > hi[k]):
                width = hi[k] - lo[k]
                y = (x[s, k] - lo[k]) % (2.0 * width)
                x[s, k] = lo[k] + (2.0 * width - y if y > width else y)


@jit
def wrap_kernel(x, lo, hi, periodic, outside):
    """x_k ← lo + (x_k − lo) mod (hi − lo) on the ``periodic`` axes (into [lo, hi), as
    :meth:`gridlbc.Grid.wrap`), and ``outside[s]`` set where a closed coordinate of sample s lies
    outside [lo, hi], in place."""
    n, d = x.shape
    for s in range(n):
        for k in range(d):
            if periodic[k]:
                x[s, k] = lo[k] + (x[s, k] - lo[k]) % (hi[k] - lo[k])
            elif x[s, k] < lo[k] or x[s, k] > hi[k]:
                outside[s] = True


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
    exit_times: np.ndarray | None = None  # τ, NaN where not exited; None without an exit set
    log_likelihoods: np.ndarray | None = None  # log dQ_j/dP per scored policy j, (n, J)
    integral: np.ndarray | None = None  # Σ r(x_k, t_k) Δt up to τ for an ``integrand`` r


def euler_maruyama(
    problem: Problem,
    policy,
    x: np.ndarray,
    n_steps: int,
    rng,
    noise: bool = True,
    on_step=None,
    boundary: str | None = None,
    horizon: float | None = None,
    scored=(),
    integrand=None,
    costs: bool = True,
) -> SamplePaths:
    """Run the Euler–Maruyama loop shared by :func:`~gridlbc.simulate` and :func:`gridlbc.certify`.

    With an exit set a sample stops on the first step that lands in it (module docstring): its
    state, costs and Girsanov term are frozen from then on, and its control is recorded as 0.

    For each policy u_j in ``scored`` the log-likelihood ratio of the chain driven by u_j to the
    passive chain (u = 0), at the path drawn, is accumulated step by step (up to τ):

        log dQ_j/dP = Σ_k ( u_jᵀ R dε'_k − ½ u_jᵀ R u_j Δt ) / λ,    dε'_k = u Δt + dε_k,

    dε' being the passive chain's noise that produces the same step (u the sampling policy's
    control, dε its noise). For u_j = u this is (Σ uᵀR dε + ½ Σ uᵀRu Δt)/λ, the inverse of the
    Girsanov factor of :func:`gridlbc.certify`; the folds at reflecting edges and the stopping
    rule are functions of the path and cancel from every ratio (:mod:`gridlbc.certificate`).

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
    boundary : {"free", "reflect"}, optional
        At closed edges of the grid's box (see :func:`~gridlbc.simulate`;
        None: :func:`~gridlbc.simulate.resolve_boundary`).
    horizon : float, optional
        How long the paths run (:func:`rollout_horizon`; default the problem's T).
    scored : sequence of callables
        Policies whose log-likelihood ratios to the passive chain are accumulated
        (:attr:`SamplePaths.log_likelihoods`, one column each; a policy that *is* ``policy``
        reuses its controls). Requires ``noise``.
    integrand : callable, optional
        ``r(x, t)`` → ``(N,)`` (or ``(N, k)``: k rates, one integral each) for the running
        samples' states ``(N, d)``, summed per sample as the state cost is (rectangle rule, up
        to τ) into :attr:`SamplePaths.integral`; called
        each step right after ``policy``, at the same states. Its values are not checked (they
        may be negative or NaN).
    costs : bool
        Whether to charge the problem's state, terminal and exit costs (False: ``running_cost``
        holds the control cost alone and ``terminal_cost`` zeros; the paths, their exit times
        and ``integral`` are the same).

    Returns
    -------
    SamplePaths
    """
    reflect = resolve_boundary(problem, boundary) == "reflect"
    T = problem.require_horizon("simulate") if horizon is None else horizon
    step = T / n_steps
    grid, system = problem.grid, problem.system
    n, m = x.shape[0], system.control_dim
    R = np.ascontiguousarray(problem.R)
    root = np.linalg.cholesky(problem.R_inv) * math.sqrt(problem.temperature * step)

    running = np.zeros(n)
    ito = np.zeros(n)
    left = np.zeros(n, dtype=bool)
    x = np.array(problem.wrap(x), dtype=float)  # a copy: the loop updates it in place
    start = x.copy()
    end_cost = np.zeros(n)
    exits = _Exits(problem, x, end_cost if costs else None) if problem.exit is not None else None
    eps = np.zeros((n, m))
    scored = tuple(scored)
    log_likelihoods = np.zeros((n, len(scored))) if scored else None
    integral: np.ndarray | None = None if integrand is None else np.zeros(n)
    if grid is not None:  # the box, as the kernels read it
        lo, hi, periodic = grid.lo, grid.hi, grid.periodic
    for k in range(n_steps):
        t = k * step
        if noise:
            eps = rng.standard_normal((n, m))  # for every sample: the draws do not depend on τ
        # the samples still running: all of them (a view) without an exit set
        alive = slice(None) if exits is None else exits.alive.copy()
        x_a = x[alive]
        u = np.zeros((n, m))  # a stopped sample's control is 0 (replaced by u_a without exits)
        if x_a.shape[0]:
            u_a = _controls(policy, x_a, t, m, k)
            drift = np.ascontiguousarray(system.drift(x_a), dtype=float)
            B = np.ascontiguousarray(system.input_matrix(x_a), dtype=float)
            running_a, ito_a = running[alive], ito[alive]
            if integral is not None:
                r = np.asarray(integrand(x_a, t), dtype=float) * step
                if r.ndim == 2 and integral.ndim == 1:  # several rates: one integral each
                    integral = np.zeros((n, r.shape[1]))
                integral[alive] += r
            if costs and problem.state_cost is not None:  # as it is between the nodes (signed)
                running_a += problem.state_cost_values(x_a, t, signed=True) * step
            x_new = np.empty_like(x_a)
            eps_a = np.ascontiguousarray(eps[alive])
            em_kernel(x_a, drift, B, u_a, eps_a, root, R, step, x_new, running_a, ito_a)
            if log_likelihoods is not None:
                passive_noise = u_a * step + eps_a @ root.T  # dε' = u Δt + dε
                for j, other in enumerate(scored):
                    u_j = u_a if other is policy else _controls(other, x_a, t, m, k)
                    log_likelihoods[alive, j] += (
                        np.einsum("ni,ij,nj->n", u_j, R, passive_noise - 0.5 * step * u_j)
                        / problem.temperature
                    )
            if exits is None:  # views of the whole arrays: nothing to put back
                u = u_a
            else:
                running[alive], ito[alive], u[alive] = running_a, ito_a, u_a
            outside = np.zeros(len(x_new), dtype=bool)
            if grid is None:
                x_new = problem.wrap(x_new)
            else:
                wrap_kernel(x_new, lo, hi, periodic, outside)
                left[alive] |= outside
            still = np.ones(len(x_new), dtype=bool)
            if exits is not None:  # before any fold: a step into an exit set beyond an edge ends
                folded = outside if reflect else None
                spread = None  # the bridge's noise, B C √(λ Δt) (none: its straight part)
                if exits.parts:
                    spread = B @ root if noise else np.zeros_like(B)
                exits.step(x_a, x_new, spread, (k + 1) * step, rng, folded)
                still = exits.alive[alive]
            if reflect and grid is not None and outside.any():
                fold_kernel(x_new, lo, hi, ~periodic, still)
            x[alive] = x_new
        if on_step is not None:
            on_step(k, x, u)
    running_at_end = slice(None) if exits is None else exits.alive
    if costs and not problem.stationary:  # the samples still running at T pay g(x_T)
        end_cost[running_at_end] = evaluate_cost(
            problem.require_terminal_cost("simulate"), x[running_at_end], "terminal_cost"
        )
    times = np.arange(n_steps + 1) * step
    times[-1] = T
    exit_times = None if exits is None else exits.times
    return SamplePaths(
        times, start, running, x, end_cost, ito, left, exit_times, log_likelihoods, integral
    )


BRIDGE_LEVELS = 30
"""The most halvings of a step's Brownian bridge where a crossing into a shaped exit set is
plausible (:data:`BRIDGE_REFINE`). Halving stops sooner, where a crossing of the tangent plane
becomes implausible or the boundary is one plane; this only bounds the depth (a step split 2³⁰
times) for a path that ends next to E. A fixed depth is not enough: the depth a boundary needs
grows with the noise a step carries along it against the boundary's curvature (docs page
:doc:`first_exit`, "The rule is exact for a flat boundary")."""

BRIDGE_REFINE = 1e-4
"""Above this flat-boundary crossing probability a step's bridge is halved
(:data:`BRIDGE_LEVELS`): below it a crossing is rare enough that the rule's error for a curved
boundary, a fraction of it, is left."""


PLANE = 1e-9
"""Two normals whose dot product is within this of 1, and two boundary points this close to one
plane (relative to the distances), are one plane: a flat face, whose bridge is not halved."""


class _Exits:
    """Which samples have reached the exit set, when, and the exit cost they paid (into
    ``end_cost``; not charged where it is None); the bridge crossing where the region knows its
    geometry (module docstring), each state's distance from E found once (a step's end is the
    next one's start)."""

    def __init__(self, problem: Problem, x: np.ndarray, end_cost: np.ndarray | None):
        self.problem, self.end_cost = problem, end_cost
        geometric = has_geometry(problem.exit)
        self.parts = boundary_parts(problem.exit) if geometric else ()
        self.alive = np.ones(x.shape[0], dtype=bool)
        self.times = np.full(x.shape[0], np.nan)
        # each sample's distance from each part of E and the outward normal there, at its
        # current state (NaN: not yet found)
        self.distance = np.full((x.shape[0], len(self.parts)), np.nan)
        self.normal = np.empty((x.shape[0], len(self.parts), x.shape[1]))
        self._stop(np.arange(x.shape[0]), self.problem.exit_mask(x), x, 0.0)

    def step(self, before, after, noise_factor, t: float, rng, folded=None) -> None:
        """Stop the running samples (in order, ``before`` → ``after``, both ``(n_alive, d)``)
        that entered E during the step ending at ``t``; ``noise_factor`` ``(n_alive, d, m)`` is
        B C √(λ Δt) with C Cᵀ = R⁻¹ (zeros without noise; None: no bridge). ``folded``
        ``(n_alive,)``: the samples whose ``after`` a reflecting edge moves next (their distance
        from E is found again at the next step)."""
        running = np.flatnonzero(self.alive)
        entered = self.problem.exit_mask(after)
        where = after
        if self.parts and noise_factor is not None:
            draws = rng.random(len(running))
            out = np.flatnonzero(~entered)
            ids = running[out]
            d0, normal = self.distance[ids], self.normal[ids]
            unknown = np.isnan(d0[:, 0])
            if unknown.any():
                d0[unknown], normal[unknown] = part_distances(self.parts, before[out[unknown]])
            d1, normal1 = part_distances(self.parts, after[out])
            self.distance[ids], self.normal[ids] = d1, normal1
            if folded is not None:
                self.distance[ids[folded[out]]] = np.nan
            crossed, reached = self._bridge(
                before[out], after[out], (d0, normal), (d1, normal1), noise_factor[out],
                draws[out], rng, BRIDGE_LEVELS,
            )  # fmt: skip
            if crossed.any():
                where = after.copy()
                hit = out[crossed]
                where[hit] = reached[crossed]
                entered[hit] = True
        self._stop(running, entered, where, t)

    def _bridge(self, a, b, start, end, factor, draws, rng, levels: int):
        """Which steps a → b (``(n, d)``, both ends outside E, ``start`` and ``end`` their
        distances ``(n, K)`` and outward normals ``(n, K, d)`` from each of E's K parts,
        :func:`~gridlbc.regions.part_distances`) the Brownian bridge between the two ends
        crosses into E, and a point of E for each that does: the flat-boundary probability
        p = exp(−2 d_a d_b / σₙ²) of each part (module docstring), combined by :meth:`_judge`,
        against the uniform ``draws``; where :meth:`_judge` asks and ``levels`` remain, the
        bridge's midpoint is drawn instead (mean (a + b)/2, noise ``factor``/2) and, outside E,
        each half is judged the same way with the noise ``factor``/√2. The
        tangent plane at the nearest point of a convex E holds E, so the flat rule over-counts
        crossings of a curved boundary, and a certificate of a first exit into a ball is then
        far low (stranger round 34's ball: docs page :doc:`validating`, "An interval", and
        :doc:`first_exit`, "The rule is exact for a flat boundary"); each halving shrinks the
        step against the curvature.

        The halves are judged level by level, all of a level's at once (one batch of draws per
        level: a bridge halved six times costs six batches, not up to 2⁶ − 1 calls), and a
        halved step takes its first half's crossing point where both halves cross."""
        crossed, reached, split = self._judge(a, b, start, end, factor, draws, levels > 0)
        tree = []  # per level: the steps halved, their midpoints, those outside E, their halves
        where = np.flatnonzero(split)
        ends = (a, b, *start, *end, factor)  # a, b, d_a, n_a, d_b, n_b, factor of each step
        for level in range(levels, 0, -1):
            if not len(where):
                break
            a, b, d_a, n_a, d_b, n_b, factor = (column[where] for column in ends)
            step = wrap_difference(b - a, self.problem.periods)
            noise = np.einsum("ndm,nm->nd", factor, rng.standard_normal((len(a), factor.shape[2])))
            middle = self.problem.wrap(a + 0.5 * step + 0.5 * noise)
            rest = np.flatnonzero(~self.problem.exit_mask(middle))  # a midpoint in E: crossed
            d_m, n_m = np.zeros((0, len(self.parts))), np.zeros((0, *n_a.shape[1:]))
            if len(rest):
                d_m, n_m = part_distances(self.parts, middle[rest])
            half = factor[rest] / math.sqrt(2.0)
            # the first halves, then the second halves, of the steps whose midpoint is outside E
            ends = tuple(
                np.concatenate(pair)
                for pair in (
                    (a[rest], middle[rest]), (middle[rest], b[rest]), (d_a[rest], d_m),
                    (n_a[rest], n_m), (d_m, d_b[rest]), (n_m, n_b[rest]), (half, half),
                )
            )  # fmt: skip
            halves = self._judge(
                ends[0],
                ends[1],
                ends[2:4],
                ends[4:6],
                ends[6],
                rng.random(2 * len(rest)),
                level > 1,
            )
            tree.append((where, middle, rest, halves))
            where = np.flatnonzero(halves[2])
        # bottom-up: a step halved crosses where its midpoint lies in E (and reaches it there),
        # else where either half crosses (the first half's point where both do)
        for depth in range(len(tree) - 1, -1, -1):
            where, middle, rest, (h_crossed, h_reached, _) = tree[depth]
            n = len(rest)
            first = h_crossed[:n]
            step_crossed = np.ones(len(where), dtype=bool)
            step_reached = middle.copy()
            step_crossed[rest] = first | h_crossed[n:]
            step_reached[rest] = np.where(first[:, None], h_reached[:n], h_reached[n:])
            above = (crossed, reached) if depth == 0 else tree[depth - 1][3]
            above[0][where], above[1][where] = step_crossed, step_reached
        return crossed, reached

    def _judge(self, a, b, start, end, factor, draws, refine: bool):
        """The flat-boundary rule on steps a → b (:meth:`_bridge`), for each part of E (``start``
        and ``end``: distances ``(n, K)`` and normals ``(n, K, d)``): (crossed, the point of E
        nearest each end b, and which steps are to be halved instead, where ``refine``). A step
        crosses into E where it crosses into any part, 1 − Π_k (1 − p_k) (the parts' crossings
        taken as independent); it is halved where a crossing of a part that is not one plane at
        both ends is plausible, or of two parts (a gap between them narrower than the step's
        noise: stranger round 45's slab between two half-spaces, where the nearest part's rule
        alone stopped too few paths), or where the step's straight segment meets a part
        (:func:`~gridlbc.regions.part_segments`: a set thinner than the step, crossed along an
        axis without noise)."""
        (d_a, n_a), (d_b, n_b) = start, end
        variance = np.sum(np.einsum("nkd,ndm->nkm", n_a, factor) ** 2, axis=2)
        spread = variance > 0  # else the bridge is its straight part across the boundary
        with np.errstate(under="ignore"):
            p = np.where(spread, np.exp(-2 * d_a * d_b / np.where(spread, variance, 1.0)), 0.0)
        near_b = b[:, None, :] - d_b[..., None] * n_b  # each part's point nearest the step's end
        reached = near_b[np.arange(len(b)), np.argmin(d_b, axis=1)]  # E's
        finer = np.zeros(len(p), dtype=bool)
        if refine:  # a plausible crossing of a boundary that is not one plane at both ends
            plane = np.einsum("nkd,nkd->nk", n_a, n_b) >= 1.0 - PLANE
            offset = np.einsum("nkd,nkd->nk", n_a, near_b - (a[:, None, :] - d_a[..., None] * n_a))
            plane &= np.abs(offset) <= PLANE * (1.0 + np.abs(d_a) + np.abs(d_b))
            plausible = p > BRIDGE_REFINE
            finer = np.any(plausible & ~plane, axis=1) | (plausible.sum(axis=1) > 1)
            finer |= self._segments(a, b, d_a, ~finer)
        return ~finer & (draws < 1.0 - np.prod(1.0 - p, axis=1)), reached, finer

    def _segments(self, a, b, d_a, asked) -> np.ndarray:
        """Which of the ``asked`` steps a → b (``(n,)`` masks) have a straight segment that meets
        a part of E (:func:`~gridlbc.regions.part_segments`), tested only where a part is no
        farther from ``a`` than the segment is long (``d_a`` ``(n, K)``,
        :func:`~gridlbc.regions.part_distances`, is at most the true distance: exact for boxes,
        a lower bound for ellipsoids, whose ρ is convex)."""
        met = np.zeros(len(a), dtype=bool)
        rows = np.flatnonzero(asked)
        if len(rows):
            periods = self.problem.periods
            length = np.linalg.norm(wrap_difference(b[rows] - a[rows], periods), axis=1)
            rows = rows[np.any(d_a[rows] <= length[:, None], axis=1)]
        if len(rows):
            met[rows] = np.any(part_segments(self.parts, a[rows], b[rows], periods), axis=1)
        return met

    def _stop(self, running, entered, where, t: float) -> None:
        ids = running[entered]
        if len(ids):
            if self.end_cost is not None:
                self.end_cost[ids] = self.problem.exit_values(where[entered])
            self.times[ids] = t
            self.alive[ids] = False
