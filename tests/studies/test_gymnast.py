"""The gymnast study on a small grid: the grid-optimal controllers (plain and fitted) against
zero torque and each other, and the problem and figure helpers of gridlbc.studies.gymnast."""

from pathlib import Path

import numpy as np
import pytest
from conftest import EXACTNESS_ONLY

import gridlbc
from gridlbc.simulate import simulate
from gridlbc.studies.gymnast import angle_distance, animate_swingup, plot_swingup
from gridlbc.studies.problems import GYMNAST_START, gymnast_problem

NOISY = {"n_samples": 800, "dt": 0.005, "seed": 11, "noise": True}
"""Rollouts with noise; the same seed gives every controller the same noise (common random
numbers), so paired differences have small standard errors."""


@pytest.fixture(scope="module")
def small_solutions():
    problem = gymnast_problem(21)
    return {
        fitting: gridlbc.solve(problem, dt=0.1, fitting=fitting) for fitting in (None, "terminal")
    }


@pytest.fixture(scope="module")
def noisy_runs(small_solutions):
    """Noisy rollouts of each 21⁴ controller and of zero torque, with the same noise."""
    problem = small_solutions[None].problem

    def grid_policy(solution):
        return lambda x, t: solution.policy(x, min(t, problem.horizon))

    runs = {
        fitting: simulate(problem, grid_policy(sol), GYMNAST_START, **NOISY)
        for fitting, sol in small_solutions.items()
    }
    runs["zero"] = simulate(problem, lambda x, t: np.zeros((len(x), 1)), GYMNAST_START, **NOISY)
    return runs


def paired(a, b):
    """Mean and standard error of the paired cost difference a − b."""
    difference = a.costs - b.costs
    return difference.mean(), difference.std(ddof=1) / np.sqrt(difference.size)


@EXACTNESS_ONLY
@pytest.mark.parametrize("fitting, ratio", [(None, 0.7), ("terminal", 0.36)])
def test_controller_beats_zero_torque_by_a_wide_margin(noisy_runs, fitting, ratio):
    """Expected cost with noise over 800 paired samples at 21⁴, Δt = 0.1, the hip stops and
    momentum bounds reflecting as in the solve: the controller must beat zero torque by more than
    4 standard errors of the paired difference (a false failure has probability < 1e-4) and its
    cost ratio to zero torque must stay below the measured ratio plus 4 of its standard errors
    (delta method on the paired samples), rounded up: plain 53.3 ± 0.8 and fitted 27.2 ± 0.3
    against 82.6 ± 1.6 for zero torque, ratios 0.645 ± 0.011 and 0.329 ± 0.007. (With free box
    edges zero torque flails past the stops and costs 130.2 ± 8.0: ratios 0.45 and 0.21.)"""
    controlled, passive = noisy_runs[fitting], noisy_runs["zero"]
    mean, se = paired(controlled, passive)
    assert mean < -4 * se, (mean, se)
    assert controlled.mean_cost < ratio * passive.mean_cost
    assert np.median(angle_distance(controlled.final_states)) < np.median(
        angle_distance(passive.final_states)
    )


@EXACTNESS_ONLY
def test_fitting_makes_the_small_grid_controller_better(noisy_runs):
    """At 21⁴ the fitted drift's controller costs less than the plain one's under the same
    noise, by more than 4 paired standard errors (measured −26.1 ± 0.8, 33 SE, with the box edges
    reflecting; −31.4 ± 1.9 with them free)."""
    mean, se = paired(noisy_runs["terminal"], noisy_runs[None])
    assert mean < -4 * se, (mean, se)


def test_gymnast_problem_and_distance():
    problem = gymnast_problem((5, 6, 7, 8), momentum_bounds=(12, 6))
    assert problem.grid.shape == (5, 6, 7, 8)
    assert problem.grid.periodic.tolist() == [True, False, False, False]
    assert problem.grid.hi[2] == 12 and problem.grid.lo[3] == -6
    assert problem.grid.lo[1] == -np.pi and problem.grid.hi[1] == np.pi  # hip stops at ±180°
    # g is wrap-aware in θ1: θ1 = π − ε and −π + ε are the same distance from the handstand
    g = problem.terminal_values(np.array([[np.pi - 0.1, 0, 0, 0], [-np.pi + 0.1, 0, 0, 0]]))
    np.testing.assert_allclose(g, 10 * (np.pi - 0.1) ** 2)
    # ... but not in θ2, whose ends are stops: a full hip rotation is not the handstand
    over_rotated = np.array([[0, 2 * np.pi - 0.1, 0, 0]])
    np.testing.assert_allclose(problem.terminal_values(over_rotated), 10 * (2 * np.pi - 0.1) ** 2)
    free = gymnast_problem(5, hip_range=None)
    assert free.grid.periodic.tolist() == [True, True, False, False]
    np.testing.assert_allclose(free.terminal_values(over_rotated), 10 * 0.1**2)
    assert gymnast_problem(5, hip_range=2.5).grid.hi[1] == 2.5
    np.testing.assert_allclose(angle_distance([[2 * np.pi + 0.3, -0.4, 5, 5]]), [0.5])
    np.testing.assert_allclose(GYMNAST_START[:2], np.radians([-105, -15]))
    with pytest.raises(ValueError, match="momentum_bounds"):
        gymnast_problem(5, momentum_bounds=(0, 1))
    with pytest.raises(ValueError, match="n must be"):
        gymnast_problem((5, 5))
    for bad in (0.0, 4.0, "pi"):
        with pytest.raises(ValueError, match="hip_range"):
            gymnast_problem(5, hip_range=bad)


def test_figures_are_written(tmp_path):
    times = np.linspace(0, 0.4, 21)
    states = np.column_stack([np.linspace(-2, 0, 21), np.zeros(21), np.ones(21), np.zeros(21)])
    controls = np.zeros(20)
    plot_swingup(
        times,
        {"test": (states, controls)},
        tmp_path / "swing.png",
        reference=(times, states, controls),
    )
    animate_swingup(times, states, tmp_path / "swing.gif", fps=10)
    assert (tmp_path / "swing.png").stat().st_size > 0
    assert (tmp_path / "swing.gif").stat().st_size > 0


def test_greedy_switch_follows_the_largest_blend_weight():
    """GreedySwitch uses, at each state, the policy of the component with the largest α."""
    from gridlbc.studies.gymnast import GreedySwitch, at_rest
    from gridlbc.trajectory import expand, optimize

    grid = gridlbc.Grid([gridlbc.Axis(-5, 5, 5), gridlbc.Axis(-5, 5, 5)])
    trackers = []
    for center in (-1.0, 1.0):
        problem = gridlbc.Problem(
            gridlbc.systems.PointMass(), grid, 1.0, gridlbc.Quadratic([center, 0.0], [3.0, 0.5])
        )
        trackers.append(expand(problem, optimize(problem, np.zeros(2), restarts=1, n_intervals=20)))
    combination = gridlbc.combine(trackers)
    np.testing.assert_array_equal(at_rest([0.1, -0.2]), [[0.1, -0.2, 0.0, 0.0]])
    x = np.array([[-2.0, 0.0], [-0.5, 0.0], [0.4, 0.0], [3.0, 0.0]])
    best = np.argmax(combination.blend_weights(x, 0.3), axis=1)
    assert set(best) == {0, 1}
    expected = np.stack([trackers[b].policy(x[k], 0.3) for k, b in enumerate(best)])
    # equal to rounding: the saturation's einsum sums in another order for another batch
    np.testing.assert_allclose(GreedySwitch(combination).policy(x, 0.3), expected, rtol=1e-14)


# -- the trackers of the paper's Fig. 7 ------------------------------------------------------------
#
# The tapes of benchmarks/gymnast_trackers.py (optimize with its default 128 restarts, 300 RK4
# intervals) from (−90°, 0°), (−110°, −20°) and the test state (−105°, −15°), stored as
# tests/data/fig7_tapes.npz so that the test need not repeat the minutes-long search; iLQR from
# each stored tape (search=False) turns it back into a converged Trajectory of this problem.

FIG7_TAPES = Path(__file__).parents[1] / "data" / "fig7_tapes.npz"


@pytest.fixture(scope="module")
def fig7():
    from gridlbc.studies.gymnast import TRACKER_STARTS, at_rest
    from gridlbc.trajectory import expand, optimize

    problem = gymnast_problem(41)
    tapes = np.load(FIG7_TAPES)
    starts = [*at_rest(TRACKER_STARTS[:2]), GYMNAST_START]
    tracker1, tracker2, optimum = (
        optimize(problem, x0, n_intervals=300, initial_controls=tapes[name], search=False)
        for x0, name in zip(starts, ("tracker1", "tracker2", "optimum"))
    )
    components = [expand(problem, t) for t in (tracker1, tracker2)]
    return problem, components, optimum


def test_fig7_noise_free(fig7):
    """Noise-free from (−105°, −15°) (Euler, Δt = 0.001): LBC within 5 % of the better tracker and
    within 10 % of the deterministic optimum, the naive average at least 2× costlier (measured
    13.03, 13.02 and 13.18; the naive average 103.5)."""
    problem, components, optimum = fig7
    assert all(c.trajectory.converged for c in components) and optimum.converged
    assert optimum.cost == pytest.approx(13.18, abs=0.01)  # the stored tape is the optimum

    def cost(policy):
        return simulate(problem, policy, GYMNAST_START, 1, dt=0.001, noise=False).costs[0]

    trackers = [cost(c.policy) for c in components]
    lbc = cost(gridlbc.combine(components).policy)
    naive = cost(gridlbc.naive_blend(components, None).policy)
    assert lbc <= 1.05 * min(trackers)
    assert abs(lbc - optimum.cost) <= 0.10 * optimum.cost
    assert naive >= 2.0 * lbc


def test_fig7_noisy_lbc_is_within_half_of_the_certified_optimum(fig7):
    """With noise (λ = 1), 300 paths at Δt = 0.002: LBC's cost J ± SE against the certified v* ±
    SE from the same paths (gridlbc.certify, LBC as proposal). The claim J ≤ 1.5 v* must hold with
    two standard errors to spare on each side (measured 20.42 ± 0.30 against 19.71 ± 0.14, ratio
    1.04; with the full DDP gains and no saturation, the previous default, 44.6 ± 8.1).

    LBC is a poor proposal for v*: its weights have a heavy tail (PSIS k̂ = 0.80 here), so the
    certificate warns and is untrusted, and its v* is biased upward: with the default 51⁴ grid
    policy as proposal v* = 19.091 ± 0.011 at this Δt, box edges reflecting (8000 paths;
    benchmarks/gymnast_trackers.py, table (r)), and at 3000 paths LBC costs 20.75 ± 0.10, 8.7 %
    above it (table (a)). A too-high v* makes J ≤ 1.5 v* easier; against the grid-proposal figure
    the claim holds with room (1.5 × 19.09 = 28.6 against J ≈ 20.8), which this test is too
    short to recompute. LBC's own certificate is not always flagged when it is too high (at
    3000 paths, seed 0: k̂ = 0.63, v* = 19.78 ± 0.06, 11 SE above the grid figure); at 300 paths,
    seed 0, it is (``proposal=None``: LBC alone; the default pools it with a grid solution, the
    next test)."""
    problem, components, _ = fig7
    lbc = gridlbc.combine(components)
    with pytest.warns(gridlbc.CertificateWarning, match="heavy tail"):
        cert = gridlbc.certify(
            problem,
            lbc.policy,
            GYMNAST_START,
            n_samples=300,
            dt=0.002,
            seed=0,
            progress=False,
            proposal=None,
        )
    assert cert.pareto_k > cert.max_pareto_k and not cert.trusted
    assert np.isfinite(cert.policy_cost)
    upper = cert.policy_cost + 2.0 * cert.policy_cost_se
    lower = cert.optimal_value - 2.0 * cert.optimal_value_se
    assert upper <= 1.5 * lower


def test_fig7_lbc_pooled_with_a_grid_solution_certifies_the_optimum(fig7):
    """Issue 28: LBC as its own proposal passes as trusted while 10–13 SE too high at some seeds
    and path counts (docs/validating.rst), which no diagnostic of its samples shows. By default
    certify pools it with a grid solution of the problem (the 41⁴ box solved on 31⁴, the
    AUTO_PROPOSAL_NODES budget): the pooled v* must agree with the 51⁴ grid proposal's
    19.091 ± 0.011 at this step within 3 SE of the difference. Measured at 1000 paths, seeds
    0–2: 19.07 ± 0.09, 19.01 ± 0.08, 19.13 ± 0.06, all trusted; LBC alone gives 19.89 ± 0.06
    (trusted, k̂ 0.46), 19.60 ± 0.12, 19.87 ± 0.07."""
    problem, components, _ = fig7
    lbc = gridlbc.combine(components)
    cert = gridlbc.certify(  # against a reference at the same step: its bias is not in question
        problem,
        lbc.policy,
        GYMNAST_START,
        n_samples=1000,
        dt=0.002,
        seed=0,
        progress=False,
        step_check=False,
    )
    assert cert.proposals[1].startswith("a 31×31×31×31 grid solution (auto)")
    assert cert.trusted
    value, se = GRID_PROPOSAL_OPTIMUM
    assert abs(cert.optimal_value - value) < 3 * np.hypot(cert.optimal_value_se, se)


GRID_PROPOSAL_OPTIMUM = (19.091, 0.011)
"""v*(x₀) of the gymnast at Δt 0.002 (hip stops and momentum box reflecting), certified with the
default 51⁴ grid policy as proposal, 8000 paths (``benchmarks/gymnast_trackers.py``, table (r))."""

STEP_EXTRAPOLATED_OPTIMUM = (19.657, 0.024)
"""v*(x₀) of the gymnast's SDE (hip stops and momentum box reflecting), extrapolated to Δt → 0
from certificates at Δt 0.001 and 0.002 with the default 51⁴ grid policy as proposal, 8000 paths
each (``benchmarks/gymnast_trackers.py``, table (r); from Δt 0.002 and 0.004: 19.644 ± 0.026)."""


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::gridlbc.errors.ResolutionWarning")  # the 31⁴ solve's estimate
def test_default_certificate_holds_the_step_extrapolated_optimum():
    """Issue 28, item 2: a certificate of the gymnast with a grid policy as proposal and
    ``richardson=True`` at Δt 0.002 (and 0.004) gives an interval that holds the step-extrapolated
    optimum, which the single-step estimate (about 3 % low) misses. The default 31⁴ solve (a few
    seconds, 0.6 GiB) is the proposal here: poorer than the 51⁴ one of the reference, so its
    certificate is wider, but trusted (k̂ < 0.7). Measured: v* = 19.10 ± 0.06 at Δt 0.002 (ESS 239
    of 2000, k̂ 0.57), extrapolated 19.64 ± 0.13, 95 % interval [19.38, 19.89]; about 15 s."""
    problem = gymnast_problem(31)
    solution = gridlbc.solve(problem)

    def policy(x, t):
        return solution.policy(x, min(t, problem.horizon))

    cert = gridlbc.certify(
        problem, policy, GYMNAST_START, n_samples=2000, dt=0.002, seed=0, richardson=True
    )
    assert cert.trusted and cert.pareto_k < 0.7
    value, se = STEP_EXTRAPOLATED_OPTIMUM
    lo, hi = cert.interval(0.95)
    assert lo - 2 * se <= value <= hi + 2 * se, (lo, hi)
    # the step matters: the Δt = 0.002 estimate alone is several of its SE below the optimum
    assert cert.optimal_value + 3 * cert.optimal_value_se < value - se
