"""How accurate is a solve: the embedded error estimate and solves to a tolerance (docs page
:doc:`accuracy`, which explains what the estimate sees and what it cannot).

- :mod:`gridlbc.accuracy.grids`: the embedded grids (every other node) and the finer ones;
- :mod:`gridlbc.accuracy.embedding`: what every grid solve runs to carry its estimate;
- :mod:`gridlbc.accuracy.estimate`: the embedded estimate, read at any state;
- :mod:`gridlbc.accuracy.matter`: the states at which a default solve is judged;
- :mod:`gridlbc.accuracy.assessment`: the estimate judged against a tolerance, and the default
  solve's warning;
- :mod:`gridlbc.accuracy.paths`: what the grid cannot see of the costs, sampled along the solve's
  paths;
- :mod:`gridlbc.accuracy.subcell`: the costs' excess between the nodes and what it changes in a
  coarse solve;
- :mod:`gridlbc.accuracy.flow`: a drift that changes between the nodes where neither the grid nor
  the coarser solves follow it;
- :mod:`gridlbc.accuracy.tracing`: a drift that switches within a step, seen by tracing each
  step's foot by two half steps;
- :mod:`gridlbc.accuracy.truncation`: the generator's truncation error on a stationary solve's
  value, where z falls faster than a cell;
- :mod:`gridlbc.accuracy.bellman`: a local certificate, the solved value against what the SDE
  makes of it a little later, which confirms the warning where an error is confined to a few
  states;
- :mod:`gridlbc.accuracy.certified`: the error measured by certificates where the estimate
  cannot decide;
- :mod:`gridlbc.accuracy.tolerance`: solves to a tolerance (``gridlbc.solve(problem, tol=...)``).

Each module's docstring has its equations; the names imported here are the package's public
ones.
"""

from .assessment import (
    ASSESSED_PATHS,
    DEFAULT_TOLERANCE,
    QUANTILE,
    Assessment,
    assess,
    check_accuracy,
    check_scalar,
    statistic,
)
from .bellman import (
    BELLMAN_SE,
    LOCAL_SAMPLES,
    LOCAL_WORK,
    WHOLE_SAMPLES,
    bellman_gap,
    largest_discount,
    local_error,
)
from .certified import (
    CERTIFICATE_LEVEL,
    CERTIFICATE_SAMPLES,
    CERTIFICATE_STEPS,
    CERTIFIED_STATES,
    certifiable,
    certificate_work,
    certified_error,
)
from .estimate import (
    ASYMPTOTIC,
    EmbeddedEstimate,
    ScalarEstimate,
    attach_estimates,
    clipped_order,
    embedded_estimate,
    observed_order,
    relative_difference,
    relative_error,
    richardson,
    scalar_estimate,
    scalar_relative,
)
from .exits import check_exit, missed_exit, missed_points
from .flow import (
    FLOW_CELLS,
    FLOW_SAMPLES,
    SMOOTH_ORDER,
    check_flow,
    flow_excess,
    followed,
    follows_coefficients,
    noise_excess,
    reads_pair,
)
from .grids import (
    cells,
    embedded_grid,
    embedded_solves,
    embedded_store_every,
    pair_solves,
    phase_pair,
    refined_grid,
    scaled_grid,
)
from .matter import (
    ASSESSED,
    SAMPLE,
    better_half,
    calibration_states,
    judged_states,
    states_that_matter,
)
from .paths import (
    PATH_SAMPLES,
    PATH_WORK,
    STATIONARY_SAMPLES,
    cost_gap,
    path_gap,
    path_step,
    stationary_gap,
    terminal_gap,
)
from .subcell import (
    NEGLIGIBLE,
    Excess,
    Response,
    WithExcess,
    excess,
    responses,
    samples_per_cell,
)
from .tolerance import (
    MARCH_WORK_EXPONENT,
    UNPOSED,
    Refinement,
    at_observed_order,
    axes_to_refine,
    axis_shares,
    check_budget,
    check_tolerance,
    confirmed,
    finish,
    fitting_plan,
    fitting_storage,
    holding,
    limiting_axes,
    over_budget,
    predicted_seconds,
    refinement_factors,
    shares_add_up,
    solve_to_tolerance,
    tell_held,
    unestimated,
    unsteerable,
)
from .tracing import tracing_gap, tracing_rate
from .truncation import average_truncation, truncation_gap, truncation_rate

__all__ = [
    "ASSESSED",
    "ASSESSED_PATHS",
    "ASYMPTOTIC",
    "BELLMAN_SE",
    "CERTIFICATE_LEVEL",
    "CERTIFICATE_SAMPLES",
    "CERTIFICATE_STEPS",
    "CERTIFIED_STATES",
    "DEFAULT_TOLERANCE",
    "FLOW_CELLS",
    "FLOW_SAMPLES",
    "LOCAL_SAMPLES",
    "LOCAL_WORK",
    "MARCH_WORK_EXPONENT",
    "NEGLIGIBLE",
    "PATH_SAMPLES",
    "PATH_WORK",
    "QUANTILE",
    "SAMPLE",
    "SMOOTH_ORDER",
    "STATIONARY_SAMPLES",
    "UNPOSED",
    "WHOLE_SAMPLES",
    "Assessment",
    "EmbeddedEstimate",
    "Excess",
    "Refinement",
    "Response",
    "ScalarEstimate",
    "WithExcess",
    "assess",
    "at_observed_order",
    "attach_estimates",
    "average_truncation",
    "axes_to_refine",
    "axis_shares",
    "bellman_gap",
    "better_half",
    "calibration_states",
    "cells",
    "certifiable",
    "certificate_work",
    "certified_error",
    "check_accuracy",
    "check_budget",
    "check_exit",
    "check_flow",
    "check_scalar",
    "check_tolerance",
    "clipped_order",
    "confirmed",
    "cost_gap",
    "embedded_estimate",
    "embedded_grid",
    "embedded_solves",
    "embedded_store_every",
    "excess",
    "finish",
    "fitting_plan",
    "fitting_storage",
    "flow_excess",
    "followed",
    "follows_coefficients",
    "holding",
    "judged_states",
    "largest_discount",
    "limiting_axes",
    "local_error",
    "missed_exit",
    "missed_points",
    "noise_excess",
    "observed_order",
    "over_budget",
    "pair_solves",
    "path_gap",
    "path_step",
    "phase_pair",
    "predicted_seconds",
    "reads_pair",
    "refined_grid",
    "refinement_factors",
    "relative_difference",
    "relative_error",
    "responses",
    "richardson",
    "samples_per_cell",
    "scalar_estimate",
    "scalar_relative",
    "scaled_grid",
    "shares_add_up",
    "solve_to_tolerance",
    "states_that_matter",
    "stationary_gap",
    "statistic",
    "tell_held",
    "terminal_gap",
    "tracing_gap",
    "tracing_rate",
    "truncation_gap",
    "truncation_rate",
    "unestimated",
    "unsteerable",
]
