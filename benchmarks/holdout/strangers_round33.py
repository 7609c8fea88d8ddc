"""Stranger round 33: a regression check of r33 (= main 3821f8e) against the library of 3aea650.

RESULTS (2026-12-06, one thread, OLD = /work/wt-old 3aea650, NEW = r33 = main 3821f8e; the
commands at the end of this docstring, ``compare`` prints the table):
179 problems run under both (60 ``r33_*`` drawn from seed 33: 22 LQ, 18 separable with a
horizon, 9 first exit, 6 horizon + exit, 5 nonseparable certified; round 25's 88; 31 ``ex*``
first-exit problems with Box / Ball / union exit sets, 2-D and 3-D). 906 (problem, state, t)
pairs with a trusted truth. Warned: OLD 129, NEW 130.

- Values: bit-identical under OLD and NEW in every one of the 173 solves that ran (13 029 reads:
  the states at t = 0 and T − 2Δt and 40 random points of the box). (c) changes nothing here.
- Crashes: none new. 6 ``ex*`` problems whose exit set holds no node raise the same ValueError
  under both (by design: "contains no node of the grid"); ``ex2_slab_node`` has no estimate under
  both (its strip holds no node of the 2h grid; the solve warns so).
- Warnings after stripping numbers (NEW prints states with 4 digits, OLD numpy's repr, so every
  message's text differs): the same set in 177 of 179. Two differ, both in (b):
  1. ``ex2_slab_thin_cost`` (a cheap strip 0.521 ≤ x₀ ≤ 0.523, 0.02 = 0.2 cell, between node
     rows 0.5 and 0.6; a dear wall x₀ ≤ −1.9): OLD SILENT with v 5.060 vs the 1-D truth 0.242
     at (0.35, −0.5) (+1992 %), 3.230 vs 2.151 at (−1, 0.3); OLD's lattice (an eighth of a cell)
     stepped over the strip, missed_exit None. NEW finds it exactly (missed_exit (0.522, −1.95))
     and warns twice. An improvement.
  2. ``ex3_seam`` (ball r 0.12 at (π, 0.05, −0.05) across the seam of a periodic x₀, holding the
     node (−π, 0, 0)): OLD warned "a part between the nodes near (−3.037, −0.006, −0.069)" (the
     edge of the part the node holds, in a cell next to it) and "estimated error > 5 % ... up to
     163 %"; NEW no longer searches that cell (missed_exit None) and warns once ("at 12 % of the
     states that matter"). Actual error against a 2× finer solve: at most 2.74 % (v 4.9655 /
     0.5287 / 2.4682 vs 4.9837 / 0.5435 / 2.4419); NEW's estimates 0.132 / 0.072 / 0.078 (OLD
     0.496 / 0.354 / 0.349) still ≥ the errors 0.018 / 0.015 / 0.026. OLD's exit warning was a
     false alarm; NEW is right, and still warns (a false alarm by the 5 % bar, shared).
- Estimates: unchanged (to the bit) everywhere except 3 ``ex*`` problems: ex3_seam above;
  ``ex2_ball07_mid_u`` (ball r 0.07 between four nodes) near state (0.30, −0.07): 8.64 → 5.99,
  the error against a 3× finer solve 6.04 (v 6.653 vs 0.615); ``ex2_two_balls`` near state
  (0.7, 0.5): 2.52 → 2.17, error 2.16 (v 2.396 vs 0.235). Both now just under the error (the
  reference itself is a grid solve), above half of it; both warned under both versions.
- Under-reads that got worse (NEW ê < ½ err where OLD's was not): 0. False alarms new in NEW: 0.
  Warnings lost: only ex3_seam's exit message above (a false alarm). (a) added no warning on any
  of the 179.
- Shared by OLD and NEW (not regressions, recorded for the main session):
  ``ex2_adj_strip``: a cheap strip (cost 0, −1.935 ≤ x₀ ≤ −1.925) inside the cell next to the
  dear wall's node row (x₀ ≤ −1.95, cost 3): neither version searches cells with a corner in E,
  missed_exit None under both, v 3.352 vs the 1-D truth 0.318 at (−1.7, −0.5) (+953 %); warned
  (the convergence estimate, ê 3.06), not named as an exit part. ``ex2_adj_ball`` likewise (a
  cheap ball r 0.025 at (0.05, 0.05) next to a dear one holding node (0, 0)): 3.743 vs 0.703
  (fine ×3), ê 2.58, warned. The 3-D strip ``ex3_adj_strip`` is solved right (0.176 vs 0.177)
  and warned with ê ≈ 3.0 at every state (a shared false alarm).
  ``r33_lq3_06`` far state (1.58, −1.61, 1.96) t = 0: v 12.908 vs Riccati 13.960 (−7.5 %),
  ê 0.138, SILENT under both; the box's wall (a 1.5× wider box at the same spacing gives 13.957).
  ``sep2fe_00`` (round 25's) 7.8 % silent under both, as in round 25. ``ex2_seam_r05`` 5.8 %
  against a 3× finer solve, silent, ê 0.175 ≥ err 0.035.
- (c)'s refusal (``tprobe``: a double integrator, 41², T = 1, λ = 0.5, g = |x|², q ≡ 1):
  ``q(x, t)`` without a default: OLD a raw TypeError ("missing 1 required positional argument:
  't'"), NEW a ValueError that says what to do (better). ``q(x, t=0.0)``, a cost that ignores
  t: OLD solves it (v(0, 0) = 1.3472), NEW REFUSES it with the same ValueError ("state_cost
  depends on time ..."). A problem OLD solved now raises: intended by (c), but a default value
  for t is caught too; say so in the release notes or accept a defaulted t.
- Not exercised: the average cost's eigen-solve (no average problems drawn).

Reproduce a single problem (OLD, then NEW, then its truth, then the table and its numbers):
    PYTHONPATH=/work/wt-old python $S batch old ex3_seam --redo
    PYTHONPATH=/work/wt-r33 python $S batch new ex3_seam --redo
    PYTHONPATH=/work/wt-r33 python $S truth ex3_seam
    python $S compare; python $S detail ex3_seam; python $S wall r33_lq3_06
    PYTHONPATH=/work/wt-old python $S tprobe; PYTHONPATH=/work/wt-r33 python $S tprobe

What is compared: each problem is solved with the default ``gridlbc.solve`` under OLD
(/work/wt-old, 3aea650) and under NEW (/work/wt-r33) in separate processes (one process per
version runs the whole batch, one at a time), and per problem the values and estimates at the
states (t = 0 and T − 2Δt for horizon problems) and at 40 random points of the box, the set of
GridlbcWarning messages and ``gridlbc.accuracy.missed_exit(problem)`` are recorded. The truths
are computed once (``truth``), with the NEW library where a library solve is the reference.

Problems:

1. ``r33_*``: 60 drawn with round 25's generators (``gen_lq``, ``gen_sep``, ``gen_ns``) from a
   fresh ``numpy.random.default_rng(33)``; truths as round 25's ``truth_for`` (Riccati, 1-D
   backward Euler / CN, finite-difference first exit, certificates for ``ns``).
2. round 25's own 88 (``draw()``), truths taken from its stored results where the time read is
   the same, else recomputed (``ns`` not recomputed).
3. ``ex*``: first-exit problems with :mod:`gridlbc.regions` exit sets written here (2-D and
   3-D; goal balls of radius 0.5–3 cells at nodes, mid-cell and off-centre, thin boxes between
   and on node rows, unions, balls across a periodic seam). Truth: the 1-D finite-difference
   first exit of x₀ where the exit set is a full slab (the problem is then 1-D); else a NEW
   solve on a grid 3× (2-D) or 2× (3-D) finer ("fine" reference, not exact).

    cd /work/wt-r33 && export NUMBA_NUM_THREADS=1 S=benchmarks/holdout/strangers_round33.py
    PYTHONPATH=/work/wt-old python $S batch old [NAMES]    # OLD
    PYTHONPATH=/work/wt-r33 python $S batch new [NAMES]    # NEW
    PYTHONPATH=/work/wt-r33 python $S truth [NAMES]
    python $S compare
"""

from __future__ import annotations

import importlib.util
import json
import math
import re
import sys
import time
import traceback
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem
from gridlbc.regions import Ball, Box

_HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("r25", _HERE / "strangers_round25.py")
r25 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(r25)

OUT = Path("/work/main/benchmarks/holdout/strangers_round33_results")  # gitignored there
R25_OUT = Path("/work/main/benchmarks/holdout/strangers_round25_results")
SEED = 33


# ================= problems ======================================================================
def draw33():
    plan = (
        ("lq", 2, 12),
        ("lq", 3, 8),
        ("lq", 4, 2),
        ("hz", 2, 12),
        ("hz", 3, 6),
        ("fe", 2, 6),
        ("fe", 3, 3),
        ("hzfe", 2, 6),
        ("ns", 2, 5),
    )
    rng = np.random.default_rng(SEED)
    specs = {}
    for kind, d, cnt in plan:
        for k in range(cnt):
            if kind == "lq":
                s = r25.gen_lq(rng, d, k)
            elif kind == "ns":
                s = r25.gen_ns(rng, k)
            else:
                s = r25.gen_sep(rng, d, k, kind)
            s["name"] = "r33_" + s["name"]
            specs[s["name"]] = s
    return specs


def _ex(name, d, lo, hi, n, per, lam, drift, q, regions, costs, X, slab=False, b=1.0):
    return dict(
        family="ex",
        name=name,
        d=d,
        lo=lo,
        hi=hi,
        n=n,
        per=per,
        lam=lam,
        drift=drift,
        q=q,
        regions=regions,
        costs=costs,
        X=X,
        slab=slab,
        b=b,
        T=None,
    )


def exit_specs():
    """First-exit problems with shape exit sets. 2-D: [-2, 2]², 41 nodes (h = 0.1); 3-D:
    [-1, 1]³, 21 nodes (h = 0.1); periodic axes [-π, π) with 64 nodes (h = 0.0982)."""
    P = math.pi
    hp = 2 * P / 64
    L2, H2, N2 = [-2.0, -2.0], [2.0, 2.0], [41, 41]
    L3, H3, N3 = [-1.0] * 3, [1.0] * 3, [21] * 3
    inf = math.inf
    S = []
    # balls in 2-D
    for nm, c, r, lam, dr in (
        ("ex2_ball05_node", [0.0, 0.0], 0.05, 0.3, [0.0, 0.0]),
        ("ex2_ball07_mid", [0.05, 0.05], 0.07, 0.5, [0.2, -0.1]),
        ("ex2_ball1_off", [0.03, 0.07], 0.1, 0.3, [0.0, 0.0]),
        ("ex2_ball2_off", [0.51, -0.33], 0.2, 0.2, [-0.3, 0.2]),
        ("ex2_ball3", [0.5, 0.5], 0.3, 0.1, [0.0, 0.0]),
        ("ex2_ball_tangent", [0.0, 0.05], 0.06, 0.3, [0.0, 0.0]),
        ("ex2_ball_edge", [0.05, 0.0], 0.0501, 0.4, [0.1, 0.0]),
    ):
        S.append(
            _ex(
                nm, 2, L2, H2, N2, [False, False], lam, dr, 1.0, [["ball", c, r]], [0.0],
                [[-1.0, -0.7], [c[0] + 0.25, c[1] - 0.12], [1.7, 1.6]],
            )
        )  # fmt: skip
    # a goal ball half a cell wide between four nodes (with a dear wall so E holds a node)
    S.append(
        _ex(
            "ex2_ball05_mid", 2, L2, H2, N2, [False, False], 0.3, [0.0, 0.0], 1.0,
            [["ball", [0.05, 0.05], 0.05], ["box", [-inf, -inf], [-1.95, inf]]], [0.0, 3.0],
            [[-1.0, -0.7], [0.3, -0.07], [1.7, 1.6]],
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex3_ball05_mid_u", 3, L3, H3, N3, [False] * 3, 0.3, [0.0] * 3, 1.0,
            [["ball", [0.05, 0.05, 0.05], 0.05], ["box", [-inf, -inf, -inf], [-0.95, inf, inf]]],
            [0.0, 3.0], [[-0.5, 0.2, 0.1], [0.2, 0.1, 0.0], [0.85, -0.85, 0.85]],
        )
    )  # fmt: skip
    # thin boxes in 2-D
    S.append(
        _ex(
            "ex2_slab_mid", 2, L2, H2, N2, [False, False], 0.3, [0.2, 0.0], 0.8,
            [["box", [0.52, -inf], [0.55, inf]]], [0.0], [[-1.0, 0.3], [0.3, -0.5], [-1.7, 1.5]],
            slab=True,
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex2_slab_node", 2, L2, H2, N2, [False, False], 0.3, [0.2, 0.0], 0.8,
            [["box", [0.49, -inf], [0.51, inf]]], [0.0], [[-1.0, 0.3], [0.3, -0.5], [-1.7, 1.5]],
            slab=True,
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex2_slab_thin_cost", 2, L2, H2, N2, [False, False], 0.15, [0.0, 0.0], 1.0,
            [["box", [0.521, -inf], [0.523, inf]], ["box", [-inf, -inf], [-1.9, inf]]],
            [0.0, 2.0], [[-1.0, 0.3], [0.35, -0.5], [-1.5, 1.5]], slab=True,
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex2_box_short", 2, L2, H2, N2, [False, False], 0.3, [0.0, 0.0], 1.0,
            [["box", [0.52, -0.5], [0.56, 0.5]]], [0.0], [[-1.0, 0.3], [0.3, 0.0], [1.7, 1.7]],
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex2_union", 2, L2, H2, N2, [False, False], 0.3, [0.0, 0.0], 1.0,
            [["ball", [0.55, 0.55], 0.15], ["box", [-inf, -inf], [-1.85, inf]]],
            [0.0, 1.5], [[-1.0, 0.3], [0.8, 0.55], [-1.5, 1.7]],
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex2_two_balls", 2, L2, H2, N2, [False, False], 0.25, [0.0, 0.0], 1.0,
            [["ball", [0.55, 0.55], 0.06], ["ball", [-0.65, 0.45], 0.12]],
            [0.0, 0.4], [[0.0, 0.3], [0.7, 0.5], [-1.5, -1.7]],
        )
    )  # fmt: skip
    # periodic seam (axis 0 periodic)
    for nm, r, off in (
        ("ex2_seam_r15", 1.5 * hp, 0.0),
        ("ex2_seam_r05", 0.5 * hp, 0.3 * hp),
        ("ex2_seam_r3", 3 * hp, -0.2 * hp),
    ):
        S.append(
            _ex(
                nm, 2, [-P, -2.0], [P, 2.0], [64, 41], [True, False], 0.3, [0.3, 0.0], 1.0,
                [["ball", [P + off, 0.03], r]], [0.0],
                [[0.0, 0.3], [-P + 0.3, 0.1], [2.7, -1.5]],
            )
        )  # fmt: skip
    # 3-D
    S.append(
        _ex(
            "ex3_ball05_mid", 3, L3, H3, N3, [False] * 3, 0.3, [0.0] * 3, 1.0,
            [["ball", [0.05, 0.05, 0.05], 0.05]], [0.0],
            [[-0.5, 0.2, 0.1], [0.2, 0.1, 0.0], [0.85, -0.85, 0.85]],
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex3_ball15", 3, L3, H3, N3, [False] * 3, 0.3, [0.1, 0.0, -0.1], 1.0,
            [["ball", [0.23, -0.12, 0.07], 0.15]], [0.0],
            [[-0.5, 0.2, 0.1], [0.45, -0.1, 0.0], [-0.85, 0.85, -0.85]],
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex3_slab_mid", 3, L3, H3, N3, [False] * 3, 0.3, [0.2, 0.0, 0.0], 0.8,
            [["box", [0.52, -inf, -inf], [0.55, inf, inf]]], [0.0],
            [[-0.5, 0.2, 0.1], [0.3, 0.1, 0.0], [-0.85, 0.85, -0.85]],
            slab=True,
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex3_seam", 3, [-P, -1.0, -1.0], [P, 1.0, 1.0], [64, 21, 21], [True, False, False],
            0.3, [0.0, 0.0, 0.0], 1.0, [["ball", [P, 0.05, -0.05], 0.12]], [0.0],
            [[0.0, 0.2, 0.1], [-P + 0.3, 0.1, 0.0], [2.5, -0.85, 0.85]],
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex3_union", 3, L3, H3, N3, [False] * 3, 0.3, [0.0] * 3, 1.0,
            [["ball", [0.45, 0.45, 0.45], 0.07], ["box", [-0.53, -inf, -inf], [-0.51, inf, inf]]],
            [0.0, 1.0], [[0.0, 0.2, 0.1], [0.55, 0.45, 0.45], [-0.85, 0.85, -0.85]],
        )
    )  # fmt: skip
    # the shapes above that hold no node, again with a dear wall at the low side holding nodes
    wall2 = ["box", [-inf, -inf], [-1.95, inf]]
    wall3 = ["box", [-inf, -inf, -inf], [-0.95, inf, inf]]
    for s in list(S):
        if s["name"] in ("ex2_ball07_mid", "ex2_slab_mid", "ex2_box_short", "ex3_slab_mid"):
            u = dict(s, name=s["name"] + "_u")
            u["regions"] = s["regions"] + [wall2 if s["d"] == 2 else wall3]
            u["costs"] = s["costs"] + [3.0]
            S.append(u)
    u = dict(next(s for s in S if s["name"] == "ex3_union"), name="ex3_union_u")
    u["regions"] = u["regions"] + [wall3]
    u["costs"] = u["costs"] + [3.0]
    S.append(u)
    # a cheap part of E in a cell next to a dear node of E (NEW no longer searches those cells)
    S.append(
        _ex(
            "ex2_adj_strip", 2, L2, H2, N2, [False, False], 0.3, [0.0, 0.0], 1.0,
            [["box", [-inf, -inf], [-1.95, inf]], ["box", [-1.935, -inf], [-1.925, inf]]],
            [3.0, 0.0], [[-1.5, 0.3], [-1.7, -0.5], [0.0, 1.5]], slab=True,
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex3_adj_strip", 3, L3, H3, N3, [False] * 3, 0.3, [0.0] * 3, 1.0,
            [["box", [-inf, -inf, -inf], [-0.95, inf, inf]],
             ["box", [-0.935, -inf, -inf], [-0.925, inf, inf]]],
            [3.0, 0.0], [[-0.6, 0.3, 0.0], [-0.8, -0.5, 0.2], [0.5, 0.5, 0.5]], slab=True,
        )
    )  # fmt: skip
    S.append(
        _ex(
            "ex2_adj_ball", 2, L2, H2, N2, [False, False], 0.3, [0.0, 0.0], 1.0,
            [["ball", [0.0, 0.0], 0.03], ["ball", [0.05, 0.05], 0.025]],
            [3.0, 0.0], [[-0.5, 0.3], [0.3, 0.2], [1.5, -1.5]],
        )
    )  # fmt: skip
    return {s["name"]: s for s in S}


def build_ex(spec, factor=1):
    d = spec["d"]
    axes = []
    for i in range(d):
        n = spec["n"][i]
        if factor > 1:
            n = n * factor if spec["per"][i] else (n - 1) * factor + 1
        axes.append(Axis(spec["lo"][i], spec["hi"][i], n, periodic=spec["per"][i]))
    grid = Grid(axes)
    sysm = r25.Sep(
        [r25.make_fn([["const", c]]) for c in spec["drift"]],
        [r25.make_fn([["const", spec["b"]]]) for _ in range(d)],
        [i for i in range(d) if spec["per"][i]],
    )
    regs = []
    for kind, a, b in spec["regions"]:
        regs.append(Ball(a, b) if kind == "ball" else Box(a, b))
    region = regs[0]
    for r in regs[1:]:
        region = region | r
    costs = spec["costs"]
    if len(set(costs)) == 1:
        exit_cost = float(costs[0])
    else:

        def exit_cost(x):
            x = np.asarray(x, float)
            out = np.full(len(x), np.inf)
            for r, c in zip(regs, costs):
                out = np.where(r.with_periods(_periods(spec))(x), np.minimum(out, c), out)
            return np.where(np.isfinite(out), out, max(costs))

    qv = float(spec["q"])
    return Problem(
        sysm,
        grid,
        None,
        state_cost=lambda x: qv + 0 * np.asarray(x)[:, 0],
        control_cost=np.ones(d),
        temperature=spec["lam"],
        exit=region,
        exit_cost=exit_cost,
    )


def _periods(spec):
    return [
        (spec["hi"][i] - spec["lo"][i]) if spec["per"][i] else math.inf for i in range(spec["d"])
    ]


def ex_truth(spec, X):
    X = np.asarray(X, float)
    if spec["slab"]:
        ax = dict(
            lo=spec["lo"][0],
            hi=spec["hi"][0],
            periodic=spec["per"][0],
            a=lambda x: spec["drift"][0] + 0 * x,
            b=lambda x: spec["b"] + 0 * x,
            q=lambda x: spec["q"] + 0 * x,
            R=1.0,
        )

        def mask(x):
            m = np.zeros(len(x), bool)
            for _k, a, b in spec["regions"]:
                m |= (x >= a[0]) & (x <= b[0])
            return m

        def cost(x):
            out = np.full(len(x), np.inf)
            for (_k, a, b), c in zip(spec["regions"], spec["costs"]):
                out = np.where((x >= a[0]) & (x <= b[0]), np.minimum(out, c), out)
            return np.where(np.isfinite(out), out, 0.0)

        vs = []
        for n in (40001, 80001):
            f, _z = r25.fd_exit1d(ax, spec["lam"], mask, cost, n)
            vs.append(f(X[:, 0]))
        return {0.0: (vs[1], np.abs(vs[1] - vs[0]), np.zeros(len(X), bool), {"ref": "1d"})}
    factor = 3 if spec["d"] == 2 else 2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fine = gridlbc.solve(build_ex(spec, factor), error_estimate=False)
    v = np.asarray(fine.value(X), float)
    return {0.0: (v, np.zeros(len(X)), np.zeros(len(X), bool), {"ref": f"fine x{factor}"})}


def all_specs():
    out = {}
    out.update(draw33())
    out.update(exit_specs())
    out.update(r25.draw())
    return out


def build(spec):
    if spec["family"] == "ex":
        return build_ex(spec)
    return r25.build(spec)


# ================= one version's batch ===========================================================
def _warns(w):
    return sorted(
        {
            f"{x.category.__name__}: {x.message}"
            for x in w
            if issubclass(x.category, gridlbc.GridlbcWarning)
        }
    )


def one(name, spec, tag):
    rec = dict(name=name, tag=tag, lib=gridlbc.__file__)
    try:
        p = build(spec)
        X = np.asarray(spec["X"], float)
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            s = gridlbc.solve(p)
        rec["seconds"] = time.perf_counter() - t0
        rec["warnings"] = _warns(w)
        stationary = p.horizon is None
        ts = [0.0] if stationary else [0.0, float(max(p.horizon - 2 * s.diagnostics.dt, 0.0))]
        rec["dt"] = None if stationary else float(s.diagnostics.dt)
        rng = np.random.default_rng(7)
        lo = np.array([a.lo for a in p.grid.axes])
        hi = np.array([a.hi for a in p.grid.axes])
        Y = lo + (hi - lo) * rng.random((40, len(lo)))
        rec["reads"] = []
        for t in ts:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                v = np.asarray(s.value(X, t), float)
                try:
                    e = np.asarray(s.error_estimate(X, t), float)
                except ValueError as ex:  # no estimate (an exit set the 2h grid cannot hold)
                    e = np.full(len(X), np.nan)
                    rec["no_estimate"] = repr(ex)[:200]
                vy = np.asarray(s.value(Y, t), float)
            rec["reads"].append(dict(t=t, v=v.tolist(), est=e.tolist(), v_random=vy.tolist()))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                me = gridlbc.accuracy.missed_exit(p)
            rec["missed_exit"] = None if me is None else np.asarray(me).tolist()
        except Exception as ex:
            rec["missed_exit"] = f"error: {ex!r}"
    except Exception as ex:
        rec["crash"] = repr(ex)
        rec["traceback"] = traceback.format_exc()
    d = OUT / tag
    d.mkdir(parents=True, exist_ok=True)
    (d / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
    print(
        f"{tag} {name:18s} {rec.get('seconds', -1):6.1f}s warns={len(rec.get('warnings', []))} "
        f"{'CRASH ' + rec['crash'][:100] if 'crash' in rec else ''}",
        flush=True,
    )


def batch(tag, names):
    specs = all_specs()
    for n in names or list(specs):
        if (OUT / tag / f"{n}.json").exists() and "--redo" not in sys.argv:
            continue
        one(n, specs[n], tag)


# ================= truths ========================================================================
def _r25_truth(name, ts):
    f = R25_OUT / f"{name}.json"
    if not f.exists():
        return None
    r = json.loads(f.read_text())
    out = {}
    for t in ts:
        hit = [x for x in r["reads"] if abs(x["t"] - t) < 1e-12]
        if not hit:
            return None
        out[t] = (hit[0]["truth"], hit[0]["pm"], hit[0]["untrusted"])
    return out


def truth(names):
    specs = all_specs()
    d = OUT / "truth"
    d.mkdir(parents=True, exist_ok=True)
    for n in names or list(specs):
        if (d / f"{n}.json").exists():
            continue
        new = OUT / "new" / f"{n}.json"
        if not new.exists():
            continue
        rn = json.loads(new.read_text())
        if "reads" not in rn:
            continue
        spec = specs[n]
        ts = [x["t"] for x in rn["reads"]]
        t0 = time.perf_counter()
        try:
            if spec["family"] == "ex":
                tr = ex_truth(spec, spec["X"])
            elif not n.startswith("r33_") and (got := _r25_truth(n, ts)) is not None:
                tr = got
            elif not n.startswith("r33_") and spec["family"] == "ns":
                continue
            else:
                tr = r25.truth_for(spec, np.asarray(spec["X"], float), ts)
        except Exception as ex:
            print("truth failed", n, repr(ex), flush=True)
            continue
        rec = {
            repr(float(t)): dict(
                truth=np.asarray(tr[t][0], float).tolist(),
                pm=np.asarray(tr[t][1], float).tolist(),
                untrusted=np.asarray(tr[t][2], bool).tolist(),
            )
            for t in ts
        }
        (d / f"{n}.json").write_text(json.dumps(rec, indent=1))
        print(f"truth {n:18s} {time.perf_counter() - t0:5.1f}s", flush=True)


# ================= comparison ====================================================================
def _norm(m):
    """A warning's text without its numbers (NEW prints states with 4 digits, OLD numpy's repr)."""
    m = re.sub(r"[-+]?\d+(\.\d*)?(e[-+]?\d+)?", "#", m)
    return re.sub(r"\s+", " ", re.sub(r"\[[#,\s.]*\]", "[#]", m))


def detail(names):
    for n in names:
        o = json.loads((OUT / "old" / f"{n}.json").read_text())
        w = json.loads((OUT / "new" / f"{n}.json").read_text())
        ft = OUT / "truth" / f"{n}.json"
        tr = json.loads(ft.read_text()) if ft.exists() else {}
        print(n, "old", o.get("warnings"), "\n   new", w.get("warnings"))
        for ro, rw in zip(o["reads"], w["reads"]):
            T = tr.get(repr(float(rw["t"])), {})
            print(
                f"  t={rw['t']:.4f} v_old={np.round(ro['v'], 5).tolist()} v_new="
                f"{np.round(rw['v'], 5).tolist()} truth={np.round(T.get('truth', []), 5).tolist()}"
                f"\n     est_old={np.round(ro['est'], 5).tolist()} est_new={np.round(rw['est'], 5).tolist()}"
            )


def compare():
    specs = all_specs()
    rows, counts = [], dict(problems=0, pairs=0, warned_old=0, warned_new=0)
    for n, spec in specs.items():
        fo, fn = OUT / "old" / f"{n}.json", OUT / "new" / f"{n}.json"
        if not (fo.exists() and fn.exists()):
            continue
        o, w = json.loads(fo.read_text()), json.loads(fn.read_text())
        counts["problems"] += 1
        if "crash" in o or "crash" in w:
            same = o.get("crash") == w.get("crash")
            rows.append((7 if same else 0, n, f"crash old={o.get('crash')} new={w.get('crash')}"))
            continue
        counts["warned_old"] += bool(o["warnings"])
        counts["warned_new"] += bool(w["warnings"])
        ft = OUT / "truth" / f"{n}.json"
        tr = json.loads(ft.read_text()) if ft.exists() else None
        lam = spec["lam"]
        worst, notes = 0.0, []
        for ro, rw in zip(o["reads"], w["reads"]):
            vo, vn = np.array(ro["v"]), np.array(rw["v"])
            eo, en = np.array(ro["est"]), np.array(rw["est"])
            dv = np.max(np.abs(vo - vn) / np.maximum(np.abs(vo), lam))
            dvr = np.max(
                np.abs(np.array(ro["v_random"]) - np.array(rw["v_random"]))
                / np.maximum(np.abs(np.array(ro["v_random"])), lam)
            )
            if dv > 1e-9 or dvr > 1e-9:
                notes.append(f"value changed t={ro['t']:.3f}: states {dv:.2e}, random {dvr:.2e}")
            if tr is not None and repr(float(rw["t"])) in tr:
                T = tr[repr(float(rw["t"]))]
                vt = np.array(T["truth"])
                bad = np.array(T["untrusted"])
                err = np.abs(vn - vt)
                rel = err / np.maximum(np.abs(vt), lam)
                for i in range(len(vn)):
                    if bad[i]:
                        continue
                    counts["pairs"] += 1
                    worst = max(worst, rel[i])
                    if en[i] < 0.5 * err[i] and eo[i] >= 0.5 * err[i] and rel[i] > 0.02:
                        notes.append(
                            f"UNDER-READ new t={rw['t']:.3f} x{i}: err {rel[i]:.2%}, "
                            f"est new {en[i]:.3g} old {eo[i]:.3g} abs err {err[i]:.3g}"
                        )
            re_ = np.max(np.abs(en - eo) / np.maximum(np.abs(eo), 1e-12))
            if re_ > 0.2:
                notes.append(
                    f"estimate changed t={rw['t']:.3f}: old {np.round(eo, 4).tolist()} "
                    f"new {np.round(en, 4).tolist()}"
                )
        so, sn = {_norm(m) for m in o["warnings"]}, {_norm(m) for m in w["warnings"]}
        if so != sn:
            acc = "" if tr is None else f" (worst err {worst:.2%})"
            if not so and sn:
                kind = 1 if (tr is not None and worst < 0.05) else 3
                notes.insert(0, f"NEW WARNING{acc}: {sorted(sn - so)[0][:200]}")
            elif so and not sn:
                kind = 2
                notes.insert(0, f"LOST WARNING{acc}: {sorted(so - sn)[0][:200]}")
            else:
                kind = 4
                notes.insert(
                    0,
                    f"messages differ{acc}: -{[m[:120] for m in so - sn]} +{[m[:120] for m in sn - so]}",
                )
            rows.append((kind, n, "; ".join(notes)))
        elif notes:
            rows.append((5, n, "; ".join(notes)))
        if not so and not sn and tr is not None and worst > 0.05:
            rows.append((8, n, f"silent in both, worst err {worst:.2%}"))
        if spec["family"] == "ex":
            print(
                f"  {n:18s} warned old/new {len(so)}/{len(sn)} worst err {worst:.2%} "
                f"missed_exit old {o.get('missed_exit') is not None} new "
                f"{w.get('missed_exit') is not None}"
            )
        if o.get("missed_exit") != w.get("missed_exit"):
            rows.append(
                (6, n, f"missed_exit old={o.get('missed_exit')} new={w.get('missed_exit')}")
            )
    rows.sort()
    for r in rows:
        print(r[0], r[1], r[2])
    print(counts)
    (OUT / "compare.json").write_text(json.dumps(dict(rows=rows, counts=counts), indent=1))


def wall(names):
    """LQ: the same spacing on a box 1.5× wider at the same Δt (round 25's wall check)."""
    specs = all_specs()
    for n in names:
        spec = specs[n]
        w = json.loads((OUT / "new" / f"{n}.json").read_text())
        X = np.asarray(spec["X"], float)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sw = gridlbc.solve(r25.build_lq(spec, 1.5), dt=w["dt"], error_estimate=False)
        for r in w["reads"]:
            print(n, f"t={r['t']:.4f}", "v", np.round(r["v"], 4).tolist(), "wider box",
                  np.round(np.asarray(sw.value(X, r["t"])), 4).tolist(), "riccati",
                  np.round(r25.lq_value(spec, X, r["t"]), 4).tolist())  # fmt: skip


def tprobe():
    """(c): a state cost with a parameter named t, with and without a default."""
    from gridlbc.systems import LinearSystem

    sysm = LinearSystem([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]])
    grid = Grid([Axis(-2, 2, 41), Axis(-2, 2, 41)])
    for label, q in (
        ("q(x, t)", lambda x, t: 1.0 + 0 * x[:, 0] + 0.1 * t),
        ("q(x, t=0)", lambda x, t=0.0: 1.0 + 0 * x[:, 0]),
    ):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                p = Problem(
                    sysm,
                    grid,
                    1.0,
                    terminal_cost=lambda x: (x**2).sum(1),
                    state_cost=q,
                    temperature=0.5,
                )
                sol = gridlbc.solve(p, error_estimate=False)
            print(label, "v(0) =", float(sol.value(np.zeros((1, 2)))[0]))
        except Exception as ex:
            print(label, "refused:", repr(ex)[:300])


if __name__ == "__main__":
    cmd = sys.argv[1]
    args = [a for a in sys.argv[2:] if not a.startswith("--")]
    if cmd == "batch":
        batch(args[0], args[1:])
    elif cmd == "truth":
        truth(args)
    elif cmd == "tprobe":
        tprobe()
    elif cmd == "wall":
        wall(args)
    elif cmd == "detail":
        detail(args)
    elif cmd == "compare":
        compare()
    elif cmd == "list":
        for n in all_specs():
            print(n)
