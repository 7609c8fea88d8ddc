"""Numerical diffusion on a fast-drift problem: the pendulum swing-up, judged by the certified optimum.

Problem (issue 2): Pendulum(), T = 3, λ = 1, R = 1, g = xᵀdiag(10, 0.5)x, start (2.8, 0);
θ periodic on [−π, π) with n nodes, ω ∈ [−10, 10] with n + 1 nodes (so ω = 0 is a node).

First the truth: the certified optimum v*(x₀) of gridlbc.certify (importance sampling on the SDE,
exact for any proposal up to the rollout step), with the fitted solve at dt 0.02 on the largest
grid as the proposal. Then for each grid and scheme (``fitted``: the splitting scheme with its drift
fitted to the terminal cost, ``fitting="terminal"``): the solver's predicted cost
v(x₀, 0) = −λ log z(x₀, 0) and its error against v*, the wall time, and the certificate of its own
policy: the policy's cost J ± SE, the gap J − v* (the policy's suboptimality) and the effective
sample size of that certificate (near 100 % for a near-optimal policy). Numerical diffusion makes
the prediction too optimistic (it smears z, as if the noise were larger and more helpful than it
is). See gridlbc.studies.convergence.certified_study.

    python benchmarks/swingup_accuracy.py [--sizes 64 128 256 512] [--samples 400]
        [--figure figures/certified_convergence.png]
"""

from __future__ import annotations

import argparse

import gridlbc
from gridlbc.studies.convergence import certified_study
from gridlbc.studies.figures import plot_certified_convergence
from gridlbc.studies.problems import SWINGUP_START, swingup_problem

CONFIGS = [
    ("splitting", None),
    ("splitting", 0.02),
    ("fitted", None),
    ("implicit", 0.01),
    ("fitted", 0.02),
]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 512])
    parser.add_argument(
        "--samples",
        type=int,
        default=400,
        help="samples of each row's own certificate (default 400)",
    )
    parser.add_argument("--truth-samples", type=int, default=4000)
    parser.add_argument(
        "--rollout-dt",
        type=float,
        default=0.002,
        help="Euler–Maruyama step of the rollouts (default 0.002: at 0.01 the "
        "scheme's O(Δt) bias lowers this problem's costs by about 1)",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--figure",
        metavar="PNG",
        help="also plot the default-dt schemes "
        "(gridlbc.studies.figures.plot_certified_convergence)",
    )
    args = parser.parse_args(argv)

    for scheme in ("splitting", "fitted", "implicit"):  # compile outside the timings
        gridlbc.solve(
            swingup_problem(16),
            fitting="terminal" if scheme == "fitted" else None,
            method="implicit" if scheme == "implicit" else "splitting",
        )
    study = certified_study(
        swingup_problem,
        args.sizes,
        SWINGUP_START,
        CONFIGS,
        samples=args.samples,
        truth_samples=args.truth_samples,
        rollout_dt=args.rollout_dt,
        seed=args.seed,
    )
    print(study.format())
    if args.figure:
        fig = plot_certified_convergence(study, labels=["splitting", "fitted", "implicit dt 0.01"])
        fig.savefig(args.figure, dpi=100)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
