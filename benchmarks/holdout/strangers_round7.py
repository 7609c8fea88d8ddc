"""Stranger round 7: problems aimed at γ, the cost the grid's interpolants add along the solve's
own paths (``gridlbc.accuracy.cost_gap``), and at the estimate in general.

Not a corpus member and not run by the tests. The runner, the certificate recipe and the output
format are round 3's (``strangers_round3.run``: the default solve, a finer solve's policy as the
certificate's proposal at ``cert_dt`` and ``cert_dt / 2``, extrapolated), registered as round 6
does; ``--own`` and ``--halfdt`` are its double checks.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round7.py NAME [NAME ...] [--own] [--halfdt]
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round7.py NAME --quick   (solve, v, ê, γ)
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round7.py goal_3d notch_terminal_hot pit_4d --exact
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round7.py NAME --diagnose  (ê's parts, γ at 1000 steps)
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round7.py torus_pit --study  (2×, 4×, 8× grids)
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round7.py pit_3d_cell --study  (3×, 4×)

Problems: (1) false alarms: ``stiff_relax`` (ẋ = −50x + u: γ's Euler–Maruyama at T/100 is
unstable), ``fast_spin`` (a rotation ω = 30), ``steep_bowl`` (q = 400x²), ``hot_kink`` (λ = 3, a
kink between nodes); (2) misses: ``gate_drift`` (a wall a fifth of a cell wide across a drift
with no noise along it), ``notch_terminal_hot`` (a notch 0.3 cell wide in g only, λ = 2),
``goal_3d`` (a narrow goal, w = h/2, at a 3-D cell centre; ``goal_3d_node``: on a node),
``pit_3d_cell`` (the same cost as a state cost too), ``ridge_quiet_axis`` (a ridge narrow along the
position axis, which the noise does not move), ``torus_pit`` (two periodic axes, the pit at the seam
corner, λ = 0.01), ``pit_4d`` (25⁴, a pit at a (x₁, x₂) cell centre).

Results (library of commit 351f36e, unchanged on this branch; run 2026-12-05, one thread; error =
(v − v*ₓ) / max(|v*ₓ|, λ) with v*ₓ the runner's extrapolated certificate, estimate =
ê / max(|v|, λ); v* ± SE at cert_dt / 2; time of the default solve in s)::

    problem            state                       v         v* ± SE      v*x   ESS     error     est  w  t/s
    stiff_relax        (0, 0)                 0.1540   0.1540±0.0001   0.1536   799    +0.29%  13.30%  Y  8.1
    stiff_relax        (1, 0.5)               0.2433   0.2434±0.0001   0.2431   799    +0.08%   3.23%  Y  8.1
    stiff_relax        (-1.5, -1)             0.4936   0.4941±0.0001   0.4921   799    +0.30%   0.29%  Y  8.1
    fast_spin          (0.5, 0)               0.9142   1.0791±0.0027   0.8849   700    +3.32%   1.69%  n 18.5
    fast_spin          (0, 1)                 1.2935   1.5438±0.0036   1.2296   638    +5.20%   1.69%  n 18.5
    fast_spin          (-0.8, -0.6)           1.2935   1.5492±0.0035   1.2376   641    +4.52%   1.69%  n 18.5
    fast_spin_still    (0.5, 0)               0.9084   0.9082±0.0004   0.9080   798    +0.05%   0.10%  n 10.3
    fast_spin_still    (0, 1)                 1.2846   1.2852±0.0004   1.2864   797    -0.14%   0.07%  n 10.3
    fast_spin_still    (-0.8, -0.6)           1.2846   1.2849±0.0004   1.2848   798    -0.02%   0.07%  n 10.3
    steep_bowl         (0.3, 0)              10.0302  10.1938±0.0004  10.1759   761    -1.43%   2.32%  Y  5.4
    steep_bowl         (-0.5, 1)             16.7495  16.9158±0.0004  16.8847   762    -0.80%   2.03%  Y  5.4
    steep_bowl         (0.1, -2)             10.9616  11.0949±0.0004  11.0746   758    -1.02%   2.03%  Y  5.4
    hot_kink           (1, 0)                 8.1141   8.1108±0.0055   8.1166   798    -0.03%   0.11%  n  0.6
    hot_kink           (-2, 1)                9.4978   9.4853±0.0054   9.4765   798    +0.22%   0.06%  n  0.6
    hot_kink           (0.5, -2)              9.0272   9.0205±0.0056   9.0140   798    +0.15%   0.26%  n  0.6
    gate_drift         (-1, 0)                0.1453   0.2389±0.0013   0.2376  1041   -38.84%  59.69%  Y  1.5
    gate_drift         (-0.515, 0.8)          0.4623   0.4734±0.0007   0.4748  2180    -2.62%  14.37%  Y  1.5
    gate_drift         (0, -0.5)              0.2004   0.8596±0.0117   0.8539    18   -76.53% 114.96%  Y  1.5
    notch_terminal_hot (0.3, 0)              10.0776   8.8843±0.0423   9.0300  1432   +11.60%  14.70%  Y  1.2
    notch_terminal_hot (-0.5, 1)             10.3536  10.0331±0.0485  10.1337  1192    +2.17%   3.48%  Y  1.2
    notch_terminal_hot (1, -1)               10.2712   8.7611±0.0500   8.8247  1143   +16.39%  18.13%  Y  1.2
    goal_3d            (0, 0, 0)              2.0138   1.2047±0.0146   1.1581    47   +73.89%   0.39%  n  1.0
    goal_3d            (1, -1, 0.5)           2.2148   2.1813±0.0274   2.1520    13    +2.92%   0.06%  n  1.0
    goal_3d            (0.35, 0.25, -0.2)     1.9867   1.0665±0.0256   1.0748    15   +84.84%   1.61%  n  1.0
    goal_3d_node       (0, 0, 0)              1.3267   1.1627±0.0160   1.1414    39   +16.24%  52.41%  Y  1.0
    goal_3d_node       (1, -1, 0.5)           2.2114   2.1963±0.0083   2.1801   142    +1.44%   0.51%  Y  1.0
    goal_3d_node       (0.3, 0.2, -0.15)      1.2147   1.0788±0.0111   1.0918    79   +11.26%  66.88%  Y  1.0
    pit_3d_cell        (0, 0, 0)              4.0206   3.1635±0.0154   3.1928    40   +25.93%   0.28%  n  1.1
    pit_3d_cell        (1, -1, 0.5)           4.4075   4.3794±0.0173   4.3858    32    +0.50%   0.06%  n  1.1
    pit_3d_cell        (0.35, 0.25, -0.2)     3.9761   2.9410±0.0169   2.8957    34   +37.31%   1.37%  n  1.1
    pit_3d_cell_x3     (0, 0, 0)              4.0206   3.2349±0.0523   3.3863     4   +18.73%   0.28%  n  1.4
    pit_3d_cell_x3     (1, -1, 0.5)           4.4075   4.3827±0.0091   4.3610   116    +1.07%   0.06%  n  1.4
    pit_3d_cell_x3     (0.35, 0.25, -0.2)     3.9761   3.1329±0.0167   3.1718    35   +25.36%   1.37%  n  1.4
    ridge_quiet_axis   (-1, 0.5)              3.0456   3.3891±0.0044   3.3889    20   -10.13%  16.20%  Y  1.6
    ridge_quiet_axis   (0, 0)                 1.3100   1.7613±0.0025   1.7579    59   -25.48%  33.13%  Y  1.6
    ridge_quiet_axis   (-0.5, 1.5)            1.9090   2.1935±0.0058   2.1956    12   -13.06%  20.62%  Y  1.6
    torus_pit          (2.8, 2.5)            10.1810   5.2870±0.0071  -6.9577     2  +246.33%  21.19%  Y  0.9
    torus_pit          (-3, 0)               12.2529   8.6516±0.0098  -5.0426     1  +342.99%  13.72%  Y  0.9
    torus_pit          (2, -2.9)             11.6413   7.0526±0.0067  -6.1314     2  +289.86%  17.35%  Y  0.9
    pit_4d             (0, 0, 0, 0)           6.3101   2.6067±0.0221   2.5483     5  +147.61%  16.69%  Y  5.8
    pit_4d             (0.5, -1, 0.5, 0)      7.2326   3.8713±0.0388   3.8292     2   +88.88%  10.85%  Y  5.8
    pit_4d             (-0.6, 0.4, 0, -0.5)   7.3593   4.0773±0.0322   4.0342     2   +82.42%  15.39%  Y  5.8

Better truths where the certificates cannot be trusted (the error and estimate columns above use
the certificates; these replace them in the verdict):

- ``goal_3d``, ``goal_3d_node``, ``notch_terminal_hot``: terminal cost only and Gaussian passive
  dynamics, so v = −λ log E exp(−g(X_T)/λ) by quadrature (``--exact``; halving the quadrature
  step changes nothing at 4 decimals). goal_3d v* = 1.2246, 2.2075, 1.0624: errors +64.5 %,
  +0.33 %, +87.0 %. goal_3d_node v* = 1.1662, 2.1988, 1.0527: +13.8 %, +0.57 %, +15.4 %.
  notch_terminal_hot v* = 8.7293, 10.0389, 8.5962: +15.5 %, +3.1 %, +19.5 %. The 3-D certificates
  are biased high: with the 3× proposal (``goal_3d_x3``, 121³) they give 1.52, 2.2151 ± 0.0004
  (ESS 3797), 1.37 — at (1, −1, 0.5) twenty standard errors above the exact 2.2075, the goal's
  −0.007 unsampled; the 121³ solve itself gives 1.268, 2.210, 1.106.
- ``pit_4d``: costs, noise and box separate into (x₁, x₂) and (x₃, x₄) (``--exact``): v* =
  2.5077, 3.8144, 3.9889 (the 2-D pit on 401² and 801² agreeing to 1e-4, plus
  ``reference.lq_solution``): errors +151.6 %, +89.6 %, +84.5 %. (Its 2-D certificates with the
  801² policy: ESS 1–25, 0.1–0.2 above.)
- ``torus_pit``: the certificates degenerate (ESS 1–2, dt and dt/2 disagree by a factor 2–3) with
  either the 2× or the 4× proposal; the grid study (``--study``; the pit is on a node of the 2×,
  4×, 8× grids) gives 4.880/4.630/4.611, 8.158/7.981/7.966, 6.576/6.342/6.323: against the 960²
  values, +120.8 %, +53.8 %, +84.1 %.
- ``pit_3d_cell``: no closed form; the 3×, 4× grids (121³, 161³) give 3.197/3.167, 4.387/4.381,
  3.005/2.975, decreasing towards the truth from above as goal_3d's do (41³, 61³, 121³: 2.014,
  1.539, 1.268 against the exact 1.225), so the errors are at least +27.0 % and +33.7 % at the
  first and third states.
- ``fast_spin``: its certificate is wrong (the Euler–Maruyama rotation at Δt = 0.001 grows r² by
  (1 + (ωΔt)²)^{T/Δt} ≈ 15; dt and dt/2 differ by 18 %). Costs and noise are rotation invariant,
  so its value is that of ω = 0 (``fast_spin_still``, ESS ≈ 800): 0.9082, 1.2852, 1.2849;
  errors +0.66 %, +0.65 %, +0.67 % with estimates 1.69 %.

Tally with these truths (12 problems, 36 pairs; the _x3 and _still rows are checks): the
estimate is at least half the error at 23 of 36 (64 %, contract ≥ 90 %); silently more than
10 % off at 4 pairs; falsely warned (error < 2 %) at 6 pairs of 2 problems (and at
goal_3d_node's (1, −1, 0.5), +0.57 %, which its other states warn for rightly).

**Broken (1): a narrow goal or pit at a 3-D cell centre, silent.** ``goal_3d`` (builder
``goal_3d()``, 41³, goal w = 0.05 = h/2 at c = (0.35, 0.25, −0.45), the centre of a cell:
√3 h/2 = 1.7 w from all 8 of its nodes; λ = 0.1, T = 1): against the exact truth +64.5 % at
(0, 0, 0) and +87.0 % at (0.35, 0.25, −0.2), estimates 0.39 % and 1.61 %, no warning; +0.33 %
with 0.06 % at (1, −1, 0.5). ``--diagnose``: the embedded/pair part is the whole estimate (0.39,
0.06, 1.61 %, observed order 1.17); γ is 0.03, 0.02, −0.73 % (16 paths, 100 steps), 0.07, 0.02,
1.03 % (256 paths, 1000 steps): the paths of the solve's policy end in the grid's shallow dip
(the goal term of I_h g is 1.55 throughout the goal's cell: all 8 nodes are 1.73 w from c) and
almost never within w of c, whereas the optimum for g does go there (λ = 0.1 against a depth
of 2: a factor e²⁰). γ is a lower bound on v[I_h g] − v[g] along π_h, and π_h is not the
policy that exploits what the grid cannot see.
The coarser grids miss the goal nearly alike, though not by the same offsets (pair offsets
0.16/0.34, 0.31/0.19, 0.36/0.14 cells on the three axes): their nearest nodes are 1.73 w
(embedded), 2.13 w and 1.56 w (pair) from c, where the goal term of g is 1.55, 1.79 and 1.41 (0
at c, 2 far off), and the embedded and pair terms (the whole estimate) are 0.06–1.6 %. The same
goal on a node (``goal_3d_node``, c = (0.3, 0.2, −0.4)) is seen: +13.8 %, +0.57 %, +15.4 % with
52 %, 0.51 %, 67 %, warned.
``pit_3d_cell`` (builder ``goal_3d(running=True)``, the same cost as a state cost too): +25.9 %
and +37.3 % (certificates; at least +27.0 % and +33.7 % against the 161³ solve) with estimates
0.28 % and 1.37 %, silent; γ 0.02, 0.02, 1.1 % (0.1, 0.02, 0.48 % from 256 paths of 1000 steps);
no warning with or without γ. ``solve(problem, tol=0.05, states=X)`` stops on the default 41³
grid and step for both, silent, with the same values.

**Broken (2): a false warning from γ's Euler–Maruyama paths where the dynamics are fast.**
``stiff_relax`` (builder ``stiff_relax()``, ẋ = −50x + u₁, ẏ = u₂, 101², λ = 0.1, T = 5, a
resolved obstacle at |x| = 1.7 that no controlled path nears): errors +0.29 %, +0.08 %, +0.30 %
(ESS 799; the 201² solve agrees to 0.1 %), estimates 13.3 %, 3.2 %, 0.29 %, warned ("exceeds 5 %
at 69 % of the states that matter … largest 53 %"). ``--diagnose``: the embedded/pair part is
0.40, 0.35, 0.29 %; γ is −13.3, −3.2, −0.25 % from 16 paths of 100 steps (−7.4, −4.8, −2.4 % from
256), but +1.24, +0.78, +0.54 % from 1000 steps; with γ patched to zero the solve does not warn.
The solve took 1042 steps (Δt = 0.0048); γ's paths take 100 of 0.05, where 1 − kΔt = −1.5: the
Euler–Maruyama paths oscillate with growing amplitude, reflect at the walls and cross the
obstacle, which the true process never reaches (the sign of γ is then that of I_h q − q on the
obstacle's crest: negative).

**Broken (3): warned, but the estimate a fifth to a tenth of the error (contract (a)).**
``torus_pit`` (builder ``torus_pit()``, both axes periodic, 120², pit w = h/2 at the seam
corner, λ = 0.01): +120.8 %, +53.8 %, +84.1 % against the 960² solve, estimates 21.2 %, 13.7 %,
17.4 % (γ 20.7, 7.3, 16.4 %). ``pit_4d`` (builder ``pit_4d()``, 25⁴, a pit w = 0.08 = 0.48 h at a
cell centre of (x₁, x₂)): +151.6 %, +89.6 %, +84.5 % against the separated truth, estimates
16.7 %, 10.9 %, 15.4 % (all γ). γ sees these pits (the paths sit in the grid's smeared pit, on
the cell that holds the true one) but as the lower bound it is: along π_h, which sits where the
grid thinks the pit is, not at its centre where the optimum sits.

**False warning of another kind.** ``steep_bowl`` (q = g = 400x² + 0.2v², 201², λ = 0.05,
T = 3, 50 steps): errors −1.4 %, −0.8 %, −1.0 % with estimates 2.0–2.3 %, but the solve warns
(ResolutionWarning) that the optimal control moves the state by 54 cells per step. Not the
estimate's warning; the certificates' dt and dt/2 differ by 0.2 %, so the errors are 0.8–1.6 %.

**Not broken.** ``gate_drift``: as designed, γ does not see the thin wall (0.04–0.19 %: x
advances by the same 1.5Δt on every path, which steps over it), but the embedded/pair
differences do: −38.8 %, −2.6 %, −76.5 % with 59.7 %, 14.4 %, 115 %, warned (the third state's ESS
is 18). ``notch_terminal_hot``: +15.5 %, +3.1 %, +19.5 % (exact) with 14.7 %, 3.5 %, 18.1 %,
warned; here too γ is small (1.5, 0, 1.3 %) and the embedded solves carry the estimate.
``ridge_quiet_axis``: −10.1 %, −25.5 %, −13.1 % with 16.2 %, 33.1 %, 20.6 % (all γ, negative:
the paths cross a ridge the grid flattens), warned (ESS 12–59). ``hot_kink`` (λ = 3): within
0.22 % with 0.06–0.26 % (at (−2, 1) +0.22 % against 0.06 %, inside the certificate's noise: v*
and v*ₓ differ by 0.09 %). ``fast_spin``: +0.66 % with 1.69 % against fast_spin_still's truth;
γ's paths did not blow up here (ω = 30, 100 steps of 0.03: |γ| ≤ 0.7 %).
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import strangers_round3 as r3  # noqa: E402
from corpus import GOAL_IN_CELL, Affine, goal_in_cell, stiff_relax  # noqa: E402
from strangers_round5 import _wrap  # noqa: E402

import gridlbc  # noqa: E402
from gridlbc import Problem, Quadratic  # noqa: E402
from gridlbc.accuracy import cost_gap  # noqa: E402
from gridlbc.systems import LinearSystem, PointMass  # noqa: E402

OUT = HERE / "strangers_round7_results"
PI = np.pi
G, S = r3.G, r3.S


def _bump(d, width):
    return np.exp(-0.5 * (d / width) ** 2)


# ---- (1) false alarms: accurate solves where γ could be large ----
def fast_spin(omega=30.0):
    """A fast rotation ẋ = −ωy + u₁, ẏ = ωx + u₂ (ω = 30) on [−2, 2]² (151²), q = r² /2 plus a
    resolved ring ridge 10 exp(−(r − 1.75)²/2w²) (w = 0.05) outside every start, g = 2r², λ = 0.2,
    T = 3. Euler–Maruyama with Δt = 0.03 grows r by √(1 + (ωΔt)²) = 1.35 per step."""

    def q(x):
        x = np.atleast_2d(x)
        r = np.hypot(x[:, 0], x[:, 1])
        return 0.5 * r**2 + 10 * _bump(r - 1.75, 0.05)

    sys_ = Affine(lambda x: np.stack([-omega * x[:, 1], omega * x[:, 0]], 1), np.eye(2))
    return Problem(
        sys_,
        G((-2, 2, 151), (-2, 2, 151)),
        3.0,
        Quadratic([0, 0], [2.0, 2.0]),
        state_cost=q,
        temperature=0.2,
    )


def steep_bowl():
    """A point mass in a steep but resolved bowl q = 400 x² + 0.2 v² (I_h q − q up to
    400 h²/4 = 0.04 per unit time on 201 nodes over [−2, 2]), g = q, λ = 0.05, T = 3."""
    return Problem(
        PointMass(),
        G((-2, 2, 201), (-4, 4, 201)),
        3.0,
        Quadratic([0, 0], [400.0, 0.2]),
        state_cost=Quadratic([0, 0], [400.0, 0.2]),
        temperature=0.05,
    )


def hot_kink():
    """λ = 3 (paths spread over the whole box), a point mass with a kinked cost
    q = 2|x − 0.013| + 0.1 v² (the kink between two nodes of 101 over [−3, 3]: h = 0.06) and a
    sharp terminal valley g = 4|x − 0.013|, T = 2, [−3, 3] × [−6, 6] on 101²."""

    def q(x):
        x = np.atleast_2d(x)
        return 2 * np.abs(x[:, 0] - 0.013) + 0.1 * x[:, 1] ** 2

    def g(x):
        x = np.atleast_2d(x)
        return 4 * np.abs(x[:, 0] - 0.013)

    return Problem(
        PointMass(),
        G((-3, 3, 101), (-6, 6, 101)),
        2.0,
        g,
        state_cost=q,
        temperature=3.0,
    )


# ---- (2) misses: narrow features the paths step over ----
def gate_drift(width=0.004):
    """ẋ = 1.5 (no noise, no control on x), ẏ = u: a thin wall 100 exp(−(x − 0.51)²/2w²),
    w = 0.004 (a fifth of a cell, midway between the nodes 0.50 and 0.52 of 201 over [−2, 2]),
    with a gate 1 − exp(−(y − 0.3)²/2·0.15²) in it, + 0.5 y², g = 2y², λ = 0.05, T = 2. γ's
    paths move along x by the same 1.5 Δt = 0.03 each: whether a sample lands in the wall
    (± 0.01) is fixed by the start's x."""

    def q(x):
        x = np.atleast_2d(x)
        wall = 100 * _bump(x[:, 0] - 0.51, width) * (1 - _bump(x[:, 1] - 0.3, 0.15))
        return wall + 0.5 * x[:, 1] ** 2

    sys_ = Affine(lambda x: np.stack([np.full(len(x), 1.5), 0 * x[:, 1]], 1), [[0.0], [1.0]])
    return Problem(
        sys_,
        G((-2, 2, 201), (-2, 2, 201)),
        2.0,
        Quadratic([0, 0], [0.0, 2.0]),
        state_cost=q,
        temperature=0.05,
    )


def notch_terminal_hot():
    """Terminal cost only at a large temperature: a point mass, g = 0.5 x² + 0.2 v² − 10
    exp(−(x − 0.51)²/2w²), w = 0.006 (0.3 cell, midway between 0.50 and 0.52, 201 nodes over
    [−2, 2]), λ = 2, T = 0.5. At λ = 2 the optimum tilts the paths into the notch (e^{5}); γ's
    paths, driven by a policy that does not see it, land in it about 1 % of the time."""

    def g(x):
        x = np.atleast_2d(x)
        return 0.5 * x[:, 0] ** 2 + 0.2 * x[:, 1] ** 2 - 10 * _bump(x[:, 0] - 0.51, 0.006) + 10

    return Problem(
        PointMass(),
        G((-2, 2, 201), (-4, 4, 201)),
        0.5,
        g,
        temperature=2.0,
    )


GOAL = GOAL_IN_CELL


def goal_3d(c=GOAL, running=False):
    """corpus.goal_in_cell: the 3-D goal (w = h/2) at ``c`` (a cell centre by default)."""
    return goal_in_cell(c, running)


def ridge_quiet_axis():
    """A point mass whose noise does not move x: a narrow cost ridge along v (a line x = 0.31,
    across the position axis, 0.3 cell wide: w = 0.006, midway between 0.30 and 0.32) of height
    30, + 0.5 v² + 0.5 (x − 1)², g = 2(x − 1)² + 2v², λ = 0.02, T = 3, 201² on [−2, 2] × [−3, 3].
    Paths from x < 0.31 must cross it (or stay left)."""

    def q(x):
        x = np.atleast_2d(x)
        return 30 * _bump(x[:, 0] - 0.31, 0.006) + 0.5 * x[:, 1] ** 2 + 0.5 * (x[:, 0] - 1) ** 2

    return Problem(
        PointMass(),
        G((-2, 2, 201), (-3, 3, 201)),
        3.0,
        Quadratic([1, 0], [2.0, 2.0]),
        state_cost=q,
        temperature=0.02,
    )


def torus_pit():
    """Both axes periodic (a torus, 120 × 120 nodes over [−π, π)²), ẋ = u₁, ẏ = 0.8 + u₂ (a
    circulation along y): a pit 3(1 − exp(−(Δx² + Δy²)/2w²)), w = 0.5 h = 0.026, at the seam
    corner (x, y) = (π − h/2, π − h/2) (midway between the last node and the first in both),
    λ = 0.01, T = 4, g = q."""
    h = 2 * PI / 120
    c = PI - h / 2

    def q(x):
        x = np.atleast_2d(x)
        r2 = _wrap(x[:, 0] - c) ** 2 + _wrap(x[:, 1] - c) ** 2
        return 3 * (1 - np.exp(-0.5 * r2 / (0.5 * h) ** 2))

    sys_ = Affine(
        lambda x: np.stack([0 * x[:, 0], np.full(len(x), 0.8)], 1),
        np.eye(2),
        names=("a", "b"),
        angle_axes=(0, 1),
    )
    return Problem(
        sys_,
        G((-PI, PI, 120, True), (-PI, PI, 120, True)),
        4.0,
        q,
        state_cost=q,
        temperature=0.01,
    )


def pit_4d():
    """A 4-D single integrator ẋ = u on [−2, 2]⁴ (25⁴, h = 1/6): a pit in (x₁, x₂),
    3(1 − exp(−Δ²/2w²)), w = 0.08, at a cell centre (1/12, −1/4) + 0.2(x₃² + x₄²), λ = 0.05,
    T = 2, g = q."""
    c = np.array([1 / 12, -1 / 4])

    def q(x):
        x = np.atleast_2d(x)
        r2 = np.sum((x[:, :2] - c) ** 2, axis=1)
        return 3 * (1 - np.exp(-0.5 * r2 / 0.08**2)) + 0.2 * (x[:, 2] ** 2 + x[:, 3] ** 2)

    sys_ = Affine(lambda x: np.zeros_like(x), np.eye(4))
    return Problem(sys_, G(*[(-2, 2, 25)] * 4), 2.0, q, state_cost=q, temperature=0.05)


# ---- exact truths of the two terminal-only problems with Gaussian passive dynamics ----
def exact_goal_3d(X, step=0.005, c=GOAL):
    """goal_3d's v(x, 0) = −λ log E exp(−g(x + √(λT) N)/λ) (B = I, R = 1: the passive process is
    λ-scaled Brownian motion; the walls, ≥ 3 standard deviations away and against the pull of
    0.1|x|², are ignored): the quadratic part in closed form, the goal's excess
    exp(20 e^{−r²/2w²}) − 1 by the trapezoid rule on a cube of half-side 7w around c (spacing
    w/10)."""
    lam, T, w = 0.1, 1.0, 0.05
    c = np.asarray(c, float)
    s2 = lam * T
    ax = np.arange(-7 * w, 7 * w + step / 2, step)
    Y = np.stack(np.meshgrid(ax, ax, ax, indexing="ij"), -1).reshape(-1, 3) + c
    excess = np.expm1(20 * np.exp(-0.5 * np.sum((Y - c) ** 2, 1) / w**2)) * np.exp(-np.sum(Y**2, 1))
    out = []
    for x in np.atleast_2d(X):
        closed = np.prod(np.exp(-(x**2) / (1 + 2 * s2)) / np.sqrt(1 + 2 * s2))
        kernel = np.exp(-0.5 * np.sum((Y - x) ** 2, 1) / s2) / (2 * PI * s2) ** 1.5
        z = closed + np.sum(kernel * excess) * step**3
        out.append(-lam * (np.log(z) - 20))
    return np.array(out)


def exact_notch(X, dx=0.0005, dv=0.01):
    """notch_terminal_hot's v(x, 0) = −λ log E exp(−g(X_T)/λ), X_T Gaussian (mean (x + vT, v),
    covariance λ[[T³/3, T²/2], [T²/2, T]]), by the trapezoid rule on x ∈ [−2.5, 3.5] (spacing
    0.0005, w/12) × v ∈ [−7, 7] (0.01); the walls (≥ 5 and 3 standard deviations) ignored."""
    lam, T, w = 2.0, 0.5, 0.006
    C = lam * np.array([[T**3 / 3, T**2 / 2], [T**2 / 2, T]])
    Ci, det = np.linalg.inv(C), np.linalg.det(C)
    xs, vs = np.arange(-2.5, 3.5, dx), np.arange(-7, 7, dv)
    gx = 0.5 * xs**2 - 10 * _bump(xs - 0.51, w) + 10
    out = []
    for x0, v0 in np.atleast_2d(X):
        m = np.array([x0 + v0 * T, v0])
        z = 0.0
        for i in range(0, len(xs), 2000):
            a = xs[i : i + 2000, None] - m[0]
            b = vs[None, :] - m[1]
            quad = Ci[0, 0] * a**2 + 2 * Ci[0, 1] * a * b + Ci[1, 1] * b**2
            g = gx[i : i + 2000, None] + 0.2 * vs[None, :] ** 2
            z += np.sum(np.exp(-0.5 * quad - g / lam)) * dx * dv
        out.append(-lam * np.log(z / (2 * PI * np.sqrt(det))))
    return np.array(out)


def split_pit_4d(X, nodes=(401, 801), n=1500, dt=0.001):
    """pit_4d's truth by separation: its costs are a sum over (x₁, x₂) and (x₃, x₄), the noise and
    the box are products, so v = v_pit(x₁, x₂) + v_LQ(x₃, x₄). v_LQ by
    ``gridlbc.reference.lq_solution`` (on R², the walls 6 standard deviations away);
    v_pit by 2-D solves at ``nodes`` per axis (w = 8 and 16 cells) and certified with the finest
    one's policy at ``dt`` and ``dt / 2`` (n samples). Prints each piece; returns the sum with
    v_pit of the finest grid (401² and 801² agree to 1e-4; the 2-D certificates degenerate, ESS
    1–25, and lie 0.1–0.2 above it: an upper bound in expectation)."""
    from gridlbc.reference import lq_solution

    c, lam, T = np.array([1 / 12, -1 / 4]), 0.05, 2.0

    def q(x):
        x = np.atleast_2d(x)
        return 3 * (1 - np.exp(-0.5 * np.sum((x - c) ** 2, axis=1) / 0.08**2))

    X = np.atleast_2d(X)
    sys2 = Affine(lambda x: np.zeros_like(x), np.eye(2))
    lq = Problem(
        LinearSystem(np.zeros((2, 2)), np.eye(2)),
        None,
        T,
        Quadratic([0, 0], [0.2, 0.2]),
        state_cost=Quadratic([0, 0], [0.2, 0.2]),
        temperature=lam,
    )
    v34 = lq_solution(lq).value(X[:, 2:], 0.0)
    print("v_LQ(x3, x4):", np.round(v34, 5).tolist())
    pit = None
    for k in nodes:
        pit = Problem(sys2, G((-2, 2, k), (-2, 2, k)), T, q, state_cost=q, temperature=lam)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sol = gridlbc.solve(pit)
        v12 = sol.value(X[:, :2])
        print(f"v_pit on {k}²:", np.round(v12, 5).tolist(), flush=True)
    out = []
    for j, d in enumerate((dt, dt / 2)):
        cert, w = r3.cert(pit, sol.policy, X[:, :2], n, d, 11 + j, None)
        print(
            f"v_pit certified dt={d}:",
            np.round(cert.optimal_value, 5).tolist(),
            "±",
            np.round(cert.optimal_value_se, 5).tolist(),
            "ESS",
            np.round(cert.effective_sample_size).tolist(),
            w[:2],
            flush=True,
        )
        out.append(cert.optimal_value)
    print("v* = v_pit(dt/2) + v_LQ:", np.round(out[1] + v34, 4).tolist())
    print("v*x (extrapolated) + v_LQ:", np.round(2 * out[1] - out[0] + v34, 4).tolist())
    print("v_pit (finest grid) + v_LQ:", np.round(v12 + v34, 4).tolist())
    return v12 + v34


EXACT = {
    "goal_3d": exact_goal_3d,
    "goal_3d_node": lambda X: exact_goal_3d(X, c=(0.3, 0.2, -0.4)),
    "notch_terminal_hot": exact_notch,
}
EXACT["pit_4d"] = split_pit_4d


P7 = {  # name: builder, states, cert_dt, fine, max_time (round 3's layout)
    "stiff_relax": (stiff_relax, S((0, 0), (1.0, 0.5), (-1.5, -1.0)), 0.002, 2.0, None),
    "fast_spin": (fast_spin, S((0.5, 0), (0, 1.0), (-0.8, -0.6)), 0.001, 2.0, None),
    # fast_spin's costs and noise are rotation invariant, so its value is that of ω = 0 (the
    # certificate's Euler–Maruyama at Δt = 0.001 grows r² by (1 + (ωΔt)²)^{T/Δt} ≈ 15)
    "fast_spin_still": (
        lambda: fast_spin(0.0),
        S((0.5, 0), (0, 1.0), (-0.8, -0.6)),
        0.001,
        2.0,
        None,
    ),
    "steep_bowl": (steep_bowl, S((0.3, 0), (-0.5, 1.0), (0.1, -2.0)), 0.001, 2.0, None),
    "hot_kink": (hot_kink, S((1.0, 0), (-2.0, 1.0), (0.5, -2.0)), 0.002, 2.0, None),
    "gate_drift": (gate_drift, S((-1.0, 0), (-0.515, 0.8), (0.0, -0.5)), 0.001, 2.0, None),
    "notch_terminal_hot": (
        notch_terminal_hot,
        S((0.3, 0), (-0.5, 1.0), (1.0, -1.0)),
        0.001,
        2.0,
        None,
    ),
    "goal_3d": (goal_3d, S((0, 0, 0), (1.0, -1.0, 0.5), (0.35, 0.25, -0.2)), 0.002, 1.5, None),
    "goal_3d_node": (  # the goal on a node (0.3, 0.2, −0.4): the control
        lambda: goal_3d((0.3, 0.2, -0.4)),
        S((0, 0, 0), (1.0, -1.0, 0.5), (0.3, 0.2, -0.15)),
        0.002,
        1.5,
        None,
    ),
    "pit_3d_cell": (  # goal_3d's cost as state cost too: a pit at the cell centre
        lambda: goal_3d(running=True),
        S((0, 0, 0), (1.0, -1.0, 0.5), (0.35, 0.25, -0.2)),
        0.002,
        1.5,
        None,
    ),
    "ridge_quiet_axis": (
        ridge_quiet_axis,
        S((-1.0, 0.5), (0.0, 0.0), (-0.5, 1.5)),
        0.001,
        2.0,
        None,
    ),
    # the 2× grid (240²) has the pit on a node; its certificates degenerate (ESS 1–2): the
    # proposal is the 4× solve (480², pit on a node, w = 2 of its cells)
    "torus_pit": (torus_pit, S((2.8, 2.5), (-3.0, 0.0), (2.0, -2.9)), 0.001, 4.0, None),
    "pit_4d": (
        pit_4d,
        S((0, 0, 0, 0), (0.5, -1.0, 0.5, 0), (-0.6, 0.4, 0, -0.5)),
        0.002,
        1.5,
        None,
    ),
}
# the 3-D certificates again with a 3× proposal (121³, h = 0.033: the goal 1.5 cells wide);
# goal_3d's checks the certificate against its exact truth
for _name in ("goal_3d", "pit_3d_cell"):
    P7[_name + "_x3"] = P7[_name][:3] + (3.0, None)
r3.P.update(P7)


def quick(name):
    """The default solve only: v, ê and γ (relative), the warning, the time."""
    build, X = P7[name][:2]
    problem = build()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        sol = gridlbc.solve(problem)
        dt = time.perf_counter() - t0
        v, est = sol.value(X), sol.error_estimate(X)
        gap = cost_gap(sol, X)
    scale = np.maximum(np.abs(v), problem.temperature)
    for i in range(len(X)):
        print(
            f"{name:18s} {X[i].tolist()!s:22s} v={v[i]:8.4f} est={100 * est[i] / scale[i]:6.2f}% "
            f"gamma={100 * gap[i] / scale[i]:+7.2f}% t={dt:.1f}s steps={sol.diagnostics.steps}"
        )
    print("  warnings:", [f"{x.category.__name__}: {str(x.message)[:200]}" for x in w], flush=True)


def diagnose(name, steps=(100, 1000), samples=(16, 256)):
    """What the estimate is made of at the problem's states (relative to max(|v|, λ)): the
    embedded/pair part (max(local, floor)), γ from ``samples`` paths of ``steps`` Euler–Maruyama
    steps (``gridlbc.accuracy.paths.PATH_STEPS`` patched), and whether the default solve still
    warns with γ patched to zero."""
    from gridlbc.accuracy import estimate as est_mod
    from gridlbc.accuracy import paths

    build, X = P7[name][:2]
    problem = build()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        sol = gridlbc.solve(problem)
    v, _, local = sol.embedded._read(sol, X, 0.0)
    scale = np.maximum(np.abs(v), problem.temperature)
    base = np.maximum(local, sol.embedded.floor * scale) / scale
    print(f"{name}: embedded/pair part {np.round(100 * base, 2).tolist()} %", flush=True)
    print(
        f"  observed order {sol.embedded.observed_order:.2f}, floor {100 * sol.embedded.floor:.2f} %"
    )
    default = paths.PATH_STEPS
    for k in steps:
        paths.PATH_STEPS = k
        for m in samples:
            gam = cost_gap(sol, X, samples=m) / scale
            print(f"  γ ({k} steps, {m} paths): {np.round(100 * gam, 2).tolist()} %", flush=True)
    paths.PATH_STEPS = default
    print("  warned:", [str(x.message)[:90] for x in w if "estimated error" in str(x.message)])
    real = est_mod.cost_gap
    est_mod.cost_gap = lambda solution, x, t=0.0, samples=16: np.zeros(len(np.atleast_2d(x)))
    try:
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            gridlbc.solve(problem)
    finally:
        est_mod.cost_gap = real
    print(
        "  warned without γ:",
        [str(x.message)[:90] for x in w if "estimated error" in str(x.message)],
        flush=True,
    )


def grid_study(name, factors=(2.0, 4.0, 8.0)):
    """The problem's values at its states on grids with ``factors`` × the cells per axis
    (corpus.refine; default step, no error estimate): a truth where the certificates degenerate."""
    build, X = P7[name][:2]
    problem = build()
    for f in factors:
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sol = gridlbc.solve(r3.refine(problem, f), error_estimate=False)
        print(
            f"{name} ×{f:g} ({sol.grid.shape}): {np.round(sol.value(X), 4).tolist()} "
            f"({time.perf_counter() - t0:.0f} s)",
            flush=True,
        )


def main(argv: list[str]) -> None:
    OUT.mkdir(exist_ok=True)
    r3.OUT = OUT
    for name in [a for a in argv if not a.startswith("--")]:
        if "--quick" in argv:
            quick(name)
        elif "--study" in argv:
            grid_study(name, {"pit_3d_cell": (3.0, 4.0)}.get(name, (2.0, 4.0, 8.0)))
        elif "--diagnose" in argv:
            diagnose(name)
        elif "--exact" in argv:
            X = P7[name][1]
            print(name, "exact v*:", np.round(EXACT[name](X), 4).tolist(), flush=True)
        else:
            r3.run(name, "--own" in argv, 0.5 if "--halfdt" in argv else 1.0)


if __name__ == "__main__":
    main(sys.argv[1:])
