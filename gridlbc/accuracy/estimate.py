"""The embedded error estimate of a solve: what it is made of and how it is read at any state
(docs page :doc:`accuracy`). Which states a default solve is judged at is
:mod:`gridlbc.accuracy.matter`; how it is judged against a tolerance and warned about,
:mod:`gridlbc.accuracy.assessment`.

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
  :meth:`EmbeddedEstimate.order_at <gridlbc.accuracy.EmbeddedEstimate.order_at>`) where the two
  solves differ by at most :data:`~gridlbc.accuracy.estimate.ASYMPTOTIC` relative to the value, and
  q = 1 where they differ by more: a coarse solve that far from the fine one is outside the range
  where Richardson's model holds, and an order observed from it says more about the coarse grids
  than about this one (dividing by 3 there understated the error of the hold-out corpus's 25⁴
  acrobot: docs page :doc:`accuracy`, "What the estimate is");
- the floor r, the median over the calibration states
  (:func:`~gridlbc.accuracy.calibration_states`) of the first term relative to the value:
  errors accumulate with the cost along the characteristics, so where the two solves happen to agree
  (their difference changes sign) the error is not smaller, relative to v, than the typical one
  (:func:`~gridlbc.accuracy.embedded_estimate`).

The estimate is also at least abs(v_c₁ − v_c₂), undivided: the difference between the solves
(step 2Δt) on a pair of grids whose cell counts add up to the grid's
(:func:`~gridlbc.accuracy.phase_pair`). The embedded grid misses a narrow feature midway
between two nodes by as much as the grid does, and the pair's difference is what sees that error; it
is how far a coarse solve moves with where its nodes fall, not a difference between h and 2h, so it
is not divided by 2^q − 1. The pair costs one or two more coarse solves (one where every axis has an
odd cell count: its first grid is then the embedded one), and is solved only where the problem may
have a feature narrower than a cell (:func:`~gridlbc.accuracy.reads_pair`: costs with an excess
between the nodes, an exit set, a drift or a noise whose interpolation error does not converge at
first order on the grids the estimate reads); with smooth costs and coefficients its difference is
of the order of the embedded one.

The estimate is also at least abs(γ(x, t)), the cost that the grid's interpolants of q and g add
along the solve's own paths (:mod:`gridlbc.accuracy.paths`): it sees a cost narrower than a cell
wherever the nodes fall, also where the pair's two offsets are equal and every coarser grid
misses the feature alike (next to the ends of an axis, and its centre where its cell count is
even: :func:`~gridlbc.accuracy.phase_pair`).

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
(:meth:`EmbeddedEstimate.between_slices <gridlbc.accuracy.EmbeddedEstimate.between_slices>`).

At the states a user asks about (:meth:`EmbeddedEstimate.error
<gridlbc.accuracy.EmbeddedEstimate.error>`, not at the states a default solve is judged at, where it
would cost several times γ's paths) it is also at least the local certificate's abs(v_h − v_ℓ) less
two of its standard errors (:mod:`gridlbc.accuracy.bellman`): v_h against what the SDE makes of it a
few steps later. It sees a value steeper than a cell where the costs are smooth (next to an
invariant edge), which the coarser grids interpolate alike and the cost gap does not see. Beside it,
where its paths are affordable, the certificate of the whole remaining task (the paths run to the
horizon, where v_h is g, exact): an error that x shares with every state its paths reach before T
(an exit across an axis without noise, late in a task) is seen only so.

The estimate never changes the solution it checks. It sees what refining h and Δt would change:
time steps too long for a fast local flow, features narrower than a cell, a grid too coarse for
the value's curvature. It cannot see an error that all the solves share and the paths do not
feel: a box too small for the process (reflection at a closed axis acts the same on each), a
feature that every grid misses and the paths step over.
Where the observed order is below 1 the coarser solves are not converging at first
order: they are too coarse to say how accurate this grid is, and the estimate is rough in either
direction (far above the error on 4-D grids of a few dozen nodes per axis, below it where the
solves converge slowly, as on a first-exit pendulum swing-up: docs page :doc:`accuracy`, "What
the estimate is"), and the warning says so.

**Relative error.** ``ê / max(abs(v), λ)``: a value below the temperature λ is compared with λ,
the scale on which v = −λ log z is resolved (near a goal v can be arbitrarily small while its
error is a fraction of λ). At the user's own states (``solve(tol=, states=)``) the floor is
min(λ, abs(v(x, 0))) instead (:func:`given_floor`): a tolerance there is relative to v itself.
"""

from __future__ import annotations

import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..errors import UnderflowWarning
from ..problem import bracket
from ..representation import warn_underflow
from .bellman import local_error, value_bound
from .matter import calibration_states
from .paths import PATH_SAMPLES, nodal, sampled
from .subcell import Response
from .tracing import gaps
from .truncation import truncation_gap

if TYPE_CHECKING:
    from ..solution import Solution


ASYMPTOTIC = 0.15
"""Where the embedded solve differs from the solve by more than this (relative to
``max(abs(v), λ)``), the estimate does not divide by the observed order (the module docstring)."""


ORDER_SAMPLE = 2_000
"""At most this many of the calibration states give the order observed at a time t > 0
(:meth:`EmbeddedEstimate.order_at <gridlbc.accuracy.EmbeddedEstimate.order_at>`): a ratio of two
sums, read at each time asked for."""


def relative_error(estimate: np.ndarray, value: np.ndarray, floor) -> np.ndarray:
    """``estimate / max(|value|, floor)`` (see the module docstring), the floor λ or an array of
    floors, one per state (the user's own states: :func:`given_floor`); +inf where the value is
    not finite (underflow); 0 where the estimate and the scale are both 0 (a state in the exit
    set, whose value is given)."""
    value = np.asarray(value, dtype=float)
    estimate = np.asarray(estimate, dtype=float)
    scale = np.maximum(np.abs(value), floor)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where((estimate == 0) & (scale == 0), 0.0, estimate / scale)
    return np.where(np.isfinite(value) & np.isfinite(out), out, np.inf)


def given_floor(solution, X: np.ndarray) -> np.ndarray:
    """The floor of the scale a relative error is read against at the user's own states ``X``
    (``solve(tol=, states=)``): min(λ, abs(v(x, 0))) per state, in place of λ; λ for an average
    cost, whose relative value h is defined up to a constant (zero at a state of its own choosing),
    so that abs(h) there is no scale.

    So at t = 0 a tolerance there is relative to abs(v(x, 0)) itself, as its user reads it, and
    later in the task to the larger of abs(v(x, t)) and that. Why not λ: at a state where v is
    well below λ (near an exit, a cheap task at a high temperature) a tolerance relative to λ
    is many times one relative to v, and ``tol=0.05`` there accepted values 11 to 19 % off with no
    refinement (stranger round 47, first exits with a horizon, 3 cells from E: docs page
    :doc:`accuracy`, "Relative error and the states that matter"). Over the states that matter,
    which a default solve is judged at, λ stays the floor: they include the nodes next to a
    goal or an exit, where every grid's relative error is large and says nothing of the task."""
    if solution.problem.average_cost:
        return np.full(len(X), solution.temperature)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnderflowWarning)  # +inf: the floor is λ there
        v = np.abs(np.asarray(solution.value(X, 0.0), dtype=float)).reshape(-1)
    return np.minimum(solution.temperature, v)


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
        solves differ by at most :data:`~gridlbc.accuracy.estimate.ASYMPTOTIC`.
    floor : float
        The least relative error reported (the median over the
        :func:`~gridlbc.accuracy.calibration_states`).
    pair : tuple of two Solution, or None
        The same problem solved on the grids of :func:`~gridlbc.accuracy.phase_pair` (step
        2Δt); None where the grid is too coarse for them.
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
        :data:`~gridlbc.accuracy.estimate.ORDER_SAMPLE` of
        the :func:`~gridlbc.accuracy.calibration_states`, clipped as
        :attr:`order` is.

        Why: which error dominates changes along a task. At t = 0 a grid's spacing may set it,
        and the levels converge at second order; in the first steps from T the step's error
        and the interpolation between stored slices set it, and a solve at 2Δt with its
        longer steps differs from the solve by as much as the solve's own error or more (the
        order observed there is below 1): divided by 2^q − 1 with the second order of t = 0
        it reads about a third of the error (stranger round 21, docs page :doc:`accuracy`,
        "The last step")."""
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
        difference and abs(v_c₁ − v_c₂), the ``pair``'s
        (:func:`~gridlbc.accuracy.phase_pair`)."""
        return self._read(solution, x, t)[2]

    def local(self, solution: Solution, x, t=0.0) -> np.ndarray:
        """abs(v_2h − v_h) / (2^q − 1) at states ``x`` (N, d), time ``t``, with q = ``order``
        where the relative difference is at most :data:`~gridlbc.accuracy.estimate.ASYMPTOTIC` and 1
        elsewhere, and at least the pair's difference abs(v_c₁ − v_c₂) and :meth:`between_slices`,
        undivided."""
        return self._read(solution, x, t)[3]

    def between_slices(self, solution: Solution, x, t=0.0, embedded=None) -> np.ndarray:
        """τ(x, t) = abs((1 − θ) v_2h(x, t_j) + θ v_2h(x, t_j+1) − v_2h(x, t)) at states ``x``
        (N, d), t = (1 − θ) t_j + θ t_j+1 between two of the solve's stored times: what
        interpolating linearly in time between the solve's slices changes, measured on the
        embedded solve, which stores its own at most half as far apart
        (:func:`~gridlbc.accuracy.embedded_store_every`); 0 at a stored time and where the
        solve stores every step (between its steps the interpolation is part of the step's
        error, which the embedded difference reads). Where the embedded solve stores no slice
        inside [t_j, t_j+1] (an interval as short as its own step, as the last one often is),
        it interpolates there as the solve does and τ is read from the solve's own slices
        instead (:func:`~gridlbc.accuracy.estimate.own_interpolation_error`). ``embedded``: v_2h(x,
        t), where the caller has it."""
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
        (:func:`~gridlbc.accuracy.cost_gap`, from ``samples`` paths per state), the
        truncation and tracing terms where they apply (module docstring), and at least the
        local certificate beyond its noise (:func:`~gridlbc.accuracy.local_error`); +inf where
        v underflowed, told once (:func:`gridlbc.representation.warn_underflow`): the states are
        the caller's, the estimate's own reads of the solves are not."""
        with quiet_reads():
            v, error = self._error(solution, x, t, samples, whole=True)
        warn_underflow(~np.isfinite(v))
        return error

    def excess_response(self, x, t=0.0) -> np.ndarray:
        """S = abs(v_2h[g + δg, q + δq] − v_2h[g, q]) at states ``x`` (N, d), time ``t``: what
        the costs' excess between the nodes changes in the embedded solve
        (:class:`~gridlbc.accuracy.subcell.Response`); zero without it."""
        if self.excess is None:
            return np.zeros(len(np.atleast_2d(x)))
        return self.excess(x, t)

    def relative(
        self,
        solution: Solution,
        x,
        t=0.0,
        samples: int = PATH_SAMPLES,
        local: bool = True,
        whole: bool = False,
        floor=None,
    ) -> np.ndarray:
        """:meth:`error` relative to ``max(abs(v), λ)``
        (:func:`~gridlbc.accuracy.estimate.relative_error`; ``floor`` in place of λ where given,
        :func:`given_floor`), with the local certificate
        over :data:`~gridlbc.accuracy.bellman.SPAN` steps only (what ``solve(tol=, states=)`` reads
        each round) unless ``whole`` (the whole remaining task's beside it, as :meth:`error`
        reads it), and without either where ``local`` is False."""
        v, error = self._error(solution, x, t, samples, local, whole)
        return relative_error(error, v, solution.temperature if floor is None else floor)

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
        with np.errstate(invalid="ignore"):  # 0 · inf where v underflowed: _error says inf
            floor = self.floor * np.maximum(np.abs(v), solution.temperature)
        if response is None:
            response = 0.0 if self.excess is None else self.excess(x, t)
        return v, np.maximum(np.maximum(local, floor), response)

    def _error(
        self, solution: Solution, x, t, samples: int, local: bool = True, whole: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """v_h and :meth:`error` at ``x``: without the local certificate, and without holding the
        truncation term below a policy's cost (:func:`~gridlbc.accuracy.bellman.value_bound`),
        where ``local`` is False (the states a default solve is judged at,
        :func:`~gridlbc.accuracy.assessment.assess`), with the whole remaining task's certificate
        beside it where ``whole`` is True (the user's states)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        v, grid_terms = self._grid_terms(solution, x, t)
        gap, tracing = gaps(solution, x, samples, t)  # γ and the traced feet, on the same paths
        terms = np.fmax(grid_terms, np.abs(gap))
        truncation = truncation_gap(solution, x, samples, t, below=terms, v=v)
        with np.errstate(invalid="ignore"):  # inf − inf where v underflowed (inf below)
            truncation = np.fmin(truncation, worst_value(solution, t) - v)  # v − v_h: at most
        # an error larger than the value: at most what a policy costs here, sampled from each
        # such state where the local certificate is read too (not at every judged node)
        beyond = np.flatnonzero(truncation > np.fmax(np.abs(v), solution.temperature))
        if local and len(beyond):
            bound = value_bound(solution, x[beyond], t) - v[beyond]
            truncation[beyond] = np.fmin(truncation[beyond], bound)
        error = np.fmax(np.fmax(terms, np.abs(truncation)), np.abs(tracing))
        if local and sampled(solution.problem):
            error = np.fmax(error, local_error(solution, x, t, whole=whole))
        # where v underflowed (+inf) no term is a number and the error is not bounded: +inf, as
        # relative_error reads it (stranger round 44: 0 there, from NaN terms fmax passed over)
        error = np.where(np.isfinite(v), error, np.inf)
        if solution.problem.exit is not None:  # v = g_E on E, exactly (Solution.fields)
            error = np.where(solution.problem.exit_mask(x), 0.0, error)
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


def worst_value(solution: Solution, t: float = 0.0) -> float:
    """What doing nothing costs at worst from time ``t``, read at the nodes: (T − t) max q plus
    the largest cost a path can end with (g, and g_E with an exit set), an upper bound on the
    optimal value (u = 0 pays no control cost, and the box keeps the paths by its nodes); +inf
    without a horizon or for the average cost. The truncation term estimates v − v_h ≥ 0 to
    first order, and is held to this less v_h (:meth:`EmbeddedEstimate.error`): where v/λ
    changes by a hundred from node to node the expansion fails, its term holding e^100
    (stranger round 39's r39_3d_hzfe_13: docs page :doc:`accuracy`, "Where v/λ changes by a
    hundred"). A cost's peak between the nodes is not
    seen, which can only lower the bound on that one term; the others are not held.

    Parameters
    ----------
    solution : Solution
        A grid solution.
    t : float
        The time.

    Returns
    -------
    float
    """
    problem = solution.problem
    if problem.average_cost or problem.stationary:
        return np.inf
    ends = [nodal(solution, "terminal")]
    if problem.exit is not None:
        ends.append(nodal(solution, "exit_cost")[problem.exit_mask()])
    highest = max(float(np.max(e, initial=-np.inf)) for e in ends)
    q = nodal(solution, "state_cost") if problem.state_cost is not None else np.zeros(1)
    return highest + (problem.require_horizon("a worst value") - t) * float(q.max())


def own_interpolation_error(solution, x: np.ndarray, j: int, theta: float) -> np.ndarray:
    """What interpolating linearly in time between the solve's stored slices j and j + 1 changes
    at θ between them, from the solve's own slices: the interpolation's error across the two
    intervals around a middle slice b (t_j, or t_j+1 where j is the first),

        D = abs((1 − θ_b) v(t_a) + θ_b v(t_c) − v(t_b)),   θ_b = (t_b − t_a) / (t_c − t_a),

    carried to θ on [t_j, t_j+1] as an error that grows with the interval's length,
    D · θ(1 − θ) / (θ_b(1 − θ_b)) · (t_j+1 − t_j) / (t_c − t_a). Why linearly: near the horizon
    v changes fastest in the last moments (z between two goals, or at a kink of g), and the
    quadratic model of a smooth curvature under-reads the error there (stranger round 26,
    store_every=4 in the last interval: docs page :doc:`accuracy`, "Between stored slices");
    where v is smooth in time this reads high, by up to the ratio of the two intervals. 0 with
    fewer than three stored slices
    (:meth:`EmbeddedEstimate.between_slices <gridlbc.accuracy.EmbeddedEstimate.between_slices>`)."""
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
    those on :func:`~gridlbc.accuracy.phase_pair`.

    Over the :func:`~gridlbc.accuracy.calibration_states`: the observed order::

        p = log₂( Σ abs(v_4h − v_2h) / Σ abs(v_2h − v_h) )

    (NaN without the third solve) and the floor, the median of the local estimate relative to
    ``max(abs(v), λ)`` (the module docstring says why each).

    Parameters
    ----------
    solution, embedded, coarser : Solution
        The solves at h, 2h and 4h (steps Δt, 2Δt, 4Δt); ``coarser`` None: no third solve.
    pair : tuple of two Solution, or None
        The solves on :func:`~gridlbc.accuracy.phase_pair` (step 2Δt).
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
    ``relative`` size is at most :data:`~gridlbc.accuracy.estimate.ASYMPTOTIC`, the ``difference``
    itself elsewhere (the module docstring says why)."""
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

    and without the division where abs(c_2h − c_h)
    exceeds :data:`~gridlbc.accuracy.estimate.ASYMPTOTIC` · abs(c_h), as for the values
    (:func:`richardson`). The second term is the difference that the coarser pair predicts between
    the finer: it keeps ê from vanishing where c_h and c_2h agree by chance (two error terms of
    opposite sign crossing), as the floor does for the values. ê is also at least abs(c_c₁ − c_c₂),
    the difference on the pair of
    :func:`~gridlbc.accuracy.phase_pair`, undivided as for the values: it is how far a coarse
    solve moves with where its nodes fall, not a multiple of this grid's error. And it is at least
    abs(γ_c), for an average cost the cost per unit time that the grid leaves out of q under the
    solve's stationary law (:func:`gridlbc.accuracy.paths.stationary_gap`), and at least S_c =
    abs(c_2h[q + δq] − c_2h[q]), what the state cost's excess between the nodes changes in the
    embedded solve (:mod:`gridlbc.accuracy.subcell`): the levels miss a feature of q narrower than a
    cell alike, γ_c sees one the solve's law crosses and S_c one a path would seek. And it is at
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
    ``levels[1]`` (2h) and, if given, ``levels[2]`` (4h) and on
    :func:`~gridlbc.accuracy.phase_pair` (whose difference abs(c_c₁ − c_c₂) the estimate is at
    least), and at least abs(``gap``), ``response`` and abs(``truncation``).

    Parameters
    ----------
    levels : sequence of float
        c_h, c_2h and optionally c_4h.
    pair : tuple of two float, or None
        The number on the grids of :func:`~gridlbc.accuracy.phase_pair`.
    gap : float
        γ_c, what the grid leaves out of the number along the solve's own law
        (:func:`gridlbc.accuracy.paths.stationary_gap`).
    response : float
        S_c, what the costs' excess between the nodes changes in the number on the embedded grid.
    truncation : float
        E_π[λτ], what the generator's truncation error leaves out of the number
        (:func:`gridlbc.accuracy.average_truncation`).

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


def attach_estimates(solutions, levels: list, pairs=None, excess=None) -> None:
    """Give each of ``solutions`` its :class:`EmbeddedEstimate` from the solves ``levels[0][r]``
    (2h), if present ``levels[1][r]`` (4h), ``pairs[0][r]``, ``pairs[1][r]``
    (:func:`~gridlbc.accuracy.phase_pair`) and ``excess[r]`` (what the costs' sub-cell
    excess changes, :class:`~gridlbc.accuracy.subcell.Response`)."""
    for r, solution in enumerate(solutions):
        coarser = levels[1][r] if len(levels) > 1 else None
        pair = (pairs[0][r], pairs[1][r]) if pairs is not None else None
        response = excess[r] if excess is not None else None
        estimate = embedded_estimate(solution, levels[0][r], coarser, pair, response)
        object.__setattr__(solution, "embedded", estimate)


def relative_difference(solution, other, X: np.ndarray, t: float = 0.0, floor=None) -> np.ndarray:
    """abs(v_other − v) relative to the solution's value
    (:func:`~gridlbc.accuracy.estimate.relative_error`, with ``floor`` in place of λ where given:
    :func:`given_floor` at the user's own states) at states ``X`` at time ``t``: the embedded
    estimate when ``other`` is the embedded solve."""
    v = solution.value(X, t)
    floor = solution.temperature if floor is None else floor
    return relative_error(np.abs(other.value(X, t) - v), v, floor)


@contextmanager
def quiet_reads():
    """Silence the :class:`gridlbc.UnderflowWarning` of the estimate's own reads of a solution:
    where v underflowed they are +inf, and the estimate takes that for what it is, but those are
    not the user's queries (the solve warns once of its underflowed nodes): without it a solve
    warned of "query states" that no one had asked about, and a solve to a tolerance once per
    read of its states (stranger rounds 27–29, docs page :doc:`benchmarks`). Also a decorator
    (``@quiet_reads()``) of the functions that read a solution to judge it."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnderflowWarning)
        yield
