"""What every grid solve runs to carry its error estimate (docs page :doc:`accuracy`): the
embedded solves, the response to the costs' excess between the nodes, the pair where a feature
narrower than a cell asks for it, the estimate attached, and the exit set's parts that no node
holds. A time march (:func:`gridlbc.solve` with a horizon) and a stationary solve (first exit,
average cost) differ only in how they solve on another grid, which they pass in.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

from ..errors import ResolutionWarning, warn_user
from ..problem import Problem
from .assessment import check_accuracy
from .estimate import attach_estimates, quiet_reads
from .exits import check_exit, missed_points
from .flow import reads_pair
from .grids import embedded_solves, pair_solves
from .subcell import responses


class Embedding(NamedTuple):
    """The solves that an estimate reads (:func:`embed`)."""

    levels: list  # [(solutions at 2h), (at 4h)], fewer where a grid is too coarse to embed
    pairs: list | None  # the solves on the pair of grids, None where not read
    excess: list | None  # the Response to the costs' excess of each cost, None without levels


def embed(
    problem: Problem,
    costs: list,
    solutions: list,
    on_grid: Callable,
    on_coarse: Callable,
    base: bool = False,
) -> Embedding:
    """Attach to each of ``solutions`` (one per terminal or exit cost of ``costs``) its
    embedded estimate (:func:`~gridlbc.accuracy.estimate.attach_estimates`) and warn where it
    exceeds the default tolerance (:func:`~gridlbc.accuracy.assessment.check_accuracy`), where none
    could be made (a grid too coarse to embed, or a problem that cannot be posed on the embedded
    grid: the grid resolves it too barely for an estimate), or where the exit set has a part that no
    node holds (:func:`~gridlbc.accuracy.check_exit`):

    1. the solves on the grids with every other node, 2h and 4h
       (:func:`~gridlbc.accuracy.embedded_solves`, by ``on_grid(grid, factor)``, factor the
       step's multiple where the solve marches in time);
    2. the response of the solve at 2h to the costs' sub-cell excess
       (:func:`~gridlbc.accuracy.responses`, by ``on_coarse(problem, costs)`` with the problem
       moved to the grid at 2h; ``base``: the
       level at 2h is that solve's own base, as for a stationary solve, rather than solved again
       without exponential fitting, as a time march needs);
    3. where a feature narrower than a cell asks for it (:func:`~gridlbc.accuracy.reads_pair`),
       the solves on the pair of grids (:func:`~gridlbc.accuracy.pair_solves`, by ``on_grid``).

    Their own warnings are the callers' to silence: they are not the user's.
    """
    fine = problem.require_grid("an embedded solve")
    with quiet_reads():
        levels, reason = embedded_solves(fine, on_grid)
        excess = pairs = None
        missed = missed_points(problem)  # the exit set's parts no node holds (none without one)
        if levels:
            coarse = levels[0][0].grid
            own = levels[0] if base else None

            def solve(on: Problem, raised: list) -> list:
                return on_coarse(on.replace(grid=coarse), raised)

            excess = responses(problem, costs, coarse, solve, own, missed)
            if reads_pair(solutions[0], excess):
                pairs = pair_solves(fine, levels[0], on_grid)
            attach_estimates(solutions, levels, pairs, excess)
            for solution in solutions:
                check_accuracy(solution)
        elif reason:
            warn_user(
                f"no error estimate for this solve: {reason} (docs page 'accuracy')",
                ResolutionWarning,
            )
        check_exit(solutions[0], missed)  # the exit set is the problem's: one look for all
    return Embedding(levels, pairs, excess)
