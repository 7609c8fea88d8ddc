"""The scaled complementary error function erfcx(x) = e^{x²} erfc(x) for the numba kernels.

The fitted diffusion integrates a Gaussian against an exponential-quadratic on every cell, and
each such integral is a difference of two erfcx values weighted by the integrand at the cell's
ends (:func:`~gridlbc.backends.numba.fitted_cells.cell_mass`). The C library's erfc costs
several times an exp, so here erfcx on [0, 26) is a table of degree-7 polynomials, one per
interval of width 1/8, each the Chebyshev interpolant of :func:`scipy.special.erfcx` at 32 points of its interval
(relative error below 1e-13, checked against scipy in the tests), evaluated by Estrin's scheme;
beyond 26 it is the asymptotic series

    erfcx(x) = (1/(x√π)) (1 − 1/(2x²) + 3/(4x⁴) − 15/(8x⁶) + 105/(16x⁸) − 945/(32x¹⁰) + …),

whose first omitted term is below 1e-16 there.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from .options import jit_inline

_ERFCX_PER_UNIT = 8  # table intervals per unit of x
_ERFCX_TOP = 26.0  # the asymptotic series from here on
_ERFCX_DEGREE = 7


def _erfcx_table(points: int = 32) -> np.ndarray:
    """Power-basis coefficients in t ∈ [−1, 1] of each interval's Chebyshev interpolant."""
    theta = np.pi * (np.arange(points) + 0.5) / points
    orders = np.arange(_ERFCX_DEGREE + 1)
    cosines = np.cos(np.outer(orders, theta))
    table = np.zeros((int(_ERFCX_TOP * _ERFCX_PER_UNIT), _ERFCX_DEGREE + 1))
    for i, row in enumerate(table):
        values = special.erfcx((i + 0.5 + 0.5 * np.cos(theta)) / _ERFCX_PER_UNIT)
        chebyshev = 2.0 / points * (cosines * values).sum(axis=1)
        chebyshev[0] /= 2.0
        power = np.polynomial.chebyshev.cheb2poly(chebyshev)
        row[: power.size] = power
    return table


_ERFCX = _erfcx_table()


@jit_inline
def erfcx(x):
    """e^{x²} erfc(x) for x ≥ 0 (see the module docstring; NaN gives NaN)."""
    if not x < _ERFCX_TOP:  # also NaN, which must not index the table
        inv = 1.0 / (x * x)
        series = 1.0 - inv * (0.5 - inv * (0.75 - inv * (1.875 - inv * (6.5625 - 29.53125 * inv))))
        return series / (x * math.sqrt(math.pi))
    u = x * _ERFCX_PER_UNIT
    i = int(u)
    t = 2.0 * (u - i) - 1.0
    c = _ERFCX[i]
    t2 = t * t
    return ((c[0] + c[1] * t) + t2 * (c[2] + c[3] * t)) + (t2 * t2) * (
        (c[4] + c[5] * t) + t2 * (c[6] + c[7] * t)
    )
