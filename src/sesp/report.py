"""Plain-text reports: what a sesp dataset holds."""

from __future__ import annotations

import math

import numpy as np

from .dataset import format_of, grid_of
from .measures import closed_excluded_area, lattice_excluded_area

__all__ = ["describe"]


def _particle_line(attrs, prefix) -> str:
    if attrs.get(f"{prefix}_kind") == "SeSP":
        shape = (
            f"SeSP n={attrs[f'{prefix}_n']:g} m={attrs[f'{prefix}_m']:g} aspect={attrs[f'{prefix}_aspect']:g} "
            f"opening={math.degrees(attrs[f'{prefix}_opening']):g} deg"
        )
    else:
        shape = f"Polyline of {attrs[f'{prefix}_segments']} segments"
    thickness = float(attrs.get(f"{prefix}_thickness", 0.0))
    thick = f", thickness={thickness:g} b" if thickness else ""
    return f"{prefix:9s}: {shape}, N={attrs[f'{prefix}_segments']}, length={attrs[f'{prefix}_length']:.6g} b{thick}"


def _area_line(ds) -> str:
    """A_ex with its error bar and what it is of (scanlines), or the lattice's count of a bare field."""
    area = lattice_excluded_area(ds)
    if "mean_excluded_area_error" in ds:
        area = float(ds.mean_excluded_area)
        text = f"A_ex     : {area:.8g} ± {float(ds.mean_excluded_area_error):.2g} b^2"
        text += f" (scanlines, {ds.attrs.get('excluded_area_of', 'polygons')})"
    else:
        text = f"A_ex     : {area:.8g} b^2 (lattice count; `sesp area` gives A_ex with an error bar)"
    try:
        closed = closed_excluded_area(ds)
    except ValueError:  # a Polyline has no closed shape
        return text
    return f"{text}\n           A_ex / A_ex(closed) = {area / closed:.6g}; closed {closed:.6g} b^2"


def _topology_line(ds) -> str:
    """The certified count of excluded components (a bracket where undecided) and its resolution."""
    low, high = int(ds.excluded_components), int(ds.excluded_components_high)
    count = f"{low}" if low == high else f"{low}-{high} (undecided)"
    return f"topology : {count} excluded components at resolution {ds.excluded_components.attrs['resolution']:g} b"


def _sweep_lines(ds) -> list:
    lines = [f"sweep    : {ds.attrs.get('sweep_name')}"]
    for dim in ds.dims:
        if dim in ("phi", "y", "x", "component"):
            continue
        values = ds[dim].values
        shown = np.degrees(values) if dim.endswith("opening") else values
        unit = " deg" if dim.endswith("opening") else ""
        lines.append(f"  {dim:7s}: {len(values)} values, {shown.min():g} to {shown.max():g}{unit}")
    grid = [f"{k}={ds.attrs[k]}" for k in ("nx", "ny", "nphi") if k in ds.attrs]
    if grid:
        lines.append(f"grid     : {' '.join(grid)}")
    return lines


def describe(ds) -> str:
    """A human-readable summary of any sesp dataset (scan, summary, point, sweep, Monte Carlo)."""
    attrs = ds.attrs
    kind = format_of(ds)
    lines = [f"{kind} file written by sesp {attrs.get('sesp_version')}"]
    if "particle_kind" in attrs:
        lines += [_particle_line(attrs, p) for p in ("particle", "other")]
    if kind == "sesp.sweep":
        lines += _sweep_lines(ds)
    elif kind == "sesp.monte_carlo":
        lines.append(f"samples  : {attrs['samples']}")
        lines.append(f"A_ex     : {float(ds.excluded_area):.6g} ± {float(ds.excluded_area_error):.2g} b^2")
    else:
        grid = grid_of(ds)
        lines.append(
            f"grid     : nx={grid.nx} ny={grid.ny} nphi={grid.nphi} half_width={grid.half_width:.6g} b"
            + (f", engine={attrs['engine']}" if "engine" in attrs else "")
        )
        lines.append(_area_line(ds))
        if "excluded_components" in ds:
            lines.append(_topology_line(ds))
    names = ", ".join(f"{name}{tuple(var.dims) if var.dims else ''}" for name, var in ds.data_vars.items())
    lines.append(f"variables: {names}")
    return "\n".join(lines)
