"""Stranger round 44: random problems on the library's OWN built-in systems (seed 44), public
API only.

WHAT MAIN DID WITH THEM (2026-12-07, after the run): ``error_estimate`` where v underflowed is
+inf, told once (it read 0.0 with numpy's invalid-value warnings); a stored z a rounding below 0
(the implicit march's linear solve) reads as underflowed, not NaN with numpy's warning; the
warnings of certify(richardson=True)'s runs at 2Δt and 4Δt name their run. Left open: the
``tol=`` under-read of r44_PointMass_fe_18 (order ≈ 0.7 along the noise-free axis, read as ≥ 1),
and the certificate of r44_PointMass_fe_04 that moves with dt: its v* RISES as dt falls (0.92,
1.09, 1.22 at dt 0.004, 0.001, 0.00025 with main's certify, seed 44), so the paths exit too
early or too cheaply at a long step, not too late; a test that stops a step whose straight part
passes through E (the missed-crossing reading) lowered it further and was not kept.

LATER (2026-12-07, main 06a8953): the certificate of r44_PointMass_fe_04 moved with dt because the
bridge stopped halving a step after six halvings; it halves now until a crossing is implausible,
and reads 1.27, 1.25, 1.29 at dt 0.004, 0.001, 0.00025 (seed 44, 4000 paths, the default solve's
policy). The stored truth of r44_PointMass_fe_18 x0 (1.2424, old bridge) is 1.217 with the new
one (dt 0.002 … 0.0005, 4000 paths, the 1377×85 policy); the default solve's estimate at x0 on
689×85 is 4.4 % (the whole task's certificate now runs without a horizon too), error 6.7 %.

RESULTS (library of main 28937ed, worktree r44, 2026-12-07 15:10–15:50 UTC, one thread, the
other core busy): ``--run`` of all 30 draws (17, then 3, then 4, then 6 appended to ``KINDS``;
the earlier draws unchanged), each under ``timeout 480`` (none hit it); ``--tolcheck`` of
r44_PointMass_fe_04 0 0, r44_Linear2_fe_19 0 0, r44_PointMass_fe_18 0 0, r44_Pendulum_hzfe_02 1 0
(twice), r44_PlanarChain_hz_16 1 1; ``--recheck r44_PointMass_fe_18 r44_PointMass_fe_04``;
``--dtcheck`` of both at x0; by hand, the certificate of those two x0 at dt 0.004 … 0.00025 and
r44_PointMass_fe_18 solved on finer grids (below); ``--table``.

- 30 problems (Pendulum 8, PointMass 6, SingleIntegrator 3, LinearSystem 2-D 5 / 3-D 4, Acrobot 2,
  PlanarChain(2) 1; 12 fixed horizon, 11 stationary first exits, 7 first exits with a horizon;
  λ 0.013–2.36; default solves 0.4–21.6 s). As first drawn, r44_Linear2_fe_10 and
  r44_Linear3_hzfe_14 (one control on several axes of a LinearSystem, B = (1.51, 0.87)ᵀ) were
  REFUSED: "the noise covariance λ B R⁻¹ Bᵀ is not diagonal … choose B and R so that B R⁻¹ Bᵀ is
  diagonal": true and documented; the generator now gives one control one axis.
  r44_Linear2_fe_10 (re-drawn, B = (0, −1.23)ᵀ) has an exit x0 < −1.114 that ẋ0 = −0.74 x0 +
  0.033 x1 never reaches from x0 > −1.11: the solve says so (UnderflowWarning "cannot be reached
  from 9984 of 14016 nodes", TRUE), v = +inf at all 3 states, and certify raises ValueError
  (the proposal's controls are NaN): counted as "raised", no pairs.
- 144 (problem, state, t) pairs, 91 trusted (ESS ≥ 100, k̂ ≤ 0.7, in the box, paths exited;
  r44_PointMass_fe_04 excluded, ``DT_BIASED``). 25 of 29 solved problems warned; quiet: 5
  (r44_SingleIntegrator_fe_08, r44_SingleIntegrator_hz_21, r44_Pendulum_fe_20,
  r44_Linear2_hz_26, r44_Linear2_hz_28), every trusted pair of them ≤ 2.5 % off.
- > 10 % off (trusted): 11, ALL WARNED. SILENT: 0. (err / ê) r44_Linear2_fe_19 x0 38 / 90 %;
  r44_Linear3_fe_12 x2 40 / 62; r44_Linear3_hzfe_14 t = T − 2Δt x2 95 / 1733 (v 0.60 vs v* 11.08
  ± 0.0001, 0.043 before the end; v(x2, T) itself 9.64 against g = 11.94; warned "the plain
  scheme cannot resolve … v is underestimated"); r44_Pendulum_hzfe_02 T − 2Δt x0 23 / 29, x1
  45 / 81; r44_PlanarChain_hz_16 t = 0 x1 11 / 57, T − 2Δt x1 18 / 35; r44_PointMass_fe_18 x0
  19 / 17, x2 16 / 17; r44_PointMass_fe_25 x2 11 / 23; r44_SingleIntegrator_hzfe_07 T − 2Δt x0
  18 / 15.
- Coverage of the DEFAULT solves: ê ≥ ½ err (or err < 1 %) at 91 of 91; under-reads 0 (the two
  ê < ½ err are r44_Linear2_hz_26 at T − 2Δt, err 0.34 % / 0.48 %).
- UNDER-READ AFTER ``solve(tol=0.05)`` (it says MET): r44_PointMass_fe_18 (PointMass m 1.90, λ
  0.690, R 0.079, stationary exit = a Ball ∪ Ball, constant exit cost 0.898) at x0 = (0.643,
  −0.480): met with ê 2.67 % on 689×85 (rounds' ê 17.4, 6.2, 5.1, 7.0, 2.67 %; only the position
  axis refined), v 1.1353 against v* ≈ 1.22: 1.2424 ± 0.012 (seed 44, dt 0.004), 1.2178 (seed
  45), 1.2314 / 1.2043 (dt 0.002 / 0.001), 1.230 / 1.221 / 1.233 / 1.214 (x0 alone, dt 0.004 …
  0.00025), and with the 689×169 solve's own policy, 4000 paths: 1.229 ± 0.004 (dt 0.002),
  1.217 ± 0.004 (dt 0.0005), that policy's cost 1.218–1.223, ESS 3900: err 7.0 % > tol, ê < ½
  err. Refining the position axis alone (velocity 85): 44 → 1.009, 173 → 1.087, 689 → 1.135,
  1377 → 1.176, 2753 → 1.205 (ê 17.4, –, 2.25, 1.93, 1.14 %; 2753×85 is quiet at 1.2 % off):
  steps of 0.048, 0.030 per halving, order ≈ 0.7 along the noise-free axis, read as order ≥ 1.
  ``--tolcheck r44_PointMass_fe_18 0 0``. The other tol solves: r44_Linear2_fe_19 x0 met, 1.67 %
  off (ê 2.06 %); r44_PointMass_fe_04 x0 not met (ê 7.4 % on 4705×165, v 1.2473);
  r44_Pendulum_hzfe_02 T − 2Δt x0 not met (time budget; 5.8 % off, ê 25 %);
  r44_PlanarChain_hz_16 T − 2Δt x1 not met (stopped at 13 s of 120: the next round too slow).
- CERTIFY SILENTLY BIASED (a first exit crossed along a noise-free axis): r44_PointMass_fe_04
  (m 0.78, λ 1.03, R 0.0137; exit = Ball ∪ a small Ball of radii 0.027 (position) × 0.205) at
  x0 = (0.412, 0.879), the 2× finer solve's policy, richardson, reflect: v* 0.983 ± 0.018 in the
  run (dt 0.004, ESS 1788, k̂ 0.30, NO CertificateWarning), 1.092 / 1.206 at dt 0.002 / 0.001
  (``--dtcheck r44_PointMass_fe_04 0``), and x0 alone: 1.006 (dt 0.004, warned "bias not yet of
  first order"), 1.198 (0.001), 1.266 (0.0005), 1.303 (0.00025), no warning below 0.004: steps
  0.068, 0.037 per halving, an O(√dt) approach (the ball is crossed within a step in position,
  where the bridge sees no noise). Its pairs are not trusted here; the default solve's v 1.019
  is then ≈ 25 % below the dt → 0 limit (≈ 1.35), ê 98 % (warned).
- Over-reads (ê > 20× max(err, 1 %), trusted): 6, none above 50 % (round 39's "absurd": 0):
  r44_Pendulum_hzfe_03 t = 0 x0 1.06 / 33 %, x1 0.88 / 24 %; r44_Linear3_hz_13 t = 0 x2 0.24 /
  32 %; r44_Linear3_fe_12 x0 0.93 / 21 %; r44_Acrobot_hz_29 T − 2Δt x2 0.21 / 31 %;
  r44_PlanarChain_hz_16 T − 2Δt x2 1.52 / 35 %. At t = T − 2Δt the estimate is the SAME relative
  value at every state (the floor calibrated at t = 0): r44_Acrobot_hz_29 30.73 % at errors 4.1 /
  3.2 / 0.21 %; r44_PlanarChain_hz_16 34.77 % (4.8 / 18 / 1.5 %); r44_Pendulum_hzfe_01 3.50 %
  (0.10–0.43 %); r44_Pendulum_hzfe_03 4.46 % (0.10–0.57 %); r44_Acrobot_hz_15 4.18 % (4.4 / 5.6 /
  0.15 %).
- Stray numpy warnings from the library: gridlbc/accuracy/estimate.py:290 "invalid value
  encountered in multiply" and :308 "invalid value encountered in subtract" from
  ``Solution.error_estimate`` at states where v = +inf (r44_Linear2_fe_10; the estimate returned
  there is 0.0); gridlbc/representation.py:242 "invalid value encountered in log" (twice) in
  ``solve(tol=0.05, states=…)`` of r44_Pendulum_hzfe_02 (λ 0.037; its last round 232×195, dt
  0.0006): ``log_nodes`` takes the log of a negative stored desirability (its errstate silences
  divide only). ``--tolcheck r44_Pendulum_hzfe_02 1 0`` (90 s). The default solves and
  certificates raised none.
- Warnings read: every ResolutionWarning where a trusted pair was > 10 % off was true in
  direction; the UnderflowWarning on r44_Linear2_fe_10 is true. API oddity: certify(richardson=
  True) warns of heavy tails in its 4Δt check run ("k̂ = 0.96 / 1.84 … v* = 1.136 / 1.14 is likely
  too high", r44_PointMass_fe_18 x0) whose k̂ and v* appear nowhere in the Certificate
  (pareto_k 0.07–0.12, the Δt and 2Δt runs'), without saying which run it means.

Generator (``gen``, seed 44): a system of ``gridlbc.systems`` with random constructor parameters
(Pendulum: mass, length, gravity, damping; PointMass: mass; SingleIntegrator; LinearSystem: a
random A (entries N(0, 0.7²)) and B (one control on one axis, or the identity); Acrobot and PlanarChain(2):
masses, lengths, gravity), a box a user would choose (angles periodic on [−π, π), velocities and
momenta ±4–12, positions ±2–5), λ log-uniform in [0.01, 3], R log-uniform in [0.01, 10] (diagonal
for several controls), q = a random mix of a constant, a quadratic about a random point, a narrow
wall (a Gaussian ridge across one closed axis) or pit (q0·(1 − e^(−|x−c|²/2w²)) of depth q0) of
width 0.5–3 cells, and 1 − cos on the angles; the ending: a horizon T in [0.5, 5] with a terminal
cost (wrap-aware quadratic about a random target, or a swing-up cost a(1 − cos θ) + b·rate²), a
stationary first exit (round 41's ``exit_draw``, q ≥ 0.05 off E), or both. Grids 61–201 per
axis in 1-D, 31–201 in 2-D, 21–41 in 3-D, 15–17 in 4-D. States: a typical one, one near a feature
(half a width off the wall or pit, or near the target), a far corner (0.85 of the box), read at
t = 0 and at T − 2Δt.

Truth: round 39's ``certify_at`` (a 2× finer solve's policy, 1.5× above 1.2 M fine nodes, 1.3×
in 4-D, Δt halved; richardson, reflect, 2000 paths, seed 44) through this round's ``build``;
trusted as in round 41 (ESS ≥ 100, k̂ ≤ 0.7, state in the box, unexited paths negligible).
``--tolcheck NAME K I`` re-solves with ``solve(problem, tol=0.05, states=[x], max_seconds=120)``
and ``--recheck NAME`` certifies again with seed 45 (for silent / under-read pairs).

    cd /work/wt-r44 && PYTHONPATH=/work/wt-r44 NUMBA_NUM_THREADS=1 \\
        python benchmarks/holdout/strangers_round44.py --list | --run [NAMES] | --table \\
        | --tolcheck NAME K I | --recheck NAME | --dtcheck NAME I
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import strangers_round39 as r39
import strangers_round41 as r41  # patches round 39's trusted and _warnlist (stray warnings)
from strangers_round25 import loguni

import gridlbc
from gridlbc import Problem
from gridlbc import systems as S

OUT = Path("/work/main/benchmarks/holdout/strangers_round44_results")  # gitignored there
SEED = 44
PI = math.pi
KINDS = (
    ["Pendulum"] * 4
    + ["PointMass"] * 3
    + ["SingleIntegrator"] * 2
    + ["Linear2"] * 3
    + ["Linear3"] * 3
    + ["Acrobot", "PlanarChain"]
    + ["Pendulum", "PointMass", "Linear2"]  # three more, drawn after the first 17
    + ["Pendulum", "SingleIntegrator", "PointMass", "Linear3"]  # and four more after those
    + ["Pendulum", "PointMass", "Linear2", "Pendulum", "Linear2", "Acrobot"]  # and six more
)


# ================= costs =========================================================================
class StateCost:
    """q(x) = c0 + Σ_i Wq_i (x − c)_i² + ridges H e^(−(x_k − c)²/2w²) + pits D (1 − e^(−|x − c|²/2w²))
    + Σ_angles a (1 − cos(θ − φ))."""

    def __init__(self, q, per):
        self.q, self.per = q, tuple(per)

    def __call__(self, x):
        x = np.asarray(x, float)
        q = self.q
        out = q["c0"] + np.zeros(len(x))
        if q["quad"] is not None:
            d = r39.wrapdiff(x, q["quad"]["c"], self.per)
            out += d**2 @ np.asarray(q["quad"]["W"])
        for f in q["feat"]:
            if f["kind"] == "wall":
                k = f["axis"]
                out += f["H"] * np.exp(-0.5 * ((x[:, k] - f["c"]) / f["w"]) ** 2)
            else:
                d = r39.wrapdiff(x, f["c"], self.per) / np.asarray(f["w"])
                out += f["D"] * (1.0 - np.exp(-0.5 * np.sum(d**2, axis=1)))
        for a in q["cos"]:
            out += a["a"] * (1.0 - np.cos(x[:, a["axis"]] - a["phi"]))
        return out


class TermCost:
    """ "quad": Σ W_i (x − c)_i² (wrap-aware); "swing": Σ_angles a (1 − cos θ) + Σ_rest b x²."""

    def __init__(self, g, per):
        self.g, self.per = g, tuple(per)

    def __call__(self, x):
        x = np.asarray(x, float)
        g = self.g
        if g["kind"] == "quad":
            d = r39.wrapdiff(x, g["c"], self.per)
            return d**2 @ np.asarray(g["W"])
        out = np.zeros(len(x))
        for i in range(x.shape[1]):
            if i in self.per:
                out += g["a"] * (1.0 - np.cos(x[:, i]))
            else:
                out += g["b"] * x[:, i] ** 2
        return out


# ================= the draw ======================================================================
def system_draw(rng, kind):
    if kind == "Pendulum":
        par = dict(
            mass=loguni(rng, 0.2, 5.0),
            length=loguni(rng, 0.3, 2.0),
            gravity=float(rng.choice([9.81, 1.62, 3.71, 24.8])),
            damping=float(rng.choice([0.0, loguni(rng, 0.01, 1.0)])),
        )
        W = float(rng.uniform(4, 12))
        return par, [[-PI, PI], [-W, W]], [0]
    if kind == "PointMass":
        par = dict(mass=loguni(rng, 0.1, 10.0))
        return par, [[-rng.uniform(2, 5)] * 2, [-rng.uniform(3, 8)] * 2], []
    if kind == "SingleIntegrator":
        return {}, [[-rng.uniform(2, 5)] * 2], []
    if kind in ("Linear2", "Linear3"):
        d = 2 if kind == "Linear2" else 3
        m = int(rng.choice([1, d]))
        A = rng.normal(0.0, 0.7, size=(d, d))
        B = np.eye(d) if m == d else rng.normal(0.0, 1.0, size=(d, 1))
        if m == 1:
            j = int(rng.integers(d))
            B[j] = rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 2.0)
            # one control on several axes is refused (noise not diagonal, r44_Linear2_fe_10 and
            # r44_Linear3_hzfe_14 as first drawn): it drives axis j alone
            B[np.arange(d) != j] = 0.0
        return dict(A=A.tolist(), B=B.tolist()), [[-rng.uniform(2, 5)] * 2 for _ in range(d)], []
    if kind == "Acrobot":
        par = dict(
            m1=loguni(rng, 0.5, 2.0),
            m2=loguni(rng, 0.5, 2.0),
            l1=loguni(rng, 0.5, 1.5),
            l2=loguni(rng, 0.5, 1.5),
            gravity=float(rng.choice([9.81, 3.71])),
        )
    else:
        par = dict(
            n_links=2,
            masses=[loguni(rng, 0.5, 2.0) for _ in range(2)],
            lengths=[loguni(rng, 0.5, 1.5) for _ in range(2)],
            gravity=float(rng.choice([9.81, 1.62])),
        )
    P = float(rng.uniform(4, 10))
    return par, [[-PI, PI], [-PI, PI], [-P, P], [-P, P]], [0, 1]


def make_system(spec):
    k, par = spec["kind"], spec["params"]
    if k in ("Linear2", "Linear3"):
        return S.LinearSystem(np.asarray(par["A"]), np.asarray(par["B"]))
    if k == "PlanarChain":
        return S.PlanarChain(**par)
    return getattr(S, k)(**par)


def _fix(box):
    for b in box:
        b[0] = -abs(b[0])
        b[1] = abs(b[1])
    return box


def gen(rng, k):
    kind = KINDS[k]
    par, box, per = system_draw(rng, kind)
    box = _fix([[float(a), float(b)] for a, b in box])
    d = len(box)
    lo_n, hi_n = {1: (61, 201), 2: (31, 201), 3: (21, 41), 4: (15, 17)}[d]
    ns = [int(rng.integers(lo_n, hi_n + 1)) for _ in range(d)]
    ns = [n + n % 2 if i in per else n for i, n in enumerate(ns)]
    box = [[lo, hi, n] for (lo, hi), n in zip(box, ns)]
    h = [(hi - lo) / (n - (0 if i in per else 1)) for i, (lo, hi, n) in enumerate(box)]
    Ls = [hi for _, hi, _ in box]
    closed = [i for i in range(d) if i not in per]
    m = make_system(dict(kind=kind, params=par)).control_dim
    lam = loguni(rng, 0.01, 3.0)
    R = np.diag([loguni(rng, 0.01, 10.0) for _ in range(m)]).tolist()
    u = rng.random()
    ending = "hz" if u < 0.5 else "fe" if u < 0.8 else "hzfe"
    if d == 4 and ending == "fe":
        ending = "hz"
    T = None if ending == "fe" else float(rng.uniform(0.5, 5.0))
    # the state cost
    q = dict(c0=0.0, quad=None, feat=[], cos=[])
    if rng.random() < 0.6 or ending == "fe":
        q["c0"] = float(rng.uniform(0.05, 1.0))
    if rng.random() < 0.6:
        q["quad"] = dict(
            c=[float(rng.uniform(-0.5, 0.5) * L) for L in Ls],
            W=[float(loguni(rng, 0.05, 3.0) if rng.random() < 0.7 else 0.0) for _ in range(d)],
        )
    feat_near = None
    if rng.random() < 0.7:
        w = float(rng.uniform(0.5, 3.0))
        if closed and rng.random() < 0.5:
            ax = int(rng.choice(closed))
            c = float(rng.uniform(-0.5, 0.5) * Ls[ax])
            q["feat"].append(dict(kind="wall", axis=ax, c=c, w=w * h[ax], H=loguni(rng, 0.5, 20.0)))
            feat_near = ("wall", ax, c, w * h[ax])
        else:
            c = [float(rng.uniform(-0.5, 0.5) * L) for L in Ls]
            q["feat"].append(
                dict(kind="pit", c=c, w=[w * hh for hh in h], D=loguni(rng, 0.5, 10.0))
            )
            feat_near = ("pit", c, [w * hh for hh in h])
    for i in per:
        if rng.random() < 0.6:
            q["cos"].append(dict(axis=i, a=loguni(rng, 0.1, 5.0), phi=float(rng.choice([0.0, PI]))))
    spec = dict(
        name=f"r44_{kind}_{ending}_{k:02d}",
        kind=kind,
        params=par,
        d=d,
        box=box,
        periodic=per,
        lam=lam,
        R=R,
        T=T,
        q=q,
        q0=q["c0"],
        ending=ending,
    )
    if T is not None:
        if per and rng.random() < 0.5:
            spec["g"] = dict(kind="swing", a=loguni(rng, 0.5, 10.0), b=loguni(rng, 0.01, 0.5))
        else:
            spec["g"] = dict(
                kind="quad",
                c=[float(rng.uniform(-0.6, 0.6) * L) for L in Ls],
                W=[loguni(rng, 0.1, 10.0) for _ in range(d)],
            )
    spec["exit"] = None
    if ending != "hz":
        for _ in range(20):
            spec["exit"] = r41.exit_draw(rng, d, box, per, h)
            try:
                share = r41.in_exit(spec, r41._nodes(spec)).mean()
            except Exception:  # a draw the problem refuses: draw again
                continue
            if 0 < share < 0.5:
                break
        spec["exit_share"] = float(share)
    # states: typical, near the feature (or the target), far corner
    typ = [float(rng.uniform(-0.3, 0.3) * L) for L in Ls]
    if feat_near is not None and feat_near[0] == "wall":
        near = list(typ)
        near[feat_near[1]] = feat_near[2] + float(rng.choice([-1, 1])) * feat_near[3]
    elif feat_near is not None:
        near = [c + float(rng.choice([-0.5, 0.5])) * w for c, w in zip(feat_near[1], feat_near[2])]
    elif T is not None and spec["g"]["kind"] == "quad":
        near = [c + 0.5 * hh for c, hh in zip(spec["g"]["c"], h)]
    else:
        near = [float(rng.uniform(-0.6, 0.6) * L) for L in Ls]
    far = [float(rng.choice([-1, 1]) * (0.99 * PI if i in per else 0.85 * Ls[i])) for i in range(d)]
    spec["X"] = [typ, near, far]
    return spec


def draw():
    rng = np.random.default_rng(SEED)
    return {s["name"]: s for s in (gen(rng, k) for k in range(len(KINDS)))}


# ================= building (round 39's run, certify_at and fine_solve build through it) =========
def build(spec, scale=1.0, widen=1.0, horizon="spec"):
    per = tuple(spec["periodic"])
    T = spec["T"] if horizon == "spec" else horizon
    kw = {}
    if spec["exit"] is not None:
        kw = dict(exit=r41.region(spec["exit"]), exit_cost=r41.exit_cost(spec))
    return Problem(
        make_system(spec),
        r39.make_grid(spec["box"], per, scale, widen),
        T,
        terminal_cost=None if T is None else TermCost(spec["g"], per),
        state_cost=StateCost(spec["q"], per),
        control_cost=np.asarray(spec["R"]),
        temperature=spec["lam"],
        **kw,
    )


_r39_fine_scale = r39.fine_scale


def fine_scale(spec):
    if spec["d"] == 4:
        return 1.3
    return _r39_fine_scale(spec)


_r39_certify_at = r39.certify_at


def certify_at(spec, fine, X, t, n=2000, seed=SEED):
    return _r39_certify_at(spec, fine, X, t, n, seed)


r39.build, r41.build = build, build
r39.OUT, r41.OUT = OUT, OUT
r39.fine_scale = fine_scale
r39.certify_at = certify_at


# Truths that move with the SDE step beyond their SE (the certificate at x0, fine policy, seed 44:
# 1.006, 1.198, 1.266, 1.303 at dt 0.004, 0.001, 0.0005, 0.00025, an O(√dt) approach; no warning
# in the run): the exit set's small ball (radius 0.027 in position, a noise-free axis) is crossed
# within a step and not seen. Not trusted at any state.
DT_BIASED = {"r44_PointMass_fe_04"}


def trusted(r, k, i):
    return r["name"] not in DT_BIASED and r41.trusted(r, k, i)


r39.trusted = trusted  # round 39's table() counts with this


# ================= run, checks, table ============================================================
def run(name, spec):
    r41.STRAY.clear()
    r41._CALLS.clear()
    f = OUT / f"{name}.json"
    try:
        r39.run(name, spec, wall=spec["d"] < 4)
    except Exception as ex:  # the truth failed (r44_Linear2_fe_10: the proposal's controls NaN)
        fail = f"after the solve: {type(ex).__name__}: {ex}"[:600]
        print(name, "RAISED", fail)
        X = np.asarray(spec["X"], float)
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            sol = gridlbc.solve(build(spec), progress=False)
            v = np.asarray(sol.value(X), float)
            e = np.asarray(sol.error_estimate(X), float)
        wl = r41._warnlist(w)
        rec = dict(name=name, spec=spec, warnings=wl, warned=bool(wl), seconds=0.0, reads=[])
        rec.update(fail=fail, v=v.tolist(), est=e.tolist(), shape=list(sol.grid.shape))
        f.write_text(json.dumps(rec, indent=1, default=float))
    rec = json.loads(f.read_text())
    rec["stray"] = list(r41.STRAY)
    f.write_text(json.dumps(rec, indent=1, default=float))
    for x in r41.STRAY:
        print("    STRAY:", x["category"], x["stage"], x["where"], x["message"][:200])


def flagged(rec):
    """(k, i, kind) of the trusted pairs that are SILENT (> 10 % off, quiet) or UNDER-READ."""
    out = []
    for k, rd in enumerate(rec.get("reads", [])):
        for i in range(len(rd["v"])):
            if not trusted(rec, k, i):
                continue
            err, est = rd["err_rel"][i], rd["est_rel"][i]
            if err > 0.10 and not rec["warned"]:
                out.append((k, i, "SILENT"))
            elif err >= 0.01 and not (est >= 0.5 * err):
                out.append((k, i, "UNDER"))
    return out


def tolcheck(name, k, i):
    spec = draw()[name]
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    rd = rec["reads"][k]
    x, t, vt = spec["X"][i], rd["t"], rd["truth"][i]
    t1 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        kw = {} if spec["T"] is None or t == 0 else dict(times=[t])
        try:
            s = gridlbc.solve(
                build(spec), tol=0.05, states=[x], max_seconds=120, progress=False, **kw
            )
            fail = None
        except Exception as ex:
            s, fail = None, f"{type(ex).__name__}: {ex}"[:600]
    res = dict(
        k=k,
        i=i,
        t=t,
        seconds=time.perf_counter() - t1,
        fail=fail,
        warnings=[
            dict(
                category=y.category.__name__,
                message=str(y.message)[:300],
                where=f"{y.filename}:{y.lineno}",
            )
            for y in w
        ],
    )
    if s is not None:
        args = (np.asarray([x], float),) if spec["T"] is None else (np.asarray([x], float), t)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            v = float(np.asarray(s.value(*args))[0])
            e = float(np.asarray(s.error_estimate(*args))[0])
        ref = getattr(s, "refinement", None) or []
        res.update(
            met=bool(ref[-1].met(0.05)) if ref else None,
            rounds=[(list(r.shape), float(r.error), r.reason) for r in ref],
            v=v,
            err_rel=abs(v - vt) / max(abs(vt), spec["lam"]),
            est_rel=e / max(abs(v), spec["lam"]),
        )
        print(
            f"{name} k={k} i={i}: met={res['met']} v={v:.5g} v*={vt:.5g} "
            f"err={res['err_rel']:.2%} est={res['est_rel']:.2%} {res['seconds']:.0f}s"
        )
    else:
        print(f"{name} k={k} i={i}: RAISED {fail}")
    for y in res["warnings"]:
        print("   ", y["category"], y["where"], y["message"][:200])
    rec.setdefault("tolcheck", []).append(res)
    f.write_text(json.dumps(rec, indent=1, default=float))


def recheck(name, seed=SEED + 1):
    spec = draw()[name]
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = gridlbc.solve(build(spec), error_estimate=False, progress=False)
    fine, _ = r39.fine_solve(spec, s)
    out = []
    for rd in rec["reads"]:
        vt, info = _r39_certify_at(spec, fine, np.asarray(spec["X"], float), rd["t"], 2000, seed)
        out.append(dict(t=rd["t"], truth=vt.tolist(), info=info))
        print(f"{name} t={rd['t']:.4g} v*={np.round(vt, 5).tolist()} first={rd['truth']}")
    rec["recheck"] = out
    f.write_text(json.dumps(rec, indent=1, default=float))


def table():
    r39.table()
    n_over, n_pairs, n_tr, over = 0, 0, 0, []
    for f in sorted(OUT.glob("*.json")):
        r = json.loads(f.read_text())
        for k, rd in enumerate(r.get("reads", [])):
            for i in range(len(rd["v"])):
                n_pairs += 1
                if not trusted(r, k, i):
                    continue
                n_tr += 1
                err, est = rd["err_rel"][i], rd["est_rel"][i]
                if est > 20 * max(err, 0.01):
                    n_over += 1
                    over.append((r["name"], round(rd["t"], 4), i, round(err, 4), round(est, 4)))
    print(f"over-reads by this round's rule (ê > 20× max(err, 1 %), trusted): {n_over}")
    print(*over, sep="\n  ")
    print("\nper pair (t, i, v, v*, ±, ESS, k̂, err, ê, trusted):")
    for f in sorted(OUT.glob("*.json")):
        r = json.loads(f.read_text())
        sp = r["spec"]
        print(
            f"{r['name']} {r.get('shape')} λ={sp['lam']:.3g} T={sp['T']} "
            f"{r['seconds']:.1f}s warned={r['warned']} fail={r.get('fail')}"
        )
        for x in r.get("warnings", []):
            print("   warn:", x["category"], x["message"][:200])
        for x in r.get("stray", []):
            print("   STRAY:", x["category"], x["stage"], x["where"], x["message"][:200])
        for k, rd in enumerate(r.get("reads", [])):
            inf = rd["info"]
            for i in range(len(rd["v"])):
                print(
                    f"   t={rd['t']:.4g} x{i} v={rd['v'][i]:.5g} v*={rd['truth'][i]:.5g}"
                    f"±{inf['se'][i]:.2g} ess={inf['ess'][i]:.0f} k={inf['khat'][i]:.2f} "
                    f"err={rd['err_rel'][i]:.2%} est={rd['est_rel'][i]:.2%} "
                    f"trusted={trusted(r, k, i)}"
                )
        for k, i, kind in flagged(r):
            print(f"   FLAG {kind} k={k} x{i}")
        for c in r.get("tolcheck", []):
            print(
                f"   tolcheck k={c['k']} x{c['i']}: met={c.get('met')} "
                f"err={c.get('err_rel', float('nan')):.2%} est={c.get('est_rel', float('nan')):.2%}"
            )


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
    elif "--tolcheck" in argv:
        a = argv[argv.index("--tolcheck") + 1 :]
        tolcheck(a[0], int(a[1]), int(a[2]))
    elif "--recheck" in argv:
        for n in argv[argv.index("--recheck") + 1 :]:
            recheck(n)
    elif "--dtcheck" in argv:  # round 41's: the truth again at SDE steps 0.002 and 0.001
        a = argv[argv.index("--dtcheck") + 1 :]
        r41.dtcheck(a[0], specs[a[0]], int(a[1]))
    elif "--table" in argv:
        table()
    else:
        print(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
