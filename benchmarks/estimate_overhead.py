"""What the error estimate costs: the catalogue's default solves with and without it.

In-process, after a warm-up, the shortest of five alternating solves each way, and their ratio.

    python benchmarks/estimate_overhead.py
"""

import time
import warnings

import gridlbc as g
from gridlbc.studies import problems as P

warnings.simplefilter("ignore")
cases = [
    ("swingup 256", P.swingup_problem()),
    ("mild 128", P.mild_pendulum_problem()),
    ("steep 201 λ=1", P.steep_swingup_problem()),
    ("coordination 81", P.coordination_problem()),
    ("rotor 101", P.rotor_problem()),
    ("pointmass h=0.1", P.pointmass_problem(0.1)),
    ("obstacle", P.obstacle_problem()),
]
for name, pb in cases:
    g.solve(pb)
    g.solve(pb, error_estimate=False)
    a = []
    b = []
    for _ in range(5):
        t = time.perf_counter()
        g.solve(pb, error_estimate=False)
        b.append(time.perf_counter() - t)
        t = time.perf_counter()
        g.solve(pb)
        a.append(time.perf_counter() - t)
    print(
        f"{name:18s} without {min(b):.3f}s with {min(a):.3f}s ratio {min(a) / min(b):.2f}",
        flush=True,
    )
