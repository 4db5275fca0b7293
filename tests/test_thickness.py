"""Thick particles: exact excluded areas, engines that agree, and the thin limit."""

import hashlib
import math

import numpy as np
import pytest
import shapely

from sesp import Grid, Pair, Polyline, SeSP, scan
from sesp.measures import excluded_perimeter, monte_carlo, shifted_excluded_area
from sesp.orientations import allowed_orientations

from cases import ZED, interval_disagreements

L, D = 2.0, 0.1


def _ring(radius, thickness, segments=256):
    theta = np.linspace(0, 2 * np.pi, segments + 1)
    theta[-1] = 0.0
    return Polyline(radius * np.column_stack([np.cos(theta), np.sin(theta)]), thickness=thickness)


def test_thick_needles_are_spherocylinders():
    """A_ex(φ) = L²|sin φ| + 4LD + πD² for rods of length L and diameter D (1024² × 32, shifted lattices)."""
    area = shifted_excluded_area(Polyline([[-1.0, 0.0], [1.0, 0.0]], thickness=D), Grid(1024, nphi=32))
    exact = L**2 * np.abs(np.sin(area.phi.values)) + 4 * L * D + math.pi * D**2
    assert area.values.mean() / exact.mean() - 1 == pytest.approx(0, abs=1e-3)
    np.testing.assert_allclose(area.values, exact, rtol=2e-2)  # per φ, thin stadia near φ = 0 are the worst


def test_thick_circles_exclude_a_disk_of_radius_2r_plus_d():
    area = shifted_excluded_area(_ring(1.0, D), Grid(512, nphi=16))
    np.testing.assert_allclose(area.values, math.pi * (2 + D) ** 2, rtol=1e-3)


@pytest.mark.parametrize("n", [2, 4, 8])
def test_thick_closed_convex_curves_follow_steiner(n):
    """Orientation mean A_ex = 2A + P²/2π + 2PD + πD² (A, P of the closed polygon)."""
    particle = SeSP(n=n, thickness=0.05)
    polygon = particle.polyline(256)
    area, perimeter = polygon.area, polygon.length
    exact = 2 * area + perimeter**2 / (2 * math.pi) + 2 * perimeter * 0.05 + math.pi * 0.05**2
    assert float(shifted_excluded_area(particle, Grid(512, nphi=64)).mean()) == pytest.approx(exact, rel=1e-3)


THICK_CASES = [
    (SeSP(n=8, thickness=0.05), None),  # flat sides exactly parallel at φ = 0
    (SeSP(n=8, opening=1.0, thickness=0.05), None),
    (SeSP(n=2, opening=2.0, thickness=0.1), Polyline(ZED.vertices, thickness=0.02)),  # two thicknesses
]


@pytest.mark.parametrize("nx", [24, 25])
@pytest.mark.parametrize("case", range(len(THICK_CASES)))
def test_raster_equals_direct_on_every_thick_state(case, nx):
    particle, other = THICK_CASES[case]
    grid = Grid(nx, nx + 2, nphi=8 if nx % 2 else 7)
    kw = dict(other=other, segments=24, crossings=True, entangled=True)
    fast, slow = scan(particle, grid, **kw), scan(particle, grid, engine="direct", **kw)
    for name in ("crossings", "allowed", "entangled"):
        np.testing.assert_array_equal(fast[name].values, slow[name].values)
    assert fast.allowed.values.any() and not fast.allowed.values.all()
    # overlap only: the raster marks crossings, then (end point, segment) pairs once each; the same states
    only = scan(particle, grid, other=other, segments=24)
    np.testing.assert_array_equal(only.allowed.values, slow.allowed.values)


@pytest.mark.parametrize("case", range(len(THICK_CASES)))
def test_overlap_only_raster_equals_direct_on_a_fine_thick_grid(case):
    """Many nodes near the thick boundary: the two-phase raster (crossings, then near end points) against the
    direct engine's segment-pair test."""
    particle, other = THICK_CASES[case]
    grid = Grid(81, nphi=5)
    fast = scan(particle, grid, other=other, segments=24)
    slow = scan(particle, grid, other=other, segments=24, engine="direct")
    np.testing.assert_array_equal(fast.allowed.values, slow.allowed.values)


def test_thick_overlap_is_the_curves_coming_closer_than_the_contact_distance():
    """Monte-Carlo states against shapely's distance between the two polylines."""
    first, second = SeSP(n=4, opening=2.0, thickness=0.1), Polyline(ZED.vertices, thickness=0.3)
    pair = Pair.of(first, second, segments=20)
    mc = monte_carlo(pair, samples=400, seed=7)
    line1 = shapely.LineString(pair.curve1.vertices)
    for x, y, phi, overlap in zip(mc.x.values, mc.y.values, mc.phi.values, mc.overlap.values):
        c, s = math.cos(phi), math.sin(phi)
        moved = pair.curve2.vertices @ np.array([[c, s], [-s, c]]) + [x, y]
        distance = line1.distance(shapely.LineString(moved))
        if abs(distance - pair.contact) > 1e-7:  # ties decided by the tolerance
            assert overlap == (distance <= pair.contact)


def test_thick_entanglement_is_each_curve_within_contact_of_the_other_hull():
    pair = Pair.of(SeSP(n=2, opening=1.5, thickness=0.08), segments=24)
    ds = scan(pair, Grid(20, nphi=5), entangled=True)
    hull1 = shapely.Polygon(pair.curve1.hull())
    line1 = shapely.LineString(pair.curve1.vertices)
    for k, phi in enumerate(ds.phi.values):
        c, s = math.cos(phi), math.sin(phi)
        rot = np.array([[c, s], [-s, c]])
        for iy, y in enumerate(ds.y.values):
            for ix, x in enumerate(ds.x.values):
                line2 = shapely.LineString(pair.curve2.vertices @ rot + [x, y])
                hull2 = shapely.Polygon(pair.curve2.hull() @ rot + [x, y])
                d1, d2 = hull1.distance(line2), hull2.distance(line1)
                if min(abs(d1 - pair.contact), abs(d2 - pair.contact)) < 1e-6:
                    continue  # a tie, decided by the tolerance
                expected = d1 <= pair.contact and d2 <= pair.contact and bool(ds.allowed.values[k, iy, ix])
                assert bool(ds.entangled.values[k, iy, ix]) == expected


def test_thick_orientation_intervals_match_a_direct_scan():
    particle, other = SeSP(n=4, opening=math.radians(100), thickness=0.06), SeSP(n=2, opening=2.0, thickness=0.1)
    ds = scan(particle, Grid(12, nphi=48), other=other, segments=16, engine="direct")
    assert interval_disagreements(particle, other, ds, 16) == 0
    # thicker particles exclude more orientations at every position
    xs, ys = np.meshgrid(ds.x.values, ds.y.values)
    thin = allowed_orientations(SeSP(n=4, opening=math.radians(100)), xs, ys, other=SeSP(n=2, opening=2.0),
                                segments=16)  # fmt: skip
    thick = allowed_orientations(particle, xs, ys, other=other, segments=16)
    assert np.all(thick <= thin + 1e-12) and np.any(thick < thin - 1e-3)


# Fields and values computed by the thin engines before thickness existed (sesp 196a67c), on the polylines
# of equal arc it had: D = 0 is bit for bit.
THIN_HASHES = {
    "n8": ("b8f98f2fb40579a3", "3a44c8a334266f44", "b473ce70758fd7a2"),
    "zed": ("8f99e6503ff127f8", "b49443b7d963d1da", "77993fc52fe1fec2"),
    "mc": "aab0d0cfa0478665",
    "shifted": "937f751381142c43",
    "orient": "cfe60f4d0d4b04a4",
}


def _h(array):
    return hashlib.sha256(np.ascontiguousarray(array).tobytes()).hexdigest()[:16]


def test_zero_thickness_is_the_thin_engine_bit_for_bit(monkeypatch):
    monkeypatch.setattr(SeSP, "flank_and_back", lambda self, segments: None)  # equal arc, as in 196a67c
    ds = scan(SeSP(n=8, opening=1.0, thickness=0.0), Grid(33, nphi=16), segments=40, crossings=True, entangled=True)
    assert (_h(ds.allowed.values), _h(ds.crossings.values), _h(ds.entangled.values)) == THIN_HASHES["n8"]
    ds = scan(SeSP(n=2, opening=2.0), Grid(32, nphi=12), other=ZED, segments=24, crossings=True, entangled=True,
              engine="direct")  # fmt: skip
    assert (_h(ds.allowed.values), _h(ds.crossings.values), _h(ds.entangled.values)) == THIN_HASHES["zed"]
    mc = monte_carlo(SeSP(n=4, opening=1.0, thickness=0.0), samples=2000, segments=32, seed=3)
    assert _h(mc.overlap.values) == THIN_HASHES["mc"]
    shifted = shifted_excluded_area(SeSP(n=2, opening=1.5), Grid(48, nphi=16), segments=32)
    assert _h(shifted.values) == THIN_HASHES["shifted"]
    xs, ys = np.meshgrid(np.linspace(-1.5, 1.5, 9), np.linspace(-1.2, 1.2, 7))
    assert _h(allowed_orientations(SeSP(n=4, opening=2.0), xs, ys, segments=32)) == THIN_HASHES["orient"]


def _union_perimeter(pair, phi):
    """Exact perimeter of the excluded set at φ: the union of the Minkowski parallelograms (shapely)."""
    c, s = math.cos(phi), math.sin(phi)
    v1, b2 = pair.curve1.vertices, pair.curve2.vertices @ np.array([[c, s], [-s, c]])
    polys = []
    for i in range(len(v1) - 1):
        for j in range(len(b2) - 1):
            corner, d, f = v1[i] - b2[j], v1[i + 1] - v1[i], b2[j] - b2[j + 1]
            polys.append(shapely.Polygon([corner, corner + d, corner + d + f, corner + f]))
    # closing by 1e-7 b removes the hairline cracks floating point leaves between parallelograms sharing an edge
    return shapely.unary_union(polys).buffer(1e-7).buffer(-1e-7).length


@pytest.mark.parametrize("opening", [60, 120, 200])
def test_thin_limit_slope_is_the_excluded_perimeter(opening):
    pair = Pair.of(SeSP(n=2, opening=math.radians(opening)), segments=32)
    perimeter = excluded_perimeter(pair, Grid(768, nphi=12))
    for k in (1, 2, 5):  # generic orientations (no parallel segments)
        assert float(perimeter[k]) == pytest.approx(_union_perimeter(pair, float(perimeter.phi[k])), rel=1e-2)


def test_thickness_is_checked_and_recorded():
    with pytest.raises(ValueError, match="thickness"):
        SeSP(thickness=-0.1)
    with pytest.raises(ValueError, match="thickness"):
        Polyline([[0, 0], [1, 0]], thickness=float("nan"))
    pair = Pair.of(SeSP(thickness=0.1), Polyline([[0, 0], [1, 0]], thickness=0.3))
    assert pair.contact == pytest.approx(0.2)
    ds = scan(pair, Grid(8, nphi=2))
    assert ds.attrs["particle_thickness"] == 0.1 and ds.attrs["other_thickness"] == 0.3
    assert ds.attrs["contact_distance"] == pytest.approx(0.2)


def test_thick_closed_shape_normalises_to_one_and_sweeps_take_thickness(tmp_path, capsys):
    from sesp import analyze, load
    from sesp.cli import main
    from sesp.sweep import load_spec

    from cases import write_sweep

    ds = analyze(SeSP(n=4, thickness=0.05), Grid(256, nphi=32), rtol=1e-4)
    assert float(ds.mean_normalized_excluded_area) == pytest.approx(1.0, abs=1e-3)
    spec = load_spec(write_sweep(tmp_path, THICK_SWEEP.format(out=tmp_path / "o")))
    assert spec.dims == ["thickness"]
    assert [p.pair().contact for p in spec.points()] == [0.0, 0.1]
    out = tmp_path / "thick.nc"
    assert main(["-q", "scan", "--n", "2", "--thickness", "0.1", "--nx", "16", "--nphi", "4", "-o", str(out)]) == 0
    assert load(out).attrs["particle_thickness"] == 0.1
    main(["info", "--rtol", "1e-3", str(out)])
    assert "thickness=0.1 b" in capsys.readouterr().out


THICK_SWEEP = """
[sweep]
output = "{out}"
angles = "degrees"

[particle]
n = 2
opening = 90
thickness = [0, 0.1]

[grid]
nx = 16
nphi = 4

[output]
rtol = 1e-3
"""
