"""Stranger round 32: NEIGHBOURS OF THE KNOWN FAILURES (issue 25), IN NEW SHAPES (SPEC §1, §3, §6, §10).

RESULTS (library of r32 = main a29cb79, 2026-12-06, one thread; ``--run``, ``--lq``, ``--screen``
(10 of 24 problems reached in the time box), ``--tol``, ``--table``)

Posed (public API, ``Flow`` = a user ControlAffineSystem with constant B; corpus TollRoad/Unicycle):
24 new problems. (a) fast local flows: jet2 (a 6 m/s jet 0.15 wide), shear2 (tanh shear layer 0.1
thick, periodic x), source_sink (regularised pair), vortex_wall (core 18 rad/s, r 0.25, 0.25 from
a wall), vortex_seam (core straddling a periodic seam of period 4), vortex_offnode (25 rad/s, r
0.12 = 2.4 cells, centre off the nodes), fast_band (8 m/s flow in a band 1 cell wide), vortex_tube3
and jet3 (3-D, 41³). (b) 4-D on coarse grids: cartpole (21·20·21·21, two controls), two_di_cold
(21⁴, λ 0.05), coupled_di (25⁴, springs), rotor2 (two coupled pendula, 24²·25²), acrobot19 (19⁴,
λ 0.3, moving start), pm2_cold (25⁴, λ 0.02). (c) narrow costs on drift-only axes: ring_unicycle
(toll ring σ 0.3 cell), diag_strip (a toll strip along s + y/2 = 1.5, σ 0.15 cell), moving_strip
(time as an axis), periodic_strip (strip on a periodic drift axis), terminal_bump (σ 0.2 cell bump
in g along s), toll_tails (σ 0.004 core + σ 0.08 tail), strip2d, phase_terminal (narrow reward in
g on a periodic phase), phase_toll. λ 0.02–1 (×3 in variants), reads at t = 0, mid-interval near
T/2, T − Δt/2. Truths: ``certify`` (proposal None, the policy of the default solve on a grid 2×
finer (1.5–1.6× in 4-D) at Δt/2; ``richardson=True``; 2000 paths, 8000 where SE ≥ 0.5 %; trusted:
ESS ≥ 400 and SE < 0.5 % of max(|v*|, λ)); the three LQ members also against Riccati (round 25's
``lq_value``) at 400 states in the inner half of the box × 3 times × 4 variants.
``--screen``: per problem 4 variants (grid ×1, 1.5, 1, 2; λ ×1, 1, 3, 2; terminal Quadratic weights
×0.15 so the last step stops dominating) against a 2×-finer Δt/4 solve at 300 random states × 3
times; the worst (unwarned) or the worst under-read (warned) 3–4 pairs certified with 4000 paths.

Counts: 76 default solves (24 base + 40 screen variants + 12 LQ variants); 14711 pairs, 14669
trusted (239 certified: 150 base + 89 screen; 14472 Riccati). > 10 % off: 905 (mostly LQ 4-D
interior states, all warned). SILENT: 2. Under-reads: 27 (25 certified, 2 Riccati). ê ≥ ½ err at
14640 / 14669. All 24 base solves warn (ResolutionWarning), also at grid ×2 / λ ×4 with the steep
terminal costs: the warning names t ≈ T − Δt (the first step off g). Unwarned solves: 9 of 64
non-LQ (vortex_wall ×2, vortex_offnode ×3, vortex_seam ×1, shear2 ×3). Crashes: none. Stray
non-gridlbc warnings: none (CertificateWarnings from certify only, on the discarded truths).

After the fix (main, 2026-12-06): the warning's confirmation reads the tracing gap (the step
doubling of the paths' feet) beside γ and the local certificate; both silent solves warn
(vortex_seam g2,l2: confirmed 12.9 % at (1.925, −0.15), t = 2.38; vortex_wall g1,l1: 6.8 % at
(1.75, 0.15), t = 1.9; g2,l2: 7.3 %). The under-reads of finding 3 are in warned solves and
stay (the diagonal strip's estimate is 8× below its error).

FINDINGS, by severity

1. SILENT, vortex_wall soft (81², λ 1, g weights ×0.15; ``--screen vortex_wall``, variant g1,l1):
   x = (−1.805, 1.991) (a corner of the box), t = 1.9 = T − Δt/2: v 1.1565 vs v* 1.0454 ± 0.0024
   (10.6 %), ê 6.6 %, ESS 3983, no warning. The solve's own estimate at that state exceeds 5 %, but
   the warning only judges "the states that matter". ``solve(p, tol=0.05, states=[x])``: 81²,
   1.9 s, no warning, still 7.7 % off at the same (x, t) (v 1.1263): NOT within 5 %, silent again.
   The g2,l2 variant (161², λ 2): (1.989, 0.201) t 1.9: 9.7 %, ê 8.5 %, no warning.
2. SILENT, vortex_seam soft (160×161, λ 1, core on the periodic seam; variant g2,l2):
   x = (1.989, 0.201) (on the seam, next to the core), t = 2.375 = T − Δt/2: v 1.0527 vs v* 0.9291
   ± 0.0024 (12.4 %), ê 15.3 %, ESS 3983, no warning (again the estimate is right, the solve is
   silent). ``solve(p, tol=0.05, states=[x])``: within (v 0.9199, 0.9 %), 15 s, no warning.
3. Under-reads in warned solves (ê < ½ err, err > 2 %), worst ratios:
   - diag_strip (toll strip not aligned with the axes, σ 0.015 on a 0.1 grid): g1,l1 (41³)
     x = (1.148, 0.481, 3.549) t 1.375: v 1.5176 vs v* 2.1114 (28.1 %), ê 3.5 %; g2,l2 (81³, λ 2)
     (0.803, 1.234, 2.956) t 0: 1.2080 vs 1.7638 (27.8 %), ê 3.8 %; g1,l3 (1.41, −0.185, 3.303)
     t 1.375: 1.3517 vs 2.5054 (38.5 %), ê 6.5 %; 6 under-reads in 4 variants. The grid misses
     the diagonal toll (v < v*) and the estimate does not see it.
   - strip2d (ṡ = 1.2 drift only, strip σ 0.01 vs cells 0.05/0.033/0.025): 4 pairs 84–89 % off
     with ê 27–35 %: g1,l1 (0.351, −0.887) t 0: v 0.2849 vs v* 2.1856 (k̂ 0.72: v* may be high,
     but the toll's own integral 100·0.01·√(2π)/1.2 = 2.09 sets it); g1.5 (0.954, 1.187) t 0:
     0.1622 vs 1.4590, ê 30.6 %; g2,l2 (0.961, 1.67): 0.3665 vs 2.3561, ê 34.5 %.
   - fast_band (8 m/s band 1 cell wide): g1.5 (0.321, 0.9) t 1.1: 0.5999 vs 0.7439 (19.4 %),
     ê 4.7 %; g1,l3 (0.509, −0.389) t 1.9: 0.3849 vs 0.3059 (13.2 %), ê 3.8 %; g2,l2 (0.488, 0.28)
     t 1.083: 17.3 % with ê 3.8 % (screen) and g1.5 (0.467, 0.361) t 1.1: 34.3 % with ê 12.3 %.
   - jet2 downstream of the jet, near the far wall: 10 pairs, e.g. g1,l1 (2.285, −0.147) t 1.1:
     0.6977 vs 0.7493 (6.9 %), ê 2.0 %; g1,l3 (2.467, 0.081) t 1.9: 12.0 %, ê 5.3 %.
   - vortex_wall base (81², λ 1, steep g): (1.6, 0.1) t 1.1: 4.4947 vs 4.2407 (6.0 %), ê 1.8 %;
     g1.5: (1.697, −0.372) t 1.9: 3.9 %, ê 0.4 %.
   - pm2_cold g1.5 soft (37⁴, λ 0.02, Riccati): (1.466, −0.916, 1.982, −1.125) t 1.65: 7.5 %, ê
     2.3 %; (−0.13, −1.479, −0.043, −1.939): 8.4 %, ê 3.8 %.
4. The 4-D members (b) always warn and their estimates cover (ê ≥ ½ err at 14470 of 14472
   Riccati pairs; worst two_di_cold 21⁴ 120 % off with ê above it). acrobot19 at rest upright (x = 0) t 0.85: v 13.16 vs
   v* 1.00 (12×), warned, ê 92×. Several truths untrusted (ESS < 400): source_sink (ESS 2–5 from
   (0, −0.5)), acrobot19 t = 0, strip2d (0, −1), fast_band t ≤ 1.1 of the base run.
5. Messages: clear; but a solve warns "near [0.69, 0.025] at t = 1.9" for every steep terminal
   cost (all 24 base problems, and at λ ×4 / grid ×2), i.e. at the last step: a user learns
   nothing about the feature from it. Not a failure, a usability note.
6. Not reached in the time box: ``--screen`` of toll_tails, periodic_strip, moving_strip,
   source_sink, ring_unicycle, jet3, vortex_tube3, phase_terminal, rotor2, cartpole, acrobot19.

    cd /work/wt-r32 && PYTHONPATH=/work/wt-r32 NUMBA_NUM_THREADS=1 \
        python benchmarks/holdout/strangers_round32.py --list | --run [NAMES] | --lq \
        | --screen [NAMES] | --tol | --table
    (e.g. ``--screen vortex_wall vortex_seam diag_strip strip2d fast_band jet2 --force``; then
    ``--tol`` reruns ``solve(tol=0.05, states=[x])`` for every silent pair the table lists)
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import Acrobot, ControlAffineSystem, LinearSystem

sys.path.insert(0, str(Path(__file__).resolve().parent))
from corpus import TollRoad, Unicycle

OUT = Path("/work/main/benchmarks/holdout/strangers_round32_results")  # gitignored there
PI = math.pi


# ================= the user's own systems ======================================================
class Flow(ControlAffineSystem):
    """ẋ = a(x) + B u with a drift function ``fn`` and a constant input matrix ``B`` (d × m)."""

    def __init__(self, fn, B, angle_axes=()):
        self.fn, self.B = fn, np.asarray(B, float)
        self.state_dim, self.control_dim = self.B.shape
        self.state_names = tuple(f"x{i}" for i in range(self.state_dim))
        self.angle_axes = tuple(angle_axes)

    def drift(self, x):
        return self.fn(self._states(x))

    def input_matrix(self, x):
        return np.broadcast_to(self.B, (self._states(x).shape[0], *self.B.shape))


def wrap(d, period):
    return (d + period / 2) % period - period / 2


def gauss(d, s):
    return np.exp(-0.5 * (d / s) ** 2)


def spin(rel, rate, radius):
    w = rate * np.exp(-(rel**2).sum(1) / (2 * radius**2))
    return w[:, None] * np.stack([-rel[:, 1], rel[:, 0]], axis=1)


def G(*axes):
    return Grid([Axis(a[0], a[1], a[2], periodic=len(a) > 3 and a[3]) for a in axes])


# ================= the problems ================================================================
def problems():
    P = {}
    I2, I3 = np.eye(2), np.eye(3)

    # ---- (a) fast local flows in a quiet box ------------------------------------------------
    def jet(x):
        return np.stack([6.0 * gauss(x[:, 1], 0.15), np.zeros(len(x))], 1)

    P["jet2"] = dict(
        p=Problem(
            Flow(jet, I2),
            G((-3, 3, 101), (-2, 2, 81)),
            2.0,
            Quadratic([1.5, 0.8], [2.0, 2.0]),
            temperature=0.3,
        ),
        X=[[-2.0, 0.0], [-1.0, 0.5]],
    )

    def shear(x):
        return np.stack([4.0 * np.tanh(x[:, 1] / 0.1), np.zeros(len(x))], 1)

    P["shear2"] = dict(
        p=Problem(
            Flow(shear, I2),
            G((-3, 3, 100, True), (-2, 2, 81)),
            1.5,
            Quadratic([1.0, 0.3], [1.0, 3.0]),
            temperature=0.1,
        ),
        X=[[0.0, 0.05], [-1.0, -0.3]],
    )

    def srcsink(x):
        out = np.zeros_like(x)
        for c, k in (((-0.5, 0.0), 1.5), ((0.5, 0.0), -1.5)):
            r = x - np.array(c)
            out += k * r / ((r**2).sum(1) + 0.1**2)[:, None]
        return out

    P["source_sink"] = dict(
        p=Problem(
            Flow(srcsink, I2),
            G((-2, 2, 101), (-2, 2, 101)),
            2.0,
            Quadratic([0.0, 1.0], [2.0, 2.0]),
            temperature=0.5,
        ),
        X=[[-0.45, 0.05], [0.0, -0.5]],
    )

    def wallvortex(x):
        return spin(x - np.array([1.75, 0.0]), 18.0, 0.25) + 0.3 * np.stack([-x[:, 1], x[:, 0]], 1)

    P["vortex_wall"] = dict(
        p=Problem(
            Flow(wallvortex, I2),
            G((-2, 2, 81), (-2, 2, 81)),
            2.0,
            Quadratic([-1.0, 0.0], [2.0, 2.0]),
            temperature=1.0,
        ),
        X=[[1.6, 0.1], [1.0, -0.5]],
    )

    def seamvortex(x):
        rel = np.stack([wrap(x[:, 0] - 2.0, 4.0), x[:, 1]], 1)
        out = spin(rel, 18.0, 0.3)
        out[:, 1] += 0.2
        return out

    P["vortex_seam"] = dict(
        p=Problem(
            Flow(seamvortex, I2),
            G((-2, 2, 80, True), (-2, 2, 81)),
            2.5,
            Quadratic([0.0, 0.5], [2.0, 2.0]),
            temperature=0.5,
        ),
        X=[[1.9, 0.0], [-1.9, 0.2]],
    )

    def offvortex(x):
        c = np.array([0.825, 0.0167])
        return spin(x - c, 25.0, 0.12) + 0.3 * np.stack([-x[:, 1], x[:, 0]], 1)

    P["vortex_offnode"] = dict(
        p=Problem(
            Flow(offvortex, I2),
            G((-2.5, 2.5, 101), (-2.5, 2.5, 101)),
            2.0,
            Quadratic([-1.0, 0.0], [2.0, 2.0]),
            temperature=0.3,
        ),
        X=[[0.83, 0.02], [0.6, 0.3]],
    )

    def band(x):
        return np.stack([np.full(len(x), 0.3), 8.0 * gauss(x[:, 0] - 0.5, 0.05)], 1)

    P["fast_band"] = dict(
        p=Problem(
            Flow(band, I2),
            G((-3, 3, 121), (-2, 2, 81)),
            2.0,
            Quadratic([1.5, 0.0], [2.0, 2.0]),
            temperature=0.2,
        ),
        X=[[0.0, 0.0], [0.5, -1.0]],
    )

    def tube(x):
        out = np.zeros_like(x)
        out[:, :2] = spin(x[:, :2] - np.array([0.6, 0.0]), 15.0, 0.25)
        out[:, 2] = 0.3
        return out

    P["vortex_tube3"] = dict(
        p=Problem(
            Flow(tube, I3),
            G((-2, 2, 41), (-2, 2, 41), (-2, 2, 41)),
            1.5,
            Quadratic([-1.0, 0.0, 0.5], [2.0, 2.0, 1.0]),
            temperature=0.5,
        ),
        X=[[0.6, 0.1, 0.0], [0.3, -0.3, -0.5]],
    )

    def jet3(x):
        out = np.zeros_like(x)
        out[:, 0] = 5.0 * np.exp(-(x[:, 1] ** 2 + x[:, 2] ** 2) / (2 * 0.15**2))
        return out

    P["jet3"] = dict(
        p=Problem(
            Flow(jet3, I3),
            G((-2, 2, 41), (-2, 2, 41), (-2, 2, 41)),
            1.5,
            Quadratic([1.0, 0.5, 0.0], [2.0, 2.0, 2.0]),
            temperature=0.2,
        ),
        X=[[-1.5, 0.0, 0.0], [-1.0, 0.2, -0.1]],
    )

    # ---- (b) 4-D on coarse grids --------------------------------------------------------------
    def cartpole(x):
        th, v, om = x[:, 1], x[:, 2], x[:, 3]
        return np.stack([v, om, -0.1 * v, 9.81 * np.sin(th) - 0.3 * om - 2.0 * np.cos(th) * v], 1)

    B = np.zeros((4, 2))
    B[2, 0] = B[3, 1] = 1.0
    P["cartpole"] = dict(
        p=Problem(
            Flow(cartpole, B, angle_axes=(1,)),
            G((-3, 3, 21), (-PI, PI, 20, True), (-4, 4, 21), (-8, 8, 21)),
            2.0,
            Quadratic([0, 0, 0, 0], [1.0, 5.0, 0.2, 0.5]),
            control_cost=np.diag([1.0, 5.0]),
            temperature=0.3,
        ),
        X=[[1.0, 0.5, 1.5, -2.0], [0.0, 0.2, 0.0, 0.0]],
        fine=1.5,
    )
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1.0
    P["two_di_cold"] = dict(
        p=Problem(
            LinearSystem(A, B),
            G((-3, 3, 21), (-3, 3, 21), (-4, 4, 21), (-4, 4, 21)),
            2.0,
            Quadratic([0, 0, 0, 0], [2.0, 2.0, 0.5, 0.5]),
            state_cost=Quadratic([0, 0, 0, 0], [0.5, 0.5, 0.05, 0.05]),
            temperature=0.05,
        ),
        X=[[1.5, -1.0, 2.0, 1.0], [0.5, 0.5, 0.0, -0.5]],
        fine=1.5,
    )
    Ac = A.copy()
    Ac[2, 0], Ac[2, 1], Ac[3, 1], Ac[3, 0] = -2.0, 0.5, -1.0, 0.5
    P["coupled_di"] = dict(
        p=Problem(
            LinearSystem(Ac, B),
            G((-3, 3, 25), (-3, 3, 25), (-4, 4, 25), (-4, 4, 25)),
            2.5,
            Quadratic([0, 0, 0, 0], [2.0, 2.0, 0.5, 0.5]),
            temperature=0.2,
        ),
        X=[[1.0, 1.0, -1.5, 2.0], [-0.5, 0.8, 1.0, 0.0]],
        fine=1.5,
    )

    def rotor2(x):
        t1, t2, p1, p2 = x.T
        c = np.sin(t2 - t1)
        return np.stack([p1, p2, -2 * np.sin(t1) + c, -2 * np.sin(t2) - c], 1)

    P["rotor2"] = dict(
        p=Problem(
            Flow(rotor2, B, angle_axes=(0, 1)),
            G((-PI, PI, 24, True), (-PI, PI, 24, True), (-5, 5, 25), (-5, 5, 25)),
            2.0,
            Quadratic([PI, PI, 0, 0], [3.0, 3.0, 0.3, 0.3]),
            temperature=0.5,
        ),
        X=[[0.3, -0.5, 2.0, -1.5], [2.5, 2.8, 0.5, 0.5]],
        fine=1.5,
    )
    ac = Acrobot()
    P["acrobot19"] = dict(
        p=Problem(
            ac,
            ac.default_grid(19),
            1.5,
            Quadratic([0, 0, 0, 0], [10.0, 10.0, 0.5, 0.5]),
            state_cost=Quadratic([0, 0, 0, 0], [1.0, 1.0, 0.1, 0.1]),
            temperature=0.3,
        ),
        X=[[0.2, -0.3, 1.5, -1.0], [0.0, 0.0, 0.0, 0.0]],
        fine=1.6,
    )
    P["pm2_cold"] = dict(
        p=Problem(
            LinearSystem(A, B),
            G((-3, 3, 25), (-3, 3, 25), (-4, 4, 25), (-4, 4, 25)),
            3.0,
            Quadratic([0.5, -0.5, 0, 0], [3.0, 3.0, 1.0, 1.0]),
            temperature=0.02,
        ),
        X=[[2.0, -1.0, -1.0, 1.5], [-1.0, 1.0, 1.0, 0.0]],
        fine=1.5,
    )

    # ---- (c) narrow costs along drift-only axes -------------------------------------------------
    def ring(x):
        r = np.hypot(x[:, 0], x[:, 1])
        ang = np.arctan2(x[:, 1], x[:, 0])
        return 60.0 * gauss(r - 1.5, 0.03) * (1 - gauss(wrap(ang, 2 * PI), 0.3))

    P["ring_unicycle"] = dict(
        p=Problem(
            Unicycle(),
            G((-3, 3, 61), (-3, 3, 61), (-PI, PI, 48, True)),
            3.0,
            Quadratic([2.0, 0.0, 0.0], [2.0, 2.0, 0.0]),
            state_cost=ring,
            temperature=0.3,
        ),
        X=[[0.0, 0.0, 0.0], [0.0, 0.0, PI / 2]],
    )

    def diag(x):
        return 80.0 * gauss(x[:, 0] + 0.5 * x[:, 1] - 1.5, 0.015) * (1 - gauss(x[:, 1] - 1, 0.3))

    P["diag_strip"] = dict(
        p=Problem(
            TollRoad(),
            G((-0.5, 3.5, 41), (-2, 2, 41), (-4, 4, 41)),
            2.5,
            Quadratic([0, 0, 0], [0.0, 2.0, 0.5]),
            state_cost=diag,
        ),
        X=[[0.0, 0.0, 0.0], [0.0, 1.0, 0.5]],
    )

    A3 = np.zeros((3, 3))
    A3[1, 2] = 1.0

    def moving(x):
        return 60.0 * gauss(x[:, 1] - 0.5 - 0.8 * x[:, 0], 0.02) * (1 - gauss(x[:, 0] - 1.0, 0.2))

    def drift_ms(x):
        return np.stack([np.ones(len(x)), x[:, 2], np.zeros(len(x))], 1)

    P["moving_strip"] = dict(
        p=Problem(
            Flow(drift_ms, [[0.0], [0.0], [1.0]]),
            G((0, 3, 41), (-2, 4, 61), (-4, 4, 41)),
            2.5,
            Quadratic([0, 3.0, 0], [0.0, 2.0, 0.5]),
            state_cost=moving,
            temperature=0.5,
        ),
        X=[[0.0, 0.0, 1.0], [0.0, -0.5, 0.0]],
        clock=0,  # axis 0 is time: read states with x[0] = t
    )

    class PerToll:
        def __call__(self, x):
            x = np.atleast_2d(x)
            return 80.0 * gauss(wrap(x[:, 0] - PI, 2 * PI), 0.02) * (1 - gauss(x[:, 1] - 1, 0.3))

    P["periodic_strip"] = dict(
        p=Problem(
            PerTollRoad(),
            G((-PI, PI, 60, True), (-2, 2, 41), (-4, 4, 41)),
            4.0,
            Quadratic([0, 0, 0], [0.0, 2.0, 0.5]),
            state_cost=PerToll(),
            temperature=0.5,
        ),
        X=[[0.0, 0.0, 0.0], [2.0, 1.0, 0.0]],
    )

    def gbump(x):
        x = np.atleast_2d(x)
        return (0.5 * x[:, 1] ** 2 + 0.2 * x[:, 2] ** 2
                + 5.0 * gauss(x[:, 0] - 2.0, 0.02) * (1 - gauss(x[:, 1] - 1, 0.3)))  # fmt: skip

    P["terminal_bump"] = dict(
        p=Problem(
            TollRoad(), G((-0.5, 3.5, 41), (-2, 2, 41), (-4, 4, 41)), 1.5, gbump, temperature=0.3
        ),
        X=[[0.5, 0.0, 0.0], [0.52, 0.0, 0.0], [0.45, 1.0, 0.0]],
    )

    def tails(x):
        x = np.atleast_2d(x)
        d = x[:, 0] - 1.5
        return 150.0 * (gauss(d, 0.004) + 0.05 * gauss(d, 0.08)) * (1 - gauss(x[:, 1] - 1, 0.3))

    P["toll_tails"] = dict(
        p=Problem(
            TollRoad(),
            G((-0.5, 3.5, 61), (-2, 2, 61), (-4, 4, 61)),
            2.5,
            Quadratic([0, 0, 0], [0.0, 2.0, 0.5]),
            state_cost=tails,
        ),
        X=[[0.0, 0.0, 0.0], [0.0, 1.0, 0.5]],
    )

    def strip2(x):
        x = np.atleast_2d(x)
        return 100.0 * gauss(x[:, 0] - 1.0, 0.01) * (1 - gauss(x[:, 1] - 0.8, 0.2))

    def d_s2(x):
        return np.stack([np.full(len(x), 1.2), np.zeros(len(x))], 1)

    P["strip2d"] = dict(
        p=Problem(
            Flow(d_s2, [[0.0], [1.0]]),
            G((-0.5, 3, 71), (-2, 2, 81)),
            2.0,
            Quadratic([0, 0], [0.0, 1.0]),
            state_cost=strip2,
            temperature=0.1,
        ),
        X=[[0.0, 0.0], [0.0, 0.8], [0.0, -1.0]],
    )

    def d_phase(x):
        return np.stack([1.0 + 0.5 * x[:, 1], np.zeros(len(x))], 1)

    def gphase(x):
        x = np.atleast_2d(x)
        return 0.5 * x[:, 1] ** 2 - 4.0 * gauss(wrap(x[:, 0] - PI, 2 * PI), 0.03)

    P["phase_terminal"] = dict(
        p=Problem(
            Flow(d_phase, [[0.0], [1.0]], angle_axes=(0,)),
            G((-PI, PI, 80, True), (-2, 2, 81)),
            2.0,
            gphase,
            temperature=0.2,
        ),
        X=[[0.0, 0.0], [1.0, 0.5]],
    )

    def d_rot(x):
        return np.stack([2.0 + x[:, 1], np.zeros(len(x))], 1)

    def qrot(x):
        x = np.atleast_2d(x)
        return 50.0 * gauss(wrap(x[:, 0], 2 * PI), 0.02) * (1 - gauss(x[:, 1] - 0.5, 0.15))

    P["phase_toll"] = dict(
        p=Problem(
            Flow(d_rot, [[0.0], [1.0]], angle_axes=(0,)),
            G((-PI, PI, 80, True), (-2, 2, 81)),
            3.0,
            Quadratic([0, 0], [0.0, 0.5]),
            state_cost=qrot,
            temperature=0.3,
        ),
        X=[[-1.0, 0.0], [2.0, 0.5]],
    )
    return P


class PerTollRoad(TollRoad):
    """The toll road with s an angle (a circuit of length 2π driven at speed 2)."""

    angle_axes = (0,)

    def __init__(self):
        super().__init__(speed=2.0)


# ================= running =====================================================================
def wclass(w):
    return f"{type(w.message).__name__}: {str(w.message)[:160]}"


def is_grid_warning(w):
    return isinstance(w.message, gridlbc.GridlbcWarning)


def solve_recorded(problem, **kw):
    t0 = time.time()
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        sol = gridlbc.solve(problem, **kw)
    return sol, ws, time.time() - t0


def finer(grid, f):
    axes = []
    for a in grid.axes:
        if a.periodic:
            n = round(a.n * f)
            n += n % 2
        else:
            n = round((a.n - 1) * f) + 1
        axes.append(Axis(a.lo, a.hi, n, periodic=a.periodic))
    return Grid(axes)


def read_states(spec, t):
    X = np.array(spec["X"], float)
    if "clock" in spec:
        X[:, spec["clock"]] += t
    return X


def certify_at(problem, pol, X, t, n_samples, seed):
    T = problem.horizon
    H = T - t
    sub = problem.replace(horizon=H)
    nst = max(40, math.ceil(400 * H / T))

    def spol(y, s):
        return pol(y, s + t)

    with warnings.catch_warnings(record=True) as cw:
        warnings.simplefilter("always")
        c = gridlbc.certify(sub, spol, X, n_samples=n_samples, seed=seed, proposal=None,
                            dt=H / nst, richardson=True)  # fmt: skip
    return c, [wclass(w) for w in cw]


def run(name, spec):
    p = spec["p"]
    lam = p.temperature
    T = p.horizon
    out = dict(problem=name, grid=list(p.grid.shape), lam=lam, T=T)
    try:
        sol, ws, el = solve_recorded(p)
    except Exception as e:
        out["crash"] = f"{type(e).__name__}: {e}"
        return out
    dt = float(sol.times[1] - sol.times[0])
    out.update(seconds=el, dt=dt, warnings=[wclass(w) for w in ws],
               warned=any(is_grid_warning(w) for w in ws),
               stray=[wclass(w) for w in ws if not is_grid_warning(w)])  # fmt: skip
    print(name, p.grid.shape, f"{el:.1f}s dt={dt:.4g}", out["warnings"][:2], flush=True)
    f = spec.get("fine", 2.0)
    fp = p.replace(grid=finer(p.grid, f))
    fsol, fws, fel = solve_recorded(fp, dt=dt / 2, error_estimate=False)
    out.update(proposal=dict(grid=list(fp.grid.shape), dt=dt / 2, seconds=fel,
                             warnings=[wclass(w) for w in fws]))  # fmt: skip
    print("  proposal", fp.grid.shape, f"{fel:.1f}s", flush=True)
    pairs = []
    for t in (0.0, round(T / 2 / dt) * dt + 0.5 * dt, T - dt / 2):
        X = read_states(spec, t)
        with warnings.catch_warnings(record=True) as rw:
            warnings.simplefilter("always")
            v = sol.value(X, t)
            e = sol.error_estimate(X, t)
        n = 2000
        for attempt in range(2):
            c, cw = certify_at(p, fsol.policy, X, t, n, seed=32 + attempt)
            vs = np.atleast_1d(c.extrapolated_value)
            se = np.atleast_1d(c.extrapolated_value_se)
            if np.all(se < 0.005 * np.maximum(np.abs(vs), lam)) or attempt == 1:
                break
            n = 8000
        ess = np.atleast_1d(c.effective_sample_size)
        k = np.atleast_1d(getattr(c, "pareto_k", np.full(len(X), np.nan)))
        for i, x in enumerate(X):
            scale = max(abs(vs[i]), lam)
            row = dict(problem=name, x=list(map(float, x)), t=float(t), v=float(v[i]),
                       est=float(e[i]), vstar=float(vs[i]), se=float(se[i]), ess=float(ess[i]),
                       k=float(k[i]), n=n, raw=float(np.atleast_1d(c.optimal_value)[i]),
                       err=float(abs(v[i] - vs[i]) / scale), est_rel=float(e[i] / scale),
                       trusted=bool(ess[i] >= 400 and se[i] < 0.005 * scale),
                       warned=out["warned"],
                       read_warnings=[wclass(w) for w in rw], cert_warnings=cw)  # fmt: skip
            pairs.append(row)
            print(f"  t={t:.3f} x={np.round(x, 3)} v={v[i]:.4f} v*={vs[i]:.4f}±{se[i]:.4f} "
                  f"err={row['err']:.3f} est={row['est_rel']:.3f} ess={ess[i]:.0f} "
                  f"trusted={row['trusted']}", flush=True)  # fmt: skip
    out["pairs"] = pairs
    return out


# ================= screening: variants the default solve does not warn about ====================
VARIANTS = [(1.0, 1.0), (1.5, 1.0), (1.0, 3.0), (2.0, 2.0)]


def variant(spec, f, m, soft=0.15):
    """Grid × f, λ × m, and a soft terminal cost (a Quadratic's weights × ``soft``): the
    default warns near T of any steep terminal cost, which hides the feature's own error."""
    p = spec["p"]
    g = p.grid if f == 1.0 else finer(p.grid, f)
    tc = p.terminal_cost
    if isinstance(tc, Quadratic):
        tc = Quadratic(tc.center, np.asarray(tc.weights) * soft)
    return p.replace(grid=g, temperature=p.temperature * m, terminal_cost=tc)


def sample_states(spec, p, t, n, rng):
    lo = np.array([a.lo for a in p.grid.axes])
    hi = np.array([a.hi for a in p.grid.axes])
    X = lo + (hi - lo) * rng.random((n, len(lo)))
    X = np.vstack([read_states(spec, t), X])
    if "clock" in spec:
        X[:, spec["clock"]] = t
    return X


def screen(name, spec, budget_nodes=3.0e6):
    """Variants (grid × f, λ × m); for each one the default solve does not warn about, compare
    with a 2×-finer Δt/4 solve at 300 random states and the user's states, three times; then
    certify the worst pairs (the finer solve's policy as the proposal)."""
    rng = np.random.default_rng(32)
    res = []
    for f, m in VARIANTS:
        p = variant(spec, f, m)
        if p.grid.size > budget_nodes:
            continue
        try:
            sol, ws, el = solve_recorded(p)
        except Exception as e:  # a crash is a finding
            res.append(dict(problem=name, f=f, m=m, crash=f"{type(e).__name__}: {e}"))
            continue
        warned = any(is_grid_warning(w) for w in ws)
        dt = float(sol.times[1] - sol.times[0])
        rec = dict(problem=name, f=f, m=m, grid=list(p.grid.shape), lam=p.temperature, dt=dt,
                   seconds=el, warned=warned, warnings=[wclass(w) for w in ws])  # fmt: skip
        print(
            name,
            f,
            m,
            p.grid.shape,
            f"{el:.1f}s warned={warned}",
            [w[:140] for w in rec["warnings"]],
            flush=True,
        )
        res.append(rec)
        ff = 2.0
        while finer(p.grid, ff).size > 4 * budget_nodes and ff > 1.3:
            ff -= 0.25
        fp = p.replace(grid=finer(p.grid, ff))
        fsol, _, fel = solve_recorded(fp, dt=dt / 4, error_estimate=False)
        rec["ref"] = dict(grid=list(fp.grid.shape), dt=dt / 4, seconds=fel)
        cand = []
        T = p.horizon
        for t in (0.0, round(T / 2 / dt) * dt + 0.5 * dt, T - dt / 2):
            X = sample_states(spec, p, t, 300, rng)
            with warnings.catch_warnings(record=True) as rw:
                warnings.simplefilter("always")
                v = sol.value(X, t)
                e = sol.error_estimate(X, t)
            vr = fsol.value(X, t)
            sc = np.maximum(np.abs(vr), p.temperature)
            err = np.abs(v - vr) / sc
            ok = np.isfinite(err)
            est = e / sc
            # silent candidates: the largest errors; under-read candidates: err > 3 %, ê < ½ err
            score = np.where(ok, err if not warned else np.where(est < 0.5 * err, err, -1), -1)
            for i in np.argsort(score)[::-1][:3]:
                if score[i] > 0:
                    cand.append((float(err[i]), float(est[i]), t, X[i]))
            rec.setdefault("screen", []).append(
                dict(t=t, max_err=float(np.nanmax(err)), q90=float(np.nanquantile(err, 0.9)),
                     n_over10=int((err > 0.1).sum()), read_warnings=[wclass(w) for w in rw])
            )  # fmt: skip
            print(f"  t={t:.3f} max={np.nanmax(err):.3f} q90={np.nanquantile(err, 0.9):.3f} "
                  f">10%: {(err > 0.1).sum()}", flush=True)  # fmt: skip
        cand = [c for c in cand if c[0] > (0.05 if not warned else 0.03)]
        cand.sort(key=lambda c: -c[0])
        rec["n_candidates"] = len(cand)
        pairs = []
        for err_ref, _est, t, x in cand[:4]:
            c, cw = certify_at(p, fsol.policy, x[None], t, 4000, seed=32)
            vs = float(np.atleast_1d(c.extrapolated_value)[0])
            se = float(np.atleast_1d(c.extrapolated_value_se)[0])
            ess = float(np.atleast_1d(c.effective_sample_size)[0])
            v = float(sol.value(x[None], t)[0])
            e = float(sol.error_estimate(x[None], t)[0])
            sc = max(abs(vs), p.temperature)
            row = dict(problem=f"{name}@g{f},l{m}", x=list(map(float, x)), t=float(t), v=v,
                       est=e, vstar=vs, se=se, ess=ess, err=abs(v - vs) / sc, est_rel=e / sc,
                       err_ref=err_ref, trusted=bool(ess >= 400 and se < 0.005 * sc),
                       warned=warned, cert_warnings=cw, n=4000, est_ref=est)  # fmt: skip
            pairs.append(row)
            print(f"  CERT t={t:.3f} x={np.round(x, 3)} v={v:.4f} v*={vs:.4f}±{se:.4f} "
                  f"err={row['err']:.3f} (ref {err_ref:.3f}) est={row['est_rel']:.3f} "
                  f"ess={ess:.0f}", flush=True)  # fmt: skip
        rec["pairs"] = pairs
    return res


# ================= the linear-quadratic members: Riccati truth (round 25's lq_value) =============
def wmat(w):
    w = np.asarray(w, float)
    return np.diag(w) if w.ndim == 1 else w


def lq_spec(p):
    sysm = p.system
    d = p.grid.ndim
    tc, qc = p.terminal_cost, p.state_cost
    return dict(A=np.asarray(sysm.A, float), B=np.asarray(sysm.B, float).reshape(d, -1),
                R=np.atleast_2d(p.R), Wq=wmat(qc.weights) if qc is not None else np.zeros((d, d)),
                cq=np.asarray(qc.center, float) if qc is not None else np.zeros(d),
                WT=wmat(tc.weights), cT=np.asarray(tc.center, float), lam=p.temperature,
                T=p.horizon)  # fmt: skip


def lq_screen(name, spec, inner=0.5):
    """Default solves of an LQ member and its variants against Riccati at 400 states in the inner
    ``inner`` of the box (where the box's walls hardly matter) and the user's states."""
    from strangers_round25 import lq_value

    rng = np.random.default_rng(32)
    res = []
    for f, m, soft in ((1.0, 1.0, 1.0), (1.0, 1.0, 0.15), (1.0, 3.0, 1.0), (1.5, 1.0, 0.15)):
        p = variant(spec, f, m, soft)
        sol, ws, el = solve_recorded(p)
        warned = any(is_grid_warning(w) for w in ws)
        dt = float(sol.times[1] - sol.times[0])
        lqs = lq_spec(p)
        lo = np.array([a.lo for a in p.grid.axes])
        hi = np.array([a.hi for a in p.grid.axes])
        mid, half = (lo + hi) / 2, (hi - lo) / 2 * inner
        rows = []
        T = p.horizon
        for t in (0.0, round(T / 2 / dt) * dt + 0.5 * dt, T - dt / 2):
            X = np.vstack([read_states(spec, t), mid + half * (2 * rng.random((400, len(lo))) - 1)])
            with warnings.catch_warnings(record=True) as rw:
                warnings.simplefilter("always")
                v = sol.value(X, t)
                e = sol.error_estimate(X, t)
            vs = lq_value(lqs, X, t)
            sc = np.maximum(np.abs(vs), p.temperature)
            err, est = np.abs(v - vs) / sc, e / sc
            for i in range(len(X)):
                rows.append(dict(problem=f"{name}@g{f},l{m},s{soft}", x=X[i].tolist(), t=float(t),
                                 v=float(v[i]), est=float(e[i]), vstar=float(vs[i]), se=0.0,
                                 ess=np.inf, err=float(err[i]), est_rel=float(est[i]),
                                 trusted=True, warned=warned, truth="riccati",
                                 read_warnings=len(rw)))  # fmt: skip
            print(f"{name} g{f} l{m} s{soft} warned={warned} t={t:.3f} max={err.max():.3f} "
                  f">10%={int((err > 0.1).sum())} under={int(((err > 0.02) & (est < 0.5 * err)).sum())}"
                  f"/{len(X)}", flush=True)  # fmt: skip
        res.append(dict(problem=f"{name}@g{f},l{m},s{soft}", grid=list(p.grid.shape),
                        lam=p.temperature, dt=dt, seconds=el, warned=warned,
                        warnings=[wclass(w) for w in ws], pairs=rows))  # fmt: skip
    return res


def run_tol(name, spec, row):
    """A silent pair: solve(tol=0.05, states=[x]) and compare with the truth."""
    p = spec["p"]
    if "@g" in row["problem"]:
        parts = row["problem"].split("@g")[1].replace(",l", " ").replace(",s", " ").split()
        p = variant(spec, *map(float, parts))
    x = np.array(row["x"])
    sol, ws, el = solve_recorded(p, tol=0.05, states=[x])
    v = float(sol.value(x[None], row["t"])[0])
    err = abs(v - row["vstar"]) / max(abs(row["vstar"]), p.temperature)
    return dict(problem=row["problem"], x=row["x"], t=row["t"], v=v, vstar=row["vstar"], err=err,
                seconds=el, grid=list(sol.grid.shape) if hasattr(sol, "grid") else None,
                within=err <= 0.05, warnings=[wclass(w) for w in ws])  # fmt: skip


def table():
    rows, solves = [], []
    for f in sorted(OUT.glob("*.json")):
        if f.name.startswith("tol_"):
            continue
        data = json.loads(f.read_text())
        for d in data if isinstance(data, list) else [data]:
            if "f" in d:
                d = dict(d, problem=f"{d['problem']}@g{d['f']},l{d['m']}")
            solves.append(d)
            rows += d.get("pairs", [])
    tr = [r for r in rows if r["trusted"]]
    print(f"problems {len(solves)}, pairs {len(rows)}, trusted {len(tr)}")
    big = [r for r in tr if r["err"] > 0.10]
    silent = [r for r in big if not r["warned"]]
    under = [r for r in tr if r["err"] > 0.02 and r["est_rel"] < 0.5 * r["err"]]
    cover = sum(r["est_rel"] >= 0.5 * r["err"] for r in tr)
    print(
        f">10%: {len(big)}  SILENT: {len(silent)}  under: {len(under)}  ê≥½err: {cover}/{len(tr)}"
    )
    for d in solves:
        pr = [r for r in d.get("pairs", []) if r["trusted"]]
        worst = max((r["err"] for r in pr), default=float("nan"))
        print(f"{d['problem']:24s} warned={d.get('warned')} trusted={len(pr)}/"
              f"{len(d.get('pairs', []))} worst={worst:.3f} {d.get('crash', '')}"
              f" stray={len(d.get('stray', []))}")  # fmt: skip
    for tag, lst in (("SILENT", silent), ("UNDER", under)):
        for r in lst:
            print(tag, r["problem"], np.round(r["x"], 3), f"t={r['t']:.4f} v={r['v']:.4f} "
                  f"v*={r['vstar']:.4f}±{r['se']:.4f} err={r['err']:.3f} "
                  f"est={r['est_rel']:.3f} ess={r['ess']:.0f} warned={r['warned']}")  # fmt: skip
    return silent


def main(argv):
    OUT.mkdir(parents=True, exist_ok=True)
    P = problems()
    if "--list" in argv:
        for k, s in P.items():
            print(k, s["p"].grid.shape, s["p"].temperature, s["p"].horizon)
    if "--run" in argv:
        names = [a for a in argv if a in P] or list(P)
        for k in names:
            f = OUT / f"{k}.json"
            if f.exists() and "--force" not in argv:
                continue
            t0 = time.time()
            res = run(k, P[k])
            res["wall"] = time.time() - t0
            f.write_text(json.dumps(res, indent=1, default=lambda o: np.asarray(o).tolist()))
    if "--screen" in argv:
        names = [a for a in argv if a in P] or list(P)
        for k in names:
            f = OUT / f"screen_{k}.json"
            if f.exists() and "--force" not in argv:
                continue
            f.write_text(
                json.dumps(screen(k, P[k]), indent=1, default=lambda o: np.asarray(o).tolist())
            )
    if "--lq" in argv:
        for k in ("two_di_cold", "coupled_di", "pm2_cold"):
            (OUT / f"lq_{k}.json").write_text(
                json.dumps(lq_screen(k, P[k]), default=lambda o: np.asarray(o).tolist())
            )
    if "--table" in argv:
        table()
    if "--tol" in argv:
        for r in table():
            res = run_tol(r["problem"], P[r["problem"].split("@")[0]], r)
            print("TOL", res, flush=True)
            f = OUT / f"tol_{r['problem']}_{r['t']:.3f}_{'_'.join(map(str, r['x']))}.json"
            f.write_text(json.dumps(res, indent=1, default=lambda o: np.asarray(o).tolist()))


if __name__ == "__main__":
    main(sys.argv[1:])
