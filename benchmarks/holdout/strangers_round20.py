"""Stranger round 20: the estimate read at t > 0, rough costs everywhere, the catalogue's systems
with a stranger's costs, extreme control costs, and combinations of stranger solutions — posed with
the public API only (SPEC §1–3, §6, §10; README "Your own system").

Kinds of problem (none covered by rounds 3–19b):

1. The value and its estimate read at t > 0 (``solution.value(x, t)``,
   ``solution.error_estimate(x, t)``) at t = T/2 ("_mid") and t = 0.9 T ("_late"): the catalogue
   pendulum (damped, cosine goal), a point mass LQ (Riccati at any t), a steep terminal goal
   (point mass, W_T = diag(300, 30), λ = 0.1: late times hold a z narrower than a cell), and a
   user's own cart on a corrugated track; and tasks with an exit set and a horizon (SPEC §9),
   read at t = 0, T/2 and 0.9 T: a point mass leaving through |x₁| ≥ 1.8 at λ = 0.2, 0.5, 1.5
   (101², and 201² as a user refines), a 2-D single integrator with the same exit, the catalogue
   pendulum caught near the upright, the corrugated cart leaving at x ≥ 2.5; and a control, the
   late task posed as its own short problem.
2. Rough costs everywhere: q = 1 + 0.5 sin(k x₁) sin(k x₂) with ~4 cells per wave (k = 40) and
   several waves per cell (k = 300), a cost aliased by the grid (cos(2π x/h): every node sees
   1.5, the mean is 1), a wiggly terminal cost, white-noise-like tables (a random 401² table,
   linearly interpolated) as q and as g, and a 3-D wiggly q.
3. The catalogue's systems with a stranger's goal: the Acrobot on 21⁴ asked to reach the
   horizontal pose, the pendulum with Mars gravity held horizontal, a short hot swing-up, a heavy
   point mass (m = 20).
4. Extreme control cost: R = 1e-3 (noise λR⁻¹ = 50 and 10) and R = 1e3 (noise 3e-3 and 1e-5)
   on 2-D and 3-D LQ problems (Riccati) and on the pendulum (certified), λ from 0.01 to 3.
5. ``gridlbc.combine`` of default solves with mixed weights (1 : 1e-3; 1e2 : 1 : 1e-2; 5 : 0.02),
   read between the goals; truth: the combined problem (terminal desirability Σ w_i h_i).

Layout as round 19b: ``P20`` name → (builder, states, truth, tag, t). The builder returns a
Problem, or for "comb" (problems, weights). ``quick20`` solves with the defaults, records v(x, t),
ê(x, t) and its terms (embedded/pair local term, floor, S, γ at t) and every GridlbcWarning.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round20.py NAME [NAME ...]
    ... --truth NAME ...    (the truth alone)   ... --solve NAME ...   ... --table

Truths ("tag"), none from the library's grid solvers' values:

- "ricc": my Riccati ODEs (P, p, c₀ of SPEC §6, with centres and any R) over the remaining
  horizon T − t. "mix": for the LQ combinations, v = −λ log Σ w_i exp(−v_i/λ) with v_i Riccati
  (the PDE is linear in z, so this is exact).
- "cert": ``gridlbc.certify`` (boundary "reflect", proposal=None, Richardson in Δt, Δt 0.004 /
  0.008) of the problem with horizon T − t (costs and dynamics do not depend on time, so this is
  the remaining task from t), the proposal being the policy of a solve on a grid with 1.5–2× the
  cells per axis (≈ 1.2× in 4-D); ESS and k̂ are stored.

- "heat": for the 2-D single integrators with constant q and a rough terminal cost (wig_g,
  noise_g), z(x, t) = exp(−q τ/λ) E[h(x + √(λτ) N)] (reflected into the box) by quadrature on a
  0.00125 grid; ± the change from doubling that spacing. (The certificates of these two were
  unusable, ESS 2–50, k̂ > 1, with the default-Δt proposal; with Δt 0.005 wig_g's certificate
  agrees with the quadrature to 1.5 SE.)
- exit problems: the exit-aware grid policies over-rate the exit and make poor proposals
  (ESS 2–70); each is pooled with a second proposal: the exact LQ policy of the problem without
  its exit (exit_hz*, exit_warm*, exit_short) or a 2× finer solve without the exit (pend_catch,
  cart_exit). For exit_warm the certified values at t = 1.8 sit on the no-exit LQ value (an upper
  bound: 4.749, 3.891, 5.364, 2.803 against 4.753 ± 0.009, 3.890, 5.365 ± 0.009, 2.801).

RESULTS (library of commit ca448a0, 2026-12-06, one thread; ``--table``): 36 problems (a grid
variant counted as a problem), 58 (problem, t) entries, 231 (problem, state, t) pairs; 29 entries
read at t > 0. ê ≥ ½|v − v*| at 222 / 231 pairs (96.1 %). Nothing refused.

- SILENT (> 10 % off, no GridlbcWarning), 4 pairs, all read at t = 1.8 of T = 2 of one task at
  two temperatures: a point mass (λ = 0.5, q = 1, g = 2x₁² + v², exit |x₁| ≥ 1.8 at cost 0, 101² box
  [−2, 2] × [−4, 4]). ``exit_warm_late`` (1.6, 0): v 2.827 against 5.365 ± 0.009 (−47 %), ê 0.165
  (5.8 %); (−1.5, 0): 3.917 against 4.753 (−17.6 %), ê 0.673 (17 %, not an under-read). On 201²
  (``exit_warm201_late``, what a user does next) (1.6, 0): 3.651 (−32 %), ê 0.824, still no
  warning. The same task from t = 0 reads within 6 % (``exit_warm_0``, ``exit_warm_mid``).
  Mechanism as far as measured: the default picks the plain implicit scheme (diagnostics
  method='implicit', Δt 0.01) and at short remaining horizons it puts far too much desirability
  near the exit (v below the truth at every grid; at (1.6, 0), t = 1.8: 2.50, 2.83, 3.65, 4.54 at
  51², 101², 201², 401² against 5.36: the increments do not shrink, so no two-level
  difference measures the error). The estimate at (1.6, 0) is the pair's 0.165; the embedded
  difference 0.327 (11.6 % of |v|, under ASYMPTOTIC = 15 %) is divided by 2^2.70 − 1 with the
  order 2.70 observed over the calibration states at t = 0; S = 0, γ = 0.001, floor 0.5 %. Silent
  because the warning judges v(x, 0) only (module docstring of gridlbc.accuracy.estimate: "v(x, 0)
  is the cost of a task started at x"); ``error_estimate(x, 1.8)`` warns of nothing either.
  Control: the same remaining task posed as its own problem (``exit_short_0``, T = 0.2) warns
  (ResolutionWarning, 100 % of the states that matter) and reads ê = 48 % at (1.6, 0) against
  −46 % (a term beyond local/pair/floor/S/γ, which read ≤ 12 %, sets it). The same task at
  λ = 1.5 (``exit_hot_late``, no warning) (1.6, 0): v 4.594 against 5.511 ± 0.006 (20 000 samples,
  k̂ 2.5 flagged; the no-exit LQ value 5.536 bounds v* above), −16.6 %, ê 0.142 (3.1 %: the pair;
  embedded difference 0.184 divided by 2^1.66 − 1); grid sequence 4.41, 4.59, 5.03, 5.27 at
  51²–401². With noise on the exit's axis (``si_exit_late``: a 2-D single integrator, same exit,
  costs and times, λ = 0.3) every pair is within 2.3 %: every failing case here has its exit across
  an axis without noise (the position of a point mass or cart).
- Under-reads (ê < ½|v − v*|, |err| > 2 %), 9 pairs, all exit-plus-horizon problems read at
  t > 0 (6 severe; warned except exit_warm's and exit_hot's): ``exit_hot_late`` (1.6, 0) above and
  (−1.5, 0) −3.6 %, ratio 0.47; ``exit_hz_late`` (−1.5, 0) (λ = 0.2): −53 %,
  ê/err 0.19 (grid sequence 1.72, 2.20, 3.16, 4.38 at 51²–401² against 4.70; embedded difference
  0.478 undivided, pair 0.008); ``exit201_late`` (1.6, 0): −60 %, 0.18; ``cart_exit_late``
  (2.2, 0) (a user's cart, exit x ≥ 2.5, t = 4.7 of 5): −62 %, 0.16 (embedded difference 0.197,
  pair 0.056); ``exit_warm_late`` (1.6, 0) and ``exit_warm201_late`` (1.6, 0) above; minor:
  ``exit_hz_mid`` (0, 0) and ``exit_hz_late`` (0, 0), −2.6 % / −2.5 % with ê at the floor (1.1 %),
  ratio 0.41 / 0.43. The λ = 0.2 versions warn from t = 0 ("the plain scheme cannot resolve this
  problem's desirability … v is underestimated there"), so they are not silent.
- Estimate held at t > 0 elsewhere: pendulum, LQ (Riccati, incl. t = 2.987 between slices), the
  corrugated cart, a steep goal (W_T = 300: −24 % … +196 % at t = 1.8, 1.95, all warned, ê/err
  ≥ 0.50), the steep pendulum goal, wiggly and white-noise terminal costs at t = 0.9T, 0.95T, LQ
  combinations at t = T/2, 0.9T, R = 1e-3 at t = 0.9T (−12.5 %, ê/err 0.91, warned).
- Rough costs: the aliased q (every node sees 1.5, mean 1): +35 … +40 %, ê/err 1.36, warned (S
  carries it). noise_g (white-noise terminal table): −3.5 … −4.9 %, ê/err ≥ 0.59, warned.
- Extreme R: rtiny_3d (R = 1e-3, λ = 0.01: noise 10) −8 … −10 %, ê/err ≥ 0.94, warned; R = 1e3
  at λ = 3 and 0.01 within 3.3 %.
- Combinations (1 : 1e-3, 1e2 : 1 : 1e-2, 5 : 0.02) between goals, t = 0 and t > 0: within 1.7 %,
  Σ|α_i|ê_i ≥ ½ err everywhere.
- Acrobot on 21⁴ aiming at the horizontal: +34 % at the handstand, ê 40 %, warned (truth from a
  31⁴ proposal, ESS 474–3861).
- False alarms (warned, every pair < 3 %): wig40, wig40_mid, wig_cell, noise_q (S from the
  wiggles/table between the nodes: 4–19 % against < 0.7 %), rtiny_pm, rtiny_cold (the "control
  moves the state 34 cells per step" splitting warning; < 2.5 %), rhuge_3d (warns near
  (0.225, −0.375, 0.075); tabled states ≤ 1.2 %), comb_pend (warns of (−0.06, −6.4); ≤ 1 %),
  pend_steep_mid / pend_steep_late (≤ 1.7 %), si_exit_late (≤ 2.3 %, plain-scheme warning).
- Truths flagged shaky: catch_0 at (1, −1) (ESS 70; the solve is −40 % with ê 136 %, warned).

AFTER (the same day, the library that answered this round; ``--solve`` of every entry, the truths
unchanged): ê ≥ ½|v − v*| at 229 / 231 pairs, none silent. The estimate at the user's states
now certifies the whole remaining task beside the 8-step local certificate (paths to the
horizon, g exact at their end; gridlbc.accuracy.bellman.local_error), the truncation term reads
its slices over [t, T], and a solve with a horizon is also confirmed 8 steps before T
(gridlbc.accuracy.estimate.late_time): exit_warm_late (1.6, 0) ê/err 0.06 → 2.1 and warned
(12.5 % near (−1.76, 3.84) at t = 1.92), exit_warm201_late and exit_hot_late warned,
exit201_late (1.6, 0) 0.18 → 1.3, exit_hz_late (−1.5, 0) 0.19 → 1.4. Left: cart_exit_late
(2.2, 0) −62 %, ê/err 0.34 (warned; the whole task's certificate there, from a policy that
steers to the exit, is noisy: −1.90 ± 0.22, −1.47 ± 0.23, −1.04 ± 0.23 from 32, 8 and 128
paths against −1.23), exit_hz_late (0, 0) −2.5 % read at 1.1 %. False alarms 14: the 11 above,
rtiny_pend (its late confirmation names (−1.0, −9.8) at t = 1.41, a box edge: 2.6 % low against
a 3× grid at Δt/8, read above 5 %), and pend_mid / pend_late, whose warning is true at the state
it names ((−0.35, 1.04) at t = 3.29: 0.303 against 0.243 from a 3× grid at Δt/8) while the
tabled states are within 1 %.

AFTER, second run (the certificates' two chains paired, the whole task's from up to 512 paths,
the confirmation's discount for its largest candidate): ê ≥ ½|v − v*| at 231 / 231 pairs, none
silent, no under-read (cart_exit_late (2.2, 0): ê/err 0.83). Warned with every tabled state
within 3 %: 16 entries, of them pend_mars and pend_short new, both true at the state and time
they name (−5.1 % at (1.29, −2.92), t = 2.55; +10.9 % at (0.09, −0.5), t = 0.43; against 4×
grids at Δt/8), like pend_mid and pend_late. Three of the exit members joined the corpus (``exit_late``,
``exit_late_cold``, ``cart_exit_late``, read at t > 0: corpus.Member.time).
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import RegularGridInterpolator
from strangers_round12 import HERE
from strangers_round16 import _warned
from strangers_round19b import Affine, one

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.accuracy import cost_gap
from gridlbc.systems import Acrobot, LinearSystem, Pendulum, PointMass

OUT = HERE / "strangers_round20_results"
PI = math.pi


def S(*states):
    return np.array(states, dtype=float)


# ---------------- exact LQ references (SPEC §6, with centres and any R) ---------------------------
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


def ricc(A, B, R, Wq, cq, WT, cT, lam, tau):
    def truth(X):
        return lq_exact(A, B, R, Wq, cq, WT, cT, lam, tau)(np.asarray(X)), np.zeros(len(X)), {}

    return truth


def mix(parts, weights, lam):
    """Exact truth of an LQ combination: −λ log Σ w_i exp(−v_i/λ)."""

    def truth(X):
        X = np.asarray(X)
        vs = np.stack([lq_exact(*p)(X) for p in parts])
        lw = np.log(np.asarray(weights, float))[:, None] - vs / lam
        m = lw.max(0)
        return -lam * (m + np.log(np.exp(lw - m).sum(0))), np.zeros(len(X)), {}

    return truth


# ---------------- certified truths (remaining task from t) --------------------------------------
def finer(p, factor):
    axes = [
        Axis(a.lo, a.hi, round(a.n * factor), True)
        if a.periodic
        else Axis(a.lo, a.hi, round((a.n - 1) * factor) + 1)
        for a in p.grid.axes
    ]
    return p.replace(grid=Grid(axes))


def cert(build, t=0.0, factor=2.0, samples=2000, dt=0.004, composite=None, sdt=0.01, also=None):
    """v* of the task from time t (horizon T − t) by gridlbc.certify, proposal = a finer solve's
    policy (solved with Δt = ``sdt``: the default Δt, e.g. 0.2 for T = 2, leaves the policy near
    T too coarse in time for a wiggly terminal cost, ESS < 50). ``composite`` (problems, weights)
    → the combined problem's terminal cost. ``also(p)`` → a second proposal policy, pooled with
    the first (multiple importance sampling, certify's ``proposal`` list)."""

    def truth(X):
        if composite is None:
            p = build()
        else:
            probs, w = build()
            p = composite_problem(probs, w)
        p = p.replace(horizon=p.horizon - t)
        kw = dict(
            n_samples=samples,
            dt=dt,
            richardson=True,
            progress=False,
            proposal=None,
            boundary="reflect",
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            s = gridlbc.solve(finer(p, factor), dt=sdt, error_estimate=False)
            t1 = time.perf_counter()
            if also is not None:
                kw["proposal"] = [s.policy, also(p)]
            c = gridlbc.certify(p, s.policy, np.asarray(X), seed=20, **kw)
        print(f"    fine solve {t1 - t0:.1f} s, certificate {time.perf_counter() - t1:.1f} s")
        extra = dict(
            ess=np.asarray(c.effective_sample_size).tolist(),
            khat=np.asarray(c.pareto_k).tolist(),
            v_dt=np.asarray(c.optimal_value).tolist(),
            fine_v=np.asarray(s.value(np.asarray(X), 0.0)).tolist(),
        )
        return np.asarray(c.extrapolated_value), np.asarray(c.extrapolated_value_se), extra

    return truth


def composite_problem(probs, weights):
    lam = probs[0].temperature
    gs = [p.terminal_cost for p in probs]
    lw = np.log(np.asarray(weights, float))

    def g(x):
        a = np.stack([lw[i] - np.asarray(gi(x)) / lam for i, gi in enumerate(gs)])
        m = a.max(0)
        return -lam * (m + np.log(np.exp(a - m).sum(0)))

    return probs[0].replace(terminal_cost=g)


def heat(build, q0, t=0.0, spacing=0.00125, width=6.0):
    """Exact truth for a 2-D single integrator (a = 0, B = I) with a constant state cost q0:
    z(x, t) = exp(−q0 τ/λ) E[h(fold(x + √(λτ) N))], τ = T − t, h = exp(−g/λ), fold the
    reflection into the box (the closed edges reflect), by quadrature on a grid of ``spacing``
    (the noise tables' cells are 0.01) out to ``width`` standard deviations; the uncertainty is
    the change from doubling the spacing."""

    def truth(X):
        v, v2 = one(X, spacing), one(X, 2 * spacing)
        return v, np.abs(v - v2), {"v_2spacing": v2.tolist()}

    def one(X, spacing):
        p = build()
        lam, tau = p.temperature, p.horizon - t
        sig = math.sqrt(lam * tau)
        lo = np.array([a.lo for a in p.grid.axes])
        hi = np.array([a.hi for a in p.grid.axes])

        def fold(y, a, b):
            L = b - a
            r = np.mod(y - a, 2 * L)
            return a + np.where(r > L, 2 * L - r, r)

        out = []
        for x in np.asarray(X, float):
            k = np.arange(-width * sig, width * sig + spacing / 2, spacing)
            w1 = np.exp(-0.5 * (k / sig) ** 2)
            ys = [fold(x[i] + k, lo[i], hi[i]) for i in range(2)]
            logs = []
            for j in range(0, len(k), 256):
                Y = np.stack(np.meshgrid(ys[0][j : j + 256], ys[1], indexing="ij"), -1).reshape(
                    -1, 2
                )
                a = -np.asarray(p.terminal_cost(Y), float).reshape(-1, len(k)) / lam
                a = a + np.log(w1[j : j + 256])[:, None] + np.log(w1)[None, :]
                logs.append(np.logaddexp.reduce(a.ravel()))
            log_z = np.logaddexp.reduce(logs) - np.log(w1.sum() ** 2) - q0 * tau / lam
            out.append(-lam * log_z)
        return np.array(out)

    return truth


# ---------------- 1. read at t > 0 ----------------------------------------------------------------
def pend_t():
    sysm = Pendulum(damping=0.3)
    grid = Grid([Axis(-PI, PI, 100, periodic=True), Axis(-8.0, 8.0, 101)])
    return Problem(
        sysm,
        grid,
        4.0,
        terminal_cost=lambda x: 5.0 * (1 - np.cos(x[:, 0])) + 0.25 * x[:, 1] ** 2,
        state_cost=lambda x: 0.5 * (1 - np.cos(x[:, 0])),
        temperature=0.3,
    )


PM_A = np.array([[0.0, 1.0], [0.0, 0.0]])


def pm_B(m=1.0):
    return np.array([[0.0], [1.0 / m]])


LQT = dict(m=2.0, Wq=np.diag([1.0, 0.1]), cq=[-0.5, 0.0], WT=np.diag([4.0, 1.0]), cT=[1.0, 0.0])


def lq_t():
    grid = Grid([Axis(-4, 4, 101), Axis(-6, 6, 101)])
    return Problem(
        PointMass(mass=LQT["m"]),
        grid,
        3.0,
        terminal_cost=Quadratic(LQT["cT"], LQT["WT"]),
        state_cost=Quadratic(LQT["cq"], LQT["Wq"]),
        temperature=0.5,
    )


def lq_t_truth(t):
    return ricc(PM_A, pm_B(LQT["m"]), 1.0, LQT["Wq"], LQT["cq"], LQT["WT"], LQT["cT"], 0.5, 3.0 - t)


STEEP = dict(WT=np.diag([300.0, 30.0]), cT=[0.5, 0.0], Wq=np.diag([0.2, 0.0]), cq=[0.0, 0.0])


def steep_t():
    grid = Grid([Axis(-3, 3, 101), Axis(-4, 4, 101)])
    return Problem(
        PointMass(),
        grid,
        2.0,
        terminal_cost=Quadratic(STEEP["cT"], STEEP["WT"]),
        state_cost=Quadratic(STEEP["cq"], STEEP["Wq"]),
        temperature=0.1,
    )


def steep_t_truth(t):
    return ricc(PM_A, pm_B(), 1.0, STEEP["Wq"], STEEP["cq"], STEEP["WT"], STEEP["cT"], 0.1, 2.0 - t)


def cart_t():
    """A cart on a corrugated track: ẍ = −2 sin(2x) − 0.2 ẋ + u, parked at x = 1.5."""
    sysm = Affine(
        2,
        lambda x: np.stack([x[:, 1], -2.0 * np.sin(2 * x[:, 0]) - 0.2 * x[:, 1]], 1),
        one(),
        (1,),
        name="corrugated cart",
    )
    grid = Grid([Axis(-3, 3, 101), Axis(-4, 4, 101)])
    return Problem(
        sysm,
        grid,
        5.0,
        terminal_cost=Quadratic([1.5, 0.0], [3.0, 0.5]),
        state_cost=lambda x: 0.1 * x[:, 1] ** 2,
        temperature=0.2,
    )


# ---------------- 2. rough costs --------------------------------------------------------------
SI2 = LinearSystem(np.zeros((2, 2)), np.eye(2))


def si2(q, g=None, lam=0.3, T=2.0, n=101, L=2.0):
    grid = Grid([Axis(-L, L, n), Axis(-L, L, n)])
    return Problem(
        SI2,
        grid,
        T,
        terminal_cost=g if g is not None else Quadratic([0.0, 0.0], [1.0, 1.0]),
        state_cost=q,
        temperature=lam,
    )


def wig40():
    return si2(lambda x: 1 + 0.5 * np.sin(40 * x[:, 0]) * np.sin(40 * x[:, 1]))


def wig_cell():
    """Several waves per cell (k = 300, h = 0.04), on a point mass."""
    grid = Grid([Axis(-2, 2, 101), Axis(-2, 2, 101)])
    return Problem(
        PointMass(),
        grid,
        2.0,
        terminal_cost=Quadratic([0.0, 0.0], [1.0, 0.5]),
        state_cost=lambda x: 1 + 0.5 * np.sin(300 * x[:, 0]) * np.sin(300 * x[:, 1]),
        temperature=0.3,
    )


def alias():
    """q = 1 + 0.5 cos(2πx₁/h) cos(2πx₂/h), h the grid spacing: 1.5 at every node, mean 1."""
    k = 2 * PI / 0.04
    return si2(lambda x: 1 + 0.5 * np.cos(k * x[:, 0]) * np.cos(k * x[:, 1]))


def wig_g():
    return si2(
        lambda x: 0.5 + 0 * x[:, 0],
        g=lambda x: (
            0.5 * (x[:, 0] ** 2 + x[:, 1] ** 2) + 0.3 * np.sin(25 * x[:, 0]) * np.cos(25 * x[:, 1])
        ),
        lam=0.1,
    )


def _table(seed, amp):
    rng = np.random.default_rng(seed)
    ax = np.linspace(-2, 2, 401)
    vals = amp * np.tanh(rng.standard_normal((401, 401)))
    f = RegularGridInterpolator((ax, ax), vals, bounds_error=False, fill_value=None)
    return lambda x: f(np.clip(x[:, :2], -2, 2))


_TQ, _TG = _table(20, 0.5), _table(21, 0.4)


def noise_q():
    return si2(lambda x: 1 + _TQ(x), lam=0.3)


def noise_g():
    return si2(
        lambda x: 0.3 + 0 * x[:, 0],
        g=lambda x: 0.5 * (x[:, 0] ** 2 + x[:, 1] ** 2) + _TG(x),
        lam=0.2,
    )


def wig3d():
    sysm = LinearSystem(np.zeros((3, 3)), np.eye(3))
    grid = Grid([Axis(-2, 2, 41)] * 3)
    return Problem(
        sysm,
        grid,
        2.0,
        terminal_cost=Quadratic([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        state_cost=lambda x: (
            1 + 0.5 * np.sin(20 * x[:, 0]) * np.sin(20 * x[:, 1]) * np.sin(20 * x[:, 2])
        ),
        temperature=0.5,
    )


# ---------------- 3. catalogue systems, stranger's goals -------------------------------------------
def acro_horiz(n=21):
    grid = Grid(
        [
            Axis(-PI, PI, n - 1, periodic=True),
            Axis(-PI, PI, n - 1, periodic=True),
            Axis(-16, 16, n),
            Axis(-9, 9, n),
        ]
    )
    return Problem(
        Acrobot(),
        grid,
        2.0,
        terminal_cost=lambda x: (
            5.0 * (1 - np.cos(x[:, 0] - PI / 2))
            + 3.0 * (1 - np.cos(x[:, 1]))
            + 0.02 * (x[:, 2] ** 2 + x[:, 3] ** 2)
        ),
        temperature=1.0,
    )


def pend_mars():
    sysm = Pendulum(mass=0.5, length=2.0, gravity=3.7, damping=0.05)
    grid = Grid([Axis(-PI, PI, 100, periodic=True), Axis(-4.0, 4.0, 101)])
    return Problem(
        sysm,
        grid,
        4.0,
        terminal_cost=lambda x: 4.0 * (1 - np.cos(x[:, 0] - PI / 2)) + 0.5 * x[:, 1] ** 2,
        state_cost=lambda x: 1.0 * (1 - np.cos(x[:, 0] - PI / 2)),
        temperature=0.1,
    )


def pend_short():
    sysm = Pendulum()
    grid = Grid([Axis(-PI, PI, 100, periodic=True), Axis(-10.0, 10.0, 101)])
    return Problem(
        sysm,
        grid,
        1.0,
        terminal_cost=lambda x: 20.0 * (1 - np.cos(x[:, 0])) + 0.5 * x[:, 1] ** 2,
        temperature=1.0,
    )


HEAVY = dict(m=20.0, Wq=np.diag([1.0, 0.5]), cq=[0.0, 0.0], WT=np.diag([5.0, 5.0]), cT=[-1.0, 0.5])


def pm_heavy():
    grid = Grid([Axis(-4, 4, 101), Axis(-3, 3, 101)])
    return Problem(
        PointMass(mass=HEAVY["m"]),
        grid,
        3.0,
        terminal_cost=Quadratic(HEAVY["cT"], HEAVY["WT"]),
        state_cost=Quadratic(HEAVY["cq"], HEAVY["Wq"]),
        temperature=0.2,
    )


# ---------------- 4. extreme control cost ---------------------------------------------------------
EXT = dict(Wq=np.diag([1.0, 0.1]), cq=[0.0, 0.0], WT=np.diag([2.0, 0.5]), cT=[0.5, 0.0])


def pm_R(R, lam, T, vmax):
    grid = Grid([Axis(-4, 4, 101), Axis(-vmax, vmax, 101)])
    return Problem(
        PointMass(),
        grid,
        T,
        terminal_cost=Quadratic(EXT["cT"], EXT["WT"]),
        state_cost=Quadratic(EXT["cq"], EXT["Wq"]),
        control_cost=R,
        temperature=lam,
    )


def rtiny_pm():
    return pm_R(1e-3, 0.05, 1.0, 15.0)


def rhuge_pm():
    return pm_R(1e3, 3.0, 2.0, 6.0)


EXT3 = dict(
    Wq=np.diag([1.0, 0.5, 0.2]), cq=[0, 0, 0], WT=np.diag([2.0, 2.0, 1.0]), cT=[0.5, -0.5, 0]
)


def si3_R(R, lam, T):
    grid = Grid([Axis(-3, 3, 41)] * 3)
    return Problem(
        LinearSystem(np.zeros((3, 3)), np.eye(3)),
        grid,
        T,
        terminal_cost=Quadratic(EXT3["cT"], EXT3["WT"]),
        state_cost=Quadratic(EXT3["cq"], EXT3["Wq"]),
        control_cost=R,
        temperature=lam,
    )


def rtiny_3d():
    return si3_R(1e-3, 0.01, 1.0)


def rhuge_3d():
    return si3_R(1e3, 0.01, 2.0)


def pend_R(R, lam, T):
    grid = Grid([Axis(-PI, PI, 100, periodic=True), Axis(-10.0, 10.0, 101)])
    return Problem(
        Pendulum(damping=0.1),
        grid,
        T,
        terminal_cost=lambda x: 5.0 * (1 - np.cos(x[:, 0])) + 0.2 * x[:, 1] ** 2,
        state_cost=lambda x: 1 - np.cos(x[:, 0]),
        control_cost=R,
        temperature=lam,
    )


def rtiny_pend():
    return pend_R(1e-3, 0.02, 2.0)


def rhuge_pend():
    return pend_R(1e3, 3.0, 3.0)


# ---------------- 5. combinations ---------------------------------------------------------------
CPM = dict(W=np.diag([3.0, 0.5]), goals=([-1.5, 0.0], [1.5, 0.0]), w=(1.0, 1e-3), lam=0.3, T=2.0)


def comb_pm():
    grid = Grid([Axis(-4, 4, 101), Axis(-5, 5, 101)])
    base = Problem(
        PointMass(),
        grid,
        CPM["T"],
        terminal_cost=Quadratic(CPM["goals"][0], CPM["W"]),
        state_cost=lambda x: 0.2 + 0 * x[:, 0],
        temperature=CPM["lam"],
    )
    return [base.replace(terminal_cost=Quadratic(c, CPM["W"])) for c in CPM["goals"]], CPM["w"]


CSI = dict(
    W=np.diag([2.0, 2.0]),
    goals=([-1.0, -1.0], [1.0, 0.0], [0.0, 1.2]),
    w=(1e2, 1.0, 1e-2),
    lam=0.2,
    T=1.5,
)


def comb_si3():
    grid = Grid([Axis(-3, 3, 101), Axis(-3, 3, 101)])
    base = Problem(
        SI2, grid, CSI["T"], terminal_cost=Quadratic(CSI["goals"][0], CSI["W"]), temperature=0.2
    )
    return [base.replace(terminal_cost=Quadratic(c, CSI["W"])) for c in CSI["goals"]], CSI["w"]


def comb_pend():
    base = pend_t().replace(horizon=3.0)
    goals = [
        lambda x: 5.0 * (1 - np.cos(x[:, 0])) + 0.25 * x[:, 1] ** 2,
        lambda x: 5.0 * (1 - np.cos(x[:, 0] - PI / 2)) + 0.25 * x[:, 1] ** 2,
    ]
    return [base.replace(terminal_cost=g) for g in goals], (5.0, 0.02)


# ---------------- the table of problems -----------------------------------------------------------
X_PEND = S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5))
X_PM = S((0.0, 0.0), (-1.0, 1.0), (2.0, -1.0), (0.5, 0.5))
X_SI = S((0.0, 0.0), (1.0, -0.5), (-1.0, 1.0), (0.3, 0.2))
X_3 = S((0.0, 0.0, 0.0), (1.0, -0.5, 0.3), (-1.0, 1.0, -1.0), (0.3, 0.2, 1.5))

P20 = {
    "pend_mid": (pend_t, X_PEND, cert(pend_t, 2.0), "cert", 2.0),
    "pend_late": (pend_t, X_PEND, cert(pend_t, 3.6), "cert", 3.6),
    "lq_mid": (lq_t, X_PM, lq_t_truth(1.5), "ricc", 1.5),
    "lq_late": (lq_t, X_PM, lq_t_truth(2.7), "ricc", 2.7),
    "steep_mid": (
        steep_t,
        S((0.0, 0.0), (0.5, 0.0), (1.0, -1.0), (-1.0, 1.0)),
        steep_t_truth(1.0),
        "ricc",
        1.0,
    ),
    "steep_late": (
        steep_t,
        S((0.3, 0.0), (0.5, 0.0), (0.6, -0.5), (0.0, 1.0)),
        steep_t_truth(1.8),
        "ricc",
        1.8,
    ),
    "cart_mid": (cart_t, X_PM, cert(cart_t, 2.5), "cert", 2.5),
    "cart_late": (cart_t, X_PM, cert(cart_t, 4.5), "cert", 4.5),
    "wig40": (wig40, X_SI, cert(wig40), "cert", 0.0),
    "wig_cell": (wig_cell, X_SI, cert(wig_cell), "cert", 0.0),
    "alias": (alias, X_SI, cert(alias), "cert", 0.0),
    "wig_g": (wig_g, X_SI, heat(wig_g, 0.5), "heat", 0.0),
    "noise_q": (noise_q, X_SI, cert(noise_q), "cert", 0.0),
    "noise_g": (noise_g, X_SI, heat(noise_g, 0.3), "heat", 0.0),
    "wig3d": (wig3d, X_3, cert(wig3d, factor=1.5), "cert", 0.0),
    "acro_horiz": (
        acro_horiz,
        S((PI, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), (-PI / 2, 0.5, 2.0, 0.0)),
        cert(acro_horiz, factor=1.5, sdt=None, samples=4000),
        "cert",
        0.0,
    ),
    "pend_mars": (pend_mars, X_PEND, cert(pend_mars), "cert", 0.0),
    "pend_short": (pend_short, X_PEND, cert(pend_short), "cert", 0.0),
    "pm_heavy": (
        pm_heavy,
        X_PM,
        ricc(PM_A, pm_B(20.0), 1.0, HEAVY["Wq"], HEAVY["cq"], HEAVY["WT"], HEAVY["cT"], 0.2, 3.0),
        "ricc",
        0.0,
    ),
    "rtiny_pm": (
        rtiny_pm,
        X_PM,
        ricc(PM_A, pm_B(), 1e-3, EXT["Wq"], EXT["cq"], EXT["WT"], EXT["cT"], 0.05, 1.0),
        "ricc",
        0.0,
    ),
    "rhuge_pm": (
        rhuge_pm,
        X_PM,
        ricc(PM_A, pm_B(), 1e3, EXT["Wq"], EXT["cq"], EXT["WT"], EXT["cT"], 3.0, 2.0),
        "ricc",
        0.0,
    ),
    "rtiny_3d": (
        rtiny_3d,
        X_3,
        ricc(
            np.zeros((3, 3)),
            np.eye(3),
            1e-3 * np.eye(3),
            EXT3["Wq"],
            EXT3["cq"],
            EXT3["WT"],
            EXT3["cT"],
            0.01,
            1.0,
        ),
        "ricc",
        0.0,
    ),
    "rhuge_3d": (
        rhuge_3d,
        X_3,
        ricc(
            np.zeros((3, 3)),
            np.eye(3),
            1e3 * np.eye(3),
            EXT3["Wq"],
            EXT3["cq"],
            EXT3["WT"],
            EXT3["cT"],
            0.01,
            2.0,
        ),
        "ricc",
        0.0,
    ),
    "rtiny_pend": (rtiny_pend, X_PEND, cert(rtiny_pend, dt=0.002), "cert", 0.0),
    "rhuge_pend": (rhuge_pend, X_PEND, cert(rhuge_pend), "cert", 0.0),
    "comb_pm": (
        comb_pm,
        S((0.0, 0.0), (0.5, 0.0), (1.0, 0.5), (-0.3, -0.5)),
        mix(
            [
                (PM_A, pm_B(), 1.0, np.zeros((2, 2)), [0, 0], CPM["W"], c, CPM["lam"], CPM["T"])
                for c in CPM["goals"]
            ],
            CPM["w"],
            CPM["lam"],
        ),
        "mix",
        0.0,
    ),
    "comb_si3": (
        comb_si3,
        S((0.0, 0.0), (0.5, 0.5), (0.0, -0.5), (-0.5, 0.6)),
        mix(
            [
                (
                    np.zeros((2, 2)),
                    np.eye(2),
                    1.0,
                    np.zeros((2, 2)),
                    [0, 0],
                    CSI["W"],
                    c,
                    CSI["lam"],
                    CSI["T"],
                )
                for c in CSI["goals"]
            ],
            CSI["w"],
            CSI["lam"],
        ),
        "mix",
        0.0,
    ),
    "comb_pend": (
        comb_pend,
        S((0.8, 0.0), (PI, 0.0), (0.5, -1.0), (1.2, 0.5)),
        cert(comb_pend, composite=True),
        "cert",
        0.0,
    ),
}


def comb_pm_truth(t):
    """comb_pm's truth from time t; its state cost is the constant 0.2 (Wq = 0 in the Riccati
    parts: add 0.2 (T − t))."""
    tau = CPM["T"] - t
    f = mix(
        [
            (PM_A, pm_B(), 1.0, np.zeros((2, 2)), [0, 0], CPM["W"], c, CPM["lam"], tau)
            for c in CPM["goals"]
        ],
        CPM["w"],
        CPM["lam"],
    )

    def truth(X):
        v, u, e = f(X)
        return v + 0.2 * tau, u, e

    return truth


def comb_si3_truth(t):
    parts = [
        (
            np.zeros((2, 2)),
            np.eye(2),
            1.0,
            np.zeros((2, 2)),
            [0, 0],
            CSI["W"],
            c,
            CSI["lam"],
            CSI["T"] - t,
        )
        for c in CSI["goals"]
    ]
    return mix(parts, CSI["w"], CSI["lam"])


def rhuge_cold():
    return pm_R(1e3, 0.01, 2.0, 6.0)


def rtiny_cold():
    return pm_R(1e-3, 0.01, 1.0, 15.0)


P20["comb_pm"] = (*P20["comb_pm"][:2], comb_pm_truth(0.0), *P20["comb_pm"][3:])
P20.update(
    {
        "comb_pm_late": (
            comb_pm,
            S((0.0, 0.0), (0.5, 0.0), (1.0, 0.5), (-0.3, -0.5)),
            comb_pm_truth(1.8),
            "mix",
            1.8,
        ),
        "comb_si3_mid": (
            comb_si3,
            S((0.0, 0.0), (0.5, 0.5), (0.0, -0.5), (-0.5, 0.6)),
            comb_si3_truth(0.75),
            "mix",
            0.75,
        ),
        "rhuge_cold": (
            rhuge_cold,
            X_PM,
            ricc(PM_A, pm_B(), 1e3, EXT["Wq"], EXT["cq"], EXT["WT"], EXT["cT"], 0.01, 2.0),
            "ricc",
            0.0,
        ),
        "rtiny_cold": (
            rtiny_cold,
            X_PM,
            ricc(PM_A, pm_B(), 1e-3, EXT["Wq"], EXT["cq"], EXT["WT"], EXT["cT"], 0.01, 1.0),
            "ricc",
            0.0,
        ),
    }
)


def pend_steep():
    """The catalogue pendulum with a steep upright goal, λ = 0.05: read near the end."""
    return pend_t().replace(
        terminal_cost=lambda x: 40.0 * (1 - np.cos(x[:, 0])) + 1.0 * x[:, 1] ** 2,
        temperature=0.05,
        horizon=3.0,
    )


def exit_hz():
    """A horizon and an exit set (SPEC §9): the point mass leaves through |x₁| ≥ 1.8 at cost 0,
    pays q = 1 per unit time and g = 2 x₁² + v² if still inside at T = 2."""

    grid = Grid([Axis(-2, 2, 101), Axis(-4, 4, 101)])
    return Problem(
        PointMass(),
        grid,
        2.0,
        terminal_cost=lambda x: 2.0 * x[:, 0] ** 2 + x[:, 1] ** 2,
        state_cost=lambda x: 1.0 + 0 * x[:, 0],
        temperature=0.2,
        exit=lambda x: np.abs(x[:, 0]) >= 1.8,
        exit_cost=0.0,
    )


def exit_lq_policy(p):
    """The exact LQ policy of exit_hz without its exit (and its constant q): a second proposal."""
    from gridlbc.reference import lq_solution

    q = p.replace(
        exit=None, exit_cost=None, state_cost=None, terminal_cost=Quadratic([0, 0], [2, 1])
    )
    return lq_solution(q).policy


P20.update(
    {
        "steep_end": (
            steep_t,
            S((0.5, 0.0), (0.52, 0.1), (0.45, -0.2), (0.6, 0.0)),
            steep_t_truth(1.95),
            "ricc",
            1.95,
        ),
        "lq_slice": (lq_t, X_PM, lq_t_truth(2.987), "ricc", 2.987),
        "wig_g_late": (wig_g, X_SI, heat(wig_g, 0.5, 1.8), "heat", 1.8),
        "noise_g_late": (noise_g, X_SI, heat(noise_g, 0.3, 1.9), "heat", 1.9),
        "pend_steep_late": (
            pend_steep,
            S((0.3, 0.0), (-0.5, 1.0), (1.0, -1.0), (0.1, 0.5)),
            cert(pend_steep, 2.7),
            "cert",
            2.7,
        ),
        "pend_steep_mid": (pend_steep, X_PEND, cert(pend_steep, 1.5), "cert", 1.5),
        "exit_hz_mid": (
            exit_hz,
            S((0.0, 0.0), (1.0, 0.5), (-1.5, 0.0), (0.5, -1.0)),
            cert(exit_hz, 1.0, also=exit_lq_policy),
            "cert",
            1.0,
        ),
        "exit_hz_late": (
            exit_hz,
            S((0.0, 0.0), (1.0, 0.5), (-1.5, 0.0), (1.7, -1.0)),
            cert(exit_hz, 1.8, also=exit_lq_policy),
            "cert",
            1.8,
        ),
    }
)


P20.update(
    {
        "exit_hz_0": (
            exit_hz,
            S((0.0, 0.0), (1.0, 0.5), (-1.5, 0.0), (0.5, -1.0)),
            cert(exit_hz, 0.0, also=exit_lq_policy),
            "cert",
            0.0,
        ),
        "rtiny_late": (
            rtiny_pm,
            X_PM,
            ricc(PM_A, pm_B(), 1e-3, EXT["Wq"], EXT["cq"], EXT["WT"], EXT["cT"], 0.05, 0.1),
            "ricc",
            0.9,
        ),
        "rhuge_cold_late": (
            rhuge_cold,
            X_PM,
            ricc(PM_A, pm_B(), 1e3, EXT["Wq"], EXT["cq"], EXT["WT"], EXT["cT"], 0.01, 0.2),
            "ricc",
            1.8,
        ),
        "wig40_mid": (wig40, X_SI, cert(wig40, 1.0), "cert", 1.0),
    }
)


def exit_hz201():
    """exit_hz on 201² (what a user does when warned)."""
    return exit_hz().replace(grid=Grid([Axis(-2, 2, 201), Axis(-4, 4, 201)]))


def exit_warm():
    return exit_hz().replace(temperature=0.5)


X_EXL = S((-1.5, 0.0), (-1.4, 0.5), (1.6, 0.0), (1.0, 0.5))
P20.update(
    {
        "exit201_late": (
            exit_hz201,
            X_EXL,
            cert(exit_hz201, 1.8, also=exit_lq_policy),
            "cert",
            1.8,
        ),
        "exit201_mid": (exit_hz201, X_EXL, cert(exit_hz201, 1.0, also=exit_lq_policy), "cert", 1.0),
        "exit_warm_late": (
            exit_warm,
            X_EXL,
            cert(exit_warm, 1.8, also=exit_lq_policy),
            "cert",
            1.8,
        ),
    }
)


def exit_warm201():
    return exit_warm().replace(grid=Grid([Axis(-2, 2, 201), Axis(-4, 4, 201)]))


P20.update(
    {
        "exit_warm201_late": (
            exit_warm201,
            X_EXL,
            cert(exit_warm201, 1.8, also=exit_lq_policy),
            "cert",
            1.8,
        ),
        "exit_warm_mid": (exit_warm, X_EXL, cert(exit_warm, 1.0, also=exit_lq_policy), "cert", 1.0),
        "exit_warm_0": (exit_warm, X_EXL, cert(exit_warm, 0.0, also=exit_lq_policy), "cert", 0.0),
    }
)


def pend_catch():
    """The catalogue pendulum caught near the upright: exit |θ| ≤ 0.2, |ω| ≤ 1 at cost 0, q = 0.5,
    and a terminal cost if not caught by T = 3."""
    sysm = Pendulum(damping=0.2)
    grid = Grid([Axis(-PI, PI, 100, periodic=True), Axis(-8.0, 8.0, 101)])
    return Problem(
        sysm,
        grid,
        3.0,
        terminal_cost=lambda x: 3.0 * (1 - np.cos(x[:, 0])) + 0.1 * x[:, 1] ** 2,
        state_cost=lambda x: 0.5 + 0 * x[:, 0],
        temperature=0.3,
        exit=lambda x: (
            (np.abs(np.mod(x[:, 0] + PI, 2 * PI) - PI) <= 0.2) & (np.abs(x[:, 1]) <= 1.0)
        ),
        exit_cost=0.0,
    )


def cart_exit():
    """cart_t with an exit at x ≥ 2.5 (cost 0) and q = 0.5."""
    return cart_t().replace(
        state_cost=lambda x: 0.5 + 0.1 * x[:, 1] ** 2,
        exit=lambda x: x[:, 0] >= 2.5,
        exit_cost=0.0,
    )


def noexit_policy(p):
    """The policy of a 2× finer solve of the same problem without its exit set: a second proposal
    (the exit-aware grid policies steer toward an exit their grid over-rates, ESS < 100)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        q = finer(p.replace(exit=None, exit_cost=None), 2.0)
        return gridlbc.solve(q, dt=0.01, error_estimate=False).policy


X_CATCH = S((0.5, 0.0), (-0.4, 1.5), (1.0, -1.0), (PI, 0.0))
X_CEX = S((2.2, 0.0), (2.0, -0.5), (1.5, 0.0), (0.0, 0.0))
P20.update(
    {
        "catch_0": (pend_catch, X_CATCH, cert(pend_catch, 0.0, also=noexit_policy), "cert", 0.0),
        "catch_mid": (pend_catch, X_CATCH, cert(pend_catch, 1.5, also=noexit_policy), "cert", 1.5),
        "catch_late": (pend_catch, X_CATCH, cert(pend_catch, 2.7, also=noexit_policy), "cert", 2.7),
        "cart_exit_mid": (cart_exit, X_CEX, cert(cart_exit, 2.5, also=noexit_policy), "cert", 2.5),
        "cart_exit_late": (cart_exit, X_CEX, cert(cart_exit, 4.7, also=noexit_policy), "cert", 4.7),
    }
)


def exit_short():
    """Control: exit_warm's remaining task from t = 1.8 posed as its own problem (T = 0.2)."""
    return exit_warm().replace(horizon=0.2)


P20["exit_short_0"] = (exit_short, X_EXL, cert(exit_short, 0.0, also=exit_lq_policy), "cert", 0.0)


def si_exit():
    """exit_hz's task for a 2-D single integrator (noise on both axes), λ = 0.3."""
    return exit_hz().replace(system=SI2, temperature=0.3, control_cost=1.0)


def exit_hot():
    return exit_hz().replace(temperature=1.5)


P20.update(
    {
        "si_exit_late": (si_exit, X_EXL, cert(si_exit, 1.8, also=exit_lq_policy), "cert", 1.8),
        "exit_hot_late": (
            exit_hot,
            X_EXL,
            cert(
                exit_hot, 1.8, factor=4.0, samples=20000, dt=0.002, sdt=0.001, also=exit_lq_policy
            ),
            "cert",
            1.8,
        ),
    }
)


# ---------------- default solve, read at t ----------------------------------------------------
_CACHE = {}


def _solve(build):
    if build not in _CACHE:
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            t0 = time.perf_counter()
            built = build()
            if isinstance(built, Problem):
                sol = gridlbc.solve(built)
            else:
                probs, weights = built
                comps = [gridlbc.solve(p) for p in probs]
                sol = gridlbc.combine(comps, weights)
            dt = time.perf_counter() - t0
        _CACHE[build] = (sol, list(w), dt)
    return _CACHE[build]


def quick20(name):
    build, X, _f, _tag, t = P20[name]
    sol, w, dt = _solve(build)
    lam = sol.problem.temperature if hasattr(sol, "problem") else build().temperature
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
        warnings=[f"{x.category.__name__}: {str(x.message)[:300]}" for x in ws],
        v=v.tolist(),
        est=est.tolist(),
    )
    emb = getattr(sol, "embedded", None)
    if emb is not None:
        _v, v2h, _diff, local = emb._read(sol, X, t)
        out.update(
            v2h=np.asarray(v2h).tolist(),
            local=np.asarray(local).tolist(),
            floor=float(emb.floor),
            order=float(emb.observed_order),
            S=np.asarray(emb.excess_response(X, t)).tolist(),
            gamma=np.abs(np.asarray(cost_gap(sol, X, t))).tolist(),
        )
        if emb.pair is not None:
            out["pair"] = np.abs(emb.pair[0].value(X, t) - emb.pair[1].value(X, t)).tolist()
    else:  # a combination: the components' estimates and α
        out["alpha"] = np.asarray(sol.blend_weights(X, t)).tolist()
        out["comp_est"] = [np.asarray(c.error_estimate(X, t)).tolist() for c in sol.components]
        out["comp_v"] = [np.asarray(c.value(X, t)).tolist() for c in sol.components]
        out["exact"] = bool(getattr(sol, "exact", False))
    sc = np.maximum(np.abs(v), lam)
    for i in range(len(X)):
        print(
            f"{name:12s} {X[i].round(3).tolist()!s:26s} t={t} v={v[i]:9.4f} est={100 * est[i] / sc[i]:6.2f}%"
        )
    for k in ("local", "pair", "S", "gamma"):
        if k in out:
            print(f"  {k:6s} {np.round(100 * np.asarray(out[k]) / sc, 2).tolist()} %")
    if "floor" in out:
        print(f"  floor {100 * out['floor']:.2f} %  order {out['order']:.2f}")
    print(f"  solve {dt:.1f} s; warnings: {out['warnings']}", flush=True)
    (OUT / f"{name}_solve.json").write_text(json.dumps(out, indent=1))


def truth_run(name):
    _b, X, f, tag, _t = P20[name]
    t0 = time.perf_counter()
    vstar, unc, extra = f(X)
    print(
        f"  {name} truth ({tag}, {time.perf_counter() - t0:.1f} s): "
        f"{np.round(vstar, 4).tolist()} ± {np.round(np.asarray(unc), 4).tolist()}",
        flush=True,
    )
    if extra:
        print(
            "   ", {k: np.round(np.asarray(v, dtype=float), 4).tolist() for k, v in extra.items()}
        )
    (OUT / f"{name}_truth.json").write_text(
        json.dumps(
            dict(vstar=np.asarray(vstar).tolist(), unc=np.asarray(unc).tolist(), tag=tag, **extra)
        )
    )


def _lam(build):
    b = build()
    return (b if isinstance(b, Problem) else b[0][0]).temperature


def table():
    print(
        f"{'problem':12s} {'state':24s} {'t':>4s} {'pred':>9s} {'truth':>9s} {'±':>6s} {'ESS':>5s}"
        f" {'k̂':>5s} {'err':>8s} {'est':>7s} {'abs':>6s} w"
    )
    silent, under, false, n_pairs, n_ok = [], [], [], 0, 0
    n_probs = 0
    for name, (build, X, _f, _tag, t) in P20.items():
        fs, ft = OUT / f"{name}_solve.json", OUT / f"{name}_truth.json"
        if not (fs.exists() and ft.exists()):
            continue
        n_probs += 1
        lam = _lam(build)
        d, tr = json.loads(fs.read_text()), json.loads(ft.read_text())
        errs = []
        for i in range(len(X)):
            v, vs, e = d["v"][i], tr["vstar"][i], d["est"][i]
            sc = max(abs(vs), lam)
            err, rel_e = (v - vs) / sc, e / max(abs(v), lam)
            errs.append(abs(err))
            ess = tr.get("ess", [float("nan")] * len(X))[i]
            kh = tr.get("khat", [float("nan")] * len(X))[i]
            ratio = e / max(abs(v - vs), 1e-12)
            n_pairs += 1
            n_ok += ratio >= 0.5
            shaky = ess < 100 or kh > 0.7
            print(
                f"{name:12s} {np.round(X[i], 2).tolist()!s:24s} {t:4.1f} {v:9.4f} {vs:9.4f}"
                f" {100 * tr['unc'][i] / sc:5.2f}% {ess:5.0f} {kh:5.2f}"
                f" {100 * err:+7.2f}% {100 * rel_e:6.2f}% {min(ratio, 999):6.2f} "
                f"{'Y' if d['warned'] else 'n'}{' (truth shaky)' if shaky else ''}"
            )
            if abs(err) > 0.10 and not d["warned"]:
                silent.append((name, i, round(100 * err, 1)))
            if abs(err) > 0.02 and ratio < 0.5:
                under.append((name, i, round(100 * err, 1), round(100 * rel_e, 1), round(ratio, 2)))
        if d["warned"] and max(errs) < 0.03:
            false.append(name)
    print(
        f"entries (problem, t) {n_probs}, pairs {n_pairs}, ê ≥ ½|err| at {n_ok}/{n_pairs}\n"
        f"silent (>10 %, no warning): {silent}\nunder-reads (ê < ½|err|, err > 2 %): {under}"
        f" (state index, err %, est % of |v|, ê/|v − v*|)\nfalse alarms (warned, every state < 3 %): {false}"
    )


def main(argv):
    OUT.mkdir(exist_ok=True)
    if "--table" in argv:
        table()
        return
    for name in [a for a in argv if not a.startswith("--")]:
        if "--truth" not in argv:
            quick20(name)
        if "--solve" not in argv:
            truth_run(name)


if __name__ == "__main__":
    main(sys.argv[1:])
