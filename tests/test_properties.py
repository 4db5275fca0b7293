"""Property-based tests: geometry and kernels over random valid inputs (derandomized)."""

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sesp import Grid, Pair, Polyline, SeSP, overlaps, scan
from sesp.kernels.overlap import crossings_at_states
from sesp.measures import lattice_excluded_area

import naive

PROPS = settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])

degrees = st.floats(0.3, 12.0)
sesps = st.builds(SeSP, n=degrees, m=degrees, aspect=st.floats(0.3, 3.0), opening=st.floats(0.0, 6.2))


@st.composite
def polylines(draw, max_vertices=7):
    count = draw(st.integers(2, max_vertices))
    pts = draw(st.lists(st.tuples(st.floats(-1.5, 1.5), st.floats(-1.5, 1.5)), min_size=count, max_size=count))
    v = np.array(pts)
    steps = np.hypot(*np.diff(v, axis=0).T)
    if np.any(steps < 1e-3):
        v = v + np.arange(len(v))[:, None] * 0.01  # keep vertices apart
    return Polyline(v)


@PROPS
@given(sesps, st.integers(1, 200))
def test_polyline_is_finite_with_exact_mirror_endpoints(particle, segments):
    if particle.opening == 0 and segments < 3:
        segments = 3
    line = particle.polyline(segments)
    v = line.vertices
    assert v.shape == (segments + 1, 2) and np.all(np.isfinite(v))
    np.testing.assert_array_equal(v[::-1], v * [1, -1])
    np.testing.assert_allclose(v[0], particle.point(particle.opening / 2), rtol=0, atol=1e-12)
    assert np.all(line.segment_lengths > 0)


@PROPS
@given(
    st.builds(SeSP, n=st.floats(1.0, 10.0), aspect=st.floats(0.5, 2.0), opening=st.floats(0.0, 6.0)),
    st.integers(32, 256),
)
def test_chords_span_nearly_equal_arcs_for_convex_shapes(particle, segments):
    """Each segment spans an arc of the curve no longer than L/(N − 4) (the split into flanks and back that
    keeps the polyline mirror-symmetric, tests/test_shape.py) and at least a quarter of the longest. Its
    chord is never longer than its arc, and no shorter than arc · sin(α/2) across a corner of angle α; for
    n = m >= 1 the sharpest corner is the n = 1 rhombus's, α = 2 atan(min(A, 1/A))."""
    upper = particle.vertex_arcs(segments)  # arc length from the upper end to each upper-half vertex
    ends = np.concatenate([upper, particle.length - upper[::-1]])
    arcs = np.diff(np.unique(np.round(ends, 12)))
    assert arcs.size == segments
    lengths = particle.polyline(segments).segment_lengths
    sharpest = 2 * math.atan(min(particle.aspect, 1 / particle.aspect))
    assert arcs.max() <= particle.length / (segments - 4) and arcs.min() >= arcs.max() / 4 * (1 - 1e-9)
    # the arcs are the arc-length table's, whose chords cut a corner (n = 1 at θ = π/2) by up to about 1e-7 b
    assert np.all(lengths <= arcs + 2e-7)
    assert np.all(lengths >= arcs * math.sin(sharpest / 2) - 2e-7)


@PROPS
@given(
    st.one_of(sesps.map(lambda p: p.polyline(10)), polylines()),
    st.one_of(sesps.map(lambda p: p.polyline(9)), polylines()),
    st.integers(9, 14),
    st.integers(2, 6),
)
def test_raster_and_direct_engines_agree(curve1, curve2, nx, nphi):
    grid = Grid(nx, nphi=nphi)
    fast = scan(curve1, grid, other=curve2, crossings=True)
    slow = scan(curve1, grid, other=curve2, crossings=True, engine="direct")
    np.testing.assert_array_equal(fast.crossings.values, slow.crossings.values)


@PROPS
@given(sesps, sesps, st.integers(9, 16), st.integers(1, 9), st.integers(8, 24))
def test_mirrored_slices_equal_computed_slices(first, second, nx, nphi, segments):
    """The raster engine mirrors SeSP slices past π; the direct engine computes them all."""
    grid = Grid(nx, nx + 1, nphi=nphi)
    kw = dict(other=second, segments=segments, crossings=True, entangled=True)
    fast, slow = scan(first, grid, **kw), scan(first, grid, engine="direct", **kw)
    for name in ("crossings", "allowed", "entangled"):
        np.testing.assert_array_equal(fast[name].values, slow[name].values)


def _counts(c1, c2, x, y, phi):
    out = np.empty(len(x), dtype=np.uint16)
    crossings_at_states(c1.vertices, c2.vertices, np.asarray(x), np.asarray(y), np.asarray(phi), 1e-9, 0.0, True, out)
    return out


@PROPS
@given(
    sesps.map(lambda p: p.polyline(12)),
    sesps.map(lambda p: p.polyline(11)),
    st.lists(st.tuples(st.floats(-4, 4), st.floats(-4, 4), st.floats(0, 2 * math.pi)), min_size=1, max_size=20),
)
def test_overlap_is_symmetric_under_swapping_the_particles(curve1, curve2, states):
    x, y, phi = (np.array(v) for v in zip(*states))
    # particle 1 seen from particle 2: translation −R(−φ) t, rotation −φ
    c, s = np.cos(-phi), np.sin(-phi)
    xs, ys = -(c * x - s * y), -(s * x + c * y)
    forward = _counts(curve1, curve2, x, y, phi) > 0
    backward = _counts(curve2, curve1, xs, ys, (-phi) % (2 * math.pi)) > 0
    reference = [naive.crossings(curve1.vertices, curve2.vertices, *state) > 0 for state in states]
    np.testing.assert_array_equal(forward, reference)
    np.testing.assert_array_equal(backward, reference)


@PROPS
@given(sesps, st.integers(11, 20), st.sampled_from([4, 6, 8, 12]))
def test_mirror_symmetric_particles_exclude_the_same_at_plus_and_minus_phi(particle, nx, nphi):
    ds = scan(particle, Grid(nx, nphi=nphi), segments=12)
    allowed = ds.allowed.values
    mirrored = allowed[(-np.arange(nphi)) % nphi, ::-1, :]  # φ -> −φ, y -> −y
    np.testing.assert_array_equal(allowed, mirrored)
    area = lattice_excluded_area(ds, by="phi").values
    np.testing.assert_array_equal(area, area[(-np.arange(nphi)) % nphi])


@PROPS
@given(polylines(max_vertices=5), st.floats(-0.7, 0.7), st.floats(-0.7, 0.7))
def test_excluded_area_does_not_depend_on_the_reference_point(curve, cx, cy):
    """Moving a particle's centre shifts its excluded region at fixed φ: same area."""
    moved = Polyline(curve.vertices + [cx, cy])
    grid = Grid(96, nphi=4)
    a = lattice_excluded_area(scan(curve, grid), by="phi").values
    b = lattice_excluded_area(scan(moved, grid), by="phi").values
    cell = (2 * (2 * moved.max_radius) * 96 / 94 / 96) ** 2
    scale = max(a.max(), 1.0)
    np.testing.assert_allclose(a, b, atol=0.05 * scale + 200 * cell)


@PROPS
@given(
    sesps.map(lambda p: p.polyline(40)),
    polylines(),
    st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3), st.floats(0, 2 * math.pi)), min_size=1, max_size=40),
)
def test_overlaps_is_the_naive_segment_test_state_by_state(curve1, curve2, states):
    """sesp.overlaps (chunks of segments skipped whole where their boxes are apart) says overlap exactly where
    some segment pair meets (tests/naive.py, every pair); a Pair's polylines are used as they are."""
    x, y, phi = (np.array(v) for v in zip(*states))
    pair = Pair.of(curve1, curve2)
    expected = [naive.crossings(pair.vertices1, pair.vertices2, *state) > 0 for state in zip(x, y, phi)]
    np.testing.assert_array_equal(overlaps(pair, None, x, y, phi), expected)
