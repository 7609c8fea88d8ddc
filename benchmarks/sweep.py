"""Speed-up of gridlbc.sweep on a local Dask cluster over the same solves one after another.

Eight pendulum swing-ups (θ periodic, ω ∈ [−10, 10], T = 3, dt = 0.02, every 10th slice
stored) at temperatures λ spread over [0.5, 2]. Each case solves all eight, saves each Solution
and evaluates v(x₀, 0) at the hanging-down state x₀ = (π, 0):

- serial, numba's default threads (all cores): a plain loop of gridlbc.solve + gridlbc.save;
- serial, 1 numba thread: the same loop on one core;
- sweep on a warm cluster: gridlbc.sweep on ``--workers`` one-thread processes whose kernels are
  already loaded (the cluster's start and warm-up are timed apart);
- sweep from cold: the same call with client=None (starts, uses and closes its own cluster).

Every sweep member's file and value must equal the serial solve's bit for bit. The machine's load
average (``os.getloadavg``) is printed before and after: the timings are only as good as the
machine is quiet. Usage:

    python benchmarks/sweep.py [--grid 401] [--members 8] [--workers 2]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numba
import numpy as np

import gridlbc as g
from gridlbc.systems import Pendulum

X0 = np.array([[np.pi, 0.0]])


def problems(n: int, members: int) -> list[g.Problem]:
    grid = g.Grid([g.Axis(-np.pi, np.pi, n, periodic=True), g.Axis(-10, 10, n + 1)])
    base = g.Problem(Pendulum(), grid, 3.0, g.Quadratic([0, 0], [10, 0.5]))
    return [base.replace(temperature=t) for t in np.linspace(0.5, 2.0, members)]


def _serial(problems, options, out: Path):
    solutions = [g.solve(p, **options) for p in problems]
    for i, s in enumerate(solutions):
        g.save(s, out / f"serial-{i}.npz")
        s.value(X0, 0.0)
    return solutions


def _mean_solve(results) -> float:
    """Mean wall time of the solves themselves (diagnostics), without saving and evaluating."""
    return float(np.mean([r.diagnostics.wall_time for r in results]))


def _warm_up():
    """Load the kernels in a worker (numba's disk cache), outside the timings."""
    g.solve(problems(21, 1)[0], dt=0.02)


def _identical(members, solutions) -> bool:
    for m, s in zip(members, solutions):
        if m.error is not None:
            return False
        stored = g.load(m.path)
        if not (
            np.array_equal(stored.slices, s.slices)
            and np.array_equal(stored.log_scales, s.log_scales)
            and np.array_equal(m.values, s.value(X0, 0.0))
        ):
            return False
    return True


def main(argv=None) -> None:
    from dask.distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=401, help="θ nodes (ω has one more)")
    parser.add_argument("--members", type=int, default=8)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    options = {"dt": 0.02, "store_every": 10}
    members = problems(args.grid, args.members)
    load_before = os.getloadavg()
    _warm_up()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        t0 = time.perf_counter()
        serial = _serial(members, options, tmp)
        rows.append(
            (
                f"serial, {numba.get_num_threads()} numba threads",
                time.perf_counter() - t0,
                _mean_solve(serial),
                "-",
            )
        )
        default_threads = numba.get_num_threads()
        numba.set_num_threads(1)
        t0, cpu0 = time.perf_counter(), time.process_time()
        one = _serial(members, options, tmp)
        rows.append(("serial, 1 numba thread", time.perf_counter() - t0, _mean_solve(one), "-"))
        serial_cpu = time.process_time() - cpu0
        numba.set_num_threads(default_threads)

        t0 = time.perf_counter()
        with (
            LocalCluster(
                n_workers=args.workers,
                threads_per_worker=1,
                dashboard_address=":0",
                env={"NUMBA_NUM_THREADS": "1"},
            ) as cluster,
            Client(cluster) as client,
        ):
            client.run(_warm_up)
            start = time.perf_counter() - t0
            t0, cpu0 = time.perf_counter(), sum(client.run(time.process_time).values())
            swept = g.sweep(
                members, tmp / "warm", states=X0, client=client, progress=False, **options
            )
            sweep_cpu = sum(client.run(time.process_time).values()) - cpu0
            rows.append(
                (
                    f"sweep, {args.workers} workers, warm cluster",
                    time.perf_counter() - t0,
                    _mean_solve(swept),
                    _identical(swept, serial),
                )
            )
        rows.append((f"  (cluster start and warm-up: {start:.1f} s)", None, None, ""))
        t0 = time.perf_counter()
        swept = g.sweep(
            members, tmp / "cold", states=X0, workers=args.workers, progress=False, **options
        )
        rows.append(
            (
                f"sweep, {args.workers} workers, from cold",
                time.perf_counter() - t0,
                _mean_solve(swept),
                _identical(swept, serial),
            )
        )
    load_after = os.getloadavg()

    print(
        f"{args.members} pendulum solves on {args.grid}×{args.grid + 1}, "
        f"{serial[0].diagnostics.steps} steps each; {os.cpu_count()} cores; load average "
        f"before {load_before[0]:.2f}, after {load_after[0]:.2f} (1 min)"
    )
    base, one = rows[0][1], rows[1][1]
    print(
        f"{'case':<40} {'wall s':>7} {'per solve s':>12} {'vs serial':>10} {'vs 1 thread':>12} "
        f"{'bitwise':>8}"
    )
    for name, wall, per_solve, same in rows:
        if wall is None:
            print(name)
            continue
        print(
            f"{name:<40} {wall:>7.2f} {per_solve:>12.2f} {base / wall:>9.2f}× "
            f"{one / wall:>11.2f}× {same!s:>8}"
        )
    # Under load the wall times say little (the kernel shares the cores between sessions, not
    # processes); CPU time does not depend on the share. The bound is W × (serial CPU / sweep
    # CPU): the speed-up over one thread on an otherwise idle machine, less load imbalance.
    print(
        f"CPU time: serial 1 thread {serial_cpu:.2f} s, sweep workers {sweep_cpu:.2f} s in "
        f"all; on {args.workers} idle cores at most {args.workers * serial_cpu / sweep_cpu:.2f}× "
        "the 1-thread serial"
    )


if __name__ == "__main__":
    main()
