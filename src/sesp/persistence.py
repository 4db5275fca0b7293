"""Each excluded component's life over the opening Ψ, and each change of the count named for what it is.

A component at one opening is the same as one at the next where they lie in
the same place and their depths are nearest: of the pairs whose boxes (grown
by a quarter of their diagonals) meet, the one where the deepest point of
one lies in the other's box, with the least distance of their deepest points
(over their larger diagonal) and then the least |ln(depth ratio)|, is taken
first, and so on greedily (:func:`_score`). A component left without a
partner ends (or joins the one its box meets); one left new begins (or parts
from the one its box meets).

A change of the count between two openings is one of two kinds:

* a **topological event** of E_ε: components deeper than ε + rim on both
  sides join, or one parts in two, or one is born or dies while deeper than
  ε + rim (where the excluded set itself changes at once, as at Ψ = 0);
* a **resolution crossing**: a component's depth passes ε + rim; the
  component lives on, shallower or deeper, and the count at a lower rim does
  not change there.

Where a component's depth falls towards 0 at the end of its life, its end is
estimated from its depth curve: the law depth ≈ c·(Ψ_end − Ψ)^p fitted to its
last points by least squares in log depth, with a bar from leaving each point
out in turn (jackknife).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .certified import Certified
from .units import link_errors, quantity

__all__ = ["Step", "steps_between", "lives", "end_estimate", "FIT_POINTS"]

GROWTH = 0.25  # boxes are grown by this share of their diagonal before they are said to meet
FIT_POINTS = 6  # the last points of a dying component's depth curve that the end's law is fitted to


def _diagonal(c) -> float:
    x0, x1, y0, y1 = c.box
    return math.hypot(x1 - x0, y1 - y0)


def _meet(a, b) -> bool:
    """Whether the boxes of components ``a`` and ``b``, each grown by GROWTH of its diagonal, meet."""
    ga, gb = GROWTH * _diagonal(a), GROWTH * _diagonal(b)
    return (
        a.box[0] - ga <= b.box[1] + gb
        and b.box[0] - gb <= a.box[1] + ga
        and a.box[2] - ga <= b.box[3] + gb
        and b.box[2] - gb <= a.box[3] + ga
    )


def _inside(point, c, growth: float = GROWTH) -> bool:
    """Whether ``point`` lies in component ``c``'s box, grown by ``growth`` of its diagonal."""
    grow = growth * _diagonal(c)
    x0, x1, y0, y1 = c.box
    return x0 - grow <= point[0] <= x1 + grow and y0 - grow <= point[1] <= y1 + grow


def _score(a, b) -> float:
    """How unlike two components whose grown boxes meet are: 1 unless the deepest point of one lies in the
    other's grown box (the same place), plus the distance of their deepest points over the larger diagonal,
    plus a quarter of |ln depth ratio| (depths change fast where components thin out; places do not)."""
    scale = max(_diagonal(a), _diagonal(b), 1e-12)
    ratio = abs(math.log(max(b.depth, 1e-300) / max(a.depth, 1e-300)))
    if not (np.all(np.isfinite(a.point)) and np.all(np.isfinite(b.point))):
        return 1.0 + 0.25 * ratio
    same = _inside(a.point, b) or _inside(b.point, a)
    return (0.0 if same else 1.0) + math.dist(a.point, b.point) / scale + 0.25 * ratio


def match(before: list, after: list) -> tuple:
    """(pairs, joined, parted): index pairs (i, j) of ``before``'s and ``after``'s components that are the same
    component (greedy by :func:`_score` among those whose grown boxes meet); ``joined`` maps an ``i`` left over
    to a ``j`` whose box holds its deepest point (it joined that one), ``parted`` a ``j`` left over to the ``i``
    it parted from."""
    candidates = sorted((_score(a, b), i, j) for i, a in enumerate(before) for j, b in enumerate(after) if _meet(a, b))
    pairs, taken_i, taken_j = [], set(), set()
    for _, i, j in candidates:
        if i not in taken_i and j not in taken_j:
            pairs.append((i, j))
            taken_i.add(i)
            taken_j.add(j)
    # a join or a part: the deepest point of the one left over lies in the other's box itself
    joined = {
        i: j for _, i, j in candidates if i not in taken_i and j in taken_j and _inside(before[i].point, after[j], 0)
    }
    parted = {j: i for _, i, j in reversed(candidates)
              if j not in taken_j and i in taken_i and _inside(after[j].point, before[i], 0)}  # fmt: skip
    return pairs, joined, parted


@dataclass(frozen=True)
class Step:
    """One component's part in a change of the count: ``kind`` "event" or "crossing", ``what`` in words
    ("joins", "parts", "is born", "dies", "passes below ε + rim", "passes above ε + rim"), the component on
    each side (None where there is none) and its depth (b) there."""

    kind: str
    what: str
    before: object
    after: object

    def __str__(self) -> str:
        one = self.before if self.before is not None else self.after
        x0, x1, y0, y1 = one.box
        where = f"x {x0:+.3f}..{x1:+.3f}, y {y0:+.3f}..{y1:+.3f} b"
        depths = " -> ".join(f"{c.depth:.2g} b" if c is not None else "none" for c in (self.before, self.after))
        return f"{self.kind}: the component at {where} {self.what} (depth {depths})"


def steps_between(before, after) -> list:
    """The :class:`Step` s that make the counted components of ``before`` (a :class:`~sesp.Certified`) those of
    ``after``: events where components deeper than ε + rim on both sides join, or one parts in two; crossings
    where one component's depth passes ε + rim (also where it is listed on one side only: no cell of it is
    certified ε deep on the other, so its depth passed ε + rim on the way)."""
    a, b = before.components, after.components
    pairs, joined, parted = match(a, b)
    steps = []
    for i, j in pairs:
        if a[i].counted and not b[j].counted:
            steps.append(Step("crossing", "passes below ε + rim", a[i], b[j]))
        elif b[j].counted and not a[i].counted:
            steps.append(Step("crossing", "passes above ε + rim", a[i], b[j]))
    paired_i, paired_j = {i for i, _ in pairs}, {j for _, j in pairs}
    for i in sorted(set(range(len(a))) - paired_i):
        if a[i].counted:
            into = joined.get(i)
            if into is not None and b[into].counted:
                steps.append(Step("event", "joins another", a[i], b[into]))
            else:
                steps.append(Step("crossing", "passes below ε + rim and is no longer listed", a[i], None))
    for j in sorted(set(range(len(b))) - paired_j):
        if b[j].counted:
            source = parted.get(j)
            if source is not None and a[source].counted:
                steps.append(Step("event", "parts in two", a[source], b[j]))
            else:
                steps.append(Step("crossing", "is listed and passes above ε + rim", None, b[j]))
    return steps


def lives(counts: dict) -> xr.Dataset:
    """Each component's certified depth bracket over Ψ, followed from one opening to the next (:func:`match`).

    ``counts``: opening (rad) -> :class:`~sesp.Certified`. Returns a Dataset over (``life``, ``opening``):
    ``depth`` and ``top`` (b, NaN where the component is not listed), ``counted``; over ``opening``:
    ``opening_deg``, ``bar`` (ε + rim, b), ``count_low`` and ``count_high``; over ``life``: ``began`` and
    ``ended`` (deg: its first and last opening), ``end_estimate`` and ``end_estimate_error`` (deg: where its
    depth reaches 0, :func:`end_estimate`; NaN where it does not fall towards 0 or joins another) and the law's
    exponent ``end_exponent``."""
    openings = sorted(counts)
    rows, previous, joining, next_id = [], None, set(), 0
    for o in openings:
        found = counts[o].components
        row = [None] * len(found)
        if previous is not None:
            pairs, joined, _ = match(previous[1], found)
            for i, j in pairs:
                row[j] = previous[0][i]
            # a join of E_ε's components: both counted (a shallow one's cells may merge with a deeper candidate's)
            joining |= {previous[0][i] for i, j in joined.items() if previous[1][i].counted and found[j].counted}
        for j in range(len(found)):
            if row[j] is None:
                row[j], next_id = next_id, next_id + 1
        previous = (row, found)
        rows.append(previous)
    return _lives_dataset(openings, counts, rows, joining, next_id)


def _lives_dataset(openings, counts, ids, joining, count) -> xr.Dataset:
    depth, top = np.full((count, len(openings)), np.nan), np.full((count, len(openings)), np.nan)
    counted = np.zeros((count, len(openings)), bool)
    for k, (row, found) in enumerate(ids):
        for life, c in zip(row, found):
            depth[life, k], top[life, k], counted[life, k] = c.depth, c.top, c.counted
    deg = np.degrees(openings)
    seen = ~np.isnan(depth)
    began = np.array([deg[np.argmax(s)] for s in seen]) if count else np.zeros(0)
    ended = np.array([deg[len(s) - 1 - np.argmax(s[::-1])] for s in seen]) if count else np.zeros(0)
    ends = np.full((count, 3), np.nan)
    departure = _departures(openings, counts)
    for life in range(count):
        last = len(deg) - 1 - np.argmax(seen[life][::-1])
        if last < len(deg) - 1 and life not in joining:  # it ends inside the range, not by joining another
            shift = 2 * float(np.max(departure[seen[life]]))
            ends[life] = end_estimate(deg[seen[life]], depth[life][seen[life]], shift)
    c0 = counts[openings[0]]
    return link_errors(xr.Dataset(
        {
            "depth": (("life", "opening"), depth, quantity(1, "certified depth (lower bound)")),
            "top": (("life", "opening"), top, quantity(1, "upper bound on the depth")),
            "counted": (("life", "opening"), counted, {"long_name": "counted: at least resolution + rim deep"}),
            "bar": ("opening", [counts[o].resolution + counts[o].rim for o in openings],
                    quantity(1, "resolution + rim: the depth from which a component is counted")),
            "count_low": ("opening", [counts[o].low for o in openings], {"units": "1"}),
            "count_high": ("opening", [counts[o].high for o in openings], {"units": "1"}),
            "began": ("life", began, {"units": "degree", "long_name": "first opening it is listed at"}),
            "ended": ("life", ended, {"units": "degree", "long_name": "last opening it is listed at"}),
            "end_estimate": ("life", ends[:, 0], {"units": "degree", "long_name": "opening where its depth reaches 0"}),
            "end_estimate_error": ("life", ends[:, 1], {"units": "degree", "long_name": "error bar of end_estimate"}),
            "end_exponent": ("life", ends[:, 2], {"units": "1", "long_name": "p of depth = c (end - opening)^p"}),
        },
        coords={"opening": ("opening", np.asarray(openings), {"units": "rad"}),
                "opening_deg": ("opening", deg, {"units": "degree"}), "life": np.arange(count)},
        attrs={"resolution": c0.resolution},
    ))  # fmt: skip


def _departures(openings, counts) -> np.ndarray:
    """b, per opening: the polylines' departure from the smooth curves (0 where no component says)."""
    return np.array([max([c.departure for c in counts[o].components], default=0.0) for o in openings])


def end_estimate(deg, depth, shift: float = 0.0) -> tuple:
    """(end, bar, p), degrees: where a depth curve falling towards 0 reaches 0, from the law depth ≈
    c·(end − Ψ)^p fitted by least squares in ln depth to its last FIT_POINTS points (at least 4, falling). The
    bar adds a jackknife over the points and the change of the end when every depth is raised by ``shift`` (b:
    twice the polylines' departure from the smooth curves, by which a depth of the smooth particle's excluded
    set may differ from the polylines'); NaN where there are too few points or they do not fall."""
    deg, depth = np.asarray(deg, float), np.asarray(depth, float)
    keep = depth > 0
    deg, depth = deg[keep], depth[keep]
    falling = len(depth)
    while falling > 1 and depth[falling - 2] > depth[falling - 1]:
        falling -= 1
    use = slice(max(falling - 1, len(depth) - FIT_POINTS), len(depth))
    x, y = deg[use], np.log(depth[use])
    if len(x) < 4:
        return math.nan, math.nan, math.nan
    end, p = _fit_end(x, y)
    outs = np.array([_fit_end(np.delete(x, k), np.delete(y, k))[0] for k in range(len(x))])
    jackknife = (len(x) - 1) / len(x) * float(((outs - outs.mean()) ** 2).sum())
    shifted = _fit_end(x, np.log(depth[use] + shift))[0] if shift > 0 else end
    return end, math.sqrt(jackknife + (shifted - end) ** 2), p


def _fit_end(x, y) -> tuple:
    """(end, p) minimising Σ (y − a − p ln(end − x))² over end > max(x) (a, p by linear least squares at each
    end, the end by a search on ln(end − max x) refined by golden sections)."""
    last, span = float(x.max()), float(x.max() - x.min())

    def residual(log_gap):
        g = np.log(last + math.exp(log_gap) - x)
        design = np.column_stack([np.ones_like(g), g])
        coef, *_ = np.linalg.lstsq(design, y, rcond=None)
        return float(((design @ coef - y) ** 2).sum()), float(coef[1])

    grid = np.linspace(math.log(span * 1e-4), math.log(span * 10), 121)
    values = [residual(v)[0] for v in grid]
    k = int(np.argmin(values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    ratio = (math.sqrt(5) - 1) / 2
    for _ in range(60):
        a, b = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
        if residual(a)[0] < residual(b)[0]:
            hi = b
        else:
            lo = a
    best = 0.5 * (lo + hi)
    return last + math.exp(best), residual(best)[1]


def sweep_lives(ds: xr.Dataset) -> xr.Dataset:
    """:func:`lives` along the ``opening`` of a collected sweep that kept "topology", at every value of its other
    swept parameters: ``life_depth``, ``life_top`` and ``life_counted`` over (..., ``life``, ``opening``), and
    ``life_end_estimate`` ± ``life_end_estimate_error`` (deg) and ``life_end_exponent`` over (..., ``life``);
    lives padded with NaN to the most any slice has."""
    others = [d for d in ds.excluded_components.dims if d != "opening"]
    stacked = ds.stack(slice_=others) if others else ds.expand_dims("slice_")
    found = []
    for k in range(stacked.sizes["slice_"]):
        one = stacked.isel(slice_=k)
        counts = {float(o): Certified.from_dataset(one.sel(opening=o)) for o in one.opening.values}
        found.append(lives(counts))
    size = max([f.sizes["life"] for f in found] + [1])
    padded = [f.reindex(life=np.arange(size)) for f in found]
    out = xr.concat(padded, dim="slice_").assign_coords(slice_=stacked.slice_)
    out = out.unstack("slice_") if others else out.isel(slice_=0, drop=True)
    names = {"depth": "life_depth", "top": "life_top", "counted": "life_counted", "end_estimate": "life_end_estimate",
             "end_estimate_error": "life_end_estimate_error", "end_exponent": "life_end_exponent"}  # fmt: skip
    out = out[list(names)].rename(names)
    out["life_counted"] = out.life_counted.fillna(False).astype(bool)
    out = out.drop_vars("opening_deg", errors="ignore").assign_coords(opening=ds.opening)
    return out.transpose(*others, "life", ...)
