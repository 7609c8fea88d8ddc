"""The interactive page (gridlbc interactive): its numbers against gridlbc.combine, in Chromium.

The page evaluates, in JavaScript, the same interpolation of the same embedded slices as
gridlbc.combine, so the two agree to rounding (float64 on both sides): the browser tests ask
for 1e-9 relative, far tighter than the 1e-5 the command promises. The rollout is the same
Euler recursion as gridlbc.simulate(noise=False); 300 steps of a swing-up amplify rounding by a
few orders of magnitude at most (1e-7 asked).
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numba
import numpy as np
import pytest
from conftest import SMOKE_SIZES

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.cli import main
from gridlbc.interactive import decimate, embed, write_page
from gridlbc.project import projection
from gridlbc.systems import Pendulum, PointMass, SingleIntegrator

CHROMIUM = shutil.which("chromium")
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="Debian's chromium is not installed here (.ci/run installs it in CI)"
)
REL = 1e-9


@pytest.fixture(scope="module")
def pendulum_files(tmp_path_factory):
    """Three small pendulum solutions (one fitted operator), saved as a user would."""
    grid = Grid([Axis(-np.pi, np.pi, 31, periodic=True), Axis(-8.0, 8.0, 29)])
    problem = Problem(Pendulum(), grid, 1.0, Quadratic([0, 0], [4, 0.5]), temperature=1.0)
    goals = [Quadratic([c, 0.0], [4.0, 0.5]) for c in (-0.8, 0.8, 3.0)]
    sols = gridlbc.solve_many(problem, goals, fitting="terminal", dt=0.05)
    out = tmp_path_factory.mktemp("interactive")
    return [gridlbc.save(s, out / f"goal{i}.npz") for i, s in enumerate(sols)]


def _dump(page: Path, query: str) -> dict:
    """Open page?query in headless Chromium; the JSON of #probe, #probe-details and #timing."""
    with tempfile.TemporaryDirectory() as profile:
        dom = subprocess.run(
            [
                CHROMIUM,
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                f"--user-data-dir={profile}",
                "--dump-dom",
                f"{page.resolve().as_uri()}?{query}",
            ],
            capture_output=True,
            text=True,
            timeout=120,
            check=True,
        ).stdout
    out = {}
    for name in ("probe", "probe-details", "timing"):
        match = re.search(f'<pre id="{name}">([^<]*)</pre>', dom)
        assert match, f"#{name} missing from the page's DOM"
        out[name] = json.loads(match.group(1).replace("&amp;", "&").replace("&quot;", '"'))
    return out


def _query(weights, state, t) -> str:
    return f"weights={','.join(map(repr, weights))}&state={','.join(map(repr, state))}&time={t!r}"


def _assert_probe(probe: dict, combined, weights, state, t):
    x = np.asarray(state, dtype=float)
    assert "error" not in probe, probe
    v = combined.value(x, t)
    u = combined.policy(x, t)
    alpha = combined.blend_weights(x, t)
    np.testing.assert_allclose(probe["value"], v, rtol=REL)
    np.testing.assert_allclose(probe["policy"], u, rtol=REL, atol=REL * max(1.0, abs(u).max()))
    np.testing.assert_allclose(probe["alpha"], alpha, rtol=REL, atol=REL)


CASES = [
    ((1.0, 1.0, 0.0), (2.8, 0.0), 0.0),  # swing up to either goal, from near hanging
    ((1.0, 0.5, 0.0), (np.pi - 1e-4, 1.3), 0.37),  # just left of the periodic seam, between slices
    ((0.7, 1.2, 0.1), (-np.pi + 1e-4, -2.1), 0.9),  # just right of it
    ((1.0, -0.05, 0.5), (5.0, 11.0), 0.53),  # θ wrapped from outside, ω clamped; w < 0
]


@SMOKE_SIZES
@pytest.mark.slow
@needs_chromium
def test_page_equals_combine_on_saved_solutions(pendulum_files, tmp_path):
    page = tmp_path / "page.html"
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "gridlbc.cli",
            "interactive",
            *map(str, pendulum_files),
            "--out",
            str(page),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "decimated" not in result.stdout  # small enough to embed whole
    solutions = [gridlbc.load(p) for p in pendulum_files]
    for weights, state, t in CASES:
        combined = gridlbc.combine(solutions, weights)
        out = _dump(page, _query(weights, state, t))
        _assert_probe(out["probe"], combined, weights, state, t)
        if t == 0.0:  # the rollout drawn on the maps: gridlbc.simulate's noise-free closed loop
            threads = numba.get_num_threads()
            numba.set_num_threads(1)  # one state per step: a thread launch costs more than it
            try:  # computes (≈ 100× on a loaded 2-core machine)
                rollout = gridlbc.simulate(combined.problem, combined.policy, state, noise=False)
            finally:
                numba.set_num_threads(threads)
            details = out["probe-details"]["rollout"]
            assert details["steps"] == rollout.controls.shape[1]
            np.testing.assert_allclose(
                details["final_state"], rollout.final_states[0], rtol=1e-7, atol=1e-7
            )
            np.testing.assert_allclose(details["cost"], rollout.costs[0], rtol=1e-7)

    # a goal picked by projection: gridlbc.projection's weights (quadrature on the periodic grid)
    goal = (0.3, 0.4)
    out = _dump(page, f"goal={goal[0]},{goal[1]}&state=1,0.5&time=0.2")
    costs = [s.problem.terminal_cost for s in solutions]
    target = Quadratic(goal, costs[0].weights).with_periods(solutions[0].grid.periods)
    expected = projection(target, costs, solutions[0].grid, temperature=1.0)
    got = out["probe-details"]["projection"]
    assert got["method"] == expected.method == "quadrature"
    np.testing.assert_allclose(got["weights"], expected.weights, rtol=1e-9)
    np.testing.assert_allclose(got["residual"], expected.residual, rtol=1e-6)
    _assert_probe(
        out["probe"],
        gridlbc.combine(solutions, expected.weights),
        expected.weights,
        (1.0, 0.5),
        0.2,
    )


@SMOKE_SIZES
@needs_chromium
def test_decimated_page_equals_combine_of_decimated(pendulum_files, tmp_path):
    """Decimated on the way in (grid and slices), the page is exact for the decimated data."""
    page = tmp_path / "small.html"
    solutions = [gridlbc.load(p) for p in pendulum_files]
    report = write_page(solutions, page, nodes=(17, 13), n_times=6)
    assert report.embedding.decimated and report.embedding.shape == (17, 13)
    small = report.embedding.components
    for weights, state, t in CASES[1:3]:
        _assert_probe(
            _dump(page, _query(weights, state, t))["probe"],
            gridlbc.combine(small, weights),
            weights,
            state,
            t,
        )


@SMOKE_SIZES
@needs_chromium
def test_pointmass_projection_is_closed_form(tmp_path):
    grid = Grid([Axis(-2.0, 2.0, 25), Axis(-3.0, 3.0, 21)])
    problem = Problem(PointMass(), grid, 1.0, Quadratic([0, 0], [2, 1]), temperature=0.5)
    goals = [Quadratic([-1, 0], [2, 1]), Quadratic([1, 0], [2, 1])]
    sols = gridlbc.solve_many(problem, goals, dt=0.05)
    page = tmp_path / "pm.html"
    write_page(sols, page)
    out = _dump(page, "goal=0.25,0.1&state=1.5,-1&time=0.3")
    expected = projection(Quadratic([0.25, 0.1], [2, 1]), goals, None, temperature=0.5)
    assert out["probe-details"]["projection"]["method"] == expected.method == "analytic"
    np.testing.assert_allclose(
        out["probe-details"]["projection"]["weights"], expected.weights, rtol=1e-9
    )
    _assert_probe(
        out["probe"], gridlbc.combine(sols, expected.weights), expected.weights, (1.5, -1.0), 0.3
    )
    bad = _dump(page, "weights=1,-1&state=0,0")["probe"]
    assert "sum" in bad["error"]


@SMOKE_SIZES
@needs_chromium
def test_first_exit_page_equals_combine_and_stops_at_the_exit(tmp_path):
    # Three parking bays (a stationary first-exit problem): the page holds its one slice over
    # [0, T] (time does not matter), evaluates gridlbc.combine exactly, and its rollout ends in
    # the exit set. The components' exit costs are of the three kinds the page reads: one by its
    # values at the nodes (a callable), a quadratic and a constant.
    from gridlbc.regions import GridRegion
    from gridlbc.studies.problems import bay_cost, bays_problem

    base = bays_problem(41)
    costs = [bay_cost(1), Quadratic([0.0, 0.0], [1.0, 0.5]), 0.7]
    parts = [gridlbc.solve(base.replace(exit_cost=c)) for c in costs]
    page = tmp_path / "bays.html"
    write_page(parts, page)
    weights = (1.0, 0.02, 0.02)
    combined = gridlbc.combine(parts, weights)
    out = _dump(page, "weights=1,0.02,0.02&state=-0.6,1.2&time=3")
    _assert_probe(out["probe"], combined, weights, (-0.6, 1.2), 0.0)
    html = page.read_text()
    assert '"stationary":true' in html
    # In the middle bay, in cells that its edge crosses: the task has ended, so the value is the
    # composite exit cost -λ log Σ w_i exp(-g_i/λ) and the control is 0, as gridlbc.combine
    # gives; interpolating the nodes across the edge would mix in the solved z of the nodes
    # outside the bay. The page knows the bay's shape: a state in it whose nodes' membership
    # interpolates below 1/2 is in E, and one outside it above 1/2 is not.
    lam = base.temperature
    by_nodes = GridRegion(base.grid, base.exit_mask())
    x = np.random.default_rng(1).uniform([-0.25, -0.5], [0.25, 0.5], (400, 2))
    inside, nodal = base.exit(x), by_nodes(x)
    states = [x[inside & ~nodal][0], x[~inside & nodal][0], (0.0, 0.35)]
    for state in states:
        query = f"weights=1,0.02,0.02&state={float(state[0])!r},{float(state[1])!r}&time=0"
        probe = _dump(page, query)["probe"]
        _assert_probe(probe, combined, weights, state, 0.0)
        if base.exit(np.array([state]))[0]:
            g_i = [
                cost(np.array([state]))[0] if callable(cost) else cost
                for cost in (parts[0].problem.exit_cost, parts[1].problem.exit_cost, 0.7)
            ]
            composite = -lam * np.log(np.dot(weights, np.exp(-np.array(g_i) / lam)))
            np.testing.assert_allclose(probe["value"], composite, rtol=1e-12)
            assert probe["policy"] == [0.0]


@SMOKE_SIZES
def test_decimate_evaluates_the_solution_itself(pendulum_files):
    sol = gridlbc.load(pendulum_files[0])
    small = decimate(sol, (11, 9), n_times=5)
    assert small.grid.shape == (11, 9) and small.grid.axes[0].period == sol.grid.axes[0].period
    assert small.times[0] == 0.0 and small.times[-1] == sol.problem.horizon
    assert np.all(np.isin(small.times, sol.times))
    assert small.slices.dtype == np.float32 and small.diagnostics.flushed_values == 0
    X = small.grid.nodes()
    for t in small.times:  # float32 rounds z by 2^-24 relative: v by λ 2^-24 (λ = 1)
        np.testing.assert_allclose(small.value(X, t), sol.value(X, t), rtol=0, atol=2.0**-23)
    exact = decimate(sol, (11, 9), n_times=5, dtype="float64")
    for t in small.times:
        np.testing.assert_allclose(exact.value(X, t), sol.value(X, t), rtol=1e-12)
    assert embed([sol]).components[0] is sol  # small: embedded whole
    assert embed([sol], max_bytes=20_000).decimated


# Appended to a copy of the page: drives its controls as a user would, then reports.
USER_SCRIPT = """<script>
(function () {
  const out = {};
  const sliders = document.querySelectorAll("#weights input[type=range]");
  sliders[2].value = "2"; sliders[2].dispatchEvent(new Event("input"));
  out.after_weight = document.getElementById("readout").textContent;
  const map = document.getElementById("value-map"), r = map.getBoundingClientRect();
  const click = (fx, fy) => map.dispatchEvent(new MouseEvent("click", {bubbles: true,
    clientX: r.left + fx * r.width, clientY: r.top + fy * r.height}));
  click(0.5, 0.5);
  out.after_click = document.getElementById("readout").textContent;
  const goal = document.querySelector("input[name=mode][value=goal]");
  goal.checked = true; goal.dispatchEvent(new Event("change"));
  click(0.55, 0.5);
  out.projection = document.getElementById("projection").textContent;
  out.weights = Array.from(document.querySelectorAll("#weights input[type=number]"), (b) => Number(b.value));
  document.getElementById("timing").textContent = JSON.stringify(out);
})();
</script></body>"""


@SMOKE_SIZES
@needs_chromium
def test_controls_drive_the_page(pendulum_files, tmp_path):
    """Slider, click and goal mode change what the page shows (the wiring, not the numbers)."""
    page = write_page(
        [gridlbc.load(p) for p in pendulum_files],
        tmp_path / "p.html",
        weights=(1, 1, 0),
        state=(2.8, 0.0),
    ).path
    page.write_text(page.read_text(encoding="utf-8").replace("</body>", USER_SCRIPT))
    out = _dump(page, "")["timing"]
    # the third goal (θ = 3, near the start) now dominates the blend at the start state
    alpha3 = float(re.search(r"α3([-0-9.]+)", out["after_weight"]).group(1))
    assert alpha3 > 0.9, out["after_weight"]
    assert "state x(2.800, 0.000)" in out["after_weight"]
    assert "state x(2.800" not in out["after_click"]  # the click moved the start state
    assert out["projection"].startswith("goal (")
    assert out["weights"] != [1.0, 1.0, 2.0]  # projection replaced the slider weights


@SMOKE_SIZES
def test_page_loads_nothing_from_the_network(pendulum_files, tmp_path):
    report = write_page([gridlbc.load(p) for p in pendulum_files], tmp_path / "p.html")
    html = report.path.read_text(encoding="utf-8")
    assert report.size == len(html.encode("utf-8"))
    for reference in (
        "http://",
        "https://",
        "//cdn",
        " src=",
        "<link",
        "import(",
        "fetch(",
        "XMLHttpRequest",
        "url(",
    ):
        assert reference not in html, reference
    assert html.count("<script") == 2  # the data (JSON) and the inline script


def test_unsupported_system_is_a_clear_error(tmp_path, capsys):
    grid = Grid([Axis(-1.0, 1.0, 11)])
    sol = gridlbc.solve(Problem(SingleIntegrator(), grid, 0.5, Quadratic([0], [1])), dt=0.1)
    path = gridlbc.save(sol, tmp_path / "si.npz")
    assert main(["interactive", str(path), "--out", str(tmp_path / "x.html")]) == 2
    assert "supports 2-D Pendulum and PointMass" in capsys.readouterr().err
