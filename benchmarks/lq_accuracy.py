"""Accuracy and speed on the PointMass LQ problem, against the exact Riccati solution.

Problem (issue 2): mass 1, λ = 0.5, q = xᵀdiag(0.5, 0.05)x, g = (x−(1,0))ᵀdiag(2, 0.5)(x−(1,0)),
T = 2, box [−4, 4] × [−6, 6]. Errors at t = 0 over the nodes where v < min v + 5 inside
|position| < 2, |velocity| < 3 (away from the box, where the state constraint changes the problem).

Baseline: a plain scipy implementation of the first-order implicit upwind scheme (sparse
assembly with Kronecker products, one ``splu``, 200 backward-Euler steps), written here without
the library so that it is what a user would write by hand. Ratios are measured in the same run.

    python benchmarks/lq_accuracy.py [--sizes 101 201 401 801] [--no-baseline]
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.reference import lq_solution
from gridlbc.systems import PointMass

LAM, T = 0.5, 2.0


def problem(n: int) -> Problem:
    grid = Grid([Axis(-4.0, 4.0, n), Axis(-6.0, 6.0, n)])
    return Problem(
        PointMass(),
        grid,
        T,
        Quadratic([1.0, 0.0], [2.0, 0.5]),
        state_cost=Quadratic([0.0, 0.0], [0.5, 0.05]),
        temperature=LAM,
    )


def region(prob: Problem, exact) -> np.ndarray:
    x = prob.grid.nodes()
    inside = (np.abs(x[:, 0]) < 2) & (np.abs(x[:, 1]) < 3)
    v = exact.value(x, 0.0)
    return inside & (v < v[inside].min() + 5)


def scipy_baseline(n: int, steps: int = 200) -> np.ndarray:
    """Plain scipy: upwind drift, central diffusion, reflecting box, backward Euler, splu."""
    pos = np.linspace(-4, 4, n)
    vel = np.linspace(-6, 6, n)
    h0, h1 = pos[1] - pos[0], vel[1] - vel[0]
    dt = T / steps
    P, V = np.meshgrid(pos, vel, indexing="ij")
    ones = np.ones(n)
    fwd = sp.diags([-ones, ones[:-1]], [0, 1], format="lil")  # z_{i+1} − z_i
    bwd = sp.diags([ones, -ones[:-1]], [0, -1], format="lil")  # z_i − z_{i−1}
    fwd[-1, -1] = 0.0  # no jump out of the box
    bwd[0, 0] = 0.0
    second = (fwd - bwd).tocsr()  # z_{i+1} − 2z_i + z_{i−1} with reflecting ends
    eye = sp.identity(n)
    vp, vm = np.maximum(V.ravel(), 0), np.maximum(-V.ravel(), 0)
    L = (
        sp.diags(vp / h0) @ sp.kron(fwd, eye)
        - sp.diags(vm / h0) @ sp.kron(bwd, eye)
        + (0.5 * LAM / h1**2) * sp.kron(eye, second)
    )
    q = 0.5 * P.ravel() ** 2 + 0.05 * V.ravel() ** 2
    A = (sp.identity(n * n) + sp.diags(dt * q / LAM) - dt * L).tocsc()
    lu = spla.splu(A)
    g = 2 * (P.ravel() - 1) ** 2 + 0.5 * V.ravel() ** 2
    z = np.exp(-(g - g.min()) / LAM)
    log_scale = -g.min() / LAM
    for _ in range(steps):
        z = lu.solve(z)
        m = z.max()
        z /= m
        log_scale += np.log(m)
    return -LAM * (np.log(z) + log_scale)


def measure(run):
    tracemalloc.start()
    started = time.perf_counter()
    out = run()
    wall = time.perf_counter() - started
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return out, wall, peak


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[101, 201, 401, 801])
    parser.add_argument("--no-baseline", action="store_true")
    parser.add_argument(
        "--max-implicit",
        type=int,
        default=401,
        help="largest n for the implicit scheme (its Courant-1 default is slow)",
    )
    args = parser.parse_args(argv)

    gridlbc.solve(problem(21))  # compile the kernels outside the timings
    gridlbc.solve(problem(21), method="implicit")
    gridlbc.solve(problem(21), fitting=None)
    header = (
        f"{'method':<17}{'grid':>8}{'dt':>9}{'steps':>7}{'time s':>9}{'node-steps/s':>14}"
        f"{'peak MB':>9}{'max|Δv|':>9}{'mean|Δv|':>10}{'max|Δu|':>9}"
    )
    print(header)
    print("-" * len(header))
    rows = []
    for n in args.sizes:
        prob = problem(n)
        exact = lq_solution(prob)
        mask = region(prob, exact)
        x = prob.grid.nodes()[mask]
        v_exact, u_exact = exact.value(x, 0.0), exact.policy(x, 0.0)
        # The plain splitting (fitting=None) at its default Courant number (6, tuned for fast
        # drift) and at 2, which suits this slow-drift problem better (its O(Δt) splitting error
        # dominates), and the default, fitted to the terminal cost: exact for quadratic log z,
        # so on this LQ problem only its time step errs.
        runs = [
            ("plain", lambda prob=prob: gridlbc.solve(prob, fitting=None)),
            ("plain C=2", lambda prob=prob: gridlbc.solve(prob, fitting=None, courant=2.0)),
            ("fitted (default)", lambda prob=prob: gridlbc.solve(prob)),
            ("implicit", lambda prob=prob: gridlbc.solve(prob, method="implicit")),
        ][: 4 if n <= args.max_implicit else 3]
        if not args.no_baseline and n <= 401:
            runs.append(("scipy baseline", lambda n=n: scipy_baseline(n)))
        for name, run in runs:
            out, wall, peak = measure(run)
            if isinstance(out, np.ndarray):
                v, u, dt, steps = out[mask], None, T / 200, 200
            else:
                v, u = out.value(x, 0.0), out.policy(x, 0.0)
                dt, steps = out.diagnostics.dt, out.diagnostics.steps
            dv = np.abs(v - v_exact)
            du = "-" if u is None else f"{np.abs(u - u_exact).max():.3f}"
            rate = n * n * steps / wall
            rows.append((name, n, wall, dv.max(), dv.mean()))
            print(
                f"{name:<17}{f'{n}²':>8}{dt:>9.4f}{steps:>7}{wall:>9.2f}{rate:>14.3g}"
                f"{peak / 2**20:>9.0f}{dv.max():>9.3f}{dv.mean():>10.4f}{du:>9}",
                flush=True,
            )
    base = [r for r in rows if r[0] == "scipy baseline"]
    if base:
        b = base[-1]
        print(
            f"\nEqual-accuracy speed-up against the scipy baseline at {b[1]}² "
            f"(max|Δv| = {b[3]:.3f}, mean = {b[4]:.4f}, {b[2]:.2f} s):"
        )
        for name in ("plain", "plain C=2", "fitted (default)", "implicit"):
            good = [r for r in rows if r[0] == name and r[3] <= b[3] * 1.05 and r[4] <= b[4] * 1.05]
            if good:
                r = min(good, key=lambda r: r[2])
                print(
                    f"  {name:<16} at {r[1]}²: {r[2]:.2f} s → {b[2] / r[2]:.1f}× faster "
                    f"(max|Δv| = {r[3]:.3f}, mean = {r[4]:.4f})"
                )
            else:
                print(f"  {name:<16}: no size reached the baseline's accuracy")


if __name__ == "__main__":
    main()
