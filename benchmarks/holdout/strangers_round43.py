"""Stranger round 43: COMBINATIONS of solutions on RANDOM problems (seed 43), public API only.

RESULTS (library commit b2da72c, worktree r43, 2026-12-07 14:16–15:00 UTC, one thread, the other
core busy): ``--run NAME`` of each draw as its own process (``timeout 600``, later 420);
r43_2d_hz_07 (λ 1.55, T 4.71) was stopped by the timeout unfinished (no record); the other 14 ran
(0.5–4 min each, most of it the certificates). Then ``--recheck r43_2d_hzfe_03 r43_2d_hzfe_04``
(seed 44) and ``--table``. Counts (``--table``):

- 14 problems (9 2-D with a horizon, 2 of them with an exit set; 2 3-D; 3 stationary 2-D first
  exits combining EXIT costs), 29 flows (14 "w", 14 "coord", 5 "sep", 4 "proj"; 3 of the "proj"
  have no composite: their weights make Σ w_i h_i ≤ 0 at some node), 240 (flow, state, t) pairs,
  236 trusted. > 10 % off (trusted): 34, all warned; SILENT 0. ê ≥ ½ err (or err < 1 %): 219 of
  236. UNDER-READS (err ≥ 1 %): 17, all in the two problems with an exit set AND a horizon, all
  explained by finding 1, all standing on the seed-44 recheck. OVER-READS (ê > 20× max(err, 1 %)):
  1, ``r43_2d_hz_06`` "w" t = 0 x1: err 2.38 %, ê 47.85 % (20.1×; the direct solve of the composite
  reads ê 44.7 % at err 2.97 %, so it is the solves' estimate, not the combination's). Only one
  flow was quiet: ``r43_2d_fe_13`` "coord" (errors 0.81–1.74 %). Exceptions: 0 from the library,
  except combine refusing projected weights with Σ w ≤ 0 (below). Stray numpy warnings: 4.

WHAT MAIN DID WITH THEM (2026-12-07, after the run): finding 1 is the superposition's own rule,
not a numerical error: the combination is exactly the task ``combined.problem`` states, whose
exit cost is the composite of the components' (g_E − λ log Σw for a shared g_E). A user combining
terminal costs expects g_E kept, so ``combine`` now warns where a task with a horizon and an exit
set has its shared exit cost moved (Σw ≠ 1), saying by how much (r43_2d_hzfe_03: "g_E − 6.791"
at Σw 26.6, "g_E − 2.868" for coordination, silent at Σw = 1); docs page first_exit says it.
The 17 under-reads were read against the task with g_E kept, not the task solved. Finding 2:
``solve_many``'s docstring corrected. Finding 3: the check of a combination reads its components
quietly (also eight UnderflowWarnings about "query states" from one combine call) and without the
numpy warnings. The refusal of Σw ≤ 0 now advises what fits projected weights.

FINDINGS

1. EXIT SET + HORIZON: ``combine`` of terminal-cost components is NOT the composite, though it
   says ``exact=True``. On a problem with an exit set (fixed exit cost g_E) and a horizon, z_i = h_i
   on E for every component, so Σ w_i z_i = (Σ w_i) exp(−g_E/λ) on E: the combination is the
   composite terminal cost WITH EXIT COST g_E − λ log Σ w_i, not with g_E. Verified in ONE
   ``solve_many(p, gs + [g_composite])`` call (/tmp/r43_exitcheck.py, recorded here): r43_2d_hzfe_03
   (λ 2.07, Box exit, g_E 0.405) "w" (Σw 26.6) at t = 0: combination [−4.849, −5.457, −3.659,
   −4.822], composite from the same call [−4.169, −3.101, −2.558, −4.209], composite with exit cost
   g_E − λ log Σw [−4.849, −5.457, −3.659, −4.822] (identical); with weights normalised to Σw = 1
   all three agree. Against the certified composite: "w" 14.6 / 76.4 / 43.6 / 13.2 % off (v*
   −4.233, −3.094, −2.549, −4.261; seed 44: −4.242, −3.145, −2.555, −4.261), ê 1.9 / 4.3 / 4.7 /
   1.8 %; "coord" (Σw 4) 33 / 88 / 51 / 30 % off, ê 5.2 / 13.7 / 10.2 / 4.9 %; the separately
   solved "sep" Combination the same (the implicit scheme, exact=True too); the DIRECT solve of
   the composite is within 0.2–1.6 %. r43_2d_hzfe_04 (λ 0.10, Σw 10.5): x0 183 % / 175 % off (of
   λ; v −0.132 vs v* 0.0526) at ê 45 % / 57 %. Counted as warned only because the components'
   solves and ``combine`` warn about RESOLUTION ("solve the components on a finer grid or with a
   smaller dt"), which is not the cause and would not fix it; the estimate Σ|α_i|ê_i cannot see
   it. Reproduce: ``--run r43_2d_hzfe_03`` (or the 20-line check in the final report).
2. ``solve_many``'s docstring is false with the default settings: "One per cost, each exactly as
   solve would return for problem.replace(terminal_cost=g_i)". For K > 1 it fits ONE shared
   reference (every solution's ``diagnostics.fitting`` sha256:6d6cfb9b…) where ``solve`` fits each
   cost its own: r43_2d_hz_00, t = 0, component 1 at x1: 12.85 (solve_many) vs 16.14 (solve),
   component 0 at x0: 3.50 vs 4.22 (for K = 1 they agree). Its cost: the exact CombinedSolution is
   less accurate than the Combination of separate default solves: r43_2d_hz_00 "w" x3 t = 0:
   17.6 % off (ê 21.9 %, warned) against "sep" 0.26 %; r43_2d_hz_06 "w" x3 8.5 % vs 2.7 %.
3. Stray numpy warnings from ``combine`` (its ``check_combination``) on r43_3d_hz_10 ("w" and
   "coord"): ``RuntimeWarning: invalid value encountered in multiply`` at
   gridlbc/accuracy/assessment.py:609 and ``invalid value encountered in subtract`` at :655, next to
   its UnderflowWarning (15 of 256 query states underflowed). Reproduce: ``--run r43_3d_hz_10``.

Other observations (not findings): the superposition on the shared-operator path holds to
rounding (the combination of ``solve_many(p, gs + composites)[:n]`` equals the composite solved
in that call, ``v_many_comb`` vs ``v_many`` in the records) wherever there is no exit set;
stationary first exits combining EXIT costs (r43_2d_fe_12/13/14) are exact against the direct
solve, as SPEC §9 says. ``project`` warned correctly every time (negative weights, sums far
from 1, residual 1); its weights match my own Gram solve (r43_2d_hz_01: [−1.051, 0.0011, 0.0022],
the raw Gram's condition 3.6e14 while ``Projection.condition`` reads 1.00005, the normalised one).
``combine`` then refuses Σw = −1.05 ("flip the signs or use weights=None"), although Σ w_i h_i > 0
at most nodes; r43_2d_hz_05's projected weights (sum 9.5e-7) give v = +inf at one state, with a
GridlbcWarning saying so.

What is drawn (``draw``, seed 43): round 39's ``gen`` (imported) for problems with a horizon
(kinds "hz" and "hzfe"; a "fe" draw is drawn again), round 41's ``gen`` for stationary first exits;
the grids capped (2-D ≤ 81 nodes per axis, 3-D ≤ 25) so that a default solve stays well under 20 s.
Each problem gets 2–4 COMPONENT costs g_i: with a horizon, terminal costs drawn like round 39's
(``TermCost``: a rotated quadratic, W eigenvalues log-uniform in [0.1, 4], centred uniformly in
±0.6 of the half-widths, one in three with a narrow dip); for a stationary first exit, EXIT
costs (constant, a quadratic about a point of E, or a wave, round 41's ``ExitCost``). Flows
(each is one combination, read at 4 states: round 39's/41's three or four plus the midpoint of
the first two component centres):

- "w": ``gridlbc.combine(solve_many(problem, gs), w)``, w log-uniform in [1e-2, 1e2];
- "coord": the same components, weights None (coordination, all ones);
- "sep" (every third problem): each component a separate default ``gridlbc.solve`` of
  ``problem.replace(terminal_cost=g_i)`` (``exit_cost=g_i``), weights those of "w" (a
  ``Combination``, not exact, unless the library says so);
- "proj" (every fourth problem): weights from ``gridlbc.project(target, gs, grid,
  temperature=λ)`` for a target cost drawn like the components; the combination is judged
  against the composite with THOSE weights (not against the target).

Truth of a flow: the composite problem, terminal (exit) cost g = −λ log Σ w_i exp(−g_i/λ) (round 26's
``composite_cost``, signed for projected weights), certified by round 39's ``certify_at`` (2000
samples, seed 43, richardson, reflect) with the policy of a finer solve of the composite (round
39's ``fine_scale``; Δt halved; all composites of a problem in one ``solve_many`` on the fine grid,
``error_estimate=False``) as proposal, at t = 0 and (horizon) t = T − 2Δt. Trusted: ESS ≥ 100 and
k̂ ≤ 0.7 (round 39's ``trusted``), and for stationary exits at most 1 % of paths unexited. Errors
relative to max(|v*|, λ); estimates ê (the combination's ``error_estimate(x, t)``) relative to
max(|v|, λ). Also recorded per pair: the DIRECT default solve of the composite (its v and ê),
and the composite solved by ``solve_many`` with the components' settings (one call for all
composites; superposition is exact only where the operator is shared: recorded, not judged).
Warnings: every warning of solve_many, the separate solves, combine, project, the direct solve;
GridlbcWarnings by category and text, everything else as "stray".

    cd /work/wt-r43 && PYTHONPATH=/work/wt-r43 NUMBA_NUM_THREADS=1 \\
        python benchmarks/holdout/strangers_round43.py --list | --run [NAMES] | --table \\
        | --recheck NAMES
"""

from __future__ import annotations

import json
import math
import sys
import time
import traceback
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import strangers_round39 as r39
import strangers_round41 as r41
from strangers_round25 import loguni
from strangers_round26 import composite_cost

import gridlbc
from gridlbc import Problem
from gridlbc.regions import Ball, Box

OUT = Path("/work/main/benchmarks/holdout/strangers_round43_results")  # gitignored there
SEED = 43
N2, N3, NFE = 10, 2, 3  # horizon 2-D, horizon 3-D, stationary first exits (2-D)
CAP = {2: 81, 3: 25}


# ================= costs ==========================================================================
class Const:
    def __init__(self, c0):
        self.c0 = float(c0)

    def __call__(self, x):
        return np.full(len(np.atleast_2d(x)), self.c0)


def cost_of(cs, periodic):
    """A component cost from its dict: {"kind": "term", "g": {...}} (round 39's TermCost),
    {"kind": "const", "c0"} or round 41's exit cost dicts ("quad", "sin")."""
    if cs["kind"] == "term":
        return r39.TermCost(dict(g=cs["g"], periodic=list(periodic)))
    if cs["kind"] == "const":
        return Const(cs["c0"])
    return r41.ExitCost(cs, periodic)


def flow_cost(spec, flow):
    """The composite cost of a flow: −λ log Σ w_i exp(−g_i/λ)."""
    gs = [cost_of(c, spec["periodic"]) for c in spec["comps"]]
    w = spec["flows"][flow]["w_truth"]
    return composite_cost(gs, w, spec["lam"])


# ================= building (round 39's and 41's, with the flow's composite cost) ===============
def build(spec, scale=1.0, widen=1.0, horizon="spec"):
    per = tuple(spec["periodic"])
    sysm = r39.RandSys(
        spec["A"], spec["a0"], spec["terms"], spec["b"], spec["beta"], spec["gk"], spec["M"], per
    )
    T = spec["T"] if horizon == "spec" else horizon
    flow = spec.get("flow")
    comp = flow_cost(spec, flow) if flow else cost_of(spec["comps"][0], per)
    kw = {}
    if isinstance(spec["exit"], dict):  # round 41's stationary exit: the components are exit costs
        kw = dict(exit=r41.region(spec["exit"]), exit_cost=comp)
    elif spec["exit"] is not None:  # round 39's exit with a horizon: fixed constant exit cost
        e = spec["exit"]
        kw = dict(
            exit=Ball(e[1], e[2]) if e[0] == "ball" else Box(e[1], e[2]), exit_cost=float(e[3])
        )
    return Problem(
        sysm,
        r39.make_grid(spec["box"], per, scale, widen),
        T,
        terminal_cost=None if T is None else comp,
        state_cost=r39.StateCost(spec),
        control_cost=np.asarray(spec["R"]),
        temperature=spec["lam"],
        **kw,
    )


r39.build = build  # round 39's certify_at() and fine_solve() build through it


def with_flow(spec, flow):
    s = dict(spec)
    s["flow"] = flow
    return s


# ================= the draw =======================================================================
def _cap(spec):
    d = spec["d"]
    for b in spec["box"]:
        per = b[0] == -math.pi and b[1] == math.pi
        if b[2] > CAP[d]:
            b[2] = CAP[d] - (CAP[d] % 2 if per else 1 - CAP[d] % 2)
    return spec


def term_draw(rng, spec):
    Ls = [hi for _, hi, _ in spec["box"]]
    d = spec["d"]
    per = spec["periodic"]
    h = [(hi - lo) / (n - (0 if i in per else 1)) for i, (lo, hi, n) in enumerate(spec["box"])]
    Q = r39.rand_orth(rng, d)
    g = dict(
        c=[float(rng.uniform(-0.6 * L, 0.6 * L)) for L in Ls],
        W=(Q @ np.diag([loguni(rng, 0.1, 4.0) for _ in range(d)]) @ Q.T).tolist(),
        dips=[],
    )
    if rng.random() < 1 / 3:
        g["dips"].append(
            dict(
                c=[float(rng.uniform(-0.5 * L, 0.5 * L)) for L in Ls],
                s=[loguni(rng, 0.7, 3.0) * hh for hh in h],
                D=loguni(rng, 0.5, 3.0),
            )
        )
    return dict(kind="term", g=g)


def exit_cost_draw(rng, spec):
    d = spec["d"]
    p0 = spec["exit"]["parts"][0]
    if p0[0] == "ball":
        ce = list(p0[1])
    else:
        ce = []
        for a, b in zip(p0[1], p0[2]):
            fa, fb = math.isfinite(a), math.isfinite(b)
            ce.append((a + b) / 2 if fa and fb else a if fa else b if fb else 0.0)
    ck = str(rng.choice(["const", "quad", "quad", "sin"]))
    if ck == "const":
        return dict(kind="const", c0=float(rng.uniform(0.0, 2.0)))
    if ck == "quad":
        Q = r39.rand_orth(rng, d)
        W = Q @ np.diag([loguni(rng, 0.1, 3.0) for _ in range(d)]) @ Q.T
        c = [v + float(rng.normal(0, 0.3)) for v in ce]
        return dict(kind="quad", c0=float(rng.uniform(0.0, 1.0)), c=c, W=W.tolist())
    per = spec["periodic"]
    h = [(hi - lo) / (n - (0 if i in per else 1)) for i, (lo, hi, n) in enumerate(spec["box"])]
    k = [
        float(rng.integers(-2, 3))
        if i in per
        else float(rng.uniform(-1, 1) * 2 * math.pi / (loguni(rng, 4.0, 20.0) * h[i]))
        for i in range(d)
    ]
    return dict(
        kind="sin",
        c0=float(rng.uniform(0.0, 0.5)),
        a=loguni(rng, 0.2, 2.0),
        k=k,
        phi=float(rng.uniform(0, 2 * math.pi)),
    )


def centre(cs):
    return cs["g"]["c"] if cs["kind"] == "term" else cs.get("c")


def gen(rng, kind, d, k):
    if kind == "fe":
        spec = r41.gen(rng, d, k)
    else:
        while True:
            spec = r39.gen(rng, d, k)
            if spec["kind"] != "fe":
                break
    spec = _cap(spec)
    spec["name"] = f"r43_{d}d_{spec['kind']}_{k:02d}"
    nc = int(rng.integers(2, 5))
    draw_one = exit_cost_draw if kind == "fe" else term_draw
    spec["comps"] = [draw_one(rng, spec) for _ in range(nc)]
    w = [float(10 ** rng.uniform(-2, 2)) for _ in range(nc)]
    flows = {
        "w": dict(w=w, w_truth=w, path="many"),
        "coord": dict(w=None, w_truth=[1.0] * nc, path="many"),
    }
    if k % 3 == 0:
        flows["sep"] = dict(w=w, w_truth=w, path="sep", truth_of="w")
    if k % 4 == 1:
        flows["proj"] = dict(target=draw_one(rng, spec), path="proj")
    spec["flows"] = flows
    X = [list(map(float, x)) for x in spec["X"]]
    c0, c1 = centre(spec["comps"][0]), centre(spec["comps"][1])
    if c0 is not None and c1 is not None:
        X.append([(a + b) / 2 for a, b in zip(c0, c1)])
    spec["X"] = X[:4]
    return spec


def draw():
    rng = np.random.default_rng(SEED)
    specs = [gen(rng, "hz", 2, k) for k in range(N2)]
    specs += [gen(rng, "hz", 3, N2 + k) for k in range(N3)]
    specs += [gen(rng, "fe", 2, N2 + N3 + k) for k in range(NFE)]
    return {s["name"]: s for s in specs}


# ================= warnings =======================================================================
def warn_split(w, stage):
    """(GridlbcWarnings as round 39 records them, every other warning as a stray record)."""
    lib = [dict(stage=stage, **x) for x in r41._r39_warnlist(w)]
    stray = [
        dict(
            stage=stage,
            category=x.category.__name__,
            message=str(x.message)[:300],
            where=f"{x.filename}:{x.lineno}",
        )
        for x in w
        if not issubclass(x.category, gridlbc.GridlbcWarning)
    ]
    return lib, stray


class Rec:
    def __init__(self):
        self.warn, self.stray, self.fail = [], [], []

    def call(self, stage, f, *a, **kw):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            try:
                out = f(*a, **kw)
            except Exception as ex:
                out = None
                self.fail.append(
                    dict(
                        stage=stage,
                        error=f"{type(ex).__name__}: {ex}"[:600],
                        tb=traceback.format_exc()[-2500:],
                    )
                )
        lib, stray = warn_split(w, stage)
        self.warn += lib
        self.stray += stray
        return out


def _arr(f, *a):
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return np.asarray(f(*a), float).tolist()
    except Exception as ex:  # a missing estimate is recorded, not fatal
        return f"{type(ex).__name__}: {ex}"[:300]


# ================= one problem ====================================================================
def run(name, spec):
    OUT.mkdir(parents=True, exist_ok=True)
    lam, per = spec["lam"], spec["periodic"]
    X = np.asarray(spec["X"], float)
    stationary = spec["T"] is None
    R = Rec()
    t0 = time.perf_counter()
    p = build(spec)
    gs = [cost_of(c, per) for c in spec["comps"]]
    key = "exit_cost" if stationary else "terminal_cost"
    comps = R.call("solve_many components", gridlbc.solve_many, p, gs, progress=False)
    rec = dict(name=name, spec=spec, shape=list(p.grid.shape), flows={})
    if comps is None:
        rec.update(warnings=R.warn, stray=R.stray, fails=R.fail)
        (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
        print(name, "RAISED", R.fail)
        return rec
    rec["seconds_many"] = time.perf_counter() - t0
    dt = None if stationary else float(comps[0].diagnostics.dt)
    rec["dt"] = dt
    ts = [0.0] if stationary else [0.0, spec["T"] - 2 * dt]
    comp_warn = list(R.warn)
    # projected weights
    for fl in spec["flows"].values():
        if fl["path"] == "proj":
            tgt = cost_of(fl["target"], per)
            kw = dict(where=p.exit) if stationary else {}
            w = R.call("project", gridlbc.project, tgt, gs, p.grid, temperature=lam, **kw)
            fl["w"] = None if w is None else np.asarray(w, float).tolist()
            fl["w_truth"] = fl["w"]
            if w is not None:
                hsum = sum(wi * np.exp(-g(p.grid.nodes()) / lam) for wi, g in zip(w, gs))
                fl["min_h_on_nodes"] = float(hsum.min())
    sep = None
    if any(fl["path"] == "sep" for fl in spec["flows"].values()):
        sep = [
            R.call(f"solve sep {i}", gridlbc.solve, p.replace(**{key: g}), progress=False)
            for i, g in enumerate(gs)
        ]
    n_warn_before_truth = len(R.warn)
    # the composites: direct default solves, one solve_many of all of them
    truth_flows = [
        f
        for f, fl in spec["flows"].items()
        if "truth_of" not in fl
        and fl["w_truth"] is not None
        and fl.get("min_h_on_nodes", 1.0) > 0  # Σ w_i h_i ≤ 0 somewhere: no composite cost
    ]
    comp_costs = [flow_cost(spec, f) for f in truth_flows]
    # components and composites in ONE call (one shared operator: superposition exact)
    direct_many = R.call(
        "solve_many composites", gridlbc.solve_many, p, gs + comp_costs, progress=False
    )
    direct = {}
    for f, g in zip(truth_flows, comp_costs):
        direct[f] = R.call(
            f"direct solve {f}", gridlbc.solve, p.replace(**{key: g}), progress=False
        )
    # fine composite solutions (the proposals)
    sc = r39.fine_scale(spec)
    pf = build(spec, scale=sc)
    t1 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fkw = {} if stationary else dict(dt=dt / 2)
        fine = gridlbc.solve_many(pf, comp_costs, error_estimate=False, progress=False, **fkw)
    rec["fine_seconds"] = time.perf_counter() - t1
    rec["fine_scale"] = sc
    truths = {}
    for j, f in enumerate(truth_flows):
        sf = with_flow(spec, f)
        truths[f] = []
        for t in ts:
            vt, info = r39.certify_at(sf, fine[j], X, t, seed=SEED)
            info["v_fine"] = np.asarray(fine[j].value(X, t)).tolist()
            truths[f].append((vt, info))
    # the combinations
    for f, fl in spec["flows"].items():
        fr = dict(path=fl["path"], w=fl.get("w"), reads=[])
        if fl.get("w_truth") is None:
            fr["skipped"] = "no weights"
            rec["flows"][f] = fr
            continue
        parts = sep if fl["path"] == "sep" else comps
        nw = len(R.warn)
        cmb = R.call(f"combine {f}", gridlbc.combine, parts, fl["w"])
        fr["combine_warnings"] = R.warn[nw:]
        if cmb is None:
            rec["flows"][f] = fr
            continue
        fr["exact"] = bool(getattr(cmb, "exact", False))
        fr["reason"] = str(getattr(cmb, "reason", ""))
        tf = fl.get("truth_of", f)
        if tf not in truth_flows:  # no composite: record what the combination says, unjudged
            fr["skipped"] = "Σ w_i h_i ≤ 0 at some node: no composite cost"
            fr["untruthed"] = [
                dict(
                    t=t,
                    v=np.asarray(R.call(f"value {f}", cmb.value, X, t), float).tolist(),
                    est=_arr(cmb.error_estimate, X, t),
                    v_nodes_nan=int(np.isnan(np.asarray(_arr(cmb.value, p.grid.nodes(), t))).sum()),
                )
                for t in ts
            ]
            fr["value_warnings"] = R.warn[nw:]
            rec["flows"][f] = fr
            continue
        k = truth_flows.index(tf)
        for kk, t in enumerate(ts):
            vt, info = truths[tf][kk]
            v = np.asarray(R.call(f"value {f}", cmb.value, X, t), float)
            e = _arr(cmb.error_estimate, X, t)
            dv = direct[tf]
            rd = dict(
                t=t,
                v=v.tolist(),
                est=e,
                truth=vt.tolist(),
                info=info,
                v_direct=_arr(dv.value, X, t) if dv is not None else None,
                est_direct=_arr(dv.error_estimate, X, t) if dv is not None else None,
                v_many=_arr(direct_many[len(gs) + k].value, X, t) if direct_many else None,
                v_many_comb=_arr(
                    lambda *a, _w=fl["w"]: gridlbc.combine(direct_many[: len(gs)], _w).value(*a),
                    X,
                    t,
                )
                if direct_many and fl["path"] != "sep"
                else None,
                alpha=_arr(cmb.blend_weights, X, t),
            )
            rd["err_rel"] = (np.abs(v - vt) / np.maximum(np.abs(vt), lam)).tolist()
            ee = np.asarray(e, float) if not isinstance(e, str) else np.full(len(X), np.nan)
            rd["est_rel"] = (ee / np.maximum(np.abs(v), lam)).tolist()
            if isinstance(rd["v_direct"], list):
                vd = np.asarray(rd["v_direct"])
                rd["err_direct"] = (np.abs(vd - vt) / np.maximum(np.abs(vt), lam)).tolist()
                ed = (
                    np.asarray(rd["est_direct"], float)
                    if isinstance(rd["est_direct"], list)
                    else np.nan
                )
                rd["est_direct_rel"] = (ed / np.maximum(np.abs(vd), lam) + 0 * vd).tolist()
            fr["reads"].append(rd)
        rec["flows"][f] = fr
    rec.update(
        warnings=R.warn,
        comp_warnings=comp_warn,
        n_warn_before_truth=n_warn_before_truth,
        stray=R.stray,
        fails=R.fail,
        seconds=time.perf_counter() - t0,
    )
    (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
    show(rec)
    return rec


def flow_warned(rec, f):
    """Warned for this flow: the components' solves (solve_many, or the separate solves for
    "sep"), project (for "proj"), and combine of this flow."""
    path = rec["flows"][f]["path"]
    for w in rec["warnings"]:
        st = w["stage"]
        if st == "solve_many components" and path != "sep":
            return True
        if st.startswith("solve sep") and path == "sep":
            return True
        if st == "project" and path == "proj":
            return True
        if st in (f"combine {f}", f"value {f}"):
            return True
    return False


def direct_warned(rec, f):
    tf = rec["spec"]["flows"][f].get("truth_of", f)
    return any(w["stage"] == f"direct solve {tf}" for w in rec["warnings"])


def show(rec):
    sp = rec["spec"]
    print(
        f"{rec['name']:18s} {tuple(rec['shape'])!s:13s} λ={sp['lam']:.3g} T={sp['T']} "
        f"n={len(sp['comps'])} {rec.get('seconds', 0):.0f}s (fine {rec.get('fine_seconds', 0):.0f}s ×"
        f"{rec.get('fine_scale')}) fails={len(rec.get('fails', []))} stray={len(rec.get('stray', []))}"
    )
    for f, fr in rec["flows"].items():
        print(
            f"  flow {f} ({fr['path']}) exact={fr.get('exact')} warned={flow_warned(rec, f)} "
            f"w={np.round(fr['w'], 3).tolist() if fr['w'] is not None else None} {fr.get('skipped', '')}"
        )
        for rd in fr["reads"]:
            for i in range(len(rd["v"])):
                inf = rd["info"]
                vd = rd["v_direct"][i] if isinstance(rd["v_direct"], list) else float("nan")
                vm = rd["v_many"][i] if isinstance(rd["v_many"], list) else float("nan")
                ed = rd.get("est_direct_rel", [float("nan")] * 9)[i]
                print(
                    f"    t={rd['t']:.4g} x{i} v={rd['v'][i]:.5g} v*={rd['truth'][i]:.5g}±"
                    f"{inf['se'][i]:.2g} err={rd['err_rel'][i]:.2%} ê={rd['est_rel'][i]:.2%} "
                    f"ess={inf['ess'][i]:.0f} k={inf['khat'][i]:.2f} | direct {vd:.5g} "
                    f"err={rd.get('err_direct', [float('nan')] * 9)[i]:.2%} ê={ed:.2%} | many {vm:.5g}"
                )
    for w in rec.get("warnings", []):
        print(f"    warn [{w['stage']}] {w['category']}: {w['message'][:250]}")
    for w in rec.get("stray", []):
        print(f"    STRAY [{w['stage']}] {w['category']} {w['where']}: {w['message'][:200]}")
    for x in rec.get("fails", []):
        print(f"    FAIL [{x['stage']}] {x['error']}")


# ================= table ==========================================================================
def trusted(rec, rd, i):
    inf = rd["info"]
    ok = inf["ess"][i] >= 100 and inf["khat"][i] <= 0.7 and np.isfinite(inf["khat"][i])
    if rec["spec"]["T"] is None:
        ok = ok and inf.get("unexited", [0] * 9)[i] <= 0.01
    return bool(ok)


def table():
    recs = [json.loads(f.read_text()) for f in sorted(OUT.glob("*.json"))]
    n = dict(pairs=0, trusted=0, big=0, silent=0, est=0, cov=0, under=0, over=0)
    under, over, silent, missing, rows = [], [], [], [], []
    for r in recs:
        for f, fr in r["flows"].items():
            wd = flow_warned(r, f)
            for rd in fr["reads"]:
                for i in range(len(rd["v"])):
                    n["pairs"] += 1
                    tr = trusted(r, rd, i)
                    err, est = rd["err_rel"][i], rd["est_rel"][i]
                    ed = rd.get("err_direct", [np.nan] * 9)[i]
                    edr = rd.get("est_direct_rel", [np.nan] * 9)[i]
                    tag = f"{r['name']} {f} t={rd['t']:.4g} x{i}"
                    wt = r["spec"]["flows"][f].get("w_truth") or [1.0]
                    if r["spec"]["kind"] == "hzfe" and abs(sum(wt) - 1) > 1e-9:
                        tag += f" [exit+horizon, Σw={sum(wt):.3g}]"
                    rows.append(
                        f"{tag:34s} {'T' if tr else '-'} err={err:7.2%} ê={est:8.2%} "
                        f"warned={int(wd)} | direct err={ed:7.2%} ê={edr:8.2%} "
                        f"dwarned={int(direct_warned(r, f))}"
                    )
                    if not tr:
                        continue
                    n["trusted"] += 1
                    if err > 0.10:
                        n["big"] += 1
                        if not wd:
                            n["silent"] += 1
                            silent.append(f"{tag} err {err:.2%} ê {est:.2%}")
                    if not np.isfinite(est):
                        missing.append(tag)
                        continue
                    n["est"] += 1
                    if est >= 0.5 * err or err < 0.01:
                        n["cov"] += 1
                    else:
                        n["under"] += 1
                        under.append(f"{tag} err {err:.2%} ê {est:.2%}")
                    if est > 20 * max(err, 0.01):
                        n["over"] += 1
                        over.append(f"{tag} err {err:.2%} ê {est:.2%}")
    print(*rows, sep="\n")
    print(
        f"problems {len(recs)}, pairs {n['pairs']}, trusted {n['trusted']}, > 10 % off "
        f"{n['big']}, silent {n['silent']}, covered ê ≥ ½ err (or err < 1 %) {n['cov']} of "
        f"{n['est']}, under-reads {n['under']}, over-reads (> 20× max(err, 1 %)) {n['over']}"
    )
    print("SILENT:", *silent, sep="\n  ")
    print("UNDER-READS:", *under, sep="\n  ")
    print("OVER-READS:", *over, sep="\n  ")
    print("estimate missing (trusted):", *missing, sep="\n  ")
    for r in recs:
        for x in r.get("fails", []):
            print("FAIL", r["name"], x["stage"], x["error"][:300])
        for x in r.get("stray", []):
            print("STRAY", r["name"], x["stage"], x["category"], x["where"], x["message"][:150])


def recheck(name, spec, seed=44):
    """A second certificate (another seed) at every pair of a run."""
    rec = json.loads((OUT / f"{name}.json").read_text())
    X = np.asarray(spec["X"], float)
    per_flow = [
        f for f, fl in spec["flows"].items() if "truth_of" not in fl and rec["flows"][f]["reads"]
    ]
    s2 = dict(spec)
    for f in per_flow:
        s2["flows"][f]["w_truth"] = rec["flows"][f]["w"] or [1.0] * len(spec["comps"])
    pf = build(s2, scale=r39.fine_scale(spec))
    costs = [flow_cost(s2, f) for f in per_flow]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        kw = {} if spec["T"] is None else dict(dt=rec["dt"] / 2)
        fine = gridlbc.solve_many(pf, costs, error_estimate=False, progress=False, **kw)
    for j, f in enumerate(per_flow):
        for rd in rec["flows"][f]["reads"]:
            vt, info = r39.certify_at(with_flow(s2, f), fine[j], X, rd["t"], seed=seed)
            rd["recheck"] = dict(truth=vt.tolist(), info=info)
            for i in range(len(X)):
                err = abs(rd["v"][i] - vt[i]) / max(abs(vt[i]), spec["lam"])
                print(
                    f"{name} {f} t={rd['t']:.4g} x{i}: v={rd['v'][i]:.5g} v*={rd['truth'][i]:.5g} "
                    f"seed {seed}: {vt[i]:.5g}±{info['se'][i]:.2g} ess={info['ess'][i]:.0f} "
                    f"k={info['khat'][i]:.2f} err={err:.2%} ê={rd['est_rel'][i]:.2%}"
                )
    (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))


def main(argv):
    specs = draw()
    if "--list" in argv:
        for n, s in specs.items():
            print(n, json.dumps(s))
    elif "--run" in argv:
        names = argv[argv.index("--run") + 1 :] or [
            n for n in specs if not (OUT / f"{n}.json").exists()
        ]
        for n in names:
            run(n, specs[n])
    elif "--recheck" in argv:
        for n in argv[argv.index("--recheck") + 1 :]:
            recheck(n, specs[n])
    elif "--table" in argv:
        table()
    else:
        print(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
