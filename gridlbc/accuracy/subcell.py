"""Costs narrower than a cell, wherever they lie: their excess between the nodes and what it
changes (docs page :doc:`accuracy`, "Costs between the nodes").

A grid solve knows its costs only at its nodes. A goal or a well narrower than a cell can sit
between them, and the solve then answers a different problem, whose costs are shallow where the
true ones are deep. The embedded solves (:mod:`gridlbc.accuracy.estimate`) miss such a feature
as much as the grid does when their nodes miss it too, and the sampled cost gap γ
(:mod:`gridlbc.accuracy.paths`) misses it when the solve's own paths never go there: a goal the
grid cannot see is not sought. This module looks for such features in the costs themselves and
measures what they change.

**The excess.** On the sampling *lattice*, m points per cell along every axis (spacing h/m;
the most of 8, 4 and 2 for which the lattice holds at most 2²⁴ points: m = 8 on a 2-D grid up to
512² and a 3-D one up to 32³, 4 up to about 1000² and 64³, 2 beyond,
:func:`~gridlbc.accuracy.grids.samples_per_cell`), each cost f is compared
with its reconstruction R f from the nodes (:func:`refine`, along each axis in turn): nodes keep
their values, and a point at offset t within a cell takes the cubic through the four nodes
around it (at t = ½ the rule (−f_{i−1} + 9 f_i + 9 f_{i+1} − f_{i+2})/16), or, where one side's
second difference exceeds the other's :data:`KINK` times (a kink on a node: a wrapped
quadratic's seam, ``abs(x)``), the quadratic through the three nodes of the smoother side. R is
exact for every quadratic, so the excess f − R f is zero at every lattice point for a quadratic
cost and O(h⁴) for a smooth one; where a feature narrower than a cell lies between the nodes it
is the feature's depth at the lattice points near it. The library's own quadratic costs are not
sampled (:func:`reproduced`).

**Carried to the embedded grid.** On each node j of the embedded grid (spacing 2h, hat functions
φ_j) the excess is summed up as a soft minimum at the temperature λ/τ,

    δ_j = −(λ/τ) log( Σ_s φ_j(s) exp(−τ (f − I f_c)(s)/λ) / Σ_s φ_j(s) exp(−τ (R f − I f_c)(s)/λ) ),

over the lattice points s, with τ = 1 for the terminal cost g (and an exit cost g_E) and, for
the state cost q, τ = T, the horizon, or without one (first exit, average cost) the time in
which the noise moves a path across a cell of the embedded grid
(:func:`~gridlbc.accuracy.subcell.hold_time`). For g this is the ratio of the desirability exp(−g/λ)
that the hat holds to the one its reconstruction holds: a narrow goal counts with its weight, as the
value does. For q it is what a path that stays by the node for the time τ could gain: a narrow well
is worth its depth to a path that holds still in it, a narrow pit (which a path can step around)
little. Held longer than the noise's time across a cell, a path pays to stay in the well, and the
soft minimum at that τ charges at most what staying costs
(:func:`~gridlbc.accuracy.subcell.hold_time`): a task that never ends is priced by it, not by a hold
of infinite length, which would make any well worth its whole depth. I f_c, the embedded grid's
multilinear interpolant of the cost at its own nodes, keeps the exponentials in range. No hat holds
a cost below its lowest sample: δ_j is at least min f(s) − f(x_j) over the lattice points s in
the support of φ_j and the bottoms :func:`descend` reaches there (a cost that jumps inside a cell
stays at its lower level up to the jump while R f ramps across it, and against I f_c the ratio
above reads that stretch as a goal as deep as the jump, below every cost the problem has:
stranger round 39). An exit cost
is paid on the exit set E only: the sums run over the lattice points in E (a hat with none has no
excess), so a user's g_E off E (``np.where`` of a door's cost, 0 elsewhere, which no path pays) is
no feature.

**Between the lattice points.** A goal much narrower than the lattice's spacing whose centre is
as far from a node as from the lattice points around it is seen by all of them alike, by its
tail. Where the excess has a local minimum below zero on the lattice (the lattice sees more than
the reconstruction, by more than rounding), :func:`descend` looks between the points: it cuts
the box of the lattice's spacing around the point into 3^d boxes, and the one where f − I f_c is
lowest again, up to :data:`DESCENT_LEVELS` times, down to the feature's bottom (while the boxes'
means and centres disagree more for the cost than for its reconstruction); where it found one, it
sums both exponentials again over a box of that width around the bottom by the same adaptive
midpoint rule, and the two sums take the point's place. Where the cost is smooth the two sums
move alike and δ does not. The descent costs at most as many evaluations of the cost as the
lattice (:func:`_deeper`).

**The response.** The embedded problem is solved once more with its costs raised by the excess,
g + δg and q + δq (:class:`WithExcess`; q + δq at least 0), and

    S(x, t) = abs( v_2h[g + δg, q + δq](x, t) − v_2h[g, q](x, t) )

is what the costs between the nodes change, seen at the embedded grid's resolution whether or
not the solve's paths go near them (:class:`Response`;
:meth:`gridlbc.accuracy.EmbeddedEstimate.error` reads it beside its other terms). Both solves
are made without exponential fitting: a fitted scheme interpolates z relative to its reference
in every step, which spreads a dip that the reference does not have by about a cell per step,
so its response to one is a fraction of the true one (:func:`~gridlbc.accuracy.responses`). Where
sup|δg| + τ sup|δq| is at most :data:`~gridlbc.accuracy.subcell.NEGLIGIBLE` λ the raised solve is
not run and S is that bound, which with a horizon it never exceeds (v is 1-Lipschitz in the costs in
the supremum norm). For the average cost the response is read for the relative value h and for c
(:func:`gridlbc.accuracy.estimate.scalar_estimate`).

What S cannot see: a feature that no lattice point sees at all (narrower than the lattice's
spacing and too shallow in its tails to leave an excess below zero at a point near it). It errs
high where holding still in a narrow well costs more, in noise fought, than the well saves (the
embedded grid holds a path at a node for free), and where a cost steps inside a cell (the cubic
overshoots the step by a quarter of the jump, which reads as a goal). For a first-exit task
without a horizon a path gains nothing by holding (q ≥ 0: the task must still end), and τ is
about the time it spends in a hat it passes through (less where the drift carries it). Its cost: the costs
evaluated at m^d lattice points per node and at most 2 · 3^d · :data:`DESCENT_LEVELS` points
around each seed, and where they have an excess, two more solves on the embedded grid.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.special import logsumexp

from ..backends.numba.lattice import (
    lattice_points,
    least_in_supports,
    local_minima,
    multilinear_points,
    rebuild_points,
    refine_rows,
)
from ..costs import Constant, Quadratic
from ..grid import NODE_CHUNK, Axis, Grid
from ..interpolate import interpolate
from .exits import MovedExit, missed_points
from .grids import refined_grid, samples_per_cell

if TYPE_CHECKING:
    from ..solution import Solution

LATTICE_BLOCK = 1 << 21
"""At most about this many points of the sampling lattice are held at once
(:func:`~gridlbc.accuracy.excess` works through it in blocks of whole rows along the first axis)."""


EXPONENT_CAP = 700.0
"""The soft minimum's exponentials are evaluated with their exponents capped here: an excess
deeper than this many λ/τ is counted as this deep (still a huge one)."""


KINK = 2.0
"""A point between two nodes takes the quadratic of the smoother side where one side's second
difference exceeds the other's this many times (a kink on a node, :func:`refine`)."""


def refine(values: np.ndarray, axis: int, along_axis: Axis, m: int, rows=None) -> np.ndarray:
    """Nodal ``values`` carried to the lattice of m points per cell along ``axis`` (of the grid
    axis ``along_axis``). Every m-th point is a node; a point at offset t (0 < t < 1, in cells)
    from node i towards i + 1 takes the cubic through nodes i − 1 … i + 2, except where one
    side's second difference exceeds the other's :data:`KINK` times (a kink on the node between
    them: a wrapped quadratic's seam, ``abs(x)``), where it takes the quadratic through the three
    nodes of the smoother side, which is exact there as well; in the end cells of a closed axis
    the only quadratic there is. Exact for every quadratic; at t = ½ the cubic is the rule
    (−1, 9, 9, −1)/16. ``rows``: only these points of the lattice's axis (default all)."""
    n = along_axis.n
    size = m * n if along_axis.periodic else m * (n - 1) + 1
    rows = np.arange(size) if rows is None else np.asarray(rows, dtype=np.int64)
    moved = np.moveaxis(values, axis, -1)
    flat = np.ascontiguousarray(moved.reshape(-1, n), dtype=float)
    out = np.empty((flat.shape[0], len(rows)))
    refine_rows(flat, rows, m, along_axis.periodic, KINK, out)
    return np.moveaxis(out.reshape(moved.shape[:-1] + (len(rows),)), -1, axis)


def hat_weights(coarse: Axis, points: np.ndarray) -> sp.csr_matrix:
    """The sparse matrix ``(coarse nodes, points)`` of the coarse axis's hat functions
    φ_j(s) = max(0, 1 − abs(s − x_j)/H) at ``points`` in its box (two per point: the nodes of
    the cell it lies in; nearest image on a periodic axis)."""
    n = coarse.n
    cell, t = _cells(coarse, points)
    columns = np.arange(len(cell))
    rows = np.concatenate([cell % n, (cell + 1) % n])
    weights = np.concatenate([1.0 - t, t])
    shape = (n, len(cell))
    return sp.csr_matrix((weights, (rows, np.concatenate([columns, columns]))), shape=shape)


def _cells(coarse: Axis, points) -> tuple[np.ndarray, np.ndarray]:
    """The cell of the coarse axis each of ``points`` lies in (its first node's index; the last
    cell of a closed axis for its last node) and the offset t in it, in cells."""
    position = (np.asarray(points, dtype=float) - coarse.lo) / coarse.spacing
    cell = np.floor(position).astype(np.int64)
    if not coarse.periodic:
        cell = np.clip(cell, 0, coarse.n - 2)
    return cell, position - cell


def multilinear(coarse: Grid, values: np.ndarray, x) -> np.ndarray:
    """Σ_j φ_j(x) c_j, the multilinear interpolant of the nodal ``values`` c of ``coarse`` at
    states ``x`` (N, d): the hat functions of :func:`hat_weights`, at scattered states (the
    library's :func:`~gridlbc.interpolate.interpolate` is barycentric on simplices)."""
    positions = (np.atleast_2d(np.asarray(x, dtype=float)) - coarse.lo) / coarse.spacing
    out = np.empty(len(positions))
    shape = np.array(coarse.shape, dtype=np.int64)
    flat = np.ascontiguousarray(values, dtype=float).reshape(-1)
    multilinear_points(flat, shape, np.asarray(coarse.periodic), positions, out)
    return out


def along(matrix: sp.csr_matrix, values: np.ndarray, axis: int) -> np.ndarray:
    """``matrix`` applied to ``values`` along ``axis``."""
    moved = np.moveaxis(values, axis, 0)
    out = matrix @ moved.reshape(moved.shape[0], -1)
    return np.moveaxis(np.asarray(out).reshape((matrix.shape[0],) + moved.shape[1:]), 0, axis)


@dataclass(frozen=True)
class Excess:
    """The costs' sub-cell excess carried to the nodes of a coarse grid (module docstring).

    Attributes
    ----------
    terminal : ndarray (K, Nc)
        δg_j for each terminal cost (each exit cost of a task without a horizon).
    state : ndarray (Nc,) or None
        δq_j (None without a state cost, or for one the reconstruction reproduces:
        :func:`reproduced`).
    exit : ndarray (Nc,) or None
        δg_E,j for the exit cost of a task with a horizon and an exit set (None otherwise, or
        where it is reproduced).
    hold : float
        τ of the state cost (:func:`~gridlbc.accuracy.subcell.hold_time`; 0 where ``state`` is
        None).
    """

    terminal: np.ndarray
    state: np.ndarray | None
    exit: np.ndarray | None = None
    hold: float = 0.0


def _ending(problem) -> str:
    """The name of the cost a path pays where it ends: ``"exit_cost"`` for a task without a
    horizon (first exit), ``"terminal_cost"`` otherwise."""
    return "exit_cost" if problem.stationary else "terminal_cost"


HOLD_STATES = 4096
"""At most this many nodes of the coarse grid (evenly spaced)
give :func:`~gridlbc.accuracy.subcell.hold_time`."""


def hold_time(problem, coarse: Grid) -> float | None:
    """τ of the state cost's soft minimum (module docstring): the horizon T where the task has
    one; without one (first exit, average cost) the time in which the noise moves a path across
    a cell of ``coarse`` along its slowest noisy axis where it is slowest,

        τ = 1 / min_j min_{k: Σ_kk > 0} Σ_kk(x_j) / H_k²,

    over (up to :data:`HOLD_STATES`) nodes x_j of ``coarse`` (spacing H, Σ = λ B R⁻¹ Bᵀ). Held
    longer than that, a path pays to stay in a well: in one dimension, to keep a path within a
    width w = 2ρH of the hat (a share ρ of it) costs λ Σ π² / (2 w²) per unit time, and the
    soft minimum at λ/τ charges λ log(1/ρ) / τ = λ Σ log(1/ρ) / H², never more (log(1/ρ) ≤
    π²/(8ρ²)): the excess δq is at least as deep as what holding in the well can gain. None
    where no node has noise."""
    if not problem.stationary:
        return problem.require_horizon("an excess")
    step = max(1, coarse.size // HOLD_STATES)
    x = coarse.node_coordinates(np.arange(0, coarse.size, step))
    rates = problem.noise_diagonal(x) / np.asarray(coarse.spacing, dtype=float) ** 2
    noisy = rates[rates > 0]
    return 1.0 / float(noisy.min()) if noisy.size else None


def excess(problem, coarse: Grid, terminal_costs, m: int | None = None) -> Excess:
    """The sub-cell excess of ``problem``'s state cost and of each of ``terminal_costs``, as a soft
    minimum over the hat functions of ``coarse`` (module docstring). For a problem without a
    horizon the costs are exit costs g_E (τ = 1, as for g; none for the average cost) and the
    state cost's τ is :func:`~gridlbc.accuracy.subcell.hold_time`; with a horizon and an exit set,
    the exit cost is sampled beside g and q (τ = 1).

    Parameters
    ----------
    problem : Problem
        A problem on its grid (spacing h), whose lattice is sampled.
    coarse : Grid
        The grid on whose nodes the excess is wanted (the same box).
    terminal_costs : sequence of callable
        The terminal costs g_i (exit costs for a problem without a horizon).
    m : int, optional
        Lattice points per cell along each axis (default
        :func:`~gridlbc.accuracy.grids.samples_per_cell`).

    Returns
    -------
    Excess
    """
    grid = problem.require_grid("a sub-cell excess")
    m = samples_per_cell(grid) if m is None else m
    points = refined_grid(grid, factor=m)  # the sampling lattice
    hats = [hat_weights(c, a.points()) for c, a in zip(coarse.axes, points.axes, strict=True)]
    ending = _ending(problem)
    ends = [problem.replace(**{ending: g}) for g in terminal_costs]
    # (the index of a terminal cost, "state" or "exit"; the cost's values; its time scale τ;
    # whether it is paid on the exit set only)
    sampled: list[tuple[int | str, Callable, float, bool]] = [
        (i, p.exit_values if problem.stationary else p.terminal_values, 1.0, problem.stationary)
        for i, p in enumerate(ends)
        if not reproduced(getattr(p, ending))
    ]
    hold = None if reproduced(problem.state_cost) else hold_time(problem, coarse)
    if hold is not None:
        sampled.append(("state", partial(problem.state_cost_values, signed=True), hold, False))
    if not problem.stationary and problem.exit is not None and not reproduced(problem.exit_cost):
        sampled.append(("exit", problem.exit_values, 1.0, True))
    nodal = [grid.reshape(grid.node_values(values)) for _, values, _, _ in sampled]
    anchors = [coarse.reshape(coarse.node_values(values)) for _, values, _, _ in sampled]
    scale = problem.temperature
    sums = np.zeros((2, len(sampled)) + coarse.shape)
    least = np.full((len(sampled),) + coarse.shape, np.inf)  # min of f over each hat's support
    supports = [_support(hat) for hat in hats]
    paid_on_exit = any(on_exit for *_, on_exit in sampled)
    for block in _blocks(points) if sampled else ():
        off_exit = ~block.evaluate(problem.exit_mask, bool) if paid_on_exit else None
        for k, (_, values, tau, on_exit) in enumerate(sampled):
            true, rebuilt = block.values(values, nodal[k], grid, m)
            outside = off_exit if on_exit else None
            if outside is not None:  # paid on E only: no seeds off E, and no share in either sum
                true = np.where(outside, rebuilt, true)
            anchor = block.spread(anchors[k], hats)
            measure = partial(_exponents, values, nodal[k], grid, coarse, anchors[k], tau / scale)
            seeds, deeper, bottoms = _deeper(measure, grid, coarse, block, true, rebuilt, m)
            lowest = true.copy() if outside is None else np.where(outside, np.inf, true)
            if len(seeds):  # the descents' bottoms, where they went below the lattice
                lowest.reshape(-1)[seeds] = np.fmin(lowest.reshape(-1)[seeds], values(bottoms))
            np.minimum(least[k], block.least(lowest, supports), out=least[k])
            for side, exponent in enumerate((true, rebuilt)):  # −τ (f − I f_c)/λ, in place
                np.subtract(exponent, anchor, out=exponent)
                np.multiply(exponent, -tau, out=exponent)
                np.divide(exponent, scale, out=exponent)
                exponent.reshape(-1)[seeds] = deeper[side]
                np.minimum(exponent, EXPONENT_CAP, out=exponent)
                if outside is not None:
                    exponent[outside] = -np.inf
                with np.errstate(under="ignore"):
                    sums[side, k] += block.average(np.exp(exponent, out=exponent), hats)
    terminal = np.zeros((len(terminal_costs),) + coarse.shape)
    others: dict[str, np.ndarray] = {}
    for k, (i, _, tau, _) in enumerate(sampled):
        soft = -scale / tau * _log_ratio(*sums[:, k])
        floor = least[k] - anchors[k]  # no hat holds a cost below its lowest sample
        soft = np.where(np.isfinite(floor), np.fmax(soft, floor), soft)
        if isinstance(i, str):
            others[i] = soft.reshape(-1)
        else:
            terminal[i] = soft
    state = others.get("state")
    return Excess(
        terminal.reshape(len(terminal_costs), coarse.size),
        state,
        others.get("exit"),
        0.0 if state is None or hold is None else hold,
    )


ROUNDING = 1e-10
"""An excess smaller than this share of the cost's largest magnitude on a block is taken for
rounding (the reconstruction's sums round at about 4^d machine epsilons of it, of the nodal
values, which the lattice holds): no seed there."""


DESCENT_LEVELS = 6
"""At most this many levels of :func:`descend`: its finest boxes are 3⁻⁶ of the lattice's
spacing wide."""


def rebuild(nodes: np.ndarray, grid: Grid, x) -> np.ndarray:
    """The reconstruction R f from the nodal values ``nodes`` of ``grid`` at states ``x``
    (N, d): the rule of :func:`refine` at any offset, along each axis in turn (the lattice's
    values where ``x`` are its points)."""
    positions = (np.atleast_2d(np.asarray(x, dtype=float)) - grid.lo) / grid.spacing
    out = np.empty(len(positions))
    shape = np.array(grid.shape, dtype=np.int64)
    flat = np.ascontiguousarray(nodes, dtype=float).reshape(-1)
    rebuild_points(flat, shape, np.asarray(grid.periodic), positions, KINK, out)
    return out


def descend(measure, grid: Grid, centres: np.ndarray, side: np.ndarray):
    """Box averages of exp(u) for the two exponents u that ``measure`` returns (the cost's and its
    reconstruction's, :func:`~gridlbc.accuracy.excess`), around each of ``centres`` (S, d), and
    where the first is largest.

    The box B of width ``side`` (per axis) around a centre is cut into 3^d boxes a third as wide
    (its centre stays a sample), each counted by its centre's value, and the one where the first
    exponent is largest is cut again, up to :data:`DESCENT_LEVELS` times: an adaptive midpoint
    rule that follows a goal or a well narrower than the box down to its bottom, where the points
    around it see only its tail. It stops where the box's mean over its 3^d centres and its own
    centre's value agree as well for one exponent as for the other,
    to :data:`~gridlbc.accuracy.subcell.NEGLIGIBLE` (in log): the cost is as smooth as its
    reconstruction there, and cutting further would move both sums alike.

    Parameters
    ----------
    measure : callable
        ``measure(x)`` → (2, N): the two exponents at states x (N, d).
    grid : Grid
        The box (closed axes clip, periodic ones wrap).
    centres : ndarray (S, d)
    side : ndarray (d,)

    Returns
    -------
    log_average : ndarray (2, S)
        The log of the mean of exp(u) over B, for each exponent, by the adaptive midpoint rule.
    bottoms : ndarray (S, d)
        The centres of the last boxes cut: where the first exponent is largest.
    cut : ndarray (S,) of int
        How many times each box was cut.
    """
    d = grid.ndim
    offsets = np.array(list(itertools.product((-1.0, 0.0, 1.0), repeat=d)))
    centres = np.array(centres, dtype=float)
    current = measure(centres)
    counted = np.full(current.shape, -np.inf)  # log of the share-weighted sum of the boxes done
    share = np.zeros(len(centres))  # log of the share of B still being cut
    active = np.arange(len(centres))
    cut = np.zeros(len(centres), dtype=np.int64)
    for _ in range(DESCENT_LEVELS):
        if len(active) == 0:
            break
        side = side / 3.0
        rows = np.arange(len(active))
        x = grid.clamp(centres[active, None, :] + offsets * side).reshape(-1, d)
        found = measure(x).reshape(2, len(active), len(offsets))
        best = np.argmax(found[0], axis=1)
        share[active] -= d * np.log(3.0)
        others = found.copy()
        others[:, rows, best] = -np.inf
        counted[:, active] = np.logaddexp(
            counted[:, active], share[active] + logsumexp(others, axis=2)
        )
        # the box's mean over its 3^d centres against its own centre's value, for each exponent
        refined = logsumexp(found, axis=2) - d * np.log(3.0) - current[:, active]
        moved = np.abs(refined[0] - refined[1]) > NEGLIGIBLE
        below = found[:, rows, best]
        centres[active] = x.reshape(len(active), -1, d)[rows, best]
        current[:, active] = below
        cut[active] += 1
        active = active[moved]
    return np.logaddexp(counted, share + current), centres, cut


def _exponents(f, nodes, grid: Grid, coarse: Grid, anchor, rate, x) -> np.ndarray:
    """(2, N): the soft minimum's exponents −rate (f − I f_c) and −rate (R f − I f_c) at states
    ``x`` (:func:`~gridlbc.accuracy.excess`), for :func:`descend`."""
    reference = multilinear(coarse, anchor, x)
    return -rate * np.stack([f(x) - reference, rebuild(nodes, grid, x) - reference])


def _deeper(measure, grid: Grid, coarse: Grid, block: _Block, true, rebuilt, m: int):
    """The block's points that are local minima of the excess f − R f (``true`` − ``rebuilt``)
    where it is below zero by more than rounding (:data:`ROUNDING`; rounding leaves a quadratic
    cost's excess ragged, with a local minimum in every cell), as flat indices; and the log box
    averages there of the exponents ``measure`` returns (:func:`descend` in the point's box of
    the lattice's spacing; where it found a feature there, in a box of that width around the
    feature's bottom).

    The descent costs at most 2 · 3^d · :data:`DESCENT_LEVELS` evaluations per point, and it
    looks around as many points as keep that within the block's size (a trough along an axis
    has a minimum at every point along it): first the lowest in each cell of ``coarse`` (each
    hat wants its own), the lowest of them where they are more; then the others, evenly spread
    over the block. Also returned: the bottoms the descents reached (S, d)."""
    rounding = ROUNDING * max(float(true.max()), -float(true.min()))  # max abs(f), no copy
    true, rebuilt = true.reshape(-1), rebuilt.reshape(-1)
    minima = np.empty(true.size, dtype=bool)
    wrap = np.array([False] + [a.periodic for a in grid.axes[1:]])  # the block's rows clip
    local_minima(true, rebuilt, np.array(block.shape, dtype=np.int64), wrap, rounding, minima)
    seeds = np.flatnonzero(minima)
    most = max(1, true.size // (2 * max(DESCENT_LEVELS, 1) * 3**grid.ndim))
    if len(seeds) > most:
        depth = true[seeds] - rebuilt[seeds]
        cell = np.ravel_multi_index(
            tuple(
                np.minimum(np.floor((c - a.lo) / a.spacing).astype(np.int64), a.n - 1)
                for c, a in zip(block.points(seeds).T, coarse.axes, strict=True)
            ),
            coarse.shape,
        )
        order = np.lexsort((depth, cell))
        first = order[np.unique(cell[order], return_index=True)[1]]
        first = first[np.argsort(depth[first])][:most]
        rest = np.setdiff1d(np.arange(len(seeds)), first)
        spread = rest[np.linspace(0, len(rest) - 1, most - len(first)).astype(np.int64)]
        seeds = seeds[np.concatenate([first, spread])]
    if len(seeds) == 0:
        return seeds, np.empty((2, 0)), np.empty((0, grid.ndim))
    side = grid.spacing / m
    found, bottoms, cut = descend(measure, grid, block.points(seeds), side)
    deep = cut > 1  # a feature between the points: summed again around its bottom
    if deep.any():
        found[:, deep] = descend(measure, grid, bottoms[deep], side)[0]
    return seeds, found, bottoms


def reproduced(cost) -> bool:
    """Whether the reconstruction reproduces ``cost`` (absent, a :class:`~gridlbc.costs.Constant`
    or a :class:`~gridlbc.costs.Quadratic`): its excess is zero without sampling it. A quadratic
    wrapped on a periodic axis has a kink at its seam, where the cost is largest; where the seam
    falls between two nodes, a ridge a path would cross there is as low on the grid as it is at
    the nodes around it, which is not looked for."""
    return cost is None or isinstance(cost, (Constant, Quadratic))


@dataclass(frozen=True)
class _Block:
    """Whole rows ``rows`` (along the first axis) of the sampling lattice, of ``shape``, and the
    coordinates along each axis of its points (``axes``; the first axis's at ``rows``)."""

    rows: np.ndarray
    axes: list[np.ndarray]
    shape: tuple[int, ...]

    def points(self, flat: np.ndarray) -> np.ndarray:
        """The block's points (N, d) at the flat indices ``flat`` (C order)."""
        index = np.unravel_index(flat, self.shape)
        return np.stack([axis[j] for axis, j in zip(self.axes, index, strict=True)], axis=1)

    def values(self, f, nodes: np.ndarray, grid: Grid, m: int) -> tuple[np.ndarray, np.ndarray]:
        """f at the block's points (:meth:`evaluate`), and its reconstruction from its values at
        the ``nodes`` of ``grid`` (:func:`refine` along each axis, m points per cell)."""
        rebuilt = refine(nodes, 0, grid.axes[0], m, self.rows)
        for k in range(1, grid.ndim):
            rebuilt = refine(rebuilt, k, grid.axes[k], m)
        return self.evaluate(f), rebuilt

    def evaluate(self, f, dtype=float) -> np.ndarray:
        """``f(points)`` at the block's points, of the block's shape, their coordinates formed
        :data:`~gridlbc.grid.NODE_CHUNK` at a time."""
        out = np.empty(int(np.prod(self.shape)), dtype=dtype)
        shape = np.array(self.shape, dtype=np.int64)
        values, starts = np.concatenate(self.axes), np.cumsum([0] + [len(a) for a in self.axes])
        for first in range(0, len(out), NODE_CHUNK):
            points = np.empty((min(NODE_CHUNK, len(out) - first), len(self.axes)))
            lattice_points(first, shape, values, starts[:-1], points)
            out[first : first + len(points)] = f(points)
        return out.reshape(self.shape)

    def spread(self, coarse_values: np.ndarray, hats: list) -> np.ndarray:
        """The multilinear interpolant Σ_j φ_j(s) c_j of coarse nodal values at the block's
        points s."""
        values = along(hats[0][:, self.rows].T, coarse_values, 0)
        for k in range(1, len(hats)):
            values = along(hats[k].T, values, k)
        return values

    def least(self, values: np.ndarray, supports: list) -> np.ndarray:
        """min over the block's points s in the support of φ_j of ``values``(s), for every coarse
        node j (+inf where none lies in the block)."""
        for k in range(1, len(supports)):
            values = _least_along(supports[k], values, k)
        return _least_along(supports[0][:, self.rows], values, 0)

    def average(self, values: np.ndarray, hats: list) -> np.ndarray:
        """Σ_s φ_j(s) values(s) over the block's points s, for every coarse node j."""
        for k in range(1, len(hats)):
            values = along(hats[k], values, k)
        return along(hats[0][:, self.rows], values, 0)


def _support(hat: sp.csr_matrix) -> sp.csr_matrix:
    """The hat matrix without its zero weights (a point on a coarse node is in no other hat)."""
    support = hat.copy()
    support.eliminate_zeros()
    return support


def _least_along(support: sp.csr_matrix, values: np.ndarray, axis: int) -> np.ndarray:
    """For every row j of ``support`` (a coarse node), the least of ``values`` along ``axis``
    over the points in its hat's support (+inf where it holds none)."""
    values = np.ascontiguousarray(values, dtype=float)
    outer, inner = int(np.prod(values.shape[:axis])), int(np.prod(values.shape[axis + 1 :]))
    out = np.empty((outer, support.shape[0], inner))
    least_in_supports(values.reshape(outer, -1, inner), support.indptr, support.indices, out)
    return out.reshape(values.shape[:axis] + (support.shape[0],) + values.shape[axis + 1 :])


def _blocks(points: Grid):
    """The lattice ``points`` in :class:`_Block` s of about :data:`LATTICE_BLOCK` points."""
    axes = [a.points() for a in points.axes]
    step = max(1, LATTICE_BLOCK // int(np.prod(points.shape[1:])))
    for start in range(0, points.shape[0], step):
        rows = np.arange(start, min(start + step, points.shape[0]))
        yield _Block(rows, [axes[0][rows]] + axes[1:], (len(rows),) + points.shape[1:])


def _log_ratio(true: np.ndarray, rebuilt: np.ndarray) -> np.ndarray:
    """log(true / rebuilt); 0 where both sums underflowed (nothing is known there), and where
    only the reconstruction's did, log(true) + :data:`EXPONENT_CAP`."""
    out = np.zeros(true.shape)
    both = (true > 0) & (rebuilt > 0)
    out[both] = np.log(true[both] / rebuilt[both])
    unseen = (true > 0) & (rebuilt == 0)
    out[unseen] = np.log(true[unseen]) + EXPONENT_CAP
    return out


@dataclass(frozen=True, eq=False)
class WithExcess:
    """A cost plus its sub-cell excess, interpolated from the nodes of a coarse grid:
    ``cost(x) + I δ(x)``, at least ``floor`` (0 for a state cost, which must stay non-negative;
    None for a terminal cost).

    Parameters
    ----------
    cost : callable or None
        The cost (None: zero).
    grid : Grid
        The coarse grid that holds δ.
    delta : ndarray (Nc,)
        δ at its nodes.
    floor : float or None
        The least value returned.
    """

    cost: Callable | None
    grid: Grid
    delta: np.ndarray
    floor: float | None = None

    def __call__(self, x) -> np.ndarray:
        x = np.atleast_2d(np.asarray(x, dtype=float))
        base = np.zeros(len(x)) if self.cost is None else np.asarray(self.cost(x), dtype=float)
        out = base + interpolate(self.grid, self.delta, x)
        return out if self.floor is None else np.maximum(out, self.floor)


NEGLIGIBLE = 0.01
"""Where sup|δg| + T sup|δq| is at most this many λ, the raised solve is not run: S is at most
that bound everywhere (:class:`Response`), at most this share of max(abs(v), λ)."""


@dataclass(frozen=True)
class Response:
    """What the costs' sub-cell excess changes in a coarse solve (module docstring).

    Attributes
    ----------
    base : Solution or None
        The coarse solve, v_c[g, q], by the plain scheme; None where it was not needed.
    raised : Solution or None
        The same with the costs raised by their excess, v_c[g + δg, q + δq]; None where
        ``bound`` is negligible (:data:`~gridlbc.accuracy.subcell.NEGLIGIBLE`) and neither was
        solved.
    bound : float
        sup|δg| + τ sup|δq| (+ sup|δg_E| with an exit set and a horizon) over the coarse nodes,
        τ = :func:`~gridlbc.accuracy.subcell.hold_time`. With a horizon (τ = T) S never exceeds it
        (v is 1-Lipschitz in the costs, in the supremum norm, and so is a monotone scheme's);
        without one it only says whether the excess is negligible (a first-exit path may stay longer
        than τ).
    """

    base: Solution | None
    raised: Solution | None
    bound: float

    def __call__(self, x, t=0.0) -> np.ndarray:
        """S(x, t) = abs(v_c[g + δg, q + δq] − v_c[g, q]) at states ``x`` (N, d), or ``bound``
        where the raised solve was not run; 0 where both values are infinite (underflow)."""
        if self.raised is None or self.base is None:
            return np.full(len(np.atleast_2d(x)), self.bound)
        with np.errstate(invalid="ignore"):
            response = np.abs(self.raised.value(x, t) - self.base.value(x, t))
        return np.where(np.isnan(response), 0.0, response)


def responses(
    problem, terminal_costs, coarse: Grid, solve, base=None, missed=None
) -> list[Response]:
    """The :class:`Response` of the coarse solves of ``problem`` with each of ``terminal_costs``
    to the costs' sub-cell excess.

    Both solves, v_c[g, q] and v_c[g + δg, q + δq], are made by ``solve`` (the solver passes
    its scheme without exponential fitting): a fitted scheme interpolates z relative to its
    reference φ in every step, which spreads a feature that φ does not have, such as the
    raised costs' narrow dip, by about a cell's width per step (and a reference fitted to the
    raised cost itself takes its dip geometrically between the nodes): its response to a dip
    is a fraction of the true one, the smaller the more axes and steps (docs page
    :doc:`accuracy`, "Costs between the nodes", has the measurements).

    Where the exit set has parts that no node of the grid holds
    (:func:`~gridlbc.accuracy.exits.missed_points`), the raised solve also moves them onto the
    coarse grid's nearest nodes (:class:`~gridlbc.accuracy.exits.MovedExit`), and is run
    whatever the costs' excess: S then reads what those parts change too (and ``bound`` is
    +inf).

    Parameters
    ----------
    problem : Problem
        The problem on its own grid, whose lattice is sampled.
    terminal_costs : sequence of callable
    coarse : Grid
        The grid of the coarse solves.
    solve : callable
        ``solve(problem, costs)`` → list of Solution, one per cost: the coarse solve.
    base : list of Solution, optional
        v_c[g, q] for each cost where the caller has it already (a stationary solve's embedded
        level, made by the same ``solve``); solved here otherwise.
    missed : ndarray (M, d), optional
        The exit set's parts that no node holds (:func:`~gridlbc.accuracy.exits.missed_points`),
        where the caller has them; found here otherwise.

    Returns
    -------
    list of Response
    """
    found = excess(problem, coarse, terminal_costs)
    held = 0.0 if found.state is None else found.hold * float(np.abs(found.state).max())
    if found.exit is not None:
        held += float(np.abs(found.exit).max())
    bounds = [float(np.abs(dg).max()) + held for dg in found.terminal] or [held]
    points = missed_points(problem) if missed is None else missed
    moved = MovedExit(problem, coarse, points) if len(points) else None
    if moved is not None:  # what a part of E moved onto a node changes has no such bound
        bounds = [np.inf for _ in bounds]
    if max(bounds) <= NEGLIGIBLE * problem.temperature:
        return [Response(None, None, bound) for bound in bounds]
    changes: dict = {}
    if found.state is not None:
        changes["state_cost"] = WithExcess(problem.state_cost, coarse, found.state, 0.0)
    ending = _ending(problem)
    exit_cost = problem.exit_cost
    if moved is not None:
        changes["exit"] = moved.region
        if ending != "exit_cost":
            exit_cost = changes["exit_cost"] = moved.cost(exit_cost)
    if found.exit is not None:
        changes["exit_cost"] = WithExcess(exit_cost, coarse, found.exit)
    costs = []
    for g, dg in zip(terminal_costs, found.terminal, strict=True):
        own = getattr(problem.replace(**{ending: g}), ending)
        if moved is not None and ending == "exit_cost":  # a first exit's costs are exit costs
            own = moved.cost(own)
        costs.append(WithExcess(own, coarse, dg))
    base = solve(problem, list(terminal_costs)) if base is None else list(base)
    raised = solve(problem.replace(**changes), costs)
    return [Response(b, r, bound) for b, r, bound in zip(base, raised, bounds, strict=True)]
