"""Argument checks shared by every public function: one message style, one place.

Each check returns the value converted to its canonical type, or raises
``ValueError`` naming the parameter and the allowed range.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "check_range",
    "check_nonnegative",
    "check_positive",
    "check_finite",
    "check_count",
    "check_segments",
    "check_opening",
    "check_rtol",
    "check_choice",
    "check_samples",
    "check_resolution",
    "check_count_scale",
]


def _number(value, said: str) -> float:
    """``value`` as a finite float, or ``ValueError(said)``: a bool, a string or NaN is no number."""
    if isinstance(value, bool):
        raise ValueError(said)
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(said) from None
    if not math.isfinite(number):
        raise ValueError(said)
    return number


def check_positive(name: str, value, unit: str = "") -> float:
    """A finite number > 0, as float (``unit``, e.g. " (b^-2)", said after the range)."""
    said = f"{name} must be a finite number > 0{unit}, got {value!r}"
    if _number(value, said) <= 0:
        raise ValueError(said)
    return float(value)


# Lengths sesp accepts, in b: the arithmetic of the kernels (cross products of coordinates, tolerances relative to
# the pair's size) keeps its precision over this range; beyond it results would silently lose digits.
MAX_LENGTH = 1e6
# The largest particle, in b (its semi-axes, thickness and vertices): a pair of two, with its contact distance,
# then reaches at most 3e5 b, so that its default grid (half-width about its reach) is one MAX_LENGTH accepts.
MAX_PARTICLE = MAX_LENGTH / 10
# The certified count's cells along the excluded set's edges are about the rim wide, so they number from about
# the pair's reach over the rim to ten times it (benchmarks/README.md, "fine counts"); beyond this ratio a count
# needs millions of cells: tens of minutes or more on two cores.
MAX_REACH_PER_RIM = 1e6
# Shortest segment relative to the particle's size: shorter ones are rounding noise, not geometry.
MIN_SEGMENT_RATIO = 1e-9


def check_range(name: str, value, low: float, high: float, unit: str = "") -> float:
    """A finite number in [low, high], as float (``unit`` said after the range)."""
    said = f"{name} must be in [{low:g}, {high:g}]{unit}, got {value!r}"
    if not low <= _number(value, said) <= high:
        raise ValueError(said)
    return float(value)


def check_nonnegative(name: str, value, unit: str = "") -> float:
    """A finite number >= 0, as float (``unit`` said after the range)."""
    said = f"{name} must be a finite number >= 0{unit}, got {value!r}"
    if _number(value, said) < 0:
        raise ValueError(said)
    return float(value)


def check_finite(name: str, values, unit: str = "", at=None) -> np.ndarray:
    """An array of finite numbers (no NaN, no inf), as float; ``at`` (a format and the values along the first
    axis, e.g. ``("phi = {:.6g}°", degrees)``) says where the first non-finite value is."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be finite numbers{unit}, got {values!r}") from None
    bad = ~np.isfinite(array)
    if bad.any():
        where = ""
        if at is not None:
            first = np.argwhere(bad)[0]
            where = ", the first at " + at[0].format(at[1][first[0]])
        raise ValueError(f"{name} must be finite{unit} everywhere: {int(bad.sum())} of {array.size} values are "
                         f"NaN or inf{where}")  # fmt: skip
    return array


def check_count(name: str, value, lo: int, hi: int, unit: str = "") -> int:
    """An integer (not a bool) in [lo, hi] (``unit``: what it counts, said after the range)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}]{unit}, got {value!r}")
    if not lo <= value <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}]{unit}, got {value}")
    return int(value)


MAX_SEGMENTS = 1 << 16


def check_segments(segments) -> int:
    """The polyline segment count N in [1, 65536]."""
    if isinstance(segments, bool) or not isinstance(segments, (int, np.integer, float)):
        raise ValueError(f"segments must be an integer in [1, {MAX_SEGMENTS}], got {segments!r}")
    if not (math.isfinite(segments) and int(segments) == segments and 1 <= segments <= MAX_SEGMENTS):
        raise ValueError(f"segments must be an integer in [1, {MAX_SEGMENTS}], got {segments!r}")
    return int(segments)


def check_opening(opening, *, degrees: bool = False) -> float:
    """An opening Ψ in [0, 2π) radians (``degrees``: in [0, 360) degrees, as the command line takes it)."""
    top, unit = (360.0, "degrees") if degrees else (2 * math.pi, "radians")
    said = f"opening must be in [0, {'360' if degrees else '2π'}) {unit}, got {opening!r}"
    try:
        value = float(opening)
    except (TypeError, ValueError):
        raise ValueError(said) from None
    if isinstance(opening, bool) or not (math.isfinite(value) and 0.0 <= value < top):
        raise ValueError(said)
    return value


RTOLS = (1e-12, 0.5)  # relative error bars a refinement can be asked for


def check_rtol(rtol, what: str, name: str = "rtol") -> float | None:
    """A relative error bar to refine to, in [1e-12, 0.5] (``what``: of which quantity; ``name``: the parameter),
    or None (no refinement)."""
    if rtol is None:
        return None
    return check_range(name, rtol, *RTOLS, f" (relative error bar of {what}) or None")


def check_choice(name: str, value, choices) -> str:
    """One of ``choices``."""
    if value not in choices:
        raise ValueError(f"{name} must be one of {tuple(choices)}, got {value!r}")
    return value


def check_samples(samples) -> int:
    """A sample count >= 1."""
    if isinstance(samples, bool) or int(samples) != samples or samples < 1:
        raise ValueError(f"samples must be an integer >= 1, got {samples!r}")
    return int(samples)


# The certified count's lengths (b) and base grid: below 1e-9 b a count's cells would outnumber memory long before
# it finished; above 1 b nothing of a particle of size ~1 b is resolved.
RESOLUTIONS = (1e-9, 1.0)
BASES = (4, 4096)


def check_count_scale(reach: float, rim: float) -> None:
    """Refuse, before any work, a certified count whose reach (b) over its rim (b) exceeds MAX_REACH_PER_RIM:
    its cells would number that ratio or more, tens of minutes of work or more."""
    if reach / rim > MAX_REACH_PER_RIM:
        raise ValueError(
            f"rim must be at least {reach / MAX_REACH_PER_RIM:.3g} b for this pair (reach {reach:.3g} b): the count's"
            f" cells along the edges are about the rim wide, so a rim of {rim:.3g} b would need about"
            f" {reach / rim:.1e} of them or more (tens of minutes or more); raise the rim (or the resolution)"
        )


def check_resolution(resolution, rim=None, base=None) -> None:
    """The certified count's ``resolution`` ε (a length in [1e-9, 1] b), ``rim`` (None, or a length in [ε, 1] b)
    and ``base`` (None, or a whole number of cells in [4, 4096]): the one check of each, for Python and the
    command line alike."""
    low, high = RESOLUTIONS
    resolution = check_range("resolution", resolution, low, high, " b")
    if rim is not None:
        check_range("rim", rim, resolution, high, f" b (from the resolution, {resolution:g} b)")
    if base is not None:
        check_count("base", base, *BASES, " cells")
