import json
import math
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest

import sesp
from sesp import load
from sesp.cli import main


def test_scan_then_info(tmp_path, capsys):
    out = tmp_path / "out.nc"
    assert (
        main(
            [
                "-q",
                "scan",
                "--n",
                "2",
                "--opening",
                "90",
                "--nx",
                "24",
                "--nphi",
                "8",
                "--segments",
                "32",
                "-o",
                str(out),
            ]
        )
        == 0
    )
    ds = load(out)
    assert ds.attrs["particle_opening"] == pytest.approx(np.pi / 2)
    assert dict(ds.allowed.sizes) == {"phi": 8, "y": 24, "x": 24}
    capsys.readouterr()
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert "opening=90 deg" in text and "A_ex" in text


@pytest.mark.parametrize(
    "argv, word",
    [
        (["scan", "--n", "-2", "-o", "x.nc"], "n must be"),
        (["scan", "--opening", "400", "-o", "x.nc"], "--opening"),
        (["scan", "--nx", "2", "-o", "x.nc"], "nx"),
        (["info", "missing.nc"], "no such file"),
    ],
)
def test_errors_are_one_line_without_traceback(argv, word, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert word in err and "Traceback" not in err and err.count("\n") == 1


def test_python_dash_m_works(tmp_path):
    result = subprocess.run([sys.executable, "-m", "sesp", "--help"], capture_output=True, text=True)
    assert result.returncode == 0 and "scan" in result.stdout


@pytest.mark.slow
def test_topology_over_the_opening_prints_the_changes_and_json_with_units(tmp_path, capsys):
    command = ["-q", "topology", "--n", "2", "--opening-range", "150", "190", "--step", "40", "--width", "10",
               "--resolution", "1e-2", "--segments", "128"]  # fmt: skip
    png = tmp_path / "t.png"
    assert main([*command, "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert "excluded components over the opening, at resolution 1.0e-02 b" in text and "2 -> " in text
    assert png.stat().st_size > 20_000
    assert main([*command[1:], "--json"]) == 0  # not quiet: each change is told on stderr as it is bracketed
    told = capsys.readouterr()
    out = json.loads(told.out)  # stdout holds the JSON alone
    assert (out["n"], out["segments"], out["resolution"], out["width_deg"]) == (2.0, 128, 1e-2, 10.0)
    assert out["counts"][0] == {"opening_deg": 150.0, "opening": math.radians(150), "count_low": 2, "count_high": 2}
    assert out["transitions"][-1]["count_after"] == [0, 0] and out["transitions"][-1]["high_deg"] <= 190.0
    assert "found: " in told.err and "2 -> " in told.err


def test_global_options_are_accepted_after_the_command(tmp_path, capsys):
    out = tmp_path / "o.nc"
    assert main(["scan", "--nx", "8", "--nphi", "2", "--segments", "8", "-o", str(out), "-q"]) == 0
    assert capsys.readouterr().out == ""  # quiet
    with pytest.raises(FileNotFoundError):  # --debug after the command: the traceback is shown
        main(["info", str(tmp_path / "missing.nc"), "--debug"])


def test_every_option_has_help_text():
    import argparse

    from sesp.cli import build_parser

    parser = build_parser()
    (subcommands,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    for name, command in [("sesp", parser), *subcommands.choices.items()]:
        for action in command._actions:
            if action.dest == "help" or isinstance(action, argparse._SubParsersAction):
                continue
            assert action.help, f"{name} {action.option_strings or action.dest} has no help text"


@pytest.mark.parametrize(
    "option, value",
    [("--width", "nan"), ("--width", "1e-300"), ("--step", "inf"), ("--width", "100"), ("--resolution", "-1"),
     ("--base", "2"), ("--opening-range", "10 5"), ("--rim", "1e-6"), ("--rim", "nan")],
)  # fmt: skip
def test_topology_options_are_checked_in_their_units(option, value, capsys):
    assert main(["topology", option, *value.split()]) == 2
    err = capsys.readouterr().err
    assert option in err and ("degrees" in err or " b" in err or "cells" in err) and "Traceback" not in err


def test_plot_misuse_is_one_line(tmp_path, capsys):
    scan_file = tmp_path / "s.nc"
    main(["-q", "scan", "--nx", "8", "--nphi", "2", "--segments", "8", "-o", str(scan_file)])
    capsys.readouterr()
    assert main(["plot", "curve", str(scan_file), "-o", str(tmp_path / "c.png")]) == 2
    err = capsys.readouterr().err
    assert "needs a collected sweep" in err and str(scan_file) in err and err.count("\n") == 1


@pytest.mark.parametrize("manifest", ["[]", "{}", '{"points": []}', "not json"])
def test_collect_on_a_broken_manifest_is_one_line(manifest, tmp_path, capsys):
    (tmp_path / "sweep.json").write_text(manifest)
    assert main(["collect", str(tmp_path), "-o", str(tmp_path / "c.nc")]) == 2
    err = capsys.readouterr().err
    assert "sweep.json" in err and "Traceback" not in err and err.count("\n") == 1


def test_area_of_closed_circles_is_four_pi_within_its_error_bar(capsys):
    """`sesp area --json` on the closed circle: 4π within rtol and the printed error bar; B₂ is half, with half
    the bar; the parameters and units are in the JSON."""
    code = main(["-q", "area", "--opening", "0", "--rtol", "1e-4", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["converged"] and len(out["excluded_area"]) == out["nphi"]
    assert abs(out["mean_excluded_area"] - 4 * math.pi) <= out["mean_excluded_area_error"] <= 1e-4 * 4 * math.pi
    assert out["second_virial_coefficient"] == out["mean_excluded_area"] / 2
    assert out["second_virial_coefficient_error"] == out["mean_excluded_area_error"] / 2
    assert (out["n"], out["opening_deg"], out["units"]["areas"], out["excluded_area_of"]) == (
        2,
        0,
        "b^2",
        "smooth curves",
    )
    assert out["leading_instability"] == 0  # a circle's A_ex(φ) is flat: no order goes unstable
    assert main(["area", "--rows", "100"]) == 2 and "multiple of 8" in capsys.readouterr().err


def test_area_of_a_polyline_of_one_s_own(tmp_path, capsys):
    """`--vertices`: a needle of length 2 excludes 4 |sin φ|: <A_ex> = 8/π, B₂ = 4/π, nematic first at
    ρ* L² = 3π/2; with --thickness D the mean grows by 4 L D + π D² (a thick needle's Steiner terms)."""
    needle = tmp_path / "needle.txt"
    needle.write_text("-1 0\n1 0\n")
    assert main(["-q", "area", "--vertices", str(needle), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["mean_excluded_area"] == pytest.approx(8 / math.pi, rel=1e-5)
    assert out["leading_instability"] == 2
    assert out["leading_instability_density"] * 4 == pytest.approx(3 * math.pi / 2, rel=1e-4)
    assert main(["-q", "area", "--vertices", str(needle), "--thickness", "0.1", "--json"]) == 0
    thick = json.loads(capsys.readouterr().out)["mean_excluded_area"]
    assert thick == pytest.approx(8 / math.pi + 4 * 2 * 0.1 + math.pi * 0.01, rel=1e-5)
    assert main(["area", "--vertices", str(tmp_path / "none.txt")]) == 2
    assert "--vertices" in capsys.readouterr().err
    main(["-q", "area", "--vertices", str(needle)])
    printed = capsys.readouterr().out
    assert "polylines as given" in printed and "nematic (k = 2)" in printed and "B2" in printed


def test_virial_prints_what_python_computes_digit_for_digit(tmp_path, capsys):
    """`sesp virial --json`: B₂ and B₃ with their bars, the same floats as sesp.virial's functions; a mixture
    of two polylines by --vertices files and --fractions; angles in degrees."""
    from sesp.virial import second_virial, third_virial

    asp = sesp.SeSP(n=2, opening=math.radians(90))
    argv = ["-q", "virial", "--n", "2", "--opening", "90", "--nodes", "41", "--nphi", "4", "--b3-rtol", "0.01"]
    with warnings.catch_warnings():  # rtol 0.01 not met at 41 nodes and 4 orientations: said by b3_converged
        warnings.simplefilter("ignore")
        assert main([*argv, "--json"]) == 0
        b3 = third_virial(asp, rtol=0.01, nodes=41, nphi=4)
    out = json.loads(capsys.readouterr().out)
    b2 = second_virial(asp, rtol=1e-5)
    assert out["opening_deg"] == 90 and out["units"]["angles"] == "deg"
    assert out["second_virial_coefficient"] == float(b2.second_virial_coefficient)
    assert out["second_virial_coefficient_error"] == float(b2.second_virial_coefficient_error)
    assert out["third_virial_coefficient"] == float(b3.third_virial_coefficient)
    assert out["third_virial_coefficient_error"] == float(b3.third_virial_coefficient_error)
    assert out["b3_converged"] is False
    staple, needle = tmp_path / "staple.txt", tmp_path / "needle.txt"
    staple.write_text("0.5 -0.5\n-0.5 -0.5\n-0.5 0.5\n0.5 0.5\n")
    needle.write_text("-1 0\n1 0\n")
    files = ["--vertices", str(staple), "--vertices", str(needle), "--fractions", "0.3", "0.7"]
    assert main(["-q", "virial", *files, "--no-b3", "--rtol", "1e-4", "--json"]) == 0
    mixture = json.loads(capsys.readouterr().out)
    expected = second_virial([sesp.Polyline(np.loadtxt(staple)), sesp.Polyline(np.loadtxt(needle))], [0.3, 0.7],
                             rtol=1e-4)  # fmt: skip
    assert mixture["second_virial_coefficient"] == float(expected.second_virial_coefficient)
    assert main(["virial", *files[:2], "--fractions", "0.5", "0.5"]) == 2
    assert "--fractions" in capsys.readouterr().err


def test_phases_prints_the_instabilities_and_first_transition_python_computes(capsys):
    """`sesp phases --json`: each order's ρ*_k with its bar and the first transition with its kind and bar, the
    same floats as sesp.onsager's functions; n = 8 at 90° orders nematically, continuously."""
    from sesp.onsager import first_transition, instabilities

    assert main(["-q", "phases", "--n", "8", "--opening", "90", "--rtol", "1e-2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    area = sesp.excluded_area(sesp.SeSP(n=8, opening=math.radians(90)), rtol=1e-2)
    first, found = first_transition(area), instabilities(area)
    assert out["first_transition"]["kind"] == "continuous" and out["first_transition"]["order"] == 2
    assert out["first_transition"]["density"] == float(first.transition_density)
    assert out["first_transition"]["density_error"] == float(first.transition_density_error) > 0
    nematic = [row for row in out["instabilities"] if row["order"] == 2][0]
    assert nematic["density"] == float(found.density.sel(order=2)) == out["first_transition"]["density"]
    assert [row["density"] for row in out["instabilities"] if row["order"] == 1] == [None]  # a_1 > 0: never
    main(["-q", "phases", "--n", "8", "--opening", "90", "--rtol", "1e-2"])
    assert "nematic (k = 2), continuous, at rho = " in capsys.readouterr().out


def test_version_is_the_package_s(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip() == f"sesp {sesp.__version__}"


def test_the_command_line_scan_writes_the_file_python_writes(tmp_path, capsys):
    """`sesp scan` is `sesp.scan` then `sesp.save`: the same file, bit for bit (provenance aside), and `sesp info`
    describes both alike."""
    from sesp import Grid, SeSP, save, scan

    from cases import content_digest

    cli = tmp_path / "cli.nc"
    assert main(["-q", "scan", "--n", "8", "--opening", "90", "--nx", "16", "--nphi", "8", "--segments", "16",
                 "-o", str(cli)]) == 0  # fmt: skip
    python = save(scan(SeSP(n=8, opening=math.radians(90)), Grid(16, nphi=8), segments=16), tmp_path / "py.nc")
    assert content_digest(cli) == content_digest(python)
    capsys.readouterr()
    main(["info", str(cli)])
    main(["info", str(python)])
    first, second = capsys.readouterr().out.split("sesp.scan file")[1:]
    assert first == second


def test_topology_help_states_the_defaults_the_engine_uses():
    """The parser does not import the engine (start-up stays fast): its help text names the defaults, which
    must be the engine's."""
    from sesp.certified import BASE, RESOLUTION, RIM
    from sesp.cli import build_parser
    from sesp.topology import STEP, WIDTH

    (sub,) = [a for a in build_parser()._actions if hasattr(a, "choices") and a.choices and "topology" in a.choices]
    stated = {a.dest: float(re.search(r"\(default ([\d.e-]+)[,)]", a.help)[1]) for a in sub.choices["topology"]._actions
              if a.dest in ("resolution", "rim", "base", "step", "width")}  # fmt: skip
    assert stated == {"resolution": RESOLUTION, "rim": RIM, "base": BASE, "step": math.degrees(STEP),
                      "width": math.degrees(WIDTH)}  # fmt: skip


def test_the_compile_notice_names_each_command_s_own_kernels(tmp_path, monkeypatch):
    """The notice "compiling numba kernels" is shown until every kernel module the command uses is cached:
    `sesp topology` does not compile the overlap kernels of a scan, and the reverse."""
    import numba

    from sesp.cli import kernels_cached

    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path))
    assert not kernels_cached(["depth"])
    (tmp_path / "sesp_kernels").mkdir()
    (tmp_path / "sesp_kernels" / "depth.cover-12.py311.nbi").touch()
    assert kernels_cached(["depth"])
    assert not kernels_cached(["depth", "overlap"])


def test_a_sweep_keeping_topology_waits_for_the_certified_count_s_kernels_too():
    from sesp.cli import CERTIFIED_KERNELS, sweep_kernels

    assert set(CERTIFIED_KERNELS) <= set(sweep_kernels(("excluded_area", "topology")))
    assert not set(CERTIFIED_KERNELS) & set(sweep_kernels(("excluded_area", "classes")))


STAPLE_ROWS = "-0.5 0.5\n-0.5 -0.5\n0.5 -0.5\n0.5 0.5\n"


@pytest.mark.parametrize("shape", ["n8", "staple"])
def test_every_route_to_the_excluded_area_gives_the_same_number_and_bar(shape, tmp_path, capsys):
    """n = 8 at 90° and a staple of thickness 0.05 b: `sesp.excluded_area`, `sesp area`, `sesp info` on a
    command-line scan and on a Python scan, and a sweep report the same ⟨A_ex⟩ and error bar, digit for digit
    (and the sweep the same first instability as `sesp area`)."""
    from sesp import Grid, Polyline, SeSP, excluded_area, save, scan
    from sesp.report import area_text
    from sesp.sweep import run

    from cases import write_sweep

    rtol = "1e-3"  # the defaults' 1e-5 takes seconds more per route; the route, not the tolerance, is tested
    if shape == "n8":
        particle, args = SeSP(n=8, opening=math.radians(90)), ["--n", "8", "--opening", "90"]
        toml = "[particle]\nn = 8\nopening = 90\n"
    else:
        (tmp_path / "staple.txt").write_text(STAPLE_ROWS)
        particle = Polyline(np.loadtxt(tmp_path / "staple.txt"), thickness=0.05)
        args = ["--vertices", str(tmp_path / "staple.txt"), "--thickness", "0.05"]
        toml = "[particle]\nvertices = [[-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5], [0.5, 0.5]]\nthickness = 0.05\n"
    best = excluded_area(particle, rtol=float(rtol))
    expected = area_text(float(best.mean_excluded_area), float(best.mean_excluded_area_error))
    assert main(["-q", "area", *args, "--rtol", rtol, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert area_text(out["mean_excluded_area"], out["mean_excluded_area_error"]) == expected
    cli = tmp_path / "cli.nc"
    assert main(["-q", "scan", *args, "--nx", "16", "--nphi", "8", "-o", str(cli)]) == 0
    python = save(scan(particle, Grid(16, nphi=8)), tmp_path / "py.nc")
    for path in (cli, python):
        assert main(["info", "--rtol", rtol, str(path)]) == 0
        assert f"A_ex     : {expected} (of the {best.attrs['excluded_area_of']};" in capsys.readouterr().out
    collected = run(write_sweep(tmp_path, f"{toml}\n[output]\nrtol = {rtol}\n"), workers=1, progress=False)
    swept = load(collected)
    for name in ("mean_excluded_area", "mean_excluded_area_error"):
        assert float(swept[name]) == float(best[name])
    assert float(swept.second_virial_coefficient_error) == float(best.mean_excluded_area_error) / 2
    leading = int(swept.leading_instability)  # and so B₂'s spectrum: the first instability as `sesp area` gives it
    assert leading == out["leading_instability"]
    assert float(swept.instability_density.sel(order=leading)) == out["leading_instability_density"]
