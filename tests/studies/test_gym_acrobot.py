"""Gymnasium's Acrobot-v1 as a minimum-time first exit: the model is gym's book dynamics, and the
library's policies swing the tip above the bar (smoke tests: the scores over 1000 episodes are in
benchmarks/gym_clients.py --only acrobot)."""

import numpy as np
import pytest

import gridlbc

gymnasium = pytest.importorskip("gymnasium")


def test_acrobot_model_in_canonical_momenta_is_gyms_book_dynamics(rng):
    # The accelerations of gym's _dsdt (book dynamics) equal d/dt of θ̇ = M⁻¹p under the
    # model's Hamilton equations: θ̈ = M⁻¹(ṗ − Ṁ θ̇), Ṁ = M'(θ₂) θ̇₂.
    from gridlbc.studies.gym_acrobot import GymAcrobot, acrobot_above_bar

    env = gymnasium.make("Acrobot-v1").unwrapped
    system = GymAcrobot()
    for _ in range(100):
        s = np.array([*rng.uniform(-np.pi, np.pi, 2), *rng.uniform(-6, 6, 2)])
        torque = rng.choice([-1.0, 0.0, 1.0])
        gym_rates = np.array(env._dsdt(np.append(s, torque))[:4])
        x = system.from_velocities(s[None])
        np.testing.assert_allclose(system.velocities(x)[0], s[2:], atol=1e-12)
        rates = system.dynamics(x, [[torque]])[0]
        M = system.mass_matrix(s[1])
        dM = np.array([[-np.sin(s[1]), -0.5 * np.sin(s[1])], [-0.5 * np.sin(s[1]), 0.0]])
        accel = np.linalg.solve(M, rates[2:] - dM @ s[2:] * s[3])
        np.testing.assert_allclose(rates[:2], gym_rates[:2], atol=1e-12)
        np.testing.assert_allclose(accel, gym_rates[2:], rtol=1e-9, atol=1e-9)
    assert acrobot_above_bar([[np.pi, 0.0], [0.0, 0.0]]).tolist() == [True, False]


def test_acrobot_minimum_time_policy_swings_up():
    # 11⁴ (a fraction of a second): gym's torque as the sign of the linear policy gets the tip
    # above the bar in every episode, far sooner than gym's 500 steps (measured about −80).
    from gridlbc.studies.gym_acrobot import acrobot_problem, acrobot_torques, run_acrobot

    solution = gridlbc.solve(acrobot_problem((11, 11, 11, 11)), error_estimate=False)
    episodes = run_acrobot(acrobot_torques(solution), episodes=5)
    assert episodes.reached.all() and episodes.mean > -150
    with pytest.raises(ValueError, match="actions"):
        run_acrobot(lambda x: np.full(len(x), 3), episodes=2)
