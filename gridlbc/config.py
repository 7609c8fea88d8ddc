"""Problem descriptions in TOML: what ``gridlbc solve --config FILE`` reads.

A file names a system, a grid, the horizon T, the temperature λ, the control cost R and
quadratic costs g(x) = (x − c)ᵀW(x − c) (terminal) and q(x) = (x − c)ᵀW(x − c) (state), and
optionally solver settings. Angles are in radians from the upright; a number may be written as a
multiple of π in a string (``"pi"``, ``"-pi"``, ``"pi/2"``, ``"2*pi"``)::

    horizon = 3.0            # T
    temperature = 1.0        # λ
    control_cost = 1.0       # R: a number, one per control, or a matrix

    [system]
    name = "Pendulum"        # a class of gridlbc.systems, or "package.module.Class"
    parameters = { damping = 0.1 }

    [grid]                   # either node counts with the system's default box ...
    n = [101, 101]
    # ... or explicit axes, one table per state coordinate:
    # [[grid.axes]]
    # lo = "-pi"
    # hi = "pi"
    # n = 101
    # periodic = true

    [terminal_cost]
    center = [0, 0]
    weights = [10, 0.5]      # the diagonal of W, or the full matrix

    [state_cost]             # optional
    center = [0, 0]
    weights = [0.1, 0.0]

    [solver]                 # optional: any gridlbc.SolverSettings field
    method = "splitting"
    dt = 0.02
    fitting = "none"         # the plain operator ("auto", the default: fitted to g)

A task that ends when the state enters an exit set (SPEC §9) leaves out ``horizon`` and
``terminal_cost`` and gives the set as one or more regions (their union) and, optionally, the
exit cost (a number or a quadratic table; default 0); its ``[solver]`` table takes the fields of
:class:`gridlbc.stationary.StationarySettings` (``rates``, ``linear_solver``, ...). In TOML a
key belongs to the last table above it, so ``exit_cost`` goes with the other top-level keys,
before the first table::

    exit_cost = 0.0          # with temperature, control_cost, ...

    [[exit]]
    box = { lower = [0.45, "-inf"], upper = ["inf", "inf"] }   # the half-plane x₀ ≥ 0.45
    [[exit]]
    ball = { center = [-1.3, 0], radius = [0.2, 0.4] }

``horizon = "average"`` poses the average-cost problem (no exit, no terminal cost).

Every key is checked: an unknown or missing key or a bad value raises ``ValueError``, a value of
the wrong type ``TypeError``, each naming the key.
"""

from __future__ import annotations

import importlib
import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

from . import systems
from .costs import Quadratic
from .grid import Axis, Grid
from .problem import AVERAGE, Problem
from .regions import Ball, Box, Union
from .settings import SolverSettings
from .stationary import StationarySettings

TOP_KEYS = (
    "system",
    "grid",
    "horizon",
    "temperature",
    "control_cost",
    "terminal_cost",
    "state_cost",
    "solver",
    "exit",
    "exit_cost",
)
REQUIRED_KEYS = ("system", "grid")

_PI = re.compile(r"^\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)?)\s*\*?\s*pi\s*(?:/\s*(\d+(?:\.\d*)?))?\s*$")


@dataclass(frozen=True)
class ProblemConfig:
    """A problem read from a description, and how to solve it."""

    problem: Problem
    settings: SolverSettings | StationarySettings


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def number(value, key: str, allow_infinite: bool = False) -> float:
    """A finite float from a TOML number or a multiple of π written as a string (``"inf"`` and
    ``"-inf"`` too with ``allow_infinite``)."""
    if isinstance(value, bool):
        raise TypeError(f"{key} must be a number, got {value!r}")
    if isinstance(value, (int, float)) or (isinstance(value, str) and _is_float(value)):
        result = float(value)
        if allow_infinite and math.isinf(result):
            return result
    elif isinstance(value, str) and (match := _PI.match(value.lower())):
        coefficient = {"": 1.0, "+": 1.0, "-": -1.0}.get(match[1])
        coefficient = float(match[1]) if coefficient is None else coefficient
        result = coefficient * math.pi / (float(match[2]) if match[2] else 1.0)
    else:
        raise ValueError(
            f'{key} must be a number (or a multiple of pi such as "-pi", "pi/2"), got {value!r}'
        )
    if not math.isfinite(result):
        raise ValueError(f"{key} must be finite, got {value!r}")
    return result


def numbers(value, key: str, allow_infinite: bool = False) -> list | float:
    """A number or a (nested) list of numbers, each as :func:`number`."""
    if isinstance(value, list):
        return [numbers(v, f"{key}[{i}]", allow_infinite) for i, v in enumerate(value)]
    return number(value, key, allow_infinite)


def _table(data, key: str, allowed, required=()) -> dict:
    if not isinstance(data, dict):
        raise TypeError(f"{key} must be a table (section), got {type(data).__name__}")
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        raise ValueError(
            f"unknown key {'.'.join(filter(None, (key, unknown[0])))!r}: valid keys "
            f"{'in ' + key + ' ' if key else ''}are {', '.join(allowed)}"
        )
    missing = [k for k in required if k not in data]
    if missing:
        raise ValueError(f"missing key {'.'.join(filter(None, (key, missing[0])))!r}")
    return data


def system_from_name(name, parameters=None):
    """A system by class name in :mod:`gridlbc.systems` (case-insensitive) or by import path."""
    if not isinstance(name, str) or not name:
        raise ValueError(f'system.name must be a class name such as "Pendulum", got {name!r}')
    parameters = {} if parameters is None else dict(parameters)
    builtin = {
        n.lower(): getattr(systems, n)
        for n in systems.__all__
        if n not in ("ControlAffineSystem", "LinearSystem")
    }
    if "." in name:
        module_name, _, qualname = name.rpartition(".")
        try:
            cls = getattr(importlib.import_module(module_name), qualname)
        except (ImportError, AttributeError):
            raise ValueError(
                f"system.name {name!r} cannot be imported: give a class of "
                'gridlbc.systems or an importable "package.module.Class"'
            ) from None
    elif name.lower() in builtin:
        cls = builtin[name.lower()]
    else:
        raise ValueError(
            f"unknown system.name {name!r}: choose one of "
            f"{', '.join(cls.__name__ for cls in builtin.values())} or give "
            '"package.module.Class"'
        )
    try:
        return cls(**parameters)
    except TypeError as exc:
        raise ValueError(f"system.parameters do not fit {cls.__name__}: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"system.parameters: {exc}") from None


def _count(value, key: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{key} must be an integer number of nodes, got {value!r}")
    return value


def _grid(data, system) -> Grid:
    data = _table(data, "grid", ("n", "axes"))
    if ("n" in data) == ("axes" in data):
        raise ValueError(
            "grid needs exactly one of grid.n (node counts with the system's default "
            "box) or grid.axes (a table per coordinate with lo, hi, n, periodic)"
        )
    if "n" in data:
        counts = data["n"] if isinstance(data["n"], list) else [data["n"]]
        if not system.default_box:
            raise ValueError(
                f"{type(system).__name__} has no default box: give grid.axes (lo, "
                "hi, n per coordinate)"
            )
        try:
            return system.default_grid([_count(n, f"grid.n[{i}]") for i, n in enumerate(counts)])
        except ValueError as exc:
            raise ValueError(f"grid.{exc}") from None
    if not isinstance(data["axes"], list) or not data["axes"]:
        raise ValueError("grid.axes must be a list of tables ([[grid.axes]] in TOML)")
    axes = []
    for i, axis in enumerate(data["axes"]):
        key = f"grid.axes[{i}]"
        axis = _table(axis, key, ("lo", "hi", "n", "periodic", "name"), ("lo", "hi", "n"))
        periodic = axis.get("periodic", False)
        if not isinstance(periodic, bool):
            raise TypeError(f"{key}.periodic must be true or false, got {periodic!r}")
        try:
            axes.append(
                Axis(
                    number(axis["lo"], f"{key}.lo"),
                    number(axis["hi"], f"{key}.hi"),
                    _count(axis["n"], f"{key}.n"),
                    periodic,
                    axis.get("name"),
                )
            )
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{key}: {exc}") from None
    return Grid(axes)


def _quadratic(data, key: str):
    if data is None:
        return None
    data = _table(data, key, ("center", "weights"), ("center", "weights"))
    try:
        return Quadratic(
            numbers(data["center"], f"{key}.center"), numbers(data["weights"], f"{key}.weights")
        )
    except ValueError as exc:
        raise ValueError(f"{key}: {exc}") from None


def _region(data, key: str):
    """One region of an ``[[exit]]`` list: ``box = {lower, upper}`` or ``ball = {center,
    radius}``."""
    data = _table(data, key, ("box", "ball"))
    if len(data) != 1:
        raise ValueError(f"{key} must give exactly one of box or ball, got {sorted(data)}")
    kind, shape = next(iter(data.items()))
    fields = ("lower", "upper") if kind == "box" else ("center", "radius")
    shape = _table(shape, f"{key}.{kind}", fields, fields)
    values = [numbers(shape[f], f"{key}.{kind}.{f}", allow_infinite=True) for f in fields]
    try:
        return Box(*values) if kind == "box" else Ball(*values)
    except ValueError as exc:
        raise ValueError(f"{key}.{kind}: {exc}") from None


def _exit(data):
    """The exit set: the union of the ``[[exit]]`` regions (None without)."""
    if data is None:
        return None
    if not isinstance(data, list) or not data:
        raise TypeError("exit must be a list of regions: [[exit]] tables with box or ball")
    regions = [_region(r, f"exit[{i}]") for i, r in enumerate(data)]
    return regions[0] if len(regions) == 1 else Union(tuple(regions))


def _exit_cost(data):
    if data is None or isinstance(data, dict):
        return _quadratic(data, "exit_cost")
    return number(data, "exit_cost")


def _horizon(data) -> float | str | None:
    if "horizon" not in data:
        if "exit" not in data:
            raise ValueError(
                "missing key 'horizon' (a task without one needs an exit set: [[exit]] regions, "
                'or horizon = "average")'
            )
        return None
    value = data["horizon"]
    return AVERAGE if value == AVERAGE else number(value, "horizon")


def _solver_settings(data, stationary: bool = False) -> SolverSettings | StationarySettings:
    if stationary:
        data = _table(data or {}, "solver", tuple(StationarySettings.__dataclass_fields__))
        try:
            return StationarySettings(**data)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"solver: {exc}") from None
    fields = tuple(SolverSettings.__dataclass_fields__)
    data = _table(data or {}, "solver", fields)
    if data.get("fitting") == "none":  # TOML has no null: "none" is the plain operator
        data["fitting"] = None
    try:
        return SolverSettings(**data)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"solver: {exc}") from None


def problem_from_dict(data: dict) -> ProblemConfig:
    """Build the problem and solver settings from a parsed description (see the module doc)."""
    data = _table(data, "", TOP_KEYS, REQUIRED_KEYS)
    system_data = _table(data["system"], "system", ("name", "parameters"), ("name",))
    parameters = system_data.get("parameters", {})
    if not isinstance(parameters, dict):
        raise TypeError("system.parameters must be a table of constructor arguments")
    system = system_from_name(system_data["name"], parameters)
    grid = _grid(data["grid"], system)
    control_cost = numbers(data.get("control_cost", 1.0), "control_cost")
    horizon = _horizon(data)
    if isinstance(horizon, float) and "terminal_cost" not in data:
        raise ValueError("missing key 'terminal_cost'")
    try:
        problem = Problem(
            system,
            grid,
            horizon,
            _quadratic(data.get("terminal_cost"), "terminal_cost"),
            state_cost=_quadratic(data.get("state_cost"), "state_cost"),
            control_cost=control_cost,
            temperature=number(data.get("temperature", 1.0), "temperature"),
            exit=_exit(data.get("exit")),
            exit_cost=_exit_cost(data.get("exit_cost")),
        )
    except TypeError as exc:
        raise ValueError(str(exc)) from None
    return ProblemConfig(problem, _solver_settings(data.get("solver"), problem.stationary))


def read_description(path) -> dict:
    """The parsed TOML of ``path``; a syntax error becomes a ``ValueError`` with the line."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no problem description at {str(path)!r}")
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: invalid TOML: {exc}") from None


def load_config(path) -> ProblemConfig:
    """Read a TOML problem description (see the module doc); errors name the file and the key."""
    try:
        return problem_from_dict(read_description(path))
    except (TypeError, ValueError) as exc:
        message = str(exc)
        raise type(exc)(
            message if message.startswith(str(path)) else f"{path}: {message}"
        ) from None
