"""How far the splitting's one midpoint step per Δt misplaces where the drift carries a path, and
what that changes in the value (docs page :doc:`accuracy`, "A drift that switches within a
step").

The splitting scheme (:mod:`gridlbc.schemes.splitting`) carries each node x along the drift over
a step Δt to its second-order (midpoint) foot

    X(x) = x + Δt a(x + ½Δt a(x))

and reads the value of the next time there. Where a changes little over the distance a path
moves in a step, X is accurate to O(Δt³) and the default step, set by the drift's speed
(its Courant rate), may carry a path across several cells. Where a changes sign within that
distance (a pull to a line that switches over less than a step's travel: a sliding mode, a
saturating controller built into the dynamics), the midpoint is taken on the far side of the
switch and X lands as far beyond it as the path started before it: the solve answers a problem
in which the line repels the paths it should hold. Every coarser solve, with a longer step,
does the same, so the embedded estimate reads nothing.

Two half steps, X₂(x) = X(X(x; Δt/2); Δt/2), trace the flow more closely (step doubling, as an
ODE solver controls its step). A solve that landed at X₂ would read v(X₂, t + Δt) instead of
v(X, t + Δt), so per unit time the solve's value exceeds the better-traced one by

    ρ(x, t) = ( v_h(X(x), t + Δt) − v_h(X₂(x), t + Δt) ) / Δt,

and :func:`~gridlbc.accuracy.tracing_gap` carries ρ along the solve's own paths
(:func:`gridlbc.accuracy.path_gap` at the solve's step, the paths γ is sampled on: :func:`gaps`)
from t to T, E[∫ ρ ds], a first-order estimate of how much the feet move v.
Where the flow is smooth on the scale of a step, X and X₂ differ by O(Δt³) per step and the term
is below the scheme's other errors; for a linear drift a = A x with A³ = 0 (a point mass, a
chain of integrators) the two feet agree exactly and no path is run
(:func:`~gridlbc.accuracy.tracing.traced`). The implicit scheme (first exit with a horizon) reads
the drift at the nodes only and has no feet: there the term is zero.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..schemes.splitting.feet import foot
from .paths import cost_gap


def traced(solution) -> bool:
    """Whether the solution was marched by the splitting scheme over a horizon, whose feet
    :func:`~gridlbc.accuracy.tracing_gap` compares, with a drift for which they can differ: for a =
    A x the one step and the two half steps land at (I + ΔtA + Δt²A²/2) x and (I + ΔtA/2 + Δt²A²/8)²
    x, which differ by (Δt³A³/8 + Δt⁴A⁴/64) x, zero where A³ = 0 (a point mass, a chain of
    integrators)."""
    problem = solution.problem
    if solution.operator.method != "splitting" or problem.stationary:
        return False
    linear = problem.system.linear_matrices()
    return linear is None or bool(np.any(np.linalg.matrix_power(linear[0], 3)))


def tracing_rate(solution, y: np.ndarray, t: float) -> np.ndarray:
    """ρ(y, t) (module docstring) at states ``y`` (n, d) and time ``t``: the value at the foot of
    one step Δt less the value at the foot of two half steps, per unit time; 0 where either is
    not finite."""
    problem, dt = solution.problem, solution.diagnostics.dt
    later = min(t + dt, problem.horizon)
    n = len(y)
    # the one step and the first half step in one call of the drift, then the second half step
    steps = np.repeat([[dt], [0.5 * dt]], n, axis=0)
    feet = foot(problem, np.concatenate([y, y]), steps)
    feet[n:] = foot(problem, feet[n:], 0.5 * dt)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an underflowed value is the solve's to warn of
        v = solution.value(feet, later)  # X and X₂ read in one call
        rate = (v[:n] - v[n:]) / dt
    return np.where(np.isfinite(rate), rate, 0.0)


def tracing_gap(solution, x, samples: int, t: float = 0.0) -> np.ndarray:
    """E[∫_t^T ρ(X_s, s) ds] from states ``x`` (N, d) at time ``t``, along ``samples`` paths per
    state driven by the solve's policy at its step (module docstring); zeros for a solution that
    is not :func:`~gridlbc.accuracy.tracing.traced`.

    Returns
    -------
    ndarray (N,)
        The first-order change of v that tracing the drift by two half steps makes (positive
        where the solve's one midpoint step overestimates v).
    """
    return gaps(solution, x, samples, t)[1]


def gaps(solution, x, samples: int, t: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """γ (:func:`gridlbc.accuracy.cost_gap`) and :func:`~gridlbc.accuracy.tracing_gap` at states
    ``x`` (N, d), from the same paths (the same draws, the solve's policy and step): each is what it
    would be alone, and the paths are run once."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    if not traced(solution) or len(x) == 0:
        return cost_gap(solution, x, t, samples), np.zeros(len(x))
    both = cost_gap(solution, x, t, samples, also=lambda y, s: tracing_rate(solution, y, s))
    return both[:, 0], both[:, 1]
