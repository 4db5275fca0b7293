"""Allowed channels thinner than a map's cells, certified by following them with clearance disks.

An allowed channel through the excluded set E thinner than a map's cells is
seen only at the few nodes that fall in it (allowed slivers enclosed by E),
and the bodies on either side are joined wherever no node did: the ASP's
lens and body for small Ψ, parted by two crescents y·Ψ wide at a distance y
from the particle's centre, are one body on a base grid of 97 cells below
about 1°. The persistence rule cannot part them there: the channel ends at
the centre's pinch, and behind it, where the crescents are thinner than the
cells, the two bodies look joined over a stretch h/Ψ long.

So the channel is followed from each sliver, not sampled. At an allowed
position p the curves are farther apart than c at some orientation (the
middle of :func:`sesp.maps.widest_window`'s window, less the contact
distance), so the disk of radius c about p is allowed (the clearance
certificate of :mod:`sesp.maps`; in a thin channel the middle of the window
is where the curves are farthest apart). The next position is taken 1.5·c
ahead, in the direction within 45° of the last step whose clearance c' is
largest (the channel's middle), if c' > 0.5·c, so that the two disks
overlap; otherwise 0.9·c ahead, where any c' > 0 does. Each step thus
extends a chain of overlapping allowed disks: a certified allowed path. It is followed both
ways from the sliver until the channel is as wide as the cells (the grid
sees it from there), or narrower than a tenth of the floor (a pinch), or no
direction ahead is allowed (the channel ends, or turns sharper than the
directions tried), or it leaves the pair's reach. The ASP's crescents at
Ψ = 0.3125° (256 segments, 97 cells) are followed from the outside of the
set to 0.007 b from the centre, where the disks are 1e-5 b wide (a floor of
1e-4 b): the rule judges the rest of the way to the centre's pinch.

A map then leaves out of E every node whose cell meets a disk of the path
(:func:`meets`), on every window, when it counts components: the cells a
proven allowed path crosses hold no single body, and the bodies on either
side are apart on every grid, up to where the path ends. Each such node is
then given, for its area, to the component of a neighbouring node on the
same side of the path as itself (:func:`same_side`). What this proves: each
disk is allowed. What it does not: that the channel continues past where the
path stops.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from .kernels.orientations import chunk_boxes, chunk_count, clearance, widest_windows
from .orientations import ANGLE_GAP, SCREEN_SLACK

__all__ = ["clearance_radii", "traced_channels", "meets", "same_side"]

# Steps, in clearance radii c, and the radius the next position needs so that its disk overlaps this one's.
STEPS = ((1.5, 0.5 + 1e-3), (0.9, 0.0))
AHEAD = np.radians(np.linspace(-45.0, 45.0, 7))  # directions tried about the last step
AROUND = np.linspace(0.0, 2 * math.pi, 24, endpoint=False)  # directions tried at a sliver, to find the channel
MAX_STEPS = 20000  # positions per path at most


def clearance_radii(pair, x, y, cap) -> np.ndarray:
    """Radius (b) of the disk about each position (x, y) proven allowed by the clearance certificate, at most
    ``cap``: the curves' distance at the middle of the widest window, less the contact distance; 0 where the
    position is excluded."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    y = np.atleast_1d(np.asarray(y, dtype=float))
    v1, v2 = pair.vertices1, pair.vertices2
    width, middle, _ = widest_windows(v1, v2, x, y, SCREEN_SLACK, ANGLE_GAP, pair.contact)
    out = np.zeros(len(x))
    boxes1 = chunk_boxes(v1, np.empty((chunk_count(v1), 4)))
    moved, boxes2 = np.empty_like(v2), np.empty((chunk_count(v2), 4))
    limit = float(cap) + pair.contact
    for p in np.flatnonzero(width > 0.0):
        distance = clearance(v1, boxes1, v2, x[p], y[p], middle[p], limit, moved, boxes2)
        out[p] = max(min(distance - pair.contact, float(cap)), 0.0)
    return out


def traced_channels(pair, seeds, cell: float, floor: float, tick=None) -> np.ndarray:
    """(k, 5) array of certified allowed disks along the channels through the ``seeds``: centre x, y and
    radius (b), and the direction of the path there (a unit vector).

    ``seeds``: (m, 2) allowed positions (b) enclosed by the excluded set on cells of side ``cell``. Each is
    followed both ways (module notes) while the channel is narrower than ``cell`` and wider than ``floor`` / 10;
    a seed within ``cell`` of a disk already traced is not followed again. ``tick``: called with the number of
    positions classified after each batch (a progress bar's ``update``).
    """
    tick = tick or (lambda count: None)
    disks = []
    for x, y in np.asarray(seeds, dtype=float).reshape(-1, 2):
        if disks and np.min(np.hypot(*(np.array(disks)[:, :2] - (x, y)).T)) < cell:
            continue
        radius = float(clearance_radii(pair, x, y, cell)[0])
        tick(1)
        if not 0.0 < radius < cell:
            continue
        directions = _channel_directions(pair, x, y, radius, cell, tick)
        if not directions:
            continue
        disks.append((x, y, radius, math.cos(directions[0]), math.sin(directions[0])))
        for direction in directions:
            disks += _followed(pair, x, y, radius, direction, cell, floor, tick)
    return np.array(disks, dtype=float).reshape(-1, 5)


def _channel_directions(pair, x, y, radius, cell, tick):
    """The directions (radians) from a seed to the channel's two arms: the best of the directions tried
    around it (0.9·radius away, so that any allowed one's disk overlaps the seed's), and the best of those
    pointing away from it (more than 90° off); fewer where none is allowed."""
    step = STEPS[-1][0] * radius
    c = clearance_radii(pair, x + step * np.cos(AROUND), y + step * np.sin(AROUND), cell)
    tick(len(AROUND))
    if not c.max() > 0.0:
        return []
    first = int(np.argmax(c))
    away = np.cos(AROUND - AROUND[first]) < 0.0
    directions = [AROUND[first]]
    if (c * away).max() > 0.0:
        directions.append(AROUND[int(np.argmax(c * away))])
    return directions


def _followed(pair, x, y, radius, direction, cell, floor, tick):
    """The disks of a path from (x, y) (radius certified) heading ``direction`` (radians), until it stops."""
    out = []
    reach = pair.reach + cell
    for _ in range(MAX_STEPS):
        for length, needed in STEPS:
            angles = direction + AHEAD
            xs, ys = x + length * radius * np.cos(angles), y + length * radius * np.sin(angles)
            c = clearance_radii(pair, xs, ys, cell)
            tick(len(AHEAD))
            best = int(np.argmax(c))
            if c[best] > needed * radius:
                break
        else:
            break  # nothing ahead is allowed: the channel ends here, or turns sharper than we look
        x, y, radius, direction = xs[best], ys[best], float(c[best]), angles[best]
        out.append((x, y, radius, math.cos(direction), math.sin(direction)))
        if radius >= cell or radius < floor / 10 or math.hypot(x, y) > reach:
            break
    return out


def meets(disks: np.ndarray, x, y, h: float) -> np.ndarray:
    """Per node (x, y; b): whether its square cell of side ``h`` meets one of the ``disks``
    (:func:`traced_channels`)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    out = np.zeros(x.shape, dtype=bool)
    if not len(disks) or not x.size:
        return out
    tree = cKDTree(disks[:, :2])
    reach = h / math.sqrt(2) + float(disks[:, 2].max())
    for i, near in enumerate(tree.query_ball_point(np.column_stack([x.ravel(), y.ravel()]), reach)):
        if not near:
            continue
        d = disks[near]
        dx = np.maximum(np.abs(d[:, 0] - x.flat[i]) - h / 2, 0.0)
        dy = np.maximum(np.abs(d[:, 1] - y.flat[i]) - h / 2, 0.0)
        out.flat[i] = bool(np.any(dx * dx + dy * dy < d[:, 2] ** 2))
    return out


def same_side(disks: np.ndarray, x, y, dx, dy) -> np.ndarray:
    """Per point (x, y; b) and each offset (dx, dy) (b, shape (m,)): whether the point moved by the offset
    lies on the same side of the path as the point, at the disk nearest to the point, (n, m)."""
    points = np.column_stack([np.ravel(x), np.ravel(y)])
    _, k = cKDTree(disks[:, :2]).query(points)
    d = disks[k]
    rx, ry = points[:, 0] - d[:, 0], points[:, 1] - d[:, 1]
    side = d[:, 3] * ry - d[:, 4] * rx
    mx = rx[:, None] + np.asarray(dx)[None, :]
    my = ry[:, None] + np.asarray(dy)[None, :]
    moved = d[:, 3, None] * my - d[:, 4, None] * mx
    return np.sign(moved) == np.sign(side)[:, None]
