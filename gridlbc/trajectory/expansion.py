"""The quadratic value expansion and LQR tracker along an optimised trajectory (paper §5, eq. 12).

Along a trajectory (x̄_k, ū_k) of :func:`gridlbc.trajectory.optimize`, the DDP backward passes of
:mod:`gridlbc.trajectory.ddp` give at every node t_k the gradient p_k and Hessian P_k of the
cost-to-go and the gain K_k. Two passes play different parts:

- *the value* (``curvature="newton"``, the default) comes from the full DDP pass of Jacobson and
  Mayne, with the dynamics' second derivatives Σ_i p_i ∇²F_i: P_k is then the exact Hessian of
  the discrete cost-to-go of the tape's neighbouring optima, so v̂, and with it the blend weight
  α, ranks the components by what they really cost off their tapes. ``curvature="gauss-newton"``
  drops those terms (the iLQR model, P_k ⪰ 0 by construction); on a swing-up it misses much of
  the curvature that gravity adds, so v̂ is optimistic off the trajectory (docs/trajectory.rst,
  accuracy of v̂). Where the exact P_k is not positive semi-definite (the neighbouring optima's cost is
  not convex in some direction), the value uses its projection P_k⁺ onto the positive
  semi-definite cone (negative eigenvalues set to zero), so that no component's desirability
  grows without bound away from its trajectory.
- *the tracker's gain* K_k = −Q_uu⁻¹Q_ux (``feedback="projected-newton"``, the default) comes
  from the full DDP pass run with P_k+1 replaced by its positive semi-definite part P_k+1⁺ at
  every step: each step's model keeps the curvature that the dynamics add where it is positive
  (gravity's, on a swing-up), and no step's model rewards a deviation. ``feedback="newton"``
  takes the exact full DDP gain, the first-order change of the neighbouring optima's controls:
  where their cost is concave (P_k indefinite) its model rewards deviations along those
  directions, which holds for small deviations but not for the large ones that noise causes
  (docs/trajectory.rst, the gymnast's Fig. 7). ``feedback="gauss-newton"`` is the iLQR gain, the LQR gain of the tape's
  linearisation without the dynamics' curvature. For linear dynamics the three coincide.

The component is

    v̂(x, t) = v̄(t) + p(t)ᵀΔx + ½ Δxᵀ P(t) Δx,      Δx = x ⊖ x̄(t)   (nearest image on periodic axes)
    u(x, t) = ū(t) + K(t) Δx · min(1, ρ_max / ρ(x, t))                (the LQR tracker)
    z(x, t) = exp(−v̂(x, t)/λ)

with P = P⁺ and v̄_k = g(x̄_K) + Σ_{j≥k} (q(x̄_j, t_j) + ½ ū_jᵀRū_j) Δt the cost along the
trajectory, plus, with noise (``stochastic=True``, the default), the Itô correction of the
Riccati equation

    c_k = (λ/2) ∫_{t_k}^T tr(S P) ds,   S = B(x̄) R⁻¹ B(x̄)ᵀ   (trapezoidal rule on the nodes),

with the exact P (the expected cost of the noise to second order; clipping P's negative
eigenvalues would overstate it), which makes v̂ exact for linear-quadratic problems (the
Riccati solution of docs/maths.rst, "Exact references"); the paper uses the deterministic v̄ (``stochastic=False``). Between
nodes v̄, c, p, P and x̄ are linear in time, ū and K are held on each interval, as the optimiser
held the controls.

Far from its trajectory a tracker extrapolates a local model: KΔx grows without bound. The
feedback is therefore saturated at the Mahalanobis distance

    ρ(x, t) = √(Δxᵀ P(t) Δx / λ),

the number of standard deviations at which x lies under the component's own Gaussian
desirability z ∝ exp(−½ Δxᵀ(P/λ)Δx); v̂ itself is not changed. Under that Gaussian ρ² is χ²
distributed with d degrees of freedom (d the state dimension), so the default radius

    ρ_max = √(χ²_d⁻¹(0.99))      (:data:`VALIDITY`)

keeps the plain tracker u = ū + KΔx wherever the component's desirability holds 99 % of its
mass, and bounds it beyond. On a linear-quadratic problem (linear dynamics, quadratic or no
costs, no periodic axis) the expansion is not local: it is the Riccati solution everywhere, so
the default does not saturate there, and the tracker is the exact Riccati controller at every
state. ``radius=None`` never saturates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.stats import chi2

from ..costs import wrap_difference
from ..errors import TrajectoryWarning, warn_user
from ..problem import Problem, bracket, check_time, state_evaluation
from ..reference.lq import is_linear_quadratic
from .ddp import positive_part, sweeps
from .optimize import Trajectory, shooting_for, timed_state_cost

CURVATURES = ("gauss-newton", "newton")
"""How P is computed (``curvature``): without or with the dynamics' second derivatives."""

FEEDBACKS = ("projected-newton", "newton", "gauss-newton")
"""The backward pass that gives the tracker's gain K (``feedback``)."""

VALIDITY = 0.99
"""The probability mass of a component's Gaussian desirability within the default radius
ρ_max = √(χ²_d⁻¹(VALIDITY)) of its feedback saturation."""


def default_radius(state_dim: int) -> float:
    """ρ_max = √(χ²_d⁻¹(:data:`VALIDITY`)): the Mahalanobis radius that holds that probability
    of a d-dimensional Gaussian."""
    return float(np.sqrt(chi2.ppf(VALIDITY, state_dim)))


def state_periods(problem: Problem) -> np.ndarray:
    """The period of each state coordinate (``inf`` where not periodic), shape ``(d,)``."""
    periods = getattr(problem, "periods", None)
    if periods is None:
        periods = problem.require_grid("state_periods").periods
    return np.asarray(periods, dtype=float)


@dataclass(frozen=True, eq=False)
class TrajectoryExpansion:
    """A trajectory-based component: v̂, z and the tracker of the module docstring.

    Attributes
    ----------
    problem : Problem
    trajectory : Trajectory
    nominal_values : ndarray (K+1,)
        v̄(t_k), with the Itô correction c_k when ``stochastic``.
    gradients : ndarray (K+1, d)
        p_k.
    hessians : ndarray (K+1, d, d)
        P_k⁺, positive semi-definite.
    gains : ndarray (K, m, d)
        K_k, the tracker's feedback on [t_k, t_k+1) (from the ``feedback`` pass).
    stochastic : bool
        Whether ``nominal_values`` include (λ/2)∫tr(SP).
    radius : float or None
        ρ_max of the feedback saturation (None: none).
    periods : ndarray (d,)
        The period of each coordinate (inf where not periodic).
    curvature : str
        The pass that gives P: ``"newton"`` (full DDP) or ``"gauss-newton"``.
    feedback : str
        The pass that gives K, one of :data:`~gridlbc.trajectory.expansion.FEEDBACKS`.
    """

    problem: Problem
    trajectory: Trajectory
    nominal_values: np.ndarray
    gradients: np.ndarray
    hessians: np.ndarray
    gains: np.ndarray
    stochastic: bool
    radius: float | None
    periods: np.ndarray
    curvature: str
    feedback: str

    @property
    def times(self) -> np.ndarray:
        return self.trajectory.times

    @property
    def temperature(self) -> float:
        return self.problem.temperature

    def _states(self, x) -> np.ndarray:
        d = self.problem.system.state_dim
        arr = np.asarray(x, dtype=float)
        if arr.ndim == 1:
            arr = arr[None, :]
        if arr.ndim != 2 or arr.shape[1] != d:
            raise ValueError(
                f"x must be states of shape (N, {d}) or one state ({d},), got shape {np.shape(x)}"
            )
        return arr

    def _bracket(self, t) -> tuple[int, float]:
        """Times are checked and bracketed exactly as a grid Solution's slices are."""
        return bracket(
            self.times, check_time(t, self.problem.require_horizon("a trajectory component"))
        )

    def _at(self, field: np.ndarray, j: int, theta: float) -> np.ndarray:
        return (1.0 - theta) * field[j] + theta * field[j + 1]

    @state_evaluation
    def deviation(self, x, t) -> np.ndarray:
        """Δx = x ⊖ x̄(t), to the nearest image on periodic axes, shape ``(N, d)`` (``(d,)`` for one
        state)."""
        j, theta = self._bracket(t)
        return self._deviation(self._states(x), j, theta)

    def _deviation(self, x: np.ndarray, j: int, theta: float) -> np.ndarray:
        return wrap_difference(x - self._at(self.trajectory.states, j, theta), self.periods)

    @state_evaluation
    def value(self, x, t) -> np.ndarray:
        """v̂(x, t) = v̄ + pᵀΔx + ½ ΔxᵀPΔx, shape ``(N,)`` (a scalar for one state ``(d,)``)."""
        j, theta = self._bracket(t)
        dx = self._deviation(self._states(x), j, theta)
        P = self._at(self.hessians, j, theta)
        return (
            self._at(self.nominal_values, j, theta)
            + dx @ self._at(self.gradients, j, theta)
            + 0.5 * np.einsum("ni,ij,nj->n", dx, P, dx)
        )

    @state_evaluation
    def log_desirability(self, x, t) -> np.ndarray:
        """log z = −v̂/λ, shape ``(N,)`` (a scalar for one state ``(d,)``)."""
        return -self.value(x, t) / self.temperature

    @state_evaluation
    def desirability(self, x, t) -> np.ndarray:
        """z = exp(−v̂/λ), shape ``(N,)`` (a scalar for one state ``(d,)``) (may underflow far away:
        use :meth:`value`)."""
        with np.errstate(under="ignore", over="ignore"):
            return np.exp(self.log_desirability(x, t))

    @state_evaluation
    def mahalanobis(self, x, t) -> np.ndarray:
        """ρ = √(ΔxᵀPΔx/λ), shape ``(N,)`` (a scalar for one state ``(d,)``): how far x is from the
        trajectory in the component's own metric."""
        j, theta = self._bracket(t)
        dx = self._deviation(self._states(x), j, theta)
        return self._rho(dx, j, theta)

    def _rho(self, dx: np.ndarray, j: int, theta: float) -> np.ndarray:
        P = self._at(self.hessians, j, theta)
        return np.sqrt(np.maximum(np.einsum("ni,ij,nj->n", dx, P, dx), 0.0) / self.temperature)

    @state_evaluation
    def policy(self, x, t) -> np.ndarray:
        """The tracker u = ū + K Δx · min(1, ρ_max/ρ) (no saturation when ``radius`` is None),
        shape ``(N, m)`` (``(m,)`` for one state)."""
        j, theta = self._bracket(t)
        dx = self._deviation(self._states(x), j, theta)
        if self.radius is not None:
            rho = self._rho(dx, j, theta)
            with np.errstate(divide="ignore"):
                dx = dx * np.minimum(1.0, self.radius / rho)[:, None]
        # ū and K are held on [t_j, t_j+1) (t = T falls in the last interval)
        return self.trajectory.controls[j] + dx @ self.gains[j].T


def expand(
    problem: Problem,
    trajectory: Trajectory,
    stochastic: bool = True,
    radius: float | str | None = "auto",
    curvature: str = "newton",
    feedback: str = "projected-newton",
) -> TrajectoryExpansion:
    """The quadratic value expansion and LQR tracker of ``trajectory`` (module docstring).

    Parameters
    ----------
    problem : Problem
        The problem the trajectory was optimised for (its temperature λ may differ: it sets the
        Itô correction, the desirability's unit and the Mahalanobis distance ρ).
    trajectory : Trajectory
        From :func:`gridlbc.trajectory.optimize`.
    stochastic : bool
        Include (λ/2)∫tr(B R⁻¹ Bᵀ P) in v̄ (exact for LQ); ``False``: the paper's deterministic v̄.
    radius : "auto", float or None
        Saturate the tracker's feedback at this Mahalanobis distance ρ_max (in standard
        deviations of the component's desirability). ``"auto"`` (the default):
        ρ_max = √(χ²_d⁻¹(0.99)), :func:`~gridlbc.trajectory.expansion.default_radius`, and no
        saturation on a linear-quadratic problem, where the expansion is global; ``None``: no
        saturation.
    curvature : {"newton", "gauss-newton"}
        The pass that gives p and P of the value: full DDP (the default) or Gauss–Newton.
    feedback : {"projected-newton", "newton", "gauss-newton"}
        The pass that gives the tracker's gain K: full DDP carrying the positive semi-definite
        part of each P (the default), exact full DDP, or Gauss–Newton (module docstring).

    Returns
    -------
    TrajectoryExpansion
        A component for :func:`gridlbc.combine` with ``value``, ``desirability`` and ``policy``.
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a gridlbc.Problem, got {type(problem).__name__}")
    if not isinstance(trajectory, Trajectory):
        raise TypeError(
            "trajectory must be a gridlbc.trajectory.Trajectory (from "
            f"gridlbc.trajectory.optimize), got {type(trajectory).__name__}"
        )
    for name, value, allowed in (
        ("curvature", curvature, CURVATURES),
        ("feedback", feedback, FEEDBACKS),
    ):
        if not isinstance(value, str) or value not in allowed:
            raise ValueError(f"{name} must be one of {allowed}, got {value!r}")
    radius = _check_radius(radius, problem)
    _check_same_problem(problem, trajectory)
    if not trajectory.converged:
        warn_user(
            f"the trajectory's optimisation did not converge ({trajectory.message}): "
            "its expansion is a local model of a suboptimal tape; optimise again with "
            "more restarts or intervals",
            TrajectoryWarning,
        )
    U, X = trajectory.controls, trajectory.states
    K = len(U)
    shooting = shooting_for(problem, X[0], K)
    passes = (curvature, feedback) if feedback != curvature else (curvature,)
    states, backs = sweeps(shooting, U, problem.terminal_cost, problem.state_cost, passes)
    back, gains = backs[0], backs[-1].gains
    P = positive_part(back.P)
    dt = shooting.dt
    running = 0.5 * np.einsum("ki,ij,kj->k", U, problem.R, U)
    q = timed_state_cost(problem)
    if q is not None:
        running = running + np.asarray(q(states[:-1], trajectory.times[:-1]), dtype=float)
    terminal = float(
        np.asarray(problem.require_terminal_cost("expand")(states[-1:]), dtype=float)[0]
    )
    to_go = terminal + dt * np.concatenate([np.cumsum(running[::-1])[::-1], [0.0]])
    if stochastic:
        B = np.asarray(problem.system.input_matrix(states), dtype=float)  # (K+1, d, m)
        S = np.einsum("kim,mn,kjn->kij", B, problem.R_inv, B)
        trace = np.einsum("kij,kji->k", S, back.P)  # the exact P: this term needs no sign
        step = 0.25 * problem.temperature * dt * (trace[:-1] + trace[1:])
        to_go = to_go + np.concatenate([np.cumsum(step[::-1])[::-1], [0.0]])
    return TrajectoryExpansion(
        problem,
        trajectory,
        to_go,
        back.p,
        P,
        gains,
        bool(stochastic),
        radius,
        state_periods(problem),
        curvature,
        feedback,
    )


def _check_radius(radius, problem: Problem) -> float | None:
    """``radius`` as ρ_max (None: no saturation), ``"auto"`` resolved to the default."""
    if radius is None:
        return None
    if isinstance(radius, str):
        if radius != "auto":
            raise ValueError(f"radius must be 'auto', None or a positive number, got {radius!r}")
        return None if is_linear_quadratic(problem) else default_radius(problem.system.state_dim)
    if isinstance(radius, bool) or not isinstance(radius, (int, float, np.integer, np.floating)):
        raise TypeError(f"radius must be 'auto', None or a positive number, got {radius!r}")
    radius = float(radius)
    if not (np.isfinite(radius) and radius > 0):
        raise ValueError(f"radius must be 'auto', None or a positive number, got {radius}")
    return radius


def _check_same_problem(problem: Problem, trajectory: Trajectory) -> None:
    """Raise if ``trajectory`` was optimised for a problem other than ``problem``."""
    other = trajectory.problem
    differs = []
    if other.system != problem.system:
        differs.append(f"system ({other.system!r} vs {problem.system!r})")
    if not np.isclose(trajectory.times[-1], problem.require_horizon("expand"), rtol=1e-12, atol=0):
        differs.append(
            f"horizon (the trajectory ends at {trajectory.times[-1]:g}, the problem's "
            f"T is {problem.horizon:g})"
        )
    if not np.array_equal(other.R, problem.R):
        differs.append(f"control cost R ({other.R.tolist()} vs {problem.R.tolist()})")
    x, t = trajectory.states, trajectory.times
    for name in ("terminal_cost", "state_cost"):
        a, b = getattr(other, name), getattr(problem, name)
        if a is b:
            continue
        if a is None or b is None:
            differs.append(name.replace("_", " "))
            continue
        timed = getattr(a, "time_dependent", False), getattr(b, "time_dependent", False)
        if timed[0] != timed[1] or not np.allclose(
            a(x, t) if timed[0] else a(x), b(x, t) if timed[1] else b(x), rtol=1e-12, atol=1e-12
        ):
            differs.append(f"{name.replace('_', ' ')} (values differ along the trajectory)")
    if differs:
        raise ValueError(
            "trajectory was optimised for another problem: it differs in "
            f"{'; '.join(differs)}. Optimise it for this problem "
            "(gridlbc.trajectory.optimize(problem, x0))."
        )
