"""Backward time stepping of the linear Bellman PDE: :func:`solve` and :func:`solve_many`.

From the terminal data z(·, T) = exp(−g/λ) a step operator S (a monotone linear map, see
:mod:`gridlbc.schemes.splitting` and :mod:`gridlbc.schemes.implicit`) is applied n = T/Δt times,

    z(·, t − Δt) = S z(·, t).

To keep z in range every slice is renormalised, z = Z e^ℓ with max Z = 1: the scale ℓ is carried
exactly in the log domain, so nothing underflows as a whole and linear combinations stay exact.
Nodes whose Z underflows to zero are counted in the diagnostics (their value is +∞).

Here: the time grid, the fitting reference and the loop. How to solve is
:mod:`gridlbc.settings`; where the slices live (memory check, storage) is :mod:`gridlbc.storage`.
"""

from __future__ import annotations

import hashlib
import math
import time
import warnings

import numpy as np

from ._numba import jit, work_blocks
from .problem import Problem
from .progress import ProgressBar
from .schemes import METHODS
from .schemes.splitting import (
    _TINY,
    SplittingStep,
    _diffusion_coefficients,
    _flat_chunks,
    _node_values,
)
from .settings import (
    FITTED_COURANT,
    FITTED_MIN_STEPS,
    PLAIN_COURANT,
    PLAIN_MIN_STEPS,
    SolverSettings,
    is_own_reference,
    resolve_settings,
)
from .solution import FittingReference, ResolutionWarning, Solution, SolveDiagnostics
from .storage import check_memory, memory_estimate, slice_storage, store_kernel


def courant_rates(problem: Problem) -> tuple[float, float]:
    """The Courant rates (1/time) of the drift: the maximum over the nodes of
    ``r(x) = max_k |a_k(x)| / h_k`` and its root mean square over them (in chunks of nodes)."""
    grid = problem.grid
    spacing = np.asarray(grid.spacing, dtype=float)
    peak, squares = 0.0, 0.0
    for flat in _flat_chunks(grid.size):
        drift = np.asarray(problem.system.drift(grid.node_coordinates(flat)), dtype=float)
        chunk_peak, chunk_squares = _rate_sums(drift, spacing)
        peak, squares = max(peak, chunk_peak), squares + chunk_squares
    if math.isnan(squares):
        raise ValueError("the system's drift is NaN at some nodes: check system.drift on the grid")
    return peak, math.sqrt(squares / grid.size)


@jit
def _rate_sums(drift, spacing):
    """max over the rows of r = max_k |drift_k| / spacing_k, and the sum of r² (NaN if any
    drift is NaN)."""
    peak, squares = 0.0, 0.0
    for i in range(drift.shape[0]):
        rate = 0.0
        for k in range(drift.shape[1]):
            rate = max(rate, abs(drift[i, k]) / spacing[k])
            if drift[i, k] != drift[i, k]:
                squares = math.nan
        peak = max(peak, rate)
        squares += rate * rate
    return peak, squares


def time_grid(
    problem: Problem,
    settings: SolverSettings,
    rates: tuple[float, float],
    max_step: float = math.inf,
) -> tuple[float, int]:
    """The step Δt and the number of steps n with n Δt = T; ``rates`` from :func:`courant_rates`.

    The default plain splitting step holds the largest Courant number max_x r(x) Δt at
    ``courant``; the fitted one holds the root-mean-square r Δt at ``courant``, because its
    error balances an O(h²/Δt) interpolation term against the O(Δt) splitting over the nodes
    that matter, and in 4-D the largest rate sits in far corners of the box, far above its root
    mean square. The default step is also at most ``max_step`` (for the splitting scheme
    :func:`cost_sampling_step`, where a steep state cost needs it)."""
    T = problem.horizon
    if settings.dt is not None:
        if settings.dt > T:
            raise ValueError(f"dt = {settings.dt} exceeds the horizon T = {T}")
        n = math.ceil(T / settings.dt - 1e-9)
    else:
        fitted = settings.reference is not None
        courant = (
            1.0
            if settings.method != "splitting"
            else settings.courant or (FITTED_COURANT if fitted else PLAIN_COURANT)
        )
        rate = rates[1] if fitted else rates[0]
        min_steps = settings.min_steps or (FITTED_MIN_STEPS if fitted else PLAIN_MIN_STEPS)
        n = max(
            int(min_steps),
            math.ceil(T * rate / courant - 1e-9),
            math.ceil(T / max_step - 1e-9) if max_step < math.inf else 1,
        )
    return T / n, n


def _terminal_data(problem: Problem, terminal_costs) -> tuple[np.ndarray, np.ndarray]:
    """Scaled terminal desirabilities Z (K, N), max 1 per row, and their log-scales ℓ (K,)."""
    lam = problem.temperature
    Z = np.empty((len(terminal_costs), problem.grid.size))
    scales = np.empty(len(terminal_costs))
    for r, cost in enumerate(terminal_costs):
        g = Z[r]  # g, then in place exp(−(g − min g)/λ)
        g[:] = _node_values(problem.replace(terminal_cost=cost).terminal_values, problem.grid)
        g_min = g.min()
        np.negative(np.subtract(g, g_min, out=g), out=g)
        np.divide(g, lam, out=g)
        with np.errstate(under="ignore"):
            np.exp(g, out=g)
        scales[r] = -g_min / lam
    return Z, scales


def _with_reference(problem: Problem, fitting, Z: np.ndarray, log_scale: np.ndarray):
    """Add the fitting reference φ to the terminal data ``Z`` (K, N) as row K, or point at row 0
    when a single terminal cost is its own reference. Returns ``(Z, ℓ, row, fingerprint)``:
    ``row`` is None without fitting, and the fingerprint (a digest of the scaled φ at the nodes,
    which fixes the operator) is what :func:`gridlbc.combine` compares."""
    if fitting is None:
        return Z, log_scale, None, "none"
    K = Z.shape[0]
    if is_own_reference(fitting, K):
        return Z, log_scale, 0, _fingerprint(Z[0])
    if fitting == "terminal":  # the composite h = Σ_i h_i
        top = log_scale.max()
        phi = np.exp(log_scale - top) @ Z
        peak = phi.max()
        phi, phi_scale = phi / peak, top + np.log(peak)
    else:
        phi, phi_scale = (a[0] for a in _terminal_data(problem, [fitting]))
    return np.vstack([Z, phi]), np.append(log_scale, phi_scale), K, _fingerprint(phi)


def _fingerprint(phi: np.ndarray) -> str:
    digest = hashlib.sha256(np.ascontiguousarray(phi, dtype=float).tobytes())
    return "sha256:" + digest.hexdigest()[:16]


def solve_many(problem: Problem, terminal_costs, settings=None, **options) -> list[Solution]:
    """Solve one problem for several terminal costs at once (one operator, many right-hand sides).

    ``terminal_costs`` is a sequence of callables g_i; returns one :class:`Solution` per cost,
    each exactly as :func:`solve` would return for ``problem.replace(terminal_cost=g_i)``.
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a gridlbc.Problem, got {type(problem).__name__}")
    terminal_costs = list(terminal_costs)
    if not terminal_costs:
        raise ValueError("terminal_costs is empty: give at least one terminal cost")
    s = resolve_settings(settings, options)
    grid = problem.require_grid("solve")
    problem.noise_diagonal(grid.node_coordinates([0]))  # refuse cross-diffusion before any work
    started = time.perf_counter()
    K = len(terminal_costs)
    what = f"solving on {grid.describe()}"
    # Before touching the grid: the first and last slices and the working arrays must fit.
    check_memory(memory_estimate(problem, s, 2, K), what, s.mmap_dir)
    rates = courant_rates(problem)
    rate = rates[0]
    cost_step, cost_axis = (
        cost_sampling_step(problem) if s.method == "splitting" else (math.inf, "")
    )
    dt, n_steps = time_grid(problem, s, rates, cost_step)
    if dt > cost_step * (1.0 + 1e-9):  # only a given dt can be: the default is held below it
        _warn_cost_sampling(dt, cost_step, cost_axis)
    kept = sorted(set(range(0, n_steps + 1, s.store_every)) | {n_steps})
    estimate = memory_estimate(problem, s, len(kept), K)
    check_memory(estimate, what, s.mmap_dir)

    if is_own_reference(s.reference, K) and s.method == "splitting":
        solution, diffusion = _solve_log(problem, s, kept, dt, n_steps, rate, estimate, started)
        _check_splitting([solution], diffusion, fitted=True)
        return [solution]
    Z, log_scale = _terminal_data(problem, terminal_costs)
    Z, log_scale, reference, fingerprint = _with_reference(problem, s.reference, Z, log_scale)
    options = {"linear_solver": s.linear_solver} if s.method == "implicit" else {}
    step = METHODS[s.method](problem, dt, **options)
    setup_time = time.perf_counter() - started

    slices = slice_storage((K, len(kept), grid.size), np.dtype(s.dtype), s.mmap_dir)
    scales = np.empty((len(kept), K))
    blocks = np.zeros(work_blocks(grid.size), dtype=np.int64)
    flushed = store_kernel(Z[:K], np.ones(K), slices[:, -1], blocks)
    scales[-1] = log_scale[:K]
    progress = ProgressBar(
        n_steps, s.progress, f"{s.method} {grid.describe()}", work_per_item=grid.size
    )
    log_phi = None  # the reference's log φ at the stored times (fitted)
    if reference is None:
        flushed += _march(step, Z, log_scale, kept, dt, slices, scales, blocks, progress)
    else:  # log φ at the stored times, shared by the solutions: they are evaluated relative to it
        log_phi = FittingReference(
            slice_storage((len(kept), grid.size), np.dtype(s.dtype), s.mmap_dir),
            np.empty(len(kept)),
        )
        _store_reference(Z[reference], log_scale[reference], log_phi, -1)
        flushed += _march_fitted(
            step, Z, log_scale, reference, kept, dt, slices, scales, blocks, progress, log_phi
        )
    wall = time.perf_counter() - started
    times = np.array(kept, dtype=float) * dt
    times[-1] = problem.horizon
    iterations = tuple(step.iterations)
    out = []
    for r, cost in enumerate(terminal_costs):
        diagnostics = SolveDiagnostics(
            method=s.method,
            dt=dt,
            steps=n_steps,
            store_every=s.store_every,
            wall_time=wall,
            setup_time=setup_time,
            underflow_nodes=int(np.count_nonzero(slices[r, 0] <= 0)),
            stored_bytes=int(slices[r].nbytes),
            operator_bytes=step.nbytes,
            courant=rate * dt,
            iterations=iterations,
            flushed_values=int(flushed),
            memory_estimate=estimate["ram"],
            fitting=fingerprint,
            interpolation="linear" if log_phi is None else "fitted",
        )
        out.append(
            Solution(
                problem.replace(terminal_cost=cost),
                times,
                slices[r],
                scales[:, r].copy(),
                diagnostics,
                log_phi,
            )
        )
    if reference is None:
        diffusion_step = 0.5 * dt if s.method == "splitting" else dt
        for solution in out:
            check_resolution(
                solution.problem, solution, diffusion_step, getattr(step, "diffusion", None)
            )
    if s.method == "splitting":
        _check_splitting(out, step.diffusion, fitted=reference is not None)
    return out


def _check_splitting(solutions: list[Solution], diffusion: list, fitted: bool):
    """The splitting's checks of its solutions: the control's step (:func:`check_control_step`)
    and, fitted, the resolution of log z (:func:`check_fitted_resolution`; ``diffusion`` the
    D_k per axis)."""
    for solution in solutions:
        check_control_step(solution.problem, solution)
        if fitted:
            check_fitted_resolution(solution.problem, solution, diffusion)


def _march(
    step,
    Z: np.ndarray,
    log_scale: np.ndarray,
    kept: list[int],
    dt: float,
    slices: np.ndarray,
    scales: np.ndarray,
    blocks: np.ndarray,
    progress: ProgressBar,
) -> int:
    """Apply the step operator n times from the terminal data ``Z`` (K, N) with log-scales
    ``log_scale`` (K,) (z = Z e^ℓ, renormalised lazily: the next step and the storage multiply
    by 1/peak), storing the ``kept`` steps' slices and scales (the terminal one is stored;
    ``blocks``: :func:`~gridlbc.storage.store_kernel`'s counts). Returns the number of values
    the float32 storage flushed to zero."""
    K = slices.shape[0]
    buffer = np.empty_like(Z)
    scale = np.ones(Z.shape[0])
    slot, flushed = len(kept) - 1, 0
    for n in range(kept[-1] - 1, -1, -1):  # step n+1 → n, t_n = n Δt
        peak = step(Z, buffer, scale)  # buffer = S(scale · Z), its row maxima
        Z, buffer = buffer, Z
        _check_peak(peak, n * dt)
        log_scale = log_scale + np.log(peak)
        scale = 1.0 / peak
        if n == kept[slot - 1]:
            slot -= 1
            flushed += store_kernel(Z[:K], scale[:K], slices[:, slot], blocks)
            scales[slot] = log_scale[:K]
        progress.update(kept[-1] - n)
    return flushed


def _store_reference(phi: np.ndarray, log_scale: float, log_phi: FittingReference, slot: int):
    """Slot ``slot`` of ``log_phi``: log φ relative to its maximum (floored where φ underflowed)
    and its log-scale, for φ = ``phi`` · e^{log_scale}."""
    top = float(phi.max())
    with np.errstate(divide="ignore"):
        np.log(np.maximum(phi / top, _TINY), out=log_phi.log_slices[slot], casting="unsafe")
    log_phi.log_scales[slot] = log_scale + math.log(top)


def _march_fitted(
    step: SplittingStep,
    Z: np.ndarray,
    log_scale: np.ndarray,
    reference: int,
    kept: list[int],
    dt: float,
    slices: np.ndarray,
    scales: np.ndarray,
    blocks: np.ndarray,
    progress: ProgressBar,
    log_phi: FittingReference,
) -> int:
    """:func:`_march` for the splitting fitted to row ``reference`` of ``Z``: n steps of
    C D½ M P D½ C (:class:`SplittingStep`; P fitted by :meth:`SplittingStep.drift`, D½ by
    :meth:`SplittingStep.fitted_diffusion`).

    Without a state cost (C = M = 1) the two half diffusions that meet between consecutive
    steps are one diffusion over the whole step: the Gaussian's semigroup, D½ D½ = D, which the
    fitted diffusion keeps exactly where z ∝ φ with a quadratic log φ (elsewhere the two differ
    by the interpolation half way, which the whole step skips). So n steps take n − 1 whole
    diffusions and two halves, about half the fitted diffusion's work,

        z_0 = D½ P (D P)ⁿ⁻¹ D½ z_T.

    A slice t_k (0 < k < n) then lies half way through a whole diffusion; it is stored as
    ½(y + D y), y = P …, the desirability before and after it, which is D½ y to O(Δt²) and a
    linear, non-negative function of z_T like every slice. With a state cost the two halves
    stay apart, so that the cost between them is taken half way through the diffusion, where
    Simpson's rule along the path wants it (merged, a steep cost would be sampled at the
    diffusion's ends). The reference row's log is stored in ``log_phi`` at the same times."""
    K = slices.shape[0]
    merge = step.cost_factor.size == 0
    if not merge:
        Z *= step.cost_factor
    x = step.fitted_diffusion(Z, np.empty_like(Z), reference)  # D½ C z_T
    free = [np.empty_like(Z), Z if x is not Z else np.empty_like(Z)]
    scale = np.ones(Z.shape[0])
    slot, flushed = len(kept) - 1, 0
    for n in range(kept[-1] - 1, -1, -1):
        y, other = free
        step.drift(x, y, scale, reference)  # y = MP x (x is consumed)
        if step.mid_cost_factor.size:
            y *= step.mid_cost_factor
        storing = n == kept[slot - 1]
        whole = merge and n > 0
        if whole and storing:
            np.copyto(x, y)
        result = step.fitted_diffusion(y, other, reference, full=whole)
        peak = step.row_maxima(result, cost=not merge)  # and result *= C
        _check_peak(peak, n * dt)
        if storing:
            slot -= 1
            stored, top = result, peak
            if whole:  # ½(y + D y)
                stored = x
                stored += result
                stored *= 0.5
                top = step.row_maxima(stored)
            flushed += store_kernel(stored[:K], 1.0 / top[:K], slices[:, slot], blocks)
            scales[slot] = log_scale[:K] + np.log(top[:K])
            _store_reference(stored[reference], log_scale[reference], log_phi, slot)
        log_scale = log_scale + np.log(peak)
        scale = 1.0 / peak
        if n > 0 and not merge:  # the next step opens with its own D½ C (x is free)
            result *= step.cost_factor
            result = step.fitted_diffusion(result, x, reference)
        free = [a for a in (x, y, other) if a is not result]
        x = result
        progress.update(kept[-1] - n)
    return flushed


def _check_peak(peak: np.ndarray, t: float):
    if not np.all(peak > 0) or not np.all(np.isfinite(peak)):
        raise FloatingPointError(
            f"desirability vanished or overflowed everywhere at t = {t:g}: the costs are "
            "too large for this temperature (rescale them or raise the temperature)"
        )


TAIL_SHARE = 0.01
"""A plain solve warns when more than this share of the nodes sit at its diffusion's tail cap."""


def _diffusion_tail_cap(ratio: np.ndarray) -> np.ndarray:
    """log(1/ρ) per cell of the implicit diffusion (1 + 2r) z_i − r (z_{i−1} + z_{i+1}) = b:
    its inverse decays like ρ^k, ρ = ((1 + 2r) − √(1 + 4r)) / (2r), so however fast the true
    desirability falls, the computed one falls by at most this factor of e per cell."""
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = ((1 + 2 * ratio) - np.sqrt(1 + 4 * ratio)) / (2 * ratio)
        return np.where(ratio > 0, -np.log(rho), np.inf)


COST_NOISE_SCALE = 0.5
"""A splitting solve with a state cost warns when one step's noise moves a path by more than this
fraction of the state cost's length scale along some noise axis."""


def cost_sampling_step(problem: Problem) -> tuple[float, str]:
    """The largest Δt at which one step's noise, √(2 D_k Δt), moves a path no more than
    :data:`COST_NOISE_SCALE` of the distance ℓ_k = (max q − min q) / max |∂_k q| over which the
    state cost rises (from the nodes), along every noise axis k; and the axis that sets it
    (∞ and "" without a state cost or noise). The splitting takes ∫ q dt over a step at three
    points of a path (Simpson's rule along the characteristic), so a longer step steps over a
    steep cost (a wall, a narrow well): the default step is held below this."""
    if problem.state_cost is None:
        return math.inf, ""
    grid = problem.grid
    q = grid.reshape(_node_values(problem.state_cost_values, grid))
    span = float(q.max() - q.min())
    limit, axis = math.inf, ""
    if span <= 0.0:
        return limit, axis
    for k, (ax, coefficient) in enumerate(
        zip(grid.axes, _diffusion_coefficients(problem), strict=True)
    ):
        largest = float(np.max(coefficient))
        if largest <= 0.0:
            continue
        wrapped = np.concatenate([q, q.take([0], axis=k)], axis=k) if ax.periodic else q
        rises = np.abs(np.diff(wrapped, axis=k))
        length = span * ax.spacing / max(float(rises.max()), np.finfo(float).tiny)
        step = (COST_NOISE_SCALE * length) ** 2 / (2.0 * largest)
        if step < limit:
            limit, axis = step, ax.name or f"axis {k}"
    return limit, axis


def _warn_cost_sampling(dt: float, limit: float, axis: str):
    """The :class:`ResolutionWarning` for a given ``dt`` above :func:`cost_sampling_step`."""
    warnings.warn(
        f"with Δt = {dt:.3g} one step's noise moves a path "
        f"{COST_NOISE_SCALE * math.sqrt(dt / limit):.2f} of the distance over which the state "
        f"cost rises (along {axis}), and the splitting samples that cost at three points per "
        "step: it steps over a steep cost (a wall, a narrow well), and v and the policy can be "
        f"far off. Pass dt ≤ {limit:.3g} (or leave dt to the default) and check with "
        "gridlbc.certify.",
        ResolutionWarning,
        stacklevel=4,
    )


CONTROL_STEP_CELLS = 30.0
"""A splitting solve warns when the optimal control moves the state by more than this many cells
of some axis per step (root mean square over the nodes at t = 0)."""
_CONTROL_SAMPLE = 20_000  # nodes at which check_control_step evaluates the policy


def check_control_step(problem: Problem, solution: Solution) -> float:
    """Warn (:class:`ResolutionWarning`) when the optimal control moves the state by many cells
    per step: the root mean square over the nodes (at most ``_CONTROL_SAMPLE`` of them, evenly
    spaced) at t = 0 of max_k |(B u*)_k| Δt / h_k is above :data:`CONTROL_STEP_CELLS`. The
    splitting applies the control (its diffusion) and the drift one after the other; its error
    is of order Δt², but with a cheap control (small R) that jumps the state across much of the
    grid in one step it is several percent (Pendulum-v1: README, "Limitations"). The step it
    suggests aims at two thirds of the threshold, since u* itself changes with the step.
    Returns that root mean square."""
    grid, dt = problem.grid, solution.diagnostics.dt
    x = grid.node_coordinates(np.arange(0, grid.size, max(1, grid.size // _CONTROL_SAMPLE)))
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an underflowed policy (NaN) is the caller's to hear of
        u = solution.policy(x, 0.0)
    moved = np.abs(np.einsum("nim,nm->ni", problem._input_matrix(x), u)) * dt
    cells = moved / np.asarray(grid.spacing, dtype=float)
    largest = cells.max(axis=1)
    largest = largest[np.isfinite(largest)]
    rms = float(np.sqrt(np.mean(largest**2))) if largest.size else 0.0
    if rms > CONTROL_STEP_CELLS:
        k = int(np.argmax(np.nanmean(cells**2, axis=0)))
        axis = grid.axes[k].name or f"axis {k}"
        warnings.warn(
            f"the optimal control moves the state by {rms:.0f} cells per step (root mean square "
            f"over the nodes at t = 0, mostly along {axis}): the splitting takes the control and "
            f"the drift one after the other, and at such steps v and the policy can be several "
            f"percent off (its error falls as Δt²). Pass dt ≤ "
            f"{dt * CONTROL_STEP_CELLS / (1.5 * rms):.3g} and compare.",
            ResolutionWarning,
            stacklevel=3,
        )
    return rms


FIT_CURVATURE_JUMP = 0.6
"""A fitted solve warns when the second difference of log z along a noise axis changes from one
node to the next by more than this fraction of itself (median over the cells that matter)."""
_FIT_RELEVANT = 20.0  # cells whose log z is within this of the largest at t = 0 are judged


def check_fitted_resolution(problem: Problem, solution: Solution, diffusion: list) -> float:
    """Warn (:class:`ResolutionWarning`) when the grid does not resolve the curvature of
    ℓ = log z along a noise axis, which the fitted diffusion models by a quadratic per cell:
    the median, over the cells whose ℓ at t = 0 is within ``_FIT_RELEVANT`` of its largest
    value, of |κ_{i+1} − κ_i| / (|κ_i + κ_{i+1}|/2 + 1), κ_i = ℓ_{i−1} − 2ℓ_i + ℓ_{i+1}, is
    above :data:`FIT_CURVATURE_JUMP` on some axis. A smooth ℓ keeps it near h|ℓ‴|/|ℓ″|, far
    below one; where it is of order one the quadratics bulge between nodes, and the value is
    off by far more than the scheme's order suggests and moves with Δt (README, "Limitations",
    for the calibration). ``diffusion``: the D_k per axis. Returns the largest median."""
    grid = problem.grid
    ell = -solution.value_nodes(0) / problem.temperature
    finite = np.isfinite(ell)
    top = float(ell[finite].max()) if finite.any() else 0.0
    worst, worst_axis = 0.0, ""
    for k, (ax, coefficient) in enumerate(zip(grid.axes, diffusion, strict=True)):
        if ax.n < 4 or not np.any(np.asarray(coefficient) > 0):
            continue
        lines = np.moveaxis(grid.reshape(ell), k, -1).reshape(-1, ax.n)
        kappa = lines[:, :-2] - 2.0 * lines[:, 1:-1] + lines[:, 2:]
        with np.errstate(invalid="ignore"):
            jump = np.abs(np.diff(kappa, axis=1)) / (0.5 * np.abs(kappa[:, 1:] + kappa[:, :-1]) + 1)
            judged = (lines[:, 2:-1] >= top - _FIT_RELEVANT) & np.isfinite(jump)
        if np.any(judged):
            median = float(np.median(jump[judged]))
            if median > worst:
                worst, worst_axis = median, ax.name or f"axis {k}"
    if worst > FIT_CURVATURE_JUMP:
        warnings.warn(
            f"the grid does not resolve the curvature of log z along {worst_axis}: its second "
            f"difference changes by {worst:.2f} of itself from node to node (median over the "
            f"nodes that carry the solution, at t = 0; resolved grids stay well below "
            f"{FIT_CURVATURE_JUMP}). The fitted diffusion's quadratics then bulge between nodes, "
            "and v can be off by tens of percent and move with dt. Refine that axis (or the "
            "grid), or raise the temperature, and compare.",
            ResolutionWarning,
            stacklevel=3,
        )
    return worst


def check_resolution(
    problem: Problem, solution: Solution, step: float, diffusion: list | None = None
) -> float:
    """Warn (:class:`ResolutionWarning`) when the plain operator's z tails, not the PDE, set the
    value: the share of nodes where v/λ at t = T (the terminal cost) or t = 0 rises from a node
    to its neighbour along a noise axis by at least 0.9 of the diffusion's tail cap
    (:func:`_diffusion_tail_cap`, for r = ``step`` D_k / h_k², ``step`` the diffusion's time
    step). The scheme cannot carry such a fall of z: it fills it with its own tails, so v is
    underestimated, more so as λ falls. ``diffusion``: the D_k of the problem if already
    evaluated (:attr:`SplittingStep.diffusion`). Returns that share."""
    grid = problem.grid
    flagged, worst = 0, (0.0, 0.0, "")
    if diffusion is None:
        diffusion = _diffusion_coefficients(problem)
    for value in (_node_values(problem.terminal_values, grid), solution.value_nodes(0)):
        flagged, worst = _count_at_cap(problem, value, step, flagged, worst, diffusion)
    share = flagged / (2 * grid.size)
    if share > TAIL_SHARE:
        warnings.warn(
            f"the plain scheme cannot resolve this problem's desirability: at {100 * share:.0f} % "
            f"of the nodes v/λ rises from node to node faster than its diffusion's tails allow "
            f"(up to {worst[0]:.3g} per cell along {worst[2]}, where the tails cap it at "
            f"{worst[1]:.3g}), so v is underestimated there, increasingly as λ falls. Solve with "
            "fitting='terminal' (exact tails), or refine that axis, or raise the temperature.",
            ResolutionWarning,
            stacklevel=3,
        )
    return share


def _count_at_cap(
    problem: Problem, value: np.ndarray, step: float, flagged: int, worst, diffusion: list
):
    """Add to ``flagged`` the nodes whose v/λ rises to a noise-axis neighbour by ≥ 0.9 of the tail
    cap, and keep the worst (rise, cap, axis) seen (``diffusion``: the D_k of
    :func:`gridlbc.schemes.splitting._diffusion_coefficients`)."""
    grid, lam = problem.grid, problem.temperature
    for flat in _flat_chunks(grid.size):
        index = np.stack(np.unravel_index(flat, grid.shape), axis=1)
        hit = np.zeros(flat.size, dtype=bool)
        for k, ax in enumerate(grid.axes):
            coefficient = (
                np.full(flat.size, diffusion[k])
                if np.ndim(diffusion[k]) == 0
                else diffusion[k][flat]
            )
            if not np.any(coefficient > 0):
                continue
            nxt = index.copy()
            nxt[:, k] += 1
            inside = nxt[:, k] < ax.n
            if ax.periodic:
                nxt[:, k] %= ax.n
                inside[:] = True
            neighbour = np.ravel_multi_index(
                tuple(np.minimum(nxt, np.array(grid.shape) - 1).T), grid.shape
            )
            with np.errstate(invalid="ignore"):  # +inf where one side underflowed, NaN both
                rise = np.abs(value[neighbour] - value[flat]) / lam
            cap = _diffusion_tail_cap(step * coefficient / ax.spacing**2)
            at_cap = inside & ~np.isnan(rise) & (rise >= 0.9 * cap)
            hit |= at_cap
            if np.any(at_cap):
                i = np.argmax(np.where(at_cap, rise, -1.0))
                if rise[i] > worst[0]:
                    worst = (float(rise[i]), float(cap[i]), ax.name or f"axis {k}")
        flagged += int(hit.sum())
    return flagged, worst


def _solve_log(
    problem: Problem,
    s: SolverSettings,
    kept: list[int],
    dt: float,
    n_steps: int,
    rate: float,
    estimate: dict[str, int],
    started: float,
):
    """A single terminal cost fitted to itself, stepped in the log domain; returns the
    :class:`Solution` and the D_k of its axes (:attr:`SplittingStep.diffusion`).

    ℓ = log z is advanced by the same composition as :func:`_march_fitted` (whole diffusions
    between the steps when there is no state cost), with the parts in the log domain
    (:meth:`SplittingStep.log_drift`, :meth:`SplittingStep.log_diffusion`; the state cost C an
    addition). A slice inside a merged step is the mean ½(y + D y) of log z before and after
    its diffusion, not of z as in :func:`_march_fitted` (nothing need be linear here: the
    operator depends on z itself); it is D½ y to O(Δt²) as well, and its policy is the better
    one (README, "Two schemes, and exponential fitting"). So a solution fitted to itself agrees
    with one fitted to the same cost explicitly (``fitting=g``) at t = 0 and T to rounding, and
    at the slices between only to O(Δt²) where the halves are merged: :func:`gridlbc.combine`
    does not combine the two exactly.

    The slices are stored as log z relative to their maximum (``interpolation="log"``: the
    solution then interpolates v = −λ log z, not z), so that neither the solve nor the stored
    solution underflows however large v/λ grows across the grid.
    """
    grid = problem.grid
    g = _node_values(problem.terminal_values, grid)
    ell = (-(g - g.min()) / problem.temperature)[None, :]
    log_scale = -g.min() / problem.temperature
    fingerprint = _fingerprint(np.exp(ell[0]))
    step = SplittingStep(problem, dt)
    cost = step.log_cost[None, :] if step.log_cost.size else None  # C: log z += cost
    setup_time = time.perf_counter() - started
    slices = slice_storage((len(kept), grid.size), np.dtype(s.dtype), s.mmap_dir)
    scales = np.empty(len(kept))
    slot = len(kept) - 1
    slices[slot], scales[slot] = ell[0], log_scale
    spares = (np.empty_like(ell), np.empty_like(ell))
    if cost is not None:
        ell += cost
    x = step.log_diffusion(ell, spares)  # D½ C ℓ_T
    free = [a for a in (ell, *spares) if a is not x]
    progress = ProgressBar(
        n_steps, s.progress, f"fitted {grid.describe()}", work_per_item=grid.size
    )
    for n in range(n_steps - 1, -1, -1):
        y, other = free
        step.log_drift(x, y)  # y = MP x
        whole = cost is None and n > 0  # merged with the next step's D½ (_march_fitted)
        result = step.log_diffusion(y, (x, other), full=whole)
        if cost is not None:
            result += cost
        peak = float(result.max())
        if n == kept[slot - 1]:
            slot -= 1
            stored, top = result, peak
            if whole:  # ½(y + D y): half way through the whole diffusion, in log z
                stored = x if result is other else other
                np.add(y, result, out=stored)
                stored *= 0.5
                top = float(stored.max())
            np.subtract(stored[0], top, out=slices[slot])
            scales[slot] = log_scale + top
        result -= peak
        log_scale += peak
        if n > 0 and cost is not None:  # the next step opens with its own D½ C
            result += cost
            result = step.log_diffusion(result, [a for a in (x, y, other) if a is not result])
        free = [a for a in (x, y, other) if a is not result]
        x = result
        progress.update(n_steps - n)
    times = np.array(kept, dtype=float) * dt
    times[-1] = problem.horizon
    diagnostics = SolveDiagnostics(
        method=s.method,
        dt=dt,
        steps=n_steps,
        store_every=s.store_every,
        wall_time=time.perf_counter() - started,
        setup_time=setup_time,
        underflow_nodes=0,
        stored_bytes=int(slices.nbytes),
        operator_bytes=step.nbytes,
        courant=rate * dt,
        memory_estimate=estimate["ram"],
        fitting=fingerprint,
        interpolation="log",
    )
    return Solution(problem, times, slices, scales, diagnostics), step.diffusion


def solve(problem: Problem, dt: float | None = None, settings=None, **options) -> Solution:
    """Solve the linear Bellman PDE of ``problem`` backward from T to 0.

    Parameters
    ----------
    problem : Problem
    dt : float, optional
        Time step (default from the Courant number, see :class:`SolverSettings`).
    settings : SolverSettings or str, optional
        Settings or the name of a preset in :data:`gridlbc.PRESETS`.
    **options
        Any :class:`SolverSettings` field, e.g. ``method="implicit"``, ``store_every=5``,
        ``progress=True``.

    Returns
    -------
    Solution
        Value, desirability and policy at any (x, t), with :class:`SolveDiagnostics`.
    """
    if dt is not None:
        options["dt"] = dt
    return solve_many(problem, [problem.terminal_cost], settings, **options)[0]
