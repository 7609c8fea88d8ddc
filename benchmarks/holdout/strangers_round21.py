"""Stranger round 21: kinds of problem rounds 3–20 did not cover, posed with the public API only
(SPEC §1–3, §6, §9–10; README "Your own system").

Kinds (none covered by rounds 3–20):

1. 1-D problems: a single integrator on a line (a quadratic goal; a goal narrower than a cell), a
   nonlinear flow on a circle (periodic), a stiff OU on a line, first exit from an interval (warm
   and cold, an exit between nodes), the average cost on a circle with a rotation.
2. Costs that put v at or below zero: a terminal cost shifted by −50 and by +1000, and shifted so
   that v ≈ 0 at the judged states (the relative measure is then max(|v|, λ)). A negative state
   cost is refused (round 16 recorded it; its message says to add a constant).
3. Large temperatures: λ = 5 in a box far smaller than the noise's reach (2-D, reflecting walls
   all the time), λ = 30 in 3-D, λ = 10 with a nonlinear drift.
4. 5-D problems on coarse grids (13⁵): two point masses and a leaky integrator (Riccati), and a
   5-D single integrator with separable cosine costs.
5. Options a user passes: dt 5× the default, store_every = 7 read between stored slices,
   dtype float32 at λ = 0.02, method="implicit" on a rotation, fitting=None at λ = 0.05, the
   "fast" and "reference" presets.
6. ``gridlbc.solve_many`` components read individually at t = 0 and late (t = 0.9 T) near the
   other component's goal, and ``combine`` of them late.

Layout as round 20 (``P21``: name → (builder, states, truth, tag, t)), whose ``quick20``,
``truth_run`` and ``table`` run this round's entries (module globals pointed at ``P21`` and this
round's results folder); ``OPTS`` gives an entry's solve options, or its ``solve_many`` source.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round21.py NAME [NAME ...]
    ... --truth NAME ...    (the truth alone)   ... --solve NAME ...   ... --table

Truths, none from the library's grid solvers:

- "1-D": my own Crank–Nicolson solve (four backward-Euler half steps first, z renormalised each
  step) of ∂τ z = D z″ + a z′ − (q/λ) z with reflecting (Neumann) or periodic ends, on 8001 and
  16001 nodes (τ/4000 and τ/8000 steps); ± their difference. Separable d-D problems (a
  single integrator, each axis's costs and drift its own) sum the axes' 1-D values.
- "exact": first exit in 1-D with constant coefficients: (q/λ) z = a z′ + D z″ in closed form
  (two exponentials), z = e^{−g_E/λ} at the exit points.
- "eig": the average cost on a circle: the principal eigenvalue of my periodic finite-difference
  operator D z″ + a z′ − (q/λ) z (shift-invert), c = −λ μ, on 4000 and 8000 nodes.
- "ricc": round 20's Riccati (``lq_exact``) over the remaining horizon; "mix": round 20's
  exact combination −λ log Σ w_i e^{−v_i/λ} of Riccati values.
- "cert": the pendulum and cart entries reuse round 20's stored certificates (same problem,
  states and time: ``r20_truth``); ``pend_q0_*`` are certified here with round 20's ``cert``.

    ... --compact   (the table below)   ... --avg   (the average cost on the circle)
    ... --named NAME "x1,x2;y1,y2"   (v, ê and the truth at the states a warning names)

RESULTS (library of commit 6918083, 2026-12-06, one thread; ``--table``/``--compact``): 80
(problem, t) entries, 249 (problem, state, t) pairs (about 45 problems), and 4 average costs.
ê ≥ ½|v − v*| at 241 / 249. Nothing refused (a negative state cost is, with a clear message).

- SILENT (> 10 % off, no GridlbcWarning): 22 pairs, two mechanisms, both late in a task:

  1. The default step of a problem without drift and without a state cost is T/10 (the fitted
     scheme's ``min_steps``), and the last step or two before T carry a time-step error that
     no part of the warning reads: ẋ = u with a quadratic goal (g = 4(x₀ − 0.5)² + 2x₁²,
     λ = 0.3, T = 2, 101²) is exact at t = 0 (≤ 0.3 %), +4.7/+5.0/+9.7 % at the last stored slice
     t = 1.8, and +18.5/+13.4/+26.9 % at t = 1.9 (``si2_t19``; +15/+10/+19 % at 1.95), in 1-D
     (``si1_long_t285``: T = 3, Δt = 0.3, +32/+32/+46 %; ``si1_quad_t95`` +10.8 %), in 3-D
     (``si3_q0_t19``: +14/+12/+25 %), and for ``solve_many`` components and their combination
     (``sim0_t19``: −41 % and +20 %; ``sim_comb_t19`` +20 %). A 2× grid changes nothing
     (201²: the same +18.5/+13.4/+26.9 %); Δt/2 gives +3.4/+2.5/+5.0 %, Δt/4 +0.8/+0.6/+1.2 %,
     Δt/10 ≤ 0.2 % (si1_long at t = 2.85: 31.8/45.8 % → 5.4/7.8 → 1.3/1.8 → 0.2/0.3 %). The
     estimate at the user's state holds (ê/err 0.74–0.97) through the whole remaining task's
     certificate; its grid terms do not: the embedded difference at t = 1.9 is 3.5/3.2/5.1 % of
     |v| after division by 2^q − 1 with q = 1.94, the order observed over the calibration states
     at t = 0 (a spatial order; the late error is the step's), and the pair reads ≤ 0.1 %. The
     warning judges t = 0 and the late time T − 8Δt = 0.4 (``estimate.late_time``), both before
     the error appears, and its confirmation needs the grid terms above 5 % before it samples
     the certificate (``confirmed_locally``: min(grid terms, max(γ, local certificate))).
     With a drift or a state cost the default step is shorter and the same reads are fine
     (``pm_q0_t19`` ≤ 1.2 %, ``lq_t292`` ≤ 1.3 %, ``pend_q0_t19`` ≤ 1.1 %).
  2. ``store_every`` large enough that t is read between two stored slices far apart: the
     point mass LQ of round 20 with ``store_every=19`` (its 19 steps: only t = 0 and T kept) read
     at t = 1.5: +29/−27/−16 % (``opt_store19``), at 0.5: +13 %, at 2.7: −27/−21 %; ê/err
     0.57–3.5 except one under-read below. The embedded solves interpolate their slices alike
     (embedded term 0.05–0.7 %), the estimate at the state comes from the whole task's
     certificate, and the warning's confirmation never runs (gated by the grid terms as above).
     store_every = 1, 3, 5, 10 at t = 1.5: ≤ 0.4, 1.0, 1.4, 2.1 %; 19: 29 %. (store_every = 10
     read at t = 0.8 and 2.2, between 1.58 and T, is 17–24 % off and warned.)

- Under-reads (ê < ½ err, err > 2 %): 3 pairs, minor: ``opt_store19_late`` (0, 0) −3.0 % with
  ê 0.9 % (0.30); ``sim0_t19``/``sim_comb_t19`` (1, 0.5) +2.2 % with ê 1.1 % (0.49).
- Warned and true: the 1-D goal 0.4 cell wide (+99…+147 %, S), the hot needle (λ = 5, +32…+41 %,
  S), fitting=None at λ = 0.05 and with float32 at λ = 0.1 (−10…−64 %), dt = 0.4 on the
  pendulum (−43…−50 %) and 0.5 on the cart (−3…−14 %), circ5 (5-D periodic 12⁵, +14 %), the
  solve_many component 2.5 from its goal at λ = 0.08 (−23 %, ê 266 %), fe1_frozen (first exit
  at λ = 0.005, −34 % next to the exit, ê ≫ err), the average cost at λ = 0.02 (c −19.8 %,
  ê 26 %). At t = 1.8 that component's far state underflows (v = +inf, UnderflowWarning).
- Offsets: g + 1000 and g − 50 leave the value's absolute error unchanged; g − 50 makes v cross
  zero inside the box and the solve then warns where |v| ≈ 0 ((−3.32, −2.22): |v| 0.50 against
  0.79 from Riccati, which ignores the wall there), g + 1000 and g + 0 do not; shifted so that
  v(0, 0) = 0 at λ = 0.05 it warns at (−0.2, −0.18), true in the relative measure (+26.5 % of
  max(|v*|, λ), an absolute 0.019 = 0.37 λ); ``fe1_reward`` (exit cost −3) likewise at −0.26
  (−26 %). Relative errors at states where v ≈ 0 are judged against λ, so these are true.
- False alarms (warned, every tabled state within 3 %): lq5_17 (17⁵; at the state it names
  +0.9 % against ê 39 %), si5 (13⁵; +0.5 % against 11 %), pend_q0 (+1.4 % against 21 % at
  (1.948, −5.28), certificate ESS ≈ 2000), spin_store6, pend_mars_dt, si1_coarse (21 nodes),
  fe1_reward / lq_minus50 / lq_cold_vzero (the offsets above, true where named), the solve_many
  combinations (their components' true warnings). 5-D estimates over-read 5–25× (lq5 at the
  origin: +5.3 % with ê 125 %).
- Also seen: solve_many at λ = 0.08 (``mc0``) warns "the optimal control moves the state by
  93260982 cells per step … Pass dt ≤ 3.3e-08" (and 5.9e9 for the second), with two
  RuntimeWarnings "invalid value encountered in add": the control-step check reads a component
  whose z underflows at 2 of 256 states (v = +inf); float32 with fitting=None at λ = 0.1 says
  "2034762264988 cells per step" and "up to inf per cell". The advice is not usable.
- Fine and quiet: 1-D quadratic/stiff OU/first exits (warm, between nodes), hot (λ = 5 in a box
  of 0.5, λ = 30 in 3-D, λ = 10 nonlinear: ≤ 0.8 %), 5-D single integrator without q, the
  options float32 (λ = 0.02), dt = 2× default, the "fast" preset, the average cost on the
  circle (warm, fast rotation: ≤ 0.2 %).

AFTER (library of commit db1831f, the same day: a solve with a horizon is also confirmed at
T − Δs/2, the middle of its last stored interval, and read at t > 0 the embedded difference is
divided by 2^q − 1 with the order observed at that time, ``EmbeddedEstimate.order_at``):
ê ≥ ½|v − v*| at 243 / 249. Silent: 6 pairs, all mechanism 2 (``opt_store19*``: only t = 0
and T stored, read between them; a user's ``store_every``, not the default). Mechanism 1 warns
on every entry, naming the last step (si2 near (2, −0.04) at t = 1.9; si1_long, si1_quad,
si3_q0, sim0 likewise). Under-reads: 1 (``opt_store19_late`` (0, 0), as before). The new late
warnings, each checked at the state and time it names (Riccati, or this round's 1-D truths):
pm_q0 7.2 % (t = 1.92), spin 13.3 % (1.97), the "fast" preset's spin 22.6 % (1.96), lq_cold
7.0 % and its float32 twin 7.1 % (2.92), lq_warm01 6.9 % (2.92), opt_dt5 10 % (2.85), ou1_stiff
5.6 % (1.99), tiny_hot 35 % low (0.997), nl_hot10 68 % high (0.981), hot30_3d 27 % low (0.497):
all true (the hot ones, quiet and within 0.8 % at t = 0, are far off in their last step);
si5_q0 (13⁵) at (0.167, 0.167, 0, 0.167, 0.167), t = 0.95: 3.8 %, a false alarm (ê 62 %: the
5-D estimates over-read). The "false alarm" tally of ``--table`` counts these solves, whose
tabled states (mostly at t = 0) are within 3 %. Since commit 1f54625 the control-step check reads
the better half of the nodes: mc0's components read 28.5 cells per step there (9·10⁷ over every
node, with the advice dt ≤ 3·10⁻⁸), below the threshold, and their combination's estimate no
longer raises a RuntimeWarning where a component without weight underflowed.
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import strangers_round20 as r20
from strangers_round19b import Affine, one
from strangers_round20 import PM_A, S, lq_exact, mix, pm_B, ricc

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import LinearSystem, PointMass, SingleIntegrator

OUT = Path("/work/main/benchmarks/holdout/strangers_round21_results")  # gitignored there
PI = math.pi


# ---------------- my own 1-D references ------------------------------------------------------------
def _operator(x, h, a, D, q, lam, periodic):
    n = len(x)
    main = -2 * D / h**2 - q / lam
    up = D / h**2 + a / (2 * h)
    dn = D / h**2 - a / (2 * h)
    L = sp.lil_matrix((n, n))
    for j in range(n):
        L[j, j] = main[j]
        if periodic:
            L[j, (j + 1) % n] += up[j]
            L[j, (j - 1) % n] += dn[j]
        elif j == 0:
            L[j, 1] += up[j] + dn[j]  # ghost z_{-1} = z_1: reflecting wall
        elif j == n - 1:
            L[j, n - 2] += up[j] + dn[j]
        else:
            L[j, j + 1] += up[j]
            L[j, j - 1] += dn[j]
    return L.tocsc()


def cn1d(lo, hi, tau, lam, a, D, q, g, periodic=False, n=8001, steps=4000):
    """v(x) of ∂τ z = D z″ + a z′ − (q/λ) z, z(0) = e^{−g/λ}, at τ (the remaining horizon)."""
    if periodic:
        x = lo + (hi - lo) * np.arange(n) / n
        h = (hi - lo) / n
    else:
        x = np.linspace(lo, hi, n)
        h = x[1] - x[0]
    av, Dv, qv = (np.broadcast_to(np.asarray(f(x), float), x.shape) for f in (a, D, q))
    L = _operator(x, h, av, Dv, qv, lam, periodic)
    gv = np.asarray(g(x), float)
    z, logs = np.exp(-(gv - gv.min()) / lam), -gv.min() / lam
    eye = sp.identity(len(x), format="csc")
    if tau > 0:
        dt = tau / steps
        be = spla.splu((eye - 0.5 * dt * L).tocsc())
        for _ in range(4):
            z = be.solve(z)
            m = z.max()
            z, logs = z / m, logs + math.log(m)
        A = spla.splu((eye - 0.5 * dt * L).tocsc())
        Bm = (eye + 0.5 * dt * L).tocsr()
        for _ in range(steps - 2):
            z = A.solve(Bm @ z)
            m = z.max()
            z, logs = z / m, logs + math.log(m)
    v = -lam * (np.log(np.maximum(z, 1e-300)) + logs)
    if periodic:
        xx, vv, P = np.append(x, hi), np.append(v, v[0]), hi - lo
        return lambda y: np.interp(lo + np.mod(np.asarray(y) - lo, P), xx, vv)
    return lambda y: np.interp(np.asarray(y), x, v)


def one_d(axes_specs, t=0.0):
    """Separable truth: axes_specs[i] = dict(lo, hi, T, lam, a, D, q, g, periodic); v = Σ v_i."""

    def truth(X):
        X = np.asarray(X, float)
        res = []
        for n, steps in ((8001, 4000), (16001, 8000)):
            v = np.zeros(len(X))
            for i, s in enumerate(axes_specs):
                s = dict(s)
                tau = s.pop("T") - t
                v += cn1d(tau=tau, n=n, steps=steps, **s)(X[:, i])
            res.append(v)
        return res[1], np.abs(res[1] - res[0]), {"v_coarse": res[0].tolist()}

    return truth


def exit1d(lo, hi, lam, a, D, q, gE_lo, gE_hi):
    """First exit from (lo, hi) with constant a, D, q: z = A e^{m₊(x − hi)} + B e^{m₋(x − lo)},
    m± the roots of D m² + a m − q/λ = 0 (each term at most 1 on [lo, hi]: well conditioned),
    z(lo) = e^{−gE_lo/λ}, z(hi) = e^{−gE_hi/λ}. Exact."""

    def truth(X):
        X = np.asarray(X, float)[:, 0]
        disc = math.sqrt(a * a + 4 * D * q / lam)
        mp, mm = (-a + disc) / (2 * D), (-a - disc) / (2 * D)
        zl, zh = math.exp(-gE_lo / lam), math.exp(-gE_hi / lam)
        M = np.array([[math.exp(mp * (lo - hi)), 1.0], [1.0, math.exp(mm * (hi - lo))]])
        A, B = np.linalg.solve(M, [zl, zh])
        z = A * np.exp(mp * (X - hi)) + B * np.exp(mm * (X - lo))
        return -lam * np.log(z), np.zeros(len(X)), {}

    return truth


def eig1d(lo, hi, lam, a, D, q):
    """Average cost on the circle [lo, hi): c = −λ μ, μ the principal eigenvalue."""

    def solve(n):
        x = lo + (hi - lo) * np.arange(n) / n
        h = (hi - lo) / n
        av, Dv, qv = (np.broadcast_to(np.asarray(f(x), float), x.shape) for f in (a, D, q))
        L = _operator(x, h, av, Dv, qv, lam, True)
        sigma = -qv.min() / lam + 1e-3
        mu = spla.eigs(L, k=1, sigma=sigma, which="LM", return_eigenvectors=False)
        return float(-lam * mu[0].real)

    def truth(X):
        c1, c2 = solve(4000), solve(8000)
        return np.array([c2]), np.array([abs(c2 - c1)]), {"c_coarse": c1}

    return truth


def shifted(truth, shift):
    def f(X):
        v, u, e = truth(X)
        return np.asarray(v) + shift, u, e

    return f


# ---------------- 1. 1-D problems --------------------------------------------------------------------
Z = lambda x: np.zeros(len(x))  # noqa: E731


def si1_quad():
    grid = Grid([Axis(-2, 2, 201)])
    return Problem(
        SingleIntegrator(), grid, 1.0, terminal_cost=Quadratic([0.5], [4.0]), temperature=0.3
    )


def si1_long():
    return si1_quad().replace(horizon=3.0)


def si2_quad():
    """ẋ = u in 2-D (101², [−2, 2]²), g = 4 (x₀ − 0.5)² + 2 x₁², λ = 0.3, T = 2."""
    return Problem(
        si_d(2),
        Grid([Axis(-2, 2, 101)] * 2),
        2.0,
        terminal_cost=Quadratic([0.5, 0.0], np.diag([4.0, 2.0])),
        temperature=0.3,
    )


def si2_truth(t):
    return ricc(
        np.zeros((2, 2)),
        np.eye(2),
        1.0,
        np.zeros((2, 2)),
        [0, 0],
        np.diag([4.0, 2.0]),
        [0.5, 0.0],
        0.3,
        2.0 - t,
    )


def pm_q0():
    """A point mass with a terminal cost only (no state cost: the default step is T/10)."""
    return Problem(
        PointMass(),
        Grid([Axis(-4, 4, 101), Axis(-6, 6, 101)]),
        2.0,
        terminal_cost=Quadratic([1.0, 0.0], np.diag([4.0, 1.0])),
        temperature=0.3,
    )


def pm_q0_truth(t):
    return ricc(
        PM_A, pm_B(), 1.0, np.zeros((2, 2)), [0, 0], np.diag([4.0, 1.0]), [1.0, 0.0], 0.3, 2.0 - t
    )


def si3_q0():
    return Problem(
        si_d(3),
        Grid([Axis(-2, 2, 41)] * 3),
        2.0,
        terminal_cost=Quadratic([0.5, 0.0, -0.5], np.diag([4.0, 2.0, 1.0])),
        temperature=0.3,
    )


def si3_truth(t):
    return ricc(
        np.zeros((3, 3)),
        np.eye(3),
        1.0,
        np.zeros((3, 3)),
        [0, 0, 0],
        np.diag([4.0, 2.0, 1.0]),
        [0.5, 0.0, -0.5],
        0.3,
        2.0 - t,
    )


def pend_q0():
    """The catalogue pendulum (damping 0.3) with a terminal cost only, λ = 0.3, T = 2."""
    return Problem(
        r20.Pendulum(damping=0.3),
        Grid([Axis(-PI, PI, 100, periodic=True), Axis(-8.0, 8.0, 101)]),
        2.0,
        terminal_cost=lambda x: 5.0 * (1 - np.cos(x[:, 0])) + 0.25 * x[:, 1] ** 2,
        temperature=0.3,
    )


SI1_QUAD = dict(
    lo=-2, hi=2, T=1.0, lam=0.3, a=Z, D=lambda x: 0.15, q=Z, g=lambda x: 4 * (x - 0.5) ** 2
)


def _narrow_g(x):
    x = np.asarray(x)
    return 0.5 * x**2 + 2.0 * (1 - np.exp(-((x - 0.313) ** 2) / (2 * 0.008**2)))


def si1_narrow():
    """A goal 0.4 cell wide (w = 0.008, h = 0.02) 0.35 cell off a node at λ = 0.1."""
    grid = Grid([Axis(-2, 2, 201)])
    return Problem(
        SingleIntegrator(),
        grid,
        0.5,
        terminal_cost=lambda x: _narrow_g(x[:, 0]),
        temperature=0.1,
    )


SI1_NARROW = dict(lo=-2, hi=2, T=0.5, lam=0.1, a=Z, D=lambda x: 0.05, q=Z, g=_narrow_g)


def circ_drift(x):
    return 2.0 * np.sin(x)


def ou1_circle():
    """ẋ = 2 sin x + u on a circle (unstable at 0, the goal), λ = 0.2, T = 3."""
    sysm = Affine(1, lambda x: circ_drift(x), one(), (0,), angle_axes=(0,), name="circle")
    grid = Grid([Axis(-PI, PI, 128, periodic=True)])
    return Problem(
        sysm,
        grid,
        3.0,
        terminal_cost=lambda x: 2.0 * (1 - np.cos(x[:, 0])),
        state_cost=lambda x: 0.5 * (1 - np.cos(x[:, 0])),
        temperature=0.2,
    )


OU1_CIRCLE = dict(
    lo=-PI,
    hi=PI,
    T=3.0,
    lam=0.2,
    a=circ_drift,
    D=lambda x: 0.1,
    q=lambda x: 0.5 * (1 - np.cos(x)),
    g=lambda x: 2.0 * (1 - np.cos(x)),
    periodic=True,
)


def ou1_stiff():
    """ẋ = −8 x + u on [−3, 3], λ = 1, q = 4 (x − 0.7)², g = 0, T = 2 (a stiff OU)."""
    sysm = LinearSystem(np.array([[-8.0]]), np.array([[1.0]]))
    grid = Grid([Axis(-3, 3, 121)])
    return Problem(
        sysm,
        grid,
        2.0,
        terminal_cost=lambda x: 0 * x[:, 0],
        state_cost=Quadratic([0.7], [4.0]),
        temperature=1.0,
    )


OU1_STIFF = dict(
    lo=-3,
    hi=3,
    T=2.0,
    lam=1.0,
    a=lambda x: -8 * x,
    D=lambda x: 0.5,
    q=lambda x: 4 * (x - 0.7) ** 2,
    g=Z,
)


def fe1(lam, lo_exit=-1.0, hi_exit=1.0, n=121):
    """First exit from (lo_exit, hi_exit) in the box [−1.2, 1.2]: left exit costs 2, right 0,
    a drift −1 against the cheap door, q = 0.5."""
    sysm = Affine(1, lambda x: -1.0 + 0 * x, one(), (0,), name="line")
    grid = Grid([Axis(-1.2, 1.2, n)])
    return Problem(
        sysm,
        grid,
        None,
        state_cost=lambda x: 0.5 + 0 * x[:, 0],
        temperature=lam,
        exit=lambda x: (x[:, 0] <= lo_exit) | (x[:, 0] >= hi_exit),
        exit_cost=lambda x: np.where(x[:, 0] < 0, 2.0, 0.0),
    )


def fe1_truth(lam, lo_exit=-1.0, hi_exit=1.0):
    return exit1d(lo_exit, hi_exit, lam, -1.0, lam / 2, 0.5, 2.0, 0.0)


def avg1(lam=0.3, rate=1.5):
    """The average cost on a circle: ẋ = rate + u, q = 1.2 − cos x, λ = 0.3 (128 nodes)."""
    sysm = Affine(1, lambda x: rate + 0 * x, one(), (0,), angle_axes=(0,), name="rot")
    grid = Grid([Axis(-PI, PI, 128, periodic=True)])
    return Problem(
        sysm, grid, "average", state_cost=lambda x: 1.2 - np.cos(x[:, 0]), temperature=lam
    )


AVG = {
    "avg1": (0.3, 1.5),
    "avg1_cold": (0.02, 1.5),
    "avg1_fast": (0.3, 12.0),
    "avg1_cold_fast": (0.02, 12.0),
}


# ---------------- 2. offsets: v ≤ 0, v ≈ 0 -------------------------------------------------------
LQ = dict(m=2.0, Wq=np.diag([1.0, 0.1]), cq=[-0.5, 0.0], WT=np.diag([4.0, 1.0]), cT=[1.0, 0.0])


def lq_shift(shift, lam=0.5):
    grid = Grid([Axis(-4, 4, 101), Axis(-6, 6, 101)])
    gq = Quadratic(LQ["cT"], LQ["WT"])
    return Problem(
        PointMass(mass=LQ["m"]),
        grid,
        3.0,
        terminal_cost=lambda x: np.asarray(gq(x)) + shift,
        state_cost=Quadratic(LQ["cq"], LQ["Wq"]),
        temperature=lam,
    )


def lq_truth(t, shift=0.0, lam=0.5, T=3.0):
    return shifted(
        ricc(PM_A, pm_B(LQ["m"]), 1.0, LQ["Wq"], LQ["cq"], LQ["WT"], LQ["cT"], lam, T - t), shift
    )


X_LQ = S((0.0, 0.0), (1.5, 1.0), (-2.0, -1.0))
# v of the unshifted cold problem (λ = 0.05) at X_LQ[0]: the shift that puts v there at 0
V0_COLD = float(
    lq_exact(PM_A, pm_B(2.0), 1.0, LQ["Wq"], LQ["cq"], LQ["WT"], LQ["cT"], 0.05, 3.0)(X_LQ[:1])[0]
)


def si_d(d):
    """ẋ = u in d dimensions (B = I)."""
    return LinearSystem(np.zeros((d, d)), np.eye(d))


# ---------------- 3. hot -------------------------------------------------------------------------
def tiny_hot():
    """λ = 5 in [0, 0.5]²: the noise crosses the box 4× in a unit of time (σ√T = 2.2)."""
    grid = Grid([Axis(0, 0.5, 51), Axis(0, 0.5, 51)])
    return Problem(
        si_d(2),
        grid,
        1.0,
        terminal_cost=lambda x: 30 * (x[:, 0] - 0.1) ** 2 + 20 * np.sin(6 * x[:, 1]) ** 2,
        state_cost=lambda x: 40 * (x[:, 0] - 0.4) ** 2 + 10 * x[:, 1],
        temperature=5.0,
    )


TINY_HOT = [
    dict(
        lo=0,
        hi=0.5,
        T=1.0,
        lam=5.0,
        a=Z,
        D=lambda x: 2.5,
        q=lambda x: 40 * (x - 0.4) ** 2,
        g=lambda x: 30 * (x - 0.1) ** 2,
    ),
    dict(
        lo=0,
        hi=0.5,
        T=1.0,
        lam=5.0,
        a=Z,
        D=lambda x: 2.5,
        q=lambda x: 10 * x,
        g=lambda x: 20 * np.sin(6 * x) ** 2,
    ),
]


def hot30_3d():
    """λ = 30 on [−1, 1]³ (41³), T = 0.5, separable costs steep enough to matter."""
    grid = Grid([Axis(-1, 1, 41)] * 3)
    return Problem(
        si_d(3),
        grid,
        0.5,
        terminal_cost=lambda x: (
            200 * (x[:, 0] - 0.5) ** 2 + 100 * np.abs(x[:, 1]) + 50 * x[:, 2] ** 4
        ),
        state_cost=lambda x: 300 * x[:, 0] ** 2 + 100 * (1 + np.cos(3 * x[:, 2])),
        temperature=30.0,
    )


HOT30 = [
    dict(
        lo=-1,
        hi=1,
        T=0.5,
        lam=30.0,
        a=Z,
        D=lambda x: 15.0,
        q=lambda x: 300 * x**2,
        g=lambda x: 200 * (x - 0.5) ** 2,
    ),
    dict(lo=-1, hi=1, T=0.5, lam=30.0, a=Z, D=lambda x: 15.0, q=Z, g=lambda x: 100 * np.abs(x)),
    dict(
        lo=-1,
        hi=1,
        T=0.5,
        lam=30.0,
        a=Z,
        D=lambda x: 15.0,
        q=lambda x: 100 * (1 + np.cos(3 * x)),
        g=lambda x: 50 * x**4,
    ),
]


def nl_drift(x):
    return -6.0 * np.sin(2.0 * x)


def nl_hot10():
    """λ = 10, ẋᵢ = −6 sin 2xᵢ + uᵢ on [−1.5, 1.5]² (101²), costs per axis, T = 1."""
    sysm = Affine(2, nl_drift, lambda x: np.ones((len(x), 2)), (0, 1), name="nl2")
    grid = Grid([Axis(-1.5, 1.5, 101)] * 2)
    return Problem(
        sysm,
        grid,
        1.0,
        terminal_cost=lambda x: 40 * (x[:, 0] - 1.0) ** 2 + 30 * (x[:, 1] + 0.5) ** 2,
        state_cost=lambda x: 20 * x[:, 0] ** 2 + 15 * (1 - np.cos(2 * x[:, 1])),
        temperature=10.0,
    )


NL_HOT = [
    dict(
        lo=-1.5,
        hi=1.5,
        T=1.0,
        lam=10.0,
        a=nl_drift,
        D=lambda x: 5.0,
        q=lambda x: 20 * x**2,
        g=lambda x: 40 * (x - 1) ** 2,
    ),
    dict(
        lo=-1.5,
        hi=1.5,
        T=1.0,
        lam=10.0,
        a=nl_drift,
        D=lambda x: 5.0,
        q=lambda x: 15 * (1 - np.cos(2 * x)),
        g=lambda x: 30 * (x + 0.5) ** 2,
    ),
]


# ---------------- 4. 5-D ----------------------------------------------------------------------------
A5 = np.zeros((5, 5))
A5[0, 1] = A5[2, 3] = 1.0
A5[4, 4] = -0.5
B5 = np.zeros((5, 3))
B5[1, 0] = B5[3, 1] = B5[4, 2] = 1.0
W5q = np.diag([1.0, 0.1, 1.0, 0.1, 1.0])
W5T = np.diag([3.0, 0.5, 3.0, 0.5, 2.0])
C5T = np.array([0.5, 0.0, -0.5, 0.0, 0.3])


def lq5(n=13):
    grid = Grid(
        [Axis(-3, 3, n), Axis(-4, 4, n), Axis(-3, 3, n), Axis(-4, 4, n), Axis(-2.5, 2.5, n)]
    )
    return Problem(
        LinearSystem(A5, B5),
        grid,
        1.5,
        terminal_cost=Quadratic(C5T, W5T),
        state_cost=Quadratic(np.zeros(5), W5q),
        temperature=0.5,
    )


def si5():
    grid = Grid([Axis(-1, 1, 13)] * 5)
    return Problem(
        si_d(5),
        grid,
        1.0,
        terminal_cost=lambda x: 2 * np.sum((x - 0.2) ** 2, axis=1),
        state_cost=lambda x: 0.5 * np.sum(1 - np.cos(3 * x), axis=1),
        temperature=0.3,
    )


def si5_q0():
    return si5().replace(state_cost=None)


SI5_Q0 = [
    dict(lo=-1, hi=1, T=1.0, lam=0.3, a=Z, D=lambda x: 0.15, q=Z, g=lambda x: 2 * (x - 0.2) ** 2)
] * 5

SI5 = [
    dict(
        lo=-1,
        hi=1,
        T=1.0,
        lam=0.3,
        a=Z,
        D=lambda x: 0.15,
        q=lambda x: 0.5 * (1 - np.cos(3 * x)),
        g=lambda x: 2 * (x - 0.2) ** 2,
    )
] * 5


# ---------------- 5. options a user passes ---------------------------------------------------------
def spin(rate=3.0, lam=0.3):
    A = np.array([[0.0, -rate], [rate, 0.0]])
    grid = Grid([Axis(-3, 3, 121), Axis(-3, 3, 121)])
    return Problem(
        LinearSystem(A, np.eye(2)),
        grid,
        2.0,
        terminal_cost=Quadratic([1.0, 0.0], np.diag([3.0, 3.0])),
        state_cost=Quadratic([0.0, 0.0], np.diag([0.5, 0.5])),
        temperature=lam,
    )


def spin_truth(t=0.0, rate=3.0, lam=0.3):
    A = np.array([[0.0, -rate], [rate, 0.0]])
    return ricc(
        A,
        np.eye(2),
        1.0,
        np.diag([0.5, 0.5]),
        [0, 0],
        np.diag([3.0, 3.0]),
        [1.0, 0.0],
        lam,
        2.0 - t,
    )


X_SPIN = S((0.0, 0.0), (1.5, -1.0), (-1.0, 1.2))


# ---------------- 6. solve_many components --------------------------------------------------------
def many_base(lam=0.3):
    grid = Grid([Axis(-4, 4, 101), Axis(-6, 6, 101)])
    return Problem(
        PointMass(),
        grid,
        2.0,
        terminal_cost=Quadratic([1.5, 0.0], np.diag([3.0, 1.0])),
        state_cost=Quadratic([0.0, 0.0], np.diag([0.2, 0.05])),
        temperature=lam,
    )


MANY_G = [Quadratic([1.5, 0.0], np.diag([3.0, 1.0])), Quadratic([-1.5, 0.0], np.diag([3.0, 1.0]))]
MANY_PARTS = [
    (PM_A, pm_B(), 1.0, np.diag([0.2, 0.05]), [0, 0], np.diag([3.0, 1.0]), [1.5, 0.0], 0.3),
    (PM_A, pm_B(), 1.0, np.diag([0.2, 0.05]), [0, 0], np.diag([3.0, 1.0]), [-1.5, 0.0], 0.3),
]


def many_truth(i, t):
    return ricc(*MANY_PARTS[i], 2.0 - t)


def many_mix_truth(w, t):
    return mix([(*p, 2.0 - t) for p in MANY_PARTS], w, 0.3)


def many_comp(i):
    def build():
        return many_base().replace(terminal_cost=MANY_G[i])

    build.__name__ = f"many_comp{i}"
    return build


MANY_BUILD = [many_comp(0), many_comp(1)]


def many_comb():
    return many_base()


X_MANY = S((-1.5, 0.0), (0.0, 0.0), (1.5, 0.5))


# the same at λ = 0.08 with the goals at ±2.5 (components far from the composite reference)
MC_G = [Quadratic([2.5, 0.0], np.diag([3.0, 1.0])), Quadratic([-2.5, 0.0], np.diag([3.0, 1.0]))]
MC_PARTS = [
    (PM_A, pm_B(), 1.0, np.diag([0.2, 0.05]), [0, 0], np.diag([3.0, 1.0]), [2.5, 0.0], 0.08),
    (PM_A, pm_B(), 1.0, np.diag([0.2, 0.05]), [0, 0], np.diag([3.0, 1.0]), [-2.5, 0.0], 0.08),
]


def mc_comp(i):
    def build():
        return many_base(0.08).replace(terminal_cost=MC_G[i])

    build.__name__ = f"mc_comp{i}"
    return build


MC_BUILD = [mc_comp(0), mc_comp(1)]
X_MC = S((-2.5, 0.0), (0.0, 0.0), (2.0, 0.5))


SIM_G = [Quadratic([1.0, 0.0], np.diag([4.0, 2.0])), Quadratic([-1.0, 0.0], np.diag([4.0, 2.0]))]


def sim_truth(i, t):
    c = [1.0, 0.0] if i == 0 else [-1.0, 0.0]
    return ricc(
        np.zeros((2, 2)),
        np.eye(2),
        1.0,
        np.zeros((2, 2)),
        [0, 0],
        np.diag([4.0, 2.0]),
        c,
        0.3,
        2.0 - t,
    )


def sim_comp0():
    return si2_quad().replace(terminal_cost=SIM_G[0])


X_SIM = S((-1.0, 0.0), (0.0, 0.0), (1.0, 0.5))


def fe1_reward():
    """First exit with a reward: the right door pays 3 (exit cost −3), the left costs 1; λ = 0.05,
    drift −1, q = 0.5: v crosses zero inside."""
    sysm = Affine(1, lambda x: -1.0 + 0 * x, one(), (0,), name="line")
    return Problem(
        sysm,
        Grid([Axis(-1.2, 1.2, 121)]),
        None,
        state_cost=lambda x: 0.5 + 0 * x[:, 0],
        temperature=0.05,
        exit=lambda x: (x[:, 0] <= -1.0) | (x[:, 0] >= 1.0),
        exit_cost=lambda x: np.where(x[:, 0] < 0, 1.0, -3.0),
    )


def _lq_warm01():
    return lq_shift(0.0, lam=0.1)


def si1_coarse():
    """A user's coarse 1-D grid: 21 nodes on [−2, 2], q = 1 + cos 4x (8 cells a wave), λ = 0.1."""
    return Problem(
        SingleIntegrator(),
        Grid([Axis(-2, 2, 21)]),
        2.0,
        terminal_cost=lambda x: (x[:, 0] - 0.5) ** 2,
        state_cost=lambda x: 1 + np.cos(4 * x[:, 0]),
        temperature=0.1,
    )


SI1_COARSE = dict(
    lo=-2,
    hi=2,
    T=2.0,
    lam=0.1,
    a=Z,
    D=lambda x: 0.05,
    q=lambda x: 1 + np.cos(4 * x),
    g=lambda x: (x - 0.5) ** 2,
)


def _needle_g(x):
    return 40.0 * (1 - np.exp(-((np.asarray(x) - 0.013) ** 2) / (2 * 0.01**2)))


def hot_needle():
    """λ = 5, a goal 40 deep and a quarter cell wide (h = 0.04) between nodes, T = 0.2, 2-D."""
    return Problem(
        si_d(2),
        Grid([Axis(-2, 2, 101), Axis(-2, 2, 101)]),
        0.2,
        terminal_cost=lambda x: _needle_g(x[:, 0]),
        temperature=5.0,
    )


HOT_NEEDLE = [
    dict(lo=-2, hi=2, T=0.2, lam=5.0, a=Z, D=lambda x: 2.5, q=Z, g=_needle_g),
    dict(lo=-2, hi=2, T=0.2, lam=5.0, a=Z, D=lambda x: 2.5, q=Z, g=Z),
]


def circ5():
    """Five independent circles ẋᵢ = 2 sin xᵢ + uᵢ (periodic, 12 nodes each), λ = 0.5, T = 2."""
    sysm = Affine(
        5,
        lambda x: circ_drift(x),
        lambda x: np.ones((len(x), 5)),
        tuple(range(5)),
        angle_axes=tuple(range(5)),
        name="circ5",
    )
    return Problem(
        sysm,
        Grid([Axis(-PI, PI, 12, periodic=True)] * 5),
        2.0,
        terminal_cost=lambda x: np.sum(1 - np.cos(x), axis=1),
        state_cost=lambda x: 0.5 * np.sum(1 - np.cos(x), axis=1),
        temperature=0.5,
    )


CIRC5 = [
    dict(
        lo=-PI,
        hi=PI,
        T=2.0,
        lam=0.5,
        a=circ_drift,
        D=lambda x: 0.25,
        q=lambda x: 0.5 * (1 - np.cos(x)),
        g=lambda x: 1 - np.cos(x),
        periodic=True,
    )
] * 5


def fe1_frozen():
    return fe1(0.005, lo_exit=-0.99, hi_exit=0.987)


def r20_truth(entry):
    """Round 20's stored certified truth of one of its entries (same states, same time)."""

    def truth(X):
        d = json.loads(
            (OUT.parent / "strangers_round20_results" / f"{entry}_truth.json").read_text()
        )
        return (
            np.asarray(d["vstar"]),
            np.asarray(d["unc"]),
            {"ess": d.get("ess"), "khat": d.get("khat")},
        )

    return truth


# ---------------- the table of entries ---------------------------------------------------------------
def _cold_vzero():
    return lq_shift(-V0_COLD, lam=0.05)


def _cold():
    return lq_shift(0.0, lam=0.05)


def _minus50():
    return lq_shift(-50.0)


def _plus1000():
    return lq_shift(1000.0)


def _fe1_warm():
    return fe1(0.3)


def _fe1_cold():
    return fe1(0.02)


def _fe1_between():
    return fe1(0.1, lo_exit=-0.99, hi_exit=0.987)


def _lq_default():
    return lq_shift(0.0)


def _lq_cold02():
    return lq_shift(0.0, lam=0.02)


def _spin():
    return spin()


P21 = {
    "si1_quad": (si1_quad, S((0.0,), (1.0,), (-1.5,)), one_d([SI1_QUAD]), "1-D", 0.0),
    "si1_quad_late": (si1_quad, S((0.0,), (1.0,), (-1.5,)), one_d([SI1_QUAD], 0.9), "1-D", 0.9),
    "si1_quad_t95": (si1_quad, S((0.0,), (1.0,), (-1.5,)), one_d([SI1_QUAD], 0.95), "1-D", 0.95),
    "lq_t292": (_lq_default, X_LQ, lq_truth(2.92), "ricc", 2.92),
    "spin_t195": (_spin, X_SPIN, spin_truth(1.975), "ricc", 1.975),
    "si1_quad_t99": (si1_quad, S((0.0,), (1.0,), (-1.5,)), one_d([SI1_QUAD], 0.99), "1-D", 0.99),
    "si1_long_t285": (
        si1_long,
        S((0.0,), (1.0,), (-1.5,)),
        one_d([dict(SI1_QUAD, T=3.0)], 2.85),
        "1-D",
        2.85,
    ),
    "si1_long_t27": (
        si1_long,
        S((0.0,), (1.0,), (-1.5,)),
        one_d([dict(SI1_QUAD, T=3.0)], 2.7),
        "1-D",
        2.7,
    ),
    "si2_t19": (si2_quad, S((0.0, 0.0), (1.0, 1.0), (-1.5, 0.5)), si2_truth(1.9), "ricc", 1.9),
    "si2_t195": (si2_quad, S((0.0, 0.0), (1.0, 1.0), (-1.5, 0.5)), si2_truth(1.95), "ricc", 1.95),
    "si2_t0": (si2_quad, S((0.0, 0.0), (1.0, 1.0), (-1.5, 0.5)), si2_truth(0.0), "ricc", 0.0),
    "pm_q0_t0": (pm_q0, X_LQ, pm_q0_truth(0.0), "ricc", 0.0),
    "pm_q0_t19": (pm_q0, X_LQ, pm_q0_truth(1.9), "ricc", 1.9),
    "pm_q0_t18": (pm_q0, X_LQ, pm_q0_truth(1.8), "ricc", 1.8),
    "si3_q0_t19": (
        si3_q0,
        S((0, 0, 0), (1.0, 1.0, -1.0), (-1.5, 0.5, 0.5)),
        si3_truth(1.9),
        "ricc",
        1.9,
    ),
    "pend_q0_t19": (
        pend_q0,
        S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5)),
        r20.cert(pend_q0, 1.9),
        "cert",
        1.9,
    ),
    "pend_q0_t0": (
        pend_q0,
        S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5)),
        r20.cert(pend_q0, 0.0),
        "cert",
        0.0,
    ),
    "sim0_t0": (sim_comp0, X_SIM, sim_truth(0, 0.0), "ricc", 0.0),
    "sim0_t1": (sim_comp0, X_SIM, sim_truth(0, 1.0), "ricc", 1.0),
    "sim0_t19": (sim_comp0, X_SIM, sim_truth(0, 1.9), "ricc", 1.9),
    "sim_comb_t19": (
        si2_quad,
        X_SIM,
        lambda X: mix(
            [
                (
                    np.zeros((2, 2)),
                    np.eye(2),
                    1.0,
                    np.zeros((2, 2)),
                    [0, 0],
                    np.diag([4.0, 2.0]),
                    c,
                    0.3,
                    0.1,
                )
                for c in ([1.0, 0.0], [-1.0, 0.0])
            ],
            [1.0, 0.1],
            0.3,
        )(X),
        "mix",
        1.9,
    ),
    "si2_t15": (si2_quad, S((0.0, 0.0), (1.0, 1.0), (-1.5, 0.5)), si2_truth(1.5), "ricc", 1.5),
    "si5_q0_t09": (
        si5_q0,
        S((0, 0, 0, 0, 0), (0.5, -0.5, 0.3, 0.8, -0.8), (-0.9, 0.9, -0.9, 0.9, 0.0)),
        one_d(SI5_Q0, 0.9),
        "1-D",
        0.9,
    ),
    "si5_q0_t0": (
        si5_q0,
        S((0, 0, 0, 0, 0), (0.5, -0.5, 0.3, 0.8, -0.8), (-0.9, 0.9, -0.9, 0.9, 0.0)),
        one_d(SI5_Q0, 0.0),
        "1-D",
        0.0,
    ),
    "si1_narrow": (si1_narrow, S((0.3,), (0.0,), (0.6,)), one_d([SI1_NARROW]), "1-D", 0.0),
    "si1_narrow_late": (
        si1_narrow,
        S((0.3,), (0.32,), (0.25,)),
        one_d([SI1_NARROW], 0.45),
        "1-D",
        0.45,
    ),
    "ou1_circle": (ou1_circle, S((1.0,), (3.0,), (-2.0,)), one_d([OU1_CIRCLE]), "1-D", 0.0),
    "ou1_stiff": (ou1_stiff, S((0.0,), (1.5,), (-2.0,)), one_d([OU1_STIFF]), "1-D", 0.0),
    "fe1_warm": (_fe1_warm, S((0.0,), (-0.8,), (0.9,)), fe1_truth(0.3), "exact", 0.0),
    "fe1_cold": (_fe1_cold, S((0.0,), (-0.8,), (0.9,)), fe1_truth(0.02), "exact", 0.0),
    "fe1_between": (
        _fe1_between,
        S((0.0,), (-0.95,), (0.95,)),
        fe1_truth(0.1, -0.99, 0.987),
        "exact",
        0.0,
    ),
    "lq_minus50": (_minus50, X_LQ, lq_truth(0.0, -50.0), "ricc", 0.0),
    "lq_plus1000": (_plus1000, X_LQ, lq_truth(0.0, 1000.0), "ricc", 0.0),
    "lq_cold_vzero": (_cold_vzero, X_LQ, lq_truth(0.0, -V0_COLD, lam=0.05), "ricc", 0.0),
    "lq_t0": (_lq_default, X_LQ, lq_truth(0.0), "ricc", 0.0),
    "lq_cold": (_cold, X_LQ, lq_truth(0.0, 0.0, lam=0.05), "ricc", 0.0),
    "tiny_hot": (tiny_hot, S((0.1, 0.0), (0.25, 0.25), (0.45, 0.5)), one_d(TINY_HOT), "1-D", 0.0),
    "hot30_3d": (
        hot30_3d,
        S((0.0, 0.0, 0.0), (0.5, -0.5, 0.8), (-0.9, 0.9, -0.3)),
        one_d(HOT30),
        "1-D",
        0.0,
    ),
    "nl_hot10": (nl_hot10, S((0.0, 0.0), (1.0, -0.5), (-1.2, 1.2)), one_d(NL_HOT), "1-D", 0.0),
    "lq5": (
        lq5,
        S((0, 0, 0, 0, 0), (1.0, 0.5, -1.0, -0.5, 0.5), (-1.5, 1.0, 1.5, 0.0, -1.0)),
        ricc(A5, B5, 1.0, W5q, np.zeros(5), W5T, C5T, 0.5, 1.5),
        "ricc",
        0.0,
    ),
    "lq5_17": (
        lambda: lq5(17),
        S((0, 0, 0, 0, 0), (1.0, 0.5, -1.0, -0.5, 0.5), (-1.5, 1.0, 1.5, 0.0, -1.0)),
        ricc(A5, B5, 1.0, W5q, np.zeros(5), W5T, C5T, 0.5, 1.5),
        "ricc",
        0.0,
    ),
    "si5": (
        si5,
        S((0, 0, 0, 0, 0), (0.5, -0.5, 0.3, 0.8, -0.8), (-0.9, 0.9, -0.9, 0.9, 0.0)),
        one_d(SI5),
        "1-D",
        0.0,
    ),
    "opt_dt5": (_lq_default, X_LQ, lq_truth(0.0), "ricc", 0.0),
    "opt_store7": (_lq_default, X_LQ, lq_truth(1.37), "ricc", 1.37),
    "opt_store10": (_lq_default, X_LQ, lq_truth(0.8), "ricc", 0.8),
    "opt_store10_2": (_lq_default, X_LQ, lq_truth(2.2), "ricc", 2.2),
    "opt_dt_huge": (_lq_default, X_LQ, lq_truth(0.0), "ricc", 0.0),
    "opt_f32_cold": (_lq_cold02, X_LQ, lq_truth(0.0, 0.0, lam=0.02), "ricc", 0.0),
    "opt_implicit_spin": (_spin, X_SPIN, spin_truth(), "ricc", 0.0),
    "opt_fitnone_cold": (_cold, X_LQ, lq_truth(0.0, 0.0, lam=0.05), "ricc", 0.0),
    "opt_fast_spin": (_spin, X_SPIN, spin_truth(), "ricc", 0.0),
    "opt_ref_spin": (_spin, X_SPIN, spin_truth(), "ricc", 0.0),
    "spin": (_spin, X_SPIN, spin_truth(), "ricc", 0.0),
    "many0": (MANY_BUILD[0], X_MANY, many_truth(0, 0.0), "ricc", 0.0),
    "many1_late": (MANY_BUILD[1], X_MANY, many_truth(1, 1.8), "ricc", 1.8),
    "many0_late": (MANY_BUILD[0], X_MANY, many_truth(0, 1.8), "ricc", 1.8),
    "many_comb_late": (many_comb, X_MANY, many_mix_truth([1.0, 0.01], 1.8), "mix", 1.8),
    "mc0_late": (MC_BUILD[0], X_MC, lambda X: ricc(*MC_PARTS[0], 0.2)(X), "ricc", 1.8),
    "mc0": (MC_BUILD[0], X_MC, lambda X: ricc(*MC_PARTS[0], 2.0)(X), "ricc", 0.0),
    "mc_comb_late": (
        lambda: many_base(0.08),
        X_MC,
        lambda X: mix([(*p, 0.2) for p in MC_PARTS], [1.0, 1e-3], 0.08)(X),
        "mix",
        1.8,
    ),
    "fe1_reward": (
        fe1_reward,
        S((0.0,), (0.6,), (0.95,), (-0.9,)),
        exit1d(-1.0, 1.0, 0.05, -1.0, 0.025, 0.5, 1.0, -3.0),
        "exact",
        0.0,
    ),
    "opt_store19": (_lq_default, X_LQ, lq_truth(1.5), "ricc", 1.5),
    "opt_store19_early": (_lq_default, X_LQ, lq_truth(0.5), "ricc", 0.5),
    "opt_store19_late": (_lq_default, X_LQ, lq_truth(2.7), "ricc", 2.7),
    "spin_store6": (_spin, X_SPIN, spin_truth(0.49), "ricc", 0.49),
    "si1_store5": (si1_quad, S((0.0,), (1.0,), (-1.5,)), one_d([SI1_QUAD], 0.25), "1-D", 0.25),
    "pend_store8_mid": (r20.pend_t, r20.X_PEND, r20_truth("pend_mid"), "cert", 2.0),
    "pend_store8_late": (r20.pend_t, r20.X_PEND, r20_truth("pend_late"), "cert", 3.6),
    "cart_store8_mid": (r20.cart_t, r20.X_PM, r20_truth("cart_mid"), "cert", 2.5),
    "pend_dt04_mid": (r20.pend_t, r20.X_PEND, r20_truth("pend_mid"), "cert", 2.0),
    "pend_mars_dt": (r20.pend_mars, r20.X_PEND, r20_truth("pend_mars"), "cert", 0.0),
    "cart_dt05_mid": (r20.cart_t, r20.X_PM, r20_truth("cart_mid"), "cert", 2.5),
    "opt_dt_huge_mid": (_lq_default, X_LQ, lq_truth(1.1), "ricc", 1.1),
    "si1_coarse": (si1_coarse, S((0.0,), (0.8,), (-1.3,)), one_d([SI1_COARSE]), "1-D", 0.0),
    "fe1_frozen": (
        fe1_frozen,
        S((0.0,), (-0.95,), (0.95,)),
        exit1d(-0.99, 0.987, 0.005, -1.0, 0.0025, 0.5, 2.0, 0.0),
        "exact",
        0.0,
    ),
    "hot_needle": (
        hot_needle,
        S((0.0, 0.0), (0.3, 1.0), (-1.0, -0.5)),
        one_d(HOT_NEEDLE),
        "1-D",
        0.0,
    ),
    "circ5": (
        circ5,
        S((0, 0, 0, 0, 0), (1.0, -1.0, 2.0, 0.5, -2.5), (3.0, 3.0, -3.0, 0.0, 1.5)),
        one_d(CIRC5),
        "1-D",
        0.0,
    ),
    "opt_f32_fitnone": (_lq_warm01, X_LQ, lq_truth(0.0, 0.0, lam=0.1), "ricc", 0.0),
    "lq_warm01": (_lq_warm01, X_LQ, lq_truth(0.0, 0.0, lam=0.1), "ricc", 0.0),
    "many_comb": (many_comb, X_MANY, many_mix_truth([1.0, 0.01], 0.0), "mix", 0.0),
}

# solve options per entry (a fresh solve, cached under the entry's name), or its solve_many source
OPTS = {
    "opt_dt5": dict(dt=0.3),
    "opt_store7": dict(store_every=7),
    "opt_store10": dict(store_every=10),
    "opt_store10_2": dict(store_every=10),
    "opt_dt_huge": dict(dt=0.75),
    "opt_f32_cold": dict(dtype="float32"),
    "opt_implicit_spin": dict(method="implicit"),
    "opt_fitnone_cold": dict(fitting=None),
    "opt_fast_spin": dict(settings="fast"),
    "opt_ref_spin": dict(settings="reference"),
    "opt_store19": dict(store_every=19),
    "opt_store19_early": dict(store_every=19),
    "opt_store19_late": dict(store_every=19),
    "spin_store6": dict(store_every=6),
    "si1_store5": dict(store_every=5),
    "pend_store8_mid": dict(store_every=8),
    "pend_store8_late": dict(store_every=8),
    "cart_store8_mid": dict(store_every=8),
    "pend_dt04_mid": dict(dt=0.4),
    "pend_mars_dt": dict(dt=0.25),
    "cart_dt05_mid": dict(dt=0.5),
    "opt_dt_huge_mid": dict(dt=0.75),
    "opt_f32_fitnone": dict(dtype="float32", fitting=None),
    "mc0": dict(many=0, mc=True),
    "mc0_late": dict(many=0, mc=True),
    "mc_comb_late": dict(many=(1.0, 1e-3), mc=True),
    "sim0_t0": dict(many=0, base="si"),
    "sim0_t1": dict(many=0, base="si"),
    "sim0_t19": dict(many=0, base="si"),
    "sim_comb_t19": dict(many=(1.0, 0.1), base="si"),
    "many0": dict(many=0),
    "many0_late": dict(many=0),
    "many1_late": dict(many=1),
    "many_comb_late": dict(many=(1.0, 0.01)),
    "many_comb": dict(many=(1.0, 0.01)),
}

_MANY = {}


def _solve21(name):
    """Solve the entry (its options or solve_many) and put it into round 20's cache."""
    build = P21[name][0]
    opts = dict(OPTS.get(name, {}))
    key = build if not opts else (name, build)
    if key in r20._CACHE:
        return key
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        if "many" in opts:
            tag = "mc" if opts.get("mc") else opts.get("base", "many")
            created = tag not in _MANY
            if created:
                base, gs = {
                    "mc": (many_base(0.08), MC_G),
                    "many": (many_base(), MANY_G),
                    "si": (si2_quad(), SIM_G),
                }[tag]
                _MANY[tag] = (gridlbc.solve_many(base, gs), time.perf_counter() - t0, list(w))
            comps, t_many, w_many = _MANY[tag]
            m = opts["many"]
            sol = comps[m] if isinstance(m, int) else gridlbc.combine(comps, list(m))
            ws = list(w) if created else w_many + list(w)
        else:
            sol = gridlbc.solve(build(), **opts)
            ws = list(w)
        dt = time.perf_counter() - t0
        if "many" in opts and not created:
            dt += t_many
    r20._CACHE[key] = (sol, ws, dt)
    return key


def quick21(name):
    key = _solve21(name)
    build = P21[name][0]
    r20._CACHE[build] = r20._CACHE[key]  # quick20 reads the cache under the builder
    r20.quick20(name)
    r20._CACHE.pop(build, None) if key != build else None
    if hasattr(r20._CACHE[key][0], "diagnostics"):
        d = r20._CACHE[key][0].diagnostics
        f = OUT / f"{name}_solve.json"
        out = json.loads(f.read_text())
        out["method"], out["dt"] = getattr(d, "method", None), float(getattr(d, "dt", float("nan")))
        f.write_text(json.dumps(out, indent=1))
        print(f"  method {out['method']} dt {out['dt']}")


def avg_run(name):
    """The average cost on a circle: c and its estimate against my eigen-solve."""
    lam, rate = AVG[name]
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        sol = gridlbc.solve(avg1(lam, rate))
        dt = time.perf_counter() - t0
    c, ce = float(sol.average_cost), float(sol.average_cost_error)
    tr = eig1d(-PI, PI, lam, lambda x: rate + 0 * x, lambda x: lam / 2, lambda x: 1.2 - np.cos(x))(
        None
    )
    print(
        f"{name}: c {c:.5f} ± {ce:.5f} (est {100 * ce / c:.2f} %), truth {tr[0][0]:.5f} ± {tr[1][0]:.1e}, err {100 * (c - tr[0][0]) / tr[0][0]:+.2f} %, {dt:.1f} s, warnings {[str(x.message)[:200] for x in w]}"
    )
    (OUT / f"{name}.json").write_text(
        json.dumps(
            dict(
                c=c,
                c_err=ce,
                truth=float(tr[0][0]),
                unc=float(tr[1][0]),
                time=dt,
                warnings=[str(x.message) for x in w],
            )
        )
    )


def main(argv):
    OUT.mkdir(exist_ok=True)
    r20.P20, r20.OUT = P21, OUT
    if "--avg" in argv:
        for name in AVG:
            avg_run(name)
        return
    if "--table" in argv:
        r20.table()
        return
    if "--compact" in argv:
        compact()
        return
    if "--named" in argv:  # NAME x1,x2;y1,y2
        name, pts = argv[1], argv[2]
        named(name, [[float(c) for c in q.split(",")] for q in pts.split(";")])
        return
    for name in [a for a in argv if not a.startswith("--")]:
        if "--truth" not in argv:
            quick21(name)
        if "--solve" not in argv:
            r20.truth_run(name)


def named(name, states, t=None):
    """v, ê and the truth at the states a warning names (a false alarm or a true one?)."""
    build, _X, f, _tag, t0 = P21[name]
    t = t0 if t is None else t
    key = _solve21(name)
    sol = r20._CACHE[key][0]
    X = np.atleast_2d(np.asarray(states, float))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        v, e = np.asarray(sol.value(X, t)), np.asarray(sol.error_estimate(X, t))
    vs = np.asarray(f(X)[0]) if t == t0 else None
    lam = r20._lam(build)
    for i in range(len(X)):
        sc = max(abs(vs[i]), lam) if vs is not None else max(abs(v[i]), lam)
        err = f"{100 * (v[i] - vs[i]) / sc:+.2f} %" if vs is not None else "-"
        print(
            f"  {name} {X[i].tolist()} t={t}: v {v[i]:.4f} truth {vs[i] if vs is not None else float('nan'):.4f} err {err} ê {100 * e[i] / max(abs(v[i]), lam):.2f} %"
        )


def compact():
    """The report's table: one line per (problem, state, t), with the truth's kind and the time."""
    print(
        "problem           state                    t      pred     truth ±unc  kind    err%   ê%  w  s"
    )
    for name, (build, X, _f, tag, t) in P21.items():
        fs, ft = OUT / f"{name}_solve.json", OUT / f"{name}_truth.json"
        if not (fs.exists() and ft.exists()):
            continue
        lam = r20._lam(build)
        d, tr = json.loads(fs.read_text()), json.loads(ft.read_text())
        for i in range(len(X)):
            v, vs, e = d["v"][i], tr["vstar"][i], d["est"][i]
            sc = max(abs(vs), lam)
            st = ",".join(f"{c:g}" for c in np.round(X[i], 2))
            print(
                f"{name:17s} ({st})".ljust(42)
                + f"{t:5.2f} {v:9.4f} {vs:9.4f} {tr['unc'][i]:.0e} {tag:5s} {100 * (v - vs) / sc:+7.1f} "
                f"{100 * e / max(abs(v), lam):5.1f}  {'Y' if d['warned'] else 'n'} {d['time']:4.1f}"
            )


if __name__ == "__main__":
    main(sys.argv[1:])
