"""The hold-out corpus (benchmarks/holdout/): its truths are well formed, and the default solve of
its cheap 2-D members still predicts what the stored table says.

The truths are certified optima (gridlbc.certify) stored with how they were made; the table
(``table.json``, written by ``run.py --json``) holds the default solve's predictions. When a change
to the default solve moves them on purpose, rerun ``python benchmarks/holdout/run.py --json
benchmarks/holdout/table.json`` and read the new errors against the truths.
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

HOLDOUT = Path(__file__).resolve().parents[2] / "benchmarks" / "holdout"
sys.path.insert(0, str(HOLDOUT))

from corpus import BY_NAME, MEMBERS  # noqa: E402

TRUTH_KEYS = {"what", "proposal", "n_samples", "dt", "dt_coarse", "date", "command", "states"}
STATE_KEYS = {"x", "v", "se", "ess", "v_coarse_dt", "step_bias", "left_box"}


@pytest.fixture(scope="module")
def truths():
    return json.loads((HOLDOUT / "truths.json").read_text())["members"]


def test_corpus_spans_what_it_claims():
    assert len(MEMBERS) >= 15
    dims = {m.build().grid.ndim for m in MEMBERS}
    assert dims == {2, 3, 4}
    temperatures = [m.build().temperature for m in MEMBERS]
    assert min(temperatures) <= 0.01 and max(temperatures) >= 3.0
    for m in MEMBERS:
        assert m.states.shape[0] >= 3 and m.states.shape[1] == m.build().grid.ndim, m.name


def test_truths_are_well_formed(truths):
    """Every member has a truth at each of its states, with its SE, ESS, proposal, samples, step
    and command; the step bias (v* at dt and 2 dt) and the SE are small against v*."""
    assert set(truths) <= set(BY_NAME)
    assert len(truths) >= 15
    for name, record in truths.items():
        assert set(record) >= TRUTH_KEYS, name
        states = record["states"]
        np.testing.assert_allclose([s["x"] for s in states], BY_NAME[name].states)
        for s in states:
            assert set(s) >= STATE_KEYS, name
            assert np.isfinite(s["v"]), name
            if record["proposal"].startswith("exact"):  # by quadrature or a closed form
                assert s["se"] == 0 and s["ess"] is None and s["step_bias"] == 0, name
                continue
            assert s["se"] > 0 and 0 < s["ess"] <= record["n_samples"], name
            assert s["se"] <= 0.02 * abs(s["v"]), (name, s)


def test_fast_members_predict_what_the_table_says():
    """run.py --fast runs, and its predictions are those of the stored table."""
    table = {
        (r["member"], tuple(r["state"])): r["predicted"]
        for r in json.loads((HOLDOUT / "table.json").read_text())
    }
    result = subprocess.run(
        [sys.executable, str(HOLDOUT / "run.py"), "--fast", "--json", "-"],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    rows = json.loads(result.stdout.split("\n#json\n", 1)[1])
    assert {r["member"] for r in rows} == {m.name for m in MEMBERS if m.fast}
    for r in rows:
        expected = table[(r["member"], tuple(r["state"]))]
        assert r["predicted"] == pytest.approx(expected, rel=1e-6), r
    assert "pairs with a truth" in result.stdout


@pytest.mark.parametrize("periodic, n", [(True, 201), (False, 202)])
def test_a_pit_between_nodes_of_an_axis_that_is_not_nested_is_not_silent(truths, periodic, n):
    """rotor_pit: the pit's centre lies midway between two nodes (an odd periodic axis, or an
    even closed one over the same circle: the same nodes plus one at +π), and the embedded axis
    of n // 2 nodes has a node at it. Without the pair of grids (phase_pair) the estimate was
    three quarters of a 10 % error and the solve silent; now it must be at least half the error
    against the certified optimum at every state (the corpus calibration target) and warn. The
    closed variant is judged against the periodic truth: reflection at ±π is never reached from
    these states by a rotor held in the pit at λ = 0.005."""
    import gridlbc as g

    problem = BY_NAME["rotor_pit"].build()
    theta, omega = problem.grid.axes
    grid = g.Grid([g.Axis(theta.lo, theta.hi, n, periodic=periodic), omega])
    _judge(problem.replace(grid=grid), "rotor_pit", truths)


@pytest.mark.parametrize("name", ["mass_pit_centre", "mass_pit_wall"])
def test_a_pit_where_the_pair_is_blind_is_seen_along_the_paths(truths, name):
    """A pit half a cell from a node next to the centre of the axis, or next to its wall: there the
    two grids of the pair miss it by the same fraction of their cell, as the embedded grid does,
    and the solve was silently 15 % high (estimate 4 % and 9 %). The cost the grid's
    interpolant adds along the solve's own paths (gridlbc.accuracy.cost_gap) sees it: the
    estimate must be at least half the error against the certified optimum at every state (the
    corpus calibration target) and the default solve must warn."""
    relative = _judge(BY_NAME[name].build(), name, truths)
    assert relative.max() > 0.1  # the grid misses the pit


@pytest.mark.parametrize("name", ["goal_off8_3d", "goal_m2_3d"])
def test_a_goal_between_the_lattice_points_is_found_and_warned(truths, name):
    """A 3-D goal far narrower than the sampling lattice's spacing whose centre is equidistant
    from a node and the lattice points around it (an eighth of a cell wide an eighth off with
    four lattice points per cell; a fifth of a cell wide a quarter off with two): all of them see
    the same tail, and the solve was silently 30–43 % high with estimates below 0.3 %. The
    descent from the lattice's lowest excess (gridlbc.accuracy.subcell.descend) finds its
    bottom: at the states more than 10 % off the estimate must be at least half the error
    against the exact values (the corpus calibration target), and the default solve must warn.
    (Away from the goal, at (1, −1, 0.5), goal_m2_3d's estimate is 0.058 against an error of
    0.119: the response of the embedded grid, spacing 2h, is not all of it.)"""
    _covered_where_off(truths, name, share=0.1, least=2)


def test_a_4d_goal_is_felt_by_the_response_of_the_plain_scheme(truths):
    """goal4d_mid (a 4-D goal a sixth of a cell wide at a lattice cell's centre) was silently
    11.5 % high with S = 2.6 %: the embedded solve, exponentially fitted, spreads a dip that its
    reference does not have by about a cell per step (a dip at one node of an 11⁴ grid moved v
    by 0.15–0.3 of the heat kernel's exact response). The response is now measured with the
    plain scheme: the default solve must warn, and the estimate must be at least half the error
    against the exact values wherever that exceeds 5 % (the corpus calibration target)."""
    _covered_where_off(truths, "goal4d_mid", share=0.05, least=2)


@pytest.mark.parametrize("name", ["notch_exit", "notch_exit_horizon"])
def test_a_notch_in_the_exit_cost_is_felt_by_the_first_exit_estimate(truths, name):
    """notch_exit (first exit through a half-plane whose exit cost has a cheap notch a twelfth
    of a cell wide, 0.024 from the nodes of every grid the estimate reads) was silently 13–47 %
    high with estimates of 2 %: every level and the pair miss the notch alike. S, the embedded
    solve's response to the exit cost's excess between the nodes, sees it: the default solve
    must warn, and the estimate must be at least half the error against the exact values at
    every state more than 10 % off (the corpus calibration target); with a horizon too, where
    the exit cost is sampled beside g and q (stranger round 12: 13 % and 47 % high with
    estimates of 6.5 % and 8.7 % before)."""
    _covered_where_off(truths, name, share=0.1, least=2)


def _covered_where_off(truths, name, share, least):
    """Solve member ``name`` by default and check it against its exact values (:func:`_judge`):
    at least ``least`` of its states are more than ``share`` off."""
    relative = _judge(BY_NAME[name].build(), name, truths, key="v", share=share)
    assert np.sum(relative > share) >= least  # the grid misses the feature


def _judge(problem, name, truths, key="v_extrapolated", share=0.0):
    """Solve ``problem`` by default and check it against member ``name``'s truths (``key``: the
    certificate extrapolated in Δt, or "v", exact values): the estimate at least half the error
    at every state more than ``share`` off, and a ResolutionWarning. Returns the relative
    errors."""
    import warnings

    import gridlbc as g

    states = BY_NAME[name].states
    truth = np.array([s[key] for s in truths[name]["states"]])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        solution = g.solve(problem)
    error = np.abs(solution.value(states) - truth)
    off = error > share * np.abs(truth)
    assert np.all(solution.error_estimate(states[off]) >= error[off] / 2)
    assert any(issubclass(w.category, g.ResolutionWarning) for w in caught)
    return error / np.abs(truth)


def test_a_local_response_warns_where_the_percentile_does_not():
    """goal4d_mid (a 4-D goal a sixth of a cell wide, 11.5 % high at it): the estimate's 90th
    percentile over the states that matter is below the 5 % tolerance, since the goal changes v
    on a small share of them; S, judged at its largest (accuracy.assessment.largest_response),
    exceeds it near the goal, and the warning says where."""
    import warnings

    import gridlbc as g
    from gridlbc.accuracy import assessment, matter

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        solution = g.solve(BY_NAME["goal4d_mid"].build())
    X = matter.judged_states(solution)
    relative = solution.embedded.relative(
        solution, X, samples=assessment.ASSESSED_PATHS, local=False
    )
    percentile = assessment.statistic(relative, False)
    largest, where = assessment.largest_response(solution)
    assert percentile < assessment.DEFAULT_TOLERANCE < largest
    assert np.linalg.norm(where - np.array([0.05, -0.35, 0.25, -0.15])) < 0.5  # near the goal
    messages = [str(w.message) for w in caught if issubclass(w.category, g.ResolutionWarning)]
    assert any("near" in m and "narrower than a cell" in m for m in messages)
