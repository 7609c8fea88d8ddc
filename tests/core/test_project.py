"""project / projection (gridlbc.project): the Gram system of docs/maths.rst (paper §4.1),
analytic and by quadrature."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

import gridlbc as g
from gridlbc.combine import CompositeCost
from gridlbc.project import analytic_gram

COMPONENTS = [
    g.Quadratic([-1, 0], [4, 0.5]),
    g.Quadratic([1, 0], [4, 0.5]),
    g.Quadratic([0.5, 1], [4, 0.5]),
]
WIDE = g.Grid([g.Axis(-8, 8, 321), g.Axis(-12, 12, 241)])


@pytest.mark.parametrize("lam", [1.0, 0.3])
def test_gaussian_inner_product_matches_numerical_integral(lam):
    # 1-D: ⟨h_i, h_j⟩ = ∫ exp(−(g_i + g_j)/λ) dx, by adaptive quadrature to ~1e-12.
    a, b = g.Quadratic([-0.4], [1.5]), g.Quadratic([0.7], [3.0])
    numeric, _ = quad(
        lambda x: np.exp(-(a([[x]])[0] + b([[x]])[0]) / lam),
        -30,
        30,
        epsabs=0,
        epsrel=1e-13,
        points=[-0.4, 0.7],
    )
    np.testing.assert_allclose(analytic_gram([a, b], lam)[0, 1], numeric, rtol=1e-10)


@pytest.mark.parametrize("lam", [1.0, 0.3])
def test_analytic_and_quadrature_agree_on_a_wide_box(lam):
    # Gaussians that are ~0 at the box edges: the trapezoid rule converges spectrally, so the
    # two methods agree to rounding of the Gram solve (condition ~3) times the truncation ~1e-12.
    target = g.Quadratic([0.2, 0.1], [4, 0.5])
    a = g.projection(target, COMPONENTS, temperature=lam)
    q = g.projection(target, COMPONENTS, WIDE, temperature=lam, method="quadrature")
    assert (a.method, q.method) == ("analytic", "quadrature")
    np.testing.assert_allclose(q.weights, a.weights, rtol=1e-9)
    np.testing.assert_allclose(q.gram, a.gram, rtol=1e-9)
    np.testing.assert_allclose(q.residual, a.residual, rtol=1e-6)


def test_a_component_as_target_gives_its_unit_vector():
    p = g.projection(COMPONENTS[1], COMPONENTS, temperature=0.5)
    np.testing.assert_allclose(p.weights, [0, 1, 0], atol=1e-12)
    assert p.residual < 1e-7  # √ε floor of the Gram-form residual
    assert p.messages == ()


def test_numbers_are_constant_costs_sampled_on_the_grid():
    """A number is the constant cost, as Problem reads one: the target c against components
    [a quadratic, the constant 0] is exp(−c/λ) times the second, so w = (0, exp(−c/λ)) exactly
    (to the Gram solve's rounding). Without a grid a constant cannot be projected (its integral
    over Rᵈ diverges), and the error says to pass one."""
    grid = g.Grid([g.Axis(-2, 2, 41), g.Axis(-2, 2, 41)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", g.ProjectionWarning)  # Σw = e^{−c/λ}, far from 1
        w = g.project(0.5, [COMPONENTS[0], 0.0], grid, temperature=0.7)
    np.testing.assert_allclose(w, [0.0, np.exp(-0.5 / 0.7)], atol=1e-12)
    with pytest.raises(ValueError, match=r"target_cost is a number.*grid="):
        g.project(0.5, COMPONENTS)
    with pytest.raises(TypeError, match=r"component_costs\[1\] must be a cost callable"):
        g.project(COMPONENTS[0], [COMPONENTS[0], "0"], grid)


@settings(max_examples=10, deadline=None)
@given(weights=st.lists(st.floats(0.05, 5.0), min_size=3, max_size=3), lam=st.floats(0.3, 2.0))
def test_recovers_weights_of_a_combination(weights, lam):
    # h̄ = Σ w_i h_i exactly at the nodes, so the discrete projection returns w up to rounding
    # times the Gram condition number (≲ 1e3 here).
    w = np.array(weights)
    target = CompositeCost(tuple(COMPONENTS), w, lam)
    p = g.projection(target, COMPONENTS, WIDE, temperature=lam)
    assert p.method == "quadrature"
    np.testing.assert_allclose(p.weights, w, rtol=1e-8)
    assert p.residual < 1e-6


def test_periodic_grid_uses_quadrature_and_recovers_weights():
    grid = g.Grid([g.Axis(-np.pi, np.pi, 96, periodic=True), g.Axis(-10, 10, 97)])
    comps = [g.Quadratic([-3.0, 0], [2, 0.5]), g.Quadratic([2.9, 0], [2, 0.5])]  # across the seam
    comps = [c.with_periods(grid.periods) for c in comps]
    target = CompositeCost(tuple(comps), np.array([0.7, 0.4]), 1.0)
    p = g.projection(target, comps, grid)
    assert p.method == "quadrature"
    np.testing.assert_allclose(p.weights, [0.7, 0.4], rtol=1e-8)
    with pytest.raises(ValueError, match=r"grid=problem.grid"):
        g.project(target, comps)


def test_poor_basis_warns():
    # Narrow components far from the target: weights sum far below one (paper Fig. 4).
    far = [g.Quadratic([-2, 0], [10, 0.5]), g.Quadratic([2, 0], [10, 0.5])]
    with pytest.warns(g.ProjectionWarning) as record:
        w = g.project(g.Quadratic([0, 0], [10, 0.5]), far)
    messages = " ".join(str(r.message) for r in record)
    assert "far from 1" in messages and "residual" in messages
    assert w.sum() < 0.1
    # A target beyond the components: extrapolation needs a negative weight.
    near = [g.Quadratic([-0.3, 0], [1, 0.5]), g.Quadratic([0.3, 0], [1, 0.5])]
    with pytest.warns(g.ProjectionWarning, match="negative weights"):
        w = g.project(g.Quadratic([0.6, 0], [1, 0.5]), near)
    assert w.min() < 0
    # Components bracketing the target closely interpolate it without complaint.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        w = g.project(g.Quadratic([0.1, 0], [1, 0.5]), near)
    assert np.all(w > 0) and abs(w.sum() - 1) < 0.25


def test_bad_input():
    target = COMPONENTS[0]
    with pytest.raises(ValueError, match="empty"):
        g.project(target, [])
    with pytest.raises(TypeError, match=r"component_costs\[1\]"):
        g.project(target, [target, "3.0"])
    with pytest.raises(ValueError, match="temperature"):
        g.project(target, COMPONENTS, temperature=0.0)
    with pytest.raises(ValueError, match="method"):
        g.project(target, COMPONENTS, method="exact")
    with pytest.raises(ValueError, match="linearly dependent"):
        g.project(target, [COMPONENTS[0], COMPONENTS[0]])
    with pytest.raises(ValueError, match="needs Quadratic"):
        g.project(lambda x: x[:, 0] ** 2, COMPONENTS, WIDE, method="analytic")
    with pytest.raises(TypeError, match="grid"):
        g.project(target, COMPONENTS, grid="grid")
