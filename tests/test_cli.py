"""The ``gridlbc`` command and TOML problem descriptions.

Subprocess runs check what a user sees: exit status 0 on success, 2 and one line on stderr for a
mistake (never a traceback). Validation messages are checked in-process (fast), through
``cli.main``, which is what the console script calls.
"""

import subprocess
import sys

import numpy as np
import pytest

import gridlbc
from gridlbc.cli import main
from gridlbc.config import load_config, number, problem_from_dict

POINTMASS = """
horizon = 1.0
temperature = 0.5
[system]
name = "PointMass"
[grid]
n = 21
[terminal_cost]
center = [{c}, 0]
weights = [4, 1]
[solver]
dt = 0.05
"""


def run(*args):
    return subprocess.run([sys.executable, "-m", "gridlbc.cli", *args], capture_output=True,
                          text=True, timeout=300, check=False)


def one_line_error(result, *fragments):
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


@pytest.mark.parametrize("command", ["", "demo", "verify", "solve", "combine", "certify",
                                     "figures"])
def test_help_everywhere(command):
    result = run(*([command] if command else []), "--help")
    assert result.returncode == 0
    assert "usage: gridlbc" in result.stdout


def test_solve_combine_round_trip(tmp_path):
    """solve from TOML and from flags saves exactly what gridlbc.solve computes; combine
    evaluates the combination exactly as gridlbc.combine does."""
    (tmp_path / "left.toml").write_text(POINTMASS.format(c=-1))
    left = run("solve", "--config", str(tmp_path / "left.toml"), "--out", str(tmp_path / "l"))
    assert left.returncode == 0, left.stderr
    assert "wrote" in left.stdout and "steps" in left.stderr  # progress bar on stderr
    right = run("solve", "--system", "pointmass", "--grid", "21", "--horizon", "1",
                "--temperature", "0.5", "--terminal-center", "1,0", "--terminal-weights", "4,1",
                "--dt", "0.05", "--out", str(tmp_path / "r.npz"), "--quiet")
    assert right.returncode == 0, right.stderr
    a, b = gridlbc.load(tmp_path / "l.npz"), gridlbc.load(tmp_path / "r.npz")
    for saved, c in ((a, -1), (b, 1)):
        direct = gridlbc.solve(problem_from_dict(_description(c)).problem, dt=0.05)
        np.testing.assert_array_equal(saved.slices, direct.slices)  # deterministic: bit for bit
        np.testing.assert_array_equal(saved.log_scales, direct.log_scales)

    table = tmp_path / "t.csv"
    result = run("combine", str(tmp_path / "l.npz"), str(tmp_path / "r.npz"), "--at=0.3,0.2",
                 "--at=0,0", "--table", str(table))
    assert result.returncode == 0, result.stderr
    rows = np.loadtxt(table, delimiter=",", skiprows=1)
    combined = gridlbc.combine([a, b])
    states = np.array([[0.3, 0.2], [0.0, 0.0]])
    np.testing.assert_allclose(rows[:, 2], combined.value(states, 0.0), rtol=1e-12)
    np.testing.assert_allclose(rows[:, 4:], combined.blend_weights(states, 0.0), rtol=1e-12)
    # at the symmetric state both goals are equally desirable
    np.testing.assert_allclose(rows[1, 4:], [0.5, 0.5], atol=1e-12)


def test_combine_project_prints_weights_and_warnings(tmp_path):
    problem = problem_from_dict(_description(-1)).problem
    sols = gridlbc.solve_many(problem, [gridlbc.Quadratic([c, 0], [4, 1]) for c in (-1, 1)],
                              dt=0.05)
    paths = [gridlbc.save(s, tmp_path / f"s{k}") for k, s in enumerate(sols)]
    result = run("combine", *map(str, paths), "--project", "0.2,0")
    assert result.returncode == 0, result.stderr
    expected = gridlbc.projection(gridlbc.Quadratic([0.2, 0], [4, 1]),
                                  [s.problem.terminal_cost for s in sols], problem.grid,
                                  temperature=0.5).weights
    printed = result.stdout.split("[")[1].split("]")[0]
    np.testing.assert_allclose([float(v) for v in printed.split(",")], expected, rtol=0,
                               atol=5e-7)  # printed rounded to 6 decimals
    # components ±1 with W = 4 at λ = 0.5 (width 0.25) are far too narrow for a target at 0.2
    assert "warning: weights sum to" in result.stderr


def test_certify_prints_what_gridlbc_certify_computes(tmp_path):
    """certify on a saved solution: the same numbers as gridlbc.certify with the same seed (the
    run is deterministic given the seed), beside the solution's prediction."""
    problem = problem_from_dict(_description(0.5)).problem
    solution = gridlbc.solve(problem, dt=0.05)
    path = gridlbc.save(solution, tmp_path / "s")
    result = run("certify", str(path), "--state=0.2,-0.3", "--state=0,0", "--samples", "200",
                 "--seed", "3", "--quiet")
    assert result.returncode == 0, result.stderr
    states = np.array([[0.2, -0.3], [0.0, 0.0]])
    cert = gridlbc.certify(problem, solution.policy, states, n_samples=200, seed=3)
    rows = np.array([[float(v) for v in line.split()] for line in result.stdout.splitlines()[-2:]])
    predicted = solution.value(states, 0.0)
    for column, expected in ((0, predicted), (1, cert.optimal_value), (4, cert.policy_cost),
                             (5, cert.gap), (6, cert.effective_sample_size)):
        np.testing.assert_allclose(rows[:, column], expected, rtol=1e-4)  # printed to 5 digits
    assert "certified optimum v*" in result.stdout and result.stderr == ""
    one_line_error(run("certify", str(path)), "--state")


@pytest.mark.parametrize("args, fragments", [
    (["solve", "--system", "nope", "--grid", "5", "--horizon", "1", "--terminal-center", "0",
      "--terminal-weights", "1", "--out", "x"], ["unknown system.name 'nope'", "Pendulum"]),
    (["solve", "--system", "pendulum", "--axis=-pi,pi,x", "--out", "x"], ["--axis expects"]),
    (["combine", "missing.npz"], ["no saved solution at 'missing.npz'"]),
])
def test_user_mistakes_subprocess(args, fragments):
    one_line_error(run(*args), *fragments)


def test_bad_flag_is_argparse_error():
    result = run("solve", "--no-such-flag", "--out", "x")
    assert result.returncode == 2 and "unrecognized arguments" in result.stderr


def _description(c):
    import tomllib

    return tomllib.loads(POINTMASS.format(c=c))


@pytest.mark.parametrize("change, fragment", [
    ({"horizon": None}, "missing key 'horizon'"),
    ({"horizn": 1.0}, "unknown key 'horizn'"),
    ({"grid": {"n": [21, 21, 21]}}, "grid.n must be one node count or 2"),
    ({"grid": {"n": 21, "axes": []}}, "exactly one of grid.n"),
    ({"grid": {"axes": [{"lo": -1, "hi": 1}]}}, "missing key 'grid.axes[0].n'"),
    ({"terminal_cost": {"center": [0, 0], "weight": [1, 1]}}, "unknown key 'terminal_cost.weight'"),
    ({"terminal_cost": {"center": [0, 0, 0], "weights": [1, 1, 1]}}, "3 coordinates"),
    ({"solver": {"method": "magic"}}, "unknown method 'magic'"),
    ({"system": {"name": "PointMass", "parameters": {"mass": -1}}}, "system.parameters: mass must be a positive"),
    ({"system": {"name": "PointMass", "parameters": {"length": 1}}}, "system.parameters"),
    ({"temperature": "hot"}, "temperature must be a number"),
    ({"horizon": -1.0}, "horizon must be positive"),
])
def test_description_errors_name_the_key(change, fragment):
    data = _description(0)
    for key, value in change.items():
        if value is None:
            del data[key]
        else:
            data[key] = value
    with pytest.raises((ValueError, TypeError), match=None) as info:
        problem_from_dict(data)
    assert fragment in str(info.value)


def test_load_config_explicit_axes_and_pi(tmp_path):
    path = tmp_path / "p.toml"
    path.write_text("""
horizon = 2
control_cost = [0.5]
[system]
name = "gridlbc.systems.Pendulum"
parameters = { damping = 0.1 }
[[grid.axes]]
lo = "-pi"
hi = "pi"
n = 24
periodic = true
[[grid.axes]]
lo = -8
hi = 8
n = 17
[terminal_cost]
center = [0, 0]
weights = [[10, 0], [0, 0.5]]
[state_cost]
center = ["pi/2", 0]
weights = [1, 0]
""")
    config = load_config(path)
    p = config.problem
    assert p.system == gridlbc.systems.Pendulum(damping=0.1)
    assert p.grid.shape == (24, 17) and p.grid.axes[0].periodic and not p.grid.axes[1].periodic
    assert p.grid.axes[0].lo == -np.pi and p.grid.axes[0].hi == np.pi
    np.testing.assert_array_equal(p.R, [[0.5]])
    # the state cost is centred at π/2: q(π/2, 0) = 0 and q(0, 0) = (π/2)²
    np.testing.assert_allclose(p.state_cost(np.array([[np.pi / 2, 0], [0, 0]])),
                               [0, (np.pi / 2) ** 2], rtol=1e-15, atol=0)
    assert config.settings.method == "splitting"


def test_load_config_reports_file_and_syntax(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("horizon = = 1\n")
    with pytest.raises(ValueError, match="bad.toml: invalid TOML"):
        load_config(path)
    with pytest.raises(FileNotFoundError):
        load_config(tmp_path / "none.toml")


@pytest.mark.parametrize("text, expected", [("pi", np.pi), ("-pi", -np.pi), ("pi/2", np.pi / 2),
                                            ("2*pi", 2 * np.pi), ("-0.5pi", -np.pi / 2),
                                            ("1e-3", 1e-3), (3, 3.0)])
def test_number(text, expected):
    assert number(text, "k") == expected


@pytest.mark.parametrize("bad", ["pie", "inf", True, None])
def test_number_rejects(bad):
    with pytest.raises((ValueError, TypeError), match="k must be"):
        number(bad, "k")


def test_main_catches_mistakes_in_process(capsys):
    assert main(["combine", "nothing.npz"]) == 2
    assert "no saved solution" in capsys.readouterr().err
    assert main(["solve", "--grid", "5,x", "--out", "o"]) == 2
    assert "--grid expects node counts" in capsys.readouterr().err
    assert main(["solve", "--system", "pointmass", "--grid", "5", "--horizon", "1",
                 "--out", "o"]) == 2
    assert "give --terminal-center and --terminal-weights" in capsys.readouterr().err


def test_demo_runs_small_and_checks_what_it_claims(tmp_path):
    """The demo job on a 61² grid: superposition of the fitted combination to rounding, and the
    fitted prediction closer to its Monte-Carlo cost than the plain one (measured at 61²: plain
    gap about 50 %, fitted under 10 %)."""
    from gridlbc.demo import run_demo

    results = run_demo(tmp_path, grid_size=61, progress=False, n_samples=100)
    assert results["superposition_value"] < 1e-10 and results["superposition_policy"] < 1e-8
    assert abs(results["relative_gap"]) < abs(results["plain_relative_gap"])
    assert (tmp_path / "demo_swingup.png").stat().st_size > 0
    assert (tmp_path / "demo_combined.png").stat().st_size > 0
