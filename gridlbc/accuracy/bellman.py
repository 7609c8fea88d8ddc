"""The solved value against its own values a little later, along the SDE: a local certificate
(docs page :doc:`accuracy`, "A value steeper than a cell where the costs are smooth").

The optimal desirability obeys the Feynman–Kac identity over any stretch of time: for a stopping
time σ ≤ T (the first of τ, a short time τ_ℓ and the horizon),

    z(x, t) = E_0[ exp(−∫_t^σ q ds / λ) z(X_σ, σ) ]

under the passive dynamics (paper §3.1), so v = −λ log z is, at every state, what the SDE makes
of v a little later. :func:`~gridlbc.accuracy.bellman_gap` measures how far the solve's v_h is from
that:

    v_ℓ(x) = −λ log E_u[ exp(−S/λ) ],   S = ∫_t^σ (q + ½uᵀRu) ds + ∫_t^σ uᵀR dε + v_h(X_σ, σ),

sampled as :func:`gridlbc.certify` samples v* (importance sampling with the Girsanov weights,
exact for any proposal; the solve's own policy proposes, its pull tamed where an explicit
step would overshoot, :func:`_tamed`), with v_h(X_σ, σ) replaced by the exit
cost g_E where a path exits and by the terminal cost g at the horizon, and read at the paths'
ends exactly where v_h is a quadratic (:func:`quadratic_read`: the plain interpolant of a convex
v is high between the nodes). Where v_h is the optimal value, v_ℓ = v_h up to the sampling error
and the Euler–Maruyama chain's weak error. Where v_h is wrong at x but right where the paths go
within τ_ℓ, v_h(x) − v_ℓ(x) is that error.

The paths run over τ_ℓ = :data:`~gridlbc.accuracy.bellman.SPAN` of the solve's steps
(of :func:`gridlbc.accuracy.path_step` without a horizon), at a quarter and an eighth of that step,
the coarser chain driven by the finer one's Brownian motion (:class:`_Paired`), extrapolated to a
vanishing step (:func:`~gridlbc.accuracy.bellman_gap`): long enough to leave the cells next to a
feature the grid does not resolve (a value that changes by many λ within one cell of an invariant
edge, where the grid interpolates across the change), short enough that the errors the solve carries
along its characteristics are mostly shared by x and by where its paths go (those are the
embedded solves' to measure). It is therefore a check of the solve's *local* consistency: an
error that v_h makes alike at x and a stretch downstream is not seen. Run on to the horizon
(``whole``), where v_h is g, exact, the same paths certify the whole remaining task
(:func:`~gridlbc.accuracy.local_error`): nothing of the solve is read at their end, and an error
shared all the way to T is seen, at the price of weights whose spread grows with the span.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.stats import norm

from ..certificate import effective_sample_sizes
from ..interpolate import barycentric
from ..simulate import euler_maruyama
from .paths import SEED, path_step

SPAN = 8
"""τ_ℓ, in the solve's steps (module docstring)."""

SUBSTEPS = 4
"""Path steps per solve step of the coarser of the two chains
that :func:`~gridlbc.accuracy.bellman_gap` extrapolates from (the finer takes twice as many)."""

LOCAL_SAMPLES = 32
"""Paths per state of :func:`~gridlbc.accuracy.bellman_gap` (fewer
where :data:`~gridlbc.accuracy.bellman.LOCAL_WORK` asks)."""

WHOLE_SAMPLES = 512
"""Paths per state of the whole remaining task's certificate
(:func:`~gridlbc.accuracy.local_error`), fewer where
:data:`~gridlbc.accuracy.bellman.LOCAL_WORK` asks: its paths run to the horizon under a proposal
that may steer where the solve is wrong, and their weights are heavy-tailed, so that a few dozen
paths scatter widely about the error (stranger round 20's ``exit_late``: docs page
:doc:`accuracy`, "Stranger round 20 found where the whole task is needed")."""

LOCAL_WORK = 1 << 22
"""At most this many path-steps per call of :func:`~gridlbc.accuracy.bellman_gap` (but at least 8
paths per state): a map of the estimate over many states is checked more thinly, and its noise,
which
:func:`~gridlbc.accuracy.local_error` discounts, is larger."""

BELLMAN_SE = 2.0
"""The local certificate's difference from the solve counts beyond this many of its standard
errors (:func:`~gridlbc.accuracy.local_error`)."""

LOCAL_ESS = 4.0
"""Below this effective sample size (Σw)²/Σw² of either chain's weights at a state, the local
certificate's v_ℓ is held to at most what the uncontrolled process pays over the same span
(:func:`~gridlbc.accuracy.bellman_gap`), E_0[∫ q ds + v_h(X_σ)]
plus :data:`~gridlbc.accuracy.bellman.BELLMAN_SE` of its standard errors, since the optimum over the
span is at most the cost of any policy, doing nothing included. There a few paths carry the whole
weight, and −λ log of the weights' mean, biased high as the logarithm of a mean is, can lie far
above the true v_ℓ where the solve's policy is absurd (stranger round 25's first exit at small λ
whose policy pushes hard, one path carrying the weight: docs page :doc:`benchmarks`, "It found
the local certificate reading ...")."""


def bellman_gap(
    solution, x, t: float = 0.0, samples: int = LOCAL_SAMPLES, whole: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """v_h(x, t) − v_ℓ(x, t) at states ``x`` (N, d), time ``t``, and its standard error (the
    delta method over the two chains' paired paths, :func:`_extrapolated`), from ``samples`` paths per state (fewer where
    :data:`~gridlbc.accuracy.bellman.LOCAL_WORK` asks; module docstring); NaN where v_h or the
    policy is not finite (v_ℓ at most the uncontrolled process's cost where fewer
    than :data:`~gridlbc.accuracy.bellman.LOCAL_ESS` paths carry the weight). v_ℓ
    is extrapolated in the chain's step δ, 2 v_ℓ(δ/2) − v_ℓ(δ) with δ =
    Δt/:data:`~gridlbc.accuracy.bellman.SUBSTEPS`, which removes the Euler–Maruyama chain's
    first-order weak error (a solve's step may be long against its dynamics, and the chain's
    own error then dwarfs the solve's: round 18's springs, docs page :doc:`accuracy`, "A value
    steeper than a cell where the costs are smooth").

    Parameters
    ----------
    solution : Solution
        A grid solution of a task with a horizon, an exit set or both (not average cost).
    x : ndarray (N, d)
        States.
    t : float
        Time in [0, T] (0 without a horizon); zeros at T, where v_h is the terminal cost.
    samples : int
        Paths per state.
    whole : bool
        Whether the paths run to the horizon (the remaining task certified whole), or without a
        horizon for as long as the work allows (:func:`_span`), rather than
        over :data:`~gridlbc.accuracy.bellman.SPAN` of the solve's steps.

    Returns
    -------
    gap : ndarray (N,)
    se : ndarray (N,)
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    problem = solution.problem
    t = 0.0 if problem.stationary else float(t)
    if len(x) == 0 or (not problem.stationary and t >= problem.horizon):
        return np.zeros(len(x)), np.zeros(len(x))
    span, steps = _span(solution, t, whole, len(x))
    work = 3 * SUBSTEPS * steps  # both chains' steps per path
    samples = int(np.clip(LOCAL_WORK // (len(x) * work), min(8, samples), samples))
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an underflowed value is the solve's to warn of
        v = solution.value(x, t)
    coarse = _log_weights(solution, x, t, samples, span, steps * SUBSTEPS, paired=True)
    fine = _log_weights(solution, x, t, samples, span, steps * 2 * SUBSTEPS)
    local, se = _extrapolated(fine, coarse, solution.temperature)
    few = np.flatnonzero(
        np.fmin(effective_sample_sizes(fine), effective_sample_sizes(coarse)) < LOCAL_ESS
    )
    if len(few):  # a few heavy paths: v_ℓ at most what the uncontrolled process pays
        bound = _policy_cost(solution, x[few], t, samples, span, steps * 2 * SUBSTEPS, passive=True)
        local[few] = np.fmin(local[few], bound)
    return v - local, se


def value_bound(solution, x, t: float = 0.0) -> np.ndarray:
    """An upper bound on the optimal v(x, t) at states ``x`` (N, d), time ``t``: the lesser of what
    the uncontrolled process (u = 0) and the solve's own policy (as the local certificate's chain
    takes it, :func:`_tamed`) pay to the end of the task (its exit or the horizon),
    E[∫ (q + ½ uᵀRu) ds + g], each plus :data:`~gridlbc.accuracy.bellman.BELLMAN_SE` of its
    standard errors (every policy pays at least v*). From
    :data:`~gridlbc.accuracy.bellman.BOUND_SAMPLES` paths per state, fewer where
    :data:`~gridlbc.accuracy.bellman.LOCAL_WORK` asks, at the steps of the local certificate's
    finer chain. +inf without a horizon (the paths need not end) or at T.

    Parameters
    ----------
    solution : Solution
        A grid solution.
    x : ndarray (N, d)
        States.
    t : float
        Time in [0, T].

    Returns
    -------
    ndarray (N,)
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    problem = solution.problem
    if problem.stationary or len(x) == 0 or t >= problem.horizon:
        return np.full(len(x), np.inf)
    span, steps = _span(solution, t, True)
    steps *= 2 * SUBSTEPS
    samples = int(np.clip(LOCAL_WORK // (2 * len(x) * steps), 8, BOUND_SAMPLES))
    return np.fmin(
        _policy_cost(solution, x, t, samples, span, steps, passive=True),
        _policy_cost(solution, x, t, samples, span, steps, passive=False),
    )


BOUND_SAMPLES = 256
"""Paths per state and policy of :func:`~gridlbc.accuracy.bellman.value_bound`."""


def _policy_cost(
    solution, x, t: float, samples: int, span: float, steps: int, passive: bool
) -> np.ndarray:
    """The mean cost S of ``samples`` paths per state of the uncontrolled process (``passive``) or
    of the chain's proposal over ``span`` in ``steps`` chain steps (v_h read where they are still
    running at its end, :func:`_log_weights`; the Itô term of S has mean 0), plus
    :data:`~gridlbc.accuracy.bellman.BELLMAN_SE` of its standard errors; +inf where a cost is not
    finite."""
    costs = -solution.temperature * _log_weights(
        solution, x, t, samples, span, steps, passive=passive
    )
    bound = costs.mean(axis=1) + BELLMAN_SE * costs.std(axis=1) / np.sqrt(samples)
    return np.where(np.isfinite(bound), bound, np.inf)


def local_error(
    solution,
    x,
    t: float = 0.0,
    samples: int = LOCAL_SAMPLES,
    whole: bool = False,
    discount: float = BELLMAN_SE,
) -> np.ndarray:
    """abs(:func:`~gridlbc.accuracy.bellman_gap`) less ``discount`` of its standard errors, at least
    0, at states ``x`` (N, d), time ``t``: what the local certificate says of the solve's error
    beyond its sampling noise (:func:`largest_discount` where the largest over many states is read);
    NaN where it could not be read. With ``whole``, also the certificate of
    the whole remaining task (the paths run to the horizon; without one, for as long as the work
    allows, :func:`_span`: stranger round 44's first exit along an axis without noise, 6.7 % off
    where the short stretch read nothing beyond its noise), from as many paths per state
    as :data:`~gridlbc.accuracy.bellman.LOCAL_WORK` affords up
    to :data:`~gridlbc.accuracy.bellman.WHOLE_SAMPLES`, where that is longer than
    :data:`~gridlbc.accuracy.bellman.SPAN` of the solve's steps (none where it affords fewer
    than ``samples``) or, as long as the span, from more paths than ``samples``; and the larger
    of the two. Why also the short one: in the last steps of a task v can change within one
    step by more than interpolating between two slices says (a terminal layer thinner than
    Δt, which the coarser solves interpolate alike), and a few paths read such an error below
    their noise where more paths resolve it (stranger round 38's mixing inputs at T − Δt/2:
    docs page :doc:`accuracy`, "Stranger round 20 found where the whole task is needed")."""
    gap, se = bellman_gap(solution, x, t, samples)
    out = beyond_noise(gap, se, discount)
    x = np.atleast_2d(np.asarray(x, dtype=float))
    problem = solution.problem
    if not whole or len(x) == 0 or (not problem.stationary and t >= problem.horizon):
        return out
    steps = _span(solution, t, True, len(x))[1]
    affordable = min(WHOLE_SAMPLES, LOCAL_WORK // (len(x) * 3 * SUBSTEPS * steps))
    if affordable > samples or (steps > SPAN and affordable == samples):
        gap, se = bellman_gap(solution, x, t, affordable, whole=True)
        out = np.fmax(out, beyond_noise(gap, se, discount))
    return out


def beyond_noise(gap: np.ndarray, se: np.ndarray, discount: float) -> np.ndarray:
    """abs(``gap``) less ``discount`` of its standard errors ``se``, at least 0 (0 where the gap
    is NaN): what a local certificate says beyond its sampling noise
    (:func:`~gridlbc.accuracy.local_error`,
    :func:`gridlbc.accuracy.assessment.path_check`)."""
    return np.fmax(np.abs(gap) - discount * se, 0.0)


def largest_discount(count: int) -> float:
    """The standard errors by which the largest of ``count`` certificates is discounted: the
    level z that the largest of ``count`` independent standard normals exceeds with the
    probability that one exceeds :data:`~gridlbc.accuracy.bellman.BELLMAN_SE` (about 2.3 %), z =
    Φ⁻¹(1 − p/count) (3.6 for 128). Read at many states, a difference of two standard errors is
    found somewhere by chance; the warning's confirmation reads the largest over its candidates."""
    tail = float(norm.sf(BELLMAN_SE))
    return float(norm.isf(tail / max(count, 1)))


def _span(solution, t: float, whole: bool, states: int = 1) -> tuple[float, int]:
    """τ_ℓ from time ``t`` and the solve steps it spans: :data:`~gridlbc.accuracy.bellman.SPAN` of
    them, or the time to the horizon where that is shorter or ``whole`` asks for it (at
    least :data:`~gridlbc.accuracy.bellman.SPAN` steps still: a shorter stretch is taken in as many
    chain steps). Without a horizon, steps of :func:`~gridlbc.accuracy.paths.path_step`:
    :data:`~gridlbc.accuracy.bellman.SPAN` of them, or with ``whole`` as many as
    :data:`~gridlbc.accuracy.bellman.LOCAL_WORK` affords :data:`~gridlbc.accuracy.bellman.WHOLE_SAMPLES`
    paths at each of ``states`` states (at least :data:`~gridlbc.accuracy.bellman.SPAN`): a task
    that ends at its exit set is run for as long as the work allows, most of its paths to their
    exit."""
    problem = solution.problem
    if problem.stationary:
        steps = SPAN
        if whole:
            steps = max(SPAN, LOCAL_WORK // (states * 3 * SUBSTEPS * WHOLE_SAMPLES))
        return steps * path_step(solution), steps
    dt, remaining = solution.diagnostics.dt, problem.horizon - t
    if whole or remaining <= SPAN * dt:
        return remaining, max(SPAN, int(np.ceil(remaining / dt - 1e-9)))
    return SPAN * dt, SPAN


def _log_weights(
    solution,
    x: np.ndarray,
    t: float,
    samples: int,
    span: float,
    steps: int,
    paired: bool = False,
    passive: bool = False,
) -> np.ndarray:
    """−S/λ of ``samples`` paths per state from states ``x`` (N, d) at time ``t`` over ``span`` in
    ``steps`` chain steps (module docstring), ``(N, samples)``; NaN where a weight is not finite.
    ``paired``: the paths follow the Brownian motion of the chain with twice as many steps and
    the same seed (:class:`_Paired`), so that the two chains' difference is mostly the step's.
    ``passive``: the paths of the uncontrolled process (u = 0) instead of the solve's policy."""
    problem = solution.problem
    starts = np.repeat(x, samples, axis=0)

    def policy(y: np.ndarray, s: float) -> np.ndarray:
        """The chain's proposal (:func:`_tamed`), or u = 0 for the uncontrolled paths."""
        if passive:
            return np.zeros((len(y), problem.system.control_dim))
        return _tamed(solution, y, t + s, span / steps)

    rng = np.random.default_rng(SEED)
    paths = euler_maruyama(
        problem, policy, starts, steps, _Paired(rng) if paired else rng, horizon=span
    )
    end = paths.terminal_cost.copy()  # g_E where exited, g(X_T) where the horizon ended them
    running = np.ones(len(starts), dtype=bool)
    if paths.exit_times is not None:
        running = np.isnan(paths.exit_times)
    if problem.stationary or span < problem.horizon - t:  # still running at τ_ℓ: v_h there
        end[running] = quadratic_read(
            solution, paths.final_states[running], 0.0 if problem.stationary else t + span
        )
    log_weights = -(paths.running_cost + paths.ito + end) / problem.temperature
    return np.where(np.isfinite(log_weights), log_weights, np.nan).reshape(len(x), samples)


def _read_policy(solution, y: np.ndarray, t: float) -> np.ndarray:
    """The solve's policy at states ``y`` (N, d), time ``t``; 0 where it underflowed (the
    sample's weight is then NaN)."""
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an underflowed policy was the solve's to warn of
        u = np.asarray(solution.policy(y, t), dtype=float)
    return np.where(np.isfinite(u), u, 0.0)


def _tamed(solution, y: np.ndarray, t: float, step: float) -> np.ndarray:
    """The proposal of the local certificate's chain of step δ = ``step`` at states ``y`` (N, d),
    time ``t``: the solve's policy u₀ = u(y, t), scaled by α ∈ (0, 1] where the control moves a
    state by more than :data:`~gridlbc.accuracy.bellman.TAMED_CELLS` of a cell per step,

        α = ‖u₀‖² / (2‖u₀‖² − u₀·u₁),   u₁ = u(y + B u₀ δ, t),

    the linearly implicit step along u₀ (α u₀ = u(y + α B u₀ δ) with u linear between y and
    y + B u₀ δ; α = 1 where u grows along its own direction).

    Why: the chain steps explicitly, and where the policy's gain k (the rate at which it pulls
    a state back) exceeds 2/δ each step overshoots by more than it corrects. The paths then
    oscillate with growing amplitude and their weights carry nothing, so the certificate reads
    an error orders of magnitude above v where v is exact (stranger round 37's huge box: docs
    page :doc:`accuracy`, "The chain steps explicitly"). The certificate is exact for any
    proposal, so the proposal may be changed: the linearly implicit step divides the pull by
    1 + kδ and, for
    a quadratic v a step later, is the mean of the chain's own optimal transition (where the
    pull is weak, α ≈ 1 − kδ, near the solve's policy)."""
    u0 = _read_policy(solution, y, t)
    move = np.einsum("nij,nj->ni", solution.problem.system.input_matrix(y), u0) * step
    reach = TAMED_CELLS * solution.grid.spacing
    beyond = np.abs(move[:, 0]) > reach[0]
    for k in range(1, len(reach)):  # axis by axis: a reduction along a short axis is slow
        beyond |= np.abs(move[:, k]) > reach[k]
    far = np.flatnonzero(beyond)
    if len(far) == 0:
        return u0
    ahead = _read_policy(solution, solution.grid.clamp(y[far] + move[far]), t)
    square = np.sum(u0[far] ** 2, axis=1)
    below = 2 * square - np.sum(u0[far] * ahead, axis=1)  # > square where u shrinks ahead
    alpha = square / np.where(below > square, below, square)
    u0[far] *= alpha[:, None]
    return u0


TAMED_CELLS = 1.0
"""The local certificate's proposal is the solve's policy where it moves a state by at most this
many cells (of each axis) per chain step, and the linearly implicit step along it beyond
(:func:`~gridlbc.accuracy.bellman._tamed`): a step shorter than a cell overshoots by less than a
cell, and within a cell the interpolated policy's gain is not resolved anyway."""


class _Paired:
    """A generator whose normal draws are the normalised sums of consecutive pairs of another's:
    a chain of step 2δ driven by it follows the Brownian motion of a chain of step δ driven by
    the same seed (its increments are the sums of two of the other's). An exit set with a
    geometry also draws uniforms for its crossing check, after which the pairs no longer match:
    the two chains are then independent, and their difference noisier, not biased."""

    def __init__(self, rng: np.random.Generator):
        self.rng = rng

    def standard_normal(self, shape) -> np.ndarray:
        """(z₁ + z₂)/√2 from two draws of ``shape``."""
        return (self.rng.standard_normal(shape) + self.rng.standard_normal(shape)) / np.sqrt(2.0)

    def random(self, size) -> np.ndarray:
        """Uniforms, drawn as they are asked for."""
        return self.rng.random(size)


def _extrapolated(
    fine: np.ndarray, coarse: np.ndarray, lam: float
) -> tuple[np.ndarray, np.ndarray]:
    """2 v_ℓ(δ/2) − v_ℓ(δ) per state from the log weights of the two chains' paths (N, n), paired
    path by path, and its standard error by the delta method: with r = w/w̄ − 1 for each chain,
    the estimate moves by −λ (2 r_fine − r_coarse) per path, whose spread over √n is the SE
    (the pairing makes the two chains' noise largely cancel). NaN where a weight is not
    finite."""
    value, se = np.full(len(fine), np.nan), np.full(len(fine), np.nan)
    for i, (a, b) in enumerate(zip(fine, coarse, strict=True)):
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            continue
        w, u = np.exp(a - a.max()), np.exp(b - b.max())
        value[i] = -lam * (2 * (a.max() + np.log(w.mean())) - (b.max() + np.log(u.mean())))
        spread = 2 * (w / w.mean() - 1) - (u / u.mean() - 1)
        se[i] = lam * spread.std(ddof=1) / np.sqrt(len(a)) if len(a) > 1 else np.nan
    return value, se


def quadratic_read(solution, x: np.ndarray, t: float) -> np.ndarray:
    """v_h at states ``x`` (n, d), time ``t``, read exactly where v_h is a quadratic: the
    barycentric interpolant less its error for a quadratic with the Hessian H of v_h's nodal
    values (central differences at the node nearest each state, the next node inward at a
    closed edge),

        v(x) ≈ Σ_i w_i v_h(x_i) − ½ Σ_i w_i (x_i − x)ᵀ H (x_i − x),

    x_i and w_i the vertices and weights of x's simplex (:func:`gridlbc.interpolate.barycentric`).
    The paths of :func:`~gridlbc.accuracy.bellman_gap` end between the nodes, where the plain
    interpolant of a convex v is high by up to h²∂²v/8: read so, a well's bottom would make the
    local certificate read an error the solve does not have."""
    grid = solution.grid
    d, h = grid.ndim, grid.spacing
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an underflowed value is the solve's to warn of
        value = solution.value(x, t)
        n = np.array(grid.shape)
        index = grid.nearest_node(x)
        index = np.where(grid.periodic, index, np.clip(index, 1, n - 2))  # inward at a closed end
        centre = grid.lo + index * h
        offsets = [np.zeros(d)]
        for k in range(d):
            for sign in (1.0, -1.0):
                offsets.append(sign * h * np.eye(d)[k])
        for k in range(d):
            for m in range(k + 1, d):
                for a, b in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                    offsets.append(a * h[k] * np.eye(d)[k] + b * h[m] * np.eye(d)[m])
        points = (centre[:, None, :] + np.array(offsets)[None]).reshape(-1, d)
        around = solution.value(grid.wrap(points), t).reshape(len(x), len(offsets))
    # where v underflowed (+inf) the Hessian is no number and so is the read: NaN, which the
    # caller takes for a weight it cannot read
    with np.errstate(invalid="ignore"):
        hessian = np.empty((len(x), d, d))
        for k in range(d):
            second = around[:, 1 + 2 * k] - 2 * around[:, 0] + around[:, 2 + 2 * k]
            hessian[:, k, k] = second / h[k] ** 2
        j = 1 + 2 * d
        for k in range(d):
            for m in range(k + 1, d):
                pp, pm, mp, mm = (around[:, j + i] for i in range(4))
                hessian[:, k, m] = hessian[:, m, k] = (pp - pm - mp + mm) / (4 * h[k] * h[m])
                j += 4
        idx, weights = barycentric(grid, x)
        vertices = grid.node_coordinates(idx.ravel()).reshape(len(x), d + 1, d)
        gaps = vertices - grid.wrap(x)[:, None, :]
        period = grid.hi - grid.lo
        gaps = np.where(grid.periodic, (gaps + 0.5 * period) % period - 0.5 * period, gaps)
        error = 0.5 * np.einsum("ni,nik,nkl,nil->n", weights, gaps, hessian, gaps)
        return value - error
