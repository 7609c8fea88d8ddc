"""simulate: Euler–Maruyama rollouts, checked against exact moments and the Riccati optimum.

Statistical checks use fixed seeds and bounds of a few standard errors; the Euler–Maruyama bias
is exactly zero for the linear systems used where stated, O(Δt) otherwise.
"""

import numpy as np
import pytest
from conftest import line, lq_point_mass

import gridlbc as g
from gridlbc.reference import lq_solution
from gridlbc.simulate import em_kernel, em_step_numpy, fold_kernel, reflect_into_box, wrap_kernel
from gridlbc.systems import Pendulum


def _line(temperature=1.0, control_cost=1.0, horizon=1.0, state_cost=None, n=41):
    return line(
        n, horizon, state_cost=state_cost, control_cost=control_cost, temperature=temperature
    )


def _zero(x, t):
    return np.zeros((x.shape[0], 1))


def test_kernel_matches_numpy_reference(rng):
    n, d, m = 57, 3, 2
    x, drift = rng.normal(size=(n, d)), rng.normal(size=(n, d))
    B, u, eps = rng.normal(size=(n, d, m)), rng.normal(size=(n, m)), rng.normal(size=(n, m))
    noise = np.tril(rng.normal(size=(m, m)))
    M = rng.normal(size=(m, m))
    R = M @ M.T + np.eye(m)
    out, cost, ito = np.empty((n, d)), np.full(n, 0.25), np.full(n, -0.5)
    em_kernel(x, drift, B, u, eps, noise, R, 0.01, out, cost, ito)
    x_ref, c_ref, ito_ref = em_step_numpy(x, drift, B, u, eps, noise, R, 0.01)
    np.testing.assert_allclose(out, x_ref, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(cost, 0.25 + c_ref, rtol=1e-13)
    np.testing.assert_allclose(ito, -0.5 + ito_ref, rtol=1e-12, atol=1e-14)


def test_deterministic_constant_control_is_exact():
    # ẋ = u = c: x_T = x0 + cT; J = ½ R c² T + g(x_T) (the rectangle rule is exact here).
    problem = _line(control_cost=2.0)
    r = g.simulate(
        problem, lambda x, t: np.full((x.shape[0], 1), 0.5), [0.25], n_samples=3, noise=False
    )
    np.testing.assert_allclose(r.final_states[:, 0], 0.75, rtol=1e-13)
    np.testing.assert_allclose(r.costs, 0.5 * 2.0 * 0.25 + 0.75**2, rtol=1e-13)
    assert r.states.shape == (3, 301, 1) and r.controls.shape == (3, 300, 1)
    assert r.times[0] == 0 and r.times[-1] == problem.horizon


def test_noise_covariance_and_state_cost():
    # u = 0: x_T ~ N(x0, λ R⁻¹ T) exactly under Euler–Maruyama. With q = x² the expected running
    # cost is ∫ (x0² + λt/R) dt, of which the left rectangle rule gives Σ (x0² + λ t_k/R) Δt.
    lam, r_cost, T, x0, n = 0.5, 2.0, 1.0, 0.3, 20000
    problem = _line(lam, r_cost, T, state_cost=g.Quadratic([0], [1]))
    r = g.simulate(problem, _zero, [x0], n_samples=n, dt=0.01, seed=3)
    var = lam / r_cost * T
    xT = r.final_states[:, 0]
    assert abs(xT.mean() - x0) < 4 * np.sqrt(var / n)
    assert abs(xT.var(ddof=1) - var) < 4 * var * np.sqrt(2 / (n - 1))
    t = r.times[:-1]
    expected = np.sum(x0**2 + lam * t / r_cost) * r.dt + x0**2 + var
    assert abs(r.mean_cost - expected) < 4 * r.standard_error


def test_seed_reproduces_and_different_seeds_differ():
    problem = _line()
    a = g.simulate(problem, _zero, [0.0], n_samples=5, seed=7)
    b = g.simulate(problem, _zero, [0.0], n_samples=5, seed=7)
    c = g.simulate(problem, _zero, [0.0], n_samples=5, seed=8)
    np.testing.assert_array_equal(a.states, b.states)
    np.testing.assert_array_equal(a.costs, b.costs)
    assert not np.array_equal(a.states, c.states)


def test_periodic_axis_wraps_and_box_exits_are_counted():
    grid = g.Grid([g.Axis(-np.pi, np.pi, 16, periodic=True), g.Axis(-2, 2, 9)])
    problem = g.Problem(Pendulum(gravity=0.0), grid, 1.0, g.Quadratic([0, 0], [1, 1]))
    # ω = 1.5 constant (no gravity, no control): θ runs 1.5 rad past +π and wraps.
    r = g.simulate(
        problem,
        lambda x, t: np.zeros((x.shape[0], 1)),
        [[3.0, 1.5], [0.0, 0.0]],
        n_samples=2,
        noise=False,
    )
    theta = r.states[:, :, 0]
    assert np.all((theta >= -np.pi) & (theta < np.pi))
    np.testing.assert_allclose(r.final_states[0, 0], 4.5 - 2 * np.pi, rtol=1e-12)
    assert r.n_left_box == 0
    push = g.simulate(
        problem, lambda x, t: np.full((x.shape[0], 1), 5.0), [0.0, 0.0], noise=False
    )  # ω reaches 5 > 2: leaves the ω range of the box
    assert push.n_left_box == 1


def test_grid_policy_cost_matches_riccati():
    # The grid policy's mean cost vs the exact optimum: within 3 SE plus the discretisation error
    # |v_grid − v_riccati| measured at this grid (the policy error enters the cost only at second
    # order, so this is generous). The Riccati policy itself must match within 3 SE + O(Δt) bias.
    problem = lq_point_mass(61)
    x0 = np.array([1.0, -0.5])
    exact = lq_solution(problem)
    v_exact = float(exact.value(x0, 0.0))
    # the policy's cost against the optimum, not the value's error (5.9 % near (0.33, −0.6),
    # which the default solve warns of): no estimate
    sol = g.solve(problem, error_estimate=False)
    discretisation = abs(float(sol.value(x0, 0.0)) - v_exact)
    grid_run = g.simulate(problem, sol.policy, x0, n_samples=4000, seed=11)
    assert abs(grid_run.mean_cost - v_exact) < 3 * grid_run.standard_error + discretisation
    exact_run = g.simulate(problem, exact.policy, x0, n_samples=4000, seed=12)
    bias = 2 * grid_run.dt * v_exact  # O(Δt) weak error of Euler–Maruyama, generous constant
    assert abs(exact_run.mean_cost - v_exact) < 3 * exact_run.standard_error + bias


@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        ({"x0": [np.nan]}, ValueError, "x0 has a non-finite"),
        ({"x0": [0.0, 1.0]}, ValueError, "x0 must have shape"),
        ({"x0": [[0.0], [1.0]], "n_samples": 3}, ValueError, "2 rows but n_samples = 3"),
        ({"n_samples": 0}, ValueError, "at least 1"),
        ({"n_samples": 2.5}, TypeError, "integer"),
        ({"dt": -0.1}, ValueError, "dt must lie"),
        ({"dt": 5.0}, ValueError, "dt must lie"),
        ({"policy": lambda x, t: np.zeros(x.shape[0])}, ValueError, r"shape \(N, m\) = \(1, 1\)"),
        ({"policy": lambda x, t: np.full((x.shape[0], 1), np.nan)}, ValueError, "non-finite"),
        ({"policy": "u"}, TypeError, "callable"),
    ],
)
def test_bad_input(kwargs, error, match):
    args = {"problem": _line(), "policy": _zero, "x0": [0.0]}
    args.update(kwargs)
    with pytest.raises(error, match=match):
        g.simulate(**args)
    with pytest.raises(TypeError, match="Problem"):
        g.simulate("problem", _zero, [0.0])


def test_reflect_folds_back_as_often_as_needed():
    # Mirror images at lo and hi: lo − 2.5L → lo + 2.5L → hi − 1.5L = lo − 0.5L → lo + 0.5L.
    lo, hi = np.array([-1.0, 0.0]), np.array([1.0, 5.0])
    x = np.array([[-6.0, 1.0], [1.5, 2.0], [0.3, 7.0], [3.2, -0.5]])
    folded = reflect_into_box(x.copy(), lo, hi, np.array([True, False]))
    np.testing.assert_allclose(folded[:, 0], [0.0, 0.5, 0.3, -0.8], atol=1e-15)
    np.testing.assert_array_equal(folded[:, 1], x[:, 1])  # not a closed axis here
    assert folded[2, 0] == 0.3  # inside: untouched


def test_the_step_wraps_periodic_coordinates_and_flags_and_folds_closed_ones():
    # the compiled box step: periodic coordinates as Grid.wrap puts them, a sample marked where
    # a closed coordinate left [lo, hi], and folded only where its row asks
    grid = g.Grid([g.Axis(-np.pi, np.pi, 9, periodic=True), g.Axis(0.0, 2.0, 5)])
    lo, hi, periodic = grid.lo, grid.hi, grid.periodic
    x = np.array([[4.0, 1.0], [-7.5, 2.5], [0.1, -0.3], [3.0, 2.0], [10.0, -5.0]])
    wrapped = x.copy()
    outside = np.zeros(len(x), dtype=bool)
    wrap_kernel(wrapped, lo, hi, periodic, outside)
    np.testing.assert_array_equal(wrapped[:, 0], grid.wrap(x)[:, 0])
    np.testing.assert_array_equal(wrapped[:, 1], x[:, 1])
    np.testing.assert_array_equal(outside, [False, True, True, False, True])
    rows = np.array([True, True, False, True, True])
    fold_kernel(wrapped, lo, hi, ~periodic, rows)
    np.testing.assert_allclose(wrapped[[1, 4], 1], [1.5, 1.0], atol=1e-15)  # 2.5 → 1.5, −5 → 1
    assert wrapped[2, 1] == -0.3  # its row was not asked to fold
    assert wrapped[3, 1] == 2.0  # on the edge: inside


def _free_and_reflected(half_width, temperature, n_samples, seed):
    """Uncontrolled rollouts from 0 on [−half_width, half_width], free and reflected."""
    box = g.Grid([g.Axis(-half_width, half_width, 11)])
    problem = line(11, temperature=temperature)
    problem = g.Problem(problem.system, box, 1.0, problem.terminal_cost, temperature=temperature)
    zero = lambda x, t: np.zeros((x.shape[0], 1))  # noqa: E731
    return tuple(
        g.simulate(problem, zero, [0.0], n_samples=n_samples, seed=seed, boundary=b)
        for b in ("free", "reflect")
    )


def test_reflect_keeps_every_sample_in_the_box():
    # A narrow box and fast noise: most paths reach an edge, none ends up outside it.
    free, reflected = _free_and_reflected(0.3, 1.0, 400, 2)
    assert np.any(np.abs(free.states) > 0.3)
    assert np.all(np.abs(reflected.states) <= 0.3)
    assert reflected.left_box.mean() > 0.5 and reflected.boundary == "reflect"


def test_reflect_far_from_the_edges_changes_nothing():
    # σ = √(λT) = 0.7 against edges at ±6 (8.5σ): no path reaches them, so the folded and free
    # rollouts are the same numbers (a state inside the box is never touched).
    free, reflected = _free_and_reflected(6.0, 0.5, 2000, 3)
    assert not free.left_box.any()
    np.testing.assert_array_equal(free.states, reflected.states)
    np.testing.assert_array_equal(free.costs, reflected.costs)


def test_boundary_is_checked():
    problem = line(11)
    zero = lambda x, t: np.zeros((x.shape[0], 1))  # noqa: E731
    with pytest.raises(ValueError, match="boundary must be one of"):
        g.simulate(problem, zero, [0.0], boundary="wall")
    free_space = g.Problem(problem.system, None, 1.0, problem.terminal_cost)
    with pytest.raises(ValueError, match="needs the problem's grid"):
        g.simulate(free_space, zero, [0.0], boundary="reflect")


def test_the_bridge_does_not_invent_crossings_of_a_curved_exit():
    """A point mass (noise on the velocity only, λ = 2) 0.02 outside a ball of radius 0.4, its
    normal nearly along the position: in 0.04 it moves about 0.002 in position and cannot reach
    the ball (256 steps of the exact chain: no exit). The tangent plane at the nearest point
    holds the ball and, tilted by the velocity, is reached by the velocity's noise: the flat rule
    over one step stopped 16 % of the paths there (stranger round 34's Duffing certificate at
    Δt = 0.004 was 38 % low for it). Halving the bridge where a crossing is plausible brings one
    step to the fine chain: at most a few stops in 20 000 (binomial: 0 expected)."""
    problem = g.Problem(
        g.systems.PointMass(),
        g.Grid([g.Axis(-2.0, 2.0, 9), g.Axis(-3.0, 3.0, 9)]),
        0.04,
        terminal_cost=lambda x: np.zeros(len(x)),
        temperature=2.0,
        exit=g.regions.Ball([1.0, 0.0], 0.4),
        exit_cost=0.0,
    )
    x0 = np.array([0.58, 0.05])
    fine = g.simulate(problem, _zero, x0, n_samples=20_000, dt=0.04 / 256, seed=1)
    one = g.simulate(problem, _zero, x0, n_samples=20_000, dt=0.04, seed=2)
    assert np.isnan(fine.exit_times).all()
    assert np.sum(~np.isnan(one.exit_times)) <= 20


def test_the_bridge_halves_a_step_as_deep_as_a_thin_exit_needs():
    """An ellipse 0.027 wide in position and 0.2 in velocity, a point mass beside its tip whose
    velocity's noise over one step (σ√Δt = 2 over Δt = 0.04) is 70 times the tip's radius of
    curvature: the tangent plane there is crossed by most paths where the ellipse is reached by
    about a fifth (stranger round 44's certificate was 27 % low for it at Δt = 0.004). With the
    halving stopped at six levels one step stopped 70 % of 20 000 paths, against 22–24 % for the
    chain of 256 steps; halving until a crossing is implausible brings one step to it. The
    tolerance, 0.05 of the paths, is four binomial standard deviations of the difference (0.017)
    and the chains' own spread over their steps (1, 8 and 1024 steps: 0.23, 0.25 and 0.22)."""
    problem = g.Problem(
        g.systems.PointMass(),
        g.Grid([g.Axis(-2.0, 2.0, 9), g.Axis(-4.0, 4.0, 9)]),
        0.04,
        terminal_cost=lambda x: np.zeros(len(x)),
        control_cost=0.01,
        temperature=1.0,
        exit=g.regions.Ball([0.0, 1.5], [0.027, 0.2]),
        exit_cost=0.0,
    )
    x0 = np.array([0.025, 0.9])
    stopped = [
        np.mean(~np.isnan(g.simulate(problem, _zero, x0, 20_000, dt=dt, seed=1).exit_times))
        for dt in (0.04, 0.04 / 256)
    ]
    assert abs(stopped[0] - stopped[1]) <= 0.05


def test_a_step_over_an_exit_thinner_than_it_stops_along_an_axis_without_noise():
    """A point mass at position 0.45 moving at 5, Euler step 0.04: its position moves 0.2 in a
    step whatever the noise does to its velocity, straight over a slab of positions 0.05 wide
    ([0.5, 0.55], any velocity) that no step's end lies in, and the bridge has no noise across
    the slab. Every path enters it during the first step, exactly; before the straight part of
    a step was tested against E none did (stranger round 45's slab, certified 7 % high). Without
    noise, the deterministic path crosses an ellipse 0.04 wide in position during its second
    step, exactly."""

    def problem(exit):
        return g.Problem(
            g.systems.PointMass(),
            g.Grid([g.Axis(-2.0, 2.0, 9), g.Axis(-8.0, 8.0, 9)]),
            1.0,
            terminal_cost=lambda x: np.zeros(len(x)),
            temperature=1.0,
            exit=exit,
            exit_cost=0.0,
        )

    slab = problem(g.regions.Box([0.5, -np.inf], [0.55, np.inf]))
    noisy = g.simulate(slab, _zero, [0.45, 5.0], 2000, dt=0.04, seed=1)
    assert np.all(noisy.exit_times == 0.04)
    thin = problem(g.regions.Ball([0.5, 5.0], [0.02, 1.0]))
    path = g.simulate(thin, _zero, [-0.1, 5.0], 1, dt=0.1, noise=False)
    assert path.exit_times[0] == pytest.approx(0.2)  # positions −0.1, 0.4, 0.9: over it


def test_the_bridge_sees_both_sides_of_a_gap_between_two_parts_of_the_exit():
    """A Brownian motion (σ² = λ = 0.4) in the gap |x| < a = 0.06 between two half-lines of the
    exit set, over one step of 0.01 (σ√Δt = 0.063, the gap's half width): it leaves with the
    probability 1 − (4/π) Σ_n (−1)ⁿ/(2n+1) exp(−(2n+1)² π² σ² Δt / (8a²)) = 0.6767. Judging the
    nearest part alone stopped 0.652 of 20 000 paths (stranger round 45's slab between two
    half-spaces, certified 1 % high); each part judged, and the step halved where both are
    within reach, one step stops the exact share within four binomial standard deviations."""
    a, variance, dt, n = 0.06, 0.4, 0.01, 20_000
    problem = g.Problem(
        g.systems.LinearSystem(np.zeros((1, 1)), np.eye(1)),
        g.Grid([g.Axis(-1.0, 1.0, 21)]),
        dt,
        terminal_cost=lambda x: np.zeros(len(x)),
        temperature=variance,
        exit=g.regions.Box([-np.inf], [-a]) | g.regions.Box([a], [np.inf]),
        exit_cost=0.0,
    )
    k = np.arange(50)
    rate = (2 * k + 1) ** 2 * np.pi**2 * variance * dt / (8 * a**2)
    exact = 1.0 - 4.0 / np.pi * np.sum((-1.0) ** k / (2 * k + 1) * np.exp(-rate))
    one = g.simulate(problem, _zero, [0.0], n, dt=dt, seed=1)
    stopped = np.mean(~np.isnan(one.exit_times))
    assert abs(stopped - exact) <= 4 * np.sqrt(exact * (1 - exact) / n)
