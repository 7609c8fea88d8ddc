"""The plain operator's tails: where the implicit diffusion, not the PDE, sets the value.

Both schemes diffuse by backward Euler along each noise axis, (1 + 2r) z_i − r (z_{i−1} + z_{i+1})
= b with r = Δt D_k / h_k² (the splitting over each half step, the implicit scheme over the
whole step), and the inverse of that operator decays geometrically from a node, by a factor ρ(r)
per cell. However fast the true z falls, the computed one falls by at most that factor: v/λ can
rise by at most log(1/ρ) per cell. :func:`check_resolution` warns where the solution sits at that
cap.
"""

from __future__ import annotations

import numpy as np

from ..errors import ResolutionWarning, warn_user
from ..grid import flat_chunks
from ..problem import Problem
from ..solution import Solution
from .noise import diffusion_coefficients

TAIL_SHARE = 0.01
"""A plain solve warns when more than this share of the nodes sit at its diffusion's tail cap."""


def diffusion_tail_cap(ratio: np.ndarray) -> np.ndarray:
    """log(1/ρ) per cell of the implicit diffusion (1 + 2r) z_i − r (z_{i−1} + z_{i+1}) = b:
    its inverse decays like ρ^k, ρ = ((1 + 2r) − √(1 + 4r)) / (2r), so however fast the true
    desirability falls, the computed one falls by at most this factor of e per cell."""
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = ((1 + 2 * ratio) - np.sqrt(1 + 4 * ratio)) / (2 * ratio)
        return np.where(ratio > 0, -np.log(rho), np.inf)


def check_resolution(
    problem: Problem, solution: Solution, step: float, diffusion: list | None = None
) -> float:
    """Warn (:class:`ResolutionWarning`) when the plain operator's z tails, not the PDE, set the
    value: the share of nodes where v/λ at t = T (the terminal cost) or t = 0 rises from a node to its
    neighbour along a noise axis by at least 0.9 of the diffusion's tail cap
    (:func:`diffusion_tail_cap`, for r = ``step`` D_k / h_k², ``step`` the diffusion's time step).
    The scheme cannot carry such a fall of z: it fills it with its own tails, so v is
    underestimated, more so as λ falls. ``diffusion``: the D_k of the problem if already evaluated
    (e.g. :attr:`gridlbc.schemes.splitting.SplittingStep.diffusion`). Returns that share."""
    grid = problem.require_grid("check_resolution()")
    flagged, worst = 0, (0.0, 0.0, "")
    if diffusion is None:
        diffusion = diffusion_coefficients(problem)
    for value in (grid.node_values(problem.terminal_values), solution.value_nodes(0)):
        flagged, worst = count_at_cap(problem, value, step, flagged, worst, diffusion)
    share = flagged / (2 * grid.size)
    if share > TAIL_SHARE:
        warn_user(
            f"the plain scheme cannot resolve this problem's desirability: at {100 * share:.0f} % "
            f"of the nodes v/λ rises from node to node faster than its diffusion's tails allow "
            f"(up to {worst[0]:.3g} per cell along {worst[2]}, where the tails cap it at "
            f"{worst[1]:.3g}), so v is underestimated there, increasingly as λ falls. "
            + (
                "Refine that axis, or raise the temperature (a task with an exit set and a "
                "horizon has no fitted scheme)."
                if problem.exit is not None
                else "Solve with fitting='terminal' (exact tails), or refine that axis, or raise "
                "the temperature."
            ),
            ResolutionWarning,
        )
    return share


def count_at_cap(
    problem: Problem, value: np.ndarray, step: float, flagged: int, worst, diffusion: list
):
    """Add to ``flagged`` the nodes whose v/λ rises to a noise-axis neighbour by ≥ 0.9 of the tail
    cap, and keep the worst (rise, cap, axis) seen (``diffusion``: the D_k of
    :func:`gridlbc.schemes.noise.diffusion_coefficients`)."""
    grid, lam = problem.require_grid("count_at_cap()"), problem.temperature
    for flat in flat_chunks(grid.size):
        index = np.stack(np.unravel_index(flat, grid.shape), axis=1)
        hit = np.zeros(flat.size, dtype=bool)
        for k, ax in enumerate(grid.axes):
            coefficient = (
                np.full(flat.size, diffusion[k])
                if np.ndim(diffusion[k]) == 0
                else diffusion[k][flat]
            )
            if not np.any(coefficient > 0):
                continue
            nxt = index.copy()
            nxt[:, k] += 1
            inside = nxt[:, k] < ax.n
            if ax.periodic:
                nxt[:, k] %= ax.n
                inside[:] = True
            neighbour = np.ravel_multi_index(
                tuple(np.minimum(nxt, np.array(grid.shape) - 1).T), grid.shape
            )
            with np.errstate(invalid="ignore"):  # +inf where one side underflowed, NaN both
                rise = np.abs(value[neighbour] - value[flat]) / lam
            cap = diffusion_tail_cap(step * coefficient / ax.spacing**2)
            at_cap = inside & ~np.isnan(rise) & (rise >= 0.9 * cap)
            hit |= at_cap
            if np.any(at_cap):
                i = np.argmax(np.where(at_cap, rise, -1.0))
                if rise[i] > worst[0]:
                    worst = (float(rise[i]), float(cap[i]), ax.name or f"axis {k}")
        flagged += int(hit.sum())
    return flagged, worst
