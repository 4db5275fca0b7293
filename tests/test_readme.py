"""Every ```python block of README.md runs, in order, in one namespace (grids made small)."""

import re
import shutil

import matplotlib
import pytest

from sesp.sweep import run

from cases import ROOT

README = ROOT / "README.md"


def python_blocks(text: str) -> list:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def small(code: str) -> str:
    """The same code on small grids: every Grid(n...) gets 32 cells and at most 16 orientations."""
    code = re.sub(r"Grid\(\d+", "Grid(32", code)
    return re.sub(r"nphi=\d+", "nphi=16", code)


@pytest.fixture
def quick_results(tmp_path, monkeypatch):
    """The README's main job (sesp sweep sweeps/quick.toml) on a small grid, in a fresh folder."""
    monkeypatch.chdir(tmp_path)
    shutil.copytree(ROOT / "sweeps", tmp_path / "sweeps")
    sweep = tmp_path / "sweeps" / "quick.toml"
    sweep.write_text(re.sub(r"nphi = \d+", "nphi = 16", re.sub(r"nx = \d+", "nx = 32", sweep.read_text())))
    run(sweep, workers=1, progress=False)
    return tmp_path


def test_readme_has_python_blocks():
    assert len(python_blocks(README.read_text())) >= 3


def test_every_python_block_runs(quick_results):
    matplotlib.use("Agg")
    namespace = {}
    for block in python_blocks(README.read_text()):
        exec(compile(small(block), str(README), "exec"), namespace)
    import matplotlib.pyplot as plt

    plt.close("all")
