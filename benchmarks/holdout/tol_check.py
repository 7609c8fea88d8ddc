"""Is ``gridlbc.solve(problem, tol=...)`` honest on the hold-out corpus?

For each member of ``corpus.py``: ``gridlbc.solve(member.build(), tol=TOL, max_seconds=...)``,
either with ``states=member.states`` (``--states``; ``times=[member.time]`` for a member read late
in its task) or without (the states that matter), every
warning it raises recorded (category and the first 120 characters). The value is then read at
the member's states at ``t = member.time`` and compared with the certified optimum of
``truths.json`` exactly as ``run.py`` does (its :func:`run.rows_for`: the certificate
extrapolated to a vanishing SDE step, error = (v − v*) / |v*|). Recorded per member: every round
of ``solution.refinement`` (grid, Δt, estimate, the step's share, ...), whether the last round met
``tol``, the wall time, the warnings, and the actual error at each state.

A solve that ends without a ResolutionWarning claims that its estimate met ``tol``; it is
*silently wrong* where the truth puts some state more than 2×tol off. The results are written one
JSON file per member and mode into ``RESULTS`` (``--out``), which ``--table`` reads back.

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python benchmarks/holdout/tol_check.py \\
        [--only NAME ...] [--tol 0.05] [--states] [--max-seconds 120] [--json OUT]
    python benchmarks/holdout/tol_check.py --table [--json OUT]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import re
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import run  # noqa: E402
from corpus import MEMBERS, Member  # noqa: E402

import gridlbc  # noqa: E402

RESULTS = Path("/work/main/benchmarks/holdout/strangers_round21t_results")
"""Where the per-member results go (ignored by git: ``strangers_round*_results/``)."""


def _plain(value):
    """``value`` with NaN and infinities as None and tuples as lists, for JSON."""
    if isinstance(value, float | np.floating):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [_plain(v) for v in value]
    return value


def _caught(records) -> list[str]:
    return [f"{w.category.__name__}: {str(w.message)[:120]}" for w in records]


def check(member: Member, truths: dict, tol: float, states: bool, max_seconds: float) -> dict:
    """One tol solve of ``member`` and its errors against the truths (one dict, JSON-ready)."""
    problem = member.build()
    with warnings.catch_warnings(record=True) as during:
        warnings.simplefilter("always")
        with np.errstate(all="warn", under="ignore"):
            start = time.perf_counter()
            solution = gridlbc.solve(
                problem,
                tol=tol,
                states=member.states if states else None,
                # a member read late is judged where it is read
                times=[member.time] if states and member.time > 0.0 else None,
                max_seconds=max_seconds,
                **member.options,  # a user's own solve options (corpus.Member.options)
            )
            seconds = time.perf_counter() - start
    with warnings.catch_warnings(record=True) as reading:
        warnings.simplefilter("always")
        with np.errstate(all="warn", under="ignore"):
            values = np.asarray(solution.value(member.states, member.time), dtype=float)
            estimates, parts = None, {}
            if solution.embedded is not None:
                estimates = np.asarray(
                    solution.error_estimate(member.states, member.time), dtype=float
                ).reshape(-1)
                # the estimate's parts at the states (units of v), for diagnosing a miss
                e, X, t = solution.embedded, member.states, member.time
                parts = {
                    "observed_order": e.observed_order,
                    "order": e.order,
                    "floor": e.floor,
                    "pair": e.pair is not None,
                    "excess": e.excess is not None,
                    "difference": np.reshape(e.difference(solution, X, t), -1),
                    "local": np.reshape(e.local(solution, X, t), -1),
                    "grid_terms": np.reshape(e.grid_terms(solution, X, t), -1),
                    "excess_response": np.reshape(e.excess_response(X, t), -1),
                }
    p = {
        "values": values.reshape(-1),
        "estimates": estimates,
        "warnings": _caught(during),
        "seconds": seconds,
        "dt": solution.diagnostics.dt,
        "steps": solution.diagnostics.steps,
    }
    # run.rows_for reads the truths and computes the errors exactly as run.py does, from the
    # prediction its module-level ``predict`` returns: here the tol solve's
    default = run.predict
    run.predict = lambda _member: p
    try:
        rows, _ = run.rows_for(member, truths)
    finally:
        run.predict = default
    rounds = [dataclasses.asdict(r) for r in solution.refinement]
    last = solution.refinement[-1]
    resolution = [w for w in during if issubclass(w.category, gridlbc.ResolutionWarning)]
    errors = [abs(r["error"]) for r in rows if "error" in r]
    beyond_se = [  # the error less two SE of the truth, relative to |v*|
        max(abs(r["predicted"] - r["certified"]) - 2 * r["se"], 0.0) / abs(r["certified"])
        for r in rows
        if "error" in r
    ]
    met = last.met(tol)
    # what the tol solve says stopped it: the words after "not {tol}: " in its own warning
    stopped = [str(w.message) for w in resolution if str(w.message).startswith("solve(tol=")]
    found = re.search(r"not [0-9.]+%: (.*?)(; |$)", stopped[0], re.S) if stopped else None
    stop_reason = found.group(1) if found else (stopped[0] if stopped else None)
    max_error = max(errors) if errors else None
    return _plain(
        {
            "member": member.name,
            "mode": "states" if states else "matter",
            "tol": tol,
            "max_seconds": max_seconds,
            "met": met,
            "resolution_warned": bool(resolution),
            "warnings": _caught(during),
            "stop_reason": stop_reason,
            "read_warnings": _caught(reading),
            "seconds": seconds,
            "final_shape": list(last.shape),
            "final_dt": last.dt,
            "final_estimate": last.error,
            "final_time_error": last.time_error,
            "final_certified_error": last.certified_error,
            "rounds": rounds,
            "embedded": parts,
            "max_error": max_error,
            "max_error_beyond_2se": max(beyond_se) if beyond_se else None,
            "silently_wrong": bool(
                not resolution and max_error is not None and max_error > 2 * tol
            ),
            "met_between_tol_and_2tol": bool(
                not resolution and max_error is not None and tol < max_error <= 2 * tol
            ),
            "rows": rows,
        }
    )


def _path(out: Path, name: str, mode: str) -> Path:
    return out / f"{name}__{mode}.json"


def _pct(x) -> str:
    return "" if x is None else f"{100 * x:.2f}%"


def table(results: list[dict]) -> str:
    """The results as a fixed-width table, one line per member and mode."""
    head = (
        f"{'member':20} {'mode':6} {'met':>3} {'grid':>13} {'dt':>9} {'est':>7} "
        f"{'maxerr':>7} {'>2SE':>6} {'secs':>6} {'rnds':>4}  verdict / warnings"
    )
    lines = [head]
    failed = [r for r in results if "exception" in r]
    results = [r for r in results if "exception" not in r]
    for r in failed:
        lines.append(f"{r['member']:20} {r['mode']:6} raised {r['exception'][:100]}")
    for r in results:
        verdict = (
            "SILENTLY WRONG"
            if r["silently_wrong"]
            else "met, tol<err<=2tol"
            if r["met_between_tol_and_2tol"]
            else "NOT MET, NO WARNING"
            if not r["met"] and not r["resolution_warned"]
            else ""
        )
        warned = "; ".join(dict.fromkeys(w[:70] for w in r["warnings"]))
        grid = "x".join(map(str, r["final_shape"]))
        lines.append(
            f"{r['member']:20} {r['mode']:6} {'yes' if r['met'] else 'no':>3} {grid:>13} "
            f"{r['final_dt']:9.3g} {_pct(r['final_estimate']):>7} {_pct(r['max_error']):>7} "
            f"{_pct(r['max_error_beyond_2se']):>6} "
            f"{r['seconds']:6.1f} {len(r['rounds']):>4}  {verdict} {warned}"
        )
    silent = [r for r in results if r["silently_wrong"]]
    between = [r for r in results if r["met_between_tol_and_2tol"]]
    met = [r for r in results if r["met"]]
    lines.append(
        f"\n{len(results)} solves: {len(met)} met tol, {len(silent)} silently wrong "
        f"(no ResolutionWarning, error > 2×tol), {len(between)} unwarned with tol < error ≤ 2×tol"
    )
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="*", help="member names (in this order)")
    parser.add_argument("--tol", type=float, default=0.05)
    parser.add_argument("--states", action="store_true", help="states=member.states")
    parser.add_argument("--json", help="also write every result to this file (--table: read it)")
    parser.add_argument("--max-seconds", type=float, default=120.0, help="max_seconds per solve")
    parser.add_argument("--out", default=str(RESULTS), help="folder of per-member results")
    parser.add_argument("--table", action="store_true", help="print the saved results")
    args = parser.parse_args(argv)
    out = Path(args.out)
    if args.table:
        if args.json:
            results = json.loads(Path(args.json).read_text())
        else:
            results = [json.loads(p.read_text()) for p in sorted(out.glob("*.json"))]
        print(table(results))
        return 0
    by_name = {m.name: m for m in MEMBERS}
    members = [by_name[n] for n in args.only] if args.only else list(MEMBERS)
    truths = run.load_truths()
    out.mkdir(parents=True, exist_ok=True)
    results = []
    for member in members:
        try:
            result = check(member, truths, args.tol, args.states, args.max_seconds)
        except Exception as exc:  # recorded, not fatal: the other members still run
            print(f"{member.name}: {type(exc).__name__}: {exc}", file=sys.stderr, flush=True)
            mode = "states" if args.states else "matter"
            failed = {"member": member.name, "mode": mode, "exception": repr(exc)[:500]}
            _path(out, member.name, mode).write_text(json.dumps(failed, indent=1) + "\n")
            continue
        _path(out, member.name, result["mode"]).write_text(json.dumps(result, indent=1) + "\n")
        print(table([result]).split("\n")[1], flush=True)
        results.append(result)
    print(table(results))
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
