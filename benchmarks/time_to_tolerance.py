"""Time to a tolerance: how long each method takes to bring v(x₀) within 3 % and 1 % of the truth.

The truth at x₀ is a certified optimum extrapolated to a vanishing SDE step (Richardson:
2 v*(Δt) − v*(2Δt), ``gridlbc.certify`` with the policy of a fine solve as proposal): for the
swing-up and the gymnast it is certified here, for the hold-out corpus's 3-D triple integrator it
is read from ``benchmarks/holdout/truths.json``. Methods, each on a sequence of grids (and its default step):

- ``default``: ``gridlbc.solve(problem)`` on each grid, in order, until one is within the target
  (the time is that solve's; a user would not know which grid to pick);
- ``tol``: ``gridlbc.solve(start, tol=target, states=[x₀])`` from the coarsest grid, and for the
  gymnast from 41⁴, the grid a user would choose in 4-D, and at most two refinements (the time
  of all its rounds);
- ``plain``: the same sequence with ``fitting=None``;
- ``hjb``: ``gridlbc.reference.solve_hjb`` on the same sequence.

All in one run, on one machine.

    python benchmarks/time_to_tolerance.py [--samples 2000] [--only swingup triple gymnast]
        [--methods default plain hjb]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc import accuracy
from gridlbc.reference import solve_hjb
from gridlbc.studies import problems as P

HOLDOUT = Path(__file__).resolve().parent / "holdout"
TARGETS = (0.03, 0.01)


def _refine(problem, k):
    for _ in range(k):
        problem = problem.replace(grid=accuracy.refined_grid(problem.grid))
    return problem


def _swingup(samples):
    sizes = [P.swingup_problem(n) for n in (32, 64, 128, 256)]
    x0 = P.SWINGUP_START
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gridlbc.ResolutionWarning)
        proposal = gridlbc.solve(sizes[-1])
    values = []
    for dt in (0.002, 0.004):
        cert = gridlbc.certify(
            sizes[-1], proposal.policy, x0, samples, dt=dt, seed=1, progress=False
        )
        values.append(cert.optimal_value)
    return "swingup (2-D)", sizes, x0, 2 * values[0] - values[1], {}


def _triple(_samples):
    sys.path.insert(0, str(HOLDOUT))
    from corpus import BY_NAME

    member = BY_NAME["triple_integrator"]
    record = json.loads((HOLDOUT / "truths.json").read_text())["members"]["triple_integrator"]
    state = record["states"][0]
    base = member.build()
    coarse = base.replace(grid=accuracy.embedded_grid(base.grid))
    sizes = [coarse, base, _refine(base, 1)]
    return (
        "triple integrator (3-D)",
        sizes,
        np.array(state["x"]),
        2 * state["v"] - state["v_coarse_dt"],
        {},
    )


def _gymnast(samples, truth=None):
    """The acrobot swing-up from the paper's test state, 21⁴ … 51⁴; the truth certified with the
    51⁴ policy as proposal (hip stops reflecting), extrapolated from Δt 0.002 and 0.004. The
    value-space HJB reference takes minutes per solve beyond 31⁴: it tries 21⁴ and 31⁴ only;
    ``tol`` starts from 41⁴ (on 21⁴ the estimate is too rough to steer: docs/benchmarks.rst) and
    stops after two refinements (a 4-D round beyond 41⁴ takes minutes)."""
    sizes = [P.gymnast_problem(n) for n in (21, 31, 41, 51)]
    x0 = P.GYMNAST_START
    if truth is not None:  # a previous run's certified value (--gymnast-truth)
        return "gymnast (4-D)", sizes, x0, truth, {"hjb": 2, "tol_from": 2, "tol_rounds": 2}
    proposal, _ = _quiet(gridlbc.solve, sizes[-1])
    cert = gridlbc.certify(
        sizes[-1], proposal.policy, x0, samples, dt=0.002, seed=1, richardson=True, progress=False
    )
    return (
        "gymnast (4-D)",
        sizes,
        x0,
        float(cert.extrapolated_value),
        {"hjb": 2, "tol_from": 2, "tol_rounds": 2},
    )


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gridlbc.GridlbcWarning)
        started = time.perf_counter()
        out = fn(*args, **kwargs)
        return out, time.perf_counter() - started


def _first_within(sizes, x0, truth, target, solver):
    """(grid shape, seconds, relative error, met) of the first size within ``target``, or the
    last that fitted in memory (NaN error if none did)."""
    shape, wall, error = sizes[0].grid.shape, np.nan, np.nan
    for problem in sizes:
        try:
            solution, wall = _quiet(solver, problem)
        except MemoryError:
            return shape, wall, error, False
        shape, error = problem.grid.shape, abs(float(solution.value(x0, 0.0)) / truth - 1)
        if error <= target:
            return shape, wall, error, True
    return shape, wall, error, False


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=2000)
    parser.add_argument("--only", nargs="*", default=["swingup", "triple"])
    parser.add_argument(
        "--gymnast-truth",
        type=float,
        help="reuse the gymnast's certified value printed by an earlier run (its certificate "
        "takes several minutes)",
    )
    parser.add_argument(
        "--methods",
        nargs="*",
        default=["default", "plain", "hjb"],
        help="the grid-sequence methods to run besides tol (default: all three)",
    )
    args = parser.parse_args(argv)
    makers = {
        "swingup": _swingup,
        "triple": _triple,
        "gymnast": lambda n: _gymnast(n, args.gymnast_truth),
    }
    print(f"{'problem':<26}{'target':>7}  {'method':<8}{'grid':>18}{'seconds':>9}{'error':>8}")
    for key in args.only:
        name, sizes, x0, truth, limits = makers[key](args.samples)
        print(f"{name}: truth v(x0) = {truth:.4f}")
        methods = {
            "default": gridlbc.solve,
            "plain": lambda p: gridlbc.solve(p, fitting=None),
            "hjb": lambda p: solve_hjb(p, error_estimate=False),  # the solve alone, as measured
        }
        for target in TARGETS:
            for method, solver in methods.items():
                if method not in args.methods:
                    continue
                tried = sizes[: limits.get(method, len(sizes))]
                shape, wall, error, met = _first_within(tried, x0, truth, target, solver)
                flag = "" if met else " (not met)"
                grid = "×".join(map(str, shape))
                print(
                    f"{'':<26}{target:>7.0%}  {method:<8}{grid:>18}{wall:>9.2f}{error:>8.2%}{flag}"
                )
            start = sizes[limits.get("tol_from", 0)]
            limit = {"max_refinements": limits["tol_rounds"]} if "tol_rounds" in limits else {}
            solution, wall = _quiet(gridlbc.solve, start, tol=target, states=[x0], **limit)
            error = abs(float(solution.value(x0, 0.0)) / truth - 1)
            grid = "×".join(map(str, solution.problem.grid.shape))
            last = solution.refinement[-1]
            certified = (
                "" if np.isnan(last.certified_error) else f", certified {last.certified_error:.2%}"
            )
            print(
                f"{'':<26}{target:>7.0%}  {'tol':<8}{grid:>18}{wall:>9.2f}{error:>8.2%}"
                f"  ({len(solution.refinement)} rounds, estimate {last.error:.2%}{certified})"
            )


if __name__ == "__main__":
    main()
