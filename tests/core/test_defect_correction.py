"""Defect correction of first-exit solves (StationarySettings.defect_correction,
gridlbc.stationary.first_exit._defect_correction): second order on an axis without noise, still one linear
map of the exit values, and the first-order solve kept where z is not resolved."""

import warnings

import numpy as np
import pytest

import gridlbc as g
from gridlbc.regions import Ball, Box
from gridlbc.systems import ControlAffineSystem, PointMass

LAM, R, Q, SPEED = 1.0, 1.0, 1.0, 1.0


class Conveyor(ControlAffineSystem):
    """dx = c dt (no noise: upwind rates, first order), dy = u dt + dξ (y an angle)."""

    state_dim, control_dim = 2, 1

    def drift(self, x):
        x = self._states(x)
        return np.column_stack([np.full(len(x), SPEED), np.zeros(len(x))])

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((len(x), 2, 1))
        B[:, 1, 0] = 1.0
        return B


def conveyor(n, exit_cost=None):
    """The conveyor until x ≥ 1, q = Q, on n cells per unit of x (the exit set's boundary half a
    cell beyond the last node outside it, on every grid) and n nodes round y."""
    h = 1.0 / n
    grid = g.Grid([g.Axis(h / 2, 1 + 2.5 * h, n + 3), g.Axis(-np.pi, np.pi, n, periodic=True)])
    if exit_cost is None:
        exit_cost = lambda x: -LAM * np.log(2 + np.cos(x[:, 1]))  # noqa: E731
    return g.Problem(
        Conveyor(),
        grid,
        None,
        state_cost=lambda x: np.full(len(x), Q),
        control_cost=R,
        temperature=LAM,
        exit=Box([1.0, -np.inf], [np.inf, np.inf]),
        exit_cost=exit_cost,
    )


def conveyor_exact(x):
    """With s = (1 − x)/c the time to the exit and D = λ/(2R) the noise along y:
    z = e^{−Qs/λ} (2 + e^{−Ds} cos y), the heat semigroup of z_E = 2 + cos y."""
    s = (1 - x[:, 0]) / SPEED
    return Q * s - LAM * np.log(2 + np.exp(-LAM / (2 * R) * s) * np.cos(x[:, 1]))


def nodal_errors(steps, sizes=(16, 32, 64)):
    errors = []
    for n in sizes:
        problem = conveyor(n)
        solution = g.solve(problem, defect_correction=steps, error_estimate=False)
        x = problem.grid.nodes()
        x = x[(x[:, 0] > 0.1) & (x[:, 0] < 0.9)]
        errors.append(np.abs(solution.value(x) - conveyor_exact(x)).max())
    return np.array(errors)


@pytest.mark.parametrize("steps", [1, 2])
def test_defect_correction_raises_the_order_from_one_to_two(steps):
    # The upwind rate along x is first order (numerical diffusion c h/2): halving h halves the
    # error. One or two steps of defect correction with the second-order L₂ make it second
    # order: halving h divides the error by 4; 3.5 (an observed order of 1.8) allows for the
    # next term, and the plain solve's halving ratio must lie within 2 ± 0.3.
    plain = nodal_errors(0)
    corrected = nodal_errors(steps)
    assert np.all(np.abs(plain[:-1] / plain[1:] - 2) < 0.3)
    assert np.all(corrected[:-1] / corrected[1:] > 3.5)
    assert corrected[-1] < plain[-1] / 50


def test_defect_corrected_exit_costs_combine_exactly():
    # Each step is linear in the exit values: solve_many's solutions combine into the direct
    # solve of the composite exit cost, and a solve of one exit cost equals its solve_many twin.
    g1 = lambda x: 0.5 * (1 - np.cos(x[:, 1]))  # noqa: E731
    g2 = lambda x: 0.5 * (1 + np.sin(x[:, 1]))  # noqa: E731
    w = np.array([0.3, 0.7])
    base = conveyor(32)
    parts = g.solve_many(base, [g1, g2], defect_correction=2, error_estimate=False)
    assert all(p.operator.method.endswith("+dc2") for p in parts)
    combined = g.combine(parts, w)
    assert combined.exact

    def composite(x):
        return -LAM * np.log(w[0] * np.exp(-g1(x) / LAM) + w[1] * np.exp(-g2(x) / LAM))

    direct = g.solve(base.replace(exit_cost=composite), defect_correction=2, error_estimate=False)
    x = base.grid.nodes()[::7]
    np.testing.assert_allclose(combined.value(x), direct.value(x), rtol=1e-12, atol=1e-12)
    alone = g.solve(base.replace(exit_cost=g1), defect_correction=2, error_estimate=False)
    np.testing.assert_allclose(alone.value(x), parts[0].value(x), rtol=1e-12, atol=1e-12)
    plain = g.solve(base.replace(exit_cost=g1), error_estimate=False)
    assert not g.combine([plain, alone]).exact  # another linear map


def test_defect_correction_keeps_the_first_order_solve_where_z_is_not_resolved():
    # A point mass docking in a small ball at λ = 0.05: v changes by many λ across a cell, a
    # correction step makes z negative, and the solve says so and keeps the first-order z.
    grid = g.Grid([g.Axis(-2, 2, 61), g.Axis(-2, 2, 61)])
    problem = g.Problem(
        PointMass(),
        grid,
        None,
        state_cost=lambda x: 1.0 + x[:, 0] ** 2,
        temperature=0.05,
        exit=Ball([0.0, 0.0], [0.1, 0.1]),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", g.ResolutionWarning)
        plain = g.solve(problem, error_estimate=False)
    with pytest.warns(g.ResolutionWarning, match="defect correction made z ≤ 0"):
        kept = g.solve(problem, defect_correction=1, error_estimate=False)
    x = grid.nodes()[::11]
    np.testing.assert_array_equal(kept.value(x), plain.value(x))
    assert kept.operator == plain.operator


@pytest.mark.parametrize(
    "options, match",
    [
        ({"defect_correction": -1}, "number of steps"),
        ({"defect_correction": 1.5}, "number of steps"),
        ({"defect_correction": True}, "number of steps"),
        ({"defect_correction": 1, "fit_exit": False}, "fit_exit"),
    ],
)
def test_bad_defect_correction_settings_are_refused(options, match):
    with pytest.raises(ValueError, match=match):
        g.solve(conveyor(8), **options)
