"""The embedded error estimate of a solve: how it is made, read and warned about (docs page
:doc:`accuracy`).

**The embedded estimate.** A solve on a grid of spacing h with step Δt is accompanied by solves of
the same problem, with the same scheme and settings, on the *embedded* grids that keep every other
node of each axis: spacing 2h with step 2Δt, and 4h with 4Δt. Together they cost about
2^−(d+1) + 2^−(2d+2) of the solve they check. If the error behaves as e(h) ≈ C h^p with
Δt ∝ h, Richardson's argument gives v_2h − v_h ≈ (2^p − 1) C h^p, and the order p can be observed
from the three solves::

    p = log₂( Σ abs(v_4h − v_2h) / Σ abs(v_2h − v_h) )   over the states that matter.

:meth:`gridlbc.Solution.error_estimate` returns::

    ê(x, t) = max( abs(v_2h(x, t) − v_h(x, t)) / (2^q − 1),  r · max(abs(v_h(x, t)), λ) ),

evaluated at any states by the same interpolation as the values, with

- q = p clipped to [1, 2] (the library's schemes are monotone, hence first order in general,
  and second order at best; read at t > 0, p is observed at that time,
  :meth:`EmbeddedEstimate.order_at`) where the two solves differ by at most :data:`ASYMPTOTIC` relative
  to the value, and q = 1 where they differ by more: a coarse solve that far from the fine one
  is outside the range where Richardson's model holds, and an order observed from it says more
  about the coarse grids than about this one (dividing by 3 there understated the error of a
  25⁴ acrobot threefold);
- the floor r, the median over the calibration states (:func:`calibration_states`) of the first
  term relative to the value: errors accumulate with the cost along the characteristics, so
  where the two solves happen to agree (their difference changes sign) the error is not smaller,
  relative to v, than the typical one (:func:`embedded_estimate`).

The estimate is also at least abs(v_c₁ − v_c₂), undivided: the difference between the solves
(step 2Δt) on a pair of grids whose cell counts add up to the grid's (:func:`phase_pair`). The
embedded grid misses a narrow feature midway between two nodes by as much as the grid does, and
the pair's difference is what sees that error; it is how far a coarse solve moves with where its
nodes fall, not a difference between h and 2h, so it is not divided by 2^q − 1. The pair costs
one or two more coarse solves (one where every axis has an odd cell count: its first grid is
then the embedded one), and is solved only where the problem may have a feature narrower than
a cell (:func:`~gridlbc.accuracy.flow.reads_pair`: costs with an excess between the nodes, an
exit set, a drift or a noise whose interpolation error does not converge at first order on
the grids the estimate reads); with smooth costs and coefficients its difference is of the
order of the embedded one.

The estimate is also at least abs(γ(x, t)), the cost that the grid's interpolants of q and g add
along the solve's own paths (:mod:`gridlbc.accuracy.paths`): it sees a cost narrower than a cell
wherever the nodes fall, also where the pair's two offsets are equal and every coarser grid
misses the feature alike (next to the ends of an axis, and its centre where its cell count is
even: :func:`phase_pair`).

And it is at least S(x, t) = abs(v_2h[g + δg, q + δq] − v_2h[g, q]), what the costs' excess
between the nodes (δg, δq: the costs at points between the nodes against their reconstruction
from the nodes, exact for quadratics) changes in the embedded solve
(:mod:`gridlbc.accuracy.subcell`): it sees a goal or a well narrower than a cell that the
solve's paths never approach, which γ cannot.

For a stationary solve (first exit, average cost) it is also at least the generator's
truncation error on the solved v carried along the paths (:mod:`gridlbc.accuracy.truncation`):
where z falls by many times e per cell every coarser grid is further off still, and their
differences say little. For a solve of the splitting scheme with a horizon it is also at least
what landing each step's foot by two half steps instead of one midpoint step changes in v,
carried along the paths (:mod:`gridlbc.accuracy.tracing`): a drift that switches within a step's
travel sends the midpoint foot across the switch on every grid alike.

Where the solve stores only every k-th step's slice (``store_every``), it is also at least
τ(x, t), what interpolating v linearly in time between the solve's stored slices changes on the
embedded solve, which stores its own at least twice as densely
(:meth:`EmbeddedEstimate.between_slices`).

At the states a user asks about (:meth:`EmbeddedEstimate.error`, not at the states a default solve
is judged at, where it would cost several times γ's paths) it is also at least the local
certificate's abs(v_h − v_ℓ) less two of its standard errors (:mod:`gridlbc.accuracy.bellman`):
v_h against what the SDE makes of it a few steps later. It sees a value steeper than a cell
where the costs are smooth (next to an invariant edge), which the coarser grids interpolate
alike and the cost gap does not see. Beside it, where its paths are affordable, the certificate
of the whole remaining task (the paths run to the horizon, where v_h is g, exact): an error that
x shares with every state its paths reach before T (an exit across an axis without noise, late
in a task) is seen only so.

The estimate never changes the solution it checks. It sees what refining h and Δt would change:
time steps too long for a fast local flow, features narrower than a cell, a grid too coarse for
the value's curvature. It cannot see an error that all the solves share and the paths do not
feel: a box too small for the process (reflection at a closed axis acts the same on each), a
feature that every grid misses and the paths step over.
Where the observed order is below 1 the coarser solves are not converging at first
order: they are too coarse to say how accurate this grid is, and the estimate is rough in either
direction (far above the error on 4-D grids of a few dozen nodes per axis, below it where the
solves converge slowly: half the error on a first-exit pendulum swing-up), and the warning says
so.

**Relative error.** ``ê / max(abs(v), λ)``: a value below the temperature λ is compared with λ,
the scale on which v = −λ log z is resolved (near a goal v can be arbitrarily small while its
error is a fraction of λ).

**Where it matters.** Without states from the user, a solve is judged at the states that matter
(:func:`states_that_matter`): for a task that runs on (no exit set, no horizon) the nodes whose
value is finite and at most the median over the grid (the better half of the box, where the
controlled process spends its time; the far corners of a box, where every solve is poor, do not
count); for a task that ends (an exit set, a horizon or both) every node with a finite value off
the exit set, since v(x, 0) is the cost of a task started at x and a task starts anywhere,
typically far from where it ends, where v is largest. The relative estimate is read there at its
90th percentile, and S at its largest (a cost narrower than a cell changes v near it only, on a
share of the states that may be far below a tenth: :func:`largest_response`). A finite horizon
without an exit set is also judged, as before, at the better half, where its paths end up: a
defect there is a share of the better half twice as large as of the box (the states read that
lie in it, so that the paths are sampled once). A large estimate on
too few states for the percentile warns where the grid terms and γ both exceed the tolerance
there or at the centre of a cell around there, where an interpolated value is furthest from the
nodes (:func:`confirmed_locally`). A solve with a horizon is also confirmed so at
:func:`late_times`: 8 steps before T, where the local certificate certifies the remaining task
whole, and in the middle of the last interval between stored slices, where a step long against
the terminal cost errs most: the warning judges v(x, 0), and a controller is also used late in
its task. Where the solve stores every k-th slice only, τ is read there too, at its
:data:`QUANTILE` over the states that matter (:func:`interpolated_in_time`). With ``states=``,
at its largest over them, at t = 0 and those late times (or the ``times=`` given).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from scipy.special import logsumexp

from ..errors import ResolutionWarning, warn_user
from ..problem import bracket
from .bellman import SPAN, bellman_gap, beyond_noise, largest_discount, local_error
from .paths import PATH_SAMPLES, cost_gap, sampled
from .subcell import Response
from .tracing import gaps
from .truncation import truncation_gap

if TYPE_CHECKING:
    from ..solution import Solution


DEFAULT_TOLERANCE = 0.05
"""The relative error above which a default solve warns (:func:`check_accuracy`)."""


QUANTILE = 0.9
"""The share of the states that matter whose relative estimate must meet the tolerance."""


ASYMPTOTIC = 0.15
"""Where the embedded solve differs from the solve by more than this (relative to
``max(abs(v), λ)``), the estimate does not divide by the observed order (the module docstring)."""


SAMPLE = 20_000
"""At most this many of the calibration states give the floor (evenly spaced in the nodes'
order): a median of the estimate needs no more, and a 4-D grid has millions."""


ORDER_SAMPLE = 2_000
"""At most this many of the calibration states give the order observed at a time t > 0
(:meth:`EmbeddedEstimate.order_at`): a ratio of two sums, read at each time asked for."""


ASSESSED = 256
"""At most this many of the states that matter are judged against a tolerance (evenly spaced in
the nodes' order): the estimate there samples paths from each (:mod:`gridlbc.accuracy.paths`),
and a 90th percentile needs no more."""


ASSESSED_PATHS = 4
"""Paths per state from which the judged states' γ is sampled (:mod:`gridlbc.accuracy.paths`):
their percentile averages the paths' noise over the states."""


def relative_error(estimate: np.ndarray, value: np.ndarray, temperature: float) -> np.ndarray:
    """``estimate / max(|value|, λ)`` (see the module docstring); +inf where the value is not
    finite (underflow)."""
    value = np.asarray(value, dtype=float)
    scale = np.maximum(np.abs(value), temperature)
    with np.errstate(invalid="ignore"):
        out = np.asarray(estimate, dtype=float) / scale
    return np.where(np.isfinite(value) & np.isfinite(out), out, np.inf)


def _evenly(solution, chosen: np.ndarray, limit: int) -> np.ndarray:
    """The nodes of the mask ``chosen``, at most ``limit`` of them evenly spaced, ``(M, d)``."""
    return _nodes(solution, _evenly_index(chosen, limit))


def _nodes(solution, keep: np.ndarray) -> np.ndarray:
    """The coordinates of the nodes of flat indices ``keep``, ``(M, d)`` (also for none)."""
    if len(keep) == 0:
        return np.empty((0, solution.grid.ndim))
    return solution.grid.node_coordinates(keep)


def _evenly_index(chosen: np.ndarray, limit: int) -> np.ndarray:
    """The flat indices of :func:`_evenly`'s nodes."""
    keep = np.flatnonzero(chosen)
    if len(keep) > limit:
        keep = keep[np.linspace(0, len(keep) - 1, limit).astype(np.int64)]
    return keep


def _finite_off_exit(solution) -> np.ndarray:
    """The mask of the nodes whose value at t = 0 is finite and that are not in the exit set."""
    chosen = np.isfinite(solution.value_nodes(0))
    if solution.problem.exit is not None:
        chosen &= ~solution.problem.exit_mask()
    return chosen


def better_half(solution, limit: int = SAMPLE) -> np.ndarray:
    """The nodes whose value at t = 0 is finite and at most the median over the grid, ``(M, d)``
    (at most ``limit`` of them, evenly spaced): where a controlled process without an exit set
    spends its time, and where a finite-horizon task's paths end up."""
    return _evenly(solution, solution.better_half(), limit)


def states_that_matter(solution, limit: int = SAMPLE) -> np.ndarray:
    """The states at which a default solve is judged, ``(M, d)`` (at most ``limit`` of them,
    evenly spaced).

    - A task that runs on (no exit set, no horizon: discounted or average cost): the
      :func:`better_half`, the nodes whose value is finite and at most the median. Its process
      forgets where it started and spends its time where v is low; the far corners of the box,
      where every solve is poor, do not count.
    - A task that ends (an exit set, a horizon or both): every node with a finite value at t = 0,
      outside the exit set. v(x, 0) is the cost of the task started at x, and a task starts
      anywhere, typically far from where it ends, where v is largest (a pendulum hanging at rest
      when E is near the top; the states upstream of a headwind in a finite horizon). The better
      half would judge only the states next to the end, and a defect that raises v (a fast local
      flow against the paths) moves the very states it spoils out of the better half (stranger
      round 13's ``hz_gust``, docs page :doc:`accuracy`). The nodes in E do not count: their
      value is the exit cost, given, not solved for.

    A finite horizon without an exit set is also judged at the :func:`better_half`
    (:func:`assess`), where its paths end up.

    Parameters
    ----------
    solution : Solution
        A grid solution.
    limit : int
        The most states returned.

    Returns
    -------
    ndarray (M, d)
        The states at which a solve is judged when the user gives none.
    """
    return _evenly(solution, matter_mask(solution), limit)


def matter_mask(solution) -> np.ndarray:
    """The flat mask of the nodes among which :func:`states_that_matter` are chosen."""
    problem = solution.problem
    if problem.exit is None and problem.stationary:
        return solution.better_half()
    return _finite_off_exit(solution)


def calibration_states(solution, limit: int = SAMPLE) -> np.ndarray:
    """The states over which the estimate's floor and observed order are measured
    (:func:`embedded_estimate`), ``(M, d)``: the :func:`better_half` of a task without an exit
    set (with or without a horizon), every node off the exit set of a task with one.

    The floor is the typical relative error that an error carried along the characteristics
    leaves where the two solves happen to agree, and the order is Richardson's model of the
    levels. A finite horizon's paths end up in the better half from wherever they start, so the
    errors they carry are read there; the states far up the value, judged for the warning
    (:func:`states_that_matter`), hold the errors of their own region (a gust, a wall) and
    often levels that do not converge at all, which, taken into the floor and the order, would
    raise the estimate everywhere. The estimate at any state is therefore the same as when the
    better half alone was judged: only where it is judged changed."""
    if solution.problem.exit is None:
        return better_half(solution, limit)
    return _evenly(solution, _finite_off_exit(solution), limit)


@dataclass(frozen=True)
class Assessment:
    """The embedded estimate of a solve, read at a set of states.

    Attributes
    ----------
    error : float
        The relative estimate that is compared with the tolerance: its :data:`QUANTILE` over the
        states that matter, or its maximum over the user's states; without the user's states at
        least the largest S over the states that matter (:func:`largest_response`).
    worst_state : ndarray (d,)
        Where the relative estimate is largest.
    worst_error : float
        The largest relative estimate.
    share_above : float
        The share of the states whose relative estimate exceeds the tolerance.
    n_states : int
        How many states were read.
    local : bool
        Whether ``error`` is the largest S over the states that matter (:func:`largest_response`),
        above the quantile.
    half : bool
        Whether ``error`` and ``share_above`` are read over the :func:`better_half` (a finite
        horizon without an exit set, where the quantile there is the larger) rather than over
        all the states that matter.
    confirmed : bool
        Whether ``error`` is the largest estimate that the coarser solves and the solve's own
        paths both give at a few states (:func:`confirmed_locally`), above the quantile.
    between : bool
        Whether ``error`` is what interpolating in time between the stored slices changes
        (:func:`interpolated_in_time`), above the quantile at t = 0.
    time : float
        The time at which ``error`` was read: 0, or one of :func:`late_times` (or of the user's
        ``times``) where the reading there found the larger error.
    late_error : float
        At the user's states, the largest relative estimate over the times after 0 (0 where none
        was read): certificates at t = 0 cannot vouch for those (:func:`gridlbc.accuracy.tolerance.solve_to_tolerance`).
    """

    error: float
    worst_state: np.ndarray
    worst_error: float
    share_above: float
    n_states: int
    local: bool = False
    half: bool = False
    confirmed: bool = False
    between: bool = False
    time: float = 0.0
    late_error: float = 0.0


@dataclass(frozen=True)
class EmbeddedEstimate:
    """What a solution's error estimate reads (the module docstring): the solve on the embedded
    grid and the numbers observed from it and the one below it.

    Attributes
    ----------
    solution : Solution
        The same problem solved on the grid with every other node, step 2Δt.
    observed_order : float
        log₂ of the ratio of the differences between successive levels (NaN without a third
        level). Below 1 the coarser solves are not converging at first order: they are too
        coarse to say how accurate this grid is, and the estimate is rough in either direction.
    order : float
        q, the observed order clipped to [1, 2] (1 without a third level), used where the two
        solves differ by at most :data:`ASYMPTOTIC`.
    floor : float
        The least relative error reported (the median over the :func:`calibration_states`).
    pair : tuple of two Solution, or None
        The same problem solved on the grids of :func:`phase_pair` (step 2Δt); None where the
        grid is too coarse for them.
    excess : Response or None
        What the costs' sub-cell excess changes in the embedded solve
        (:class:`~gridlbc.accuracy.subcell.Response`); None where not measured.
    coarser : Solution or None
        The same problem solved on the grid below the embedded one (4h, step 4Δt), from which
        the order is observed at later times (:meth:`order_at`); None without it.
    """

    solution: Solution
    observed_order: float
    order: float
    floor: float
    pair: tuple[Solution, Solution] | None = None
    excess: Response | None = None
    coarser: Solution | None = None
    _orders: dict = field(default_factory=dict, repr=False, compare=False)

    def order_at(self, solution: Solution, t: float) -> float:
        """q at time ``t``: :attr:`order` at t = 0 (and without a horizon or a 4h solve), and
        later in the task the order observed there from the three solves, over
        :data:`ORDER_SAMPLE` of the :func:`calibration_states`, clipped as :attr:`order` is.

        Why: which error dominates changes along a task. At t = 0 a grid's spacing may set it,
        and the levels converge at second order; in the first steps from T the step's error
        and the interpolation between stored slices set it, and a solve at 2Δt with its
        longer steps differs from the solve by as much as the solve's own error or more (the
        order observed there is below 1): divided by 2^q − 1 with the order of t = 0 it read
        a third of an error of 10 % (stranger round 21, docs page :doc:`accuracy`)."""
        if t == 0.0 or self.coarser is None or solution.problem.stationary:
            return self.order
        if t not in self._orders:
            X = calibration_states(solution, ORDER_SAMPLE)
            with np.errstate(invalid="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore")  # an underflowed level is left out below
                v, v2, v4 = (s.value(X, t) for s in (solution, self.solution, self.coarser))
                fine, coarse = np.abs(v2 - v), np.abs(v4 - v2)  # NaN where two underflowed
            self._orders[t] = clipped_order(observed_order(fine, coarse))
        return self._orders[t]

    @property
    def converging(self) -> bool:
        """Whether the levels converge at first order or better (or could not be compared)."""
        return not (self.observed_order < 1.0)

    def difference(self, solution: Solution, x, t=0.0) -> np.ndarray:
        """abs(v_2h − v_h) at states ``x`` (N, d), time ``t``: the larger of the embedded
        difference and abs(v_c₁ − v_c₂), the ``pair``'s (:func:`phase_pair`)."""
        return self._read(solution, x, t)[2]

    def local(self, solution: Solution, x, t=0.0) -> np.ndarray:
        """abs(v_2h − v_h) / (2^q − 1) at states ``x`` (N, d), time ``t``, with q = ``order``
        where the relative difference is at most :data:`ASYMPTOTIC` and 1 elsewhere, and at
        least the pair's difference abs(v_c₁ − v_c₂) and :meth:`between_slices`, undivided."""
        return self._read(solution, x, t)[3]

    def between_slices(self, solution: Solution, x, t=0.0, embedded=None) -> np.ndarray:
        """τ(x, t) = abs((1 − θ) v_2h(x, t_j) + θ v_2h(x, t_j+1) − v_2h(x, t)) at states ``x``
        (N, d), t = (1 − θ) t_j + θ t_j+1 between two of the solve's stored times: what
        interpolating linearly in time between the solve's slices changes, measured on the
        embedded solve, which stores its own at most half as far apart
        (:func:`~gridlbc.accuracy.grids.embedded_store_every`); 0 at a stored time and where the
        solve stores every step (between its steps the interpolation is part of the step's
        error, which the embedded difference reads). Where the embedded solve stores no slice
        inside [t_j, t_j+1] (an interval as short as its own step, as the last one often is),
        it interpolates there as the solve does and τ is read from the solve's own slices
        instead (:func:`own_interpolation_error`). ``embedded``: v_2h(x, t), where the caller
        has it."""
        x = np.atleast_2d(x)
        if solution.problem.stationary or solution.diagnostics.store_every == 1:
            return np.zeros(len(x))
        times = solution.times
        j, theta = bracket(times, float(t))
        if theta in (0.0, 1.0):
            return np.zeros(len(x))
        coarse = self.solution
        if not np.any((coarse.times > times[j]) & (coarse.times < times[j + 1])):
            return own_interpolation_error(solution, x, j, theta)
        embedded = coarse.value(x, t) if embedded is None else embedded
        with np.errstate(invalid="ignore"):  # inf − inf where the embedded solve underflowed
            ends = (1 - theta) * coarse.value(x, times[j]) + theta * coarse.value(x, times[j + 1])
            return np.abs(ends - embedded)

    def error(self, solution: Solution, x, t=0.0, samples: int = PATH_SAMPLES) -> np.ndarray:
        """The estimate at states ``x`` (N, d), time ``t``: the local term, at least ``floor``
        relative to ``max(abs(v), λ)``, at least the :meth:`excess_response` S, at least
        abs(γ), the cost that the grid's interpolants add along the solve's paths
        (:func:`~gridlbc.accuracy.paths.cost_gap`, from ``samples`` paths per state), the
        truncation and tracing terms where they apply (module docstring), and at least the
        local certificate beyond its noise (:func:`~gridlbc.accuracy.bellman.local_error`)."""
        return self._error(solution, x, t, samples, whole=True)[1]

    def excess_response(self, x, t=0.0) -> np.ndarray:
        """S = abs(v_2h[g + δg, q + δq] − v_2h[g, q]) at states ``x`` (N, d), time ``t``: what
        the costs' excess between the nodes changes in the embedded solve
        (:class:`~gridlbc.accuracy.subcell.Response`); zero without it."""
        if self.excess is None:
            return np.zeros(len(np.atleast_2d(x)))
        return self.excess(x, t)

    def relative(
        self, solution: Solution, x, t=0.0, samples: int = PATH_SAMPLES, local: bool = True
    ) -> np.ndarray:
        """:meth:`error` relative to ``max(abs(v), λ)`` (:func:`relative_error`), with the
        local certificate over :data:`~gridlbc.accuracy.bellman.SPAN` steps only (what
        ``solve(tol=, states=)`` reads each round), and without it where ``local`` is False."""
        v, error = self._error(solution, x, t, samples, local)
        return relative_error(error, v, solution.temperature)

    def grid_terms(self, solution: Solution, x, t=0.0, v=None, response=None) -> np.ndarray:
        """The estimate at ``x`` without γ: the local term, at least ``floor`` relative to
        ``max(abs(v), λ)``, and at least S (no sampling: every state at the cost of an
        interpolation). ``v`` (v_h) and ``response`` (S) at ``x``: where the caller has read
        them."""
        return self._grid_terms(solution, x, t, v, response)[1]

    def _grid_terms(
        self, solution: Solution, x, t, v=None, response=None
    ) -> tuple[np.ndarray, np.ndarray]:
        """v_h and :meth:`grid_terms` at ``x`` (``v`` = v_h and ``response`` = S there where the
        caller has read them)."""
        v, _, _, local = self._read(solution, x, t, v)
        floor = self.floor * np.maximum(np.abs(v), solution.temperature)
        if response is None:
            response = 0.0 if self.excess is None else self.excess(x, t)
        return v, np.maximum(np.maximum(local, floor), response)

    def _error(
        self, solution: Solution, x, t, samples: int, local: bool = True, whole: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """v_h and :meth:`error` at ``x``: without the local certificate where ``local`` is
        False (the states a default solve is judged at, :func:`assess`), with the whole
        remaining task's certificate beside it where ``whole`` is True (the user's states)."""
        v, grid_terms = self._grid_terms(solution, x, t)
        gap, tracing = gaps(solution, x, samples, t)  # γ and the traced feet, on the same paths
        terms = np.fmax(grid_terms, np.abs(gap))
        truncation = truncation_gap(solution, x, samples, t, below=terms, v=v)
        error = np.fmax(np.fmax(terms, np.abs(truncation)), np.abs(tracing))
        if local and sampled(solution.problem):
            error = np.fmax(error, local_error(solution, x, t, whole=whole))
        return v, error

    def _read(self, solution: Solution, x, t, v=None) -> tuple[np.ndarray, ...]:
        """v_h, v_2h, :meth:`difference` and :meth:`local` at ``x``, each solve evaluated
        once (v_h not at all where given as ``v``)."""
        v = solution.value(x, t) if v is None else v
        embedded = self.solution.value(x, t)
        pair = None if self.pair is None else [side.value(x, t) for side in self.pair]
        order = self.order_at(solution, float(t))
        difference, local = _local(v, embedded, pair, solution.temperature, order)
        local = np.fmax(local, self.between_slices(solution, x, t, embedded))
        return v, embedded, difference, local


def own_interpolation_error(solution, x: np.ndarray, j: int, theta: float) -> np.ndarray:
    """What interpolating linearly in time between the solve's stored slices j and j + 1 changes
    at θ between them, from the solve's own slices: the interpolation's error across the two
    intervals around a middle slice b (t_j, or t_j+1 where j is the first),

        D = abs((1 − θ_b) v(t_a) + θ_b v(t_c) − v(t_b)),   θ_b = (t_b − t_a) / (t_c − t_a),

    carried to θ on [t_j, t_j+1] as an error that grows with the interval's length,
    D · θ(1 − θ) / (θ_b(1 − θ_b)) · (t_j+1 − t_j) / (t_c − t_a). Why linearly: near the horizon
    v changes fastest in the last moments (z between two goals, or at a kink of g), and the
    quadratic model of a smooth curvature read a third of the error there (stranger round 26,
    store_every=4 in the last interval); where v is smooth in time this reads high, by up to the
    ratio of the two intervals. 0 with fewer than three stored slices
    (:meth:`EmbeddedEstimate.between_slices`)."""
    times = solution.times
    if j >= 1:
        a, b, c = j - 1, j, j + 1
    elif j + 2 < len(times):
        a, b, c = j, j + 1, j + 2
    else:
        return np.zeros(len(x))
    ta, tb, tc = (float(times[k]) for k in (a, b, c))
    middle = (tb - ta) / (tc - ta)
    with np.errstate(invalid="ignore"):  # inf − inf where the solve underflowed
        va, vb, vc = (solution.value(x, s) for s in (ta, tb, tc))
        across = np.abs((1 - middle) * va + middle * vc - vb)
    length = (float(times[j + 1]) - float(times[j])) / (tc - ta)
    return across * theta * (1 - theta) / (middle * (1 - middle)) * length


def _local(v, embedded, pair, temperature: float, order: float) -> tuple[np.ndarray, np.ndarray]:
    """The difference and the local term (:meth:`EmbeddedEstimate.local`) from the values of the
    solve, of the embedded solve and of the ``pair`` (or None) at the same states. Only the
    embedded difference is divided by 2^q − 1: the pair's is not a difference between the
    spacings h and 2h but how much a solve at 2h moves with where its nodes fall, an error the
    grid shares, not a multiple of it."""
    with np.errstate(invalid="ignore"):  # inf − inf where v and a level underflowed: NaN there
        difference = np.abs(embedded - v)
        local = richardson(difference, relative_error(difference, v, temperature), order)
        if pair is not None:
            moved = np.abs(pair[0] - pair[1])
            difference, local = np.maximum(difference, moved), np.maximum(local, moved)
    return difference, local


def embedded_estimate(solution, embedded, coarser=None, pair=None, excess=None) -> EmbeddedEstimate:
    """The estimate of ``solution`` from its embedded solve and, if given, the one below it and
    those on :func:`phase_pair`.

    Over the :func:`calibration_states`: the observed order::

        p = log₂( Σ abs(v_4h − v_2h) / Σ abs(v_2h − v_h) )

    (NaN without the third solve) and the floor, the median of the local estimate relative to
    ``max(abs(v), λ)`` (the module docstring says why each).

    Parameters
    ----------
    solution, embedded, coarser : Solution
        The solves at h, 2h and 4h (steps Δt, 2Δt, 4Δt); ``coarser`` None: no third solve.
    pair : tuple of two Solution, or None
        The solves on :func:`phase_pair` (step 2Δt).
    excess : Response or None
        What the costs' sub-cell excess changes in the embedded solve
        (:attr:`EmbeddedEstimate.excess`).

    Returns
    -------
    EmbeddedEstimate
    """
    X = calibration_states(solution)
    v, v2 = solution.value(X, 0.0), embedded.value(X, 0.0)
    observed = np.nan
    if coarser is not None:
        observed = observed_order(np.abs(v2 - v), np.abs(coarser.value(X, 0.0) - v2))
    order = clipped_order(observed)
    sides = None if pair is None else [side.value(X, 0.0) for side in pair]
    _, local = _local(v, v2, sides, solution.temperature, order)
    relative = relative_error(local, v, solution.temperature)
    relative = relative[np.isfinite(relative)]
    floor = float(np.median(relative)) if len(relative) else 0.0
    return EmbeddedEstimate(embedded, observed, order, floor, pair, excess, coarser)


def observed_order(fine, coarse) -> float:
    """p = log₂( Σ coarse / Σ fine ) over the entries where both differences are finite: the
    order observed from the differences between successive levels, ``fine`` = abs(v_2h − v_h)
    and ``coarse`` = abs(v_4h − v_2h); NaN where nothing can be compared."""
    fine, coarse = np.atleast_1d(np.asarray(fine, float)), np.atleast_1d(np.asarray(coarse, float))
    usable = np.isfinite(fine) & np.isfinite(coarse)
    if not usable.any() or fine[usable].sum() <= 0:
        return np.nan
    with np.errstate(divide="ignore"):
        return float(np.log2(coarse[usable].sum() / fine[usable].sum()))


def clipped_order(observed: float) -> float:
    """q: the ``observed`` order clipped to [1, 2], and 1 where it is NaN (module docstring)."""
    return 1.0 if np.isnan(observed) else float(np.clip(observed, 1.0, 2.0))


def richardson(difference, relative, order: float) -> np.ndarray:
    """The local estimate from abs(v_2h − v_h): ``difference`` / (2^q − 1) where its
    ``relative`` size is at most :data:`ASYMPTOTIC`, the ``difference`` itself elsewhere (the
    module docstring says why)."""
    difference = np.asarray(difference, dtype=float)
    near = np.asarray(relative) <= ASYMPTOTIC
    return np.where(near, difference / (2.0**order - 1.0), difference)


@dataclass(frozen=True)
class ScalarEstimate:
    """The embedded estimate of one number computed by a solve (an average cost c), from the same
    number computed on the embedded grids h, 2h and 4h. With the order observed from them,

        p = log₂( abs(c_4h − c_2h) / abs(c_2h − c_h) ),      q = p clipped to [1, 2]

    (q = 1 without the 4h level), the estimate is

        ê = max( abs(c_2h − c_h),  abs(c_4h − c_2h) / 2^q ) / (2^q − 1),

    and without the division where abs(c_2h − c_h) exceeds :data:`ASYMPTOTIC` · abs(c_h), as for
    the values (:func:`richardson`). The second term is the difference that the coarser pair
    predicts between the finer: it keeps ê from vanishing where c_h and c_2h agree by chance
    (two error terms of opposite sign crossing), as the floor does for the values. ê is also at
    least abs(c_c₁ − c_c₂), the difference on the pair of :func:`phase_pair`, undivided as for
    the values: it is how far a coarse solve moves with where its nodes fall, not a multiple of
    this grid's error. And it is at least abs(γ_c), for an average cost the cost per unit time
    that the grid leaves out of q under the solve's stationary law
    (:func:`gridlbc.accuracy.paths.stationary_gap`), and at least S_c = abs(c_2h[q + δq] −
    c_2h[q]), what the state cost's excess between the nodes changes in the embedded solve
    (:mod:`gridlbc.accuracy.subcell`): the levels miss a feature of q narrower than a cell
    alike, γ_c sees one the solve's law crosses and S_c one a path would seek. And it is at
    least abs(E_π[λτ]), what the generator's truncation error leaves out of c under the same
    law (:mod:`gridlbc.accuracy.truncation`): where h/λ changes by several units per cell the
    levels are all far from their asymptotic range.

    Attributes
    ----------
    error : float
        ê, in the units of the number.
    observed_order : float
        p before clipping (NaN without a third level).
    levels : tuple of float
        The number on the grids h, 2h (and 4h).
    gap : float
        γ_c (0 where not sampled).
    response : float
        S_c (0 where not measured).
    truncation : float
        E_π[λτ] (0 where not measured).
    """

    error: float
    observed_order: float
    levels: tuple[float, ...]
    gap: float = 0.0
    response: float = 0.0
    truncation: float = 0.0

    @property
    def relative(self) -> float:
        """ê / abs(c_h) (:func:`scalar_relative`)."""
        return scalar_relative(self.error, self.levels[0])


def scalar_relative(error: float, value: float) -> float:
    """``error / abs(value)``: 0 where both are zero, +inf where only the value is."""
    if value != 0:
        return float(error / abs(value))
    return 0.0 if error == 0 else np.inf


def scalar_estimate(
    levels, pair=None, gap: float = 0.0, response: float = 0.0, truncation: float = 0.0
) -> ScalarEstimate:
    """The :class:`ScalarEstimate` of ``levels[0]`` from the same number on the embedded grids
    ``levels[1]`` (2h) and, if given, ``levels[2]`` (4h) and on :func:`phase_pair` (whose
    difference abs(c_c₁ − c_c₂) the estimate is at least), and at least abs(``gap``),
    ``response`` and abs(``truncation``).

    Parameters
    ----------
    levels : sequence of float
        c_h, c_2h and optionally c_4h.
    pair : tuple of two float, or None
        The number on the grids of :func:`phase_pair`.
    gap : float
        γ_c, what the grid leaves out of the number along the solve's own law
        (:func:`gridlbc.accuracy.paths.stationary_gap`).
    response : float
        S_c, what the costs' excess between the nodes changes in the number on the embedded grid.
    truncation : float
        E_π[λτ], what the generator's truncation error leaves out of the number
        (:func:`gridlbc.accuracy.truncation.average_truncation`).

    Returns
    -------
    ScalarEstimate
    """
    c = [float(level) for level in levels]
    fine = difference = abs(c[1] - c[0])
    observed, order = np.nan, 1.0
    if len(c) > 2:
        observed = observed_order(fine, abs(c[2] - c[1]))
        order = clipped_order(observed)
        difference = max(difference, abs(c[2] - c[1]) / 2.0**order)
    relative = difference / abs(c[0]) if c[0] != 0 else np.inf
    error = float(richardson(difference, relative, order))
    if pair is not None:  # how far a coarse solve moves with where its nodes fall: undivided
        error = max(error, abs(float(pair[0]) - float(pair[1])))
    error = max(error, abs(float(gap)), float(response), abs(float(truncation)))
    return ScalarEstimate(error, observed, tuple(c), float(gap), float(response), float(truncation))


def attach_estimates(solutions, levels: list, pairs=None, excess=None, reason: str = "") -> None:
    """Give each of ``solutions`` its :class:`EmbeddedEstimate` from the solves ``levels[0][r]``
    (2h), if present ``levels[1][r]`` (4h), ``pairs[0][r]``, ``pairs[1][r]``
    (:func:`phase_pair`) and ``excess[r]`` (what the costs' sub-cell excess changes,
    :class:`~gridlbc.accuracy.subcell.Response`), and warn (:func:`check_accuracy`) where one exceeds the
    default tolerance. Without levels there is no estimate, and a
    :class:`gridlbc.ResolutionWarning` gives the ``reason`` (a grid too coarse to embed, or a
    problem that cannot be posed on the embedded grid: the grid resolves it too barely for an
    estimate)."""
    if not levels:
        if reason:
            warn_user(
                f"no error estimate for this solve: {reason} (docs page 'accuracy')",
                ResolutionWarning,
            )
        return
    for r, solution in enumerate(solutions):
        coarser = levels[1][r] if len(levels) > 1 else None
        pair = (pairs[0][r], pairs[1][r]) if pairs is not None else None
        response = excess[r] if excess is not None else None
        estimate = embedded_estimate(solution, levels[0][r], coarser, pair, response)
        object.__setattr__(solution, "embedded", estimate)
        check_accuracy(solution)


def judged_states(solution, states=None) -> np.ndarray:
    """``states`` as ``(N, d)``, or :data:`ASSESSED` of :func:`states_that_matter` when None."""
    if states is None:
        return _nodes(solution, _judged_nodes(solution))
    return np.atleast_2d(np.asarray(states, dtype=float))


def _judged_nodes(solution) -> np.ndarray:
    """The flat indices of the nodes :func:`judged_states` reads without states: the
    :data:`ASSESSED` of :func:`states_that_matter`."""
    return _evenly_index(matter_mask(solution), ASSESSED)


def relative_difference(solution, other, X: np.ndarray, t: float = 0.0) -> np.ndarray:
    """abs(v_other − v) relative to the solution's value (:func:`relative_error`) at states ``X``
    at time ``t``: the embedded estimate when ``other`` is the embedded solve."""
    v = solution.value(X, t)
    return relative_error(np.abs(other.value(X, t) - v), v, solution.temperature)


def statistic(rel: np.ndarray, given: bool) -> float:
    """The number compared with a tolerance: the maximum over the user's states, the
    :data:`QUANTILE` over the states that matter."""
    if len(rel) == 0:
        return np.inf
    return float(rel.max()) if given else float(np.quantile(rel, QUANTILE))


def assess(solution, tol: float, states=None, times=None) -> Assessment | None:
    """Read the embedded estimate of ``solution`` at ``states`` (default: :func:`states_that_matter`).

    Parameters
    ----------
    solution : Solution
        A solution that carries its embedded solve.
    tol : float
        The relative tolerance that ``share_above`` counts against.
    states : array_like (N, d) or (d,), optional
        The states to judge; the statistic is then the maximum rather than the quantile, over
        ``times``.
    times : sequence of float, optional
        With ``states``: the times at which they are judged (default: 0 and :func:`late_times`).

    Returns
    -------
    Assessment or None
        None when the solution carries no embedded solve (a grid too coarse to embed).
    """
    if solution.embedded is None:
        return None
    if states is not None:
        return _assess_given(solution, tol, judged_states(solution, states), times)
    keep = _judged_nodes(solution)
    X = _nodes(solution, keep)
    # the local certificate only where confirmed_locally checks a candidate (its paths cost more
    # than γ's)
    rel = solution.embedded.relative(solution, X, samples=ASSESSED_PATHS, local=False)
    a = _read_at(X, rel, tol, False)
    problem = solution.problem
    if problem.exit is None and not problem.stationary:
        # also the better half, where a finite horizon's paths end up (states_that_matter):
        # the states read above that lie in it, an evenly spaced sample of it
        held = solution.better_half()[keep]
        half = _read_at(X[held], rel[held], tol, False)
        if half.error > a.error:
            a = replace(half, half=True)
        if half.worst_error > a.worst_error:
            a = replace(a, worst_state=half.worst_state, worst_error=half.worst_error)
    matter = _Matter(solution)  # what S's maximum and the confirmation both read
    if solution.embedded.excess is not None:
        largest, where = largest_response(solution, matter)
        if largest > a.error:
            a = replace(a, error=largest, local=True)
        if largest > a.worst_error:
            a = replace(a, worst_state=where, worst_error=largest)
    for reading in _readings(solution, matter):
        if a.error > tol:
            break
        between = interpolated_in_time(solution, tol, reading)
        if between is not None and between.error > a.error:
            a = replace(between, between=True, time=reading.t)
            if a.error > tol:
                break
        both, where = confirmed_locally(solution, tol, reading)
        if both > a.error:
            worst = max(both, a.worst_error)
            a = replace(a, error=both, worst_state=where, worst_error=worst, confirmed=True)
            a = replace(a, between=False, time=reading.t)
    return a


def _readings(solution, matter: _Matter):
    """The states that matter read at t = 0, then (lazily: :func:`assess` stops where a reading
    already exceeds its tolerance) at each of :func:`late_times`."""
    yield matter
    for t in late_times(solution):
        yield matter.at(t)


def interpolated_in_time(solution, tol: float, matter: _Matter) -> Assessment | None:
    """:meth:`EmbeddedEstimate.between_slices` relative to max(abs(v), λ), read at the states
    that matter at the time of ``matter`` (its :data:`QUANTILE`); None where the solve stores
    every step or the time is a stored one.

    Why on its own: interpolating in time between stored slices far apart errs alike at most
    states (a broad error, read at the quantile as the grid terms are), and the coarser solves,
    which store theirs more densely, measure it directly, without the sampling that the
    confirmation needs; the middle of the last stored interval, one of :func:`late_times`, is
    where it is largest."""
    if solution.diagnostics.store_every == 1 or matter.t in solution.times:
        return None
    X = matter.states
    tau = solution.embedded.between_slices(solution, X, matter.t)
    return _read_at(X, relative_error(tau, matter.value, solution.temperature), tol, False)


def late_times(solution) -> list[float]:
    """The times late in a task with a horizon at which :func:`assess` also confirms a default
    solve (:func:`confirmed_locally`): :func:`late_time`, from which the local certificate runs
    to the horizon, and T − Δs/2, Δs the last interval between stored slices (T − Δt/2 where
    every step is stored); none without a horizon.

    Why the second: a step long against how fast the terminal cost makes v change errs most in
    the first steps from T, and a value read between two stored slices is interpolated in time
    (a point mass with a terminal cost only, no drift and no state cost, solved at the default
    step T/10, is within 0.3 % at t = 0 and 13–27 % off at T − Δt/2, stranger round 21); 8 steps
    before T that error has not yet reached the states, and on a 10-step solve T − 8Δt is early
    in the task. At that time the solves at 2h and 4h, with their longer steps, interpolate
    across more of the change than the solve, and the order observed from them there
    (:meth:`EmbeddedEstimate.order_at`) says so."""
    problem = solution.problem
    if problem.stationary:
        return []
    times = solution.times
    middle = float(times[-1] - (times[-1] - times[-2]) / 2) if len(times) > 1 else 0.0
    return [t for t in dict.fromkeys((late_time(solution), middle)) if t > 0.0]


def _assess_given(solution, tol: float, X: np.ndarray, times=None) -> Assessment:
    """:func:`assess` at the user's states ``X``: the largest estimate there, with the local
    certificate, over ``times`` (default: t = 0 and :func:`late_times`, since a task with a
    horizon is also run late, from wherever it stands), and the largest over those after 0."""
    times = (0.0, *late_times(solution)) if times is None else tuple(times)
    readings = []
    for t in times:
        rel = solution.embedded.relative(solution, X, t, samples=ASSESSED_PATHS)
        readings.append(replace(_read_at(X, rel, tol, True), time=t))
    a = max(readings, key=lambda reading: reading.error)
    late = [reading.error for reading in readings if reading.time > 0.0]
    return replace(a, late_error=max(late, default=0.0))


def late_time(solution) -> float:
    """T − :data:`~gridlbc.accuracy.bellman.SPAN` Δt, the time from which the local certificate
    of :func:`confirmed_locally` runs to the horizon, where a default solve with a horizon is
    also checked (:func:`assess`); 0 without a horizon or where the horizon is closer than that
    (the check at t = 0 is then the same)."""
    problem = solution.problem
    if problem.stationary:
        return 0.0
    return max(0.0, problem.horizon - SPAN * solution.diagnostics.dt)


class _Matter:
    """The :func:`states_that_matter` of a solution, and v and S there at time ``t``, each read
    once when first asked for (:func:`assess` gives them to :func:`largest_response` and to
    :func:`confirmed_locally`)."""

    def __init__(self, solution, t: float = 0.0):
        self.solution, self.t = solution, t

    def at(self, t: float) -> _Matter:
        """The same states (chosen at t = 0) read at time ``t``: their nodes and mask shared."""
        other = _Matter(self.solution, t)
        other.__dict__.update(states=self.states, mask=self.mask)  # the cached properties
        return other

    @cached_property
    def states(self) -> np.ndarray:
        """:func:`states_that_matter`."""
        return states_that_matter(self.solution)

    @cached_property
    def mask(self) -> np.ndarray:
        """The flat mask of the nodes among which :attr:`states` are chosen
        (:func:`states_that_matter`)."""
        return matter_mask(self.solution)

    @cached_property
    def value(self) -> np.ndarray:
        """v at :attr:`states`, time t."""
        return self.solution.value(self.states, self.t)

    @cached_property
    def response(self) -> np.ndarray:
        """S at :attr:`states`, time t (:meth:`EmbeddedEstimate.excess_response`)."""
        return self.solution.embedded.excess_response(self.states, self.t)


CONFIRMED = 64
"""At most this many states, those with the largest grid terms above the tolerance among the
states that matter and the centres of the cells around them, are checked along the solve's own
paths by :func:`confirmed_locally`, each from :data:`~gridlbc.accuracy.paths.PATH_SAMPLES` paths
(as many paths in all as the quantile's states take: the largest of a few noisy means would
otherwise read high)."""


def confirmed_locally(
    solution, tol: float, matter: _Matter | None = None
) -> tuple[float, np.ndarray]:
    """The largest relative error that two independent parts of the estimate both give at one
    of the states that matter or between them, at the time of ``matter`` (0 by default), and
    where: min(grid terms, max(abs(γ), :func:`~gridlbc.accuracy.bellman.local_error`)) relative
    to max(abs(v), λ), over the :data:`CONFIRMED` candidates whose grid terms (the embedded and
    pair differences, the floor and S, :meth:`EmbeddedEstimate.grid_terms`) are the largest
    above ``tol``; 0 where none is above it or γ is not sampled. The candidates are the
    :data:`CONFIRMED` states that matter with the largest grid terms and the centres of the cells
    around them that lie among the states that matter (:func:`cell_centres`).

    Why: the quantile lets a tenth of the states through, and an error confined to a small
    region (a steep goal at a short horizon, a kink between the nodes) stays under it however
    large it is there. Judged at their maximum alone, the grid terms raise false alarms where
    the coarser solves over-read a well's bottom or a box's edge; γ, sampled along the solve's
    own paths from the same states, measures something else (the costs the grid leaves out
    along the way and at the end), so where both exceed the tolerance the error is taken as
    real. The states that matter are nodes, where a value is solved for; a value read between
    them is also interpolated, and where v bends within a cell (a kink of g between the nodes
    under a short horizon) its error is largest at the cell's centre, where no node sees it.
    ``matter``: the states that matter and what is read there, where the caller has them
    (:func:`assess`)."""
    problem = solution.problem
    none = (0.0, np.full(solution.grid.ndim, np.nan))
    if not sampled(problem):
        return none
    matter = _Matter(solution) if matter is None else matter
    X = matter.states
    if len(X) == 0:
        return none
    v, t = matter.value, matter.t
    estimate = solution.embedded
    response = None if estimate.excess is None else matter.response
    grid = relative_error(estimate.grid_terms(solution, X, t, v, response), v, solution.temperature)
    top = np.argsort(grid)[::-1][:CONFIRMED]
    centres = cell_centres(solution, X[top], matter.mask)
    v_centres = solution.value(centres, t)
    grid_centres = relative_error(
        estimate.grid_terms(solution, centres, t, v_centres), v_centres, solution.temperature
    )
    X = np.concatenate([X[top], centres])
    v = np.concatenate([v[top], v_centres])
    grid = np.concatenate([grid[top], grid_centres])
    top = candidates(grid, tol)
    if len(top) == 0:
        return none
    paths = relative_error(np.abs(path_check(solution, X[top], t)), v[top], solution.temperature)
    both = np.fmin(grid[top], paths)
    worst = int(np.argmax(both))
    return float(both[worst]), X[top[worst]]


def candidates(rel: np.ndarray, tol: float) -> np.ndarray:
    """The indices of the :data:`CONFIRMED` largest entries of ``rel`` above ``tol``, largest
    first: the states a reading checks along the paths (:func:`confirmed_locally`,
    :func:`check_combination`)."""
    above = np.flatnonzero(rel > tol)
    return above[np.argsort(rel[above])[::-1][:CONFIRMED]]


def path_check(solution, X: np.ndarray, t: float) -> np.ndarray:
    """What the solve's own paths say of its error at the candidates ``X`` (N, d), time ``t``,
    signed as v − v_h: the larger of abs(γ) (with the sign of −γ: γ > 0 where the grid charges
    more than the costs) and :func:`~gridlbc.accuracy.bellman.local_error` (with the sign of
    v_ℓ − v_h), the local certificate discounted as the largest of N is
    (:func:`~gridlbc.accuracy.bellman.largest_discount`) (:func:`confirmed_locally` reads its
    size, :func:`check_combination` carries it through the blend)."""
    gamma = cost_gap(solution, X, t, PATH_SAMPLES)
    gap, se = bellman_gap(solution, X, t)
    local = beyond_noise(gap, se, largest_discount(len(X)))
    return np.where(np.abs(gamma) >= local, -gamma, -np.sign(gap) * local)


def cell_centres(solution, nodes: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The centres of the cells that have one of ``nodes`` (N, d) as a corner and whose every
    corner is in ``mask`` (a flat boolean array over the grid's nodes), ``(M, d)``, each once:
    on a closed axis the cells inside the box, on a periodic one also those across its seam."""
    grid = solution.grid
    if len(nodes) == 0:
        return np.empty((0, grid.ndim))
    n = np.array(grid.shape)
    periodic = grid.periodic
    index = grid.nearest_node(nodes)
    shifts = np.array(np.meshgrid(*([[-1, 0]] * grid.ndim), indexing="ij")).reshape(grid.ndim, -1).T
    lower = (index[:, None, :] + shifts[None]).reshape(-1, grid.ndim)
    lower = np.where(periodic, lower % n, lower)
    inside = np.all(periodic | ((lower >= 0) & (lower <= n - 2)), axis=1)
    lower = np.unique(lower[inside], axis=0)
    corners = (lower[:, None, :] + shifts[None] + 1) % n  # lower + {0, 1}^d, wrapped
    held = np.all(mask[corners @ grid.strides], axis=1)
    return grid.lo + (lower[held] + 0.5) * grid.spacing


def _read_at(X: np.ndarray, rel: np.ndarray, tol: float, given: bool) -> Assessment:
    """The :class:`Assessment` of the relative estimate ``rel`` read at the states ``X``
    (:func:`statistic`), without S's maximum."""
    if len(rel) == 0:
        return Assessment(np.inf, np.full(X.shape[1], np.nan), np.inf, 1.0, 0)
    worst = int(np.argmax(rel))
    error = statistic(rel, given)
    return Assessment(error, X[worst], float(rel[worst]), float(np.mean(rel > tol)), len(X))


def largest_response(solution, matter: _Matter | None = None) -> tuple[float, np.ndarray]:
    """The largest relative S (:meth:`EmbeddedEstimate.excess_response`, relative as
    :func:`relative_error`) over the :func:`states_that_matter`, and where it is.

    A cost feature narrower than a cell changes the value near it only, on a share of the states
    that matter that may be far below 1 − :data:`QUANTILE`: S is judged by its largest value. It
    is a solve's response to the measured excess, with no sampling noise for a quantile to
    discount. ``matter``: the states that matter and what is read there, where the caller has
    them (:func:`assess`)."""
    matter = _Matter(solution) if matter is None else matter
    X = matter.states
    if len(X) == 0:
        return 0.0, np.full(solution.grid.ndim, np.nan)
    rel = relative_error(matter.response, matter.value, solution.temperature)
    worst = int(np.argmax(rel))
    return float(rel[worst]), X[worst]


ESTIMATE_WARNING = "the estimated error of "
"""How :func:`check_accuracy`'s warning begins (a solve to a tolerance reads the estimate itself
and reports it, :func:`gridlbc.accuracy.tolerance.finish`)."""


def check_accuracy(solution, tol: float = DEFAULT_TOLERANCE) -> None:
    """Warn (:class:`gridlbc.ResolutionWarning`) when the embedded estimate of a default solve
    exceeds ``tol`` at the states that matter (:func:`assess`).

    Parameters
    ----------
    solution : Solution
        The solution to judge.
    tol : float
        The relative tolerance (default :data:`DEFAULT_TOLERANCE`).
    """
    a = assess(solution, tol)
    if a is None or a.error <= tol:
        return
    state = np.array2string(a.worst_state, precision=3, separator=", ")
    loose = (
        ""
        if solution.embedded.converging
        else " The coarser grids converge slowly or not at all (their differences shrink by less "
        "than 2 per level), so the estimate is rough: the error may be well above or well below "
        "it; gridlbc.certify at your states tells."
    )
    change = (
        "Give a finer grid"
        if solution.problem.stationary
        else f"Solve with tol={tol:g} to refine dt and the grid until the estimate meets it, or "
        "give a finer grid or a smaller dt"
    )
    if a.between:
        every = solution.diagnostics.store_every
        where = (
            f"at t = {a.time:.3g}, between the stored slices (store_every={every}: the value "
            "is interpolated linearly in time between every "
            f"{every}th step's slice), where interpolating changes v by more than {a.error:.0%} "
            f"at {1 - QUANTILE:.0%} of the states that matter (the largest, "
            f"{a.worst_error:.0%}, at {state}), measured on the grid with every other node, "
            "which stores its slices at least twice as densely"
        )
        change = "Read v at the stored times (solution.times), or solve with a smaller store_every"
    elif a.confirmed:
        when = f" at t = {a.time:.3g}" if a.time else ""
        where = (
            f"near {state}{when}: there the solves on the grids with every other node and a check "
            "along the solve's own paths (the costs its grid leaves out, or its value against "
            f"what the SDE makes of it a little later) both put it at {a.error:.0%} of |v|, on a "
            "share of the states that matter too small for the percentile the warning "
            "otherwise reads"
        )
    elif a.local:
        where = (
            f"near {state}, where a cost or a part of the exit set narrower than a cell, between "
            "the nodes, changes the solve on the grid with every other node by up to "
            f"{a.error:.0%} of |v| (the costs sampled between the nodes against their "
            "reconstruction from the nodes, and the exit set's parts that no node holds)"
        )
    else:
        judged = (
            "the better half of the states (value at most the median), where the paths end up"
            if a.half
            else "the states that matter"
        )
        where = (
            f"at {a.share_above:.0%} of {judged} ({QUANTILE:.0%} of them are "
            f"within {a.error:.1%}; the largest, {a.worst_error:.0%}, is at {state}): measured "
            "against solves on the grids with every other node"
            + (" and along the solve's own paths" if sampled(solution.problem) else "")
        )
    value, symbol = "v", "v"
    if getattr(solution, "average_cost", None) is not None:
        value, symbol = "the relative value h (the average cost c has its own estimate)", "h"
    warn_user(
        f"{ESTIMATE_WARNING}{value} exceeds {tol:.0%} of |{symbol}| {where}, see "
        f"solution.error_estimate(x) at your own states.{loose} {change} (docs page 'accuracy')",
        ResolutionWarning,
    )


def check_combination(combined, tol: float = DEFAULT_TOLERANCE) -> None:
    """Warn (:class:`gridlbc.ResolutionWarning`) when the estimate that a combination of grid
    solutions carries, Σ_i abs(α_i) ê_i (:func:`gridlbc.combine.combined_error`), exceeds
    ``tol`` relative to the combination's value at the :data:`ASSESSED` states that matter of its
    first component: at t = 0 at their :data:`QUANTILE`, with each ê_i its grid terms
    (:meth:`EmbeddedEstimate.grid_terms`: no paths), and at the late times where its
    components are judged (:func:`late_times`) where the components' own paths confirm it, as a
    solve's late readings are confirmed (:func:`confirmed_locally`): at the :data:`CONFIRMED`
    states where the carried grid terms are largest above ``tol``,

        min( Σ_i abs(α_i) ê_i, abs(δv) ) / max(abs(v), λ),

    δv the components' signed path checks (:func:`path_check`) carried through the blend
    (:func:`blended`).

    Why: weights far from one move the combination's value far from its components' (a weight
    10³ lowers it by λ log 10³ where that component leads), while their absolute errors carry
    over: a component 4 % off can leave a combination 30 % off, relative to its own smaller
    value, and each component's solve judged only itself. Late in a task a component's value
    between its time levels is a few percent off where z changes fast (between two goals near
    T), within its own tolerance, and the same error is many times that of a combination whose
    weights bring its value near 0 (stranger round 26: 13–16 % at t = 1.9 of 2 with weights 1
    and 10³, the components within 2.4 %, silent while only t = 0 was judged). There the grid
    terms alone over-read (the coarser solves' longer steps), as they do for the components'
    own late readings. Nothing is checked where a component carries no estimate."""
    components = combined.components
    if not all(getattr(c, "embedded", None) is not None for c in components):
        return
    X = judged_states(components[0])
    if len(X) == 0:
        return
    lam = combined.problem.temperature
    for t in (0.0, *late_times(components[0])):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an underflowed blend was combine's to warn of
            alpha, value = combined.blend_and_value(X, t)  # one evaluation of the components
            alpha = np.asarray(alpha, dtype=float).reshape(len(X), -1)
        grid = np.stack([c.embedded.grid_terms(c, X, t) for c in components], axis=1)
        rel = relative_error(np.sum(np.abs(alpha) * grid, axis=1), value, lam)
        usable = np.isfinite(rel)
        if not usable.any():
            continue
        if t == 0.0:
            error = statistic(rel[usable], False)
            share = f"at {np.mean(rel[usable] > tol):.0%} of the states that matter "
            share += f"({QUANTILE:.0%} of them are within {error:.1%})"
        else:
            top = candidates(rel, tol)
            if len(top) == 0:
                continue
            paths = np.stack([path_check(c, X[top], t) for c in components], axis=1)
            carried = relative_error(blended(alpha[top], paths, lam), value[top], lam)
            both = np.fmin(rel[top], carried)
            if not np.isfinite(both).any():
                continue
            error = float(np.nanmax(both))
            worst = np.array2string(X[top[int(np.nanargmax(both))]], precision=3, separator=", ")
            share = f"near {worst} at t = {t:.3g}, where its components' own paths confirm it"
        if error > tol:
            warn_user(
                f"the estimated error of the combination's v exceeds {tol:.0%} of |v| {share}: "
                "its components' estimates carried by the blend weights, Σ|α_i| ê_i, against a "
                "value that weights far from one move far from the components' own. See "
                "combined.error_estimate(x, t) at your own states; solve the components on a "
                "finer grid or with a smaller dt, or with tol= (docs page 'accuracy')",
                ResolutionWarning,
            )
            return


def blended(alpha: np.ndarray, errors: np.ndarray, lam: float) -> np.ndarray:
    """abs(δv) of a combination whose components are off by the signed ``errors`` δv_i (N, n)
    (v_i + δv_i their values), with blend weights ``alpha`` (N, n):

        δv = −λ log Σ_i α_i exp(−δv_i / λ),

    exact for any size of the δv_i where the weights are positive (a component far too low
    dominates the blend, one far too high drops out of it: Σ_i α_i δv_i, its first order, read
    7.4 % where the combination is 2.7 % off, a component 12 above its own value at weight ½);
    Σ_i abs(α_i δv_i) where a weight is negative (:func:`check_combination`)."""
    if np.any(alpha < 0):
        return np.sum(np.abs(alpha * errors), axis=1)
    with np.errstate(divide="ignore"):
        return np.abs(-lam * logsumexp(np.log(alpha) - errors / lam, axis=1))


def check_scalar(estimate: ScalarEstimate, name: str, tol: float = DEFAULT_TOLERANCE) -> None:
    """Warn (:class:`gridlbc.ResolutionWarning`) when the relative :class:`ScalarEstimate` of the
    number ``name`` exceeds ``tol``, as :func:`check_accuracy` does for the values.

    Parameters
    ----------
    estimate : ScalarEstimate
    name : str
        What the number is, for the message (e.g. ``"the average cost c"``).
    tol : float
        The relative tolerance (default :data:`DEFAULT_TOLERANCE`).
    """
    if estimate.relative <= tol:
        return
    levels = ", ".join(f"{c:.4g}" for c in estimate.levels)
    loose = (
        " The coarser grids converge slowly or not at all (their differences shrink by less "
        "than 2 per level), so the estimate is rough: the error may be well above or well below "
        "it."
        if estimate.observed_order < 1.0
        else ""
    )
    gap = ""
    if abs(estimate.gap) >= estimate.error:
        gap = (
            "; the state cost between the nodes, sampled under the solve's stationary law, "
            f"differs from what the grid charges by {estimate.gap:.3g} per unit time (a feature "
            "of q narrower than a cell)"
        )
    elif estimate.response >= estimate.error:
        gap = (
            "; the state cost's excess between the nodes (a well narrower than a cell) moves c "
            f"on the grid with every other node by {estimate.response:.3g}"
        )
    elif abs(estimate.truncation) >= estimate.error:
        gap = (
            "; the grid's truncation error on the solved relative value (which changes by "
            f"several λ between the nodes) leaves out {estimate.truncation:.3g} per unit time "
            "under the solve's stationary law"
        )
    warn_user(
        f"the estimated error of {name} = {estimate.levels[0]:.6g} is {estimate.error:.3g}, "
        f"{estimate.relative:.1%} of it (above {tol:.0%}): measured against the same solve on the "
        f"grids with every other node ({levels} on h, 2h, 4h){gap}.{loose} Give a finer grid "
        "(docs page 'accuracy')",
        ResolutionWarning,
    )
