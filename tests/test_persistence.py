"""Each component's life over Ψ, the kinds of change, and the end of a component whose depth falls to 0."""

import math

import numpy as np
import pytest

from sesp import SeSP, transitions
from sesp.certified import Certified, CertifiedComponent
from sesp.persistence import end_estimate, match, steps_between

COARSE = dict(resolution=1e-2, segments=64)


def _component(depth, box, point, bar=2e-2, parts=1):
    return CertifiedComponent(parts, depth, 0.1, 0.2, box, 0.0, depth * 1.2, bar, point)


def _found(*components, bar=2e-2):
    counted = sum(c.counted for c in components)
    return Certified(counted, counted, bar / 2, bar / 2, 1e-3, list(components))


BODY = ((-0.6, -0.1, -0.3, 0.3), (-0.4, 0.0))
LENS = ((0.05, 0.5, -0.05, 0.05), (0.25, 0.0))


def test_a_lens_that_becomes_shallow_is_a_crossing_and_keeps_its_life():
    before = _found(_component(0.10, *BODY), _component(0.03, *LENS))
    after = _found(_component(0.09, *BODY), _component(0.015, *LENS))
    (step,) = steps_between(before, after)
    assert (step.kind, step.what) == ("crossing", "passes below ε + rim")
    pairs, joined, parted = match(before.components, after.components)
    assert sorted(pairs) == [(0, 0), (1, 1)] and not joined and not parted


def test_a_component_that_parts_from_another_is_an_event_and_one_no_longer_listed_a_crossing():
    whole = _found(_component(0.10, (-0.6, 0.5, -0.3, 0.3), (-0.4, 0.0)))
    parted = _found(_component(0.10, *BODY), _component(0.03, *LENS))
    (step,) = steps_between(whole, parted)
    assert (step.kind, step.what) == ("event", "parts in two")
    (step,) = steps_between(parted, _found(_component(0.09, *BODY)))  # the lens is listed no more: its depth
    assert step.kind == "crossing"  # passed ε + rim on its way below ε (not a join: the body's box lacks it)


def test_two_components_that_join_are_an_event():
    apart = _found(_component(0.10, *BODY), _component(0.03, (-0.05, 0.3, -0.05, 0.05), (0.1, 0.0)))
    joined = _found(_component(0.11, (-0.6, 0.3, -0.3, 0.3), (-0.35, 0.0)))
    (step,) = steps_between(apart, joined)
    assert (step.kind, step.what) == ("event", "joins another")


def test_the_end_of_a_depth_curve_is_where_the_fitted_law_reaches_zero():
    """The ASP's lens, 1 − sin(Ψ/2) ≈ (π − Ψ)²/8, at the openings a default table lists it: its end is π within
    0.05°, the law's exponent 2; a curve that does not fall, or has too few points, has none."""
    deg = np.array([165, 170, 172.8, 174.6, 174.75, 174.9])
    end, bar, p = end_estimate(deg, 1 - np.sin(np.radians(deg) / 2))
    assert abs(end - 180) < 0.05 and bar < 0.05 and p == pytest.approx(2, abs=0.01)
    assert math.isnan(end_estimate(deg, np.linspace(0.01, 0.02, 6))[0])
    assert math.isnan(end_estimate(deg[:3], 1 - np.sin(np.radians(deg[:3]) / 2))[0])


def test_the_asps_components_over_psi_their_kinds_and_where_the_lens_ends():
    """At ε = 1e-2 b: the lens (inscribed radius 1 − sin(Ψ/2), within the polylines' departure of the certified
    bracket) crosses ε + rim = 2ε at 157.0°, a crossing; it is followed as one life from 120° and its end lies
    within its bar of π; the body is followed as another."""
    found = transitions(SeSP(n=2), (math.radians(120), math.radians(165)), step=math.radians(15),
                        width=math.radians(1), workers=2, resolution=1e-2, segments=128)  # fmt: skip
    crossing = found.changes[0]
    assert crossing.kind == "crossing" and math.radians(157.0) - crossing.low < math.radians(1.01)
    ds = found.lives
    lens = int(np.nanargmin(ds.depth.sel(opening=found.openings[0]).values))
    seen = np.isfinite(ds.depth.sel(life=lens).values)
    psi = found.openings[seen]
    exact = 1 - np.sin(psi / 2)
    departure = found.counts[found.openings[0]].components[0].departure
    assert np.all(ds.depth.sel(life=lens).values[seen] <= exact + departure)
    assert np.all(ds.top.sel(life=lens).values[seen] >= exact - departure)
    end, bar = float(ds.end_estimate.sel(life=lens)), float(ds.end_estimate_error.sel(life=lens))
    assert abs(end - 180) <= bar and bar < 5
    assert ds.sizes["life"] == 2 and float(ds.began.sel(life=1 - lens)) == pytest.approx(120)
    record = found.to_dict()
    assert record["transitions"][0]["kind"] == "crossing" and len(record["components"]) == 2


@pytest.mark.slow
def test_counts_are_kept_in_a_cache_a_rerun_reads_them_and_a_damaged_one_is_counted_again(tmp_path, monkeypatch):
    from sesp import topology

    span = (math.radians(150), math.radians(170))
    first = transitions(SeSP(n=2), span, step=math.radians(10), width=math.radians(5), workers=1, cache=tmp_path,
                        **COARSE)  # fmt: skip
    files = sorted(tmp_path.glob("*.json"))
    assert len(files) == len(first.counts)

    def refused(*args, **kwargs):
        raise AssertionError("counted again")

    monkeypatch.setattr(topology, "certified_components", refused)
    again = transitions(SeSP(n=2), span, step=math.radians(10), width=math.radians(5), workers=1, cache=tmp_path,
                        **COARSE)  # fmt: skip
    assert [t.what() for t in again.changes] == [t.what() for t in first.changes]
    monkeypatch.undo()
    files[0].write_text("{not json")
    third = transitions(SeSP(n=2), span, step=math.radians(10), width=math.radians(5), workers=1, cache=tmp_path,
                        **COARSE)  # fmt: skip
    assert len(list(tmp_path.glob("*.damaged"))) == 1 and len(third.counts) == len(first.counts)


def test_ctrl_c_during_a_search_gives_what_was_counted(monkeypatch):
    from sesp import topology

    real, calls = topology.certified_components, []

    def interrupted(particle, **kwargs):
        calls.append(particle.opening)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(particle, **kwargs)

    monkeypatch.setattr(topology, "certified_components", interrupted)
    with pytest.raises(topology.Interrupted) as stopped:
        transitions(SeSP(n=2), (math.radians(140), math.radians(200)), step=math.radians(10), workers=1, **COARSE)
    assert len(stopped.value.partial.counts) == 2


@pytest.mark.slow
def test_each_settled_run_is_told_in_order():
    runs = []
    transitions(SeSP(n=2), (math.radians(140), math.radians(200)), step=math.radians(10), width=math.radians(10),
                workers=2, on_run=lambda a, b, f: runs.append((round(math.degrees(a)), round(math.degrees(b)),
                                                               f.bracket)), **COARSE)  # fmt: skip
    assert runs[0] == (140, 150, "2") and runs[-1][1:] == (200, "0")
    assert [r[0] for r in runs] == sorted(r[0] for r in runs)
