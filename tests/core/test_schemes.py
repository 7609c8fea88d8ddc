"""Large-grid solver paths: kernels against numpy references, every method against the exact
LQ solution and the backward-Euler reference in 2D/3D/4D, superposition on every storage and
solver path, float32 flush accounting, memory-mapped slices and the memory check."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from conftest import EXACTNESS_ONLY

import gridlbc
from gridlbc import Axis, Grid, Problem, Quadratic
from gridlbc.interpolate import barycentric
from gridlbc.reference import lq_solution
from gridlbc.schemes.implicit import ImplicitStep
from gridlbc.schemes.splitting import SplittingStep, characteristic_feet, tridiagonal_factors
from gridlbc.systems import Acrobot, SingleIntegrator
from gridlbc.systems.base import ControlAffineSystem, LinearSystem


def _chain(d: int) -> LinearSystem:
    """d = 2: a point mass; d = 3: a triple integrator; d = 4: two point masses (2 controls)."""
    if d == 4:
        A = np.kron(np.eye(2), [[0.0, 1.0], [0.0, 0.0]])
        B = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [0.0, 1.0]])
        return LinearSystem(A, B)
    A = np.eye(d, k=1)
    B = np.zeros((d, 1))
    B[-1, 0] = 1.0
    return LinearSystem(A, B)


def _lq_problem(d: int, n: int, horizon: float = 0.5, half_width: float = 3.0) -> Problem:
    grid = Grid([Axis(-half_width, half_width, n)] * d)
    return Problem(
        _chain(d), grid, horizon, Quadratic(np.full(d, 0.3), np.ones(d)), temperature=0.5
    )


class _VaryingNoise(ControlAffineSystem):
    """A 2D system whose input gain depends on the state: non-uniform tridiagonal lines."""

    state_dim, control_dim = 2, 1

    def drift(self, x):
        x = self._states(x)
        return np.stack([x[:, 1], -np.sin(x[:, 0])], axis=1)

    def input_matrix(self, x):
        x = self._states(x)
        B = np.zeros((x.shape[0], 2, 1))
        B[:, 1, 0] = 1.0 + 0.5 * np.cos(x[:, 0])
        return B


def _sparse_step(problem: Problem, dt: float) -> np.ndarray:
    """The splitting step as one dense float64 matrix, D½ ∘ interpolation ∘ D½ (numpy/scipy),
    with D½ the half-step diffusion solve along each noise axis (no state cost here)."""
    grid = problem.grid
    idx, w = barycentric(grid, characteristic_feet(problem, dt))
    rows = np.repeat(np.arange(grid.size), w.shape[1])
    interpolation = sp.csr_matrix((w.ravel(), (rows, idx.ravel())), shape=(grid.size,) * 2)
    D = 0.5 * problem.noise_diagonal(grid.nodes())
    half = np.identity(grid.size)
    for k, ax in enumerate(grid.axes):
        if not np.any(D[:, k] > 0):
            continue
        r = 0.5 * dt * D[:, k] / ax.spacing**2
        i = np.unravel_index(np.arange(grid.size), grid.shape)[k]
        s = int(grid.strides[k])
        up, down = i < ax.n - 1, i > 0
        off = sp.csr_matrix(
            (
                np.concatenate([-r[up], -r[down]]),
                (
                    np.concatenate([np.flatnonzero(up), np.flatnonzero(down)]),
                    np.concatenate([np.flatnonzero(up) + s, np.flatnonzero(down) - s]),
                ),
            ),
            shape=(grid.size,) * 2,
        )
        diag = sp.diags(1.0 + r * up + r * down)
        half = spla.spsolve((diag + off).tocsc(), half)
    return half @ (interpolation @ half)


@pytest.mark.parametrize("feet", ["compact", "table"])
@pytest.mark.parametrize("system", ["pointmass", "varying", "acrobot"])
def test_step_kernels_match_the_numpy_step(feet, system, rng):
    if system == "acrobot":
        grid = Grid([Axis(-np.pi, np.pi, 5, periodic=True)] * 2 + [Axis(-8, 8, 5), Axis(-4, 4, 6)])
        problem = Problem(Acrobot(), grid, 1.0, Quadratic(np.zeros(4), [1, 1, 0.1, 0.1]))
    elif system == "varying":
        grid = Grid([Axis(-np.pi, np.pi, 12, periodic=True), Axis(-3, 3, 9)])
        problem = Problem(_VaryingNoise(), grid, 1.0, Quadratic([0, 0], [1, 1]))
    else:
        problem = _lq_problem(2, 11)
    dt = 0.07
    reference = _sparse_step(problem, dt)
    step = SplittingStep(problem, dt, feet=feet)
    z = rng.random((2, problem.grid.size))
    scale = np.array([1.0, 0.25])
    out = np.empty_like(z)
    expected = (reference @ (z * scale[:, None]).T).T
    peak = step(z, out, scale)  # consumes z
    # Table: float32 weights (relative rounding 2⁻²⁴ each, d+1 of them). Compact: the foot moves
    # by ≤ 1/(2·65535) cell per axis, so the result moves by ≤ d/131070 · max jump of z between
    # neighbouring nodes (≤ 1 for uniform random z in [0, 1)) — then the diffusion (a
    # contraction in max norm) can only shrink either error.
    d = problem.grid.ndim
    tol = (d + 1) * 2.0**-24 * 2 if feet == "table" else d / 131070
    np.testing.assert_allclose(out, expected, rtol=0, atol=tol * scale[:, None].max())
    np.testing.assert_array_equal(peak, out.max(axis=1))


def test_tridiagonal_factors_solve_the_line_system(rng):
    n = 9
    r = rng.random(n)
    factors = tridiagonal_factors(r, n)
    b = rng.random(n)
    y = np.empty(n)
    for i in range(n):
        y[i] = b[i] * factors[0, i] + (factors[1, i] * y[i - 1] if i else 0.0)
    for i in range(n - 2, -1, -1):
        y[i] -= factors[2, i] * y[i + 1]
    A = np.diag(1 + 2 * r) - np.diag(r[1:], -1) - np.diag(r[:-1], 1)
    A[0, 0], A[-1, -1] = 1 + r[0], 1 + r[-1]
    np.testing.assert_allclose(A @ y, b, rtol=1e-13, atol=1e-13)


@EXACTNESS_ONLY
@pytest.mark.parametrize(
    "d, sizes, half_width", [(2, (33, 65), 3.0), (3, (17, 33), 3.0), (4, (9, 17), 2.0)]
)
@pytest.mark.parametrize("method", ["splitting", "fitted", "implicit"])
def test_methods_converge_to_the_exact_lq_value(d, sizes, half_width, method):
    """All schemes are first order in h with Δt ∝ h (upwind: O(h + Δt); semi-Lagrangian, plain
    or fitted: O(h²/Δt + Δt)): halving h and Δt must halve the max error near the goal. Measured
    ratios are 1.8–2.4; the check asks for ≥ 1.6 (observed order ≥ 0.68) to allow for the coarse
    grids."""
    options = {"fitting": "terminal"} if method == "fitted" else {"method": method}
    x = np.random.default_rng(3).uniform(-0.5, 0.5, (40, d)) + 0.3
    errors = []
    for n in sizes:
        problem = _lq_problem(d, n, half_width=half_width)
        h = problem.grid.spacing[0]
        exact = lq_solution(problem).value(x, 0.0)
        solution = gridlbc.solve(problem, dt=h / 2, **options)
        errors.append(np.abs(solution.value(x, 0.0) - exact).max())
    assert errors[0] / errors[1] > 1.6, errors


@EXACTNESS_ONLY
@pytest.mark.parametrize(
    "grid",
    [
        Grid([Axis(-np.pi, np.pi, 16, periodic=True), Axis(-6, 6, 17)]),
        Grid([Axis(-np.pi, np.pi, 6, periodic=True)] * 2 + [Axis(-8, 8, 7), Axis(-4, 4, 7)]),
    ],
    ids=["2d", "4d"],
)
def test_iterative_solvers_agree_with_the_direct_implicit_step(grid):
    """Same discrete operator: Gauss–Seidel stops when a sweep changes z by ≤ tol·max z, so its
    error is ≤ ρ/(1 − ρ)·tol·max z (ρ the contraction); BiCGSTAB's relative residual is ≤ tol,
    an error ≤ cond(A)·tol (cond ≤ (1 + ρ)/(1 − ρ) in the max norm for this M-matrix)."""
    from gridlbc.systems import Pendulum

    system = Pendulum() if grid.ndim == 2 else Acrobot()
    problem = Problem(system, grid, 0.3, Quadratic(np.zeros(grid.ndim), np.ones(grid.ndim)))
    solutions = {
        ls: gridlbc.solve(problem, dt=0.03, method="implicit", linear_solver=ls)
        for ls in ("direct", "gauss-seidel", "bicgstab")
    }
    step = ImplicitStep(problem, 0.03, linear_solver="gauss-seidel")
    rho = step.contraction
    z = {ls: s.slices[0] * np.exp(s.log_scales[0]) for ls, s in solutions.items()}
    steps = solutions["direct"].diagnostics.steps
    tol = steps * 1e-10 * (1 + rho) / (1 - rho) * z["direct"].max()
    np.testing.assert_allclose(z["gauss-seidel"], z["direct"], rtol=0, atol=tol)
    np.testing.assert_allclose(z["bicgstab"], z["direct"], rtol=0, atol=tol)
    assert np.all(solutions["gauss-seidel"].slices >= 0)
    assert len(solutions["gauss-seidel"].diagnostics.iterations) == steps


def _superposition_case():
    grid = Grid([Axis(-np.pi, np.pi, 24, periodic=True), Axis(-5, 5, 21)])
    from gridlbc.systems import Pendulum

    g1 = Quadratic([0.0, 0.0], [2.0, 0.2], periods=grid.periods)
    g2 = Quadratic([1.0, 0.5], [1.0, 0.3], periods=grid.periods)
    lam = 0.7

    def g_sum(x):  # −λ log(e^{−g1/λ} + e^{−g2/λ})
        return -lam * np.logaddexp(-g1(x) / lam, -g2(x) / lam)

    problem = Problem(Pendulum(), grid, 0.5, g1, temperature=lam)
    return problem, g1, g2, g_sum


@pytest.mark.parametrize(
    "options",
    [
        {"method": "splitting", "fitting": None},
        {"method": "splitting", "fitting": None, "dtype": "float32"},
        {"method": "splitting", "fitting": None, "store_every": 3},
        {"method": "splitting", "fitting": "g1"},
        {"method": "implicit", "linear_solver": "direct"},
        {"method": "implicit", "linear_solver": "direct", "dtype": "float32"},
        {"method": "implicit", "linear_solver": "gauss-seidel"},
    ],
    ids=["split64", "split32", "split-every3", "fitted", "direct64", "direct32", "gauss-seidel"],
)
@EXACTNESS_ONLY
def test_superposition_on_every_path(options, tmp_path):
    """z for h1 + h2 equals z1 + z2 at every stored time. The stepping is linear, so the only
    differences are rounding: float64 steps contribute ~steps·ε₆₄ relative, float32 storage one
    rounding per stored value (2⁻²⁴ relative) of each of the three; Gauss–Seidel is linear only up
    to its stopping tolerance (1e-10 · ρ/(1 − ρ) per step). The fitted drift is linear for its
    fixed reference (here g1, shared by all three solves)."""
    problem, g1, g2, g_sum = _superposition_case()
    if options.get("fitting") == "g1":
        options = {**options, "fitting": g1}
    parts = gridlbc.solve_many(problem, [g1, g2], dt=0.05, **options)
    whole = gridlbc.solve(problem.replace(terminal_cost=g_sum), dt=0.05, **options)
    assert len(whole.times) == len(parts[0].times)
    if options.get("linear_solver") == "gauss-seidel":
        rtol = 1e-10 * 10 * 20
    elif options.get("dtype") == "float32":
        rtol = 4 * 2.0**-24
    else:
        rtol = 1e-12
    for j in range(len(whole.times)):
        z = [s.slices[j].astype(float) * np.exp(s.log_scales[j]) for s in (*parts, whole)]
        np.testing.assert_allclose(z[2], z[0] + z[1], rtol=rtol, atol=rtol * z[2].max() * 1e-3)
    # off the grid too: scaled fields are linear in the nodal z
    x = np.array([[0.3, 0.2], [-2.0, 1.0], [3.0, -4.0]])
    fields = [s.scaled_fields(x, 0.21) for s in (*parts, whole)]
    zs = [np.exp(L) * z for L, z, _ in fields]
    gs = [np.exp(L) * g for L, _, g in fields]
    np.testing.assert_allclose(zs[2], zs[0] + zs[1], rtol=10 * rtol)
    np.testing.assert_allclose(
        gs[2], gs[0] + gs[1], rtol=10 * rtol, atol=1e-9 * np.abs(gs[2]).max()
    )


@EXACTNESS_ONLY
def test_float32_flushes_are_counted_and_mmap_storage_is_identical(tmp_path):
    """g = 100 x² makes z(x, T) = e^{−100x²} < 1.4e-45 (float32's smallest) for |x| > 1.02 while
    float64 keeps it down to |x| ≈ 2.7: those values are counted, not silently zeroed."""
    grid = Grid([Axis(-4.0, 4.0, 81)])
    problem = Problem(SingleIntegrator(), grid, 0.2, Quadratic([0.0], [100.0]), temperature=1.0)
    plain = {"dt": 0.02, "fitting": None}  # the fitted solve stores log z, which never flushes
    wide = gridlbc.solve(problem, **plain)
    narrow = gridlbc.solve(problem, **plain, dtype="float32")
    mapped = gridlbc.solve(problem, **plain, dtype="float32", mmap_dir=str(tmp_path))
    flushed = np.count_nonzero((wide.slices > 0) & (wide.slices.astype(np.float32) == 0))
    assert flushed > 0
    assert narrow.diagnostics.flushed_values == flushed
    assert wide.diagnostics.flushed_values == 0
    np.testing.assert_array_equal(mapped.slices, narrow.slices)
    assert isinstance(mapped.slices, np.memmap)
    assert narrow.nbytes < wide.nbytes and narrow.diagnostics.memory_estimate > 0


@EXACTNESS_ONLY
def test_store_every_interpolates_linearly_in_time():
    problem = _lq_problem(2, 21)
    every = gridlbc.solve(problem, dt=0.05, fitting=None)  # stores z (a fitted solve: log z)
    sparse = gridlbc.solve(problem, dt=0.05, fitting=None, store_every=4)
    np.testing.assert_allclose(sparse.times, [0.0, 0.2, 0.4, 0.5])
    x = np.array([[0.2, -0.1], [1.0, 0.5]])
    # at stored times both agree exactly; between them z is the linear blend of the neighbours
    np.testing.assert_allclose(sparse.desirability(x, 0.2), every.desirability(x, 0.2), rtol=1e-13)
    blend = 0.75 * every.desirability(x, 0.2) + 0.25 * every.desirability(x, 0.4)
    np.testing.assert_allclose(sparse.desirability(x, 0.25), blend, rtol=1e-13)


def test_memory_error_before_allocating():
    grid = Grid([Axis(-1.0, 1.0, 400)] * 4)  # 2.56e10 bytes per float64 slice
    problem = Problem(_chain(4), grid, 1.0, Quadratic(np.zeros(4), np.ones(4)))
    with pytest.raises(MemoryError, match=r"needs about .* GiB of memory .* is available"):
        gridlbc.solve(problem, dt=0.01)
    # the estimate counts every stored slice in the stored dtype, plus the working arrays
    settings = gridlbc.SolverSettings(dtype="float32")
    estimate = gridlbc.settings.memory_estimate(problem, settings, 101)
    assert estimate["stored"] == 101 * 400**4 * 4
    assert estimate["ram"] >= estimate["stored"] + 3 * 400**4 * 8


def test_bad_storage_options_are_named():
    problem = _lq_problem(2, 11)
    with pytest.raises(ValueError, match="mmap_dir"):
        gridlbc.solve(problem, mmap_dir="/no/such/dir")
    with pytest.raises(ValueError, match="linear_solver"):
        gridlbc.solve(problem, method="implicit", linear_solver="lu")
    with pytest.raises(ValueError, match="feet"):
        SplittingStep(problem, 0.1, feet="dense")


@pytest.mark.parametrize(
    "shape, periodic",
    [
        ((7, 8), (True, False)),
        ((5, 6, 4), (False, True, False)),
        ((4, 5, 4, 6), (True, True, False, False)),
        ((3, 4, 3, 3, 4, 3), (True, False, False, True, False, False)),
    ],
)
def test_compact_feet_kernel_matches_barycentric(shape, periodic, rng):
    """The compiled encoding of the feet equals barycentric() followed by the numpy encoding, bit
    for bit (the same arithmetic), and the shape codes equal np.unique's, on every kind of axis;
    the 6-D grid takes the sorting branch of the shape codes."""
    from gridlbc.backends.numba.feet import encode_compact_kernel
    from gridlbc.schemes.splitting.feet import compact_feet, shape_codes, walk_steps

    grid = Grid([Axis(-1.0, 2.0, n, periodic=p) for n, p in zip(shape, periodic, strict=True)])
    x = rng.uniform(-1.5, 2.5, (4000, grid.ndim))
    x[:50] = grid.node_coordinates(rng.integers(0, grid.size, 50))  # on nodes: ties in the sort
    x = grid.clamp(x)
    base, packed, frac = compact_feet(grid, *barycentric(grid, x))
    out = (np.empty_like(base), np.empty_like(packed), np.empty_like(frac))
    encode_compact_kernel(x, *grid.kernel_arrays(), walk_steps(grid), *out)
    for expected, got in zip((base, packed, frac), out, strict=True):
        np.testing.assert_array_equal(got, expected)
    distinct, ids = shape_codes(grid, packed)
    unique, inverse = np.unique(packed, return_inverse=True)
    np.testing.assert_array_equal(distinct, unique)
    np.testing.assert_array_equal(ids, inverse)


def test_a_drift_that_is_not_finite_is_named():
    class _Blowup(SingleIntegrator):
        def drift(self, x):
            x = np.asarray(x)
            return np.where((x > 0.5) | np.isnan(x), np.nan, 0.0)

    problem = Problem(_Blowup(), Grid([Axis(-1.0, 1.0, 11)]), 1.0, Quadratic([0.0], [1.0]))
    with pytest.raises(ValueError, match=r"foot of node 8 .* _Blowup.drift returned a non-finite"):
        SplittingStep(problem, 0.1)


@EXACTNESS_ONLY
def test_every_method_is_a_scheme_and_the_protocol_is_all_the_solver_calls(monkeypatch):
    """Each entry of METHODS is a Scheme; a scheme registered under a new name, that only
    delegates to the implicit one, solves identically, called in the protocol's order."""
    from gridlbc.schemes import IMPLICIT, METHODS, Scheme

    assert all(isinstance(scheme, Scheme) for scheme in METHODS.values())
    calls = []

    class Recording:
        name, supports_fitting, step = "recording", False, ImplicitStep

        def __getattr__(self, attribute):
            def call(*args):
                calls.append(attribute)
                return getattr(IMPLICIT, attribute)(*args)

            return call

    monkeypatch.setitem(METHODS, "recording", Recording())
    problem = Problem(
        LinearSystem([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]]),
        Grid([Axis(-2, 2, 21), Axis(-2, 2, 21)]),
        0.5,
        Quadratic([0.0, 0.0], [1.0, 1.0]),
    )
    # without the embedded solves, which call the protocol again on coarser grids
    recorded = gridlbc.solve(problem, method="recording", error_estimate=False)
    protocol_order = ["step_bound", "step_rule", "estimate_bytes", "march", "check"]
    assert calls == ["estimate_bytes", *protocol_order]
    np.testing.assert_array_equal(recorded.slices, gridlbc.solve(problem, method="implicit").slices)
