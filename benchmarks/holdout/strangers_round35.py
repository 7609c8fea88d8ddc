"""Stranger round 35: is ``gridlbc.certify`` honest under POOR proposals?

RESULTS (library of main 4600fb4, branch r35, 2026-12-07, one thread, ``--all`` then ``--table``):
590 configs, 9400 certificates (each with ``richardson=True``). z = (v̂ − v_true)/SE, "warned" =
what a plain certify call says (the fine run's ESS < 30, k̂ > 0.7 or unexited > 1 %), SILENT =
|z| > 4, not warned, |v̂ − v_true| ≥ 0.5 % of max(|v_true|, λ); "chain" = the same against the
exact value of the Euler–Maruyama chain (LQ) or the truth where the chain is exact (bim).

SILENT, harmful (reproduce: ``--run NAME``, NAME = problem-policy-proposal-n{200,1000,4000}):

A. Unvisited mode, ``proposal=None`` (bim1, bim1s: ẋ = u, q = 0, two terminal wells, the deeper one
   1.5 from x₀ = 0.5, λ = 0.1, T = 1; chain exact, truth by quadrature). The exact policy of the
   near well alone (``near``, ``near0.5``): 200/200 runs SILENT, bim1 v̂ = 0.22–0.24 vs −0.358
   (5.9 λ), bim1s 0.22–0.24 vs 0.169 (0.6 λ), ESS 0.51–0.99 n, k̂ ≤ 0.25, z 9–3145. Even the
   passive policy: 12/50 (bim1) and 22/50 (bim1s) SILENT (ESS 2–16 % of n but ≥ 30, k̂ ≤ 0.31).
   ``proposal="auto"`` fixes every one (0/300): the grid solve sees the far well.
B. A terminal-cost dip narrower than a cell, between the nodes (bimn: σ 0.03 at −1.05, 61 nodes,
   spacing 0.1): EVERY policy and BOTH proposals, incl. certifying the problem's own default solve
   (``bimn-grid-auto-n1000``: 50/50 SILENT, v̂ 0.2334 ± 0.0004 vs truth −0.3518, ESS 0.96 n, k̂ ≤
   0.44, gap J − v* ≈ 0). ``gridlbc.solve`` warns about the sub-cell cost; certify's automatic
   grid solve silences that warning and inherits the blindness; certify agrees with the wrong
   solve to 4 digits. 482/500 runs of bimn SILENT (the rest: passive with ESS < 30, and 2).
C. Over-aggressive feedback (lq4-g3-none: 4-D, λ = 3, T = 0.5, exact gains ×3): 11/50 SILENT at
   chain level, v̂ 7.6–9.2 vs 6.58 (15–39 %), ESS 5–36 % of n, k̂ 0.28–0.70 (n = 200: 6/20, 4000:
   3/10). The proposal is narrower than the optimal path law; the missing tail is never sampled, so
   k̂ cannot see it. ``auto``: 0/50.
D. Marginal ESS with the default pool (lq4s: 4-D, λ = 0.1, T = 2, auto grid 13⁴): every poor
   policy 8–9/50 chain-SILENT (g0.5: 2/50; 59/450 in all), v̂ +0.8–2.0 % (≈ 0.4 λ), z_chain 4–7.5,
   ESS 4–19 % of n (≥ 30), k̂ 0.26–0.69
   (e.g. ``lq4s-zero-auto-n1000`` seeds 7, 10, 14; ``lq4s-zero-auto-n4000`` seeds 3, 4); same with
   the coarse policy alone (``lq4s-coarse-none-*``: 8/50). Mean z_chain +1.7. Likewise
   exit2-coarse-auto / exit2-g3-auto: 12/50 each, +0.6–1.4 % (part of it the bias of E).
E. First exit, discrete monitoring (exit1: ẋ = u, q = 1, E = {x ≥ 1}, v = √(2qR)(1 − x₀)): the
   chain stops only at steps inside E, so v̂ is high by O(√Δt): 4.0 %, 1.9 %, 0.92 % at Δt 0.04,
   0.01, 0.0025 with the exact (or the pooled auto) proposal, z ≈ 40, nothing warned. Richardson
   assumes O(Δt) and removes only 2 − √2 of it: extrapolated 2.4 %, 1.2 %, 0.55 % off, z ≈ 8.6
   (``exit1-exact-none-n1000``: 20/20 SILENT plain, 20/20 extrapolated). exit2 (2-D, λ = 0.05):
   0.5 % at Δt 0.01, 1.1 % at 0.04.

Documented, not counted as dishonest: the Euler–Maruyama O(Δt) bias with near-zero-variance
proposals (lq*-exact-none-K30/K100: up to 3.9 % at 30 steps, z up to 220 at λ = 0.01; 0.14–0.36 %
at the default 300 steps, "silent-tiny"); ``richardson=True`` removes it (0 SILENT extrapolated
in every LQ config, |mean z_ext| ≤ 1.2). Against the chain's own value, over the TRUSTED runs
only: mean z_chain +5.5 (lq4-g3-none), +4.3 to +5.1 (lq4s auto with every poor policy, and
lq4s-coarse-none), +3.1 (pm2-g0.5-none, 2 trusted runs, 1 SILENT: seed 19, ESS 31.5, k̂ 0.65,
+2.7 %), and within ±1.2 in every other LQ config.

Warned correctly: zero, ×0.1, ×3, moved-goal and away (κ = 4, 8) proposals alone at λ ≤ 0.3
(ESS mostly 1–10, k̂ up to 150), first exit with a policy that never exits (unexited warning).
``auto`` made every LQ poor-proposal config except lq4s honest against the chain; against the
SDE's value its |mean z| reaches 7 (lq3) and 16–50 (lq2tiny, λ = 0.01) from the Δt bias alone,
≤ 0.55 % of v.

Confusing: (1) with ``richardson=True`` the Certificate's ESS, k̂ and ``trusted`` are the Δt
run's only; the 2Δt run's are dropped (a warning is all): lq4s-zero-auto-n1000 seed 3 says
trusted (ESS 79, k̂ 0.39) while the 2Δt run had k̂ 1.15 and the extrapolated value is 5.5 of its
SEs off. (2) ``auto`` falls back to the policy alone without a warning when the grid solve fails
(lq2long: cross-diffusion B = (0.8, 0.3)ᵀ; only ``Certificate.proposals`` says so). No crashes.

Exact truths only: LQ problems (Riccati, ``lq_value`` of round 25) in 1-D to 4-D, a
``gridlbc.systems.PointMass``, and a first-exit problem with a closed-form value (ẋ = u, constant
q, exit set x₀ ≥ 1, free boundary: v = √(2 q R)(1 − x₀), whatever λ). For the LQ problems also the
value of the SAME Euler–Maruyama chain the certificate samples (a discrete Riccati recursion of
Gaussian integrals, left-point state cost, ``chain_value``), so the time-step bias is separated from
the statistical error: z_chain = (v̂ − v_chain)/SE is what the SE is supposed to cover,
z = (v̂ − v_true)/SE is what the brief classifies.

Proposals (the ``policy`` argument), each with ``proposal=None`` and ``proposal="auto"``: zero
control, the exact LQ policy with gains ×0.1 / ×0.5 / ×3, a coarse-grid (13 nodes per axis) solve's
policy, the exact policy of a problem whose goal is moved by 3 noise scales, a constant bias away
from the goal of 4 or 8 "noise units" (KL ≈ κ²/2 nats), and the exact policy. n = 200, 1000,
4000; seeds 0…19 (10 at n = 4000); every run with ``richardson=True`` (the fine certificate is the
plain one at that seed). Boundary "free" (the truths live on Rᵈ).

    cd /work/main && PYTHONPATH=/work/wt-r35 NUMBA_NUM_THREADS=1 \
        python benchmarks/holdout/strangers_round35.py --list | --selftest | --run NAME... | --all | --table
"""

from __future__ import annotations

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
from gridlbc.systems import LinearSystem, PointMass

sys.path.insert(0, str(Path(__file__).parent))
from strangers_round25 import build_lq, gen_lq, lq_value

OUT = Path("/work/main/benchmarks/holdout/strangers_round35_results")  # gitignored there


# ================= problems =======================================================================
def _lq(name, A, B, R, Wq, cq, WT, cT, lam, T, L, n, x0, pointmass=None):
    d = len(A)
    return dict(
        family="lq",
        name=name,
        d=d,
        A=np.asarray(A, float).tolist(),
        B=np.asarray(B, float).tolist(),
        R=np.asarray(R, float).tolist(),
        Wq=np.asarray(Wq, float).tolist(),
        cq=list(map(float, cq)),
        WT=np.asarray(WT, float).tolist(),
        cT=list(map(float, cT)),
        lam=float(lam),
        T=float(T),
        L=list(map(float, L)),
        n=list(map(int, n)),
        x0=list(map(float, x0)),
        pointmass=pointmass,
    )


def _random_lq(name, d, seed, lam, T, n):
    spec = gen_lq(np.random.default_rng(seed), d, 0)
    return _lq(
        name,
        spec["A"],
        spec["B"],
        spec["R"],
        spec["Wq"],
        spec["cq"],
        spec["WT"],
        spec["cT"],
        lam,
        T,
        spec["L"],
        [n] * d,
        spec["X"][0],
    )


def problems():
    P = {}
    P["lq1"] = _lq("lq1", [[0.5]], [[1.0]], [[1.0]], [[1.0]], [0.0], [[5.0]], [1.0], 0.3, 2.0,
                   [5.0], [201], [-1.0])  # fmt: skip
    P["pm2"] = _lq("pm2", [[0, 1], [0, 0]], [[0], [1.0]], [[1.0]], np.diag([0.5, 0.05]), [0, 0],
                   np.diag([20.0, 2.0]), [1.0, 0.0], 0.05, 3.0, [4.0, 6.0], [61, 61],
                   [-1.0, 0.0], pointmass=1.0)  # fmt: skip
    P["lq2tiny"] = _lq("lq2tiny", [[-0.2, 1.0], [-0.5, 0.1]], [[1.0, 0], [0, 0.7]], np.diag([1, 2.0]),
                       np.diag([1.0, 0.3]), [0.3, -0.2], np.diag([8.0, 3.0]), [1.0, -0.5], 0.01,
                       1.0, [3.0, 3.0], [61, 61], [-1.0, 0.8])  # fmt: skip
    P["lq2long"] = _lq("lq2long", [[0.2, 0.5], [-0.3, -0.4]], [[0.8], [0.3]], [[0.5]],
                       np.diag([0.4, 0.4]), [0.5, 0.5], np.diag([4.0, 1.0]), [-1.0, 1.0], 0.5, 5.0,
                       [5.0, 5.0], [61, 61], [1.5, -1.5])  # fmt: skip
    P["lq3"] = _random_lq("lq3", 3, 3501, 1.0, 1.5, 25)
    P["lq4"] = _random_lq("lq4", 4, 3502, 3.0, 0.5, 13)
    P["lq4s"] = _random_lq("lq4s", 4, 3503, 0.1, 2.0, 13)
    P["exit1"] = dict(family="exit", name="exit1", d=1, q0=1.0, R=1.0, lam=0.2, L=[-4.0, 1.5],
                      n=[221], x0=[-0.5], max_time=6.0, dt=0.01)  # fmt: skip
    P["exit2"] = dict(family="exit", name="exit2", d=2, q0=0.5, R=2.0, lam=0.05, L=[-3.0, 1.5],
                      n=[91, 61], x0=[-1.0, 0.3], max_time=8.0, dt=0.01)  # fmt: skip
    # two goals (ẋ = u, q = 0): the truth is a 1-D Gaussian quadrature and the Euler–Maruyama
    # chain is exact (no time-step bias); the deeper well is far from the start
    P["bim1"] = dict(family="bim", name="bim1", d=1, lam=0.1, T=1.0, R=1.0, W=5.0, depth=1.5,
                     width=None, centre=-1.0, L=[3.0], n=[121], x0=[0.5])  # fmt: skip
    P["bim1s"] = dict(family="bim", name="bim1s", d=1, lam=0.1, T=1.0, R=1.0, W=5.0, depth=0.9,
                      width=None, centre=-1.0, L=[3.0], n=[121], x0=[0.5])  # fmt: skip
    # a narrow deep dip between the nodes of a 61-node grid (spacing 0.1, dip σ 0.03 at −1.05)
    P["bimn"] = dict(family="bim", name="bimn", d=1, lam=0.1, T=1.0, R=1.0, W=5.0, depth=2.0,
                     width=0.03, centre=-1.05, L=[3.0], n=[61], x0=[0.5])  # fmt: skip
    return P


def bim_terminal(spec):
    W, D, c, w = spec["W"], spec["depth"], spec["centre"], spec["width"]

    def g(x):
        x = np.asarray(x, float)[..., 0]
        if w is None:  # two quadratic wells, the one at c deeper by D
            return np.minimum(W * (x - 1.0) ** 2, W * (x - c) ** 2 - D)
        return (
            W * (x - 1.0) ** 2 * 0.0
            + W * np.minimum((x - 1.0) ** 2, 1.0)
            - (D + W) * np.exp(-((x - c) ** 2) / (2 * w**2))
        )

    return g


def bim_truth(spec):
    lam, T, R = spec["lam"], spec["T"], spec["R"]
    sd = math.sqrt(lam * T / R)
    w = np.linspace(-12 * sd, 12 * sd, 400001)
    g = bim_terminal(spec)(spec["x0"][0] + w[:, None])
    a = -(w**2) / (2 * sd**2) - g / lam
    top = a.max()
    z = np.trapezoid(np.exp(a - top), w) / (math.sqrt(2 * math.pi) * sd)
    return float(-lam * (top + math.log(z)))


def bim_single_spec(spec):
    """The LQ problem of the near well alone (goal +1): its exact policy misses the far well."""
    return _lq(spec["name"] + "_near", [[0.0]], [[1.0]], [[spec["R"]]], [[0.0]], [0.0],
               [[spec["W"]]], [1.0], spec["lam"], spec["T"], spec["L"], spec["n"], spec["x0"])  # fmt: skip


_BUILT: dict = {}


def build(spec):
    """The Problem (cached per name: ``proposal="auto"`` solves once per problem object)."""
    if spec["name"] in _BUILT:
        return _BUILT[spec["name"]]
    if spec["family"] == "lq":
        if spec.get("pointmass"):
            axes = [Axis(-L, L, n) for L, n in zip(spec["L"], spec["n"])]
            prob = Problem(
                PointMass(spec["pointmass"]),
                Grid(axes),
                spec["T"],
                terminal_cost=Quadratic(spec["cT"], spec["WT"]),
                state_cost=Quadratic(spec["cq"], spec["Wq"]),
                control_cost=np.array(spec["R"]),
                temperature=spec["lam"],
            )
        else:
            prob = build_lq(spec)
    elif spec["family"] == "bim":
        prob = Problem(
            LinearSystem([[0.0]], [[1.0]]),
            Grid([Axis(-spec["L"][0], spec["L"][0], spec["n"][0])]),
            spec["T"],
            terminal_cost=bim_terminal(spec),
            control_cost=np.array([[spec["R"]]]),
            temperature=spec["lam"],
        )
    else:
        d = spec["d"]
        lo, hi = spec["L"]
        axes = [Axis(lo, hi, spec["n"][0])] + [Axis(-3.0, 3.0, n) for n in spec["n"][1:]]
        R = np.diag([spec["R"]] + [1.0] * (d - 1))
        q0 = spec["q0"]
        prob = Problem(
            LinearSystem(np.zeros((d, d)), np.eye(d)),
            Grid(axes),
            None,
            state_cost=lambda x, q0=q0: q0 + 0.0 * x[:, 0],
            control_cost=R,
            temperature=spec["lam"],
            exit=lambda x: x[:, 0] >= 1.0,
            exit_cost=0.0,
        )
    _BUILT[spec["name"]] = prob
    return prob


def truth(spec):
    if spec["family"] == "lq":
        return float(lq_value(spec, np.array([spec["x0"]]), 0.0)[0])
    if spec["family"] == "bim":
        return bim_truth(spec)
    return math.sqrt(2 * spec["q0"] * spec["R"]) * (1.0 - spec["x0"][0])


# ================= the discrete chain's exact value ==============================================
def chain_value(spec, K):
    """v of the Euler–Maruyama chain x' = x + A x Δt + B ε, ε ~ N(0, λR⁻¹Δt), with state cost q(x)Δt
    at the left point and g at step K: −λ log E₀[exp(−(Σ q Δt + g)/λ)], by a backward recursion of
    Gaussian integrals of exp(−(½xᵀMx + bᵀx + c)) (= z)."""
    A, B, R = (np.asarray(spec[k], float) for k in ("A", "B", "R"))
    Wq, WT = np.asarray(spec["Wq"], float), np.asarray(spec["WT"], float)
    cq, cT = np.asarray(spec["cq"], float), np.asarray(spec["cT"], float)
    lam, T = spec["lam"], spec["T"]
    d = A.shape[0]
    dt = T / K
    Sig = lam * dt * B @ np.linalg.solve(R, B.T)
    F = np.eye(d) + A * dt
    M, b, c = 2 * WT / lam, -2 * WT @ cT / lam, cT @ WT @ cT / lam
    eye = np.eye(d)
    for _ in range(K):
        G = Sig @ np.linalg.inv(eye + M @ Sig)
        G = 0.5 * (G + G.T)
        _, logdet = np.linalg.slogdet(eye + Sig @ M)
        Mn = M - M @ G @ M
        bn = b - M @ G @ b
        c = c - 0.5 * b @ G @ b + 0.5 * logdet + cq @ Wq @ cq * dt / lam
        M = F.T @ Mn @ F + 2 * Wq * dt / lam
        b = F.T @ bn - 2 * Wq @ cq * dt / lam
        M = 0.5 * (M + M.T)
    x = np.asarray(spec["x0"], float)
    return float(lam * (0.5 * x @ M @ x + b @ x + c))


# ================= policies =======================================================================
def riccati_path(spec, goal_shift=0.0):
    """t ↦ (P(t), p(t)) of the LQ spec (terminal and state centres moved by ``goal_shift``)."""
    A, B, R = (np.asarray(spec[k], float) for k in ("A", "B", "R"))
    Wq, WT = np.asarray(spec["Wq"], float), np.asarray(spec["WT"], float)
    cq = np.asarray(spec["cq"], float) + goal_shift
    cT = np.asarray(spec["cT"], float) + goal_shift
    d = A.shape[0]
    Sm = B @ np.linalg.solve(R, B.T)

    def rhs(tau, y):
        P, p = y[: d * d].reshape(d, d), y[d * d :]
        dP = A.T @ P + P @ A - P @ Sm @ P + 2 * Wq
        dp = (A - Sm @ P).T @ p - 2 * Wq @ cq
        return np.concatenate([dP.ravel(), dp])

    y0 = np.concatenate([(2 * WT).ravel(), -2 * WT @ cT])
    sol = solve_ivp(rhs, (0.0, spec["T"]), y0, rtol=1e-10, atol=1e-12, dense_output=True)

    def at(t):
        y = sol.sol(min(max(spec["T"] - t, 0.0), spec["T"]))
        return y[: d * d].reshape(d, d), y[d * d :]

    return at


def noise_scale(spec):
    B, R = np.asarray(spec["B"], float), np.asarray(spec["R"], float)
    Sm = B @ np.linalg.solve(R, B.T)
    return math.sqrt(spec["lam"] * np.trace(Sm) * spec["T"] / spec["d"])


def lq_policy(spec, gain=1.0, goal_shift=0.0):
    at = riccati_path(spec, goal_shift)
    B, R = np.asarray(spec["B"], float), np.asarray(spec["R"], float)
    Kb = np.linalg.solve(R, B.T)
    cache = {}

    def policy(x, t):
        key = round(float(t), 12)
        if key not in cache:
            cache[key] = at(float(t))
        P, p = cache[key]
        return -gain * (np.asarray(x) @ P.T + p) @ Kb.T

    return policy


def away_policy(spec, kappa):
    """A constant control of KL ≈ κ²/2 nats pointing away from the goal (in control space)."""
    B, R = np.asarray(spec["B"], float), np.asarray(spec["R"], float)
    direction = B.T @ (np.asarray(spec["cT"]) - np.asarray(spec["x0"]))
    if np.linalg.norm(direction) < 1e-9:
        direction = np.ones(B.shape[1])
    e = direction / math.sqrt(direction @ R @ direction)
    u = -kappa * math.sqrt(spec["lam"] / spec["T"]) * e  # ½uᵀRu T/λ = κ²/2
    return lambda x, t: np.tile(u, (len(x), 1))


def coarse_policy(spec, nodes=13):
    prob = build(spec)
    axes = [Axis(a.lo, a.hi, nodes, a.periodic, a.name) for a in prob.grid.axes]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = gridlbc.solve(prob.replace(grid=Grid(axes)))

    def policy(x, t):
        return np.nan_to_num(sol.policy(x, t), nan=0.0, posinf=0.0, neginf=0.0)

    return policy


def exit_policy(spec, kind):
    d, q0, R = spec["d"], spec["q0"], spec["R"]
    speed = math.sqrt(2 * q0 / R)  # u* = −R⁻¹ v′ (on x₀)
    s = {"exact": 1.0, "g0.5": 0.5, "g3": 3.0, "other": 2.0, "zero": 0.0, "away": -1.0}[kind]
    u = np.zeros(d)
    u[0] = s * speed
    return lambda x, t: np.tile(u, (len(x), 1))


LQ_POLICIES = ("exact", "zero", "g0.1", "g0.5", "g3", "coarse", "other", "away4", "away8")
EXIT_POLICIES = ("exact", "zero", "g0.5", "g3", "away", "coarse")
BIM_POLICIES = ("near", "near0.5", "zero", "coarse", "grid")


def make_policy(spec, kind):
    if kind == "grid":  # the problem's own default solve: what certify is there to check
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return gridlbc.solve(build(spec)).policy
    if kind == "coarse":
        return coarse_policy(spec)
    if spec["family"] == "exit":
        return exit_policy(spec, kind)
    if spec["family"] == "bim":
        if kind == "zero":
            return lambda x, t: np.zeros((len(x), 1))
        near = bim_single_spec(spec)
        return lq_policy(near, gain={"near": 1.0, "near0.5": 0.5}[kind])
    if kind == "exact":
        return lq_policy(spec)
    if kind == "zero":
        return lambda x, t: np.zeros((len(x), len(spec["R"])))
    if kind.startswith("g"):
        return lq_policy(spec, gain=float(kind[1:]))
    if kind == "other":
        return lq_policy(spec, goal_shift=3 * noise_scale(spec))
    if kind.startswith("away"):
        return away_policy(spec, float(kind[4:]))
    raise ValueError(kind)


# ================= configs ========================================================================
def configs():
    """name → (problem, policy kind, proposal, n, steps or None, seeds)."""
    out = {}
    for pname, spec in problems().items():
        kinds = {"exit": EXIT_POLICIES, "bim": BIM_POLICIES}.get(spec["family"], LQ_POLICIES)
        for kind in kinds:
            for prop in ("none", "auto"):
                for n in (200, 1000, 4000):
                    seeds = 20 if n < 4000 else 10
                    out[f"{pname}-{kind}-{prop}-n{n}"] = (pname, kind, prop, n, None, seeds)
        # explicit steps
        if spec["family"] == "bim":
            continue
        if spec["family"] == "lq":
            for K in (30, 100, 1000):
                for kind in ("exact", "g0.5"):
                    out[f"{pname}-{kind}-none-n1000-K{K}"] = (pname, kind, "none", 1000, K, 10)
        else:
            for dt in (0.04, 0.0025):
                for kind in ("exact", "g0.5"):
                    out[f"{pname}-{kind}-none-n1000-dt{dt}"] = (pname, kind, "none", 1000, dt, 10)
    return out


def run(name, cfg):
    pname, kind, prop, n, steps, nseeds = cfg
    spec = problems()[pname]
    prob = build(spec)
    vt = truth(spec)
    try:
        pol = make_policy(spec, kind)
    except ValueError as e:  # e.g. no grid solve of a problem with cross-diffusion
        rec = dict(name=name, cfg=list(cfg), truth=vt, lam=spec["lam"], skipped=str(e)[:300])
        OUT.mkdir(parents=True, exist_ok=True)
        (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1))
        return rec
    x0 = np.array(spec["x0"])
    kw = dict(boundary="free", richardson=True, progress=False)
    if spec["family"] == "lq":
        K = steps or 300
        kw["dt"] = spec["T"] / K
        vchain = chain_value(spec, K)
        vchain2 = chain_value(spec, K // 2) if K % 2 == 0 else None
    elif spec["family"] == "bim":
        kw["dt"] = spec["T"] / 300
        vchain, vchain2 = vt, vt  # ẋ = u, q = 0: the chain is exact
    else:
        kw["dt"] = steps or spec["dt"]
        kw["max_time"] = spec["max_time"]
        vchain = vchain2 = None
    runs = []
    t0 = time.time()
    for seed in range(nseeds):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            try:
                c = gridlbc.certify(
                    prob,
                    pol,
                    x0,
                    n_samples=n,
                    seed=1000 * seed,
                    proposal=None if prop == "none" else "auto",
                    **kw,
                )
            except Exception as e:  # report, do not stop
                runs.append(dict(seed=seed, error=f"{type(e).__name__}: {e}"))
                continue
        cw = [str(x.message)[:300] for x in w if issubclass(x.category, gridlbc.CertificateWarning)]
        other = [
            f"{x.category.__name__}: {str(x.message)[:200]}"
            for x in w
            if not issubclass(x.category, gridlbc.CertificateWarning)
        ]
        runs.append(
            dict(
                seed=seed,
                v=c.optimal_value,
                se=c.optimal_value_se,
                ext=c.extrapolated_value,
                ext_se=c.extrapolated_value_se,
                ess=c.effective_sample_size,
                k=c.pareto_k,
                trusted=bool(c.trusted),
                unexited=float(c.unexited_fraction),
                J=c.policy_cost,
                proposals=list(c.proposals),
                pvals=None if c.proposal_values is None else np.asarray(c.proposal_values).tolist(),
                warnings=cw,
                other_warnings=other,
            )
        )
    rec = dict(
        name=name,
        cfg=list(cfg),
        truth=vt,
        chain=vchain,
        chain2=vchain2,
        lam=spec["lam"],
        dt=kw["dt"],
        seconds=time.time() - t0,
        runs=runs,
    )
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{name}.json").write_text(json.dumps(rec, indent=1, default=float))
    return rec


# ================= table ==========================================================================
def classify(rec, r, value="v", se="se", ref=None):
    ref = rec["truth"] if ref is None else ref
    if r.get(value) is None or not r.get(se) or not np.isfinite(r[se]) or r[se] <= 0:
        z = math.inf if r.get(value) is not None and r[value] != ref else 0.0
    else:
        z = (r[value] - ref) / r[se]
    rel = abs(r[value] - ref) / max(abs(ref), rec["lam"])
    if value == "v":  # what a plain certify call (no richardson) says: the fine run's own flags
        warned = not r["trusted"] or r["unexited"] > 0.01
    else:  # richardson=True also warns about the 2Δt run (its flags are not in the Certificate)
        warned = bool(r["warnings"]) or not r["trusted"]
    if abs(z) <= 3 or warned:
        cls = "OK"
    elif abs(z) > 4:
        cls = "SILENT" if rel >= 0.005 else "silent-tiny"
    else:
        cls = "grey"
    return z, rel, warned, cls


def summarize(rec):
    runs = [r for r in rec["runs"] if "error" not in r]
    out = dict(name=rec["name"], errors=len(rec["runs"]) - len(runs), n=len(runs))
    if not runs:
        return out
    for tag, value, se, ref in (
        ("v", "v", "se", None),
        ("chain", "v", "se", rec["chain"]),
        ("ext", "ext", "ext_se", None),
    ):
        if tag == "chain" and ref is None:
            continue
        cl = [classify(rec, r, value, se, ref) for r in runs]
        zs = np.array([c[0] for c in cl])
        out[tag] = dict(
            big=float(np.mean(np.abs(zs) > 3)),
            meanz=float(np.mean(zs[np.isfinite(zs)])) if np.isfinite(zs).any() else math.nan,
            worst_rel=float(max(c[1] for c in cl)),
            silent=int(sum(c[3] == "SILENT" for c in cl)),
            silent_tiny=int(sum(c[3] == "silent-tiny" for c in cl)),
        )
    out["warned"] = float(np.mean([not r["trusted"] or r["unexited"] > 0.01 for r in runs]))
    out["warned_rich"] = float(np.mean([bool(r["warnings"]) or not r["trusted"] for r in runs]))
    out["ess_min"] = float(min(r["ess"] for r in runs))
    out["k_max"] = float(np.nanmax([r["k"] for r in runs])) if runs else math.nan
    return out


def table():
    recs = [json.loads(f.read_text()) for f in sorted(OUT.glob("*.json"))]
    hdr = (
        f"{'config':34s} {'|z|>3':>6s} {'mean z':>7s} {'relmax':>8s} {'warn':>5s} "
        f"{'zc>3':>5s} {'mzc':>6s} {'ext>3':>6s} {'mz ext':>7s} {'relext':>7s} "
        f"{'ESSmin':>7s} {'kmax':>5s} S/s"
    )
    print(hdr)
    silent = []
    for rec in recs:
        if "skipped" in rec:
            print(f"{rec['name']:34s} SKIPPED: {rec['skipped'][:60]}")
            continue
        s = summarize(rec)
        if "v" not in s:
            print(f"{s['name']:34s} ALL ERRORS")
            continue
        v, e = s["v"], s["ext"]
        c = s.get("chain", dict(big=math.nan, meanz=math.nan))
        print(
            f"{s['name']:34s} {v['big']:6.2f} {v['meanz']:7.2f} {v['worst_rel']:8.2e} "
            f"{s['warned']:5.2f} {c['big']:5.2f} {c['meanz']:6.2f} {e['big']:6.2f} "
            f"{e['meanz']:7.2f} {e['worst_rel']:7.1e} {s['ess_min']:7.1f} {s['k_max']:5.2f} "
            f"{v['silent']}/{e['silent']}/{c.get('silent', '-')}"
            + (f" ERR {s['errors']}" if s["errors"] else "")
        )
        if v["silent"] or e["silent"] or c.get("silent"):
            silent.append((rec["name"], v["silent"], e["silent"], c.get("silent"), s["n"]))
    print(
        "\nSILENT (|z|>4, no warning, trusted, rel >= 0.5 %): name, plain, richardson, "
        "vs the chain's own value, of runs"
    )
    for row in silent:
        print("  ", row)


def selftest():
    P = problems()
    for name, spec in P.items():
        if spec["family"] != "lq":
            continue
        at = riccati_path(spec)
        Pm, _p = at(0.0)
        x = np.array(spec["x0"])
        print(
            name,
            "truth",
            truth(spec),
            "chain K=300",
            chain_value(spec, 300),
            "K=3000",
            chain_value(spec, 3000),
            "P(0) check",
            np.abs(
                Pm
                - np.asarray(
                    __import__("strangers_round25").riccati(
                        spec["A"],
                        spec["B"],
                        spec["R"],
                        spec["Wq"],
                        spec["cq"],
                        spec["WT"],
                        spec["cT"],
                        spec["lam"],
                        spec["T"],
                    )[0]
                )
            ).max(),
            "x0",
            x,
        )


def main(argv):
    if "--list" in argv:
        for k, v in configs().items():
            print(k, v)
    elif "--selftest" in argv:
        selftest()
    elif "--table" in argv:
        table()
    elif "--run" in argv or "--all" in argv:
        cf = configs()
        if "--run" in argv:
            names = argv[argv.index("--run") + 1 :]
        else:  # the n = 1000 runs first, then the explicit steps, n = 4000 and n = 200
            order = {"n1000": 0, "K": 1, "dt": 1, "n4000": 2, "n200": 3}
            names = sorted(cf, key=lambda k: min(v for t, v in order.items() if t in k))
        for name in names:
            if "--all" in argv and (OUT / f"{name}.json").exists():
                continue
            rec = run(name, cf[name])
            if "skipped" in rec:
                print(name, "skipped", rec["skipped"][:100], flush=True)
                continue
            s = summarize(rec)
            print(name, f"{rec['seconds']:.1f}s", json.dumps(s, default=float), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
