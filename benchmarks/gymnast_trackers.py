"""Trajectory-based linear Bellman combination on the gymnast (paper §5, eq. 12; Fig. 7), judged
against the grid optimum and the certified optimum.

Problem: the gymnast of gridlbc.studies.problems (T 3, λ 1, R 1, g = xᵀdiag(10, 10, ½, ½)x, hip
stops at ±180°). Trackers: gridlbc.trajectory.optimize from each start of TRACKER_STARTS at rest
(300 RK4 intervals, expanded by gridlbc.trajectory.expand): the paper's two trackers and the
deterministic optimum from the test state by multi-start shooting + iLQR (--restarts); the four
further trackers by iLQR alone (search=False) from the cheapest of those three tapes.

(a) Fig. 7: from (−105°, −15°) at rest: tracker 1 (−90°, 0°), tracker 2 (−110°, −20°), the naive
    average and sum, LBC with v̂ including (λ/2)∫tr(SP) (default) and with the paper's
    deterministic v̄, the grid-optimal controller (splitting fitted to g, --grid n⁴), and the
    deterministic optimum from the test state (its RK4 cost, and its own tracker). Columns: the
    controller's prediction v(x₀), the noise-free cost and final angle distance (Euler, --dt),
    then gridlbc.certify with the controller as proposal (--samples paths at --noisy-dt): its
    noisy cost J ± SE, max |u| over the paths, the certified optimum v* ± SE and the effective
    sample size.
(b) v̂ against the grid value and the certified v* (proposal: the grid controller) at the two
    trackers' start states shifted along (θ1, θ2) by 0 … 0.35 rad.
(c) Coverage: the starts of a (θ1, θ2) box at rest; J*(x₀) is the best local optimum from each
    found by iLQR from the cheapest of the seven tapes (an upper bound on the global optimum). Share of starts whose noise-free cost is within 25 % of
    J*, for LBC of the first K trackers, the best single one of them (an oracle: the cheapest of
    the K rollouts), greedy switching (argmax α) and the grid controller.
(d) Validity: the noisy LBC of six trackers with the feedback saturated at Mahalanobis radius
    ρ_max (None, 5, 3, 2): noisy cost, max |u| and v*.

    python benchmarks/gymnast_trackers.py --figure figures/gymnast_trackers.png   # ≈ 30 min loaded
"""

from __future__ import annotations

import argparse
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
from gridlbc.trajectory import expand, optimize, tape_cost


def trajectories(problem, starts, restarts, cache: Path | None, label: str, warm=None):
    """optimize from each start (cached by label, start and restarts); with ``warm`` (a list of
    Trajectories), no search: DDP from the warm tape that is cheapest from the start."""
    out = []
    for x0 in starts:
        key = (f"{label}_{'warm' if warm else restarts}_" + "_".join(f"{v:.4f}" for v in x0)
               + ".pkl")
        path = None if cache is None else cache / key
        if path is not None and path.exists():
            with open(path, "rb") as f:
                times, states, controls, cost, converged, message = pickle.load(f)
            trajectory = gridlbc.trajectory.Trajectory(times, states, controls, cost, problem,
                                                       converged, message)
        elif warm:
            tape = min((t.controls for t in warm), key=lambda U: tape_cost(problem, x0, U)[0])
            trajectory = optimize(problem, x0, n_intervals=300, initial_controls=tape,
                                  search=False)
        else:
            trajectory = optimize(problem, x0, restarts=restarts, n_intervals=300)
            if path is not None:
                with open(path, "wb") as f:
                    pickle.dump((trajectory.times, trajectory.states, trajectory.controls,
                                 trajectory.cost, trajectory.converged, trajectory.message), f)
        out.append(trajectory)
    return out


def grid_controller(n, memory):
    problem = gymnast_problem(n)
    n_slices = round(problem.horizon / 0.05) + 1
    store_every = max(1, int(np.ceil(n_slices * problem.grid.size * 8 / memory)))
    started = time.perf_counter()
    solution = gridlbc.solve(problem, dt=0.05, method="splitting", fitting="terminal",
                             store_every=store_every)
    return solution, time.perf_counter() - started, store_every


def clamped(policy, horizon):
    return lambda x, t: policy(x, min(t, horizon))


def certify_row(problem, policy, x0, samples, dt, seed=0):
    cert = gridlbc.certify(problem, policy, x0, n_samples=samples, dt=dt, seed=seed,
                           progress=False)
    runs = gridlbc.simulate(problem, policy, x0, samples, dt=dt, seed=seed)  # same paths: max |u|
    return cert, float(np.abs(runs.controls).max())


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=51, help="n of the n⁴ grid controller")
    parser.add_argument("--memory", type=float, default=4.0, help="GiB of stored slices")
    parser.add_argument("--restarts", type=int, default=32)
    parser.add_argument("--dt", type=float, default=0.001, help="noise-free rollout step")
    parser.add_argument("--noisy-dt", type=float, default=0.002)
    parser.add_argument("--samples", type=int, default=300)
    parser.add_argument("--cache", default="/tmp/gridlbc_trackers", help="trajectory cache")
    parser.add_argument("--figure", default=None)
    parser.add_argument("--skip", nargs="*", default=[], choices=["a", "b", "c", "d"])
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
    optimum, = trajectories(problem, [GYMNAST_START], args.restarts, cache, "tracker")
    trackers = first + trajectories(problem, at_rest(TRACKER_STARTS[2:]), args.restarts, cache,
                                    "tracker", warm=[*first, optimum])
    print(f"trajectories: {time.perf_counter() - started:.0f} s; costs from their own starts: "
          + ", ".join(f"{t.cost:.2f}" for t in trackers)
          + f"; deterministic optimum from the test state {optimum.cost:.3f}", flush=True)
    solution, wall, kept = grid_controller(args.grid, args.memory * 2**30)
    grid_policy = clamped(solution.policy, T)
    print(f"grid controller {args.grid}⁴ fitted, Δt 0.05, every {kept}. slice: {wall:.0f} s",
          flush=True)
    c = [expand(problem, t) for t in trackers]
    c_det = [expand(problem, t, stochastic=False) for t in trackers]

    def noise_free(policy, x0):
        run = gridlbc.simulate(problem, policy, x0, len(np.atleast_2d(x0)), dt=args.dt,
                               noise=False)
        return run

    if "a" not in args.skip:
        lbc = gridlbc.combine(c[:2])
        controllers = {
            "tracker 1": (c[0].policy, c[0].value),
            "tracker 2": (c[1].policy, c[1].value),
            "naive average": (gridlbc.naive_blend(c[:2], None).policy, None),
            "naive sum": (gridlbc.naive_blend(c[:2], None, mode="sum").policy, None),
            "LBC (v̂ with λ term)": (lbc.policy, lbc.value),
            "LBC (paper's v̄)": (gridlbc.combine(c_det[:2]).policy,
                                gridlbc.combine(c_det[:2]).value),
            f"grid {args.grid}⁴ fitted": (grid_policy, solution.value),
            "optimum's own tracker": (expand(problem, optimum).policy,
                                      expand(problem, optimum).value),
        }
        print(f"\n(a) Fig. 7 from (−105°, −15°); deterministic optimum (RK4 tape): cost "
              f"{optimum.cost:.2f}, final distance {angle_distance(optimum.states[-1:])[0]:.2f}")
        print(f"{'controller':<24} {'v(x0)':>6} {'cost':>6} {'dist':>5} | {'noisy J':>13} "
              f"{'max|u|':>6} {'v*':>13} {'ESS':>5}")
        for label, (policy, value) in controllers.items():
            run = noise_free(policy, GYMNAST_START)
            cert, umax = certify_row(problem, policy, GYMNAST_START, args.samples, args.noisy_dt)
            v = "" if value is None else f"{float(value(GYMNAST_START, 0.0)[0]):6.2f}"
            print(f"{label:<24} {v:>6} {run.costs[0]:6.2f} "
                  f"{angle_distance(run.final_states)[0]:5.2f} | {cert.policy_cost:6.2f} ± "
                  f"{cert.policy_cost_se:4.2f} {umax:6.1f} {cert.optimal_value:6.2f} ± "
                  f"{cert.optimal_value_se:4.2f} {cert.effective_sample_size:5.0f}", flush=True)
        if args.figure:
            runs = {}
            for label in ("tracker 1", "tracker 2", "naive average", "LBC (v̂ with λ term)",
                          f"grid {args.grid}⁴ fitted"):
                run = noise_free(controllers[label][0], GYMNAST_START)
                runs[label.split(" (")[0]] = (run.states[0], run.controls[0])
            lbc_states = runs["LBC"][0]
            alpha = np.array([lbc.blend_weights(x, min(t, T))[0]
                              for x, t in zip(lbc_states, run.times)])
            fig = plot_trackers({"tracker 1": trackers[0], "tracker 2": trackers[1]}, runs,
                                run.times, alpha, args.figure)
            del fig
            print(f"wrote {args.figure}")

    if "b" not in args.skip:
        print("\n(b) v̂ against the grid value and the certified v* (proposal: grid controller), "
              "t = 0, start shifted by δ along (θ1, θ2) = (1, 1)/√2")
        print(f"{'tracker':<8} {'δ rad':>5} {'v̂ (λ)':>7} {'v̂ det':>7} {'grid v':>7} "
              f"{'v*':>13} {'ESS':>5}")
        direction = np.array([1.0, 1.0, 0.0, 0.0]) / np.sqrt(2)
        for i in (0, 1):
            starts = np.array([trackers[i].states[0] + d * direction
                               for d in (0.0, 0.05, 0.1, 0.2, 0.35)])
            cert = gridlbc.certify(problem, grid_policy, starts, n_samples=args.samples,
                                   dt=args.noisy_dt, seed=1, progress=False)
            for k, d in enumerate((0.0, 0.05, 0.1, 0.2, 0.35)):
                x = starts[k]
                print(f"{i + 1:<8} {d:5.2f} {c[i].value(x, 0.0)[0]:7.2f} "
                      f"{c_det[i].value(x, 0.0)[0]:7.2f} {solution.value(x, 0.0)[0]:7.2f} "
                      f"{cert.optimal_value[k]:6.2f} ± {cert.optimal_value_se[k]:4.2f} "
                      f"{cert.effective_sample_size[k]:5.0f}", flush=True)

    if "c" not in args.skip:
        th1, th2 = np.meshgrid(np.radians([-120, -110, -100, -90, -80]),
                               np.radians([-30, -15, 0]), indexing="ij")
        starts = at_rest(np.stack([th1.ravel(), th2.ravel()], axis=1))
        best = trajectories(problem, starts, None, cache, "coverage", warm=[*trackers, optimum])
        J_star = np.array([t.cost for t in best])
        grid_cost = noise_free(grid_policy, starts).costs
        print(f"\n(c) coverage of {len(starts)} starts θ1 ∈ [−120°, −80°] × θ2 ∈ [−30°, 0°] at "
              f"rest: share with noise-free cost ≤ 1.25 J*(x₀); J* from {J_star.min():.1f} to "
              f"{J_star.max():.1f}")
        print(f"{'K':>2} {'LBC':>6} {'best single':>11} {'greedy':>6} {'grid':>6} "
              f"{'LBC mean cost/J*':>16}")
        within = lambda cost: np.mean(cost <= 1.25 * J_star)
        for K in (1, 2, 4, 6):
            combination = gridlbc.combine(c[:K])
            lbc_cost = noise_free(combination.policy, starts).costs
            single = np.min([noise_free(ci.policy, starts).costs for ci in c[:K]], axis=0)
            greedy = noise_free(GreedySwitch(combination).policy, starts).costs
            print(f"{K:2d} {within(lbc_cost):6.0%} {within(single):11.0%} {within(greedy):6.0%} "
                  f"{within(grid_cost):6.0%} {np.mean(lbc_cost / J_star):16.2f}", flush=True)

    if "d" not in args.skip:
        print("\n(d) validity: noisy LBC of six trackers from the test state, feedback saturated "
              "at Mahalanobis radius ρ_max")
        print(f"{'ρ_max':>6} {'noise-free':>10} {'noisy J':>13} {'max|u|':>6} {'v*':>13} "
              f"{'ESS':>5}")
        for radius in (None, 5.0, 3.0, 2.0):
            parts = [expand(problem, t, radius=radius) for t in trackers]
            policy = gridlbc.combine(parts).policy
            run = noise_free(policy, GYMNAST_START)
            cert, umax = certify_row(problem, policy, GYMNAST_START, args.samples, args.noisy_dt)
            print(f"{radius!s:>6} {run.costs[0]:10.2f} {cert.policy_cost:6.2f} ± "
                  f"{cert.policy_cost_se:4.2f} {umax:6.1f} {cert.optimal_value:6.2f} ± "
                  f"{cert.optimal_value_se:4.2f} {cert.effective_sample_size:5.0f}", flush=True)


if __name__ == "__main__":
    main()
