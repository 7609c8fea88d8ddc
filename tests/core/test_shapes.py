"""One convention for the shape of an evaluation's result (gridlbc.problem.state_evaluation,
docs/api.rst "Result shapes"): states (N, d) give values (N,), controls (N, m) and blend weights
(N, n); one state (d,) gives a scalar value, a control (m,) and blend weights (n,), the first row
of the same state given as (1, d). Every kind of solution follows it."""

import warnings

import numpy as np
import pytest

import gridlbc as g
from gridlbc.reference import lq_solution, solve_hjb
from gridlbc.systems import PointMass
from gridlbc.trajectory import expand, optimize

X = np.array([[0.3, -0.4], [-1.0, 0.5], [0.0, 0.0]])


def _problem(center=(1.0, 0.0)):
    grid = g.Grid([g.Axis(-3, 3, 13), g.Axis(-3, 3, 13)])
    return g.Problem(
        PointMass(), grid, 0.5, g.Quadratic(center, [2.0, 0.5]), control_cost=0.5, temperature=0.7
    )


def _evaluated():
    """(name, object, the methods to check) for each kind of solution."""
    problem = _problem()
    other = problem.replace(terminal_cost=g.Quadratic([-1.0, 0.0], [2.0, 0.5]))
    plain = g.solve(problem, dt=0.05, fitting=None)
    fitted = g.solve(problem, dt=0.05)  # log z
    pair = g.solve_many(problem, [problem.terminal_cost, other.terminal_cost], dt=0.05)
    tape = optimize(problem, X[1], restarts=1, n_intervals=10)
    component = expand(problem, tape)
    fields = ("value", "log_desirability", "desirability", "policy")
    grid_fields = (*fields, "error_estimate")
    return [
        ("linear Solution", plain, grid_fields),
        ("log Solution", fitted, grid_fields),
        ("relative Solution", pair[0], grid_fields),
        ("CombinedSolution", g.combine(pair), (*grid_fields, "blend_weights")),
        ("Combination", g.combine([plain, fitted]), (*fields, "blend_weights")),
        ("TrajectoryExpansion", component, (*fields, "mahalanobis", "deviation")),
        ("LQSolution", lq_solution(problem), ("value", "policy")),
        ("HJBSolution", solve_hjb(problem, slices=5), ("value", "gradient", "policy")),
    ]


@pytest.fixture(scope="module")
def evaluated():
    with warnings.catch_warnings():  # 13² is far too coarse to be accurate: shapes only
        warnings.simplefilter("ignore", g.ResolutionWarning)
        return _evaluated()


def test_one_state_gives_the_first_row_and_arrays_keep_their_rows(evaluated):
    for name, solution, methods in evaluated:
        for method in methods:
            evaluate = getattr(solution, method)
            many = np.asarray(evaluate(X, 0.1))
            one = evaluate(X[0], 0.1)
            assert many.shape[0] == len(X), (name, method, many.shape)
            assert np.shape(one) == many.shape[1:], (name, method, np.shape(one))
            np.testing.assert_array_equal(one, evaluate(X[:1], 0.1)[0], err_msg=f"{name}.{method}")
            if method == "error_estimate":
                # its sampled terms draw one stream per call, which the batch divides among its
                # states: a state's paths, and so its estimate, differ between batches by their
                # sampling noise (Solution.error_estimate)
                np.testing.assert_allclose(one, many[0], rtol=0.25)
                continue
            # the same numbers as in a batch, to rounding (a batch shares one log-scale)
            np.testing.assert_allclose(one, many[0], rtol=1e-13, atol=1e-13)


def test_a_single_value_is_a_float(evaluated):
    for name, solution, _ in evaluated:
        value = solution.value([0.3, -0.4], 0.0)
        assert np.ndim(value) == 0 and isinstance(float(value), float), name
        assert solution.policy([0.3, -0.4], 0.0).shape == (1,), name


def test_a_wrong_single_state_is_named_as_given(evaluated):
    for _, solution, _ in evaluated:
        with pytest.raises(ValueError, match=r"\(3,\)"):
            solution.value([0.3, -0.4, 1.0], 0.0)
