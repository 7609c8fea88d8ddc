"""The time loop of a linear step operator, and the pieces the schemes' own loops share.

From the terminal data z_T = Z e^ℓ the operator S is applied n times, z_n = S z_{n+1}, each slice
renormalised lazily: the next step and the storage multiply by 1/peak, and ℓ += log peak, so that
no slice underflows as a whole and the map stays linear in z_T (:mod:`gridlbc.solver`).
"""

from __future__ import annotations

import math

import numpy as np

from ..backends import REFERENCE_FLOOR
from ..backends.numba.options import work_blocks
from ..representation import LinearZ
from ..storage import store_kernel
from .protocol import Marched, MarchPlan, StepOperator, Terminal


def check_peak(peak: np.ndarray, t: float):
    """A clear error when a slice's maximum is zero or not finite (``peak`` per row, at ``t``)."""
    if not np.all(peak > 0) or not np.all(np.isfinite(peak)):
        raise FloatingPointError(
            f"desirability vanished or overflowed everywhere at t = {t:g}: the costs are "
            "too large for this temperature (rescale them or raise the temperature)"
        )


def open_slices(plan: MarchPlan, terminal: Terminal):
    """The slice storage of a linear march, ``(K, len(kept), N)``, with the terminal slice
    stored, and the log-scales ``(len(kept), K)``. Returns ``(slices, scales, blocks,
    flushed)``, ``blocks`` the work blocks of :func:`~gridlbc.storage.store_kernel` and
    ``flushed`` the values it flushed to zero."""
    K, N = terminal.count, plan.problem.require_grid("solve").size
    slices = plan.storage(K, len(plan.kept), N)
    scales = np.empty((len(plan.kept), K))
    blocks = np.zeros(work_blocks(N), dtype=np.int64)
    flushed = store_kernel(terminal.values[:K], np.ones(K), slices[:, -1], blocks)
    scales[-1] = terminal.log_scale[:K]
    return slices, scales, blocks, flushed


def underflow_nodes(slices: np.ndarray) -> tuple[int, ...]:
    """Per solution, the nodes whose stored z is zero at t = 0 (their value is +∞)."""
    return tuple(int(np.count_nonzero(rows[0] <= 0)) for rows in slices)


def march_linear(
    plan: MarchPlan, terminal: Terminal, step: StepOperator, label: str, setup_time: float
) -> Marched:
    """Apply ``step`` n times from the terminal data (plain: no reference), storing the kept
    slices; ``label`` names the run on the progress bar."""
    slices, scales, blocks, flushed = open_slices(plan, terminal)
    Z, log_scale, kept, K = terminal.values, terminal.log_scale, plan.kept, terminal.count
    progress = plan.progress_bar(label)
    buffer = np.empty_like(Z)
    scale = np.ones(Z.shape[0])
    slot = len(kept) - 1
    for n in range(kept[-1] - 1, -1, -1):  # step n+1 → n, t_n = n Δt
        peak = step(Z, buffer, scale)  # buffer = S(scale · Z), its row maxima
        Z, buffer = buffer, Z
        check_peak(peak, n * plan.dt)
        log_scale = log_scale + np.log(peak)
        scale = 1.0 / peak
        if n == kept[slot - 1]:
            slot -= 1
            flushed += store_kernel(Z[:K], scale[:K], slices[:, slot], blocks)
            scales[slot] = log_scale[:K]
        progress.update(kept[-1] - n)
    return Marched(
        slices, scales, LinearZ(), step, setup_time, underflow_nodes(slices), int(flushed)
    )


def store_reference(phi: np.ndarray, log_scale: float | np.floating, log_phi, slot: int):
    """Slot ``slot`` of ``log_phi`` (a :class:`~gridlbc.representation.RelativeZ`): log φ
    relative to its maximum (floored where φ underflowed) and its log-scale, for
    φ = ``phi`` · e^{log_scale}."""
    top = float(phi.max())
    with np.errstate(divide="ignore"):
        np.log(
            np.maximum(phi / top, REFERENCE_FLOOR), out=log_phi.log_slices[slot], casting="unsafe"
        )
    log_phi.log_scales[slot] = log_scale + math.log(top)
