"""The exponentially fitted drift of the splitting scheme (gridlbc.schemes.splitting, "Exponential
fitting"): exact for desirabilities proportional to the reference, linear and positive for any
other, exactly superposable among solutions that share the reference, and far more honest than
plain interpolation where v is steep."""

import numpy as np
import pytest
from conftest import pendulum

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.schemes.splitting import SplittingStep, characteristic_feet
from gridlbc.simulate import simulate
from gridlbc.studies.problems import SWINGUP_START, swingup_problem


def _pendulum(n=24):
    return pendulum(n, weights=(1, 0.1))


@pytest.mark.parametrize("feet", ["compact", "table"])
def test_fitted_drift_is_exact_for_desirabilities_proportional_to_the_reference(feet):
    """Reference φ = exp(ℓ) with ℓ affine in the unwrapped coordinates of a closed grid: the
    fitted drift gives c·exp(ℓ(X)) at every foot X for the rows φ and c·φ. The only errors are
    the stored weights: quantised feet (≤ d/131070 cell, compact) or float32 weights (table),
    times |∇ℓ| h. The plain drift, by contrast, is off by the interpolation error of the
    exponential, about (|∇ℓ| h)²/8 relative: the test can tell the two apart."""
    grid = Grid([Axis(-2, 2, 21), Axis(-3, 3, 31)])
    from gridlbc.systems import PointMass

    problem = Problem(PointMass(), grid, 1.0, Quadratic([0, 0], [1, 1]))
    dt = 0.13
    step = SplittingStep(problem, dt, feet=feet)
    slope = np.array([2.5, -1.5])  # |∇ℓ| h ≈ 0.5 per cell
    ell = grid.nodes() @ slope
    z = np.stack([np.exp(ell), 3.0 * np.exp(ell)])
    feet_x = characteristic_feet(problem, dt)
    expected = np.exp(feet_x @ slope) * np.array([[1.0], [3.0]])
    out = np.empty_like(z)
    step.drift(z.copy(), out, np.ones(2), reference=0)
    h_grad = np.abs(slope * grid.spacing).sum()
    tol = h_grad * (2 / 131070 if feet == "compact" else 4 * 2.0**-24)
    np.testing.assert_allclose(out, expected, rtol=2 * tol)
    plain = np.empty_like(z)
    step.drift(z.copy(), plain, np.ones(2))
    assert np.max(np.abs(plain / expected - 1)) > 100 * tol


@pytest.mark.parametrize("feet", ["compact", "table"])
@pytest.mark.parametrize("underflow", [False, True])
def test_reference_row_shortcut_is_the_gathered_number(feet, underflow, rng):
    """The reference row fitted to itself skips its gather (z/φ = 1 exactly, so the result is
    φ̄ times the weights' sum): a copy of that row, gathered, must give the same bits. Where φ
    is floored at TINY (zeros, ``underflow``), the shortcut is off and both rows are gathered;
    the output stays finite and non-negative."""
    problem = _pendulum()
    step = SplittingStep(problem, 0.1, feet=feet)
    phi = np.exp(-problem.terminal_values(problem.grid.nodes())) * rng.uniform(0.5, 1.5)
    if underflow:
        phi[rng.random(phi.size) < 0.2] = 0.0
    rows = np.stack([phi, phi, rng.random(phi.size)])
    out = np.empty_like(rows)
    step.drift(rows.copy(), out, np.ones(3), reference=0)
    np.testing.assert_array_equal(out[0], out[1])
    assert np.all(np.isfinite(out)) and np.all(out >= 0)
    assert np.count_nonzero(out[0] == 0) == 0 or underflow


def test_fitted_step_is_linear_and_positive(rng):
    problem = _pendulum()
    step = SplittingStep(problem, 0.1)
    N = problem.grid.size
    phi = np.exp(-problem.terminal_values(problem.grid.nodes()))
    z1, z2 = rng.random(N), rng.random(N) ** 4
    a, b = 0.7, 2.5
    rows = np.stack([z1, z2, a * z1 + b * z2, phi])
    out = np.empty_like(rows)
    step(rows, out, np.ones(4), 3)
    assert np.all(out >= 0)
    np.testing.assert_allclose(out[2], a * out[0] + b * out[1], rtol=1e-13,
                               atol=1e-15 * out[2].max())


def test_combination_exact_with_a_shared_reference_and_refused_without():
    problem = _pendulum()
    g1 = Quadratic([0.5, 0.0], [2.0, 0.2])
    g2 = Quadratic([-1.0, 0.5], [1.0, 0.3])
    parts = gridlbc.solve_many(problem, [g1, g2], dt=0.05, fitting="terminal")
    combined = gridlbc.combine(parts, [0.3, 1.7])
    direct = gridlbc.solve(combined.problem, dt=0.05, fitting=parts[0].problem.terminal_cost)
    # the composite of g1, g2 (solve_many's reference) is not g1: fitted to different references
    assert direct.diagnostics.fitting != parts[0].diagnostics.fitting
    with pytest.raises(ValueError, match="fitting reference"):
        gridlbc.combine([parts[0], direct])
    # with the reference shared, the combination is the direct solve to rounding
    shared = gridlbc.solve_many(problem, [g1, g2, combined.problem.terminal_cost], dt=0.05,
                                fitting=g2)
    combo = gridlbc.combine(shared[:2], [0.3, 1.7])
    x = problem.grid.nodes()[::5]
    for t in (0.0, 0.55):
        np.testing.assert_allclose(combo.value(x, t), shared[2].value(x, t), rtol=1e-12)
        np.testing.assert_allclose(combo.policy(x, t), shared[2].policy(x, t), rtol=1e-9,
                                   atol=1e-11)


def test_own_reference_row_and_explicit_reference_agree():
    """solve(fitting="terminal") fits to its own row; fitting=g adds g as a separate reference
    row. Same φ, same operator: the same numbers (the own row is stepped in the log domain,
    the explicit one in z, so they agree to rounding) and fingerprints."""
    problem = _pendulum()
    own = gridlbc.solve(problem, dt=0.05, fitting="terminal")
    explicit = gridlbc.solve(problem, dt=0.05, fitting=problem.terminal_cost)
    assert own.diagnostics.interpolation == "log" and explicit.diagnostics.interpolation == "linear"
    for j in range(len(own.times)):
        np.testing.assert_allclose(own.log_desirability_nodes(j),
                                   explicit.log_desirability_nodes(j), rtol=1e-11, atol=1e-11)
    assert own.diagnostics.fitting == explicit.diagnostics.fitting != "none"
    assert gridlbc.solve(problem, dt=0.05).diagnostics.fitting == "none"


def test_fitting_makes_the_swingup_prediction_honest():
    """Pendulum swing-up at 128², Δt = 0.03 (measured: plain predicts 12.05 against a
    Monte-Carlo cost of 16.1 for its policy; fitted predicts 14.47 against 14.85, with standard
    errors ≈ 0.17). The fitted gap must be under 6 % of the realised cost (well over 3 standard
    errors away from the measured 2.6 %), the plain one over 15 % (measured 25 %)."""
    problem = swingup_problem(128)
    x0 = SWINGUP_START.copy()
    gaps = {}
    for fitting in (None, "terminal"):
        solution = gridlbc.solve(problem, dt=0.03, fitting=fitting)
        run = simulate(problem, solution.policy, x0, 1000, dt=0.005, seed=3)
        gaps[fitting] = (run.mean_cost - solution.value(x0, 0.0)[0]) / run.mean_cost
    assert abs(gaps["terminal"]) < 0.06, gaps
    assert gaps[None] > 0.15, gaps


def test_fitting_options_are_checked(tmp_path):
    problem = _pendulum(8)
    with pytest.raises(ValueError, match="fitting applies to method='splitting'"):
        gridlbc.solve(problem, method="implicit", fitting="terminal")
    with pytest.raises(ValueError, match="fitting must be None, 'terminal'"):
        gridlbc.solve(problem, fitting="own")
    solution = gridlbc.solve(problem, dt=0.1, fitting="terminal")
    gridlbc.save(solution, tmp_path / "fitted.npz")
    assert gridlbc.load(tmp_path / "fitted.npz").diagnostics.fitting == solution.diagnostics.fitting
