"""matplotlib figures: shapes, allowed-configuration maps, excluded area, topology.

Every function takes ``ax=None`` (or ``fig=None``), returns the axes or the
figure and never calls ``show()``. Orientations use the cyclic ``twilight``
colormap.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import xarray as xr

from .dataset import SespFileError, particle_from_attrs
from .io import load
from .onsager import ORDER_NAMES as ORDER_NAME
from .regions import position_summary
from .shape import SeSP, as_polyline

__all__ = [
    "draw_particle",
    "shape_gallery",
    "allowed_map",
    "excluded_area_curve",
    "excluded_area_panels",
    "topology_plot",
    "map_grid",
    "render_figures",
    "figure",
    "onsager_plot",
    "thickness_curves",
]

PHI_CMAP = "twilight"
CLASS_COLORS = ("#ffffff", "#9ecae1", "#fdae6b", "#252525")


def _axes(ax):
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots()
    return ax


def draw_particle(particle, ax=None, *, x=0.0, y=0.0, phi=0.0, segments=256, color="k", arrow=True, lw=1.5):
    """Draw a SeSP or Polyline rotated by ``phi`` (rad) and moved to (x, y).

    The orientation vector β̂ (from the centre through the middle of the
    opening) is drawn as an arrow from the centre.
    """
    ax = _axes(ax)
    curve = as_polyline(particle, segments)
    c, s = math.cos(phi), math.sin(phi)
    v = curve.vertices @ np.array([[c, s], [-s, c]]) + [x, y]
    ax.plot(v[:, 0], v[:, 1], color=color, lw=lw, solid_capstyle="round")
    if arrow:
        length = 0.6 * curve.max_radius
        ax.annotate(
            "", xy=(x + length * c, y + length * s), xytext=(x, y), arrowprops=dict(arrowstyle="->", color=color, lw=1)
        )
        ax.plot([x], [y], ".", color=color, ms=3)
    ax.set_aspect("equal")
    return ax


GALLERY_EXTRAS = (
    SeSP(n=2, aspect=2.0, opening=math.pi / 2),
    SeSP(n=4, m=2, opening=math.pi / 2),
    SeSP(n=0.7, aspect=1.5, opening=2 * math.pi / 3),
    SeSP(n=8, aspect=0.5, opening=math.pi),
    SeSP(n=2, m=6, opening=math.pi / 4),
)


def shape_gallery(ns=(0.5, 1, 2, 4, 8), openings=(0, 60, 120, 180, 270), *, extras=GALLERY_EXTRAS, fig=None):
    """Paper Fig. 1c: SeSPs over degree n (rows) and opening Ψ in degrees (columns).

    A last row shows ``extras`` (aspect ratio A ≠ 1, m ≠ n). Each particle is
    drawn with its orientation vector.
    """
    import matplotlib.pyplot as plt

    rows = len(ns) + (1 if extras else 0)
    cols = max(len(openings), len(extras) if extras else 0)
    fig = fig or plt.figure(figsize=(1.8 * cols, 1.8 * rows))
    axes = fig.subplots(rows, cols, squeeze=False)
    for i, n in enumerate(ns):
        for j, deg in enumerate(openings):
            draw_particle(SeSP(n=n, opening=math.radians(deg)), axes[i, j])
            axes[i, j].set_title(f"n={n:g}, Ψ={deg:g}°", fontsize=8)
    for j, p in enumerate(extras or ()):
        draw_particle(p, axes[-1, j], color="C3")
        axes[-1, j].set_title(f"n={p.n:g} m={p.m:g} A={p.aspect:g}\nΨ={math.degrees(p.opening):.0f}°", fontsize=7)
    for ax in axes.ravel():
        ax.set_xlim(-2.2, 2.2)
        ax.set_ylim(-2.2, 2.2)
        ax.axis("off")
    return fig


def _particle_of(ds, particle):
    """The particle to draw on a map: given, else from the dataset's attributes or scalar coordinates."""
    if particle is not None:
        return particle
    if "particle_kind" in ds.attrs:
        try:
            return particle_from_attrs(ds.attrs, "particle")
        except (SespFileError, KeyError):
            pass
    coords = {k: float(ds[k]) for k in ("n", "opening") if k in ds.coords and ds[k].ndim == 0}
    if "n" in coords and "opening" in coords:
        return SeSP(n=coords["n"], opening=coords["opening"])
    return None


def _orientation_colors(fraction, mean):
    """RGB image: hue = mean allowed orientation (twilight), fading to white as fewer are allowed."""
    import matplotlib

    cmap = matplotlib.colormaps[PHI_CMAP]
    rgb = cmap(np.nan_to_num(mean / (2 * np.pi)))[..., :3]
    rgb[np.isnan(mean)] = 0.55  # every orientation allowed: no preferred direction
    weight = np.sqrt(np.clip(fraction, 0, 1))[..., None]
    return 1.0 - weight * (1.0 - rgb)


def allowed_map(
    ds: xr.Dataset,
    *,
    style: str = "raster",
    ax=None,
    particle=None,
    outlines: bool = True,
    samples: int = 40_000,
    seed: int = 0,
    colorbar: bool = True,
):
    """Paper Figs. 2–3: where particle 2's centre may go, coloured by allowed orientation.

    Parameters
    ----------
    ds : xarray.Dataset
        A scan (``allowed``), a summary, or one point of a collected sweep
        (``allowed_fraction`` and ``mean_orientation``, optionally ``classes``).
    style : {"raster", "dots"}
        "raster": hue = circular mean of the allowed orientations, lightness =
        fraction allowed (white: excluded, grey: every orientation allowed).
        "dots": the paper's look, a reproducible random subsample of allowed
        states drawn at their positions and coloured by φ (needs ``allowed``).
    outlines : bool
        Draw the boundaries between position classes, if ``classes`` is known.
    """
    import matplotlib.pyplot as plt

    ax = _axes(ax)
    x, y = ds.x.values, ds.y.values
    extent = (x[0] - (x[1] - x[0]) / 2, x[-1] + (x[1] - x[0]) / 2, y[0] - (y[1] - y[0]) / 2, y[-1] + (y[1] - y[0]) / 2)
    if style == "dots":
        if "allowed" not in ds:
            raise ValueError("style='dots' needs the allowed field (keep 'allowed' in the sweep)")
        k, iy, ix = np.nonzero(ds.allowed.values)
        rng = np.random.default_rng(seed)
        pick = rng.choice(len(k), size=min(samples, len(k)), replace=False) if len(k) else []
        art = ax.scatter(
            x[ix[pick]],
            y[iy[pick]],
            c=ds.phi.values[k[pick]],
            cmap=PHI_CMAP,
            vmin=0,
            vmax=2 * np.pi,
            s=1.5,
            lw=0,
            rasterized=True,
        )
    elif style == "raster":
        summary = ds if "allowed_fraction" in ds else position_summary(ds)
        rgb = _orientation_colors(summary.allowed_fraction.values, summary.mean_orientation.values)
        ax.imshow(rgb, origin="lower", extent=extent, interpolation="nearest")
        art = plt.cm.ScalarMappable(cmap=PHI_CMAP, norm=plt.Normalize(0, 2 * np.pi))
    else:
        raise ValueError(f"style must be 'raster' or 'dots', got {style!r}")
    classes = ds["classes"] if "classes" in ds else None
    if outlines and classes is not None:
        ax.contour(x, y, classes.values, levels=[0.5, 1.5, 2.5], colors="k", linewidths=0.4)
    shape = _particle_of(ds, particle)
    if shape is not None:
        draw_particle(shape, ax, color="k", lw=2)
    if colorbar:
        bar = ax.figure.colorbar(art, ax=ax, label="φ (rad)", ticks=np.arange(5) * np.pi / 2)
        bar.ax.set_yticklabels(["0", "π/2", "π", "3π/2", "2π"])
    ax.set(xlim=extent[:2], ylim=extent[2:], xlabel="x / b", ylabel="y / b", aspect="equal")
    return ax


def _opening_degrees(ds):
    return ds["opening_degrees"].values if "opening_degrees" in ds.coords else np.degrees(ds.opening.values)


def excluded_area_curve(ds: xr.Dataset, *, ax=None):
    """Paper Fig. 4: orientation-averaged normalised A_ex against Ψ (one line per n)."""
    ax = _axes(ax)
    value = ds.mean_normalized_excluded_area
    deg = _opening_degrees(ds)
    if "n" in value.dims:
        for i, n in enumerate(value.n.values):
            ax.plot(deg, value.sel(n=n).values, "o-", ms=2.5, color=f"C{i}", label=f"n = {n:g}")
        ax.legend(frameon=False)
    else:
        ax.plot(deg, value.values, "o-", ms=2.5)
    ax.set(xlabel="opening Ψ (degrees)", ylabel="A_ex / A_ex(closed)", xlim=(0, 360), ylim=(0, None))
    ax.set_xticks(np.arange(0, 361, 90))
    return ax


def _nearest_phi(ds, degrees):
    return ds.phi.values[int(np.argmin(np.abs(np.angle(np.exp(1j * (ds.phi.values - math.radians(degrees)))))))]


def excluded_area_panels(ds: xr.Dataset, *, phis=(0, 45, 90, 135, 180), ns=(2, 4, 8, 10), fig=None):
    """Paper Fig. 5: normalised A_ex(φ) against Ψ in a 3 × 3 layout.

    (a)–(e): fixed φ (degrees) with n as line colour; (f)–(i): fixed n with φ
    (0°–180°) as line colour.
    """
    import matplotlib
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(12, 10), layout="constrained")
    axes = fig.subplots(3, 3, sharex=True, sharey=True).ravel()
    value = ds.normalized_excluded_area
    deg = _opening_degrees(ds)
    ns = [n for n in ns if n in value.n.values]
    n_colors = matplotlib.colormaps["viridis"](np.linspace(0, 0.9, len(ns)))
    for ax, phi_deg in zip(axes[:5], phis):
        phi = _nearest_phi(ds, phi_deg)
        for color, n in zip(n_colors, ns):
            ax.plot(deg, value.sel(n=n, phi=phi).values, color=color, label=f"n = {n:g}")
        ax.set_title(f"φ = {math.degrees(phi):.0f}°", fontsize=9)
    axes[0].legend(frameon=False, fontsize=8)
    shades = np.arange(0, 181, 22.5)
    phi_cmap = matplotlib.colormaps[PHI_CMAP]
    for ax, n in zip(axes[5:], ns):
        for phi_deg in shades:
            phi = _nearest_phi(ds, phi_deg)
            ax.plot(deg, value.sel(n=n, phi=phi).values, color=phi_cmap(phi / (2 * np.pi)), lw=1)
        ax.set_title(f"n = {n:g}", fontsize=9)
    for label, ax in zip("abcdefghi", axes):
        ax.text(0.02, 0.04, f"({label})", transform=ax.transAxes, fontsize=9)
        ax.set_xticks(np.arange(0, 361, 90))
    for ax in axes[6:]:
        ax.set_xlabel("opening Ψ (degrees)")
    for ax in axes[::3]:
        ax.set_ylabel("A_ex(φ) / A_ex(closed)")
    sm = plt.cm.ScalarMappable(cmap=PHI_CMAP, norm=plt.Normalize(0, 360))
    fig.colorbar(sm, ax=axes[5:].tolist(), label="φ (degrees), panels f–i", shrink=0.6)
    return fig


def topology_plot(ds: xr.Dataset, *, fig=None):
    """Excluded components and their areas against Ψ, with the changes marked.

    ``ds`` is a collected sweep with ``excluded_components`` and
    ``component_area`` (keep "topology"). For n = 2 the exact island area
    (π − Ψ) − sin Ψ is drawn for comparison.
    """
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(8, 6), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    deg = _opening_degrees(ds)
    if "n" in ds.excluded_components.dims:
        series = [(float(n), ds.sel(n=n)) for n in ds.n.values]
    else:
        series = [(float(ds.n) if "n" in ds.coords else None, ds)]
    for i, (n, sub) in enumerate(series):
        label = "" if n is None else f"n = {n:g}"
        counts = sub.excluded_components.values
        top.step(deg, counts, where="mid", color=f"C{i}", label=label)
        for j in np.flatnonzero(np.diff(counts)):
            top.axvline(0.5 * (deg[j] + deg[j + 1]), color=f"C{i}", ls=":", lw=0.8)
        areas = sub.component_area.values
        bottom.plot(deg, areas[:, 0], "o-", ms=3, color=f"C{i}", label=f"largest {label}")
        bottom.plot(deg, areas[:, 1], "s--", ms=3, color=f"C{i}", label=f"second {label}")
    if any(n == 2 for n, _ in series):
        psi = np.radians(np.linspace(0, 180, 200))
        bottom.plot(np.degrees(psi), (np.pi - psi) - np.sin(psi), "k:", lw=1, label="exact ASP lens (π − Ψ) − sin Ψ")
    top.set(ylabel="excluded components")
    if any(n is not None for n, _ in series):
        top.legend(frameon=False, fontsize=8)
    bottom.set(xlabel="opening Ψ (degrees)", ylabel="component area (b²)", yscale="symlog")
    bottom.set_yscale("symlog", linthresh=1e-2)
    bottom.legend(frameon=False, fontsize=7)
    bottom.set_xticks(np.arange(0, 361, 45))
    return fig


def thickness_curves(ds: xr.Dataset, *, fig=None):
    """Normalised orientation-averaged A_ex against Ψ, one line per thickness D, one panel per n.

    ``ds`` is a collected sweep over ``n``, ``opening`` and ``thickness``
    (``sweeps/thickness_opening.toml``); each curve is normalised by the
    closed shape of the same thickness.
    """
    import matplotlib
    import matplotlib.pyplot as plt

    ns = ds.n.values if "n" in ds.dims else [float(ds.n)]
    fig = fig or plt.figure(figsize=(4.2 * len(ns), 3.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(ns), sharey=True, squeeze=False)).ravel()
    deg = _opening_degrees(ds)
    thicknesses = ds.thickness.values
    colors = matplotlib.colormaps["viridis"](np.linspace(0, 0.85, len(thicknesses)))
    for ax, n in zip(axes, ns):
        sub = ds.sel(n=n) if "n" in ds.dims else ds
        for color, thickness in zip(colors, thicknesses):
            value = sub.mean_normalized_excluded_area.sel(thickness=thickness).values
            ax.plot(deg, value, color=color, lw=1.3, label=f"$D = {thickness:g}\\,b$")
        ax.set(title=f"$n = {n:g}$", xlabel=r"opening $\Psi$ (degrees)", xlim=(0, 360), ylim=(0, None))
        ax.set_xticks(np.arange(0, 361, 90))
    axes[0].set_ylabel(r"$\langle A_\mathrm{ex} \rangle / \langle A_\mathrm{ex} \rangle_\mathrm{closed}$")
    axes[-1].legend(frameon=False, fontsize=8, title="thickness", title_fontsize=8)
    return fig


ORDER_MARKERS = {1: "o", 2: "s", 3: "v", 4: "D", 6: "h"}


def onsager_plot(ds: xr.Dataset, *, fig=None):
    """B₂ and the leading isotropic instability ρ*_k⟨A_ex⟩ against Ψ, one line per n.

    ``ds`` is a collected sweep over ``n`` and ``opening`` (every sweep stores
    ``second_virial_coefficient`` and ``reduced_instability_density``; see
    :mod:`sesp.onsager`). The lower panel draws, at each Ψ, the smallest
    ρ*_k⟨A_ex⟩ over k, with a marker for the order k that goes unstable first;
    openings where no order goes unstable are left out.
    """
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    fig = fig or plt.figure(figsize=(7, 6.5), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    deg = _opening_degrees(ds)
    ns = ds.n.values if "n" in ds.dims else [None]
    for i, n in enumerate(ns):
        sub = ds if n is None else ds.sel(n=n)
        label = "" if n is None else f"$n = {n:g}$"
        top.plot(deg, sub.second_virial_coefficient.values, "-", color=f"C{i}", label=label)
        reduced = sub.reduced_instability_density
        leading = sub.leading_instability.values
        best = reduced.min("order", skipna=True).values
        bottom.plot(deg, best, "-", color=f"C{i}", lw=1)
        for k, marker in ORDER_MARKERS.items():
            pick = leading == k
            if pick.any():
                bottom.plot(deg[pick], best[pick], marker, color=f"C{i}", ms=3.5, ls="none")
    top.set(ylabel=r"$B_2 = \langle A_\mathrm{ex} \rangle / 2$ ($b^2$)", ylim=(0, None))
    if ns[0] is not None:
        top.legend(frameon=False, fontsize=8)
    handles = [Line2D([], [], color="0.3", marker=m, ls="none", label=f"{ORDER_NAME[k]} ($k = {k}$)")
               for k, m in ORDER_MARKERS.items() if k in ORDER_NAME]  # fmt: skip
    bottom.legend(handles=handles, frameon=False, fontsize=8, title="first unstable order", title_fontsize=8)
    bottom.set(xlabel=r"opening $\Psi$ (degrees)", ylabel=r"$\rho^*_k \langle A_\mathrm{ex} \rangle$", yscale="log")
    bottom.set_xticks(np.arange(0, 361, 45))
    top.set_title("isotropic state: second virial coefficient and first instability", fontsize=10)
    return fig


FIGURES = {
    # file name: (sweep folder, what to draw)
    "fig1_shape_gallery.png": (None, "gallery"),
    "fig2_maps_asp.png": ("maps_asp", "maps"),
    "fig2_maps_asp_raster.png": ("maps_asp", "maps_raster"),
    "fig3_maps_exponent.png": ("maps_exponent", "maps"),
    "fig3_maps_exponent_raster.png": ("maps_exponent", "maps_raster"),
    "fig4_asp_opening.png": ("asp_opening", "curve"),
    "fig5_exponent_opening_orientation.png": ("exponent_opening_orientation", "panels"),
    "topology_asp.png": ("asp_opening", "topology"),
    "onsager_exponent_opening.png": ("exponent_opening_orientation", "onsager"),
    "thickness_opening.png": ("thickness_opening", "thickness"),
}


def map_grid(ds: xr.Dataset, *, style="dots", fig=None):
    """One allowed-configuration map per swept point of a map sweep (paper Figs. 2 and 3)."""
    import matplotlib.pyplot as plt

    swept = [d for d in ("opening", "n") if d in ds.dims]
    points = [dict(zip(swept, values)) for values in _product(ds, swept)]
    cols = min(3, len(points))
    rows = -(-len(points) // cols)
    fig = fig or plt.figure(figsize=(4.2 * cols, 3.8 * rows), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    for ax, point in zip(axes, points):
        sub = ds.sel(point)
        shape = SeSP(n=float(sub.n) if "n" in sub.coords else 2.0, opening=float(sub.opening))
        allowed_map(sub, style=style, ax=ax, particle=shape, colorbar=False)
        ax.set_title(f"n = {shape.n:g}, Ψ = {math.degrees(shape.opening):.0f}°", fontsize=9)
    for ax in axes[len(points) :]:
        ax.axis("off")
    sm = plt.cm.ScalarMappable(cmap=PHI_CMAP, norm=plt.Normalize(0, 2 * np.pi))
    bar = fig.colorbar(sm, ax=axes.tolist(), label="φ (rad)", shrink=0.6, ticks=np.arange(5) * np.pi / 2)
    bar.ax.set_yticklabels(["0", "π/2", "π", "3π/2", "2π"])
    return fig


def _product(ds, dims):
    return itertools.product(*(ds[d].values for d in dims))


def render_figures(results, out, *, fmt: str = "png", dpi: float = 150) -> dict:
    """Render the paper's figure set from the shipped sweeps' outputs.

    ``results`` holds one folder per sweep (``<results>/<name>/<name>.nc``).
    Returns, for each figure, the path written or the reason it was skipped
    (its sweep has not been run).
    """
    import matplotlib.pyplot as plt

    results, out = Path(results), Path(out)
    out.mkdir(parents=True, exist_ok=True)
    outcome = {}
    for name, (sweep, kind) in FIGURES.items():
        target = out / f"{Path(name).stem}.{fmt}"
        source = None if sweep is None else results / sweep / f"{sweep}.nc"
        if source is not None and not source.is_file():
            outcome[target.name] = f"no {source} (run: sesp sweep sweeps/{sweep}.toml)"
            continue
        fig = figure(kind, None if source is None else load(source))
        fig.savefig(target, dpi=dpi)
        plt.close(fig)
        outcome[target.name] = target
    return outcome


def figure(kind: str, ds: xr.Dataset | None = None):
    """One of the paper's figures as a matplotlib Figure.

    ``kind`` is "gallery", "maps" (dots), "maps_raster", "curve", "panels",
    "topology", "onsager" or "thickness"; ``ds`` is the matching collected sweep (not for "gallery").
    """
    if kind == "gallery":
        return shape_gallery()
    if kind in ("maps", "maps_raster"):
        return map_grid(ds, style="dots" if kind == "maps" else "raster")
    if kind == "curve":
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
        excluded_area_curve(ds, ax=ax)
        return fig
    if kind == "panels":
        return excluded_area_panels(ds)
    if kind == "topology":
        return topology_plot(ds)
    if kind == "onsager":
        return onsager_plot(ds)
    if kind == "thickness":
        return thickness_curves(ds)
    raise ValueError(f"unknown figure kind {kind!r}")
