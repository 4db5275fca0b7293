"""Progress bars that cost nothing when off (tqdm is imported only when a bar is shown). A bar appears only
once its work has run for ``DELAY`` seconds: quick calls print nothing."""

from __future__ import annotations

__all__ = ["progress_bar", "progress_iter", "NoProgress", "DELAY"]

DELAY = 2.0  # s: how long work runs before its bar is shown


class NoProgress:
    """A stand-in for a tqdm bar that shows nothing: the same interface."""

    total = 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def update(self, n=1):
        pass

    def refresh(self):
        pass

    def set_postfix_str(self, text="", refresh=True):
        pass


def progress_bar(total, enabled: bool, desc: str, unit: str = "it", initial: int = 0, leave: bool = False):
    """A tqdm bar when ``enabled``, else a silent stand-in with the same interface (``total`` None: steps not
    known ahead; ``set_postfix_str`` shows where a step got)."""
    if not enabled:
        return NoProgress()
    from tqdm.auto import tqdm

    return tqdm(total=total, unit=unit, desc=desc, leave=leave, initial=initial, delay=DELAY)


def progress_iter(iterable, enabled: bool, desc: str, unit: str = "it"):
    """``iterable``, with a tqdm bar over it when ``enabled``."""
    if not enabled:
        return iterable
    from tqdm.auto import tqdm

    return tqdm(iterable, desc=desc, unit=unit, leave=False, delay=DELAY)
