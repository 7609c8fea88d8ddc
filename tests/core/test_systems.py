import numpy as np
import pytest

from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import Acrobot, ControlAffineSystem, Pendulum, PointMass, SingleIntegrator


@pytest.mark.parametrize("system", [SingleIntegrator(), PointMass(2.0), Pendulum(), Acrobot()])
def test_shapes_and_vectorisation(system, rng):
    d, m = system.state_dim, system.control_dim
    x = rng.normal(size=(7, d))
    assert system.drift(x).shape == (7, d)
    assert system.input_matrix(x).shape == (7, d, m)
    np.testing.assert_allclose(system.drift(x[3]), system.drift(x)[3:4])
    with pytest.raises(ValueError, match=f"shape \\(N, {d}\\)"):
        system.drift(np.zeros((2, d + 1)))


def test_spec_table_drifts():
    pend = Pendulum(mass=2.0, length=0.5, gravity=9.81, damping=0.3)
    x = np.array([[0.4, -1.2]])
    inertia = 2.0 * 0.25
    np.testing.assert_allclose(
        pend.drift(x), [[-1.2, 9.81 / 0.5 * np.sin(0.4) + 0.3 * 1.2 / inertia]]
    )
    np.testing.assert_allclose(pend.input_matrix(x)[0], [[0.0], [1 / inertia]])
    pm = PointMass(mass=4.0)
    np.testing.assert_allclose(pm.drift([[1.0, 2.0]]), [[2.0, 0.0]])
    np.testing.assert_allclose(pm.input_matrix([[1.0, 2.0]])[0], [[0.0], [0.25]])


def _rk4(f, x, dt, steps):
    for _ in range(steps):
        k1 = f(x)
        k2 = f(x + 0.5 * dt * k1)
        k3 = f(x + 0.5 * dt * k2)
        k4 = f(x + dt * k3)
        x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return x


def test_acrobot_conserves_energy_without_control(rng):
    acro = Acrobot()
    x0 = np.column_stack([rng.uniform(-np.pi, np.pi, (5, 2)), rng.uniform(-3, 3, (5, 2))])
    H0 = acro.energy(x0)
    # RK4 energy drift over a fixed time is O(dt⁴): halving dt must cut it ~16×.
    errs = []
    for dt in (2e-3, 1e-3):
        x = _rk4(acro.drift, x0, dt, round(1.0 / dt))
        errs.append(np.abs(acro.energy(x) - H0).max())
    assert errs[1] < 1e-6 * np.abs(H0).max() + 1e-9
    assert errs[1] < errs[0] / 8


def test_acrobot_momentum_form_matches_velocity_form(rng):
    acro = Acrobot(m1=1.3, m2=0.7, l1=1.1, l2=0.9)
    xv = np.column_stack([rng.uniform(-np.pi, np.pi, (20, 2)), rng.uniform(-2, 2, (20, 2))])
    u = rng.normal(size=20)
    xp = acro.from_velocities(xv)
    np.testing.assert_allclose(acro.to_velocities(xp), xv, atol=1e-12)
    # d/dt p = d/dt (M(θ2) θ̇): compare the momentum drift with the Lagrange form by the chain rule.
    vel = acro.velocity_dynamics(xv, u)
    xdot_p = acro.dynamics(xp, u[:, None])
    np.testing.assert_allclose(xdot_p[:, :2], xv[:, 2:], atol=1e-12)
    eps = 1e-6
    p_plus = acro.from_velocities(xv + eps * vel)[:, 2:]
    p_minus = acro.from_velocities(xv - eps * vel)[:, 2:]
    np.testing.assert_allclose(xdot_p[:, 2:], (p_plus - p_minus) / (2 * eps), rtol=1e-7, atol=1e-7)


def test_acrobot_upright_is_equilibrium_and_hanging_is_stable():
    acro = Acrobot()
    np.testing.assert_allclose(acro.drift(np.zeros(4)), 0.0, atol=1e-15)
    np.testing.assert_allclose(acro.drift([np.pi, 0, 0, 0]), 0.0, atol=1e-12)
    assert acro.energy(np.zeros(4))[0] == pytest.approx(9.81 * 3)


def test_pendulum_energy_conserved(rng):
    pend = Pendulum(length=0.8)
    x0 = np.column_stack([rng.uniform(-3, 3, 4), rng.uniform(-2, 2, 4)])
    x = _rk4(pend.drift, x0, 1e-3, 2000)
    np.testing.assert_allclose(pend.energy(x), pend.energy(x0), rtol=1e-9)


def test_bad_parameters():
    with pytest.raises(ValueError, match="mass"):
        PointMass(mass=0)
    with pytest.raises(ValueError, match="length"):
        Pendulum(length=-1)
    with pytest.raises(ValueError, match="damping"):
        Pendulum(damping=np.nan)


class _Skewed(ControlAffineSystem):
    """A control that moves both coordinates: noise not diagonal in these coordinates."""

    state_dim, control_dim = 2, 1
    state_names = ("a", "b")

    def drift(self, x):
        return np.zeros_like(self._states(x))

    def input_matrix(self, x):
        x = self._states(x)
        return np.broadcast_to(np.array([[1.0], [1.0]]), (x.shape[0], 2, 1))


def test_non_diagonal_noise_is_rejected_with_a_fix():
    grid = Grid([Axis(-1, 1, 5), Axis(-1, 1, 5)])
    problem = Problem(_Skewed(), grid, 1.0, Quadratic([0, 0], [1, 1]))
    with pytest.raises(ValueError, match=r"not diagonal.*canonical momenta"):
        problem.noise_diagonal(grid.nodes())
    import gridlbc

    with pytest.raises(ValueError, match="not diagonal"):
        gridlbc.solve(problem)
