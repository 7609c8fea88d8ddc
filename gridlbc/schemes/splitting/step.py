"""The splitting's step operator: the parts of one step (:mod:`gridlbc.schemes.splitting`) built
once per solve and composed, plain (:meth:`SplittingStep.__call__`), fitted to a reference
(:meth:`SplittingStep.drift`, :meth:`SplittingStep.fitted_diffusion`) or in the log domain
(:meth:`SplittingStep.log_drift`, :meth:`SplittingStep.log_diffusion`).

The state cost enters by Simpson's rule along the characteristic: C multiplies by
exp(−q Δt/(6λ)) at the nodes (a path's ends) and M by exp(−2 q(m(x)) Δt/(3λ)) at the foot m(x)
of half a step, between the drift and the first half diffusion.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...backends.numba.diffusion import cost_max_kernel
from ...backends.numba.options import work_blocks
from ...grid import Grid
from ...problem import Problem
from ..noise import diffusion_coefficients
from .curvature import CurvatureCorrection
from .diffusion import half_diffusion, max_blocks, noise_axes
from .drift import advect, fitting_kernel
from .feet import Feet, foot
from .fitted_diffusion import fitted_pass


class SplittingStep:
    """The splitting step operator of a problem and time step, built once per solve.

    Call ``step(z, out, scale)``: writes ``out = S(scale · z)`` for ``z`` ``(K, N)`` and the
    per-row factors ``scale`` ``(K,)``, and returns the per-row maximum of ``out``. Its
    ``diffusion`` holds D_k = ½ (λ B R⁻¹ Bᵀ)_kk per axis: a float where it is the same at every
    node, else one value per node; ``noise`` the :class:`~.diffusion.NoiseAxis` of each axis
    the noise acts on; ``feet`` the characteristic feet (:class:`~.feet.Feet`).
    """

    name = "splitting"
    supports_fitting = True

    def __init__(self, problem: Problem, dt: float, feet: str = "compact"):
        grid = problem.require_grid("the splitting")
        if grid.size >= 2**31:
            raise ValueError(f"grid {grid.describe()} has ≥ 2³¹ nodes: int32 indices overflow")
        self.grid = grid
        self.feet = Feet(problem, dt, feet)
        self.diffusion = diffusion_coefficients(problem)  # D_k: a float, or one per node
        self.noise = noise_axes(grid, self.diffusion, 0.5 * dt)
        q = grid.node_values(problem.state_cost_values)
        lam = problem.temperature
        if np.any(q != 0):  # Simpson's rule along the characteristic (module docstring)
            self.log_cost = -q * dt / (6.0 * lam)
            self.log_mid_cost = (-2.0 * dt / (3.0 * lam)) * grid.node_values(
                lambda x: problem.state_cost_values(foot(problem, x, 0.5 * dt))
            )
        else:
            self.log_cost = self.log_mid_cost = np.empty(0)
        self.cost_factor = np.exp(self.log_cost)
        self.mid_cost_factor = np.exp(self.log_mid_cost)
        self._buffers: dict[tuple[int, int], np.ndarray] = {}
        self.curvature_correction = CurvatureCorrection(self.feet)
        """The fitted drift's curvature term at the feet:
        ``curvature_correction(ell, out=None, add_mean=False)``
        (:class:`~.curvature.CurvatureCorrection`)."""
        self.iterations: list[int] = []  # direct tridiagonal solves: no iterations

    @property
    def layout(self) -> str:
        """How the feet are stored (:data:`~.feet.FEET_LAYOUTS`)."""
        return self.feet.layout

    @staticmethod
    def estimate_bytes(grid: Grid, feet: str = "compact") -> int:
        """Memory of the operator for ``grid``, without building it (for the memory check)."""
        return Feet.estimate_bytes(grid, feet) + grid.size * 8

    @property
    def nbytes(self) -> int:
        arrays = [
            *self.feet.arrays,
            self.cost_factor,
            self.log_cost,
            self.mid_cost_factor,
            self.log_mid_cost,
            *(axis.data for axis in self.noise),
            *(axis.variance for axis in self.noise),
            *(a for a in self.diffusion if isinstance(a, np.ndarray)),
        ]
        return int(sum(a.nbytes for a in arrays))

    def __call__(self, z: np.ndarray, out: np.ndarray, scale: np.ndarray) -> np.ndarray:
        """out = C D½ M P D½ C (scale · z), the plain step; ``z`` is consumed (overwritten).
        Returns the row maxima of ``out``. (The fitted operator is composed over all steps by
        :func:`~.march.march_fitted`, from :meth:`drift` and :meth:`fitted_diffusion`.)"""
        K = z.shape[0]
        if self.cost_factor.size:
            z *= self.cost_factor
        self._half_diffusion(z, None)
        self.drift(z, out, scale)
        if self.mid_cost_factor.size:
            out *= self.mid_cost_factor
        blocks = max_blocks(self.grid, self.noise) if self.cost_factor.size == 0 else 0
        if blocks == 0:
            self._half_diffusion(out, None)
            return self.row_maxima(out, cost=True)
        # no state cost: the slice maximum fused into the last (closed-axis) diffusion pass
        block_max = self._buffer(K, blocks)
        self._half_diffusion(out, block_max)
        return block_max.max(axis=1)

    def drift(
        self, z: np.ndarray, out: np.ndarray, scale: np.ndarray, reference: int | None = None
    ):
        """out = P (scale · z): the semi-Lagrangian drift alone, fitted to row ``reference`` of
        ``z`` when it is given (``z`` is then consumed: divided by that row in place). The
        reference row fitted to itself needs no gather of z, only of log φ: P_φ φ = φ̄."""
        ones_row = -1
        if reference is None:
            ell = np.empty(0)
        else:
            ell = self._buffer(1, self.grid.size)[0]  # log φ of the reference
            if fitting_kernel(z, reference, ell) == 0:
                ones_row = reference
        advect(self.feet, z, scale, ell, ones_row, out)
        if reference is not None:
            out *= np.exp(self.curvature_correction(ell))

    def log_drift(self, ell: np.ndarray, out: np.ndarray):
        """out = log M P_z z for ℓ = log z (``(1, N)``, consumed): the drift fitted to z itself,
        in the log domain. That is the value-space semi-Lagrangian update ℓ(x) ← Σ_j w_j ℓ(y_j)
        with the curvature term, then the middle share of the state cost (Simpson's rule)."""
        self.curvature_correction(ell[0], out[0], add_mean=True)
        if self.log_mid_cost.size:
            out[0] += self.log_mid_cost

    def log_diffusion(
        self, ell: np.ndarray, spares: Sequence[np.ndarray], full: bool = False
    ) -> np.ndarray:
        """log D z for ℓ = log z (``(1, N)``, not written): the diffusion fitted to z itself,
        log ∫ G_σ e^ℓ̄ along each noise axis in turn, over half a step (σ² = 2 D_k Δt/2) or,
        with ``full``, a whole one (σ² = 2 D_k Δt: two half steps in one pass, the Gaussian's
        semigroup). The passes alternate between the two arrays ``spares``; returns the one that
        holds the result."""
        source = ell
        for position, noise in enumerate(self.noise):
            target = spares[position % 2]
            fitted_pass(self.grid, noise, source, source[0], full, True, target)
            source = target
        return source

    def fitted_diffusion(
        self, z: np.ndarray, spare: np.ndarray, reference: int, full: bool = False
    ) -> np.ndarray:
        """D fitted to row ``reference`` (:mod:`~.fitted_diffusion`) over half a step or, with
        ``full``, a whole one (as :meth:`log_diffusion`), one noise axis at a time, alternating
        between ``z`` and ``spare`` (both are overwritten). Returns the array that holds the
        result: ``spare`` after an odd number of noise axes, ``z`` after an even one."""
        source, target = z, spare
        ell = self._buffer(1, self.grid.size)[0]
        for noise in self.noise:
            fitting_kernel(source, reference, ell)
            fitted_pass(self.grid, noise, source, ell, full, False, target)
            source, target = target, source
        return source

    def row_maxima(self, z: np.ndarray, cost: bool = False) -> np.ndarray:
        """The row maxima of ``z`` ``(K, N)``, after multiplying it by the nodes' share of the
        state cost C when ``cost`` (one pass)."""
        block_max = self._buffer(z.shape[0], work_blocks(self.grid.size))
        cost_max_kernel(z, self.cost_factor if cost else self.cost_factor[:0], block_max)
        return block_max.max(axis=1)

    def _half_diffusion(self, z: np.ndarray, block_max: np.ndarray | None):
        """D½ in place on every noise axis (:func:`~.diffusion.half_diffusion`)."""
        half_diffusion(self.grid, self.noise, z, block_max)

    def _buffer(self, rows: int, columns: int) -> np.ndarray:
        """A scratch array of this shape, allocated (zeroed) once and reused by later steps."""
        key = (rows, columns)
        if key not in self._buffers:
            self._buffers[key] = np.zeros(key)
        return self._buffers[key]
