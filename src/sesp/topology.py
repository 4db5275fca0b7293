"""Topology of the excluded set over the opening Ψ, and the plain components of a stored field.

The count
---------
"How many components does the excluded set have?" has one answer in sesp:
:func:`sesp.certified_components`, the components of the excluded set eroded
by a resolution ε (b), certified on both sides and exact in φ (the definition
is in :mod:`sesp.certified`). :func:`transitions` follows that count over Ψ:
it counts at openings ``step`` apart and bisects every step where what is
known of the count changes (a decided count changes, becomes undecided or is
decided; two undecided brackets that do not overlap) until the change is
held in a bracket at most ``width`` wide. Within a stretch of overlapping
undecided brackets the count is not known at that resolution, and is not
bisected. A change that undoes itself within one step (a count going
2 → 3 → 2) is not seen; a finer ``step`` finds it.

A stored field's components
---------------------------
:func:`lattice_components` labels the nodes of a stored boolean field (the
excluded positions of a scan or summary, or the allowed or entangled states
in (x, y, φ), φ periodic): nodes sharing a face are joined, nothing else. It
describes the field at its node spacing (a neck thinner than a node parts,
a body thinner than a node may be missed), not the set: for the count,
quote :func:`sesp.certified_components`.
"""

from __future__ import annotations

import dataclasses
import functools
import heapq
import itertools
import math
import os
import time
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .cache import CountCache
from .certified import BASE, RESOLUTION, Certified, certified_components
from .checks import check_resolution
from .dataset import cell_area
from .kernels import cells as cell_kernels
from .pair import Pair, as_pair
from .persistence import lives, steps_between
from .progress import progress_bar
from .shape import DEFAULT_SEGMENTS, SeSP
from .workers import start_pool, stop_pool

__all__ = [
    "LatticeComponents",
    "lattice_components",
    "Transition",
    "Transitions",
    "transitions",
    "Interrupted",
    "opening_family",
    "STEP",
    "WIDTH",
]

WIDTH = math.radians(0.3)  # rad: every change is bracketed at least this narrowly
STEP = 16 * WIDTH  # rad (4.8°): openings first counted this far apart; four halvings end at the width exactly


# --- transitions over the opening Ψ -------------------------------------------------------


def opening_family(family):
    """opening -> particle: a SeSP's opening varied, or the callable itself."""
    if isinstance(family, SeSP):
        return lambda opening: dataclasses.replace(family, opening=float(opening))
    if callable(family) and not isinstance(family, Pair):
        return family
    raise TypeError("family must be a SeSP (its opening is varied) or a callable opening (rad) -> particle or Pair")


def _state(found: Certified) -> tuple:
    return found.low, found.high


def _apart(a: Certified, b: Certified) -> bool:
    """Whether the two count brackets have no count in common: the count itself differs."""
    return a.high < b.low or b.high < a.low


def changed(a: Certified, b: Certified) -> bool:
    """Whether what is known of the count differs between two openings: a decided count changed, became
    undecided or was decided; two undecided brackets differ only where they do not overlap (where they do,
    where between them the count changes, if it does, is not known at this resolution)."""
    if a.count is None and b.count is None:
        return _apart(a, b)
    return _state(a) != _state(b)


@dataclass(frozen=True)
class Transition:
    """A change of the certified count between the openings ``low`` and ``high`` (radians), with the counts
    at both ends (``before``, ``after``: :class:`~sesp.certified.Certified`)."""

    low: float
    high: float
    before: Certified
    after: Certified

    @property
    def opening(self) -> float:
        """rad: the middle of the bracket."""
        return 0.5 * (self.low + self.high)

    @property
    def certain(self) -> bool:
        """Whether the count itself changes: the brackets on the two sides have no count in common. Otherwise
        what is known of it changes (a count becomes undecided, or is decided), where the count may not."""
        return _apart(self.before, self.after)

    @property
    def steps(self) -> list:
        """The components' parts in the change (:func:`sesp.persistence.steps_between`)."""
        return steps_between(self.before, self.after)

    @property
    def kind(self) -> str:
        """ "event" where components deeper than ε + rim on both sides join or part, "crossing" where a
        component's depth passes ε + rim (the count at a lower rim does not change here), "undecided" where the
        count on either side is not one number."""
        if self.before.count is None or self.after.count is None:
            return "undecided"
        return "event" if any(step.kind == "event" for step in self.steps) else "crossing"

    def what(self) -> str:
        """In words: the count on each side, the kind of change, and each component's part in it (where the
        count is undecided, which component is undecided and why)."""
        said = f"{self.before.bracket} -> {self.after.bracket}: {self.kind}"
        if self.kind == "undecided":
            side = self.before if self.before.count is None else self.after
            unsure = [c for c in side.components if not c.decided]
            return f"{said}; " + "; ".join(f"{_place(c)}: {c.why()}" for c in unsure[:2])
        return f"{said}; " + "; ".join(str(step).split(": ", 1)[1] for step in self.steps)


def _place(component) -> str:
    x0, x1, y0, y1 = component.box
    return f"the component at x {x0:+.3f}..{x1:+.3f}, y {y0:+.3f}..{y1:+.3f} b"


@dataclass
class Transitions:
    """The certified count over the opening: ``counts`` maps each opening counted (radians) to its
    :class:`~sesp.certified.Certified`; ``changes`` lists every :class:`Transition` found, in order."""

    counts: dict
    changes: list
    resolution: float
    step: float
    width: float
    label: str = ""
    seconds: float = 0.0

    @property
    def openings(self) -> np.ndarray:
        """rad, ascending."""
        return np.array(sorted(self.counts))

    @functools.cached_property
    def lives(self) -> xr.Dataset:
        """Each component's certified depth bracket over the openings counted, followed from one to the next,
        with where its depth reaches 0 (:func:`sesp.persistence.lives`)."""
        return lives(self.counts)

    def __str__(self) -> str:
        lines = []
        if self.label:
            lines.append(self.label)
        lines.append(f"excluded components over the opening, at resolution {self.resolution:.1e} b (degrees)")
        if self.counts:
            rims = [f.rim for f in self.counts.values()]  # the polylines' departure changes with the opening
            lines.append(f"  (counted: components at least resolution + rim deep, rim {min(rims):.1e}.."
                         f"{max(rims):.1e} b over the openings; shallower ones are listed, not counted)")  # fmt: skip
        lines.append(f"{'from':>9} {'to':>9} {'count':>6}")
        first = sorted(self.runs_of())
        for a, b, found in first:
            lines.append(f"{math.degrees(a):9.3f} {math.degrees(b):9.3f} {found.bracket:>6}")
        lines.append(f"changes (brackets at most {math.degrees(self.width):.3g} deg wide; an event changes E_ε, a "
                     "crossing is a component's depth passing resolution + rim):")  # fmt: skip
        for t in self.changes:
            lines.append(f"  {math.degrees(t.low):9.3f} .. {math.degrees(t.high):9.3f}: {t.what()}")
        if not self.changes:
            lines.append("  none")
        certain = self.certain_changes()
        if certain and any(not t.certain for t in self.changes):
            lines.append("the count certainly changes (between decided counts):")
            for t in certain:
                lines.append(f"  {math.degrees(t.low):9.3f} .. {math.degrees(t.high):9.3f}: {t.before.count} -> "
                             f"{t.after.count}")  # fmt: skip
        lines += self._lives_lines()
        lines.append(f"({len(self.counts)} openings counted, {self.seconds:.0f} s)")
        return "\n".join(lines)

    def _lives_lines(self) -> list:
        """The components followed over Ψ: where each is listed, its depth there, and where it reaches 0."""
        found = self.lives
        if not found.sizes.get("life"):
            return []
        lines = ["components followed over the opening (depth: certified lower bound, b; ends: where it reaches 0):"]
        for life in found.life.values:
            row = found.sel(life=life)
            seen = np.isfinite(row.depth.values)
            depths = row.depth.values[seen]
            said = (f"  {int(life) + 1}: {float(row.began):.3f} .. {float(row.ended):.3f} deg, depth "
                    f"{depths.max():.3g} .. {depths[-1]:.3g} b")  # fmt: skip
            if np.isfinite(float(row.end_estimate)):
                said += (f"; reaches 0 at {float(row.end_estimate):.2f} ± {float(row.end_estimate_error):.2f} deg "
                         f"(depth ≈ c (end − Ψ)^{float(row.end_exponent):.2f})")  # fmt: skip
            lines.append(said)
        return lines

    def certain_changes(self) -> list:
        """Where the count certainly changes: a :class:`Transition` between each two openings counted whose
        counts are decided and differ, with no decided count between them. Where undecided counts lie between,
        the bracket is wider than ``width``: the count is not decided there at this resolution."""
        decided = [(o, f) for o, f in sorted(self.counts.items()) if f.count is not None]
        return [Transition(a, b, fa, fb) for (a, fa), (b, fb) in zip(decided, decided[1:]) if fa.count != fb.count]

    def runs_of(self) -> list:
        """(first opening, last opening, Certified at the first): runs of openings with one count bracket."""
        runs = []
        for o in self.openings:
            found = self.counts[o]
            if runs and _state(runs[-1][2]) == _state(found):
                runs[-1] = (runs[-1][0], o, runs[-1][2])
            else:
                runs.append((o, o, found))
        return runs

    def to_dict(self) -> dict:
        """Plain numbers for JSON: openings in degrees and radians, lengths in b."""
        return {
            "resolution": self.resolution, "step_deg": math.degrees(self.step), "width_deg": math.degrees(self.width),
            "units": {"lengths": "b", "areas": "b^2", "openings": "deg (and rad where named)"},
            "seconds": self.seconds,
            "counts": [
                {"opening_deg": math.degrees(o), "opening": o, "count_low": f.low, "count_high": f.high}
                for o, f in sorted(self.counts.items())
            ],
            "transitions": [
                {"low_deg": math.degrees(t.low), "high_deg": math.degrees(t.high), "low": t.low, "high": t.high,
                 "count_before": [t.before.low, t.before.high], "count_after": [t.after.low, t.after.high],
                 "certain": t.certain, "kind": t.kind, "what": t.what(),
                 "steps": [{"kind": step.kind, "what": step.what, "box": list((step.before or step.after).box),
                            "depth_before": step.before.depth if step.before is not None else None,
                            "depth_after": step.after.depth if step.after is not None else None}
                           for step in (t.steps if t.kind != "undecided" else [])]}
                for t in self.changes
            ],
            "components": _lives_dict(self.lives),
            "certain_changes": [
                {"low_deg": math.degrees(t.low), "high_deg": math.degrees(t.high), "low": t.low, "high": t.high,
                 "count_before": t.before.count, "count_after": t.after.count}
                for t in self.certain_changes()
            ],
        }  # fmt: skip


def _lives_dict(found: xr.Dataset) -> list:
    """:attr:`Transitions.lives` as plain numbers: per component, where it is listed and its depth bracket."""
    out = []
    for life in found.life.values:
        row = found.sel(life=life)
        seen = np.isfinite(row.depth.values)
        out.append({
            "began_deg": float(row.began), "ended_deg": float(row.ended),
            "end_estimate_deg": _number(row.end_estimate), "end_estimate_error_deg": _number(row.end_estimate_error),
            "end_exponent": _number(row.end_exponent),
            "depths": [{"opening_deg": float(o), "depth": float(d), "top": float(t), "counted": bool(c)}
                       for o, d, t, c in zip(found.opening_deg.values[seen], row.depth.values[seen],
                                             row.top.values[seen], row.counted.values[seen])],
        })  # fmt: skip
    return out


def _number(value):
    """A float, or None for NaN (JSON has no NaN)."""
    value = float(value)
    return value if math.isfinite(value) else None


def _openings(opening_range, step):
    """The first pass's openings: ``step`` apart from the range's start, the end included, below 2π."""
    lo, hi = (float(v) for v in opening_range)
    if not (0.0 <= lo < hi <= 2 * math.pi):
        raise ValueError(f"openings must satisfy 0 <= low < high <= 2π rad, got {opening_range}")
    count = max(1, math.ceil((hi - lo) / step - 1e-9))
    openings = np.linspace(lo, hi, count + 1)
    return [float(o) for o in openings if o < 2 * math.pi]


def transitions(
    family,
    openings=(0.0, 2 * math.pi),
    *,
    step: float = STEP,
    width: float = WIDTH,
    resolution: float = RESOLUTION,
    rim: float | None = None,
    base: int = BASE,
    segments: int = DEFAULT_SEGMENTS,
    progress: bool = True,
    on_change=None,
    on_run=None,
    workers: int | None = None,
    cache=None,
) -> Transitions:
    """Where the certified count of excluded components changes as the opening Ψ varies.

    Parameters
    ----------
    family : SeSP or callable
        A SeSP whose opening is varied, or a function opening (rad) -> particle or Pair.
    openings : (float, float)
        The range of Ψ, radians, within [0, 2π] (2π itself, no particle, is left out).
    step : float
        rad: openings first counted at most this far apart (the range is cut into equal steps).
    width : float
        rad: every change is bisected until its bracket is at most this wide.
    resolution, rim, base, segments
        As for :func:`sesp.certified_components`.
    on_change : callable, optional
        Called with each :class:`Transition` as soon as it is bracketed: a long search shows, or keeps, what
        it found so far.
    on_run : callable, optional
        Called with (first opening, last opening, :class:`~sesp.Certified`) for each run of the first pass's
        openings with one count, as soon as every opening up to its end is counted.
    workers : int, optional
        Count this many openings at once, each in a worker process (default: one per core; 1: in this
        process, one opening at a time with all of numba's threads). The counts, and so the result, are the
        same (``benchmarks/transition_tables.py --workers 1 2``).
    cache : str or Path, optional
        A folder of counted openings (:class:`sesp.cache.CountCache`): counts found there are not counted
        again, and each count made is written there as soon as it is done, so an interrupted search resumes.

    Returns
    -------
    Transitions

    Raises
    ------
    Interrupted
        On Ctrl-C, after the workers are stopped; its ``partial`` is the :class:`Transitions` of what was
        counted so far.

    Examples
    --------
    >>> import math
    >>> from sesp import SeSP
    >>> found = transitions(SeSP(n=2), (math.radians(150), math.radians(200)), step=math.radians(50),
    ...                     width=math.radians(25), resolution=1e-2, segments=128)
    >>> [(found.counts[o].low, found.counts[o].high) for o in found.openings[[0, -1]]]
    [(2, 2), (0, 0)]
    >>> all(t.high - t.low <= math.radians(25) for t in found.changes)
    True
    """
    if not (step > 0 and width > 0 and math.isfinite(step) and math.isfinite(width)):
        raise ValueError(f"step and width must be angles > 0 (rad), got {step!r}, {width!r}")
    check_resolution(resolution, rim, base)
    workers = (os.cpu_count() or 1) if workers is None else workers
    if not (isinstance(workers, int | np.integer) and workers >= 1):
        raise ValueError(f"workers must be a whole number of processes >= 1, got {workers!r}")
    grid = _openings(openings, step)
    start = time.perf_counter()
    kept = None if cache is None else cache if isinstance(cache, CountCache) else CountCache(cache)
    counter = _Counter(opening_family(family), (resolution, rim, base, segments), int(workers), kept)
    state = {"counts": {}, "changes": []}  # what is known so far, kept whatever stops the search
    try:
        _search(counter, grid, width, progress, (on_change, on_run), state)
    except BaseException as stopped:  # Ctrl-C, or a failed count: stop the workers now
        counter.stop()
        if isinstance(stopped, KeyboardInterrupt):
            partial = _result(state, resolution, step, width, start)
            raise Interrupted(partial) from stopped
        raise
    counter.close()
    return _result(state, resolution, step, width, start)


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`transitions`: ``partial`` holds what was counted (a :class:`Transitions`)."""

    def __init__(self, partial):
        super().__init__("interrupted")
        self.partial = partial


def _result(state, resolution, step, width, start) -> Transitions:
    changes = sorted(state["changes"], key=lambda t: t.low)
    return Transitions(dict(state["counts"]), changes, resolution, step, width, seconds=time.perf_counter() - start)


def _settled_runs(grid, counts, printed, on_run):
    """Call ``on_run`` for each run of the first pass's openings with one count whose openings up to its end are
    all counted, and that is followed by another count (``printed``: [index of the next opening to settle])."""
    k = printed[0]
    while k < len(grid) and grid[k] in counts:
        end = k
        while (
            end + 1 < len(grid) and grid[end + 1] in counts and _state(counts[grid[end + 1]]) == _state(counts[grid[k]])
        ):
            end += 1
        if end + 1 < len(grid) and grid[end + 1] not in counts:
            break  # the run may go on: not settled yet
        on_run(grid[k], grid[end], counts[grid[k]])
        k = end + 1
    printed[0] = k


def _search(counter, grid, width, progress, callbacks, state):
    """Counts at ``grid``, then every step where what is known changes bisected to ``width``
    (:func:`transitions`), written into ``state`` ("counts" per opening, "changes") as they are found."""
    on_change, on_run = callbacks
    counts, changes = state["counts"], state["changes"]
    printed = [0]
    with progress_bar(len(grid), progress, "openings", unit="Ψ") as bar:
        for o in grid:
            counter.ask(o)
        while (got := counter.next()) is not None:
            counts[got[0]] = got[1]
            bar.update(1)
            if on_run is not None:
                _settled_runs(grid, counts, printed, on_run)
    pending = [(a, b) for a, b in zip(grid[:-1], grid[1:]) if changed(counts[a], counts[b])]
    done = width + 1e-12  # rad: a bracket this narrow is done (the halved openings' rounding is far below this)

    def halvings(lo, hi):  # counts a bracket [lo, hi] needs until it is at most ``width`` wide
        return max(0, math.ceil(math.log2((hi - lo) / done)))

    brackets = {}  # the middle being counted -> its bracket

    def bisect(a, b):
        if b - a > done:
            brackets[0.5 * (a + b)] = (a, b)
            counter.ask(0.5 * (a + b), max(counts[a].seconds, counts[b].seconds))
            return
        changes.append(Transition(a, b, counts[a], counts[b]))
        if on_change is not None:
            on_change(changes[-1])

    def guess():  # an opening a bisection under way may ask for next: a middle of a half of the costliest
        options = [(-max(counts[a].seconds, counts[b].seconds), q)
                   for mid, (a, b) in brackets.items() if b - a > 2 * done
                   for q in (0.5 * (a + mid), 0.5 * (mid + b)) if q not in counts and not counter.knows(q)]  # fmt: skip
        return min(options)[1] if options else None

    counter.guess = guess
    with progress_bar(sum(halvings(a, b) for a, b in pending), progress, "bisections", unit="Ψ") as bar:
        for a, b in pending:
            bisect(a, b)
        while (got := counter.next()) is not None:
            mid, found = got
            counts[mid] = found
            bar.update(1)
            a, b = brackets.pop(mid)
            halves = [(lo, hi) for lo, hi in ((a, mid), (mid, b)) if changed(counts[lo], counts[hi])]
            if len(halves) != 1:  # a second branch to bisect, or none left (the change undid itself)
                bar.total += (len(halves) - 1) * halvings(a, mid)
                bar.refresh()
            for lo, hi in halves:
                bisect(lo, hi)


def _count(particle, resolution, rim, base, segments) -> Certified:
    """One opening's certified count (in a worker process where there are several)."""
    return certified_components(particle, resolution=resolution, rim=rim, base=base, segments=segments, progress=False)


class _Counter:
    """Counts openings: in this process, or in ``workers`` worker processes (:func:`~sesp.workers.start_pool`;
    the counts do not depend on them), each as soon as one is free. The costliest opening asked for goes first
    (``cost``: the seconds its bracket's ends took), so the chain of bisections that takes longest starts first.
    A worker with nothing asked of it counts ahead what ``guess`` says may be asked next (the next middles of a
    bracket being bisected); a count ahead that is never asked for is dropped, so the result is the same."""

    def __init__(self, make, settings, workers, cache=None):
        self.make, self.settings, self.workers, self.cache = make, settings, workers, cache
        self.waiting, self.running = [], {}  # waiting: a heap of (-cost, order asked, opening)
        self.asked = itertools.count()
        self.ahead, self.spare, self.ready = set(), {}, []  # counting ahead; counted ahead; asked, counted ahead
        self.guess = None
        self.pool = None if workers == 1 else start_pool(workers)

    def _key(self, opening) -> str:
        return CountCache.key(as_pair(self.make(opening), segments=self.settings[3]), self.settings)

    def _kept(self, opening, found):
        """``found``, written to the cache (where there is one)."""
        if self.cache is not None:
            self.cache.put(self._key(opening), found)
        return found

    def ask(self, opening, cost=0.0):
        known = None if self.cache is None else self.cache.get(self._key(opening))
        if known is not None:
            self.ready.append((opening, known))
        elif opening in self.spare:
            self.ready.append((opening, self.spare.pop(opening)))
        elif opening in self.ahead:
            self.ahead.discard(opening)  # now asked for: returned when it is done
        else:
            heapq.heappush(self.waiting, (-cost, next(self.asked), opening))

    def knows(self, opening) -> bool:
        """Whether ``opening`` is asked for or counted ahead (its count done or under way)."""
        return opening in self.spare or opening in self.running.values() or any(w[2] == opening for w in self.waiting)

    def next(self):
        """(opening, Certified) for one opening asked for, or None when none is left."""
        if self.ready:
            return self.ready.pop(0)
        if self.pool is None:
            if not self.waiting:
                return None
            opening = heapq.heappop(self.waiting)[2]
            return opening, self._kept(opening, _count(self.make(opening), *self.settings))
        self._fill()
        while self.waiting or any(o not in self.ahead for o in self.running.values()):
            finished, _ = wait(self.running, return_when=FIRST_COMPLETED)
            future = min(finished, key=self.running.get)
            opening = self.running.pop(future)
            found = self._kept(opening, future.result())
            if opening not in self.ahead:
                return opening, found
            self.ahead.discard(opening)
            self.spare[opening] = found
            self._fill()
        return None

    def _fill(self):
        """Give each free worker the costliest opening asked for, or else one to count ahead."""
        while len(self.running) < self.workers:
            if self.waiting:
                opening = heapq.heappop(self.waiting)[2]
            elif self.guess is not None and (opening := self.guess()) is not None:
                self.ahead.add(opening)
            else:
                return
            self.running[self.pool.submit(_count, self.make(opening), *self.settings)] = opening

    def stop(self):
        if self.pool is not None:
            stop_pool(self.pool)

    def close(self):
        """Shut the workers down; counts ahead still under way are not waited for."""
        if self.pool is not None and self.running:
            stop_pool(self.pool, interrupt=False)
        elif self.pool is not None:
            self.pool.shutdown()


# --- components of a stored field ---------------------------------------------------------


@dataclass(frozen=True)
class LatticeComponents:
    """Components of a stored field's nodes, joined across faces.

    ``labels``: 0 outside the set, k = 1..count in component k, numbered by
    decreasing size; ``sizes``: nodes per component; ``measure``: area (b²)
    or hypervolume (b²·rad) of one node; ``spacing``: the field's node
    spacing in x and y (b), the resolution of this description."""

    labels: np.ndarray
    sizes: np.ndarray
    measure: float
    spacing: float

    @property
    def count(self) -> int:
        return len(self.sizes)

    @property
    def areas(self) -> np.ndarray:
        """Area (or hypervolume) of each component, largest first."""
        return self.sizes * self.measure


def _face_edges(shape, periodic: bool):
    """(a, b): flat indices of nodes that share a face, along every axis (axis 0 wrapping when ``periodic``)."""
    index = np.arange(int(np.prod(shape))).reshape(shape)
    ea, eb = [], []
    for axis in range(len(shape)):
        ea.append(np.delete(index, -1, axis=axis).ravel())
        eb.append(np.delete(index, 0, axis=axis).ravel())
        if periodic and axis == 0 and shape[0] > 2:
            ea.append(index[-1].ravel())
            eb.append(index[0].ravel())
    return np.concatenate(ea), np.concatenate(eb)


def _labelled(mask, periodic, measure, spacing) -> LatticeComponents:
    ea, eb = _face_edges(mask.shape, periodic)
    roots = cell_kernels.components(mask.ravel(), ea, eb)
    inside = roots >= 0
    found, inverse, sizes = np.unique(roots[inside], return_inverse=True, return_counts=True)
    order = np.argsort(-sizes, kind="stable")
    rank = np.empty(len(found), np.int32)
    rank[order] = np.arange(1, len(found) + 1, dtype=np.int32)
    labels = np.zeros(mask.size, np.int32)
    labels[inside] = rank[inverse]
    return LatticeComponents(labels.reshape(mask.shape), sizes[order], float(measure), float(spacing))


def lattice_components(ds: xr.Dataset, which: str = "excluded") -> LatticeComponents:
    """Face-joined components of a stored field's nodes: a description of the field at its node spacing.

    ``which``: "excluded" (positions with no allowed orientation, in the
    plane; a scan or summary), or "allowed" or "entangled" (states in
    (x, y, φ), φ periodic; a scan holding that field). For the number of
    components of the excluded set, use :func:`sesp.certified_components`.
    """
    spacing = float(ds.x[1] - ds.x[0])
    if which == "excluded":
        excluded = (ds.allowed_fraction.values == 0) if "allowed_fraction" in ds else ~ds.allowed.values.any(axis=0)
        return _labelled(excluded, False, cell_area(ds), spacing)
    if which not in ("allowed", "entangled"):
        raise ValueError(f"which must be 'excluded', 'allowed' or 'entangled', got {which!r}")
    if which not in ds:
        raise ValueError(f"the dataset has no {which!r} field: scan with {which}=True")
    measure = cell_area(ds) * 2 * math.pi / ds.sizes["phi"]
    return _labelled(ds[which].values, True, measure, spacing)
