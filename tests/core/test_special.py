"""The tabulated erfcx of the fitted diffusion's cell integrals (gridlbc.backends.numba.special)."""

import numpy as np
from scipy import special

from gridlbc.backends.numba.special import erfcx


def test_tabulated_erfcx_matches_scipy():
    """The piecewise-polynomial erfcx of the fitted diffusion's cell integrals against
    scipy.special.erfcx: relative error below 1e-13 on [0, 26) (the Chebyshev interpolants, at
    every interval's ends and at points in between) and beyond (the asymptotic series)."""
    ends = np.arange(0, 26 * 8 + 1) / 8
    x = np.concatenate([ends, np.linspace(0.0, 30.0, 2475), np.geomspace(26.0, 1e12, 200)])
    values = np.array([erfcx(v) for v in x])
    reference = special.erfcx(x)
    np.testing.assert_allclose(values, reference, rtol=1e-13, atol=0)
    assert np.isnan(erfcx(np.nan))
