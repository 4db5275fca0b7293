"""One analysis of a pair on a grid: the function the sweep runner, the CLI and notebooks call.

:func:`analyze` runs one pass over the field (:func:`sesp.field.reduce`) with
the reductions that what is kept needs, and returns one labelled Dataset:
A_ex(φ) and its normalised and averaged forms, and, as asked, position
classes, excluded components and the field itself.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .certified import BASE, COMPONENTS_KEPT, RESOLUTION, certified_components
from .checks import check_resolution
from .dataset import base_attrs, coords, grid_attrs, pair_attrs, pair_variables
from .field import reduce, resolve_grid, working_bytes
from .grid import Grid
from .measures import RTOL, closed_excluded_area, excluded_area
from .onsager import first_transition, onsager_variables, particle_area
from .pair import as_pair
from .reductions import EntangledAreaByPhi, ExcludedAreaByPhi, StoredField
from .regions import PositionSummary
from .shape import DEFAULT_SEGMENTS
from .units import link_errors, quantity
from .virial import B3_RTOL, third_virial

__all__ = ["analyze", "check_memory", "KEEP", "COMPONENTS_KEPT"]

KEEP = ("excluded_area", "classes", "topology", "phases", "third_virial", "allowed", "crossings", "entangled")
SCALAR_KEEP = ("excluded_area", "topology", "phases", "third_virial")  # what needs no pass over the lattice
FIELD_KEEP = ("allowed", "crossings", "entangled")
PER_POSITION = ("allowed_fraction", "mean_orientation", "orientation_order", "classes")
# Bytes per (x, y) position held by the position summary's running sums, its outputs and component labels.
SUMMARY_BYTES_PER_POSITION = 64


def needs_lattice(keep) -> bool:
    """Whether keeping ``keep`` takes a pass over the lattice (fields, classes, components); A_ex(φ) alone
    comes from scanlines and does not."""
    return any(k not in SCALAR_KEEP for k in check_keep(keep))


def check_memory(grid: Grid, keep, limit: int | None = None) -> None:
    """Raise ``MemoryError`` before any work if an analysis keeping ``keep`` would not fit in ``limit`` bytes
    (default half the available memory): stored fields, one chunk of working buffers, per-position sums."""
    keep = check_keep(keep)
    if not needs_lattice(keep):
        return
    fields = tuple(k for k in FIELD_KEEP if k in keep)
    computed = ("allowed",) + ("crossings",) * ("crossings" in keep)
    computed += ("entangled",) * ("entangled" in keep or "classes" in keep)
    per_position = SUMMARY_BYTES_PER_POSITION if "classes" in keep else 0
    grid.check_memory(fields, limit, working_bytes(grid, computed, per_position))


def check_keep(keep) -> tuple:
    """``keep`` as a tuple of known outputs, in the order given."""
    keep = (keep,) if isinstance(keep, str) else tuple(keep)
    unknown = [k for k in keep if k not in KEEP]
    if unknown or not keep:
        raise ValueError(f"keep must list some of {KEEP}, got {list(keep)}")
    if any(k in keep for k in ("crossings", "entangled")) and "allowed" not in keep:
        raise ValueError(f"keep: 'crossings' and 'entangled' are stored beside 'allowed', got {list(keep)}")
    return keep


def analyze(
    particle,
    grid: Grid | None = None,
    *,
    other=None,
    segments: int = DEFAULT_SEGMENTS,
    keep=("excluded_area",),
    resolution: float = RESOLUTION,
    rtol: float = RTOL,
    third_virial_rtol: float | None = B3_RTOL,
    engine: str = "raster",
    memory_limit: int | None = None,
    progress: bool = False,
) -> xr.Dataset:
    """Excluded area, classes, components and the field of one pair, from one pass.

    Parameters
    ----------
    particle, grid, other, segments
        As in :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`).
    keep : sequence of str
        What to return, any of:

        * ``"excluded_area"``: always returned: sesp's A_ex,
          :func:`sesp.excluded_area` of the particles refined to ``rtol``
          (the same call as ``sesp area``; of the smooth curves for two SeSPs,
          else of the polylines: attribute ``excluded_area_of``): the
          orientation mean ``mean_excluded_area`` ± ``mean_excluded_area_error``
          as it gives them, and ``excluded_area(phi)`` ±
          ``excluded_area_error(phi)`` at the grid's orientations at the
          settings it reached; ``normalized_excluded_area(phi)``,
          ``mean_normalized_excluded_area``, and ``closed_excluded_area``
          (b², the reference of the normalisation, the closed shapes' smooth
          curves, :func:`sesp.measures.closed_excluded_area`; NaN for
          polylines, which have no closed shape); and what
          :func:`sesp.onsager.onsager_variables` derives from the refined
          A_ex(φ), as ``sesp area``: the second virial coefficient (±
          ``second_virial_coefficient_error``), the orientational spectrum over
          ``k`` and the isotropic instabilities over ``order``, with error bars
          that hold whatever the correlation of the per-φ errors. Kept alone it
          takes no pass over the lattice (the grid's nx, ny are not used); with
          anything else the lattice's own count is there too, as
          ``lattice_excluded_area(phi)``, the A_ex of the classes and the field;
        * ``"classes"``: ``classes``, ``allowed_fraction``, ``mean_orientation``
          and ``orientation_order`` over (y, x), and the entangled area
          ``entangled_area(phi)`` and ``mean_entangled_area`` (b²) (runs the
          entanglement test);
        * ``"topology"``: the certified count of excluded components at
          ``resolution`` that reach ``resolution + rim`` deep (``component_rim``,
          b; :func:`sesp.certified_components`, exact in φ, no
          lattice): ``excluded_components`` and ``excluded_components_high``
          (the bracket; equal where decided), and per component, deepest
          first, NaN-padded to ``COMPONENTS_KEPT``: ``component_depth`` (b, a
          certified lower bound on its inscribed radius), ``component_area``
          (b², its certified cells: a lower bound) and
          ``component_area_bound`` (b², an upper bound);
        * ``"phases"``: the first ordering transition of the isotropic state in
          second-virial theory (:func:`sesp.onsager.first_transition`):
          ``transition_order`` (k, 0: none), ``transition_density`` and
          ``ordered_density`` (b⁻², the coexisting densities of a first-order
          transition), ``continuous`` and ``transition_density_error`` (b⁻²,
          that of a continuous transition; NaN for a first-order one, whose
          gap is not given an error bar); the same densities in Parsons–Lee
          theory, ``parsons_lee_transition_density`` and
          ``parsons_lee_ordered_density``, with ``particle_area`` a (b²,
          :func:`sesp.onsager.particle_area`; equal to the second-virial ones
          for a thin particle, NaN for two different particles);
        * ``"third_virial"``: ``third_virial_coefficient`` ± error (b⁴) and
          ``reduced_third_virial`` B₃/B₂² (:func:`sesp.virial.third_virial`, refined
          until the bar is at most ``third_virial_rtol`` · |B₃|, default 1e-3);
        * ``"allowed"``, ``"crossings"``, ``"entangled"``: the fields over
          (phi, y, x), as :func:`sesp.scan` stores them.
    engine : {"raster", "direct"}
        As in :func:`sesp.scan`.
    resolution : float
        b: the resolution ε of the topology count (kept "topology").
    rtol : float
        Relative error bar of ⟨A_ex⟩ that :func:`sesp.excluded_area` refines to (default 1e-5, as
        ``sesp area``).
    memory_limit : int, optional
        Bytes the stored fields may take (see :func:`sesp.scan`).
    progress : bool
        Show a progress bar over orientations.

    Returns
    -------
    xarray.Dataset
        Format ``sesp.scan`` when a field is kept, else ``sesp.summary``.

    Examples
    --------
    >>> from sesp import Grid, SeSP, analyze
    >>> ds = analyze(SeSP(n=2, opening=1.0), Grid(32, nphi=16), segments=32, keep=["topology"], resolution=1e-3)
    >>> int(ds.excluded_components)
    2
    """
    keep = check_keep(keep)
    if "topology" in keep:
        check_resolution(resolution)
    pair = as_pair(particle, other, segments)
    grid = resolve_grid(pair, grid)
    check_memory(grid, keep, memory_limit)
    ds = _lattice_pass(pair, grid, keep, engine, progress) if needs_lattice(keep) else _no_pass(pair, grid)
    best = _add_excluded_area(ds, pair, grid, rtol)
    _add_normalized(ds, pair, rtol)
    for name, value in onsager_variables(best).items():  # from the refined A_ex(φ), as `sesp area`
        ds[name] = value
    if "entangled_area" in ds:
        ds["mean_entangled_area"] = ds.entangled_area.mean("phi").assign_attrs(
            **quantity(2, "orientation-averaged entangled area A_ent")
        )
    if "topology" in keep:
        _add_components(ds, pair, resolution)
    if "phases" in keep:
        _add_phases(ds, best, pair)
    if "third_virial" in keep:
        found = third_virial(pair.particle, pair.other, segments=pair.segments, rtol=third_virial_rtol, progress=False)
        for name in ("third_virial_coefficient", "third_virial_coefficient_error", "reduced_third_virial"):
            ds[name] = found[name]
    if "classes" not in keep:
        ds = ds.drop_vars([v for v in PER_POSITION if v in ds])
    return link_errors(ds)


def _lattice_pass(pair, grid, keep, engine, progress) -> xr.Dataset:
    """One pass over the lattice for the fields, classes and components kept; its A_ex(φ) count is
    ``lattice_excluded_area``."""
    fields = tuple(k for k in FIELD_KEEP if k in keep)
    reductions = [StoredField(fields)] if fields else []
    per_position = "classes" in keep or "topology" in keep
    reductions.append(PositionSummary(entangled="classes" in keep) if per_position else ExcludedAreaByPhi())
    if "classes" in keep:
        reductions.append(EntangledAreaByPhi())
    kind = "sesp.scan" if fields else "sesp.summary"
    ds = reduce(pair, grid, reductions, engine=engine, kind=kind, progress=progress)
    lattice = ds.excluded_area.assign_attrs(long_name="A_ex(φ) counted on the lattice (the field's)")
    return ds.drop_vars("excluded_area").assign(lattice_excluded_area=lattice)


def _no_pass(pair, grid) -> xr.Dataset:
    """The summary's frame without a lattice pass: the pair, the grid's orientations, the attributes."""
    attrs = {**base_attrs("sesp.summary"), **pair_attrs(pair), **grid_attrs(grid)}
    return xr.Dataset(pair_variables(pair), coords=coords(grid, ["phi"]), attrs=attrs)


def _add_excluded_area(ds, pair, grid, rtol):
    """sesp's A_ex of the pair's particles, in place: :func:`sesp.excluded_area` refined to ``rtol``, its
    orientation mean and error bar as it gives them, and A_ex(φ) at the grid's orientations; returns its
    result, on the orientations it was refined on."""
    other = None if pair.identical else pair.other
    best = excluded_area(pair.particle, other, rtol=rtol, progress=False)
    on_grid = _at_orientations(best, pair.particle, other, grid.phi)
    for name in ("excluded_area", "excluded_area_error"):
        ds[name] = on_grid[name].assign_coords(phi=ds.phi)
    for name in ("mean_excluded_area", "mean_excluded_area_error"):
        ds[name] = best[name]
    ds.attrs["excluded_area_of"] = best.attrs["excluded_area_of"]
    ds.attrs.update({f"excluded_area_{k}": best.attrs[k] for k in ("segments", "nphi", "rows", "rtol", "converged")})
    return best


def _at_orientations(best, particle, other, phi) -> xr.Dataset:
    """A_ex(φ) of ``best`` at the orientations ``phi`` (2πk/len(phi)): taken from it where they are among its
    own, else evaluated there at the settings it reached."""
    step, rest = divmod(best.sizes["phi"], len(phi))
    if rest == 0 and np.allclose(best.phi.values[::step], phi, rtol=0, atol=1e-12):
        return best.isel(phi=slice(None, None, step))
    settings = {k: int(best.attrs[k]) for k in ("segments", "rows")}
    return excluded_area(particle, other, rtol=None, nphi=len(phi), progress=False, **settings)


def _add_normalized(ds, pair, rtol):
    """A_ex normalised by the closed shapes' (measured alike: :func:`sesp.measures.closed_excluded_area`), in place."""
    reference = closed_excluded_area(pair, rtol=rtol)
    area = ds.excluded_area
    ds["normalized_excluded_area"] = (area / reference).assign_attrs(
        units="1", long_name="A_ex(φ) / A_ex of the closed shape"
    )
    ds["normalized_excluded_area_error"] = (ds.excluded_area_error / reference).assign_attrs(
        units="1", long_name="error bar of A_ex(φ) / A_ex of the closed shape"
    )
    ds["mean_normalized_excluded_area"] = (ds.mean_excluded_area / reference).assign_attrs(
        units="1", long_name="orientation-averaged A_ex / A_ex of the closed shape"
    )
    ds["mean_normalized_excluded_area_error"] = (ds.mean_excluded_area_error / reference).assign_attrs(
        units="1", long_name="error bar of the orientation-averaged A_ex / A_ex of the closed shape"
    )
    ds["closed_excluded_area"] = xr.DataArray(
        reference, attrs=quantity(2, "orientation-averaged A_ex of the closed shape")
    )


def _add_phases(ds, best, pair):
    """The first ordering transition of the isotropic state for the refined A_ex(φ) ``best``, in place: in
    second-virial (Onsager) theory, and in Parsons–Lee theory with the particle's area (the same for thin
    particles; NaN for a mixture's pair)."""
    found = first_transition(best)
    ds.update(found)
    area = particle_area(pair.particle) if pair.identical else math.nan
    if area > 0:
        parsons_lee = first_transition(best, particle_area=area)
    else:  # a thin particle's Parsons–Lee densities are its second-virial ones
        parsons_lee = found if area == 0 else found.map(lambda v: v * math.nan)
    ds["particle_area"] = xr.DataArray(area, attrs=quantity(2, "area a the thick particle covers"))
    for name, what in (("transition", "isotropic"), ("ordered", "ordered")):
        ds[f"parsons_lee_{name}_density"] = parsons_lee[f"{name}_density"].assign_attrs(
            **quantity(-2, f"{what} density at the first transition, Parsons-Lee")
        )


def _add_components(ds, pair, resolution):
    """The certified count of excluded components, its bracket and the deepest components, in place."""
    found = certified_components(pair, resolution=resolution, base=BASE, progress=False)
    ds.update(found.to_dataset(COMPONENTS_KEPT))
