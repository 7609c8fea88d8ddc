"""The diffusion coefficients D_k = ½ (λ B R⁻¹ Bᵀ)_kk of a problem's axes, which both schemes
diffuse along (the noise must be diagonal in the grid's axes: :meth:`gridlbc.Problem.noise_diagonal`).
"""

from __future__ import annotations

import numpy as np

from ..grid import flat_chunks
from ..problem import Problem


def diffusion_coefficients(problem: Problem) -> list[float | np.ndarray]:
    """D_k = ½ (λ B R⁻¹ Bᵀ)_kk of every axis k, the noise evaluated once per chunk of nodes: a
    float where D_k is the same at every node (no per-node array is then stored), else the
    ``(N,)`` array."""
    grid = problem.require_grid("diffusion_coefficients()")
    first: np.ndarray | None = None
    columns: list[np.ndarray | None] = [None] * grid.ndim
    for flat in flat_chunks(grid.size):
        diffusion = 0.5 * problem.noise_diagonal(grid.node_coordinates(flat))
        if first is None:
            first = diffusion[0].copy()
        for k in range(grid.ndim):
            column = columns[k]
            if column is None:
                if np.all(diffusion[:, k] == first[k]):
                    continue
                # varies: the chunks before held the first value throughout
                column = columns[k] = np.full(grid.size, first[k])
            column[flat[0] : flat[-1] + 1] = diffusion[:, k]
    assert first is not None, "a grid has at least one node"
    return [float(first[k]) if column is None else column for k, column in enumerate(columns)]
