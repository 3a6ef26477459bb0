"""A progress bar on stderr for long studies (rich, loaded only when a bar is shown)."""

from __future__ import annotations

from typing import Any

__all__ = ["ProgressBar"]


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
