import numpy as np
import pytest

from gridlbc import Axis, Grid


def test_axis_spacing_periodic_has_no_duplicate_end_node():
    ax = Axis(-np.pi, np.pi, 8, periodic=True)
    assert ax.spacing == pytest.approx(2 * np.pi / 8)
    pts = ax.points()
    assert pts[0] == -np.pi and pts[-1] == pytest.approx(np.pi - 2 * np.pi / 8)
    closed = Axis(0.0, 1.0, 5)
    np.testing.assert_allclose(closed.points(), [0, 0.25, 0.5, 0.75, 1.0])


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"lo": 1.0, "hi": 1.0, "n": 5}, "lo < hi"),
        ({"lo": 2.0, "hi": 1.0, "n": 5}, "lo < hi"),
        ({"lo": 0.0, "hi": 1.0, "n": 2}, "at least 3"),
        ({"lo": 0.0, "hi": np.inf, "n": 5}, "finite"),
    ],
)
def test_axis_rejects_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Axis(**kwargs)


def test_axis_rejects_non_integer_n():
    with pytest.raises(TypeError, match="integer"):
        Axis(0.0, 1.0, 4.5)


def test_grid_nodes_c_order_and_strides():
    grid = Grid([Axis(0, 1, 3), Axis(0, 2, 4), Axis(-1, 1, 5, periodic=True)])
    assert grid.shape == (3, 4, 5) and grid.size == 60 and grid.ndim == 3
    nodes = grid.nodes()
    assert nodes.shape == (60, 3)
    flat = 2 * 20 + 3 * 5 + 4
    np.testing.assert_allclose(nodes[flat], [1.0, 2.0, -1 + 4 * 0.4])
    np.testing.assert_array_equal(grid.strides, [20, 5, 1])
    np.testing.assert_allclose(grid.node_coordinates([flat, 0]), nodes[[flat, 0]])


def test_wrap_maps_periodic_coordinates_into_box():
    grid = Grid([Axis(-np.pi, np.pi, 16, periodic=True), Axis(-1, 1, 5)])
    x = np.array([[np.pi, 3.0], [-np.pi - 0.1, -3.0], [5 * np.pi + 0.2, 0.5]])
    w = grid.wrap(x)
    np.testing.assert_allclose(w[:, 0], [-np.pi, np.pi - 0.1, -np.pi + 0.2])
    np.testing.assert_allclose(w[:, 1], x[:, 1])  # closed axes untouched by wrap
    np.testing.assert_allclose(grid.clamp(x)[:, 1], [1.0, -1.0, 0.5])


def test_check_states_messages():
    grid = Grid([Axis(0, 1, 3), Axis(0, 1, 3)])
    assert grid.check_states([0.5, 0.5]).shape == (1, 2)
    with pytest.raises(ValueError, match=r"x must have shape \(N, 2\)"):
        grid.check_states(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="non-finite"):
        grid.check_states([[0.1, np.nan]])
    with pytest.raises(TypeError):
        Grid([Axis(0, 1, 3), "axis"])


def test_flat_chunks_cover_the_nodes_once_in_order():
    from gridlbc.grid import NODE_CHUNK, flat_chunks

    size = 2 * NODE_CHUNK + 5
    chunks = list(flat_chunks(size, start=3))
    assert [len(c) for c in chunks] == [NODE_CHUNK, NODE_CHUNK, 2]
    np.testing.assert_array_equal(np.concatenate(chunks), np.arange(3, size))


def test_node_values_equal_the_function_on_all_nodes():
    grid = Grid([Axis(-1, 1, 130), Axis(0, 2, 131, periodic=True)])  # more than one chunk
    assert grid.size > (1 << 14)

    def f(x):
        return np.sin(x[:, 0]) * x[:, 1]

    np.testing.assert_array_equal(grid.node_values(f), f(grid.nodes()))


def test_axis_boundaries_and_an_unsupported_boundary_is_refused():
    from gridlbc.boundary import Boundary, axis_boundaries, require

    grid = Grid([Axis(-np.pi, np.pi, 8, periodic=True), Axis(-1, 1, 5)])
    assert axis_boundaries(grid) == (Boundary.PERIODIC, Boundary.REFLECTING)
    assert require(grid, tuple(Boundary), "here") == axis_boundaries(grid)
    with pytest.raises(NotImplementedError, match=r"the kernel .* reflecting boundary \(axis 1\)"):
        require(grid, (Boundary.PERIODIC,), "the kernel")
