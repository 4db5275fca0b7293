import math

import numpy as np
import pytest

from sesp import Grid, Polyline, SeSP, scan
from sesp.dataset import field_sha256
from sesp.measures import monte_carlo

import naive
from cases import STAPLE, ZED

CASES = [
    (SeSP(n=2, opening=math.pi / 2), None, 24),
    (SeSP(n=8), None, 32),  # closed: flat sides exactly parallel at quarter turns
    (SeSP(n=8, opening=math.pi / 2), None, 32),
    (SeSP(n=0.6, opening=1.0), SeSP(n=3, aspect=0.7, opening=2.0), 20),
    (Polyline([[-1, 0], [1, 0]]), None, 1),
    (STAPLE, ZED, 1),
]


@pytest.mark.parametrize("nx", [24, 25])
@pytest.mark.parametrize("case", range(len(CASES)))
def test_raster_equals_direct_on_every_state(case, nx):
    particle, other, segments = CASES[case]
    grid = Grid(nx, nx + 2, nphi=8 if nx % 2 else 7)  # φ = 0, π/2, π, 3π/2 exactly; and an odd nphi
    kw = dict(other=other, segments=segments, crossings=True, entangled=True)
    fast = scan(particle, grid, engine="raster", **kw)  # SeSPs: slices past π mirrored
    slow = scan(particle, grid, engine="direct", **kw)  # every slice computed
    np.testing.assert_array_equal(fast.crossings.values, slow.crossings.values)
    np.testing.assert_array_equal(fast.allowed.values, slow.allowed.values)
    np.testing.assert_array_equal(fast.entangled.values, slow.entangled.values)
    assert fast.allowed.values.any() and not fast.allowed.values.all()


def test_allowed_only_mode_matches_counts():
    p = SeSP(n=8, opening=1.0)
    with_counts = scan(p, Grid(33, nphi=8), segments=40, crossings=True)
    plain = scan(p, Grid(33, nphi=8), segments=40)
    np.testing.assert_array_equal(plain.allowed.values, with_counts.crossings.values == 0)


def test_parallel_flat_sides_overlap_at_phi_zero_on_odd_grid():
    # Identical square-like curves at φ = 0 shifted along x: the flat sides lie on
    # one line, so every such state is an overlap (touching counts).
    ds = scan(SeSP(n=8), Grid(25, nphi=4), segments=32, crossings=True)
    row = ds.crossings.sel(phi=0.0).sel(y=0.0).values
    assert row[np.abs(ds.x.values) < 1.0].min() > 0


def test_grid_states_match_naive_reference():
    p, q = SeSP(n=8, opening=1.0).polyline(16), ZED
    ds = scan(p, Grid(17, nphi=6), other=q, crossings=True)
    rng = np.random.default_rng(7)
    for k, iy, ix in zip(*(rng.integers(0, s, 300) for s in ds.crossings.shape)):
        state = (ds.x.values[ix], ds.y.values[iy], ds.phi.values[k])
        assert ds.crossings.values[k, iy, ix] == naive.crossings(p.vertices, q.vertices, *state)


@pytest.mark.parametrize("engine, grid", [("raster", Grid(73, nphi=256)), ("direct", Grid(31, nphi=12))])
def test_bit_identical_on_one_and_two_threads(engine, grid, threads):
    p = SeSP(n=4, opening=2.0)
    threads(1)
    one = scan(p, grid, segments=24, engine=engine)
    threads(2)
    two = scan(p, grid, segments=24, engine=engine)
    again = scan(p, grid, segments=24, engine=engine)
    np.testing.assert_array_equal(one.allowed.values, two.allowed.values)
    np.testing.assert_array_equal(two.allowed.values, again.allowed.values)
    assert one.attrs["allowed_sha256"] == two.attrs["allowed_sha256"] == field_sha256(one.allowed)


def test_dataset_layout_and_attributes():
    ds = scan(SeSP(n=2, opening=1.0), Grid(16, 18, nphi=4), segments=12)
    assert ds.allowed.dims == ("phi", "y", "x")
    assert ds.allowed.dtype == bool
    assert ds.sizes == {"phi": 4, "y": 18, "x": 16, "particle_vertex": 13, "other_vertex": 13, "xy": 2}
    np.testing.assert_array_equal(ds.particle_vertices.values, SeSP(n=2, opening=1.0).polyline(12).vertices)
    assert not any(key.endswith("_vertices") for key in ds.attrs)  # variables, not 13 x 2 attributes
    assert ds.x.attrs["long_name"].endswith(", b") and ds.x.attrs["units"] == "1" and ds.phi.attrs["units"] == "rad"
    np.testing.assert_allclose(ds.phi.values, 2 * np.pi * np.arange(4) / 4)
    for key in (
        "particle_n",
        "particle_opening",
        "particle_segments",
        "nx",
        "nphi",
        "half_width",
        "engine",
        "sesp_version",
        "touch_tolerance",
    ):
        assert key in ds.attrs
    assert ds.attrs["identical_particles"] == 1


def test_scan_rejects_bad_arguments_before_work():
    with pytest.raises(ValueError, match="engine"):
        scan(SeSP(), Grid(8, nphi=2), engine="fast")
    with pytest.raises(MemoryError, match="memory limit"):
        scan(SeSP(), Grid(4096, nphi=4096))
    with pytest.raises(TypeError, match="particle"):
        scan("circle", Grid(8, nphi=2))


def test_monte_carlo_reproducible_and_consistent():
    p = SeSP(n=2, opening=1.0)
    a = monte_carlo(p, samples=2000, segments=32, seed=5)
    b = monte_carlo(p, samples=2000, segments=32, seed=5)
    np.testing.assert_array_equal(a.overlap.values, b.overlap.values)
    assert float(a.excluded_area) == float(b.excluded_area)
    side = 2 * a.attrs["half_width"]
    assert float(a.excluded_area) == pytest.approx(a.overlap.values.mean() * side**2)
    with pytest.raises(ValueError, match="samples"):
        monte_carlo(p, samples=0)


@pytest.mark.parametrize("particle", [SeSP(n=2, opening=math.pi / 2), SeSP(n=8, aspect=1.4, opening=2.0), STAPLE])
def test_raster_field_matches_shapely_intersects(particle):
    import shapely

    curve = particle if isinstance(particle, Polyline) else particle.polyline(48)
    ds = scan(particle, Grid(57, nphi=24), segments=48)  # SeSPs take the mirrored path
    line = shapely.LineString(curve.vertices)
    rng = np.random.default_rng(5)
    for k, iy, ix in zip(*(rng.integers(0, s, 500) for s in ds.allowed.shape)):
        moved = naive.transform(curve.vertices, ds.x.values[ix], ds.y.values[iy], ds.phi.values[k])
        assert ds.allowed.values[k, iy, ix] == (not line.intersects(shapely.LineString(moved)))
