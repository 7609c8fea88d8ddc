"""The fitted diffusion of the splitting.

With a reference, the half-step diffusion along each noise axis is fitted too:

    (D_φ z)(x) = ∫ G_σ(x − x') φ̄(x') ȳ(x') dx',    y = z/φ,    σ² = λ (B R⁻¹ Bᵀ)_kk Δt/2,

with ȳ the piecewise-linear interpolant of y, log φ̄ on each cell the quadratic through its two
nodes with the cell's mean second difference, and the line continued by wrapping (periodic) or
mirroring (closed, the reflecting constraint); each cell's integral is closed-form (erf). For a
fixed φ this is again linear and non-negative and exact where z ∝ φ (for a Gaussian φ exactly
the heat kernel's result). Its tails are Gaussian, so moving k cells costs the control's true
(kh)²/(2 (B R⁻¹ Bᵀ)_kk Δt/2) at any λ; the tridiagonal solve's tails decay only geometrically,
which caps the rise of −λ log z per cell at λ log(1/ρ), a cap that vanishes with λ. The solver
composes the fitted operator over all steps (:func:`.march.march_fitted`): without a
state cost the half diffusions that meet between steps are taken as one over the whole step
(``full=True``: σ² doubled, the Gaussian semigroup), which halves this, the fitted step's most
expensive part. A single solve fitted to itself runs in the log domain
(:meth:`SplittingStep.log_drift`, :meth:`SplittingStep.log_diffusion`).
"""

from __future__ import annotations

import numpy as np

from ...backends.numba.fitted_diffusion import diffuse_fitted_kernel
from ...grid import Grid
from .diffusion import NoiseAxis


def fitted_pass(
    grid: Grid,
    noise: NoiseAxis,
    source: np.ndarray,
    ell: np.ndarray,
    full: bool,
    log_out: bool,
    target: np.ndarray,
):
    """One noise axis of the fitted diffusion of ``source`` with log φ = ``ell``, into
    ``target``, over half a step or, with ``full``, a whole one (σ² doubled); with ``log_out``,
    the reference alone in the log domain
    (:func:`~gridlbc.backends.numba.fitted_diffusion.diffuse_fitted_kernel`)."""
    ax, stride = grid.axes[noise.axis], int(grid.strides[noise.axis])
    diffuse_fitted_kernel(
        source,
        ell,
        float(ell.max()),
        noise.variance * (2.0 if full else 1.0),
        ax.spacing,
        ax.n,
        stride,
        noise.periodic,
        log_out,
        target,
    )
