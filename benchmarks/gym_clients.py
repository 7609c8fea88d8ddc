"""Gymnasium's first-exit tasks scored by gym itself: the library's policies against the best
published agents and the dynamic-programming optimum.

MountainCarContinuous-v0 (``gridlbc.studies.gym_clients``): the task is a first-exit problem
(exit set: the flag) with gym's force cost R = 0.2 and a time cost q per step that gym does not
have (it prices the episode's length; see the module). The rows:

- the linearly solvable policy (``gridlbc.solve``), clipped to gym's ±1, for the (λ, R, q) that
  scored best in a search on ``--search-episodes`` episodes with reset seeds 10⁶, 10⁶ + 1, …
  (the whole search is printed), then scored on ``--episodes`` fresh episodes (seeds 0, 1, …);
- the bounded HJB policy (``gridlbc.reference.solve_hjb(problem, control_bounds=(-1, 1))``,
  the first-exit mode: policy iteration), q searched the same way;
- dynamic programming on gym's own map (no model): the time-limited optimum predicted at gym's
  start distribution, and the greedy policy of a DP that prices each step (played in gym);
- the published agents, quoted (rl-baselines3-zoo benchmark.md): ARS 96.67 ± 0.78, SAC 94.68,
  TD3 93.48.

Acrobot-v1 (``gridlbc.studies.gym_acrobot``, gym's book dynamics in canonical momenta): a
minimum-time first-exit solve (q = 1 per second, exit when the tip is above the bar), its grid
and λ searched on the rollout's score; gym's torque chosen three ways from it: the sign of its
policy, a look-ahead of ``--acrobot-lookahead`` steps through gym's map on its value, and the
rollout of the sign policy through gym's map (every torque sequence of length
``--acrobot-rollout``, then the sign policy to the bar; the quickest wins). The bounded HJB on
``--acrobot-hjb``⁴ the same way. Dynamic programming on gym's own map
(``--acrobot-dp``⁴ nodes over the velocity box ``--acrobot-dp-speeds``): its predicted score at
the episodes' starts, and its policy played. QR-DQN −69.14 ± 9.97, PPO −73.5, DQN −76.6 quoted.

The first lines (stdout) are ``<env id>: mean <m> ± <se> over <N> episodes`` for the library's
best policy (the better on the search's episodes of its linear and bounded HJB policies); then
the tables. Progress goes to
stderr.

    python benchmarks/gym_clients.py [--episodes 1000] [--search-episodes 100] [--quick]
                                     [--only mountaincar acrobot]
"""

from __future__ import annotations

import argparse
import itertools
import math
import sys
import time
import warnings

import numpy as np

import gridlbc
from gridlbc.errors import GridlbcWarning
from gridlbc.reference import solve_hjb
from gridlbc.studies.gym_acrobot import (
    ACROBOT_ID,
    StepsToGo,
    acrobot_dp,
    acrobot_problem,
    acrobot_torques,
    rollout,
    run_acrobot,
)
from gridlbc.studies.gym_clients import (
    MOUNTAIN_CAR_ID,
    clipped,
    mountain_car_dp,
    mountain_car_problem,
    run_mountain_car,
    start_states,
)

SEARCH_SEED = 1_000_000
"""The search's reset seeds start here; the scored episodes use 0, 1, …: disjoint."""

PUBLISHED = {  # rl-baselines3-zoo benchmark.md: (agent, mean, ± as quoted)
    MOUNTAIN_CAR_ID: [("ARS", 96.67, "± 0.78"), ("SAC", 94.68, ""), ("TD3", 93.48, "")],
    ACROBOT_ID: [("QR-DQN", -69.14, "± 9.97"), ("PPO", -73.5, ""), ("DQN", -76.6, "")],
}


def log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def mountain_car(args) -> tuple[str, list[tuple]]:
    """Search, score and tabulate MountainCarContinuous-v0; returns the headline and the rows
    (policy, settings, solve seconds, score text)."""
    n = tuple(args.grid)
    gridlbc.solve(mountain_car_problem((25, 11)), error_estimate=False)  # compile first
    solve_hjb(mountain_car_problem((25, 11)), control_bounds=(-1, 1))
    mountain_car_dp((13, 5), 3, steps=2)

    def linear(lam, r, q):
        problem = mountain_car_problem(n, temperature=lam, control_cost=r, time_cost=q)
        started = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GridlbcWarning)
            solution = gridlbc.solve(problem, error_estimate=False)
        return clipped(solution.policy), time.perf_counter() - started

    def hjb(lam, r, q):
        problem = mountain_car_problem(n, temperature=lam, control_cost=r, time_cost=q)
        started = time.perf_counter()
        solution = solve_hjb(problem, control_bounds=(-1.0, 1.0))
        return (lambda x: solution.policy(x)), time.perf_counter() - started

    searches = {
        "linearly solvable, clipped": (linear, args.linear_search),
        "HJB, control_bounds=(-1, 1)": (hjb, args.hjb_search),
    }
    rows, best = [], None
    for name, (make, settings) in searches.items():
        found = None
        for lam, r, q in settings:
            policy, seconds = make(lam, r, q)
            episodes = run_mountain_car(policy, args.search_episodes, seed=SEARCH_SEED)
            log(f"  search {name} λ={lam:g} R={r:g} q={q:g}: {episodes.summary()}, {seconds:.1f} s")
            if found is None or episodes.mean > found[0]:
                found = (episodes.mean, (lam, r, q))
        assert found is not None
        lam, r, q = found[1]
        policy, seconds = make(lam, r, q)
        episodes = run_mountain_car(policy, args.episodes)
        log(f"  {name} λ={lam:g} R={r:g} q={q:g}: {episodes.summary()}")
        setting = (
            f"λ={lam:g}, R={r:g}, q={q:g}, {n[0]}×{n[1]}; best of {len(settings)} "
            f"(search {found[0]:.3f} on {args.search_episodes})"
        )
        rows.append((name, setting, seconds, episodes))
        if best is None or found[0] > best[0]:
            best = (found[0], episodes)

    # the same linear solve where the grid is too coarse for the noise (the docs' warning case)
    lam, r, q = args.coarse_setting
    coarse_n = tuple(args.coarse_grid)
    problem = mountain_car_problem(coarse_n, temperature=lam, control_cost=r, time_cost=q)
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridlbcWarning)
        solution = gridlbc.solve(problem, error_estimate=False)
    seconds = time.perf_counter() - started
    episodes = run_mountain_car(clipped(solution.policy), args.episodes)
    log(f"  linearly solvable, coarse λ={lam:g} R={r:g} q={q:g}: {episodes.summary()}")
    rows.append(
        (
            "linearly solvable, clipped, grid too coarse for λ",
            f"λ={lam:g}, R={r:g}, q={q:g}, {coarse_n[0]}×{coarse_n[1]}",
            seconds,
            episodes,
        )
    )

    # dynamic programming on gym's map
    dp = mountain_car_dp(tuple(args.dp_grid), args.dp_forces)
    predicted = dp.value(start_states()).mean()
    log(f"  DP time-limited: predicted {predicted:.2f} ({dp.wall_time:.0f} s)")
    rows.append(
        (
            "DP optimum on gym's map (999 steps, predicted)",
            f"{args.dp_grid[0]}×{args.dp_grid[1]} states, {args.dp_forces} forces",
            dp.wall_time,
            f"{predicted:.2f} (mean over x₀)",
        )
    )
    priced = mountain_car_dp(tuple(args.dp_grid), args.dp_forces, price=args.dp_price, tol=1e-7)
    episodes = run_mountain_car(priced.policy, args.episodes)
    log(f"  DP greedy (price {args.dp_price:g}): {episodes.summary()}")
    rows.append(
        (
            "DP greedy policy, played",
            f"price {args.dp_price:g}/step, {args.dp_grid[0]}×{args.dp_grid[1]}, "
            f"{args.dp_forces} forces (201 in play)",
            priced.wall_time,
            episodes,
        )
    )
    for agent, mean, spread in PUBLISHED[MOUNTAIN_CAR_ID]:
        rows.append(
            (f"{agent} (quoted)", "rl-baselines3-zoo", None, f"{mean:.2f} {spread}".strip())
        )
    assert best is not None
    episodes = best[1]
    headline = (
        f"{MOUNTAIN_CAR_ID}: mean {episodes.mean:.3f} ± {episodes.standard_error:.3f} over "
        f"{episodes.scores.size} episodes"
    )
    return headline, rows


def _timed(play):
    started = time.perf_counter()
    episodes = play()
    return episodes, time.perf_counter() - started


def acrobot(args) -> tuple[str, list[tuple]]:
    """Acrobot-v1: the minimum-time linear solve (grid and λ searched on the rollout's score)
    and the bounded HJB, each played with gym's torque chosen three ways (the sign of the
    policy, a look-ahead through gym's map on the solve's value, the rollout of the sign policy
    through gym's map); dynamic programming on gym's own map for comparison."""
    gridlbc.solve(acrobot_problem((5, 5, 5, 5)), error_estimate=False)  # compile first
    acrobot_dp((5, 5, 5, 5), max_sweeps=2)

    def linear(n, lam):
        problem = acrobot_problem((n,) * 4, temperature=lam)
        started = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GridlbcWarning)
            solution = gridlbc.solve(problem, error_estimate=False)
        return solution, time.perf_counter() - started

    def score(name, setting, seconds, policy):
        """A library row: searched on the search seeds, then scored; the play time noted."""
        search = run_acrobot(policy, args.search_episodes, seed=SEARCH_SEED)
        episodes, played = _timed(lambda: run_acrobot(policy, args.episodes))
        log(
            f"  Acrobot {name}: search {search.mean:.3f}, {episodes.summary()}, play {played:.0f} s"
        )
        setting += f"; play {played:.0f} s (search {search.mean:.2f})"
        return (name, setting, seconds, episodes), search.mean

    found = None
    for n, lam in args.acrobot_search:
        solution, _ = linear(n, lam)
        episodes = run_acrobot(
            rollout(acrobot_torques(solution)), args.search_episodes, SEARCH_SEED
        )
        log(f"  search Acrobot linear {n}⁴ λ={lam:g}, rollout: {episodes.summary()}")
        if found is None or episodes.mean > found[0]:
            found = (episodes.mean, (n, lam))
    assert found is not None
    n, lam = found[1]
    solution, seconds = linear(n, lam)
    sign = acrobot_torques(solution)
    where = f"λ={lam:g}, R=0.1, q=1/s, {n}⁴, p ∈ ±(15, 8)"
    scored = [
        score("linearly solvable, torque = sign(u)", where, seconds, sign),
        score(
            f"linearly solvable, look-ahead {args.acrobot_lookahead} steps on v",
            where,
            seconds,
            StepsToGo.from_solution(solution).lookahead(args.acrobot_lookahead),
        ),
    ]
    for depth in args.acrobot_rollout:
        scored.append(
            score(
                f"linearly solvable, rollout of sign(u), depth {depth}",
                f"{where} (the best of {len(args.acrobot_search)} grids and λ)",
                seconds,
                rollout(sign, depth),
            )
        )
    if args.acrobot_hjb:
        n = args.acrobot_hjb
        started = time.perf_counter()
        bounded = solve_hjb(acrobot_problem((n,) * 4, temperature=0.1), control_bounds=(-1, 1))
        seconds = time.perf_counter() - started
        where = f"λ=0.1, R=0.1, q=1/s, {n}⁴, policy iteration"
        scored.append(
            score(
                "HJB, control_bounds=(-1, 1), torque = sign(u)",
                where,
                seconds,
                acrobot_torques(bounded),
            )
        )
        scored.append(
            score(
                "HJB, control_bounds=(-1, 1), rollout of sign(u), depth 1",
                where,
                seconds,
                rollout(acrobot_torques(bounded)),
            )
        )
    rows = [row for row, _ in scored]
    best = max(scored, key=lambda item: item[1])[0][3]

    # dynamic programming on gym's map
    if args.acrobot_dp:
        n, speeds = args.acrobot_dp, tuple(args.acrobot_dp_speeds)
        dp = acrobot_dp((n,) * 4, speeds)
        where = (
            f"{n}⁴, θ̇ ∈ ±({speeds[0] / math.pi:g}π, {speeds[1] / math.pi:g}π), {dp.sweeps} sweeps "
            f"(last change {dp.change:.0e})"
        )
        greedy = [
            (
                depth,
                *_timed(lambda d=depth: run_acrobot(dp.steps_to_go.lookahead(d), args.episodes)),
            )
            for depth in (1, 3)
        ]
        predicted = 1.0 - dp.steps_to_go.costs(greedy[0][1].starts, 1).min(axis=1)
        log(f"  Acrobot DP {n}⁴: predicted {predicted.mean():.2f} ({dp.wall_time:.0f} s)")
        rows.append(
            (
                "DP optimum on gym's map (predicted at the episodes' starts)",
                where,
                dp.wall_time,
                f"{predicted.mean():.2f} ± {predicted.std(ddof=1) / np.sqrt(predicted.size):.2f}",
            )
        )
        for depth, episodes, played in greedy:
            log(f"  Acrobot DP greedy, look-ahead {depth}: {episodes.summary()}")
            rows.append(
                (
                    f"DP policy, played (look-ahead {depth} step{'s' if depth > 1 else ''} on its value)",
                    f"{where}; play {played:.0f} s",
                    dp.wall_time,
                    episodes,
                )
            )
    else:
        rows.append(("DP optimum on gym's map", "skipped (--acrobot-dp 0)", None, "–"))
    for agent, mean, spread in PUBLISHED[ACROBOT_ID]:
        rows.append(
            (f"{agent} (quoted)", "rl-baselines3-zoo", None, f"{mean:.2f} {spread}".strip())
        )
    headline = (
        f"{ACROBOT_ID}: mean {best.mean:.3f} ± {best.standard_error:.3f} over "
        f"{best.scores.size} episodes"
    )
    return headline, rows


def table(env_id: str, rows, episodes: int) -> None:
    print()
    print(
        f"{env_id}, score = gym's summed reward, mean ± standard error over {episodes} episodes "
        "(seeds 0, 1, …); machine shared, times noisy"
    )
    print("| policy | settings | solve | score | reached | steps | max abs(u) |")
    print("|---|---|---|---|---|---|---|")
    for name, setting, seconds, result in rows:
        solve = "–" if seconds is None else f"{seconds:.1f} s"
        if isinstance(result, str):
            print(f"| {name} | {setting} | {solve} | {result} | – | – | – |")
        else:
            print(
                f"| {name} | {setting} | {solve} | {result.mean:.3f} ± "
                f"{result.standard_error:.3f} | {result.reached.mean():.1%} | "
                f"{result.steps.mean():.0f} | {result.peak_force.max():.2f} |"
            )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=1000)
    parser.add_argument("--search-episodes", type=int, default=100)
    parser.add_argument(
        "--grid", type=int, nargs=2, default=[1201, 401], help="model grid (position, velocity)"
    )
    parser.add_argument("--dp-grid", type=int, nargs=2, default=[301, 201])
    parser.add_argument("--dp-forces", type=int, default=41)
    parser.add_argument(
        "--dp-price",
        type=float,
        default=3e-4,
        help="price per step of the DP whose greedy policy is played",
    )
    parser.add_argument(
        "--quick", action="store_true", help="a look in a minute: small grids, few episodes"
    )
    parser.add_argument(
        "--only", nargs="+", default=["mountaincar", "acrobot"], choices=["mountaincar", "acrobot"]
    )
    parser.add_argument(
        "--acrobot-hjb",
        type=int,
        default=13,
        help="nodes per axis of the bounded Acrobot HJB (0: skip; 13⁴ takes about a minute)",
    )
    parser.add_argument(
        "--acrobot-dp",
        type=int,
        default=51,
        help="nodes per axis of the DP on gym's Acrobot map (0: skip; 51⁴: minutes, 0.8 GB)",
    )
    parser.add_argument(
        "--acrobot-dp-speeds",
        type=float,
        nargs=2,
        default=[2 * math.pi, 3 * math.pi],
        help="the DP grid's velocity box ±(θ̇₁, θ̇₂) (gym clips at 4π, 9π)",
    )
    parser.add_argument("--acrobot-lookahead", type=int, default=3)
    parser.add_argument("--acrobot-rollout", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args(argv)
    args.acrobot_search = list(itertools.product((11, 13, 17), (0.3, 1.0)))
    args.coarse_setting, args.coarse_grid = (0.01, 0.2, 1e-3), [241, 201]
    args.linear_search = list(itertools.product((0.05, 0.1), (0.1, 0.2), (7e-4, 1e-3, 1.5e-3)))
    args.hjb_search = [(0.05, 0.2, q) for q in (7e-4, 1e-3, 1.5e-3)]
    if args.quick:
        args.episodes, args.search_episodes = 20, 10
        args.grid, args.dp_grid, args.dp_forces = [301, 101], [101, 61], 11
        args.linear_search, args.hjb_search = [(0.1, 0.2, 3e-3)], [(0.05, 0.2, 3e-3)]
        args.acrobot_search, args.acrobot_hjb = [(11, 1.0)], 0
        args.acrobot_dp, args.acrobot_rollout = 15, [1]
    results = []
    if "mountaincar" in args.only:
        results.append((MOUNTAIN_CAR_ID, *mountain_car(args)))
    if "acrobot" in args.only:
        results.append((ACROBOT_ID, *acrobot(args)))
    for _, headline, _ in results:
        print(headline)
    for env_id, _, rows in results:
        table(env_id, rows, args.episodes)


if __name__ == "__main__":
    main()
