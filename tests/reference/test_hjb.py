"""The value-space HJB solver: kernels against plain numpy, scheme properties, Riccati convergence."""

import math

import numpy as np
import pytest
from conftest import EXACTNESS_ONLY, pendulum
from scipy.interpolate import RegularGridInterpolator

from gridlbc import Axis, Grid, Problem
from gridlbc.costs import Quadratic
from gridlbc.reference import lq_solution, solve_hjb
from gridlbc.reference.hjb import (
    control_structure,
    hamiltonian_kernel,
    hamiltonian_numpy,
    multilinear,
    value_gradient,
)
from gridlbc.studies.convergence import pointmass_points
from gridlbc.studies.problems import pointmass_problem
from gridlbc.systems.base import LinearSystem

pytestmark = EXACTNESS_ONLY
"""The scheme's properties on coarse grids, where solve_hjb rightly warns that its first-order
values are not accurate (the warning itself: test_the_estimate_is_the_first_order_error)."""


def _pendulum(n=16, temperature=1.0, horizon=0.5):
    return pendulum(n, horizon=horizon, temperature=temperature)


def _kernel_hamiltonian(problem, v, control_bounds=None):
    grid = problem.grid
    x = grid.nodes()
    s = control_structure(problem, x, control_bounds)
    H, rate = np.empty(grid.size), np.empty(grid.size)
    control = np.empty((grid.size, s.axis.size))
    hamiltonian_kernel(
        v,
        np.ascontiguousarray(problem.system.drift(x)),
        s.gain,
        s.axis,
        s.r,
        s.bounds,
        np.ascontiguousarray(0.5 * problem.noise_diagonal(x)),
        problem.state_cost_values(x),
        *grid.kernel_arrays()[2:4],
        grid.spacing,
        grid.periodic,
        H,
        rate,
        control,
    )
    return H, rate, control


@pytest.mark.parametrize("bounds", [None, (-0.5, 1.0), (0.2, np.inf)])
@pytest.mark.parametrize("make", [lambda: pointmass_problem(1.0), lambda: _pendulum(12)])
def test_hamiltonian_kernel_matches_numpy_reference(make, bounds, rng):
    # The kernel clips each branch minimiser to its half-line ∩ box; the reference evaluates the
    # exact piecewise objective at every candidate (kink, branch minimisers, box ends). Same
    # arithmetic up to summation order. (0.2, ∞) excludes u = 0, an unusual but valid box.
    problem = make()
    v = rng.normal(scale=3.0, size=problem.grid.size)
    H, rate, _ = _kernel_hamiltonian(problem, v, bounds)
    H_ref, rate_ref = hamiltonian_numpy(problem, v, bounds)
    scale = np.abs(H_ref).max()
    np.testing.assert_allclose(H, H_ref, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(rate, rate_ref, rtol=1e-12)


@pytest.mark.parametrize("lo, hi", [(-60.0, 60.0), (-2.0, 3.0)])
def test_minimising_control_beats_a_dense_search(lo, hi, rng):
    # min_u [½ r u² + b⁺δ⁺ − b⁻δ⁻], b = a + β u over lo ≤ u ≤ hi: the kernel's control lies in
    # the box and no control on a fine grid of the box does better. (±60 is wider than every
    # unconstrained minimiser here, so that case is the unbounded one.)
    problem = _pendulum(10)
    v = rng.normal(scale=5.0, size=problem.grid.size)
    _, _, control = _kernel_hamiltonian(problem, v, (lo, hi))
    assert np.all((control >= lo) & (control <= hi))
    grid = problem.grid
    field = grid.reshape(v)
    h = grid.spacing[1]
    forward = (np.diff(field, axis=1, append=field[:, -1:]) / h).ravel()
    backward = (np.diff(field, axis=1, prepend=field[:, :1]) / h).ravel()
    a = problem.system.drift(grid.nodes())[:, 1]
    beta = problem.system.input_matrix(grid.nodes())[:, 1, 0]

    def objective(u):
        b = a[:, None] + beta[:, None] * u
        return (
            0.5 * u**2 + np.maximum(b, 0) * forward[:, None] - np.maximum(-b, 0) * backward[:, None]
        )

    searched = objective(np.linspace(lo, hi, 24001)[None, :]).min(axis=1)
    found = objective(control[:, :1])[:, 0]
    assert np.all(found <= searched + 1e-12 * np.abs(searched).max())


def test_multilinear_matches_scipy_on_closed_and_periodic_axes(rng):
    grid = Grid([Axis(-math.pi, math.pi, 9, periodic=True), Axis(-1.0, 2.0, 7)])
    values = rng.normal(size=grid.size)
    x = np.column_stack([rng.uniform(-3 * math.pi, 3 * math.pi, 200), rng.uniform(-1, 2, 200)])
    # Periodic axis: append the wrapped first node so scipy sees the full period.
    theta = np.append(grid.axes[0].points(), math.pi)
    table = grid.reshape(values)
    table = np.concatenate([table, table[:1]], axis=0)
    expected = RegularGridInterpolator((theta, grid.axes[1].points()), table)(grid.wrap(x))
    np.testing.assert_allclose(multilinear(grid, values, x)[0], expected, rtol=0, atol=1e-13)


def test_multilinear_reproduces_bilinear_functions_and_clamps_outside():
    grid = Grid([Axis(-1.0, 1.0, 5), Axis(0.0, 3.0, 4)])

    def f(x):
        return (1 + 2 * x[:, 0]) * (3 - x[:, 1]) + x[:, 1]

    x = np.array([[0.3, 1.7], [-0.99, 2.5], [5.0, -2.0]])
    got = multilinear(grid, f(grid.nodes()), x)[0]
    np.testing.assert_allclose(got, f(grid.clamp(x)), rtol=1e-14)


def test_value_gradient_is_exact_for_quadratics_inside_and_wraps_periodic():
    grid = Grid([Axis(-math.pi, math.pi, 16, periodic=True), Axis(-1.0, 1.0, 9)])
    x = grid.nodes()
    grad = value_gradient(grid, np.sin(x[:, 0]) + x[:, 1] ** 2)
    h = grid.spacing
    # central differences: sin → cos · sin(h)/h exactly, x² → 2x exactly (one-sided at the ends)
    np.testing.assert_allclose(grad[0], np.cos(x[:, 0]) * math.sin(h[0]) / h[0], atol=1e-14)
    inside = np.abs(x[:, 1]) < 1 - 1e-9
    np.testing.assert_allclose(grad[1][inside], 2 * x[inside, 1], atol=1e-13)


def test_terminal_slice_is_g_and_constant_cost_stays_constant():
    problem = _pendulum(12).replace(terminal_cost=lambda x: np.full(x.shape[0], 3.5))
    solution = solve_hjb(problem)
    # constant v: every difference vanishes, H = q = 0, the optimal control is u = 0
    np.testing.assert_array_equal(solution.values, 3.5)
    np.testing.assert_array_equal(solution.policy(problem.grid.nodes(), 0.0), 0.0)
    np.testing.assert_array_equal(
        solve_hjb(_pendulum(12)).values[-1], _pendulum(12).terminal_values()
    )


def test_discrete_maximum_principle():
    # Monotone scheme, transition probabilities ≥ 0 summing to one, running cost ≥ 0:
    # min g ≤ v(t) ≤ max g + (T − t) max q (q = 0 here, so v stays within [min g, max g]).
    problem = _pendulum(16)
    g = problem.terminal_values()
    values = solve_hjb(problem).values
    assert values.min() >= g.min() - 1e-12 * g.max()
    assert values.max() <= g.max() * (1 + 1e-12)


def test_point_symmetry_across_the_periodic_seam():
    # a(−x) = −a(x), g(−x) = g(x), and the node set is symmetric under x → −x mod 2π:
    # v(θ, ω) = v(−θ, −ω) at the nodes, which pairs nodes across the θ = ±π seam.
    problem = _pendulum(16)
    grid = problem.grid
    x = grid.nodes()
    solution = solve_hjb(problem)
    v = solution.values[0]
    np.testing.assert_allclose(solution.value(-x, 0.0), v, rtol=1e-12)
    np.testing.assert_allclose(solution.value(x + [2 * math.pi, 0.0], 0.0), v, rtol=1e-12)


def test_pointmass_converges_to_riccati_at_first_order():
    # Upwind Markov-chain approximation with Δt ∝ h: error C h + o(h). The observed order
    # between successive halvings of h must be 1 ± 0.2 for the value and the policy, and the
    # errors must shrink by at least 2^0.8 per halving.
    points = pointmass_points()
    exact = lq_solution(pointmass_problem(0.25))
    v_exact, u_exact = exact.value(points, 0.0), exact.policy(points, 0.0)
    region = v_exact < v_exact.min() + 5.0
    errors = []
    for h in (1 / 4, 1 / 8, 1 / 16):
        solution = solve_hjb(pointmass_problem(h))
        errors.append(
            (
                np.abs(solution.value(points, 0.0) - v_exact)[region].max(),
                np.abs(solution.policy(points, 0.0) - u_exact)[region].max(),
            )
        )
    errors = np.array(errors)
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all((orders > 0.8) & (orders < 1.2)), orders


def test_the_estimate_is_the_first_order_error():
    """The scheme is first order in h (above), e_h = C h + O(h²), so the difference from the
    solve on the grid with every other node, v_2h − v_h = C h + O(h²), is the error to within
    a factor 1 + O(h): 1.00–1.15 of it measured against Riccati on the point mass at h = 1/8
    where v is within 5 of its least value (bounds 0.8–1.25 for the O(h) term). The solve there
    is 8–30 % off and warns; the API journey's reference 13 % off on a 41² point mass
    said nothing. Without the estimate there is nothing to read, and the error says so."""
    import gridlbc

    points = pointmass_points()
    problem = pointmass_problem(1 / 8)
    exact = lq_solution(problem).value(points, 0.0)
    region = exact < exact.min() + 5.0
    with pytest.warns(gridlbc.ResolutionWarning, match="first order in h.*finer grid"):
        solution = solve_hjb(problem)
    error = np.abs(solution.value(points, 0.0) - exact)[region]
    ratio = solution.error_estimate(points, 0.0)[region] / error
    assert np.all((ratio > 0.8) & (ratio < 1.25)), (ratio.min(), ratio.max())
    assert np.isscalar(solution.error_estimate(points[0], 0.0))
    bare = solve_hjb(problem, error_estimate=False)
    assert bare.coarse is None
    np.testing.assert_array_equal(bare.values, solution.values)  # the estimate changes nothing
    with pytest.raises(ValueError, match="no error estimate"):
        bare.error_estimate(points, 0.0)


def test_bad_inputs_raise_with_the_argument_named():
    problem = _pendulum(8)
    with pytest.raises(TypeError, match="problem"):
        solve_hjb("pendulum")
    with pytest.raises(ValueError, match="dt"):
        solve_hjb(problem, dt=-0.1)
    with pytest.raises(ValueError, match="courant"):
        solve_hjb(problem, courant=1.5)
    with pytest.raises(ValueError, match="slices"):
        solve_hjb(problem, slices=0)
    with pytest.raises(ValueError, match="t must lie"):
        solve_hjb(problem).value([0.0, 0.0], 2.0)
    grid = Grid([Axis(-1, 1, 5), Axis(-1, 1, 5)])
    two_controls = LinearSystem(np.zeros((2, 2)), np.eye(2))
    coupled = Problem(
        two_controls, grid, 1.0, Quadratic([0, 0], [1, 1]), control_cost=[[2.0, 0.0], [0.0, 1.0]]
    )
    with pytest.raises(ValueError, match="diagonal control_cost"):
        solve_hjb(coupled.replace(control_cost=[[2.0, 0.5], [0.5, 1.0]]))
    same_axis = Problem(
        LinearSystem(np.zeros((2, 2)), [[0.0, 0.0], [1.0, 1.0]]),
        grid,
        1.0,
        Quadratic([0, 0], [1, 1]),
    )
    with pytest.raises(ValueError, match="own state axis"):
        solve_hjb(same_axis)


def _same_steps(problem, bounds, dt):
    """Bounded and unbounded solves on one time grid (dt below both CFL limits)."""
    free, boxed = solve_hjb(problem, dt), solve_hjb(problem, dt, control_bounds=bounds)
    for s in (free, boxed):
        assert s.diagnostics.min_step == s.diagnostics.max_step == pytest.approx(dt)
    return free, boxed


def test_bounded_value_is_above_the_unbounded_and_the_policy_in_the_box(rng):
    # With the same steps, H_boxed[v] ≥ H_free[v] pointwise (a minimum over a subset) and the
    # explicit step v + Δt H is monotone in v, so by induction v_boxed ≥ v_free at every node
    # and slice (to rounding). The torque limit ±1 binds: the swing-up needs more.
    problem = _pendulum(16)
    free, boxed = _same_steps(problem, (-1.0, 1.0), dt=2e-3)
    scale = np.abs(free.values).max()
    assert np.all(boxed.values >= free.values - 1e-12 * scale)
    assert (boxed.values[0] - free.values[0]).max() > 0.5  # the bound matters (1.04 measured)
    x = np.column_stack([rng.uniform(-4, 4, 300), rng.uniform(-8, 8, 300)])  # partly outside
    for t in (0.0, 0.13, 0.5):
        u = boxed.policy(x, t)
        assert u.shape == (300, 1) and np.all(np.abs(u) <= 1.0)
        # the clipped unconstrained minimiser of ½ r u² + u β ∂v/∂ω (r = 1, β = 1)
        beta_dv = boxed.gradient(x, t)[:, 1]
        np.testing.assert_array_equal(u[:, 0], np.clip(-beta_dv, -1.0, 1.0))


def test_bounds_that_never_bind_change_nothing():
    # Bounds wider than every minimiser the unbounded solve takes leave every minimisation, and
    # so every value, the same: equal to rounding (bitwise, in practice).
    problem = _pendulum(16)
    free, boxed = _same_steps(problem, (-1e3, 1e3), dt=2e-3)
    assert np.abs(free.policy(problem.grid.nodes(), 0.0)).max() < 1e2
    np.testing.assert_allclose(
        boxed.values, free.values, rtol=0, atol=1e-13 * np.abs(free.values).max()
    )


@pytest.mark.parametrize("lo, hi", [(-1.0, 1.0), (-10.0, 10.0), (1.5, 3.0)])
def test_single_integrator_with_a_linear_terminal_cost_is_exact(lo, hi):
    # dx = u dt + noise, q = 0, g(x) = c x, R = r: v = c x + (T − t) min_{lo≤u≤hi} (½ r u² + c u)
    # solves the bounded HJB exactly (∇²v = 0), with u* = clip(−c/r, lo, hi). Upwind differences
    # of a linear function are exact and so is the explicit step of a constant H, so the scheme
    # reproduces v to rounding at nodes the reflecting walls cannot reach: the wall's influence
    # travels against the controlled drift u* (towards +x here, at most 4 units in T = 1) and
    # spreads with the noise and the upwind scheme's own diffusion |u*|h/2 (together a spread of
    # ≤ 0.55 in T), so the wall at 6 is > 7 spreads downstream of x ≤ −2 after the drift.
    from gridlbc.systems import SingleIntegrator

    c, r, T = -4.0, 1.0, 1.0
    grid = Grid([Axis(-6.0, 6.0, 241)])
    problem = Problem(
        SingleIntegrator(), grid, T, lambda x: c * x[:, 0], control_cost=r, temperature=0.1
    )
    solution = solve_hjb(problem, control_bounds=(lo, hi))
    u_star = min(max(-c / r, lo), hi)
    x = grid.nodes()
    inside = (x[:, 0] <= -2.0) & (x[:, 0] >= -4.0)
    for j in (0, 25):
        t = solution.times[j]
        exact = c * x[:, 0] + (T - t) * (0.5 * r * u_star**2 + c * u_star)
        np.testing.assert_allclose(solution.values[j][inside], exact[inside], rtol=0, atol=1e-9)
        np.testing.assert_allclose(solution.policy(x[inside], t)[:, 0], u_star, rtol=0, atol=1e-9)


def test_control_bounds_are_checked():
    problem = _pendulum(8)
    with pytest.raises(ValueError, match=r"control_bounds .*shape \(1, 2\)"):
        solve_hjb(problem, control_bounds=(-1.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="lo > hi"):
        solve_hjb(problem, control_bounds=(1.0, -1.0))
    with pytest.raises(ValueError, match="control_bounds must be numbers"):
        solve_hjb(problem, control_bounds=(np.nan, 1.0))
    with pytest.raises(ValueError, match="control_bounds must be numbers"):
        solve_hjb(problem, control_bounds=(np.inf, np.inf))
    with pytest.raises(TypeError, match="control_bounds"):
        solve_hjb(problem, control_bounds="wide")
    grid = Grid([Axis(-1, 1, 5), Axis(-1, 1, 5)])
    two = Problem(LinearSystem(np.zeros((2, 2)), np.eye(2)), grid, 0.1, Quadratic([0, 0], [1, 1]))
    per_control = solve_hjb(two, control_bounds=[(-1, 1), (0, np.inf)])
    np.testing.assert_array_equal(per_control.control_bounds, [[-1, 1], [0, np.inf]])
    u = per_control.policy(np.random.default_rng(1).uniform(-1, 1, (50, 2)), 0.0)
    assert np.all(np.abs(u[:, 0]) <= 1) and np.all(u[:, 1] >= 0)
    with pytest.raises(ValueError, match="diagonal control_cost"):
        solve_hjb(two.replace(control_cost=[[2.0, 0.5], [0.5, 1.0]]), control_bounds=(-1, 1))


# --- first exit (horizon=None with an exit set) ----------------------------------------------

CORRIDOR_Q, CORRIDOR_R, CORRIDOR_LAM = 1.0, 1.0, 0.5


def _corridor(n, exit_cost=None):
    """dx = u dt + dξ on [0, 2], q = 1, ending at either end (the linear solve's closed-form
    test in tests/core/test_first_exit.py): the HJB and the z-equation are the same PDE."""
    from gridlbc.regions import Box
    from gridlbc.systems import SingleIntegrator

    return Problem(
        SingleIntegrator(),
        Grid([Axis(0.0, 2.0, n)]),
        None,
        state_cost=lambda x: np.full(len(x), CORRIDOR_Q),
        control_cost=CORRIDOR_R,
        temperature=CORRIDOR_LAM,
        exit=Box([-np.inf], [0.0]) | Box([2.0], [np.inf]),
        exit_cost=exit_cost,
    )


def _corridor_exact(x, g0=0.0, g1=1.0):
    k = np.sqrt(2 * CORRIDOR_Q * CORRIDOR_R) / CORRIDOR_LAM
    z0, z1 = np.exp(-g0 / CORRIDOR_LAM), np.exp(-g1 / CORRIDOR_LAM)
    A, B = np.linalg.solve([[1.0, 1.0], [np.exp(2 * k), np.exp(-2 * k)]], [z0, z1])
    return -CORRIDOR_LAM * np.log(A * np.exp(k * x) + B * np.exp(-k * x))


def _exit_costs(y):
    return np.where(y[:, 0] < 1.0, 0.0, 1.0)


def test_first_exit_hjb_converges_to_the_closed_form_at_first_order():
    # Unbounded control: min_u[½Ru² + u v'] = −v'²/2R, and the HJB is the z-equation's PDE,
    # whose solution on the corridor is closed form. The upwind chain is first order: halving h
    # halves the error (measured 0.0184, 0.0093, 0.0047); the policy is −v'/R (exact −1.392).
    x = np.linspace(0.1, 1.9, 7)[:, None]
    errors = []
    for n in (41, 81, 161):
        solution = solve_hjb(_corridor(n, _exit_costs))
        assert solution.diagnostics.method == "policy-iteration"
        assert solution.diagnostics.steps < 20
        errors.append(np.abs(solution.value(x) - _corridor_exact(x[:, 0])).max())
    assert 1.8 < errors[0] / errors[1] < 2.2 and 1.8 < errors[1] / errors[2] < 2.2
    assert errors[-1] < 6e-3
    slope = (_corridor_exact(0.5 + 1e-6) - _corridor_exact(0.5 - 1e-6)) / 2e-6
    assert solution.policy(np.array([0.5]))[0] == pytest.approx(-slope / CORRIDOR_R, rel=5e-3)
    # a first-exit solution ignores time
    assert solution.value(np.array([0.7])) == solution.value(np.array([0.7]), 3.0)


def test_first_exit_policy_iteration_is_the_steady_state_of_the_march():
    problem = _corridor(41, _exit_costs)
    howard = solve_hjb(problem)
    marched = solve_hjb(problem, method="march", tol=1e-10)
    assert marched.diagnostics.method == "markov-chain-march"
    np.testing.assert_allclose(marched.values[0], howard.values[0], atol=1e-8)
    bounded = (-0.5, 0.5)
    np.testing.assert_allclose(
        solve_hjb(problem, control_bounds=bounded, method="march", tol=1e-10).values[0],
        solve_hjb(problem, control_bounds=bounded).values[0],
        atol=1e-8,
    )


def test_first_exit_hjb_agrees_with_the_linear_solve_in_two_dimensions():
    # A point mass parking in one of two bays (the first-exit page's kind of task), unbounded:
    # the value-space solve (first order; its Richardson extrapolation from 41² and 81²) and the
    # z-space solve (gridlbc.solve, 161²) are two discretisations of one PDE. Measured
    # differences ≤ 0.036 on values near 3.
    import gridlbc
    from gridlbc.regions import Ball
    from gridlbc.systems import PointMass

    def problem(n):
        return Problem(
            PointMass(),
            Grid([Axis(-2, 2, n), Axis(-3, 3, n)]),
            None,
            state_cost=lambda x: 0.5 + 0.1 * x[:, 1] ** 2,
            temperature=0.5,
            exit=Ball([1.2, 0.0], [0.3, 0.6]) | Ball([-1.2, 0.0], [0.3, 0.6]),
            exit_cost=lambda x: x[:, 0] ** 2,
        )

    x = np.array([[0.0, 0.0], [0.5, -1.0], [-0.3, 1.0], [1.6, 0.5]])
    coarse, fine = (solve_hjb(problem(n)).value(x) for n in (41, 81))
    linear = gridlbc.solve(problem(161), error_estimate=False).value(x)
    np.testing.assert_allclose(2 * fine - coarse, linear, atol=0.05)
    assert np.all(fine > linear)  # first order from above here: the upwind diffusion's cost


def test_first_exit_hjb_with_bounds():
    problem = _corridor(41, _exit_costs)
    free = solve_hjb(problem)
    wide = solve_hjb(problem, control_bounds=(-100, 100))
    np.testing.assert_allclose(wide.values, free.values, atol=1e-12)
    tight = solve_hjb(problem, control_bounds=(-0.5, 0.5))
    nodes = problem.grid.nodes()
    assert np.all(tight.values[0] >= free.values[0] - 1e-12)
    assert tight.values[0].max() > free.values[0].max() + 0.01
    assert np.abs(tight.policy(nodes)).max() <= 0.5


def test_first_exit_hjb_refuses_bad_input():
    problem = _corridor(21)
    with pytest.raises(ValueError, match="method"):
        solve_hjb(problem, method="newton")
    with pytest.raises(ValueError, match="first-exit"):
        solve_hjb(pointmass_problem(0.5), method="policy")
    with pytest.raises(ValueError, match="tol"):
        solve_hjb(problem, tol=0.0)
    with pytest.raises(TypeError, match="time t"):
        solve_hjb(pointmass_problem(0.5)).value([0.0, 0.0])
    # no state cost, no drift and no noise (B = 0): nothing ever reaches the exit, v undefined
    from gridlbc.regions import Box

    stuck = Problem(
        LinearSystem([[0.0]], [[0.0]]),
        Grid([Axis(-1, 1, 11)]),
        None,
        exit=Box([0.9], [np.inf]),
    )
    with pytest.raises(ValueError, match="undefined"):
        solve_hjb(stuck)
