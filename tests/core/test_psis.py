"""pareto_k: the PSIS tail diagnostic against weights of known tail shape.

Tolerances: the GPD shape estimated from M exceedances has the asymptotic standard error
(1 + ξ)/√M (Smith 1985, the maximum-likelihood rate, which Zhang & Stephens' estimator attains
asymptotically); the test checks that rule against the spread of repeated draws (the sample SD of
R draws is within 3/√(2(R−1)) of its expectation, relatively), then holds single draws to 3 such
SE and the mean of R draws to 3 SE/√R, plus the known shift of PSIS's prior
(M ξ + 5)/(M + 10) − ξ.
"""

import math
import warnings

import numpy as np
import pytest
from scipy import stats

from gridlbc.psis import gpd_shape, pareto_k, tail_length

N = 20_000
REPEATS = 20


def _prior_shift(xi, M):
    return (M * xi + 5.0) / (M + 10.0) - xi


@pytest.mark.parametrize("xi", [0.2, 0.5, 0.9])
def test_exact_pareto_tails_give_their_shape(xi, rng):
    # A GPD's exceedances over any threshold are GPD with the same ξ: the fitted tail is exact.
    M = tail_length(N)
    se = (1 + xi) / math.sqrt(M)
    k = np.array(
        [
            pareto_k(np.log(stats.genpareto.rvs(xi, size=N, random_state=rng)))
            for _ in range(REPEATS)
        ]
    )
    spread = 3 / math.sqrt(2 * (REPEATS - 1))
    assert (1 - spread) * se < k.std(ddof=1) < (1 + spread) * se
    assert np.all(np.abs(k - xi) < 3 * se + abs(_prior_shift(xi, M)))
    assert abs(k.mean() - xi - _prior_shift(xi, M)) < 3 * se / math.sqrt(REPEATS)


@pytest.mark.parametrize("sigma", [0.1, 0.5])
def test_light_tails_are_reliable(sigma, rng):
    # Log-normal weights have every moment: their tail index is 0 (below 0.5 by far at small σ).
    assert pareto_k(rng.normal(0.0, sigma, N)) < 0.5


def test_scale_invariant_and_underflow_safe(rng):
    # k̂ depends on the weights only up to a common factor, so a shift of the log-weights by
    # thousands (exp would overflow or underflow) changes nothing but rounding.
    lw = rng.normal(0.0, 1.0, 4000)
    assert pareto_k(lw - 5000.0) == pytest.approx(pareto_k(lw), abs=1e-12)
    assert pareto_k(lw + 5000.0) == pytest.approx(pareto_k(lw), abs=1e-12)


def test_a_long_tail_fits_without_overflow(rng):
    # The profile likelihoods of the candidate shapes differ by M times a log ratio: over
    # thousands of exceedances by more than exp can hold, and the weight of a far less likely
    # candidate is then 0, its limit, without numpy's overflow warning (stranger round 45's
    # certificates). Exponential exceedances: ξ = 0, within 3 SE plus the prior's shift.
    M = 4000
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        k = gpd_shape(rng.exponential(size=M))
    assert abs(k) < 3 / math.sqrt(M) + abs(_prior_shift(0.0, M))


def test_a_tail_tied_at_its_largest_fits_without_numpy_warnings():
    # Most of the exceedances equal the largest (paths of one cost, stranger round 45's
    # certificates of a slab crossed without noise): θ x reaches 1 for a candidate θ, whose
    # profile likelihood is not a number and which then has no weight. A tail with a hard
    # end has a negative shape.
    x = np.r_[np.linspace(0.7115, 0.7134, 20), np.full(84, 0.7134952031398099)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert gpd_shape(x) < 0.0


def test_too_few_or_tied_weights_give_nan():
    assert math.isnan(pareto_k(np.zeros(1000)))  # all tied: no exceedance
    assert math.isnan(pareto_k(np.arange(10.0)))  # M = 2
    assert tail_length(10) == 2 and tail_length(20_000) == 425
    with pytest.raises(ValueError, match="at least"):
        gpd_shape([1.0, 2.0])
    with pytest.raises(ValueError, match="finite"):
        pareto_k([0.0, np.nan])


def test_agrees_with_arviz(rng):
    az = pytest.importorskip("arviz")
    for xi in (0.3, 1.1):
        lw = np.log(stats.genpareto.rvs(xi, size=3000, random_state=rng))
        _, k = az.psislw(lw.copy(), reff=1.0)
        assert pareto_k(lw) == pytest.approx(float(k), abs=1e-12)
