"""A minimal progress bar on stderr for long CLI jobs (no dependency).

It draws only when stderr is a terminal, or when ``force=True``; otherwise it is silent, so
tests and pipes see clean output.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO


class Progress:
    """Report progress of ``total`` units of work on a stream.

    Parameters
    ----------
    total : int
        Number of units (poses, samples) to process.
    label : str
        Text shown before the bar.
    stream : file, optional
        Where to draw (default ``sys.stderr``).
    force : bool
        Draw even when the stream is not a terminal.

    Examples
    --------
    >>> with Progress(1000, "solving") as bar:
    ...     for chunk in range(10):
    ...         bar.advance(100)
    """

    def __init__(self, total: int, label: str = "", *, stream: TextIO | None = None,
                 force: bool = False, min_interval: float = 0.1) -> None:
        self.total = max(int(total), 0)
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        self.enabled = force or bool(getattr(self.stream, "isatty", lambda: False)())
        self.done = 0
        self.min_interval = min_interval
        self._start = time.perf_counter()
        self._last = -1.0

    def __enter__(self) -> Progress:
        self._draw(final=False)
        return self

    def __exit__(self, *exc) -> None:
        self._draw(final=True)

    def advance(self, n: int = 1) -> None:
        """Mark ``n`` more units as done."""
        self.done = min(self.done + int(n), self.total) if self.total else self.done + int(n)
        now = time.perf_counter()
        if now - self._last >= self.min_interval:
            self._draw(final=False)

    def _draw(self, final: bool) -> None:
        if not self.enabled:
            return
        self._last = time.perf_counter()
        frac = self.done / self.total if self.total else 1.0
        width = 30
        filled = int(round(frac * width))
        elapsed = self._last - self._start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        line = (f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] "
                f"{self.done}/{self.total} {100 * frac:5.1f}% {elapsed:6.1f} s {rate:,.0f}/s")
        self.stream.write(line + ("\n" if final else ""))
        self.stream.flush()
