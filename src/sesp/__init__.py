"""sesp: pair configurations of superellipse sector particles.

Which relative positions and orientations two hard, thin superellipse sector
particles (SeSPs) may take, how much area one excludes from the other, and how
the allowed space changes shape as the opening closes — computed on a regular
(x, y, φ) grid with exact cross-checks.

The public API is this module's ``__all__``: one call per question. The
other estimators of A_ex and the field's own measures are in
:mod:`sesp.measures`, the position classes in :mod:`sesp.regions`, the
orientations at one position in :mod:`sesp.orientations`, virial
coefficients in :mod:`sesp.virial`, phase behaviour in :mod:`sesp.onsager`;
``docs/design.md`` maps the modules behind them.
"""

from . import (
    certified,
    dataset,
    exact,
    field,
    measures,
    onsager,
    orientations,
    plot,
    regions,
    topology,
    version,
    virial,
)
from .analysis import analyze
from .certified import Certified, certified_components
from .dataset import SespFileError
from .field import overlaps, scan
from .grid import Grid
from .io import load, save
from .measures import excluded_area
from .pair import Pair
from .regions import classify
from .report import describe
from .shape import Polyline, SeSP
from .topology import Transitions, transitions

__version__ = version.__version__

__all__ = [
    "__version__",
    # particles, pairs and grids
    "SeSP",
    "Polyline",
    "Pair",
    "Grid",
    # the field of allowed states, the overlap test state by state, and one analysis of a pair
    "scan",
    "overlaps",
    "analyze",
    # the answers, one call each
    "excluded_area",
    "classify",
    "certified_components",
    "transitions",
    "Certified",
    "Transitions",
    # files
    "save",
    "load",
    "describe",
    "SespFileError",
    # modules
    "certified",
    "dataset",
    "exact",
    "field",
    "measures",
    "onsager",
    "orientations",
    "plot",
    "regions",
    "topology",
    "virial",
]
