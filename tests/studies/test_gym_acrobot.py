"""Gymnasium's Acrobot-v1 as a minimum-time first exit: the model is gym's book dynamics, and the
library's policies swing the tip above the bar (smoke tests: the scores over 1000 episodes are in
benchmarks/gym_clients.py --only acrobot)."""

import numpy as np
import pytest

import gridlbc
from gridlbc.reference.hjb import multilinear
from gridlbc.studies.gym_acrobot import (
    ACROBOT_ID,
    GymAcrobot,
    StepsToGo,
    acrobot_dp,
    acrobot_dp_grid,
    acrobot_problem,
    acrobot_step,
    acrobot_torques,
    rollout,
    rollout_steps,
    run_acrobot,
)

gymnasium = pytest.importorskip("gymnasium")


def test_acrobot_model_in_canonical_momenta_is_gyms_book_dynamics(rng):
    # The accelerations of gym's _dsdt (book dynamics) equal d/dt of θ̇ = M⁻¹p under the
    # model's Hamilton equations: θ̈ = M⁻¹(ṗ − Ṁ θ̇), Ṁ = M'(θ₂) θ̇₂.
    from gridlbc.studies.gym_acrobot import acrobot_above_bar

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
    solution = gridlbc.solve(acrobot_problem((11, 11, 11, 11)), error_estimate=False)
    episodes = run_acrobot(acrobot_torques(solution), episodes=5)
    assert episodes.reached.all() and episodes.mean > -150
    with pytest.raises(ValueError, match="actions"):
        run_acrobot(lambda x: np.full(len(x), 3), episodes=2)


def test_acrobot_step_is_gyms_step(rng):
    # RK4 over 0.2 s with the torque held, angles wrapped, velocities clipped (states beyond the
    # clips included), and gym's end test on the new state; to rounding.
    env = gymnasium.make(ACROBOT_ID).unwrapped
    env.reset(seed=0)
    for _ in range(300):
        s = np.array([*rng.uniform(-np.pi, np.pi, 2), rng.uniform(-14, 14), rng.uniform(-30, 30)])
        a = int(rng.integers(3))
        env.state = s.copy()
        _, reward, terminated, *_ = env.step(a)
        mine, done = acrobot_step(s[None], [a])
        np.testing.assert_allclose(mine[0], env.state, rtol=0, atol=1e-12)
        assert done[0] == terminated and reward == (0.0 if terminated else -1.0)


def _brute_force_costs(table, x, depth):
    """Every sequence stepped by acrobot_step, the leaves interpolated by hjb.multilinear."""
    costs = np.full(3, np.inf)
    for seq in np.ndindex(*(3,) * depth):
        s, cost = x[None].copy(), None
        for k, a in enumerate(seq):
            s, done = acrobot_step(s, [a])
            if done[0]:
                cost = k + 1.0
                break
        if cost is None:
            leaf = GymAcrobot().from_velocities(s) if table.momenta else s
            cost = depth + multilinear(table.grid, table.values, leaf)[0, 0]
        costs[seq[0]] = min(costs[seq[0]], cost)
    return costs


@pytest.mark.parametrize("momenta", [True, False])
def test_lookahead_costs_and_torque_against_brute_force(rng, momenta):
    # A value on a small grid (random, so every leaf matters), in canonical momenta (the
    # library's problems) or gym's velocities (the DP); states near the bar, so some sequences
    # end early.
    grid = acrobot_problem((7, 6, 5, 5)).grid if momenta else acrobot_dp_grid((7, 6, 5, 5))
    table = StepsToGo(grid, rng.uniform(0, 30, grid.size), momenta)
    x = np.column_stack(
        [rng.uniform(2.0, 3.1, 6), rng.uniform(-0.5, 0.5, 6), rng.uniform(-3, 3, (6, 2))]
    )
    for depth in (1, 2, 3):
        costs = table.costs(x, depth)
        for n in range(len(x)):
            np.testing.assert_allclose(costs[n], _brute_force_costs(table, x[n], depth), atol=1e-9)
        np.testing.assert_array_equal(table.lookahead(depth)(x), np.argmin(costs, axis=1))
    leaf = GymAcrobot().from_velocities(x) if momenta else x
    np.testing.assert_allclose(table(x), multilinear(grid, table.values, leaf)[0], atol=1e-12)


def _bellman_reference(grid, values):
    """One Jacobi sweep in numpy: C = min over torques of 0 (the step ends above the bar) or
    1 + C(x') interpolated."""
    nodes = grid.nodes()
    best = np.full(grid.size, np.inf)
    for a in range(3):
        after, done = acrobot_step(nodes, np.full(grid.size, a))
        after = after.astype(np.float32).astype(float)  # the kernel stores successors in float32
        cost = np.where(done, 0.0, 1.0 + multilinear(grid, values, after)[0])
        best = np.minimum(best, cost)
    return best


def test_dp_sweeps_against_numpy_and_by_hand():
    # After one sweep C is 0 where some torque ends the episode in one step and 1 elsewhere;
    # the kernel's sweeps match the numpy reference; the upright at rest is one step from the
    # bar (C = 0) and the hanging rest is not (C ≥ 1); C never decreases from one sweep to the
    # next (Jacobi from 0, so after k sweeps it is the optimum with k steps left, and k bounds it).
    n = (8, 8, 5, 5)
    grid = acrobot_dp_grid(n)
    one = acrobot_dp(n, max_sweeps=1).steps_to_go.values
    nodes = grid.nodes()
    ends = np.any([acrobot_step(nodes, np.full(grid.size, a))[1] for a in range(3)], axis=0)
    np.testing.assert_array_equal(one, np.where(ends, 0.0, 1.0))
    values = np.zeros(grid.size)
    for _ in range(4):
        values = _bellman_reference(grid, values)
    four = acrobot_dp(n, max_sweeps=4)
    assert four.sweeps == 4
    np.testing.assert_allclose(four.steps_to_go.values, values, atol=1e-9)
    assert np.all(four.steps_to_go.values >= one) and four.steps_to_go.values.max() <= 4
    upright = (np.abs(nodes[:, 0] + np.pi) < 1e-12) & np.all(np.abs(nodes[:, 1:]) < 1e-12, axis=1)
    hanging = np.all(np.abs(nodes) < 1e-12, axis=1)
    assert four.steps_to_go.values[upright] == 0.0 and four.steps_to_go.values[hanging] >= 1


def test_rollout_is_no_slower_than_its_base(rng):
    # Deterministic map: among the rollout's first torques is the base's own, whose score is
    # the base's steps to the bar, so the rollout reaches the bar no later than the base from
    # every state (checked on gym's map from a few starts).
    solution = gridlbc.solve(acrobot_problem((9, 9, 9, 9)), error_estimate=False)
    base = acrobot_torques(solution)
    starts = rng.uniform(-0.1, 0.1, (4, 4))

    def steps(policy):
        x, taken, running = starts.copy(), np.zeros(4), np.ones(4, dtype=bool)
        for _ in range(500):
            if not running.any():
                break
            x[running], done = acrobot_step(x[running], policy(x[running]))
            taken[running] += 1
            running[np.flatnonzero(running)[done]] = False
        return np.where(running, np.inf, taken)

    scored = rollout_steps(base, starts)
    np.testing.assert_array_equal(scored[np.arange(4), base(starts)], steps(base))
    assert np.all(steps(rollout(base)) <= steps(base))
    with pytest.raises(ValueError, match="depth"):
        rollout(base, 0)
