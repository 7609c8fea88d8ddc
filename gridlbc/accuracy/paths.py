"""What a grid cannot see of the costs, sampled along the solve's own paths (docs page
:doc:`accuracy`, "Costs narrower than a cell").

A grid scheme charges a path the state cost at the nodes it visits: its chain's expected cost per
step is Σ_i p_i q(x_i), and where the chain's occupancy p_i is the continuous one projected on the
nodes' hat functions, that is ∫ ρ I_h q, the integral of the grid's interpolant I_h q rather than
of q. A solve is therefore, in effect, a solve of the problem whose costs are I_h q and I_h g.
Where a cost is narrower than a cell (a pit or a goal between two nodes, a wall a path crosses
between nodes), I_h q differs from q by the whole depth of the feature, wherever the nodes fall,
while the solves on coarser grids, which the embedded estimate compares, can all miss it alike.

The optimal value is a minimum over policies of expectations that are linear in the costs, so for
the policy π_h that is optimal with the interpolated costs (the solve's own policy),

    v[I_h q, I_h g](x, t) − v[q, g](x, t)
        ≥ γ(x, t) = E_{π_h}[ ∫_t^T (I_h q − q)(X_s) ds + (I_h g − g)(X_T) | X_t = x ],

the expected cost that the grid adds along the paths its policy takes. :func:`cost_gap` samples γ
with :data:`PATH_SAMPLES` Euler–Maruyama paths per state at the solve's own step Δt (rectangle
rule, a fixed seed: the same states give the same numbers), reflected at closed edges as the solver
does (:func:`gridlbc.simulate`). The solve's step resolves the dynamics the solve resolves; a
longer one can make the explicit paths unstable where the drift is stiff (ẋ = −kx with kΔt > 2),
and they then cross costs the true process never reaches. Where the costs vary smoothly,
I_h q − q is O(h²) and γ is mostly below the embedded estimate; where a path lingers in a feature
the grid does not resolve, γ is the error the solve makes there (``error_estimate`` reads
abs(γ)).

What γ cannot see: the error of the scheme itself for the interpolated costs (the embedded solves
measure that); costs felt between the steps of the paths; and a feature the solve's policy never
approaches (γ is a bound along that policy: a goal narrower than a cell, which the grid sees as
a shallow dip, is not sought, and is not seen). Where the paths spread over many cells of a
smooth, steep cost, the chain's lattice represents it better than I_h does and γ overstates the
error (by O(h²)). It is zero for a solution read back by :func:`gridlbc.load` whose costs were not
quadratics: those are stored as their nodal values, which the grid represents exactly. It is not
sampled for a task that ends (an exit set) or without a horizon.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..interpolate import interpolate
from ..simulate import euler_maruyama

PATH_SAMPLES = 16
"""Paths per state from which :func:`cost_gap` averages γ (fewer where many states are asked
for: :data:`PATH_WORK`)."""

PATH_WORK = 8_388_608
"""At most this many path-steps per call (but at least 4 paths per state): a map of the estimate
over many states samples each one more thinly."""

SEED = 20090801
"""The paths' seed: the same states give the same γ."""


def sampled(problem) -> bool:
    """Whether :func:`cost_gap` samples γ for ``problem``: a horizon and no exit set."""
    return not problem.stationary and problem.exit is None


def cost_gap(solution, x, t: float = 0.0, samples: int = PATH_SAMPLES) -> np.ndarray:
    """γ(x, t), the expected cost the grid's interpolants add along the solve's paths (module
    docstring), at states ``x`` (N, d): the mean over ``samples`` paths per state (fewer where
    :data:`PATH_WORK` asks) driven by ``solution.policy`` from time ``t`` to T. Zero where
    :func:`sampled` is false; NaN for a state whose paths meet an underflowed policy (the solve
    has warned of it).

    Parameters
    ----------
    solution : Solution
        A grid solution of a problem with a horizon.
    x : ndarray (N, d)
        Start states.
    t : float
        Start time in [0, T].
    samples : int
        Paths per state.

    Returns
    -------
    ndarray (N,)
    """
    problem = solution.problem
    x = np.atleast_2d(np.asarray(x, dtype=float))
    n_states = x.shape[0]
    if not sampled(problem) or n_states == 0:
        return np.zeros(n_states)
    grid, remaining = problem.grid, problem.horizon - t
    if remaining <= 0.0:  # v(x, T) = I_h g(x)
        return terminal_gap(solution, x)
    steps = max(1, int(np.ceil(remaining / solution.diagnostics.dt - 1e-9)))
    samples = int(np.clip(PATH_WORK // (n_states * steps), min(4, samples), samples))
    dt = remaining / steps
    q_nodes = nodal(solution, "state_cost") if problem.state_cost is not None else None
    starts = np.repeat(x, samples, axis=0)
    gap = np.zeros(starts.shape[0])
    undefined = np.zeros(starts.shape[0], dtype=bool)

    def policy(y: np.ndarray, s: float) -> np.ndarray:
        """The solve's policy at the paths' states y at time t + s, where the running part of γ
        is taken too (rectangle rule)."""
        if q_nodes is not None:
            gap[:] += (interpolate(grid, q_nodes, y) - problem.state_cost_values(y)) * dt
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an underflowed policy was the solve's to warn of
            u = np.asarray(solution.policy(y, t + s), dtype=float)
        bad = ~np.all(np.isfinite(u), axis=1)
        undefined[bad] = True
        u[bad] = 0.0
        return u

    rng = np.random.default_rng(SEED)
    end = euler_maruyama(problem, policy, starts, steps, rng, horizon=remaining).final_states
    gap += terminal_gap(solution, end)
    gap[undefined] = np.nan
    return gap.reshape(n_states, samples).mean(axis=1)


def terminal_gap(solution, x: np.ndarray) -> np.ndarray:
    """(I_h g − g)(x): how far the grid's interpolant of the terminal cost is from it at ``x``."""
    problem = solution.problem
    return interpolate(problem.grid, nodal(solution, "terminal"), x) - problem.terminal_values(x)


def nodal(solution, cost: str) -> np.ndarray:
    """The ``cost`` ("state_cost" or "terminal") of the solution's problem at every node, kept
    with the solution (a 4-D grid has millions of nodes)."""
    key = f"{cost}_nodes"
    if key not in solution._cache:
        problem = solution.problem
        values = problem.state_cost_values if cost == "state_cost" else problem.terminal_values
        solution._cache[key] = problem.grid.node_values(values)
    return solution._cache[key]
