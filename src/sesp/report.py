"""Plain-text reports: what a sesp dataset holds, and topology results over the opening."""

from __future__ import annotations

import math

import numpy as np

from .dataset import format_of, grid_of
from .measures import closed_excluded_area, lattice_excluded_area
from .topology import RESOLVED_PEAK, TopologyResult

__all__ = ["format_result", "describe"]


def count_runs(openings, counts):
    """Runs of equal count: (first Ψ, last Ψ, count, index of the middle sample)."""
    runs, start = [], 0
    for i in range(1, len(counts) + 1):
        if i == len(counts) or counts[i] != counts[start]:
            runs.append((openings[start], openings[i - 1], int(counts[start]), (start + i - 1) // 2))
            start = i
    return runs


def format_result(result: TopologyResult, family=None) -> str:
    """A plain-text report: Ψ intervals with counts and areas, then the transitions."""
    axis = result.quantity.endswith("(axis)")
    unit = "b^2" if result.quantity == "excluded" else "b^2 rad"
    measured = "peak radius at middle sample (b)" if axis else f"areas at middle sample ({unit})"
    lines = []
    if family is not None:
        lines.append(f"family: {family}")
    lines.append(f"{result.quantity} components over the opening (first pass; degrees)")
    lines.append(f"{'Psi from':>9} {'Psi to':>8} {'count':>6} {'shortest' if axis else 'thinnest':>9}  {measured}")
    thinnest = result.thinnest if result.thinnest is not None else np.full(len(result.openings), math.inf)
    for a, b, count, mid in count_runs(result.openings, result.counts):
        areas = ", ".join(f"{v:.4g}" for v in result.areas[mid]) or "-"
        run = (result.openings >= a) & (result.openings <= b)
        thin = float(thinnest[run].min())
        thin = "-" if math.isinf(thin) else f"{thin:.1f}"
        lines.append(
            f"{math.degrees(a):9.2f} {math.degrees(b):8.2f} {count:6d} {thin:>9}  {areas}"
            f"   (at {math.degrees(result.openings[mid]):.1f})"
        )
    if axis:
        lines.append(
            f"(shortest: fewest axis nodes in a counted component over the interval;"
            f" below {RESOLVED_PEAK:g} the count is near the axis sampling's reach)"
        )
    else:
        lines.append(
            f"(thinnest: smallest inscribed radius of a counted component over the interval, in node spacings;"
            f" below {RESOLVED_PEAK:g} the count is near the grid's reach)"
        )
    for res, transitions in result.transitions.items():
        where = f"{res[0]} axis nodes, exact in phi" if axis else f"grid nx={res[0]} ny={res[1]} nphi={res[2]}"
        lines.append(f"transitions on {where} (degrees; radians):")
        if not transitions:
            lines.append("  none")
        for t in transitions:
            lines.append(
                f"  * {t.count_low} -> {t.count_high} at Psi in [{math.degrees(t.low):.2f}, {math.degrees(t.high):.2f}]"
                f" deg = {math.degrees(t.opening):.2f} +- {math.degrees(0.5 * (t.high - t.low)):.2f}"
                f"  ({t.low:.4f} to {t.high:.4f} rad)"
                + (
                    ""
                    if t.resolved
                    else (
                        f"  [sampling-limited: a component {t.thinnest:.1f} axis nodes short]"
                        if axis
                        else f"  [grid-limited: a component {t.thinnest:.1f} nodes thin; moves with resolution]"
                    )
                )
            )
    return "\n".join(lines)


def format_map_transitions(result, family=None) -> str:
    """A plain-text report of :func:`sesp.maps.map_transitions`: Ψ intervals with counts, then the brackets."""
    lines = [f"family: {family}"] if family is not None else []
    lines.append("excluded components on adaptive maps, exact in phi (degrees)")
    lines.append(f"{'Psi from':>9} {'Psi to':>8} {'count':>6}")
    openings, counts = result.opening.values, result["count"].values
    for a, b, count, _ in count_runs(openings, counts):
        lines.append(f"{math.degrees(a):9.2f} {math.degrees(b):8.2f} {count:6d}")
    lines.append("transitions (degrees):")
    if not result.sizes["transition"]:
        lines.append("  none")
    for t in range(result.sizes["transition"]):
        unresolved = "transition_unresolved" in result and bool(result.transition_unresolved[t])
        finer = "transition_floor" in result and float(result.transition_floor[t]) != result.attrs.get("floor")
        lines.append(
            f"  * {map_change(result, t)} at Psi in"
            f" [{float(result.low_degrees[t]):.3f}, {float(result.high_degrees[t]):.3f}]"
            + (f" (floor {float(result.transition_floor[t]):g} b)" if finer else "")
            + ("  (unresolved: a component that changes in it is seen only at the floor, encloses allowed slivers"
               " that may part it, is thinner than the polylines depart from the curves, or was joined so that"
               " the partition is its own mirror image)" if unresolved else "")
        )  # fmt: skip
    return "\n".join(lines)


def map_change(result, t) -> str:
    """Transition ``t`` of :func:`sesp.maps.map_transitions` as "count -> count", with the number of
    components off the x-axis when only that changed (a step bisected for it)."""
    change = f"{int(result.count_low[t])} -> {int(result.count_high[t])}"
    if "off_axis_low" not in result or result.count_low[t] != result.count_high[t]:
        return change
    return f"{change} (off axis {int(result.off_axis_low[t])} -> {int(result.off_axis_high[t])})"


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
    """A human-readable summary of any sesp dataset (scan, summary, point, sweep, Monte Carlo, map)."""
    attrs = ds.attrs
    kind = format_of(ds)
    lines = [f"{kind} file written by sesp {attrs.get('sesp_version')}"]
    if "particle_kind" in attrs:
        lines += [_particle_line(attrs, p) for p in ("particle", "other")]
    if kind == "sesp.sweep":
        lines += _sweep_lines(ds)
    elif kind == "sesp.map":
        lines.append(
            f"map      : base {attrs['base_cells']} cells, floor {attrs['floor']:g} b, zoom {attrs['zoom']},"
            f" {attrs['positions']} positions"
        )
        areas = ", ".join(f"{a:.4g}" for a in ds.area.values)
        lines.append(f"excluded : {ds.sizes['component']} components, areas {areas or '-'} b^2")
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
    names = ", ".join(f"{name}{tuple(var.dims) if var.dims else ''}" for name, var in ds.data_vars.items())
    lines.append(f"variables: {names}")
    return "\n".join(lines)
