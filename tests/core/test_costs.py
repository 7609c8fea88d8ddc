"""The library's quadratic costs: the compiled form against the textbook numpy one."""

import numpy as np
import pytest

from gridlbc import Quadratic
from gridlbc.costs import Tracking, wrap_difference


@pytest.mark.parametrize("d", [1, 2, 3, 4])
def test_the_quadratic_form_is_the_wrapped_difference_through_w(d):
    # (x − c)ᵀ W (x − c) with x − c taken to its nearest image on the periodic axes, summed in
    # another order than numpy's einsum: equal to a few ulps of Σ abs(dᵢ Wᵢⱼ dⱼ), the size of the
    # rounding either sum can make (and at least 0, as W is positive semi-definite).
    rng = np.random.default_rng(d)
    A = rng.normal(size=(d, d))
    W = A @ A.T
    periods = np.where(np.arange(d) % 2 == 0, 2 * np.pi, np.inf)
    cost = Quadratic(rng.normal(size=d), W, periods)
    x = rng.normal(scale=6.0, size=(500, d))
    diff = wrap_difference(x - cost.center, periods)
    textbook = np.einsum("ni,ij,nj->n", diff, W, diff)
    size = np.einsum("ni,ij,nj->n", np.abs(diff), np.abs(W), np.abs(diff))
    assert np.all(np.abs(cost(x) - np.maximum(textbook, 0.0)) <= 8 * np.finfo(float).eps * size)
    assert np.all(np.abs(diff) <= np.where(np.isfinite(periods), np.pi, np.inf))
    assert cost(x[0]).shape == (1,)


def test_a_tracking_cost_reads_its_reference_at_each_time():
    # Each state against x̃ at its own time (linear between the samples), wrapped on the angle.
    cost = Tracking(
        [0.0, 1.0], [[0.0, 1.0], [2 * np.pi + 1.0, 3.0]], [2.0, 0.5], [2 * np.pi, np.inf]
    )
    x = np.array([[0.2, 1.0], [3.0, -1.0], [-3.0, 2.0]])
    t = np.array([0.0, 0.5, 1.0])
    reference = np.array([[0.0, 1.0], [np.pi + 0.5, 2.0], [2 * np.pi + 1.0, 3.0]])
    diff = wrap_difference(x - reference, [2 * np.pi, np.inf])
    np.testing.assert_allclose(
        cost(x, t), 2.0 * diff[:, 0] ** 2 + 0.5 * diff[:, 1] ** 2, rtol=1e-14
    )
