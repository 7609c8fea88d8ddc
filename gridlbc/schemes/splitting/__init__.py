"""Semi-Lagrangian operator splitting for the linear Bellman PDE (``method="splitting"``).

One backward step from t + Δt to t composes linear, monotone operators, symmetrically (Strang):

    z(·, t) = C D½ M P D½ C z(·, t + Δt)

- P, drift along characteristics: (P z)(x) = z(X(x)) with the second-order (midpoint) foot
  X(x) = x + Δt a(x + ½Δt a(x)), evaluated by barycentric interpolation (weights ≥ 0, sum 1);
  feet are wrapped on periodic axes and clamped to the box on the others;
- D½, diffusion over half a step, implicitly, one noise axis k at a time:
  (I − ½Δt D_k(x) δ²_k) z' = z,  D_k = ½ (λ B R⁻¹ Bᵀ)_kk, δ²_k the three-point second
  difference; each line is a tridiagonal M-matrix (cyclic on a periodic axis; on a closed axis the
  jumps out of the box are suppressed, a reflecting state constraint);
- C and M, the state cost, by Simpson's rule along the characteristic: ∫ q dt over the step is
  Δt (q(start) + 4 q(middle) + q(end))/6, so C: z' = exp(−q Δt/(6λ)) z at the nodes (a path's
  ends), and M: z' = exp(−2 q(m(x)) Δt/(3λ)) z applied between the drift and the first half
  diffusion, with m(x) = x + ½Δt a(x + ¼Δt a(x)), the foot of half a step, where the
  characteristic from x is half a step on (the first half diffusion then averages it over that
  half's noise). The trapezoid of the ends alone misses how q changes along a characteristic
  that crosses many cells per step, and a cost that is stiff across one step's noise.

Every stage maps non-negative z to non-negative z and constants to constants (before the cost),
so the step is the transition of a Markov chain (with killing at rate q/λ), and it is
unconditionally stable: Δt is limited by accuracy, not by a CFL condition. Its error is
O(h²/Δt) from the interpolation (a numerical diffusion of at most h²/(8Δt) per axis), O(Δt) from
the backward-Euler diffusion and O(Δt²) from the symmetric splitting and the foot; the first term
*falls* as Δt grows, so unlike an upwind scheme the splitting wants large Courant numbers. The
symmetric order matters where the drift is fast (``benchmarks/swingup_accuracy.py``).

Exponential fitting (``fitting=`` in :func:`gridlbc.solve`) interpolates relative to a reference
desirability φ instead, in the drift and in the diffusion, which makes the step exact where
z ∝ φ; a single terminal cost fitted to itself is marched in the log domain.

The package, one idea per module:

- :mod:`.feet`: the characteristic feet and their compact encoding;
- :mod:`.drift`: the drift P and its fitted form P_φ;
- :mod:`.curvature`: the curvature term of the fitted drift;
- :mod:`.diffusion`: the tridiagonal half-step diffusion D½ and the noise axes;
- :mod:`.fitted_diffusion`: the fitted (erf-integrated) diffusion;
- :mod:`.step`: :class:`SplittingStep`, the parts composed into one step;
- :mod:`.march`: the time loops (plain, fitted to a reference row, in the log domain);
- :mod:`.checks`: what the step and grid cannot resolve, as warnings;
- :mod:`.scheme`: the scheme as the solver sees it (:data:`SPLITTING`).

Their compiled kernels are in :mod:`gridlbc.backends.numba`.
"""

from .checks import (
    CONTROL_STEP_CELLS,
    COST_NOISE_SCALE,
    FIT_CURVATURE_JUMP,
    check_control_step,
    check_fitted_resolution,
    cost_sampling_step,
)
from .diffusion import NoiseAxis, tridiagonal_factors
from .feet import FEET_LAYOUTS, Feet, characteristic_feet, feet_bytes_per_node
from .scheme import SPLITTING, SplittingScheme
from .step import SplittingStep

__all__ = [
    "CONTROL_STEP_CELLS",
    "COST_NOISE_SCALE",
    "FEET_LAYOUTS",
    "FIT_CURVATURE_JUMP",
    "SPLITTING",
    "Feet",
    "NoiseAxis",
    "SplittingScheme",
    "SplittingStep",
    "characteristic_feet",
    "check_control_step",
    "check_fitted_resolution",
    "cost_sampling_step",
    "feet_bytes_per_node",
    "tridiagonal_factors",
]
