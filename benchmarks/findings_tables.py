"""The tables of docs/findings.md, computed and written into it: the numbers there cannot go stale.

Runs the certified counts the findings quote (at the defaults: ε = 1e-5 b, rim 1e-3 b, 256 segments, 64 base
cells), stores them in ``docs/findings_tables.json`` and rewrites each block of docs/findings.md between
``<!-- findings:NAME -->`` and ``<!-- /findings:NAME -->`` from that file. ``tests/test_findings.py`` checks
that the blocks are the rendering of the file, and recomputes its fast cases.

    python benchmarks/findings_tables.py                 # everything (about 25 minutes on 2 cores)
    python benchmarks/findings_tables.py --render        # rewrite the blocks from the stored numbers only
    python benchmarks/findings_tables.py --only n4_openings

Counts over Ψ are kept in a cache folder (``--cache``), so a rerun after an interruption resumes.
"""

import argparse
import json
import math
import time
from pathlib import Path

from findings_render import finite, render

from sesp import SeSP, certified_components, transitions

ROOT = Path(__file__).resolve().parent.parent

STORE = ROOT / "docs" / "findings_tables.json"
PAGE = ROOT / "docs" / "findings.md"


def _openings_n4() -> dict:
    """n = 4 at 170°, 176° and 178°: each component's certified depth bracket, box and point."""
    rows = []
    for degrees in (170, 176, 178):
        start = time.perf_counter()
        found = certified_components(SeSP(n=4, opening=math.radians(degrees)))
        rows.append({"opening_deg": degrees, "seconds": time.perf_counter() - start, **found.to_dict()})
    return {"rows": rows}


def _tables(cache) -> dict:
    """The count over 0°–360° for n = 2, 4, 8, 10: each change with its kind, each component's life."""
    out = {}
    for n in (2, 4, 8, 10):
        found = transitions(SeSP(n=n), workers=2, cache=cache, progress=True)
        out[str(n)] = {"seconds": found.seconds, **found.to_dict()}
        print(f"n = {n}: {len(found.counts)} openings, {found.seconds:.0f} s", flush=True)
    return {"tables": out}


MAKERS = {"n4_openings": _openings_n4, "transitions": _tables}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--render", action="store_true", help="only rewrite the blocks from the stored numbers")
    ap.add_argument("--only", nargs="*", default=list(MAKERS), choices=list(MAKERS))
    ap.add_argument("--cache", type=Path, default=ROOT / "results" / "findings_counts")
    args = ap.parse_args()
    stored = json.loads(STORE.read_text()) if STORE.is_file() else {}
    if not args.render:
        for name in args.only:
            made = MAKERS[name]() if name != "transitions" else MAKERS[name](args.cache)
            stored[name] = finite(made)
            STORE.write_text(json.dumps(stored, indent=1, allow_nan=False) + "\n")
    PAGE.write_text(render(PAGE.read_text(), stored))
    print(f"wrote {PAGE} from {STORE}")


if __name__ == "__main__":
    main()
