"""Sweeps on Dask distributed: the same numbers as serial solves, failures kept apart, reruns.

A sweep member is the same computation as :func:`gridlbc.solve` in another process with one numba
thread, so its saved arrays and values must equal the serial ones bit for bit (every kernel's
result is independent of the thread count). The cluster tests start 2-worker local clusters on
41² pendulum grids (a few seconds each).
"""

import math
import pickle
import shutil
import subprocess
import sys
import threading

import numpy as np
import pytest
from conftest import EXACTNESS_ONLY

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic, systems
from gridlbc.sweep import SweepMember, member_key

STATES = np.array([[math.pi, 0.0], [-1.0, 0.5]])


def pendulum(n=41, **changes):
    grid = Grid([Axis(-math.pi, math.pi, n, periodic=True), Axis(-8.0, 8.0, n)])
    problem = Problem(systems.Pendulum(), grid, 1.0, Quadratic([0.0, 0.0], [10.0, 0.5]))
    return problem.replace(**changes)


def too_large():
    """A problem whose memory check fails on the worker (hundreds of GiB), before allocating."""
    return pendulum(60000)


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
        ) as cluster,
        distributed.Client(cluster) as c,
    ):
        yield c


@pytest.mark.parametrize(
    "system",
    [
        systems.SingleIntegrator(),
        systems.PointMass(mass=2.0),
        systems.Pendulum(damping=0.1),
        systems.Acrobot(),
    ],
)
def test_problems_pickle_for_the_workers(system):
    """Plain pickle (what any cluster can ship) round-trips a problem with a built-in system and
    quadratic costs to the same dynamics and costs, bit for bit."""
    d = system.state_dim
    problem = Problem(
        system,
        system.default_grid(5),
        1.5,
        Quadratic(np.ones(d), 2.0),
        state_cost=Quadratic(np.zeros(d), 0.1),
        control_cost=0.5,
        temperature=0.7,
    )
    copy = pickle.loads(pickle.dumps(problem))
    x = problem.grid.nodes()
    np.testing.assert_array_equal(copy.system.drift(x), problem.system.drift(x))
    np.testing.assert_array_equal(copy.system.input_matrix(x), problem.system.input_matrix(x))
    np.testing.assert_array_equal(copy.terminal_cost(x), problem.terminal_cost(x))
    np.testing.assert_array_equal(copy.state_cost(x), problem.state_cost(x))
    assert member_key(copy, gridlbc.SolverSettings()) == member_key(
        problem, gridlbc.SolverSettings()
    )


def test_member_key_is_the_content():
    """Equal problems built separately share a key; anything that changes the result changes it;
    how the solve runs (progress, mmap_dir) does not."""
    s = gridlbc.SolverSettings()
    key = member_key(pendulum(), s)
    assert member_key(pendulum(), s) == key
    assert member_key(pendulum(), gridlbc.SolverSettings(progress=True, mmap_dir=".")) == key
    changed = [
        pendulum(temperature=0.5),
        pendulum(horizon=2.0),
        pendulum(system=systems.Pendulum(damping=0.1)),
        pendulum(terminal_cost=Quadratic([0.1, 0.0], [10.0, 0.5])),
    ]
    assert len({key, *(member_key(p, s) for p in changed)}) == 5
    assert member_key(pendulum(), gridlbc.SolverSettings(dt=0.05)) != key
    assert member_key(pendulum(), gridlbc.SolverSettings(fitting=None)) != key
    # the default "auto" is fitting="terminal": the same solve, the same key
    assert member_key(pendulum(), gridlbc.SolverSettings(fitting="terminal")) == key
    # A cost that is not a quadratic is identified by its values at the nodes.
    quadratic = Quadratic([0.0, 0.0], [10.0, 0.5])
    custom = pendulum(terminal_cost=lambda x: quadratic(x))
    assert member_key(custom, s) == member_key(pendulum(terminal_cost=lambda x: quadratic(x)), s)
    assert member_key(custom, s) != member_key(
        pendulum(terminal_cost=lambda x: 2 * quadratic(x)), s
    )


class Spin(systems.ControlAffineSystem):
    """A user's system as the README writes one: a flow turning at ``rate``, no parameters()."""

    state_dim, control_dim, state_names = 2, 2, ("x", "y")

    def __init__(self, rate, lock=False):
        self.rate = rate
        if lock:
            self.lock = threading.Lock()  # state that cannot be read

    def drift(self, x):
        x = self._states(x)
        return self.rate * np.stack([-x[:, 1], x[:, 0]], axis=1)

    def input_matrix(self, x):
        return np.broadcast_to(np.eye(2), (self._states(x).shape[0], 2, 2))


class NamedSpin(Spin):
    def parameters(self):
        return {"rate": self.rate}


def spin(rate, system=Spin, **options):
    grid = Grid([Axis(-2.0, 2.0, 21), Axis(-2.0, 2.0, 21)])
    return Problem(system(rate, **options), grid, 1.0, Quadratic([1.0, 0.0], [2.0, 2.0]))


def strip(center):
    """A state cost whose only number lives in the closure."""
    return lambda x: 5.0 * (np.abs(x[:, 0] - center) < 0.05)


def test_member_key_covers_a_user_systems_state():
    """Systems without parameters() differ by their attributes; costs by their closures too; a
    system whose state cannot be read is refused unless it says its parameters()."""
    s = gridlbc.SolverSettings()
    assert member_key(spin(1.0), s) == member_key(spin(1.0), s)
    assert member_key(spin(1.0), s) != member_key(spin(2.0), s)
    with_cost = spin(1.0).replace(state_cost=strip(0.3))
    assert member_key(with_cost, s) == member_key(spin(1.0).replace(state_cost=strip(0.3)), s)
    # the two strips agree at every node (both miss them): the closure tells them apart
    other = spin(1.0).replace(state_cost=strip(0.31))
    np.testing.assert_array_equal(with_cost.state_cost_values(), other.state_cost_values())
    assert member_key(with_cost, s) != member_key(other, s)
    with pytest.raises(TypeError, match=r"cannot tell one Spin .*system.lock.*parameters\(\)"):
        member_key(spin(1.0, lock=True), s)
    named = [member_key(spin(r, NamedSpin, lock=True), s) for r in (1.0, 2.0)]
    assert named[0] != named[1]


@EXACTNESS_ONLY
def test_sweep_keeps_each_user_systems_result(tmp_path, client):
    """Two members whose system differs only in a constructor argument: two files, and each
    member's values are its own serial solve's."""
    problems = [spin(0.5), spin(3.0)]
    members = gridlbc.sweep(problems, tmp_path, states=[0.0, 1.0], client=client, progress=False)
    assert members[0].path != members[1].path
    assert len(list(tmp_path.glob("*.npz"))) == 2
    for problem, member in zip(problems, members):
        assert member.error is None, member.error
        np.testing.assert_array_equal(member.values, gridlbc.solve(problem).value([0.0, 1.0], 0.0))
    assert members[0].values[0] != members[1].values[0]
    # run again: each member's file is reused (read back with the member's own system, which
    # Spin's parameters() alone cannot rebuild), with the same values
    again = gridlbc.sweep(problems, tmp_path, states=[0.0, 1.0], client=client, progress=False)
    assert [m.reused for m in again] == [True, True]
    for first, second in zip(members, again):
        np.testing.assert_array_equal(first.values, second.values)
    with pytest.raises(TypeError, match=r"problems\[1\]: gridlbc.sweep cannot tell"):
        gridlbc.sweep([spin(1.0), spin(1.0, lock=True)], tmp_path, client=client)


@EXACTNESS_ONLY
def test_sweep_equals_serial_solves_bitwise(tmp_path, capsys):
    """client=None: a local cluster of 2 one-thread processes; every file and value equals the
    serial gridlbc.solve exactly, and progress is shown."""
    pytest.importorskip("distributed")
    problems = [
        pendulum(temperature=0.5),
        pendulum(system=systems.Pendulum(damping=0.2)),
        pendulum(terminal_cost=Quadratic([0.3, 0.0], [10.0, 0.5]), horizon=1.5),
    ]
    members = gridlbc.sweep(problems, tmp_path, states=STATES, workers=2)
    assert "3/3 done, 0 failed, 0 reused" in capsys.readouterr().err
    assert [m.index for m in members] == [0, 1, 2]
    for problem, member in zip(problems, members):
        assert isinstance(member, SweepMember)
        assert member.error is None and not member.reused
        serial = gridlbc.solve(problem)
        stored = gridlbc.load(member.path)
        np.testing.assert_array_equal(stored.slices, serial.slices)
        np.testing.assert_array_equal(stored.log_scales, serial.log_scales)
        np.testing.assert_array_equal(stored.times, serial.times)
        np.testing.assert_array_equal(member.values, serial.value(STATES, 0.0))
        assert member.diagnostics.steps == serial.diagnostics.steps
        assert member.diagnostics.dt == serial.diagnostics.dt


@EXACTNESS_ONLY
def test_failed_member_is_reported_and_reruns_skip_finished(tmp_path, client):
    ok = [pendulum(temperature=0.7), pendulum(temperature=1.3)]
    problems = [ok[0], too_large(), ok[1], pendulum(temperature=0.7)]  # the last repeats the first
    first = gridlbc.sweep(problems, tmp_path, states=STATES, client=client, progress=False)
    assert "MemoryError" in first[1].error and first[1].path is None and first[1].values is None
    for m in (first[0], first[2], first[3]):
        assert m.error is None and not m.reused and m.path.exists()
    assert first[3].path == first[0].path  # the same problem twice is one member
    np.testing.assert_array_equal(first[3].values, first[0].values)
    assert len(list(tmp_path.glob("*.npz"))) == 2

    second = gridlbc.sweep(problems, tmp_path, states=STATES[:1], client=client, progress=False)
    assert [m.reused for m in second] == [True, False, True, True]
    assert "MemoryError" in second[1].error
    for a, b in zip(first, second):
        if a.error is None:
            assert a.path == b.path and a.diagnostics == b.diagnostics
            np.testing.assert_array_equal(b.values, a.values[:1])  # new states, stored solution

    # A stored file is reused only if it is complete and was written for that member.
    with open(first[0].path, "r+b") as f:
        f.truncate(f.seek(0, 2) // 2)
    third = gridlbc.sweep(ok, tmp_path, states=STATES, client=client, progress=False)
    assert [m.reused for m in third] == [False, True]
    np.testing.assert_array_equal(third[0].values, first[0].values)
    shutil.copyfile(first[2].path, first[0].path)  # another member's file in its place
    fourth = gridlbc.sweep(ok[:1], tmp_path, states=STATES, client=client, progress=False)
    assert not fourth[0].reused
    np.testing.assert_array_equal(fourth[0].values, first[0].values)
    assert not list(tmp_path.glob("*.partial.npz"))


def test_sweep_arguments_are_checked(tmp_path, monkeypatch):
    with pytest.raises(TypeError, match=r"problems\[1\] must be a gridlbc.Problem"):
        gridlbc.sweep([pendulum(), "pendulum"], tmp_path)
    with pytest.raises(ValueError, match="states must have shape"):
        gridlbc.sweep([pendulum()], tmp_path, states=[0.0, 0.0, 0.0])
    with pytest.raises(TypeError, match="unknown solve option"):
        gridlbc.sweep([pendulum()], tmp_path, step=0.1)
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if Dask were not installed
    with pytest.raises(ImportError, match=r"pip install \"gridlbc\[dask\]\""):
        gridlbc.sweep([pendulum()], tmp_path)


def test_import_gridlbc_does_not_import_dask():
    code = (
        "import sys, gridlbc; assert gridlbc.sweep; print('dask' in sys.modules, "
        "'distributed' in sys.modules)"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.split() == ["False", "False"]


@EXACTNESS_ONLY
def test_cli_sweep_on_a_scheduler(tmp_path, client):
    """gridlbc sweep --scheduler: the table shows the values of the serial solves; a rerun
    reuses every member."""
    args = [
        sys.executable,
        "-m",
        "gridlbc.cli",
        "sweep",
        "--system",
        "pendulum",
        "--axis=-pi,pi,41,periodic",
        "--axis=-8,8,41",
        "--horizon",
        "1",
        "--terminal-center",
        "0,0",
        "--terminal-weights",
        "10,0.5",
        "--temperatures",
        "0.5,1",
        "--param-values",
        "damping=0,0.2",
        "--at=pi,0",
        "--out",
        str(tmp_path),
        "--scheduler",
        client.scheduler.address,
    ]
    first = subprocess.run(args, capture_output=True, text=True, timeout=300, check=False)
    assert first.returncode == 0, first.stderr
    lines = first.stdout.splitlines()
    assert lines[0].split()[:4] == ["#", "damping", "temperature", "v(3.14159,0)"]
    rows = [line.split() for line in lines[1:5]]
    for row, (damping, temperature) in zip(rows, [(0, 0.5), (0, 1), (0.2, 0.5), (0.2, 1)]):
        problem = pendulum(system=systems.Pendulum(damping=damping), temperature=temperature)
        value = gridlbc.solve(problem).value([math.pi, 0.0], 0.0)
        assert row[1:4] == [f"{damping:g}", f"{temperature:g}", f"{value:.6g}"]
        assert row[5] == "solved"
    assert "4 members: 4 solved, 0 reused, 0 failed" in lines[5]
    again = subprocess.run(
        [*args, "--quiet"], capture_output=True, text=True, timeout=300, check=False
    )
    assert again.returncode == 0 and again.stderr == ""
    assert "4 members: 0 solved, 4 reused, 0 failed" in again.stdout


@pytest.mark.parametrize(
    "extra, message",
    [
        ([], "nothing to sweep: give --param-values"),
        (["--param-values", "damping"], "--param-values expects KEY=V1,V2"),
        (["--param-values", "mass=1,-1"], "member 1 (mass=-1.0): system.parameters"),
        (["--temperatures", "1", "--workers", "2", "--scheduler", "tcp://x:1"], "workers sizes"),
    ],
)
def test_cli_sweep_mistakes(extra, message, tmp_path, capsys):
    """Mistakes end before any cluster starts, with one line naming the flag or member."""
    pytest.importorskip("distributed")
    from gridlbc.cli import main

    base = [
        "sweep",
        "--system",
        "pendulum",
        "--grid",
        "21",
        "--horizon",
        "1",
        "--terminal-center",
        "0,0",
        "--terminal-weights",
        "10,0.5",
        "--out",
        str(tmp_path),
    ]
    assert main(base + extra) == 2
    err = capsys.readouterr().err
    assert err.startswith("gridlbc sweep: error: ") and message in err, err


@EXACTNESS_ONLY
def test_worker_warnings_reach_the_caller(tmp_path, client):
    """A warning raised on a worker (here: z flushed to zero by float32 storage at the queried
    state, so v = +inf) is kept on the member and issued again by sweep."""
    problem = pendulum(temperature=0.005, horizon=0.05)
    with pytest.warns(gridlbc.UnderflowWarning, match="sweep member 0: "):
        [member] = gridlbc.sweep(
            [problem],
            tmp_path,
            states=[-math.pi, -8.0],
            client=client,
            progress=False,
            dtype="float32",
            fitting=None,
        )
    assert member.values[0] == math.inf and member.error is None
    # the plain solve at λ = 0.005 also (rightly) raises a ResolutionWarning on the worker
    assert sum("underflow" in w for w in member.warnings) == 1, member.warnings
