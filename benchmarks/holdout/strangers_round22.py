"""Stranger round 22: features narrower than a cell at chosen offsets from the nodes, posed with the
public API only (SPEC §1–3, §6, §9–10; README "Your own system": the systems here are my own
``ControlAffineSystem`` subclass ``Sep``, each axis with its own drift aᵢ(xᵢ) and gain bᵢ(xᵢ)).

Kinds (width 0.2–0.5 cell unless said; "node", "mid", "qtr": on a node, at mid-cell, a quarter
cell off; closed axes with odd (101, 81, 41, 21) and even (100, 80, 40) node counts, periodic axes
with 63 and 64 nodes):

1. Wells in the state cost q (q = base + depth everywhere but a Gaussian well of 5 λ): 2-D 101²
   node/mid/qtr and 100² mid, 3-D 41³ qtr, periodic 63 mid and 64 qtr/node, 4-D 21⁴ mid; a round
   well at a cell centre (``pointwell2``, certified); tolls (a bump of 20 λ) the path must cross,
   2-D mid/node and 3-D mid; first exit through x₀ ≥ 1.9 across a toll or a well (2-D, 3-D).
2. Narrow terminal goals (a dip of 4–6 λ): 2-D node/mid/qtr, 3-D even qtr, periodic 64 mid and
   63 across the seam, 4-D 21⁴ (s = 0.05 cell at a quarter cell, between the lattice points of the
   costs' check), 2-D s = 0.015 cell at 3/16 cell; read at t = 0 and at 0.8–0.95 T.
3. Exit sets thinner than a cell: a strip |x₀ − c| ≤ 0.15 h (exit cost 0) beside a wide exit at
   x₀ ≤ −1.9 (cost 3), first exit on 81² node/mid/qtr, 80² mid, 41³ mid/qtr, and with a horizon
   (T = 2, read at 0 and 1.8); an exit-cost door 0.3 cell wide at mid-cell along x₀ ≥ 1.9
   (``door2_mid``, certified).
4. Dynamics narrower than a cell (kind 4 of the brief, and its drift twin): the gain b(x₀) (noise
   and control together, Cov = λ b²) dropping to 0.15 or 0.05 in a band at mid-cell, on a node,
   at a quarter cell (2-D, 3-D, periodic 63/64, λ = 0.02), a gain jumping 1 → 3 within 0.05 cell;
   a drift wall a(x₀) = −30 e^{−(x₀−c)²/2s²} (s = 0.15 h) on a node kept by the grid with every
   other node (c = 0, 0.4), on one it drops (0.44), at mid-cell and a quarter cell, in 3-D and on a
   periodic axis, read at t = 0 and 0.8.
5. Combinations: λ = 0.02 (a well and a goal on two axes), λ = 2 (3-D, a 20-deep well and a dip).

51 problems, 62 (problem, t) entries, 222 (problem, state, t) pairs; at least one state at or
next to the feature and one far from it in each.

    cd /work/wt-r22/benchmarks/holdout   (or this folder on main)
    PYTHONPATH=<repo> NUMBA_NUM_THREADS=1 python strangers_round22.py NAME [NAME ...]
    ... --truth NAME ...    ... --solve NAME ...    ... --table    ... --compact
    ... --pairs   (where the pair carries the estimate: ``est_nopair`` below)
    ... --refined NAME ...  (cross-check only: the default solve on a 2× grid, v at the states)

Layout as rounds 20–21 (``P22``: name → (builder, states, truth, tag, t); round 20's
``truth_run`` and ``table`` run it, pointed at ``P22`` and this round's results folder).
``quick22`` is round 20's ``quick20`` (v, ê and its parts: the embedded difference, the pair's
|v_c₁ − v_c₂|, S, γ, the floor, the order; every GridlbcWarning), tolerant of a library without
the pair, and it records ``est_nopair``: the solve's EmbeddedEstimate rebuilt by
``gridlbc.accuracy.estimate.embedded_estimate`` from the same embedded, 4h and excess solves with
``pair=None`` (floor included), read at the same states and time — a preview of the estimate
once the pair is dropped (the solve's warning is not previewed).

Truths (tag), none from the library's grid solvers:

- "1-D": every separable problem (costs and dynamics a sum over axes, ẋᵢ = aᵢ + bᵢuᵢ) is the sum
  of 1-D problems, each by round 21's Crank–Nicolson (``cn1d``: D = λb²/2, reflecting or periodic
  ends) on 8001 and 16001 nodes (τ/4000, τ/8000 steps): the features are 12–60 fine nodes wide;
  ± the two's difference (≤ 0.003; 0.0013 on the thinnest goal).
- "fd": first exit in 1-D (the strips and the exit tolls/wells depend on x₀ only: the other axes
  reflect and carry no cost): my own central finite differences of (q/λ) z = D z″ + a z′ off E,
  z = e^{−g_E/λ} on E, on 10001 and 20001 nodes (the 0.3-cell strip holds 38–75 of them).
- "cn": the strip with a horizon: Crank–Nicolson as above with z held at e^{−g_E/λ} on E.
- "cert": ``gridlbc.certify`` (Richardson in Δt, boundary "reflect", proposal the policy of the
  default solve on the 2× grid): ``pointwell2`` 8000 paths at Δt = 0.001 (ESS ≈ 7990, SE 1e-4);
  ``door2_mid`` 4000 paths at Δt = 5e-4, max_time 10 (ESS 304 / 8 / 239: shaky; Δt = 0.002 gave
  0.518 / 1.10 / 2.14 against 0.483 / 0.95 / 2.55: the exit point's Euler error on a door 0.3
  cell wide — the solve's error there is 4× either).
- Cross-checks: the drift wall certified with the solve's own (wall-blind) policy as proposal,
  4000 paths, Δt 4e-4 / 2e-4: 1.77 / 1.82 at (0, 0) and 1.51 / 1.74 at (0.4, 0) (ESS 5–15, shaky)
  against the CN truth 1.865 / 1.501 and the solve's 1.064 / 0.744; 2× grids (``--refined``).

RESULTS (library of commit 3fc621e merged into round22, 2026-12-06, one thread; ``--table``; the
same numbers to the last digit as under 081a65c): 62 entries, 222 pairs, ê ≥ ½|v − v*| at 187 / 222. (Errors are relative to max(|v*|, λ), ê to max(|v|, λ).)

SILENT (> 10 % off, no GridlbcWarning): 16 pairs in 5 entries, two mechanisms.

1. An exit set thinner than a cell that no grid's node falls in (first exit, no horizon).
   ``exit_strip_mid`` (81², h = 0.05, λ = 0.2, q = 1, strip |x₀ − 0.525| ≤ 0.0075, cost 0; exit
   x₀ ≤ −1.9, cost 3): v / truth (fd, ± ≤ 3e-4) at (0.225, 0.5) 5.987 / 0.414, (−1, −1) 4.266 /
   2.146 (+99 %), (1.5, 1) 7.784 / 1.368, (0.555, 0) 6.453 / 0.032, on the strip (0.525, 0)
   6.409 / 0; ê 0.40–0.45 % of |v| at the first three (embedded |v₂ₕ − v| 0.02–0.07, pair
   0.005–0.009, S = γ = 0, floor 0.40 %), 98.9 % at (0.555, 0) (the local certificate's 8 steps
   reach the strip from 0.6 cell). ``exit_strip_qtr`` (0.5125) the same: 5.970 / 0.414, 4.266 /
   2.128, 7.784 / 1.386. The exit set is a mask read at the nodes: no node of the grid (0.50,
   0.55), the embedded and 4h grids or the pair (39 and 41 cells: nearest nodes 0.462/0.564 and
   0.439/0.537) lies in the strip, so every solve is the problem without it and they agree; S and
   γ read costs only (the exit cost's step at −1.9 lies on a node of 81 and of the embedded 41);
   without a horizon there is no whole-task certificate. The 2× grid (161²) has a node at 0.525
   and is right for the mid strip (0.413, 2.143, 1.366); for the quarter strip (nodes 0.500, 0.525)
   it is as wrong (5.983, 4.271, 7.802), also silent. With a horizon (``exit_strip_T_mid``, T = 2)
   the same strip is warned and read: ê 79 / 6.2 / 29 % against +368 / +10.6 / +54 % (the whole
   task's certificate). Warned only by accident elsewhere: ``exit_strip_odd_mid`` (80²: the cost
   step at −1.9 falls between nodes: S, γ) with ê 21 / 40 / 7.8 % against +1564 / +40 / +1578 %,
   and ``exit_strip3_mid`` (41³, mid-cell; the step between the embedded grid's nodes) with
   ê 2.7 / 3.7 / 2.1 % against +1381 / +96 / +483 %. ``exit_strip3_qtr`` (41³, 0.525) is warned and
   read (ê 79–91 %) only because the pair's 19-cell grid has a node at 0.526, inside the strip.
   Reproduce: ``python strangers_round22.py exit_strip_mid exit_strip_qtr``.

2. A drift wall narrower than a cell on a node that the grid with every other node keeps.
   ``driftwall2_even_node`` (101², λ = 0.1, T = 1, ẋ₀ = −30 e^{−(x₀−0.4)²/2(0.006)²} + u₀, q = 0.3,
   g = 2(x₀ − 1.2)² + a smooth axis): v / truth (1-D, ± 0.0026) at (0, 0) 1.0639 / 1.8647 (−43 %),
   (0.4, 0) 0.7439 / 1.5006 (−50 %); ê 17.4 / 11.0 % (the local certificate: embedded, pair, S,
   γ ≤ 0.1 %, floor 0.02 %); at t = 0.8 (``_late``) 1.8124 / 2.0164 (−10.1 %, ê 7.0 %) and 0.9183 /
   1.5562 (−41 %, ê 24.9 %). ``driftwall2_node`` (the wall on x₀ = 0, the axis's centre):
   1.3880 / 2.2018 (−37 %, ê 11.9 %), 0.8879 / 1.6321 (−46 %, ê 46.6 %). The solve equals the
   problem without the wall to 1e-6 (1.063877 against 1.063877), on the 2× grid too (1.0764,
   0.7567, silent). What I can tell: the splitting's midpoint foot reads a at x + a(x)Δt/2, 1.4
   away from the wall's node (Δt = 0.091), where a ≈ 0, so no node is moved by the wall; the flow
   check (``accuracy.flow``) compares a with its interpolants from the grid and the embedded grid,
   and on a node both keep, I_h a and I_2h a are hats 2h and 4h wide: their errors grow as h
   (p = 1, not < 1), so it passes as "converging". On a node the embedded grid drops (0.44) or
   at a quarter cell (0.41) it warns (``driftwall2_odd_node``, ``_qtr``: the same v, the same
   −42…−52 %, ê 17–27 %: under-reads); in 3-D (41³, even node) and on a periodic 64-node axis the
   confirmation's local certificate warns (ê 73–84 % against −47/−50 %; 37 % against −47 %).
   Reproduce: ``python strangers_round22.py driftwall2_even_node driftwall2_even_node_late
   driftwall2_node``.

UNDER-READS (ê < ½|err|, err > 2 %): 33 pairs. Besides the silent ones above and their warned
twins (drift walls 0.44 / 0.41, periodic: ê/err 0.22–0.43; ``exit_strip_odd_mid``, ``exit_strip3_mid``):

- A gain that changes within a cell is not seen at all (B is read at the nodes; no check reads
  it between them; every part ≤ 0.1 %). ``gainband2_mid`` (b → 0.15 in a band 0.3 cell wide at
  x₀ = 0.02, mid-cell; λ = 0.1, q = 0.5, g = 3(x₀ − 1)²): (−0.5, 0) 1.6695 / 1.7693 (−5.6 %, ê
  0.9 %), (0, 0) 1.1336 / 1.2093 (−6.3 %, ê 0.9 %); ``gainband2_deep`` (b → 0.05, the same v to
  4 digits): −12.6 % (ê 1.7 %), −14.9 % (ê 2.1 %), 2× grid 1.7018 / 1.1664 (−11 / −12 %);
  ``gainjump2_qtr`` (b 1 → 3 within 0.05 cell at 0.01, λ = 0.3): −3.4 % (ê 0.4 %);
  ``gainband2_cold_qtr`` (λ = 0.02, quiet): −5.2 % (ê 1.8 %), −3.8 % (ê 0.7 %);
  ``per_gainband_even_node``: −3.6 % (ê 1.7 %). The first three are "warned" only by a warning
  about another place — near (2, −0.88) and (2, −0.28) at t = 0.95, true there (+6.9 % with
  ê 6.7 %; +77 % with ê 37 %) — which says nothing of the band. On a node (``gainband2_node``)
  or a periodic 63-node axis at mid-cell the estimate reads it (ê/err 0.7–1.8), and the 3-D
  quarter-cell band reads half (ê 14.7 / 15.7 % against −21 / −22 %).
  Reproduce: ``python strangers_round22.py gainband2_deep gainband2_mid gainjump2_qtr``.
- ``goal4_thin_qtr`` (21⁴, a dip of 5 λ with s = 0.05 cell a quarter cell off a node, λ = 0.3):
  at the dip 0.4613 / 0.2729 (+63 % of λ-scaled, ê 2.5 %: S 2.5 %, the costs' lattice has 2
  points a cell in 4-D), far (−0.8, 0.5, 0.5, −0.6) +10 % (ê 0.6 %); at t = 0.9 +115 % (ê 53 %,
  γ) and +94 % (ê 17 %). Warned (near the dip at t = 0.95, true).
- ``exit_strip_T_node`` (0.2, 0.5): +2.0 % with ê 0.9 %.

FALSE ALARMS (warned, every judged state within 3 %): well2_mid, well2_qtr, well2_even_mid,
well3_qtr, per_well_odd_mid, per_well_even_qtr — narrow wells in q (5 λ deep, 0.3–0.4 cell wide)
that a path cannot hold: errors ≤ 2.9 %, ê 8–20 % from S.

Fine (warned and read, ê/err 0.9–3): every narrow terminal goal at t = 0 and late (10–360 % off;
``per_goal_odd_seam`` across the periodic seam 396 % at the dip, ê/err 1.0), the tolls (≤ 8.5 %),
the exit tolls and wells (2–12 %), the λ = 0.02 and λ = 2 combinations, the 4-D well (17 %),
``door2_mid`` (v 2.10 against ≈ 0.48, ê 76 %); ``pointwell2`` quiet and within 0.24 %.

THE PAIR (``--pairs``, ``est_nopair``; measured under 081a65c, unchanged under 3fc621e): without
the pair, ê ≥ ½|err| would fail at 5 more states,
182 / 222: ``driftwall2_mid`` (a drift wall at mid-cell; ê 41.9 / 49.4 % → 9.7 / 12.7 % against
errors of 54 / 83 % of |v|; its flow warning does not depend on the pair) and ``exit_strip3_qtr``
(ê 91 / 79 / 81 % → 2.7 / 3.7 / 2.1 % against 93 / 50 / 82 %: only the pair's 19-cell grid has a
node inside the strip; without it this is ``exit_strip3_mid``, and its warning probably goes with
it — not previewed). Everywhere else S, γ or the local certificate carry the same reading (goal2_qtr
14.4 → 8.8 % against 9.8 %; per_well_even_node 14.6 → 10.0 % against 5.8 %). Neither S nor γ looks
at the dynamics or at the exit set: the pair's part there was by chance of where its nodes fall.
Under 3fc621e (the pair solved only where ``reads_pair`` expects a feature) both keep it
(driftwall2_mid: a drift whose interpolation does not converge; exit_strip3_qtr: an exit set), and
57 of the 62 entries still solve it; the 5 without it (driftwall2_even_node and its late read,
driftwall3_even_node, gainband2_node, gainband3_qtr: walls and bands on nodes both grids keep, whose
interpolation converges at first order) read ≤ 0.5 % from it before, and their estimates and
warnings are unchanged.

AFTER (library of commit d8e5596, rerun ``--solve`` of all 62 entries, one thread): the exit set is
sampled between the nodes (``gridlbc.accuracy.missed_exit``: every exit strip at mid-cell and a
quarter cell warns), and the drift and the noise are judged by their least interpolation order
over the estimate's grids against 1.5 (``gridlbc.accuracy.SMOOTH_ORDER``: every drift wall and
gain band warns). Silent: none (16 before). Then (library of the next commit) the response S also
moves the parts of the exit set no node holds onto the embedded grid's nearest node
(``gridlbc.accuracy.exits.MovedExit``): the strips are read (exit_strip_mid: ê 3.1–6.4 where v is
2.1–6.4 too high). ê ≥ ½|err| at 198/222 (187 before); under-reads left, each warned: the drift
walls, the gain bands, goal4_thin_qtr, exit_strip_T_node (2 %). False alarms: the same six narrow
wells.
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings
from functools import partial
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import strangers_round20 as r20
from scipy.special import expit
from strangers_round16 import _warned
from strangers_round20 import S, finer
from strangers_round21 import _operator, cn1d

import gridlbc
from gridlbc import Axis, Grid, Problem
from gridlbc.accuracy import cost_gap
from gridlbc.accuracy.estimate import embedded_estimate
from gridlbc.systems import ControlAffineSystem

OUT = Path("/work/main/benchmarks/holdout/strangers_round22_results")  # gitignored there
PI = math.pi


# ---------------- a user's own system: each axis its own drift and gain ---------------------------
class Sep(ControlAffineSystem):
    """ẋᵢ = aᵢ(xᵢ) + bᵢ(xᵢ) uᵢ, one control per axis (B diagonal, the gain may vary in a cell)."""

    def __init__(self, drifts, gains, periodic=()):
        self.state_dim = self.control_dim = len(drifts)
        self.state_names = tuple(f"x{i}" for i in range(self.state_dim))
        self.angle_axes = tuple(periodic)
        self.drifts, self.gains = drifts, gains

    def drift(self, x):
        x = self._states(x)
        return np.stack(
            [np.broadcast_to(f(x[:, i]), (len(x),)) for i, f in enumerate(self.drifts)], 1
        )

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((len(x), self.state_dim, self.control_dim))
        for i, f in enumerate(self.gains):
            B[:, i, i] = f(x[:, i])
        return B


def Z(x):
    return 0.0 * np.asarray(x, float)


def ONE(x):
    return 1.0 + 0.0 * np.asarray(x, float)


def gauss(x, c, s, period=None):
    d = np.asarray(x, float) - c
    if period is not None:
        d = (d + period / 2) % period - period / 2
    return np.exp(-(d**2) / (2 * s**2))


def _diffusion(b, lam):
    return lambda x: lam * np.asarray(b(x), float) ** 2 / 2


def _scaled_gauss(amp, c, s, period=None):
    return lambda x: amp * gauss(x, c, s, period)


def _band(drop, c, s, period=None):
    return lambda x: 1 - drop * gauss(x, c, s, period)


def _strip_mask(xe):
    return lambda x: (np.abs(x - xe) <= 0.0075) | (x <= -1.9)


def node(lo, hi, n, i, frac=0.0, periodic=False):
    """The point `frac` of a cell past node i of Axis(lo, hi, n)."""
    h = (hi - lo) / (n if periodic else n - 1)
    return lo + (i + frac) * h, h


def sep_problem(axes, lam, T, **kw):
    """axes: list of dicts lo, hi, n, periodic, a, b, q, g (functions of one coordinate)."""
    grid = Grid([Axis(s["lo"], s["hi"], s["n"], periodic=s.get("periodic", False)) for s in axes])
    sysm = Sep(
        [s.get("a", Z) for s in axes],
        [s.get("b", ONE) for s in axes],
        [i for i, s in enumerate(axes) if s.get("periodic")],
    )
    qs, gs = [s.get("q", Z) for s in axes], [s.get("g", Z) for s in axes]

    def q(x):
        return sum(np.asarray(f(x[:, i]), float) for i, f in enumerate(qs))

    def g(x):
        return sum(np.asarray(f(x[:, i]), float) for i, f in enumerate(gs))

    return Problem(sysm, grid, T, terminal_cost=g, state_cost=q, temperature=lam, **kw)


def sep_truth(axes, lam, T, t=0.0):
    """v = Σ v_i, each by round 21's Crank–Nicolson (8001 / 16001 nodes); D = λ b²/2."""

    def truth(X):
        X = np.asarray(X, float)
        res = []
        for n, steps in ((8001, 4000), (16001, 8000)):
            v = np.zeros(len(X))
            for i, s in enumerate(axes):
                b = s.get("b", ONE)
                v += cn1d(
                    s["lo"],
                    s["hi"],
                    T - t,
                    lam,
                    s.get("a", Z),
                    _diffusion(b, lam),
                    s.get("q", Z),
                    s.get("g", Z),
                    periodic=s.get("periodic", False),
                    n=n,
                    steps=steps,
                )(X[:, i])
            res.append(v)
        return res[1], np.abs(res[1] - res[0]), {"v_coarse": res[0].tolist()}

    return truth


def exit_fd(lo, hi, lam, q, exit_mask, exit_cost, b=ONE, a=Z):
    """First exit in 1-D (reflecting ends): (q/λ) z = a z′ + D z″ off E, z = e^{−g_E/λ} on E, by
    my own finite differences on 10001 and 20001 nodes (central; the exit set sampled on them)."""

    def solve(n):
        x = np.linspace(lo, hi, n)
        h = x[1] - x[0]
        D = lam * np.asarray(b(x), float) ** 2 / 2 + 0 * x
        av = np.asarray(a(x), float) + 0 * x
        qv = np.asarray(q(x), float) + 0 * x
        E = np.asarray(exit_mask(x), bool)
        main = -2 * D / h**2 - qv / lam
        up, dn = D / h**2 + av / (2 * h), D / h**2 - av / (2 * h)
        rows, cols, vals = [], [], []
        rhs = np.zeros(n)
        ge = np.asarray(exit_cost(x), float) + 0 * x
        gmin = ge[E].min()
        for j in range(n):
            if E[j]:
                rows.append(j), cols.append(j), vals.append(1.0)
                rhs[j] = math.exp(-(ge[j] - gmin) / lam)
                continue
            rows.append(j), cols.append(j), vals.append(main[j])
            if j == 0:
                rows.append(j), cols.append(1), vals.append(up[j] + dn[j])
            elif j == n - 1:
                rows.append(j), cols.append(n - 2), vals.append(up[j] + dn[j])
            else:
                rows += [j, j]
                cols += [j + 1, j - 1]
                vals += [up[j], dn[j]]
        A = sp.csc_matrix((vals, (rows, cols)), shape=(n, n))
        z = spla.spsolve(A, rhs)
        v = gmin - lam * np.log(np.maximum(z, 1e-300))
        return lambda y: np.interp(y, x, v)

    def truth(X):
        X = np.asarray(X, float)[:, 0]
        v1, v2 = solve(10001)(X), solve(20001)(X)
        return v2, np.abs(v2 - v1), {"v_coarse": v1.tolist()}

    return truth


def exit_cn1d(lo, hi, tau, lam, q, g, exit_mask, exit_cost, n, steps):
    """A task with a horizon and an exit set in 1-D (reflecting ends): Crank–Nicolson (four
    backward-Euler half steps first) of ∂τ z = D z″ − (q/λ) z off E, z = e^{−g_E/λ} held on E,
    z(0) = e^{−g/λ}; D = λ/2. v at the remaining horizon tau."""
    x = np.linspace(lo, hi, n)
    h = x[1] - x[0]
    L = _operator(x, h, 0 * x, lam / 2 + 0 * x, np.asarray(q(x), float) + 0 * x, lam, False)
    E = np.asarray(exit_mask(x), bool)
    zE = np.exp(-np.asarray(exit_cost(x), float) / lam)
    z = np.where(E, zE, np.exp(-np.asarray(g(x), float) / lam))
    keep = sp.diags((~E).astype(float))
    fix = sp.diags(E.astype(float))
    eye = sp.identity(n, format="csc")
    dt = tau / steps

    def lhs(c):
        return (fix + keep @ (eye - c * dt * L)).tocsc()

    be = spla.splu(lhs(0.5))
    for _ in range(4):
        z = be.solve(np.where(E, zE, z))
    A = spla.splu(lhs(0.5))
    Bm = (keep @ (eye + 0.5 * dt * L)).tocsr()
    for _ in range(steps - 2):
        z = A.solve(np.where(E, zE, Bm @ z))
    v = -lam * np.log(np.maximum(z, 1e-300))
    return lambda y: np.interp(y, x, v)


def exit_t_truth(t, T, lam, q, g, exit_mask, exit_cost):
    def truth(X):
        X = np.asarray(X, float)[:, 0]
        r = [
            exit_cn1d(-2, 2, T - t, lam, q, g, exit_mask, exit_cost, n, st)(X)
            for n, st in ((8001, 4000), (16001, 8000))
        ]
        return r[1], np.abs(r[1] - r[0]), {"v_coarse": r[0].tolist()}

    return truth


def cert22(build, t=0.0, factor=2.0, samples=2000, dt=0.004, sdt=None, max_time=None):
    """gridlbc.certify of the task from t, proposal = the policy of a solve `factor`× finer,
    Richardson in Δt (dt and 2 dt), boundary "reflect"."""

    def truth(X):
        p = build()
        if p.horizon is not None:
            p = p.replace(horizon=p.horizon - t)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            kws = dict(error_estimate=False)
            if sdt is not None:
                kws["dt"] = sdt
            s = gridlbc.solve(finer(p, factor), **kws)
            t1 = time.perf_counter()
            c = gridlbc.certify(
                p,
                s.policy,
                np.asarray(X),
                n_samples=samples,
                dt=dt,
                seed=22,
                richardson=True,
                progress=False,
                proposal=None,
                boundary="reflect",
                max_time=max_time,
            )
        print(f"    fine solve {t1 - t0:.1f} s, certificate {time.perf_counter() - t1:.1f} s")
        extra = dict(
            ess=np.asarray(c.effective_sample_size).tolist(),
            khat=np.asarray(c.pareto_k).tolist(),
            v_dt=np.asarray(c.optimal_value).tolist(),
            fine_v=np.asarray(s.value(np.asarray(X), 0.0)).tolist(),
            unexited=np.asarray(c.unexited_fraction).tolist(),
        )
        return np.asarray(c.extrapolated_value), np.asarray(c.extrapolated_value_se), extra

    return truth


# ---------------- the problems -------------------------------------------------------------------
SMOOTH = dict(lo=-2, hi=2, n=101, q=lambda x: 0.2 * x**2, g=lambda x: 0.5 * (x + 0.5) ** 2)


def well(c, s, depth, base=0.0, period=None):
    """A state cost `base + depth` everywhere but a well of width ~2s at c (q = base there)."""
    return lambda x: base + depth * (1 - gauss(x, c, s, period))


def dip(c, s, depth, period=None):
    """A terminal goal: −depth at c, 2s wide (g ≥ −depth)."""
    return lambda x: -depth * gauss(x, c, s, period)


def bump(c, s, height, period=None):
    return lambda x: height * gauss(x, c, s, period)


PROBS = {}  # name → (axes, lam, T)


def _def(name, axes, lam, T):
    PROBS[name] = (axes, lam, T)


def _builder(name):
    def build():
        axes, lam, T = PROBS[name]
        return sep_problem(axes, lam, T)

    build.__name__ = name
    return build


# 1. wells in q, 2-D, 101² (h = 0.04) on a node, mid-cell, quarter cell; λ = 0.1, depth 0.5 = 5 λ
_h = 0.04
for tag, frac in (("node", 0.0), ("mid", 0.5), ("qtr", 0.25)):
    c, _ = node(-2, 2, 101, 60, frac)  # 0.4 + frac h
    _def(
        f"well2_{tag}",
        [dict(lo=-2, hi=2, n=101, q=well(c, 0.15 * _h, 0.5), g=lambda x: 0.5 * x**2), SMOOTH],
        0.1,
        1.0,
    )
# the same at mid-cell on an even node count (100 nodes: 99 cells) and a 3-D well at a quarter cell
c100, h100 = node(-2, 2, 100, 59, 0.5)
_def(
    "well2_even_mid",
    [dict(lo=-2, hi=2, n=100, q=well(c100, 0.15 * h100, 0.5), g=lambda x: 0.5 * x**2), SMOOTH],
    0.1,
    1.0,
)
c41, h41 = node(-2, 2, 41, 24, 0.25)  # 0.425
_def(
    "well3_qtr",
    [
        dict(lo=-2, hi=2, n=41, q=well(c41, 0.2 * h41, 1.0), g=lambda x: 0.5 * x**2),
        dict(SMOOTH, n=41),
        dict(SMOOTH, n=41),
    ],
    0.2,
    1.0,
)
# periodic axes: 63 (odd) and 64 (even) nodes on [−π, π), drift 1.5 sin x, wells at mid / quarter
PER_C = {}
for nn, frac, tag in ((63, 0.5, "odd_mid"), (64, 0.25, "even_qtr"), (64, 0.0, "even_node")):
    cp, hp = node(-PI, PI, nn, nn // 2 + 5, frac, periodic=True)
    PER_C[f"per_well_{tag}"] = (cp, hp)
    _def(
        f"per_well_{tag}",
        [
            dict(
                lo=-PI,
                hi=PI,
                n=nn,
                periodic=True,
                a=lambda x: 1.5 * np.sin(x),
                q=well(cp, 0.15 * hp, 1.2, period=2 * PI),
                g=lambda x: 1 - np.cos(x),
            ),
            dict(lo=-PI, hi=PI, n=nn, periodic=True, q=lambda x: 0.3 * (1 - np.cos(x)), g=Z),
        ],
        0.2,
        2.0,
    )
# a toll the optimal path must cross: a bump 20 λ high, 0.3 cell wide, at mid-cell (0.02), λ = 0.05
_def(
    "toll2_mid",
    [
        dict(lo=-2, hi=2, n=101, q=bump(0.02, 0.15 * _h, 1.0), g=lambda x: 2.0 * (x - 1.0) ** 2),
        SMOOTH,
    ],
    0.05,
    1.5,
)
_def(
    "toll2_node",
    [
        dict(lo=-2, hi=2, n=101, q=bump(0.0, 0.15 * _h, 1.0), g=lambda x: 2.0 * (x - 1.0) ** 2),
        SMOOTH,
    ],
    0.05,
    1.5,
)
# 2. narrow terminal goals: a dip of 4 λ, 0.3 cell wide, 2-D (101²) at mid-cell / node / quarter,
# λ = 0.1, T = 1; read at t = 0 and late
for tag, frac in (("node", 0.0), ("mid", 0.5), ("qtr", 0.25)):
    c, _ = node(-2, 2, 101, 55, frac)  # 0.2 + frac h
    _def(
        f"goal2_{tag}",
        [
            dict(
                lo=-2,
                hi=2,
                n=101,
                q=lambda x: 0.3 + 0 * x,
                g=lambda x, c=c: 0.3 * x**2 + dip(c, 0.15 * _h, 0.4)(x),
            ),
            SMOOTH,
        ],
        0.1,
        1.0,
    )
# 3-D goal at a quarter cell on an even node count (40: 39 cells), λ = 0.3, T = 0.5
c40, h40 = node(-2, 2, 40, 22, 0.25)
_def(
    "goal3_even_qtr",
    [
        dict(lo=-2, hi=2, n=40, g=lambda x: 0.3 * x**2 + dip(c40, 0.2 * h40, 1.5)(x)),
        dict(lo=-2, hi=2, n=40, q=lambda x: 0.2 * x**2, g=Z),
        dict(lo=-2, hi=2, n=40, g=lambda x: 0.1 * x**2),
    ],
    0.3,
    0.5,
)
# periodic goal at mid-cell, 64 nodes, λ = 0.05
cpg, hpg = node(-PI, PI, 64, 40, 0.5, periodic=True)
_def(
    "per_goal_even_mid",
    [
        dict(
            lo=-PI,
            hi=PI,
            n=64,
            periodic=True,
            g=lambda x: 0.5 * (1 - np.cos(x)) + dip(cpg, 0.2 * hpg, 0.3, 2 * PI)(x),
            q=lambda x: 0.1 + 0 * x,
        ),
        dict(lo=-PI, hi=PI, n=64, periodic=True, g=lambda x: 0.3 * (1 - np.cos(x - 1))),
    ],
    0.05,
    1.0,
)
# 4. the gain changes within a cell: b(x₀) drops to 0.15 in a band 0.3 cell wide at mid-cell
# (the path to the goal must cross it), and a gain that jumps 1 → 3 within 0.2 cell
_def(
    "gainband2_mid",
    [
        dict(
            lo=-2,
            hi=2,
            n=101,
            b=lambda x: 1 - 0.85 * gauss(x, 0.02, 0.15 * _h),
            q=lambda x: 0.5 + 0 * x,
            g=lambda x: 3.0 * (x - 1.0) ** 2,
        ),
        SMOOTH,
    ],
    0.1,
    1.0,
)
_def(
    "gainjump2_qtr",
    [
        dict(
            lo=-2,
            hi=2,
            n=101,
            b=lambda x: 1 + 2 * expit((x - 0.01) / (0.05 * _h)),
            g=lambda x: 2.0 * (x - 1.0) ** 2,
            q=lambda x: 0.3 * x**2,
        ),
        SMOOTH,
    ],
    0.3,
    1.0,
)
# 5. combinations: λ = 0.02 (well + goal on two axes, 2-D), λ = 2 (3-D deep well), 4-D at 21⁴
_def(
    "combo2_cold",
    [
        dict(lo=-2, hi=2, n=101, q=well(0.42, 0.15 * _h, 0.1), g=lambda x: 0.5 * x**2),
        dict(lo=-2, hi=2, n=101, g=lambda x: 0.3 * x**2 + dip(-0.31, 0.12 * _h, 0.1)(x)),
    ],
    0.02,
    1.0,
)
_def(
    "combo3_hot",
    [
        dict(lo=-2, hi=2, n=41, q=well(0.05, 0.25 * h41, 20.0), g=lambda x: x**2),
        dict(lo=-2, hi=2, n=41, g=lambda x: 2 * x**2 + dip(-0.025, 0.2 * h41, 10.0)(x)),
        dict(SMOOTH, n=41),
    ],
    2.0,
    0.5,
)
c21, h21 = node(-1, 1, 21, 12, 0.5)  # 0.25
_def(
    "well4_mid",
    [
        dict(lo=-1, hi=1, n=21, q=well(c21, 0.2 * h21, 1.5), g=lambda x: (x - 0.2) ** 2),
        dict(lo=-1, hi=1, n=21, g=lambda x: 0.5 * x**2),
        dict(lo=-1, hi=1, n=21, q=lambda x: 0.2 * (1 - np.cos(3 * x))),
        dict(lo=-1, hi=1, n=21, g=lambda x: 0.5 * (x + 0.3) ** 2 + dip(-0.05, 0.2 * h21, 1.0)(x)),
    ],
    0.3,
    1.0,
)

# dynamics narrower than a cell (what the costs' checks cannot see): a drift wall a = −30 e^{−…}
# 0.3 cell wide between the start and the goal, at mid-cell and on a node; a gain that drops to
# 0.05 in a band 0.3 cell wide at mid-cell
for tag, cw in (("mid", 0.02), ("node", 0.0)):
    _def(
        f"driftwall2_{tag}",
        [
            dict(
                lo=-2,
                hi=2,
                n=101,
                a=_scaled_gauss(-30.0, cw, 0.15 * _h),
                q=lambda x: 0.3 + 0 * x,
                g=lambda x: 2.0 * (x - 1.0) ** 2,
            ),
            SMOOTH,
        ],
        0.1,
        1.0,
    )
_def(
    "gainband2_deep",
    [
        dict(
            lo=-2,
            hi=2,
            n=101,
            b=lambda x: 1 - 0.95 * gauss(x, 0.02, 0.15 * _h),
            q=lambda x: 0.5 + 0 * x,
            g=lambda x: 3.0 * (x - 1.0) ** 2,
        ),
        SMOOTH,
    ],
    0.1,
    1.0,
)

# the drift wall off the centre: on an even node (0.4, kept by the grid with every other node), an
# odd node (0.44, not kept) and a quarter cell (0.41); the gain band on a node and in 3-D at a
# quarter cell
for tag, cw in (("even_node", 0.4), ("odd_node", 0.44), ("qtr", 0.41)):
    _def(
        f"driftwall2_{tag}",
        [
            dict(
                lo=-2,
                hi=2,
                n=101,
                a=_scaled_gauss(-30.0, cw, 0.15 * _h),
                q=lambda x: 0.3 + 0 * x,
                g=lambda x: 2.0 * (x - 1.2) ** 2,
            ),
            SMOOTH,
        ],
        0.1,
        1.0,
    )
_def(
    "gainband2_node",
    [
        dict(
            lo=-2,
            hi=2,
            n=101,
            b=lambda x: 1 - 0.95 * gauss(x, 0.4, 0.15 * _h),
            q=lambda x: 0.5 + 0 * x,
            g=lambda x: 3.0 * (x - 1.2) ** 2,
        ),
        SMOOTH,
    ],
    0.1,
    1.0,
)
_def(
    "gainband3_qtr",
    [
        dict(
            lo=-2,
            hi=2,
            n=41,
            b=lambda x: 1 - 0.95 * gauss(x, 0.425, 0.2 * h41),
            q=lambda x: 0.5 + 0 * x,
            g=lambda x: 2.0 * (x - 1.2) ** 2,
        ),
        dict(SMOOTH, n=41),
        dict(SMOOTH, n=41),
    ],
    0.2,
    1.0,
)

# the drift wall on an even node in 3-D (41³, h = 0.1: 0.4 is node 24), λ = 0.2
_def(
    "driftwall3_even_node",
    [
        dict(
            lo=-2,
            hi=2,
            n=41,
            a=lambda x: -40.0 * gauss(x, 0.4, 0.2 * h41),
            q=lambda x: 0.3 + 0 * x,
            g=lambda x: 2.0 * (x - 1.2) ** 2,
        ),
        dict(SMOOTH, n=41),
        dict(SMOOTH, n=41),
    ],
    0.2,
    1.0,
)

# periodic: the gain band at mid-cell on 63 nodes and on an even node of 64; a drift wall on an
# even node of 64 (kept by the grid with every other node); λ = 0.2, T = 1.5, goal at x₀ = 1.2
PER_B = {}
for tag, nn, i, frac, kind in (
    ("gainband_odd_mid", 63, 36, 0.5, "gain"),
    ("gainband_even_node", 64, 38, 0.0, "gain"),
    ("driftwall_even_node", 64, 38, 0.0, "drift"),
):
    cb, hb = node(-PI, PI, nn, i, frac, periodic=True)
    PER_B[f"per_{tag}"] = cb
    ax0 = dict(
        lo=-PI,
        hi=PI,
        n=nn,
        periodic=True,
        q=lambda x: 0.3 + 0 * x,
        g=lambda x: 3.0 * (1 - np.cos(x - 1.2)),
    )
    if kind == "gain":
        ax0["b"] = _band(0.95, cb, 0.15 * hb, 2 * PI)
    else:
        ax0["a"] = _scaled_gauss(-40.0, cb, 0.15 * hb, 2 * PI)
    _def(
        f"per_{tag}",
        [ax0, dict(lo=-PI, hi=PI, n=nn, periodic=True, g=lambda x: 0.5 * (1 - np.cos(x)))],
        0.2,
        1.5,
    )

# a goal at mid-cell across the periodic seam (63 nodes: the last cell, π − h/2), λ = 0.1, T = 1;
# a gain band at a quarter cell at λ = 0.02
h63 = 2 * PI / 63
_def(
    "per_goal_odd_seam",
    [
        dict(
            lo=-PI,
            hi=PI,
            n=63,
            periodic=True,
            g=lambda x: 0.3 * (1 + np.cos(x)) + dip(PI - h63 / 2, 0.2 * h63, 0.5, 2 * PI)(x),
            q=lambda x: 0.2 + 0 * x,
        ),
        dict(lo=-PI, hi=PI, n=63, periodic=True, g=lambda x: 0.3 * (1 - np.cos(x))),
    ],
    0.1,
    1.0,
)
_def(
    "gainband2_cold_qtr",
    [
        dict(
            lo=-2,
            hi=2,
            n=101,
            b=lambda x: 1 - 0.9 * gauss(x, 0.41, 0.15 * _h),
            q=lambda x: 0.5 + 0 * x,
            g=lambda x: 3.0 * (x - 1.0) ** 2,
        ),
        SMOOTH,
    ],
    0.02,
    1.0,
)

# goals far narrower than the lattice of the costs' check: in 4-D (21⁴, 2 lattice points a cell) a
# dip of 5 λ, 0.1 cell wide (s = 0.05 h) a quarter cell off a node; in 2-D (101², 8 a cell) a dip
# of 6 λ with s = 0.015 h at 3/16 of a cell (between two lattice points)
_def(
    "goal4_thin_qtr",
    [
        dict(lo=-1, hi=1, n=21, g=lambda x: 0.5 * x**2 + dip(0.225, 0.05 * h21, 1.5)(x)),
        dict(lo=-1, hi=1, n=21, g=lambda x: 0.5 * x**2),
        dict(lo=-1, hi=1, n=21, q=lambda x: 0.2 + 0 * x),
        dict(lo=-1, hi=1, n=21, g=lambda x: 0.3 * (x - 0.2) ** 2),
    ],
    0.3,
    1.0,
)
_def(
    "goal2_thin_316",
    [
        dict(
            lo=-2, hi=2, n=101, g=lambda x: 0.3 * x**2 + dip(0.4 + 3 * _h / 16, 0.015 * _h, 0.6)(x)
        ),
        SMOOTH,
    ],
    0.1,
    1.0,
)

# a toll in 3-D (41³, h = 0.1): a bump 1.0 high (20 λ), 0.3 cell wide at mid-cell (0.05) between
# the start and the goal, λ = 0.05, T = 1.5
_def(
    "toll3_mid",
    [
        dict(lo=-2, hi=2, n=41, q=bump(0.05, 0.15 * h41, 1.0), g=lambda x: 2.0 * (x - 1.0) ** 2),
        dict(SMOOTH, n=41),
        dict(lo=-2, hi=2, n=41, g=lambda x: 0.3 * x**2),
    ],
    0.05,
    1.5,
)


# non-separable: a point well in q at a cell centre (2-D), a thin exit strip, an exit door
def pointwell2():
    """ẋ = u in 2-D (101²), q = 1 except a round well 0.3 cell wide at the cell centre
    (0.42, −0.18), λ = 0.1, T = 1, g = 0.5|x|²."""
    c = np.array([0.42, -0.18])
    return Problem(
        Sep([Z, Z], [ONE, ONE]),
        Grid([Axis(-2, 2, 101)] * 2),
        1.0,
        terminal_cost=lambda x: 0.5 * np.sum(x**2, 1),
        state_cost=lambda x: 1.0 - 0.9 * np.exp(-np.sum((x - c) ** 2, 1) / (2 * (0.15 * _h) ** 2)),
        temperature=0.1,
    )


def exit_strip(xe, n=81, horizon=None):
    """First exit (2-D, 81², h = 0.05, λ = 0.2, q = 1): the exit set is a strip |x₀ − xe| ≤ 0.15 h
    (cost 0) and x₀ ≤ −1.9 (cost 3); the walls elsewhere reflect."""
    hh = 0.05

    def E(x):
        return (np.abs(x[:, 0] - xe) <= 0.15 * hh) | (x[:, 0] <= -1.9)

    return Problem(
        Sep([Z, Z], [ONE, ONE]),
        Grid([Axis(-2, 2, n)] * 2),
        horizon,
        terminal_cost=None if horizon is None else (lambda x: 0.5 * (x[:, 0] - 0.5) ** 2),
        state_cost=lambda x: 1.0 + 0 * x[:, 0],
        temperature=0.2,
        exit=E,
        exit_cost=lambda x: np.where(x[:, 0] <= -1.9, 3.0, 0.0),
    )


def exit_strip3(xe):
    """exit_strip in 3-D, 41³ (h = 0.1), the strip |x₀ − xe| ≤ 0.15 h."""
    hh = 0.1

    def E(x):
        return (np.abs(x[:, 0] - xe) <= 0.15 * hh) | (x[:, 0] <= -1.9)

    return Problem(
        Sep([Z] * 3, [ONE] * 3),
        Grid([Axis(-2, 2, 41)] * 3),
        None,
        state_cost=lambda x: 1.0 + 0 * x[:, 0],
        temperature=0.2,
        exit=E,
        exit_cost=lambda x: np.where(x[:, 0] <= -1.9, 3.0, 0.0),
    )


def exit_strip_truth(xe):
    hh = 0.05
    return exit_fd(
        -2,
        2,
        0.2,
        lambda x: 1.0 + 0 * x,
        lambda x: (np.abs(x - xe) <= 0.15 * hh) | (x <= -1.9),
        lambda x: np.where(x <= -1.9, 3.0, 0.0),
    )


def exit_q(kind, xc, n=81, d=2, lam=0.05):
    """First exit through x₀ ≥ 1.9 (cost 0) on [−2, 2]^d (n nodes an axis), the walls elsewhere
    reflect; q = 0.5 plus a toll (a bump 2.0 high) or minus a well (q → 0.05), 0.3 cell wide at
    x₀ = xc, between the start and the exit."""
    hh = 4.0 / (n - 1)
    f = bump(xc, 0.15 * hh, 2.0) if kind == "toll" else (lambda x: -0.45 * gauss(x, xc, 0.15 * hh))
    return Problem(
        Sep([Z] * d, [ONE] * d),
        Grid([Axis(-2, 2, n)] * d),
        None,
        state_cost=lambda x: 0.5 + f(x[:, 0]),
        temperature=lam,
        exit=lambda x: x[:, 0] >= 1.9,
        exit_cost=0.0,
    )


def exit_q_truth(kind, xc, n=81, lam=0.05):
    hh = 4.0 / (n - 1)
    f = bump(xc, 0.15 * hh, 2.0) if kind == "toll" else (lambda x: -0.45 * gauss(x, xc, 0.15 * hh))
    return exit_fd(-2, 2, lam, lambda x: 0.5 + f(x), lambda x: x >= 1.9, lambda x: 0 * x)


def door2():
    """First exit through x₀ ≥ 1.9 (2-D, 81², λ = 0.1, q = 0.5): the exit costs 2 except a door
    0.3 cell wide (cost 0) at x₁ = 0.325 (mid-cell); the walls elsewhere reflect."""
    hh = 0.05
    return Problem(
        Sep([Z, Z], [ONE, ONE]),
        Grid([Axis(-2, 2, 81)] * 2),
        None,
        state_cost=lambda x: 0.5 + 0 * x[:, 0],
        temperature=0.1,
        exit=lambda x: x[:, 0] >= 1.9,
        exit_cost=lambda x: 2.0 - 2.0 * gauss(x[:, 1], 0.325, 0.15 * hh),
    )


def _lam_of(build):
    return build().temperature


P22 = {}
X2 = {
    "well2": S((0.4, 0.0), (0.4 + _h / 2, 0.3), (0.5, 0.0), (-1.2, 0.8)),
    "per": S((0.0, 0.0), (0.1, 0.5), (-2.0, 2.0)),
    "toll": S((-1.0, 0.0), (0.0, 0.0), (0.6, -0.4)),
    "goal2": S((0.2, 0.0), (0.25, 0.2), (-1.0, 0.5)),
}
for name, (axes, lam, T) in PROBS.items():
    b = _builder(name)
    if name.startswith("well2"):
        X = X2["well2"].copy()
        if name == "well2_even_mid":
            X[0, 0] = c100
    elif name.startswith("per_well"):
        cp, hp = PER_C[name]
        X = S((cp, 0.0), (cp + hp, 0.5), (0.0, 0.0), (-2.0, 2.0))
    elif name.startswith("toll2"):
        X = X2["toll"]
    elif name.startswith("goal2") and name != "goal2_thin_316":
        X = X2["goal2"]
    elif name == "well3_qtr":
        X = S((c41, 0, 0), (c41 + h41, 0.3, -0.2), (-1.0, 1.0, 0.5))
    elif name == "goal3_even_qtr":
        X = S((c40, 0, 0), (c40 - h40, 0.5, 0.2), (-1.2, -1.0, 1.0))
    elif name in PER_B:
        X = S((0.0, 0.0), (PER_B[name], 0.5), (-2.5, 2.0), (1.2, 0.0))
    elif name == "per_goal_odd_seam":
        X = S((PI - h63 / 2, 0.0), (-PI + 0.1, 0.5), (2.8, -1.0), (0.0, 0.0))
    elif name == "gainband2_cold_qtr":
        X = S((0.0, 0.0), (0.41, 0.0), (0.5, 0.3), (-1.0, 0.5))
    elif name == "goal4_thin_qtr":
        X = S((0.225, 0, 0, 0.2), (0.1, 0.2, -0.3, 0.0), (-0.8, 0.5, 0.5, -0.6))
    elif name == "goal2_thin_316":
        X = S((0.4075, 0.0), (0.45, 0.2), (-1.0, 0.5))
    elif name == "toll3_mid":
        X = S((-1.0, 0.0, 0.0), (0.0, 0.2, -0.2), (0.05, 0.0, 0.5), (0.6, -0.4, 0.0))
    elif name == "per_goal_even_mid":
        X = S((cpg, 1.0), (cpg + 0.3, 0.0), (-2.0, -1.0))
    elif name in (
        "driftwall2_even_node",
        "driftwall2_odd_node",
        "driftwall2_qtr",
        "gainband2_node",
    ):
        X = S((0.0, 0.0), (0.4, 0.0), (0.6, 0.3), (1.2, 0.5))
    elif name in ("gainband3_qtr", "driftwall3_even_node"):
        X = S((0.0, 0.0, 0.0), (0.425, 0.3, 0.0), (1.2, 0.5, -0.5))
    elif name.startswith("gain") or name.startswith("driftwall"):
        X = S((-0.5, 0.0), (0.0, 0.0), (0.8, 0.5))
    elif name == "combo2_cold":
        X = S((0.42, -0.31), (0.0, 0.0), (-1.0, 1.0))
    elif name == "combo3_hot":
        X = S((0.05, -0.025, 0.0), (0.5, 0.5, 0.5), (-1.5, 1.2, -1.0))
    elif name == "well4_mid":
        X = S((c21, 0, 0, -0.05), (0.0, 0.3, -0.3, 0.3), (-0.8, -0.5, 0.7, 0.8))
    P22[name] = (b, X, sep_truth(axes, lam, T), "1-D", 0.0)
# late reads of the goals (t = 0.8 T to 0.95 T)
for name, t in (
    ("goal4_thin_qtr", 0.9),
    ("goal2_thin_316", 0.9),
    ("driftwall2_even_node", 0.8),
    ("gainband2_deep", 0.9),
    ("goal2_mid", 0.9),
    ("goal2_node", 0.95),
    ("goal2_qtr", 0.8),
    ("goal3_even_qtr", 0.45),
    ("per_goal_even_mid", 0.9),
):
    b, X, _f, _tag, _t = P22[name]
    axes, lam, T = PROBS[name]
    P22[f"{name}_late"] = (b, X, sep_truth(axes, lam, T, t), "1-D", t)
P22["pointwell2"] = (
    pointwell2,
    S((0.42, -0.18), (0.5, -0.1), (-1.0, 1.0)),
    cert22(pointwell2, samples=8000, dt=0.001),
    "cert",
    0.0,
)
for tag, xe in (("mid", 0.525), ("node", 0.5)):
    b = partial(exit_strip, xe)
    b.__name__ = f"exit_strip_{tag}"
    P22[f"exit_strip_{tag}"] = (
        b,
        S((xe, 0.0), (xe - 0.3, 0.5), (-1.0, -1.0), (1.5, 1.0), (xe + 0.03, 0.0)),
        exit_strip_truth(xe),
        "fd",
        0.0,
    )
for tag, kind, xc, n, d in (
    ("exit_toll2_mid", "toll", 0.525, 81, 2),
    ("exit_toll2_node", "toll", 0.5, 81, 2),
    ("exit_well2_qtr", "well", 0.5125, 81, 2),
    ("exit_well3_mid", "well", 0.55, 41, 3),
):
    b = partial(exit_q, kind, xc, n, d)
    b.__name__ = tag
    X = S((xc, 0.0), (0.0, 0.5), (-1.5, -1.0), (1.7, 1.0))
    if d == 3:
        X = np.hstack([X, S((0.0,), (0.3,), (-1.0,), (1.0,))])
    P22[tag] = (b, X, exit_q_truth(kind, xc, n), "fd", 0.0)
# the thin exit strip in 3-D (41³, h = 0.1) at a quarter cell
b = partial(exit_strip3, 0.525)
b.__name__ = "exit_strip3_qtr"
P22["exit_strip3_qtr"] = (
    b,
    S((0.525, 0, 0), (0.2, 0.5, -0.5), (-1.0, -1.0, 1.0), (1.5, 1.0, 0.0)),
    exit_fd(
        -2,
        2,
        0.2,
        lambda x: 1.0 + 0 * x,
        lambda x: (np.abs(x - 0.525) <= 0.015) | (x <= -1.9),
        lambda x: np.where(x <= -1.9, 3.0, 0.0),
    ),
    "fd",
    0.0,
)
n80h = 4.0 / 79
for tag, xe, n in (("qtr", 0.5125, 81), ("odd_mid", -2 + 62.5 * n80h, 80)):
    b = partial(exit_strip, xe, n)
    b.__name__ = f"exit_strip_{tag}"
    P22[f"exit_strip_{tag}"] = (
        b,
        S((xe, 0.0), (xe - 0.3, 0.5), (-1.0, -1.0), (1.5, 1.0), (xe + 0.03, 0.0)),
        exit_strip_truth(xe),
        "fd",
        0.0,
    )
b = partial(exit_strip3, 0.55)
b.__name__ = "exit_strip3_mid"
P22["exit_strip3_mid"] = (
    b,
    S((0.55, 0, 0), (0.25, 0.5, -0.5), (-1.0, -1.0, 1.0), (1.5, 1.0, 0.0)),
    exit_fd(
        -2,
        2,
        0.2,
        lambda x: 1.0 + 0 * x,
        lambda x: (np.abs(x - 0.55) <= 0.015) | (x <= -1.9),
        lambda x: np.where(x <= -1.9, 3.0, 0.0),
    ),
    "fd",
    0.0,
)
for tag, xe in (("mid", 0.525), ("node", 0.5)):
    b = partial(exit_strip, xe, horizon=2.0)
    b.__name__ = f"exit_strip_T_{tag}"
    for t in (0.0, 1.8):
        P22[f"exit_strip_T_{tag}" + ("_late" if t else "")] = (
            b,
            S((xe, 0.0), (xe - 0.3, 0.5), (-1.0, -1.0), (1.5, 1.0)),
            exit_t_truth(
                t,
                2.0,
                0.2,
                lambda x: 1.0 + 0 * x,
                lambda x: 0.5 * (x - 0.5) ** 2,
                _strip_mask(xe),
                lambda x: np.where(x <= -1.9, 3.0, 0.0),
            ),
            "cn",
            t,
        )
P22["door2_mid"] = (
    door2,
    S((1.8, 0.325), (1.5, 0.0), (0.5, -1.0)),
    cert22(door2, samples=4000, dt=0.0005, max_time=10.0),
    "cert",
    0.0,
)


# ---------------- solve and record (round 20's quick20, tolerant of a missing pair) ---------------
def quick22(name):
    build, X, _f, _tag, t = P22[name]
    sol, w, dt = r20._solve(build)
    lam = sol.problem.temperature
    with warnings.catch_warnings(record=True) as w2:
        warnings.simplefilter("always")
        v = np.asarray(sol.value(X, t))
        est = np.asarray(sol.error_estimate(X, t))
    ws = w + list(w2)
    out = dict(
        name=name,
        X=X.tolist(),
        t=t,
        time=dt,
        warned=_warned(ws),
        warnings=[f"{x.category.__name__}: {str(x.message)[:400]}" for x in ws],
        v=v.tolist(),
        est=est.tolist(),
    )
    emb = getattr(sol, "embedded", None)
    if emb is not None:
        _v, v2h, diff, local = emb._read(sol, X, t)
        out.update(
            v2h=np.asarray(v2h).tolist(),
            diff=np.asarray(diff).tolist(),
            local=np.asarray(local).tolist(),
            floor=float(emb.floor),
            order=float(emb.observed_order),
            S=np.asarray(emb.excess_response(X, t)).tolist(),
            gamma=np.abs(np.asarray(cost_gap(sol, X, t))).tolist(),
        )
        pair = getattr(emb, "pair", None)
        if pair is not None:
            out["pair"] = np.abs(pair[0].value(X, t) - pair[1].value(X, t)).tolist()
            # a preview of the estimate without the pair: the EmbeddedEstimate rebuilt from the
            # same embedded, coarser and excess solves with pair None (its floor then from the
            # embedded difference alone); the solve's warning is not previewed
            nopair = embedded_estimate(sol, emb.solution, emb.coarser, None, emb.excess)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                out["est_nopair"] = np.asarray(nopair.error(sol, X, t)).tolist()
    d = getattr(sol, "diagnostics", None)
    out["dt"] = float(getattr(d, "dt", float("nan"))) if d is not None else None
    out["shape"] = list(sol.problem.grid.shape)
    sc = np.maximum(np.abs(v), lam)
    for i in range(len(X)):
        print(
            f"{name:18s} {X[i].round(3).tolist()!s:30s} t={t} v={v[i]:9.4f} est={100 * est[i] / sc[i]:6.2f}%"
        )
    for k in ("est_nopair", "diff", "local", "pair", "S", "gamma"):
        if k in out:
            print(f"  {k:6s} {np.round(100 * np.asarray(out[k]) / sc, 2).tolist()} %")
    if "floor" in out:
        print(f"  floor {100 * out['floor']:.2f} %  order {out['order']:.2f}")
    print(f"  solve {dt:.1f} s; warnings: {out['warnings']}", flush=True)
    (OUT / f"{name}_solve.json").write_text(json.dumps(out, indent=1))


def refined(name, factor=2.0):
    """Cross-check only: the default solve on a grid `factor`× finer, v at the entry's states."""
    build, X, _f, _tag, t = P22[name]
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        s = gridlbc.solve(finer(build(), factor), error_estimate=False)
        v = np.asarray(s.value(X, t))
    f = OUT / f"{name}_refined.json"
    old = json.loads(f.read_text()) if f.exists() else {}
    old[str(factor)] = v.tolist()
    f.write_text(json.dumps(old))
    print(
        f"  {name} ×{factor}: {np.round(v, 4).tolist()} ({time.perf_counter() - t0:.1f} s, {len(w)} warnings)"
    )


def compact():
    print(
        "problem              state                       t      pred     truth   ±unc kind  err%    ê%  ê/err w"
    )
    for name, (build, X, _f, tag, t) in P22.items():
        fs, ft = OUT / f"{name}_solve.json", OUT / f"{name}_truth.json"
        if not (fs.exists() and ft.exists()):
            continue
        d, tr = json.loads(fs.read_text()), json.loads(ft.read_text())
        lam = _lam_of(build)
        for i in range(len(X)):
            v, vs, e = d["v"][i], tr["vstar"][i], d["est"][i]
            sc = max(abs(vs), lam)
            st = ",".join(f"{c:g}" for c in np.round(X[i], 3))
            print(
                f"{name:20s} ({st})".ljust(48)
                + f"{t:5.2f} {v:9.4f} {vs:9.4f} {tr['unc'][i]:.0e} {tag:4s} {100 * (v - vs) / sc:+6.1f} "
                f"{100 * e / max(abs(v), lam):5.1f} {e / max(abs(v - vs), 1e-12):6.2f} {'Y' if d['warned'] else 'n'}"
            )


def pairs():
    """Where the pair carries the estimate: at each judged state, the pair's |v_c1 − v_c2|, the
    estimate without it (``est_nopair``: the solve's EmbeddedEstimate rebuilt with ``pair`` None,
    floor included, read at the same states and time), the actual error. Flags the states where ê ≥ ½|err| holds
    and that reconstruction without the pair does not."""
    for name, (build, X, _f, _tag, _t) in P22.items():
        fs, ft = OUT / f"{name}_solve.json", OUT / f"{name}_truth.json"
        if not (fs.exists() and ft.exists()):
            continue
        d, tr = json.loads(fs.read_text()), json.loads(ft.read_text())
        if "pair" not in d:
            continue
        lam = _lam_of(build)
        for i in range(len(X)):
            v, vs, e = d["v"][i], tr["vstar"][i], d["est"][i]
            emb = abs(d["v2h"][i] - v)
            q = 1.0 if emb > 0.15 * max(abs(v), lam) else min(max(d["order"], 1.0), 2.0)
            nopair = max(emb / (2**q - 1), d["floor"] * max(abs(v), lam), d["S"][i], d["gamma"][i])
            if "est_nopair" in d:
                nopair = d["est_nopair"][i]
            err = abs(v - vs)
            flag = e >= 0.5 * err and nopair < 0.5 * err and err > 0.02 * max(abs(vs), lam)
            if d["pair"][i] >= 0.5 * e or flag or nopair < 0.5 * e:
                sc = max(abs(v), lam)
                print(
                    f"{name:22s} {i} err {100 * err / sc:6.2f}% ê {100 * e / sc:6.2f}% pair "
                    f"{100 * d['pair'][i] / sc:6.2f}% without pair {100 * nopair / sc:6.2f}%"
                    + ("  <-- the pair carries it" if flag else "")
                )


def main(argv):
    OUT.mkdir(exist_ok=True)
    if "--pairs" in argv:
        pairs()
        return
    r20.P20, r20.OUT = P22, OUT
    if "--table" in argv:
        r20.table()
        return
    if "--compact" in argv:
        compact()
        return
    names = [a for a in argv if not a.startswith("--")]
    if "--refined" in argv:
        for name in names:
            refined(name, 2.0)
        return
    for name in names:
        if "--truth" not in argv:
            quick22(name)
        if "--solve" not in argv:
            r20.truth_run(name)


if __name__ == "__main__":
    main(sys.argv[1:])
