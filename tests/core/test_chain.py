"""PlanarChain: the Acrobot for two pinned links, Hamilton's equations, the mass model from the
positions, and the diver's conserved angular momentum."""

import numpy as np
import pytest

from gridlbc import Axis, Grid, Problem, Quadratic, simulate, solve
from gridlbc.systems import Acrobot, PlanarChain

CHAINS = [
    PlanarChain(3, masses=[1.0, 0.6, 1.4], lengths=[0.8, 1.1, 0.7]),
    PlanarChain(4, masses=[0.5, 1.5, 1.0, 0.8], lengths=[0.6, 0.9, 0.5, 1.2], pinned=False),
    PlanarChain(2, pinned=False),
]


def _states(chain, rng, size=12):
    n = chain.n_links
    return np.column_stack([rng.uniform(-np.pi, np.pi, (size, n)), rng.uniform(-3, 3, (size, n))])


@pytest.mark.parametrize(
    ("params", "chain_params"),
    [
        ({}, {}),
        (
            {"m1": 1.3, "m2": 0.7, "l1": 1.1, "l2": 0.9, "gravity": 3.0},
            {"masses": [1.3, 0.7], "lengths": [1.1, 0.9], "gravity": 3.0},
        ),
    ],
)
def test_two_pinned_links_are_the_acrobot(params, chain_params, rng):
    acrobot, chain = Acrobot(**params), PlanarChain(2, **chain_params)
    x = _states(chain, rng, 50)
    u = rng.normal(size=(50, 1))
    scale = np.abs(acrobot.dynamics(x, u)).max()
    eps = np.finfo(float).eps
    # Two evaluations of the same formulas in a different order: rounding of a few ulps of the
    # largest term (M⁻¹ has condition ≲ 50 here).
    np.testing.assert_allclose(
        chain.dynamics(x, u), acrobot.dynamics(x, u), rtol=0, atol=100 * eps * scale
    )
    np.testing.assert_allclose(
        chain.energy(x), acrobot.energy(x), rtol=0, atol=100 * eps * np.abs(acrobot.energy(x)).max()
    )
    np.testing.assert_allclose(
        chain.mass_matrix(x[:, :2]), acrobot.mass_matrix(x[:, 1]), rtol=0, atol=10 * eps
    )
    np.testing.assert_array_equal(chain.input_matrix(x), acrobot.input_matrix(x))
    xv = acrobot.to_velocities(x)
    np.testing.assert_allclose(
        chain.to_velocities(x), xv, rtol=0, atol=100 * eps * np.abs(xv).max()
    )
    np.testing.assert_allclose(
        chain.from_velocities(xv),
        acrobot.from_velocities(xv),
        rtol=0,
        atol=100 * eps * np.abs(x).max(),
    )


@pytest.mark.parametrize("chain", CHAINS, ids=["pinned3", "free4", "free2"])
def test_hamilton_equations(chain, rng):
    """ṡ = ∂H/∂p and ṗ = −∂H/∂s (u = 0) by central differences of H = ½ pᵀM⁻¹p + V."""
    x = _states(chain, rng)
    d = chain.state_dim
    h = 1e-5
    grad = np.empty_like(x)
    for k in range(d):
        step = np.zeros(d)
        step[k] = h
        grad[:, k] = (chain.energy(x + step) - chain.energy(x - step)) / (2 * h)
    n = chain.n_links
    expected = np.concatenate([grad[:, n:], -grad[:, :n]], axis=1)
    # O(h²) truncation times third derivatives of H of order |H| ≲ 10², plus rounding ε|H|/h.
    np.testing.assert_allclose(chain.drift(x), expected, rtol=0, atol=1e-6)


@pytest.mark.parametrize("chain", CHAINS, ids=["pinned3", "free4", "free2"])
def test_mass_matrix_is_the_kinetic_energy_of_the_positions(chain, rng):
    """½ ṡᵀ M ṡ equals the kinetic energy of the point masses (pinned) or the rods (free),
    with velocities differentiated from :meth:`positions`, and p1 is the angular momentum."""
    n = chain.n_links
    s, s_dot = rng.uniform(-np.pi, np.pi, (8, n)), rng.uniform(-2, 2, (8, n))
    eps = 1e-6

    def points(angles):
        return chain.positions(np.column_stack([angles, np.zeros_like(angles)]))

    r = points(s)
    v = (points(s + eps * s_dot) - points(s - eps * s_dot)) / (2 * eps)
    m = np.array(chain.masses)
    psi_dot = np.cumsum(s_dot, axis=1)
    if chain.pinned:
        np.testing.assert_array_equal(r[:, 0], 0.0)
        bodies_r, bodies_v, inertia = r[:, 1:], v[:, 1:], np.zeros(n)
    else:
        bodies_r, bodies_v = 0.5 * (r[:, 1:] + r[:, :-1]), 0.5 * (v[:, 1:] + v[:, :-1])
        np.testing.assert_allclose(np.einsum("nkc,k->nc", bodies_r, m), 0.0, atol=1e-12)
        inertia = m * np.array(chain.lengths) ** 2 / 12
    kinetic = 0.5 * np.einsum("k,nkc,nkc->n", m, bodies_v, bodies_v) + 0.5 * psi_dot**2 @ inertia
    M = chain.mass_matrix(s)
    # Central differences: O(eps²) relative error, far below 1e-8.
    np.testing.assert_allclose(0.5 * np.einsum("ni,nij,nj->n", s_dot, M, s_dot), kinetic, rtol=1e-8)
    # Angular momentum r × v (x right, y up, counterclockwise angles) about the bar or the
    # centre of mass.
    spin = (
        np.einsum("k,nk,nk->n", m, bodies_r[..., 0], bodies_v[..., 1])
        - np.einsum("k,nk,nk->n", m, bodies_r[..., 1], bodies_v[..., 0])
        + psi_dot @ inertia
    )
    p = chain.from_velocities(np.column_stack([s, s_dot]))
    np.testing.assert_allclose(chain.angular_momentum(p), spin, rtol=1e-8)


def test_straight_diver_spins_as_one_rod():
    """Rods of equal density in a line, spinning rigidly at ω: p1 = (m L²/12) ω of the whole rod,
    and the motion stays rigid (ṡ = (ω, 0, 0, 0), ṗ = 0)."""
    chain = PlanarChain(4, masses=[0.5, 1.0, 1.5, 1.0], lengths=[0.5, 1.0, 1.5, 1.0], pinned=False)
    omega, total_mass, total_length = 1.3, 4.0, 4.0
    x = chain.from_velocities([0.7, 0, 0, 0, omega, 0, 0, 0])
    assert chain.angular_momentum(x)[0] == pytest.approx(
        total_mass * total_length**2 / 12 * omega, rel=1e-14
    )
    # Rounding of the solve ṡ = M⁻¹p: cond(M) ε |p| ≈ 1e3 · 2e-16 · 7.
    np.testing.assert_allclose(chain.drift(x)[0], [omega, 0, 0, 0, 0, 0, 0, 0], atol=1e-12)


def test_pinned_upright_is_an_equilibrium_and_energy_is_conserved(rng):
    chain = CHAINS[0]
    np.testing.assert_allclose(chain.drift(np.zeros(6)), 0.0, atol=1e-15)
    x0 = _states(chain, rng, 4) * [1, 1, 1, 0.3, 0.3, 0.3]
    # RK4 over 1 s: energy error O(dt⁴), halving dt cuts it ~16×.
    errors = []
    for dt in (2e-3, 1e-3):
        x = x0.copy()
        for _ in range(round(1 / dt)):
            k1 = chain.drift(x)
            k2 = chain.drift(x + 0.5 * dt * k1)
            k3 = chain.drift(x + 0.5 * dt * k2)
            k4 = chain.drift(x + dt * k3)
            x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        errors.append(np.abs(chain.energy(x) - chain.energy(x0)).max())
    assert errors[1] < 1e-6 * np.abs(chain.energy(x0)).max()
    assert errors[1] < errors[0] / 8


def test_diver_conserves_angular_momentum_exactly(rng):
    diver = PlanarChain(4, pinned=False)
    x = _states(diver, rng, 200)
    assert np.all(diver.drift(x)[:, 4] == 0.0)  # ṗ1 = 0 in the equations, not to rounding
    assert np.all(diver.input_matrix(x)[:, 4] == 0.0)  # no torque reaches p1
    assert diver.potential(x).max() == 0.0 and diver.gravity == 9.81  # gravity: no torque
    problem = Problem(diver, None, 1.0, Quadratic(np.zeros(8), 1.0), temperature=0.5)
    x0 = np.array([0.3, 0.2, -0.4, 0.1, 1.7, 0.0, 0.3, -0.2])
    rollouts = simulate(problem, lambda xs, t: 3 * np.sin(xs[:, 1:4] + t), x0, n_samples=20, seed=1)
    assert np.abs(rollouts.controls).max() > 1  # real torques and noise act on the shape ...
    assert np.ptp(rollouts.states[:, :, 5:]) > 1
    np.testing.assert_array_equal(rollouts.states[:, :, 4], 1.7)  # ... and p1 stays put


def test_free_chain_noise_is_diagonal_and_full_R_is_refused():
    """B = [0; 0; I] in canonical momenta: λ B R⁻¹ Bᵀ is diagonal iff R is. The grid solver
    refuses a full R before doing any work, naming the entry and the fix."""
    chain = PlanarChain(3, pinned=True)
    axes = [Axis(-np.pi, np.pi, 3, periodic=True)] * 3 + [Axis(-1, 1, 3)] * 3
    g = Quadratic(np.zeros(6), 1.0)
    diag = Problem(chain, Grid(axes), 0.5, g, control_cost=[1.0, 2.0], temperature=2.0)
    np.testing.assert_allclose(diag.noise_diagonal(np.zeros((1, 6))), [[0, 0, 0, 0, 2.0, 1.0]])
    full = Problem(chain, Grid(axes), 0.5, g, control_cost=[[1.0, 0.5], [0.5, 1.0]])
    with pytest.raises(ValueError, match=r"not diagonal in the grid coordinates \(entry \(4, 5\)"):
        solve(full)
    # Rollouts need no diagonal noise: B R^{-1/2} ε.
    rollouts = simulate(
        full,
        lambda x, t: np.zeros((len(x), 2)),
        np.zeros(6),
        n_samples=400,
        seed=0,
        dt=0.5,
        noise=True,
        boundary="free",  # the raw noise: the reflection at p = ±1 would fold the increments
    )
    dp = rollouts.states[:, 1, 4:] - rollouts.states[:, 0, 4:]
    # Cov = λ R⁻¹ dt with R⁻¹ = [[4, -2], [-2, 4]]/3: the correlation is −0.5 (SE ≈ 0.04).
    assert np.corrcoef(dp.T)[0, 1] == pytest.approx(-0.5, abs=0.15)


def test_bad_arguments():
    with pytest.raises(ValueError, match="n_links must be an integer ≥ 2"):
        PlanarChain(1)
    with pytest.raises(ValueError, match="masses must be one number or one per link"):
        PlanarChain(3, masses=[1.0, 2.0])
    with pytest.raises(ValueError, match=r"lengths\[1\] must be a positive"):
        PlanarChain(2, lengths=[1.0, -1.0])
    with pytest.raises(TypeError, match="pinned must be True or False"):
        PlanarChain(2, pinned="no")
    with pytest.raises(ValueError, match=r"states must have shape \(N, 6\)"):
        PlanarChain(3).drift(np.zeros(4))
    assert PlanarChain(3, masses=2.0) == PlanarChain(3, masses=[2.0, 2.0, 2.0])
    assert PlanarChain(3) != PlanarChain(3, pinned=False)
    assert hash(PlanarChain(3)) == hash(PlanarChain(3))
