"""The certificate with the judged policy alone as proposal against the default pool (the policy
and an automatic grid solution, multiple importance sampling), on cases where the policy alone is
a poor proposal.

For each case and seed: v* ± SE, the tail shape k̂, the effective sample size, whether the
certificate is trusted, and the distance from the reference in units of the combined SE. The
references: the Euler–Maruyama chain's exact value for the LQ point mass
(``gridlbc.reference.euler_chain_value``, at the same step), and for the gymnast the 51⁴ grid
proposal's certificate at the same step, 19.091 ± 0.011 (8000 paths;
``benchmarks/gymnast_trackers.py``, table (r)).

    python benchmarks/certificate_pool.py [--seeds 0 1 2] [--paths 1000 3000] [--only lq gymnast]
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc.reference import euler_chain_value
from gridlbc.systems import PointMass

GYMNAST_REFERENCE = (19.091, 0.011)
FIG7_TAPES = Path(__file__).parents[1] / "tests" / "data" / "fig7_tapes.npz"


def lq_point_mass() -> gridlbc.Problem:
    """The LQ point mass of the tests (T = 1, λ = 0.5, R = 2, box [−4, 4]², 41²)."""
    grid = gridlbc.Grid([gridlbc.Axis(-4, 4, 41), gridlbc.Axis(-4, 4, 41)])
    return gridlbc.Problem(
        PointMass(),
        grid,
        1.0,
        gridlbc.Quadratic([0, 0], [2, 1]),
        state_cost=gridlbc.Quadratic([0, 0], [0.5, 0.1]),
        control_cost=2.0,
        temperature=0.5,
    )


def lq_case():
    problem = lq_point_mass()
    x0 = np.array([1.0, -0.5])

    def push(x, t):
        return np.full((x.shape[0], 1), 1.5)

    return (
        "LQ point mass, push u = 1.5",
        problem,
        push,
        x0,
        {},
        (euler_chain_value(problem, x0), 0.0),
    )


def gymnast_case():
    """LBC of the paper's Fig. 7: the two trackers of benchmarks/gymnast_trackers.py, rebuilt by
    iLQR from their stored tapes (tests/data/fig7_tapes.npz), combined."""
    from gridlbc.studies.gymnast import TRACKER_STARTS, at_rest
    from gridlbc.studies.problems import GYMNAST_START, gymnast_problem
    from gridlbc.trajectory import expand, optimize

    problem = gymnast_problem(41)
    tapes = np.load(FIG7_TAPES)
    trackers = [
        expand(
            problem,
            optimize(problem, x0, n_intervals=300, initial_controls=tapes[name], search=False),
        )
        for x0, name in zip(at_rest(TRACKER_STARTS[:2]), ("tracker1", "tracker2"))
    ]
    lbc = gridlbc.combine(trackers)
    return (
        "gymnast, trajectory LBC",
        problem,
        lbc.policy,
        GYMNAST_START,
        {"dt": 0.002},
        (GYMNAST_REFERENCE),
    )


CASES = {"lq": lq_case, "gymnast": gymnast_case}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--paths", type=int, nargs="+", default=[1000, 3000])
    parser.add_argument("--only", nargs="+", choices=sorted(CASES), default=sorted(CASES))
    args = parser.parse_args(argv)
    print("| case | paths | seed | proposal | v* ± SE | k̂ | ESS | trusted | off (SE) | time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in args.only:
        label, problem, policy, x0, options, (reference, reference_se) = CASES[name]()
        for n in args.paths:
            for seed in args.seeds:
                for proposal in (None, "auto"):
                    start = time.perf_counter()
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", gridlbc.CertificateWarning)
                        cert = gridlbc.certify(
                            problem,
                            policy,
                            x0,
                            n_samples=n,
                            seed=seed,
                            progress=False,
                            proposal=proposal,
                            **options,
                        )
                    seconds = time.perf_counter() - start
                    off = (cert.optimal_value - reference) / np.hypot(
                        cert.optimal_value_se, reference_se
                    )
                    source = " + ".join(cert.proposals)
                    print(
                        f"| {label} | {n} | {seed} | {source} | {cert.optimal_value:.4f} ± "
                        f"{cert.optimal_value_se:.4f} | {cert.pareto_k:.2f} | "
                        f"{cert.effective_sample_size:.0f} | {'yes' if cert.trusted else 'no'} | "
                        f"{off:+.1f} | {seconds:.1f} s |",
                        flush=True,
                    )


if __name__ == "__main__":
    main()
