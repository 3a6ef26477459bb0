"""A progress bar on stderr for long studies (rich, loaded only when a bar is shown), and
the line a sweep ends with."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["ProgressBar", "sweep_summary"]


def _file_size(path: str | Path) -> int:
    """Bytes of a file, or of every file under a directory (a Zarr store)."""
    target = Path(path)
    if target.is_dir():
        return sum(p.stat().st_size for p in target.rglob("*") if p.is_file())
    return target.stat().st_size


def _bytes(size: int) -> str:
    """``739 kB``: three significant digits in B, kB, MB or GB (powers of 1000)."""
    value = float(size)
    for unit in ("B", "kB", "MB"):
        if value < 1000:
            return f"{size} B" if unit == "B" else f"{value:.3g} {unit}"
        value /= 1000
    return f"{value:.3g} GB"


def sweep_summary(path: str | Path, dims: Sequence[tuple[str, int]], seconds: float) -> str:
    """The one line ``balance sweep`` ends with: what was written, how big, how many points and
    how long it took, e.g. ``balance: wrote s.nc (61.2 kB): 155 points (speed 5 ×
    conrod_length 31) in 0.41 s``.

    Parameters
    ----------
    path : str or Path
        The file or store written.
    dims : sequence of (str, int)
        Each varied field's dimension and its number of values.
    seconds : float
        How long the sweep took [s].

    Returns
    -------
    str
        The line, without its newline.
    """
    points = math.prod(n for _, n in dims)
    grid = " × ".join(f"{name} {n}" for name, n in dims)
    return (
        f"balance: wrote {path} ({_bytes(_file_size(path))}): {points} point"
        f"{'s' if points != 1 else ''} ({grid}) in {seconds:.2f} s"
    )


class ProgressBar:
    """A transient rich progress bar on stderr, driven by a study's progress reports
    (:class:`balance.studies.sweep.Progress`)."""

    def __init__(self, label: str = "sweep") -> None:
        self.label = label
        self._bar: Any = None
        self._task: Any = None

    def start(self, total: int) -> None:
        """Show the bar for ``total`` grid points."""
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeRemainingColumn,
        )

        self._bar = Progress(
            TextColumn(self.label),
            BarColumn(),
            MofNCompleteColumn(),
            TimeRemainingColumn(),
            console=Console(stderr=True),
            transient=True,
        )
        self._bar.__enter__()
        self._task = self._bar.add_task(self.label, total=total)

    def advance(self, points: int) -> None:
        """Count ``points`` more grid points done."""
        if self._bar is not None:
            self._bar.advance(self._task, points)

    def stop(self) -> None:
        """Remove the bar."""
        if self._bar is not None:
            self._bar.__exit__(None, None, None)
            self._bar = None
