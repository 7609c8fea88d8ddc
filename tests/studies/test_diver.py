"""The diver's problem definition (gridlbc.studies.problems) and the study's projection."""

import numpy as np
import pytest

from gridlbc.studies.diver import composite_profile, interpolation_weights
from gridlbc.studies.problems import DIVER_SPIN, diver, diver_problem, diver_start


def test_take_off_is_a_straight_rigid_spin_scaled_by_kappa():
    body = diver()
    for kappa in (0.85, 1.0, 1.15):
        x0 = diver_start(kappa)
        np.testing.assert_array_equal(x0[:4], [np.pi, 0, 0, 0])
        # Joint velocities: only the rigid spin κ ω0 (rounding of M⁻¹ M, cond(M) ≈ 1e3).
        np.testing.assert_allclose(
            body.to_velocities(x0)[0, 4:], [kappa * DIVER_SPIN, 0, 0, 0], atol=1e-12
        )
    p1 = [body.angular_momentum(diver_start(k))[0] for k in (0.85, 1.0, 1.15)]
    np.testing.assert_allclose(np.array(p1) / p1[1], [0.85, 1.0, 1.15], rtol=1e-14)


def test_entry_cost_is_wrap_aware_and_vertical_at_zero():
    problem = diver_problem()
    assert problem.grid is None and problem.periodic_axes == (0, 1, 2, 3)
    entry = np.zeros((1, 8))
    assert problem.terminal_cost(entry)[0] == 0.0
    # A full turn further is the same vertical entry; p1 carries no cost (it cannot change).
    assert problem.terminal_cost(entry + [2 * np.pi, 0, 0, 0, 5, 0, 0, 0])[0] == pytest.approx(
        0.0, abs=1e-20
    )
    short = diver_problem(entry_angle=-0.25)
    assert short.terminal_cost(entry + [-0.25, 0, 0, 0, 0, 0, 0, 0])[0] == pytest.approx(0.0)


def test_interpolation_weights_are_symmetric_and_match_the_closed_form():
    """Entries at ∓δ around the vertical: w1 = w2 = b / (A11 + A12) with Gaussian integrals
    (A = 2W/λ): b ∝ exp(−A δ²/4), A12 ∝ exp(−A δ²), A11 ∝ 1."""
    delta, lam, w1 = 0.25, 1.0, 10.0
    fit = interpolation_weights(delta, lam)
    a = 2 * w1 / lam
    expected = np.exp(-a * delta**2 / 4) / (1 + np.exp(-a * delta**2))
    np.testing.assert_allclose(fit.weights, [expected, expected], rtol=1e-12)


def test_composite_entry_cost_is_bimodal_when_components_are_far_apart():
    """Why LBC misses the vertical entry at δ = 0.25: the combined goal −λ log Σ w_i exp(−g_i/λ)
    with projected weights has two minima off vertical once 2δ exceeds twice the width
    σ = √(λ/2W1) ≈ 0.22 of exp(−g/λ) (a mixture of two equal Gaussians is unimodal iff their
    distance is at most 2σ); closer components give one minimum at 0."""
    angles = np.linspace(-0.5, 0.5, 201)
    far = composite_profile(0.25, 1.0, angles)
    assert abs(angles[np.argmin(far)]) > 0.1 and far[100] > far.min() + 0.02
    near = composite_profile(0.15, 1.0, angles)
    assert np.argmin(near) == 100
