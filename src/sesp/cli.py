"""The ``sesp`` command. Angles on the command line are in degrees."""

from __future__ import annotations

import argparse
import logging
import math
import sys
from pathlib import Path

__all__ = ["main"]

log = logging.getLogger("sesp")

USER_ERRORS = (ValueError, MemoryError, OSError, KeyError)
CERTIFIED_KERNELS = ("orientations", "runs", "tips", "depth", "cells")  # the kernel modules a certified count compiles


def kernels_cached(modules) -> bool:
    """True when numba's on-disk cache holds compiled kernels of each of ``modules`` (names in
    :mod:`sesp.kernels`) for this install."""
    import numba

    from . import kernels

    where = Path(numba.config.CACHE_DIR) if numba.config.CACHE_DIR else Path(kernels.__file__).parent / "__pycache__"
    return all(any(where.rglob(f"{m}.*.nbi")) for m in modules)


def _announce_compile(*modules):
    """Say so where the kernels of ``modules`` (the command's own) are not compiled yet."""
    if not kernels_cached(modules):
        print("sesp: compiling numba kernels (first run only, about a minute)...", file=sys.stderr)


def _add_shape_args(p: argparse.ArgumentParser, segments: int | None = 256):
    p.add_argument("--n", type=float, default=2.0, help="degree along x (default 2)")
    p.add_argument("--m", type=float, default=None, help="degree along y (default: n)")
    p.add_argument("--aspect", type=float, default=1.0, help="aspect ratio A = a/b (default 1)")
    p.add_argument("--thickness", type=float, default=0.0, help="particle thickness D in b (default 0: thin)")
    refined = "refined from 256" if segments is None else f"{segments}"
    p.add_argument("--segments", type=int, default=segments, help=f"polyline segments N (default {refined})")


def _add_vertices_arg(p: argparse.ArgumentParser):
    p.add_argument(
        "--vertices",
        type=Path,
        default=None,
        metavar="FILE",
        help="a polyline of your own instead of a SeSP: a text file of x y rows (b), its centre at 0 0",
    )


def _add_scan(sub):
    p = sub.add_parser("scan", help="scan the (x, y, φ) grid of one particle pair and save it")
    _add_shape_args(p)
    p.add_argument("--opening", type=float, default=90.0, help="opening Ψ in degrees (default 90)")
    _add_vertices_arg(p)
    p.add_argument("--nx", type=int, default=256, help="cells along x (default 256)")
    p.add_argument("--ny", type=int, default=None, help="cells along y (default: nx)")
    p.add_argument("--nphi", type=int, default=128, help="orientations (default 128)")
    p.add_argument(
        "--engine",
        choices=("raster", "direct"),
        default="raster",
        help="raster: Minkowski parallelograms (fast, default); direct: every segment pair (reference)",
    )
    p.add_argument("--crossings", action="store_true", help="also store crossing counts")
    p.add_argument("-o", "--output", required=True, type=Path, help="netCDF file to write")
    p.set_defaults(func=_cmd_scan)


def _shape_from_args(args, opening_deg: float):
    from .checks import check_opening
    from .shape import SeSP

    check_opening(opening_deg, degrees=True)
    return SeSP(n=args.n, m=args.m, aspect=args.aspect, opening=math.radians(opening_deg), thickness=args.thickness)


def _cmd_scan(args) -> int:
    from .field import scan
    from .grid import Grid
    from .io import save

    particle = _particle_from_args(args)
    grid = Grid(args.nx, args.ny, args.nphi)
    _announce_compile("overlap", "hull")
    ds = scan(
        particle, grid, segments=args.segments, engine=args.engine, crossings=args.crossings, progress=not args.quiet
    )
    save(ds, args.output)
    if not args.quiet:
        print(f"wrote {args.output} (the field; `sesp area` gives A_ex with its error bar)")
    return 0


def _add_area(sub):
    p = sub.add_parser(
        "area", help="A_ex(φ) and ⟨A_ex⟩ with error bars, refined to --rtol; B₂ and the first isotropic instability"
    )
    _add_shape_args(p, segments=None)
    p.add_argument("--opening", type=float, default=90.0, help="opening Ψ in degrees (default 90)")
    _add_vertices_arg(p)
    p.add_argument("--rtol", type=float, default=1e-5, help="relative error bar of ⟨A_ex⟩ to reach (default 1e-5)")
    p.add_argument("--nphi", type=int, default=None, help="orientations (default: refined from 128)")
    p.add_argument(
        "--rows", type=int, default=None, help="line spacings, a multiple of 8 (default: refined from 2048, or 512)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object (per-φ values included)")
    p.set_defaults(func=_cmd_area)


def _particle_from_args(args):
    """The SeSP of the shape arguments, or the polyline of ``--vertices`` (with ``--thickness``)."""
    if args.vertices is None:
        return _shape_from_args(args, args.opening)
    return _polyline_from_file(args.vertices, args.thickness)


def _polyline_from_file(path, thickness: float):
    """The polyline of a text file of x y rows (b)."""
    import numpy as np

    from .shape import Polyline

    try:
        vertices = np.loadtxt(path, ndmin=2)
    except (OSError, ValueError) as err:
        raise ValueError(f"--vertices: cannot read {path} as rows of x y (b): {err}") from None
    return Polyline(vertices, thickness=thickness)


def _cmd_area(args) -> int:
    import json

    import numpy as np

    from .measures import excluded_area
    from .onsager import ORDER_NAMES, onsager_variables
    from .report import area_text

    particle = _particle_from_args(args)
    _announce_compile("overlap", "scanline")
    ds = excluded_area(
        particle, rtol=args.rtol, segments=args.segments, nphi=args.nphi, rows=args.rows, progress=not args.quiet
    )
    found = onsager_variables(ds)
    attrs = ds.attrs
    mean, error = float(ds.mean_excluded_area), float(ds.mean_excluded_area_error)
    leading = int(found.get("leading_instability", 0))
    density = float(found["instability_density"].sel(order=leading)) if leading else math.nan
    shape = {"vertices": str(args.vertices), "thickness": args.thickness} if args.vertices is not None else {
        "n": particle.n, "m": particle.m, "aspect": particle.aspect, "thickness": particle.thickness,
        "opening_deg": args.opening,
    }  # fmt: skip
    if args.json:
        result = {
            **shape,
            **{k: attrs[k] for k in ("excluded_area_of", "segments", "nphi", "rows", "rtol")},
            "converged": bool(attrs["converged"]),
            "units": {"lengths": "b", "areas": "b^2", "densities": "b^-2", "angles": "deg"},
            "mean_excluded_area": mean,
            "mean_excluded_area_error": error,
            "second_virial_coefficient": float(found["second_virial_coefficient"]),
            "second_virial_coefficient_error": float(found["second_virial_coefficient_error"]),
            "leading_instability": leading,
            "leading_instability_density": None if not leading else density,
            "phi_deg": np.degrees(ds.phi.values).tolist(),
            "phi_rad": ds.phi.values.tolist(),
            "excluded_area": ds.excluded_area.values.tolist(),
            "excluded_area_error": ds.excluded_area_error.values.tolist(),
        }
        print(json.dumps(result))
        return 0
    if args.vertices is None:
        what = f"n = {particle.n:g}, m = {particle.m:g}, aspect {particle.aspect:g}, opening {args.opening:g} deg"
    else:
        what = f"the polyline of {args.vertices}"
    what += f", thickness {args.thickness:g} b" if args.thickness else ""
    print(f"{what}: A_ex of the {attrs['excluded_area_of']}")
    print(f"  ({attrs['nphi']} orientations, {attrs['rows']} line spacings; rtol {args.rtol:g}"
          f" {'met' if attrs['converged'] else 'NOT met'})")  # fmt: skip
    print(f"<A_ex> = {area_text(mean, error)}")
    b2, b2_error = float(found["second_virial_coefficient"]), float(found["second_virial_coefficient_error"])
    print(f"B2     = {area_text(b2, b2_error)}")
    if leading:
        reduced = density * mean
        print(f"first isotropic instability: {ORDER_NAMES.get(leading, f'k = {leading}')} (k = {leading}) at"
              f" rho* = {density:.6g} b^-2 (rho* <A_ex> = {reduced:.4g})")  # fmt: skip
    else:
        print("first isotropic instability: none (no Fourier coefficient a_k significantly negative)")
    return 0


def _add_virial(sub):
    p = sub.add_parser(
        "virial", help="B₂ and B₃ with error bars, of one particle or of a mixture (--vertices FILE per species)"
    )
    _add_shape_args(p, segments=None)
    p.add_argument("--opening", type=float, default=90.0, help="opening Ψ in degrees (default 90)")
    p.add_argument(
        "--vertices", type=Path, action="append", default=None, metavar="FILE",
        help="a polyline of your own instead of a SeSP (rows of x y, b); give it once per species of a mixture",
    )  # fmt: skip
    p.add_argument("--fractions", type=float, nargs="+", default=None, help="mole fractions (default equal)")
    p.add_argument("--rtol", type=float, default=1e-5, help="relative error bar of each ⟨A_ex⟩ (default 1e-5)")
    p.add_argument("--b3-rtol", type=float, default=1e-3, help="relative error bar of B₃ to reach (default 1e-3)")
    p.add_argument("--nodes", type=int, default=None, help="B₃ lattice nodes (odd; default: refined from 129)")
    p.add_argument("--nphi", type=int, default=None, help="B₃ orientations (even; default: refined from 32)")
    p.add_argument("--no-b3", action="store_true", help="B₂ alone (seconds, where B₃ takes up to a minute)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_cmd_virial)


def _species_from_args(args) -> list:
    """The particles of ``sesp virial``: the SeSP of the shape arguments, or one polyline per ``--vertices``."""
    if not args.vertices:
        return [_shape_from_args(args, args.opening)]
    return [_polyline_from_file(path, args.thickness) for path in args.vertices]


def _shape_json(args, particles) -> dict:
    """What the particles are, for a JSON answer (angles in degrees)."""
    if getattr(args, "vertices", None):
        files = args.vertices if isinstance(args.vertices, list) else [args.vertices]
        return {"vertices": [str(f) for f in files], "thickness": args.thickness}
    particle = particles[0]
    return {"n": particle.n, "m": particle.m, "aspect": particle.aspect, "thickness": particle.thickness,
            "opening_deg": args.opening}  # fmt: skip


def _cmd_virial(args) -> int:
    import json

    from .report import value_text
    from .shape import DEFAULT_SEGMENTS
    from .virial import mixture_third_virial, second_virial

    species = _species_from_args(args)
    fractions = args.fractions if args.fractions is not None else [1 / len(species)] * len(species)
    if len(fractions) != len(species):
        raise ValueError(f"--fractions must give one mole fraction per species ({len(species)}), got {fractions}")
    _announce_compile("overlap", "scanline", "spectra")
    if args.no_b3:
        found = second_virial(species, fractions, rtol=args.rtol)
    else:
        found = mixture_third_virial(species, fractions, rtol=args.b3_rtol, b2_rtol=args.rtol, nodes=args.nodes,
                                     nphi=args.nphi, segments=args.segments or DEFAULT_SEGMENTS,
                                     progress=not args.quiet)  # fmt: skip
    out = {**_shape_json(args, species), "fractions": list(map(float, found.fraction.values)),
           "units": {"lengths": "b", "B2": "b^2", "B3": "b^4", "angles": "deg"}}  # fmt: skip
    names = ["second_virial_coefficient"]
    names += [] if args.no_b3 else ["third_virial_coefficient", "reduced_third_virial"]
    for name in names:
        out.update({name: float(found[name]), f"{name}_error": float(found[f"{name}_error"])})
    if not args.no_b3:
        out.update(b3_rtol=args.b3_rtol, b3_converged=bool(found.attrs["converged"]))
        out.update({k: found.attrs[k] for k in ("nodes", "nphi") if k in found.attrs})
    if args.json:
        print(json.dumps(out))
        return 0
    print(f"B2 = {value_text(out['second_virial_coefficient'], out['second_virial_coefficient_error'], 'b^2')}")
    if not args.no_b3:
        print(f"B3 = {value_text(out['third_virial_coefficient'], out['third_virial_coefficient_error'], 'b^4')}"
              f"{'' if out['b3_converged'] else f' (rtol {args.b3_rtol:g} NOT met)'}")  # fmt: skip
        print(f"B3 / B2^2 = {value_text(out['reduced_third_virial'], out['reduced_third_virial_error'], '')}")
    return 0


def _add_phases(sub):
    p = sub.add_parser(
        "phases",
        help="where the isotropic state turns unstable (each order, with bars) and the first transition, its kind",
    )
    _add_shape_args(p, segments=None)
    p.add_argument("--opening", type=float, default=90.0, help="opening Ψ in degrees (default 90)")
    _add_vertices_arg(p)
    p.add_argument("--rtol", type=float, default=1e-5, help="relative error bar of ⟨A_ex⟩ (default 1e-5)")
    p.add_argument(
        "--parsons-lee", action="store_true", help="the first transition in Parsons–Lee theory (thick particles)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_cmd_phases)


def _cmd_phases(args) -> int:
    import json

    from .measures import excluded_area
    from .onsager import ORDER_NAMES, first_transition, instabilities, particle_area
    from .report import value_text

    particle = _particle_from_args(args)
    _announce_compile("overlap", "scanline")
    area = excluded_area(particle, rtol=args.rtol, segments=args.segments, progress=not args.quiet)
    found = instabilities(area)
    covered = particle_area(particle) if args.parsons_lee else 0.0
    first = first_transition(area, particle_area=covered)
    order = int(first.transition_order)
    kind = "none" if order == 0 else ("continuous" if int(first.continuous) else "first order")
    rows = [{"order": int(k), "name": ORDER_NAMES.get(int(k), f"k = {int(k)}"),
             "a": float(found.a.sel(order=k)), "a_error": float(found.a_error.sel(order=k)),
             "density": _finite_or_none(found.density.sel(order=k)),
             "density_error": _finite_or_none(found.density_error.sel(order=k)),
             "reduced_density": _finite_or_none(found.reduced_density.sel(order=k))}
            for k in found.order.values]  # fmt: skip
    out = {**_shape_json(args, [particle]), "units": {"densities": "b^-2", "areas": "b^2", "angles": "deg"},
           "mean_excluded_area": float(area.mean_excluded_area),
           "mean_excluded_area_error": float(area.mean_excluded_area_error),
           "instabilities": rows, "leading_order": int(found.leading_order),
           "theory": "Parsons-Lee" if args.parsons_lee else "second virial", "particle_area": covered,
           "first_transition": {"order": order, "name": ORDER_NAMES.get(order, "none"), "kind": kind,
                                "density": _finite_or_none(first.transition_density),
                                "density_error": _finite_or_none(first.transition_density_error),
                                "ordered_density": _finite_or_none(first.ordered_density)}}  # fmt: skip
    if args.json:
        print(json.dumps(out))
        return 0
    print(f"<A_ex> = {value_text(out['mean_excluded_area'], out['mean_excluded_area_error'], 'b^2')}")
    print("isotropic instabilities, rho*_k = -2/a_k where a_k < 0 (none where a_k is not significantly negative):")
    for row in rows:
        said = "none" if row["density"] is None else value_text(row["density"], row["density_error"], "b^-2")
        print(f"  k = {row['order']} ({row['name']}): rho* = {said}")
    first_said = out["first_transition"]
    if order == 0:
        print("first transition: none (the isotropic state is stable at every density)")
    else:
        density = value_text(first_said["density"], first_said["density_error"], "b^-2")
        print(
            f"first transition ({out['theory']}): {first_said['name']} (k = {order}), {kind}, at rho = {density}"
            + ("" if kind == "continuous" else f", ordered phase at {first_said['ordered_density']:.6g} b^-2")
        )
    return 0


def _finite_or_none(value):
    """A float for JSON: None where it is NaN (no such density)."""
    value = float(value)
    return value if math.isfinite(value) else None


def _add_info(sub):
    p = sub.add_parser("info", help="print the parameters and excluded area of a saved scan")
    p.add_argument("file", type=Path, help="any file sesp wrote: scan, summary, sweep point or collected sweep")
    p.add_argument(
        "--rtol",
        type=float,
        default=1e-5,
        help="for a scan, which stores the field alone: the relative error bar of the A_ex computed for its"
        " particles (default 1e-5, as `sesp area`)",
    )
    p.set_defaults(func=_cmd_info)


def _cmd_info(args) -> int:
    from .io import load
    from .report import describe

    print(describe(load(args.file), rtol=args.rtol))
    return 0


def _add_topology(sub):
    p = sub.add_parser(
        "topology",
        help="the certified count of excluded components at one opening, or over the opening Ψ and where it changes",
        description="The certified count of excluded components at one opening (seconds at the defaults), or over "
        "the opening Ψ with each change bracketed and named (an event of the eroded excluded set, or a "
        "component's depth crossing resolution + rim) and each component followed over Ψ (4 to 8 minutes for "
        "0-360 degrees on 2 cores at the defaults; counts are kept in --cache, so Ctrl-C keeps what is done and a "
        "rerun resumes).",
    )
    _add_shape_args(p)
    _add_vertices_arg(p)
    p.add_argument(
        "--opening",
        type=float,
        default=None,
        metavar="DEG",
        help="one opening (degrees): its excluded components, certified at --resolution and exact in φ",
    )
    p.add_argument(
        "--opening-range",
        nargs=2,
        type=float,
        default=(0.0, 360.0),
        metavar=("LOW", "HIGH"),
        help="without --opening: the openings searched, degrees (default 0 360)",
    )
    p.add_argument(
        "--resolution",
        type=float,
        default=None,
        metavar="EPS",
        help="count the components of the excluded set eroded by EPS, b (default 1e-5)",
    )
    p.add_argument("--rim", type=float, default=None, metavar="B", help="count components at least EPS + B "
                   "deep, b (default 1e-3, or EPS or the polylines' departure where larger; lower costs "
                   "more)")  # fmt: skip
    p.add_argument("--base", type=int, default=None, help="cells along each side at first (default 64)")
    p.add_argument("--step", type=float, default=None, help="openings first counted this far apart, degrees, "
                   "16 widths (default 4.8)")  # fmt: skip
    p.add_argument("--width", type=float, default=None, help="each change bracketed at least this narrowly, "
                   "degrees (default 0.3)")  # fmt: skip
    p.add_argument("--workers", type=int, default=None, help="without --opening: openings counted at once, each in "
                   "a worker process (default: all cores)")  # fmt: skip
    p.add_argument(
        "--cache",
        type=Path,
        default=None,
        metavar="DIR",
        help="without --opening: a folder of "
        "counted openings, read and written (default ~/.cache/sesp/counts, or $XDG_CACHE_HOME/sesp/counts)",
    )
    p.add_argument("--no-cache", action="store_true", help="without --opening: count every opening anew, keep none")
    p.add_argument("--json", action="store_true", help="print one JSON object (lengths in b, angles in degrees)")
    p.add_argument(
        "--plot",
        type=Path,
        default=None,
        metavar="PNG",
        help="save a figure: the components in colour (--opening), or the count over Ψ and each component's "
        "depth on a log scale with resolution + rim (the persistence of the excluded set)",
    )
    p.set_defaults(func=_cmd_topology)


def _topology_defaults(args):
    """Fill in the defaults left None by the parser (they live in sesp.certified and sesp.topology, which the
    parser does not import: ``sesp --help`` stays fast)."""
    from .certified import BASE, RESOLUTION
    from .topology import STEP, WIDTH

    args.resolution = RESOLUTION if args.resolution is None else args.resolution
    args.base = BASE if args.base is None else args.base
    args.step = math.degrees(STEP) if args.step is None else args.step
    args.width = math.degrees(WIDTH) if args.width is None else args.width


def _cmd_topology(args) -> int:
    from .checks import check_resolution

    _topology_defaults(args)
    check_resolution(args.resolution, args.rim, args.base)
    _check_figure_path(args.plot)
    if args.opening is not None or args.vertices is not None:  # a polyline has no opening to vary
        return _topology_at_opening(args)
    from .topology import Interrupted, transitions

    lo, hi = args.opening_range
    if not (0.0 <= lo < hi <= 360.0):
        raise ValueError(f"--opening-range must satisfy 0 <= LOW < HIGH <= 360 degrees, got {lo} {hi}")
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be a whole number of processes >= 1, got {args.workers}")
    step = _positive_degrees("--step", args.step, 1e-4, 360.0)
    width = _positive_degrees("--width", args.width, 1e-6, 90.0)
    family = _shape_from_args(args, 0.0)
    cache = None if args.no_cache else _count_cache(args.cache)
    _announce_compile(*CERTIFIED_KERNELS)
    try:
        found = transitions(
            family, (math.radians(lo), math.radians(hi)), step=step, width=width, resolution=args.resolution,
            rim=args.rim, base=args.base, segments=args.segments, progress=not args.quiet,
            on_change=None if args.quiet else _print_change, on_run=None if args.quiet else _print_run,
            workers=args.workers, cache=cache,
        )  # fmt: skip
    except Interrupted as stopped:
        _report_transitions(stopped.partial, family, args)
        where = f"kept in {cache.folder}: the same command resumes" if cache else "not kept (--no-cache)"
        print(f"sesp: interrupted; the counts made are {where}", file=sys.stderr)
        return 130
    _report_transitions(found, family, args)
    _save_map_plot(args.plot, "count_plot", found, family=family)
    return 0


def _count_cache(folder):
    """The folder of counted openings: ``folder``, or the default."""
    from .cache import CountCache, default_folder

    return CountCache(default_folder() if folder is None else folder)


def _report_transitions(found, family, args) -> None:
    """The table (or JSON) of a search over Ψ, to stdout."""
    import json

    found.label = f"n = {family.n:g}, m = {family.m:g}, aspect {family.aspect:g}, {args.segments} segments"
    if args.json:
        print(json.dumps({"n": family.n, "m": family.m, "aspect": family.aspect, "segments": args.segments,
                          "base": args.base, **found.to_dict()}))  # fmt: skip
    else:
        print(found)


def _print_run(low, high, found) -> None:
    """A run of openings with one count, to stderr as soon as it is settled (above the progress bar)."""
    from tqdm.auto import tqdm

    tqdm.write(f"counted: {math.degrees(low):.3f} .. {math.degrees(high):.3f} deg: {found.bracket}", file=sys.stderr)


def _print_change(t) -> None:
    """One change of the count, to stderr as soon as it is bracketed (above the progress bar)."""
    from tqdm.auto import tqdm

    tqdm.write(f"found: {math.degrees(t.low):.3f} .. {math.degrees(t.high):.3f} deg: {t.what()}", file=sys.stderr)


def _topology_at_opening(args) -> int:
    """``sesp topology --opening DEG``: the certified excluded components at resolution ``--resolution``."""
    import json

    from .certified import certified_components

    particle = _particle_from_args(args)
    _announce_compile(*CERTIFIED_KERNELS)
    found = certified_components(
        particle, resolution=args.resolution, rim=args.rim, base=args.base, segments=args.segments,
        progress=not args.quiet,
    )  # fmt: skip
    if args.vertices is not None:
        named = {"vertices": str(args.vertices), "thickness": args.thickness}
        said, title = f"the polyline of {args.vertices}, thickness {args.thickness:g} b", f"{args.vertices.name}"
    else:
        named = {"n": particle.n, "m": particle.m, "aspect": particle.aspect, "thickness": particle.thickness,
                 "opening_deg": args.opening, "segments": args.segments}  # fmt: skip
        said = f"n = {particle.n:g}, m = {particle.m:g}, opening {args.opening:g} deg, {args.segments} segments"
        title = f"n = {particle.n:g}, opening {args.opening:g}°"
    if args.json:
        print(json.dumps({**named, "base": args.base, **found.to_dict()}))
    else:
        print(said)
        print(found)
        print(f"({found.evaluations} cells, {found.seconds:.1f} s; finest cell {found.floor:.1e} b)")
    _save_map_plot(args.plot, "certified_map", found, particle=particle, title=title)
    return 0


def _positive_degrees(name: str, value: float, low: float, high: float) -> float:
    """A finite angle in degrees in [low, high], as radians."""
    if not (math.isfinite(value) and low <= value <= high):
        raise ValueError(f"{name} must be a number of degrees in [{low:g}, {high:g}], got {value}")
    return math.radians(value)


def _check_figure_path(path):
    """Fail before the work if ``path`` (None: no figure) cannot be saved: no such folder, or a format
    matplotlib does not write."""
    if path is None:
        return
    from matplotlib.figure import Figure

    formats = Figure().canvas.get_supported_filetypes()
    if path.suffix.lower().lstrip(".") not in formats:
        raise ValueError(f"--plot must end in one of {', '.join('.' + f for f in sorted(formats))}; got {path}")
    if not path.parent.is_dir():
        raise ValueError(f"--plot: no folder {path.parent} to save {path.name} in")


def _save_map_plot(path, kind, found, **kwargs):
    """Save ``sesp.plot.<kind>(found)`` at ``path`` (nothing if None)."""
    if path is None:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import plot

    drawn = getattr(plot, kind)(found, **kwargs)
    fig = getattr(drawn, "figure", drawn)
    plot.save_figure(fig, path)
    plt.close(fig)
    log.info("figure saved: %s", path)


def _add_sweep(sub):
    p = sub.add_parser("sweep", help="run a sweep file (resumable) and collect its results")
    p.add_argument("file", type=Path, help="TOML sweep file")
    p.add_argument("--output", type=Path, default=None, help="output folder (default: the file's)")
    p.add_argument("--workers", type=int, default=None, help="local worker processes (default: all cores)")
    p.add_argument("--scheduler", default=None, help="dask.distributed scheduler address")
    p.set_defaults(func=_cmd_sweep)


def sweep_kernels(keep) -> tuple:
    """The kernel modules a sweep point compiles: a scan's, and a certified count's where ``keep`` has topology."""
    return ("overlap", "scanline", *(CERTIFIED_KERNELS if "topology" in keep else ()))


def _cmd_sweep(args) -> int:
    from .sweep import load_spec, run

    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    spec = load_spec(args.file, output=args.output)
    _announce_compile(*sweep_kernels(spec.keep))
    try:
        target = run(
            args.file, output=args.output, workers=args.workers, scheduler=args.scheduler, progress=not args.quiet
        )
    except KeyboardInterrupt:
        done = len(list(spec.output.glob("????????????????.nc")))
        print(
            f"sesp: interrupted; {done} of {len(spec.points())} points are saved in {spec.output}."
            " Run the same command again to resume.",
            file=sys.stderr,
        )
        return 130
    print(f"wrote {target}")
    return 0


def _add_collect(sub):
    p = sub.add_parser("collect", help="combine a sweep folder's point files into one dataset")
    p.add_argument("folder", type=Path, help="a sweep's output folder (holds sweep.json and the point files)")
    p.add_argument("-o", "--output", type=Path, required=True, help="netCDF file to write")
    p.set_defaults(func=_cmd_collect)


def _cmd_collect(args) -> int:
    from .io import save
    from .sweep import collect

    save(collect(args.folder), args.output)
    print(f"wrote {args.output}")
    return 0


PLOT_KINDS = {
    "gallery": "paper Fig. 1c: the shapes over n and Ψ (no FILE)",
    "map": "allowed-configuration map of one scan, summary or sweep point",
    "maps": "one map per point of a collected map sweep (paper Figs. 2-3)",
    "curve": "normalised A_ex against Ψ from a collected sweep (paper Fig. 4)",
    "panels": "normalised A_ex(φ) against Ψ, 3 x 3 panels, from a collected sweep (paper Fig. 5)",
    "topology": "excluded components and their areas against Ψ, from a collected sweep",
    "onsager": "B2 and the first Onsager instability against Ψ, from a collected sweep",
    "thickness": "normalised A_ex against Ψ per thickness, from a collected thickness sweep",
    "phases": "the first ordering transition against Ψ (per n), from a sweep that keeps 'phases'",
}
SINGLE_PAIR = ("sesp.scan", "sesp.summary", "sesp.point")


def _add_plot(sub):
    kinds = "; ".join(f"{k}: {v}" for k, v in PLOT_KINDS.items())
    p = sub.add_parser("plot", help="draw one figure to an image file")
    p.add_argument("kind", choices=tuple(PLOT_KINDS), metavar="KIND", help=f"what to draw. {kinds}")
    p.add_argument("file", type=Path, nargs="?", help="a scan or collected sweep file (not for 'gallery')")
    p.add_argument("-o", "--output", type=Path, required=True, help="image file (png, pdf, svg)")
    p.add_argument(
        "--style",
        choices=("raster", "dots"),
        default="raster",
        help="map style: raster (hue: mean allowed φ, lightness: fraction allowed) or dots (paper look)",
    )
    p.add_argument("--dpi", type=float, default=150.0, help="resolution of raster images (default 150)")
    p.set_defaults(func=_cmd_plot)


def _check_plot_input(kind: str, path, ds):
    """One line naming the file and what the plot kind expects, instead of a traceback."""
    fmt = ds.attrs.get("sesp_format")
    if kind == "map" and fmt not in SINGLE_PAIR:
        raise ValueError(
            f"{path}: plot map needs a scan, summary or sweep point file, got a {fmt} file"
            " (for a collected sweep use 'maps')"
        )
    if kind != "map" and fmt != "sesp.sweep":
        raise ValueError(f"{path}: plot {kind} needs a collected sweep file, got a {fmt} file")
    needs = {
        "maps": ("opening", "n"),
        "curve": ("opening",),
        "panels": ("n",),
        "topology": ("opening",),
        "onsager": ("opening",),
        "thickness": ("thickness",),
        "phases": ("opening",),
    }
    if kind in needs and not any(d in ds.dims for d in needs[kind]):
        wanted = " or ".join(repr(d) for d in needs[kind])
        raise ValueError(f"{path}: plot {kind} needs a sweep over {wanted}; this one sweeps {list(ds.dims)}")


def _cmd_plot(args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import plot
    from .io import load

    if args.kind == "gallery":
        fig = plot.shape_gallery()
    else:
        if args.file is None:
            raise ValueError(f"plot {args.kind} needs a FILE")
        ds = load(args.file)
        _check_plot_input(args.kind, args.file, ds)
        if args.kind == "map":
            fig, ax = plt.subplots(figsize=(5.5, 4.5))
            plot.allowed_map(ds, style=args.style, ax=ax)
        else:
            kind = {"maps": "maps" if args.style == "dots" else "maps_raster"}.get(args.kind, args.kind)
            fig = plot.figure(kind, ds)
    if args.dpi <= 0 or not math.isfinite(args.dpi):
        raise ValueError(f"--dpi must be a number > 0, got {args.dpi}")
    plot.save_figure(fig, args.output, dpi=args.dpi, palette=args.style == "dots" and args.kind in ("map", "maps"))
    plt.close(fig)
    print(f"wrote {args.output}")
    return 0


def _add_figures(sub):
    p = sub.add_parser("figures", help="render the paper's figures from the shipped sweeps' results")
    p.add_argument("results", type=Path, help="folder holding one output folder per sweep")
    p.add_argument("-o", "--output", type=Path, required=True, help="folder for the images")
    p.add_argument("--format", choices=("png", "pdf", "svg"), default="png", help="image format (default png)")
    p.add_argument("--dpi", type=float, default=150.0, help="resolution of png images (default 150)")
    p.set_defaults(func=_cmd_figures)


def _cmd_figures(args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from .plot import render_figures

    if not args.results.is_dir():
        raise FileNotFoundError(f"{args.results}: no such folder")
    if args.dpi <= 0 or not math.isfinite(args.dpi):
        raise ValueError(f"--dpi must be a number > 0, got {args.dpi}")
    for name, outcome in render_figures(args.results, args.output, fmt=args.format, dpi=args.dpi).items():
        print(f"wrote {outcome}" if isinstance(outcome, Path) else f"skipped {name}: {outcome}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    from .version import __version__

    parser = argparse.ArgumentParser(prog="sesp", description=__doc__)
    parser.add_argument("--version", action="version", version=f"sesp {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks of errors")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bars")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in COMMANDS:
        add(sub)
    for command in sub.choices.values():  # the global options are accepted after the command too
        command.add_argument(
            "--debug", action="store_true", default=argparse.SUPPRESS, help="show tracebacks of errors"
        )
        command.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS, help="no progress bars")
    return parser


COMMANDS = [
    _add_scan,
    _add_area,
    _add_virial,
    _add_phases,
    _add_info,
    _add_topology,
    _add_sweep,
    _add_collect,
    _add_plot,
    _add_figures,
]


def _warning_handler() -> logging.Handler:
    class OneLine(logging.Formatter):
        def format(self, record):
            message = record.getMessage().split(": ", 1)[-1].split("\n", 1)[0]  # "file:line: Category: text"
            return f"sesp: warning: {message.removeprefix('UserWarning: ')}"

    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(OneLine())
    return handler


def _said_as_option(message: str, args) -> str:
    """A checker's message about a parameter that is also this command's option, in the option's name
    ("resolution must be ..." -> "--resolution must be ..."): Python and the command line share one checker."""
    name, _, rest = message.partition(" must ")
    if rest and name.isidentifier() and getattr(args, name, None) is not None:
        return f"--{name.replace('_', '-')} must {rest}"
    return message


def main(argv=None) -> int:
    """Entry point of the ``sesp`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if not args.quiet else logging.WARNING, format="%(message)s")
    logging.captureWarnings(True)  # a warning is one line "sesp: warning: ...", not a source listing
    logging.getLogger("py.warnings").handlers = [_warning_handler()]
    logging.getLogger("py.warnings").propagate = False
    try:
        return args.func(args)
    except USER_ERRORS as err:
        if args.debug:
            raise
        print(f"sesp: error: {_said_as_option(str(err), args)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("sesp: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
