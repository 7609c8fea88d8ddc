"""Backward time stepping of the linear Bellman PDE: :func:`~gridlbc.solve`
and :func:`~gridlbc.solve_many`.

From the terminal data z(·, T) = exp(−g/λ) a step operator S (a monotone linear map, see
:mod:`gridlbc.schemes`) is applied n = T/Δt times,

    z(·, t − Δt) = S z(·, t).

To keep z in range every slice is renormalised, z = Z e^ℓ with max Z = 1: the scale ℓ is carried
exactly in the log domain, so nothing underflows as a whole and linear combinations stay exact.
Nodes whose Z underflows to zero are counted in the diagnostics (their value is +∞).

Here: the time grid, the memory check, the terminal data with the fitting reference, and the
packaging of the solutions. The scheme (:class:`gridlbc.schemes.protocol.Scheme`, named by the
settings' ``method``) supplies its default step, marches and checks its solutions. How to solve
is :mod:`gridlbc.settings`; where the slices live is :mod:`gridlbc.storage`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import numbers
import warnings

import numpy as np

from .accuracy import check_flow, embedded_store_every, solve_to_tolerance
from .accuracy.embedding import embed
from .accuracy.tolerance import Marcher
from .backends.numba.drift import rate_sums
from .errors import GridlbcWarning
from .grid import Grid, flat_chunks
from .problem import Problem
from .schemes import METHODS
from .schemes.protocol import Marched, MarchPlan, Terminal
from .settings import SolverSettings, is_own_reference, memory_estimate, resolve_settings
from .solution import OperatorSignature, Solution, SolveDiagnostics
from .stationary import (
    exit_nodes,
    solve_stationary,
    solve_stationary_many,
    solve_stationary_to_tolerance,
)
from .storage import check_memory


def courant_rates(problem: Problem) -> tuple[float, float]:
    """The Courant rates (1/time) of the drift: the maximum over the nodes of
    ``r(x) = max_k |a_k(x)| / h_k`` and its root mean square over them (in chunks of nodes)."""
    grid = problem.require_grid("courant_rates")
    spacing = np.asarray(grid.spacing, dtype=np.float64)
    peak, squares = 0.0, 0.0
    for flat in flat_chunks(grid.size):
        drift = np.asarray(problem.system.drift(grid.node_coordinates(flat)), dtype=np.float64)
        chunk_peak, chunk_squares = rate_sums(drift, spacing)
        peak, squares = max(peak, chunk_peak), squares + chunk_squares
    if math.isnan(squares):
        raise ValueError("the system's drift is NaN at some nodes: check system.drift on the grid")
    return peak, math.sqrt(squares / grid.size)


def time_grid(
    problem: Problem,
    settings: SolverSettings,
    rates: tuple[float, float],
    max_step: float = math.inf,
) -> tuple[float, int]:
    """The step Δt and the number of steps n with n Δt = T; ``rates`` from :func:`courant_rates`.

    A given ``settings.dt`` is rounded down to divide T. Otherwise the scheme's
    :class:`~gridlbc.schemes.protocol.StepRule` sets it: the fewest steps that hold the Courant
    number (against the largest rate or its root mean square over the nodes) and its fewest
    steps, and the step is also at most ``max_step`` (the scheme's
    :class:`~gridlbc.schemes.protocol.StepBound`)."""
    T = problem.require_horizon("a time grid")
    if settings.dt is not None:
        if settings.dt > T:
            raise ValueError(f"dt = {settings.dt} exceeds the horizon T = {T}")
        n = math.ceil(T / settings.dt - 1e-9)
    else:
        rule = settings.scheme.step_rule(settings)
        rate = rates[1] if rule.rate == "rms" else rates[0]
        n = max(
            int(rule.min_steps),
            math.ceil(T * rate / rule.courant - 1e-9),
            math.ceil(T / max_step - 1e-9) if max_step < math.inf else 1,
        )
    return T / n, n


def kept_steps(steps: int, store_every: int) -> list[int]:
    """The steps whose slices a solve of ``steps`` steps stores: every ``store_every``-th and the
    last."""
    return sorted(set(range(0, steps + 1, store_every)) | {steps})


def kept_count(steps: int, store_every: int) -> int:
    """How many slices :func:`kept_steps` lists, counted without listing them (a step short
    against the horizon can plan hundreds of millions of steps, whose list alone would not fit
    in memory: stranger round 30's ±5 mm box, docs page :doc:`benchmarks`)."""
    return steps // store_every + 1 + (steps % store_every != 0)


def planned_memory(problem: Problem, settings: SolverSettings) -> dict[str, int]:
    """The bytes :func:`~gridlbc.solve` of ``problem`` with ``settings`` would hold
    (:func:`gridlbc.settings.memory_estimate`), its step chosen as the solve chooses it, without
    solving."""
    if problem.exit is not None and not settings.scheme.supports_exit:
        settings = _exit_settings(settings, explicit=False)
    _, steps = planned_step(problem, settings)
    return memory_estimate(problem, settings, kept_count(steps, settings.store_every))


def planned_step(problem: Problem, settings: SolverSettings) -> tuple[float, int]:
    """The step Δt and the number of steps n that :func:`~gridlbc.solve` of ``problem`` with
    ``settings`` would take (:func:`time_grid`), without solving."""
    if problem.exit is not None and not settings.scheme.supports_exit:
        settings = _exit_settings(settings, explicit=False)
    bound = settings.scheme.step_bound(problem)
    return time_grid(problem, settings, courant_rates(problem), bound.limit)


def _terminal_data(problem: Problem, terminal_costs, log: bool = False):
    """Scaled terminal desirabilities Z (K, N), max 1 per row, and their log-scales ℓ (K,);
    with ``log``, log Z instead of Z."""
    lam = problem.temperature
    grid = problem.require_grid("solve")
    Z = np.empty((len(terminal_costs), grid.size))
    scales = np.empty(len(terminal_costs))
    if problem.exit is not None:  # the task ends on entering E, paying g_E there
        on_exit = problem.exit_mask()
        exit_values = problem.exit_values()[on_exit]
    for r, cost in enumerate(terminal_costs):
        g = Z[r]  # g, then in place −(g − min g)/λ, then its exp
        g[:] = grid.node_values(problem.replace(terminal_cost=cost).terminal_values)
        if problem.exit is not None:
            g[on_exit] = exit_values
        g_min = g.min()
        np.negative(np.subtract(g, g_min, out=g), out=g)
        np.divide(g, lam, out=g)
        if not log:
            with np.errstate(under="ignore"):
                np.exp(g, out=g)
        scales[r] = -g_min / lam
    return Z, scales


def _terminal(problem: Problem, terminal_costs, fitting) -> Terminal:
    """The :class:`~gridlbc.schemes.protocol.Terminal` data of a solve: the costs' scaled
    desirabilities, and the fitting reference φ as a row of its own (``fitting`` a cost, or
    ``"terminal"`` for several costs: the composite h = Σ_i h_i), or as the only row when a
    single cost is its own reference (then in the log domain). The fingerprint, a digest of the
    scaled φ at the nodes, fixes the operator; :func:`gridlbc.combine` compares it."""
    K = len(terminal_costs)
    if is_own_reference(fitting, K):
        ell, log_scale = _terminal_data(problem, terminal_costs, log=True)
        return Terminal(ell, log_scale, K, 0, True, _fingerprint(np.exp(ell[0])))
    Z, log_scale = _terminal_data(problem, terminal_costs)
    if fitting is None:
        return Terminal(Z, log_scale, K, None, False, "none")
    if fitting == "terminal":
        top = log_scale.max()
        phi = np.exp(log_scale - top) @ Z
        peak = phi.max()
        phi, phi_scale = phi / peak, top + np.log(peak)
    else:
        phi, phi_scale = (a[0] for a in _terminal_data(problem, [fitting]))
    rows = np.vstack([Z, phi])
    return Terminal(rows, np.append(log_scale, phi_scale), K, K, False, _fingerprint(phi))


def _fingerprint(phi: np.ndarray) -> str:
    digest = hashlib.sha256(np.ascontiguousarray(phi, dtype=float).tobytes())
    return "sha256:" + digest.hexdigest()[:16]


def solve_many(problem: Problem, terminal_costs, settings=None, **options) -> list[Solution]:
    """Solve one problem for several terminal costs at once (one operator, many right-hand sides).

    Parameters
    ----------
    problem : Problem
        The shared system, grid, horizon, state cost and temperature.
    terminal_costs : sequence of callable
        The terminal costs g_i; for a first-exit problem without a horizon, its exit costs
        (one factorisation for all: :func:`gridlbc.stationary.solve_stationary_many`).
    settings : SolverSettings or str, optional
        A :class:`SolverSettings` or a preset's name, as for :func:`~gridlbc.solve`.
    **options
        Settings fields overriding ``settings``, as for :func:`~gridlbc.solve`.

    Returns
    -------
    list of Solution
        One per cost, of ``problem.replace(terminal_cost=g_i)`` (``exit_cost=g_i``), all of one
        linear operator, so that :func:`gridlbc.combine` superposes them exactly. With a
        horizon and the default fitting that operator is fitted to all the costs at once (one
        reference, the composite of them all), not to each alone as :func:`~gridlbc.solve`
        fits one cost, so a component can differ from its own solve by the grid's error, more
        where the costs are far apart (the combination inherits it, and each solution's
        estimate reads it); ``fitting=None`` (the plain operator) gives each exactly as
        ``solve`` with the same option would.
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a gridlbc.Problem, got {type(problem).__name__}")
    if callable(terminal_costs) or not hasattr(terminal_costs, "__iter__"):
        raise TypeError(
            "terminal_costs must be a sequence of costs, one solution each, got one "
            f"{type(terminal_costs).__name__}: give [cost] for one (or gridlbc.solve)"
        )
    terminal_costs = list(terminal_costs)
    if not terminal_costs:
        raise ValueError("terminal_costs is empty: give at least one terminal cost")
    if problem.stationary:
        if problem.average_cost or settings is not None:
            raise ValueError(
                "solve_many of a problem without a horizon takes the exit costs of a first-exit "
                "problem (no settings object: its options by name); an average-cost problem has "
                "no end costs to vary"
            )
        return solve_stationary_many(problem, terminal_costs, **options)
    s = settings_for(problem, settings, options)
    scheme = s.scheme
    grid = problem.require_grid("solve")
    if problem.exit is not None:
        exit_nodes(problem)  # refuse an exit set the grid cannot resolve
    problem.noise_diagonal(grid.node_coordinates([0]))  # refuse cross-diffusion before any work
    plan = MarchPlan(problem, 0.0, 0, [], s.dtype, s.mmap_dir, s.progress, options=s.__dict__)
    K = len(terminal_costs)
    what = f"solving on {grid.describe()}"
    # Before touching the grid: the first and last slices and the working arrays must fit.
    check_memory(memory_estimate(problem, s, 2, K), what, s.mmap_dir)
    rates = courant_rates(problem)
    bound = scheme.step_bound(problem)
    plan.dt, plan.steps = time_grid(problem, s, rates, bound.limit)
    bound.check(plan.dt)  # only a given dt can exceed it: the default is held below
    estimate = memory_estimate(problem, s, kept_count(plan.steps, s.store_every), K)
    check_memory(estimate, f"{what} in {plan.steps} steps of {plan.dt:.3g}", s.mmap_dir)
    plan.kept = kept_steps(plan.steps, s.store_every)

    terminal = _terminal(problem, terminal_costs, s.reference)
    marched = scheme.march(plan, terminal)
    solutions = _solutions(plan, terminal_costs, terminal, marched, s, rates[0], estimate)
    scheme.check(solutions, marched)
    if s.error_estimate:
        _embed(problem, terminal_costs, s, plan.dt, solutions)
    return solutions


def settings_for(problem: Problem, settings, options: dict) -> SolverSettings:
    """``settings`` with ``options`` (:func:`~gridlbc.settings.resolve_settings`), for
    ``problem``: with an exit set and a horizon, a scheme that implements the exit
    (:func:`_exit_settings`): the implicit one, also under a preset or a settings object that
    names none other than the default's (stranger round 28: ``settings="fast"`` refused such a
    problem for a method the user never named); a method asked for by name (``method=``) must
    implement it."""
    s = resolve_settings(settings, options)
    if problem.exit is not None and not s.scheme.supports_exit:
        explicit = "method" in options or s.method != SolverSettings().method
        s = _exit_settings(s, explicit, options.get("fitting", "auto"))
    return s


def _exit_settings(s: SolverSettings, explicit: bool, fitting="auto") -> SolverSettings:
    """The settings for a problem with an exit set and a horizon: a scheme that implements the
    exit (:attr:`~gridlbc.schemes.protocol.Scheme.supports_exit`), the implicit one unless
    another was asked for by name, which is then an error, as is a ``fitting`` asked for (the
    implicit scheme has no fitted form)."""
    if fitting not in ("auto", None):
        raise ValueError(
            f"fitting={fitting!r} does not apply to a task with an exit set and a horizon: its "
            "scheme, the implicit time march, has no fitted form. Where it warns that v/λ rises "
            "faster than its tails allow, refine that axis or raise the temperature, or solve "
            "the stationary first-exit problem (horizon=None)"
        )
    if explicit:
        able = [name for name, scheme in METHODS.items() if scheme.supports_exit]
        raise ValueError(
            f"method={s.method!r} does not implement an exit set (SPEC §9): solve a problem "
            f"with exit= and a horizon with method={' or '.join(map(repr, able))}, or give "
            "horizon=None for the stationary first-exit problem"
        )
    return dataclasses.replace(s, method="implicit", fitting="auto", courant=None)


def _embed(problem: Problem, terminal_costs: list, s: SolverSettings, dt: float, solutions):
    """Attach to each solution its embedded estimate (:func:`gridlbc.accuracy.embedding.embed`),
    the coarser solves marched as this one: on the grid with every other node at step 2Δt and
    the one below it at 4Δt, their slices stored at least twice as densely
    (:func:`gridlbc.accuracy.embedded_store_every`); the solves on the pair of grids at 2Δt; and
    the response to the costs' sub-cell excess by the plain scheme
    (:func:`gridlbc.accuracy.responses` says why). Then warn where the drift changes between the nodes faster than the grid follows
    (:func:`gridlbc.accuracy.check_flow`). The coarser solves' own warnings are not the user's:
    they are silenced."""
    horizon = problem.require_horizon("an embedded solve")

    def solve_on(
        grid: Grid,
        factor: int,
        on: Problem = problem,
        costs=terminal_costs,
        using=s,
        every: int = s.store_every,
    ):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GridlbcWarning)
            return solve_many(
                on.replace(grid=grid),
                costs,
                using,
                dt=min(factor * dt, horizon),
                progress=False,
                error_estimate=False,
                store_every=every,
            )

    plain = dataclasses.replace(s, fitting=None)  # why: subcell.responses
    embed(
        problem,
        terminal_costs,
        solutions,
        # the levels store their slices densely enough to read between the solve's
        lambda grid, factor: solve_on(
            grid, factor, every=embedded_store_every(s.store_every, factor)
        ),
        lambda on, costs: solve_on(on.grid, 2, on, costs, plain),
    )
    check_flow(solutions[0])  # the drift is the problem's: one look for all its solutions


def _solutions(
    plan: MarchPlan,
    terminal_costs: list,
    terminal: Terminal,
    marched: Marched,
    s: SolverSettings,
    rate: float,
    estimate: dict[str, int],
) -> list[Solution]:
    """One :class:`Solution` per terminal cost from what the scheme marched, with its
    :class:`SolveDiagnostics` and :class:`OperatorSignature` (the one place that builds
    them)."""
    wall = plan.elapsed()
    times = np.array(plan.kept, dtype=float) * plan.dt
    times[-1] = plan.problem.require_horizon("a time grid")
    step = marched.operator
    operator = OperatorSignature(s.method, plan.dt, terminal.fingerprint, terminal.log)
    out = []
    for r, cost in enumerate(terminal_costs):
        diagnostics = SolveDiagnostics(
            method=s.method,
            dt=plan.dt,
            steps=plan.steps,
            store_every=s.store_every,
            wall_time=wall,
            setup_time=marched.setup_time,
            underflow_nodes=marched.underflow_nodes[r],
            stored_bytes=int(marched.slices[r].nbytes),
            operator_bytes=step.nbytes,
            courant=rate * plan.dt,
            iterations=tuple(step.iterations),
            flushed_values=marched.flushed,
            memory_estimate=estimate["ram"],
            fitting=terminal.fingerprint,
        )
        out.append(
            Solution(
                plan.problem.replace(terminal_cost=cost),
                times,
                marched.slices[r],
                marched.scales[:, r].copy(),
                diagnostics,
                operator,
                marched.representation,
            )
        )
    return out


MARCH = Marcher(settings_for, planned_step, planned_memory, solve_many)
"""The time march as :func:`gridlbc.accuracy.solve_to_tolerance` repeats and plans it."""


def solve(
    problem: Problem,
    dt: float | SolverSettings | str | None = None,
    settings: SolverSettings | str | None = None,
    *,
    tol: float | None = None,
    states=None,
    times=None,
    max_nodes: int | None = None,
    max_seconds: float | None = None,
    **options,
) -> Solution:
    """Solve the linear Bellman PDE of ``problem`` backward from T to 0.

    Parameters
    ----------
    problem : Problem
    dt : float, SolverSettings or str, optional
        Time step (default from the Courant number, see :class:`SolverSettings`). Settings or a
        preset's name may be given here too, as the second argument of :func:`~gridlbc.solve_many`
        is: ``solve(problem, "fast")``.
    settings : SolverSettings or str, optional
        Settings or the name of a preset in :data:`gridlbc.PRESETS`.
    tol : float, optional
        A relative tolerance on v, of max(abs(v), λ) over the states that matter and of
        abs(v(x, 0)) at given ``states`` (:func:`gridlbc.accuracy.estimate.given_floor`): solve
        again, halving Δt or refining the grid, until the embedded error estimate meets it
        (:func:`gridlbc.accuracy.solve_to_tolerance`; the path
        taken is in ``solution.refinement``). Default: one solve, which warns when its estimate
        exceeds :data:`gridlbc.accuracy.DEFAULT_TOLERANCE`. For a problem without a horizon
        (first exit, average cost: there on the relative value h and on c) the grid alone is
        refined (:func:`gridlbc.stationary.solve_stationary_to_tolerance`).
    states : array_like (N, d), optional
        With ``tol``: the states where it must hold (default: the states that matter,
        :func:`gridlbc.accuracy.states_that_matter`).
    times : float or sequence of float, optional
        With ``tol`` and ``states``, for a problem with a horizon: the times in [0, T] at which
        it must hold there (default: t = 0 and late in the task,
        :func:`gridlbc.accuracy.assessment.late_times`).
    max_nodes : int, optional
        With ``tol``: refine the grid no further than this many nodes.
    max_seconds : float, optional
        With ``tol``: a wall-clock budget in seconds. Each round's time is predicted from the
        last one's before it starts, and a round that would take the total past the budget is
        not started: the last solution is returned with a :class:`gridlbc.ResolutionWarning`
        giving the estimate reached and the next round's predicted time
        (``solution.refinement[-1].predicted_seconds``). Default None: no budget (see
        :func:`gridlbc.accuracy.solve_to_tolerance` for why).
    **options
        Any :class:`SolverSettings` field, e.g. ``method="implicit"``, ``store_every=5``,
        ``progress=True``; for a problem without a horizon (first exit, ``horizon=None``, or
        average cost, ``"average"``), the fields of
        :class:`gridlbc.stationary.StationarySettings` instead (docs page :doc:`first_exit`).

    Returns
    -------
    Solution
        Value, desirability and policy at any (x, t), with :class:`SolveDiagnostics` and an
        error estimate (:meth:`Solution.error_estimate`); a
        :class:`gridlbc.StationarySolution` (no time) for a problem without a horizon.
    """
    if isinstance(problem, Problem) and problem.stationary:
        if dt is not None or settings is not None:
            raise TypeError(
                "a stationary problem (horizon None or 'average') has no time step and no "
                "time-march settings: give its options by name (rates=, linear_solver=)"
            )
        if times is not None:
            raise TypeError("times= applies to a problem with a horizon: this one has none")
        if tol is not None:
            return solve_stationary_to_tolerance(
                problem, tol, states, max_nodes, max_seconds=max_seconds, **options
            )
        _check_tolerance_options(states, max_nodes, max_seconds)
        return solve_stationary(problem, **options)
    if isinstance(dt, (SolverSettings, str)):
        if settings is not None:
            raise TypeError(
                "solve() got settings twice: as its second argument and as settings=; give one"
            )
        dt, settings = None, dt
    if dt is not None:
        if isinstance(dt, bool) or not isinstance(dt, numbers.Real):
            raise TypeError(
                f"dt must be a time step (a positive float), a SolverSettings or a preset's name, "
                f"got {type(dt).__name__}"
            )
        options["dt"] = dt
    if tol is not None:
        return solve_to_tolerance(
            problem,
            tol,
            states,
            settings,
            max_nodes,
            max_seconds=max_seconds,
            times=times,
            march=MARCH,
            **options,
        )
    _check_tolerance_options(states, max_nodes, max_seconds, times)
    return solve_many(problem, [problem.terminal_cost], settings, **options)[0]


def _check_tolerance_options(states, max_nodes, max_seconds, times=None) -> None:
    """Refuse the options of a solve to a tolerance given without ``tol``."""
    if any(option is not None for option in (states, max_nodes, max_seconds, times)):
        raise TypeError(
            "states=, times=, max_nodes= and max_seconds= apply with tol=: give tol or drop them"
        )
