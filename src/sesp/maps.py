"""Adaptive maps of the excluded set, exact in φ, and the components found on them.

Classifying a cell
------------------
At a position t the blocked orientations are a finite union of φ intervals
(:mod:`sesp.orientations`): the widest allowed window W(t) is 0 exactly on
the excluded set E. A map samples W at the centres of square cells of side h
and sorts each cell into one of three kinds:

* **certified allowed**: at the centre, at the middle of its widest window,
  the two curves are farther apart than the contact distance plus the
  cell's half-diagonal h/√2. Moving particle 2 by less than that keeps
  them apart at that orientation, so every position of the cell is
  allowed: the cell holds no point of E. This is a proof (up to rounding).
* **excluded node**: W = 0 at the centre: a point of E, found exactly.
* **uncertain**: neither (near the boundary of E, or where every allowed
  orientation leaves the curves close, as in entangled positions).

The certificate is one-sided. E lies in the union of the cells that are not
certified, so parts of that union that do not touch one another hold
different components of E; but that a cell is excluded throughout is never
proven: excluded is what W = 0 finds at nodes. A component is reported only
where an excluded node was found inside it, so a component thinner than the
finest cells it was looked for with (the floor) can be missed. On a window
at the floor one excluded node is enough (coarser windows leave parts under
two nodes thick to the finer ones): such a part is counted, and reported
``floor_limited`` (its count is the floor's), as is any component thinner
than ``RESOLVED_PEAK`` of the floor's cells. So is a component that, on a
window at the floor, holds two deep parts (at least two nodes deep) joined
only through thinner nodes, or a thin part longer than four times its depth
beyond them: on those cells a pinch one node wide cannot be told from a
waist. ``touches_floor`` says less: some part of the component reached the
floor (a thick body's tapering tip does), which leaves its count settled.

Nor does an excluded node say how deep in E it lies: an allowed sliver
thinner than the cells that no node falls in is invisible, and the bodies on
either side of it are seen as one. The ASP's lens and body, for small Ψ, are
parted only by two allowed crescents at most Ψ·b wide, so the opening below
which a map sees them as one depended on the base grid (0.3° to 0.9° on 128
and 97 cells). Where a sliver passed through a node of the base window, that
node is allowed and enclosed by E, and the channel is followed from it
(:mod:`sesp.channels`): a chain of overlapping disks, each proven allowed by
the clearance certificate, both ways until the channel is as wide as the
base cells, narrower than a tenth of the floor, or closed. The nodes whose
cells meet the chain are left out of E when the components are counted, on
every window, and each is given, for the areas, to a component beside it on
its own side of the chain: the bodies either side are then apart on every
grid up to where the chain ends (the ASP's lens and body at Ψ = 0.3125° on
97 and 128 cells, where the crescents are 0.0055 b wide, their areas within
1% of the exact lens, ``tests/test_maps.py``). A sliver found on a finer
window is not followed; a component that still encloses one is marked
(``MapComponent.encloses_slivers``: it may be more than one).
The refinement never loses such a node: ``zoom`` is odd, so the centre of
each refined cell is a node of the finer window, classified again with the
same result. An allowed slit that a coarse node fell in stays open on every
finer window, down to where the finer nodes see its width. For n = 8 at
Ψ = 5° an allowed wedge from the particle's centre, 1e-3 b wide 0.1 b up,
parts the lens from the body. Every base grid, even or odd, has a row and
a column of nodes on the axes, where the pinches and wedges of a
mirror-symmetric pair's excluded set lie: the column on x = 0 falls in
that wedge (an even grid without it found lens and body as one, unmarked,
at Ψ = 2.5°). With a zoom of 4 (whose finer nodes straddle a coarse node)
the finer windows closed it, and the two were one up to Ψ = 6°.

The map is of the pair of polylines (``segments`` per curve), not of the
curves: a polyline departs from its curve by up to about (s/2)²·κ/2 (s the
segment length, κ the curvature), 1.9e-5 b for the ASP with 256 segments
near Ψ = π. Parts of E thinner than that are the polylines'. The ASP's lens
at Ψ = 179.375° (inscribed radius 1 − sin(Ψ/2) = 1.5e-5 b) is there with
1024 segments and not with 256. So a component whose inscribed radius is
smaller than the two polylines' departures summed (:attr:`sesp.Pair.departure`)
is marked unresolved (:meth:`ExcludedMap.limit`), as is one seen only at the
floor, and, for a mirror-symmetric pair, one joined so that the partition
is its own mirror image, as the set's is (:func:`mirror_joined`), or whose
mirror image is still not a component (:attr:`ExcludedMap.unmirrored`);
so is a transition in which such a component changes (parts,
joins, appears, vanishes or leaves the axis: :func:`changed_components`
links each component to what overlaps it a step of Ψ away).

Components and the pinch rule
-----------------------------
On each window the excluded nodes are split into components by the
persistence rule of :func:`sesp.topology.components`: two bodies that meet at
a neck narrower than ``ratio`` (0.5) times the smaller one's inscribed radius
are separate, so a single-point pinch (the particle's centre for the ASP)
separates the bodies that touch there. A pinch is detected as such a neck:
where two bodies at least ``RESOLVED_PEAK`` nodes thick meet at a neck
narrower than ``UNDECIDED`` (0.8) times the smaller one's inscribed radius
but not narrow enough to separate them at this resolution (a pinch behind an
allowed wedge of small angle α looks 1/α nodes wide on any grid), the neck
is looked at again on a finer window, until the rule decides it; a neck
wider than that is a waist of one body (a crescent's ridge dips and rises
along it) and joins. So does an undecided neck that the finer window sees
about as wide in b as the coarser one did (at least ``WAIST``, 0.6, of it,
where the cells shrank ``zoom`` times): a pinch behind a wedge keeps its
width in nodes, so its width in b shrinks with the cells, while a waist
narrower than 0.8 of the bodies keeps its width on every window (the n = 4
body at Ψ = 170° on a base of 64 cells, which the floor otherwise split in
two). A neck that the rule decides by less than a node (``NEAR``: s within
a node under ``ratio`` · p) is undecided too, and looked at again: the
distance field is exact to about a node, and a shallow maximum between the
bodies can hide in that node. The n = 4 arrowhead at Ψ = 173.125° on 97
cells was cut so, its wings judged against each other where the finer
windows see a tip between them, joined to each wing by a waist (one body,
as a brute-force raster finds); such a neck is never taken for a waist,
since a narrow neck keeps its width in b on every window.
At the floor an undecided neck keeps the bodies apart:
the finer windows around a neck are small, so the bodies' radii measured in
them stay about as wide as the neck, and a pinch behind a thin wedge (the
ASP's split as Ψ → 0⁺) is never decided. Both bodies are then marked
``floor_limited``: the split is the floor's.

The centre's pinch is certified instead (:func:`centre_pinch`). Where the
particles' centres coincide (t = 0) the position is excluded for every
0 < Ψ < π of the SeSPs tried, and the parts of E left and right of it meet
there in thin wedges along the axis, one node thick on every grid near π:
the rule cannot judge them at any floor. But the column x = 0 above and
below the centre is allowed, and that is proven with clearance disks that
overlap from a tenth of the floor to three base cells. The two sides then
meet near the centre at that single point, so the map leaves the centre's
node out of E (and the column's nodes within the certified stretch, which a
finer window might inherit as excluded), and refines its cell as
uncertain: every base grid and every finer window has a node there, so the
two sides are apart on all of them (the ASP's lens at Ψ = 170° at a floor
of 2e-3 b, one node thick: its own component on 48 and 49 cells, where the
rule saw one with the body, marked ``floor``). Where the column cannot be
certified within ``_CENTRE_PROBES`` positions (the curves' distance along
it grows as κ·|y| with κ under about 1e-3: Ψ below 10° for n = 2, 8, 10, below 5° for n = 4), the rule
judges the centre like any other neck.

Thin parts at the floor are sampled, not followed: a strip thinner than
the floor's cells holds a node only here and there, so it is found as a
chain of specks one or two nodes across, a few cells apart, whose number
and places change with the grid (the n = 4 body's horn tips near
(1.98, ±0.58) b at Ψ = 0.3°: six specks on 128 base cells, none on 97).
So the specks of the floor (components seen only at the floor, thinner
than ``RESOLVED_PEAK`` of its cells) that lie within ``SPECK_GAP`` (8)
floor cells of one another are one part, and a part within that distance
of a thicker component is counted with the nearest one (never with two:
thick bodies are not joined through specks, nor across the centre's
certified pinch); only a part with no component that near is counted on
its own, marked ``floor_limited``.

For a mirror-symmetric pair the partition is made its own mirror image, as
the set's is (:func:`mirror_joined`): the rule judges a neck against the
bodies merged so far, so it can join one of two mirror lobes to a strip on
the axis and part the other (n = 8 at Ψ = 179.0625°); each component is
joined to the one holding most of its mirror image where it lies along the
axis or the two are not each other's mirror image, and marked.

Refinement
----------
A window is refined (looked at again ``zoom`` times finer, on the bounding
box of each cluster of such nodes) where its count is not settled:

* excluded or uncertain nodes farther than ``2·RESOLVED_PEAK`` nodes from
  any excluded node at least ``RESOLVED_PEAK`` nodes deep: thin parts,
  thin components, and uncertain cells that might hide one;
* the undecided necks above.

Nodes near thick parts are settled: their cell's boundary is resolved by the
thick part's own count. The nodes of such clusters within a few cells of a
body (a tip, the rim, a pinch, a thin component beside it) are refined until
the cells are ``_TAPER`` (256) times smaller than the body's inscribed
radius, and then left: a tip or a pinch looks the same at every scale. The
rest of such a cluster, running on away from the body (farther than
``_TIP``, 32, nodes from the body's nodes at least ``RESOLVED_PEAK`` deep,
even where it is joined to the body on these cells), is refined on: it
may hold a thin component (for n = 8 at Ψ = 175°, an island 3e-4 b thick
and 0.48 b long on the axis, behind the body's tail and the pinch at the
centre). So a thin component lying wholly within a few cells of a body and
thinner than a couple of those finest cells (each 1/256 of the body's
inscribed radius) can be missed: that is the maps' blind spot. At 1/64 it
hid the n = 4 arrowhead's tip at Ψ = 174.6875° (3.4e-4 b deep, at the end
of the horns of crescents 0.035 b deep) on a base of 128 cells; 1/256
finds it on 128 and 97 cells and costs about a fifth more positions.
The finer window evaluates only the refined cells (and one cell around
them); each component it finds belongs to the coarser one it shares most
nodes with outside the refined cells, or is new. It joins the other coarser
components it shares nodes with, unless another component of the finer
window belongs to that one (the finer window split them too: the line
between two touching bodies falls a node or two apart on the two windows),
or the rule split the two on the coarser window at a neck it decided and
the piece holds only a sliver of the other (less than ``_SHARED``, a
quarter, of what it holds of its own). A piece that holds much of both saw
them as one body on finer cells: the n = 4 arrowhead at Ψ = 173.75°, whose
wings were split where they were 4 nodes thick. Refinement stops when the
next cells would be smaller than ``floor``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

import numpy as np
import xarray as xr
from scipy import ndimage
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from .channels import meets, same_side, traced_channels
from .checks import check_count, check_range
from .dataset import SespFileError, base_attrs, format_of, pair_attrs, pair_of
from .io import load, save
from .kernels.orientations import widest_windows
from .orientations import ANGLE_GAP, SCREEN_SLACK
from .pair import as_pair
from .progress import progress_bar
from .shape import DEFAULT_SEGMENTS
from .topology import PINCH_RATIO, RESOLVED_PEAK, components, distance_to_complement, opening_family, renumbered
from .units import AREA, LENGTH

__all__ = [
    "MapComponent",
    "ExcludedMap",
    "excluded_map",
    "map_transitions",
    "widest_window",
    "FLOOR",
    "BASE_CELLS",
    "ZOOM",
]

FLOOR = 1e-7  # b: the smallest cell a map refines to
BASE_CELLS = 128  # cells along x and y of the first window, over the pair's reach
ZOOM = 3  # each refinement divides the cell side by this (odd: every node of a window is one of the next)
_PAD = 2  # cells around a refined cluster included in its finer window
_SETTLED = 2 * RESOLVED_PEAK  # nodes from a thick excluded node within which the count is settled
# Nodes of a deep body farther than this from its thick nodes (at least RESOLVED_PEAK deep) are not its rim or
# tip but a thin part running away from it, refined along its length (the n = 8 lens at 168°, see _untapered).
_TIP = 8 * RESOLVED_PEAK
_TAPER = 256.0  # a thick body's thin parts are refined until the cells are this many times smaller than it
MAX_WINDOW = 1 << 22  # nodes of a finer window at most: a larger cluster is left as at the floor
# Smallest inscribed radius (nodes) of a component counted on a window at the floor; coarser windows need
# 2 (thinner is left to the finer windows). At the floor there are none: a part one node thick is counted,
# marked ``floor_limited``, rather than lost.
_FLOOR_PEAK = 1.0
_DEEP = 3.0  # coarse excluded nodes this many nodes inside the set are not classified again when refined
# Necks s below this times the smaller body's inscribed radius p (and above the rule's ratio · p) are looked at
# finer: a pinch behind an allowed wedge of angle α looks 1/α nodes wide on any grid, so refining it shrinks
# s / p; a neck wider than this is a body's own waist (a crescent's ridge dips and rises) and joins.
UNDECIDED = 0.8
# An undecided neck that keeps at least this share of its width (b) when the cells shrink ``zoom`` times is a
# waist of one body (a pinch behind a wedge keeps its width in nodes: its share is about 1 / zoom).
WAIST = 0.6
_SHARED = 0.25  # of its main component's nodes: a finer piece holding this much of another joins it
_THIN = 2.0  # nodes: at the floor, parts less deep than this that join deeper ones are joins the floor cannot judge
# A thin cluster beyond _THIN nodes from the deep part, of more nodes than this times the component's depth
# (nodes), is a thin body joined at the floor, not the part's own tip (a tip narrowing at a half-angle of 14° or
# more is shorter than 4 depths): the ASP's lens at 170° on cells of 0.0032 b, 100 nodes long, 1 thick.
_THIN_TAIL = 4.0
_SLIVER = 2.0  # nodes: an allowed cluster enclosed by a component and no deeper than this is a sliver's trace
_CENTRE_CELLS = 3  # base cells above and below the centre over which the column x = 0 is certified (centre_pinch)
_CENTRE_PROBES = 5000  # positions on that column at most
SPECK_GAP = 8.0  # floor cells: specks of the floor this close to one another or to a component are one part with it


def widest_window(particle, x, y, *, other=None, segments: int = DEFAULT_SEGMENTS) -> tuple:
    """(width, middle): the widest window of allowed orientations at each position, exact in φ (radians).

    ``width`` is 0 exactly where the position is excluded (gaps narrower than
    1e-9 rad count as closed); ``middle`` is the orientation at its centre.
    ``particle``, ``other``, ``segments`` as in :func:`sesp.scan`; ``x``, ``y``
    (b) are broadcast together.
    """
    pair = as_pair(particle, other, segments)
    xs, ys = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    width, middle, _ = widest_windows(
        pair.vertices1, pair.vertices2, xs.ravel(), ys.ravel(), SCREEN_SLACK, ANGLE_GAP, pair.contact
    )
    return width.reshape(xs.shape), middle.reshape(xs.shape)


@dataclass(frozen=True)
class MapComponent:
    """One component of the excluded set on an adaptive map.

    Attributes
    ----------
    area : float
        b²: the cells of its excluded nodes, each at the finest level that
        looked at it (an estimate: the boundary's cells are counted by their
        centres).
    inscribed_radius : float
        b: the largest distance from one of its excluded nodes to a node
        outside it, less half a cell (exact to ± half the cell of that level).
    bbox : (xmin, xmax, ymin, ymax)
        b: of its excluded nodes' cells.
    touches_floor : bool
        Some part of it was seen thinner than ``RESOLVED_PEAK`` nodes on
        cells that could not be refined further (the floor; a thick body's
        tapering tip is enough), or it is one of the components below.
    x, y, cell : ndarray
        Its excluded nodes (b) and their cell sides (b), for plotting.
    encloses_slivers : bool
        It encloses nodes that are not excluded, in clusters no more than
        ``_SLIVER`` nodes from the set on every side: allowed slivers seen
        only where a node happened to fall in them. Slivers thinner than the
        cells may part it (the ASP's lens and body for small Ψ): it may be
        more than one component.
    floor_limited : bool
        Whether it counts as a component is the floor's verdict: it is
        thinner than ``RESOLVED_PEAK`` of the floor's cells (it may be
        thinner than the floor, or not there), or it was kept apart from
        another at a neck still undecided at the floor (it may be joined to
        it), or on cells at the floor it holds a part joined to the rest
        only through nodes under two nodes deep (it may be two). A thick
        body whose tip reaches the floor is not: its count is settled.
    mirror_joined : bool
        It was joined from components that the rule had parted in a way that
        is not its own mirror image, for a mirror-symmetric pair
        (:func:`mirror_joined`): the count is that convention's.
    """

    area: float
    inscribed_radius: float
    bbox: tuple
    touches_floor: bool
    x: np.ndarray = field(repr=False)
    y: np.ndarray = field(repr=False)
    cell: np.ndarray = field(repr=False)
    encloses_slivers: bool = False
    floor_limited: bool = False
    mirror_joined: bool = False

    def as_dict(self) -> dict:
        """JSON-ready: area, inscribed radius, bounding box, floor, sliver and mirror flags."""
        return {
            "area": self.area,
            "inscribed_radius": self.inscribed_radius,
            "bbox": [float(v) for v in self.bbox],
            "touches_floor": self.touches_floor,
            "floor_limited": self.floor_limited,
            "encloses_slivers": self.encloses_slivers,
            "mirror_joined": self.mirror_joined,
        }


MAP_LONG_NAMES = {
    "component": "excluded component (1, 2, ...)",
    "area": "area of the component",
    "inscribed_radius": "inscribed radius of the component",
    "touches_floor": "the component reaches cells of the floor",
    "floor_limited": "the component's count depends on cells of the floor",
    "encloses_slivers": "the component encloses allowed slivers",
    "mirror_joined": "the component was joined to its mirror image",
    "unresolved": "the component is unresolved",
    "bbox": "bounding box of the component",
    "node_x": "x of an excluded node",
    "node_y": "y of an excluded node",
    "node_cell": "cell side of an excluded node",
    "node_component": "component of an excluded node",
    "channel_x": "x of a certified allowed disk",
    "channel_y": "y of a certified allowed disk",
    "channel_radius": "radius of a certified allowed disk",
}


@dataclass(frozen=True)
class ExcludedMap:
    """The excluded set's components on an adaptive map (see the module notes)."""

    components: list
    floor: float
    base_cells: int
    reach: float
    positions: int  # positions classified, over all levels
    finest: float  # b: the smallest cell side used
    departure: float = 0.0  # b: how far the polylines depart from the curves (:attr:`sesp.Pair.departure`)
    zoom: int = ZOOM
    pair: object = field(default=None, repr=False, compare=False)  # the Pair mapped (None: read from a file)
    centre: float = 0.0  # b: the column x = 0 certified allowed this far around the centre's pinch (0: none)
    # certified allowed disks (x, y, radius; b) along the channels followed from the base window's slivers
    disks: np.ndarray = field(default=None, repr=False, compare=False)

    @property
    def channels(self) -> int:
        """How many certified disks the map followed channels with (:mod:`sesp.channels`); 0 for none, or for
        a map saved before channels were followed."""
        return 0 if self.disks is None else len(self.disks)

    @property
    def count(self) -> int:
        return len(self.components)

    @property
    def off_axis(self) -> int:
        """Components wholly above or wholly below the x-axis (their cells' box does not meet y = 0): for a
        pair symmetric under y → −y, the mirror pairs its bodies part into off the axis."""
        return sum(1 for c in self.components if not _on_axis(c))

    def limit(self, component: MapComponent) -> str:
        """What a component may be an artefact of: "floor" (``floor_limited``: thinner than a few of the floor's
        cells, or kept apart or joined at a neck the floor cannot judge), "slivers" (it encloses allowed
        slivers seen at isolated nodes, which may part it), "polylines" (thinner than the polylines depart from
        the curves: it may be theirs, not the curves'), "mirror" (the pair is mirror symmetric and the
        component was joined so that the partition is (``mirror_joined``), or its mirror image is still not one
        of the map's: :attr:`unmirrored`), or "" (resolved)."""
        if component.floor_limited:
            return "floor"
        if component.encloses_slivers:
            return "slivers"
        if component.inscribed_radius < self.departure:
            return "polylines"
        if component.mirror_joined or any(component is c for c in self.unmirrored):
            return "mirror"
        return ""

    @cached_property
    def unmirrored(self) -> tuple:
        """For a mirror-symmetric pair (:attr:`sesp.Pair.mirror_symmetric`), the components whose mirror image
        about the x-axis is not a component of this map; () for any other pair, or a map read without its pair.

        The excluded set of such a pair is its own mirror image (the state (x, −y, −φ) is the state (x, y, φ)
        mirrored), and so is its partition into components: each component is its own mirror image or one of a
        mirror pair. A map whose partition is not its own mirror image judged a neck and its mirror image
        differently (the rule parted one lobe from a body and kept the other: n = 10 at Ψ = 179.6875° on 128
        base cells, before :func:`mirror_joined`), so neither verdict is settled. A component's mirror image is
        taken to be a component when some component's bounding box is the mirrored box to within two base
        cells on each side (boundaries of thick parts are settled by the base cells). The maps join such
        components where their nodes show how (:func:`mirror_joined`); what is left here has no mirror image
        at all (a speck of the floor seen on one side only).
        """
        if self.pair is None or not self.pair.mirror_symmetric:
            return ()
        tolerance = 2 * base_cell(self.reach, self.base_cells)
        boxes = np.array([c.bbox for c in self.components], dtype=float).reshape(-1, 4)
        mirrored = boxes[:, [0, 1, 3, 2]] * np.array([1.0, 1.0, -1.0, -1.0])
        match = np.all(np.abs(mirrored[:, None, :] - boxes[None, :, :]) <= tolerance, axis=2)
        return tuple(c for c, found in zip(self.components, match.any(axis=1)) if not found)

    def dataset(self) -> xr.Dataset:
        """A ``sesp.map`` dataset: per component area, inscribed radius, bounding box, the floor, sliver and
        mirror flags and ``unresolved`` (:meth:`limit` is not ""), largest first; the map's resolution, the
        polylines' ``departure`` (b) and the pair (:func:`sesp.dataset.pair_attrs`) among the attributes; the
        excluded nodes (``node_x``, ``node_y``, ``node_cell``, b, and ``node_component``, over ``node``), so
        that a map read back can be drawn (:func:`sesp.plot.component_map`); and the certified disks of the
        channels followed (``channel_x``, ``channel_y``, ``channel_radius``, b, over ``disk``)."""
        comps = self.components
        box = np.array([c.bbox for c in comps], dtype=float).reshape(-1, 4)
        label = np.concatenate([np.full(len(c.x), k, dtype=np.int32) for k, c in enumerate(comps, start=1)] or [[]])

        def nodes(name):
            return "node", np.concatenate([getattr(c, name) for c in comps] or [[]]).astype(float), dict(LENGTH)

        def flags(name):
            return "component", np.array([getattr(c, name) for c in comps], dtype=bool)

        disks = np.empty((0, 3)) if self.disks is None else self.disks

        attrs = base_attrs("sesp.map") | ({} if self.pair is None else pair_attrs(self.pair))
        attrs |= {name: getattr(self, name) for name in _MAP_ATTRS}
        ds = xr.Dataset(
            {
                "area": ("component", np.array([c.area for c in comps], dtype=float), dict(AREA)),
                "inscribed_radius": (
                    "component", np.array([c.inscribed_radius for c in comps], dtype=float), dict(LENGTH)
                ),
                "touches_floor": flags("touches_floor"),
                "floor_limited": flags("floor_limited"),
                "encloses_slivers": flags("encloses_slivers"),
                "mirror_joined": flags("mirror_joined"),
                "unresolved": ("component", np.array([bool(self.limit(c)) for c in comps], dtype=bool)),
                "bbox": (("component", "side"), box, {**LENGTH, "sides": "xmin xmax ymin ymax"}),
                "node_x": nodes("x"),
                "node_y": nodes("y"),
                "node_cell": nodes("cell"),
                "node_component": ("node", label.astype(np.int32)),
                "channel_x": ("disk", disks[:, 0], dict(LENGTH)),
                "channel_y": ("disk", disks[:, 1], dict(LENGTH)),
                "channel_radius": ("disk", disks[:, 2], dict(LENGTH)),
            },
            coords={"component": np.arange(1, len(comps) + 1)},
            attrs=attrs,
        )  # fmt: skip
        for name, long_name in MAP_LONG_NAMES.items():
            ds[name].attrs.setdefault("units", "1")
            ds[name].attrs["long_name"] = long_name
        return ds

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> ExcludedMap:
        """The map a ``sesp.map`` dataset (:meth:`dataset`) holds, its pair rebuilt from the attributes when they
        describe one. Files written before the nodes were kept give the components without them."""
        label = ds.node_component.values if "node_component" in ds else np.empty(0, dtype=int)

        def nodes(name, k):
            return ds[name].values[label == k] if name in ds else np.empty(0)

        limited = ds.floor_limited.values if "floor_limited" in ds else ds.touches_floor.values  # older files
        joined = ds.mirror_joined.values if "mirror_joined" in ds else np.zeros(ds.sizes["component"], dtype=bool)
        comps = [
            MapComponent(
                float(a), float(r), tuple(float(v) for v in box), bool(f),
                nodes("node_x", k), nodes("node_y", k), nodes("node_cell", k), bool(s), bool(lim), bool(m),
            )
            for k, (a, r, box, f, s, lim, m) in enumerate(zip(
                ds.area.values, ds.inscribed_radius.values, ds.bbox.values.reshape(-1, 4),
                ds.touches_floor.values, ds.encloses_slivers.values, limited, joined,
            ), start=1)
        ]  # fmt: skip
        pair = pair_of(ds) if "particle_kind" in ds.attrs else None
        values = {name: kind(ds.attrs[name]) for name, kind in _MAP_ATTRS.items() if name in ds.attrs}
        disks = None
        if "channel_radius" in ds:  # absent from maps saved before channels were followed
            disks = np.column_stack([ds.channel_x.values, ds.channel_y.values, ds.channel_radius.values])
        return cls(mirror_joined(comps, pair), **values, pair=pair, disks=disks)  # older maps get the join here


# Attributes of a ``sesp.map`` dataset that rebuild its ExcludedMap, with their types.
_MAP_ATTRS = {
    "floor": float,
    "base_cells": int,
    "reach": float,
    "positions": int,
    "finest": float,
    "departure": float,
    "zoom": int,
    "centre": float,  # absent from maps saved before the centre's pinch was certified
}


@dataclass
class _Piece:
    """A component in the making: its excluded nodes (x, y, cell side), peak (b), floor and sliver flags."""

    x: np.ndarray
    y: np.ndarray
    cell: np.ndarray
    peak: float
    floor: bool
    slivers: bool = False
    split: bool = False  # kept apart or joined where the floor cannot judge (MapComponent.floor_limited)

    def joined(self, other: _Piece) -> _Piece:
        return _Piece(
            np.concatenate([self.x, other.x]),
            np.concatenate([self.y, other.y]),
            np.concatenate([self.cell, other.cell]),
            max(self.peak, other.peak),
            self.floor or other.floor,
            self.slivers or other.slivers,
            self.split or other.split,
        )


@dataclass
class _Context:
    pair: object
    floor: float
    zoom: int
    bar: object
    positions: int = 0
    finest: float = math.inf
    centre: float = 0.0  # b: half-length of the column x = 0 certified allowed around the centre's pinch; 0: none
    channels: np.ndarray = field(default_factory=lambda: np.empty((0, 5)))  # certified allowed disks


def excluded_map(
    particle,
    *,
    other=None,
    segments: int = DEFAULT_SEGMENTS,
    base: int = BASE_CELLS,
    floor: float = FLOOR,
    zoom: int = ZOOM,
    progress: bool = False,
) -> ExcludedMap:
    """The components of the excluded set, from an adaptive map exact in φ.

    Parameters
    ----------
    particle, other, segments
        As in :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`).
    base : int
        Cells along x and y of the first window, which spans the pair's reach
        (centres farther apart cannot meet) and at least half a cell more on
        each side, with a node on each axis (module notes).
    floor : float
        Smallest cell side (b) the refinement goes down to.
    zoom : int
        Each refinement divides the cell side by ``zoom`` (odd, 3 to 15: the
        centre of each refined cell is a node of the finer window too).
    progress : bool
        Show a progress bar of the positions classified.

    Returns
    -------
    ExcludedMap
        Components largest first.
    """
    base = check_count("base", base, 8, 4096)
    floor = check_range("floor", floor, 1e-12, 1.0, " b")
    zoom = check_count("zoom", zoom, 3, 15)
    if zoom % 2 == 0:
        raise ValueError(f"zoom must be odd (3, 5, ..., 15): each refined cell's centre is then a node; got {zoom}")
    pair = as_pair(particle, other, segments)
    h = base_cell(pair.reach, base)
    # A node on each axis, for even bases too (one more cell left and below): the pinches and wedges of a
    # mirror-symmetric pair's excluded set lie on them (the wedge at x = 0 that parts lens and body for small Ψ).
    start = -(base // 2 + 0.5) * h
    with progress_bar(None, progress, "map", unit="pos") as bar:
        ctx = _Context(pair, floor, zoom, bar, centre=centre_pinch(pair, floor, _CENTRE_CELLS * h))
        everywhere = np.ones((base, base), dtype=bool)
        pieces = _window(ctx, start, start, h, everywhere, everywhere, None, None, outside=False, first=True)
    found = [_component(p, floor, zoom) for p, _ in pieces if p is not None]
    found = mirror_joined(joined_specks(found, floor, zoom, ctx.centre), pair)
    return ExcludedMap(
        found, floor, base, pair.reach, ctx.positions, ctx.finest, pair.departure, zoom, pair, centre=ctx.centre,
        disks=ctx.channels[:, :3],
    )  # fmt: skip


def base_cell(reach: float, base: int) -> float:
    """Side (b) of the first window's cells: ``base`` of them span twice the pair's ``reach`` and at least half
    a cell more on each side."""
    return 2 * reach / (base - 2)


def _is_speck(component: MapComponent, floor: float, zoom: int) -> bool:
    """Seen only at the floor (its finest cells could not be refined) and thinner than ``RESOLVED_PEAK`` of them."""
    return component.touches_floor and _thin_at_floor(component.inscribed_radius, component.cell, floor, zoom)


def _thin_at_floor(radius, cells, floor, zoom) -> bool:
    """Whether a part of inscribed ``radius`` (b), finest cells at the floor, is under ``RESOLVED_PEAK`` cells."""
    cell = float(cells.min())
    return cell < zoom * floor and radius < RESOLVED_PEAK * cell


def joined_specks(found: list, floor: float, zoom: int = ZOOM, centre: float = 0.0) -> list:
    """``found`` with the specks of the floor joined (module notes, "Components and the pinch rule").

    Specks (:func:`_is_speck`) whose nodes come within ``SPECK_GAP`` floor cells of one another are one
    part; each part within that distance of a component that is not a speck joins the nearest such one.
    Two nodes on either side of the centre's certified column (|y| <= ``centre``, b) are never near. The
    joined components are marked ``touches_floor``; a part of specks alone is ``floor_limited``, and a thick
    component keeps its own mark.
    """
    specks = [k for k, c in enumerate(found) if _is_speck(c, floor, zoom)]
    if not specks:
        return found
    label = np.concatenate([np.full(len(c.x), k) for k, c in enumerate(found)])
    points = np.column_stack([np.concatenate([c.x for c in found]), np.concatenate([c.y for c in found])])
    tree = cKDTree(points)
    parent = list(range(len(found)))

    def root(k):
        while parent[k] != k:
            k = parent[k]
        return k

    nearest = {}  # speck -> (distance, nearest component that is not a speck)
    for k in specks:
        mine = np.flatnonzero(label == k)
        reach = SPECK_GAP * float(found[k].cell.min())
        for i, near in zip(mine, tree.query_ball_point(points[mine], reach)):
            near = np.asarray(near, dtype=np.int64)
            near = near[(label[near] != k) & ~_across_centre(points[i], points[near], centre)]
            for j in near:
                other = int(label[j])
                if other in specks:
                    parent[root(other)] = root(k)
                else:
                    d = float(np.hypot(*(points[j] - points[i])))
                    if d < nearest.get(k, (math.inf, None))[0]:
                        nearest[k] = (d, other)
    groups = {}
    for k in specks:
        groups.setdefault(root(k), []).append(k)
    into = {}
    for members in groups.values():
        best = min((nearest[k] for k in members if k in nearest), default=None, key=lambda v: v[0])
        for k in members:
            into[k] = members[0] if best is None else best[1]
    out = {}
    for k, c in enumerate(found):
        target = into.get(k, k)
        out[target] = c if target not in out else _merged(out[target], c)
    # a body counts with the specks it took in as it did alone; a part of specks alone is the floor's
    return [
        replace(c, touches_floor=True, floor_limited=found[t].floor_limited) if t in into.values() else c
        for t, c in out.items()
    ]


def _across_centre(point, others, centre):
    """Whether the segment from ``point`` to each of ``others`` crosses x = 0 within the certified stretch."""
    if centre <= 0.0:
        return np.zeros(len(others), dtype=bool)
    return (point[0] * others[:, 0] <= 0.0) & (abs(point[1]) <= centre) & (np.abs(others[:, 1]) <= centre)


def _merged(a: MapComponent, b: MapComponent) -> MapComponent:
    """One component of two: areas summed, the larger inscribed radius (a lower bound), boxes and nodes joined,
    each flag set if either's is."""
    box = (min(a.bbox[0], b.bbox[0]), max(a.bbox[1], b.bbox[1]), min(a.bbox[2], b.bbox[2]), max(a.bbox[3], b.bbox[3]))
    return MapComponent(
        a.area + b.area, max(a.inscribed_radius, b.inscribed_radius), box, a.touches_floor or b.touches_floor,
        np.concatenate([a.x, b.x]), np.concatenate([a.y, b.y]), np.concatenate([a.cell, b.cell]),
        a.encloses_slivers or b.encloses_slivers, a.floor_limited or b.floor_limited,
        a.mirror_joined or b.mirror_joined,
    )  # fmt: skip


def mirror_joined(found: list, pair) -> list:
    """``found`` (components of a map of ``pair``), largest first, with the partition made its own mirror image
    about the x-axis where the pair is mirror symmetric (:attr:`sesp.Pair.mirror_symmetric`).

    The excluded set of such a pair is its own mirror image, and so is its partition into components. The
    persistence rule judges a neck against the bodies as merged so far, so where two mirror lobes meet a
    thinner part on the axis (a strip, the n = 8 body's tail near Ψ = π) at mirror necks each passing the
    rule's join test against that part, the first neck joins lobe and strip and the second is judged against
    lobe and strip together, and parts the other lobe: one lobe off the axis, the other holding the strip. So
    each component's mirror image is followed (its nodes mirrored, each weighed by its cell's area, in the
    component whose cell holds it), and the component holding most of it is its twin: a component along the
    axis (:func:`_along_axis`) is its own twin, and the two of a mirror pair off the axis are each other's.
    Where a component's twin is another and it lies along the axis, or its twin's twin is not itself, the
    two are joined, as the rule joins at each neck judged alone; repeated until none is. Two bodies the rule
    parted at a pinch on the axis are left apart: the pinch's nodes go to one of them, which then touches
    the axis only at that point (n = 4's crescents at Ψ = 174.6875°). Joined components are
    marked ``mirror_joined`` (unresolved: the count is that convention's). Components read without their
    nodes are left as they are.
    """
    found = sorted(found, key=lambda c: -c.area)
    if pair is None or not pair.mirror_symmetric or len(found) < 2 or not all(len(c.x) for c in found):
        return found
    while True:
        twins = _mirror_twins(found)
        graph = np.zeros((len(found), len(found)), dtype=bool)
        for k, twin in enumerate(twins):
            if twin is not None and twin != k and (_along_axis(found[k]) or twins[twin] != k):
                graph[k, twin] = True
        if not graph.any():
            return found
        _, group = connected_components(graph, directed=False)
        groups = {}
        for g, c in zip(group, found):
            groups[g] = c if g not in groups else replace(_merged(groups[g], c), mirror_joined=True)
        found = sorted(groups.values(), key=lambda c: -c.area)


def _along_axis(component: MapComponent) -> bool:
    """Whether the component's nodes on the x-axis (y = 0 within half a cell) span at least ``PINCH_RATIO``
    times its inscribed radius along it: a part on the axis, not the point of a pinch (whose nodes go to
    either body the rule parted there: 0.0014 b of a 0.037 b deep crescent of n = 4 at Ψ = 174.6875°, where
    the n = 8 body's tail at 179.0625° spans 0.60 b)."""
    on = np.abs(component.y) < 0.5 * component.cell
    if not on.any():
        return False
    span = component.x[on].max() - component.x[on].min() + component.cell[on].max()
    return bool(span >= PINCH_RATIO * component.inscribed_radius)


def _mirror_twins(found: list) -> list:
    """Per component, the index of the component that holds most of its mirror image (None if none does)."""
    x = np.concatenate([c.x for c in found])
    y = np.concatenate([c.y for c in found])
    cell = np.concatenate([c.cell for c in found])
    label = np.concatenate([np.full(len(c.x), k) for k, c in enumerate(found)])
    distance, nearest = cKDTree(np.column_stack([x, y])).query(np.column_stack([x, -y]), p=np.inf)
    inside = distance <= 0.5 * np.maximum(cell, cell[nearest]) * (1 + 1e-9)
    twins = []
    for k in range(len(found)):
        mine = (label == k) & inside
        share = np.bincount(label[nearest[mine]], weights=cell[mine] ** 2, minlength=len(found))
        twins.append(int(np.argmax(share)) if share.any() else None)
    return twins


def _component(piece: _Piece, floor: float, zoom: int) -> MapComponent:
    half = 0.5 * piece.cell
    bbox = (
        float((piece.x - half).min()),
        float((piece.x + half).max()),
        float((piece.y - half).min()),
        float((piece.y + half).max()),
    )
    thin = piece.floor and _thin_at_floor(piece.peak, piece.cell, floor, zoom)
    return MapComponent(
        float(np.sum(piece.cell**2)), piece.peak, bbox, piece.floor or piece.split, piece.x, piece.y, piece.cell,
        piece.slivers, piece.split or thin,
    )  # fmt: skip


def _classify(ctx, x0, y0, h, evaluate, inherited):
    """(excluded, uncertain) node masks of a window; nodes not in ``evaluate`` take ``inherited`` (excluded)
    and are not uncertain."""
    iy, ix = np.nonzero(evaluate)
    xs = x0 + (ix + 0.5) * h
    ys = y0 + (iy + 0.5) * h
    half_diagonal = h / math.sqrt(2)
    pair = ctx.pair
    width, _, clear = widest_windows(
        pair.vertices1,
        pair.vertices2,
        xs,
        ys,
        SCREEN_SLACK,
        ANGLE_GAP,
        pair.contact,
        np.full(len(xs), 1.001 * half_diagonal),
    )
    ctx.positions += len(xs)
    ctx.finest = min(ctx.finest, h)
    ctx.bar.update(len(xs))
    excluded = np.zeros(evaluate.shape, dtype=bool) if inherited is None else inherited.copy()
    uncertain = np.zeros(evaluate.shape, dtype=bool)
    excluded[iy, ix] = width == 0.0
    uncertain[iy, ix] = (width > 0.0) & (clear - pair.contact <= half_diagonal)
    if ctx.centre > 0.0:  # the centre's node is left out of E, a pinch; its cell (and any inherited) not certified
        column = _centre_column(x0, y0, h, evaluate.shape, ctx.centre)
        uncertain[column] |= excluded[column]
        excluded[column] = False
    carved = _carve(ctx, x0, y0, h, excluded, uncertain)
    return excluded, uncertain & ~excluded, carved


def _sliver_seeds(excluded, x0, y0, h):
    """(m, 2) positions (b) of the allowed slivers that the excluded nodes of a window enclose."""
    parts, _ = ndimage.label(excluded, np.ones((3, 3), dtype=bool))
    _, nodes = _slivers(parts, excluded)
    iy, ix = np.nonzero(nodes)
    return np.column_stack([x0 + (ix + 0.5) * h, y0 + (iy + 0.5) * h])


def base_slivers(
    particle, *, other=None, segments: int = DEFAULT_SEGMENTS, base: int = BASE_CELLS, floor: float = FLOOR
) -> np.ndarray:
    """(m, 2) positions (b) of the allowed slivers on the base window of :func:`excluded_map`: the seeds of
    the channels it follows (:mod:`sesp.channels`). Where there are none, the map is made as if channels were
    never followed. Arguments as in :func:`excluded_map`."""
    base = check_count("base", base, 8, 4096)
    floor = check_range("floor", floor, 1e-12, 1.0, " b")
    pair = as_pair(particle, other, segments)
    h = base_cell(pair.reach, base)
    start = -(base // 2 + 0.5) * h
    with progress_bar(None, False, "map") as bar:
        ctx = _Context(pair, floor, ZOOM, bar, centre=centre_pinch(pair, floor, _CENTRE_CELLS * h))
        everywhere = np.ones((base, base), dtype=bool)
        excluded, _, _ = _classify(ctx, start, start, h, everywhere, None)
    return _sliver_seeds(excluded, start, start, h)


def _carve(ctx, x0, y0, h, excluded, uncertain):
    """The excluded nodes whose cells meet a certified allowed channel (``ctx.channels``,
    :mod:`sesp.channels`), left out of E (in place); their cells are not certified either."""
    carved = np.zeros(excluded.shape, dtype=bool)
    if not len(ctx.channels) or not excluded.any():
        return carved
    iy, ix = np.nonzero(excluded)
    cut = meets(ctx.channels, x0 + (ix + 0.5) * h, y0 + (iy + 0.5) * h, h)
    carved[iy[cut], ix[cut]] = True
    excluded[carved] = False
    uncertain[carved] = True
    return carved


_NEIGHBOURS = np.array([(dy, dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if dy or dx])


def _sides(ctx, carved, labels, x0, y0, h):
    """``labels`` with each carved node (:func:`_carve`) given the label of a neighbouring node on the same
    side of the channel as itself (:func:`sesp.channels.same_side`), for the components' areas; 0 where none
    is labelled."""
    if not carved.any():
        return labels
    iy, ix = np.nonzero(carved)
    same = same_side(ctx.channels, x0 + (ix + 0.5) * h, y0 + (iy + 0.5) * h, _NEIGHBOURS[:, 1] * h,
                     _NEIGHBOURS[:, 0] * h)  # fmt: skip
    ny = np.clip(iy[:, None] + _NEIGHBOURS[None, :, 0], 0, labels.shape[0] - 1)
    nx = np.clip(ix[:, None] + _NEIGHBOURS[None, :, 1], 0, labels.shape[1] - 1)
    near = np.where(same, labels[ny, nx], 0)
    out = labels.copy()
    out[iy, ix] = near.max(axis=1)
    return out


def _sliver_channels(ctx, x0, y0, h, excluded):
    """Certified allowed disks along the channels through the allowed slivers that the excluded parts of
    the base window enclose (:func:`sesp.channels.traced_channels`)."""
    seeds = _sliver_seeds(excluded, x0, y0, h)

    def tick(count):
        ctx.positions += count
        ctx.bar.update(count)

    return traced_channels(ctx.pair, seeds, h, ctx.floor, tick)


def _centre_column(x0, y0, h, shape, half_length):
    """Index of the window's nodes on x = 0 with |y| <= ``half_length`` (the centre's node among them), or
    an empty selection if the window has no node column on x = 0."""
    ix = int(round(-x0 / h - 0.5))
    if not (0 <= ix < shape[1] and abs(x0 + (ix + 0.5) * h) <= 1e-6 * h):
        return (np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64))
    rows = np.flatnonzero(np.abs(y0 + (np.arange(shape[0]) + 0.5) * h) <= half_length)
    return rows, np.full(len(rows), ix)


def centre_pinch(pair, floor: float, reach: float) -> float:
    """b: how far above and below the centre the column x = 0 is certified allowed when the centre is
    excluded, so that the centre is a pinch (0 where it is not, or where that is not certified).

    Where the centre (t = 0) is a point of E and the positions (0, y) are allowed for 0 < |y| <= Y, the
    parts of E left and right of the centre meet, near it, at that point only: a single-point pinch,
    which parts them by convention. It is certified, not sampled: at each position (0, y_k) of a
    geometric sequence from ``floor`` / 10 to ``reach``, the curves at the middle of the widest window are
    farther apart than c_k, so the disk of radius c_k around (0, y_k) is allowed (the clearance
    certificate of the module notes), and the disks of successive positions overlap. Then the maps leave
    the centre's node out of E and keep the column's nodes within Y of it out too (they are allowed: a
    finer window that inherits a coarser cell's flags could otherwise take them for excluded), so the
    two sides are told apart at the centre on every window and grid, however thin they are there, rather
    than by the persistence rule. The ASP's lens and body meet so for every 0 < Ψ < π, and so do the
    parts left and right of the centre for n = 4, 8, 10 (the curves' distance grows as c ≈ κ·|y| along
    the column, κ from about 0.08 at Ψ = 30° to 1 near π). Where κ is so small that more than
    ``_CENTRE_PROBES`` positions would be needed (Ψ below 5° to 10°), nothing is certified and the
    persistence rule decides, as elsewhere.
    """
    width, _, _ = widest_windows(
        pair.vertices1, pair.vertices2, np.zeros(1), np.zeros(1), SCREEN_SLACK, ANGLE_GAP, pair.contact
    )
    if width[0] > 0.0:
        return 0.0
    low = floor / 10
    coarse = np.geomspace(low, reach, 33)
    coarse = np.concatenate([coarse, -coarse])
    kappa = float(np.min(_column_clearance(pair, coarse, np.abs(coarse)) / np.abs(coarse)))
    if not kappa > 0.0:
        return 0.0
    ratio = 1.0 + 0.5 * kappa
    count = int(math.ceil(math.log(reach / low) / math.log(ratio))) + 1
    if count > _CENTRE_PROBES:
        return 0.0
    ys = low * ratio ** np.arange(count + 1)
    for sign in (1.0, -1.0):
        c = _column_clearance(pair, sign * ys, ys * (ratio - 1.0))  # a disk that wide reaches the next position
        covered = (c[:-1] > 0.0) & (ys[:-1] + c[:-1] >= ys[1:] - c[1:])
        if not (c[-1] > 0.0 and covered.all()):
            return 0.0
    return float(ys[-1])


def _column_clearance(pair, ys, caps):
    """Radius (b) of the disk certified allowed around each position (0, y), at most ``caps``: the curves'
    distance at the best orientation sampled across the widest window, less the contact distance; 0 where
    the position is excluded."""
    width, _, clear = widest_windows(
        pair.vertices1, pair.vertices2, np.zeros(len(ys)), np.asarray(ys, dtype=float), SCREEN_SLACK, ANGLE_GAP,
        pair.contact, np.asarray(caps, dtype=float),
    )  # fmt: skip
    return np.where(width > 0.0, clear - pair.contact, 0.0)


def _disk(radius):
    r = int(math.ceil(radius))
    y, x = np.mgrid[-r : r + 1, -r : r + 1]
    return x * x + y * y <= radius * radius


def _window(
    ctx, x0, y0, h, evaluate, active, inherited, owner_grid, outside=True, assumed=None, above=None, necks_above=None,
    first=False,
):  # fmt: skip
    """The pieces of E seen on one window of nodes spaced h, lower-left corner (x0, y0).

    ``evaluate``: nodes classified here; the others keep the coarser
    window's flags (``inherited`` excluded) and count, and ``owner_grid``
    holds the coarser component each of their excluded nodes belongs to.
    ``active``: nodes this window decides (the refined cells). ``outside``:
    whether the set may continue beyond the window's edge. ``assumed``:
    nodes taken as excluded without classifying them (the children of a
    coarser excluded node at least ``_DEEP`` nodes inside the set: an
    allowed hole there would not change the count of components).
    ``above``: per node, the depth (b) the coarser windows measured for
    the part it belonged to, so that a body cut by this window's edge keeps
    its depth (see :func:`_untapered`). ``necks_above``: per node, the
    width (b) of the undecided neck the coarser window refined there, 0
    elsewhere (see :func:`_waists`). ``first``: this is the base window,
    whose allowed slivers are followed as channels (:func:`_sliver_channels`)
    and left out of E here and on every finer window (:func:`_carve`).

    Returns a list of (piece or None, owners): each component found here,
    with the coarser components it touches (to be joined with them).
    """
    excluded, uncertain, carved = _classify(ctx, x0, y0, h, evaluate, inherited)
    if first:
        ctx.channels = _sliver_channels(ctx, x0, y0, h, excluded)
        carved = _carve(ctx, x0, y0, h, excluded, uncertain)
    if not excluded.any() and not (uncertain & active).any():
        return []
    counted = evaluate if assumed is None else evaluate | assumed
    # The coarser window's excluded nodes around the refined cells take part in the count (pinches between
    # them and what is found here are judged by the same rule) and say which coarser component a piece is.
    dist = distance_to_complement(excluded, (), outside)
    at_floor = h / ctx.zoom < ctx.floor
    peak = _FLOOR_PEAK if at_floor else 2.0
    found = components(excluded, outside=outside, measure=h * h, neck=UNDECIDED, distance=dist, min_peak=peak)
    found = _waists(found, necks_above, h, excluded, dist)
    thick = excluded & counted & (dist >= RESOLVED_PEAK)
    settled = ndimage.binary_dilation(thick, _disk(_SETTLED)) if thick.any() else np.zeros_like(thick)
    depth = _part_depth(excluded, dist * h if above is None else np.maximum(dist * h, above))
    zone = _untapered(_unsettled(excluded, uncertain, settled) & active, depth, h, thick)
    zone = _linked(zone, excluded, uncertain, dist, active)
    neck_width = np.zeros(zone.shape)
    for node, a, b, s in found.necks:
        if a and b and a != b:
            iy, ix = divmod(int(node), zone.shape[1])
            r = int(math.ceil(s)) + 2
            near = np.zeros_like(zone)
            near[max(iy - r, 0) : iy + r + 1, max(ix - r, 0) : ix + r + 1] = True
            zone |= near & (excluded | uncertain) & active
            neck_width[near] = np.maximum(neck_width[near], s * h)
    if not at_floor:
        zone |= _uncounted(found, excluded, uncertain) & active
    zone, stopped = _affordable(zone, ctx.zoom)
    local = _local_pieces(found, dist, active & (~zone if not at_floor else True), owner_grid, ~active,
                          x0, y0, h, at_floor, stopped, _sides(ctx, carved, found.labels, x0, y0, h))  # fmt: skip
    if at_floor or not zone.any():
        return list(local.values())
    return _refine(ctx, x0, y0, h, excluded, zone, found, local, dist, depth, neck_width)


def _uncounted(found, excluded, uncertain):
    """Excluded nodes in no component of this window (parts too thin to count here) and the nodes next to
    them: they are refined whatever the depth carried down for them (a strip one coarse node thick carries
    that node's depth, which :func:`_untapered` would take for a body's; the n = 4 strip left of the centre
    at Ψ = 178° was lost so once the centre's pinch parted it from the strip on the right)."""
    thin = excluded & (found.labels == 0)
    if not thin.any():
        return thin
    return ndimage.binary_dilation(thin, np.ones((3, 3), dtype=bool)) & (excluded | uncertain)


def _waists(found, necks_above, h, excluded, dist):
    """``found`` with the bodies joined across each undecided neck that is a waist: one that kept at least
    ``WAIST`` of the width (b) the coarser window measured for it, while the cells shrank ``zoom`` times.

    Behind an allowed wedge a pinch looks about as many nodes wide on every window, so its width in b
    shrinks with the cells; a waist of one body keeps its width. A neck the coarser window did not refine
    (``necks_above`` 0 there) is left undecided, and so is one that parts the bodies by the rule, within a
    node of its threshold (``NEAR`` in the labelling kernel): a narrow neck keeps its width in b too.
    """
    if necks_above is None or not len(found.necks):
        return found
    merged = np.arange(found.count + 1)
    kept = []
    for row in found.necks:
        node, a, b, s = int(row[0]), int(row[1]), int(row[2]), row[3]
        coarse = necks_above.flat[node]
        wide = a and b and a != b and s >= PINCH_RATIO * min(found.peaks[a - 1], found.peaks[b - 1])
        if wide and coarse > 0 and s * h >= WAIST * coarse:
            merged[merged == merged[b]] = merged[a]
        else:
            kept.append(row)
    if len(kept) == len(found.necks):
        return found
    necks = np.array(kept, dtype=float).reshape(-1, 4)
    necks[:, 1:3] = merged[necks[:, 1:3].astype(np.int64)]
    return renumbered(merged[found.labels], excluded, found.measure, dist, necks)


def _local_pieces(found, dist, keep, owner_grid, coarse, x0, y0, h, at_floor, stopped, sides):
    """Label -> (piece of its nodes in ``keep``, or None; the coarser components it shares nodes with in
    ``coarse``, the cells the coarser window decided, as {component: nodes shared}). A piece holds the nodes
    that ``sides`` gives its label: its own, and the carved nodes beside it (:func:`_sides`)."""
    local = {}
    slivers, _ = _slivers(found.labels, dist > 0)  # dist > 0: the excluded nodes
    undecided = {int(k) for row in found.necks for k in row[1:3]} if at_floor else set()
    undecided |= _thin_joins(found.labels, dist) if at_floor else set()
    for k in range(1, found.count + 1):
        mine = found.labels == k
        owners = {}
        if owner_grid is not None:
            values, shared = np.unique(owner_grid[mine & coarse], return_counts=True)
            owners = {int(v): int(c) for v, c in zip(values, shared) if v}
        nodes = (sides == k) & keep
        piece = None
        if nodes.any():
            iy, ix = np.nonzero(nodes)
            peak = float(dist[nodes].max())
            piece = _Piece(
                x0 + (ix + 0.5) * h,
                y0 + (iy + 0.5) * h,
                np.full(len(ix), h),
                (peak - 0.5) * h,
                at_floor and peak < RESOLVED_PEAK,
                k in slivers,
                (at_floor and k in undecided) or bool((mine & stopped).any()),
            )
        local[k] = (piece, owners)
    return local


def _thin_joins(labels, dist):
    """Labels of the components on a window at the floor that hold a part joined to the rest only through
    nodes less than ``_THIN`` nodes deep: two deep parts (``dist`` >= ``_THIN``) that touch only through thin
    nodes, or a cluster of thin nodes more than ``_THIN`` nodes from the deep ones and longer than a tip of
    the component would be (``_THIN_TAIL`` times its depth).
    Such a join is the floor's: a pinch one node wide, or a thin body reaching the component at a pinch,
    cannot be told from a waist on these cells (the ASP's lens near Ψ = π, on a node row through the
    centre)."""
    out = set()
    ring = np.ones((3, 3), dtype=bool)
    for k, box in enumerate(ndimage.find_objects(labels), start=1):
        if box is None:
            continue
        mine = labels[box] == k
        deep = mine & (dist[box] >= _THIN)
        if not deep.any():
            continue  # all of it thin: marked by its peak
        if ndimage.label(deep, ring)[1] > 1:
            out.add(k)
            continue
        tail = mine & (ndimage.distance_transform_edt(~deep) > _THIN)
        longest = np.bincount(ndimage.label(tail, ring)[0].ravel())[1:].max() if tail.any() else 0
        if longest >= _THIN_TAIL * float(dist[box][mine].max()):
            out.add(k)
    return out


def _slivers(labels, excluded):
    """(labels of the components that enclose a cluster of nodes not in ``excluded`` no more than ``_SLIVER``
    nodes from it on every side, the nodes of those clusters): allowed slivers seen only at the nodes that
    fell in them."""
    out = set()
    nodes = np.zeros(labels.shape, dtype=bool)
    for k, box in enumerate(ndimage.find_objects(labels), start=1):
        if box is None:
            continue
        enclosed = ndimage.binary_fill_holes(labels[box] == k) & ~excluded[box]
        if not enclosed.any():
            continue
        clusters, count = ndimage.label(enclosed)
        depth = ndimage.distance_transform_edt(enclosed)
        thin = ndimage.maximum(depth, clusters, np.arange(1, count + 1)) <= _SLIVER
        if np.any(thin):
            out.add(k)
            nodes[box] |= np.concatenate([[False], thin])[clusters]
    return out, nodes


def _affordable(zone, zoom):
    """(zone without the clusters whose finer window would exceed ``MAX_WINDOW`` nodes, those clusters)."""
    clusters, _ = ndimage.label(zone, np.ones((3, 3), dtype=bool))
    stopped = np.zeros_like(zone)
    for index, box in enumerate(ndimage.find_objects(clusters), start=1):
        size = (box[0].stop - box[0].start + 2 * _PAD) * (box[1].stop - box[1].start + 2 * _PAD) * zoom * zoom
        if size > MAX_WINDOW:
            stopped[box] |= clusters[box] == index
    return zone & ~stopped, stopped


def _join(a, b):
    if a is None or b is None:
        return a if b is None else b
    return a.joined(b)


def _refine(ctx, x0, y0, h, excluded, zone, found, local, dist, depth, neck_width):
    """Look at each cluster of the zone ``ctx.zoom`` times finer; join what is found to the ``local`` pieces.

    A finer piece belongs to the coarser component it shares most nodes with (its main one), and joins the
    others it shares nodes with, except those the rule decided apart here (:func:`_decided_apart`) and
    those that another piece of the same finer window has as its main one: that window split the two, and
    the nodes they share are a shift of the line between them (the nodes of a pinch go to the body of
    steepest ascent, which the finer window measures differently).
    """
    z = ctx.zoom
    labels = found.labels
    apart = _decided_apart(labels, found.necks)
    clusters, _ = ndimage.label(zone, np.ones((3, 3), dtype=bool))
    parent = {k: k for k in local}
    pieces = {k: piece for k, (piece, _) in local.items()}

    def root(k):
        while parent[k] != k:
            k = parent[k]
        return k

    new = []
    up = np.ones((z, z), dtype=bool)
    settled_labels = np.where(excluded & ~zone, labels, 0)
    deep = excluded & (dist >= _DEEP)
    for index, box in enumerate(ndimage.find_objects(clusters), start=1):
        ys = slice(max(box[0].start - _PAD, 0), min(box[0].stop + _PAD, zone.shape[0]))
        xs = slice(max(box[1].start - _PAD, 0), min(box[1].stop + _PAD, zone.shape[1]))
        mine = clusters[ys, xs] == index
        near = ndimage.binary_dilation(mine, np.ones((3, 3), dtype=bool))
        sub = _window(
            ctx,
            x0 + xs.start * h,
            y0 + ys.start * h,
            h / z,
            np.kron(near & ~deep[ys, xs], up).astype(bool),
            np.kron(mine, up).astype(bool),
            np.kron(excluded[ys, xs], up).astype(bool),
            np.kron(settled_labels[ys, xs], up.astype(np.int64)),
            assumed=np.kron(near & deep[ys, xs], up).astype(bool),
            above=np.kron(depth[ys, xs], up),
            necks_above=np.kron(neck_width[ys, xs], up),
        )
        owned = [({k: c for k, c in owners.items() if k in parent}, piece) for piece, owners in sub]
        owned = [(shared, piece, _main_owner(shared)) for shared, piece in owned]
        mains = {main for _, _, main in owned if main is not None}
        for shared, piece, main in owned:
            if main is None:
                if piece is not None:
                    new.append((piece, {}))
                continue
            for k in shared:  # a finer piece that joins two coarse ones: they are one
                if k not in mains and root(k) != root(main) and _joins(shared, k, main, apart):
                    parent[root(k)] = root(main)
            pieces[main] = _join(pieces[main], piece)
    groups = {}
    for k, (_, owners) in local.items():
        r = root(k)
        piece, above = groups.get(r, (None, {}))
        groups[r] = (_join(piece, pieces[k]), _summed(above, owners))
    return [g for g in groups.values() if g[0] is not None or g[1]] + new


def _joins(shared, k, main, apart):
    """Whether a finer piece whose main coarser component is ``main`` joins ``k``, another it shares nodes
    with: unless the coarser window decided the two apart and the piece holds only a sliver of ``k`` (less
    than ``_SHARED`` of what it holds of ``main``: the line between them shifted by a node or two). A piece
    that holds much of both saw them as one body, on cells finer than those that split them (the n = 4
    arrowhead at Ψ = 173.75°, whose wings were split on cells where they were 4 nodes thick)."""
    return (min(k, main), max(k, main)) not in apart or shared[k] >= _SHARED * shared[main]


def _main_owner(shared):
    """The coarser component a finer piece shares most nodes with (the lowest label on a tie), or None."""
    return max(shared, key=lambda k: (shared[k], -k)) if shared else None


def _summed(a, b):
    return {k: a.get(k, 0) + b.get(k, 0) for k in a.keys() | b.keys()}


def _decided_apart(labels, necks):
    """Pairs (a, b), a < b, of components that touch on this window but that the rule split at a neck it
    decided (not an undecided neck): a finer window, which sees only the cells around the neck, does not
    join them again. Its split between the two may fall a node or two from this window's (the nodes of a
    pinch go to the body of steepest ascent), so a finer piece can share nodes with both."""
    pairs = set()
    for a, b in ((labels[:, 1:], labels[:, :-1]), (labels[1:, :], labels[:-1, :]),
                 (labels[1:, 1:], labels[:-1, :-1]), (labels[1:, :-1], labels[:-1, 1:])):  # fmt: skip
        touch = (a > 0) & (b > 0) & (a != b)
        lo, hi = np.minimum(a[touch], b[touch]), np.maximum(a[touch], b[touch])
        pairs |= set(zip(lo.tolist(), hi.tolist()))
    undecided = {(min(int(a), int(b)), max(int(a), int(b))) for _, a, b, _ in necks}
    return pairs - undecided


def _unsettled(excluded, uncertain, settled):
    """Nodes whose count is not settled: thin excluded parts with the uncertain nodes next to them, and
    clusters of uncertain nodes away from thick parts (they might hold a thin component). The width of the
    window says nothing here: next to the ASP's lens, whose rim is where an end point lies on the other arc
    for a whole interval of φ, the window jumps from 0 to wide. Of a cluster that touches an excluded node,
    the nodes within ``_SETTLED + 2`` nodes of excluded ones are left (a body's rim, to :func:`_untapered`);
    the farther ones are kept: a strip of uncertain nodes that starts beside a body may hold a thin
    component (n = 8 at Ψ = 155°: the island on the axis, between the node rows of an even grid)."""
    ring = np.ones((3, 3), dtype=bool)
    thin = excluded & ~settled
    near_thin = ndimage.binary_dilation(thin, ring) & (excluded | uncertain) if thin.any() else thin
    alone = uncertain & ~settled & ~near_thin
    clusters, count = ndimage.label(alone, ring)
    if count:
        touching = np.unique(clusters[ndimage.binary_dilation(excluded, ring) & alone])
        beside = ndimage.distance_transform_edt(~excluded) <= _SETTLED + 2
        alone &= ~(np.isin(clusters, touching[touching > 0]) & beside)
    return near_thin | alone


def _linked(zone, excluded, uncertain, dist, active):
    """``zone`` grown by up to ``_SETTLED + 2`` nodes along the boundary layer (uncertain nodes and excluded
    nodes next to the complement): the cells that join a thin part being refined to the body it hangs on are
    refined with it, so the finer window sees the join. Without them the join, inside the body's settled
    nodes, is never looked at closely, and a thin tip is found apart from its body (the ASP at 179°: slivers
    at the corners of the body)."""
    if not zone.any():
        return zone
    layer = (uncertain | (excluded & (dist < 2))) & active
    return ndimage.binary_dilation(zone, np.ones((3, 3), dtype=bool), iterations=int(_SETTLED) + 2, mask=layer | zone)


def _part_depth(excluded, depth):
    """Per node, the largest of ``depth`` (b) over the 8-connected part of ``excluded`` it belongs to; 0 outside."""
    parts, count = ndimage.label(excluded, np.ones((3, 3), dtype=bool))
    if not count:
        return np.zeros(excluded.shape)
    return np.concatenate([[0.0], ndimage.maximum(depth, parts, np.arange(1, count + 1))])[parts]


def _untapered(zone, depth, h, thick):
    """``zone`` without its nodes beside thick parts already looked at closely enough.

    Nodes within ``_SETTLED + 2`` nodes of the rim or tip of an excluded
    part deeper than ``_TAPER`` cells (``depth``: the inscribed radius of
    each node's part, b, as this window or a coarser one measured it, so
    that a body cut by the window's edge keeps its depth) are a tip, a bump
    or a thin part of that body, a thin component pinched to it or lying
    beside it, or uncertain cells along its rim. They are refined until the
    cells are ``_TAPER`` times smaller than the body's inscribed radius,
    which resolves parts far thinner than the body, and then left: a tip is
    thin down to its end and a pinch looks the same at every scale, so both
    would be refined to the floor. The rim and tip are the part's nodes
    within ``_TIP`` nodes of its ``thick`` ones (at least ``RESOLVED_PEAK``
    nodes deep): a thin part that runs on farther is refined along its
    length, although it is joined to the body on these cells (the n = 8 lens
    at Ψ = 168.125°, 1.3e-3 b thick and 0.5 b long, under two nodes thick on
    the cells of 1/256 of the body, where the count takes it into the body's
    tail: left there, it was lost on 97 base cells and found on 128). What
    is left is the maps' blind spot: a component thinner than a couple of
    cells ``1 / _TAPER`` of the inscribed radius of a body and wholly within
    a few cells of its rim. The farther nodes of a cluster that starts
    beside the body are kept too: a thin strip that runs away from it (the
    n = 8 island at Ψ = 175°, 0.48 b long) is refined along its length,
    which costs minutes per map where the strip is 1e-4 b thick.
    """
    deep = depth > _TAPER * h
    if thick.any():
        deep &= ndimage.distance_transform_edt(~thick) <= _TIP
    if not deep.any():
        return zone
    return zone & (ndimage.distance_transform_edt(~deep) > _SETTLED + 2)


def map_transitions(
    family,
    opening_range=(0.0, 2 * math.pi),
    *,
    step: float = math.radians(5),
    tolerance: float = 0.005,
    segments: int = DEFAULT_SEGMENTS,
    base: int = BASE_CELLS,
    floor: float = FLOOR,
    progress: bool = False,
    folder=None,
    finer=(),
) -> xr.Dataset:
    """Where the count of excluded components (:func:`excluded_map`) changes with the opening Ψ.

    Maps every ``step`` over ``opening_range`` (radians, Ψ < 2π kept), then
    bisects each step whose count changes until the bracket is at most
    ``2 · tolerance`` wide (default ±0.005 rad, ±0.29°). A step is bisected
    too where the count is the same at both ends but the number of
    components off the x-axis (:attr:`ExcludedMap.off_axis`) is not: a body
    parting into a mirror pair off the axis (+1) and a strip on the axis
    joining it (−1) in one step leave the count unchanged (n = 4 between
    170° and 175° on 128 cells). Changes that cancel in both numbers within
    one step are still not seen. ``progress``: a bar
    of the maps and, below it, one of the positions of the map being made.
    ``folder``: where each map is saved as soon as it is made
    (``map_<opening>.nc``, a ``sesp.map`` dataset); a map already there is
    read instead of made again, so an interrupted search loses at most the
    map it was making, and the same call resumes it. A map there of another
    pair, base, floor or zoom is an error, not a silent mix.

    ``finer``: ranges (low, high) of Ψ (radians); every step that overlaps
    one is mapped and bisected at a floor ten times finer (its maps saved in
    ``folder/floor_<finer floor>``), and so is the step beside it wherever
    the two floors disagree at the opening they share, so that no change
    hides between floors. Use it where a bracket moves with the base grid:
    a change seen only at the floor (marked) can move by a degree when one
    node of a neck is judged the other way (n = 4's tail near 168° at
    1e-4 b: 168.12–168.44° on 128 cells, 167.19–167.50° on 97; at 1e-5 b
    both say 168.12–168.44°, ``benchmarks/README.md``).

    Returns
    -------
    xarray.Dataset
        ``count(opening)`` and per component ``area``, ``inscribed_radius``,
        ``touches_floor``, ``unresolved`` (:meth:`ExcludedMap.limit`)
        (opening, component; NaN / False beyond the count) and ``departure``
        (b) at every opening mapped; ``low``, ``high`` (rad),
        ``low_degrees``, ``high_degrees``, ``count_low``, ``count_high``,
        ``off_axis_low``, ``off_axis_high`` and ``transition_unresolved`` (a
        component that changes in the bracket is unresolved: the bracket may
        be the floor's or the polylines'; :func:`changed_components`) per
        ``transition``; ``changed_low``, ``changed_high`` (transition,
        component): which components at the low and the high end change
        (numbered as at that opening); ``off_axis`` per opening;
        ``map_floor`` per opening and ``transition_floor`` per transition
        (b): the floor the maps were made at (``floor``, or ten times finer
        in the steps of ``finer``).
    """
    lo, hi = (float(v) for v in opening_range)
    if not (0.0 <= lo < hi and math.isfinite(hi)) or not (step > 0 and tolerance > 0):
        raise ValueError(
            f"opening_range must satisfy 0 <= low < high (radians), step, tolerance > 0; got {opening_range}"
        )
    for low, high in finer:
        if not (math.isfinite(low) and math.isfinite(high) and 0.0 <= low < high):
            raise ValueError(f"finer ranges must satisfy 0 <= low < high (radians), got {(low, high)}")
    openings = lo + step * np.arange(int(math.floor((hi - lo) / step + 1e-9)) + 1)
    openings = [float(o) for o in openings if o < 2 * math.pi]
    steps = list(zip(openings[:-1], openings[1:]))
    make = opening_family(family)
    with progress_bar(None, progress, "maps over Ψ", unit="map") as bar:

        def states(at_floor, where):
            """The maps made at ``at_floor`` (kept in ``where``), and the state of one opening."""
            maps = {}

            def state(opening):
                if opening not in maps:
                    pair = as_pair(make(opening), None, segments)
                    maps[opening] = stored_map(where, opening, pair, base=base, floor=at_floor, progress=progress)
                    bar.update(1)
                return maps[opening].count, maps[opening].off_axis

            return maps, state

        coarse, coarse_state = states(floor, folder)
        fine, fine_state = states(floor / 10, None if folder is None else Path(folder) / f"floor_{floor / 10:g}")
        for opening in openings:
            coarse_state(opening)
        refined = _refined_steps(steps, finer, coarse_state, fine_state)
        brackets = []
        for i, (a, b) in enumerate(steps):
            at_floor, state = (floor / 10, fine_state) if i in refined else (floor, coarse_state)
            brackets += [(low, high, at_floor) for low, high in _bisect(state, a, b, tolerance)]
    floored = {o: (m, floor) for o, m in coarse.items()} | {o: (m, floor / 10) for o, m in fine.items()}
    return _transitions_dataset(floored, brackets, floor, base)


def _refined_steps(steps, finer, coarse_state, fine_state) -> set:
    """Indices of the ``steps`` searched at the finer floor: those that overlap a range of ``finer`` (by more
    than rounding: 170° in radians may end a step a hair above 170°), and, step by step, each beside one of
    them where the two floors disagree at the opening they share."""
    refined = {i for i, (a, b) in enumerate(steps) if any(min(b, hi) - max(a, lo) > 1e-9 for lo, hi in finer)}
    todo = sorted(refined)
    while todo:
        i = todo.pop()
        for j, shared in ((i - 1, steps[i][0]), (i + 1, steps[i][1])):
            if 0 <= j < len(steps) and j not in refined and fine_state(shared) != coarse_state(shared):
                refined.add(j)
                todo.append(j)
    return refined


def stored_map(folder, opening, pair, *, base=BASE_CELLS, floor=FLOOR, progress=False) -> ExcludedMap:
    """The map of ``pair`` (of opening Ψ = ``opening``, radians) kept in ``folder``.

    Reads ``folder/map_<opening>.nc`` (a ``sesp.map`` dataset) if it is there;
    otherwise makes the map (:func:`excluded_map`) and saves it there first.
    A file there of another pair, base, floor or zoom is an error, not a
    silent mix. ``folder=None``: the map is made and not saved. The same
    folder serves :func:`map_transitions`, ``sesp topology --maps-folder``
    and ``benchmarks/component_maps.py``, so a map made by one is read by the
    others.
    """
    path = None if folder is None else Path(folder) / f"map_{float(opening)!r}.nc"
    if path is not None and path.exists():
        return _saved_map(path, pair, base, floor)
    found = excluded_map(pair, base=base, floor=floor, progress=progress)
    if path is not None:
        save(found.dataset(), path)
    return found


def _saved_map(path, pair, base, floor) -> ExcludedMap:
    """The map saved at ``path`` by a search of ``pair`` on ``base`` cells down to ``floor``."""
    try:
        ds = load(path)
    except SespFileError as err:
        raise SespFileError(f"{err}; remove it to make that map again") from None
    expected = pair_attrs(pair) | {"base_cells": base, "floor": floor, "zoom": ZOOM}
    differs = sorted(k for k, v in expected.items() if k not in ds.attrs or not _same(ds.attrs[k], v))
    if format_of(ds) != "sesp.map" or differs:
        raise SespFileError(
            f"{path}: not a map of this search ({', '.join(differs) or 'not a sesp.map file'} differ): "
            "give another folder, or remove the file"
        )
    return ExcludedMap.from_dataset(ds)


def _same(saved, value) -> bool:
    return bool(np.all(np.asarray(saved) == np.asarray(value)))


def changed_components(low: ExcludedMap, high: ExcludedMap) -> tuple[list, list]:
    """The components of ``low`` and of ``high`` (maps a small step of Ψ apart) that change between them.

    Over a small step the curves move little, so a component at one end
    overlaps what it became at the other: two components, one on each map,
    are linked where some cell of one meets a cell of the other (their
    excluded nodes, within half the sum of their cells in x and in y). A
    group of components linked one to another is unchanged when it holds one
    component of each map, both on the x-axis or both off it
    (:attr:`ExcludedMap.off_axis`); every other group changed: a body that
    parts or joins, one that appears or vanishes, one that leaves the axis.
    A component that moved farther than its own size is taken for one that
    vanished and one that appeared. Returns (components of ``low``,
    components of ``high``) in the changed groups.
    """
    lows, highs = _changed_indices(low, high)
    return [low.components[k] for k in lows], [high.components[k] for k in highs]


def _changed_indices(low: ExcludedMap, high: ExcludedMap) -> tuple[list, list]:
    """Indices into ``low.components`` and ``high.components`` of those that change (:func:`changed_components`)."""
    comps = low.components + high.components
    first = len(low.components)
    graph = np.zeros((len(comps), len(comps)), dtype=bool)
    for i, a in enumerate(low.components):
        for j, b in enumerate(high.components):
            graph[i, first + j] = _cells_meet(a, b)
    _, group = connected_components(graph, directed=False)
    changed = set()
    for g in np.unique(group):
        members = np.flatnonzero(group == g)
        lows, highs = members[members < first], members[members >= first]
        if len(lows) != 1 or len(highs) != 1 or _on_axis(comps[lows[0]]) != _on_axis(comps[highs[0]]):
            changed.update(int(m) for m in members)
    return [m for m in sorted(changed) if m < first], [m - first for m in sorted(changed) if m >= first]


def _cells_meet(a: MapComponent, b: MapComponent) -> bool:
    """Whether a cell of one component's excluded nodes meets a cell of the other's (their boxes, for
    components read without nodes)."""
    if a.bbox[1] < b.bbox[0] or b.bbox[1] < a.bbox[0] or a.bbox[3] < b.bbox[2] or b.bbox[3] < a.bbox[2]:
        return False
    if not (len(a.x) and len(b.x)):
        return True
    reach = 0.5 * (b.cell + a.cell.max())
    near = cKDTree(np.column_stack([a.x, a.y])).query_ball_point(
        np.column_stack([b.x, b.y]), reach, p=np.inf, return_length=True
    )
    return bool(np.any(near))


def _on_axis(component: MapComponent) -> bool:
    return component.bbox[2] <= 0.0 <= component.bbox[3]


def _change(low: ExcludedMap, high: ExcludedMap, width: int) -> tuple:
    """(per component of ``low``, then of ``high``: whether it changes between the two maps, padded with
    False to ``width``; whether a component that changes is unresolved, or, where none is found to change,
    any at either end) (:func:`changed_components`, :meth:`ExcludedMap.limit`)."""
    lows, highs = _changed_indices(low, high)
    flags = [np.zeros(width, dtype=bool), np.zeros(width, dtype=bool)]
    flags[0][lows] = flags[1][highs] = True
    suspects = (lows, highs) if lows or highs else (range(low.count), range(high.count))
    unresolved = any(low.limit(low.components[k]) for k in suspects[0]) or any(
        high.limit(high.components[k]) for k in suspects[1]
    )
    return flags[0], flags[1], unresolved


def _bisect(state, low, high, tolerance):
    """Brackets no wider than 2·tolerance around each change of ``state`` in [low, high]."""
    if state(low) == state(high):
        return []
    if high - low <= 2 * tolerance:
        return [(low, high)]
    mid = 0.5 * (low + high)
    return _bisect(state, low, mid, tolerance) + _bisect(state, mid, high, tolerance)


def _transitions_dataset(floored, brackets, floor, base):
    """A search's dataset: ``floored`` {opening: (map, the floor it was made at)}, ``brackets`` [(low, high,
    the floor of the maps that bracket it)]."""
    maps = {o: m for o, (m, _) in floored.items()}
    openings = sorted(maps)
    width = max([maps[o].count for o in openings] + [1])
    area = np.full((len(openings), width), np.nan)
    radius = np.full((len(openings), width), np.nan)
    at_floor = np.zeros((len(openings), width), dtype=bool)
    unresolved = np.zeros((len(openings), width), dtype=bool)
    for i, o in enumerate(openings):
        for k, c in enumerate(maps[o].components):
            area[i, k], radius[i, k], at_floor[i, k] = c.area, c.inscribed_radius, c.touches_floor
            unresolved[i, k] = bool(maps[o].limit(c))
    low = np.array([b[0] for b in brackets])
    high = np.array([b[1] for b in brackets])
    changes = [_change(maps[a], maps[b], width) for a, b, _ in brackets]
    changed_low = np.array([c[0] for c in changes], dtype=bool).reshape(len(brackets), width)
    changed_high = np.array([c[1] for c in changes], dtype=bool).reshape(len(brackets), width)
    ends_unresolved = [c[2] for c in changes]
    return xr.Dataset(
        {
            "count": ("opening", [maps[o].count for o in openings]),
            "off_axis": ("opening", [maps[o].off_axis for o in openings]),
            "area": (("opening", "component"), area, dict(AREA)),
            "inscribed_radius": (("opening", "component"), radius, dict(LENGTH)),
            "touches_floor": (("opening", "component"), at_floor),
            "unresolved": (("opening", "component"), unresolved),
            "departure": ("opening", [maps[o].departure for o in openings], dict(LENGTH)),
            "map_floor": ("opening", [floored[o][1] for o in openings], dict(LENGTH)),
            "low": ("transition", low, {"units": "rad"}),
            "high": ("transition", high, {"units": "rad"}),
            "low_degrees": ("transition", np.degrees(low), {"units": "degree"}),
            "high_degrees": ("transition", np.degrees(high), {"units": "degree"}),
            "count_low": ("transition", np.array([maps[b[0]].count for b in brackets], dtype=int)),
            "count_high": ("transition", np.array([maps[b[1]].count for b in brackets], dtype=int)),
            "off_axis_low": ("transition", np.array([maps[b[0]].off_axis for b in brackets], dtype=int)),
            "off_axis_high": ("transition", np.array([maps[b[1]].off_axis for b in brackets], dtype=int)),
            "transition_unresolved": ("transition", np.array(ends_unresolved, dtype=bool)),
            "transition_floor": ("transition", np.array([b[2] for b in brackets], dtype=float), dict(LENGTH)),
            "changed_low": (("transition", "component"), changed_low),
            "changed_high": (("transition", "component"), changed_high),
        },
        coords={
            "opening": ("opening", openings, {"units": "rad", "long_name": "opening Ψ"}),
            "opening_degrees": ("opening", np.degrees(openings), {"units": "degree"}),
            "component": np.arange(1, width + 1),
        },
        attrs={"floor": floor, "base_cells": base, "quantity": "excluded (adaptive map, exact in phi)"},
    )
