"""Stranger round 28: the SOLVER OPTIONS a user may pick (public API only; SPEC §1, §3, §6, §7, §10).

RESULTS (library of r28 = main 539bf40, 2026-12-06, one thread, ``--run --force`` then
``--table``; ``--scan`` and ``--certify-store3`` afterwards):

17 hand-posed problems (4 LQ + PointMass ×2 with Riccati truth: λ 0.02–2, one 3-D; 8 separable
nonlinear with 1-D truths (backward Euler on 8001 nodes, Richardson in the step, CN as the ±),
one 3-D, λ 0.02–2, a dip 0.5 cell wide in g (sep_narrow), a bump 0.5 cell wide in q
(sep_narrowq); 2 stationary first exits (fe2, fe_band with a band 1.2 cells wide at λ = 0.05)
and one exit with a horizon (hzfe2); 2 catalogue ``Pendulum(damping=0.1)`` swing problems at
λ = 0.5 and 0.1, certified with the policy of a 2×-finer default solve, 2000 paths, Richardson,
ESS 1860–2000, k̂ ≤ 0.47: none untrusted) × 28 horizon options (+ 11 invalid ones on lq_pm and
pend) or 20 stationary ones. 3 states each (typical, at the feature / goal, far), read at t = 0,
mid-task between steps (round(T/2Δt)Δt + 1.5Δt) and T − 2.5Δt (Δt the default's).

Rerun after the fixes (main, 2026-12-06: τ read in the middle of every interval between stored
slices; ``--run pend --only=store3 --force`` and ``--only=mmap_store3``): pend with
store_every=3 warns, with and without mmap_dir (at t = 0.397, between the stored slices), the
same errors and estimates as below, and mmap_dir raises no ResourceWarning; ``--table``: none
silent. The presets now solve hzfe2, the exit with a horizon, by the implicit march, and
linear_solver with the splitting is refused (tests in tests/core; not rerun here).

- 467 (problem, option) entries; 3546 (problem, option, state, t) pairs read; 3405 with an
  estimate (error_estimate=False: 141 pairs without), all with a trusted truth.
- pairs > 10 % off: 508; SILENT (> 10 %, no GridlbcWarning): 2, one pair in two entries —
  ``pend``, ``store_every=3`` (and the same with ``mmap_dir``), x = (0.6, −0.5), t = 1.2794:
  v 0.9494 vs v* 0.8549 (11.1 %), ê 0.0894 (covers ½ err). ``--scan`` then found the same
  solve 15 % off at t = 1.2132 and 1.1912, certified (``--certify-store3``): v 1.2251 vs v*
  1.0597 ± 0.0005 and v 1.3167 vs 1.1473 ± 0.0005 (ESS 1999, k̂ −0.12 / −0.20), ê 0.151 /
  0.171; the solve raised no warning at all (store_every 2 and 5 of the same problem warn).
- ``--scan`` (store_every 2, 3, 5 read every Δt/4 against a Δt/4 solve; screening, finished for
  10 of the 15 horizon problems, stopped at the time box: each ``error_estimate`` call there took
  0.5–1.2 s on sep_narrowq, whose 1.3 s solve has 179 steps): all the other store_every solves
  warned (worst 1–58 % off the Δt/4 solve, e.g. pm_cold store 5 at t = 1.01: 6.31 vs 4.19); pend
  store 3 is the only silent one.
- coverage ê ≥ ½|v − v*|: 3352 / 3405 (98.4 %); per option the lowest: settings_obj
  (store_every=4, float32) 122/126, dt_x4 130/135, store3 131/135, courant3 131/135,
  fit_terminal 123/126, default 138/141; implicit / reference / dt_half / dt_quarter 135/135.
- under-reads (ê < ½ err, err > 2 %): 8, all in warned entries, e.g. lq_pm store_every=10
  (0.5, 0.05) t = 1.3: v 0.2563 vs 0.2201 (12.1 %), ê 0.0150; sep_hot fitting=None dt×2
  (1, 1) t = 0.65: 1.9642 vs 2.1627 (9.2 %), ê 0.0116; sep_per dt×4 (2.05, 0.4) t = 0:
  0.8964 vs 0.9367 (4.3 %), ê 0.0053; lq_hot store_every 3/5 at the far state (4.3–4.7 %).
- error_estimate=False: the solve warns of nothing (sep_narrow (0.41, 0.2) t = 1.125: 12.8 %
  off, silent; the default solve of it warns) and ``error_estimate(x, t)`` raises ValueError.
- Options as a user meets them: ``settings="fast"`` took 0.5–1.0× the default's Δt (min_steps
  20 against the fitted default's 10) and a median 1.19× its time: the "fast" preset is slower
  and more accurate than the default on these problems. ``settings="reference"`` is the implicit
  scheme at Courant 1: median error 9.3 % against the default's 0.62 %, worst 76 % (all warned):
  the "reference" preset is the least accurate choice. fit_terminal = default (auto). On a
  problem with an exit set and a horizon ``settings="fast"``, ``solve(p, "fast")`` and a
  ``SolverSettings()`` raise "method='splitting' does not implement an exit set … with
  method='implicit'" although the user never named a method (the default picks implicit there).
  ``linear_solver="gauss-seidel"`` with the splitting scheme is ignored without a word.
  ``fitting=<a user cost>`` (half g) at λ 0.02–0.05 raises UnderflowWarnings about "4605 of
  14641 query states … value is +inf there" while every state the user read is finite (they
  are the estimate's internal queries), plus stray RuntimeWarnings.
- Stray non-gridlbc warnings: ``mmap_dir``: ResourceWarning "unclosed file
  <_io.BufferedRandom name=3>" 2–7 per solve (``gridlbc/storage.py:77``
  ``tempfile.TemporaryFile`` handed to ``np.memmap`` and never closed, attributed to
  ``schemes/protocol.py:133``); pm_cold ``fitting=<cost>``: RuntimeWarning "invalid value
  encountered in subtract" at ``gridlbc/accuracy/bellman.py:321`` and ``:327`` (inf − inf in
  the Hessian stencil where v underflowed).
- Errors with clear messages (all ValueError/TypeError, none crashed): dtype float16,
  store_every 0, dt > T, dt < 0, method "explicit", unknown option "tolerance" (the list of
  valid options omits ``tol``), fitting "bogus", preset "accurate", missing mmap_dir, courant 0,
  method implicit + fitting "terminal" ("use one of those methods" names one), stationary +
  method / dtype / dt / "fast" ("method do not apply"), stationary linear_solver gauss-seidel,
  defect_correction without fit_exit.

    cd /work/wt-r28 && PYTHONPATH=/work/wt-r28 NUMBA_NUM_THREADS=1 \
        python benchmarks/holdout/strangers_round28.py --list | --run [NAMES] | --table
"""

from __future__ import annotations

import json
import math
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.systems import LinearSystem, Pendulum, PointMass

OUT = Path("/work/main/benchmarks/holdout/strangers_round28_results")  # gitignored there


# ================= from round 25: Riccati, the 1-D references, the separable problems ==========
from strangers_round25 import (  # noqa: E402  (the folder is the script's own)
    build_sep,
    lq_value,
    sep_truth,
)


# ================= the base problems (hand-posed) ==============================================
def _ax(lo, hi, n, a, q, g, b0=1.0, R=1.0, periodic=False, feats=()):
    return dict(
        lo=lo,
        hi=hi,
        n=n,
        periodic=periodic,
        a=a,
        b=[["ripple", b0, 0.2, 1.0, 0.4]],
        q=q,
        g=g,
        R=R,
        feats=list(feats),
    )


PI = math.pi


def problems():
    P = {}
    # --- LQ, Riccati truth -------------------------------------------------------------------
    P["lq_pm"] = dict(
        family="lq",
        catalogue="PointMass",
        A=[[0, 1], [0, 0]],
        B=[[0], [1]],
        R=[[1.0]],
        Wq=[[0.5, 0], [0, 0.1]],
        cq=[0, 0],
        WT=[[2.0, 0], [0, 0.5]],
        cT=[0.5, 0],
        lam=0.3,
        T=2.0,
        L=[5.0, 6.0],
        n=[101, 101],
        X=[[-1.0, 0.5], [0.5, 0.05], [-2.5, -2.0]],
        invalid=True,
    )
    P["pm_cold"] = dict(
        family="lq",
        catalogue="PointMass",
        A=[[0, 1], [0, 0]],
        B=[[0], [1]],
        R=[[0.5]],
        Wq=[[1.0, 0], [0, 0.2]],
        cq=[0, 0],
        WT=[[5.0, 0], [0, 1.0]],
        cT=[-0.4, 0.2],
        lam=0.05,
        T=1.5,
        L=[3.0, 4.0],
        n=[121, 121],
        X=[[0.8, -0.5], [-0.42, 0.18], [-1.8, 2.0]],
    )
    P["lq_cold"] = dict(
        family="lq",
        A=[[-0.3, 0.8], [-0.5, -0.2]],
        B=[[1.0, 0], [0, 0.7]],
        R=[[1.0, 0], [0, 2.0]],
        Wq=[[1.0, 0.3], [0.3, 0.5]],
        cq=[0, 0],
        WT=[[4.0, 0], [0, 4.0]],
        cT=[0.3, -0.2],
        lam=0.02,
        T=1.0,
        L=[2.5, 2.5],
        n=[121, 121],
        X=[[-0.6, 0.4], [0.32, -0.18], [1.3, -1.2]],
    )
    P["lq_hot"] = dict(
        family="lq",
        A=[[0.2, 1.0], [-1.0, -0.1]],
        B=[[0], [1.2]],
        R=[[0.5]],
        Wq=[[0.2, 0], [0, 0.2]],
        cq=[0, 0],
        WT=[[1.0, 0], [0, 0.3]],
        cT=[-0.5, 0.5],
        lam=2.0,
        T=3.0,
        L=[8.0, 9.0],
        n=[81, 91],
        X=[[1.0, -1.0], [-0.4, 0.6], [-3.5, 3.5]],
    )
    P["lq3"] = dict(
        family="lq",
        A=[[-0.5, 1.0, 0], [0, -0.2, 1.0], [0, 0, -0.4]],
        B=[[1.0, 0], [0, 0], [0, 1.0]],
        R=[[1.0, 0], [0, 0.5]],
        Wq=[[0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.2]],
        cq=[0, 0, 0],
        WT=[[1.0, 0, 0], [0, 1.0, 0], [0, 0, 0.5]],
        cT=[0.3, -0.3, 0],
        lam=0.5,
        T=1.5,
        L=[3.5, 3.5, 3.5],
        n=[41, 41, 41],
        X=[[0.5, 0.5, -0.5], [0.3, -0.25, 0.05], [-1.6, 1.5, 1.5]],
    )
    # --- separable nonlinear, 1-D truths -------------------------------------------------------
    P["sep_per"] = dict(
        family="sep",
        kind="hz",
        d=2,
        lam=0.1,
        T=2.0,
        axes=[
            _ax(
                -PI,
                PI,
                96,
                [["sin", -0.8, 1.0, 0.3]],
                [["cos", 0.5, 1.0, 1], ["bump", 1.0, 2.0, 0.2]],
                [["cos", 1.5, -0.5, 1]],
                b0=1.2,
                R=0.8,
                periodic=True,
                feats=[2.0],
            ),
            _ax(
                -2.5,
                2.5,
                101,
                [["tanh", 0.8, 0.3, 0.5], ["lin", -0.4, 0.0]],
                [["quad", 0.3, 0.2]],
                [["quad", 1.0, 0.4]],
                b0=0.9,
                R=1.5,
            ),
        ],
        X=[[0.5, -0.6], [2.05, 0.4], [-2.8, 2.2]],
    )
    P["sep_narrow"] = dict(
        family="sep",
        kind="hz",
        d=2,
        lam=0.05,
        T=1.5,
        axes=[
            _ax(
                -2.0,
                2.0,
                81,
                [["lin", -0.3, 0.0]],
                [["quad", 0.2, 0.0]],
                [["quad", 0.5, -0.3], ["dip", 0.3, 0.41, 0.025]],
                feats=[0.41],
            ),
            _ax(
                -2.0, 2.0, 81, [["sin", 0.5, 1.5, 0.2]], [["quad", 0.3, 0.1]], [["quad", 0.8, 0.2]]
            ),
        ],
        X=[[-0.4, 0.3], [0.41, 0.2], [-1.7, -1.6]],
    )
    P["sep_wall"] = dict(
        family="sep",
        kind="hz",
        d=2,
        lam=1.0,
        T=3.0,
        axes=[
            _ax(
                -3.0,
                3.0,
                91,
                [["cubic", 0.2, 0.0], ["sin", 0.6, 1.2, 0.5]],
                [["quad", 0.1, 0.5], ["wall", 4.0, 1.0, 0.15, 1.0]],
                [["quad", 0.4, -0.5]],
                b0=1.3,
                R=0.6,
                feats=[1.0],
            ),
            _ax(
                -3.0,
                3.0,
                81,
                [["tanh", -1.0, 0.0, 0.3]],
                [["well", 2.0, -0.5, 0.3]],
                [["quad", 0.3, 0.0]],
                feats=[-0.5],
            ),
        ],
        X=[[-0.5, 0.8], [1.02, -0.45], [2.6, 2.5]],
    )
    P["sep_hot"] = dict(
        family="sep",
        kind="hz",
        d=2,
        lam=2.0,
        T=1.0,
        axes=[
            _ax(
                -4.0,
                4.0,
                81,
                [["lin", -0.5, 0.0]],
                [["quad", 0.3, 0.0]],
                [["quad", 1.0, 1.0]],
                b0=1.5,
            ),
            _ax(
                -PI,
                PI,
                64,
                [["sin", 1.0, 1.0, 0.0]],
                [["cos", 1.0, 0.0, 1]],
                [["cos", 2.0, 1.0, 1]],
                periodic=True,
            ),
        ],
        X=[[0.3, -1.0], [1.0, 1.0], [-3.5, 3.0]],
    )
    P["sep_cold"] = dict(
        family="sep",
        kind="hz",
        d=2,
        lam=0.02,
        T=1.0,
        axes=[
            _ax(
                -2.0,
                2.0,
                121,
                [["sin", 0.7, 1.0, 0.0]],
                [["quad", 0.5, 0.2]],
                [["quad", 1.0, -0.4]],
            ),
            _ax(
                -2.0,
                2.0,
                121,
                [["lin", -0.6, 0.1]],
                [["quad", 0.3, 0.0], ["bump", 0.2, -0.3, 0.08]],
                [["quad", 2.0, 0.3]],
                b0=0.8,
                R=0.5,
                feats=[-0.3],
            ),
        ],
        X=[[0.4, 0.6], [-0.35, -0.3], [1.7, -1.7]],
    )
    P["sep3"] = dict(
        family="sep",
        kind="hz",
        d=3,
        lam=0.3,
        T=1.0,
        axes=[
            _ax(-2.5, 2.5, 41, [["lin", -0.5, 0.0]], [["quad", 0.4, 0.0]], [["quad", 1.0, 0.5]]),
            _ax(
                -PI,
                PI,
                36,
                [["sin", 0.7, 1.0, 0.5]],
                [["cos", 0.6, 0.5, 1]],
                [["cos", 1.0, 0.0, 1]],
                periodic=True,
            ),
            _ax(
                -2.0,
                2.0,
                31,
                [["tanh", 0.6, 0.0, 0.4]],
                [["quad", 0.2, 0.0], ["bump", 1.0, 0.6, 0.25]],
                [["quad", 0.5, -0.3]],
                feats=[0.6],
            ),
        ],
        X=[[0.3, 0.4, -0.4], [0.5, 0.0, 0.62], [-2.2, 2.8, 1.8]],
    )
    # --- first exit ----------------------------------------------------------------------------
    fe0 = _ax(
        -2.0, 2.0, 101, [["lin", -0.3, 0.0]], [["quad", 0.3, 0.0], ["const", 0.2]], [], b0=1.0
    )
    fe1 = _ax(-2.0, 2.0, 61, [["sin", 0.6, 1.0, 0.0]], [["const", 0.0]], [["const", 0.0]])
    P["fe2"] = dict(
        family="sep",
        kind="fe",
        d=2,
        lam=0.2,
        T=None,
        axes=[fe0, fe1],
        exit=dict(type="half", c=1.2, cost=0.5),
        X=[[-0.5, 0.3], [1.05, -0.5], [-1.6, 1.5]],
    )
    he0 = _ax(
        -2.5,
        2.5,
        121,
        [["tanh", -0.5, 0.0, 0.5]],
        [["quad", 0.2, 0.0]],
        [["quad", 1.0, 0.0]],
        b0=0.8,
    )
    he1 = _ax(-2.0, 2.0, 41, [["lin", -0.2, 0.0]], [["const", 0.0]], [["const", 0.0]])
    P["hzfe2"] = dict(
        family="sep",
        kind="hzfe",
        d=2,
        lam=0.1,
        T=2.0,
        axes=[he0, he1],
        exit=dict(type="band", c1=0.9, c2=1.05, cost=0.1, low=-2.0, lowcost=2.0),
        X=[[0.0, 0.3], [0.8, -0.5], [-1.6, 1.5]],
    )
    # --- catalogue pendulum, certified ---------------------------------------------------------
    P["pend"] = dict(
        family="pend",
        lam=0.5,
        T=1.5,
        n=[96, 101],
        W=8.0,
        X=[[0.6, -0.5], [0.1, 0.2], [2.6, 3.0]],
        invalid=True,
    )
    P["sep_narrowq"] = dict(
        family="sep",
        kind="hz",
        d=2,
        lam=0.1,
        T=2.0,
        axes=[
            _ax(
                -2.0,
                2.0,
                81,
                [["lin", -0.4, 0.0], ["sin", 0.5, 2.0, 0.3]],
                [["quad", 0.3, 0.0], ["bump", 1.5, -0.2, 0.02]],
                [["quad", 0.8, 0.3]],
                feats=[-0.2],
            ),
            _ax(
                -2.0, 2.0, 61, [["tanh", 0.5, 0.0, 0.5]], [["quad", 0.2, 0.0]], [["quad", 0.5, 0.0]]
            ),
        ],
        X=[[0.6, 0.5], [-0.19, -0.2], [-1.7, 1.7]],
    )
    fb0 = _ax(
        -2.0, 2.0, 121, [["sin", 0.5, 1.5, 0.0]], [["quad", 0.2, -0.5], ["const", 0.1]], [], b0=0.9
    )
    fb1 = _ax(-1.5, 1.5, 31, [["lin", -0.5, 0.0]], [["const", 0.0]], [["const", 0.0]])
    P["fe_band"] = dict(
        family="sep",
        kind="fe",
        d=2,
        lam=0.05,
        T=None,
        axes=[fb0, fb1],
        exit=dict(type="band", c1=0.6, c2=0.65, cost=0.05, low=-1.6, lowcost=1.5),
        X=[[0.0, 0.3], [0.55, -0.5], [-1.3, 1.2]],
    )
    P["pend_cold"] = dict(
        family="pend",
        lam=0.1,
        T=1.0,
        n=[128, 121],
        W=7.0,
        X=[[0.4, 0.5], [-0.05, 0.0], [-1.5, -2.0]],
    )
    return P


def build_lq(spec):
    axes = [Axis(-L, L, n) for L, n in zip(spec["L"], spec["n"])]
    system = (
        PointMass()
        if spec.get("catalogue") == "PointMass"
        else LinearSystem(np.array(spec["A"], float), np.array(spec["B"], float))
    )
    return Problem(
        system,
        Grid(axes),
        spec["T"],
        terminal_cost=Quadratic(spec["cT"], spec["WT"]),
        state_cost=Quadratic(spec["cq"], spec["Wq"]),
        control_cost=np.array(spec["R"], float),
        temperature=spec["lam"],
    )


def build_pend(spec, refine=1):
    n0, n1 = spec["n"]
    grid = Grid(
        [
            Axis(-PI, PI, n0 * refine, periodic=True),
            Axis(-spec["W"], spec["W"], (n1 - 1) * refine + 1),
        ]
    )
    return Problem(
        Pendulum(damping=0.1),
        grid,
        spec["T"],
        terminal_cost=Quadratic([0.0, 0.0], [[2.0, 0], [0, 0.1]]),
        state_cost=Quadratic([0.0, 0.0], [[0.5, 0], [0, 0.05]]),
        control_cost=1.0,
        temperature=spec["lam"],
    )


def build(spec):
    return {"lq": build_lq, "sep": build_sep, "pend": build_pend}[spec["family"]](spec)


def pend_truth(spec, X, ts):
    fine_p = build_pend(spec, refine=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fine = gridlbc.solve(fine_p, error_estimate=False)
    res = {}
    base = build_pend(spec)
    for t in ts:
        p = base.replace(horizon=base.horizon - t)

        def pol(x, s, t=t):
            return fine.policy(x, s + t)

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = gridlbc.certify(
                p,
                pol,
                np.asarray(X),
                n_samples=2000,
                dt=min(0.004, (base.horizon - t) / 50),
                seed=28,
                richardson=True,
                progress=False,
                proposal=None,
                boundary="reflect",
            )
        ess = np.atleast_1d(np.asarray(c.effective_sample_size, float))
        if ess.ndim > 1:
            ess = ess.min(0)
        kh = np.atleast_1d(np.asarray(c.pareto_k, float))
        if kh.ndim > 1:
            kh = kh.max(0)
        res[t] = (
            np.asarray(c.extrapolated_value, float),
            np.asarray(c.extrapolated_value_se, float),
            (ess < 100) | (kh > 0.7),
            dict(ess=ess.tolist(), khat=kh.tolist(), fine_v=fine.value(np.asarray(X), t).tolist()),
        )
    return res


def truth_for(spec, X, ts):
    if spec["family"] == "lq":
        return {t: (lq_value(spec, X, t), np.zeros(len(X)), np.zeros(len(X), bool), {}) for t in ts}
    if spec["family"] == "sep":
        return sep_truth(spec, X, ts)
    return pend_truth(spec, X, ts)


# ================= the options ==================================================================
def _fit_cost(spec, p):
    """A user's own reference cost for ``fitting=<a cost>``: half the terminal cost (or the state
    cost where there is no terminal cost)."""
    g = p.terminal_cost if p.terminal_cost is not None else p.state_cost

    def ref(x):
        return 0.5 * np.asarray(g(np.asarray(x, float)), float)

    return ref


HORIZON_OPTIONS = {
    "default": lambda s, p, dt0: {},
    "implicit": lambda s, p, dt0: dict(method="implicit"),
    "implicit_gs": lambda s, p, dt0: dict(method="implicit", linear_solver="gauss-seidel"),
    "fit_none": lambda s, p, dt0: dict(fitting=None),
    "fit_terminal": lambda s, p, dt0: dict(fitting="terminal"),
    "fit_cost": lambda s, p, dt0: dict(fitting=_fit_cost(s, p)),
    "fast": lambda s, p, dt0: dict(settings="fast"),
    "reference": lambda s, p, dt0: dict(settings="reference"),
    "float32": lambda s, p, dt0: dict(dtype="float32"),
    "dt_x2": lambda s, p, dt0: dict(dt=2 * dt0),
    "dt_half": lambda s, p, dt0: dict(dt=dt0 / 2),
    "store5": lambda s, p, dt0: dict(store_every=5),
    "mmap_store3": lambda s, p, dt0: dict(mmap_dir=tempfile.gettempdir(), store_every=3),
    "fitnone_dt_x2": lambda s, p, dt0: dict(fitting=None, dt=2 * dt0),
    # second batch
    "store2": lambda s, p, dt0: dict(store_every=2),
    "store3": lambda s, p, dt0: dict(store_every=3),
    "store10": lambda s, p, dt0: dict(store_every=10),
    "dt_x4": lambda s, p, dt0: dict(dt=4 * dt0),
    "dt_quarter": lambda s, p, dt0: dict(dt=dt0 / 4),
    "courant3": lambda s, p, dt0: dict(courant=3.0),
    "min_steps200": lambda s, p, dt0: dict(min_steps=200),
    "no_estimate": lambda s, p, dt0: dict(error_estimate=False),
    "implicit_fit_terminal": lambda s, p, dt0: dict(method="implicit", fitting="terminal"),
    "fast_fit_none": lambda s, p, dt0: dict(settings="fast", fitting=None),
    "positional_fast": lambda s, p, dt0: dict(_positional="fast"),
    "settings_obj": lambda s, p, dt0: dict(
        settings=gridlbc.SolverSettings(store_every=4, dtype="float32")
    ),
    "float32_store5": lambda s, p, dt0: dict(dtype="float32", store_every=5),
}

# options a user may get wrong: run on a few problems, to read what the library says
INVALID_OPTIONS = {
    "dtype_float16": lambda s, p, dt0: dict(dtype="float16"),
    "store0": lambda s, p, dt0: dict(store_every=0),
    "dt_gt_T": lambda s, p, dt0: dict(dt=2 * p.horizon),
    "dt_neg": lambda s, p, dt0: dict(dt=-0.1),
    "bad_method": lambda s, p, dt0: dict(method="explicit"),
    "typo_option": lambda s, p, dt0: dict(tolerance=0.01),
    "fitting_bogus": lambda s, p, dt0: dict(fitting="bogus"),
    "bad_preset": lambda s, p, dt0: dict(settings="accurate"),
    "mmap_missing_dir": lambda s, p, dt0: dict(mmap_dir="/nonexistent/dir"),
    "courant_zero": lambda s, p, dt0: dict(courant=0.0),
    "linear_solver_on_splitting": lambda s, p, dt0: dict(linear_solver="gauss-seidel"),
}

STATIONARY_OPTIONS = {
    "default": {},
    "upwind": dict(rates="upwind"),
    "direct": dict(linear_solver="direct"),
    "gauss-seidel": dict(linear_solver="gauss-seidel"),
    "bicgstab": dict(linear_solver="bicgstab"),
    "bicgstab_res1e-4": dict(linear_solver="bicgstab", residual=1e-4),
    "no_fit_exit": dict(fit_exit=False),
    "defect1": dict(defect_correction=1),
    "defect2_upwind": dict(defect_correction=2, rates="upwind"),
    "fast": dict(settings="fast"),
    "implicit_na": dict(method="implicit"),
    "float32_na": dict(dtype="float32"),
    "dt_na": dict(dt=0.01),
    "gmres": dict(linear_solver="gmres"),
    "upwind_gmres": dict(rates="upwind", linear_solver="gmres"),
    "no_estimate": dict(error_estimate=False),
    "defect1_no_fit_exit": dict(defect_correction=1, fit_exit=False),
    "bicgstab_res1e-8": dict(linear_solver="bicgstab", residual=1e-8),
    "positional_fast": dict(_positional="fast"),
    "tol_typo": dict(tolerance=0.01),
}


def _split(w):
    ours = [
        dict(category=x.category.__name__, message=str(x.message)[:300])
        for x in w
        if issubclass(x.category, gridlbc.GridlbcWarning)
    ]
    stray = [
        dict(
            category=x.category.__name__,
            message=str(x.message)[:300],
            where=f"{Path(x.filename).name}:{x.lineno}",
        )
        for x in w
        if not issubclass(x.category, gridlbc.GridlbcWarning)
    ]
    return ours, stray


def _truth_cached(name, spec, X, ts):
    f = OUT / f"_truth_{name}.json"
    if f.exists():
        d = json.loads(f.read_text())
        if all(any(abs(t - float(k)) < 1e-12 for k in d) for t in ts):
            out = {}
            for t in ts:
                k = min(d, key=lambda k: abs(float(k) - t))
                out[t] = tuple(d[k][:3]) + (d[k][3],)
            return out
    tr = truth_for(spec, X, ts)
    d = {
        repr(float(t)): [
            np.asarray(v[0]).tolist(),
            np.asarray(v[1]).tolist(),
            np.asarray(v[2]).tolist(),
            v[3] if len(v) > 3 else {},
        ]
        for t, v in tr.items()
    }
    f.write_text(json.dumps(d, indent=1, default=float))
    return {
        t: tuple(np.asarray(x) for x in v[:3]) + (v[3] if len(v) > 3 else {},)
        for t, v in tr.items()
    }


def solve_with(p, opts):
    opts = dict(opts)
    settings = opts.pop("settings", None)
    positional = opts.pop("_positional", None)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            if positional is not None:
                s = gridlbc.solve(p, positional, **opts)
            elif settings is not None:
                s = gridlbc.solve(p, settings=settings, **opts)
            else:
                s = gridlbc.solve(p, **opts)
            fail = None
        except Exception as ex:
            s, fail = None, f"{type(ex).__name__}: {ex}"
    ours, stray = _split(w)
    return s, fail, ours, stray, time.perf_counter() - t0


def run(name, spec, only=None, force=False):
    OUT.mkdir(parents=True, exist_ok=True)
    p = build(spec)
    X = np.asarray(spec["X"], float)
    lam = spec["lam"]
    stationary = p.horizon is None
    # the default solve fixes the times read and the Δt the dt options scale
    s0, fail0, *_ = solve_with(p, {})
    if s0 is None:
        print(name, "default solve failed", fail0)
        return
    if stationary:
        ts, dt0 = [0.0], None
    else:
        dt0 = float(s0.diagnostics.dt)
        # t = 0, one time in mid-task between the default's steps (and between the stored slices of
        # store_every 2, 3, 5, 10), and late, T − 2.5 Δt
        mid = round(0.5 * p.horizon / dt0) * dt0 + 1.5 * dt0
        ts = [0.0, float(min(mid, p.horizon - 3.5 * dt0)), float(max(p.horizon - 2.5 * dt0, 0.0))]
    tr = _truth_cached(name, spec, X, ts)
    table = STATIONARY_OPTIONS if stationary else dict(HORIZON_OPTIONS)
    if not stationary and spec.get("invalid"):
        table.update(INVALID_OPTIONS)
    for oname, mk in table.items():
        if only and oname not in only:
            continue
        f = OUT / f"{name}__{oname}.json"
        if f.exists() and not force:
            continue
        opts = mk if stationary else mk(spec, p, dt0)
        shown = {
            k: (
                v
                if isinstance(v, (int, float, str, type(None)))
                else ("<callable>" if callable(v) else repr(v))
            )
            for k, v in opts.items()
        }
        if oname == "default":
            s, fail, ours, stray, secs = solve_with(p, {})
        else:
            s, fail, ours, stray, secs = solve_with(p, opts)
        rec = dict(
            name=name,
            option=oname,
            opts=shown,
            lam=lam,
            T=p.horizon,
            shape=list(p.grid.shape),
            dt0=dt0,
            seconds=secs,
            fail=fail,
            warnings=ours,
            stray=stray,
            warned=bool(ours),
            reads=[],
        )
        if s is not None:
            try:
                rec["dt"] = None if stationary else float(s.diagnostics.dt)
            except Exception as ex:
                rec["dt"] = repr(ex)
            for t in ts:
                with warnings.catch_warnings(record=True) as w:
                    warnings.simplefilter("always")
                    v = np.asarray(s.value(X, t), float)
                    try:
                        e = np.asarray(s.error_estimate(X, t), float)
                        efail = None
                    except Exception as ex:
                        e, efail = np.full(len(X), np.nan), f"{type(ex).__name__}: {ex}"
                eo, es = _split(w)
                vt, pm, bad, extra = tr[t]
                vt = np.asarray(vt, float)
                err = np.abs(v - vt) / np.maximum(np.abs(vt), lam)
                est = e / np.maximum(np.abs(v), lam)
                rec["reads"].append(
                    dict(
                        t=t,
                        v=v.tolist(),
                        est=e.tolist(),
                        truth=vt.tolist(),
                        pm=np.asarray(pm, float).tolist(),
                        untrusted=np.asarray(bad, bool).tolist(),
                        err_rel=err.tolist(),
                        est_rel=est.tolist(),
                        est_fail=efail,
                        eval_warnings=eo,
                        eval_stray=es,
                        extra=extra,
                    )
                )
        f.write_text(json.dumps(rec, indent=1, default=float))
        worst = max((max(r["err_rel"]) for r in rec["reads"]), default=float("nan"))
        print(
            f"{name:10s} {oname:18s} {secs:6.1f}s dt={rec.get('dt')} warned={bool(ours)} "
            f"stray={len(stray)} worst={worst:.2%} fail={fail}"
        )
        for r in rec["reads"]:
            print(
                f"    t={r['t']:.3f} err={np.round(np.array(r['err_rel']) * 100, 2).tolist()}% "
                f"est={np.round(np.array(r['est_rel']) * 100, 2).tolist()}%"
                + (f" ESTFAIL {r['est_fail']}" if r["est_fail"] else "")
            )
        for x in ours[:2]:
            print("    warn:", x["category"], x["message"][:160])
        for x in stray[:2]:
            print("    STRAY:", x["category"], x["where"], x["message"][:160])
        sys.stdout.flush()


# ================= the table ====================================================================
def table():
    recs = [json.loads(f.read_text()) for f in sorted(OUT.glob("*__*.json"))]
    specs = problems()
    n = trusted = big = silent = cover = 0
    per = {}
    silent_list, under_list, fails, strays, by_choice = [], [], [], [], []
    for r in recs:
        o = per.setdefault(r["option"], dict(n=0, cover=0, big=0, silent=0, warned=0, entries=0))
        o["entries"] += 1
        o["warned"] += bool(r["warned"])
        if r["fail"]:
            fails.append((r["name"], r["option"], r["fail"]))
        for x in r["stray"]:
            strays.append(
                (r["name"], r["option"], "solve", x["category"], x["where"], x["message"][:200])
            )
        for rd in r["reads"]:
            if rd.get("est_fail"):
                fails.append((r["name"], r["option"], "error_estimate: " + rd["est_fail"]))
            for x in rd.get("eval_stray", []):
                strays.append(
                    (r["name"], r["option"], "eval", x["category"], x["where"], x["message"][:200])
                )
            for i in range(len(rd["v"])):
                n += 1
                if rd["untrusted"][i]:
                    continue
                trusted += 1
                o["n"] += 1
                err = rd["err_rel"][i]
                errabs = abs(rd["v"][i] - rd["truth"][i])
                X = specs[r["name"]]["X"][i]
                row = (
                    r["name"],
                    r["option"],
                    X,
                    round(rd["t"], 4),
                    rd["v"][i],
                    rd["truth"][i],
                    err,
                    rd["est"][i],
                )
                if (
                    r["option"] == "no_estimate"
                ):  # no estimate to cover with, and no warning by choice
                    trusted -= 1
                    o["n"] -= 1
                    if err > 0.10 and not r["warned"]:
                        by_choice.append(row)
                    continue
                if err > 0.10:
                    big += 1
                    o["big"] += 1
                    if not r["warned"]:
                        silent += 1
                        o["silent"] += 1
                        silent_list.append(row)
                if rd["est"][i] >= 0.5 * errabs:
                    cover += 1
                    o["cover"] += 1
                elif err > 0.02:
                    under_list.append(row + (r["warned"],))
    print(
        f"entries {len(recs)}  pairs {n}  trusted {trusted}  >10% {big}  SILENT {silent}  coverage {cover}/{trusted}"
    )
    print(f"{'option':20s} entries warned  pairs cover  >10%  silent")
    for k, o in per.items():
        print(
            f"{k:20s} {o['entries']:7d} {o['warned']:6d} {o['n']:6d} {o['cover']:5d} {o['big']:5d} {o['silent']:7d}"
        )
    print("SILENT (> 10 %, no GridlbcWarning): (problem, option, x, t, v, v*, err, est)")
    for s in silent_list:
        print("   ", s)
    print("error_estimate=False (no estimate, coverage not counted), > 10 % and silent:")
    for s in by_choice:
        print("   ", s)
    print("under-reads (est < ½ err, err > 2 %): (problem, option, x, t, v, v*, err, est, warned)")
    for s in sorted(under_list, key=lambda s: -s[6]):
        print("   ", s)
    print("failures / exceptions:")
    for f in fails:
        print("   ", f)
    print("stray (non-gridlbc) warnings:")
    for s in strays:
        print("   ", s)
    print("untrusted truths:")
    for r in recs:
        if r["option"] != "default":
            continue
        for rd in r["reads"]:
            for i, u in enumerate(rd["untrusted"]):
                if u:
                    print(
                        "   ",
                        r["name"],
                        rd["t"],
                        specs[r["name"]]["X"][i],
                        rd["truth"][i],
                        rd["pm"][i],
                        rd.get("extra"),
                    )


# ================= store_every between slices, scanned =========================================
def scan(names):
    """store_every 2, 3, 5 read every Δt/4 over [0, T) at the 3 states, against a solve at Δt/4
    (plain screening, not a truth); prints the worst pair and whether the solve warned."""
    specs = problems()
    for name in names:
        spec = specs[name]
        p = build(spec)
        X = np.asarray(spec["X"], float)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            dt0 = gridlbc.solve(p).diagnostics.dt
            fine = gridlbc.solve(p, dt=dt0 / 4, error_estimate=False)
        for k in (2, 3, 5):
            s, _fail, ours, _stray, _secs = solve_with(p, dict(store_every=k))
            worst = (0.0, None)
            for t in np.arange(0, p.horizon - dt0 / 2, dt0 / 4):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    v, vf, e = s.value(X, t), fine.value(X, t), s.error_estimate(X, t)
                err = np.abs(v - vf) / np.maximum(np.abs(vf), spec["lam"])
                i = int(np.argmax(err))
                if err[i] > worst[0]:
                    worst = (
                        float(err[i]),
                        (round(float(t), 4), X[i].tolist(), float(v[i]), float(vf[i]), float(e[i])),
                    )
            print(
                name,
                f"store_every={k}",
                "warned",
                bool(ours),
                "worst vs Δt/4:",
                round(worst[0], 4),
                worst[1],
            )


def certify_store3():
    """The silent store_every=3 pairs of ``pend`` at the scan's worst times, certified."""
    spec = problems()["pend"]
    p = build(spec)
    X = np.array([[0.6, -0.5]])
    s, _fail, ours, _stray, _secs = solve_with(p, dict(store_every=3))
    print("gridlbc warnings:", [w["message"] for w in ours])
    for t, (vt, se, _bad, ex) in pend_truth(spec, X, [1.2132, 1.1912]).items():
        print(
            f"t={t} v={s.value(X, t)} v*={vt} ±{se} ESS={ex['ess']} khat={ex['khat']} "
            f"est={s.error_estimate(X, t)} fine-grid v={ex['fine_v']}"
        )


if __name__ == "__main__":
    args = sys.argv[1:]
    specs = problems()
    if not args or args[0] == "--list":
        for k, s in specs.items():
            print(k, json.dumps(s, default=float)[:2000])
        print("horizon options:", list(HORIZON_OPTIONS))
        print("stationary options:", STATIONARY_OPTIONS)
    elif args[0] == "--table":
        table()
    elif args[0] == "--scan":
        scan(args[1:] or ["pend", "pend_cold", "sep_hot", "lq_hot"])
    elif args[0] == "--certify-store3":
        certify_store3()
    elif args[0] == "--run":
        force = "--force" in args
        only = [a[len("--only=") :] for a in args if a.startswith("--only=")]
        names = [a for a in args[1:] if not a.startswith("--")] or list(specs)
        for nm in names:
            try:
                run(nm, specs[nm], only=only or None, force=force)
            except Exception as ex:
                import traceback

                traceback.print_exc()
                print(nm, "FAILED", repr(ex))
            sys.stdout.flush()
