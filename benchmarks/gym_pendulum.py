"""Gymnasium's Pendulum-v1 scored by gym itself: linearly solvable vs bounded-torque HJB policies.

The problem is gym's own (``gridlbc.studies.gym_pendulum``): θ̈ = 15 sin θ + 3u, q = 20θ² + 2ω²,
R = 0.04, 10 s, torque clipped to ±2 by gym. Every policy is run for ``--episodes`` episodes of
gym's ``Pendulum-v1`` (reset seeds 0, 1, …, the same for every policy, so differences between
rows are paired) and scored by gym's summed reward: mean ± standard error.

Rows:

- zero torque;
- the linearly solvable policy (``gridlbc.solve``), clipped to ±2 as gym does, over a sweep of
  temperature λ and control cost R a new user would try (R = 0.04 is gym's; a larger R asks for
  smaller torques but also lowers the noise λ B R⁻¹ Bᵀ the formulation ties to it);
- the value-space HJB policy (``gridlbc.reference.solve_hjb``) without bounds, clipped;
- the bounded HJB policy, ``solve_hjb(problem, control_bounds=(-2, 2))``, and beside it the
  solver's own prediction −v(x₀, 0) averaged over the episodes' start states;
- reference numbers, quoted, not rerun: dynamic programming on gym's discrete map, measured
  for this project (−140.4 ± 1.7); TD3 and SAC from rl-baselines3-zoo's benchmark.md (mean and
  standard deviation over 750 episodes: −151.855 ± 90.227 and −156.995 ± 88.714; shown with the
  standard error std/√750).

    python benchmarks/gym_pendulum.py [--episodes 2000] [--sizes 101 201] [--quick]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import gridlbc
from gridlbc.reference import solve_hjb
from gridlbc.studies.gym_pendulum import run_episodes, zero_policy
from gridlbc.studies.problems import pendulum_v1_problem

REFERENCES = [  # (name, mean, standard error, source)
    ("dynamic programming on gym's map", -140.4, 1.7, "measured for this project"),
    ("TD3", -151.855, 90.227 / np.sqrt(750), "rl-baselines3-zoo benchmark.md, 750 episodes"),
    ("SAC", -156.995, 88.714 / np.sqrt(750), "rl-baselines3-zoo benchmark.md, 750 episodes"),
]


def _clipped(policy):
    return lambda x, t: np.clip(policy(x, t), -2.0, 2.0)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=2000)
    parser.add_argument(
        "--sizes",
        type=int,
        nargs="+",
        default=[101, 201],
        help="grid nodes per axis for the HJB solves",
    )
    parser.add_argument(
        "--temperature",
        type=float,
        default=1e-4,
        help="λ of the HJB solves (gym is deterministic: small)",
    )
    parser.add_argument(
        "--linear-size",
        type=int,
        default=201,
        help="grid nodes per axis for the linearly solvable sweep",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="a look in seconds: 51² grids, 50 episodes, one linear setting",
    )
    args = parser.parse_args(argv)
    sweep = [(lam, r) for lam in (0.2, 0.5, 1.0) for r in (0.04, 0.4, 4.0)]
    if args.quick:
        args.episodes, args.sizes, args.linear_size, sweep = 50, [51], 51, [(1.0, 4.0)]

    gridlbc.solve(pendulum_v1_problem(16, temperature=1.0))  # compile outside the timings
    solve_hjb(pendulum_v1_problem(16))
    rows = []  # (policy, grid, solve s, predicted, Episodes)

    def add(name, grid, seconds, policy, predicted=None):
        episodes = run_episodes(policy, args.episodes)
        if predicted is not None:
            predicted = -float(np.mean(predicted(episodes.starts, 0.0)))
        rows.append((name, grid, seconds, predicted, episodes))
        print(f"  {name} ({grid}): {episodes.summary()}", flush=True)

    add("zero torque", "–", None, zero_policy)
    n = args.linear_size
    for lam, r in sweep:
        problem = pendulum_v1_problem(n, temperature=lam, control_cost=r)
        started = time.perf_counter()
        solution = gridlbc.solve(problem)
        add(
            f"linearly solvable, clipped (λ={lam:g}, R={r:g})",
            f"{n}²",
            time.perf_counter() - started,
            _clipped(solution.policy),
        )
    for n in args.sizes:
        problem = pendulum_v1_problem(n, temperature=args.temperature)
        started = time.perf_counter()
        free = solve_hjb(problem)
        add(
            f"HJB unbounded, clipped (λ={args.temperature:g})",
            f"{n}²",
            time.perf_counter() - started,
            _clipped(free.policy),
        )
        started = time.perf_counter()
        boxed = solve_hjb(problem, control_bounds=(-2.0, 2.0))
        add(
            f"HJB control_bounds=(-2, 2) (λ={args.temperature:g})",
            f"{n}²",
            time.perf_counter() - started,
            boxed.policy,
            boxed.value,
        )

    print()
    print(
        f"Pendulum-v1, {args.episodes} episodes (seeds 0–{args.episodes - 1}), score = gym's "
        "summed reward; machine shared, times noisy"
    )
    header = "| policy | grid | solve | predicted −v(x₀) | score ± SE |"
    print(header)
    print("|---|---|---|---|---|")
    for name, grid, seconds, predicted, episodes in rows:
        solve = "–" if seconds is None else f"{seconds:.1f} s"
        pred = "–" if predicted is None else f"{predicted:.1f}"
        print(
            f"| {name} | {grid} | {solve} | {pred} | {episodes.mean:.1f} ± "
            f"{episodes.standard_error:.1f} |"
        )
    for name, mean, se, source in REFERENCES:
        print(f"| {name} (quoted: {source}) | – | – | – | {mean:.1f} ± {se:.1f} |")


if __name__ == "__main__":
    main()
