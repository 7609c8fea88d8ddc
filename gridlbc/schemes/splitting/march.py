"""The splitting's time loops: plain (:func:`gridlbc.schemes.march.march_linear`), fitted to a
reference row (:func:`march_fitted`) and fitted to a single terminal cost itself, in the log
domain (:func:`march_log`).
"""

from __future__ import annotations

import numpy as np

from ...representation import LogZ, RelativeZ
from ...storage import store_kernel
from ..march import check_peak, march_linear, open_slices, store_reference, underflow_nodes
from ..protocol import Marched, MarchPlan, Terminal
from .step import SplittingStep


def march(plan: MarchPlan, terminal: Terminal) -> Marched:
    """The splitting's loop for ``terminal``: in the log domain when it is a single cost fitted
    to itself, fitted to its reference row when it has one, else plain."""
    step = SplittingStep(plan.problem, plan.dt)
    setup_time = plan.elapsed()
    if terminal.log:
        return march_log(plan, terminal, step, setup_time)
    if terminal.reference is None:
        return march_linear(plan, terminal, step, "splitting", setup_time)
    return march_fitted(plan, terminal, step, setup_time)


def march_fitted(
    plan: MarchPlan, terminal: Terminal, step: SplittingStep, setup_time: float
) -> Marched:
    """n steps of C D½ M P D½ C (:class:`SplittingStep`; P fitted by
    :meth:`SplittingStep.drift`, D½ by :meth:`SplittingStep.fitted_diffusion`) fitted to the
    reference row of the terminal data; its log φ is stored at the kept times as well
    (:class:`~gridlbc.representation.RelativeZ`, the solutions' representation).

    Without a state cost (C = M = 1) the two half diffusions that meet between consecutive
    steps are one diffusion over the whole step: the Gaussian's semigroup, D½ D½ = D, which the
    fitted diffusion keeps exactly where z ∝ φ with a quadratic log φ (elsewhere the two differ
    by the interpolation half way, which the whole step skips). So n steps take n − 1 whole
    diffusions and two halves, about half the fitted diffusion's work,

        z_0 = D½ P (D P)ⁿ⁻¹ D½ z_T.

    A slice t_k (0 < k < n) then lies half way through a whole diffusion; it is stored as
    ½(y + D y), y = P …, the desirability before and after it, which is D½ y to O(Δt²) and a
    linear, non-negative function of z_T like every slice. With a state cost the two halves
    stay apart, so that the cost between them is taken half way through the diffusion, where
    Simpson's rule along the path wants it (merged, a steep cost would be sampled at the
    diffusion's ends)."""
    Z, log_scale, reference, K = (
        terminal.values,
        terminal.log_scale,
        terminal.reference,
        terminal.count,
    )
    kept = plan.kept
    assert reference is not None  # march() takes the plain loop without one
    slices, scales, blocks, flushed = open_slices(plan, terminal)
    progress = plan.progress_bar("splitting")
    log_phi = RelativeZ(
        plan.storage(len(kept), plan.problem.require_grid("solve").size), np.empty(len(kept))
    )  # log φ at the stored times, shared by the solutions: they are evaluated relative to it
    store_reference(Z[reference], log_scale[reference], log_phi, -1)
    merge = step.cost_factor.size == 0
    if not merge:
        Z *= step.cost_factor
    x = step.fitted_diffusion(Z, np.empty_like(Z), reference)  # D½ C z_T
    free = [np.empty_like(Z), Z if x is not Z else np.empty_like(Z)]
    scale = np.ones(Z.shape[0])
    slot = len(kept) - 1
    for n in range(kept[-1] - 1, -1, -1):
        y, other = free
        step.drift(x, y, scale, reference)  # y = MP x (x is consumed)
        if step.mid_cost_factor.size:
            y *= step.mid_cost_factor
        storing = n == kept[slot - 1]
        whole = merge and n > 0
        if whole and storing:
            np.copyto(x, y)
        result = step.fitted_diffusion(y, other, reference, full=whole)
        peak = step.row_maxima(result, cost=not merge)  # and result *= C
        check_peak(peak, n * plan.dt)
        if storing:
            slot -= 1
            stored, top = result, peak
            if whole:  # ½(y + D y)
                stored = x
                stored += result
                stored *= 0.5
                top = step.row_maxima(stored)
            flushed += store_kernel(stored[:K], 1.0 / top[:K], slices[:, slot], blocks)
            scales[slot] = log_scale[:K] + np.log(top[:K])
            store_reference(stored[reference], log_scale[reference], log_phi, slot)
        log_scale = log_scale + np.log(peak)
        scale = 1.0 / peak
        if n > 0 and not merge:  # the next step opens with its own D½ C (x is free)
            result *= step.cost_factor
            result = step.fitted_diffusion(result, x, reference)
        free = [a for a in (x, y, other) if a is not result]
        x = result
        progress.update(kept[-1] - n)
    return Marched(slices, scales, log_phi, step, setup_time, underflow_nodes(slices), int(flushed))


def march_log(
    plan: MarchPlan, terminal: Terminal, step: SplittingStep, setup_time: float
) -> Marched:
    """A single terminal cost fitted to itself, stepped in the log domain from ℓ = log Z.

    ℓ = log z is advanced by the same composition as :func:`march_fitted` (whole diffusions
    between the steps when there is no state cost), with the parts in the log domain
    (:meth:`SplittingStep.log_drift`, :meth:`SplittingStep.log_diffusion`; the state cost C an
    addition). A slice inside a merged step is the mean ½(y + D y) of log z before and after
    its diffusion, not of z as in :func:`march_fitted` (nothing need be linear here: the
    operator depends on z itself); it is D½ y to O(Δt²) as well, and its policy is the better
    one. So a solution fitted to itself agrees with one fitted to the same cost explicitly
    (``fitting=g``) at t = 0 and T to rounding, and at the slices between only to O(Δt²) where
    the halves are merged: :func:`gridlbc.combine` does not combine the two exactly.

    The slices are stored as log z relative to their maximum (:class:`LogZ`: the
    solution then interpolates v = −λ log z, not z), so that neither the solve nor the stored
    solution underflows however large v/λ grows across the grid.
    """
    ell, log_scale, kept = terminal.values, float(terminal.log_scale[0]), plan.kept
    cost = step.log_cost[None, :] if step.log_cost.size else None  # C: log z += cost
    slices = plan.storage(1, len(kept), plan.problem.require_grid("solve").size)
    scales = np.empty((len(kept), 1))
    slot = len(kept) - 1
    slices[0, slot], scales[slot, 0] = ell[0], log_scale
    spares = (np.empty_like(ell), np.empty_like(ell))
    if cost is not None:
        ell += cost
    x = step.log_diffusion(ell, spares)  # D½ C ℓ_T
    free = [a for a in (ell, *spares) if a is not x]
    progress = plan.progress_bar("fitted")
    for n in range(plan.steps - 1, -1, -1):
        y, other = free
        step.log_drift(x, y)  # y = MP x
        whole = cost is None and n > 0  # merged with the next step's D½ (march_fitted)
        result = step.log_diffusion(y, (x, other), full=whole)
        if cost is not None:
            result += cost
        peak = float(result.max())
        if n == kept[slot - 1]:
            slot -= 1
            stored, top = result, peak
            if whole:  # ½(y + D y): half way through the whole diffusion, in log z
                stored = x if result is other else other
                np.add(y, result, out=stored)
                stored *= 0.5
                top = float(stored.max())
            np.subtract(stored[0], top, out=slices[0, slot])
            scales[slot, 0] = log_scale + top
        result -= peak
        log_scale += peak
        if n > 0 and cost is not None:  # the next step opens with its own D½ C
            result += cost
            result = step.log_diffusion(result, [a for a in (x, y, other) if a is not result])
        free = [a for a in (x, y, other) if a is not result]
        x = result
        progress.update(plan.steps - n)
    return Marched(slices, scales, LogZ(), step, setup_time, (0,))
