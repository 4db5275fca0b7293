"""A folder of certified counts: what a search over Ψ has counted, kept so that a rerun resumes.

Each count is one JSON file named by a SHA-256 of everything it depends on: the two polylines as the engine
takes them (vertices, contact distance and tolerance), the resolution, rim, base and cost settings, and the
engine's own source (so a changed engine never reads an older engine's counts). A file that cannot be read is
set aside and counted again.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
from pathlib import Path

from .certified import Certified

__all__ = ["CountCache", "default_folder"]

ENGINE = (
    "certified.py", "_certify", "pair.py", "shape.py", "orientations.py", "checks.py",
    *(f"kernels/{name}.py" for name in ("common", "orientations", "runs", "tips", "depth", "cells")),
)  # fmt: skip


@functools.cache
def engine_digest() -> str:
    """SHA-256 of the source files the certified count's answer depends on."""
    root = Path(__file__).parent
    digest = hashlib.sha256()
    for name in ENGINE:
        path = root / name
        for file in sorted(path.rglob("*.py")) if path.is_dir() else [path]:
            digest.update(file.name.encode())
            digest.update(file.read_bytes())
    return digest.hexdigest()


def default_folder() -> Path:
    """Where the command line keeps counts: ``$XDG_CACHE_HOME/sesp/counts`` (``~/.cache/sesp/counts``)."""
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "sesp" / "counts"


class CountCache:
    """Counts kept in ``folder`` (created when first written)."""

    def __init__(self, folder):
        self.folder = Path(folder)

    @staticmethod
    def key(pair, settings: tuple) -> str:
        """The name of a count of ``pair`` with ``settings`` (resolution, rim, base, segments, cost settings)."""
        digest = hashlib.sha256(engine_digest().encode())
        for v in (pair.vertices1, pair.vertices2):
            digest.update(v.tobytes())
        digest.update(repr((pair.contact, pair.tolerance, pair.mirror_symmetric, *settings)).encode())
        return digest.hexdigest()

    def get(self, key: str) -> Certified | None:
        """The count stored under ``key``, or None (a file that cannot be read is set aside)."""
        path = self.folder / f"{key}.json"
        if not path.is_file():
            return None
        try:
            return Certified.from_dict(json.loads(path.read_text()))
        except (ValueError, KeyError, TypeError):
            path.replace(path.with_suffix(".damaged"))
            return None

    def put(self, key: str, found: Certified) -> None:
        """Store ``found`` under ``key``, atomically (a reader sees the whole file or none)."""
        self.folder.mkdir(parents=True, exist_ok=True)
        path = self.folder / f"{key}.json"
        temporary = path.with_suffix(f".{os.getpid()}.tmp")
        try:
            temporary.write_text(json.dumps(found.to_dict()))
            os.replace(temporary, path)
        finally:
            temporary.unlink(missing_ok=True)
