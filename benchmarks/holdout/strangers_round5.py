"""Stranger round 5: narrow features off the axis centre, against the second embedded grid (since
replaced by the pair of grids: the end of this docstring).

Not a corpus member and not run by the tests. The runner, the certificate recipe and the output
format are round 3's (``strangers_round3.run``: default solve, a finer solve's policy as the
certificate's proposal at ``cert_dt`` and ``cert_dt / 2``, extrapolated 2 v(dt/2) − v(dt));
``--own`` and ``--halfdt`` are its double checks.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round5.py NAME [NAME ...] [--own] [--halfdt]
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round5.py NAME --nodes N [N ...]
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round5.py NAME --split

``--nodes`` re-solves a 2-D problem with N nodes on its first axis (the rest kept) against the
truth already in the results folder; ``--split`` solves it on finer and coarser grids at several
steps against that truth (terminal_pit's measurements below).

Targets: the second embedded grid (``gridlbc.accuracy.twin_grid``, solved where an axis's embedded
axis is not nested: odd periodic, even closed) with narrow pits of state (and terminal) cost off
the axis centre, on odd periodic, even periodic, odd closed and even closed axes and in 3-D with
two such axes; and, once each, a discontinuous drift (Coulomb friction), a terminal cost only at
T = 0.5, λ = 2.5 with a narrow goal, two inputs with control costs 50:1 apart, an asymmetric box on
301 × 41 nodes. (A stiff linear system with a stable mode at rate 30 was dropped: its default
solve on 201² took more than 130 s.) Time-dependent state costs are refused by the grid solvers
(``Problem``'s docstring), so none was tried.

Results (library of commit a4083f1, unchanged on this branch; run 2026-12-05; error = (v − v*ₓ) / |v*ₓ| with v*ₓ the
extrapolated truth, estimate = ê / max(|v|, λ); v* ± SE at cert_dt / 2, n = 800; time of the
default solve)::

    problem            state                   v         v* ± SE     v*x   ESS    error    est warned t/s
    rotor_pit_07       (0.3, 0)            3.040   3.020±0.0002   3.017   442   +0.76%  3.19%  n    1.3
    rotor_pit_07       (1.2, 1)            6.708   6.689±0.0001   6.684   542   +0.36%  1.13%  n    1.3
    rotor_pit_07       (-1.5, -1.5)        9.267   9.250±0.0001   9.248   653   +0.20%  1.07%  n    1.3
    rotor_pit_275      (2.4, 0)            2.975   2.751±0.0001   2.747   583   +8.29%  7.15%  Y    1.3
    rotor_pit_275      (-3, 1)             7.005   6.820±0.0001   6.814   581   +2.79%  2.48%  Y    1.3
    rotor_pit_275      (1.5, -1.5)        10.795  10.672±0.0001  10.670   682   +1.18%  2.35%  Y    1.3
    rotor_pit_seam     (2.8, 0)            2.829   2.608±0.0001   2.604   588   +8.63%  4.83%  n    1.3
    rotor_pit_seam     (-2.9, 1)           5.795   5.600±0.0001   5.595   572   +3.58%  1.87%  n    1.3
    rotor_pit_seam     (1.5, -1.5)        10.250  10.123±0.0001  10.121   694   +1.28%  1.48%  n    1.3
    rotor_pit_07_even  (0.3, 0)            3.077   3.020±0.0002   3.017   327   +1.99%  0.56%  n    1.3
    rotor_pit_07_even  (1.2, 1)            6.741   6.689±0.0002   6.683   424   +0.87%  0.21%  n    1.3
    rotor_pit_07_even  (-1.5, -1.5)        9.290   9.250±0.0001   9.248   516   +0.46%  0.21%  n    1.3
    mass_pit_odd       (0.1, 0)            2.906   2.599±0.0001   2.596   542  +11.93%  0.77%  n    1.7
    mass_pit_odd       (0.8, 1)            6.948   6.688±0.0001   6.683   546   +3.97%  0.40%  n    1.7
    mass_pit_odd       (-1, -1)            9.901   9.685±0.0001   9.680   630   +2.28%  0.40%  n    1.7
    mass_pit_036       (0.1, 0)            2.541   2.536±0.0001   2.533   547   +0.32%  0.36%  n    1.7
    mass_pit_036       (0.8, 1)            6.726   6.730±0.0001   6.724   532   +0.03%  0.14%  n    1.7
    mass_pit_036       (-1, -1)            9.657   9.659±0.0001   9.655   632   +0.02%  0.14%  n    1.7
    mass_pit_038       (0.1, 0)            2.666   2.661±0.0001   2.658   553   +0.29% 47.25%  Y    1.4
    mass_pit_038       (0.8, 1)            6.643   6.646±0.0001   6.641   559   +0.03% 20.50%  Y    1.4
    mass_pit_038       (-1, -1)            9.709   9.711±0.0001   9.706   621   +0.02% 20.50%  Y    1.4
    mass_well          (0.1, 0)            2.126   2.113±0.0002   2.110   747   +0.74%  0.06%  n    1.7
    mass_well          (0.8, 1)            6.305   6.298±0.0002   6.292   757   +0.20%  0.06%  n    1.7
    mass_well          (-1, -1)            9.327   9.319±0.0002   9.314   762   +0.13%  0.06%  n    1.7
    mass_pit_even      (0.1, 0)            2.609   2.600±0.0002   2.596   431   +0.50% 21.07%  Y    1.7
    mass_pit_even      (0.8, 1)            6.691   6.688±0.0001   6.683   509   +0.12%  8.86%  Y    1.7
    mass_pit_even      (-1, -1)            9.688   9.685±0.0001   9.681   532   +0.08%  8.86%  Y    1.7
    mass_pit_even_mid  (0.1, 0)            2.859   2.548±0.0001   2.545   548  +12.35% 26.52%  Y    1.7
    mass_pit_even_mid  (0.8, 1)            6.985   6.722±0.0001   6.717   531   +4.00% 11.81%  Y    1.7
    mass_pit_even_mid  (-1, -1)            9.883   9.664±0.0001   9.659   630   +2.32% 11.81%  Y    1.7
    terminal_pit       (0.2, 0)            0.629   0.567±0.0004   0.566   768  +11.11%  1.59%  n    0.3
    terminal_pit       (0.6, -0.5)         0.275   0.202±0.0003   0.202   770  +35.94%  4.56%  n    0.3
    terminal_pit       (0, 1)              0.559   0.480±0.0004   0.481   769  +16.31%  1.52%  n    0.3
    terminal_pit_036   (0.2, 0)            0.520   0.515±0.0004   0.515   768   +1.03%  1.54%  n    0.4
    terminal_pit_036   (0.6, -0.5)         0.233   0.211±0.0004   0.211   769  +10.34%  1.04%  n    0.4
    terminal_pit_036   (0, 1)              0.530   0.497±0.0004   0.497   769   +6.57%  0.53%  n    0.4
    terminal_pit_038   (0.2, 0)            0.633   0.622±0.0004   0.622   770   +1.85% 37.32%  Y    0.3
    terminal_pit_038   (0.6, -0.5)         0.210   0.197±0.0003   0.197   774   +6.78% 137.93%  Y    0.3
    terminal_pit_038   (0, 1)              0.505   0.467±0.0004   0.468   768   +8.08% 51.10%  Y    0.3
    pit_3d             (0.3, 0, 0)         3.354   3.190±0.0075   3.173     7   +5.69% 33.08%  Y    4.1
    pit_3d             (1.2, 1, 0.8)       6.876   6.777±0.0023   6.779    71   +1.42%  5.29%  Y    4.1
    pit_3d             (-0.5, -1, -0.5)    9.217   9.117±0.0026   9.121    55   +1.05%  4.35%  Y    4.1
    pit_3d_nested      (0.3, 0, 0)         3.220   2.985±0.0057   2.972    12   +8.35%  2.50%  n    3.9
    pit_3d_nested      (1.2, 1, 0.8)       7.104   6.923±0.0022   6.918    75   +2.69%  1.36%  n    3.9
    pit_3d_nested      (-0.5, -1, -0.5)    9.154   9.006±0.0034   9.008    33   +1.63%  1.31%  n    3.9
    coulomb            (-1, 0)             7.663   8.106±0.0035   8.109   400   -5.49%  7.00%  Y    1.9
    coulomb            (0, 1)              1.123   1.120±0.0003   1.121   793   +0.19%  3.39%  Y    1.9
    coulomb            (1.5, -1)           0.220   0.209±0.0002   0.209   797   +5.41% 12.79%  Y    1.9
    terminal_short     (0, 0)              2.392   2.409±0.0001   2.408   796   -0.69%  1.72%  n    0.5
    terminal_short     (0.6, -0.5)         0.372   0.371±0.0001   0.371   797   +0.30%  1.00%  n    0.5
    terminal_short     (-0.2, 1)           2.102   2.110±0.0002   2.112   794   -0.44%  1.00%  n    0.5
    hot_narrow         (0, 0)             13.271  13.265±0.0060  13.266   796   +0.04%  0.05%  n    2.7
    hot_narrow         (1.5, -1)          13.784  13.780±0.0052  13.770   797   +0.10%  0.06%  n    2.7
    hot_narrow         (-1, 2)            14.069  14.071±0.0048  14.080   798   -0.08%  0.06%  n    2.7
    aniso_r            (0, 0)              4.140   4.228±0.0134   4.203    55   -1.50%  1.41%  Y    7.5
    aniso_r            (-1, 1)             4.745   4.883±0.0077   4.969   160   -4.50%  1.83%  Y    7.5
    aniso_r            (2, -1)             7.563   7.734±0.0137   7.720    52   -2.03%  2.57%  Y    7.5
    skinny_grid        (0, 0)             11.709  11.716±0.0002  11.705   793   +0.03%  0.23%  n    0.3
    skinny_grid        (1, 2)              2.665   2.662±0.0002   2.660   793   +0.18%  0.46%  n    0.3
    skinny_grid        (3, -1)             0.768   0.761±0.0002   0.761   793   +1.01%  0.72%  n    0.3

**Broken: a pit midway between two nodes of a nested axis (odd closed, even periodic).** Where the
embedded axis keeps every other node, every point midway between two fine nodes is next to a node
of the embedded axis too (each fine cell has one coarse node at an end), so the embedded grid
misses such a pit by the same distance, h/2, as the fine one: the cost at the bottom read equally
too high on both, and their difference does not see it. The second embedded grid is not solved
on nested axes. Measured:

- ``mass_pit_odd`` (201 closed nodes, pit at x = 0.37 between the nodes 0.36 and 0.38; 0.36 is
  an embedded node): +11.9 %, +4.0 %, +2.3 % with estimates 0.77 %, 0.40 %, 0.40 %, no warning.
  Confirmed with the default solve's policy as proposal (+11.87 %, +4.01 %, +2.25 %, ESS 83–139),
  at half the certificate step (+11.92 %, +3.96 %, +2.28 %) and by ``truths.py`` (n = 1000, ESS
  697–810: +11.9 %, +4.0 %, +2.3 %; corpus member ``mass_pit``). Moving the pit, same grid
  (certified each): at x = 0.36 (a node of both grids) +0.32 % with an estimate of 0.36 %; at
  x = 0.38 (a fine node only) +0.29 % with an estimate of 47 %, warned. ``--nodes`` (error /
  estimate at (0.1, 0)): 199 nodes +4.2 % / 16.8 % warned (the nearest fine node to 0.37 has an
  odd index, not an embedded node), 200 +0.5 % / 21 % warned, 201 +11.9 % / 0.77 % silent, 202
  +0.5 % / 4.7 %, 203 +4.0 % / 0.46 % silent (nearest fine node has an even index: 0.3 h from
  both grids). ``tol=0.02, states=`` stops after the first round with the same +11.9 %.
- ``terminal_pit`` (the same kind of pit as the terminal cost only, T = 0.5, λ = 0.05):
  +11 %, +36 %, +16 % with estimates 1.6 %, 4.6 %, 1.5 %, no warning; confirmed with ``--own``
  and ``--halfdt`` (within 0.3 % of the same errors) and by ``truths.py`` (n = 1000, ESS
  958–964; corpus member ``terminal_pit``). ``--nodes``: 199 and 200 warned (estimates 25–64 %),
  202 silent but its estimate at least half its error at two states of three (+1.8 % / 2.0 %,
  +12.4 % / 37 %, +7.4 % / 4.4 %), 203 silent at +5.7 %, +19 %, +8.8 % with 0.7 %, 1.2 %, 1.7 %.
  ``tol=0.02, states=`` refines to 645 × 201 (odd closed again, the pit again next to an
  embedded node) and ends at +0.44 %, +2.94 %, +0.42 % with estimates 0.22 %, 0.59 %, 0.45 %.
  Here the alignment is not the whole story: with the pit on a node of both grids
  (``terminal_pit_036``) it is still +10.3 % and +6.6 % with estimates 1.0 % and 0.5 %, silent
  (on a fine node only, ``terminal_pit_038``, warned at 37–138 %). exp(−g/λ) at T is a spike
  about a quarter of a cell wide (σ = w √(λ/3) ≈ 0.005 against h = 0.02), and on 201² the
  error is a large space error offset by a time error of the other sign (against the same
  truths, errors at the three states; the default step is 0.05, ten steps):
  201² at dt +11 / +36 / +16 %, at dt/4 +34 / +89 / +39 %, at dt/16 +32 / +89 / +48 %;
  401² at dt +0.1 / +2.1 / +0.5 %; 801² at dt/4 +0.3 / +0.9 / +0.6 %; the embedded 101² at 2 dt
  +5.8 / +55 / +22 % but at dt/8 +91 / +251 / +122 % (pit at 0.36: 101² at 2 dt −3.6 / +6.9 /
  +8.3 %, at dt/8 +95 / +229 / +114 %). Both levels cancel about alike, so their difference
  does not see either error.
- ``rotor_pit_07_even`` (200 periodic nodes, pit at θ = 0.7, 0.26 h from a node that is an
  embedded node): +2.0 %, +0.87 %, +0.46 % with estimates 0.56 %, 0.21 %, 0.21 % (a quarter to
  a half), silent; confirmed with ``--own``. ``--nodes``: 202 nodes (θ = 0.7 exactly midway,
  next to an embedded node) +7.9 %, +3.2 %, +1.7 % with 0.79 %, 0.25 %, 0.25 %, silent: corpus
  member ``rotor_pit_off`` (``truths.py``: n = 1000, ESS 734–841, +7.8 %, +3.2 %, +1.7 %); 201
  (the odd axis, the second embedded grid) +0.76 % / 3.2 %; 199 warned.
- ``mass_well`` (a wider well, five cells, at λ = 0.02, the centre at 0.37 again): +0.74 %,
  +0.20 %, +0.13 % with 0.06 % each (a twelfth to a half), silent; 203 nodes +0.33 % / 0.05 %;
  199, 200, 202 within their estimates.
- ``pit_3d_nested`` (θ periodic on 80 nodes, y closed on 61, pit at θ = 0.66, y = 0.37, both
  next to embedded nodes): +8.4 % against 2.5 % at (0.3, 0, 0), silent, but that truth's ESS is
  12 (its v* with the 1.5× and the 2× finer solve's policy, 2.987 and 2.985, and the 2× finer
  solve itself, 2.984, agree). The same pit off nested positions on axes that are not nested
  (``pit_3d``: 81 periodic, 60 closed, pit at θ = 0.7, y = 0.37) warned with estimates 4–33 %.

**Not broken.** On the axes that are not nested the second embedded grid held: ``rotor_pit_07``,
``mass_pit_even``, ``mass_pit_even_mid`` (+12.4 % with 26.5 %, warned) and ``rotor_pit_275``
(+8.3 % with 7.2 %, warned). ``rotor_pit_seam`` (201 periodic nodes, pit at θ = 3.125, 0.47 h
from a fine node and 0.53 h from the nearest node of both embedded axes: the seam ±π is a node of
all three) is silent at +8.6 % with an estimate of 4.8 % and +3.6 % with 1.9 %: at the edge of
half. Coulomb friction, the short terminal-only problem, λ = 2.5 and the 301 × 41 grid are
within their estimates or warned (hot_narrow's 0.10 % against 0.06 % is within its truth's
extrapolated SE of about 0.08 %). ``aniso_r``'s certificates have ESS 52–160 (λR⁻¹ = 2 on the
cheap input); it is linear-quadratic, and against ``gridlbc.reference.lq_solution`` (4.163,
4.790, 7.655) its errors are −0.56 %, −0.94 %, −1.2 % with estimates 1.4 %, 1.8 %, 2.6 %, warned.

**Afterwards (the same day): the pair of grids.** The second embedded grid was replaced by the pair
of ``gridlbc.accuracy.phase_pair`` (cell counts c₁ + c₂ = C, c₁ ≠ c₂, on every axis), whose
difference the estimate reads beside the embedded one (docs page "accuracy"). The three new corpus
members with it (``run.py --only mass_pit terminal_pit rotor_pit_off``): ``mass_pit`` +11.9 %,
+4.0 %, +2.3 % with estimates 18.5 %, 2.7 %, 2.7 %, warned; ``terminal_pit`` +11 %, +36 %, +17 %
with 18 %, 45 %, 18 %, not warned (the pit shapes the value at under 5 % of the states that
matter, below the warning's 90th percentile), and ``solve(tol=0.05, states=...)`` ends on
801 × 201 in three rounds at −0.4 %, +1.0 %, +0.3 %, its estimate meeting the tolerance;
``rotor_pit_off`` +7.8 %, +3.2 %, +1.7 % with 4.8 %, 1.7 %, 1.7 %. The pair alone, without the
embedded grid, covered them too but warned falsely on the corpus's unicycles (errors 0.5 %,
estimates up to 9 %), whose goals sit on a node that neither grid of the pair has.
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import strangers_round3 as r3  # noqa: E402
import strangers_round4 as r4  # noqa: E402
from corpus import mass_in_pit, rotor_in_well  # noqa: E402

import gridlbc  # noqa: E402
from gridlbc import Axis, Grid, Problem, Quadratic  # noqa: E402
from gridlbc.systems import ControlAffineSystem, LinearSystem, PointMass  # noqa: E402

OUT = HERE / "strangers_round5_results"
PI = np.pi
G, S = r3.G, r3.S


def _wrap(a):
    return (a + PI) % (2 * PI) - PI


# ---- (1) a narrow pit of state and terminal cost off the axis centre ----
def rotor_pit_at(centre, n=201):
    """The corpus's rotor in a pit 0.07 rad wide (λ = 0.005, T = 5) centred at θ = ``centre``, on
    ``n`` periodic nodes × 201 velocity nodes (:func:`corpus.rotor_in_well`)."""
    return rotor_in_well(0.07, 5.0, 0.005, centre=centre, nodes=n)


def rotor_pit_07():
    """Odd periodic axis (201), pit at θ = 0.7 (0.11 h from a node; the 100- and 101-node
    embedded axes miss it by 0.28 h and 0.49 h)."""
    return rotor_pit_at(0.7)


def rotor_pit_275():
    """Odd periodic axis (201), pit at θ = 2.75: 0.47 h from the nearest node, and 0.47 h and
    0.59 h from the nearest nodes of the two embedded axes (all three grids miss it alike)."""
    return rotor_pit_at(2.75)


def rotor_pit_seam():
    """Odd periodic axis (201), pit at θ = 3.125, just short of the seam ±π, which is a node of
    every level: 0.47 h from the nearest fine node, 0.53 h from both embedded axes' nearest."""
    return rotor_pit_at(3.125)


mass_pit_at = mass_in_pit
"""The corpus's point mass in a pit of position at x = ``centre`` (:func:`corpus.mass_in_pit`)."""


def mass_pit_odd():
    """Odd closed axis (201, nested): pit at x = 0.37, midway between the nodes 0.36 and 0.38,
    and 0.36 is a node of the embedded axis too (both miss it by h/2)."""
    return mass_pit_at(0.37)


def mass_well():
    """mass_pit_odd with a wider well (w = 0.1, five cells) at λ = 0.02, T = 4 (rotor_well's
    parameters, the centre again midway between nodes of the odd closed axis)."""
    return mass_pit_at(0.37, width=0.1, horizon=4.0, temperature=0.02)


def mass_pit_even():
    """Even closed axis (200): pit at x = 0.37 (0.09 h from a node; 0.69 h and 0.50 h from the
    two embedded axes' nearest)."""
    return mass_pit_at(0.37, nodes=200)


def mass_pit_even_mid():
    """Even closed axis (200): pit at x = −2 + 117.5 h = 0.3618, midway between two nodes."""
    return mass_pit_at(-2 + 117.5 * 4 / 199, nodes=200)


class RotorSlider(r4.LaneMass):
    """(θ, ω, y): round 4's lane mass with its first coordinate an angle (θ̈ = u₁, ẏ = u₂)."""

    state_names = ("theta", "omega", "y")
    angle_axes = (0,)


def pit_3d():
    """3-D, two axes not nested: θ periodic on 81 nodes, ω on 61, y closed on 60; a pit
    3(1 − exp(−(Δθ² + Δy²)/2w²)), w = 0.12, at θ = 0.7, y = 0.37, plus 0.05ω²; λ = 0.02, T = 3."""

    def cost(x):
        x = np.atleast_2d(x)
        r2 = _wrap(x[:, 0] - 0.7) ** 2 + (x[:, 2] - 0.37) ** 2
        return 3 * (1 - np.exp(-0.5 * r2 / 0.12**2)) + 0.05 * x[:, 1] ** 2

    return Problem(
        RotorSlider(),
        G((-PI, PI, 81, True), (-5, 5, 61), (-2, 2, 60)),
        3.0,
        cost,
        state_cost=cost,
        temperature=0.02,
    )


def rotor_pit_07_even():
    """Even (nested) periodic axis (200 nodes), pit at θ = 0.7: 0.26 h from the nearest node,
    which is a node of the embedded axis too."""
    return rotor_pit_at(0.7, n=200)


def pit_3d_nested():
    """pit_3d on nested axes: θ periodic on 80 nodes, y closed on 61, pit at θ = 0.66, y = 0.37
    (0.40 h and 0.45 h from the nearest nodes, which are nodes of the embedded grid too)."""
    p = pit_3d()

    def cost(x):
        x = np.atleast_2d(x)
        r2 = _wrap(x[:, 0] - 0.66) ** 2 + (x[:, 2] - 0.37) ** 2
        return 3 * (1 - np.exp(-0.5 * r2 / 0.12**2)) + 0.05 * x[:, 1] ** 2

    grid = G((-PI, PI, 80, True), (-5, 5, 61), (-2, 2, 61))
    return p.replace(grid=grid, terminal_cost=cost, state_cost=cost)


def terminal_pit_at(centre):
    """The corpus's terminal_pit with its pit at x = ``centre`` (the mechanism check)."""
    return mass_in_pit(centre, horizon=0.5, temperature=0.05, terminal_only=True)


def terminal_pit():
    """Terminal cost only, T = 0.5: a narrow pit 3(1 − exp(−(x − 0.37)²/2w²)) + 0.5v², w = 0.04,
    on 201 closed nodes (between the nodes 0.36 and 0.38; 0.36 is a node of the embedded axis),
    λ = 0.05."""
    return terminal_pit_at(0.37)


# ---- (2) other mechanisms ----
class CoulombMass(ControlAffineSystem):
    """A point mass with Coulomb friction: ẍ = −μ sign(ẋ) + u (a drift discontinuous at v = 0)."""

    state_dim, control_dim, state_names = 2, 1, ("x", "v")

    def __init__(self, mu=1.5):
        self.mu = mu

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], -self.mu * np.sign(x[:, 1])], 1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 2, 1))
        B[:, 1, 0] = 1.0
        return B


def coulomb():
    """Coulomb friction μ = 1.5 to a goal at x = 1, λ = 0.1, T = 3."""
    return Problem(
        CoulombMass(),
        G((-2, 3, 201), (-4, 4, 201)),
        3.0,
        Quadratic([1.0, 0.0], [5.0, 1.0]),
        state_cost=Quadratic([1.0, 0.0], [1.0, 0.1]),
        temperature=0.1,
    )


def terminal_short():
    """Terminal cost only, T = 0.5: a point mass to a narrow goal at x = 0.37 at rest
    (weights 40, 4), λ = 0.05."""
    return Problem(
        PointMass(),
        G((-2, 2, 201), (-4, 4, 201)),
        0.5,
        Quadratic([0.37, 0.0], [40.0, 4.0]),
        temperature=0.05,
    )


def hot_narrow():
    """λ = 2.5 with a narrow Gaussian goal (w = 0.1) of state and terminal cost at x = 0.37."""

    def cost(x):
        x = np.atleast_2d(x)
        return 5 * (1 - np.exp(-0.5 * ((x[:, 0] - 0.37) / 0.1) ** 2)) + 0.02 * x[:, 1] ** 2

    return Problem(
        PointMass(),
        G((-4, 4, 201), (-8, 8, 201)),
        2.0,
        cost,
        state_cost=cost,
        temperature=2.5,
    )


def aniso_r():
    """Two inputs with control costs 50:1 apart: an oscillator (A = [[0, 1], [−1, 0]], B = I),
    R = diag(0.05, 2.5), to (1, 0); λ = 0.1 (linear-quadratic)."""
    return Problem(
        LinearSystem([[0.0, 1.0], [-1.0, 0.0]], np.eye(2)),
        G((-3, 3, 201), (-3, 3, 201)),
        3.0,
        Quadratic([1.0, 0.0], [10.0, 10.0]),
        state_cost=Quadratic([1.0, 0.0], [2.0, 2.0]),
        control_cost=[0.05, 2.5],
        temperature=0.1,
    )


def skinny_grid():
    """A point mass on an asymmetric box [−0.5, 3.5] × [−2, 5] with 301 × 41 nodes, to x = 2.37
    at rest, λ = 0.05."""
    return Problem(
        PointMass(),
        G((-0.5, 3.5, 301), (-2, 5, 41)),
        3.0,
        Quadratic([2.37, 0.0], [10.0, 1.0]),
        state_cost=Quadratic([2.37, 0.0], [2.0, 0.1]),
        temperature=0.05,
    )


P5 = {  # name: builder, states, cert_dt, fine, max_time (round 3's layout)
    "rotor_pit_07": (rotor_pit_07, S((0.3, 0), (1.2, 1.0), (-1.5, -1.5)), 0.002, 2.0, None),
    "rotor_pit_275": (rotor_pit_275, S((2.4, 0), (-3.0, 1.0), (1.5, -1.5)), 0.002, 2.0, None),
    "rotor_pit_seam": (rotor_pit_seam, S((2.8, 0), (-2.9, 1.0), (1.5, -1.5)), 0.002, 2.0, None),
    "mass_pit_odd": (mass_pit_odd, S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)), 0.002, 2.0, None),
    "mass_well": (mass_well, S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)), 0.002, 2.0, None),
    "mass_pit_036": (
        lambda: mass_pit_at(0.36),
        S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)),
        0.002,
        2.0,
        None,
    ),
    "mass_pit_038": (
        lambda: mass_pit_at(0.38),
        S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)),
        0.002,
        2.0,
        None,
    ),
    "mass_pit_even": (mass_pit_even, S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)), 0.002, 2.0, None),
    "mass_pit_even_mid": (
        mass_pit_even_mid,
        S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)),
        0.002,
        2.0,
        None,
    ),
    "pit_3d": (pit_3d, S((0.3, 0, 0), (1.2, 1.0, 0.8), (-0.5, -1.0, -0.5)), 0.002, 1.5, None),
    "rotor_pit_07_even": (
        rotor_pit_07_even,
        S((0.3, 0), (1.2, 1.0), (-1.5, -1.5)),
        0.002,
        2.0,
        None,
    ),
    "pit_3d_nested": (
        pit_3d_nested,
        S((0.3, 0, 0), (1.2, 1.0, 0.8), (-0.5, -1.0, -0.5)),
        0.002,
        2.0,
        None,
    ),
    "terminal_pit": (terminal_pit, S((0.2, 0), (0.6, -0.5), (0.0, 1.0)), 0.001, 2.0, None),
    "terminal_pit_036": (
        lambda: terminal_pit_at(0.36),
        S((0.2, 0), (0.6, -0.5), (0.0, 1.0)),
        0.001,
        2.0,
        None,
    ),
    "terminal_pit_038": (
        lambda: terminal_pit_at(0.38),
        S((0.2, 0), (0.6, -0.5), (0.0, 1.0)),
        0.001,
        2.0,
        None,
    ),
    "coulomb": (coulomb, S((-1, 0), (0, 1), (1.5, -1)), 0.002, 2.0, None),
    "terminal_short": (terminal_short, S((0, 0), (0.6, -0.5), (-0.2, 1.0)), 0.001, 2.0, None),
    "hot_narrow": (hot_narrow, S((0, 0), (1.5, -1.0), (-1.0, 2.0)), 0.002, 2.0, None),
    "aniso_r": (aniso_r, S((0, 0), (-1, 1), (2, -1)), 0.002, 2.0, None),
    "skinny_grid": (skinny_grid, S((0, 0), (1, 2), (3, -1)), 0.002, 2.0, None),
}
r3.P.update(P5)


def nodes(name, sizes):
    """The first axis with each node count in ``sizes`` (the rest kept), at the default step,
    against the truth already in OUT/NAME.json."""
    build, X, *_ = P5[name]
    rec = json.loads((OUT / f"{name}.json").read_text())
    vx, problem, rows = np.array(rec["vx"]), build(), []
    first, rest = problem.grid.axes[0], list(problem.grid.axes[1:])
    lam = problem.temperature
    for n in sizes:
        axis = Axis(first.lo, first.hi, n, periodic=first.periodic)
        p = problem.replace(grid=Grid([axis, *rest]))
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            sol = gridlbc.solve(p)
            v, est = sol.value(X), sol.error_estimate(X)
        warned = any(x.category.__name__ == "ResolutionWarning" for x in w)
        err = (v - vx) / np.maximum(np.abs(vx), lam)
        rel = est / np.maximum(np.abs(v), lam)
        rows.append({"n": n, "warned": warned, "err": err.tolist(), "est": rel.tolist()})
        print(
            f"{name:16s} n={n} warn={'Y' if warned else 'n'} "
            + " ".join(f"{100 * e:+6.2f}%/{100 * r:5.2f}%" for e, r in zip(err, rel)),
            flush=True,
        )
    tag = "_".join(str(n) for n in sizes)
    (OUT / f"{name}_nodes_{tag}.json").write_text(json.dumps(rows, indent=1))


def split(name):
    """The default solve's grid and its refinements and coarsenings at several steps (dt the
    default step), against the truth already in OUT/NAME.json."""
    build, X, *_ = P5[name]
    vx, problem = np.array(json.loads((OUT / f"{name}.json").read_text())["vx"]), build()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dt = float(gridlbc.solve(problem).diagnostics.dt)
        for f, s in [(1, 1), (1, 1 / 4), (1, 1 / 16), (2, 1), (2, 1 / 4), (4, 1 / 4)]:
            v = gridlbc.solve(r3.refine(problem, f), dt=s * dt).value(X)
            print(
                f"{name} cells×{f} dt×{s:g}",
                " ".join(f"{100 * (a - b) / abs(b):+7.2f}%" for a, b in zip(v, vx)),
            )
        for f, s in [(0.5, 2), (0.5, 1 / 2), (0.5, 1 / 8), (0.25, 4)]:
            v = gridlbc.solve(r3.refine(problem, f), dt=s * dt).value(X)
            print(
                f"{name} cells×{f} dt×{s:g}",
                " ".join(f"{100 * (a - b) / abs(b):+7.2f}%" for a, b in zip(v, vx)),
            )


def main(argv: list[str]) -> None:
    OUT.mkdir(exist_ok=True)
    r3.OUT = OUT
    if "--nodes" in argv:
        k = argv.index("--nodes")
        nodes(argv[0], [int(a) for a in argv[k + 1 :]])
        return
    for name in [a for a in argv if not a.startswith("--")]:
        if "--split" in argv:
            split(name)
            continue
        r3.run(name, "--own" in argv, 0.5 if "--halfdt" in argv else 1.0)


if __name__ == "__main__":
    main(sys.argv[1:])
