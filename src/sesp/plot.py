"""matplotlib figures: shapes, allowed-configuration maps, excluded area, topology.

Every function takes ``ax=None`` (or ``fig=None``), returns the axes or the
figure and never calls ``show()``. Orientations use the cyclic ``twilight``
colormap.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from .dataset import SespFileError, particle_of
from .io import load
from .onsager import ORDER_NAMES as ORDER_NAME
from .regions import position_summary
from .shape import SeSP, as_polyline

__all__ = [
    "phase_diagram",
    "draw_particle",
    "shape_gallery",
    "allowed_map",
    "excluded_area_curve",
    "excluded_area_panels",
    "count_plot",
    "certified_map",
    "map_grid",
    "render_figures",
    "figure",
    "onsager_plot",
    "thickness_curves",
    "orientation_key",
    "map_legend_handles",
    "class_map",
    "save_figure",
]

PHI_CMAP = "twilight"
PANEL_PHI_CMAP = "plasma"  # φ over [0°, 180°] only: sequential, its near-white end left out
PSI_LABEL = r"opening $\Psi$ (degrees)"
NORMALIZED_LABEL = r"$\langle A_\mathrm{ex} \rangle / \langle A_\mathrm{ex} \rangle_\mathrm{closed}$"
CLASS_COLORS = ("#d9d9d9", "#9ecae1", "#fdae6b", "#252525")  # free, spooning, entangled, excluded


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
            return particle_of(ds, "particle")
        except (SespFileError, KeyError):
            pass
    coords = {k: float(ds[k]) for k in ("n", "opening") if k in ds.coords and ds[k].ndim == 0}
    if "n" in coords and "opening" in coords:
        return SeSP(n=coords["n"], opening=coords["opening"])
    return None


def shape_label(particle, opening: bool = True) -> str:
    """A figure title naming the particle: "n = 2, Ψ = 90°" (m and A when they differ from n and 1, D when thick;
    without Ψ when ``opening`` is False), or "polyline of K vertices"."""
    if particle is None:
        return ""
    if isinstance(particle, SeSP):
        label = f"n = {particle.n:g}" + (f", m = {particle.m:g}" if particle.m != particle.n else "")
        label += f", A = {particle.aspect:g}" if particle.aspect != 1 else ""
        label += f", Ψ = {math.degrees(particle.opening):.4g}°" if opening else ""
    else:
        label = f"polyline of {len(particle.vertices)} vertices"
    return label + (f", D = {particle.thickness:g} b" if particle.thickness else "")


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
    samples: int = 15_000,
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
    if outlines and "classes" not in ds and "allowed" in ds:  # a plain scan: classes from its field
        ds = ds.assign(classes=position_summary(ds).classes)
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
            s=2.0,
            lw=0,
            rasterized=True,
        )
    elif style == "raster":
        summary = ds if "allowed_fraction" in ds else position_summary(ds)
        ds = ds if "classes" in ds else ds.assign(classes=summary.classes)
        rgb = _orientation_colors(summary.allowed_fraction.values, summary.mean_orientation.values)
        ax.imshow(rgb, origin="lower", extent=extent, interpolation="nearest")
        art = plt.cm.ScalarMappable(cmap=PHI_CMAP, norm=plt.Normalize(0, 2 * np.pi))
    else:
        raise ValueError(f"style must be 'raster' or 'dots', got {style!r}")
    classes = ds["classes"] if "classes" in ds else None
    if outlines and classes is not None:
        _class_outlines(ax, x, y, classes.values)
    shape = _particle_of(ds, particle)
    if shape is not None:
        draw_particle(shape, ax, color="k", lw=2)
    ax.set(xlim=extent[:2], ylim=extent[2:], xlabel=r"$x$ ($b$)", ylabel=r"$y$ ($b$)", aspect="equal")
    ax.set_title(shape_label(shape), fontsize=9)
    if colorbar:
        key = ax.inset_axes([1.06, 0.55, 0.3, 0.3] if style == "raster" else [1.06, 0.5, 0.05, 0.45])
        if style == "raster":
            orientation_key(key)
        else:
            _phi_colorbar(ax.figure, art, cax=key)
        if outlines and classes is not None:
            ax.legend(handles=map_legend_handles(style), loc="upper left", bbox_to_anchor=(1.02, 0.45),
                      fontsize=7, frameon=False)  # fmt: skip
    return ax


# Lines that outline the position classes on a map: class -> line style.
OUTLINES = {"excluded": ("-", 0.9), "free": ("--", 0.7), "entangled": (":", 0.9)}


def _class_outlines(ax, x, y, classes):
    """Boundaries of the excluded, free and entangled positions, at the resolution of the data.

    Each class's indicator is smoothed over about one node before its 0.5
    contour is drawn, so a boundary follows the data between nodes instead of
    a pixel staircase, and isolated single-node specks do not draw rings.
    """
    from scipy import ndimage

    from .regions import CLASSES

    for name, (style, width) in OUTLINES.items():
        indicator = ndimage.gaussian_filter((classes == CLASSES.index(name)).astype(float), 0.8)
        if indicator.max() > 0.5:
            ax.contour(x, y, indicator, levels=[0.5], colors="k", linestyles=style, linewidths=width)


def map_legend_handles(style="raster") -> list:
    """Legend entries that explain a map: what white, grey and the outlines mean."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    if style == "raster":
        handles = [
            Patch(facecolor="white", edgecolor="0.3", lw=0.5, label="excluded (no $\\phi$ allowed)"),
            Patch(facecolor="0.55", edgecolor="0.3", lw=0.5, label="free (every $\\phi$ allowed)"),
        ]
    else:
        handles = [Patch(facecolor="white", edgecolor="0.3", lw=0.5, label="no dots: excluded")]
    handles += [
        Line2D([], [], color="k", ls=ls, lw=lw, label=f"{name} boundary") for name, (ls, lw) in OUTLINES.items()
    ]
    return handles


def orientation_key(ax):
    """The 2D colour key of raster maps: hue = mean allowed φ, lightness = fraction of φ allowed."""
    phi = np.linspace(0, 2 * np.pi, 128)
    fraction = np.linspace(0, 1, 64)
    fraction_grid, phi_grid = np.meshgrid(fraction, phi, indexing="ij")
    ax.imshow(_orientation_colors(fraction_grid, phi_grid), origin="lower", aspect="auto",
              extent=(0, 2 * np.pi, 0, 1))  # fmt: skip
    ax.set_xticks([0, np.pi, 2 * np.pi], ["0", r"$\pi$", r"$2\pi$"])
    ax.set_yticks([0, 0.5, 1])
    ax.set_xlabel(r"mean allowed $\phi$", fontsize=7)
    ax.set_ylabel("fraction allowed", fontsize=7)
    ax.tick_params(labelsize=7)
    return ax


def _phi_colorbar(fig, mappable, **where):
    """A colour bar of φ in radians with ticks at multiples of π/2; ``where`` is ``cax=`` or ``ax=``, ``shrink=``."""
    bar = fig.colorbar(mappable, ticks=np.arange(5) * np.pi / 2, **where)
    bar.ax.set_yticklabels(["0", r"$\pi/2$", r"$\pi$", r"$3\pi/2$", r"$2\pi$"])
    bar.set_label(r"$\phi$ (rad)")
    return bar


def class_map(ds: xr.Dataset, *, ax=None, particle=None):
    """The position classes of a scan or summary, one colour each, with the class names on the colour bar."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap

    from .regions import CLASSES, classify

    ax = _axes(ax)
    classes = classify(ds)
    x, y = ds.x.values, ds.y.values
    cmap = ListedColormap(CLASS_COLORS)
    norm = BoundaryNorm(np.arange(len(CLASSES) + 1) - 0.5, cmap.N)
    image = ax.pcolormesh(x, y, classes.values, cmap=cmap, norm=norm, shading="nearest", rasterized=True)
    bar = plt.colorbar(image, ax=ax, ticks=np.arange(len(CLASSES)))
    bar.ax.set_yticklabels(CLASSES)
    shape = _particle_of(ds, particle)
    if shape is not None:
        draw_particle(shape, ax, color="C3", lw=1.5)
    ax.set(xlabel=r"$x$ ($b$)", ylabel=r"$y$ ($b$)", aspect="equal")
    return ax


def _band(ax, x, value, error, color, **where):
    """Shade value ± error around a drawn line, ``error`` (a DataArray, or None: no band) taken at ``where``;
    an error bar too small to see leaves no mark."""
    if error is not None:
        error = error.sel(**where).values if where else error.values
        ax.fill_between(x, value - error, value + error, color=color, alpha=0.3, lw=0)


def _error_of(ds, name):
    """The error bar stored beside ``name`` (``name_error``), or None."""
    return ds[f"{name}_error"] if f"{name}_error" in ds else None


def _opening_degrees(ds):
    return ds["opening_degrees"].values if "opening_degrees" in ds.coords else np.degrees(ds.opening.values)


def excluded_area_curve(ds: xr.Dataset, *, ax=None):
    """Paper Fig. 4: orientation-averaged normalised A_ex against Ψ (one line per n)."""
    ax = _axes(ax)
    value, error = ds.mean_normalized_excluded_area, _error_of(ds, "mean_normalized_excluded_area")
    deg = _opening_degrees(ds)
    if "n" in value.dims:
        for i, n in enumerate(value.n.values):
            ax.plot(deg, value.sel(n=n).values, "o-", ms=2.5, color=f"C{i}", label=f"$n = {n:g}$")
            _band(ax, deg, value.sel(n=n).values, error, f"C{i}", n=n)
        ax.legend(frameon=False)
    else:
        label = f"$n = {float(ds.n):g}$" if "n" in ds.coords else None  # the particle the curve is of
        ax.plot(deg, value.values, "o-", ms=2.5, label=label)
        _band(ax, deg, value.values, error, "C0")
        if label:
            ax.legend(frameon=False)
    ax.set(xlabel=PSI_LABEL, ylabel=NORMALIZED_LABEL, xlim=(0, 360), ylim=(0, None))
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
    value, error = ds.normalized_excluded_area, _error_of(ds, "normalized_excluded_area")
    deg = _opening_degrees(ds)
    ns = [n for n in ns if n in value.n.values]
    n_colors = matplotlib.colormaps["viridis"](np.linspace(0, 0.9, len(ns)))
    for ax, phi_deg in zip(axes[:5], phis):
        phi = _nearest_phi(ds, phi_deg)
        for color, n in zip(n_colors, ns):
            ax.plot(deg, value.sel(n=n, phi=phi).values, color=color, label=f"$n = {n:g}$")
            _band(ax, deg, value.sel(n=n, phi=phi).values, error, color, n=n, phi=phi)
        ax.set_title(f"$\\phi = {math.degrees(phi):.0f}°$", fontsize=9)
    axes[0].legend(frameon=False, fontsize=8)
    shades = np.arange(0, 181, 22.5)
    # only φ in [0°, 180°] is drawn (A_ex(φ) = A_ex(−φ)): a sequential map over that range, dark to light,
    # with no colour close to the white background
    phi_cmap = matplotlib.colors.ListedColormap(matplotlib.colormaps[PANEL_PHI_CMAP](np.linspace(0.0, 0.85, 256))[::-1])
    phi_norm = plt.Normalize(0, 180)
    for ax, n in zip(axes[5:], ns):
        for phi_deg in shades:
            phi = _nearest_phi(ds, phi_deg)
            color = phi_cmap(phi_norm(math.degrees(phi)))
            ax.plot(deg, value.sel(n=n, phi=phi).values, color=color, lw=1)
            _band(ax, deg, value.sel(n=n, phi=phi).values, error, color, n=n, phi=phi)
        ax.set_title(f"$n = {n:g}$", fontsize=9)
    for label, ax in zip("abcdefghi", axes):
        ax.text(0.02, 0.04, f"({label})", transform=ax.transAxes, fontsize=9)
        ax.set_xticks(np.arange(0, 361, 90))
    for ax in axes[6:]:
        ax.set_xlabel(PSI_LABEL)
    for ax in axes[::3]:
        ax.set_ylabel(r"$A_\mathrm{ex}(\phi) / \langle A_\mathrm{ex} \rangle_\mathrm{closed}$")
    sm = plt.cm.ScalarMappable(cmap=phi_cmap, norm=phi_norm)
    bar = fig.colorbar(sm, ax=axes[5:].tolist(), shrink=0.6, ticks=np.arange(0, 181, 45))
    bar.set_label(r"$\phi$ (degrees), panels (f)–(i)")
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
        error = _error_of(sub, "mean_normalized_excluded_area")
        for color, thickness in zip(colors, thicknesses):
            value = sub.mean_normalized_excluded_area.sel(thickness=thickness).values
            ax.plot(deg, value, color=color, lw=1.3, label=f"$D = {thickness:g}\\,b$")
            _band(ax, deg, value, error, color, thickness=thickness)
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
        error = _error_of(sub, "second_virial_coefficient")
        _band(top, deg, sub.second_virial_coefficient.values, error, f"C{i}")
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


COMPONENT_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink")


def _draw_cells(ax, found, window):
    """The cells of a certified result inside ``window``: certified (solid) and undecided (pale), coloured by
    component; cells narrower than a pixel keep an edge of their colour so they stay in sight."""
    from matplotlib.collections import PolyCollection

    c = found.cells
    half = c["side"] / 2
    corners = np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)], dtype=float)
    inside = (c["x"] + half >= window[0]) & (c["x"] - half <= window[1])
    inside &= (c["y"] + half >= window[2]) & (c["y"] - half <= window[3]) & (c["component"] >= 0)
    for status, alpha in ((2, 0.3), (1, 1.0)):
        for k in range(len(found.components)):
            pick = np.nonzero(inside & (c["status"] == status) & (c["component"] == k))[0]
            if not len(pick):
                continue
            color = COMPONENT_COLORS[k % len(COMPONENT_COLORS)]
            centres = np.stack([c["x"][pick], c["y"][pick]], axis=1)[:, None, :]
            squares = centres + half[pick][:, None, None] * corners[None]
            cells = PolyCollection(squares, facecolor=color, edgecolor=color, linewidth=0.4, alpha=alpha)
            cells.set_rasterized(True)
            ax.add_collection(cells)
    # the view, set after every artist, left free to change (an equal aspect widens it without a warning)
    ax.set_xlim(window[0], window[1], auto=None)
    ax.set_ylim(window[2], window[3], auto=None)


def _padded(box, share=0.15, each=False):
    """``box`` (xmin, xmax, ymin, ymax) grown by ``share`` of its larger side, or of each side (``each``)."""
    x0, x1, y0, y1 = box
    px, py = (share * (x1 - x0), share * (y1 - y0)) if each else (share * max(x1 - x0, y1 - y0),) * 2
    return (x0 - px, x1 + px, y0 - py, y1 + py)


def certified_map(found, *, particle=None, title=None, fig=None):
    """The certified excluded components (:func:`sesp.certified.certified_components`), each in its colour.

    Every panel has equal scales on x and y (its limits widened to fill it). Left: the whole set and the fixed
    particle (in grey; the view holds both). Right: one panel per component (up to six), zoomed to its
    bounding box, its size in the panel's title; a strip far thinner than it is long shows as a line (cells
    narrower than a pixel keep an edge of their colour). Solid cells are certified deeper than the
    resolution; pale cells are undecided. A component shallower than resolution + rim is drawn as the
    others, its legend saying it is not counted. Every mark has a legend entry. ``title`` names the particle
    and opening.
    """
    import matplotlib
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    shown = found.components[:6]  # the deepest
    if fig is None:
        fig = plt.figure(figsize=(11, 4.8) if shown else (6, 4.8), layout="constrained")
    grid = fig.add_gridspec(max(1, (len(shown) + 1) // 2), 3, width_ratios=(1.4, 1, 1)) if shown else fig.add_gridspec()
    main = fig.add_subplot(grid[:, 0])
    boxes = [c.box for c in shown]
    if particle is not None:  # before the cells, which set the view (a line is drawn above them all the same)
        draw_particle(particle, main, color="0.6", arrow=False, lw=1.0)
        v = as_polyline(particle, 256).vertices
        boxes.append((v[:, 0].min(), v[:, 0].max(), v[:, 1].min(), v[:, 1].max()))
    if boxes:
        boxes = np.array(boxes)
        whole = (boxes[:, 0].min(), boxes[:, 1].max(), boxes[:, 2].min(), boxes[:, 3].max())
        _draw_cells(main, found, _padded(whole))
    main.set_aspect("equal", adjustable="datalim")  # equal scales on the whole panel: the limits widen to fill it
    main.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(4))  # a narrow panel: labels that do not touch
    main.set_xlabel("x (b)")
    main.set_ylabel("y (b)")
    handles = []
    if not shown:  # say what was looked for: a blank map alone reads as a failure
        bar = found.resolution + found.rim
        handles.append(Patch(color="none", label=f"no component at least {bar:.2e} b deep (resolution + rim)"))
    for k, comp in enumerate(shown):
        color = COMPONENT_COLORS[k % len(COMPONENT_COLORS)]
        label = f"{k + 1}: depth ≥ {comp.depth:.2g} b, area {comp.area:.2g} b$^2$"
        if not comp.area:
            label = f"{k + 1}: no cell certified, area ≤ {comp.area_bound:.2g} b$^2$"
        if comp.tag():
            label += f" ({comp.tag()})"
        handles.append(Patch(color=color, label=label))
        ax = fig.add_subplot(grid[k // 2, 1 + k % 2])
        _draw_cells(ax, found, _padded(comp.box, 0.05))
        ax.set_aspect("equal", adjustable="datalim")
        width, height = comp.box[1] - comp.box[0], comp.box[3] - comp.box[2]
        ax.set_title(f"component {k + 1}: {width:.2g} × {height:.2g} b", fontsize=8, color=color)
        ax.tick_params(labelsize=6)
        for axis in (ax.xaxis, ax.yaxis):  # plain numbers in b: an offset label is easily misread
            axis.set_major_locator(matplotlib.ticker.MaxNLocator(3))
            axis.set_major_formatter(matplotlib.ticker.ScalarFormatter(useOffset=False))
    if particle is not None:
        handles.append(Line2D([], [], color="0.6", lw=1.0, label="the fixed particle"))
    if shown and np.any((found.cells["status"] == 2) & (found.cells["component"] >= 0)):
        handles.append(Patch(facecolor="0.5", alpha=0.3, label="pale: undecided cells (whether excluded or not)"))
    if any(c.depth < c.departure for c in shown):
        handles.append(
            Patch(color="none", label=f"† shallower than the polylines' departure ({shown[0].departure:.1e} b)")
        )
    if handles:  # below the figure, so that it hides no component
        fig.legend(handles=handles, fontsize=7, loc="outside lower left")
    what = f"{found.headline} excluded component{'s' if found.high != 1 else ''} at resolution {found.resolution:.0e} b"
    fig.suptitle(f"{title}: {what}" if title else what, fontsize=10)
    return fig


@dataclass(frozen=True)
class _Series:
    """One line of :func:`count_plot`: openings (deg), the count's bracket, depths (b; opening × component or
    × component followed over Ψ, NaN where none), resolution + rim (b) and change brackets (deg)."""

    label: str
    deg: np.ndarray
    low: np.ndarray
    high: np.ndarray
    depths: np.ndarray
    bar: np.ndarray
    brackets: list
    followed: bool
    ends: np.ndarray = None  # (component, 2): where each followed component's depth reaches 0, and its bar (deg)

    @property
    def first_end(self) -> int:
        """The first component with an end estimate (its marker is named in the legend)."""
        finite = np.flatnonzero(np.isfinite(self.ends[:, 0])) if self.ends is not None else []
        return int(finite[0]) if len(finite) else -1


def _count_series(source) -> list:
    """The :class:`_Series` of a :class:`Transitions` (its components followed over Ψ) or of a collected sweep
    that kept "topology" (one per n)."""
    if isinstance(source, xr.Dataset):
        deg = _opening_degrees(source)
        bar = (source.excluded_components.attrs.get("resolution", 0.0) + source.component_rim).values
        if "n" in source.excluded_components.dims:
            subsets = [(f"$n = {float(n):g}$", source.sel(n=n), bar[k]) for k, n in enumerate(source.n.values)]
        else:
            subsets = [("", source, bar)]
        return [
            _Series(label, deg, sub.excluded_components.values, sub.excluded_components_high.values,
                    sub.component_depth.transpose("opening", ...).values.reshape(len(deg), -1),
                    np.broadcast_to(b, deg.shape), [], False)
            for label, sub, b in subsets
        ]  # fmt: skip
    counts = [source.counts[o] for o in source.openings]
    brackets = [(math.degrees(t.low), math.degrees(t.high)) for t in source.changes]
    return [
        _Series("", np.degrees(source.openings), np.array([c.low for c in counts]),
                np.array([c.high for c in counts]), source.lives.depth.transpose("opening", "life").values,
                np.array([c.resolution + c.rim for c in counts]), brackets, True,
                np.column_stack([source.lives.end_estimate.values, source.lives.end_estimate_error.values]))
    ]  # fmt: skip


def count_plot(source, *, family=None, zoom="auto", fig=None):
    """The certified count of excluded components over the opening Ψ, and each component's certified depth.

    ``source``: :func:`sesp.transitions`' result (each change's bracket shaded, each component followed over
    Ψ as one line) or a collected sweep that kept "topology" (one colour per n). Top: the count; where it is
    undecided, a bar from the bracket's low to its high end, cut and marked ▲ one above the largest low end.
    Bottom: each component's certified depth (b, log scale) and, dashed, resolution + rim: the depth from which
    a component is counted, so the count at any depth can be read off (the persistence of the excluded set over
    Ψ); for the ASP the exact lens depth 1 − sin(Ψ/2). The right-hand column repeats both over ``zoom``
    (degrees; "auto": 165°–181°, where the changes near Ψ = π crowd together, for a :class:`Transitions`, none
    for a sweep; None, or a range searched less than three times as wide: no zoom). ``family`` names the
    particle in the title.
    """
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    series = _count_series(source)
    if isinstance(zoom, str):
        zoom = None if isinstance(source, xr.Dataset) else (165.0, 181.0)
    start = min(float(s.deg.min()) for s in series)
    end = max(float(s.deg.max()) for s in series)
    if zoom is not None and end - start < 3 * (zoom[1] - zoom[0]):
        zoom = None
    columns = 1 if zoom is None else 2
    fig = fig or plt.figure(figsize=(5.0 * columns + 1.0, 6.0), layout="constrained")
    axes = np.asarray(fig.subplots(2, columns, sharex="col", squeeze=False))
    ceiling = max(int(np.max(s.low, initial=0)) for s in series) + 1
    for top, bottom in axes.T:
        for i, one in enumerate(series):
            _draw_count(top, bottom, one, f"C{i}", ceiling)
        top.yaxis.set_major_locator(MaxNLocator(integer=True))
        top.set_ylim(-0.3, ceiling + 0.3)
        bottom.set_yscale("log")
        bottom.set_xlabel(PSI_LABEL)
        if isinstance(family, SeSP) and family.n == 2 and family.m == 2 and family.aspect == 1:
            psi = np.linspace(start, min(end, 179.9), 400)
            bottom.plot(psi, 1 - np.sin(np.radians(psi) / 2), "k:", lw=1, label=r"exact lens $1 - \sin(\Psi/2)$")
    axes[0, 0].set_ylabel("excluded components")
    axes[1, 0].set_ylabel("certified depth of each component (b)")
    axes[0, 0].set_xlim(start, end)
    if zoom is not None:
        axes[0, 1].set_xlim(*zoom)
        axes[0, 1].set_title(f"{zoom[0]:g}°–{zoom[1]:g}°", fontsize=9)
    axes[0, 0].legend(handles=_count_handles(series, ceiling), frameon=False, fontsize=7)
    axes[1, 0].legend(frameon=False, fontsize=7)
    named = f"{shape_label(family, opening=False)}: " if family is not None else ""
    fig.suptitle(f"{named}excluded components at resolution {_count_resolution(source):g} b", fontsize=10)
    return fig


def _count_resolution(source) -> float:
    if isinstance(source, xr.Dataset):
        return float(source.excluded_components.attrs.get("resolution", math.nan))
    return float(source.resolution)


def _draw_count(top, bottom, one: _Series, color, ceiling):
    """One series of :func:`count_plot`: its count, undecided bars, change brackets, depths and bar."""
    top.step(one.deg, one.low, where="post" if one.brackets else "mid", color=color, lw=1.2, label=one.label or "count")
    undecided, above = one.high > one.low, one.high > ceiling
    top.vlines(one.deg[undecided], one.low[undecided], np.minimum(one.high, ceiling)[undecided], color="C3", lw=2)
    top.plot(one.deg[above], np.full(int(above.sum()), ceiling), "^", color="C3", ms=5)
    for lo, hi in one.brackets:
        top.axvspan(lo, hi, color="C1", alpha=0.3, lw=0)
    for k in range(one.depths.shape[1]):
        seen = np.isfinite(one.depths[:, k])
        if one.followed:  # each component followed over Ψ: one line each, and where its depth reaches 0
            (line,) = bottom.plot(one.deg[seen], one.depths[seen, k], "o-", ms=2.5, lw=0.8, label=f"component {k + 1}")
            end, bar = one.ends[k]
            if np.isfinite(end):
                bottom.errorbar(
                    end,
                    one.depths[seen, k][-1] / 3,
                    xerr=bar,
                    fmt="x",
                    ms=5,
                    color=line.get_color(),
                    capsize=2,
                    label="where its depth reaches 0 (fit)" if k == one.first_end else None,
                )
        else:
            label = f"depths {one.label}".strip() if k == 0 else None
            bottom.plot(one.deg[seen], one.depths[seen, k], "o", ms=3, color=color, label=label)
    bottom.plot(one.deg, one.bar, "--", color="k" if one.followed else color, lw=0.8,
                label=f"resolution + rim {one.label}".strip())  # fmt: skip


def _count_handles(series, ceiling) -> list:
    """Legend entries of :func:`count_plot`'s top panel: every mark drawn, once."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=f"C{i}", lw=1.2, label=s.label or "count") for i, s in enumerate(series)]
    if any(s.brackets for s in series):
        handles.append(Line2D([], [], color="C1", lw=6, alpha=0.3, label="bracket of a change"))
    if any((s.high > s.low).any() for s in series):
        handles.append(Line2D([], [], color="C3", lw=2, label="undecided: the bracket"))
    if any((s.high > ceiling).any() for s in series):
        handles.append(Line2D([], [], color="C3", marker="^", ls="", ms=5, label=f"bracket reaching above {ceiling}"))
    return handles


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
    cols = 2 if len(points) == 4 else min(3, len(points))  # panels laid out for their number
    rows = -(-len(points) // cols)
    fig = fig or plt.figure(figsize=(3.6 * cols + 1.6, 3.4 * rows + 0.4), layout="constrained")
    key_column = style == "raster"  # the 2D key needs room; the dots' φ colour bar goes beside the panels
    grid = fig.add_gridspec(rows, cols + key_column, width_ratios=[1] * cols + [0.45] * key_column)
    axes = [fig.add_subplot(grid[i // cols, i % cols]) for i in range(len(points))]
    for ax, point in zip(axes, points):
        sub = ds.sel(point)
        shape = SeSP(n=float(sub.n) if "n" in sub.coords else 2.0, opening=float(sub.opening))
        allowed_map(sub, style=style, ax=ax, particle=shape, colorbar=False)
        ax.set_title(f"$n = {shape.n:g}$, $\\Psi = {math.degrees(shape.opening):.0f}°$", fontsize=9)
    if key_column:
        orientation_key(fig.add_subplot(grid[0, cols]))
    else:
        sm = plt.cm.ScalarMappable(cmap=PHI_CMAP, norm=plt.Normalize(0, 2 * np.pi))
        _phi_colorbar(fig, sm, ax=axes, shrink=0.6)
    fig.legend(handles=map_legend_handles(style), loc="outside lower center", ncols=5, fontsize=7, frameon=False)
    return fig


def _product(ds, dims):
    return itertools.product(*(ds[d].values for d in dims))


def save_figure(fig, path, *, dpi: float = 150, palette: bool = False):
    """Save ``fig`` (tight bounding box). ``palette``: a PNG of scattered dots is stored with a 256-colour
    palette, which keeps every dot's colour to within a palette step and makes the file several times smaller."""
    path = Path(path)
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    if palette and path.suffix.lower() == ".png":
        from PIL import Image

        with Image.open(path) as image:
            quantized = image.convert("RGB").quantize(colors=256, dither=Image.Dither.NONE)
        quantized.save(path, optimize=True)
    return path


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
        save_figure(fig, target, dpi=dpi, palette=kind == "maps")
        plt.close(fig)
        outcome[target.name] = target
    return outcome


def figure(kind: str, ds: xr.Dataset | None = None):
    """One of the paper's figures as a matplotlib Figure.

    ``kind`` is "gallery", "maps" (dots), "maps_raster", "curve", "panels",
    "topology", "onsager", "thickness" or "phases"; ``ds`` is the matching collected sweep (not for "gallery").
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
        return count_plot(ds)
    if kind == "onsager":
        return onsager_plot(ds)
    if kind == "thickness":
        return thickness_curves(ds)
    if kind == "phases":
        return phase_diagram(ds)
    raise ValueError(f"unknown figure kind {kind!r}")


PHASE_COLORS = {0: "0.9", 1: "tab:red", 2: "tab:blue", 4: "tab:green"}
PHASE_FILLS = {1: "#fcd5c8", 2: "#d4e4f4", 4: "#d5efd0"}  # opaque light tints: no seams where bands meet


def _parsons_lee_differs(ds) -> bool:
    """Whether ``ds`` holds Parsons–Lee transition densities that differ from the second-virial ones."""
    if "parsons_lee_transition_density" not in ds:
        return False
    pl, plain = ds.parsons_lee_transition_density.values, ds.transition_density.values
    both = np.isfinite(pl) & np.isfinite(plain)
    return bool(np.any(pl[both] != plain[both]))


def phase_diagram(ds, *, axes=None):
    """Density of the first ordering transition against the opening Ψ, one column per n (Onsager theory).

    ``ds`` over (``n``, ``opening``) holds ``transition_order`` (k: 1 polar, 2 nematic, 4 tetratic; 0 none),
    ``transition_density`` and ``ordered_density`` (b⁻²; the coexisting densities of a first-order
    transition) and ``continuous`` (as ``benchmarks/phase_diagram.py`` writes it, from
    :func:`sesp.onsager.first_transition`). Top row: below the line the isotropic state is stable; the band
    above is coloured by the order that appears; first-order transitions are hollow markers; an opening with
    no transition (the isotropic state stable at every density, as for the closed circle) is a grey cross on
    the lower edge. ``transition_density_error`` (a sweep's, where present) is drawn as error bars, and
    ``parsons_lee_transition_density``, where it differs from the second-virial density (thick particles),
    as a dashed line. Bottom row: the coexistence gap of each first-order transition, (ρ_ordered −
    ρ_isotropic)/ρ_isotropic in per cent, too narrow to see on the density's log scale. ``axes``: the top
    row's axes, one per n (the gaps are then not drawn). Returns the figure.
    """
    import matplotlib.pyplot as plt

    if "transition_density" not in ds:
        raise ValueError("phase_diagram needs transition_density: a sweep that keeps 'phases'")
    if "n" not in ds.dims:  # a sweep over the opening alone: its one n
        n = float(ds.n) if "n" in ds.coords else float(ds.attrs.get("particle_n", math.nan))
        ds = ds.drop_vars("n", errors="ignore").expand_dims(n=[n])
    ns = list(ds.n.values)
    gaps = None
    if axes is None:
        fig, both = plt.subplots(2, len(ns), figsize=(3.6 * len(ns), 5.2), sharex="col", sharey="row",
                                 height_ratios=(3, 1.2), layout="constrained", squeeze=False)  # fmt: skip
        axes, gaps = both[0], both[1]
    axes = np.atleast_1d(axes)
    degrees = np.degrees(ds.opening.values)
    top = float(np.nanmax(ds.ordered_density.values)) * 3
    lowest = ["transition_density"] + ["parsons_lee_transition_density"] * _parsons_lee_differs(ds)
    bottom = min(float(np.nanmin(ds[name].values)) for name in lowest) / 3
    for i, (ax, n) in enumerate(zip(axes, ns, strict=True)):
        row = ds.sel(n=n)
        _draw_transitions(ax, degrees, row, bottom, top)
        ax.set_title(f"n = {n:g}", fontsize=10)
        if gaps is not None:
            _draw_gaps(gaps[i], degrees, row)
        else:
            ax.set_xlabel("opening Ψ (degrees)")
    axes[0].set_ylabel(r"density $\rho$ ($b^{-2}$)")
    fig = axes[0].figure
    handles = _phase_handles(ds)
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=8)
    if gaps is not None:  # one scale for every panel's gaps
        first = (ds.transition_order > 0) & (ds.continuous == 0)
        widest = float((100 * (ds.ordered_density - ds.transition_density) / ds.transition_density).where(first).max())
        gaps[0].set_ylim(0, 1.3 * widest if np.isfinite(widest) and widest > 0 else 1.0)
    thickness = float(ds.thickness) if "thickness" in ds.coords and ds.thickness.ndim == 0 else None
    thickness = ds.attrs.get("thickness", thickness)
    what = "second-virial Onsager theory" + ("; dashed: Parsons-Lee" if _parsons_lee_differs(ds) else "")
    particles = f"SeSPs of thickness {thickness:g} b" if thickness else "thin SeSPs"
    fig.suptitle(f"first ordering transition of the isotropic state, {particles}\n({what})", fontsize=10)
    return fig


def _draw_transitions(ax, degrees, row, bottom, top):
    """One n's transition density over Ψ: the line, the ordered band, the markers, the openings without one."""
    rho, order = row.transition_density.values, row.transition_order.values.astype(int)
    for i in range(len(degrees) - 1):  # the ordered band, each step coloured by the order at its ends
        k = order[i] or order[i + 1]
        if k and np.isfinite(rho[i : i + 2]).all():
            ax.fill_between(degrees[i : i + 2], rho[i : i + 2], top, color=PHASE_FILLS[k], linewidth=0)
    ax.plot(degrees, rho, color="k", lw=1)
    if "transition_density_error" in row:
        ax.errorbar(degrees, rho, yerr=row.transition_density_error.values, fmt="none", ecolor="k", lw=1)
    if _parsons_lee_differs(row):
        ax.plot(degrees, row.parsons_lee_transition_density.values, color="0.35", lw=1, ls="--")
    for d, r, k, cont in zip(degrees, rho, order, row.continuous.values, strict=True):
        if k and np.isfinite(r):
            face = PHASE_COLORS[k] if cont else "white"
            ax.plot([d], [r], "o", color=PHASE_COLORS[k], markerfacecolor=face, markersize=5)
    missing = (order == 0) | ~np.isfinite(rho)
    if missing.any():  # on the edge, unclipped (an empty unclipped line would upset the layout)
        ax.plot(degrees[missing], np.full(int(missing.sum()), bottom * 1.25), "x", color="0.4", ms=6, clip_on=False)
    ax.set_yscale("log")
    ax.set_ylim(bottom, top)
    ax.set_xlim(degrees[0], degrees[-1])
    ax.set_xticks(np.arange(0, 361, 90))
    ax.text(0.03, 0.06, "isotropic", transform=ax.transAxes, fontsize=8, color="0.3")


def _draw_gaps(ax, degrees, row):
    """One n's coexistence gaps (per cent of the isotropic density) at its first-order transitions."""
    rho, high = row.transition_density.values, row.ordered_density.values
    order = row.transition_order.values.astype(int)
    first = (order > 0) & (row.continuous.values == 0) & np.isfinite(rho) & np.isfinite(high)
    for d, r, h, k in zip(degrees[first], rho[first], high[first], order[first], strict=True):
        ax.plot([d, d], [0, 100 * (h - r) / r], color=PHASE_COLORS[k], lw=2)
        ax.plot([d], [100 * (h - r) / r], "o", color=PHASE_COLORS[k], markerfacecolor="white", markersize=5)
    if not first.any():
        ax.text(0.5, 0.5, "every transition continuous", transform=ax.transAxes, ha="center", fontsize=8)
    ax.set_xlabel("opening Ψ (degrees)")
    if ax.get_subplotspec().is_first_col():
        ax.set_ylabel("gap (%)")


def _phase_handles(ds) -> list:
    """The legend of :func:`phase_diagram`: the orders shown, the kinds of transition, no transition."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    present = sorted({int(k) for k in np.unique(ds.transition_order.values) if k})
    handles = [Patch(color=PHASE_FILLS[k], label=ORDER_NAME[k]) for k in present]
    handles += [
        Line2D([], [], marker="o", color="k", linestyle="", label="continuous"),
        Line2D([], [], marker="o", color="k", markerfacecolor="white", linestyle="", label="first order"),
    ]
    missing = (ds.transition_order.values == 0) | ~np.isfinite(ds.transition_density.values)
    if missing.any():
        handles.append(Line2D([], [], marker="x", color="0.4", linestyle="", label="no transition"))
    if _parsons_lee_differs(ds):
        handles.append(Line2D([], [], color="0.35", ls="--", label="Parsons-Lee"))
    return handles
