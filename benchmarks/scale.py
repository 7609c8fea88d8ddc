"""Speed and memory of the solvers on large grids, against a plain scipy baseline.

Cases (T = 3 s, λ = 1): the pendulum swing-up (θ periodic × ω ∈ [−10, 10], g = xᵀdiag(10, ½)x) on
n × (n+1) grids and the gymnast (:func:`gridlbc.studies.gymnast.gymnast_problem`, box ±16 × ±9) on n⁴
grids. Each case runs in its own subprocess so that its peak RSS (VmHWM) is its own. Per case
and method: wall time of the solve (setup included; numba kernels are cached on disk and warmed
up by a tiny solve first), node-steps per second (stepping only), iterations per step, peak RSS,
and the fraction of the memory bandwidth the stepping streams (a byte count per node-step from
the arrays each pass reads and writes, divided by --bandwidth, default 27 GB/s measured here).

Methods: ``splitting`` (compact feet, float32 slices), ``fitted`` (the same with the drift fitted
to the terminal cost, ``fitting="terminal"``), ``implicit`` (Gauss–Seidel sweeps) and
the plain-scipy baseline (scipy splu where the grid is 2D, else scipy BiCGSTAB with a Jacobi
preconditioner). Slow methods run fewer steps (--baseline-steps) and their node-steps per second
is extrapolated to the full run: marked ``*`` in the table. The gymnast's accuracy per second
(rollout cost against solve time, per grid, method and Δt) is ``benchmarks/gymnast.py``.

    python benchmarks/scale.py                          # the full table (≈ 10 min on 2 cores)
    python benchmarks/scale.py --pendulum 201 --acrobot 21 --steps 300
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

import gridlbc
from gridlbc import Problem
from gridlbc.schemes.splitting import feet_bytes_per_node
from gridlbc.studies.problems import gymnast_problem, swingup_problem


def problem_for(system: str, n: int) -> Problem:
    return swingup_problem(n) if system == "pendulum" else gymnast_problem(n)


def bytes_per_node_step(problem: Problem, method: str, iterations: float, store: int) -> float:
    """Bytes streamed per node and step (a lower bound: gathers counted once)."""
    d = problem.grid.ndim
    if method in ("splitting", "fitted"):
        noise_axes = 1  # both systems: noise on the last momentum only
        # feet + read z + write z*, two half-step tridiagonal read/writes (before and after the
        # drift), renormalised store (read z, write); fitted: the fitting pass reads z and
        # writes z/φ and log φ (the drift then reads log φ instead of z: the reference row,
        # fitted to itself, needs no gather of z).
        fitting = 24 if method == "fitted" else 0
        return (feet_bytes_per_node(d, "compact") + 16 + 2 * 16 * noise_axes + (8 + store)
                + fitting)
    if method == "implicit":
        # per sweep: off-diagonal CSR (value 8 + column 4 per entry, 2d entries), row pointer,
        # inverse diagonal, b and x (read and written).
        return iterations * (2 * d * 12 + 8 + 8 + 8 + 16) + (8 + store)
    return float("nan")


def run_case(system: str, n: int, method: str, steps: int, full_steps: int) -> dict:
    """Solve ``steps`` steps of the full run's Δt = T/full_steps (a shortened horizon)."""
    problem = problem_for(system, n)
    dt = problem.horizon / full_steps
    problem = problem.replace(horizon=steps * dt)
    if method == "scipy":
        linear_solver = "direct" if problem.grid.ndim == 2 else "bicgstab"
        options = {"method": "implicit", "linear_solver": linear_solver, "dtype": "float32"}
    elif method == "implicit":
        options = {"method": "implicit", "linear_solver": "gauss-seidel", "dtype": "float32"}
    else:
        options = {"method": "splitting", "dtype": "float32"}
        if method == "fitted":
            options["fitting"] = "terminal"
    # warm the numba caches and the page allocator on a tiny grid of the same kind
    small = problem_for(system, 11 if system == "acrobot" else 21)
    gridlbc.solve(small.replace(horizon=2 * dt), dt=dt, **options)
    started = time.perf_counter()
    solution = gridlbc.solve(problem, dt=dt, **options)
    wall = time.perf_counter() - started
    diag = solution.diagnostics
    stepping = diag.wall_time - diag.setup_time
    iterations = float(np.mean(diag.iterations)) if diag.iterations else 0.0
    return {
        "system": system, "n": n, "nodes": problem.grid.size, "method": method,
        "solver": options.get("linear_solver", "splitting"), "steps": steps, "wall": wall,
        "setup": diag.setup_time, "node_steps": problem.grid.size * steps / stepping,
        "iterations": iterations,
        "bytes": (float("nan") if options.get("linear_solver") == "direct"
                  else bytes_per_node_step(problem, "implicit" if method == "scipy" else method,
                                           iterations, 4)),
        "peak_rss": peak_rss(),
    }


def peak_rss() -> int:
    """This process's peak resident set (VmHWM: unlike getrusage's ru_maxrss it starts afresh at
    exec, so it does not inherit a large parent's high-water mark)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def layout_comparison(n: int, steps: int, bandwidth: float):
    """ms per splitting step on the n⁴ gymnast with each feet layout (same process, warmed up)."""
    from gridlbc.schemes.splitting import FEET_LAYOUTS, SplittingStep

    problem = gymnast_problem(n)
    z = np.exp(-problem.terminal_values()[None, :])
    out = np.empty_like(z)
    scale = np.ones(1)
    for layout in FEET_LAYOUTS:
        step = SplittingStep(problem, 0.01, feet=layout)
        step(z, out, scale)
        started = time.perf_counter()
        for _ in range(steps):
            step(z, out, scale)
        per_step = (time.perf_counter() - started) / steps
        streamed = (feet_bytes_per_node(4, layout) + 16 + 2 * 16) * problem.grid.size
        print(f"  feet layout {layout:>7} on {n}^4: {1e3 * per_step:6.1f} ms/step, "
              f"{feet_bytes_per_node(4, layout)} B/node of feet, "
              f"{100 * streamed / per_step / bandwidth:4.0f}% of bandwidth", flush=True)


def in_subprocess(system: str, n: int, method: str, steps: int, full_steps: int) -> dict:
    out = subprocess.run([sys.executable, __file__, "--case", system, str(n), method, str(steps),
                          str(full_steps)],
                         capture_output=True, text=True, check=False)
    if out.returncode != 0:
        return {"system": system, "n": n, "method": method, "error": out.stderr.strip().splitlines()[-1]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pendulum", type=int, nargs="*", default=[201, 401, 801])
    parser.add_argument("--acrobot", type=int, nargs="*", default=[21, 31, 41, 51])
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--baseline-steps", type=int, default=10,
                        help="steps for the slow methods on 4D grids (extrapolated)")
    parser.add_argument("--implicit-max-nodes", type=int, default=3_000_000,
                        help="skip the implicit and scipy methods above this many nodes")
    parser.add_argument("--layout-grid", type=int, default=41,
                        help="n⁴ gymnast grid for the feet layout comparison (0: skip)")
    parser.add_argument("--bandwidth", type=float, default=27e9, help="bytes/s (default 27e9)")
    parser.add_argument("--case", nargs=5, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.case:
        system, n, method, steps, full_steps = args.case
        print(json.dumps(run_case(system, int(n), method, int(steps), int(full_steps))))
        return

    print(f"load average at start: {os.getloadavg()[0]:.2f} (2 cores shared: timings vary)")
    if args.layout_grid:
        layout_comparison(args.layout_grid, 20, args.bandwidth)
    print(f"{'case':>14} {'nodes':>9} {'method':>9} {'steps':>6} {'wall s':>8} "
          f"{'Mnode-steps/s':>14} {'it/step':>7} {'peak RSS GiB':>12} {'B/node-step':>11} "
          f"{'% bandwidth':>11}")
    cases = [("pendulum", n) for n in args.pendulum] + [("acrobot", n) for n in args.acrobot]
    for system, n in cases:
        rows = {}
        nodes = n * (n + 1) if system == "pendulum" else n**4
        for method in ("splitting", "fitted", "implicit", "scipy"):
            fast = method in ("splitting", "fitted")
            if not fast and nodes > args.implicit_max_nodes:
                continue
            slow = not fast and system == "acrobot"
            steps = args.baseline_steps if slow else args.steps
            rows[method] = row = in_subprocess(system, n, method, steps, args.steps)
            if "error" in row:
                print(f"{system + ' ' + str(n):>14} {method:>9}  failed: {row['error']}")
                continue
            mark = "*" if steps != args.steps else " "
            full_wall = row["setup"] + args.steps * row["nodes"] / row["node_steps"]
            rate = row["node_steps"] / 1e6
            bandwidth = 100 * row["bytes"] * row["node_steps"] / args.bandwidth
            print(f"{system + ' ' + str(n):>14} {row['nodes']:9d} {method + mark:>9} "
                  f"{args.steps:6d} {full_wall:8.1f} {rate:14.2f} {row['iterations']:7.1f} "
                  f"{row['peak_rss'] / 2**30:12.2f} {row['bytes']:11.0f} {bandwidth:10.0f}%", flush=True)
        base = rows.get("scipy")
        if base and "error" not in base:
            for method in ("splitting", "fitted", "implicit"):
                if method in rows and "error" not in rows[method]:
                    print(f"{'':>14} {method} / scipy node-steps per second: "
                          f"{rows[method]['node_steps'] / base['node_steps']:.1f}×")


if __name__ == "__main__":
    main()
