"""Stranger round 19b: textbook systems, posed as a control student would pose them with the public
API (README "Your own system": a ControlAffineSystem subclass per system, SPEC §1–3, §6, §9–10).

Systems: mountain car (first exit at the hilltop, and a horizon), a damped pendulum with its own
gravity and friction (warm and cold), a Dubins / unicycle car (3-D, periodic heading: horizon,
first exit, hot), the Brockett integrator (3-D; B R⁻¹ Bᵀ is not diagonal), Lotka–Volterra with
prey harvesting (bilinear), an SIR epidemic with vaccination (bilinear), a two-mass spring chain
(4-D LQ, Riccati), a linearised cart-pole (4-D LQ: its natural coordinates are refused, the
coordinates ξ = θ + (b/a) x that make B diagonal are solved), a Duffing double well (warm and
cold), Van der Pol with control on the velocity (μ = 1, 3), a parametrically pumped (bilinear)
oscillator, and a thermostat tracking a setpoint that steps in time (clock axis ṡ = 1).

Layout (simpler than rounds 16–18): ``P19`` name → (builder, states, truth, tag). Round 12's
``quick`` (default solve, estimate and its terms) and my own ``truth_run``.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round19b.py NAME [NAME ...]
    ... --truth NAME ...    (the truth alone)      ... --table

Truths ("tag"), none from the library's grid solvers' values:

- "cert": ``gridlbc.certify`` (importance sampling, Girsanov weights; boundary "reflect", the
  library's contract for closed box edges) with the policy of a solve on a grid with 2× the cells
  per axis (1.5× in 3-D) as the only proposal, Richardson in Δt (Δt 0.004 / 0.008); the second
  proposal (the default solve's own policy, same Δt, independent samples) is stored beside it
  as a check ("check").
- "ricc": Riccati ODEs (round 15's ``riccati``) for the LQ chains (unbounded plane: start states
  chosen well inside the box).
- "track": round 18's ``tracker_1d`` (time-varying LQ tracker) for the thermostat.
- "are": round 15's ``are_truth`` (average cost c of the mass–spring–damper, ARE = Lyapunov).

Results (library of commit 97a467f, 2026-12-06, one thread; ``--table``; 36 problems, 2 refused
with a clear ValueError — Brockett and the cart-pole in (x, θ, ẋ, θ̇), B R⁻¹ Bᵀ not diagonal):

- SILENT (> 10 % off, no GridlbcWarning): the SIR epidemic at an early-epidemic start, I₀ ≤ 0.005
  on a 101² box [0, 1]² (``sir_early``/``sir_cold``/``sir_quad``/``sir_short``, λ 0.02–0.05,
  T 3–10): −23 … −73 % at 10 (problem, state) pairs, estimates 30–35 % of |v| (ê/|v − v*| 0.13–0.3
  at I₀ = 0.001, 0.002). Mechanism: I = 0 is invariant and I has no noise; v(S, I) rises from 0 at
  I = 0 to ≈ 1.4 at the first node I = 0.01 on a log-I scale, so the first cell holds a profile
  no grid of h > I₀ resolves. v at (0.999, 0.001) with I-nodes 51/101/201/401/801: 0.097, 0.144,
  0.22, 0.34, 0.55 (truth 0.531): increments grow as h shrinks, so the embedded difference (q = 1,
  |v_2h − v_h| = 0.050) under-reads eightfold; the phase pair agrees with it; S = 0 and γ = 0 (the
  cost 10 I is linear: the grid's interpolant is exact; 20 I² added: γ 2 %); the warning reads
  the better half at its 90th percentile, where one row of cells is ~1 % of the states, and the
  local confirmation needs γ > 5 % as well. ``solve(tol=0.05, states=…)`` refines only I and
  reports 38 % not reached after 62 s (at 101 × 801 its value, 0.536, is in fact right).
- Under-read but warned: ``lv_edge`` (prey at 0.01 on a [0, 3]² box, x = 0 invariant): +11.7 %
  with ê 4.3 % (ê/err 0.41).
- False alarms (warned, every tabled state < 3 %): thermostat, thermo_sharp (S: the setpoint
  step between the clock nodes; at the state the warning names, (1.65, 2.1), +2.0 % against
  10 %), mc_long (at its named state (0.384, 1.8): −0.3 % against 4.2 %), bilinear_cold, msd_avg
  (h warned; c +2.65 %). lv_harvest / lv_cold warn of the box corner (2.97, 2.44), where the
  solve is −7.1 % / −7.3 % off: a true alarm for a state no user would ask about.
"""

from __future__ import annotations

import json
import math
import sys
import time
import warnings

import numpy as np
import strangers_round12 as r12
import strangers_round16 as r16
from strangers_round12 import HERE
from strangers_round15 import are_truth, ricc_truth
from strangers_round18 import tracker_1d

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.regions import Ball, Box
from gridlbc.systems import ControlAffineSystem

OUT = HERE / "strangers_round19b_results"
PI = math.pi


def S(*states):
    return np.array(states, dtype=float)


# ---------------- a student's own systems (README recipe) ----------------------------------------
class Affine(ControlAffineSystem):
    """ẋ = a(x) + B(x) u with B's only non-zero entries B[axis_j, j] = b_j(x)."""

    def __init__(self, d, drift, gains, axes, angle_axes=(), name="affine"):
        self.state_dim, self.control_dim = d, len(axes)
        self.state_names = tuple(f"x{i}" for i in range(d))
        self.angle_axes = tuple(angle_axes)
        self.axes, self._drift, self._gains, self.name = tuple(axes), drift, gains, name

    def drift(self, x):
        return self._drift(self._states(x))

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((len(x), self.state_dim, self.control_dim))
        g = self._gains(x)
        for j, i in enumerate(self.axes):
            B[:, i, j] = g[:, j]
        return B


class Brockett(ControlAffineSystem):
    """ẋ₁ = u₁, ẋ₂ = u₂, ẋ₃ = x₁u₂ − x₂u₁ (the nonholonomic integrator)."""

    state_dim, control_dim, state_names = 3, 2, ("x1", "x2", "x3")

    def drift(self, x):
        return np.zeros_like(self._states(x))

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((len(x), 3, 2))
        B[:, 0, 0] = B[:, 1, 1] = 1.0
        B[:, 2, 0], B[:, 2, 1] = -x[:, 1], x[:, 0]
        return B


class CartPoleLinear(ControlAffineSystem):
    """The textbook linearisation in (x, θ, ẋ, θ̇): ẍ = (u − m g θ)/M, θ̈ = ((M+m) g θ − u)/(M l)."""

    state_dim, control_dim = 4, 1

    def drift(self, x):
        return self._states(x) @ CP_A.T

    def input_matrix(self, x):
        x = self._states(x)
        return np.broadcast_to(CP_B, (len(x), 4, 1))


def one(i=0):
    return lambda x: np.ones((len(x), 1))


def const(c):
    return lambda x: np.full(len(x), float(c))


# mountain car: ẍ = u − g cos(3x), hill top x = 0.5 (height (g/3) sin 3x)
def mc_drift(g=3.0):
    return lambda x: np.stack([x[:, 1], -g * np.cos(3 * x[:, 0])], axis=1)


def mc_exit():
    sysm = Affine(2, mc_drift(), one(), (1,), name="mountain car")
    grid = Grid([Axis(-1.2, 0.6, 101), Axis(-3.0, 3.0, 101)])
    return Problem(
        sysm,
        grid,
        None,
        state_cost=const(1.0),
        temperature=0.3,
        exit=Box([0.5, -3.0], [0.6, 3.0]),
        exit_cost=0.0,
    )


def mc_exit_cold():
    p = mc_exit()
    return p.replace(temperature=0.03)


def mc_hz_cold():
    p = mc_hz()
    return p.replace(temperature=0.02, grid=Grid([Axis(-1.2, 0.6, 51), Axis(-3.0, 3.0, 51)]))


def mc_hz():
    sysm = Affine(2, mc_drift(), one(), (1,), name="mountain car")
    grid = Grid([Axis(-1.2, 0.6, 101), Axis(-3.0, 3.0, 101)])
    return Problem(
        sysm, grid, 4.0, terminal_cost=Quadratic([0.5, 0.0], [5.0, 0.5]), temperature=0.1
    )


# damped pendulum, θ from the upright: θ̈ = (g/l) sin θ − b θ̇ + u
def pend_drift(g, b):
    return lambda x: np.stack([x[:, 1], g * np.sin(x[:, 0]) - b * x[:, 1]], axis=1)


def pend(g, b, lam, n, T, wmax=8.0):
    sysm = Affine(2, pend_drift(g, b), one(), (1,), angle_axes=(0,), name="damped pendulum")
    grid = Grid([Axis(-PI, PI, n - 1, periodic=True), Axis(-wmax, wmax, n)])
    return Problem(
        sysm,
        grid,
        T,
        terminal_cost=Quadratic([0.0, 0.0], [10.0, 0.5]),
        state_cost=lambda x: 0.5 * (1 - np.cos(x[:, 0])),
        temperature=lam,
    )


def pend_damped():
    return pend(4.0, 0.4, 0.5, 101, 4.0)


def pend_coarse():
    sysm = Affine(2, pend_drift(9.81, 0.1), one(), (1,), angle_axes=(0,), name="pendulum")
    grid = Grid([Axis(-PI, PI, 50, periodic=True), Axis(-8.0, 8.0, 51)])
    return Problem(
        sysm, grid, 5.0, terminal_cost=Quadratic([0.0, 0.0], [10.0, 0.5]), temperature=0.1
    )


def pend_cold():
    return pend(15.0, 1.0, 0.05, 151, 3.0, wmax=10.0)


# Dubins / unicycle: ẋ = V cos θ, ẏ = V sin θ, θ̇ = u
def dub_drift(V=1.0):
    return lambda x: np.stack([V * np.cos(x[:, 2]), V * np.sin(x[:, 2]), 0 * x[:, 0]], axis=1)


def dub_grid(n=41):
    return Grid([Axis(-2.5, 2.5, n), Axis(-2.5, 2.5, n), Axis(-PI, PI, n - 1, periodic=True)])


def dub_g(x):
    return 3.0 * ((x[:, 0] - 1.0) ** 2 + x[:, 1] ** 2)


def dubins_hz(lam=0.2):
    sysm = Affine(3, dub_drift(), one(), (2,), angle_axes=(2,), name="unicycle")
    return Problem(
        sysm, dub_grid(), 3.0, terminal_cost=dub_g, state_cost=const(0.5), temperature=lam
    )


def dubins_cold():
    return dubins_hz(0.02)


def dubins_hot():
    return dubins_hz(3.0)


def dubins_exit():
    sysm = Affine(3, dub_drift(), one(), (2,), angle_axes=(2,), name="unicycle")
    return Problem(
        sysm,
        dub_grid(),
        None,
        state_cost=const(1.0),
        temperature=0.1,
        exit=Box([0.7, -0.3, -PI], [1.3, 0.3, PI]),
        exit_cost=0.0,
    )


def brockett():
    grid = Grid([Axis(-2, 2, 41)] * 3)
    return Problem(
        Brockett(), grid, 2.0, terminal_cost=Quadratic([0, 0, 0], [2, 2, 2]), temperature=0.3
    )


# Lotka–Volterra, prey harvested: ẋ = x(1 − y) − x u, ẏ = y(x − 1)
def lv_cold():
    return lv().replace(temperature=0.02)


def lv():
    sysm = Affine(
        2,
        lambda x: np.stack([x[:, 0] * (1 - x[:, 1]), x[:, 1] * (x[:, 0] - 1)], 1),
        lambda x: -x[:, :1],
        (0,),
        name="Lotka-Volterra",
    )
    grid = Grid([Axis(0.05, 3.0, 101), Axis(0.05, 3.0, 101)])
    return Problem(
        sysm,
        grid,
        5.0,
        state_cost=lambda x: (x[:, 1] - 0.5) ** 2 + 0.5 * (x[:, 0] - 1.0) ** 2,
        terminal_cost=const(0.0),
        temperature=0.1,
    )


# SIR with vaccination: Ṡ = −βSI − S u, İ = βSI − γI
def sir(lam=0.05):
    beta, gam = 3.0, 1.0
    sysm = Affine(
        2,
        lambda x: np.stack(
            [-beta * x[:, 0] * x[:, 1], beta * x[:, 0] * x[:, 1] - gam * x[:, 1]], 1
        ),
        lambda x: -x[:, :1],
        (0,),
        name="SIR",
    )
    grid = Grid([Axis(0.0, 1.0, 101), Axis(0.0, 1.0, 101)])
    return Problem(
        sysm,
        grid,
        10.0,
        state_cost=lambda x: 10.0 * x[:, 1],
        terminal_cost=const(0.0),
        temperature=lam,
    )


def sir_cold():
    return sir(0.02)


# two masses on springs (wall–k–m1–k–m2), damping c, force on m2 only
K_S, C_D = 1.0, 0.2
CH_A = np.array(
    [[0, 0, 1, 0], [0, 0, 0, 1], [-2 * K_S, K_S, -C_D, 0], [K_S, -K_S, 0, -C_D]], dtype=float
)
CH_B = np.array([[0.0], [0.0], [0.0], [1.0]])
CH_W = np.diag([1.0, 1.0, 0.0, 0.0])


def chain4():
    sysm = Affine(4, lambda x: x @ CH_A.T, one(), (3,), name="spring chain")
    grid = Grid([Axis(-2, 2, 21), Axis(-2, 2, 21), Axis(-2.5, 2.5, 21), Axis(-2.5, 2.5, 21)])
    return Problem(
        sysm,
        grid,
        4.0,
        state_cost=lambda x: x[:, 0] ** 2 + x[:, 1] ** 2,
        terminal_cost=lambda x: x[:, 0] ** 2 + x[:, 1] ** 2,
        temperature=0.3,
    )


# cart-pole linearised: M = 1, m = 0.1, l = 0.5, g = 9.81
_M, _m, _l, _g = 1.0, 0.1, 0.5, 9.81
CP_A = np.array(
    [[0, 0, 1, 0], [0, 0, 0, 1], [0, -_m * _g / _M, 0, 0], [0, (_M + _m) * _g / (_M * _l), 0, 0]]
)
CP_B = np.array([[0.0], [0.0], [1 / _M], [-1 / (_M * _l)]])
# ξ = θ + 2x (b/a = 2): state (x, ξ, ẋ, ξ̇), u drives ẋ alone
CP_T = np.array([[1, 0, 0, 0], [2, 1, 0, 0], [0, 0, 1, 0], [0, 0, 2, 1]], dtype=float)
CPX_A = CP_T @ CP_A @ np.linalg.inv(CP_T)
CPX_B = CP_T @ CP_B
CP_W = np.diag([1.0, 5.0, 0.1, 0.1])  # in (x, θ, ẋ, θ̇)
CPX_W = np.linalg.inv(CP_T).T @ CP_W @ np.linalg.inv(CP_T)


def cartpole_natural():
    grid = Grid([Axis(-2, 2, 21), Axis(-0.6, 0.6, 21), Axis(-3, 3, 21), Axis(-6, 6, 21)])
    return Problem(
        CartPoleLinear(),
        grid,
        2.0,
        state_cost=lambda x: np.einsum("ni,ij,nj->n", x, CP_W, x),
        terminal_cost=const(0.0),
        temperature=0.2,
    )


def cartpole_xi():
    sysm = Affine(4, lambda x: x @ CPX_A.T, one(), (2,), name="cart-pole (x, xi)")
    grid = Grid([Axis(-2, 2, 21), Axis(-3, 3, 21), Axis(-4, 4, 21), Axis(-8, 8, 21)])
    return Problem(
        sysm,
        grid,
        2.0,
        state_cost=lambda x: np.einsum("ni,ij,nj->n", x, CPX_W, x),
        terminal_cost=lambda x: np.einsum("ni,ij,nj->n", x, CPX_W, x),
        temperature=0.2,
    )


# Duffing double well: ẍ = x − x³ − 0.3 ẋ + u
def dwell(lam=0.5, T=5.0):
    sysm = Affine(
        2,
        lambda x: np.stack([x[:, 1], x[:, 0] - x[:, 0] ** 3 - 0.3 * x[:, 1]], 1),
        one(),
        (1,),
        name="double well",
    )
    grid = Grid([Axis(-2.5, 2.5, 101), Axis(-3.0, 3.0, 101)])
    return Problem(
        sysm,
        grid,
        T,
        terminal_cost=Quadratic([1.0, 0.0], [2.0, 0.4]),
        state_cost=lambda x: 0.2 * x[:, 1] ** 2,
        temperature=lam,
    )


def bilinear_cold():
    return bilinear().replace(temperature=0.03)


def dwell_cold():
    return dwell(0.05, 5.0)


# Van der Pol, control on the velocity: ẍ = μ(1 − x²)ẋ − x + u
def vdp(mu, vmax, T, n=101):
    sysm = Affine(
        2,
        lambda x: np.stack([x[:, 1], mu * (1 - x[:, 0] ** 2) * x[:, 1] - x[:, 0]], 1),
        one(),
        (1,),
        name=f"Van der Pol {mu}",
    )
    grid = Grid([Axis(-3, 3, n), Axis(-vmax, vmax, n)])
    return Problem(
        sysm,
        grid,
        T,
        state_cost=lambda x: x[:, 0] ** 2 + x[:, 1] ** 2,
        terminal_cost=lambda x: x[:, 0] ** 2 + x[:, 1] ** 2,
        temperature=0.2,
    )


def vdp1():
    return vdp(1.0, 6.0, 4.0)


def vdp5_coarse():
    return vdp(5.0, 12.0, 3.0, n=51)


def vdp3():
    return vdp(3.0, 10.0, 3.0)


# parametric (bilinear) oscillator: ẍ = −x − 0.1 ẋ + x u, pumped to radius 1.5
def bilinear():
    sysm = Affine(
        2,
        lambda x: np.stack([x[:, 1], -x[:, 0] - 0.1 * x[:, 1]], 1),
        lambda x: x[:, :1],
        (1,),
        name="pumped oscillator",
    )
    grid = Grid([Axis(-3, 3, 101), Axis(-3, 3, 101)])
    return Problem(
        sysm,
        grid,
        6.0,
        terminal_cost=lambda x: (x[:, 0] ** 2 + x[:, 1] ** 2 - 2.25) ** 2,
        temperature=0.2,
    )


# thermostat: ẋ = −k x + u, setpoint c(s) steps 0 → 1 at s = 2 (width 0.1), clock ṡ = 1
K_TH, W_TH = 0.5, 2.0


def setpoint(s, width=0.1):
    return 0.5 + 0.5 * np.tanh((np.asarray(s) - 2.0) / width)


def thermo_sharp():
    """The setpoint switched within 0.02 s (a quarter of a clock cell), λ = 0.02."""
    sysm = Affine(
        2, lambda x: np.stack([-K_TH * x[:, 0], np.ones(len(x))], 1), one(), (0,), name="thermostat"
    )
    grid = Grid([Axis(-2, 3, 51), Axis(0, 6, 51)])
    cost = lambda x: W_TH * (x[:, 0] - setpoint(x[:, 1], 0.02)) ** 2  # noqa: E731
    return Problem(sysm, grid, 3.0, state_cost=cost, terminal_cost=cost, temperature=0.02)


def thermo_sharp_truth(X):
    out = []
    for x0, s0 in np.asarray(X):
        f = tracker_1d(
            lambda t, s0=s0: setpoint(s0 + t, 0.02), W_TH, W_TH, 0.02, 3.0, a=-K_TH, max_step=0.002
        )
        out.append(float(f(x0)))
    return np.array(out), np.zeros(len(out))


def thermostat():
    sysm = Affine(
        2, lambda x: np.stack([-K_TH * x[:, 0], np.ones(len(x))], 1), one(), (0,), name="thermostat"
    )
    grid = Grid([Axis(-2, 3, 51), Axis(0, 6, 51)])
    cost = lambda x: W_TH * (x[:, 0] - setpoint(x[:, 1])) ** 2  # noqa: E731
    return Problem(sysm, grid, 3.0, state_cost=cost, terminal_cost=cost, temperature=0.1)


def thermo_truth(X):
    out = []
    for x0, s0 in np.asarray(X):
        f = tracker_1d(
            lambda t, s0=s0: setpoint(s0 + t), W_TH, W_TH, 0.1, 3.0, a=-K_TH, max_step=0.01
        )
        out.append(float(f(x0)))
    return np.array(out), np.zeros(len(out))


# ---- round two: exits, an average cost, an invariant edge --------------------------------------
def lv_edge():
    """Lotka–Volterra on the box a user draws, [0, 3]²: both axes x = 0, y = 0 are invariant."""
    return lv().replace(grid=Grid([Axis(0.0, 3.0, 101), Axis(0.0, 3.0, 101)]), temperature=0.05)


def vdp_exit():
    sysm = Affine(
        2,
        lambda x: np.stack([x[:, 1], (1 - x[:, 0] ** 2) * x[:, 1] - x[:, 0]], 1),
        one(),
        (1,),
        name="Van der Pol 1",
    )
    grid = Grid([Axis(-3, 3, 101), Axis(-6, 6, 101)])
    return Problem(
        sysm,
        grid,
        None,
        state_cost=lambda x: 0.5 + 0.1 * x[:, 1] ** 2,
        temperature=0.1,
        exit=Ball([0.0, 0.0], [0.2, 0.3]),
        exit_cost=0.0,
    )


def pend_exit():
    sysm = Affine(2, pend_drift(6.0, 0.3), one(), (1,), angle_axes=(0,), name="damped pendulum")
    grid = Grid([Axis(-PI, PI, 100, periodic=True), Axis(-8.0, 8.0, 101)])
    return Problem(
        sysm,
        grid,
        None,
        state_cost=const(1.0),
        temperature=0.2,
        exit=Ball([0.0, 0.0], [0.15, 0.5]),
        exit_cost=0.0,
    )


def dubins_park():
    sysm = Affine(3, dub_drift(), one(), (2,), angle_axes=(2,), name="unicycle")
    return Problem(
        sysm,
        dub_grid(),
        3.0,
        state_cost=const(0.5),
        temperature=0.02,
        terminal_cost=lambda x: dub_g(x) + 2.0 * (1 - np.cos(x[:, 2] - PI / 2)),
    )


def mc_exit_coarse():
    return mc_exit().replace(temperature=0.1, grid=Grid([Axis(-1.2, 0.6, 51), Axis(-3.0, 3.0, 51)]))


MSD_A = np.array([[0.0, 1.0], [-1.0, -0.2]])
MSD_W = np.diag([1.0, 0.1])


def msd_avg():
    sysm = Affine(2, lambda x: x @ MSD_A.T, one(), (1,), name="mass-spring-damper")
    grid = Grid([Axis(-3, 3, 101), Axis(-3, 3, 101)])
    return Problem(
        sysm,
        grid,
        "average",
        state_cost=lambda x: x[:, 0] ** 2 + 0.1 * x[:, 1] ** 2,
        temperature=0.5,
    )


def sir_quad():
    """sir at λ = 0.05 with a convex infection cost 10 I + 20 I² (γ no longer zero)."""
    return sir(0.05).replace(state_cost=lambda x: 10.0 * x[:, 1] + 20.0 * x[:, 1] ** 2)


def sir_short():
    return sir(0.05).replace(horizon=3.0)


def vdp_long():
    return vdp(1.0, 6.0, 10.0)


def dwell_exit():
    p = dwell(0.1, 5.0)
    return p.replace(
        horizon=None,
        terminal_cost=None,
        state_cost=lambda x: 0.5 + 0.1 * x[:, 1] ** 2,
        exit=Ball([1.0, 0.0], [0.15, 0.3]),
        exit_cost=0.0,
    )


def pend_hot():
    return pend(4.0, 0.4, 3.0, 51, 4.0)


def mc_long():
    p = mc_hz()
    return p.replace(horizon=10.0, temperature=0.3, state_cost=lambda x: 0.2 * (x[:, 0] - 0.5) ** 2)


# ---------------- truths ---------------------------------------------------------------------------
def certified(build, factor=2.0, samples=2000, dt=0.004, max_time=None):
    """v* by gridlbc.certify with a finer solve's policy as the only proposal (Richardson in Δt);
    the default solve's policy as a second, independent proposal. Returns (v*, SE, extra)."""

    def truth(X):
        p = build()
        axes = [
            Axis(a.lo, a.hi, round(a.n * factor), True)
            if a.periodic
            else Axis(a.lo, a.hi, round((a.n - 1) * factor) + 1)
            for a in p.grid.axes
        ]
        fine = p.replace(grid=Grid(axes))
        kw = dict(
            n_samples=samples,
            dt=dt,
            richardson=True,
            progress=False,
            proposal=None,
            boundary="reflect",
            max_time=max_time,
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            s = gridlbc.solve(fine, error_estimate=False)
            t1 = time.perf_counter()
            c = gridlbc.certify(p, s.policy, np.asarray(X), seed=12, **kw)
            t2 = time.perf_counter()
            s0 = gridlbc.solve(p, error_estimate=False)
            c2 = gridlbc.certify(p, s0.policy, np.asarray(X), seed=34, **kw)
        print(f"    fine solve {t1 - t0:.1f} s, certificate {t2 - t1:.1f} s", flush=True)
        extra = dict(
            ess=np.asarray(c.effective_sample_size).tolist(),
            khat=np.asarray(c.pareto_k).tolist(),
            v_dt=np.asarray(c.optimal_value).tolist(),
            fine_v=np.asarray(s.value(np.asarray(X))).tolist()
            if p.horizon is None
            else np.asarray(s.value(np.asarray(X), 0.0)).tolist(),
            check=np.asarray(c2.extrapolated_value).tolist(),
            check_se=np.asarray(c2.extrapolated_value_se).tolist(),
            check_ess=np.asarray(c2.effective_sample_size).tolist(),
            unexited=np.asarray(c.unexited_fraction).tolist(),
        )
        return np.asarray(c.extrapolated_value), np.asarray(c.extrapolated_value_se), extra

    return truth


def ricc(A, B, W, WT, lam, T):
    f = ricc_truth(A, B, np.eye(B.shape[1]), W, WT, lam, T)
    return lambda X: (*f(X), {})


def raises(build):
    def run(name):
        try:
            with warnings.catch_warnings(record=True):
                warnings.simplefilter("always")
                gridlbc.solve(build())
            msg = "no error"
        except Exception as e:  # what a user sees
            msg = f"{type(e).__name__}: {e}"
        print(f"{name}: {msg}")
        (OUT / f"{name}_raise.json").write_text(json.dumps(dict(name=name, error=msg)))

    return run


P19 = {
    "mc_exit": (
        mc_exit,
        S((-0.5, 0.0), (-1.0, 0.5), (0.2, -1.0), (0.3, 1.0)),
        certified(mc_exit, max_time=20.0),
        "cert",
    ),
    "mc_hz": (
        mc_hz,
        S((-0.5, 0.0), (-1.0, 0.5), (0.2, -1.0), (0.3, 1.0)),
        certified(mc_hz),
        "cert",
    ),
    "pend_damped": (
        pend_damped,
        S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5)),
        certified(pend_damped),
        "cert",
    ),
    "pend_cold": (
        pend_cold,
        S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5)),
        certified(pend_cold, dt=0.002),
        "cert",
    ),
    "dubins_hz": (
        dubins_hz,
        S((-1.0, 0.0, 0.0), (-1.0, 0.0, PI), (0.0, 1.0, -PI / 2), (1.0, 0.0, PI / 2)),
        certified(dubins_hz, factor=1.5),
        "cert",
    ),
    "dubins_hot": (
        dubins_hot,
        S((-1.0, 0.0, 0.0), (-1.0, 0.0, PI), (0.0, 1.0, -PI / 2), (1.0, 0.0, PI / 2)),
        certified(dubins_hot, factor=1.5),
        "cert",
    ),
    "dubins_exit": (
        dubins_exit,
        S((-1.0, 0.0, 0.0), (-1.0, 0.0, PI), (0.0, 1.0, -PI / 2), (1.5, 1.0, PI / 2)),
        certified(dubins_exit, factor=1.5, max_time=20.0),
        "cert",
    ),
    "lv_harvest": (lv, S((1.0, 1.0), (2.0, 0.5), (0.5, 2.0), (1.5, 1.5)), certified(lv), "cert"),
    "sir_vacc": (sir, S((0.99, 0.01), (0.8, 0.1), (0.5, 0.3), (0.3, 0.05)), certified(sir), "cert"),
    "chain4": (
        chain4,
        S((0.5, -0.5, 0.0, 0.0), (0.0, 0.8, 0.5, 0.0), (-0.6, 0.3, 0.0, 0.7)),
        ricc(CH_A, CH_B, CH_W, CH_W, 0.3, 4.0),
        "ricc",
    ),
    "cartpole_xi": (
        cartpole_xi,
        CP_T @ S((0.5, 0.0, 0.0, 0.0), (0.0, 0.1, 0.0, 0.0), (-0.5, 0.05, 0.5, -0.3)).T,
        ricc(CPX_A, CPX_B, CPX_W, CPX_W, 0.2, 2.0),
        "ricc",
    ),
    "dwell": (dwell, S((-1.0, 0.0), (0.0, 0.0), (1.0, 0.0), (-1.5, 1.5)), certified(dwell), "cert"),
    "dwell_cold": (
        dwell_cold,
        S((-1.0, 0.0), (0.0, 0.0), (1.0, 0.0), (-1.5, 1.5)),
        certified(dwell_cold),
        "cert",
    ),
    "vdp1": (vdp1, S((2.0, 0.0), (0.0, 2.0), (-1.0, -1.0), (0.5, 0.5)), certified(vdp1), "cert"),
    "vdp3": (vdp3, S((2.0, 0.0), (0.0, 2.0), (-1.0, -1.0), (0.5, 0.5)), certified(vdp3), "cert"),
    "bilinear": (
        bilinear,
        S((0.5, 0.0), (1.0, 1.0), (-1.0, 0.5), (2.0, 0.0)),
        certified(bilinear),
        "cert",
    ),
    "thermostat": (
        thermostat,
        S((0.0, 0.0), (0.5, 1.0), (-1.0, 1.5), (1.0, 2.5)),
        thermo_truth,
        "track",
    ),
    "mc_exit_cold": (
        mc_exit_cold,
        S((-0.5, 0.0), (-1.0, 0.5), (0.2, -1.0), (0.3, 1.0)),
        certified(mc_exit_cold, max_time=20.0),
        "cert",
    ),
    "mc_hz_cold": (
        mc_hz_cold,
        S((-0.5, 0.0), (-1.0, 0.5), (0.2, -1.0), (0.3, 1.0)),
        certified(mc_hz_cold),
        "cert",
    ),
    "sir_cold": (
        sir_cold,
        S((0.999, 0.001), (0.99, 0.01), (0.9, 0.02), (0.6, 0.2)),
        certified(sir_cold),
        "cert",
    ),
    "lv_cold": (
        lv_cold,
        S((1.0, 1.0), (2.0, 0.5), (0.5, 2.0), (1.5, 1.5)),
        certified(lv_cold),
        "cert",
    ),
    "vdp5_coarse": (
        vdp5_coarse,
        S((2.0, 0.0), (0.0, 2.0), (-1.0, -1.0), (0.5, 0.5)),
        certified(vdp5_coarse),
        "cert",
    ),
    "pend_coarse": (
        pend_coarse,
        S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5)),
        certified(pend_coarse, dt=0.002),
        "cert",
    ),
    "dubins_cold": (
        dubins_cold,
        S((-1.0, 0.0, 0.0), (-1.0, 0.0, PI), (0.0, 1.0, -PI / 2), (1.0, 0.0, PI / 2)),
        certified(dubins_cold, factor=1.5),
        "cert",
    ),
    "bilinear_cold": (
        bilinear_cold,
        S((0.5, 0.0), (1.0, 1.0), (-1.0, 0.5), (2.0, 0.0)),
        certified(bilinear_cold),
        "cert",
    ),
    "thermo_sharp": (
        thermo_sharp,
        S((0.0, 0.0), (0.5, 1.0), (-1.0, 1.5), (1.0, 2.5)),
        thermo_sharp_truth,
        "track",
    ),
    "sir_early": (
        sir,
        S((0.999, 0.001), (0.995, 0.005), (0.98, 0.002), (0.9, 0.05)),
        certified(sir),
        "cert",
    ),
    "sir_quad": (
        sir_quad,
        S((0.999, 0.001), (0.995, 0.005), (0.98, 0.002), (0.9, 0.05)),
        certified(sir_quad),
        "cert",
    ),
    "sir_short": (
        sir_short,
        S((0.999, 0.001), (0.995, 0.005), (0.98, 0.002), (0.9, 0.05)),
        certified(sir_short),
        "cert",
    ),
    "vdp_long": (
        vdp_long,
        S((2.0, 0.0), (0.0, 2.0), (-1.0, -1.0), (0.5, 0.5)),
        certified(vdp_long),
        "cert",
    ),
    "dwell_exit": (
        dwell_exit,
        S((-1.0, 0.0), (0.0, 0.0), (-1.5, 1.5), (2.0, -1.0)),
        certified(dwell_exit, max_time=30.0),
        "cert",
    ),
    "pend_hot": (
        pend_hot,
        S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5)),
        certified(pend_hot),
        "cert",
    ),
    "mc_long": (
        mc_long,
        S((-0.5, 0.0), (-1.0, 0.5), (0.2, -1.0), (0.3, 1.0)),
        certified(mc_long),
        "cert",
    ),
    "lv_edge": (
        lv_edge,
        S((0.01, 1.0), (1.0, 0.01), (0.1, 0.1), (1.0, 1.0)),
        certified(lv_edge),
        "cert",
    ),
    "vdp_exit": (
        vdp_exit,
        S((2.0, 0.0), (0.0, 2.0), (-1.0, -1.0), (0.5, 0.5)),
        certified(vdp_exit, max_time=20.0),
        "cert",
    ),
    "pend_exit": (
        pend_exit,
        S((PI, 0.0), (2.0, 1.0), (-1.0, -2.0), (0.5, 0.5)),
        certified(pend_exit, max_time=20.0),
        "cert",
    ),
    "dubins_park": (
        dubins_park,
        S((-1.0, 0.0, 0.0), (-1.0, 0.0, PI), (0.0, 1.0, -PI / 2), (1.0, 0.0, PI / 2)),
        certified(dubins_park, factor=1.5),
        "cert",
    ),
    "mc_exit_coarse": (
        mc_exit_coarse,
        S((-0.5, 0.0), (-1.0, 0.5), (0.2, -1.0), (0.3, 1.0)),
        certified(mc_exit_coarse, max_time=20.0),
        "cert",
    ),
    "msd_avg": (
        msd_avg,
        S((0.5, 0.3), (-1.0, 1.0), (1.5, -1.0)),
        are_truth(MSD_A, np.array([[0.0], [1.0]]), np.eye(1), MSD_W, 0.5),
        "are",
    ),
}
# cartpole_xi's states: transpose back to rows
P19["cartpole_xi"] = (
    P19["cartpole_xi"][0],
    P19["cartpole_xi"][1].T.copy(),
    *P19["cartpole_xi"][2:],
)
RAISES = {"brockett": raises(brockett), "cartpole_natural": raises(cartpole_natural)}


def truth_run(name):
    _b, X, f, tag = P19[name]
    t0 = time.perf_counter()
    r = f(X)
    vstar, unc, extra = r if len(r) == 3 else (*r, {})
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


def table():
    head = (
        f"{'problem':14s} {'state':26s} {'pred':>8s} {'truth':>8s} {'±':>6s} {'ESS':>5s}"
        f" {'k̂':>5s} {'check':>8s} {'err':>8s} {'est':>7s} {'abs':>6s} w"
    )
    print(head)
    silent, under, false = [], [], []
    for name, (build, X, *_r) in P19.items():
        fs, ft = OUT / f"{name}_solve.json", OUT / f"{name}_truth.json"
        if not (fs.exists() and ft.exists()):
            continue
        lam = build().temperature
        d, tr = json.loads(fs.read_text()), json.loads(ft.read_text())
        errs = []
        if d.get("kind") == "average":
            c, cs, ce = d["v"][0], tr["vstar"][0], d["est"][0]
            err, rel_e = (c - cs) / abs(cs), ce / abs(c)
            print(
                f"{name:14s} {'c (average cost)':26s} {c:8.4f} {cs:8.4f} {'':>6s} {'':>5s}"
                f" {'':>5s} {'':>8s} {100 * err:+7.2f}% {100 * rel_e:6.2f}%"
                f" {rel_e / max(abs(err), 1e-12):6.2f} {'Y' if d['warned'] else 'n'}"
            )
            if abs(err) > 0.10 and not d["warned"]:
                silent.append((name, round(100 * err, 1)))
            if abs(err) > 0.02 and rel_e < abs(err) / 2:
                under.append((name, round(100 * err, 1), round(100 * rel_e, 1)))
            if d["warned"] and abs(err) < 0.03:
                false.append(name)
            continue
        for i in range(len(X)):
            v, vs, e = d["v"][i], tr["vstar"][i], d["est"][i]
            sc = max(abs(vs), lam)
            err, rel_e = (v - vs) / sc, e / max(abs(v), lam)
            errs.append(abs(err))
            ess = tr.get("ess", [float("nan")] * len(X))[i]
            kh = tr.get("khat", [float("nan")] * len(X))[i]
            chk = tr.get("check", [float("nan")] * len(X))[i]
            ratio = e / max(abs(v - vs), 1e-12)  # ê / |v − v*|, absolute
            shaky = ess < 100 or kh > 0.7  # the certificate's own trust limits (k̂ 0.7)
            print(
                f"{name:14s} {np.round(X[i], 3).tolist()!s:26s} {v:8.4f} {vs:8.4f}"
                f" {100 * tr['unc'][i] / sc:5.2f}% {ess:5.0f} {kh:5.2f} {chk:8.4f}"
                f" {100 * err:+7.2f}% {100 * rel_e:6.2f}% {ratio:6.2f} "
                f"{'Y' if d['warned'] else 'n'}{' (truth shaky)' if shaky else ''}"
            )
            if abs(err) > 0.10 and not d["warned"]:
                silent.append((name, round(100 * err, 1)))
            if abs(err) > 0.02 and ratio < 0.5:
                under.append((name, round(100 * err, 1), round(100 * rel_e, 1), round(ratio, 2)))
        if d["warned"] and max(errs) < 0.03:
            false.append(name)
    for n in RAISES:
        f = OUT / f"{n}_raise.json"
        if f.exists():
            print(f"{n:12s} raised: {json.loads(f.read_text())['error'][:300]}")
    print(
        f"silent (>10 %, no warning): {silent}\nunder-reads (est < ½ err, err > 2 %): {under}"
        f" (err %, est % of |v|, ê/|v − v*|)\nfalse alarms (warned, every state < 3 %): {false}"
    )


def main(argv):
    OUT.mkdir(exist_ok=True)
    r12.P12, r12.OUT, r12._warned = P19, OUT, r16._warned
    if "--table" in argv:
        table()
        return
    names = [a for a in argv if not a.startswith("--")]
    for name in names:
        if name in RAISES:
            RAISES[name](name)
            continue
        if "--truth" not in argv:
            r12.quick(name)
        if "--solve" not in argv:
            truth_run(name)


if __name__ == "__main__":
    main(sys.argv[1:])
