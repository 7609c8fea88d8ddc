"""An independent check: the nonlinear HJB solved directly in value space (Kushner–Dupuis).

The optimal cost-to-go v of the control problem (paper §3.2) solves the nonlinear Hamilton–Jacobi–Bellman equation

    −∂ₜv = q + min_u [ ½ uᵀR u + (a + B u)ᵀ∇v ] + ½ tr(Σ ∇²v),   Σ = λ B R⁻¹ Bᵀ,   v(·, T) = g,

which the linear solvers only reach through z = exp(−v/λ). Here it is discretised without z and
without any of their code (no splitting, no implicit generator, no Kuhn interpolation): an explicit
Markov-chain approximation with upwinding of the controlled drift b = a + B u. With one-sided
differences δ⁺_k v = (v_{i+e_k} − v_i)/h_k, δ⁻_k v = (v_i − v_{i−e_k})/h_k and D_k = ½ Σ_kk,

    v(t) = v(t + Δt) + Δt H[v(t + Δt)],
    H[v] = q + Σ_k D_k (δ⁺_k v − δ⁻_k v)/h_k + min_u [ ½ uᵀR u + Σ_k (b_k⁺ δ⁺_k v − b_k⁻ δ⁻_k v) ],

b⁺ = max(b, 0), b⁻ = max(−b, 0). Read as transition probabilities, the step moves from node i to
i ± e_k with probability Δt (b_k^± / h_k + D_k / h_k²) and stays with the rest: a monotone scheme
(and convergent, Barles–Souganidis) as long as that rest is non-negative,

    Δt · max_i ρ_i ≤ 1,   ρ_i = Σ_k (|b_k| / h_k + 2 D_k / h_k²)   (CFL, with the minimising u).

Every step picks Δt from the current policy so that Δt max ρ ≤ ``courant`` ≤ 1. The scheme is first
order in h (the upwinding) and in Δt ∝ h.

The minimum over u is exact: each control u_j drives one axis k (R diagonal, B_kj its only
nonzero in column j, as for every built-in system), so it is a one-dimensional minimisation of
the piecewise quadratic ½ r_j u² + b_k⁺ δ⁺ − b_k⁻ δ⁻ with b_k = a_k + B_kj u. The kink b = 0
splits the u-line into two half-lines; on the one where b ≥ 0 the objective is the convex
quadratic ½ r_j u² + b δ⁺, minimised at u = −B_kj δ⁺/r_j, on the other at u = −B_kj δ⁻/r_j.

Bounded controls. With ``control_bounds`` each u_j is restricted to a box [lo_j, hi_j], and the
HJB's minimum is taken over the box,

    −∂ₜv = q + min_{lo ≤ u ≤ hi} [ ½ uᵀR u + (a + B u)ᵀ∇v ] + ½ tr(Σ ∇²v).

For diagonal R the objective separates over the controls and each one is a convex quadratic in
u_j, so the constrained minimiser is the unconstrained one clipped to the box,
u*_j = clip(−(Bᵀ∇v)_j / r_j, lo_j, hi_j): that is what :meth:`HJBSolution.policy` returns. In
the discrete Hamiltonian each branch's minimiser is clipped to (its half-line ∩ the box), which is
again exact. Only the optimisation is bounded: the noise keeps its covariance Σ = λ B R⁻¹ Bᵀ,
so with bounds the problem is no longer linearly solvable (no z-space counterpart). A
non-diagonal R couples the controls (the box minimiser is then not the clipped one) and is
refused, bounded or not.

Boundaries: periodic axes wrap; on a closed axis the transitions out of the box are
suppressed (δ⁻ = 0 at the lower end, δ⁺ = 0 at the upper end: a reflecting state constraint).

First exit (``horizon=None`` with an exit set E, SPEC §9). The stationary HJB

    0 = q + min_u [ ½ uᵀR u + (a + B u)ᵀ∇v ] + ½ tr(Σ ∇²v)  off E,      v = g_E on E,

is solved on the same controlled Markov chain by policy iteration (Howard): for the current
control, the chain's jump rates r_ij (those of the explicit step above, divided by Δt) give the
*linear* equation Σ_j r_ij (v_j − v_i) + q_i + ½ uᵢᵀR uᵢ = 0 at the nodes off E, with v = g_E at
the nodes of E, solved by sparse LU; the control is then replaced by the kernel's exact minimiser
against the new v, and the two steps repeat until the control no longer changes (to ``tol`` in
v). Each step can only lower v (monotone convergence), and the fixed point is the discrete HJB's
solution, the steady state of the time march (which ``solve_hjb(..., method="march")`` runs, as a
cross-check). The exit set is on the nodes (first order in its position). The controls start at
zero: a problem in which some nodes reach neither E nor q > 0 under that control is refused
(the linear system would be singular there).

Evaluation anywhere: v by multilinear (tensor-product) interpolation of the nodal values, linear
in time between stored slices; the policy u* = −R⁻¹ B(x)ᵀ ∇v from nodal central differences of v
(one-sided at the ends of a closed axis), interpolated the same way.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .._numba import jit
from ..accuracy.assessment import DEFAULT_TOLERANCE, QUANTILE
from ..accuracy.estimate import relative_error
from ..accuracy.grids import embedded_grid
from ..accuracy.matter import states_that_matter
from ..errors import ResolutionWarning, warn_user
from ..grid import Grid
from ..problem import Problem, bracket, check_time, state_evaluation


@jit
def hamiltonian_kernel(
    v,
    drift,
    gain,
    control_axis,
    r,
    bounds,
    diffusion,
    q,
    shape,
    strides,
    spacing,
    periodic,
    out,
    rate,
    control,
):
    """H[v] and the jump rate ρ at every node, and the minimising control (see module docstring).

    ``gain[i, j]`` is B_kj at node i for the axis k = ``control_axis[j]``; axes without a control
    (``control_of_axis`` −1) are advected by the passive drift alone. ``bounds[j]`` is the box
    [lo_j, hi_j] of control j (±∞ when unbounded).
    """
    n_nodes, d = drift.shape
    m = gain.shape[1]
    control_of_axis = np.full(d, -1)
    for j in range(m):
        control_of_axis[control_axis[j]] = j
    for p in range(n_nodes):
        total = q[p]
        rho = 0.0
        for k in range(d):
            n = shape[k]
            s = strides[k]
            h = spacing[k]
            i = (p // s) % n
            if periodic[k]:
                up = p + s if i < n - 1 else p - (n - 1) * s
                down = p - s if i > 0 else p + (n - 1) * s
                forward = (v[up] - v[p]) / h
                backward = (v[p] - v[down]) / h
            else:
                forward = (v[p + s] - v[p]) / h if i < n - 1 else 0.0
                backward = (v[p] - v[p - s]) / h if i > 0 else 0.0
            total += diffusion[p, k] * (forward - backward) / h
            rho += 2.0 * diffusion[p, k] / (h * h)
            a = drift[p, k]
            j = control_of_axis[k]
            if j < 0:
                b = a
                best = max(b, 0.0) * forward - max(-b, 0.0) * backward
            else:
                lo, hi = bounds[j, 0], bounds[j, 1]
                beta = gain[p, j]
                if beta == 0.0:
                    # the control moves nothing: minimise ½ r u² over the box alone
                    u_best = min(max(0.0, lo), hi)
                    b = a
                    best = (
                        0.5 * r[j] * u_best * u_best
                        + max(b, 0.0) * forward
                        - max(-b, 0.0) * backward
                    )
                else:
                    # Branch b ≥ 0 is the half-line of u on one side of the kink −a/β, branch
                    # b ≤ 0 the other; on each, the objective is a convex quadratic, so its
                    # minimum over (half-line ∩ box) is its unconstrained minimiser clipped.
                    kink = -a / beta
                    best = np.inf
                    u_best = 0.0
                    for branch in range(2):
                        slope = forward if branch == 0 else backward
                        if (branch == 0) == (beta > 0.0):
                            low, high = max(kink, lo), hi  # u ≥ kink
                        else:
                            low, high = lo, min(kink, hi)  # u ≤ kink
                        if low <= high:
                            u = min(max(-beta * slope / r[j], low), high)
                            b = a + beta * u
                            f = 0.5 * r[j] * u * u + max(b, 0.0) * forward - max(-b, 0.0) * backward
                            if f < best:
                                best, u_best = f, u
                    b = a + beta * u_best
                control[p, j] = u_best
            total += best
            rho += abs(b) / h
        out[p] = total
        rate[p] = rho


@jit
def _multilinear_kernel(values, x, lo, spacing, shape, strides, periodic, out):
    """Tensor-product linear interpolation of nodal ``values`` (K, N) at states ``x`` (P, d)."""
    n_points, d = x.shape
    n_rows = values.shape[0]
    for p in range(n_points):
        low = np.empty(d, dtype=np.int64)
        high = np.empty(d, dtype=np.int64)
        frac = np.empty(d)
        for k in range(d):
            n = shape[k]
            s = (x[p, k] - lo[k]) / spacing[k]
            if periodic[k]:
                s = s - n * np.floor(s / n)
                i = min(int(np.floor(s)), n - 1)
                low[k] = i
                high[k] = i + 1 if i < n - 1 else 0
            else:
                s = min(max(s, 0.0), n - 1.0)
                i = min(int(np.floor(s)), n - 2)
                low[k] = i
                high[k] = i + 1
            frac[k] = s - i
        for r_ in range(n_rows):
            out[r_, p] = 0.0
        for corner in range(1 << d):
            w = 1.0
            node = 0
            for k in range(d):
                if (corner >> k) & 1:
                    w *= frac[k]
                    node += high[k] * strides[k]
                else:
                    w *= 1.0 - frac[k]
                    node += low[k] * strides[k]
            if w != 0.0:
                for r_ in range(n_rows):
                    out[r_, p] += w * values[r_, node]


def multilinear(grid: Grid, values, x) -> np.ndarray:
    """Multilinear interpolation of nodal ``values`` ``(K, size)`` at states ``x`` ``(P, d)``.

    Periodic axes wrap, closed axes clamp the state to the box. Returns ``(K, P)``.
    """
    x = grid.check_states(x)
    values = np.ascontiguousarray(np.atleast_2d(values), dtype=float)
    if values.shape[-1] != grid.size:
        raise ValueError(f"values must have {grid.size} nodal entries, got shape {values.shape}")
    _, spacing, shape, strides, periodic = grid.kernel_arrays()
    out = np.empty((values.shape[0], x.shape[0]))
    _multilinear_kernel(
        values, np.ascontiguousarray(x), grid.lo, spacing, shape, strides, periodic, out
    )
    return out


def value_gradient(grid: Grid, values: np.ndarray) -> np.ndarray:
    """∇v at every node, shape ``(d, size)``: central differences, wrapped on periodic axes and
    one-sided at the ends of closed axes."""
    field = grid.reshape(np.asarray(values, dtype=float))
    grads = []
    for k, ax in enumerate(grid.axes):
        h = ax.spacing
        if ax.periodic:
            grads.append((np.roll(field, -1, axis=k) - np.roll(field, 1, axis=k)) / (2 * h))
        else:
            grads.append(np.gradient(field, h, axis=k, edge_order=1))
    return np.stack([g.ravel() for g in grads])


@dataclass(frozen=True)
class ControlStructure:
    """Which axis each control drives and its gain B_kj at the nodes, for the exact minimisation,
    and the box each control is minimised over."""

    axis: np.ndarray  # (m,) int
    gain: np.ndarray  # (N, m)
    r: np.ndarray  # (m,) diagonal of R
    bounds: np.ndarray  # (m, 2): lo_j, hi_j (±inf when unbounded)


def control_box(control_bounds, m: int) -> np.ndarray:
    """``control_bounds`` as an ``(m, 2)`` array of [lo_j, hi_j], checked.

    Accepts ``None`` (unbounded: ±∞), one pair ``(lo, hi)`` for every control, or one pair per
    control (shape ``(m, 2)``); ``±np.inf`` leaves a side open.
    """
    if control_bounds is None:
        return np.tile([-np.inf, np.inf], (m, 1))
    try:
        box = np.array(control_bounds, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(
            f"control_bounds must be a pair (lo, hi) or one pair per control, got {control_bounds!r}"
        ) from None
    if box.shape == (2,):
        box = np.tile(box, (m, 1))
    if box.shape != (m, 2):
        raise ValueError(
            f"control_bounds must be one pair (lo, hi) for all {m} control(s) or shape ({m}, 2), "
            f"one pair per control; got shape {box.shape}"
        )
    if np.any(np.isnan(box)) or np.any(box[:, 0] == np.inf) or np.any(box[:, 1] == -np.inf):
        raise ValueError(
            f"control_bounds must be numbers (±inf for an open side), got {box.tolist()}"
        )
    if np.any(box[:, 0] > box[:, 1]):
        j = int(np.flatnonzero(box[:, 0] > box[:, 1])[0])
        raise ValueError(
            f"control_bounds for control {j} has lo > hi ({box[j, 0]:g} > {box[j, 1]:g}): "
            "give (lo, hi) with lo ≤ hi"
        )
    return box


def control_structure(problem: Problem, x: np.ndarray, control_bounds=None) -> ControlStructure:
    """Check that each control drives its own axis with a diagonal R, and return the structure
    with the box of ``control_bounds`` (see :func:`control_box`)."""
    R = problem.R
    if np.any(np.diag(np.diag(R)) != R):
        raise ValueError(
            "solve_hjb minimises over each control separately and needs a diagonal control_cost R "
            "(with control_bounds, the box minimiser is the clipped unconstrained one only then); "
            "rotate the controls to diagonalise R"
        )
    B = np.asarray(problem.system.input_matrix(x), dtype=float)
    used = np.any(B != 0, axis=0)  # (d, m)
    axis = np.argmax(used, axis=0)
    if np.any(used.sum(axis=0) > 1) or len(set(axis.tolist())) < axis.size:
        raise ValueError(
            "solve_hjb needs each control to drive its own state axis (B with one nonzero row per "
            "column, distinct rows), as every built-in system does; change coordinates so that it "
            "does (e.g. canonical momenta)"
        )
    gain = np.ascontiguousarray(B[:, axis, np.arange(axis.size)])
    return ControlStructure(
        axis.astype(np.int64),
        gain,
        np.ascontiguousarray(np.diag(R)),
        control_box(control_bounds, axis.size),
    )


def hamiltonian_numpy(
    problem: Problem, v: np.ndarray, control_bounds=None
) -> tuple[np.ndarray, np.ndarray]:
    """Plain-numpy H[v] and ρ of the module docstring, for testing the compiled kernel.

    Minimises over each control by brute force over candidate points that contain the minimiser:
    the kink and both branch minimisers, each clipped to the box, and the box's finite ends.
    """
    grid = problem.require_grid("hamiltonian_numpy()")
    x = grid.nodes()
    drift = np.asarray(problem.system.drift(x), dtype=float)
    diffusion = 0.5 * problem.noise_diagonal(x)
    structure = control_structure(problem, x, control_bounds)
    field = grid.reshape(v)
    H = problem.state_cost_values(x).copy()
    rate = np.zeros(grid.size)
    for k, ax in enumerate(grid.axes):
        h = ax.spacing
        if ax.periodic:
            forward = (np.roll(field, -1, axis=k) - field) / h
            backward = (field - np.roll(field, 1, axis=k)) / h
        else:
            forward = np.diff(field, axis=k, append=np.take(field, [-1], axis=k)) / h
            backward = np.diff(field, axis=k, prepend=np.take(field, [0], axis=k)) / h
        forward, backward = forward.ravel(), backward.ravel()
        H += diffusion[:, k] * (forward - backward) / h
        rate += 2 * diffusion[:, k] / h**2
        a = drift[:, k]
        controls = np.flatnonzero(structure.axis == k)
        if controls.size == 0:
            candidates = np.zeros((1, grid.size))
            beta, r = np.zeros(grid.size), 1.0
        else:
            j = controls[0]
            beta, r = structure.gain[:, j], structure.r[j]
            with np.errstate(divide="ignore", invalid="ignore"):
                kink = np.where(beta != 0, -a / beta, 0.0)
            lo, hi = structure.bounds[j]
            inner = np.clip([kink, -beta * forward / r, -beta * backward / r], lo, hi)
            ends = [np.full(grid.size, end) if np.isfinite(end) else inner[0] for end in (lo, hi)]
            candidates = np.concatenate([inner, ends])
        b = a + beta * candidates
        f = 0.5 * r * candidates**2 + np.maximum(b, 0) * forward - np.maximum(-b, 0) * backward
        best = np.argmin(f, axis=0)
        H += np.take_along_axis(f, best[None], axis=0)[0]
        rate += np.abs(np.take_along_axis(b, best[None], axis=0)[0]) / h
    return H, rate


@dataclass(frozen=True)
class HJBDiagnostics:
    """What :func:`solve_hjb` did.

    Attributes
    ----------
    method : str
        The time stepping used.
    dt : float
        The mean step T/steps.
    min_step, max_step : float
        The smallest and largest step taken.
    steps : int
        How many steps.
    courant : float
        The bound on Δt·max ρ the steps kept to.
    wall_time : float
        Seconds."""

    method: str
    dt: float
    min_step: float
    max_step: float
    steps: int
    courant: float
    wall_time: float


@dataclass(frozen=True, eq=False)
class HJBSolution:
    """The value-space solution of a :class:`gridlbc.Problem`: v at stored times, anywhere in x.

    Attributes
    ----------
    problem : Problem
    times : ndarray (S,)
        Stored times, increasing from 0 to T.
    values : ndarray (S, N)
        Nodal v at those times.
    diagnostics : HJBDiagnostics
    control_bounds : ndarray (m, 2)
        The box [lo_j, hi_j] each control was minimised over (±inf: unbounded).
    coarse : HJBSolution or None
        The same problem solved on the grid with every other node, which
        :meth:`error_estimate` reads (None: ``error_estimate=False``, or a grid or exit set too
        coarse for it).
    """

    problem: Problem
    times: np.ndarray
    values: np.ndarray
    diagnostics: HJBDiagnostics
    control_bounds: np.ndarray
    coarse: HJBSolution | None = None

    @property
    def grid(self) -> Grid:
        return self.problem.require_grid("an HJBSolution")

    def _nodal_at(self, t) -> np.ndarray:
        if self.problem.stationary:
            return self.values[0]  # a first-exit solution does not depend on time
        if t is None:
            raise TypeError(
                "this solution has a horizon: give the time t (value(x, t), policy(x, t))"
            )
        j, theta = bracket(
            self.times, check_time(t, self.problem.require_horizon("an HJBSolution"))
        )
        return (1 - theta) * self.values[j] + theta * self.values[j + 1]

    @state_evaluation
    def value(self, x, t=None) -> np.ndarray:
        """v(x, t), shape ``(N,)`` (a scalar for one state ``(d,)``); ``t`` is required with a
        horizon and ignored for a first-exit solution."""
        return multilinear(self.grid, self._nodal_at(t), x)[0]

    def value_nodes(self, j: int = 0) -> np.ndarray:
        """v at every node of stored slice ``j`` (time ``times[j]``), as
        :meth:`gridlbc.Solution.value_nodes` (what :func:`gridlbc.accuracy.states_that_matter`
        reads).

        Parameters
        ----------
        j : int
            The stored slice.
        """
        return self.values[j]

    @state_evaluation
    def error_estimate(self, x, t=None) -> np.ndarray:
        """abs(v_h(x, t) − v_2h(x, t)), the solve's difference from its solve on the grid with
        every other node (:attr:`coarse`): its error v_h − v* to first order in h, the order of
        the scheme (module docstring), shape ``(N,)`` (a scalar for one state ``(d,)``)."""
        if self.coarse is None:
            raise ValueError(
                "this solution carries no error estimate: it was solved with "
                "error_estimate=False, or its grid or exit set was too coarse for the grid with "
                "every other node (solve_hjb warned so); solve it again with error_estimate=True "
                "on a finer grid, or certify the values you need (gridlbc.certify)"
            )
        return np.abs(self.value(x, t) - self.coarse.value(x, t))

    @state_evaluation
    def gradient(self, x, t=None) -> np.ndarray:
        """∇v(x, t) from interpolated nodal central differences, shape ``(N, d)`` (``(d,)`` for one
        state)."""
        return multilinear(self.grid, value_gradient(self.grid, self._nodal_at(t)), x).T

    @state_evaluation
    def policy(self, x, t=None) -> np.ndarray:
        """u*(x, t) = clip(−R⁻¹ B(x)ᵀ ∇v(x, t), lo, hi), shape ``(N, m)`` (``(m,)`` for one state).

        The minimiser of ½ uᵀRu + uᵀBᵀ∇v over the box ``control_bounds`` (R is diagonal, so
        clipping each control is exact); without bounds, the unconstrained −R⁻¹Bᵀ∇v.
        """
        x = self.grid.check_states(x)
        B = np.asarray(self.problem.system.input_matrix(self.grid.clamp(x)), dtype=float)
        u = -np.einsum("nkm,nk->nm", B, self.gradient(x, t)) @ self.problem.R_inv.T
        return np.clip(u, self.control_bounds[:, 0], self.control_bounds[:, 1])


def _hamiltonian(grid: Grid, structure, drift, diffusion, q):
    """``hamiltonian(v, H, rate, control)``: :func:`hamiltonian_kernel` of this grid, control
    structure, drift, diffusion and state cost, writing H, the step's rate and the minimising
    control in place."""
    _, spacing, shape, strides, periodic = grid.kernel_arrays()

    def hamiltonian(v, H, rate, control):
        hamiltonian_kernel(
            v,
            drift,
            structure.gain,
            structure.axis,
            structure.r,
            structure.bounds,
            diffusion,
            q,
            shape,
            strides,
            spacing,
            periodic,
            H,
            rate,
            control,
        )

    return hamiltonian


def solve_hjb(
    problem: Problem,
    dt: float | None = None,
    control_bounds=None,
    *,
    courant: float = 0.9,
    slices: int = 50,
    method: str | None = None,
    tol: float = 1e-10,
    max_iterations: int = 500,
    error_estimate: bool = True,
) -> HJBSolution:
    """Solve the nonlinear HJB of ``problem`` in value space, backward from v(T) = g, or, for a
    first-exit problem (``horizon=None``), its stationary equation (module docstring).

    The scheme is first order in h: with ``error_estimate`` (the default) the same problem is
    also solved on the grid with every other node, v_h − v* ≈ v_2h − v_h is read by
    :meth:`HJBSolution.error_estimate`, and a :class:`gridlbc.ResolutionWarning` says where it
    exceeds :data:`gridlbc.accuracy.DEFAULT_TOLERANCE` of abs(v) at more than a tenth of the
    nodes (the coarser solve costs about 2⁻⁽ᵈ⁺¹⁾ of this one where Δt ∝ h, less where the
    noise sets Δt ∝ h²).

    Parameters
    ----------
    problem : Problem
        Any problem whose controls each drive their own axis with a diagonal R (all built-in
        systems); the same grid and boundary conventions as :func:`gridlbc.solve`.
    dt : float, optional
        Largest time step. Each explicit step is further limited by the CFL condition
        Δt max ρ ≤ ``courant`` of the current policy, so ``None`` means "as the CFL allows".
    control_bounds : (lo, hi) or array (m, 2), optional
        Bound the controls: u is minimised over the box lo ≤ u ≤ hi (one pair for every
        control, or one per control; ``±np.inf`` leaves a side open). ``None``: unbounded.
        The noise is unchanged (covariance λ B R⁻¹ Bᵀ), so a bounded problem has no z-space
        counterpart: this solver is then the library's way to solve it.
    courant : float
        In (0, 1]: the fraction of the monotonicity limit used.
    slices : int
        Number of stored time intervals (uniform in t, values linear in t between them).
    method : str, optional
        First exit only: ``"policy"`` (default), policy iteration with a sparse solve per
        iteration; ``"march"``, the explicit time march (the steps above, ``dt`` and
        ``courant`` apply) until the value stops changing, a cross-check.
    tol : float
        First exit only: stop when no nodal value changes by more than ``tol`` · (1 + max ``|v|``)
        in an iteration (policy iteration), or per unit time (march).
    max_iterations : int
        First exit only: the most policy iterations (× 10⁵ time steps for the march).
    error_estimate : bool
        Also solve on the grid with every other node, for :meth:`HJBSolution.error_estimate`
        and the warning (above); False: neither.

    Returns
    -------
    HJBSolution
        ``value(x, t)``, ``policy(x, t)``, ``error_estimate(x, t)``, ``times``,
        ``diagnostics``.
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a gridlbc.Problem, got {type(problem).__name__}")
    if dt is not None and not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be positive and finite (or None for the CFL limit), got {dt}")
    if not 0 < courant <= 1:
        raise ValueError(f"courant must lie in (0, 1] for a monotone scheme, got {courant}")
    if isinstance(slices, bool) or not isinstance(slices, (int, np.integer)) or slices < 1:
        raise ValueError(f"slices must be a positive integer, got {slices!r}")
    if problem.average_cost:
        raise ValueError(
            "solve_hjb solves problems with a horizon or an exit set, not average cost"
        )
    if problem.horizon is not None and method is not None:
        raise ValueError(
            f"method={method!r} applies to first-exit problems (horizon=None); this one has a "
            "horizon and is marched backward from T"
        )

    def solve_on(on: Problem, step: float | None) -> HJBSolution:
        if on.horizon is None:
            return _solve_first_exit(
                on, step, control_bounds, courant, method or "policy", tol, max_iterations
            )
        return _march(on, step, control_bounds, courant, slices)

    solution = solve_on(problem, dt)
    return _estimated(solution, solve_on, dt) if error_estimate else solution


def _march(problem: Problem, dt, control_bounds, courant: float, slices: int) -> HJBSolution:
    """The explicit march of :func:`solve_hjb` backward from v(T) = g (module docstring)."""
    started = time.perf_counter()
    grid = problem.require_grid("solve_hjb")
    x = grid.nodes()
    structure = control_structure(problem, x, control_bounds)
    drift = np.ascontiguousarray(problem.system.drift(x), dtype=float)
    diffusion = np.ascontiguousarray(0.5 * problem.noise_diagonal(x))
    q = problem.state_cost_values(x)
    hamiltonian = _hamiltonian(grid, structure, drift, diffusion, q)
    T = problem.require_horizon("solve_hjb")
    max_step = T if dt is None else min(float(dt), T)

    v = problem.terminal_values(x).copy()
    values = np.empty((slices + 1, grid.size))
    values[slices] = v
    H = np.empty(grid.size)
    rate = np.empty(grid.size)
    control = np.empty((grid.size, structure.axis.size))
    steps, smallest, largest = 0, math.inf, 0.0
    interval = T / slices
    for j in range(slices - 1, -1, -1):
        remaining = interval
        while remaining > 1e-12 * interval:
            hamiltonian(v, H, rate, control)
            limit = min(max_step, courant / max(rate.max(), 1e-300))
            n_sub = max(1, math.ceil(remaining / limit - 1e-9))
            step = remaining / n_sub
            v += step * H
            remaining -= step
            steps += 1
            smallest, largest = min(smallest, step), max(largest, step)
        if not np.all(np.isfinite(v)):
            raise FloatingPointError(f"the HJB value became non-finite at t = {j * interval:g}")
        values[j] = v
    diagnostics = HJBDiagnostics(
        method="markov-chain",
        dt=T / steps,
        min_step=smallest,
        max_step=largest,
        steps=steps,
        courant=courant,
        wall_time=time.perf_counter() - started,
    )
    times = np.linspace(0.0, T, slices + 1)
    return HJBSolution(problem, times, values, diagnostics, structure.bounds)


def _estimated(solution: HJBSolution, solve_on, dt) -> HJBSolution:
    """``solution`` with its solve on the grid with every other node
    (:func:`gridlbc.accuracy.embedded_grid`, by ``solve_on(problem, step)``, the largest step
    doubled where one was given), which :meth:`HJBSolution.error_estimate` reads; and a
    :class:`gridlbc.ResolutionWarning` where that estimate exceeds
    :data:`~gridlbc.accuracy.DEFAULT_TOLERANCE` relative to max(abs(v), λ) at more than
    1 − :data:`~gridlbc.accuracy.assessment.QUANTILE` of the states that matter (every node whose
    value at t = 0 is finite and that is not in the exit set, as a default solve is judged:
    :func:`gridlbc.accuracy.states_that_matter`), or where there is no estimate to read.

    Why: the scheme is first order in h (and in Δt ∝ h), so v_h − v* ≈ v_2h − v_h, and a
    reference that is 13 % off on a 41² point mass said nothing (API journey round 1)."""
    problem, grid = solution.problem, solution.grid
    coarse_grid = embedded_grid(grid)
    coarse, reason = None, ""
    if coarse_grid is None:
        reason = f"the grid {grid.shape} is too coarse to embed the grid with every other node"
    else:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the coarser solve's own are not the user's
                coarse = solve_on(problem.replace(grid=coarse_grid), None if dt is None else 2 * dt)
        except (ValueError, FloatingPointError) as error:  # never fail the solve it checks
            reason = f"the problem cannot be solved on the grid with every other node ({error})"
    solution = dataclasses.replace(solution, coarse=coarse)
    if coarse is None:
        warn_user(
            f"solve_hjb: no error estimate, {reason}: the value, first order in h, may be far off "
            "on so few nodes; give a finer grid (docs page 'schemes')",
            ResolutionWarning,
        )
        return solution
    x = states_that_matter(solution)
    if len(x) == 0:
        return solution
    t = None if problem.stationary else 0.0
    rel = relative_error(solution.error_estimate(x, t), solution.value(x, t), problem.temperature)
    quantile = float(np.quantile(rel, QUANTILE))
    if quantile > DEFAULT_TOLERANCE:
        warn_user(
            f"solve_hjb's estimated error of v exceeds {DEFAULT_TOLERANCE:.0%} of max(|v|, λ) at "
            f"{np.mean(rel > DEFAULT_TOLERANCE):.0%} of the nodes ({QUANTILE:.0%} of them are "
            f"within {quantile:.1%}): the scheme is first order in h, and its difference from the "
            "solve on the grid with every other node is its error to that order (see "
            "solution.error_estimate(x, t)). Give a finer grid: halving h about halves the error "
            "(docs page 'schemes')",
            ResolutionWarning,
        )
    return solution


FIRST_EXIT_METHODS = ("policy", "march")
"""How :func:`solve_hjb` solves a first-exit problem (its ``method``)."""


def controlled_chain(
    problem: Problem,
    structure: ControlStructure,
    drift: np.ndarray,
    diffusion: np.ndarray,
    control: np.ndarray,
) -> sp.csr_matrix:
    """The jump rates of the explicit scheme's chain under ``control`` ``(N, m)`` as a sparse
    matrix W (W_ij = rate i → j, zero diagonal): along axis k, to i ± e_k at
    b_k^± / h_k + D_k / h_k² with b = a + B u; periodic axes wrap, and a jump out of a closed
    axis is dropped (module docstring)."""
    grid = problem.require_grid("the controlled chain")
    flat = np.arange(grid.size)
    multi = np.unravel_index(flat, grid.shape)
    rows, cols, values = [], [], []
    for k, ax in enumerate(grid.axes):
        h, s = ax.spacing, int(grid.strides[k])
        b = drift[:, k].copy()
        for j in np.flatnonzero(structure.axis == k):
            b += structure.gain[:, j] * control[:, j]
        for sign in (1, -1):
            rate = np.maximum(sign * b, 0.0) / h + diffusion[:, k] / h**2
            target = multi[k] + sign
            if ax.periodic:
                keep = np.ones(grid.size, dtype=bool)
                to = flat + s * (np.mod(target, ax.n) - multi[k])
            else:
                keep = (target >= 0) & (target < ax.n)
                to = flat + sign * s
            keep &= rate > 0
            rows.append(flat[keep])
            cols.append(to[keep])
            values.append(rate[keep])
    entries = (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols)))
    return sp.coo_matrix(entries, shape=(grid.size, grid.size)).tocsr()


def _solve_first_exit(
    problem: Problem, dt, control_bounds, courant, method, tol, max_iterations
) -> HJBSolution:
    """The stationary first-exit HJB of :func:`solve_hjb` by policy iteration or the march
    (module docstring)."""
    started = time.perf_counter()
    if method not in FIRST_EXIT_METHODS:
        raise ValueError(
            f"method must be one of {', '.join(FIRST_EXIT_METHODS)} for a first-exit problem, "
            f"got {method!r}"
        )
    if not (0 < tol < 1):
        raise ValueError(f"tol must lie in (0, 1), got {tol}")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, (int, np.integer)):
        raise ValueError(f"max_iterations must be a positive integer, got {max_iterations!r}")
    if max_iterations < 1:
        raise ValueError(f"max_iterations must be a positive integer, got {max_iterations!r}")
    grid = problem.require_grid("solve_hjb")
    x = grid.nodes()
    structure = control_structure(problem, x, control_bounds)
    drift = np.ascontiguousarray(problem.system.drift(x), dtype=float)
    diffusion = np.ascontiguousarray(0.5 * problem.noise_diagonal(x))
    E = problem.exit_mask()
    if not E.any() or E.all():
        raise ValueError(
            f"the exit set {problem.exit!r} contains {'every' if E.any() else 'no'} node of the "
            f"grid ({grid.describe()}): solve_hjb places it on the nodes; move, widen or shrink "
            "it, or refine the grid"
        )
    q = np.where(E, 0.0, problem.state_cost_values(x))
    hamiltonian = _hamiltonian(grid, structure, drift, diffusion, q)
    v = np.zeros(grid.size)
    v[E] = problem.exit_values(x[E])
    H = np.empty(grid.size)
    rate = np.empty(grid.size)
    control = np.zeros((grid.size, structure.axis.size))
    lo, hi = structure.bounds[:, 0], structure.bounds[:, 1]
    control[:] = np.clip(0.0, lo, hi)

    def greedy(v):
        hamiltonian(v, H, rate, control)

    interior = np.flatnonzero(~E)
    steps, smallest, largest = 0, math.inf, 0.0
    converged = False
    if method == "policy":
        for steps in range(1, max_iterations + 1):
            W = controlled_chain(problem, structure, drift, diffusion, control)
            cost = q + 0.5 * (control**2) @ structure.r
            total = np.asarray(W.sum(axis=1)).ravel()
            A = (sp.diags(total) - W).tocsr()[interior]
            rhs = cost[interior] - A[:, np.flatnonzero(E)] @ v[E]
            scale = np.where(total[interior] > 0, total[interior], 1.0)
            A_II = (sp.diags(1.0 / scale) @ A[:, interior]).tocsc()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("error", spla.MatrixRankWarning)
                    new = spla.splu(A_II).solve(rhs / scale)
            except (RuntimeError, spla.MatrixRankWarning):
                new = np.full(interior.size, np.nan)
            if not np.all(np.isfinite(new)):
                raise ValueError(
                    "under the current control some nodes reach the exit set only with "
                    "probability < 1 and pay no state cost: the first-exit value is undefined "
                    "there. Give a state cost q > 0, noise, or an exit set every state can reach"
                )
            change = np.abs(new - v[interior]).max() if steps > 1 else np.inf
            v[interior] = new
            greedy(v)
            if change <= tol * (1.0 + np.abs(v).max()):
                converged = True
                break
    else:  # the explicit march to steady state: the cross-check
        max_step = np.inf if dt is None else float(dt)
        while steps < 100_000 * max_iterations:
            steps += 1
            greedy(v)
            step = min(max_step, courant / max(rate[~E].max(), 1e-300))
            smallest, largest = min(smallest, step), max(largest, step)
            speed = np.abs(H[interior]).max()
            v[interior] += step * H[interior]
            if speed <= tol * (1.0 + np.abs(v).max()):
                converged = True
                break
        if not np.all(np.isfinite(v)):
            raise FloatingPointError("the HJB value became non-finite while marching")
    if not converged:
        warn_user(
            f"solve_hjb's first-exit {method} did not converge to tol={tol:g} in {steps} "
            "iterations: the value is the last iterate",
            RuntimeWarning,
        )
    diagnostics = HJBDiagnostics(
        method="policy-iteration" if method == "policy" else "markov-chain-march",
        dt=0.0,
        min_step=0.0 if method == "policy" else smallest,
        max_step=0.0 if method == "policy" else largest,
        steps=steps,
        courant=0.0 if method == "policy" else courant,
        wall_time=time.perf_counter() - started,
    )
    return HJBSolution(problem, np.zeros(1), v[None, :].copy(), diagnostics, structure.bounds)
