"""Stranger round 14: finite-horizon problems that rounds 3–13 did not cover, posed as a new user
would with the public API (SPEC §1–2, §10):

- LONG horizons (T = 20–25, v ≈ c·T + h) and a VERY SHORT one (T far below the time the noise
  takes to cross a cell);
- terminal costs that are steep but smooth (50 |x − c|² at λ = 0.05), discontinuous (the
  indicator of a box), a minimum of several goals, kinks between the nodes;
- a box too SMALL (the optimal paths press against its edge: reflection), a box much larger
  than where the paths go, an axis 10× finer than the other, a 3-D state with a periodic angle,
  a closed velocity and a closed position (a pendulum on a rail);
- ``gridlbc.combine`` of ``solve_many`` components with weights over six orders of magnitude,
  and with a negative weight (cancellation);
- λ = 3 (Van der Pol) and λ = 0.01 (Duffing) on a 2-D nonlinear system, 151², as a user picks.

Not run by the tests. Layout as rounds 12–13 (``P14``: name → (builder, states, truth, tag));
the runner, the table and ``--levels``/``--finer`` are round 12's (imported, pointed at this
round's problems and results folder), the user's system class is round 13's ``Shaped``.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round14.py NAME [NAME ...]
        (the default solve, then the truth; both saved under strangers_round14_results/)
    ... --truth NAME ...   (the truth only)
    ... --levels NAME ...  (v on the grids h, 2h, 4h, the phase pair, 2× and 4× finer)
    ... --finer NAME ...   (the default solve with its estimate on 2× the cells per axis)
    ... --tol NAME ...     (round 13's gridlbc.solve(problem, tol=0.03, states=X) against the truth)
    ... --table            (the table and the tally from the saved results)

Truths ("tag"):

- "exact": ẋ = u (R = 1, noise λ per axis), q constant, on a closed box (reflecting walls, as
  the solver's state constraints): z(x, 0) = e^{−qT/λ} ∫ K(x, y) e^{−g(y)/λ} dy with K the
  reflecting heat kernel of variance λT per axis, by the method of images (sources at
  x + 2kL and 2lo − x + 2kL, |k| ≤ 6). A separable g: a product of 1-D integrals; a general
  g (min of goals): Σ_ij k₀(y_i) k₁(y_j) h(y_i, y_j), trapezoid on N points per axis (N with
  spacing ≤ σ/40, σ = √(λT)); the indicator of a box: normal CDFs of the images, closed form.
  Combinations: the components' z summed with the weights. The uncertainty is the difference
  between N and 2N points (zero for the closed forms).
- "ricc": linear-quadratic (PointMass): my own Riccati integration of SPEC §6 (scipy solve_ivp,
  rtol 1e-10); the box is wide enough that the walls do not matter (checked: the closed loop's
  stationary 4σ is inside it).
- "1-D": a sum over axes of round 13's Crank–Nicolson 1-D solves (reflecting ends, 20 001 nodes
  and T/4000 checked against 40 001 and T/8000); the costs are sums of one-axis functions.
- "2-D+1": ``rotor_rail``: v = v_{θω} + v_y (the costs split, the noises are independent): v_y
  by round 13's CN, v_{θω} by the library's own 2-D solve with 4× the cells per axis and a
  quarter of the default step (uncertainty: its difference from the 2× solve).
- "cert": :func:`gridlbc.certify` with the policy of a 4× finer solve as proposal, Δt = 0.004
  and 0.008 extrapolated (round 12's ``certified``); the uncertainty is the SE; ESS printed
  in the log.
- "fine": ``hz_long_pendulum``: the library's own solve on 2× and 3× the cells per axis with
  Δt/2, Δt/3 (the uncertainty is their difference; the three grids converge at order 2, whose
  extrapolation moves the 3× value by +0.022, inside it).

Checks of the truths (2026-12-05): the image-method quadratures against closed forms where the
walls are far (``hz_goal_steep``, ``hz_box_large``: the LQ value Σ ½ P(0)(x − c)² + (λ/2)
log(1 + 2W T) + qT, to 1e-6); ``combo_weights``'s component 3 at (−0.8, 0) by the same closed
form (1.642); ``hz_box_small``'s walls matter (the unconstrained LQ value at (0.9, −0.9) is 1.30
against 3.739 with reflection), and the library's solve agrees with the image sum to 1e-6 there;
``hz_short_step`` at (0.01, 0) by hand (P(N ≥ 0.75) = 0.2266: 0.2944). The certificates: ESS
1984–1999 of 2000, PSIS k̂ ≤ 0.18 (``vdp_hot``: 4× proposal, whose fine solve took 762 s, far
over the 3-minute budget; ``duffing_cold`` 2×). ``vdp_hot``'s errors (0.07–0.15 %) are inside
its certificate's SE (0.12–0.17 %): its "estimate < ½ error" is not a finding.

First run (library of commit 5f6943a, 2026-12-05, one thread; est/err "(inf)": the error is 0 to
the digits shown)::

    problem            state          predicted     truth  tag      ±    error     est est/err  w wc   t/s
    hz_long_wells      [0.0, 0.0]        7.7016    7.8757  1-D  0.00%   -2.21%   2.84%    1.28  n      1.6
    hz_long_wells      [1.5, -1.0]       7.0663    7.2041  1-D  0.00%   -1.91%   2.78%    1.45  n      1.6
    hz_long_wells      [-1.9, 1.5]       7.2890    7.4163  1-D  0.00%   -1.72%   2.60%    1.52  n      1.6
    hz_long_lq         [0.0, 0.0]        8.8542    8.8503 ricc  0.00%   +0.04%   0.23%    5.22  n      4.7
    hz_long_lq         [1.5, -1.0]      10.4896   10.4860 ricc  0.00%   +0.03%   0.20%    5.85  n      4.7
    hz_long_lq         [-2.5, 2.0]      13.3190   13.3135 ricc  0.00%   +0.04%   0.16%    3.77  n      4.7
    hz_long_pendulum   [3.14, 0.0]      34.7779   34.9517 fine  0.08%   -0.50%   0.45%    0.91  n      3.7
    hz_long_pendulum   [1.0, -2.0]      26.2341   26.3788 fine  0.12%   -0.55%   0.37%    0.68  n      3.7
    hz_long_pendulum   [0.3, 0.5]       26.2975   26.4422 fine  0.12%   -0.55%   0.37%    0.68  n      3.7
    hz_short_kink      [0.32, -0.12]     0.2893    0.2539 exact  0.00%  +13.96%   7.92%    0.57  n     25.9
    hz_short_kink      [0.31, 0.3]       0.5981    0.5793 exact  0.00%   +3.25%   2.32%    0.71  n     25.9
    hz_short_kink      [-1.0, 0.5]       2.6857    2.6857 exact  0.00%   -0.00%   0.02%   (inf)  n     25.9
    hz_short_step      [0.01, 0.0]       0.5573    0.2943 exact  0.00%  +89.34%  34.95%    0.39  Y      0.3
    hz_short_step      [0.04, 0.5]       0.2799    0.0530 exact  0.00% +113.43%  93.27%    0.82  Y      0.3
    hz_short_step      [-0.02, -1.0]     0.7820    0.7959 exact  0.00%   -1.75%  10.42%    5.95  Y      0.3
    hz_short_step_off  [0.51, 0.0]       0.5573    0.2943 exact  0.00%  +89.34%  34.95%    0.39  Y      0.4
    hz_short_step_off  [0.54, 0.5]       0.2799    0.0530 exact  0.00% +113.43%  93.27%    0.82  Y      0.4
    hz_short_step_off  [0.3, -1.0]       1.0012    1.0020 exact  0.00%   -0.08%   0.91%   11.16  Y      0.4
    hz_steep_mid       [0.31, -0.27]     0.0716    0.0549 exact  0.00%  +30.34%  56.62%    1.87  n      0.1
    hz_steep_mid       [0.34, -0.24]     0.0883    0.0758 exact  0.00%  +16.50%  91.29%    5.53  n      0.1
    hz_steep_mid       [0.4, -0.3]       0.2049    0.2049 exact  0.00%   +0.00%  22.34%   (inf)  n      0.1
    hz_short_steep     [0.31, -0.27]     0.0508    0.0091 exact  0.00%  +83.33% 168.30%    2.02  n      0.1
    hz_short_steep     [0.34, -0.24]     0.0924    0.0612 exact  0.00%  +51.06% 181.86%    3.56  n      0.1
    hz_short_steep     [0.4, -0.3]       0.3841    0.3841 exact  0.00%   +0.00%   9.66%   (inf)  n      0.1
    hz_short_vee       [0.32, -0.12]     0.1850    0.0656 exact  0.00%  +59.72%  45.13%    0.76  Y      0.4
    hz_short_vee       [0.31, 0.3]       1.3635    1.3199 exact  0.00%   +3.30%   2.38%    0.72  Y      0.4
    hz_short_vee       [0.0, -0.11]      1.0635    1.0199 exact  0.00%   +4.27%   3.74%    0.88  Y      0.4
    hz_short_steep_user [0.31, -0.27]     0.0508    0.0091 exact  0.00%  +83.33% 168.30%    2.02  n      0.1
    hz_short_steep_user [0.34, -0.24]     0.0924    0.0612 exact  0.00%  +51.06% 181.86%    3.56  n      0.1
    hz_short_steep_user [0.4, -0.3]       0.3841    0.3841 exact  0.00%   -0.00%   9.66%   (inf)  n      0.1
    hz_box_large_cold  [0.3, -0.2]       0.3402    0.3322 exact  0.00%   +2.41%  35.22%   14.62  n      1.1
    hz_box_large_cold  [0.0, 0.5]        0.5642    0.5642 exact  0.00%   +0.00%   7.38%   (inf)  n      1.1
    hz_box_large_cold  [-1.0, -1.0]      1.2642    1.2642 exact  0.00%   +0.00%   3.30%   (inf)  n      1.1
    hz_long_unstable   [0.0, 0.0]        3.3933    3.3935 ricc  0.00%   -0.01%   0.55%   91.46  n      2.9
    hz_long_unstable   [0.3, -0.5]       3.4924    3.4847 ricc  0.00%   +0.22%   0.55%    2.50  n      2.9
    hz_long_unstable   [-0.6, 1.5]       3.5565    3.5450 ricc  0.00%   +0.32%   1.04%    3.20  n      2.9
    hz_goal_steep      [0.31, -0.27]     0.1244    0.1199 exact  0.00%   +3.79%  38.48%   10.15  n      0.1
    hz_goal_steep      [0.45, -0.15]     0.2744    0.2744 exact  0.00%   +0.00%  17.27%   (inf)  n      0.1
    hz_goal_steep      [0.0, 0.1]        1.1790    1.1790 exact  0.00%   +0.00%   3.49%   (inf)  n      0.1
    hz_box_goal        [0.08, 0.02]      0.1839    0.1886 exact  0.00%   -2.33%  76.96%   32.96  Y      0.2
    hz_box_goal        [0.48, 0.0]       0.3011    0.3066 exact  0.00%   -1.78%  62.35%   34.93  Y      0.2
    hz_box_goal        [0.8, -0.5]       1.0169    1.0154 exact  0.00%   +0.15%  23.08%  158.00  Y      0.2
    hz_min_goals       [-0.1, 0.25]      0.9811    0.9812 exact  0.00%   -0.01%   2.05%  258.51  n      0.6
    hz_min_goals       [0.55, 0.4]       0.5592    0.5592 exact  0.00%   +0.00%   3.22%   (inf)  n      0.6
    hz_min_goals       [0.4, -0.5]       1.0645    1.0643 exact  0.00%   +0.02%   1.51%   72.09  n      0.6
    hz_box_small       [0.0, 0.0]        4.3291    4.3291 exact  0.00%   +0.00%   0.00%  132.43  n      0.6
    hz_box_small       [0.9, -0.9]       3.7391    3.7391 exact  0.00%   +0.00%   0.00%   95.68  n      0.6
    hz_box_small       [-0.8, 0.5]       5.3303    5.3303 exact  0.00%   -0.00%   0.00%    8.60  n      0.6
    hz_box_large       [0.3, -0.2]       0.4689    0.4609 exact  0.00%   +1.74%   9.41%    5.42  n      1.2
    hz_box_large       [0.0, 0.5]        0.6929    0.6929 exact  0.00%   +0.00%   6.87%   (inf)  n      1.2
    hz_box_large       [-1.0, -1.0]      1.3929    1.3929 exact  0.00%   +0.00%   2.71%   (inf)  n      1.2
    hz_unequal         [0.2, 0.35]       0.5135    0.4950 exact  0.00%   +3.73%  17.79%    4.77  Y      0.8
    hz_unequal         [0.0, 0.0]        0.6429    0.6266 exact  0.00%   +2.59%  15.98%    6.17  Y      0.8
    hz_unequal         [-0.5, 0.8]       0.8704    0.8538 exact  0.00%   +1.94%   8.47%    4.37  Y      0.8
    rotor_rail         [3.14, 0.0, 0.0]    4.5481    4.5413 2-D+1  0.04%   +0.15%   0.74%    4.98  n      9.6
    rotor_rail         [0.5, 1.0, -1.0]    2.8381    2.8603 2-D+1  0.14%   -0.78%   0.83%    1.07  n      9.6
    rotor_rail         [-2.0, -2.0, 1.2]    1.8681    1.8755 2-D+1  0.06%   -0.40%   0.74%    1.86  n      9.6
    combo_weights      [-0.8, 0.0]       0.1303    0.1885 exact  0.00%  -29.08%  22.52%    0.77  n      1.8
    combo_weights      [0.4, 0.2]       -0.0286    0.0206 exact  0.00%  -24.61%  16.82%    0.68  n      1.8
    combo_weights      [0.1, -0.9]      -0.9540   -0.9543 exact  0.00%   +0.03%   0.27%    8.78  n      1.8
    combo_cancel       [0.1, -0.05]      0.3398    0.3507 exact  0.00%   -3.11%   1.83%    0.59  n      0.4
    combo_cancel       [0.3, 0.1]        0.3471    0.3559 exact  0.00%   -2.47%   1.41%    0.57  n      0.4
    combo_cancel       [1.0, -1.0]       0.8078    0.8072 exact  0.00%   +0.08%   0.09%    1.15  n      0.4
    combo_cancel_sharp [0.1, -0.05]      0.6563    0.6677 exact  0.00%   -1.70%   1.66%    0.98  n      0.3
    combo_cancel_sharp [0.3, 0.1]        0.6677    0.6777 exact  0.00%   -1.48%   1.44%    0.97  n      0.3
    combo_cancel_sharp [1.0, -1.0]       1.3099    1.3122 exact  0.00%   -0.17%   0.26%    1.56  n      0.3
    vdp_hot            [2.0, 0.0]       10.0154   10.0003 cert  0.14%   +0.15%   0.02%    0.16  n     10.6
    vdp_hot            [0.0, 2.5]       11.1361   11.1450 cert  0.12%   -0.08%   0.02%    0.27  n     10.6
    vdp_hot            [-1.0, -1.0]      8.8682    8.8623 cert  0.17%   +0.07%   0.03%    0.41  n     10.6
    duffing_cold       [1.0, 0.0]        0.0036    0.0035 cert  0.12%   +1.01%   3.41%    3.37  n      1.6
    duffing_cold       [-1.0, 0.0]       1.0568    1.0562 cert  0.00%   +0.05%   0.19%    3.83  n      1.6
    duffing_cold       [0.0, 0.5]        0.1013    0.1012 cert  0.02%   +0.15%   0.19%    1.30  n      1.6
    72 pairs; > 10 % off silently at 9 [('hz_short_kink', 14.0), ('hz_steep_mid', 30.3), ('hz_steep_mid', 16.5), ('hz_short_steep', 83.3), ('hz_short_steep', 51.1), ('hz_short_steep_user', 83.3), ('hz_short_steep_user', 51.1), ('combo_weights', 29.1), ('combo_weights', 24.6)]; estimate < ½ an error above 2 % at 2 [('hz_short_step', 89.34, 34.95), ('hz_short_step_off', 89.34, 34.95)]; false alarms (warned, every pair < 2 %): 0 []; truths uncertain beyond 2 %: []
    average cost c alone (its own estimate and check, whatever h's says): 0 solves; c > 10 % off with c's estimate ≤ 5 % at 0 []; c's estimate < ½ an error above 2 % at 0 []

Coverage: the estimate is at least half the error at 67 of 72 pairs; of the five others three
are ``vdp_hot`` inside the truth's SE, the other two are the steps of ``hz_short_step`` and
``hz_short_step_off`` (warned).

Mechanisms (measured with ``--levels``, ``--tol`` and the judged set; Δt default):

- ``hz_short_steep`` / ``hz_short_steep_user`` (silent, +83 % and +51 %; estimates 168 % and
  182 %, so the estimate itself covers): T = 0.002 is ten default steps; g's desirability is half
  a cell wide, so only the few nodes near the goal are off. v at c on h, 2h, 4h, pair: 0.0508,
  0.1363, 0.8619, 0.1776/0.1770; h/2 0.0195, h/4 0.0117 (truth 0.0091). The embedded term and γ
  (88 %, 46 %) see it at the states, but the warning judges the 90th percentile of the relative
  estimate over the states that matter (v ≤ the median: 3281 nodes, v up to 108), where 0.9 % of
  them exceed 5 % (p90 0.47 %), and S, the only term judged at its maximum, is 0: g is an exact
  quadratic, which the reconstruction R reproduces, whether it is the library's Quadratic or a
  user's lambda. No term with a max-rule exists for a steep-but-smooth g. ``solve(tol=0.03,
  states=X)`` fixes it (845 × 599, 6.2 s: +1.3 %, +1.0 % with estimates 1.9 %, 1.0 %).
  ``hz_steep_mid`` (T = 0.02, ten times longer) is the same: silent +30 % and +16.5 % with
  estimates 57 % and 91 % (γ 49–51 %, S 0).
- ``hz_short_kink`` (silent, +14.0 % with an estimate 7.9 %, 0.57×): the kinks of g midway
  between nodes, T = 0.004 (ten steps of 0.0004, a third of the noise's time h²/λ across a
  cell); v at the kink on h,
  2h, 4h, pair: 0.2893, 0.3291, 0.4500, 0.3389/0.3176; h/2 0.2559, h/4 0.2536 (truth 0.2539).
  Embedded 0.040/(2^1.76 − 1) = 0.017, γ 7.3 %, S 2.3 % (below 5 %: its max-rule does not fire);
  the kink lines are a few per cent of the judged nodes (0.15 % of them above 5 %, p90 0.48 %).
  ``tol=0.03`` fixes it (241 × 125, 2.4 s: +2.5 % with 1.5 %). ``hz_short_vee`` (slopes 3,
  T = 0.001, +60 %) warns through S (10.3 % at the kink) with 0.76× the error.
- ``hz_short_step`` (warned; +89 % at (0.01, 0) with 35 %, 0.39×): a step in g half a cell from
  the axis centre (the pair's documented blind spot: pair 0.413/0.409), T = 0.002 (σ = 0.02):
  h, 2h, 4h 0.557, 0.729, 0.846, h/2 0.646, h/4 0.461 (truth 0.294): the error is not monotone
  in h (it depends on where the step falls between nodes), the embedded difference 0.17 is below
  it; γ (8.6 %) is a signed mean of I_h g − g, which is +0.4 on one side of the step and −0.4 on
  the other, and cancels; S reads 11 %. ``solve(tol=0.03, states=X)`` did not return within
  600 s (killed; no max_seconds given). ``hz_short_step_off`` moves the step to 0.525, away from
  the centre (the pair now differs: 0.493/0.330, as do 2h 0.729 and 4h 0.455; h/2 0.330, h/4
  0.281 against 0.294): the same +89 % with the same 35 % (0.39×), warned; so every term reads
  less than the error, not only the blind pair (S 14.8 %, γ 8.6 %).
- ``combo_weights`` (silent, −29 % and −25 %, Σ|α|ê 0.77× and 0.68×): ``gridlbc.combine`` raises
  no ResolutionWarning of its own, and its components did not warn: their errors are 3–5 % of
  their own v (≈ 1.4–1.6) while w₃ = 10³ shifts the combination's v down by λ log 10³ = 1.38
  to ≈ λ, so the same absolute error (α₃ δv₃ = 0.77 × −0.079) is 29 % of it. The coverage below
  1× is component 3's own estimate (0.057 against −0.079 at (−0.8, 0), 1.6 away from its goal:
  solve_many's plain operator).
- Controls, quiet and within 2 %: long horizons (``hz_long_lq``, ``hz_long_unstable``,
  ``hz_long_pendulum`` T = 20, ``hz_long_wells`` T = 25 with −1.7 to −2.2 % against estimates
  of 2.6–2.8 %); the box too small (``hz_box_small``: exact to 1e-6), too large
  (``hz_box_large``, ``hz_box_large_cold``), the min of goals, the 3-D rotor on a rail, the
  cancelling combinations (Σ|α|ê 0.57–0.98× of errors ≤ 3.1 %), Van der Pol at λ = 3 and Duffing
  at λ = 0.01 on 151². ``hz_box_goal`` (an indicator, errors ≤ 2.3 %) and ``hz_unequal`` (≤ 3.7 %)
  warn with estimates 4–35× the error (S overshoots a step; the 41-node axis's embedded grid
  has 21 nodes, observed order −0.55).

Relative error (v − v*)/max(|v*|, λ), estimate ê/max(|v|, λ), "w" a ResolutionWarning (for a
combination: one of its components' solves warned).
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings

import numpy as np
import strangers_round12 as r12
import strangers_round13 as r13
from scipy.integrate import solve_ivp
from scipy.special import ndtr
from strangers_round12 import HERE, const, free
from strangers_round13 import Shaped, cn_1d

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import LinearSystem, PointMass

OUT = HERE / "strangers_round14_results"
PI = math.pi


def box(n, lo=-2.0, hi=2.0, d=2):
    return Grid([Axis(lo, hi, n)] * d)


def S(*states):
    return np.array(states, dtype=float)


# ---------------- exact references for ẋ = u on a reflecting box ----------------------------
def _images(x, y, s, lo, hi, K=6):
    L = hi - lo
    k = np.arange(-K, K + 1)[:, None]
    a = (y[None, :] - x - 2 * k * L) / s
    b = (y[None, :] + x - 2 * lo - 2 * k * L) / s
    return (np.exp(-0.5 * a**2) + np.exp(-0.5 * b**2)).sum(0) / (s * math.sqrt(2 * PI))


def _kw(x, s, lo, hi, N):
    y = np.linspace(lo, hi, N)
    w = np.full(N, (hi - lo) / (N - 1))
    w[[0, -1]] *= 0.5
    return y, w * _images(x, y, s, lo, hi)


def _npts(s, lo, hi, base=40):
    return int(min(max(2001, base * (hi - lo) / s), 40001))


def sep_logz(gs, lam, T, bounds, X, mult=1):
    """log ∫ K e^{−Σ g_i(y_i)/λ} dy (no q) for a separable g: Σ over axes of 1-D logs."""
    s = math.sqrt(lam * T)
    out = np.zeros(len(X))
    for i, (g, (lo, hi)) in enumerate(zip(gs, bounds)):
        N = _npts(s, lo, hi) * mult
        for j, x in enumerate(X[:, i]):
            y, kw = _kw(x, s, lo, hi, N)
            gy = g(y)
            m = gy.min()
            out[j] += -m / lam + math.log(np.sum(kw * np.exp(-(gy - m) / lam)))
    return out


def exact_sep(gs, lam, T, q=0.0, bounds=((-2, 2), (-2, 2))):
    def truth(X):
        v = [q * T - lam * sep_logz(gs, lam, T, bounds, X, m) for m in (1, 2)]
        return v[1], np.abs(v[1] - v[0])

    return truth


def exact_2d(g2, lam, T, q=0.0, bounds=((-2, 2), (-2, 2))):
    """A general 2-D g: Σ_ij k₀ k₁ e^{−g/λ} on N² points, in chunks of rows."""
    s = math.sqrt(lam * T)

    def one(X, mult):
        out = []
        (l0, h0), (l1, h1) = bounds
        N0, N1 = _npts(s, l0, h0, 20) * mult, _npts(s, l1, h1, 20) * mult
        y0, y1 = np.linspace(l0, h0, N0), np.linspace(l1, h1, N1)
        gmin = np.inf
        for a in range(0, N0, 256):
            Y0, Y1 = np.meshgrid(y0[a : a + 256], y1, indexing="ij")
            gmin = min(gmin, g2(np.stack([Y0.ravel(), Y1.ravel()], 1)).min())
        for x in X:
            _, k0 = _kw(x[0], s, l0, h0, N0)
            _, k1 = _kw(x[1], s, l1, h1, N1)
            z = 0.0
            for a in range(0, N0, 256):
                Y0, Y1 = np.meshgrid(y0[a : a + 256], y1, indexing="ij")
                gg = g2(np.stack([Y0.ravel(), Y1.ravel()], 1)).reshape(Y0.shape)
                z += k0[a : a + 256] @ np.exp(-(gg - gmin) / lam) @ k1
            out.append(q * T + gmin - lam * math.log(z))
        return np.array(out)

    def truth(X):
        v = [one(X, m) for m in (1, 2)]
        return v[1], np.abs(v[1] - v[0])

    return truth


def _inside(x, a, b, s, lo, hi, K=6):
    """P(X_T ∈ [a, b]) for reflecting Brownian motion of variance s² from x on [lo, hi]."""
    L = hi - lo
    p = 0.0
    for k in range(-K, K + 1):
        for c in (x + 2 * k * L, 2 * lo - x + 2 * k * L):
            p += ndtr((b - c) / s) - ndtr((a - c) / s)
    return p


def exact_box_indicator(lo_b, hi_b, out_cost, lam, T, q):
    s = math.sqrt(lam * T)

    def truth(X):
        P = np.array(
            [
                _inside(x[0], lo_b[0], hi_b[0], s, -2, 2)
                * _inside(x[1], lo_b[1], hi_b[1], s, -2, 2)
                for x in X
            ]
        )
        e = math.exp(-out_cost / lam)
        return q * T - lam * np.log(e + (1 - e) * P), np.zeros(len(X))

    return truth


# ---------------- 1. long horizons ------------------------------------------------------------
def q_long0(y):
    return 0.4 + 0.3 * np.cos(2.0 * y)  # cheapest (0.1) at ±π/2, 0.43 from the walls


def q_long1(y):
    return 0.1 * y**2


def g_long0(y):
    return 0.5 * y**2


def hz_long_wells():
    """ẋ = u on [−2, 2]² (81²), q = 0.4 + 0.3 cos 2x₀ + 0.1 x₁² (two cheap bands at x₀ = ±π/2,
    near the walls), g = 0.5 x₀², λ = 0.3, T = 25: v ≈ c·T + h, c ≈ 0.1 + noise's price."""
    return Problem(
        free(2),
        box(81),
        25.0,
        lambda x: g_long0(x[:, 0]),
        state_cost=lambda x: q_long0(x[:, 0]) + q_long1(x[:, 1]),
        temperature=0.3,
    )


def zero(y):
    return 0.0 * y


def sum_cn(*parts):
    def truth(X):
        vs, us = zip(*(f(X[:, [i]]) for i, f in enumerate(parts)))
        return sum(vs), sum(us)

    return truth


LQ_W = (1.0, 0.2)  # q = x₀² + 0.2 x₁²
LQ_G = (1.0, 0.5)


def hz_long_lq():
    """PointMass (position, velocity), q = x₀² + 0.2 x₁² (a user's lambda), g = Quadratic
    (weights 1, 0.5), λ = 0.5, T = 20 on [−4, 4] × [−5, 5] with 121²: v ≈ c·T + h."""
    return Problem(
        PointMass(),
        Grid([Axis(-4, 4, 121), Axis(-5, 5, 121)]),
        20.0,
        Quadratic([0.0, 0.0], list(LQ_G)),
        state_cost=lambda x: LQ_W[0] * x[:, 0] ** 2 + LQ_W[1] * x[:, 1] ** 2,
        temperature=0.5,
    )


def riccati_lq(A, B, W, WT, lam, T):
    """v(x, 0) = ½ xᵀ P x + c₀ (centres at 0, R = 1) by SPEC §6, integrated backwards."""
    d = A.shape[0]
    Sm = B @ B.T

    def rhs(t, y):
        P = y[: d * d].reshape(d, d)
        dP = -(A.T @ P + P @ A - P @ Sm @ P + 2 * W)
        dc = -(0.5 * lam * np.trace(Sm @ P))
        return np.concatenate([dP.ravel(), [dc]])

    y0 = np.concatenate([(2 * WT).ravel(), [0.0]])
    sol = solve_ivp(rhs, (T, 0.0), y0, rtol=1e-10, atol=1e-12, method="LSODA")
    P = sol.y[: d * d, -1].reshape(d, d)
    c0 = sol.y[-1, -1]

    def truth(X):
        X = np.asarray(X)
        return 0.5 * np.einsum("ni,ij,nj->n", X, P, X) + c0, np.zeros(len(X))

    return truth


def hz_long_pendulum():
    """The built-in Pendulum (θ from the upright, periodic; ω on [−8, 8]), 120 × 121, λ = 0.5,
    T = 20, q = (1 − cos θ) + 0.05 ω², g = Quadratic(0, (2, 0.1)): balance it for a long time."""
    return Problem(
        gridlbc.systems.Pendulum(),
        Grid([Axis(-PI, PI, 120, periodic=True), Axis(-8, 8, 121)]),
        20.0,
        Quadratic([0.0, 0.0], [2.0, 0.1]),
        state_cost=lambda x: (1 - np.cos(x[:, 0])) + 0.05 * x[:, 1] ** 2,
        temperature=0.5,
    )


def lib_finer(build, factors=(2, 3)):
    """The library's own solve on grids with f× the cells per axis and Δt/f (no estimate); the
    uncertainty is the difference between the two finest."""

    def truth(X):
        p = build()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            dt0 = gridlbc.solve(p, error_estimate=False).diagnostics.dt
            vals = []
            for f in factors:
                g = r12._finer(p.grid, f)
                t0 = time.perf_counter()
                s = gridlbc.solve(p.replace(grid=g), dt=dt0 / f, error_estimate=False)
                vals.append(s.value(np.asarray(X)))
                print(
                    f"    ×{f} {[a.n for a in g.axes]} dt {dt0 / f:.4g}: "
                    f"{np.round(vals[-1], 5).tolist()} ({time.perf_counter() - t0:.1f} s)",
                    flush=True,
                )
        return vals[-1], np.abs(vals[-1] - vals[-2])

    return truth


# ---------------- 2. a very short horizon, kinks between nodes ---------------------------------
def g_kink0(y):
    return 1.5 * np.abs(y - 0.325)  # midway between the nodes 0.3 and 0.35 (81 nodes)


def g_kink1(y):
    return 0.8 * np.abs(y + 0.125) + 0.2


def hz_short_kink():
    """ẋ = u, 81² (h = 0.05), λ = 0.2, T = 0.004 (σ = √(λT) = 0.028 < h; the noise crosses a
    cell in h²/λ = 0.0125 = 3T), g = 1.5 |x₀ − 0.325| + 0.8 |x₁ + 0.125| + 0.2 (kinks midway
    between nodes), q = 1."""
    return Problem(
        free(2),
        box(81),
        0.004,
        lambda x: g_kink0(x[:, 0]) + g_kink1(x[:, 1]),
        state_cost=const(1.0),
        temperature=0.2,
    )


def hz_short_step():
    """ẋ = u, 81², λ = 0.2, T = 0.002 (σ = 0.02 < h = 0.05), g = 0 where x₀ ≥ 0.025 (midway
    between the nodes 0 and 0.05), 1 elsewhere (a step, a user's indicator), q = 1."""
    return Problem(
        free(2),
        box(81),
        0.002,
        lambda x: np.where(x[:, 0] >= 0.025, 0.0, 1.0),
        state_cost=const(1.0),
        temperature=0.2,
    )


def hz_short_step_off():
    """hz_short_step with the step at x₀ = 0.525 (midway between the nodes 0.5 and 0.55, away
    from the axis centre, where the pair of grids is not blind)."""
    return Problem(
        free(2),
        box(81),
        0.002,
        lambda x: np.where(x[:, 0] >= 0.525, 0.0, 1.0),
        state_cost=const(1.0),
        temperature=0.2,
    )


def hz_steep_mid():
    """hz_short_steep with T = 0.02 (ten times longer; the desirability 0.039 wide at t = 0)."""
    return hz_short_steep().replace(horizon=0.02)


def hz_short_steep():
    """ẋ = u, 81², g = Quadratic(c, 50), c = (0.31, −0.27), λ = 0.05, T = 0.002: at t = 0 the
    desirability's width √(λ/P(0)) = 0.024 is half a cell."""
    return Problem(free(2), box(81), 0.002, Quadratic(list(GS_C), [50.0, 50.0]), temperature=0.05)


def g_vee0(y):
    return 3.0 * np.abs(y - 0.325)


def g_vee1(y):
    return 3.0 * np.abs(y + 0.125)


def hz_short_vee():
    """hz_short_kink steeper and shorter: g = 3 |x₀ − 0.325| + 3 |x₁ + 0.125| (kinks midway
    between nodes), T = 0.001 (σ = 0.014), q = 1, λ = 0.2, 81²."""
    return Problem(
        free(2),
        box(81),
        0.001,
        lambda x: g_vee0(x[:, 0]) + g_vee1(x[:, 1]),
        state_cost=const(1.0),
        temperature=0.2,
    )


def hz_short_steep_user():
    """hz_short_steep with the same g written as a user's lambda (so the costs' excess S is
    sampled): 50 |x − c|², λ = 0.05, T = 0.002, 81²."""
    return Problem(
        free(2),
        box(81),
        0.002,
        lambda x: 50.0 * ((x[:, 0] - GS_C[0]) ** 2 + (x[:, 1] - GS_C[1]) ** 2),
        temperature=0.05,
    )


# ---------------- 3. terminal costs: steep, discontinuous, a minimum of goals ------------------
GS_C = (0.31, -0.27)


def hz_goal_steep():
    """ẋ = u, 81², g = Quadratic(c, 50) (50 |x − c|², c = (0.31, −0.27)), λ = 0.05, T = 0.1: at
    t = 0 the desirability's width is √(λ/P(0)) = 0.055 ≈ h."""
    return Problem(free(2), box(81), 0.1, Quadratic(list(GS_C), [50.0, 50.0]), temperature=0.05)


BOX_LO, BOX_HI = (-0.325, -0.175), (0.475, 0.225)  # edges midway between nodes (81 nodes)


def hz_box_goal():
    """ẋ = u, 81², g = 0 inside the box [−0.325, 0.475] × [−0.175, 0.225] and 2 outside (a
    user's indicator), q = 0.2, λ = 0.2, T = 0.3."""

    def g(x):
        inside = np.all((x >= np.array(BOX_LO)) & (x <= np.array(BOX_HI)), axis=1)
        return np.where(inside, 0.0, 2.0)

    return Problem(free(2), box(81), 0.3, g, state_cost=const(0.2), temperature=0.2)


GOALS = ((-0.8, 0.1), (0.6, 0.45), (0.15, -0.9))
GOAL_OFF = (0.0, 0.0, 0.3)


def g_min(x):
    return np.min(
        [
            20.0 * ((x[:, 0] - c[0]) ** 2 + (x[:, 1] - c[1]) ** 2) + o
            for c, o in zip(GOALS, GOAL_OFF)
        ],
        axis=0,
    )


def hz_min_goals():
    """ẋ = u, 81², g = min_i 20 |x − c_i|² + o_i (three goals, one 0.3 dearer; kinks on the
    ridges between them), q = 0.5, λ = 0.1, T = 0.5."""
    return Problem(free(2), box(81), 0.5, g_min, state_cost=const(0.5), temperature=0.1)


# ---------------- 4. boxes: too small, too large, unequal spacings -----------------------------
def g_small0(y):
    return (y - 2.5) ** 2


def g_small1(y):
    return 0.5 * (y + 1.8) ** 2


def hz_box_small():
    """ẋ = u on [−1, 1]² (81², h = 0.025): g = (x₀ − 2.5)² + 0.5 (x₁ + 1.8)², both minima
    outside the box, so the optimal paths press against the walls x₀ = 1, x₁ = −1 (reflected);
    q = 0.1, λ = 0.3, T = 1.5."""
    return Problem(
        free(2),
        box(81, -1.0, 1.0),
        1.5,
        lambda x: g_small0(x[:, 0]) + g_small1(x[:, 1]),
        state_cost=const(0.1),
        temperature=0.3,
    )


def hz_box_large():
    """ẋ = u on [−20, 20]² with 161² (h = 0.25): the user's box is 10× larger than where the
    paths go; g = Quadratic((0.3, −0.2), (2, 2)), q = 0.3, λ = 0.1, T = 1."""
    return Problem(
        free(2),
        box(161, -20.0, 20.0),
        1.0,
        Quadratic([0.3, -0.2], [2.0, 2.0]),
        state_cost=const(0.3),
        temperature=0.1,
    )


def hz_box_large_cold():
    """hz_box_large at λ = 0.02: [−20, 20]² with 161² (h = 0.25), g = Quadratic((0.3, −0.2),
    (2, 2)), q = 0.3, T = 1: the desirability at t = 0 is √(λ/P(0)) = 0.16 wide, under a cell."""
    return hz_box_large().replace(temperature=0.02)


def hz_long_unstable():
    """ẋ₀ = x₁, ẋ₁ = 4 x₀ − 0.5 x₁ + u (a linearised inverted pendulum, a user's LinearSystem),
    q = x₀² + 0.1 x₁², g = 0, λ = 0.1, T = 20 on [−3, 3] × [−8, 8] with 121²."""
    return Problem(
        LinearSystem(np.array([[0.0, 1.0], [4.0, -0.5]]), np.array([[0.0], [1.0]])),
        Grid([Axis(-3, 3, 121), Axis(-8, 8, 121)]),
        20.0,
        lambda x: 0.0 * x[:, 0],
        state_cost=lambda x: x[:, 0] ** 2 + 0.1 * x[:, 1] ** 2,
        temperature=0.1,
    )


def g_un0(y):
    return 0.5 * (y - 0.2) ** 2


def g_un1(y):
    return 1.2 - 1.0 * np.exp(-0.5 * ((y - 0.35) / 0.12) ** 2)


def hz_unequal():
    """ẋ = u on [−2, 2]², x₀ with 401 nodes (h = 0.01), x₁ with 41 (h = 0.1): g = 0.5 (x₀ −
    0.2)² + 1.2 − e^{−(x₁ − 0.35)²/2·0.12²} (a goal 1.2 coarse cells wide, midway between two
    coarse nodes), q = 0.2, λ = 0.1, T = 0.5."""
    return Problem(
        free(2),
        Grid([Axis(-2, 2, 401), Axis(-2, 2, 41)]),
        0.5,
        lambda x: g_un0(x[:, 0]) + g_un1(x[:, 1]),
        state_cost=const(0.2),
        temperature=0.1,
    )


# ---------------- 5. 3-D: a pendulum on a rail (periodic θ, closed ω, closed y) ----------------
def rail_drift(x):
    return np.stack([x[:, 1], 2.0 * np.sin(x[:, 0]), 0.0 * x[:, 0]], 1)


def q_rot(x):
    return 0.2 * (1 - np.cos(x[:, 0]))


def g_rot(x):
    return 2.0 * (1 - np.cos(x[:, 0])) + 0.1 * x[:, 1] ** 2


def q_y(y):
    return 0.05 * y**2


def g_y(y):
    return 1.5 * (y - 0.4) ** 2


def rotor_rail():
    """θ̇ = ω, ω̇ = 2 sin θ + u₀ (θ from the upright, periodic), ẏ = u₁ (a rail): 48 × 61 × 41
    on (−π, π] × [−6, 6] × [−2, 2]; q = 0.2 (1 − cos θ) + 0.05 y², g = 2 (1 − cos θ) + 0.1 ω² +
    1.5 (y − 0.4)², λ = 0.5, T = 2."""
    sys_ = Shaped(3, drift=rail_drift, axes=(1, 2))
    sys_.angle_axes = (0,)
    grid = Grid([Axis(-PI, PI, 48, periodic=True), Axis(-6, 6, 61), Axis(-2, 2, 41)])
    return Problem(
        sys_,
        grid,
        2.0,
        lambda x: g_rot(x) + g_y(x[:, 2]),
        state_cost=lambda x: q_rot(x) + q_y(x[:, 2]),
        temperature=0.5,
    )


def rotor_2d(n=(48, 61)):
    sys_ = Shaped(2, drift=lambda x: rail_drift(np.c_[x, 0 * x[:, 0]])[:, :2], axes=(1,))
    sys_.angle_axes = (0,)
    grid = Grid([Axis(-PI, PI, n[0], periodic=True), Axis(-6, 6, n[1])])
    return Problem(sys_, grid, 2.0, g_rot, state_cost=q_rot, temperature=0.5)


def rotor_truth(X):
    X = np.asarray(X)
    vy, uy = cn_1d(zero, q_y, g_y, 0.5, 2.0)(X[:, [2]])
    base = rotor_2d()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dt0 = gridlbc.solve(base, error_estimate=False).diagnostics.dt
        vals = []
        for f in (2, 4):
            p = rotor_2d((48 * f, 60 * f + 1))
            t0 = time.perf_counter()
            s = gridlbc.solve(p, dt=dt0 / f, error_estimate=False)
            vals.append(s.value(X[:, :2]))
            print(
                f"    rotor 2-D ×{f}: {np.round(vals[-1], 5).tolist()} ({time.perf_counter() - t0:.1f} s)"
            )
    return vals[1] + vy, np.abs(vals[1] - vals[0]) + uy


# ---------------- 6. combine(solve_many) with weights over orders of magnitude -----------------
CW_C = ((-0.8, 0.0), (0.7, 0.4), (0.1, -0.9))
CW_W = (1.0, 1e-3, 1e3)


def _qg(c, w):
    return lambda y: w * (y - c) ** 2


def combo_weights():
    """ẋ = u, 81², q = 0.3, λ = 0.2, T = 0.5; three goals Quadratic(c_i, 3) solved by solve_many
    and combined with w = (1, 10⁻³, 10³)."""
    p = Problem(
        free(2),
        box(81),
        0.5,
        Quadratic(list(CW_C[0]), [3.0, 3.0]),
        state_cost=const(0.3),
        temperature=0.2,
    )
    return p, [Quadratic(list(c), [3.0, 3.0]) for c in CW_C], list(CW_W)


def combo_cancel():
    """ẋ = u, 81², q = 0.3, λ = 0.2, T = 0.5; g₁ = 0.5 |x − c|², g₂ = 2 |x − c|² (c = (0.1,
    −0.05)), w = (1, −0.9): h = h₁ − 0.9 h₂ ≥ 0.1 h₁, cancellation near c."""
    c = [0.1, -0.05]
    p = Problem(
        free(2), box(81), 0.5, Quadratic(c, [0.5, 0.5]), state_cost=const(0.3), temperature=0.2
    )
    return p, [Quadratic(c, [0.5, 0.5]), Quadratic(c, [2.0, 2.0])], [1.0, -0.9]


def combo_cancel_sharp():
    """combo_cancel with g₁ = |x − c|², g₂ = |x − c|² + 0.5 (x₀ − c₀)², w = (1, −0.95): h =
    h₁ − 0.95 h₂ ≥ 0.05 h₁ (twenty-fold cancellation at c)."""
    c = [0.1, -0.05]
    p = Problem(
        free(2), box(81), 0.5, Quadratic(c, [1.0, 1.0]), state_cost=const(0.3), temperature=0.2
    )
    return p, [Quadratic(c, [1.0, 1.0]), Quadratic(c, [1.5, 1.0])], [1.0, -0.95]


def combo_truth(build):
    def truth(X):
        p, gs, ws = build()
        lam, T = p.temperature, p.horizon
        qT = 0.3 * T
        res = []
        for m in (1, 2):
            logs = np.array(
                [
                    sep_logz(
                        [_qg(g.center[0], g.weights[0, 0]), _qg(g.center[1], g.weights[1, 1])],
                        lam,
                        T,
                        ((-2, 2), (-2, 2)),
                        X,
                        m,
                    )
                    for g in gs
                ]
            )
            mx = logs.max(0)
            z = np.sum(np.array(ws)[:, None] * np.exp(logs - mx), 0)
            res.append(qT - lam * (mx + np.log(z)))
        return res[1], np.abs(res[1] - res[0])

    return truth


def combo_quick(name):
    _b, X, *_ = P14[name]
    p, gs, ws = COMBOS[name]()
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        sols = gridlbc.solve_many(p, gs)
        both = gridlbc.combine(sols, weights=ws)
        v, est = both.value(X), both.error_estimate(X)
    dt = time.perf_counter() - t0
    alpha = np.asarray(both.blend_weights(X, 0.0)).tolist()
    comp = [(s.value(X).tolist(), s.error_estimate(X).tolist()) for s in sols]
    out = dict(
        name=name,
        X=X.tolist(),
        time=dt,
        kind="exit",
        v=np.atleast_1d(v).tolist(),
        est=np.atleast_1d(est).tolist(),
        components=comp,
        alpha=alpha,
        exact=bool(getattr(both, "exact", False)),
        warned=r12._warned(w),
        warnings=[f"{x.category.__name__}: {str(x.message)[:300]}" for x in w],
    )
    print(
        f"{name}: v {np.round(v, 4).tolist()} est {np.round(est, 4).tolist()} t={dt:.1f}s "
        f"exact={out['exact']}"
    )
    print("  alpha", np.round(alpha, 4).tolist())
    print("  components", comp, "warnings", out["warnings"], flush=True)
    (OUT / f"{name}_solve.json").write_text(json.dumps(out, indent=1))


# ---------------- 7. nonlinear, hot and cold --------------------------------------------------
class VanDerPol(gridlbc.systems.ControlAffineSystem):
    state_dim, control_dim, state_names = 2, 1, ("x", "v")

    def __init__(self, mu=1.0):
        self.mu = mu

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], self.mu * (1 - x[:, 0] ** 2) * x[:, 1] - x[:, 0]], 1)

    def input_matrix(self, x):
        B = np.zeros((self._states(x).shape[0], 2, 1))
        B[:, 1, 0] = 1.0
        return B

    def parameters(self):
        return {"mu": self.mu}


class Duffing(gridlbc.systems.ControlAffineSystem):
    state_dim, control_dim, state_names = 2, 1, ("x", "v")

    def __init__(self, damping=0.2):
        self.damping = damping

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], x[:, 0] - x[:, 0] ** 3 - self.damping * x[:, 1]], 1)

    def input_matrix(self, x):
        B = np.zeros((self._states(x).shape[0], 2, 1))
        B[:, 1, 0] = 1.0
        return B

    def parameters(self):
        return {"damping": self.damping}


def vdp_hot():
    """Van der Pol (μ = 1), u on the velocity, λ = 3, T = 3, q = 0.5 (x² + v²), g =
    Quadratic(0, (1, 1)), [−4, 4]² with 151²."""
    return Problem(
        VanDerPol(),
        box(151, -4.0, 4.0),
        3.0,
        Quadratic([0.0, 0.0], [1.0, 1.0]),
        state_cost=lambda x: 0.5 * (x[:, 0] ** 2 + x[:, 1] ** 2),
        temperature=3.0,
    )


def duffing_cold():
    """Duffing (ẍ = x − x³ − 0.2 ẋ + u, wells at ±1), λ = 0.01, T = 2, q = 0.05 v², g = 0.5 (x −
    1)² + 0.2 v² (a user's lambda), [−2, 2]² with 151²."""
    return Problem(
        Duffing(),
        box(151),
        2.0,
        lambda x: 0.5 * (x[:, 0] - 1.0) ** 2 + 0.2 * x[:, 1] ** 2,
        state_cost=lambda x: 0.05 * x[:, 1] ** 2,
        temperature=0.01,
    )


def certified(build, factor=4, samples=2000, dt=0.004):
    def truth(X):
        p = build()
        fine = p.replace(grid=Grid([Axis(a.lo, a.hi, (a.n - 1) * factor + 1) for a in p.grid.axes]))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            s = gridlbc.solve(fine, error_estimate=False)
            print(
                f"    fine solve {time.perf_counter() - t0:.1f} s, dt {s.diagnostics.dt}",
                flush=True,
            )
            c = gridlbc.certify(
                fine,
                s.policy,
                np.asarray(X),
                n_samples=samples,
                dt=dt,
                seed=14,
                richardson=True,
                progress=False,
            )
        info = dict(
            ess=np.atleast_1d(c.effective_sample_size).tolist(),
            k=np.atleast_1d(c.pareto_k).tolist(),
            fine=s.value(np.asarray(X)).tolist(),
            v_dt=np.atleast_1d(c.optimal_value).tolist(),
            se=np.atleast_1d(c.extrapolated_value_se).tolist(),
        )
        print(f"    certificate {info}", flush=True)
        (OUT / f"{p.system.__class__.__name__}_cert_info.json").write_text(json.dumps(info))
        return np.asarray(c.extrapolated_value), np.asarray(c.extrapolated_value_se)

    return truth


P14 = {
    "hz_long_wells": (
        hz_long_wells,
        S((0.0, 0.0), (1.5, -1.0), (-1.9, 1.5)),
        sum_cn(cn_1d(zero, q_long0, g_long0, 0.3, 25.0), cn_1d(zero, q_long1, zero, 0.3, 25.0)),
        "1-D",
    ),
    "hz_long_lq": (
        hz_long_lq,
        S((0.0, 0.0), (1.5, -1.0), (-2.5, 2.0)),
        riccati_lq(
            np.array([[0.0, 1.0], [0.0, 0.0]]),
            np.array([[0.0], [1.0]]),
            np.diag(LQ_W),
            np.diag(LQ_G),
            0.5,
            20.0,
        ),
        "ricc",
    ),
    "hz_long_pendulum": (
        hz_long_pendulum,
        S((PI, 0.0), (1.0, -2.0), (0.3, 0.5)),
        lib_finer(hz_long_pendulum),
        "fine",
    ),
    "hz_short_kink": (
        hz_short_kink,
        S((0.325, -0.125), (0.31, 0.3), (-1.0, 0.5)),
        exact_sep([g_kink0, g_kink1], 0.2, 0.004, q=1.0),
        "exact",
    ),
    "hz_short_step": (
        hz_short_step,
        S((0.01, 0.0), (0.04, 0.5), (-0.02, -1.0)),
        exact_box_indicator((0.025, -2.0), (2.0, 2.0), 1.0, 0.2, 0.002, 1.0),
        "exact",
    ),
    "hz_short_step_off": (
        hz_short_step_off,
        S((0.51, 0.0), (0.54, 0.5), (0.3, -1.0)),
        exact_box_indicator((0.525, -2.0), (2.0, 2.0), 1.0, 0.2, 0.002, 1.0),
        "exact",
    ),
    "hz_steep_mid": (
        hz_steep_mid,
        S(GS_C, (0.335, -0.245), (0.4, -0.3)),
        exact_sep([_qg(GS_C[0], 50.0), _qg(GS_C[1], 50.0)], 0.05, 0.02),
        "exact",
    ),
    "hz_short_steep": (
        hz_short_steep,
        S(GS_C, (0.335, -0.245), (0.4, -0.3)),
        exact_sep([_qg(GS_C[0], 50.0), _qg(GS_C[1], 50.0)], 0.05, 0.002),
        "exact",
    ),
    "hz_short_vee": (
        hz_short_vee,
        S((0.325, -0.125), (0.31, 0.3), (0.0, -0.11)),
        exact_sep([g_vee0, g_vee1], 0.2, 0.001, q=1.0),
        "exact",
    ),
    "hz_short_steep_user": (
        hz_short_steep_user,
        S(GS_C, (0.335, -0.245), (0.4, -0.3)),
        exact_sep([_qg(GS_C[0], 50.0), _qg(GS_C[1], 50.0)], 0.05, 0.002),
        "exact",
    ),
    "hz_box_large_cold": (
        hz_box_large_cold,
        S((0.3, -0.2), (0.0, 0.5), (-1.0, -1.0)),
        exact_sep([_qg(0.3, 2.0), _qg(-0.2, 2.0)], 0.02, 1.0, q=0.3, bounds=((-20, 20), (-20, 20))),
        "exact",
    ),
    "hz_long_unstable": (
        hz_long_unstable,
        S((0.0, 0.0), (0.3, -0.5), (-0.6, 1.5)),
        riccati_lq(
            np.array([[0.0, 1.0], [4.0, -0.5]]),
            np.array([[0.0], [1.0]]),
            np.diag([1.0, 0.1]),
            np.zeros((2, 2)),
            0.1,
            20.0,
        ),
        "ricc",
    ),
    "hz_goal_steep": (
        hz_goal_steep,
        S(GS_C, (0.45, -0.15), (0.0, 0.1)),
        exact_sep([_qg(GS_C[0], 50.0), _qg(GS_C[1], 50.0)], 0.05, 0.1),
        "exact",
    ),
    "hz_box_goal": (
        hz_box_goal,
        S((0.075, 0.025), (0.475, 0.0), (0.8, -0.5)),
        exact_box_indicator(BOX_LO, BOX_HI, 2.0, 0.2, 0.3, 0.2),
        "exact",
    ),
    "hz_min_goals": (
        hz_min_goals,
        S((-0.1, 0.25), (0.55, 0.4), (0.4, -0.5)),
        exact_2d(g_min, 0.1, 0.5, q=0.5),
        "exact",
    ),
    "hz_box_small": (
        hz_box_small,
        S((0.0, 0.0), (0.9, -0.9), (-0.8, 0.5)),
        exact_sep([g_small0, g_small1], 0.3, 1.5, q=0.1, bounds=((-1, 1), (-1, 1))),
        "exact",
    ),
    "hz_box_large": (
        hz_box_large,
        S((0.3, -0.2), (0.0, 0.5), (-1.0, -1.0)),
        exact_sep([_qg(0.3, 2.0), _qg(-0.2, 2.0)], 0.1, 1.0, q=0.3, bounds=((-20, 20), (-20, 20))),
        "exact",
    ),
    "hz_unequal": (
        hz_unequal,
        S((0.2, 0.35), (0.0, 0.0), (-0.5, 0.8)),
        exact_sep([g_un0, g_un1], 0.1, 0.5, q=0.2),
        "exact",
    ),
    "rotor_rail": (
        rotor_rail,
        S((PI, 0.0, 0.0), (0.5, 1.0, -1.0), (-2.0, -2.0, 1.2)),
        rotor_truth,
        "2-D+1",
    ),
    "combo_weights": (
        lambda: combo_weights()[0],
        S((-0.8, 0.0), (0.4, 0.2), (0.1, -0.9)),
        combo_truth(combo_weights),
        "exact",
    ),
    "combo_cancel": (
        lambda: combo_cancel()[0],
        S((0.1, -0.05), (0.3, 0.1), (1.0, -1.0)),
        combo_truth(combo_cancel),
        "exact",
    ),
    "combo_cancel_sharp": (
        lambda: combo_cancel_sharp()[0],
        S((0.1, -0.05), (0.3, 0.1), (1.0, -1.0)),
        combo_truth(combo_cancel_sharp),
        "exact",
    ),
    "vdp_hot": (vdp_hot, S((2.0, 0.0), (0.0, 2.5), (-1.0, -1.0)), certified(vdp_hot), "cert"),
    "duffing_cold": (
        duffing_cold,
        S((1.0, 0.0), (-1.0, 0.0), (0.0, 0.5)),
        certified(duffing_cold, factor=2),
        "cert",
    ),
}


COMBOS = {n: globals()[n] for n in ("combo_weights", "combo_cancel", "combo_cancel_sharp")}


def main(argv):
    # round 13's command line (round 12's runner and table, round 13's --tol) on this round's
    # problems and combinations
    r13.P13, r13.OUT, r13.combo_quick = P14, OUT, combo_quick
    r13.main(argv)


if __name__ == "__main__":
    main(sys.argv[1:])
