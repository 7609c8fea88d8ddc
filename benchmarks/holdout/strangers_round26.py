"""Stranger round 26: the combination paths — ``gridlbc.solve_many``, ``gridlbc.combine`` and
``gridlbc.save`` / ``gridlbc.load`` of the components — posed with the public API only (SPEC §2–3,
§6, §9–10).

Families (each entry of ``C26`` is one combination read at 3 states: the dominant component's
goal, between the goals, far):

1. components from ``solve_many(problem, [g_1 … g_k])`` (k = 2–5: quadratics at different
   centres, a user callable with walls or a flat region), weights equal, far from one
   (1e-3 … 1e3), one dominating, summing to ≠ 1, and one negative (w = (1, −0.5) on two
   concentric goals, so Σ w_i h_i > 0 everywhere);
2. components from separate default ``gridlbc.solve`` calls (fitted, each its own reference: a
   ``Combination``, exact False) and separate ``fitting=None`` solves (exact);
3. components saved and loaded, then combined; first-exit components (a stationary problem, one
   exit set, several exit costs through ``solve_many``);
4. reads at t > 0.

Truths: "lq" — for linear systems with quadratic costs, v* = −λ log Σ w_i exp(−v_i/λ) with each
v_i from my Riccati ODEs (round 20's ``lq_exact``; signed sum for a negative weight): linearity is
exact in the continuum. The boxes are wide (the states and goals ≥ 2.5 noise widths inside);
``--wall NAME`` re-solves the composite on a 1.5× wider box to check. "fine" — the composite
problem (terminal or exit cost −λ log Σ w_i exp(−g_i/λ), my own function) solved directly on 2×
and 3× finer grids with a small step (``error_estimate=False``); v* the 3× value, its
uncertainty the 2×–3× difference.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round26.py NAME ... | --all | --table

Flows (``C26`` name → (family, flow, weights, states, t)): "many" ``solve_many``; "sep" separate
default solves (``sep:store_every=4`` with that option); "plain" separate ``fitting=None``;
"mixdt" separate solves with dt = T/10 and T/27; "saved" / "savedsep" the many / sep components
written by ``gridlbc.save`` and read by ``gridlbc.load``. Every GridlbcWarning of the solves, of
``combine`` and of the reads is recorded (category, first 150 characters). Families: pm / pmc
(PointMass λ 0.5 / 0.1, q 0.2, goals (±1.5, 0)); si5 (2-D single integrator, five goals); neg
(concentric goals W and 2W, negative weights); osc (damped oscillator, R 0.5); spin (README's
Spin); si3 (3-D, 41³); siq / siqc / pmq / siw (a dear constant q = 1–2, so weights of 1e3 move
the value to ≈ 0 between the goals); swing (my nonlinear oscillator, walled callable goals and a
flat one); flat (flat-bottomed callable goals); exit (point mass parking in three bays, first
exit, exit costs 0 in bay i and 3 in the others). Definitions in the code.

RESULTS (library of main 775ea6e merged into r26 (nothing to merge), 2026-12-06, one thread,
``--solve --all`` then ``--table``): 78 combinations, 234 (combination, state) pairs, all 3
states per combination; truths Riccati ("lq") for 66 combinations, direct fine composite solves
for 12 (2×/3×: agree to ≤ 0.004 except exit at (0, 0), ±0.02–0.03). Errors relative to
max(|v*|, λ), ê to max(|v|, λ).

- > 10 % off: 9 pairs. SILENT (no GridlbcWarning from the solves, combine or the reads): 6 pairs,
  one mechanism. Coverage ê ≥ ½ err: 232 / 234; the two misses are my truth's, not the
  library's: ``spin_eq`` (−3, −3) (ê/err 0.24) and ``siw_eq`` (−4.5, −4.5) (0.40) sit where the
  box's walls move v* (``--wall``: the composite on the box, 2× grid, Δt T/400: 4.2918 and 9.9455
  against Riccati 4.3577 and 9.9587; the same solve on a 1.5× wider box gives Riccati's);
  against the in-box values both pairs are ≤ 0.5 % off and covered, so 234 / 234. Everywhere
  else the box does not matter (``--wall siq_1k_sep_late siq_1k_se4_mid pm_far_mid``: box =
  wide = Riccati to 5e-4). Over-reads (ê > 10 err and > 5 %): 9 pairs (si3_eq, exit_far ×2,
  flat_far_late ×2, neg_c_sep_late ×2, siq_1k_sep_t18 ×2).
- Warnings: 42 of 78 combinations warn somewhere in the flow (36 quiet). Nearly every
  ``solve_many`` here warns (its components' late-time check, t = T − Δs/2, or at 5 %
  of the states that matter), while separate default solves of the same costs are quiet for
  siq, pmq, si5, neg: on siq at 31²–61², solve_many's component 0 is 3–18 % off (covered, warned)
  at the other goal where the separate solve is 0.1 % off — the shared fitting reference. With
  any warning counted, 29 combinations warned with every pair < 2 %; ``combine``'s own warning
  (check_combination) fired on 14, 8 of them with every read pair < 2 % (pm_far, pm_big,
  pmc_far, flat_far, pm_far_plain, pm_far_saved, flat_far_saved, flat_far_late; it reads its 90th
  percentile over component 0's states that matter, not mine, so these may be true elsewhere).
- Exact / not exact: every solve_many and saved-many combination is a CombinedSolution (exact);
  separate fitted solves, mixed dt and store_every give a Combination with the reason; separate
  ``fitting=None`` solves an exact one. Save/load round-trips bit for bit (saved = unsaved
  numbers in every pair), callable costs included; the exit components combine and save.
  Negative weights (1, −0.5, 1), (1, −0.9, 0.1), (1, −0.99, 0): ≤ 1.7 %, covered.

SILENT pairs (all: family ``siq``: ``LinearSystem(np.zeros((2, 2)), np.eye(2))``, grid
[−4, 4]² with 101 × 101 nodes, T = 2, q = 1 (constant callable), R = 1, λ = 0.3 (``siqc``: 0.15),
g_1 = Quadratic([−1.5, 0], I), g_2 = Quadratic([1.5, 0], I); components by two separate default
``gridlbc.solve`` calls (splitting, fitted to each g, Δt 0.2, 10 steps, no warning), then
``gridlbc.combine(components, [1, 1e3])`` (a Combination); truth −λ log(z_1 + 1e3 z_2), Riccati):

  ``siq_1k_sep_late``  (0, 0), t = 1.9:  v 0.0064, v* −0.0429, err 16.4 %, ê 0.065 (ê/err 1.3)
  ``siq_1k_saved_late`` the same components saved and loaded: identical numbers
  ``siq_1k_sep_t195`` (0, 0), t = 1.95: v 0.0919, v* 0.0514, err 13.5 %, ê 0.037 (0.92)
  ``siqc_1k_sep_late`` (λ 0.15) (0.55, 0), t = 1.9: v −0.1368, v* −0.1567, 12.7 %, ê 0.031 (1.5)
  ``siq_1k_se4_mid`` (``store_every=4``) (0, 0), t = 1.0: v 0.0556, v* 0.0070, 16.2 %, ê 0.038
  (0.78)
  ``siq_1k_se4_late`` (``store_every=4``) (0, 0), t = 1.5: v −0.1960, v* −0.2397, 14.6 %,
  ê 0.029 (0.67)

Mechanism: each component read between two stored slices is interpolated linearly in time in
z (SPEC §4). Near T (and across 4 steps with store_every=4) z changes fast between the goals (at
(0, 0) the true v is 1.908, 2.030, 2.124, 2.25 at t = 1.8, 1.9, 1.95, 2), so a component reads
2.079 at t = 1.9: +0.049, 2.4 % of its own value, below the 5 % tolerance, its own ê (0.065)
covering it; each solve's late-time check at T − Δs/2 agrees it is fine. The weight 1e3 lowers
the combination's value by λ log 1e3 = 2.07 to ≈ 0, where the same absolute error is 16 % of
max(|v|, λ). ``check_combination`` judges only t = 0 (component 0's states that matter, grid
terms), where these components are 0.1 % off, and nothing judges the combination at t > 0; at a
stored slice (t = 1.8) the error is 0.0 %. ``combined.error_estimate(x, t)`` does read it (ê/err
0.67–1.5), so a user who asks is told; nobody warns. The same combination from ``solve_many``
(``siq_1k_many_late``, ``siqc_1k_many_late``: 16.2 %, 12.7 %) is warned only because those
solves warn of their own late times. Controls: equal weights (``siqc_eq_sep_late``) 2.3 %; a
combination of steps T/10 and T/27 (``siq_1k_mixdt_late``) 1.9 %; the weight 2e4
(``siq_zero_sep_late``, v ≈ −0.9) 5.2 %.

Other > 10 % pair (warned): ``pm_far_mid`` (−3, 2.5), t = 1: v 3.007 v* 3.477 (−13.5 %), ê 69 %,
warned by the components' solves and by combine.

AFTER THE FIX (main, 2026-12-06, the same ``--solve --all`` then ``--table``): ``check_combination``
also reads the late times where its components are judged, confirmed by the components' own
paths, and a store_every interval that the embedded solve steps over in one step reads the
interpolation from the solve's own slices (``own_interpolation_error``). SILENT 0 (was 6); the
numbers read are unchanged (same v, ê), coverage 232 / 234 as before. ``combine`` now warns on
66 of 78 combinations (14 before): checked at the state and time each late warning names, 42 of
its 47 late warnings are 5 % or more off against Riccati (the Riccati mix at the named state), 2 are 2.6 %, 3 within 1.7 % (``neg_deep``, ``neg_sep``, negative weights);
the 8 read at t = 0 are the quantile's as before. The store_every=4 components' own solves now
warn at t = 1.8 (9 % off at the 90th percentile of their states that matter, τ was 0).
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import ControlAffineSystem, LinearSystem, PointMass

OUT = (
    Path(__file__).resolve().parents[3]
    / "main"
    / "benchmarks"
    / "holdout"
    / "strangers_round26_results"
)
if not OUT.parent.exists():  # run from the main checkout
    OUT = Path(__file__).resolve().parent / "strangers_round26_results"


def S(*states):
    return np.array(states, dtype=float)


# ---------------- exact LQ references ------------------------------------------------------------
def lq_exact(A, B, R, Wq, cq, WT, cT, lam, tau):
    """v(x) with remaining horizon tau: ẋ = Ax + Bu, q = (x−c_q)ᵀW_q(x−c_q), g likewise."""
    A, B, R, Wq, WT = (np.atleast_2d(np.asarray(m, dtype=float)) for m in (A, B, R, Wq, WT))
    cq, cT = np.asarray(cq, float), np.asarray(cT, float)
    d = A.shape[0]
    if R.shape[0] != B.shape[1]:
        R = R[0, 0] * np.eye(B.shape[1])
    Sm = B @ np.linalg.solve(R, B.T)

    def rhs(s, y):
        P, p = y[: d * d].reshape(d, d), y[d * d : d * d + d]
        dP = -(A.T @ P + P @ A - P @ Sm @ P + 2 * Wq)
        dp = -((A - Sm @ P).T @ p - 2 * Wq @ cq)
        dc = -(-0.5 * p @ Sm @ p + 0.5 * lam * np.trace(Sm @ P) + cq @ Wq @ cq)
        return np.concatenate([dP.ravel(), dp, [dc]])

    y0 = np.concatenate([(2 * WT).ravel(), -2 * WT @ cT, [cT @ WT @ cT]])
    if tau <= 0:
        y = y0
    else:
        y = solve_ivp(rhs, (tau, 0.0), y0, rtol=1e-11, atol=1e-12, method="LSODA").y[:, -1]
    P, p, c0 = y[: d * d].reshape(d, d), y[d * d : d * d + d], y[-1]
    return lambda X: 0.5 * np.einsum("ni,ij,nj->n", X, P, X) + X @ p + c0


def signed_lse(a, w):
    """log Σ w_i exp(a_i) over axis 0 for signed w (the total must be positive)."""
    m = a.max(0)
    s = (np.asarray(w, float)[:, None] * np.exp(a - m)).sum(0)
    return m + np.log(s)


# ---------------- the families --------------------------------------------------------------------
class Spin(ControlAffineSystem):
    """README's user system: a point pushed in the plane by a flow turning at `rate` rad/s."""

    state_dim, control_dim, state_names = 2, 2, ("x", "y")

    def __init__(self, rate=1.0):
        self.rate = rate

    def drift(self, x):
        x = self._states(x)
        return self.rate * np.stack([-x[:, 1], x[:, 0]], axis=1)

    def input_matrix(self, x):
        return np.broadcast_to(np.eye(2), (self._states(x).shape[0], 2, 2))

    def parameters(self):
        return {"rate": self.rate}


class Swing(ControlAffineSystem):
    """My own nonlinear oscillator: position x (not periodic), velocity v, a softening spring
    and a little drag: v̇ = −sin(x) − 0.1 v + u."""

    state_dim, control_dim, state_names = 2, 1, ("x", "v")

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], -np.sin(x[:, 0]) - 0.1 * x[:, 1]], axis=1)

    def input_matrix(self, x):
        n = self._states(x).shape[0]
        B = np.zeros((n, 2, 1))
        B[:, 1, 0] = 1.0
        return B

    def parameters(self):
        return {}


def const(c):
    return lambda x: c + 0.0 * x[:, 0]


def walls_goal(center, lo=-1.0, hi=1.0):
    """A user callable: quadratic around ``center`` on the first axis plus steep walls (|x₁| past
    the box [lo, hi] costs 40·dist²)."""
    c = np.asarray(center, float)

    def g(x):
        x = np.atleast_2d(x)
        d = x - c
        wall = 40 * (np.maximum(x[:, 0] - hi, 0) ** 2 + np.maximum(lo - x[:, 0], 0) ** 2)
        return 2.0 * d[:, 0] ** 2 + 0.5 * d[:, 1] ** 2 + wall

    return g


def flat_goal(center, half=0.5, k=8.0):
    """A user callable: zero on the square |x − c|∞ ≤ half, k·dist² outside."""
    c = np.asarray(center, float)

    def g(x):
        x = np.atleast_2d(x)
        dist = np.maximum(np.abs(x - c) - half, 0.0)
        return k * (dist**2).sum(1)

    return g


# an LQ family: (system, A, B, R, Wq, cq, q0, lam, T, grid, [(c_i, W_i)])
def fam_pm():
    W = np.diag([1.5, 0.3])
    return dict(
        system=PointMass(),
        A=[[0, 1], [0, 0]],
        B=[[0], [1]],
        R=1.0,
        Wq=np.zeros((2, 2)),
        cq=[0, 0],
        q0=0.2,
        lam=0.5,
        T=2.0,
        grid=Grid([Axis(-5, 5, 101), Axis(-6, 6, 101)]),
        goals=[([-1.5, 0.0], W), ([1.5, 0.0], W)],
    )


def fam_pm_cold():
    W = np.diag([1.5, 0.3])
    return dict(
        system=PointMass(),
        A=[[0, 1], [0, 0]],
        B=[[0], [1]],
        R=1.0,
        Wq=np.zeros((2, 2)),
        cq=[0, 0],
        q0=0.2,
        lam=0.1,
        T=2.0,
        grid=Grid([Axis(-5, 5, 101), Axis(-6, 6, 101)]),
        goals=[([-1.5, 0.0], W), ([1.5, 0.0], W)],
    )


SI2 = LinearSystem(np.zeros((2, 2)), np.eye(2))


def fam_si5():
    W = np.diag([1.0, 1.0])
    return dict(
        system=SI2,
        A=np.zeros((2, 2)),
        B=np.eye(2),
        R=1.0,
        Wq=0.1 * np.eye(2),
        cq=[0, 0],
        q0=0.0,
        lam=0.4,
        T=1.5,
        grid=Grid([Axis(-4.5, 4.5, 101), Axis(-4.5, 4.5, 101)]),
        goals=[
            ([-1.5, -1.5], W),
            ([1.5, -1.5], W),
            ([1.5, 1.5], W),
            ([-1.5, 1.5], W),
            ([0.0, 0.0], W),
        ],
    )


def fam_neg():
    """Two concentric goals (W and 2W) and a third: w = (1, −0.5, w3) keeps Σ w_i h_i > 0."""
    W = np.diag([1.0, 1.0])
    return dict(
        system=SI2,
        A=np.zeros((2, 2)),
        B=np.eye(2),
        R=1.0,
        Wq=np.zeros((2, 2)),
        cq=[0, 0],
        q0=0.3,
        lam=0.4,
        T=1.0,
        grid=Grid([Axis(-4.5, 4.5, 101), Axis(-4.5, 4.5, 101)]),
        goals=[([0.0, 0.0], W), ([0.0, 0.0], 2 * W), ([2.0, 0.0], W)],
    )


OSC = LinearSystem(np.array([[0.0, 1.0], [-1.0, -0.2]]), np.array([[0.0], [1.0]]))


def fam_osc():
    W = np.diag([2.0, 0.5])
    return dict(
        system=OSC,
        A=[[0, 1], [-1, -0.2]],
        B=[[0], [1]],
        R=0.5,
        Wq=np.diag([0.2, 0.0]),
        cq=[0, 0],
        q0=0.0,
        lam=0.5,
        T=2.5,
        grid=Grid([Axis(-5, 5, 101), Axis(-6, 6, 101)]),
        goals=[([1.0, 0.0], W), ([-1.0, 1.0], W), ([0.0, -1.5], W)],
    )


def fam_spin():
    W = np.diag([1.0, 1.0])
    return dict(
        system=Spin(1.0),
        A=[[0, -1], [1, 0]],
        B=np.eye(2),
        R=1.0,
        Wq=np.zeros((2, 2)),
        cq=[0, 0],
        q0=0.5,
        lam=0.3,
        T=1.5,
        grid=Grid([Axis(-4, 4, 101), Axis(-4, 4, 101)]),
        goals=[([1.2, 0.0], W), ([-1.2, 0.5], W)],
    )


SI3 = LinearSystem(np.zeros((3, 3)), np.eye(3))


def fam_si3():
    W = np.eye(3)
    return dict(
        system=SI3,
        A=np.zeros((3, 3)),
        B=np.eye(3),
        R=1.0,
        Wq=np.zeros((3, 3)),
        cq=[0, 0, 0],
        q0=0.2,
        lam=0.5,
        T=1.0,
        grid=Grid([Axis(-4, 4, 41)] * 3),
        goals=[([1.0, 0.0, 0.0], W), ([-1.0, 1.0, 0.0], W), ([0.0, -1.0, 1.0], W)],
    )


def lq_problem(f, goals=None):
    goals = f["goals"] if goals is None else goals
    Wq, cq, q0 = np.asarray(f["Wq"], float), np.asarray(f["cq"], float), f["q0"]
    if np.any(Wq):
        qc = Quadratic(cq, Wq)
        q = (lambda x: q0 + qc(x)) if q0 else qc
    else:
        q = const(q0)
    base = Problem(
        f["system"],
        f["grid"],
        f["T"],
        terminal_cost=Quadratic(*goals[0]),
        state_cost=q,
        control_cost=f["R"],
        temperature=f["lam"],
    )
    return base, [Quadratic(c, W) for c, W in goals]


def lq_truth(f, w, X, t):
    tau = f["T"] - t
    vs = np.stack(
        [
            lq_exact(f["A"], f["B"], f["R"], f["Wq"], f["cq"], W, c, f["lam"], tau)(X)
            + f["q0"] * tau
            for c, W in f["goals"]
        ]
    )
    lam = f["lam"]
    return -lam * signed_lse(-vs / lam, w)


def fam_siq():
    """A 2-D single integrator with a dear constant q = 1 (v at a goal ≈ 2 + …): weights of 1e3
    bring the combination's value to ≈ 0 there."""
    W = np.eye(2)
    return dict(
        system=SI2,
        A=np.zeros((2, 2)),
        B=np.eye(2),
        R=1.0,
        Wq=np.zeros((2, 2)),
        cq=[0, 0],
        q0=1.0,
        lam=0.3,
        T=2.0,
        grid=Grid([Axis(-4, 4, 101), Axis(-4, 4, 101)]),
        goals=[([-1.5, 0.0], W), ([1.5, 0.0], W)],
    )


def fam_siqc():
    """siq colder: λ = 0.15."""
    f = fam_siq()
    f["lam"] = 0.15
    return f


def fam_pmq():
    W = np.diag([1.0, 0.2])
    return dict(
        system=PointMass(),
        A=[[0, 1], [0, 0]],
        B=[[0], [1]],
        R=1.0,
        Wq=np.zeros((2, 2)),
        cq=[0, 0],
        q0=1.0,
        lam=0.3,
        T=2.0,
        grid=Grid([Axis(-4, 4, 101), Axis(-5, 5, 101)]),
        goals=[([-1.5, 0.0], W), ([1.5, 0.0], W)],
    )


def fam_siw():
    """siq, warm: λ = 1, q = 2, broad goals."""
    W = 0.5 * np.eye(2)
    return dict(
        system=SI2,
        A=np.zeros((2, 2)),
        B=np.eye(2),
        R=1.0,
        Wq=np.zeros((2, 2)),
        cq=[0, 0],
        q0=2.0,
        lam=1.0,
        T=2.0,
        grid=Grid([Axis(-6, 6, 101), Axis(-6, 6, 101)]),
        goals=[([-1.5, 0.0], W), ([1.5, 0.0], W), ([0.0, 2.0], W)],
    )


# the nonlinear families: (problem builder, costs)
def fam_swing():
    """My Swing with walled goals (callables) at x = ±0.8 and a flat one at x = 0."""
    grid = Grid([Axis(-3, 3, 101), Axis(-4, 4, 101)])
    gs = [walls_goal([0.8, 0.0]), walls_goal([-0.8, 0.0]), flat_goal([0.0, 0.0], 0.3, 6.0)]
    base = Problem(Swing(), grid, 2.0, terminal_cost=gs[0], state_cost=const(0.3), temperature=0.3)
    return base, gs


def fam_flat():
    """A 2-D single integrator with two flat-bottomed goals (zero on a square, steep outside) and
    a quadratic one, λ = 0.2."""
    grid = Grid([Axis(-3, 3, 101), Axis(-3, 3, 101)])
    gs = [
        flat_goal([-1.2, 0.0], 0.4, 20.0),
        flat_goal([1.2, 0.6], 0.3, 20.0),
        Quadratic([0.0, -1.5], np.eye(2)),
    ]
    base = Problem(SI2, grid, 1.0, terminal_cost=gs[0], state_cost=const(0.2), temperature=0.2)
    return base, gs


def fam_exit():
    """A point mass parking in one of three bays (first exit, stationary): exit set three balls,
    exit cost g_i = 0 in bay i and 3 in the others; q = 0.5 + 0.05 v²."""
    bays = [(-1.2, 0.0), (1.2, 0.0), (0.0, 1.5)]
    centres = np.array(bays)

    def exit_mask(x):
        x = np.atleast_2d(x)
        return np.any(
            [((x[:, 0] - c[0]) / 0.25) ** 2 + ((x[:, 1] - c[1]) / 0.5) ** 2 <= 1 for c in centres],
            axis=0,
        )

    def bay_cost(i):
        def g(x):
            x = np.atleast_2d(x)
            d = ((x[:, None, :] - centres[None]) ** 2).sum(-1)
            return np.where(d.argmin(1) == i, 0.0, 3.0)

        return g

    grid = Grid([Axis(-2.5, 2.5, 101), Axis(-3, 3, 101)])
    gs = [bay_cost(i) for i in range(3)]
    base = Problem(
        PointMass(),
        grid,
        None,
        state_cost=lambda x: 0.5 + 0.05 * x[:, 1] ** 2,
        temperature=0.5,
        exit=exit_mask,
        exit_cost=gs[0],
    )
    return base, gs


FAM = {
    "pm": fam_pm,
    "pmc": fam_pm_cold,
    "si5": fam_si5,
    "neg": fam_neg,
    "osc": fam_osc,
    "spin": fam_spin,
    "si3": fam_si3,
    "siq": fam_siq,
    "siqc": fam_siqc,
    "pmq": fam_pmq,
    "siw": fam_siw,
    "swing": fam_swing,
    "flat": fam_flat,
    "exit": fam_exit,
}
LQ = {"siqc", "pm", "pmc", "si5", "neg", "osc", "spin", "si3", "siq", "pmq", "siw"}


def problem_of(fam):
    f = FAM[fam]()
    if fam in LQ:
        return lq_problem(f)
    return f


# ---------------- the user's flow ------------------------------------------------------------------
def _rec(ws):
    return [
        (w.category.__name__, str(w.message)[:150])
        for w in ws
        if issubclass(w.category, gridlbc.GridlbcWarning)
    ]


_CACHE: dict = {}


def components(fam, flow):
    """The components as a user gets them, and the warnings their solves issued."""
    key = (fam, flow)
    if key in _CACHE:
        return _CACHE[key]
    base, gs = problem_of(fam)
    end = "exit_cost" if base.horizon is None else "terminal_cost"
    flow, _, opt = flow.partition(":")
    kw = {
        k: (int(v) if v.isdigit() else float(v))
        for k, v in (o.split("=") for o in opt.split(",") if o)
    }
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        if flow in ("many", "saved"):
            comps = gridlbc.solve_many(base, gs, **kw)
        elif flow in ("sep", "savedsep"):
            comps = [gridlbc.solve(base.replace(**{end: g}), **kw) for g in gs]
        elif flow == "mixdt":  # the user gives each solve its own step
            comps = [
                gridlbc.solve(base.replace(**{end: g}), dt=base.horizon / (10 + 17 * i))
                for i, g in enumerate(gs)
            ]
        elif flow == "plain":
            comps = [gridlbc.solve(base.replace(**{end: g}), fitting=None, **kw) for g in gs]
        else:
            raise ValueError(flow)
        if flow in ("saved", "savedsep"):
            d = tempfile.mkdtemp(prefix="r26_")
            paths = [gridlbc.save(s, os.path.join(d, f"c{i}.npz")) for i, s in enumerate(comps)]
            comps = [gridlbc.load(p) for p in paths]
    print(f"  solved {fam}/{flow} in {time.perf_counter() - t0:.1f} s, {len(ws)} warnings")
    _CACHE[key] = (comps, _rec(ws))
    return _CACHE[key]


# ---------------- fine truths --------------------------------------------------------------------
def composite_cost(gs, w, lam):
    lw = np.asarray(w, float)

    def g(x):
        a = np.stack([-np.asarray(gi(x), float) / lam for gi in gs])
        return -lam * signed_lse(a, lw)

    return g


def finer(p, factor):
    axes = [
        Axis(a.lo, a.hi, round(a.n * factor), True)
        if a.periodic
        else Axis(a.lo, a.hi, round((a.n - 1) * factor) + 1)
        for a in p.grid.axes
    ]
    return p.replace(grid=Grid(axes))


def fine_truth(fam, w, X, t, factors=(2.0, 3.0)):
    base, gs = problem_of(fam)
    lam = base.temperature
    g = composite_cost(gs, w, lam)
    p = base.replace(exit_cost=g) if base.horizon is None else base.replace(terminal_cost=g)
    vals = []
    for k in factors:
        kw = {} if base.horizon is None else {"dt": base.horizon / 400}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            s = gridlbc.solve(finer(p, k), error_estimate=False, **kw)
        vals.append(np.asarray(s.value(X, t), float))
    return vals[-1], np.abs(vals[-1] - vals[0]), {"fine_values": [v.tolist() for v in vals]}


# ---------------- the combinations ----------------------------------------------------------------
# name -> (family, flow, weights, states, t)
X_PM = S((1.5, 0.0), (0.0, 0.0), (-3.0, 2.5))
X_SIQ = S((1.5, 0.0), (0.0, 0.0), (-3.0, 2.5))
X_SIQ2 = S((-1.5, 0.0), (0.0, 0.0), (3.0, 2.5))
X_C = S((1.5, 0.0), (0.55, 0.0), (-3.0, 2.5))
X_Z = S((1.5, 0.0), (0.0, 0.0), (-3.0, 2.5))
X_SIW = S((1.5, 0.0), (0.0, 1.0), (-4.5, -4.0))
C26 = {
    # 1. solve_many
    "pm_eq": ("pm", "many", (1, 1), S((-1.5, 0.0), (0.0, 0.0), (3.0, -2.5)), 0.0),
    "pm_far": ("pm", "many", (1e-3, 1e3), X_PM, 0.0),
    "pm_big": ("pm", "many", (1e3, 1e3), X_PM, 0.0),
    "pm_tiny": ("pm", "many", (1e-3, 1e-3), X_PM, 0.0),
    "pm_dom": ("pm", "many", (1.0, 1e-3), S((-1.5, 0.0), (0.0, 0.0), (3.0, -2.5)), 0.0),
    "pmc_far": ("pmc", "many", (1e-3, 1e3), X_PM, 0.0),
    "si5_eq": ("si5", "many", (1, 1, 1, 1, 1), S((0.0, 0.0), (0.75, 0.0), (-3.5, 3.5)), 0.0),
    "si5_mix": (
        "si5",
        "many",
        (1e2, 1, 1e-2, 1e-3, 10),
        S((-1.5, -1.5), (0.0, -1.0), (3.5, 3.5)),
        0.0,
    ),
    "si5_big": (
        "si5",
        "many",
        (1e3, 1e3, 1e3, 1e3, 1e3),
        S((1.5, 1.5), (0.0, 0.75), (-3.5, 0.0)),
        0.0,
    ),
    "neg": ("neg", "many", (1.0, -0.5, 1.0), S((0.0, 0.0), (1.0, 0.0), (-3.0, 2.0)), 0.0),
    "neg_deep": ("neg", "many", (1.0, -0.9, 0.1), S((0.0, 0.0), (1.0, 0.5), (-3.0, 2.0)), 0.0),
    "osc_mix": ("osc", "many", (1.0, 0.01, 100.0), S((0.0, -1.5), (0.5, -0.5), (3.0, 3.0)), 0.0),
    "spin_eq": ("spin", "many", (1, 1), S((1.2, 0.0), (0.0, 0.3), (-3.0, -3.0)), 0.0),
    "si3_eq": ("si3", "many", (1, 1, 1), S((1.0, 0, 0), (0, 0, 0.3), (-2.5, -2.5, 2.5)), 0.0),
    "si3_far": ("si3", "many", (1e3, 1, 1e-3), S((1.0, 0, 0), (0, 0.5, 0), (-2.5, -2.5, 2.5)), 0.0),
    "swing_eq": ("swing", "many", (1, 1, 1), S((0.8, 0.0), (0.4, 0.5), (-2.5, 3.0)), 0.0),
    "swing_far": ("swing", "many", (1e-3, 1.0, 1e3), S((0.0, 0.0), (-0.5, -0.5), (2.5, -3.0)), 0.0),
    "flat_eq": ("flat", "many", (1, 1, 1), S((-1.2, 0.0), (0.0, 0.3), (2.5, -2.5)), 0.0),
    "flat_far": ("flat", "many", (1e3, 1e-3, 1.0), S((-1.2, 0.0), (0.0, 0.3), (2.5, 2.5)), 0.0),
    # 2. separate solves (fitted default) and separate plain solves
    "pm_far_sep": ("pm", "sep", (1e-3, 1e3), X_PM, 0.0),
    "pm_big_sep": ("pm", "sep", (1e3, 1e3), X_PM, 0.0),
    "si5_mix_sep": (
        "si5",
        "sep",
        (1e2, 1, 1e-2, 1e-3, 10),
        S((-1.5, -1.5), (0.0, -1.0), (3.5, 3.5)),
        0.0,
    ),
    "neg_sep": ("neg", "sep", (1.0, -0.9, 0.1), S((0.0, 0.0), (1.0, 0.5), (-3.0, 2.0)), 0.0),
    "osc_mix_sep": ("osc", "sep", (1.0, 0.01, 100.0), S((0.0, -1.5), (0.5, -0.5), (3.0, 3.0)), 0.0),
    "swing_far_sep": (
        "swing",
        "sep",
        (1e-3, 1.0, 1e3),
        S((0.0, 0.0), (-0.5, -0.5), (2.5, -3.0)),
        0.0,
    ),
    "pm_far_plain": ("pm", "plain", (1e-3, 1e3), X_PM, 0.0),
    # 3. saved / loaded, and first exit
    "pm_far_saved": ("pm", "saved", (1e-3, 1e3), X_PM, 0.0),
    "flat_far_saved": (
        "flat",
        "saved",
        (1e3, 1e-3, 1.0),
        S((-1.2, 0.0), (0.0, 0.3), (2.5, 2.5)),
        0.0,
    ),
    "exit_eq": ("exit", "many", (1, 1, 1), S((-1.2, 0.6), (0.0, 0.0), (2.0, -2.0)), 0.0),
    "exit_far": ("exit", "many", (1e-3, 1.0, 1e3), S((0.0, 1.0), (0.0, 0.0), (2.0, -2.0)), 0.0),
    "exit_far_saved": (
        "exit",
        "saved",
        (1e-3, 1.0, 1e3),
        S((0.0, 1.0), (0.0, 0.0), (2.0, -2.0)),
        0.0,
    ),
    # 4. t > 0
    "pm_far_mid": ("pm", "many", (1e-3, 1e3), X_PM, 1.0),
    "pm_far_late": ("pm", "many", (1e-3, 1e3), X_PM, 1.85),
    "si5_mix_late": (
        "si5",
        "many",
        (1e2, 1, 1e-2, 1e-3, 10),
        S((-1.5, -1.5), (0.0, -1.0), (3.5, 3.5)),
        1.35,
    ),
    "neg_deep_late": ("neg", "many", (1.0, -0.9, 0.1), S((0.0, 0.0), (1.0, 0.5), (-3.0, 2.0)), 0.9),
    "pm_far_sep_late": ("pm", "sep", (1e-3, 1e3), X_PM, 1.85),
    "swing_far_late": (
        "swing",
        "many",
        (1e-3, 1.0, 1e3),
        S((0.0, 0.0), (-0.5, -0.5), (2.5, -3.0)),
        1.8,
    ),
    "flat_far_late": (
        "flat",
        "many",
        (1e3, 1e-3, 1.0),
        S((-1.2, 0.0), (0.0, 0.3), (2.5, 2.5)),
        0.9,
    ),
    # 5. quiet components (no solve warns) pushed by the weights, t > 0 and cancellation
    "siq_1k_sep": ("siq", "sep", (1.0, 1e3), X_SIQ, 0.0),
    "siq_k1_sep": ("siq", "sep", (1e3, 1.0), X_SIQ2, 0.0),
    "siq_1k_sep_mid": ("siq", "sep", (1.0, 1e3), X_SIQ, 1.0),
    "siq_1k_sep_late": ("siq", "sep", (1.0, 1e3), X_SIQ, 1.9),
    "siq_1k_saved": ("siq", "savedsep", (1.0, 1e3), X_SIQ, 0.0),
    "siq_1k_many": ("siq", "many", (1.0, 1e3), X_SIQ, 0.0),
    "siq_big_sep": ("siq", "sep", (1e3, 1e3), X_SIQ, 0.0),
    "pmq_1k_sep": ("pmq", "sep", (1.0, 1e3), X_PM, 0.0),
    "pmq_1k_sep_late": ("pmq", "sep", (1.0, 1e3), X_PM, 1.85),
    "pmq_m_sep": ("pmq", "sep", (1e-3, 1e3), X_PM, 0.0),
    "siw_mix": ("siw", "many", (1e-3, 1e3, 1.0), X_SIW, 0.0),
    "siw_mix_sep": ("siw", "sep", (1e-3, 1e3, 1.0), X_SIW, 0.0),
    "siw_mix_late": ("siw", "many", (1e-3, 1e3, 1.0), X_SIW, 1.9),
    "siw_mix_sep_late": ("siw", "sep", (1e-3, 1e3, 1.0), X_SIW, 1.9),
    "siw_eq": ("siw", "many", (1, 1, 1), S((0.0, 2.0), (0.0, 0.7), (-4.5, -4.5)), 0.0),
    "neg_c_sep": ("neg", "sep", (1.0, -0.99, 0.0), S((0.0, 0.0), (0.5, 0.3), (-3.0, 2.0)), 0.0),
    "neg_c_sep_late": (
        "neg",
        "sep",
        (1.0, -0.99, 0.0),
        S((0.0, 0.0), (0.5, 0.3), (-3.0, 2.0)),
        0.9,
    ),
    # 6. the combination's value brought to ≈ 0 between the goals by the weights, read late
    "siq_1k_sep_t15": ("siq", "sep", (1.0, 1e3), X_SIQ, 1.5),
    "siq_1k_sep_t18": ("siq", "sep", (1.0, 1e3), X_SIQ, 1.8),
    "siq_1k_sep_t195": ("siq", "sep", (1.0, 1e3), X_SIQ, 1.95),
    "siq_1k_many_late": ("siq", "many", (1.0, 1e3), X_SIQ, 1.9),
    "siq_1k_saved_late": ("siq", "savedsep", (1.0, 1e3), X_SIQ, 1.9),
    "siq_zero_sep": ("siq", "sep", (1.0, 2e4), X_Z, 0.0),
    "siq_zero_sep_mid": ("siq", "sep", (1.0, 2e4), X_Z, 1.0),
    "siq_zero_sep_late": ("siq", "sep", (1.0, 2e4), X_Z, 1.9),
    "siq_plain_late": ("siq", "plain", (1.0, 1e3), X_SIQ, 1.9),
    "pmq_z_sep_late": ("pmq", "sep", (1.0, 300.0), S((1.5, 0.0), (0.3, 0.0), (-3.0, 2.5)), 1.9),
    "siw_z_sep_late": (
        "siw",
        "sep",
        (1.0, 50.0, 1.0),
        S((1.5, 0.0), (0.0, 0.0), (-4.5, -4.0)),
        1.9,
    ),
    "siw_z_many_late": (
        "siw",
        "many",
        (1.0, 50.0, 1.0),
        S((1.5, 0.0), (0.0, 0.0), (-4.5, -4.0)),
        1.9,
    ),
    "siqc_1k_sep": ("siqc", "sep", (1.0, 1e3), X_C, 0.0),
    "siqc_1k_sep_mid": ("siqc", "sep", (1.0, 1e3), X_C, 1.0),
    "siqc_1k_sep_late": ("siqc", "sep", (1.0, 1e3), X_C, 1.9),
    "siqc_1k_many_late": ("siqc", "many", (1.0, 1e3), X_C, 1.9),
    "siqc_eq_sep_late": ("siqc", "sep", (1.0, 1.0), X_C, 1.9),
    "siq_1k_se4_mid": ("siq", "sep:store_every=4", (1.0, 1e3), X_SIQ, 1.0),
    "siq_1k_se4_late": ("siq", "sep:store_every=4", (1.0, 1e3), X_SIQ, 1.5),
    "siq_1k_mixdt_late": ("siq", "mixdt", (1.0, 1e3), X_SIQ, 1.9),
    "siq_1k_mixdt": ("siq", "mixdt", (1.0, 1e3), X_SIQ, 0.0),
    "si3_far_sep": (
        "si3",
        "sep",
        (1e3, 1, 1e-3),
        S((1.0, 0, 0), (0, 0.5, 0), (-2.5, -2.5, 2.5)),
        0.0,
    ),
    "si3_far_sep_late": (
        "si3",
        "sep",
        (1e3, 1, 1e-3),
        S((1.0, 0, 0), (0, 0.5, 0), (-2.5, -2.5, 2.5)),
        0.95,
    ),
}


def truth_of(name):
    fam, _flow, w, X, t = C26[name]
    path = OUT / f"{name}_truth.json"
    if path.exists():
        return json.loads(path.read_text())
    t0 = time.perf_counter()
    if fam in LQ:
        v = lq_truth(FAM[fam](), w, X, t)
        rec = dict(tag="lq", v=v.tolist(), se=[0.0] * len(X))
    else:
        v, se, extra = fine_truth(fam, w, X, t)
        rec = dict(tag="fine", v=v.tolist(), se=se.tolist(), **extra)
    rec["seconds"] = time.perf_counter() - t0
    path.write_text(json.dumps(rec, indent=1))
    return rec


def solve_of(name):
    fam, flow, w, X, t = C26[name]
    comps, solve_warn = components(fam, flow)
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        c = gridlbc.combine(comps, list(w))
        comb_warn = _rec(ws)
        v = np.asarray(c.value(X, t), float)
        e = np.asarray(c.error_estimate(X, t), float)
        alpha = np.asarray(c.blend_weights(X, t), float)
        vi = [np.asarray(s.value(X, t), float).tolist() for s in comps]
        ei = [np.asarray(s.error_estimate(X, t), float).tolist() for s in comps]
        read_warn = _rec(ws)[len(comb_warn) :]
    rec = dict(
        family=fam,
        flow=flow,
        weights=list(w),
        states=X.tolist(),
        t=t,
        kind=type(c).__name__,
        exact=bool(getattr(c, "exact", False)),
        reason=getattr(c, "reason", None),
        v=v.tolist(),
        e=e.tolist(),
        alpha=alpha.tolist(),
        v_i=vi,
        e_i=ei,
        solve_warnings=solve_warn,
        combine_warnings=comb_warn,
        read_warnings=read_warn,
        diagnostics=[str(getattr(s, "diagnostics", ""))[:300] for s in comps[:1]],
    )
    (OUT / f"{name}_solve.json").write_text(json.dumps(rec, indent=1))
    return rec


def wall_check(name):
    """The composite LQ problem on a 1.5× wider box (same spacing), direct solve at 2× vs the
    Riccati mix: does the wall matter at the states read?"""
    fam, _flow, w, X, t = C26[name]
    f = FAM[fam]()
    base, gs = lq_problem(f)
    g = composite_cost(gs, w, base.temperature)
    axes = [Axis(1.5 * a.lo, 1.5 * a.hi, round((a.n - 1) * 1.5) + 1) for a in base.grid.axes]
    p = base.replace(grid=Grid(axes), terminal_cost=g)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s1 = gridlbc.solve(
            finer(base.replace(terminal_cost=g), 2.0), dt=base.horizon / 400, error_estimate=False
        )
        s2 = gridlbc.solve(finer(p, 2.0), dt=base.horizon / 400, error_estimate=False)
    print(name, "box", s1.value(X, t), "wide", s2.value(X, t), "riccati", lq_truth(f, w, X, t))


def table():
    rows = []
    for name in C26:
        ps, pt = OUT / f"{name}_solve.json", OUT / f"{name}_truth.json"
        if not (ps.exists() and pt.exists()):
            continue
        s, tr = json.loads(ps.read_text()), json.loads(pt.read_text())
        lam = problem_of(s["family"])[0].temperature
        warned = bool(s["solve_warnings"] or s["combine_warnings"])
        for i, x in enumerate(s["states"]):
            v, e, vs = s["v"][i], s["e"][i], tr["v"][i]
            err = abs(v - vs) / max(abs(vs), lam)
            rel_e = e / max(abs(v), lam)
            rows.append(
                dict(
                    name=name,
                    x=x,
                    v=v,
                    vs=vs,
                    se=tr["se"][i],
                    err=err,
                    rel_e=rel_e,
                    abs_err=abs(v - vs),
                    e=e,
                    warned=warned,
                    kind=s["kind"],
                    sw=len(s["solve_warnings"]),
                    cw=len(s["combine_warnings"]),
                )
            )
    n = len(rows)
    off = [r for r in rows if r["err"] > 0.10]
    silent = [r for r in off if not r["warned"]]
    cov = [r for r in rows if r["e"] >= 0.5 * r["abs_err"]]
    over = [r for r in rows if r["e"] > 10 * r["abs_err"] and r["rel_e"] > 0.05]
    by = {}
    for r in rows:
        by.setdefault(r["name"], []).append(r)
    false = [k for k, rs in by.items() if rs[0]["warned"] and all(r["err"] < 0.02 for r in rs)]
    false_c = [k for k, rs in by.items() if rs[0]["cw"] and all(r["err"] < 0.02 for r in rs)]
    warned_c = [k for k, rs in by.items() if rs[0]["cw"]]
    quiet = [k for k, rs in by.items() if not rs[0]["warned"]]
    for r in rows:
        flag = ("SILENT" if r in silent else "off" if r in off else "") + (
            " under" if r["e"] < 0.5 * r["abs_err"] and r["err"] > 0.02 else ""
        )
        print(
            f"{r['name']:17s} {np.round(r['x'], 2)!s:18s} v {r['v']:9.4f} v* {r['vs']:9.4f}"
            f" ±{r['se']:.4f} err {100 * r['err']:6.1f}% ê {r['e']:.4f} ({100 * r['rel_e']:5.1f}%)"
            f" w{r['sw']}/{r['cw']} {'ex' if r['kind'] == 'CombinedSolution' else 'Co'} {flag}"
        )
    print(
        f"pairs {n}; >10% off {len(off)}; silent {len(silent)}; coverage {len(cov)}/{n}; "
        f"over-reads {len(over)}; false warnings {len(false)} {false}"
    )
    print(
        f"combinations {len(by)}; quiet (no warning anywhere) {len(quiet)}; combine warned "
        f"{len(warned_c)}, of which every pair < 2 %: {len(false_c)} {false_c}"
    )
    print("over-reads:", [(r["name"], r["x"]) for r in over])


if __name__ == "__main__":
    args = sys.argv[1:]
    OUT.mkdir(parents=True, exist_ok=True)
    if args and args[0] == "--table":
        table()
        sys.exit()
    if args and args[0] == "--wall":
        for n in args[1:]:
            wall_check(n)
        sys.exit()
    mode = "both"
    if args and args[0] in ("--truth", "--solve"):
        mode, args = args[0][2:], args[1:]
    names = list(C26) if args == ["--all"] or not args else args
    for name in names:
        print(name, flush=True)
        if mode in ("both", "truth"):
            truth_of(name)
        if mode in ("both", "solve"):
            solve_of(name)
    table()
