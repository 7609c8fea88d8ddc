"""Convergence study: the z-space solvers and the value-space HJB solver under grid refinement.

Two cases, errors measured at t = 0 on a fixed lattice of evaluation points (off the grids, so the
interpolation is part of what is measured), restricted to where the value is within ``band`` of
its minimum (far tails, where no one steers, are excluded):

* **PointMass** (linear, quadratic costs): every solver against the exact Riccati solution
  (:func:`gridlbc.reference.lq_solution`);
* **Pendulum** (nonlinear, no closed form): each solver against its own Richardson estimate from its two
  finest grids, v_R = v_h + (v_h − v_{2h}) / (2^p − 1) with p observed from three grids, against
  the other solver's Richardson estimate, and the two solvers against each other on the same grid.

Observed orders are p = log(e_coarse / e_fine) / log(h_coarse / h_fine) between successive rows.

Richardson extrapolation *in z* (``"splitting+richardson"``), z_R = 2 z_h − z_{2h}, keeps exact
linearity in the terminal data (it is a fixed linear combination of two linear solves) but not
monotonicity: z_R ≤ 0 wherever the coarse z exceeds twice the fine one, i.e. wherever the value
error is above λ log 2. Those points have no value; they are counted in ``ConvergenceRow.negative``
and left out of that row's errors.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..certificate import Certificate
from ..certify import certify
from ..errors import UnderflowWarning
from ..problem import Problem
from ..reference import lq_solution
from ..reference.hjb import HJBSolution, solve_hjb
from ..solution import Solution
from ..solver import solve
from .problems import pendulum_problem, pointmass_problem

SOLVERS: dict[str, Callable[[Problem], Solution | HJBSolution]] = {
    "splitting": lambda problem: solve(problem, method="splitting", fitting=None),
    "implicit": lambda problem: solve(problem, method="implicit"),
    "hjb": solve_hjb,
}
"""The solvers compared, by name: the two plain z-space schemes (default time steps; their
operators do not depend on g, so the tables show the methods' orders) and the HJB."""


@dataclass(frozen=True)
class ConvergenceRow:
    """Errors of one solver on one grid against one reference, at t = 0 on the evaluation points.

    ``h`` is the largest grid spacing, ``dt`` the mean time step; ``value_max`` / ``value_mean``
    are the max / mean of |v − v_ref|, ``policy_max`` the max of |u − u_ref|; the orders compare
    with the previous row of the same case, solver and reference (NaN on the first);
    ``wall_time`` is the solve time in seconds (both solves for Richardson rows); ``negative`` the
    number of evaluation points of the region where an extrapolated z was ≤ 0 (excluded from the
    errors).
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
    notes: tuple[str, ...] = ()

    def select(self, case: str, solver: str, reference: str) -> tuple[ConvergenceRow, ...]:
        """The rows of one case, solver and reference, coarse to fine."""
        return tuple(
            r for r in self.rows if (r.case, r.solver, r.reference) == (case, solver, reference)
        )

    def series(self) -> list[tuple[str, str, str]]:
        """The distinct (case, solver, reference) triples, in order of appearance."""
        return list(dict.fromkeys((r.case, r.solver, r.reference) for r in self.rows))

    def format(self) -> str:
        """The table as fixed-width text."""
        head = (
            f"{'case':<9} {'solver':<20} {'reference':<21} {'grid':>9} {'h':>7} {'dt':>8} "
            f"{'max|dv|':>8} {'mean|dv|':>8} {'max|du|':>8} {'p(v)':>5} {'p(u)':>5} "
            f"{'time s':>7}"
        )
        lines = [head, "-" * len(head)]
        for r in self.rows:
            grid = "×".join(map(str, r.shape))
            lines.append(
                f"{r.case:<9} {r.solver:<20} {r.reference:<21} {grid:>9} {r.h:7.4f} {r.dt:8.5f} "
                f"{r.value_max:8.4f} {r.value_mean:8.4f} {r.policy_max:8.4f} "
                f"{r.value_order:5.2f} {r.policy_order:5.2f} {r.wall_time:7.2f}"
                + (f"  ({r.negative} points with z ≤ 0 left out)" if r.negative else "")
            )
        return "\n".join(lines + list(self.notes))


# -- the two test problems -----------------------------------------------------------------------


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
    valid: np.ndarray | None = None  # where the value exists (None: everywhere)


def _run(solver: str, problem: Problem, points: np.ndarray):
    solution = SOLVERS[solver](problem)
    run = _Run(
        solution.grid.shape,
        float(solution.grid.spacing.max()),
        solution.diagnostics.dt,
        solution.value(points, 0.0),
        solution.policy(points, 0.0),
        solution.diagnostics.wall_time,
    )
    return run, solution


def richardson_z(fine, coarse, x, t: float = 0.0):
    """Value, policy and the mask z_R > 0 of z_R = 2 z_fine − z_coarse at states ``x``.

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
    return value, policy, ~bad


def _rows(case, solver, reference, runs, ref_values, ref_policies, mask):
    """Table rows of successive runs against per-run reference fields, with observed orders."""
    rows, previous = [], None
    for run, v_ref, u_ref in zip(runs, ref_values, ref_policies):
        keep = mask if run.valid is None else mask & run.valid
        dv = np.abs(run.value - v_ref)[keep]
        du = np.abs(run.policy - u_ref)[keep]
        errors = (
            (float(dv.max()), float(dv.mean()), float(du.max())) if dv.size else (math.nan,) * 3
        )
        orders = (math.nan, math.nan)
        if previous is not None:
            ratio = math.log(previous[0].h / run.h)
            orders = tuple(
                math.log(a / b) / ratio if a > 0 and b > 0 else math.nan
                for a, b in ((previous[1][0], errors[0]), (previous[1][2], errors[2]))
            )
        rows.append(
            ConvergenceRow(
                case,
                solver,
                reference,
                run.shape,
                run.h,
                run.dt,
                *errors,
                *orders,
                run.wall_time,
                int(mask.sum() - keep.sum()),
            )
        )
        previous = (run, errors)
    return rows


def pointmass_study(
    spacings=(1 / 4, 1 / 8, 1 / 16, 1 / 32),
    solvers=("splitting", "implicit", "hjb"),
    band: float = 5.0,
    richardson=("splitting", "implicit"),
) -> ConvergenceTable:
    """Every solver against the Riccati solution on PointMass, over grid spacings ``spacings``.

    For the z-space solvers named in ``richardson`` also their z extrapolated across successive
    grids (rows ``"<solver>+richardson"``, see :func:`richardson_z`).
    The evaluation region: the lattice of :func:`pointmass_points` where v < min v + ``band``.
    """
    points = pointmass_points()
    exact = lq_solution(pointmass_problem(spacings[0]))
    v_exact, u_exact = exact.value(points, 0.0), exact.policy(points, 0.0)
    mask = v_exact < v_exact.min() + band
    rows = []
    for solver in solvers:
        runs, solutions = zip(*(_run(solver, pointmass_problem(h), points) for h in spacings))
        rows += _rows(
            "pointmass", solver, "riccati", runs, [v_exact] * len(runs), [u_exact] * len(runs), mask
        )
        if solver in richardson and len(runs) > 1:
            extrapolated = []
            for k in range(1, len(runs)):
                value, policy, valid = richardson_z(solutions[k], solutions[k - 1], points)
                extrapolated.append(
                    _Run(
                        runs[k].shape,
                        runs[k].h,
                        runs[k].dt,
                        value,
                        policy,
                        runs[k].wall_time + runs[k - 1].wall_time,
                        valid,
                    )
                )
            rows += _rows(
                "pointmass",
                f"{solver}+richardson",
                "riccati",
                extrapolated,
                [v_exact] * len(extrapolated),
                [u_exact] * len(extrapolated),
                mask,
            )
    return ConvergenceTable(tuple(rows), int(mask.sum()), band)


def richardson_estimate(fields, mask, order=None) -> tuple[np.ndarray, float]:
    """Richardson estimate f_R = f_n + (f_n − f_{n−1}) / (2^p − 1) from fields on grids with h
    halved each time (the last entries of ``fields``), and the order p used.

    Without ``order``, p is observed from the last three fields over ``mask``:
    p = log₂(max|f_{n−1} − f_{n−2}| / max|f_n − f_{n−1}|), clipped to [0.25, 2]; with only two
    fields p = 1 (the schemes' formal order).
    """
    if order is None:
        order = 1.0
        if len(fields) >= 3:
            coarse = np.abs(fields[-2] - fields[-3])[mask].max()
            fine = np.abs(fields[-1] - fields[-2])[mask].max()
            if fine > 0 and coarse > 0:
                order = float(np.clip(math.log2(coarse / fine), 0.25, 2.0))
    return fields[-1] + (fields[-1] - fields[-2]) / (2.0**order - 1.0), order


def pendulum_study(
    sizes=(64, 128, 256), solvers=("splitting", "hjb"), band: float = 5.0, **problem_options
) -> ConvergenceTable:
    """The z-space and HJB solvers on the pendulum (:func:`pendulum_problem`), ``sizes`` nodes per
    angle (doubling), against Richardson estimates (:func:`richardson_estimate`, order observed
    from the last three grids) and each other.

    References, per solver: ``"own richardson"``; ``"<other> richardson"`` for each other solver;
    and ``"<other> same grid"`` for each later solver in ``solvers`` on the same grid. The
    evaluation region: the lattice of :func:`pendulum_points` where the first solver's finest
    v < min + ``band``. The Richardson orders used are listed in the table's ``notes``.
    """
    if len(sizes) < 2:
        raise ValueError("pendulum_study needs at least two grid sizes for a Richardson estimate")
    points = pendulum_points()
    runs = {
        s: [_run(s, pendulum_problem(n, **problem_options), points)[0] for n in sizes]
        for s in solvers
    }
    finest = runs[solvers[0]][-1].value
    mask = finest < finest.min() + band
    estimate, notes = {}, []
    for s, r in runs.items():
        v_R, p_v = richardson_estimate([run.value for run in r], mask)
        u_R, p_u = richardson_estimate([run.policy for run in r], mask)
        estimate[s] = (v_R, u_R)
        notes.append(
            f"{s} Richardson estimate with observed order p(v) = {p_v:.2f}, p(u) = {p_u:.2f}"
        )
    rows = []
    for s in solvers:
        count = len(runs[s])
        for other in solvers:
            name = "own richardson" if other == s else f"{other} richardson"
            rows += _rows(
                "pendulum",
                s,
                name,
                runs[s],
                [estimate[other][0]] * count,
                [estimate[other][1]] * count,
                mask,
            )
        for other in solvers[solvers.index(s) + 1 :]:  # each pair once
            rows += _rows(
                "pendulum",
                s,
                f"{other} same grid",
                runs[s],
                [r.value for r in runs[other]],
                [r.policy for r in runs[other]],
                mask,
            )
    return ConvergenceTable(tuple(rows), int(mask.sum()), band, tuple(notes))


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
            ax.loglog(
                h,
                [r.value_max for r in rows],
                "o-",
                color=color,
                label=f"{solver} vs {reference}: max|Δv|",
            )
            ax.loglog(
                h,
                [r.policy_max for r in rows],
                "s--",
                color=color,
                label=f"{solver} vs {reference}: max|Δu|",
            )
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


# -- the deterministic limit λ → 0 ---------------------------------------------------------------

UNDERFLOW_SPAN = -math.log(np.finfo(float).smallest_subnormal)
"""≈ 744.4: a node's z = Z e^ℓ (max Z = 1 per slice) is zero in float64 once v − min v > 744.4 λ."""


@dataclass(frozen=True)
class TemperatureStudy:
    """The pendulum's value and policy along ω = 0 at t = 0 as the temperature λ decreases.

    Attributes: ``temperatures`` (K,); ``theta`` (P,) the angles sampled; ``value_z``,
    ``policy_z`` (K, P) from the z-space splitting solver (+inf / NaN where z underflowed) and
    ``value_hjb``, ``policy_hjb`` (K, P) from the HJB solver; ``underflow_nodes`` (K,) from the
    z solver's diagnostics (nodes with z = 0 at t = 0); ``value_span`` and ``value_span_z`` (K,)
    max v − min v over the grid at t = 0 of the HJB and of the z solver (where finite), to compare
    with ``UNDERFLOW_SPAN · λ``; ``grid_size``.
    """

    temperatures: np.ndarray
    theta: np.ndarray
    value_z: np.ndarray
    policy_z: np.ndarray
    value_hjb: np.ndarray
    policy_hjb: np.ndarray
    underflow_nodes: np.ndarray
    value_span: np.ndarray
    value_span_z: np.ndarray
    grid_size: int

    def format(self) -> str:
        """One line per temperature: span of v in units of λ and the underflowed nodes."""
        head = (
            f"{'λ':>6} {'span(v_hjb)/λ':>14} {'span(v_z)/λ':>12} {'underflowed nodes':>18} "
            f"{'max|v_z − v_hjb| at ω = 0':>26}"
        )
        lines = [head]
        for k, lam in enumerate(self.temperatures):
            finite = np.isfinite(self.value_z[k])
            gap = np.abs(self.value_z[k] - self.value_hjb[k])[finite]
            lines.append(
                f"{lam:6.3g} {self.value_span[k] / lam:14.1f} "
                f"{self.value_span_z[k] / lam:12.1f} "
                f"{self.underflow_nodes[k]:>8d} of {self.grid_size:<7d} "
                f"{gap.max() if gap.size else math.nan:26.3f}"
            )
        return "\n".join(lines)


def temperature_study(
    temperatures=(1.0, 0.3, 0.1, 0.03, 0.01), n: int = 128, **problem_options
) -> TemperatureStudy:
    """Solve :func:`pendulum_problem` (``n`` nodes per angle) at each temperature with the
    splitting z solver and the HJB solver, and sample both along ω = 0 at t = 0."""
    theta = np.linspace(-math.pi, math.pi, 361)[:-1]
    x = np.column_stack([theta, np.zeros_like(theta)])
    fields: dict[str, list[np.ndarray]] = {
        key: [] for key in ("value_z", "policy_z", "value_hjb", "policy_hjb")
    }
    underflow, span, span_z = [], [], []
    for lam in temperatures:
        problem = pendulum_problem(n, temperature=lam, **problem_options)
        linear = solve(problem)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnderflowWarning)  # counted, and +inf/NaN in the data
            fields["value_z"].append(linear.value(x, 0.0))
            fields["policy_z"].append(linear.policy(x, 0.0)[:, 0])
        nonlinear = solve_hjb(problem)
        fields["value_hjb"].append(nonlinear.value(x, 0.0))
        fields["policy_hjb"].append(nonlinear.policy(x, 0.0)[:, 0])
        underflow.append(linear.diagnostics.underflow_nodes)
        span.append(float(np.ptp(nonlinear.values[0])))
        value_z = linear.value_nodes(0)
        span_z.append(float(np.ptp(value_z[np.isfinite(value_z)])))
    return TemperatureStudy(
        np.array(temperatures, dtype=float),
        theta,
        **{k: np.array(v) for k, v in fields.items()},
        underflow_nodes=np.array(underflow),
        value_span=np.array(span),
        value_span_z=np.array(span_z),
        grid_size=pendulum_problem(n).require_grid("temperature_study()").size,
    )


def plot_temperature(study: TemperatureStudy, path=None):
    """v(θ, 0, 0) and u(θ, 0, 0) per temperature: z solver solid (gaps where z underflowed), HJB
    dashed. Returns the figure; saved to ``path`` when given."""
    import matplotlib.pyplot as plt

    fig, (ax_v, ax_u) = plt.subplots(1, 2, figsize=(13, 5))
    for k, lam in enumerate(study.temperatures):
        color = f"C{k % 10}"
        value_z = np.where(np.isfinite(study.value_z[k]), study.value_z[k], np.nan)
        label = f"λ = {lam:g}" + (
            f" ({study.underflow_nodes[k]} nodes underflow)" if study.underflow_nodes[k] else ""
        )
        ax_v.plot(study.theta, value_z, "-", color=color, label=label)
        ax_v.plot(study.theta, study.value_hjb[k], "--", color=color)
        ax_u.plot(study.theta, study.policy_z[k], "-", color=color, label=f"λ = {lam:g}")
        ax_u.plot(study.theta, study.policy_hjb[k], "--", color=color)
    for ax, name in ((ax_v, "value v(θ, ω = 0, t = 0)"), (ax_u, "policy u(θ, ω = 0, t = 0)")):
        ax.set_xlabel("θ (rad from upright)")
        ax.set_title(f"{name}: z solver solid, HJB dashed")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig


# -- against the certified optimum ----------------------------------------------------------------

SCHEMES: dict[str, Callable[[Problem, float | None], Solution | HJBSolution]] = {
    "splitting": lambda problem, dt: solve(problem, dt=dt, method="splitting", fitting=None),
    "fitted": lambda problem, dt: solve(problem, dt=dt, method="splitting", fitting="terminal"),
    "implicit": lambda problem, dt: solve(problem, dt=dt, method="implicit"),
    "hjb": lambda problem, dt: solve_hjb(problem, dt=dt),
}
"""Solvers of :func:`certified_study` by name, each called as ``(problem, dt)`` (dt None: the
solver's default): the plain and the fitted splitting scheme, implicit upwind, value-space HJB."""


@dataclass(frozen=True)
class CertifiedRow:
    """One solve judged by the certified optimum: its prediction v(x₀, 0) and the certificate of
    its own policy (the policy's cost J ± SE and the effective sample size of that certificate,
    near ``n_samples`` when the policy is near optimal). ``label`` names the configuration:
    the scheme, and the time step when one was given (e.g. ``"fitted dt 0.02"``)."""

    scheme: str
    label: str
    shape: tuple[int, ...]
    dt: float
    steps: int
    wall_time: float
    predicted: float
    policy_cost: float
    policy_cost_se: float
    effective_sample_size: float
    n_samples: int


def sde_optimum(certificate: Certificate) -> tuple[float, float]:
    """The SDE's v* of a one-state certificate made with ``richardson=True`` and its standard
    error: the chain's optima at Δt and 2Δt extrapolated to a vanishing step."""
    return float(np.asarray(certificate.extrapolated_value)), float(
        np.asarray(certificate.extrapolated_value_se)
    )


@dataclass(frozen=True)
class CertifiedStudy:
    """Predictions and policy costs of several solves against one certified optimum.

    ``truth`` is the :class:`gridlbc.Certificate` of v*(x₀) with the policy of ``proposal``
    (scheme, n, dt) as the importance-sampling proposal, certified with ``richardson=True``: the
    predictions are judged by the SDE's optimum, extrapolated in the Euler–Maruyama step
    (:attr:`optimum`), and the policies' costs J, which are the chain's at that step, by the
    chain's (:attr:`chain_optimum`): the rows' gaps J − v*(Δt) ≥ 0 have the standard error
    √(SE_J² + SE_v*²) (independent samples).
    """

    start: np.ndarray
    truth: Certificate
    proposal: tuple
    rows: tuple[CertifiedRow, ...]

    @property
    def optimum(self) -> tuple[float, float]:
        """The SDE's v*(x₀) and its SE: the truth extrapolated to a vanishing step."""
        return sde_optimum(self.truth)

    @property
    def chain_optimum(self) -> tuple[float, float]:
        """v*(x₀) of the Euler–Maruyama chain at the rollouts' step, and its SE."""
        return float(self.truth.optimal_value), float(self.truth.optimal_value_se)

    def select(self, label: str) -> tuple[CertifiedRow, ...]:
        """The rows of one configuration (:attr:`CertifiedRow.label`), coarse to fine."""
        return tuple(r for r in self.rows if r.label == label)

    def labels(self) -> list[str]:
        return list(dict.fromkeys(r.label for r in self.rows))

    def format(self) -> str:
        v, se = self.optimum
        chain, chain_se = self.chain_optimum
        scheme, n, dt = self.proposal
        lines = [
            f"certified optimum v*({np.array2string(self.start, precision=3)}) = {v:.3f} ± "
            f"{se:.3f} (SE), extrapolated from Δt = {self.truth.dt:g} and twice it (the chain's "
            f"at Δt: {chain:.3f} ± {chain_se:.3f}, which the gaps J − v* are taken from): "
            f"proposal {scheme} n = {n}"
            + (f" dt {dt:g}" if dt is not None else "")
            + f", {self.truth.n_samples} samples, effective sample size "
            f"{self.truth.effective_sample_size:.0f}"
        ]
        head = (
            f"{'scheme':<16}{'grid':>10}{'dt':>8}{'steps':>6}{'time s':>8}{'predicted':>10}"
            f"{'error':>8}{'policy cost':>12}{'± SE':>6}{'gap':>7}{'ESS':>6}"
        )
        lines += [head, "-" * len(head)]
        for r in self.rows:
            gap, gap_se = r.policy_cost - chain, math.hypot(r.policy_cost_se, chain_se)
            lines.append(
                f"{r.label:<16}{'×'.join(map(str, r.shape)):>10}{r.dt:8.4f}{r.steps:6d}"
                f"{r.wall_time:8.2f}{r.predicted:10.2f}{100 * (r.predicted - v) / v:7.1f}%"
                f"{r.policy_cost:12.2f}{r.policy_cost_se:6.2f}{gap:7.2f}"
                f"{100 * r.effective_sample_size / r.n_samples:5.0f}%"
                + ("" if gap > 2 * gap_se else "  (gap within 2 SE of 0)")
            )
        return "\n".join(lines)


def certified_study(
    make_problem,
    sizes,
    start,
    configs=(("splitting", None), ("fitted", None)),
    proposal=None,
    samples: int = 400,
    truth_samples: int = 2000,
    rollout_dt: float | None = None,
    seed: int = 0,
    progress: bool = False,
) -> CertifiedStudy:
    """Solve ``make_problem(n)`` for each n in ``sizes`` and each (scheme, dt) in ``configs``
    (schemes from :data:`SCHEMES`), and judge each by the certified optimum v*(``start``).

    v* is :func:`gridlbc.certify` with ``truth_samples`` samples and the policy of ``proposal`` =
    (scheme, n, dt) as proposal (default: the last config on the largest grid), which should be
    the most accurate solve at hand: its effective sample size says how far to trust v*. It is
    certified with ``richardson=True`` (:class:`CertifiedStudy`: the predictions are judged by the
    SDE's optimum, the policies' costs by the chain's at the same step). Each row
    then certifies its own policy with ``samples`` samples (its cost J and how good a proposal
    it is). ``rollout_dt`` is the Euler–Maruyama step of all rollouts (default T/300).
    """
    start = np.asarray(start, dtype=float)
    proposal = (configs[-1][0], max(sizes), configs[-1][1]) if proposal is None else tuple(proposal)
    say = print if progress else (lambda *a, **k: None)
    solutions: dict[tuple, Solution | HJBSolution] = {}

    def solved(scheme, n, dt):
        key = (scheme, n, dt)
        if key not in solutions:
            solutions.clear()  # keep one solve in memory at a time
            solutions[key] = SCHEMES[scheme](make_problem(n), dt)
        return solutions[key]

    best = solved(*proposal)
    truth = certify(
        best.problem,
        best.policy,
        start,
        truth_samples,
        dt=rollout_dt,
        richardson=True,
        seed=seed + 1,
        progress=progress,
    )
    optimum, optimum_se = sde_optimum(truth)
    say(
        f"certified optimum {optimum:.3f} ± {optimum_se:.3f} (the chain's at Δt: "
        f"{truth.optimal_value:.3f})"
    )
    rows = []
    for n in sizes:
        for scheme, dt in configs:
            sol = solved(scheme, n, dt)
            own = certify(
                sol.problem,
                sol.policy,
                start,
                samples,
                dt=rollout_dt,
                seed=seed,
                progress=progress,
                min_effective_sample_size=0,
                step_check=False,  # J is the chain's at rollout_dt, judged by chain_optimum
            )  # J and ESS used
            d = sol.diagnostics
            label = scheme if dt is None else f"{scheme} dt {dt:g}"
            rows.append(
                CertifiedRow(
                    scheme,
                    label,
                    sol.problem.grid.shape,
                    d.dt,
                    d.steps,
                    d.wall_time,
                    float(sol.value(start, 0.0)),
                    float(own.policy_cost),  # one start state: floats
                    float(own.policy_cost_se),
                    float(own.effective_sample_size),
                    samples,
                )
            )
            say(
                f"  {scheme} n = {n}: predicted {rows[-1].predicted:.3f}, policy cost "
                f"{own.policy_cost:.3f}"
            )
    return CertifiedStudy(start, truth, proposal, tuple(rows))
