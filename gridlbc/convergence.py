"""Convergence study: the z-space solvers and the value-space HJB solver under grid refinement.

Two cases, errors measured at t = 0 on a fixed lattice of evaluation points (off the grids, so the
interpolation is part of what is measured), restricted to where the value is within ``band`` of
its minimum (far tails, where no one steers, are excluded):

* **PointMass** (linear, quadratic costs): every solver against the exact Riccati solution
  (:func:`gridlbc.reference.lq_solution`, SPEC §6);
* **Pendulum** (nonlinear, no closed form): each solver against its own Richardson estimate from
  its two finest grids, v_R = 2 v_{h} − v_{2h} (first-order schemes), against the other solver's
  Richardson estimate, and the two solvers against each other on the same grid.

Observed orders are p = log(e_coarse / e_fine) / log(h_coarse / h_fine) between successive rows.

Richardson extrapolation *in z* (``"splitting+richardson"``), z_R = 2 z_h − z_{2h}, keeps exact
linearity in the terminal data (it is a fixed linear combination of two linear solves) but not
monotonicity: z_R may be negative in far tails, where its value is reported as +inf (counted in
``ConvergenceRow.negative``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .costs import Quadratic
from .grid import Axis, Grid
from .hjb import solve_hjb
from .problem import Problem
from .reference import lq_solution
from .solver import solve
from .systems import Pendulum, PointMass

SOLVERS = {
    "splitting": lambda problem: solve(problem, method="splitting"),
    "implicit": lambda problem: solve(problem, method="implicit"),
    "hjb": solve_hjb,
}
"""The solvers compared, by name: the two z-space schemes (default time steps) and the HJB."""


@dataclass(frozen=True)
class ConvergenceRow:
    """Errors of one solver on one grid against one reference, at t = 0 on the evaluation points.

    ``h`` is the largest grid spacing, ``dt`` the mean time step; ``value_max`` / ``value_mean``
    are the max / mean of |v − v_ref|, ``policy_max`` the max of |u − u_ref|; the orders compare
    with the previous row of the same case, solver and reference (NaN on the first);
    ``wall_time`` is the solve time in seconds (both solves for Richardson rows); ``negative`` the
    number of evaluation points where an extrapolated z was ≤ 0.
    """

    case: str
    solver: str
    reference: str
    shape: tuple[int, ...]
    h: float
    dt: float
    value_max: float
    value_mean: float
    policy_max: float
    value_order: float
    policy_order: float
    wall_time: float
    negative: int = 0


@dataclass(frozen=True)
class ConvergenceTable:
    """Rows of a convergence study and how the errors were measured (``points`` evaluation
    states, value within ``band`` of its minimum)."""

    rows: tuple[ConvergenceRow, ...]
    points: int
    band: float

    def select(self, case: str, solver: str, reference: str) -> tuple[ConvergenceRow, ...]:
        """The rows of one case, solver and reference, coarse to fine."""
        return tuple(r for r in self.rows
                     if (r.case, r.solver, r.reference) == (case, solver, reference))

    def series(self) -> list[tuple[str, str, str]]:
        """The distinct (case, solver, reference) triples, in order of appearance."""
        return list(dict.fromkeys((r.case, r.solver, r.reference) for r in self.rows))

    def format(self) -> str:
        """The table as fixed-width text."""
        head = (f"{'case':<9} {'solver':<20} {'reference':<21} {'grid':>9} {'h':>7} {'dt':>8} "
                f"{'max|dv|':>8} {'mean|dv|':>8} {'max|du|':>8} {'p(v)':>5} {'p(u)':>5} "
                f"{'time s':>7}")
        lines = [head, "-" * len(head)]
        for r in self.rows:
            grid = "×".join(map(str, r.shape))
            lines.append(
                f"{r.case:<9} {r.solver:<20} {r.reference:<21} {grid:>9} {r.h:7.4f} {r.dt:8.5f} "
                f"{r.value_max:8.4f} {r.value_mean:8.4f} {r.policy_max:8.4f} "
                f"{r.value_order:5.2f} {r.policy_order:5.2f} {r.wall_time:7.2f}"
                + (f"  ({r.negative} points with z ≤ 0)" if r.negative else "")
            )
        return "\n".join(lines)


# -- the two test problems -----------------------------------------------------------------------

def pointmass_problem(h: float) -> Problem:
    """PointMass (m = 1), λ = 0.5, q = xᵀdiag(0.5, 0.05)x, g = (x − (1, 0))ᵀdiag(2, 0.5)(x − (1, 0)),
    T = 2, on [−4, 4] × [−6, 6] with spacing ``h`` on both axes (8/h and 12/h must be integers)."""
    counts = [8 / h, 12 / h]
    if not all(abs(c - round(c)) < 1e-9 and c >= 2 for c in counts):
        raise ValueError(f"h must divide 8 and 12 into at least 2 cells (e.g. 1/4, 1/8), got {h}")
    grid = Grid([Axis(-4.0, 4.0, round(counts[0]) + 1, name="position"),
                 Axis(-6.0, 6.0, round(counts[1]) + 1, name="velocity")])
    return Problem(PointMass(), grid, 2.0, Quadratic([1.0, 0.0], [2.0, 0.5]),
                   Quadratic([0.0, 0.0], [0.5, 0.05]), control_cost=1.0, temperature=0.5)


PENDULUM_WEIGHTS = (10.0, 0.5)
"""Terminal weights of the pendulum study: g = θ² · 10 + ω² · 0.5 (upright at rest)."""


def pendulum_problem(n: int, temperature: float = 1.0, horizon: float = 1.0,
                     weights=PENDULUM_WEIGHTS) -> Problem:
    """Pendulum (m = l = 1, g = 9.81), θ periodic on [−π, π) with ``n`` nodes, ω ∈ [−8, 8] with
    n + 1 nodes (equal spacing 2π/n and 16/n), g = (θ, ω)ᵀdiag(weights)(θ, ω), no state cost."""
    grid = Grid([Axis(-math.pi, math.pi, n, periodic=True, name="theta"),
                 Axis(-8.0, 8.0, n + 1, name="omega")])
    return Problem(Pendulum(), grid, horizon, Quadratic([0.0, 0.0], list(weights)),
                   temperature=temperature)


def pointmass_points() -> np.ndarray:
    """Evaluation lattice |position| ≤ 2, |velocity| ≤ 3 (41 × 61 points)."""
    return _lattice(np.linspace(-2.0, 2.0, 41), np.linspace(-3.0, 3.0, 61))


def pendulum_points() -> np.ndarray:
    """Evaluation lattice θ ∈ [−π, π) (60 points), |ω| ≤ 5 (41 points): off the ω bounds."""
    return _lattice(np.linspace(-math.pi, math.pi, 61)[:-1], np.linspace(-5.0, 5.0, 41))


def _lattice(*axes) -> np.ndarray:
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))


# -- measuring -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Run:
    """One solve, reduced to what the table needs: v and u at the evaluation points at t = 0."""

    shape: tuple[int, ...]
    h: float
    dt: float
    value: np.ndarray
    policy: np.ndarray
    wall_time: float
    negative: int = 0


def _run(solver: str, problem: Problem, points: np.ndarray):
    solution = SOLVERS[solver](problem)
    run = _Run(problem.grid.shape, float(problem.grid.spacing.max()), solution.diagnostics.dt,
               solution.value(points, 0.0), solution.policy(points, 0.0),
               solution.diagnostics.wall_time)
    return run, solution


def richardson_z(fine, coarse, x, t: float = 0.0):
    """Value, policy and the count of z ≤ 0 of z_R = 2 z_fine − z_coarse at states ``x``.

    Linear in the nodal z of both solutions: v_R = −λ log z_R, u_R = λ R⁻¹ Bᵀ∇z_R / z_R.
    """
    problem = fine.problem
    L_f, z_f, g_f = fine.scaled_fields(x, t)
    L_c, z_c, g_c = coarse.scaled_fields(x, t)
    L = max(L_f, L_c)
    w_f, w_c = 2.0 * math.exp(L_f - L), math.exp(L_c - L)
    z = w_f * z_f - w_c * z_c
    g = w_f * g_f - w_c * g_c
    bad = ~(z > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        value = np.where(bad, np.inf, -problem.temperature * (np.log(np.where(bad, 1.0, z)) + L))
        policy = problem.temperature * (g @ problem.R_inv.T) / z[:, None]
    policy[bad] = np.nan
    return value, policy, int(bad.sum())


def _rows(case, solver, reference, runs, ref_values, ref_policies, mask):
    """Table rows of successive runs against per-run reference fields, with observed orders."""
    rows, previous = [], None
    for run, v_ref, u_ref in zip(runs, ref_values, ref_policies):
        dv = np.abs(run.value - v_ref)[mask]
        du = np.abs(run.policy - u_ref)[mask]
        errors = (float(dv.max()), float(dv.mean()), float(du.max()))
        orders = (math.nan, math.nan)
        if previous is not None:
            ratio = math.log(previous[0].h / run.h)
            orders = tuple(math.log(a / b) / ratio if a > 0 and b > 0 else math.nan
                           for a, b in ((previous[1][0], errors[0]), (previous[1][2], errors[2])))
        rows.append(ConvergenceRow(case, solver, reference, run.shape, run.h, run.dt, *errors,
                                   *orders, run.wall_time, run.negative))
        previous = (run, errors)
    return rows


def pointmass_study(spacings=(1 / 4, 1 / 8, 1 / 16, 1 / 32),
                    solvers=("splitting", "implicit", "hjb"), band: float = 5.0,
                    richardson: bool = True) -> ConvergenceTable:
    """Every solver against the Riccati solution on PointMass, over grid spacings ``spacings``.

    With ``richardson`` also the splitting scheme's z extrapolated across successive grids.
    The evaluation region: the lattice of :func:`pointmass_points` where v < min v + ``band``.
    """
    points = pointmass_points()
    exact = lq_solution(pointmass_problem(spacings[0]))
    v_exact, u_exact = exact.value(points, 0.0), exact.policy(points, 0.0)
    mask = v_exact < v_exact.min() + band
    rows = []
    for solver in solvers:
        runs, solutions = zip(*(_run(solver, pointmass_problem(h), points) for h in spacings))
        rows += _rows("pointmass", solver, "riccati", runs, [v_exact] * len(runs),
                      [u_exact] * len(runs), mask)
        if richardson and solver == "splitting" and len(runs) > 1:
            extrapolated = []
            for k in range(1, len(runs)):
                value, policy, negative = richardson_z(solutions[k], solutions[k - 1], points)
                extrapolated.append(_Run(runs[k].shape, runs[k].h, runs[k].dt, value, policy,
                                         runs[k].wall_time + runs[k - 1].wall_time, negative))
            rows += _rows("pointmass", "splitting+richardson", "riccati", extrapolated,
                          [v_exact] * len(extrapolated), [u_exact] * len(extrapolated), mask)
    return ConvergenceTable(tuple(rows), int(mask.sum()), band)


def pendulum_study(sizes=(64, 128, 256), solvers=("splitting", "hjb"), band: float = 5.0,
                   **problem_options) -> ConvergenceTable:
    """The z-space and HJB solvers on the pendulum (:func:`pendulum_problem`), ``sizes`` nodes per
    angle, against Richardson estimates v_R = 2 v_finest − v_next (first order) and each other.

    References, per solver: ``"own richardson"``; ``"<other> richardson"`` for each other solver;
    and ``"<other> same grid"`` for the other solvers on the same grid. The evaluation region: the
    lattice of :func:`pendulum_points` where the first solver's Richardson v < min + ``band``.
    """
    if len(sizes) < 2:
        raise ValueError("pendulum_study needs at least two grid sizes for a Richardson estimate")
    points = pendulum_points()
    runs = {s: [_run(s, pendulum_problem(n, **problem_options), points)[0] for n in sizes]
            for s in solvers}
    estimate = {s: (2 * r[-1].value - r[-2].value, 2 * r[-1].policy - r[-2].policy)
                for s, r in runs.items()}
    first = estimate[solvers[0]][0]
    mask = first < first.min() + band
    rows = []
    for s in solvers:
        count = len(runs[s])
        for other in solvers:
            name = "own richardson" if other == s else f"{other} richardson"
            rows += _rows("pendulum", s, name, runs[s], [estimate[other][0]] * count,
                          [estimate[other][1]] * count, mask)
        for other in solvers:
            if other != s:
                rows += _rows("pendulum", s, f"{other} same grid", runs[s],
                              [r.value for r in runs[other]], [r.policy for r in runs[other]],
                              mask)
    return ConvergenceTable(tuple(rows), int(mask.sum()), band)


def plot_convergence(tables, path=None):
    """Log-log error against h: one panel per table, value max (solid) and policy max (dashed)
    for each (solver, reference) series, with a slope-1 guide. Returns the figure; saved to
    ``path`` when given."""
    import matplotlib.pyplot as plt

    tables = list(tables)
    fig, axes = plt.subplots(1, len(tables), figsize=(6.5 * len(tables), 5), squeeze=False)
    for ax, table in zip(axes[0], tables):
        hs = []
        for k, (case, solver, reference) in enumerate(table.series()):
            if reference.endswith("same grid"):
                continue
            rows = table.select(case, solver, reference)
            h = [r.h for r in rows]
            hs += h
            color = f"C{k % 10}"
            ax.loglog(h, [r.value_max for r in rows], "o-", color=color,
                      label=f"{solver} vs {reference}: max|Δv|")
            ax.loglog(h, [r.policy_max for r in rows], "s--", color=color,
                      label=f"{solver} vs {reference}: max|Δu|")
        guide = np.array([min(hs), max(hs)])
        ax.loglog(guide, guide / guide.max(), "k:", label="slope 1")
        ax.set_xlabel("grid spacing h")
        ax.set_ylabel("error at t = 0")
        ax.set_title(f"{table.rows[0].case}: {table.points} points, v < min v + {table.band:g}")
        ax.legend(fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig
