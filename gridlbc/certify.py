"""The certified optimum's public entry, :func:`gridlbc.certify` (docs page :doc:`validating`):
the importance sampler of :mod:`gridlbc.certificate` with its default proposal, the judged policy
pooled with a grid solution of the problem that this module solves (:func:`gridlbc.solve`).
The sampler itself sits below the solver, so that the error estimate can certify a solve
(:mod:`gridlbc.accuracy.certified`); only this default needs a solve.
"""

from __future__ import annotations

import functools
import warnings
import weakref

import numpy as np

from .certificate import (
    MAX_PARETO_K,
    MIN_EFFECTIVE_SAMPLE_SIZE,
    PILOT_SHARE,
    Certificate,
    sample_certificate,
)
from .errors import CertificateWarning, warn_user
from .grid import Axis, Grid
from .problem import Problem
from .solver import solve

AUTO_PROPOSAL_NODES = 1_000_000
"""With ``proposal="auto"``, the most grid nodes :func:`~gridlbc.certify` solves on by itself to
pool a grid policy with the judged one (a larger grid is coarsened to this many, box unchanged)."""


AUTO_HALVINGS = 3
"""At most this many halvings of the automatic grid solution's time step."""

AUTO_WORK = 4
"""A halving is made only where the solve it needs takes at most this many node-steps (nodes ×
time steps) per sample-step of the certificate's draws (samples × Euler–Maruyama steps per start
state): an interpolation or a stencil each, a node-step the cheaper of the two, so that the
proposal never costs much more than the certificate it serves."""


_GRID_PROPOSALS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
"""The grid solutions ``proposal="auto"`` solved, per problem: the default solve, then those with
the time step halved (each solved once per problem)."""


def certify(
    problem: Problem,
    policy,
    x0,
    n_samples: int = 2000,
    dt: float | None = None,
    seed: int | None = None,
    progress: bool | None = None,
    min_effective_sample_size: float = MIN_EFFECTIVE_SAMPLE_SIZE,
    max_pareto_k: float = MAX_PARETO_K,
    proposal="auto",
    boundary: str | None = None,
    richardson: bool = False,
    max_time: float | None = None,
    step_check: bool = True,
) -> Certificate:
    """Estimate the true optimal cost v*(x₀) by importance sampling, and the cost of ``policy``.

    v*(x₀) = −λ log E_u[exp(−S_u/λ)] with S_u = g(x_T) + ∫(q + ½uᵀRu) dt + ∫uᵀR dε holds for any
    proposal policy u (Feynman–Kac and Girsanov; :mod:`gridlbc.certificate` and the README
    section "Certified optimality"). The judged policy's own cost J(policy) is the plain Monte-Carlo mean
    of its realised costs, and the gap J − v* ≥ 0 says how suboptimal it is.

    The proposal sets only the variance, and a poor one (few effective samples, a heavy weight
    tail: see :attr:`Certificate.pareto_k`) can make v̂* too high by many of its own standard
    errors without any diagnostic showing it, because the paths that carry the weight are never
    drawn. So by default (``proposal="auto"``) a policy that is not itself a grid solution of
    ``problem`` is pooled with one: :func:`~gridlbc.certify` solves the problem on its grid
    (coarsened to
    :data:`~gridlbc.certify.AUTO_PROPOSAL_NODES` nodes at most, once per problem) and draws half the
    samples with each policy, weighted by multiple importance sampling (the balance heuristic,
    :mod:`gridlbc.certificate`), which is as good as the better of the two up to a factor 2 in variance. J then
    comes from the judged policy's half, and the gap's SE is √(SE(J)² + SE(v*)²). Without a grid
    (or with ``proposal=None``) the judged policy is the only proposal: one set of samples gives
    v*, J and the gap, whose SE is that of the paired linearisation C + λw/w̄. With a
    ``proposal`` of your own (or a list of them, pooled the same way) v* is estimated from its
    samples while J comes from independent samples of ``policy``.

    Parameters
    ----------
    problem : Problem
        Dynamics, costs, temperature λ and horizon T.
    policy : callable
        ``policy(x, t)`` → controls ``(N, m)`` for states ``(N, d)``: the judged controller, and
        the proposal when ``proposal`` is None. Any controller works; as a proposal, the closer to
        optimal the smaller the standard error.
    x0 : array_like (d,) or (k, d)
        One start state (the estimates are floats) or k of them (arrays ``(k,)``).
    n_samples : int
        Samples per start state (all k·n are rolled out together, the policy called on all).
    dt : float, optional
        Euler–Maruyama step, as in :func:`gridlbc.simulate` (default T / 300; required for a
        problem without a horizon, where ``max_time`` is only a cap). The estimate is
        exact for the time-discretised chain; its distance from the SDE's optimum is the scheme's
        O(Δt) weak error, which ``step_check`` reads and warns of (``richardson=True`` removes it).
    seed : int, optional
        Seed of ``np.random.default_rng``: the same seed gives the same certificate.
    progress : bool, optional
        A progress bar on stderr: True always, False never, None (default) once the run has
        taken :data:`gridlbc.progress.DELAY` seconds.
    min_effective_sample_size : float
        Warn (:class:`CertificateWarning`) and flag the summary where the effective sample size is
        below this.
    max_pareto_k : float
        Likewise where the PSIS tail shape k̂ of the weights exceeds this (Vehtari et al., JMLR
        2024: above 0.7 the estimate is unreliable whatever the sample count).
    proposal : "auto", None, object with ``.policy(x, t)``, callable, or a list of them
        The importance-sampling proposal for v*. ``"auto"`` (default): ``policy`` pooled with a
        grid solution of the problem (solved with a finer time step where a pilot of a few paths
        finds it a poor proposal, docs page :doc:`validating`), or ``policy`` alone
        when it is a grid solution's policy of this problem that the pilot finds a good proposal
        or the problem has no grid (:attr:`Certificate.proposals` says which). None:
        ``policy`` alone. A :class:`~gridlbc.Solution`, a combination or a callable
        ``policy(x, t)``: that proposal, its paths drawn first from the seeded generator and
        those of ``policy`` after them (independent). A list or tuple: those proposals pooled
        (``n_samples`` split between them; a member that *is* ``policy`` also gives J).
    boundary : {"free", "reflect"}, optional
        At a closed edge of the grid's box (:func:`gridlbc.simulate`): ``"reflect"`` certifies
        the problem with the box as a reflecting state constraint, as the solver treats it, so a
        grid prediction and its certificate concern the same problem; ``"free"`` the problem on
        Rᵈ (the box only a computational domain). None (default): ``"reflect"`` when the grid
        has a closed axis, ``"free"`` otherwise (no grid: no box). The Girsanov weight is exact
        for both (:mod:`gridlbc.certificate`).
    richardson : bool
        Also certify at twice the step, from independent draws (seed + 1), and extrapolate the
        step's O(Δt) bias away: :attr:`Certificate.extrapolated_value`, its SE and
        :attr:`Certificate.step_contribution`; :meth:`Certificate.interval` then bounds the
        SDE's optimum, and the diagnostics are the worse of the two runs'. A third run at 4Δt
        (seed + 2) checks the extrapolation (:attr:`Certificate.extrapolation_gap`), and
        :class:`CertificateWarning` says where the bias is not yet of first order. Needs at
        least 8 steps; costs three quarters as much again. An exit set given as a callable and
        crossed by the noise carries an O(√Δt) bias that no extrapolation here removes, and is
        warned of (:func:`gridlbc.certificate.crossings_unchecked`, docs page
        :doc:`validating`).
    max_time : float, optional
        For a first-exit problem without a horizon (required there): the paths stop at this
        time; the share that had not exited is :attr:`Certificate.unexited_fraction`.
    step_check : bool
        Without ``richardson``: also certify at four times the step with half the samples
        (seed + 1, an eighth more work) to read the step's own bias at ``dt``,
        :attr:`Certificate.step_bias`, which v*'s standard error leaves out, and warn
        (:class:`CertificateWarning`) where it is beyond the sampling and larger than that
        standard error. False skips it.

    Returns
    -------
    Certificate
    """
    return sample_certificate(
        problem,
        policy,
        x0,
        n_samples=n_samples,
        dt=dt,
        seed=seed,
        progress=progress,
        min_effective_sample_size=min_effective_sample_size,
        max_pareto_k=max_pareto_k,
        proposal=proposal,
        boundary=boundary,
        richardson=richardson,
        max_time=max_time,
        grid_proposal=functools.partial(_grid_proposal, progress=progress),
        step_check=step_check,
    )


def _grid_proposal(problem: Problem, pilot=None, work: int = 0, progress: bool | None = None):
    """A grid solution's policy for ``proposal="auto"`` and its name, or (None, why not).

    The default :func:`gridlbc.solve` of the problem on its own grid, or, above
    :data:`~gridlbc.certify.AUTO_PROPOSAL_NODES` nodes, on the same box with every axis's node count
    scaled by (AUTO_PROPOSAL_NODES / nodes)^(1/d). Its warnings are silenced and non-finite controls
    (where z underflowed) replaced by 0 (:class:`GridPolicy`): any policy is a valid proposal, its
    quality only sets the variance, which the certificate's diagnostics report. Where the solve
    fails, the judged policy draws alone, and :class:`gridlbc.CertificateWarning` says so: the
    pool is what guards a poor policy's certificate.

    With a horizon and a ``pilot`` (:func:`gridlbc.certificate.pilot_share`, which draws a few
    paths of a candidate from the certificate's start states), the time step is halved, up to
    :data:`AUTO_HALVINGS` times and while the solve's node-steps stay within :data:`AUTO_WORK`
    times the certificate's sample-steps ``work``, as long as the pilot's effective share is below
    :data:`PILOT_SHARE` (the finest is kept: a pilot of a poor proposal is too noisy to compare
    two by, and a finer step does not make a grid policy worse). Why: the policy
    between two stored slices is interpolated linearly in time, and where the terminal cost is
    steep the policy grows within the last step far from linearly; at a small temperature the
    weights are sharp enough for that to leave a few effective paths, and then the unseen tail
    biases v̂* high with a small SE and a moderate k̂, which no diagnostic flags; a finer step
    restores the effective samples and removes the bias, where more nodes do not (stranger
    round 35's 4-D LQ at λ = 0.1: docs page :doc:`validating`, "Pooled proposals").
    ``progress`` is the certificate's, passed on to those solves.
    """
    if problem.grid is None:
        return None, "no grid to solve on"
    if problem not in _GRID_PROPOSALS:
        grid = problem.grid
        scale = min(1.0, (AUTO_PROPOSAL_NODES / grid.size) ** (1.0 / grid.ndim))
        axes = [
            Axis(a.lo, a.hi, max(4 if a.periodic else 3, int(a.n * scale)), a.periodic, a.name)
            for a in grid.axes
        ]
        coarse = problem if scale == 1.0 else problem.replace(grid=Grid(axes))
        try:
            solution = _quiet_solve(coarse, progress=progress)
        except (ValueError, MemoryError) as error:
            warn_user(
                f'certify: proposal="auto" found no grid solution to pool with the policy (its '
                f"solve failed: {error}), so the policy alone draws the samples; a poor policy's "
                "certificate can then be far off with nothing in its diagnostics to show it. Pass "
                "a proposal of your own (a solution that resolves the problem)",
                CertificateWarning,
            )
            return None, f"no grid proposal: its solve failed ({error})"
        _GRID_PROPOSALS[problem] = [solution]
    solutions = _GRID_PROPOSALS[problem]
    chosen = solutions[0]
    for halving in range(1, AUTO_HALVINGS + 1):
        if pilot is None or problem.stationary or pilot(GridPolicy(chosen)) >= PILOT_SHARE:
            break
        first = solutions[0]
        if first.grid.size * first.diagnostics.steps * 2**halving > AUTO_WORK * work:
            break
        if len(solutions) == halving:
            try:
                solutions.append(
                    _quiet_solve(first.problem, first.diagnostics.dt / 2**halving, progress)
                )
            except (ValueError, MemoryError):
                break
        chosen = solutions[halving]
    shape = "×".join(str(a.n) for a in chosen.problem.grid.axes)
    step = "" if problem.stationary else f", dt = {chosen.diagnostics.dt:.3g}"
    return GridPolicy(chosen), f"a {shape} grid solution (auto){step}"


def _quiet_solve(problem: Problem, dt: float | None = None, progress: bool | None = None):
    """:func:`gridlbc.solve` with its warnings silenced (a proposal's quality is the
    certificate's to judge)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return solve(problem, dt, progress=progress)


class GridPolicy:
    """A grid solution's policy as the proposal of ``proposal="auto"``: 0 where a control is not
    finite (z underflowed), the last slice's past the horizon; the solution kept as
    :attr:`solution` (the certificate reads its error estimate:
    :func:`gridlbc.certificate.check_unvisited`)."""

    def __init__(self, solution):
        self.solution = solution

    def __call__(self, x, t):
        """u(x, t), finite."""
        horizon = self.solution.problem.horizon
        t = t if horizon is None else min(t, horizon)
        return np.nan_to_num(self.solution.policy(x, t), nan=0.0, posinf=0.0, neginf=0.0)
