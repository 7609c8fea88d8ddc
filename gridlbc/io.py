"""Saving and loading solutions: :func:`~gridlbc.save` and :func:`load` (exact round trip).

File format (``.npz``, a zip of ``.npy`` arrays, readable with plain numpy):

- ``times`` (S,), ``slices`` (S, N) float64 or float32, ``log_scales`` (S,): the solution, bit
  for bit;
- ``metadata``: a JSON document (a 0-d unicode array) with ``format`` (``"gridlbc-solution"``),
  ``format_version``, ``library_version``, the grid (axes), the system (import path and
  constructor parameters), horizon, temperature, control cost R, the terminal and state costs,
  the solver diagnostics, the solution's ``representation`` (its name: ``"linear"``,
  ``"relative"`` or ``"log"``, :mod:`gridlbc.representation`) and ``operator`` (its
  :class:`gridlbc.solution.OperatorSignature`), and ``sha256``: a digest of the three arrays,
  checked on load;
- ``terminal_nodes``, ``state_cost_nodes``: a cost that is not a :class:`gridlbc.Quadratic` (an
  arbitrary callable) is stored by its values at the nodes and comes back as a
  :class:`GridCost`, which interpolates them (exact at the nodes; the error estimate's terms that
  sample paths, γ and the certificates of :mod:`gridlbc.accuracy.bellman`, then read the
  interpolated costs, and an exit set as its nodes hold it);
- ``exit_mask`` (N,): a first-exit problem's exit set E at the nodes, with ``metadata["exit"]``
  its description; where E is made of the library's shapes (:class:`gridlbc.regions.Box`,
  :class:`gridlbc.regions.Ball`, their unions), ``metadata["exit_region"]`` holds them and
  :func:`load` rebuilds E exactly; any other E (a callable) comes back as its nodes hold it
  (:class:`gridlbc.regions.GridRegion`: a state is in it where the interpolated membership of
  the nodes is at least ½), and so do the values, rollouts and certificates read near its
  boundary;
- ``reference_log_slices`` (S, N), ``reference_log_scales`` (S,): for a solution fitted to a
  shared reference (:class:`gridlbc.representation.RelativeZ`), log φ at the stored times, which
  its evaluation needs, with its own digest ``reference_sha256`` in the metadata;
- ``embedded.*``: the solve on the embedded grid that the error estimate reads
  (:meth:`gridlbc.Solution.error_estimate`, :mod:`gridlbc.accuracy`), its arrays under this
  prefix and its metadata as ``metadata["embedded"]`` (with the estimate's
  ``observed_order``, ``order`` and ``floor``, :class:`gridlbc.accuracy.EmbeddedEstimate`); absent when
  the solution carries none;
- ``embedded_coarser.*``: the solve on the grid below the embedded one (4h), from which the
  estimate observes its order late in a task (:meth:`gridlbc.accuracy.EmbeddedEstimate.order_at`),
  its metadata as ``metadata["embedded"]["coarser"]``; absent where there was none, and in files
  written before it was kept (their estimate then uses the order observed at t = 0);
- ``embedded_pair0.*``, ``embedded_pair1.*``: the solves on the pair of grids of
  :func:`gridlbc.accuracy.phase_pair`, their metadata as ``metadata["embedded"]["pair"]`` (a
  list of two; ``"embedded"`` in place of the first where it is the embedded solve itself).
- ``embedded_excess.*``, ``embedded_excess_base.*``: the solves on the embedded grid with the
  costs raised by their sub-cell excess and without (:class:`gridlbc.accuracy.Response`), their
  metadata as ``metadata["embedded"]["excess"]`` (``"raised"``, ``"base"``) with the excess's
  ``bound`` (no arrays where they were not solved; a file without ``"base"`` was written when
  the embedded solve was the response's base, and loads so).

Version 1 files (before solutions knew their representation: it was
``diagnostics["interpolation"]``, ``"linear"``, ``"fitted"`` or ``"log"``, and the operator was
read from the diagnostics) are read too. Loading refuses other versions and a truncated or
corrupted file with a clear message.
"""

from __future__ import annotations

import hashlib
import importlib
import json
import zipfile
from dataclasses import asdict
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .accuracy import EmbeddedEstimate, Response
from .costs import Quadratic
from .errors import GridlbcWarning, warn_user
from .fingerprint import UnidentifiableError, digest, json_default, state_record
from .grid import Axis, Grid
from .interpolate import interpolate
from .problem import Problem
from .regions import Ball, Box, GridRegion, Union
from .representation import REPRESENTATIONS, LinearZ, LogZ, RelativeZ
from .solution import OperatorSignature, Solution, SolveDiagnostics, StationarySolution
from .systems import ControlAffineSystem
from .version import __version__

FORMAT = "gridlbc-solution"
FORMAT_VERSION = 2
"""The version :func:`~gridlbc.save` writes."""
EMBEDDED = "embedded."
"""The prefix of the embedded solve's arrays (the error estimate's, :mod:`gridlbc.accuracy`)."""
PAIR = ("embedded_pair0.", "embedded_pair1.")
"""The prefixes of the arrays of the solves on the pair of :func:`gridlbc.accuracy.phase_pair`."""
COARSER = "embedded_coarser."
"""The prefix of the arrays of the solve on the grid below the embedded one (4h)."""
EXCESS = ("embedded_excess.", "embedded_excess_base.")
"""The prefixes of the arrays of the solves on the embedded grid with the costs' excess between
the nodes and without (:class:`gridlbc.accuracy.Response`)."""
READABLE_VERSIONS = (1, 2)
"""The versions :func:`load` reads."""


class GridCost:
    """A cost known at the grid nodes, interpolated barycentrically elsewhere."""

    def __init__(self, grid: Grid, values):
        values = np.asarray(values, dtype=float)
        if values.shape != (grid.size,):
            raise ValueError(f"GridCost values must have shape ({grid.size},), got {values.shape}")
        self.grid, self.values = grid, values

    def __call__(self, x) -> np.ndarray:
        return interpolate(self.grid, self.values, x)


def _digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(str(a.dtype).encode())
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def quadratic_record(cost: Quadratic) -> dict:
    """A :class:`gridlbc.Quadratic` as JSON-ready data: ``kind`` (``"quadratic"``), ``center``,
    ``weights`` and ``periods`` (``None``, or one per coordinate, inf where not periodic).

    Parameters
    ----------
    cost : Quadratic
        The cost.
    """
    periods = None if cost.periods is None else [float(p) for p in cost.periods]
    return {
        "kind": "quadratic",
        "center": cost.center.tolist(),
        "weights": cost.weights.tolist(),
        "periods": periods,
    }


def cost_record(cost, name: str, problem: Problem, arrays: dict) -> dict | None:
    """A cost as JSON-ready data: a quadratic by its parameters (:func:`quadratic_record`), any
    other callable by its values at the grid's nodes, which go into ``arrays`` as
    ``{name}_nodes`` (:func:`load` gives them back as a :class:`GridCost`).

    Parameters
    ----------
    cost : callable or None
        The cost (``None``: no cost, recorded as ``None``).
    name : str
        Its name in ``arrays``.
    problem : Problem
        The problem whose grid samples a non-quadratic cost.
    arrays : dict
        Where the nodal values go.
    """
    if cost is None:
        return None
    if isinstance(cost, Quadratic):
        return quadratic_record(cost)
    nodes = problem.require_grid("recording a non-quadratic cost").nodes()
    arrays[f"{name}_nodes"] = np.asarray(cost(nodes), dtype=float)
    return {"kind": "nodes", "type": f"{type(cost).__module__}.{type(cost).__qualname__}"}


def _cost_from_record(record, name: str, grid: Grid, data):
    if record is None:
        return None
    if record["kind"] == "quadratic":
        periods = record["periods"]
        return Quadratic(
            record["center"],
            record["weights"],
            None if periods is None else np.array(periods, dtype=float),
        )
    return GridCost(grid, data[f"{name}_nodes"])


def problem_record(problem: Problem, arrays: dict) -> dict:
    """The problem as JSON-ready metadata; costs that are not quadratics go into ``arrays``.

    Two problems with equal records (and equal ``arrays``) describe the same PDE on the same
    grid: :func:`load` rebuilds the problem from them, :func:`gridlbc.sweep` hashes them.
    """
    system = problem.system
    return {
        "grid": [
            {"lo": a.lo, "hi": a.hi, "n": a.n, "periodic": a.periodic, "name": a.name}
            for a in problem.require_grid("problem_record()").axes
        ],
        "system": {
            "class": f"{type(system).__module__}.{type(system).__qualname__}",
            "parameters": recorded_parameters(system),
        },
        "horizon": problem.horizon,
        "temperature": problem.temperature,
        "control_cost": problem.R.tolist(),
        "terminal_cost": cost_record(problem.terminal_cost, "terminal", problem, arrays),
        "state_cost": cost_record(problem.state_cost, "state_cost", problem, arrays),
        **_exit_record(problem, arrays),
    }


def region_record(region) -> dict | None:
    """An exit set made of the library's shapes (:class:`~gridlbc.regions.Box`,
    :class:`~gridlbc.regions.Ball`, their unions) as JSON data that :func:`region_from_record`
    rebuilds exactly; None for anything else (a callable, known to a file by its nodes only:
    :class:`~gridlbc.regions.GridRegion`). A shape's periods are the problem's, bound again when
    the loaded problem is made."""
    if isinstance(region, Box):
        return {"box": {"lower": region.lower.tolist(), "upper": region.upper.tolist()}}
    if isinstance(region, Ball):
        return {"ball": {"center": region.center.tolist(), "radius": region.radius.tolist()}}
    if isinstance(region, Union):
        parts = [region_record(part) for part in region.parts]
        return None if any(part is None for part in parts) else {"union": parts}
    return None


def region_from_record(record: dict):
    """The region of :func:`region_record`."""
    if "box" in record:
        return Box(record["box"]["lower"], record["box"]["upper"])
    if "ball" in record:
        return Ball(record["ball"]["center"], record["ball"]["radius"])
    return Union(tuple(region_from_record(part) for part in record["union"]))


def recorded_parameters(system) -> dict:
    """``system.parameters()`` as a file records it and :func:`load` passes it back to the
    system's class: JSON data, numpy arrays and numbers as lists and Python numbers (a user's
    ``parameters()`` may return arrays); a clear error for what JSON cannot hold."""
    parameters = system.parameters()
    try:
        return json.loads(json.dumps(parameters, default=json_default))
    except (TypeError, ValueError) as exc:
        raise TypeError(
            f"{type(system).__qualname__}.parameters() must return data that a file can hold "
            f"(numbers, strings, lists, dicts, numpy arrays), got {parameters!r} ({exc}): give "
            "the constructor's arguments as such data"
        ) from None


def _exit_record(problem: Problem, arrays: dict) -> dict:
    """A first-exit problem's exit set (its nodes, into ``arrays``) and exit cost; nothing for a
    problem without one (so the records of other problems are unchanged)."""
    if problem.exit is None:
        return {}
    arrays["exit_mask"] = problem.exit_mask()
    return {
        "exit": repr(problem.exit),
        "exit_cost": cost_record(problem.exit_cost, "exit_cost", problem, arrays),
    }


def save(solution: Solution, path, annotations: dict | None = None) -> Path:
    """Write ``solution`` to ``path`` (``.npz`` appended if missing).

    Parameters
    ----------
    solution : Solution
        What :func:`gridlbc.solve` returned.
    path : str or Path
        The file to write; ``.npz`` is appended if missing.
    annotations : dict, optional
        JSON-serialisable data kept with the file (:func:`~gridlbc.io.read_metadata` returns it
        under ``"annotations"``; :func:`load` ignores it).

    Returns
    -------
    Path
        The path written.

    The system is recorded by its class's import path and its ``parameters()``; where those
    cannot rebuild it (a user's class whose constructor takes arguments and that has no
    ``parameters()`` returning them) the file is written and a :class:`gridlbc.GridlbcWarning`
    says that :func:`load` will need the system passed to it.
    """
    if not isinstance(solution, Solution):
        raise TypeError(f"save expects a gridlbc.Solution, got {type(solution).__name__}")
    problem = solution.problem
    rebuilt = rebuild(problem.system, problem.require_grid("save"))
    if rebuilt.failure is not None:
        call, reason = rebuilt.failure
        name = type(problem.system).__qualname__
        fix = (
            f"make {name}.parameters() return every constructor argument, as data its "
            "constructor takes back (numbers, strings, lists, dicts)"
            if type(problem.system).parameters is not ControlAffineSystem.parameters
            else f"give {name} a parameters() method that returns its constructor arguments"
        )
        warn_user(
            f"the saved file records the system as {call}, which cannot rebuild it ({reason}): "
            f"load it with gridlbc.load(path, system=...) giving the system, or {fix} (docs "
            "page 'tutorial')",
            GridlbcWarning,
        )
    return write(solution, path, annotations, rebuilt=rebuilt)


def write(
    solution: Solution, path, annotations: dict | None = None, rebuilt: Rebuild | None = None
) -> Path:
    """:func:`~gridlbc.save` without its warning where :func:`load` cannot rebuild the system
    alone (for a caller that loads with ``system=``, as :func:`gridlbc.sweep` does). ``rebuilt``:
    what the record rebuilds (:func:`rebuild`), where the caller has it. Where it rebuilds the
    system, the file records the digest of the system it rebuilds, which :func:`load` compares
    with the system it rebuilds (their attributes may differ in type from the solved system's: a
    numpy number comes back as a float)."""
    if rebuilt is None:
        rebuilt = rebuild(solution.problem.system, solution.problem.require_grid("write"))
    path = Path(path)
    if path.suffix != ".npz":
        path = path.with_name(path.name + ".npz")
    arrays: dict = {}
    meta = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "library_version": __version__,
        **_record(solution, arrays),
        "system_rebuilt_sha256": rebuilt.digest,
    }
    estimate = solution.embedded
    if isinstance(estimate, EmbeddedEstimate):  # the estimate's coarse solve, under its own prefix
        meta["embedded"] = {
            **_record_under(estimate.solution, EMBEDDED, arrays),
            "observed_order": None
            if np.isnan(estimate.observed_order)
            else estimate.observed_order,
            "order": estimate.order,
            "floor": estimate.floor,
        }
        if estimate.coarser is not None:
            meta["embedded"]["coarser"] = _record_under(estimate.coarser, COARSER, arrays)
        if estimate.pair is not None:
            meta["embedded"]["pair"] = [
                "embedded" if side is estimate.solution else _record_under(side, prefix, arrays)
                for prefix, side in zip(PAIR, estimate.pair, strict=True)
            ]
        response = estimate.excess
        if response is not None:
            meta["embedded"]["excess"] = {"bound": response.bound}
            for prefix, key in zip(EXCESS, ("raised", "base"), strict=True):
                side = getattr(response, key)
                meta["embedded"]["excess"][key] = (
                    None if side is None else _record_under(side, prefix, arrays)
                )
    if annotations is not None:
        meta["annotations"] = annotations
    arrays["metadata"] = np.array(json.dumps(meta, default=json_default))
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    return path


def _record_under(solution: Solution, prefix: str, arrays: dict) -> dict:
    """:func:`_record` of a solution the saved one carries, its arrays put into ``arrays`` under
    ``prefix``."""
    held: dict = {}
    record = _record(solution, held)
    arrays.update({prefix + k: v for k, v in held.items()})
    return record


def _record(solution: Solution, arrays: dict) -> dict:
    """The metadata of one solution (problem, diagnostics, representation, operator, digests);
    its arrays go into ``arrays``."""
    arrays.update(times=solution.times, slices=solution.slices, log_scales=solution.log_scales)
    reference = solution.reference
    if reference is not None:  # log φ of a fitted operator: the solution's evaluation needs it
        arrays["reference_log_slices"] = reference.log_slices
        arrays["reference_log_scales"] = reference.log_scales
    shape = region_record(solution.problem.exit)
    meta = {
        **problem_record(solution.problem, arrays),
        **({} if shape is None else {"exit_region": shape}),
        "diagnostics": asdict(solution.diagnostics),
        "representation": solution.representation.name,
        "operator": asdict(solution.operator),
        "sha256": _digest(solution.times, solution.slices, solution.log_scales),
        "system_state_sha256": state_digest(solution.problem.system),
    }
    if isinstance(solution, StationarySolution) and solution.average_cost is not None:
        meta["average_cost"] = solution.average_cost
        meta["average_cost_error"] = solution.average_cost_error
        if solution.stationary_distribution is not None:
            arrays["stationary_distribution"] = solution.stationary_distribution
    if reference is not None:
        meta["reference_sha256"] = _digest(reference.log_slices, reference.log_scales)
    return meta


REBUILD_STATES = 4096
"""At most this many grid nodes (evenly spread) at which :func:`rebuild` compares the drift and
input matrix of a rebuilt system with the original's."""


class Rebuild(NamedTuple):
    """What the record of a system rebuilds (:func:`rebuild`)."""

    digest: str | None
    """The :func:`state_digest` of the system rebuilt, where it computes what the system does."""
    failure: tuple[str, str] | None
    """Where it does not: the call :func:`load` makes and why it fails."""


def rebuild(system, grid: Grid) -> Rebuild:
    """``type(system)(**parameters)``, what :func:`load` calls with the parameters as the file
    records them (:func:`recorded_parameters`), judged: it rebuilds this system where its state is
    the same (:func:`state_digest`) or it computes the same drift and input matrix, bit for bit,
    at :data:`REBUILD_STATES` of the grid's nodes (a parameter given as a numpy number or a tuple
    comes back as a float or a list)."""
    cls, parameters = type(system), recorded_parameters(system)
    call = f"{cls.__qualname__}(**{parameters!r})"
    try:
        rebuilt = cls(**parameters)
    except Exception as exc:  # the user's constructor refuses the record: say so, not raise
        return Rebuild(None, (call, f"{call} raises {type(exc).__name__}: {exc}"))
    digest = state_digest(rebuilt)
    if digest == state_digest(system):
        return Rebuild(digest, None)
    x = grid.node_coordinates(
        np.linspace(0, grid.size - 1, min(grid.size, REBUILD_STATES), dtype=int)
    )
    try:
        same = all(
            np.array_equal(getattr(rebuilt, name)(x), getattr(system, name)(x))
            for name in ("drift", "input_matrix")
        )
    except Exception:  # the rebuilt system cannot even evaluate there: not the same
        same = False
    if same:
        return Rebuild(digest, None)
    reason = f"{call} builds a system whose attributes and dynamics differ from this one's"
    return Rebuild(None, (call, reason))


def state_digest(system) -> str | None:
    """The SHA-256 of a system's full state (:func:`gridlbc.fingerprint.state_record`, arrays by
    their bytes), which :func:`~gridlbc.save` records and :func:`load` compares with the system it
    rebuilds; None where the state cannot be read."""
    arrays: dict = {}
    try:
        return digest(state_record(system, arrays, "system"), arrays)
    except UnidentifiableError:
        return None


def _check_system(meta: dict, system, given: bool) -> None:
    """Warn where the loaded solution's system is not in the state it was saved in (its digest,
    when the file has one: files from before it have none); a system rebuilt from the record
    (not ``given``) is compared with the one the record rebuilt at save, where it rebuilt one
    that computes what the solved system did (:func:`rebuild`)."""
    saved = meta.get("system_state_sha256")
    rebuilt = None if given else meta.get("system_rebuilt_sha256")
    if saved is None or state_digest(system) in (None, saved, rebuilt):
        return
    warn_user(
        f"the system of this file, as loaded ({system!r}), differs from the one the solution was "
        "solved with (the digest of its attributes): the values are the file's, but its policy "
        "paths, certificates and error estimate read the system. Pass the system it was solved "
        "with, gridlbc.load(path, system=...), or give its class a parameters() method that "
        "returns its constructor arguments",
        GridlbcWarning,
    )


def _system_from_record(record, system=None):
    """The system of a saved solution: rebuilt from its class and ``parameters()``, or ``system``
    where the caller gives it (its class must be the recorded one)."""
    module_name, _, qualname = record["class"].rpartition(".")
    if isinstance(system, type):
        raise TypeError(
            f"load(system=...) takes the system itself, an instance such as {system.__name__}(...)"
            f", not its class {system.__name__}"
        )
    if system is not None:
        given = f"{type(system).__module__}.{type(system).__qualname__}"
        if given != record["class"]:
            raise ValueError(
                f"load(system=...) got a {given}, but the file was saved with a "
                f"{record['class']}: give a system of the class it was solved with"
            )
        return system
    try:
        cls = getattr(importlib.import_module(module_name), qualname)
    except (ImportError, AttributeError):
        raise ValueError(
            f"the saved solution's system {record['class']} cannot be imported: import the module "
            "that defines it (it must be importable by that name) before loading, or pass it: "
            "gridlbc.load(path, system=...)"
        ) from None
    try:
        return cls(**record["parameters"])
    except TypeError as exc:
        raise ValueError(
            f"the saved solution's system {qualname}(**{record['parameters']!r}) cannot be "
            f"rebuilt ({exc}): pass it, gridlbc.load(path, system=...), or give {qualname} a "
            "parameters() method that returns its constructor arguments (docs page 'tutorial')"
        ) from None


def _read(path, arrays: bool) -> tuple[dict, dict]:
    """The metadata of a saved solution and, if ``arrays``, its arrays (checked readable)."""
    path = Path(path)
    if not path.exists() and path.suffix != ".npz" and path.with_name(path.name + ".npz").exists():
        path = path.with_name(path.name + ".npz")  # as save names it
    if not path.exists():
        raise FileNotFoundError(f"no saved solution at {str(path)!r}")
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["metadata"]))
            contents = {k: data[k] for k in data.files if k != "metadata"} if arrays else {}
    except (zipfile.BadZipFile, OSError, ValueError, KeyError, EOFError) as exc:
        # numpy's advice to load with allow_pickle=True does not apply: no solution holds objects
        reason = str(exc).split(" If you trust the file")[0]
        raise ValueError(
            f"{str(path)!r} is not a readable gridlbc solution (truncated or corrupted?): {reason}"
        ) from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ValueError(f"{str(path)!r} is not a gridlbc solution file")
    return meta, contents


def read_metadata(path) -> dict:
    """The metadata of a file written by :func:`~gridlbc.save`, without reading its arrays."""
    return _read(path, arrays=False)[0]


def load(path, system=None) -> Solution:
    """Read a Solution written by :func:`~gridlbc.save`; the arrays come back bit for bit.

    Parameters
    ----------
    path : str or Path
        A file written by :func:`~gridlbc.save` (``.npz`` may be left out, as ``save`` appends
        it).
    system : ControlAffineSystem, optional
        The solution's system, where the file's record (its class and ``parameters()``) cannot
        rebuild it (a user's class without ``parameters()``, or one not importable here); it
        must be of the recorded class, and is taken as the one the solution was solved with.

    Where the system rebuilt (or given) is not in the state the solution was solved with (the
    digest of its attributes that :func:`~gridlbc.save` records), a :class:`gridlbc.GridlbcWarning`
    says so: the values are the file's, but the policy's paths, certificates and the error estimate
    read the system.

    Returns
    -------
    Solution
    """
    meta, contents = _read(path, arrays=True)
    version = meta.get("format_version")
    if version not in READABLE_VERSIONS:
        raise ValueError(
            f"{str(path)!r} has format version {version}, this gridlbc reads versions "
            f"{', '.join(map(str, READABLE_VERSIONS))}: load it with gridlbc "
            f"{meta.get('library_version')}"
        )
    solution = _solution(meta, contents, version, path, system)
    _check_system(meta, solution.problem.system, given=system is not None)
    if "embedded" in meta:
        record = meta["embedded"]
        observed = record["observed_order"]
        embedded = _solution(record, _prefixed(contents, EMBEDDED), version, path, system)
        pair = None
        if "pair" in record:
            first, second = (
                embedded
                if side == "embedded"
                else _solution(side, _prefixed(contents, prefix), version, path, system)
                for prefix, side in zip(PAIR, record["pair"], strict=True)
            )
            pair = (first, second)
        response = None
        if "excess" in record:
            excess = record["excess"]
            raised, base = (
                None
                if excess.get(key) is None
                else _solution(excess[key], _prefixed(contents, prefix), version, path, system)
                for prefix, key in zip(EXCESS, ("raised", "base"), strict=True)
            )
            if "base" not in excess:  # written when the embedded solve was the base
                base = embedded
            response = Response(base, raised, float(excess["bound"]))
        coarser = None
        if "coarser" in record:  # absent from files written before it was kept
            held = _prefixed(contents, COARSER)
            coarser = _solution(record["coarser"], held, version, path, system)
        estimate = EmbeddedEstimate(
            embedded,
            np.nan if observed is None else float(observed),
            float(record["order"]),
            float(record["floor"]),
            pair,
            response,
            coarser,
        )
        object.__setattr__(solution, "embedded", estimate)
    return solution


def _solution(meta: dict, contents: dict, version: int, path, system=None) -> Solution:
    """One solution from its metadata and arrays (:func:`_record`), checked against its digests."""
    times, slices, scales = contents["times"], contents["slices"], contents["log_scales"]
    if _digest(times, slices, scales) != meta["sha256"]:
        raise ValueError(f"{str(path)!r} is corrupted: its arrays do not match their checksum")
    reference = None
    if "reference_sha256" in meta:
        try:
            reference = RelativeZ(
                contents["reference_log_slices"], contents["reference_log_scales"]
            )
        except KeyError:
            raise ValueError(
                f"{str(path)!r} is corrupted: its fitting reference is missing"
            ) from None
        if _digest(reference.log_slices, reference.log_scales) != meta["reference_sha256"]:
            raise ValueError(
                f"{str(path)!r} is corrupted: its fitting reference does not match its checksum"
            )
    grid = Grid([Axis(**a) for a in meta["grid"]])
    exit_set = None
    if "exit_region" in meta:
        exit_set = region_from_record(meta["exit_region"])
    elif "exit" in meta:
        exit_set = GridRegion(grid, contents["exit_mask"], meta["exit"])
    problem = Problem(
        _system_from_record(meta["system"], system),
        grid,
        meta["horizon"],
        _cost_from_record(meta["terminal_cost"], "terminal", grid, contents),
        state_cost=_cost_from_record(meta["state_cost"], "state_cost", grid, contents),
        control_cost=np.array(meta["control_cost"]),
        temperature=meta["temperature"],
        exit=exit_set,
        exit_cost=_cost_from_record(meta.get("exit_cost"), "exit_cost", grid, contents),
    )
    diag = dict(meta["diagnostics"])
    diag["iterations"] = tuple(diag.get("iterations", ()))
    known = SolveDiagnostics.__dataclass_fields__
    diagnostics = SolveDiagnostics(**{k: v for k, v in diag.items() if k in known})
    if version == 1:  # the representation and the operator were strings in the diagnostics
        legacy = diag.get("interpolation", "linear")  # "linear", "fitted" or "log"
        name = RelativeZ.name if legacy == "fitted" else legacy
        operator = OperatorSignature(
            diagnostics.method, diagnostics.dt, diagnostics.fitting, name == "log"
        )
    else:
        name, operator = meta["representation"], OperatorSignature(**meta["operator"])
    representation = _representation(str(name), reference, path)
    fields = (problem, times, slices, scales, diagnostics, operator, representation)
    if problem.stationary:
        return StationarySolution(
            *fields,
            average_cost=meta.get("average_cost"),
            average_cost_error=meta.get("average_cost_error"),
            stationary_distribution=contents.get("stationary_distribution"),
        )
    return Solution(*fields)


def _representation(name: str, reference: RelativeZ | None, path) -> LinearZ | RelativeZ | LogZ:
    """The representation recorded as ``name`` (its log φ ``reference`` for a relative one)."""
    if name not in REPRESENTATIONS:
        raise ValueError(f"{str(path)!r} records an unknown representation {name!r}")
    if name == RelativeZ.name:
        if reference is None:
            raise ValueError(f"{str(path)!r} is corrupted: its fitting reference is missing")
        return reference
    return LogZ() if name == LogZ.name else LinearZ()


def _prefixed(contents, prefix: str) -> dict:
    """The arrays of ``contents`` whose names start with ``prefix``, without it."""
    return {k[len(prefix) :]: v for k, v in contents.items() if k.startswith(prefix)}
