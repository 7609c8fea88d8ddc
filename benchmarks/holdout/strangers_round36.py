"""Stranger round 36: do certify's new warnings cry wolf, and did the bridge halving hurt?

RESULTS (library of main 46de7f5, branch r36, 2026-12-07, one thread, ``--all`` then ``--table``;
73 configs, 567 certificates, each ``richardson=True`` with seeds 0, 1, 2; the old library, 4a218de
before (4), via ``git archive 4a218de gridlbc`` and ``R36_OUT=.../old``). Counts are per
certificate (start state × seed); (2) per problem.

(1) check_unvisited: fired 63 — justified 48 (bimn 3/3; corpus goal_m2_3d, goal_off8, goal_off8_3d,
    goal_face_3d s1, goal_4d s2, goal4d_mid, goal_quarter s0–s1, exit_strip_between s1: many of
    them trusted, ESS ≈ n, nothing else warned: v̂ 0.1–0.6 above the exact value), FALSE 15, all
    on certificates nothing else warned of, all reproducible on every seed:
    * ``--run r25-sep2hz_02`` (9/9): S = 0.0085–0.010 (≈ 1 % of v), v̂ = the grid's own = truth:
      s0 (0.619, −0.579) v̂ 1.011 ± 0.0001, truth 1.0112; s1 1.007 vs 1.0078 (z −5, Δt bias,
      0.08 %); s2 2.489 vs 2.4868 (Δt bias 0.09 %; extrapolated 2.487, z_ext ≤ 0.5).
    * ``--run corpus-goal_in_cell`` s1 (1, −1, 0.5) (3/3): S = 0.103 (4.6 % of v), v̂ 2.215 ±
      0.00003 = the grid's own = truth 2.2148 (|z| ≤ 0.6): a start far from the goal, which the
      goal does not change, but S does.
    * ``--run corpus-goal_quarter`` s2 (−1, 0.5) (3/3): S = 0.000158 (0.01 % of v) against an SE of
      0.000024: v̂ 1.6223 = truth. S has no floor relative to v or λ, so a negligible S fires
      wherever the SE is smaller still.
    The response S bounds what the feature could change; at starts it does not reach (and where
    the grid solution is right) it still fires. A check that the feature is near the paths (or
    that S matters against max(|v|, λ)) would remove all three.
(2) callable exit crossed by noise (step_order ½; fires on every plain call): 13 problems, each
    with at least one start/seed off by > 3 SE in the plain call (exit1 z 57–59, exit2 z 22–24,
    sep2fe/hzfe z up to 53, cold_flow_exit, exit_strip_between); on notch_exit and toll_blind
    barely (1 of 9 at |z| 3.3–3.9, the rest within 3 SE). No false alarm worth the name. BUT the
    order-½ extrapolation made two right answers WRONG, silently (no gap warning):
    * ``--run corpus-toll_blind``: plain v̂ within 3 SE at 8/9 (s2 (−0.1, −1.0) seed 2: 0.8967 =
      truth 0.8967), extrapolated +0.04…+0.08 high on 8 of 9 (z_ext +1.5…+3.3; s2 seed 2: 0.9737,
      +8.6 %; s0 seed 2: 2.3547 vs 2.2954): v at 2Δt is LOWER than at Δt (the toll strip, w =
      0.008, is stepped over), so the bias is not the missed-crossing O(√Δt) the extrapolation
      assumes, and the gap check does not see it at 3 SE.
    * ``--run corpus-exit_strip_between`` s2 (1.5, 1.0): plain 1.424 (z 24), extrapolated
      1.301–1.320 vs 1.3682 (z_ext −4.2…−5.8, 3/3 seeds), no gap warning.
(3) extrapolation_gap: fired 65 — justified 42 (thin_wall s1, driftwall_kept_node, gain_band:
    certificates 25–30 % low that NOTHING else warned of — a valuable true alarm; r25-lq3_00,
    sliding_switch, cold_flow_exit beside ESS warnings), false beside ESS/k̂ warnings 4, FALSE on
    right answers with no other CertificateWarning 19:
    * zero SE (15): ``--run corpus-logistic_edge`` (12/12: no noise, SE 0; extrapolated 1.568 =
      truth 1.568 to 4 digits, gap 0.0014, "inf of that difference's SEs") and ``--run
      r25-sep2fe_02`` s0 (3/3: x0 inside the exit set, v = 0.1227 at every step, gap 5.55e-17).
      Each also raises a RuntimeWarning "divide by zero encountered in scalar divide" from the
      message (|gap| / SE). Needs a floor: gap against max(3 SE, rounding or a share of |v|).
    * ``--run r25-sep2hz_01`` s2 (−1.932, −2.639) (3/3 seeds, systematic): v = 2.877, 2.884, 2.903
      at Δt, 2Δt, 4Δt; extrapolated 2.870–2.871 vs truth 2.8710 (z_ext 0.2, −1.2, −2.0), gap
      0.003–0.0055 (3.1–5.6 SEs). The bias has a Δt² part: with c₁h + c₂h² the (Δt, 2Δt)
      extrapolation is off by 2c₂Δt² and the gap is 6c₂Δt², three times that; the warning says
      "off by about as much" and fires on an extrapolation that is right. Testing gap/3 (the
      fine extrapolation's own residual) against its SE would not fire here.
    * ``--run corpus-two_doors`` s0 seed 2 (1/9): gap 3.2 SEs, extrapolated 1.302 vs 1.2990 (z_ext
      2.8): chance (≈ 570 tests at 3 σ).
True alarms still fire: bimn (unvisited, 3/3, v̂ 0.2334 vs −0.3518), exit1 (step order, plain z
57–59; extrapolated now right, z_ext −1.8…0.6). duffing_exit_hot (0.58, 0.05) and a point mass by
a Ball at λ 1 and 3 (``pmball-l1.0``, ``-l3.0``, start (0.58, 0.05)) no longer need one: (4)
fixed them (duffing v̂ 0.931–0.949 vs dt-0.001 reference 0.9434, z −0.9…0.4; the old library
0.6 % … z −34.5; pmball-l1.0 z −2.1…−1.9 vs old −13.5…−14.1), so nothing warns and nothing
should. No true alarm was lost.
(4) bridge halving, shaped exits with exact truths, z of plain v̂ | of the extrapolation (new vs
old): flat Box exits (1-D, 2-D) IDENTICAL to the old library to every digit (plane detection
works; plain z 3–10 is the documented O(Δt), z_ext −2.6…1.8); two_doors identical; 3-D ball
(λ 0.3, 1, 2; exact and grid policies, 54 certificates) plain |z| ≤ 2.8, |z_ext| ≤ 2.5 (old ≤ 2.3
| 2.2); tiny_ball_cold (ESS/k̂-warned) plain z up to 5.6 new vs 3.8 old, z_ext ≤ 3.1 vs 1.9
(within its warned noise); three_doors |z_ext| ≤ 1.3 both. Nothing got worse. COST: a plain
certify of the 3-D Ball first exit, n = 2000, Δt 0.004 (``--time``): 2.1–2.4 s vs 0.70–0.84 s
before (×3); with richardson (third run included) 9–14 s vs 3.6–4.6 s per start; pmball 3.4 s vs
0.6 s, duffing 5.9 s vs 1.3 s. Flat boxes: unchanged.

Not run / caveats: verdicts are recomputed in ``--table`` (an SE of 0 gets a floor of 0.1 % of
max(|v|, λ)); reference values of pmball and duffing are certificates at Δt/8 of the same
library (not exact); r25 LQ draws with the default grid policy were mostly ESS/k̂-warned
(no new warning on them was false).

Mechanisms (library of main 46de7f5): (1) ``check_unvisited`` (a grid solution that drew samples
is blind to a sub-cell cost feature and v̂* agrees with it); (2) a callable exit set crossed by
noise (plain certify warns of O(√Δt); richardson extrapolates at order ½); (3) richardson's third
run at 4Δt (``extrapolation_gap`` > 3 SE warns); (4) the Brownian bridge halved near curved
shaped exits.

Every run is ONE ``certify(problem, policy, x0, richardson=True, seed=s)`` per start state, the
policy the problem's default grid solve (or an exact/good policy where stated), default
``proposal="auto"`` and ``n_samples``: the Δt run of a richardson certificate is the plain
certificate at that seed, and it is the one ``check_unvisited`` reads, so (1) and (3) are seen in
one call; (2) fires in a plain call exactly where ``step_order(problem) < 1`` (read directly).
A warning is JUSTIFIED where the value it warns about is off from the truth: (1) the plain v̂ off
by > 3 SE and > 0.5 % of max(|v|, λ) (or the extrapolated one by > 3 of its SEs); (2) the plain v̂
off by > 3 SE; (3) the extrapolated value off by > 3 of its SEs. Otherwise a FALSE ALARM.

    cd /work/main && PYTHONPATH=/work/wt-r36 NUMBA_NUM_THREADS=1 \
        python benchmarks/holdout/strangers_round36.py --list | --run NAME... | --all | --table
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem
from gridlbc.regions import Ball, Box
from gridlbc.systems import LinearSystem, PointMass

sys.path.insert(0, str(Path(__file__).parent))
import corpus
import strangers_round25 as r25
import strangers_round35 as r35

OUT = Path(
    os.environ.get("R36_OUT", "/work/main/benchmarks/holdout/strangers_round36_results")
)  # gitignored there; R36_OUT for a run of the library before (4) (git archive 4a218de)
TRUTHS = json.loads((Path(__file__).parent / "truths.json").read_text())["members"]
SEEDS = tuple(int(s) for s in os.environ.get("R36_SEEDS", "0,1,2").split(","))
_DRAW: dict = {}


def draw():
    """Round 25's draws (cached: drawing them is slow)."""
    if not _DRAW:
        _DRAW.update(r25.draw())
    return _DRAW


def _solve(p):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return gridlbc.solve(p)


# ================= configs: () -> dict(problem, policy, X, truth, truth_se, kw, group) ==========
def _r25(name):
    spec = draw()[name]
    p = r25.build(spec)
    X = np.asarray(spec["X"], float)
    tr = r25.truth_for(spec, X, [0.0])[0.0]
    kw = {}
    if p.horizon is None:
        kw = dict(dt=0.004, max_time=30.0)
    return dict(problem=p, policy=_solve(p).policy, X=X, truth=np.asarray(tr[0]),
                truth_se=np.asarray(tr[1]), kw=kw, group="A")  # fmt: skip


def _r35(name, kind):
    spec = r35.problems()[name]
    p = r35.build(spec)
    kw = {}
    if spec["family"] == "exit":
        kw = dict(dt=spec["dt"], max_time=spec["max_time"])
    pol = _solve(p).policy if kind == "grid" else r35.make_policy(spec, kind)
    return dict(problem=p, policy=pol, X=np.array([spec["x0"]]), truth=np.array([r35.truth(spec)]),
                truth_se=np.zeros(1), kw=kw, group="B" if name in ("bimn", "exit1") else "A")  # fmt: skip


def _corpus(name):
    m = corpus.BY_NAME[name]
    p = m.build()
    states = TRUTHS[name]["states"]
    X = np.array([s["x"] for s in states])
    vt = np.array([s.get("v_extrapolated", s["v"]) for s in states])
    se = np.array([s.get("se_extrapolated", s["se"]) or 0.0 for s in states])
    kw = {}
    if p.horizon is None:
        kw = dict(dt=m.cert_dt, max_time=m.max_time or 30.0)
    return dict(problem=p, policy=_solve(p).policy, X=X, truth=vt, truth_se=se, kw=kw, group="A")


def ball3d(lam=1.0, q=0.5, R=1.0, r=0.5, n=41, L=3.0, x0=((1.2, 0, 0), (0.8, 0.3, 0), (2, 1, 0.5))):
    """3-D Brownian motion, constant q, into a ball of radius r at 0: v = λ log(ρ/r) +
    (ρ − r)√(2qR), u* = −R⁻¹(λ/ρ + √(2qR)) ρ̂ (exact on R³: boundary "free")."""
    p = Problem(
        LinearSystem(np.zeros((3, 3)), np.eye(3)),
        Grid([Axis(-L, L, n)] * 3),
        None,
        state_cost=lambda x, q=q: q + 0.0 * x[:, 0],
        control_cost=R * np.eye(3),
        temperature=lam,
        exit=Ball([0.0, 0.0, 0.0], r),
        exit_cost=0.0,
    )
    X = np.array(x0, float)
    rho = np.linalg.norm(X, axis=1)
    vt = lam * np.log(rho / r) + (rho - r) * math.sqrt(2 * q * R)

    def exact(x, t):
        x = np.asarray(x, float)
        rr = np.maximum(np.linalg.norm(x, axis=1, keepdims=True), 1e-9)
        return -(lam / rr + math.sqrt(2 * q * R)) * x / rr / R

    return p, X, vt, exact


def _ball3d(lam, policy):
    p, X, vt, exact = ball3d(lam=lam)
    pol = exact if policy == "exact" else _solve(p).policy
    return dict(problem=p, policy=pol, X=X, truth=vt, truth_se=np.zeros(len(X)),
                kw=dict(dt=0.004, max_time=30.0, boundary="free"), group="C")  # fmt: skip


def flat_box(d, lam, policy):
    """ẋ = u in d = 1 or 2, q = 1, R = 1, exit Box x₀ ≥ 1 (a flat face): v = √2 (1 − x₀)."""
    axes = [Axis(-3.0, 1.5, 91)] + [Axis(-3.0, 3.0, 61)] * (d - 1)
    lo, hi = [1.0] + [-50.0] * (d - 1), [50.0] * d
    p = Problem(
        LinearSystem(np.zeros((d, d)), np.eye(d)),
        Grid(axes),
        None,
        state_cost=lambda x: 1.0 + 0.0 * x[:, 0],
        control_cost=np.eye(d),
        temperature=lam,
        exit=Box(lo, hi),
        exit_cost=0.0,
    )
    X = np.array([[-0.5] + [0.3] * (d - 1), [0.9] + [0.0] * (d - 1), [0.99] + [0.0] * (d - 1)])
    vt = math.sqrt(2.0) * (1.0 - X[:, 0])
    u = np.zeros(d)
    u[0] = math.sqrt(2.0)
    pol = (lambda x, t: np.tile(u, (len(x), 1))) if policy == "exact" else _solve(p).policy
    return dict(problem=p, policy=pol, X=X, truth=vt, truth_se=np.zeros(3),
                kw=dict(dt=0.01, max_time=20.0, boundary="free"), group="C")  # fmt: skip


def pm_ball(lam, x0, dt=0.01):
    """A point mass (noise on the velocity only) into a Ball exit, q = 0.5, λ 1–3, started next
    to the ball (within a step's spread along the velocity); reference: the same certificate at
    dt/8 (richardson extrapolated)."""
    p = Problem(
        PointMass(1.0),
        Grid([Axis(-3.0, 3.0, 121), Axis(-4.0, 4.0, 121)]),
        None,
        state_cost=lambda x: 0.5 + 0.0 * x[:, 0],
        control_cost=np.eye(1),
        temperature=lam,
        exit=Ball([1.0, 0.0], 0.4),
        exit_cost=0.0,
    )
    return dict(problem=p, policy=_solve(p).policy, X=np.array([x0], float), truth=None,
                truth_se=None, kw=dict(dt=dt, max_time=30.0), group="B", ref_dt=dt / 8)  # fmt: skip


def _r34_duffing():
    import strangers_round34 as r34

    spec = r34.problems()["duffing_exit_hot_side"]
    p = spec["p"]
    return dict(problem=p, policy=_solve(p).policy, X=np.array([[0.58, 0.05]]), truth=None,
                truth_se=None, kw=dict(dt=0.008, max_time=30.0), group="B", ref_dt=0.001)  # fmt: skip


def configs():
    C = {}
    D = draw()
    for d in (2, 3, 4):
        for k in [x for x, s in D.items() if s["family"] == "lq" and s["d"] == d][:3]:
            C[f"r25-{k}"] = lambda k=k: _r25(k)
    for kind in ("hz", "fe", "hzfe"):
        for k in [x for x, s in D.items() if s["family"] == "sep" and s["kind"] == kind][:3]:
            C[f"r25-{k}"] = lambda k=k: _r25(k)
    for name in ("lq1", "pm2", "lq3", "lq4", "lq2tiny"):
        C[f"r35-{name}-exact"] = lambda name=name: _r35(name, "exact")
        C[f"r35-{name}-grid"] = lambda name=name: _r35(name, "grid")
    C["r35-exit2-exact"] = lambda: _r35("exit2", "exact")
    C["r35-bimn-grid"] = lambda: _r35("bimn", "grid")
    C["r35-exit1-exact"] = lambda: _r35("exit1", "exact")
    C["r35-exit1-grid"] = lambda: _r35("exit1", "grid")
    for name, rec in TRUTHS.items():
        m = corpus.BY_NAME.get(name)
        if m is None or m.time != 0 or "average" in rec["problem"]:
            continue
        exact = all(s["se"] == 0 for s in rec["states"])
        if exact or name in ("goal_in_cell", "pinpoint_goal", "thin_wall", "narrow_goal", "dock"):
            C[f"corpus-{name}"] = lambda name=name: _corpus(name)
    for lam in (0.3, 1.0, 2.0):
        for pol in ("exact", "grid"):
            C[f"ball3d-l{lam}-{pol}"] = lambda lam=lam, pol=pol: _ball3d(lam, pol)
    for d in (1, 2):
        for pol in ("exact", "grid"):
            C[f"flat{d}d-{pol}"] = lambda d=d, pol=pol: flat_box(d, 0.2, pol)
    for lam in (1.0, 3.0):
        C[f"pmball-l{lam}"] = lambda lam=lam: pm_ball(lam, [0.58, 0.05])
    C["duffing_exit_hot_side"] = _r34_duffing
    return C


# ================= run ============================================================================
KINDS = {
    "unvisited": "costs have a feature narrower than a cell",
    "steporder": "not a gridlbc.regions shape",
    "gap": "does not shrink as dt",
}


def _kind(message):
    for k, s in KINDS.items():
        if s in message:
            return k
    return "other"


def certify_one(p, pol, x, seed, kw, richardson=True):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        c = gridlbc.certify(p, pol, x, seed=seed, progress=False, richardson=richardson, **kw)
        sec = time.perf_counter() - t0
    ws = [(_kind(str(m.message)), str(m.message)[:400]) for m in w]
    ws = [m for m in ws if m[0] != "other" or "Certificate" in m[1] or True]
    return c, ws, sec


def run(name, cfg_fn):
    cfg = cfg_fn()
    p, pol, X = cfg["problem"], cfg["policy"], cfg["X"]
    lam = p.temperature
    order = getattr(gridlbc.certificate, "step_order", lambda p: 1.0)(p)
    refs = cfg["truth"]
    ref_se = cfg["truth_se"]
    if refs is None:  # a fine-step certificate is the reference
        refs, ref_se = [], []
        for x in X:
            kw = dict(cfg["kw"], dt=cfg["ref_dt"])
            c, _, _ = certify_one(p, pol, x, 99, kw)
            refs.append(c.extrapolated_value)
            ref_se.append(c.extrapolated_value_se)
        refs, ref_se = np.array(refs), np.array(ref_se)
    rows = []
    for i, x in enumerate(X):
        for seed in SEEDS:
            try:
                c, ws, sec = certify_one(p, pol, x, seed, cfg["kw"])
            except Exception as e:  # report, do not stop
                rows.append(dict(state=i, seed=seed, error=f"{type(e).__name__}: {e}"[:300]))
                continue
            vt, st = float(refs[i]), float(ref_se[i])
            v, se = float(c.optimal_value), float(c.optimal_value_se)
            ext, ext_se = float(c.extrapolated_value), float(c.extrapolated_value_se)
            z = (v - vt) / max(math.hypot(se, st), 1e-300)
            z_ext = (ext - vt) / max(math.hypot(ext_se, st), 1e-300)
            tol = 0.005 * max(abs(vt), lam)
            plain_off = abs(z) > 3 and abs(v - vt) > tol
            ext_off = abs(z_ext) > 3
            kinds = sorted({k for k, _ in ws})
            verdict = {}
            if "unvisited" in kinds:
                verdict["unvisited"] = plain_off or ext_off
            if "gap" in kinds:
                verdict["gap"] = ext_off
            if order < 1:
                verdict["steporder"] = abs(z) > 3
            rows.append(
                dict(
                    state=i, x=np.asarray(x).tolist(), seed=seed, truth=vt, truth_se=st, v=v,
                    se=se, ext=ext, ext_se=ext_se, gap=float(getattr(c, "extrapolation_gap", None) or np.nan), z=z,
                    z_ext=z_ext, ess=float(c.effective_sample_size), k=float(c.pareto_k),
                    trusted=bool(c.trusted), seconds=sec, kinds=kinds, verdict=verdict,
                    warnings=[m for _, m in ws],
                )
            )  # fmt: skip
    rec = dict(name=name, group=cfg["group"], lam=lam, order=order, kw=str(cfg["kw"]), rows=rows)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
    return rec


def table(out=OUT):
    """Per (group, mechanism): fired, justified, false alarms on a certificate that nothing else
    warned of ("alone"), and false alarms beside an ESS / k̂ / unexited warning ("redundant").
    (2) is one warning per problem: counted per problem, justified where any start and seed's
    plain v̂ was off by > 3 SE."""
    counts = {}
    for f in sorted(out.glob("*.json")):
        rec = json.loads(f.read_text())
        rows = [r for r in rec["rows"] if "error" not in r]
        for r in rec["rows"]:
            if "error" in r:
                print(rec["name"], "ERROR", r["error"])
        if rows and "steporder" in rows[0]["verdict"]:
            ok = any(r["verdict"]["steporder"] for r in rows)
            c = counts.setdefault((rec["group"], "steporder/problem"), [0, 0, 0, 0])
            c[0] += 1
            c[1 if ok else 2] += 1
            zs = " ".join(f"{r['z']:.1f}" for r in rows)
            print(f"{rec['name']} steporder {'JUSTIFIED' if ok else 'NOT NEEDED'} plain z: {zs}")
        for r in rows:
            floor = 1e-3 * max(abs(r["truth"]), rec["lam"])  # an SE of 0 (no noise, x0 in E)
            ext_off = abs(r["ext"] - r["truth"]) > max(
                3 * math.hypot(r["ext_se"], r["truth_se"]), floor
            )
            if "gap" in r["verdict"]:
                r["verdict"]["gap"] = ext_off
            if "unvisited" in r["verdict"]:
                r["verdict"]["unvisited"] = ext_off or (
                    abs(r["v"] - r["truth"])
                    > max(3 * math.hypot(r["se"], r["truth_se"]), 5 * floor)
                )
            for k, ok in r["verdict"].items():
                if k == "steporder":
                    continue
                c = counts.setdefault((rec["group"], k), [0, 0, 0, 0])
                c[0] += 1
                other = "other" in r["kinds"]
                c[1 if ok else (3 if other else 2)] += 1
                if not ok:
                    print(f"{rec['name']} s{r['state']} seed{r['seed']} {k} "
                          f"FALSE{' (redundant)' if other else ''} v={r['v']:.4g}±{r['se']:.2g} "
                          f"ext={r['ext']:.4g}±{r['ext_se']:.2g} gap={r['gap']:.3g} "
                          f"truth={r['truth']:.4g} z={r['z']:.1f} z_ext={r['z_ext']:.1f}")  # fmt: skip
    for key, (n, ok, bad, red) in sorted(counts.items()):
        print(key, f"fired {n} justified {ok} false-alone {bad} false-redundant {red}")


def main(argv):
    C = configs()
    if "--list" in argv:
        print("\n".join(C))
    if "--run" in argv:
        for name in argv[argv.index("--run") + 1 :]:
            if name.startswith("--"):
                break
            t0 = time.time()
            run(name, C[name])
            print(name, f"{time.time() - t0:.0f}s", flush=True)
    if "--all" in argv:
        for name in C:
            if (OUT / f"{name}.json").exists():
                continue
            t0 = time.time()
            try:
                run(name, C[name])
            except Exception as e:  # keep going
                print(name, "FAILED", type(e).__name__, str(e)[:200], flush=True)
                continue
            print(name, f"{time.time() - t0:.0f}s", flush=True)
    if "--time" in argv:  # plain certify of a Ball first exit, n = 2000 (after a warm-up)
        p, X, vt, exact = ball3d(lam=1.0)
        for rep in range(3):
            t0 = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                c = gridlbc.certify(p, exact, X[0], n_samples=2000, dt=0.004, max_time=30.0,
                                    boundary="free", seed=rep, progress=False, proposal=None)  # fmt: skip
            print(f"ball3d certify n=2000 dt=0.004 plain: {time.perf_counter() - t0:.2f}s "
                  f"v={c.optimal_value:.4f}±{c.optimal_value_se:.4f} truth={vt[0]:.4f}")  # fmt: skip
    if "--table" in argv:
        table()


if __name__ == "__main__":
    main(sys.argv[1:])
