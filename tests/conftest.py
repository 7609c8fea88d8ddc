"""Shared fixtures: seeded random numbers, strict floating point, headless matplotlib."""

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")


@pytest.fixture(autouse=True)
def _strict_floating_point():
    old = np.seterr(all="raise", under="ignore")
    yield
    np.seterr(**old)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


# -- problem factories shared by the test modules (the studies' named problems live in
# gridlbc.studies.problems; these are the small variants the unit tests use) ----------------------


def pendulum(
    n=24, omega_max=6.0, omega_nodes=None, horizon=1.0, weights=(2.0, 0.2), system=None, **options
):
    """Pendulum on θ periodic [−π, π) (``n`` nodes) × ω ∈ [−ω_max, ω_max] (``omega_nodes``,
    default n + 1), g = xᵀdiag(weights)x; ``options`` go to :class:`gridlbc.Problem`."""
    import gridlbc as g
    from gridlbc.systems import Pendulum

    grid = g.Grid(
        [
            g.Axis(-np.pi, np.pi, n, periodic=True),
            g.Axis(-omega_max, omega_max, n + 1 if omega_nodes is None else omega_nodes),
        ]
    )
    return g.Problem(
        Pendulum() if system is None else system,
        grid,
        horizon,
        g.Quadratic([0.0, 0.0], list(weights)),
        **options,
    )


def lq_point_mass(n=41):
    """The linear-quadratic point mass on [−4, 4]² (``n`` nodes per axis), T = 1, λ = 0.5, R = 2,
    with a state cost: its exact value is gridlbc.reference.lq_solution's (Riccati)."""
    import gridlbc as g
    from gridlbc.systems import PointMass

    grid = g.Grid([g.Axis(-4, 4, n), g.Axis(-4, 4, n)])
    return g.Problem(
        PointMass(),
        grid,
        1.0,
        g.Quadratic([0, 0], [2, 1]),
        state_cost=g.Quadratic([0, 0], [0.5, 0.1]),
        control_cost=2.0,
        temperature=0.5,
    )


def line(n=41, horizon=1.0, **options):
    """SingleIntegrator on [−3, 3] with ``n`` nodes and g = x²; ``options`` go to Problem."""
    import gridlbc as g
    from gridlbc.systems import SingleIntegrator

    return g.Problem(
        SingleIntegrator(), g.Grid([g.Axis(-3, 3, n)]), horizon, g.Quadratic([0], [1]), **options
    )


POINTMASS_TOML = """
horizon = 1.0
temperature = 0.5
[system]
name = "PointMass"
[grid]
n = 21
[terminal_cost]
center = [{c}, 0]
weights = [4, 1]
[solver]
dt = 0.05
"""
"""A PointMass problem description (TOML) with its goal at position ``{c}``."""


def pointmass_description(c):
    """:data:`POINTMASS_TOML` with goal ``c``, parsed to a dict."""
    import tomllib

    return tomllib.loads(POINTMASS_TOML.format(c=c))


# -- expected warnings ------------------------------------------------------------------------------
# The suite turns every gridlbc warning into an error (pyproject's filterwarnings), so a new one is
# never missed. Tests that expect one either assert it with pytest.warns or carry one of these
# marks, whose names say why the warning is not the subject of the test.

EXACTNESS_ONLY = pytest.mark.filterwarnings("ignore::gridlbc.errors.ResolutionWarning")
"""For tests of exact properties of the discrete operator (linearity, superposition, storage,
agreement of two linear solvers, orders of convergence measured over a refinement): they solve
coarse grids on purpose, where the solver rightly warns that the values are not accurate."""

ESTIMATE_ABOVE_TOLERANCE = pytest.mark.filterwarnings(
    "ignore:the estimated error:gridlbc.errors.ResolutionWarning"
)
"""For tests on grids where the solve's own error estimate (first-order, so conservative: several
times the actual error on smooth problems at coarse grids, docs/accuracy.rst) exceeds the default
5 %, while the test measures the accuracy it needs against an exact or certified answer itself.
Only that warning is ignored; every other one still fails the test."""

SMOKE_SIZES = pytest.mark.filterwarnings("ignore::gridlbc.errors.GridlbcWarning")
"""For smoke tests of plumbing (figures, command line, reports) at sizes far too small to be
accurate: every accuracy and certificate warning is expected there, and their numbers are not
checked."""
