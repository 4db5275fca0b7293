import subprocess
import sys

import numpy as np
import pytest

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
def test_topology_report_with_the_axis_count(capsys):
    assert (
        main(
            [
                "-q",
                "topology",
                "--n",
                "2",
                "--opening-range",
                "150",
                "190",
                "--step",
                "20",
                "--nx",
                "24",
                "--nphi",
                "16",
                "--segments",
                "64",
                "--refine",
                "1",
                "--axis",
                "64",
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    axis = text[text.index("excluded (axis)") :]
    assert "transitions on 64 axis nodes, exact in phi" in axis
    assert "2 -> 0 at Psi" in axis  # island and body end together, at π
    assert main(["topology", "--axis", "4"]) == 2
    assert "--axis" in capsys.readouterr().err
