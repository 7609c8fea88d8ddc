"""TOML problem descriptions (gridlbc.config): every mistake names its key."""

import numpy as np
import pytest
from conftest import pointmass_description

import gridlbc
from gridlbc.config import load_config, number, problem_from_dict


@pytest.mark.parametrize(
    "change, fragment",
    [
        ({"horizon": None}, "missing key 'horizon'"),
        ({"horizn": 1.0}, "unknown key 'horizn'"),
        ({"grid": {"n": [21, 21, 21]}}, "grid.n must be one node count or 2"),
        ({"grid": {"n": 21, "axes": []}}, "exactly one of grid.n"),
        ({"grid": {"axes": [{"lo": -1, "hi": 1}]}}, "missing key 'grid.axes[0].n'"),
        (
            {"terminal_cost": {"center": [0, 0], "weight": [1, 1]}},
            "unknown key 'terminal_cost.weight'",
        ),
        ({"terminal_cost": {"center": [0, 0, 0], "weights": [1, 1, 1]}}, "3 coordinates"),
        ({"solver": {"method": "magic"}}, "unknown method 'magic'"),
        (
            {"system": {"name": "PointMass", "parameters": {"mass": -1}}},
            "system.parameters: mass must be a positive",
        ),
        ({"system": {"name": "PointMass", "parameters": {"length": 1}}}, "system.parameters"),
        ({"temperature": "hot"}, "temperature must be a number"),
        ({"horizon": -1.0}, "horizon must be positive"),
    ],
)
def test_description_errors_name_the_key(change, fragment):
    data = pointmass_description(0)
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
    np.testing.assert_allclose(
        p.state_cost(np.array([[np.pi / 2, 0], [0, 0]])), [0, (np.pi / 2) ** 2], rtol=1e-15, atol=0
    )
    assert config.settings.method == "splitting"


def test_load_config_reports_file_and_syntax(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("horizon = = 1\n")
    with pytest.raises(ValueError, match=r"bad.toml: invalid TOML"):
        load_config(path)
    with pytest.raises(FileNotFoundError):
        load_config(tmp_path / "none.toml")


@pytest.mark.parametrize(
    "text, expected",
    [
        ("pi", np.pi),
        ("-pi", -np.pi),
        ("pi/2", np.pi / 2),
        ("2*pi", 2 * np.pi),
        ("-0.5pi", -np.pi / 2),
        ("1e-3", 1e-3),
        (3, 3.0),
    ],
)
def test_number(text, expected):
    assert number(text, "k") == expected


@pytest.mark.parametrize("bad", ["pie", "inf", True, None])
def test_number_rejects(bad):
    with pytest.raises((ValueError, TypeError), match="k must be"):
        number(bad, "k")


def _first_exit(**changes):
    data = pointmass_description(0)
    del data["horizon"], data["terminal_cost"]
    data.pop("solver", None)  # the time march's settings do not apply
    data["state_cost"] = {"center": [0, 0], "weights": [0.0, 0.05]}
    data["exit"] = [
        {"ball": {"center": [-1.0, 0], "radius": [0.3, 0.5]}},
        {"box": {"lower": [1.5, "-inf"], "upper": ["inf", "inf"]}},
    ]
    data.update(changes)
    return data


def test_first_exit_description_builds_the_union_of_its_regions():
    config = problem_from_dict(_first_exit(exit_cost=0.5, solver={"rates": "upwind"}))
    problem = config.problem
    assert problem.horizon is None and problem.terminal_cost is None
    x = np.array([[-1.0, 0.2], [1.7, -3.0], [0.0, 0.0]])
    np.testing.assert_array_equal(problem.exit_mask(x), [True, True, False])
    np.testing.assert_array_equal(problem.exit_values(x), 0.5)
    assert config.settings.rates == "upwind"
    average = problem_from_dict(_first_exit(horizon="average", exit=None))
    assert average.problem.average_cost


@pytest.mark.parametrize(
    "change, fragment",
    [
        ({"exit": [{"disc": {}}]}, "unknown key 'exit[0].disc'"),
        ({"exit": [{"ball": {"center": [0, 0]}}]}, "missing key 'exit[0].ball.radius'"),
        ({"exit": {"ball": {}}}, "exit must be a list of regions"),
        ({"exit": [{"box": {"lower": [1, 0], "upper": [0, 1]}}]}, "must not exceed upper"),
        ({"exit": None}, "needs an exit set"),
        ({"solver": {"method": "splitting"}}, "unknown key 'solver.method'"),
    ],
)
def test_first_exit_description_errors_name_the_key(change, fragment):
    data = _first_exit()
    for key, value in change.items():
        if value is None:
            del data[key]
        else:
            data[key] = value
    with pytest.raises((ValueError, TypeError)) as info:
        problem_from_dict(data)
    assert fragment in str(info.value)
