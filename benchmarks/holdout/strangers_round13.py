"""Stranger round 13: kinds of problem rounds 3–12 did not cover, posed as a new user would with
the public API (SPEC §9–10):

- a user's own system with a state-dependent input matrix B(x) (so state-dependent noise
  λ B R⁻¹ Bᵀ), a fast narrow local flow in a quiet box, noise and control on one axis only with
  a noiseless axis carried by a nonlinear flow; first exit and finite horizon;
- a narrow cheap trough in the STATE cost of a first-exit task, midway between nodes, running
  towards the exit (the sub-cell excess S is not computed for q in first exit), in 2-D and 3-D,
  with cheap and expensive control;
- λ at the extremes (0.01, 3) in first exit;
- average cost on a 3-D torus with a narrow well, and on a torus with a fast local flow;
- ``gridlbc.combine`` of two first-exit solutions (its Σ|α_i| ê_i).

Not run by the tests. Layout as rounds 11–12 (``P13``: name → (builder, states, truth, tag)); the
runner, the table and ``--levels``/``--finer`` are round 12's, pointed at this round's problems
and results folder.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round13.py NAME [NAME ...]
        (the default solve, then the truth; both saved under strangers_round13_results/)
    ... --truth NAME ...   (the truth only)
    ... --levels NAME ...  (v or c on the grids h, 2h, 4h, the phase pair, 2× and 4× finer)
    ... --finer NAME ...   (the default solve with its estimate on 2× the cells per axis)
    ... --tol NAME ...     (gridlbc.solve(problem, tol=0.03, states=X) against the truth)
    ... --table            (the table and the tally from the saved results)

Truths ("tag"):

- "bvp": the problem reduces to x₀ alone (costs, exit and B(x) of x₀; the other axes free and
  not in the costs): my own second-order finite-difference solve (not the library's) of
  (q/λ) z = a z′ + (λ b²/2R) z″ on [−2, a_E], z′(−2) = 0, z(a_E) = e^{−g_E/λ}, with 400 001
  and 800 001 nodes; the uncertainty is their difference.
- "1-D": a finite horizon that reduces to x₀: my own Crank–Nicolson solve (four implicit Euler
  half-steps first) of ∂_τ z = a z′ + (λb²/2R) z″ − (q/λ) z on [−2, 2] with reflecting ends,
  20 001 nodes and T/4000, checked against 40 001 nodes and T/8000; the uncertainty is their
  difference. ``hz_one_axis`` adds the noiseless axis's cost along its deterministic path
  (scipy solve_ivp, rtol 1e-10).
- "eigx": ẋ = u, q = q(x₀), exit x₁ ≥ a_E with g_E(x₀): x₀ and x₁ are independent under the
  passive dynamics, so z = Σ_k φ_k(x₀) ⟨φ_k, e^{−g_E/λ}⟩ E_{x₁}[e^{−μ_k τ}], with (φ_k, μ_k)
  the Neumann eigenpairs of (λ/2R) d² − q/λ on [−2, 2] (cell-centred differences, scipy
  eigh_tridiagonal) and E[e^{−μτ}] = cosh(κ(x₁+2))/cosh(κ(a_E+2)), κ² = 2Rμ/λ. 4000 and
  8000 cells (all modes with μ below a cut where cosh ratios are < 1e-16 of the first); the
  uncertainty is their difference. A 3-D version has x₂ free: z does not depend on it.
- "eig": average cost, q a sum of one-axis functions (round 12's eig_truth), or with a drift
  a(x₀) on the torus: the principal eigenvalue of −(λ²/2R) d² − λ a d + q on the periodic
  interval (central differences, scipy eigs shift-invert), 40 000 and 80 000 points.
- combination: the two components' exact z (eigx) summed, v = −λ log(z₁ + z₂).

Relative error and estimate as in round 12 (error (v − v*)/max(|v*|, λ), est ê/max(|v|, λ); for
c: relative to c; "w": the default solve raised a ResolutionWarning). ``combo_trough`` is
``gridlbc.combine`` of ``solve_many(fe_trough(), [g_A, g_B])`` (exit costs 0.6 (x₀ ± 1)²): its
v and Σ|α_i| ê_i; "w" if a component's solve warned.

Checks of the truths (2026-12-05): the Crank–Nicolson solver against the exact LQ value of
hz_one_axis's x₀ part (ẋ = u, q = 0.2, g = 1.5 x², T = 1, λ = 0.3: v = 0.375 x² + 0.2 + 0.15 log 4)
to 1e-7 at x₀ = 0, 0.5 and 1e-5 at −1 (the reflecting wall); ``hz_headwind``'s CN truth (2.1550,
1.7544, 1.1680) against the library's own 2-D solve on the default 81² grid with Δt = 0.001875
(2.1218, 1.7399, 1.1559: within that grid's spatial error); the eigen-expansion at (−0.5, 0) of
fe_trough gives 6.3241 where a constant q = 2 gives exactly √(2Rq)·1 = 6.3246 (the lane is 0.5
away and cannot help; q ≤ 2 bounds v by it). A first version cut the modes too early and gave
6.564 there, above that bound: the cut now keeps every mode below the continuum (μ ≤ max q/λ).

First run (library of commit 5f52743, 2026-12-05, one thread)::

    problem            state          predicted     truth  tag      ±    error     est est/err  w wc   t/s
    fe_gain_step       [-1.5, 0.0]       6.3458    6.6856  bvp  0.00%   -5.08%   7.85%    1.54  Y      0.1
    fe_gain_step       [-0.6, 0.5]       1.6047    1.5944  bvp  0.00%   +0.65%   6.55%   10.13  Y      0.1
    fe_gain_step       [0.0, -1.0]       0.3227    0.3230  bvp  0.00%   -0.08%   6.55%   77.41  Y      0.1
    fe_gain_hot        [-1.5, 0.0]       8.4608    8.3908  bvp  0.00%   +0.83%   1.35%    1.62  n      0.1
    fe_gain_hot        [-0.6, 0.5]       3.7459    3.7082  bvp  0.00%   +1.02%   2.36%    2.33  n      0.1
    fe_gain_hot        [0.0, -1.0]       1.1309    1.1222  bvp  0.00%   +0.29%   1.35%    4.65  n      0.1
    fe_headwind        [-1.0, 0.0]       2.0089    2.0836  bvp  0.00%   -3.59%  17.53%    4.89  Y      0.0
    fe_headwind        [-0.3, 0.5]       1.3107    1.3836  bvp  0.00%   -5.27%  26.88%    5.10  Y      0.0
    fe_headwind        [0.0, -1.0]       0.4924    0.4945  bvp  0.00%   -0.42%  14.87%   35.56  Y      0.0
    fe_headwind_cold   [-1.0, 0.0]       1.6330    2.1690  bvp  0.00%  -24.71%  21.75%    0.88  Y      0.1
    fe_headwind_cold   [-0.3, 0.5]       1.1717    1.4690  bvp  0.00%  -20.23%  30.39%    1.50  Y      0.1
    fe_headwind_cold   [0.0, -1.0]       0.2965    0.4500  bvp  0.00%  -34.11%  25.25%    0.74  Y      0.1
    hz_headwind        [-1.0, 0.0]       1.5881    2.1550  1-D  0.00%  -26.30%   0.06%    0.00  n      0.6
    hz_headwind        [-0.3, 0.5]       1.1282    1.7544  1-D  0.00%  -35.69%   0.08%    0.00  n      0.6
    hz_headwind        [0.0, -1.0]       1.0164    1.1680  1-D  0.00%  -12.98%   0.07%    0.01  n      0.6
    hz_gain_step       [-1.5, 0.0]       6.9223    6.9223  1-D  0.00%   +0.00%   0.04% 2708.28  n      0.9
    hz_gain_step       [-0.6, 0.5]       1.4094    1.4986  1-D  0.00%   -5.95%   4.63%    0.78  n      0.9
    hz_gain_step       [0.0, -1.0]       0.8533    0.8699  1-D  0.00%   -1.91%   0.34%    0.18  n      0.9
    hz_gust            [-1.0, 0.0]       2.2051    3.4148  1-D  0.00%  -35.43%  18.85%    0.53  n      0.7
    hz_gust            [-0.3, 0.5]       1.8288    3.2467  1-D  0.00%  -43.67%  22.27%    0.51  n      0.7
    hz_gust            [0.3, -1.0]       1.0389    1.0477  1-D  0.00%   -0.83%   0.59%    0.70  n      0.7
    hz_one_axis        [0.0, -1.0]       3.5424    3.5421  1-D  0.00%   +0.01%   0.17%   22.54  Y      0.4
    hz_one_axis        [0.5, 0.0]        1.5017    1.5017  1-D  0.00%   +0.00%   0.17%  470.36  Y      0.4
    hz_one_axis        [-1.0, 0.2]       1.3194    1.1833  1-D  0.00%  +11.50%  10.15%    0.88  Y      0.4
    fe_trough          [0.02, -1.0]      7.2902    8.2007 eigx  0.01%  -11.10%  32.05%    2.89  Y      4.2
    fe_trough          [-0.5, 0.0]       3.7371    6.3241 eigx  0.00%  -40.91%  32.05%    0.78  Y      4.2
    fe_trough          [0.6, -0.5]       5.6057    8.8599 eigx  0.01%  -36.73%  32.05%    0.87  Y      4.2
    fe_trough_cold     [0.02, -1.0]      2.5698    2.8052 eigx  0.01%   -8.39%  29.88%    3.56  Y      0.3
    fe_trough_cold     [-0.5, 0.0]       1.3178    2.0000 eigx  0.00%  -34.11%  29.88%    0.88  Y      0.3
    fe_trough_cold     [0.6, -0.5]       1.9767    2.9045 eigx  0.01%  -31.94%  29.88%    0.94  Y      0.3
    fe_trough_warm     [0.02, -1.0]      3.9225    3.8863 eigx  0.00%   +0.93%   1.98%    2.12  n      0.4
    fe_trough_warm     [-0.5, 0.0]       1.9782    1.9952 eigx  0.00%   -0.85%   1.55%    1.82  n      0.4
    fe_trough_warm     [0.6, -0.5]       2.9669    2.9913 eigx  0.00%   -0.82%   1.55%    1.90  n      0.4
    fe_trough_3d       [0.06, -1.0, 0.0]    8.8927    8.6595 eigx  0.00%   +2.69%  30.68%   11.39  Y      1.4
    fe_trough_3d       [-0.5, 0.0, 1.0]    4.5854    6.2977 eigx  0.00%  -27.19%  30.68%    1.13  Y      1.4
    fe_trough_3d       [0.6, -0.5, -0.3]    6.8830    8.7696 eigx  0.00%  -21.51%  30.68%    1.43  Y      1.4
    combo_trough       [0.02, -1.0]      7.8186    8.7538 eigx  0.01%  -10.68%  29.25%    2.74  Y      1.8
    combo_trough       [-0.5, 0.0]       3.8804    6.4550 eigx  0.00%  -39.89%  30.67%    0.77  Y      1.8
    combo_trough       [0.6, -0.5]       5.6962    9.4108 eigx  0.01%  -39.47%  31.38%    0.79  Y      1.8
    avg_well_3d        c                 0.7467    0.7361  eig  0.00%   +1.44%   0.06%    0.04  n  n   1.7
    avg_well_3d        h [0.0, 0.0, 0.0]    0.2587    0.2636  eig  0.00%   -1.65%   2.66%    1.61  n      1.7
    avg_well_3d        h [0.5, 1.0, -1.0]    0.1993    0.2392  eig  0.00%  -13.30%   2.66%    0.20  n      1.7
    avg_well_3d        h [-1.5, -0.5, 1.0]    0.7163    0.8324  eig  0.00%  -13.95%   2.66%    0.19  n      1.7
    avg_gain_spot      c                 0.2070    0.2064  eig  0.00%   +0.30%   0.35%    1.16  n  n   0.6
    avg_gain_spot      h [-1.0, 0.0]     1.3004    1.3065  eig  0.00%   -0.46%   0.55%    1.18  n      0.6
    avg_gain_spot      h [0.1, 1.0]      0.2089    0.2094  eig  0.00%   -0.18%   0.60%    3.39  n      0.6
    avg_gain_spot      h [1.0, -0.5]     1.3580    1.3633  eig  0.00%   -0.39%   0.48%    1.23  n      0.6
    avg_flow           c                 0.4197    0.4198  eig  0.00%   -0.02%   0.10%    5.30  n  n   0.3
    avg_flow           h [-1.0, 0.0]     0.4822    0.4821  eig  0.00%   +0.02%   0.09%    4.24  n      0.3
    avg_flow           h [0.1, 1.0]      0.5185    0.5184  eig  0.00%   +0.03%   0.38%   12.37  n      0.3
    avg_flow           h [1.0, -0.5]     0.1131    0.1129  eig  0.00%   +0.04%   0.05%    1.26  n      0.3
    51 pairs; > 10 % off silently at 7 [('hz_headwind', 26.3), ('hz_headwind', 35.7), ('hz_headwind', 13.0), ('hz_gust', 35.4), ('hz_gust', 43.7), ('avg_well_3d', 13.3), ('avg_well_3d', 13.9)]; estimate < ½ an error above 2 % at 5 [('hz_headwind', 26.3, 0.06), ('hz_headwind', 35.69, 0.08), ('hz_headwind', 12.98, 0.07), ('avg_well_3d', 13.3, 2.66), ('avg_well_3d', 13.95, 2.66)]; false alarms (warned, every pair < 2 %): 0 []; truths uncertain beyond 2 %: []
    average cost c alone (its own estimate and check, whatever h's says): 3 solves; c > 10 % off with c's estimate ≤ 5 % at 0 []; c's estimate < ½ an error above 2 % at 0 []

Mechanisms (measured):

- ``hz_headwind`` (silent, −13 to −36 %, estimate 0.06–0.08 %): the solve's default step is
  Δt = 0.15 (10 steps, splitting, Courant 11, the rate read at the nodes, which see −3.7 of the
  gust's −8). v on every grid the estimate reads is the same to 0.2 %: h 1.58814, 2h 1.58819,
  4h 1.58744, pair 1.58821/1.58952 at (−1, 0) (each at its 2Δt, 4Δt), and so are 2× and 4×
  finer grids (1.625, 1.617): the scheme steps over the gust. On the 81² grid v is the same at
  Δt = 0.3, 0.15 and 0.075 (1.5881, 1.1282, 1.0164) and moves only below: 0.0375 → 1.6253,
  0.03 → 1.7161, 0.0075 → 2.1109, 0.001875 → 2.1218 (truth 2.1550). No term of the estimate
  sees it: the embedded/pair difference conflates h with Δt but the plateau spans Δt..4Δt, a
  step-halving check (Δt/2) would see nothing either, S and γ are for costs (γ 0.05–0.08 %;
  the drift between nodes is not sampled by anything). ``solve(tol=0.03, states=X)`` stops at
  once (estimate 0.04 %) on the same 81² grid with the same −26/−36/−13 %.
- ``hz_gust`` (silent, −35 % and −44 %, estimates 19 % and 22 %: half the error, not warned): the
  same step problem with a gust three cells wide (the grid resolves it; Δt = 0.15 again;
  Δt = 0.03 → 3.379, 0.0075 → 3.417 against 3.415). Here the embedded levels differ and the
  estimate at the states is about half the error, but a finite-horizon problem without an exit
  is judged at "the states that matter" = nodes with v ≤ the median of v: the gust RAISES v
  upstream of it, so the states it spoils leave the judged set. Over all 81² nodes 38 % have
  an estimate above 5 % and the 90th percentile is 22 %; the judged half lies downstream
  (estimates < 3 %). The 2× finer grid (161²) is −29 %/−37 % with estimates 23 %/28 % and is
  silent too. ``solve(tol=0.03, states=X)`` does fix it (7.4 s, 81², smaller step: −0.06 %,
  −0.21 %, −0.19 % with estimates 0.4–0.65 %).
- ``avg_well_3d`` (h silent −13 %/−14 % with h's estimate 2.7 %, c +1.44 % with c's estimate
  0.06 %): a well 0.15 h wide at a cell's centre; no node of 24³, 12³, 6³, 11³, 13³ sees it (q
  there ≥ 0.598 of 0.6): c on h, 2h, 4h, pair: 0.74673, 0.74552, 0.74029, 0.74537/0.74513; 48³
  (a node on the well) 0.73044 (c* 0.73613) with h +6 %. The average cost has no S (no horizon
  to give τ) and no γ, so only the embedded term speaks and it is blind to the well (the
  "S-less" gap of round 12's ``avg_well_cold``, now in 3-D and in h).
- The trough problems (``fe_trough*``, ``combo_trough``, warned, ratios 0.77–0.94) did not isolate
  the state cost's sub-cell excess in first exit: a lane narrower than a cell binds a path only
  where λ²/(2Rw²) < its depth, i.e. with little noise (λ/R = 0.005–0.02 here), and there the
  first-exit scheme's own error dominates: WITHOUT the lane (q ≡ 2) the 81² solve of fe_trough
  is 3.7371 at (−0.5, 0) against the exact 6.3246 (−41 %), and 2× and 4× finer grids give
  4.95, 5.80 with the lane (about order ½). The embedded term sees that (32 %, observed order
  negative) and covers the total. ``solve(fe_trough_cold, tol=0.03, states=X)`` refined to
  161 × 5121 (x₁, along the lane, 64×; x₀, across it, 2×) in 19.9 s and stopped at
  "max_refinements = 6 rounds were spent", estimated 72 %, actual −21/−6.5/−14 %.
- ``fe_trough_3d`` first at λ = 0.1, w = 0.03 (v* 7.6–8.2, v/λ ≈ 80): the default solve's z
  underflowed at two of three states (v = inf, UnderflowWarning and ResolutionWarning): the
  floor of z (1e-38) caps v/λ at about 88, as docs/limitations says.
- Controls and covered cases: ``fe_gain_hot`` (λ = 3), ``fe_trough_warm``, ``avg_flow`` (a jet),
  ``avg_gain_spot`` (a narrow noisy spot in B(x) on the torus) within 1 %, quiet;
  ``fe_headwind_cold`` (λ = 0.01, −20 to −34 %) warned with 0.74–1.5× the error;
  ``combine``'s Σ|α_i| ê_i is 0.77–2.7× the combination's error.
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg  # noqa: F401  (sp.linalg.splu)
import strangers_round12 as r12
from scipy.integrate import solve_ivp
from scipy.linalg import eigh_tridiagonal
from scipy.sparse.linalg import eigs, spsolve
from strangers_round12 import HERE, _bump, const, eig_truth, free, ripple, torus

import gridlbc
from gridlbc import Axis, Grid, Problem
from gridlbc.systems import ControlAffineSystem

OUT = HERE / "strangers_round13_results"
PI = math.pi


# ---------------- a user's own system ---------------------------------------------------------
class Shaped(ControlAffineSystem):
    """ẋ_i = a_i(x) + b_i(x) u_i on the controlled axes, ẋ_i = a_i(x) on the others.

    drift(x) -> (N, d); gain(x) -> (N, m), the diagonal of B on the controlled axes ``axes``."""

    def __init__(self, d, drift=None, gain=None, axes=None):
        self.state_dim = d
        self.axes = tuple(range(d)) if axes is None else tuple(axes)
        self.control_dim = len(self.axes)
        self.state_names = tuple(f"x{i}" for i in range(d))
        self._drift, self._gain = drift, gain

    def drift(self, x):
        x = self._states(x)
        return np.zeros_like(x) if self._drift is None else self._drift(x)

    def input_matrix(self, x):
        x = self._states(x)
        b = np.ones((len(x), self.control_dim)) if self._gain is None else self._gain(x)
        B = np.zeros((len(x), self.state_dim, self.control_dim))
        for j, i in enumerate(self.axes):
            B[:, i, j] = b[:, j]
        return B


def box(d, n, lo=-2.0, hi=2.0):
    return Grid([Axis(lo, hi, n)] * d)


def sig(y):
    return 0.5 * (1.0 + np.tanh(y))


A_E = 0.45


def xexit(a=A_E):
    return lambda x: np.asarray(x)[:, 0] >= a - 1e-12


# -------- B(x): the control gain (and the noise) steps up inside a cell ------------------------
BSTEP = (-0.475, 0.01)  # a cell's centre on 81 nodes, the step over about 2w


def bstep(y):
    return 0.25 + 1.75 * sig((y - BSTEP[0]) / BSTEP[1])


def fe_gain_step(lam=0.2, n=81):
    """ẋ₀ = b(x₀) u₀, ẋ₁ = u₁, b = 0.25 → 2 over 0.02 at a cell's centre (x₀ = −0.475): the
    noise λb² grows 64×; q = 1, exit x₀ ≥ 0.45, g_E = 0, λ = 0.2; 81²."""
    sys_ = Shaped(2, gain=lambda x: np.stack([bstep(x[:, 0]), np.ones(len(x))], 1))
    return Problem(sys_, box(2, n), None, state_cost=const(1.0), temperature=lam, exit=xexit())


def fe_gain_hot():
    """fe_gain_step at λ = 3 (q = 1, 81²)."""
    return fe_gain_step(lam=3.0)


# -------- a fast narrow headwind in a quiet box ------------------------------------------------
WIND = (-0.175, 0.02)  # midway between the nodes −0.2 and −0.15 (81 nodes)


def wind(y, F=-8.0):
    return F * _bump(*WIND)(y)


def fe_headwind(lam=0.2):
    """ẋ₀ = −8 e^{−(x₀−c)²/2w²} + u₀ (w = 0.02, midway between nodes: a gust against the way
    to the exit x₀ ≥ 0.45), ẋ₁ = u₁; q = 0.5, g_E = 0; 81²."""
    sys_ = Shaped(2, drift=lambda x: np.stack([wind(x[:, 0]), 0 * x[:, 0]], 1))
    return Problem(sys_, box(2, 81), None, state_cost=const(0.5), temperature=lam, exit=xexit())


def fe_headwind_cold():
    """fe_headwind at λ = 0.01."""
    return fe_headwind(lam=0.01)


def hz_headwind():
    """fe_headwind with a horizon and no exit: T = 1.5, g = 2 (x₀ − 0.5)², q = 0.5, λ = 0.2."""
    sys_ = Shaped(2, drift=lambda x: np.stack([wind(x[:, 0]), 0 * x[:, 0]], 1))
    return Problem(
        sys_,
        box(2, 81),
        1.5,
        lambda x: 2.0 * (x[:, 0] - 0.5) ** 2,
        state_cost=const(0.5),
        temperature=0.2,
    )


def hz_gain_step():
    """fe_gain_step's system (b = 0.25 → 2 over 0.02 at x₀ = −0.475) with a horizon and no exit:
    T = 1, g = 2 (x₀ − 0.5)², q = 0.5, λ = 0.2; 81²."""
    sys_ = Shaped(2, gain=lambda x: np.stack([bstep(x[:, 0]), np.ones(len(x))], 1))
    return Problem(
        sys_,
        box(2, 81),
        1.0,
        lambda x: 2.0 * (x[:, 0] - 0.5) ** 2,
        state_cost=const(0.5),
        temperature=0.2,
    )


def gust(y):
    return -5.0 * _bump(-0.3, 0.15)(y)  # three cells wide, 5 against the way


def hz_gust():
    """A fast local headwind three cells wide (ẋ₀ = −5 e^{−(x₀+0.3)²/2·0.15²} + u₀, ẋ₁ = u₁),
    T = 1.5, g = 2 (x₀ − 0.5)², q = 0.5, λ = 0.2; 81²."""
    sys_ = Shaped(2, drift=lambda x: np.stack([gust(x[:, 0]), 0 * x[:, 0]], 1))
    return Problem(
        sys_,
        box(2, 81),
        1.5,
        lambda x: 2.0 * (x[:, 0] - 0.5) ** 2,
        state_cost=const(0.5),
        temperature=0.2,
    )


# -------- noise and control on x₀ only; x₁ carried by a nonlinear flow with a fast spot -------
def flow1(y):
    return -0.4 * y + 3.0 * _bump(0.3, 0.06)(y)  # quiet inward flow, a fast kick near 0.3


def q1(y):
    return 0.5 * y**2


def g1(y):
    return (y - 1.0) ** 2


def hz_one_axis():
    """ẋ₀ = u (noise on x₀ only), ẋ₁ = −0.4 x₁ + 3 e^{−(x₁−0.3)²/2·0.06²} (no noise, no
    control); q = 0.2 + 0.5 x₁², g = 1.5 x₀² + (x₁ − 1)², T = 1, λ = 0.3; 81²."""
    sys_ = Shaped(2, drift=lambda x: np.stack([0 * x[:, 0], flow1(x[:, 1])], 1), axes=(0,))
    return Problem(
        sys_,
        box(2, 81),
        1.0,
        lambda x: 1.5 * x[:, 0] ** 2 + g1(x[:, 1]),
        state_cost=lambda x: 0.2 + q1(x[:, 1]),
        temperature=0.3,
    )


# -------- a cheap trough in q running to the exit ---------------------------------------------
def trough(c, w, base=2.0, depth=1.9):
    return lambda y: base - depth * _bump(c, w)(y)


TR2 = (0.025, 0.012)  # midway between the nodes 0 and 0.05 (81 nodes)


def fe_trough(lam=0.05, R=10.0, gE=None):
    """ẋ = u on [−2, 2]² (81²), q = 2 − 1.9 e^{−(x₀−c)²/2w²} (w = 0.012, midway between the
    nodes 0 and 0.05, which see q = 1.78): a cheap lane along x₁ towards the exit x₁ ≥ 1
    (g_E = 0); λ = 0.05 and expensive control R = 10 (little noise: a path can stay in the lane,
    whose confinement costs λ²/2Rw² ≈ 0.9 < 1.9)."""
    return Problem(
        free(2),
        box(2, 81),
        None,
        state_cost=lambda x: trough(*TR2)(x[:, 0]),
        temperature=lam,
        control_cost=R,
        exit=lambda x: np.asarray(x)[:, 1] >= 1.0 - 1e-12,
        exit_cost=0.0 if gE is None else gE,
    )


def fe_trough_cold():
    """fe_trough at λ = 0.02, R = 1 (confinement ≈ 1.4 < 1.9)."""
    return fe_trough(lam=0.02, R=1.0)


def fe_trough_warm():
    """fe_trough at λ = 0.2, R = 1: the noise (λ/R) throws a path out of the lane at once
    (confinement ≈ 140 ≫ 1.9): the lane barely matters (a near-control)."""
    return fe_trough(lam=0.2, R=1.0)


TR3 = (0.0625, 0.04)  # a cell's centre on 33 nodes (h = 0.125)


def fe_trough_3d():
    """3-D: ẋ = u on [−2, 2]³ (33³), q = 2 − 1.9 e^{−(x₀−c)²/2w²} (w = 0.04 = h/3, at a cell's
    centre, where the nodes see q = 1.44), exit x₁ ≥ 1 (g_E = 0), λ = 0.2, R = 10 (confinement
    λ²/2Rw² = 1.25 < 1.9). At λ = 0.1, w = 0.03 the default solve's desirability underflowed
    (UnderflowWarning, v = inf) at (0.0625, −1, 0) and (0.6, −0.5, −0.3), where v* = 7.6, 8.2."""
    return Problem(
        free(3),
        box(3, 33),
        None,
        state_cost=lambda x: trough(*TR3)(x[:, 0]),
        temperature=0.2,
        control_cost=10.0,
        exit=lambda x: np.asarray(x)[:, 1] >= 1.0 - 1e-12,
        exit_cost=0.0,
    )


def gA(y):
    return 0.6 * (y + 1.0) ** 2


def gB(y):
    return 0.6 * (y - 1.0) ** 2


# ---------------- average cost ----------------------------------------------------------------
WELL3 = (0.0833333, 0.025)  # a cell's centre on a 24-node torus (h = 1/6)


def well3(y):
    return 0.6 - 0.55 * _bump(*WELL3)(y)


def rip2(y):
    return 0.15 * (1.0 + np.sin(PI * y / 2))


def avg_well_3d():
    """3-D torus [−2, 2)³ (24³, h = 1/6), ẋ = u, q = 0.6 − 0.55 e^{−(x₀−c)²/2w²} (w = 0.025 =
    0.15 h, at a cell's centre) + 0.1 (1 − cos(πx₁/2)) + 0.15 (1 + sin(πx₂/2)), λ = 0.3."""
    return Problem(
        free(3),
        torus(3, 24),
        "average",
        state_cost=lambda x: well3(x[:, 0]) + ripple(x[:, 1]) + rip2(x[:, 2]),
        temperature=0.3,
    )


def flow_avg(y):
    return 0.5 + 4.0 * _bump(0.025, 0.03)(y)  # a quiet stream with a fast narrow jet


def q_avg(y):
    return 0.4 + 0.3 * np.cos(PI * y / 2)


def avg_flow():
    """2-D torus (80², h = 0.05), ẋ₀ = 0.5 + 4 e^{−(x₀−0.025)²/2·0.03²} + u₀ (a jet midway between
    nodes), ẋ₁ = u₁; q = 0.4 + 0.3 cos(πx₀/2) + 0.1 (1 − cos(πx₁/2)), λ = 0.5."""
    sys_ = Shaped(2, drift=lambda x: np.stack([flow_avg(x[:, 0]), 0 * x[:, 0]], 1))
    return Problem(
        sys_,
        torus(2, 80),
        "average",
        state_cost=lambda x: q_avg(x[:, 0]) + ripple(x[:, 1]),
        temperature=0.5,
    )


# ---------------- truths ----------------------------------------------------------------------
def bvp_1d(a_fun, b_fun, q_fun, lam, R=1.0, gE=0.0, lo=-2.0, a=A_E, ns=(400001, 800001)):
    """My own finite differences for (q/λ) z = a z′ + (λ b²/2R) z″, z′(lo) = 0, z(a) = e^{−g_E/λ};
    v at X[:, 0]; the uncertainty is the two resolutions' difference."""

    def one(n, y):
        x = np.linspace(lo, a, n)
        h = x[1] - x[0]
        D = lam * b_fun(x) ** 2 / (2 * R) / h**2
        C = a_fun(x) / (2 * h)
        lower = D - C  # coefficient of z_{i−1}
        upper = D + C
        main = -2 * D - q_fun(x) / lam
        # ghost z_{−1} = z_1 at lo; Dirichlet at a
        up = upper.copy()
        up[0] = upper[0] + lower[0]
        rhs = np.zeros(n)
        M = sp.diags([main, lower[1:], up[:-1]], [0, -1, 1], format="lil")
        M[n - 1, :] = 0
        M[n - 1, n - 1] = 1.0
        rhs[-1] = math.exp(-gE / lam)
        # scale: solve for z relative to e^{−g_E/λ}
        z = spsolve(M.tocsc(), rhs)
        return -lam * np.log(np.interp(y, x, z))

    def truth(X):
        y = np.asarray(X)[:, 0]
        v1, v2 = one(ns[0], y), one(ns[1], y)
        return v2, np.abs(v2 - v1)

    return truth


def cn_1d(
    a_fun,
    q_fun,
    g_fun,
    lam,
    T,
    R=1.0,
    lo=-2.0,
    hi=2.0,
    ns=((20001, 4000), (40001, 8000)),
    extra=None,
    b_fun=None,
):
    """My own Crank–Nicolson solve of ∂_τ z = a z′ + (λb²/2R) z″ − (q/λ) z, z(τ=0) = e^{−g/λ},
    reflecting ends (ghost nodes), to τ = T (four implicit Euler half-steps first); v at
    X[:, 0] (+ ``extra(X)``); the uncertainty is the two resolutions' difference."""

    def one(n, steps, y):
        x = np.linspace(lo, hi, n)
        h = x[1] - x[0]
        D = lam / (2 * R) / h**2 * (np.ones(n) if b_fun is None else b_fun(x) ** 2)
        C = a_fun(x) / (2 * h)
        lower, upper = D - C, D + C
        main = -2 * D - q_fun(x) / lam
        up, lw = upper.copy(), lower.copy()
        up[0] += lower[0]
        lw[-1] += upper[-1]
        M = sp.diags([main, lw[1:], up[:-1]], [0, -1, 1], format="csc")
        eye = sp.identity(n, format="csc")
        g = g_fun(x)
        shift = g.min()
        z = np.exp(-(g - shift) / lam)
        dt = T / steps
        lu_half = sp.linalg.splu((eye - 0.5 * dt * M).tocsc())
        for _ in range(4):  # Rannacher start: four implicit Euler steps of Δt/2
            z = lu_half.solve(z)
        lu = sp.linalg.splu((eye - 0.5 * dt * M).tocsc())
        B = (eye + 0.5 * dt * M).tocsr()
        for _ in range(steps - 2):
            z = lu.solve(B @ z)
        return shift - lam * np.log(np.interp(y, x, z))

    def truth(X):
        X = np.asarray(X)
        v = [one(n, k, X[:, 0]) + (0 if extra is None else extra(X)) for n, k in ns]
        return v[-1], np.abs(v[-1] - v[0])

    return truth


def one_axis_path(X, T=1.0):
    """∫₀ᵀ 0.5 x₁(t)² dt + (x₁(T) − 1)² along ẋ₁ = flow1(x₁)."""
    out = []
    for y0 in np.asarray(X)[:, 1]:
        s = solve_ivp(
            lambda t, y: [flow1(y[0]), q1(y[0])], (0, T), [y0, 0.0], rtol=1e-10, atol=1e-12
        )
        out.append(s.y[1, -1] + g1(s.y[0, -1]))
    return np.array(out)


def eigx(q_fun, lam, R=1.0, gEs=(None,), aE=1.0, lo=-2.0, hi=2.0, ns=(4000, 8000)):
    """z for ẋ = u, q(x₀), exit x₁ ≥ aE with exit costs g_E(x₀) (a list: one z each; v of the
    sum), by the eigen-expansion in x₀ (module docstring)."""

    def zs(n, X):
        h = (hi - lo) / n
        x = lo + (np.arange(n) + 0.5) * h
        D = lam / (2 * R) / h**2
        diag = -2 * D * np.ones(n) - q_fun(x) / lam
        diag[0] += D
        diag[-1] += D
        off = -D * np.ones(n - 1)
        mu0 = eigh_tridiagonal(-diag, off, eigvals_only=True, select="i", select_range=(0, 0))[0]
        # every mode up to the continuum's bottom (μ = max q/λ) and e^{−60} beyond it at the
        # states (the lowest modes are bound in the trough: exponentially small away from it)
        gapmin = max(aE - np.max(X[:, 1]), 1e-3)
        kcut = math.sqrt(2 * R * max(mu0, np.max(q_fun(x)) / lam) / lam) + 60.0 / gapmin
        mu, phi = eigh_tridiagonal(
            -diag, off, select="v", select_range=(-1.0, kcut**2 * lam / (2 * R))
        )
        kap = np.sqrt(2 * R * mu / lam)
        phi = phi / math.sqrt(h)  # orthonormal in L²
        out = []
        for gE in gEs:
            f = np.ones(n) if gE is None else np.exp(-gE(x) / lam)
            coef = h * phi.T @ f
            z = np.zeros(len(X))
            for i, (x0, x1) in enumerate(X[:, :2]):
                j = int(np.clip(np.searchsorted(x, x0) - 1, 0, n - 2))
                t = np.clip((x0 - x[j]) / h, 0.0, 1.0)
                ph = (1 - t) * phi[j] + t * phi[j + 1]
                ps = (
                    np.exp(kap * (x1 - aE))
                    * (1 + np.exp(-2 * kap * (x1 - lo)))
                    / (1 + np.exp(-2 * kap * (aE - lo)))
                )
                z[i] = np.sum(ph * coef * ps)
            out.append(z)
        return np.sum(out, axis=0)

    def truth(X):
        X = np.asarray(X)
        v = [-lam * np.log(zs(n, X)) for n in ns]
        return v[-1], np.abs(v[-1] - v[0])

    return truth


def ground_drift(a_fun, q_fun, lam, R=1.0, lo=-2.0, L=4.0, n=40000, b_fun=None):
    """Principal eigenpair of H = −(λ²/2R) d² − λ a d + q on the periodic interval: c and the
    relative value −λ log e (e the right eigenvector, min 0)."""
    x = lo + L * np.arange(n) / n
    h = L / n
    D = lam**2 / (2 * R) / h**2 * (1.0 if b_fun is None else b_fun(x) ** 2)
    C = lam * a_fun(x) / (2 * h)
    main = 2 * D + q_fun(x)
    lower = -D + C  # coefficient of e_{i−1}
    upper = -D - C
    H = sp.diags([main, lower[1:], upper[:-1]], [0, -1, 1], format="lil")
    H[0, n - 1] = lower[0]
    H[n - 1, 0] = upper[n - 1]
    val, vec = eigs(H.tocsc(), k=1, sigma=q_fun(x).min() - 1e-3, which="LM")
    e = np.abs(np.real(vec[:, 0]))
    hv = -lam * np.log(e / e.max())

    def rel(y):
        y = lo + np.mod(np.asarray(y) - lo, L)
        return np.interp(y, np.append(x, lo + L), np.append(hv, hv[0]))

    return float(np.real(val[0])), rel


def avg_flow_truth(X, ns=(40000, 80000)):
    X = np.asarray(X)
    out = []
    for n in ns:
        c0, h0 = ground_drift(flow_avg, q_avg, 0.5, n=n)
        c1, h1 = r12.ground(ripple, 0.5, n=n)
        hs = h0(X[:, 0]) + h1(X[:, 1])
        out.append(np.concatenate([[c0 + c1], hs]))
    return out[-1], np.abs(out[-1] - out[0])


def spot_b(y):
    return 0.3 + 1.7 * _bump(0.025, 0.012)(y)


def q_spot(y):
    return 0.4 - 0.3 * np.cos(PI * y / 2)


def avg_gain_spot():
    """2-D torus (80², h = 0.05), ẋ₀ = b(x₀) u₀ with b = 0.3 + 1.7 e^{−(x₀−0.025)²/2·0.012²} (a
    narrow spot of cheap control and 33× the noise, midway between nodes, at the cheapest place
    of q), ẋ₁ = u₁; q = 0.4 − 0.3 cos(πx₀/2) + 0.1 (1 − cos(πx₁/2)), λ = 0.3."""
    sys_ = Shaped(2, gain=lambda x: np.stack([spot_b(x[:, 0]), np.ones(len(x))], 1))
    return Problem(
        sys_,
        torus(2, 80),
        "average",
        state_cost=lambda x: q_spot(x[:, 0]) + ripple(x[:, 1]),
        temperature=0.3,
    )


def avg_gain_truth(X, ns=(40000, 80000)):
    X = np.asarray(X)
    out = []
    for n in ns:
        c0, h0 = ground_drift(zero, q_spot, 0.3, n=n, b_fun=spot_b)
        c1, h1 = r12.ground(ripple, 0.3, n=n)
        out.append(np.concatenate([[c0 + c1], h0(X[:, 0]) + h1(X[:, 1])]))
    return out[-1], np.abs(out[-1] - out[0])


def S(*states):
    return np.array(states, dtype=float)


def zero(y):
    return 0 * y


def one(y):
    return 0 * y + 1.0


P13 = {
    "fe_gain_step": (
        fe_gain_step,
        S((-1.5, 0.0), (-0.6, 0.5), (0.0, -1.0)),
        bvp_1d(zero, bstep, lambda y: 0 * y + 1.0, 0.2),
        "bvp",
    ),
    "fe_gain_hot": (
        fe_gain_hot,
        S((-1.5, 0.0), (-0.6, 0.5), (0.0, -1.0)),
        bvp_1d(zero, bstep, lambda y: 0 * y + 1.0, 3.0),
        "bvp",
    ),
    "fe_headwind": (
        fe_headwind,
        S((-1.0, 0.0), (-0.3, 0.5), (0.0, -1.0)),
        bvp_1d(wind, one, lambda y: 0 * y + 0.5, 0.2),
        "bvp",
    ),
    "fe_headwind_cold": (
        fe_headwind_cold,
        S((-1.0, 0.0), (-0.3, 0.5), (0.0, -1.0)),
        bvp_1d(wind, one, lambda y: 0 * y + 0.5, 0.01),
        "bvp",
    ),
    "hz_headwind": (
        hz_headwind,
        S((-1.0, 0.0), (-0.3, 0.5), (0.0, -1.0)),
        cn_1d(wind, lambda y: 0 * y + 0.5, lambda y: 2.0 * (y - 0.5) ** 2, 0.2, 1.5),
        "1-D",
    ),
    "hz_gain_step": (
        hz_gain_step,
        S((-1.5, 0.0), (-0.6, 0.5), (0.0, -1.0)),
        cn_1d(zero, lambda y: 0 * y + 0.5, lambda y: 2.0 * (y - 0.5) ** 2, 0.2, 1.0, b_fun=bstep),
        "1-D",
    ),
    "hz_gust": (
        hz_gust,
        S((-1.0, 0.0), (-0.3, 0.5), (0.3, -1.0)),
        cn_1d(gust, lambda y: 0 * y + 0.5, lambda y: 2.0 * (y - 0.5) ** 2, 0.2, 1.5),
        "1-D",
    ),
    "hz_one_axis": (
        hz_one_axis,
        S((0.0, -1.0), (0.5, 0.0), (-1.0, 0.2)),
        cn_1d(zero, lambda y: 0 * y + 0.2, lambda y: 1.5 * y**2, 0.3, 1.0, extra=one_axis_path),
        "1-D",
    ),
    "fe_trough": (
        fe_trough,
        S((0.025, -1.0), (-0.5, 0.0), (0.6, -0.5)),
        eigx(trough(*TR2), 0.05, R=10.0),
        "eigx",
    ),
    "fe_trough_cold": (
        fe_trough_cold,
        S((0.025, -1.0), (-0.5, 0.0), (0.6, -0.5)),
        eigx(trough(*TR2), 0.02),
        "eigx",
    ),
    "fe_trough_warm": (
        fe_trough_warm,
        S((0.025, -1.0), (-0.5, 0.0), (0.6, -0.5)),
        eigx(trough(*TR2), 0.2),
        "eigx",
    ),
    "fe_trough_3d": (
        fe_trough_3d,
        S((0.0625, -1.0, 0.0), (-0.5, 0.0, 1.0), (0.6, -0.5, -0.3)),
        eigx(trough(*TR3), 0.2, R=10.0),
        "eigx",
    ),
    "combo_trough": (
        lambda: fe_trough(gE=lambda x: gA(x[:, 0])),
        S((0.025, -1.0), (-0.5, 0.0), (0.6, -0.5)),
        eigx(trough(*TR2), 0.05, R=10.0, gEs=(gA, gB)),
        "eigx",
    ),
    "avg_well_3d": (
        avg_well_3d,
        S((0.0, 0.0, 0.0), (0.5, 1.0, -1.0), (-1.5, -0.5, 1.0)),
        eig_truth([well3, ripple, rip2], 0.3),
        "eig",
    ),
    "avg_gain_spot": (
        avg_gain_spot,
        S((-1.0, 0.0), (0.1, 1.0), (1.0, -0.5)),
        avg_gain_truth,
        "eig",
    ),
    "avg_flow": (
        avg_flow,
        S((-1.0, 0.0), (0.1, 1.0), (1.0, -0.5)),
        avg_flow_truth,
        "eig",
    ),
}


def combo_quick(name):
    """combine() of the trough problem's two first-exit solves (exit costs gA, gB), saved as a
    default solve would be (warned: either component's solve warned)."""
    _b, X, *_ = P13[name]
    costs = [lambda x: gA(x[:, 0]), lambda x: gB(x[:, 0])]
    save_combination(name, X, lambda: gridlbc.solve_many(fe_trough(), costs))


def save_combination(name, X, components, weights=None, out=None, warned=None):
    """combine() of the solutions ``components()`` returns (with ``weights``), read at ``X``
    with its error estimate and its components', saved under ``out`` (default: this round's
    results) as a default solve would be; ``warned`` (default round 12's) judges the warnings
    the solves and the combination raised. Rounds 16 and 17 save theirs by it."""
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        sols = components()
        both = gridlbc.combine(sols, weights=weights)
        v, est = both.value(X), both.error_estimate(X)
    dt = time.perf_counter() - t0
    comp = [(s.value(X).tolist(), s.error_estimate(X).tolist()) for s in sols]
    result = dict(
        name=name,
        X=X.tolist(),
        time=dt,
        kind="exit",
        v=np.atleast_1d(v).tolist(),
        est=np.atleast_1d(est).tolist(),
        components=comp,
        warned=(warned or r12._warned)(w),
        warnings=[f"{x.category.__name__}: {str(x.message)[:300]}" for x in w],
    )
    print(f"{name}: v {np.round(v, 4).tolist()} est {np.round(est, 4).tolist()} t={dt:.1f}s")
    print("  components", comp, "warnings", result["warnings"], flush=True)
    ((out or OUT) / f"{name}_solve.json").write_text(json.dumps(result, indent=1))


def tol_run(name, tol=0.03):
    build, X, *_ = P13[name]
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s = gridlbc.solve(build(), tol=tol, states=X)
    dt = time.perf_counter() - t0
    tr = json.loads((OUT / f"{name}_truth.json").read_text())["vstar"]
    p = build()
    if p.average_cost:
        v, e = [s.average_cost, *s.value(X).tolist()], [s.average_cost_error, *s.error_estimate(X)]
    else:
        v, e = s.value(X).tolist(), s.error_estimate(X).tolist()
    print(f"  {name} tol={tol}: {dt:.1f} s, grid {[a.n for a in s.problem.grid.axes]}")
    for vi, ei, ti in zip(v, e, tr):
        sc = max(abs(ti), p.temperature)
        print(
            f"    v={vi:.5f} truth={ti:.5f} error={100 * (vi - ti) / sc:+.2f}% est={100 * ei / sc:.2f}%"
        )
    for x in w:
        print("   ", x.category.__name__, str(x.message)[:600])


def main(argv):
    r12.P12, r12.OUT = P13, OUT  # round 12's runner and table on this round's problems
    OUT.mkdir(exist_ok=True)
    if "--table" in argv:
        r12.table()
        return
    for name in [a for a in argv if not a.startswith("--")]:
        if "--levels" in argv:
            r12.levels(name)
        elif "--finer" in argv:
            r12.finer(name)
        elif "--tol" in argv:
            tol_run(name)
        else:
            if "--truth" not in argv:
                combo_quick(name) if name.startswith("combo") else r12.quick(name)
            r12.truth(name)


if __name__ == "__main__":
    main(sys.argv[1:])
