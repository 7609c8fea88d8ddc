"""Predicted values and policies against the certified optimum, plain and fitted, by temperature.

Problems (``gridlbc.studies.problems``): the mild pendulum (damped, with a state cost, T = 1,
λ = 1) from six states in |θ| ≤ 1, |ω| ≤ 2, and the steep swing-up (g = xᵀdiag(50, 5)x, T = 2)
from (3, 0) at several temperatures. For each scheme and time step: the solve's wall time, its
predicted v(x₀, 0), the certified optimum v* (``gridlbc.certify`` with the solve's own policy as
the proposal, ``richardson=True``: the SDE's optimum, extrapolated from rollouts at Δt = 0.002 and
0.004) and the policy's own expected cost J on the same samples, judged by the chain's optimum
v*(Δt) at its own step. Where the certificate
has too few effective samples (small λ) the deterministic optimum 27.95 is the reference, as
λ → 0 the optimum tends to it.

    python benchmarks/accuracy.py [--mild 128] [--steep 201] [--temperatures 1 0.1 0.01 0.001]
                                  [--samples 400] [--fitted-dts 0.02 0.08]
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

import gridlbc
from gridlbc.studies.convergence import sde_optimum
from gridlbc.studies.problems import (
    MILD_STATES,
    STEEP_DETERMINISTIC_OPTIMUM,
    STEEP_START,
    mild_pendulum_problem,
    steep_swingup_problem,
)

ROLLOUT_DT = 0.002


def _schemes(fitted_dts):
    yield "plain", {"fitting": None}
    yield "fitted", {"fitting": "terminal"}
    for dt in fitted_dts:
        yield "fitted", {"fitting": "terminal", "dt": dt}


def _solve(problem, options):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", gridlbc.ResolutionWarning)
        started = time.perf_counter()
        solution = gridlbc.solve(problem, **options)
        wall = time.perf_counter() - started
    warned = any(issubclass(w.category, gridlbc.ResolutionWarning) for w in caught)
    return solution, wall, warned


def _row(name, problem, scheme, solution, wall, warned, x0, cert, fallback=None):
    """One row. The prediction is judged by the SDE's optimum (v*, extrapolated from the chains at
    Δt and 2Δt: richardson=True), the policy's cost J, a mean over rollouts at Δt, by the chain's
    own optimum v*(Δt), as is the gap J − v*(Δt); ``fallback`` replaces both references where the
    certificate has fewer than 20 effective samples."""
    v = float(solution.value(x0, 0.0))
    d = solution.diagnostics
    grid = "×".join(str(n) for n in problem.grid.shape)
    (optimum, optimum_se), chain = sde_optimum(cert), cert.optimal_value
    trusted = fallback is None or cert.effective_sample_size >= 20
    reference, chain_reference = (optimum, chain) if trusted else (fallback, fallback)
    print(
        f"{name:<7}{problem.temperature:>7g} {scheme:<7}{grid:>9}{d.dt:>8.4f}{wall:>8.2f}"
        f"{v:>10.3f}{optimum:>9.3f}{optimum_se:>7.3f}{chain:>9.3f}"
        f"{100 * (v / reference - 1):>+8.1f}%{cert.policy_cost:>9.3f}{cert.policy_cost_se:>7.3f}"
        f"{100 * (cert.policy_cost / chain_reference - 1):>+8.1f}%"
        f"{100 * cert.gap / chain:>+8.2f}%{100 * cert.gap_se / chain:>6.2f}%"
        f"{cert.effective_sample_size:>7.0f}"
        f"{'  warned' if warned else ''}",
        flush=True,
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mild", type=int, default=128)
    parser.add_argument("--steep", type=int, default=201)
    parser.add_argument("--temperatures", type=float, nargs="*", default=[1, 0.1, 0.01, 0.001])
    parser.add_argument("--samples", type=int, default=400)
    parser.add_argument("--fitted-dts", type=float, nargs="*", default=[])
    args = parser.parse_args(argv)

    for options in ({"fitting": None}, {"fitting": "terminal"}):  # compile outside the timings
        gridlbc.solve(mild_pendulum_problem(16), **options)
    header = (
        f"{'problem':<7}{'λ':>7} {'scheme':<7}{'grid':>9}{'dt':>8}{'solve s':>8}"
        f"{'predicted':>10}{'v*':>9}{'± SE':>7}{'v*(Δt)':>9}{'error':>9}{'policy J':>9}{'± SE':>7}"
        f"{'excess':>9}{'gap':>9}{'± SE':>7}{'ESS':>7}"
    )
    print(
        "error = predicted / v* − 1 (v* the SDE's optimum, extrapolated from the chains at Δt and "
        "2Δt), excess = J / v*(Δt) − 1 (J and v*(Δt) the chain's at the rollout step Δt); both "
        f"references are {STEEP_DETERMINISTIC_OPTIMUM} (the deterministic optimum) where the "
        "certificate has ESS < 20; gap = (J − v*(Δt))/v*(Δt) from the same samples, with its "
        "paired SE"
    )
    print(header)
    print("-" * len(header))
    problem = mild_pendulum_problem(args.mild)
    for scheme, options in _schemes(args.fitted_dts):
        solution, wall, warned = _solve(problem, options)
        for x0 in MILD_STATES:
            cert = gridlbc.certify(
                problem,
                solution.policy,
                x0,
                args.samples,
                dt=ROLLOUT_DT,
                seed=1,
                progress=False,
                richardson=True,
            )
            _row("mild", problem, scheme, solution, wall, warned, x0, cert)
    for lam in args.temperatures:
        problem = steep_swingup_problem(args.steep, lam)
        for scheme, options in _schemes(args.fitted_dts):
            solution, wall, warned = _solve(problem, options)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # underflowed policies, few effective samples
                policy = _finite(solution.policy)
                cert = gridlbc.certify(
                    problem,
                    policy,
                    STEEP_START,
                    args.samples,
                    dt=ROLLOUT_DT,
                    seed=0,
                    progress=False,
                    richardson=True,
                )
            _row(
                "steep",
                problem,
                scheme,
                solution,
                wall,
                warned,
                STEEP_START,
                cert,
                STEEP_DETERMINISTIC_OPTIMUM,
            )


def _finite(policy):
    """The policy with undefined controls (where z underflowed) replaced by zero torque, so that
    the certificate can still be computed for the plain scheme at small λ."""

    def wrapped(x, t):
        u = policy(x, t)
        return np.where(np.isfinite(u), u, 0.0)

    return wrapped


if __name__ == "__main__":
    main()
