"""sesp: pair configurations of superellipse sector particles.

Which relative positions and orientations two hard, thin superellipse sector
particles (SeSPs) may take, how much area one excludes from the other, and how
the allowed space changes shape as the opening closes — computed on a regular
(x, y, φ) grid with exact cross-checks.
"""

from ._version import __version__
from .grid import Grid
from .io import SespFileError, load, save
from .measures import (
    closed_excluded_area,
    convex_excluded_area,
    excluded_area,
    excluded_area_error,
    kinematic_integral,
    normalized_excluded_area,
    shifted_excluded_area,
)
from .scan import ENGINES, monte_carlo, scan
from .shape import Polyline, SeSP

__all__ = [
    "__version__",
    "SeSP",
    "Polyline",
    "Grid",
    "scan",
    "monte_carlo",
    "ENGINES",
    "excluded_area",
    "excluded_area_error",
    "shifted_excluded_area",
    "normalized_excluded_area",
    "closed_excluded_area",
    "convex_excluded_area",
    "kinematic_integral",
    "save",
    "load",
    "SespFileError",
]
