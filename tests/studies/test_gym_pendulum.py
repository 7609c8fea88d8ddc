"""Gymnasium's Pendulum-v1 as a gridlbc problem: the model is gym's, and the bounded policy works."""

import numpy as np
import pytest

from gridlbc.reference import solve_hjb
from gridlbc.studies.gym_pendulum import (
    DT,
    STEPS,
    run_episodes,
    state_from_observation,
    zero_policy,
)
from gridlbc.studies.problems import pendulum_v1_problem

gymnasium = pytest.importorskip("gymnasium")


def test_one_gym_step_is_semi_implicit_euler_of_the_library_model(rng):
    # Gym: ω' = clip(ω + (15 sin θ + 3 clip(u, ±2)) Δt, ±8), θ' = θ + ω' Δt, reward −Δt (q + ½Ru²)
    # with θ wrapped in q. The library's drift a(x) and B(x) of Pendulum(0.75, 2/3, 10) and the
    # problem's q and R must reproduce it to rounding (states well beyond ±π and ±8 included).
    problem = pendulum_v1_problem(9)
    system = problem.system
    env = gymnasium.make("Pendulum-v1").unwrapped
    env.reset(seed=0)
    for _ in range(200):
        x = np.array([rng.uniform(-8, 8), rng.uniform(-10, 10)])
        u = rng.uniform(-4, 4)
        env.state = x.copy()
        _, reward, *_ = env.step(np.array([u]))
        applied = np.clip(u, -2, 2)
        accel = system.drift(x)[0, 1] + system.input_matrix(x)[0, 1, 0] * applied
        omega = np.clip(x[1] + accel * DT, -8, 8)
        np.testing.assert_allclose(env.state, [x[0] + omega * DT, omega], rtol=1e-13, atol=1e-13)
        wrapped = np.array([[np.angle(np.exp(1j * x[0])), x[1]]])
        rate = problem.state_cost_values(wrapped)[0] + 0.5 * problem.R[0, 0] * applied**2
        np.testing.assert_allclose(reward, -DT * rate, rtol=1e-12)


def test_observations_map_to_the_state():
    env = gymnasium.make("Pendulum-v1")
    obs, _ = env.reset(seed=3)
    theta, omega = env.unwrapped.state
    # gym's observation is float32: θ from atan2 of float32 cos and sin
    np.testing.assert_allclose(
        state_from_observation(obs)[0], [np.angle(np.exp(1j * theta)), omega], atol=1e-6
    )
    with pytest.raises(ValueError, match="3 entries"):
        state_from_observation([1.0, 0.0])


def test_run_episodes_scores_like_a_plain_gym_loop():
    # The batched runner is gym's own episode: same seeds, same summed reward, to rounding.
    result = run_episodes(zero_policy, episodes=3, seed=7)
    for i in range(3):
        env = gymnasium.make("Pendulum-v1")
        env.reset(seed=7 + i)
        total, steps, done = 0.0, 0, False
        while not done:
            _, reward, terminated, truncated, _ = env.step(np.zeros(1, dtype=np.float32))
            total, steps, done = total + reward, steps + 1, terminated or truncated
        assert steps == STEPS
        assert result.scores[i] == pytest.approx(total, rel=1e-12)
    with pytest.raises(ValueError, match="shape"):
        run_episodes(lambda x, t: np.zeros(len(x)), episodes=2)


def test_bounded_hjb_policy_swings_up_on_a_coarse_grid():
    # 51² (a fraction of a second to solve): the bounded policy must beat zero torque by far
    # more than the paired noise, and its torques stay within gym's ±2. Measured: about −140
    # against −1190 over these 20 episodes; the bound checked is a paired margin of 10 SE.
    problem = pendulum_v1_problem(51)
    solution = solve_hjb(problem, control_bounds=(-2, 2), error_estimate=False)
    policy = solution.policy(problem.grid.nodes(), 0.0)
    assert np.abs(policy).max() <= 2.0
    bounded = run_episodes(solution.policy, episodes=20)
    zero = run_episodes(zero_policy, episodes=20)
    gain = bounded.scores - zero.scores
    se = gain.std(ddof=1) / np.sqrt(gain.size)
    assert gain.mean() > 10 * se
    assert bounded.mean > -300  # SAC scores about −157; zero torque about −1190
