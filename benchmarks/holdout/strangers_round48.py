"""Stranger round 48: first exits WITH a horizon after the fitted exit boundary (seed 48), public API only.

WHAT IT TESTS: main db3ff19 solves a task with a horizon AND an exit set
(``Problem(system, grid, T, terminal_cost, exit=E, exit_cost=g_E)``) by the implicit march with
the exit set's boundary fitted between the nodes (``gridlbc.schemes.generator
.folded_exit_generator``), as the stationary first-exit solve (horizon=None) already did. Before
it, such tasks read 11–19 % too high three cells from a small exit set, silently (round 47).
Here every problem but four has a horizon and an exit set ("hzfe"), with exits of the kinds the
fold touches: a small Ball (2–4 cells across), a thin Box slab with its faces on grid lines
("slab_on") or between them ("slab_mid"), a Box touching the edge of the grid's box ("edge"), a
union of two small balls, an exit given as a plain python function mask (``lambda x: ...``;
"func", no geometry, so held at the nodes), exits across the periodic seam of a pendulum's angle
("seam": a wrap-aware Ball; "func_seam": a wrapping lambda). Exit costs: constant, linear,
quadratic, and "steep" (linear along the exit's boundary at 2–5 λ per cell, not scaled with the
task). Four stationary first exits ("fe") are twins of hzfe draws (the same system, exit and
costs, no horizon) for comparison. States: far, middle, and one 2–4 cells from the exit set.

RESULTS (library of main db3ff19, worktree wt-r48 branch round48, one thread, the other core
busy): ``--run`` of all 20 draws, each under ``timeout 500`` (none hit it; 10–169 s wall per
problem, 15.8 min in all; default solves 0.6–13.6 s, certificates 3–129 s); ``--diagnose`` of the
four OFF problems and the two with quiet pairs 5–10 % off; ``--extra`` (the seam's mirror states,
a recheck of r48_Pendulum_hzfe_func_seam_14 x2); ``--before`` with db3ff19~1 (``git archive`` into
the results folder, ``PYTHONPATH`` at it); ``--table``.

- 20 problems (16 hzfe, 4 stationary twins), 60 pairs, 57 trusted (one heavy tail, k̂ 0.90; two
  "not yet of first order" far states). v*/λ 0.10–14; 19 trusted pairs with v* < λ, 28 with
  v* ≥ 2λ. 16 of 20 default solves warned. No crash, no non-gridlbc (numpy) warning.
- OFF (> 10 %): 4, all warned, none silent. ê ≥ |v − v*| at 46 of 57, within 2× at 57 of 57
  (lowest ê/|err| 0.62), no under-read.

      pair                              v       v*              err      ê        tol=0.05 at x
      r48_Pendulum_hzfe_seam_02 x2      1.358   1.562±0.012     −13.0 %  0.281    1.514 (−3.1 %), not met, 77 s
      r48_Pendulum_fe_seam_18 x2        1.358   1.562±0.010     −13.0 %  0.299    1.533 (−1.9 %), met, 76 s
      r48_PointMass_hzfe_slab_mid_13 x2 0.4246  0.5896±0.0062   −28.0 %  0.160    0.553 (−6.2 %), not met, 99 s
      r48_River2_hzfe_union_03 x2       0.02994 0.02612±0.0008  +14.6 %  0.00395  0.02634 (+0.9 %), met, 15 s

  All four are grid error of first order: the 2× grid reads −6.5 %, −6.4 %, −16.1 %, +6.0 %;
  dt/2 on the same grid changes nothing (−13.0 %, −27.6 %, +14.8 %). The seam is not the cause:
  the seam state's mirror on the near side of θ = π reads −9.4 % (hzfe) / −8.2 % (fe), −12.3 %
  across it (same v* within 1 SE). The hzfe and fe seam pairs agree to the digit (the exit is
  reached long before T): the march with a horizon now reads what the stationary solve reads.
- Near-exit states of the 16 hzfe draws now −28 … +14.6 % (median |err| 2.2 %); with db3ff19~1
  (``--before``) the same draws read +10.2, +13.3, +19.0, +19.3, +12.7 % at five near states (and
  +46 % / +22 % at r48_Pendulum_hzfe_ball_08's middle/far states, steep exit cost), now −2.2,
  −2.4, −1.2, +2.3, +6.6 % (−1.2 / −5.1 %). Two near states read worse after the fix: the seam
  pair (−4.3 → −13.0 %, the stationary twin's value: the node-held exit had cancelled the grid
  error) and r48_River2_hzfe_union_03 (+7.0 → +14.6 %, a steep exit cost of 24–43 λ on the nearer
  ball: an obstacle, v* = 0.47 λ); both warned.
- Quiet pairs 5–10 % off: r48_Linear3_hzfe_slab_on_15 x1 −6.4 %, x2 +6.2 % (2× grid −3.0 / +4.0 %,
  ê ≥ 0.96 |err|), r48_Pendulum_hzfe_func_seam_14 x2 +6.6 % (truth rechecked 0.0734 ± 0.0018:
  +2.9 %; within sampling).
- Odd exits (``probes/``): a Box across the pendulum's seam is not wrapped (a Ball is), silently;
  ``certify(progress=False)`` draws the auto proposal's progress bar (both fixed on main since: a
  Box with finite sides on a periodic axis wraps, and the proposal's solve takes ``progress``); a Box one cell thick with its
  faces on grid lines holds one node line (0.6000000000000001 > 0.6) and, on the embedded grid,
  none: no error estimate (warned; ``error_estimate`` raises). A slab thinner than a cell with no
  node: a clear ValueError.

Generator (``gen``, seed 48): PointMass, Pendulum, LinearSystem 2-D / 3-D (identity-like B, or
one control on one axis), a user ``ControlAffineSystem`` ("River", as round 47); λ log-uniform
in [0.05, 3]; R diagonal log-uniform [0.1, 3]; q = c0 + a quadratic about a goal; terminal cost a
Quadratic about the goal; T uniform [0.5, 4]. Grids as a user picks them: 61–121 per axis in
2-D, 25–37 in 3-D. All costs but the steep exit slope are scaled by one factor s, calibrated by
a few coarse solves so that v at the middle state is target_frac λ, log-uniform in [0.15, 0.8]
(cheap) or [1.5, 6] (expensive), half each.

Truth: ``gridlbc.certify(problem, policy, X, 2000, dt, seed=48, richardson=True)`` with the
policy of a solve on a grid 2× finer per axis (1.5× in 3-D above 3·10⁵ fine nodes) at half the
default step; dt = T/160 with a horizon, 0.005 (max_time 300) without. A function-mask exit is
certified on its twin region (the same set as a Ball, whose boundary crossings the Brownian
bridge catches; the lambda alone draws the "not a gridlbc.regions shape" distrust). Trusted: ESS
≥ 100, k̂ ≤ 0.7, no CertificateWarning naming the state about heavy tails, unexited weight, the
extrapolation, the effective sample size or an unvisited feature. Pairs more than 10 % off:
``solve(problem, tol=0.05, states=[x], max_seconds=120)`` as well (in ``--run``).

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round48.py --list | --run [NAMES] | --table \\
        | --diagnose [NAMES] | --extra NAME TAG x0,x1[,x2] ... | --before
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

import gridlbc
from gridlbc import Problem, Quadratic
from gridlbc.regions import Ball, Box

sys.path.insert(0, str(Path(__file__).resolve().parent))
from strangers_round47 import (
    certify_kw,
    distrusted,
    fine_scale,
    loguni,
    make_grid,
    make_system,
)

OUT = Path(__file__).parent / "strangers_round48_results"  # gitignored
SEED = 48
PI = math.pi
KINDS = [
    # (system, ending, exit kind, exit-cost kind); ("twin", k): draw k without its horizon
    ("PointMass", "hzfe", "ball", "const"),
    ("Linear2", "hzfe", "slab_on", "linear"),
    ("Pendulum", "hzfe", "seam", "quad"),
    ("River2", "hzfe", "union", "steep"),
    ("PointMass", "hzfe", "func", "quad"),
    ("Linear3", "hzfe", "ball", "linear"),
    ("Linear2", "hzfe", "edge", "const"),
    ("River2", "hzfe", "slab_mid", "quad"),
    ("Pendulum", "hzfe", "ball", "steep"),
    ("Linear2", "hzfe", "func", "linear"),
    ("PointMass", "hzfe", "edge", "linear"),
    ("River3", "hzfe", "ball", "quad"),
    ("Linear2", "hzfe", "union", "const"),
    ("PointMass", "hzfe", "slab_mid", "steep"),
    ("Pendulum", "hzfe", "func_seam", "const"),
    ("Linear3", "hzfe", "slab_on", "const"),
    ("twin", 0),
    ("twin", 3),
    ("twin", 2),
    ("twin", 9),
]


# ================= a user's own system ===========================================================


# ================= costs =========================================================================
def wrap(d):
    return (d + PI) % (2 * PI) - PI


class StateCost:
    """q(x) = s (c0 + Σ W_i (x − c)_i²), wrap-aware on the periodic axes."""

    def __init__(self, q, per, s):
        self.q, self.per, self.s = q, tuple(per), s

    def __call__(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        d = x - np.asarray(self.q["c"])
        for i in self.per:
            d[:, i] = wrap(d[:, i])
        return self.s * (self.q["c0"] + d**2 @ np.asarray(self.q["W"]))


class ExitCost:
    """g_E(x) = s (c0 + a (x_k − x0)^p) for "linear" (p = 1) and "quad" (p = 2); "steep":
    slope (x_k − x0), unscaled (slope = m λ / h_k: m λ per cell along the exit's boundary)."""

    def __init__(self, e, s, per=()):
        self.e, self.s, self.per = e, s, tuple(per)

    def __call__(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        e = self.e
        d = x[:, e["axis"]] - e["x0"]
        if e["axis"] in self.per:
            d = wrap(d)
        if e["kind"] == "steep":
            return e["slope"] * d
        if e["kind"] == "linear":
            return self.s * (e["c0"] + e["a"] * d)
        return self.s * (e["c0"] + e["a"] * d**2)


# ================= exit sets =====================================================================
def ball_mask(b, X, per=()):
    d = np.atleast_2d(np.asarray(X, float)) - np.asarray(b["c"])
    for i in per:
        d[:, i] = wrap(d[:, i])
    return np.sum((d / np.asarray(b["r"])) ** 2, axis=1) <= 1.0


def in_region(ex, X, per=()):
    """The exit set's mask, computed here independently of gridlbc (states, near-state checks)."""
    X = np.atleast_2d(np.asarray(X, float))
    k = ex["kind"]
    if k in ("ball", "func", "seam", "func_seam"):
        return ball_mask(ex, X, per)
    if k == "union":
        return ball_mask(ex["parts"][0], X, per) | ball_mask(ex["parts"][1], X, per)
    lo, hi = np.asarray(ex["lo"], float), np.asarray(ex["hi"], float)
    return np.all((lo <= X) & (hi >= X), axis=1)


def user_lambda(ex):
    """The exit a user writes as a plain function of the states (N, d) → mask (N,)."""
    c, r = ex["c"], ex["r"]
    if ex["kind"] == "func_seam":  # the angle wrapped by hand
        return lambda x: (
            (((x[:, 0] - c[0] + np.pi) % (2 * np.pi) - np.pi) / r[0]) ** 2
            + ((x[:, 1] - c[1]) / r[1]) ** 2
            <= 1.0
        )
    return lambda x: ((x[:, 0] - c[0]) / r[0]) ** 2 + ((x[:, 1] - c[1]) / r[1]) ** 2 <= 1.0


def region(ex, twin=False):
    """The exit set as given to Problem; ``twin``: a function mask's Ball twin (certificates)."""
    k = ex["kind"]
    if k in ("func", "func_seam") and not twin:
        return user_lambda(ex)
    if k in ("ball", "seam", "func", "func_seam"):
        return Ball(ex["c"], ex["r"])
    if k == "union":
        a, b = ex["parts"]
        return Ball(a["c"], a["r"]) | Ball(b["c"], b["r"])
    return Box(ex["lo"], ex["hi"])


# ================= the draw ======================================================================
def system_draw(rng, kind):
    if kind == "PointMass":
        m = loguni(rng, 0.3, 3.0)
        return dict(mass=m), [[-3.0, 3.0], [-4.0, 4.0]], [], 1
    if kind == "Pendulum":
        par = dict(
            mass=loguni(rng, 0.3, 2.0),
            length=loguni(rng, 0.5, 1.5),
            gravity=float(rng.choice([9.81, 3.71, 1.62])),
            damping=float(rng.choice([0.0, loguni(rng, 0.05, 0.5)])),
        )
        return par, [[-PI, PI], [-8.0, 8.0]], [0], 1
    if kind in ("Linear2", "Linear3"):
        d = 3 if kind == "Linear3" else 2
        A = rng.normal(0.0, 0.5, size=(d, d))
        A -= 0.3 * np.eye(d)  # mostly stable, as a user's model would be
        if rng.random() < 0.6:
            B = np.diag([rng.uniform(0.6, 1.5) for _ in range(d)])
        else:
            B = np.zeros((d, 1))
            B[int(rng.integers(d)), 0] = rng.choice([-1.0, 1.0]) * rng.uniform(0.7, 1.5)
        L = float(rng.uniform(2.0, 3.5))
        return dict(A=A.tolist(), B=B.tolist()), [[-L, L]] * d, [], B.shape[1]
    d = 3 if kind == "River3" else 2
    par = dict(
        d=d,
        flow=float(rng.uniform(0.3, 1.2)),
        L=float(rng.uniform(1.5, 2.5)),
        gamma=float(rng.uniform(0.1, 0.6)),
        kappa=float(rng.uniform(0.2, 0.8)),
        eps=float(rng.uniform(0.0, 0.4)),
        b=[float(rng.uniform(0.5, 1.5)) for _ in range(d)],
    )
    return par, [[-3.0, 3.0]] * d, [], d


def draw_exit(rng, kind, box, per, h, ns):
    d = len(box)
    L = [b[1] for b in box]
    c = [
        float(rng.uniform(-PI, PI)) if i in per else float(rng.uniform(-0.4, 0.4) * L[i])
        for i in range(d)
    ]
    if kind in ("ball", "func"):
        return dict(kind=kind, c=c, r=[float(rng.uniform(1.0, 2.0)) * hh for hh in h])
    if kind in ("seam", "func_seam"):  # across θ = ±π
        c[0] = PI - float(rng.uniform(0.0, 1.0)) * h[0]
        return dict(kind=kind, c=c, r=[float(rng.uniform(1.2, 2.0)) * hh for hh in h])
    if kind == "union":
        r1 = [float(rng.uniform(1.0, 2.5)) * hh for hh in h]
        r2 = [float(rng.uniform(1.0, 2.5)) * hh for hh in h]
        u = rng.normal(size=d)
        u /= np.linalg.norm(u)
        c2 = [ci + float(rng.uniform(6.0, 15.0)) * ui * hh for ci, ui, hh in zip(c, u, h)]
        c2 = [float(np.clip(v, -0.7 * Li, 0.7 * Li)) for v, Li in zip(c2, L)]
        return dict(kind="union", parts=[dict(c=c, r=r1), dict(c=c2, r=r2)])
    a = int(rng.integers(d))  # the thin axis / the axis whose edge is touched
    lo = [ci - float(rng.uniform(4.0, 12.0)) * hh for ci, hh in zip(c, h)]
    hi = [ci + float(rng.uniform(4.0, 12.0)) * hh for ci, hh in zip(c, h)]
    if kind == "slab_on":  # faces on grid lines, 2 or 3 cells thick
        lines = np.linspace(box[a][0], box[a][1], ns[a])  # the grid lines, as a user finds them
        j = int(np.floor((c[a] - box[a][0]) / h[a]))
        m = int(rng.integers(2, 4))
        lo[a], hi[a] = float(lines[j]), float(lines[j + m])
        if rng.random() < 0.5:  # along the whole other axes
            for i in range(d):
                if i != a:
                    lo[i], hi[i] = -math.inf, math.inf
    elif kind == "slab_mid":  # faces between grid lines, 2.2–2.9 cells thick
        t = float(rng.uniform(2.2, 2.9)) * h[a]
        off = float(rng.uniform(0.15, 0.85)) * h[a]
        lo_a = box[a][0] + math.floor((c[a] - box[a][0]) / h[a]) * h[a] + off
        lo[a], hi[a] = lo_a, lo_a + t
    else:  # "edge": reaching the box's upper or lower edge along axis a
        w = float(rng.uniform(3.0, 8.0)) * h[a]
        beyond = float(rng.choice([0.0, 0.5]))
        if rng.random() < 0.5:
            lo[a], hi[a] = L[a] - w, L[a] + beyond
        else:
            lo[a], hi[a] = -L[a] - beyond, -L[a] + w
        c[a] = 0.5 * (max(lo[a], -L[a]) + min(hi[a], L[a]))
    return dict(kind="box", sub=kind, lo=lo, hi=hi, axis=a, c=c)


def exit_extent(ex, k):
    """The exit set's lowest and highest coordinate k (finite parts)."""
    if ex["kind"] == "union":
        parts = ex["parts"]
        return (
            min(p["c"][k] - p["r"][k] for p in parts),
            max(p["c"][k] + p["r"][k] for p in parts),
        )
    if ex["kind"] == "box":
        return ex["lo"][k], ex["hi"][k]
    return ex["c"][k] - ex["r"][k], ex["c"][k] + ex["r"][k]


def near_state(rng, ex, box, per, h, steps=4000):
    """A state k ∈ [2, 4] cells off the exit set along one axis, ≥ 2 cells from it along all."""
    d = len(box)
    for attempt in range(40):
        if ex["kind"] == "box":
            a = ex["axis"] if ex["sub"] != "edge" or rng.random() < 0.7 else int(rng.integers(d))
            anchor = list(ex["c"])
        elif ex["kind"] == "union":
            a = int(rng.integers(d))
            anchor = list(ex["parts"][0]["c"])
        else:
            a = 0 if ex["kind"] in ("seam", "func_seam") and attempt < 10 else int(rng.integers(d))
            anchor = list(ex["c"])
        sign = float(rng.choice([-1.0, 1.0]))
        if ex["kind"] in ("seam", "func_seam") and a == 0 and attempt < 10:
            sign = 1.0  # across the seam
        if ex["kind"] == "union":
            off = ex["parts"][1]["c"][a] - anchor[a]
            if off != 0:
                sign = -math.copysign(1.0, off)
        e = np.zeros(d)
        e[a] = sign
        p = np.asarray(anchor, float)
        t = 0.0
        for _ in range(steps):
            if not in_region(ex, [p + t * e], per)[0]:
                break
            t += 0.02 * h[a]
        cells = float(rng.uniform(2.0, 4.0))
        x = p + (t + cells * h[a]) * e
        for i in per:
            x[i] = wrap(x[i])
        ok = all(i in per or box[i][0] + 2 * h[i] <= x[i] <= box[i][1] - 2 * h[i] for i in range(d))
        for j in range(d):
            for s_ in (-2.0, 2.0):
                y = x.copy()
                y[j] += s_ * h[j]
                ok &= not in_region(ex, [y], per)[0]
        ok &= not in_region(ex, [x], per)[0]
        if ok:
            return x.tolist(), cells, a
    raise RuntimeError("no near state")


def gen(rng, k, specs):
    entry = KINDS[k]
    if entry[0] == "twin":  # the same draw without the horizon
        base = specs[int(entry[1])]
        spec = json.loads(json.dumps(base))
        spec.update(
            name=base["name"].replace("_hzfe_", "_fe_").rsplit("_", 1)[0] + f"_{k:02d}",
            ending="fe",
            T=None,
            twin_of=base["name"],
        )
        spec.pop("g", None)
        return spec
    kind, ending, exk, cost = entry
    par, box, per, m = system_draw(rng, kind)
    d = len(box)
    lo_n, hi_n = {2: (61, 121), 3: (25, 37)}[d]
    ns = [int(rng.integers(lo_n, hi_n + 1)) for _ in range(d)]
    ns = [n + n % 2 if i in per else n for i, n in enumerate(ns)]
    h = [(hi - lo) / (n - (0 if i in per else 1)) for i, ((lo, hi), n) in enumerate(zip(box, ns))]
    lam = loguni(rng, 0.05, 3.0)
    R = [loguni(rng, 0.1, 3.0) for _ in range(m)]
    goal = [0.0 if i in per else float(rng.uniform(-0.35, 0.35) * box[i][1]) for i in range(d)]
    if kind == "Pendulum":
        goal[1] = 0.0
    q = dict(
        c0=float(rng.uniform(0.2, 1.0)),
        c=goal,
        W=[float(loguni(rng, 0.02, 0.5) if rng.random() < 0.7 else 0.0) for _ in range(d)],
    )
    T = float(rng.uniform(0.5, 4.0))
    ex = draw_exit(rng, exk, box, per, h, ns)
    # the exit cost
    ax = int(rng.integers(d))
    if exk in ("slab_on", "slab_mid", "edge") and d > 1:  # along the boundary: not the thin axis
        ax = int(rng.choice([i for i in range(d) if i != ex["axis"]]))
    lo_e, hi_e = exit_extent(ex, ax)
    if cost == "const":
        ec = dict(kind="const", c0=float(rng.uniform(0.0, 0.5)))
    elif cost == "linear":
        a = float(rng.uniform(0.2, 1.0))
        ref = lo_e if math.isfinite(lo_e) else exit_extent(ex, ax)[0]
        ec = dict(kind="linear", c0=float(rng.uniform(0.0, 0.3)), a=a, axis=ax, x0=ref)
    elif cost == "quad":
        ec = dict(
            kind="quad",
            c0=float(rng.uniform(0.0, 0.3)),
            a=float(rng.uniform(0.3, 2.0)),
            axis=ax,
            x0=float(rng.uniform(lo_e, hi_e)) if math.isfinite(hi_e - lo_e) else 0.0,
        )
    else:  # steep: m λ per cell along axis ax, zero at one end of the exit set
        mm = float(rng.uniform(2.0, 5.0))
        sgn = float(rng.choice([-1.0, 1.0]))
        ec = dict(
            kind="steep",
            slope=sgn * mm * lam / h[ax],
            per_cell=mm,
            axis=ax,
            x0=lo_e if sgn > 0 else hi_e,
        )
    ex["cost"] = ec
    spec = dict(
        name=f"r48_{kind}_{ending}_{exk}_{k:02d}",
        kind=kind,
        ending=ending,
        exit_kind=exk,
        cost_kind=cost,
        params=par,
        d=d,
        box=[[lo, hi, n] for (lo, hi), n in zip(box, ns)],
        h=h,
        periodic=per,
        lam=lam,
        R=R,
        T=T,
        q=q,
        goal=goal,
        g=dict(c=goal, W=[float(loguni(rng, 0.1, 2.0)) for _ in range(d)]),
        exit=ex,
    )
    # states: far (0.75 of the box), middle (halfway from the exit), near (2–4 cells off E)
    anchor = ex["parts"][0]["c"] if ex["kind"] == "union" else ex["c"]
    sign = [float(rng.choice([-1, 1])) for _ in range(d)]
    far = [0.9 * PI * sign[i] if i in per else 0.75 * box[i][1] * sign[i] for i in range(d)]
    if in_region(ex, [far], per)[0]:
        far = [-f for f in far]
    mid = [
        (0.5 * (a_ + f) if i not in per else wrap(a_ + 0.5 * wrap(f - a_)))
        + float(rng.uniform(-0.1, 0.1)) * box[i][1]
        for i, (a_, f) in enumerate(zip(anchor, far))
    ]
    if in_region(ex, [mid], per)[0]:
        mid = [0.5 * (a_ + f) for a_, f in zip(mid, far)]
    near, cells, nax = near_state(rng, ex, box, per, h)
    spec["X"] = [far, mid, near]
    spec["near"] = dict(cells=cells, axis=nax)
    u = rng.random()
    spec["target_frac"] = loguni(rng, 0.15, 0.8) if u < 0.5 else loguni(rng, 1.5, 6.0)
    return spec


def draw():
    rng = np.random.default_rng(SEED)
    specs = []
    for k in range(len(KINDS)):
        specs.append(gen(rng, k, specs))
    return {s["name"]: s for s in specs}


# ================= building ======================================================================


def build(sp, s=None, scale=1.0, twin=False):
    """The problem as a user writes it; ``twin``: a function-mask exit as its Ball (certify)."""
    s = sp.get("scale", 1.0) if s is None else s
    per = tuple(sp["periodic"])
    ex = sp["exit"]
    c = ex["cost"]
    T = sp["T"]
    return Problem(
        make_system(sp),
        make_grid(sp["box"], per, scale),
        T,
        terminal_cost=None if T is None else Quadratic(sp["g"]["c"], s * np.asarray(sp["g"]["W"])),
        state_cost=StateCost(sp["q"], per, s),
        control_cost=np.diag(sp["R"]),
        temperature=sp["lam"],
        exit=region(ex, twin=twin),
        exit_cost=s * c["c0"] if c["kind"] == "const" else ExitCost(c, s, per),
    )


def calibrate(sp):
    """The cost factor s with v(middle) ≈ target_frac λ, by at most three solves on a grid 0.6×
    as fine (error estimate off); secant on log s, v ≈ c s^p. A twin keeps its draw's s."""
    twin = sp.get("twin_of")
    if twin and (OUT / f"{twin}.json").exists():
        s = json.loads((OUT / f"{twin}.json").read_text())["spec"]["scale"]
        return s, [("twin", s)]
    target = sp["target_frac"] * sp["lam"]
    xm = np.asarray([sp["X"][1]], float)
    hist = []
    s = 1.0
    for _ in range(3):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sol = gridlbc.solve(build(sp, s=s, scale=0.6), error_estimate=False, progress=False)
            v = float(np.asarray(sol.value(xm))[0])
        hist.append((s, v))
        if not (v > 0 and math.isfinite(v)) or abs(math.log(v / target)) < math.log(1.25):
            break
        if len(hist) == 1:
            p = 1.0
        else:
            (s1, v1), (s2, v2) = hist[-2], hist[-1]
            p = math.log(v2 / v1) / math.log(s2 / s1) if s1 != s2 and v1 > 0 else 1.0
            p = min(max(p, 0.3), 1.5)
        s = s * (target / v) ** (1.0 / p)
        s = min(max(s, 1e-3), 1e3)
    # the last s tried if it hit, else the best of those tried
    best = min(hist, key=lambda t: abs(math.log(max(t[1], 1e-300) / target)))
    return best[0], hist


# ================= run ===========================================================================
def gw(w):
    return [
        dict(category=x.category.__name__, message=str(x.message)[:600])
        for x in w
        if issubclass(x.category, gridlbc.GridlbcWarning)
    ]


def stray(w):
    """Warnings that are not gridlbc's (numpy RuntimeWarnings and the like): bugs to report."""
    return [
        f"{x.category.__name__}: {str(x.message)[:200]} ({Path(x.filename).name}:{x.lineno})"
        for x in w
        if not issubclass(x.category, gridlbc.GridlbcWarning)
    ]


def tol_check(sp, x):
    """``solve(problem, tol=0.05, states=[x], max_seconds=120)`` at one state."""
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            st = gridlbc.solve(build(sp), tol=0.05, states=[x], max_seconds=120, progress=False)
            xx = np.asarray([x], float)
            v = float(np.asarray(st.value(xx))[0])
            e = float(np.asarray(st.error_estimate(xx))[0])
            ref = list(getattr(st, "refinement", ()) or ())
            rounds = [(list(r.shape), float(r.dt), float(r.error)) for r in ref]
            met = bool(ref[-1].met(0.05)) if ref else None
            shape, fail = list(st.grid.shape), None
        except Exception as ex:
            v = e = float("nan")
            rounds, met, shape = [], None, None
            fail = f"{type(ex).__name__}: {ex}"[:400]
    return dict(
        v=v,
        est=e,
        met=met,
        shape=shape,
        rounds=rounds,
        fail=fail,
        warnings=gw(w),
        stray=stray(w),
        seconds=time.perf_counter() - t0,
    )


def run(name, sp):
    OUT.mkdir(parents=True, exist_ok=True)
    X = np.asarray(sp["X"], float)
    lam = sp["lam"]
    rec = dict(name=name)
    try:
        t0 = time.perf_counter()
        s, hist = calibrate(sp)
        sp = dict(sp, scale=s, calibration=hist)
        rec["spec"] = sp
        t_cal = time.perf_counter() - t0
        p = build(sp)
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            sol = gridlbc.solve(p, progress=False)
            secs = time.perf_counter() - t0
            v = np.asarray(sol.value(X), float)
            try:
                e = np.asarray(sol.error_estimate(X), float)
                e_fail = None
            except Exception as ex:  # no estimate (an exit set the embedded grid misses)
                e = np.full(len(X), np.nan)
                e_fail = f"{type(ex).__name__}: {ex}"[:400]
        wl, st0 = gw(w), stray(w)
        dt0 = float(sol.diagnostics.dt)
        t1 = time.perf_counter()
        sc = fine_scale(sp)
        with warnings.catch_warnings(record=True) as wf:
            warnings.simplefilter("always")
            kw = {} if sp["T"] is None else dict(dt=dt0 / 2)
            fine = gridlbc.solve(build(sp, scale=sc), error_estimate=False, progress=False, **kw)
            v_fine = np.asarray(fine.value(X), float)
        t_fine = time.perf_counter() - t1
        twin = sp["exit"]["kind"] in ("func", "func_seam")
        pc = build(sp, twin=True) if twin else p
        t1 = time.perf_counter()
        with warnings.catch_warnings(record=True) as w2:
            warnings.simplefilter("always")
            c = gridlbc.certify(
                pc,
                fine.policy,
                X,
                2000,
                seed=SEED,
                richardson=True,
                progress=False,
                **certify_kw(sp),
            )
        t_cert = time.perf_counter() - t1
        cw = gw(w2)
        vt = np.asarray(c.extrapolated_value, float)
        se = np.asarray(c.extrapolated_value_se, float)
        ess = np.asarray(c.effective_sample_size, float)
        kh = np.asarray(c.pareto_k, float)
        bad = distrusted(cw, X)
        trusted = (ess >= 100) & (kh <= 0.7) & ~bad & np.isfinite(vt)
        rec.update(
            shape=list(p.grid.shape),
            exit_nodes=int(p.exit_mask().sum()),
            dt=dt0,
            method=str(sol.diagnostics.method),
            fine_scale=sc,
            seconds=dict(calibrate=t_cal, solve=secs, fine=t_fine, certify=t_cert),
            warnings=wl,
            warned=bool(wl),
            est_fail=e_fail,
            stray=st0 + stray(wf) + stray(w2),
            v=v.tolist(),
            est=e.tolist(),
            v_fine=v_fine.tolist(),
            certified_on_twin=twin,
            truth=vt.tolist(),
            se=se.tolist(),
            v_dt=np.asarray(c.optimal_value).tolist(),
            ess=ess.tolist(),
            khat=kh.tolist(),
            unexited=np.atleast_1d(np.asarray(c.unexited_fraction, float)).tolist(),
            cert_warnings=cw,
            trusted=trusted.tolist(),
        )
        # the pairs more than 10 % off: does tol=0.05 at the state bring them within 5 %?
        rec["tol"] = {}
        for i in range(len(X)):
            if trusted[i] and abs(v[i] - vt[i]) > 0.10 * abs(vt[i]):
                r = tol_check(sp, X[i])
                r["err"] = (r["v"] - vt[i]) / abs(vt[i])
                rec["tol"][str(i)] = r
        rec["seconds"]["tol"] = sum(r["seconds"] for r in rec["tol"].values())
    except Exception as ex:
        rec["crash"] = f"{type(ex).__name__}: {ex}\n{traceback.format_exc()}"[-3000:]
        rec.setdefault("spec", sp)
        (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
        print(f"{name}: CRASH {type(ex).__name__}: {ex}")
        return rec
    (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
    sec = rec["seconds"]
    print(
        f"{name:34s} {tuple(p.grid.shape)!s:14s} λ={lam:.3g} T={sp['T']} s={s:.3g} E nodes "
        f"{rec['exit_nodes']} solve {secs:.1f}s fine {t_fine:.0f}s cert {t_cert:.0f}s "
        f"tol {sec['tol']:.0f}s warned={bool(wl)}"
    )
    for i in range(len(X)):
        ev = (v[i] - vt[i]) / abs(vt[i])
        print(
            f"    x{i} v={v[i]:.4g} v*={vt[i]:.4g}±{se[i]:.2g} ess={ess[i]:.0f} k={kh[i]:.2f} "
            f"err={ev:+.1%} ê={e[i]:.3g} fine={v_fine[i]:.4g} trusted={trusted[i]}"
        )
    for k_, r in rec["tol"].items():
        print(
            f"    tol x{k_}: v={r['v']:.4g} err={r['err']:+.1%} met={r['met']} {r['seconds']:.0f}s "
            f"fail={r['fail']}"
        )
    for x in wl:
        print("    warn:", x["category"], x["message"][:200])
    for x in cw:
        print("    cert:", x["category"], x["message"][:200])
    for x in rec["stray"]:
        print("    STRAY:", x)
    return rec


# ================= classification, diagnosis, table ==============================================
def pairs(rec):
    """Per state: the numbers and the flags OFF (> 10 % of |v*|), SILENT (OFF, no warning),
    COVER (ê ≥ ½ |v − v*|: at least the error or within 2×), UNDER (ê < ½ |v − v*| beyond 2 SE)."""
    lam = rec["spec"]["lam"]
    out = []
    for i in range(len(rec["v"])):
        v, vt, se, e = rec["v"][i], rec["truth"][i], rec["se"][i], rec["est"][i]
        ev = (v - vt) / abs(vt)
        el = (v - vt) / max(abs(vt), lam)
        tr = rec["trusted"][i]
        off = tr and abs(ev) > 0.10
        dev = max(abs(v - vt) - 2 * se, 0.0)  # beyond 2 SE
        out.append(
            dict(
                i=i,
                v=v,
                vt=vt,
                se=se,
                e=e,
                ev=ev,
                el=el,
                e_rel=e / abs(vt),
                trusted=tr,
                small=abs(vt) < lam,
                OFF=bool(off),
                SILENT=bool(off and not rec["warned"]),
                COVER=bool(e >= 0.5 * abs(v - vt)),
                COVER_SE=bool(e >= 0.5 * dev),
                UNDER=bool(tr and dev > 0 and not e >= 0.5 * abs(v - vt)),
            )
        )
    return out


def variant(sp, scale=1.0, dt=None, est=True):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        kw = {} if dt is None else dict(dt=dt)
        s = gridlbc.solve(build(sp, scale=scale), error_estimate=est, progress=False, **kw)
        X = np.asarray(sp["X"], float)
        v = np.asarray(s.value(X), float).tolist()
        try:
            e = np.asarray(s.error_estimate(X), float).tolist() if est else None
        except ValueError:
            e = None
    return dict(
        scale=scale,
        dt=float(s.diagnostics.dt),
        shape=list(s.grid.shape),
        v=v,
        est=e,
        warned=bool(gw(w)),
        warnings=gw(w),
        stray=stray(w),
        seconds=time.perf_counter() - t0,
    )


def diagnose(name):
    """For OFF pairs (and quiet pairs 5–10 % off): the default solve on a 2× grid (its own
    step), and at dt/2 on the same grid."""
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    if "crash" in rec:
        return
    todo = [
        p["i"]
        for p in pairs(rec)
        if p["OFF"] or p["UNDER"] or (p["trusted"] and abs(p["ev"]) > 0.05 and not rec["warned"])
    ]
    if not todo:
        print(name, "nothing to diagnose")
        return
    sp = rec["spec"]
    dg = dict(states=todo)
    dg["grid2"] = variant(sp, scale=2.0)
    if sp["T"] is not None:
        dg["dt_half"] = variant(sp, dt=rec["dt"] / 2)
    rec["diagnosis"] = dg
    f.write_text(json.dumps(rec, indent=1, default=float))
    print_diag(rec)


def print_diag(rec):
    dg = rec.get("diagnosis")
    if not dg:
        return
    vt = rec["truth"]
    for key in ("grid2", "dt_half"):
        r = dg.get(key)
        if not r:
            continue
        for i in dg["states"]:
            e = r["est"][i] if r["est"] else float("nan")
            print(
                f"     DIAG {key} {r['shape']} dt={r['dt']:.3g} ({r['seconds']:.0f}s, warned="
                f"{r['warned']}) x{i}: v={r['v'][i]:.4g} ({(r['v'][i] - vt[i]) / abs(vt[i]):+.1%}) "
                f"ê={e:.3g}"
            )


def extra(name, states, tag):
    """v, ê and a certified v* at further states of a drawn problem (the seam check: the near
    state's mirror image on the near side of θ = ±π)."""
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    sp = rec["spec"]
    X = np.atleast_2d(np.asarray(states, float))
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        sol = gridlbc.solve(build(sp), progress=False)
        v, e = np.asarray(sol.value(X), float), np.asarray(sol.error_estimate(X), float)
        kw = {} if sp["T"] is None else dict(dt=rec["dt"] / 2)
        fine = gridlbc.solve(
            build(sp, scale=rec["fine_scale"]), error_estimate=False, progress=False, **kw
        )
        twin = sp["exit"]["kind"] in ("func", "func_seam")
        c = gridlbc.certify(
            build(sp, twin=twin),
            fine.policy,
            X,
            2000,
            seed=SEED,
            richardson=True,
            progress=False,
            **certify_kw(sp),
        )
    vt = np.asarray(c.extrapolated_value, float)
    out = dict(
        X=X.tolist(),
        v=v.tolist(),
        est=e.tolist(),
        truth=vt.tolist(),
        se=np.asarray(c.extrapolated_value_se).tolist(),
        ess=np.asarray(c.effective_sample_size).tolist(),
        khat=np.asarray(c.pareto_k).tolist(),
        warnings=gw(w),
        stray=stray(w),
    )
    rec.setdefault("extra", {})[tag] = out
    f.write_text(json.dumps(rec, indent=1, default=float))
    for i in range(len(X)):
        print(
            f"{name} {tag} x={X[i].round(4).tolist()} v={v[i]:.4g} v*={vt[i]:.4g}±"
            f"{out['se'][i]:.2g} err={(v[i] - vt[i]) / abs(vt[i]):+.1%} ê={e[i]:.3g} "
            f"ess={out['ess'][i]:.0f} k={out['khat'][i]:.2f}"
        )


def before():
    """The default solves again with whichever gridlbc is on the path (run with PYTHONPATH at a
    checkout of db3ff19's parent to see the near-exit states before the fitted boundary)."""
    outdir = OUT / "before"
    outdir.mkdir(exist_ok=True)
    for f in sorted(OUT.glob("r48_*.json")):
        rec = json.loads(f.read_text())
        if "crash" in rec:
            continue
        sp = rec["spec"]
        X = np.asarray(sp["X"], float)
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            sol = gridlbc.solve(build(sp), progress=False)
            v = np.asarray(sol.value(X), float)
            try:
                e = np.asarray(sol.error_estimate(X), float)
            except ValueError:
                e = np.full(len(X), np.nan)
        out = dict(
            name=rec["name"],
            library=str(Path(gridlbc.__file__).parent),
            v=v.tolist(),
            est=e.tolist(),
            warned=bool(gw(w)),
            warnings=gw(w),
            seconds=time.perf_counter() - t0,
        )
        (outdir / f.name).write_text(json.dumps(out, indent=1, default=float))
        vt = rec["truth"]
        print(
            f"{rec['name']:34s} "
            + "  ".join(
                f"x{i} {v[i]:.4g} ({(v[i] - vt[i]) / abs(vt[i]):+.1%}, now "
                f"{(rec['v'][i] - vt[i]) / abs(vt[i]):+.1%})"
                for i in range(len(X))
            )
            + f" warned={out['warned']}"
        )


def table():
    recs = [json.loads(f.read_text()) for f in sorted(OUT.glob("r48_*.json"))]
    allp, flagged, crashes, strays = [], [], [], []
    times = []
    print(
        f"{'pair':38s} {'v':>9s} {'v*±SE':>18s} {'err':>7s} {'ê':>9s} {'ê/|v*|':>7s} "
        f"{'v*/λ':>6s} warned tags"
    )
    for r in recs:
        sp = r["spec"]
        if "crash" in r:
            crashes.append(r)
            print(f"{r['name']}: CRASH {r['crash'].splitlines()[0]}")
            continue
        sec = r["seconds"]
        times.append((r["name"], sec))
        if r["stray"]:
            strays.append((r["name"], r["stray"]))
        print(
            f"{r['name']} {r['shape']} λ={sp['lam']:.3g} T={sp['T']} exit={sp['exit_kind']}"
            f"/{sp['cost_kind']} E-nodes={r['exit_nodes']} s={sp['scale']:.3g} "
            f"solve {sec['solve']:.1f}s fine {sec['fine']:.0f}s cert {sec['certify']:.0f}s "
            f"tol {sec.get('tol', 0):.0f}s cal {sec['calibrate']:.0f}s"
        )
        for x in r["warnings"]:
            print(f"   warn: {x['category']}: {x['message'][:160]}")
        if r.get("est_fail"):
            print(f"   NO ESTIMATE: {r['est_fail'][:160]}")
        for x in r["cert_warnings"]:
            print(f"   cert: {x['message'][:140]}")
        for p in pairs(r):
            i = p["i"]
            tags = [k for k in ("OFF", "SILENT", "UNDER") if p[k]]
            if not p["trusted"]:
                tags.append("untrusted")
            where = ["far", "mid", f"near({sp['near']['cells']:.1f} cells)"][i]
            print(
                f"   x{i} {where:17s} {p['v']:9.4g} {p['vt']:9.4g}±{p['se']:<8.2g} "
                f"{p['ev']:+7.1%} {p['e']:9.3g} {p['e_rel']:7.1%} {p['vt'] / sp['lam']:6.2f} "
                f"{'yes' if r['warned'] else 'no':3s} {' '.join(tags)}"
            )
            t = r.get("tol", {}).get(str(i))
            if t:
                print(
                    f"       tol=0.05 at x{i}: v={t['v']:.4g} err={t['err']:+.1%} met={t['met']} "
                    f"shape={t['shape']} {t['seconds']:.0f}s fail={t['fail']} "
                    f"warned={bool(t['warnings'])}"
                )
            allp.append((r, p))
            if tags and tags != ["untrusted"]:
                flagged.append((r, p, tags))
        print_diag(r)
    tr = [p for _, p in allp if p["trusted"]]
    n = len(allp)
    print(
        f"\nproblems {len(recs)} (crashed {len(crashes)}), pairs {n}, trusted {len(tr)} "
        f"(v* < λ: {sum(p['small'] for p in tr)}, v* ≥ 2λ: "
        f"{sum(abs(p['vt']) >= 2 * r['spec']['lam'] for r, p in allp if p['trusted'])})"
    )
    off = [(r, p) for r, p in allp if p["OFF"]]
    print(
        f"OFF (> 10 %): {len(off)}; warned {sum(r['warned'] for r, _ in off)}, "
        f"silent {sum(p['SILENT'] for _, p in off)}"
    )
    print(f"5–10 % off: {sum(p['trusted'] and 0.05 < abs(p['ev']) <= 0.10 for _, p in allp)}")
    cov = [p for p in tr if np.isfinite(p["e"])]
    print(
        f"ê ≥ |err| or within 2×: {sum(p['COVER'] for p in cov)} / {len(cov)} "
        f"({sum(p['COVER'] for p in cov) / max(len(cov), 1):.0%}); allowing 2 SE: "
        f"{sum(p['COVER_SE'] for p in cov)} / {len(cov)}"
    )
    print(f"UNDER (ê < ½|v − v*| beyond 2 SE): {sum(p['UNDER'] for p in tr)}")
    hz = [p for r, p in allp if p["trusted"] and r["spec"]["T"] is not None]
    nr = [p for r, p in allp if p["trusted"] and r["spec"]["T"] is not None and p["i"] == 2]
    print(
        f"hzfe: {len(hz)} trusted pairs, near-exit {len(nr)}: errors "
        + ", ".join(f"{p['ev']:+.1%}" for p in nr)
    )
    print(f"warned problems {sum(r['warned'] for r in recs if 'crash' not in r)} of {len(recs)}")
    tot = [sum(v for k, v in s.items()) for _, s in times]
    print(
        f"time per problem: median {np.median(tot):.0f}s, max {max(tot):.0f}s, total "
        f"{sum(tot) / 60:.1f} min; default solve {min(s['solve'] for _, s in times):.1f}–"
        f"{max(s['solve'] for _, s in times):.1f}s"
    )
    print("\nflagged pairs (name x: v, v*, err, ê, ê/|v*|, tags, warned):")
    for r, p, tags in flagged:
        print(
            f"  {r['name']} x{p['i']}: {p['v']:.4g} {p['vt']:.4g} {p['ev']:+.1%} {p['e']:.3g} "
            f"{p['e_rel']:.1%} {'/'.join(tags)} warned={r['warned']}"
        )
    print("\nstray (non-gridlbc) warnings:", strays or "none")
    for r in crashes:
        print("CRASH", r["name"], r["crash"])


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
    elif "--diagnose" in argv:
        names = argv[argv.index("--diagnose") + 1 :] or [
            f.stem for f in sorted(OUT.glob("r48_*.json"))
        ]
        for n in names:
            diagnose(n)
    elif "--extra" in argv:  # --extra NAME TAG x0,x1[,x2] ...
        a = argv[argv.index("--extra") + 1 :]
        extra(a[0], [[float(t) for t in z.split(",")] for z in a[2:]], a[1])
    elif "--before" in argv:
        before()
    elif "--table" in argv:
        table()
    else:
        print(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
