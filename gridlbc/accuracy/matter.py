"""The states at which a default solve is judged, and those its estimate is calibrated on (docs
page :doc:`accuracy`, "Relative error and the states that matter").

Without states from the user, a solve is judged at the states that matter
(:func:`~gridlbc.accuracy.states_that_matter`): for a task that runs on (no exit set, no horizon)
the nodes whose value is finite and at most the median over the grid (the better half of the box,
where the controlled process spends its time; the far corners of a box, where every solve is poor,
do not count); for a task that ends (an exit set, a horizon or both) every node with a finite value
off the exit set, since v(x, 0) is the cost of a task started at x and a task starts anywhere,
typically far from where it ends, where v is largest. The estimate's floor and observed order
are measured over :func:`~gridlbc.accuracy.calibration_states`, where the errors carried along the
paths end up.
"""

from __future__ import annotations

import numpy as np

SAMPLE = 20_000
"""At most this many of the calibration states give the floor (evenly spaced in the nodes'
order): a median of the estimate needs no more, and a 4-D grid has millions."""


ASSESSED = 256
"""At most this many of the states that matter are judged against a tolerance (evenly spaced in
the nodes' order): the estimate there samples paths from each (:mod:`gridlbc.accuracy.paths`),
and a 90th percentile needs no more."""


def _evenly(solution, chosen: np.ndarray, limit: int) -> np.ndarray:
    """The nodes of the mask ``chosen``, at most ``limit`` of them evenly spaced, ``(M, d)``."""
    return node_states(solution, _evenly_index(chosen, limit))


def node_states(solution, keep: np.ndarray) -> np.ndarray:
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
    (:func:`~gridlbc.accuracy.assess`), where its paths end up.

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
    """The flat mask of the nodes among which :func:`~gridlbc.accuracy.states_that_matter` are
    chosen."""
    problem = solution.problem
    if problem.exit is None and problem.stationary:
        return solution.better_half()
    return _finite_off_exit(solution)


def calibration_states(solution, limit: int = SAMPLE) -> np.ndarray:
    """The states over which the estimate's floor and observed order are measured
    (:func:`~gridlbc.accuracy.embedded_estimate`), ``(M, d)``: the :func:`better_half` of a
    task without an exit set (with or without a horizon), every node off the exit set of a task with
    one.

    The floor is the typical relative error that an error carried along the characteristics
    leaves where the two solves happen to agree, and the order is Richardson's model of the
    levels. A finite horizon's paths end up in the better half from wherever they start, so the
    errors they carry are read there; the states far up the value, judged for the warning
    (:func:`~gridlbc.accuracy.states_that_matter`), hold the errors of their own region (a gust, a
    wall) and often levels that do not converge at all, which, taken into the floor and the order,
    would raise the estimate everywhere. The estimate at any state is therefore the same as when the
    better half alone was judged: only where it is judged changed."""
    if solution.problem.exit is None:
        return better_half(solution, limit)
    return _evenly(solution, _finite_off_exit(solution), limit)


def judged_states(solution, states=None) -> np.ndarray:
    """``states`` as ``(N, d)``, or :data:`ASSESSED` of :func:`~gridlbc.accuracy.states_that_matter`
    when None."""
    if states is None:
        return node_states(solution, judged_nodes(solution))
    return np.atleast_2d(np.asarray(states, dtype=float))


def judged_nodes(solution) -> np.ndarray:
    """The flat indices of the nodes :func:`judged_states` reads without states: the
    :data:`ASSESSED` of :func:`~gridlbc.accuracy.states_that_matter`."""
    return _evenly_index(matter_mask(solution), ASSESSED)
