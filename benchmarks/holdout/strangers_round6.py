"""Stranger round 6: narrow features where the pair of coarse grids misses them alike.

Not a corpus member and not run by the tests. The runner, the certificate recipe and the output
format are round 3's (``strangers_round3.run``: the default solve, a finer solve's policy (2× cells
per axis, 1.5× in 3-D) as the certificate's proposal at ``cert_dt`` and ``cert_dt / 2``,
extrapolated 2 v(dt/2) − v(dt)); ``--own`` (the default solve's policy as proposal) and
``--halfdt`` (half the certificate step) are its double checks.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round6.py NAME [NAME ...] [--own] [--halfdt]

Targets: the pair of ``gridlbc.accuracy.phase_pair`` (c₁ + c₂ = C cells). At a point a fraction
u = (x − lo)/L along an axis, the pair's offsets from their nearest nodes are a = uc₁ and
b = uc₂ (in their cells). On an even C (odd closed node count, even periodic one) c₂ − c₁ = 2, so
for a point midway between two fine nodes a and b are both a quarter cell off where 2u is near
an integer: next to the centre of the axis and next to both ends; on an odd C (c₂ − c₁ = 1) only
next to the ends (closed walls, the seam ±π of a periodic axis). ``offsets(lo, hi, n,
periodic, x)`` prints them. Problems: a narrow pit (mass_pit's, w = 0.04, λ = 0.005, T = 5) midway
next to the centre of a 201-node closed axis, near the wall of a 200-node one; round 5's
rotor_pit_seam (201 periodic, next to ±π) rerun with the pair; the rotor pit next to θ = 0 on 200
periodic nodes; round 5's 3-D pit moved next to the centre of θ (80 periodic) and y (61 closed);
two pits at once (one on a node, one midway next to the centre; either one the deeper); a
one-cell pit on a 41-node axis; round 5's terminal-only pit next to the centre; a jet (ẋ = u₁ +
4 exp(−(y − 0.01)²/2w²), w = 0.03, 1.5 cells) in a thin band midway next to the centre; a smooth
point-mass problem on 201² and 200² (false warnings); and the sweeps of one change each
(``mass_pit_X_N``: the pit at X on N nodes).

Results (library of commit bcc88e8, unchanged on this branch; run 2026-12-05; error =
(v − v*ₓ) / max(|v*ₓ|, λ) with v*ₓ the extrapolated truth, estimate = ê / max(|v|, λ); v* ± SE
at cert_dt / 2, n = 800; time of the default solve in s)::

    problem             state                  v     v* ± SE        v*x  ESS    error     est  w  t/s
    mass_pit_centre     (0.2, 0)           2.365   2.052±0.0001   2.049  562  +15.43%   3.81%  n  1.9
    mass_pit_centre     (0.8, 1)           8.249   8.009±0.0001   8.004  599   +3.06%   1.25%  n  1.9
    mass_pit_centre     (-1, -1)           8.922   8.692±0.0001   8.687  583   +2.71%   1.25%  n  1.9
    mass_pit_wall       (-1.6, 0)          2.362   2.044±0.0001   2.041  566  +15.69%   2.54%  n  1.6
    mass_pit_wall       (-1, 1)            8.249   8.005±0.0001   8.001  597   +3.10%   0.69%  n  1.6
    mass_pit_wall       (-0.5, -1)         5.028   4.756±0.0001   4.754  595   +5.77%   1.03%  n  1.6
    rotor_pit_zero_even (0.3, 0)           2.607   2.360±0.0001   2.357  618  +10.61%   3.02%  n  1.4
    rotor_pit_zero_even (1.2, 1)           9.105   8.923±0.0001   8.919  644   +2.09%   0.82%  n  1.4
    rotor_pit_zero_even (-1.5, -1.5)      10.432  10.284±0.0001  10.282  685   +1.46%   0.82%  n  1.4
    rotor_pit_seam      (2.8, 0)           2.829   2.608±0.0001   2.604  588   +8.63%   4.83%  n  1.3
    rotor_pit_seam      (-2.9, 1)          5.795   5.600±0.0001   5.595  572   +3.58%   1.85%  n  1.3
    rotor_pit_seam      (1.5, -1.5)       10.250  10.123±0.0001  10.121  694   +1.28%   1.48%  n  1.3
    two_pits            (0.2, 0)           2.365   2.052±0.0001   2.049  562  +15.43%   3.81%  n  2.0
    two_pits            (-0.4, 0.5)        2.751   2.445±0.0001   2.443  547  +12.61%   2.89%  n  2.0
    two_pits            (1, -1)            4.249   3.968±0.0001   3.966  596   +7.14%   2.02%  n  2.0
    two_pits_aligned_deeper(0.2, 0)           4.636   4.637±0.0001   4.634  596   +0.04%   0.25%  n  2.0
    two_pits_aligned_deeper(-0.4, 0.5)        3.660   3.659±0.0001   3.654  548   +0.15%   0.25%  n  2.0
    two_pits_aligned_deeper(1, -1)            5.306   5.305±0.0001   5.302  599   +0.07%   0.25%  n  2.0
    pit_3d_centre       (0.3, 0, 0)        2.431   2.187±0.0073   2.166    7  +12.19%  18.44%  n  4.4
    pit_3d_centre       (1.2, 1, 0.8)      9.162   8.970±0.0022   8.981   74   +2.02%   1.55%  n  4.4
    pit_3d_centre       (-0.5, -1, -0.5)   7.171   6.963±0.0031   6.966   39   +2.94%   1.55%  n  4.4
    terminal_pit_centre (0.2, 0)           0.747   0.680±0.0004   0.679  766  +10.10%   4.97%  n  0.3
    terminal_pit_centre (0.6, -0.5)        2.536   2.487±0.0010   2.484  602   +2.09%   0.15%  n  0.3
    terminal_pit_centre (0, 1)             3.067   3.049±0.0007   3.044  691   +0.74%   0.91%  n  0.3
    few_nodes           (0.2, 0)           1.924   1.119±0.0005   1.117  547  +72.29%  24.26%  Y  0.1
    few_nodes           (0.8, 1)           8.088   7.504±0.0004   7.498  581   +7.87%   3.63%  Y  0.1
    few_nodes           (-1, -1)           8.994   8.442±0.0004   8.437  572   +6.59%   3.63%  Y  0.1
    jet                 (-1.5, 0.3)        2.327   2.348±0.0038   2.352  145   -1.08%   0.39%  n  2.1
    jet                 (-1, -0.5)         2.381   2.400±0.0042   2.407  123   -1.10%   0.21%  n  2.1
    jet                 (0, 1)             2.532   2.534±0.0053   2.526   81   +0.25%   0.71%  n  2.1
    smooth_odd          (1, 0)             1.528   1.531±0.0003   1.530  795   -0.11%   0.14%  n  1.8
    smooth_odd          (-2, 1)            3.265   3.268±0.0003   3.266  795   -0.05%   0.10%  n  1.8
    smooth_odd          (0.5, -2)          2.704   2.708±0.0003   2.706  795   -0.07%   0.12%  n  1.8
    smooth_even         (1, 0)             1.529   1.531±0.0003   1.530  795   -0.07%   0.12%  n  1.6
    smooth_even         (-2, 1)            3.265   3.268±0.0003   3.266  795   -0.04%   0.09%  n  1.6
    smooth_even         (0.5, -2)          2.704   2.708±0.0003   2.706  795   -0.07%   0.09%  n  1.6
    mass_pit_0.09_201   (0.2, 0)           1.644   1.330±0.0001   1.327  582  +23.85%  10.12%  Y  1.8
    mass_pit_0.09_201   (0.8, 1)           7.985   7.741±0.0001   7.736  596   +3.22%   2.53%  Y  1.8
    mass_pit_0.09_201   (-1, -1)           9.151   8.924±0.0001   8.919  591   +2.60%   2.53%  Y  1.8
    mass_pit_0.17_201   (0.2, 0)           0.626   0.287±0.0001   0.286  598 +119.00%  49.16%  Y  1.7
    mass_pit_0.17_201   (0.8, 1)           7.709   7.461±0.0001   7.456  605   +3.39%   4.36%  Y  1.7
    mass_pit_0.17_201   (-1, -1)           9.373   9.149±0.0001   9.144  603   +2.50%   4.36%  Y  1.7
    mass_pit_0_200      (0.2, 0)           2.443   2.127±0.0001   2.124  552  +15.00%  40.76%  Y  1.7
    mass_pit_0_200      (0.8, 1)           8.284   8.041±0.0001   8.037  596   +3.08%  15.35%  Y  1.7
    mass_pit_0_200      (-1, -1)           8.896   8.662±0.0001   8.657  584   +2.76%  15.35%  Y  1.7
    mass_pit_0.01_203   (0.2, 0)           2.357   2.052±0.0001   2.049  553  +15.04%   1.85%  n  1.8
    mass_pit_0.01_203   (0.8, 1)           8.244   8.009±0.0001   8.004  600   +2.99%   1.09%  n  1.8
    mass_pit_0.01_203   (-1, -1)           8.912   8.692±0.0001   8.687  582   +2.60%   1.09%  n  1.8
    mass_pit_-1.387_200 (-1.6, 0)          2.537   2.222±0.0001   2.218  532  +14.38%  17.26%  n  1.8
    mass_pit_-1.387_200 (-1, 1)            6.771   6.504±0.0001   6.499  521   +4.18%   1.92%  n  1.8
    mass_pit_-1.387_200 (-0.5, -1)         3.970   3.680±0.0001   3.679  604   +7.93%   3.46%  n  1.8
    mass_pit_-1.79_201  (-1.6, 0)          2.365   2.052±0.0001   2.049  562  +15.43%   4.38%  n  1.6
    mass_pit_-1.79_201  (-1, 1)            8.249   8.009±0.0001   8.004  599   +3.06%   1.20%  n  1.6
    mass_pit_-1.79_201  (-0.5, -1)         5.027   4.758±0.0001   4.756  595   +5.69%   1.80%  n  1.6

The smooth problems and the sweeps' default solves took 1.6–2.1 s; pit_3d_centre's 4.4 s.

**Broken (1): a narrow pit midway between two nodes next to the centre of an axis with an even
cell count.** ``mass_pit_centre`` (201 closed nodes, pit at x = 0.01, between the nodes 0 and
0.02; offsets fine 0.5, embedded 0.25, pair 0.253 and 0.248): +15.4 %, +3.1 %, +2.7 % with
estimates 3.8 %, 1.25 %, 1.25 %, no warning. Confirmed with ``--own`` (+15.3 %, +3.1 %, +2.7 %,
ESS 76–119), with ``--halfdt`` (+15.4 %, +3.1 %, +2.7 %, ESS 617–677) and by ``truths.py``
(n = 1000, ESS 698–782; corpus member ``mass_pit_centre``). The solves at the first state
(error against the truth): h +15.4 %, embedded 2h +19.8 %, pair c₁ +17.0 %, c₂ +15.6 %: every
grid misses the pit by about the same distance, so no difference sees the error. One change at a
time (error / estimate at (0.2, 0), each with its own truth):

- the position, 201 nodes: x = 0.01 (pair offsets 0.253/0.248) +15.4 % / 3.8 % silent; 0.09
  (0.273/0.228) +23.9 % / 10.1 % warned; 0.17 (0.293/0.208) +119 % / 49 % warned; 0.37 (round
  5's mass_pit, 0.342/0.157) warned with 18.5 % against +11.9 %.
- the node count, pit next to the centre: 200 nodes with the pit at x = 0 (midway, C odd: pair
  offsets 0.5 and 0) +15.0 % / 40.8 % warned; 203 nodes with the pit at 0.01 (fine 0.495, pair
  0.250/0.255) +15.0 % / 1.85 % silent (c₁ and c₂ both +18.16 %).
- the step of the default solve (same grid, against the same truth): dt +15.4 % / 3.8 %, dt/2
  +17.4 % / 3.4 %, dt/4 +19.5 % / 3.0 %; 2× cells −0.1 % / 12.8 %.
- the periodic analogue, ``rotor_pit_zero_even`` (200 periodic nodes, pit at θ = π/200 next to
  θ = 0): +10.6 %, +2.1 %, +1.5 % with 3.0 %, 0.8 %, 0.8 %, silent; confirmed with ``--own``
  (+10.6 %, +2.1 %, +1.5 %).
- ``two_pits`` (a pit of depth 3 midway at x = 0.01 and one of depth 2.5 on the node −0.6):
  +15.4 %, +12.6 %, +7.1 % with 3.8 %, 2.9 %, 2.0 %, silent (the optimum goes to the midway pit,
  from (0.2, 0) exactly as in mass_pit_centre). With the aligned pit the deeper one
  (``two_pits_aligned_deeper``) the midway pit is never used: within 0.15 %.

**Broken (2): near a wall the pair's difference is seen and then divided by 3.**
``mass_pit_wall`` (200 closed nodes, C = 199, the pit midway between the nodes 10 and 11,
x = −1.789; pair offsets 0.224 and 0.276): +15.7 %, +3.1 %, +5.8 % with 2.5 %, 0.7 %, 1.0 %,
silent. Confirmed by ``truths.py`` (n = 1000, ESS 703–761; corpus member ``mass_pit_wall``).
Here the pair does differ (c₁ +13.8 %, c₂ +22.6 % at (−1.6, 0); |v_c₁ − v_c₂| = 7.6 % of v) but
the observed order is 2.0 and the relative difference is under ``ASYMPTOTIC`` = 0.15, so the
local estimate is the difference / (2² − 1) = 2.5 %. The same on 201 nodes with the pit at
−1.79 (``mass_pit_-1.79_201``, pair 0.197/0.302): c₁ +11.1 %, c₂ +26.3 %, difference 13.2 %, order
2.0, estimate 4.4 % against +15.4 %, silent. Moving the pit away from the wall on 200 nodes, to
node 30.5 (``mass_pit_-1.387_200``, pair 0.173/0.327): difference 17.3 % at (−1.6, 0), above
0.15, not divided: estimate 17.3 % against +14.4 %; the other two states are divided by 3
(1.9 % against +4.2 %, 3.5 % against +7.9 %), and the solve is still silent. The observed orders
of the centre problems were 1.0 (divided by 1), of the 0_200 sweep 1.4. A difference between the
two grids of the pair is not a difference between levels h and 2h, and the Richardson division
by 2^q − 1 does not apply to it as measured here.

``solve(problem, tol=0.05, states=X)`` at the three states stops on the default grid and step
for both (201 × 201 and 200 × 201, dt 0.060, 1.8 s and 1.6 s) with the same errors (+15.4 %,
+15.7 % at the first state), its estimate already under the tolerance.

**Not broken or not conclusive.** ``rotor_pit_seam`` gives round 5's numbers exactly (+8.6 % with
4.8 %, silent; pair offsets 0.264/0.267): the pair changed nothing there, the estimate is at the
edge of half. ``terminal_pit_centre``: +10.1 % with 5.0 % at (0.2, 0), silent, also at the edge
of half. ``pit_3d_centre``: +12.2 % with 18.4 % at (0.3, 0, 0), not warned, but that truth's ESS
is 7 (the other states +2.0 % / 1.55 %, +2.9 % / 1.55 %, ESS 39–74). ``few_nodes`` (41 nodes,
one-cell pit next to the centre) +72 % with 24 %, warned. ``jet``: −1.1 % with 0.2–0.4 %, but
ESS 81–145 and the extrapolated truth's SE is about 0.4 %: not conclusive. No false warnings:
``smooth_odd`` and ``smooth_even`` within 0.11 % with estimates 0.09–0.14 %, silent.

**Afterwards (commit 202a284): the pair's difference undivided.** The estimate no longer divides
the pair's difference by 2^q − 1. ``run.py`` on the corpus: ``mass_pit_wall`` +15.7 %, +3.1 %,
+5.8 % with 7.6 %, 2.1 %, 3.1 % (not warned; ``tol=0.05`` ends on 565 × 305 within 0.2 %);
``mass_pit_centre`` unchanged (the blind spot, documented on the accuracy page).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import strangers_round3 as r3  # noqa: E402
import strangers_round5 as r5  # noqa: E402

from gridlbc import Problem, Quadratic  # noqa: E402
from gridlbc.systems import ControlAffineSystem, PointMass  # noqa: E402

OUT = HERE / "strangers_round6_results"
PI = np.pi
G, S = r3.G, r3.S


def offsets(lo, hi, n, periodic, x):
    """How far x lies from the nearest node, in cells, of the axis (lo, hi, n), of its embedded
    axis and of the two axes of the pair (``gridlbc.accuracy.phase_pair``'s cell counts)."""
    C = n if periodic else n - 1
    u = (x - lo) / (hi - lo)

    def d(c):
        return round(abs(u * c - round(u * c)), 3)

    c1, c2 = ((C - 1) // 2, (C + 1) // 2) if C % 2 else (C // 2 - 1, C // 2 + 1)
    return {"fine": d(C), "embedded": d(C // 2) if C % 2 == 0 else d(c1), "c1": d(c1), "c2": d(c2)}


def _pit(d, width):
    return np.exp(-0.5 * (d / width) ** 2)


# ---- (1) one narrow pit (state and terminal cost) where the pair's offsets are both ≈ ¼ ----
def mass_pit_centre():
    """Point mass, 201 × 201 closed nodes over [−2, 2] × [−4, 4] (C = 200, even), pit
    3(1 − exp(−(x − 0.01)²/2w²)) + 0.05v², w = 0.04, λ = 0.005, T = 5: x = 0.01 is midway between
    the nodes 0 and 0.02 next to the axis's centre, where the pair's offsets are 0.253 and 0.248
    cells (and the embedded axis's 0.25)."""
    return r5.mass_pit_at(0.01)


def mass_pit_wall():
    """mass_pit_centre's pit near the wall x = −2 of an even closed axis (200 nodes, C = 199,
    odd: no centre node), midway between the nodes 10 and 11 (x = −2 + 10.5 h = −1.789): the
    pair's offsets 0.224 and 0.276 (the embedded axis is c₁'s)."""
    return r5.mass_pit_at(-2 + 10.5 * 4 / 199, nodes=200)


def rotor_pit_seam():
    """Round 5's rotor_pit_seam (201 periodic nodes, pit 0.07 rad wide at θ = 3.125, next to the
    seam ±π): offsets 0.47 (fine), 0.264 and 0.267 (pair)."""
    return r5.rotor_pit_seam()


def rotor_pit_zero_even():
    """The rotor pit (w = 0.07, λ = 0.005, T = 5) at θ = π/200 on 200 periodic nodes: midway
    between the nodes 0 and 2π/200 (the axis's centre), the pair's offsets 0.253 and 0.248."""
    return r5.rotor_pit_at(PI / 200, n=200)


def pit_3d_centre():
    """Round 5's pit_3d (rotor θ̈ = u₁ and slider ẏ = u₂; pit w = 0.12 in (θ, y), λ = 0.02,
    T = 3) on θ: 80 periodic, ω: 61, y: 61 closed, centred at θ = π/80 and y = 1/30, midway
    between nodes next to each axis's centre (pair offsets θ 0.263/0.238, y 0.267/0.233)."""

    def cost(x):
        x = np.atleast_2d(x)
        r2 = ((x[:, 0] - PI / 80 + PI) % (2 * PI) - PI) ** 2 + (x[:, 2] - 1 / 30) ** 2
        return 3 * (1 - np.exp(-0.5 * r2 / 0.12**2)) + 0.05 * x[:, 1] ** 2

    return Problem(
        r5.RotorSlider(),
        G((-PI, PI, 80, True), (-5, 5, 61), (-2, 2, 61)),
        3.0,
        cost,
        state_cost=cost,
        temperature=0.02,
    )


def two_pits(aligned=2.5, midway=3.0):
    """Point mass, 201 × 201 closed: two pits, w = 0.04, at x = −0.6 (a node of the grid and of
    the embedded grid), depth ``aligned``, and at x = 0.01 (midway near the centre), depth
    ``midway``; cost max(3 − aligned·exp(…) − midway·exp(…), 0) + 0.05v², λ = 0.005, T = 5."""

    def cost(x):
        x = np.atleast_2d(x)
        pits = 3 - aligned * _pit(x[:, 0] + 0.6, 0.04) - midway * _pit(x[:, 0] - 0.01, 0.04)
        return np.maximum(pits, 0.0) + 0.05 * x[:, 1] ** 2

    return Problem(
        PointMass(),
        G((-2, 2, 201), (-4, 4, 201)),
        5.0,
        cost,
        state_cost=cost,
        temperature=0.005,
    )


def few_nodes():
    """A point mass on 41 × 101 closed nodes over [−2, 2] × [−4, 4] (h = 0.1 in x), pit
    w = 0.1 (one cell) at x = 0.05, midway next to the centre (pair offsets 0.263/0.238),
    λ = 0.02, T = 4."""
    return r5.mass_pit_at(0.05, nodes=41, width=0.1, horizon=4.0, temperature=0.02).replace(
        grid=G((-2, 2, 41), (-4, 4, 101))
    )


def terminal_pit_centre():
    """Round 5's terminal_pit (terminal cost only, w = 0.04, T = 0.5, λ = 0.05, 201²) with the
    pit at x = 0.01."""
    return r5.terminal_pit_at(0.01)


# ---- (2) a narrow feature of the drift: a fast jet in a thin band ----
class Jet(ControlAffineSystem):
    """ẋ = u₁ + J exp(−(y − y₀)²/2w²), ẏ = u₂: a jet along x in a band of width w about y₀."""

    state_dim, control_dim, state_names = 2, 2, ("x", "y")

    def __init__(self, y0, speed=4.0, width=0.03):
        self.y0, self.speed, self.width = y0, speed, width

    def drift(self, x):
        x = self._states(x)
        return np.stack([self.speed * _pit(x[:, 1] - self.y0, self.width), np.zeros(len(x))], 1)

    def input_matrix(self, x):
        return np.broadcast_to(np.eye(2), (self._states(x).shape[0], 2, 2))


def jet(y0=0.01, n=201):
    """Jet of speed 4 in a band w = 0.03 (1.5 cells) at y = y₀ on [−2, 2]² (n × n closed): a
    terminal cost Quadratic([1.5, 0], [5, 5]), a state cost of 1, λ = 0.05, T = 2."""
    return Problem(
        Jet(y0),
        G((-2, 2, n), (-2, 2, n)),
        2.0,
        Quadratic([1.5, 0.0], [5.0, 5.0]),
        state_cost=lambda x: np.ones(len(np.atleast_2d(x))),
        temperature=0.05,
    )


# ---- (3) smooth problems on odd and even node counts (false warnings) ----
def smooth(n):
    """Point mass to the origin from a smooth quadratic cost, λ = 0.1, T = 3, n × n nodes on
    [−3, 3] × [−4, 4]."""
    return Problem(
        PointMass(),
        G((-3, 3, n), (-4, 4, n)),
        3.0,
        Quadratic([0.0, 0.0], [4.0, 1.0]),
        state_cost=Quadratic([0.0, 0.0], [1.0, 0.1]),
        temperature=0.1,
    )


X_MASS = S((0.2, 0), (0.8, 1.0), (-1.0, -1.0))
P6 = {  # name: builder, states, cert_dt, fine, max_time (round 3's layout)
    "mass_pit_centre": (mass_pit_centre, X_MASS, 0.002, 2.0, None),
    "mass_pit_wall": (mass_pit_wall, S((-1.6, 0), (-1.0, 1.0), (-0.5, -1.0)), 0.002, 2.0, None),
    "rotor_pit_seam": (rotor_pit_seam, S((2.8, 0), (-2.9, 1.0), (1.5, -1.5)), 0.002, 2.0, None),
    "rotor_pit_zero_even": (
        rotor_pit_zero_even,
        S((0.3, 0), (1.2, 1.0), (-1.5, -1.5)),
        0.002,
        2.0,
        None,
    ),
    "pit_3d_centre": (
        pit_3d_centre,
        S((0.3, 0, 0), (1.2, 1.0, 0.8), (-0.5, -1.0, -0.5)),
        0.002,
        1.5,
        None,
    ),
    "two_pits_aligned_deeper": (
        lambda: two_pits(3.0, 2.5),
        S((0.2, 0), (-0.4, 0.5), (1.0, -1.0)),
        0.002,
        2.0,
        None,
    ),
    "two_pits": (two_pits, S((0.2, 0), (-0.4, 0.5), (1.0, -1.0)), 0.002, 2.0, None),
    "few_nodes": (few_nodes, X_MASS, 0.002, 2.0, None),
    "terminal_pit_centre": (
        terminal_pit_centre,
        S((0.2, 0), (0.6, -0.5), (0.0, 1.0)),
        0.001,
        2.0,
        None,
    ),
    "jet": (jet, S((-1.5, 0.3), (-1.0, -0.5), (0.0, 1.0)), 0.002, 2.0, None),
    "smooth_odd": (lambda: smooth(201), S((1, 0), (-2, 1), (0.5, -2)), 0.002, 2.0, None),
    "smooth_even": (lambda: smooth(200), S((1, 0), (-2, 1), (0.5, -2)), 0.002, 2.0, None),
}
X_WALL = S((-1.6, 0), (-1.0, 1.0), (-0.5, -1.0))
for _x, _n, _X in [  # the position and node-count sweeps (one change each)
    (0.09, 201, X_MASS),
    (0.17, 201, X_MASS),
    (0.0, 200, X_MASS),
    (0.01, 203, X_MASS),
    (-2 + 30.5 * 4 / 199, 200, X_WALL),
    (-1.79, 201, X_WALL),
]:
    P6[f"mass_pit_{_x:.4g}_{_n}"] = (
        lambda _x=_x, _n=_n: r5.mass_pit_at(_x, nodes=_n),
        _X,
        0.002,
        2.0,
        None,
    )
r3.P.update(P6)


def main(argv: list[str]) -> None:
    OUT.mkdir(exist_ok=True)
    r3.OUT = OUT
    for name in [a for a in argv if not a.startswith("--")]:
        r3.run(name, "--own" in argv, 0.5 if "--halfdt" in argv else 1.0)


if __name__ == "__main__":
    main(sys.argv[1:])
