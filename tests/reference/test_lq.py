"""Grid solutions against the exact Riccati solution (docs/maths.rst, "Exact references";
gridlbc.reference.lq)."""

import numpy as np
import pytest
from conftest import EXACTNESS_ONLY

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.reference import lq_solution
from gridlbc.studies.problems import pointmass_problem
from gridlbc.systems import Pendulum, PointMass, SingleIntegrator


def test_riccati_matches_closed_form_for_single_integrator():
    """Scalar case, q = 0: P(t) = P_T / (1 + P_T S (T − t)), p = P c-shifted, c₀ from the ODE."""
    lam, r, w, c, T = 0.7, 2.0, 1.5, 0.4, 1.3
    grid = Grid([Axis(-3, 3, 11)])
    problem = Problem(
        SingleIntegrator(), grid, T, Quadratic([c], [w]), control_cost=r, temperature=lam
    )
    exact = lq_solution(problem)
    S = 1 / r
    for t in (0.0, 0.6, T):
        tau = T - t
        P = 2 * w / (1 + 2 * w * S * tau)
        # v = ½P(x − c)² + (λ/2) ∫ S P dτ = ½P(x − c)² + (λ/2) log(1 + 2wSτ)
        x = np.array([[-1.0], [0.3], [2.0]])
        v = 0.5 * P * (x[:, 0] - c) ** 2 + 0.5 * lam * np.log(1 + 2 * w * S * tau)
        np.testing.assert_allclose(exact.value(x, t), v, rtol=1e-10)
        np.testing.assert_allclose(exact.policy(x, t)[:, 0], -S * P * (x[:, 0] - c), rtol=1e-10)


def test_lq_solution_rejects_nonlinear_and_periodic():
    grid = Grid([Axis(-np.pi, np.pi, 8, periodic=True), Axis(-1, 1, 5)])
    with pytest.raises(TypeError, match="linear system"):
        lq_solution(Problem(Pendulum(), grid, 1.0, Quadratic([0, 0], [1, 1])))
    with pytest.raises(ValueError, match="periodic"):
        lq_solution(Problem(PointMass(), grid, 1.0, Quadratic([0, 0], [1, 1])))
    closed = Grid([Axis(-1, 1, 5), Axis(-1, 1, 5)])
    with pytest.raises(TypeError, match="Quadratic"):
        lq_solution(Problem(PointMass(), closed, 1.0, lambda x: x[:, 0] ** 2))


def _errors(problem, method, region, **options):
    """max |Δv|, mean |Δv|, mean |Δu| at t = 0 over the query states of ``region``."""
    exact = lq_solution(problem)
    sol = gridlbc.solve(problem, method=method, error_estimate=False, **options)
    nodes = problem.grid.nodes()
    x = region(nodes, exact)
    dv = np.abs(sol.value(x, 0.0) - exact.value(x, 0.0))
    du = np.abs(sol.policy(x, 0.0) - exact.policy(x, 0.0))
    return dv.max(), dv.mean(), du.mean()


def _orders(errors):
    e = np.asarray(errors)
    return np.log2(e[:-1] / e[1:])


def _pointmass(n):
    return pointmass_problem(grid=Grid([Axis(-4.0, 4.0, n), Axis(-6.0, 6.0, n)]))


def _low_cost_interior(nodes, exact):
    """Fixed query states: |position| < 2, |velocity| < 3 and v < min v + 5 (boundary-free)."""
    g = np.stack(np.meshgrid(np.linspace(-2, 2, 41), np.linspace(-3, 3, 41)), -1).reshape(-1, 2)
    v = exact.value(g, 0.0)
    return g[v < v.min() + 5]


@EXACTNESS_ONLY
@pytest.mark.parametrize("method", ["splitting", "implicit"])
def test_point_mass_converges_to_riccati_at_first_order(method):
    # A fixed Courant number (and no minimum step count) makes Δt ∝ h; the plain operators.
    errs = np.array(
        [
            _errors(
                _pointmass(n), method, _low_cost_interior, courant=2.0, min_steps=1, fitting=None
            )
            for n in (51, 101, 201)
        ]
    )
    orders = _orders(errs)
    # Both schemes are first order in h (dt ∝ h at a fixed Courant number): each error halves
    # per refinement once asymptotic (measured orders 0.78–0.95 for the value, 0.7–0.8 for the
    # mean policy error on these grids, rising towards 1 on finer ones). Require monotone
    # decrease, value orders in [0.7, 1.5] and policy orders above 0.6.
    assert np.all(np.diff(errs, axis=0) < 0), errs
    assert np.all((orders[:, :2] > 0.7) & (orders[:, :2] < 1.5)), orders
    assert np.all(orders[:, 2] > 0.6), orders
    assert errs[-1, 0] < 0.5  # max |Δv| at h = 0.04 (absolute sanity bound, v ~ 1–5 here)


def test_fitted_point_mass_converges_to_riccati_at_second_order():
    """The fitted splitting scheme (the default), whose drift averages log z over the simplex
    with its curvature term (exact for the quadratic log z of an LQ problem), at the same fixed
    Courant number: second order in h (measured 1.98–2.25 for the value, 1.9 for the policy on
    these grids). Require monotone decrease and orders above 1.5 (policy 1.4)."""
    errs = np.array(
        [
            _errors(
                _pointmass(n),
                "splitting",
                _low_cost_interior,
                courant=2.0,
                min_steps=1,
                fitting="terminal",
            )
            for n in (51, 101, 201)
        ]
    )
    orders = _orders(errs)
    assert np.all(np.diff(errs, axis=0) < 0), errs
    assert np.all((orders[:, :2] > 1.5) & (orders[:, :2] < 2.7)), orders
    assert np.all(orders[:, 2] > 1.4), orders


@EXACTNESS_ONLY
@pytest.mark.parametrize("method", ["splitting", "implicit"])
def test_single_integrator_converges_to_riccati(method):
    def problem(n):
        grid = Grid([Axis(-5.0, 5.0, n)])
        return Problem(
            SingleIntegrator(),
            grid,
            1.0,
            Quadratic([0.5], [3.0]),
            state_cost=Quadratic([-0.5], [0.4]),
            control_cost=0.5,
            temperature=0.3,
        )

    def region(nodes, exact):
        return np.linspace(-2, 2, 81)[:, None]

    # No drift, so the default Δt would stay at T/min_steps: refine Δt with h (Δt ∝ h) so that
    # the O(Δt) splitting/backward-Euler error and the O(h²) diffusion error both shrink.
    errs = np.array(
        [_errors(problem(n), method, region, dt=2.0 / (n - 1)) for n in (101, 201, 401)]
    )
    orders = _orders(errs)
    assert np.all(np.diff(errs, axis=0) < 0), errs
    assert np.all(orders > 0.8), orders


def test_reference_is_reachable_as_an_attribute():
    """The documented call form (docs/api.rst): ``gridlbc.reference.lq_solution`` after a plain
    ``import gridlbc``."""
    assert gridlbc.reference.lq_solution is lq_solution
    assert callable(gridlbc.reference.solve_hjb)
