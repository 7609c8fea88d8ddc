"""Stranger round 37: extremes of TIME and SCALE, posed with the public API only (SPEC §1, §6, §9–10).

RESULTS (library of main 46de7f5, worktree r37, 2026-12-07, one thread, ``--run`` then
``--tol`` then ``--table``; 77 problems run, 74 counted):

- 423 counted (problem, state, t) pairs (t = 0 and 0.9 T), 21 more flagged as wall pairs (a box
  1.5× wider at the same spacing and Δt moves v by more than a quarter of the error: the
  free-space Riccati is not their truth) and not counted. No crash. No UnderflowWarning anywhere
  and ``diagnostics.underflow_nodes`` = 0 in every solve, also at v/λ up to ~10⁴
  (``long_pm_T50_l0.001`` 7400, ``cost_offset1000`` 10⁴, ``cost_si_s1000`` 3900): right or
  warned by ResolutionWarning.
- > 10 % off: 94 pairs in 27 problems, every one warned. SILENT (> 10 %, no GridlbcWarning): 0.
- under-reads in warned solves (ê < ½ |v − v*|, err > 2 %): 4, all ``wall_goal_a100_q0_g10000_41``
  (drift +100 pressing into the wall at x0 = 0.2 where g = 10⁴ (x0 − 0.2)² is centred, λ 1,
  41², a boundary layer λ/(2a) = 0.005 of half a cell): v 1.085 vs 0.3216 (76 % of λ), ê 29 %,
  at the states (0.2, 0.05) and (−0.195, −0.195), t = 0 and 1.8 (ê 126 % at the origin).
- 3 LQ boxes with an unstable axis (``mixed_unstable_r*``: rates 100 / 10 beside −0.1, box ±3) are
  50–98 % off the FREE-SPACE Riccati and two are quiet, but that is the walls: the same problems
  judged against the reflected truth (``refl_unstable_r*``, separable: round 25's 1-D FD) are
  within 1.1 %, 4.0 % and 5.1 % (ê 5.1 % at the 5.1 % pair); they are not counted. A teacher
  comparing with Riccati gets no hint that the box, not the grid, made v 5× smaller.
- unwarned problems (13): largest error 5.1 % (``refl_unstable_r10_l2``, ê 5.1 %); the wall
  layers ``wall_drift_*`` (λ ≥ 0.5) are 3.4–4.3 % low with ê 2–4 %; the corner press
  ``corner_a50_g0`` 2.7 % with ê 1.8–2.3 %.
- false warnings (warned, every pair < 2 %): 23 of 74 — every long-horizon point mass and
  oscillator (T 20–1000), the stiff LQs, the scaled copies and the tiny boxes; nearly all name a
  state near the goal at t ≈ T − Δt.
- absurd over-reads on huge boxes: ``huge_si_L*`` (±50–±100, h = 0.5–1, goal exp(−16|x − c|²),
  λ 0.5–5, T 20–50) are exact at t = 0 (errors ≤ 0.4 % at the 3 states, 0.00 % at most) while
  ê reads 10⁴–10⁶ % of v there (e.g. 53520 % at (40, −20), λ 2, where v = v* = 62.05). The
  default step there is T/10 (Δt = 2 and 5, 10 steps), and at t = 0.9 T (one step before the end)
  v is 20–32 % high at the far states (warned).
- scale invariance holds to the printed digits: the same point-mass task with space scaled by
  10⁻⁶ / 10⁶ and time by 10⁻⁴ / 10⁴ (T = 5·10⁻⁴ … 5·10⁴) gives identical v, ê, warnings
  (17 steps each).
- tol = 0.02 (states = the 3, times = 0 and 0.9 T, max_seconds = 90): ``short_mid_W100_l0.3_41``
  met on 321² at Δt 6.25e−5 (errors < 0.003 %); three said they stopped on the time budget with
  the estimate reached: ``wall_goal_a100_q0_g1000_41`` (refined Δt only, 41² kept: 22 % → 10.9 %
  off, estimate 11.2 %), ``cost_pm_s1000`` (321², 218.7 % estimated; errors 0.2–22 %, the 22 % at
  a wall-flagged far state), ``huge_si_201_l0.1`` (401², 326 % estimated; t = 0 exact, 5.9 % at
  t = 4.5). Met-but-off: none.

Default-solve findings by family (worst error, warned?): very long horizons are accurate
(≤ 1.8 % on 31²–121², 4.5 % on 21², T up to 1000, Δt 0.19–1.15, up to 1691 steps) and over-warned;
very short horizons with a steep g off the nodes are 13–2450 % off next to the goal on 41²–121²
and always warned (201² at λ = 2 is right and quiet); the huge box (±50, goal 100× smaller) is 5 %,
352 % (λ 0.1) and 129 % (point mass) off, warned; tiny reflected boxes are within 0.6 %; g, q ×1000
is 12–17 % off (warned, the splitting message "control moves the state by 86–117 cells per step");
stiff rate-100 axes (stable, coupled, actuator lags) within 3.5 %, the 3-D lagged point mass 16 %
(warned) and the ω = 20 oscillator 22–67 % (warned, partly walls).

Families (``--list`` prints every problem's definition):

1. ``long_*``: horizons of 20–100 against dynamics whose time scale is about 1 (point mass,
   damped oscillator, unstable spiral, stable 2-D LQ at small λ), with and without a terminal cost
   that matters. Truth: Riccati (SPEC §6), imported from round 25.
2. ``short_*``: horizons of 0.001–0.05 with a steep quadratic terminal cost off the nodes,
   λ 0.01–2, 41²–201². Truth: Riccati.
3. ``huge_*``: a box 100× the goal's width; ``tiny_*``: a box a few noise lengths wide, where the
   reflecting walls matter. Tiny boxes are separable (diagonal A, B, R, W) and posed as
   ``LinearSystem`` + ``Quadratic``; their truth is round 25's 1-D reflected finite differences
   (``sep_truth``) of the SAME reflected problem (free-space Riccati recorded beside it as
   ``riccati_free``, not used as the truth).
4. ``cost_*``: g and q scaled by 10⁻³ … 10³ at fixed λ = 0.1 (v/λ up to ~10⁴), and a constant
   offset of 1000 in g (callable). Truth: Riccati (+ offset).
5. ``mixed_*``: a stiff axis (rate 100) beside a slow one (0.1) in 2-D/3-D LQ; a fast oscillator
   (ω = 20) with a slow goal. Truth: Riccati.

LQ problems more than 5 % off somewhere are re-solved on a box 1.5× wider at the same spacing and
Δt (``wall``): pairs where that moves v by more than a quarter of the error are flagged as wall
pairs (the free-space Riccati is not their truth) and not counted.

Per problem 3 states (typical, near the goal/feature, far) at t = 0 and t = 0.9 T. Errors relative
to max(|v*|, λ), the estimate relative to max(|v|, λ).

    cd /work/main && PYTHONPATH=/work/wt-r37 NUMBA_NUM_THREADS=1 \\
        python benchmarks/holdout/strangers_round37.py --list | --run [NAMES] | --tol NAMES | --table
"""

from __future__ import annotations

import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from strangers_round25 import build_sep, lq_value, sep_truth

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import LinearSystem, PointMass

OUT = Path("/work/main/benchmarks/holdout/strangers_round37_results")  # gitignored there
TOL = 0.02

PM_A = [[0.0, 1.0], [0.0, 0.0]]
PM_B = [[0.0], [1.0]]
I2 = [[1.0, 0.0], [0.0, 1.0]]
Z2 = [[0.0, 0.0], [0.0, 0.0]]


def diag(*v):
    return np.diag(v).tolist()


def lq(name, A, B, R, Wq, cq, WT, cT, lam, T, box, X, pm=False, offset=0.0, note=""):
    return dict(
        family="lq",
        name=name,
        A=A,
        B=B,
        R=R,
        Wq=Wq,
        cq=cq,
        WT=WT,
        cT=cT,
        lam=lam,
        T=T,
        box=box,
        X=X,
        pm=pm,
        offset=offset,
        note=note,
    )


def tiny(name, a, wq, cq, wt, ct, lam, T, box, X, note="", a0=None):
    """Separable reflected LQ: ẋᵢ = aᵢ xᵢ + uᵢ, q = Σ wqᵢ (xᵢ − cqᵢ)², g = Σ wtᵢ (xᵢ − ctᵢ)²."""
    return dict(
        family="tiny",
        name=name,
        a=a,
        wq=wq,
        cq=cq,
        wt=wt,
        ct=ct,
        lam=lam,
        T=T,
        box=box,
        X=X,
        note=note,
        a0=a0,
    )


def problems():
    P = {}

    def add(s):
        P[s["name"]] = s

    # ---- 1. very long horizons ----------------------------------------------------------------
    for T in (20.0, 50.0, 100.0):
        add(
            lq(
                f"long_pm_T{int(T)}",
                PM_A,
                PM_B,
                [[1.0]],
                diag(1.0, 0.1),
                [0.0, 0.0],
                I2,
                [1.0, 0.0],
                0.5,
                T,
                [(-4, 4, 81), (-4, 4, 81)],
                [[-1.5, 1.0], [0.05, 0.05], [3.2, -3.0]],
                pm=True,
                note="point mass, q = x² + 0.1 v², g = |x − (1,0)|², λ 0.5",
            )
        )
    add(
        lq(
            "long_pm_T100_noterm",
            PM_A,
            PM_B,
            [[1.0]],
            diag(1.0, 0.1),
            [0.0, 0.0],
            Z2,
            [0.0, 0.0],
            0.5,
            100.0,
            [(-4, 4, 81), (-4, 4, 81)],
            [[-1.5, 1.0], [0.05, 0.05], [3.2, -3.0]],
            pm=True,
            note="no terminal cost (average-cost regime)",
        )
    )
    add(
        lq(
            "long_pm_T100_bigterm",
            PM_A,
            PM_B,
            [[1.0]],
            diag(0.2, 0.05),
            [0.0, 0.0],
            diag(10.0, 10.0),
            [2.0, 0.0],
            0.5,
            100.0,
            [(-4, 4, 81), (-4, 4, 81)],
            [[-1.5, 1.0], [2.0, 0.0], [3.2, -3.0]],
            pm=True,
            note="steep terminal goal off the running-cost centre",
        )
    )
    add(
        lq(
            "long_osc_T50",
            [[0.0, 1.0], [-1.0, -0.2]],
            PM_B,
            [[1.0]],
            diag(0.5, 0.5),
            [0.5, 0.0],
            diag(2.0, 2.0),
            [-1.0, 0.0],
            0.3,
            50.0,
            [(-4, 4, 101), (-4, 4, 101)],
            [[1.0, -1.0], [-1.0, 0.0], [-3.3, 3.3]],
            note="lightly damped oscillator ω = 1",
        )
    )
    add(
        lq(
            "long_unstable_T20",
            [[0.3, 1.0], [-1.0, 0.3]],
            I2,
            I2,
            I2,
            [0.0, 0.0],
            I2,
            [0.5, 0.5],
            1.0,
            20.0,
            [(-4, 4, 61), (-4, 4, 61)],
            [[1.0, -1.0], [0.5, 0.5], [-3.3, 3.3]],
            note="unstable spiral (rate +0.3), fully actuated",
        )
    )
    add(
        lq(
            "long_smalllam_T50",
            [[-0.2, 0.0], [0.0, -0.2]],
            I2,
            I2,
            diag(1.0, 0.3),
            [0.5, -0.5],
            I2,
            [0.0, 0.0],
            0.05,
            50.0,
            [(-3, 3, 121), (-3, 3, 121)],
            [[-1.0, 1.0], [0.5, -0.5], [2.8, 2.8]],
            note="stable 2-D, λ 0.05",
        )
    )
    # ---- 2. very short horizons ---------------------------------------------------------------
    A0 = Z2
    for nm, T, lam, W, n, L in (
        ("short_T0.001_l0.01_41", 0.001, 0.01, 100.0, 41, 2.0),
        ("short_T0.001_l2_201", 0.001, 2.0, 50.0, 201, 1.0),
        ("short_T0.01_l0.1_81", 0.01, 0.1, 100.0, 81, 2.0),
        ("short_T0.05_l2_201", 0.05, 2.0, 1000.0, 201, 1.0),
        ("short_T0.05_l0.01_121", 0.05, 0.01, 30.0, 121, 2.0),
    ):
        c = [0.13 * L / 2, -0.07 * L / 2]
        add(
            lq(
                nm,
                A0,
                I2,
                I2,
                Z2,
                [0.0, 0.0],
                diag(W, W),
                c,
                lam,
                T,
                [(-L, L, n), (-L, L, n)],
                [[0.4 * L, -0.3 * L], [c[0] + 0.011, c[1] - 0.007], [-0.9 * L, 0.85 * L]],
                note=f"2-D single integrator, g = {W}|x − c|², c off the nodes",
            )
        )
    add(
        lq(
            "short_pm_T0.01",
            PM_A,
            PM_B,
            [[1.0]],
            Z2,
            [0.0, 0.0],
            diag(100.0, 10.0),
            [0.33, -0.21],
            0.5,
            0.01,
            [(-3, 3, 101), (-3, 3, 101)],
            [[1.0, 1.0], [0.35, -0.2], [-2.7, 2.7]],
            pm=True,
            note="point mass, steep g",
        )
    )
    # ---- 3. huge and tiny boxes ---------------------------------------------------------------
    add(
        lq(
            "huge_si_101",
            Z2,
            I2,
            I2,
            diag(0.001, 0.001),
            [0.0, 0.0],
            diag(16.0, 16.0),
            [0.3, -0.2],
            1.0,
            10.0,
            [(-50, 50, 101), (-50, 50, 101)],
            [[20.0, -10.0], [0.3, -0.2], [42.0, 40.0]],
            note="box ±50 (h = 1), goal exp(−16|x−c|²) of width ~0.25",
        )
    )
    add(
        lq(
            "huge_si_201_l0.1",
            Z2,
            I2,
            I2,
            Z2,
            [0.0, 0.0],
            diag(16.0, 16.0),
            [0.3, -0.2],
            0.1,
            5.0,
            [(-50, 50, 201), (-50, 50, 201)],
            [[20.0, -10.0], [0.3, -0.2], [42.0, 40.0]],
            note="box ±50 (h = 0.5), λ 0.1, no running cost",
        )
    )
    add(
        lq(
            "huge_pm_201",
            PM_A,
            PM_B,
            [[1.0]],
            diag(0.01, 0.0),
            [0.0, 0.0],
            diag(25.0, 1.0),
            [0.2, 0.0],
            0.5,
            8.0,
            [(-40, 40, 201), (-20, 20, 101)],
            [[15.0, -3.0], [0.2, 0.0], [-30.0, 10.0]],
            pm=True,
            note="point mass, position box 100× the goal width",
        )
    )
    add(
        tiny(
            "tiny_si_41",
            [0.0, 0.0],
            [1.0, 0.5],
            [0.1, 0.0],
            [5.0, 2.0],
            [-0.1, 0.2],
            1.0,
            2.0,
            [(-0.3, 0.3, 41), (-0.3, 0.3, 41)],
            [[0.25, -0.25], [-0.1, 0.2], [0.29, 0.29]],
            note="box ±0.3, noise length √(λT) = 1.4",
        )
    )
    add(
        tiny(
            "tiny_unstable_61",
            [2.0, -1.0],
            [1.0, 1.0],
            [0.0, 0.0],
            [10.0, 10.0],
            [0.05, 0.0],
            0.5,
            5.0,
            [(-0.2, 0.2, 61), (-0.2, 0.2, 61)],
            [[0.15, -0.1], [0.05, 0.0], [-0.19, 0.19]],
            note="unstable axis rate 2 beside a stable one, box ±0.2",
        )
    )
    add(
        tiny(
            "tiny_smalllam_81",
            [0.0, -0.5],
            [0.0, 2.0],
            [0.0, 0.3],
            [20.0, 0.0],
            [0.2, 0.0],
            0.02,
            1.0,
            [(-0.3, 0.3, 81), (-0.3, 0.3, 81)],
            [[-0.25, 0.1], [0.2, 0.3], [-0.29, -0.29]],
            note="λ 0.02, box ±0.3 (noise length 0.14)",
        )
    )
    # ---- 4. cost magnitudes -------------------------------------------------------------------
    for s in (1e-3, 1e-1, 10.0, 1e3):
        add(
            lq(
                f"cost_pm_s{s:g}",
                PM_A,
                PM_B,
                [[1.0]],
                diag(s, 0.1 * s),
                [0.0, 0.0],
                diag(s, s),
                [0.5, 0.0],
                0.1,
                2.0,
                [(-3, 3, 81), (-3, 3, 81)],
                [[-1.5, 1.0], [0.5, 0.0], [2.7, -2.7]],
                pm=True,
                note=f"point mass, q and g scaled by {s:g}, λ 0.1",
            )
        )
    add(
        lq(
            "cost_si_s1000",
            Z2,
            I2,
            I2,
            diag(1e3, 1e3),
            [0.0, 0.0],
            diag(1e3, 1e3),
            [0.5, -0.5],
            0.1,
            1.0,
            [(-3, 3, 81), (-3, 3, 81)],
            [[-1.5, 1.0], [0.5, -0.5], [2.7, -2.7]],
            note="2-D single integrator, q and g ×1000, λ 0.1 (v/λ ~ 1e5 far)",
        )
    )
    add(
        lq(
            "cost_offset1000",
            PM_A,
            PM_B,
            [[1.0]],
            diag(1.0, 0.1),
            [0.0, 0.0],
            I2,
            [0.5, 0.0],
            0.1,
            2.0,
            [(-3, 3, 81), (-3, 3, 81)],
            [[-1.5, 1.0], [0.5, 0.0], [2.7, -2.7]],
            pm=True,
            offset=1000.0,
            note="g = 1000 + |x − c|² (callable), λ 0.1: v/λ ≈ 1e4 everywhere",
        )
    )
    # ---- 5. mixed time scales -----------------------------------------------------------------
    add(
        lq(
            "mixed_stiff2",
            diag(-100.0, -0.1),
            I2,
            I2,
            I2,
            [0.5, 0.5],
            I2,
            [-0.5, 1.0],
            0.5,
            5.0,
            [(-3, 3, 81), (-3, 3, 81)],
            [[1.0, -1.0], [-0.5, 1.0], [2.8, -2.8]],
            note="rates 100 and 0.1, fully actuated",
        )
    )
    add(
        lq(
            "mixed_stiff_coupled",
            [[-100.0, 100.0], [0.0, -0.1]],
            [[0.0], [1.0]],
            [[1.0]],
            diag(1.0, 0.1),
            [0.0, 0.0],
            diag(2.0, 0.5),
            [1.0, 1.0],
            0.5,
            5.0,
            [(-3, 3, 81), (-3, 3, 81)],
            [[-1.0, 0.5], [1.0, 1.0], [2.8, -2.8]],
            note="x0 stiffly slaved to x1 (rate 100), control on the slow axis",
        )
    )
    add(
        lq(
            "mixed_stiff3",
            diag(-100.0, -1.0, -0.1),
            np.eye(3).tolist(),
            np.eye(3).tolist(),
            np.eye(3).tolist(),
            [0.5, 0.0, -0.5],
            np.eye(3).tolist(),
            [-0.5, 0.5, 1.0],
            0.5,
            3.0,
            [(-3, 3, 41)] * 3,
            [[1.0, -1.0, 0.5], [-0.5, 0.5, 1.0], [2.8, -2.8, 2.8]],
            note="3-D, rates 100, 1, 0.1",
        )
    )
    for T in (5.0, 20.0):
        add(
            lq(
                f"mixed_fastosc_T{int(T)}",
                [[0.0, 1.0], [-400.0, 0.0]],
                PM_B,
                [[1.0]],
                diag(0.5, 0.0),
                [0.0, 0.0],
                diag(2.0, 0.0),
                [1.0, 0.0],
                0.5,
                T,
                [(-3, 3, 81), (-40, 40, 81)],
                [[0.5, 5.0], [1.0, 0.0], [-2.5, 30.0]],
                note="oscillator ω = 20, slow goal x0 → 1",
            )
        )
    # ---- round-2 pushes: coarse long horizons, scaled copies, thin wall layers ----------------
    for T, n in ((100.0, 31), (100.0, 21), (1000.0, 41)):
        add(
            lq(
                f"long_pm_T{int(T)}_{n}",
                PM_A,
                PM_B,
                [[1.0]],
                diag(1.0, 0.1),
                [0.0, 0.0],
                I2,
                [1.0, 0.0],
                0.5,
                T,
                [(-4, 4, n), (-4, 4, n)],
                [[-1.5, 1.0], [0.05, 0.05], [3.2, -3.0]],
                pm=True,
                note="coarse point mass, long horizon",
            )
        )
    for T, rate, n in ((50.0, 0.5, 41), (20.0, 1.0, 41)):
        add(
            lq(
                f"long_unstable_r{rate:g}_T{int(T)}",
                [[rate, 1.0], [-1.0, rate]],
                I2,
                I2,
                I2,
                [0.0, 0.0],
                I2,
                [0.5, 0.5],
                1.0,
                T,
                [(-4, 4, n), (-4, 4, n)],
                [[1.0, -1.0], [0.5, 0.5], [-3.3, 3.3]],
                note=f"unstable spiral (rate +{rate:g}), fully actuated",
            )
        )
    for lam in (1e-3, 1e-2):
        add(
            lq(
                f"long_pm_T50_l{lam:g}",
                PM_A,
                PM_B,
                [[1.0]],
                diag(1.0, 0.1),
                [0.0, 0.0],
                I2,
                [1.0, 0.0],
                lam,
                50.0,
                [(-4, 4, 81), (-4, 4, 81)],
                [[-1.5, 1.0], [0.05, 0.05], [3.2, -3.0]],
                pm=True,
                note=f"point mass, long horizon, λ {lam:g} (v/λ up to 1e5)",
            )
        )
    # the same point-mass task with space scaled by eps (R → R/eps², W → W/eps²): v unchanged
    for eps in (1e-6, 1e6):
        add(
            lq(
                f"scale_x{eps:g}",
                PM_A,
                PM_B,
                [[1.0 / eps**2]],
                diag(1.0 / eps**2, 0.1 / eps**2),
                [0.0, 0.0],
                diag(1.0 / eps**2, 1.0 / eps**2),
                [1.0 * eps, 0.0],
                0.5,
                5.0,
                [(-4 * eps, 4 * eps, 81), (-4 * eps, 4 * eps, 81)],
                [[-1.5 * eps, 1.0 * eps], [0.05 * eps, 0.05 * eps], [3.2 * eps, -3.0 * eps]],
                pm=True,
                note=f"point mass with space scaled by {eps:g} (same v as the unscaled task)",
            )
        )
    # the same task with time scaled by k (A → A/k, R → kR, q → q/k, T → kT): v unchanged
    for k in (1e-4, 1e4):
        add(
            lq(
                f"scale_t{k:g}",
                [[0.0, 1.0 / k], [0.0, 0.0]],
                PM_B,
                [[k]],
                diag(1.0 / k, 0.1 / k),
                [0.0, 0.0],
                I2,
                [1.0, 0.0],
                0.5,
                5.0 * k,
                [(-4, 4, 81), (-4, 4, 81)],
                [[-1.5, 1.0], [0.05, 0.05], [3.2, -3.0]],
                note=f"point mass as LinearSystem with time scaled by {k:g} (same v)",
            )
        )
    for s in (30.0, 100.0, 300.0):
        add(
            lq(
                f"cost_pm_s{s:g}_41",
                PM_A,
                PM_B,
                [[1.0]],
                diag(s, 0.1 * s),
                [0.0, 0.0],
                diag(s, s),
                [0.5, 0.0],
                1.0,
                2.0,
                [(-3, 3, 41), (-3, 3, 41)],
                [[-1.5, 1.0], [0.5, 0.0], [2.7, -2.7]],
                pm=True,
                note=f"point mass, q and g scaled by {s:g}, λ 1, 41²",
            )
        )
    for W, lam, n, T in ((200.0, 2.0, 41, 0.001), (400.0, 1.0, 61, 0.002), (100.0, 0.3, 41, 0.01)):
        L = 2.0
        h = 2 * L / (n - 1)
        c = [0.5 * h + 0.1, -0.5 * h - 0.1]
        add(
            lq(
                f"short_mid_W{W:g}_l{lam:g}_{n}",
                Z2,
                I2,
                I2,
                Z2,
                [0.0, 0.0],
                diag(W, W),
                c,
                lam,
                T,
                [(-L, L, n), (-L, L, n)],
                [[0.4 * L + 0.5 * h, -0.3 * L - 0.5 * h], c, [c[0] + 0.5 * h, c[1] + 0.5 * h]],
                note="steep goal centred on a cell centre; states at cell centres",
            )
        )
    # drift into a wall: a stationary boundary layer of width λ/(2|a0|), thinner than a cell
    for a0, lam, n in ((5.0, 0.1, 41), (20.0, 0.1, 41), (20.0, 0.5, 81)):
        add(
            tiny(
                f"wall_drift_a{a0:g}_l{lam:g}_{n}",
                [0.0, 0.0],
                [1.0, 0.5],
                [-0.1, 0.0],
                [5.0, 2.0],
                [-0.15, 0.05],
                lam,
                2.0,
                [(-0.2, 0.2, n), (-0.2, 0.2, n)],
                [[0.0, 0.0], [-0.15, 0.05], [0.195, 0.195]],
                note=f"constant drift +{a0:g} on x0 into the wall at 0.2, box ±0.2 (user system)",
                a0=[a0, 0.0],
            )
        )
    # a stiff UNSTABLE axis beside a slow one; long unstable horizons at large λ
    for r, lam in ((100.0, 0.5), (10.0, 0.5), (10.0, 2.0)):
        add(
            lq(
                f"mixed_unstable_r{r:g}_l{lam:g}",
                diag(r, -0.1),
                I2,
                I2,
                diag(1.0, 1.0),
                [0.0, 0.5],
                diag(1.0, 1.0),
                [0.3, -0.5],
                lam,
                5.0,
                [(-3, 3, 81), (-3, 3, 81)],
                [[1.0, -1.0], [0.3, -0.5], [2.8, -2.8]],
                note=f"axis 0 unstable at rate {r:g}, axis 1 stable at 0.1, both actuated",
            )
        )
    for lam, n in ((2.0, 41), (5.0, 61)):
        add(
            lq(
                f"long_unstable_bigl{lam:g}_{n}",
                [[0.5, 1.0], [-1.0, 0.5]],
                I2,
                I2,
                I2,
                [0.0, 0.0],
                I2,
                [0.5, 0.5],
                lam,
                50.0,
                [(-5, 5, n), (-5, 5, n)],
                [[1.0, -1.0], [0.5, 0.5], [-2.5, 2.5]],
                note=f"unstable spiral rate 0.5, λ {lam:g}, T 50",
            )
        )
    # the same stiff-unstable problems judged against the REFLECTED truth (separable: 1-D FD)
    for r, lam in ((100.0, 0.5), (10.0, 0.5), (10.0, 2.0)):
        add(
            tiny(
                f"refl_unstable_r{r:g}_l{lam:g}",
                [r, -0.1],
                [1.0, 1.0],
                [0.0, 0.5],
                [1.0, 1.0],
                [0.3, -0.5],
                lam,
                5.0,
                [(-3, 3, 81), (-3, 3, 81)],
                [[1.0, -1.0], [0.3, -0.5], [2.8, -2.8]],
                note=f"= mixed_unstable_r{r:g}_l{lam:g}, truth of the reflected box",
            )
        )
    for a0, lam, n in ((100.0, 0.5, 41), (50.0, 1.0, 41)):
        add(
            tiny(
                f"wall_drift_a{a0:g}_l{lam:g}_{n}",
                [0.0, 0.0],
                [1.0, 0.5],
                [-0.1, 0.0],
                [5.0, 2.0],
                [-0.15, 0.05],
                lam,
                2.0,
                [(-0.2, 0.2, n), (-0.2, 0.2, n)],
                [[0.0, 0.0], [-0.15, 0.05], [0.195, 0.195]],
                note=f"constant drift +{a0:g} on x0 into the wall at 0.2, box ±0.2 (user system)",
                a0=[a0, 0.0],
            )
        )
    # a goal AT the wall the drift presses on: the boundary layer λ/(2 a0) decides v
    for a0, lam, n, wq0, wt0 in (
        (100.0, 1.0, 41, 0.0, 1e4),
        (100.0, 1.0, 41, 1e4, 0.0),
        (30.0, 1.0, 81, 0.0, 3e3),
        (300.0, 1.0, 41, 0.0, 1e5),
        (100.0, 1.0, 41, 0.0, 1e3),
        (100.0, 1.0, 41, 0.0, 2e3),
        (100.0, 1.0, 41, 0.0, 3e3),
        (100.0, 2.0, 41, 0.0, 3e3),
    ):
        add(
            tiny(
                f"wall_goal_a{a0:g}_q{wq0:g}_g{wt0:g}_{n}" + ("" if lam == 1.0 else f"_l{lam:g}"),
                [0.0, 0.0],
                [wq0, 0.5],
                [0.2, 0.0],
                [wt0, 2.0],
                [0.2, 0.05],
                lam,
                2.0,
                [(-0.2, 0.2, n), (-0.2, 0.2, n)],
                [[0.0, 0.0], [0.2, 0.05], [-0.195, -0.195]],
                note=f"drift +{a0:g} into the wall at 0.2 where a steep cost is centred",
                a0=[a0, 0.0],
            )
        )
    # a fast actuator lag (time constant 0.01–0.02) beneath slow dynamics
    for b, lam in ((10.0, 0.5), (30.0, 0.2)):
        add(
            lq(
                f"mixed_lag2_b{b:g}_l{lam:g}",
                [[-0.1, 1.0], [0.0, -100.0]],
                [[0.0], [b]],
                [[1.0]],
                diag(1.0, 0.0),
                [0.5, 0.0],
                diag(2.0, 0.0),
                [0.5, 0.0],
                lam,
                5.0,
                [(-3, 3, 81), (-3, 3, 81)],
                [[-1.5, 0.0], [0.5, 0.0], [2.5, -1.0]],
                note=f"slow x0 driven by a fast lagged actuator x1 (rate 100, gain {b:g})",
            )
        )
    add(
        lq(
            "mixed_lag3_pm",
            [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -50.0]],
            [[0.0], [0.0], [50.0]],
            [[1.0]],
            diag(1.0, 0.1, 0.0),
            [0.0, 0.0, 0.0],
            diag(1.0, 1.0, 0.0),
            [1.0, 0.0, 0.0],
            0.5,
            5.0,
            [(-4, 4, 41), (-4, 4, 41), (-6, 6, 41)],
            [[-1.5, 1.0, 0.0], [1.0, 0.0, 0.0], [3.0, -2.5, 1.0]],
            note="point mass whose force lags the control (rate 50)",
        )
    )
    # a drift at 45 degrees pressing the state into a corner (the Δt/h blind spot), goal there
    for a0, wt0 in ((50.0, 300.0), (50.0, 0.0)):
        add(
            tiny(
                f"corner_a{a0:g}_g{wt0:g}",
                [0.0, 0.0],
                [0.5, 0.5],
                [0.0, 0.0],
                [wt0 or 2.0, wt0 or 2.0],
                [0.2, 0.2] if wt0 else [-0.1, -0.1],
                1.0,
                2.0,
                [(-0.2, 0.2, 41), (-0.2, 0.2, 41)],
                [[0.0, 0.0], [0.195, 0.195], [-0.195, -0.195]],
                note=f"constant drift ({a0:g}, {a0:g}) into the corner (0.2, 0.2)",
                a0=[a0, a0],
            )
        )
    # huge boxes at large λ and long horizons: the goal sub-cell, the paths far
    for L, n, lam, T in ((100.0, 201, 2.0, 20.0), (50.0, 101, 5.0, 50.0), (50.0, 101, 0.5, 50.0)):
        add(
            lq(
                f"huge_si_L{L:g}_{n}_l{lam:g}_T{T:g}",
                Z2,
                I2,
                I2,
                Z2,
                [0.0, 0.0],
                diag(16.0, 16.0),
                [0.3, -0.2],
                lam,
                T,
                [(-L, L, n), (-L, L, n)],
                [[0.4 * L, -0.2 * L], [0.3, -0.2], [0.84 * L, 0.8 * L]],
                note=f"box ±{L:g} (h = {2 * L / (n - 1):g}), goal width ~0.25, no running cost",
            )
        )
    return P


# ================= building ======================================================================
def build(spec, widen=1.0):
    axes = []
    for lo, hi, n in spec["box"]:
        if widen != 1.0:
            h = (hi - lo) / (n - 1)
            k = max(2, round((widen - 1) * (n - 1) / 2))
            lo, hi, n = lo - k * h, hi + k * h, n + 2 * k
        axes.append(Axis(lo, hi, n))
    grid = Grid(axes)
    lam, T = spec["lam"], spec["T"]
    if spec["family"] == "tiny" and spec.get("a0"):
        return build_sep(sep_spec(spec))
    if spec["family"] == "tiny":
        d = len(spec["a"])
        sysm = LinearSystem(np.diag(spec["a"]), np.eye(d))
        return Problem(
            sysm,
            grid,
            T,
            terminal_cost=Quadratic(spec["ct"], np.diag(spec["wt"])),
            state_cost=Quadratic(spec["cq"], np.diag(spec["wq"])),
            control_cost=np.eye(d),
            temperature=lam,
        )
    sysm = PointMass() if spec["pm"] else LinearSystem(np.array(spec["A"]), np.array(spec["B"]))
    g = Quadratic(spec["cT"], spec["WT"])
    if spec["offset"]:
        off = spec["offset"]

        def gfun(x, _g=g, _o=off):
            return _g(x) + _o

        term = gfun
    else:
        term = g
    return Problem(
        sysm,
        grid,
        T,
        terminal_cost=term,
        state_cost=Quadratic(spec["cq"], spec["Wq"]),
        control_cost=np.array(spec["R"]) if len(spec["R"]) > 1 else float(spec["R"][0][0]),
        temperature=lam,
    )


def sep_spec(spec):
    """Round 25's separable spec of a ``tiny`` problem (reflecting walls); with a constant drift
    ``a0`` it is solved as round 25's ``Sep`` system (a user's own ``ControlAffineSystem``)."""
    axes = []
    for i, (lo, hi, n) in enumerate(spec["box"]):
        a_terms = [["lin", spec["a"][i], 0.0]]
        if spec.get("a0"):
            a_terms.append(["const", spec["a0"][i]])
        axes.append(
            dict(
                lo=lo,
                hi=hi,
                n=n,
                periodic=False,
                R=1.0,
                a=a_terms,
                b=[["const", 1.0]],
                q=[["quad", spec["wq"][i], spec["cq"][i]]],
                g=[["quad", spec["wt"][i], spec["ct"][i]]],
            )
        )
    return dict(family="sep", kind="hz", axes=axes, lam=spec["lam"], T=spec["T"])


def free_lq(spec):
    d = len(spec["a"])
    return dict(
        A=np.diag(spec["a"]).tolist(),
        B=np.eye(d).tolist(),
        R=np.eye(d).tolist(),
        Wq=np.diag(spec["wq"]).tolist(),
        cq=spec["cq"],
        WT=np.diag(spec["wt"]).tolist(),
        cT=spec["ct"],
        lam=spec["lam"],
        T=spec["T"],
    )


def truth(spec, X, ts):
    if spec["family"] == "tiny":
        st = sep_truth(sep_spec(spec), X, ts)
        if spec.get("a0"):
            return {t: (np.asarray(st[t][0]), np.asarray(st[t][1]), None) for t in ts}
        fl = free_lq(spec)
        return {t: (np.asarray(st[t][0]), np.asarray(st[t][1]), lq_value(fl, X, t)) for t in ts}
    sp = dict(spec)
    if spec["pm"]:
        sp["A"], sp["B"] = PM_A, PM_B
    return {t: (lq_value(sp, X, t) + spec["offset"], np.zeros(len(X)), None) for t in ts}


def _warnlist(w):
    return [
        dict(category=x.category.__name__, message=str(x.message)[:200])
        for x in w
        if issubclass(x.category, gridlbc.GridlbcWarning)
    ]


def run(name, spec):
    OUT.mkdir(parents=True, exist_ok=True)
    p = build(spec)
    X = np.asarray(spec["X"], float)
    ts = [0.0, 0.9 * spec["T"]]
    t0 = time.perf_counter()
    fail = None
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            s = gridlbc.solve(p)
        except Exception as ex:  # a crash is a finding
            s, fail = None, repr(ex)[:500]
    secs = time.perf_counter() - t0
    wl = _warnlist(w)
    rec = dict(
        name=name, spec=spec, warnings=wl, warned=bool(wl), seconds=secs, fail=fail, reads=[]
    )
    if s is None:
        print(f"{name}: CRASH {fail}")
        (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
        return rec
    dg = s.diagnostics
    rec.update(dt=float(dg.dt), steps=int(dg.steps), underflow_nodes=int(dg.underflow_nodes))
    tr = truth(spec, X, ts)
    lam = spec["lam"]
    worst = 0.0
    for t in ts:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            v = np.asarray(s.value(X, t), float)
            e = np.asarray(s.error_estimate(X, t), float)
        vt, pm, free = tr[t]
        err = np.abs(v - vt) / np.maximum(np.abs(vt), lam)
        est = e / np.maximum(np.abs(v), lam)
        rd = dict(
            t=t,
            v=v.tolist(),
            est=e.tolist(),
            truth=vt.tolist(),
            pm=pm.tolist(),
            err_rel=err.tolist(),
            est_rel=est.tolist(),
        )
        if free is not None:
            rd["riccati_free"] = np.asarray(free).tolist()
        rec["reads"].append(rd)
        worst = max(worst, float(err.max()))
    rec["worst"] = worst
    print(
        f"{name:24s} {tuple(p.grid.shape)!s:14s} λ={lam:g} T={spec['T']:g} dt={dg.dt:.4g} "
        f"steps={dg.steps} {secs:6.1f}s warned={bool(wl)} worst={worst:.3%}"
    )
    for r in rec["reads"]:
        for i in range(len(X)):
            print(
                f"    t={r['t']:.4g} x={np.round(X[i], 3).tolist()} v={r['v'][i]:.6g} "
                f"v*={r['truth'][i]:.6g} err={r['err_rel'][i]:.2%} est={r['est_rel'][i]:.2%}"
                + (f" free={r['riccati_free'][i]:.5g}" if "riccati_free" in r else "")
            )
    for x in wl:
        print("    warn:", x["category"], x["message"][:200])
    if worst > 0.05 and spec["family"] == "lq":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sw = gridlbc.solve(build(spec, 1.5), dt=float(dg.dt), error_estimate=False)
        rec["wall"] = [np.asarray(sw.value(X, t)).tolist() for t in ts]
        print("    wider box:", [np.round(x, 5).tolist() for x in rec["wall"]])
    (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
    return rec


def tol_run(name, spec, max_seconds=90):
    p = build(spec)
    X = np.asarray(spec["X"], float)
    ts = [0.0, 0.9 * spec["T"]]
    t1 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            st = gridlbc.solve(p, tol=TOL, states=X, times=ts, max_seconds=max_seconds)
            fail = None
        except Exception as ex:
            st, fail = None, repr(ex)[:500]
    tr2 = dict(seconds=time.perf_counter() - t1, warnings=_warnlist(w), fail=fail, reads=[])
    if st is not None:
        tr2["rounds"] = [
            dict(shape=list(r.shape), dt=r.dt, error=r.error, met=bool(r.met(TOL)))
            for r in st.refinement
        ]
        tr2["met"] = bool(st.refinement[-1].met(TOL)) and not any(
            "tol" in x["message"] for x in tr2["warnings"]
        )
        tr = truth(spec, X, ts)
        for t in ts:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                v = np.asarray(st.value(X, t), float)
                e = np.asarray(st.error_estimate(X, t), float)
            vt = tr[t][0]
            err = np.abs(v - vt) / np.maximum(np.abs(vt), spec["lam"])
            tr2["reads"].append(dict(t=t, v=v.tolist(), est=e.tolist(), err_rel=err.tolist()))
        print(
            f"{name} tol={TOL}: met={tr2['met']} {tr2['seconds']:.0f}s rounds="
            f"{[(r['shape'], round(r['dt'], 5)) for r in tr2['rounds']]} errs="
            f"{[np.round(r['err_rel'], 4).tolist() for r in tr2['reads']]}"
        )
    else:
        print(f"{name} tol run failed {fail}")
    for x in tr2["warnings"]:
        print("    warn:", x["category"], x["message"][:200])
    f = OUT / f"{name}.json"
    rec = json.loads(f.read_text()) if f.exists() else dict(name=name)
    rec["tol"] = tr2
    f.write_text(json.dumps(rec, indent=1, default=float))


def wall_flags(r):
    flags = set()
    if "wall" not in r:
        return flags
    lam = r["spec"]["lam"]
    for k, (rd, vw) in enumerate(zip(r["reads"], r["wall"])):
        for i in range(len(rd["v"])):
            eff = abs(vw[i] - rd["v"][i])
            err = abs(rd["v"][i] - rd["truth"][i])
            if eff > max(0.01 * max(abs(rd["truth"][i]), lam), 0.25 * err):
                flags.add((k, i))
    return flags


def table():
    recs = [json.loads(f.read_text()) for f in sorted(OUT.glob("*.json"))]
    # the unstable boxes are judged against their reflected truth (refl_unstable_*): against the
    # free-space Riccati they are the walls' doing (a box 1.5x wider moves v by 2-5x)
    skipped = [r["name"] for r in recs if r["name"].startswith("mixed_unstable_")]
    recs = [r for r in recs if r["name"] not in skipped]
    print("judged by their reflected twins (refl_unstable_*), not counted:", skipped)
    n = big = silent = under_w = 0
    silent_list, walled, crashes, under_list = [], [], [], []
    for r in recs:
        if r.get("fail"):
            crashes.append((r["name"], r["fail"]))
            continue
        fl = wall_flags(r)
        for k, rd in enumerate(r["reads"]):
            for i in range(len(rd["v"])):
                if (k, i) in fl:
                    walled.append((r["name"], rd["t"], r["spec"]["X"][i], rd["err_rel"][i]))
                    continue
                n += 1
                err = rd["err_rel"][i]
                errabs = abs(rd["v"][i] - rd["truth"][i])
                if err > 0.10:
                    big += 1
                    if not r["warned"]:
                        silent += 1
                        silent_list.append(
                            (r["name"], rd["t"], r["spec"]["X"][i], rd["v"][i], rd["truth"][i])
                            + (round(err, 4), round(rd["est_rel"][i], 4))
                        )
                if r["warned"] and rd["est"][i] < 0.5 * errabs and err > 0.02:
                    under_w += 1
                    under_list.append(
                        (r["name"], rd["t"], r["spec"]["X"][i], round(err, 4))
                        + (round(rd["est_rel"][i], 4),)
                    )
    print(
        f"problems {len(recs)}  pairs {n}  >10% {big}  SILENT {silent}  "
        f"under-reads in warned solves {under_w}  wall pairs (not counted) {len(walled)}"
    )
    print("silent:")
    for s in silent_list:
        print("   ", s)
    print("under-reads in warned solves:")
    for u in under_list:
        print("   ", u)
    print("wall-flagged:", walled)
    print("crashes:", crashes)
    for r in recs:
        if "tol" in r:
            t = r["tol"]
            print(
                f"   tol {r['name']}: met={t.get('met')} {t['seconds']:.0f}s "
                f"errs={[np.round(x['err_rel'], 4).tolist() for x in t['reads']]}"
            )


def main(argv):
    P = problems()
    if "--list" in argv:
        for k, v in P.items():
            print(k, json.dumps(v))
    elif "--run" in argv:
        names = argv[argv.index("--run") + 1 :] or list(P)
        for nm in names:
            run(nm, P[nm])
    elif "--tol" in argv:
        for nm in argv[argv.index("--tol") + 1 :]:
            tol_run(nm, P[nm])
    elif "--table" in argv:
        table()


if __name__ == "__main__":
    main(sys.argv[1:])
