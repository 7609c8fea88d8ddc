"""Speed-up of one solve_many over K separate solves (one operator, K right-hand sides).

Pendulum swing-up grids (θ periodic, ω ∈ [−10, 10]), T = 3, λ = 1, dt = 0.02, K goals
θ_k spread over [−1, 1]. Checks on the way that each column equals its separate solve bit for bit
(the step is the same linear map). Usage:

    python benchmarks/solve_many.py [--grids 128 256] [--counts 1 2 4 8] [--repeat 2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import gridlbc as g
from gridlbc.systems import Pendulum


def _best_time(fn, repeat: int) -> tuple[float, object]:
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", type=int, nargs="+", default=[128, 256])
    parser.add_argument("--counts", type=int, nargs="+", default=[1, 2, 4, 8])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--dt", type=float, default=0.02)
    args = parser.parse_args(argv)

    print(
        f"{'grid':>9} {'K':>3} {'separate s':>11} {'solve_many s':>13} {'speed-up':>9} "
        f"{'max |Δ log z|':>14}"
    )
    for n in args.grids:
        grid = g.Grid([g.Axis(-np.pi, np.pi, n, periodic=True), g.Axis(-10, 10, n + 1)])
        problem = g.Problem(Pendulum(), grid, 3.0, g.Quadratic([0, 0], [10, 0.5]))
        g.solve(problem, dt=args.dt)  # compile and warm caches outside the timings
        for K in args.counts:
            costs = [g.Quadratic([c, 0], [10, 0.5]) for c in np.linspace(-1, 1, K)]
            t_sep, separate = _best_time(
                lambda p=problem, cs=costs: [
                    g.solve(p.replace(terminal_cost=c), dt=args.dt) for c in cs
                ],
                args.repeat,
            )
            t_many, many = _best_time(
                lambda p=problem, cs=costs: g.solve_many(p, cs, dt=args.dt), args.repeat
            )
            diff = max(
                np.max(np.abs(a.log_desirability_nodes(0) - b.log_desirability_nodes(0)))
                for a, b in zip(separate, many)
            )
            print(
                f"{n:>4}×{n + 1:<4} {K:>3} {t_sep:>11.2f} {t_many:>13.2f} "
                f"{t_sep / t_many:>8.2f}× {diff:>14.2e}"
            )


if __name__ == "__main__":
    main()
