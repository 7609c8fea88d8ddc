"""Stranger round 30: UNITS (public API only; SPEC §1, §6, §7, §9, §10).

RESULTS (library of r30 = main 3aea650, 2026-12-06, one thread; ``--run`` (see BASES and
``transforms``), ``--table``, ``--probes``, ``--tol``):

Posed: 37 base problems (30 from the hold-out corpus: first exits with and without a horizon,
average costs, narrow features, 3-D toll_strip / goal_face_3d, 4-D goal_4d / pair_average_4d,
λ 0.005–1; 3 LQ from round 25 with the exact Riccati truth, lq2_00, lq2_03, lq3_00; 4 user LQ
problems written in SI units with a ±5 mm box, pm_mm_default / pm_mm_cold / int_mm_euro, and
int_mm_hour, which cannot be solved: see 5.), each rewritten in new units by an exact change
of units through the public API only (``Scaled``, a ControlAffineSystem wrapping the base system, and
``rescale``): space x = s·y (s scalar 1e-6 … 1e5, or per axis with ratios up to 1e8), costs and λ
×c (1e-15 … 1e8), time t' = τt (1e-6 … 3.15e7 s), and combinations (``si``: s = (1e-3, 100, 0.05,
1e3), c = 1e4, τ = 3600; ``box5mm``: the box rescaled to ±5 mm; ``year_micro``: c = 1e-6, τ =
3.15e7). The default ``solve(problem)`` of every pair, read back in the base units at the
corpus's states (and times), against the identity wrapper (s = c = τ = 1) and against the truths
(truths.json, Riccati, or ``--probes``' certificates). ``--table``: 36 problems, 479
(problem, units) solves, 443 of them rescaled; value changed by > 1e-6 of max(|v|, λ): 7 pairs
(all in 2.); estimate changed by > 5 %: 18; warning categories or percentages differ: 44;
"silent" 4 and under-read states 31, all explained below (pm_mm_default against the Riccati
value on R², 12 states; driftwall_kept_node's 2 states in all 8 unit systems alike, 16;
toll_blind at c = 1e-15, 3).

The default Δt is exactly unit-invariant (Δt/τ identical in every finite-horizon pair: no
legitimate discretisation difference to explain anything below). In exact binary scalings
(powers of two) values and estimates are bit-identical everywhere. Most pairs are bit-identical.

After the fixes (main, 2026-12-06): ``interpolated_exactly`` takes rounding relative to the
cost's own size (not max(1, max|q|)); toll_blind, three_doors and cold_ou_average at c = 1e-15,
1e-12 and year_micro now read the same values, estimates and warnings as in the base units
(0.998 / 0.751 / 1.111 on toll_blind; c's own warning on cold_ou_average). int_mm_hour is
refused at once with a MemoryError naming its 564537601 steps (the kept slices are counted
before they are listed). States in messages are given to 4 significant digits.

Findings, by severity:

0. SILENT pairs under a change of units: none. Every rescaled solve that is > 10 % off its truth
   is warned in every unit system tried.

1. The estimate's absolute cost floor (``gridlbc/accuracy/paths.py:357``:
   ``ROUNDING * max(1.0, max|q|)`` in ``interpolated_exactly``: a gap below 1e-12 *cost units*
   counts as rounding): when the costs are small numbers the γ term (along the paths, first exit
   without a horizon) and γ_c (average cost) are dropped as if the costs were affine.
   - toll_blind (first exit, λ = 0.2, truth 2.2954 / 1.2967 / 0.8967): v = 1.9719 / 0.9755 /
     0.5766 in every unit system (errors 0.323 / 0.321 / 0.320); the estimate (read back) is
     0.998 / 0.751 / 1.111 for c ≥ 3e-14, and 0.100 / 0.100 / 0.100 for c ≤ 1e-14 and for
     c = 1e-9, τ = 3.15e7 (costs per second over a year): 10× lower, UNDER-READ at all 3 states
     (ê < ½ err). Still warned, but by a different warning (the sub-cell one, "up to 21 % of
     |v|", instead of "exceeds 5 % at 92 % of the states ... along the solve's own paths").
   - cold_ou_average (average cost, λ = 0.005): at c = 1e-12, c = 1e-15 and year_micro the
     average cost's own ResolutionWarning ("c = 0.00298181 is 0.000157, 5.3 % of it") is gone
     (1 warning instead of 2); ê_c 1.57e-4 → 4.86e-5 (×0.31). The exact c is 0.00294474, the
     solve's 0.00298181 (1.26 % off): still covered, so not silent here.
   - three_doors (exit costs 1.2 / …): at c ≤ 1e-12 the estimate at (1.4, 1.4) drops
     0.01788 → 0.00118 (15×); actual error 2.5e-4, still covered.

2. Values that change under an exact change of units (first exits with a horizon, whose exit
   boundary lies on a row of nodes): rounding in the new units puts those nodes just outside E,
   and the solve is discontinuous in the boundary's position there. Reproduced in the base units
   by moving the boundary outward by 1e-12 (``--probes``, ``probe_exit_shift``):
   - exit_late (|x₀| ≥ 1.8 on a node row, read at t = 1.8, truth 4.7488 / 3.8916 / 5.3640 /
     2.8020): units box5mm, s = 0.1, 0.01, 1e-4: v(1.6, 0) 2.8272 → 3.3288 (18 %), ê 2.326 →
     1.623; si and s = 1e-3: v(−1.5, 0) 3.9170 → 4.2635, ê 0.859 → 1.020; boundary +1e-12:
     exit nodes 1212 → 1010, both changes at once.
   - exit_late_cold box5mm: v(1.7, −1) 4.1741 → 4.4660 (truth 5.5827), ê 1.335 → 1.173; si:
     v(−1.5, 0) 2.1959 → 2.4621 (truth 4.6970), ê 3.259 → 3.059.
   - notch_exit_horizon (Box([0.45, −inf], …), truth 2.0463 / 1.4344 / 0.8236): s = 0.1, 1e-3,
     1e-6, si: v 1.2080 → 1.2774 and 1.6266 → 1.6968; its estimate does not move (0.3837 /
     0.1901) although v moved by 0.07.
   - the same shift leaves the stationary notch_exit bit-identical (its exit is fitted by
     bisection): the jump is the horizon (implicit march) path's. All these are warned in both
     units; the estimates cover ½ the error in both.
   - dock (stationary first exit) box5mm: v changes by 6e-4, ê by 11 %.

3. Estimates and warning percentages that change with the units (values identical):
   notch_exit ê ×1.11 at c = 1e-6 and year_micro, ×1.07 at c = 1e8, ×1.13 at c = 1e-15 (0.299 →
   0.326 at (−0.5, 0)); notch_exit_horizon ×1.21 at c = 1e-6 (0.0524 → 0.0636); comb_torus ×1.06
   at c = 1e-3; the warnings' percentages: notch_exit "up to 39 %" → 45 % (si), 40 % (c1e4);
   toll_blind si 92 % / 109.8 % / 253 % → 93 % / 107.9 % / 240 %; dock box5mm 37.9 % / 81 % →
   34.1 % / 76 %; exit_late_cold box5mm 29 % / 68 % → 31 % / 92 %.

4. Warnings locate the trouble in the user's units with numpy's default print precision, so in
   a millimetre box the location is lost: notch_exit in units s = 1e-3 says "near [0., 0.]"
   (the base says "near [0.4, 0.]"), narrow_goal box5mm "[0.   , 0.001]", cold_ou_average box5mm
   "[-0.004,  0.   ]", notch_exit tiny "[4.000e-06, 3.388e-21]".

5. A user's SI problem kills the process: int_mm_hour (LinearSystem 2-D, u on both axes, box
   ±5 mm on 101², T = 3600 s, λ = 1e-3, R = 1e-3 I, g = 10|x|², q = 0.1|x|²): the default plans
   564 537 601 steps of 6.38e-6 s, and ``solve`` (already ``planned_memory``) is OOM-killed at
   24 GB RSS building ``solver.kept_steps``' set of all steps — no error message. (``--run``
   now skips a solve planning > 1e7 steps; run it only under ``ulimit -v``.)

6. The box is a reflecting state constraint, and a millimetre box with the default λ = 1 says
   nothing about it: pm_mm_default (PointMass, ±5 mm × ±5 cm/s, g = 1e4 x² + 1e2 v², λ = 1,
   T = 1): v = 0.171 / 0.168 / 0.174 where the Riccati value on R² is 6.369 (97 % lower), no
   warning, ê 0.013. Certified on the reflecting box (the solve's boundary, 2000 paths, the
   default solve's policy): v* = 0.149 / 0.129 / 0.218 ± 0.012 (ESS 1544–1571), so the solve is
   2–4 % off the problem it solves: not a failure of the estimate by the contract, but the user
   gets the reflected problem's answer 37× below the unbounded one with no hint. pm_mm_cold
   (λ = 1e-6, warned): v = 3.601e-4 / 8.25e-6 / 1.190e-3 vs certified 3.505e-4 / 6.47e-6 /
   1.187e-3 (ESS 23 / 389 / 15) and Riccati 3.477e-4 / 6.37e-6 / 1.179e-3.

7. int_mm_euro (LinearSystem, a = diag(−0.5, 0), box ±5 mm on 101², T = 1, λ = 0.01,
   R = 1e-4 I, g = 1e8 |x|²: the noise λR⁻¹ = 100 fills the box at once): v = 0.8169 at all 3
   states (Riccati on R²: 0.2809), warned, ``error_estimate`` 1766 / 1693 / 1811 (2000× |v|)
   while its warning says "90 % of them are within 48.7 %; the largest, 57 %". The estimate of a
   state depends on the batch it is read in: 1765.8 at (0.002, 0.001) read with the other two,
   1699.7 read alone. At c = 1e-15 the warning switches to the other variant ("at 100 % of the
   better half of the states (value at most the median), where the paths end up (90 % ... within
   50.4 %)"). Its certificate with the default solve's policy degenerates (ESS 1.0, v* ~5e13,
   the policy's cost ~1e14): no trusted truth.

8. ``solve(problem, tol=0.05, states=X)`` (``--tol``: lq2_00, two_doors, narrow_goal,
   toll_blind, in units id, s1e-6, c1e-15, tau3e7, si, year_micro): the same grid and Δt
   chosen in every unit system; values identical; toll_blind's estimate 0.0093 → 0.0100 in
   units s1e-6 and si. cold_ou_average's tol run died in ``splu`` under this script's
   ``ulimit -v 8 GB`` (refined average-cost grid), not a units effect; its log is tol.log.

Everything else is unit-invariant: lq2_00 / lq2_03 / lq3_00 (Riccati), narrow_goal, vortex,
cheap_control, hot_rotor, gust_between_nodes, goal_face_3d, goal_4d, toll_strip, two_doors,
well_torus_average, pair_average_4d, relative_value_cold, well_face, pit_drift, hot_band,
cold_flow_exit, exit_strip_between, logistic_edge, driftwall_kept_node (its 2 under-read states
are under-read in every unit), tiny_ball_cold: bit-identical values, estimates and warnings.

    cd /work/wt-r30 && PYTHONPATH=/work/wt-r30 NUMBA_NUM_THREADS=1 \
        python benchmarks/holdout/strangers_round30.py --list | --run [NAMES] [--only=K,..] | --table
                                                          | --probes | --tol
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
        if "runs" not in res:  # probes.json, tol.json, certified_user.json
            continue
        lam, truth = res["lam"], res["truth"]
        base = res["runs"].get("id")
        if base is None or "skipped" in base:
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
        X = np.asarray(b["spec"]()["X"], float) if X is None else X
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
    for name in ("pm_mm_default", "pm_mm_cold", "int_mm_euro"):
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
