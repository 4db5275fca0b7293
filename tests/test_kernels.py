"""Fast kernels against slow, obvious references on random states."""

import numpy as np
import pytest
import shapely

from sesp import Grid, Pair, SeSP
from sesp.field import resolve_grid
from sesp.kernels.orientations import chunk_boxes, chunk_count, clearance_at
from sesp.kernels.overlap import crossings_at_states, in_pair_set, pair_meets, raster_slices, raster_slices_serial

import naive
from cases import SHAPES


def _random_states(rng, reach, count):
    r = reach * np.sqrt(rng.uniform(0, 1.05, count))
    a = rng.uniform(0, 2 * np.pi, count)
    return r * np.cos(a), r * np.sin(a), rng.uniform(0, 2 * np.pi, count)


def _kernel_counts(c1, c2, x, y, phi):
    out = np.empty(len(x), dtype=np.uint16)
    crossings_at_states(c1.vertices, c2.vertices, x, y, phi, 1e-9, 0.0, True, out)
    return out


@pytest.mark.parametrize("i", range(len(SHAPES)))
def test_crossing_counts_match_naive_orientation_test(i):
    rng = np.random.default_rng(i)
    c1, c2 = SHAPES[i], SHAPES[(i + 1) % len(SHAPES)]
    x, y, phi = _random_states(rng, c1.max_radius + c2.max_radius, 400)
    fast = _kernel_counts(c1, c2, x, y, phi)
    slow = [naive.crossings(c1.vertices, c2.vertices, *s) for s in zip(x, y, phi)]
    np.testing.assert_array_equal(fast, slow)
    assert 0 < np.count_nonzero(fast) < len(fast)  # both outcomes exercised


@pytest.mark.parametrize("i", range(len(SHAPES)))
def test_overlap_matches_shapely_intersects(i):
    rng = np.random.default_rng(100 + i)
    c1, c2 = SHAPES[i], SHAPES[i]
    x, y, phi = _random_states(rng, 2 * c1.max_radius, 400)
    fast = _kernel_counts(c1, c2, x, y, phi) > 0
    line1 = shapely.LineString(c1.vertices)
    ref = [line1.intersects(shapely.LineString(naive.transform(c2.vertices, *s))) for s in zip(x, y, phi)]
    np.testing.assert_array_equal(fast, ref)


@pytest.mark.parametrize("i", range(len(SHAPES)))
def test_clearance_is_shapely_distance_capped(i):
    """The clearance (the pruned search for the nearest pair of segments) is the distance between the curves,
    capped, on states near contact, crossing and far apart: 0 where they meet, the cap where farther."""
    rng = np.random.default_rng(200 + i)
    c1, c2 = SHAPES[i], SHAPES[(i + 1) % len(SHAPES)]
    x, y, phi = _random_states(rng, c1.max_radius + c2.max_radius, 300)
    line1 = shapely.LineString(c1.vertices)
    ref = np.array([line1.distance(shapely.LineString(naive.transform(c2.vertices, *s))) for s in zip(x, y, phi)])
    caps = rng.choice([0.05, 0.3, 10.0], len(x))
    got = np.empty(len(x))
    boxes1 = chunk_boxes(c1.vertices, np.empty((chunk_count(c1.vertices), 4)))
    clearance_at(c1.vertices, boxes1, c2.vertices, x, y, phi, caps, got)
    np.testing.assert_allclose(got, np.minimum(ref, caps), rtol=1e-12, atol=1e-12)
    assert (got == 0).any() and (got == caps).any() and ((got > 0) & (got < caps)).any()  # each kind exercised


def test_pair_predicate_closed_and_degenerate():
    d, f = (1.0, 0.0), (0.0, 1.0)
    assert in_pair_set(0.0, 0.0, *d, *f, 1.0, 1.0, 0.0)  # corner: touching counts
    assert in_pair_set(1.0, 1.0, *d, *f, 1.0, 1.0, 0.0)
    assert not in_pair_set(1.0 + 1e-6, 0.5, *d, *f, 1.0, 1.0, 1e-9)
    # parallel segments: the set is the segment [-1, 1] x {0}
    assert in_pair_set(0.5, 0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 1.0, 1e-9)
    assert in_pair_set(-1.0, 1e-10, 1.0, 0.0, -1.0, 0.0, 1.0, 1.0, 1e-9)
    assert not in_pair_set(1.5, 0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 1.0, 1e-9)
    assert not in_pair_set(0.5, 1e-6, 1.0, 0.0, -1.0, 0.0, 1.0, 1.0, 1e-9)
    # nearly parallel: no tolerance tail far along the segments
    assert not in_pair_set(3.0, 0.0, 1.0, 0.0, -1.0, 1e-13, 1.0, 1.0, 1e-9)


def test_parallel_and_serial_raster_kernels_agree():
    pair = Pair.of(SeSP(n=8, opening=1.0), segments=40)
    g = resolve_grid(pair, Grid(33, nphi=16))
    c, s = g.rotations()
    args = (pair.vertices1, pair.vertices2, c, s, g.x, g.y, pair.tolerance, 0.0, True)
    parallel = np.zeros((16, 33, 33), dtype=np.uint16)
    serial = np.zeros_like(parallel)
    raster_slices(*args, parallel)
    raster_slices_serial(*args, serial)
    np.testing.assert_array_equal(parallel, serial)
    assert parallel.any()


def test_thick_pair_predicate_is_the_distance_to_the_parallelogram():
    """Random points against the exact distance to {λd + μf} (shapely), with and without a contact distance:
    segment 0 of v1 runs from 0 by d, segment 0 of b2 from 0 by −f, so c = 0 and t = w."""
    rng = np.random.default_rng(11)
    for _ in range(200):
        d, f = rng.normal(size=2), rng.normal(size=2)
        if rng.random() < 0.2:
            f = -0.7 * d  # a degenerate (parallel) pair
        contact = rng.choice([0.0, 0.05, 0.3])
        w = rng.normal(size=2) * 1.5
        corners = np.array([[0, 0], d, d + f, f])
        region = shapely.Polygon(corners) if abs(d[0] * f[1] - d[1] * f[0]) > 1e-12 else shapely.LineString(corners)
        distance = region.distance(shapely.Point(w))
        if abs(distance - contact) < 1e-9:
            continue
        v1, b2 = np.array([[0.0, 0.0], d]), np.array([[0.0, 0.0], -f])
        got = pair_meets(v1, b2, 0, 0, w[0], w[1], np.hypot(*d), np.hypot(*f), 1e-12, contact)
        assert got == (distance <= contact), (d, f, w, contact, distance)
