"""Step schemes for the backward time stepping of the desirability z (README, "The maths in brief").

Every scheme is a *step operator* S with z(·, t − Δt) = S z(·, t), linear in z and monotone
(z ≥ 0 and a discrete maximum principle), so the discrete problem is itself a linearly solvable
Markov chain and superposition holds to rounding. :class:`StepOperator` writes the contract the
solver relies on; :data:`METHODS` names the schemes.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from ..grid import Grid
from .implicit import LINEAR_SOLVERS, ImplicitStep
from .splitting import SplittingStep


@runtime_checkable
class StepOperator(Protocol):
    """One backward step of the linear Bellman PDE on a fixed grid and time step.

    Built as ``Scheme(problem, dt, **options)``; then for K right-hand sides at once,

        peak = step(z, out, scale)      out[r] = S (scale[r] · z[r]),  r < K

    with ``z`` and ``out`` float64 arrays of shape (K, N) (``z`` may be overwritten) and
    ``peak[r] = max out[r]`` (the solver renormalises with it). A scheme that supports
    exponential fitting (:attr:`supports_fitting`, the splitting) also offers the fitted
    operator's parts, which the solver composes over all steps (:mod:`gridlbc.solver`).
    """

    supports_fitting: bool
    iterations: list[int]
    """Per-step iteration counts of an iterative linear solver (empty for direct schemes)."""

    @property
    def nbytes(self) -> int:
        """Memory held by the operator."""

    @staticmethod
    def estimate_bytes(grid: Grid) -> int:
        """Memory the operator will hold on ``grid``, without building it."""

    def __call__(self, z: np.ndarray, out: np.ndarray, scale: np.ndarray) -> np.ndarray: ...


METHODS: dict[str, type[StepOperator]] = {"splitting": SplittingStep, "implicit": ImplicitStep}
"""Step schemes by name; both are linear in z and monotone (z ≥ 0, discrete maximum principle).

- ``"splitting"`` (default): semi-Lagrangian drift + implicit tridiagonal diffusion + exact cost
  (:mod:`gridlbc.schemes.splitting`). Error O(h²/Δt + Δt); unconditionally stable; O(N) work per
  step with parallel, allocation-free kernels and compact feet. Exactly linear (superposition to
  rounding); supports exponential fitting of the drift.
- ``"implicit"``: upwind + backward Euler, error O(h + Δt) (:mod:`gridlbc.schemes.implicit`), the
  reference. Its linear system is solved by sparse LU on small 2D grids (exact to rounding) and
  by Gauss–Seidel sweeps otherwise (non-negative iterates, stopped at a max-norm change of
  ``1e-10`` of max z: linear and monotone up to that tolerance); ``linear_solver`` overrides.
"""

__all__ = ["LINEAR_SOLVERS", "METHODS", "ImplicitStep", "SplittingStep", "StepOperator"]
