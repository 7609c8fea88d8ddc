"""The ``gridlbc`` command.

Each subcommand is a function ``_cmd_<name>(args)`` registered in :func:`build_parser`; user
mistakes (``ValueError``, ``TypeError``, ``FileNotFoundError``) end with a one-line message on
stderr and exit status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def _cmd_demo(args) -> int:
    from .demo import run_demo

    run_demo(Path(args.out), grid_size=args.grid, progress=not args.quiet)
    return 0


def _cmd_verify(args) -> int:
    """Exit status 0 when every check passes, 1 when one fails (the table says which)."""
    from .verify import run_verification

    report = run_verification(grid_size=args.grid, samples=args.samples, seed=args.seed,
                              quick=args.quick, progress=not args.quiet)
    print(report.table())
    if args.convergence:
        from .convergence import pendulum_study, pointmass_study

        spacings, sizes = ((1 / 4, 1 / 8, 1 / 16), (32, 64, 128)) if args.quick else \
            ((1 / 4, 1 / 8, 1 / 16, 1 / 32), (64, 128, 256))
        for name, table in (("PointMass vs Riccati", pointmass_study(spacings)),
                            ("Pendulum: z-space vs value-space HJB", pendulum_study(sizes))):
            print(f"\n{name} ({table.points} points, v < min v + {table.band:g})")
            print(table.format())
    if args.json:
        report.to_json(Path(args.json))
        print(f"wrote {args.json}")
    print(f"{'all checks passed' if report.passed else 'SOME CHECKS FAILED'} "
          f"({report.wall_time:.0f} s)")
    return 0 if report.passed else 1


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="gridlbc",
        description="Linearly solvable optimal control on grids and linear Bellman combination.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    demo = sub.add_parser(
        "demo",
        help="solve the pendulum swing-up, combine two goals, verify and write figures",
        description="Solve a pendulum swing-up on a grid, combine solutions for two goals, check "
        "superposition and the predicted cost by Monte Carlo, and write figures.",
    )
    demo.add_argument("--out", default="figures", help="folder for the figures (default: figures)")
    demo.add_argument("--grid", type=int, default=201,
                      help="nodes per axis of the pendulum grid (default: 201)")
    demo.add_argument("--quiet", action="store_true", help="no progress output")
    demo.set_defaults(func=_cmd_demo)

    verify = sub.add_parser(
        "verify",
        help="check superposition, optimality, interpolation and coordination; print a table",
        description="Check the linear Bellman combination claims against exact answers "
        "(direct solves, Riccati, Monte Carlo) and print a table. Exit status 1 if a check fails.",
    )
    verify.add_argument("--grid", type=int, default=256,
                        help="θ nodes of the pendulum swing-up grid (default: 256)")
    verify.add_argument("--samples", type=int, default=8000,
                        help="Monte-Carlo samples of the swing-up (default: 8000)")
    verify.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    verify.add_argument("--json", metavar="PATH", help="also write the results as JSON")
    verify.add_argument("--quick", action="store_true",
                        help="smoke-test sizes (bounds not expected to hold; use with small "
                        "--grid and --samples)")
    verify.add_argument("--quiet", action="store_true", help="no progress output")
    verify.add_argument("--convergence", action="store_true",
                        help="also run the convergence study: both z-space schemes and the "
                        "value-space HJB solver under grid refinement (a few minutes)")
    verify.set_defaults(func=_cmd_verify)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except (ValueError, TypeError, FileNotFoundError, MemoryError) as exc:
        print(f"gridlbc {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
