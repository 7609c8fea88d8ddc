"""The embedded error estimate on the catalogue: is it at least the error, and what does it cost?

For each problem, the default solve's value at its states is compared with a reference: the
exact Riccati value for the linear-quadratic point mass, otherwise a solve on the grid refined
``--refine`` times (h / 2^k) with Δt / 2^k (``error_estimate=False``), whose own error is about
2^−k of the default's for a first-order scheme. Printed per problem and state: the predicted
value, the reference, the actual relative error, the estimated one
(``solution.error_estimate(x) / max(|v|, λ)``), whether the estimate covers the error
(ê ≥ e / 2, docs/accuracy.rst) and whether the default solve warned. Per problem: the time of the default
solve with and without the estimate, measured in the same run, and their ratio.

    python benchmarks/error_estimate.py [--refine 2] [--only pointmass swingup ...]
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

import gridlbc
from gridlbc import accuracy
from gridlbc.reference import lq_solution
from gridlbc.studies import problems as P


def _catalogue():
    """(name, problem, states, exact) for each member; ``exact`` a reference or None."""
    point_mass = P.pointmass_problem(0.1)
    yield "pointmass", point_mass, np.array([[1.0, -0.5], [-1.5, 1.0], [0.5, 1.5]]), lq_solution
    yield "swingup", P.swingup_problem(), np.array([P.SWINGUP_START, [0.5, 1.0], [-2.0, 3.0]]), None
    yield "mild", P.mild_pendulum_problem(), np.asarray(P.MILD_STATES), None
    for lam in (1.0, 0.1, 0.01):
        states = np.array([P.STEEP_START, [1.0, 0.0], [0.0, 2.0]])
        yield f"steep λ={lam:g}", P.steep_swingup_problem(temperature=lam), states, None
    yield "coordination", P.coordination_problem(), np.array([[0.0, 0.0], [1.0, 1.0]]), None
    yield "rotor", P.rotor_problem(), np.array([P.ROTOR_START, [1.0, 0.0]]), None


def _timed(problem, repeats=2, **options):
    """The solution, the shortest wall time of ``repeats`` solves (the first may compile), and
    whether the error estimate warned."""
    walls = []
    for _ in range(repeats):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", gridlbc.ResolutionWarning)
            started = time.perf_counter()
            solution = gridlbc.solve(problem, **options)
            walls.append(time.perf_counter() - started)
    warned = any("estimated error" in str(w.message) for w in caught)
    return solution, min(walls), warned


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--refine", type=int, default=2, help="reference grid h / 2^k")
    parser.add_argument("--only", nargs="*", help="names (prefixes) of members to run")
    args = parser.parse_args(argv)
    print(
        f"{'problem':<14}{'state':>20}{'predicted':>11}{'reference':>11}{'error':>9}"
        f"{'estimate':>10}{'covered':>9}{'warned':>8}"
    )
    covered_all = []
    for name, problem, states, exact in _catalogue():
        if args.only and not any(name.startswith(o) for o in args.only):
            continue
        _, plain_wall, _ = _timed(problem, error_estimate=False)
        solution, wall, warned = _timed(problem)
        if exact is not None:
            truth = exact(problem).value(states, 0.0)
        else:
            fine = problem
            for _ in range(args.refine):
                fine = fine.replace(grid=accuracy.refined_grid(fine.grid))
            dt = solution.diagnostics.dt / 2**args.refine
            truth = gridlbc.solve(fine, dt=dt, error_estimate=False).value(states, 0.0)
        v = solution.value(states, 0.0)
        error = accuracy.relative_error(np.abs(v - truth), v, problem.temperature)
        estimate = accuracy.relative_error(solution.error_estimate(states), v, problem.temperature)
        covered = estimate >= error / 2
        covered_all.extend(covered)
        for x, vi, ti, e, est, c in zip(states, v, truth, error, estimate, covered):
            where = np.array2string(np.asarray(x), precision=2, separator=",")
            print(
                f"{name:<14}{where:>20}{vi:>11.4f}{ti:>11.4f}{e:>9.2%}{est:>10.2%}"
                f"{'yes' if c else 'NO':>9}{'yes' if warned else '':>8}"
            )
        print(
            f"{name:<14} solve {wall:.2f} s with the estimate, {plain_wall:.2f} s without "
            f"({wall / plain_wall:.2f}×), order {solution.embedded.order:.2f} (observed {solution.embedded.observed_order:.2f})"
        )
    print(f"covered at {np.mean(covered_all):.0%} of {len(covered_all)} (problem, state) pairs")


if __name__ == "__main__":
    main()
