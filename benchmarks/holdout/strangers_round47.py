"""Stranger round 47: the λ-relative reading of the error where v* < λ (seed 47), public API only.

WHAT MAIN DID WITH IT (2026-12-08): at the user's own states, ``solve(tol=, states=)`` reads the
relative error against abs(v(x, 0)) (``gridlbc.accuracy.estimate.given_floor``: min(λ, abs(v(x, 0)))
in place of λ; λ for an average cost, whose h is zero at a state of the solve's choosing), and
the warnings name the scale they read ("of max(|v|, λ)"). ``solve(tol=0.05, states=[x2])``:
r47_PointMass_hzfe_18 +11.0 % → −0.5 % (seven rounds, 32 s), r47_River2_hzfe_17 +12.3 % → +2.1 %
(three rounds, 16 s), both accepted unrefined before. The default solve's warning still reads
λ over the states that matter: the four silent pairs stay silent. This folder's results were
lost when the worktree was removed; ``--run`` makes them again.

WHAT IT TESTS: the library judges a solve's relative error as ê / max(|v|, λ) (docs/accuracy.rst
"Relative error"; gridlbc/accuracy/estimate.py ``relative_error``) and the default solve warns
(ResolutionWarning) when that exceeds 5 %. An outside user reads "% off" as |v − v*| / |v*|. Where
v* < λ (a high temperature, a cheap task, a state near its goal or exit) an error of 15 % of v*
can read below 5 % of λ and pass silently. Only 7 of the 212 pairs of the library's own hold-out
corpus have |v*| < λ. Here every problem is drawn in that regime: λ log-uniform in [0.5, 3], the
costs (state, terminal, exit, all multiplied by one factor) scaled by a few coarse solves so that
v at the middle state is a log-uniform 0.15 … 0.8 λ.

RESULTS (library of main a934fce, worktree r47, 2026-12-07 23:35 – 2026-12-08 00:12 UTC, one
thread, the other core busy): ``--run`` of all 22 draws (18, then 4 appended to ``KINDS`` toward
the exits; the earlier draws unchanged), each under ``timeout 400`` (none hit it; default solves
0.2–7.4 s, certificates 1–140 s); ``--diagnose`` of the 6 problems with a silent or λ-quiet pair;
``--recheck`` (seed 48, half the SDE step) of the 4 silent ones; by hand ``solve(tol=0.05 |v*| /
λ, states=[x])`` of two silent pairs (``--tighttol``, first run from a copy of it); ``--table``.

- 22 problems (PointMass 5, Pendulum 3, LinearSystem 2-D 4 / 3-D 2, 2-D single integrator 3,
  River 2-D 4 / 3-D 1; 6 fixed horizon, 8 stationary first exits, 8 first exits with a horizon),
  λ 0.50–2.76, cost factors 0.02–1.0. 66 pairs, ALL trusted (ESS 1931–2000, k̂ ≤ 0.66, no
  CertificateWarning after max_time was raised from 40 to 300: at 40, 8–14 % of the paths of
  r47_PointMass_fe_00 had not exited, their weight not negligible at a state cost of 0.013/s).
  v*/λ 0.013–1.77; 62 of 66 pairs have v* < λ. 5 of 22 default solves warned.
- OFF (|v − v*| > 10 % of |v*|): 7. SILENT: 4. λ-quiet (OFF and |err_λ| < 5 %): all 7 (the
  largest |err_λ| of the round is 4.6 %: by the library's own reading NO pair is more than 5 %
  off). UNDER-READ (ê < ½ |v − v*| beyond 2 SE): 0; ê ≥ |v − v*| at every OFF pair.

      pair                      v        v*               err_v    err_λ   ê        ê/|v*|  warned
      r47_Linear2_hzfe_13 x2    0.02468  0.02222±0.0008   +11.1 %  +0.2 %  0.00256  11.5 %  no
      r47_Linear2_hzfe_20 x2    0.01935  0.01628±0.0009   +18.8 %  +0.2 %  0.00961  59 %    no
      r47_PointMass_hzfe_18 x2  0.04881  0.04396±0.0006   +11.0 %  +0.9 %  0.00622  14.1 %  no
      r47_River2_hzfe_17 x2     0.06277  0.05587±0.0011   +12.3 %  +1.4 %  0.0112   20 %    no
      r47_PointMass_hzfe_05 x2  0.2694   0.2261±0.017     +19.2 %  +1.9 %  0.0992   44 %    yes (1)
      r47_River3_hzfe_09 x1     0.4776   0.4280±0.0073    +11.6 %  +3.4 %  0.0758   17.7 %  yes (2)
      r47_River3_hzfe_09 x2     0.4265   0.3806±0.0074    +12.1 %  +3.2 %  0.0829   21.8 %  yes (2)

  (1) ResolutionWarning "exceeds 5% of |v| near [0.7385, −0.1368] … both put it at 12% of |v|"
  (a point by the exit, not x2 = [0.944, −0.670]); (2) "exceeds 5% of |v| at 14% of the states
  that matter (90% of them are within 5.1%; the largest, 11%, …)": both warnings were tripped by
  other states, and x2 of r47_PointMass_hzfe_05 read alone is 4.4 % of λ. Also 5–10 % off, quiet:
  r47_SI2_hzfe_21 x2 +8.4 % (v*/λ 0.075, err_λ +0.6 %), r47_Pendulum_fe_06 x2 −5.5 %,
  r47_PointMass_hzfe_18 x1 +5.1 %; warned: r47_River3_hzfe_09 x0 +8.2 %, r47_Linear3_fe_03 x0
  +6.2 %.
- WHERE: every OFF pair is a first exit WITH a horizon (hzfe), 6 of its 7 at the state 3 cells off
  the exit set, v too HIGH in all 7 (+11 … +19 %): 7 of the 8 hzfe near-exit states are +8 … +19 %
  off (the eighth, r47_Pendulum_hzfe_12 x2, +0.6 %). The stationary first exits near their exit
  sets are within −5.5 … +4.2 % (8 pairs), the fixed horizons within 0.6 % everywhere. In
  absolute terms the silent errors are 0.0025–0.007 = 0.2–1.4 % of λ: v* there is 1.3–11 % of λ,
  mostly the (scaled) exit cost plus a short approach.
- DIAGNOSES (``--diagnose``: the default solve on a grid 2× finer per axis, with its estimate;
  ``solve(problem, tol=0.05, states=[x], max_seconds=120)``):

      pair                      2× grid v (err_v)   2× ê      tol=0.05 at x: v (err_v), ê, met
      r47_Linear2_hzfe_13 x2    0.02441 (+9.9 %)    0.00253   0.02468 (+11.1 %), 0.00256, MET at once
      r47_Linear2_hzfe_20 x2    0.01698 (+4.3 %)    0.00296   0.01935 (+18.8 %), 0.00961, MET at once
      r47_PointMass_hzfe_18 x2  0.04576 (+4.1 %)    0.00305   0.04881 (+11.0 %), 0.00622, MET at once
      r47_River2_hzfe_17 x2     0.05853 (+4.8 %)    0.00424   0.06277 (+12.3 %), 0.0112,  MET at once
      r47_PointMass_hzfe_05 x2  0.2519 (+11.4 %)    0.0399    0.2694 (+19.2 %), 0.0992,  MET at once
      r47_River3_hzfe_09 x1     0.4564 (+6.6 %)     0.0124    0.4776 (+11.6 %), 0.0758,  MET at once
      r47_River3_hzfe_09 x2     0.4089 (+7.4 %)     0.0124    0.4265 (+12.1 %), 0.0829,  MET at once

  ``tol=0.05`` never refines: the first round's estimate at x, read as ê / max(|v|, λ), is
  already ≤ 5 % (River3 x2: 5.75 % by the grids, "met" by the round's certified error 4.95 %
  of λ, Refinement.certified_error). Its result is the default solve's value, 11–19 % off, with no
  warning. The 2× grids converge at first order toward v* (+4 … +11 % left); those of the four silent
  pairs do not warn either (r47_PointMass_hzfe_05's does). The estimate itself is RIGHT at every silent pair: ê ≥ |v − v*| (ratio 1.04–3.1), ê/|v|
  10–50 %; only the λ-relative reading (warning and tol) keeps it quiet. The 2× grid of
  r47_River3_hzfe_09 under-reads (ê 0.0124 at errors 0.028 / 0.028), the one under-read seen.
  Truths rechecked (seed 48, SDE step halved): 0.02243 ± 0.0006, 0.01509 ± 0.0006, 0.04378 ±
  0.0006, 0.05433 ± 0.0008 (first 0.02222, 0.01628, 0.04396, 0.05587), no CertificateWarning: the
  errors stand (or grow). Asked in λ's units for 5 % of v*
  (``solve(tol=0.05 |v*| / λ, states=[x2], max_seconds=120)``, by hand): r47_PointMass_hzfe_18
  tol 0.0043, MET on 149×1675 in 49 s, v 0.04416 (+0.4 %); r47_Linear2_hzfe_20 tol 0.00065,
  stopped by the time budget on 553×533 at 0.10 % (warned, true), v 0.01589 (−2.4 %): the
  refinement reaches the truth when the tolerance is put in λ's units; only the reading stops
  it.
- THE BLIND SPOT IS REAL, in the λ-relative reading and not in the estimate: 4 of 66 pairs (6 %;
  4 of the 8 hzfe near-exit states) are 11–19 % off with a quiet default solve, 7 of 66 are > 10 %
  off and every one of them is below 5 % by the library's reading, and ``tol=0.05`` at the very
  state returns them unrefined. Its size is bounded by the convention: |v − v*| ≤ 5 % λ means
  err_v ≤ 5 % λ / v*, unbounded as v* → 0 (here v*/λ ≥ 0.013 and the absolute errors 0.2–1.9 % of
  λ). Messages: the ResolutionWarning says "exceeds 5% of |v|" and "12% of |v|" where it reads
  max(|v|, λ) (gridlbc/accuracy/assessment.py ``check_accuracy``), so a user is told the wrong
  denominator.

Generator (``gen``, seed 47): PointMass, Pendulum, LinearSystem 2-D / 3-D (identity B, or one
control on one axis), a 2-D single integrator with anisotropic control cost, and a user
``ControlAffineSystem`` ("River", 2-D / 3-D: a channel flow along x0, restoring drift on the
others, state-dependent gain on x0); λ log-uniform in [0.5, 3]; R diagonal, log-uniform [0.1, 3]
(anisotropic noise where several controls differ); q = c0 + a quadratic about the goal, and in
some a narrow well (q0 − D e^(−|x − c|²/2w²), clipped ≥ 0.02 c0, width 1–2 cells) or narrow ridge;
the ending: a horizon T in [1, 4] with a Quadratic terminal cost about a goal ("hz"), a stationary
first exit into a Ball or Box near the goal (a narrow Ball of radius 2–3 cells in some) with a
constant or quadratic exit cost ("fe"), or both ("hzfe"). Grids as a user picks them: 61–121 per
axis in 2-D, 25–37 in 3-D. States: far (0.75 of the box from the goal), middle, near (the goal,
or ≥ 2.5 cells off the exit set).

Truth: ``gridlbc.certify(problem, policy, X, 2000, dt, seed=47, richardson=True)`` (default
proposal "auto", default boundary) with the policy of a solve on a grid 2× finer per axis (1.5×
in 3-D above 3·10⁵ fine nodes); dt = T/160 with a horizon, 0.005 (max_time 300) without.
Trusted: ESS ≥ 100, k̂ ≤ 0.7, no CertificateWarning naming the state about heavy tails, unexited
weight, the extrapolation, the effective sample size or an unvisited feature.

    cd /work/wt-r47 && PYTHONPATH=/work/wt-r47 NUMBA_NUM_THREADS=1 \\
        python benchmarks/holdout/strangers_round47.py --list | --run [NAMES] | --table \\
        | --diagnose [NAMES] | --recheck NAMES | --tighttol NAMES
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

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc import systems as S
from gridlbc.regions import Ball, Box
from gridlbc.systems.base import ControlAffineSystem

OUT = Path(__file__).parent / "strangers_round47_results"  # gitignored
SEED = 47
PI = math.pi
KINDS = [
    ("PointMass", "fe"),
    ("Pendulum", "hz"),
    ("Linear2", "hz"),
    ("Linear3", "fe"),
    ("River2", "fe"),
    ("PointMass", "hzfe"),
    ("Pendulum", "fe"),
    ("SI2", "hz"),
    ("Linear3", "hz"),
    ("River3", "hzfe"),
    ("Linear2", "fe"),
    ("PointMass", "hz"),
    ("Pendulum", "hzfe"),
    ("Linear2", "hzfe"),
    ("River2", "hz"),
    ("SI2", "fe"),
    ("PointMass", "fe"),
    ("River2", "hzfe"),
    # four more after the first 18, toward the exits (an exit set and a state 3 cells off it)
    ("PointMass", "hzfe"),
    ("River2", "fe"),
    ("Linear2", "hzfe"),
    ("SI2", "hzfe"),
]


def loguni(rng, a, b):
    return float(math.exp(rng.uniform(math.log(a), math.log(b))))


# ================= a user's own system ===========================================================
class River(ControlAffineSystem):
    """A channel flow along x0 (fastest at x1 = 0), restoring drift on the other axes, a gain on
    x0 that grows downstream: a(x) = (f (1 − (x1/L)²), −γ x1, −κ x2 + ε sin x0),
    B = diag(b0 (1 + ½ tanh x0), b1, b2)."""

    def __init__(self, d, flow, L, gamma, kappa, eps, b):
        self.state_dim = self.control_dim = int(d)
        self.flow, self.L, self.gamma, self.kappa, self.eps = flow, L, gamma, kappa, eps
        self.b = np.asarray(b, float)
        self.state_names = tuple(f"x{i}" for i in range(d))
        self.angle_axes = ()

    def drift(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        a = np.zeros_like(x)
        a[:, 0] = self.flow * (1.0 - np.minimum((x[:, 1] / self.L) ** 2, 4.0))
        a[:, 1] = -self.gamma * x[:, 1]
        if self.state_dim == 3:
            a[:, 2] = -self.kappa * x[:, 2] + self.eps * np.sin(x[:, 0])
        return a

    def input_matrix(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        g = np.tile(self.b, (len(x), 1))
        g[:, 0] *= 1.0 + 0.5 * np.tanh(x[:, 0])
        B = np.zeros((len(x), self.state_dim, self.state_dim))
        idx = np.arange(self.state_dim)
        B[:, idx, idx] = g
        return B

    def parameters(self):
        return dict(d=self.state_dim, flow=self.flow, L=self.L, b=self.b.tolist())


def make_system(sp):
    k, p = sp["kind"], sp["params"]
    if k == "PointMass":
        return S.PointMass(**p)
    if k == "Pendulum":
        return S.Pendulum(**p)
    if k.startswith("River"):
        return River(**p)
    return S.LinearSystem(np.asarray(p["A"]), np.asarray(p["B"]))


# ================= costs =========================================================================
class StateCost:
    """q(x) = s (c0 + Σ W_i (x − c)_i² [wrap-aware] + feature); feature "well": −D e^(−|x−cw|²/2w²)
    (q clipped ≥ 0.02 s c0), "ridge": H e^(−(x_k − c)²/2w²)."""

    def __init__(self, q, per, s):
        self.q, self.per, self.s = q, tuple(per), s

    def __call__(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        q = self.q
        d = x - np.asarray(q["c"])
        for i in self.per:
            d[:, i] = (d[:, i] + PI) % (2 * PI) - PI
        out = q["c0"] + d**2 @ np.asarray(q["W"])
        f = q.get("feat")
        if f and f["kind"] == "well":
            e = x - np.asarray(f["c"])
            for i in self.per:
                e[:, i] = (e[:, i] + PI) % (2 * PI) - PI
            out = out - f["D"] * np.exp(-0.5 * np.sum((e / np.asarray(f["w"])) ** 2, axis=1))
            out = np.maximum(out, 0.02 * q["c0"])
        elif f:
            out = out + f["H"] * np.exp(-0.5 * ((x[:, f["axis"]] - f["c"]) / f["w"]) ** 2)
        return self.s * out


class ExitCost:
    def __init__(self, e, s):
        self.e, self.s = e, s

    def __call__(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        e = self.e
        return self.s * (e["c0"] + e["a"] * (x[:, e["axis"]] - e["x0"]) ** 2)


def region(ex):
    if ex["kind"] == "ball":
        return Ball(ex["c"], ex["r"])
    return Box(ex["lo"], ex["hi"])


def in_region(ex, X, per=()):
    X = np.atleast_2d(np.asarray(X, float))
    if ex["kind"] == "ball":
        d = X - np.asarray(ex["c"])
        for i in per:
            d[:, i] = (d[:, i] + PI) % (2 * PI) - PI
        return np.sum((d / np.asarray(ex["r"])) ** 2, axis=1) <= 1.0
    lo, hi = np.asarray(ex["lo"]), np.asarray(ex["hi"])
    return np.all((lo <= X) & (hi >= X), axis=1)


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
    if kind in ("Linear2", "Linear3", "SI2"):
        d = 3 if kind == "Linear3" else 2
        if kind == "SI2":
            A, B = np.zeros((2, 2)), np.eye(2)
        else:
            A = rng.normal(0.0, 0.5, size=(d, d))
            A -= 0.3 * np.eye(d)  # mostly stable, as a user's model would be
            if rng.random() < 0.5:
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


def gen(rng, k):
    kind, ending = KINDS[k]
    par, box, per, m = system_draw(rng, kind)
    d = len(box)
    lo_n, hi_n = {2: (61, 121), 3: (25, 37)}[d]
    ns = [int(rng.integers(lo_n, hi_n + 1)) for _ in range(d)]
    ns = [n + n % 2 if i in per else n for i, n in enumerate(ns)]
    h = [(hi - lo) / (n - (0 if i in per else 1)) for i, ((lo, hi), n) in enumerate(zip(box, ns))]
    lam = loguni(rng, 0.5, 3.0)
    R = [loguni(rng, 0.1, 3.0) for _ in range(m)]
    # the goal: the upright for a pendulum, else a point in the inner half of the box
    goal = [0.0 if i in per else float(rng.uniform(-0.35, 0.35) * box[i][1]) for i in range(d)]
    if kind == "Pendulum":
        goal[1] = 0.0
    q = dict(
        c0=float(rng.uniform(0.2, 1.0)),
        c=goal,
        W=[float(loguni(rng, 0.02, 0.5) if rng.random() < 0.7 else 0.0) for _ in range(d)],
    )
    sharp = []
    u = rng.random()
    if u < 0.3:  # a narrow well of low cost (1–2 cells wide), between the middle and the goal
        w = [float(rng.uniform(1.0, 2.0)) * hh for hh in h]
        cw = [g + float(rng.uniform(-0.3, 0.3)) * box[i][1] for i, g in enumerate(goal)]
        q["feat"] = dict(kind="well", c=cw, w=w, D=0.95 * q["c0"])
        sharp.append("well")
    elif u < 0.45:
        ax = int(rng.choice([i for i in range(d) if i not in per]))
        w = float(rng.uniform(1.0, 2.0)) * h[ax]
        c = goal[ax] + float(rng.choice([-1, 1]) * rng.uniform(0.2, 0.4)) * box[ax][1]
        q["feat"] = dict(kind="ridge", axis=ax, c=c, w=w, H=float(rng.uniform(1.0, 4.0)))
        sharp.append("ridge")
    if m > 1 and max(R) / min(R) > 5:
        sharp.append("anisotropic noise")
    T = None if ending == "fe" else float(rng.uniform(1.0, 4.0))
    spec = dict(
        name=f"r47_{kind}_{ending}_{k:02d}",
        kind=kind,
        ending=ending,
        params=par,
        d=d,
        box=[[lo, hi, n] for (lo, hi), n in zip(box, ns)],
        periodic=per,
        lam=lam,
        R=R,
        T=T,
        q=q,
        goal=goal,
    )
    if T is not None:
        spec["g"] = dict(c=goal, W=[float(loguni(rng, 0.1, 2.0)) for _ in range(d)])
    spec["exit"] = None
    if ending != "hz":
        narrow = rng.random() < 0.35
        if narrow:
            cells = float(rng.uniform(2.0, 3.0))
            ex = dict(kind="ball", c=goal, r=[cells * hh for hh in h])
            sharp.append("narrow exit")
        elif rng.random() < 0.5:
            ex = dict(
                kind="ball",
                c=goal,
                r=[float(rng.uniform(0.08, 0.18)) * (2 * box[i][1]) for i in range(d)],
            )
        else:
            half = [float(rng.uniform(0.06, 0.15)) * (2 * box[i][1]) for i in range(d)]
            ex = dict(
                kind="box",
                lo=[g - w for g, w in zip(goal, half)],
                hi=[g + w for g, w in zip(goal, half)],
            )
        if rng.random() < 0.6:
            ex["cost"] = dict(kind="const", c0=float(rng.uniform(0.0, 0.5)))
        else:
            ex["cost"] = dict(
                kind="quad",
                c0=float(rng.uniform(0.0, 0.3)),
                a=float(rng.uniform(0.1, 1.0)),
                axis=int(rng.integers(d)),
                x0=goal[0],
            )
        spec["exit"] = ex
    spec["sharp"] = sharp
    # states: far (0.75 of the box from the goal), middle, near the goal
    sign = [float(rng.choice([-1, 1])) for _ in range(d)]
    far = [0.9 * PI * sign[i] if i in per else 0.75 * box[i][1] * sign[i] for i in range(d)]
    mid = [
        0.5 * (g + f) + float(rng.uniform(-0.1, 0.1)) * box[i][1]
        for i, (g, f) in enumerate(zip(goal, far))
    ]
    ax = int(rng.integers(d))
    near = list(goal)
    if spec["exit"] is None:
        near[ax] += 3.0 * h[ax] * sign[ax]
    else:
        ex = spec["exit"]
        reach = ex["r"][ax] if ex["kind"] == "ball" else ex["hi"][ax] - goal[ax]
        near[ax] += (reach + 3.0 * h[ax]) * sign[ax]
        # ≥ 2 cells from E along every axis
        for j in range(d):
            for s_ in (-1, 1):
                y = list(near)
                y[j] += s_ * 2.0 * h[j]
                assert not in_region(ex, [y], per)[0], spec["name"]
    spec["X"] = [far, mid, near]
    spec["target_frac"] = loguni(rng, 0.15, 0.8)  # v at the middle state / λ
    return spec


def draw():
    rng = np.random.default_rng(SEED)
    return {s["name"]: s for s in (gen(rng, k) for k in range(len(KINDS)))}


# ================= building ======================================================================
def make_grid(box, per, scale=1.0):
    axes = []
    for i, (lo, hi, n) in enumerate(box):
        p = i in per
        if scale != 1.0:
            n = round(n * scale) if p else round((n - 1) * scale) + 1
            n += n % 2 if p else 0
        axes.append(Axis(lo, hi, n, periodic=p))
    return Grid(axes)


def build(sp, s=None, scale=1.0):
    s = sp.get("scale", 1.0) if s is None else s
    per = tuple(sp["periodic"])
    kw = {}
    if sp["exit"] is not None:
        c = sp["exit"]["cost"]
        kw = dict(
            exit=region(sp["exit"]),
            exit_cost=s * c["c0"] if c["kind"] == "const" else ExitCost(c, s),
        )
    T = sp["T"]
    return Problem(
        make_system(sp),
        make_grid(sp["box"], per, scale),
        T,
        terminal_cost=None if T is None else Quadratic(sp["g"]["c"], s * np.asarray(sp["g"]["W"])),
        state_cost=StateCost(sp["q"], per, s),
        control_cost=np.diag(sp["R"]),
        temperature=sp["lam"],
        **kw,
    )


def calibrate(sp):
    """The cost factor s with v(middle) ≈ target_frac λ, by a few solves on a grid half as fine
    (error estimate off); secant on log s, v ≈ c s^p."""
    target = sp["target_frac"] * sp["lam"]
    xm = np.asarray([sp["X"][1]], float)
    hist = []
    s = 1.0
    for _ in range(4):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sol = gridlbc.solve(build(sp, s=s, scale=0.6), error_estimate=False, progress=False)
            v = float(np.asarray(sol.value(xm))[0])
        hist.append((s, v))
        if abs(math.log(v / target)) < math.log(1.25):
            break
        if len(hist) == 1:
            p = 1.0
        else:
            (s1, v1), (s2, v2) = hist[-2], hist[-1]
            p = math.log(v2 / v1) / math.log(s2 / s1) if s1 != s2 else 1.0
            p = min(max(p, 0.3), 1.5)
        s = s * (target / v) ** (1.0 / p)
    return s, hist


# ================= run ===========================================================================
def gw(w):
    return [
        dict(category=x.category.__name__, message=str(x.message)[:500])
        for x in w
        if issubclass(x.category, gridlbc.GridlbcWarning)
    ]


BAD = (
    "heavy tail",
    "had not reached",
    "not yet of first order",
    "effective sample size",
    "never visited",
    "not a gridlbc.regions",
)


def distrusted(cw, X):
    """Which states a CertificateWarning of the kinds in BAD names (all, where it names none)."""
    out = np.zeros(len(X), bool)
    for c in cw:
        m = c["message"]
        if not any(b in m for b in BAD):
            continue
        if "had not reached" in m and "so v* is not" in m:
            continue  # unexited weight negligible
        hit = re.search(r"x0 = \[([-0-9.e, ]+)\]", m)
        if hit is None:
            out[:] = True
            continue
        y = np.array([float(t) for t in re.split(r"[,\s]+", hit.group(1).strip())])
        if len(y) != X.shape[1]:
            out[:] = True
            continue
        out[int(np.argmin(np.sum((X - y) ** 2, axis=1)))] = True
    return out


def fine_scale(sp):
    n = np.prod([b[2] for b in sp["box"]])
    return 2.0 if n * 2 ** sp["d"] <= 3e5 else 1.5


def certify_kw(sp):
    if sp["T"] is None:
        return dict(dt=0.005, max_time=300.0)
    return dict(dt=sp["T"] / 160)


def run(name, sp):
    OUT.mkdir(parents=True, exist_ok=True)
    X = np.asarray(sp["X"], float)
    lam = sp["lam"]
    t0 = time.perf_counter()
    s, hist = calibrate(sp)
    sp = dict(sp, scale=s, calibration=hist)
    t_cal = time.perf_counter() - t0
    p = build(sp)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        sol = gridlbc.solve(p, progress=False)
        secs = time.perf_counter() - t0
        v = np.asarray(sol.value(X), float)
        e = np.asarray(sol.error_estimate(X), float)
    wl = gw(w)
    stray = [
        f"{x.category.__name__}: {str(x.message)[:200]}"
        for x in w
        if not issubclass(x.category, gridlbc.GridlbcWarning)
    ]
    t1 = time.perf_counter()
    sc = fine_scale(sp)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        kw = {} if sp["T"] is None else dict(dt=float(sol.diagnostics.dt) / 2)
        fine = gridlbc.solve(build(sp, scale=sc), error_estimate=False, progress=False, **kw)
        v_fine = np.asarray(fine.value(X), float)
    t_fine = time.perf_counter() - t1
    t1 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w2:
        warnings.simplefilter("always")
        c = gridlbc.certify(
            p, fine.policy, X, 2000, seed=SEED, richardson=True, progress=False, **certify_kw(sp)
        )
    t_cert = time.perf_counter() - t1
    cw = gw(w2)
    vt = np.asarray(c.extrapolated_value, float)
    se = np.asarray(c.extrapolated_value_se, float)
    ess = np.asarray(c.effective_sample_size, float)
    kh = np.asarray(c.pareto_k, float)
    bad = distrusted(cw, X)
    trusted = (ess >= 100) & (kh <= 0.7) & ~bad & np.isfinite(vt)
    rec = dict(
        name=name,
        spec=sp,
        shape=list(p.grid.shape),
        fine_scale=sc,
        seconds=dict(calibrate=t_cal, solve=secs, fine=t_fine, certify=t_cert),
        warnings=wl,
        warned=bool(wl),
        stray=stray,
        v=v.tolist(),
        est=e.tolist(),
        v_fine=v_fine.tolist(),
        truth=vt.tolist(),
        se=se.tolist(),
        v_dt=np.asarray(c.optimal_value).tolist(),
        ess=ess.tolist(),
        khat=kh.tolist(),
        unexited=np.atleast_1d(np.asarray(c.unexited_fraction, float)).tolist(),
        proposals=list(c.proposals),
        cert_warnings=cw,
        trusted=trusted.tolist(),
    )
    (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
    print(
        f"{name:24s} {tuple(p.grid.shape)!s:14s} λ={lam:.3g} T={sp['T']} s={s:.3g} "
        f"solve {secs:.1f}s fine {t_fine:.0f}s cert {t_cert:.0f}s warned={bool(wl)}"
    )
    for i in range(len(X)):
        ev = (v[i] - vt[i]) / abs(vt[i])
        el = (v[i] - vt[i]) / max(abs(vt[i]), lam)
        print(
            f"    x{i} v={v[i]:.4g} v*={vt[i]:.4g}±{se[i]:.2g} ess={ess[i]:.0f} k={kh[i]:.2f} "
            f"err_v={ev:+.1%} err_λ={el:+.1%} ê={e[i]:.3g} fine={v_fine[i]:.4g} "
            f"trusted={trusted[i]}"
        )
    for x in wl:
        print("    warn:", x["category"], x["message"][:200])
    for x in cw:
        print("    cert:", x["category"], x["message"][:200])
    return rec


# ================= classification, diagnosis, table ==============================================
def recheck(name):
    """The truth again: seed 48 and half the SDE step (the silent pairs' v* checked)."""
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    sp = rec["spec"]
    X = np.asarray(sp["X"], float)
    p = build(sp)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = gridlbc.solve(p, error_estimate=False, progress=False)
        kw = {} if sp["T"] is None else dict(dt=float(sol.diagnostics.dt) / 2)
        fine = gridlbc.solve(
            build(sp, scale=rec["fine_scale"]), error_estimate=False, progress=False, **kw
        )
    ck = certify_kw(sp)
    ck["dt"] /= 2
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        c = gridlbc.certify(
            p, fine.policy, X, 2000, seed=SEED + 1, richardson=True, progress=False, **ck
        )
    rec["recheck"] = dict(
        dt=ck["dt"],
        seed=SEED + 1,
        truth=np.asarray(c.extrapolated_value).tolist(),
        se=np.asarray(c.extrapolated_value_se).tolist(),
        ess=np.asarray(c.effective_sample_size).tolist(),
        khat=np.asarray(c.pareto_k).tolist(),
        cert_warnings=gw(w),
    )
    f.write_text(json.dumps(rec, indent=1, default=float))
    print_recheck(rec)


def print_recheck(rec):
    rc = rec.get("recheck")
    if not rc:
        return
    txt = ", ".join(
        f"x{i} {t:.4g}±{s:.2g} (first {v:.4g})"
        for i, (t, s, v) in enumerate(zip(rc["truth"], rc["se"], rec["truth"]))
    )
    print(
        f"   RECHECK seed {rc['seed']} dt {rc['dt']:.3g}: {txt}; warned {len(rc['cert_warnings'])}"
    )


def pairs(rec):
    """Per state: the numbers and the flags OFF, SILENT, LAMQUIET (OFF but |err_λ| < 5 %), UNDER."""
    lam = rec["spec"]["lam"]
    out = []
    for i in range(len(rec["v"])):
        v, vt, se, e = rec["v"][i], rec["truth"][i], rec["se"][i], rec["est"][i]
        ev = (v - vt) / abs(vt)
        el = (v - vt) / max(abs(vt), lam)
        off = rec["trusted"][i] and abs(ev) > 0.10
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
                trusted=rec["trusted"][i],
                small=abs(vt) < lam,
                OFF=bool(off),
                SILENT=bool(off and not rec["warned"]),
                LAMQUIET=bool(off and abs(el) < 0.05),
                UNDER=bool(rec["trusted"][i] and dev > 0 and e < 0.5 * abs(v - vt)),
            )
        )
    return out


def diagnose(name):
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    sp = rec["spec"]
    X = np.asarray(sp["X"], float)
    todo = [p["i"] for p in pairs(rec) if p["SILENT"] or p["LAMQUIET"]]
    if not todo:
        print(name, "nothing to diagnose")
        return
    dg = dict(states=todo)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s2 = gridlbc.solve(build(sp, scale=2.0), progress=False)
        dg["fine2_v"] = np.asarray(s2.value(X), float).tolist()
        dg["fine2_est"] = np.asarray(s2.error_estimate(X), float).tolist()
    dg["fine2_warnings"] = gw(w)
    dg["fine2_seconds"] = time.perf_counter() - t0
    dg["tol"] = []
    for i in todo:
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            try:
                st = gridlbc.solve(
                    build(sp), tol=0.05, states=[X[i]], max_seconds=120, progress=False
                )
                vv = float(np.asarray(st.value(X[i : i + 1]))[0])
                ee = float(np.asarray(st.error_estimate(X[i : i + 1]))[0])
                ref = getattr(st, "refinement", None) or []
                met = bool(ref[-1].met(0.05)) if ref else None
                shape = list(st.grid.shape)
                fail = None
            except Exception as ex:
                vv = ee = float("nan")
                met, shape, fail = None, None, f"{type(ex).__name__}: {ex}"[:300]
        dg["tol"].append(
            dict(
                i=i,
                v=vv,
                est=ee,
                met=met,
                shape=shape,
                fail=fail,
                warnings=gw(w),
                seconds=time.perf_counter() - t0,
            )
        )
    rec["diagnosis"] = dg
    f.write_text(json.dumps(rec, indent=1, default=float))
    print_diag(rec)


def tight_tol(name, i=2):
    """``solve(tol=0.05 |v*| / λ, states=[x_i])``: 5 % of v* asked in λ's units."""
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text())
    sp = rec["spec"]
    vt = rec["truth"][i]
    x = np.asarray([sp["X"][i]], float)
    tol = 0.05 * abs(vt) / sp["lam"]
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        st = gridlbc.solve(build(sp), tol=tol, states=x, max_seconds=120, progress=False)
    v, e = float(st.value(x)[0]), float(st.error_estimate(x)[0])
    rounds = [(list(r.shape), float(r.error), r.reason[:60]) for r in st.refinement]
    rec.setdefault("diagnosis", {})["tight_tol"] = dict(
        tol=tol,
        v=v,
        est=e,
        rounds=rounds,
        seconds=time.perf_counter() - t0,
        warnings=[
            str(y.message)[:300] for y in w if issubclass(y.category, gridlbc.GridlbcWarning)
        ],
    )
    f.write_text(json.dumps(rec, indent=1, default=float))
    print(
        f"{name} x{i} tol={tol:.4g}: v={v:.5g} v*={vt:.5g} err_v={(v - vt) / abs(vt):+.1%} ê={e:.3g}"
    )


def print_diag(rec):
    dg = rec.get("diagnosis")
    if not dg:
        return
    vt = rec["truth"]
    print(f"   DIAG 2× grid ({dg['fine2_seconds']:.0f}s, warned={bool(dg['fine2_warnings'])}):")
    for i in dg["states"]:
        v2, e2 = dg["fine2_v"][i], dg["fine2_est"][i]
        print(f"     x{i}: v={v2:.4g} ({(v2 - vt[i]) / abs(vt[i]):+.1%}) ê={e2:.3g}")
    for t in dg["tol"]:
        i = t["i"]
        print(
            f"     tol=0.05 x{i}: v={t['v']:.4g} ({(t['v'] - vt[i]) / abs(vt[i]):+.1%}) "
            f"ê={t['est']:.3g} met={t['met']} shape={t['shape']} {t['seconds']:.0f}s "
            f"fail={t['fail']}"
        )
        for x in t["warnings"]:
            print("       warn:", x["category"], x["message"][:120])
    tt = dg.get("tight_tol")
    if tt:
        print(
            f"     tol={tt['tol']:.3g} (5 % of v* in λ's units) x2: v={tt['v']:.4g} "
            f"({(tt['v'] - vt[2]) / abs(vt[2]):+.1%}) ê={tt['est']:.3g} last round "
            f"{tt['rounds'][-1][:2]} warned={bool(tt['warnings'])}"
        )


def table():
    recs = [json.loads(f.read_text()) for f in sorted(OUT.glob("*.json"))]
    allp, flagged = [], []
    for r in recs:
        sp = r["spec"]
        sec = r["seconds"]
        wtxt = "; ".join(f"{x['category']}: {x['message'][:80]}" for x in r["warnings"]) or "-"
        print(
            f"{r['name']} {r['shape']} λ={sp['lam']:.3g} T={sp['T']} sharp={sp['sharp']} "
            f"solve {sec['solve']:.1f}s fine {sec['fine']:.0f}s cert {sec['certify']:.0f}s"
        )
        print(f"   warned: {wtxt}")
        for x in r["cert_warnings"]:
            print(f"   cert: {x['message'][:120]}")
        for p in pairs(r):
            i = p["i"]
            tags = [k for k in ("OFF", "SILENT", "LAMQUIET", "UNDER") if p[k]]
            print(
                f"   x{i} v={p['v']:.4g} v*={p['vt']:.4g}±{p['se']:.2g} "
                f"ESS={r['ess'][i]:.0f} k={r['khat'][i]:.2f} err_v={p['ev']:+.1%} "
                f"err_λ={p['el']:+.1%} ê={p['e']:.3g} (ê/|v*| {p['e_rel']:.1%}) "
                f"v*/λ={p['vt'] / sp['lam']:.2f} trusted={p['trusted']} {' '.join(tags)}"
            )
            allp.append(p)
            if tags:
                flagged.append((r, p, tags, wtxt))
        print_diag(r)
        print_recheck(r)
    n = len(allp)
    tr = [p for p in allp if p["trusted"]]
    print(
        f"\nproblems {len(recs)}, pairs {n}, trusted {len(tr)}, "
        f"trusted with v* < λ {sum(p['small'] for p in tr)}"
    )
    for k in ("OFF", "SILENT", "LAMQUIET", "UNDER"):
        print(f"{k}: {sum(p[k] for p in allp)}")
    print(f"warned problems {sum(r['warned'] for r in recs)} of {len(recs)}")
    print("\nflagged pairs (name x: v, v*, err_v, err_λ, ê, ê/|v*|, tags, warned):")
    for r, p, tags, wtxt in flagged:
        print(
            f"  {r['name']} x{p['i']}: {p['v']:.4g} {p['vt']:.4g} {p['ev']:+.1%} {p['el']:+.1%} "
            f"{p['e']:.3g} {p['e_rel']:.1%} {'/'.join(tags)} | {wtxt[:80]}"
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
    elif "--diagnose" in argv:
        names = argv[argv.index("--diagnose") + 1 :] or [f.stem for f in sorted(OUT.glob("*.json"))]
        for n in names:
            diagnose(n)
    elif "--tighttol" in argv:
        for n in argv[argv.index("--tighttol") + 1 :]:
            tight_tol(n)
    elif "--recheck" in argv:
        for n in argv[argv.index("--recheck") + 1 :]:
            recheck(n)
    elif "--table" in argv:
        table()
    else:
        print(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
