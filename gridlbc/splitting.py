"""Semi-Lagrangian operator splitting for the linear Bellman PDE (SPEC §3).

One backward step from t + Δt to t applies three linear, monotone operators to z(·, t + Δt):

1. drift along characteristics: z*(x) = z(X(x)) with the second-order (midpoint) foot
   X(x) = x + Δt a(x + ½Δt a(x)), evaluated by barycentric interpolation (weights ≥ 0, sum 1);
   feet are wrapped on periodic axes and clamped to the box on the others;
2. diffusion, implicitly, one noise axis k at a time:
   (I − Δt D_k(x) δ²_k) z** = z*,  D_k = ½ (λ B R⁻¹ Bᵀ)_kk, δ²_k the three-point second difference;
   each line is a tridiagonal M-matrix (cyclic on a periodic axis; on a closed axis the jumps out
   of the box are suppressed, a reflecting state constraint);
3. the state cost exactly: z(·, t) = exp(−q Δt/λ) z**.

Every stage maps non-negative z to non-negative z and constants to constants (before the cost),
so the step is the transition of a Markov chain, and it is unconditionally stable: Δt is limited
by accuracy, not by a CFL condition. Numerical diffusion is O(h²/Δt) from the interpolation plus
O(Δt) from the splitting and the foot, far less than the O(|a| h) of first-order upwinding.
"""

from __future__ import annotations

import numpy as np

from ._numba import jit_parallel, prange
from .interpolate import barycentric
from .problem import Problem

_CHUNK = 64  # lines solved side by side in one task of the tridiagonal kernel


@jit_parallel
def _advect_kernel(z, idx, weights, out):
    n_rhs, n_nodes = z.shape
    n_vertices = idx.shape[1]
    for p in prange(n_nodes):
        for r in range(n_rhs):
            acc = 0.0
            for j in range(n_vertices):
                acc += weights[p, j] * z[r, idx[p, j]]
            out[r, p] = acc


@jit_parallel
def _diffuse_closed_kernel(z, ratio, n, stride, chunk):
    """Solve (1 + 2r_i) z_i − r_i (z_{i−1} + z_{i+1}) = rhs_i on every line of one closed axis.

    ``ratio`` is r = Δt D / h² per node; at the two ends the out-of-box neighbour is dropped
    (row 0: (1 + r_0) z_0 − r_0 z_1). Thomas algorithm, in place, ``chunk`` lines side by side
    so that memory is read contiguously whatever the axis.
    """
    n_rhs, n_nodes = z.shape
    n_outer = n_nodes // (n * stride)
    n_chunks = (stride + chunk - 1) // chunk
    for task in prange(n_rhs * n_outer * n_chunks):
        r_idx = task // (n_outer * n_chunks)
        rest = task % (n_outer * n_chunks)
        base = (rest // n_chunks) * n * stride
        j0 = (rest % n_chunks) * chunk
        width = min(stride, j0 + chunk) - j0
        cp = np.empty((n, width))
        for i in range(n):
            for jj in range(width):
                node = base + i * stride + j0 + jj
                r = ratio[node]
                lower = -r if i > 0 else 0.0
                upper = -r if i < n - 1 else 0.0
                diag = 1.0 - lower - upper
                if i == 0:
                    m = diag
                    z[r_idx, node] = z[r_idx, node] / m
                else:
                    m = diag - lower * cp[i - 1, jj]
                    z[r_idx, node] = (z[r_idx, node] - lower * z[r_idx, node - stride]) / m
                cp[i, jj] = upper / m
        for i in range(n - 2, -1, -1):
            for jj in range(width):
                node = base + i * stride + j0 + jj
                z[r_idx, node] -= cp[i, jj] * z[r_idx, node + stride]


@jit_parallel
def _diffuse_periodic_kernel(z, ratio, n, stride):
    """The cyclic version of :func:`_diffuse_closed_kernel`, by Sherman–Morrison per line."""
    n_rhs, n_nodes = z.shape
    n_outer = n_nodes // (n * stride)
    for task in prange(n_rhs * n_outer * stride):
        r_idx = task // (n_outer * stride)
        rest = task % (n_outer * stride)
        base = (rest // stride) * n * stride + rest % stride
        a = np.empty(n)
        b = np.empty(n)
        y = np.empty(n)
        q = np.zeros(n)
        for i in range(n):
            rr = ratio[base + i * stride]
            a[i] = -rr
            b[i] = 1.0 + 2.0 * rr
            y[i] = z[r_idx, base + i * stride]
        # A = T + u vᵀ with T tridiagonal: u = (γ, 0…0, c_{n−1}), v = (1, 0…0, a_0/γ).
        gamma = -b[0]
        corner_low = a[0]  # A[0, n−1]
        corner_up = a[n - 1]  # A[n−1, 0] (symmetric stencil: c_{n−1} = a_{n−1})
        bb = b.copy()
        bb[0] -= gamma
        bb[n - 1] -= corner_up * corner_low / gamma
        q[0] = gamma
        q[n - 1] = corner_up
        cp = np.empty(n)
        # Thomas on T for y and q together (sub- and super-diagonal both equal a[i] / a[i+1]).
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
        factor = (y[0] + corner_low / gamma * y[n - 1]) / (1.0 + q[0] + corner_low / gamma * q[n - 1])
        for i in range(n):
            z[r_idx, base + i * stride] = y[i] - factor * q[i]


def characteristic_feet(problem: Problem, dt: float) -> np.ndarray:
    """Feet X(x) = x + Δt a(x + ½Δt a(x)) of all nodes, wrapped and clamped to the box."""
    grid, system = problem.grid, problem.system
    x = grid.nodes()
    midpoint = grid.clamp(x + 0.5 * dt * system.drift(x))
    return grid.clamp(x + dt * system.drift(midpoint))


class SplittingStep:
    """The splitting step operator of a problem and time step, built once per solve."""

    name = "splitting"

    def __init__(self, problem: Problem, dt: float):
        grid = problem.grid
        self.grid = grid
        self.idx, self.weights = barycentric(grid, characteristic_feet(problem, dt))
        diffusion = 0.5 * problem.noise_diagonal(grid.nodes())  # D_k = ½ Σ_kk
        self.noise_axes = [k for k in range(grid.ndim) if np.any(diffusion[:, k] > 0)]
        self.ratios = {k: dt * diffusion[:, k] / grid.spacing[k] ** 2 for k in self.noise_axes}
        self.cost_factor = np.exp(-problem.state_cost_values() * dt / problem.temperature)
        self.has_cost = bool(np.any(self.cost_factor != 1.0))
        self._buffer = None

    @property
    def nbytes(self) -> int:
        arrays = [self.idx, self.weights, self.cost_factor, *self.ratios.values()]
        return int(sum(a.nbytes for a in arrays))

    def __call__(self, z: np.ndarray) -> np.ndarray:
        """One backward step of nodal values ``z`` ``(K, N)``; returns a new ``(K, N)`` array."""
        out = np.empty_like(z)
        _advect_kernel(z, self.idx, self.weights, out)
        for k in self.noise_axes:
            ax = self.grid.axes[k]
            stride = int(self.grid.strides[k])
            if ax.periodic:
                _diffuse_periodic_kernel(out, self.ratios[k], ax.n, stride)
            else:
                _diffuse_closed_kernel(out, self.ratios[k], ax.n, stride, _CHUNK)
        if self.has_cost:
            out *= self.cost_factor
        return out
