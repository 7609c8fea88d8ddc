"""How accurate is a solve: the embedded error estimate and solves to a tolerance (docs page :doc:`accuracy`).

The docs page :doc:`accuracy` explains what the estimate sees and what it cannot.

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
  and second order at best) where the two solves differ by at most :data:`ASYMPTOTIC` relative
  to the value, and q = 1 where they differ by more: a coarse solve that far from the fine one
  is outside the range where Richardson's model holds, and an order observed from it says more
  about the coarse grids than about this one (dividing by 3 there understated the error of a
  25⁴ acrobot threefold);
- the floor r, the median over the states that matter of the first term relative to the value:
  errors accumulate with the cost along the characteristics, so where the two solves happen to
  agree (their difference changes sign) the error is not smaller, relative to v, than the
  typical one (:func:`embedded_estimate`).

Where an axis's embedded axis is not nested in it (an odd periodic axis, an even closed one) the
coarse nodes can sit closer to a narrow feature than the fine ones; the same problem is then also
solved on :func:`twin_grid` (one node more on those axes, another 2^−(d+1) of the solve), and
abs(v_2h − v_h) is the larger of the two differences.

The estimate never changes the solution it checks. It sees what refining h and Δt would change:
time steps too long for a fast local flow, features narrower than a cell, a grid too coarse for
the value's curvature. It cannot see an error that all the solves share: a box too small for the
process (reflection at a closed axis acts the same on each), or a feature that every grid misses
entirely. Where the observed order is below 1 the coarser solves are not converging at first
order: they are too coarse to say how accurate this grid is, and the estimate is rough in either
direction (far above the error on 4-D grids of a few dozen nodes per axis, below it where the
solves converge slowly: half the error on a first-exit pendulum swing-up), and the warning says
so.

**Relative error.** ``ê / max(abs(v), λ)``: a value below the temperature λ is compared with λ,
the scale on which v = −λ log z is resolved (near a goal v can be arbitrarily small while its
error is a fraction of λ).

**Where it matters.** Without states from the user, a solve is judged at the states that matter:
the nodes whose value at t = 0 is finite and at most the median over the grid (the better half
of the box, where a controlled process spends its time; the far corners of a box, where every
solve is poor, do not count), and the relative estimate is read there at its 90th percentile.
With ``states=``, at its largest over them.

**Tolerance.** :func:`solve_to_tolerance` (``gridlbc.solve(problem, tol=...)``) repeats the solve
until the estimate meets ``tol`` or a limit (memory, ``max_nodes``, ``max_refinements``) stops it.
Between rounds it measures each part's share of the error, the step's by a solve at 2Δt and
each axis's by a solve with that axis alone coarsened, and models the estimate as their sum,
e ≈ Σ_i C_i h_i^q + C_t Δt: it chooses the factors by which to refine each axis and the step
so that the predicted estimate meets ``tol`` at the least work (:func:`refinement_factors`),
rounded to feasible grids and cut to what fits in memory (:func:`fitting_plan`). The model
extrapolates only as far as it has been checked: by at most 2 per round until a round's
estimate comes within 2× of what it predicted (each such round doubles the reach). Where it
does not describe the errors (:func:`unsteerable`: an estimate above 100 % of v, or shares
that do not add up to the embedded difference) every axis and the step are refined by 2;
where the levels do not converge at first order, the largest shares by 2. Where they do not
converge, the estimate cannot prove a tolerance it meets (it is far above the error on 4-D
grids of a few dozen nodes per axis): at a few states given by the user, certificates measure
the error itself (:func:`certified_error`) and end the solve when they prove ``tol``. The path
is in :attr:`gridlbc.Solution.refinement`. A default solve whose estimate exceeds
:data:`DEFAULT_TOLERANCE` warns (:class:`gridlbc.ResolutionWarning`) with the estimate and what to
change.
"""

from __future__ import annotations

import dataclasses
import time
import warnings
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from .errors import GridlbcWarning, ResolutionWarning, warn_user
from .grid import Axis, Grid

if TYPE_CHECKING:
    from .solution import Solution

DEFAULT_TOLERANCE = 0.05
"""The relative error above which a default solve warns (:func:`check_accuracy`)."""

QUANTILE = 0.9
"""The share of the states that matter whose relative estimate must meet the tolerance."""

ASYMPTOTIC = 0.15
"""Where the embedded solve differs from the solve by more than this (relative to
``max(abs(v), λ)``), the estimate does not divide by the observed order (the module docstring)."""

SAMPLE = 20_000
"""At most this many of the states that matter are read (evenly spaced in the nodes' order):
quantiles and medians of the estimate need no more, and a 4-D grid has millions."""


CERTIFIED_STATES = 16
""":func:`solve_to_tolerance` certifies the user's states (:func:`certified_error`) where the
embedded levels do not converge, if there are at most this many."""

CERTIFICATE_SAMPLES = 1000
"""Samples per state of the certificates that :func:`certified_error` draws first (four times as
many where the first ones cannot decide)."""

CERTIFICATE_LEVEL = 0.95
"""The confidence level of each state's certified interval (:func:`certified_error`)."""


def embedded_grid(grid: Grid, axes=None) -> Grid | None:
    """The grid with every other node of each axis (spacing 2h), or of the given ``axes`` only;
    None when an axis would keep fewer than three nodes (four on a periodic axis). A closed axis
    with an odd node count and a periodic one with an even count keep exactly their
    even-numbered nodes; otherwise the coarse spacing is slightly above 2h, the coarse nodes are
    not the fine ones, and the estimate also reads :func:`twin_grid`."""
    out = []
    for i, a in enumerate(grid.axes):
        if axes is not None and i not in axes:
            out.append(a)
            continue
        n = a.n // 2 if a.periodic else (a.n + 1) // 2
        if n < (4 if a.periodic else 3):
            return None
        out.append(Axis(a.lo, a.hi, n, periodic=a.periodic, name=a.name))
    return Grid(out)


def nested(axis: Axis) -> bool:
    """Whether every other node of ``axis`` is a node of its embedded axis: a periodic axis with
    an even node count, a closed one with an odd count (an even number of cells)."""
    return axis.n % 2 == (0 if axis.periodic else 1)


def twin_grid(grid: Grid, axes=None) -> Grid | None:
    """The embedded grid (:func:`embedded_grid`) with one node more on each axis whose embedded
    axis is not nested in it (:func:`nested`: an odd periodic axis, an even closed one), or on
    those of the given ``axes`` only; None when every such axis is nested or the grid is too
    coarse to embed.

    Why a second embedded grid: on an axis that is not nested, the coarse nodes can lie closer to
    a narrow feature of the problem (a pit in the state cost) than any node of the grid, and the
    coarse solve can then be *more* accurate than the fine one, hiding the fine grid's error.
    Measured in units of their own cells, the offset f of the fine nodes from any point is the
    sum of the offsets a and b of the two embedded axes (m and m + 1 nodes bracketing the fine
    count's half: a periodic axis of 2m + 1 nodes has f = x(2m + 1)/L = a + b, a closed one of
    2m nodes f = x(2m − 1)/L = a + b), so the fine grid's distance to the nearest node is at most
    twice the larger of the two coarse ones (distance to the nearest integer is subadditive),
    which is about what a coarse cell of 2h makes it: one of the two coarse grids misses every
    point at least as badly as the grid itself. The estimate reads the larger of the two
    differences (:meth:`EmbeddedEstimate.difference`)."""
    coarse = embedded_grid(grid, axes)
    if coarse is None:
        return None
    chosen = range(grid.ndim) if axes is None else axes
    misaligned = [i for i in chosen if not nested(grid.axes[i])]
    if not misaligned:
        return None
    return Grid(
        [
            Axis(c.lo, c.hi, c.n + 1, periodic=c.periodic, name=c.name) if i in misaligned else c
            for i, c in enumerate(coarse.axes)
        ]
    )


def refined_grid(grid: Grid, axes=None) -> Grid:
    """The grid with every cell halved (spacing h/2), or only along the given ``axes``: the grid
    whose embedded grid is ``grid``."""
    return Grid(
        [
            a
            if axes is not None and i not in axes
            else Axis(
                a.lo, a.hi, 2 * a.n if a.periodic else 2 * a.n - 1, periodic=a.periodic, name=a.name
            )
            for i, a in enumerate(grid.axes)
        ]
    )


def axis_shares(solution, solve_on, states=None) -> tuple[np.ndarray, float]:
    """Each axis's share of the error of ``solution`` and the difference from its embedded solve.

    The share of axis i is the relative difference (:func:`statistic` at the judged states) from
    a solve with only that axis coarsened (every other node, ``solve_on(grid)``, which may return
    None where the problem cannot be posed on that grid; NaN then, and for an axis too coarse to
    coarsen), the larger of two where the axis is not nested (:func:`twin_grid`). The difference
    D from the embedded solves, which coarsen every axis (and double the step), is read the same
    way (:meth:`EmbeddedEstimate.difference`).

    Returns
    -------
    shares : ndarray (d,)
    whole : float
        D.
    """
    X = judged_states(solution, states)
    grid, given = solution.grid, states is not None
    shares = np.full(grid.ndim, np.nan)
    for i in range(grid.ndim):
        for coarse in (embedded_grid(grid, axes=(i,)), twin_grid(grid, axes=(i,))):
            other = None if coarse is None else solve_on(coarse)
            if other is not None:
                share = statistic(relative_difference(solution, other, X), given)
                shares[i] = np.fmax(shares[i], share)
    v = solution.value(X, 0.0)
    difference = solution.embedded.difference(solution, X, 0.0)
    whole = statistic(relative_error(difference, v, solution.temperature), given)
    return shares, whole


def shares_add_up(shares: np.ndarray, whole: float, time_share: float = 0.0) -> bool:
    """Whether the per-axis shares (and the step's, ``time_share``) add up to at least half the
    embedded difference ``whole``: a first-order error splits into parts C_i h_i (and C_t Δt)
    whose sum the embedded solve, which coarsens everything, measures; where they do not add up
    the errors are not in that regime (the grids are too coarse for a per-component model)."""
    return bool(np.any(np.isfinite(shares)) and np.nansum(shares) + time_share >= 0.5 * whole)


def axes_to_refine(
    solution, solve_on, states=None, time_share: float = 0.0
) -> tuple[list[int], np.ndarray]:
    """Which axes limit the accuracy of ``solution``, from each axis's share of the error
    (:func:`axis_shares`).

    Where the shares add up (:func:`shares_add_up`), the axes whose share is at least half the
    largest are returned: refining the others alone would gain little. Where they do not, every
    axis is returned. Also returned: every share (NaN for an axis too coarse to coarsen).
    """
    shares, whole = axis_shares(solution, solve_on, states)
    if not shares_add_up(shares, whole, time_share):
        return list(range(solution.grid.ndim)), shares
    top = np.nanmax(shares)
    return [i for i in range(solution.grid.ndim) if not shares[i] < 0.5 * top], shares


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


def scaled_grid(grid: Grid, factors) -> Grid:
    """The grid with each axis's spacing divided by at least ``factors[i]`` (≥ 1; 1 leaves the
    axis as it is): the fewest cells that do so, an even number of them, so that the grid with
    every other node (:func:`embedded_grid`) keeps spacing exactly 2h. A factor of 2 gives
    :func:`refined_grid`."""
    out = []
    for a, r in zip(grid.axes, factors):
        cells = a.n if a.periodic else a.n - 1
        if r <= 1.0:
            out.append(a)
            continue
        cells = 2 * int(np.ceil(cells * r / 2.0 - 1e-9))
        n = cells if a.periodic else cells + 1
        out.append(Axis(a.lo, a.hi, n, periodic=a.periodic, name=a.name))
    return Grid(out)


def relative_error(estimate: np.ndarray, value: np.ndarray, temperature: float) -> np.ndarray:
    """``estimate / max(|value|, λ)`` (see the module docstring); +inf where the value is not
    finite (underflow)."""
    value = np.asarray(value, dtype=float)
    scale = np.maximum(np.abs(value), temperature)
    with np.errstate(invalid="ignore"):
        out = np.asarray(estimate, dtype=float) / scale
    return np.where(np.isfinite(value) & np.isfinite(out), out, np.inf)


def states_that_matter(solution) -> np.ndarray:
    """The nodes whose value at t = 0 is finite and at most the median over the grid, ``(M, d)``
    (at most :data:`SAMPLE` of them, evenly spaced).

    A task that ends (an exit set) counts every node outside the exit set instead: there the
    value is the cost of getting to E, largest where a task typically starts (far from E: a
    pendulum hanging at rest, when E is near the top), so the better half would judge only the
    states next to E; the nodes in E do not count, their value is the exit cost, given, not
    solved for.

    Parameters
    ----------
    solution : Solution
        A grid solution.

    Returns
    -------
    ndarray (M, d)
        The states at which a solve is judged when the user gives none.
    """
    v = solution.value_nodes(0)
    chosen = np.isfinite(v)
    if solution.problem.exit is not None:
        chosen &= ~solution.problem.exit_mask()
    elif chosen.any():
        chosen &= v <= np.median(v[chosen])
    keep = np.flatnonzero(chosen)
    if len(keep) == 0:
        return np.empty((0, solution.grid.ndim))
    if len(keep) > SAMPLE:
        keep = keep[np.linspace(0, len(keep) - 1, SAMPLE).astype(np.int64)]
    return solution.grid.node_coordinates(keep)


@dataclass(frozen=True)
class Assessment:
    """The embedded estimate of a solve, read at a set of states.

    Attributes
    ----------
    error : float
        The relative estimate that is compared with the tolerance: its :data:`QUANTILE` over the
        states that matter, or its maximum over the user's states.
    worst_state : ndarray (d,)
        Where the relative estimate is largest.
    worst_error : float
        The largest relative estimate.
    share_above : float
        The share of the states whose relative estimate exceeds the tolerance.
    n_states : int
        How many states were read.
    """

    error: float
    worst_state: np.ndarray
    worst_error: float
    share_above: float
    n_states: int


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
        The least relative error reported (the median over the states that matter).
    twin : Solution or None
        The same problem solved on :func:`twin_grid` (step 2Δt), where an axis's embedded grid
        is not nested in the grid; None where every axis is.
    """

    solution: Solution
    observed_order: float
    order: float
    floor: float
    twin: Solution | None = None

    @property
    def converging(self) -> bool:
        """Whether the levels converge at first order or better (or could not be compared)."""
        return not (self.observed_order < 1.0)

    def difference(self, solution: Solution, x, t=0.0) -> np.ndarray:
        """abs(v_2h − v_h) at states ``x`` (N, d), time ``t``: the larger of the two embedded
        solves' differences where there is a ``twin``."""
        return self._read(solution, x, t)[1]

    def local(self, solution: Solution, x, t=0.0) -> np.ndarray:
        """abs(v_2h − v_h) / (2^q − 1) at states ``x`` (N, d), time ``t`` (:meth:`difference`),
        with q = ``order`` where the relative difference is at most :data:`ASYMPTOTIC` and 1
        elsewhere."""
        return self._read(solution, x, t)[2]

    def error(self, solution: Solution, x, t=0.0) -> np.ndarray:
        """The estimate at states ``x`` (N, d), time ``t``: the local term, at least ``floor``
        relative to ``max(abs(v), λ)``."""
        v, _, local = self._read(solution, x, t)
        return np.maximum(local, self.floor * np.maximum(np.abs(v), solution.temperature))

    def _read(self, solution: Solution, x, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """v_h, :meth:`difference` and :meth:`local` at ``x``, each solve evaluated once."""
        v = solution.value(x, t)
        difference = np.abs(self.solution.value(x, t) - v)
        if self.twin is not None:
            difference = np.maximum(difference, np.abs(self.twin.value(x, t) - v))
        relative = relative_error(difference, v, solution.temperature)
        return v, difference, richardson(difference, relative, self.order)


def embedded_estimate(solution, embedded, coarser=None, twin=None) -> EmbeddedEstimate:
    """The estimate of ``solution`` from its embedded solve and, if given, the one below it and
    the one on :func:`twin_grid`.

    Over the states that matter: the observed order::

        p = log₂( Σ abs(v_4h − v_2h) / Σ abs(v_2h − v_h) )

    (NaN without the third solve) and the floor, the median of the local estimate relative to
    ``max(abs(v), λ)`` (the module docstring says why each).

    Parameters
    ----------
    solution, embedded, coarser : Solution
        The solves at h, 2h and 4h (steps Δt, 2Δt, 4Δt); ``coarser`` None: no third solve.
    twin : Solution or None
        The solve on :func:`twin_grid` (step 2Δt), None where every axis is nested.

    Returns
    -------
    EmbeddedEstimate
    """
    X = states_that_matter(solution)
    v, v2 = solution.value(X, 0.0), embedded.value(X, 0.0)
    observed = np.nan
    if coarser is not None:
        observed = observed_order(np.abs(v2 - v), np.abs(coarser.value(X, 0.0) - v2))
    order = clipped_order(observed)
    estimate = EmbeddedEstimate(embedded, observed, order, 0.0, twin)
    relative = relative_error(estimate.local(solution, X), v, solution.temperature)
    relative = relative[np.isfinite(relative)]
    floor = float(np.median(relative)) if len(relative) else 0.0
    return dataclasses.replace(estimate, floor=floor)


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
    (two error terms of opposite sign crossing), as the floor does for the values.

    Attributes
    ----------
    error : float
        ê, in the units of the number.
    observed_order : float
        p before clipping (NaN without a third level).
    levels : tuple of float
        The number on the grids h, 2h (and 4h).
    """

    error: float
    observed_order: float
    levels: tuple[float, ...]

    @property
    def relative(self) -> float:
        """ê / abs(c_h) (+inf where c_h is zero and ê is not)."""
        fine = abs(self.levels[0])
        if fine > 0:
            return self.error / fine
        return 0.0 if self.error == 0 else np.inf


def scalar_estimate(levels, twin: float | None = None) -> ScalarEstimate:
    """The :class:`ScalarEstimate` of ``levels[0]`` from the same number on the embedded grids
    ``levels[1]`` (2h) and, if given, ``levels[2]`` (4h) and ``twin`` (:func:`twin_grid`: the
    larger of abs(c_2h − c_h) and abs(c_twin − c_h) is read).

    Parameters
    ----------
    levels : sequence of float
        c_h, c_2h and optionally c_4h.
    twin : float or None
        The number on :func:`twin_grid`, None where every axis is nested.

    Returns
    -------
    ScalarEstimate
    """
    c = [float(level) for level in levels]
    fine = abs(c[1] - c[0])
    difference = fine if twin is None else max(fine, abs(twin - c[0]))
    observed, order = np.nan, 1.0
    if len(c) > 2:
        observed = observed_order(fine, abs(c[2] - c[1]))
        order = clipped_order(observed)
        difference = max(difference, abs(c[2] - c[1]) / 2.0**order)
    relative = difference / abs(c[0]) if c[0] != 0 else np.inf
    error = float(richardson(difference, relative, order))
    return ScalarEstimate(error, observed, tuple(c))


def attach_estimates(solutions, levels: list, twins=None) -> None:
    """Give each of ``solutions`` its :class:`EmbeddedEstimate` from the solves ``levels[0][r]``
    (2h), if present ``levels[1][r]`` (4h) and ``twins[r]`` (:func:`twin_grid`), and warn
    (:func:`check_accuracy`) where one exceeds the default tolerance; nothing without levels (a
    grid too coarse to embed)."""
    if not levels:
        return
    for r, solution in enumerate(solutions):
        coarser = levels[1][r] if len(levels) > 1 else None
        twin = twins[r] if twins is not None else None
        estimate = embedded_estimate(solution, levels[0][r], coarser, twin)
        object.__setattr__(solution, "embedded", estimate)
        check_accuracy(solution)


def judged_states(solution, states=None) -> np.ndarray:
    """``states`` as ``(N, d)``, or :func:`states_that_matter` when None."""
    if states is None:
        return states_that_matter(solution)
    return np.atleast_2d(np.asarray(states, dtype=float))


def relative_difference(solution, other, X: np.ndarray) -> np.ndarray:
    """abs(v_other − v) relative to the solution's value (:func:`relative_error`) at states ``X``
    at t = 0: the embedded estimate when ``other`` is the embedded solve."""
    v = solution.value(X, 0.0)
    return relative_error(np.abs(other.value(X, 0.0) - v), v, solution.temperature)


def statistic(rel: np.ndarray, given: bool) -> float:
    """The number compared with a tolerance: the maximum over the user's states, the
    :data:`QUANTILE` over the states that matter."""
    if len(rel) == 0:
        return np.inf
    return float(rel.max()) if given else float(np.quantile(rel, QUANTILE))


def assess(solution, tol: float, states=None) -> Assessment | None:
    """Read the embedded estimate of ``solution`` at ``states`` (default: :func:`states_that_matter`).

    Parameters
    ----------
    solution : Solution
        A solution that carries its embedded solve.
    tol : float
        The relative tolerance that ``share_above`` counts against.
    states : array_like (N, d) or (d,), optional
        The states to judge; the statistic is then the maximum rather than the quantile.

    Returns
    -------
    Assessment or None
        None when the solution carries no embedded solve (a grid too coarse to embed).
    """
    if solution.embedded is None:
        return None
    X = judged_states(solution, states)
    rel = relative_error(solution.error_estimate(X), solution.value(X, 0.0), solution.temperature)
    if len(rel) == 0:
        return Assessment(np.inf, np.full(solution.grid.ndim, np.nan), np.inf, 1.0, 0)
    worst = int(np.argmax(rel))
    error = statistic(rel, states is not None)
    return Assessment(error, X[worst], float(rel[worst]), float(np.mean(rel > tol)), len(X))


def certifiable(solution, states) -> bool:
    """Whether :func:`solve_to_tolerance` certifies the user's ``states`` (:func:`certified_error`)
    after a round whose estimate missed: where the embedded levels do not converge at first order
    (the estimate is then rough in either direction: far above the error on 4-D grids of a few
    dozen nodes per axis) and the user gave at most :data:`CERTIFIED_STATES` states."""
    embedded = solution.embedded
    if states is None or embedded is None or embedded.converging:
        return False
    return len(judged_states(solution, states)) <= CERTIFIED_STATES


def certified_error(solution, X: np.ndarray, tol: float) -> float:
    """The relative error of v at the states ``X`` measured against certified optima::

        ê_c = max over x of  max(v(x) − lo(x), hi(x) − v(x)) / max(|v(x)|, λ),

    with [lo, hi] the :data:`CERTIFICATE_LEVEL` interval of :func:`gridlbc.certify` at x for the
    SDE's optimum: importance sampling with the solution's own policy as proposal (exact for any
    proposal, docs page :doc:`validating`), extrapolated to a vanishing Euler–Maruyama step from
    Δt_c and 2Δt_c (``richardson=True``), Δt_c = T/300 at first. It measures the error itself,
    so it holds where the embedded estimate cannot say (levels that do not converge: grids too
    coarse to judge this one). The certificates are drawn again, at most twice each, with half
    the step where the step's contribution exceeds ``tol``/4 (the extrapolation leaves
    O(Δt_c²), small beside it), and with four times the samples where the interval is too wide
    to decide ``tol`` (v lies within ``tol`` of its centre, not of both ends).

    Parameters
    ----------
    solution : Solution
        A grid solution of a problem with a horizon.
    X : ndarray (N, d)
        The states.
    tol : float
        The relative tolerance the certificates must decide.

    Returns
    -------
    float
        ê_c; NaN where a certificate is not :attr:`~gridlbc.Certificate.trusted` at every
        state (too few effective samples or a heavy weight tail: the solve's policy is too poor a
        proposal to certify with).
    """
    from .certify import certify

    v = np.asarray(solution.value(X, 0.0), dtype=float).reshape(-1)
    scale = np.maximum(np.abs(v), solution.temperature)
    n, dt = CERTIFICATE_SAMPLES, solution.problem.horizon / 300
    halvings = more = 0
    while True:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GridlbcWarning)
            c = certify(
                solution.problem,
                solution.policy,
                X,
                n,
                dt=dt,
                seed=0,
                progress=False,
                proposal=None,
                richardson=True,
            )
        if not np.all(c.trusted):
            return np.nan
        lo, hi = (np.asarray(end, dtype=float).reshape(-1) for end in c.interval(CERTIFICATE_LEVEL))
        error = float(np.max(np.maximum(v - lo, hi - v) / scale))
        step = np.abs(np.asarray(c.step_contribution, dtype=float).reshape(-1)) / scale
        centre = np.abs(v - 0.5 * (lo + hi)) / scale
        if step.max() > tol / 4 and halvings < 2:
            dt, halvings = dt / 2, halvings + 1
        elif error > tol and centre.max() <= tol and more < 2:
            n, more = 4 * n, more + 1
        else:
            return error


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
    warn_user(
        f"the estimated error of v exceeds {tol:.0%} of |v| at {a.share_above:.0%} of the states "
        f"that matter ({QUANTILE:.0%} of them are within {a.error:.1%}; the largest, "
        f"{a.worst_error:.0%}, is at {state}): measured against solves on the grids with every "
        f"other node, see solution.error_estimate(x) at your own states.{loose} {change} "
        "(docs page 'accuracy')",
        ResolutionWarning,
    )


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
    warn_user(
        f"the estimated error of {name} = {estimate.levels[0]:.6g} is {estimate.error:.3g}, "
        f"{estimate.relative:.1%} of it (above {tol:.0%}): measured against the same solve on the "
        f"grids with every other node ({levels} on h, 2h, 4h).{loose} Give a finer grid (docs "
        "page 'accuracy')",
        ResolutionWarning,
    )


@dataclass(frozen=True)
class Refinement:
    """One solve of :func:`solve_to_tolerance`.

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
        Seconds for this solve and its estimates.
    dtype : str
        How its slices were stored: ``"float64"`` or ``"float32"``.
    store_every : int
        It stored every ``store_every``-th step's slice (and the last).
    axis_errors : tuple of float
        Where it was followed by another round: each axis's share of the error, the relative
        difference from a solve with only that axis coarsened (:func:`axis_shares`). Empty
        otherwise.
    factors : tuple of float
        The refinement asked for after it, per axis and then for the step (h_i → h_i / r_i,
        Δt → Δt / r_t; 1: unchanged); the grid reached may be coarser where memory or
        ``max_nodes`` held it. Empty where it was the last round.
    reason : str
        Why the factors were not the model's own choice (:func:`unsteerable`, or levels that do
        not converge at first order); "" where they were.
    certified_error : float
        Where the embedded levels did not converge and the user gave few states: the relative
        error at those states measured against certified optima (:func:`certified_error`); NaN
        where it was not measured or the certificates could not say.
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

    def met(self, tol: float) -> bool:
        """Whether this round proved ``tol``: by its estimate or at certified states."""
        return bool(self.error <= tol or self.certified_error <= tol)


def unsteerable(embedded, error: float, shares, whole: float, time_share: float) -> str:
    """Why the measured shares cannot choose the next grid, or "" where they can.

    The per-component model e ≈ Σ_i C_i h_i^p + C_t Δt (:func:`refinement_factors`) steers
    where it describes the errors. Where it does not, the estimate says that the solve is poor,
    not which part to refine, and every axis and the step are refined: an estimate above 100 %
    of v (the coarser solves are not near v at all), or shares that do not add up to the
    embedded difference (:func:`shares_add_up`)."""
    if not error <= 1.0:
        return f"estimate {error:.0%} above 100 % of v"
    total = np.nansum(shares) + time_share
    if not (total > 0 and shares_add_up(np.asarray(shares), whole, time_share)):
        return f"shares add up to {total:.3g} of the embedded difference {whole:.3g}"
    return ""


def fitting_plan(problem, settings, factors, max_nodes: int | None = None):
    """The grid refined by ``factors`` (:func:`scaled_grid`), or by less where that would exceed
    ``max_nodes`` or the memory: the largest ``factors**α`` (α in [0, 1], bisected) whose grid
    fits, with its storage (:func:`fitting_storage`).

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
        return grid, fitting_storage(problem.replace(grid=grid), settings)

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


def solve_to_tolerance(
    problem,
    tol: float,
    states=None,
    settings=None,
    max_nodes: int | None = None,
    max_refinements: int = 8,
    **options,
):
    """Solve ``problem`` again and again until the embedded estimate meets ``tol``.

    Each round solves on the current grid with the current step and reads the relative estimate
    ê (:func:`assess`). If it exceeds ``tol``, it measures the step's share ê_t = abs(v_{h,2Δt} −
    v_{h,Δt}) and each axis's share (:func:`axis_shares`: solves at the same step with one axis
    coarsened at a time), and chooses the next grid and step:

    - in the model's range (:func:`unsteerable` says nothing), the factors that bring the sum of
      the shares, scaled to add up to ê and extrapolated with the observed order q for the axes
      and 1 for the step, to ``tol`` at the least work (:func:`refinement_factors`), each at
      most the *reach*: 2 until a round's estimate comes within 2× of the model's prediction
      for it, doubled by each round that does, back to 2 by one that does not; where the levels
      do not converge at first order (observed order below 1), only the shares at least half
      the largest are refined, by at most 2;
    - outside it, every axis by 2 with the scheme's default step for the finer grid (or half
      the current step once one has been set).

    Where the levels do not converge (the estimate is then rough in either direction) and the
    user gave at most :data:`CERTIFIED_STATES` states, a round whose estimate misses ``tol`` is
    also judged by certificates at those states (:func:`certified_error`), and ends the solve if
    they prove it (:attr:`Refinement.certified_error`).

    The grid is the one with each axis's spacing divided by its factor (:func:`scaled_grid`);
    where it would exceed ``max_nodes`` or the memory, the factors are reduced together to the
    largest grid that fits (:func:`fitting_plan`: its slices stored as float32, then only every
    k-th, :func:`fitting_storage`); if not even a slightly finer grid fits, Δt is halved
    instead and the limit is reported.

    Parameters
    ----------
    problem : Problem
        The problem; its grid is the first one tried.
    tol : float
        The relative tolerance on v (see :func:`relative_error`), in (0, 1).
    states : array_like (N, d), optional
        Where the tolerance must hold; default :func:`states_that_matter` (at :data:`QUANTILE`).
    settings : SolverSettings or str, optional
        As for :func:`gridlbc.solve`.
    max_nodes : int, optional
        Refine the grid no further than this many nodes (default: what the memory allows).
    max_refinements : int
        At most this many rounds after the first.
    **options
        Settings fields, as for :func:`gridlbc.solve`.

    Returns
    -------
    Solution
        The last solution, with :attr:`~gridlbc.Solution.refinement` (one :class:`Refinement` per
        round). A :class:`gridlbc.ResolutionWarning` says what stopped it if ``tol`` was not met.
    """
    from .settings import resolve_settings
    from .solver import solve_many

    check_tolerance(tol, options)
    base = resolve_settings(settings, options)
    dt = base.dt
    history: list[Refinement] = []
    limit = ""
    coarser = None  # (problem, step) of the last round, to return to if a finer grid won't fit
    # The model is trusted to extrapolate as far as it has been checked: a factor of 2 (the span
    # its shares were measured over) until a round's estimate comes within 2× of what the model
    # predicted for it; each such round doubles the reach, a miss resets it.
    reach, predicted = 2.0, np.nan
    while True:
        started = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ResolutionWarning)
                solution = solve_many(
                    problem, [problem.terminal_cost], base, dt=dt, error_estimate=True
                )[0]
        except MemoryError:
            if coarser is None:
                raise
            # the finer grid does not fit after all: stay on the last one, halve its step
            limit = f"memory: the grid {problem.grid.shape} does not fit in the memory available"
            problem, dt = coarser[0], coarser[1] / 2
            coarser = None
            continue
        a = assess(solution, tol, states)
        if a is None:
            raise ValueError(
                f"the grid {problem.grid.shape} is too coarse to embed a grid with every other "
                "node (each axis needs at least 5 nodes): give a finer grid"
            )
        held = predicted / 2 <= a.error <= 2 * predicted
        reach, predicted = (2 * reach if held else 2.0), np.nan
        time_error = certified = np.nan
        if a.error > tol and certifiable(solution, states):
            certified = certified_error(solution, judged_states(solution, states), tol)
        done = a.error <= tol or certified <= tol or len(history) >= max_refinements
        if not done:
            steps = solution.diagnostics.steps
            half = _march_quietly(problem, base, 2 * solution.diagnostics.dt, steps, problem.grid)
            rel = relative_difference(solution, half, judged_states(solution, states))
            time_error = statistic(rel, states is not None)
        history.append(
            Refinement(
                problem.grid.shape,
                solution.diagnostics.dt,
                a.error,
                time_error,
                time.perf_counter() - started,
                base.dtype,
                base.store_every,
                certified_error=certified,
            )
        )
        if base.progress:
            stored = "" if base.store_every == 1 else f", every {base.store_every}th slice stored"
            proved = "" if np.isnan(certified) else f", certified at the states {certified:.2%}"
            print(
                f"tol: grid {'×'.join(map(str, problem.grid.shape))}, dt {solution.diagnostics.dt:.4g}"
                f" ({base.dtype}{stored}): estimated error {a.error:.2%}{proved}",
                flush=True,
            )
        if done:
            break
        step, steps = solution.diagnostics.dt, solution.diagnostics.steps
        solve_on = partial(_march_quietly, problem, base, step, steps)
        shares, whole = axis_shares(solution, solve_on, states)
        embedded = solution.embedded
        assert embedded is not None  # assess read it
        reason = unsteerable(embedded, a.error, shares, whole, time_error)
        if reason:  # every axis and the step, by 2 (the scheme's step for the finer grid)
            factors = np.full(problem.grid.ndim + 1, 2.0)
        else:
            components = np.append(shares, time_error)
            orders = np.append(np.full(problem.grid.ndim, embedded.order), 1.0)
            scale = a.error / np.nansum(components)  # the components add up to the estimate
            factors = np.minimum(refinement_factors(scale * components, orders, tol), reach)
            if not embedded.converging:
                # levels not converging at first order: the shares, measured between h and 2h,
                # say which parts limit the error but not how far beyond h/2 the model holds:
                # refine by 2 those at least half the largest (the others alone gain little)
                top = np.nanmax(components)
                factors = np.where(components >= 0.5 * top, np.minimum(factors, 2.0), 1.0)
                reason = (
                    f"observed order {embedded.observed_order:.2f} < 1: the largest shares by 2"
                )
            else:
                predicted = float(np.nansum(scale * components * factors**-orders))
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
        if np.all(factors == 2.0):
            next_dt = None if dt is None else step / 2
        else:
            next_dt = step / factors[-1]
        finer, storage, capped = fitting_plan(
            problem, dataclasses.replace(base, dt=next_dt), factors[:-1], max_nodes
        )
        if finer is not None and next_dt is not None:
            next_dt = min(next_dt, base.scheme.step_bound(finer).limit)
        if finer is None:  # not even a slightly finer grid fits: the step is all that is left
            limit = capped
            dt = step / 2 if next_dt is None or next_dt >= step else next_dt
            continue
        limit = capped
        base = dataclasses.replace(storage, dt=base.dt)
        coarser = (problem, step)
        problem, dt = finer, next_dt
    where = f"{'×'.join(map(str, problem.grid.shape))} with dt {solution.diagnostics.dt:.4g}"
    advice = "raise max_refinements or max_nodes, store float32 or use mmap_dir"
    finish(solution, tol, history, where, limit, max_refinements, advice)
    return solution


def _march_quietly(problem, settings, dt: float, steps: int, grid: Grid):
    """``problem`` solved on ``grid`` with step ``dt``, its warnings silenced and no estimate,
    storing only the first and last slices (at most ``steps`` steps): a comparison solve of
    :func:`solve_to_tolerance`, read at t = 0."""
    from .solver import solve_many

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridlbcWarning)
        return solve_many(
            problem.replace(grid=grid),
            [problem.terminal_cost],
            settings,
            dt=dt,
            error_estimate=False,
            store_every=steps,
        )[0]


def fitting_storage(problem, settings):
    """``settings`` for a solve of ``problem`` whose slices fit in the memory available, or a
    message saying why none do.

    The slices of every stored step dominate a time-marched solve's memory. If they do not fit,
    they are stored as float32 (the march itself stays in double precision), then only every
    k-th step's slice is stored (k = 2, 4, …: the value at t = 0, which the tolerance judges, is
    unchanged; the value and the policy between stored slices are interpolated in time). The
    embedded solve (2^−(d+1) of the slices' bytes: 2^−d of the nodes, half the steps) is held
    with the solution, and so is the second one where the grid has one (:func:`twin_grid`), hence
    the margin.
    """
    from .solver import planned_memory
    from .storage import available_memory

    available = available_memory()
    if available is None:
        return settings
    embedded = 1 if twin_grid(problem.grid) is None else 2
    margin = 1.0 + embedded * 2.0 ** -(problem.grid.ndim + 1)
    candidate, stored = settings, None
    while True:
        need = planned_memory(problem, candidate)
        if need["ram"] * margin <= 0.9 * available:
            return candidate
        if candidate.dtype == "float64":
            candidate = dataclasses.replace(candidate, dtype="float32")
        elif need["stored"] != stored:  # fewer slices still help
            stored = need["stored"]
            candidate = dataclasses.replace(candidate, store_every=2 * candidate.store_every)
        else:
            need = need["ram"] * margin
            return (
                f"memory: the grid {problem.grid.shape} would need about {need / 2**30:.1f} GiB "
                f"of {available / 2**30:.1f} GiB available even storing few slices"
            )


def check_tolerance(tol, options: dict) -> None:
    """A clear error unless ``tol`` is a relative error in (0, 1) and the ``options`` keep the
    embedded estimate that a solve to a tolerance reads."""
    if not (isinstance(tol, (int, float)) and 0 < tol < 1):
        raise ValueError(f"tol must be a relative error in (0, 1), e.g. 0.02; got {tol!r}")
    if options.get("error_estimate") is False:
        raise ValueError("tol needs the embedded estimate: drop error_estimate=False")


def finish(
    solution, tol: float, history: list, where: str, limit: str, rounds: int, advice: str
) -> None:
    """Record the ``history`` of a solve to a tolerance on ``solution`` and warn
    (:class:`gridlbc.ResolutionWarning`) if its last estimate still exceeds ``tol``, saying
    ``where`` it stopped, why (``limit``, or the ``rounds`` spent) and what to change
    (``advice``)."""
    object.__setattr__(solution, "refinement", tuple(history))
    last = history[-1]
    if not last.met(tol):
        why = limit or f"max_refinements = {rounds} rounds were spent"
        certified = (
            ""
            if np.isnan(last.certified_error)
            else f" (certified at your states: {last.certified_error:.1%})"
        )
        warn_user(
            f"solve(tol={tol:g}) reached an estimated error of {last.error:.1%}{certified} on "
            f"{where}, not {tol:.1%}: {why}; {advice}",
            ResolutionWarning,
        )
