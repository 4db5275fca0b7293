"""Image tests: every plot renders without warnings and the PNG is not blank."""

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from sesp import Grid, SeSP, plot, scan
from sesp.cli import main
from sesp.regions import position_summary
from sesp.sweep import run

from cases import SMALL


def _pixels(path):
    image = plt.imread(path)[..., :3]
    return image.reshape(-1, 3)


def assert_not_blank(path, min_colors=8):
    pixels = _pixels(path)
    assert pixels.std() > 0.05, "image is (nearly) uniform"
    assert len(np.unique(np.round(pixels, 2), axis=0)) >= min_colors, "image has too few colours"
    assert (pixels.sum(axis=1) < 1.5).mean() > 0.002, "nothing dark drawn"


@pytest.fixture(scope="module")
def scan_ds():
    return scan(SeSP(n=2, opening=math.pi / 2), Grid(48, nphi=32), segments=48, entangled=True)


@pytest.fixture(scope="module")
def sweep_ds(tmp_path_factory):
    import xarray as xr

    folder = tmp_path_factory.mktemp("sweep")
    path = folder / "s.toml"
    text = SMALL.format(out=folder / "out").replace("n = [2, 8]", "n = [2, 4, 8, 10]")
    text = text.replace("stop = 120, step = 30", "stop = 270, step = 45")
    path.write_text(text)
    return xr.load_dataset(run(path, workers=1, progress=False))


@pytest.fixture(scope="module")
def topology_ds(tmp_path_factory):
    """A collected sweep that kept the certified count (coarse, so it takes seconds)."""
    import xarray as xr

    folder = tmp_path_factory.mktemp("topology")
    text = SMALL.format(out=folder / "out").replace("stop = 120, step = 30", "stop = 270, step = 60")
    text = text.replace('keep = ["excluded_area", "classes"]', 'keep = ["topology"]\nresolution = 0.05')
    path = folder / "s.toml"
    path.write_text(text)
    return xr.load_dataset(run(path, workers=1, progress=False))


def _save(fig_or_ax, path):
    fig = getattr(fig_or_ax, "figure", fig_or_ax)
    fig.savefig(path, dpi=60)
    plt.close(fig)
    return path


def test_shape_gallery(tmp_path):
    assert_not_blank(_save(plot.shape_gallery(), tmp_path / "g.png"))


@pytest.mark.parametrize("style", ["raster", "dots"])
def test_allowed_map_from_scan(scan_ds, tmp_path, style):
    assert_not_blank(_save(plot.allowed_map(scan_ds, style=style), tmp_path / "m.png"))


def test_allowed_map_from_summary_has_class_outlines(scan_ds, tmp_path):
    ax = plot.allowed_map(position_summary(scan_ds))
    assert ax.collections, "class outlines are drawn as contours"
    assert_not_blank(_save(ax, tmp_path / "s.png"))
    with pytest.raises(ValueError, match="dots"):
        plot.allowed_map(position_summary(scan_ds), style="dots")


@pytest.mark.slow
def test_excluded_area_curve_and_panels(sweep_ds, tmp_path):
    assert_not_blank(_save(plot.excluded_area_curve(sweep_ds), tmp_path / "c.png"))
    fig = plot.excluded_area_panels(sweep_ds)
    assert len(fig.axes) >= 9
    assert_not_blank(_save(fig, tmp_path / "p.png"))


def test_curves_shade_their_error_bars(sweep_ds, tmp_path):
    """The stored error bars are drawn as bands: invisible at their true size (1e-4 of A_ex), so here made
    large; the band's pale shade of the line colour then covers many pixels."""

    def pale_pixels(ds):
        path = _save(plot.excluded_area_curve(ds, ax=plt.figure(figsize=(5, 4)).gca()), tmp_path / "e.png")
        pixels = _pixels(path)
        pale_blue = (np.abs(pixels - np.array([0.70, 0.82, 0.91])) < 0.06).all(axis=1)  # C0 at alpha 0.3
        return int(pale_blue.sum())

    assert "mean_normalized_excluded_area_error" in sweep_ds
    widened = sweep_ds.assign(mean_normalized_excluded_area_error=sweep_ds.mean_normalized_excluded_area * 0 + 0.1)
    assert pale_pixels(sweep_ds) < 50 < pale_pixels(widened)


@pytest.mark.slow
def test_count_plot_of_a_sweep(topology_ds, tmp_path):
    """One line per n, integer count ticks, every component's depth and the depth that decides the count."""
    fig = plot.count_plot(topology_ds)
    top, bottom = fig.axes[0], fig.axes[1]
    assert fig.get_suptitle() == "excluded components at resolution 0.05 b"
    assert list(top.lines[0].get_ydata()) == topology_ds.excluded_components.sel(n=2).values.tolist()
    ticks = [t for t in top.get_yticks() if top.get_ylim()[0] <= t <= top.get_ylim()[1]]
    assert ticks and all(float(t).is_integer() for t in ticks)
    assert top.get_ylim()[1] == int(topology_ds.excluded_components.max()) + 1.3
    bar = [line for line in bottom.lines if line.get_label() == "resolution + rim $n = 2$"]
    assert bar and np.allclose(bar[0].get_ydata(), 0.05 + topology_ds.component_rim.sel(n=2).values)
    assert_not_blank(_save(fig, tmp_path / "t.png"))


def test_count_plot_shades_brackets_marks_undecided_counts_and_names_the_particle(tmp_path):
    from sesp.certified import Certified, CertifiedComponent
    from sesp.topology import Transition, Transitions

    def found(low, high, depths):
        parts = [CertifiedComponent(1, d, 0.1, 0.2, (0.0, 1.0, -0.5, 0.5)) for d in depths]
        return Certified(low, high, 1e-5, 1e-3, 2e-6, parts)

    table = [
        (0, (1, 1, [0.9])), (90, (2, 2, [0.9, 0.3])), (170, (2, 3, [0.5, 0.01])), (175, (1, 434, [0.5])),
        (180, (0, 0, [])),
    ]  # fmt: skip
    counts = {math.radians(d): found(*c) for d, c in table}
    rad = sorted(counts)
    changes = [Transition(rad[i], rad[i + 1], counts[rad[i]], counts[rad[i + 1]]) for i in range(4)]
    result = Transitions(counts, changes, 1e-5, math.radians(5), math.radians(0.3))
    fig = plot.count_plot(result, family=SeSP(n=4))
    top, zoomed = fig.axes[0], fig.axes[1]
    assert zoomed.get_xlim() == (165.0, 181.0)
    assert list(top.lines[0].get_ydata()) == [1, 2, 2, 1, 0]
    assert len(top.patches) == 4  # one bracket per change
    bars = [s[:, 1].tolist() for s in top.collections[0].get_segments()]
    assert bars == [[2, 3], [1, 3]]  # undecided at 170° and 175°: the second cut one above the largest low end
    assert top.get_ylim() == (-0.3, 3.3)  # the counts stay readable beside a high end of 434
    assert list(top.lines[1].get_xdata()) == [175]  # ... which is marked at the cut
    assert fig.get_suptitle().startswith("n = 4: excluded components at resolution 1e-05 b")
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert "undecided: the bracket" in legend and "bracket reaching above 3" in legend
    assert_not_blank(_save(fig, tmp_path / "m.png"))


def test_map_grid_from_sweep(sweep_ds, tmp_path):
    assert_not_blank(_save(plot.map_grid(sweep_ds.isel(opening=[0, 1, 2]), style="raster"), tmp_path / "mg.png"))


@pytest.mark.slow
def test_cli_plot_and_figures(sweep_ds, tmp_path, capsys, topology_ds):
    from sesp import save

    assert main(["plot", "gallery", "-o", str(tmp_path / "gallery.png")]) == 0
    assert_not_blank(tmp_path / "gallery.png")
    results = tmp_path / "results"
    for name in ("asp_opening", "exponent_opening_orientation"):
        save(topology_ds.sel(n=2) if name == "asp_opening" else sweep_ds, results / name / f"{name}.nc")
    assert main(["figures", str(results), "-o", str(tmp_path / "figs")]) == 0
    written = sorted(p.name for p in (tmp_path / "figs").iterdir())
    assert written == [
        "fig1_shape_gallery.png",
        "fig4_asp_opening.png",
        "fig5_exponent_opening_orientation.png",
        "onsager_exponent_opening.png",
        "topology_asp.png",
    ]
    for name in written:
        assert_not_blank(tmp_path / "figs" / name)
    out = capsys.readouterr().out
    assert "skipped fig2_maps_asp.png: no " in out and "sesp sweep sweeps/maps_asp.toml" in out
    assert main(["figures", str(results), "-o", str(tmp_path / "pdf"), "--format", "pdf"]) == 0
    pdfs = sorted(p.name for p in (tmp_path / "pdf").iterdir())
    assert pdfs == [name.replace(".png", ".pdf") for name in written]
    assert (tmp_path / "pdf" / pdfs[0]).read_bytes()[:4] == b"%PDF"


def test_onsager_plot_draws_b2_and_the_leading_instability(sweep_ds, tmp_path):
    fig = plot.onsager_plot(sweep_ds)
    top, bottom = fig.axes
    assert len(top.lines) == sweep_ds.sizes["n"]  # one B₂ curve per n
    plotted = np.concatenate([line.get_ydata() for line in top.lines])
    np.testing.assert_allclose(np.sort(plotted), np.sort(sweep_ds.second_virial_coefficient.values.ravel()))
    assert bottom.get_yscale() == "log" and "rho" in bottom.get_ylabel()
    assert_not_blank(_save(fig, tmp_path / "onsager.png"))


def test_maps_explain_themselves_and_fill_their_panels(sweep_ds, tmp_path):
    four = sweep_ds.isel(opening=[0, 1]).isel(n=[0, 1])  # 2 x 2 points: a 2 x 2 layout, no empty slot
    fig = plot.map_grid(four.stack(point=("n", "opening")).unstack("point"), style="raster")
    maps = [ax for ax in fig.axes if ax.images and ax.get_xlabel().startswith("$x$")]
    assert len(maps) == 4
    positions = {(round(ax.get_position().x0, 2), round(ax.get_position().y0, 2)) for ax in maps}
    assert len({x for x, _ in positions}) == 2 and len({y for _, y in positions}) == 2
    legend_text = " ".join(t.get_text() for legend in fig.legends for t in legend.get_texts())
    assert "excluded" in legend_text and "free" in legend_text and "boundary" in legend_text
    key = [ax for ax in fig.axes if ax.get_ylabel() == "fraction allowed"]
    assert len(key) == 1  # the hue x lightness key of the raster style
    assert_not_blank(_save(fig, tmp_path / "maps.png"))


def test_panels_colour_bar_spans_the_drawn_phi_and_counts_have_integer_ticks(sweep_ds, tmp_path):
    fig = plot.excluded_area_panels(sweep_ds)
    bar = [ax for ax in fig.axes if "panels (f)" in ax.get_ylabel()]
    assert len(bar) == 1 and bar[0].get_ylim() == (0.0, 180.0)
    darkest = [line.get_color() for line in fig.axes[5].lines]
    assert all(sum(matplotlib.colors.to_rgb(c)) < 2.7 for c in darkest)  # no near-white line on white
    plt.close("all")


def test_class_map_names_the_classes(scan_ds, tmp_path):
    ax = plot.class_map(scan_ds)
    bar = ax.figure.axes[-1]
    assert [t.get_text() for t in bar.get_yticklabels()] == ["free", "spooning", "entangled", "excluded"]
    assert_not_blank(_save(ax, tmp_path / "classes.png"), min_colors=4)


def test_dots_maps_are_saved_with_a_palette(scan_ds, tmp_path):
    from PIL import Image

    from sesp import save

    path = save(scan_ds, tmp_path / "scan.nc")
    assert main(["plot", "map", str(path), "--style", "dots", "-o", str(tmp_path / "dots.png")]) == 0
    with Image.open(tmp_path / "dots.png") as image:
        assert image.mode == "P"  # 256 colours: several times smaller than RGBA noise
    assert_not_blank(tmp_path / "dots.png")
