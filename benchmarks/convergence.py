"""Convergence of the z-space solvers and the value-space HJB solver, and the deterministic limit.

PointMass (mass 1, λ = 0.5, q = xᵀdiag(0.5, 0.05)x, g = (x−(1,0))ᵀdiag(2, 0.5)(x−(1,0)), T = 2, box
[−4, 4] × [−6, 6]): splitting, implicit and HJB against the exact Riccati solution, plus the z
solvers' Richardson extrapolation in z. Pendulum (θ periodic, ω ∈ [−8, 8], T = 1, λ = 1,
g = xᵀdiag(10, 0.5)x): splitting vs HJB, each against its own and the other's Richardson estimate
and against each other on the same grid. Errors at t = 0 on a lattice of states where v < min v + 5
(see gridlbc.studies.convergence). The Richardson estimates are the solvers' own extrapolations;
the truth for the pendulum is the certified optimum v*(x₀) (gridlbc.certify, importance sampling
on the SDE with the finest fitted solve's policy as proposal) from --start, against which each
solver's prediction and its policy's cost are tabulated (certified_study). Then the pendulum along
ω = 0 as λ → 0.

Writes figures/convergence.png and figures/temperature.png.

    python benchmarks/convergence.py [--spacings 4 8 16 32] [--sizes 64 128 256] [--out figures]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gridlbc.studies.convergence import (
    certified_study,
    pendulum_study,
    plot_convergence,
    plot_temperature,
    pointmass_study,
    temperature_study,
)
from gridlbc.studies.problems import pendulum_problem


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--spacings",
        type=int,
        nargs="+",
        default=[4, 8, 16, 32],
        help="PointMass grid spacings as 1/h (default: 4 8 16 32)",
    )
    parser.add_argument(
        "--sizes",
        type=int,
        nargs="+",
        default=[64, 128, 256],
        help="pendulum nodes per angle, doubling (default: 64 128 256)",
    )
    parser.add_argument(
        "--temperatures", type=float, nargs="+", default=[1.0, 0.3, 0.1, 0.03, 0.01]
    )
    parser.add_argument(
        "--temperature-grid",
        type=int,
        default=128,
        help="pendulum nodes per angle for the λ → 0 study (default: 128)",
    )
    parser.add_argument(
        "--start",
        type=float,
        nargs=2,
        default=[1.5, 0.0],
        metavar=("THETA", "OMEGA"),
        help="start state of the certified pendulum comparison (default 1.5 0)",
    )
    parser.add_argument(
        "--samples",
        type=int,
        default=400,
        help="samples of each solver's own certificate (default 400)",
    )
    parser.add_argument("--truth-samples", type=int, default=2000)
    parser.add_argument("--out", default="figures", help="folder for the figures")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    pointmass = pointmass_study(spacings=tuple(1.0 / k for k in args.spacings))
    print(f"PointMass vs Riccati ({pointmass.points} points, v < min v + {pointmass.band:g})")
    print(pointmass.format(), "\n", flush=True)
    pendulum = pendulum_study(sizes=tuple(args.sizes))
    print(f"Pendulum ({pendulum.points} points, v < min v + {pendulum.band:g})")
    print(pendulum.format(), "\n", flush=True)
    plot_convergence([pointmass, pendulum], out / "convergence.png")
    certified = certified_study(
        pendulum_problem,
        args.sizes,
        args.start,
        (("splitting", None), ("hjb", None), ("fitted", None)),
        samples=args.samples,
        truth_samples=args.truth_samples,
        rollout_dt=0.002,
    )
    print("Pendulum against the certified optimum (rollouts at Δt = 0.002)")
    print(certified.format(), "\n", flush=True)

    study = temperature_study(temperatures=tuple(args.temperatures), n=args.temperature_grid)
    print(
        f"Pendulum as λ → 0 ({args.temperature_grid} nodes per angle); z underflows in float64 "
        "where (v − min v)/λ > 744"
    )
    print(study.format())
    plot_temperature(study, out / "temperature.png")
    print(f"\nwrote {out / 'convergence.png'} and {out / 'temperature.png'}")


if __name__ == "__main__":
    main()
