"""Each kernel's Python body gives what its compiled form gives, on the arguments a real computation passes it.

numba compiles a kernel's Python source; running that source as Python (``kernel.py_func``) on the same
arguments must write the same outputs and return the same values. This checks that nothing in a kernel
depends on a compiled-only behaviour (integer wrap-around, a float rounding, an unchecked index) and lets
coverage see the kernel's top-level lines, which it cannot trace in compiled code.
"""

import copy
import math

import numpy as np

import sesp.kernels.cells
import sesp.kernels.depth
import sesp.kernels.orientations
from sesp import SeSP, certified_components
from sesp.kernels.common import find_root, sort_first


def _same(a, b) -> bool:
    if isinstance(a, tuple | list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, np.ndarray):
        return a.dtype == np.asarray(b).dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    return a == b or (isinstance(a, float) and math.isnan(a) and math.isnan(b))


def _copied(value):
    """A deep copy that keeps each array's read-only flag: numba compiles read-only and writable arrays as
    different types, and a copy that changed the flag would compile the kernel again for it."""
    if isinstance(value, tuple) and hasattr(value, "_fields"):  # a named tuple: the kernels' structured arguments
        return type(value)(*(_copied(v) for v in value))
    if isinstance(value, tuple | list):
        return type(value)(_copied(v) for v in value)
    if isinstance(value, np.ndarray):
        copy_ = value.copy()
        copy_.flags.writeable = value.flags.writeable
        return copy_
    return copy.deepcopy(value)


def _recorded(monkeypatch, owner, name, most: int = 4) -> list:
    """Record the arguments of the first ``most`` calls of ``owner.name`` (copied before the kernel writes
    into them)."""
    kernel, calls = getattr(owner, name), []

    def recording(*args):
        if len(calls) < most:
            calls.append(_copied(args))
        return kernel(*args)

    monkeypatch.setattr(owner, name, recording)
    return calls


def _assert_body_matches(kernel, args):
    compiled, python = _copied(args), _copied(args)
    assert _same(kernel(*compiled), kernel.py_func(*python))
    assert _same(compiled, python)  # the outputs written into the arguments


def test_union_find_and_insertion_sort_bodies():
    rng = np.random.default_rng(3)
    values = rng.normal(size=12)
    for kernel in (sort_first, sort_first.py_func):
        v = values.copy()
        kernel(v, 9)
        assert np.array_equal(v[:9], np.sort(values[:9])) and np.array_equal(v[9:], values[9:])
    parent = np.array([0, 0, 1, 2, 3, 5, 5, 6])  # a chain 4 -> 3 -> 2 -> 1 -> 0, and 7 -> 6 -> 5
    for kernel in (find_root, find_root.py_func):
        p = parent.copy()
        assert kernel(p, 4) == 0 and kernel(p, 7) == 5 and kernel(p, 0) == 0
        assert p[4] == 2 and p[7] == 5  # paths halved on the way
    _assert_body_matches(find_root, (parent.copy(), 4))


def test_certified_engine_kernel_bodies(monkeypatch):
    kernels = {
        (sesp.kernels.orientations, "windows_at"): sesp.kernels.orientations.windows_at,
        (sesp.kernels.orientations, "clearance_at"): sesp.kernels.orientations.clearance_at,
        (sesp.kernels.depth, "cover_at"): sesp.kernels.depth.cover_at,
        (sesp.kernels.cells, "leaf_edges"): sesp.kernels.cells.leaf_edges,
        (sesp.kernels.cells, "components"): sesp.kernels.cells.components,
        (sesp.kernels.cells, "adjacency"): sesp.kernels.cells.adjacency,
        (sesp.kernels.cells, "disk_components"): sesp.kernels.cells.disk_components,
        (sesp.kernels.cells, "corridors"): sesp.kernels.cells.corridors,
    }
    calls = {key: _recorded(monkeypatch, *key) for key in kernels}
    certified_components(SeSP(n=2, opening=math.radians(150)), resolution=1e-2, base=8, segments=32)
    certified_components(SeSP(n=4, opening=0.0), resolution=1e-1, base=8, segments=16)  # a closed curve
    for key, kernel in kernels.items():
        assert calls[key], f"{key[1]} was not called"
        for args in calls[key]:
            _assert_body_matches(kernel, args)


def test_lattice_kernel_bodies(monkeypatch):
    from sesp import Grid, analyze, scan
    from sesp.kernels import hull, orientations, overlap, scanline
    from sesp.measures import scanline_excluded_area
    from sesp.orientations import allowed_orientations, blocked_orientations

    kernels = {
        (overlap, "raster_slices_serial"): overlap.raster_slices_serial,
        (overlap, "direct_slices"): overlap.direct_slices,
        (hull, "mutual_hull_slices"): hull.mutual_hull_slices,
        (scanline, "scanline_lengths"): scanline.scanline_lengths,
        # Python wrappers, recorded for their arguments (a kernel other kernels call cannot be replaced)
        (orientations, "blocked_intervals"): orientations.blocked_intervals,
        (orientations, "allowed_measures"): orientations.allowed_measures,
    }
    calls = {key: _recorded(monkeypatch, *key, most=2) for key in kernels}
    asp = SeSP(n=2, opening=math.radians(150))
    grid = Grid(12, nphi=4)
    analyze(asp, grid, segments=12, keep=["classes"])
    scan(asp, grid, segments=12, engine="direct")
    scanline_excluded_area(asp, segments=12, nphi=4, rows=8)
    blocked_orientations(asp, 0.3, 0.1, segments=12)
    allowed_orientations(asp, [0.3, 0.9], [0.1, 0.2], segments=12)
    for key, kernel in kernels.items():
        assert calls[key], f"{key[1]} was not called"
        for args in calls[key]:
            if key[0] is not orientations:
                _assert_body_matches(kernel, args)
    v1, v2, tx, ty, slack, *contact = calls[orientations, "blocked_intervals"][0]
    spans2, contact = orientations.radial_spans(v2), float(contact[0] if contact else 0.0)
    _assert_body_matches(orientations.blocked_angles, (v1, v2, spans2, float(tx), float(ty), slack, contact))
    v1, v2, xs, ys, slack, gap, *contact = calls[orientations, "allowed_measures"][0]
    contact = float(contact[0] if contact else 0.0)
    args = (v1, v2, orientations.radial_spans(v2), xs, ys, slack, gap, contact, np.empty(len(xs)))
    _assert_body_matches(orientations.allowed_angle_at, args)
    # the raster's work is done by raster_phi, which only compiled code calls: run one slice of it both ways
    v1, v2, cos_phi, sin_phi, xs, ys, delta, contact, count, out = calls[overlap, "raster_slices_serial"][0]
    dlen = np.empty(len(v1) - 1)
    overlap.segment_lengths(v1, dlen)
    for k in range(len(cos_phi)):
        args = (v1, dlen, v2, cos_phi[k], sin_phi[k], xs, ys, delta, contact, count, out[k])
        _assert_body_matches(overlap.raster_phi, args)
