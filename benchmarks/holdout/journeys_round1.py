"""Journeys round 1: a demanding new user walks through every public entry point of gridlbc.

Each journey is a function that writes user code as a stranger would (own systems subclassing
``gridlbc.systems.ControlAffineSystem``, odd but legal choices, plain functions and lambdas as
costs, exit sets as regions or callables) and checks what comes back: no crash, no raw
library-internal exception, no stray numpy RuntimeWarning, consistent shapes, exact round trips,
and the right numbers where an exact answer exists (``lq_solution``; superposition of
``fitting=None`` components against the solve of the composite cost).

    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/holdout/journeys_round1.py --run [NAME ...]
    python benchmarks/holdout/journeys_round1.py --list

prints ``PASS name: ...`` or ``FINDING name: ...`` per journey. Grids are small (at most 61² in
2-D, 21³ in 3-D) and horizons short: the whole run takes a few minutes on one core.

RESULTS (library of main c67d62c, worktree journey, 2026-12-07 11:49 UTC, one numba thread):
``--run`` gives 19 findings in 33 journeys, 2 minutes. Most consequential:

- first_exit_save_load: a loaded first-exit solution reads E by its nodes (a GridRegion that
  prints as the Ball): states OUTSIDE the ball read v = g_E, u = 0, and certify on the loaded
  problem returns v* = 0 there (0.116 on the original); states inside read above g_E.
- cli_first_exit_certify: ``gridlbc certify`` cannot certify a first-exit file (asks for
  max_time; the CLI has no such flag).
- combine_negative_weights: Σ w_i z_i < 0 is reported as an underflow (+inf, "shrink the box").
- quadratic_standalone_wrap / project_periodic_without_grid: a Quadratic is wrap-aware only once a
  Problem binds it; called by the user (a composite, project without grid) it is not, silently.
- save_numpy_scalar_parameter / save_tuple_parameter: np.float64 or tuple parameters make save
  and load warn that the system cannot be rebuilt / differs, advising a parameters() it has.
- first_exit_union_stray_warning: numpy "invalid value encountered in divide" (simulate.py:791)
  from a default solve.
- raw internal TypeErrors: solve_many(p, one_cost), combine(weights=generator).
- messages: combine's grid mismatch describes both grids identically; lq_solution calls a linear
  user system nonlinear; load of a damaged file relays numpy's allow_pickle advice; save('run1')
  then load('run1') fails; load(system=Drag) says "got a builtins.type".
- small API asymmetries: dtype=np.float32 refused; state_cost=1.0 refused (exit_cost=0.5 is
  accepted); project refuses a number exit cost that solve_many accepts; solve_hjb 13.5 % off
  on 41² without a word (documented first order).

Passed: shapes and t handling on a 3-D user system, superposition to 1e-15 (point mass and a
periodic 3-D user system with state-dependent B), first-exit certificate and composition,
average cost vs Riccati, tol/states/times/max_seconds, presets, methods, fittings, 3 controls,
simulate/certify edge cases, bit-exact save/load (float32, store_every, implicit, fitted),
trajectory optimize/expand vs Riccati, a local Dask sweep with reruns, the CLI on TOML files.

Rerun 2026-12-07 13:00 UTC on the fixes of that session (main after 9500d4c): 28 PASS, 5 FINDING.
Left as reported: quadratic_standalone_wrap and project_periodic_without_grid (a user's
Quadratic knows no periods until a problem or grid binds them; project's docstring now says to
give grid=), project_number_component, hjb_reference (first order, 13.5 % on 41²);
cli_first_exit_certify asks for ``--max-time`` alone, and a first exit needs ``--dt`` too, by
design (the message now names both flags).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.regions import Ball, Box, region_mask
from gridlbc.systems import ControlAffineSystem, PointMass

TMP = Path(tempfile.mkdtemp(prefix="journeys_"))


class Finding(Exception):
    """What a journey found: the message says what happened and what was expected."""


def quiet(f, *args, **kwargs):
    """Call f, recording warnings; return (result, list of warnings)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = f(*args, **kwargs)
    return result, caught


def numpy_warnings(caught):
    """The stray numpy RuntimeWarnings among ``caught`` (not gridlbc's own warnings)."""
    return [
        w
        for w in caught
        if w.category is RuntimeWarning
        and any(k in str(w.message) for k in ("encountered in", "divide by zero", "overflow"))
    ]


def messages(caught, category=None):
    return [str(w.message) for w in caught if category is None or issubclass(w.category, category)]


def expect_clear_error(f, must_mention, exc_types=(ValueError, TypeError)):
    """f must raise one of exc_types whose message mentions every word of must_mention."""
    try:
        quiet(f)
    except exc_types as e:
        text = str(e)
        missing = [w for w in must_mention if w.lower() not in text.lower()]
        if missing:
            raise Finding(f"error does not mention {missing}: {type(e).__name__}: {text}") from e
        return text
    except Exception as e:  # a raw exception of the wrong kind is a finding
        raise Finding(f"raw {type(e).__name__}: {e}") from e
    raise Finding("no error raised")


# --------------------------------------------------------------------------- user systems


class Drag(ControlAffineSystem):
    """A cart with linear drag; its parameters are whatever the user passes."""

    state_dim, control_dim = 2, 1
    state_names = ("pos", "vel")

    def __init__(self, k=0.3):
        self.k = k

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], -self.k * x[:, 1]], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 2, 1))
        B[:, 1, 0] = 1.0
        return B

    def parameters(self):
        return {"k": self.k}


class Gains(Drag):
    """Parameters as a tuple (a legal, common choice)."""

    def __init__(self, gains=(0.3, 1.0)):
        self.gains = gains
        self.k = gains[0]

    def parameters(self):
        return {"gains": self.gains}


class Flow(ControlAffineSystem):
    """The README's Spin: a point pushed in the plane by a turning flow (2 controls)."""

    state_dim, control_dim, state_names = 2, 2, ("x", "y")

    def __init__(self, rate=0.5):
        self.rate = rate

    def drift(self, x):
        x = self._states(x)
        return self.rate * np.stack([-x[:, 1], x[:, 0]], axis=1)

    def input_matrix(self, x):
        return np.broadcast_to(np.eye(2), (self._states(x).shape[0], 2, 2))

    def parameters(self):
        return {"rate": self.rate}


class Rotor(ControlAffineSystem):
    """3 states (one periodic), 1 control with a state-dependent gain, no parameters()."""

    state_dim, control_dim = 3, 1
    state_names = ("angle", "rate", "slow")
    angle_axes = (0,)

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], np.sin(x[:, 0]) - 0.1 * x[:, 1], -x[:, 2]], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 3, 1))
        B[:, 1, 0] = 1.0 + 0.3 * np.cos(x[:, 0])
        return B


class Three(ControlAffineSystem):
    """3 states, 3 controls, diagonal but state-dependent B."""

    state_dim, control_dim = 3, 3
    angle_axes = (2,)

    def drift(self, x):
        x = self._states(x)
        return np.stack([-x[:, 0], np.sin(x[:, 2]), 0.2 + 0 * x[:, 0]], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((len(x), 3, 3))
        B[:, 0, 0] = 1.0
        B[:, 1, 1] = 1.0 + 0.5 * x[:, 0] ** 2
        B[:, 2, 2] = 0.5
        return B


class Oscillator(ControlAffineSystem):
    """A damped oscillator written by hand: linear, but without linear_matrices()."""

    state_dim, control_dim = 2, 1

    def drift(self, x):
        x = self._states(x)
        return x @ np.array([[0.0, 1.0], [-1.0, -0.2]]).T

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((len(x), 2, 1))
        B[:, 1, 0] = 1.0
        return B


def pointmass_problem(n=41, T=1.0):
    grid = Grid([Axis(-2, 2, n), Axis(-3, 3, n)])
    return Problem(PointMass(), grid, T, Quadratic([0, 0], [1, 0.5]), temperature=0.5)


# --------------------------------------------------------------------------- journeys


def j_save_numpy_scalar_parameter():
    """parameters() returning a numpy scalar (np.float64), as a user's own arithmetic gives."""
    grid = Grid([Axis(-2, 2, 31), Axis(-3, 3, 31)])
    p = Problem(Drag(np.float64(0.3)), grid, 0.5, Quadratic([0, 0], [1, 0.5]), temperature=0.5)
    s, _ = quiet(gridlbc.solve, p, dt=0.05, fitting=None)
    _, w_save = quiet(gridlbc.save, s, TMP / "np_scalar.npz")
    _, w_load = quiet(gridlbc.load, TMP / "np_scalar.npz")
    odd = [m for m in messages(w_save + w_load, gridlbc.GridlbcWarning) if "system" in m]
    if odd:
        raise Finding(
            "Drag(np.float64(0.3)) with parameters() {'k': self.k}: save warns and load warns "
            f"that the system differs ({len(odd)} warnings), e.g. save: {odd[0][:260]!r}"
        )
    return "saved and loaded without a system warning"


def j_save_tuple_parameter():
    """parameters() returning a tuple: recorded as a list, rebuilt as a list."""
    grid = Grid([Axis(-2, 2, 31), Axis(-3, 3, 31)])
    p = Problem(Gains((0.3, 1.0)), grid, 0.5, Quadratic([0, 0], [1, 0.5]), temperature=0.5)
    s, _ = quiet(gridlbc.solve, p, dt=0.05, fitting=None)
    _, w_save = quiet(gridlbc.save, s, TMP / "tuple.npz")
    s2, w_load = quiet(gridlbc.load, TMP / "tuple.npz")
    odd = [m for m in messages(w_save + w_load, gridlbc.GridlbcWarning) if "system" in m]
    X = grid.nodes()[::17]
    same = np.array_equal(s.value(X, 0.0), s2.value(X, 0.0))
    if odd:
        raise Finding(
            f"Gains((0.3, 1.0)) (parameters() returns the tuple): {len(odd)} system warnings on "
            f"save/load (values equal: {same}); load: {odd[-1][:200]!r}"
        )
    return "tuple parameters round trip quietly"


def j_shapes_and_times_custom_3d():
    """A 3-D user system with one control, periodic axis, list states, t at/between/out of slices."""
    grid = Grid([Axis(-np.pi, np.pi, 16, periodic=True), Axis(-3, 3, 17), Axis(-1, 1, 9)])
    p = Problem(
        Rotor(),
        grid,
        0.6,
        Quadratic([0, 0, 0], [2, 0.2, 0.5]),
        state_cost=lambda x: 0.1 * x[:, 2] ** 2,
        temperature=0.7,
    )
    s, caught = quiet(gridlbc.solve, p)
    if numpy_warnings(caught):
        raise Finding(f"stray numpy warning: {numpy_warnings(caught)[0].message}")
    x = [0.2, 0.1, 0.0]
    checks = {
        "value one": np.shape(s.value(x, 0.0)) == (),
        "value int list": np.isfinite(s.value([0, 1, 0], 0)),
        "value float32": np.isfinite(s.value(np.array(x, np.float32), np.float32(0.3))),
        "policy one": s.policy(x, 0.0).shape == (1,),
        "policy many": s.policy([x, x], 0.0).shape == (2, 1),
        "policy (1,d)": s.policy([x], 0.0).shape == (1, 1),
        "desirability": s.desirability([x, x], 0.6).shape == (2,),
        "error one": np.shape(s.error_estimate(x)) == (),
        "error many": s.error_estimate([x, x], 0.3).shape == (2,),
        "empty": s.value(np.zeros((0, 3)), 0.0).shape == (0,),
        "wrap": abs(s.value([0.2 + 2 * np.pi, 0.1, 0.0], 0.0) - s.value(x, 0.0)) < 1e-12,
    }
    bad = [k for k, ok in checks.items() if not ok]
    for t in (0.7, -0.1, np.nan):
        expect_clear_error(lambda t=t: s.value(x, t), ["t must lie"])
    expect_clear_error(lambda: s.value([0.0, 0.0], 0.0), ["shape"])
    expect_clear_error(lambda: s.value([np.nan, 0, 0], 0.0), ["non-finite"])
    if bad:
        raise Finding(f"shape checks failed: {bad}")
    return "shapes (d,), (N,d), (1,d), lists, float32, empty, wrap, and t errors all clear"


def j_superposition_pointmass():
    """solve_many(fitting=None) with Quadratic and lambda costs, combined vs the composite solve."""
    p = pointmass_problem()
    p = p.replace(state_cost=Quadratic([0.5, 0], [0.2, 0.0]))
    costs = [
        Quadratic([-1, 0], [2, 0.5]),
        Quadratic([1, 0], [2, 0.5]),
        lambda x: 0.3 * x[:, 0] ** 2,
    ]
    w = [1.0, 0.5, 2.0]
    sols, _ = quiet(gridlbc.solve_many, p, costs, fitting=None, dt=0.02)
    comb, _ = quiet(gridlbc.combine, sols, weights=w)

    def composite(x):
        x = np.atleast_2d(x)
        return -0.5 * np.log(sum(wi * np.exp(-c(x) / 0.5) for wi, c in zip(w, costs)))

    direct, _ = quiet(gridlbc.solve, p.replace(terminal_cost=composite), fitting=None, dt=0.02)
    X = p.grid.nodes()[::53]
    err = max(
        max(
            np.abs(comb.value(X, t) - direct.value(X, t)).max(),
            np.abs(comb.policy(X, t) - direct.policy(X, t)).max(),
        )
        for t in (0.0, 0.37, 1.0)
    )
    if err > 1e-10 or not comb.exact:
        raise Finding(f"superposition off by {err:.3g} (exact={comb.exact})")
    loaded = [gridlbc.load(gridlbc.save(s, TMP / f"sp{i}.npz")) for i, s in enumerate(sols)]
    again, _ = quiet(gridlbc.combine, loaded, w)
    if not np.array_equal(again.value(X, 0.0), comb.value(X, 0.0)):
        raise Finding("combination of loaded components differs from the original combination")
    return f"combine = composite solve to {err:.1e} at t 0, 0.37, T; loaded components equal"


def j_superposition_custom_periodic():
    """Same on a user system with a periodic axis and a state-dependent B."""
    grid = Grid([Axis(-np.pi, np.pi, 16, periodic=True), Axis(-3, 3, 17), Axis(-1, 1, 9)])
    lam = 0.7
    p = Problem(Rotor(), grid, 0.4, Quadratic([0, 0, 0], [1, 0.2, 0.5]), temperature=lam)
    costs = [Quadratic([1.0, 0, 0], [1, 0.2, 0.5]), lambda x: 0.5 * (1 - np.cos(x[:, 0] + 1))]
    sols, _ = quiet(gridlbc.solve_many, p, costs, fitting=None, dt=0.04)

    # the costs as the problem evaluates them (a Quadratic is wrap-aware only once bound:
    # see j_quadratic_standalone_wrap)
    bound = [p.replace(terminal_cost=c).terminal_cost for c in costs]

    def composite(x):
        return -lam * np.log(sum(np.exp(-c(x) / lam) for c in bound))

    direct, _ = quiet(gridlbc.solve, p.replace(terminal_cost=composite), fitting=None, dt=0.04)
    comb, _ = quiet(gridlbc.combine, sols)
    X = np.random.default_rng(0).uniform([-4, -3, -1], [4, 3, 1], (200, 3))
    err = np.abs(comb.value(X, 0.0) - direct.value(X, 0.0)).max()
    perr = np.abs(comb.policy(X, 0.13) - direct.policy(X, 0.13)).max()
    if max(err, perr) > 1e-10:
        raise Finding(f"periodic superposition off: value {err:.3g}, policy {perr:.3g}")
    return f"value {err:.1e}, policy {perr:.1e}"


def j_quadratic_standalone_wrap():
    """A user's own composite cost built from the Quadratic they gave a problem with an angle."""
    grid = Grid([Axis(-np.pi, np.pi, 16, periodic=True), Axis(-3, 3, 17), Axis(-1, 1, 9)])
    q = Quadratic([1.0, 0, 0], [1, 0.2, 0.5])
    p = Problem(Rotor(), grid, 0.4, q, temperature=0.7)
    x = np.array([[-3.0, 0.0, 0.0]])
    mine, theirs = float(q(x)[0]), float(p.terminal_cost(x)[0])
    if abs(mine - theirs) > 1e-12:
        raise Finding(
            f"q = {q!r} called directly gives q(x) = {mine:.4f} at x = (-3, 0, 0); the problem's "
            f"terminal cost, printed the same ({p.terminal_cost!r}), gives {theirs:.4f}: a "
            "composite written from q (lambda x: -lam*log(exp(-q(x)/lam) + ...)) is silently "
            "not the composite of the solved costs near the seam"
        )
    return "same"


def j_project_periodic_without_grid():
    """project(target, components) on a pendulum's angle, with and without the grid."""
    grid = Grid([Axis(-np.pi, np.pi, 40, periodic=True), Axis(-6, 6, 41)])
    comps = [Quadratic([-3.0, 0], [2, 0.2]), Quadratic([0.0, 0], [2, 0.2])]
    target = Quadratic([3.0, 0], [2, 0.2])  # 0.28 rad from the first component across the seam
    with_grid, _ = quiet(gridlbc.project, target, comps, grid)
    without, caught = quiet(gridlbc.project, target, comps)
    if np.abs(with_grid - without).max() > 0.05:
        raise Finding(
            f"weights {np.round(with_grid, 4).tolist()} with grid=, "
            f"{np.round(without, 6).tolist()} without (the closed form ignores the angle's "
            f"wrap: the Quadratics carry no periods until a Problem binds them); warnings: "
            f"{[m[:60] for m in messages(caught)]}"
        )
    return "same weights"


def j_combine_negative_weights():
    """Projection-style negative weights where the blend's desirability goes negative."""
    from gridlbc.systems import Pendulum

    grid = Grid([Axis(-np.pi, np.pi, 40, periodic=True), Axis(-6, 6, 41)])
    comps = [Quadratic([-3.0, 0], [2, 0.2]), Quadratic([0.0, 0], [2, 0.2])]
    p = Problem(Pendulum(), grid, 1.0, comps[0], temperature=1.0)
    sols, _ = quiet(gridlbc.solve_many, p, comps, fitting=None, dt=0.02)
    c, _ = quiet(gridlbc.combine, sols, [1.0, -0.9])
    x = np.array([[0.0, 0.0]])
    z = c.desirability(x, 0.0)
    v, caught = quiet(c.value, x, 0.0)
    said = messages(caught)
    if z[0] < 0 and any("underflow" in m for m in said):
        raise Finding(
            f"Σ w_i z_i = {z[0]:.4f} < 0 at x = (0, 0) (z_i = "
            f"{[round(float(s.desirability(x, 0.0)[0]), 4) for s in sols]}, w = (1, -0.9)); "
            f"value(x) = {v[0]} with the warning {said[0][:150]!r}: it did not underflow, "
            "the blend is negative there (simulate then raises 'a grid policy is undefined "
            "where the desirability underflowed')"
        )
    return f"z {z[0]}, v {v[0]}, warnings {said}"


def j_combine_project_naive_edges():
    """Weights as ints/lists, bad weights, combine of a combination, naive_blend, project."""
    p = pointmass_problem(31)
    costs = [Quadratic([-1, 0], [2, 0.5]), Quadratic([1, 0], [2, 0.5])]
    sols, _ = quiet(gridlbc.solve_many, p, costs, fitting=None, dt=0.05)
    X = p.grid.nodes()[::37]
    one, _ = quiet(lambda: gridlbc.combine(sols, weights=[1, 0]).value(X, 0.0))
    if np.abs(one - sols[0].value(X, 0.0)).max() > 1e-12:
        raise Finding("combine with weights [1, 0] differs from the first component")
    expect_clear_error(lambda: gridlbc.combine(sols, weights=[1.0]), ["weights"])
    expect_clear_error(lambda: gridlbc.combine(sols, weights=[1.0, np.nan]), ["finite"])
    expect_clear_error(lambda: gridlbc.combine(sols, weights=[0, 0]), ["zero"])
    expect_clear_error(lambda: gridlbc.combine([]), ["empty"])
    nested, _ = quiet(lambda: gridlbc.combine([gridlbc.combine(sols), sols[0]]).value(X, 0.0))
    nb = gridlbc.naive_blend(sols, [1, 1])
    mean = np.mean([s.policy(X, 0.3) for s in sols], axis=0)
    if np.abs(nb.policy(X, 0.3) - mean).max() > 1e-12 or nb.policy([0.1, 0.2], 0.3).shape != (1,):
        raise Finding("naive_blend is not the mean of the policies, or its (d,) shape is off")
    w, _ = quiet(gridlbc.project, Quadratic([0.3, 0], [2, 0.5]), costs, p.grid, temperature=0.5)
    if np.shape(w) != (2,) or not np.all(np.isfinite(nested)):
        raise Finding(f"project gave {w!r}")
    return "weights, errors, nested combine, naive_blend, project all fine"


def j_project_number_component():
    """The exit costs solve_many accepts (a number among them) given to project as they are."""
    grid = Grid([Axis(-2, 2, 41), Axis(-2, 2, 41)])
    E = Ball([1.0, 0.0], 0.3) | Box([-2, -2], [-1.8, 2])
    p = Problem(Flow(), grid, None, state_cost=lambda x: 1.0 + 0 * x[:, 0], temperature=0.5, exit=E)
    costs = [lambda x: x[:, 1] ** 2, 0.5]
    quiet(gridlbc.solve_many, p, costs)  # accepted
    try:
        quiet(gridlbc.project, lambda x: x[:, 1] ** 2 + 0.1, costs, grid, temperature=0.5, where=E)
    except TypeError as e:
        raise Finding(
            f"solve_many accepts exit cost 0.5 but project(target, same list, ...) raises "
            f"TypeError: {e}"
        ) from e
    return "project accepts the same costs as solve_many"


def j_first_exit_union_stray_warning():
    """A first exit with a horizon, a union exit set and a constant exit cost: the default solve."""
    grid = Grid([Axis(-2, 2, 41), Axis(-2, 2, 41)])
    E = Ball([1.0, 0.0], 0.3) | Box([-2, -2], [-1.8, 2])
    p = Problem(
        Flow(),
        grid,
        1.0,
        Quadratic([0, 0], [1, 1]),
        state_cost=lambda x: 1.0 + 0 * x[:, 0],
        temperature=0.5,
        exit=E,
        exit_cost=0.2,
    )
    _, caught = quiet(gridlbc.solve, p, progress=False)
    stray = numpy_warnings(caught)
    if stray:
        w = stray[0]
        raise Finding(
            f"{len(stray)} stray numpy RuntimeWarning(s) from the default solve: "
            f"{w.message} ({Path(w.filename).name}:{w.lineno})"
        )
    return "no numpy warning"


def j_first_exit_journey():
    """README first exit with a user system: value/policy without t, inside E, certify, compose."""
    grid = Grid([Axis(-2, 2, 41), Axis(-2, 2, 41)])
    E = Ball([1.0, 0.0], 0.3) | Box([-2, -2], [-1.8, 2])
    lam = 0.5
    p = Problem(
        Flow(),
        grid,
        None,
        state_cost=lambda x: 1.0 + 0 * x[:, 0],
        temperature=lam,
        exit=E,
        exit_cost=lambda x: x[:, 1] ** 2,
    )
    s, _ = quiet(gridlbc.solve, p)
    x0 = [0.0, 0.5]
    if s.policy(x0).shape != (2,) or s.policy([x0, x0]).shape != (2, 2):
        raise Finding("first-exit policy shapes")
    if s.value(x0, 3.0) != s.value(x0):
        raise Finding("a first-exit value depends on the t it is given")
    if abs(s.value([1.0, 0.1]) - 0.01) > 1e-12 or np.any(s.policy([1.0, 0.1]) != 0):
        raise Finding(f"inside E: v {s.value([1.0, 0.1])}, u {s.policy([1.0, 0.1])}")
    c, _ = quiet(gridlbc.certify, p, s.policy, x0, n_samples=200, dt=0.005, max_time=10, seed=0)
    gap = abs(c.optimal_value - s.value(x0))
    if gap > 3 * c.optimal_value_se + 2 * s.error_estimate(x0):
        raise Finding(
            f"certified {c.optimal_value:.4f} ± {c.optimal_value_se:.4f} vs {s.value(x0)}"
        )
    ecs = [lambda x: x[:, 1] ** 2, 0.5, Quadratic([1, 0], [1, 1])]
    many, _ = quiet(gridlbc.solve_many, p, ecs)

    def composite(x):
        x = np.atleast_2d(x)
        z = np.exp(-ecs[0](x) / lam) + np.exp(-0.5 / lam) + np.exp(-ecs[2](x) / lam)
        return -lam * np.log(z)

    direct, _ = quiet(gridlbc.solve, p.replace(exit_cost=composite))
    X = np.random.default_rng(1).uniform(-2, 2, (300, 2))
    comb, _ = quiet(gridlbc.combine, many)
    err = np.abs(comb.value(X) - direct.value(X)).max()
    if err > 1e-10:
        raise Finding(f"first-exit composition off by {err}")
    return (
        f"v(x0) {s.value(x0):.4f} vs certified {c.optimal_value:.4f} ± {c.optimal_value_se:.4f}; "
        f"composition exact to {err:.1e}"
    )


def j_first_exit_save_load():
    """Save and load a first-exit solution with a Ball exit set; read near E's edge, certify."""
    grid = Grid([Axis(-2, 2, 41), Axis(-3, 3, 41)])
    E = Ball([0, 0], [0.3, 0.5])
    p = Problem(
        PointMass(), grid, None, state_cost=lambda x: 0.5 + 0 * x[:, 0], temperature=0.5, exit=E
    )
    s, _ = quiet(gridlbc.solve, p, error_estimate=False)
    s2, _ = quiet(gridlbc.load, gridlbc.save(s, TMP / "fe.npz"))
    X = np.random.default_rng(0).uniform([-0.6, -0.8], [0.6, 0.8], (4000, 2))
    inside = region_mask(E, X)
    diff = np.abs(s.value(X) - s2.value(X))
    outside_changed = ~inside & (diff > 1e-9)
    if outside_changed.any():
        i = np.flatnonzero(outside_changed)[np.argmax(diff[outside_changed])]
        x0 = X[i]
        c1, _ = quiet(gridlbc.certify, p, s.policy, x0, n_samples=50, dt=0.002, max_time=5, seed=0)
        c2, _ = quiet(
            gridlbc.certify, s2.problem, s2.policy, x0, n_samples=50, dt=0.002, max_time=5, seed=0
        )
        raise Finding(
            f"after load, {outside_changed.sum()} of {(~inside).sum()} states OUTSIDE the exit "
            f"ball read differently (max {diff[~inside].max():.3f}; inside E up to "
            f"{diff[inside].max():.3f}); at x0 = {np.round(x0, 4).tolist()} (outside {E!r}) "
            f"v {s.value(x0):.4f} -> {s2.value(x0):.4f}, u {s.policy(x0)} -> {s2.policy(x0)}; "
            f"loaded exit prints as {s2.problem.exit!r} but is a {type(s2.problem.exit).__name__} "
            f"with x0 inside; certify on the loaded problem: v* {c2.optimal_value:.4f} vs "
            f"{c1.optimal_value:.4f} on the original"
        )
    return "first-exit round trip exact"


def j_average_cost():
    """horizon='average' on the point mass: c against Riccati, save/load, simulate, certify."""
    import scipy.linalg as sl

    grid = Grid([Axis(-2, 2, 31), Axis(-3, 3, 31)])
    p = Problem(
        PointMass(), grid, "average", state_cost=Quadratic([0, 0], [1, 0.2]), temperature=0.5
    )
    s, _ = quiet(gridlbc.solve, p)
    A = np.array([[0, 1], [0, 0.0]])
    B = np.array([[0], [1.0]])
    P = sl.solve_continuous_are(A, B, 2 * np.diag([1, 0.2]), np.eye(1))
    c_exact = 0.5 * 0.5 * np.trace(B @ B.T @ P)
    rel = abs(s.average_cost - c_exact) / c_exact
    s2, _ = quiet(gridlbc.load, gridlbc.save(s, TMP / "avg.npz"))
    X = np.random.default_rng(0).uniform(-2, 2, (100, 2))
    same = (
        s2.average_cost == s.average_cost
        and np.array_equal(s.value(X), s2.value(X))
        and np.array_equal(s.policy(X), s2.policy(X))
    )
    expect_clear_error(
        lambda: gridlbc.certify(p, s.policy, [0.5, 0], n_samples=10, max_time=1.0), ["average"]
    )
    r = gridlbc.simulate(p, s.policy, [0.5, 0], n_samples=3, dt=0.01, max_time=1.0, seed=0)
    if rel > 0.01 or not same or r.costs.shape != (3,):
        raise Finding(f"average cost {s.average_cost} vs Riccati {c_exact} ({rel:.2%}); rt {same}")
    return f"c {s.average_cost:.5f} vs Riccati {c_exact:.5f} ({rel:.2%}); round trip exact"


def j_solve_options():
    """tol/states/times/max_seconds, dt, settings, presets, methods, fitting, against lq_solution."""
    p = pointmass_problem(31)
    lq = gridlbc.reference.lq_solution(p)
    x0 = [0.5, 0.0]
    st, _ = quiet(gridlbc.solve, p, tol=0.01, states=[x0], times=[0.0, 0.5], max_seconds=30)
    err = abs(st.value(x0, 0) - lq.value(x0, 0)) / lq.value(x0, 0)
    if err > 0.01:
        raise Finding(f"tol=0.01 solve is {err:.2%} from Riccati")
    expect_clear_error(lambda: gridlbc.solve(p, times=[0.5]), ["tol"])
    expect_clear_error(lambda: gridlbc.solve(p, tol=0.05, states=[x0], times=[2.0]), ["times"])
    expect_clear_error(lambda: gridlbc.solve(p, "fastest"), ["preset"])
    expect_clear_error(lambda: gridlbc.solve(p, fiting=None), ["fiting"])
    expect_clear_error(lambda: gridlbc.solve(p, fitting="bogus"), ["fitting"])
    expect_clear_error(lambda: gridlbc.solve(p, 2.0), ["horizon"])
    out = []
    for kw in (
        {"method": "splitting", "dt": 0.02},
        {"method": "implicit", "dt": 0.02},
        {"fitting": "terminal"},
        {"fitting": None, "dt": 0.02},
        {"fitting": lambda x: x[:, 0] ** 2},
    ):
        s, _ = quiet(gridlbc.solve, p, **kw)
        out.append(abs(s.value(x0, 0) - lq.value(x0, 0)) / lq.value(x0, 0))
    s, _ = quiet(gridlbc.solve, p, "fast")
    s, _ = quiet(gridlbc.solve, p, settings=gridlbc.SolverSettings(dt=0.05))
    if s.diagnostics.dt != 0.05 or max(out) > 0.05:
        raise Finding(f"relative errors vs lq {np.round(out, 4)}")
    return f"tol=0.01: {err:.2%} from Riccati; methods/fittings within {max(out):.2%}"


def j_solve_dtype_numpy():
    """dtype given the numpy way (np.float32), as users write it for every other numpy API."""
    p = pointmass_problem(21)
    try:
        s, _ = quiet(gridlbc.solve, p, dtype=np.float32)
    except (TypeError, ValueError) as e:
        raise Finding(f"solve(dtype=np.float32) refused: {e}") from e
    return f"accepted ({s.value([0.1, 0.2], 0):.4f})"


def j_costs_variants():
    """Costs returning lists, ints, (N,1); time-dependent, negative, NaN; 3 controls, R per control."""
    grid = Grid([Axis(-1, 1, 15), Axis(-1.5, 1.5, 17), Axis(-np.pi, np.pi, 16, periodic=True)])
    p = Problem(
        Three(),
        grid,
        0.5,
        lambda x: (x[:, 0] ** 2 + x[:, 1] ** 2).tolist(),
        state_cost=lambda x: 0.1 * np.ones(len(x)),
        control_cost=[1.0, 2.0, 0.5],
        temperature=0.4,
    )
    s, _ = quiet(gridlbc.solve, p)
    x = [0.1, 0.2, 3.0]
    if s.policy(x, 0).shape != (3,) or s.policy([x, x], 0.25).shape != (2, 3):
        raise Finding("3-control policy shapes")
    expect_clear_error(
        lambda: gridlbc.solve(p.replace(terminal_cost=lambda x: x[:, :1] ** 2)), ["shape"]
    )
    expect_clear_error(
        lambda: gridlbc.solve(p.replace(state_cost=lambda x, t: t * np.ones(len(x)))), ["time"]
    )
    expect_clear_error(
        lambda: gridlbc.solve(p.replace(state_cost=lambda x: -0.1 * np.ones(len(x)))),
        ["non-negative"],
    )
    expect_clear_error(
        lambda: gridlbc.solve(p.replace(terminal_cost=lambda x: x[:, 0] * np.nan)), ["finite"]
    )
    c, _ = quiet(gridlbc.certify, p, s.policy, x, n_samples=200, dt=0.005, seed=0)
    gap = abs(c.optimal_value - s.value(x, 0))
    est = s.error_estimate(x)
    if gap > 3 * c.optimal_value_se + 2 * est:
        raise Finding(f"3x3 certified {c.optimal_value} vs {s.value(x, 0)} (ê {est})")
    return f"3 controls: v {s.value(x, 0):.4f}, certified {c.optimal_value:.4f}, ê {est:.4f}"


def j_simulate_certify_edges():
    """simulate/certify with lists, ints, policies returning lists, bad policies, seeds, reflect."""
    p = pointmass_problem()
    s, _ = quiet(gridlbc.solve, p, dt=0.02)
    x0 = [0.5, 0.0]
    r = gridlbc.simulate(p, s.policy, x0, n_samples=5, dt=0.01, seed=1)
    shapes = (r.times.shape, r.states.shape, r.controls.shape, r.costs.shape)
    if shapes != ((101,), (5, 101, 2), (5, 100, 1), (5,)):
        raise Finding(f"rollout shapes {shapes}")
    gridlbc.simulate(p, lambda x, t: [[0.0]] * len(x), x0, n_samples=3, dt=0.01, seed=1)
    expect_clear_error(
        lambda: gridlbc.simulate(p, lambda x, t: np.zeros(len(x)), x0, n_samples=3), ["(N, m)"]
    )
    expect_clear_error(lambda: gridlbc.simulate(p, s, x0, n_samples=3), ["callable"])
    expect_clear_error(lambda: gridlbc.simulate(p, s.policy, x0, n_samples=2.0), ["integer"])
    a = gridlbc.simulate(p, s.policy, x0, n_samples=4, dt=0.01, seed=3).costs
    b = gridlbc.simulate(p, s.policy, x0, n_samples=4, dt=0.01, seed=3).costs
    if not np.array_equal(a, b):
        raise Finding("same seed, different rollouts")
    lq = gridlbc.reference.lq_solution(p)
    c, _ = quiet(gridlbc.certify, p, s.policy, x0, n_samples=400, dt=0.005, seed=0)
    if abs(c.optimal_value - lq.value(x0, 0)) > 4 * c.optimal_value_se + 0.01:
        raise Finding(f"certified {c.optimal_value} ± {c.optimal_value_se} vs lq {lq.value(x0, 0)}")
    expect_clear_error(
        lambda: gridlbc.certify(p, s.policy, x0, n_samples=10, boundary="bogus"), ["boundary"]
    )
    return f"certified {c.optimal_value:.4f} ± {c.optimal_value_se:.4f} vs Riccati {lq.value(x0, 0):.4f}"


def j_policy_wrong_signature():
    """A user policy written policy(x) (no t), the commonest slip."""
    p = pointmass_problem(21)
    try:
        gridlbc.simulate(p, lambda x: np.zeros((len(x), 1)), [0.5, 0], n_samples=2, dt=0.01)
    except TypeError as e:
        if "policy" not in str(e):
            raise Finding(f"raw TypeError from the user's function: {e}") from e
    return "clear"


def j_save_load_variants():
    """Round trips bit for bit: float32, store_every, implicit, fitted to a cost; odd paths."""
    p = pointmass_problem()
    X = np.random.default_rng(0).uniform([-2, -3], [2, 3], (300, 2))
    for opts in (
        {"dtype": "float32"},
        {"store_every": 3, "dt": 0.01},
        {"method": "implicit", "dt": 0.05},
        {"fitting": Quadratic([0.3, 0], [1, 1])},
    ):
        s, _ = quiet(gridlbc.solve, p, **opts)
        s2 = gridlbc.load(gridlbc.save(s, TMP / "o.npz"))
        for t in (0.0, 0.013, 0.5, float(s.times[1]), 1.0):
            if not (
                np.array_equal(s.value(X, t), s2.value(X, t))
                and np.array_equal(s.policy(X, t), s2.policy(X, t))
            ):
                raise Finding(f"round trip with {opts} differs at t = {t}")
        if not np.array_equal(s.error_estimate(X), s2.error_estimate(X)):
            raise Finding(f"error estimate differs after load with {opts}")
    return "float32, store_every, implicit, fitted: bit for bit at 5 times"


def j_save_path_without_suffix():
    """save(s, 'run1') then load('run1'): the same string both ways."""
    p = pointmass_problem(21)
    s, _ = quiet(gridlbc.solve, p, dt=0.05)
    written = gridlbc.save(s, TMP / "run1")
    try:
        gridlbc.load(TMP / "run1")
    except FileNotFoundError as e:
        raise Finding(
            f"save(s, 'run1') wrote {written.name}, load('run1') raises FileNotFoundError: {e}"
        ) from e
    return "symmetric"


def j_load_damaged_file():
    p = Path(TMP / "junk.npz")
    p.write_bytes(b"not a zip file")
    text = expect_clear_error(lambda: gridlbc.load(p), ["not a readable"])
    if "allow_pickle" in text:
        raise Finding(f"message passes on numpy's advice to unpickle an untrusted file: {text}")
    return "clear"


def j_lq_user_linear_system():
    """lq_solution on a user's own linear system (drift x @ A.T, constant B)."""
    grid = Grid([Axis(-3, 3, 61), Axis(-3, 3, 61)])
    p = Problem(
        Oscillator(),
        grid,
        1.0,
        Quadratic([0.5, 0], [1, 0.5]),
        state_cost=Quadratic([0, 0], [0.5, 0.1]),
        temperature=0.5,
        control_cost=2.0,
    )
    try:
        gridlbc.reference.lq_solution(p)
    except TypeError as e:
        if "linear_matrices" not in str(e) and "LinearSystem" not in str(e):
            raise Finding(f"a linear user system is called nonlinear: {e}") from e
    lq = gridlbc.reference.lq_solution(
        p.replace(system=gridlbc.systems.LinearSystem([[0, 1], [-1, -0.2]], [[0], [1]]))
    )
    s, _ = quiet(gridlbc.solve, p, dt=0.01)
    X = np.array([[0.3, 0.2], [-0.5, 0.4], [1.0, -0.5]])
    err = np.abs(s.value(X, 0) - lq.value(X, 0)).max()
    if err > np.max(s.error_estimate(X)) * 2 + 1e-3:
        raise Finding(f"grid vs Riccati {err}")
    return f"grid vs Riccati {err:.1e}"


def j_hjb_reference():
    """solve_hjb on the LQ point mass: bounds forms, and its accuracy against lq_solution."""
    from gridlbc.reference import lq_solution, solve_hjb

    p = pointmass_problem()
    x0 = [0.5, 0.0]
    h, caught = quiet(solve_hjb, p, dt=0.02)
    quiet(solve_hjb, p, dt=0.02, control_bounds=[(-1, 1)])
    expect_clear_error(lambda: solve_hjb(p, control_bounds=(1, -1)), ["lo"])
    lq = lq_solution(p)
    rel = abs(h.value(x0, 0) - lq.value(x0, 0)) / lq.value(x0, 0)
    if rel > 0.05 and not messages(caught):
        raise Finding(
            f"solve_hjb on 41² (dt 0.02) reads {h.value(x0, 0):.4f} against Riccati "
            f"{lq.value(x0, 0):.4f} ({rel:.1%}), without a warning (the LBC solve: 0.1 %)"
        )
    return f"{rel:.2%} from Riccati"


def j_trajectory():
    """optimize/expand on the LQ point mass; combine expansions; grid-free problem."""
    from gridlbc import trajectory

    p = pointmass_problem()
    lq = gridlbc.reference.lq_solution(p)
    x0 = [0.5, 0.0]
    tr = trajectory.optimize(p, x0, restarts=1, seed=0)
    shapes = (tr.times.shape, tr.states.shape, tr.controls.shape)
    comp = trajectory.expand(p, tr)
    X = np.array([[0.3, 0.2], [-0.4, 0.5], [0.8, -0.3]])
    err = np.abs(comp.value(X, 0.4) - lq.value(X, 0.4)).max()
    if err > 1e-4 or shapes[1][1] != 2 or shapes[2][1] != 1:
        raise Finding(f"expansion vs Riccati {err}, shapes {shapes}")
    q2 = p.replace(terminal_cost=Quadratic([1, 0], [1, 0.5]))
    comp2 = trajectory.expand(q2, trajectory.optimize(q2, x0, restarts=1, seed=0))
    cb = gridlbc.combine([comp, comp2])
    if cb.blend_weights(X, 0.2).shape != (3, 2) or cb.policy(X, 0.2).shape != (3, 1):
        raise Finding("trajectory combination shapes")
    free = p.replace(grid=None)
    v = trajectory.expand(free, trajectory.optimize(free, x0, restarts=1, seed=0)).value(x0, 0)
    expect_clear_error(lambda: trajectory.optimize(p, [x0], restarts=1, seed=0), ["x0"])
    return f"expansion = Riccati to {err:.1e}; grid-free v {v:.4f}"


def j_sweep_local():
    """gridlbc.sweep with one local worker on an importable user system, and a rerun."""
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        return "skipped: Dask not installed"
    module = TMP / "journey_systems.py"
    module.write_text(
        textwrap.dedent(
            """
            import numpy as np
            from gridlbc.systems import ControlAffineSystem

            class Drag(ControlAffineSystem):
                state_dim, control_dim = 2, 1
                def __init__(self, k=0.3):
                    self.k = k
                def drift(self, x):
                    x = self._states(x)
                    return np.stack([x[:, 1], -self.k * x[:, 1]], axis=1)
                def input_matrix(self, x):
                    x = self._states(x)
                    B = np.zeros((x.shape[0], 2, 1))
                    B[:, 1, 0] = 1.0
                    return B
                def parameters(self):
                    return {"k": self.k}
            """
        )
    )
    script = textwrap.dedent(
        f"""
        import sys, warnings, numpy as np, gridlbc
        sys.path.insert(0, {str(TMP)!r})
        from journey_systems import Drag
        from gridlbc import Axis, Grid, Problem, Quadratic
        if __name__ == "__main__":
            g = Grid([Axis(-2, 2, 21), Axis(-3, 3, 21)])
            probs = [Problem(Drag(k), g, 0.5, Quadratic([0, 0], [1, 0.5]), temperature=0.5)
                     for k in (0.1, 0.2)]
            ms = gridlbc.sweep(probs, {str(TMP / "sweep")!r}, states=[[0.5, 0.0]], workers=1,
                               dt=0.05, progress=False)
            assert all(m.error is None for m in ms), [m.error for m in ms]
            again = gridlbc.sweep(probs, {str(TMP / "sweep")!r}, states=[[0.5, 0.0]],
                                  workers=1, dt=0.05, progress=False)
            assert all(m.reused for m in again)
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                v = [gridlbc.load(m.path).value([0.5, 0.0], 0.0) for m in ms]
            assert np.allclose(v, [m.values[0] for m in ms])
            print("OK", v, len([x for x in w if "system" in str(x.message)]))
        """
    )
    path = TMP / "sweep_run.py"
    path.write_text(script)
    r = subprocess.run(
        [sys.executable, str(path)], capture_output=True, text=True, timeout=300, env=os.environ
    )
    if r.returncode != 0 or "OK" not in r.stdout:
        raise Finding(f"sweep failed: {r.stderr[-500:]}")
    return r.stdout.strip().splitlines()[-1]


def _cli(*args, cwd=TMP):
    return subprocess.run(
        [sys.executable, "-m", "gridlbc.cli", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=os.environ,
        timeout=300,
    )


PM_TOML = """
horizon = 1.0
temperature = 0.5

[system]
name = "PointMass"

[grid]
n = [31, 31]

[terminal_cost]
center = [{c}, 0]
weights = [2, 0.5]

[solver]
dt = 0.02
fitting = "none"
"""

FE_TOML = """
temperature = 0.5
exit_cost = 0.0

[system]
name = "PointMass"

[grid]
[[grid.axes]]
lo = -2
hi = 2
n = 31
[[grid.axes]]
lo = -3
hi = 3
n = 31

[state_cost]
center = [0, 0]
weights = [0.5, 0.05]

[[exit]]
box = { lower = [0.45, "-inf"], upper = ["inf", "inf"] }
[[exit]]
ball = { center = [-1.3, 0], radius = [0.2, 0.4] }
"""


def j_cli_horizon():
    """gridlbc solve/combine/certify/interactive on TOML files, --at, --tol, --project, --table."""
    (TMP / "a.toml").write_text(PM_TOML.format(c=-1))
    (TMP / "b.toml").write_text(PM_TOML.format(c=1))
    steps = [
        ("solve", "--config", "a.toml", "--out", "a.npz", "--at=0.5,0", "--quiet"),
        ("solve", "--config", "b.toml", "--out", "b.npz", "--quiet"),
        ("combine", "a.npz", "b.npz", "--at=0.2,0"),
        ("combine", "a.npz", "b.npz", "--project", "0.3,0", "--at=0.2,0"),
        ("combine", "a.npz", "b.npz", "--table", "grid.csv"),
        ("certify", "a.npz", "--state=0.5,0", "--samples", "100", "--seed", "0", "--quiet"),
        ("interactive", "a.npz", "b.npz", "--out", "page.html"),
        ("solve", "--config", "a.toml", "--tol", "0.05", "--at=0.5,0", "--out", "t.npz"),
    ]
    for args in steps:
        r = _cli(*args)
        if r.returncode != 0:
            raise Finding(f"gridlbc {' '.join(args)} exited {r.returncode}: {r.stderr[-300:]}")
    return "solve, combine (--at, --project, --table), certify, interactive, --tol: exit 0"


def j_cli_first_exit_certify():
    """gridlbc solve on the config docstring's first-exit example, then gridlbc certify on it."""
    (TMP / "fe.toml").write_text(FE_TOML)
    r = _cli("solve", "--config", "fe.toml", "--out", "fe.npz", "--at=0,0", "--quiet")
    if r.returncode != 0:
        raise Finding(f"solve first exit: {r.stderr[-300:]}")
    r = _cli("certify", "fe.npz", "--state=0,0", "--samples", "100", "--seed", "0", "--quiet")
    if r.returncode != 0:
        line = r.stderr.strip().splitlines()[-1]
        r2 = _cli("certify", "fe.npz", "--state=0,0", "--samples", "100", "--max-time", "10")
        line2 = r2.stderr.strip().splitlines()[-1]
        raise Finding(
            f"`gridlbc certify fe.npz --state=0,0` exits {r.returncode}: {line!r}; the flag it "
            f"asks for does not exist: `--max-time 10` gives {line2!r}"
        )
    return "certified"


def j_combine_mismatch_message():
    """combine two solutions whose grids differ only in their bounds (a default box vs mine)."""
    g1 = Grid([Axis(-2, 2, 31), Axis(-3, 3, 31)])
    g2 = Grid([Axis(-4, 4, 31), Axis(-6, 6, 31)])
    p1 = Problem(PointMass(), g1, 1.0, Quadratic([0, 0], [1, 1]), temperature=0.5)
    s1, _ = quiet(gridlbc.solve, p1, dt=0.05)
    s2, _ = quiet(gridlbc.solve, p1.replace(grid=g2, system=PointMass(2.0)), dt=0.05)
    text = expect_clear_error(lambda: gridlbc.combine([s1, s2]), ["grid"])
    part = text[text.index("grid (") + len("grid (") :].split("). ")[0]
    first, _, second = part.partition(" vs ")
    if first == second:
        raise Finding(
            f"the grids ({g1.axes[0].lo}..{g1.axes[0].hi} vs {g2.axes[0].lo}..{g2.axes[0].hi}) "
            f"are said to differ but are described identically; the message also names "
            f"'solutions[1] and solutions[0]' but lists [0]'s values first: {text}"
        )
    return "names the difference"


def j_load_system_class():
    """load(path, system=Drag) with the class instead of an instance."""
    grid = Grid([Axis(-2, 2, 21), Axis(-3, 3, 21)])
    p = Problem(Drag(0.3), grid, 0.5, Quadratic([0, 0], [1, 0.5]), temperature=0.5)
    s, _ = quiet(gridlbc.solve, p, dt=0.05)
    path = gridlbc.save(s, TMP / "drag.npz")
    text = expect_clear_error(lambda: gridlbc.load(path, system=Drag), ["system"])
    if "instance" not in text and "Drag()" not in text:
        raise Finding(f"class instead of instance: {text}")
    return "clear"


def j_solve_many_one_cost():
    """solve_many(problem, Quadratic(...)): one cost where a list is expected (a common slip)."""
    p = pointmass_problem(21)
    try:
        quiet(gridlbc.solve_many, p, Quadratic([1, 0], [1, 1]), dt=0.05)
    except TypeError as e:
        if "terminal_costs" not in str(e):
            raise Finding(f"raw TypeError: {e}") from e
    return "clear"


def j_combine_weights_generator():
    """combine(components, weights=<a generator>), as solve_many accepts a generator of costs."""
    p = pointmass_problem(21)
    s, _ = quiet(gridlbc.solve, p, dt=0.05)
    try:
        quiet(gridlbc.combine, [s, s], (w for w in (1.0, 1.0)))
    except TypeError as e:
        if "weights" not in str(e):
            raise Finding(f"raw TypeError: {e}") from e
    return "accepted or clear"


def j_state_cost_number():
    """state_cost=1.0 (a constant), as exit_cost=0.5 is accepted for the same problem."""
    grid = Grid([Axis(-2, 2, 31), Axis(-3, 3, 31)])
    try:
        Problem(PointMass(), grid, None, state_cost=1.0, exit=Ball([0, 0], 0.3), exit_cost=0.5)
    except TypeError as e:
        raise Finding(f"exit_cost=0.5 is accepted, state_cost=1.0 is refused: {e}") from e
    return "accepted"


JOURNEYS = {name[2:]: f for name, f in globals().items() if name.startswith("j_")}


def main(argv):
    if "--list" in argv or not argv:
        for name, f in JOURNEYS.items():
            print(f"{name}: {(f.__doc__ or '').strip().splitlines()[0]}")
        return 0
    chosen = [a for a in argv if not a.startswith("--")] or list(JOURNEYS)
    findings = 0
    for name in chosen:
        t0 = time.perf_counter()
        try:
            with np.errstate(all="warn", under="ignore"):
                msg = JOURNEYS[name]()
            print(f"PASS {name}: {msg} ({time.perf_counter() - t0:.1f} s)", flush=True)
        except Finding as e:
            findings += 1
            print(f"FINDING {name}: {e} ({time.perf_counter() - t0:.1f} s)", flush=True)
        except Exception as e:  # a crash is a finding too
            findings += 1
            print(f"FINDING {name}: crashed with {type(e).__name__}: {e}", flush=True)
    print(f"{findings} finding(s) in {len(chosen)} journeys")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
