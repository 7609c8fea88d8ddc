"""Each gallery figure at a tiny size writes a non-empty image; the push helper is checked
against one uninterrupted rollout."""

import numpy as np
import pytest
from conftest import SMOKE_SIZES

from gridlbc import simulate
from gridlbc.studies import figures
from gridlbc.studies.problems import coordination_problem

PNG = b"\x89PNG\r\n\x1a\n"


@SMOKE_SIZES
@pytest.mark.parametrize(
    "name, options",
    [
        ("cost_reward_space", {"n": 21}),
        ("projection", {"points": 101}),
        ("interpolation", {"n": 21, "samples": 20, "traces": 2, "dt": 0.1, "restarts": 2}),
        ("coordination", {"n": 21, "samples": 20, "traces": 2, "dt": 0.05}),
        ("gymnast", {"n": 5, "reference": False}),
        pytest.param(  # about 50 s (the combination's error estimate, certificates with exits)
            "exit_bays", {"n": 21, "samples": 20, "traces": 2, "dt": 0.05}, marks=pytest.mark.slow
        ),
        ("certified_convergence", {"sizes": (8, 16), "samples": 10, "truth_samples": 20}),
        (
            "convergence",
            {"spacings": (1, 2), "sizes": (16, 32), "temperatures": (1.0,), "temperature_grid": 16},
        ),
    ],
)
def test_figure_writes_png(tmp_path, name, options):
    function = figures.FIGURES[name][0]
    paths = function(tmp_path, **options)
    assert paths
    for path in paths:
        data = path.read_bytes()
        assert len(data) > 1000
        assert data.startswith((PNG, b"GIF8"))


def test_make_all_rejects_unknown_name(tmp_path):
    with pytest.raises(ValueError, match=r"unknown figure 'nope'.*projection"):
        figures.make_all(tmp_path, only=["nope"])


def test_push_without_kick_equals_one_rollout():
    """Splitting a noise-free rollout at t_p with a zero kick must reproduce the uninterrupted
    rollout: the second call restarts the policy's clock at t_p, Euler steps coincide (same Δt,
    t_p a multiple of it), so the states agree to rounding."""
    problem = coordination_problem(21)

    def policy(x, t):
        return -x[:, :1] + np.sin(3 * t) * np.ones((len(x), 1))  # time-dependent on purpose

    times, states = figures.simulate_with_push(
        problem, policy, [0.3, 0.0], 1.0, [0.0, 0.0], noise=False, dt=0.01
    )
    whole = simulate(problem, policy, [0.3, 0.0], 1, dt=0.01, noise=False)
    k = 100  # t_p = 1 s = 100 steps; times[k] == times[k + 1] == t_p, before and after the kick
    assert times[k] == times[k + 1] == 1.0
    np.testing.assert_array_equal(states[:, k], states[:, k + 1])  # zero kick
    keep = np.r_[0 : k + 1, k + 2 : len(times)]
    np.testing.assert_allclose(times[keep], whole.times, rtol=0, atol=1e-12)
    np.testing.assert_allclose(states[:, keep], whole.states, rtol=0, atol=1e-12)


def test_push_rejects_time_outside_horizon():
    problem = coordination_problem(21)
    with pytest.raises(ValueError, match="push_time must lie in"):
        figures.simulate_with_push(problem, lambda x, t: 0 * x[:, :1], [0, 0], 3.0, [0, 0])


def test_remaining_task_shifts_horizon_and_clock():
    """The task left at t_s: horizon T − t_s, the same costs, and the policy read at t + t_s."""
    problem = coordination_problem(21)
    task, shifted = figures.remaining_task(problem, lambda x, t: np.full((len(x), 1), t), 1.25)
    assert task.horizon == problem.horizon - 1.25
    assert task.terminal_cost is problem.terminal_cost
    np.testing.assert_array_equal(shifted(np.zeros((3, 2)), 0.5), np.full((3, 1), 1.75))
