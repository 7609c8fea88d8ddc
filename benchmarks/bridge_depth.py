"""What halving the Brownian bridge until a crossing is implausible costs and changes, against the
six halvings it stopped at before (docs page ``first_exit``, "The rule is exact for a flat
boundary").

Two first exits of a point mass (noise on the velocity only), certified with the passive policy
(u = 0: v* is the passive chain's −λ log E[exp(−(∫q + g_E)/λ)]) at Δt = 0.004, 2000 paths per
state, in the same process at both depths (``gridlbc.simulate.BRIDGE_LEVELS``): a round ball of
radius 0.4 (its curvature is resolved by six halvings: the same v*, the same time) and a thin
ellipse 0.027 × 0.2 beside a ball (radius of curvature 0.003 at its tips against a velocity noise
of 0.63 per step: six halvings certified far too low). Prints v*, its standard error and the
seconds of each, and the time ratio.

    python benchmarks/bridge_depth.py
"""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np

import gridlbc as g

SIMULATE = sys.modules["gridlbc.simulate"]  # the module (gridlbc.simulate is the function)


def first_exit(speed: float, exit, **options) -> g.Problem:
    """A point mass on [−2, 2] × [−speed, speed] (41² nodes), q = 1, ending on ``exit`` at no
    cost; ``options`` go to :class:`gridlbc.Problem` (temperature, control cost)."""
    grid = g.Grid([g.Axis(-2.0, 2.0, 41), g.Axis(-speed, speed, 41)])
    return g.Problem(
        g.systems.PointMass(), grid, None, state_cost=1.0, exit=exit, exit_cost=0.0, **options
    )


def problems():
    ball = first_exit(3.0, g.regions.Ball([1.0, 0.0], 0.4), temperature=2.0)
    thin = first_exit(
        4.0,
        g.regions.Ball([0.0, 1.5], [0.027, 0.2]) | g.regions.Ball([-1.0, 0.0], 0.3),
        control_cost=0.01,
        temperature=1.0,
    )
    return {
        "round ball r 0.4": (ball, [[0.58, 0.05], [-1.0, 1.0]]),
        "thin ellipse 0.027 x 0.2": (thin, [[0.025, 0.9], [0.5, -1.0]]),
    }


def certified(problem, x0, levels: int):
    SIMULATE.BRIDGE_LEVELS = levels
    zero = lambda x, t: np.zeros((len(x), 1))  # noqa: E731
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = g.certify(problem, zero, x0, 2000, dt=0.004, seed=1, max_time=20.0, progress=False)
    return c.optimal_value, c.optimal_value_se, time.perf_counter() - start


def main() -> None:
    deep = SIMULATE.BRIDGE_LEVELS
    certified(*next(iter(problems().values())), 6)  # the kernels loaded before anything is timed
    print(f"{'exit set':26} {'depth':>5} {'v* (state 1, state 2)':>26} {'SE':>16} {'s':>6}")
    for name, (problem, x0) in problems().items():
        seconds = {}
        for levels in (6, deep):
            v, se, seconds[levels] = certified(problem, x0, levels)
            values = ", ".join(f"{a:.4f}" for a in v)
            errors = ", ".join(f"{a:.4f}" for a in se)
            print(f"{name:26} {levels:5d} {values:>26} {errors:>16} {seconds[levels]:6.1f}")
        print(f"{'':26} time ratio {seconds[deep] / seconds[6]:.2f}")
    SIMULATE.BRIDGE_LEVELS = deep


if __name__ == "__main__":
    main()
