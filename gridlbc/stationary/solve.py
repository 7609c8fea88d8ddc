"""The stationary solves as :func:`gridlbc.solve` runs them: first exit or average cost on the
grid, with the embedded solves that carry the error estimate (:mod:`gridlbc.accuracy.embedding`),
and to a tolerance (:func:`~gridlbc.stationary.solve_stationary_to_tolerance`)."""

from __future__ import annotations

import dataclasses
import time
import warnings
from functools import partial
from typing import cast

import numpy as np

from ..accuracy import (
    UNPOSED,
    Refinement,
    assess,
    average_truncation,
    axes_to_refine,
    check_budget,
    check_scalar,
    check_tolerance,
    confirmed,
    embedded_grid,
    finish,
    holding,
    limiting_axes,
    over_budget,
    predicted_seconds,
    refined_grid,
    scalar_estimate,
    scalar_relative,
    stationary_gap,
    tell_held,
    unestimated,
)
from ..accuracy.embedding import embed
from ..accuracy.estimate import quiet_reads
from ..errors import (
    ConvergenceError,
    GridlbcWarning,
)
from ..grid import Grid
from ..problem import Problem
from ..solution import StationarySolution
from ..storage import available_memory
from .average import solve_average_cost
from .first_exit import solve_first_exit, solve_first_exit_many
from .linear import (
    BYTES_PER_NODE,
    StationarySettings,
    linear_method,
    stationary_settings,
    stationary_work_exponent,
)


def solve_stationary_to_tolerance(
    problem: Problem,
    tol: float,
    states=None,
    max_nodes: int | None = None,
    max_refinements: int = 6,
    max_seconds: float | None = None,
    **options,
) -> StationarySolution:
    """Solve a first-exit or an average-cost problem on finer and finer grids (h → h/2 along the
    axes that limit it) until its embedded error estimate meets ``tol`` from levels that converge
    at first order or better (:meth:`gridlbc.accuracy.Refinement.met`), or ``max_nodes``, the
    memory, ``max_refinements`` or the time budget ``max_seconds`` stops it (then a
    :class:`gridlbc.ResolutionWarning` says which). :func:`gridlbc.solve` calls this for
    ``solve(problem, tol=...)``.

    A round's error is the relative estimate of v at ``states`` (:func:`gridlbc.accuracy.assess`;
    where it meets ``tol`` at the user's states, as :meth:`gridlbc.Solution.error_estimate` reads
    them, :func:`gridlbc.accuracy.confirmed`);
    for the average cost, the larger of that of the relative value h and c's own,
    ê_c / c (``average_cost_error``, :func:`gridlbc.accuracy.estimate.scalar_estimate`): c is what
    an average-cost solve is asked for first, and h's estimate does not bound it. The axes refined
    are those whose share of the larger error is at least half the largest share: h's shares by
    :func:`gridlbc.accuracy.tolerance.axes_to_refine`, c's
    by :func:`~gridlbc.stationary.solve.shares_of_c`, from the same solves with one axis coarsened.

    Before each refinement its round's time (the solve, its embedded solves and the solves with
    one axis coarsened that steer the next) is predicted from the last round's: its wall time
    times the ratio of the nodes to the power
    :func:`~gridlbc.stationary.stationary_work_exponent` (measured for the linear solvers); a
    round that would take the total past ``max_seconds`` is not started
    (:attr:`gridlbc.accuracy.Refinement.predicted_seconds`), nor steered where the time left would
    not hold even a round on the same grid.

    Parameters
    ----------
    problem : Problem
        A problem without a horizon (first exit) or with ``horizon="average"``; its grid is the
        first one tried.
    tol : float
        The relative tolerance on v (on h and c for the average cost), in (0, 1).
    states : array_like (N, d), optional
        Where v (h) must meet it (default: the states that matter).
    max_nodes : int, optional
        Refine no further than this many nodes.
    max_refinements : int
        At most this many refinements.
    max_seconds : float, optional
        A wall-clock budget in seconds (default None: none), as for
        :func:`gridlbc.accuracy.solve_to_tolerance`.
    **options
        :class:`~gridlbc.stationary.linear.StationarySettings` fields.

    Returns
    -------
    StationarySolution
        The last solve, with :attr:`~gridlbc.Solution.refinement` (one
        :class:`~gridlbc.accuracy.Refinement` per grid, ``dt`` 0).
    """
    check_tolerance(tol, options)
    check_budget(max_seconds)
    clock = time.perf_counter()
    s = stationary_settings(options)
    history: list[Refinement] = []
    limit = ""
    while True:
        started = time.perf_counter()
        solution, round_warnings = holding(partial(_solved, problem, s))
        a = assess(solution, tol, states)
        if a is None and embedded_grid(solution.grid) is None:
            raise unestimated(solution.grid)
        order = np.nan if solution.embedded is None else solution.embedded.observed_order
        if a is not None:
            a = confirmed(solution, tol, states, None, a, order)
        error = UNPOSED if a is None else a.error  # None: refine until the coarser grid poses it
        c_error = _relative_error_of_c(solution)
        solved = time.perf_counter() - started
        history.append(
            Refinement(
                solution.grid.shape,
                0.0,
                max(error, c_error),
                np.nan,
                solved,
                observed_order=order,
            )
        )
        if history[-1].met(tol) or len(history) > max_refinements:
            break
        here = f"grid {'×'.join(map(str, solution.grid.shape))} or finer"
        limit = over_budget(max_seconds, time.perf_counter() - clock, here, solved, least=True)
        if limit:  # not even a round on this grid fits in the time left: no need to steer
            history[-1] = dataclasses.replace(history[-1], predicted_seconds=solved)
            break
        if a is None:  # the grid with every other node cannot pose the problem: every axis
            axes, shares = list(range(solution.grid.ndim)), np.full(solution.grid.ndim, np.nan)
        else:
            coarsened: dict[tuple[int, ...], StationarySolution | None] = {}
            axes, shares = axes_to_refine(
                solution, partial(_solve_quietly, problem, s, kept=coarsened), states
            )
            if c_error > error:
                axes, shares = shares_of_c(solution, coarsened)
        finer = refined_grid(solution.grid, axes)
        seconds = time.perf_counter() - started
        method = linear_method(s, finer.ndim, finer.size)
        exponent = stationary_work_exponent(method, finer.ndim)
        predicted = predicted_seconds(seconds, solution.grid.size, finer.size, exponent)
        history[-1] = dataclasses.replace(
            history[-1],
            axis_errors=tuple(shares.tolist()),
            wall_time=seconds,
            predicted_seconds=predicted,
        )
        available = available_memory()
        if max_nodes is not None and finer.size > max_nodes:
            limit = f"the grid {finer.shape} would exceed max_nodes = {max_nodes}"
        elif available is not None and BYTES_PER_NODE * finer.size > 0.9 * available:
            limit = f"memory: the grid {finer.shape} would need about " + (
                f"{BYTES_PER_NODE * finer.size / 2**30:.1f} GiB of {available / 2**30:.1f} GiB"
            )
        if not limit:
            plan = f"grid {'×'.join(map(str, finer.shape))}"
            limit = over_budget(max_seconds, time.perf_counter() - clock, plan, predicted)
        if limit:
            break
        problem = problem.replace(grid=finer)
    where = "×".join(map(str, solution.grid.shape))
    advice = "raise max_refinements or max_nodes"
    if limit.startswith("the time budget"):
        advice = "raise max_seconds or loosen tol"
    finish(solution, tol, history, where, limit, max_refinements, advice)
    tell_held(round_warnings)
    return solution


def _relative_error_of_c(solution: StationarySolution) -> float:
    """ê_c / c of an average-cost solve (0 for first exit; 0 where both are 0)."""
    if solution.average_cost_error is None:
        return 0.0
    return scalar_relative(solution.average_cost_error, _average_cost(solution))


@quiet_reads()
def shares_of_c(solution: StationarySolution, coarsened: dict) -> tuple[list[int], np.ndarray]:
    """Each axis's share of c's error, abs(c_i − c) / c with c_i from the solve with that axis
    alone coarsened (``coarsened``, by grid shape; NaN where there is none), and the axes whose
    share is at least half the largest (every axis where none is known)."""
    c = _average_cost(solution)
    shares = np.full(solution.grid.ndim, np.nan)
    for i in range(solution.grid.ndim):
        grid = embedded_grid(solution.grid, axes=(i,))
        other = None if grid is None else coarsened.get(grid.shape)
        if other is not None and c != 0:
            shares[i] = abs(_average_cost(other) - c) / abs(c)
    return limiting_axes(shares), shares


def _solve_quietly(problem: Problem, s: StationarySettings, grid: Grid, kept=None):
    """The stationary solve of ``problem`` on ``grid`` without its estimate and warnings, or None
    where the exit set or the costs are not resolved on that grid or its solve did not converge;
    also kept in ``kept`` (a dict, by the grid's shape) where given."""
    solve = solve_average_cost if problem.average_cost else solve_first_exit
    try:
        solution = _quietly(solve, problem.replace(grid=grid), s)
    except (ValueError, ConvergenceError):
        solution = None
    if kept is not None:
        kept[grid.shape] = solution
    return solution


def solve_stationary_many(problem: Problem, exit_costs, **options) -> list:
    """:func:`gridlbc.solve_many` for a first-exit problem: one operator, several exit costs
    (:func:`~gridlbc.stationary.solve_first_exit_many`), each solution with its embedded
    estimate.

    Parameters
    ----------
    problem : Problem
        With ``horizon=None`` and an exit set.
    exit_costs : sequence of callable
        The exit costs g_i.
    **options
        :class:`~gridlbc.stationary.linear.StationarySettings` fields.

    Returns
    -------
    list of StationarySolution
    """
    s = stationary_settings(options)
    exit_costs = list(exit_costs)
    solutions = solve_first_exit_many(problem, exit_costs, s)
    if s.error_estimate:
        _embed_many(problem, exit_costs, s, solutions)
    return solutions


def solve_stationary(problem: Problem, **options) -> StationarySolution:
    """Solve a stationary problem: first exit (``horizon=None``) or average cost
    (``horizon="average"``); :func:`gridlbc.solve` calls this for them.

    Parameters
    ----------
    problem : Problem
    **options
        :class:`~gridlbc.stationary.linear.StationarySettings` fields.

    Returns
    -------
    StationarySolution
    """
    return _solved(problem, stationary_settings(options))


def _solved(problem: Problem, s: StationarySettings) -> StationarySolution:
    """:func:`solve_stationary` with its settings: the solve, and its estimate unless
    ``s.error_estimate`` is False."""
    if not problem.average_cost:
        solution = solve_first_exit(problem, s)
        if s.error_estimate:
            _embed(problem, s, solution)
        return solution
    solution = solve_average_cost(problem, s, distribution=s.error_estimate)
    if s.error_estimate:
        _embed_average(problem, s, solution)
    return solution


def _embed(problem: Problem, s: StationarySettings, solution: StationarySolution) -> None:
    """Attach the embedded estimate to one solution (:func:`_embed_many`)."""
    _embed_many(problem, [problem.exit_cost], s, [solution])


def _embed_many(problem: Problem, exit_costs, s: StationarySettings, solutions) -> None:
    """Attach to each solution its embedded estimate (:func:`gridlbc.accuracy.embedding.embed`):
    the same problem and exit cost on the grids with every other node (2h and 4h), the embedded
    solve's response to the exit costs' sub-cell excess and, where a feature narrower than a
    cell asks for it, the pair; and warn where an estimate exceeds the default tolerance, where
    none could be made, or where the exit set has a part that no node holds."""

    def solve(on: Problem, costs=exit_costs) -> list:
        return _quietly(solve_first_exit_many, on, costs, s)

    embed(problem, exit_costs, solutions, _on_grids(problem, solve), solve, base=True)


def _embed_average(problem: Problem, s: StationarySettings, solution: StationarySolution) -> None:
    """Attach to an average-cost solution the embedded estimates of its relative value h
    (:func:`gridlbc.accuracy.embedding.embed`: h normalised to min 0 at the nodes on every
    level, as on this one, and S, the response of the embedded solve to the state cost's excess
    between the nodes) and of its average cost c (``average_cost_error``,
    :func:`gridlbc.accuracy.estimate.scalar_estimate` from c on the grids h, 2h and 4h, γ_c and
    S_c); warn where either exceeds the default tolerance."""

    def solve(on: Problem, costs=()) -> list:
        return [_quietly(solve_average_cost, on, s)]

    levels, pairs, excess = embed(problem, [], [solution], _on_grids(problem, solve), solve, True)
    if not levels:
        return
    (moved,) = cast(list, excess)
    response = 0.0  # S_c: what the excess moves c by on the embedded grid
    if moved.raised is not None and moved.base is not None:
        response = abs(_average_cost(moved.raised) - _average_cost(moved.base))
    with quiet_reads():
        estimate = scalar_estimate(
            [solution.average_cost] + [level[0].average_cost for level in levels],
            None if pairs is None else [side[0].average_cost for side in pairs],
            stationary_gap(solution),
            response,
            average_truncation(solution),
        )
    object.__setattr__(solution, "average_cost_error", estimate.error)
    check_scalar(estimate, "the average cost c")


def _average_cost(solution) -> float:
    """c of an average-cost solve (:func:`~gridlbc.stationary.average.solve_average_cost` sets
    it)."""
    c = cast(StationarySolution, solution).average_cost
    assert c is not None
    return c


def _on_grids(problem: Problem, solve):
    """``solve`` of ``problem`` moved to a grid (the step factor of a time march is not used)."""

    def solve_on(grid: Grid, factor: int):
        return solve(problem.replace(grid=grid))

    return solve_on


def _quietly(solve, *args):
    """``solve(*args)`` with its gridlbc warnings silenced: the warnings of a solve that checks
    another (an embedded or comparison solve) are not the user's."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridlbcWarning)
        return solve(*args)
