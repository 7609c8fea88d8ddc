"""The ``gridlbc`` command.

Subprocess runs check what a user sees: exit status 0 on success, 2 and one line on stderr for a
mistake (never a traceback). Validation messages are checked in-process (fast), through
``cli.main``, which is what the console script calls.
"""

import subprocess
import sys

import numpy as np
import pytest
from conftest import POINTMASS_TOML, SMOKE_SIZES, pointmass_description

import gridlbc
from gridlbc.cli import main
from gridlbc.config import problem_from_dict


def run(*args):
    return subprocess.run(
        [sys.executable, "-m", "gridlbc.cli", *args],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


def one_line_error(result, *fragments):
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


@pytest.mark.parametrize(
    "command", ["", "demo", "verify", "solve", "combine", "certify", "figures", "sweep"]
)
def test_help_everywhere(command):
    result = run(*([command] if command else []), "--help")
    assert result.returncode == 0
    assert "usage: gridlbc" in result.stdout


@SMOKE_SIZES
def test_solve_combine_round_trip(tmp_path):
    """solve from TOML and from flags saves exactly what gridlbc.solve computes; combine
    evaluates the combination exactly as gridlbc.combine does."""
    (tmp_path / "left.toml").write_text(POINTMASS_TOML.format(c=-1))
    left = run("solve", "--config", str(tmp_path / "left.toml"), "--out", str(tmp_path / "l"))
    assert left.returncode == 0, left.stderr
    assert "wrote" in left.stdout and "steps" in left.stderr  # progress bar on stderr
    right = run(
        "solve",
        "--system",
        "pointmass",
        "--grid",
        "21",
        "--horizon",
        "1",
        "--temperature",
        "0.5",
        "--terminal-center",
        "1,0",
        "--terminal-weights",
        "4,1",
        "--dt",
        "0.05",
        "--out",
        str(tmp_path / "r.npz"),
        "--quiet",
    )
    assert right.returncode == 0, right.stderr
    a, b = gridlbc.load(tmp_path / "l.npz"), gridlbc.load(tmp_path / "r.npz")
    for saved, c in ((a, -1), (b, 1)):
        direct = gridlbc.solve(problem_from_dict(pointmass_description(c)).problem, dt=0.05)
        np.testing.assert_array_equal(saved.slices, direct.slices)  # deterministic: bit for bit
        np.testing.assert_array_equal(saved.log_scales, direct.log_scales)

    table = tmp_path / "t.csv"
    result = run(
        "combine",
        str(tmp_path / "l.npz"),
        str(tmp_path / "r.npz"),
        "--at=0.3,0.2",
        "--at=0,0",
        "--table",
        str(table),
    )
    assert result.returncode == 0, result.stderr
    rows = np.loadtxt(table, delimiter=",", skiprows=1)
    combined = gridlbc.combine([a, b])
    states = np.array([[0.3, 0.2], [0.0, 0.0]])
    np.testing.assert_allclose(rows[:, 2], combined.value(states, 0.0), rtol=1e-12)
    np.testing.assert_allclose(rows[:, 4:], combined.blend_weights(states, 0.0), rtol=1e-12)
    # at the symmetric state both goals are equally desirable: to rounding for the plain operator,
    # to the fitted scheme's small mirror asymmetry (its stencils are not mirror images; measured
    # |α − ½| ≈ 1e-6) for the default, each file fitted to its own goal
    assert not combined.exact
    np.testing.assert_allclose(rows[1, 4:], [0.5, 0.5], atol=1e-5)


@SMOKE_SIZES
def test_combine_project_prints_weights_and_warnings(tmp_path):
    problem = problem_from_dict(pointmass_description(-1)).problem
    sols = gridlbc.solve_many(
        problem, [gridlbc.Quadratic([c, 0], [4, 1]) for c in (-1, 1)], dt=0.05
    )
    paths = [gridlbc.save(s, tmp_path / f"s{k}") for k, s in enumerate(sols)]
    result = run("combine", *map(str, paths), "--project", "0.2,0")
    assert result.returncode == 0, result.stderr
    expected = gridlbc.projection(
        gridlbc.Quadratic([0.2, 0], [4, 1]),
        [s.problem.terminal_cost for s in sols],
        problem.grid,
        temperature=0.5,
    ).weights
    printed = result.stdout.split("[")[1].split("]")[0]
    np.testing.assert_allclose(
        [float(v) for v in printed.split(",")], expected, rtol=0, atol=5e-7
    )  # printed rounded to 6 decimals
    # components ±1 with W = 4 at λ = 0.5 (width 0.25) are far too narrow for a target at 0.2
    assert "warning: weights sum to" in result.stderr


@SMOKE_SIZES
def test_certify_prints_what_gridlbc_certify_computes(tmp_path):
    """certify on a saved solution: the same numbers as gridlbc.certify with the same seed (the
    run is deterministic given the seed), beside the solution's prediction."""
    problem = problem_from_dict(pointmass_description(0.5)).problem
    solution = gridlbc.solve(problem, dt=0.05)
    path = gridlbc.save(solution, tmp_path / "s")
    result = run(
        "certify",
        str(path),
        "--state=0.2,-0.3",
        "--state=0,0",
        "--samples",
        "200",
        "--seed",
        "3",
        "--quiet",
    )
    assert result.returncode == 0, result.stderr
    states = np.array([[0.2, -0.3], [0.0, 0.0]])
    cert = gridlbc.certify(problem, solution.policy, states, n_samples=200, seed=3)
    rows = np.array([[float(v) for v in line.split()] for line in result.stdout.splitlines()[-2:]])
    predicted = solution.value(states, 0.0)
    for column, expected in (
        (0, predicted),
        (1, cert.optimal_value),
        (4, cert.policy_cost),
        (5, cert.gap),
        (6, cert.effective_sample_size),
    ):
        np.testing.assert_allclose(rows[:, column], expected, rtol=1e-4)  # printed to 5 digits
    assert "certified optimum v*" in result.stdout and result.stderr == ""
    # By default the closed edges reflect, as in the solve the certificate judges.
    assert "box edges reflect" in result.stdout
    one_line_error(run("certify", str(path)), "--state")
    free = run("certify", str(path), "--state=0,0", "--samples=200", "--seed=3", "--boundary=free")
    cert = gridlbc.certify(
        problem, solution.policy, states[1], n_samples=200, seed=3, boundary="free"
    )
    assert "box edges free" in free.stdout
    v = float(free.stdout.splitlines()[-1].split()[1])
    assert v == pytest.approx(cert.optimal_value, rel=1e-4)
    # --richardson: the certified column is the extrapolated (SDE's) optimum, its SE beside it
    extrapolated = run("certify", str(path), "--state=0,0", "--samples=200", "--seed=3",
                       "--richardson", "--quiet")  # fmt: skip
    cert = gridlbc.certify(problem, solution.policy, states[1], n_samples=200, seed=3,
                           richardson=True)  # fmt: skip
    v, se = (float(c) for c in extrapolated.stdout.splitlines()[-1].split()[1:3])
    assert (v, se) == (
        pytest.approx(cert.extrapolated_value, rel=1e-4),
        pytest.approx(cert.extrapolated_value_se, rel=1e-4),
    )
    assert cert.extrapolated_value != pytest.approx(cert.optimal_value, rel=1e-4)


@pytest.mark.parametrize(
    "args, fragments",
    [
        (
            [
                "solve",
                "--system",
                "nope",
                "--grid",
                "5",
                "--horizon",
                "1",
                "--terminal-center",
                "0",
                "--terminal-weights",
                "1",
                "--out",
                "x",
            ],
            ["unknown system.name 'nope'", "Pendulum"],
        ),
        (["solve", "--system", "pendulum", "--axis=-pi,pi,x", "--out", "x"], ["--axis expects"]),
        (["combine", "missing.npz"], ["no saved solution at 'missing.npz'"]),
    ],
)
def test_user_mistakes_subprocess(args, fragments):
    one_line_error(run(*args), *fragments)


def test_bad_flag_is_argparse_error():
    result = run("solve", "--no-such-flag", "--out", "x")
    assert result.returncode == 2 and "unrecognized arguments" in result.stderr


def test_main_catches_mistakes_in_process(capsys):
    assert main(["combine", "nothing.npz"]) == 2
    assert "no saved solution" in capsys.readouterr().err
    assert main(["solve", "--grid", "5,x", "--out", "o"]) == 2
    assert "--grid expects node counts" in capsys.readouterr().err
    assert (
        main(["solve", "--system", "pointmass", "--grid", "5", "--horizon", "1", "--out", "o"]) == 2
    )
    assert "give --terminal-center and --terminal-weights" in capsys.readouterr().err


def test_solve_to_a_tolerance_prints_its_rounds_and_the_estimate(tmp_path, capsys):
    """``gridlbc solve --tol --at`` is ``gridlbc.solve(problem, tol=, states=)``: the file holds
    that solution bit for bit, and the table prints its value and error estimate at the
    states."""
    (tmp_path / "p.toml").write_text(POINTMASS_TOML.format(c=-1))
    out = str(tmp_path / "p.npz")
    flags = ["--config", str(tmp_path / "p.toml"), "--out", out, "--quiet"]
    assert main(["solve", *flags, "--tol", "0.05", "--at=0.3,0.2", "--at=-1,0"]) == 0
    printed = capsys.readouterr().out
    problem = problem_from_dict(pointmass_description(-1)).problem
    states = np.array([[0.3, 0.2], [-1.0, 0.0]])
    direct = gridlbc.solve(problem, dt=0.05, tol=0.05, states=states)
    saved = gridlbc.load(out)
    np.testing.assert_array_equal(saved.slices, direct.slices)
    assert printed.count("  round: ") == len(direct.refinement)
    assert f"estimated error {direct.refinement[-1].error:.2%}" in printed
    assert "tolerance 0.05 met" in printed and direct.refinement[-1].met(0.05)
    rows = [line.split() for line in printed.splitlines()[-2:]]
    np.testing.assert_allclose([float(r[1]) for r in rows], direct.value(states), rtol=1e-5)
    np.testing.assert_allclose(
        [float(r[2]) for r in rows], direct.error_estimate(states), rtol=1e-2
    )
    assert main(["solve", *flags, "--max-seconds", "5"]) == 2
    assert "give --tol too" in capsys.readouterr().err


def test_the_config_modules_first_exit_example_reads():
    """The TOML of gridlbc.config's docstring for an exit set, with a system and a grid added,
    describes a first-exit problem (its exit_cost above the tables, where TOML keeps it
    top-level)."""
    import textwrap
    import tomllib

    import gridlbc.config

    example = gridlbc.config.__doc__.split("before the first table::")[1].split("``horizon")[0]
    data = tomllib.loads(textwrap.dedent(example))
    data.update(
        system={"name": "PointMass"},
        grid={"n": [21, 21]},
        state_cost={"center": [0, 0], "weights": [1, 1]},
    )
    problem = problem_from_dict(data).problem
    assert problem.horizon is None and problem.exit is not None
    assert problem.exit_mask(np.array([[0.5, 0.0], [-1.3, 0.0], [0.0, 0.0]])).tolist() == [
        True,
        True,
        False,
    ]


def test_certify_a_first_exit_file(tmp_path, capsys):
    """A first exit without a horizon is certified from the command line with --max-time (and
    --dt, which it requires); without them the one-line error names what to give."""
    solution = gridlbc.solve(
        gridlbc.Problem(
            gridlbc.systems.PointMass(),
            gridlbc.Grid([gridlbc.Axis(-2, 2, 21), gridlbc.Axis(-3, 3, 21)]),
            None,
            state_cost=lambda x: 1.0 + 0 * x[:, 0],
            temperature=0.5,
            exit=gridlbc.regions.Ball([1.0, 0.0], [0.4, 0.8]),
        ),
        error_estimate=False,
    )
    path = str(gridlbc.save(solution, tmp_path / "exit"))
    for given in ([], ["--max-time", "20"], ["--dt", "0.02"]):
        assert main(["certify", path, "--state=-1,0", *given, "--quiet"]) == 2
        assert "needs --dt, the Euler–Maruyama step" in capsys.readouterr().err
    flags = ["--state=-1,0", "--samples", "40", "--dt", "0.02", "--max-time", "20", "--seed", "0"]
    assert main(["certify", path, *flags, "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "certified optimum v*" in printed and "first exit" in printed


@SMOKE_SIZES
def test_demo_runs_small_and_checks_what_it_claims(tmp_path):
    """The demo job on a 61² grid: superposition of the fitted combination to rounding, and the
    fitted prediction closer to the certified optimum than the plain one (the plain scheme's
    value is optimistic by tens of percent at 61², the fitted one's within a few)."""
    from gridlbc.studies.demo import run_demo

    results = run_demo(tmp_path, grid_size=61, progress=False, n_samples=100)
    assert results["superposition_value"] < 1e-10 and results["superposition_policy"] < 1e-8
    assert abs(results["relative_error"]) < abs(results["plain_relative_error"])
    assert (tmp_path / "demo_swingup.png").stat().st_size > 0
    assert (tmp_path / "demo_combined.png").stat().st_size > 0
