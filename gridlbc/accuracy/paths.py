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

the expected cost that the grid adds along the paths its policy
takes. :func:`~gridlbc.accuracy.cost_gap` samples γ with :data:`PATH_SAMPLES` Euler–Maruyama paths
per state at the solve's own step Δt (rectangle rule, a fixed seed: the same states give the same
numbers), reflected at closed edges as the solver does (:func:`gridlbc.simulate`). The solve's step
resolves the dynamics the solve resolves; a longer one can make the explicit paths unstable where
the drift is stiff (ẋ = −kx with kΔt > 2), and they then cross costs the true process never reaches.
Where the costs vary smoothly, I_h q − q is O(h²) and γ is mostly below the embedded estimate; where
a path lingers in a feature the grid does not resolve, γ is the error the solve makes there
(``error_estimate`` reads abs(γ)).

What γ cannot see: the error of the scheme itself for the interpolated costs (the embedded solves
measure that); costs felt between the steps of the paths; and a feature the solve's policy never
approaches (γ is a bound along that policy: a goal narrower than a cell, which the grid sees as
a shallow dip, is not sought, and is not seen). Where the paths spread over many cells of a
smooth, steep cost, the chain's lattice represents it better than I_h does and γ overstates the
error (by O(h²)). It is zero for a solution read back by :func:`gridlbc.load` whose costs were not
quadratics: those are stored as their nodal values, which the grid represents exactly.

**Tasks that end** (an exit set E, with or without a horizon: :func:`~gridlbc.accuracy.path_gap`).
The paths stop at τ, on entering E (:func:`gridlbc.simulate.euler_maruyama`, whose Brownian-bridge
check also stops a path that crossed into E between two steps, at the nearest point of E's
boundary), or at min(τ, T), and

    γ(x) = E_{π_h}[ ∫_0^τ (I_h q − q)(X_s) ds + (I_h g_E − g_E)(X_τ) ],

(I_h g − g)(X_T) for a path that reaches T first. I_h g_E is the interpolant of g_E's values at
the nodes: the grid reads g_E at the nodes of E and at the points where its grid lines cross E's
boundary, and on a boundary along grid lines (a half-space at a node) the nodal interpolant is
what it charges between those points; elsewhere the two differ by O(h²) where g_E is smooth. A
problem without a horizon has no solve step; the paths take :func:`~gridlbc.accuracy.path_step`,
about a cell along any axis per step (a finite-horizon solve's step moves the passive drift by up to
one cell, implicit, or six or seven, splitting: these paths are no coarser), and run in chunks of
:data:`CHUNK` steps until every path has exited, or twice the steps by which nine in ten had
(:data:`SETTLED`), or :data:`EXIT_STEPS` steps or :data:`EXIT_WORK` path-steps are spent. A path
still running at that cap adds the part it has accrued: γ is then truncated (a lower bound of
its size where I_h q − q has one sign along the paths); :func:`~gridlbc.accuracy.path_gap` counts
such paths. Where the grid charges less than the costs (a toll the nodes miss), the solve's policy
does not avoid the toll and crosses it more slowly than the optimal one, and γ overstates the error
(stranger round 11's ``toll_blind``, docs page :doc:`accuracy`, "What the estimate is"). Without
a horizon, where the costs equal their interpolants at every cell's centre (constant or affine
costs: :func:`interpolated_exactly`)
γ is zero and no path is run.

**Average cost** (no end, no horizon: :func:`stationary_gap`). The cost per unit time that the
grid leaves out is an expectation under the solve's long-run law instead of along paths that
end. The solve's chain spends the share p_i of its time at node i
(:func:`gridlbc.stationary.average.stationary_distribution`) and is charged q(x_i) there; its
continuous counterpart spreads that share over the node's hat function, ρ_h = Σ_i p_i φ_i / ∫φ_i,
and is charged q where it is. For the policy π_h that is optimal on the grid, c[q] ≤ c_{π_h}[q], the
control's cost is the same in both, so

    c_h − c[q] ≥ γ_c = Σ_i p_i ( q(x_i) − ⟨q⟩_{φ_i} ) = E[ q(x_I) − q(X) ],

the mean over :data:`STATIONARY_SAMPLES` draws of a node I by p and a state X from its hat
(along each axis an offset h (U₁ − U₂) with U₁, U₂ uniform, folded back into the box at a
closed edge): no path and no mixing time. A toll narrower than a cell between the nodes gives a
γ_c below zero, what the solve's policy, which does not see it, pays for it per unit time: it
bounds c's error where the grid charges too little. A narrow well is sought by the optimal
policy and not by the solve's, and γ_c (above zero, the well's weight under the solve's smooth
law) understates what it changes. For a smooth q, γ_c is −(h²/12) Σ_k E[∂²q/∂x_k²], of the
order of the scheme's own error.
"""

from __future__ import annotations

import warnings
from functools import partial
from typing import cast

import numpy as np

from ..interpolate import interpolate
from ..regions import RegionBase, has_geometry
from ..simulate import euler_maruyama

PATH_SAMPLES = 16
"""Paths per state from which :func:`~gridlbc.accuracy.cost_gap` averages γ (fewer where many states
are asked for: :data:`~gridlbc.accuracy.paths.PATH_WORK`)."""

PATH_WORK = 8_388_608
"""At most this many path-steps per call (but at least 4 paths per state): a map of the estimate
over many states samples each one more thinly."""

SEED = 20090801
"""The paths' seed: the same states give the same γ."""


EXIT_STEPS = 16_384
"""At most this many steps per path for a problem without a horizon (first exit): a path still
running then is truncated (:func:`~gridlbc.accuracy.path_gap`)."""

EXIT_WORK = 1 << 18
"""At most about this many path-steps per call for a first-exit problem without a horizon (but
at least one :data:`CHUNK` per path): its paths run until they exit, which on a fine grid with
a noiseless axis takes thousands of steps of a cell each; a path stopped by this budget adds the
part it has accrued (:func:`~gridlbc.accuracy.path_gap`)."""

CHUNK = 128
"""The steps between two looks at which paths of a first-exit problem have exited (the run ends
when all have, or :data:`EXIT_WORK` or :data:`EXIT_STEPS` is spent)."""

SETTLED = 0.9
"""Once this share of a first-exit problem's paths (without a horizon) has exited, at step k,
the rest run to step 2k at most: exit times have an exponential tail, so about one in a hundred
is then still running, and the steps that follow would be spent on ever fewer paths."""

ROUNDING = 1e-12
"""A gap between a cost and its interpolant below this share of the cost's magnitude (at least 1)
is rounding (:func:`interpolated_exactly`)."""

STEP_STATES = 1024
"""At most this many nodes off the exit set give the paths' step of a first-exit problem
without a horizon (:func:`~gridlbc.accuracy.path_step`)."""


STATIONARY_SAMPLES = 1 << 16
"""States drawn from the stationary law of an average-cost solve for γ_c
(:func:`stationary_gap`)."""


def sampled(problem) -> bool:
    """Whether :func:`~gridlbc.accuracy.cost_gap` samples γ for ``problem``: a horizon (with or
    without an exit set), or an exit set without one (first exit); not for average cost."""
    if problem.average_cost:
        return False
    return not problem.stationary or problem.exit is not None


def cost_gap(solution, x, t: float = 0.0, samples: int = PATH_SAMPLES, also=None) -> np.ndarray:
    """γ(x, t), the expected cost the grid's interpolants add along the solve's paths (module
    docstring), at states ``x`` (N, d): the mean over ``samples`` paths per state (fewer where
    :data:`~gridlbc.accuracy.paths.PATH_WORK` asks) driven by ``solution.policy`` from time ``t`` to
    T. Zero where
    :func:`~gridlbc.accuracy.paths.sampled` is false; NaN for a state whose paths meet an
    underflowed policy (the solve has warned of it).

    Parameters
    ----------
    solution : Solution
        A grid solution (a horizon, an exit set or both: :func:`~gridlbc.accuracy.paths.sampled`).
    x : ndarray (N, d)
        Start states.
    t : float
        Start time in [0, T] (0 without a horizon).
    samples : int
        Paths per state.
    also : callable, optional
        A second rate ``r(y, t)`` ``(n,)`` integrated along the same paths
        (:func:`~gridlbc.accuracy.path_gap`).

    Returns
    -------
    ndarray (N,), or (N, 2) with ``also``: γ, and the integral of ``also`` in the second column
    """
    problem = solution.problem
    x = np.atleast_2d(np.asarray(x, dtype=float))
    n_states = x.shape[0]
    if not sampled(problem) or n_states == 0:
        return np.zeros(n_states if also is None else (n_states, 2))
    return path_gap(solution, x, t, samples, also=also)[0]


def path_gap(solution, x, t: float = 0.0, samples: int = PATH_SAMPLES, along=None, also=None):
    """γ(x, t) (:func:`~gridlbc.accuracy.cost_gap`), and how many of its paths had not exited when
    they were stopped (the cap of a task without a horizon: the module docstring).

    ``along``: ``(problem, policy, rate)``, the problem whose dynamics, exit set and horizon
    the paths follow, a policy ``u(y, t)`` ``(n, m)`` and a running cost ``r(y, t)`` ``(n,)``
    that replace the solution's problem, the solve's policy and I_h q − q; the paths then add
    no exit or terminal gap (:func:`gridlbc.accuracy.truncation_gap` integrates λτ
    so). ``also``: a second rate ``r(y, t)`` ``(n,)`` integrated along the same paths (the same
    draws: :func:`gridlbc.accuracy.tracing_gap` shares γ's paths so), returned as the
    second column of ``gap``.

    The paths stop at τ, on entering an exit set E (:func:`gridlbc.simulate.euler_maruyama`,
    with its Brownian-bridge crossing check), or at T where there is a horizon, and run at the
    solve's step Δt there, at :func:`~gridlbc.accuracy.path_step` without one. A path that exits at
    x_τ adds (I_h g_E − g_E)(x_τ), one still running at T adds (I_h g − g)(x_T), one still running
    at the cap of a problem without a horizon adds nothing more (its γ is the part accrued).

    Returns
    -------
    gap : ndarray (N,), or (N, 2) with ``also``
        γ at each state (NaN where a path met an underflowed policy), and the integral of
        ``also`` in the second column.
    unexited : int
        Paths of a problem without a horizon that had not exited at the cap (0 with a
        horizon).
    """
    problem = solution.problem if along is None else along[0]
    x = np.atleast_2d(np.asarray(x, dtype=float))
    n_states = x.shape[0]
    columns = 1 if also is None else 2
    if along is None and problem.stationary and interpolated_exactly(solution):
        return _columns(np.zeros(n_states), columns), 0
    if problem.stationary:
        dt = path_step(solution, None if along is None else lambda y: along[1](y, t))
        steps = EXIT_STEPS
    else:
        remaining = problem.horizon - t
        if remaining <= 0.0:  # v(x, T) = I_h g(x) off E, I_h g_E(x) on it
            gap = terminal_gap(solution, x)
            if problem.exit is not None:
                inside = problem.exit_mask(x)
                gap[inside] = exit_cost_gap(solution, x[inside])
            return _columns(gap, columns), 0
        steps = max(1, int(np.ceil(remaining / solution.diagnostics.dt - 1e-9)))
        dt = remaining / steps
    samples = int(np.clip(PATH_WORK // (n_states * steps), min(4, samples), samples))
    budget = max(EXIT_WORK, n_states * samples * CHUNK)
    q_nodes = nodal(solution, "state_cost") if problem.state_cost is not None else None
    starts = np.repeat(x, samples, axis=0)
    n = starts.shape[0]
    gap = np.zeros((n, columns))
    undefined = np.zeros(n, dtype=bool)
    last_bad = np.zeros(0, dtype=bool)
    last = None  # the solve's stencil at the states its policy last read: the rate reads them

    def policy(y: np.ndarray, s: float) -> np.ndarray:
        """The solve's policy at the running paths' states y (an underflowed one: 0, marked)."""
        nonlocal last_bad, last
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an underflowed policy was the solve's to warn of
            if along is None:  # solution.policy, its stencil kept for the rate
                last = solution.stencil(y, t + s)
                u = solution.fields_at(last).policy(solution.temperature, problem.R_inv)
            else:
                u = np.asarray(along[1](y, t + s), dtype=float)
        last_bad = ~np.all(np.isfinite(u), axis=1)
        u[last_bad] = 0.0
        return u

    def rate(y: np.ndarray, s: float) -> np.ndarray:
        """I_h q − q at the same states (rectangle rule); NaN marks an underflowed policy."""
        r = np.zeros(y.shape[0])
        if along is not None:
            r = along[2](y, t + s)
        elif q_nodes is not None:
            assert last is not None  # the policy's, at the same states y
            interpolated = last.interpolate(q_nodes[None], np.ones(1))  # I_h q
            r = interpolated - problem.state_cost_values(y, signed=True)
        r[last_bad] = np.nan
        return r if also is None else np.column_stack([r, also(y, t + s)])

    rng = np.random.default_rng(SEED)
    running = np.arange(n)  # the paths not yet exited, by index
    position = starts
    done = 0  # steps taken
    while len(running) and done < steps and budget > 0:
        chunk = min(CHUNK, steps - done) if problem.stationary else steps
        paths = euler_maruyama(
            problem, policy, position, chunk, rng, horizon=chunk * dt, integrand=rate, costs=False
        )
        budget -= len(running) * chunk
        done += chunk
        integral = cast(np.ndarray, paths.integral).reshape(len(running), columns)
        gap[running] += np.where(np.isnan(integral), 0.0, integral)
        undefined[running] |= np.isnan(integral[:, 0])
        times = paths.exit_times  # None without an exit set: no path exits
        exited = np.zeros(len(running), dtype=bool) if times is None else ~np.isnan(times)
        if along is None:
            ends = exit_points(problem, paths.final_states[exited])
            gap[running[exited], 0] += exit_cost_gap(solution, ends)
        if not problem.stationary:  # still running at T: (I_h g − g)(x_T)
            if along is None:
                gap[running[~exited], 0] += terminal_gap(solution, paths.final_states[~exited])
            running = running[:0]
            break
        running, position = running[~exited], paths.final_states[~exited]
        if len(running) <= (1.0 - SETTLED) * n:  # the tail: twice the time 9 in 10 took
            steps = min(steps, 2 * done)
    gap[undefined, 0] = np.nan
    mean = gap.reshape(n_states, samples, columns).mean(axis=1)
    return (mean[:, 0] if also is None else mean), len(running)


def _columns(gap: np.ndarray, columns: int) -> np.ndarray:
    """``gap`` (N,), with a second column of zeros where :func:`~gridlbc.accuracy.path_gap`
    integrates ``also``."""
    return gap if columns == 1 else np.column_stack([gap, np.zeros(len(gap))])


def stationary_gap(solution, samples: int = STATIONARY_SAMPLES) -> float:
    """γ_c = E[q(x_I) − q(X)], the cost per unit time that the grid leaves out of an average-cost
    solve's state cost under its stationary law (module docstring); 0 where the solution has no
    ``stationary_distribution`` or q equals its interpolant at every cell's centre
    (:func:`interpolated_exactly`: constant or affine). A fixed seed: the same solve gives the
    same number.

    Parameters
    ----------
    solution : StationarySolution
        An average-cost solution with its ``stationary_distribution``.
    samples : int
        Nodes I drawn from the stationary distribution, and one state X from each one's hat.

    Returns
    -------
    float
        γ_c (below zero where the grid charges less than q along the way).
    """
    share = getattr(solution, "stationary_distribution", None)
    problem, grid = solution.problem, solution.problem.grid
    if share is None or problem.state_cost is None or interpolated_exactly(solution):
        return 0.0
    rng = np.random.default_rng(SEED)
    nodes = rng.choice(len(share), size=samples, p=share)
    offsets = (rng.random((samples, grid.ndim)) - rng.random((samples, grid.ndim))) * grid.spacing
    x = grid.node_coordinates(nodes) + offsets
    lo, hi = grid.lo, grid.hi
    closed = ~grid.periodic
    x[:, closed] = np.where(x[:, closed] < lo[closed], 2 * lo[closed] - x[:, closed], x[:, closed])
    x[:, closed] = np.where(x[:, closed] > hi[closed], 2 * hi[closed] - x[:, closed], x[:, closed])
    q = problem.state_cost_values(grid.wrap(x), signed=True)
    gap = nodal(solution, "state_cost")[nodes] - q
    return float(np.mean(gap))


def interpolated_exactly(solution) -> bool:
    """Whether the grid's interpolants of the state cost and the exit cost equal the costs, to
    rounding, at the centre of every cell: then γ of a first-exit problem is zero without a path
    (a constant or affine cost, the common "minimum time" q = 1). A cost that is not affine in a
    cell differs from its interpolant at the cell's centre (a toll or a notch narrower than a
    cell anywhere between the nodes has a tail there far above rounding). Kept with the
    solution."""
    if "interpolated_exactly" in solution._cache:
        return solution._cache["interpolated_exactly"]
    problem, grid = solution.problem, solution.problem.grid
    axes = [a.lo + a.spacing * (np.arange(a.n if a.periodic else a.n - 1) + 0.5) for a in grid.axes]
    centres = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, grid.ndim)
    exact = True
    for cost, values in (
        ("state_cost", partial(problem.state_cost_values, signed=True)),
        ("exit_cost", problem.exit_values),
    ):
        if getattr(problem, cost) is None:
            continue
        for block in np.array_split(centres, max(1, len(centres) // 65_536)):
            truth = values(block)
            gap = interpolate(grid, nodal(solution, cost), block) - truth
            # rounding relative to the cost's own size, in whatever unit it is given (stranger
            # round 30: an absolute floor took a whole toll written in small numbers for rounding)
            if np.max(np.abs(gap)) > ROUNDING * float(np.max(np.abs(truth))):
                exact = False
                break
        if not exact:
            break
    solution._cache["interpolated_exactly"] = exact
    return exact


def path_step(solution, policy=None) -> float:
    """The paths' step for a first-exit problem without a horizon, which has no solve step Δt:
    the time in which a path moves about a cell along any axis,

        Δt = 1 / max_x max_k ( abs(a + B u)_k / h_k + Σ_kk / h_k² ),

    by the drift under the solve's policy u (or ``policy(x)``, where given) or by the noise
    Σ = λ B R⁻¹ Bᵀ (a standard deviation of h_k in Δt), the largest over up to
    :data:`~gridlbc.accuracy.paths.STEP_STATES` nodes off the exit set (where the policy is
    defined): as the finite-horizon γ's step, what the grid resolves of the paths. Kept with the
    solution (for the solve's policy)."""
    if policy is None and "path_step" in solution._cache:
        return solution._cache["path_step"]
    problem, grid = solution.problem, solution.problem.grid
    keep = np.flatnonzero(~problem.exit_mask() & np.isfinite(solution.value_nodes(0)))
    if len(keep) > STEP_STATES:
        keep = keep[np.linspace(0, len(keep) - 1, STEP_STATES).astype(np.int64)]
    X = grid.node_coordinates(keep)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = np.asarray(solution.policy(X) if policy is None else policy(X), dtype=float)
    usable = np.all(np.isfinite(u), axis=1)
    X, u = X[usable], u[usable]
    h = grid.spacing
    rate = 0.0
    if len(X):
        B = problem.input_matrix(X)
        speed = np.abs(problem.system.drift(X) + np.einsum("ndm,nm->nd", B, u))
        noise = np.einsum("nkk->nk", problem.noise_covariance(X))
        rate = float(np.max(speed / h + noise / h**2))
    dt = 1.0 / rate if np.isfinite(rate) and rate > 0 else float(np.min(h))
    if policy is None:
        solution._cache["path_step"] = dt
    return dt


def exit_points(problem, x: np.ndarray) -> np.ndarray:
    """Where the paths that stopped at ``x`` paid g_E: ``x`` itself where it lies in E, its
    nearest point of E's boundary where the Brownian-bridge check stopped it outside
    (:class:`gridlbc.simulate._Exits`)."""
    outside = ~problem.exit_mask(x) if len(x) else np.zeros(0, dtype=bool)
    if not outside.any() or not has_geometry(problem.exit):
        return x
    x = x.copy()
    distance, normal = cast(RegionBase, problem.exit).boundary_distance(x[outside])
    x[outside] -= distance[:, None] * normal
    return x


def exit_cost_gap(solution, x: np.ndarray) -> np.ndarray:
    """(I_h g_E − g_E)(x) at exit points ``x``: the grid's interpolant of the exit cost's nodal
    values against the cost (the module docstring says what the grid charges for an exit)."""
    if len(x) == 0:
        return np.zeros(0)
    problem = solution.problem
    return interpolate(problem.grid, nodal(solution, "exit_cost"), x) - problem.exit_values(x)


def terminal_gap(solution, x: np.ndarray) -> np.ndarray:
    """(I_h g − g)(x): how far the grid's interpolant of the terminal cost is from it at ``x``."""
    problem = solution.problem
    return interpolate(problem.grid, nodal(solution, "terminal"), x) - problem.terminal_values(x)


def nodal(solution, cost: str) -> np.ndarray:
    """The ``cost`` ("state_cost", "terminal" or "exit_cost") of the solution's problem at every
    node, kept with the solution (a 4-D grid has millions of nodes)."""
    key = f"{cost}_nodes"
    if key not in solution._cache:
        problem = solution.problem
        values = {
            "state_cost": problem.state_cost_values,
            "terminal": problem.terminal_values,
            "exit_cost": problem.exit_values,
        }[cost]
        solution._cache[key] = problem.grid.node_values(values)
    return solution._cache[key]
