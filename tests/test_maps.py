"""Adaptive maps exact in φ: the widest window, the clearance certificate, components against exact sets."""

import dataclasses
import fcntl
import functools
import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy import ndimage
from scipy.sparse.csgraph import connected_components

from sesp import Polyline, SeSP, allowed_orientations, channels, maps
from sesp.cli import main
from sesp.dataset import SespFileError
from sesp.io import load, save
from sesp.kernels.orientations import widest_windows
from sesp.maps import (
    SPECK_GAP,
    ExcludedMap,
    MapComponent,
    centre_pinch,
    excluded_map,
    joined_specks,
    map_transitions,
    stored_map,
    widest_window,
)
from sesp.orientations import ANGLE_GAP, SCREEN_SLACK
from sesp.pair import as_pair
from sesp.report import format_map_transitions, map_change
from sesp.topology import RESOLVED_PEAK, components

ASP90 = SeSP(n=2, opening=math.radians(90))
ASP170 = math.radians(170)


@pytest.fixture(scope="session")
def asp170_maps(tmp_path_factory):
    """A maps folder holding the ASP's map at 170° (base 48 cells, floor 1e-4 b, 256 segments), made once for
    all test processes (the first to need it, under a lock) and read by the tests that need that map."""
    shared = tmp_path_factory.getbasetemp().parent / "asp170_maps"
    with open(f"{shared}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        shared.mkdir(exist_ok=True)
        stored_map(shared, ASP170, as_pair(SeSP(n=2, opening=ASP170)), base=48, floor=1e-4)
    return shared


def test_widest_window_agrees_with_the_measure_and_a_fine_phi_sample():
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-2.2, 2.2, (2, 400))
    width, middle = widest_window(ASP90, x, y, segments=64)
    measure = allowed_orientations(ASP90, x, y, segments=64)
    assert np.array_equal(width == 0, measure == 0)  # excluded exactly where nothing is allowed
    assert np.all(width <= measure + 1e-12)
    # for a few positions: a blocked-orientation sample on a fine φ grid finds no longer free run than W
    pair = as_pair(ASP90, segments=64)
    phis = np.linspace(0, 2 * np.pi, 2048, endpoint=False)
    c, s = np.cos(phis), np.sin(phis)
    for k in range(12):
        blocked = []
        for ck, sk in zip(c, s):
            curve = pair.vertices2 @ np.array([[ck, sk], [-sk, ck]]) + (x[k], y[k])
            blocked.append(_polylines_meet(pair.vertices1, curve))
        blocked = np.array(blocked)
        free = ~np.concatenate([blocked, blocked])
        longest, run = 0, 0
        for f in free:
            run = run + 1 if f else 0
            longest = max(longest, min(run, len(phis)))
        step = 2 * np.pi / len(phis)
        assert longest * step <= width[k] + 2 * step
        assert width[k] <= (longest + 2) * step
        if width[k] > 4 * step:  # its middle is allowed
            i = int(round(middle[k] / step)) % len(phis)
            assert not blocked[i]


def _polylines_meet(a, b):
    """Brute force: any segment of a crosses or touches any segment of b."""
    p, q = a[:-1, None, :], a[1:, None, :]
    u, v = b[None, :-1, :], b[None, 1:, :]

    def cross(o, s, t):
        return (s[..., 0] - o[..., 0]) * (t[..., 1] - o[..., 1]) - (s[..., 1] - o[..., 1]) * (t[..., 0] - o[..., 0])

    return bool(np.any((cross(p, q, u) * cross(p, q, v) <= 0) & (cross(u, v, p) * cross(u, v, q) <= 0)))


def _polyline_distance(a, b):
    """Brute force: distance between two polylines (0 when they meet)."""
    if _polylines_meet(a, b):
        return 0.0

    def point_segments(points, s):
        d = s[1:] - s[:-1]
        w = points[:, None, :] - s[None, :-1, :]
        lam = np.clip((w * d).sum(-1) / (d * d).sum(-1), 0, 1)
        return np.linalg.norm(w - lam[..., None] * d, axis=-1).min()

    return min(point_segments(a, b), point_segments(b, a))


def test_clearance_is_the_distance_between_the_curves_and_certifies_its_disk():
    rng = np.random.default_rng(5)
    pair = as_pair(SeSP(n=4, opening=math.radians(120)), segments=64)
    x, y = rng.uniform(-2.5, 2.5, (2, 300))
    caps = np.full(len(x), 10.0)
    width, middle, clear = widest_windows(pair.vertices1, pair.vertices2, x, y, SCREEN_SLACK, ANGLE_GAP, 0.0, caps)
    checked = 0
    for k in np.flatnonzero(width > 0)[:40]:
        c, s = math.cos(middle[k]), math.sin(middle[k])
        curve = pair.vertices2 @ np.array([[c, s], [-s, c]]) + (x[k], y[k])
        exact = _polyline_distance(pair.vertices1, curve)
        assert clear[k] >= exact - 1e-12  # the largest over the tried orientations, the middle among them
        # certificate: every point of the disk of radius clear[k] about t is allowed at some orientation
        for angle in np.linspace(0, 2 * np.pi, 5, endpoint=False):
            r = 0.999 * clear[k]
            xs, ys = x[k] + r * math.cos(angle), y[k] + r * math.sin(angle)
            assert allowed_orientations(pair, xs, ys) > 0
        checked += 1
    assert checked >= 20


def test_clearance_pruned_by_boxes_of_segment_runs_is_the_capped_distance():
    from sesp.kernels.orientations import chunk_boxes, chunk_count, clearance

    rng = np.random.default_rng(8)
    pair = as_pair(SeSP(n=4, opening=math.radians(100)), segments=250)  # the last run of 16 is shorter
    v1, v2 = pair.vertices1, pair.vertices2
    boxes1 = chunk_boxes(v1, np.empty((chunk_count(v1), 4)))
    moved, boxes2 = np.empty_like(v2), np.empty((chunk_count(v2), 4))
    measured = 0
    for x, y, phi, cap in zip(*rng.uniform([-2, -2, 0, 0.001], [2, 2, 2 * np.pi, 0.3], (200, 4)).T):
        c, s = math.cos(phi), math.sin(phi)
        exact = _polyline_distance(v1, v2 @ np.array([[c, s], [-s, c]]) + (x, y))
        got = clearance(v1, boxes1, v2, x, y, phi, cap, moved, boxes2)
        assert got == pytest.approx(min(cap, exact), abs=1e-12)
        measured += 0 < exact < cap
    assert measured >= 15  # not only overlaps and far positions


@pytest.mark.slow
def test_asp_map_finds_the_exact_two_components_and_none_past_pi():
    found = excluded_map(ASP90, base=64)
    assert found.count == 2
    lens = min(found.components, key=lambda c: c.area)
    psi = ASP90.opening
    assert lens.area == pytest.approx((math.pi - psi) - math.sin(psi), rel=0.03)  # README: the lens's exact area
    cell = 2 * as_pair(ASP90).reach / 62
    assert abs(lens.inscribed_radius - (1 - math.sin(psi / 2))) <= cell
    assert 0 < lens.bbox[0] and lens.bbox[1] <= 2 * math.cos(psi / 2) + cell  # the lens lies on x > 0
    assert excluded_map(SeSP(n=2, opening=math.radians(181)), base=64).count == 0


@pytest.mark.slow
def test_asp_map_counts_two_at_30_degrees_with_the_lens_right_of_the_centre():
    """Exact: the lens (in both endpoint disks) on x > 0 and the body (in neither) around it, for 0 < Ψ < π."""
    psi = math.radians(30)
    found = excluded_map(SeSP(n=2, opening=psi), base=64)
    assert found.count == 2
    lens = min(found.components, key=lambda c: c.area)
    assert lens.area == pytest.approx((math.pi - psi) - math.sin(psi), rel=0.03)
    assert 0 < lens.bbox[0] and lens.bbox[1] <= 2 * math.cos(psi / 2) + 2 * as_pair(found.pair).reach / 62


@pytest.mark.parametrize("base", [48, 49])
def test_a_lens_one_node_thick_at_the_floor_is_parted_from_the_body_at_the_centre_s_pinch(base):
    """At 170° the ASP's lens has inscribed radius 1 − sin(Ψ/2) = 0.0038 b; with a floor of 2e-3 b the finest
    cells are 0.0032 b and the lens is one node thick on them. It meets the body only at the particle's
    centre, whose column x = 0 is certified allowed above and below (``centre_pinch``), so lens and body are
    two components on either base grid: the lens on x > 0, marked ``floor`` (one node thick), its area
    within 15 % of the exact (π − Ψ) − sin Ψ (cells of 0.0032 b counted by their centres on a lens 0.0076 b
    thick); the body not marked. Before the centre's pinch was certified, the map saw one component spanning
    both, marked ``floor``."""
    psi = math.radians(170)
    found = excluded_map(SeSP(n=2, opening=psi), base=base, floor=2e-3)
    assert found.finest > 1 - math.sin(psi / 2) - found.finest / 2
    assert found.count == 2
    body, lens = found.components
    assert lens.bbox[0] > 0 > body.bbox[1]
    assert lens.area == pytest.approx((math.pi - psi) - math.sin(psi), rel=0.15)
    assert found.limit(lens) == "floor" and found.limit(body) == ""


@pytest.mark.slow
def test_the_centre_is_a_certified_pinch_for_0_to_pi_and_not_beyond():
    """The column x = 0 is certified allowed around the excluded centre for the ASP and n = 4, 8 (from about 10°,
    5° for n = 4, up to π; checked at 30°, 150°, 179°), over at least the 3 base cells asked for; past π the
    centre is allowed (no pinch)."""
    for n in (2, 4, 8):
        for degrees in (30, 150, 179):
            pair = as_pair(SeSP(n=n, opening=math.radians(degrees)))
            assert centre_pinch(pair, 1e-4, 0.1) >= 0.1, (n, degrees)
        assert centre_pinch(as_pair(SeSP(n=n, opening=math.radians(181))), 1e-4, 0.1) == 0.0
    needle = Polyline([[0.0, -1.0], [0.0, 1.0]])  # along x = 0: the column is excluded, the centre no pinch
    assert centre_pinch(as_pair(needle), 1e-4, 0.1) == 0.0


@pytest.mark.slow
@pytest.mark.parametrize("base", [64, pytest.param(65, marks=pytest.mark.full)])
def test_asp_thin_lens_at_150_degrees_on_even_and_odd_base_grids(base):
    found = excluded_map(SeSP(n=2, opening=math.radians(150)), base=base)
    assert found.count == 2
    lens = min(found.components, key=lambda c: c.area)
    assert lens.area == pytest.approx((math.pi - math.radians(150)) - 0.5, rel=0.1)
    assert not any(c.touches_floor for c in found.components)


@pytest.mark.slow
def test_a_finer_window_that_splits_two_bodies_again_does_not_join_them():
    """At Ψ = 3.125° the ASP's lens and body touch at two pinches behind allowed crescents about 0.05 b thick.
    On 65 cells the coarse window keeps them apart at an undecided neck; the finer window around it splits
    them too, but its line between them falls a node or two from the coarse one, so each finer piece shares
    nodes with both coarse bodies (they were joined: one component)."""
    psi = math.radians(3.125)
    found = excluded_map(SeSP(n=2, opening=psi), base=65, floor=1e-4)
    assert found.count == 2
    lens = min(found.components, key=lambda c: c.area)
    assert lens.area == pytest.approx((math.pi - psi) - math.sin(psi), rel=0.03)


def test_parts_thinner_than_the_polylines_departure_from_the_curve_are_the_polylines():
    """The ASP's lens at 179.375° has inscribed radius 1 − sin(Ψ/2) = 1.5e-5 b; 256 segments depart from the
    circle by 1.9e-5 b (sesp.maps notes), and the lens is not there; 1024 segments (1.2e-6 b) have it."""
    asp = SeSP(n=2, opening=math.radians(179.375))
    x = np.linspace(0.001, 0.01, 32)  # across the lens, 1e-6 b off the axis: 0 < x < 2cos(Ψ/2) = 0.0109
    for segments, departure in ((256, 1.9e-5), (1024, 1.2e-6)):
        v = as_pair(asp, segments=segments).vertices1
        middle = 0.5 * (v[1:] + v[:-1])
        assert 1 - np.hypot(*middle.T).min() == pytest.approx(departure, rel=0.02)  # chord middles: the largest
    width_256, _ = widest_window(asp, x, 1e-6, segments=256)
    width_1024, _ = widest_window(asp, x, 1e-6, segments=1024)
    assert (width_256 > 0).all() and (width_1024 == 0).all()


@pytest.mark.slow
def test_the_polylines_departure_is_the_sagitta_and_thinner_components_are_marked_unresolved(asp170_maps):
    """An ASP's polyline departs from the circle by the sagitta 1 − cos(Δ/2), Δ the angle its longest chord
    spans; a pair departs by both. With 12 segments every piece of the set at 170° is thinner than the 0.019 b
    departure or seen only at the floor, and marked; with 256 the lens and body are resolved."""
    from sesp.maps import _transitions_dataset

    psi = math.radians(170)
    for segments in (12, 256):
        chord = np.hypot(*np.diff(SeSP(n=2, opening=psi).polyline(segments).vertices, axis=0).T).max()
        sagitta = 1 - math.sqrt(1 - chord**2 / 4)
        assert as_pair(SeSP(n=2, opening=psi), segments=segments).departure == pytest.approx(2 * sagitta, rel=1e-6)
    assert as_pair(Polyline([[0, 0], [1, 0]])).departure == 0.0
    polygon = excluded_map(SeSP(n=2, opening=psi), segments=12, base=48, floor=1e-4)
    assert polygon.count and all(polygon.limit(c) for c in polygon.components)
    arc = stored_map(asp170_maps, psi, as_pair(SeSP(n=2, opening=psi)), base=48, floor=1e-4)  # 256 segments
    assert arc.count == 2 and not any(arc.limit(c) for c in arc.components)
    assert arc.dataset().attrs["departure"] == pytest.approx(2 * sagitta, rel=1e-6)
    both = _transitions_dataset({psi: (polygon, 1e-4), psi + 0.01: (arc, 1e-4)}, [(psi, psi + 0.01, 1e-4)], 1e-4, 48)
    assert both.transition_unresolved.values.tolist() == [True]
    assert both.unresolved.values[1].tolist() == [False] * both.sizes["component"]  # padded to the polygon's 5


@pytest.mark.slow
@pytest.mark.full  # the channel rule's fast checks: the two synthetic channel and sliver tests below
@pytest.mark.parametrize("base", [97, 128])
def test_the_asp_crescents_at_0_3_degrees_are_followed_and_part_lens_and_body(base, tmp_path):
    """At Ψ = 0.3125° the ASP's lens and body (exact: two components) are parted by crescents at most
    2·sin(Ψ/2) = 0.0055 b wide, an eighth of a cell of 97 (97 cells saw one body before). The channels
    through the base window's slivers are followed with certified disks: two components, resolved, on both
    grids, the lens within 1% of its exact area (π − Ψ) − sin Ψ; every disk's points are allowed."""
    psi = math.radians(0.3125)
    found = excluded_map(SeSP(n=2, opening=psi), base=base, floor=1e-4)
    assert found.count == 2 and found.channels > 100
    assert not any(found.limit(c) for c in found.components)
    lens = min(found.components, key=lambda c: c.area)
    assert lens.area == pytest.approx((math.pi - psi) - math.sin(psi), rel=0.01)
    assert lens.bbox[0] > -0.05 and lens.bbox[1] == pytest.approx(2 * math.cos(psi / 2), abs=0.05)
    back = ExcludedMap.from_dataset(load(save(found.dataset(), tmp_path / "map.nc")))
    assert back.channels == found.channels == len(back.disks) and back.count == 2
    assert np.array_equal(back.disks, found.disks)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sesp.plot import component_map

    ax = component_map(back)
    assert [t.get_text() for t in ax.get_legend().get_texts()][-1].startswith("certified allowed channel")
    plt.close(ax.figure)


def test_channel_disks_hold_only_allowed_positions_and_overlap_along_the_path():
    """The disks a channel is followed with (sesp.channels) are proven allowed by the clearance certificate:
    random points inside them are allowed, exact in φ, and each disk overlaps the next one of its path."""
    pair = as_pair(SeSP(n=2, opening=math.radians(2.5)))
    psi = math.radians(2.5)
    seed = (math.cos(psi / 2), 1.0)  # the middle of the upper crescent, between the circles about the end points
    disks = channels.traced_channels(pair, [seed], cell=0.04, floor=1e-4)
    assert len(disks) > 50 and np.all(disks[:, 2] > 0) and np.all(disks[:, 2] <= 0.04)
    rng = np.random.default_rng(5)
    pick = disks[rng.choice(len(disks), 200)]
    r = pick[:, 2] * np.sqrt(rng.uniform(0, 1, 200))
    angle = rng.uniform(0, 2 * np.pi, 200)
    width, _ = widest_window(pair, pick[:, 0] + r * np.cos(angle), pick[:, 1] + r * np.sin(angle))
    assert np.all(width > 0)
    apart = np.hypot(*(disks[:, None, :2] - disks[None, :, :2]).transpose(2, 0, 1))
    overlap = apart < disks[:, None, 2] + disks[None, :, 2]
    assert connected_components(overlap, directed=False)[0] == 1  # one chain through the seed, both arms
    # the path runs in the exact allowed set: inside the crescent (the first end point's unit disk, not the
    # second's) from near the centre, and out beyond |t| = 2cos(Ψ/2), where the crescent opens
    e = np.array([math.cos(psi / 2), math.sin(psi / 2)])
    inside1 = np.hypot(*(disks[:, :2] - e).T) <= 1 + 1e-3
    outside2 = np.hypot(*(disks[:, :2] - e * [1, -1]).T) >= 1 - 1e-3
    beyond = np.hypot(*disks[:, :2].T) >= 2 * math.cos(psi / 2) - 1e-3
    assert np.all((inside1 & outside2) | beyond) and beyond.any()
    assert np.hypot(*disks[:, :2].T).min() < 0.01


def test_base_slivers_are_the_seeds_of_the_channels_and_none_where_the_cells_see_the_set():
    """The ASP at Ψ = 0.3125° on 97 cells: a few allowed nodes enclosed by the excluded set, each in the exact
    allowed set (in one end point's unit disk only), to within how far the polylines depart from the arcs;
    at 90° none."""
    psi = math.radians(0.3125)
    asp = SeSP(n=2, opening=psi)
    seeds = maps.base_slivers(asp, base=97, floor=1e-4)
    assert 2 <= len(seeds) <= 40
    e = np.array([math.cos(psi / 2), math.sin(psi / 2)])
    d1 = np.hypot(*(seeds - e).T) - 1  # signed distance to the unit circle about each end point
    d2 = np.hypot(*(seeds - e * [1, -1]).T) - 1
    near = np.minimum(abs(d1), abs(d2)) <= as_pair(asp).departure
    assert np.all((np.sign(d1) != np.sign(d2)) | near) and not near.all()
    assert len(maps.base_slivers(ASP90, base=97, floor=1e-4)) == 0


def test_a_component_that_encloses_allowed_slivers_is_marked():
    """A component that encloses allowed nodes in clusters at most two nodes deep (slivers seen only where a
    node fell in them) is marked; one whose hole is deeper is not."""
    labels = np.zeros((12, 12), dtype=np.int64)
    labels[1:11, 1:11] = 1
    labels[5, 5] = 0  # a one-node sliver
    flagged, nodes = maps._slivers(labels, labels > 0)
    assert flagged == {1} and nodes.sum() == 1 and nodes[5, 5]
    labels[3:9, 3:9] = 0  # a hole 6 nodes across: an allowed region the cells resolve
    assert maps._slivers(labels, labels > 0)[0] == set()


def test_asymmetric_polyline_components_off_every_axis_match_a_brute_force_raster():
    """A hook has no symmetry axis; a fine exact-in-φ raster counted by the same pinch rule finds the same pieces."""
    hook = Polyline([[-0.6, -0.5], [0.5, -0.5], [0.5, 0.6], [0.1, 0.6], [0.1, 0.1]])
    pair = as_pair(hook, segments=64)
    found = excluded_map(pair, base=64)
    nodes = 320  # the small piece is about 0.03 b thick: coarser rasters (160, 241 nodes) merge it
    step = 2 * pair.reach / nodes
    side = (np.arange(nodes) - (nodes - 1) / 2) * step
    x, y = np.meshgrid(side, side)
    brute = components(allowed_orientations(pair, x, y) == 0, measure=step * step)
    assert found.count == brute.count == 2
    for k, comp in enumerate(found.components, start=1):
        assert comp.area == pytest.approx(brute.areas[k - 1], rel=0.2)
        cy, cx = ndimage.center_of_mass(brute.labels == k)
        cx, cy = side[0] + cx * step, side[0] + cy * step
        assert comp.bbox[0] <= cx <= comp.bbox[1] and comp.bbox[2] <= cy <= comp.bbox[3]
    small = found.components[1]
    assert abs(small.bbox[2] + small.bbox[3]) > 0.1 or abs(small.bbox[0] + small.bbox[1]) > 0.1  # off-centre


def test_components_report_undecided_necks_only_when_asked():
    y, x = np.mgrid[:80, :80]
    mask = ((x - 25) ** 2 + (y - 40) ** 2 <= 14**2) | ((x - 55) ** 2 + (y - 40) ** 2 <= 14**2)
    mask |= (np.abs(y - 40) <= 8) & (x > 30) & (x < 50)  # a neck 17 nodes wide between two disks of radius 14
    assert components(mask).count == 1 and len(components(mask).necks) == 0
    found = components(mask, neck=1.0)
    assert found.count == 2  # kept apart for a finer look
    assert len(found.necks) == 1 and set(found.necks[0, 1:3]) == {1, 2}
    assert 8 <= found.necks[0, 3] <= 10


def test_a_neck_within_a_node_of_the_threshold_is_undecided_not_apart():
    """Disks of radius 14 nodes joined by a bar 6.5 nodes in half-width: the neck s (about 6.5) is under
    0.5 · 14 = 7, so the rule parts them, but by less than a node (NEAR), which the distance field does not
    resolve: asked for necks, components keeps them apart as undecided, for a finer look; not asked, apart.
    A bar 4.5 nodes wide parts them by more than a node: apart either way, no neck listed."""
    y, x = np.mgrid[:80, :80]
    disks = ((x - 25) ** 2 + (y - 40) ** 2 <= 14**2) | ((x - 55) ** 2 + (y - 40) ** 2 <= 14**2)
    near, narrow = (disks | (np.abs(y - 40) <= half) & (x > 30) & (x < 50) for half in (6.5, 4.5))
    found = components(near, neck=0.8)
    assert found.count == 2 and len(found.necks) == 1
    assert 0.5 * found.peaks.min() - 1 <= found.necks[0, 3] < 0.5 * found.peaks.min()
    # seen as wide by a coarser window (as a waist is), it stays undecided: it still parts the bodies by the rule
    from sesp.maps import _waists
    from sesp.topology import distance_to_complement

    dist = distance_to_complement(near, (), False)
    assert _waists(found, np.full(near.shape, found.necks[0, 3]), 1.0, near, dist).count == 2
    for mask, asked in ((near, 0.0), (narrow, 0.8), (narrow, 0.0)):
        found = components(mask, neck=asked)
        assert found.count == 2 and len(found.necks) == 0


def _arrowhead():
    """Two wings (disks of radius 30 nodes) each joined to a tip (radius 18) by a bar 12 nodes in half-width:
    narrow for the wings (12 < 0.5 · 30), undecided for the tip (0.5 · 18 <= 12 < 0.8 · 18)."""
    y, x = np.mgrid[:180, :130]

    def bar(ax, ay, bx, by, half):
        t = np.clip(((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2), 0, 1)
        return (x - ax - t * (bx - ax)) ** 2 + (y - ay - t * (by - ay)) ** 2 <= half * half

    mask = ((x - 40) ** 2 + (y - 40) ** 2 <= 30**2) | ((x - 40) ** 2 + (y - 140) ** 2 <= 30**2)
    mask |= ((x - 95) ** 2 + (y - 90) ** 2 <= 18**2) | bar(95, 90, 40, 40, 12) | bar(95, 90, 40, 140, 12)
    return mask


def test_a_body_that_reaches_a_part_at_a_smaller_body_is_judged_against_that_body():
    """The second wing meets the part made of the first wing and the tip at the tip: its neck is judged
    against the tip (undecided, like the first wing's), not against the first wing (narrow: apart). So the
    mirror-symmetric arrowhead has two mirror necks, and the wings are not cut from each other."""
    found = components(_arrowhead(), neck=0.8)
    assert found.count == 3
    tip = int(np.argmin(found.peaks)) + 1
    pairs = sorted(tuple(sorted(int(k) for k in row[1:3])) for row in found.necks)
    assert pairs == sorted(tuple(sorted((wing, tip))) for wing in {1, 2, 3} - {tip})
    assert found.necks[0, 3] == found.necks[1, 3]


@pytest.mark.slow
@pytest.mark.parametrize(
    "base, degrees, floor",
    [
        pytest.param(97, 172.5, 1e-3, marks=pytest.mark.full),
        (128, 172.5, 1e-3),
        pytest.param(97, 173.75, 3e-4, marks=pytest.mark.full),
        (128, 173.75, 3e-4),
        pytest.param(97, 173.125, 3e-4, marks=pytest.mark.full),
    ],
)
def test_the_n4_arrowhead_is_one_body_on_even_and_odd_base_grids(base, degrees, floor):
    """n = 4, Ψ = 172.5° to 173.75°: two wings meet at a tip on the axis. A brute-force exact-in-φ raster
    (cells of 0.004 b, four-connected) finds one body; so must the map, on either base grid. At 172.5° it cut
    a wing or the tip off while a third body met a part at a kept body and was judged against the part's
    largest; at 173.75° a finer window saw the wings as one, but the coarser one had split them, 4 nodes
    thick, at a neck it decided. At 173.125° on 97 cells it cut a wing off at a neck the rule decided by
    less than a node, where a shallow maximum at the tip went unseen. (At the finer floor the map may also
    find the thin island and tail on the axis right of the arrowhead: they are not part of this test.)"""
    particle = SeSP(n=4, opening=math.radians(degrees))
    found = excluded_map(particle, base=base, floor=floor)
    arrowhead = [c for c in found.components if c.bbox[0] < -0.38]
    assert len(arrowhead) == 1
    assert all(c.bbox[0] > -0.3 and max(-c.bbox[2], c.bbox[3]) < 0.01 for c in found.components[1:])
    x, y = np.arange(-0.72, -0.38, 0.004), np.arange(-0.25, 0.25, 0.004)
    width, _ = widest_window(particle, *np.meshgrid(x, y))
    pieces, count = ndimage.label(width == 0)
    sizes = np.bincount(pieces.ravel())[1:]
    assert count == 1 or np.sort(sizes)[-2] < 0.01 * sizes.max()  # one body (and at most specks)
    assert arrowhead[0].area == pytest.approx(sizes.max() * 0.004**2, rel=0.05)
    iy, ix = np.nonzero(pieces == np.argmax(sizes) + 1)
    raster_box = (x[ix].min(), x[ix].max(), y[iy].min(), y[iy].max())
    assert arrowhead[0].bbox == pytest.approx(raster_box, abs=0.01)  # both wings and the tip


@pytest.mark.slow
@pytest.mark.parametrize("base", [pytest.param(97, marks=pytest.mark.full), 128])
def test_an_allowed_wedge_a_node_fell_in_stays_open_on_finer_windows(base):
    """n = 8, Ψ = 5°: the lens (right of the centre) and the body meet only at the particle's centre; between
    them an allowed wedge runs up from the centre along x ≈ 0, 1.2e-3 b wide at y = 0.1 b (brute force below:
    allowed in it, excluded on either side). The base grid's column of nodes on x = 0 lies in it; the finer
    windows nest (odd zoom), so those allowed nodes stay and the pinch at the centre parts the two. With a zoom
    of 4 the finer nodes straddled the column, closed the wedge, and the 97-cell map found one body. The lens
    reaches the wedge: a brute-force raster (cells of 0.005 b) finds W = 0 from x = 0.005 to 0.4 b on every row
    below y = 0.25 b. Every base grid has a column of nodes on x = 0: without it the 128-cell grid saw no
    allowed node in the wedge (at 2.5° it found lens and body as one, unmarked)."""
    particle = SeSP(n=8, opening=math.radians(5))
    width, _ = widest_window(particle, np.array([-0.002, 0.0003, 0.003]), np.full(3, 0.1))
    assert width[0] == 0 and width[1] > 0 and width[2] == 0
    found = excluded_map(particle, base=base, floor=3e-3)
    assert found.count == 2
    lens = found.components[1]
    assert lens.bbox[1] < 2.0 and lens.bbox[3] == pytest.approx(-lens.bbox[2], abs=0.05)
    assert 0 < lens.bbox[0] < 0.01  # the lens reaches the wedge, on either base grid


@pytest.mark.parametrize("zoom", [2, 4, 17])
def test_the_zoom_must_be_odd_and_at_most_15(zoom):
    with pytest.raises(ValueError, match="zoom"):
        excluded_map(SeSP(n=2, opening=1.0), zoom=zoom, floor=1e-2)


@pytest.mark.slow
def test_a_strip_of_uncertain_cells_that_starts_beside_a_body_is_refined_along_its_length():
    """n = 8, Ψ = 155°: the island on the axis right of the centre, 0.01 b thick (brute force below), lies
    between the two node rows of an even base grid, whose nodes beside it are uncertain. That strip of
    uncertain nodes starts beside the body's tail; on the first finer window it touched the tail's excluded
    nodes, and the whole strip was left as the body's rim: the 128-cell map missed the island."""
    particle = SeSP(n=8, opening=math.radians(155))
    width, _ = widest_window(particle, np.array([0.1, 0.4, 0.7, 0.1, 0.4, 0.7]), np.repeat([0.0, 0.006], 3))
    assert np.all(width[:3] == 0) and np.all(width[3:] > 0)
    found = excluded_map(particle, base=128, floor=1e-3)
    assert found.count == 2
    island = found.components[1]
    assert island.bbox[0] < 0.1 and island.bbox[1] > 0.7 and max(-island.bbox[2], island.bbox[3]) < 0.01


@pytest.mark.slow
def test_bodies_kept_apart_at_a_neck_undecided_at_the_floor_are_marked():
    """At a floor of 1e-3 b the n = 4 arrowhead at Ψ = 173.75° is seen in pieces (two wings, the tip apart or
    with one of them), kept apart at necks the floor stops the look at (refined, they join: the test above):
    each is marked ``floor``."""
    found = excluded_map(SeSP(n=4, opening=math.radians(173.75)), base=97, floor=1e-3)
    assert found.count >= 2
    assert all(found.limit(c) == "floor" for c in found.components)


def _dumbbell(h):
    """Two disks of radius 1 b about x = ±2 b joined by a bar 1.3 b wide, on nodes spaced h b: (mask, x, y)."""
    y, x = np.mgrid[-1.5:1.5:h, -3.5:3.5:h]
    mask = ((np.abs(x) - 2) ** 2 + y**2 <= 1) | ((np.abs(x) < 2) & (np.abs(y) <= 0.65))
    return mask, x, y


@pytest.mark.parametrize("coarse_share", [1.0, 4.0])
def test_a_neck_that_keeps_its_width_on_finer_cells_is_a_waist(coarse_share):
    """The bar (s / p = 0.65) stays undecided at any cell size. Seen again on cells 4 times smaller, its
    width in b stays: it is a waist, and the bodies join. Had the coarser window seen it 4 times wider (a
    pinch behind a wedge keeps its width in nodes), it stays undecided."""
    from sesp.maps import _waists
    from sesp.topology import distance_to_complement

    h = 0.1
    coarse = components(_dumbbell(h)[0], neck=0.8)
    assert coarse.count == 2 and len(coarse.necks) == 1
    mask, x, y = _dumbbell(h / 4)
    dist = distance_to_complement(mask, (), False)
    fine = components(mask, neck=0.8, distance=dist)
    assert fine.count == 2 and len(fine.necks) == 1  # the rule alone never decides it
    necks_above = np.where(np.abs(x) < 2, coarse_share * coarse.necks[0, 3] * h, 0.0)
    joined = _waists(fine, necks_above, h / 4, mask, dist)
    assert joined.count == (1 if coarse_share == 1.0 else 2)
    assert len(joined.necks) == (0 if coarse_share == 1.0 else 1)
    assert joined.sizes.sum() == fine.sizes.sum()


def test_a_thin_strip_running_away_from_a_thick_body_is_refined_beyond_the_body_s_cells():
    """Beside a body deeper than 256 cells its rim and tips are left unrefined (they look the same at every
    scale), but a cluster of unsettled nodes that runs on away from it (the n = 8 island at Ψ = 175°, behind
    the body's tail and the centre's pinch, 0.48 b long and 3e-4 b thick) is refined beyond the body's cells:
    it may hold a component."""
    from sesp.maps import _SETTLED, _untapered

    h = 0.01
    y, x = np.mgrid[0:200, 0:300].astype(float)
    body = (x - 80) ** 2 + (y - 100) ** 2 <= 70**2
    depth = np.where(body, 300 * h, 0.0)  # the body's inscribed radius as the coarser windows measured it, b
    rim = ndimage.binary_dilation(body, iterations=2) & ~body
    strip = (y == 100) & (x >= 150) & (x < 290)  # starts at the body's edge, runs 140 nodes away
    thick = ndimage.distance_transform_edt(body) >= RESOLVED_PEAK
    kept = _untapered(rim | strip, depth, h, thick)
    assert not (kept & rim).any()
    gap = ndimage.distance_transform_edt(~body)
    assert np.array_equal(kept, strip & (gap > _SETTLED + 2))
    assert kept.sum() > 100
    assert _untapered(rim | strip, depth, 2 * h, thick).sum() == (rim | strip).sum()  # 150 cells deep: all refined


def test_a_thin_part_of_a_thick_body_running_away_from_it_is_refined_beyond_its_tip():
    """A thin part joined to a deep body on these cells (the n = 8 lens at Ψ = 168.125°, under two nodes thick
    on the cells where the count took it into the body's tail) takes the body's depth; only its first
    ``_TIP`` nodes from the body's thick nodes are the body's tip and left: the rest is refined. Left whole,
    the lens was lost on 97 base cells and found on 128."""
    from sesp.maps import _SETTLED, _TIP, _untapered

    h = 0.01
    y, x = np.mgrid[0:200, 0:300].astype(float)
    core = (x - 80) ** 2 + (y - 100) ** 2 <= 70**2
    tail = (np.abs(y - 100) <= 1) & (x >= 150) & (x < 290)  # three nodes wide: no node of it is thick
    body = core | tail
    depth = np.where(body, 300 * h, 0.0)
    thick = ndimage.distance_transform_edt(body) >= RESOLVED_PEAK
    assert not (thick & tail).any()
    kept = _untapered(tail, depth, h, thick)
    gap = ndimage.distance_transform_edt(~thick)
    assert np.array_equal(kept, tail & (gap > _TIP + _SETTLED + 2))
    assert kept.sum() > 200


@pytest.mark.slow
def test_transitions_on_maps_bracket_the_asp_end_at_pi(tmp_path, monkeypatch, capsys, asp170_maps):
    """The excluded set ends at π: the last change, to 0, is bracketed around 180°. Below it the lens, under
    4e-3 b thick from 170° (a twentieth of a base cell) and pinched to the body at the centre, is found: two
    components, the lens with its exact area (π − Ψ) − sin Ψ. Each map is saved as it is made: the same
    search again reads them all and makes none, and gives the same result."""
    search = functools.partial(map_transitions, ASP90, (math.radians(170), math.radians(210)), step=math.radians(20),
                               base=48, tolerance=math.radians(5), floor=1e-4, folder=tmp_path)  # fmt: skip
    result = search()
    saved = sorted(tmp_path.glob("map_*.nc"))
    assert len(saved) == result.sizes["opening"]
    monkeypatch.setattr(maps, "excluded_map", lambda *args, **kwargs: pytest.fail("a saved map was made again"))
    xr.testing.assert_identical(search(), result)
    with pytest.raises(SespFileError, match="base_cells differ"):
        functools.partial(search, base=64)()
    assert list(result["count"].sel(opening=[math.radians(190)]).values) == [0]
    assert result["count"].sel(opening=math.radians(170)).item() == 2
    lens = result["area"].sel(opening=math.radians(170)).values[1]
    psi = math.radians(170)
    assert lens == pytest.approx((math.pi - psi) - math.sin(psi), rel=0.05)
    assert result.count_high.values[-1] == 0
    assert result.high_degrees.values[-1] - result.low_degrees.values[-1] <= 10.0
    assert result.low_degrees.values[-1] <= 180.0 <= result.high_degrees.values[-1] + 2.5
    # the command line draws the same search from the saved maps, and prints it as JSON
    command = ["topology", "--n", "2", "--opening-range", "170", "210", "--step", "20", "--base", "48", "--floor",
               "1e-4", "--tolerance", "5", "--maps-folder", str(tmp_path), "--quiet"]  # fmt: skip
    png = tmp_path / "counts.png"
    assert main([*command, "--map", "--plot", str(png)]) == 0
    assert png.stat().st_size > 10_000
    capsys.readouterr()
    assert main([*command, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [t["count_high"] for t in out["transitions"]] == list(result.count_high.values)
    last = out["transitions"][-1]  # everything at its low end vanishes
    assert last["changed_low"] == list(range(1, last["count_low"] + 1)) and last["changed_high"] == []
    first, final = out["intervals"][0], out["intervals"][-1]
    assert (first["from_deg"], first["count"]) == (170.0, 2) and (final["to_deg"], final["count"]) == (210.0, 0)


def _piece(ymin, ymax):
    return _boxed(-1.0, 1.0, ymin, ymax)


def test_transition_search_sees_changes_that_leave_the_count_unchanged_over_a_step(monkeypatch):
    """A strip on the axis joins the body at 3° (2 -> 1) and the body parts into a mirror pair off the axis at
    6° (1 -> 2): the count is 2 at both ends of the 0-10° step, and the number off the axis is not, so the
    step is bisected and both changes are bracketed."""

    def search(join, part):
        def fake_map(folder, opening, pair, **kwargs):
            psi = math.degrees(opening)
            body = [_piece(-0.5, 0.5)] if psi < part else [_piece(-0.5, -0.01), _piece(0.01, 0.5)]
            strip = [_piece(-1e-3, 1e-3)] if psi < join else []
            return ExcludedMap(body + strip, floor=1e-4, base_cells=32, reach=2.0, positions=1, finest=1e-4)

        monkeypatch.setattr(maps, "stored_map", fake_map)
        return map_transitions(SeSP(n=4), (0.0, math.radians(10)), step=math.radians(10),
                               tolerance=math.radians(0.5))  # fmt: skip

    result = search(3.0, 6.0)
    assert [int(v) for v in result["count"].sel(opening=[0.0, math.radians(10)])] == [2, 2]
    assert list(result.off_axis.sel(opening=[0.0, math.radians(10)]).values) == [0, 2]
    assert [(int(a), int(b)) for a, b in zip(result.count_low, result.count_high)] == [(2, 1), (1, 2)]
    for t, event in enumerate((3.0, 6.0)):
        assert result.low_degrees[t] < event <= result.high_degrees[t] <= result.low_degrees[t] + 1.0
    assert list(result.off_axis_high.values) == [0, 2]
    both = search(3.0, 3.1)  # in one bracket: the count is the same at its ends, the number off the axis is not
    assert both.sizes["transition"] == 1 and map_change(both, 0) == "2 -> 2 (off axis 0 -> 2)"
    assert "2 -> 2 (off axis 0 -> 2) at Psi in" in format_map_transitions(both)
    assert map_change(result, 0) == "2 -> 1"


def test_steps_given_as_finer_are_searched_at_a_tenth_of_the_floor_and_grow_where_the_floors_disagree(
    monkeypatch, capsys
):
    """A body parts at 9.5° on maps at the floor and at 10.5° on maps ten times finer. Asking for 0-10° finer
    searches that step at 1e-5 b, which sees no change in it and a state at 10° that the floor's map does not
    share: the step beside it is searched finer too, and the one change is bracketed there, at 1e-5 b, and
    nowhere at 1e-4 b."""
    asked = []

    def fake_map(folder, opening, pair, *, floor, **kwargs):
        asked.append((folder, floor))
        parts = math.degrees(opening) >= (9.5 if floor == 1e-4 else 10.5)
        body = [_piece(-0.5, -0.01), _piece(0.01, 0.5)] if parts else [_piece(-0.5, 0.5)]
        return ExcludedMap(body, floor=floor, base_cells=32, reach=2.0, positions=1, finest=floor)

    monkeypatch.setattr(maps, "stored_map", fake_map)

    def search(finer):
        return map_transitions(SeSP(n=4), (0.0, math.radians(30)), step=math.radians(10), tolerance=math.radians(0.5),
                               floor=1e-4, folder="saved", finer=finer)  # fmt: skip

    plain = search(())
    assert plain.low_degrees.item() < 9.5 <= plain.high_degrees.item() and plain.transition_floor.item() == 1e-4
    assert {f for _, f in asked} == {1e-4}
    asked.clear()
    refined = search([(0.0, math.radians(10))])
    assert refined.sizes["transition"] == 1
    assert refined.low_degrees.item() < 10.5 <= refined.high_degrees.item() <= refined.low_degrees.item() + 1.0
    assert refined.transition_floor.item() == 1e-5
    floors = dict(zip(refined.opening_degrees.values.round(6), refined.map_floor.values))
    assert floors[0.0] == floors[10.0] == floors[20.0] == 1e-5 and floors[30.0] == 1e-4  # 20-30 stays at the floor
    assert {folder for folder, f in asked if f == 1e-5} == {Path("saved") / "floor_1e-05"}
    (line,) = [line for line in format_map_transitions(refined).splitlines() if line.startswith("  * ")]
    assert line.startswith("  * 1 -> 2 at Psi in [10.") and line.endswith("(floor 1e-05 b)")
    command = ["topology", "--n", "4", "--opening-range", "0", "30", "--step", "10", "--tolerance", "0.5", "--floor",
               "1e-4", "--maps-folder", "saved", "--quiet", "--json"]  # fmt: skip
    capsys.readouterr()
    assert main([*command, "--finer", "0", "10"]) == 0
    (only,) = json.loads(capsys.readouterr().out)["transitions"]
    assert (only["low_deg"], only["high_deg"], only["floor"]) == (
        refined.low_degrees.item(), refined.high_degrees.item(), 1e-5
    )  # fmt: skip
    for wrong in (["--finer", "10", "5"], ["--finer", "0", "400"]):
        with pytest.raises(ValueError, match="--finer must satisfy 0 <= LOW < HIGH <= 360"):
            main([*command, "--debug", *wrong])
    with pytest.raises(ValueError, match="finer ranges must satisfy 0 <= low < high"):
        search([(0.3, 0.1)])  # a range given backwards is an error, not silently nothing
    with pytest.raises(ValueError, match="--finer refines a search on adaptive maps"):
        main(["topology", "--debug", "--opening", "90", "--finer", "0", "10"])


def test_a_finer_range_ending_on_a_step_s_opening_does_not_reach_into_the_next_step():
    """The openings of a search are low + k·step, so 170° may be a hair below math.radians(170): the range
    165-170° given as finer is the one step 165-170°, not also 170-175° (where the floors agree)."""
    step = math.radians(5)
    openings = [float(o) for o in step * np.arange(73)]
    assert openings[34] != math.radians(170)  # the rounding this guards against
    steps = list(zip(openings[:-1], openings[1:]))
    same = lambda opening: (1, 0)  # noqa: E731
    assert maps._refined_steps(steps, [(math.radians(165), math.radians(170))], same, same) == {33}
    assert maps._refined_steps(steps, [(math.radians(166), math.radians(171))], same, same) == {33, 34}


def _change_unresolved(low, high):
    return maps._change(low, high, max(low.count, high.count))[2]


def test_a_transition_is_unresolved_only_where_a_component_that_changes_is():
    """Two maps a step apart: a resolved body parts in two, and a strip of the floor beside it moves a little
    and stays: the body's parts are the change, the strip is not, and the transition is resolved. When the
    strip vanishes instead, or leaves the axis, it changes, and the transition is unresolved."""
    cell = 0.01
    body = _blob(-0.5, 0.0, cell, 80, 0.2, floor=False)  # x from -0.5 to 0.29
    left, right = _blob(-0.5, 0.0, cell, 38, 0.1, floor=False), _blob(-0.1, 0.0, cell, 39, 0.1, floor=False)
    strip, moved, lifted = (
        dataclasses.replace(_blob(x, y, cell, 20, 1e-4), floor_limited=True)
        for x, y in ((0.5, 0.0), (0.505, 0.0), (0.5, 0.02))  # lifted: wholly above the axis, 2 cells up
    )

    def pair_of_maps(low, high):
        return tuple(ExcludedMap(c, floor=1e-4, base_cells=32, reach=2.0, positions=1, finest=1e-4)
                     for c in (low, high))  # fmt: skip

    low, high = pair_of_maps([body, strip], [left, right, moved])
    assert high.limit(moved) == "floor" and not high.limit(left)
    assert [c.x.size for c in maps.changed_components(low, high)[0]] == [80]
    assert [c.x.size for c in maps.changed_components(low, high)[1]] == [38, 39]
    assert not _change_unresolved(low, high)
    assert [list(row) for row in maps._change(low, high, 4)[:2]] == [
        [True, False, False, False],
        [True, True, False, False],
    ]
    for high in ([left, right], [left, right, lifted]):
        assert _change_unresolved(*pair_of_maps([body, strip], high))
    # where none is found to change (the count did not either), any unresolved component marks it
    assert maps.changed_components(*pair_of_maps([strip], [moved])) == ([], [])
    assert _change_unresolved(*pair_of_maps([strip], [moved]))


def _boxed(*bbox):
    return maps.MapComponent(1.0, 0.1, bbox, False, np.empty(0), np.empty(0), np.empty(0))


def test_a_component_whose_mirror_image_is_not_one_is_unresolved_for_a_mirror_symmetric_pair():
    """The excluded set of a SeSP with itself is its own mirror image about the x-axis, and so is its
    partition: a body on the axis and a mirror pair off it are resolved; a lobe parted from a body that keeps
    the other lobe (the two judged differently at mirror necks) is marked "mirror", and so is that body. A pair
    of Polylines has no such symmetry: nothing is marked."""
    body, upper, lower = _boxed(-1.0, 0.0, -0.3, 0.3), _boxed(0.2, 0.5, 0.1, 0.4), _boxed(0.2, 0.5, -0.41, -0.1)
    lobe, rest = _boxed(-1.0, -0.6, 0.002, 0.26), _boxed(-1.0, 0.0, -0.26, 0.035)
    components = [body, upper, lower, lobe, rest]

    def mapped(pair):
        return ExcludedMap(components, floor=1e-4, base_cells=128, reach=2.0, positions=1, finest=1e-4, pair=pair)

    found = mapped(as_pair(ASP90))
    assert [found.limit(c) for c in components] == ["", "", "", "mirror", "mirror"]
    assert found.dataset().unresolved.values.tolist() == [False, False, False, True, True]
    square = Polyline([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    assert [mapped(as_pair(square)).limit(c) for c in components] == [""] * 5
    assert [mapped(None).limit(c) for c in components] == [""] * 5  # read without its pair: not known


def _lattice(xs, ys, radius, cell=0.01):
    """A synthetic map component: the nodes of the rectangle xs × ys (ranges of b) on a lattice of ``cell``."""
    x, y = np.meshgrid(np.arange(*xs, cell), np.arange(*ys, cell))
    x, y = np.round(x.ravel(), 9), np.round(y.ravel(), 9)
    box = (x.min() - cell / 2, x.max() + cell / 2, y.min() - cell / 2, y.max() + cell / 2)
    return MapComponent(x.size * cell * cell, radius, box, False, x, y, np.full(x.size, cell))


def test_a_partition_that_is_not_its_own_mirror_image_is_joined_into_one_that_is():
    """Two mirror lobes off the axis and a strip along it: parted as the lower lobe with the strip and the upper
    lobe alone (mirror necks judged differently), they are joined into one, marked; parted all three, or as two
    lobes of which one holds a pinch's point on the axis, they are left. A pair of Polylines is not mirror
    symmetric: nothing is joined."""
    lower, upper = _lattice((-0.9, -0.6), (-0.25, -0.045), 0.1), _lattice((-0.9, -0.6), (0.05, 0.255), 0.1)
    strip = _lattice((-0.59, 0.001), (0.0, 0.001), 0.005)
    pinch = _lattice((-0.6, -0.599), (0.0, 0.001), 0.005)  # one node on the axis
    pair = as_pair(ASP90)
    joined = maps.mirror_joined([maps._merged(lower, strip), upper], pair)
    assert len(joined) == 1 and joined[0].mirror_joined and joined[0].x.size == lower.x.size * 2 + strip.x.size
    found = ExcludedMap(joined, floor=1e-4, base_cells=128, reach=2.0, positions=1, finest=1e-4, pair=pair)
    assert found.limit(joined[0]) == "mirror" and found.dataset().mirror_joined.values.tolist() == [True]
    assert [c.mirror_joined for c in maps.mirror_joined([lower, upper, strip], pair)] == [False] * 3
    assert len(maps.mirror_joined([maps._merged(lower, pinch), upper], pair)) == 2
    square = as_pair(Polyline([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]))
    assert len(maps.mirror_joined([maps._merged(lower, strip), upper], square)) == 2


@pytest.mark.slow
def test_a_map_saved_and_read_back_keeps_its_components_and_marks(tmp_path, capsys):
    found = excluded_map(ASP90, base=48)
    path = save(found.dataset(), tmp_path / "asp90.nc")
    back = ExcludedMap.from_dataset(load(path))
    assert back.count == found.count == 2
    for a, b in zip(back.components, found.components):
        assert (a.area, a.inscribed_radius, a.bbox, a.touches_floor) == (b.area, b.inscribed_radius, b.bbox,
                                                                          b.touches_floor)  # fmt: skip
        assert back.limit(a) == found.limit(b)
        assert len(a.x) > 0 and all(np.array_equal(getattr(a, k), getattr(b, k)) for k in ("x", "y", "cell"))
    assert (back.departure, back.floor, back.base_cells, back.centre) == (found.departure, found.floor, 48,
                                                                        found.centre)  # fmt: skip
    assert found.centre > 0  # the ASP's centre is a certified pinch
    assert back.pair.departure == found.departure and back.pair.particle == ASP90
    assert main(["info", str(path)]) == 0
    assert "2 components" in capsys.readouterr().out


def test_map_arguments_are_checked():
    with pytest.raises(ValueError, match="base"):
        excluded_map(ASP90, base=4)
    with pytest.raises(ValueError, match="floor"):
        excluded_map(ASP90, floor=0.0)
    assert main(["topology", "--opening", "400", "--json"]) == 2
    for wrong in (["--opening", "90", "--plot", "map.xyz"], ["--opening", "90", "--plot", "/no/such/map.png"],
                  ["--plot", "counts.png"]):  # fmt: skip
        with pytest.raises(ValueError, match="--plot"):
            main(["topology", "--debug", *wrong])


@pytest.mark.slow
def test_component_map_draws_each_component_in_its_colour():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sesp.plot import component_map

    found = excluded_map(ASP90, base=48)
    fig, ax = plt.subplots(figsize=(4, 4), dpi=80)
    component_map(found, ax=ax, particle=ASP90)
    ax.get_legend().remove()
    fig.canvas.draw()
    image = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int)
    plt.close(fig)
    for color in ((31, 119, 180), (255, 127, 14)):  # tab:blue (the body), tab:orange (the lens)
        assert (np.abs(image - color).sum(axis=-1) < 30).sum() > 200


@pytest.mark.slow
def test_component_map_legend_says_what_a_component_may_be_an_artefact_of():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sesp.plot import component_map

    polygon = excluded_map(SeSP(n=2, opening=math.radians(170)), segments=12, base=48, floor=1e-4)
    labels = [t.get_text() for t in component_map(polygon).get_legend().get_texts()]
    assert len(labels) == polygon.count
    for label, comp in zip(labels, polygon.components):
        assert label.endswith(f"unresolved: {polygon.limit(comp)}")
    arc = [t.get_text() for t in component_map(excluded_map(ASP90, base=48)).get_legend().get_texts()]
    assert len(arc) == 2 and not any("unresolved" in label for label in arc)
    plt.close("all")


@pytest.mark.slow
def test_a_crescent_whose_ridge_dips_is_one_component():
    """n = 4 at Ψ = 176°: two mirror-image crescents beside the axis, whose ridges dip and rise along them
    (saddles of the distance to the allowed set nearly as high as its peaks). Each is one component, not a
    row of slices, with the area of a brute-force exact-in-φ raster within 3 %."""
    particle = SeSP(n=4, opening=math.radians(176))
    found = excluded_map(particle, floor=1e-3)
    crescents = [c for c in found.components if c.bbox[1] < -0.4]
    assert len(crescents) == 2
    upper, lower = sorted(crescents, key=lambda c: -c.bbox[2])
    assert upper.bbox[2] > 0 > lower.bbox[3]
    assert upper.area == pytest.approx(lower.area, rel=1e-9)  # mirror images
    x, y = np.linspace(-0.64, -0.47, 86), np.linspace(0.0, 0.14, 71)
    width, _ = widest_window(particle, *np.meshgrid(x, y))
    raster = np.count_nonzero(width == 0) * (x[1] - x[0]) * (y[1] - y[0])
    assert upper.area == pytest.approx(raster, rel=0.03)


def _blob(x0, y0, cell, n, radius, floor=True):
    """A synthetic map component: n nodes in a row from (x0, y0), spaced one ``cell``."""
    x = x0 + cell * np.arange(n)
    y = np.full(n, float(y0))
    return MapComponent(n * cell * cell, radius, (x[0], x[-1], y0, y0), floor, x, y, np.full(n, cell))


def test_specks_of_the_floor_join_one_another_and_the_nearest_body_never_two():
    """Specks (seen only at the floor, under RESOLVED_PEAK cells deep) within SPECK_GAP floor cells of one
    another are one part, which joins the nearest thicker component within that distance, and only that one;
    a speck farther than that from everything stays a component; nothing joins across the centre's pinch."""
    floor, cell = 1e-4, 1.5e-4  # a floor cell: between the floor and zoom times it
    body_a = _blob(-1.0, 0.0, cell, 40, 10 * cell, floor=False)  # x from -1 to -1 + 39 cells
    body_b = _blob(-1.0 + 43 * cell, 0.0, cell, 40, 10 * cell, floor=False)  # 4 cells right of body_a
    bridge = _blob(-1.0 + 40.8 * cell, 0.0, cell, 1, 0.5 * cell)  # 1.8 cells from body_a, 2.2 from body_b
    near_a = _blob(-1.0 + 10 * cell, 2 * cell, cell, 2, 0.5 * cell)  # 2 cells above body_a
    chain = _blob(-1.0 + 10 * cell, 9 * cell, cell, 1, 0.5 * cell)  # 9 cells above body_a, 7 above near_a
    alone = _blob(0.5, 0.5, cell, 3, 0.5 * cell)
    assert SPECK_GAP < 9
    found = joined_specks([body_a, body_b, bridge, near_a, chain, alone], floor)
    assert sorted(len(c.x) for c in found) == [3, 40, 44]  # body_a with bridge, near_a, chain; body_b; alone
    joined = next(c for c in found if len(c.x) == 44)
    assert joined.touches_floor and np.isclose(joined.bbox[0], -1.0) and joined.bbox[1] < body_b.bbox[0]
    assert not next(c for c in found if len(c.x) == 40).touches_floor
    # across the centre's certified column a speck one cell away stays apart
    left, right = _blob(-21 * cell, 0.0, cell, 20, 5 * cell, floor=False), _blob(cell, 0.0, cell, 1, 0.5 * cell)
    assert len(joined_specks([left, right], floor, centre=0.01)) == 2
    assert len(joined_specks([left, right], floor, centre=0.0)) == 1


@pytest.mark.slow
@pytest.mark.full  # the speck rule's fast check: test_specks_of_the_floor_join_one_another_and_the_nearest_body...
@pytest.mark.parametrize("base", [97, 128])
def test_the_n4_body_s_horn_tips_are_no_specks_of_their_own(base):
    """At Ψ = 0.3125° the n = 4 body's horns end near (1.98, ±0.58) b in strips about 4e-4 b wide, which the
    floor's cells (1.6e-4 and 2.1e-4 b) sample in pieces; a brute-force raster on cells of 5e-5 b finds the
    strip in one piece. The map counts lens and body only, on either base grid (before: 8 on 128 cells)."""
    found = excluded_map(SeSP(n=4, opening=math.radians(0.3125)), base=base, floor=1e-4)
    assert found.count == 2
    x, y = np.meshgrid(1.9796 + np.linspace(-0.002, 0.002, 41), 0.5842 + np.linspace(-0.002, 0.002, 41))
    width, _ = widest_window(SeSP(n=4, opening=math.radians(0.3125)), x, y)
    assert ndimage.label(width == 0, np.ones((3, 3)))[1] == 1


@pytest.mark.slow
def test_a_thick_body_whose_tip_reaches_the_floor_is_not_unresolved_for_it():
    """n = 4 at Ψ = 120° on 64 cells: the body (1.53 b², inscribed radius 0.5 b) tapers to horn tips that the
    map follows to the floor, so it touches the floor; its count does not hang on the floor, so it is not
    ``floor_limited`` and the map's two components are resolved."""
    found = excluded_map(SeSP(n=4, opening=math.radians(120)), base=64, floor=1e-4)
    assert found.count == 2
    body = found.components[0]
    assert body.touches_floor and not body.floor_limited
    assert [found.limit(c) for c in found.components] == ["", ""]


def test_a_damaged_saved_map_and_a_bad_range_are_clear_errors(tmp_path):
    """A map file that cannot be read names itself and the remedy; a search range the wrong way round is
    refused before any map is made."""
    pair = as_pair(SeSP(n=2, opening=ASP170))
    (tmp_path / f"map_{ASP170!r}.nc").write_bytes(b"not a netCDF file")
    with pytest.raises(SespFileError, match="remove it to make that map again"):
        stored_map(tmp_path, ASP170, pair, base=48, floor=1e-4)
    with pytest.raises(ValueError, match="opening_range must satisfy"):
        map_transitions(ASP90, (2.0, 1.0))


def test_a_map_component_says_what_it_may_be_an_artefact_of():
    """The limits in the order the map reports them, and the JSON form of a component."""
    piece = MapComponent(area=1.0, inscribed_radius=1e-3, bbox=(0.0, 1.0, 0.0, 1.0), touches_floor=False,
                         x=np.zeros(1), y=np.zeros(1), cell=np.ones(1))  # fmt: skip
    found = ExcludedMap(components=[piece], floor=1e-4, base_cells=48, reach=2.0, positions=1, finest=1e-4,
                        departure=1e-2)  # fmt: skip
    assert found.limit(piece) == "polylines" and found.channels == 0
    assert found.limit(dataclasses.replace(piece, encloses_slivers=True)) == "slivers"
    assert piece.as_dict()["area"] == 1.0
