"""Every ```python block of README.md and docs/*.md runs, in order, one namespace per page (grids made small);
every command line is accepted by the CLI, the README's quick start runs, and every script or sweep file
named exists."""

import json
import re
import shlex
import shutil

import matplotlib
import pytest

from sesp.cli import build_parser, main
from sesp.sweep import run

from cases import ROOT

README = ROOT / "README.md"
PAGES = [README, *sorted((ROOT / "docs").glob("*.md"))]
# certified counts at a coarser resolution than the default: the same engine, in a second instead of ten
COARSE = 1e-3


def python_blocks(text: str) -> list:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def small(code: str) -> str:
    """The same code, smaller: every Grid(n...) gets 32 cells and at most 16 orientations, and certified
    components are counted at resolution COARSE."""
    code = re.sub(r"Grid\(\d+", "Grid(32", code)
    code = re.sub(r"nphi=\d+", "nphi=16", code)
    return code.replace("sesp.certified_components(", f"sesp.certified_components(resolution={COARSE}, particle=")


def shell_lines(text: str) -> list:
    """The command lines of every ```bash block, comments dropped."""
    lines = []
    for block in re.findall(r"^```bash\n(.*?)^```", text, flags=re.S | re.M):
        for line in block.splitlines():
            command = line.split(" #")[0].strip()
            if command:
                lines.append(command)
    return lines


@pytest.fixture(scope="session")
def quick_results_once(tmp_path_factory):
    """The README's main job (sesp sweep sweeps/quick.toml) on a small grid, run once per test process."""
    root = tmp_path_factory.mktemp("quick")
    shutil.copytree(ROOT / "sweeps", root / "sweeps")
    sweep = root / "sweeps" / "quick.toml"
    sweep.write_text(re.sub(r"nphi = \d+", "nphi = 16", re.sub(r"nx = \d+", "nx = 32", sweep.read_text())))
    run(sweep, workers=1, progress=False)
    return root


@pytest.fixture
def quick_results(quick_results_once, tmp_path, monkeypatch):
    """A fresh copy of that job's folder (sweep files and results), as the working directory."""
    shutil.copytree(quick_results_once, tmp_path, dirs_exist_ok=True)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_pages_have_python_blocks():
    assert len(python_blocks(README.read_text())) >= 3
    assert {p.name for p in PAGES} >= {"README.md", "guide.md", "findings.md", "benchmarks.md", "design.md"}


def test_readme_is_short_and_starts_with_the_two_commands():
    text = README.read_text()
    assert len(text.splitlines()) <= 150
    assert shell_lines(text)[:2] == ['pip install -e ".[test]" && sesp sweep sweeps/quick.toml', "pytest"]


@pytest.mark.slow
@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_python_block_runs(quick_results, page):
    matplotlib.use("Agg")
    namespace = {}
    for block in python_blocks(page.read_text()):
        exec(compile(small(block), str(page), "exec"), namespace)
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_command_line_is_accepted_by_the_cli_or_names_a_real_file(page):
    lines = shell_lines(page.read_text())
    for line in lines:
        if line.startswith("sesp "):
            try:
                build_parser().parse_args(shlex.split(line)[1:])
            except SystemExit:
                pytest.fail(f"{page.name}: line not accepted by the CLI: {line}")
    for line in lines:
        for word in shlex.split(line):
            if word.startswith(("benchmarks/", "sweeps/")) and word.endswith((".py", ".toml")):
                assert (ROOT / word).is_file(), f"{page.name} names a missing file: {word}"
    for name in re.findall(
        r"`((?:benchmarks|sweeps|docs|examples)/[\w./-]+\.(?:py|toml|md|ipynb|png))`", page.read_text()
    ):
        assert (ROOT / name).is_file(), f"{page.name} names a missing file: {name}"


def small_command(line: str) -> list:
    """The words after ``sesp`` of a page's command line, smaller: grids of 32 cells and 16 orientations,
    certified counts at resolution COARSE, a range of openings in two steps bracketed no finer; the ``sesp``
    part of an ``install && sesp ...`` line."""
    words = shlex.split(line.split("&&")[-1])[1:]
    if "--opening-range" in words:
        at = words.index("--opening-range")
        half = str((float(words[at + 2]) - float(words[at + 1])) / 2)
        words += ["--step", half, "--width", half]  # the last of a repeated option wins
    for flag, value in (("--nx", "32"), ("--ny", "32"), ("--nphi", "16")):
        if flag in words:
            words[words.index(flag) + 1] = value
    if words[0] == "topology" and "--resolution" not in words:
        words += ["--resolution", str(COARSE)]
    return words


@pytest.mark.slow
@pytest.mark.parametrize("page", [README, ROOT / "docs" / "guide.md"], ids=lambda p: p.name)
def test_every_command_line_runs(quick_results, page):
    """Every ``sesp`` line of the page, in order, in a folder holding the quick sweep's results, the sweep
    files (grids of 32 cells, openings 90° apart) and the README's polyline file; set-up lines (pip, venv,
    pytest) are what CI itself runs."""
    matplotlib.use("Agg")
    (quick_results / "my_particle.txt").write_text("-1 0\n1 0\n")
    (quick_results / "a.txt").write_text("-1 0\n1 0\n")  # the guide's mixture: a needle and a staple
    (quick_results / "b.txt").write_text("0.5 -0.5\n-0.5 -0.5\n-0.5 0.5\n0.5 0.5\n")
    for sweep in (quick_results / "sweeps").glob("*.toml"):
        if sweep.name != "quick.toml":
            text = re.sub(r"nx = \d+", "nx = 32", sweep.read_text())
            sweep.write_text(re.sub(r"step = \d+", "step = 90", re.sub(r"nphi = \d+", "nphi = 16", text)))
    lines = [line for line in shell_lines(page.read_text()) if "sesp " in line.split("&&")[-1]]
    assert lines
    for line in lines:
        assert main(["-q", *small_command(line)]) == 0, line
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.mark.slow
def test_the_readme_quick_start_commands_run(tmp_path, monkeypatch, capsys):
    """Each `sesp` line of the quick start, as printed (certified counts at COARSE where the line names no
    resolution), in a folder with the README's own polyline file."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my_particle.txt").write_text("-1 0\n1 0\n")  # a needle of length 2
    quick_start = README.read_text().split("## Quick start")[1].split("\n## ")[0]
    lines = [line for line in shell_lines(quick_start) if line.startswith("sesp ")]
    assert len(lines) >= 3
    for line in lines:
        words = shlex.split(line)[1:]
        if words[0] == "topology" and "--resolution" not in words:
            words += ["--resolution", str(COARSE)]
        assert main(["-q", *words]) == 0, line
    printed = capsys.readouterr().out
    assert "<A_ex> =" in printed and "B2" in printed and "components" in printed
    assert (tmp_path / "asp150.png").stat().st_size > 10_000
    assert main(["-q", "area", "--vertices", "my_particle.txt", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["leading_instability"] == 2
