"""Stranger round 30: UNITS (public API only; SPEC §1, §6, §7, §9, §10).

RESULTS: (filled in at the end of the round)

    cd /work/wt-r30 && PYTHONPATH=/work/wt-r30 NUMBA_NUM_THREADS=1 \
        python benchmarks/holdout/strangers_round30.py --list | --run [NAMES] | --table
"""

from __future__ import annotations

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

import corpus  # noqa: E402
import strangers_round25 as r25  # noqa: E402

import gridlbc  # noqa: E402
from gridlbc import Axis, Grid, Problem  # noqa: E402
from gridlbc.systems import ControlAffineSystem  # noqa: E402

OUT = Path("/work/main/benchmarks/holdout/strangers_round30_results")  # gitignored there
TRUTHS = json.loads((HERE / "truths.json").read_text())["members"]


# ================= the change of units ===========================================================
class Scaled(ControlAffineSystem):
    """The system in new units: x = s·y (per axis), t' = τ·t. a'(x) = s·a(x/s)/τ, B'(x) =
    s·B(x/s) (row-wise); the control in new time is u/τ, paid with R' = τR."""

    def __init__(self, inner, s, tau):
        self.inner, self.s, self.tau = inner, np.asarray(s, float), float(tau)
        self.state_dim, self.control_dim = inner.state_dim, inner.control_dim
        self.state_names = tuple(getattr(inner, "state_names", ()))
        self.angle_axes = tuple(getattr(inner, "angle_axes", ()))

    def drift(self, x):
        x = np.asarray(x, float)
        return self.s * np.asarray(self.inner.drift(x / self.s), float) / self.tau

    def input_matrix(self, x):
        x = np.asarray(x, float)
        return self.s[None, :, None] * np.asarray(self.inner.input_matrix(x / self.s), float)


def rescale(p: Problem, s=1.0, c=1.0, tau=1.0) -> Problem:
    """``p`` in new units: space x = s·y (scalar or per axis), cost ×c (λ ×c), time t' = τt."""
    d = p.state_dim
    s = np.broadcast_to(np.asarray(s, float), (d,)).copy()
    axes = [Axis(a.lo * sk, a.hi * sk, a.n, a.periodic, a.name) for a, sk in zip(p.grid.axes, s)]
    kw = dict(control_cost=np.asarray(p.control_cost) * c * tau, temperature=p.temperature * c)
    if p.state_cost is not None:
        q = p.state_cost
        kw["state_cost"] = lambda x: (c / tau) * np.asarray(q(np.asarray(x) / s), float)
    if p.terminal_cost is not None:
        g = p.terminal_cost
        kw["terminal_cost"] = lambda x: c * np.asarray(g(np.asarray(x) / s), float)
    if p.exit is not None:
        kw["exit"] = lambda x: p.exit_mask(np.asarray(x) / s)
        kw["exit_cost"] = lambda x: c * p.exit_values(np.asarray(x) / s)
    h = p.horizon
    horizon = h if (h is None or isinstance(h, str)) else float(h) * tau
    return Problem(Scaled(p.system, s, tau), Grid(axes), horizon, **kw)


def transforms(p: Problem) -> dict:
    d = p.state_dim
    half = max(max(abs(a.lo), abs(a.hi)) for a in p.grid.axes)
    aniso = np.array([1e-2, 10.0, 1e3, 0.1])[:d]
    si = np.array([1e-3, 100.0, 0.05, 1e3])[:d]
    return {
        "id": dict(),
        "s1e-3": dict(s=1e-3),
        "s1e3": dict(s=1e3),
        "c1e4": dict(c=1e4),
        "c1e-3": dict(c=1e-3),
        "tau3600": dict(tau=3600.0),
        "tau1e-2": dict(tau=1e-2),
        "aniso": dict(s=aniso),
        "box5mm": dict(s=0.005 / half),
        "si": dict(s=si, c=1e4, tau=3600.0),
        "s1e-6": dict(s=1e-6),
        "c1e-6": dict(c=1e-6),
        "c1e8": dict(c=1e8),
        "tau3e7": dict(tau=3.15e7),
        "tau1e-6": dict(tau=1e-6),
        "aniso8": dict(s=np.array([1e-4, 1e4, 1e-4, 1e4])[:d]),
        "tiny": dict(s=1e-5, c=1e-5, tau=1e-5),
        "huge": dict(s=1e5, c=1e6, tau=1e7),
        "c1e-12": dict(c=1e-12),
        "c1e-15": dict(c=1e-15),
        "year_micro": dict(c=1e-6, tau=3.15e7),
    }


# ================= base problems =================================================================
def _corpus(name):
    m = corpus.BY_NAME[name]

    def truth(X, t):
        rec = TRUTHS.get(name)
        if rec is None:
            return None
        return np.array([st.get("v_extrapolated", st["v"]) for st in rec["states"]])

    return dict(build=m.build, X=np.asarray(m.states, float), t=float(m.time), truth=truth)


_R25 = None


def _r25(name):
    def spec():
        global _R25
        if _R25 is None:
            _R25 = r25.draw()
        return _R25[name]

    def truth(X, t):
        sp = spec()
        if sp["family"] == "lq":
            return r25.lq_value(sp, X, t)
        tr = r25.truth_for(sp, X, [t])[t]
        return np.asarray(tr[0], float)

    return dict(
        build=lambda: r25.build(spec()),
        X=None,
        t=0.0,
        truth=truth,
        spec=spec,
    )


def _user_lq(A, B, R, Wq, WT, lam, T, L, n, X, cq=None, cT=None):
    """An LQ problem as an engineer writes it in SI units (a box of millimetres, ...): not an
    exact rescaling of anything, its truth the Riccati solution (SPEC §6)."""
    d = len(L)
    sp = dict(
        family="lq",
        d=d,
        A=np.asarray(A, float).tolist(),
        B=np.asarray(B, float).tolist(),
        R=np.atleast_2d(R).tolist(),
        Wq=np.asarray(Wq, float),
        WT=np.asarray(WT, float),
        cq=list(cq if cq is not None else np.zeros(d)),
        cT=list(cT if cT is not None else np.zeros(d)),
        lam=lam,
        T=T,
        L=list(L),
        n=list(n),
        X=np.asarray(X, float).tolist(),
    )
    return dict(
        build=lambda: r25.build_lq(sp),
        X=np.asarray(X, float),
        t=0.0,
        truth=lambda X, t: r25.lq_value(sp, X, t),
        spec=lambda: sp,
    )


_PM_A, _PM_B = [[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]]
_MM = [[0.002, 0.01], [0.0, 0.0], [-0.004, 0.03]]

USER = {
    # PointMass, box ±5 mm × ±5 cm/s, g = 1e4 x² + 1e2 v², everything else default (λ = 1, R = 1)
    "pm_mm_default": _user_lq(
        _PM_A,
        _PM_B,
        1.0,
        np.zeros((2, 2)),
        np.diag([1e4, 1e2]),
        1.0,
        1.0,
        [0.005, 0.05],
        [101, 101],
        _MM,
    ),
    # the same with the noise the box was drawn for (λ = 1e-6)
    "pm_mm_cold": _user_lq(
        _PM_A,
        _PM_B,
        1.0,
        np.zeros((2, 2)),
        np.diag([1e4, 1e2]),
        1e-6,
        1.0,
        [0.005, 0.05],
        [101, 101],
        _MM,
    ),
    # λ = 1e-3 with costs ×1e-3 (R = 1e-3), a horizon of an hour, a box of ±5 mm
    "int_mm_hour": _user_lq(
        np.zeros((2, 2)),
        np.eye(2),
        1e-3 * np.eye(2),
        1e-3 * np.eye(2) * 1e2,
        1e-3 * np.eye(2) * 1e4,
        1e-3,
        3600.0,
        [0.005, 0.005],
        [101, 101],
        [[0.002, 0.001], [0.0, 0.0], [-0.004, 0.004]],
    ),
    # costs of 1e4 (a euro per ...), λ = 0.01, box ±5 mm
    "int_mm_euro": _user_lq(
        np.array([[-0.5, 0.0], [0.0, 0.0]]),
        np.eye(2),
        np.eye(2) * 1e-4,
        np.zeros((2, 2)),
        np.eye(2) * 1e4 * 1e4,
        0.01,
        1.0,
        [0.005, 0.005],
        [101, 101],
        [[0.002, 0.001], [0.0, 0.0], [-0.004, 0.004]],
    ),
}

BASES = {
    **USER,
    "narrow_goal": _corpus("narrow_goal"),
    "notch_exit": _corpus("notch_exit"),
    "two_doors": _corpus("two_doors"),
    "well_torus_average": _corpus("well_torus_average"),
    "cold_ou_average": _corpus("cold_ou_average"),
    "goal_face_3d": _corpus("goal_face_3d"),
    "goal_4d": _corpus("goal_4d"),
    "hot_rotor": _corpus("hot_rotor"),
    "cheap_control": _corpus("cheap_control"),
    "vortex": _corpus("vortex"),
    "comb_torus": _corpus("comb_torus"),
    "gust_between_nodes": _corpus("gust_between_nodes"),
    "toll_strip": _corpus("toll_strip"),
    "lq2_00": _r25("lq2_00"),
    **{
        n: _corpus(n)
        for n in (
            "cold_flow_exit",
            "tiny_ball_cold",
            "exit_late",
            "exit_late_cold",
            "exit_strip_between",
            "driftwall_kept_node",
            "relative_value_cold",
            "pair_average_4d",
            "notch_exit_horizon",
            "toll_blind",
            "three_doors",
            "logistic_edge",
            "well_face",
            "pit_drift",
            "mass_pit",
            "hot_band",
            "dock",
        )
    },
    "lq2_03": _r25("lq2_03"),
    "lq3_00": _r25("lq3_00"),
}


def _warnlist(caught):
    out = []
    for w in caught:
        msg = str(w.message)
        out.append(
            dict(
                category=w.category.__name__,
                gridlbc=issubclass(w.category, gridlbc.GridlbcWarning),
                message=msg[:400],
                shape=re.sub(r"[-+]?\d[\d.,]*(e[-+]?\d+)?", "#", msg)[:400],
            )
        )
    return out


def one(p: Problem, X, t, tr: dict) -> dict:
    s = np.broadcast_to(np.asarray(tr.get("s", 1.0), float), (p.state_dim,))
    c, tau = float(tr.get("c", 1.0)), float(tr.get("tau", 1.0))
    q = rescale(p, **tr) if tr is not None else p
    Xs, ts = X * s, t * tau
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        start = time.perf_counter()
        sol = gridlbc.solve(q)
        secs = time.perf_counter() - start
        v = np.asarray(sol.value(Xs, ts), float).reshape(-1) / c
        try:
            e = np.asarray(sol.error_estimate(Xs, ts), float).reshape(-1) / c
        except Exception as exc:
            e = None
            err = repr(exc)
        else:
            err = None
    diag = sol.diagnostics
    dt = getattr(diag, "dt", None)
    rec = dict(
        v=v.tolist(),
        est=None if e is None else e.tolist(),
        est_error=err,
        warnings=_warnlist(caught),
        seconds=secs,
        dt=None if dt is None else float(dt) / tau,
        steps=getattr(diag, "steps", None),
        lam=p.temperature,
    )
    ac = getattr(sol, "average_cost", None)
    if ac is not None:
        rec["average_cost"] = float(ac) * tau / c
        ace = getattr(sol, "average_cost_error", None)
        rec["average_cost_error"] = None if ace is None else float(ace) * tau / c
    return rec


MAX_STEPS = 10_000_000
"""A default solve planning more steps is not run: ``solve`` of ``int_mm_hour`` plans 564 537 601
steps and is OOM-killed (24 GB) building the set of kept steps (``solver.kept_steps``)."""


def planned(problem):
    """The number of steps the default solve plans (None without a horizon)."""
    if problem.stationary:
        return None
    from gridlbc.solver import planned_step, settings_for

    return planned_step(problem, settings_for(problem, None, {}))[1]


def run(names, only=None):
    OUT.mkdir(parents=True, exist_ok=True)
    for name in names:
        b = BASES[name]
        p = b["build"]()
        X = b["X"]
        if X is None:
            X = np.asarray(b["spec"]()["X"], float)
        path = OUT / f"{name}.json"
        res = json.loads(path.read_text()) if path.exists() else {}
        res.update(dict(name=name, X=X.tolist(), t=b["t"], lam=p.temperature))
        if "truth" not in res:
            tv = b["truth"](X, b["t"])
            res["truth"] = None if tv is None else np.asarray(tv, float).tolist()
        res.setdefault("runs", {})
        for key, tr in transforms(p).items():
            if only and key not in only:
                continue
            if key in res["runs"]:
                continue
            steps = planned(rescale(p, **tr))
            if steps is not None and steps > MAX_STEPS:
                print(f"{name:20s} {key:8s} skipped: the default solve plans {steps} steps")
                res["runs"][key] = dict(skipped=f"{steps} steps planned")
                path.write_text(json.dumps(res, indent=1))
                continue
            rec = one(p, X, b["t"], tr)
            rec["transform"] = {k: np.asarray(v).tolist() for k, v in tr.items()}
            res["runs"][key] = rec
            ws = [w["category"] for w in rec["warnings"]]
            print(
                f"{name:20s} {key:8s} {rec['seconds']:6.1f}s dt={rec['dt']!s:.8} "
                f"v={np.round(rec['v'], 5).tolist()} est={rec['est'] and np.round(rec['est'], 5).tolist()} "
                f"{ws}",
                flush=True,
            )
            path.write_text(json.dumps(res, indent=1))


def _percents(message):
    """The unit-free numbers of a warning: its percentages (the rest are in the user's units)."""
    return tuple(re.findall(r"(\d+(?:\.\d+)?)%", message))


def table():
    rows = []
    for path in sorted(p for p in OUT.glob("*.json") if p.name != "table.json"):
        res = json.loads(path.read_text())
        lam, truth = res["lam"], res["truth"]
        base = res["runs"].get("id")
        if base is None:
            continue
        vb = np.array(base["v"])
        ref = np.array(truth) if truth is not None else vb
        den = np.maximum(np.abs(ref), lam)
        bshape = sorted((w["category"], _percents(w["message"])) for w in base["warnings"])
        for key, r in res["runs"].items():
            if "skipped" in r:
                continue
            v = np.array(r["v"])
            err = np.abs(v - ref) / den if truth is not None else None
            est = None if r["est"] is None else np.array(r["est"]) / den
            best = None if base["est"] is None else np.array(base["est"]) / den
            shape = sorted((w["category"], _percents(w["message"])) for w in r["warnings"])
            warned = any(w["gridlbc"] for w in r["warnings"])
            row = dict(
                name=res["name"],
                key=key,
                dt_ratio=None if not (r["dt"] and base["dt"]) else r["dt"] / base["dt"],
                dv=float(np.max(np.abs(v - vb) / den)),
                err=None if err is None else float(err.max()),
                est=None if est is None else est.tolist(),
                est_ratio=None
                if est is None or best is None
                else float(
                    np.max(np.abs(np.log(np.maximum(est, 1e-300) / np.maximum(best, 1e-300))))
                ),
                warn_same=shape == bshape,
                warned=warned,
                warnings=[w["category"] + ": " + w["message"][:160] for w in r["warnings"]],
                silent=bool(err is not None and err.max() > 0.1 and not warned),
                under=None
                if err is None or est is None
                else int(np.sum((est < 0.5 * err) & (err > 0.02))),
            )
            rows.append(row)
            flag = []
            if row["silent"]:
                flag.append("SILENT")
            if not row["warn_same"]:
                flag.append("WARN-DIFF")
            if row["est_ratio"] is not None and row["est_ratio"] > 0.05:
                flag.append(f"EST×{math.exp(row['est_ratio']):.3g}")
            if row["dv"] > 1e-6:
                flag.append(f"dv={row['dv']:.2e}")
            if base.get("average_cost") is not None and r.get("average_cost") is not None:
                acd = abs(r["average_cost"] / base["average_cost"] - 1)
                ace = (r.get("average_cost_error") or 0) / max(
                    base.get("average_cost_error") or 0, 1e-300
                )
                row["average_cost_rel_change"], row["average_cost_error_ratio"] = acd, ace
                if acd > 1e-6 or abs(ace - 1) > 0.05:
                    flag.append(f"AVG c×{1 + acd:.6g} ê_c×{ace:.3g}")
            if row["under"]:
                flag.append(f"under={row['under']}")
            print(
                f"{row['name']:20s} {key:8s} dt×{row['dt_ratio'] or 0:.4g} err="
                f"{row['err'] if row['err'] is None else round(row['err'], 4)} "
                f"est={None if est is None else np.round(est, 4).tolist()} {' '.join(flag)}"
            )
            if not row["warn_same"]:
                for w in row["warnings"]:
                    print("      ", w)
                for w in base["warnings"]:
                    print("   id:", w["category"] + ": " + w["message"][:160])
    (OUT / "table.json").write_text(json.dumps(rows, indent=1))
    other = [r for r in rows if r["key"] != "id"]
    print(
        f"{len({r['name'] for r in rows})} problems, {len(rows)} (problem, units) solves, "
        f"{len(other)} rescaled; value changed (> 1e-6 of max(|v|, λ)): "
        f"{sum(r['dv'] > 1e-6 for r in other)}; estimate changed > 5 %: "
        f"{sum((r['est_ratio'] or 0) > 0.05 for r in other)}; warnings' categories or "
        f"percentages differ: {sum(not r['warn_same'] for r in other)}; silent: "
        f"{sum(r['silent'] for r in rows)}; under-read states: {sum(r['under'] or 0 for r in rows)}"
    )


def probe_cost_floor():
    """toll_blind with its costs (and λ) ×c, and with costs per second over a year: the estimate
    read back in the original units."""
    b = BASES["toll_blind"]
    p, X = b["build"](), b["X"]
    out = {}
    for tr in [dict(c=c) for c in (1.0, 1e-12, 1e-13, 3e-14, 1e-14, 1e-15)] + [
        dict(c=1e-6, tau=86400.0),
        dict(c=1e-9, tau=3.15e7),
    ]:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sol = gridlbc.solve(rescale(p, **tr))
            v = np.ravel(sol.value(X)) / tr["c"]
            e = np.ravel(sol.error_estimate(X)) / tr["c"]
        out[json.dumps(tr)] = dict(v=v.tolist(), est=e.tolist(), warnings=_warnlist(caught))
        print(tr, "v", np.round(v, 4), "est", np.round(e, 4), "truth", b["truth"](X, 0), flush=True)
    return out


def probe_exit_shift():
    """The exit set's boundary moved outward by 1e-12 (original units): the nodes on it leave E."""
    out = {}
    for name in ("exit_late", "notch_exit_horizon", "notch_exit"):
        b = BASES[name]
        p, X, t = b["build"](), b["X"], b["t"]
        for eps in (0.0, 1e-12):

            def mask(x, eps=eps, p=p):
                y = np.array(x, float)
                y[:, 0] = y[:, 0] - eps * np.sign(y[:, 0])
                return p.exit_mask(y)

            q = p.replace(exit=mask, exit_cost=lambda x, p=p: p.exit_values(x))
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                sol = gridlbc.solve(q)
                v, e = np.ravel(sol.value(X, t)), np.ravel(sol.error_estimate(X, t))
            rec = dict(
                exit_nodes=int(q.exit_mask().sum()),
                v=v.tolist(),
                est=e.tolist(),
                truth=np.ravel(b["truth"](X, t)).tolist(),
                warnings=_warnlist(caught),
            )
            out[f"{name} {eps:g}"] = rec
            print(name, eps, {k: rec[k] for k in ("exit_nodes", "v", "est", "truth")}, flush=True)
    return out


def probe_tol(names=("lq2_00", "two_doors", "narrow_goal", "toll_blind", "cold_ou_average")):
    """``solve(problem, tol=0.05, states=X)`` in several units: what it chose and met."""
    out = {}
    for name in names:
        b = BASES[name]
        p, X, t = b["build"](), b["X"], b["t"]
        for key in ("id", "s1e-6", "c1e-15", "tau3e7", "si", "year_micro"):
            tr = transforms(p)[key]
            s = np.broadcast_to(np.asarray(tr.get("s", 1.0), float), (p.state_dim,))
            c, tau = tr.get("c", 1.0), tr.get("tau", 1.0)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                start = time.perf_counter()
                sol = gridlbc.solve(rescale(p, **tr), tol=0.05, states=X * s)
                secs = time.perf_counter() - start
                v = np.ravel(sol.value(X * s, t * tau)) / c
                e = np.ravel(sol.error_estimate(X * s, t * tau)) / c
            rec = dict(
                grid=sol.problem.grid.describe(),
                dt=None if sol.diagnostics.dt is None else float(sol.diagnostics.dt) / tau,
                v=v.tolist(),
                est=e.tolist(),
                seconds=secs,
                warnings=_warnlist(caught),
            )
            out[f"{name} {key}"] = rec
            print(
                f"{name:18s} {key:10s} {rec['grid']:24s} dt={rec['dt']} v={np.round(v, 4)} "
                f"est={np.round(e, 4)} {secs:.1f}s {[w['category'] for w in rec['warnings']]}",
                flush=True,
            )
    return out


def probe_certify_user():
    """The user's millimetre problems certified on their reflecting box (the solve's boundary),
    with the default solve's policy, 2000 paths; the Riccati value on R² beside it."""
    out = {}
    for name in ("pm_mm_default", "pm_mm_cold"):
        b = BASES[name]
        p, X = b["build"](), b["X"]
        sol = gridlbc.solve(p)
        vs, es, ric = np.ravel(sol.value(X)), np.ravel(sol.error_estimate(X)), b["truth"](X, 0)
        for i, x in enumerate(X):
            c = gridlbc.certify(p, sol.policy, x, n_samples=2000, seed=30)
            rec = dict(
                x=x.tolist(),
                v=float(vs[i]),
                est=float(es[i]),
                vstar=float(np.ravel(c.optimal_value)[0]),
                se=float(np.ravel(c.optimal_value_se)[0]),
                ess=float(np.ravel(c.effective_sample_size)[0]),
                riccati=float(ric[i]),
            )
            out.setdefault(name, []).append(rec)
            print(name, rec, flush=True)
    return out


if __name__ == "__main__":
    args = sys.argv[1:]
    if not args or args[0] == "--list":
        print("\n".join(BASES))
    elif args[0] == "--run":
        only = [a.split("=", 1)[1].split(",") for a in args if a.startswith("--only=")]
        names = [a for a in args[1:] if not a.startswith("--")] or list(BASES)
        run(names, only[0] if only else None)
    elif args[0] == "--table":
        table()
    elif args[0] == "--probes":
        OUT.mkdir(parents=True, exist_ok=True)
        probes = dict(
            cost_floor=probe_cost_floor(),
            exit_shift=probe_exit_shift(),
            certify_user=probe_certify_user(),
        )
        (OUT / "probes.json").write_text(json.dumps(probes, indent=1))
    elif args[0] == "--tol":
        OUT.mkdir(parents=True, exist_ok=True)
        (OUT / "tol.json").write_text(json.dumps(probe_tol(), indent=1))
