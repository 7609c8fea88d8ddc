"""First-exit problems nobody tuned for: does the default stationary solve's error estimate
cover its actual error, and does it warn where it should? (docs/first_exit.rst, "Hold-outs").

Each problem is written as a new user would write it with the public API. The truth at each
state is the certificate with the grid policy as proposal, paths stopped on entering the exit
set (with the bridge crossing), at Δt and 2Δt with the O(Δt) step bias extrapolated away
(``richardson=True``); its standard error is printed with it. The table gives, per state: the
prediction, its error estimate, the certified value ± SE, the actual error, the ratio of the
estimate to the actual error, whether the default solve warned, and the seconds of the solve.

    python benchmarks/first_exit_holdout.py [--samples 2000] [--dt 0.005]
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem
from gridlbc.regions import Ball, Box
from gridlbc.systems import LinearSystem, Pendulum


def bays() -> Problem:
    """A point mass parking in one of three bays (no noise on position: upwind there)."""
    from gridlbc.studies.problems import bays_problem

    return bays_problem(161)


def upright() -> Problem:
    """Swing a pendulum up until it is near the top and slow, as fast as possible (q = 1)."""
    grid = Grid([Axis(-math.pi, math.pi, 201, periodic=True), Axis(-8.0, 8.0, 201)])
    return Problem(
        Pendulum(),
        grid,
        None,
        state_cost=lambda x: np.ones(len(x)),
        temperature=0.5,
        exit=Ball([0.0, 0.0], [0.3, 1.0]),
    )


def door() -> Problem:
    """Leave a room through a narrow door in its right wall, at a low temperature."""
    grid = Grid([Axis(-2.0, 2.0, 161), Axis(-2.0, 2.0, 161)])
    return Problem(
        LinearSystem(np.zeros((2, 2)), np.eye(2)),
        grid,
        None,
        state_cost=lambda x: np.ones(len(x)),
        temperature=0.2,
        exit=Box([1.9, -0.2], [np.inf, 0.2]),
    )


def chain3() -> Problem:
    """A 3-D chain x₀ ← x₁ ← x₂ ← u, noisy on every axis, reaching a ball."""
    grid = Grid([Axis(-2.0, 2.0, 41) for _ in range(3)])
    return Problem(
        LinearSystem(np.diag([0.5, 0.5], 1), np.eye(3)),
        grid,
        None,
        state_cost=lambda x: 1.0 + 0.25 * np.sum(x**2, axis=1),
        control_cost=[1.0, 2.0, 3.0],
        temperature=0.5,
        exit=Ball([1.0, 0.0, 0.0], 0.6),
    )


PROBLEMS = {
    "bays (point mass)": (bays, [[-0.6, 1.2], [1.5, -1.0]]),
    "upright (pendulum)": (upright, [[math.pi - 0.1, 0.0], [1.5, 2.0]]),
    "door (λ = 0.2)": (door, [[0.0, 0.0], [-1.5, 1.5]]),
    "chain 3-D": (chain3, [[-1.0, 0.0, 0.0], [0.0, 1.0, -1.0]]),
}


def main(samples: int = 2000, dt: float = 0.005, seed: int = 0) -> None:
    print(
        f"{'problem':<20}{'state':<20}{'predicted':>10}{'estimate':>10}{'certified':>18}"
        f"{'actual':>9}{'est/act':>8}{'warned':>8}{'solve s':>8}",
        flush=True,
    )
    for name, (build, states) in PROBLEMS.items():
        problem = build()
        started = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", gridlbc.ResolutionWarning)
            solution = gridlbc.solve(problem)
        wall = time.perf_counter() - started
        warned = any(issubclass(w.category, gridlbc.ResolutionWarning) for w in caught)
        X = np.asarray(states, dtype=float)
        certificate = gridlbc.certify(
            problem,
            solution.policy,
            X,
            n_samples=samples,
            dt=dt,
            seed=seed,
            max_time=30.0,
            richardson=True,
            progress=False,
        )
        v, e = solution.value(X), solution.error_estimate(X)
        truth, se = certificate.extrapolated_value, certificate.extrapolated_value_se
        for i, x in enumerate(X):
            actual = abs(v[i] - truth[i])
            state = np.array2string(x, precision=2, separator=",")
            print(
                f"{name:<20}{state:<20}{v[i]:>10.4f}{e[i]:>10.4f}"
                f"{truth[i]:>11.4f} ± {se[i]:.4f}{actual:>9.4f}{e[i] / actual:>8.2f}"
                f"{'yes' if warned else 'no':>8}{wall:>8.1f}",
                flush=True,
            )


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=2000)
    parser.add_argument("--dt", type=float, default=0.005)
    args = parser.parse_args()
    main(args.samples, args.dt)
