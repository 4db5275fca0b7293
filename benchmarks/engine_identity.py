"""The certified count's full answer on a fixed list of cases, for comparing two versions of the engine.

Prints, per case, one line of JSON: ``Certified.to_dict()`` without its
seconds, and a SHA-256 of the leaves (centres, sides, statuses and
components). Run it with each version and compare the outputs: a change
that must not alter any answer leaves them identical.

    python benchmarks/engine_identity.py > after.jsonl
    diff before.jsonl after.jsonl
"""

import hashlib
import json
import math
import sys
import time

import numpy as np

from sesp import Polyline, SeSP, certified_components

STAPLE = Polyline([[0.5, -0.5], [-0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]])
BENT = Polyline([[-0.6, -0.3], [0.1, 0.2], [0.5, -0.4]])

# (name, particle, other, keyword arguments): thin SeSPs of four n near the changes of their counts, a closed
# curve, a thick arc, polylines without mirror symmetry, and a mixture whose components lie on no axis
CASES = [
    ("asp 90", SeSP(n=2, opening=math.radians(90)), None, {}),
    ("asp 150", SeSP(n=2, opening=math.radians(150)), None, {}),
    ("asp 177", SeSP(n=2, opening=math.radians(177)), None, {}),
    ("asp 1.5", SeSP(n=2, opening=math.radians(1.5)), None, {}),
    ("n4 60 128", SeSP(n=4, opening=math.radians(60)), None, {"segments": 128}),
    ("n4 171.6", SeSP(n=4, opening=math.radians(171.6)), None, {}),
    ("n4 176", SeSP(n=4, opening=math.radians(176)), None, {}),
    ("n8 0", SeSP(n=8, opening=0.0), None, {}),
    ("n8 179.7", SeSP(n=8, opening=math.radians(179.7)), None, {}),
    ("n10 170", SeSP(n=10, opening=math.radians(170)), None, {}),
    ("n10 0.6", SeSP(n=10, opening=math.radians(0.6)), None, {}),
    ("thick asp 90", SeSP(n=2, opening=math.radians(90), thickness=0.05), None, {"resolution": 1e-3}),
    ("staple", STAPLE, None, {"resolution": 1e-2}),
    ("mixture", SeSP(n=4, opening=math.radians(100)), BENT, {"resolution": 1e-3, "segments": 64}),
    ("asp 120 rim 1e-4", SeSP(n=2, opening=math.radians(120)), None, {"rim": 1e-4, "base": 48}),
]


def _digest(cells) -> str:
    h = hashlib.sha256()
    for key in sorted(cells):
        h.update(key.encode())
        h.update(np.ascontiguousarray(cells[key]).tobytes())
    return h.hexdigest()


def main(names):
    for name, particle, other, kw in CASES:
        if names and name not in names:
            continue
        start = time.perf_counter()
        found = certified_components(particle, other, **kw)
        said = found.to_dict()
        said.pop("seconds")
        said["leaves_sha256"] = _digest(found.cells)
        print(json.dumps({"case": name, **said}), flush=True)
        print(f"{name}: {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
