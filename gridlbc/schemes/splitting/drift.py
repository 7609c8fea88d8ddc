"""The drift P of the splitting: semi-Lagrangian transport along the characteristics,

    (P z)(x) = z(X(x)) ≈ Σ_j w_j z(y_j),

over the vertices y_j and weights w_j of the foot X's simplex (:mod:`.feet`).

Exponential fitting (``fitting=`` in :func:`gridlbc.solve`). Barycentric interpolation is exact
for affine z, but z = e^{−v/λ} is exponential wherever v is steep (a swing-up's terminal bowl
rises by several λ per cell), and interpolating it linearly *is* the numerical diffusion that
makes the plain scheme optimistic. The fitted drift interpolates relative to a reference
desirability φ > 0 instead:

    (P_φ z)(x) = Σ_j w_j c_j z(y_j),    c_j = φ̄(X) / φ(y_j),    φ̄(X) = exp(Σ_i w_i log φ(y_i)),

over the vertices y_j of the foot X's simplex. It is exact wherever z ∝ φ across the simplex,
for instance for log-affine z when φ is log-affine there. The factors c_j depend on φ alone, so
for a fixed φ the step is linear in z and non-negative; its weights sum to Σ_j w_j c_j ≥ 1
(Jensen), so it is the transition of a linearly solvable Markov chain with an extra state reward
λ log(Σ_j w_j c_j)/Δt: the correction that cancels the interpolation's diffusion when z ∝ φ. The
reference is itself advanced by the fitted step, as one more right-hand side (fitted to itself,
P_φ φ = φ̄: v(x) ← Σ_j w_j v(y_j), the value-space semi-Lagrangian update). A problem fitted to
its own terminal cost therefore has the accuracy of interpolating v rather than z, and all
terminal costs solved with the same reference share one linear operator, so superposition stays
exact among them (docs/schemes.rst compares the two on the swing-up).
"""

from __future__ import annotations

import numpy as np

from ...backends.numba.drift import advect_compact_kernel, advect_table_kernel, fitting_kernel
from .feet import Feet

__all__ = ["advect", "fitting_kernel"]


def advect(
    feet: Feet,
    z: np.ndarray,
    scale: np.ndarray,
    ell: np.ndarray,
    ones_row: int,
    out: np.ndarray,
):
    """out[r] = scale[r] · F · Σ_j w_j z[r, y_j] at every node's foot, F = exp(Σ_j w_j ell[y_j])
    the reference's geometric mean over the simplex when ``ell`` (log φ, with ``z`` already
    divided by φ by :func:`fitting_kernel`) is given, else 1; row ``ones_row`` (−1: none) is
    known to be all ones, and its gather is skipped."""
    if feet.layout == "compact":
        advect_compact_kernel(
            z, feet.base, feet.code, feet.frac, feet.offsets, scale, ell, ones_row, out
        )
    else:
        advect_table_kernel(z, feet.idx, feet.weights, scale, ell, ones_row, out)
