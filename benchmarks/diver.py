"""The diver beyond the grid (paper Figs. 6 and 8): trajectory-based LBC on an 8-D free chain.

Problem: :func:`gridlbc.studies.problems.diver_problem` (4 uniform rods, T = 1 s, λ = 1,
R = 50 per joint torque, entry cost 10 (θ1 − c)² + 2 Σ θk², take-off straight with arms
overhead spinning at κ · 2 rad/s). Study: :mod:`gridlbc.studies.diver`.

- Interpolation (Fig. 6): dives optimised to enter at c = −δ and +δ (under- and over-rotating),
  combined with the projected weights to enter vertically; LBC against the naive blend with the
  same weights, each component's tracker alone and the vertical dive optimised directly.
- Coordination (Fig. 8): vertical dives from κ = 0.85, 1, 1.15 combined with w = 1, tested from
  eight κ in [0.8, 1.2]; LBC against the naive average, the κ = 1 tracker and the optimum
  from each κ.

Every controller is rolled out without noise (Δt = 5 ms) and, with ``--certify N``, on the noisy
problem (N paths, the same noise for every controller at a take-off): its cost J ± SE, the
difference from a baseline controller ± its paired SE (a "tie" when within 3 SE), and its own
certificate (the controller as proposal: v* ± SE, the effective sample size and the PSIS tail
k̂; above 0.7 that v* is unreliable). With ``--truth-samples M`` the Fig. 6 optimum is also
certified with the cheapest noisy controller as proposal (the one closest to optimal: J − v* =
λ KL), at two seeds of M paths. Prints the tables of docs/trajectory.rst, "The diver".

    python benchmarks/diver.py --certify 3000 --truth-samples 100000 --figures figures
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

from gridlbc import CertificateWarning, certify
from gridlbc.studies.diver import (
    animate_dives,
    blend_at_start,
    composite_profile,
    plot_study,
    run_coordination,
    run_interpolation,
)
from gridlbc.studies.problems import DIVER_TEMPERATURE, diver_problem, diver_start


def _noisy(run, baseline=None) -> str:
    """Cells: noisy J ± SE, the paired difference from ``baseline`` (with "tie" within 3 SE),
    and the run's own certificate: v* ± SE, ESS, k̂."""
    if run.noisy_costs is None:
        return "| — | — | — | — | — "
    J, se = run.noisy_cost
    if baseline is None or baseline is run:
        diff = "—"
    else:
        d, d_se = run.paired_difference(baseline)
        diff = f"{d:+.2f} ± {d_se:.2f}" + (" (tie)" if abs(d) < 3 * d_se else "")
    c = run.certificate
    return (
        f"| {J:.2f} ± {se:.2f} | {diff} | {c.optimal_value:.3g} ± {c.optimal_value_se:.2g} | "
        f"{c.effective_sample_size:.0f} | {c.pareto_k:.2f}{'' if c.trusted else ' (untrusted)'} "
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--offset", type=float, default=0.25, help="δ: the components enter at ∓δ rad from vertical"
    )
    parser.add_argument("--restarts", type=int, default=8, help="trajectory optimisation starts")
    parser.add_argument("--intervals", type=int, default=100, help="control intervals per dive")
    parser.add_argument("--dt", type=float, default=0.005, help="rollout step (s)")
    parser.add_argument("--certify", type=int, default=0, help="noisy paths per controller")
    parser.add_argument(
        "--truth-samples",
        type=int,
        default=0,
        help="paths of the Fig. 6 certificate with the cheapest controller as proposal (0: none)",
    )
    parser.add_argument("--tests", type=int, default=8, help="test κ values in [0.8, 1.2]")
    parser.add_argument(
        "--temperature",
        type=float,
        default=DIVER_TEMPERATURE,
        help="λ (the noise level and the scale of α); the projection needs λ ≈ 1",
    )
    parser.add_argument(
        "--only",
        choices=("interpolation", "coordination"),
        default=None,
        help="run one experiment (no figures)",
    )
    parser.add_argument("--figures", default=None, help="folder for diver.png and diver.gif")
    args = parser.parse_args(argv)

    options = {
        "restarts": args.restarts,
        "n_intervals": args.intervals,
        "screen_intervals": min(50, args.intervals),
        "temperature": args.temperature,
    }
    if args.only != "coordination":
        runs = interpolation(args, options)
    if args.only != "interpolation":
        coordination = coordination_tables(args, options)
    if args.figures and args.only is None:
        out = Path(args.figures)
        out.mkdir(parents=True, exist_ok=True)
        plot_study(runs, coordination, out / "diver.png")
        animate_dives([r for r in runs if r.label in ("LBC", "naive blend")], out / "diver.gif")
        print(f"wrote {out / 'diver.png'} and {out / 'diver.gif'}")


def interpolation(args, options):
    started = time.perf_counter()
    fit, runs = run_interpolation(args.offset, args.dt, args.certify, **options)
    print(
        f"## Interpolation (Fig. 6): components entering at ∓{args.offset:g} rad, "
        f"projected weights {np.round(fit.weights, 4).tolist()} (residual {fit.residual:.2f})\n"
    )
    angles = np.array([-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5]) * args.offset
    profile = composite_profile(args.offset, args.temperature, angles)
    print("composite entry cost −λ log Σ w_i exp(−g_i/λ), body straight, against θ1 (rad):")
    print("| θ1 | " + " | ".join(f"{a:+.3f}" for a in angles) + " |")
    print("|---" * (len(angles) + 1) + "|")
    print("| g | " + " | ".join(f"{v:.4f}" for v in profile) + " |\n")
    print(
        "| controller | noise-free J | entry error (°) | shape error (°) | noisy J(u) | "
        "− LBC (paired) | own v* | ESS | k̂ |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    lbc = next(r for r in runs if r.label == "LBC")
    for r in runs:
        print(
            f"| {r.label} | {r.cost:.4g} | {np.degrees(r.entry_error):.1f} | "
            f"{np.degrees(r.shape_error):.1f} {_noisy(r, lbc)}|"
        )
    if args.truth_samples and args.certify:
        best = min(runs, key=lambda r: r.noisy_cost[0])
        print(
            f"\nv* with the cheapest noisy controller ({best.label}, J = "
            f"{best.noisy_cost[0]:.2f} ± {best.noisy_cost[1]:.2f}) as proposal, "
            f"{args.truth_samples} paths:"
        )
        target = diver_problem(0.0, temperature=args.temperature)
        for seed in (1, 2):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", CertificateWarning)
                c = certify(
                    target,
                    best.policy,
                    diver_start(1.0),
                    n_samples=args.truth_samples,
                    dt=args.dt,
                    seed=seed,
                    progress=False,
                )
            print(
                f"seed {seed}: v* = {c.optimal_value:.2f} ± {c.optimal_value_se:.2f}, ESS "
                f"{c.effective_sample_size:.0f}, k̂ = {c.pareto_k:.2f}"
                f"{'' if c.trusted else ' (untrusted)'}; J = {c.policy_cost:.2f} ± "
                f"{c.policy_cost_se:.2f}",
                flush=True,
            )
    print(f"\n({time.perf_counter() - started:.0f} s)\n")
    return runs


def coordination_tables(args, options):
    started = time.perf_counter()
    tests = np.linspace(0.8, 1.2, args.tests)
    components, deterministic, coordination = run_coordination(
        tests=tests, dt=args.dt, certify_samples=args.certify, **options
    )
    print(
        f"## Coordination (Fig. 8): components from κ = 0.85, 1, 1.15, λ = {args.temperature:g}\n"
    )
    print(
        "| κ | controller | noise-free J | J / optimum | entry error (°) | noisy J(u) | "
        "− κ = 1 tracker (paired) | own v* | ESS | k̂ |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for kappa in tests:
        rows = [r for r in coordination if r.momentum_scale == kappa]
        best = next(r for r in rows if r.label == "optimum")
        single = next(r for r in rows if r.label == "single tracker (κ = 1)")
        for r in rows:
            print(
                f"| {kappa:.3f} | {r.label} | {r.cost:.4g} | {r.cost / best.cost:.2f} | "
                f"{np.degrees(r.entry_error):.1f} {_noisy(r, single)}|"
            )
    labels = ("LBC", "LBC, deterministic v̄", "naive blend", "single tracker (κ = 1)")
    print("\n| controller | mean J / optimum | worst J / optimum | best at (of κ) |")
    print("|---|---|---|---|")
    table = {
        label: np.array(
            [
                next(r.cost for r in coordination if r.label == label and r.momentum_scale == k)
                for k in tests
            ]
        )
        for label in labels
    }
    optimum = np.array(
        [
            next(r.cost for r in coordination if r.label == "optimum" and r.momentum_scale == k)
            for k in tests
        ]
    )
    winner = np.argmin(np.stack([table[label] for label in labels]), axis=0)
    for i, label in enumerate(labels):
        ratio = table[label] / optimum
        print(
            f"| {label} | {ratio.mean():.2f} | {ratio.max():.2f} | "
            f"{int(np.sum(winner == i))} of {len(tests)} |"
        )
    print(
        "\nWhat α sees at take-off: v̂_i(x0, 0) of the components κ = 0.85, 1, 1.15 (with the "
        "Itô term (λ/2)∫tr(BR⁻¹BᵀP), and the paper's deterministic v̄) and α_i(x0, 0)\n"
    )
    print("| κ | v̂ (with Itô term) | α | v̂ (deterministic) | α |")
    print("|---|---|---|---|---|")
    for kappa in tests:
        cells = []
        for group in (components, deterministic):
            values, alpha = blend_at_start(group, kappa)
            cells += [", ".join(f"{v:.3f}" for v in values), ", ".join(f"{a:.2f}" for a in alpha)]
        print(f"| {kappa:.3f} | " + " | ".join(cells) + " |")
    print(f"\n({time.perf_counter() - started:.0f} s)")
    return coordination


if __name__ == "__main__":
    main()
