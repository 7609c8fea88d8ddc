"""Kuhn-simplex barycentric interpolation (gridlbc.interpolate; docs/schemes.rst,
"Interpolation"): exact for affine functions (to rounding)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gridlbc import Axis, Grid
from gridlbc.interpolate import barycentric, input_gradient, interpolate, interpolate_slices
from gridlbc.testing import barycentric_numpy

GRIDS = {
    1: Grid([Axis(-1.0, 2.0, 7)]),
    2: Grid([Axis(-np.pi, np.pi, 9, periodic=True), Axis(-2.0, 3.0, 6)]),
    3: Grid([Axis(0.0, 1.0, 4), Axis(-1.0, 1.0, 5, periodic=True), Axis(2.0, 5.0, 3)]),
    4: Grid(
        [
            Axis(-np.pi, np.pi, 6, periodic=True),
            Axis(-np.pi, np.pi, 5, periodic=True),
            Axis(-3.0, 3.0, 4),
            Axis(-1.0, 1.0, 5),
        ]
    ),
}


def _affine_nodal(grid, slope, cut):
    """Nodal values of an affine function; on periodic axes affine in the coordinate unwrapped
    from ``cut`` (a point away from the query cells), so it is affine across the seam cell."""
    x = grid.nodes().copy()
    for k, ax in enumerate(grid.axes):
        if ax.periodic:
            x[:, k] = cut[k] + np.mod(x[:, k] - cut[k], ax.period)
    return x @ slope + 0.7, x


def _affine_at(grid, slope, cut, pts):
    y = pts.copy()
    for k, ax in enumerate(grid.axes):
        if ax.periodic:
            y[:, k] = cut[k] + np.mod(y[:, k] - cut[k], ax.period)
    return y @ slope + 0.7


@pytest.mark.parametrize("d", [1, 2, 3, 4])
def test_affine_functions_reproduced_to_rounding(d, rng):
    grid = GRIDS[d]
    slope = rng.normal(size=d)
    # Cut each periodic axis in the middle of its interior so that the seam cell (between the
    # last node and lo + period) lies inside one affine branch; sample only away from the cut.
    cut = np.array([ax.lo + 0.5 * ax.period if ax.periodic else 0.0 for ax in grid.axes])
    values, _ = _affine_nodal(grid, slope, cut)
    pts = rng.uniform(grid.lo, grid.hi, size=(500, d))
    for k, ax in enumerate(grid.axes):
        if ax.periodic:  # keep away from the cut: within a quarter period of the seam
            pts[:, k] = ax.lo + np.mod(rng.uniform(-0.25, 0.25, 500) * ax.period, ax.period)
    got = interpolate(grid, values, pts)
    expected = _affine_at(grid, slope, cut, pts)
    # Rounding: a sum of d+1 products of O(|f|) values; allow 64 ulps of the largest value.
    np.testing.assert_allclose(
        got, expected, rtol=0, atol=64 * np.finfo(float).eps * np.abs(values).max()
    )


@pytest.mark.parametrize("d", [1, 2, 3, 4])
def test_weights_nonnegative_sum_to_one_and_match_numpy_reference(d, rng):
    grid = GRIDS[d]
    span = grid.hi - grid.lo
    pts = rng.uniform(grid.lo - 0.3 * span, grid.hi + 0.3 * span, size=(400, d))  # incl. outside
    pts[:50] = grid.nodes()[rng.integers(0, grid.size, 50)]  # exactly on nodes
    idx, w = barycentric(grid, pts)
    ref_idx, ref_w = barycentric_numpy(grid, pts)
    assert np.all(w >= 0)
    np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-14)
    assert idx.min() >= 0 and idx.max() < grid.size
    # Same interpolant; vertices with zero weight may legitimately differ on ties.
    f = rng.normal(size=grid.size)
    np.testing.assert_allclose((f[idx] * w).sum(1), (f[ref_idx] * ref_w).sum(1), atol=1e-13)
    np.testing.assert_allclose(np.sort(w, axis=1), np.sort(ref_w, axis=1), atol=1e-14)


def test_periodic_seam_interpolates_between_last_and_first_node():
    grid = Grid([Axis(0.0, 1.0, 4, periodic=True)])  # nodes 0, .25, .5, .75; period 1
    values = np.array([10.0, 0.0, 0.0, 2.0])
    got = interpolate(grid, values, [[0.875], [1.875], [-0.125], [0.0], [1.0]])
    np.testing.assert_allclose(got, [6.0, 6.0, 6.0, 10.0, 10.0], atol=1e-12)


def test_points_outside_closed_box_are_clamped():
    grid = Grid([Axis(0.0, 1.0, 3)])
    np.testing.assert_allclose(
        interpolate(grid, [1.0, 2.0, 5.0], [[-7.0], [0.25], [9.0]]), [1.0, 1.5, 5.0]
    )


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(-10, 10), min_size=3, max_size=3))
def test_hypothesis_points_give_convex_weights(point):
    grid = GRIDS[3]
    _, w = barycentric(grid, np.array(point))
    assert np.all(w >= 0) and abs(w.sum() - 1) < 1e-14


def _at_nodes(grid, values, axis, log_divisor=None):
    """The derivative of ``values`` (1, size) along ``axis`` at every node: each node its own
    one-vertex simplex of weight 1, and B the unit input along ``axis``."""
    nodes = np.arange(grid.size)[:, None]
    B = np.zeros((grid.size, 1, grid.ndim, 1))
    B[:, :, axis, 0] = 1.0
    return input_gradient(grid, values, np.ones(1), nodes, np.ones((grid.size, 1)), B, log_divisor)[
        :, 0
    ]


def test_node_gradient_exact_for_affine_and_one_sided_at_ends(rng):
    grid = Grid([Axis(-1.0, 1.0, 6), Axis(0.0, 2.0, 5, periodic=True)])
    x = grid.nodes()
    values = (3.0 * x[:, 0] - 0.5 * x[:, 0] ** 2)[None, :]
    nodes = np.arange(grid.size)
    d0 = _at_nodes(grid, values, 0)
    h = grid.spacing[0]
    i = np.unravel_index(nodes, grid.shape)[0]
    interior = (i > 0) & (i < 5)
    # central differences are exact for quadratics; one-sided ones are off by h/2·|f''|.
    np.testing.assert_allclose(d0[interior], 3.0 - x[interior, 0], atol=1e-12)
    np.testing.assert_allclose(
        d0[~interior],
        3.0 - x[~interior, 0] + np.where(i[~interior] == 0, -1, 1) * 0.5 * h,
        atol=1e-12,
    )
    periodic_values = np.sin(np.pi * x[:, 1])[None, :]
    d1 = _at_nodes(grid, periodic_values, 1)
    h1 = grid.spacing[1]
    expected = (np.sin(np.pi * (x[:, 1] + h1)) - np.sin(np.pi * (x[:, 1] - h1))) / (2 * h1)
    np.testing.assert_allclose(d1, expected, atol=1e-12)


def test_interpolate_slices_reproduces_an_affine_function_in_space_and_time(rng):
    # barycentric weights reproduce affine functions, and the time weights blend the slices:
    # slices f_r = a_r + b_r·x give Σ_r τ_r (a_r + b_r·x) at any state, exactly up to rounding;
    # with log_divisor the slices are divided by e^{divisor} node by node first
    grid = Grid([Axis(-1.0, 1.0, 11), Axis(0.0, 3.0, 13, periodic=False)])
    x = grid.nodes()
    slices = np.stack([1.0 + 2 * x[:, 0] - x[:, 1], 0.5 * x[:, 1]])
    tau = np.array([0.25, 0.75])
    states = np.array([[-0.93, 0.1], [0.31, 2.2], [0.0, 1.5]])
    idx, w = barycentric(grid, states)
    expected = tau[0] * (1 + 2 * states[:, 0] - states[:, 1]) + tau[1] * 0.5 * states[:, 1]
    np.testing.assert_allclose(interpolate_slices(slices, tau, idx, w), expected, atol=1e-13)
    positive = np.abs(slices)
    divisor = np.log(positive + 1.0)
    ratio = positive / np.exp(divisor)
    got = interpolate_slices(positive, tau, idx, w, log_divisor=divisor)
    np.testing.assert_allclose(got, np.einsum("r,rnv,nv->n", tau, ratio[:, idx], w), rtol=1e-13)


def test_input_gradient_interpolates_the_vertices_gradients_through_B(rng):
    # Bᵀ∇y at a state is Σ_v w_v B(x_v)ᵀ Σ_r τ_r ∇y_r(x_v): a quadratic's central differences
    # are exact, so with an affine B(x) and two slices the sum is known in closed form
    grid = Grid([Axis(-1.0, 1.0, 11), Axis(0.0, 3.0, 13)])
    x = grid.nodes()
    slices = np.stack([x[:, 0] ** 2 + 2 * x[:, 1], -x[:, 0] * x[:, 1]])
    tau = np.array([0.25, 0.75])
    lo, hi = np.array([-0.8, 0.3]), np.array([0.8, 2.7])  # interior: central differences
    states = lo + (hi - lo) * rng.random((50, 2))
    idx, w = barycentric(grid, states)
    vertices = grid.node_coordinates(idx.ravel()).reshape(50, 3, 2)
    B = np.stack([1.0 + vertices[..., 1], 2.0 * vertices[..., 0]], axis=-1)[..., None]  # (N,3,2,1)
    grad = np.stack(
        [
            tau[0] * 2 * vertices[..., 0] - tau[1] * vertices[..., 1],
            tau[0] * 2.0 - tau[1] * vertices[..., 0],
        ],
        axis=-1,
    )
    expected = np.einsum("nv,nvk,nvk->n", w, B[..., 0], grad)
    got = input_gradient(grid, slices, tau, idx, w, B)[:, 0]
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)
    # one state reads its own vertices' B, as it does among many
    np.testing.assert_array_equal(
        input_gradient(grid, slices, tau, idx[:1], w[:1], B[:1]), got[:1, None]
    )
    constant = np.broadcast_to(np.array([[0.5], [-2.0]]), (50, 3, 2, 1))
    expected = np.einsum("nv,k,nvk->n", w, np.array([0.5, -2.0]), grad)
    np.testing.assert_allclose(
        input_gradient(grid, slices, tau, idx, w, constant)[:, 0], expected, rtol=1e-12, atol=1e-12
    )


@pytest.mark.parametrize("d", [2, 4])
def test_the_serial_and_threaded_kernels_agree_bitwise(d, monkeypatch):
    # few states run in the calling thread (SERIAL_BELOW): the same arithmetic per item, so the
    # two paths must give identical simplices, weights and gradients, not merely close ones
    import gridlbc.interpolate as interpolation

    grid = GRIDS[d]
    rng = np.random.default_rng(3)
    lo, hi = np.array([a.lo for a in grid.axes]), np.array([a.hi for a in grid.axes])
    x = lo + (hi - lo) * rng.random((500, d))
    values = rng.random((2, grid.size))
    out = []
    for threshold in (0, 10**9):
        monkeypatch.setattr(interpolation, "SERIAL_BELOW", threshold)
        idx, weights = barycentric(grid, x)
        B = np.zeros((len(x), d + 1, d, 1))
        B[:, :, d - 1, 0] = 1.0
        gradient = input_gradient(grid, values, np.ones(2), idx, weights, B, log_divisor=values)
        out.append((idx, weights, gradient, interpolate(grid, values, x)))
    for threaded, serial in zip(*out):
        np.testing.assert_array_equal(threaded, serial)


@pytest.mark.parametrize("d", [1, 3, 4])
def test_interpolate_sums_each_rows_vertices_as_the_weights_say(d, rng):
    # the compiled sum over a state's d + 1 vertices, in their order, for every row of a stack
    # of nodal values (any leading shape, any real dtype): the same numbers as the plain gather
    grid = GRIDS[d]
    x = rng.uniform(grid.lo, grid.hi, size=(200, d))
    idx, w = barycentric(grid, x)
    values = rng.normal(size=(2, 3, grid.size))
    expected = (values[..., idx] * w).sum(axis=-1)
    got = interpolate(grid, values, x)
    assert got.shape == (2, 3, 200)
    np.testing.assert_array_equal(got, expected)
    mask = values[0, 0] > 0
    np.testing.assert_array_equal(interpolate(grid, mask, x), (mask[idx] * w).sum(axis=-1))
    single = values[0, 0].astype(np.float32)
    np.testing.assert_array_equal(interpolate(grid, single, x), (single[idx] * w).sum(axis=-1))
