"""Many independent solves in parallel on Dask distributed: :func:`sweep`.

A sweep solves a list of problems (a grid of temperatures, horizons, dynamics parameters or
goals), each with :func:`gridlbc.solve`, on the workers of a Dask cluster. Each worker writes its
member's :class:`gridlbc.Solution` with :func:`gridlbc.save` and sends back only a summary: the
value v(x, 0) = −λ log z(x, 0) at the requested states, the solve's diagnostics, or the error
that stopped it.

A member is identified by a content hash (SHA-256) of its problem as :func:`gridlbc.save` records
it (grid, system and its parameters, horizon, temperature, R, the costs: quadratics by centre and
weights, other callables by their values at the nodes), of the full state of its system and costs
(attributes, arrays by their bytes, a function's code and closure: :mod:`gridlbc.fingerprint`), of
the solver settings that change the result, and of the library and file-format versions. A system
whose state cannot be read and that has no ``parameters()`` of its own is refused with an error
that says what to add, rather than risk two members sharing one file. The hash names the member's file and is
stored in it, so a rerun of the same sweep reuses every finished member (after checking the
stored hash and the arrays' checksum) and solves only what is missing or failed.

Problems that differ only in their terminal cost share one operator: :func:`gridlbc.solve_many`
solves them together, and exactly (one step operator, many right-hand sides), which beats a sweep
whenever they fit in memory at once.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import os
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import warn_user
from .fingerprint import UnidentifiableError, digest, state_record
from .io import FORMAT_VERSION, cost_record, load, problem_record, read_metadata, write
from .problem import Problem
from .progress import ProgressBar
from .settings import SolverSettings, resolve_settings
from .solution import SolveDiagnostics
from .solver import solve
from .systems.base import ControlAffineSystem
from .version import __version__

_NOT_HASHED = ("progress", "mmap_dir")
"""Settings that change how a solve runs but not its result."""


@dataclass(frozen=True)
class SweepMember:
    """The outcome of one problem of a :func:`sweep`.

    Attributes
    ----------
    index : int
        Position of the problem in the list given to :func:`sweep`.
    key : str
        SHA-256 of the problem and the solver settings (hex): the member's identity.
    path : Path or None
        The saved Solution (:func:`gridlbc.load` reads it); ``None`` if the member failed.
    values : ndarray (n,) or None
        v(x, 0) at the sweep's ``states`` (``None`` without states or when failed); +inf where
        z underflowed.
    diagnostics : SolveDiagnostics or None
        Of the solve that wrote the file (also when the file was reused).
    error : str or None
        ``None``, or why the member failed (exception type and message).
    reused : bool
        The file was already complete from an earlier run and was not solved again.
    warnings : tuple of str
        Warnings raised while solving or evaluating this member (also re-issued by
        :func:`sweep`).
    """

    index: int
    key: str
    path: Path | None
    values: np.ndarray | None
    diagnostics: SolveDiagnostics | None
    error: str | None = None
    reused: bool = False
    warnings: tuple[str, ...] = ()


@dataclass(frozen=True)
class _Outcome:
    """What a worker sends back: small, whatever the grid size."""

    values: np.ndarray | None
    diagnostics: SolveDiagnostics | None
    error: str | None
    reused: bool
    warnings: tuple[tuple[type, str], ...]


def settings_record(problem: Problem, settings: SolverSettings, arrays: dict) -> dict:
    """The solver settings that change a solve's result, as JSON-ready data.

    A fitting cost that is not a quadratic goes into ``arrays`` by its values at the nodes.
    """
    record = {
        k: v
        for k, v in dataclasses.asdict(settings).items()
        if k not in _NOT_HASHED and k != "fitting"
    }
    fitting = settings.reference
    record["fitting"] = (
        fitting
        if fitting is None or isinstance(fitting, str)
        else cost_record(fitting, "fitting", problem, arrays)
    )
    return record


def _own_parameters(system) -> bool:
    """Whether the system's class (or a base other than the library's) defines parameters()."""
    return type(system).parameters is not ControlAffineSystem.parameters


def identity_record(problem: Problem, arrays: dict) -> dict:
    """The full state of the problem's system and costs (:func:`gridlbc.fingerprint.state_record`).

    :func:`gridlbc.io.problem_record` describes a system by its ``parameters()``, which a user's
    system need not define, and a cost that is not a quadratic by its values at the nodes; this
    adds what the objects hold, so that two systems that differ only in a constructor argument
    (or two costs that agree at the nodes) are two members. A system whose state cannot be read
    is identified by its own ``parameters()`` where it has one; otherwise it is refused.
    """
    system = problem.system
    record = {}
    try:
        record["system"] = state_record(system, arrays, "system")
    except UnidentifiableError as exc:
        if not _own_parameters(system):
            name = type(system).__name__
            raise TypeError(
                f"gridlbc.sweep cannot tell one {name} from another: {exc}. Give {name} a "
                "parameters() method that returns every constructor argument that changes its "
                "dynamics (as a dict of numbers, strings or lists), so that members with "
                "different systems get different results"
            ) from None
    for name in ("terminal_cost", "state_cost"):
        cost = getattr(problem, name)
        try:
            record[name] = state_record(cost, arrays, name)
        except UnidentifiableError as exc:
            raise TypeError(
                f"gridlbc.sweep cannot tell one {name} from another: {exc}. Make the cost a "
                "function or an object whose attributes (or closure) hold every number it uses"
            ) from None
    return record


def member_key(problem: Problem, settings: SolverSettings) -> str:
    """SHA-256 (hex) of what determines a solve's result: problem, settings and versions.

    The problem enters by its description (:func:`gridlbc.io.problem_record`) and by the full
    state of its system and costs (:func:`identity_record`).
    """

    arrays: dict = {}
    description = {
        "library_version": __version__,
        "format_version": FORMAT_VERSION,
        "problem": problem_record(problem, arrays),
        "identity": identity_record(problem, arrays),
        "settings": settings_record(problem, settings, arrays),
    }
    return digest(description, arrays)


def _finished(path: Path, key: str, problem: Problem):
    """The Solution stored at ``path`` if it is complete and was written for ``key``, else None.
    The key covers the system's full state, so the member's own ``problem.system`` is the saved
    one (a user's class need not be rebuildable from its ``parameters()``)."""
    try:
        if read_metadata(path).get("annotations", {}).get("sweep_key") != key:
            return None
        return load(path, system=problem.system)  # verifies the arrays against their checksum
    except (FileNotFoundError, ValueError, KeyError, TypeError):
        return None


def _save_atomic(solution, path: Path, key: str) -> None:
    """Save under a temporary name, then rename: a killed worker never leaves a partial file."""
    partial = path.with_name(f"{path.stem}.{os.getpid()}.partial.npz")
    try:
        write(solution, partial, annotations={"sweep_key": key})
        os.replace(partial, path)
    finally:
        partial.unlink(missing_ok=True)


def _run_member(
    problem: Problem, settings: SolverSettings, states, path: str, key: str, numba_threads: int
) -> _Outcome:
    """Solve (or reuse) one member on a worker; every failure is returned, never raised."""
    import numba

    # numba.config sets its options from the environment at import, out of mypy's sight
    largest = numba.config.NUMBA_NUM_THREADS  # type: ignore[attr-defined]
    numba.set_num_threads(max(1, min(numba_threads, largest)))
    file = Path(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            solution = _finished(file, key, problem)
            reused = solution is not None
            if not reused:
                solution = solve(problem, settings=settings)
                _save_atomic(solution, file, key)
            values = None if states is None else solution.value(states, 0.0)
            error = None
        except Exception as exc:
            values, error, reused = None, f"{type(exc).__name__}: {exc}", False
            solution = None
    return _Outcome(
        values,
        None if solution is None else solution.diagnostics,
        error,
        reused,
        tuple((w.category, str(w.message)) for w in caught),
    )


def import_distributed():
    """The ``distributed`` module, or an ImportError that says how to install it (the command
    line asks before it starts a sweep)."""
    try:
        import distributed
    except ImportError as exc:
        raise ImportError(
            "gridlbc.sweep needs Dask distributed, which is not installed: install the extra "
            'with pip install "gridlbc[dask]" (or pip install "dask[distributed]")'
        ) from exc
    return distributed


def available_cores() -> int:
    """Cores this process may run on (the default number of local workers)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


@contextlib.contextmanager
def _connect(client, workers, numba_threads):
    """A Dask client: the given one, one connected to an address, or a new local cluster."""
    distributed = import_distributed()
    if client is not None and workers is not None:
        raise ValueError(
            "workers sizes the local cluster started when client is None: drop "
            "workers, or size your own cluster"
        )
    if isinstance(client, distributed.Client):
        yield client
        return
    if isinstance(client, str):
        with distributed.Client(client) as connected:
            yield connected
        return
    if client is not None:
        raise TypeError(
            f"client must be None, a dask.distributed.Client or a scheduler address "
            f"such as 'tcp://host:8786', got {type(client).__name__}"
        )
    workers = available_cores() if workers is None else workers
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a positive integer, got {workers!r}")
    env = {"NUMBA_NUM_THREADS": str(numba_threads)}
    with (
        distributed.LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0", env=env
        ) as cluster,
        distributed.Client(cluster) as local,
    ):
        yield local


def _describe(client) -> str:
    n = len(client.scheduler_info().get("workers", {}))
    return f"{n} worker{'s' * (n != 1)} at {client.scheduler.address}"


def sweep(
    problems,
    out_dir,
    states=None,
    client=None,
    *,
    workers: int | None = None,
    numba_threads: int = 1,
    progress: bool = True,
    settings=None,
    **solve_options,
) -> list[SweepMember]:
    """Solve many problems in parallel on Dask distributed; one saved Solution per problem.

    Parameters
    ----------
    problems : sequence of Problem
        The members. They are pickled to the workers: the built-in systems and
        :class:`gridlbc.Quadratic` costs are; your own systems and costs must be importable on
        the workers. Each member is identified by the full state of its system and costs (see
        the module docstring); a system whose attributes cannot be read needs a
        ``parameters()`` method, or the sweep refuses it before any work.
    out_dir : path
        Where each member's Solution is written, as ``<system>-<key[:16]>.npz``. On a cluster of
        several machines it must be a directory that every worker can write to.
    states : array_like (n, d) or (d,), optional
        States at which to report v(x, 0) in each member's ``values``.
    client : None, dask.distributed.Client or str
        ``None``: start a local cluster of ``workers`` processes with one thread each, and close
        it at the end. A Client: use its cluster. A scheduler address (``"tcp://host:8786"``):
        connect to it.
    workers : int, optional
        Processes of the local cluster (default: the cores available to this process).
    numba_threads : int
        Threads each member's numba kernels use (default 1: the parallelism is across members).
    progress : bool
        Print the sweep's progress to stderr.
    settings, **solve_options
        As for :func:`gridlbc.solve`, the same for every member.

    Returns
    -------
    list of SweepMember
        One per problem, in order. A member that failed has its ``error`` set; the others are
        kept. Members already in ``out_dir`` from an earlier run of the same problem and settings
        are loaded (``reused``), not solved again.
    """
    problems = list(problems)
    for i, problem in enumerate(problems):
        if not isinstance(problem, Problem):
            raise TypeError(
                f"problems[{i}] must be a gridlbc.Problem, got {type(problem).__name__}"
            )
    if isinstance(numba_threads, bool) or not isinstance(numba_threads, int) or numba_threads < 1:
        raise ValueError(f"numba_threads must be a positive integer, got {numba_threads!r}")
    s = dataclasses.replace(resolve_settings(settings, solve_options), progress=False)
    points = None if states is None else [p.grid.check_states(states, "states") for p in problems]
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    keys = []
    for i, problem in enumerate(problems):
        try:
            keys.append(member_key(problem, s))
        except TypeError as exc:
            raise TypeError(f"problems[{i}]: {exc}") from None
    paths = [
        (out_dir / f"{type(p.system).__name__.lower()}-{k[:16]}.npz").resolve()
        for p, k in zip(problems, keys)
    ]
    state_tag = (
        "none"
        if points is None
        else hashlib.sha256(np.ascontiguousarray(points[0]).tobytes()).hexdigest()[:16]
    )
    outcomes: dict[str, _Outcome] = {}
    with _connect(client, workers, numba_threads) as c:
        pending, submitted = {}, set()
        for i, (problem, key, path) in enumerate(zip(problems, keys, paths)):
            if key in submitted:
                continue  # the same problem twice: solved once, reported for both
            submitted.add(key)
            try:
                future = c.submit(
                    _run_member,
                    problem,
                    s,
                    None if points is None else points[i],
                    str(path),
                    key,
                    numba_threads,
                    key=f"gridlbc-sweep-{key[:32]}-{state_tag}",
                )
            except Exception as exc:
                outcomes[key] = _Outcome(None, None, f"{type(exc).__name__}: {exc}", False, ())
                continue
            pending[future] = key
        if progress:
            sys.stderr.write(f"sweep: {len(set(keys))} members on {_describe(c)}\n")
        bar = ProgressBar(len(set(keys)), progress, "sweep", items="done")
        failed = sum(o.error is not None for o in outcomes.values())
        reused = 0
        bar.update(len(outcomes), f", {failed} failed, {reused} reused")
        distributed = import_distributed()
        for future in distributed.as_completed(list(pending)):
            try:
                outcome = future.result()
            except Exception as exc:
                outcome = _Outcome(None, None, f"{type(exc).__name__}: {exc}", False, ())
            outcomes[pending[future]] = outcome
            failed += outcome.error is not None
            reused += outcome.reused
            bar.update(len(outcomes), f", {failed} failed, {reused} reused")
            future.release()
    members = []
    for i, (key, path) in enumerate(zip(keys, paths)):
        o = outcomes[key]
        for category, message in o.warnings:
            warn_user(f"sweep member {i}: {message}", category)
        members.append(
            SweepMember(
                i,
                key,
                None if o.error else path,
                o.values,
                o.diagnostics,
                o.error,
                o.reused,
                tuple(m for _, m in o.warnings),
            )
        )
    return members
