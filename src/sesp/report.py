"""Plain-text reports: what a sesp dataset holds."""

from __future__ import annotations

import math

import numpy as np

from .dataset import format_of, grid_of, pair_of
from .measures import RTOL, closed_excluded_area, excluded_area, lattice_excluded_area

__all__ = ["describe"]

SHOWN_POINTS = 12  # a collected sweep of at most this many points lists ⟨A_ex⟩ at each


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


def value_text(value: float, error: float, unit: str) -> str:
    """A value ± its error bar as every command prints it (``unit`` as "b^2")."""
    return f"{value:.8g} ± {error:#.2g}" + (f" {unit}" if unit else "")


def area_text(mean: float, error: float) -> str:
    """⟨A_ex⟩ ± its error bar as every command prints it."""
    return value_text(mean, error, "b^2")


def _area_line(ds, rtol: float) -> str:
    """sesp's A_ex with its error bar: as the file stores it, else :func:`sesp.excluded_area` of the file's
    particles, computed now; beside it the lattice count of a stored field, that field's own measure."""
    pair = pair_of(ds)
    if "mean_excluded_area_error" in ds:
        mean, error = float(ds.mean_excluded_area), float(ds.mean_excluded_area_error)
        text = f"A_ex     : {area_text(mean, error)} (of the {ds.attrs.get('excluded_area_of', 'polygons')})"
    else:
        best = excluded_area(pair.particle, None if pair.identical else pair.other, rtol=rtol, progress=False)
        mean, error = float(best.mean_excluded_area), float(best.mean_excluded_area_error)
        text = (
            f"A_ex     : {area_text(mean, error)} (of the {best.attrs['excluded_area_of']}; sesp.excluded_area"
            f" of the file's particles, rtol {best.attrs['rtol']:g})"
        )
    if "allowed" in ds:
        text += f"\n           the field's lattice count {lattice_excluded_area(ds):.8g} b^2 (its own measure)"
    stored = "closed_excluded_area" in ds
    closed = float(ds.closed_excluded_area) if stored else closed_excluded_area(pair, rtol=rtol)
    if math.isnan(closed):  # a Polyline has no closed shape
        return text
    return f"{text}\n           A_ex / A_ex(closed) = {mean / closed:.6g}; closed {closed:.6g} b^2"


def _topology_line(ds) -> str:
    """The certified count of excluded components (a bracket where undecided) and its resolution."""
    low, high = int(ds.excluded_components), int(ds.excluded_components_high)
    count = f"{low}" if low == high else f"{low}-{high} (undecided)"
    said = f"topology : {count} excluded components at resolution {ds.excluded_components.attrs['resolution']:g} b"
    return said + (f", at least resolution + {float(ds.component_rim):g} b deep" if "component_rim" in ds else "")


def _point_label(point, swept) -> str:
    """The swept parameters of one point of a collected sweep, openings in degrees."""
    parts = []
    for dim in swept:
        value = float(point[dim])
        parts.append(f"{dim} {math.degrees(value):g} deg" if dim.endswith("opening") else f"{dim} {value:g}")
    return ", ".join(parts)


def _sweep_lines(ds) -> list:
    """The swept parameters and their ranges, the grid, and ⟨A_ex⟩ ± its error bar at each point (up to
    ``SHOWN_POINTS`` of them)."""
    lines = [f"sweep    : {ds.attrs.get('sweep_name')}"]
    swept = ds.mean_excluded_area.dims if "mean_excluded_area" in ds else ()
    for dim in swept:
        values = ds[dim].values
        shown = np.degrees(values) if dim.endswith("opening") else values
        unit = " deg" if dim.endswith("opening") else ""
        lines.append(f"  {dim:7s}: {len(values)} values, {shown.min():g} to {shown.max():g}{unit}")
    grid = [f"{k}={ds.attrs[k]}" for k in ("nx", "ny", "nphi") if k in ds.attrs]
    if grid:
        lines.append(f"grid     : {' '.join(grid)}")
    if "mean_excluded_area_error" in ds and ds.mean_excluded_area.size <= SHOWN_POINTS:
        stacked = ds[["mean_excluded_area", "mean_excluded_area_error"]]
        stacked = stacked.stack(point=swept) if swept else stacked.expand_dims("point")
        for i in range(stacked.sizes["point"]):
            point = stacked.isel(point=i)
            text = area_text(float(point.mean_excluded_area), float(point.mean_excluded_area_error))
            label = _point_label(point, swept)
            lines.append(f"A_ex     : {text}" + (f" at {label}" if label else ""))
    return lines


def _lives_lines(ds) -> list:
    """Each excluded component followed over the opening: where it is listed, its depth, where it reaches 0."""
    others = [d for d in ds.life_depth.dims if d not in ("life", "opening")]
    stacked = ds[["life_depth", "life_end_estimate", "life_end_estimate_error"]]
    stacked = stacked.stack(slice_=others) if others else stacked.expand_dims("slice_")
    deg = np.degrees(ds.opening.values)
    lines = [f"components followed over the opening (depth: certified lower bound, b; resolution "
             f"{ds.excluded_components.attrs['resolution']:g} b):"]  # fmt: skip
    for k in range(stacked.sizes["slice_"]):
        one = stacked.isel(slice_=k)
        label = _point_label(one, others)
        for life in one.life.values:
            depth = one.life_depth.sel(life=life).values
            seen = np.isfinite(depth)
            if not seen.any():
                continue
            said = f"  {label + ': ' if label else ''}{int(life) + 1}: {deg[seen][0]:g} .. {deg[seen][-1]:g} deg, "
            said += f"depth {np.nanmax(depth):.3g} .. {depth[seen][-1]:.3g} b"
            end = float(one.life_end_estimate.sel(life=life))
            if np.isfinite(end):
                said += f"; reaches 0 at {end:.2f} ± {float(one.life_end_estimate_error.sel(life=life)):.2f} deg"
            lines.append(said)
    return lines


def describe(ds, *, rtol: float = RTOL) -> str:
    """A human-readable summary of any sesp dataset (scan, summary, point, sweep, Monte Carlo).

    A scan stores the field alone: its A_ex line is :func:`sesp.excluded_area` of its particles, computed
    to ``rtol`` (a few seconds; the default is ``sesp area``'s)."""
    attrs = ds.attrs
    kind = format_of(ds)
    lines = [f"{kind} file written by sesp {attrs.get('sesp_version')}"]
    if "particle_kind" in attrs:
        lines += [_particle_line(attrs, p) for p in ("particle", "other")]
    if kind == "sesp.sweep":
        lines += _sweep_lines(ds)
        if "life_depth" in ds:
            lines += _lives_lines(ds)
    elif kind == "sesp.monte_carlo":
        lines.append(f"samples  : {attrs['samples']}")
        lines.append(f"A_ex     : {float(ds.excluded_area):.6g} ± {float(ds.excluded_area_error):.2g} b^2")
    else:
        grid = grid_of(ds)
        lines.append(
            f"grid     : nx={grid.nx} ny={grid.ny} nphi={grid.nphi} half_width={grid.half_width:.6g} b"
            + (f", engine={attrs['engine']}" if "engine" in attrs else "")
        )
        lines.append(_area_line(ds, rtol))
        if "excluded_components" in ds:
            lines.append(_topology_line(ds))
    names = ", ".join(f"{name}{tuple(var.dims) if var.dims else ''}" for name, var in ds.data_vars.items())
    lines.append(f"variables: {names}")
    return "\n".join(lines)
