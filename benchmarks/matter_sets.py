"""Which states matter for a finite-horizon task without an exit set? Candidate definitions of
``states_that_matter`` measured against the hold-out truths (analysis; may be dropped).

Only a finite horizon without an exit set (and without an average cost) is judged at "the nodes
whose value at t = 0 is at most the median"; every other kind keeps its set, so only those
problems are measured. For each: the default solve (today's warning), the 4h solve once (as
``warning_rules._tail_order``), then per candidate the library's own ``embedded_estimate`` (floor
and observed order over the candidate's states) and ``assess`` with ``states_that_matter``
replaced by the candidate: does it warn, and what are the estimates at the checked states?

Candidates (masks over the nodes with a finite value at t = 0):

- M   median (today): v ≤ median(v);
- A   all: every finite node (as a task that ends is judged: every node off E);
- B1  half range: v ≤ min v + (max v − min v)/2 (a tuned number, for comparison);
- B2  v ≤ min v + λ log N (z within 1/N of its largest; a tuned number, for comparison);
- C   paths: the median set and every node γ's own paths visit from it (the solve's optimal
      paths, 4 per state from ASSESSED judged states, at the solve's Δt: nearest node);
- E   (table only) M or A: the quantile over either set exceeds tol (each with its own floor
      and order);
- F0  the estimate as today (floor and observed order over the better half), judged over every
      finite node (only the judged set changes: ``error_estimate(x)`` does not);
- F   (table only) F0 or M: judged over every node and over the better half;
- D   median, and R4: where the levels are not converging (observed order < 1), the largest
      deterministic part of the relative estimate over the median set > tol.

Problems: catalogue, corpus, strangers rounds 9, 10 and 13 (truths in ``--results``'s
``strangers_round{9,10,13}_results``: ``*_exact.json`` / ``*_truth.json``, not in git), and
round 13's ``hz_gust`` on 161² (Δt / 2).

    NUMBA_NUM_THREADS=1 python benchmarks/matter_sets.py --collect --results DIR [--only A B]
    python benchmarks/matter_sets.py --table
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc import accuracy as E
from gridlbc.accuracy import DEFAULT_TOLERANCE, embedded_grid, relative_error
from gridlbc.accuracy import assessment as A  # where assess looks states_that_matter up

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE / "holdout")]
SAVED = Path("/tmp/matter_sets.json")
TOL = DEFAULT_TOLERANCE
ORIGINAL = A.states_that_matter

from warning_rules import _finer, _kind  # noqa: E402  (the same helpers as the earlier analysis)


def problems(results: Path):
    """(group, name, builder, states, truth or None, solve options)."""
    import corpus
    import error_estimate
    import strangers_round9 as r9
    import strangers_round10 as r10
    import strangers_round13 as r13

    for name, problem, states, exact in error_estimate._catalogue():
        truth = None if exact is None else exact(problem).value(states, 0.0)
        yield "catalogue", name, (lambda p=problem: p), states, truth, {}
    table = json.loads((HERE / "holdout" / "table.json").read_text())
    for m in corpus.MEMBERS:
        rows = [r for r in table if r["member"] == m.name]
        truth = [r["certified"] for r in rows] if len(rows) == len(m.states) else None
        yield "corpus", m.name, m.build, m.states, truth, {}
    for rnd, P, suffix in (
        ("r9", r9.P9, "exact"),
        ("r10", r10.P10, "exact"),
        ("r13", r13.P13, "truth"),
    ):
        for name, (build, X, *_r) in P.items():
            f = results / f"strangers_round{rnd[1:]}_results" / f"{name}_{suffix}.json"
            truth = json.loads(f.read_text())["vstar"] if f.exists() else None
            yield rnd, name, build, X, truth, {}
            if name == "hz_gust":
                finer = lambda b=build: b().replace(grid=_finer(b().grid, 2))  # noqa: E731
                yield rnd, name + "@161", finer, X, truth, {}  # the round's --finer: T/50
                yield rnd, name + "@161dt/2", finer, X, truth, "half"


def node_mask_median(sol):
    v = sol.value_nodes(0)
    ok = np.isfinite(v)
    return ok & (v <= np.median(v[ok]))


def node_mask(sol, which: str, s4=None):
    v = sol.value_nodes(0).ravel()
    ok = np.isfinite(v)
    lam = sol.temperature
    if which in ("M", "D"):
        return ok & (v <= np.median(v[ok]))
    if which == "A":
        return ok
    vmin, vmax = v[ok].min(), v[ok].max()
    if which == "B1":
        return ok & (v <= vmin + 0.5 * (vmax - vmin))
    if which == "B2":
        return ok & (v <= vmin + lam * np.log(ok.sum()))
    if which == "C":
        return path_mask(sol, ok & (v <= np.median(v[ok])))
    raise KeyError(which)


def path_mask(sol, start_mask):
    """The start nodes and every node the solve's optimal paths from ASSESSED of them visit."""
    from gridlbc.simulate import simulate

    grid = sol.grid
    keep = np.flatnonzero(start_mask.ravel())
    keep = keep[np.linspace(0, len(keep) - 1, min(len(keep), E.ASSESSED)).astype(np.int64)]
    X0 = grid.node_coordinates(keep)
    X0 = np.repeat(X0, E.ASSESSED_PATHS, axis=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        paths = simulate(
            sol.problem,
            sol.policy,
            X0,
            n_samples=len(X0),
            dt=sol.diagnostics.dt,
            seed=7,
        )
    pts = paths.states.reshape(-1, grid.ndim)
    idx = nearest_nodes(grid, pts)
    mask = start_mask.ravel().copy()
    mask[idx] = True
    return mask & np.isfinite(sol.value_nodes(0).ravel())


def nearest_nodes(grid, pts):
    ids = []
    for k, a in enumerate(grid.axes):
        h = (a.hi - a.lo) / (a.n if a.periodic else a.n - 1)
        i = np.rint((pts[:, k] - a.lo) / h).astype(np.int64)
        i = np.mod(i, a.n) if a.periodic else np.clip(i, 0, a.n - 1)
        ids.append(i)
    return np.ravel_multi_index(tuple(ids), tuple(a.n for a in grid.axes))


def patched(mask_flat):
    def states_that_matter(solution, limit: int = E.SAMPLE):
        keep = np.flatnonzero(mask_flat)
        if len(keep) > limit:
            keep = keep[np.linspace(0, len(keep) - 1, limit).astype(np.int64)]
        return solution.grid.node_coordinates(keep)

    return states_that_matter


def measure(problem, states, truth, opts) -> dict:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        sol = gridlbc.solve(problem, **opts)
        secs = time.perf_counter() - t0
    warned = any(issubclass(w.category, gridlbc.ResolutionWarning) for w in caught)
    out = dict(kind=_kind(problem), warned=warned, seconds=secs)
    lam = problem.temperature
    states = np.atleast_2d(np.asarray(states, float))
    v = sol.value(states, 0.0)
    if truth is not None:
        truth = np.asarray(truth, float)
        out["errors"] = ((v - truth) / np.maximum(np.abs(truth), lam)).tolist()
    emb = sol.embedded
    if emb is None or out["kind"] != "T":
        out["estimate"] = emb is not None
        return out
    g4 = embedded_grid(emb.solution.grid)
    s4 = None
    if g4 is not None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            s4 = gridlbc.solve(
                problem.replace(grid=g4),
                error_estimate=False,
                dt=min(4 * sol.diagnostics.dt, problem.horizon),
            )
    out["estimate"] = True
    out["order_today"] = float(emb.observed_order)
    cands = {}
    for which in ("M", "A", "B1", "B2", "C", "D", "F0"):
        mask = node_mask(sol, "A" if which == "F0" else which)
        A.states_that_matter = patched(node_mask(sol, "M") if which == "F0" else mask)
        try:
            est = E.embedded_estimate(sol, emb.solution, s4, emb.pair, emb.excess)
            A.states_that_matter = patched(mask)
            object.__setattr__(sol, "embedded", est)
            a = E.assess(sol, TOL)
            X = A.states_that_matter(sol)
            vx, _, _, local = est._read(sol, X, 0.0)
            scale = np.maximum(np.abs(vx), lam)
            det = relative_error(
                np.maximum(np.maximum(local, est.floor * scale), est.excess_response(X)), vx, lam
            )
            det = det[np.isfinite(det)]
            est_checked = relative_error(sol.error_estimate(states), v, lam)
        finally:
            A.states_that_matter = ORIGINAL
            object.__setattr__(sol, "embedded", emb)
        fires = a.error > TOL
        if which == "D":
            fires = fires or (est.observed_order < 1 and det.max() > TOL)
        cands[which] = dict(
            fires=bool(fires),
            error=float(a.error),
            share=float(mask.mean()),
            n=int(mask.sum()),
            order=float(est.observed_order),
            floor=float(est.floor),
            det_max=float(det.max()),
            local=bool(a.local),
            est_checked=est_checked.tolist(),
        )
    out["cands"] = cands
    return out


def collect(results: Path, only=None):
    saved = json.loads(SAVED.read_text()) if SAVED.exists() else {}
    for group, name, build, states, truth, opts in problems(results):
        if only and name not in only:
            continue
        p = build()
        if _kind(p) != "T":
            continue
        if opts == "half":
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                base = gridlbc.solve(build(), error_estimate=False)
            opts = dict(dt=base.diagnostics.dt / 2)
        t0 = time.perf_counter()
        rec = measure(p, states, truth, opts)
        rec["group"] = group
        saved[f"{group}:{name}"] = rec
        SAVED.write_text(json.dumps(saved, indent=1))
        err = rec.get("errors")
        c = rec.get("cands", {})
        print(
            f"{group}:{name} warned={rec['warned']} maxerr="
            f"{np.max(np.abs(err)) if err else float('nan'):.3f} "
            + " ".join(f"{k}={'Y' if r['fires'] else 'n'}{r['error']:.3f}" for k, r in c.items())
            + f" ({time.perf_counter() - t0:.1f} s)",
            flush=True,
        )


def table():
    saved = json.loads(SAVED.read_text())
    names = ("M", "A", "B1", "B2", "C", "D", "E", "F0", "F")
    tallies = {k: dict(silent=[], false=[], new=[], lost=[]) for k in names}
    print(f"{'problem':26s} w  maxerr  " + "  ".join(f"{k:>12s}" for k in names))
    for key, r in saved.items():
        if "cands" not in r:
            continue
        errs = r.get("errors")
        me = max(abs(e) for e in errs) if errs else None
        c = dict(r["cands"])
        c["E"] = dict(c["A"], fires=c["A"]["fires"] or c["M"]["fires"])
        if "F0" in c:
            c["F"] = dict(c["F0"], fires=c["F0"]["fires"] or c["M"]["fires"])
        else:
            continue
        if c["M"]["fires"] != r["warned"]:
            print(f"   ({key}: M reproduction differs from the solve's warning)")
        print(
            f"{key:26s} {'Y' if r['warned'] else 'n'} {'    -' if me is None else f'{100 * me:6.1f}'}  "
            + "  ".join(
                f"{'Y' if c[k]['fires'] else 'n'} {100 * c[k]['error']:5.1f} {100 * c[k]['share']:3.0f}%"
                for k in names
            )
        )
        for k in names:
            t, fire = tallies[k], c[k]["fires"]
            if me is not None and me > 0.10 and not fire:
                t["silent"].append(f"{key} {100 * me:.0f}%")
            if me is not None and me < 0.02 and fire:
                t["false"].append(key)
            if fire and not c["M"]["fires"]:
                t["new"].append(f"{key} ({'-' if me is None else f'{100 * me:.1f}%'})")
            if c["M"]["fires"] and not fire:
                t["lost"].append(key)
    for k, t in tallies.items():
        print(
            f"{k}: silent >10 %: {len(t['silent'])} {t['silent']}; false alarms (warned, all < 2 %):"
            f" {len(t['false'])} {t['false']}; newly warned vs M: {len(t['new'])} {t['new']};"
            f" no longer warned: {t['lost']}"
        )


def verify(names, results: Path):
    """Candidate A's alarms against a solve on 2× the cells per axis (Δt/2, no estimate): at the
    nodes off the better half (v > median) whose deterministic estimate under A exceeds tol
    (≤ 300 evenly spaced, and the 20 largest), the actual |v − v_ref| / max(|v_ref|, λ)."""
    import corpus

    found = {n: (b, o) for _g, n, b, _x, _t, o in problems(results)}
    for name in names:
        build, _ = found[name]
        p = build()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            s = gridlbc.solve(p)
            emb, lam = s.embedded, p.temperature
            g4 = embedded_grid(emb.solution.grid)
            s4 = gridlbc.solve(
                p.replace(grid=g4), error_estimate=False, dt=min(4 * s.diagnostics.dt, p.horizon)
            )
            mask = node_mask(s, "A")
            A.states_that_matter = patched(mask)
            try:
                est = E.embedded_estimate(s, emb.solution, s4, emb.pair, emb.excess)
            finally:
                A.states_that_matter = ORIGINAL
            upper = mask & ~node_mask(s, "M").ravel()
            X = s.grid.node_coordinates(np.flatnonzero(upper))
            v, _, _, local = est._read(s, X, 0.0)
            scale = np.maximum(np.abs(v), lam)
            det = np.maximum(np.maximum(local, est.floor * scale), est.excess_response(X)) / scale
            big = np.flatnonzero(det > TOL)
            if len(big) == 0:
                print(f"{name}: no upper-half node above tol")
                continue
            big = big[np.linspace(0, len(big) - 1, min(len(big), 300)).astype(int)]
            idx = np.unique(np.r_[big, np.argsort(-det)[:20]])
            fine = corpus.refine(p, 2)
            ref = gridlbc.solve(fine, error_estimate=False, dt=s.diagnostics.dt / 2).value(
                X[idx], 0.0
            )
        act = np.abs(v[idx] - ref) / np.maximum(np.abs(ref), lam)
        print(
            f"{name}: upper half {upper.sum()} nodes, {np.mean(det > TOL):.2f} above tol (floor "
            f"{est.floor:.3f}); at {len(idx)}: estimate median {np.median(det[idx]):.3f} max "
            f"{det[idx].max():.3f}; |v - v_2x| median {np.median(act):.3f} max {act.max():.3f}, "
            f"share > tol {np.mean(act > TOL):.2f}, share with estimate >= |v - v_2x|/2 "
            f"{np.mean(det[idx] >= act / 2):.2f}",
            flush=True,
        )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--collect", action="store_true")
    parser.add_argument("--table", action="store_true")
    parser.add_argument("--results", type=Path, default=HERE / "holdout")
    parser.add_argument("--only", nargs="*")
    parser.add_argument("--verify", nargs="*")
    args = parser.parse_args(argv)
    if args.collect:
        collect(args.results, args.only)
    if args.verify:
        verify(args.verify, args.results)
    elif args.table or not args.collect:
        table()


if __name__ == "__main__":
    main()
