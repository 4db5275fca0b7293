import numpy as np
import pytest

from sesp import Grid
from sesp.grid import exact_cos_sin


def test_default_box_is_reach_plus_one_cell():
    g = Grid(100, nphi=8).resolve(2.0)
    assert g.half_width == pytest.approx(2.0 + g.dx)
    assert g.x[0] == pytest.approx(-g.half_width + g.dx / 2)


@pytest.mark.parametrize("nx", [10, 11])
def test_coordinates_exactly_symmetric(nx):
    g = Grid(nx, nphi=4).resolve(3.0)
    np.testing.assert_array_equal(g.x, -g.x[::-1])
    if nx % 2:
        assert g.x[nx // 2] == 0.0


def test_rotations_exact_at_quarter_turns():
    c, s = exact_cos_sin(np.arange(8), 8)
    np.testing.assert_array_equal(c[::2], [1, 0, -1, 0])
    np.testing.assert_array_equal(s[::2], [0, 1, 0, -1])
    np.testing.assert_allclose(c[1], np.cos(np.pi / 4))


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"nx": 2}, "nx"),
        ({"nx": 10, "ny": 0}, "ny"),
        ({"nphi": 0}, "nphi"),
        ({"nx": 3.5}, "nx"),
        ({"half_width": -1.0}, "half_width"),
    ],
)
def test_invalid_grid(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Grid(**kwargs)


def test_memory_refused_before_allocation():
    g = Grid(4096, nphi=4096)
    with pytest.raises(MemoryError, match="memory limit"):
        g.check_memory(limit=1 << 30)
    assert g.nbytes(("allowed", "crossings")) == 3 * 4096**3


def test_box_limits_and_a_truncating_box_is_warned():
    import pytest

    from sesp import SeSP, scan
    from sesp.field import TruncatedBoxWarning

    with pytest.raises(ValueError, match="half_width must be in"):
        Grid(half_width=1e300)
    with pytest.warns(TruncatedBoxWarning, match="truncated"):
        scan(SeSP(), Grid(8, nphi=2, half_width=0.1), segments=8)
