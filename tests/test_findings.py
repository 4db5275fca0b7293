"""docs/findings.md's tables are the rendering of the numbers benchmarks/findings_tables.py stored, and those
numbers are the engine's: its fast cases are counted again here."""

import json
import math
import sys
from pathlib import Path

import pytest

from sesp import SeSP, certified_components

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

from findings_render import render  # noqa: E402

STORE = json.loads((ROOT / "docs" / "findings_tables.json").read_text())


def test_the_page_shows_the_stored_numbers():
    page = (ROOT / "docs" / "findings.md").read_text()
    assert render(page, STORE) == page, "run: python benchmarks/findings_tables.py --render"
    for name in STORE:
        block = page.split(f"<!-- findings:{name} -->\n", 1)[1].split(f"<!-- /findings:{name} -->", 1)[0]
        assert block.count("\n") >= 3, f"the block {name} is empty"


@pytest.mark.parametrize("degrees", [176, 178])
def test_the_stored_counts_are_the_engines(degrees):
    """A count of the page, made again: the same bracket, cells and certified depths, digit for digit."""
    (row,) = [r for r in STORE["n4_openings"]["rows"] if r["opening_deg"] == degrees]
    found = certified_components(SeSP(n=4, opening=math.radians(degrees))).to_dict()
    for key in ("count_low", "count_high", "cells", "rim", "floor"):
        assert found[key] == row[key], key
    assert [(c["depth"], c["top"], c["box"]) for c in found["components"]] == [
        (c["depth"], c["top"], c["box"]) for c in row["components"]
    ]
