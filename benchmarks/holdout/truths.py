"""Certified truths of the hold-out corpus, written to ``truths.json`` one member at a time.

For each member of ``corpus.py``: two proposals, the policy of a finer solve of the same problem
(``member.fine`` times as many cells per axis, at its default step) and the policy of the default
solve (and, for members marked ``trajectory``, a third: a locally optimal trajectory's LQR tracker
from each state, certifying that state); a pilot certificate of each (``--pilot`` samples per state at ``member.cert_dt``) picks the
one with the larger effective sample size. The sample count is then set so that the standard
error is about ``--target`` of v* (within ``--min``/``--max`` samples), and v* is certified at
``cert_dt`` and at half of it: the truth is the finer step's, and the difference between the two
(``step_bias``) says how large the Euler–Maruyama step bias still is (about as large again, for a
first-order weak error: ``v_extrapolated`` is the Richardson extrapolation to Δt → 0). Each state's record also keeps the share of
the optimal path measure that left the grid's box (the certificate lives on Rᵈ, the grid solve on
the box: a large share means the box, not the solver, sets the difference).

A member with an ``exact`` function (narrow terminal goals, where the certificates degenerate)
gets its exact values instead, in the same layout: ``proposal`` "exact (how)", no certificate,
the same value at both steps (no step bias), ``se`` 0, and ``dt``, ``ess`` and ``n_samples``
None.

    python benchmarks/holdout/truths.py [--only NAME ...] [--target 0.005] [--pilot 400]
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import subprocess
import sys
import time
import warnings
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from corpus import BY_NAME, MEMBERS, Member, refine  # noqa: E402

import gridlbc  # noqa: E402

TRUTHS = HERE / "truths.json"


@dataclass
class _Result:
    """What a truth keeps of certificates, one entry per state."""

    optimal_value: np.ndarray
    optimal_value_se: np.ndarray
    effective_sample_size: np.ndarray
    policy_cost: np.ndarray
    optimal_left_box_fraction: np.ndarray
    unexited_fraction: np.ndarray


def _certify(problem, policy, states, n, dt, seed, max_time=None):
    """Certify every state with ``policy``, or state i with ``policy[i]`` if it is a list."""
    options = {
        "n_samples": n,
        "dt": dt,
        "seed": seed,
        "progress": False,
        "max_time": max_time,
        "proposal": None,  # the chosen proposal alone, as the stored truths were made
    }
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if isinstance(policy, list):
            certificates = [
                gridlbc.certify(problem, u, x, **options) for u, x in zip(policy, states)
            ]
        else:
            certificates = [gridlbc.certify(problem, policy, states, **options)]
    result = _Result(
        *(
            np.concatenate([np.atleast_1d(getattr(c, f.name)) for c in certificates])
            for f in fields(_Result)
        )
    )
    return result, [f"{w.category.__name__}: {str(w.message)[:120]}" for w in caught]


def truth(member: Member, pilot: int, target: float, n_min: int, n_max: int, seed: int) -> dict:
    """The certified optimum at every state of ``member``, with how it was obtained."""
    start = time.perf_counter()
    problem = member.certified_problem()
    fine_problem = refine(problem, member.fine)
    fine = gridlbc.solve(fine_problem)
    default = gridlbc.solve(problem)
    shape = "×".join(str(a.n) for a in fine_problem.grid.axes)
    proposals = {
        f"finer solve ({shape}, dt {fine.diagnostics.dt:.3g})": fine.policy,
        f"default solve (dt {default.diagnostics.dt:.3g})": default.policy,
    }
    if member.trajectory:
        from gridlbc.trajectory import expand, optimize

        proposals["a locally optimal trajectory's LQR tracker from each state"] = [
            expand(problem, optimize(problem, x, restarts=16, seed=0)).policy for x in member.states
        ]
    if member.proposals is not None:
        proposals.update(member.proposals(problem))
    dt = member.cert_dt
    pilots = {}
    for name, policy in proposals.items():
        c, _ = _certify(problem, policy, member.states, pilot, dt, seed, member.max_time)
        pilots[name] = c
    best = max(pilots, key=lambda k: float(np.min(pilots[k].effective_sample_size)))
    c = pilots[best]
    ratio = np.max(np.asarray(c.optimal_value_se) / (target * np.abs(c.optimal_value)))
    n = int(min(n_max, max(n_min, math.ceil(pilot * ratio**2 / 100) * 100)))
    coarse, w1 = _certify(problem, proposals[best], member.states, n, dt, seed + 1, member.max_time)
    finer, w2 = _certify(
        problem, proposals[best], member.states, n, dt / 2, seed + 2, member.max_time
    )
    states = []
    for i, x in enumerate(member.states):
        v, v1 = float(finer.optimal_value[i]), float(coarse.optimal_value[i])
        states.append(
            {
                "x": [float(c) for c in x],
                "v": v,
                "se": float(finer.optimal_value_se[i]),
                "ess": float(finer.effective_sample_size[i]),
                "policy_cost": float(finer.policy_cost[i]),
                "left_box": float(finer.optimal_left_box_fraction[i]),
                "unexited": float(finer.unexited_fraction[i]),
                "v_coarse_dt": v1,
                "se_coarse_dt": float(coarse.optimal_value_se[i]),
                "step_bias": (v1 - v) / abs(v),
            }
        )
    return {
        "what": member.what,
        "problem": repr(problem.system) + f", T = {problem.horizon}, λ = {problem.temperature}",
        "grid": [a.n for a in problem.grid.axes],
        "proposal": best,
        "pilot_min_ess": {k: float(np.min(p.effective_sample_size)) for k, p in pilots.items()},
        "pilot_samples": pilot,
        "n_samples": n,
        "dt": dt / 2,
        "dt_coarse": dt,
        "seed": seed,
        "warnings": sorted(set(w1 + w2)),
        "states": states,
        "seconds": time.perf_counter() - start,
    }


def exact_truth(member: Member) -> dict:
    """The exact optimum at every state of ``member`` (``member.exact``), in :func:`truth`'s
    layout."""
    start = time.perf_counter()
    problem = member.certified_problem()
    values = np.asarray(member.exact(member.states), dtype=float).reshape(-1)
    how = " ".join((member.exact.__doc__ or "").split("\n\n")[0].split())
    states = []
    for x, v in zip(member.states, values):
        states.append(
            {
                "x": [float(c) for c in x],
                "v": float(v),
                "se": 0.0,
                "ess": None,
                "policy_cost": None,
                "left_box": None,
                "unexited": None,
                "v_coarse_dt": float(v),
                "se_coarse_dt": 0.0,
                "step_bias": 0.0,
            }
        )
    return {
        "what": member.what,
        "problem": repr(problem.system) + f", T = {problem.horizon}, λ = {problem.temperature}",
        "grid": [a.n for a in problem.grid.axes],
        "proposal": f"exact ({how})",
        "n_samples": None,
        "dt": None,
        "dt_coarse": None,
        "seed": None,
        "warnings": [],
        "states": states,
        "seconds": time.perf_counter() - start,
    }


def _extrapolate(state: dict) -> None:
    """Add the Richardson extrapolation of v* to Δt → 0 (first-order weak error) and its SE."""
    state["v_extrapolated"] = 2 * state["v"] - state["v_coarse_dt"]
    state["se_extrapolated"] = math.hypot(2 * state["se"], state["se_coarse_dt"])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="*", help="member names, in this order (default: all)")
    parser.add_argument("--target", type=float, default=0.005, help="SE / v* aimed at")
    parser.add_argument("--pilot", type=int, default=400)
    parser.add_argument("--min", type=int, default=1000)
    parser.add_argument("--max", type=int, default=6000)
    parser.add_argument("--seed", type=int, default=25)
    parser.add_argument("--out", default=str(TRUTHS))
    args = parser.parse_args(argv)
    out = Path(args.out)
    data = json.loads(out.read_text()) if out.exists() else {"members": {}}
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=HERE
    ).stdout.strip()
    # the options that differ from their defaults, for the record's command
    options = "".join(
        f" --{k} {getattr(args, k)}"
        for k in ("target", "pilot", "min", "max", "seed")
        if getattr(args, k) != parser.get_default(k)
    )
    for member in [BY_NAME[n] for n in args.only] if args.only else MEMBERS:
        if member.exact is not None:
            record = exact_truth(member)
        else:
            record = truth(member, args.pilot, args.target, args.min, args.max, args.seed)
        record["date"] = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
        record["command"] = "python benchmarks/holdout/truths.py --only " + member.name + options
        record["commit"] = commit
        data["members"][member.name] = record
        for other in data["members"].values():
            for st in other["states"]:
                _extrapolate(st)
        out.write_text(json.dumps(data, indent=1) + "\n")
        if member.exact is not None:
            summary = ", ".join(f"{s['v']:.6g}" for s in record["states"])
        else:
            summary = ", ".join(
                f"{s['v']:.4g}±{s['se']:.2g} (ESS {s['ess']:.0f}, "
                f"bias {100 * s['step_bias']:+.1f}%, left {s['left_box']:.2f})"
                for s in record["states"]
            )
        print(
            f"{member.name}: n {record['n_samples']}, {record['proposal']}: {summary}; "
            f"{record['seconds']:.0f} s",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
