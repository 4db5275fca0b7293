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
    "check_count",
    "check_segments",
    "check_opening",
    "check_choice",
    "check_samples",
]


def check_positive(name: str, value) -> float:
    """A finite number > 0, as float."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    value = float(value)
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return value


# Lengths sesp accepts, in b: the arithmetic of the kernels (cross products of coordinates, tolerances relative to
# the pair's size) keeps its precision over this range; beyond it results would silently lose digits.
MAX_LENGTH = 1e6
# Shortest segment relative to the particle's size: shorter ones are rounding noise, not geometry.
MIN_SEGMENT_RATIO = 1e-9


def check_range(name: str, value, low: float, high: float, unit: str = "") -> float:
    """A finite number in [low, high]."""
    value = check_positive(name, value) if low > 0 else check_nonnegative(name, value)
    if not low <= value <= high:
        raise ValueError(f"{name} must be in [{low:g}, {high:g}]{unit}, got {value!r}")
    return value


def check_nonnegative(name: str, value) -> float:
    """A finite number >= 0, as float."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    value = float(value)
    if not math.isfinite(value) or value < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return value


def check_count(name: str, value, lo: int, hi: int) -> int:
    """An integer (not a bool) in [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value!r}")
    if not lo <= value <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value}")
    return int(value)


MAX_SEGMENTS = 1 << 16


def check_segments(segments) -> int:
    """The polyline segment count N in [1, 65536]."""
    if isinstance(segments, bool) or not isinstance(segments, (int, np.integer, float)):
        raise ValueError(f"segments must be an integer in [1, {MAX_SEGMENTS}], got {segments!r}")
    if not (math.isfinite(segments) and int(segments) == segments and 1 <= segments <= MAX_SEGMENTS):
        raise ValueError(f"segments must be an integer in [1, {MAX_SEGMENTS}], got {segments!r}")
    return int(segments)


def check_opening(opening) -> float:
    """An opening Ψ in [0, 2π) radians."""
    value = float(opening)
    if not (math.isfinite(value) and 0.0 <= value < 2 * math.pi):
        raise ValueError(f"opening must be in [0, 2π) radians, got {opening!r}")
    return value


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
