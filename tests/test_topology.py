"""The search over Ψ on the certified count, and the plain components of a stored field."""

import math

import numpy as np
import pytest
import xarray as xr

from sesp import Grid, SeSP, scan, topology
from sesp.certified import Certified
from sesp.progress import NoProgress
from sesp.regions import summarize
from sesp.topology import changed, lattice_components, opening_family, transitions

COARSE = dict(resolution=1e-2, segments=128)  # b: the certified engine in about half a second per opening


def test_face_joined_components_are_sorted_and_measured_and_a_corner_does_not_join():
    mask = np.zeros((10, 10), dtype=bool)
    mask[1:4, 1:4] = True  # 9 nodes
    mask[4, 4] = True  # touches the first only at a corner: apart
    mask[6:9, 2:8] = True  # 18 nodes
    summary = xr.Dataset(  # excluded where no orientation is allowed; cells 0.1 b by 5 b
        {"allowed_fraction": (("y", "x"), np.where(mask, 0.0, 1.0))},
        coords={"x": 0.1 * np.arange(10), "y": 5.0 * np.arange(10)},
    )
    found = lattice_components(summary)
    assert found.spacing == pytest.approx(0.1)
    assert found.count == 3
    assert found.sizes.tolist() == [18, 9, 1]
    assert found.areas.tolist() == [9.0, 4.5, 0.5]
    assert found.labels[7, 3] == 1 and found.labels[2, 2] == 2 and found.labels[4, 4] == 3
    assert (found.labels > 0).sum() == mask.sum()


def test_periodic_axis_joins_components_across_the_seam():
    field = np.zeros((20, 12, 12), dtype=bool)
    field[:4, 3:9, 3:9] = True  # first 4 slices ...
    field[-4:, 3:9, 3:9] = True  # ... and last 4 slices are one blob through φ = 0
    field[8:13, 3:9, 3:9] = True  # a separate blob in the middle
    ds = xr.Dataset(
        {"allowed": (("phi", "y", "x"), field)},
        coords={"phi": 2 * np.pi * np.arange(20) / 20, "y": np.arange(12.0), "x": np.arange(12.0)},
    )
    found = lattice_components(ds, "allowed")
    assert found.count == 2 and found.sizes.tolist() == [8 * 36, 5 * 36]


def test_allowed_states_wrap_in_phi_and_the_field_name_is_checked():
    ds = scan(SeSP(n=2, opening=math.pi / 2), Grid(40, nphi=32), segments=32, entangled=True)
    allowed = lattice_components(ds, "allowed")
    assert allowed.count >= 1
    assert allowed.sizes.sum() == int(ds.allowed.sum())
    assert allowed.measure == pytest.approx(float(ds.x[1] - ds.x[0]) ** 2 * 2 * math.pi / 32)
    with pytest.raises(ValueError, match="which"):
        lattice_components(ds, "free")


def test_on_the_lattice_the_asp_pinch_joins_lens_and_body_which_is_why_the_count_is_certified():
    """The ASP's lens and body meet at the centre only; a field's excluded nodes there touch across faces, so
    the field's description is one component where the set has two."""
    s = summarize(SeSP(n=2, opening=math.radians(60)), Grid(64, nphi=256), segments=128, entangled=False)
    found = lattice_components(s)
    iy = int(np.argmin(np.abs(s.y.values)))
    lens = found.labels[iy, int(np.argmin(np.abs(s.x.values - 0.9)))]
    body = found.labels[iy, int(np.argmin(np.abs(s.x.values + 0.9)))]
    assert lens == body == 1 and found.spacing == pytest.approx(float(s.x[1] - s.x[0]))


@pytest.mark.slow
def test_the_asp_count_falls_from_two_to_none_before_pi_at_a_coarse_resolution(monkeypatch):
    """At ε = 1e-2 b (the rim, then, as the polylines depart from the curves by less) the lens (inscribed radius
    1 − sin(Ψ/2)) is counted while it is deeper than ε + rim = 2ε, so until Ψ = 2 asin(1 − 2ε) = 157.0°; the
    body, thinner still near π, ends by π; nothing is excluded past π. The bisections' progress bar ends at
    its total (it grows where a step holds two changes)."""
    bars = []

    class Bar(NoProgress):
        def __init__(self, total, enabled, desc, unit="it"):
            self.total, self.done = total, 0
            bars.append(self)

        def update(self, n=1):
            self.done += n

    monkeypatch.setattr(topology, "progress_bar", Bar)
    told = []
    found = transitions(
        SeSP(n=2), (math.radians(140), math.radians(200)), step=math.radians(30), width=math.radians(4),
        on_change=told.append, **COARSE,
    )  # fmt: skip
    assert sorted(told, key=lambda t: t.low) == found.changes  # each change told as it was bracketed
    assert (bars[1].total, bars[1].done) == (len(found.counts) - 3,) * 2  # openings, then bisections
    assert len(found.changes) >= 2  # more than one change in a step: the bar grew
    openings = np.degrees(found.openings)
    counts = {round(float(d), 3): (found.counts[o].low, found.counts[o].high) for d, o in zip(openings, found.openings)}
    assert counts[140.0] == (2, 2) and counts[200.0] == (0, 0)
    lens_gone = 2 * math.degrees(math.asin(1 - 2e-2))
    first = found.changes[0]
    assert math.degrees(first.low) <= lens_gone <= math.degrees(first.high)
    assert (first.before.low, first.before.high) == (2, 2)
    last = found.changes[-1]
    assert math.degrees(last.high) <= 185.0 and (last.after.low, last.after.high) == (0, 0)
    assert all(t.high - t.low <= math.radians(4) + 1e-12 for t in found.changes)
    assert "changes (brackets at most 4 deg wide; an event changes E_ε" in str(found)
    # the lens does not vanish at 157°: its depth passes ε + rim there (a crossing), and it lives on to π
    assert first.kind == "crossing" and "passes below ε + rim" in first.what()
    assert "vanishing" not in str(found)
    rims = [f.rim for f in found.counts.values()]  # ε here: the polylines' departure is smaller
    assert f"rim {min(rims):.1e}..{max(rims):.1e} b" in str(found) and max(rims) == 1e-2
    record = found.to_dict()
    assert record["units"]["lengths"] == "b" and len(record["transitions"]) == len(found.changes)
    # certain: no count lies in both brackets (lens and body, 2, before and none after is such a change)
    counts_in = [(set(range(t.before.low, t.before.high + 1)), set(range(t.after.low, t.after.high + 1)))
                 for t in found.changes]  # fmt: skip
    assert [t.certain for t in found.changes] == [not (a & b) for a, b in counts_in]
    assert [r["certain"] for r in record["transitions"]] == [t.certain for t in found.changes]
    # every opening is decided here (the body too: two end points hold it, :func:`~sesp.kernels.depth.two_tips`),
    # so every change is certain and there is no separate list of certain changes
    assert all(f.count is not None for f in found.counts.values())
    assert [(t.before.count, t.after.count) for t in found.changes] == [(2, 1), (1, 0)]
    assert [(t.low, t.high) for t in found.certain_changes()] == [(t.low, t.high) for t in found.changes]
    assert "the count certainly changes" not in str(found) and len(record["certain_changes"]) == 2


def test_certain_changes_span_the_undecided_openings_between_decided_counts():
    """Where undecided openings lie between two decided counts, the count certainly changes somewhere across
    them: one certain change from the last decided count to the next, wider than the brackets, listed apart."""

    def counted(low, high):
        return Certified(low, high, 1e-2, 1e-2, 1e-3)

    counts = {0.1: counted(2, 2), 0.2: counted(1, 2), 0.3: counted(1, 1), 0.4: counted(0, 1), 0.5: counted(0, 0)}
    openings = sorted(counts)
    changes = [topology.Transition(a, b, counts[a], counts[b]) for a, b in zip(openings, openings[1:])]
    found = topology.Transitions(counts, changes, 1e-2, 0.1, 0.1)
    certain = found.certain_changes()
    assert [(t.low, t.high, t.before.count, t.after.count) for t in certain] == [(0.1, 0.3, 2, 1), (0.3, 0.5, 1, 0)]
    assert not any(t.certain for t in changes)  # each bracket's counts overlap
    assert "the count certainly changes (between decided counts):" in str(found)


@pytest.mark.slow
def test_counts_in_worker_processes_are_those_counted_here():
    """Openings counted in two worker processes give the counts, and so the changes, counted in this one. While
    the middle of 150°-200° is counted the other worker counts ahead at a middle of one of its halves; it is
    kept only if the bisection then asks for it."""
    args = (SeSP(n=2), (math.radians(150), math.radians(200)))
    kwargs = dict(step=math.radians(50), width=math.radians(12.5), **COARSE)
    here, there = transitions(*args, workers=1, **kwargs), transitions(*args, workers=2, **kwargs)
    assert {o: (f.low, f.high) for o, f in here.counts.items()} == {o: (f.low, f.high) for o, f in there.counts.items()}
    assert len(here.counts) == 4 and [(t.low, t.high) for t in here.changes] == [(t.low, t.high) for t in there.changes]
    for o, f in here.counts.items():
        assert all(np.array_equal(f.cells[k], there.counts[o].cells[k]) for k in f.cells)


def test_the_range_and_family_are_checked():
    with pytest.raises(ValueError, match="openings"):
        transitions(SeSP(n=2), (1.0, 0.5))
    with pytest.raises(ValueError, match="step and width"):
        transitions(SeSP(n=2), (0.5, 1.0), width=0.0)
    with pytest.raises(ValueError, match="workers"):
        transitions(SeSP(n=2), (0.5, 1.0), workers=0)
    with pytest.raises(TypeError, match="family"):
        opening_family(3)


def test_a_step_is_bisected_where_what_is_known_of_the_count_changes():
    """Decided counts that differ, or a count decided on one side only, are a change; two undecided brackets
    are one only where they do not overlap (where they do, the count is not known between them)."""

    def at(low, high):
        return Certified(low, high, 1e-5, 1e-3, 2.5e-6)

    assert changed(at(2, 2), at(1, 1)) and changed(at(2, 2), at(2, 4))
    assert changed(at(1, 3), at(1, 1)) and changed(at(0, 1), at(2, 3))
    assert not changed(at(2, 2), at(2, 2)) and not changed(at(2, 4), at(1, 3))
    assert not changed(at(2, 5), at(0, 2))


def test_the_default_step_is_halved_to_the_width_in_four_counts(monkeypatch):
    """A count that changes once (here 2 below 178°, 1 above) is bracketed in exactly four bisections from the
    default step (16 widths), though the halved openings carry rounding: no fifth, costlier one."""
    counted = []

    def fake(particle, **_):
        counted.append(particle.opening)
        n = 2 if particle.opening < math.radians(178) else 1
        return Certified(n, n, 1e-5, 1e-3, 2.5e-6)

    monkeypatch.setattr(topology, "certified_components", fake)
    found = transitions(SeSP(n=2), workers=1)
    (change,) = found.changes
    assert len(counted) == 75 + 4 and math.radians(0.3) - 1e-15 < change.high - change.low <= math.radians(0.3) + 1e-12
    assert change.low < math.radians(178) <= change.high
