"""The splitting's checks of a solve: what its step and grid cannot resolve, said as a
:class:`~gridlbc.solution.ResolutionWarning` with what to change.

- :func:`cost_sampling_step`: the splitting samples the state cost at three points of a path per
  step (Simpson's rule), so one step's noise must not carry a path across the distance over
  which the cost rises; the default step is held below this (:class:`CostSamplingBound`).
- :func:`check_control_step`: the control and the drift are taken one after the other, so the
  optimal control must not move the state by many cells per step.
- :func:`check_fitted_resolution`: the fitted diffusion models log z by a quadratic per cell,
  which needs its curvature resolved.
- The plain operator's tails (:func:`gridlbc.schemes.tails.check_resolution`), shared with the
  implicit scheme.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ...errors import ResolutionWarning, warn_user
from ...problem import Problem
from ...solution import Solution
from ..noise import diffusion_coefficients
from ..protocol import StepBound

COST_NOISE_SCALE = 0.5
"""A splitting solve with a state cost warns when one step's noise moves a path by more than this
fraction of the state cost's length scale along some noise axis."""


_LOG_LARGEST = math.log(np.finfo(float).max) - 1.0


def cost_sampling_step(problem: Problem) -> tuple[float, str]:
    """The largest Δt at which one step's noise, √(2 D_k Δt), moves a path no more than
    :data:`COST_NOISE_SCALE` of the distance ℓ_k = (max q − min q) / max |∂_k q| over which the
    state cost rises (from the nodes), along every noise axis k; and the axis that sets it
    (∞ and "" without a state cost or noise). The splitting takes ∫ q dt over a step at three
    points of a path (Simpson's rule along the characteristic), so a longer step steps over a
    steep cost (a wall, a narrow well): the default step is held below this."""
    if problem.state_cost is None:
        return math.inf, ""
    grid = problem.require_grid("cost_sampling_step()")
    q = grid.reshape(grid.node_values(problem.state_cost_values))
    span = float(q.max() - q.min())
    limit, axis = math.inf, ""
    if span <= 0.0:
        return limit, axis
    for k, (ax, coefficient) in enumerate(
        zip(grid.axes, diffusion_coefficients(problem), strict=True)
    ):
        largest = float(np.max(coefficient))
        if largest <= 0.0:
            continue
        wrapped = np.concatenate([q, q.take([0], axis=k)], axis=k) if ax.periodic else q
        rise = float(np.abs(np.diff(wrapped, axis=k)).max())
        if rise <= 0.0:  # q does not change along this axis: no limit from it
            continue
        # ℓ = span·h / rise and the step (c ℓ)² / (2 D), in logs: a rise far below the span (a
        # cost all but independent of this axis) is a step beyond any horizon, not an overflow
        log_step = 2.0 * (
            math.log(COST_NOISE_SCALE) + math.log(span) + math.log(ax.spacing) - math.log(rise)
        ) - math.log(2.0 * largest)
        step = math.exp(log_step) if log_step < _LOG_LARGEST else math.inf
        if step < limit:
            limit, axis = step, ax.name or f"axis {k}"
    return limit, axis


@dataclass(frozen=True)
class CostSamplingBound(StepBound):
    """:func:`cost_sampling_step` as the splitting's :class:`~gridlbc.schemes.protocol.StepBound`:
    ``limit`` the step, ``reason`` the axis that sets it; :meth:`check` warns about a given step
    above it."""

    def check(self, dt: float) -> None:
        """The :class:`ResolutionWarning` for a given ``dt`` above the limit."""
        if dt <= self.limit * (1.0 + 1e-9):  # the default step is held below it
            return
        warn_user(
            f"with Δt = {dt:.3g} one step's noise moves a path "
            f"{COST_NOISE_SCALE * math.sqrt(dt / self.limit):.2f} of the distance over which the "
            f"state cost rises (along {self.reason}), and the splitting samples that cost at three "
            "points per step: it steps over a steep cost (a wall, a narrow well), and v and the "
            f"policy can be far off. Pass dt ≤ {self.limit:.3g} (or leave dt to the default) and "
            "check with gridlbc.certify.",
            ResolutionWarning,
        )


CONTROL_STEP_CELLS = 30.0
"""A splitting solve warns when the optimal control moves the state by more than this many cells
of some axis per step (root mean square over the better half of the nodes at t = 0)."""
_CONTROL_SAMPLE = 20_000  # nodes at which check_control_step evaluates the policy


def check_control_step(problem: Problem, solution: Solution) -> float:
    """Warn (:class:`ResolutionWarning`) when the optimal control moves the state by many cells
    per step: the root mean square over the nodes whose value at t = 0 is finite and at most
    the median (at most ``_CONTROL_SAMPLE`` nodes read, evenly spaced) of
    max_k |(B u*)_k| Δt / h_k is above :data:`CONTROL_STEP_CELLS`. The splitting applies the
    control (its diffusion) and the drift one after the other; its error is of order Δt², but
    with a cheap control (small R) that jumps the state across much of the grid in one step it
    is several percent (Pendulum-v1; docs/schemes.rst). The step it suggests aims at two thirds
    of the threshold, since u* itself changes with the step. Returns that root mean square.

    Why the better half: it is where the controlled process spends its time, and far up the
    value a component solved with a reference fitted to several goals (:func:`gridlbc.solve_many`)
    holds its z at the precision floor, where its gradient is noise and the rate read over every
    node is absurd, where over the better half it is not (stranger round 21's components at
    λ = 0.08: docs page :doc:`benchmarks`)."""
    grid, dt = problem.require_grid("check_control_step()"), solution.diagnostics.dt
    read = np.arange(0, grid.size, max(1, grid.size // _CONTROL_SAMPLE))
    x = grid.node_coordinates(read[solution.better_half()[read]])
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an underflowed policy (NaN) is the caller's to hear of
        u = solution.policy(x, 0.0)
    moved = np.abs(np.einsum("nim,nm->ni", problem.input_matrix(x), u)) * dt
    cells = moved / np.asarray(grid.spacing, dtype=float)
    largest = cells.max(axis=1)
    largest = largest[np.isfinite(largest)]
    rms = float(np.sqrt(np.mean(largest**2))) if largest.size else 0.0
    if rms > CONTROL_STEP_CELLS:
        k = int(np.argmax(np.nanmean(cells**2, axis=0)))
        axis = grid.axes[k].name or f"axis {k}"
        warn_user(
            f"the optimal control moves the state by {rms:.0f} cells per step (root mean square "
            f"over the better half of the nodes at t = 0, mostly along {axis}): the splitting "
            "takes the control and the drift one after the other, and at such steps v and the "
            "policy can be several percent off (its error falls as Δt²). Pass dt ≤ "
            f"{dt * CONTROL_STEP_CELLS / (1.5 * rms):.3g} and compare.",
            ResolutionWarning,
        )
    return rms


FIT_CURVATURE_JUMP = 0.6
"""A fitted solve warns when the second difference of log z along a noise axis changes from one
node to the next by more than this fraction of itself (median over the cells that matter)."""
_FIT_RELEVANT = 20.0  # cells whose log z is within this of the largest at t = 0 are judged


def check_fitted_resolution(problem: Problem, solution: Solution, diffusion: list) -> float:
    """Warn (:class:`ResolutionWarning`) when the grid does not resolve the curvature of
    ℓ = log z along a noise axis, which the fitted diffusion models by a quadratic per cell:
    the median, over the cells whose ℓ at t = 0 is within ``_FIT_RELEVANT`` of its largest
    value, of |κ_{i+1} − κ_i| / (|κ_i + κ_{i+1}|/2 + 1), κ_i = ℓ_{i−1} − 2ℓ_i + ℓ_{i+1}, is
    above :data:`FIT_CURVATURE_JUMP` on some axis. A smooth ℓ keeps it near h|ℓ‴|/|ℓ″|, far
    below one; where it is of order one the quadratics bulge between nodes, and the value is
    off by far more than the scheme's order suggests and moves with Δt (docs/schemes.rst, for the
    calibration). ``diffusion``: the D_k per axis. Returns the largest median."""
    grid = problem.require_grid("check_fitted_resolution()")
    ell = -solution.value_nodes(0) / problem.temperature
    finite = np.isfinite(ell)
    top = float(ell[finite].max()) if finite.any() else 0.0
    worst, worst_axis = 0.0, ""
    for k, (ax, coefficient) in enumerate(zip(grid.axes, diffusion, strict=True)):
        if ax.n < 4 or not np.any(np.asarray(coefficient) > 0):
            continue
        lines = np.moveaxis(grid.reshape(ell), k, -1).reshape(-1, ax.n)
        with np.errstate(invalid="ignore"):  # −inf − (−inf) where z underflowed: not judged
            kappa = lines[:, :-2] - 2.0 * lines[:, 1:-1] + lines[:, 2:]
            jump = np.abs(np.diff(kappa, axis=1)) / (0.5 * np.abs(kappa[:, 1:] + kappa[:, :-1]) + 1)
            judged = (lines[:, 2:-1] >= top - _FIT_RELEVANT) & np.isfinite(jump)
        if np.any(judged):
            median = float(np.median(jump[judged]))
            if median > worst:
                worst, worst_axis = median, ax.name or f"axis {k}"
    if worst > FIT_CURVATURE_JUMP:
        warn_user(
            f"the grid does not resolve the curvature of log z along {worst_axis}: its second "
            f"difference changes by {worst:.2f} of itself from node to node (median over the "
            f"nodes that carry the solution, at t = 0; resolved grids stay well below "
            f"{FIT_CURVATURE_JUMP}). The fitted diffusion's quadratics then bulge between nodes, "
            "and v can be off by tens of percent and move with dt. Refine that axis (or the "
            "grid), or raise the temperature, and compare.",
            ResolutionWarning,
        )
    return worst
