"""Semi-Lagrangian operator splitting for the linear Bellman PDE.

One backward step from t + Δt to t composes linear, monotone operators, symmetrically (Strang):

    z(·, t) = C D½ M P D½ C z(·, t + Δt)

- P, drift along characteristics: (P z)(x) = z(X(x)) with the second-order (midpoint) foot
  X(x) = x + Δt a(x + ½Δt a(x)), evaluated by barycentric interpolation (weights ≥ 0, sum 1);
  feet are wrapped on periodic axes and clamped to the box on the others;
- D½, diffusion over half a step, implicitly, one noise axis k at a time:
  (I − ½Δt D_k(x) δ²_k) z' = z,  D_k = ½ (λ B R⁻¹ Bᵀ)_kk, δ²_k the three-point second
  difference; each line is a tridiagonal M-matrix (cyclic on a periodic axis; on a closed axis the
  jumps out of the box are suppressed, a reflecting state constraint);
- C and M, the state cost, by Simpson's rule along the characteristic: ∫ q dt over the step is
  Δt (q(start) + 4 q(middle) + q(end))/6, so C: z' = exp(−q Δt/(6λ)) z at the nodes (a path's
  ends), and M: z' = exp(−2 q(m(x)) Δt/(3λ)) z applied between the drift and the first half
  diffusion, with m(x) = x + ½Δt a(x + ¼Δt a(x)), the foot of half a step, where the
  characteristic from x is half a step on (the first half diffusion then averages it over that
  half's noise). The trapezoid of the ends alone misses how q changes along a characteristic
  that crosses many cells per step, and a cost that is stiff across one step's noise.

Every stage maps non-negative z to non-negative z and constants to constants (before the cost),
so the step is the transition of a Markov chain (with killing at rate q/λ), and it is
unconditionally stable: Δt is limited by accuracy, not by a CFL condition. Its error is
O(h²/Δt) from the interpolation (a numerical diffusion of at most h²/(8Δt) per axis), O(Δt) from
the backward-Euler diffusion and O(Δt²) from the symmetric splitting and the foot; the first term
*falls* as Δt grows, so unlike an upwind scheme the splitting wants large Courant numbers. The
symmetric order matters where the drift is fast (``benchmarks/swingup_accuracy.py``).

Exponential fitting (``fitting=`` in :func:`gridlbc.solve`). Barycentric interpolation is exact
for affine z, but z = e^{−v/λ} is exponential wherever v is steep (a swing-up's terminal bowl
rises by several λ per cell), and interpolating it linearly *is* the numerical diffusion that
makes the plain scheme optimistic. The fitted drift interpolates relative to a reference
desirability φ > 0 instead:

    (P_φ z)(x) = Σ_j w_j c_j z(y_j),    c_j = φ̄(X) / φ(y_j),    φ̄(X) = exp(Σ_i w_i log φ(y_i)),

over the vertices y_j of the foot X's simplex. It is exact wherever z ∝ φ across the simplex,
for instance for log-affine z when φ is log-affine there. The factors c_j depend on φ alone, so
for a fixed φ the step is linear in z and non-negative; its weights sum to Σ_j w_j c_j ≥ 1
(Jensen), so it is the transition of a linearly solvable Markov chain with an extra state reward
λ log(Σ_j w_j c_j)/Δt: the correction that cancels the interpolation's diffusion when z ∝ φ. The
reference is itself advanced by the fitted step, as one more right-hand side (fitted to itself,
P_φ φ = φ̄: v(x) ← Σ_j w_j v(y_j), the value-space semi-Lagrangian update). A problem fitted to
its own terminal cost therefore has the accuracy of interpolating v rather than z, and all
terminal costs solved with the same reference share one linear operator, so superposition stays
exact among them (the README's swing-up tables compare the two).

Curvature term. Averaging log φ linearly over the simplex misses its curvature: for quadratic
ℓ = log φ with index-unit Hessian H, Σ_j w_j ℓ(y_j) = ℓ(X) + ½ Σ_ab M_ab H_ab with the
simplex's second moments M_ab = Σ_j w_j (y_j − X)_a (y_j − X)_b, which on the Kuhn simplex are
min(f_a, f_b) − f_a f_b for the foot's fractional coordinates f in its cell. Where v is convex
that bias overestimates v by about h² v''/8 per step, accumulating over the steps (pessimism
of order h²/Δt). The fitted drift therefore uses

    log φ̄(X) = Σ_j w_j ℓ(y_j) − ½ Σ_ab M_ab H_ab,

H the central second differences of ℓ at the simplex's vertex of largest weight, and the result
limited to [min_j ℓ(y_j), max_j ℓ(y_j)] over the vertices of positive weight (a face's range when
the foot lies on it, so that mirror images stay mirror images) so that it creates no new extrema (stable where ℓ is
kinked; at a smooth maximum inside a cell it costs the bias back there). φ̄ is still a positive
function of φ alone, so for a fixed reference the step stays linear and non-negative in z, and
exact where z ∝ φ; φ̄ is now also exact for quadratic log φ.

Fitted diffusion. With a reference, the half-step diffusion along each noise axis is fitted too:

    (D_φ z)(x) = ∫ G_σ(x − x') φ̄(x') ȳ(x') dx',    y = z/φ,    σ² = λ (B R⁻¹ Bᵀ)_kk Δt/2,

with ȳ the piecewise-linear interpolant of y, log φ̄ on each cell the quadratic through its two
nodes with the cell's mean second difference, and the line continued by wrapping (periodic) or
mirroring (closed, the reflecting constraint); each cell's integral is closed-form (erf). For a
fixed φ this is again linear and non-negative and exact where z ∝ φ (for a Gaussian φ exactly
the heat kernel's result). Its tails are Gaussian, so moving k cells costs the control's true
(kh)²/(2 (B R⁻¹ Bᵀ)_kk Δt/2) at any λ; the tridiagonal solve's tails decay only geometrically,
which caps the rise of −λ log z per cell at λ log(1/ρ), a cap that vanishes with λ. The solver
composes the fitted operator over all steps (:func:`gridlbc.solver._march_fitted`): without a
state cost the half diffusions that meet between steps are taken as one over the whole step
(``full=True``: σ² doubled, the Gaussian semigroup), which halves this, the fitted step's most
expensive part. A single solve fitted to itself runs in the log domain
(:meth:`SplittingStep.log_drift`, :meth:`SplittingStep.log_diffusion`).

Large grids. The feet are computed once per solve, in chunks, and stored compactly
(:data:`FEET_LAYOUTS`): ``"compact"`` keeps per node the base corner (int32), the index (uint16) of its
simplex's shape (axis order and periodic seams; a small table holds the d+1 vertex offsets of
each shape) and the sorted fractional coordinates quantised to 1/65535 of a cell (uint16):
6 + 2d bytes per node, decoded inside the kernel. The quantisation
moves each foot by at most 1/131070 of a cell (far below the O(h²) interpolation error) and keeps
the weights exactly non-negative and summing to one, so linearity and monotonicity are exact.
``"table"`` stores the d+1 vertex indices (int32) and weights (float32) explicitly: 8(d+1) bytes.
The kernels run over all cores, allocate nothing per line or node, fold the renormalisation of
the previous slice into the drift pass and the slice maximum into the cost pass (or, without a
state cost, into the last diffusion pass), so a step streams z through memory about twice.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .._numba import jit, jit_inline, jit_parallel, prange, work_blocks
from .._special import erfcx
from ..grid import Grid
from ..interpolate import _cell, _kuhn_kernel, barycentric
from ..problem import Problem

FEET_LAYOUTS = ("compact", "table")
"""How the characteristic feet are stored (see the module docstring)."""

_Q = 65535  # quantisation of the fractional coordinates in the compact layout
_MAX_COMPACT_DIM = 8  # the packed simplex shape holds 4 bits per walk step
_FEET_CHUNK = 1 << 14  # nodes per call of the system's functions: small enough that the
# allocator reuses the chunk's temporaries (first writes to fresh memory are slow)
_FEET_BATCH = 1 << 20  # nodes per call of the compiled foot encoding (bounds the setup memory)
_TINY = 1e-300  # floor of the fitting reference: 1/φ and the factors stay finite


# -- feet ---------------------------------------------------------------------------------------


def _flat_chunks(stop: int, start: int = 0):
    """Consecutive ranges of the flat node indices start … stop − 1, ``_FEET_CHUNK`` at a time."""
    for first in range(start, stop, _FEET_CHUNK):
        yield np.arange(first, min(first + _FEET_CHUNK, stop))


def _node_values(function, grid: Grid) -> np.ndarray:
    """``function(x)`` at every node of ``grid``, ``(N,)``, evaluated in chunks of nodes (the
    full ``(N, d)`` node array is never built)."""
    out = np.empty(grid.size)
    for flat in _flat_chunks(grid.size):
        out[flat[0] : flat[-1] + 1] = function(grid.node_coordinates(flat))
    return out


def _foot(problem: Problem, x: np.ndarray, dt: float) -> np.ndarray:
    """The second-order (midpoint) foot X(x) = x + Δt a(x + ½Δt a(x)) of the states x after a
    time dt, wrapped and clamped."""
    grid, system = problem.grid, problem.system
    midpoint = grid.clamp(x + 0.5 * dt * np.asarray(system.drift(x), dtype=float))
    return grid.clamp(x + dt * np.asarray(system.drift(midpoint), dtype=float))


def _foot_chunks(problem: Problem, dt: float, start: int = 0, stop: int | None = None):
    """Feet X(x) (:func:`_foot`) of the nodes start … stop − 1 (default: all), in chunks."""
    grid = problem.grid
    for flat in _flat_chunks(grid.size if stop is None else stop, start):
        yield flat, _foot(problem, grid.node_coordinates(flat), dt)


def _compact_feet(grid: Grid, idx: np.ndarray, weights: np.ndarray):
    """Compact form of barycentric vertices and weights ``(M, d+1)`` (see the module docstring).

    Returns the base corners (int32), the packed simplex shapes (uint32: for each walk step j the
    position in :func:`_walk_steps` of its flat offset, 4 bits each) and the sorted fractional
    coordinates f_j = Σ_{i>j} w_i quantised to 1/65535 (uint16, non-increasing in j).
    """
    steps = np.searchsorted(_walk_steps(grid), np.diff(idx, axis=1))
    shape = np.zeros(idx.shape[0], dtype=np.uint32)
    for j in range(grid.ndim):
        shape |= steps[:, j].astype(np.uint32) << np.uint32(4 * j)
    tail = np.cumsum(weights[:, :0:-1], axis=1)[:, ::-1]  # f_j = w_{j+1} + … + w_d
    frac = np.rint(np.clip(tail[:, : grid.ndim], 0.0, 1.0) * _Q).astype(np.uint16)
    return idx[:, 0].astype(np.int32), shape, frac


@jit_parallel
def _encode_compact_kernel(x, lo, spacing, shape, strides, periodic, walk, base, packed, frac):
    """The compact form of the feet ``x`` ``(M, d)`` (wrapped and clamped) in one pass: the
    cell and sorted fractional coordinates of :func:`gridlbc.interpolate.barycentric` (the same
    arithmetic), written as base corners, packed shapes and quantised fractions into ``base``,
    ``packed`` and ``frac`` exactly as :func:`_compact_feet` encodes barycentric's output
    (``walk``: :func:`_walk_steps`)."""
    n_points, d = x.shape
    n_blocks = min(n_points, 256)
    for b in prange(n_blocks):
        f = np.empty(d)
        order = np.empty(d, dtype=np.int64)
        for p in range(b * n_points // n_blocks, (b + 1) * n_points // n_blocks):
            corner = 0
            for k in range(d):
                i, f[k] = _cell(x[p, k], lo[k], spacing[k], shape[k], periodic[k])
                corner += i * strides[k]
                j = k  # insertion into the decreasing order, ties in axis order (stable)
                while j > 0 and f[order[j - 1]] < f[k]:
                    order[j] = order[j - 1]
                    j -= 1
                order[j] = k
            base[p] = corner
            node = corner
            code = np.uint32(0)
            for j in range(d):  # the Kuhn walk; each step's position in walk, 4 bits each
                k = order[j]
                n = shape[k]
                step = -(n - 1) * strides[k] if (node // strides[k]) % n == n - 1 else strides[k]
                node += step
                position = 0
                while position < walk.size - 1 and walk[position] < step:
                    position += 1
                code |= np.uint32(position) << np.uint32(4 * j)
            packed[p] = code
            tail = 0.0  # f_j = w_{j+1} + … + w_d, summed as the twin's cumsum does
            for j in range(d - 1, -1, -1):
                tail += f[order[j]] - (f[order[j + 1]] if j + 1 < d else 0.0)
                frac[p, j] = np.uint16(np.rint(min(max(tail, 0.0), 1.0) * _Q))


def _shape_codes(grid: Grid, shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(shapes, return_inverse=True)`` for the packed simplex shapes: by a table of
    all 16^d packed values when that is small (one pass instead of a sort), else by sorting."""
    if 16**grid.ndim > 1 << 20:
        return np.unique(shapes, return_inverse=True)
    present = np.bincount(shapes, minlength=16**grid.ndim) > 0
    rank = np.cumsum(present) - 1
    return np.flatnonzero(present).astype(np.uint32), rank[shapes]


def _walk_steps(grid: Grid) -> np.ndarray:
    """The flat offsets of one step of the Kuhn walk, sorted: +s_k, or −(n_k − 1) s_k across the
    seam of a periodic axis."""
    strides = grid.strides
    wraps = [-(ax.n - 1) * strides[k] for k, ax in enumerate(grid.axes) if ax.periodic]
    return np.sort(np.concatenate([strides, np.array(wraps, dtype=np.int64)]))


def _vertex_offsets(grid: Grid, shapes: np.ndarray) -> np.ndarray:
    """Offsets of the d+1 simplex vertices from the base corner per packed shape, ``(S, d+1)``."""
    walk = _walk_steps(grid)
    offsets = np.zeros((shapes.size, grid.ndim + 1), dtype=np.int64)
    for j in range(grid.ndim):
        offsets[:, j + 1] = offsets[:, j] + walk[(shapes.astype(np.int64) >> (4 * j)) & 15]
    return offsets


def _walk_axes(grid: Grid, offsets: np.ndarray) -> np.ndarray:
    """The axis of each walk step per packed shape, ``(S, d)``, from the vertex offsets
    (a step is +s_a, or −(n_a − 1) s_a across a periodic seam)."""
    steps = np.diff(offsets, axis=1)
    axes = np.zeros(steps.shape, dtype=np.int64)
    for a, ax in enumerate(grid.axes):
        stride = grid.strides[a]
        axes[(steps == stride) | (ax.periodic & (steps == -(ax.n - 1) * stride))] = a
    return axes


def characteristic_feet(problem: Problem, dt: float) -> np.ndarray:
    """Feet of all nodes, ``(N, d)`` (plain numpy, for tests and plots)."""
    return np.concatenate([feet for _, feet in _foot_chunks(problem, dt)])


def feet_bytes_per_node(ndim: int, layout: str) -> int:
    """Memory of the stored feet per node for a layout (see :data:`FEET_LAYOUTS`)."""
    return 6 + 2 * ndim if layout == "compact" else 8 * (ndim + 1)


# -- drift pass ---------------------------------------------------------------------------------


@functools.cache
def _advect_kernels(d: int):
    """The drift kernels of :func:`_advect_compact_kernel` and :func:`_advect_table_kernel` for
    grids of dimension ``d``, compiled with d a constant (numba unrolls the vertex loops) and
    with the per-node arrays read as flat rows through unsigned indices (no negative-index
    wrapping), which lets the compiler vectorise the decoding."""

    @jit_parallel
    def compact(z, base, code, frac, offsets, scale, ell, ones_row, out):
        n_rhs, n_nodes = z.shape
        fitted = ell.size > 0
        fractions = frac.reshape(-1)
        vertex = offsets.reshape(-1)
        for p in prange(n_nodes):
            node = np.int64(base[p])
            row = np.int64(code[p]) * (d + 1)
            fit = 1.0
            if fitted:
                previous = _Q
                mean = 0.0
                for j in range(d + 1):
                    f = np.int64(fractions[p * d + j]) if j < d else np.int64(0)
                    mean += (previous - f) * ell[np.uint64(node + vertex[row + j])]
                    previous = f
                fit = np.exp(mean * (1.0 / _Q))
            for r in range(n_rhs):
                if r == ones_row:  # the integer weights telescope to Q: the same number, exactly
                    acc = float(_Q)
                else:
                    zr = z[r]
                    previous = _Q
                    acc = 0.0
                    for j in range(d):
                        f = np.int64(fractions[p * d + j])
                        acc += (previous - f) * zr[np.uint64(node + vertex[row + j])]
                        previous = f
                    acc += previous * zr[np.uint64(node + vertex[row + d])]
                out[r, p] = acc * (fit * scale[r] * (1.0 / _Q))

    @jit_parallel
    def table(z, idx, weights, scale, ell, ones_row, out):
        n_rhs, n_nodes = z.shape
        fitted = ell.size > 0
        vertices = idx.reshape(-1)
        weight = weights.reshape(-1)
        for p in prange(n_nodes):
            first = p * (d + 1)
            fit = 1.0
            total = 0.0
            if fitted:
                mean = 0.0
                for j in range(d + 1):
                    mean += weight[first + j] * ell[np.uint64(vertices[first + j])]
                    total += weight[first + j]
                fit = np.exp(mean)
            for r in range(n_rhs):
                if r == ones_row:
                    acc = total
                else:
                    zr = z[r]
                    acc = 0.0
                    for j in range(d + 1):
                        acc += weight[first + j] * zr[np.uint64(vertices[first + j])]
                out[r, p] = acc * (fit * scale[r])

    return compact, table


def _advect_compact_kernel(z, base, code, frac, offsets, scale, ell, ones_row, out):
    """out[r, p] = scale[r] · F_p · Σ_j w_j z[r, v_j] over the foot's simplex vertices
    v_j = base[p] + offsets[code[p], j] with w_j = (f_{j−1} − f_j)/Q from the sorted quantised
    fractions (f_{−1} = Q, f_d = 0). Fitted (``ell`` = log φ given, ``z`` already divided by φ
    by :func:`_fitting_kernel`): F_p = exp(Σ_j w_j ell[v_j]) = φ̄, the reference's geometric mean
    over the simplex; F_p = 1 when ``ell`` is empty. Row ``ones_row`` (−1: none) is known to be
    all ones, so its gather is skipped: Σ_j w_j · 1 = 1 exactly. All arrays C-contiguous."""
    _advect_kernels(frac.shape[1])[0](z, base, code, frac, offsets, scale, ell, ones_row, out)


def _advect_table_kernel(z, idx, weights, scale, ell, ones_row, out):
    """out[r, p] = scale[r] · F_p · Σ_j weights[p, j] z[r, idx[p, j]], the fitting factor F_p and
    ``ones_row`` as in :func:`_advect_compact_kernel`."""
    _advect_kernels(idx.shape[1] - 1)[1](z, idx, weights, scale, ell, ones_row, out)


@jit_parallel
def _fitting_kernel(z, reference, ell):
    """With φ = max(z[reference], TINY): ell = log φ, and every row of ``z`` divided by φ in
    place, so that the drift's gather Σ_j w_j z(y_j)/φ(y_j) times φ̄ is the fitted P_φ z.
    Returns the number of nodes where φ was floored: where it is zero, the reference row is
    all ones (x/x = 1 exactly in floating point)."""
    n_rhs, n_nodes = z.shape
    floored = 0
    for p in prange(n_nodes):
        phi = z[reference, p]
        if phi < _TINY:
            phi = _TINY
            floored += 1
        ell[p] = np.log(phi)
        for r in range(n_rhs):
            z[r, p] /= phi
    return floored


# -- curvature correction of the fitted drift ---------------------------------------------------


def _hessian_pairs(ndim: int) -> np.ndarray:
    """``pairs[a, b]``: the column of the index-unit Hessian component ∂_a∂_b in
    :func:`_hessian_at` (symmetric; d(d+1)/2 columns)."""
    pairs = np.empty((ndim, ndim), dtype=np.int64)
    m = 0
    for a in range(ndim):
        for b in range(a, ndim):
            pairs[a, b] = pairs[b, a] = m
            m += 1
    return pairs


def _stencils(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Where :func:`_hessian_at` centres its stencil at each node, as (``place``, ``stencils``):
    ``place`` (N,) numbers the node's position along each axis (0 inside, 1 at the first node,
    2 at the last) as the base-3 digits Σ_a 3^a position_a, and row ``place`` of ``stencils``
    ``(3^d, 1 + 2d)`` holds the stencil's centre offset from the node, then the offsets of its
    +e_a and −e_a neighbours from the centre: ±s_a, wrapped on a periodic axis; on a closed axis
    the centre is moved in from an end to its neighbour, and an axis of fewer than 3 nodes has
    no neighbours (offsets 0). One byte per node up to d = 5 (two up to 10), against d(d+1)/2
    numbers per node for a stored Hessian."""
    d = grid.ndim
    place = np.zeros(grid.shape, dtype=np.min_scalar_type(3**d - 1))
    for a, n in enumerate(grid.shape):
        position = np.zeros(n, dtype=place.dtype)
        position[0], position[-1] = 1, 2
        place += (
            (3**a * position).astype(place.dtype).reshape([-1 if b == a else 1 for b in range(d)])
        )
    stencils = np.zeros((3**d, 1 + 2 * d), dtype=np.int64)
    for row in range(3**d):
        for a, (n, s, periodic) in enumerate(
            zip(grid.shape, grid.strides, grid.periodic, strict=True)
        ):
            position = row // 3**a % 3
            if periodic:
                up, down = (
                    s if position != 2 else -(n - 1) * s,
                    -s if position != 1 else (n - 1) * s,
                )
            elif n < 3:
                up = down = 0
            else:
                up, down = s, -s
                stencils[row, 0] += {0: 0, 1: s, 2: -s}[position]
            stencils[row, 1 + a], stencils[row, 1 + d + a] = up, down
    return place.reshape(-1), stencils


@jit_inline
def _hessian_at(ell, node, stencil, d, hessian):
    """``hessian[pairs[a, b]]`` (:func:`_hessian_pairs`) = the second difference of ``ell`` in
    index units at ``node``, on ``stencil``, the row of :func:`_stencils` for the node's place:
    ℓ(+a) − 2ℓ + ℓ(−a) on the diagonal, ((ℓ(+a+b) − ℓ(−a+b)) − (ℓ(+a−b) − ℓ(−a−b)))/4 off it,
    exactly 0 along an axis of fewer than 3 nodes (its offsets are 0) without a branch. ``d``
    is the grid's dimension, a compile-time constant where the caller's is (the loops unroll)."""
    centre = np.int64(node) + stencil[0]
    middle = ell[centre]
    column = 0
    for a in range(d):
        up_a, down_a = stencil[1 + a], stencil[1 + d + a]
        hessian[column] = ell[centre + up_a] - 2.0 * middle + ell[centre + down_a]
        column += 1
        for b in range(a + 1, d):
            up_b, down_b = stencil[1 + b], stencil[1 + d + b]
            hessian[column] = 0.25 * (
                (ell[centre + up_a + up_b] - ell[centre + down_a + up_b])
                - (ell[centre + up_a + down_b] - ell[centre + down_a + down_b])
            )
            column += 1


@jit_inline
def _limited(ell_lin, term, low, high):
    """The curvature term, cut so that ℓ_lin + term stays within [low, high] (the vertex values'
    range): no new extrema, which keeps the corrected drift stable where ℓ is kinked."""
    return min(max(ell_lin + term, low), high) - ell_lin


@functools.cache
def _curvature_compact_kernels(d: int):
    """:func:`_curvature_compact_kernel` compiled for grids of dimension ``d`` (a constant: the
    loops over the vertices and walk steps unroll), reading flat rows through unsigned indices
    as :func:`_advect_kernels` does."""

    @jit_parallel
    def kernel(
        ell, base, code, frac, offsets, columns, place, stencils, record, places, add_mean, out
    ):
        n_nodes = base.size
        n_blocks = min(n_nodes, 256)
        fractions = frac.reshape(-1)
        vertex = offsets.reshape(-1)
        column = columns.reshape(-1)
        for block in prange(n_blocks):
            hessian = np.empty(d * (d + 1) // 2)  # scratch
            for p in range(block * n_nodes // n_blocks, (block + 1) * n_nodes // n_blocks):
                node = np.int64(base[p])
                c = np.int64(code[p])
                previous = _Q
                lin = 0.0
                low, high = np.inf, -np.inf
                nearest, largest = node, -1
                for j in range(d + 1):
                    fj = np.int64(fractions[p * d + j]) if j < d else np.int64(0)
                    v = node + vertex[c * (d + 1) + j]
                    value = ell[np.uint64(v)]
                    lin += (previous - fj) * value
                    if previous > fj:
                        low, high = min(low, value), max(high, value)
                    if previous - fj > largest:
                        nearest, largest = v, previous - fj
                    previous = fj
                if record:
                    places[p] = place[nearest]
                _hessian_at(ell, nearest, stencils[np.int64(places[p])], d, hessian)
                acc = 0.0
                for k in range(d):
                    cross = 0.0
                    for m in range(k + 1, d):
                        cross += (
                            np.float64(fractions[p * d + m]) * hessian[column[(c * d + k) * d + m]]
                        )
                    f = np.float64(fractions[p * d + k]) * (1.0 / _Q)
                    acc += (1.0 - f) * (
                        f * hessian[column[(c * d + k) * d + k]] + 2.0 * cross * (1.0 / _Q)
                    )
                mean = lin * (1.0 / _Q)
                term = _limited(mean, -0.5 * acc, low, high)
                out[p] = mean + term if add_mean else term

    return kernel


def _curvature_compact_kernel(
    ell, base, code, frac, offsets, columns, place, stencils, record, places, add_mean, out
):
    """out[p] = the limited curvature term of the compact feet (see
    :meth:`SplittingStep.curvature_correction`), plus the linear mean Σ_j w_j ell[v_j] when
    ``add_mean`` (the fitted log drift in one pass): with the sorted fractions f_k of walk steps
    k along axes π_k, M_{π_k π_k} = f_k (1 − f_k) and, for k < l, M_{π_k π_l} = f_l (1 − f_k);
    H at the vertex of largest weight (the first on a tie), computed there from ``ell``
    (:func:`_hessian_at`; a stored table of it would be gathered at the feet, five times the
    bytes of ``ell``), its component ∂_{π_k}∂_{π_l} at :func:`_hessian_pairs` index
    ``columns[code[p], k, l]`` (:func:`_hessian_columns`). The stencil's row is ``places[p]``,
    the ``place`` (:func:`_stencils`) of that vertex; the feet being fixed, it is gathered once,
    by a call with ``record``, and read in order by the later ones."""
    _curvature_compact_kernels(frac.shape[1])(
        ell, base, code, frac, offsets, columns, place, stencils, record, places, add_mean, out
    )


def _hessian_columns(walk_axes: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """``columns[c, k, l]`` = the Hessian column (:func:`_hessian_pairs`) of ∂_{π_k}∂_{π_l}
    for the walk axes π = ``walk_axes[c]`` of each simplex shape c (:func:`_walk_axes`)."""
    return np.ascontiguousarray(pairs[walk_axes[:, :, None], walk_axes[:, None, :]])


@jit_parallel
def _curvature_table_kernel(
    ell, idx, weights, place, stencils, shape, strides, pairs, add_mean, out
):
    """:func:`_curvature_compact_kernel` for the table feet: the walk step j → j + 1 runs along
    the axis whose stride (or wrap −(n − 1) × stride) is idx[p, j+1] − idx[p, j], and its
    fraction is f_j = Σ_{i>j} weights[p, i]; ``add_mean`` as there. Nodes are taken in blocks, so
    that the scratch of the walk's axes and fractions and of the Hessian is allocated once per
    block."""
    n_nodes, n_vertices = idx.shape
    d = n_vertices - 1
    n_blocks = min(n_nodes, 256)
    for block in prange(n_blocks):
        axis = np.empty(d, dtype=np.int64)
        f = np.empty(d)
        hessian = np.empty(d * (d + 1) // 2)
        for p in range(block * n_nodes // n_blocks, (block + 1) * n_nodes // n_blocks):
            tail = 0.0
            lin = 0.0
            low, high = np.inf, -np.inf
            for j in range(d - 1, -1, -1):
                tail += np.float64(weights[p, j + 1])
                f[j] = tail
                step = np.int64(idx[p, j + 1]) - np.int64(idx[p, j])
                axis[j] = 0
                for a in range(d):
                    if step == strides[a] or step == -(shape[a] - 1) * strides[a]:
                        axis[j] = a
            node, largest = np.int64(idx[p, 0]), -1.0
            for j in range(n_vertices):
                value = ell[idx[p, j]]
                lin += weights[p, j] * value
                if weights[p, j] > 0:
                    low, high = min(low, value), max(high, value)
                if weights[p, j] > largest:
                    node, largest = np.int64(idx[p, j]), weights[p, j]
            _hessian_at(ell, node, stencils[np.int64(place[node])], d, hessian)
            acc = 0.0
            for k in range(d):
                cross = 0.0
                for m in range(k + 1, d):
                    cross += f[m] * hessian[pairs[axis[k], axis[m]]]
                acc += (1.0 - f[k]) * (f[k] * hessian[pairs[axis[k], axis[k]]] + 2.0 * cross)
            term = _limited(lin, -0.5 * acc, low, high)
            out[p] = lin + term if add_mean else term


def curvature_correction_numpy(grid: Grid, ell: np.ndarray, feet: np.ndarray) -> np.ndarray:
    """Plain-numpy twin of :meth:`SplittingStep.curvature_correction` from the feet ``(N, d)``
    (unquantised): −½ Σ_ab (min(f_a, f_b) − f_a f_b) H_ab, f the foot's fractional coordinates
    in its cell and H the index-unit Hessian of ``ell`` (by :func:`numpy.roll`; closed ends: the
    neighbour's) at the simplex vertex of largest weight, limited to the vertices' range."""
    shape = np.array(grid.shape)
    s = (grid.clamp(feet) - grid.lo) / grid.spacing
    s = np.where(grid.periodic, np.mod(s, shape), s)
    cell = np.where(grid.periodic, np.floor(s) % shape, np.minimum(np.floor(s), shape - 2))
    f = s - cell
    idx, weights = barycentric(grid, feet)
    nearest = idx[np.arange(len(feet)), np.argmax(weights, axis=1)]
    field = grid.reshape(ell)
    centre = [
        np.arange(n) if p or n < 3 else np.clip(np.arange(n), 1, n - 2)
        for n, p in zip(grid.shape, grid.periodic)
    ]
    total = np.zeros(len(feet))
    for a in range(grid.ndim):
        for b in range(a, grid.ndim):
            if (not grid.periodic[a] and shape[a] < 3) or (not grid.periodic[b] and shape[b] < 3):
                continue
            if a == b:
                h = np.roll(field, -1, a) - 2 * field + np.roll(field, 1, a)
            else:
                h = 0.25 * sum(
                    sign_a * sign_b * np.roll(field, (-sign_a, -sign_b), (a, b))
                    for sign_a in (1, -1)
                    for sign_b in (1, -1)
                )
            moment = np.minimum(f[:, a], f[:, b]) - f[:, a] * f[:, b]
            total += (1 if a == b else 2) * moment * h[np.ix_(*centre)].reshape(-1)[nearest]
    lin = (ell[idx] * weights).sum(axis=1)
    carried = weights > 0  # the range of the vertices that carry weight
    low = np.where(carried, ell[idx], np.inf).min(axis=1)
    high = np.where(carried, ell[idx], -np.inf).max(axis=1)
    limited = np.clip(lin - 0.5 * total, low, high)
    return limited - lin


# -- diffusion pass -----------------------------------------------------------------------------


def tridiagonal_factors(ratio: np.ndarray, n: int) -> np.ndarray:
    """LU factors of (1 + 2r_i) z_i − r_i (z_{i−1} + z_{i+1}) on closed lines of length n.

    ``ratio`` holds r = Δt D / h² along the lines (shape ``(..., n)``, the line index last); the
    out-of-box neighbour is dropped at both ends (row 0: (1 + r_0) z_0 − r_0 z_1). Returns
    ``(3, ..., n)``: 1/m_i, r_i/m_i and c_i = −r_i/m_i (c_{n−1} = 0) of the Thomas recursion
    y_i = (b_i + r_i y_{i−1})/m_i, z_i = y_i − c_i z_{i+1}.
    """
    ratio = np.asarray(ratio, dtype=float)
    lower = ratio.copy()
    lower[..., 0] = 0.0
    upper = ratio.copy()
    upper[..., n - 1] = 0.0
    diag = 1.0 + lower + upper
    out = np.empty((3, *ratio.shape))
    c_prev = np.zeros(ratio.shape[:-1])
    for i in range(n):
        m = diag[..., i] + lower[..., i] * c_prev
        out[0, ..., i] = 1.0 / m
        out[1, ..., i] = lower[..., i] / m
        c_prev = -upper[..., i] / m
        out[2, ..., i] = c_prev
    return out


_INTERLEAVED = 8  # contiguous lines solved side by side: their recursions overlap in the core


@jit
def closed_line_tasks(n_nodes: int, n: int, stride: int) -> int:
    """How many tasks :func:`_diffuse_closed_kernel` splits the lines of one closed axis into:
    ``_INTERLEAVED`` contiguous lines (stride 1) or 64 neighbouring strided lines per task."""
    if stride == 1:
        return -(-(n_nodes // n) // _INTERLEAVED)
    return n_nodes // (n * stride) * -(-stride // 64)


@jit_parallel
def _diffuse_closed_kernel(z, factors, uniform, n, stride, block_max):
    """Solve every line of one closed axis in place with precomputed Thomas factors.

    ``factors`` is ``(3, n)`` when the coefficients are the same on every line (``uniform``),
    else ``(3, N)`` per node. Lines are taken several at a time side by side
    (:func:`closed_line_tasks`): strided lines 64 at a time, so that memory is read
    contiguously whatever the axis; contiguous lines ``_INTERLEAVED`` at a time, so that their
    serial recursions interleave instead of each waiting on its previous node. When
    ``block_max`` has columns, the maximum of each row over each block of tasks is written there
    (fusing the slice maximum into this pass).
    """
    n_rhs, n_nodes = z.shape
    chunk = min(stride, 64)
    n_chunks = (stride + chunk - 1) // chunk
    n_tasks = closed_line_tasks(n_nodes, n, stride)
    n_blocks = block_max.shape[1] if block_max.shape[1] > 0 else min(n_tasks, 256)
    track = block_max.shape[1] > 0
    n_lines = n_nodes // n
    for b in prange(n_blocks):
        for r in range(n_rhs):
            peak = 0.0
            for task in range(b * n_tasks // n_blocks, (b + 1) * n_tasks // n_blocks):
                if stride == 1:  # contiguous lines, interleaved
                    first = task * _INTERLEAVED
                    last = min(first + _INTERLEAVED, n_lines)
                    for i in range(n):
                        for line in range(first, last):
                            node = line * n + i
                            f = i if uniform else node
                            if i == 0:
                                z[r, node] = z[r, node] * factors[0, f]
                            else:
                                z[r, node] = (
                                    z[r, node] * factors[0, f] + factors[1, f] * z[r, node - 1]
                                )
                    for line in range(first, last):
                        peak = max(peak, z[r, line * n + n - 1])
                    for i in range(n - 2, -1, -1):
                        for line in range(first, last):
                            node = line * n + i
                            f = i if uniform else node
                            z[r, node] -= factors[2, f] * z[r, node + 1]
                            peak = max(peak, z[r, node])
                    continue
                start = (task // n_chunks) * n * stride
                j0 = (task % n_chunks) * chunk
                j1 = min(stride, j0 + chunk)
                for i in range(n):
                    row = start + i * stride
                    for node in range(row + j0, row + j1):
                        f = i if uniform else node
                        if i == 0:
                            z[r, node] = z[r, node] * factors[0, f]
                        else:
                            z[r, node] = (
                                z[r, node] * factors[0, f] + factors[1, f] * z[r, node - stride]
                            )
                if track:
                    row = start + (n - 1) * stride
                    for node in range(row + j0, row + j1):
                        peak = max(peak, z[r, node])
                for i in range(n - 2, -1, -1):
                    row = start + i * stride
                    for node in range(row + j0, row + j1):
                        f = i if uniform else node
                        z[r, node] -= factors[2, f] * z[r, node + stride]
                        if track:
                            peak = max(peak, z[r, node])
            if track:
                block_max[r, b] = peak


@jit_parallel
def _diffuse_periodic_kernel(z, ratio, n, stride):
    """The cyclic version of :func:`_diffuse_closed_kernel`, by Sherman–Morrison per line."""
    n_rhs, n_nodes = z.shape
    n_outer = n_nodes // (n * stride)
    n_tasks = n_rhs * n_outer * stride
    n_blocks = min(n_tasks, 256)
    for blk in prange(n_blocks):
        a = np.empty(n)
        bb = np.empty(n)
        y = np.empty(n)
        q = np.empty(n)
        cp = np.empty(n)
        for task in range(blk * n_tasks // n_blocks, (blk + 1) * n_tasks // n_blocks):
            r_idx = task // (n_outer * stride)
            rest = task % (n_outer * stride)
            base = (rest // stride) * n * stride + rest % stride
            for i in range(n):
                rr = ratio[base + i * stride]
                a[i] = -rr
                bb[i] = 1.0 + 2.0 * rr
                y[i] = z[r_idx, base + i * stride]
                q[i] = 0.0
            # A = T + u vᵀ with T tridiagonal: u = (γ, 0…0, c_{n−1}), v = (1, 0…0, a_0/γ).
            gamma = -bb[0]
            corner_low = a[0]  # A[0, n−1]
            corner_up = a[n - 1]  # A[n−1, 0] (symmetric stencil: c_{n−1} = a_{n−1})
            bb[0] -= gamma
            bb[n - 1] -= corner_up * corner_low / gamma
            q[0] = gamma
            q[n - 1] = corner_up
            # Thomas on T for y and q together (sub- and super-diagonal a[i] / a[i+1]).
            cp[0] = a[0] / bb[0]
            y[0] /= bb[0]
            q[0] /= bb[0]
            for i in range(1, n):
                m = bb[i] - a[i] * cp[i - 1]
                cp[i] = (a[i] if i < n - 1 else 0.0) / m
                y[i] = (y[i] - a[i] * y[i - 1]) / m
                q[i] = (q[i] - a[i] * q[i - 1]) / m
            for i in range(n - 2, -1, -1):
                y[i] -= cp[i] * y[i + 1]
                q[i] -= cp[i] * q[i + 1]
            factor = (y[0] + corner_low / gamma * y[n - 1]) / (
                1.0 + q[0] + corner_low / gamma * q[n - 1]
            )
            for i in range(n):
                z[r_idx, base + i * stride] = y[i] - factor * q[i]


# -- fitted diffusion ---------------------------------------------------------------------------

_FIT_WINDOW = 20.0  # cells whose integrand stays below e^{−20} of the largest are skipped
_FIT_IMAGES = 16  # the fitted diffusion scans at most this many line lengths to each side
_FIT_TABLE_RANGE = 600.0  # lines whose ℓ spans at most this take the integrand from tables
_FIT_SLACK = 30.0  # the sums are rescaled only when a cell peaks this far above their scale


@jit_inline
def _cell_constants(A, kappa):
    """(A_c, √A_c, 1/(2A_c), √π/(2√A_c)) of a cell whose log-integrand is −A_c s² + B s + C,
    A_c = A − κ/2 > 0: the Gaussian's A = h²/(2σ²) less the cell's curvature κ (≤ A)."""
    Ac = A - 0.5 * kappa
    root = math.sqrt(Ac)
    return Ac, root, 0.5 / Ac, 0.5 * math.sqrt(math.pi) / root


@jit_inline
def _cell_mass(root, mu, top, E, F0, F1, prefactor):
    """∫₀¹ e^{f(s) − E} ds for the concave f(s) = −A s² + B s + C (A > 0) with its vertex at
    μ = B/(2A), its largest value on [0, 1] ``top`` and the integrand at the ends F0 =
    e^{f(0) − E}, F1 = e^{f(1) − E} (E ≥ ``top``, so nothing overflows); ``root`` = √A and
    ``prefactor`` = √π/(2√A) (:func:`_cell_constants`).

    With the ends lo = −√A μ, hi = √A (1 − μ) in the Gaussian's units, and
    erfc(x) e^{f(μ)} = erfcx(x) e^{f(μ) − x²}, it is √π/(2√A) times

        F0 erfcx(lo) − F1 erfcx(hi)                  (μ ≤ 0, the integrand falls),
        F1 erfcx(−hi) − F0 erfcx(−lo)                (μ ≥ 1, it rises),
        2 e^{f(μ) − E} − F1 erfcx(hi) − F0 erfcx(−lo) (its peak inside the cell, f(μ) = top),

    every erfcx taken at a non-negative argument, so it is bounded and never underflows."""
    lo, hi = -root * mu, root * (1.0 - mu)
    if lo >= 0.0:
        mass = F0 * erfcx(lo) - F1 * erfcx(hi)
    elif hi <= 0.0:
        mass = F1 * erfcx(-hi) - F0 * erfcx(-lo)
    else:
        peak = 1.0 if top == E else math.exp(top - E)  # the cell that set E: no exp
        mass = 2.0 * peak - F1 * erfcx(hi) - F0 * erfcx(-lo)
    return max(prefactor * mass, 0.0)


@jit_inline
def _line_bounds(ell, line, n, stride, periodic, curvature):
    """For the line starting at ``line``: ``curvature[i]`` = ℓ_{i−1} − 2ℓ_i + ℓ_{i+1} at its node
    i (wrapped on a periodic line; at the ends of a closed one, the neighbour's), and returns
    (rise, bulge, top, low): the largest |ℓ_{i+1} − ℓ_i| between neighbours, and the most the
    curved interpolant of the fitted diffusion rises above the nodes, max(0, −min κ)/8,
    which together bound how far the fitted diffusion scans; and the line's largest and
    smallest ℓ."""
    rise = 0.0
    lowest = 0.0
    top, low = -np.inf, np.inf
    for i in range(n):
        top, low = max(top, ell[line + i * stride]), min(low, ell[line + i * stride])
        left = i - 1 if i > 0 else (n - 1 if periodic else 1)
        right = i + 1 if i < n - 1 else (0 if periodic else n - 2)
        if not periodic and (i == 0 or i == n - 1):
            inner = 1 if i == 0 else n - 2  # the neighbour's curvature
            left, right, centre = inner - 1, inner + 1, inner
        else:
            centre = i
        kappa = (
            ell[line + left * stride]
            - 2.0 * ell[line + centre * stride]
            + ell[line + right * stride]
        )
        curvature[i] = kappa
        lowest = min(lowest, kappa)
        if periodic or i < n - 1:
            j = i + 1 if i + 1 < n else 0
            rise = max(rise, abs(ell[line + j * stride] - ell[line + i * stride]))
    return rise, -lowest / 8.0, top, low


@jit_inline
def _cell_curvature(curvature, cell, n, A):
    """κ of cell ``cell`` of a line (nodes cell and cell + 1, wrapped: a periodic line's seam is
    cell n − 1): the mean of its nodes' second differences, capped at A."""
    return min(0.5 * (curvature[cell] + curvature[cell + 1 if cell + 1 < n else 0]), A)


@jit_parallel
def _diffuse_fitted_kernel(y, ell, ell_max, sigma2, h, n, stride, periodic, log_out, out):
    """out[r, p] = ∫ G_σ(x_p − x) φ̄(x) ȳ_r(x) dx along one axis, for y = z/φ and ell = log φ at
    the nodes: ȳ_r the piecewise-linear interpolant of y_r, φ̄ = exp(ℓ̄) with ℓ̄ on each cell the
    quadratic through its two nodes with the mean of their second differences κ
    (:func:`_line_bounds`), capped at A below so that every cell's integrand stays concave in
    the exponent (exact for quadratic ℓ), G_σ the Gaussian of variance σ² = ``sigma2`` (one value, or
    one per node), continued across the ends by wrapping (periodic) or mirroring (closed). The
    curvature removes the bias of a linear ℓ̄, which overestimates v = −λℓ by h²v''/8 mid-cell.

    Each side of x_p is scanned cell by cell once, integrating every cell whose peak of the
    log-integrand −(x_p − x)²/(2σ²) + ℓ̄(x) is within 20 (``_FIT_WINDOW``) of the largest peak
    seen so far, so no cell within 20 of the final largest peak is missed. The sums are kept
    relative to a scale e^E, E raised to a cell's peak (and the sums rescaled) only when that
    peak passes E + 30 (``_FIT_SLACK``): nothing overflows, and few nodes pay an exp for it. A
    cell c cells away peaks at most at −A c² + ℓ (A = h²/(2σ²), ℓ its near node's, plus the
    line's bulge), and beyond c > L/(2A), L the line's rise (:func:`_line_bounds`), no later
    cell can peak higher than that: the scan stops there once it falls below the window, or
    once −A c² + ``ell_max`` (plus the bulge) does (after at most ``_FIT_IMAGES`` line lengths).

    With one σ² for all nodes, each cell's constants (:func:`_cell_constants`) are computed once
    per line, not once per node that integrates the cell; the lines are taken in blocks, each
    with its own table of them. The integrand at a node k, c cells from x_p, over e^E is then
    e^{ℓ_k − L} · e^{−A c²} · e^{L − E} (L the line's largest ℓ): the first factor tabulated
    once per line, the second once per call, the third updated with E, so that it costs two
    products instead of an exp. Only where the line's ℓ spans at most 600
    (``_FIT_TABLE_RANGE``): every factor of a cell within the window is then far from
    underflow and overflow (elsewhere, at small temperatures, each is an exp as before).

    A discrete maximum principle: where the reference's own result ψ(x_p) = ∫ G_σ φ̄ exceeds
    e^L, L the line's largest ℓ, every row at p is scaled by e^L/ψ(x_p) (a factor of φ alone,
    so the step stays linear and non-negative in y). The exact heat kernel never does that
    where φ's peaks are resolved (a Gaussian peak of variance s between two nodes lifts them
    only if h > 2√s); on a grid too coarse for ℓ, ℓ̄'s quadratics bulge above their nodes, and
    without the cap each step would lift the largest value again, a growth of z that can send v
    below zero (README, "Limitations").

    With ``log_out`` the rows of ``y`` are taken to be ones and out[0, p] is the logarithm of
    the integral, log ∫ G_σ φ̄ (capped at L): the reference advanced alone, in the log domain
    (nothing underflows however steep ℓ is)."""
    n_lines = y.shape[1] // n
    n_blocks = min(n_lines, 256)
    uniform = sigma2.size == 1
    reach = _FIT_IMAGES * n
    shared = uniform and sigma2[0] > 0.0  # one Gaussian for every node
    A_shared = h * h / (2.0 * sigma2[0]) if shared else 0.0
    norm_shared = h / math.sqrt(2.0 * math.pi * sigma2[0]) if shared else 0.0
    gaussian = np.zeros(reach + 2)  # e^{−A c²} for the one σ², shared by all lines
    if shared:
        for c in range(reach + 2):
            gaussian[c] = math.exp(-A_shared * c * c)
    for block in prange(n_blocks):
        cells = np.empty((5, n))  # per cell k (nodes k, k + 1): κ, A_c, √A_c, 1/(2A_c), prefactor
        nodes = np.empty(n)  # e^{ℓ_k − L} per node k of the line
        curvature = np.empty(n)  # κ per node of the line
        A, norm = A_shared, norm_shared
        free = top = 0.0
        tables = False
        for line_id in range(block * n_lines // n_blocks, (block + 1) * n_lines // n_blocks):
            line = (line_id // stride) * n * stride + line_id % stride  # no division per node
            rise, bulge, top, low = _line_bounds(ell, line, n, stride, periodic, curvature)
            if shared:
                free = rise / (2.0 * A)
                for k in range(n if periodic else n - 1):
                    kappa = _cell_curvature(curvature, k, n, A)
                    cells[0, k] = kappa
                    cells[1, k], cells[2, k], cells[3, k], cells[4, k] = _cell_constants(A, kappa)
                tables = top - low <= _FIT_TABLE_RANGE
                if tables:
                    for k in range(n):
                        nodes[k] = math.exp(ell[line + k * stride] - top)
            for i in range(n):
                p = line + i * stride
                if not uniform and sigma2[p] > 0.0:
                    A = h * h / (2.0 * sigma2[p])
                    free = rise / (2.0 * A)
                    norm = h / math.sqrt(2.0 * math.pi * sigma2[p])
                if sigma2[0 if uniform else p] <= 0.0:  # no noise at this node: z' = z
                    for r in range(y.shape[0]):
                        out[r, p] = ell[p] if log_out else y[r, p] * math.exp(ell[p])
                    continue
                _diffuse_fitted_node(
                    y,
                    ell,
                    curvature,
                    bulge,
                    ell_max,
                    A,
                    free,
                    norm,
                    n,
                    stride,
                    periodic,
                    log_out,
                    out,
                    line,
                    i,
                    cells,
                    uniform,
                    tables,
                    nodes,
                    gaussian,
                    top,
                )


@jit_inline
def _diffuse_fitted_node(
    y,
    ell,
    curvature,
    bulge,
    ell_max,
    A,
    free,
    norm,
    n,
    stride,
    periodic,
    log_out,
    out,
    line,
    i,
    cells,
    uniform,
    tables,
    nodes,
    gaussian,
    line_top,
):
    """:func:`_diffuse_fitted_kernel` at node i of the line starting at ``line``, for the
    Gaussian's A = h²/(2σ²) there, ``free`` = the line's rise/(2A), ``norm`` = h/√(2πσ²),
    ``bulge`` the line's; ``cells``: the line's cell constants when ``uniform`` (one σ²); with
    ``tables``, ``nodes`` = e^{ℓ_k − L}, ``gaussian`` = e^{−A c²} and ``line_top`` = L (the
    kernel's docstring)."""
    n_rhs = y.shape[0]
    p = line + i * stride
    reach = _FIT_IMAGES * n
    peak = ell[p]  # the largest cell peak so far, which sets the window
    scale = peak  # E: the sums are kept relative to e^E, raised only when a peak passes E + 30
    factor = 1.0 / nodes[i] if tables else 0.0  # e^{L − E}, E = ℓ_i: no exp
    accumulated = False
    mass = 0.0  # log_out: ∫ G_σ φ̄ over e^E (in a register, not in ``out``)
    if not log_out:
        for r in range(n_rhs):
            out[r, p] = 0.0
    for side in range(2):
        step = 1 if side == 0 else -1
        near = i  # unfolded index of the cell's node nearest to x_p, then the far one
        k_near = i
        heading = step  # the direction of the folded index (mirrors turn it round)
        near_log = ell[p]  # the log-integrand at the near node
        near_value = (
            nodes[i] * factor
            if tables  # and the integrand over e^E (−1: not known)
            else math.exp(near_log - scale)
        )
        for c in range(reach):
            far = near + step
            k_far = k_near + heading
            if k_far == n:
                k_far, heading = (0, heading) if periodic else (n - 2, -heading)
            elif k_far == -1:
                k_far, heading = (n - 1, heading) if periodic else (1, -heading)
            gauss = -A * c * c  # the Gaussian's log at the cell's near end
            near_ell, far_ell = ell[line + k_near * stride], ell[line + k_far * stride]
            if gauss + ell_max + bulge < peak - _FIT_WINDOW or (
                c > free and gauss + near_ell + bulge < peak - _FIT_WINDOW
            ):
                break
            far_log = far_ell - A * (far - i) * (far - i)
            if gauss + max(near_ell, far_ell) + bulge < peak - _FIT_WINDOW:  # the cell is out
                near, k_near = far, k_far
                near_log, near_value = far_log, -1.0
                continue
            lo_node, hi_node = (k_near, k_far) if side == 0 else (k_far, k_near)
            a = near - i if side == 0 else far - i  # (the cell's left end − x_p)/h
            k0, k1 = line + lo_node * stride, line + hi_node * stride
            cell = min(lo_node, hi_node)  # its folded index (a periodic line's seam: n − 1)
            if max(lo_node, hi_node) - cell > 1:
                cell = n - 1
            if uniform:
                kappa, Ac, root = cells[0, cell], cells[1, cell], cells[2, cell]
                half_inverse, prefactor = cells[3, cell], cells[4, cell]
            else:
                kappa = _cell_curvature(curvature, cell, n, A)
                Ac, root, half_inverse, prefactor = _cell_constants(A, kappa)
            B = ell[k1] - ell[k0] - 2.0 * A * a - 0.5 * kappa
            C = ell[k0] - A * a * a
            mu = B * half_inverse
            s = min(max(mu, 0.0), 1.0)
            top = C + s * (B - Ac * s)  # the cell's peak
            k_cell_near = k_near
            near, k_near = far, k_far
            if top > peak:
                peak = top
            elif top < peak - _FIT_WINDOW:
                near_log, near_value = far_log, -1.0
                continue
            if top > scale + _FIT_SLACK:  # rescale what is summed so far to e^top
                rescale = math.exp(scale - top)
                mass *= rescale
                if accumulated and not log_out:
                    for r in range(n_rhs):
                        out[r, p] *= rescale
                if near_value >= 0.0:
                    near_value *= rescale
                factor *= rescale
                scale = top
            if tables:
                if near_value < 0.0:
                    near_value = nodes[k_cell_near] * factor * gaussian[c]
                far_value = nodes[k_far] * factor * gaussian[c + 1]
            else:
                if near_value < 0.0:
                    near_value = math.exp(near_log - scale)
                far_value = math.exp(far_log - scale)
            F0, F1 = (near_value, far_value) if side == 0 else (far_value, near_value)
            near_log, near_value = far_log, far_value
            accumulated = True
            total = _cell_mass(root, mu, top, scale, F0, F1, prefactor)
            mass += total
            if log_out:
                continue
            # ∫₀¹ s e^{f} ds from ∫₀¹ (s − μ) e^{f} ds = (e^{f(0)} − e^{f(1)})/(2A_c)
            w1 = max(mu * total + (F0 - F1) * half_inverse, 0.0)
            w0 = max(total - w1, 0.0)
            for r in range(n_rhs):
                out[r, p] += w0 * y[r, k0] + w1 * y[r, k1]
    excess = scale + math.log(mass * norm) - line_top  # log ∫ G_σ φ̄ above the line's top
    if log_out:
        out[0, p] = line_top + min(excess, 0.0)
        return
    norm *= math.exp(scale - max(excess, 0.0))
    for r in range(n_rhs):
        out[r, p] *= norm


def diffuse_fitted_numpy(
    y: np.ndarray,
    ell: np.ndarray,
    variance: float,
    h: float,
    periodic: bool,
    points: int = 64,
    images: int = 3,
) -> np.ndarray:
    """Plain-numpy twin of :func:`_diffuse_fitted_kernel` on one line (``y`` ``(K, n)``, ``ell``
    ``(n,)``): the same integral by the midpoint rule with ``points`` per cell over ``images``
    line lengths to each side, every cell taken (no window), and the kernel's cap at the line's
    largest φ."""
    n = ell.size
    period = n if periodic else 2 * (n - 1)
    if periodic:
        left, centre, right = np.roll(ell, 1), ell, np.roll(ell, -1)
        kappa = left - 2 * centre + right
    else:
        inner = np.clip(np.arange(n), 1, n - 2)
        kappa = ell[inner - 1] - 2 * ell[inner] + ell[inner + 1]
    A = h * h / (2 * variance)
    m = np.arange(-images * n, images * n)
    k = np.mod(m, period)
    k0 = np.where(k > n - 1, period - k, k)
    k = np.mod(m + 1, period)
    k1 = np.where(k > n - 1, period - k, k)
    s = (np.arange(points) + 0.5) / points
    cell_kappa = np.minimum(0.5 * (kappa[k0] + kappa[k1]), A)[:, None]
    log_phi = (1 - s) * ell[k0, None] + s * ell[k1, None] - 0.5 * cell_kappa * s * (1 - s)
    y_bar = (1 - s) * y[:, k0, None] + s * y[:, k1, None]
    out = np.empty_like(y, dtype=float)
    for i in range(n):
        x = (m[:, None] - i + s) * h
        weight = np.exp(-x * x / (2 * variance) + log_phi) * h / points
        reference = weight.sum() / np.sqrt(2 * np.pi * variance)  # ∫ G_σ φ̄, capped at e^{max ℓ}
        cap = min(1.0, np.exp(ell.max()) / reference)
        out[:, i] = cap * (y_bar * weight).sum(axis=(1, 2)) / np.sqrt(2 * np.pi * variance)
    return out


@jit_parallel
def _cost_max_kernel(z, cost, block_max):
    """z[r] *= cost (when ``cost`` is not empty); block_max[r, b] = max of z[r] over block b."""
    n_rhs, n_nodes = z.shape
    n_blocks = block_max.shape[1]
    use_cost = cost.size > 0
    for b in prange(n_blocks):
        for r in range(n_rhs):
            peak = 0.0
            for p in range(b * n_nodes // n_blocks, (b + 1) * n_nodes // n_blocks):
                if use_cost:
                    z[r, p] *= cost[p]
                peak = max(peak, z[r, p])
            block_max[r, b] = peak


def _diffusion_coefficients(problem: Problem) -> list:
    """D_k = ½ (λ B R⁻¹ Bᵀ)_kk of every axis k, the noise evaluated once per chunk of nodes: a
    float where D_k is the same at every node (no per-node array is then stored), else the
    ``(N,)`` array."""
    grid = problem.grid
    first = None
    columns = [None] * grid.ndim
    for flat in _flat_chunks(grid.size):
        diffusion = 0.5 * problem.noise_diagonal(grid.node_coordinates(flat))
        if first is None:
            first = diffusion[0].copy()
        for k in range(grid.ndim):
            if columns[k] is None and np.all(diffusion[:, k] == first[k]):
                continue
            if columns[k] is None:  # varies: the chunks before held the first value throughout
                columns[k] = np.full(grid.size, first[k])
            columns[k][flat[0] : flat[-1] + 1] = diffusion[:, k]
    return [float(first[k]) if column is None else column for k, column in enumerate(columns)]


class SplittingStep:
    """The splitting step operator of a problem and time step, built once per solve.

    Call ``step(z, out, scale)``: writes ``out = S(scale · z)`` for ``z`` ``(K, N)`` and the
    per-row factors ``scale`` ``(K,)``, and returns the per-row maximum of ``out``. Its
    ``diffusion`` holds D_k = ½ (λ B R⁻¹ Bᵀ)_kk per axis: a float where it is the same at every
    node, else one value per node.
    """

    name = "splitting"
    supports_fitting = True

    def __init__(self, problem: Problem, dt: float, feet: str = "compact"):
        if feet not in FEET_LAYOUTS:
            raise ValueError(f"feet must be one of {FEET_LAYOUTS}, got {feet!r}")
        grid = problem.grid
        if feet == "compact" and grid.ndim > _MAX_COMPACT_DIM:
            feet = "table"
        if grid.size >= 2**31:
            raise ValueError(f"grid {grid.describe()} has ≥ 2³¹ nodes: int32 indices overflow")
        self.grid, self.layout = grid, feet
        self._encode_feet(problem, dt)
        self._setup_diffusion(problem, 0.5 * dt)
        q = _node_values(problem.state_cost_values, grid)
        lam = problem.temperature
        if np.any(q != 0):  # Simpson's rule along the characteristic (module docstring)
            self.log_cost = -q * dt / (6.0 * lam)
            self.log_mid_cost = (-2.0 * dt / (3.0 * lam)) * _node_values(
                lambda x: problem.state_cost_values(_foot(problem, x, 0.5 * dt)), grid
            )
        else:
            self.log_cost = self.log_mid_cost = np.empty(0)
        self.cost_factor = np.exp(self.log_cost)
        self.mid_cost_factor = np.exp(self.log_mid_cost)
        self._buffers = {}
        self._stencils = None  # where the Hessian's stencils sit (_stencils; first fitted step)
        self._correction = None  # the curvature term's default output (first call without one)
        self.iterations: list[int] = []  # direct tridiagonal solves: no iterations

    @staticmethod
    def estimate_bytes(grid: Grid, feet: str = "compact") -> int:
        """Memory of the operator for ``grid``, without building it (for the memory check)."""
        batch = min(grid.size, _FEET_BATCH) * (24 * grid.ndim + 16)  # feet, vertices, weights
        return grid.size * (feet_bytes_per_node(grid.ndim, feet) + 8) + batch

    def _encode_feet(self, problem: Problem, dt: float):
        grid, N, d = self.grid, self.grid.size, self.grid.ndim
        if self.layout == "compact":
            self.base = np.empty(N, dtype=np.int32)
            shapes = np.empty(N, dtype=np.uint32)
            self.frac = np.empty((N, d), dtype=np.uint16)
        else:
            self.idx = np.empty((N, d + 1), dtype=np.int32)
            self.weights = np.empty((N, d + 1), dtype=np.float32)
        batch = min(N, _FEET_BATCH)
        feet = np.empty((batch, d))
        if self.layout == "table":
            idx = np.empty((batch, d + 1), dtype=np.int64)
            weights = np.empty((batch, d + 1))
        walk = _walk_steps(grid)
        for start in range(0, N, batch):
            stop = min(start + batch, N)
            m = stop - start
            for flat, chunk in _foot_chunks(problem, dt, start, stop):
                feet[flat[0] - start : flat[-1] + 1 - start] = chunk
            finite = np.isfinite(feet[:m]).all(axis=1)
            if not finite.all():
                node = start + int(np.argmin(finite))
                raise ValueError(
                    f"the characteristic foot of node {node} (x = {grid.node_coordinates(node)}) is "
                    f"not finite: {type(problem.system).__name__}.drift returned a non-finite value"
                )
            rows = slice(start, stop)
            if self.layout == "compact":
                _encode_compact_kernel(
                    feet[:m],
                    *grid.kernel_arrays(),
                    walk,
                    self.base[rows],
                    shapes[rows],
                    self.frac[rows],
                )
            else:
                _kuhn_kernel(feet[:m], *grid.kernel_arrays(), idx[:m], weights[:m])
                self.idx[rows], self.weights[rows] = idx[:m], weights[:m]
        if self.layout == "compact":
            distinct, ids = _shape_codes(grid, shapes)
            self.code = ids.astype(np.uint16 if distinct.size <= 2**16 else np.uint32)
            self.offsets = _vertex_offsets(grid, distinct)
            self.arrays = [self.base, self.code, self.frac, self.offsets]
        else:
            self.arrays = [self.idx, self.weights]

    def _setup_diffusion(self, problem: Problem, dt: float):
        grid = self.grid
        self.noise = []  # (axis, periodic, data, uniform)
        self.variances = []  # per noise axis: σ² = 2 D_k Δt of the half step (one, or per node)
        self.diffusion = _diffusion_coefficients(problem)  # D_k: a float, or one per node
        for k, (ax, diffusion) in enumerate(zip(grid.axes, self.diffusion, strict=True)):
            if not np.any(diffusion > 0):
                continue
            ratio = dt * diffusion / ax.spacing**2
            variance = 2.0 * dt * diffusion
            constant = np.ndim(diffusion) == 0
            if constant or np.all(variance == variance[0]):
                self.variances.append(np.full(1, variance) if constant else variance[:1])
            else:
                self.variances.append(variance)
            if ax.periodic:
                self.noise.append(
                    (k, True, np.full(grid.size, ratio) if constant else ratio, False)
                )
                continue
            if constant:
                self.noise.append((k, False, tridiagonal_factors(np.full(ax.n, ratio), ax.n), True))
                continue
            lines = np.moveaxis(grid.reshape(ratio), k, -1)
            uniform = bool(np.all(lines == lines.reshape(-1, ax.n)[0]))
            if uniform:
                factors = tridiagonal_factors(lines.reshape(-1, ax.n)[0], ax.n)
            else:
                factors = np.moveaxis(tridiagonal_factors(lines, ax.n), -1, k + 1)
                factors = factors.reshape(3, grid.size)
            self.noise.append((k, False, np.ascontiguousarray(factors), uniform))

    @property
    def nbytes(self) -> int:
        arrays = [
            *self.arrays,
            self.cost_factor,
            self.log_cost,
            self.mid_cost_factor,
            self.log_mid_cost,
            *(data for _, _, data, _ in self.noise),
            *self.variances,
            *(a for a in self.diffusion if np.ndim(a)),
        ]
        return int(sum(a.nbytes for a in arrays))

    def __call__(self, z: np.ndarray, out: np.ndarray, scale: np.ndarray) -> np.ndarray:
        """out = C D½ M P D½ C (scale · z), the plain step; ``z`` is consumed (overwritten).
        Returns the row maxima of ``out``. (The fitted operator is composed over all steps by
        the solver, from :meth:`drift` and :meth:`fitted_diffusion`.)"""
        K = z.shape[0]
        if self.cost_factor.size:
            z *= self.cost_factor
        self._half_diffusion(z, None)
        self.drift(z, out, scale)
        if self.mid_cost_factor.size:
            out *= self.mid_cost_factor
        block_max = None
        if self.cost_factor.size == 0 and self.noise and not self.noise[-1][1]:
            # no state cost: fuse the slice maximum into the last (closed-axis) diffusion pass
            k = self.noise[-1][0]
            n_tasks = closed_line_tasks(
                self.grid.size, self.grid.axes[k].n, int(self.grid.strides[k])
            )
            block_max = self._buffer(K, work_blocks(n_tasks))
        self._half_diffusion(out, block_max)
        if block_max is None:
            return self.row_maxima(out, cost=True)
        return block_max.max(axis=1)

    def drift(
        self, z: np.ndarray, out: np.ndarray, scale: np.ndarray, reference: int | None = None
    ):
        """out = P (scale · z): the semi-Lagrangian drift alone, fitted to row ``reference`` of
        ``z`` when it is given (``z`` is then consumed: divided by that row in place). The
        reference row fitted to itself needs no gather of z, only of log φ: P_φ φ = φ̄."""
        ones_row = -1
        if reference is None:
            ell = np.empty(0)
        else:
            ell = self._buffer(1, self.grid.size)[0]  # log φ of the reference
            if _fitting_kernel(z, reference, ell) == 0:
                ones_row = reference
        if self.layout == "compact":
            _advect_compact_kernel(
                z, self.base, self.code, self.frac, self.offsets, scale, ell, ones_row, out
            )
        else:
            _advect_table_kernel(z, self.idx, self.weights, scale, ell, ones_row, out)
        if reference is not None:
            out *= np.exp(self.curvature_correction(ell))

    def curvature_correction(
        self, ell: np.ndarray, out: np.ndarray | None = None, add_mean: bool = False
    ) -> np.ndarray:
        """The curvature term c(X) = −½ Σ_ab M_ab(X) H_ab of the fitted drift at every node's
        foot X (see the module docstring): ``log φ̄ = Σ_j w_j ℓ(y_j) + c``; with ``add_mean``,
        log φ̄ itself (the fitted log drift in one pass). Written into ``out`` ``(N,)``, by
        default a scratch array (overwritten by the next call), which is returned."""
        grid = self.grid
        record = self._stencils is None
        if record:
            self._stencils = _stencils(grid)
            self._places = np.empty(
                grid.size if self.layout == "compact" else 0, self._stencils[0].dtype
            )
            self._pairs = _hessian_pairs(grid.ndim)
            if self.layout == "compact":
                self._columns = _hessian_columns(_walk_axes(grid, self.offsets), self._pairs)
        if out is None:
            if self._correction is None:
                self._correction = np.empty(grid.size)
            out = self._correction
        if self.layout == "compact":
            _curvature_compact_kernel(
                ell,
                self.base,
                self.code,
                self.frac,
                self.offsets,
                self._columns,
                *self._stencils,
                record,
                self._places,
                add_mean,
                out,
            )
        else:
            _curvature_table_kernel(
                ell,
                self.idx,
                self.weights,
                *self._stencils,
                np.array(grid.shape, dtype=np.int64),
                grid.strides,
                self._pairs,
                add_mean,
                out,
            )
        return out

    def log_drift(self, ell: np.ndarray, out: np.ndarray):
        """out = log M P_z z for ℓ = log z (``(1, N)``, consumed): the drift fitted to z itself,
        in the log domain. That is the value-space semi-Lagrangian update ℓ(x) ← Σ_j w_j ℓ(y_j)
        with the curvature term, then the middle share of the state cost (Simpson's rule)."""
        self.curvature_correction(ell[0], out[0], add_mean=True)
        if self.log_mid_cost.size:
            out[0] += self.log_mid_cost

    def log_diffusion(self, ell: np.ndarray, spares: tuple, full: bool = False) -> np.ndarray:
        """log D z for ℓ = log z (``(1, N)``, not written): the diffusion fitted to z itself,
        log ∫ G_σ e^ℓ̄ along each noise axis in turn, over half a step (σ² = 2 D_k Δt/2) or,
        with ``full``, a whole one (σ² = 2 D_k Δt: two half steps in one pass, the Gaussian's
        semigroup). The passes alternate between the two arrays ``spares``; returns the one that
        holds the result."""
        source = ell
        for axis, noise in enumerate(zip(self.noise, self.variances, strict=True)):
            target = spares[axis % 2]
            self._fitted_pass(noise, source, source[0], full, True, target)
            source = target
        return source

    def fitted_diffusion(
        self, z: np.ndarray, spare: np.ndarray, reference: int, full: bool = False
    ) -> np.ndarray:
        """D fitted to row ``reference`` (see the module docstring) over half a step or, with
        ``full``, a whole one (as :meth:`log_diffusion`), one noise axis at a time, alternating
        between ``z`` and ``spare`` (both are overwritten). Returns the array that holds the
        result: ``spare`` after an odd number of noise axes, ``z`` after an even one."""
        source, target = z, spare
        ell = self._buffer(1, self.grid.size)[0]
        for noise in zip(self.noise, self.variances, strict=True):
            _fitting_kernel(source, reference, ell)
            self._fitted_pass(noise, source, ell, full, False, target)
            source, target = target, source
        return source

    def _fitted_pass(
        self,
        noise,
        source: np.ndarray,
        ell: np.ndarray,
        full: bool,
        log_out: bool,
        target: np.ndarray,
    ):
        """One noise axis (``noise`` = (an entry of :attr:`noise`, its variances)) of the fitted
        diffusion of ``source`` with log φ = ``ell``, into ``target``
        (:func:`_diffuse_fitted_kernel`)."""
        (k, periodic, _, _), variance = noise
        ax, stride = self.grid.axes[k], int(self.grid.strides[k])
        _diffuse_fitted_kernel(
            source,
            ell,
            float(ell.max()),
            variance * (2.0 if full else 1.0),
            ax.spacing,
            ax.n,
            stride,
            periodic,
            log_out,
            target,
        )

    def row_maxima(self, z: np.ndarray, cost: bool = False) -> np.ndarray:
        """The row maxima of ``z`` ``(K, N)``, after multiplying it by the nodes' share of the
        state cost C when ``cost`` (one pass)."""
        block_max = self._buffer(z.shape[0], work_blocks(self.grid.size))
        _cost_max_kernel(z, self.cost_factor if cost else self.cost_factor[:0], block_max)
        return block_max.max(axis=1)

    def _half_diffusion(self, z: np.ndarray, block_max: np.ndarray | None):
        """D½ in place on every noise axis; the last pass also records row maxima per block in
        ``block_max`` when it is given (otherwise a zero-width buffer turns that off)."""
        K = z.shape[0]
        for position, (k, periodic, data, uniform) in enumerate(self.noise):
            ax, stride = self.grid.axes[k], int(self.grid.strides[k])
            if periodic:
                _diffuse_periodic_kernel(z, data, ax.n, stride)
                continue
            last = position == len(self.noise) - 1 and block_max is not None
            _diffuse_closed_kernel(
                z, data, uniform, ax.n, stride, block_max if last else self._buffer(K, 0)
            )

    def _buffer(self, rows: int, columns: int) -> np.ndarray:
        """A scratch array of this shape, allocated (zeroed) once and reused by later steps."""
        key = (rows, columns)
        if key not in self._buffers:
            self._buffers[key] = np.zeros(key)
        return self._buffers[key]
