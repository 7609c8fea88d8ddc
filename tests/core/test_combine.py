"""combine / naive_blend: superposition against direct solves of the composite terminal cost.

The grid solver is a linear map of the terminal data and every evaluation (z, Bᵀ∇z) is linear in
the nodal z, so combine(solutions, w) equals the direct solve of g = −λ log Σ w_i exp(−g_i/λ) up to
rounding: ~1e-15 relative measured; the tolerance 1e-10 (the issue's bar) leaves room for the
condition of the renormalisations over a few hundred steps.
"""

import warnings

import numpy as np
import pytest
from conftest import EXACTNESS_ONLY, line
from hypothesis import given, settings
from hypothesis import strategies as st

import gridlbc as g
from gridlbc.combine import CompositeCost
from gridlbc.systems import Pendulum, PointMass

RTOL = 1e-10
PLAIN = {"fitting": None}

# superposition is exact for the plain operator however coarse its grid; these grids are coarse
pytestmark = EXACTNESS_ONLY
"""The plain operator (independent of the terminal cost): these tests check its exact superposition
against direct solves; a shared fitting reference is checked in test_fitting.py."""


@pytest.fixture(scope="module")
def pendulum():
    grid = g.Grid([g.Axis(-np.pi, np.pi, 32, periodic=True), g.Axis(-8, 8, 25)])
    problem = g.Problem(
        Pendulum(),
        grid,
        0.5,
        g.Quadratic([0, 0], [4, 0.5]),
        state_cost=g.Quadratic([0, 0], [0.1, 0.01]),
        control_cost=0.5,
        temperature=0.7,
    )
    # The third is the first squared (h_3 = h_1²), so 2h_1 + ½h_2 − h_3 > 0 despite a negative weight.
    costs = [
        g.Quadratic([-1, 0], [4, 0.5]),
        g.Quadratic([1, 0], [4, 0.5]),
        g.Quadratic([-1, 0], [8, 1]),
    ]
    return problem, g.solve_many(problem, costs, dt=0.01, **PLAIN)


def _direct(combined):
    return g.solve(combined.problem, dt=combined.components[0].diagnostics.dt, **PLAIN)


def _relative(a, b):
    """max|a − b| / max|b|."""
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


def _check_superposition(combined, direct, x, t):
    lam = combined.temperature
    # value: per point, relative to max(|v|, λ) (v may cross zero where Σ w > 1).
    v_c, v_d = combined.value(x, t), direct.value(x, t)
    assert np.max(np.abs(v_c - v_d) / np.maximum(np.abs(v_d), lam)) < RTOL
    assert _relative(combined.policy(x, t), direct.policy(x, t)) < RTOL
    # α_i = w_i z_i / z against the direct z: w_i exp(log z_i − log z).
    log_z = direct.log_desirability(x, t)
    alpha = np.stack(
        [
            w * np.exp(s.log_desirability(x, t) - log_z)
            for w, s in zip(combined.weights, combined.components)
        ],
        axis=1,
    )
    assert np.max(np.abs(combined.blend_weights(x, t) - alpha)) < RTOL


@pytest.mark.parametrize("weights", [None, [0.3, 1.2, 0.01], [2.0, 0.5, -1.0]])
def test_superposition_off_grid(pendulum, rng, weights):
    _, sols = pendulum
    combined = g.combine(sols, weights)
    direct = _direct(combined)
    x = rng.uniform([-4, -7], [4, 7], size=(300, 2))  # includes θ outside [−π, π): wraps
    for t in (0.0, 0.123, 0.5):
        _check_superposition(combined, direct, x, t)


def test_superposition_on_grid(pendulum):
    _, sols = pendulum
    combined = g.combine(sols, [0.5, 0.25, 1.0])
    direct = _direct(combined)
    nodes = direct.grid.nodes()
    for j in (0, len(direct.times) // 2):
        v_d = direct.value_nodes(j)
        v_c = combined.value(nodes, direct.times[j])
        assert np.max(np.abs(v_c - v_d) / np.maximum(np.abs(v_d), 1.0)) < RTOL


def test_blend_weights_are_a_partition_of_unity(pendulum, rng):
    _, sols = pendulum
    alpha = g.combine(sols, [0.2, 3.0, 1.0]).blend_weights(rng.uniform(-3, 3, (200, 2)), 0.25)
    assert alpha.shape == (200, 3)
    assert np.all(alpha >= 0)
    np.testing.assert_allclose(alpha.sum(axis=1), 1.0, rtol=0, atol=1e-14)


def test_policy_is_the_alpha_blend_of_component_policies(pendulum, rng):
    _, sols = pendulum
    combined = g.combine(sols, [0.2, 3.0, 1.0])
    x = rng.uniform(-3, 3, (200, 2))
    u_i = np.stack([s.policy(x, 0.1) for s in sols], axis=1)  # (N, n, m)
    blend = np.einsum("ni,nim->nm", combined.blend_weights(x, 0.1), u_i)
    assert _relative(combined.policy(x, 0.1), blend) < RTOL


def test_evaluation_api_matches_solution(pendulum, rng):
    _, sols = pendulum
    single = g.combine(sols[:1], [2.0])  # z = 2 z_1: same policy, value shifted by −λ log 2
    x = rng.uniform(-3, 3, (50, 2))
    lam = single.temperature
    np.testing.assert_allclose(
        single.value(x, 0.2), sols[0].value(x, 0.2) - lam * np.log(2), rtol=1e-13, atol=1e-13
    )
    np.testing.assert_allclose(
        single.desirability(x, 0.2), 2 * sols[0].desirability(x, 0.2), rtol=1e-13
    )
    np.testing.assert_allclose(single.policy(x, 0.2), sols[0].policy(x, 0.2), rtol=1e-12)
    np.testing.assert_array_equal(single.times, sols[0].times)


def _line_problem(n=41, horizon=0.4, temperature=1.0):
    return line(n, horizon, temperature=temperature)


def test_components_with_scales_1e300_apart_combine_exactly(rng):
    # z_2 carries an extra factor e^{−700} ≈ 1e−304: with weight e^{700} it contributes as much as
    # the unshifted component would, and nothing overflows or underflows on the way.
    problem = _line_problem()
    near, far = g.Quadratic([-1], [2]), g.Quadratic([1], [2])

    def shifted(x):
        return far(x) + 700.0

    plain = g.solve_many(problem, [near, far], dt=0.01, **PLAIN)
    scaled = g.solve_many(problem, [near, shifted], dt=0.01, **PLAIN)
    x = rng.uniform(-3, 3, (100, 1))
    a = g.combine(plain, [1.0, 1.0])
    b = g.combine(scaled, [1.0, np.exp(700.0)])
    # The log-scale ℓ ≈ −700 is accumulated over the steps: each addition rounds by ≈ eps·700,
    # so v = −λ(log Z + ℓ) agrees to about steps·eps·700·λ absolute (≈ 3e−12 here).
    v_tol = 40 * np.finfo(float).eps * 700 * problem.temperature
    for t in (0.0, 0.2):
        np.testing.assert_allclose(b.value(x, t), a.value(x, t), rtol=1e-12, atol=v_tol)
        np.testing.assert_allclose(b.blend_weights(x, t), a.blend_weights(x, t), atol=1e-12)
    # Both components e^{−1000} small: the combination keeps the scale in the log domain.
    huge = g.solve_many(
        problem, [lambda x: near(x) + 1000.0, lambda x: far(x) + 1000.0], dt=0.01, **PLAIN
    )
    c = g.combine(huge)
    np.testing.assert_allclose(c.value(x, 0.1), a.value(x, 0.1) + 1000.0, rtol=1e-13)
    _check_superposition(c, _direct(c), x, 0.1)


def test_underflowed_combination_is_reported_not_nan():
    problem = _line_problem(n=61, horizon=0.1, temperature=0.01)
    sols = g.solve_many(
        problem, [g.Quadratic([-2.5], [50]), g.Quadratic([-2], [50])], dt=0.01, **PLAIN
    )  # stepped in z (a single fitted solve is stepped in log z)
    combined = g.combine(sols)
    x = np.array([[-2.2], [2.9]])  # z(2.9, T) = exp(−50 · 4.4² / 0.01): zero in float64
    with pytest.warns(g.UnderflowWarning, match="underflowed at 1 of 2"):
        v = combined.value(x, 0.1)
    assert np.isfinite(v[0]) and v[1] == np.inf
    with pytest.warns(g.UnderflowWarning):
        alpha = combined.blend_weights(x, 0.1)
    assert np.all(np.isfinite(alpha[0])) and np.all(np.isnan(alpha[1]))


def test_combine_reads_an_underflowed_blend_without_a_word_of_its_own():
    """At λ = 0.002 with goals of weight 400 the blend of two fitted components underflows at
    most of the states its check reads (the components' estimates carried by the blend weights,
    check_combination): those reads are combine's own, not the user's queries, and neither an
    UnderflowWarning about "query states" nor numpy's "invalid value" (NaN weights times an
    infinite estimate) may reach the user (stranger round 43: eight UnderflowWarnings and a
    RuntimeWarning from one call to combine)."""
    grid = g.Grid([g.Axis(-3, 3, 61), g.Axis(-3, 3, 61)])
    problem = g.Problem(
        PointMass(), grid, horizon=0.5, terminal_cost=g.Quadratic([1, 0], [1, 1]), temperature=0.002
    )
    costs = [g.Quadratic([1, 0], [400, 400]), g.Quadratic([-1, 0], [400, 400])]
    solutions = g.solve_many(problem, costs, progress=False)
    with warnings.catch_warnings(record=True) as told:
        warnings.simplefilter("always")
        g.combine(solutions)
    assert [w for w in told if not issubclass(w.category, g.ResolutionWarning)] == []


@settings(max_examples=8, deadline=None)
@given(
    weights=st.lists(st.floats(0.01, 10.0), min_size=2, max_size=3),
    centers=st.lists(st.floats(-1.5, 1.5), min_size=3, max_size=3),
    t=st.floats(0.0, 0.3),
    seed=st.integers(0, 2**32 - 1),
)
def test_superposition_property(weights, centers, t, seed):
    grid = g.Grid([g.Axis(-3, 3, 17), g.Axis(-3, 3, 17)])
    problem = g.Problem(PointMass(), grid, 0.3, g.Quadratic([0, 0], [1, 1]), temperature=0.5)
    costs = [g.Quadratic([c, 0.5 * c], [2, 1]) for c in centers[: len(weights)]]
    combined = g.combine(g.solve_many(problem, costs, dt=0.02, **PLAIN), weights)
    x = np.random.default_rng(seed).uniform(-3.5, 3.5, (40, 2))
    _check_superposition(combined, _direct(combined), x, t)
    alpha = combined.blend_weights(x, t)
    assert np.all(alpha >= 0) and np.allclose(alpha.sum(axis=1), 1.0, rtol=0, atol=1e-14)


def test_composite_cost_formula():
    costs = (g.Quadratic([-1], [1]), g.Quadratic([1], [2]))
    x = np.linspace(-2, 2, 9)[:, None]
    w = np.array([0.3, 2.0])
    expected = -0.5 * np.log(w[0] * np.exp(-costs[0](x) / 0.5) + w[1] * np.exp(-costs[1](x) / 0.5))
    np.testing.assert_allclose(CompositeCost(costs, w, 0.5)(x), expected, rtol=1e-14)
    negative = CompositeCost(costs, np.array([1.0, -1.0]), 0.5)(x)  # Σ w h ≤ 0 where g_2 < g_1
    assert np.all(negative[costs[1](x) < costs[0](x)] == np.inf)


def test_a_negative_combination_says_so_and_not_underflow(pendulum):
    # API journey round 1: where negative weights outweigh the positive ones, Σ w_i z_i < 0 was
    # reported as an underflow ("shrink the box, or raise the temperature"), which no setting fixes
    _, sols = pendulum
    x = sols[1].grid.nodes()
    z = [s.desirability(x, 0.0) for s in sols]
    where = np.flatnonzero(2 * z[0] < z[1])[:3]  # there 2·z_0 − z_1 < 0
    combined = g.combine(sols[:2], [2.0, -1.0])
    with pytest.warns(g.GridlbcWarning, match=r"Σ w_i z_i < 0 at 3 of 3 .* negative weights") as w:
        v = combined.value(x[where], 0.0)
    assert not any(issubclass(r.category, g.UnderflowWarning) for r in w)
    assert np.all(v == np.inf)


# -- mismatched components and bad weights ----------------------------------------------------------


@pytest.fixture(scope="module")
def line_solution():
    problem = _line_problem(n=21, horizon=0.2)
    return problem, g.solve(problem, dt=0.02)


@pytest.mark.parametrize(
    "change, match",
    [
        ({"grid": g.Grid([g.Axis(-3, 3, 23)])}, "grid"),
        # same node count, another box: the message shows the boxes (API journey round 1)
        ({"grid": g.Grid([g.Axis(-4, 4, 21)])}, r"grid \(21 .* on \[-3, 3\] vs 21 .* on \[-4, 4\]"),
        ({"horizon": 0.4}, "horizon"),
        ({"temperature": 2.0}, "temperature"),
        ({"control_cost": 3.0}, "control cost R"),
        ({"state_cost": g.Quadratic([0], [1])}, "state cost"),
    ],
)
def test_mismatched_problems_are_named(line_solution, change, match):
    problem, sol = line_solution
    other = g.solve(problem.replace(**change), dt=0.02)
    with pytest.raises(ValueError, match=match):
        g.combine([sol, other])


def test_weights_may_be_any_iterable_of_numbers(line_solution):
    _, sol = line_solution
    x = np.array([[0.3]])
    given = g.combine([sol, sol], (w for w in (1, 2)))  # a generator, as solve_many takes costs
    np.testing.assert_array_equal(given.value(x), g.combine([sol, sol], [1.0, 2.0]).value(x))
    with pytest.raises(TypeError, match="weights must be 2 numbers"):
        g.combine([sol, sol], ["a", 1])


def test_mismatched_system_is_named_and_other_operators_combine_inexactly():
    grid = g.Grid([g.Axis(-2, 2, 9), g.Axis(-2, 2, 9)])
    problem = g.Problem(PointMass(), grid, 0.2, g.Quadratic([0, 0], [1, 1]))
    sol = g.solve(problem, dt=0.02)
    with pytest.raises(ValueError, match="system"):
        g.combine([sol, g.solve(problem.replace(system=PointMass(mass=2.0)), dt=0.02)])
    # Same problem, other operators: combined through their values, and said to be inexact.
    other = problem.replace(terminal_cost=g.Quadratic([1, 0], [1, 1]))
    for solved, why in [
        (g.solve(other, dt=0.01), "time grid"),
        (g.solve(other, dt=0.02, method="implicit"), "implicit"),
    ]:
        combo = g.combine([sol, solved])
        assert isinstance(combo, g.Combination) and not combo.exact
        assert why in combo.reason and "solve_many" in combo.reason
    # Equal state costs given as different objects are fine (compared at the nodes).
    q1, q2 = g.Quadratic([0, 0], [1, 1]), g.Quadratic([0, 0], [1, 1])
    a = g.solve(problem.replace(state_cost=q1), dt=0.02, **PLAIN)
    b = g.solve(
        problem.replace(state_cost=q2, terminal_cost=g.Quadratic([1, 0], [1, 1])), dt=0.02, **PLAIN
    )
    assert g.combine([a, b]).exact
    # Solved separately with the defaults (each fitted to its own g): inexact, and said so.
    fitted = [g.solve(p, dt=0.02) for p in (problem, other)]
    assert "another reference" in g.combine(fitted).reason


@pytest.mark.parametrize(
    "weights, match",
    [
        ([1.0], "2 numbers"),
        ([[1.0, 2.0]], "2 numbers"),
        ([1.0, np.nan], "finite"),
        ([0.0, 0.0], "all zero"),
        ([1.0, -2.0], "sum to -1"),
    ],
)
def test_bad_weights(line_solution, weights, match):
    _, sol = line_solution
    with pytest.raises(ValueError, match=match):
        g.combine([sol, sol], weights)
    with pytest.raises(ValueError, match=match):
        g.naive_blend([sol, sol], weights)


def test_bad_components(line_solution):
    _, sol = line_solution
    with pytest.raises(ValueError, match="empty"):
        g.combine([])
    with pytest.raises(TypeError, match=r"components\[1\]"):
        g.combine([sol, "not a solution"])
    with pytest.raises(TypeError, match="policy"):
        g.naive_blend([sol, object()], [1, 1])


def test_naive_blend_is_the_fixed_weight_average(pendulum, rng):
    _, sols = pendulum
    w = np.array([0.2, 3.0, 1.0])
    x = rng.uniform(-3, 3, (50, 2))
    expected = sum(wi * s.policy(x, 0.3) for wi, s in zip(w, sols)) / w.sum()
    np.testing.assert_allclose(g.naive_blend(sols, w).policy(x, 0.3), expected, rtol=1e-13)
    # ... and differs from the combination, whose weights follow the state (combining these
    # coarse components warns that the combination's estimate is large: not under test here).
    combined = g.combine(sols, w)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _relative(combined.policy(x, 0.3), expected) > 0.1
