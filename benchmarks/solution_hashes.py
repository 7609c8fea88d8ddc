"""Digests of a set of solves covering every solver path, to show that a refactoring leaves the
solutions bitwise unchanged: run before and after, and compare the printed table.

    python benchmarks/solution_hashes.py

Paths: the fitted default (log domain) in 2-D and 4-D, the plain splitting, explicit fitting to a
cost (solve_many's shared reference), the implicit scheme, float32 storage with ``store_every``.
Each digest covers the stored slices, their log-scales, the times and, where present, the fitted
reference's log φ.
"""

from __future__ import annotations

import hashlib

import numpy as np

import gridlbc as g
from gridlbc.studies.problems import gymnast_problem
from gridlbc.systems import Pendulum, PointMass


def digest(solution) -> str:
    h = hashlib.sha256()
    for array in (solution.times, solution.slices, solution.log_scales):
        h.update(np.ascontiguousarray(array).tobytes())
    if solution.reference is not None:
        h.update(np.ascontiguousarray(solution.reference.log_slices).tobytes())
        h.update(np.ascontiguousarray(solution.reference.log_scales).tobytes())
    return h.hexdigest()[:16]


def cases():
    pendulum_grid = g.Grid([g.Axis(-np.pi, np.pi, 64, periodic=True), g.Axis(-8, 8, 65)])
    swing = g.Problem(
        Pendulum(),
        pendulum_grid,
        2.0,
        g.Quadratic([0, 0], [4, 0.5]),
        state_cost=g.Quadratic([0, 0], [1, 0.1]),
        temperature=0.1,
    )
    mass_grid = g.Grid([g.Axis(-3, 3, 41), g.Axis(-3, 3, 41)])
    mass = g.Problem(PointMass(), mass_grid, 1.0, g.Quadratic([1, 0], [4, 1]), temperature=0.5)
    goals = [g.Quadratic([c, 0], [4, 1]) for c in (-1.0, 1.0)]
    yield "pendulum fitted default", lambda: [g.solve(swing)]
    yield "pendulum plain", lambda: [g.solve(swing, fitting=None)]
    yield (
        "pendulum plain float32/5",
        lambda: [g.solve(swing, fitting=None, dtype="float32", store_every=5)],
    )
    yield "pointmass fitted pair", lambda: g.solve_many(mass, goals, fitting=goals[0])
    yield "pointmass terminal pair", lambda: g.solve_many(mass, goals, fitting="terminal")
    yield "pointmass implicit", lambda: [g.solve(mass, method="implicit")]
    yield "gymnast 15^4 fitted", lambda: [g.solve(gymnast_problem(15))]
    yield "gymnast 15^4 plain", lambda: [g.solve(gymnast_problem(15), fitting=None)]


def main():
    import warnings

    warnings.simplefilter("ignore")
    print(f"{'case':28s} digests")
    for name, run in cases():
        print(f"{name:28s} {' '.join(digest(s) for s in run())}")


if __name__ == "__main__":
    main()
