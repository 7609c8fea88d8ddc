"""Stranger round 5: narrow features off the axis centre, against the second embedded grid.

Not a corpus member and not run by the tests. The runner, the certificate recipe and the output
format are round 3's (``strangers_round3.run``: default solve, a finer solve's policy as the
certificate's proposal at ``cert_dt`` and ``cert_dt / 2``, extrapolated 2 v(dt/2) − v(dt));
``--own`` and ``--halfdt`` are its double checks.

    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round5.py NAME [NAME ...] [--own] [--halfdt]
    NUMBA_NUM_THREADS=1 python benchmarks/holdout/strangers_round5.py NAME --nodes N [N ...]

``--nodes`` re-solves a 2-D problem with N nodes on its first axis (the rest kept) against the
truth already in the results folder.

RESULTS
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

import gridlbc  # noqa: E402
from gridlbc import Axis, Grid, Problem, Quadratic  # noqa: E402
from gridlbc.systems import ControlAffineSystem, LinearSystem, Pendulum, PointMass  # noqa: E402

OUT = HERE / "strangers_round5_results"
PI = np.pi
G, S = r3.G, r3.S


def _wrap(a):
    return (a + PI) % (2 * PI) - PI


# ---- (1) a narrow pit of state and terminal cost off the axis centre ----
def rotor_pit_at(centre, n=201, width=0.07, horizon=5.0, temperature=0.005):
    """A rotor (pendulum without gravity) in a Gaussian pit 3(1 − exp(−Δθ²/2w²)) + 0.05ω²
    centred at θ = ``centre``, on ``n`` periodic nodes × 201 velocity nodes."""

    def cost(x):
        x = np.atleast_2d(x)
        d = _wrap(x[:, 0] - centre)
        return 3 * (1 - np.exp(-0.5 * (d / width) ** 2)) + 0.05 * x[:, 1] ** 2

    return Problem(
        Pendulum(gravity=0.0),
        G((-PI, PI, n, True), (-6, 6, 201)),
        horizon,
        cost,
        state_cost=cost,
        temperature=temperature,
    )


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


def mass_pit_at(centre, n=201, width=0.04, horizon=5.0, temperature=0.005):
    """A point mass in a Gaussian pit of position 3(1 − exp(−Δx²/2w²)) + 0.05v² (state and
    terminal cost) at x = ``centre``, on ``n`` closed nodes over [−2, 2] × 201 over [−4, 4]."""

    def cost(x):
        x = np.atleast_2d(x)
        d = x[:, 0] - centre
        return 3 * (1 - np.exp(-0.5 * (d / width) ** 2)) + 0.05 * x[:, 1] ** 2

    return Problem(
        PointMass(),
        G((-2, 2, n), (-4, 4, 201)),
        horizon,
        cost,
        state_cost=cost,
        temperature=temperature,
    )


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
    return mass_pit_at(0.37, n=200)


def mass_pit_even_mid():
    """Even closed axis (200): pit at x = −2 + 117.5 h = 0.3618, midway between two nodes."""
    return mass_pit_at(-2 + 117.5 * 4 / 199, n=200)


class RotorSlider(ControlAffineSystem):
    """(θ, ω, y): a rotor (θ̈ = u₁) and a slider driven directly (ẏ = u₂)."""

    state_dim, control_dim, state_names = 3, 2, ("theta", "omega", "y")
    angle_axes = (0,)

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], np.zeros(len(x)), np.zeros(len(x))], 1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 3, 2))
        B[:, 1, 0] = 1.0
        B[:, 2, 1] = 1.0
        return B


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


def terminal_pit():
    """Terminal cost only, T = 0.5: a narrow pit 3(1 − exp(−(x − 0.37)²/2w²)) + 0.5v², w = 0.04,
    on 201 closed nodes (between the nodes 0.36 and 0.38; 0.36 is a node of the embedded axis),
    λ = 0.05."""

    def g(x):
        x = np.atleast_2d(x)
        return 3 * (1 - np.exp(-0.5 * ((x[:, 0] - 0.37) / 0.04) ** 2)) + 0.5 * x[:, 1] ** 2

    return Problem(PointMass(), G((-2, 2, 201), (-4, 4, 201)), 0.5, g, temperature=0.05)


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


def stiff():
    """A stiff linear system: a slow unstable state driven through a fast actuator state,
    ẋ₁ = 0.5x₁ + x₂, ẋ₂ = −30x₂ + 30u (one stable mode at rate 30), λ = 0.1 (linear-quadratic)."""
    return Problem(
        LinearSystem([[0.5, 1.0], [0.0, -30.0]], [0.0, 30.0]),
        G((-2, 2, 201), (-1.5, 1.5, 201)),
        2.0,
        Quadratic([0.0, 0.0], [10.0, 0.0]),
        state_cost=Quadratic([0.0, 0.0], [2.0, 0.1]),
        temperature=0.1,
    )


P5 = {  # name: builder, states, cert_dt, fine, max_time (round 3's layout)
    "rotor_pit_07": (rotor_pit_07, S((0.3, 0), (1.2, 1.0), (-1.5, -1.5)), 0.002, 2.0, None),
    "rotor_pit_275": (rotor_pit_275, S((2.4, 0), (-3.0, 1.0), (1.5, -1.5)), 0.002, 2.0, None),
    "rotor_pit_seam": (rotor_pit_seam, S((2.8, 0), (-2.9, 1.0), (1.5, -1.5)), 0.002, 2.0, None),
    "mass_pit_odd": (mass_pit_odd, S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)), 0.002, 2.0, None),
    "mass_well": (mass_well, S((0.1, 0), (0.8, 1.0), (-1.0, -1.0)), 0.002, 2.0, None),
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
    "coulomb": (coulomb, S((-1, 0), (0, 1), (1.5, -1)), 0.002, 2.0, None),
    "terminal_short": (terminal_short, S((0, 0), (0.6, -0.5), (-0.2, 1.0)), 0.001, 2.0, None),
    "hot_narrow": (hot_narrow, S((0, 0), (1.5, -1.0), (-1.0, 2.0)), 0.002, 2.0, None),
    "aniso_r": (aniso_r, S((0, 0), (-1, 1), (2, -1)), 0.002, 2.0, None),
    "skinny_grid": (skinny_grid, S((0, 0), (1, 2), (3, -1)), 0.002, 2.0, None),
    "stiff": (stiff, S((0.5, 0), (-1, 0.5), (1.0, -1.0)), 0.001, 1.5, None),
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


def main(argv: list[str]) -> None:
    OUT.mkdir(exist_ok=True)
    r3.OUT = OUT
    if "--nodes" in argv:
        k = argv.index("--nodes")
        nodes(argv[0], [int(a) for a in argv[k + 1 :]])
        return
    for name in [a for a in argv if not a.startswith("--")]:
        r3.run(name, "--own" in argv, 0.5 if "--halfdt" in argv else 1.0)


if __name__ == "__main__":
    main(sys.argv[1:])
