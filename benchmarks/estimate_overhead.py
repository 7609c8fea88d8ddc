"""What the error estimate costs: the catalogue's default solves with and without it, three
hold-out corpus members in 3-D whose costs are sampled between the nodes (the estimate's S,
docs/accuracy.rst), and three stationary members (first exit, average cost) whose estimate
carries the generator's truncation error along paths.

In-process, after a warm-up, the shortest of five solves each way, and their ratio
(docs/accuracy.rst, "Measured").

    python benchmarks/estimate_overhead.py
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import gridlbc
from gridlbc.studies import problems as P

sys.path.insert(0, str(Path(__file__).resolve().parent / "holdout"))
from corpus import BY_NAME

CASES = {
    "swing-up 256²": lambda: P.swingup_problem(),
    "mild pendulum 128²": lambda: P.mild_pendulum_problem(),
    "steep swing-up 201²": lambda: P.steep_swingup_problem(),
    "coordination 81²": lambda: P.coordination_problem(),
    "rotor 101²": lambda: P.rotor_problem(),
    "point mass h = 0.1": lambda: P.pointmass_problem(0.1),
    "obstacle": lambda: P.obstacle_problem(),
    "gymnast 31⁴": lambda: P.gymnast_problem(31),
    "toll strip 61³": BY_NAME["toll_strip"].build,
    "goal in a cell 41³": BY_NAME["goal_in_cell"].build,
    "tumbling body 61³": BY_NAME["tumbling_body"].build,
    "dock (first exit) 201²": BY_NAME["dock"].build,
    "cold flow exit 81²": BY_NAME["cold_flow_exit"].build,
    "cold OU average 161²": BY_NAME["cold_ou_average"].build,
}


def _shortest(problem, repeats: int, **options) -> float:
    walls = []
    for _ in range(repeats):
        started = time.perf_counter()
        gridlbc.solve(problem, progress=False, **options)
        walls.append(time.perf_counter() - started)
    return min(walls)


def main(repeats: int = 5) -> None:
    warnings.simplefilter("ignore", gridlbc.GridlbcWarning)
    print(f"{'problem':<22}{'without':>10}{'with':>10}{'ratio':>8}")
    for name, build in CASES.items():
        problem = build()
        _shortest(problem, 1)  # compile and warm the caches
        without = _shortest(problem, repeats, error_estimate=False)
        with_estimate = _shortest(problem, repeats)
        print(f"{name:<22}{without:>9.3f}s{with_estimate:>9.3f}s{with_estimate / without:>8.2f}")


if __name__ == "__main__":
    main()
