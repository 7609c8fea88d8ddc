"""Stranger round 46: is the DEFAULT solve ever silently wrong? Random hold-out problems (seed 46)
mixing round 44's built-in systems and round 39/41's user-written nonseparable ``RandSys``, public
API only.

WHAT MAIN DID WITH IT (2026-12-08): certify's warnings of few effective samples, a heavy tail and
unexited paths name the start state with ``state_text`` (4 significant digits), as the others do.
r46_Linear2_fe_29's heavy-tailed certificate at a reflecting wall is left open (warned each time).

RESULTS (library of main 923a4ee, worktree r46, 2026-12-07 22:59–23:45 UTC, one thread, the
other core busy): ``--run`` of the 24 draws of ``PLAN`` (each under ``timeout 480``, none hit
it; r46_PointMass_fe_02, r46_Linear3_hzfe_06 and r46_Linear2_fe_08 rerun after two fixes to this
script: a certify warning printing its state as a plain numpy array, and the truth skipping a
state whose fine value is +inf), then 8 more draws appended to ``PLAN`` (the first 24 unchanged),
``--diag r46_rand3d_fe_15 2``, by hand the checks of r46_Linear2_fe_29 below, ``--table``.

- 32 problems (built-in 16: Pendulum 4, PointMass 4, LinearSystem 2-D 4 / 3-D 4; user-written
  RandSys 16: 2-D 8, 3-D 8; 11 fixed horizon, 13 stationary first exits, 8 first exits with a
  horizon; λ 0.0104–2.55), 0 raised. Default solves 0.5–32 s (error_estimate at the 3 states
  another 0.1–10 s). 30 of 32 warned (37 ResolutionWarnings, 1 UnderflowWarning); quiet:
  r46_rand2d_fe_05 (λ 1.93) and r46_rand2d_fe_13 (λ 1.65), every pair ≤ 0.6 % off.
- 96 (problem, state) pairs at t = 0, 63 trusted. The 33 others: ESS 1–15 (k̂ 1.3–87) at small
  λ (PointMass_fe_02 λ 0.020, PointMass_hzfe_20 0.011, rand3d_fe_26 0.019, rand3d_hz_19 0.031,
  Linear3_hzfe_06 0.060, Linear2_hz_22 0.025, Linear3_hz_31 0.17, PointMass_fe_25 0.17; all
  warned, ê 55–170 % of |v*| where they are off), k̂ 0.75–1.8 (Linear3_fe_14 x0, Pendulum_hzfe_16
  x0, rand3d_hz_30 x0, Linear2_fe_29 x0/x1, below), ESS 78–99 (Pendulum_hz_27 x1,
  Pendulum_fe_10 x2, Linear2_fe_29 x1), and no truth: r46_Linear2_fe_08 x0 (the exit set cannot
  be reached from it: v = +inf, UnderflowWarning, TRUE: ẋ1 = 0.30 x0 + 1.65 x1 with the one
  control on x0) and r46_PointMass_fe_25 x0 (the 2× finer solve's z underflows there, v/λ ≈ 620;
  the default solve reads 105.5 with ê 143).
- OFF (> 10 % of |v*|, trusted): 8, ALL WARNED. SILENT: 0. (err / ê, both of |v*|)
  r46_rand2d_fe_21 x0 −29.9 / 34.6 %, x1 −10.9 / 15.9, x2 −15.6 / 28.8 (λ 0.038);
  r46_rand2d_hzfe_03 x0 −17.8 / 17.9, x1 −15.6 / 18.1 (λ 0.020); r46_rand3d_fe_15 x2 (near)
  −15.4 / 13.2; r46_Pendulum_fe_10 x0 −12.4 / 33.9; r46_rand3d_hzfe_11 x2 (near) +10.2 / 30.0.
  Relative to max(|v*|, λ) the same numbers (v* > λ at all of them).
- UNDER-READS (ê < ½|v − v*|, |v − v*| > 2 SE, trusted): 0. Closest (ê / |v − v*|):
  r46_rand3d_fe_15 x2 0.86, r46_rand2d_hz_17 x0 0.87 (err 1.9 %), r46_Pendulum_hz_00 x2 0.93,
  r46_Linear2_hzfe_18 x1 0.96, r46_Pendulum_hz_00 x1 0.98, r46_rand2d_hzfe_03 x0 1.00.
  ``--diag r46_rand3d_fe_15 2`` (near state (0.25, 0.77, −0.63), union exit, λ 0.456): default
  39×39×41 v 1.3543; the 2× finer solve 1.5518 (its own ê 0.198); v* 1.6000 ± 0.006 (dt 0.004,
  seed 46) and 1.6095 ± 0.006 (dt 0.002, seed 47, ESS 1851, k̂ 0.19): the default GRID is the
  error (0.246 → 0.048 on halving), the estimate sees 86 % of it; the 1.5× wider box leaves v
  (1.3543) unchanged.
- UNTRUSTED, flagged UNDER, warned: r46_Linear2_fe_29 x0 (far corner (−1.90, −3.80), LinearSystem
  A = [[0.56, 1.58], [1.09, −0.84]] (eigenvalues 1.35, −1.63), B = I, R = diag(9.98, 0.47),
  λ 2.07, exit a box x0 ∈ [0.196, 0.416] with a wave cost, 126×41): v 9.789, ê 0.085 (0.9 %),
  v* 8.196 ± 0.51 (ESS 75, k̂ 1.84, "heavy tail" warned). The grid converges: 9.789, 9.720,
  9.684 (1×, 2×, 4× per axis; x1 7.226, 7.212, 7.204), so ê ≈ the grid's own error. The
  certificate does not settle: v* 8.55 ± 0.26 (2× policy, 8000 paths, seed 47, k̂ 2.62), 9.02 ±
  0.41 (the default solve's policy, k̂ 1.84), 8.50 ± 0.36 (dt 0.001, k̂ 2.52), 8.47 / 8.45 (the
  4× solve's policy, dt 0.004 / 0.001, k̂ 2.4 / 2.7), while that policy's own cost J = 9.58 ±
  0.075 (dt 0.004) and 9.57 ± 0.073 (dt 0.001), every path from x0 touching the reflecting box
  (left_box_fraction 1.0; the 1.5× wider box gives v 20.06, the far corner is held by the wall).
  J ≈ the grid's value makes a 12 % suboptimal converged policy unlikely: read as a certify
  weakness at a reflecting wall under large noise (σ² = λ/R = 4.4 along x1), NOT counted, open.
- Warned with all three trusted pairs < 5 % off: 10 (Linear2_hzfe_18 4.2 %, rand3d_fe_01 4.9,
  Pendulum_hz_00 3.8, rand2d_hz_17 1.9, rand2d_hzfe_28 1.3, Linear3_hz_04 0.75, PointMass_hz_12
  0.29, rand3d_hz_07 0.25, rand2d_hz_09 0.05, rand2d_hz_24 0.02). The horizon problems'
  warnings name a state at a LATER time (t = T − 0.01 … T − 0.31 in 7 of 8; rand2d_hz_24 at t =
  0.196 of T 0.98), not the t = 0 read here, where ê is 0.0–3.5 %; the two first exits with a
  horizon also warn that "the plain scheme cannot resolve" v/λ's rise at 37–48 % of the nodes;
  rand3d_fe_01's "at 100 % of the states that matter" is matched by ê 8.5–11 % at the states
  (errors 0.2–4.9 %). Not checked further (the brief reads t = 0 only).
- Stray warnings: none (no non-gridlbc warning from a solve, a read or a certificate). API
  oddities: certify's warnings of few effective samples, heavy tails and unexited paths print
  x0 as a plain numpy array ("[-3.03743371 -3.06       -1.955     ]"), its step-bias warning
  with ``state_text`` ("[-3.834, 4.66]"); ``Solution.policy`` of an underflowed state warns
  UnderflowWarning at every call (≈ 10⁴ times in one certify under "always", r46_Linear2_fe_08,
  where this script zeroes the NaN controls so that certify runs).

Generator (``gen``, seed 46; ``PLAN`` fixes each draw's family, system or dimension and ending,
the rest is random): built-in systems (Pendulum, PointMass, LinearSystem 2-D / 3-D; the
1-D SingleIntegrator left out) with round 44's ``system_draw`` (random constructor parameters, a box a user would pick,
angles periodic), round 44's grid sizes (2-D 31–201 per axis, 3-D 21–41), state cost (constant,
quadratic, a narrow wall or pit, 1 − cos on angles) and terminal cost (wrap-aware quadratic about
a random target, or a swing-up cost); or a user-written ``ControlAffineSystem`` with nonseparable
drift (round 39's ``RandSys``: a random rotation/shear generator, bounded tanh / sin / product
couplings, state-dependent gains, maybe one unactuated axis; its state cost of Gaussians, ridges
and logistic walls; its terminal cost a rotated quadratic with maybe a dip; 2-D 61–201 nodes per
axis, 3-D 31–41). λ log-uniform in [0.01, 3] for every draw. Endings: a horizon T (0.5–5), a
stationary first exit (q ≥ 0.05 off E; exit sets of round 41's ``exit_draw``: a Ball, a Box, a
half-space, or a union, "small" parts one or two cells wide; constant, quadratic or wave exit
cost), or a first exit with a horizon. States, as a user picks them, on the line from the GOAL
(the terminal cost's target, or a point of the first part of E) to the corner of the box (at 0.85
of each closed half-width, the angle opposite the goal on a periodic axis) farthest from it:
"far" = that corner, "middle" = halfway, "near" = the nearest point at 10–45 % of the way whose
±1.5-cell neighbourhood is clear of E (and at least 15 % of the way).

Truth: ``gridlbc.certify(problem, fine.policy, X, 2000, dt, seed=46, proposal=None,
richardson=True, boundary="reflect")`` at t = 0, ``fine`` the problem solved on a grid 2× finer
per axis (1.5× where that passes 1.5 M nodes, the default solve's own policy above 3 M) with half
the default solve's Δt; dt = 0.004 (min(0.004, T/50) with a horizon), max_time 25 without one.
A pair is TRUSTED when ESS ≥ 100, k̂ ≤ 0.7 and no CertificateWarning names the state for heavy
tails, too few effective samples, or unexited paths that carry weight ("v* and J are
underestimated"). The default solve is ``gridlbc.solve(problem, progress=False)`` under
``warnings.catch_warnings(record=True)``; WARNED = any GridlbcWarning raised in it (those raised
by ``value`` / ``error_estimate`` are recorded apart). Per pair: err = (v − v*)/|v*| and
errλ = (v − v*)/max(|v*|, λ); OFF = |err| > 10 %; SILENT = OFF and not warned; UNDER-READ =
error_estimate(x) < ½|v − v*| with |v − v*| > 2 SE(v*).

    cd /work/wt-r46 && PYTHONPATH=/work/wt-r46 NUMBA_NUM_THREADS=1 \\
        python benchmarks/holdout/strangers_round46.py --list | --run [NAMES] | --table \\
        | --diag NAME I [I ...]
"""

from __future__ import annotations

import json
import math
import re
import sys
import time
import traceback
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import strangers_round39 as r39
import strangers_round41 as r41
import strangers_round44 as r44
from strangers_round25 import loguni

import gridlbc
from gridlbc import Problem

OUT = Path(__file__).parent / "strangers_round46_results"  # gitignored
SEED = 46
PI = math.pi
# (family, system or dimension, ending): the draw's skeleton; everything else is random
PLAN = [
    ("builtin", "Pendulum", "hz"),
    ("rand", 3, "fe"),
    ("builtin", "PointMass", "fe"),
    ("rand", 2, "hzfe"),
    ("builtin", "Linear3", "hz"),
    ("rand", 2, "fe"),
    ("builtin", "Linear3", "hzfe"),
    ("rand", 3, "hz"),
    ("builtin", "Linear2", "fe"),
    ("rand", 2, "hz"),
    ("builtin", "Pendulum", "fe"),
    ("rand", 3, "hzfe"),
    ("builtin", "PointMass", "hz"),
    ("rand", 2, "fe"),
    ("builtin", "Linear3", "fe"),
    ("rand", 3, "fe"),
    ("builtin", "Pendulum", "hzfe"),
    ("rand", 2, "hz"),
    ("builtin", "Linear2", "hzfe"),
    ("rand", 3, "hz"),
    ("builtin", "PointMass", "hzfe"),
    ("rand", 2, "fe"),
    ("builtin", "Linear2", "hz"),
    ("rand", 3, "fe"),
    # eight more, drawn after the first 24 had run (those unchanged)
    ("rand", 2, "hz"),
    ("builtin", "PointMass", "fe"),
    ("rand", 3, "fe"),
    ("builtin", "Pendulum", "hz"),
    ("rand", 2, "hzfe"),
    ("builtin", "Linear2", "fe"),
    ("rand", 3, "hz"),
    ("builtin", "Linear3", "hz"),
]


def _h(box, per):
    return [(hi - lo) / (n - (0 if i in per else 1)) for i, (lo, hi, n) in enumerate(box)]


# ================= the draw ======================================================================
def gen_builtin(rng, kind, ending, k):
    """Round 44's draw of a built-in system and its costs, with the ending given."""
    par, box, per = r44.system_draw(rng, kind)
    box = r44._fix([[float(a), float(b)] for a, b in box])
    d = len(box)
    lo_n, hi_n = {2: (31, 201), 3: (21, 41)}[d]
    ns = [int(rng.integers(lo_n, hi_n + 1)) for _ in range(d)]
    ns = [n + n % 2 if i in per else n for i, n in enumerate(ns)]
    box = [[lo, hi, n] for (lo, hi), n in zip(box, ns)]
    h = _h(box, per)
    Ls = [hi for _, hi, _ in box]
    closed = [i for i in range(d) if i not in per]
    m = r44.make_system(dict(kind=kind, params=par)).control_dim
    R = np.diag([loguni(rng, 0.01, 10.0) for _ in range(m)]).tolist()
    T = None if ending == "fe" else float(rng.uniform(0.5, 5.0))
    q = dict(c0=0.0, quad=None, feat=[], cos=[])
    if rng.random() < 0.6 or ending == "fe":
        q["c0"] = float(rng.uniform(0.05, 1.0))
    if rng.random() < 0.6:
        q["quad"] = dict(
            c=[float(rng.uniform(-0.5, 0.5) * L) for L in Ls],
            W=[float(loguni(rng, 0.05, 3.0) if rng.random() < 0.7 else 0.0) for _ in range(d)],
        )
    if rng.random() < 0.7:
        w = float(rng.uniform(0.5, 3.0))
        if closed and rng.random() < 0.5:
            ax = int(rng.choice(closed))
            c = float(rng.uniform(-0.5, 0.5) * Ls[ax])
            q["feat"].append(dict(kind="wall", axis=ax, c=c, w=w * h[ax], H=loguni(rng, 0.5, 20.0)))
        else:
            c = [float(rng.uniform(-0.5, 0.5) * L) for L in Ls]
            q["feat"].append(
                dict(kind="pit", c=c, w=[w * hh for hh in h], D=loguni(rng, 0.5, 10.0))
            )
    for i in per:
        if rng.random() < 0.6:
            q["cos"].append(dict(axis=i, a=loguni(rng, 0.1, 5.0), phi=float(rng.choice([0.0, PI]))))
    spec = dict(
        name=f"r46_{kind}_{ending}_{k:02d}",
        family="builtin",
        kind=kind,
        params=par,
        d=d,
        box=box,
        periodic=per,
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
    return spec


def gen_rand(rng, d, ending, k):
    """Round 39's nonseparable RandSys and costs, 3-D grids capped at 41 per axis."""
    spec = r39.gen(rng, d, k)
    for b in spec["box"]:
        if d == 3 and b[2] > 41:
            b[2] = 40 if b[2] % 2 == 0 else 41
    T = None if ending == "fe" else float(np.round(rng.uniform(0.5, 5.0), 2))
    if ending == "fe":
        spec["q0"] = float(rng.uniform(0.2, 1.0))
    spec.update(name=f"r46_rand{d}d_{ending}_{k:02d}", family="rand", kind=f"rand{d}d", T=T)
    spec["ending"] = ending
    return spec


def build(spec, scale=1.0, widen=1.0):
    per = tuple(spec["periodic"])
    T = spec["T"]
    kw = {}
    if spec.get("exit") is not None:
        kw = dict(exit=r41.region(spec["exit"]), exit_cost=r41.exit_cost(spec))
    grid = r39.make_grid(spec["box"], per, scale, widen)
    if spec["family"] == "builtin":
        sysm = r44.make_system(spec)
        qc, gc = (
            r44.StateCost(spec["q"], per),
            (None if T is None else r44.TermCost(spec["g"], per)),
        )
    else:
        sysm = r39.RandSys(
            spec["A"],
            spec["a0"],
            spec["terms"],
            spec["b"],
            spec["beta"],
            spec["gk"],
            spec["M"],
            per,
        )
        qc, gc = r39.StateCost(spec), (None if T is None else r39.TermCost(spec))
    return Problem(
        sysm,
        grid,
        T,
        terminal_cost=gc,
        state_cost=qc,
        control_cost=np.asarray(spec["R"]),
        temperature=spec["lam"],
        **kw,
    )


def in_exit(spec, X):
    if spec.get("exit") is None:
        return np.zeros(len(np.atleast_2d(X)), bool)
    return np.asarray(r41.region(spec["exit"])(np.atleast_2d(np.asarray(X, float))), bool)


def goal_point(spec):
    d = spec["d"]
    if spec.get("exit") is not None:
        p = spec["exit"]["parts"][0]
        if p[0] == "ball":
            return list(p[1])
        out = []
        for a, b in zip(p[1], p[2]):
            fa, fb = math.isfinite(a), math.isfinite(b)
            out.append((a + b) / 2 if fa and fb else a if fa else b if fb else 0.0)
        return out
    g = spec["g"]
    if g.get("kind") == "swing":
        return [0.0] * d
    return [float(c) for c in g["c"]]


def states_draw(rng, spec):
    """far corner, middle, near-but-clear-of-E, on the line from the goal to the far corner."""
    d, per = spec["d"], spec["periodic"]
    box = spec["box"]
    h = _h(box, per)
    Ls = [hi for _, hi, _ in box]
    G = np.asarray(goal_point(spec), float)
    offs = np.array(list(np.ndindex(*(7,) * d)), float) / 2.0 - 1.5  # ±1.5 cells, half steps

    def clear(x):
        pts = np.asarray(x)[None] + offs * np.asarray(h)[None]
        return not in_exit(spec, pts).any()

    def inbox(x):
        return all(i in per or lo <= v <= hi for i, (v, (lo, hi, _)) in enumerate(zip(x, box)))

    def wrap(x):
        x = np.array(x, float)
        for i in per:
            x[i] = (x[i] + PI) % (2 * PI) - PI
        return x

    best, far = -1.0, None
    for signs in np.ndindex(*(2,) * d):
        x = np.array([0.85 * L * (1 if s else -1) for s, L in zip(signs, Ls)])
        for i in per:
            x[i] = G[i] + PI * (0.95 if signs[i] else -0.95)
        x = wrap(x)
        dist = float(np.linalg.norm(r39.wrapdiff(x[None], G, per)[0] / np.asarray(Ls)))
        if clear(x) and dist > best:
            best, far = dist, x
    if far is None:
        raise RuntimeError("no far corner clear of E")
    D = r39.wrapdiff(far[None], G, per)[0]

    def along(f):
        return wrap(G + f * D)

    mid = None
    for f in (0.5, 0.45, 0.55, 0.4, 0.6, 0.35, 0.65, 0.7, 0.3):
        x = along(f + float(rng.uniform(-0.03, 0.03)))
        if clear(x) and inbox(x):
            mid = x
            break
    near = None
    for f in np.arange(0.10, 0.46, 0.01):
        x = along(max(f, 0.15))
        if clear(x) and inbox(x):
            near = x
            break
    if mid is None or near is None:
        raise RuntimeError("no middle or near state clear of E")
    spec["X"] = [far.tolist(), mid.tolist(), near.tolist()]
    spec["X_kind"] = ["far", "middle", "near"]
    spec["goal"] = G.tolist()
    return spec


def nodes(spec):
    axes = [
        np.linspace(lo, hi, n, endpoint=i not in spec["periodic"])
        for i, (lo, hi, n) in enumerate(spec["box"])
    ]
    g = np.meshgrid(*axes, indexing="ij")
    return np.stack([a.ravel() for a in g], axis=1)


def gen(rng, k):
    fam, what, ending = PLAN[k]
    draw_one = gen_builtin if fam == "builtin" else gen_rand
    spec = draw_one(rng, what, ending, k)
    spec["lam"] = loguni(rng, 0.01, 3.0)
    spec["exit"] = None
    if ending != "hz":
        h = _h(spec["box"], spec["periodic"])
        share = 0.0
        for _ in range(30):
            spec["exit"] = r41.exit_draw(rng, spec["d"], spec["box"], spec["periodic"], h)
            try:
                share = float(in_exit(spec, nodes(spec)).mean())
            except Exception:  # a draw the region refuses: draw again
                continue
            if 0 < share < 0.5:
                break
        spec["exit_share"] = share
    return states_draw(rng, spec)


def draw():
    rng = np.random.default_rng(SEED)
    return {s["name"]: s for s in (gen(rng, k) for k in range(len(PLAN)))}


# ================= truth =========================================================================
def fine_solve(spec, sol):
    n = float(np.prod([b[2] for b in spec["box"]]))
    d = spec["d"]
    sc = 2.0 if n * 2**d <= 1.5e6 else 1.5
    if n * sc**d > 3e6:
        return sol, 1.0
    kw = {} if spec["T"] is None else dict(dt=float(sol.diagnostics.dt) / 2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return gridlbc.solve(build(spec, scale=sc), error_estimate=False, progress=False, **kw), sc


def _named_state(msg, X):
    """The index of the state in X a certify warning names ('x0 = [..]'), or None."""
    m = re.search(r"x0 = \[([-0-9.e, +]+)\]", msg)
    if not m:
        return None
    try:
        x = np.array([float(v) for v in re.split(r"[,\s]+", m.group(1).strip())])
    except ValueError:
        return None
    if len(x) != X.shape[1]:
        return None
    dist = np.abs(X - x[None]).max(1) / np.maximum(np.abs(X).max(1), 1e-3)
    i = int(np.argmin(dist))
    return i if dist[i] < 1e-3 else None


BAD = ("heavy tail", "effective sample size", "v* and J are underestimated")


def certify_truth(spec, policy, X, n=2000, seed=SEED, dt=None):
    p = build(spec)
    if spec["T"] is None:
        kw = dict(dt=dt or 0.004, max_time=25.0)
    else:
        kw = dict(dt=dt or min(0.004, spec["T"] / 50))
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        c = gridlbc.certify(
            p,
            policy,
            X,
            n,
            seed=seed,
            proposal=None,
            richardson=True,
            progress=False,
            boundary="reflect",
            **kw,
        )
    cw, bad, seen = [], np.zeros(len(X), bool), {}
    for x in w:
        msg = str(x.message)
        i = _named_state(msg, X) if issubclass(x.category, gridlbc.GridlbcWarning) else None
        is_bad = issubclass(x.category, gridlbc.CertificateWarning) and any(b in msg for b in BAD)
        if is_bad:
            if i is None:
                bad[:] = True
            else:
                bad[i] = True
        key = (x.category.__name__, i, is_bad, re.sub(r"[0-9.]+", "#", msg[:120]))
        if key in seen:  # a warning repeated at every policy call: kept once, counted
            cw[seen[key]]["count"] += 1
            continue
        seen[key] = len(cw)
        cw.append(
            dict(category=x.category.__name__, state=i, bad=is_bad, message=msg[:400], count=1)
        )
    return dict(
        v=np.asarray(c.extrapolated_value, float).tolist(),
        se=np.asarray(c.extrapolated_value_se, float).tolist(),
        v_dt=np.asarray(c.optimal_value, float).tolist(),
        ess=np.asarray(c.effective_sample_size, float).tolist(),
        khat=np.asarray(c.pareto_k, float).tolist(),
        unexited=np.asarray(c.unexited_fraction, float).tolist(),
        cert_bad=bad.tolist(),
        cert_warnings=cw,
        dt=kw["dt"],
        n=n,
        seed=seed,
    )


def zero_where_nan(policy):
    """The policy with u = 0 where it is NaN (where E cannot be reached and z underflowed): a
    path that wanders there never exits and pays q until max_time, so its weight is negligible;
    the certificate holds for any policy (SPEC §6)."""

    def pol(x, t):
        return np.nan_to_num(np.asarray(policy(x, t), float), nan=0.0, posinf=0.0, neginf=0.0)

    return pol


def trusted_pair(tr, i):
    kh = tr["khat"][i]
    return bool(
        tr["ess"][i] >= 100
        and (not np.isfinite(kh) or kh <= 0.7)
        and not tr["cert_bad"][i]
        and np.isfinite(tr["v"][i])
    )


# ================= run ===========================================================================
def _wl(w):
    return [
        dict(
            category=x.category.__name__,
            gridlbc=issubclass(x.category, gridlbc.GridlbcWarning),
            message=str(x.message)[:500],
            where=f"{Path(x.filename).name}:{x.lineno}",
        )
        for x in w
    ]


def run(name, spec):
    OUT.mkdir(parents=True, exist_ok=True)
    f = OUT / f"{name}.json"
    rec = dict(name=name, spec=spec, status="started")
    f.write_text(json.dumps(rec, indent=1, default=float))
    X = np.asarray(spec["X"], float)
    t0 = time.perf_counter()
    sol = None
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            p = build(spec)
            sol = gridlbc.solve(p, progress=False)
        except Exception as ex:
            rec["fail"] = f"{type(ex).__name__}: {ex}"[:600]
            rec["tb"] = traceback.format_exc()[-3000:]
    rec["solve_seconds"] = time.perf_counter() - t0
    rec["solve_warnings"] = _wl(w)
    rec["warned"] = any(x["gridlbc"] for x in rec["solve_warnings"])
    if sol is None:
        rec["status"] = "raised"
        print(f"{name}: RAISED {rec['fail']}")
        f.write_text(json.dumps(rec, indent=1, default=float))
        return
    rec["shape"] = list(p.grid.shape)
    if spec["T"] is not None:
        rec["dt"] = float(sol.diagnostics.dt)
    t1 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        v = np.asarray(sol.value(X), float)
        e = np.asarray(sol.error_estimate(X), float)
    rec["read_seconds"] = time.perf_counter() - t1
    rec["read_warnings"] = _wl(w)
    rec.update(v=v.tolist(), est=e.tolist())
    f.write_text(json.dumps(rec, indent=1, default=float))
    t2 = time.perf_counter()
    fine, sc = fine_solve(spec, sol)
    rec["fine_scale"], rec["fine_seconds"] = sc, time.perf_counter() - t2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec["v_fine"] = np.asarray(fine.value(X), float).tolist()
    t3 = time.perf_counter()
    ok = np.isfinite(rec["v_fine"])  # +inf where E cannot be reached (the solve warns): no truth
    try:
        try:
            tr = certify_truth(spec, fine.policy, X[ok])
        except ValueError as ex:  # a path stepped where the fine policy is NaN (E unreachable)
            if "non-finite controls" not in str(ex):
                raise
            rec["policy_nan_to_zero"] = str(ex)[:300]
            tr = certify_truth(spec, zero_where_nan(fine.policy), X[ok])
        for key in ("v", "se", "v_dt", "ess", "khat", "unexited", "cert_bad"):
            full = [math.nan] * len(X) if key != "cert_bad" else [True] * len(X)
            for j, i in enumerate(np.flatnonzero(ok)):
                full[i] = tr[key][j]
            tr[key] = full
        tr["certified"] = ok.tolist()
    except Exception as ex:
        rec["status"] = "truth raised"
        rec["fail"] = f"certify: {type(ex).__name__}: {ex}"[:600]
        print(f"{name}: certify RAISED {rec['fail']}")
        f.write_text(json.dumps(rec, indent=1, default=float))
        return
    rec["truth_seconds"] = time.perf_counter() - t3
    rec["truth"] = tr
    rec["status"] = "done"
    f.write_text(json.dumps(rec, indent=1, default=float))
    print_rec(rec)


# ================= table =========================================================================
def pairs(rec):
    """Per state: the numbers the table and the summary use."""
    out = []
    if rec.get("status") != "done":
        return out
    lam = rec["spec"]["lam"]
    tr = rec["truth"]
    for i in range(len(rec["v"])):
        v, vt, se, e = rec["v"][i], tr["v"][i], tr["se"][i], rec["est"][i]
        diff = v - vt
        err = diff / abs(vt) if vt != 0 else math.inf
        errl = diff / max(abs(vt), lam)
        tru = trusted_pair(tr, i)
        off = abs(err) > 0.10
        under = (not e >= 0.5 * abs(diff)) and abs(diff) > 2 * se
        out.append(
            dict(
                i=i,
                kind=rec["spec"]["X_kind"][i],
                v=v,
                vt=vt,
                se=se,
                ess=tr["ess"][i],
                khat=tr["khat"][i],
                err=err,
                errl=errl,
                est=e,
                est_rel=e / abs(vt) if vt else math.inf,
                trusted=tru,
                off=off,
                silent=off and not rec["warned"],
                under=under,
                v_fine=rec["v_fine"][i],
            )
        )
    return out


def warn_head(rec):
    ws = [x for x in rec.get("solve_warnings", []) if x["gridlbc"]]
    if not ws:
        return "quiet"
    cats = sorted({x["category"] for x in ws})
    return f"{'+'.join(cats)}: {ws[0]['message'][:80]!r}"


def print_rec(rec):
    sp = rec["spec"]
    print(
        f"{rec['name']} {rec.get('shape')} λ={sp['lam']:.3g} T={sp['T']} "
        f"solve {rec.get('solve_seconds', 0):.1f}s (+read {rec.get('read_seconds', 0):.1f}s, fine "
        f"×{rec.get('fine_scale')} {rec.get('fine_seconds', 0):.0f}s, truth "
        f"{rec.get('truth_seconds', 0):.0f}s) [{rec.get('status')}] {rec.get('fail', '')}"
    )
    print("   warned:", warn_head(rec))
    for x in rec.get("read_warnings", []):
        print("   read warning:", x["category"], x["where"], x["message"][:120])
    if rec.get("status") == "done":
        seen = {}
        for x in rec["truth"]["cert_warnings"]:
            key = (x["category"], x["state"], re.sub(r"[0-9.]+", "#", x["message"][:120]))
            seen.setdefault(key, [x, 0])[1] += x.get("count", 1)
        for x, c in seen.values():
            print(f"   cert warning (x{x['state']}, bad={x['bad']}, ×{c}):", x["message"][:150])
    for q in pairs(rec):
        flags = [k for k in ("off", "silent", "under") if q[k]]
        print(
            f"   x{q['i']} {q['kind']:6s} v={q['v']:.5g} v*={q['vt']:.5g}±{q['se']:.2g} "
            f"ess={q['ess']:.0f} k={q['khat']:.2f} err={q['err']:+.2%} errλ={q['errl']:+.2%} "
            f"ê={q['est']:.3g} ({q['est_rel']:.1%}) fine={q['v_fine']:.5g} "
            f"trusted={q['trusted']} {' '.join(flags).upper()}"
        )


def table():
    recs = [json.loads(f.read_text()) for f in sorted(OUT.glob("r46_*.json"))]
    n = dict(problems=len(recs), done=0, pairs=0, trusted=0, off=0, silent=0, under=0)
    n["warned"] = sum(bool(r.get("warned")) for r in recs)
    flagged = []
    for r in recs:
        print_rec(r)
        if r.get("status") == "done":
            n["done"] += 1
        for q in pairs(r):
            n["pairs"] += 1
            if not q["trusted"]:
                if q["off"] or q["under"]:
                    flagged.append((r["name"], q, "untrusted"))
                continue
            n["trusted"] += 1
            n["off"] += q["off"]
            n["silent"] += q["silent"]
            n["under"] += q["under"]
            if q["off"] or q["under"]:
                flagged.append((r["name"], q, "trusted"))
        for c in r.get("diag", []):
            print(f"   diag x{c['i']}: {c}")
    print("\nSUMMARY (counts over trusted pairs):", n)
    close = sorted(
        (q["est"] / abs(q["v"] - q["vt"]), name, q["i"], q["err"], q["est_rel"])
        for name, r in ((r["name"], r) for r in recs)
        for q in pairs(r)
        if q["trusted"] and abs(q["v"] - q["vt"]) > 2 * q["se"] and abs(q["err"]) > 0.01
    )
    print("closest to an under-read (ê / |v − v*|, trusted, err > 1 %):")
    for c in close[:6]:
        print(f"  {c[1]} x{c[2]}: ê/|v−v*| = {c[0]:.2f} (err {c[3]:+.2%}, ê {c[4]:.2%} of |v*|)")
    print("off / silent / under-read pairs (err, errλ, ê relative to |v*|, warned):")
    for name, q, t in flagged:
        rec = next(r for r in recs if r["name"] == name)
        print(
            f"  {name} x{q['i']} ({q['kind']}) [{t}] v={q['v']:.5g} v*={q['vt']:.5g}±{q['se']:.2g} "
            f"err={q['err']:+.2%} errλ={q['errl']:+.2%} ê={q['est_rel']:.2%} "
            f"{'SILENT ' if q['silent'] else ''}{'UNDER ' if q['under'] else ''}"
            f"OFF={q['off']} warned={warn_head(rec)[:60]}"
        )


# ================= diagnosis of a flagged pair ===================================================
def diag(name, idx):
    """The default solve again on a 2× finer grid (same Δt, then Δt halved as well with a horizon),
    and the certificate at half the SDE step and another seed, at the states ``idx``."""
    spec = draw()[name]
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    X = np.asarray([spec["X"][i] for i in idx], float)
    res = dict(idx=idx)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = gridlbc.solve(build(spec), progress=False)
        kw = {} if spec["T"] is None else dict(dt=float(s.diagnostics.dt))
        t0 = time.perf_counter()
        s2 = gridlbc.solve(build(spec, scale=2.0), progress=False, **kw)
        res["fine2_seconds"] = time.perf_counter() - t0
        res["fine2_v"] = np.asarray(s2.value(X), float).tolist()
        res["fine2_est"] = np.asarray(s2.error_estimate(X), float).tolist()
        if spec["T"] is not None:
            s3 = gridlbc.solve(build(spec), dt=float(s.diagnostics.dt) / 4, progress=False)
            res["dt4_v"] = np.asarray(s3.value(X), float).tolist()
        sw = gridlbc.solve(build(spec, widen=1.5), progress=False, error_estimate=False, **kw)
        res["wide_v"] = np.asarray(sw.value(X), float).tolist()
    fine, _ = fine_solve(spec, s)
    dt0 = rec["truth"]["dt"]
    tr2 = certify_truth(spec, fine.policy, X, n=2000, seed=SEED + 1, dt=dt0 / 2)
    res["truth_half_dt"] = dict(
        dt=tr2["dt"], v=tr2["v"], se=tr2["se"], ess=tr2["ess"], khat=tr2["khat"]
    )
    print(name, json.dumps(res, default=float))
    rec["diag"] = [r for r in rec.get("diag", []) if r.get("idx") != idx] + [res]
    f.write_text(json.dumps(rec, indent=1, default=float))


def main(argv):
    specs = draw()
    if "--list" in argv:
        for n, s in specs.items():
            print(n, json.dumps(s))
    elif "--names" in argv:
        print(" ".join(specs))
    elif "--run" in argv:
        names = argv[argv.index("--run") + 1 :] or [
            n for n in specs if not (OUT / f"{n}.json").exists()
        ]
        for n in names:
            run(n, specs[n])
    elif "--diag" in argv:
        a = argv[argv.index("--diag") + 1 :]
        diag(a[0], [int(v) for v in a[1:]])
    elif "--table" in argv:
        table()
    else:
        print(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
