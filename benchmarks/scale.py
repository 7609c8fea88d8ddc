"""Speed and memory of the solvers on large grids, against a plain scipy baseline.

Cases (T = 3 s, λ = 1): the pendulum swing-up (θ periodic × ω ∈ [−10, 10], g = xᵀdiag(10, ½)x) on
n × (n+1) grids and the gymnast (:func:`gridlbc.studies.gymnast.gymnast_problem`, box ±16 × ±9) on n⁴
grids. Each case runs in its own subprocess so that its peak RSS (VmHWM) is its own. Per case
and method: the solve's setup (feet, diffusion factors, terminal data), its stepping and the
wall time of the whole call (setup, stepping and the resolution check; numba kernels are
cached on disk and warmed up by a tiny solve first), node-steps per second (stepping only),
iterations per step, peak RSS, and the fraction of the memory bandwidth the stepping streams:
a byte count per node-step from the arrays each pass reads and writes, divided by the bandwidth
that the same subprocess measures just after the solve (the faster of a numba triad
a = b + s·c and a copy, on all threads, over arrays of at least twice the last-level cache).

For the plain splitting the subprocess also times each pass of a step on its own (the two
half-step diffusions, the drift's gather, the float32 store of a slice) with its bytes per node
and share of that bandwidth, and the same gather with every foot at its own node (Δt → 0): the
gather's time with perfectly sequential vertices, the bound its access pattern allows. For the
fitted default it times the fitted drift and the whole-step fitted diffusion, whose cost is
arithmetic (a Gaussian integrated against each cell near a node), far below the bandwidth. A pass is
timed by repeating it on the same arrays, so where its bytes fit in the last-level cache it runs
from that cache and can exceed the memory bandwidth: such passes are marked "in cache".

Methods: ``splitting`` (the plain operator, ``fitting=None``: compact feet, float32 slices),
``fitted`` (the default, ``fitting="terminal"``: drift and diffusion fitted to the terminal cost,
a single cost stepped in the log domain), ``implicit`` (Gauss–Seidel sweeps) and
the plain-scipy baseline (scipy splu where the grid is 2D, else scipy BiCGSTAB with a Jacobi
preconditioner). Slow methods run fewer steps (--baseline-steps) and their node-steps per second
is extrapolated to the full run: marked ``*`` in the table; the ratios to scipy are printed both
per node-step and for the whole solve including setup. The gymnast's accuracy per second
(rollout cost against solve time, per grid, method and Δt) is ``benchmarks/gymnast.py``.

    python benchmarks/scale.py                          # the full table (≈ 10 min on 2 cores)
    python benchmarks/scale.py --pendulum 201 --acrobot 21 --steps 300
    python benchmarks/scale.py --pendulum --acrobot 31 --steps 50 --layout-grid 0
    python benchmarks/scale.py --pendulum --acrobot 51 --methods splitting --layout-grid 0
"""

from __future__ import annotations

import argparse
import glob
import json
import math
import os
import resource
import subprocess
import sys
import time

import numpy as np

import gridlbc
from gridlbc import Problem
from gridlbc._numba import jit_parallel, prange, work_blocks
from gridlbc.schemes.splitting import SplittingStep, feet_bytes_per_node
from gridlbc.storage import store_kernel
from gridlbc.studies.problems import gymnast_problem, swingup_problem

METHODS = ("splitting", "fitted", "implicit", "scipy")


def problem_for(system: str, n: int) -> Problem:
    return swingup_problem(n) if system == "pendulum" else gymnast_problem(n)


def bytes_per_node_step(problem: Problem, method: str, iterations: float, store: int) -> float:
    """Bytes streamed per node and step (a lower bound: gathers counted once)."""
    d = problem.grid.ndim
    noise_axes = 1  # both systems: noise on the last momentum only
    if method == "splitting":
        # feet + read z + write z*, two half-step tridiagonal read/writes (before and after the
        # drift), renormalised store (read z, write).
        return feet_bytes_per_node(d, "compact") + 16 + 2 * 16 * noise_axes + (8 + store)
    if method == "fitted":
        # a single cost fitted to itself runs in the log domain: feet + read log z + write the
        # drifted log z, one whole-step fitted diffusion per noise axis (read, write: the half
        # diffusions of neighbouring steps are merged), the store (read, write).
        return feet_bytes_per_node(d, "compact") + 16 + 16 * noise_axes + (8 + store)
    if method == "implicit":
        # per sweep: off-diagonal CSR (value 8 + column 4 per entry, 2d entries), row pointer,
        # inverse diagonal, b and x (read and written).
        return iterations * (2 * d * 12 + 8 + 8 + 8 + 16) + (8 + store)
    return float("nan")


@jit_parallel
def _triad(a, b, c, s):
    for i in prange(a.size):
        a[i] = b[i] + s * c[i]


@jit_parallel
def _copy(a, b):
    for i in prange(a.size):
        a[i] = b[i]


def last_level_cache_bytes() -> int:
    """Size of the largest CPU cache (Linux sysfs; 0 where it cannot be read)."""
    sizes = []
    for index in glob.glob("/sys/devices/system/cpu/cpu0/cache/index*/size"):
        with open(index) as f:
            text = f.read().strip()
        units = {"K": 2**10, "M": 2**20, "G": 2**30}
        sizes.append(int(text[:-1]) * units[text[-1]] if text[-1] in units else int(text))
    return max(sizes, default=0)


def measure_bandwidth(repeats: int = 5) -> float:
    """Bytes per second of the faster of a triad (24 B per element) and a copy (16 B), the best
    of ``repeats`` runs each over arrays written once before (no first-write cost), each array
    at least twice the last-level cache (and 128 MiB) so that memory, not the cache, is timed."""
    size = max(1 << 24, 2 * last_level_cache_bytes() // 8)
    a, b, c = np.ones(size), np.ones(size), np.ones(size)
    best = 0.0
    for kernel, args, nbytes in ((_triad, (a, b, c, 2.0), 24), (_copy, (a, b), 16)):
        kernel(*args)
        for _ in range(repeats):
            started = time.perf_counter()
            kernel(*args)
            best = max(best, nbytes * size / (time.perf_counter() - started))
    return best


def _best_time(function, repeats: int) -> float:
    """The least wall time of ``repeats`` calls (the machine is shared: the least is the least
    disturbed)."""
    best = math.inf
    for _ in range(repeats):
        started = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - started)
    return best


def pass_profile(problem: Problem, dt: float, repeats: int = 5) -> dict:
    """Seconds per pass of one plain splitting step, K = 1, and the bytes per node each streams:
    the half-step diffusion (each noise axis reads and writes z), the drift's gather (the feet,
    z read once, the result written), the same gather with the feet at the nodes (Δt → 0), and
    the float32 store of a slice (z read, the slice written)."""
    grid = problem.grid
    step = SplittingStep(problem, dt)
    at_nodes = SplittingStep(problem, 1e-12 * dt)
    z = np.exp(-problem.terminal_values()[None, :] / problem.temperature)
    out, scale = np.empty_like(z), np.ones(1)
    slices = np.empty((1, 3, grid.size), dtype=np.float32)
    blocks = np.zeros(work_blocks(grid.size), dtype=np.int64)
    slices[:] = 0.0  # written once: the store is timed without the first-write cost
    step(z.copy(), out, scale)
    gather = feet_bytes_per_node(grid.ndim, step.layout) + 16
    return {
        "diffusion": (
            _best_time(lambda: step._half_diffusion(z, None), repeats),
            16 * len(step.noise),
        ),
        "gather": (_best_time(lambda: step.drift(z, out, scale), repeats), gather),
        "gather at nodes": (_best_time(lambda: at_nodes.drift(z, out, scale), repeats), gather),
        "store": (_best_time(lambda: store_kernel(z, scale, slices[:, 1], blocks), repeats), 12),
    }


def fitted_pass_profile(problem: Problem, dt: float, repeats: int = 3) -> dict:
    """Seconds per pass of one step of the default (fitted, log-domain) solve, and the bytes per
    node each streams: the fitted drift (the feet and log z read, the drifted log z written) and
    one whole-step fitted diffusion (log z read and written per noise axis), on log z of the
    terminal cost. The diffusion integrates a Gaussian against every cell within e^{−20} of a
    node's peak, so its time is arithmetic (erfcx and exp per cell), not memory traffic."""
    grid = problem.grid
    step = SplittingStep(problem, dt)
    ell = -problem.terminal_values()[None, :] / problem.temperature
    ell -= ell.max()
    out, spares = np.empty_like(ell), (np.empty_like(ell), np.empty_like(ell))
    step.log_drift(ell.copy(), out)  # records the stencil places, as a solve's first step does
    drift = feet_bytes_per_node(grid.ndim, step.layout) + 16
    return {
        "fitted drift": (_best_time(lambda: step.log_drift(ell, out), repeats), drift),
        "fitted diffusion": (
            _best_time(lambda: step.log_diffusion(ell, spares, full=True), repeats),
            16 * len(step.noise),
        ),
    }


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
        options = {
            "method": "splitting",
            "dtype": "float32",
            "fitting": "terminal" if method == "fitted" else None,
        }
    # warm the numba caches and the page allocator on a tiny grid of the same kind
    small = problem_for(system, 11 if system == "acrobot" else 21)
    gridlbc.solve(small.replace(horizon=2 * dt), dt=dt, **options)
    started = time.perf_counter()
    solution = gridlbc.solve(problem, dt=dt, **options)
    wall = time.perf_counter() - started
    rss = peak_rss()  # before the bandwidth's arrays raise the high-water mark
    bandwidth = measure_bandwidth()
    diag = solution.diagnostics
    stepping = diag.wall_time - diag.setup_time
    iterations = float(np.mean(diag.iterations)) if diag.iterations else 0.0
    return {
        "system": system,
        "n": n,
        "nodes": problem.grid.size,
        "method": method,
        "solver": options.get("linear_solver", "splitting"),
        "steps": steps,
        "wall": wall,
        "setup": diag.setup_time,
        "node_steps": problem.grid.size * steps / stepping,
        "iterations": iterations,
        "bytes": (
            float("nan")
            if options.get("linear_solver") == "direct"
            else bytes_per_node_step(
                problem, "implicit" if method == "scipy" else method, iterations, 4
            )
        ),
        "peak_rss": rss,
        "bandwidth": bandwidth,
        "passes": (
            pass_profile(problem, dt)
            if method == "splitting"
            else fitted_pass_profile(problem, dt)
            if method == "fitted"
            else {}
        ),
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
    from gridlbc.schemes.splitting import FEET_LAYOUTS

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
        print(
            f"  feet layout {layout:>7} on {n}^4: {1e3 * per_step:6.1f} ms/step, "
            f"{feet_bytes_per_node(4, layout)} B/node of feet, "
            f"{100 * streamed / per_step / bandwidth:4.0f}% of bandwidth",
            flush=True,
        )


def in_subprocess(system: str, n: int, method: str, steps: int, full_steps: int) -> dict:
    out = subprocess.run(
        [sys.executable, __file__, "--case", system, str(n), method, str(steps), str(full_steps)],
        capture_output=True,
        text=True,
        check=False,
    )
    if out.returncode != 0:
        return {
            "system": system,
            "n": n,
            "method": method,
            "error": out.stderr.strip().splitlines()[-1],
        }
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pendulum", type=int, nargs="*", default=[201, 401, 801])
    parser.add_argument("--acrobot", type=int, nargs="*", default=[21, 31, 41, 51])
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument(
        "--baseline-steps",
        type=int,
        default=10,
        help="steps for the slow methods on 4D grids (extrapolated)",
    )
    parser.add_argument(
        "--implicit-max-nodes",
        type=int,
        default=3_000_000,
        help="skip the implicit and scipy methods above this many nodes",
    )
    parser.add_argument(
        "--layout-grid",
        type=int,
        default=41,
        help="n⁴ gymnast grid for the feet layout comparison (0: skip)",
    )
    parser.add_argument(
        "--methods",
        nargs="*",
        default=list(METHODS),
        choices=METHODS,
        help="methods to run (default: all)",
    )
    parser.add_argument("--case", nargs=5, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.case:
        system, n, method, steps, full_steps = args.case
        print(json.dumps(run_case(system, int(n), method, int(steps), int(full_steps))))
        return

    print(f"load average at start: {os.getloadavg()[0]:.2f} (2 cores shared: timings vary)")
    bandwidth, cache = measure_bandwidth(), last_level_cache_bytes()
    print(
        f"memory bandwidth (numba triad/copy, this process): {bandwidth / 1e9:.1f} GB/s; each "
        "case's percentages use the bandwidth its own subprocess measured just after it; "
        f"last-level cache {cache / 2**20:.0f} MiB"
    )
    if args.layout_grid:
        layout_comparison(args.layout_grid, 20, bandwidth)
    print(
        f"{'case':>14} {'nodes':>9} {'method':>9} {'steps':>6} {'setup s':>8} {'step ms':>8} "
        f"{'wall s':>8} {'Mnode-steps/s':>14} {'it/step':>7} {'peak RSS GiB':>12} "
        f"{'B/node-step':>11} {'GB/s':>5} {'% bandwidth':>11}"
    )
    cases = [("pendulum", n) for n in args.pendulum] + [("acrobot", n) for n in args.acrobot]
    for system, n in cases:
        rows = {}
        nodes = n * (n + 1) if system == "pendulum" else n**4
        for method in args.methods:
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
            per_step = row["nodes"] / row["node_steps"]
            row["full_wall"] = row["wall"] + (args.steps - steps) * per_step  # whole call
            share = 100 * row["bytes"] * row["node_steps"] / row["bandwidth"]
            print(
                f"{system + ' ' + str(n):>14} {row['nodes']:9d} {method + mark:>9} "
                f"{args.steps:6d} {row['setup']:8.2f} {1e3 * per_step:8.1f} "
                f"{row['full_wall']:8.1f} {row['node_steps'] / 1e6:14.2f} "
                f"{row['iterations']:7.1f} {row['peak_rss'] / 2**30:12.2f} {row['bytes']:11.0f} "
                f"{row['bandwidth'] / 1e9:5.1f} {share:10.0f}%",
                flush=True,
            )
            for name, (seconds, per_node) in row["passes"].items():
                rate = per_node * row["nodes"] / seconds
                cached = " (in cache)" if per_node * row["nodes"] < cache else ""
                print(
                    f"{'':>14} pass {name:>15}: {1e3 * seconds:7.2f} ms, {per_node:3d} B/node, "
                    f"{rate / 1e9:5.1f} GB/s = {100 * rate / row['bandwidth']:3.0f}% of "
                    f"{row['bandwidth'] / 1e9:.1f} GB/s{cached}",
                    flush=True,
                )
        base = rows.get("scipy")
        if base and "error" not in base:
            for method in ("splitting", "fitted", "implicit"):
                if method in rows and "error" not in rows[method]:
                    print(
                        f"{'':>14} {method} / scipy: node-steps per second "
                        f"{rows[method]['node_steps'] / base['node_steps']:.1f}×, whole solve "
                        f"of {args.steps} steps including setup "
                        f"{base['full_wall'] / rows[method]['full_wall']:.1f}× "
                        f"({rows[method]['full_wall']:.1f} s against {base['full_wall']:.1f} s)"
                    )


if __name__ == "__main__":
    main()
