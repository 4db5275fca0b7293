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


def shell_lines(text: str) -> list:
    """The command lines of every ```bash block, comments dropped."""
    lines = []
    for block in re.findall(r"^```bash\n(.*?)^```", text, flags=re.S | re.M):
        for line in block.splitlines():
            command = line.split(" #")[0].strip()
            if command:
                lines.append(command)
    return lines


def test_every_readme_command_line_is_accepted_by_the_cli_or_names_a_real_script():
    import shlex

    from sesp.cli import build_parser

    lines = shell_lines(README.read_text())
    sesp_lines = [line for line in lines if line.startswith("sesp ")]
    assert len(sesp_lines) >= 8
    for line in sesp_lines:
        try:
            build_parser().parse_args(shlex.split(line)[1:])
        except SystemExit:
            pytest.fail(f"README line not accepted by the CLI: {line}")
    for line in lines:
        words = shlex.split(line)
        for word in words:
            if word.startswith(("benchmarks/", "sweeps/")) and word.endswith((".py", ".toml")):
                assert (ROOT / word).is_file(), f"README names a missing file: {word}"
