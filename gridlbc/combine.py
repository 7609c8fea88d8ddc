"""Linear Bellman combination of solved controllers (paper §3–4).

Desirabilities z_i of one linear PDE (same dynamics a, B, state cost q, control cost R,
temperature λ and horizon T) for terminal rewards h_i = exp(−g_i/λ) superpose: for fixed weights
w_i,

    z = Σ w_i z_i   solves the same PDE with   h = Σ w_i h_i,  i.e.  g = −λ log Σ w_i exp(−g_i/λ),

and its optimal policy is the state- and time-dependent blend of the component policies

    u(x, t) = Σ α_i(x, t) u_i(x, t),      α_i = w_i z_i / Σ_j w_j z_j          (paper eq. 1, 11).

With w_i = 1 the combination *coordinates* (several acceptable outcomes); with w from
:func:`gridlbc.project` it *interpolates* goals. Since the grid solver is linear in the terminal
data, :func:`combine` equals the direct solve of the composite cost to rounding.

Each component stores z_i = Z_i e^{ℓ_i} with its own log-scale per slice. The combination works
with the common scale L = max_i L_i(t),

    z e^{−L} = Σ w_i z̃_i e^{L_i − L},

so components whose scales differ by e^{±700} (1e±300) combine without overflow: the smaller ones
contribute what they contribute in float64, and no more.

Components of any other kind (trajectory expansions from :func:`gridlbc.trajectory.expand`,
alone or mixed with grid solutions of the same problem), and grid solutions of different
operators (each fitted to its own terminal cost, or solved with other time steps or schemes),
combine through their values, in the log domain (paper §5, eq. 12):

    α_i = w_i exp(−(v_i − v_min)/λ) / Σ_j w_j exp(−(v_j − v_min)/λ),   u = Σ α_i u_i,

with v_min = min_j v_j per state, so nothing underflows. Such a combination is only as accurate
as its components; a combination of grid solutions of one linear operator is exactly the direct
solve. The ``exact`` attribute of the result says which holds.

:func:`naive_blend` is the baseline the paper beats: u = Σ w_i u_i / Σ w_i with the weights fixed
(or the plain sum Σ w_i u_i, the paper's Fig. 7 baseline).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .accuracy.assessment import check_combination
from .errors import GridlbcWarning, UnderflowWarning, warn_user
from .problem import Problem, state_evaluation
from .representation import Fields, not_positive
from .solution import FieldEvaluation, OperatorSignature, Solution


def check_weights(weights, n: int) -> np.ndarray:
    """Validate fixed blend weights: ``None`` → all ones (coordination), else ``n`` finite numbers
    with a positive sum (single weights may be negative, as projection can give)."""
    if weights is None:
        return np.ones(n)
    try:  # a sequence, an array, or a generator of numbers
        w = np.asarray(weights if hasattr(weights, "__len__") else list(weights), dtype=float)
    except (TypeError, ValueError):
        raise TypeError(
            f"weights must be {n} numbers, one per component, got {weights!r}"
        ) from None
    if w.ndim != 1 or w.size != n:
        raise ValueError(
            f"weights must be {n} numbers, one per component, got shape {np.shape(weights)}"
        )
    if not np.all(np.isfinite(w)):
        raise ValueError(f"weights must be finite, got {w.tolist()}")
    if not np.any(w != 0):
        raise ValueError("weights are all zero: the combined desirability would vanish everywhere")
    if not w.sum() > 0:
        raise ValueError(
            f"weights sum to {w.sum():g} ≤ 0: the combined desirability Σ w_i z_i must be "
            "positive, and with Σw ≤ 0 it is negative wherever the components' z are alike; "
            "weights from gridlbc.project that sum to ≤ 0 say that the components do not "
            "represent the target (its ProjectionWarning): choose components closer to it, or "
            "use weights=None (coordination, all ones)"
        )
    return w


def _same_cost(a, b, x: np.ndarray, t=None) -> bool:
    """Whether two state costs agree at states ``x`` (and times ``t`` for a time-dependent one):
    the grid nodes for grid solutions (the discrete problem only sees node values), a
    trajectory's states and times for trajectory components."""
    if a is b:
        return True
    if a is None or b is None:
        return False
    values = [c(x, t) if getattr(c, "time_dependent", False) else c(x) for c in (a, b)]
    return bool(np.array_equal(np.asarray(values[0], float), np.asarray(values[1], float)))


def _problem_differences(p0: Problem, p: Problem) -> list[str]:
    """What differs between two problems besides the terminal cost, state cost and grid."""
    differs = []
    if p.system != p0.system:
        differs.append(f"system ({p0.system!r} vs {p.system!r})")
    if p.horizon != p0.horizon:
        differs.append(f"horizon ({p0.horizon!r} vs {p.horizon!r})")
    if (p.exit is None) != (p0.exit is None):
        differs.append("exit set (one has none)")
    if p.temperature != p0.temperature:
        differs.append(f"temperature λ ({p0.temperature:g} vs {p.temperature:g})")
    if not np.array_equal(p.R, p0.R):
        differs.append(f"control cost R ({p0.R.tolist()} vs {p.R.tolist()})")
    return differs


def check_components(solutions) -> tuple[tuple[Solution, ...], list[str]]:
    """Grid Solutions of one PDE: raise if anything but the terminal cost differs in the problem
    or the grid. Returns the solutions and what differs in their *operators* (time grid, and
    their :class:`~gridlbc.solution.OperatorSignature`): empty when they combine exactly."""
    solutions = tuple(solutions)
    if not solutions:
        raise ValueError("solutions is empty: give at least one gridlbc.Solution to combine")
    for i, s in enumerate(solutions):
        if not isinstance(s, Solution):
            raise TypeError(f"solutions[{i}] must be a gridlbc.Solution, got {type(s).__name__}")
    ref = solutions[0]
    p0 = ref.problem
    operators = []
    nodes = None
    for i, s in enumerate(solutions[1:], start=1):
        p = s.problem
        differs = _problem_differences(p0, p)
        if p.grid != p0.grid:
            boxes = [
                f"{g.describe()} on " + " × ".join(f"[{a.lo:.6g}, {a.hi:.6g}]" for a in g.axes)
                for g in (p0.grid, p.grid)
            ]
            differs.append(f"grid ({boxes[0]} vs {boxes[1]})")
        if p.grid == p0.grid and p.state_cost is not p0.state_cost:
            nodes = p0.grid.nodes() if nodes is None else nodes  # built once, only if needed
            if not _same_cost(p.state_cost, p0.state_cost, nodes):
                differs.append("state cost q (values differ at the grid nodes)")
        both_exit = p.exit is not None and p0.exit is not None
        if p.grid == p0.grid and both_exit and not np.array_equal(p.exit_mask(), p0.exit_mask()):
            differs.append("exit set E (different nodes)")
        if differs:
            raise ValueError(
                f"solutions[0] and solutions[{i}] must solve the same PDE to combine, but differ "
                f"in: {'; '.join(differs)}. Only the terminal and exit costs may differ "
                "(gridlbc.solve_many solves several terminal costs consistently)."
            )
        if not np.array_equal(s.times, ref.times):
            operators.append(
                f"solutions[{i}] has another time grid ({len(s.times)} vs "
                f"{len(ref.times)} stored slices, or different times)"
            )
        operators += _operator_differences(f"solutions[{i}]", s.operator, ref.operator)
    return solutions, operators


def _operator_differences(name: str, a: OperatorSignature, b: OperatorSignature) -> list[str]:
    """Why the operator of solution ``name`` (signature ``a``) is not that of solutions[0]
    (``b``), in words: empty when they are one linear operator."""
    reasons = [
        (a.method != b.method, f"{name} was solved by {a.method}, solutions[0] by {b.method}"),
        (
            a.method == b.method and a.dt != b.dt,
            f"{name} was solved with another time step (Δt {a.dt:g} vs {b.dt:g})",
        ),
        (
            a.reference != b.reference,
            f"{name} was fitted to another reference ({a.reference} vs {b.reference})",
        ),
        (
            a.reference == b.reference and a.log_domain != b.log_domain,
            f"{name} and solutions[0] were fitted to the same reference, but only one was "
            "stepped in the log domain (a solve fitted to its own terminal cost), whose "
            "slices between t = 0 and T are not linear in z",
        ),
    ]
    return [text for differs, text in reasons if differs]


EXACT_HINT = (
    "for an exact combination solve the components together with "
    "gridlbc.solve_many(problem, costs), or all with fitting=None, or all with one "
    "shared reference cost fitting=g_ref, with the same dt and store_every"
)
"""How to make a combination of grid solutions exact, for :attr:`Combination.reason`."""


@dataclass(frozen=True, eq=False)
class CompositeCost:
    """The terminal cost of a combination, g(x) = −λ log Σ w_i exp(−g_i(x)/λ).

    Evaluated stably (log-sum-exp); +inf where Σ w_i exp(−g_i/λ) ≤ 0, which only negative weights
    can cause.
    """

    costs: tuple
    weights: np.ndarray
    temperature: float

    def __call__(self, x) -> np.ndarray:
        lam = self.temperature
        e = np.stack([-np.asarray(c(x), dtype=float) / lam for c in self.costs])  # (n, N)
        top = e.max(axis=0)
        s = np.einsum("i,in->n", self.weights, np.exp(e - top))
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(s > 0, -lam * (np.log(np.where(s > 0, s, 1.0)) + top), np.inf)


def _normalised(terms: np.ndarray) -> np.ndarray:
    """α = terms / Σ terms, ``(n, N)`` → ``(N, n)``; NaN (with a warning,
    :func:`~gridlbc.representation.not_positive`) where the sum is not positive."""
    total = terms.sum(axis=0)
    bad = not_positive(total)
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha = (terms / np.where(bad, 1.0, total)).T
    alpha[bad] = np.nan
    return alpha


def combined_error(components, alpha: np.ndarray, x, t) -> np.ndarray:
    """The components' error estimates carried to their combination, ``(N,)``.

    With v = −λ log Σ_i w_i z_i, an error δv_i in component i changes v by Σ_i α_i δv_i to first
    order (α the blend weights), so ``abs(δv) ≤ Σ_i abs(α_i) ê_i`` with ê_i from each component's
    :meth:`gridlbc.Solution.error_estimate`."""
    missing = [
        i for i, c in enumerate(components) if not callable(getattr(c, "error_estimate", None))
    ]
    if missing:
        raise ValueError(
            f"components {missing} carry no error estimate (only grid Solutions do): estimate "
            "their error separately, e.g. with gridlbc.certify"
        )
    estimates = np.stack([np.atleast_1d(c.error_estimate(x, t)) for c in components], axis=1)
    with np.errstate(invalid="ignore"):  # 0 · inf where a component without weight underflowed
        carried = np.where(alpha == 0.0, 0.0, np.abs(alpha) * estimates)
    return np.sum(carried, axis=1)


@dataclass(frozen=True, eq=False)
class CombinedSolution(FieldEvaluation):
    """z = Σ w_i z_i of solutions sharing one PDE; evaluates like a :class:`gridlbc.Solution`.

    Attributes
    ----------
    components : tuple of Solution
    weights : ndarray (n,)
        The fixed weights w (all ones for coordination).
    problem : Problem
        The components' problem with the composite terminal cost
        g = −λ log Σ w_i exp(−g_i/λ) (a :class:`~gridlbc.combine.CompositeCost`), e.g.
        for :func:`gridlbc.simulate`.
    exact : bool
        Always True: the components share one linear operator (same scheme, and no fitting or
        one shared fitting reference), so this is the direct solve of the composite cost to
        rounding.
    """

    components: tuple[Solution, ...]
    weights: np.ndarray
    problem: Problem
    exact: ClassVar[bool] = True

    @property
    def times(self) -> np.ndarray:
        return self.components[0].times

    @property
    def grid(self):
        return self.problem.grid

    def _component_fields(self, x, t, gradient: bool):
        """Per component (w_i e^{L_i − L} z̃_i, w_i e^{L_i − L} g̃_i) on the common scale L."""
        fields = [s.scaled_fields(x, t, gradient) for s in self.components]
        L = max(f[0] for f in fields)
        factors = [w * math.exp(f[0] - L) for w, f in zip(self.weights, fields)]  # may underflow
        z = np.stack([c * f[1] for c, f in zip(factors, fields)])  # (n, N)
        g = np.stack([c * f[2] for c, f in zip(factors, fields)]) if gradient else None
        return L, z, g

    def fields(self, x, t, gradient: bool = True) -> Fields:
        """The combined fields at states ``x``, time ``t``: z(x, t) = z e^L and Bᵀ∇z(x, t) =
        g e^L (L the largest component scale; g only with ``gradient``), as
        :meth:`gridlbc.Solution.fields` gives them."""
        L, z, g = self._component_fields(x, t, gradient)
        return Fields(None, L, z.sum(axis=0), None, g.sum(axis=0) if gradient else None)

    @state_evaluation
    def blend_weights(self, x, t=0.0) -> np.ndarray:
        """α_i(x, t) = w_i z_i / Σ_j w_j z_j, shape ``(N, n)`` (``(n,)`` for one state):
        non-negative and summing to one when the weights are; NaN (with an UnderflowWarning) where Σ
        w_j z_j underflowed."""
        _, z, _ = self._component_fields(x, t, gradient=False)
        return _normalised(z)

    def blend_and_value(self, x, t=0.0) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`blend_weights` and :meth:`~gridlbc.solution.FieldEvaluation.value` at states ``x``
        (N, d) from one evaluation of the components' fields."""
        L, z, _ = self._component_fields(x, t, gradient=False)
        value = -self.temperature * Fields(None, L, z.sum(axis=0)).log_desirability()
        return _normalised(z), value

    @state_evaluation
    def error_estimate(self, x, t=0.0) -> np.ndarray:
        """``Σ_i abs(α_i) ê_i``: the components' error estimates carried to the combination
        (:func:`~gridlbc.combine.combined_error`), ``(N,)`` (a scalar for one state)."""
        return combined_error(self.components, self.blend_weights(x, t), x, t)


@dataclass(frozen=True, eq=False)
class Combination:
    """Σ w_i z_i of components known through their values: α_i ∝ w_i exp(−(v_i − v_min)/λ).

    Attributes
    ----------
    components : tuple
        Trajectory expansions and/or grid Solutions of one problem.
    weights : ndarray (n,)
    problem : Problem
        The components' problem with the composite terminal cost
        (a :class:`~gridlbc.combine.CompositeCost`).
    exact : bool
        Always False: the combination is only as accurate as its components (their values are
        approximations of different origins, not one linear operator's solutions), so it
        agrees with the direct solve of the composite cost to within the components'
        discretisation errors, not to rounding.
    reason : str
        Why it is not exact (which components differ, and how to make it exact).
    """

    components: tuple
    weights: np.ndarray
    problem: Problem
    reason: str = "its components are not solutions of one linear operator"
    exact: ClassVar[bool] = False

    @property
    def temperature(self) -> float:
        return self.problem.temperature

    def _log_terms(self, x, t) -> np.ndarray:
        """log |w_i| + log z_i(x, t), shape ``(n, N)`` (−inf where a component underflowed)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnderflowWarning)  # only the total's underflow counts
            logs = [_log_desirability(c, x, t) for c in self.components]
        with np.errstate(divide="ignore"):
            return np.log(np.abs(self.weights))[:, None] + np.stack(logs)

    def _scaled(self, x, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(top, terms, total): terms_i = sign(w_i) exp(e_i − top), total = Σ terms_i."""
        e = self._log_terms(x, t)
        top = e.max(axis=0)
        finite = np.isfinite(top)
        terms = np.sign(self.weights)[:, None] * np.exp(e - np.where(finite, top, 0.0))
        terms[:, ~finite] = 0.0
        return top, terms, terms.sum(axis=0)

    @state_evaluation
    def log_desirability(self, x, t=0.0) -> np.ndarray:
        """log Σ w_i z_i(x, t), shape ``(N,)`` (a scalar for one state ``(d,)``) (−inf, with an
        UnderflowWarning, where it is not positive)."""
        top, _, total = self._scaled(x, t)
        return _log_total(top, total)

    @state_evaluation
    def desirability(self, x, t=0.0) -> np.ndarray:
        """z = Σ w_i z_i, shape ``(N,)`` (a scalar for one state ``(d,)``) (may underflow: use
        :meth:`~gridlbc.solution.FieldEvaluation.value`)."""
        with np.errstate(under="ignore", over="ignore"):
            return np.exp(self.log_desirability(x, t))

    @state_evaluation
    def value(self, x, t=0.0) -> np.ndarray:
        """v = −λ log Σ w_i z_i, shape ``(N,)`` (a scalar for one state ``(d,)``)."""
        return -self.temperature * self.log_desirability(x, t)

    @state_evaluation
    def blend_weights(self, x, t=0.0) -> np.ndarray:
        """α_i(x, t), shape ``(N, n)`` (``(n,)`` for one state) (NaN, with an UnderflowWarning,
        where Σ w_j z_j ≤ 0)."""
        return _normalised(self._scaled(x, t)[1])

    def blend_and_value(self, x, t=0.0) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`blend_weights` and :meth:`~gridlbc.solution.FieldEvaluation.value` at states ``x``
        (N, d) from one evaluation of the components."""
        top, terms, total = self._scaled(x, t)
        return _normalised(terms), -self.temperature * _log_total(top, total)

    @state_evaluation
    def error_estimate(self, x, t=0.0) -> np.ndarray:
        """``Σ_i abs(α_i) ê_i`` (:func:`~gridlbc.combine.combined_error`), ``(N,)`` (a scalar for
        one state); every component must be a grid Solution."""
        return combined_error(self.components, self.blend_weights(x, t), x, t)

    @state_evaluation
    def policy(self, x, t=0.0) -> np.ndarray:
        """u = Σ α_i u_i, shape ``(N, m)`` (``(m,)`` for one state); components with α_i = 0 are not
        evaluated there."""
        alpha = self.blend_weights(x, t)
        shape = (alpha.shape[0], self.problem.system.control_dim)
        u = np.zeros(shape)
        for i, c in enumerate(self.components):
            active = alpha[:, i] != 0
            if not np.any(active):
                continue
            ui = np.zeros(shape)
            ui[active] = np.asarray(c.policy(np.atleast_2d(x)[active], t), dtype=float)
            u = u + alpha[:, i, None] * ui
        return u


def _log_total(top: np.ndarray, total: np.ndarray) -> np.ndarray:
    """log Σ w_i z_i = log(total) + top (:meth:`Combination._scaled`); −inf, with a warning
    (:func:`~gridlbc.representation.not_positive`), where the total is not positive."""
    bad = not_positive(total)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(bad, -np.inf, np.log(np.where(bad, 1.0, total)) + top)


def _log_desirability(component, x, t) -> np.ndarray:
    if callable(getattr(component, "log_desirability", None)):
        return np.asarray(component.log_desirability(x, t), dtype=float)
    return -np.asarray(component.value(x, t), dtype=float) / component.problem.temperature


def _check_general_components(components) -> tuple:
    """Components with ``.value``, ``.policy`` and ``.problem``, all of one problem."""
    for i, c in enumerate(components):
        for attr in ("value", "policy"):
            if not callable(getattr(c, attr, None)):
                raise TypeError(
                    f"components[{i}] ({type(c).__name__}) has no .{attr}(x, t): combine needs "
                    "each component's value function and policy (a gridlbc.Solution, or "
                    "gridlbc.trajectory.expand(problem, trajectory))"
                )
        if not isinstance(getattr(c, "problem", None), Problem):
            raise TypeError(
                f"components[{i}] ({type(c).__name__}) has no .problem: combine "
                "checks that all components solve the same problem"
            )
    p0 = components[0].problem
    sample = next((c.trajectory for c in components if hasattr(c, "trajectory")), None)
    for i, c in enumerate(components[1:], start=1):
        p = c.problem
        differs = _problem_differences(p0, p)
        if sample is not None and not _same_cost(
            p.state_cost, p0.state_cost, sample.states, sample.times
        ):
            differs.append("state cost q (values differ along a component's trajectory)")
        if differs:
            raise ValueError(
                f"components[{i}] and components[0] must be controllers of the same problem to "
                f"combine, but differ in: {'; '.join(differs)}. Only the terminal cost may differ."
            )
    return components


def combine(components, weights=None) -> CombinedSolution | Combination:
    """Linear Bellman combination z = Σ w_i z_i of controllers of one problem (paper §3–5).

    Parameters
    ----------
    components : sequence of Solution and/or trajectory components
        Grid Solutions solved for different terminal costs g_i of one problem on one grid
        (system, horizon, state cost q, control cost R, temperature λ), however each was
        solved; or any components with ``.value(x, t)``, ``.policy(x, t)`` and ``.problem`` of
        one problem, such as :func:`gridlbc.trajectory.expand`, mixed with grid Solutions or
        not. Otherwise an error names what differs.
    weights : array_like (n,), optional
        Fixed weights w_i. ``None`` (coordination): all ones. Otherwise finite with a positive
        sum; from :func:`gridlbc.project` to interpolate a target cost.

    Returns
    -------
    CombinedSolution or Combination
        Grid Solutions of one linear operator (same scheme and time grid, and ``fitting=None``
        or one shared fitting reference, as :func:`gridlbc.solve_many` gives): a
        :class:`CombinedSolution`, exactly the solution of the composite terminal cost
        g = −λ log Σ w_i exp(−g_i/λ) to rounding (``exact`` True). Where the task has an exit
        set its exit cost combines the same way, −λ log Σ w_i exp(−g_E,i/λ): one g_E shared by
        the components becomes g_E − λ log Σw, kept only by weights that sum to 1 (combine
        warns otherwise); ``combined.problem`` is the task solved. Otherwise — grid Solutions
        solved separately with their own fitting references (the default), other time grids or
        schemes, or trajectory components — a :class:`Combination`, as accurate as its
        components (``exact`` False, and ``reason`` says why). Both have ``value``,
        ``log_desirability``, ``desirability``, ``policy`` (u = Σ α_i u_i) and
        ``blend_weights`` α_i = w_i z_i / Σ_j w_j z_j. Where the grid components carry error
        estimates, combine warns (:class:`gridlbc.ResolutionWarning`) when the estimate they
        carry to the combination exceeds the default tolerance relative to its value
        (:func:`gridlbc.accuracy.assessment.check_combination`).
    """
    components = tuple(components)
    if not components:
        raise ValueError(
            "components is empty: give at least one gridlbc.Solution or trajectory "
            "component to combine"
        )
    if all(isinstance(c, Solution) for c in components):
        solutions, operators = check_components(components)
        w = check_weights(weights, len(solutions))
        problem = composite_problem(solutions, w)
        combined: CombinedSolution | Combination = (
            Combination(solutions, w, problem, f"{'; '.join(operators)}: {EXACT_HINT}")
            if operators
            else CombinedSolution(solutions, w, problem)
        )
        check_combination(combined)
        return combined
    components = _check_general_components(components)
    w = check_weights(weights, len(components))
    kinds = sorted({type(c).__name__ for c in components})
    return Combination(
        components,
        w,
        composite_problem(components, w),
        f"components of kinds {', '.join(kinds)} combine through their values",
    )


def composite_problem(components, w: np.ndarray) -> Problem:
    """The problem a combination solves: the components' with each cost paid at the end (the
    terminal cost, and the exit cost where there is an exit set) replaced by its
    :class:`~gridlbc.combine.CompositeCost`; warned of where that moves an exit cost the
    components share (:func:`check_exit_cost`)."""
    base = components[0].problem
    ends = {}
    for name in ("terminal_cost", "exit_cost"):
        if getattr(base, name) is not None:
            costs = tuple(getattr(c.problem, name) for c in components)
            ends[name] = CompositeCost(costs, w, base.temperature)
    check_exit_cost(components, w)
    return base.replace(**ends)


def check_exit_cost(components, w: np.ndarray) -> None:
    """Warn (:class:`gridlbc.GridlbcWarning`) where the components of a task with a horizon and
    an exit set share one exit cost g_E and Σw ≠ 1 (without a horizon the exit costs are what
    is combined).

    On the exit set every component's desirability is exp(−g_E/λ), so the combination's is
    Σw · exp(−g_E/λ): it solves the task whose exit cost is −λ log Σ_i w_i exp(−g_E/λ) =
    g_E − λ log Σw, not g_E. That is the superposition's own rule (the exit cost combines as the
    terminal cost does, paper §3), and :attr:`CombinedSolution.problem` says so, but a user
    combining terminal costs of a task with an exit set expects g_E kept: coordinating two goals
    of a task that may also end on E read 30–88 % off a certified optimum with g_E (stranger
    round 43). Weights that sum to 1 keep g_E."""
    problem = components[0].problem
    total = float(np.sum(w))
    if problem.exit is None or problem.stationary or abs(math.log(total)) <= 1e-12:
        return
    g_E = problem.exit_cost
    others = [c.problem.exit_cost for c in components[1:] if c.problem.exit_cost is not g_E]
    if others:  # compared at the nodes, g_E evaluated there once
        if problem.grid is None:
            return
        nodes = problem.grid.nodes()
        own = np.asarray(g_E(nodes), dtype=float)
        if any(not np.array_equal(np.asarray(c(nodes), dtype=float), own) for c in others):
            return  # exit costs that differ: combining them is the point
    warn_user(
        f"the components share one exit cost g_E and the weights sum to {total:.4g}, not 1: on "
        "the exit set the combination's desirability is Σw·exp(−g_E/λ), so it solves the task "
        f"whose exit cost is g_E − λ log Σw = g_E {'−' if total > 1 else '+'} "
        f"{problem.temperature * abs(math.log(total)):.4g} "
        "(combined.problem), not g_E (the exit cost combines as the terminal cost does). To keep "
        "g_E, give weights that sum to 1, w / Σw, which raises the composite terminal cost by "
        "λ log Σw (docs page 'first_exit')",
        GridlbcWarning,
    )


BLEND_MODES = ("average", "sum")
"""How :func:`naive_blend` adds the weighted policies."""


@dataclass(frozen=True, eq=False)
class NaiveBlend:
    """The fixed-weight average u = Σ w_i u_i / Σ w_i of component policies (the paper's
    baseline), or the sum Σ w_i u_i (``mode="sum"``): same weights at every state and time,
    blind to which component is relevant.

    Attributes
    ----------
    components : tuple
        The controllers blended: any objects with ``.policy(x, t)``.
    weights : ndarray (n,)
        w_i, non-negative.
    mode : {"average", "sum"}
        Divide by Σ w_i (``"average"``) or not (``"sum"``).
    """

    components: tuple
    weights: np.ndarray
    mode: str = "average"

    def policy(self, x, t=0.0) -> np.ndarray:
        """u(x, t) = Σ w_i u_i(x, t) / Σ w_i (or Σ w_i u_i(x, t)), shape ``(N, m)``."""
        u = [np.asarray(c.policy(x, t), dtype=float) for c in self.components]
        shapes = {a.shape for a in u}
        if len(shapes) != 1:
            raise ValueError(f"component policies return different shapes {sorted(shapes)}")
        total = np.einsum("i,i...->...", self.weights, np.stack(u))
        return total if self.mode == "sum" else total / self.weights.sum()


def naive_blend(solutions, weights, mode: str = "average") -> NaiveBlend:
    """The naive blend u = Σ w_i u_i / Σ w_i with fixed ``weights`` (paper Fig. 6).

    Parameters
    ----------
    solutions : sequence
        Any objects with ``.policy(x, t)``: Solutions, trajectory components or your own
        controllers.
    weights : array_like (n,) or None
        w_i ≥ 0 as for :func:`combine` (``None``: all ones).
    mode : {"average", "sum"}
        ``"sum"`` gives Σ w_i u_i instead, the paper's Fig. 7 baseline (the two tracking
        controllers' outputs simply summed).

    Returns
    -------
    NaiveBlend
    """
    components = tuple(solutions)
    if not components:
        raise ValueError("solutions is empty: give at least one controller to blend")
    for i, c in enumerate(components):
        if not callable(getattr(c, "policy", None)):
            raise TypeError(f"solutions[{i}] has no .policy(x, t) method ({type(c).__name__})")
    if mode not in BLEND_MODES:
        raise ValueError(f"mode must be one of {', '.join(map(repr, BLEND_MODES))}, got {mode!r}")
    return NaiveBlend(components, check_weights(weights, len(components)), mode)
