"""The scanline kernel's lengths against a brute-force union of every pair's cut (docs/design.md §8).

The kernel counts parallelograms over a line from the crossings of the few edges that step the count (and
joins the capsules of those edges for thick curves); the reference here cuts every P_ij, dilated by the
contact distance, with the line and measures the union of the N² intervals.
"""

import math

import numpy as np
import pytest

from sesp import SeSP
from sesp.kernels import scanline
from sesp.kernels.common import rotate


def chord(points, y):
    """The x-extent of the convex polygon ``points`` (closed) on the line at height y, or None."""
    xs = []
    for (ax, ay), (bx, by) in zip(points, np.roll(points, -1, axis=0), strict=True):
        if (ay - y) * (by - y) > 0:
            continue
        if ay == by:
            xs += [ax, bx]
        else:
            xs.append(ax + (bx - ax) * (y - ay) / (by - ay))
    return (min(xs), max(xs)) if xs else None


def dilated_cut(corners, contact, y):
    """The cut of the parallelogram ``corners`` dilated by a disk of radius ``contact``: the hull of the cuts
    of the parallelogram, its edges' rectangles and its corners' disks."""
    pieces = [chord(corners, y)]
    for p, q in zip(corners, np.roll(corners, -1, axis=0), strict=True):
        for c in (p, q):
            if abs(y - c[1]) <= contact:
                w = math.sqrt(contact**2 - (y - c[1]) ** 2)
                pieces.append((c[0] - w, c[0] + w))
        e = q - p
        if contact > 0 and np.hypot(*e) > 0:
            n = np.array([-e[1], e[0]]) / np.hypot(*e) * contact
            pieces.append(chord(np.array([p - n, q - n, q + n, p + n]), y))
    pieces = [c for c in pieces if c is not None]
    return (min(c[0] for c in pieces), max(c[1] for c in pieces)) if pieces else None


def brute_force_length(a1, b2, contact, y):
    cuts = []
    for i in range(len(a1) - 1):
        for j in range(len(b2) - 1):
            corners = np.array([a1[i] - b2[j], a1[i + 1] - b2[j], a1[i + 1] - b2[j + 1], a1[i] - b2[j + 1]])
            cut = dilated_cut(corners, contact, y)
            if cut is not None:
                cuts.append(cut)
    total, hi = 0.0, -math.inf
    for lo, end in sorted(cuts):
        if end > hi:
            total += end - max(lo, hi)
            hi = end
    return total


def turned(vertices, angle):
    out = np.empty_like(vertices)
    rotate(vertices, math.cos(angle), math.sin(angle), out)
    return out


def curves():
    """Random open polylines, some pairs identical (flat P_ij at φ = π), and a SeSP."""
    rng = np.random.default_rng(3)
    walks = [np.cumsum(rng.normal(size=(k, 2)), axis=0) * 0.4 for k in (2, 4, 7, 9)]
    asp = SeSP(n=4, opening=math.pi / 2).polyline(12).vertices
    return [(walks[0], walks[1]), (walks[2], walks[2]), (walks[3], walks[1]), (asp, asp)]


@pytest.mark.parametrize("contact", [0.0, 0.07])
@pytest.mark.parametrize("phi", [0.3, math.pi, 4.0])
@pytest.mark.parametrize("case", range(4))
def test_row_lengths_equal_the_union_of_every_pairs_cut(case, phi, contact):
    """Lines across the whole set, and lines from a corner a_i − b_j up (the first exactly through it, where
    two edges meet): the lengths agree with the brute force to 1e-12 b."""
    v1, v2 = curves()[case]
    a1, b2 = turned(v1, 0.1), turned(v2, 0.1 + phi)
    corners = (a1[:, None, 1] - b2[None, :, 1]).ravel()
    top, bottom = corners.max() + contact, corners.min() - contact
    corner = float(np.sort(corners)[len(corners) // 3])
    rows = 30
    for y0 in (bottom, corner):
        h = (top - y0) / (rows - 1)
        out = np.zeros(rows)
        scanline.row_lengths(a1, b2, y0, h, contact, out)
        expected = [brute_force_length(a1, b2, contact, y0 + r * h) for r in range(rows)]
        assert max(expected) > 0.1
        np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)


def test_a_line_through_a_corner_is_crossed_although_rounding_puts_it_a_line_higher():
    """y0 + 2h = 0.30000000000000004 exactly at a corner, where (corner − y0)/h rounds to just above 2: the
    edges from that corner still cross line 2."""
    y0, h = 0.1, 0.1
    corner = y0 + 2 * h
    assert (corner - y0) / h > 2
    a1 = np.array([[-1.0, -0.6], [0.2, corner], [0.9, 1.3], [1.5, 0.4]])
    b2 = np.array([[0.0, 0.0], [0.3, -0.35], [0.5, 0.2]])
    out = np.zeros(12)
    scanline.row_lengths(a1, b2, y0, h, 0.0, out)
    expected = [brute_force_length(a1, b2, 0.0, y0 + r * h) for r in range(12)]
    assert expected[2] > 0.1
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)


def test_a_line_with_many_crossings():
    """A zigzag of 120 teeth against a short tilted needle: each line holds far more crossings than a SeSP
    pair's (the sort takes its other branch); the lengths still equal the brute force."""
    k = np.arange(241)
    zigzag = np.column_stack([0.02 * k, np.where(k % 2, 0.5, -0.5)])
    needle = np.array([[0.0, 0.0], [0.004, 0.01]])
    rows = 9
    y0, h = -0.45, 0.9 / (rows - 1)
    out = np.zeros(rows)
    scanline.row_lengths(zigzag, needle, y0, h, 0.0, out)
    expected = [brute_force_length(zigzag, needle, 0.0, y0 + r * h) for r in range(rows)]
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)
