"""How hard the certified count works: settings that change its cost, never a decided count."""

from __future__ import annotations

from dataclasses import dataclass, fields

from ..checks import check_count, check_range
from ..kernels.depth import Options


@dataclass(frozen=True)
class Settings:
    """The certified count's cost settings (:func:`sesp.certified_components`).

    None of them is part of the definition of the count: a decided count is
    the same whatever they are (``tests/test_certified.py`` halves and
    doubles each), and the depths reported are certified lower bounds for any
    of them. They set how many cells are split and how long each certificate
    may work; ``depth_tolerance`` and ``search_gain`` also set how close to
    the largest provable depth a reported depth comes.

    Attributes
    ----------
    steps_per_vertex : int
        Intervals of φ a depth walk may take at first, per vertex of the longer polyline (a walk that runs out
        is retried with four times as many).
    most_steps : int
        Intervals of φ a depth walk may take at most.
    candidates : int
        Cells per candidate component at which its depth is proved (those with the largest upper bounds).
    turns : tuple of float
        rad: the steps of the search over φ for a larger clearance at an allowed centre.
    subcells : int
        Squares per side on which a rim cell is shown to hide no component.
    nearest : int
        Certified and allowed disks nearest a cell that bound its depth or show it searched.
    tallest : int
        Cells per candidate from which allowed points are sought, per round.
    rays : int
        Directions along which allowed points are sought from each such cell.
    probes : int
        Halvings of each ray.
    depth_tolerance : float
        Relative: a depth is proved to within a factor 1 + this of the largest the certificate proves.
    search_gain : float
        Relative: the search for a deeper point of a component moves where it gains a factor 1 + this.
    proof_depth : float
        b: the depth proved at a centre to show it excluded without its exact windows (any length > 0 would).
    fallback_steps : int
        Intervals of φ a walk at ``proof_depth`` may take before the exact windows decide the position.
    long_crossings : int
        A run is lengthened to its whole curve only where the curves cross at most this often at one φ.
    least_tip_step : float
        Relative to the depth: two end points' walk gives up on turns that move curve 2 less than this.
    max_crossings : int
        Crossings of the polylines at one φ beyond which a depth walk gives up (the windows then decide).
    samples : int
        Evenly spaced orientations at which a thick pair's centre that is neither allowed at its hint nor
        proved excluded is tried before the exact windows.
    """

    steps_per_vertex: int = 4
    most_steps: int = 4096
    candidates: int = 4
    turns: tuple = (0.1, 0.03, 0.01, 0.003, 0.001)
    subcells: int = 4
    nearest: int = 6
    tallest: int = 16
    rays: int = 32
    probes: int = 12
    depth_tolerance: float = 1e-3
    search_gain: float = 3e-3
    proof_depth: float = 1e-9
    fallback_steps: int = 64
    long_crossings: int = 16
    least_tip_step: float = 1e-6
    max_crossings: int = 1024
    samples: int = 32

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "turns":
                if not value:
                    raise ValueError("turns must list at least one angle in (0, π] rad")
                object.__setattr__(self, "turns", tuple(check_range("turns", t, 1e-12, 3.2, " rad") for t in value))
            elif f.type == "int":
                object.__setattr__(self, f.name, check_count(f.name, value, 1, 1 << 24))
            else:
                object.__setattr__(self, f.name, check_range(f.name, value, 1e-15, 1.0))

    @property
    def depth_ratio(self) -> float:
        """A depth is proved to within this factor of the largest the certificate proves."""
        return 1.0 + self.depth_tolerance

    @property
    def search_ratio(self) -> float:
        """The search for a deeper point moves where it gains this factor."""
        return 1.0 + self.search_gain

    def walk_options(self, tips: int) -> Options:
        """The depth kernels' options (:data:`sesp.kernels.depth.Options`): pairs r apart lengthened; two end
        points tried where ``tips`` (0 never, 1 where no pair of runs holds, 2 at every step)."""
        return Options(
            self.max_crossings, self.long_crossings, self.fallback_steps, self.least_tip_step, int(tips), True
        )
