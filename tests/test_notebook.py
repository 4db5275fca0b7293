"""The example notebook runs top to bottom, and its stored outputs are what it prints."""

import shutil
from pathlib import Path

import pytest

NOTEBOOK = Path(__file__).resolve().parents[1] / "examples" / "topology.ipynb"


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_topology_notebook_runs(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    shutil.copy(NOTEBOOK, tmp_path / NOTEBOOK.name)
    nb = nbformat.read(tmp_path / NOTEBOOK.name, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    client.execute()
    outputs = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []))
    assert "TqdmWarning" not in outputs and "Warning" not in outputs  # progress off: no bar, no warning
    assert "Ψ =  90°: 2 components; lens depth 0.29" in outputs and "Ψ = 181°: 0 components" in outputs
    assert (tmp_path / "asp90.nc").is_file()


def test_the_notebook_ships_with_the_outputs_of_a_run():
    """A reader on GitHub sees the figures and the printed counts without running it."""
    nbformat = pytest.importorskip("nbformat")
    nb = nbformat.read(NOTEBOOK, as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(c.get("outputs") for c in code[1:]), "a code cell after the imports has no stored output"
    printed = "".join(o.get("text", "") for c in code for o in c.outputs)
    assert "Ψ = 150°: 2 components" in printed
