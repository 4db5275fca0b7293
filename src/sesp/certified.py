"""Components of the excluded set at a stated resolution, certified on both sides, exact in φ.

Definition. The depth p(t) of a translation t is its distance (b) to the
nearest allowed translation (one at which some orientation φ keeps the two
particles apart). At resolution ε the excluded set is eroded by ε:
E_ε = {t : p(t) ≥ ε}. The count is the number of components of E_ε that
reach a depth of ε + rim: a single-point pinch (the ASP's centre) always
separates, a neck narrower than 2ε separates, and a component whose deepest
point is shallower than ε + rim is not counted. In the language of
persistence (Edelsbrunner and Harer): the components of the superlevel sets
of p born deeper than ε + rim that have not died at ε. The rim is 1e-3 b by
default, or ε or the polylines' departure from the smooth curves
(:attr:`sesp.Pair.departure`) where either is larger: a body thinner than
the departure may be the polylines' own, not the particle's.

Certificates. The reach box is cut into a quadtree of square cells. A cell
is *in* where its centre is proved ε + h deep (h its half-diagonal;
:mod:`sesp.kernels.depth`), *out* where an upper bound on the depth anywhere
in it (from allowed points nearby, exact in φ) is below ε, *undecided*
otherwise. Every component of E_ε lies in one component of in ∪ undecided
cells (a candidate); every certified part (in-cells joined where they touch
or their certified disks meet) lies in one component of E_ε. A candidate is
*counted* where a point of it is proved ε + rim deep, *shallow* where every
upper bound on it is below ε + rim. ``low`` counts the counted candidates,
``high`` adds up the parts of those not shallow that may each be a component
of their own (1 for a candidate without a part). Cells are split only where
that could change the bracket, down to cells of side ε/4, and the rims are
searched to ``rim``: a point deeper than ε + d at a distance d from a
certified disk joins that disk's part (the depth is 1-Lipschitz), so every
component deeper than ε + rim is found and the decided count does not depend
on the cells. A SeSP pair is symmetric about the x axis, exactly, so each
cell below it is decided as its mirror image.

The steps are :mod:`sesp._certify`'s; their cost settings, :class:`Settings`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ._certify.centres import allowed
from ._certify.leaves import IN, OUT, UNDECIDED
from ._certify.pipeline import count
from ._certify.problem import prepare
from ._certify.settings import Settings
from .checks import check_count_scale, check_resolution
from .pair import as_pair
from .shape import DEFAULT_SEGMENTS
from .units import dimensionless, quantity

__all__ = [
    "RESOLUTION", "RIM", "BASE", "Settings", "Certified", "CertifiedComponent", "certified_components",
    "allowed_positions", "OUT", "IN", "UNDECIDED",
]  # fmt: skip

RESOLUTION = 1e-5  # b: the default ε, the erosion length of the count
RIM = 1e-3  # b: the default rim, at least (a component is counted from ε + rim deep; rims are searched to it)
BASE = 64  # cells along each side of the reach box before refinement
COMPONENTS_KEPT = 4  # components stored by :meth:`Certified.to_dataset`, deepest first


@dataclass(frozen=True)
class CertifiedComponent:
    """One candidate: a component of in ∪ undecided cells.

    ``parts``: certified parts in it that may each be a counted component (1: one component of E_ε; 0: none
    certified; more: its joins undecided). ``depth`` and ``top`` (b): certified lower and upper bounds on its
    largest depth (inscribed radius). ``area`` (b²): its in-cells, a lower bound on the area of E_ε there;
    ``area_bound``: all its cells, an upper bound. ``box``: (xmin, xmax, ymin, ymax), b. ``departure`` (b): the
    polylines' departure from the smooth curves; ``bar`` (b): the depth from which a component is counted
    (resolution + rim); ``point`` (x, y), b: where its depth is proved (where none is, its cell of largest upper
    bound on the depth)."""

    parts: int
    depth: float
    area: float
    area_bound: float
    box: tuple
    departure: float = 0.0
    top: float = math.inf
    bar: float = 0.0
    point: tuple = (math.nan, math.nan)

    @property
    def counted(self) -> bool:
        """Certified at least ``bar`` deep: it holds a counted component."""
        return self.parts > 0 and self.depth >= self.bar

    @property
    def shallow(self) -> bool:
        """Certified shallower than ``bar`` everywhere: it holds no counted component."""
        return self.top < self.bar

    @property
    def decided(self) -> bool:
        return self.shallow or (self.parts == 1 and self.counted)

    def tag(self) -> str:
        """A few words for a legend: "" for one counted component, else what is undecided or why it is not
        counted; † where it is shallower than the polylines' departure from the curves."""
        if self.shallow:
            said = "not counted: shallow"
        elif self.decided:
            said = ""
        elif not self.parts:
            said = "undecided: no certified part"
        elif self.parts > 1:
            said = f"undecided: {self.parts} parts"
        else:
            said = "undecided: depth"
        return " ".join(w for w in (said, "†" if self.depth < self.departure else "") if w)

    def why(self) -> str:
        """In words: one component, or why it is not counted or not decided."""
        if self.shallow:
            said = f"not counted: at most {self.top:.3e} b deep, less than resolution + rim ({self.bar:.3e} b)"
        elif not self.parts:
            said = "no cell of it is certified deeper than the resolution: at most about the resolution deep, or none"
        elif self.parts > 1:
            said = f"{self.parts} certified parts whose joins were not decided down to the floor"
        elif not self.counted:
            said = (
                f"{self.depth:.3e} to {self.top:.3e} b deep: whether it reaches resolution + rim "
                f"({self.bar:.3e} b) was not decided down to the floor"
            )
        else:
            said = "one component"
        if self.depth < self.departure and not self.shallow:
            said += (
                f"; shallower than the polylines' departure from the curves ({self.departure:.1e} b): a feature of "
                "the polylines, not resolved for the smooth particle (more segments resolve it)"
            )
        return said


@dataclass
class Certified:
    """The count of excluded components at resolution ``resolution`` (b), as a bracket ``low`` ≤ count ≤ ``high``.

    ``rim`` (b): a component is counted where it reaches ``resolution +
    rim`` in depth (and rims are searched to ``rim``, so none that deep is
    missed); shallower ones are not counted (listed where a cell of them is
    certified at least ``resolution`` deep). ``floor`` (b): the smallest cell
    side reached. ``components``: one :class:`CertifiedComponent` per
    candidate listed, deepest first. ``evaluations``: cells evaluated;
    ``cells``: per leaf, x, y, side (b), status (0 out, 1 in, 2 undecided)
    and component (its index in ``components``, −1 for none)."""

    low: int
    high: int
    resolution: float
    rim: float
    floor: float
    components: list = field(default_factory=list)
    evaluations: int = 0
    seconds: float = 0.0
    cells: dict = field(default_factory=dict, repr=False)

    def to_dict(self) -> dict:
        """The result as plain numbers (lengths in b, areas in b²), for JSON."""
        return {
            "count": self.count, "count_low": self.low, "count_high": self.high,
            "resolution": self.resolution, "rim": self.rim, "floor": self.floor,
            "units": {"lengths": "b", "areas": "b^2"}, "cells": self.evaluations, "seconds": self.seconds,
            "components": [
                {"parts": c.parts, "depth": c.depth, "top": c.top, "area": c.area, "area_bound": c.area_bound,
                 "box": list(c.box), "point": list(c.point), "counted": c.counted, "departure": c.departure,
                 "bar": c.bar, "status": c.why()}
                for c in self.components
            ],
        }  # fmt: skip

    @classmethod
    def from_dict(cls, said: dict) -> Certified:
        """The result :meth:`to_dict` wrote (without its cells)."""
        components = [
            CertifiedComponent(int(c["parts"]), float(c["depth"]), float(c["area"]), float(c["area_bound"]),
                               tuple(map(float, c["box"])), float(c["departure"]), float(c["top"]), float(c["bar"]),
                               tuple(map(float, c["point"])))
            for c in said["components"]
        ]  # fmt: skip
        return cls(int(said["count_low"]), int(said["count_high"]), float(said["resolution"]), float(said["rim"]),
                   float(said["floor"]), components, int(said["cells"]), float(said["seconds"]))  # fmt: skip

    def to_dataset(self, kept: int = COMPONENTS_KEPT) -> xr.Dataset:
        """The count's bracket, rim and the ``kept`` deepest components (NaN-padded) as labelled variables: the
        form :func:`sesp.analyze` and sweeps store, from which :meth:`from_dataset` rebuilds the count (without
        its cells)."""
        attrs = {"units": "1", "resolution": self.resolution}  # the resolution in b
        said = f"excluded components at the resolution ({self.resolution:g} b), at least resolution + rim deep"
        ds = xr.Dataset()
        ds["excluded_components"] = xr.DataArray(self.low, attrs={**attrs, "long_name": f"{said} (bracket's low end)"})
        ds["excluded_components_high"] = xr.DataArray(
            self.high, attrs={**attrs, "long_name": f"{said} (bracket's high end)"}
        )
        ds["component_rim"] = xr.DataArray(
            self.rim, attrs=quantity(1, "rim: a component is counted from resolution + rim deep")
        )
        ds["component_floor"] = xr.DataArray(self.floor, attrs=quantity(1, "smallest cell side"))
        listed = self.components[:kept]
        for name, unit, what, long_name in (
            ("component_depth", 1, "depth", "certified depth (inscribed radius, lower bound) of each component"),
            ("component_top", 1, "top", "upper bound on the depth of each component"),
            ("component_area", 2, "area", "certified area (lower bound) of each excluded component"),
            ("component_area_bound", 2, "area_bound", "upper bound on the area of each excluded component"),
            ("component_parts", 0, "parts", "certified parts that may each be a counted component"),
            ("component_departure", 1, "departure", "the polylines' departure from the smooth curves"),
        ):
            values = np.full(kept, np.nan)
            values[: len(listed)] = [getattr(c, what) for c in listed]
            said = f"{long_name}, deepest first"
            attrs = quantity(unit, said) if unit else dimensionless(said)
            ds[name] = xr.DataArray(values, dims="component", attrs=attrs)
        for name, dim, what, long_name in (
            ("component_box", "edge", "box", "box of each component: xmin, xmax, ymin, ymax"),
            ("component_point", "xy", "point", "where each component's depth is proved: x, y"),
        ):
            values = np.full((kept, 4 if dim == "edge" else 2), np.nan)
            if listed:
                values[: len(listed)] = [getattr(c, what) for c in listed]
            ds[name] = xr.DataArray(values, dims=("component", dim), attrs=quantity(1, long_name))
        return ds

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> Certified:
        """The count :meth:`to_dataset` wrote (its listed components; no cells)."""
        bar = float(ds.excluded_components.attrs["resolution"]) + float(ds.component_rim)
        components = [
            CertifiedComponent(int(ds.component_parts[k]), float(ds.component_depth[k]), float(ds.component_area[k]),
                               float(ds.component_area_bound[k]), tuple(map(float, ds.component_box[k].values)),
                               float(ds.component_departure[k]), float(ds.component_top[k]), bar,
                               tuple(map(float, ds.component_point[k].values)))
            for k in range(ds.sizes["component"]) if np.isfinite(float(ds.component_depth[k]))
        ]  # fmt: skip
        return cls(int(ds.excluded_components), int(ds.excluded_components_high),
                   float(ds.excluded_components.attrs["resolution"]), float(ds.component_rim),
                   float(ds.component_floor), components)  # fmt: skip

    @property
    def count(self):
        """The count where the bracket is one number, else None."""
        return self.low if self.low == self.high else None

    @property
    def bracket(self) -> str:
        """The count as text: "2", or "1-2" where undecided."""
        return f"{self.low}" if self.count is not None else f"{self.low}-{self.high}"

    @property
    def headline(self) -> str:
        """The bracket with "(undecided)" where it is not one number: the head of a report or a map's title."""
        return self.bracket + (" (undecided)" if self.count is None else "")

    @property
    def searched(self) -> str:
        """What the count leaves out, in words (the rim beside ε)."""
        return (f"  (counted: components at least {self.resolution + self.rim:.2e} b deep (resolution + rim, rim "
                f"{self.rim:.1e} b); shallower ones are not counted; --rim or rim= lowers the rim)")  # fmt: skip

    def __str__(self):
        lines = [f"excluded components at resolution {self.resolution:.1e} b: {self.headline}", self.searched]
        for k, c in enumerate(self.components, 1):
            x0, x1, y0, y1 = c.box
            lines.append(
                f"  {k}: depth >= {c.depth:.3e} b, area {c.area:.4e} b^2 (<= {c.area_bound:.4e}), "
                f"x {x0:+.4f}..{x1:+.4f}, y {y0:+.4f}..{y1:+.4f} b: {c.why()}"
            )
        return "\n".join(lines)


def certified_components(
    particle,
    other=None,
    *,
    resolution: float = RESOLUTION,
    rim: float | None = None,
    base: int = BASE,
    segments: int = DEFAULT_SEGMENTS,
    settings: Settings | None = None,
    progress: bool = True,
) -> Certified:
    """The excluded components of a pair at resolution ``resolution`` (b), certified on both sides, exact in φ.

    ``particle``/``other`` as for :func:`sesp.scan` (a Pair is taken as is);
    ``segments`` per polyline; ``rim`` (b; default 1e-3 b, or ``resolution``
    or the polylines' departure from the curves where either is larger): a
    component is counted where it is at least ``resolution + rim`` deep (a
    lower rim counts shallower components and costs more); ``base``: cells
    along each side at first; ``settings``: the cost settings
    (:class:`Settings`; a decided count does not depend on them); ``progress``:
    a progress bar once the count has run 2 s (default; False: none). See
    the module text for the definition.

    Examples
    --------
    >>> import math
    >>> from sesp import SeSP
    >>> found = certified_components(SeSP(n=2, opening=math.radians(200)), resolution=1e-3)
    >>> found.count
    0
    """
    check_resolution(resolution, rim, base)
    pair = as_pair(particle, other, segments=segments)
    rim = max(resolution, RIM, pair.departure) if rim is None else rim
    check_count_scale(pair.reach, rim)
    start = time.perf_counter()
    got = count(pair, resolution, rim, int(base), Settings() if settings is None else settings, progress)
    departure, bar = pair.departure, resolution + got.rim  # departure: measured once, on the dense arc table
    components = [
        CertifiedComponent(int(p), float(d), float(a), float(ab), tuple(map(float, box)), departure, float(t), bar,
                           tuple(map(float, point)))
        for p, d, t, a, ab, box, point in zip(got.parts, got.depth, got.top, got.area, got.area_bound, got.box,
                                              got.point)
    ]  # fmt: skip
    low = sum(1 for c in components if c.counted)
    high = sum(max(c.parts, 1) for c in components if not c.shallow)
    return Certified(
        low, high, resolution, got.rim, got.floor, components, got.evaluations, time.perf_counter() - start,
        cells=got.cells,
    )  # fmt: skip


def allowed_positions(particle, x, y, *, other=None, hint=None, segments: int = DEFAULT_SEGMENTS):
    """(allowed, phi): whether each translation (x, y) (b) is allowed, decided as the certified count decides a
    cell's centre, and an orientation (rad) allowed there (NaN where not allowed).

    Allowed where the curves keep apart at ``hint`` (rad, per position; NaN or None: no hint), excluded where
    the depth certificate proves the position excluded, the exact windows in φ (:func:`sesp.orientations.widest_window`)
    deciding the rest. Every position the windows allow is allowed; a hint also finds allowed positions whose
    windows are narrower than the windows resolve (the apex of a pinch's allowed wedge)."""
    pair = as_pair(particle, other, segments=segments)
    x, y = (np.atleast_1d(np.asarray(v, dtype=float)).ravel() for v in (x, y))
    hint = np.full(len(x), np.nan) if hint is None else np.asarray(hint, dtype=float).ravel()
    problem = prepare(pair, RESOLUTION, max(RESOLUTION, RIM, pair.departure), BASE, Settings())
    return allowed(problem, x, y, hint)
