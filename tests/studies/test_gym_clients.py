"""Gymnasium's MountainCarContinuous-v0 as a first-exit problem: the model is gym's map, the
runner is gym's episode, and the library's policies reach the flag cheaply (a smoke test: the
scores with 1000 episodes are in benchmarks/gym_clients.py)."""

import numpy as np
import pytest

import gridlbc
from gridlbc.reference import solve_hjb
from gridlbc.studies.gym_clients import (
    MC_STEPS,
    MOUNTAIN_CAR_ID,
    clipped,
    mountain_car_dp,
    mountain_car_problem,
    mountain_car_step,
    run_mountain_car,
    start_states,
    zero_policy,
)

gymnasium = pytest.importorskip("gymnasium")


def test_gym_step_is_semi_implicit_euler_of_the_model_with_the_problem_costs(rng):
    # Gym: v' = clip(v + 0.0015 clip(u) − 0.0025 cos 3x, ±0.07), x' = clip(x + v'), v' = 0 at
    # the left wall, reward −0.1u² (+100 at the flag). The model's a(x) + B u over one time unit,
    # and ½Ru² with gym's R, reproduce it (states at the walls and forces beyond ±1 included).
    problem = mountain_car_problem((25, 11))
    system = problem.system
    env = gymnasium.make(MOUNTAIN_CAR_ID).unwrapped
    env.reset(seed=0)
    for _ in range(300):
        x = np.array([rng.uniform(-1.2, 0.6), rng.uniform(-0.07, 0.07)])
        if rng.uniform() < 0.2:
            x = np.array([-1.19, -0.05])  # into the wall
        u = rng.uniform(-1.5, 1.5)
        env.state = x.copy()
        state, reward, terminated, *_ = env.step(np.array([u]))
        mine, my_reward, done = mountain_car_step(x[None], np.array([u]))
        np.testing.assert_allclose(state, mine[0], rtol=1e-6, atol=1e-7)  # gym stores float32
        assert reward == pytest.approx(my_reward[0], abs=1e-9) and terminated == done[0]
        accel = system.dynamics(x, np.clip(u, -1, 1))[0, 1]
        v = np.clip(x[1] + accel, -0.07, 0.07)
        if mine[0, 0] > -1.2:
            np.testing.assert_allclose(mine[0], [np.clip(x[0] + v, -1.2, 0.6), v], atol=1e-12)
        cost = 0.5 * problem.R[0, 0] * u**2
        assert my_reward[0] == pytest.approx((100.0 if done[0] else 0.0) - cost, abs=1e-12)
    assert problem.exit_mask(np.array([[0.45, 0.0], [0.45, -1e-3], [0.44, 0.01]])).tolist() == [
        True,
        False,
        False,
    ]


def test_run_mountain_car_scores_like_a_plain_gym_loop():
    def pump(x):  # push along the velocity: reaches the flag
        return 0.5 * np.sign(x[:, 1:2] + 1e-9)

    result = run_mountain_car(pump, episodes=3, seed=5)
    for i in range(3):
        env = gymnasium.make(MOUNTAIN_CAR_ID)
        obs, _ = env.reset(seed=5 + i)
        total, steps, done = 0.0, 0, False
        while not done:
            obs, reward, terminated, truncated, _ = env.step(pump(obs[None])[0].astype(np.float32))
            total, steps, done = total + reward, steps + 1, terminated or truncated
        assert result.scores[i] == pytest.approx(total, rel=1e-12)
        assert result.steps[i] == steps and result.reached[i] == terminated
    assert result.reached.all()
    idle = run_mountain_car(zero_policy, episodes=2)
    assert idle.scores.tolist() == [0.0, 0.0] and idle.steps.tolist() == [MC_STEPS, MC_STEPS]
    with pytest.raises(ValueError, match="shape"):
        run_mountain_car(lambda x: np.zeros(len(x)), episodes=2)


def test_linearly_solvable_and_bounded_hjb_policies_reach_the_flag_cheaply():
    # Coarse grids (a second each): every episode reaches the flag, for well under the force
    # ARS spends (96.67). Measured on these 10 episodes: about 99.0 for both.
    problem = mountain_car_problem((301, 101), temperature=0.1, time_cost=3e-3)
    linear = run_mountain_car(clipped(gridlbc.solve(problem, error_estimate=False).policy), 10)
    assert linear.reached.all() and linear.mean > 98.0
    bounded = solve_hjb(
        problem.replace(temperature=0.05), control_bounds=(-1, 1), error_estimate=False
    )
    assert np.abs(bounded.policy(problem.grid.nodes())).max() <= 1.0
    played = run_mountain_car(lambda x: bounded.policy(x), 10)
    assert played.reached.all() and played.mean > 98.0


def test_dynamic_programming_on_gyms_map():
    # Coarse (a second): the time-limited optimum from the start states lies between what the
    # policies above reach and 100 (measured 99.33 here, 99.62 on 601×401 with 41 forces).
    dp = mountain_car_dp((101, 61), forces=11)
    assert dp.sweeps == MC_STEPS
    predicted = dp.value(start_states(101))
    assert np.all((predicted > 98.5) & (predicted < 100.0))
    assert dp.values.max() <= 100.0
    assert dp.value(np.array([[0.44, 0.07]]))[0] == pytest.approx(100.0)  # one free step to go
