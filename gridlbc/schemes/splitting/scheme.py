"""The splitting as a :class:`~gridlbc.schemes.protocol.Scheme`: its default step, its loops and
its checks, as :func:`gridlbc.solve` calls them.

The default step holds a Courant number: of the largest rate max_x max_k |a_k(x)| / h_k for the
plain operator, and of that rate's root mean square over the nodes for the fitted one, whose
error balances an O(h²/Δt) interpolation term against the O(Δt) splitting over the nodes that
matter (in 4-D the largest rate sits in far corners of the box, far above its root mean square).
With a state cost the step is also at most :func:`~.checks.cost_sampling_step`.
"""

from __future__ import annotations

from ...problem import Problem
from ...representation import LinearZ
from ..protocol import Marched, MarchPlan, SchemeBase, StepRule, Terminal
from ..tails import check_resolution
from .checks import (
    CostSamplingBound,
    check_control_step,
    check_fitted_resolution,
    cost_sampling_step,
)
from .march import march
from .step import SplittingStep

PLAIN_COURANT, PLAIN_MIN_STEPS = 6.0, 50
"""Default Courant number and fewest steps of the plain splitting scheme."""
FITTED_COURANT, FITTED_MIN_STEPS = 7.0, 10
"""The same for the fitted one, against the root-mean-square Courant rate over the nodes rather
than the largest."""


class SplittingScheme(SchemeBase):
    """Semi-Lagrangian splitting (:mod:`gridlbc.schemes.splitting`), with exponential fitting."""

    name = "splitting"
    supports_fitting = True
    step = SplittingStep

    def step_rule(self, settings) -> StepRule:
        """Courant 6 against the largest rate and at least 50 steps (plain), Courant 7 against
        the rate's root mean square and at least 10 (fitted); ``courant`` and ``min_steps`` of
        the settings override."""
        fitted = settings.reference is not None
        return StepRule(
            settings.courant or (FITTED_COURANT if fitted else PLAIN_COURANT),
            "rms" if fitted else "peak",
            settings.min_steps or (FITTED_MIN_STEPS if fitted else PLAIN_MIN_STEPS),
        )

    def step_bound(self, problem: Problem) -> CostSamplingBound:
        """:func:`~.checks.cost_sampling_step`: the step at which the noise still samples the
        state cost."""
        return CostSamplingBound(*cost_sampling_step(problem))

    def march(self, plan: MarchPlan, terminal: Terminal) -> Marched:
        """:func:`.march.march`: plain, fitted to a reference row, or in the log domain."""
        return march(plan, terminal)

    def check(self, solutions: list, marched: Marched) -> None:
        """Plain: the tails (:func:`~gridlbc.schemes.tails.check_resolution`, for the half
        step's diffusion); then the control's step (:func:`~.checks.check_control_step`) and,
        fitted, the resolution of log z (:func:`~.checks.check_fitted_resolution`)."""
        diffusion = marched.operator.diffusion
        fitted = not isinstance(marched.representation, LinearZ)
        if not fitted:
            for solution in solutions:
                check_resolution(
                    solution.problem, solution, 0.5 * solution.diagnostics.dt, diffusion
                )
        for solution in solutions:
            check_control_step(solution.problem, solution)
            if fitted:
                check_fitted_resolution(solution.problem, solution, diffusion)


SPLITTING = SplittingScheme()
"""The splitting scheme (``method="splitting"``, the default)."""
