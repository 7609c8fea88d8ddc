"""Trajectory-based linear Bellman combination on the gymnast (paper §5, eq. 12; Fig. 7), judged
against the grid optimum and the certified optimum.

Problem: the gymnast of gridlbc.studies.problems (T 3, λ 1, R 1, g = xᵀdiag(10, 10, ½, ½)x, hip
stops at ±180°). Trackers: gridlbc.trajectory.optimize from each start of TRACKER_STARTS at rest
and from the test state (the deterministic optimum), by multi-start shooting + iLQR (--restarts,
300 RK4 intervals), expanded by gridlbc.trajectory.expand (defaults: v̂ from the full DDP
pass, the tracker's gain from the full DDP pass carrying the positive semi-definite part of
each P, feedback saturated at the χ²_4 99 % Mahalanobis radius ρ_max = 3.64).

(a) Fig. 7: from (−105°, −15°) at rest: tracker 1 (−90°, 0°), tracker 2 (−110°, −20°), the naive
    average and sum, LBC with the defaults, with the paper's deterministic v̄, with the
    Gauss–Newton P, with the Gauss–Newton gains, and with the previous default (full DDP gains,
    no saturation), the
    grid-optimal controller (splitting fitted to g, --grid n⁴), and the optimum's own tracker. Columns: the controller's prediction v(x₀),
    the noise-free cost and final angle distance (Euler, --dt), then with noise (--samples
    paths at --noisy-dt, the same noise for every row): the cost J ± SE, max |u| over the paths,
    the gap J − v* ± SE to the reference optimum (r) and J / v*, the difference from LBC's cost
    ± its paired SE, and the tail k̂ (and ESS) of the controller's own certificate, i.e. of
    v* estimated with the controller as proposal (k̂ > 0.7: that estimate is unreliable).
(r) The reference optimum v*(x₀): gridlbc.certify with the default fitted --reference-grid n⁴
    solution's policy as proposal (--truth-samples paths) at each of --reference-dts with
    richardson=True (also at twice the step), box edges reflecting as in the solve: v* ± SE,
    ESS, k̂ and the share of paths that reached an edge per step, and the step-extrapolated
    optimum; then the trajectory LBC as its own proposal at --noisy-dt (--samples paths): is it
    flagged, or within the grid-proposal interval?
(a') Noise-free, trackers 1 and 2 from --compare-restarts restarts (another local optimum from
    (−90°, 0°)) against --restarts, each with both curvatures (for P and K alike, unsaturated):
    v̂_i(x₀), α₁(x₀) and the costs.
(b) v̂ at the two trackers' start states shifted towards the test state by 0 … 0.35 rad: the
    deterministic v̂ (both curvatures) against the local optimum from there (iLQR continued in δ
    from the tracker's tape), and v̂ with the λ term against the grid value and the certified v*
    (proposal: the --reference-grid policy, --samples paths).
(c) Coverage: the starts of a (θ1, θ2) box at rest; J*(x₀) is the best of the local optima found
    by iLQR from each of the seven tapes (an upper bound on the global optimum). Share of starts
    whose noise-free cost is within 25 % of J*, for LBC of the first K trackers (the defaults,
    the Gauss–Newton P, the full DDP gains, the Gauss–Newton gains, and the previous default:
    full DDP gains, unsaturated), the best single
    one of them (an oracle: the cheapest of the K rollouts), greedy switching (argmax α) and the
    grid controller.
(d) Validity treatments, noisy, from the test state: tracker 2, LBC of trackers 1 and 2 and LBC
    of six, for the tracker's gain (projected full DDP, Gauss–Newton or full DDP) × the
    saturation radius (the default, None; 3 and 5 for the default gain) × v̄ in α (with the λ
    term or deterministic), each rolled out at --seeds seeds of --samples paths: J ± SE at each
    seed, the mean and worst ratio J / v* over the seeds with v* the reference (r) at --noisy-dt,
    J − v* ± SE over all the seeds' paths, and the difference from the same controller with the
    default treatment (the first row of each controller) ± its paired SE.

Trajectories, the grid solutions and the reference (r) are cached in --cache (a rerun reads
them).

    python benchmarks/gymnast_trackers.py --figure figures/gymnast_trackers.png
"""

from __future__ import annotations

import argparse
import json
import pickle
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc.studies.gymnast import (
    TRACKER_STARTS,
    GreedySwitch,
    angle_distance,
    at_rest,
    plot_trackers,
)
from gridlbc.studies.problems import GYMNAST_START, gymnast_problem
from gridlbc.trajectory import expand, optimize


def trajectories(problem, starts, restarts, cache: Path | None, label: str, warm=None):
    """optimize from each start (cached by label, start and restarts); with ``warm`` (a list of
    Trajectories), no search: DDP from each warm tape, the cheapest result kept."""
    out = []
    for x0 in starts:
        key = f"{label}_{'warm' if warm else restarts}_" + "_".join(f"{v:.4f}" for v in x0) + ".pkl"
        path = None if cache is None else cache / key
        if path is not None and path.exists():
            with open(path, "rb") as f:
                times, states, controls, cost, converged, message = pickle.load(f)
            out.append(
                gridlbc.trajectory.Trajectory(
                    times, states, controls, cost, problem, converged, message
                )
            )
            continue
        if warm:
            trajectory = min(
                (
                    optimize(
                        problem, x0, n_intervals=300, initial_controls=t.controls, search=False
                    )
                    for t in warm
                ),
                key=lambda t: t.cost,
            )
        else:
            trajectory = optimize(problem, x0, restarts=restarts, n_intervals=300)
        if path is not None:
            with open(path, "wb") as f:
                pickle.dump(
                    (
                        trajectory.times,
                        trajectory.states,
                        trajectory.controls,
                        trajectory.cost,
                        trajectory.converged,
                        trajectory.message,
                    ),
                    f,
                )
        out.append(trajectory)
    return out


def grid_controller(n, memory, cache: Path):
    """The fitted n⁴ splitting solution (Δt 0.05), read from ``cache`` if solved before."""
    path = cache / f"gymnast_grid_{n}.npz"
    if path.exists():
        return gridlbc.load(path), None
    problem = gymnast_problem(n)
    n_slices = round(problem.horizon / 0.05) + 1
    store_every = max(1, int(np.ceil(n_slices * problem.grid.size * 8 / memory)))
    started = time.perf_counter()
    solution = gridlbc.solve(
        problem, dt=0.05, method="splitting", fitting="terminal", store_every=store_every
    )
    wall = time.perf_counter() - started
    gridlbc.save(solution, path)
    return solution, wall


def clamped(policy, horizon):
    return lambda x, t: policy(x, min(t, horizon))


def reference_solution(n, cache: Path):
    """The default fitted n⁴ solve (``gridlbc.solve(gymnast_problem(n))``), read from ``cache``
    if solved before: the proposal of the reference optimum."""
    path = cache / f"gymnast_default_{n}.npz"
    if path.exists():
        return gridlbc.load(path), None
    started = time.perf_counter()
    solution = gridlbc.solve(gymnast_problem(n))
    wall = time.perf_counter() - started
    gridlbc.save(solution, path)
    return solution, wall


def reference_optimum(problem, args, cache: Path) -> dict:
    """v*(x₀) with the --reference-grid policy as proposal at each of --reference-dts (and twice
    each, richardson=True), cached in ``cache`` as JSON: {dt: {value, se, ess, k, edge}, and
    "extrapolated" per fine step}."""
    key = (
        f"reference_{args.reference_grid}_{args.truth_samples}_"
        + "_".join(f"{dt:g}" for dt in args.reference_dts)
        + "_v2.json"
    )
    path = cache / key
    if path.exists():
        return json.loads(path.read_text())
    solution, wall = reference_solution(args.reference_grid, cache)
    print(
        f"reference grid {args.reference_grid}⁴ (default fitted solve): "
        + ("read from the cache" if wall is None else f"solved in {wall:.0f} s"),
        flush=True,
    )
    policy = clamped(solution.policy, problem.horizon)
    out: dict = {
        "steps": [],
        "extrapolated": {},
        "prediction": float(solution.value(GYMNAST_START, 0.0)),
    }
    for seed, dt in enumerate(args.reference_dts):
        started = time.perf_counter()
        fine = gridlbc.certify(
            problem,
            policy,
            GYMNAST_START,
            n_samples=args.truth_samples,
            dt=dt,
            seed=10 + 2 * seed,
            richardson=True,
            progress=False,
            proposal=None,  # the grid policy alone: it is the reference proposal
        )
        coarse = gridlbc.certify(  # the richardson partner, for its own diagnostics (same draws)
            problem,
            policy,
            GYMNAST_START,
            n_samples=args.truth_samples,
            dt=2 * fine.dt,
            seed=10 + 2 * seed + 1,
            progress=False,
            proposal=None,
        )
        for cert in (coarse, fine):
            out["steps"].append(
                {
                    "dt": cert.dt,
                    "value": cert.optimal_value,
                    "se": cert.optimal_value_se,
                    "ess": cert.effective_sample_size,
                    "k": cert.pareto_k,
                    "edge": cert.left_box_fraction,
                    "edge_optimal": cert.optimal_left_box_fraction,
                    "seed": cert.seed,
                },
            )
        lo, hi = fine.interval(0.95)
        out["extrapolated"][f"{fine.dt:g}"] = {
            "value": fine.extrapolated_value,
            "se": fine.extrapolated_value_se,
            "step_contribution": fine.step_contribution,
            "interval": [lo, hi],
            "seconds": time.perf_counter() - started,
        }
    path.write_text(json.dumps(out, indent=1))
    return out


def print_reference(reference: dict) -> None:
    print(
        f"\n(r) reference optimum v*(x₀): certify with the default fitted grid policy as proposal, "
        f"box edges reflecting; grid prediction v(x₀) = {reference['prediction']:.2f}"
    )
    print(f"{'Δt':>6} {'v*':>16} {'ESS':>6} {'k̂':>6} {'edge':>6} {'edge*':>6} {'seed':>4}")
    for r in sorted(reference["steps"], key=lambda r: -r["dt"]):
        print(
            f"{r['dt']:>6g} {r['value']:8.3f} ± {r['se']:5.3f} {r['ess']:6.0f} {r['k']:6.2f} "
            f"{r['edge']:6.1%} {r['edge_optimal']:6.1%} {r['seed']:4d}"
        )
    for dt, r in reference["extrapolated"].items():
        print(
            f"extrapolated from Δt {dt} and {2 * float(dt):g}: {r['value']:.3f} ± {r['se']:.3f} "
            f"(95 % interval [{r['interval'][0]:.3f}, {r['interval'][1]:.3f}]; the step added "
            f"{r['step_contribution']:+.3f} at Δt {dt}; {r['seconds']:.0f} s)",
            flush=True,
        )


def noisy_rows(problem, policies: dict, x0, samples, dt, seed, own=True):
    """Each policy rolled out at the same noise (``seed``): its per-path costs and max |u|, and
    (``own``) its own certificate (the policy as proposal, the same paths)."""
    rows = {}
    for label, policy in policies.items():
        runs = gridlbc.simulate(problem, policy, x0, samples, dt=dt, seed=seed)
        cert = None
        if own:
            cert = gridlbc.certify(  # the controller's own certificate: it alone as proposal
                problem,
                policy,
                x0,
                n_samples=samples,
                dt=dt,
                seed=seed,
                progress=False,
                proposal=None,
            )
        rows[label] = (runs.costs, float(np.abs(runs.controls).max()), cert)
    return rows


def mean_se(costs) -> tuple[float, float]:
    return float(np.mean(costs)), float(np.std(costs, ddof=1) / np.sqrt(len(costs)))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=41, help="n of the n⁴ grid controller")
    parser.add_argument("--memory", type=float, default=4.0, help="GiB of stored slices")
    parser.add_argument("--restarts", type=int, default=128)
    parser.add_argument("--dt", type=float, default=0.001, help="noise-free rollout step")
    parser.add_argument("--noisy-dt", type=float, default=0.002)
    parser.add_argument("--samples", type=int, default=3000, help="noisy paths per controller")
    parser.add_argument("--seeds", type=int, default=1, help="seeds of the validity table (d)")
    parser.add_argument(
        "--reference-grid", type=int, default=51, help="n of the n⁴ proposal for v* (r)"
    )
    parser.add_argument("--truth-samples", type=int, default=4000, help="paths of the reference")
    parser.add_argument(
        "--reference-dts",
        type=float,
        nargs="+",
        default=[0.002],
        help="steps of the reference (each also at twice the step, extrapolated)",
    )
    parser.add_argument(
        "--cache",
        default="/tmp/gridlbc_trackers",
        help="cache of the trajectories and the grid solution",
    )
    parser.add_argument(
        "--compare-restarts",
        type=int,
        default=32,
        help="(a') also build trackers 1 and 2 from this many restarts (0: no)",
    )
    parser.add_argument("--figure", default=None)
    parser.add_argument("--skip", nargs="*", default=[], choices=["r", "a", "b", "c", "d"])
    args = parser.parse_args(argv)
    # Low effective sample sizes are in the ESS column; the certificates' warnings would drown
    # the tables.
    warnings.simplefilter("ignore", gridlbc.CertificateWarning)
    cache = Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    problem = gymnast_problem(args.grid)
    T = problem.horizon

    started = time.perf_counter()
    first = trajectories(problem, at_rest(TRACKER_STARTS[:2]), args.restarts, cache, "tracker")
    (optimum,) = trajectories(problem, [GYMNAST_START], args.restarts, cache, "tracker")
    trackers = first + trajectories(
        problem, at_rest(TRACKER_STARTS[2:]), args.restarts, cache, "tracker"
    )
    print(
        f"trajectories: {time.perf_counter() - started:.0f} s; costs from their own starts: "
        + ", ".join(f"{t.cost:.2f}" for t in trackers)
        + f"; deterministic optimum from the test state {optimum.cost:.3f}",
        flush=True,
    )
    solution, wall = grid_controller(args.grid, args.memory * 2**30, cache)
    grid_policy = clamped(solution.policy, T)
    print(
        f"grid controller {args.grid}⁴ fitted, Δt 0.05: "
        + ("read from the cache" if wall is None else f"solved in {wall:.0f} s"),
        flush=True,
    )
    c = [expand(problem, t) for t in trackers]
    c_det = [expand(problem, t, stochastic=False) for t in trackers]
    c_gn = [expand(problem, t, curvature="gauss-newton") for t in trackers[:2]]
    c_gnk = [expand(problem, t, feedback="gauss-newton") for t in trackers[:2]]
    c_old = [expand(problem, t, feedback="newton", radius=None) for t in trackers[:2]]

    def noise_free(policy, x0):
        run = gridlbc.simulate(problem, policy, x0, len(np.atleast_2d(x0)), dt=args.dt, noise=False)
        return run

    reference = reference_optimum(problem, args, cache)
    v_star = next(  # the first certificate at the noisy step
        r for r in reference["steps"] if abs(r["dt"] - args.noisy_dt) < 1e-12
    )
    if "r" not in args.skip:
        print_reference(reference)
        lo, hi = reference["extrapolated"][f"{args.noisy_dt:g}"]["interval"]
        lo_step = v_star["value"] - 1.96 * v_star["se"]
        hi_step = v_star["value"] + 1.96 * v_star["se"]
        print(
            f"the trajectory LBC as its own proposal at Δt {args.noisy_dt:g}, against the grid "
            f"proposal's 95 % interval at that step [{lo_step:.3f}, {hi_step:.3f}] "
            f"(extrapolated: [{lo:.3f}, {hi:.3f}])"
        )
        print(f"{'paths':>6} {'seed':>4} {'v*':>16} {'ESS':>6} {'k̂':>6} {'verdict':<9}")
        for n in sorted({300, 1000, args.samples, 10000}):
            for seed in range(3):
                own = gridlbc.certify(
                    problem,
                    gridlbc.combine(c[:2]).policy,
                    GYMNAST_START,
                    n_samples=n,
                    dt=args.noisy_dt,
                    seed=seed,
                    progress=False,
                    proposal=None,  # LBC's own certificate
                )
                inside = lo_step <= own.optimal_value <= hi_step
                print(
                    f"{n:6d} {seed:4d} {own.optimal_value:8.3f} ± {own.optimal_value_se:5.3f} "
                    f"{own.effective_sample_size:6.0f} {own.pareto_k:6.2f} "
                    f"{'trusted' if own.trusted else 'flagged':<9} "
                    f"{'inside' if inside else 'outside'} "
                    f"({(own.optimal_value - v_star['value']) / own.optimal_value_se:+.1f} own SE)",
                    flush=True,
                )

    if "a" not in args.skip:
        lbc = gridlbc.combine(c[:2])
        controllers = {
            "tracker 1": (c[0].policy, c[0].value),
            "tracker 2": (c[1].policy, c[1].value),
            "naive average": (gridlbc.naive_blend(c[:2], None).policy, None),
            "naive sum": (gridlbc.naive_blend(c[:2], None, mode="sum").policy, None),
            "LBC (defaults)": (lbc.policy, lbc.value),
            "LBC (paper's v̄)": (
                gridlbc.combine(c_det[:2]).policy,
                gridlbc.combine(c_det[:2]).value,
            ),
            "LBC (Gauss–Newton P)": (gridlbc.combine(c_gn).policy, gridlbc.combine(c_gn).value),
            "LBC (Gauss–Newton gains)": (
                gridlbc.combine(c_gnk).policy,
                gridlbc.combine(c_gnk).value,
            ),
            "LBC (previous default)": (gridlbc.combine(c_old).policy, gridlbc.combine(c_old).value),
            f"grid {args.grid}⁴ fitted": (grid_policy, solution.value),
            "optimum's own tracker": (
                expand(problem, optimum).policy,
                expand(problem, optimum).value,
            ),
        }
        print(
            f"\n(a) Fig. 7 from (−105°, −15°); deterministic optimum (RK4 tape): cost "
            f"{optimum.cost:.2f}, final distance {angle_distance(optimum.states[-1:])[0]:.2f}; "
            f"noisy: {args.samples} paths at Δt {args.noisy_dt:g} (seed 0), v* = "
            f"{v_star['value']:.3f} ± {v_star['se']:.3f} (r)"
        )
        print(
            f"{'controller':<26} {'v(x0)':>6} {'cost':>6} {'dist':>5} | {'noisy J':>13} "
            f"{'max|u|':>6} {'J − v*':>13} {'J/v*':>5} {'J − J(LBC)':>14} | {'own k̂':>6} "
            f"{'ESS':>5}"
        )
        noisy = noisy_rows(
            problem,
            {label: policy for label, (policy, _) in controllers.items()},
            GYMNAST_START,
            args.samples,
            args.noisy_dt,
            seed=0,
        )
        lbc_costs = noisy["LBC (defaults)"][0]
        for label, (policy, value) in controllers.items():
            run = noise_free(policy, GYMNAST_START)
            costs, umax, cert = noisy[label]
            J, se = mean_se(costs)
            d, d_se = mean_se(costs - lbc_costs)
            v = "" if value is None else f"{float(value(GYMNAST_START, 0.0)):6.2f}"
            print(
                f"{label:<26} {v:>6} {run.costs[0]:6.2f} "
                f"{angle_distance(run.final_states)[0]:5.2f} | {J:6.2f} ± {se:4.2f} {umax:6.1f} "
                f"{J - v_star['value']:6.2f} ± {np.hypot(se, v_star['se']):4.2f} "
                f"{J / v_star['value']:5.3f} {d:+6.2f} ± {d_se:5.2f} | {cert.pareto_k:6.2f} "
                f"{cert.effective_sample_size:5.0f}",
                flush=True,
            )
        if args.figure:
            runs = {}
            for label in (
                "tracker 1",
                "tracker 2",
                "naive average",
                "LBC (defaults)",
                f"grid {args.grid}⁴ fitted",
            ):
                run = noise_free(controllers[label][0], GYMNAST_START)
                runs[label.split(" (")[0]] = (run.states[0], run.controls[0])
            lbc_states = runs["LBC"][0]
            alpha = np.array(
                [lbc.blend_weights(x, min(t, T)) for x, t in zip(lbc_states, run.times)]
            )
            fig = plot_trackers(
                {"tracker 1": trackers[0], "tracker 2": trackers[1]},
                runs,
                run.times,
                alpha,
                args.figure,
            )
            del fig
            print(f"wrote {args.figure}")

    if "a" not in args.skip and args.compare_restarts:
        print(
            f"\n(a') the same, noise-free, with tapes 1 and 2 from {args.compare_restarts} "
            f"restarts instead of {args.restarts}, for both curvatures"
        )
        print(
            f"{'restarts':>8} {'curvature':<13} {'J1 own':>6} {'v̂1(x0)':>7} {'v̂2(x0)':>7} "
            f"{'α1(x0)':>6} {'tracker 1':>9} {'tracker 2':>9} {'naive':>7} {'LBC':>6}"
        )
        other = trajectories(
            problem, at_rest(TRACKER_STARTS[:2]), args.compare_restarts, cache, "tracker"
        )
        for restarts, tapes in ((args.compare_restarts, other), (args.restarts, trackers[:2])):
            for curvature in ("newton", "gauss-newton"):
                parts = [
                    expand(
                        problem,
                        t,
                        stochastic=False,
                        curvature=curvature,
                        feedback=curvature,
                        radius=None,
                    )
                    for t in tapes
                ]
                lbc_part = gridlbc.combine(parts)
                costs = [
                    noise_free(policy, GYMNAST_START).costs[0]
                    for policy in (
                        parts[0].policy,
                        parts[1].policy,
                        gridlbc.naive_blend(parts, None).policy,
                        lbc_part.policy,
                    )
                ]
                v1, v2 = (float(part.value(GYMNAST_START, 0.0)) for part in parts)
                a1 = lbc_part.blend_weights(GYMNAST_START, 0.0)[0]
                print(
                    f"{restarts:8d} {curvature:<13} {tapes[0].cost:6.2f} {v1:7.2f} {v2:7.2f} "
                    f"{a1:6.2f} "
                    + " ".join(f"{x:9.2f}" for x in costs[:2])
                    + f" {costs[2]:7.2f} {costs[3]:6.2f}",
                    flush=True,
                )

    if "b" not in args.skip:
        print(
            "\n(b) v̂ at t = 0 from each tracker's start shifted by δ towards the test state: "
            "deterministic v̂ (Newton and Gauss–Newton P) against the local optimum V from "
            "there (DDP continued in δ from the tracker's tape); v̂ with the λ term against the grid value "
            f"and the certified v* (proposal: the default fitted {args.reference_grid}⁴ policy, "
            f"{args.samples} paths)"
        )
        reference_grid, _ = reference_solution(args.reference_grid, cache)
        reference_policy = clamped(reference_grid.policy, T)
        print(
            f"{'tracker':<7} {'δ rad':>5} {'V local':>7} {'v̂ Newton':>8} {'v̂ GN':>7} | "
            f"{'v̂ (λ)':>7} {'grid v':>7} {'v*':>13} {'ESS':>5} {'k̂':>5}"
        )
        deltas = (0.0, 0.05, 0.1, 0.2, 0.35)
        for i in (0, 1):
            towards = GYMNAST_START - trackers[i].states[0]
            starts = np.array(
                [trackers[i].states[0] + d * towards / np.linalg.norm(towards) for d in deltas]
            )
            gauss_newton = expand(problem, trackers[i], stochastic=False, curvature="gauss-newton")
            cert = gridlbc.certify(
                problem,
                reference_policy,
                starts,
                n_samples=args.samples,
                dt=args.noisy_dt,
                seed=1,
                progress=False,
                proposal=None,
            )
            tape = trackers[i].controls
            for k, d in enumerate(deltas):
                x = starts[k]
                local = optimize(
                    problem, x, n_intervals=300, initial_controls=tape, search=False
                )  # continuation in δ: the tape's own family
                tape = local.controls
                local = local.cost
                print(
                    f"{i + 1:<7} {d:5.2f} {local:7.2f} {c_det[i].value(x, 0.0):8.2f} "
                    f"{gauss_newton.value(x, 0.0):7.2f} | {c[i].value(x, 0.0):7.2f} "
                    f"{solution.value(x, 0.0):7.2f} {cert.optimal_value[k]:6.2f} ± "
                    f"{cert.optimal_value_se[k]:4.2f} {cert.effective_sample_size[k]:5.0f} "
                    f"{cert.pareto_k[k]:5.2f}",
                    flush=True,
                )

    if "c" not in args.skip:
        th1, th2 = np.meshgrid(
            np.radians([-120, -110, -100, -90, -80]), np.radians([-30, -15, 0]), indexing="ij"
        )
        starts = at_rest(np.stack([th1.ravel(), th2.ravel()], axis=1))
        best = trajectories(
            problem, starts, None, cache, f"coverage{args.restarts}", warm=[*trackers, optimum]
        )
        J_star = np.array([t.cost for t in best])
        grid_cost = noise_free(grid_policy, starts).costs
        print(
            f"\n(c) coverage of {len(starts)} starts θ1 ∈ [−120°, −80°] × θ2 ∈ [−30°, 0°] at "
            f"rest: share with noise-free cost ≤ 1.25 J*(x₀); J* from {J_star.min():.1f} to "
            f"{J_star.max():.1f}"
        )
        variants = {  # LBC of the first K trackers, expanded with these options
            "LBC": {},
            "GN P": {"curvature": "gauss-newton"},
            "DDP K": {"feedback": "newton"},
            "GN K": {"feedback": "gauss-newton"},
            "old": {"feedback": "newton", "radius": None},
        }
        print(
            f"{'K':>2} "
            + " ".join(f"{name:>6}" for name in variants)
            + f" {'best single':>11} {'greedy':>6} {'grid':>6} | mean cost / J*: "
            + " ".join(f"{name:>6}" for name in variants)
            + f" {'single':>6} {'greedy':>6}"
        )

        def within(cost):
            return np.mean(cost <= 1.25 * J_star)

        for K in (1, 2, 4, 6):
            combination = gridlbc.combine(c[:K])
            lbc = [
                noise_free(
                    gridlbc.combine([expand(problem, t, **options) for t in trackers[:K]]).policy,
                    starts,
                ).costs
                for options in variants.values()
            ]
            single = np.min([noise_free(ci.policy, starts).costs for ci in c[:K]], axis=0)
            greedy = noise_free(GreedySwitch(combination).policy, starts).costs
            print(
                f"{K:2d} "
                + " ".join(f"{within(cost):6.0%}" for cost in lbc)
                + f" {within(single):11.0%} {within(greedy):6.0%} {within(grid_cost):6.0%} | "
                + f"{'':>15} "
                + " ".join(f"{np.mean(cost / J_star):6.2f}" for cost in lbc)
                + f" {np.mean(single / J_star):6.2f} {np.mean(greedy / J_star):6.2f}",
                flush=True,
            )

    if "d" not in args.skip:
        seeds = range(args.seeds)
        print(
            f"\n(d) validity treatments from the test state: noisy cost J ± SE at seeds "
            f"0…{args.seeds - 1} ({args.samples} paths each, Δt {args.noisy_dt}), the mean and "
            f"worst J / v* over the seeds and J − v* ± SE over all their paths, v* = "
            f"{v_star['value']:.3f} ± {v_star['se']:.3f} (r); radius 'auto' = {c[0].radius:.2f}"
        )
        print(
            f"{'controller':<12} {'gain':<16} {'radius':>6} {'v̄':<5} {'noise-free':>10} | "
            + " ".join(f"{'seed ' + str(k):>13}" for k in seeds)
            + f" | {'mean':>5} {'worst':>5} {'J − v*':>13} {'− default':>14}"
        )
        defaults: dict = {}  # each controller's costs with the default treatment, for pairing
        for feedback in ("projected-newton", "gauss-newton", "newton"):
            for radius in ("auto", None, 3.0, 5.0):
                for stochastic in (True, False):
                    if (not stochastic or feedback != "projected-newton") and radius in (3.0, 5.0):
                        continue
                    if not stochastic and radius is None:
                        continue
                    parts = [
                        expand(problem, t, stochastic=stochastic, radius=radius, feedback=feedback)
                        for t in trackers
                    ]
                    rows = [("LBC of 1, 2", gridlbc.combine(parts[:2]).policy)]
                    if stochastic:
                        rows = [
                            ("tracker 2", parts[1].policy),
                            *rows,
                            ("LBC of six", gridlbc.combine(parts).policy),
                        ]
                    for label, policy in rows:
                        run = noise_free(policy, GYMNAST_START)
                        costs = [
                            gridlbc.simulate(
                                problem,
                                policy,
                                GYMNAST_START,
                                args.samples,
                                dt=args.noisy_dt,
                                seed=seed,
                            ).costs
                            for seed in seeds
                        ]
                        stats = [mean_se(cost) for cost in costs]
                        ratio = [J / v_star["value"] for J, _ in stats]
                        J, se = mean_se(np.concatenate(costs))
                        pooled = np.concatenate(costs)
                        base = defaults.setdefault(label, pooled)  # the first row is the default
                        d, d_se = mean_se(pooled - base) if base is not pooled else (0.0, 0.0)
                        print(
                            f"{label:<12} {feedback:<16} {radius!s:>6} "
                            f"{'λ' if stochastic else 'det':<5} {run.costs[0]:10.2f} | "
                            + " ".join(f"{J_k:6.2f} ± {se_k:4.2f}" for J_k, se_k in stats)
                            + f" | {np.mean(ratio):5.3f} {np.max(ratio):5.3f} "
                            f"{J - v_star['value']:6.2f} ± {np.hypot(se, v_star['se']):4.2f} "
                            f"{d:+6.2f} ± {d_se:5.2f}",
                            flush=True,
                        )


if __name__ == "__main__":
    main()
