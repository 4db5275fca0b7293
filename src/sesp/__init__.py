"""sesp: pair configurations of superellipse sector particles.

Which relative positions and orientations two hard, thin superellipse sector
particles (SeSPs) may take, how much area one excludes from the other, and how
the allowed space changes shape as the opening closes — computed on a regular
(x, y, φ) grid with exact cross-checks.

The public API is this module's ``__all__``; ``docs/design.md`` maps the
modules behind it.
"""

from . import exact, onsager, plot, topology, version, virial
from .analysis import analyze
from .certified import Certified, certified_components
from .dataset import SespFileError, cell_area, grid_of, pair_of
from .field import ENGINES, iter_slices, monte_carlo, reduce, scan
from .grid import Grid
from .io import load, save
from .measures import (
    closed_excluded_area,
    convex_excluded_area,
    excluded_area,
    kinematic_integral,
    lattice_excluded_area,
    lattice_excluded_area_error,
    normalized_excluded_area,
    scanline_excluded_area,
    shifted_excluded_area,
    smooth_excluded_area,
)
from .orientations import allowed_orientations, blocked_orientations, widest_window
from .pair import Pair
from .reductions import Reduction
from .regions import CLASSES, classify, position_summary, summarize
from .report import describe
from .shape import Polyline, SeSP
from .topology import LatticeComponents, Transitions, lattice_components, transitions

__version__ = version.__version__

__all__ = [
    "__version__",
    # particles, pairs and grids
    "SeSP",
    "Polyline",
    "Pair",
    "Grid",
    # the field and its reductions
    "scan",
    "reduce",
    "iter_slices",
    "Reduction",
    "analyze",
    "monte_carlo",
    "ENGINES",
    # measures
    "excluded_area",
    "lattice_excluded_area",
    "lattice_excluded_area_error",
    "scanline_excluded_area",
    "smooth_excluded_area",
    "shifted_excluded_area",
    "normalized_excluded_area",
    "closed_excluded_area",
    "convex_excluded_area",
    "kinematic_integral",
    # positions and orientations
    "CLASSES",
    "summarize",
    "classify",
    "position_summary",
    "allowed_orientations",
    "blocked_orientations",
    "widest_window",
    # topology
    "certified_components",
    "Certified",
    "transitions",
    "Transitions",
    "lattice_components",
    "LatticeComponents",
    # files and datasets
    "save",
    "load",
    "SespFileError",
    "grid_of",
    "pair_of",
    "cell_area",
    "describe",
    # modules
    "exact",
    "onsager",
    "plot",
    "topology",
    "virial",
]
