"""The gymnast (acrobot) swing-up: grid-optimal controller vs the deterministic optimum.

Problem: see :mod:`gridlbc.studies.gymnast` (T = 3, λ = 1, R = 1, q = 0, g = xᵀdiag(10, 10, ½, ½)x;
hip stops at ±180°, or a free hip with --hip free). For each grid size, method (``fitted``: the
splitting scheme fitted to the terminal cost, ``fitting="terminal"``) and time step:
solve, then roll the grid-optimal policy out from (−105°, −15°, at rest) without noise and
with noise (gridlbc.certify of its own policy, Euler–Maruyama at Δt = 2 ms). The slices are stored
in float64 (every k-th, "kept" in the table, to fit --memory). Reported: the solver's prediction
v(x₀, 0) = −λ log z(x₀, 0), the noise-free rollout cost and final angle distance from the
handstand, the noisy policy cost J ± its standard error, the effective sample size of the
policy's own certificate, and the wall time of the solve: the accuracy-per-second frontier.
References: the deterministic optimum (gridlbc.trajectory.optimize, multistart RK4 single
shooting polished by iLQR) for the
noise-free cost, and for the noisy problem the certified optimum v*(x₀) (gridlbc.certify with
--truth-samples, the policy of the row with the lowest J as proposal), against which the
predictions and the policies' costs are then tabulated.

    python benchmarks/gymnast.py --sizes 31 41 51 61 71 81 --dts 0.05 0.1   # ≈ 20 min, 8 GiB
    python benchmarks/gymnast.py --sizes 61 --methods fitted --dts 0.05 --figures figures
    python benchmarks/gymnast.py --sizes 31 35 --methods fitted --dts default 0.05 \
        --noisy-samples 1500 --truth-samples 2000
"""

from __future__ import annotations

import argparse
import itertools
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc.errors import CertificateWarning
from gridlbc.settings import SolverSettings
from gridlbc.simulate import simulate
from gridlbc.solver import courant_rates, time_grid
from gridlbc.studies.gymnast import angle_distance, animate_swingup, plot_swingup
from gridlbc.studies.problems import GYMNAST_START, gymnast_problem
from gridlbc.trajectory import optimize


def deterministic_optimum(problem):
    return optimize(problem, GYMNAST_START, n_intervals=300)


def policy_of(solution):
    def policy(x, t):
        return solution.policy(x, min(t, solution.problem.horizon))

    return policy


def study_row(n, method, dt, bounds, hip, n_noisy, rollout_dt, memory, seed=0):
    problem = gymnast_problem(n, bounds, hip)
    # float64 slices: noisy rollouts visit states whose z is below float32's range relative to
    # the slice maximum (v − min v > 103 λ), where a float32 policy is undefined. Keep every
    # k-th slice so that the slices fit in ``memory`` bytes (linear interpolation in time).
    if dt is None:  # the solver's default step
        dt = time_grid(problem, SolverSettings(**_options(method)), courant_rates(problem))[0]
    n_slices = round(problem.horizon / dt) + 1
    store_every = max(1, int(np.ceil(n_slices * problem.grid.size * 8 / memory)))
    started = time.perf_counter()
    solution = gridlbc.solve(problem, dt=dt, store_every=store_every, **_options(method))
    wall = time.perf_counter() - started
    predicted = float(solution.value(GYMNAST_START, 0.0))
    clean = simulate(problem, policy_of(solution), GYMNAST_START, 1, dt=rollout_dt, noise=False)
    noisy = gridlbc.certify(
        problem,
        policy_of(solution),
        GYMNAST_START,
        n_noisy,
        dt=rollout_dt,
        seed=seed,
        min_effective_sample_size=0,
        proposal=None,
    )  # J and the ESS of its own samples are used
    row = {
        "grid": f"{n}^4",
        "method": method,
        "dt": solution.diagnostics.dt,
        "bounds": bounds,
        "store_every": store_every,
        "wall": wall,
        "predicted": predicted,
        "clean_cost": float(clean.costs[0]),
        "clean_distance": float(angle_distance(clean.final_states)[0]),
        "noisy_cost": noisy.policy_cost,
        "noisy_se": noisy.policy_cost_se,
        "ess": noisy.effective_sample_size,
        "noisy_distance": float(np.median(angle_distance(noisy.final_states))),
    }
    return row, solution, clean


def _options(method):
    return (
        {"method": "splitting", "fitting": "terminal"}
        if method == "fitted"
        else {"method": method, "fitting": None}
    )


def _step(text):
    return None if text == "default" else float(text)


def zero_torque_cost(problem, rollout_dt):
    zero = simulate(
        problem, lambda x, t: np.zeros((len(x), 1)), GYMNAST_START, 1, dt=rollout_dt, noise=False
    )
    return float(zero.costs[0]), float(angle_distance(zero.final_states)[0])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[31, 41, 51])
    parser.add_argument(
        "--methods",
        nargs="+",
        default=["fitted", "splitting"],
        help="splitting (plain, fitting=None), fitted (fitting='terminal'), implicit",
    )
    parser.add_argument(
        "--dts",
        type=_step,
        nargs="+",
        default=[0.05, 0.1],
        help="time steps, or 'default' for the solver's own choice",
    )
    parser.add_argument(
        "--bounds",
        type=float,
        nargs=2,
        default=[16.0, 9.0],
        metavar=("P1", "P2"),
        help="momentum box ±P1 × ±P2 (default 16 9)",
    )
    parser.add_argument(
        "--hip",
        default="stops",
        choices=["stops", "free"],
        help="hip stops at ±180° (default, the issue's problem) or a free hip",
    )
    parser.add_argument("--noisy-samples", type=int, default=100)
    parser.add_argument(
        "--truth-samples",
        type=int,
        default=2000,
        help="samples of the certified optimum (default 2000)",
    )
    parser.add_argument("--rollout-dt", type=float, default=0.002)
    parser.add_argument(
        "--memory",
        type=float,
        default=6.0,
        help="GiB for the stored float64 slices of one solve (default 6; the "
        "best solve so far is kept as the certificate's proposal, so up to "
        "twice this is held)",
    )
    parser.add_argument("--figures", default=None, help="folder for the swing-up plot and GIF")
    args = parser.parse_args(argv)
    hip = np.pi if args.hip == "stops" else None

    reference = deterministic_optimum(gymnast_problem(11, args.bounds, hip))
    ref_distance = float(angle_distance(reference.states[-1:])[0])
    zero_cost, zero_distance = zero_torque_cost(
        gymnast_problem(11, args.bounds, hip), args.rollout_dt
    )
    print(
        f"deterministic optimum (trajectory.optimize): cost {reference.cost:.2f}, final angle distance "
        f"{ref_distance:.2f} rad, max |p1| {np.abs(reference.states[:, 2]).max():.1f}, "
        f"max |p2| {np.abs(reference.states[:, 3]).max():.1f}"
    )
    print(f"zero torque: cost {zero_cost:.2f}, final angle distance {zero_distance:.2f} rad")
    print(
        f"target: noise-free rollout cost ≤ {1.25 * reference.cost:.2f} (+25 %) and final "
        "distance < 1 rad"
    )
    header = (
        f"{'grid':>6} {'method':>9} {'dt':>6} {'box':>8} {'wall s':>7} {'v(x0)':>6} "
        f"{'cost':>6} {'dist':>5} {'noisy cost':>13} {'dist':>5} {'ESS':>4} {'kept':>4}"
    )
    print(header)
    best = None
    rows, proposal = [], None
    for n, method, dt in itertools.product(args.sizes, args.methods, args.dts):
        row, solution, clean = study_row(
            n,
            method,
            dt,
            tuple(args.bounds),
            hip,
            args.noisy_samples,
            args.rollout_dt,
            args.memory * 2**30,
        )
        print(
            f"{row['grid']:>6} {method:>9} {row['dt']:6.3f} "
            f"{args.bounds[0]:>3g}×{args.bounds[1]:<4g} {row['wall']:7.1f} "
            f"{row['predicted']:6.2f} {row['clean_cost']:6.2f} {row['clean_distance']:5.2f} "
            f"{row['noisy_cost']:7.2f} ± {row['noisy_se']:4.2f} {row['noisy_distance']:5.2f} "
            f"{row['ess']:4.0f} {row['store_every']:4d}",
            flush=True,
        )
        if best is None or row["clean_cost"] < best[0]["clean_cost"]:
            best = (row, clean)
        rows.append(row)
        if proposal is None or row["noisy_cost"] < proposal[0]["noisy_cost"]:
            proposal = (row, solution)
        del solution
    if proposal is not None:
        row, solution = proposal
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", CertificateWarning)
            truth = gridlbc.certify(
                solution.problem,
                policy_of(solution),
                GYMNAST_START,
                args.truth_samples,
                dt=args.rollout_dt,
                seed=1,
                proposal=None,  # the best grid policy alone
            )
        del proposal, solution
        v, se = truth.optimal_value, truth.optimal_value_se
        print(
            f"\ncertified optimum v*(x0) = {v:.2f} ± {se:.2f} (SE), proposal {row['grid']} "
            f"{row['method']} dt {row['dt']:.3f}, {args.truth_samples} samples, effective "
            f"sample size {truth.effective_sample_size:.0f}"
        )
        for w in caught:
            print(f"warning: {w.message}")
        print(
            f"{'grid':>6} {'method':>9} {'dt':>6} {'v(x0)':>6} {'error':>7} {'noisy cost':>13} "
            f"{'gap J − v*':>11}"
        )
        for r in rows:
            print(
                f"{r['grid']:>6} {r['method']:>9} {r['dt']:6.3f} {r['predicted']:6.2f} "
                f"{100 * (r['predicted'] - v) / v:6.1f}% {r['noisy_cost']:7.2f} ± "
                f"{r['noisy_se']:4.2f} {r['noisy_cost'] - v:6.2f} ± "
                f"{np.hypot(r['noisy_se'], se):4.2f}"
            )
    if args.figures and best is not None:
        row, clean = best
        out = Path(args.figures)
        out.mkdir(exist_ok=True)
        label = f"grid {row['grid']} {row['method']} Δt={row['dt']:.3f}"
        plot_swingup(
            clean.times,
            {label: (clean.states[0], clean.controls[0])},
            out / "gymnast_swingup.png",
            reference=(reference.times, reference.states, reference.controls),
        )
        animate_swingup(
            clean.times, clean.states[0], out / "gymnast.gif", title=f"gymnast, {row['grid']}"
        )
        print(f"wrote {out / 'gymnast_swingup.png'} and {out / 'gymnast.gif'}")


if __name__ == "__main__":
    main()
