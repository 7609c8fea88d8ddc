"""Solves to a tolerance: refine the step and the grid until the embedded estimate meets ``tol``
(docs page :doc:`accuracy`).

:func:`~gridlbc.accuracy.solve_to_tolerance` (``gridlbc.solve(problem, tol=...)``) repeats the solve
until the estimate meets ``tol`` or a limit (memory, ``max_nodes``, ``max_refinements``) stops it.
Between rounds it measures each part's share of the error, the step's by a solve at 2Δt and
each axis's by a solve with that axis alone coarsened, and models the estimate as their sum,
e ≈ Σ_i C_i h_i^q + C_t Δt: it chooses the factors by which to refine each axis and the step
so that the predicted estimate meets ``tol`` at the least work
(:func:`~gridlbc.accuracy.refinement_factors`), rounded to feasible grids and cut to what fits in
memory (:func:`~gridlbc.accuracy.fitting_plan`). The model extrapolates only as far as it has been
checked: by at most 2 per round until a round's estimate comes within 2× of what it predicted (each
such round doubles the reach). Where it does not describe the errors
(:func:`~gridlbc.accuracy.unsteerable`: an estimate above 100 % of v, or shares that do not add up
to the embedded difference) every axis and the step are refined by 2; where the levels do not
converge at first order, the largest shares by 2. Where they do not converge, the estimate cannot
prove a tolerance it meets (it is far above the error on 4-D grids of a few dozen nodes per axis):
at a few states given by the user, certificates measure the error itself
(:func:`~gridlbc.accuracy.certified_error`) and end the solve when they prove ``tol``. The path is
in :attr:`gridlbc.Solution.refinement`. A round is met only where the step's own share (a solve at
2Δt) meets ``tol`` too, and where the drift does not change between the nodes faster than the grid
follows (:mod:`gridlbc.accuracy.flow`). A default solve whose estimate exceeds
:data:`~gridlbc.accuracy.DEFAULT_TOLERANCE` warns (:class:`gridlbc.ResolutionWarning`) with the
estimate and what to change.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import NamedTuple, TypeVar

import numpy as np

from .. import progress
from ..errors import GridlbcWarning, ResolutionWarning, warn_user
from ..grid import Grid
from ..storage import available_memory
from .assessment import ESTIMATE_WARNING, Assessment, assess, statistic
from .certified import (
    certifiable,
    certified_error,
)
from .estimate import given_floor, quiet_reads, relative_difference, relative_error
from .flow import FLOW_CELLS, FLOW_WARNING, NOISE_WARNING, check_flow, flow_excess, followed
from .grids import (
    embedded_grid,
    embedded_store_every,
    scaled_grid,
)
from .matter import judged_states

Solved = TypeVar("Solved")


class Marcher(NamedTuple):
    """The time march that :func:`~gridlbc.accuracy.solve_to_tolerance` repeats and plans,
    as :mod:`gridlbc.solver` passes it in (the solver calls this module, not the other way
    round)."""

    settings_for: Callable  # (problem, settings, options) → the SolverSettings of a solve
    planned_step: Callable  # (problem, settings) → (Δt, steps)
    planned_memory: Callable  # (problem, settings) → what a solve holds (dict of bytes)
    solve_many: Callable  # (problem, costs, settings, **options) → one Solution per cost


@quiet_reads()
def axis_shares(solution, solve_on, states=None, t: float = 0.0) -> tuple[np.ndarray, float]:
    """Each axis's share of the error of ``solution`` and the difference from its embedded solve,
    read at time ``t`` (where :func:`assess` found the largest error).

    The share of axis i is the relative difference (:func:`~gridlbc.accuracy.assessment.statistic`
    at the judged states) from a solve with only that axis coarsened (every other node,
    ``solve_on(grid)``, which may return None where the problem cannot be posed on that grid; NaN
    then, and for an axis too coarse to coarsen). The difference D from the embedded solves, which
    coarsen every axis (and double the step), is read the same way
    (:meth:`EmbeddedEstimate.difference`, with the pair of
    :func:`~gridlbc.accuracy.phase_pair`, which the shares leave out: where misaligned features make
    D, the shares do not add up to it and every axis is
    refined, :func:`~gridlbc.accuracy.tolerance.shares_add_up`).

    Returns
    -------
    shares : ndarray (d,)
    whole : float
        D.
    """
    X = judged_states(solution, states)
    grid, given = solution.grid, states is not None
    floor = given_floor(solution, X) if given else solution.temperature
    shares = np.full(grid.ndim, np.nan)
    for i in range(grid.ndim):
        coarse = embedded_grid(grid, axes=(i,))
        other = None if coarse is None else solve_on(coarse)
        if other is not None:
            shares[i] = statistic(relative_difference(solution, other, X, t, floor), given)
    v = solution.value(X, t)
    difference = solution.embedded.difference(solution, X, t)
    whole = statistic(relative_error(difference, v, floor), given)
    return shares, whole


def shares_add_up(shares: np.ndarray, whole: float, time_share: float = 0.0) -> bool:
    """Whether the per-axis shares (and the step's, ``time_share``) add up to at least half the
    embedded difference ``whole``: a first-order error splits into parts C_i h_i (and C_t Δt)
    whose sum the embedded solve, which coarsens everything, measures; where they do not add up
    the errors are not in that regime (the grids are too coarse for a per-component model)."""
    return bool(np.any(np.isfinite(shares)) and np.nansum(shares) + time_share >= 0.5 * whole)


@quiet_reads()
def axes_to_refine(
    solution, solve_on, states=None, time_share: float = 0.0
) -> tuple[list[int], np.ndarray]:
    """Which axes limit the accuracy of ``solution``, from each axis's share of the error
    (:func:`~gridlbc.accuracy.axis_shares`).

    Where the shares add up (:func:`~gridlbc.accuracy.tolerance.shares_add_up`), the axes whose
    share is at least half the largest are returned: refining the others alone would gain little.
    Where they do not, every axis is returned. Also returned: every share (NaN for an axis too
    coarse to coarsen).
    """
    shares, whole = axis_shares(solution, solve_on, states)
    if not shares_add_up(shares, whole, time_share):
        return list(range(len(shares))), shares
    return limiting_axes(shares), shares


def limiting_axes(shares) -> list[int]:
    """The axes whose share of an error is at least half the largest share (NaN: unknown, not
    chosen); every axis where none is known."""
    shares = np.asarray(shares, dtype=float)
    if not np.any(np.isfinite(shares)):
        return list(range(len(shares)))
    top = np.nanmax(shares)
    return [i for i in range(len(shares)) if not shares[i] < 0.5 * top]


def refinement_factors(errors, orders, tol: float) -> np.ndarray:
    """The least refinement that brings a sum of error components within ``tol``.

    With components e_k ≈ C_k h_k^(p_k) (``errors``, ``orders``: one per axis and one for the
    step), refining component k by r_k ≥ 1 (h_k → h_k / r_k) leaves Σ_k e_k r_k^(−p_k). The
    work grows as Π r_k; its least value with the sum at ``tol`` (Lagrange: log r_k =
    (log e_k − log u_k) / p_k) gives the refined components budgets u_k ∝ 1/p_k that share
    what the unrefined ones leave of ``tol``. A component already within its budget is not
    refined (r_k = 1), and the budgets are shared again among the others.

    Parameters
    ----------
    errors : array_like (m,)
        e_k ≥ 0 (NaN: unknown, not refined).
    orders : array_like (m,)
        p_k > 0.
    tol : float

    Returns
    -------
    ndarray (m,)
        r_k ≥ 1.
    """
    e = np.nan_to_num(np.asarray(errors, dtype=float), nan=0.0)
    p = np.asarray(orders, dtype=float) * np.ones_like(e)
    refined = e > 0
    while True:
        budget = tol - e[~refined].sum()
        weights = np.where(refined, 1.0 / p, 0.0)
        if not refined.any() or budget <= 0:
            break
        u = budget * weights / weights.sum()
        within = refined & (e <= u)
        if not within.any():
            break
        refined &= ~within
    r = np.ones_like(e)
    if refined.any() and budget > 0:
        r[refined] = (e[refined] / u[refined]) ** (1.0 / p[refined])
    return r


@dataclass(frozen=True)
class Refinement:
    """One solve of :func:`~gridlbc.accuracy.solve_to_tolerance`.

    Attributes
    ----------
    shape : tuple of int
        The grid's nodes per axis.
    dt : float
        The step.
    error : float
        The relative estimate at the states judged (:class:`Assessment`).
    time_error : float
        The part of it from the time step (a solve at 2Δt on the same grid), NaN if not measured.
    wall_time : float
        Seconds for this round: its solve, its estimates and, where another round followed,
        the comparison solves that chose it (the shares): what :attr:`predicted_seconds`
        predicts for a round.
    dtype : str
        How its slices were stored: ``"float64"`` or ``"float32"``.
    store_every : int
        It stored every ``store_every``-th step's slice (and the last).
    axis_errors : tuple of float
        Where it was followed by another round: each axis's share of the error, the relative
        difference from a solve with only that axis coarsened
        (:func:`~gridlbc.accuracy.axis_shares`). Empty otherwise.
    factors : tuple of float
        The refinement asked for after it, per axis and then for the step (h_i → h_i / r_i,
        Δt → Δt / r_t; 1: unchanged); the grid reached may be coarser where memory or
        ``max_nodes`` held it. Empty where it was the last round.
    reason : str
        Why the factors were not the model's own choice (:func:`~gridlbc.accuracy.unsteerable`, or
        levels that do not converge at first order); "" where they were.
    certified_error : float
        Where the embedded levels did not converge and the user gave few states: the relative
        error at those states measured against certified optima
        (:func:`~gridlbc.accuracy.certified_error`); NaN where it was not measured or the
        certificates could not say.
    observed_order : float
        The order p observed from the embedded levels (NaN where not measured): below 1 the
        round is judged by :func:`at_observed_order`.
    predicted_seconds : float
        The predicted :attr:`wall_time` of the round planned after this one, from this round's
        (:func:`predicted_seconds`), whether or not the budget ``max_seconds`` let it run; NaN
        where none was planned. Where the budget stopped the solve before the next round was
        planned (not even a round like this one fitted in the time left), the least it would
        take: this round's solve and estimates.
    """

    shape: tuple[int, ...]
    dt: float
    error: float
    time_error: float
    wall_time: float
    dtype: str = "float64"
    store_every: int = 1
    axis_errors: tuple[float, ...] = ()
    factors: tuple[float, ...] = ()
    reason: str = ""
    certified_error: float = np.nan
    predicted_seconds: float = np.nan
    observed_order: float = np.nan

    def met(self, tol: float) -> bool:
        """Whether this round proved ``tol``: by its estimate at the observed order
        (:func:`at_observed_order`; and the step's share where it was measured), or at certified
        states."""
        proved = at_observed_order(self.error, self.observed_order) <= tol
        return bool((proved and not self.time_error > tol) or self.certified_error <= tol)


def at_observed_order(error: float, order: float) -> float:
    """``error``, a relative estimate (Richardson's with an order q of at least 1), as a round to
    a tolerance is judged by: unchanged where the levels converge at first order or better (or
    were not compared, NaN), and where they converge more slowly, at their observed order p < 1,
    error / (2^p − 1) (infinite for p ≤ 0): the estimate divides the difference of the solves at
    h and 2h by 2^q − 1 ≥ 1, and a solve whose error shrinks as h^p is off by that difference
    divided by 2^p − 1, up to 1/(2^p − 1) times more (stranger round 27: an average cost's
    relative value along an axis without noise, whose levels converge far below first order,
    was said met while several times the tolerance off; docs page :doc:`accuracy`, "Solving to
    a tolerance")."""
    if not order < 1.0:
        return error
    return error / (2.0**order - 1.0) if order > 0.0 else np.inf


def confirmed(solution, tol: float, states, times, a: Assessment, order: float) -> Assessment:
    """A round's assessment ``a``, read again where the user gave ``states`` and ``a`` meets
    ``tol`` there (at the levels' observed ``order``, :func:`at_observed_order`): as
    :meth:`gridlbc.Solution.error_estimate` reads those states, with the whole remaining task's
    certificate beside the 8-step one (:func:`~gridlbc.accuracy.local_error`), so that a round
    is met only where the estimate the user will read meets ``tol`` too
    (:func:`~gridlbc.accuracy.solve_to_tolerance`). Without ``states``, or where ``a`` misses
    ``tol``, ``a`` itself."""
    if states is None or at_observed_order(a.error, order) > tol:
        return a
    whole = assess(solution, tol, states, times, whole=True)
    assert whole is not None  # the same solve and embedded estimate that gave ``a``
    return whole


@quiet_reads()
def _step_share(march: Marcher, solution, problem, settings, states, t: float = 0.0) -> float:
    """The step's share of the error of ``solution``: ê_t = abs(v_{h,2Δt} − v_{h,Δt}) relative to
    v (:func:`~gridlbc.accuracy.assessment.statistic` at the judged states, time ``t``), from one
    more solve on the same grid at twice the step (the error of a first-order step, or more)."""
    dt, steps = solution.diagnostics.dt, solution.diagnostics.steps
    half = _march_quietly(march, problem, settings, 2 * dt, steps, problem.grid, t)
    X = judged_states(solution, states)
    floor = None if states is None else given_floor(solution, X)
    return statistic(relative_difference(solution, half, X, t, floor), states is not None)


def unsteerable(embedded, error: float, shares, whole: float, time_share: float) -> str:
    """Why the measured shares cannot choose the next grid, or "" where they can.

    The per-component model e ≈ Σ_i C_i h_i^p + C_t Δt
    (:func:`~gridlbc.accuracy.refinement_factors`) steers where it describes the errors. Where it
    does not, the estimate says that the solve is poor, not which part to refine, and every axis and
    the step are refined: an estimate above 100 % of v (the coarser solves are not near v at all),
    or shares that do not add up to the embedded difference
    (:func:`~gridlbc.accuracy.tolerance.shares_add_up`)."""
    if not error <= 1.0:
        return f"estimate {error:.0%} above 100 % of v"
    total = np.nansum(shares) + time_share
    if not (total > 0 and shares_add_up(np.asarray(shares), whole, time_share)):
        return f"shares add up to {total:.3g} of the embedded difference {whole:.3g}"
    return ""


def fitting_plan(march: Marcher, problem, settings, factors, max_nodes: int | None = None):
    """The grid refined by ``factors`` (:func:`scaled_grid`), or by less where that would exceed
    ``max_nodes`` or the memory: the largest ``factors**α`` (α in [0, 1], bisected) whose grid
    fits, with its storage (:func:`~gridlbc.accuracy.tolerance.fitting_storage`).

    Returns
    -------
    problem : Problem or None
        On the chosen grid; None where no finer grid fits (``problem``'s own grid where no axis
        is to be refined).
    settings : SolverSettings or None
        Its storage.
    limit : str
        What held the grid below ``factors`` ("" if nothing did).
    """
    factors = np.asarray(factors, dtype=float)

    def attempt(alpha):
        grid = scaled_grid(problem.grid, factors**alpha)
        if max_nodes is not None and grid.size > max_nodes:
            return grid, f"the grid {grid.shape} would exceed max_nodes = {max_nodes}"
        return grid, fitting_storage(march, problem.replace(grid=grid), settings)

    grid, storage = attempt(1.0)
    if not isinstance(storage, str):
        return problem.replace(grid=grid), storage, ""
    limit = storage
    if np.all(factors <= 1.0):
        return None, None, limit
    lo, hi, best = 0.0, 1.0, None
    for _ in range(8):
        mid = 0.5 * (lo + hi)
        grid, storage = attempt(mid)
        if isinstance(storage, str):
            hi = mid
        else:
            lo = mid
            if grid.shape != problem.grid.shape:
                best = (grid, storage)
    if best is None:
        return None, None, limit
    return problem.replace(grid=best[0]), best[1], limit


UNPOSED = np.inf
"""The error a round of a solve to a tolerance records where the grid with every other node
cannot pose the problem (an exit set that holds none of its nodes): no estimate, so every axis
is refined by 2 (and the step), until that coarser grid holds the set."""


MARCH_WORK_EXPONENT = 1.0
"""The power of the work ratio (nodes × steps) by which :func:`~gridlbc.accuracy.solve_to_tolerance`
scales a round's time to predict the next one's (:func:`predicted_seconds`): a time-marched solve,
its embedded solves and its comparison solves all cost a fixed amount per node and step."""


def predicted_seconds(seconds: float, work: float, planned: float, exponent: float) -> float:
    """The seconds a round of ``planned`` work should take after one of ``work`` took
    ``seconds``: ``seconds · (planned / work)^exponent`` (work: nodes × steps for a time march,
    :data:`MARCH_WORK_EXPONENT`; nodes for a first-exit solve, the exponent of
    :func:`gridlbc.stationary.stationary_work_exponent`)."""
    return float(seconds * (planned / work) ** exponent)


def check_budget(max_seconds) -> None:
    """A clear error unless ``max_seconds`` is None or a positive finite number of seconds."""
    if max_seconds is None:
        return
    if (
        isinstance(max_seconds, bool)
        or not isinstance(max_seconds, numbers.Real)
        or not (math.isfinite(max_seconds) and float(max_seconds) > 0)
    ):
        raise ValueError(
            "max_seconds must be a positive finite number of seconds (or None: no budget), "
            f"e.g. 300; got {max_seconds!r}"
        )


def over_budget(
    max_seconds: float | None, spent: float, plan: str, seconds: float, least: bool = False
) -> str:
    """The message saying that the time budget stops a solve to a tolerance: ``spent`` seconds
    so far, and the next round (``plan``) would take ``seconds`` (``least``: at least that),
    past ``max_seconds``; "" where it fits (or there is no budget)."""
    if max_seconds is None or spent + seconds <= max_seconds:
        return ""
    about = "at least about" if least else "about"
    return (
        f"the time budget stopped it: {spent:.3g} s spent, and the next round, {plan}, would "
        f"take {about} {seconds:.3g} s: beyond max_seconds = {max_seconds:g}"
    )


def solve_to_tolerance(
    problem,
    tol: float,
    states=None,
    settings=None,
    max_nodes: int | None = None,
    max_refinements: int = 8,
    max_seconds: float | None = None,
    times=None,
    *,
    march: Marcher,
    **options,
):
    """Solve ``problem`` again and again until the embedded estimate meets ``tol``.

    Each round solves on the current grid with the current step and reads the relative estimate
    ê (:func:`assess`). If it exceeds ``tol``, it measures the step's share ê_t = abs(v_{h,2Δt} −
    v_{h,Δt}) and each axis's share (:func:`~gridlbc.accuracy.axis_shares`: solves at the same step
    with one axis coarsened at a time), both at the time where ê was read (0, or late in the task
    where the check there found the larger error, :func:`~gridlbc.accuracy.assessment.late_times`),
    and chooses the next grid and step:

    - in the model's range (:func:`~gridlbc.accuracy.unsteerable` says nothing), the factors that
      bring the sum of the shares, scaled to add up to ê and extrapolated with the observed order q
      for the axes and 1 for the step, to ``tol`` at the least work
      (:func:`~gridlbc.accuracy.refinement_factors`), each at most the *reach*: 2 until a round's
      estimate comes within 2× of the model's prediction for it, doubled by each round that does,
      back to 2 by one that does not; where the levels do not converge at first order (observed
      order below 1), only the shares at least half the largest are refined, by at most 2;
    - outside it, every axis by 2 with the scheme's default step for the finer grid (or half
      the current step once one has been set).

    At the user's ``states`` each round reads the local certificate over 8 steps; a round whose
    estimate meets ``tol`` there is read again as :meth:`gridlbc.Solution.error_estimate` reads
    them, with the whole remaining task's certificate beside it
    (:func:`~gridlbc.accuracy.local_error`), and is met only if that meets ``tol`` too: an error
    that a state shares with every state its paths reach soon is seen only so (stranger round
    44's first exit across an axis without noise).

    A round whose estimate meets ``tol`` is confirmed by the step's own share ê_t (the solve
    at 2Δt on the same grid): the embedded solve doubles the step and coarsens the grid at
    once, and where the two errors it changes cancel (a drift that changes faster along a path
    than the step follows, whose error the coarser grid happens to offset) it reads far less
    than either. Where ê_t exceeds ``tol`` the step alone is refined, by ê_t / tol (at most the
    reach). And a round is not met where the drift changes between the nodes faster than the
    grid follows (:func:`~gridlbc.accuracy.flow_excess`: F
    ≥ :data:`~gridlbc.accuracy.flow.FLOW_CELLS` cells a step and an observed order that is
    not :func:`~gridlbc.accuracy.followed`): the coarser solves step over such a gust alike, and the
    step is refined until F is below :data:`~gridlbc.accuracy.flow.FLOW_CELLS` (F ∝ Δt/h: by
    F/:data:`~gridlbc.accuracy.flow.FLOW_CELLS` times the largest axis factor); if the solve ends
    with it unresolved, it warns as the default solve does (:func:`~gridlbc.accuracy.check_flow`,
    which also judges the noise).

    Where the levels do not converge (the estimate is then rough in either direction) and the
    user gave at most :data:`CERTIFIED_STATES` states, a round whose estimate misses ``tol`` is
    also judged by certificates at those states (:func:`~gridlbc.accuracy.certified_error`), and
    ends the solve if they prove it (:attr:`Refinement.certified_error`).

    The grid is the one with each axis's spacing divided by its factor (:func:`scaled_grid`);
    where it would exceed ``max_nodes`` or the memory, the factors are reduced together to the
    largest grid that fits (:func:`~gridlbc.accuracy.fitting_plan`: its slices stored as float32,
    then only every k-th, :func:`~gridlbc.accuracy.tolerance.fitting_storage`); if not even a
    slightly finer grid fits, Δt is halved instead and the limit is reported.

    Before each round after the first, its time is predicted from the last round's: that
    round's wall time (its solve, estimates and the comparison solves that steered it) times
    the ratio of the work, nodes × steps (steps = T/Δt), of the planned round to the last
    one's (:func:`predicted_seconds`; the march, the embedded solves and the comparison solves
    all cost a fixed amount per node and step). With ``max_seconds``, a round whose predicted
    time would take the total past it is not started: the solve stops with the last solution
    and a :class:`gridlbc.ResolutionWarning` giving the estimate reached and the predicted time
    of the next round. A round is not steered either (no comparison solves) where the time left
    would not hold even a round on the same grid and step. The prediction is in
    :attr:`Refinement.predicted_seconds` and printed with ``progress=True``, or with
    ``progress=None`` (the default) where it exceeds :data:`gridlbc.progress.DELAY`. The first
    round always runs: nothing has been measured to predict it from.

    Parameters
    ----------
    problem : Problem
        The problem; its grid is the first one tried.
    tol : float
        The relative tolerance on v (see :func:`~gridlbc.accuracy.estimate.relative_error`; at
        given ``states``, relative to abs(v(x, 0)): :func:`~gridlbc.accuracy.estimate.given_floor`),
        in (0, 1).
    states : array_like (N, d), optional
        Where the tolerance must hold; default :func:`states_that_matter`
        (at :data:`~gridlbc.accuracy.assessment.QUANTILE`).
    times : sequence of float, optional
        With ``states``: the times in [0, T] at which it must hold there (default: 0 and
        :func:`~gridlbc.accuracy.assessment.late_times`, late in the task where a step errs most).
    settings : SolverSettings or str, optional
        As for :func:`gridlbc.solve`.
    max_nodes : int, optional
        Refine the grid no further than this many nodes (default: what the memory allows).
    max_refinements : int
        At most this many rounds after the first.
    max_seconds : float, optional
        A wall-clock budget in seconds for the whole solve: no round starts whose predicted time
        would exceed what is left of it. Default None: no budget. The tolerance is what was
        asked for, and a default budget would make the grid reached, and so the answer, depend
        on the machine's speed and load; ``max_refinements`` and the memory already bound the
        work, and each long round's prediction is printed before it starts (every round's with
        ``progress=True``), so a long solve is announced rather than cut short. Give one where
        the time matters more than ``tol``.
    march : Marcher
        The solver's time march (:func:`gridlbc.solve` passes ``gridlbc.solver.MARCH``).
    **options
        Settings fields, as for :func:`gridlbc.solve`.

    Returns
    -------
    Solution
        The last solution, with :attr:`~gridlbc.Solution.refinement` (one :class:`Refinement` per
        round). A :class:`gridlbc.ResolutionWarning` says what stopped it if ``tol`` was not met.
    """
    check_tolerance(tol, options)
    check_budget(max_seconds)
    times = judged_times(problem, states, times)
    clock = time.perf_counter()
    base = march.settings_for(problem, settings, options)
    dt = base.dt
    history: list[Refinement] = []
    limit = ""
    coarser = None  # (problem, step) of the last round, to return to if a finer grid won't fit
    # The model is trusted to extrapolate as far as it has been checked: a factor of 2 (the span
    # its shares were measured over) until a round's estimate comes within 2× of what the model
    # predicted for it; each such round doubles the reach, a miss resets it.
    reach, predicted = 2.0, np.nan
    measured = None  # (seconds, nodes × steps) of the last round run: what predicts the next
    flow = 0.0  # F of the last round where the grid does not follow the drift (flow_excess)
    while True:
        if measured is not None:
            planned_dt, n = march.planned_step(problem, dataclasses.replace(base, dt=dt))
            seconds = predicted_seconds(*measured, problem.grid.size * n, MARCH_WORK_EXPONENT)
            history[-1] = dataclasses.replace(history[-1], predicted_seconds=seconds)
            plan = f"grid {'×'.join(map(str, problem.grid.shape))} with dt {planned_dt:.4g}"
            spent = time.perf_counter() - clock
            if base.progress or (base.progress is None and seconds > progress.DELAY):
                print(
                    f"tol: the next round, {plan}, should take about {seconds:.3g} s "
                    f"({spent:.3g} s spent)",
                    flush=True,
                )
            stop = over_budget(max_seconds, spent, plan, seconds)
            if stop:
                limit = stop
                break
        started = time.perf_counter()
        try:
            (solution,), round_warnings = holding(
                partial(
                    march.solve_many,
                    problem,
                    [problem.terminal_cost],
                    base,
                    dt=dt,
                    error_estimate=True,
                )
            )
        except MemoryError:
            if coarser is None:
                raise
            # the finer grid does not fit after all: stay on the last one, halve its step
            limit = f"memory: the grid {problem.grid.shape} does not fit in the memory available"
            problem, dt = coarser[0], coarser[1] / 2
            coarser = None
            continue
        a = assess(solution, tol, states, times)
        if a is None and embedded_grid(problem.grid) is None:
            raise unestimated(problem.grid)
        order = np.nan if solution.embedded is None else solution.embedded.observed_order
        if a is not None:
            a = confirmed(solution, tol, states, times, a, order)
        error = UNPOSED if a is None else a.error  # None: refine until the coarser grid poses it
        when = 0.0 if a is None else a.time  # where the error was read: the shares are read there
        solved = time.perf_counter() - started  # the least a round on a grid as fine takes
        held = predicted / 2 <= error <= 2 * predicted
        reach, predicted = (2 * reach if held else 2.0), np.nan
        time_error = certified = np.nan
        proved = at_observed_order(error, order)  # the estimate, where the levels converge
        # where the levels do not converge, whatever the estimate (certifiable); certificates
        # read t = 0: they cannot vouch for an estimate late in the task
        if a is not None and a.late_error <= tol and certifiable(solution, states):
            certified = certified_error(solution, judged_states(solution, states), tol)
        cells, flow_order, _ = flow_excess(solution)
        flow = cells if cells >= FLOW_CELLS and not followed(flow_order) else 0.0
        if proved <= tol and not flow:  # confirmed by the step's own share
            time_error = _step_share(march, solution, problem, base, states, when)
        met = (proved <= tol and not flow and time_error <= tol) or certified <= tol
        done = met or len(history) >= max_refinements
        least = np.nan  # where the time left would not hold even a round like this one
        if not done and max_seconds is not None:
            here = f"grid {'×'.join(map(str, problem.grid.shape))} or finer"
            stop = over_budget(max_seconds, time.perf_counter() - clock, here, solved, least=True)
            if stop:
                done, limit, least = True, stop, solved
        if not done and proved > tol:
            time_error = _step_share(march, solution, problem, base, states, when)
        history.append(
            Refinement(
                problem.grid.shape,
                solution.diagnostics.dt,
                error,
                time_error,
                time.perf_counter() - started,
                base.dtype,
                base.store_every,
                certified_error=certified,
                predicted_seconds=least,
                observed_order=order,
            )
        )
        if base.progress:
            stored = (
                "" if base.store_every == 1 else f", a slice stored every {base.store_every} steps"
            )
            told = "" if np.isnan(certified) else f", certified at the states {certified:.2%}"
            if proved > error:
                told += f", {proved:.2%} at the levels' observed order {order:.2f}"
            print(
                f"tol: grid {'×'.join(map(str, problem.grid.shape))}, dt {solution.diagnostics.dt:.4g}"
                f" ({base.dtype}{stored}): estimated error {error:.2%}{told}",
                flush=True,
            )
        if done:
            break
        step, steps = solution.diagnostics.dt, solution.diagnostics.steps
        solve_on = partial(_march_quietly, march, problem, base, step, steps, t=when)
        embedded = solution.embedded
        shares = np.full(problem.grid.ndim, np.nan)
        factors = np.ones(problem.grid.ndim + 1)  # met but for the step or the flow: the step
        reason = ""
        if proved <= tol and time_error > tol:  # the estimate met tol, the step's share did not
            factors[-1] = min(time_error / tol, reach)
            reason = f"the step's own share {time_error:.2%} (the estimate {error:.2%})"
        elif proved > tol:
            if embedded is None:
                reason = "no estimate: the grid with every other node cannot pose the problem"
            else:
                shares, whole = axis_shares(solution, solve_on, states, when)
                reason = unsteerable(embedded, error, shares, whole, time_error)
            if reason:  # every axis and the step, by 2 (the scheme's step for the finer grid)
                factors[:] = 2.0
            else:
                assert embedded is not None  # unsteerable says why where it is missing
                components = np.append(shares, time_error)
                orders = np.append(np.full(problem.grid.ndim, embedded.order), 1.0)
                scale = error / np.nansum(components)  # the components add up to the estimate
                factors = np.minimum(refinement_factors(scale * components, orders, tol), reach)
                if not embedded.converging:
                    # levels not converging at first order: the shares, measured between h and
                    # 2h, say which parts limit the error but not how far beyond h/2 the model
                    # holds: refine by 2 those at least half the largest (the others alone
                    # gain little)
                    top = np.nanmax(components)
                    chosen = np.minimum(factors, 2.0) if error > tol else 2.0
                    factors = np.where(components >= 0.5 * top, chosen, 1.0)
                    reason = (
                        f"observed order {embedded.observed_order:.2f} < 1: the largest shares by 2"
                    )
                else:
                    predicted = float(np.nansum(scale * components * factors**-orders))
        if flow:  # F = max |a − I a| Δt / h, ∝ Δt and at most ∝ 1/h on the grid refined
            factors[-1] = max(factors[-1], flow / FLOW_CELLS * factors[:-1].max())
            reason = "; ".join(
                filter(None, [reason, f"the drift between the nodes: {flow:.2g} cells a step"])
            )
        history[-1] = dataclasses.replace(
            history[-1],
            axis_errors=tuple(shares.tolist()),
            factors=tuple(factors.tolist()),
            reason=reason,
        )
        if base.progress:
            plan = "refine by " + ", ".join(f"{f:.2f}" for f in factors)
            plan += f" ({reason})" if reason else ""
            print(f"tol: shares {np.round(shares, 4)}, step {time_error:.4f}: {plan}", flush=True)
        if np.all(factors == 2.0) and not flow:
            next_dt = None if dt is None else step / 2
        else:
            next_dt = step / factors[-1]
        finer, storage, capped = fitting_plan(
            march, problem, dataclasses.replace(base, dt=next_dt), factors[:-1], max_nodes
        )
        if finer is not None and next_dt is None:
            # the scheme's step for the finer grid, but at most half this one: it does not
            # shrink with the grid where nothing sets a rate (no drift, no state cost: T/10)
            default, _ = march.planned_step(finer, dataclasses.replace(storage, dt=None))
            next_dt = min(default, step / 2)
        if finer is not None:
            next_dt = min(next_dt, base.scheme.step_bound(finer).limit)
        seconds = time.perf_counter() - started
        history[-1] = dataclasses.replace(history[-1], wall_time=seconds)
        measured = (seconds, problem.grid.size * steps)
        if finer is None:  # not even a slightly finer grid fits: the step is all that is left
            limit = capped
            dt = step / 2 if next_dt is None or next_dt >= step else next_dt
            continue
        limit = capped
        base = dataclasses.replace(storage, dt=base.dt)
        coarser = (problem, step)
        problem, dt = finer, next_dt
    where = f"{'×'.join(map(str, solution.grid.shape))} with dt {solution.diagnostics.dt:.4g}"
    advice = "raise max_refinements or max_nodes, store float32 or use mmap_dir"
    if limit.startswith("the time budget"):
        advice = "raise max_seconds or loosen tol"
    finish(solution, tol, history, where, limit, max_refinements, advice)
    check_flow(solution)  # the returned solve's drift and noise, read once (held above)
    tell_held(round_warnings)
    return solution


def judged_times(problem, states, times) -> tuple[float, ...] | None:
    """``times`` checked (:func:`~gridlbc.accuracy.solve_to_tolerance`): a non-empty sequence of
    times in [0, T], given with ``states``; None where not given."""
    if times is None:
        return None
    if states is None:
        raise TypeError(
            "times= says when the given states= are judged: give states too (without them a "
            "solve is judged at the states that matter at t = 0 and late in the task)"
        )
    out = tuple(float(t) for t in np.atleast_1d(np.asarray(times, dtype=float)))
    horizon = problem.require_horizon("times=")
    if not out or not all(0.0 <= t <= horizon for t in out):
        raise ValueError(
            f"times must be one or more times in [0, T] = [0, {horizon:g}], got {times!r}"
        )
    return out


def holding(solve: Callable[[], Solved]) -> tuple[Solved, list]:
    """``solve()``, one round of a solve to a tolerance, with its gridlbc warnings held back
    (other warnings pass as they come): the rounds before the last are refined away, and what
    their solves warned of is not the user's; the last round's are told at the end
    (:func:`tell_held`)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", GridlbcWarning)
        solution = solve()
    held = [w for w in caught if issubclass(w.category, GridlbcWarning)]
    for w in caught:
        if w not in held:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return solution, held


def tell_held(held: list) -> None:
    """Warn again of what the returned round's solve warned of (:func:`holding`), but of its
    estimate, which :func:`~gridlbc.accuracy.tolerance.finish` reports with the rounds, and of the drift and the noise,
    which :func:`~gridlbc.accuracy.check_flow` reads once more for the solution returned."""
    for caught in held:
        text = str(caught.message)
        if not text.startswith((ESTIMATE_WARNING, FLOW_WARNING, NOISE_WARNING)):
            warn_user(text, caught.category)


def _march_quietly(
    march: Marcher, problem, settings, dt: float, steps: int, grid: Grid, t: float = 0.0
):
    """``problem`` solved on ``grid`` with step ``dt``, its warnings silenced and no estimate: a
    comparison solve of :func:`~gridlbc.accuracy.solve_to_tolerance`, read at time ``t``. It stores
    only the first and last slices (at most ``steps`` steps) where it is read at t = 0, its slices
    as ``settings`` store them where it is read later (between them, as the solve it is compared
    with)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridlbcWarning)
        return march.solve_many(
            problem.replace(grid=grid),
            [problem.terminal_cost],
            settings,
            dt=dt,
            error_estimate=False,
            store_every=steps if t == 0.0 else settings.store_every,
        )[0]


def held_memory(need: dict, ndim: int, store_every: int) -> float:
    """The bytes that a solve planned as ``need`` (:func:`gridlbc.solver.planned_memory`) holds
    with its estimate: its own, and the coarser solves' slices, (r₂ + 1) 2^−d + r₄ 4^−d of its
    slices' bytes. The embedded solve (2^−d of the nodes, half the steps) and the one below it
    (4^−d, a quarter) store every k-th of their steps
    (:func:`~gridlbc.accuracy.embedded_store_every`), r₂ = store_every / 2k and
    r₄ = store_every / 4k of the solve's slice count; the two solves on the pair of grids
    (:func:`~gridlbc.accuracy.phase_pair`) store as the solve does, half as many slices each."""
    r2 = store_every / (2 * embedded_store_every(store_every, 2))
    r4 = store_every / (4 * embedded_store_every(store_every, 4))
    return need["ram"] + need["stored"] * ((r2 + 1) * 2.0**-ndim + r4 * 4.0**-ndim)


def fitting_storage(march: Marcher, problem, settings):
    """``settings`` for a solve of ``problem`` whose slices fit in the memory available, or a
    message saying why none do.

    The slices of every stored step dominate a time-marched solve's memory. If they do not fit,
    they are stored as float32 (the march itself stays in double precision), then only every
    k-th step's slice is stored (k = 2, 4, …: the value at t = 0, which the tolerance judges, is
    unchanged; the value and the policy between stored slices are interpolated in time). The
    embedded solve is held with the solution, and so are the solves on the pair of grids
    (:func:`~gridlbc.accuracy.phase_pair`): :func:`held_memory` counts their slices."""
    available = available_memory()
    if available is None:
        return settings
    candidate, stored = settings, None
    while True:
        need = march.planned_memory(problem, candidate)
        held = held_memory(need, problem.grid.ndim, candidate.store_every)
        if held <= 0.9 * available:
            return candidate
        if candidate.dtype == "float64":
            candidate = dataclasses.replace(candidate, dtype="float32")
        elif need["stored"] != stored:  # fewer slices still help
            stored = need["stored"]
            candidate = dataclasses.replace(candidate, store_every=2 * candidate.store_every)
        else:
            return (
                f"memory: the grid {problem.grid.shape} would need about {held / 2**30:.1f} GiB "
                f"of {available / 2**30:.1f} GiB available even storing few slices"
            )


def unestimated(grid: Grid) -> ValueError:
    """The error of a solve to a tolerance on a ``grid`` too coarse to embed: no estimate to judge
    (where only the problem cannot be posed on the grid with every other node, the solve refines
    instead: :data:`UNPOSED`)."""
    return ValueError(
        f"the grid {grid.shape} is too coarse to embed a grid with every other node (each axis "
        "needs at least 5 nodes): give a finer grid"
    )


def check_tolerance(tol, options: dict) -> None:
    """A clear error unless ``tol`` is a relative error in (0, 1) and the ``options`` keep the
    embedded estimate that a solve to a tolerance reads."""
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise TypeError(f"tol must be a number, a relative error in (0, 1), e.g. 0.02; got {tol!r}")
    if not 0 < float(tol) < 1:
        raise ValueError(f"tol must be a relative error in (0, 1), e.g. 0.02; got {tol!r}")
    if options.get("error_estimate") is False:
        raise ValueError("tol needs the embedded estimate: drop error_estimate=False")


def finish(
    solution, tol: float, history: list, where: str, limit: str, rounds: int, advice: str
) -> None:
    """Record the ``history`` of a solve to a tolerance on ``solution`` and warn
    (:class:`gridlbc.ResolutionWarning`) if its last round did not prove ``tol``
    (:meth:`~gridlbc.accuracy.Refinement.met`: an estimate above it, or below it from levels that
    do not converge at first order), saying ``where`` it stopped, why (``limit``, or the
    ``rounds`` spent) and what to change (``advice``)."""
    object.__setattr__(solution, "refinement", tuple(history))
    last = history[-1]
    if not last.met(tol):
        why = limit or f"max_refinements = {rounds} rounds were spent"
        certified = (
            ""
            if np.isnan(last.certified_error)
            else f" (certified at your states: {last.certified_error:.1%})"
        )
        step = (
            f" (the step's own share, from a solve at twice the step: {last.time_error:.1%})"
            if last.error <= tol < last.time_error
            else ""
        )
        digits = 1 if f"{last.error:.1%}" != f"{tol:.1%}" else 2  # 10.02 % is not 10.0 %
        reached = f"reached an estimated error of {last.error:.{digits}%}"
        proved = at_observed_order(last.error, last.observed_order)
        if np.isfinite(proved) and proved > last.error:
            reached += f" ({proved:.1%} at its levels' observed order {last.observed_order:.2f})"
        reached += f"{step}{certified} on {where}"
        if last.error <= tol and not step and proved > tol:
            slow = (
                f"{proved:.1%} at the order its coarser levels converge at "
                f"({last.observed_order:.2f}, below 1)"
                if np.isfinite(proved)
                else f"from coarser levels that do not converge (observed order "
                f"{last.observed_order:.2f}), which cannot prove {tol:.1%}"
            )
            reached = (
                f"stopped on {where} with an estimated error of {last.error:.1%}{certified}, {slow}"
            )
        else:
            reached += f", not {tol:.{digits}%}"
        warn_user(f"solve(tol={tol:g}) {reached}: {why}; {advice}", ResolutionWarning)
