"""Stranger round 31: COSTS THAT CHANGE IN TIME, q(x, t) (public API only; SPEC §1, §2, §6, §7, §10).

RESULTS (library of r31 = main 3aea650, 2026-12-06, one thread; ``--run`` per name, then ``--table``)

What the library offers: a state cost declared ``time_dependent = True`` (``costs.Tracking`` or a
user's own) is refused by ``solve`` (and ``solve(tol=…)``) with a clear ValueError ("the grid
solvers need q(x) alone; use gridlbc.trajectory"); ``simulate``/``certify`` and
``gridlbc.trajectory`` accept it. So a control researcher with q(x, t) has four routes, all posed:

- "freeze": the user's callable ``q(x, t=0.0)`` without the flag, handed to ``solve``;
- "aug": time as a state coordinate (a user ``ControlAffineSystem`` with ds = dt, no noise on s,
  s-axis [0, 1.15 T], 41 nodes; q(x, s) is then a cost of the state); also ``store_every=3``;
- "chain": one grid solve per interval on which q is constant, chained backwards (terminal cost
  of a segment = the next segment's ``value(x, 0)``); on/off problems only;
- "traj": ``trajectory.optimize`` + ``expand`` (LQ only).

Problems (20 + a combination): 12 LQ tracking problems with EXACT truth (Riccati with a moving
reference x̃(t): sinusoid, fast sinusoid, ramp, step at T/2; SingleIntegrator 1-D/2-D/3-D and
PointMass, λ 0.01–3; aug of the 3-D one is 4-D). ``riccati_moving`` agrees with round 25's
``lq_value`` to 7e-15 for a fixed reference, and the aug solve of si2_sin agrees with it to
0.01 % at t = 0. 8 nonlinear 2-D problems (a disc forbidden only for t ∈ [T/3, 2T/3]; a narrow
well moving 1.5 and ~4 cells per step; cost pulses 0.01–0.04 long, shorter than Δt and falling
between the time nodes of the aug grid, at λ 0.2/0.5/1; a centre circling with period T/2),
truths by ``certify`` (proposal: the policy of a 2×-finer aug solve at Δt/4, or the chain's
policy for the pulses; 4000 paths at steps h and h/2 with the on/off factor averaged over each
step, Richardson by hand; trusted if ESS ≥ 400 and SE < 0.5 % of max(|v*|, λ): 180 certificates,
ESS 667–3996 for the trusted, 1 discarded (well, x = (−1.5, 0), t = 0, ESS 142)). Read at
t = 0, T/2, between slices (round(T/2Δt)Δt + 1.5Δt), T − Δt/2, just before every switch, and on
the pulse problems at 5 more times before the pulse. 875 (problem, variant, state, t) pairs.

    variant        pairs  >10%  SILENT  under  ê ≥ ½err
    freeze           156   133      58    141        13
    aug              335    76      21     23       311
    aug_store3       156     6       0      1       154
    chain            138     0       0      0       125
    tol0.05 (aug)     30    21      21      9        21
    tol0.05+states    30    21       0      6        18
    combined/direct    6     0       0      0         6
    traj              24     0       0      0  (no estimate)

After the fixes (main, 2026-12-06): a state cost with a parameter named t (or time) is marked
time-dependent (``costs.TimeDependent``), so the "freeze" variant is refused by ``solve`` with
a ValueError that says what to do (trajectory methods, piece by piece as "chain" does, or the
time as a state axis as "aug" does); its 58 silent pairs are now errors. The pulse between the
s axis's lattice points (finding 2) is a documented limitation (docs/limitations.rst, "When the
state cost depends on time").

FINDINGS, by severity

1. SILENT, the freeze (58 pairs in 6 problems: si1_sinf, si2_hot, si2_ramp, si2_sin,
   si2_step_hot, si3_ramp; 133 of 156 freeze pairs > 10 % off): a callable ``q(x, t=0.0)``
   without ``time_dependent = True`` is solved as q(x, 0) for the whole horizon with no word;
   its error estimate measures the frozen problem (0.1–1 %). Worst: si1_sinf x = 0,
   t = 0: v 0.2394 vs v* 3.0104 (92.0 %), ê 0.09 %; si2_sin (0, 0) t = 0: 0.9041 vs 1.8930
   (52.2 %), ê 0.46 %; si3_ramp, si2_hot, si2_ramp, si2_sin: the same, no warning. The other
   freeze solves warn, but only of their resolution elsewhere. (A signature with a parameter
   named t, or a second parameter, could be detected.) ``--run si1_sinf si2_sin``.
2. SILENT, a cost pulse between the time nodes of the augmented grid (pulse_hot: λ = 1,
   q = 0.1|x|² + 100|x − (1, 0)|² for t ∈ [0.7, 0.71), s-nodes 0.69 and 0.7475): the default
   solve raises NO warning at all and is 17–76 % off at every read before the pulse (21 pairs):
   x = (0, 0), t = 0: v 1.3049 vs v* 2.4931 ± 0.0057 (47.7 %) with ê 48.6 % — the estimate is
   right and the solve is silent; t = 0.65, x = (−1, −1): 1.5216 vs 5.9923 ± 0.0097 (74.6 %),
   ê 0.11 %. The solve's own ``error_estimate`` over its ``states_that_matter`` at t = 0 has
   q90 11.0 % and 11.9 % of them above 5 % (``--matter pulse_hot``), yet no ResolutionWarning.
   ``solve(tol=0.05)``: no refinement (51×51×41, Δt 0.2 as the default), no warning, the same 21
   silent pairs (``--run tol_pulse_hot``). With ``states=`` (the user's states at s = 0) and
   ``times=[0]``: refines x to 101×101 (s stays 41 nodes, Δt 0.18), stops at the 240 s budget
   with an honest warning (278.7 %), but ê at t = 0.65/0.69 stays 0.01–0.05 % for errors
   17–76 % (``--run tolst_pulse_hot``). ``--run pulse_hot``.
3. Under-reads in warned aug solves (23 pairs): the estimate of a missed pulse flickers with the
   read time. pulse (λ 0.5): ê 20–290 % at t = 0, 0.1, 0.3, 0.6 but 0.1–0.5 % at t = 0.5, 0.65,
   0.69 (errors 26–85 %), e.g. t = 0.65, x = (−1, −1): v 1.6534 vs 9.6308 ± 0.0198 (82.8 %),
   ê 0.11 %; its one warning names t = 1.9 near (0, 0.72), not the pulse. kick (λ 0.2, 0.02 long
   at 1.21): t = 1.0, x = (0, 0.5): 0.3476 vs 1.5267 (77.2 %) ê 16.1 %; (0, −0.5): 25.8 % ê 0.79 %;
   (1, 1): 11.2 % ê 0.82 % (t = 0.8 and 1.1 read fine). band_late t = 1.2 (0, 0): 27.1 % ê 12.1 %.
   ``--run pulse kick band_late``.
4. Minor under-read: si2_hot aug_store3 (no warning) t = 0.65, x = (−2, 0.5): 4.7617 vs 4.6653
   (2.07 %), ê 0.87 %.
5. Not findings: the aug LQ solves (12 problems, 4-D included): 0 silent, ê ≥ ½ err at 311/335
   aug pairs overall; the chained segments: 138 pairs, none > 10 %, worst 1.7 % (kick, ê 0.59 %);
   ``combine`` of aug components solved with fitting=None reproduces the direct solve of the
   composite terminal cost to 2.5e-16 (``exact`` True); with default fits 4.8e-4 and ``exact``
   False with a clear ``reason`` (no warning, as documented); trajectory route 0.06–0.9 % off on
   LQ tracking (no estimate to judge). No stray non-gridlbc warnings, no crashes. ``certify`` with
   the default proposal="auto" on a time-dependent problem silently uses the judged policy alone
   (same value as proposal=None).

    cd /work/wt-r31 && PYTHONPATH=/work/wt-r31 NUMBA_NUM_THREADS=1 \
        python benchmarks/holdout/strangers_round31.py --list | --run NAMES | --table | --matter NAME
    (NAMES: the LQ and nonlinear names of --list, riccati, combine, traj_<lq>, tol_<nl>, tolst_<nl>;
    tol_/tolst_ read the truths that ``--run <nl>`` saved)
"""

from __future__ import annotations

import itertools
import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import LinearSystem
from gridlbc.systems.base import ControlAffineSystem

OUT = Path("/work/main/benchmarks/holdout/strangers_round31_results")  # gitignored there

from strangers_round25 import lq_value  # noqa: E402  (the folder is the script's own)


# ================= references x̃(t) =============================================================
def make_ref(kind, T, amp):
    amp = np.asarray(amp, float)
    if kind == "fixed":
        return lambda t: np.broadcast_to(amp, (np.size(t), amp.size)) * 1.0, []
    if kind == "sin":
        w = 2 * math.pi / T
        return lambda t: np.outer(np.sin(w * np.atleast_1d(t)), amp), []
    if kind == "sin_fast":
        w = 6 * math.pi / T
        return lambda t: np.outer(np.sin(w * np.atleast_1d(t)), amp), []
    if kind == "ramp":
        return lambda t: np.outer(np.atleast_1d(t) / T, amp), []
    if kind == "step":
        return lambda t: np.outer((np.atleast_1d(t) >= T / 2).astype(float), amp), [T / 2]
    raise ValueError(kind)


# ================= exact LQ truth with a moving reference ======================================
def riccati_moving(A, B, R, W, ref, breaks, WT, cT, lam, T, t0):
    """(P, p, c0) at t0 of v = ½xᵀPx + pᵀx + c0, q = (x − c(t))ᵀW(x − c(t)) (SPEC §6 with c_q(t))."""
    A, B, R, W, WT = (np.atleast_2d(np.asarray(m, float)) for m in (A, B, R, W, WT))
    cT = np.asarray(cT, float)
    d = A.shape[0]
    S = B @ np.linalg.solve(R, B.T)

    def rhs(t, y):
        P, p = y[: d * d].reshape(d, d), y[d * d : d * d + d]
        c = ref(t)[0]
        dP = -(A.T @ P + P @ A - P @ S @ P + 2 * W)
        dp = -((A - S @ P).T @ p - 2 * W @ c)
        dc = -(-0.5 * p @ S @ p + 0.5 * lam * np.trace(S @ P) + c @ W @ c)
        return np.concatenate([dP.ravel(), dp, [dc]])

    y = np.concatenate([(2 * WT).ravel(), -2 * WT @ cT, [cT @ WT @ cT]])
    knots = sorted({T, t0, *[b for b in breaks if t0 < b < T]}, reverse=True)
    for a, b in itertools.pairwise(knots):
        if a > b:
            y = solve_ivp(rhs, (a, b), y, rtol=1e-11, atol=1e-12, method="LSODA").y[:, -1]
    return y[: d * d].reshape(d, d), y[d * d : d * d + d], y[-1]


def lq_truth(spec, X, t):
    ref, breaks = make_ref(spec["ref"], spec["T"], spec["amp"])
    P, p, c0 = riccati_moving(
        spec["A"], spec["B"], spec["R"], spec["W"], ref, breaks, spec["WT"], spec["cT"],
        spec["lam"], spec["T"], t,
    )  # fmt: skip
    X = np.atleast_2d(np.asarray(X, float))
    return 0.5 * np.einsum("ni,ij,nj->n", X, P, X) + X @ p + c0


# ================= the time-augmented system (time as a state coordinate) ======================
class TimeAugmented(ControlAffineSystem):
    """(x, s) with dx = (Ax + Bu)dt + noise, ds = dt (no noise): q(x, s) is then a cost of the state."""

    def __init__(self, A, B):
        self.A = np.atleast_2d(np.asarray(A, float))
        B = np.asarray(B, float)
        self.B = B[:, None] if B.ndim == 1 else B
        self.d = self.A.shape[0]
        self.state_dim, self.control_dim = self.d + 1, self.B.shape[1]
        self.state_names = tuple(f"x{k}" for k in range(self.d)) + ("s",)

    def drift(self, x):
        x = self._states(x)
        return np.concatenate([x[:, : self.d] @ self.A.T, np.ones((x.shape[0], 1))], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        Bt = np.vstack([self.B, np.zeros((1, self.control_dim))])
        return np.broadcast_to(Bt, (x.shape[0], *Bt.shape)).copy()

    def parameters(self):
        return {"A": self.A.tolist().__repr__(), "B": self.B.tolist().__repr__()}


class TimeCost:
    """A user's q(x, t), declared time-dependent as the library asks (problem.py)."""

    time_dependent = True

    def __init__(self, f):
        self.f = f

    def __call__(self, x, t):
        x = np.atleast_2d(np.asarray(x, float))
        return self.f(x, np.broadcast_to(np.asarray(t, float), x.shape[:1]))


class OnState:
    """The same q evaluated on the augmented state (x, s): q(x, s), time-independent."""

    def __init__(self, f, d):
        self.f, self.d = f, d

    def __call__(self, X):
        X = np.atleast_2d(np.asarray(X, float))
        return self.f(X[:, : self.d], X[:, self.d])


def quad_track(W, ref):
    W = np.atleast_2d(np.asarray(W, float))

    def f(x, t):
        diff = x - ref(t)
        return np.einsum("ni,ij,nj->n", diff, W, diff)

    return f


# ================= problems =====================================================================
def lq_spec(name, d, ref, amp, lam, T, L, n, X, W=None, WT=None, cT=None, A=None, B=None, **kw):
    A = np.zeros((d, d)) if A is None else np.asarray(A, float)
    B = np.eye(d) if B is None else np.asarray(B, float)
    m = B.shape[1]
    return dict(
        name=name,
        family="lq",
        d=d,
        A=A.tolist(),
        B=B.tolist(),
        R=np.eye(m).tolist(),
        W=(np.eye(d) if W is None else np.asarray(W, float)).tolist(),
        WT=(np.eye(d) if WT is None else np.asarray(WT, float)).tolist(),
        cT=[0.0] * d if cT is None else list(cT),
        ref=ref,
        amp=list(amp),
        lam=lam,
        T=T,
        L=L,
        n=n,
        X=X,
        **kw,
    )


PM_A, PM_B = [[0, 1], [0, 0]], [[0], [1]]


def problems():
    P = {}
    # ---- LQ tracking (exact truth). "freeze": q(x, t=0.0) handed straight to the grid solver;
    # "aug": the same problem with time as a state coordinate (a user's own system).
    P["si2_sin"] = lq_spec("si2_sin", 2, "sin", [1.0, 0.5], 0.3, 2.0, 3.0, 61,
                           [[0, 0], [0.8, -0.4], [-1.2, 1.0]])  # fmt: skip
    P["si2_ramp"] = lq_spec("si2_ramp", 2, "ramp", [1.5, -1.0], 1.0, 1.5, 3.5, 61,
                            [[0, 0], [1.0, -0.5], [-1.0, 1.0]])  # fmt: skip
    P["si2_step"] = lq_spec("si2_step", 2, "step", [1.2, 0.0], 0.1, 2.0, 3.0, 61,
                            [[0, 0], [1.0, 0.3], [-1.0, -1.0]], W=[[4, 0], [0, 1]])  # fmt: skip
    P["si2_cold"] = lq_spec("si2_cold", 2, "sin_fast", [0.8, 0.8], 0.01, 1.0, 2.5, 61,
                            [[0, 0], [0.5, -0.3], [-1.0, 0.6]], W=[[3, 0], [0, 3]])  # fmt: skip
    P["si2_hot"] = lq_spec("si2_hot", 2, "sin", [1.0, -1.0], 3.0, 1.0, 5.0, 61,
                           [[0, 0], [1.0, 1.0], [-2.0, 0.5]])  # fmt: skip
    P["pm_sin"] = lq_spec("pm_sin", 2, "sin", [1.0, 0.0], 0.3, 3.0, 5.0, 61,
                          [[0, 0], [0.5, -0.5], [-1.5, 1.0]], A=PM_A, B=PM_B,
                          W=[[2, 0], [0, 0.1]], WT=[[1, 0], [0, 0.2]])  # fmt: skip
    P["pm_step"] = lq_spec("pm_step", 2, "step", [1.0, 0.0], 0.05, 2.0, 5.0, 61,
                           [[0, 0], [0.5, 0.5], [-1.0, -0.5]], A=PM_A, B=PM_B,
                           W=[[3, 0], [0, 0.1]], WT=[[1, 0], [0, 0.2]])  # fmt: skip
    P["si3_ramp"] = lq_spec("si3_ramp", 3, "ramp", [1.0, -0.5, 0.5], 0.5, 1.0, 3.0, 31,
                            [[0, 0, 0], [0.5, 0.5, -0.5], [-1.0, 0.8, 0.3]], n_aug=21, ns=21)  # fmt: skip
    P["si1_step"] = lq_spec("si1_step", 1, "step", [1.5], 0.02, 2.0, 3.0, 121,
                            [[0.0], [0.7], [-1.0]], W=[[5.0]])  # fmt: skip
    P["si1_sinf"] = lq_spec("si1_sinf", 1, "sin_fast", [1.0], 0.1, 2.0, 3.0, 121,
                            [[0.0], [0.5], [-1.2]], W=[[3.0]])  # fmt: skip
    P["si2_step_hot"] = lq_spec("si2_step_hot", 2, "step", [1.0, -1.0], 3.0, 1.0, 5.0, 61,
                                [[0, 0], [1.0, -1.0], [-1.5, 1.5]], W=[[2, 0], [0, 2]])  # fmt: skip
    P["pm_ramp"] = lq_spec("pm_ramp", 2, "ramp", [1.5, 0.0], 0.5, 2.0, 5.0, 61,
                           [[0, 0], [1.0, 0.5], [-1.0, -1.0]], A=PM_A, B=PM_B,
                           W=[[2, 0], [0, 0.2]], WT=[[2, 0], [0, 0.2]], cT=[1.5, 0.0])  # fmt: skip
    return P


def nl_problems():
    """Nonlinear time-varying q on SingleIntegrator-like dynamics; truth by certify."""
    P = {}
    T = 2.0

    def zone_base(x, t):
        return 0.5 * np.sum(x**2, 1)

    def zone_strength(x):  # forbidden disc, switched on only for t in [T/3, 2T/3]
        return 8.0 * np.exp(-np.sum((x - [0.5, 0.0]) ** 2, 1) / 0.1)

    zone_on = [(T / 3, 2 * T / 3, zone_strength)]
    zone = with_pulses(zone_base, zone_on)

    P["zone"] = dict(name="zone", f=zone, lam=0.3, T=T, L=2.5, n=51, g=([1.2, 0.0], [2.0, 2.0]),
                     X=[[-0.5, 0.0], [0.5, 0.0], [0.0, 0.8]], switch=[T / 3, 2 * T / 3], base=zone_base, pulses=zone_on)  # fmt: skip

    def well(x, t):  # a narrow well (σ = 0.08, ~ 1 cell) moving across the box at speed 1.5
        c = np.stack([-1.5 + 1.5 * t, 0 * t], 1)
        return 3.0 - 3.0 * np.exp(-np.sum((x - c) ** 2, 1) / (2 * 0.08**2)) + 0.2 * np.sum(x**2, 1)

    P["well"] = dict(name="well", f=well, lam=0.1, T=T, L=2.5, n=51, g=([1.5, 0.0], [1.0, 1.0]),
                     X=[[-1.5, 0.0], [0.0, 0.3], [1.0, -0.5]], switch=[])  # fmt: skip

    def pulse_base(x, t):
        return 0.3 * np.sum(x**2, 1)

    def pulse_strength(x):  # a cost pulse 0.01 long at t = 0.7 (≪ the default Δt)
        return 200.0 * np.sum((x - [1.0, 0.0]) ** 2, 1)

    pulse_on = [(0.7, 0.71, pulse_strength)]
    pulse = with_pulses(pulse_base, pulse_on)

    P["pulse"] = dict(name="pulse", f=pulse, lam=0.5, T=T, L=3.0, n=51, g=([0.0, 0.0], [1.0, 1.0]),
                      X=[[0.0, 0.0], [1.0, 0.5], [-1.0, -1.0]], switch=[0.7],
                      base=pulse_base, pulses=pulse_on, proposal="chain",
                      extra_times=[0.1, 0.3, 0.5, 0.6, 0.69])  # fmt: skip

    def periodic(x, t):  # q's centre circles, period T/2
        w = 4 * math.pi / T
        c = np.stack([np.cos(w * t), np.sin(w * t)], 1)
        return 2.0 * np.sum((x - c) ** 2, 1) + np.sum(x**2, 1) * (1 + np.sin(w * t)) * 0.5

    P["periodic"] = dict(name="periodic", f=periodic, lam=1.0, T=T, L=3.0, n=51,
                         g=([0.0, 0.0], [1.0, 1.0]), X=[[0.0, 0.0], [1.0, 0.0], [-1.0, 1.0]],
                         switch=[])  # fmt: skip

    def well_fast(x, t):  # narrower (σ = 0.05, half a cell) and faster (speed 5: ~ 4 cells/step)
        c = np.stack([-2.0 + 5.0 * (t % 0.8), 0 * t], 1)
        return 4.0 - 4.0 * np.exp(-np.sum((x - c) ** 2, 1) / (2 * 0.05**2)) + 0.2 * np.sum(x**2, 1)

    P["well_fast"] = dict(name="well_fast", f=well_fast, lam=0.05, T=T, L=2.5, n=51,
                          g=([0.0, 0.0], [1.0, 1.0]), X=[[-1.0, 0.0], [0.0, 0.05], [1.0, 0.0]],
                          switch=[0.8, 1.6])  # fmt: skip

    def kick_base(x, t):
        return 0.2 * np.sum(x**2, 1)

    def kick_strength(x):  # 0.02 long, between the time nodes of the default augmented grid
        return 100.0 * np.exp(-np.sum((x - [0.0, 0.5]) ** 2, 1) / 0.3)

    kick_on = [(1.21, 1.23, kick_strength)]
    P["kick"] = dict(name="kick", f=with_pulses(kick_base, kick_on), lam=0.2, T=T, L=2.5, n=51,
                     g=([0.0, 0.0], [1.0, 1.0]), X=[[0.0, 0.5], [0.0, -0.5], [1.0, 1.0]],
                     switch=[1.21], base=kick_base, pulses=kick_on, proposal="chain",
                     extra_times=[0.2, 0.5, 0.8, 1.1, 1.2])  # fmt: skip

    def hot_base(x, t):
        return 0.1 * np.sum(x**2, 1)

    def hot_strength(x):  # 0.01 long at t = 0.7, between the time nodes (λ = 1: smooth elsewhere)
        return 100.0 * np.sum((x - [1.0, 0.0]) ** 2, 1)

    hot_on = [(0.7, 0.71, hot_strength)]
    P["pulse_hot"] = dict(name="pulse_hot", f=with_pulses(hot_base, hot_on), lam=1.0, T=T, L=3.0,
                          n=51, g=([0.0, 0.0], [0.5, 0.5]), X=[[0.0, 0.0], [1.0, 0.5], [-1.0, -1.0]],
                          switch=[0.7], base=hot_base, pulses=hot_on, proposal="chain",
                          extra_times=[0.1, 0.3, 0.5, 0.6, 0.69])  # fmt: skip

    def late_strength(x):  # a forbidden band switched on for [1.22, 1.26) only, λ = 0.5
        return 20.0 * np.exp(-((x[:, 0] - 0.3) ** 2) / 0.2)

    late_on = [(1.22, 1.26, late_strength)]
    P["band_late"] = dict(name="band_late", f=with_pulses(hot_base, late_on), lam=0.5, T=T, L=3.0,
                          n=51, g=([0.8, 0.0], [1.0, 1.0]), X=[[0.0, 0.0], [0.8, 0.5], [-1.0, 1.0]],
                          switch=[1.22], base=hot_base, pulses=late_on, proposal="chain",
                          extra_times=[0.3, 0.7, 1.0, 1.1, 1.2])  # fmt: skip
    return P


def with_pulses(base, pulses):
    def f(x, t):
        out = base(x, t)
        for on, off, strength in pulses:
            out = out + ((t >= on) & (t < off)).astype(float) * strength(x)
        return out

    return f


def step_averaged(spec, t0, h):
    """q(x, t0 + s) for a rollout with left-point steps h: the on/off factors averaged over the step
    (exact in time while x is frozen over the step), so a switch between steps costs no O(1) error."""
    base, pulses = spec.get("base"), spec.get("pulses", [])
    f = spec["f"]
    if not pulses:
        return TimeCost(lambda y, s: f(y, s + t0))

    def q(y, s):
        a = s + t0
        out = base(y, a)
        for on, off, strength in pulses:
            frac = np.clip(np.minimum(a + h, off) - np.maximum(a, on), 0.0, None) / h
            out = out + frac * strength(y)
        return out

    return TimeCost(q)


# ================= helpers ======================================================================
def wclass(w):
    return f"{w.category.__name__}: {str(w.message)[:160]}"


def is_gridlbc(w):
    return issubclass(w.category, gridlbc.GridlbcWarning)


def aug_grid(d, L, n, T, ns):
    return Grid([Axis(-L, L, n) for _ in range(d)] + [Axis(0.0, 1.15 * T, ns)])


def solve_recorded(problem, **opts):
    t0 = time.time()
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        sol = gridlbc.solve(problem, **opts)
    return sol, [wclass(w) for w in ws], any(is_gridlbc(w) for w in ws), time.time() - t0


def read_times(spec, dt):
    T = spec["T"]
    ts = {"t0": 0.0, "mid": T / 2, "between": round(T / (2 * dt)) * dt + 1.5 * dt,
          "end": T - dt / 2}  # fmt: skip
    for k, s in enumerate(spec.get("extra_times", [])):
        ts[f"extra{k}"] = s
    for k, s in enumerate(spec.get("switch", [])):
        ts[f"pre_switch{k}"] = max(s - 0.25 * dt, 0.0)
    if spec.get("ref") == "step":
        ts["pre_switch"] = T / 2 - 0.25 * dt
    return ts


def read(sol, X, t, aug):
    X = np.atleast_2d(np.asarray(X, float))
    Xq = np.c_[X, np.full(len(X), t)] if aug else X
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        v = sol.value(Xq, t)
        try:
            e = sol.error_estimate(Xq, t)
        except Exception as exc:
            e = np.full(len(X), np.nan)
            ws.append(warnings.WarningMessage(f"error_estimate raised {exc!r}", UserWarning, "", 0))
    return np.asarray(v, float), np.asarray(e, float), [wclass(w) for w in ws]


def record(rows, spec, variant, X, ts, sol, warned, truth_fn, aug, extra=None):
    lam = spec["lam"]
    for tname, t in ts.items():
        v, e, rw = read(sol, X, t, aug)
        vs = truth_fn(X, t)
        for i, x in enumerate(X):
            if not np.isfinite(vs[i]):
                continue
            scale = max(abs(vs[i]), lam)
            rows.append(
                dict(
                    problem=spec["name"],
                    variant=variant,
                    x=list(map(float, x)),
                    tname=tname,
                    t=float(t),
                    v=float(v[i]),
                    truth=float(vs[i]),
                    err=float(abs(v[i] - vs[i]) / scale),
                    est=float(e[i] / scale),
                    warned=bool(warned),
                    read_warnings=rw,
                    **(extra or {}),
                )
            )


# ================= runs =========================================================================
def run_lq(spec, rows, log):
    d, T, lam = spec["d"], spec["T"], spec["lam"]
    ref, _ = make_ref(spec["ref"], T, spec["amp"])
    f = quad_track(spec["W"], ref)
    X = np.asarray(spec["X"], float)
    truth = lambda X_, t: lq_truth(spec, X_, t)  # noqa: E731
    g = Quadratic(spec["cT"], spec["WT"])
    lin = LinearSystem(spec["A"], spec["B"])
    grid = Grid([Axis(-spec["L"], spec["L"], spec["n"]) for _ in range(d)])

    # (1) the user's q(x, t=0.0): the grid solver calls q(x)
    def q_user(x, t=0.0):
        return f(np.atleast_2d(x), np.broadcast_to(t, (np.atleast_2d(x).shape[0],)))

    prob = Problem(lin, grid, T, g, state_cost=q_user, temperature=lam)
    sol, ws, warned, el = solve_recorded(prob)
    dt = float(np.min(np.diff(sol.times)))
    log.append(dict(problem=spec["name"], variant="freeze", warnings=ws, seconds=el, dt=dt))
    record(rows, spec, "freeze", X, read_times(spec, dt), sol, warned, truth, False)
    # the declared-time-dependent form (TimeCost) must be refused clearly
    try:
        gridlbc.solve(Problem(lin, grid, T, g, state_cost=TimeCost(f), temperature=lam))
        log.append(dict(problem=spec["name"], variant="declared", outcome="SOLVED"))
    except Exception as exc:
        log.append(dict(problem=spec["name"], variant="declared", outcome=repr(exc)[:300]))

    # (2) time as a state coordinate
    if d <= 2 or spec.get("n_aug"):
        ns = spec.get("ns", 41)
        agrid = aug_grid(d, spec["L"], spec.get("n_aug", spec["n"]), T, ns)
        aprob = Problem(TimeAugmented(spec["A"], spec["B"]), agrid, T,
                        Quadratic(list(spec["cT"]) + [0.0], np.diag(list(np.diag(spec["WT"])) + [0.0])),
                        state_cost=OnState(f, d), temperature=lam)  # fmt: skip
        if not np.allclose(spec["WT"], np.diag(np.diag(spec["WT"]))):
            raise ValueError("aug needs a diagonal WT")
        for variant, opts in [("aug", {}), ("aug_store3", {"store_every": 3})]:
            try:
                sol, ws, warned, el = solve_recorded(aprob, **opts)
            except Exception as exc:
                log.append(dict(problem=spec["name"], variant=variant, crash=repr(exc)[:400]))
                continue
            dt = float(np.min(np.diff(sol.times)))
            log.append(dict(problem=spec["name"], variant=variant, warnings=ws, seconds=el, dt=dt))
            record(rows, spec, variant, X, read_times(spec, dt), sol, warned, truth, True)


def run_traj(spec, rows, log):
    """The library's own route for q(x, t): gridlbc.trajectory.optimize + expand (exact for LQ)."""
    d, T, lam = spec["d"], spec["T"], spec["lam"]
    ref, _ = make_ref(spec["ref"], T, spec["amp"])
    lin = LinearSystem(spec["A"], spec["B"])
    grid = Grid([Axis(-spec["L"], spec["L"], spec["n"]) for _ in range(d)])
    prob = Problem(lin, grid, T, Quadratic(spec["cT"], spec["WT"]),
                   state_cost=TimeCost(quad_track(spec["W"], ref)), temperature=lam)  # fmt: skip
    X = np.asarray(spec["X"], float)
    with warnings.catch_warnings(record=True) as ws:
        warnings.simplefilter("always")
        t0 = time.time()
        try:
            tr = gridlbc.trajectory.optimize(prob, X[0], restarts=4, seed=0)
            comp = gridlbc.trajectory.expand(prob, tr)
        except Exception as exc:
            log.append(dict(problem=spec["name"], variant="traj", crash=repr(exc)[:400]))
            return
    warned = any(is_gridlbc(w) for w in ws)
    log.append(dict(problem=spec["name"], variant="traj", warnings=[wclass(w) for w in ws],
                    seconds=time.time() - t0))  # fmt: skip
    for tname, t in {"t0": 0.0, "mid": T / 2}.items():
        v = np.asarray(comp.value(X, t), float)
        vs = lq_truth(spec, X, t)
        for i, x in enumerate(X):
            scale = max(abs(vs[i]), lam)
            rows.append(dict(problem=spec["name"], variant="traj", x=list(map(float, x)),
                             tname=tname, t=float(t), v=float(v[i]), truth=float(vs[i]),
                             err=float(abs(v[i] - vs[i]) / scale), est=float("nan"),
                             warned=warned, read_warnings=[]))  # fmt: skip


def check_riccati():
    """My moving-reference Riccati against round 25's for a fixed reference."""
    spec = lq_spec("chk", 2, "fixed", [0.4, -0.3], 0.3, 2.0, 3.0, 61, [[0.5, 0.5]],
                   A=PM_A, B=PM_B, W=[[2, 0], [0, 0.1]])  # fmt: skip
    r25 = dict(A=spec["A"], B=spec["B"], R=spec["R"], Wq=spec["W"], cq=spec["amp"],
               WT=spec["WT"], cT=spec["cT"], lam=0.3, T=2.0)  # fmt: skip
    X = np.array([[0.5, 0.5], [-1.0, 0.2]])
    return [
        float(a - b) for t in (0.0, 1.0) for a, b in zip(lq_truth(spec, X, t), lq_value(r25, X, t))
    ]


def run_nl(spec, rows, log, n_samples=4000):
    T, lam, d = spec["T"], spec["lam"], 2
    f = spec["f"]
    X = np.asarray(spec["X"], float)
    L, n = spec["L"], spec["n"]
    lin = LinearSystem(np.zeros((d, d)), np.eye(d))
    grid = Grid([Axis(-L, L, n) for _ in range(d)])
    c, w = spec["g"]
    g = Quadratic(c, w)
    ga = Quadratic(list(c) + [0.0], np.diag(list(w) + [0.0]))
    aprob = Problem(TimeAugmented(np.zeros((d, d)), np.eye(d)), aug_grid(d, L, n, T, 41), T, ga,
                    state_cost=OnState(f, d), temperature=lam)  # fmt: skip
    sol, ws, warned, el = solve_recorded(aprob)
    dt = float(np.min(np.diff(sol.times)))
    log.append(dict(problem=spec["name"], variant="aug", warnings=ws, seconds=el, dt=dt))
    # the proposal: a finer augmented solve, Δt/4
    if spec.get("proposal") != "chain":
        fprob = aprob.replace(grid=aug_grid(d, L, 2 * n - 1, T, 61))
        fsol, fws, _, fel = solve_recorded(fprob, dt=dt / 4)
        log.append(dict(problem=spec["name"], variant="proposal", warnings=fws, seconds=fel))

    def pol(x, t):
        x = np.atleast_2d(x)
        return fsol.policy(np.c_[x, np.full(len(x), t)], t)

    chain = build_chain(spec["name"], log) if spec.get("pulses") else None
    if spec.get("proposal") == "chain":
        pol = chain_policy(chain[0], T)

    oprob = Problem(lin, grid, T, g, state_cost=TimeCost(f), temperature=lam)
    ts = read_times(spec, dt)
    cache = {}

    def truth(X_, t):
        out = []
        for x in X_:
            key = (tuple(x), t)
            if key not in cache:
                # v*(x, t): certify the remaining horizon T − t with the cost shifted in time,
                # at steps h and h/2 (on/off factors step-averaged), Richardson by hand
                H = T - t
                res = []
                for k in (1, 2):
                    nst = math.ceil(H / spec.get("cert_dt", 0.01)) * k
                    h = H / nst
                    sub = oprob.replace(horizon=H, state_cost=step_averaged(spec, t, h))

                    def spol(y, s, t=t):
                        return pol(y, s + t)

                    with warnings.catch_warnings(record=True) as cw:
                        warnings.simplefilter("always")
                        cert = gridlbc.certify(sub, spol, x, n_samples=n_samples, seed=31 + k,
                                               proposal=None, dt=h)  # fmt: skip
                    res.append(cert)
                v = 2 * res[1].optimal_value - res[0].optimal_value
                se = math.hypot(2 * res[1].optimal_value_se, res[0].optimal_value_se)
                ess = float(min(c.effective_sample_size for c in res))
                ok = ess >= 0.1 * n_samples and se < 0.005 * max(abs(v), lam)
                cert = res[1]
                cache[key] = v if ok else np.nan
                log.append(dict(problem=spec["name"], certify=list(map(float, x)), t=t,
                                v=float(v), se=float(se), ess=ess, raw=float(cert.optimal_value),
                                raw_h=float(res[0].optimal_value),
                                k=float(getattr(cert, "pareto_k", np.nan)), trusted=bool(ok),
                                warnings=[wclass(w_) for w_ in cw]))  # fmt: skip
            out.append(cache[key])
        return np.array(out)

    record(rows, spec, "aug", X, ts, sol, warned, truth, True)
    if chain is not None:
        run_chain(spec["name"], rows, log, truth, dt, *chain)
    return aprob, sol, truth


def build_chain(name, log):
    """The on/off problem as a user may pose it without a time axis: one grid solve per interval
    where q is constant in time, chained backwards (each segment's terminal cost is the next
    segment's value at its start, a callable g(x)). Judged against the certified truth."""
    spec = nl_problems()[name]
    T, lam, d = spec["T"], spec["lam"], 2
    L, n = spec["L"], spec["n"]
    lin = LinearSystem(np.zeros((d, d)), np.eye(d))
    grid = Grid([Axis(-L, L, n) for _ in range(d)])
    knots = sorted({0.0, T, *[a for on, off, _ in spec["pulses"] for a in (on, off)]})
    g = Quadratic(*spec["g"])
    segs = []  # (t_start, t_end, solution), backwards
    term = g
    warned_any = False
    for a, b in reversed(list(itertools.pairwise(knots))):
        mid = 0.5 * (a + b)
        on = [st for lo, hi, st in spec["pulses"] if lo <= mid < hi]

        def q(x, on=on):
            return spec["base"](x, 0.0) + sum((st(x) for st in on), np.zeros(len(x)))

        prob = Problem(lin, grid, b - a, term, state_cost=q, temperature=lam)
        sol, ws, warned, el = solve_recorded(prob)
        warned_any |= warned
        log.append(dict(problem=name, variant="chain", segment=[a, b], warnings=ws, seconds=el))
        segs.append((a, b, sol))
        term = (lambda s_: lambda x: s_.value(x, 0.0))(sol)
    return segs, warned_any


def chain_policy(segs, T):
    def pol(x, t):
        x = np.atleast_2d(x)
        a, b, sol = next(sg for sg in segs if sg[0] <= t < sg[1] or (t >= T and sg[1] == T))
        return sol.policy(x, min(t - a, b - a))

    return pol


def run_chain(name, rows, log, truth, dt, segs, warned_any):
    spec = nl_problems()[name]
    T, lam = spec["T"], spec["lam"]
    X = np.asarray(spec["X"], float)
    for tname, t in read_times(spec, dt).items():
        a, _b, sol = next(sg for sg in segs if sg[0] <= t < sg[1] or (t == T and sg[1] == T))
        # the segment's own estimate, and whether ANY segment solve warned (both recorded)
        v, e, rw = read(sol, X, t - a, False)
        vs = truth(X, t)
        for i, x in enumerate(X):
            if not np.isfinite(vs[i]):
                continue
            scale = max(abs(vs[i]), lam)
            rows.append(dict(problem=name, variant="chain", x=list(map(float, x)), tname=tname,
                             t=float(t), v=float(v[i]), truth=float(vs[i]),
                             err=float(abs(v[i] - vs[i]) / scale), est=float(e[i] / scale),
                             warned=bool(warned_any), read_warnings=rw))  # fmt: skip


def run_combine(rows, log):
    """Components on the augmented grid sharing the zone q, different terminal costs."""
    spec = nl_problems()["zone"]
    T, lam, d, f = spec["T"], spec["lam"], 2, spec["f"]
    L, n = spec["L"], spec["n"]
    sysm = TimeAugmented(np.zeros((d, d)), np.eye(d))
    grid = aug_grid(d, L, n, T, 41)
    gs = [Quadratic([1.2, 0.0, 0.0], np.diag([2.0, 2.0, 0.0])),
          Quadratic([-1.2, 0.5, 0.0], np.diag([2.0, 2.0, 0.0]))]  # fmt: skip
    base = Problem(sysm, grid, T, gs[0], state_cost=OnState(f, d), temperature=lam)
    comps = []
    for i, gi in enumerate(gs):
        s_, ws, warned, el = solve_recorded(base.replace(terminal_cost=gi), fitting=None)
        comps.append(s_)
        log.append(dict(problem="combine", component=i, warnings=ws, seconds=el))
    with warnings.catch_warnings(record=True) as cw:
        warnings.simplefilter("always")
        comb = gridlbc.combine(comps)
    log.append(dict(problem="combine", combine_warnings=[wclass(w) for w in cw]))
    comb_warned = any(is_gridlbc(w) for w in cw) or any(
        any("Warning" in w_ for w_ in e.get("warnings", [])) for e in log if "component" in e
    )

    def gmix(x):
        return -lam * np.logaddexp(-gs[0](x) / lam, -gs[1](x) / lam)

    direct, ws, warned, el = solve_recorded(base.replace(terminal_cost=gmix), fitting=None)
    dt = float(np.min(np.diff(direct.times)))
    X = np.asarray(spec["X"], float)
    diffs = []
    for t in (0.0, T / 3 - 0.25 * dt, T / 2, T - dt / 2):
        Xq = np.c_[X, np.full(len(X), t)]
        a, b = comb.value(Xq, t), direct.value(Xq, t)
        diffs.append(float(np.max(np.abs(a - b) / np.maximum(np.abs(b), lam))))
    log.append(dict(problem="combine", superposition_maxrel=max(diffs), per_time=diffs,
                    direct_warnings=ws))  # fmt: skip
    log.append(dict(problem="combine", exact_attr=bool(getattr(comb, "exact", None))))
    # the same with default solves (fitting auto): is the combination exact, and does it say so?
    dcomps = [solve_recorded(base.replace(terminal_cost=gi))[0] for gi in gs]
    with warnings.catch_warnings(record=True) as cw2:
        warnings.simplefilter("always")
        dcomb = gridlbc.combine(dcomps)
    ddirect = solve_recorded(base.replace(terminal_cost=gmix))[0]
    ddiffs = []
    for t in (0.0, T / 3 - 0.25 * dt, T / 2, T - dt / 2):
        Xq = np.c_[np.asarray(spec["X"], float), np.full(len(spec["X"]), t)]
        a, b = dcomb.value(Xq, t), ddirect.value(Xq, t)
        ddiffs.append(float(np.max(np.abs(a - b) / np.maximum(np.abs(b), lam))))
    log.append(dict(problem="combine", default_fit_maxrel=max(ddiffs), per_time=ddiffs,
                    exact_attr=bool(getattr(dcomb, "exact", None)),
                    reason=str(getattr(dcomb, "reason", ""))[:300],
                    combine_warnings=[wclass(w) for w in cw2]))  # fmt: skip
    # truth of the composite (certify with the direct's policy, no finer proposal here)
    oprob = Problem(LinearSystem(np.zeros((d, d)), np.eye(d)), Grid([Axis(-L, L, n)] * 2), T,
                    lambda x: gmix(np.c_[x, np.zeros(len(x))]), state_cost=TimeCost(f),
                    temperature=lam)  # fmt: skip

    def pol(x, t):
        x = np.atleast_2d(x)
        return direct.policy(np.c_[x, np.full(len(x), t)], t)

    vals = {}
    for x in X:
        cert = gridlbc.certify(oprob, pol, x, n_samples=4000, seed=31, proposal=None,
                               dt=dt / 4, richardson=True)  # fmt: skip
        vals[tuple(x)] = (cert.extrapolated_value, cert.extrapolated_value_se,
                          float(cert.effective_sample_size))  # fmt: skip
        log.append(dict(problem="combine", certify=list(map(float, x)), v=vals[tuple(x)][0],
                        se=vals[tuple(x)][1], ess=vals[tuple(x)][2]))  # fmt: skip

    def truth(X_, t):
        return np.array([vals[tuple(x)][0] if vals[tuple(x)][1] < 0.005 * max(
            abs(vals[tuple(x)][0]), lam) else np.nan for x in X_])  # fmt: skip

    cspec = dict(spec, name="combine")
    with warnings.catch_warnings(record=True) as cw:
        warnings.simplefilter("always")
        record(rows, cspec, "combined", X, {"t0": 0.0}, comb, comb_warned, truth, True)
    record(rows, cspec, "direct", X, {"t0": 0.0}, direct, warned, truth, True)


def run_tol(name, rows, log, tol=0.05, with_states=False):
    """solve(tol=…) of the augmented problem, judged against the truths certified by ``--run name``."""
    spec = nl_problems()[name]
    T, lam, d = spec["T"], spec["lam"], 2
    L, n = spec["L"], spec["n"]
    c, w = spec["g"]
    ga = Quadratic(list(c) + [0.0], np.diag(list(w) + [0.0]))
    aprob = Problem(TimeAugmented(np.zeros((d, d)), np.eye(d)), aug_grid(d, L, n, T, 41), T, ga,
                    state_cost=OnState(spec["f"], d), temperature=lam)  # fmt: skip
    old = json.loads((OUT / f"{name}.json").read_text())["rows"]
    known = {(tuple(r["x"]), r["t"]): r["truth"] for r in old if r["variant"] == "aug"}
    X = np.asarray(spec["X"], float)
    opts = dict(tol=tol)
    if with_states:  # the user's states at s = t = 0, as solve(tol=, states=, times=) allows
        opts.update(states=np.c_[X, np.zeros(len(X))], times=[0.0], max_seconds=240)
    variant = f"tol{tol}" + ("_states" if with_states else "")
    sol, ws, warned, el = solve_recorded(aprob, **opts)
    log.append(dict(problem=name, variant=variant, warnings=ws, seconds=el,
                    dt=float(np.min(np.diff(sol.times))), shape=list(sol.grid.shape)
                    if hasattr(sol, "grid") else None))  # fmt: skip
    ts = sorted({t for _, t in known})
    record(rows, dict(spec, name=name), variant, X, {f"t{t:.3f}": t for t in ts}, sol, warned,
           lambda X_, t: np.array([known.get((tuple(map(float, x)), t), np.nan) for x in X_]),
           True)  # fmt: skip


def matter(name):
    """The default solve's own error_estimate over its states that matter, at t = 0."""
    from gridlbc.accuracy.matter import states_that_matter

    spec = nl_problems()[name]
    T, lam, d = spec["T"], spec["lam"], 2
    c, w = spec["g"]
    ga = Quadratic(list(c) + [0.0], np.diag(list(w) + [0.0]))
    aprob = Problem(TimeAugmented(np.zeros((d, d)), np.eye(d)),
                    aug_grid(d, spec["L"], spec["n"], T, 41), T, ga,
                    state_cost=OnState(spec["f"], d), temperature=lam)  # fmt: skip
    sol, ws, warned, _ = solve_recorded(aprob)
    M = states_that_matter(sol)
    rel = sol.error_estimate(M, 0.0) / np.maximum(np.abs(sol.value(M, 0.0)), lam)
    print(
        f"{name}: warned {warned} ({len(ws)} warnings); {len(M)} states that matter, "
        f"rel. estimate q50 {np.quantile(rel, 0.5):.4f} q90 {np.quantile(rel, 0.9):.4f} "
        f"max {rel.max():.3f}, share > 5 %: {(rel > 0.05).mean():.3f}"
    )


def main(argv):
    OUT.mkdir(parents=True, exist_ok=True)
    if "--list" in argv:
        print(list(problems()), list(nl_problems()), ["combine", "riccati"])
        return
    if "--matter" in argv:
        matter(argv[argv.index("--matter") + 1])
        return
    if "--table" in argv:
        table()
        return
    names = [a for a in argv[argv.index("--run") + 1 :] if not a.startswith("--")]
    for name in names:
        rows, log = [], []
        t0 = time.time()
        with warnings.catch_warnings(record=True) as top:
            warnings.simplefilter("always")
            if name == "riccati":
                log.append(dict(riccati_vs_round25=check_riccati()))
            elif name.startswith("tol_") and name[4:] in nl_problems():
                run_tol(name[4:], rows, log)
            elif name.startswith("tolst_") and name[6:] in nl_problems():
                run_tol(name[6:], rows, log, with_states=True)
            elif name.startswith("traj_") and name[5:] in problems():
                run_traj(problems()[name[5:]], rows, log)
            elif name in problems():
                run_lq(problems()[name], rows, log)
            elif name in nl_problems():
                run_nl(nl_problems()[name], rows, log)
            elif name == "combine":
                run_combine(rows, log)
        log.append(dict(top_warnings=[wclass(w) for w in top], seconds=time.time() - t0))
        (OUT / f"{name}.json").write_text(json.dumps(dict(rows=rows, log=log), indent=1))
        print(name, f"{time.time() - t0:.1f}s", len(rows), "rows", flush=True)


def table():
    allrows = []
    for p in sorted(OUT.glob("*.json")):
        allrows += json.loads(p.read_text())["rows"]
    print(f"{len(allrows)} pairs")
    per = {}
    for r in allrows:
        c = per.setdefault(r["variant"], [0, 0, 0, 0, 0])
        c[0] += 1
        c[1] += r["err"] > 0.10
        c[2] += r["err"] > 0.10 and not r["warned"]
        c[3] += r["err"] > 0.02 and r["est"] < 0.5 * r["err"]
        c[4] += r["est"] >= 0.5 * r["err"]
    for k, c in per.items():
        print(
            f"{k:10s} pairs {c[0]:4d}  >10% {c[1]:3d}  silent {c[2]:3d}  under {c[3]:3d}  ê≥½err {c[4]}"
        )
    for r in allrows:
        flag = ""
        if r["err"] > 0.10 and not r["warned"]:
            flag = "SILENT"
        elif r["err"] > 0.02 and r["est"] < 0.5 * r["err"]:
            flag = "UNDER"
        print(f"{r['problem']:9s} {r['variant']:10s} {r['tname']:11s} t={r['t']:.4f} "
              f"x={np.round(r['x'], 2).tolist()} v={r['v']:.4f} v*={r['truth']:.4f} "
              f"err={100 * r['err']:.2f}% est={100 * r['est']:.2f}% warned={r['warned']} {flag}")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1:])
