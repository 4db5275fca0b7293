"""Certified excluded components: the ASP's exact set, rotation invariance, the depth certificate's soundness."""

import functools
import json
import logging
import math
import time
from dataclasses import fields, replace

import matplotlib.pyplot as plt
import numpy as np
import pytest

from sesp import Polyline, SeSP
from sesp.certified import Settings, certified_components
from sesp.cli import main
from sesp.kernels import depth as depth_kernels
from sesp.kernels import runs as run_kernels
from sesp.orientations import allowed_orientations, widest_window
from sesp.pair import as_pair
from sesp.topology import transitions

import naive
from cases import FULL

COARSE = dict(resolution=1e-3)  # b: a resolution that keeps these tests to seconds
NO_TIPS = depth_kernels.OPTIONS._replace(tips=False)  # depth walks without two end points


def assert_excluded_around(part, x, y, r, segments=256):
    """Positions (x, y) and 16 points 0.999 r from each (b) are excluded exactly in φ: what a certificate of depth
    r at them claims."""
    turns = np.linspace(0, 2 * math.pi, 16, endpoint=False)
    xs = np.concatenate([x, *(x + 0.999 * r * math.cos(t) for t in turns)])
    ys = np.concatenate([y, *(y + 0.999 * r * math.sin(t) for t in turns)])
    width, _ = widest_window(part, xs, ys, segments=segments)
    assert np.all(width == 0)


def _asp(degrees):
    return SeSP(n=2, opening=math.radians(degrees))


def test_asp_at_90_degrees_is_lens_and_body_with_the_exact_lens():
    """Two components (the centre is a pinch); the lens's inscribed radius is 1 − sin(Ψ/2) and its area
    (π − Ψ) − sin Ψ: the certified depth is a lower bound close to it, the areas bracket it."""
    psi = math.radians(90)
    found = certified_components(_asp(90), **COARSE)
    assert (found.low, found.high) == (2, 2)
    lens = min(found.components, key=lambda c: c.area)
    exact_depth = 1 - math.sin(psi / 2)
    assert exact_depth - 1e-3 <= lens.depth <= exact_depth + 1e-4  # the polyline's departure: under 1e-4 b
    exact_area = (math.pi - psi) - math.sin(psi)
    assert lens.area <= exact_area <= lens.area_bound + 0.01
    assert lens.box[0] > 0  # right of the centre


@pytest.mark.parametrize("n", [2, 4])
def test_a_closed_curve_excludes_one_piece(n):
    """At Ψ = 0 the curves have no ends: the certificate lets sub-arcs pass the polyline's first vertex, and the
    one disk-like excluded set is decided (before, a ring about the seam stayed undecided)."""
    found = certified_components(SeSP(n=n, opening=0.0), resolution=1e-2, segments=64)
    assert (found.low, found.high) == (1, 1)


def test_a_lens_barely_deeper_than_its_rim_beside_the_body_is_its_own_component():
    """The ASP at 150° with ε = 1e-2 b: the lens is 1 − sin 75° = 0.034 b deep, more than ε + rim (0.02 b); lens
    and body meet at the centre only, so they are two components, and every certified part is refined apart
    from others."""
    found = certified_components(_asp(150), resolution=1e-2, segments=128)
    assert (found.low, found.high) == (2, 2)


def test_no_excluded_component_past_pi():
    found = certified_components(_asp(200), **COARSE)
    assert (found.low, found.high) == (0, 0) and found.components == []


def test_resolution_rim_and_base_are_checked():
    with pytest.raises(ValueError, match="resolution"):
        certified_components(_asp(90), resolution=-1.0)
    with pytest.raises(ValueError, match="rim"):
        certified_components(_asp(90), resolution=1e-3, rim=1e-4)
    with pytest.raises(ValueError, match="base"):
        certified_components(_asp(90), base=2)
    with pytest.raises(ValueError, match="rim"):  # over Ψ too
        transitions(SeSP(n=2), resolution=1e-3, rim=1e-4, workers=1)


@pytest.mark.parametrize(
    "particle, kwargs, said",
    [
        (SeSP(n=2, aspect=1e5), {}, r"rim must be at least 0.2 b for this pair \(reach 2e\+05 b\)"),
        (_asp(60), {"resolution": 1e-9, "rim": 1e-9}, r"rim must be at least 2e-06 b .* 2.0e\+09 of them"),
    ],
    ids=["a long particle", "a rim of 1e-9 b"],
)
def test_a_count_of_hours_is_refused_up_front_with_its_estimate(particle, kwargs, said):
    """The count's cells along the edges are about the rim wide: a pair whose reach over the rim is beyond
    checks.MAX_REACH_PER_RIM is refused before any work, saying what rim would do and how many cells it asked."""
    start = time.perf_counter()
    with pytest.raises(ValueError, match=said):
        certified_components(particle, **kwargs)
    assert time.perf_counter() - start < 5.0


def test_a_particle_no_grid_can_hold_is_refused_at_construction():
    with pytest.raises(ValueError, match=r"aspect must be in \[1e-05, 100000\]"):
        SeSP(aspect=1e6)
    with pytest.raises(ValueError, match=r"thickness must be in \[0, 100000\] b"):
        SeSP(thickness=1e6)
    with pytest.raises(ValueError, match="vertices must lie within 100000 b"):
        Polyline([[0, 0], [2e5, 0]])


@pytest.mark.slow
def test_counts_unchanged_when_both_frames_turn_together():
    """Turning the particle's own frame by α turns the whole excluded set by α: the count is the same, and the
    components now lie on no axis."""
    curve = _asp(60).polyline(64).vertices
    a = 0.37
    turned = curve @ np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])
    plain = certified_components(Polyline(curve), resolution=3e-3)
    rotated = certified_components(Polyline(turned), resolution=3e-3)
    assert (plain.low, plain.high) == (rotated.low, rotated.high) == (2, 2)
    plain, rotated = (sorted(f.components, key=lambda c: c.area) for f in (plain, rotated))
    assert [c.area for c in plain] == pytest.approx([c.area for c in rotated], rel=0.1)
    assert [c.depth for c in plain] == pytest.approx([c.depth for c in rotated], abs=2e-3)


@pytest.mark.slow
def test_a_mirror_symmetric_pair_is_decided_above_the_axis_and_counts_as_its_polylines_do():
    """A SeSP pair is symmetric about the x axis ((t, φ) overlaps where (Mt, −φ) does): each leaf below the axis
    is decided as its mirror image, so the cells are mirror images of each other, status and all; the same
    polylines given as Polylines (no symmetry assumed) are counted alike. Odd base: a row of cells on the axis."""
    for base in (16, 15):
        pair = as_pair(_asp(60), segments=64)
        mirrored = certified_components(pair, resolution=3e-3, base=base)
        plain = certified_components(
            Polyline(pair.vertices1), Polyline(pair.vertices2), resolution=3e-3, base=base, segments=64
        )
        assert (mirrored.low, mirrored.high) == (plain.low, plain.high) == (2, 2)
        cells = mirrored.cells
        above = {(x, y, s, k) for x, y, s, k in zip(cells["x"], cells["y"], cells["side"], cells["status"])}
        below = {(x, -y, s, k) for x, y, s, k in zip(cells["x"], cells["y"], cells["side"], cells["status"])}
        assert above == below


def test_depth_certificate_is_a_lower_bound_on_the_asps_lens_depth():
    """Along the axis through the lens the best certified depth never exceeds the exact inscribed radius
    1 − sin(Ψ/2) (beyond the polyline's departure from the circle, under 1e-4 b at 256 segments) and comes
    within 1 % of it."""
    psi = math.radians(90)
    pair = as_pair(_asp(90), segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    exact = 1 - math.sin(psi / 2)
    best = 0.0
    for x in np.linspace(0.05, 1.95, 39):
        lo, hi = 1e-6, 1.0
        for _ in range(20):
            mid = math.sqrt(lo * hi)
            ok = depth_kernels.certified_deep(curves, np.array([x]), np.array([0.0]), np.array([mid]), np.array([1024]))
            lo, hi = (mid, hi) if ok[0] == 1 else (lo, mid)
        best = max(best, lo)
    assert exact * 0.99 <= best <= exact + 1e-4


def test_depth_certificate_falls_back_to_a_smaller_depth_where_the_first_fails():
    """One walk around φ: where it fails at r it goes on at the fallback (what is certified at r is at any
    smaller depth), so a position of the ASP's lens (inscribed radius 1 − sin 45° = 0.293 b) is 2 (at least
    the fallback deep, not r) at r = 0.5 b, 1 at r = 0.2 b; an allowed position (the particles apart) is 0."""
    pair = as_pair(_asp(90), segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    lens, apart = (np.array([0.8, 5.0]), np.array([0.0, 0.0]))
    got = depth_kernels.certified_deep(curves, lens, apart, np.array([0.5, 0.5]), 1024, fallback=1e-3)
    assert got.tolist() == [2, 0]
    got = depth_kernels.certified_deep(curves, lens, apart, np.array([0.2, 0.2]), 1024, fallback=1e-3)
    assert got.tolist() == [1, 0]
    assert depth_kernels.certified_deep(curves, lens[:1], apart[:1], np.array([0.5]), 1024).tolist() == [0]


def test_a_long_walk_at_the_fallback_gives_up_and_the_exact_windows_say_the_same():
    """The ASP at 4.8° (the arcs almost a closed circle): at (-1.813, -0.828) b the walk fails at 0.022 b and
    needs more than FALLBACK_STEPS intervals at 1e-9 b, so it gives up (0), though a walk begun at 1e-9 b
    proves the position excluded (1); the exact windows, which then decide it, find no allowed orientation."""
    pair = as_pair(_asp(4.8), segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    x, y = np.array([-1.8125]), np.array([-0.828125])
    assert depth_kernels.certified_deep(curves, x, y, np.array([0.022107]), 1024, fallback=1e-9).tolist() == [0]
    assert depth_kernels.certified_deep(curves, x, y, np.array([1e-9]), 4096, options=NO_TIPS).tolist() == [1]
    assert allowed_orientations(pair, x, y).tolist() == [0.0]


def _plain_widest_odd_runs(v1, w, cross):
    """The widest-margin odd run pair by the definition, without tables or pruning: the whole open curves, and
    runs of 1, 2, 4, ... segments about each crossing, parities counted and margins measured to every segment."""

    def to_run(points, v, lo, hi):
        a, b = v[lo:hi], v[lo + 1 : hi + 1]
        d = b - a
        t = np.clip(((points[:, None, :] - a) * d).sum(-1) / (d * d).sum(-1), 0.0, 1.0)
        return np.sqrt((((a + t[..., None] * d) - points[:, None, :]) ** 2).sum(-1).min())

    def margin(i0, i1, j0, j1):
        return min(to_run(v1[[i0, i1]], w, j0, j1), to_run(w[[j0, j1]], v1, i0, i1))

    n1, n2 = len(v1) - 1, len(w) - 1
    best = margin(0, n1, 0, n2) if len(cross) % 2 else -1.0
    for i, j in cross:
        half = 1
        while True:
            i0, i1, j0, j1 = max(0, i - half + 1), min(n1, i + half), max(0, j - half + 1), min(n2, j + half)
            if (i0, i1, j0, j1) == (0, n1, 0, n2):
                break
            inside = ((cross[:, 0] >= i0) & (cross[:, 0] < i1) & (cross[:, 1] >= j0) & (cross[:, 1] < j1)).sum()
            if inside % 2:
                best = max(best, margin(i0, i1, j0, j1))
            half *= 2
    return best


@pytest.mark.parametrize("offset", [3e-5, 0.3])
def test_the_widest_odd_runs_are_those_a_plain_search_finds_with_many_crossings_or_few(offset):
    """Two nearly coincident arcs cross hundreds of times (their parities then come from a table, and runs that
    cannot beat the best margin are skipped); two arcs 0.3 b apart cross a few times. Both give the margin of
    a plain search by the definition."""
    pair = as_pair(_asp(5), segments=256)
    v1, w = pair.vertices1, np.ascontiguousarray(naive.transform(pair.vertices2, offset, 0.0, 0.3))
    curves, _ = depth_kernels.prepared(v1, w)
    boxes2 = curves.frame_boxes2  # w, as it is: its own boxes
    cross = np.empty((depth_kernels.OPTIONS.max_crossings, 2), np.int64)
    count = run_kernels.crossings(curves.v1, curves.boxes1, curves.v2, boxes2, cross, 0, 0)
    assert (count > 100) == (offset < 1e-3)
    table = run_kernels.parities(cross, count, len(v1) - 1, len(w) - 1)
    assert (table.shape[0] > 1) == (offset < 1e-3)
    moved = run_kernels.Moved(curves.v2, boxes2, cross)
    *_, margin = run_kernels.widest_odd_runs(curves, moved, count, table)
    assert margin == pytest.approx(_plain_widest_odd_runs(v1, w, cross[:count]), rel=1e-12)


@pytest.mark.parametrize("opening", [0, 30])
def test_crossings_of_curves_stored_twice_over_are_every_segment_pair_that_meets(opening):
    """Closed curves are stored twice over and their crossings found on the first copy only, then written for
    both: the same pairs as every segment pair of the stored polylines that meets (an open curve: as it is)."""
    pair = as_pair(SeSP(n=3, opening=math.radians(opening)), segments=64)
    (v1, boxes1, v2, _, _, _, p1, p2), _ = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    assert (p1 > 0) == (opening == 0)
    for x, y, phi in [(0.4, 0.3, 0.5), (1.1, -0.2, 2.0), (0.05, 0.02, 3.0)]:
        w = np.ascontiguousarray(naive.transform(v2, x, y, phi))
        boxes2 = depth_kernels.chunk_boxes(w, np.empty((depth_kernels.chunk_count(w), 4)))
        cross = np.empty((depth_kernels.OPTIONS.max_crossings, 2), np.int64)
        count = run_kernels.crossings(v1, boxes1, w, boxes2, cross, p1, p2)
        expected = np.argwhere(naive.segment_pairs_meet(v1, w))
        assert count == len(expected) > 0
        assert sorted(map(tuple, cross[:count].tolist())) == sorted(map(tuple, expected.tolist()))


def test_crossing_parities_from_the_table_equal_those_counted():
    rng = np.random.default_rng(7)
    cross = rng.integers(0, 40, size=(300, 2))
    table = run_kernels.parity_table(cross, len(cross), 40, 40)
    for i0, i1, j0, j1 in rng.integers(0, 41, size=(200, 4)):
        runs = (int(min(i0, i1)), int(max(i0, i1)), int(min(j0, j1)), int(max(j0, j1)))
        counted = run_kernels.inside_parity(cross, len(cross), np.zeros((1, 1), np.uint8), runs)
        assert counted == naive.crossing_parity(cross, runs)
        assert run_kernels.inside_parity(cross, len(cross), table, runs) == counted


def test_the_walk_around_phi_proves_the_same_wherever_it_begins():
    """The ASP's lens at 90° (inscribed radius 0.293 b) is certified 0.2 b deep, and not 0.5 b, from any start."""
    pair = as_pair(_asp(90), segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    starts = np.linspace(0.0, 2 * math.pi, 7, endpoint=False)
    x, y = np.full(7, 0.8), np.zeros(7)
    assert depth_kernels.certified_deep(curves, x, y, 0.2, 1024, start=starts).tolist() == [1] * 7
    assert depth_kernels.certified_deep(curves, x, y, 0.5, 1024, start=starts).tolist() == [0] * 7


@pytest.mark.slow
def test_cli_one_opening_prints_json_with_parameters_and_units_and_draws_the_components(tmp_path, capsys):
    png = tmp_path / "components.png"
    command = ["topology", "--n", "2", "--opening", "90", "--resolution", "1e-3", "--base", "32", "--quiet"]
    assert main([*command, "--json", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["n"], out["opening_deg"], out["segments"]) == (2.0, 90.0, 256)
    assert (out["count"], out["count_low"], out["count_high"], out["resolution"]) == (2, 2, 2, 1e-3)
    assert out["units"] == {"lengths": "b", "areas": "b^2"}
    assert [c["status"] for c in out["components"]] == ["one component"] * 2
    assert png.stat().st_size > 20_000
    assert main(command) == 0
    assert "2 excluded components" not in capsys.readouterr().out  # the text report says it its own way


def test_the_map_shows_every_component_at_equal_scale_on_its_whole_panel(caplog):
    """Every panel keeps x and y at one scale by widening its limits, not by shrinking the panel (which left a
    gap beside it), and so without a matplotlib warning about fixed limits; the overview holds the components
    and the particle, each zoom panel its component; the legend names the particle and the pale cells."""
    from sesp.plot import certified_map
    from sesp.shape import as_polyline

    found = certified_components(_asp(90), base=32, **COARSE)
    fig = certified_map(found, particle=_asp(90))
    with caplog.at_level(logging.WARNING):
        fig.canvas.draw()
    assert not caplog.records
    v = as_polyline(_asp(90), 256).vertices
    boxes = [c.box for c in found.components]
    held = [[*boxes, (v[:, 0].min(), v[:, 0].max(), v[:, 1].min(), v[:, 1].max())], *([b] for b in boxes)]
    for ax, inside in zip(fig.axes, held, strict=True):
        assert ax.get_position(original=False).bounds == pytest.approx(ax.get_position(original=True).bounds)
        (x0, x1), (y0, y1), extent = ax.get_xlim(), ax.get_ylim(), ax.get_window_extent()
        assert (x1 - x0) / extent.width == pytest.approx((y1 - y0) / extent.height, rel=1e-6)
        for box in inside:
            assert x0 <= box[0] and box[1] <= x1 and y0 <= box[2] and box[3] <= y1
    boxes = np.array(held[0])
    x_lo, x_hi, y_lo, y_hi = boxes[:, 0].min(), boxes[:, 1].max(), boxes[:, 2].min(), boxes[:, 3].max()
    pad = 0.15 * max(x_hi - x_lo, y_hi - y_lo)  # the view: the whole box grown by 15 % of its larger side
    (x0, x1), (y0, y1) = fig.axes[0].get_xlim(), fig.axes[0].get_ylim()
    # one pair of limits is the padded box, the other is widened to the panel: not zoomed out
    assert (x0, x1) == pytest.approx((x_lo - pad, x_hi + pad)) or (y0, y1) == pytest.approx((y_lo - pad, y_hi + pad))
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "the fixed particle" in labels
    assert any(t.startswith("pale: undecided") for t in labels) == bool(np.any(found.cells["status"] == 2))
    plt.close(fig)


def test_a_map_without_components_says_how_deep_one_was_looked_for():
    from sesp.plot import certified_map

    found = certified_components(_asp(200), **COARSE)
    fig = certified_map(found, particle=_asp(200))
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == [
        "no component at least 2.00e-03 b deep (resolution + rim)",
        "the fixed particle",
    ]
    assert len(fig.axes) == 1


@pytest.mark.parametrize(
    "particle, other",
    [(_asp(120), None), (SeSP(n=4, opening=math.radians(100)), Polyline([[-0.6, -0.3], [0.1, 0.2], [0.5, -0.4]]))],
    ids=["asp", "mixture"],
)
def test_certified_cells_are_excluded_within_the_resolution_by_brute_force(particle, other):
    """Every point of a cell certified in E_ε lies at least ε inside the excluded set: its corners, its centre
    and the points ε from each of them are excluded exactly in φ (the widest allowed window is 0). The mixture
    (a SeSP against a bent polyline) has components on no axis."""
    eps = 1e-2
    found = certified_components(particle, other, resolution=eps, segments=64)
    cells = found.cells
    inn = np.flatnonzero(cells["status"] == 1)
    assert len(inn) > 50
    pick = inn[np.random.default_rng(1).choice(len(inn), size=min(300, len(inn)), replace=False)]
    half = cells["side"][pick] / 2
    offsets = [(dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)]
    turns = np.linspace(0, 2 * math.pi, 8, endpoint=False)
    xs, ys = [], []
    for dx, dy in offsets:
        for r, t in [(0.0, 0.0), *((eps * 0.999, t) for t in turns)]:
            xs.append(cells["x"][pick] + dx * half + r * math.cos(t))
            ys.append(cells["y"][pick] + dy * half + r * math.sin(t))
    width, _ = widest_window(particle, np.array(xs), np.array(ys), other=other, segments=64)
    assert np.all(width == 0)


def test_depth_certificate_ends_runs_mid_segment_where_a_corner_crosses_a_flat_side():
    """Beside the closed n = 8 curve's excluded set, at φ ≈ 28°, a rounded corner of curve 1 crosses a flat side
    of curve 2 in a lens about one segment long: every vertex of curve 2 near it lies within 3e-5 b of a crossing.
    Runs that may end at a segment's middle prove at least half the depth there (an allowed position lies
    8.3e-4 b away); runs ending at vertices proved only 3e-5 b, and the count of this shape did not finish at
    the default resolution."""
    pair = as_pair(SeSP(n=8, opening=0.0), segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    x, y = -1.3240539, 1.8415378
    turn = math.radians(117)
    near = allowed_orientations(pair, x + 8.3e-4 * math.cos(turn), y + 8.3e-4 * math.sin(turn))
    assert near > 0  # the depth is at most 8.3e-4 b
    got = depth_kernels.certified_deep(curves, np.array([x]), np.array([y]), np.array([4.15e-4]), 4096)
    assert got.tolist() == [1]


def test_two_tips_through_opposite_sides_prove_a_depth_no_one_pair_of_runs_shows():
    """n = 10, Ψ = 170°, at (−1.233752, +0.009654) b: at φ ≈ −0.0154 rad both ends of curve 2 poke through the
    flat top and bottom of curve 1. A short translation frees either end alone, in opposite directions, so one
    pair of runs proves only 8.3e-6 b; the two ends' half-planes prove 3.6e-4 b. Exact windows find no allowed
    position 3.6e-4 b away (720 directions) and one 3.7e-4 b away."""
    part = SeSP(n=10, opening=math.radians(170))
    pair = as_pair(part, segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    x, y = np.array([-1.233752]), np.array([0.009654])
    assert depth_kernels.certified_deep(curves, x, y, 3.5e-4, 1 << 16).tolist() == [1]
    assert depth_kernels.certified_deep(curves, x, y, 1e-5, 1 << 16, options=NO_TIPS).tolist() == [0]
    turn = math.radians(218)
    assert allowed_orientations(pair, x[0] + 3.7e-4 * math.cos(turn), y[0] + 3.7e-4 * math.sin(turn)) > 0


def test_two_tips_sliding_along_flat_sides_are_certified_in_long_turns_and_excluded_by_brute_force():
    """n = 8, Ψ = 179.7°, at (−0.3251, −2e-5) b, on the thin axis strip: near φ = 0 both ends of curve 2 lie on
    the flat top and bottom of curve 1, 1.1e-5 and 1.3e-5 b through them, and slide along them as φ turns. Their
    motion across the sides is a fifth of their speed, so the half-planes hold over turns long enough that the
    walk at 3.83e-5 b closes within 128 intervals (bounded by the curve's radius instead it took over 500).
    Exact windows find no allowed position 0.999 of that depth away (64 directions)."""
    part, r = SeSP(n=8, opening=math.radians(179.7)), 3.83e-5
    pair = as_pair(part, segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    x, y = np.array([-0.32510]), np.array([-0.000020])
    assert depth_kernels.certified_deep(curves, x, y, r, 128).tolist() == [1]
    assert depth_kernels.certified_deep(curves, x, y, r, 1 << 16, options=NO_TIPS).tolist() == [0]
    turns = np.linspace(0, 2 * math.pi, 64, endpoint=False)
    width, _ = widest_window(part, x + 0.999 * r * np.cos(turns), y + 0.999 * r * np.sin(turns), segments=256)
    assert np.all(width == 0)


@pytest.mark.parametrize(("n", "degrees"), [(10, 170), (8, 175)])
def test_depths_proved_by_two_tips_are_excluded_by_brute_force(n, degrees):
    """Where two end points prove a position 1e-4 b deep and one pair of runs does not (positions along the
    body's left edges, where both ends of curve 2 poke through opposite sides of curve 1), the position and 16
    points 0.999e-4 b from it are excluded exactly in φ."""
    part, r = SeSP(n=n, opening=math.radians(degrees)), 1e-4
    pair = as_pair(part, segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    rng = np.random.default_rng(0)
    x, y = rng.uniform(-1.35, -0.95, 4000), rng.uniform(-0.3, 0.3, 4000)
    both = depth_kernels.certified_deep(curves, x, y, r, 4096)
    one = depth_kernels.certified_deep(curves, x, y, r, 4096, options=NO_TIPS)
    assert np.all(both[one == 1] == 1)
    only = np.flatnonzero((both == 1) & (one != 1))
    assert len(only) >= 3
    assert_excluded_around(part, x[only], y[only], r, segments=256)


def test_the_asps_body_near_pi_is_proved_deep_by_two_end_points():
    """Near π the ASP's body lies along −x, where the two arcs nearly coincide and cross near both ends of curve
    1; at Ψ = 177° and t = (−0.04, 0) an end of curve 2 pokes through curve 1 near each of them at φ = 0, and no
    one pair of runs holds 3e-4 b. Two end points prove 1.7e-3 b; 32 points 0.999 of that from t are excluded
    exactly in φ, and t + 1.9e-3 b (cos 87°, sin 87°) is allowed: the depth is under 1.9e-3 b. A walk at
    1.9e-3 b fails, and one begun at the orientation where it failed fails at its first interval."""
    part = SeSP(n=2, opening=math.radians(177))
    pair = as_pair(part, segments=256)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    x, y = np.array([-0.04]), np.array([0.0])
    assert depth_kernels.certified_deep(curves, x, y, 3e-4, 4096, options=NO_TIPS).tolist() == [0]
    assert depth_kernels.certified_deep(curves, x, y, 1.7e-3, 4096).tolist() == [1]
    turns = np.linspace(0, 2 * math.pi, 32, endpoint=False)
    r = 0.999 * 1.7e-3
    width, _ = widest_window(part, np.r_[x, x + r * np.cos(turns)], np.r_[y, y + r * np.sin(turns)], segments=256)
    assert np.all(width == 0)
    up = math.radians(87)
    width, _ = widest_window(part, x + 1.9e-3 * math.cos(up), y + 1.9e-3 * math.sin(up), segments=256)
    assert width[0] > 0
    # deeper than that the walk fails, and says where: begun there, it fails at its first interval
    stops = np.zeros(1)
    assert depth_kernels.certified_deep(curves, x, y, 1.9e-3, 4096, stops=stops).tolist() == [0]
    assert depth_kernels.certified_deep(curves, x, y, 1.9e-3, 1).tolist() == [-1]  # from φ = 0: out of steps
    assert depth_kernels.certified_deep(curves, x, y, 1.9e-3, 1, start=stops[0]).tolist() == [0]


def test_a_shallow_overlap_of_closed_curves_is_certified_in_a_few_intervals_and_excluded_by_brute_force():
    """Two unit circles (n = 2, Ψ = 0; 128-gons) overlapping about 3e-3 b deep cross twice across a lens about
    one segment long. A pair of runs short on both sides keeps its ends apart only while a vertex of each lies
    in the lens: one interval of φ per vertex passing it, over 100 around the circle. With curve 2's run
    lengthened to the whole curve the pair holds until the turning curve sweeps over an end of curve 1's run:
    8 intervals suffice at 24 positions. Each, and 16 points 0.999 r from each, is excluded exactly in φ."""
    part, r = SeSP(n=2, opening=0.0), 1e-3
    pair = as_pair(part, segments=128)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    angles = np.linspace(0.1, 0.1 + 2 * math.pi, 24, endpoint=False)
    x, y = (2 - 3 * r) * np.cos(angles), (2 - 3 * r) * np.sin(angles)
    assert depth_kernels.certified_deep(curves, x, y, r, 8).tolist() == [1] * 24
    assert_excluded_around(part, x, y, r, segments=128)


@pytest.mark.parametrize(("n", "degrees"), [(2, 10), (8, 5)])
def test_lens_and_body_part_at_a_pinch_whose_allowed_wedge_runs_between_cell_centres(n, degrees):
    """At small Ψ the lens and the body meet only at the centre: the allowed set there is a wedge along x = 0
    (angle about Ψ for the ASP), narrower than a floor cell near the centre, and x = 0 is a line of cell edges.
    The corners of the floor cells left between the two parts are tried as well as their centres: allowed
    corners bound the depth beside them below ε and part lens from body (exact for the ASP: 2 for 0 < Ψ < π).
    With centres alone both stayed 1-2."""
    found = certified_components(SeSP(n=n, opening=math.radians(degrees)), resolution=1e-3, segments=64)
    assert (found.low, found.high) == (2, 2)


@pytest.mark.parametrize(("n", "degrees"), [(8, 5), (4, 144), (10, 0.3)])
def test_positions_are_allowed_where_some_orientation_keeps_the_curves_apart(n, degrees):
    """Corners tried between parts are decided as centres are: allowed where the curves keep apart at a hint
    orientation, excluded where the depth certificate proves it, the exact windows deciding the rest. Whatever
    the hint (that of the nearest other allowed point, a random one, none), every position the windows allow is
    allowed, and every other one allowed has no crossing at its hint orientation, by brute force. At the apex
    of the pinch's allowed wedge (n = 10 at 0.3°, on x = 0) the curves keep apart by about 1e-11 b there,
    in windows narrower than ANGLE_GAP (1e-9 rad), which the windows close: only the hint finds them."""
    from scipy.spatial import cKDTree

    from sesp.certified import allowed_positions

    pair = as_pair(SeSP(n=n, opening=math.radians(degrees)), segments=256)
    rng = np.random.default_rng(n)
    x = np.concatenate([rng.uniform(-1, 1, 300) * pair.reach, rng.normal(0, 2e-3, 300), np.zeros(300)])
    y = np.concatenate([rng.uniform(-1, 1, 300) * pair.reach, rng.normal(0, 2e-3, 300), rng.normal(0, 3e-4, 300)])
    width, middle = widest_window(pair, x, y)
    exact = width > 0
    assert 0 < exact.sum() < len(x)  # both answers occur
    allowed = np.nonzero(exact)[0]
    _, k = cKDTree(np.column_stack([x[allowed], y[allowed]])).query(np.column_stack([x, y]), k=2)
    nearest = middle[allowed[k[:, 1]]]
    for hint in (nearest, rng.uniform(0, 2 * math.pi, len(x)), np.full(len(x), np.nan)):
        got, phi = allowed_positions(pair, x, y, hint=hint)
        assert got[exact].all()
        assert np.isnan(phi[~got]).all()
        extra = np.nonzero(got & ~exact)[0]
        for q in extra:
            assert phi[q] == hint[q]
        # the orientation returned keeps the curves apart: every extra position, and some the windows decided
        for q in np.concatenate([extra, rng.choice(np.nonzero(got)[0], 12, replace=False)]):
            moved = naive.transform(pair.vertices2, x[q], y[q], phi[q])
            assert not naive.segment_pairs_meet(pair.vertices1, moved).any()
        if hint is nearest and n == 10:
            assert len(extra) and np.all(x[extra] == 0.0)  # the apex of the wedge, on x = 0


@pytest.mark.parametrize("trial", range(40))
def test_corridors_between_seeds_are_those_of_one_search_per_seed(trial):
    """The corridor kernel (one search from all seeds, then searches only as far as each path is long) marks
    what a search from every seed over every leaf marks, on a grid of leaves with random seeds and walls; the
    seeds are blocks of 1 to 36 leaves, so a large seed reaches farther than the paths to it are long."""
    from sesp.kernels import cells as cell_kernels

    rng = np.random.default_rng(trial)
    side = 14
    index = np.arange(side * side).reshape(side, side)
    pairs = [(index[i, j], index[i + di, j + dj]) for i in range(side) for j in range(side)
             for di in (-1, 0, 1) for dj in (-1, 0, 1)
             if (di or dj) and 0 <= i + di < side and 0 <= j + dj < side]  # fmt: skip
    ea, eb = (np.array(v, dtype=np.int64) for v in zip(*pairs))
    passable = rng.random(side * side) < 0.7
    seed = np.full(side * side, -1, np.int64)
    for label in rng.choice(side * side, size=5, replace=False):
        r = rng.integers(1, 7)  # the block's side, in leaves
        around = index[
            max(0, label // side - r + 1) : label // side + 1, max(0, label % side - r + 1) : label % side + 1
        ]
        seed[around.ravel()] = label
        passable[around.ravel()] = True
    near = cell_kernels.adjacency(side * side, ea, eb)
    got = cell_kernels.corridors(seed, passable, near, 2)
    want = naive.corridors(seed, passable, pairs, 2)
    assert got.any() or not want.any()
    np.testing.assert_array_equal(got, want)


@pytest.mark.slow
def test_a_lens_shallower_than_resolution_plus_rim_is_not_counted(capsys):
    """The ASP at 172.5° and ε = 1e-3 b: the exact lens is 1 − sin(Ψ/2) = 2.14e-3 b deep. With rim = 2e-3 b it is
    shallower than ε + rim: the count is the body alone, and the report says from which depth a component
    counts. With rim = ε (``--rim`` on the command line) the
    lens is deeper than ε + rim and counted, as deep as the exact one within a floor cell."""
    asp = SeSP(n=2, opening=math.radians(172.5))
    lens = 1 - math.sin(math.radians(172.5) / 2)
    coarse = certified_components(asp, resolution=1e-3, rim=2e-3)
    assert coarse.count == 1 and lens < coarse.resolution + coarse.rim
    assert f"at least {coarse.resolution + coarse.rim:.2e} b deep (resolution + rim" in str(coarse)
    fine = certified_components(asp, resolution=1e-3, rim=1e-3)
    assert fine.count == 2 and lens - 1e-4 < fine.components[1].depth <= lens * (1 + 1e-9)
    # the same on the command line
    assert main(["-q", "topology", "--n", "2", "--opening", "172.5", "--resolution", "1e-3", "--rim", "1e-3",
                 "--json"]) == 0  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    assert (out["count"], out["rim"]) == (2, 1e-3)


def test_a_lens_deeper_than_resolution_plus_rim_beside_the_body_is_counted():
    """Every component deeper than ε + rim is found. The ASP at 165°, ε = 1e-3 b: the exact lens,
    1 − sin(82.5°) = 8.6e-3 b deep, is deeper than ε + rim and is counted."""
    found = certified_components(SeSP(n=2, opening=math.radians(165)), resolution=1e-3)
    lens = 1 - math.sin(math.radians(82.5))
    assert lens > found.resolution + found.rim
    assert found.count == 2 and found.components[1].depth <= lens * (1 + 1e-9)


def test_the_default_rim_is_a_thousandth_of_b_or_the_resolution_or_the_polylines_departure():
    """The default rim is 1e-3 b, or ε or the polylines' departure from the curves (b) where larger: a body
    thinner than the departure may be the polylines' own."""
    for particle, resolution, segments, want in ((_asp(200), 1e-5, 128, 1e-3), (_asp(200), 1e-1, 128, 1e-1),
                                                 (SeSP(n=10, opening=math.radians(200)), 1e-5, 64, None)):  # fmt: skip
        found = certified_components(particle, resolution=resolution, segments=segments)
        departure = as_pair(particle, segments=segments).departure
        assert found.rim == (departure if want is None else want) and departure < 1e-1
        assert (departure > 1e-3) == (want is None)


SETTINGS_CASES = {  # fast cases whose counts are decided at the default settings: two end points, no axis
    "asp 150": (_asp(150), None, dict(resolution=1e-2, segments=64)),
    "n4 176": (SeSP(n=4, opening=math.radians(176)), None, dict(resolution=3e-3, segments=64)),
    "n10 170": (SeSP(n=10, opening=math.radians(170)), None, dict(resolution=1e-2, segments=64)),
    "mixture": (SeSP(n=4, opening=math.radians(100)), Polyline([[-0.6, -0.3], [0.1, 0.2], [0.5, -0.4]]),
                dict(resolution=1e-2, segments=64)),
}  # fmt: skip


@functools.cache
def _default_count(case):
    particle, other, kw = SETTINGS_CASES[case]
    return certified_components(particle, other, **kw).count


def _scaled(name, factor):
    """The default Settings with ``name`` multiplied by ``factor`` (a whole number stays whole; ``turns``, each
    angle)."""
    default = getattr(Settings(), name)
    if name == "turns":
        return replace(Settings(), turns=tuple(t * factor for t in default))
    if isinstance(default, int):
        return replace(Settings(), **{name: max(1, round(default * factor))})
    return replace(Settings(), **{name: default * factor})


_VARIANTS = [(name, factor) for name in (f.name for f in fields(Settings)) for factor in (0.5, 2.0)]
# the fast suite runs each variant on one case, the cases in turn; SESP_FULL_TESTS=1 every variant on every case
_RUNS = [(case, *variant) for k, variant in enumerate(_VARIANTS) for c, case in enumerate(SETTINGS_CASES)
         if FULL or k % len(SETTINGS_CASES) == c]  # fmt: skip


@pytest.mark.parametrize(("case", "name", "factor"), _RUNS, ids=[f"{c}-{n}x{f:g}" for c, n, f in _RUNS])
def test_the_cost_settings_change_no_decided_count(case, name, factor):
    """Every cost setting, halved and doubled: the count is decided and the same as at the defaults."""
    particle, other, kw = SETTINGS_CASES[case]
    changed = certified_components(particle, other, settings=_scaled(name, factor), **kw)
    assert _default_count(case) is not None and changed.count == _default_count(case)


def test_settings_are_checked():
    with pytest.raises(ValueError, match="rays"):
        Settings(rays=0)
    with pytest.raises(ValueError, match="depth_tolerance"):
        Settings(depth_tolerance=2.0)
    with pytest.raises(ValueError, match="turns"):
        Settings(turns=())


def test_thick_particles_are_certified_deep_where_their_curves_stay_near_and_excluded_by_brute_force():
    """Thick particles overlap where their curves come within the contact distance D, crossed or not: a position
    whose curves stay within D − r of each other at every φ (their distance grows by at most ρ per radian) is r
    deep. Positions of the ASP at 90°, 0.05 b thick, certified 4e-3 b deep where the curves cross at some φ and
    not at others, and 16 points 0.999 of that from each, are excluded exactly in φ."""
    part, r = SeSP(n=2, opening=math.radians(90), thickness=0.05), 4e-3
    pair = as_pair(part, segments=128)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-2.1, 2.1, 3000), rng.uniform(-2.1, 2.1, 3000)
    thick = depth_kernels.certified_deep(curves, x, y, r, 4096, contact=pair.contact)
    crossing = depth_kernels.certified_deep(curves, x, y, r, 4096)  # the thin curves crossed at every φ
    near = np.flatnonzero((thick == 1) & (crossing != 1))
    assert len(near) >= 20  # the band of width about D about the thin excluded set
    assert_excluded_around(part, x[near], y[near], r, segments=128)


def test_thick_particles_certified_at_the_fallback_depth_are_that_deep_by_brute_force():
    """A walk that fails at its depth goes on at the fallback depth, where thick particles count as near enough
    too (within D less the fallback, by the Lipschitz bound or by one curve's nearest segment against the whole
    other curve). Positions of the ASP at 90°, 0.05 b thick, about the excluded set's edge, proved 2e-3 b deep
    at the fallback and not 0.5 b, some only where the curves come near without crossing: 50 of them (40 of
    those) and 16 points 0.999 of that from each are excluded exactly in φ."""
    part, fallback = SeSP(n=2, opening=math.radians(90), thickness=0.05), 2e-3
    pair = as_pair(part, segments=64)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    rng = np.random.default_rng(5)
    x, y = rng.uniform(-2.1, 2.1, 3000), rng.uniform(-2.1, 2.1, 3000)
    got = depth_kernels.certified_deep(curves, x, y, 0.5, 4096, fallback=fallback, contact=pair.contact)
    crossed = depth_kernels.certified_deep(curves, x, y, fallback, 4096)  # the thin curves crossed at every φ
    proved = np.flatnonzero(got == 2)
    near = proved[crossed[proved] != 1]  # proved only as near enough
    assert len(proved) >= 100 and len(near) >= 20
    some = np.concatenate([near[:40], proved[crossed[proved] == 1][:10]])
    assert_excluded_around(part, x[some], y[some], fallback, segments=64)


def test_a_staple_is_certified_deep_across_its_axis_and_excluded_by_brute_force():
    """Two staples (three unit segments) at φ = 0 with their arms along each other: on the axis each arm of the
    moving staple lies along the fixed staple's, and a translation up crosses its lower arm with the other's
    back, one down its upper arm. No pair of runs shows that (each tip lies on the other curve's line); the two
    tips' half-planes, with opposite normals, hold it jointly as φ turns through 0. Positions about the axis
    certified 0.01 b deep, and 16 points 0.999 of that from each, are excluded exactly in φ."""
    staple, r = Polyline([[0.5, -0.5], [-0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]]), 0.01
    pair = as_pair(staple)
    curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
    x = np.linspace(-0.9, -0.6, 31)
    y = np.full(31, 4e-3)
    got = depth_kernels.certified_deep(curves, x, y, r, 4096)
    assert np.all(got == 1)
    assert_excluded_around(staple, x, y, r, segments=256)
